//! One vocabulary of options: one clap `Args` struct per concern, flattened into every command
//! that needs it, so that an option has one name, one unit, one default and one meaning in
//! every command.
//!
//! - [`RobotArg`]: `--robot`, `--tool`
//! - [`PathArg`]: `--path`, `--path-units`, `--scale`
//! - [`AtArg`]: `--at`, `--spin` (where the path's part frame sits)
//! - [`TimingArgs`]: `--zone`, `--period`, `--accel`, `--jerk`
//! - [`FeasibilityArgs`]: `--no-collisions`, `--check-every`, the wrist, joint, elbow and
//!   shoulder margins
//! - [`EnergyArgs`]: `--regeneration`, `--no-payload`, `--no-friction`
//! - [`OutputArgs`]: `--out`, `--json`, `--force`

use anyhow::{bail, Context, Result};
use printwatt::energy::EnergyOptions;
use printwatt::evaluate::feasibility::FeasibilityOptions;
use printwatt::robot::{Regeneration, RobotModel};
use printwatt::timing::ProfileOptions;
use printwatt::toolpath::{Placement, ReadOptions, Zone};
use std::path::{Path, PathBuf};

/// The robot every command uses when `--robot` is not given.
pub const DEFAULT_ROBOT: &str = "abb_irb6700_200_260";

/// The robot.
#[derive(clap::Args, Debug, Clone)]
pub struct RobotArg {
    /// Robot: a shipped robot's name (`printwatt robots` lists them), a directory with
    /// robot.urdf (+ drive.toml), a .urdf file (rigid body only), or a drive .toml naming its
    /// URDF (e.g. a calibrated robot written by `identify`).
    #[arg(long, value_name = "NAME|PATH", default_value = DEFAULT_ROBOT)]
    pub robot: PathBuf,
    /// Tool preset replacing the robot's tool and payload (a .toml file, e.g.
    /// `presets/seed001_spindle.toml`). Default: the robot's own tool.
    #[arg(long, value_name = "FILE")]
    pub tool: Option<PathBuf>,
}

impl RobotArg {
    /// Load the robot (shipped name or path; a near-miss name gets "did you mean") with the
    /// tool preset applied; its warnings are shown.
    pub fn load(&self) -> Result<RobotModel> {
        let mut m = super::load_robot(&self.robot)?;
        if let Some(t) = &self.tool {
            printwatt::robot::apply_tool_preset(&mut m, t)?;
        }
        Ok(m)
    }
}

/// Where the path's part frame is placed in the robot base frame (one placement).
#[derive(clap::Args, Debug, Clone)]
pub struct AtArg {
    /// Placement of the path's part frame in the robot base frame: `x,y,z,yaw[,spin]` in m, m,
    /// m, deg, deg (z: height of the part origin, the nozzle tip on the bed). `sweep` and
    /// `optimise` take several separated by `;`.
    #[arg(long, value_name = "X,Y,Z,YAW[,SPIN]", allow_hyphen_values = true)]
    pub at: Option<String>,
    /// Nozzle rotation about its own vertical axis relative to the part, deg, added to each
    /// placement's own spin [default: 0]. `sweep` and `optimise` take a list or a range
    /// `min:max:step`.
    #[arg(long, value_name = "DEG", allow_hyphen_values = true)]
    pub spin: Option<String>,
}

impl AtArg {
    /// The one placement `--at` (+ `--spin`, one value) names; `None` without `--at`.
    pub fn one(&self) -> Result<Option<Placement>> {
        let Some(at) = &self.at else {
            if self.spin.is_some() {
                bail!("--spin needs --at x,y,z,yaw");
            }
            return Ok(None);
        };
        if at.contains(';') {
            bail!("--at `{at}`: this command evaluates one placement (use `printwatt sweep` for several)");
        }
        let mut p = Placement::parse(at).with_context(|| format!("--at `{at}`"))?;
        if let Some(s) = &self.spin {
            let v: f64 = s
                .trim()
                .parse()
                .ok()
                .filter(|v: &f64| v.is_finite())
                .with_context(|| format!("--spin `{s}`: expected one angle in deg"))?;
            if at.split(',').count() == 5 {
                bail!("--at `{at}` gives a nozzle spin and so does --spin {s}: give one");
            }
            p.nozzle_spin = v.to_radians();
        }
        check_metres(&p).with_context(|| format!("--at `{at}`"))?;
        Ok(Some(p))
    }
}

