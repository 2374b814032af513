//! The live view: a local web server ([`server`]) and one page showing the robot (the
//! URDF's visual geometry where a link has it, else the collision shapes the feasibility
//! checks use), the bed, the part at a placement, the reach
//! and the energy map of the job's grid. Moving the part re-evaluates the placement with the
//! job's own [`Evaluator`] (the evaluator and the options of an optimisation run); the page
//! plays the arm along the timed path, runs the optimisation and writes its hand-off.
//!
//! This module holds what the page asks for as plain functions of a [`ViewState`] (each answer
//! a JSON value); [`server`] routes requests to them, drops superseded evaluations and keeps
//! the server to its address, its token and its size limits. Units: SI inside, metres and
//! degrees in the JSON (the names say which).

pub mod server;

use crate::error::{Error, Result};
use crate::evaluate::evaluator::{Evaluated, Evaluator, Scratch};
use crate::evaluate::feasibility::collision::{RobotShapes, Role};
use crate::evaluate::feasibility::{self, Infeasible};
use crate::evaluate::PathJob;
use crate::frame::Placement;
use crate::math::{Frame, V3};
use crate::robot::VisualShape;
use crate::search::job::OptimiseConfig;
use crate::timing::JointStageOptions;
use serde_json::{json, Value};
use std::path::PathBuf;

/// Largest number of path points the scene draws (the path is thinned evenly beyond).
pub(crate) const MAX_SCENE_POINTS: usize = 20_000;
/// Largest number of arm frames one playback request may ask for.
pub(crate) const MAX_FRAMES: usize = 600;
/// Points of the power trace sent with a playback.
pub(crate) const TRACE_POINTS: usize = 800;
/// Largest visual mesh file the server sends, bytes.
pub(crate) const MAX_MESH_BYTES: u64 = 64 << 20;

/// A visual mesh file the page may ask for, by its index in [`ViewState::meshes`].
#[derive(Clone, Debug, PartialEq)]
pub struct MeshFile {
    /// The file (canonical; checked inside its directory when the robot was loaded).
    pub path: PathBuf,
    /// `stl`, `dae` or `obj`.
    pub format: String,
    /// The name the URDF gives it.
    pub filename: String,
}

/// What the view serves: the optimisation job (robot, path, grid, every setting), the first
/// placement shown and where the page's export goes.
pub struct ViewConfig {
    /// The job, as `optimise` builds it.
    pub job: OptimiseConfig,
    /// The placement shown first; `None`: the feasible grid cell nearest the centre of the
    /// feasible region (the grid's first cell when none is feasible).
    pub start: Option<Placement>,
    /// Where the export button writes the hand-off; `None`: the button says it needs one.
    pub export_dir: Option<PathBuf>,
    /// Replace existing export files.
    pub force: bool,
    /// How the front end names its settings in messages: how to give an export directory
    /// (e.g. the command line's option) and how to allow replacing files.
    pub hints: ViewHints,
}

/// The front end's words for the view's settings, used in its messages (the library names
/// no command-line option itself).
#[derive(Clone, Debug, Default)]
pub struct ViewHints {
    /// How to give an export directory.
    pub export_dir: String,
    /// How to allow replacing existing files.
    pub force: String,
}

/// The state the page's requests are answered from: the job built once.
pub struct ViewState<'c> {
    /// The configuration.
    pub config: &'c ViewConfig,
    /// The job's placement-independent side.
    pub job: PathJob<'c>,
    /// The robot's shapes (those of the feasibility checks), for drawing.
    shapes: RobotShapes,
    /// The visual mesh files of the robot's URDF, each once: all the server sends of them.
    pub meshes: Vec<MeshFile>,
    /// The grid evaluated once (the energy map), in the grid's order.
    pub grid: Vec<Evaluated>,
    /// The placement shown first.
    pub start: Placement,
}

