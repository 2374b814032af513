#!/bin/sh
# .ci/run's cluster check: a sweep split into a Slurm job array of 4 shards on the one-node
# cluster of tools/cluster/slurm-local.sh, merged with `printwatt merge`, must give the files
# of the same sweep run on this machine in one process, bit for bit; and so must the shipped
# design study (studies/example.toml, 12 cases) split into an array of 3 shards by case.
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
# The design study, split by case.
STUDY="$ROOT/studies/example.toml"
"$BIN" study "$STUDY" --out study-single > study-single.txt 2> study-single.err
cat > study.sbatch <<JOB
#!/bin/sh
#SBATCH --job-name=printwatt-study
#SBATCH --array=0-2
#SBATCH --cpus-per-task=1
#SBATCH --output=$W/study-%A_%a.out
"$BIN" study "$STUDY" --shard auto --out $W/study-shards --threads 1
JOB
sbatch --wait study.sbatch > sbatch-study.txt
cat study-*.out
n=$(ls -d study-shards/shard-* | wc -l)
[ "$n" -eq 3 ] || { echo "expected 3 study shards, found $n" >&2; exit 1; }
"$BIN" merge study-shards --out study-merged > study-merged.txt 2> study-merged.err
ls study-single > single.ls
ls study-merged > merged.ls
cmp single.ls merged.ls
for f in $(cat single.ls); do
    [ "$f" = run.json ] || cmp "study-single/$f" "study-merged/$f"
done
grep -v '^report:' study-single.txt > a.txt
grep -v '^report:' study-merged.txt > b.txt
cmp a.txt b.txt
echo "slurm: $(cat sbatch-study.txt); 3 study shards merged = single run, bit for bit ($(grep -c . study-single/study.csv) lines in study.csv, $(grep -c '^case-' single.ls) case reports)"
cd "$ROOT"
rm -rf "$W"
