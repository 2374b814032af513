//! How much to trust the recommended placement: draw plausible robots and re-evaluate the
//! candidate placements under each.
//!
//! Every estimated number of a shipped robot carries a range in its drive file's
//! `[uncertainty]` table (uniform, ± relative to the nominal value unless the key says
//! otherwise; [`Ranges`]). Each effect draws its own numbers ([`crate::effects::Effect::draw`],
//! in the order of [`crate::effects::Uncertainty`]). A draw perturbs every link's mass, centre of mass and inertia, the
//! payload's mass, every joint's torque constant, winding resistance, viscous and Coulomb
//! friction and gear efficiency, the cabinet's standby power, and the balancer (absent with
//! the stated probability, else its preload and stiffness scaled), each independently. A
//! calibrated robot (a drive file with a `[calibration]` table written by `identify`) draws
//! every identified parameter from a normal distribution with its identified standard error,
//! correlated as the fit of the round that identified it found (the `correlation` of its
//! `[[calibration.rounds]]`), instead of its range (an identified balancer is always present; an identified payload
//! draws its mass and first moment, so its centre of mass too; an identified armature, which
//! has no range, is drawn; an identified winding resistance was fitted with the torque
//! constant held, so the torque constant is not drawn on top of it); the numbers `identify`
//! did not fit keep their ranges. [`Study::calibrated`] lists the parameters so drawn.
//!
//! Timing does not depend on these numbers (kinematics and joint limits are not varied), so
//! each candidate is timed once and only its energy is recomputed per draw
//! ([`Evaluator::energy_of`]). Draws run in parallel; draw `d` uses its own ChaCha8 stream
//! (`seed`, stream `d`), and every reduction runs in draw order, so the study is identical for
//! any thread count.

use crate::effects::{DrawPhase, Drawing, Effect, EffectSet, Uncertainty};
use crate::energy::EnergyModel;
use crate::error::{Error, Result};
use crate::evaluate::evaluator::{Evaluated, Evaluator};
use crate::evaluate::PathJob;
use crate::robot::RobotModel;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

/// The `[uncertainty]` table of a drive file: half-widths of uniform ranges (dimensionless
/// fractions of the nominal value, except where the key names a unit).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Ranges {
    /// Link masses, ± fraction.
    pub link_mass_rel: f64,
    /// Link centres of mass, ± m along each axis of the link frame.
    pub link_com_m: f64,
    /// Link inertia tensors, ± fraction (scaled as a whole).
    pub link_inertia_rel: f64,
    /// Payload mass (inertia scaled with it), ± fraction.
    pub payload_mass_rel: f64,
    /// Motor torque constants, ± fraction.
    pub torque_constant_rel: f64,
    /// Winding resistances, ± fraction.
    pub winding_resistance_rel: f64,
    /// Viscous friction coefficients, ± fraction.
    pub viscous_rel: f64,
    /// Coulomb friction torques, ± fraction.
    pub coulomb_rel: f64,
    /// Gear efficiencies, ± absolute (kept within (0.3, 1]).
    pub gear_efficiency_abs: f64,
    /// Cabinet standby power, ± fraction.
    pub standby_power_rel: f64,
    /// Probability that the balancer is absent (dimensionless, 0–1; robots with a balancer).
    #[serde(default)]
    pub balancer_absent_probability: f64,
    /// Balancer preload and stiffness, ± fraction (one factor for both).
    #[serde(default)]
    pub balancer_force_rel: f64,
}

impl Default for Ranges {
    /// Used only for a robot whose drive file has no `[uncertainty]` table (said so in the
    /// study): ±20 % masses, ±0.05 m centres of mass, ±50 % inertias, ±25 % payload, ±20 %
    /// motor constants, ±50 % friction, ±0.05 gear efficiency, ±30 % standby, balancer
    /// absent with probability 0.2 and ±30 % force.
    fn default() -> Self {
        Ranges {
            link_mass_rel: 0.2,
            link_com_m: 0.05,
            link_inertia_rel: 0.5,
            payload_mass_rel: 0.25,
            torque_constant_rel: 0.2,
            winding_resistance_rel: 0.2,
            viscous_rel: 0.5,
            coulomb_rel: 0.5,
            gear_efficiency_abs: 0.05,
            standby_power_rel: 0.3,
            balancer_absent_probability: 0.2,
            balancer_force_rel: 0.3,
        }
    }
}