impl<'c> ViewState<'c> {
    /// Build the job and evaluate its grid (the energy map). Errors: the job's own (a robot
    /// without dynamics, an empty path, settings no check can use).
    pub fn new(config: &'c ViewConfig) -> Result<Self> {
        let c = &config.job;
        let s = &c.settings;
        s.check()?;
        let job = PathJob::new(
            &c.robot,
            &c.path,
            s.energy,
            s.profile,
            JointStageOptions::default(),
        )?;
        let shapes = RobotShapes::new(
            &c.robot,
            feasibility::reach_m(&c.robot),
            &s.feasibility.radii,
        );
        let grid_placements = match &c.placements {
            Some(p) => p.placements.clone(),
            None => {
                crate::search::optimise::default_grid(feasibility::reach_m(&c.robot)).placements()
            }
        };
        let grid = {
            let ev = Evaluator::new(&job, s.feasibility, s.objective);
            ev.sweep(&grid_placements, &|_, _| {})?
        };
        let start = config
            .start
            .or_else(|| crate::search::optimise::feasible_centre(&grid).map(|e| e.placement))
            .or_else(|| grid_placements.first().copied())
            .unwrap_or_default();
        let mut meshes: Vec<MeshFile> = Vec::new();
        let v = &c.robot.visuals;
        for g in v.base.iter().chain(v.links.iter().flatten()) {
            if let VisualShape::Mesh {
                path,
                format,
                filename,
                ..
            } = &g.shape
            {
                if !meshes.iter().any(|m| &m.path == path) {
                    meshes.push(MeshFile {
                        path: path.clone(),
                        format: format.clone(),
                        filename: filename.clone(),
                    });
                }
            }
        }
        Ok(ViewState {
            config,
            job,
            shapes,
            meshes,
            grid,
            start,
        })
    }

    /// The evaluator of the job (the one `optimise` uses, with its path reduction).
    pub fn evaluator(&self) -> Evaluator<'_, 'c> {
        let c = &self.config.job;
        let s = &c.settings;
        crate::search::run::evaluator(&self.job, &c.path, s.feasibility, s.objective, s.evaluation)
    }

    /// The scene: robot, reach, path (part frame), bed (part frame), the energy map, the
    /// first placement and what the page may do.
    pub fn scene(&self) -> Value {
        let c = &self.config.job;
        let motion = &self.job.plan.motion;
        let step = motion.p.len().div_ceil(MAX_SCENE_POINTS).max(1);
        let mut pts = Vec::new();
        let mut print = Vec::new();
        for (k, p) in motion.p.iter().enumerate() {
            if k % step == 0 || k + 1 == motion.p.len() {
                pts.extend([p.x, p.y, p.z]);
                print.push(motion.print.get(k).copied().unwrap_or(false));
            }
        }
        let (lo, hi) = bbox(&motion.p);
        let w = feasibility::World::new(&Frame::identity(), (lo, hi), &c.settings.feasibility);
        let map: Vec<Value> = self
            .grid
            .iter()
            .map(|e| {
                let p = &e.placement;
                json!({
                    "x_m": p.x, "y_m": p.y, "z_m": p.z, "yaw_deg": p.yaw.to_degrees(),
                    "energy_j": e.feasible().map(|f| f.energy_j),
                })
            })
            .collect();
        json!({
            "robot": c.robot.name(),
            "path_file": c.path_file.display().to_string(),
            "objective": c.settings.objective.name(),
            "objective_text": c.settings.objective.describe(),
            "reach_m": feasibility::reach_m(&c.robot),
            "dof": c.robot.dof(),
            "joints": c.robot.joints.iter().map(|j| j.name.clone()).collect::<Vec<_>>(),
            "shapes": self.shape_geometry(),
            "visuals": self.visual_geometry(),
            "meshes": self.meshes.iter().enumerate().map(|(k, m)| json!({
                "index": k, "file": m.filename, "format": m.format,
            })).collect::<Vec<_>>(),
            "visuals_skipped": c.robot.visuals.skipped,
            "path": { "points_m": pts, "print": print, "samples": motion.p.len() },
            "bed": { "lo_m": [w.bed_lo.x, w.bed_lo.y, w.bed_lo.z], "hi_m": [w.bed_hi.x, w.bed_hi.y, w.bed_hi.z] },
            "map": map,
            "start": placement_json(&self.start),
            "export_dir": self.config.export_dir.as_ref().map(|d| d.display().to_string()),
        })
    }

