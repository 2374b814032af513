//! Physical plausibility of every effect's fitted values (docs/effects.md, "Plausibility"):
//! a fit no physical robot has is reported with the reason, is not written as the calibrated
//! robot by `identify` and is not claimed by `diagnose`.
//!
//! - `payload`: mass in `[0, k · rated payload]` ([`PAYLOAD_RATED_FACTOR`]; without a rated
//!   payload, [`PAYLOAD_MOVING_MASS_SHARE`] of the moving links' mass), centre of mass within
//!   [`PAYLOAD_MAX_COM_M`] of the flange origin (given the first moment's standard errors),
//!   inertia about the centre of mass a rigid body's (eigenvalues and triangle inequality,
//!   within [`PAYLOAD_INERTIA_TOL_KG_M2`]);
//! - `viscous`, `coulomb`, `stribeck`: friction ≥ 0 (and Stribeck velocity > 0);
//! - `balancer`: geometry physical (levers > 0 and different), stiffness ≥ 0; the preload may
//!   have either sign (a cylinder pushing at its shortest length);
//! - `armature` ≥ 0 and `copper` > 0 (no winding has zero resistance) for every fitted value;
//! - `gear_efficiency` in (0, 1], `regeneration` in [0, 1], `standby` ≥ 0;
//! - and what the effect itself says ([`crate::effects::Effect::implausible_fit`]: a
//!   `rigid_body` fit that gives a link a negative mass; a `balancer` on a robot whose drive
//!   file declares none).

use crate::effects::{Balancer, Payload};
use crate::identify::model::Model;
use crate::robot::Inertial;

/// The payload may weigh at most this multiple of the robot's rated payload.
pub const PAYLOAD_RATED_FACTOR: f64 = 2.0;
/// Without a rated payload: at most this share of the moving links' mass.
pub const PAYLOAD_MOVING_MASS_SHARE: f64 = 0.5;
/// The payload's centre of mass lies within this distance of the flange origin, m.
pub const PAYLOAD_MAX_COM_M: f64 = 1.0;
/// Tolerance of the payload inertia's rigid-body conditions, kg·m².
pub const PAYLOAD_INERTIA_TOL_KG_M2: f64 = 0.01;
/// Standard errors a value may sit beyond a limit before it is implausible.
pub(crate) const PLAUSIBILITY_SIGMAS: f64 = 3.0;

/// The largest payload mass that is plausible for the robot of `model`, kg.
pub(crate) fn payload_mass_limit(model: &Model) -> f64 {
    match model.rated_payload_kg {
        Some(r) if r > 0.0 => PAYLOAD_RATED_FACTOR * r,
        _ => PAYLOAD_MOVING_MASS_SHARE * model.moving_mass_kg,
    }
}

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

fn fitted(std_errors: &[Option<f64>], i: usize) -> bool {
    std_errors.get(i).is_some_and(|s| s.is_some())
}

fn se(std_errors: &[Option<f64>], i: usize) -> f64 {
    std_errors.get(i).copied().flatten().unwrap_or(0.0)
}

/// Why the current (fitted) values of effect `name` are not physically plausible for the
/// robot of `model`, given each value's standard error (`None`: held or not identifiable), or
/// `None` when they are. See the module docs for the rules.
pub fn implausible_fit(model: &Model, name: &str, std_errors: &[Option<f64>]) -> Option<String> {
    if let Some(w) = model.implausible_fit(name, std_errors) {
        return Some(w);
    }
    let e = model.effect(name).ok()?;
    let specs = e.params();
    let v = e.values();
    let mut why: Vec<String> = Vec::new();
    match name {
        "payload" => {
            let p = e.as_any().downcast_ref::<Payload>()?;
            payload_reasons(model, p, std_errors, &mut why);
        }
        "viscous" | "coulomb" | "stribeck" | "armature" | "standby" => {
            sign_reasons(name, &specs, &v, std_errors, &mut why);
        }
        "copper" => {
            for (i, (s, x)) in specs.iter().zip(&v).enumerate() {
                if *x <= 0.0 && fitted(std_errors, i) {
                    why.push(format!(
                        "{} = {x:.4} {}: no winding has zero or negative resistance",
                        s.name, s.unit
                    ));
                }
            }
        }
        "gear_efficiency" => {
            for (s, x) in specs.iter().zip(&v) {
                if !(*x > 0.0 && *x <= 1.0) {
                    why.push(format!("{} = {x:.4} outside (0, 1]", s.name));
                }
            }
        }
        "regeneration" => {
            for (s, x) in specs.iter().zip(&v) {
                if !(0.0..=1.0).contains(x) {
                    why.push(format!("{} = {x:.4} outside [0, 1]", s.name));
                }
            }
        }
        "balancer" => {
            let b = e.as_any().downcast_ref::<Balancer>()?;
            balancer_reasons(b, std_errors, &mut why);
        }
        _ => {}
    }
    (!why.is_empty()).then(|| why.join("; "))
}