impl Ranges {
    /// The `[uncertainty]` table of the robot's drive file (`Ok(None)` when it has none or the
    /// robot has no drive file). Errors name the file.
    pub fn of_robot(model: &RobotModel) -> Result<Option<(Ranges, String)>> {
        // The drive file: named by its [effects]/[calibration] tables, else beside the URDF
        // of a robot directory, else the .toml the robot was loaded from.
        let file = match model.effects.file.clone() {
            Some(f) => f,
            None => {
                let src = &model.source;
                let cand = if src.is_dir() {
                    src.join("drive.toml")
                } else if src.extension().is_some_and(|e| e == "toml") {
                    src.clone()
                } else {
                    src.with_file_name("drive.toml")
                };
                if !cand.is_file() {
                    return Ok(None);
                }
                cand.display().to_string()
            }
        };
        let file = &file;
        let text =
            std::fs::read_to_string(file).map_err(|e| Error::Invalid(format!("{file}: {e}")))?;
        let v: toml::Value =
            toml::from_str(&text).map_err(|e| Error::Invalid(format!("{file}: {e}")))?;
        match v.get("uncertainty") {
            None => Ok(None),
            Some(t) => t
                .clone()
                .try_into::<Ranges>()
                .map(|r| Some((r, file.clone())))
                .map_err(|e| Error::Invalid(format!("{file}: [uncertainty]: {e}"))),
        }
    }
}

/// Where the draws' spreads came from.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub enum Source {
    /// The drive file's `[uncertainty]` ranges.
    DriveFile(String),
    /// Built-in default ranges (the drive file has no `[uncertainty]` table).
    Default,
    /// Ranges given by the caller.
    Given,
}

/// The outcome of the study, for the recommended placement (index 0 of the candidates).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Study {
    /// Draws made.
    pub draws: usize,
    /// Seed of the draws.
    pub seed: u64,
    /// Where the ranges came from.
    pub source: Source,
    /// Identified parameters drawn from their standard errors (calibrated robots), by name.
    pub calibrated: Vec<String>,
    /// Candidate placements re-evaluated per draw (the recommended one first).
    pub candidates: usize,
    /// Share of draws in which the recommended placement is within 1 % of that draw's best
    /// candidate (dimensionless, 0–1).
    pub p_within_1pct: f64,
    /// Share of draws in which it is the best candidate.
    pub p_best: f64,
    /// Saving of the recommended placement against the baseline (the last candidate), % of the
    /// baseline's energy: mean, 5th and 95th percentile over the draws (`None` without a
    /// baseline).
    pub saving_pct: Option<[f64; 3]>,
    /// Spearman rank correlation of the candidates' energies between each draw and the nominal
    /// robot: mean and minimum over the draws.
    pub rank_correlation: [f64; 2],
    /// Parameters ranked by |Spearman ρ| between their drawn value and the recommended
    /// placement's regret ((E_rec − E_best)/E_best) or, where the regret never varies, its
    /// saving: (name, ρ), the first is what the answer depends on most (top 5).
    pub depends_on: Vec<(String, f64)>,
    /// Per draw: the recommended placement's energy and the best candidate's, J.
    pub per_draw_j: Vec<[f64; 2]>,
}