    /// Each shape in its own frame: `capsule` (axis ends and radius), `box` (half extents),
    /// `ball` (radius), `cylinder` (along y: half height and radius), `hull` (a convex piece of
    /// a link: vertices, m, and outward triangles as vertex indices), otherwise its bounding
    /// `ball`; with its role.
    fn shape_geometry(&self) -> Vec<Value> {
        self.shapes
            .shapes
            .iter()
            .map(|s| {
                let role = match s.role {
                    Role::Link => "link",
                    Role::Head => "head",
                    Role::Hose => "hose",
                };
                let sh = &s.shape;
                let g = if let Some(c) = sh.as_capsule() {
                    let (a, b) = (c.segment.a, c.segment.b);
                    json!({"kind": "capsule", "a_m": [a.x, a.y, a.z], "b_m": [b.x, b.y, b.z], "radius_m": c.radius})
                } else if let Some(b) = sh.as_cuboid() {
                    let h = b.half_extents;
                    json!({"kind": "box", "half_m": [h.x, h.y, h.z]})
                } else if let Some(b) = sh.as_ball() {
                    json!({"kind": "ball", "centre_m": [0.0, 0.0, 0.0], "radius_m": b.radius})
                } else if let Some(cy) = sh.as_cylinder() {
                    json!({"kind": "cylinder", "half_height_m": cy.half_height, "radius_m": cy.radius})
                } else if let Some(h) = sh.as_convex_polyhedron() {
                    let (v, t) = h.to_trimesh();
                    let v: Vec<[f64; 3]> = v.iter().map(|p| [p.x, p.y, p.z]).collect();
                    json!({"kind": "hull", "vertices_m": v, "triangles": t})
                } else {
                    let (c, r) = s.bound;
                    json!({"kind": "ball", "centre_m": [c.x, c.y, c.z], "radius_m": r})
                };
                let mut g = g;
                g["role"] = json!(role);
                g["label"] = json!(s.label);
                g["body"] = json!(s.body);
                // The pedestal is no link of the URDF: a visual never stands in for it.
                g["pedestal"] = json!(s.body == 0 && s.label.starts_with("pedestal"));
                g
            })
            .collect()
    }

    /// The URDF's visual elements: `body` (0 the fixed base, `i` the link of joint `i`), the
    /// URDF `link`, the pose in the body frame (`xyz_m`, quaternion `quat_xyzw`) and the
    /// geometry: `box` (`size_m`), `cylinder` along z (`radius_m`, `length_m`), `sphere`
    /// (`radius_m`) or `mesh` (`mesh`: its index in `meshes`, `format`, `scale`).
    fn visual_geometry(&self) -> Vec<Value> {
        let v = &self.config.job.robot.visuals;
        let bodies = std::iter::once((0, &v.base))
            .chain(v.links.iter().enumerate().map(|(i, l)| (i + 1, l)));
        let mut out = Vec::new();
        for (body, geoms) in bodies {
            for g in geoms {
                let q = quat_xyzw(&g.origin);
                let p = g.origin.pos;
                let mut j = match &g.shape {
                    VisualShape::Box { size_m } => json!({"kind": "box", "size_m": size_m}),
                    VisualShape::Cylinder { radius_m, length_m } => {
                        json!({"kind": "cylinder", "radius_m": radius_m, "length_m": length_m})
                    }
                    VisualShape::Sphere { radius_m } => {
                        json!({"kind": "sphere", "radius_m": radius_m})
                    }
                    VisualShape::Mesh {
                        path,
                        format,
                        scale,
                        ..
                    } => json!({
                        "kind": "mesh",
                        "mesh": self.meshes.iter().position(|m| &m.path == path),
                        "format": format,
                        "scale": scale,
                    }),
                };
                j["body"] = json!(body);
                j["link"] = json!(g.link);
                j["xyz_m"] = json!([p.x, p.y, p.z]);
                j["quat_xyzw"] = json!(q);
                out.push(j);
            }
        }
        out
    }

