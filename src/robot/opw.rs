//! Parameters of an ortho-parallel arm with a spherical wrist, in the convention of
//! Brandstötter, Angerer, Hofbaur, "An analytical solution of the inverse kinematics problem of
//! industrial serial manipulators with an ortho-parallel basis and a spherical wrist" (2014), as
//! used by opw_kinematics: `q_opw = q · sign − offset`. Lengths in m, offsets in rad.

/// OPW geometry and the map between OPW and URDF joint angles.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OpwParams {
    /// Shoulder offset along x, m.
    pub a1: f64,
    /// Elbow offset (forearm axis below/above the upper-arm line), m.
    pub a2: f64,
    /// Lateral offset along y, m.
    pub b: f64,
    /// Shoulder height, m.
    pub c1: f64,
    /// Upper-arm length, m.
    pub c2: f64,
    /// Forearm length, m.
    pub c3: f64,
    /// Wrist centre to flange, m.
    pub c4: f64,
    /// Offsets, rad: `q_opw = q · sign − offset`.
    pub offsets: [f64; 6],
    /// Direction signs (+1 or −1).
    pub signs: [f64; 6],
}

use crate::math::{Frame, M3, V3};

impl OpwParams {
    /// Map URDF joint angles (rad) to OPW angles: `q_opw = q · sign − offset`.
    #[inline]
    pub fn to_opw(&self, q: &[f64]) -> [f64; 6] {
        let mut o = [0.0; 6];
        for i in 0..6 {
            o[i] = q[i] * self.signs[i] - self.offsets[i];
        }
        o
    }

    /// Map OPW angles back to URDF joint angles (rad): `q = (q_opw + offset) · sign`.
    #[inline]
    pub fn from_opw(&self, o: &[f64; 6]) -> [f64; 6] {
        let mut q = [0.0; 6];
        for i in 0..6 {
            q[i] = (o[i] + self.offsets[i]) * self.signs[i];
        }
        q
    }

    /// Flange pose in the base frame for URDF joint angles `q` (rad), by the closed-form
    /// forward kinematics of the OPW paper (eqs. for `c` and `R_0c · R_ce`).
    pub fn forward(&self, q: &[f64]) -> Frame {
        let o = self.to_opw(q);
        let psi3 = self.a2.atan2(self.c3);
        let k = (self.a2 * self.a2 + self.c3 * self.c3).sqrt();
        let cx1 = self.c2 * o[1].sin() + k * (o[1] + o[2] + psi3).sin() + self.a1;
        let cy1 = self.b;
        let cz1 = self.c2 * o[1].cos() + k * (o[1] + o[2] + psi3).cos();
        let (s0, c0) = o[0].sin_cos();
        let c = V3::new(cx1 * c0 - cy1 * s0, cx1 * s0 + cy1 * c0, cz1 + self.c1);
        let (s1, c1) = o[0].sin_cos();
        let (s23, c23) = (o[1] + o[2]).sin_cos();
        let r0c = M3::new(
            c1 * c23,
            -s1,
            c1 * s23,
            s1 * c23,
            c1,
            s1 * s23,
            -s23,
            0.0,
            c23,
        );
        let (s4, c4) = o[3].sin_cos();
        let (s5, c5) = o[4].sin_cos();
        let (s6, c6) = o[5].sin_cos();
        let rce = M3::new(
            c4 * c5 * c6 - s4 * s6,
            -c4 * c5 * s6 - s4 * c6,
            c4 * s5,
            s4 * c5 * c6 + c4 * s6,
            -s4 * c5 * s6 + c4 * c6,
            s4 * s5,
            -s5 * c6,
            s5 * s6,
            c5,
        );
        let r = r0c * rce;
        let pos = c + r.column(2) * self.c4;
        Frame { rot: r, pos }
    }
}
