//! The energy report: per-joint and total figures, and the per-sample series.

use serde::Serialize;
use std::io::Write;

/// Energies and figures of one joint over a trajectory. Energies in J (trapezoidal
/// `∫ P dt`, seed 000 eq. 7), powers in W, torques in N·m.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct JointEnergy {
    /// URDF joint name.
    pub name: String,
    /// `∫ τ q̇ dt` with the joint torque incl. friction (seed 000, eqs. 6–7), J.
    pub mechanical_j: f64,
    /// `∫ τ_rb q̇ dt`, rigid body incl. payload and armature, J.
    pub rigid_body_j: f64,
    /// `∫ τ_b q̇ dt`, work of the motor against the balancer (`balancer` effect), J.
    pub balancer_j: f64,
    /// `∫ τ_f q̇ dt`, friction loss, J.
    pub friction_j: f64,
    /// Gearbox loss, J.
    pub gear_j: f64,
    /// Copper loss `∫ R i² dt`, J.
    pub copper_j: f64,
    /// Net electrical energy `∫ u i dt` (seed 001, eq. 4), J.
    pub electrical_j: f64,
    /// Drawn electrical energy `∫ max(u i, 0) dt`, J.
    pub electrical_positive_j: f64,
    /// Peak of `τ q̇`, W.
    pub peak_mechanical_power_w: f64,
    /// Peak of `u i`, W.
    pub peak_electrical_power_w: f64,
    /// RMS joint torque over time, `sqrt(∫ τ² dt / T)`, N·m.
    pub rms_torque_nm: f64,
    /// Largest |τ|, N·m.
    pub max_abs_torque_nm: f64,
}

/// Totals over all joints, J (W for powers). The breakdown closes:
/// `supply = rigid_body + balancer + friction + gear + copper + regeneration_lost + standby`.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct TotalEnergy {
    /// Σ joints `∫ τ q̇ dt`, J.
    pub mechanical_j: f64,
    /// Σ joints `∫ τ_rb q̇ dt`, J.
    pub rigid_body_j: f64,
    /// Σ joints `∫ τ_b q̇ dt` (balancer), J.
    pub balancer_j: f64,
    /// Σ friction losses, J.
    pub friction_j: f64,
    /// Σ gearbox losses, J.
    pub gear_j: f64,
    /// Σ copper losses, J.
    pub copper_j: f64,
    /// Σ joints net electrical energy, J.
    pub electrical_j: f64,
    /// Energy drawn by the drives after the regeneration policy, J.
    pub drives_j: f64,
    /// Returned energy that the policy burns (`drives − electrical`), J.
    pub regeneration_lost_j: f64,
    /// Standby power × duration, J.
    pub standby_j: f64,
    /// Energy from the supply (drives + standby), J.
    pub supply_j: f64,
    /// Peak supply power, W.
    pub peak_supply_power_w: f64,
    /// Mean supply power, W.
    pub mean_supply_power_w: f64,
}

/// The energy one effect of the model accounts for. A joint-torque effect's is its own work
/// `Σ_j ∫ τ_e,j q̇_j dt` (trapezoidal, as the totals), booked to `rigid_body`, `friction` or
/// `balancer`: the effects of one part add up to that part of [`TotalEnergy`] (the rigid
/// body's part also holds the rigid body's own work). A motor or supply effect's is the part
/// of the totals its term makes: `copper` (winding resistance), `gear` (gear efficiency),
/// `regeneration_lost`, `standby`.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct EffectEnergy {
    /// The effect's stable name (`printwatt effects`).
    pub effect: String,
    /// The part of [`TotalEnergy`] it is booked to: a field's name without `_j`.
    pub part: &'static str,
    /// Its energy, J. Absent for an effect folded into the rigid body (a payload is a body of
    /// the rigid-body model: its work is inside `rigid_body_j`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub energy_j: Option<f64>,
}

/// Per-sample series (row-major `sample × joint` for per-joint arrays).
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct SampleSeries {
    /// Number of joints.
    pub n: usize,
    /// Times, s.
    pub t: Vec<f64>,
    /// Joint torque, N·m.
    pub tau: Vec<f64>,
    /// Mechanical power `τ q̇`, W.
    pub p_mech: Vec<f64>,
    /// Electrical power `u i`, W.
    pub p_el: Vec<f64>,
    /// Motor current, A.
    pub current: Vec<f64>,
    /// Supply power, W.
    pub p_supply: Vec<f64>,
}