    /// The bytes of visual mesh `k` and its content type; `None` when there is no mesh `k`.
    /// Only files of [`ViewState::meshes`] are read, each checked again to be the file found
    /// when the robot was loaded (its canonical path unchanged) and at most
    /// [`MAX_MESH_BYTES`] long.
    pub fn mesh(&self, k: usize) -> Option<Result<(Vec<u8>, &'static str)>> {
        let m = self.meshes.get(k)?;
        let read = || -> Result<(Vec<u8>, &'static str)> {
            let canon = std::fs::canonicalize(&m.path).map_err(|e| Error::io(&m.path, e))?;
            if canon != m.path {
                return Err(Error::Invalid(format!(
                    "{}: the file moved since the robot was loaded",
                    m.path.display()
                )));
            }
            let len = std::fs::metadata(&m.path)
                .map_err(|e| Error::io(&m.path, e))?
                .len();
            if len > MAX_MESH_BYTES {
                return Err(Error::Invalid(format!(
                    "{}: {len} bytes, more than the {MAX_MESH_BYTES} sent",
                    m.path.display()
                )));
            }
            let b = std::fs::read(&m.path).map_err(|e| Error::io(&m.path, e))?;
            let ctype = match m.format.as_str() {
                "dae" => "model/vnd.collada+xml",
                "obj" => "text/plain",
                _ => "application/octet-stream",
            };
            Ok((b, ctype))
        };
        Some(read())
    }

    /// Every shape's pose and every body's frame (base frame: position, m, and quaternion
    /// `x, y, z, w`) at `q`: shapes in the order of `shapes`, bodies 0 (the fixed base) to
    /// the last link.
    fn poses(&self, q: &[f64]) -> (Vec<f64>, Vec<f64>) {
        let bodies = self.shapes.body_frames(q, None, &Frame::identity());
        let mut out = Vec::with_capacity(self.shapes.shapes.len() * 7);
        for s in &self.shapes.shapes {
            let iso = bodies.shape_pose(s);
            let t = iso.translation.vector;
            let r = iso.rotation.coords;
            out.extend([t.x, t.y, t.z, r.x, r.y, r.z, r.w]);
        }
        let n = self.config.job.robot.dof();
        let mut b = Vec::with_capacity((n + 1) * 7);
        for k in 0..=n {
            let f = bodies.body(k);
            let [x, y, z, w] = quat_xyzw(f);
            b.extend([f.pos.x, f.pos.y, f.pos.z, x, y, z, w]);
        }
        (out, b)
    }

    /// Evaluate one placement with the job's evaluator: energies, per-joint energy, the
    /// tightest margins, or why it is infeasible (the reason, the sample, the time). The
    /// supply energy is also given as text to the digits `printwatt energy --at` prints.
    /// `sc`: the evaluating thread's scratch ([`Evaluator::scratch`]), kept between calls.
    pub fn evaluate(
        &self,
        ev: &Evaluator<'_, 'c>,
        sc: &mut Scratch<'c>,
        at: &Placement,
    ) -> Result<Value> {
        at.check_metres()
            .map_err(|e| Error::Invalid(format!("placement: {e}")))?;
        let t0 = std::time::Instant::now();
        let e = ev.evaluate(sc, at);
        let secs = t0.elapsed().as_secs_f64();
        let names: Vec<&str> = self
            .config
            .job
            .robot
            .joints
            .iter()
            .map(|j| j.name.as_str())
            .collect();
        let mut v = json!({
            "placement": placement_json(at),
            "evaluation_s": secs,
            "objective": self.config.job.settings.objective.name(),
        });
        match &e.outcome {
            Ok(f) => {
                let m = &f.margins;
                v["feasible"] = json!(true);
                v["energy_j"] = json!(f.energy_j);
                v["supply_j"] = json!(f.supply_j);
                v["supply_text"] = json!(one_decimal(f.supply_j));
                v["drives_j"] = json!(f.drives_j);
                v["drives_text"] = json!(one_decimal(f.drives_j));
                v["standby_j"] = json!(f.standby_j);
                v["duration_s"] = json!(f.duration_s);
                v["samples"] = json!(f.samples);
                v["joints"] = json!(names
                    .iter()
                    .enumerate()
                    .map(|(j, n)| json!({
                        "name": n,
                        "electrical_j": f.joint_electrical_j.get(j),
                        "mechanical_abs_j": f.joint_mechanical_abs_j.get(j),
                    }))
                    .collect::<Vec<_>>());
                v["margins"] = json!({
                    "joint": m.joint_limit_rad.map(|(j, r)| json!({
                        "joint": j,
                        "name": names.get(j.saturating_sub(1)),
                        "deg": r.to_degrees(),
                    })),
                    "wrist_deg": m.wrist_deg(),
                    "clearance_m": m.bed_clearance_m,
                    "elbow": m.elbow,
                    "shoulder_m": m.shoulder_m,
                });
                if let Some(r) = &f.path_reduction {
                    v["path_reduction"] = serde_json::to_value(r).unwrap_or(Value::Null);
                }
            }
            Err(i) => {
                v["feasible"] = json!(false);
                v["infeasible"] = infeasible_json(i);
            }
        }
        Ok(v)
    }

