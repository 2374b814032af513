//! The reduced evaluation's path tracking (`printwatt::timing::joint::track_near`, behind
//! the representative layers' windows and the re-planned stretches of src/evaluate/reduce.rs)
//! against the per-sample `IkSolver::solve_near` loop it stands for: the same joint vectors
//! bit for bit, and the same first failing sample, tip and reason, on every SIMD level.

mod common;

use printwatt::kinematics::{nozzle_target, IkSolver};
use printwatt::math::{M3, V3};
use printwatt::simd::{self, Level};
use printwatt::timing::joint::track_near;
use std::sync::Mutex;

/// Held by every test here that sets the process-wide SIMD level (the libtest threads share
/// it).
static LEVEL_LOCK: Mutex<()> = Mutex::new(());

type Tracked = Result<Vec<u64>, (usize, [u64; 3], String)>;

/// The per-sample loop the reduced evaluation ran: `solve_near` near the previous answer.
fn per_sample(solver: &IkSolver, rot: &M3, tips: &[V3], q0: &[f64]) -> Tracked {
    let mut prev = q0.to_vec();
    let mut qs = Vec::new();
    for (i, t) in tips.iter().enumerate() {
        let target = printwatt::math::Frame { rot: *rot, pos: *t };
        match solver.solve_near(&target, &prev) {
            Ok(q) => {
                qs.extend(q.iter().map(|v| v.to_bits()));
                prev = q.to_vec();
            }
            Err(r) => return Err((i, bits(t), format!("{r:?}"))),
        }
    }
    Ok(qs)
}

fn bits(t: &V3) -> [u64; 3] {
    [t.x.to_bits(), t.y.to_bits(), t.z.to_bits()]
}

fn tracked(solver: &IkSolver, rot: &M3, tips: &[V3], q0: &[f64]) -> Tracked {
    let mut qs = vec![1.0; 7];
    match track_near(solver, rot, tips.len(), |i| tips[i], q0, &mut qs) {
        Ok(()) => Ok(qs.iter().map(|v| v.to_bits()).collect()),
        Err((i, t, r)) => Err((i, bits(&t), format!("{r:?}"))),
    }
}

/// A wavy circle of `len` tips about 1 mm apart around a point inside the arm's reach (base
/// frame, m) that the per-sample loop tracks to the end, and the arm's answer at the first.
fn circle(solver: &IkSolver, rot: &M3, len: usize) -> (Vec<V3>, Vec<f64>) {
    // The reach bound is loose for some arms: the first scale that tracks.
    for f in [0.55, 0.45, 0.35, 0.3, 0.25, 0.2] {
        let r = f * solver.reach_bound_m;
        let c = V3::new(r, 0.1 * r, 0.3 * r);
        let rad = 0.2 * r;
        let tips: Vec<V3> = (0..len)
            .map(|i| {
                let a = i as f64 * 0.001 / rad;
                c + V3::new(rad * a.cos(), rad * a.sin(), 0.04 * r * (7.0 * a).sin())
            })
            .collect();
        let first = printwatt::math::Frame {
            rot: *rot,
            pos: tips[0],
        };
        let Some(q0) = solver.solve_all(&first).ok().map(|s| s[0].q.to_vec()) else {
            continue;
        };
        if per_sample(solver, rot, &tips, &q0).is_ok() {
            return (tips, q0);
        }
    }
    panic!("{}: no circle tracks", solver.model.name())
}

