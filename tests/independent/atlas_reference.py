"""Independent reference values for the cohort comparison and the population coverage
(NumPy/SciPy, not phalanx).

Run from the repository root: python3 tests/independent/atlas_reference.py
(NumPy 2.4, SciPy 1.17 when the values in the tests were taken.)

1. A small hand-made pair of cohorts: Welch's interval (scipy.stats.ttest_ind with
   equal_var=False and its confidence_interval), Hedges' g and its large-sample interval
   (Hedges and Olkin 1985, written out below), and external coverage (scipy.stats.t).
2. The paper's X-rays (data/measurements.csv) against the atlas (data/atlas/landmarks.csv,
   distances computed here from the raw coordinates): the same statistics per finger and
   relative value, and the soft-tissue offset of the last segment.
3. Coverage on the atlas as a population: samples of n = 5 drawn with replacement, the
   t interval, the prediction interval for one further draw, and the exact-bootstrap
   percentile and BCa intervals (all 126 resamples of 5 enumerated with multinomial
   weights; weighted inverted-CDF quantiles; mid-rank bias correction and jackknife
   acceleration as in Efron 1987), 200,000 simulations, NumPy's PCG64 seeded 1.
"""
import csv
import itertools
import math
import sys

import numpy as np
from scipy import stats

C = 0.95


def welch(a, b):
    r = stats.ttest_ind(b, a, equal_var=False)
    ci = r.confidence_interval(C)
    return r.df, ci.low, ci.high


def hedges(a, b):
    na, nb = len(a), len(b)
    sp = math.sqrt(((na - 1) * np.var(a, ddof=1) + (nb - 1) * np.var(b, ddof=1)) / (na + nb - 2))
    g = (1 - 3 / (4 * (na + nb) - 9)) * (np.mean(b) - np.mean(a)) / sp
    se = math.sqrt((na + nb) / (na * nb) + g * g / (2 * (na + nb)))
    z = stats.norm.ppf(0.5 + C / 2)
    return g, g - z * se, g + z * se


def pi(x):
    n = len(x)
    h = stats.t.ppf(0.5 + C / 2, n - 1) * np.std(x, ddof=1) * math.sqrt(1 + 1 / n)
    return np.mean(x) - h, np.mean(x) + h


def inside(ref, other):
    lo, hi = pi(ref)
    return int(np.sum((other >= lo) & (other <= hi)))


def section1():
    a = np.array([1.1, 2.3, 2.9, 3.4, 4.0])
    b = np.array([2.0, 3.1, 3.5, 4.8, 5.2, 6.0, 6.1, 7.9])
    df, lo, hi = welch(a, b)
    g, glo, ghi = hedges(a, b)
    print("# 1. small cohorts A = [1.1, 2.3, 2.9, 3.4, 4.0], B = [2.0, 3.1, 3.5, 4.8, 5.2, 6.0, 6.1, 7.9]")
    print(f"welch df {df:.10f} ci [{lo:.10f}, {hi:.10f}]")
    print(f"hedges g {g:.10f} ci [{glo:.10f}, {ghi:.10f}]")
    print(f"pi A [{pi(a)[0]:.10f}, {pi(a)[1]:.10f}] B inside {inside(a, b)} of {len(b)}")
    print(f"pi B [{pi(b)[0]:.10f}, {pi(b)[1]:.10f}] A inside {inside(b, a)} of {len(a)}")


FINGERS = {
    "thumb": [18, 19, 20],
    "index": [21, 22, 23, 24],
    "middle": [25, 26, 27, 28],
    "ring": [29, 30, 31, 32],
    "little": [33, 34, 35, 36],
}


def atlas():
    pts = []
    for line in open("data/atlas/landmarks.csv"):
        f = line.strip().split(",")
        pts.append([(float(f[1 + 2 * k]), float(f[2 + 2 * k])) for k in range(37)])
    p = np.array(pts)
    out = {}
    for name, ch in FINGERS.items():
        seg = np.array([np.hypot(*(p[:, ch[i + 1]] - p[:, ch[i]]).T) for i in range(len(ch) - 1)]).T
        out[name] = (seg / seg.sum(axis=1, keepdims=True), seg.sum(axis=1))
    return out


def paper():
    rows = list(csv.DictReader(open("data/measurements.csv")))
    out = {}
    for name in FINGERS:
        segs = np.array([[float(r["j1"]), float(r["j2"])] + ([float(r["j3"])] if r["j3"] else [])
                         for r in rows if r["finger"] == name])
        out[name] = (segs / segs.sum(axis=1, keepdims=True), segs.sum(axis=1))
    return out


