"""The joint region's calibration, drawn by brute force without phalanx's code.

phalanx judges a finger's relative joint positions u = (J~1, J~1 + J~2) against the 95%
prediction region T^2 = d' [S* (1 + 1/n)]^-1 d <= 2 (n - 1) / (n - 2) F(0.95; 2, n - 2),
where S* keeps the X-rays' variances and pools their correlation r_S with the atlas's r0
weighted as m = 10 hands: r* = (m r0 + (n - 1) r_S) / (m + n - 1) (src/analysis/region/,
crates/stats/src/region.rs). This script draws every reference hand (NumPy's normal draws and
np.cov, not the Bartlett draws phalanx uses), builds the region, and counts:

- false alarms: a new normal hand outside, at n = 5, 10, 40 and 910 and a true correlation
  anywhere in the Fisher 95% interval of the paper's index r = 0.969 (0.60 to 0.998); each
  simulation also draws the true SDs from the 95% intervals of the paper's SDs (chi-squared,
  4 degrees of freedom), so the variances vary too;
- power: the same new hand with one joint moved towards the tip on a 90 mm finger, 2, 3 and
  5 mm (PIP: u1 + d/L; DIP: u2 + d/L; MCP with the tip held: (u - d/L) / (1 - d/L)), at the
  paper's index SDs (0.0131, 0.0150), lowest to highest over the correlations.

Run from the repository root: python3 tests/independent/region_calibration.py
(numpy and scipy: bench/run.sh makes target/bench-venv with them). Its output is committed as
tests/independent/region_calibration.txt; a test (tests/report.rs) checks phalanx's table
against it within Monte Carlo error.
"""
import csv

import numpy as np
from scipy import stats

SIZES = (5, 10, 40, 910)
CORRELATIONS = (0.60, 0.70, 0.80, 0.90, 0.969, 0.99, 0.998)
MOVES = (2.0, 3.0, 5.0)
L = 90.0
SIMS = 20000
M = 10.0


def positions(path, finger):
    rows = [r for r in csv.DictReader(open(path)) if r["finger"] == finger]
    s = np.array([[float(r["j1"]), float(r["j2"]), float(r["j3"])] for r in rows])
    j = s.sum(1)
    return np.stack([s[:, 0] / j, (s[:, 0] + s[:, 1]) / j], 1)


paper = positions("data/measurements.csv", "index")
atlas = positions("data/atlas/measurements.csv", "index")
R0 = np.corrcoef(atlas.T)[0, 1]
MU, SD = paper.mean(0), paper.std(0, ddof=1)
R_PAPER = np.corrcoef(paper.T)[0, 1]
z = stats.norm.ppf(0.975) / np.sqrt(len(paper) - 3)
FISHER = np.tanh(np.arctanh(R_PAPER) - z), np.tanh(np.arctanh(R_PAPER) + z)
rng = np.random.default_rng(20130101)


def draw(n, r, sd, k):
    """k sets of n hands and one new hand, of correlation r and SDs sd (k x 2)."""
    z1 = rng.standard_normal((k, n + 1))
    z2 = rng.standard_normal((k, n + 1))
    x = MU[0] + sd[:, :1] * z1
    y = MU[1] + sd[:, 1:] * (r * z1 + np.sqrt(1 - r * r) * z2)
    u = np.stack([x, y], 2)
    return u[:, :n], u[:, n]


def outside(ref, new, n, prior):
    mean = ref.mean(1)
    d = ref - mean[:, None, :]
    c = np.einsum("kni,knj->kij", d, d) / (n - 1)
    a, b, dd = c[:, 0, 0], c[:, 0, 1], c[:, 1, 1]
    r_s = b / np.sqrt(a * dd)
    r = (M * R0 + (n - 1) * r_s) / (M + n - 1) if prior else r_s
    cs = np.empty_like(c)
    cs[:, 0, 0], cs[:, 1, 1] = a, dd
    cs[:, 0, 1] = cs[:, 1, 0] = r * np.sqrt(a * dd)
    diff = new - mean
    t2 = np.einsum("ki,kij,kj->k", diff, np.linalg.inv(cs * (1 + 1 / n)), diff)
    bound = 2 * (n - 1) / (n - 2) * stats.f.ppf(0.95, 2, n - 2)
    return t2 > bound


def moved(new, joint, mm):
    d = mm / L
    if joint == "PIP":
        return new + [d, 0.0]
    if joint == "DIP":
        return new + [0.0, d]
    return (new - d) / (1 - d)


def chunks(n):
    k = max(1, min(SIMS, 4_000_000 // (n + 1)))
    done = 0
    while done < SIMS:
        yield min(k, SIMS - done)
        done += k


print(f"index: r_S {R_PAPER:.3f} (Fisher 95% [{FISHER[0]:.3f}, {FISHER[1]:.3f}]), "
      f"atlas r0 {R0:.3f}, m {M:.0f}, SDs {SD[0]:.4f} {SD[1]:.4f}; {SIMS} simulations a cell")
print("false alarms with the prior (on the X-rays' own S), true SDs drawn from their 95% intervals:")
print("n    " + " ".join(f"r={r:<13}" for r in CORRELATIONS))
lo_var = (len(paper) - 1) / stats.chi2.ppf(0.975, len(paper) - 1)
hi_var = (len(paper) - 1) / stats.chi2.ppf(0.025, len(paper) - 1)
worst = 0.0
power = {}
for n in SIZES:
    cells = []
    for r in CORRELATIONS:
        fa = np.zeros(2)
        hits = {}
        for k in chunks(n):
            # The variances vary: each simulation's true SDs from the SDs' 95% intervals.
            sd = SD * np.sqrt(rng.uniform(lo_var, hi_var, (k, 2)))
            ref, new = draw(n, r, sd, k)
            fa += [outside(ref, new, n, True).sum(), outside(ref, new, n, False).sum()]
            # Power at the paper's SDs.
            ref, new = draw(n, r, np.tile(SD, (k, 1)), k)
            for joint in ("PIP", "DIP", "MCP"):
                for mm in MOVES:
                    u = moved(new, joint, mm)
                    h = hits.setdefault((joint, mm), np.zeros(2))
                    h += [outside(ref, u, n, True).sum(), outside(ref, u, n, False).sum()]
        fa /= SIMS
        worst = max(worst, fa[0])
        cells.append(f"{fa[0]:.3f} ({fa[1]:.3f})")
        for key, h in hits.items():
            power.setdefault((key, n), []).append(h / SIMS)
    print(f"{n:<4} " + " ".join(f"{c:<15}" for c in cells))
se = np.sqrt(0.05 * 0.95 / SIMS)
print(f"most false alarms with the prior: {worst:.3f} (target 0.05; Monte Carlo SE {se:.4f})")
print("power with the prior, lowest-highest over the correlations (on the X-rays' own S):")
print("moved      " + " ".join(f"n={n:<18}" for n in SIZES))
for joint in ("PIP", "DIP", "MCP"):
    for mm in MOVES:
        row = []
        for n in SIZES:
            v = np.array(power[((joint, mm), n)])
            row.append(f"{v[:, 0].min():.2f}-{v[:, 0].max():.2f} ({v[:, 1].min():.2f}-{v[:, 1].max():.2f})")
        print(f"{joint} {mm:.0f} mm   " + " ".join(f"{c:<20}" for c in row))
