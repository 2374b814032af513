#!/usr/bin/env bash
# Placement verdicts with the published collision geometry against the capsules it replaces.
#
#   results/geometry_comparison/regenerate.sh        (from the repository root)
#
# For each robot and path of studies/example.toml, `printwatt sweep` over the default grid
# (1536 placements) twice with the same binary: once with the shipped robots without their
# `<collision>` elements (a capsule per link sized from the reach; PRINTWATT_ROBOTS points at
# these copies; drive files, print head and hose the same) and once with robots/ (convex pieces
# per link). Both runs check the floor. The run directories go to a temporary folder (removed at the end);
# this writes changes.csv (per robot and path: placements, feasible before/after, verdicts
# changed, how, and which shapes met in the changed verdicts) and prints the README's table
# and each sweep's wall time.
set -euo pipefail
cd "$(dirname "$0")/../.."
OUT=results/geometry_comparison
# BIN: the printwatt binary to run (default: build and run target/release/printwatt).
if [ -z "${BIN:-}" ]; then
  cargo build --release --quiet
  BIN=target/release/printwatt
fi
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
mkdir -p "$tmp/robots"
for robot in abb_irb6700_200_260 abb_irb4600_40_255; do
  mkdir -p "$tmp/robots/$robot"
  cp "robots/$robot/drive.toml" "$tmp/robots/$robot/"
  python3 - "robots/$robot/robot.urdf" "$tmp/robots/$robot/robot.urdf" <<'PY'
import re, sys
text = open(sys.argv[1]).read()
open(sys.argv[2], "w").write(re.sub(r"\s*<collision>.*?</collision>", "", text, flags=re.S))
PY
done
for robot in abb_irb6700_200_260 abb_irb4600_40_255; do
  for path in default.gcode column_arcs.gcode wall_rapid.mod; do
    name="$robot-${path%.*}"
    for kind in capsules pieces; do
      robots=robots
      [ "$kind" = capsules ] && robots="$tmp/robots"
      t0=$(date +%s.%N)
      PRINTWATT_ROBOTS="$robots" "$BIN" sweep --robot "$robot" --path "paths/$path" \
        --out "$tmp/$kind/$name" --force >/dev/null 2>&1
      t1=$(date +%s.%N)
      echo "$name $kind $(echo "$t1 - $t0" | bc) s" >&2
    done
  done
done
python3 - "$tmp" "$OUT" <<'PY'
import collections, csv, os, re, sys
tmp, out = sys.argv[1], sys.argv[2]

def who(detail):
    # The shapes named in a collision message, without shape indices.
    d = re.sub(r" \(shape \d+\)", "", detail)
    m = re.match(r"(.*) and (.*) collide", d)
    if m:
        return " + ".join(sorted(s.split(" (")[0] for s in m.groups()))
    m = re.match(r"(.*?) (meets the bed|comes within|is below the floor|reaches below)", d)
    return (m.group(1).split(" (")[0] if m else d[:40])

rows = []
for name in sorted(os.listdir(os.path.join(tmp, "pieces"))):
    read = lambda k: {r["name"]: r for r in csv.DictReader(open(os.path.join(tmp, k, name, "placements.csv")))}
    a, b = read("capsules"), read("pieces")
    moved, why = collections.Counter(), collections.Counter()
    for k in a:
        fa, fb = a[k]["feasible"] == "true", b[k]["feasible"] == "true"
        if fa != fb:
            moved["%s -> %s" % (a[k]["reason"] or "feasible", b[k]["reason"] or "feasible")] += 1
            r = b[k] if fa else a[k]
            why["%s: %s" % (r["reason"], who(r["detail"]))] += 1
    fa = sum(r["feasible"] == "true" for r in a.values())
    fb = sum(r["feasible"] == "true" for r in b.values())
    rows.append((name, len(a), fa, fb, sum(moved.values()),
                 "; ".join("%d %s" % (n, w) for w, n in moved.most_common()),
                 "; ".join("%d %s" % (n, w) for w, n in why.most_common())))
with open(os.path.join(out, "changes.csv"), "w", newline="") as f:
    w = csv.writer(f)
    w.writerow(["robot-path", "placements", "feasible_capsules", "feasible_pieces", "changed", "how", "shapes"])
    w.writerows(rows)
print("| Robot, path | Placements | Feasible (capsules) | Feasible (published geometry) | Verdicts changed "
      "| How (capsule verdict -> new verdict) | Shapes that met (in the infeasible one of the two) |")
print("|---|---|---|---|---|---|---|")
for r in rows:
    print("| `%s` | %d | %d | %d | %d | %s | %s |" % r)
PY
