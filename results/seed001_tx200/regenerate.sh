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
# 4. The paper's model (presets/seed001_paper_tx200.toml: no balancer, DC motors of eqs. 2-4,
#    no friction, gear loss or standby; R of motors 2, 3, 5 fitted to the paper's Sec. 3 power
#    levels) with the paper's spindle, every path, and the y2x variant with the slow y leg.
P=presets/seed001_paper_tx200.toml
for p in x y2x_r8 y2x_r12 y2x2y_r8 y2x2y_r12; do
  $B sweep --robot $P --tool presets/seed001_spindle.toml \
    --path paths/seed001_$p.gcode --at "1.0,0,0,0,180" \
    --objective supply --results-dir $R --force --run paper_$p
done
$B sweep --robot $P --tool presets/seed001_spindle.toml \
  --path "$T/seed001_y2x_r8_slow_y.gcode" --at "1.0,0,0,0,180" \
  --objective supply --results-dir $R --force --run paper_y2x_r8_slow_y
# 5. From the shipped estimate to the paper's model, one assumption at a time (x path, spindle):
#    (a) the shipped drive file without its balancer; (b) the paper's model with the shipped
#    motor resistances (no balancer, friction, gear loss). Both written beside this script.
sed -e '1i # Written by results/seed001_tx200/regenerate.sh: robots/staubli_tx200/drive.toml without its balancer.' \
  -e '/^balancer_/d' -e 's|^\[robot\]$|[robot]\nurdf = "../../robots/staubli_tx200/robot.urdf"|' \
  robots/staubli_tx200/drive.toml > "$T/tx200_no_balancer.toml"
sed -e '1i # Written by results/seed001_tx200/regenerate.sh: presets/seed001_paper_tx200.toml with the shipped resistances.' \
  -e 's/^winding_resistance_ohm = 22.90 .*/winding_resistance_ohm = 1.3  # the shipped ESTIMATE/' \
  -e 's/^winding_resistance_ohm = 964.95 .*/winding_resistance_ohm = 2.0  # the shipped ESTIMATE/' \
  -e 's/^winding_resistance_ohm = 981.75 .*/winding_resistance_ohm = 3.2  # the shipped ESTIMATE/' \
  -e 's|^urdf = "../robots/|urdf = "../../robots/|' \
  $P > "$T/paper_model_shipped_r.toml"
test "$(grep -c 'the shipped ESTIMATE$' "$T/paper_model_shipped_r.toml")" = 3
for v in tx200_no_balancer paper_model_shipped_r; do
  $B sweep --robot "$T/$v.toml" --tool presets/seed001_spindle.toml \
    --path paths/seed001_x.gcode --at "1.0,0,0,0,180" \
    --objective supply --results-dir $R --force --run ladder_${v}_x
done
# 6. The fit of the paper model's resistances, recomputed from the x path's per-sample torques
#    (fails when the preset no longer holds it).
F=${TMPDIR:-/tmp}/printwatt-seed001-fit
$B energy --robot $P --tool presets/seed001_spindle.toml --path paths/seed001_x.gcode \
  --at "1.0,0,0,0,180" --out "$F" --force > /dev/null
python3 $R/fit_paper_drive.py "$F/seed001_x.energy.csv" $P