/// The identified parameters of a calibrated robot with a drawn shift each:
/// `(effect, name, value, se·z)`, where `z` is standard normal and, within the parameters one
/// round fitted together, correlated as that round's fit (`z = S·n` with `S` the symmetric
/// square root of the round's correlation matrix, so a singular one draws too). Parameters
/// without a finite positive standard error are not drawn.
fn calibrated_shifts(
    c: &crate::robot::drive::Calibration,
    rng: &mut ChaCha8Rng,
    normal: &dyn Fn(&mut ChaCha8Rng) -> f64,
) -> Vec<(String, String, f64, f64)> {
    let params: Vec<_> = c
        .params
        .iter()
        .filter_map(|p| {
            let se = p.std_error.filter(|se| se.is_finite() && *se > 0.0)?;
            Some((p, se))
        })
        .collect();
    let mut z: Vec<f64> = params.iter().map(|_| normal(rng)).collect();
    for round in &c.rounds {
        let n = round.correlated.len();
        if n < 2 || round.correlation.len() != n || round.correlation.iter().any(|r| r.len() != n) {
            continue;
        }
        // The rows of this round that are still its parameters' latest values.
        let rows: Vec<(usize, usize)> = (0..n)
            .filter_map(|r| {
                let k = params.iter().position(|(p, _)| {
                    p.round == round.round
                        && format!("{}.{}", p.effect, p.name) == round.correlated[r]
                })?;
                Some((r, k))
            })
            .collect();
        if rows.len() < 2 {
            continue;
        }
        let corr = nalgebra::DMatrix::from_fn(rows.len(), rows.len(), |a, b| {
            let v = round.correlation[rows[a].0][rows[b].0];
            if v.is_finite() {
                v
            } else {
                f64::from(u8::from(a == b))
            }
        });
        let eig = corr.symmetric_eigen();
        let mut root = nalgebra::DMatrix::<f64>::zeros(rows.len(), rows.len());
        for (i, &ev) in eig.eigenvalues.iter().enumerate() {
            let v = eig.eigenvectors.column(i);
            root += (v * v.transpose()) * ev.max(0.0).sqrt();
        }
        let n0 = nalgebra::DVector::from_iterator(rows.len(), rows.iter().map(|&(_, k)| z[k]));
        let zc = root * n0;
        for (a, &(_, k)) in rows.iter().enumerate() {
            z[k] = zc[a];
        }
    }
    params
        .iter()
        .zip(z)
        .map(|((p, se), z)| (p.effect.clone(), p.name.clone(), p.value, se * z))
        .collect()
}

/// A perturbed robot, the normalised values drawn (name, value in the parameter's own
/// scale: the multiplier, the shift in m, or 1/0 for the balancer's presence), and the
/// identified parameters that were drawn with their standard errors (calibrated robots).
/// `effects` are the nominal robot's effects ([`EffectSet::of_robot`]); each draws its own
/// numbers ([`crate::effects::Effect::draw`]) in the order of their
/// [`crate::effects::Uncertainty`].
fn draw_robot(
    nominal: &RobotModel,
    effects: &EffectSet,
    r: &Ranges,
    rng: &mut ChaCha8Rng,
) -> (RobotModel, Vec<(String, f64)>, Vec<String>) {
    let mut m = nominal.clone();
    let mut drawn = Vec::new();
    // Identified parameters (calibrated robot): normal with their standard errors and the
    // correlation of the round that fitted them (the fit's covariance); each one's shift
    // `dv = se·z` is drawn up front.
    let normal = |rng: &mut ChaCha8Rng| {
        // Box–Muller from two uniforms of the stream.
        let a: f64 = rng.gen_range(f64::EPSILON..1.0);
        let b: f64 = rng.gen_range(0.0..1.0);
        (-2.0 * a.ln()).sqrt() * (2.0 * std::f64::consts::PI * b).cos()
    };
    let cal: Vec<(String, String, f64, f64)> = nominal
        .effects
        .calibration
        .as_ref()
        .map(|c| calibrated_shifts(c, rng, &normal))
        .unwrap_or_default();
    let mut used = Vec::<String>::new();
    // The effects that draw, in the order of their draws.
    let mut drawing: Vec<(Uncertainty, &dyn Effect)> = effects
        .iter()
        .filter_map(|(e, _)| Some((e.uncertainty()?, e)))
        .collect();
    drawing.sort_by_key(|(u, _)| (u.phase, u.rank));
    let dof = nominal.drive.as_ref().map_or(0, |d| d.joints.len());
    {
        let mut d = Drawing::new(&mut m, r, rng, &mut drawn, &cal, &mut used);
        draw_by_phase(&mut d, &drawing, dof, nominal.drive.is_some());
    }
    // Every other identified parameter that a calibrated robot keeps in `[effects.values]`
    // (which wins over the drive keys drawn above: coulomb per direction, offset, stribeck,
    // rigid_body, …): normal with its standard error, within the parameter's bounds. Effects
    // whose own draw takes their identified values are left to it.
    let own: Vec<&str> = drawing
        .iter()
        .filter(|(u, _)| u.draws_identified)
        .map(|(_, e)| e.name())
        .collect();
    draw_identified_values(&mut m, effects, &cal, &own, &mut drawn, &mut used);
    (m, drawn, used)
}

