//! Identification with the error ladder: the base model, then each listed effect added in turn
//! (all added so far re-fitted jointly on the training data), each step validated on held-out
//! data (the last quarter of the log, or a second log); and the updated drive file.

use crate::error::{Error, Result};
use crate::identify::fit::{fit, FittedParam, IllConditioning};
use crate::identify::metrics::{evaluate_rows, rel_pct};
use crate::identify::model::{Model, Prepared};
use serde::Serialize;
use std::path::Path;

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
    /// Parameters the data cannot tell apart, if any.
    pub ill_conditioned: Option<IllConditioning>,
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
    for i in 0..effects.len() {
        let r = fit(train.0, model, &effects[..=i], train.1)?;
        ladder.push(step(model, format!("+{}", effects[i]), &effects[..=i]));
        last = Some(r);
    }
    let (params, ill) = match last {
        Some(r) => (r.params, r.ill_conditioned),
        None => (vec![], None),
    };
    Ok(Identification {
        validation,
        ladder,
        params,
        ill_conditioned: ill,
    })
}

/// Write the drive file `src` updated with the model's parameters to `dst` (beside it). Drive
/// keys get the identified values (`viscous_nm_s_per_rad`, `coulomb_nm`, `rotor_inertia_kg_m2`
/// = armature/G², `winding_resistance_ohm`, `gear_efficiency`, `standby_power_w`, payload
/// `mass_kg` += Δm); the switches and the parameters without drive keys go to `[effects]`.
/// Refuses to write over `src`, and over an existing `dst` unless `force`.
pub fn write_drive_file(
    src: &Path,
    dst: &Path,
    model: &Model,
    urdf: &Path,
    force: bool,
) -> Result<()> {
    if dst == src
        || dst
            .canonicalize()
            .ok()
            .is_some_and(|d| src.canonicalize().is_ok_and(|s| s == d))
    {
        return Err(Error::Invalid(format!(
            "{}: refusing to overwrite the input drive file",
            dst.display()
        )));
    }
    if dst.exists() && !force {
        return Err(Error::Invalid(format!(
            "{}: exists; pass --force to overwrite it",
            dst.display()
        )));
    }
    let text = crate::error::read_text(src)?;
    let mut t: toml::Table = toml::from_str(&text).map_err(|e| Error::Field {
        file: src.display().to_string(),
        field: "(file)".into(),
        msg: e.message().to_string(),
    })?;
    let f = |x: f64| toml::Value::Float(x);
    if let Some(joints) = t.get_mut("joints").and_then(|j| j.as_array_mut()) {
        for (j, jt) in joints.iter_mut().enumerate() {
            let Some(jt) = jt.as_table_mut() else {
                continue;
            };
            if j >= model.n {
                break;
            }
            jt.insert("viscous_nm_s_per_rad".into(), f(model.viscous.fv[j]));
            jt.insert("coulomb_nm".into(), f(model.coulomb.fc[j]));
            let g = model.gear[j];
            jt.insert(
                "rotor_inertia_kg_m2".into(),
                f(model.armature.ia[j] / (g * g)),
            );
            jt.insert("winding_resistance_ohm".into(), f(model.copper.r[j]));
            jt.insert("gear_efficiency".into(), f(model.gear_efficiency.eta[j]));
        }
    }
    let cab = t
        .entry("cabinet")
        .or_insert_with(|| toml::Value::Table(Default::default()));
    if let Some(c) = cab.as_table_mut() {
        c.insert("standby_power_w".into(), f(model.standby.power));
    }
    let mut enabled: Vec<&str> = model.enabled_names();
    if model.payload.dm != 0.0 {
        let p = t
            .entry("payload")
            .or_insert_with(|| toml::Value::Table(Default::default()));
        if let Some(p) = p.as_table_mut() {
            let m0 = p
                .get("mass_kg")
                .and_then(|v| v.as_float().or_else(|| v.as_integer().map(|i| i as f64)))
                .unwrap_or(0.0);
            p.insert("mass_kg".into(), f(m0 + model.payload.dm));
        }
        enabled.retain(|e| *e != "payload");
    }
    if let Some(r) = t.get_mut("robot").and_then(|r| r.as_table_mut()) {
        if !r.contains_key("urdf") {
            let dir = dst.parent().unwrap_or(Path::new("."));
            let rel = match (urdf.parent(), urdf.file_name()) {
                (Some(p), Some(n)) if p.canonicalize().ok() == dir.canonicalize().ok() => {
                    n.to_string_lossy().into_owned()
                }
                _ => urdf
                    .canonicalize()
                    .unwrap_or(urdf.to_path_buf())
                    .display()
                    .to_string(),
            };
            r.insert("urdf".into(), toml::Value::String(rel));
        }
    }
    let mut e = toml::Table::new();
    e.insert(
        "enabled".into(),
        toml::Value::Array(
            enabled
                .iter()
                .map(|s| toml::Value::String(s.to_string()))
                .collect(),
        ),
    );
    e.insert(
        "stribeck_nm".into(),
        toml::Value::Array(model.stribeck.fs.iter().map(|x| f(*x)).collect()),
    );
    e.insert("stribeck_velocity_rad_s".into(), f(model.stribeck.vs));
    e.insert("balancer_preload_n".into(), f(model.balancer.preload));
    e.insert(
        "balancer_stiffness_n_per_m".into(),
        f(model.balancer.stiffness),
    );
    e.insert(
        "regeneration_recovered_fraction".into(),
        f(model.regeneration.recovered),
    );
    t.insert("effects".into(), toml::Value::Table(e));
    let body =
        toml::to_string(&t).map_err(|e| Error::Invalid(format!("writing drive file: {e}")))?;
    let out = format!(
        "# drive file identified by `printwatt identify` from {}; all values SI, unit in the key\n{body}",
        src.display()
    );
    crate::output::write_atomic(dst, out.as_bytes())
}