    /// The arm along the timed path at `at`: `frames` evenly spaced samples (each shape's
    /// pose, base frame, see [`ViewState::scene`]'s `shapes`), the nozzle tip per frame, and
    /// the supply power trace. A path that cannot be timed there answers with the reason.
    pub fn playback(&self, at: &Placement, frames: usize) -> Result<Value> {
        at.check_metres()
            .map_err(|e| Error::Invalid(format!("placement: {e}")))?;
        let frames = frames.clamp(2, MAX_FRAMES);
        let pe = match self.job.evaluate(at)? {
            Ok(pe) => pe,
            Err(t) => {
                return Ok(json!({
                    "placement": placement_json(at),
                    "timed": false,
                    "infeasible": infeasible_json(&Infeasible::from_timing(&t)),
                }))
            }
        };
        let traj = &pe.timed.traj;
        let n = traj.n;
        let len = traj.t.len();
        if len == 0 || n == 0 {
            return Err(Error::Invalid("the timed path has no samples".into()));
        }
        let pick = |k: usize, of: usize| -> usize {
            if of <= 1 {
                0
            } else {
                (k * (len - 1)) / (of - 1)
            }
        };
        let mut t = Vec::with_capacity(frames);
        let mut poses = Vec::with_capacity(frames);
        let mut bodies = Vec::with_capacity(frames);
        let mut tip = Vec::with_capacity(frames * 3);
        for k in 0..frames.min(len) {
            let i = pick(k, frames.min(len));
            t.push(traj.t[i]);
            let (p, b) = self.poses(&traj.q[i * n..(i + 1) * n]);
            poses.push(p);
            bodies.push(b);
            if let Some(p) = pe.timed.tcp.get(i) {
                tip.extend([p.x, p.y, p.z]);
            }
        }
        let series = &pe.energy.series;
        let m = TRACE_POINTS.min(series.t.len());
        let mut trace_t = Vec::with_capacity(m);
        let mut trace_p = Vec::with_capacity(m);
        for k in 0..m {
            let i = if m <= 1 {
                0
            } else {
                (k * (series.t.len() - 1)) / (m - 1)
            };
            trace_t.push(series.t[i]);
            trace_p.push(series.p_supply.get(i).copied().unwrap_or(0.0));
        }
        Ok(json!({
            "placement": placement_json(at),
            "timed": true,
            "duration_s": pe.energy.duration_s,
            "t_s": t,
            "poses": poses,
            "bodies": bodies,
            "tip_m": tip,
            "power": { "t_s": trace_t, "supply_w": trace_p },
            "supply_text": one_decimal(pe.energy.total.supply_j),
        }))
    }