/// Every drawing effect draws its numbers, phase by phase; in the joint phase, every effect of
/// the phase for joint 1, then 2, …; the cabinet phase only where the robot has a drive.
fn draw_by_phase(
    d: &mut Drawing<'_>,
    drawing: &[(Uncertainty, &dyn Effect)],
    dof: usize,
    has_drive: bool,
) {
    for phase in [
        DrawPhase::Robot,
        DrawPhase::Joint,
        DrawPhase::Cabinet,
        DrawPhase::Effects,
    ] {
        let of_phase = drawing.iter().filter(|(u, _)| u.phase == phase);
        match phase {
            DrawPhase::Joint => {
                for j in 0..dof {
                    for (_, e) in of_phase.clone() {
                        e.draw(d, Some(j));
                    }
                }
            }
            DrawPhase::Cabinet if !has_drive => {}
            _ => {
                for (_, e) in of_phase {
                    e.draw(d, None);
                }
            }
        }
    }
}

/// The identified parameters of `[effects.values]` that no effect's own draw takes (`own`):
/// each shifted by its drawn `dv` (`cal`) within the parameter's bounds, recorded in `drawn`
/// and `used`.
fn draw_identified_values(
    m: &mut RobotModel,
    effects: &EffectSet,
    cal: &[(String, String, f64, f64)],
    own: &[&str],
    drawn: &mut Vec<(String, f64)>,
    used: &mut Vec<String>,
) {
    let with_values = m.effects.table.values.is_some() && !cal.is_empty();
    if let (Some(vals), true) = (m.effects.table.values.as_mut(), with_values) {
        for (effect, name, value, dv) in cal.iter().filter(|c| !own.contains(&c.0.as_str())) {
            let (value, dv) = (*value, *dv);
            let (Some(v), Ok(e)) = (vals.get_mut(effect), effects.get(effect)) else {
                continue;
            };
            let ps = e.params();
            let Some(i) = ps.iter().position(|p| &p.name == name) else {
                continue;
            };
            if i >= v.len() {
                continue;
            }
            let x = (value + dv).clamp(ps[i].lower, ps[i].upper);
            v[i] = x;
            drawn.push((format!("{effect} {name}"), x - value));
            if !used.iter().any(|n| n == name) {
                used.push(name.clone());
            }
        }
    }
}

/// Average ranks (1-based, ties share their mean rank).
fn ranks(v: &[f64]) -> Vec<f64> {
    let mut idx: Vec<usize> = (0..v.len()).collect();
    idx.sort_by(|&a, &b| v[a].total_cmp(&v[b]).then(a.cmp(&b)));
    let mut r = vec![0.0; v.len()];
    let mut i = 0;
    while i < idx.len() {
        let mut j = i;
        while j + 1 < idx.len() && v[idx[j + 1]] == v[idx[i]] {
            j += 1;
        }
        let avg = (i + j) as f64 / 2.0 + 1.0;
        for &k in &idx[i..=j] {
            r[k] = avg;
        }
        i = j + 1;
    }
    r
}

