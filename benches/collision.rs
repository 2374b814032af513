//! What collision feasibility (parry3d-f64) costs per path sample, as a ratio to a bare RNEA
//! call measured in the same run, on the shipped IRB 6700 and `paths/default.gcode` at a
//! feasible placement: one full check (shape poses from FK, bed, printed beads in the BVH,
//! self pairs), the amortised cost per sample with the default `check_every`, and the bead
//! BVH build (once per job; again only for placements whose timing re-planned the motion).
//!
//! The same check with the arm's published geometry (convex pieces per link, as shipped) and
//! with a capsule per link (the URDF's collision elements dropped, as for an arm without
//! meshes), so the cost of the meshes is measured against the capsules in the same run.
//!
//! Run: `cargo bench --bench collision` (criterion, ~30 s); the ratios are printed at the end
//! from criterion's own estimates.

#[path = "../tests/common/mod.rs"]
mod common;

use criterion::{black_box, Criterion};
use printwatt::dynamics::rnea;
use printwatt::evaluate::feasibility::collision::{self, Beads, RobotShapes, BEAD_RADIUS_M};
use printwatt::evaluate::feasibility::{reach_m, FeasibilityOptions, World};
use printwatt::math::V3;
use printwatt::toolpath::Placement;
use std::path::Path;
use std::time::Duration;

fn estimate_ns(dir: &Path, name: &str) -> Option<f64> {
    let p = dir.join(name).join("new/estimates.json");
    let v: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(p).ok()?).ok()?;
    v["mean"]["point_estimate"].as_f64()
}