/// Why a fitted payload is not plausible: a negative mass or one above the limit, a centre of
/// mass too far from the flange, an inertia no rigid body has.
fn payload_reasons(model: &Model, p: &Payload, std_errors: &[Option<f64>], why: &mut Vec<String>) {
    let (m, h, _) = p.standard();
    let limit = payload_mass_limit(model);
    let sm = PLAUSIBILITY_SIGMAS * se(std_errors, 0);
    if m < -sm {
        why.push(format!("its mass is {m:.3} kg (< 0)"));
    } else if m > limit + sm {
        why.push(format!(
            "its mass {m:.3} kg is above {limit:.1} kg ({})",
            match model.rated_payload_kg {
                Some(r) if r > 0.0 => format!("{PAYLOAD_RATED_FACTOR} × the rated payload {r} kg"),
                _ => format!(
                    "{PAYLOAD_MOVING_MASS_SHARE} × the moving links' {:.1} kg",
                    model.moving_mass_kg
                ),
            }
        ));
    }
    let sh = (1..4).map(|i| se(std_errors, i)).fold(0.0, f64::max);
    if h.norm() > m.max(0.0) * PAYLOAD_MAX_COM_M + PLAUSIBILITY_SIGMAS * sh * 3f64.sqrt() {
        let b = p.body();
        why.push(format!(
            "its centre of mass lies {:.2} m from the flange origin (first moment {:.3} kg·m for {m:.3} kg; at most {PAYLOAD_MAX_COM_M} m)",
            b.com.norm(),
            h.norm()
        ));
    }
    if m > 0.0 && why.is_empty() {
        let si = (4..10).map(|i| se(std_errors, i)).fold(0.0, f64::max);
        let tol = PAYLOAD_INERTIA_TOL_KG_M2 + PLAUSIBILITY_SIGMAS * si;
        if let Some(w) = inertia_violation(&p.body(), tol) {
            why.push(w);
        }
    }
}

/// Why fitted friction, armature or standby values are not plausible: a fitted value below
/// zero, a Stribeck velocity that is not positive.
fn sign_reasons(
    name: &str,
    specs: &[crate::effects::ParamSpec],
    v: &[f64],
    std_errors: &[Option<f64>],
    why: &mut Vec<String>,
) {
    for (i, (s, x)) in specs.iter().zip(v).enumerate() {
        if *x < 0.0 && fitted(std_errors, i) {
            why.push(format!("{} = {x:.4} {} < 0", s.name, s.unit));
        }
    }
    if name == "stribeck" {
        if let Some((s, x)) = specs.iter().zip(v).find(|(s, _)| s.name.starts_with("v_s")) {
            if *x <= 0.0 {
                why.push(format!("{} = {x} {} is not > 0", s.name, s.unit));
            }
        }
    }
}

/// Why a fitted balancer is not plausible: levers that are not physical, a negative
/// stiffness.
fn balancer_reasons(b: &Balancer, std_errors: &[Option<f64>], why: &mut Vec<String>) {
    if !(b.a > 0.0 && b.b > 0.0 && (b.a - b.b).abs() > 1e-6) {
        why.push(format!(
            "its geometry is not physical (levers {} m and {} m must be > 0 and differ)",
            b.a, b.b
        ));
    }
    if b.stiffness < -PLAUSIBILITY_SIGMAS * se(std_errors, 1) {
        why.push(format!("its stiffness {:.1} N/m is < 0", b.stiffness));
    }
}
