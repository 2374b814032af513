//! Margins as a trade: the answer found again with other joint-limit and wrist-singularity
//! margins, so a site can choose robustness knowingly. A larger margin keeps the arm further
//! from its stops and from the wrist singularity (time to react to a path edit, a
//! calibration offset, a controller's look-ahead), and it shrinks the set of placements a
//! search may use: its energy cost is what the table states.
//!
//! Each setting re-runs the same search as the answer (grid, refinement with the placement
//! tolerance, full re-evaluation of a reduced answer) with only the margin changed; the
//! configured setting is the answer itself and is not searched twice.

use crate::error::Result;
use crate::evaluate::evaluator::Evaluated;
use crate::evaluate::feasibility::FeasibilityOptions;
use crate::frame::Placement;
use serde::Serialize;

/// Joint-limit margins traded, degrees.
pub(crate) const JOINT_MARGINS_DEG: [f64; 3] = [3.0, 5.0, 8.0];
/// Wrist-singularity margins traded, degrees (0: the wrist may pass through).
pub(crate) const WRIST_MARGINS_DEG: [f64; 3] = [0.0, 5.0, 8.0];

/// One margin setting and the answer the search finds with it.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct MarginPoint {
    /// Joint-limit margin, degrees (the joints without a drive-file margin).
    pub joint_margin_deg: f64,
    /// Wrist-singularity margin, degrees.
    pub wrist_margin_deg: f64,
    /// The configured setting (the run's answer).
    pub configured: bool,
    /// The answer with this setting (`None`: no feasible placement).
    #[serde(serialize_with = "ser_opt_placement")]
    pub placement: Option<Placement>,
    /// The objective's energy there, J.
    pub energy_j: Option<f64>,
    /// Drives' energy there, J.
    pub drives_j: Option<f64>,
    /// The energy against the configured setting's answer, J (positive: dearer).
    pub delta_j: Option<f64>,
    /// Why there is no answer.
    pub reason: Option<String>,
}

fn ser_opt_placement<S: serde::Serializer>(
    p: &Option<Placement>,
    s: S,
) -> std::result::Result<S::Ok, S::Error> {
    struct P<'a>(&'a Placement);
    impl Serialize for P<'_> {
        fn serialize<S: serde::Serializer>(&self, s: S) -> std::result::Result<S::Ok, S::Error> {
            crate::search::robust::ser_placement(self.0, s)
        }
    }
    match p {
        Some(p) => s.serialize_some(&P(p)),
        None => s.serialize_none(),
    }
}

/// The settings traded around `feas` (its first joint's margin and its wrist margin): every
/// joint margin of [`JOINT_MARGINS_DEG`] at the configured wrist margin, every wrist margin of
/// [`WRIST_MARGINS_DEG`] at the configured joint margin, and the configured setting; in that
/// order, without repeats.
pub fn settings(feas: &FeasibilityOptions) -> Vec<(f64, f64)> {
    let (joint, wrist) = configured(feas);
    let mut out: Vec<(f64, f64)> = Vec::new();
    let mut push = |s: (f64, f64)| {
        if !out
            .iter()
            .any(|o| (o.0 - s.0).abs() < 1e-9 && (o.1 - s.1).abs() < 1e-9)
        {
            out.push(s);
        }
    };
    for j in JOINT_MARGINS_DEG {
        push((j, wrist));
    }
    for w in WRIST_MARGINS_DEG {
        push((joint, w));
    }
    push((joint, wrist));
    out.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.total_cmp(&b.1)));
    out
}

/// The configured (joint, wrist) margins of `feas` in degrees, to a micro-degree (so that
/// 3° given in radians reads back as 3°).
fn configured(feas: &FeasibilityOptions) -> (f64, f64) {
    let deg = |r: f64| (r.to_degrees() * 1e6).round() / 1e6;
    (deg(feas.joint_margin_rad[0]), deg(feas.wrist_margin_rad))
}

/// `feas` with the joint margin `joint_deg` on every joint and the wrist margin `wrist_deg`.
pub(crate) fn with_margins(
    feas: &FeasibilityOptions,
    joint_deg: f64,
    wrist_deg: f64,
) -> FeasibilityOptions {
    let mut f = *feas;
    f.joint_margin_rad = [joint_deg.to_radians(); crate::kinematics::MAX_DOF];
    f.wrist_margin_rad = wrist_deg.to_radians();
    f
}

/// The trade: every setting of [`settings`] and its answer.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct MarginTrade {
    /// The settings, ordered by joint then wrist margin.
    pub points: Vec<MarginPoint>,
    /// When a stricter setting's answer was cheaper than the first answer: the refinement ran
    /// again from it under the configured margins, and this is what it gave.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub restart: Option<Restart>,
    /// Evaluations the trade's searches made (grids, refinements, tolerance corners; with a
    /// restart, also the first refinement's).
    pub evaluations: usize,
}

