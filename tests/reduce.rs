//! Path reduction for long repetitive prints (src/placement/reduce.rs,
//! src/toolpath/repeat.rs): the estimate against the full evaluation, feasibility across z,
//! the fallback for paths that do not repeat, and optimise's report of both figures.

mod common;
#[path = "common/wall.rs"]
mod wall;

use printwatt::placement::reduce::{ReduceOptions, Reduction};
use printwatt::placement::{Evaluator, FeasibilityOptions, Objective, Placement};
use printwatt::toolpath::{self, ReadOptions, Toolpath};

fn wall_path(layers: usize) -> Toolpath {
    toolpath::parse_gcode(
        &wall::wall_gcode(800.0, 200.0, 20.0, layers),
        "wall.gcode",
        &ReadOptions::default(),
    )
    .unwrap()
}

fn forced() -> ReduceOptions {
    ReduceOptions {
        min_samples: 0,
        ..Default::default()
    }
}

#[test]
fn explore() {
    let model = common::robot("abb_irb6700_200_260");
    let tp = wall_path(30);
    let job = common::default_job(&model, &tp);
    let red = Reduction::plan(&job, &tp, forced()).unwrap();
    eprintln!("{:?}", red.summary);
    let full = Evaluator::new(&job, FeasibilityOptions::default(), Objective::Supply);
    let ev = Evaluator::new(&job, FeasibilityOptions::default(), Objective::Supply)
        .with_reduction(red);
    let mut sc = ev.scratch().unwrap();
    let mut sf = full.scratch().unwrap();
    for at in [
        Placement::new(1.8, 0.0, 0.0, 0.0),
        Placement::new(1.6, 0.5, 0.3, 1.5),
        Placement::new(1.4, -0.6, 0.0, 0.0),
    ] {
        let t0 = std::time::Instant::now();
        let r = ev.evaluate(&mut sc, &at);
        let t1 = t0.elapsed();
        let t0 = std::time::Instant::now();
        let f = full.evaluate(&mut sf, &at);
        let t2 = t0.elapsed();
        match (&r.outcome, &f.outcome) {
            (Ok(a), Ok(b)) => eprintln!(
                "{at:?}: est {} full {} diff {:.3e} err {:?} t {t1:?} vs {t2:?}",
                a.energy_j,
                b.energy_j,
                (a.energy_j - b.energy_j) / b.energy_j,
                a.reduction
            ),
            (a, b) => eprintln!("{at:?}: {:?} / {:?}", a.as_ref().err(), b.as_ref().err()),
        }
    }
}
