#!/usr/bin/env python3
"""Fit the paper-model drive file's per-axis copper-loss coefficients to the power levels the
paper states for its x path (Sec. 3), and print the winding resistances they give.

Usage: fit_paper_drive.py ENERGY_CSV PRESET_TOML
ENERGY_CSV: the per-sample file of `printwatt energy` on paths/seed001_x.gcode with the paper
model (any resistances: with no friction, gear loss or rotor inertia the joint torques do not
depend on them). With gear efficiency 1 the electrical power of axis j is
    P_j = c_j tau_j^2 + tau_j qd_j,   c_j = R_j / (K_t,j G_j)^2,
so c_j is the one number the stated power fixes. Paper (Sec. 3): motor 2 "starts around
2000 W, increases to stabilise around 2600 W" (least squares on the first and last sample);
motor 3 "between 400 and 500 W" (mean 450 W); motor 5 "almost constant at 500 W" (mean 500 W).
Exits 1 when the preset's resistances differ from the fit by more than 0.1 %.
"""
import csv
import re
import sys

rows = list(csv.DictReader(open(sys.argv[1])))
t = [float(r["t[s]"]) for r in rows]
T = t[-1] - t[0]


def col(name):
    return [float(r[name]) for r in rows]


def mean(v):
    return sum((v[k] + v[k + 1]) / 2 * (t[k + 1] - t[k]) for k in range(len(t) - 1)) / T


def joints(path):
    """(gear ratio, torque constant, resistance) per [[joints]] table of a drive file."""
    out = []
    for block in open(path).read().split("[[joints]]")[1:]:
        g = lambda k: float(re.search(rf"^{k}\s*=\s*([0-9.eE+-]+)", block, re.M).group(1))
        out.append((g("gear_ratio"), g("torque_constant_nm_per_a"), g("winding_resistance_ohm")))
    return out


drive = joints(sys.argv[2])
c = {}
tau2, pm2 = col("tau2[Nm]"), col("p_mech2[W]")
pts = [(tau2[0] ** 2, 2000.0 - pm2[0]), (tau2[-1] ** 2, 2600.0 - pm2[-1])]
c[2] = sum(a * b for a, b in pts) / sum(a * a for a, _ in pts)
for j, target in [(3, 450.0), (5, 500.0)]:
    tj, pm = col(f"tau{j}[Nm]"), col(f"p_mech{j}[W]")
    c[j] = (target - mean(pm)) / mean([x * x for x in tj])
bad = False
print(f"x path, {T:.3f} s")
print("| motor | paper's power (Sec. 3) | c = R/(K_t G)^2 [W/(N m)^2] | R fitted [ohm] | R in the preset [ohm] | mean |tau| [N m] |")
print("|---|---|---|---|---|---|")
for j, what in [(2, "2000 W rising to 2600 W"), (3, "400-500 W"), (5, "~500 W")]:
    G, kt, r = drive[j - 1]
    fit = c[j] * (kt * G) ** 2
    bad |= abs(r - fit) > 1e-3 * fit
    print(f"| M{j} | {what} | {c[j]:.4e} | {fit:.2f} | {r:.2f} | {mean([abs(x) for x in col(f'tau{j}[Nm]')]):.1f} |")
if bad:
    print("the preset's resistances differ from the fit by more than 0.1 %", file=sys.stderr)
    sys.exit(1)
