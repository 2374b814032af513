//! Joint trajectories: samples of time, position, velocity and acceleration per joint.

use crate::error::{Error, Result};

/// A sampled joint trajectory. Positions in rad (m for prismatic joints), velocities in
/// rad/s, accelerations in rad/s², times in s. Joint values are stored row-major: sample `k`,
/// joint `j` at index `k * n + j`.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct JointTrajectory {
    /// Number of joints.
    pub n: usize,
    /// Sample times, s, strictly increasing.
    pub t: Vec<f64>,
    /// Positions, rad (row-major, `t.len() * n`).
    pub q: Vec<f64>,
    /// Velocities, rad/s (row-major).
    pub qd: Vec<f64>,
    /// Accelerations, rad/s² (row-major).
    pub qdd: Vec<f64>,
}

impl JointTrajectory {
    /// An empty trajectory for `n` joints.
    pub fn new(n: usize) -> Self {
        JointTrajectory {
            n,
            ..Default::default()
        }
    }

    /// Append one sample; slices must have length `n`.
    pub fn push(&mut self, t: f64, q: &[f64], qd: &[f64], qdd: &[f64]) {
        debug_assert!(q.len() == self.n && qd.len() == self.n && qdd.len() == self.n);
        self.t.push(t);
        self.q.extend_from_slice(q);
        self.qd.extend_from_slice(qd);
        self.qdd.extend_from_slice(qdd);
    }

    /// Number of samples.
    pub fn len(&self) -> usize {
        self.t.len()
    }

    /// Whether there are no samples.
    pub fn is_empty(&self) -> bool {
        self.t.is_empty()
    }

    /// Positions of sample `k`, rad.
    pub fn q(&self, k: usize) -> &[f64] {
        &self.q[k * self.n..(k + 1) * self.n]
    }

    /// Velocities of sample `k`, rad/s.
    pub fn qd(&self, k: usize) -> &[f64] {
        &self.qd[k * self.n..(k + 1) * self.n]
    }

    /// Accelerations of sample `k`, rad/s².
    pub fn qdd(&self, k: usize) -> &[f64] {
        &self.qdd[k * self.n..(k + 1) * self.n]
    }

    /// Duration, s.
    pub fn duration(&self) -> f64 {
        match (self.t.first(), self.t.last()) {
            (Some(a), Some(b)) => b - a,
            _ => 0.0,
        }
    }

    /// Check that times are finite and strictly increasing and all values finite.
    pub fn validate(&self, what: &str) -> Result<()> {
        for (k, w) in self.t.windows(2).enumerate() {
            if !(w[1] > w[0]) {
                return Err(Error::Invalid(format!(
                    "{what}: time is not strictly increasing at sample {} (t = {} then {})",
                    k + 1,
                    w[0],
                    w[1]
                )));
            }
        }
        for (name, v) in [("q", &self.q), ("qd", &self.qd), ("qdd", &self.qdd)] {
            if let Some(i) = v.iter().position(|x| !x.is_finite()) {
                return Err(Error::Invalid(format!(
                    "{what}: {name}{} is not finite at sample {}",
                    i % self.n + 1,
                    i / self.n
                )));
            }
        }
        Ok(())
    }
}