    /// Write the hand-off of `at` (the files `optimise --export` writes) into the export
    /// directory; an existing file is replaced only with `force`, an input never. A placement
    /// the checks refuse is not exported.
    pub fn export(&self, at: &Placement) -> Result<Vec<PathBuf>> {
        let Some(dir) = &self.config.export_dir else {
            return Err(Error::Invalid(format!(
                "no export directory was given ({})",
                self.config.hints.export_dir
            )));
        };
        let ev = self.evaluator();
        let mut sc = ev.scratch()?;
        if let Err(i) = ev.evaluate_full(&mut sc, at).outcome {
            return Err(Error::Invalid(format!(
                "the placement is infeasible, nothing exported: {i}"
            )));
        }
        let cfg = &self.config.job;
        let files: Vec<(PathBuf, String)> = crate::search::run::hand_off(cfg, at)?
            .into_iter()
            .map(|(name, text)| (dir.join(name), text))
            .collect();
        for (f, _) in &files {
            if f.exists() && !self.config.force {
                return Err(Error::Invalid(format!(
                    "{} exists: replacing it needs {}",
                    f.display(),
                    self.config.hints.force
                )));
            }
            crate::output::guard_inputs(f, &[cfg.path_file.as_path()])?;
        }
        for (f, text) in &files {
            crate::output::write_atomic(f, text.as_bytes())?;
        }
        Ok(files.into_iter().map(|(f, _)| f).collect())
    }
}

/// The rotation of `f` as a unit quaternion `[x, y, z, w]`.
fn quat_xyzw(f: &Frame) -> [f64; 4] {
    let r = nalgebra::Rotation3::from_matrix(&f.rot);
    let q = nalgebra::UnitQuaternion::from_rotation_matrix(&r);
    let c = q.coords;
    [c.x, c.y, c.z, c.w]
}

/// `x` to one decimal as the command line prints energies (a value that rounds to zero is
/// `0.0`, not `-0.0`).
pub(crate) fn one_decimal(x: f64) -> String {
    let s = format!("{x:.1}");
    if s == "-0.0" {
        "0.0".into()
    } else {
        s
    }
}

/// A placement in the JSON's units (m, deg).
pub(crate) fn placement_json(p: &Placement) -> Value {
    json!({
        "x_m": p.x, "y_m": p.y, "z_m": p.z,
        "yaw_deg": p.yaw.to_degrees(), "spin_deg": p.nozzle_spin.to_degrees(),
    })
}

/// A placement from the JSON's units (m, deg): `x_m`, `y_m`, `z_m`, `yaw_deg`, optional
/// `spin_deg`. Errors name the missing or non-finite field.
pub(crate) fn placement_from_json(v: &Value) -> Result<Placement> {
    let num = |k: &str, required: bool| -> Result<f64> {
        match v.get(k) {
            Some(x) => x
                .as_f64()
                .filter(|x| x.is_finite())
                .ok_or_else(|| Error::Invalid(format!("`{k}`: expected a finite number"))),
            None if required => Err(Error::Invalid(format!("`{k}` is missing"))),
            None => Ok(0.0),
        }
    };
    let p = Placement {
        x: num("x_m", true)?,
        y: num("y_m", true)?,
        z: num("z_m", true)?,
        yaw: num("yaw_deg", true)?.to_radians(),
        nozzle_spin: num("spin_deg", false)?.to_radians(),
    };
    p.check_metres()
        .map_err(|e| Error::Invalid(format!("placement: {e}")))?;
    Ok(p)
}

/// The answer of a run directory written by `optimise` or `sweep`: the `best` placement of
/// its `summary.json`. Errors name the file and what is missing.
pub fn placement_of_run(dir: &std::path::Path) -> Result<Placement> {
    let f = dir.join("summary.json");
    let text = std::fs::read_to_string(&f).map_err(|e| Error::io(&f, e))?;
    let v: Value = serde_json::from_str(&text)
        .map_err(|e| Error::Invalid(format!("{}: not JSON: {e}", f.display())))?;
    let p = v
        .get("best")
        .and_then(|b| b.get("placement"))
        .ok_or_else(|| {
            Error::Invalid(format!(
                "{}: no `best.placement` (a run of `optimise` or `sweep` has one)",
                f.display()
            ))
        })?;
    placement_from_json(p)
        .map_err(|e| Error::Invalid(format!("{}: best.placement: {e}", f.display())))
}

