#!/usr/bin/env python3
"""The NumPy peer of `phalanx stats --format json`: the same statistics, vectorised.

For every finger of a phalanx measurements CSV (columns xray, finger, j1, j2, j3, ...):
the relative values J~k = Jk / J, the ratios J2/J1 and J3/J2 and the total J, and for each
the mean, SD, SE, median, min, max, range and CV, the Student-t and bootstrap percentile and
BCa 95% confidence intervals of the mean, and the 95% prediction interval for one new X-ray.
As in phalanx, the X-ray is the unit resampled: fingers measured on the same X-rays share
every resample, and each resample serves all their quantities at once.

The bootstrap is written as fast as NumPy allows: per chunk of resamples, one matrix of
uniform X-ray indices (numpy's PCG64), turned into per-X-ray counts by one bincount, then one
BLAS matrix product of the counts (chunk x n) with the values (n x quantities), which OpenBLAS
runs on every core; the quantiles come from one sort along the resample axis. With n X-rays
and C(2n-1, n) <= resamples, the distinct resamples are enumerated with their multinomial
weights instead, as phalanx does (the paper's 5 X-rays: 126). The random numbers are not
phalanx's (ChaCha8), so the bootstrap intervals agree with phalanx's to Monte-Carlo error only.

Usage: bench/peer.py DATA.csv [--resamples B] [--seed S] > stats.json
Needs numpy and scipy: bench/run.sh installs the pinned versions of bench/requirements.txt into
target/bench-venv and runs this file with that Python. Phase times go to standard error.
"""

import argparse
import csv
import json
import math
import sys
import time

import numpy as np
from scipy import special, stats

FINGERS = ["thumb", "index", "middle", "ring", "little"]


def load(path):
    """Rows of each finger, in file order: (xray ids, lengths as an n x 3 array, NaN for none)."""
    by_finger = {f: ([], []) for f in FINGERS}
    with open(path, newline="") as fh:
        reader = csv.reader(fh)
        header = next(reader)
        ix, fx = header.index("xray"), header.index("finger")
        jx = [header.index(c) for c in ("j1", "j2", "j3")]
        for row in reader:
            ids, lengths = by_finger[row[fx]]
            ids.append(row[ix])
            lengths.append([float(row[j]) if row[j] else math.nan for j in jx])
    return {
        f: (ids, np.array(lengths, dtype=np.float64).reshape(-1, 3))
        for f, (ids, lengths) in by_finger.items()
        if ids
    }


def quantities(finger, lengths):
    """The quantities of one finger, as columns of an n x q array, with their names."""
    segments = lengths[:, :2] if finger == "thumb" else lengths
    total = segments.sum(axis=1)
    cols = [segments[:, k] / total for k in range(segments.shape[1])]
    names = [f"rel_j{k + 1}" for k in range(segments.shape[1])]
    cols.append(segments[:, 1] / segments[:, 0])
    names.append("ratio_j2_j1")
    if segments.shape[1] == 3:
        cols.append(segments[:, 2] / segments[:, 1])
        names.append("ratio_j3_j2")
    cols.append(total)
    names.append("total")
    return names, np.column_stack(cols)


def compositions(n):
    """Every vector of n counts summing to n (C(2n-1, n) of them), as rows."""
    out = []

    def rec(prefix, left, slots):
        if slots == 1:
            out.append(prefix + [left])
            return
        for c in range(left, -1, -1):
            rec(prefix + [c], left - c, slots - 1)

    rec([], n, n)
    return np.array(out, dtype=np.float64)


def bootstrap_means(values, resamples, rng, chunk=512):
    """Resampled means of every column of values (n x q): (means m x q, weights m)."""
    n = values.shape[0]
    if math.comb(2 * n - 1, n) <= resamples:
        counts = compositions(n)
        logw = special.gammaln(n + 1) - special.gammaln(counts + 1).sum(axis=1) - n * math.log(n)
        w = np.exp(logw)
        return counts @ values / n, w / w.sum()
    means = np.empty((resamples, values.shape[1]))
    offsets = None
    for start in range(0, resamples, chunk):
        m = min(chunk, resamples - start)
        idx = rng.integers(0, n, size=(m, n), dtype=np.int64)
        if offsets is None or offsets.shape[0] != m:
            offsets = (np.arange(m, dtype=np.int64) * n)[:, None]
        idx += offsets
        counts = np.bincount(idx.ravel(), minlength=m * n).reshape(m, n).astype(np.float64)
        np.matmul(counts, values, out=means[start : start + m])
    means /= n
    return means, np.full(resamples, 1.0 / resamples)


