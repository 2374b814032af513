//! The model the measurements are compared with: the rigid body (nominal payload) plus the
//! catalogue's effects, each switched on or off and carrying its own parameters, and the
//! motor model that turns joint torque into the logged signal (seed 001, eqs. 2–4).
//!
//! Prediction per sample: `τ = τ_rb + Σ_enabled τ_effect` (joint side, N·m); then
//! `τ_m = τ/(G η)` when driving (`τ q̇ ≥ 0`) else `τ η/G`, `i = τ_m/K_t`, `P = τ_m G q̇ + R i²`
//! per axis, and `P_supply = P_drives − ρ (P_drives − Σ P) + P_0` with `P_drives` from the
//! drive's regeneration policy. Effects switched off contribute nothing: no friction, `η = 1`,
//! `R = 0`, `ρ = 0`, `P_0 = 0`.

use crate::dynamics::{rnea, DynModel, DynOptions, MAX_DOF};
use crate::effects::{catalogue, Effect, EffectSet, MotorTerm, ParamSpec, Stage};
pub use crate::effects::{catalogue_index, DEFAULT_EFFECTS};
use crate::error::{Error, Result};
use crate::identify::log::{Log, SignalKind};
use crate::identify::motion::Rates;
use crate::robot::{Regeneration, RobotModel};
use std::path::{Path, PathBuf};

/// The motor- and supply-stage values of the enabled electrical effects, cached for the
/// per-sample motor model (refreshed whenever the effects change).
#[derive(Clone, Debug, Default)]
struct MotorCache {
    /// `R` per axis, Ω (0 when `copper` is off).
    r: Vec<f64>,
    /// `η` per axis (1 when `gear_efficiency` is off).
    eta: Vec<f64>,
    /// `ρ` (0 when `regeneration` is off).
    rho: f64,
    /// `P_0`, W (0 when `standby` is off).
    p0: f64,
}

impl MotorCache {
    /// The cache of `n` axes from the terms the enabled effects supply (a term nobody
    /// supplies leaves no loss: `R = 0`, `η = 1`, `ρ = 0`, `P_0 = 0`).
    fn of(t: crate::effects::MotorTerms, n: usize) -> MotorCache {
        MotorCache {
            r: t.winding_resistance.unwrap_or_else(|| vec![0.0; n]),
            eta: t.gear_efficiency.unwrap_or_else(|| vec![1.0; n]),
            rho: t.regeneration.unwrap_or(0.0),
            p0: t.standby_w.unwrap_or(0.0),
        }
    }
}

/// The comparison model: every registered effect ([`crate::effects::REGISTRY`]) with its
/// parameters and an on/off switch, the rigid body and the motor model.
#[derive(Debug)]
pub struct Model {
    /// Number of joints.
    pub n: usize,
    /// Robot name.
    pub robot_name: String,
    /// Gear ratios (motor turns per joint turn).
    pub gear: Vec<f64>,
    /// Torque constants K_t, N·m/A (motor side).
    pub kt: Vec<f64>,
    /// Drive regeneration policy.
    pub policy: Regeneration,
    /// Whether drive data exist (needed for current logs).
    pub has_drive: bool,
    /// The effects with their switches (the same set the energy model builds).
    pub effects: EffectSet,
    /// Whether `coulomb` is fitted per direction (`f_c+[j]`, `f_c−[j]` free; the candidate
    /// [`DIRECTIONAL_COULOMB`]); by default both directions share one level per joint.
    pub coulomb_directional: bool,
    /// Whether the payload's inertia about the flange (`dI_*`) is fitted (the candidate
    /// [`PAYLOAD_WITH_INERTIA`]); by default it is held at its prior and the mass and centre of
    /// mass are fitted.
    pub payload_inertia: bool,
    /// The robot's rated payload, kg (drive file `[robot] rated_payload_kg`), if stated.
    pub rated_payload_kg: Option<f64>,
    /// Total mass of the moving links, kg.
    pub moving_mass_kg: f64,
    /// Name of the flange link: the frame of the payload's centre of mass and inertia.
    pub flange_link: String,
    motor: MotorCache,
    dynamics: DynModel,
}

/// The per-direction Coulomb candidate: `coulomb` with `f_c+[j]` and `f_c−[j]` fitted
/// separately (claimed by `diagnose` only when it beats the symmetric `coulomb` significantly).
pub(crate) const DIRECTIONAL_COULOMB: &str = "coulomb_directional";

