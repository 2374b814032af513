//! What an effect draws in the placement's uncertainty study
//! ([`crate::search::uncertainty`]): each effect states when it draws ([`Uncertainty`]) and
//! draws its own numbers of the robot ([`super::Effect::draw`]) through a [`Drawing`], which
//! holds the drawn robot, the ranges, the random stream and the identified values of a
//! calibrated robot.
//!
//! The random numbers of a draw come from one stream in a fixed order: the phases in the order
//! of [`DrawPhase`], within a phase the effects by [`Uncertainty::rank`], and every joint's
//! numbers together (joint 1 of every effect, then joint 2, …). The ranks of the built-in
//! effects are that order; an effect added later takes a rank after them, so a seed keeps
//! drawing the same robots.

use crate::robot::RobotModel;
use crate::search::uncertainty::Ranges;
use rand::Rng;
use rand_chacha::ChaCha8Rng;

/// When in a draw an effect draws.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum DrawPhase {
    /// The robot's bodies (links, payload), first.
    Robot,
    /// Per joint of the drive (robots with drive data): [`super::Effect::draw`] is called
    /// with each joint in turn, every effect of this phase for joint 1, then joint 2, ….
    Joint,
    /// The cabinet (robots with drive data), after the joints.
    Cabinet,
    /// The drive file's `[effects]` table, last.
    Effects,
}

/// What an effect draws in the uncertainty study.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Uncertainty {
    /// When it draws.
    pub phase: DrawPhase,
    /// Its place within the phase (lower first).
    pub rank: u32,
    /// Whether its draw also draws its identified values (a calibrated robot's
    /// `[effects.values]`), which the study then leaves to it.
    pub draws_identified: bool,
}

/// One draw in progress: the robot being drawn, the ranges, the random stream and the
/// identified values of a calibrated robot with their drawn shifts.
pub struct Drawing<'a> {
    /// The robot being drawn (a copy of the nominal one); an effect changes the numbers it is
    /// built from (drive data, bodies, `[effects]` keys, `[effects.values]`).
    pub robot: &'a mut RobotModel,
    /// Half-widths of the uniform ranges.
    pub ranges: &'a Ranges,
    rng: &'a mut ChaCha8Rng,
    drawn: &'a mut Vec<(String, f64)>,
    identified: &'a [(String, String, f64, f64)],
    used: &'a mut Vec<String>,
}

impl std::fmt::Debug for Drawing<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "Drawing({} values drawn)", self.drawn.len())
    }
}

impl<'a> Drawing<'a> {
    /// A draw of `robot` from `rng`, recording into `drawn`; `identified` are the identified
    /// parameters `(effect, name, value, drawn shift)`, `used` collects those taken.
    pub(crate) fn new(
        robot: &'a mut RobotModel,
        ranges: &'a Ranges,
        rng: &'a mut ChaCha8Rng,
        drawn: &'a mut Vec<(String, f64)>,
        identified: &'a [(String, String, f64, f64)],
        used: &'a mut Vec<String>,
    ) -> Self {
        Drawing {
            robot,
            ranges,
            rng,
            drawn,
            identified,
            used,
        }
    }

    /// A uniform number in [−1, 1] from the stream (multiply by a half-width).
    pub fn uniform(&mut self) -> f64 {
        self.rng.gen_range(-1.0..=1.0)
    }

    /// A uniform number in [0, 1) from the stream (compare with a probability).
    pub fn unit(&mut self) -> f64 {
        self.rng.gen_range(0.0..1.0)
    }

    /// The identified value of parameter `name` (a calibrated robot) and its drawn shift
    /// (normal with its standard error, correlated as its fit), marking it as drawn; `None`
    /// when it was not identified with a standard error.
    pub fn identified(&mut self, name: &str) -> Option<(f64, f64)> {
        let c = self.identified.iter().find(|(_, n, _, _)| n == name)?;
        if !self.used.iter().any(|n| n == name) {
            self.used.push(name.to_string());
        }
        Some((c.2, c.3))
    }

    /// Record a drawn value (name, value in the parameter's own scale: a multiplier, a shift,
    /// 1/0 for presence); the study ranks what its answer depends on by them.
    pub fn record(&mut self, name: impl Into<String>, value: f64) {
        self.drawn.push((name.into(), value));
    }
}

impl Drawing<'_> {
    /// The drive data of joint `j` (0-based) of the robot being drawn, if it has drive data.
    pub fn joint(&mut self, j: usize) -> Option<&mut crate::robot::JointDrive> {
        self.robot.drive.as_mut()?.joints.get_mut(j)
    }

    /// The multiplier `(v + dv)⁺ / v` of an identified parameter `name` drawn with its
    /// standard error ([`Drawing::identified`]), or `None`.
    pub(crate) fn identified_factor(&mut self, name: &str) -> Option<f64> {
        self.identified(name)
            .map(|(v, dv)| (v + dv).max(0.0) / v.max(1e-300))
    }

    /// The multiplier of parameter `name`: identified ([`Drawing::identified_factor`]), else
    /// uniform in `1 ± rel`; recorded as `label`.
    pub fn factor(&mut self, name: &str, rel: f64, label: impl Into<String>) -> f64 {
        let f = match self.identified_factor(name) {
            Some(f) => f,
            None => 1.0 + rel * self.uniform(),
        };
        self.record(label, f);
        f
    }
}

/// An [`Uncertainty`] in `phase` at `rank` that leaves identified values to the study.
pub(crate) const fn at(phase: DrawPhase, rank: u32) -> Option<Uncertainty> {
    Some(Uncertainty {
        phase,
        rank,
        draws_identified: false,
    })
}
