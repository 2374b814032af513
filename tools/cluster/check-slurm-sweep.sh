#!/bin/sh
# .ci/run's cluster check: a sweep split into a Slurm job array of 4 shards on the one-node
# cluster of tools/cluster/slurm-local.sh, merged with `printwatt merge`, must give the files
# of the same sweep run on this machine in one process, bit for bit.
# Usage: sh tools/cluster/check-slurm-sweep.sh [path/to/printwatt]   (from the repository root)
set -eu
BIN=$(realpath "${1:-target/release/printwatt}")
ROOT=$(pwd)
eval "$(sh tools/cluster/slurm-local.sh)"
W=$(mktemp -d /tmp/printwatt-slurm-check.XXXXXX)
GRID="--x 1.3:1.9:0.05 --y -0.6:0.6:0.1 --yaw 90,80 --path $ROOT/paths/default.gcode"
cd "$W"
# shellcheck disable=SC2086
"$BIN" sweep $GRID --out single > single.txt 2> single.err
cat > sweep.sbatch <<JOB
#!/bin/sh
#SBATCH --job-name=printwatt-sweep
#SBATCH --array=0-3
#SBATCH --cpus-per-task=1
#SBATCH --output=$W/slurm-%A_%a.out
"$BIN" sweep $GRID --shard auto --out $W/shards --threads 1
JOB
sbatch --wait sweep.sbatch > sbatch.txt
cat slurm-*.out
n=$(ls -d shards/shard-* | wc -l)
[ "$n" -eq 4 ] || { echo "expected 4 shards, found $n" >&2; exit 1; }
"$BIN" merge shards --out merged > merged.txt 2> merged.err
for f in summary.json placements.csv report.html; do
    cmp "single/$f" "merged/$f"
done
cmp single.txt merged.txt
echo "slurm: $(cat sbatch.txt); 4 shards merged = single run, bit for bit ($(grep -c . single/placements.csv) lines in placements.csv)"
cd "$ROOT"
rm -rf "$W"