/// The payload with its own inertia: `payload` with `dI_*` fitted too.
pub(crate) const PAYLOAD_WITH_INERTIA: &str = "payload_inertia";

/// Whether an effect list asks for the payload's inertia.
pub(crate) fn asks_payload_inertia(s: &str) -> bool {
    s.split(',')
        .map(|w| w.trim().split('[').next().unwrap_or("").trim())
        .any(|w| w == PAYLOAD_WITH_INERTIA)
}

/// Whether an effect list (`coulomb_directional,payload`) asks for per-direction Coulomb.
pub(crate) fn asks_directional_coulomb(s: &str) -> bool {
    s.split(',')
        .map(|w| w.trim().split('[').next().unwrap_or("").trim())
        .any(|w| w == DIRECTIONAL_COULOMB)
}

/// An effect to fit and, for `effect[j]`, the 1-based joints whose parameters are fitted
/// (`None`: every joint). Several entries of one effect (`viscous[2],viscous[3]`) merge.
pub(crate) type EffectSubset = (&'static str, Option<Vec<usize>>);

/// Parse `coulomb,viscous[2],viscous[3]` (effect names of the catalogue, a joint in brackets as
/// `simulate`'s hidden effects take it, [`crate::identify::simulate::split_joint`]) for a robot
/// of `n` joints. Order kept, duplicates merged; `viscous` and `viscous[2]` together mean every
/// joint. Errors: an unknown effect, a bad joint or one beyond `n`.
pub(crate) fn parse_effect_subsets(s: &str, n: usize) -> Result<Vec<EffectSubset>> {
    let cat = catalogue();
    let mut out: Vec<EffectSubset> = Vec::new();
    for w in s.split(',').map(str::trim).filter(|w| !w.is_empty()) {
        let (name, joint) = crate::identify::simulate::split_joint(w)?;
        let name = match name {
            DIRECTIONAL_COULOMB => "coulomb",
            PAYLOAD_WITH_INERTIA => "payload",
            n => n,
        };
        let e = cat[catalogue_index(name)?];
        if let Some(k) = joint.filter(|&k| k > n) {
            return Err(Error::Invalid(format!(
                "`{w}`: joint {k}, but the robot has {n} joints"
            )));
        }
        match out.iter_mut().find(|(x, _)| *x == e) {
            Some((_, js)) => match (js.as_mut(), joint) {
                (Some(v), Some(k)) => {
                    if !v.contains(&k) {
                        v.push(k)
                    }
                }
                (_, None) => *js = None,
                (None, Some(_)) => {}
            },
            None => out.push((e, joint.map(|k| vec![k]))),
        }
    }
    Ok(out)
}

/// The drive file a `--robot` argument refers to (directory → `drive.toml`, a `.toml` file →
/// itself), if any.
pub(crate) fn drive_file_of(robot_arg: &Path) -> Option<PathBuf> {
    if robot_arg.is_dir() {
        let p = robot_arg.join("drive.toml");
        p.is_file().then_some(p)
    } else if robot_arg.extension().is_some_and(|e| e == "toml") {
        Some(robot_arg.to_path_buf())
    } else {
        None
    }
}

/// Whether an effect acting at `stage` can be seen in a log of signal `kind`: a joint-side
/// torque in every log; the winding resistance (copper loss `R i²`) in power logs only, since
/// a torque log never sees the motor and a current log gives `i` but not `R`; the gear
/// efficiency in current and power logs (the motor torque `τ_m = k_t i` differs from the
/// joint torque by the gear loss); the supply terms (regeneration, standby) in `p_total` logs
/// only.
pub(crate) fn observable_at(stage: Stage, kind: SignalKind) -> bool {
    match stage {
        Stage::Torque => true,
        Stage::Motor(MotorTerm::WindingResistance) => {
            matches!(kind, SignalKind::AxisPower | SignalKind::TotalPower)
        }
        Stage::Motor(MotorTerm::GearEfficiency) => kind != SignalKind::Torque,
        Stage::Supply(_) => kind == SignalKind::TotalPower,
    }
}

impl Model {
    /// The model of a robot: every registered effect built from the robot's drive data and
    /// drive-file tables ([`EffectSet::of_robot`], the same the energy model reads), the rigid
    /// body with the nominal payload and without armature (that is the `armature` effect).
    /// Errors: the robot lacks inertials; a bad `[effects]` key (naming file and key).
    pub fn new(robot: &RobotModel) -> Result<Self> {
        let n = robot.dof();
        let dynamics = DynModel::new(
            robot,
            DynOptions {
                payload: true,
                armature: false,
            },
        )?;
        let d = robot.drive.as_ref();
        let per = |f: &dyn Fn(&crate::robot::JointDrive) -> f64, dflt: f64| -> Vec<f64> {
            match d {
                Some(d) => d.joints.iter().map(f).collect(),
                None => vec![dflt; n],
            }
        };
        if let Some(d) = d {
            robot.check_len("drive joints", d.joints.len())?;
        }
        let mut m = Model {
            n,
            robot_name: robot.name().to_string(),
            gear: per(&|j| j.gear_ratio, 1.0),
            kt: per(&|j| j.torque_constant, 1.0),
            policy: d.map_or(Regeneration::None, |d| d.regeneration),
            has_drive: d.is_some(),
            effects: EffectSet::of_robot(robot)?,
            coulomb_directional: false,
            payload_inertia: false,
            rated_payload_kg: robot.info.rated_payload_kg,
            moving_mass_kg: robot.moving_mass(),
            flange_link: robot.flange_link.clone(),
            motor: MotorCache::default(),
            dynamics,
        };
        m.refresh()?;
        Ok(m)
    }

    /// The motor cache from the enabled effects, each by the motor or supply term it names
    /// ([`EffectSet::motor_terms`], as the energy model reads them). Error: two enabled
    /// effects supply one term; the cache is then left as it was.
    fn refresh(&mut self) -> Result<()> {
        self.motor = MotorCache::of(self.effects.motor_terms()?, self.n);
        Ok(())
    }

    /// Switch an effect on or off. Errors: unknown name; switching on a second effect for a
    /// motor or supply term another enabled effect supplies (the switch is then left as it
    /// was).
    pub fn set_enabled(&mut self, name: &str, on: bool) -> Result<()> {
        self.effects.get(name)?;
        let was = self.effects.is_enabled(name);
        self.effects.set_enabled(name, on);
        if let Err(e) = self.refresh() {
            self.effects.set_enabled(name, was);
            return Err(e);
        }
        Ok(())
    }

    /// Switch every effect off (the rigid body only).
    pub fn disable_all(&mut self) {
        self.effects.disable_all();
        self.motor = MotorCache::of(Default::default(), self.n);
    }

    /// Whether an effect is switched on (false for unknown names).
    pub fn is_enabled(&self, name: &str) -> bool {
        self.effects.is_enabled(name)
    }

    /// Names of the effects switched on, in catalogue order.
    pub fn enabled_names(&self) -> Vec<&'static str> {
        self.effects.enabled_names()
    }

    /// Position of the effect called `name` in the model's set.
    pub fn position(&self, name: &str) -> Option<usize> {
        self.effects.iter().position(|(e, _)| e.name() == name)
    }

    /// The effect called `name`.
    pub fn effect(&self, name: &str) -> Result<&dyn Effect> {
        self.effects.get(name)
    }

    /// Parameter specs of an effect.
    pub fn params(&self, name: &str) -> Result<Vec<ParamSpec>> {
        Ok(self.effect(name)?.params())
    }

    /// The parameters (`effect.param`, as [`crate::identify::fit::fit_holding`] names them) of
    /// `effect` that belong to a joint outside `joints` (1-based): what a per-joint subset
    /// holds at its prior. Parameters of no joint (a transition width, a mass) are fitted.
    pub(crate) fn params_outside(&self, effect: &str, joints: &[usize]) -> Result<Vec<String>> {
        Ok(self
            .params(effect)?
            .into_iter()
            .filter(|p| {
                p.name
                    .rsplit_once('[')
                    .and_then(|(_, j)| j.strip_suffix(']')?.parse::<usize>().ok())
                    .is_some_and(|k| !joints.contains(&k))
            })
            .map(|p| format!("{effect}.{}", p.name))
            .collect())
    }

    /// Keep `effect` on the joints in `joints` (1-based) only: its per-joint parameters of
    /// every other joint are set to zero (no torque from that effect there), its parameters of
    /// no joint (a transition width, a mass) are kept. Errors: an unknown effect, or zero
    /// outside a parameter's bounds (named).
    pub(crate) fn keep_joints(&mut self, effect: &str, joints: &[usize]) -> Result<()> {
        let specs = self.params(effect)?;
        let mut v = self.values(effect)?;
        for (p, x) in specs.iter().zip(v.iter_mut()) {
            let outside = p
                .name
                .rsplit_once('[')
                .and_then(|(_, j)| j.strip_suffix(']')?.parse::<usize>().ok())
                .is_some_and(|k| !joints.contains(&k));
            if outside {
                if !(p.lower..=p.upper).contains(&0.0) {
                    return Err(Error::Invalid(format!(
                        "{effect}.{}: cannot be switched off on its own joint (0 is outside [{}, {}] {})",
                        p.name, p.lower, p.upper, p.unit
                    )));
                }
                *x = 0.0;
            }
        }
        self.set_values(effect, &v)
    }

    /// Parameter values of an effect (SI).
    pub fn values(&self, name: &str) -> Result<Vec<f64>> {
        Ok(self.effect(name)?.values())
    }

    /// Set the parameter values of an effect (checked against the bounds).
    pub fn set_values(&mut self, name: &str, values: &[f64]) -> Result<()> {
        self.effects.get_mut(name)?.set_values(values)?;
        self.refresh()
    }

    /// Whether the effect called `name` can be seen in a log of this signal, by the stage it
    /// acts at ([`observable_at`]); an effect the model does not hold is not.
    pub fn observable(&self, name: &str, kind: SignalKind) -> bool {
        self.effects
            .get(name)
            .is_ok_and(|e| observable_at(e.stage(), kind))
    }

    /// Joint torque of the model at one state (N·m), into `tau` (length `n`).
    pub fn torque(&self, q: &[f64], qd: &[f64], qdd: &[f64], tau: &mut [f64]) -> Result<()> {
        let mut data = self.dynamics.data();
        rnea(&self.dynamics, &mut data, q, qd, qdd, tau)?;
        self.effects.add_torque(q, qd, qdd, tau);
        Ok(())
    }

    /// Signal of kind `kind` from joint torques `tau` (N·m) at velocities `qd` (rad/s), into
    /// `out` (`kind.channels(n)` values).
    pub fn signal_from_torque(&self, kind: SignalKind, tau: &[f64], qd: &[f64], out: &mut [f64]) {
        let n = self.n;
        if kind == SignalKind::Torque {
            out[..n].copy_from_slice(&tau[..n]);
            return;
        }
        let mut p = [0.0; MAX_DOF];
        for j in 0..n {
            let m = crate::energy::motor(
                tau[j],
                qd[j],
                self.gear[j],
                self.motor.eta[j],
                self.kt[j],
                self.motor.r[j],
            );
            p[j] = m.p_el;
            match kind {
                SignalKind::Current => out[j] = m.current,
                SignalKind::AxisPower => out[j] = p[j],
                _ => {}
            }
        }
        if kind == SignalKind::TotalPower {
            out[0] =
                crate::energy::supply_power(self.policy, &p[..n], self.motor.rho, self.motor.p0)
                    .supply;
        }
    }

    /// The rigid-body model (nominal payload, no armature: that is the `armature` effect).
    pub fn dynamics(&self) -> &DynModel {
        &self.dynamics
    }

    /// Why the effect called `name` is not physically plausible for this robot, or `None`.
    pub fn implausible(&self, name: &str) -> Option<String> {
        self.effect(name).ok().and_then(|e| e.implausible())
    }

    /// Why the *current values* of the effect called `name` (just fitted, with standard
    /// errors `std_errors` in parameter order) are not physically plausible for this robot, or
    /// `None` ([`Effect::implausible_fit`]).
    pub fn implausible_fit(&self, name: &str, std_errors: &[Option<f64>]) -> Option<String> {
        self.effect(name)
            .ok()
            .and_then(|e| e.implausible_fit(std_errors))
    }
}

