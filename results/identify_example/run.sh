#!/bin/sh
# Regenerates results/identify_example/ (run from the repository root after `cargo build --release`).
set -e
B=${PRINTWATT:-target/release/printwatt}
D=results/identify_example
R=$D/robot
rm -rf $R && mkdir -p $R && cp robots/abb_irb4600_40_255/* $R/
$B simulate --robot $R --excite 20 --hidden coulomb=30,balancer=3000:20000 --signal tau --noise 2 --rate 250 --seed 7 --out $D/log.csv
$B compare --robot $R --log $D/log.csv --out $D/compare > $D/compare.txt
$B diagnose --robot $R --log $D/log.csv > $D/diagnose_1.txt
$B diagnose --robot $R --log $D/log.csv --json > $D/diagnose_1.json
$B identify --robot $R --log $D/log.csv --effects balancer --drive-out $R/step1.toml --force --out $D/identify_1 > $D/identify_1.txt
$B diagnose --robot $R/step1.toml --log $D/log.csv > $D/diagnose_2.txt
$B identify --robot $R --log $D/log.csv --effects balancer,coulomb --force --out $D/identify > $D/identify.txt
$B diagnose --robot $R/drive.identified.toml --log $D/log.csv > $D/diagnose_3.txt
$B compare --robot $R/drive.identified.toml --log $D/log.csv --out $D/compare_identified > $D/compare_identified.txt