fn main() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let model = common::robot("abb_irb6700_200_260");
    let tp = common::path("default.gcode");
    let job = common::default_job(&model, &tp);
    let at = Placement::new(1.4, 0.0, 0.5, std::f64::consts::FRAC_PI_2);
    let full = job.evaluate(&at).unwrap().unwrap();
    let tr = &full.timed.traj;
    let motion = &*full.timed.motion;
    let m = tr.len();
    let k = m / 2; // mid-print: half the beads laid
    let o = FeasibilityOptions::default();
    let mut lo = V3::repeat(f64::INFINITY);
    let mut hi = V3::repeat(f64::NEG_INFINITY);
    for p in &motion.p {
        lo = lo.inf(p);
        hi = hi.sup(p);
    }
    let world = World::new(&at.frame(), (lo, hi), &o);
    let shapes = RobotShapes::new(&model, reach_m(&model), &o.radii);
    let every = o.check_every.max(1);
    let beads = Beads::new(&motion.p, &motion.print, every, BEAD_RADIUS_M);
    let laid = beads.laid_at(k);

    let mut c = Criterion::default()
        .warm_up_time(Duration::from_secs(1))
        .measurement_time(Duration::from_secs(4))
        .configure_from_args();
    let mut data = job.energy.data();
    let mut tau = vec![0.0; model.dof()];
    c.bench_function("rnea_one_sample", |b| {
        b.iter(|| {
            rnea(
                job.energy.dynamics(),
                &mut data,
                tr.q(k),
                tr.qd(k),
                tr.qdd(k),
                &mut tau,
            )
            .unwrap();
            black_box(&tau);
        })
    });
    let mut poses = Vec::new();
    // The running bed clearance of the samples before k (as along a real path).
    let mut clear0 = None;
    for j in (0..k).step_by(every) {
        shapes.poses_into(&model, tr.q(j), &world.base_iso, &mut poses);
        collision::check(
            &shapes,
            &poses,
            &world.bed,
            &beads,
            beads.laid_at(j),
            &mut clear0,
        );
    }
    c.bench_function("collision_check_one_sample", |b| {
        b.iter(|| {
            shapes.poses_into(&model, tr.q(k), &world.base_iso, &mut poses);
            let mut clear = clear0;
            black_box(collision::check(
                &shapes, &poses, &world.bed, &beads, laid, &mut clear,
            ))
        })
    });
    // As a placement evaluation runs it: the links' frames from the FK
    // re-check's shared sines (computed here once, outside the timed loop, as the evaluation
    // has them), composed in the part frame, and the check from those frames.
    let q = tr.q(k);
    let sincos: Vec<f64> = {
        let (s, c): (Vec<f64>, Vec<f64>) =
            q.iter().map(|&x| printwatt::fastmath::sin_cos(x)).unzip();
        [s, c].concat()
    };
    let mut bodies = collision::BodyFrames::default();
    let mut isos = Vec::new();
    c.bench_function("collision_check_one_sample_shared_sines", |b| {
        b.iter(|| {
            shapes.body_frames_into(q, Some(&sincos), &world.base_to_part, &mut bodies);
            let mut clear = clear0;
            black_box(collision::check_bodies(
                &shapes, &bodies, &world.bed, &beads, laid, &mut clear, &mut isos,
            ))
        })
    });
    // The same arm with a capsule per link (its URDF collision elements dropped).
    let mut capsule_model = model.clone();
    capsule_model.base_collision.clear();
    capsule_model.link_collision.iter_mut().for_each(Vec::clear);
    let capsules = RobotShapes::new(&capsule_model, reach_m(&capsule_model), &o.radii);
    let mut clear_c = None;
    for j in (0..k).step_by(every) {
        capsules.body_frames_into(tr.q(j), None, &world.base_to_part, &mut bodies);
        collision::check_bodies(
            &capsules,
            &bodies,
            &world.bed,
            &beads,
            beads.laid_at(j),
            &mut clear_c,
            &mut isos,
        );
    }
    c.bench_function("collision_check_one_sample_shared_sines_capsules", |b| {
        b.iter(|| {
            capsules.body_frames_into(q, Some(&sincos), &world.base_to_part, &mut bodies);
            let mut clear = clear_c;
            black_box(collision::check_bodies(
                &capsules, &bodies, &world.bed, &beads, laid, &mut clear, &mut isos,
            ))
        })
    });
    c.bench_function("bead_bvh_build_per_placement", |b| {
        b.iter(|| black_box(Beads::new(&motion.p, &motion.print, every, BEAD_RADIUS_M)))
    });
    c.final_summary();

    let dir = root.join("target/criterion");
    if let (Some(r), Some(ch), Some(bv)) = (
        estimate_ns(&dir, "rnea_one_sample"),
        estimate_ns(&dir, "collision_check_one_sample_shared_sines"),
        estimate_ns(&dir, "bead_bvh_build_per_placement"),
    ) {
        if let Some(cap) = estimate_ns(&dir, "collision_check_one_sample_shared_sines_capsules") {
            println!(
                "  published geometry ({} shapes, {} self pairs): {ch:9.1} ns; capsules ({} shapes, {} self pairs): {cap:9.1} ns ({:.2}x)",
                shapes.shapes.len(),
                shapes.pairs.len(),
                capsules.shapes.len(),
                capsules.pairs.len(),
                ch / cap
            );
        }
        if let Some(plain) = estimate_ns(&dir, "collision_check_one_sample") {
            println!(
                "  poses by libm sines and quaternions + check (plain): {plain:9.1} ns; from the shared sines: {ch:9.1} ns ({:.2}x)",
                ch / plain
            );
        }
        let per_sample = ch / every as f64;
        println!(
            "collision feasibility ({} shapes, {} self pairs, {} beads, {m} samples, check every {every}):",
            shapes.shapes.len(),
            shapes.pairs.len(),
            beads.len()
        );
        println!(
            "  one check            {ch:9.1} ns = {:6.2}x RNEA ({r:.1} ns)",
            ch / r
        );
        println!(
            "  amortised per sample {per_sample:9.1} ns = {:6.2}x RNEA",
            per_sample / r
        );
        println!(
            "  bead BVH build       {bv:9.1} ns = {:6.2} RNEA calls ({:.2}x RNEA per path sample; once per job, again only for a placement whose timing re-planned)",
            bv / r,
            bv / m as f64 / r
        );
    }
}
