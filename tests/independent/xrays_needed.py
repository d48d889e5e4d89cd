"""Independent reference values for "X-rays needed" (NumPy/SciPy, not phalanx).

Run from the repository root: python3 tests/independent/xrays_needed.py > tests/independent/xrays_needed.txt
(NumPy 2.4, SciPy 1.17 when the committed output was made.)

For every finger and relative quantity J~k = Jk / J of the paper's X-rays (data/measurements.csv)
and of the atlas (data/atlas/measurements.csv, 910 hands), with W = 0.005 and c = 95%:

1. s, the sample SD (numpy, ddof=1), and U, the upper end of the SD's two-sided 95% confidence
   interval, U = s * sqrt((n - 1) / chi2.ppf(0.025, n - 1)): exact for normal data, since
   (n - 1) S^2 / sigma^2 ~ chi2(n - 1); the true SD lies below U with 97.5% confidence.
2. plug_in: the smallest n >= 2 with t.ppf(0.975, n - 1) * s / sqrt(n) <= W (the SD taken as exact).
3. assured(sigma): the smallest n >= 2 with
   chi2.cdf((n - 1) * n * W^2 / (t.ppf(0.975, n - 1)^2 * sigma^2), n - 1) >= 0.8
   (Kupper and Hafner 1989): the t interval of n X-rays has half-width <= W in 80% of studies
   when the true SD is sigma. Found by a plain linear search from n = 2.
4. For comparison only (not what the report uses): the predictive assurance, which integrates
   over the SD's sampling distribution: S_new^2 / s^2 ~ F(n - 1, n0 - 1) when both samples come
   from one normal population (n0 the X-rays measured), so the smallest n with
   f.cdf(n * W^2 / (t.ppf(0.975, n - 1)^2 * s^2), n - 1, n0 - 1) >= 0.8.

Each line: finger quantity | paper n s U plug_in assured(s) assured(U) predictive | atlas n s U assured(U).
"""
import csv

import numpy as np
from scipy import stats

W = 0.005
C = 0.95
LEVEL = 0.8
FINGERS = ["thumb", "index", "middle", "ring", "little"]


def relative(path):
    out = {}
    for r in csv.DictReader(open(path)):
        js = [float(r[k]) for k in ("j1", "j2", "j3") if r.get(k)]
        out.setdefault(r["finger"], []).append([j / sum(js) for j in js])
    return {f: np.array(v) for f, v in out.items()}


def upper(s, n):
    return s * np.sqrt((n - 1) / stats.chi2.ppf((1 - C) / 2, n - 1))


def t(n):
    return stats.t.ppf((1 + C) / 2, n - 1)


def first(ok):
    n = 2
    while not ok(n):
        n += 1
    return n


def plug_in(s):
    return first(lambda n: t(n) * s / np.sqrt(n) <= W)


def assured(sigma):
    return first(lambda n: stats.chi2.cdf((n - 1) * n * W**2 / (t(n) ** 2 * sigma**2), n - 1) >= LEVEL)


def predictive(s, n0):
    return first(lambda n: stats.f.cdf(n * W**2 / (t(n) ** 2 * s**2), n - 1, n0 - 1) >= LEVEL)


paper = relative("data/measurements.csv")
atlas = relative("data/atlas/measurements.csv")
print("# finger quantity | paper n s U plug_in assured_s assured_U predictive | atlas n s U assured_U")
for f in FINGERS:
    p, a = paper[f], atlas[f]
    for k in range(p.shape[1]):
        n, s = len(p), p[:, k].std(ddof=1)
        u = upper(s, n)
        na, sa = len(a), a[:, k].std(ddof=1)
        ua = upper(sa, na)
        print(
            f"{f} rel_j{k + 1} | paper {n} {s:.10f} {u:.10f} {plug_in(s)} {assured(s)} {assured(u)} "
            f"{predictive(s, n)} | atlas {na} {sa:.10f} {ua:.10f} {assured(ua)}"
        )
