#!/bin/sh
# Regenerate the seed-001 per-motor reproductions on the Stäubli TX200 (run from the
# repository root after `cargo build --release`). Placement: part origin (start of every
# path) at x = 1.0 m, y = 0, z = 0 (table at the height of the base-frame origin), yaw 0:
# the x legs run away from the base along +x, as in the paper's Fig. 6.
set -e
B=${PRINTWATT:-target/release/printwatt}
R=results/seed001_tx200
# 1. The shipped 3DCP nozzle (payload below the wrist centre, on the axis of joint 6). At the
#    paper's placement its wrist passes 4.1° from q5 = 0, within the default wrist margin of 5°;
#    the reproduction evaluates the paper's placement as the paper did (--wrist-margin 0: the
#    round nozzle's q6 is free).
for p in x y2x_r8 y2x_r12 y2x2y_r8 y2x2y_r12; do
  $B sweep --robot staubli_tx200 --path paths/seed001_$p.gcode --at "1.0,0,0,0" \
    --wrist-margin 0 --objective supply --results-dir $R --force --run $p
done
# 2. The paper's machining spindle (tool preset, ESTIMATE: 40 kg, centre of mass 0.20 m off the
#    axis of joint 6). Spin 180°: the offset points along the arm, away from the base, so the
#    wrist (joint 5) holds it as in the paper's Fig. 6 (spin 0 passes within 2.9° of the wrist
#    singularity at this placement).
for p in x y2x_r8 y2x_r12 y2x2y_r8 y2x2y_r12; do
  $B sweep --robot staubli_tx200 --tool presets/seed001_spindle.toml \
    --path paths/seed001_$p.gcode --at "1.0,0,0,0,180" \
    --objective supply --results-dir $R --force --run spindle_$p
done
# 3. Why the paper's y2x/x ratio is 2.00: the same y2x path with its 40 mm y leg at 14 mm/s
#    (F840, the feed at which that leg takes as long as the 140 mm x leg at 50 mm/s), spindle on.
#    The variant is written beside this script (derived from the shipped path, never edited).
T=$R
sed -e 's/^G1 Y32 F3000/G1 Y32 F840/' -e 's/^G2 X8 Y40 I8 J0$/G2 X8 Y40 I8 J0 F3000/' \
  paths/seed001_y2x_r8.gcode > "$T/seed001_y2x_r8_slow_y.gcode"
grep -q '^G1 Y32 F840' "$T/seed001_y2x_r8_slow_y.gcode"
$B sweep --robot staubli_tx200 --tool presets/seed001_spindle.toml \
  --path "$T/seed001_y2x_r8_slow_y.gcode" --at "1.0,0,0,0,180" \
  --objective supply --results-dir $R --force --run spindle_y2x_r8_slow_y
