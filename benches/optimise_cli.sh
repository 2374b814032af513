#!/usr/bin/env bash
# The target "`printwatt optimise` on the default job at least 3x faster than b5bfebb,
# same answer", measured end to end the way a user runs it: the release binary of this
# checkout against the release binary of a reference commit, each run `printwatt optimise`
# (the shipped default robot and path, the report and the run directory written), in rounds
# that alternate the two (the order rotating each round) so that a load spike hits both
# alike; medians of wall and CPU (user + system) time, their ratios, the load average before
# and after, and whether both printed the same answer.
#
# usage: benches/optimise_cli.sh [REF] [ROUNDS]     (defaults: b5bfebb, 8)
#
# The reference is built once in a worktree under target/compare-optimise/ (a few minutes;
# later runs reuse it). Needs hyperfine (installed with apt-get when missing, and said so).
# Figures are only idle figures on an otherwise idle machine: the load is printed.
set -euo pipefail

REF=${1:-b5bfebb}
ROUNDS=${2:-8}
ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
WORK="$ROOT/target/compare-optimise"
REV=$(git -C "$ROOT" rev-parse --short "$REF")
HEAD_REV=$(git -C "$ROOT" rev-parse --short HEAD)
mkdir -p "$WORK/bin" "$WORK/run"

if ! command -v hyperfine >/dev/null; then
  echo "[optimise_cli] hyperfine missing: installing it with apt-get" >&2
  apt-get install -y hyperfine >/dev/null
fi

# The reference binary: its own worktree, so that it finds its own shipped robot and path.
REF_BIN="$WORK/bin/printwatt-$REV"
if [ ! -x "$REF_BIN" ]; then
  if [ ! -d "$WORK/ref-$REV" ]; then
    git -C "$ROOT" worktree add --detach "$WORK/ref-$REV" "$REV" >/dev/null
  fi
  echo "[optimise_cli] building the reference $REV (once)" >&2
  cargo build --release --quiet --manifest-path "$WORK/ref-$REV/Cargo.toml" --bin printwatt
  cp "$WORK/ref-$REV/target/release/printwatt" "$REF_BIN"
fi
cargo build --release --quiet --manifest-path "$ROOT/Cargo.toml" --bin printwatt
NEW_BIN="$WORK/bin/printwatt-$HEAD_REV"
cp "$ROOT/target/release/printwatt" "$NEW_BIN"

# The answers first (one run each, outside the timing).
cd "$WORK/run"
answer() { "$1" optimise 2>/dev/null | grep -E '^(best placement:|energy )' ; }
rm -rf results
A_NEW=$(answer "$NEW_BIN")
rm -rf results
A_REF=$(answer "$REF_BIN")

LOAD0=$(cut -d' ' -f1-3 /proc/loadavg)
rm -f "$WORK"/hf-*.json
bins=("$NEW_BIN" "$REF_BIN")
for r in $(seq "$ROUNDS"); do
  k=$((r % 2))
  ordered=("${bins[@]:$k}" "${bins[@]:0:$k}")
  cmds=()
  for b in "${ordered[@]}"; do cmds+=("$b optimise"); done
  hyperfine -N --runs 1 --prepare "rm -rf $WORK/run/results" \
    --export-json "$WORK/hf-$r.json" "${cmds[@]}" >/dev/null 2>&1
done
LOAD1=$(cut -d' ' -f1-3 /proc/loadavg)

python3 - "$WORK" "$NEW_BIN" "$REF_BIN" "$HEAD_REV" "$REV" <<'PY'
import collections, glob, json, statistics, sys
work, new, ref, new_rev, ref_rev = sys.argv[1:]
d = collections.defaultdict(list)
for f in glob.glob(f"{work}/hf-*.json"):
    for r in json.load(open(f))["results"]:
        d[r["command"].split()[0]].append((r["times"][0], r["user"] + r["system"]))
med = {}
for b, name in ((new, new_rev), (ref, ref_rev)):
    v = d[b]
    w = [x[0] for x in v]
    c = [x[1] for x in v]
    med[b] = (statistics.median(w), statistics.median(c))
    print(f"{name}: {len(v)} runs; wall median {med[b][0]:.3f} s ({min(w):.3f}-{max(w):.3f}); CPU median {med[b][1]:.3f} s ({min(c):.3f}-{max(c):.3f})")
print(f"{new_rev} / {ref_rev}: wall {med[new][0] / med[ref][0]:.3f} ({med[ref][0] / med[new][0]:.2f}x faster), CPU {med[new][1] / med[ref][1]:.3f} ({med[ref][1] / med[new][1]:.2f}x)")
PY
echo "load average (1, 5, 15 min) before: $LOAD0; after: $LOAD1; $(nproc) cores"
if [ "$A_NEW" = "$A_REF" ]; then
  echo "same answer: $(echo "$A_NEW" | head -1)"
else
  echo "DIFFERENT answers:"; echo "  $HEAD_REV: $A_NEW"; echo "  $REV: $A_REF"
fi
