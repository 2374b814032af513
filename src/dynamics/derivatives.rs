//! Finite-difference velocities and accelerations for trajectories that carry positions only.

use crate::error::{Error, Result};
use crate::trajectory::JointTrajectory;

/// Fill `qd` (rad/s) and `qdd` (rad/s²) of `traj` from its positions `q` (rad) and times `t` (s)
/// by differentiating the quadratic through three neighbouring samples (Lagrange form; equals
/// the second-order central difference on a uniform grid, handles non-uniform steps). Interior
/// samples use (k−1, k, k+1); the first and last use the one-sided windows (0, 1, 2) and
/// (N−3, N−2, N−1). Two samples: constant velocity, zero acceleration; one: zeros.
///
/// Error: [`Error::Invalid`] if times are not strictly increasing or `q` has the wrong length.
pub fn fill_derivatives(traj: &mut JointTrajectory) -> Result<()> {
    let n = traj.n;
    let len = traj.t.len();
    if traj.q.len() != len * n {
        return Err(Error::SizeMismatch {
            what: "fill_derivatives: q (samples × joints)".into(),
            got: traj.q.len(),
            expected: len * n,
        });
    }
    if let Some(k) = traj
        .t
        .windows(2)
        .position(|w| w[1].partial_cmp(&w[0]) != Some(std::cmp::Ordering::Greater))
    {
        return Err(Error::Invalid(format!(
            "fill_derivatives: time is not strictly increasing at sample {}",
            k + 1
        )));
    }
    traj.qd.clear();
    traj.qd.resize(len * n, 0.0);
    traj.qdd.clear();
    traj.qdd.resize(len * n, 0.0);
    if len < 2 {
        return Ok(());
    }
    if len == 2 {
        let h = traj.t[1] - traj.t[0];
        for j in 0..n {
            let v = (traj.q[n + j] - traj.q[j]) / h;
            traj.qd[j] = v;
            traj.qd[n + j] = v;
        }
        return Ok(());
    }
    for k in 0..len {
        let c = k.clamp(1, len - 2);
        let idx = [c - 1, c, c + 1];
        let ts = [traj.t[idx[0]], traj.t[idx[1]], traj.t[idx[2]]];
        let x = traj.t[k];
        // Lagrange basis derivatives at x, and constant second derivatives.
        let mut d1 = [0.0; 3];
        let mut d2 = [0.0; 3];
        for a in 0..3 {
            let (b, c2) = ((a + 1) % 3, (a + 2) % 3);
            let den = (ts[a] - ts[b]) * (ts[a] - ts[c2]);
            d1[a] = ((x - ts[b]) + (x - ts[c2])) / den;
            d2[a] = 2.0 / den;
        }
        for j in 0..n {
            let f = [
                traj.q[idx[0] * n + j],
                traj.q[idx[1] * n + j],
                traj.q[idx[2] * n + j],
            ];
            traj.qd[k * n + j] = d1[0] * f[0] + d1[1] * f[1] + d1[2] * f[2];
            traj.qdd[k * n + j] = d2[0] * f[0] + d2[1] * f[1] + d2[2] * f[2];
        }
    }
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