/// Rows of a log up to which the regressors of the costly effects are computed once for
/// every row; a longer log keeps them for at most this many rows, those the fits ask for
/// ([`Prepared::regressor_row`]), and evaluates them where it needs them elsewhere, so that its
/// memory does not grow with the log's length.
pub(crate) const REGRESSOR_CACHE_ROWS: usize = 5 * crate::identify::fit::FIT_ROWS_MAX;

/// The regressor of one costly effect: of every row, or of the rows asked for so far.
#[derive(Debug)]
enum Regressors {
    /// `len × n × P`, row-major.
    Every(Vec<f64>),
    /// Row → its `n × P` values, at most [`REGRESSOR_CACHE_ROWS`] rows.
    Some(std::sync::Mutex<std::collections::HashMap<usize, Box<[f64]>>>),
}

/// The rigid-body torques of a log: of every row, or of the rows the fits asked for so far.
#[derive(Debug)]
enum RigidTorques {
    /// `len × n`, row-major, N·m.
    Every(Vec<f64>),
    /// The torques of at most [`REGRESSOR_CACHE_ROWS`] rows (those the fits use again and
    /// again); every other row's are computed where they are needed.
    Some(KeptRows),
}

/// Values of some rows of a log, `width` a row, kept as the fits ask for them: per row of the
/// log the slot holding its values plus one (0: none), and [`REGRESSOR_CACHE_ROWS`] slots.
/// Reading takes no lock (the fits read the same rows many times over, from several threads).
#[derive(Debug)]
struct KeptRows {
    width: usize,
    slot_of: Vec<std::sync::atomic::AtomicU32>,
    used: std::sync::atomic::AtomicUsize,
    /// The values' bits, slot by slot.
    values: Vec<std::sync::atomic::AtomicU64>,
}

