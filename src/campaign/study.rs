//! Design studies: every toolpath of a building (walls, columns, floors) on several robots and
//! in several cells, each case optimised on its own, and the answers put side by side: which
//! robot and cell prints each path for the least energy, and which robot-and-cell combination
//! prints all of them.
//!
//! A study is read from a TOML file ([`Study::read`]; the format is in `docs/study.md`):
//!
//! ```toml
//! [study]
//! name = "house-a"
//!
//! [[robot]]
//! name = "irb6700"
//! robot = "abb_irb6700_200_260"      # a shipped robot's name or a path
//!
//! [[cell]]
//! name = "bay"
//! x = "0.9:2.5:0.1"                  # where the part may go, m (the command line's syntax)
//! y = "-1.5:1.5:0.1"
//! yaw = "0,90"                       # deg
//!
//! [[path]]
//! name = "wall-1"
//! file = "../paths/default.gcode"    # relative to the study file
//! ```
//!
//! The cases are every robot × cell × path, in that nesting order (robot slowest), unless
//! `[[case]]` entries list them. A case's answer ([`CaseResult`]) depends on its inputs alone,
//! so a study splits into shards by case index ([`crate::campaign::shard`]) and merges bit for bit.
//!
//! Units: positions m, angles in the file's text as the command line takes them (deg); every
//! number of a result is SI (m, rad, J, s) unless its name says otherwise.

use crate::error::{Error, Result};
use crate::evaluate::evaluator::{Feasible, Objective};
use crate::report::placement::RunReport;
use crate::search::run::{error_text, tolerance_line};
use crate::search::{Observer, OptimiseConfig, OptimiseOutcome};
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// Most cases a study may hold.
pub const MAX_CASES: usize = 10_000;

/// A number or a text in the study file (a cell's `x = 1.5` or `x = "0.9:2.5:0.1"`), kept as
/// the text the command line would take.
#[derive(Clone, Debug, Deserialize)]
#[serde(untagged)]
enum Spec {
    Int(i64),
    Num(f64),
    Text(String),
}

