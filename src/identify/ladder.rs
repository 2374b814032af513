//! Identification with the error ladder: the base model, then each listed effect added in turn
//! (all added so far re-fitted jointly on the training data), each step validated on held-out
//! data (the last quarter of the log, or a second log). Parameters the motion does not excite
//! (or cannot tell apart) are named, held at their prior values, and the others fitted
//! ([`crate::identify::fit::fit_holding`]). The calibrated robot is written by
//! [`crate::identify::calibrate`].

use crate::error::Result;
use crate::identify::fit::{fit_holding, FittedParam, IllConditioning};
use crate::identify::metrics::{evaluate_rows, rel_pct};
use crate::identify::model::{Model, Prepared};
use serde::Serialize;

/// One rung of the ladder.
#[derive(Clone, Debug, Serialize)]
pub struct LadderStep {
    /// `base` or `+effect`.
    pub step: String,
    /// Effects fitted so far.
    pub fitted: Vec<String>,
    /// RMSE on the training data (signal unit).
    pub train_rmse: f64,
    /// RMSE on the validation data (signal unit).
    pub validation_rmse: f64,
    /// Relative energy error on the validation data, %.
    pub validation_energy_error_pct: f64,
    /// `100 − |energy error|`, %.
    pub validation_accuracy_pct: f64,
}

/// The identification result.
#[derive(Clone, Debug, Serialize)]
pub struct Identification {
    /// What was validated on.
    pub validation: String,
    /// The ladder.
    pub ladder: Vec<LadderStep>,
    /// Parameters of the final fit (values withheld from display when ill-conditioned).
    pub params: Vec<FittedParam>,
    /// Parameters the data cannot tell apart, if any (in the first fit of the last rung).
    pub ill_conditioned: Option<IllConditioning>,
    /// Parameters held at their prior values because the motion does not excite them or
    /// cannot tell them apart; the others are fitted.
    pub held_at_prior: Vec<HeldParam>,
    /// Fitted parameters of the final fit that sit at a bound of their range: the fit wanted
    /// to go further (another effect may be missing, or soaked up by this one).
    pub at_bound: Vec<String>,
    /// Effects whose final fitted values are not physically plausible, with the reason
    /// ([`crate::identify::plausible`]); such a fit is not written as the calibrated robot.
    pub implausible: Vec<String>,
    /// Rows per block of the autocorrelation-consistent standard errors of the final fit.
    pub hac_block_rows: usize,
    /// Correlation of the final fit's parameters that have a standard error.
    pub correlation: crate::identify::fit::Correlation,
}

/// A parameter held at its prior value, and why.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct HeldParam {
    /// `effect.param`, e.g. `coulomb.f_c[5]`.
    pub name: String,
    /// Why, in words.
    pub reason: String,
}

/// RMS joint velocity below which a joint counts as still, rad/s (0.06 °/s: position noise and
/// encoder quantisation of a joint held by its brake or servo give less).
pub(crate) const STILL_RMS_VELOCITY_RAD_S: f64 = 1e-3;