/// Spearman's rank correlation of two equally long series (Pearson on average ranks);
/// `None` when either has no spread.
pub(crate) fn spearman(a: &[f64], b: &[f64]) -> Option<f64> {
    let n = a.len();
    if n < 2 || b.len() != n {
        return None;
    }
    let (ra, rb) = (ranks(a), ranks(b));
    let mean = (n as f64 + 1.0) / 2.0;
    let (mut sab, mut saa, mut sbb) = (0.0, 0.0, 0.0);
    for k in 0..n {
        let (x, y) = (ra[k] - mean, rb[k] - mean);
        sab += x * y;
        saa += x * x;
        sbb += y * y;
    }
    (saa > 0.0 && sbb > 0.0).then(|| sab / (saa * sbb).sqrt())
}

/// Linear-interpolated percentile `p` (0–1) of sorted values (NaN when empty).
pub(crate) fn percentile(sorted: &[f64], p: f64) -> f64 {
    if sorted.is_empty() {
        return f64::NAN;
    }
    let x = p * (sorted.len() - 1) as f64;
    let (i, f) = (x.floor() as usize, x - x.floor());
    let j = (i + 1).min(sorted.len() - 1);
    sorted[i] * (1.0 - f) + sorted[j] * f
}

/// Run the study: `candidates[0]` is the recommended placement, `baseline` (if any) is
/// compared against it; every candidate must be feasible under the nominal robot (infeasible
/// ones are skipped). `draws` ≥ 1. Errors: no drive data to vary, a model error.
pub fn study(
    job: &PathJob,
    ev: &Evaluator,
    candidates: &[Evaluated],
    baseline: Option<&Evaluated>,
    draws: usize,
    seed: u64,
) -> Result<Study> {
    study_with(job, ev, candidates, baseline, draws, seed, None)
}

/// [`study`] with the ranges given (`None`: the drive file's, else the defaults). `_job` is
/// the evaluator's job (the draws rebuild it per drawn robot from `ev.job`).
pub fn study_with(
    _job: &PathJob,
    ev: &Evaluator,
    candidates: &[Evaluated],
    baseline: Option<&Evaluated>,
    draws: usize,
    seed: u64,
    ranges: Option<Ranges>,
) -> Result<Study> {
    let setup = StudySetup::new(ev, candidates, baseline, draws, seed, ranges)?;
    let all: Vec<usize> = (0..draws).collect();
    let per = setup.draws(&all)?;
    setup.reduce(&per)
}

/// One draw of a study: the energies of every candidate under the drawn robot (J, the study's
/// candidate order: the recommended placement first, the baseline last when there is one;
/// `inf` where a candidate's energy could not be evaluated) and the values drawn (name, value
/// in the parameter's own scale). Serialisable, so that draws computed on several machines
/// ([`crate::campaign::shard`]) reduce to the same study as one run.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Draw {
    /// Energy of each candidate under this draw's robot, J.
    pub energies_j: Vec<f64>,
    /// The parameters drawn: (name, multiplier, shift in m, or 1/0 for presence).
    pub drawn: Vec<(String, f64)>,
}

/// A study prepared: the candidates timed once under the nominal robot (timing does not depend
/// on the drawn numbers), the ranges, the seed and the number of draws. Draw `d` depends only
/// on `(seed, d)`, so any subset of draws can be computed anywhere and [`StudySetup::reduce`]
/// gives the same [`Study`] from all of them, in draw order.
pub struct StudySetup<'s, 'j, 'a> {
    ev: &'s Evaluator<'j, 'a>,
    timed: Vec<crate::timing::TimedPath>,
    nominal: Vec<f64>,
    has_base: bool,
    ranges: Ranges,
    source: Source,
    draws: usize,
    seed: u64,
    /// The nominal robot's effects, which draw their own numbers.
    effects: EffectSet,
}

