#!/bin/sh
# The argmin (Nelder–Mead) refinement against the earlier pattern search on the
# shipped examples. Default grid, default budget (--max-evals 120), no placement tolerance (the
# pattern search has none), one thread (so that the Nelder–Mead run makes no speculative
# evaluations: every evaluation either search makes is counted). Run from the repository root
# after `cargo build --release`; then `python3 results/search_comparison/table.py`.
set -e
B=${PRINTWATT:-target/release/printwatt}
R=results/search_comparison
for job in "abb_irb6700_200_260 paths/default.gcode" "abb_irb4600_40_255 paths/wall_multilayer.gcode" \
           "abb_irb6700_200_260 paths/seed000_test_path.gcode" "staubli_tx200 paths/seed001_y2x2y_r8.gcode"; do
  set -- $job
  for s in pattern nelder-mead; do
    $B optimise --robot $1 --path $2 --search $s --tolerance 0,0 --threads 1 --no-report --json \
      > $R/$1-$(basename $2 .gcode)-$s.json
  done
done
