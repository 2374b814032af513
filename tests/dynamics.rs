//! Rigid-body dynamics against Pinocchio 4.1 reference data, identities between algorithms,
//! the work–energy balance and the PUMA 560 published values.

#![allow(clippy::needless_range_loop)] // index-parallel arrays read more clearly in tests

mod common;
use common::{robot, Sines};
use printwatt::dynamics::*;
use printwatt::trajectory::JointTrajectory;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::f64::consts::PI;
use std::path::Path;

const ROBOTS: [&str; 5] = [
    "abb_irb6700_200_260",
    "abb_irb4600_40_255",
    "staubli_tx200",
    "ur10e",
    "puma560",
];
/// Relative tolerance vs Pinocchio: |Δ| ≤ REL_TOL · max(1, |τ|).
const REL_TOL: f64 = 1e-9;

/// Rows of a reference CSV (first line a comment, second the header). Missing file = failure.
fn csv(name: &str) -> (Vec<String>, Vec<Vec<f64>>) {
    let p = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/pinocchio")
        .join(name);
    let text = std::fs::read_to_string(&p)
        .unwrap_or_else(|e| panic!("reference file {} missing: {e}", p.display()));
    let mut lines = text.lines().filter(|l| !l.starts_with('#'));
    let header: Vec<String> = lines
        .next()
        .expect("header")
        .split(',')
        .map(|s| s.trim().to_string())
        .collect();
    let rows: Vec<Vec<f64>> = lines
        .filter(|l| !l.trim().is_empty())
        .map(|l| {
            l.split(',')
                .map(|x| x.trim().parse().expect("number"))
                .collect()
        })
        .collect();
    assert!(!rows.is_empty(), "{name}: no rows");
    (header, rows)
}

fn col(header: &[String], name: &str) -> usize {
    header
        .iter()
        .position(|h| h == name)
        .unwrap_or_else(|| panic!("column {name} missing"))
}

fn rel_err(got: f64, want: f64) -> f64 {
    (got - want).abs() / want.abs().max(1.0)
}

#[test]
fn rnea_gravity_mass_match_pinocchio_on_every_shipped_robot() {
    for name in ROBOTS {
        let r = robot(name);
        let n = r.dof();
        let bare = DynModel::new(&r, DynOptions::default()).unwrap();
        let full = common::dyn_model(&r, true);
        assert!(full.has_armature(), "{name}: drive data expected");
        let mut d = bare.data();
        let (h, rows) = csv(&format!("{name}.csv"));
        let c = |s: &str, j: usize| col(&h, &format!("{s}{}", j + 1));
        let (mut e_rb, mut e_full, mut e_g) = (0.0f64, 0.0f64, 0.0f64);
        let mut tau = vec![0.0; n];
        for row in &rows {
            let pick = |s: &str| (0..n).map(|j| row[c(s, j)]).collect::<Vec<f64>>();
            let (q, qd, qdd) = (pick("q"), pick("qd"), pick("qdd"));
            rnea(&bare, &mut d, &q, &qd, &qdd, &mut tau).unwrap();
            for j in 0..n {
                e_rb = e_rb.max(rel_err(tau[j], row[c("tau_rb", j)]));
            }
            rnea(&full, &mut d, &q, &qd, &qdd, &mut tau).unwrap();
            for j in 0..n {
                e_full = e_full.max(rel_err(tau[j], row[c("tau", j)]));
            }
            gravity_torque(&full, &mut d, &q, &mut tau).unwrap();
            for j in 0..n {
                e_g = e_g.max(rel_err(tau[j], row[c("g", j)]));
            }
        }
        let (hm, mrows) = csv(&format!("{name}_mass.csv"));
        let mut e_m = 0.0f64;
        let mut m = vec![0.0; n * n];
        for row in &mrows {
            let q: Vec<f64> = (0..n)
                .map(|j| row[col(&hm, &format!("q{}", j + 1))])
                .collect();
            mass_matrix(&full, &mut d, &q, &mut m).unwrap();
            for a in 0..n {
                for b in 0..n {
                    let want = row[col(&hm, &format!("M{}{}", a + 1, b + 1))];
                    e_m = e_m.max(rel_err(m[a * n + b], want));
                }
            }
        }
        println!(
            "{name}: {} states, max rel err tau_rb {e_rb:.1e}, tau {e_full:.1e}, g {e_g:.1e}, \
             M {e_m:.1e} ({} states)",
            rows.len(),
            mrows.len()
        );
        for (what, e) in [("tau_rb", e_rb), ("tau", e_full), ("g", e_g), ("M", e_m)] {
            assert!(
                e <= REL_TOL,
                "{name}: {what} differs from pinocchio by {e:e}"
            );
        }
    }
}