impl Spec {
    fn text(&self) -> String {
        match self {
            Spec::Int(i) => i.to_string(),
            Spec::Num(v) => v.to_string(),
            Spec::Text(s) => s.clone(),
        }
    }
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct FileToml {
    study: HeaderToml,
    #[serde(default)]
    robot: Vec<RobotToml>,
    #[serde(default)]
    cell: Vec<CellToml>,
    #[serde(default)]
    path: Vec<PathToml>,
    #[serde(default)]
    case: Vec<CaseToml>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct HeaderToml {
    name: String,
    #[serde(default)]
    description: Option<String>,
    #[serde(default)]
    options: Vec<String>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RobotToml {
    name: String,
    robot: String,
    #[serde(default)]
    tool: Option<String>,
    #[serde(default)]
    options: Vec<String>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct CellToml {
    name: String,
    #[serde(default)]
    x: Option<Spec>,
    #[serde(default)]
    y: Option<Spec>,
    #[serde(default)]
    z: Option<Spec>,
    #[serde(default)]
    yaw: Option<Spec>,
    #[serde(default)]
    spin: Option<Spec>,
    #[serde(default)]
    z_bounds: Option<String>,
    #[serde(default)]
    baseline: Option<String>,
    #[serde(default)]
    set: Option<String>,
    #[serde(default)]
    options: Vec<String>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct PathToml {
    name: String,
    file: String,
    #[serde(default)]
    options: Vec<String>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct CaseToml {
    robot: String,
    cell: String,
    path: String,
}

/// A robot of the study.
#[derive(Clone, Debug, PartialEq)]
pub struct StudyRobot {
    /// Its name in the study (letters, digits, `-`, `_`, `.`).
    pub name: String,
    /// The robot: a path (resolved against the study file's directory when it exists there)
    /// or a shipped robot's name, as given.
    pub robot: PathBuf,
    /// Tool preset file (resolved against the study file's directory).
    pub tool: Option<PathBuf>,
    /// Further options of this robot's cases (the optimise command line's syntax).
    pub options: Vec<String>,
}

/// A cell: where in the robot's workspace the part may be placed, and how the search runs
/// there. Every field is optional and in the command line's syntax (`x`, `y`, `z`: m; `yaw`,
/// `spin`: deg; `z_bounds`: `min:max` m; `baseline`: `x,y,z,yaw`; `set`: a named placements
/// CSV); a missing one takes the command's default.
#[derive(Clone, Debug, PartialEq, Default)]
pub struct StudyCell {
    /// Its name in the study.
    pub name: String,
    /// `(option, value)` pairs, in a fixed order: `x`, `y`, `z`, `yaw`, `spin`, `z-bounds`,
    /// `baseline`, `set`.
    pub placement: Vec<(&'static str, String)>,
    /// Further options of this cell's cases.
    pub options: Vec<String>,
}

/// A toolpath of the study.
#[derive(Clone, Debug, PartialEq)]
pub struct StudyPath {
    /// Its name in the study.
    pub name: String,
    /// The path file (resolved against the study file's directory).
    pub file: PathBuf,
    /// Further options of this path's cases (e.g. its corner zone, timing).
    pub options: Vec<String>,
}

/// One case: a robot, a cell and a path of the study (indices into its lists).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Case {
    /// Index of the case in the study (0-based), the order of every table.
    pub index: usize,
    /// Index into [`Study::robots`].
    pub robot: usize,
    /// Index into [`Study::cells`].
    pub cell: usize,
    /// Index into [`Study::paths`].
    pub path: usize,
}

/// A design study read from its file.
#[derive(Clone, Debug, PartialEq)]
pub struct Study {
    /// The study's name.
    pub name: String,
    /// Free text shown in the report.
    pub description: Option<String>,
    /// The study file, as named.
    pub file: PathBuf,
    /// Options of every case (e.g. `--objective`, `--max-evals`).
    pub options: Vec<String>,
    /// The robots.
    pub robots: Vec<StudyRobot>,
    /// The cells.
    pub cells: Vec<StudyCell>,
    /// The paths.
    pub paths: Vec<StudyPath>,
    /// The cases, in study order.
    pub cases: Vec<Case>,
}

/// A cell's `z_bounds`: `min:max` in m, finite, min <= max (as `optimise --z-bounds`).
fn check_z_bounds(s: &str) -> std::result::Result<(), String> {
    let v: Option<Vec<f64>> = s
        .split(':')
        .map(|t| t.trim().parse::<f64>().ok().filter(|v| v.is_finite()))
        .collect();
    match v.as_deref() {
        Some([a, b]) if a <= b => Ok(()),
        Some([_, _]) => Err(format!("`{s}`: expected min:max with min <= max (m)")),
        _ => Err(format!("`{s}`: expected min:max, two finite numbers in m")),
    }
}

/// An `options` list (`what`: which entry's) holding a number that is not finite (`nan`,
/// `inf`, alone or in a list such as `--tolerance nan,1`): no option of a case takes one.
fn check_option_numbers(options: &[String], what: &str) -> std::result::Result<(), String> {
    for o in options {
        let value = match o.split_once('=') {
            Some((flag, v)) if flag.starts_with("--") => v,
            _ if o.starts_with("--") => continue,
            _ => o.as_str(),
        };
        for t in value.split([',', ':']) {
            if t.trim().parse::<f64>().is_ok_and(|v| !v.is_finite()) {
                return Err(format!(
                    "{what}: `{o}`: `{}` is not a finite number",
                    t.trim()
                ));
            }
        }
    }
    Ok(())
}

/// A name in a study: 1 to 40 characters, letters, digits, `-`, `_`, `.`, starting with a
/// letter or digit (it becomes part of a file name).
fn check_name(what: &str, name: &str) -> Result<()> {
    let ok = !name.is_empty()
        && name.len() <= 40
        && name
            .chars()
            .next()
            .is_some_and(|c| c.is_ascii_alphanumeric())
        && name
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || matches!(c, '-' | '_' | '.'));
    if ok {
        Ok(())
    } else {
        Err(Error::Invalid(format!(
            "{what} name `{name}`: use 1 to 40 letters, digits, `-`, `_` or `.`, starting with a letter or digit (it becomes part of a file name)"
        )))
    }
}

/// A study file's path `s` resolved against the study file's directory `dir`.
fn resolve(dir: &Path, s: &str) -> PathBuf {
    let p = Path::new(s);
    if p.is_absolute() {
        p.to_path_buf()
    } else {
        dir.join(p)
    }
}

/// Every name of the study, its robots, cells and paths well-formed, each kind present and
/// its names unique.
fn check_names(t: &FileToml, err: &impl Fn(String) -> Error) -> Result<()> {
    check_name("study", &t.study.name).map_err(|e| err(e.to_string()))?;
    for (kind, names) in [
        ("robot", t.robot.iter().map(|r| &r.name).collect::<Vec<_>>()),
        ("cell", t.cell.iter().map(|c| &c.name).collect()),
        ("path", t.path.iter().map(|p| &p.name).collect()),
    ] {
        if names.is_empty() {
            return Err(err(format!(
                "no `[[{kind}]]` entry: a study needs at least one robot, one cell and one path"
            )));
        }
        let mut seen = std::collections::HashSet::new();
        for n in &names {
            check_name(kind, n).map_err(|e| err(e.to_string()))?;
            if !seen.insert(*n) {
                return Err(err(format!("{kind} `{n}` is defined twice")));
            }
        }
    }
    Ok(())
}

/// Values the cases' command lines would refuse fail the study here, before any work,
/// naming the file, the entry and the key (a case that cannot run is not an answer).
fn check_values(t: &FileToml, err: &impl Fn(String) -> Error) -> Result<()> {
    check_option_numbers(&t.study.options, "[study] options").map_err(err)?;
    for r in &t.robot {
        check_option_numbers(&r.options, &format!("robot `{}` options", r.name)).map_err(err)?;
    }
    for c in &t.cell {
        let at = |key: &str| format!("cell `{}` {key}", c.name);
        if let Some(z) = &c.z_bounds {
            check_z_bounds(z).map_err(|m| err(format!("{}: {m}", at("z_bounds"))))?;
        }
        if let Some(b) = &c.baseline {
            crate::frame::Placement::parse(b).map_err(|e| {
                err(format!(
                    "{} `{b}`: {e} (expected x,y,z,yaw[,spin] in m and deg)",
                    at("baseline")
                ))
            })?;
        }
        check_option_numbers(&c.options, &at("options")).map_err(err)?;
    }
    for p in &t.path {
        check_option_numbers(&p.options, &format!("path `{}` options", p.name)).map_err(err)?;
    }
    Ok(())
}

/// The number of cases before any is built: a study of 10⁴ robots, cells and paths is
/// refused without building 10¹² cases.
fn check_case_count(t: &FileToml, err: &impl Fn(String) -> Error) -> Result<()> {
    let n_cases = if t.case.is_empty() {
        t.robot
            .len()
            .checked_mul(t.cell.len())
            .and_then(|n| n.checked_mul(t.path.len()))
            .unwrap_or(usize::MAX)
    } else {
        t.case.len()
    };
    if n_cases > MAX_CASES {
        let n = if n_cases == usize::MAX {
            "more than 2^64".to_string()
        } else {
            n_cases.to_string()
        };
        return Err(err(format!(
            "{n} cases: at most {MAX_CASES}; split the study"
        )));
    }
    Ok(())
}

/// The study's robots, their files resolved (a robot that is not a file or directory beside
/// the study is taken as a shipped robot's name).
fn study_robots(robots: Vec<RobotToml>, dir: &Path) -> Vec<StudyRobot> {
    robots
        .into_iter()
        .map(|r| {
            let local = resolve(dir, &r.robot);
            StudyRobot {
                robot: if local.exists() {
                    local
                } else {
                    PathBuf::from(&r.robot)
                },
                tool: r.tool.as_deref().map(|s| resolve(dir, s)),
                name: r.name,
                options: r.options,
            }
        })
        .collect()
}

/// The study's cells, each with its placement options in command-line order.
fn study_cells(cells: Vec<CellToml>, dir: &Path) -> Vec<StudyCell> {
    cells
        .into_iter()
        .map(|c| {
            let mut placement = Vec::new();
            for (k, v) in [
                ("x", c.x.as_ref().map(Spec::text)),
                ("y", c.y.as_ref().map(Spec::text)),
                ("z", c.z.as_ref().map(Spec::text)),
                ("yaw", c.yaw.as_ref().map(Spec::text)),
                ("spin", c.spin.as_ref().map(Spec::text)),
                ("z-bounds", c.z_bounds.clone()),
                ("baseline", c.baseline.clone()),
                (
                    "set",
                    c.set
                        .as_deref()
                        .map(|s| resolve(dir, s).display().to_string()),
                ),
            ] {
                if let Some(v) = v {
                    placement.push((k, v));
                }
            }
            StudyCell {
                name: c.name,
                placement,
                options: c.options,
            }
        })
        .collect()
}

/// The `[[case]]` entries as (robot, cell, path) indices: every name defined, no case twice.
fn named_cases(
    case: &[CaseToml],
    robots: &[StudyRobot],
    cells: &[StudyCell],
    paths: &[StudyPath],
    err: &impl Fn(String) -> Error,
) -> Result<Vec<(usize, usize, usize)>> {
    let index = |names: Vec<&String>| -> std::collections::HashMap<String, usize> {
        names
            .into_iter()
            .enumerate()
            .map(|(i, n)| (n.clone(), i))
            .collect()
    };
    let robot_names: Vec<&String> = robots.iter().map(|r| &r.name).collect();
    let cell_names: Vec<&String> = cells.iter().map(|c| &c.name).collect();
    let path_names: Vec<&String> = paths.iter().map(|p| &p.name).collect();
    let robot_ix = index(robot_names.clone());
    let cell_ix = index(cell_names.clone());
    let path_ix = index(path_names.clone());
    let mut seen = std::collections::HashMap::new();
    let mut cases = Vec::new();
    for (k, c) in case.iter().enumerate() {
        let find = |kind: &str,
                    ix: &std::collections::HashMap<String, usize>,
                    names: &[&String],
                    n: &str| {
            ix.get(n).copied().ok_or_else(|| {
                err(format!(
                    "[[case]] {} names {kind} `{n}`, which no [[{kind}]] defines (defined: {})",
                    k + 1,
                    names
                        .iter()
                        .map(|s| s.as_str())
                        .collect::<Vec<_>>()
                        .join(", ")
                ))
            })
        };
        let r = find("robot", &robot_ix, &robot_names, &c.robot)?;
        let ce = find("cell", &cell_ix, &cell_names, &c.cell)?;
        let p = find("path", &path_ix, &path_names, &c.path)?;
        if let Some(j) = seen.insert((r, ce, p), k) {
            return Err(err(format!(
                "[[case]] {} ({} / {} / {}) repeats [[case]] {}",
                k + 1,
                c.robot,
                c.cell,
                c.path,
                j + 1
            )));
        }
        cases.push((r, ce, p));
    }
    Ok(cases)
}

impl Study {
    /// Read and check a study file: every name well-formed and unique within its kind, every
    /// case's names defined, no case listed twice, at least one case, at most [`MAX_CASES`].
    /// Files are resolved against the study file's directory (a robot that is not a file or
    /// directory there is taken as a shipped robot's name). Errors name the file (and the
    /// line, for TOML errors) and the entry at fault.
    pub fn read(file: &Path) -> Result<Study> {
        let text = crate::error::read_text(file)?;
        Study::parse(&text, file)
    }

    /// [`Study::read`] of a study file's text; `file` names it and anchors relative paths.
    pub fn parse(text: &str, file: &Path) -> Result<Study> {
        let f = file.display();
        let t: FileToml = toml::from_str(text).map_err(|e| {
            let at = e
                .span()
                .map(|s| format!(" (line {})", text[..s.start].lines().count().max(1)))
                .unwrap_or_default();
            Error::Invalid(format!(
                "{f}{at}: not a printwatt study file: {}",
                e.message()
            ))
        })?;
        let dir = match file.parent() {
            Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
            _ => PathBuf::new(),
        };
        let err = |m: String| Error::Invalid(format!("{f}: {m}"));
        check_names(&t, &err)?;
        check_values(&t, &err)?;
        check_case_count(&t, &err)?;
        let robots = study_robots(t.robot, &dir);
        let cells = study_cells(t.cell, &dir);
        let paths: Vec<StudyPath> = t
            .path
            .into_iter()
            .map(|p| StudyPath {
                file: resolve(&dir, &p.file),
                name: p.name,
                options: p.options,
            })
            .collect();
        let cases = if t.case.is_empty() {
            let mut cases = Vec::new();
            for r in 0..robots.len() {
                for c in 0..cells.len() {
                    for p in 0..paths.len() {
                        cases.push((r, c, p));
                    }
                }
            }
            cases
        } else {
            named_cases(&t.case, &robots, &cells, &paths, &err)?
        };
        if cases.len() > MAX_CASES {
            return Err(err(format!(
                "{} cases: at most {MAX_CASES}; split the study",
                cases.len()
            )));
        }
        Ok(Study {
            name: t.study.name,
            description: t.study.description,
            file: file.to_path_buf(),
            options: t.study.options,
            robots,
            cells,
            paths,
            cases: cases
                .into_iter()
                .enumerate()
                .map(|(index, (robot, cell, path))| Case {
                    index,
                    robot,
                    cell,
                    path,
                })
                .collect(),
        })
    }

    /// A case's name: `robot / cell / path`.
    pub fn case_name(&self, c: &Case) -> String {
        format!(
            "{} / {} / {}",
            self.robots[c.robot].name, self.cells[c.cell].name, self.paths[c.path].name
        )
    }

    /// The file name of a case's report in the study directory:
    /// `case-<index>-<robot>-<cell>-<path>.html` (index zero-padded to the study's width).
    pub fn case_file(&self, c: &Case) -> String {
        let w = self.cases.len().saturating_sub(1).to_string().len();
        format!(
            "case-{:0w$}-{}-{}-{}.html",
            c.index, self.robots[c.robot].name, self.cells[c.cell].name, self.paths[c.path].name
        )
    }
}

/// The answer of one case.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct CaseResult {
    /// The objective minimised (its command-line name, e.g. `supply`).
    pub objective: String,
    /// The chosen placement, or why there is none (the case's error, in words).
    pub outcome: std::result::Result<CaseBest, String>,
    /// Placements on the case's grid (or set).
    pub grid: usize,
    /// Feasible placements among them.
    pub grid_feasible: usize,
    /// Evaluations the answer needed (grid, refinement, tolerance corners, sensitivity).
    pub evaluations: usize,
    /// SHA-256 (hex) of the case's optimise report page (self-contained HTML), when the case
    /// has an answer; the page itself is written beside the results as it is made
    /// ([`Study::case_file`]), so that a study holds one page in memory at a time.
    pub report_sha256: Option<String>,
}

impl CaseResult {
    /// The result of a case from its optimisation (`grid`: placements of the case's grid):
    /// the answer, or the optimisation's error in words (no feasible placement, a reduced
    /// answer infeasible in full, …), with the case's report page when it has an answer. The
    /// result is the one a shard carries ([`CaseResult::as_stored`]).
    pub fn of(
        objective: Objective,
        grid: usize,
        outcome: Result<OptimiseOutcome>,
    ) -> Result<(CaseResult, Option<String>)> {
        let objective = objective.name().to_string();
        let mut page = None;
        let r = match outcome {
            Ok(c) => {
                let rep = &c.report;
                let best = rep.best().ok_or_else(|| {
                    Error::Invalid("the optimisation returned no placement".into())
                })?;
                let f = best.feasible().ok_or_else(|| {
                    Error::Invalid("the optimisation's answer is infeasible".into())
                })?;
                let p = &best.placement;
                let si = rep.optimise.as_ref().and_then(|o| o.search.as_ref());
                let base_tol = baseline_tolerance(rep);
                let notes = answer_notes(rep);
                CaseResult {
                    objective,
                    outcome: Ok(CaseBest {
                        placement: [p.x, p.y, p.z, p.yaw, p.nozzle_spin],
                        feasible: f.clone(),
                        baseline_j: rep
                            .baseline
                            .as_ref()
                            .map(|(_, b)| b.cost())
                            .filter(|c| c.is_finite()),
                        baseline_holds_tolerance: base_tol.map(|t| t.holds),
                        tolerance: si.map(|si| tolerance_line(&si.tolerance)),
                        notes,
                        robust: case_robust(rep),
                    }),
                    grid: rep.rows.len(),
                    grid_feasible: rep.rows.iter().filter(|r| r.cost().is_finite()).count(),
                    evaluations: c.evaluations,
                    report_sha256: Some(crate::output::sha256_hex(
                        page.insert(rep.html()).as_bytes(),
                    )),
                }
            }
            Err(e) => CaseResult {
                objective,
                outcome: Err(error_text(&e)),
                grid,
                grid_feasible: 0,
                evaluations: grid,
                report_sha256: None,
            },
        };
        // Exactly what a shard carries, so that a single run and a merge write the same files.
        Ok((r.as_stored()?, page))
    }
}

/// The answer's notes: a tolerance that does not hold, an optimum on a search bound or a
/// joint-limit margin, a spent search budget, a baseline that does not hold the tolerance.
fn answer_notes(rep: &RunReport) -> Vec<String> {
    let si = rep.optimise.as_ref().and_then(|o| o.search.as_ref());
    let mut notes = Vec::new();
    if let Some(si) = si {
        if !si.tolerance.holds && si.tolerance.corners > 0 {
            notes.push(format!("tolerance {}", tolerance_line(&si.tolerance)));
        }
        if !si.on_bounds.is_empty() {
            notes.push(format!(
                "optimum on a search bound: {}",
                si.on_bounds.join(", ")
            ));
        }
        if let Some(om) = &si.on_margin {
            notes.push(format!("optimum on a joint-limit margin: {om}"));
        }
        if let Some(b) = &si.budget_spent {
            notes.push(format!("search stopped: {b}"));
        }
    }
    let base_tol = baseline_tolerance(rep);
    if let Some(t) = base_tol.filter(|t| !t.holds) {
        notes.push(format!(
            "the baseline does not hold the tolerance ({} of its {} corners infeasible): the saving is measured against a placement a site could not rely on",
            t.failures.len(),
            t.corners
        ));
    }
    notes
}

/// The baseline's tolerance study, when it has corners.
fn baseline_tolerance(rep: &RunReport) -> Option<&crate::search::tolerance::ToleranceCheck> {
    rep.optimise
        .as_ref()
        .and_then(|o| o.baseline_tolerance.as_ref())
        .filter(|t| t.corners > 0)
}

/// The robust recommendation of the answer, when the run made one.
fn case_robust(rep: &RunReport) -> Option<CaseRobust> {
    rep.optimise
        .as_ref()
        .and_then(|o| o.decision.as_ref())
        .and_then(|d| d.robust.as_ref())
        .map(|r| {
            let c = r.recommendation();
            let q = &c.placement;
            CaseRobust {
                placement: [q.x, q.y, q.z, q.yaw, q.nozzle_spin],
                expected_regret_j: c.expected_regret_j,
                p95_regret_j: c.p95_regret_j,
                p_within_1pct: c.p_within_1pct,
                nominal_expected_regret_j: r.nominal().expected_regret_j,
            }
        })
}

/// What a front end does with each answered case: the case, its result, its report page (when
/// it has an answer) and its wall time, s.
pub(crate) type CaseDone<'a> =
    dyn FnMut(&Case, &CaseResult, Option<String>, f64) -> Result<()> + 'a;

/// Run the cases `indices` of a study (in order), each optimised as its config says
/// (`config_of`: the case's job; an error there is the study's, an error of the optimisation
/// is the case's answer), in the caller's rayon pool. `done` receives each case as it is
/// answered, with its report page (when it has an answer) and its wall time (s).
pub fn run(
    study: &Study,
    indices: &[usize],
    config_of: &dyn Fn(&Case) -> Result<OptimiseConfig>,
    observer: &dyn Observer,
    done: &mut CaseDone<'_>,
) -> Result<Vec<CaseResult>> {
    let mut out = Vec::with_capacity(indices.len());
    for &k in indices {
        let t = std::time::Instant::now();
        let c = study.cases.get(k).ok_or_else(|| {
            Error::Invalid(format!(
                "case {k} of a study of {} cases",
                study.cases.len()
            ))
        })?;
        let in_case = |e: Error| {
            Error::Invalid(format!(
                "case {k} ({}): {}",
                study.case_name(c),
                error_text(&e)
            ))
        };
        let cfg = config_of(c).map_err(in_case)?;
        let grid = cfg.placement_set().placements.len();
        let outcome = crate::search::run(&cfg, observer);
        let (r, page) = CaseResult::of(cfg.settings.objective, grid, outcome).map_err(in_case)?;
        done(c, &r, page, t.elapsed().as_secs_f64())?;
        out.push(r);
    }
    Ok(out)
}

/// A case's chosen placement and its figures.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct CaseBest {
    /// x, y, z of the part origin (m), part yaw and nozzle spin (rad).
    pub placement: [f64; 5],
    /// The figures at the chosen placement (evaluated in full).
    pub feasible: Feasible,
    /// The objective's energy at the case's baseline placement, J, when there is one.
    pub baseline_j: Option<f64>,
    /// Whether the baseline holds the placement tolerance the answer holds (`None`: not
    /// checked, e.g. a zero tolerance). A saving against a baseline that does not hold it is
    /// measured against a placement a site could not rely on.
    pub baseline_holds_tolerance: Option<bool>,
    /// The placement tolerance check, in words.
    pub tolerance: Option<String>,
    /// Notes on the answer: an optimum on a search bound or a joint-limit margin, a search
    /// stopped by its budget.
    pub notes: Vec<String>,
    /// The robust choice (a case run with `--uncertainty N` and the Nelder–Mead search).
    pub robust: Option<CaseRobust>,
}

/// A case's robust choice over its plausible robots.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct CaseRobust {
    /// x, y, z (m), yaw and nozzle spin (rad) of the recommended placement.
    pub placement: [f64; 5],
    /// Its expected regret over the draws, J.
    pub expected_regret_j: f64,
    /// Its 95th-percentile regret, J.
    pub p95_regret_j: f64,
    /// Share of the draws in which it is within 1 % of the drives' energy of the draw's best.
    pub p_within_1pct: f64,
    /// The nominal answer's expected regret over the same draws, J.
    pub nominal_expected_regret_j: f64,
}

impl CaseResult {
    /// The objective's energy at the chosen placement, J; `None` without an answer.
    pub fn energy_j(&self) -> Option<f64> {
        self.outcome.as_ref().ok().map(|b| b.feasible.energy_j)
    }

    /// The same result as written to and read back from a shard (postcard): every number
    /// bit for bit, and only what a shard carries. A single run passes its results through
    /// this too, so that it and a merge of shards write the same files by construction.
    pub(crate) fn as_stored(&self) -> Result<CaseResult> {
        let bytes = postcard::to_stdvec(self)
            .map_err(|e| Error::Invalid(format!("encoding a case result: {e}")))?;
        postcard::from_bytes(&bytes)
            .map_err(|e| Error::Invalid(format!("decoding a case result: {e}")))
    }
}

/// The cheapest case of one path over every robot and cell it was tried on.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct PathBest {
    /// The path's name.
    pub path: String,
    /// Cases of this path.
    pub cases: usize,
    /// Cases with an answer.
    pub feasible: usize,
    /// Index of the cheapest case, when any has an answer.
    pub best_case: Option<usize>,
    /// Its robot and cell.
    pub best: Option<(String, String)>,
    /// Its energy, J.
    pub energy_j: Option<f64>,
    /// How much more the second-cheapest case needs, J and % of the cheapest.
    pub runner_up: Option<(usize, f64, f64)>,
}

/// One robot in one cell over every path of the study it was given.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Combination {
    /// Robot name.
    pub robot: String,
    /// Cell name.
    pub cell: String,
    /// Paths tried.
    pub paths: usize,
    /// Paths with an answer.
    pub feasible: usize,
    /// Names of the paths without an answer.
    pub infeasible: Vec<String>,
    /// Sum of the objective's energy over the paths with an answer, J.
    pub energy_j: f64,
    /// Sum of their print times, s.
    pub duration_s: f64,
    /// Sum of their supply energy, J.
    pub supply_j: f64,
}