/// Every shipped robot, on every SIMD level this CPU runs (and scalar), on `case`'s tips.
fn on_every_level(
    what: &str,
    case: impl Fn(&mut IkSolver, &M3) -> (Vec<V3>, Vec<f64>),
) -> Vec<Tracked> {
    let _g = LEVEL_LOCK.lock().unwrap_or_else(|e| e.into_inner());
    let mut answers = Vec::new();
    for name in [
        "abb_irb6700_200_260",
        "abb_irb4600_40_255",
        "staubli_tx200",
        "puma560",
        "ur10e",
    ] {
        let model = common::robot(name);
        let mut solver = IkSolver::new(&model).unwrap();
        let rot = nozzle_target(&V3::zeros(), 0.3).rot;
        let (tips, q0) = case(&mut solver, &rot);
        let want = per_sample(&solver, &rot, &tips, &q0);
        for level in [Level::Scalar, Level::Sse2, Level::Avx2, Level::Avx512] {
            if !simd::set_level(level) {
                continue;
            }
            let got = tracked(&solver, &rot, &tips, &q0);
            assert!(
                got == want,
                "{what}, {name} at {level:?}: {:?} where the per-sample loop gives {:?}",
                got.as_ref().map(|q| q.len()).map_err(|e| e.clone()),
                want.as_ref().map(|q| q.len()).map_err(|e| e.clone()),
            );
        }
        simd::set_level(simd::detected());
        answers.push(want);
    }
    answers
}

#[test]
fn lockstep_tracking_gives_the_per_sample_answers_on_a_feasible_path() {
    // 1003 samples: the last batch is partial.
    let answers = on_every_level("feasible", |s, rot| circle(s, rot, 1003));
    // Feasible for the arms the reduced evaluation batches (closed form).
    assert!(answers[..4].iter().all(|a| a.is_ok()), "{answers:?}");
}

#[test]
fn lockstep_tracking_reports_the_first_unreachable_sample_in_the_middle_of_a_batch() {
    let answers = on_every_level("unreachable", |s, rot| {
        let (mut tips, q0) = circle(s, rot, 1003);
        // Out of reach from sample 517 (lane 5 of its batch) for 3 samples, and again
        // later.
        for k in [517, 518, 519, 800] {
            tips[k] = V3::new(3.0 * s.reach_bound_m, 0.0, 0.0);
        }
        (tips, q0)
    });
    for a in &answers {
        assert!(matches!(a, Err((517, _, _))), "{a:?}");
    }
}

#[test]
fn lockstep_tracking_reports_a_failing_fk_recheck_ahead_of_a_later_unreachable_sample() {
    // The position tolerance of the FK re-check lowered to the error of a sample `f` in the
    // middle of a batch whose error is above every earlier one's: `f` fails its re-check
    // (deferred in lockstep), and the unreachable sample after it in the same batch must not
    // be reported instead.
    let fails = std::cell::RefCell::new(Vec::new());
    let answers = on_every_level("re-check", |s, rot| {
        let (mut tips, q0) = circle(s, rot, 1003);
        let per = per_sample(s, rot, &tips, &q0).expect("feasible circle");
        let mut worst = 0.0f64;
        let mut f = None;
        for (k, t) in tips.iter().enumerate().take(990) {
            let q: Vec<f64> = per[k * s.model.dof()..(k + 1) * s.model.dof()]
                .iter()
                .map(|b| f64::from_bits(*b))
                .collect();
            let target = printwatt::math::Frame { rot: *rot, pos: *t };
            let (dp, _) = s.check(&target, &q).expect("re-check passes by default");
            if k >= 100 && k % 8 <= 6 && dp > worst {
                f = Some((k, dp));
                break;
            }
            worst = worst.max(dp);
        }
        if let Some((k, dp)) = f {
            s.check_position_m = dp;
            tips[k + 1] = V3::new(3.0 * s.reach_bound_m, 0.0, 0.0);
        }
        fails.borrow_mut().push(f.map(|(k, _)| k));
        (tips, q0)
    });
    // Where a sample was found, the per-sample loop (and so the lockstep one) stops at its
    // failing re-check.
    let fails = fails.into_inner();
    assert!(fails.iter().any(|f| f.is_some()), "{fails:?}");
    for (f, a) in fails.iter().zip(&answers) {
        if let Some(f) = f {
            assert!(
                matches!(a, Err((k, _, r)) if k == f && r.starts_with("CheckFailed")),
                "{a:?}"
            );
        }
    }
}
