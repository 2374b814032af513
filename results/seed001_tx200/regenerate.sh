#!/bin/sh
# Regenerate the seed-001 per-motor reproductions on the Stäubli TX200 (run from the
# repository root after `cargo build --release`). Placement: part origin (start of every
# path) at x = 1.0 m, y = 0, z = 0 (table at the height of the base-frame origin), yaw 0:
# the x legs run away from the base along +x, as in the paper's Fig. 6.
set -e
B=${PRINTWATT:-target/release/printwatt}
R=results/seed001_tx200
for p in x y2x_r8 y2x_r12 y2x2y_r8 y2x2y_r12; do
  $B sweep --robot staubli_tx200 --path paths/seed001_$p.gcode --at "1.0,0,0,0" \
    --objective supply --results-dir $R --run $p
done
