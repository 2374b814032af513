#!/usr/bin/env python3
"""Print the seed-001 tables of results/README.md from the run directories' summary.json
(per-motor electrical energy ∫u·i dt, J; run from the repository root after regenerate.sh)."""
import json
import os

R = os.path.join("results", "seed001_tx200")
PATHS = ["x", "y2x_r8", "y2x_r12", "y2x2y_r8", "y2x2y_r12"]
# Seed 001, Table 1 (J): motors 1-6 per trajectory.
PAPER = {
    "x": [0.00, 6363.75, 1228.06, 0.61, 1329.97, 0.03],
    "y2x_r8": [1.93, 12773.04, 2271.35, 103.06, 2689.52, 0.10],
    "y2x_r12": [1.67, 12659.49, 2251.31, 90.16, 2663.20, 0.10],
    "y2x2y_r8": [3.39, 15801.13, 2723.71, 183.20, 3251.40, 0.08],
    "y2x2y_r12": [2.85, 15544.40, 2681.25, 157.39, 3198.79, 0.08],
}


def motors(run):
    d = json.load(open(os.path.join(R, run, "summary.json")))["details"][0]
    return [j["electrical_j"] for j in d["joints"]], d["supply_j"], d["duration_s"]


def table(prefix, title):
    print(f"\n{title}\n")
    print("| path | M1 | M2 | M3 | M4 | M5 | M6 | motors Σ | supply (incl. standby) | time [s] | joints 1–3 share | paper's share |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|")
    tot = {}
    for p in PATHS:
        m, sup, t = motors(prefix + p)
        s = sum(m)
        tot[p] = s
        share = sum(m[:3]) / s * 100
        pshare = sum(PAPER[p][:3]) / sum(PAPER[p]) * 100
        cells = " | ".join(f"{v:.1f}" for v in m)
        print(f"| {p.replace('_', ' ')} | {cells} | {s:.1f} | {sup:.1f} | {t:.2f} | **{share:.1f} %** | {pshare:.2f} % |")
    return tot


a = table("", "Shipped 3DCP nozzle (payload on the joint-6 axis):")
b = table("spindle_", "Seed 001's spindle (presets/seed001_spindle.toml, spin 180°):")


def supply(run):
    return motors(run)[1]


print("\nRatios (paper: Table 1 totals):\n")
print("| ratio | nozzle (motors) | spindle (motors) | spindle (supply) | paper |")
print("|---|---|---|---|---|")
for p in ["y2x_r8", "y2x2y_r8"]:
    pr = sum(PAPER[p]) / sum(PAPER["x"])
    print(f"| {p.replace('_', ' ')} / x | {a[p] / a['x']:.2f} | {b[p] / b['x']:.2f} | "
          f"{supply('spindle_' + p) / supply('spindle_x'):.2f} | {pr:.2f} |")
m, sup, t = motors("spindle_y2x_r8_slow_y")
print(f"| y2x r8, y leg at 14 mm/s / x | | {sum(m) / b['x']:.2f} | {sup / supply('spindle_x'):.2f} | "
      f"{sum(PAPER['y2x_r8']) / sum(PAPER['x']):.2f} |")
print(f"\n(slow-y run: {t:.2f} s, motors Σ {sum(m):.1f} J, supply {sup:.1f} J)")


def signed(v):
    return f"{v:+.1f} %"


print("\nThe paper's model (presets/seed001_paper_tx200.toml, spindle, runs paper_*), per motor "
      "against Table 1:\n")
print("| path | time [s] | M1 | M2 | M3 | M4 | M5 | M6 | total | Table 1: M2 / M3 / M5 / total | M2 / M3 / M5 / total vs Table 1 |")
print("|---|---|---|---|---|---|---|---|---|---|---|")
for p in PATHS + ["y2x_r8_slow_y"]:
    m, _, t = motors("paper_" + p)
    ref = PAPER[p.replace("_slow_y", "")]
    cells = " | ".join(f"{v:.1f}" for v in m)
    dev = " / ".join(signed((m[j] / ref[j] - 1) * 100) for j in (1, 2, 4))
    print(f"| {p.replace('_', ' ')} | {t:.2f} | {cells} | {sum(m):.1f} | "
          f"{ref[1]:.2f} / {ref[2]:.2f} / {ref[4]:.2f} / {sum(ref):.2f} | "
          f"{dev} / {signed((sum(m) / sum(ref) - 1) * 100)} |")

print("\nFrom the shipped estimate to the paper's model, x path with the spindle (J):\n")
print("| model | M2 | M3 | M5 | total (6 motors) |")
print("|---|---|---|---|---|")
for run, what in [("spindle_x", "shipped TX200 (balancer, friction, gear loss, estimated motors)"),
                  ("ladder_tx200_no_balancer_x", "… without the balancer"),
                  ("ladder_paper_model_shipped_r_x", "… and without friction and gear loss (the paper's model, shipped R)"),
                  ("paper_x", "… and R fitted to the paper's power levels (the paper's model)")]:
    m, _, _ = motors(run)
    print(f"| {what} | {m[1]:.1f} | {m[2]:.1f} | {m[4]:.1f} | {sum(m):.1f} |")
x = PAPER["x"]
print(f"| paper, Table 1 | {x[1]:.2f} | {x[2]:.2f} | {x[4]:.2f} | {sum(x):.2f} |")