impl KeptRows {
    fn new(len: usize, width: usize) -> Self {
        use std::sync::atomic::{AtomicU32, AtomicU64, AtomicUsize};
        KeptRows {
            width,
            slot_of: zeroed_atomics::<AtomicU32, u32>(len),
            used: AtomicUsize::new(0),
            values: zeroed_atomics::<AtomicU64, u64>(REGRESSOR_CACHE_ROWS * width),
        }
    }

    /// The values of row `k` into `out[..width]`, if kept.
    fn get(&self, k: usize, out: &mut [f64]) -> bool {
        use std::sync::atomic::Ordering;
        let s = self.slot_of[k].load(Ordering::Acquire);
        if s == 0 {
            return false;
        }
        let s = s - 1;
        let w = self.width;
        let vals = &self.values[s as usize * w..(s as usize + 1) * w];
        for (o, v) in out[..w].iter_mut().zip(vals) {
            *o = f64::from_bits(v.load(Ordering::Relaxed));
        }
        true
    }

    /// Keep `vals` (`width` values) as row `k`'s while there are free slots.
    fn put(&self, k: usize, vals: &[f64]) {
        use std::sync::atomic::Ordering;
        if self.slot_of[k].load(Ordering::Acquire) != 0 {
            return;
        }
        let s = self.used.fetch_add(1, Ordering::Relaxed);
        if s >= REGRESSOR_CACHE_ROWS {
            return;
        }
        let w = self.width;
        for (v, x) in self.values[s * w..(s + 1) * w].iter().zip(&vals[..w]) {
            v.store(x.to_bits(), Ordering::Relaxed);
        }
        self.slot_of[k].store(s as u32 + 1, Ordering::Release);
    }
}

