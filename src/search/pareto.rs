//! Print time against energy at the answer: the print speed is fixed by the concrete, but the
//! controller's TCP acceleration and jerk limits (RAPID `AccSet`, a URScript `a`) set how fast
//! corners, blends, travel moves, starts and stops are taken. The answer's path is timed again
//! with both limits scaled by [`SCALES`] and evaluated with the same checks and energy model;
//! the settings no other setting beats in both print time and energy form the Pareto front.
//! Each point's CO₂ follows from the stated grid intensity.

use crate::error::Result;
use crate::evaluate::Evaluator;
use crate::frame::Placement;
use crate::search::job::OptimiseConfig;
use serde::Serialize;

/// Factors applied to the TCP acceleration (tangential and lateral) and jerk limits.
pub const SCALES: [f64; 5] = [0.5, 0.75, 1.0, 1.5, 2.0];

/// One timing setting at the answer.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct TimingPoint {
    /// Factor on the configured acceleration and jerk limits.
    pub scale: f64,
    /// TCP acceleration limit, m/s².
    pub accel_m_s2: f64,
    /// TCP jerk limit, m/s³.
    pub jerk_m_s3: f64,
    /// Print time, s (`None`: infeasible).
    pub duration_s: Option<f64>,
    /// The objective's energy, J.
    pub energy_j: Option<f64>,
    /// Drives' energy, J (what the timing changes besides the standby time).
    pub drives_j: Option<f64>,
    /// Standby energy, J.
    pub standby_j: Option<f64>,
    /// CO₂ of the objective's energy at the stated grid intensity, kg per print.
    pub kg_co2: Option<f64>,
    /// Why the setting is infeasible at the answer.
    pub reason: Option<String>,
    /// On the Pareto front of print time and energy.
    pub pareto: bool,
}

/// The answer `at` of `config` timed with every factor of [`SCALES`] on its acceleration and
/// jerk limits (in that order), with the Pareto front of (print time, energy) marked.
pub(crate) fn time_energy(config: &OptimiseConfig, at: &Placement) -> Result<Vec<TimingPoint>> {
    let s = &config.settings;
    let mut out = Vec::with_capacity(SCALES.len());
    for k in SCALES {
        let mut profile = s.profile;
        profile.accel *= k;
        profile.lateral_accel *= k;
        profile.jerk *= k;
        let job = crate::search::job::job_with(config, &config.robot, profile)?;
        let ev = Evaluator::new(&job, s.feasibility, s.objective);
        let e = ev
            .sweep(&[*at], &|_, _| {})?
            .into_iter()
            .next()
            .expect("one placement evaluated");
        let mut p = TimingPoint {
            scale: k,
            accel_m_s2: profile.accel,
            jerk_m_s3: profile.jerk,
            duration_s: None,
            energy_j: None,
            drives_j: None,
            standby_j: None,
            kg_co2: None,
            reason: None,
            pareto: false,
        };
        match &e.outcome {
            Ok(f) => {
                p.duration_s = Some(f.duration_s);
                p.energy_j = Some(f.energy_j);
                p.drives_j = Some(f.drives_j);
                p.standby_j = Some(f.standby_j);
                p.kg_co2 = Some(f.energy_j / 3.6e6 * s.grid_kg_co2_per_kwh);
            }
            Err(i) => p.reason = Some(i.to_string()),
        }
        out.push(p);
    }
    mark_front(&mut out);
    Ok(out)
}

/// Mark the feasible points that no other feasible point beats in both print time and energy
/// (at least as good in both, better in one).
fn mark_front(ps: &mut [TimingPoint]) {
    let pts: Vec<Option<(f64, f64)>> = ps.iter().map(|p| p.duration_s.zip(p.energy_j)).collect();
    for i in 0..ps.len() {
        let Some((ti, ei)) = pts[i] else { continue };
        ps[i].pareto = !pts.iter().enumerate().any(|(j, q)| {
            j != i && q.is_some_and(|(tj, ej)| tj <= ti && ej <= ei && (tj < ti || ej < ei))
        });
    }
}

/// The points in a few lines (terminal and report).
pub fn lines(ps: &[TimingPoint]) -> Vec<String> {
    ps.iter()
        .map(|p| match (p.duration_s, p.energy_j) {
            (Some(t), Some(e)) => format!(
                "timing ×{:.2} (accel {:.2} m/s², jerk {:.1} m/s³): print time {t:.2} s, energy {e:.1} J (drives {:.1} J, standby {:.1} J), {:.1} g CO₂{}",
                p.scale,
                p.accel_m_s2,
                p.jerk_m_s3,
                p.drives_j.unwrap_or(f64::NAN),
                p.standby_j.unwrap_or(f64::NAN),
                1e3 * p.kg_co2.unwrap_or(f64::NAN),
                if p.pareto { "; on the Pareto front" } else { "" }
            ),
            _ => format!(
                "timing ×{:.2} (accel {:.2} m/s², jerk {:.1} m/s³): infeasible at the answer ({})",
                p.scale,
                p.accel_m_s2,
                p.jerk_m_s3,
                p.reason.as_deref().unwrap_or("?")
            ),
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn pt(t: Option<f64>, e: f64) -> TimingPoint {
        TimingPoint {
            scale: 1.0,
            accel_m_s2: 1.0,
            jerk_m_s3: 10.0,
            duration_s: t,
            energy_j: t.map(|_| e),
            drives_j: None,
            standby_j: None,
            kg_co2: None,
            reason: None,
            pareto: false,
        }
    }

    #[test]
    fn the_front_keeps_only_points_no_other_beats_in_both() {
        let mut ps = vec![
            pt(Some(10.0), 100.0),
            pt(Some(9.0), 110.0),
            pt(Some(11.0), 105.0),
            pt(None, 0.0),
            pt(Some(9.0), 110.0),
        ];
        mark_front(&mut ps);
        let front: Vec<bool> = ps.iter().map(|p| p.pareto).collect();
        assert_eq!(front, [true, true, false, false, true]);
    }
}
