#!/bin/sh
# Copy the shipped files into the cargo-fuzz corpus directories (fuzz/corpus/<target>/).
# Run from anywhere: sh fuzz/seed.sh
set -e
here=$(cd "$(dirname "$0")" && pwd)
root=$(dirname "$here")
c="$here/corpus"
mkdir -p "$c/urdf" "$c/drive" "$c/gcode" "$c/rapid" "$c/csv_path" "$c/placements" "$c/trajectory" "$c/log"
for r in "$root"/robots/*/; do
  n=$(basename "$r")
  [ -f "$r/robot.urdf" ] && cp "$r/robot.urdf" "$c/urdf/$n.urdf"
  [ -f "$r/drive.toml" ] && cp "$r/drive.toml" "$c/drive/$n.toml"
done
cp "$root"/paths/*.gcode "$root"/tests/data/toolpath/*.gcode "$c/gcode/"
cp "$root"/paths/*.mod "$root"/tests/data/toolpath/*.mod "$c/rapid/"
cp "$root"/tests/data/toolpath/*.csv "$c/csv_path/"
cp "$root"/paths/placements/*.csv "$c/placements/"
cp "$root"/tests/data/traj/*.csv "$c/trajectory/"
cp "$root"/tests/data/logs/*.csv "$c/log/"
echo "corpus in $c"