/// The study's answers put together.
#[derive(Clone, Debug, PartialEq)]
pub struct StudyTables {
    /// Per path: the cheapest robot and cell.
    pub paths: Vec<PathBest>,
    /// Per robot and cell (in study order of first appearance): totals over its paths,
    /// complete ones (every path feasible) ranked first by energy.
    pub combinations: Vec<Combination>,
}

impl Study {
    /// Check that `results` (one per case, in case order) belong to this study and share one
    /// objective.
    pub(crate) fn check_results(&self, results: &[CaseResult]) -> Result<()> {
        if results.len() != self.cases.len() {
            return Err(Error::Invalid(format!(
                "{} results for {} cases",
                results.len(),
                self.cases.len()
            )));
        }
        if let Some((k, r)) = results
            .iter()
            .enumerate()
            .find(|(_, r)| r.objective != results[0].objective)
        {
            return Err(Error::Invalid(format!(
                "case {} ({}) minimises `{}`, case 0 ({}) `{}`: energies of different objectives cannot be compared; set the objective once, in [study] options",
                k,
                self.case_name(&self.cases[k]),
                r.objective,
                self.case_name(&self.cases[0]),
                results[0].objective
            )));
        }
        Ok(())
    }

    /// The per-path and per-combination tables of `results` (one per case, in case order).
    /// Ties are broken by case order, so the tables are deterministic.
    pub fn tables(&self, results: &[CaseResult]) -> Result<StudyTables> {
        self.check_results(results)?;
        let paths = self.path_bests(results);
        let combos = self.combinations(results);
        Ok(StudyTables {
            paths,
            combinations: combos,
        })
    }