impl<'s, 'j, 'a> StudySetup<'s, 'j, 'a> {
    /// Prepare a study of `draws` draws (>= 1) seeded by `seed`: `candidates[0]` is the
    /// recommended placement, `baseline` (if any) is compared against it; infeasible candidates
    /// are skipped. Errors: no draw, no feasible candidate, a candidate that cannot be re-timed.
    pub fn new(
        ev: &'s Evaluator<'j, 'a>,
        candidates: &[Evaluated],
        baseline: Option<&Evaluated>,
        draws: usize,
        seed: u64,
        ranges: Option<Ranges>,
    ) -> Result<Self> {
        if draws == 0 {
            return Err(Error::Invalid("uncertainty study: at least 1 draw".into()));
        }
        let (ranges, source) = match ranges {
            Some(r) => (r, Source::Given),
            None => match Ranges::of_robot(ev.job.robot)? {
                Some((r, file)) => (r, Source::DriveFile(file)),
                None => (Ranges::default(), Source::Default),
            },
        };
        // Candidates: feasible, the recommended first, the baseline last; timed once.
        let mut cands: Vec<&Evaluated> = candidates
            .iter()
            .filter(|e| e.feasible().is_some())
            .collect();
        if cands.is_empty() {
            return Err(Error::Invalid(
                "uncertainty study: no feasible candidate".into(),
            ));
        }
        let has_base = match baseline.filter(|b| b.feasible().is_some()) {
            Some(b) => {
                cands.push(b);
                true
            }
            None => false,
        };
        let mut sc = ev.scratch()?;
        let mut timed = Vec::with_capacity(cands.len());
        for c in &cands {
            let t = ev.timed(&mut sc, &c.placement).map_err(|e| {
                Error::Invalid(format!("uncertainty study: re-timing a candidate: {e}"))
            })?;
            timed.push(t);
        }
        let nominal: Vec<f64> = cands.iter().map(|c| c.cost()).collect();
        let effects = EffectSet::of_robot(ev.job.robot)?;
        Ok(StudySetup {
            effects,
            ev,
            timed,
            nominal,
            has_base,
            ranges,
            source,
            draws,
            seed,
        })
    }

    /// Number of draws of the study.
    pub fn len(&self) -> usize {
        self.draws
    }

    /// Whether the study has no draws (never: [`StudySetup::new`] refuses 0).
    pub fn is_empty(&self) -> bool {
        self.draws == 0
    }

    /// Draw `d`: a robot from its own ChaCha8 stream (`seed`, stream `d`), and its energies at
    /// every candidate. Errors: `d` beyond the study, a model error.
    pub fn draw(&self, d: usize) -> Result<Draw> {
        if d >= self.draws {
            return Err(Error::Invalid(format!(
                "uncertainty study: draw {d} of a study of {} draws",
                self.draws
            )));
        }
        let job = self.ev.job;
        let mut rng = ChaCha8Rng::seed_from_u64(self.seed);
        rng.set_stream(d as u64);
        let (m, drawn, _) = draw_robot(job.robot, &self.effects, &self.ranges, &mut rng);
        let jd = PathJob {
            robot: &m,
            energy: EnergyModel::with_options(&m, job.energy.options())?,
            moves: job.moves.clone(),
            pieces: job.pieces.clone(),
            plan: job.plan.clone(),
            profile: job.profile,
            joint: job.joint,
            source: job.source.clone(),
        };
        let evd = Evaluator::new(&jd, self.ev.feasibility, self.ev.objective);
        let mut scd = evd.scratch()?;
        let energies_j: Vec<f64> = self
            .timed
            .iter()
            .map(|t| {
                evd.energy_of(&mut scd, t, Default::default())
                    .map_or(f64::INFINITY, |f| f.energy_j)
            })
            .collect();
        Ok(Draw { energies_j, drawn })
    }

