//! Finite-difference velocities and accelerations for trajectories that carry positions only.

use crate::error::{Error, Result};
use crate::trajectory::JointTrajectory;

/// Fill `qd` (rad/s) and `qdd` (rad/s²) of `traj` from its positions `q` (rad) and times `t` (s)
/// with [`crate::numerics::differentiate`] (the quadratic through three neighbouring samples;
/// the second-order central difference on a uniform grid; non-uniform steps handled).
///
/// Error: [`Error::Invalid`] if times are not strictly increasing or `q` has the wrong length.
pub fn fill_derivatives(traj: &mut JointTrajectory) -> Result<()> {
    let n = traj.n;
    let (qd, qdd) = crate::numerics::differentiate(
        crate::numerics::Grid::Times(&traj.t),
        &traj.q,
        n,
    )
    .map_err(|e| match e {
        Error::SizeMismatch { got, expected, .. } => Error::SizeMismatch {
            what: "fill_derivatives: q (samples × joints)".into(),
            got,
            expected,
        },
        Error::Invalid(m) => Error::Invalid(m.replace("differentiate:", "fill_derivatives:")),
        e => e,
    })?;
    traj.qd = qd;
    traj.qdd = qdd;
    Ok(())
}

/// Fill whatever derivatives a trajectory file did not give (see
/// [`crate::trajectory::Supplied`]): both given, nothing changes; q̇ given, q̈ (rad/s²) comes
/// from differentiating q̇; q̇ missing, q̇ (rad/s) comes from q and so does q̈ unless the file
/// gave it (then it is kept). Differences as in [`fill_derivatives`].
///
/// Error: as [`fill_derivatives`] (times not strictly increasing, wrong lengths).
pub fn complete_derivatives(
    traj: &mut JointTrajectory,
    supplied: crate::trajectory::Supplied,
) -> Result<()> {
    match (supplied.velocities, supplied.accelerations) {
        (true, true) => {}
        (true, false) => {
            let mut v = JointTrajectory {
                n: traj.n,
                t: traj.t.clone(),
                q: traj.qd.clone(),
                qd: vec![0.0; traj.qd.len()],
                qdd: vec![0.0; traj.qd.len()],
            };
            fill_derivatives(&mut v)?;
            traj.qdd = v.qd;
        }
        (false, acc) => {
            let keep = traj.qdd.clone();
            fill_derivatives(traj)?;
            if acc {
                traj.qdd = keep;
            }
        }
    }
    Ok(())
}