    /// The best case of each path (cases answered, the best and the runner-up).
    fn path_bests(&self, results: &[CaseResult]) -> Vec<PathBest> {
        let mut paths = Vec::new();
        for (pi, p) in self.paths.iter().enumerate() {
            let mine: Vec<(&Case, &CaseResult)> = self
                .cases
                .iter()
                .zip(results)
                .filter(|(c, _)| c.path == pi)
                .collect();
            if mine.is_empty() {
                continue;
            }
            let mut ok: Vec<(usize, f64)> = mine
                .iter()
                .filter_map(|(c, r)| r.energy_j().map(|e| (c.index, e)))
                .collect();
            // Stable: equal energies keep case order.
            ok.sort_by(|a, b| a.1.total_cmp(&b.1));
            let best = ok.first().copied();
            paths.push(PathBest {
                path: p.name.clone(),
                cases: mine.len(),
                feasible: ok.len(),
                best_case: best.map(|b| b.0),
                best: best.map(|(i, _)| {
                    let c = &self.cases[i];
                    (
                        self.robots[c.robot].name.clone(),
                        self.cells[c.cell].name.clone(),
                    )
                }),
                energy_j: best.map(|b| b.1),
                runner_up: match (best, ok.get(1)) {
                    (Some((_, e0)), Some(&(i1, e1))) => {
                        Some((i1, e1 - e0, 100.0 * (e1 - e0) / e0.abs().max(1e-12)))
                    }
                    _ => None,
                },
            });
        }
        paths
    }