/// A placement whose position looks like millimetres where metres are expected: an error
/// with the hint ([`Placement::check_metres`]).
pub fn check_metres(p: &Placement) -> Result<()> {
    Ok(p.check_metres()?)
}

/// How the controller times the path.
#[derive(clap::Args, Debug, Clone)]
pub struct TimingArgs {
    /// Corner blend radius for G-code moves that give none, mm (RAPID zones are read from the
    /// file).
    #[arg(long, value_name = "MM", default_value_t = 5.0)]
    pub zone: f64,
    /// Interpolation period of the controller, ms (the sample period of the timed motion).
    #[arg(long, value_name = "MS", default_value_t = 4.0)]
    pub period: f64,
    /// TCP acceleration limit (along the path and lateral), m/s².
    #[arg(long, value_name = "M/S²", default_value_t = 1.0)]
    pub accel: f64,
    /// TCP jerk limit, m/s³.
    #[arg(long, value_name = "M/S³", default_value_t = 10.0)]
    pub jerk: f64,
}

impl TimingArgs {
    fn check(&self) -> Result<()> {
        for (opt, v) in [
            ("--zone", self.zone),
            ("--period", self.period),
            ("--accel", self.accel),
            ("--jerk", self.jerk),
        ] {
            super::finite(opt, v)?;
        }
        if self.zone < 0.0 {
            bail!("--zone {}: expected a blend radius >= 0 mm", self.zone);
        }
        for (opt, v, unit) in [
            ("--period", self.period, "ms"),
            ("--accel", self.accel, "m/s²"),
            ("--jerk", self.jerk, "m/s³"),
        ] {
            if v <= 0.0 {
                bail!("{opt} {v}: expected a value > 0 {unit}");
            }
        }
        if self.period < 0.1 {
            bail!(
                "--period {} ms: the interpolation period is far shorter than a controller's (0.5–12 ms); --period is in ms: did you mean {} ms?",
                self.period,
                self.period * 1000.0
            );
        }
        if self.period > 1000.0 {
            bail!(
                "--period {} ms: no controller interpolates that slowly; did you mean {} ms?",
                self.period,
                self.period / 1000.0
            );
        }
        Ok(())
    }

    /// The path reader's options (the default corner zone).
    pub fn read_options(&self) -> Result<ReadOptions> {
        self.check()?;
        Ok(ReadOptions {
            default_zone: Zone::Blend(self.zone * 1e-3),
            ..Default::default()
        })
    }

    /// The speed-profile options (SI).
    pub fn profile(&self) -> Result<ProfileOptions> {
        self.check()?;
        Ok(ProfileOptions {
            accel: self.accel,
            lateral_accel: self.accel,
            jerk: self.jerk,
            dt: self.period * 1e-3,
            ..Default::default()
        })
    }
}

/// How each placement is evaluated (parsed into [`printwatt::search::EvaluationMode`]).
#[derive(clap::Args, Debug, Clone)]
pub struct EvaluationArgs {
    /// `auto`: a long path (at least 200,000 samples) whose layers repeat up to a shift in z
    /// is evaluated on a few representative layers, the others interpolated over z with a
    /// stated error, and the answer re-evaluated in full; `full`: every sample of every
    /// placement; `reduced`: the reduction whenever layers repeat, whatever the length.
    #[arg(long, value_name = "MODE", default_value = "auto")]
    pub evaluation: String,
}

/// What the energy model includes.
#[derive(clap::Args, Debug, Clone)]
pub struct EnergyArgs {
    /// Regeneration policy, overriding the drive file's: `none` (braking energy lost),
    /// `per_axis`, `dc_bus` (shared between axes) or `grid` (returned). Default: the drive
    /// file's policy.
    #[arg(long, value_name = "POLICY")]
    pub regeneration: Option<Regeneration>,
    /// Leave the payload out.
    #[arg(long)]
    pub no_payload: bool,
    /// Leave friction out.
    #[arg(long)]
    pub no_friction: bool,
}

impl EnergyArgs {
    /// The energy model's options.
    pub fn options(&self) -> Result<EnergyOptions> {
        let mut opts = EnergyOptions {
            payload: !self.no_payload,
            friction: !self.no_friction,
            ..Default::default()
        };
        opts.regeneration = self.regeneration;
        Ok(opts)
    }
}

