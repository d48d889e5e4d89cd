"""Independent reference values for the comparison with a published summary table
(NumPy/SciPy, not phalanx).

Run from the repository root: python3 tests/independent/literature_reference.py > tests/independent/literature_reference.txt
(NumPy 2.4, SciPy 1.17 when the committed output was made.)

1. The paper's last segment (J~3; the thumb's J~2) per finger from data/measurements.csv:
   mean and 95% t interval (scipy.stats.t).
2. Buryanov & Kotiuk 2010 (data/literature/buryanov-kotiuk-2010.csv): the last segment as a
   ratio of means, bone only (distal / phalanges) and bone plus soft tissue ((distal + soft) /
   (phalanges + soft)).
3. The assumed correlation: per finger, the mean of the Pearson correlations between every two
   of J1, J2, J3 and the metacarpal, computed here from the atlas's raw landmarks
   (data/atlas/landmarks.csv; numpy.corrcoef).
4. The standard error of each ratio of means at correlations 0, the atlas's and 0.9, by a
   numerical gradient (central differences) of the ratio and the covariance matrix of the
   means, C_ij = rho s_i s_j / n (not the closed form phalanx uses), and the Welch-type 95%
   interval of table - paper: SE = sqrt(SE_paper^2 + SE_table^2), Welch-Satterthwaite df with
   4 and 65 df, scipy.stats.t.ppf.
"""
import csv
import math

import numpy as np
from scipy import stats

C = 0.95
FINGERS = ["thumb", "index", "middle", "ring", "little"]
LANDMARKS = {
    # CMC, MCP, ..., tip (data/atlas/README.md)
    "thumb": [17, 18, 19, 20],
    "index": [16, 21, 22, 23, 24],
    "middle": [15, 25, 26, 27, 28],
    "ring": [14, 29, 30, 31, 32],
    "little": [13, 33, 34, 35, 36],
}


def paper():
    rows = list(csv.DictReader(open("data/measurements.csv")))
    out = {}
    for f in FINGERS:
        segs = np.array([[float(r["j1"]), float(r["j2"])] + ([float(r["j3"])] if r["j3"] else [])
                         for r in rows if r["finger"] == f])
        out[f] = segs[:, -1] / segs.sum(axis=1)
    return out


def table():
    t = {}
    for r in csv.DictReader(open("data/literature/buryanov-kotiuk-2010.csv")):
        t[(r["finger"], r["segment"])] = (float(r["mean"]), float(r["sd"]), int(r["n"]))
    return t


def atlas_rho():
    pts = []
    for line in open("data/atlas/landmarks.csv"):
        f = line.strip().split(",")
        pts.append([(float(f[1 + 2 * k]), float(f[2 + 2 * k])) for k in range(37)])
    p = np.array(pts)
    out = {}
    for name, ch in LANDMARKS.items():
        segs = np.array([np.hypot(*(p[:, ch[i + 1]] - p[:, ch[i]]).T) for i in range(len(ch) - 1)])
        # rows: mc, J1, J2[, J3]
        c = np.corrcoef(segs)
        k = c.shape[0]
        out[name] = float(np.mean([c[i, j] for i in range(k) for j in range(i + 1, k)]))
    return out


def ratio_se(means, sds, n, num, rho):
    means = np.array(means, dtype=float)
    sds = np.array(sds, dtype=float)

    def r(m):
        return sum(m[i] for i in num) / m.sum()

    g = np.zeros(len(means))
    for i in range(len(means)):
        h = 1e-6 * means[i]
        up, dn = means.copy(), means.copy()
        up[i] += h
        dn[i] -= h
        g[i] = (r(up) - r(dn)) / (2 * h)
    corr = np.full((len(means), len(means)), rho)
    np.fill_diagonal(corr, 1.0)
    cov = corr * np.outer(sds, sds) / n
    return r(means), math.sqrt(g @ cov @ g)


def main():
    pa, tb, rho = paper(), table(), atlas_rho()
    print("# finger rho_atlas | paper mean t_low t_high | bone ratio | skin ratio | at rho: bone_se skin_se bone_diff_low bone_diff_high skin_diff_low skin_diff_high")
    for f in FINGERS:
        x = pa[f]
        n = len(x)
        m, s = x.mean(), x.std(ddof=1)
        se_p = s / math.sqrt(n)
        h = stats.t.ppf(0.5 + C / 2, n - 1) * se_p
        ph = ["proximal", "distal"] if f == "thumb" else ["proximal", "middle", "distal"]
        bone = [tb[(f, p)] for p in ph]
        skin = bone + [tb[(f, "tip_soft_tissue")]]
        last_bone = [len(bone) - 1]
        last_skin = [len(bone) - 1, len(bone)]
        line = f"{f} rho_atlas {rho[f]:.10f} paper {m:.10f} {m - h:.10f} {m + h:.10f}"
        rb = sum(v[0] for v in bone[-1:]) / sum(v[0] for v in bone)
        rs = (bone[-1][0] + skin[-1][0]) / sum(v[0] for v in skin)
        line += f" bone {rb:.10f} skin {rs:.10f}"
        for r in (0.0, rho[f], 0.9):
            out = []
            for parts, num in ((bone, last_bone), (skin, last_skin)):
                val, se = ratio_se([p[0] for p in parts], [p[1] for p in parts], 66, num, r)
                va, vb = se_p ** 2, se ** 2
                df = (va + vb) ** 2 / (va ** 2 / (n - 1) + vb ** 2 / 65)
                t = stats.t.ppf(0.5 + C / 2, df)
                d = val - m
                hw = t * math.sqrt(va + vb)
                out += [se, d - hw, d + hw]
            line += (f" | rho {r:.10f} bone_se {out[0]:.10f} skin_se {out[3]:.10f}"
                     f" bone_diff {out[1]:.10f} {out[2]:.10f} skin_diff {out[4]:.10f} {out[5]:.10f}")
        print(line)


if __name__ == "__main__":
    main()