/// `len` atomics holding zero, in memory the system zeroes on first touch: the slots never
/// used cost no resident memory.
fn zeroed_atomics<A, T: Copy + Default>(len: usize) -> Vec<A> {
    const { assert!(std::mem::size_of::<A>() == std::mem::size_of::<T>()) };
    const { assert!(std::mem::align_of::<A>() == std::mem::align_of::<T>()) };
    let mut v = std::mem::ManuallyDrop::new(vec![T::default(); len]);
    // SAFETY: `A` is `AtomicU32`/`AtomicU64` for `T` = `u32`/`u64`: the same size, alignment
    // (checked above) and bit validity, so the allocation and its zeroed values are valid as
    // `A`s and are freed with the same layout.
    unsafe { Vec::from_raw_parts(v.as_mut_ptr().cast::<A>(), v.len(), v.capacity()) }
}

/// A log prepared for repeated prediction: rigid-body torques and the regressors of the
/// linear torque effects computed once (of every row of a log of at most
/// [`REGRESSOR_CACHE_ROWS`] rows; of a longer log, of the rows the fits use, so that its
/// memory does not grow with the log's length).
#[derive(Debug)]
pub struct Prepared<'a> {
    /// The log.
    pub log: &'a Log,
    /// Rigid-body torque per sample (N·m).
    tau_rb: RigidTorques,
    /// Regressors of the costly linear torque effects ([`Effect::costly`]: those that need
    /// inverse-dynamics passes) by position in the model's effect set (`None` for the others,
    /// which are evaluated directly): `n × P` per row, of every row of a log of at most
    /// [`REGRESSOR_CACHE_ROWS`] rows.
    regs: Vec<Option<Regressors>>,
    /// The costly effects' parameter counts, by position (0 for the others).
    reg_params: Vec<usize>,
    /// The velocities and accelerations of the rows the fits use, when the log keeps its
    /// rates in a file ([`crate::identify::motion::LogMotion::rates_in_file`]).
    rates_kept: Option<KeptRows>,
}