/// Where results go.
#[derive(clap::Args, Debug, Clone)]
pub struct OutputArgs {
    /// Directory for every file this command writes (created if missing; never an input's
    /// place). Default: the current directory for `energy`, `simulate` and `identify`; a new
    /// `results/runs/optimise-<robot>-<path>-<UTC time>/` for `optimise` and
    /// `results/runs/study-<name>-<UTC time>/` for `study`; no files for `sweep`, `compare`
    /// and `diagnose`. With --json and no --out, nothing but the JSON is
    /// written (except `identify`'s calibrated robot, its result).
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
    /// Print the result as JSON on stdout (shapes: docs/json.md).
    #[arg(long)]
    pub json: bool,
    /// Replace output files that exist already (never an input; a run directory holding
    /// files printwatt did not write is refused even then). Without it an existing output is
    /// an error.
    #[arg(long)]
    pub force: bool,
}

impl OutputArgs {
    /// The directory files go to: --out, else `default` unless this is a JSON run.
    pub fn dir(&self, default: Option<&Path>) -> Option<PathBuf> {
        match &self.out {
            Some(d) => Some(d.clone()),
            None if self.json => None,
            None => default.map(Path::to_path_buf),
        }
    }
}

/// An output directory that files are written into (beside whatever else it holds): it must
/// be a directory if it exists. Each file is checked against the inputs on its own.
pub fn check_out_dir(dir: &Path) -> Result<()> {
    if dir.exists() && !dir.is_dir() {
        bail!(
            "--out {}: exists and is not a directory (--out names a directory; the file names are fixed)",
            dir.display()
        );
    }
    Ok(())
}

/// The shipped robots' names (sub-directories of the robots directory), sorted.
pub fn shipped_robots() -> Vec<String> {
    printwatt::robot::shipped::names()
}

/// "did you mean" for a robot name that is neither a file nor a shipped robot: the nearest
/// shipped names (edit distance, or a shipped name containing what was typed) and the list.
pub fn robot_suggestion(arg: &Path) -> String {
    let typed = arg.to_string_lossy().to_ascii_lowercase();
    let names = shipped_robots();
    let mut near: Vec<(f64, &String)> = names
        .iter()
        .map(|n| {
            let score = if n.contains(typed.as_str()) && typed.len() >= 3 {
                1.0
            } else {
                strsim::normalized_damerau_levenshtein(&typed, n)
            };
            (score, n)
        })
        .filter(|(s, _)| *s >= 0.6)
        .collect();
    near.sort_by(|a, b| b.0.total_cmp(&a.0).then(a.1.cmp(b.1)));
    let mut s = String::new();
    if !near.is_empty() {
        let list: Vec<String> = near.iter().map(|(_, n)| format!("`{n}`")).collect();
        s.push_str(&format!("did you mean {}? ", list.join(" or ")));
    }
    s.push_str(&format!(
        "Shipped robots: {} (`printwatt robots`); or give a robot directory, a .urdf or a drive .toml",
        names.join(", ")
    ));
    s
}

/// The toolpath.
#[derive(clap::Args, Debug, Clone)]
pub struct PathArg {
    /// Toolpath in its part frame: G-code, CSV of points or an ABB RAPID module. Default:
    /// `paths/default.gcode` (for `simulate`: none; give --path, --trajectory or --excite).
    #[arg(long, value_name = "FILE")]
    pub path: Option<PathBuf>,
    /// Length unit of a CSV path's x, y, z columns written without one (`x`, not `x[mm]`);
    /// unlabelled speeds follow it per second. Without it such a file is read in mm, with a
    /// warning that mm was assumed. A unit in the header wins. G-code and RAPID state their
    /// own units and refuse it.
    #[arg(long, value_name = "mm|m")]
    pub path_units: Option<String>,
    /// RAPID: the procedure to read as the entry instead of `main`, for a module whose main
    /// chooses its path at run time (an IF on an input); the reader lists the procedures when
    /// it cannot decide. Other formats refuse it.
    #[arg(long = "proc", value_name = "NAME")]
    pub proc_name: Option<String>,
    /// Factor applied to the path's geometry after its units are read (points, arcs; not
    /// speeds), e.g. 0.5 to print a half-size part.
    #[arg(long, value_name = "FACTOR", default_value_t = 1.0)]
    pub scale: f64,
}

impl PathArg {
    /// The path reader's options: the timing's (default corner zone) with the path units
    /// and scale.
    pub fn read_options(&self, timing: &TimingArgs) -> Result<ReadOptions> {
        let mut o = timing.read_options()?;
        if let Some(u) = &self.path_units {
            o.path_units = Some(
                printwatt::toolpath::PathUnits::parse(u)
                    .with_context(|| format!("--path-units `{u}`"))?,
            );
        }
        if !(self.scale.is_finite() && self.scale > 0.0) {
            bail!("--scale {}: expected a finite factor > 0", self.scale);
        }
        o.scale = self.scale;
        o.proc = self.proc_name.clone();
        Ok(o)
    }

