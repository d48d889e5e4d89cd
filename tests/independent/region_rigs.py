"""What the joint prediction region would say of each finger of the shared rigs, beside the audit.

For every rig in ../shared/rigs, the audit's JSON gives each finger's compared segments; their
positions u = (J~1, J~1 + J~2) (the thumb's J~1) are judged against the 95% Hotelling prediction
region of the paper's 5 X-rays (src/analysis/region.rs's formula, computed here with numpy and
scipy), beside the audit's own verdict (its explanation fits with no move: "fits").

Run from the repository root after `cargo build --release`: python3 tests/independent/region_rigs.py
It skips with the reason printed when ../shared/rigs is absent.
"""
import csv
import glob
import json
import os
import subprocess
import sys

import numpy as np
from scipy import stats

rows = list(csv.DictReader(open("data/measurements.csv")))


def reference(finger):
    R = [r for r in rows if r["finger"] == finger]
    if finger == "thumb":
        S = np.array([[float(r["j1"]), float(r["j2"])] for r in R])
        return (S[:, 0] / S.sum(1))[:, None]
    S = np.array([[float(r["j1"]), float(r["j2"]), float(r["j3"])] for r in R])
    J = S.sum(1)
    return np.stack([S[:, 0] / J, (S[:, 0] + S[:, 1]) / J], 1)


def region(U):
    n, p = U.shape
    C = np.atleast_2d(np.cov(U.T)) * (1 + 1 / n)
    return U.mean(0), np.linalg.inv(C), p * (n - 1) / (n - p) * stats.f.ppf(0.95, p, n - p)


if not os.path.isdir("../shared/rigs"):
    print("skipped: ../shared/rigs is absent (the shared rigs sit beside the checkout, not in it)")
    sys.exit(0)
rigs = sorted(glob.glob("../shared/rigs/*/*.gl*") + glob.glob("../shared/rigs/*/*.fbx"))
for path in rigs:
    run = subprocess.run(["target/release/phalanx", "audit", path, "--format", "json"],
                         capture_output=True, text=True, check=True)
    out = []
    for f in json.loads(run.stdout)["rig"]["fingers"]:
        a = f["audit"]
        name = (f.get("side") or "")[:1] + f["finger"]
        if a["basis"] != "relative":
            out.append(f"{name}: -")
            continue
        s = np.array(a["compared"])
        u = s[:1] / s.sum() if f["finger"] == "thumb" else np.array([s[0], s[0] + s[1]]) / s.sum()
        m, inv, bound = region(reference(f["finger"]))
        t2 = (u - m) @ inv @ (u - m)
        rule = "fits" if a["explanation"]["consistent"] and not a["explanation"]["moved"] else "OUT"
        out.append(f"{name}: T2 {t2:.0f} {'in' if t2 <= bound else 'OUT'} (audit {rule})")
    print(path.split("rigs/")[1], "|", "; ".join(out))