/// The refinement run again from a stricter setting's answer.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Restart {
    /// The stricter setting it started from, degrees.
    pub joint_margin_deg: f64,
    /// The stricter setting it started from, degrees.
    pub wrist_margin_deg: f64,
    /// The first answer's energy, J.
    pub before_j: f64,
    /// The answer's energy after the second refinement, J.
    pub after_j: f64,
}

impl MarginTrade {
    /// The cheapest answer of a setting at least as strict as the configured one in both
    /// margins (so it keeps the configured margins too) that is cheaper than the configured
    /// setting's answer: the search stopped short of it.
    pub fn cheaper_stricter(&self) -> Option<&MarginPoint> {
        let c = self.points.iter().find(|p| p.configured)?;
        let e0 = c.energy_j?;
        self.points
            .iter()
            .filter(|p| {
                !p.configured
                    && p.joint_margin_deg >= c.joint_margin_deg
                    && p.wrist_margin_deg >= c.wrist_margin_deg
            })
            .filter(|p| p.energy_j.is_some_and(|e| e < e0))
            .min_by(|a, b| a.energy_j.unwrap().total_cmp(&b.energy_j.unwrap()))
    }

    /// The configured setting's answer replaced by `answer`; the differences follow it.
    pub(crate) fn answer_is(&mut self, answer: &Evaluated) {
        let e0 = answer.feasible().map(|f| f.energy_j);
        for p in &mut self.points {
            if p.configured {
                p.placement = Some(answer.placement);
                p.energy_j = e0;
                p.drives_j = answer.feasible().map(|f| f.drives_j);
            }
            p.delta_j = p.energy_j.zip(e0).map(|(e, a)| e - a);
        }
    }
}

/// The trade: `find(options)` searches with the given feasibility options and answers with
/// the best placement (or the reason there is none); the configured setting is `answer`.
pub fn trade(
    feas: &FeasibilityOptions,
    answer: &Evaluated,
    find: &dyn Fn(&FeasibilityOptions) -> Result<std::result::Result<Evaluated, String>>,
) -> Result<MarginTrade> {
    let (joint, wrist) = configured(feas);
    let mut points = Vec::new();
    for (j, w) in settings(feas) {
        let configured = (j - joint).abs() < 1e-9 && (w - wrist).abs() < 1e-9;
        let found = if configured {
            Ok(answer.clone())
        } else {
            find(&with_margins(feas, j, w))?
        };
        let mut p = MarginPoint {
            joint_margin_deg: j,
            wrist_margin_deg: w,
            configured,
            placement: None,
            energy_j: None,
            drives_j: None,
            delta_j: None,
            reason: None,
        };
        match found.as_ref().map(|e| (e, e.feasible())) {
            Ok((e, Some(f))) => {
                p.placement = Some(e.placement);
                p.energy_j = Some(f.energy_j);
                p.drives_j = Some(f.drives_j);
            }
            Ok((e, None)) => {
                p.reason = Some(match &e.outcome {
                    Err(i) => i.to_string(),
                    Ok(_) => "infeasible".into(),
                })
            }
            Err(why) => p.reason = Some(why.clone()),
        }
        points.push(p);
    }
    let mut t = MarginTrade {
        points,
        restart: None,
        evaluations: 0,
    };
    t.answer_is(answer);
    Ok(t)
}

/// The trade in a few lines (terminal and report).
pub fn lines(t: &MarginTrade) -> Vec<String> {
    let mut out: Vec<String> = t
        .points
        .iter()
        .map(|p| {
            let head = format!(
                "margins joint {:.0}°, wrist {:.0}°{}",
                p.joint_margin_deg,
                p.wrist_margin_deg,
                if p.configured { " (the answer's)" } else { "" }
            );
            match (&p.placement, p.energy_j) {
                (Some(at), Some(e)) => format!(
                    "{head}: {e:.1} J{} at x = {:.3} m, y = {:.3} m, z = {:.3} m, yaw = {:.1}°",
                    match p.delta_j {
                        Some(d) if !p.configured => format!(" ({d:+.1} J)"),
                        _ => String::new(),
                    },
                    at.x,
                    at.y,
                    at.z,
                    at.yaw.to_degrees()
                ),
                _ => format!(
                    "{head}: no feasible placement ({})",
                    p.reason.as_deref().unwrap_or("?")
                ),
            }
        })
        .collect();
    if let Some(r) = &t.restart {
        out.push(format!(
            "margin restart: the search with margins joint {:.0}°, wrist {:.0}° found a placement that also keeps the configured margins and was cheaper than the first answer; the refinement ran again from it: {:.1} J → {:.1} J",
            r.joint_margin_deg, r.wrist_margin_deg, r.before_j, r.after_j
        ));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_traded_settings_hold_the_configured_one_once() {
        let f = with_margins(&FeasibilityOptions::default(), 3.0, 5.0);
        let s = settings(&f);
        assert_eq!(
            s,
            vec![(3.0, 0.0), (3.0, 5.0), (3.0, 8.0), (5.0, 5.0), (8.0, 5.0)]
        );
        let f = with_margins(&f, 4.0, 2.0);
        let s = settings(&f);
        assert_eq!(s.len(), 7);
        assert!(s.contains(&(4.0, 2.0)));
    }
}