    /// The path file, the shipped default when none is given.
    pub fn file(&self) -> PathBuf {
        self.path
            .clone()
            .unwrap_or_else(|| super::sweep::shipped("paths/default.gcode"))
    }
}

/// Which feasibility checks a placement must pass (the same in `energy --at`, `sweep` and
/// `optimise`).
#[derive(clap::Args, Debug, Clone)]
pub struct FeasibilityArgs {
    /// Skip collision checks.
    #[arg(long)]
    pub no_collisions: bool,
    /// Check singularities and collisions every k-th sample.
    #[arg(long, default_value_t = 10)]
    pub check_every: usize,
    /// |sin q5| below which a sample is near the wrist singularity; there joints 4 and 6 may
    /// use at most --wrist-rate-max of their velocity/acceleration limits.
    #[arg(long, default_value_t = 0.05)]
    pub wrist_min: f64,
    /// Largest share of the joint 4/6 velocity or acceleration limit near the wrist
    /// singularity (0.5 = half).
    #[arg(long, default_value_t = printwatt::evaluate::feasibility::margins::DEFAULT_WRIST_RATE_MAX)]
    pub wrist_rate_max: f64,
    /// Distance kept from the wrist singularity, deg: on every sample q5 stays at least this
    /// far from 0 and ±180°. 0 lets the wrist pass through it (a round nozzle whose q6 is
    /// free); the RAPID export then sets `SingArea \Wrist`.
    #[arg(long, value_name = "DEG", default_value_t = printwatt::evaluate::feasibility::margins::DEFAULT_WRIST_MARGIN_DEG)]
    pub wrist_margin: f64,
    /// Margin kept from every joint's position limits, deg: one value for all joints or a
    /// comma list per joint (the drive file's `limit_margin_rad` takes precedence).
    #[arg(long, default_value = "3")]
    pub joint_margin: String,
    /// Smallest elbow measure accepted, |sin q3'| (dimensionless, 0…1; 0 switches the check
    /// off): how far the arm is from being stretched straight or folded.
    #[arg(long, default_value_t = 0.05)]
    pub elbow_min: f64,
    /// Smallest wrist-centre distance from axis 1 accepted, m.
    #[arg(long, default_value_t = 0.10)]
    pub shoulder_min: f64,
}

impl FeasibilityArgs {
    /// The library's feasibility options for a robot of `dof` joints.
    pub fn options(&self, dof: usize) -> Result<FeasibilityOptions> {
        for (opt, v) in [
            ("--wrist-min", self.wrist_min),
            ("--elbow-min", self.elbow_min),
            ("--shoulder-min", self.shoulder_min),
        ] {
            if !(v.is_finite() && v >= 0.0) {
                bail!("{opt} {v}: expected a finite margin >= 0 (0 switches the check off)");
            }
        }
        if self.check_every == 0 {
            bail!("--check-every must be at least 1");
        }
        let margins = printwatt::search::parse_range("joint-margin", &self.joint_margin)?;
        if margins.iter().any(|m| *m < 0.0 || *m > 90.0) {
            bail!(
                "--joint-margin `{}`: margins must lie in [0, 90] deg",
                self.joint_margin
            );
        }
        if margins.len() != 1 && margins.len() != dof {
            bail!(
                "--joint-margin `{}`: give one margin or {dof} (one per joint)",
                self.joint_margin
            );
        }
        let mut joint_margin_rad = [0.0; printwatt::kinematics::MAX_DOF];
        for (j, m) in joint_margin_rad.iter_mut().enumerate() {
            *m = margins
                .get(j)
                .or(margins.last())
                .copied()
                .unwrap_or(0.0)
                .to_radians();
        }
        if !(self.wrist_rate_max > 0.0 && self.wrist_rate_max.is_finite()) {
            bail!("--wrist-rate-max must be > 0");
        }
        let feas = FeasibilityOptions {
            wrist_min: self.wrist_min,
            wrist_rate_max: self.wrist_rate_max,
            wrist_margin_rad: self.wrist_margin.to_radians(),
            joint_margin_rad,
            elbow_min: self.elbow_min,
            shoulder_min_m: self.shoulder_min,
            collisions: !self.no_collisions,
            check_every: self.check_every,
            ..Default::default()
        };
        feas.check()?;
        Ok(feas)
    }
}