    /// The draws `indices`, in parallel, returned in the order given.
    pub fn draws(&self, indices: &[usize]) -> Result<Vec<Draw>> {
        let results: Vec<Result<Draw>> = indices.par_iter().map(|&d| self.draw(d)).collect();
        results.into_iter().collect()
    }

    /// The study from all its draws, `per[d]` being draw `d` (every reduction in draw order,
    /// so the result does not depend on where or on how many threads the draws ran). Errors:
    /// not exactly one draw per index, or a draw of another set of candidates.
    pub fn reduce(&self, per: &[Draw]) -> Result<Study> {
        let draws = self.draws;
        self.check_draws(per)?;
        let k_opt = self.timed.len() - usize::from(self.has_base); // candidates competing for "best"
        let tally = Tally::of(per, k_opt, self.has_base, &self.nominal);
        let savings = &tally.savings;
        let saving_pct = (!savings.is_empty()).then(|| {
            let mean = savings.iter().sum::<f64>() / savings.len() as f64;
            let mut s = savings.clone();
            s.sort_by(f64::total_cmp);
            [mean, percentile(&s, 0.05), percentile(&s, 0.95)]
        });
        let rhos = &tally.rhos;
        let rank_correlation = if rhos.is_empty() {
            [1.0, 1.0]
        } else {
            [
                rhos.iter().sum::<f64>() / rhos.len() as f64,
                rhos.iter().copied().fold(f64::INFINITY, f64::min),
            ]
        };
        // Which drawn parameter moves the answer: against the regret where it varies, else
        // against the saving.
        let regret = &tally.regret;
        let response: &[f64] = if regret.iter().any(|r| *r != regret[0]) || savings.is_empty() {
            regret
        } else {
            savings
        };
        let depends = depends_on(per, response);
        // The identified parameters the draws take from their standard errors (the same in
        // every draw: which parameters, not their values, depend on the robot alone).
        let (_, _, calibrated) = draw_robot(
            self.ev.job.robot,
            &self.effects,
            &self.ranges,
            &mut ChaCha8Rng::seed_from_u64(self.seed),
        );
        Ok(Study {
            draws,
            seed: self.seed,
            source: self.source.clone(),
            calibrated,
            candidates: k_opt,
            p_within_1pct: tally.within as f64 / draws as f64,
            p_best: tally.best_n as f64 / draws as f64,
            saving_pct,
            rank_correlation,
            depends_on: depends,
            per_draw_j: tally.per_draw_j,
        })
    }

    /// Errors: not exactly one draw per index, or a draw of another set of candidates.
    fn check_draws(&self, per: &[Draw]) -> Result<()> {
        let draws = self.draws;
        if per.len() != draws {
            return Err(Error::Invalid(format!(
                "uncertainty study: {} draws given for a study of {draws}",
                per.len()
            )));
        }
        if let Some(d) = per
            .iter()
            .position(|p| p.energies_j.len() != self.timed.len())
        {
            return Err(Error::Invalid(format!(
                "uncertainty study: draw {d} holds {} candidates, the study {}",
                per[d].energies_j.len(),
                self.timed.len()
            )));
        }
        Ok(())
    }
}

/// The recommendation over the draws, in draw order.
struct Tally {
    /// Draws where it is within 1 % of the best candidate.
    within: usize,
    /// Draws where it is the best.
    best_n: usize,
    /// Per draw: its saving against the baseline, %.
    savings: Vec<f64>,
    /// Per draw: the rank correlation of the candidates with their nominal order.
    rhos: Vec<f64>,
    /// Per draw: its relative regret against the best candidate.
    regret: Vec<f64>,
    /// Per draw: its energy and the best candidate's, J.
    per_draw_j: Vec<[f64; 2]>,
}

