//! What the effects' plausibility rules share ([`super::Effect::implausible_fit`]; the driver
//! is `crate::identify::plausible`): the payload's limits, the rigid-body conditions of an
//! inertia, the standard errors a value may sit beyond a limit, and the rule of values that
//! are physically non-negative (friction, armature, standby).

use super::Payload;
use crate::robot::Inertial;

/// The payload may weigh at most this multiple of the robot's rated payload.
pub(crate) const PAYLOAD_RATED_FACTOR: f64 = 2.0;
/// Without a rated payload: at most this share of the moving links' mass.
pub(crate) const PAYLOAD_MOVING_MASS_SHARE: f64 = 0.5;
/// The payload's centre of mass lies within this distance of the flange origin, m.
pub(crate) const PAYLOAD_MAX_COM_M: f64 = 1.0;
/// Tolerance of the payload inertia's rigid-body conditions, kg·m².
pub(crate) const PAYLOAD_INERTIA_TOL_KG_M2: f64 = 0.01;
/// Standard errors a value may sit beyond a limit before it is implausible.
pub(crate) const PLAUSIBILITY_SIGMAS: f64 = 3.0;

/// Why a body's inertia about its centre of mass is no rigid body's (beyond `tol`), or `None`.
pub(crate) fn inertia_violation(b: &Inertial, tol: f64) -> Option<String> {
    let i = b.inertia;
    let eig = i.symmetric_eigen();
    let emin = eig
        .eigenvalues
        .iter()
        .cloned()
        .fold(f64::INFINITY, f64::min);
    let (a, bb, c) = (i[(0, 0)], i[(1, 1)], i[(2, 2)]);
    let tri = (a + bb - c).min(a + c - bb).min(bb + c - a);
    if emin < -tol || tri < -tol {
        Some(format!(
            "its inertia about the centre of mass is no rigid body's (smallest principal moment {emin:.4} kg·m², triangle inequality short by {:.4} kg·m²)",
            (-tri).max(0.0)
        ))
    } else {
        None
    }
}

/// The payload of `model` as written into the calibrated robot: the identified body, its
/// inertia raised to the nearest rigid body's when it violates the conditions by less than
/// the tolerance (the amount, kg·m², is returned; 0 when nothing was changed).
pub(crate) fn payload_written(p: &Payload) -> (Inertial, f64) {
    let mut b = p.body();
    let eig = b.inertia.symmetric_eigen();
    let emin = eig
        .eigenvalues
        .iter()
        .cloned()
        .fold(f64::INFINITY, f64::min);
    let (a, bb, c) = (b.inertia[(0, 0)], b.inertia[(1, 1)], b.inertia[(2, 2)]);
    let tri = (a + bb - c).min(a + c - bb).min(bb + c - a);
    let lift = (-emin).max(-tri).max(0.0);
    if lift > 0.0 {
        // Adding `λ 1` raises every principal moment by λ and every triangle slack by λ.
        b.inertia += crate::math::M3::identity() * lift;
    }
    (b, lift)
}

/// Whether value `i` was fitted (has a standard error).
pub(crate) fn fitted(std_errors: &[Option<f64>], i: usize) -> bool {
    std_errors.get(i).is_some_and(|s| s.is_some())
}

/// The standard error of value `i` (0 when held or not identifiable).
pub(crate) fn se(std_errors: &[Option<f64>], i: usize) -> f64 {
    std_errors.get(i).copied().flatten().unwrap_or(0.0)
}

/// The reasons, joined, or `None` when there are none.
pub(crate) fn reasons(why: Vec<String>) -> Option<String> {
    (!why.is_empty()).then(|| why.join("; "))
}

/// The rule of values that are physically non-negative (friction, armature, standby): each
/// fitted value below zero is a reason.
pub(crate) fn negative_fitted(
    specs: &[super::ParamSpec],
    v: &[f64],
    std_errors: &[Option<f64>],
) -> Vec<String> {
    let mut why = Vec::new();
    for (i, (s, x)) in specs.iter().zip(v).enumerate() {
        if *x < 0.0 && fitted(std_errors, i) {
            why.push(format!("{} = {x:.4} {} < 0", s.name, s.unit));
        }
    }
    why
}

/// [`negative_fitted`] of an effect's current values, joined.
pub(crate) fn implausible_if_negative(
    e: &dyn super::Effect,
    std_errors: &[Option<f64>],
) -> Option<String> {
    reasons(negative_fitted(&e.params(), &e.values(), std_errors))
}
