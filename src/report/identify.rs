//! The report page of an identification round (`identify`): the calibration rounds so far,
//! the parameters fitted with their standard errors and plausibility, the error per joint
//! before and after the fit, and the error ladder. Numbers arrive computed; this module only
//! formats them.

use super::html::{table, Page};
use super::svg;
use crate::identify::ladder::Identification;
use crate::identify::metrics::Comparison;
use crate::robot::drive::CalibrationRound;

/// Everything the identification page shows.
#[derive(Clone, Debug)]
pub(crate) struct IdentifyReport<'a> {
    /// Title of the page.
    pub title: String,
    /// Facts shown at the top (robot, robot file, drive data, log, signal, validation).
    pub facts: Vec<(String, String)>,
    /// The calibration rounds the robot had before this one (its drive file's record).
    pub earlier_rounds: &'a [CalibrationRound],
    /// This round's result.
    pub id: &'a Identification,
    /// Unit of the compared signal (e.g. `N·m`).
    pub unit: String,
    /// The model against the log before the fit and after it, and which log that is.
    pub before_after: Option<(&'a Comparison, &'a Comparison, String)>,
}

impl IdentifyReport<'_> {
    /// Whether a fitted parameter is plausible, in words: `yes`, or what is wrong with it (a
    /// physically implausible value, a bound reached, held at its prior, ill-conditioned).
    fn plausibility(&self, effect: &str, name: &str) -> String {
        let full = format!("{effect}.{name}");
        let id = self.id;
        let mut why: Vec<String> = id
            .implausible
            .iter()
            .filter(|m| m.contains(&full) || m.contains(name))
            .map(|m| format!("NOT plausible: {m}"))
            .collect();
        if id.at_bound.iter().any(|b| b.contains(&full)) {
            why.push("at a bound of its range".into());
        }
        if let Some(h) = id.held_at_prior.iter().find(|h| h.name == full) {
            why.push(format!("held at its prior value ({})", h.reason));
        }
        if why.is_empty() {
            "yes".into()
        } else {
            why.join("; ")
        }
    }

    /// The ladder as a bar chart: the validation RMSE after each step (the `ladder.svg`
    /// written beside the report).
    pub(crate) fn ladder_svg(&self) -> String {
        let labels: Vec<String> = self.id.ladder.iter().map(|s| s.step.clone()).collect();
        let vals: Vec<f64> = self.id.ladder.iter().map(|s| s.validation_rmse).collect();
        svg::bar_chart(
            &svg::Frame::new(
                "Error ladder: validation RMSE per step",
                "ladder step (effects added cumulatively)",
                &format!("validation RMSE [{}]", self.unit),
            ),
            &labels,
            &[("validation RMSE".into(), vals)],
        )
    }

    /// The page (self-contained XHTML).
    pub fn html(&self) -> String {
        let mut pg = Page::new(&self.title);
        pg.kv(&self.facts);
        self.rounds_section(&mut pg);
        self.params_section(&mut pg);
        if let Some((before, after, on)) = &self.before_after {
            self.per_joint_section(&mut pg, (before, after), on);
        }
        self.ladder_section(&mut pg);
        pg.finish()
    }

    /// The calibration rounds so far, this one last, and whether its fit is plausible.
    fn rounds_section(&self, pg: &mut Page) {
        let id = self.id;
        pg.h2("Rounds");
        let mut rows: Vec<Vec<String>> = self
            .earlier_rounds
            .iter()
            .map(|r| {
                vec![
                    r.round.to_string(),
                    r.effects.join(", "),
                    format!("{} ({})", r.log, r.signal),
                    format!("{:.4}", r.validation_rmse_before),
                    format!("{:.4}", r.validation_rmse_after),
                ]
            })
            .collect();
        rows.push(vec![
            format!("{} (this one)", self.earlier_rounds.len() + 1),
            id.ladder
                .last()
                .map(|s| s.fitted.join(", "))
                .unwrap_or_default(),
            id.validation.clone(),
            id.ladder
                .first()
                .map_or("-".into(), |s| format!("{:.4}", s.validation_rmse)),
            id.ladder
                .last()
                .map_or("-".into(), |s| format!("{:.4}", s.validation_rmse)),
        ]);
        let u = &self.unit;
        pg.table(
            &header(&[
                "round",
                "effects fitted",
                "log (validation)",
                &format!("validation RMSE before [{u}]"),
                &format!("after [{u}]"),
            ]),
            &rows,
        );
        if !id.implausible.is_empty() {
            pg.p(&format!(
                "The fit is NOT physically plausible, so no calibrated robot was written: {}",
                id.implausible.join("; ")
            ));
        }
    }

    /// The fitted parameters: before, fitted, standard error and plausibility.
    fn params_section(&self, pg: &mut Page) {
        let id = self.id;
        pg.h2("Fitted parameters");
        let rows: Vec<Vec<String>> = id
            .params
            .iter()
            .map(|p| {
                vec![
                    p.effect.clone(),
                    p.name.clone(),
                    p.unit.clone(),
                    format!("{:.6}", p.nominal),
                    format!("{:.6}", p.value),
                    p.std_error.map_or("-".into(), |e| format!("{e:.6}")),
                    p.std_error
                        .filter(|e| p.value != 0.0 && e.is_finite())
                        .map_or("-".into(), |e| format!("{:.1}", 100.0 * e / p.value.abs())),
                    self.plausibility(&p.effect, &p.name),
                ]
            })
            .collect();
        pg.table(
            &header(&[
                "effect",
                "parameter",
                "unit",
                "before",
                "fitted",
                "standard error",
                "standard error [%]",
                "plausible",
            ]),
            &rows,
        );
        if let Some(ill) = &id.ill_conditioned {
            pg.p(&ill.to_string());
        }
    }

    /// The error per joint before and after the fit on the log `on`: a table and a chart.
    fn per_joint_section(
        &self,
        pg: &mut Page,
        (before, after): (&Comparison, &Comparison),
        on: &str,
    ) {
        let u = &self.unit;
        pg.h2("Error per joint, before and after the fit");
        pg.p(&format!("On {on}."));
        let mut rows = Vec::new();
        let mut cats = Vec::new();
        let (mut vb, mut va) = (Vec::new(), Vec::new());
        for (b, a) in before
            .channels
            .iter()
            .chain(std::iter::once(&before.total))
            .zip(after.channels.iter().chain(std::iter::once(&after.total)))
        {
            rows.push(vec![
                b.name.clone(),
                format!("{:.4}", b.rmse),
                format!("{:.4}", a.rmse),
                format!("{:.2}", b.energy_error_pct),
                format!("{:.2}", a.energy_error_pct),
            ]);
            if b.name != before.total.name {
                cats.push(b.name.clone());
                vb.push(b.rmse);
                va.push(a.rmse);
            }
        }
        pg.table(
            &header(&[
                "joint",
                &format!("RMSE before [{u}]"),
                &format!("RMSE after [{u}]"),
                "energy error before [%]",
                "energy error after [%]",
            ]),
            &rows,
        );
        pg.figure(
            "per-joint",
            &svg::bar_chart(
                &svg::Frame::new(
                    "Error per joint before and after the fit",
                    "joint",
                    &format!("RMSE [{u}]"),
                )
                .size(760.0, 340.0),
                &cats,
                &[("before".into(), vb), ("after".into(), va)],
            ),
            "RMSE of the modelled signal against the log, per joint, with the model before the fit and with the fitted parameters.",
        );
    }

    /// The error ladder: a table of the steps and its chart.
    fn ladder_section(&self, pg: &mut Page) {
        let (id, u) = (self.id, &self.unit);
        pg.h2("Error ladder");
        let rows: Vec<Vec<String>> = id
            .ladder
            .iter()
            .map(|r| {
                vec![
                    r.step.clone(),
                    format!("{:.4}", r.train_rmse),
                    format!("{:.4}", r.validation_rmse),
                    format!("{:.2}", r.validation_energy_error_pct),
                    format!("{:.2}", r.validation_accuracy_pct),
                ]
            })
            .collect();
        pg.raw(&table(
            &header(&[
                "step",
                &format!("train RMSE [{u}]"),
                &format!("validation RMSE [{u}]"),
                "validation energy error [%]",
                "accuracy [%]",
            ]),
            &rows,
        ));
        pg.figure(
            "ladder",
            &self.ladder_svg(),
            "Validation RMSE after each step of the ladder (effects added one by one, each fitted with those before it).",
        );
    }
}

/// Column headings as owned strings.
fn header(v: &[&str]) -> Vec<String> {
    v.iter().map(|s| s.to_string()).collect()
}
