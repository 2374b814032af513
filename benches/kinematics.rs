//! Kinematics timings: FK, OPW all branches, OPW single branch + FK re-check (the path loop),
//! numeric solve_near on the UR10e, and the pieces of the OPW path step (FK re-check chain,
//! branch classification, joint-limit fitting).

use criterion::{black_box, criterion_group, criterion_main, Criterion};
use printwatt::kinematics::{self, opw, IkSolver};
use printwatt::robot::{self, RobotModel};
use std::path::Path;

fn load(name: &str) -> RobotModel {
    let p = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("robots")
        .join(name);
    match robot::load(&p) {
        Ok(m) => m,
        Err(e) => panic!("{name}: {e}"),
    }
}

fn bench(c: &mut Criterion) {
    let abb = load("abb_irb6700_200_260");
    let ur = load("ur10e");
    let p = abb.opw.expect("OPW parameters");
    let q = [0.3, 0.2, -0.4, 0.5, 0.7, -0.6];
    let q_next = [0.301, 0.199, -0.401, 0.502, 0.699, -0.598];
    let target = kinematics::tool_pose(&abb, &q_next);
    let solver = IkSolver::new(&abb).expect("solver");
    let flange = solver.flange_target(&target);

    c.bench_function("fk flange (URDF chain, 6R)", |b| {
        b.iter(|| kinematics::flange_pose(black_box(&abb), black_box(&q)))
    });
    c.bench_function("fk all frames + tool", |b| {
        b.iter(|| kinematics::fk(black_box(&abb), black_box(&q)))
    });
    c.bench_function("jacobian 6x6", |b| {
        b.iter(|| kinematics::jacobian(black_box(&abb), black_box(&q)))
    });
    c.bench_function("opw all 8 branches (raw)", |b| {
        b.iter(|| opw::solve_all(black_box(&p), black_box(&flange)))
    });
    c.bench_function("opw solve_branch (raw)", |b| {
        let br = opw::Branch::of(&p, &q);
        b.iter(|| opw::solve_branch(black_box(&p), black_box(&flange), br))
    });
    c.bench_function("fk FastChain tool (re-check chain)", |b| {
        let chain = kinematics::FastChain::new(&abb);
        b.iter(|| chain.tool(black_box(&q)))
    });
    c.bench_function("IkSolver::check (FastChain + pose distance)", |b| {
        b.iter(|| solver.check(black_box(&target), black_box(&q_next)))
    });
    c.bench_function("Branch::of", |b| {
        b.iter(|| opw::Branch::of(black_box(&p), black_box(&q)))
    });
    c.bench_function("fit_limits", |b| {
        b.iter(|| {
            let mut x = q_next;
            kinematics::fit_limits(&abb, black_box(&mut x), Some(black_box(&q)))
        })
    });
    c.bench_function(
        "IkSolver::solve_near OPW (branch + limits + FK re-check)",
        |b| b.iter(|| solver.solve_near(black_box(&target), black_box(&q))),
    );
    c.bench_function(
        "IkSolver::solve_all OPW (8 branches + limits + FK re-check)",
        |b| b.iter(|| solver.solve_all(black_box(&target))),
    );

    let qu = [0.3, -1.2, 1.4, -1.5, -1.4, 0.4];
    let qu_next = [0.302, -1.199, 1.398, -1.501, -1.402, 0.403];
    let target_u = kinematics::tool_pose(&ur, &qu_next);
    let solver_u = IkSolver::new(&ur).expect("solver");
    c.bench_function(
        "IkSolver::solve_near numeric UR10e (LM from previous sample)",
        |b| b.iter(|| solver_u.solve_near(black_box(&target_u), black_box(&qu))),
    );
}

criterion_group!(benches, bench);
criterion_main!(benches);