    /// The totals of each robot and cell over its paths, complete combinations first, then by
    /// energy.
    fn combinations(&self, results: &[CaseResult]) -> Vec<Combination> {
        let mut combos: Vec<Combination> = Vec::new();
        let mut keys: Vec<(usize, usize)> = Vec::new();
        for (c, r) in self.cases.iter().zip(results) {
            let k = match keys.iter().position(|k| *k == (c.robot, c.cell)) {
                Some(k) => k,
                None => {
                    keys.push((c.robot, c.cell));
                    combos.push(Combination {
                        robot: self.robots[c.robot].name.clone(),
                        cell: self.cells[c.cell].name.clone(),
                        paths: 0,
                        feasible: 0,
                        infeasible: Vec::new(),
                        energy_j: 0.0,
                        duration_s: 0.0,
                        supply_j: 0.0,
                    });
                    keys.len() - 1
                }
            };
            let m = &mut combos[k];
            m.paths += 1;
            match &r.outcome {
                Ok(b) => {
                    m.feasible += 1;
                    m.energy_j += b.feasible.energy_j;
                    m.duration_s += b.feasible.duration_s;
                    m.supply_j += b.feasible.supply_j;
                }
                Err(_) => m.infeasible.push(self.paths[c.path].name.clone()),
            }
        }
        // Complete combinations first (fewest paths without an answer), then by energy; the
        // sort is stable, so ties keep study order.
        combos.sort_by(|a, b| {
            (a.paths - a.feasible)
                .cmp(&(b.paths - b.feasible))
                .then(a.energy_j.total_cmp(&b.energy_j))
        });
        combos
    }