fn random_state(rng: &mut ChaCha8Rng, n: usize) -> Vec<f64> {
    (0..n).map(|_| rng.gen_range(-PI..PI)).collect()
}

#[test]
fn crba_equals_rnea_columns_and_is_spd() {
    let mut rng = ChaCha8Rng::seed_from_u64(42);
    for name in ["abb_irb6700_200_260", "ur10e", "puma560"] {
        let r = robot(name);
        let n = r.dof();
        let model = common::dyn_model(&r, true);
        let mut d = model.data();
        let (mut m, mut g, mut col_tau) = (vec![0.0; n * n], vec![0.0; n], vec![0.0; n]);
        for _ in 0..100 {
            let q = random_state(&mut rng, n);
            mass_matrix(&model, &mut d, &q, &mut m).unwrap();
            gravity_torque(&model, &mut d, &q, &mut g).unwrap();
            let zero = vec![0.0; n];
            let mut scale = 0.0f64;
            for j in 0..n {
                let mut e = zero.clone();
                e[j] = 1.0;
                rnea(&model, &mut d, &q, &zero, &e, &mut col_tau).unwrap();
                for i in 0..n {
                    let mij = col_tau[i] - g[i];
                    scale = scale.max(m[i * n + j].abs());
                    assert!(
                        (mij - m[i * n + j]).abs() <= 1e-10 * scale.max(1.0),
                        "{name}: CRBA vs RNEA column M[{i}][{j}]"
                    );
                    assert!((m[i * n + j] - m[j * n + i]).abs() <= 1e-12 * scale.max(1.0));
                }
            }
            let mm = nalgebra::DMatrix::from_row_slice(n, n, &m);
            assert!(mm.cholesky().is_some(), "{name}: M not positive definite");
        }
    }
}

#[test]
fn work_equals_change_of_kinetic_plus_potential_energy() {
    for (name, armature) in [
        ("abb_irb6700_200_260", true),
        ("ur10e", false),
        ("puma560", true),
    ] {
        let r = robot(name);
        let n = r.dof();
        let model = common::dyn_model(&r, armature);
        let mut d = model.data();
        let sines = Sines::random(n, 7, 0.1..0.5, 0.3..2.0);
        let traj = |t: f64| sines.at(t);
        let (t_end, steps) = (5.0, 20_000usize); // Simpson's rule, even number of steps
        let h = t_end / steps as f64;
        let mut tau = vec![0.0; n];
        let mut work = 0.0;
        let mut scale = 0.0f64;
        for k in 0..=steps {
            let (q, qd, qdd) = traj(k as f64 * h);
            rnea(&model, &mut d, &q, &qd, &qdd, &mut tau).unwrap();
            let p: f64 = tau.iter().zip(&qd).map(|(a, b)| a * b).sum();
            scale = scale.max(p.abs());
            let wgt = if k == 0 || k == steps {
                1.0
            } else if k % 2 == 1 {
                4.0
            } else {
                2.0
            };
            work += wgt * p;
        }
        work *= h / 3.0;
        let energy = |t: f64, d: &mut DynData| {
            let (q, qd, _) = traj(t);
            kinetic_energy(&model, d, &q, &qd).unwrap() + potential_energy(&model, d, &q).unwrap()
        };
        let delta = energy(t_end, &mut d) - energy(0.0, &mut d);
        let rel = (work - delta).abs() / delta.abs().max(scale * t_end * 1e-3);
        println!("{name}: work {work:.9} J, ΔE {delta:.9} J, rel {rel:.1e}");
        assert!(rel < 1e-6, "{name}: work {work} vs ΔE {delta}");
    }
}

#[test]
fn kinetic_energy_equals_half_qd_m_qd() {
    let r = robot("staubli_tx200");
    let n = r.dof();
    let model = common::dyn_model(&r, true);
    let mut d = model.data();
    let mut rng = ChaCha8Rng::seed_from_u64(3);
    let mut m = vec![0.0; n * n];
    for _ in 0..20 {
        let q = random_state(&mut rng, n);
        let qd = random_state(&mut rng, n);
        mass_matrix(&model, &mut d, &q, &mut m).unwrap();
        let mut t = 0.0;
        for i in 0..n {
            for j in 0..n {
                t += 0.5 * qd[i] * m[i * n + j] * qd[j];
            }
        }
        let ke = kinetic_energy(&model, &mut d, &q, &qd).unwrap();
        assert!((ke - t).abs() < 1e-10 * t.max(1.0), "{ke} vs {t}");
    }
}

