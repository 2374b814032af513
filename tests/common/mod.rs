//! Helpers shared by the integration tests: shipped robots, relative comparison, and smooth
//! sum-of-sines joint motion with exact derivatives.
#![allow(dead_code)] // each test binary uses a subset

use printwatt::robot::{load, RobotModel};
use printwatt::trajectory::JointTrajectory;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::f64::consts::PI;
use std::path::PathBuf;

/// The repository root.
pub fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// A shipped robot by directory name.
pub fn robot(name: &str) -> RobotModel {
    load(&root().join("robots").join(name)).unwrap_or_else(|e| panic!("loading {name}: {e}"))
}

/// The rigid-body model of `model` with its payload, and with the motors' reflected rotor
/// inertia (armature) when `armature` is set.
pub fn dyn_model(model: &RobotModel, armature: bool) -> printwatt::dynamics::DynModel {
    printwatt::dynamics::DynModel::new(
        model,
        printwatt::dynamics::DynOptions {
            payload: true,
            armature,
        },
    )
    .unwrap_or_else(|e| panic!("dynamic model of {}: {e}", model.name()))
}

/// A deterministic stream of pseudo-random numbers in [0, 1) (xorshift; seeded).
pub fn xorshift(seed: u64) -> impl FnMut() -> f64 {
    let mut s = seed.max(1);
    move || {
        s ^= s << 13;
        s ^= s >> 7;
        s ^= s << 17;
        (s >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// `|a − b| ≤ rel · max(|a|, |b|, 1)`.
pub fn close(a: f64, b: f64, rel: f64) -> bool {
    (a - b).abs() <= rel * a.abs().max(b.abs()).max(1.0)
}

/// Joint motion `q_j(t) = Σ a sin(ω t + φ)` per joint, with exact q̇ and q̈.
pub struct Sines {
    /// Per joint: (amplitude rad, angular frequency rad/s, phase rad).
    pub terms: Vec<Vec<(f64, f64, f64)>>,
}

impl Sines {
    /// Three terms per joint drawn from a seeded ChaCha8: amplitude in `amp` (rad), angular
    /// frequency in `omega` (rad/s), phase in [0, 2π).
    pub fn random(
        n: usize,
        seed: u64,
        amp: std::ops::Range<f64>,
        omega: std::ops::Range<f64>,
    ) -> Self {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let terms = (0..n)
            .map(|_| {
                (0..3)
                    .map(|_| {
                        (
                            rng.gen_range(amp.clone()),
                            rng.gen_range(omega.clone()),
                            rng.gen_range(0.0..2.0 * PI),
                        )
                    })
                    .collect()
            })
            .collect();
        Sines { terms }
    }

    /// Multiply every amplitude by `k`.
    pub fn scaled(mut self, k: f64) -> Self {
        for t in self.terms.iter_mut().flatten() {
            t.0 *= k;
        }
        self
    }

    /// (q, q̇, q̈) at time `t` (s).
    pub fn at(&self, t: f64) -> (Vec<f64>, Vec<f64>, Vec<f64>) {
        let n = self.terms.len();
        let (mut q, mut qd, mut qdd) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
        for (j, terms) in self.terms.iter().enumerate() {
            for &(a, w, p) in terms {
                let (s, c) = (w * t + p).sin_cos();
                q[j] += a * s;
                qd[j] += a * w * c;
                qdd[j] -= a * w * w * s;
            }
        }
        (q, qd, qdd)
    }

    /// `steps + 1` uniform samples on [0, t_end] (s).
    pub fn trajectory(&self, t_end: f64, steps: usize) -> JointTrajectory {
        let mut tr = JointTrajectory::new(self.terms.len());
        for k in 0..=steps {
            let t = t_end * k as f64 / steps as f64;
            let (q, qd, qdd) = self.at(t);
            tr.push(t, &q, &qd, &qdd);
        }
        tr
    }
}

/// A shipped path (`paths/<name>`) read with the default options.
pub fn path(name: &str) -> printwatt::toolpath::Toolpath {
    printwatt::toolpath::load(
        &root().join("paths").join(name),
        &printwatt::toolpath::ReadOptions::default(),
    )
    .unwrap_or_else(|e| panic!("loading path {name}: {e}"))
}

/// The job of `path` on `model` with every option at its default (energy, Cartesian profile,
/// joint stage): what most placement tests evaluate.
pub fn default_job<'a>(
    model: &'a RobotModel,
    path: &printwatt::toolpath::Toolpath,
) -> printwatt::evaluate::PathJob<'a> {
    printwatt::evaluate::PathJob::new(
        model,
        path,
        printwatt::energy::EnergyOptions::default(),
        printwatt::timing::ProfileOptions::default(),
        printwatt::timing::JointStageOptions::default(),
    )
    .unwrap_or_else(|e| panic!("job of {}: {e}", path.source))
}

/// The `printwatt` binary, run in the repository root.
pub fn bin() -> std::process::Command {
    let mut c = std::process::Command::new(env!("CARGO_BIN_EXE_printwatt"));
    c.current_dir(root());
    c
}

/// Run `printwatt args` in `cwd`.
pub fn run(args: &[&str], cwd: &std::path::Path) -> std::process::Output {
    std::process::Command::new(env!("CARGO_BIN_EXE_printwatt"))
        .args(args)
        .current_dir(cwd)
        .output()
        .expect("run printwatt")
}

/// A fresh scratch directory `printwatt-<prefix>-<pid>-<name>` under the system's temp dir.
pub fn scratch(prefix: &str, name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("printwatt-{prefix}-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// The parts a supply energy is made of, J: rigid body, balancer, friction, gear, copper,
/// regeneration lost and standby.
pub fn supply_parts(t: &printwatt::energy::TotalEnergy) -> f64 {
    t.rigid_body_j
        + t.balancer_j
        + t.friction_j
        + t.gear_j
        + t.copper_j
        + t.regeneration_lost_j
        + t.standby_j
}

/// Assert that a command succeeded, showing its stderr when it did not.
pub fn assert_ok(o: &std::process::Output) {
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
}

/// Run `printwatt args` in `cwd` and assert that it succeeded (naming the arguments when it
/// did not); its output.
pub fn run_ok(args: &[&str], cwd: &std::path::Path) -> std::process::Output {
    let o = run(args, cwd);
    assert!(
        o.status.success(),
        "{args:?}: {}",
        String::from_utf8_lossy(&o.stderr)
    );
    o
}

/// Run `cmd` to its end and assert that it succeeded; its output.
pub fn ok(cmd: &mut std::process::Command) -> std::process::Output {
    let o = cmd.output().expect("run");
    assert_ok(&o);
    o
}

/// A written report (XHTML, with a DTD) parsed as XML.
pub fn parse_xhtml(html: &str) -> roxmltree::Document<'_> {
    roxmltree::Document::parse_with_options(
        html,
        roxmltree::ParsingOptions {
            allow_dtd: true,
            ..Default::default()
        },
    )
    .expect("report.html is well-formed XML")
}

/// The ids of a report's figures, in document order.
pub fn figure_ids<'a>(doc: &'a roxmltree::Document) -> Vec<&'a str> {
    doc.descendants()
        .filter(|n| n.has_tag_name("figure"))
        .filter_map(|n| n.attribute("id"))
        .collect()
}

/// A command's stderr as text.
pub fn stderr_of(o: &std::process::Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// Every uncertainty range zero: a draw is the nominal robot but for what a calibrated robot
/// identified.
pub fn zero_ranges() -> printwatt::search::uncertainty::Ranges {
    printwatt::search::uncertainty::Ranges {
        link_mass_rel: 0.0,
        link_com_m: 0.0,
        link_inertia_rel: 0.0,
        payload_mass_rel: 0.0,
        torque_constant_rel: 0.0,
        winding_resistance_rel: 0.0,
        viscous_rel: 0.0,
        coulomb_rel: 0.0,
        gear_efficiency_abs: 0.0,
        standby_power_rel: 0.0,
        balancer_absent_probability: 0.0,
        balancer_force_rel: 0.0,
    }
}

/// A one-cell optimisation that the default robot can do on the default path in a few
/// evaluations: `printwatt optimise` plus these arguments.
pub const ONE_CELL_OPTIMISE: [&str; 11] = [
    "optimise",
    "--x",
    "1.5",
    "--y",
    "0",
    "--z",
    "0.5",
    "--yaw",
    "90",
    "--max-evals",
    "4",
];
