#!/usr/bin/env python3
"""Print the seed-000 P1–P5 energies under the three mechanical definitions at z = 0.2 m
(IRB 6700) from the run directories' summary.json (run from the repository root after
regenerate.sh). The positive-only energy ∫Σmax(τq̇, 0) dt follows exactly from the two runs:
max(p, 0) = (|p| + p) / 2 per joint and sample, so E+ = (E_abs + E_signed) / 2."""
import json
import os

R = os.path.join("results", "seed000_p1p5")
PAPER = {"P1": 1185.4, "P2": 1151.2, "P3": None, "P4": 2497.6, "P5": 1237.8}


def named(run):
    d = json.load(open(os.path.join(R, run, "summary.json")))
    # schema_version 1 writes the outcome's fields directly; older files wrapped them in "Ok".
    return {n: e["outcome"].get("Ok", e["outcome"])["energy_j"] for n, e in d["named"]}


a = named("irb6700_z0.2_abs")
s = named("irb6700_z0.2_signed")
p = {k: (a[k] + s[k]) / 2 for k in a}
print("| energy (IRB 6700, z = 0.2 m) | P1 | P2 | P3 | P4 | P5 | (max−min)/max | order |")
print("|---|---|---|---|---|---|---|---|")
for name, e in [("signed ∫Στ·q̇ (eq. 6–7 as printed)", s), ("positive-only ∫Σmax(τ·q̇, 0) (no regeneration)", p), ("absolute ∫Σ\\|τ·q̇\\| (main runs)", a)]:
    v = [e[k] for k in ["P1", "P2", "P3", "P4", "P5"]]
    red = (max(v) - min(v)) / max(v) * 100
    order = " > ".join(sorted(e, key=lambda k: -e[k]))
    print(f"| {name} | " + " | ".join(f"{x:.1f}" for x in v) + f" | {red:.2f} % | {order} |")
v = [PAPER[k] for k in ["P1", "P2", "P4", "P5"]]
print("| paper (seed 000 §3.2) | 1185.4 | 1151.2 | ≈ P4 | 2497.6 | 1237.8 | 53.72 % | P4 ≈ P3 > P5 > P1 > P2 |")
