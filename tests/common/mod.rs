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