def intervals(x, boot, w, confidence):
    """Stats and the four intervals of the mean of each column of x (n x q)."""
    n = x.shape[0]
    mean = x.mean(axis=0)
    sd = x.std(axis=0, ddof=1)
    t = stats.t.ppf(0.5 + confidence / 2, n - 1)
    alpha = 1 - confidence
    z = special.ndtri(1 - alpha / 2)
    order = np.argsort(boot, axis=0, kind="stable")
    svals = np.take_along_axis(boot, order, axis=0)
    scum = np.cumsum(w[order], axis=0)
    m, q = boot.shape
    cols = np.arange(q)

    def quantile(p):
        i = (scum < p[None, :] - 1e-12).sum(axis=0)
        return svals[np.minimum(i, m - 1), cols]

    lo_p, hi_p = np.full(q, alpha / 2), np.full(q, 1 - alpha / 2)
    perc = (quantile(lo_p), quantile(hi_p))
    # BCa: z0 from the mid-rank of the estimate, a from the jackknife of the mean.
    tol = 1e-12 * np.maximum(np.abs(mean), 1e-300)
    below = (svals < (mean - tol)[None, :]).sum(axis=0)
    upto = (svals <= (mean + tol)[None, :]).sum(axis=0)

    def at(i):
        return np.where(i == 0, 0.0, scum[np.maximum(i - 1, 0), cols])

    p0 = at(below) + (at(upto) - at(below)) / 2
    d = (x - mean) / (n - 1)
    s2, s3 = (d * d).sum(axis=0), (d**3).sum(axis=0)
    with np.errstate(all="ignore"):
        z0 = special.ndtri(p0)
        a = s3 / (6 * s2**1.5)
        lo = special.ndtr(z0 + (z0 - z) / (1 - a * (z0 - z)))
        hi = special.ndtr(z0 + (z0 + z) / (1 - a * (z0 + z)))
    ok = (p0 > 0) & (p0 < 1) & (s2 > 0) & (1 - a * (z0 - z) > 0) & (1 - a * (z0 + z) > 0)
    bca = (quantile(np.where(ok, lo, 0.5)), quantile(np.where(ok, hi, 0.5)))
    half_t = t * sd / math.sqrt(n)
    half_p = t * sd * math.sqrt(1 + 1 / n)
    out = []
    for k in range(q):
        mn, mx = float(x[:, k].min()), float(x[:, k].max())
        out.append(
            {
                "n": n,
                "mean": float(mean[k]),
                "sd": float(sd[k]),
                "se": float(sd[k] / math.sqrt(n)),
                "median": float(np.median(x[:, k])),
                "min": mn,
                "max": mx,
                "range": mx - mn,
                "cv": float(sd[k] / mean[k]),
                "ci_t": [float(mean[k] - half_t[k]), float(mean[k] + half_t[k])],
                "ci_percentile": [float(perc[0][k]), float(perc[1][k])],
                "ci_bca": [float(bca[0][k]), float(bca[1][k])] if ok[k] else None,
                "pi": [float(mean[k] - half_p[k]), float(mean[k] + half_p[k])],
            }
        )
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("data")
    ap.add_argument("--resamples", type=int, default=10_000)
    ap.add_argument("--seed", type=int, default=20130101)
    ap.add_argument("--confidence", type=float, default=0.95)
    args = ap.parse_args()
    t0 = time.perf_counter()
    fingers = load(args.data)
    t1 = time.perf_counter()
    rng = np.random.default_rng(args.seed)
    # Fingers measured on the same X-rays (in the same order) share one bootstrap.
    groups = []
    for f, (ids, lengths) in fingers.items():
        names, cols = quantities(f, lengths)
        for g in groups:
            if g["ids"] == ids:
                g["members"].append((f, names, cols))
                break
        else:
            groups.append({"ids": ids, "members": [(f, names, cols)]})
    result = {"fingers": []}
    boot_s = 0.0
    for g in groups:
        values = np.hstack([cols for _, _, cols in g["members"]])
        tb = time.perf_counter()
        boot, w = bootstrap_means(values, args.resamples, rng)
        boot_s += time.perf_counter() - tb
        stats_all = intervals(values, boot, w, args.confidence)
        k = 0
        for f, names, cols in g["members"]:
            qs = []
            for name in names:
                qs.append({"name": name, **stats_all[k]})
                k += 1
            result["fingers"].append({"finger": f, "n": len(g["ids"]), "quantities": qs})
    t2 = time.perf_counter()
    json.dump(result, sys.stdout)
    t3 = time.perf_counter()
    print(
        f"peer: load {t1 - t0:.3f} s, bootstrap draws and products {boot_s:.3f} s, "
        f"statistics and intervals {t2 - t1 - boot_s:.3f} s, JSON {t3 - t2:.3f} s",
        file=sys.stderr,
    )


if __name__ == "__main__":
    main()