/// Parameters of the per-joint effects that act only while their joint moves
/// ([`crate::effects::Effect::needs_joint_motion`]: friction, armature) on joints that do not
/// move in `rows` of the log.
pub(crate) fn still_joint_params(
    model: &Model,
    prep: &Prepared,
    rows: &[usize],
    effects: &[&'static str],
) -> Vec<HeldParam> {
    let n = model.n;
    let mut out = Vec::new();
    for j in 0..n {
        let ms = rows
            .iter()
            .map(|&k| prep.log.traj.rates(k).qd()[j].powi(2))
            .sum::<f64>()
            / rows.len().max(1) as f64;
        let rms = ms.sqrt();
        if rms >= STILL_RMS_VELOCITY_RAD_S {
            continue;
        }
        for e in effects {
            if !model.effect(e).is_ok_and(|x| x.needs_joint_motion()) {
                continue;
            }
            for p in model.params(e).unwrap_or_default() {
                if p.name.ends_with(&format!("[{}]", j + 1)) {
                    out.push(HeldParam {
                        name: format!("{e}.{}", p.name),
                        reason: format!(
                            "joint {} does not move (RMS velocity {rms:.1e} rad/s)",
                            j + 1
                        ),
                    });
                }
            }
        }
    }
    out
}

/// Identify `effects` in order. `train`: prepared training log and its rows; `val`: validation
/// log and rows. The model ends with the final fit.
pub fn identify(
    model: &mut Model,
    train: (&Prepared, &[usize]),
    val: (&Prepared, &[usize]),
    effects: &[&'static str],
    validation: String,
) -> Result<Identification> {
    identify_holding(model, train, val, effects, validation, &[])
}

/// [`identify`] holding the parameters `hold` at their prior values (`effect.param` with the
/// reason, e.g. the joints outside a per-joint subset, [`Model::params_outside`]).
pub(crate) fn identify_holding(
    model: &mut Model,
    train: (&Prepared, &[usize]),
    val: (&Prepared, &[usize]),
    effects: &[&'static str],
    validation: String,
    hold: &[HeldParam],
) -> Result<Identification> {
    let step = |model: &Model, name: String, fitted: &[&str]| {
        let (tr, _, _) = evaluate_rows(train.0, model, train.1);
        let (vr, em, ep) = evaluate_rows(val.0, model, val.1);
        let e = rel_pct(ep, em);
        LadderStep {
            step: name,
            fitted: fitted.iter().map(|s| s.to_string()).collect(),
            train_rmse: tr,
            validation_rmse: vr,
            validation_energy_error_pct: e,
            validation_accuracy_pct: 100.0 - e.abs(),
        }
    };
    let mut ladder = vec![step(model, "base".into(), &[])];
    let mut last = None;
    let mut held: Vec<HeldParam> = hold.to_vec();
    for h in still_joint_params(model, train.0, train.1, effects) {
        if !held.iter().any(|x| x.name == h.name) {
            held.push(h);
        }
    }
    let mut first_ill = None;
    for i in 0..effects.len() {
        let before = model.state();
        let names: Vec<String> = held.iter().map(|h| h.name.clone()).collect();
        let mut r = fit_holding(train.0, model, &effects[..=i], train.1, &names)?;
        // Hold what the motion cannot determine at its prior and fit the rest (again, if
        // the reduced fit still finds a direction it cannot determine).
        for _pass in 0..3 {
            let Some(ill) = r.ill_conditioned.clone() else {
                break;
            };
            hold_ill_conditioned(&ill, &mut held);
            model.restore(&before);
            let names: Vec<String> = held.iter().map(|h| h.name.clone()).collect();
            r = fit_holding(train.0, model, &effects[..=i], train.1, &names)?;
            first_ill.get_or_insert(ill);
        }
        ladder.push(step(model, format!("+{}", effects[i]), &effects[..=i]));
        last = Some(r);
    }
    let (params, at_bound, hac_block_rows, correlation) = last
        .map(|r| (r.params, r.at_bound, r.hac_block_rows, r.correlation))
        .unwrap_or_default();
    let implausible = implausible_effects(model, effects, &params, &held);
    Ok(Identification {
        validation,
        ladder,
        params,
        ill_conditioned: first_ill,
        held_at_prior: held,
        at_bound,
        implausible,
        hac_block_rows,
        correlation,
    })
}

/// Every parameter of an ill-conditioned fit's groups held at its prior (once), with the
/// reason: not excited, or not told apart from the rest of its group.
fn hold_ill_conditioned(ill: &crate::identify::fit::IllConditioning, held: &mut Vec<HeldParam>) {
    for g in &ill.groups {
        for name in g {
            if !held.iter().any(|h| h.name == *name) {
                held.push(HeldParam {
                    name: name.clone(),
                    reason: if g.len() == 1 {
                        "not excited by this motion".into()
                    } else {
                        format!("cannot be told apart from {}", g.join(", "))
                    },
                });
            }
        }
    }
}

/// Why the fitted values of each of `effects` are not plausible (`effect: why`), held
/// parameters counting as without a standard error.
fn implausible_effects(
    model: &Model,
    effects: &[&'static str],
    params: &[crate::identify::fit::FittedParam],
    held: &[HeldParam],
) -> Vec<String> {
    let mut implausible = Vec::new();
    for e in effects {
        let se: Vec<Option<f64>> = params
            .iter()
            .filter(|p| p.effect == *e)
            .map(|p| {
                let key = format!("{}.{}", p.effect, p.name);
                if held.iter().any(|h| h.name == key) {
                    None
                } else {
                    p.std_error
                }
            })
            .collect();
        if let Some(w) = crate::identify::plausible::implausible_fit(model, e, &se) {
            implausible.push(format!("{e}: {w}"));
        }
    }
    implausible
}

/// The ladder as a Markdown table: per step, train and validation RMSE (in the signal's `unit`),
/// validation energy error and accuracy (%).
pub fn table(id: &Identification, unit: &str) -> String {
    let mut s = format!(
        "| step | train RMSE [{unit}] | validation RMSE [{unit}] | validation energy error [%] | accuracy [%] |\n|---|---|---|---|---|\n"
    );
    for r in &id.ladder {
        s.push_str(&format!(
            "| {} | {:.4} | {:.4} | {:.2} | {:.2} |\n",
            r.step,
            r.train_rmse,
            r.validation_rmse,
            r.validation_energy_error_pct,
            r.validation_accuracy_pct
        ));
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 2 s torque log of the UR10e at 250 Hz in which every joint but joint 6 moves.
    fn log_with_joint_6_still() -> crate::identify::log::Log {
        let mut s = String::from("t,q1,q2,q3,q4,q5,q6,tau1,tau2,tau3,tau4,tau5,tau6\n");
        for k in 0..500 {
            let t = k as f64 * 0.004;
            let q: Vec<String> = (0..6)
                .map(|j| {
                    let v = if j == 5 {
                        0.3
                    } else {
                        0.4 * ((1.0 + j as f64) * t).sin()
                    };
                    format!("{v:.9}")
                })
                .collect();
            s += &format!("{t:.3},{},1,1,1,1,1,1\n", q.join(","));
        }
        crate::identify::log::parse_log(&s, "still.csv", 6, None).unwrap()
    }

    #[test]
    fn the_parameters_of_effects_that_need_joint_motion_are_held_on_a_still_joint_and_no_others() {
        let robot = crate::robot::load(
            &std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("robots/ur10e"),
        )
        .unwrap();
        let model = Model::new(&robot).unwrap();
        let log = log_with_joint_6_still();
        let prep = Prepared::new(&model, &log).unwrap();
        let rows: Vec<usize> = (0..log.len()).collect();
        let effects = ["viscous", "coulomb", "armature", "balancer", "payload"];
        let held: Vec<String> = still_joint_params(&model, &prep, &rows, &effects)
            .into_iter()
            .map(|h| h.name)
            .collect();
        let want: Vec<String> = ["viscous", "coulomb", "armature"]
            .iter()
            .flat_map(|e| {
                let model = &model;
                model
                    .params(e)
                    .unwrap()
                    .into_iter()
                    .filter(|p| p.name.ends_with("[6]"))
                    .map(move |p| format!("{e}.{}", p.name))
            })
            .collect();
        assert!(!want.is_empty());
        assert_eq!(held, want);
        for e in ["viscous", "coulomb", "stribeck", "armature"] {
            assert!(model.effect(e).unwrap().needs_joint_motion(), "{e}");
        }
        for e in ["balancer", "payload", "gear_efficiency", "standby"] {
            assert!(!model.effect(e).unwrap().needs_joint_motion(), "{e}");
        }
    }
}