/// PUMA 560 published values: /work/shared/reference/robots.md §7 (roboticstoolbox-python
/// 1.5.0, `gravload`, g = 9.81, no payload; `inertia(qn)` with G²Jm). The shipped URDF has
/// the same joint zero as the DH model (tools/reference/gen_pinocchio.py compares them the
/// same way), so every constant set applies. Values are given to 4 decimals.
#[test]
fn puma560_matches_published_gravity_and_inertia() {
    const DEG: f64 = PI / 180.0;
    const GRAVLOAD_NM: [([f64; 6], [f64; 6]); 4] = [
        (
            [0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
            [0.0, 37.4837, 0.2489, 0.0, 0.0, 0.0],
        ),
        (
            [0.0, 90.0, -90.0, 0.0, 0.0, 0.0],
            [0.0, -0.7752, 0.2489, 0.0, 0.0, 0.0],
        ),
        (
            [0.0, 0.0, -90.0, 0.0, 0.0, 0.0],
            [0.0, 46.0069, 8.7722, 0.0, 0.0283, 0.0],
        ),
        (
            [0.0, 45.0, -180.0, 0.0, 45.0, 0.0],
            [0.0, 31.6399, 6.0351, 0.0, 0.0283, 0.0],
        ),
    ];
    const M_QN_DIAG_KG_M2: [f64; 6] = [3.6594, 4.4137, 0.9378, 0.1925, 0.1713, 0.1941];
    const ROUNDING: f64 = 0.6e-4;
    let r = robot("puma560");
    let rigid = DynModel::new(&r, DynOptions::default()).unwrap();
    let mut d = rigid.data();
    let mut g = [0.0; 6];
    for (qdeg, want) in GRAVLOAD_NM {
        let q: Vec<f64> = qdeg.iter().map(|x| x * DEG).collect();
        gravity_torque(&rigid, &mut d, &q, &mut g).unwrap();
        for j in 0..6 {
            assert!(
                (g[j] - want[j]).abs() < ROUNDING,
                "q {qdeg:?} joint {j}: {g:?} vs {want:?}"
            );
        }
    }
    let with_arm = DynModel::new(
        &r,
        DynOptions {
            payload: false,
            armature: true,
        },
    )
    .unwrap();
    let q: Vec<f64> = GRAVLOAD_NM[3].0.iter().map(|x| x * DEG).collect();
    let mut m = [0.0; 36];
    mass_matrix(&with_arm, &mut d, &q, &mut m).unwrap();
    for j in 0..6 {
        let got = m[j * 6 + j];
        assert!(
            (got - M_QN_DIAG_KG_M2[j]).abs() < ROUNDING,
            "M(qn)[{j}][{j}] = {got} vs {}",
            M_QN_DIAG_KG_M2[j]
        );
    }
}

#[test]
fn fill_derivatives_is_exact_for_quadratics_on_nonuniform_grid() {
    let mut tr = JointTrajectory::new(2);
    let times = [0.0, 0.1, 0.25, 0.3, 0.7, 0.75, 1.2];
    for &t in &times {
        tr.push(
            t,
            &[1.0 + 2.0 * t - 3.0 * t * t, 0.5 * t * t],
            &[0.0; 2],
            &[0.0; 2],
        );
    }
    tr.qd.clear();
    tr.qdd.clear();
    fill_derivatives(&mut tr).unwrap();
    for (k, &t) in times.iter().enumerate() {
        assert!((tr.qd(k)[0] - (2.0 - 6.0 * t)).abs() < 1e-12);
        assert!((tr.qdd(k)[0] + 6.0).abs() < 1e-10);
        assert!((tr.qd(k)[1] - t).abs() < 1e-12);
        assert!((tr.qdd(k)[1] - 1.0).abs() < 1e-10);
    }
    let mut bad = JointTrajectory::new(1);
    bad.t = vec![0.0, 0.0];
    bad.q = vec![1.0, 2.0];
    assert!(fill_derivatives(&mut bad).is_err());
}

#[test]
fn missing_inertial_is_an_error_naming_the_link_and_sizes_are_checked() {
    let mut r = robot("ur10e");
    let name = r.link_names[2].clone();
    r.links[2] = None;
    let e = DynModel::new(&r, DynOptions::default())
        .unwrap_err()
        .to_string();
    assert!(e.contains(&name), "{e}");
    let r = robot("ur10e");
    let m = DynModel::new(&r, DynOptions::default()).unwrap();
    let mut d = m.data();
    let mut tau = [0.0; 6];
    assert!(rnea(&m, &mut d, &[0.0; 5], &[0.0; 6], &[0.0; 6], &mut tau).is_err());
    let mut mm = [0.0; 35];
    assert!(mass_matrix(&m, &mut d, &[0.0; 6], &mut mm).is_err());
}