fn summary_of(dir: &std::path::Path) -> Result<(PathBuf, Value)> {
    let f = dir.join("summary.json");
    let text = std::fs::read_to_string(&f).map_err(|e| Error::io(&f, e))?;
    let v: Value = serde_json::from_str(&text)
        .map_err(|e| Error::Invalid(format!("{}: not JSON: {e}", f.display())))?;
    Ok((f, v))
}

/// One station of a `stations` run directory: the part's placement in that station's robot
/// frame and the moves it prints.
#[derive(Clone, Debug, PartialEq)]
pub struct StationOfRun {
    /// The part frame in the station's robot base frame.
    pub placement: Placement,
    /// First and last move of the path it prints (0-based, inclusive).
    pub moves: [usize; 2],
    /// Stations in the plan.
    pub stations: usize,
    /// The path the plan was made for, as its `meta.path` says it.
    pub path: Option<String>,
}

/// Station `k` (1-based) of the `stations` run directory `dir` (its `summary.json`).
/// Errors name the file and what is missing, or the stations there are.
pub fn station_of_run(dir: &std::path::Path, k: usize) -> Result<StationOfRun> {
    let (f, v) = summary_of(dir)?;
    let segs = v.get("segments").and_then(Value::as_array).ok_or_else(|| {
        Error::Invalid(format!(
            "{}: no `segments` (a run of `stations` has them)",
            f.display()
        ))
    })?;
    let seg = k.checked_sub(1).and_then(|i| segs.get(i)).ok_or_else(|| {
        Error::Invalid(format!(
            "{}: station {k} does not exist: the plan has stations 1 to {}",
            f.display(),
            segs.len()
        ))
    })?;
    let at = seg
        .get("at")
        .ok_or_else(|| Error::Invalid(format!("{}: segments[{}]: no `at`", f.display(), k - 1)))?;
    let placement = placement_from_json(at)
        .map_err(|e| Error::Invalid(format!("{}: segments[{}].at: {e}", f.display(), k - 1)))?;
    let moves = seg
        .get("moves")
        .and_then(Value::as_array)
        .and_then(|m| Some([m.first()?.as_u64()? as usize, m.get(1)?.as_u64()? as usize]))
        .filter(|m| m[0] <= m[1])
        .ok_or_else(|| {
            Error::Invalid(format!(
                "{}: segments[{}]: no `moves` [first, last]",
                f.display(),
                k - 1
            ))
        })?;
    Ok(StationOfRun {
        placement,
        moves,
        stations: segs.len(),
        path: v
            .get("meta")
            .and_then(|m| m.get("path"))
            .and_then(Value::as_str)
            .map(str::to_string),
    })
}

/// One case of a `study` run directory: its robot, tool, path, options and answer.
#[derive(Clone, Debug, PartialEq)]
pub struct CaseOfRun {
    /// The case's index.
    pub index: usize,
    /// "robot / cell / path".
    pub name: String,
    /// The robot as the study resolved it.
    pub robot: String,
    /// The tool drive file, if the study gave one.
    pub tool: Option<String>,
    /// The path file.
    pub path: String,
    /// The options the case ran with: the study's, its robot's, its cell's, its path's.
    pub options: Vec<String>,
    /// The cell's placement fields as the command line takes them (`x`, `y`, `z`, `yaw`, …).
    pub cell: Vec<(String, String)>,
    /// The case's answer (`None`: the case has none).
    pub placement: Option<Placement>,
}