    /// `study.csv`: one row per case (SI units in the header; angles in deg as labelled).
    pub fn csv(&self, results: &[CaseResult]) -> Result<String> {
        self.check_results(results)?;
        let mut s = String::from(
            "case,robot,cell,path,status,x_m,y_m,z_m,yaw_deg,spin_deg,energy_j,supply_j,drives_j,standby_j,duration_s,baseline_j,saving_pct,baseline_holds_tolerance,grid,grid_feasible,evaluations,report,robust_x_m,robust_y_m,robust_z_m,robust_yaw_deg,robust_spin_deg,robust_expected_regret_j,robust_p95_regret_j,robust_p_within_1pct,nominal_expected_regret_j,note\n",
        );
        let q = |t: &str| {
            if t.contains([',', '"', '\n']) {
                format!("\"{}\"", t.replace('"', "\"\""))
            } else {
                t.to_string()
            }
        };
        for (c, r) in self.cases.iter().zip(results) {
            let head = format!(
                "{},{},{},{}",
                c.index,
                q(&self.robots[c.robot].name),
                q(&self.cells[c.cell].name),
                q(&self.paths[c.path].name)
            );
            let tail = format!("{},{},{}", r.grid, r.grid_feasible, r.evaluations);
            match &r.outcome {
                Ok(b) => {
                    let [x, y, z, yaw, spin] = b.placement;
                    let f = &b.feasible;
                    let (bj, sv) = match b.baseline_j {
                        Some(bj) => (
                            bj.to_string(),
                            (100.0 * (bj - f.energy_j) / bj.abs().max(1e-12)).to_string(),
                        ),
                        None => (String::new(), String::new()),
                    };
                    let bt = b
                        .baseline_holds_tolerance
                        .map_or(String::new(), |h| h.to_string());
                    let rb = b.robust.as_ref().map_or(",,,,,,,,".to_string(), |r| {
                        let [x, y, z, yaw, spin] = r.placement;
                        format!(
                            "{x},{y},{z},{},{},{},{},{},{}",
                            yaw.to_degrees(),
                            spin.to_degrees(),
                            r.expected_regret_j,
                            r.p95_regret_j,
                            r.p_within_1pct,
                            r.nominal_expected_regret_j
                        )
                    });
                    s.push_str(&format!(
                        "{head},feasible,{x},{y},{z},{},{},{},{},{},{},{},{bj},{sv},{bt},{tail},{},{rb},{}\n",
                        yaw.to_degrees(),
                        spin.to_degrees(),
                        f.energy_j,
                        f.supply_j,
                        f.drives_j,
                        f.standby_j,
                        f.duration_s,
                        q(&self.case_file(c)),
                        q(&b.notes.join("; "))
                    ));
                }
                Err(why) => s.push_str(&format!(
                    "{head},no answer,,,,,,,,,,,,,,{tail},,,,,,,,,,,{}\n",
                    q(why)
                )),
            }
        }
        Ok(s)
    }