impl<'a> Prepared<'a> {
    /// Prepare `log` for `model`. Errors: joint count mismatch; a current or power log for a
    /// robot without drive data.
    pub fn new(model: &Model, log: &'a Log) -> Result<Self> {
        Self::with_progress(model, log, &crate::identify::NoProgress)
    }

    /// [`Prepared::new`], telling `progress` how many rows are done (stage
    /// `"preparing the log"`; the rigid body and each costly effect's regressor are one pass
    /// each over the rows).
    pub fn with_progress(
        model: &Model,
        log: &'a Log,
        progress: &dyn crate::identify::Progress,
    ) -> Result<Self> {
        check_log(model, log)?;
        let len = log.len();
        let every = len <= REGRESSOR_CACHE_ROWS;
        let passes = if every {
            1 + model
                .effects
                .iter()
                .filter(|(e, _)| e.stage() == Stage::Torque && e.costly())
                .count()
        } else {
            0
        };
        let total = (passes * len) as u64;
        let step = (len / 100).max(1);
        let stage = "preparing the log";
        let tick = |k: usize| progress.update(stage, k as u64, total);
        let tau_rb = rigid_torques(model, log, every, step, &tick)?;
        let (regs, reg_params) = regressors(model, log, every, step, &tick);
        progress.update(stage, total, total);
        let rates_kept = log
            .traj
            .rates_in_file()
            .then(|| KeptRows::new(len, 2 * model.n));
        Ok(Prepared {
            log,
            tau_rb,
            regs,
            reg_params,
            rates_kept,
        })
    }

    /// Number of samples.
    pub fn len(&self) -> usize {
        self.log.len()
    }

    /// Whether there are no samples.
    pub fn is_empty(&self) -> bool {
        self.log.is_empty()
    }

    /// Velocities and accelerations of sample `k`; kept for the next call when `keep` (a row
    /// a fit uses again and again) and the log keeps its rates in a file.
    pub(crate) fn rates(&self, k: usize, keep: bool) -> Rates {
        let n = self.log.traj.n;
        let Some(kept) = &self.rates_kept else {
            return self.log.traj.rates(k);
        };
        let mut both = [0.0; 2 * MAX_DOF];
        if kept.get(k, &mut both) {
            return Rates::from_both(n, &both);
        }
        let r = self.log.traj.rates(k);
        if keep {
            kept.put(k, r.both());
        }
        r
    }

    /// [`Prepared::torque_row`] at a row a fit uses again and again: its rigid-body torque
    /// and rates are kept for the next call (while fewer than [`REGRESSOR_CACHE_ROWS`] rows
    /// are kept).
    pub(crate) fn torque_row_kept(&self, model: &Model, k: usize, skip: &[usize], tau: &mut [f64]) {
        let r = self.rates(k, true);
        self.rigid_row(model, k, &r, true, &mut None, tau);
        self.effects_row(model, k, &r, skip, tau);
    }

    /// The rigid-body torque at sample `k` (rates `r`) into `tau[..n]`: kept, or computed
    /// (and kept when `keep` and there is room); `data` is the inverse dynamics' workspace,
    /// made when first needed.
    fn rigid_row(
        &self,
        model: &Model,
        k: usize,
        r: &Rates,
        keep: bool,
        data: &mut Option<crate::dynamics::DynData>,
        tau: &mut [f64],
    ) {
        let n = model.n;
        match &self.tau_rb {
            RigidTorques::Every(v) => tau[..n].copy_from_slice(&v[k * n..(k + 1) * n]),
            RigidTorques::Some(m) => {
                if m.get(k, tau) {
                    return;
                }
                let data = data.get_or_insert_with(|| model.dynamics.data());
                let (q, qd, qdd) = (self.log.traj.q(k), r.qd(), r.qdd());
                // The joint counts were checked when the log was prepared.
                let _ = rnea(&model.dynamics, data, q, qd, qdd, &mut tau[..n]);
                if keep {
                    m.put(k, tau);
                }
            }
        }
    }