def section2(at, pa):
    print("# 2. paper (A) against atlas (B): finger rel_jk: welch ci, hedges g ci, B in PI(A), A in PI(B)")
    for name in FINGERS:
        ra, ta = pa[name]
        rb, tb = at[name]
        for k in range(ra.shape[1]):
            a, b = ra[:, k], rb[:, k]
            df, lo, hi = welch(a, b)
            g, glo, ghi = hedges(a, b)
            print(f"{name} rel_j{k + 1}: diff {b.mean() - a.mean():.10f} welch df {df:.6f} "
                  f"[{lo:.10f}, {hi:.10f}] g {g:.10f} [{glo:.10f}, {ghi:.10f}] "
                  f"b_in_a {inside(a, b)}/{len(b)} a_in_b {inside(b, a)}/{len(a)}")
        last = ra.shape[1] - 1
        r_a, r_b = ra[:, last].mean(), rb[:, last].mean()
        share_a = (r_a - r_b) / (1 - r_b)
        share_bone = (r_a - r_b) / (1 - r_a)
        print(f"{name} tip offset: share_of_a {share_a:.10f} share_of_bone {share_bone:.10f} "
              f"in_a_units {share_a * ta.mean():.10f} in_b_units {share_bone * tb.mean():.10f}")


def compositions(n):
    out = []
    for combo in itertools.combinations_with_replacement(range(n), n):
        c = np.bincount(combo, minlength=n)
        out.append(c)
    c = np.array(out, dtype=float)
    w = np.array([math.factorial(n) / np.prod([math.factorial(int(k)) for k in row]) / n ** n for row in c])
    return c, w / w.sum()


def weighted_quantile(sorted_vals, cum, p):
    # Smallest value whose cumulative weight reaches p (minus 1e-12), row by row.
    idx = np.array([np.searchsorted(cum_row, pp - 1e-12, side="left") for cum_row, pp in zip(cum, p)])
    idx = np.minimum(idx, sorted_vals.shape[1] - 1)
    return sorted_vals[np.arange(len(idx)), idx]


def coverage(pop, n=5, sims=200_000, seed=1, batch=20_000):
    rng = np.random.default_rng(seed)
    cmat, w = compositions(n)
    mu = pop.mean()
    z = stats.norm.ppf(0.5 + C / 2)
    t = stats.t.ppf(0.5 + C / 2, n - 1)
    hits = np.zeros(4)
    undefined = np.zeros(4)
    done = 0
    while done < sims:
        s = min(batch, sims - done)
        x = pop[rng.integers(0, len(pop), size=(s, n))]
        new = pop[rng.integers(0, len(pop), size=s)]
        m = x.mean(axis=1)
        sd = x.std(axis=1, ddof=1)
        h = t * sd / math.sqrt(n)
        hits[0] += np.sum((m - h <= mu) & (mu <= m + h))
        hp = t * sd * math.sqrt(1 + 1 / n)
        hits[3] += np.sum((m - hp <= new) & (new <= m + hp))
        bm = x @ cmat.T / n  # s x 126 bootstrap means
        order = np.argsort(bm, axis=1, kind="stable")
        sv = np.take_along_axis(bm, order, axis=1)
        cum = np.cumsum(w[order], axis=1)
        lo = weighted_quantile(sv, cum, np.full(s, (1 - C) / 2))
        hi = weighted_quantile(sv, cum, np.full(s, (1 + C) / 2))
        hits[1] += np.sum((lo <= mu) & (mu <= hi))
        # BCa
        tol = 1e-12 * np.maximum(np.abs(m), 1e-300)
        below = np.sum(w * (bm < (m - tol)[:, None]), axis=1)
        at = np.sum(w * (np.abs(bm - m[:, None]) <= tol[:, None]), axis=1)
        p0 = below + at / 2
        d = (x - m[:, None]) / (n - 1)
        s2 = np.sum(d ** 2, axis=1)
        s3 = np.sum(d ** 3, axis=1)
        with np.errstate(divide="ignore", invalid="ignore"):
            a = s3 / (6 * s2 ** 1.5)
            z0 = stats.norm.ppf(p0)
            den_lo = 1 - a * (z0 - z)
            den_hi = 1 - a * (z0 + z)
            ok = (p0 > 0) & (p0 < 1) & (s2 > 0) & (den_lo > 0) & (den_hi > 0)
            plo = stats.norm.cdf(z0 + (z0 - z) / den_lo)
            phi = stats.norm.cdf(z0 + (z0 + z) / den_hi)
        ok &= np.isfinite(plo) & np.isfinite(phi)
        blo = weighted_quantile(sv, cum, np.where(ok, plo, 0.5))
        bhi = weighted_quantile(sv, cum, np.where(ok, phi, 0.5))
        hits[2] += np.sum(ok & (blo <= mu) & (mu <= bhi))
        undefined[2] += np.sum(~ok)
        done += s
    return hits / sims, undefined[2]


def section3(at):
    print("# 3. coverage on the atlas as a population, n = 5, 200,000 simulations: t, percentile, bca, prediction")
    for name in FINGERS:
        rel = at[name][0]
        for k in range(rel.shape[1]):
            cov, und = coverage(rel[:, k])
            print(f"{name} rel_j{k + 1}: t {cov[0]:.5f} percentile {cov[1]:.5f} bca {cov[2]:.5f} "
                  f"prediction {cov[3]:.5f} (bca undefined {int(und)})")


if __name__ == "__main__":
    section1()
    at, pa = atlas(), paper()
    section2(at, pa)
    if "--no-coverage" not in sys.argv:
        section3(at)
