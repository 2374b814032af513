//! The candidate grid of placements and the `min:max:step` ranges it is written in.

use serde::Serialize;

use crate::error::{Error, Result};
use crate::frame::Placement;

/// A regular grid of placements. Order of [`Grid::placements`]: z, yaw, spin, y, x (x fastest).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Grid {
    /// x values, m.
    pub xs: Vec<f64>,
    /// y values, m.
    pub ys: Vec<f64>,
    /// z values, m.
    pub zs: Vec<f64>,
    /// Part yaws, rad.
    pub yaws: Vec<f64>,
    /// Nozzle spins, rad.
    pub spins: Vec<f64>,
}

impl Grid {
    /// The finer of the x and y spacings (the first two values of each axis), m; `None` when
    /// both axes have a single value. `optimise` starts its simplex at half of it.
    pub fn step_xy_m(&self) -> Option<f64> {
        let d = |v: &[f64]| (v.len() > 1).then(|| (v[1] - v[0]).abs());
        match (d(&self.xs), d(&self.ys)) {
            (Some(a), Some(b)) => Some(a.min(b)),
            (a, b) => a.or(b),
        }
    }

    /// Number of placements.
    pub fn len(&self) -> usize {
        self.xs.len() * self.ys.len() * self.zs.len() * self.yaws.len() * self.spins.len()
    }
    /// True if the grid has no placements.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
    /// Flat index of `(ix, iy, iz, iyaw, ispin)`.
    pub fn index(&self, ix: usize, iy: usize, iz: usize, iyaw: usize, ispin: usize) -> usize {
        (((iz * self.yaws.len() + iyaw) * self.spins.len() + ispin) * self.ys.len() + iy)
            * self.xs.len()
            + ix
    }
    /// All placements, x fastest.
    pub fn placements(&self) -> Vec<Placement> {
        let mut v = Vec::with_capacity(self.len());
        for &z in &self.zs {
            for &yaw in &self.yaws {
                for &spin in &self.spins {
                    for &y in &self.ys {
                        for &x in &self.xs {
                            v.push(Placement {
                                x,
                                y,
                                z,
                                yaw,
                                nozzle_spin: spin,
                            });
                        }
                    }
                }
            }
        }
        v
    }
}

/// Parse `min:max:step` (or a single value, or a comma list) into values. Units are the
/// caller's (m on the command line). Errors name the text.
pub fn parse_range(what: &str, s: &str) -> Result<Vec<f64>> {
    let bad = |m: &str| Error::Invalid(format!("--{what} `{s}`: {m}"));
    let num = |t: &str| {
        t.trim()
            .parse::<f64>()
            .ok()
            .filter(|v| v.is_finite())
            .ok_or_else(|| bad(&format!("`{t}` is not a number")))
    };
    if s.contains(':') {
        let p: Vec<&str> = s.split(':').collect();
        if p.len() != 3 {
            return Err(bad("expected min:max:step"));
        }
        let (a, b, st) = (num(p[0])?, num(p[1])?, num(p[2])?);
        if st <= 0.0 {
            return Err(bad("step must be > 0"));
        }
        if b < a {
            return Err(bad("max < min"));
        }
        let n = ((b - a) / st + 1e-9).floor() as usize + 1;
        if n > 100_000 {
            return Err(bad("more than 100000 values"));
        }
        Ok((0..n).map(|i| a + st * i as f64).collect())
    } else {
        // An empty item (`1,,2`) is an error, not skipped: it is a typo.
        let v: Result<Vec<f64>> = s
            .split(',')
            .enumerate()
            .map(|(i, t)| {
                if t.trim().is_empty() {
                    Err(bad(&format!("item {} is empty", i + 1)))
                } else {
                    num(t)
                }
            })
            .collect();
        let v = v?;
        if v.is_empty() {
            return Err(bad("no values"));
        }
        Ok(v)
    }
}