    /// Add the torque effects of `model` at sample `k` (rates `r`) to `tau[..n]`, skipping
    /// those at the positions in `skip`.
    fn effects_row(&self, model: &Model, k: usize, r: &Rates, skip: &[usize], tau: &mut [f64]) {
        let n = model.n;
        let (q, qd, qdd) = (self.log.traj.q(k), r.qd(), r.qdd());
        let mut buf = [0.0; MAX_REGRESSOR];
        for (i, (e, on)) in model.effects.iter().enumerate() {
            if !on || e.stage() != Stage::Torque || skip.contains(&i) {
                continue;
            }
            let p = self.reg_params.get(i).copied().unwrap_or(0);
            let yk: &[f64] = match self.regs.get(i) {
                Some(Some(Regressors::Every(y))) => &y[k * n * p..(k + 1) * n * p],
                Some(Some(Regressors::Some(_))) if n * p <= MAX_REGRESSOR => {
                    let y = &mut buf[..n * p];
                    if !self.cached_regressor(i, k, n, p, y) {
                        e.regressor(q, qd, qdd, y);
                    }
                    y
                }
                _ => {
                    e.add_torque(q, qd, qdd, &mut tau[..n]);
                    continue;
                }
            };
            let vals = e.values();
            for (j, t) in tau[..n].iter_mut().enumerate() {
                let row = &yk[j * p..(j + 1) * p];
                *t += row.iter().zip(&vals).map(|(a, b)| a * b).sum::<f64>();
            }
        }
    }

    /// The cached regressor of the effect at position `i` of the model's set at sample `k`
    /// (`n × P`, row-major) into `out`, if it is cached; `false` (leaving `out` untouched)
    /// otherwise.
    pub(crate) fn cached_regressor(
        &self,
        i: usize,
        k: usize,
        n: usize,
        p: usize,
        out: &mut [f64],
    ) -> bool {
        match self.regs.get(i) {
            Some(Some(Regressors::Every(y))) => {
                out.copy_from_slice(&y[k * n * p..(k + 1) * n * p]);
                true
            }
            Some(Some(Regressors::Some(m))) => {
                let m = m.lock().unwrap_or_else(|e| e.into_inner());
                match m.get(&k) {
                    Some(y) => {
                        out.copy_from_slice(y);
                        true
                    }
                    None => false,
                }
            }
            _ => false,
        }
    }

    /// The regressor of the effect at position `i` of the model's set at sample `k` into
    /// `out` (`n × P`, row-major): the cached one, or computed and kept for the next call while
    /// fewer than [`REGRESSOR_CACHE_ROWS`] rows are kept (the rows a fit asks for again and
    /// again). `false` when the effect has no regressor.
    pub(crate) fn regressor_row(&self, model: &Model, i: usize, k: usize, out: &mut [f64]) -> bool {
        let n = model.n;
        let p = self.reg_params.get(i).copied().unwrap_or(0);
        if p == 0 || out.len() != n * p {
            return false;
        }
        if self.cached_regressor(i, k, n, p, out) {
            return true;
        }
        let Some((e, _)) = model.effects.iter().nth(i) else {
            return false;
        };
        let r = self.rates(k, false);
        if !e.regressor(self.log.traj.q(k), r.qd(), r.qdd(), out) {
            return false;
        }
        if let Some(Some(Regressors::Some(m))) = self.regs.get(i) {
            let mut m = m.lock().unwrap_or_else(|e| e.into_inner());
            if m.len() < REGRESSOR_CACHE_ROWS {
                m.insert(k, out.to_vec().into_boxed_slice());
            }
        }
        true
    }

    /// Model prediction of the logged signal at the samples `rows`, row-major
    /// `rows.len() × channels`, into `out` (resized).
    pub(crate) fn predict(&self, model: &Model, rows: &[usize], out: &mut Vec<f64>) {
        let n = model.n;
        let ch = self.log.channels;
        out.clear();
        out.resize(rows.len() * ch, 0.0);
        let mut tau = [0.0; MAX_DOF];
        let mut data = None;
        for (i, &k) in rows.iter().enumerate() {
            let r = self.rates(k, false);
            self.rigid_row(model, k, &r, false, &mut data, &mut tau);
            self.effects_row(model, k, &r, &[], &mut tau);
            model.signal_from_torque(
                self.log.kind,
                &tau[..n],
                r.qd(),
                &mut out[i * ch..(i + 1) * ch],
            );
        }
    }
}