/// The case `case` (its index, or `robot/cell/path` by names) of the `study` run directory
/// `dir` (its `summary.json`).
pub fn case_of_run(dir: &std::path::Path, case: &str) -> Result<CaseOfRun> {
    let (f, v) = summary_of(dir)?;
    let bad = |m: String| Error::Invalid(format!("{}: {m}", f.display()));
    if v.get("kind").and_then(Value::as_str) != Some("printwatt-study") {
        return Err(bad(
            "not a study's summary (`kind` is not `printwatt-study`)".into(),
        ));
    }
    let list = |k: &str| {
        v.get(k)
            .and_then(Value::as_array)
            .cloned()
            .unwrap_or_default()
    };
    let cases = list("cases");
    let c = match case.parse::<usize>() {
        Ok(i) => cases.get(i),
        Err(_) => cases.iter().find(|c| case_name(c) == case),
    }
    .ok_or_else(|| {
        bad(format!(
            "no case `{case}`: give an index 0 to {} or robot/cell/path (e.g. `{}`)",
            cases.len().saturating_sub(1),
            cases.first().map(case_name).unwrap_or_default()
        ))
    })?;
    let named = |k: &str, name: &str| -> Result<Value> {
        list(k)
            .into_iter()
            .find(|x| x.get("name").and_then(Value::as_str) == Some(name))
            .ok_or_else(|| bad(format!("{k}: no `{name}`")))
    };
    let field = |c: &Value, k: &str| c.get(k).and_then(Value::as_str).unwrap_or("").to_string();
    let robot = named("robots", &field(c, "robot"))?;
    let cell = named("cells", &field(c, "cell"))?;
    let path = named("paths", &field(c, "path"))?;
    let mut options = options_of(&v);
    options.extend(options_of(&robot));
    options.extend(options_of(&cell));
    options.extend(options_of(&path));
    let placement = match c.get("placement") {
        Some(p) if !p.is_null() => {
            Some(placement_from_json(p).map_err(|e| bad(format!("case {case}: placement: {e}")))?)
        }
        _ => None,
    };
    Ok(CaseOfRun {
        index: c.get("case").and_then(Value::as_u64).unwrap_or(0) as usize,
        name: case_name(c),
        robot: field(&robot, "robot"),
        tool: robot
            .get("tool")
            .and_then(Value::as_str)
            .map(str::to_string),
        path: field(&path, "file"),
        options,
        cell: cell_placement(&cell),
        placement,
    })
}

/// A study case's name: "robot/cell/path" ("?" for a missing part).
fn case_name(c: &Value) -> String {
    format!(
        "{}/{}/{}",
        c.get("robot").and_then(Value::as_str).unwrap_or("?"),
        c.get("cell").and_then(Value::as_str).unwrap_or("?"),
        c.get("path").and_then(Value::as_str).unwrap_or("?")
    )
}

/// The command-line options a study entry (the study, a robot, a cell, a path) lists.
fn options_of(x: &Value) -> Vec<String> {
    x.get("options")
        .and_then(Value::as_array)
        .map(|a| {
            a.iter()
                .filter_map(|o| o.as_str().map(str::to_string))
                .collect()
        })
        .unwrap_or_default()
}

/// A study cell's placement fields as the command line takes them (`x`, `y`, `z`, `yaw`, …).
fn cell_placement(cell: &Value) -> Vec<(String, String)> {
    cell.get("placement")
        .and_then(Value::as_object)
        .map(|m| {
            m.iter()
                .map(|(k, v)| (k.clone(), v.as_str().map_or(v.to_string(), str::to_string)))
                .collect()
        })
        .unwrap_or_default()
}

fn infeasible_json(i: &Infeasible) -> Value {
    json!({
        "reason": i.reason.name(),
        "text": i.to_string(),
        "sample": i.sample,
        "t_s": i.t_s,
        "line": i.line,
        "point_m": i.point_m,
        "detail": i.detail,
    })
}

fn bbox(p: &[V3]) -> (V3, V3) {
    let mut lo = V3::repeat(f64::INFINITY);
    let mut hi = V3::repeat(f64::NEG_INFINITY);
    for q in p {
        lo = lo.inf(q);
        hi = hi.sup(q);
    }
    if p.is_empty() {
        (V3::zeros(), V3::zeros())
    } else {
        (lo, hi)
    }
}
