#!/bin/sh
# Regenerates results/identify_example/ (run from the repository root after `cargo build --release`).
# Two rounds: round 1 finds and fits the balancer error on the nominal robot and writes the
# calibrated robot identify_1/robot.calibrated.toml; round 2 runs on that calibrated robot, finds
# Coulomb friction and writes identify/robot.calibrated.toml (both rounds listed in it).
set -e
B=${PRINTWATT:-target/release/printwatt}
D=results/identify_example
R=$D/robot
rm -rf $R $D/identify $D/identify_1 && mkdir -p $R && cp -r robots/abb_irb4600_40_255/. $R/
$B simulate --robot $R --excite 20 --hidden coulomb=30,balancer=3000:20000 --signal tau --noise 2 --rate 250 --seed 7 --out $D --force
$B compare --robot $R --log $D/log.csv --out $D/compare --force > $D/compare.txt
$B diagnose --robot $R --log $D/log.csv > $D/diagnose_1.txt
$B diagnose --robot $R --log $D/log.csv --json > $D/diagnose_1.json
$B identify --robot $R --log $D/log.csv --effects balancer --out $D/identify_1 > $D/identify_1.txt
$B diagnose --robot $D/identify_1/robot.calibrated.toml --log $D/log.csv > $D/diagnose_2.txt
$B identify --robot $D/identify_1/robot.calibrated.toml --log $D/log.csv --effects coulomb --out $D/identify > $D/identify.txt
$B diagnose --robot $D/identify/robot.calibrated.toml --log $D/log.csv > $D/diagnose_3.txt
$B compare --robot $D/identify/robot.calibrated.toml --log $D/log.csv --out $D/compare_identified --force > $D/compare_identified.txt
