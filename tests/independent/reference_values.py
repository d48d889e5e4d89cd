"""Independent reference values for phalanx's tests (NumPy/SciPy, not phalanx).

Run: python3 tests/independent/reference_values.py
Prints, for every finger and relative quantity of data/measurements.csv (Table 1):
mean, sd, the Student-t 95% interval and prediction interval (scipy.stats.t),
a plain NumPy random bootstrap (1,000,000 resamples, seed 1) percentile interval
(inverted-CDF quantiles) and BCa interval (mid-rank bias correction, jackknife
acceleration), and scipy.stats.bootstrap's percentile and BCa intervals.
"""
import csv
import numpy as np
from scipy import stats

rows = list(csv.DictReader(open("data/measurements.csv")))
fingers = ["thumb", "index", "middle", "ring", "little"]
rng = np.random.default_rng(1)
B = 1_000_000
for f in fingers:
    rs = [r for r in rows if r["finger"] == f]
    segs = [[float(r["j1"]), float(r["j2"])] + ([float(r["j3"])] if r["j3"] else []) for r in rs]
    tot = np.array([sum(s) for s in segs])
    n = len(segs)
    idx = rng.integers(0, n, size=(B, n))
    for k in range(len(segs[0])):
        x = np.array([s[k] for s in segs]) / tot
        m, sd = x.mean(), x.std(ddof=1)
        t = stats.t.ppf(0.975, n - 1)
        ci = (m - t * sd / np.sqrt(n), m + t * sd / np.sqrt(n))
        pi = (m - t * sd * np.sqrt(1 + 1 / n), m + t * sd * np.sqrt(1 + 1 / n))
        bm = x[idx].mean(axis=1)
        pct = np.quantile(bm, [0.025, 0.975], method="inverted_cdf")
        tol = 1e-12 * abs(m)
        p0 = np.mean(bm < m - tol) + 0.5 * np.mean(np.abs(bm - m) <= tol)
        z0 = stats.norm.ppf(p0)
        d = (x - m) / (n - 1)
        a = (d ** 3).sum() / (6 * (d ** 2).sum() ** 1.5)
        z = stats.norm.ppf([0.025, 0.975])
        lv = stats.norm.cdf(z0 + (z0 + z) / (1 - a * (z0 + z)))
        bca = np.quantile(bm, lv, method="inverted_cdf")
        sp = stats.bootstrap((x,), np.mean, n_resamples=20000, method="percentile", random_state=2).confidence_interval
        sb = stats.bootstrap((x,), np.mean, n_resamples=20000, method="BCa", random_state=2).confidence_interval
        print(f"{f} rel_j{k+1}: mean {m:.6f} sd {sd:.6f} ci_t [{ci[0]:.6f}, {ci[1]:.6f}] "
              f"pi [{pi[0]:.6f}, {pi[1]:.6f}] pct [{pct[0]:.6f}, {pct[1]:.6f}] "
              f"bca [{bca[0]:.6f}, {bca[1]:.6f}] scipy_pct [{sp.low:.6f}, {sp.high:.6f}] "
              f"scipy_bca [{sb.low:.6f}, {sb.high:.6f}]")
