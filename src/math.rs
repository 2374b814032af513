//! Small rigid-transform helpers on nalgebra's fixed-size types (f64, SI units).

use nalgebra::{Matrix3, Vector3};

/// 3-vector, metres or radians depending on context.
pub type V3 = Vector3<f64>;
/// 3×3 matrix (rotations and inertia tensors).
pub type M3 = Matrix3<f64>;

/// A rigid transform: `x_parent = rot * x_child + pos`. `pos` in metres.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Frame {
    /// Rotation from child to parent axes.
    pub rot: M3,
    /// Origin of the child frame in the parent frame, m.
    pub pos: V3,
}

impl Default for Frame {
    fn default() -> Self {
        Self::identity()
    }
}

impl Frame {
    /// The identity transform.
    pub fn identity() -> Self {
        Frame {
            rot: M3::identity(),
            pos: V3::zeros(),
        }
    }

    /// Build from a rotation and a translation (m).
    pub fn new(rot: M3, pos: V3) -> Self {
        Frame { rot, pos }
    }

    /// URDF `<origin xyz rpy>`: translation in m, fixed-axis roll–pitch–yaw in rad,
    /// `R = Rz(yaw) · Ry(pitch) · Rx(roll)`.
    pub fn from_xyz_rpy(xyz: [f64; 3], rpy: [f64; 3]) -> Self {
        Frame {
            rot: rot_rpy(rpy[0], rpy[1], rpy[2]),
            pos: V3::new(xyz[0], xyz[1], xyz[2]),
        }
    }

    /// Composition `self ∘ other` (apply `other` first, then `self`).
    #[inline]
    pub fn compose(&self, other: &Frame) -> Frame {
        Frame {
            rot: self.rot * other.rot,
            pos: self.rot * other.pos + self.pos,
        }
    }

    /// The inverse transform.
    #[inline]
    pub fn inverse(&self) -> Frame {
        let rt = self.rot.transpose();
        Frame {
            rot: rt,
            pos: -(rt * self.pos),
        }
    }

    /// Map a point from child to parent coordinates.
    #[inline]
    pub fn apply(&self, p: &V3) -> V3 {
        self.rot * p + self.pos
    }
}

/// Rotation about x by `a` rad.
pub(crate) fn rot_x(a: f64) -> M3 {
    let (s, c) = a.sin_cos();
    M3::new(1.0, 0.0, 0.0, 0.0, c, -s, 0.0, s, c)
}

/// Rotation about y by `a` rad.
pub(crate) fn rot_y(a: f64) -> M3 {
    let (s, c) = a.sin_cos();
    M3::new(c, 0.0, s, 0.0, 1.0, 0.0, -s, 0.0, c)
}

/// Rotation about z by `a` rad.
pub(crate) fn rot_z(a: f64) -> M3 {
    let (s, c) = a.sin_cos();
    M3::new(c, -s, 0.0, s, c, 0.0, 0.0, 0.0, 1.0)
}

/// Fixed-axis roll, pitch, yaw (rad) as in URDF: `Rz(yaw) · Ry(pitch) · Rx(roll)`.
pub(crate) fn rot_rpy(roll: f64, pitch: f64, yaw: f64) -> M3 {
    rot_z(yaw) * rot_y(pitch) * rot_x(roll)
}

/// Rotation of `angle` rad about the unit `axis` (Rodrigues).
#[inline]
pub fn rot_axis(axis: &V3, angle: f64) -> M3 {
    let (s, c) = angle.sin_cos();
    rot_axis_sc(axis, s, c)
}

/// [`rot_axis`] from the angle's sine `s` and cosine `c`.
#[inline]
pub(crate) fn rot_axis_sc(axis: &V3, s: f64, c: f64) -> M3 {
    let t = 1.0 - c;
    let (x, y, z) = (axis.x, axis.y, axis.z);
    M3::new(
        t * x * x + c,
        t * x * y - s * z,
        t * x * z + s * y,
        t * x * y + s * z,
        t * y * y + c,
        t * y * z - s * x,
        t * x * z - s * y,
        t * y * z + s * x,
        t * z * z + c,
    )
}

/// Skew-symmetric matrix `[v]×` such that `[v]× w = v × w`.
pub fn skew(v: &V3) -> M3 {
    M3::new(0.0, -v.z, v.y, v.z, 0.0, -v.x, -v.y, v.x, 0.0)
}

/// Angle (rad) of the rotation `a^T b`, i.e. the geodesic distance between two rotations.
pub(crate) fn rotation_distance(a: &M3, b: &M3) -> f64 {
    let r = a.transpose() * b;
    ((r.trace() - 1.0) * 0.5).clamp(-1.0, 1.0).acos()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rodrigues_matches_elementary_rotations() {
        for &a in &[-2.0, -0.3, 0.0, 0.7, 3.0] {
            assert!((rot_axis(&V3::x(), a) - rot_x(a)).norm() < 1e-15);
            assert!((rot_axis(&V3::y(), a) - rot_y(a)).norm() < 1e-15);
            assert!((rot_axis(&V3::z(), a) - rot_z(a)).norm() < 1e-15);
        }
    }

    /// Roll, pitch, yaw (rad) of a rotation matrix, inverse of [`rot_rpy`].
    fn rpy_of(r: &M3) -> [f64; 3] {
        let pitch = (-r[(2, 0)]).clamp(-1.0, 1.0).asin();
        let roll = r[(2, 1)].atan2(r[(2, 2)]);
        let yaw = r[(1, 0)].atan2(r[(0, 0)]);
        [roll, pitch, yaw]
    }

    #[test]
    fn rpy_round_trip_and_inverse() {
        let f = Frame::from_xyz_rpy([0.1, -0.2, 0.3], [0.4, -0.5, 2.0]);
        let back = rpy_of(&f.rot);
        assert!((back[0] - 0.4).abs() < 1e-12 && (back[1] + 0.5).abs() < 1e-12);
        assert!((back[2] - 2.0).abs() < 1e-12);
        let id = f.compose(&f.inverse());
        assert!((id.rot - M3::identity()).norm() < 1e-14 && id.pos.norm() < 1e-14);
    }
}