/// The largest regressor of one row evaluated without a heap allocation (`n × P` values).
const MAX_REGRESSOR: usize = MAX_DOF * 16;

/// A saved copy of a model's switches and parameter values.
#[derive(Clone, Debug)]
pub struct ModelState {
    effects: EffectSet,
}

impl Model {
    /// Save switches and values.
    pub fn state(&self) -> ModelState {
        ModelState {
            effects: self.effects.clone(),
        }
    }
    /// Restore a saved state.
    pub(crate) fn restore(&mut self, s: &ModelState) {
        self.effects = s.effects.clone();
        // A saved state is a model's, whose switches every change keeps valid (set_enabled
        // refuses a second effect for one term), so its terms read without error.
        let _ = self.refresh();
    }
}

/// Errors for a log the model cannot prepare: another joint count, or a current log for a
/// robot without drive data.
fn check_log(model: &Model, log: &Log) -> Result<()> {
    let n = model.n;
    if log.traj.n != n {
        return Err(Error::SizeMismatch {
            what: format!(
                "{}: joints in the log for robot `{}`",
                log.file, model.robot_name
            ),
            got: log.traj.n,
            expected: n,
        });
    }
    if log.kind == SignalKind::Current && !model.has_drive {
        return Err(Error::Invalid(format!(
            "{}: a current log (`i1..i{n}`) needs each joint's gear ratio and torque constant K_t \
(drive file [[joints]] `gear_ratio`, `torque_constant_nm_per_a`), and robot `{}` has none; \
log joint torque (`tau`), axis power (`p`) or supply power (`p_total`) instead, or give a drive file",
            log.file, model.robot_name
        )));
    }
    Ok(())
}

/// The rigid-body torque of every row when `every` (one pass, `tick(k)` every `step` rows),
/// else a store of the rows kept.
fn rigid_torques(
    model: &Model,
    log: &Log,
    every: bool,
    step: usize,
    tick: &dyn Fn(usize),
) -> Result<RigidTorques> {
    let n = model.n;
    let len = log.len();
    Ok(if every {
        let mut data = model.dynamics.data();
        let mut tau_rb = vec![0.0; len * n];
        for k in 0..len {
            if k % step == 0 {
                tick(k);
            }
            let r = log.traj.rates(k);
            rnea(
                &model.dynamics,
                &mut data,
                log.traj.q(k),
                r.qd(),
                r.qdd(),
                &mut tau_rb[k * n..(k + 1) * n],
            )?;
        }
        RigidTorques::Every(tau_rb)
    } else {
        RigidTorques::Some(KeptRows::new(len, n))
    })
}

/// Each costly torque effect's regressor (`None` for the others) and its parameter count:
/// every row's when `every` (one pass each, `tick` counting on from the rigid body's pass),
/// else a store of the rows kept.
fn regressors(
    model: &Model,
    log: &Log,
    every: bool,
    step: usize,
    tick: &dyn Fn(usize),
) -> (Vec<Option<Regressors>>, Vec<usize>) {
    let n = model.n;
    let len = log.len();
    let mut regs: Vec<Option<Regressors>> = Vec::new();
    let mut reg_params = Vec::new();
    let mut pass = 1;
    for (e, _) in model.effects.iter() {
        regs.push(None);
        reg_params.push(0);
        if e.stage() != Stage::Torque || !e.costly() {
            continue;
        }
        let i = regs.len() - 1;
        let p = e.params().len();
        let mut y = vec![0.0; n * p];
        let r0 = (len > 0).then(|| log.traj.rates(0));
        if !r0.is_some_and(|r| e.regressor(log.traj.q(0), r.qd(), r.qdd(), &mut y)) {
            continue;
        }
        reg_params[i] = p;
        if !every {
            regs[i] = Some(Regressors::Some(Default::default()));
            continue;
        }
        let mut all = vec![0.0; len * n * p];
        for k in 0..len {
            if k % step == 0 {
                tick(pass * len + k);
            }
            let y = &mut all[k * n * p..(k + 1) * n * p];
            let r = log.traj.rates(k);
            e.regressor(log.traj.q(k), r.qd(), r.qdd(), y);
        }
        regs[i] = Some(Regressors::Every(all));
        pass += 1;
    }
    (regs, reg_params)
}