    /// One case's entry of `summary.json`: its names, its answer or why there is none.
    fn case_json(&self, c: &Case, r: &CaseResult) -> serde_json::Value {
        let mut v = serde_json::json!({
            "case": c.index,
            "robot": self.robots[c.robot].name,
            "cell": self.cells[c.cell].name,
            "path": self.paths[c.path].name,
            "grid": r.grid,
            "grid_feasible": r.grid_feasible,
            "evaluations": r.evaluations,
        });
        match &r.outcome {
            Ok(b) => {
                let [x, y, z, yaw, spin] = b.placement;
                v["status"] = "feasible".into();
                v["placement"] = serde_json::json!({
                    "x_m": x, "y_m": y, "z_m": z,
                    "yaw_deg": yaw.to_degrees(), "spin_deg": spin.to_degrees(),
                });
                v["outcome"] = serde_json::to_value(&b.feasible).unwrap_or_default();
                v["baseline_j"] = serde_json::json!(b.baseline_j);
                v["baseline_holds_tolerance"] = serde_json::json!(b.baseline_holds_tolerance);
                v["tolerance"] = serde_json::json!(b.tolerance);
                v["notes"] = serde_json::json!(b.notes);
                v["robust"] = match &b.robust {
                    Some(r) => {
                        let [x, y, z, yaw, spin] = r.placement;
                        serde_json::json!({
                            "placement": {
                                "x_m": x, "y_m": y, "z_m": z,
                                "yaw_deg": yaw.to_degrees(), "spin_deg": spin.to_degrees(),
                            },
                            "expected_regret_j": r.expected_regret_j,
                            "p95_regret_j": r.p95_regret_j,
                            "p_within_1pct": r.p_within_1pct,
                            "nominal_expected_regret_j": r.nominal_expected_regret_j,
                        })
                    }
                    None => serde_json::Value::Null,
                };
                v["report"] = self.case_file(c).into();
            }
            Err(why) => {
                v["status"] = "no answer".into();
                v["reason"] = why.clone().into();
            }
        }
        v
    }

    /// `summary.json`'s value: the study, every case's answer (without its report page), the
    /// per-path and per-combination tables.
    pub fn summary(&self, results: &[CaseResult]) -> Result<serde_json::Value> {
        let t = self.tables(results)?;
        let cases: Vec<serde_json::Value> = self
            .cases
            .iter()
            .zip(results)
            .map(|(c, r)| self.case_json(c, r))
            .collect();
        Ok(serde_json::json!({
            "kind": "printwatt-study",
            "study": self.name,
            "description": self.description,
            "objective": results.first().map(|r| r.objective.clone()),
            "options": self.options,
            "robots": self.robots.iter().map(|r| serde_json::json!({
                "name": r.name,
                "robot": r.robot.display().to_string(),
                "tool": r.tool.as_ref().map(|t| t.display().to_string()),
                "options": r.options,
            })).collect::<Vec<_>>(),
            "cells": self.cells.iter().map(|c| serde_json::json!({
                "name": c.name,
                "placement": c.placement.iter().map(|(k, v)| (k.to_string(), serde_json::Value::from(v.clone()))).collect::<serde_json::Map<_, _>>(),
                "options": c.options,
            })).collect::<Vec<_>>(),
            "paths": self.paths.iter().map(|p| serde_json::json!({
                "name": p.name,
                "file": p.file.display().to_string(),
                "options": p.options,
            })).collect::<Vec<_>>(),
            "cases": cases,
            "best_per_path": t.paths,
            "combinations": t.combinations,
        }))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const STUDY: &str = r#"
[study]
name = "house-a"
options = ["--max-evals", "20"]

[[robot]]
name = "big"
robot = "abb_irb6700_200_260"

[[robot]]
name = "small"
robot = "abb_irb4600_40_255"

[[cell]]
name = "bay"
x = "0.9:2.5:0.4"
y = 0
yaw = 90.5

[[path]]
name = "wall-1"
file = "../paths/default.gcode"

[[path]]
name = "column"
file = "/abs/column.gcode"
"#;

    #[test]
    fn study_cases_are_every_robot_cell_and_path_in_nesting_order() {
        let s = Study::parse(STUDY, Path::new("studies/house.toml")).unwrap();
        let names: Vec<String> = s.cases.iter().map(|c| s.case_name(c)).collect();
        assert_eq!(
            names,
            [
                "big / bay / wall-1",
                "big / bay / column",
                "small / bay / wall-1",
                "small / bay / column"
            ]
        );
        assert_eq!(s.paths[0].file, Path::new("studies/../paths/default.gcode"));
        assert_eq!(s.paths[1].file, Path::new("/abs/column.gcode"));
        // A shipped robot's name is kept as a name (no such path beside the study).
        assert_eq!(s.robots[0].robot, Path::new("abb_irb6700_200_260"));
        assert_eq!(
            s.cells[0].placement,
            vec![
                ("x", "0.9:2.5:0.4".to_string()),
                ("y", "0".to_string()),
                ("yaw", "90.5".to_string())
            ]
        );
        assert_eq!(s.case_file(&s.cases[3]), "case-3-small-bay-column.html");
    }

    #[test]
    fn study_file_errors_name_the_line_or_the_entry_at_fault() {
        let f = Path::new("s.toml");
        let e = Study::parse("[study]\nname = \"a\"\n[[robot]]\nnme = \"x\"\n", f)
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("s.toml (line 3") || e.contains("s.toml (line 4"),
            "{e}"
        );
        let dup = STUDY.replace("name = \"column\"", "name = \"wall-1\"");
        let e = Study::parse(&dup, f).unwrap_err().to_string();
        assert!(e.contains("path `wall-1` is defined twice"), "{e}");
        let bad = STUDY.replace("name = \"bay\"", "name = \"bay/1\"");
        let e = Study::parse(&bad, f).unwrap_err().to_string();
        assert!(e.contains("cell name `bay/1`"), "{e}");
        let case =
            format!("{STUDY}\n[[case]]\nrobot = \"big\"\ncell = \"bay\"\npath = \"wal-1\"\n");
        let e = Study::parse(&case, f).unwrap_err().to_string();
        assert!(
            e.contains("[[case]] 1 names path `wal-1`, which no [[path]] defines (defined: wall-1, column)"),
            "{e}"
        );
        let twice = format!(
            "{STUDY}\n[[case]]\nrobot = \"big\"\ncell = \"bay\"\npath = \"column\"\n[[case]]\nrobot = \"big\"\ncell = \"bay\"\npath = \"column\"\n"
        );
        let e = Study::parse(&twice, f).unwrap_err().to_string();
        assert!(
            e.contains("[[case]] 2 (big / bay / column) repeats [[case]] 1"),
            "{e}"
        );
        let none = "[study]\nname = \"a\"\n[[robot]]\nname = \"r\"\nrobot = \"x\"\n";
        let e = Study::parse(none, f).unwrap_err().to_string();
        assert!(e.contains("no `[[cell]]` entry"), "{e}");
    }

