"""Independent reference for a summary table without SDs (NumPy/SciPy, not phalanx).

Run from the repository root: python3 tests/independent/untestable_table.py
(NumPy 2.4, SciPy 1.17 when the figures in tests/literature.rs were taken.)

tests/fixtures/joint-centre-table.csv is a joint-centre table in the style of those that give
segment lengths as shares of hand length (Buchholz et al. 1992, say), with no SD and no n: a
test fixture, not a transcription of any paper. No difference from it can be tested. For each
quantity the paper's X-rays (data/measurements.csv) and the table both give (23: the thumb's
J~1, J~2, J2/J1; each finger's J~1, J~2, J~3, J2/J1, J3/J2), this prints the table's ratio of
means (to the end of its last segment: the table gives no soft tissue), the paper's mean and
95% t interval (scipy.stats.t, 4 df), and whether the table's value lies outside it; then the
count.
"""
import csv

import numpy as np
from scipy import stats

FINGERS = ["thumb", "index", "middle", "ring", "little"]
table = {(r["finger"], r["segment"]): float(r["mean"]) for r in csv.DictReader(open("tests/fixtures/joint-centre-table.csv"))}
rows = list(csv.DictReader(open("data/measurements.csv")))
outside = total = 0
for f in FINGERS:
    a = np.array([[float(r["j1"]), float(r["j2"])] + ([float(r["j3"])] if r["j3"] else []) for r in rows if r["finger"] == f])
    segs = ["proximal", "distal"] if f == "thumb" else ["proximal", "middle", "distal"]
    b = np.array([table[(f, s)] for s in segs])
    J, B = a.sum(axis=1), b.sum()
    qs = {f"J~{k + 1}": (a[:, k] / J, b[k] / B) for k in range(len(segs))}
    qs["J2/J1"] = (a[:, 1] / a[:, 0], b[1] / b[0])
    if len(segs) == 3:
        qs["J3/J2"] = (a[:, 2] / a[:, 1], b[2] / b[1])
    for q, (x, v) in qs.items():
        m, h = x.mean(), stats.t.ppf(0.975, len(x) - 1) * x.std(ddof=1) / np.sqrt(len(x))
        out = not (m - h <= v <= m + h)
        outside += out
        total += 1
        print(f"{f} {q}: table {v:.4f}, paper {m:.4f} [{m - h:.4f}, {m + h:.4f}] {'outside' if out else 'inside'}")
print(f"{outside} of {total} of the table's point values lie outside the paper's 95% t intervals")