impl Tally {
    /// The tally over `per` of the first of `k_opt` competing candidates (the baseline last
    /// when `has_base`), `nominal` being their nominal energies.
    fn of(per: &[Draw], k_opt: usize, has_base: bool, nominal: &[f64]) -> Tally {
        let draws = per.len();
        let mut within = 0usize;
        let mut best_n = 0usize;
        let mut savings = Vec::new();
        let mut rhos = Vec::new();
        let mut regret = Vec::with_capacity(draws);
        let mut per_draw_j = Vec::with_capacity(draws);
        for Draw { energies_j: e, .. } in per {
            let best = e[..k_opt].iter().copied().fold(f64::INFINITY, f64::min);
            let rec = e[0];
            if rec <= 1.01 * best {
                within += 1;
            }
            if rec <= best {
                best_n += 1;
            }
            regret.push((rec - best) / best);
            per_draw_j.push([rec, best]);
            if has_base {
                let b = e[e.len() - 1];
                savings.push((b - rec) / b * 100.0);
            }
            if let Some(r) = spearman(&e[..k_opt], &nominal[..k_opt]) {
                rhos.push(r);
            }
        }
        Tally {
            within,
            best_n,
            savings,
            rhos,
            regret,
            per_draw_j,
        }
    }
}

/// The drawn parameters that move `response` most (at most five, by rank correlation).
fn depends_on(per: &[Draw], response: &[f64]) -> Vec<(String, f64)> {
    let mut depends: Vec<(String, f64)> = Vec::new();
    if let Some(first) = per.first() {
        for (i, (name, _)) in first.drawn.iter().enumerate() {
            let xs: Vec<f64> = per
                .iter()
                .map(|d| d.drawn.get(i).map_or(0.0, |v| v.1))
                .collect();
            if let Some(r) = spearman(&xs, response) {
                depends.push((name.clone(), r));
            }
        }
    }
    depends.sort_by(|a, b| b.1.abs().total_cmp(&a.1.abs()).then(a.0.cmp(&b.0)));
    depends.truncate(5);
    depends
}

/// The ranges a study of `model` draws from: `given`, else the drive file's `[uncertainty]`
/// table, else the built-in defaults, and where they came from.
pub(crate) fn resolve_ranges(
    model: &RobotModel,
    given: Option<Ranges>,
) -> Result<(Ranges, Source)> {
    Ok(match given {
        Some(r) => (r, Source::Given),
        None => match Ranges::of_robot(model)? {
            Some((r, file)) => (r, Source::DriveFile(file)),
            None => (Ranges::default(), Source::Default),
        },
    })
}

/// Draw `d` of a study seeded by `seed`: the robot [`StudySetup::draw`] evaluates (the same
/// ChaCha8 stream) and the values drawn (name, value in the parameter's own scale), for a
/// caller that evaluates more than a fixed set of candidates under it.
pub fn drawn_robot(
    nominal: &RobotModel,
    ranges: &Ranges,
    seed: u64,
    d: usize,
) -> (RobotModel, Vec<(String, f64)>) {
    let effects = EffectSet::of_robot(nominal).unwrap_or_default();
    drawn_robot_of(nominal, &effects, ranges, seed, d)
}

/// [`drawn_robot`] with the nominal robot's effects built once ([`EffectSet::of_robot`]), for
/// a caller that draws many robots.
pub(crate) fn drawn_robot_of(
    nominal: &RobotModel,
    effects: &EffectSet,
    ranges: &Ranges,
    seed: u64,
    d: usize,
) -> (RobotModel, Vec<(String, f64)>) {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    rng.set_stream(d as u64);
    let (m, drawn, _) = draw_robot(nominal, effects, ranges, &mut rng);
    (m, drawn)
}

/// The identified parameters a study of `nominal` draws from their standard errors
/// (calibrated robots), by name.
pub(crate) fn calibrated_names(nominal: &RobotModel, ranges: &Ranges) -> Vec<String> {
    let effects = EffectSet::of_robot(nominal).unwrap_or_default();
    draw_robot(nominal, &effects, ranges, &mut ChaCha8Rng::seed_from_u64(0)).2
}