    #[test]
    fn listed_cases_are_kept_in_the_order_given() {
        let s = Study::parse(
            &format!(
                "{STUDY}\n[[case]]\nrobot = \"small\"\ncell = \"bay\"\npath = \"column\"\n[[case]]\nrobot = \"big\"\ncell = \"bay\"\npath = \"wall-1\"\n"
            ),
            Path::new("s.toml"),
        )
        .unwrap();
        let names: Vec<String> = s.cases.iter().map(|c| s.case_name(c)).collect();
        assert_eq!(names, ["small / bay / column", "big / bay / wall-1"]);
    }

    fn result(e: Option<f64>) -> CaseResult {
        CaseResult {
            objective: "supply".into(),
            outcome: match e {
                Some(e) => Ok(CaseBest {
                    placement: [1.0, 0.0, 0.0, 0.0, 0.0],
                    feasible: Feasible {
                        energy_j: e,
                        supply_j: e,
                        drives_j: e,
                        standby_j: 0.0,
                        mechanical_j: e,
                        mechanical_positive_j: e,
                        mechanical_abs_j: e,
                        electrical_j: e,
                        losses: Default::default(),
                        duration_s: 10.0,
                        samples: 2500,
                        rounds: 1,
                        joint_mechanical_j: vec![e / 6.0; 6],
                        joint_mechanical_abs_j: vec![e / 6.0; 6],
                        joint_electrical_j: vec![e / 6.0; 6],
                        margins: Default::default(),
                        path_reduction: None,
                    },
                    baseline_j: Some(e * 1.1),
                    baseline_holds_tolerance: Some(false),
                    tolerance: None,
                    notes: vec![],
                    robust: None,
                }),
                None => Err("unreachable".into()),
            },
            grid: 4,
            grid_feasible: 2,
            evaluations: 30,
            report_sha256: None,
        }
    }

    #[test]
    fn study_tables_rank_the_cheapest_robot_per_path_and_complete_combinations_first() {
        let s = Study::parse(STUDY, Path::new("s.toml")).unwrap();
        // big: wall 100, column none; small: wall 120, column 50.
        let r = vec![
            result(Some(100.0)),
            result(None),
            result(Some(120.0)),
            result(Some(50.0)),
        ];
        let t = s.tables(&r).unwrap();
        assert_eq!(t.paths[0].best, Some(("big".into(), "bay".into())));
        assert_eq!(t.paths[0].runner_up, Some((2, 20.0, 20.0)));
        assert_eq!(t.paths[1].best_case, Some(3));
        assert_eq!(t.paths[1].feasible, 1);
        assert_eq!(t.paths[1].runner_up, None);
        // small prints everything (170 J); big leaves the column out and comes second even
        // though its sum (100 J) is lower.
        assert_eq!(t.combinations[0].robot, "small");
        assert_eq!(t.combinations[0].energy_j, 170.0);
        assert_eq!(t.combinations[1].infeasible, vec!["column".to_string()]);
        let csv = s.csv(&r).unwrap();
        assert_eq!(csv.lines().count(), 5);
        assert!(csv.lines().nth(2).unwrap().contains(",no answer,"), "{csv}");
        let mut mixed = r.clone();
        mixed[2].objective = "drives".into();
        let e = s.tables(&mixed).unwrap_err().to_string();
        assert!(
            e.contains("case 2 (small / bay / wall-1) minimises `drives`"),
            "{e}"
        );
    }

    #[test]
    fn a_stored_case_result_is_the_result_bit_for_bit() {
        let mut r = result(Some(0.1 + 0.2));
        r.report_sha256 = Some(crate::output::sha256_hex(b"<html/>"));
        assert_eq!(r.as_stored().unwrap(), r);
    }
}
