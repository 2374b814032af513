#!/usr/bin/env bash
# Placement verdicts with the published collision hulls against the capsules they replace.
#
#   results/geometry_comparison/regenerate.sh        (from the repository root)
#
# For each robot and path of studies/example.toml, `printwatt sweep` over the default grid
# (16 x 16 placements over the reach, z = 0, yaw 0) twice with the same binary: once with the
# shipped robots as they were before the hulls (robot files of commit OLD, capsules sized from
# the reach; PRINTWATT_ROBOTS points at them) and once with robots/ (the hulls). Both runs
# check the floor. Writes capsules/ and hulls/ run directories (placements.csv) and
# changes.csv (per robot and path: placements, feasible before/after, verdicts changed and
# their reasons), then prints the table of the README.
set -euo pipefail
cd "$(dirname "$0")/../.."
OLD=e39ee20
OUT=results/geometry_comparison
BIN=target/release/printwatt
cargo build --release --quiet
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
git archive "$OLD" robots | tar -x -C "$tmp"
for robot in abb_irb6700_200_260 abb_irb4600_40_255; do
  for path in default.gcode column_arcs.gcode wall_rapid.mod; do
    name="$robot-${path%.*}"
    PRINTWATT_ROBOTS="$tmp/robots" "$BIN" sweep --robot "$robot" --path "paths/$path" \
      --out "$OUT/capsules/$name" --force >/dev/null 2>&1
    "$BIN" sweep --robot "$robot" --path "paths/$path" --out "$OUT/hulls/$name" --force >/dev/null 2>&1
  done
done
rm -f "$OUT"/{capsules,hulls}/*/report.html
python3 - "$OUT" <<'PY'
import csv, collections, os, sys
out = sys.argv[1]
rows = []
for name in sorted(os.listdir(os.path.join(out, "hulls"))):
    read = lambda k: {r["name"]: r for r in csv.DictReader(open(os.path.join(out, k, name, "placements.csv")))}
    a, b = read("capsules"), read("hulls")
    moved = collections.Counter()
    for k in a:
        fa, fb = a[k]["feasible"] == "true", b[k]["feasible"] == "true"
        if fa != fb:
            moved["%s -> %s" % (a[k]["reason"] or "feasible", b[k]["reason"] or "feasible")] += 1
    fa = sum(r["feasible"] == "true" for r in a.values())
    fb = sum(r["feasible"] == "true" for r in b.values())
    rows.append((name, len(a), fa, fb, sum(moved.values()),
                 "; ".join("%d %s" % (n, w) for w, n in moved.most_common())))
with open(os.path.join(out, "changes.csv"), "w", newline="") as f:
    w = csv.writer(f)
    w.writerow(["robot-path", "placements", "feasible_capsules", "feasible_hulls", "changed", "how"])
    w.writerows(rows)
print("| Robot, path | Placements | Feasible (capsules) | Feasible (hulls) | Verdicts changed | How (capsule verdict -> hull verdict) |")
print("|---|---|---|---|---|---|")
for r in rows:
    print("| `%s` | %d | %d | %d | %d | %s |" % r)
PY