impl SampleSeries {
    pub(crate) fn with_capacity(n: usize, len: usize) -> Self {
        SampleSeries {
            n,
            t: Vec::with_capacity(len),
            tau: Vec::with_capacity(len * n),
            p_mech: Vec::with_capacity(len * n),
            p_el: Vec::with_capacity(len * n),
            current: Vec::with_capacity(len * n),
            p_supply: Vec::with_capacity(len),
        }
    }

    /// The first value of the series (and of `traj`, as [`Self::write_csv`] writes them) that
    /// is not finite: its CSV column name, sample index and value, scanning sample by sample.
    pub fn first_non_finite(
        &self,
        traj: Option<&crate::trajectory::JointTrajectory>,
    ) -> Option<(String, usize, f64)> {
        let n = self.n;
        for k in 0..self.t.len() {
            if !self.t[k].is_finite() {
                return Some(("t[s]".into(), k, self.t[k]));
            }
            let mut blocks: Vec<(&str, &str, &[f64])> = Vec::with_capacity(7);
            if let Some(tr) = traj {
                blocks.extend([
                    ("q", "rad", tr.q(k)),
                    ("qd", "rad/s", tr.qd(k)),
                    ("qdd", "rad/s^2", tr.qdd(k)),
                ]);
            }
            for (p, u, v) in [
                ("tau", "Nm", &self.tau),
                ("p_mech", "W", &self.p_mech),
                ("p_el", "W", &self.p_el),
                ("i", "A", &self.current),
            ] {
                blocks.push((p, u, &v[k * n..(k + 1) * n]));
            }
            for (p, u, b) in blocks {
                if let Some(j) = b.iter().position(|x| !x.is_finite()) {
                    return Some((format!("{p}{}[{u}]", j + 1), k, b[j]));
                }
            }
            if !self.p_supply[k].is_finite() {
                return Some(("p_supply[W]".into(), k, self.p_supply[k]));
            }
        }
        None
    }

    /// Write the series as CSV with units in the headers (the same convention printwatt reads):
    /// `t[s]`, then, when `traj` is given, `q1[rad].., qd1[rad/s].., qdd1[rad/s^2]..`, then
    /// `tau1[Nm].., p_mech1[W].., p_el1[W].., i1[A]..`, `p_supply[W]`.
    pub fn write_csv<W: Write>(
        &self,
        traj: Option<&crate::trajectory::JointTrajectory>,
        mut w: W,
    ) -> std::io::Result<()> {
        let n = self.n;
        let mut head = vec!["t[s]".to_string()];
        let mut cols: Vec<(&str, &str)> = Vec::new();
        if traj.is_some() {
            cols.extend([("q", "rad"), ("qd", "rad/s"), ("qdd", "rad/s^2")]);
        }
        cols.extend([("tau", "Nm"), ("p_mech", "W"), ("p_el", "W"), ("i", "A")]);
        for (p, u) in &cols {
            head.extend((1..=n).map(|j| format!("{p}{j}[{u}]")));
        }
        head.push("p_supply[W]".into());
        writeln!(w, "{}", head.join(","))?;
        for k in 0..self.t.len() {
            write!(w, "{}", self.t[k])?;
            let mut blocks: Vec<&[f64]> = Vec::with_capacity(7);
            if let Some(tr) = traj {
                blocks.extend([tr.q(k), tr.qd(k), tr.qdd(k)]);
            }
            for v in [&self.tau, &self.p_mech, &self.p_el, &self.current] {
                blocks.push(&v[k * n..(k + 1) * n]);
            }
            for b in blocks {
                for x in b {
                    write!(w, ",{x}")?;
                }
            }
            writeln!(w, ",{}", self.p_supply[k])?;
        }
        Ok(())
    }
}

/// Result of [`super::evaluate`]. Serialises to JSON (the per-sample series included).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct EnergyReport {
    /// Robot display name.
    pub robot: String,
    /// What the model contains (rigid body only, or with drive effects).
    pub model: String,
    /// Whether the electrical model was used.
    pub has_drive: bool,
    /// Regeneration policy name.
    pub regeneration: String,
    /// Standby power, W.
    pub standby_power_w: f64,
    /// Trajectory duration, s.
    pub duration_s: f64,
    /// Number of samples.
    pub samples: usize,
    /// Per-joint figures.
    pub joints: Vec<JointEnergy>,
    /// Totals.
    pub total: TotalEnergy,
    /// The energy of each effect in the model, in catalogue order: where the totals' parts
    /// come from.
    pub by_effect: Vec<EffectEnergy>,
    /// Per-sample series.
    pub series: SampleSeries,
}
