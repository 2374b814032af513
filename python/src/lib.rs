//! The `printwatt` Python module: PyO3 bindings over the printwatt library (never the binary).
//!
//! Units are SI in and out (m, rad, s, kg, N·m, W, J, m/s); dictionaries that mirror a
//! `--json` document (docs/json.md) keep its field names, which carry their unit (`_m`,
//! `_deg`, `_j`, …). Every library error becomes a `printwatt.PrintwattError` with the
//! library's message (file, line, column or field); nothing panics across the boundary.
//! The Python API is documented in docs/python.md.

use numpy::ndarray::Array2;
use numpy::{IntoPyArray, PyArray1, PyArray2, PyReadonlyArray2};
use printwatt::energy::EnergyOptions;
use printwatt::evaluate::evaluator::{Evaluated, Evaluator, Objective};
use printwatt::evaluate::feasibility::{self, FeasibilityOptions};
use printwatt::identify::{self as pid, metrics, Log, Model, Prepared};
use printwatt::nalgebra::Vector3;
use printwatt::robot::{Regeneration, RobotModel};
use printwatt::search::optimise as popt;
use printwatt::search::tolerance::Tolerance;
use printwatt::search::{Grid, OptimiseConfig, OptimiseSettings, PlacementSet};
use printwatt::timing::{JointStageOptions, ProfileOptions};
use printwatt::toolpath::{ReadOptions, Toolpath, Zone};
use printwatt::{PathJob, Placement};
use pyo3::create_exception;
use pyo3::exceptions::{PyException, PyTypeError};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};
use std::path::{Path, PathBuf};

create_exception!(
    printwatt,
    PrintwattError,
    PyException,
    "An error from printwatt: bad input (the message names the file and the line, column or \
field), an infeasible placement, or a model error. The message is the library's."
);

/// A library (or any displayable) error as a Python `PrintwattError`.
fn err(e: impl std::fmt::Display) -> PyErr {
    PrintwattError::new_err(e.to_string())
}

/// An integer argument within `min..=max`: a negative or out-of-range one raises
/// PrintwattError naming the argument (taken as `i64`, so that -1 is not an OverflowError).
fn int_arg<T: TryFrom<i64>>(name: &str, v: i64, min: i64, max: i64) -> PyRes<T> {
    if v < min || v > max {
        return Err(err(format!(
            "{name} = {v}: expected an integer from {min} to {max}"
        )));
    }
    T::try_from(v).map_err(|_| err(format!("{name} = {v}: out of range")))
}

type PyRes<T> = PyResult<T>;

// The defaults in the `#[pyo3(signature = ...)]` attributes are literals, so that Python's
// `inspect.signature` (and `help`) shows them; these checks keep them equal to the library's.
const _: () = assert!(printwatt::search::job::DEFAULT_MAX_EVALS == 120);
const _: () = assert!(printwatt::search::job::DEFAULT_SEED == 42);
const _: () = assert!(printwatt::search::job::DEFAULT_PRINTS_PER_YEAR == 1000.0);
const _: () = assert!(printwatt::search::job::DEFAULT_GRID_KG_CO2_PER_KWH == 0.4);
const _: () = assert!(
    printwatt::evaluate::feasibility::margins::DEFAULT_WRIST_MARGIN_DEG.to_radians()
        == 0.08726646259971647
);
// The joint margin, 3° (the command line's `--joint-margin` default).
const _: () = assert!(3f64.to_radians() == 0.05235987755982989);

/// A sequence of numbers for the argument `name` (a list, tuple or 1-D array of floats): a
/// string, a mapping or anything else raises TypeError naming the argument and the form
/// expected (`what`), instead of PyO3's generic extraction message.
fn float_seq(obj: &Bound<'_, PyAny>, name: &str, what: &str) -> PyRes<Vec<f64>> {
    let kind = || {
        obj.get_type()
            .name()
            .map(|n| n.to_string())
            .unwrap_or_else(|_| "?".into())
    };
    if obj.is_instance_of::<pyo3::types::PyString>()
        || obj.is_instance_of::<pyo3::types::PyBytes>()
        || obj.is_instance_of::<PyDict>()
    {
        return Err(PyTypeError::new_err(format!(
            "{name}: expected {what}, got a {} ({})",
            kind(),
            obj.repr().map(|r| r.to_string()).unwrap_or_default()
        )));
    }
    obj.extract::<Vec<f64>>().map_err(|_| {
        PyTypeError::new_err(format!(
            "{name}: expected {what}, got a {} ({})",
            kind(),
            obj.repr().map(|r| r.to_string()).unwrap_or_default()
        ))
    })
}

/// What `at` and `baseline` take.
const PLACEMENT_FORM: &str =
    "a sequence (x, y, z, yaw) or (x, y, z, yaw, spin) of numbers in m, m, m, rad, rad";

// ---------------------------------------------------------------------------------------------
// Robots

fn robots_dir() -> PathBuf {
    printwatt::robot::shipped::robots_dir()
}

fn shipped_names() -> Vec<String> {
    printwatt::robot::shipped::names()
}

fn load_robot_model(arg: &Path, tool: Option<&Path>) -> PyRes<RobotModel> {
    let resolved = printwatt::robot::shipped::resolve(arg).ok_or_else(|| {
        err(format!(
            "robot `{}`: no such file or directory, and no shipped robot of that name; shipped robots: {} (or give a robot directory, a .urdf or a drive .toml)",
            arg.display(),
            shipped_names().join(", ")
        ))
    })?;
    // Library errors name the file and the line:column or field already.
    let mut m = printwatt::load_robot(&resolved).map_err(err)?;
    if let Some(t) = tool {
        printwatt::robot::apply_tool_preset(&mut m, t).map_err(err)?;
    }
    Ok(m)
}

/// A robot arm: kinematics, inertias and (with a drive file) motors, gears, friction, payload
/// and tool. Load one with `load_robot`. Lengths in m, angles in rad.
#[pyclass(module = "printwatt", frozen)]
struct Robot {
    inner: RobotModel,
}

#[pymethods]
impl Robot {
    /// Display name of the robot.
    #[getter]
    fn name(&self) -> String {
        self.inner.name().to_string()
    }
    /// Number of actuated joints.
    #[getter]
    fn dof(&self) -> usize {
        self.inner.dof()
    }
    /// Names of the actuated joints, base to flange.
    #[getter]
    fn joint_names(&self) -> Vec<String> {
        self.inner.joints.iter().map(|j| j.name.clone()).collect()
    }
    /// The URDF the robot was loaded from.
    #[getter]
    fn source(&self) -> String {
        self.inner.source.display().to_string()
    }
    /// Reach of the arm, m (from its kinematics).
    #[getter]
    fn reach_m(&self) -> f64 {
        feasibility::reach_m(&self.inner)
    }
    /// The reader's warnings (file, line and message in each).
    #[getter]
    fn warnings(&self) -> Vec<String> {
        self.inner.warnings.clone()
    }
    fn __repr__(&self) -> String {
        format!(
            "Robot({:?}, dof={}, source={:?})",
            self.inner.name(),
            self.inner.dof(),
            self.inner.source.display().to_string()
        )
    }
}

/// Load a robot: a shipped robot's name (see `shipped_robots()`), a robot directory
/// (`robot.urdf` + optional `drive.toml`), a `.urdf` file (rigid body only: mechanical power)
/// or a drive `.toml` naming its URDF (e.g. a calibrated robot written by `identify`).
/// `tool`: a tool preset `.toml` replacing the robot's tool and payload. Units inside: SI
/// (m, rad, kg, N·m). Raises PrintwattError naming the file and line:column at fault.
#[pyfunction]
#[pyo3(signature = (robot, tool = None))]
fn load_robot(robot: PathBuf, tool: Option<PathBuf>) -> PyRes<Robot> {
    Ok(Robot {
        inner: load_robot_model(&robot, tool.as_deref())?,
    })
}

/// Names of the shipped robots (directories of `$PRINTWATT_ROBOTS`, `./robots` or the source
/// tree's `robots/`), sorted.
#[pyfunction]
fn shipped_robots() -> Vec<String> {
    shipped_names()
}

/// A robot given either as a loaded `Robot` or as a name/path to load.
#[derive(FromPyObject)]
enum RobotArg<'py> {
    Loaded(PyRef<'py, Robot>),
    Name(PathBuf),
}

enum RobotHold<'py> {
    Ref(PyRef<'py, Robot>),
    Own(Box<RobotModel>),
}

impl<'py> RobotArg<'py> {
    fn hold(self) -> PyRes<RobotHold<'py>> {
        match self {
            RobotArg::Loaded(r) => Ok(RobotHold::Ref(r)),
            RobotArg::Name(p) => Ok(RobotHold::Own(Box::new(load_robot_model(&p, None)?))),
        }
    }
}

impl std::ops::Deref for RobotHold<'_> {
    type Target = RobotModel;
    fn deref(&self) -> &RobotModel {
        match self {
            RobotHold::Ref(r) => &r.inner,
            RobotHold::Own(m) => m,
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Toolpaths

/// A toolpath in its part frame (m, m/s): the moves the nozzle makes, from a G-code, CSV or
/// RAPID file (`load_path`) or from points (`path_from_points`).
#[pyclass(name = "Toolpath", module = "printwatt", frozen)]
struct Toolpath_ {
    inner: Toolpath,
}

#[pymethods]
impl Toolpath_ {
    /// Where the path came from (a file name, or the name given to `path_from_points`).
    #[getter]
    fn source(&self) -> String {
        self.inner.source.clone()
    }
    /// Number of moves.
    #[getter]
    fn moves(&self) -> usize {
        self.inner.moves.len()
    }
    /// Total length, m (printing and travel).
    #[getter]
    fn length_m(&self) -> f64 {
        self.inner.length()
    }
    /// Length of the printing (extruding) moves, m.
    #[getter]
    fn print_length_m(&self) -> f64 {
        self.inner.print_length()
    }
    /// The start point and every move's end point, an (N+1, 3) float64 array in m (part frame;
    /// arcs contribute their end point only).
    fn points<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        let mut v = Vec::with_capacity(3 * (self.inner.moves.len() + 1));
        v.extend(self.inner.start.iter());
        for m in &self.inner.moves {
            v.extend(m.end.iter());
        }
        rows(v, 3).into_pyarray(py)
    }
    /// Commanded TCP speed of every move, an (N,) float64 array in m/s.
    fn speeds<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        let v: Vec<f64> = self.inner.moves.iter().map(|m| m.speed).collect();
        PyArray1::from_vec(py, v)
    }
    /// The reader's warnings (file, line and message in each).
    #[getter]
    fn warnings(&self) -> Vec<String> {
        self.inner.warnings.clone()
    }
    fn __repr__(&self) -> String {
        format!(
            "Toolpath({:?}, moves={}, length_m={:.4})",
            self.inner.source,
            self.inner.moves.len(),
            self.inner.length()
        )
    }
}

fn read_options(print_speed: f64, travel_speed: f64, zone: f64) -> PyRes<ReadOptions> {
    for (name, v) in [("print_speed", print_speed), ("travel_speed", travel_speed)] {
        if !(v.is_finite() && v > 0.0) {
            return Err(err(format!("{name} = {v}: expected a speed > 0 m/s")));
        }
    }
    if !(zone.is_finite() && zone >= 0.0) {
        return Err(err(format!(
            "zone = {zone}: expected a blend radius >= 0 m"
        )));
    }
    Ok(ReadOptions {
        default_print_speed: print_speed,
        default_travel_speed: travel_speed,
        default_zone: Zone::Blend(zone),
        ..Default::default()
    })
}

/// Read a toolpath in its part frame: G-code (`.gcode`, `.nc`, …), CSV of points
/// (`x,y,z[,speed][,print]`, units in the header) or an ABB RAPID module (`.mod`). The file's
/// units are converted to SI (m, m/s). `print_speed` and `travel_speed` (m/s) apply where the
/// file gives no speed; `zone` (m) is the corner blend radius where the file gives none.
/// `path_units` (`"mm"` or `"m"`) is the unit of a CSV path's x, y, z written without one
/// (default: mm, with a warning in `Toolpath.warnings`); `scale` multiplies the geometry.
/// `proc` names the procedure of a RAPID module to read instead of `main` (case-insensitive),
/// for modules whose `main` chooses its path at run time; other formats refuse it.
/// Raises PrintwattError naming the file, line and column at fault.
#[pyfunction]
#[pyo3(signature = (file, print_speed = 0.1, travel_speed = 0.25, zone = 0.005, path_units = None, scale = 1.0, proc = None))]
fn load_path(
    file: PathBuf,
    print_speed: f64,
    travel_speed: f64,
    zone: f64,
    path_units: Option<String>,
    scale: f64,
    proc: Option<String>,
) -> PyRes<Toolpath_> {
    let mut opts = read_options(print_speed, travel_speed, zone)?;
    if let Some(u) = &path_units {
        opts.path_units = Some(printwatt::toolpath::PathUnits::parse(u).map_err(err)?);
    }
    opts.scale = scale;
    opts.proc = proc;
    let tp = printwatt::load_path(&file, &opts).map_err(err)?;
    Ok(Toolpath_ { inner: tp })
}

/// A printing toolpath through `points`, an (N, 3) array-like of x, y, z in m (the part
/// frame: +z up, the nozzle points down), N >= 2, at the print speed `speed` (m/s), with
/// corners blended within `zone` (m; 0 stops at every point). Consecutive duplicate points are
/// dropped. Raises PrintwattError for a wrong shape, a non-finite coordinate (naming the row)
/// or a non-positive speed.
#[pyfunction]
#[pyo3(signature = (points, speed, zone = 0.005, name = "points"))]
fn path_from_points(
    py: Python<'_>,
    points: &Bound<'_, PyAny>,
    speed: f64,
    zone: f64,
    name: &str,
) -> PyRes<Toolpath_> {
    let pts = points_array(py, points, "points")?;
    let tp = Toolpath::from_points(&pts, speed, Zone::Blend(zone), name).map_err(err)?;
    Ok(Toolpath_ { inner: tp })
}

/// An (N, 3) array-like of floats (m) as points; errors name the argument.
fn points_array(py: Python<'_>, points: &Bound<'_, PyAny>, what: &str) -> PyRes<Vec<Vector3<f64>>> {
    let np = py.import("numpy")?;
    // A complex array is refused: converting it to floats would drop its imaginary part.
    let complex: bool = np.call_method1("iscomplexobj", (points,))?.extract()?;
    if complex {
        return Err(err(format!(
            "{what}: complex numbers given; expected an (N, 3) array of real floats (m)"
        )));
    }
    let arr = np
        .call_method1("asarray", (points, "float64"))
        .map_err(|e| {
            err(format!(
                "{what}: expected an (N, 3) array of floats (m): {e}"
            ))
        })?;
    let ndim: usize = arr.getattr("ndim")?.extract()?;
    let shape: Vec<usize> = arr.getattr("shape")?.extract()?;
    if ndim != 2 || shape[1] != 3 {
        return Err(err(format!(
            "{what}: expected an (N, 3) array of x, y, z in m, got shape {shape:?}"
        )));
    }
    let a: PyReadonlyArray2<f64> = arr.extract()?;
    let a = a.as_array();
    Ok(a.rows()
        .into_iter()
        .map(|r| Vector3::new(r[0], r[1], r[2]))
        .collect())
}

/// A toolpath given either as a `Toolpath` or as a file to load with the default options.
#[derive(FromPyObject)]
enum PathArg<'py> {
    Loaded(PyRef<'py, Toolpath_>),
    File(PathBuf),
}

enum PathHold<'py> {
    Ref(PyRef<'py, Toolpath_>),
    Own(Box<Toolpath>),
}

impl<'py> PathArg<'py> {
    /// The path, loaded with the default options when it is a file; `proc` chooses the RAPID
    /// procedure of a file (a loaded `Toolpath` has its procedure already: `proc` is refused).
    fn hold(self, proc: Option<String>) -> PyRes<PathHold<'py>> {
        match self {
            PathArg::Loaded(r) => match proc {
                None => Ok(PathHold::Ref(r)),
                Some(p) => Err(err(format!(
                    "proc = {p:?}: applies to a path given as a file; this Toolpath was \
                     already read (from {}): pass proc to load_path instead",
                    r.inner.source
                ))),
            },
            PathArg::File(f) => Ok(PathHold::Own(Box::new(
                load_path(f, 0.1, 0.25, 0.005, None, 1.0, proc)?.inner,
            ))),
        }
    }
}

impl std::ops::Deref for PathHold<'_> {
    type Target = Toolpath;
    fn deref(&self) -> &Toolpath {
        match self {
            PathHold::Ref(r) => &r.inner,
            PathHold::Own(t) => t,
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Options shared by energy, sweep and optimise

fn profile(period: f64, accel: f64, jerk: f64) -> PyRes<ProfileOptions> {
    for (name, v, unit) in [
        ("period", period, "s"),
        ("accel", accel, "m/s²"),
        ("jerk", jerk, "m/s³"),
    ] {
        if !(v.is_finite() && v > 0.0) {
            return Err(err(format!("{name} = {v}: expected a value > 0 {unit}")));
        }
    }
    if period > 1.0 {
        return Err(err(format!(
            "period = {period} s: no controller interpolates that slowly; the period is in s (did you mean {} s?)",
            period / 1000.0
        )));
    }
    Ok(ProfileOptions {
        accel,
        lateral_accel: accel,
        jerk,
        dt: period,
        ..Default::default()
    })
}

fn energy_options(
    regeneration: Option<&str>,
    payload: bool,
    friction: bool,
) -> PyRes<EnergyOptions> {
    let mut o = EnergyOptions {
        payload,
        friction,
        ..Default::default()
    };
    if let Some(r) = regeneration {
        o.regeneration = Some(Regeneration::parse(r).ok_or_else(|| {
            err(format!(
                "regeneration `{r}`: expected none, per_axis, dc_bus or grid"
            ))
        })?);
    }
    Ok(o)
}

/// A placement from `(x, y, z, yaw[, spin])` in m, m, m, rad, rad.
fn placement(at: &[f64]) -> PyRes<Placement> {
    let (x, y, z, yaw, spin) = match *at {
        [x, y, z, yaw] => (x, y, z, yaw, 0.0),
        [x, y, z, yaw, spin] => (x, y, z, yaw, spin),
        _ => {
            return Err(err(format!(
                "at = {at:?}: expected (x, y, z, yaw) or (x, y, z, yaw, spin) in m, m, m, rad, rad"
            )))
        }
    };
    if at.iter().any(|v| !v.is_finite()) {
        return Err(err(format!("at = {at:?}: every value must be finite")));
    }
    for (name, v) in [("yaw", yaw), ("spin", spin)] {
        if v.abs() > 2.0 * std::f64::consts::PI + 1e-9 {
            return Err(err(format!(
                "at: {name} = {v} rad: more than a full turn; angles are in radians — did you mean {} rad ({v}°)?",
                v.to_radians()
            )));
        }
    }
    let p = Placement {
        x,
        y,
        z,
        yaw,
        nozzle_spin: spin,
    };
    p.check_metres().map_err(|e| err(format!("at: {e}")))?;
    Ok(p)
}

fn placement_tuple(p: &Placement) -> (f64, f64, f64, f64, f64) {
    (p.x, p.y, p.z, p.yaw, p.nozzle_spin)
}

fn feasibility_options(
    joint_margin: f64,
    wrist_margin: f64,
    collisions: bool,
    check_every: i64,
) -> PyRes<FeasibilityOptions> {
    if !(joint_margin.is_finite() && (0.0..=std::f64::consts::FRAC_PI_2).contains(&joint_margin)) {
        return Err(err(format!(
            "joint_margin = {joint_margin}: expected a margin in [0, π/2] rad"
        )));
    }
    let check_every: usize = int_arg("check_every", check_every, 1, 1_000_000)?;
    let o = FeasibilityOptions {
        joint_margin_rad: [joint_margin; printwatt::kinematics::MAX_DOF],
        wrist_margin_rad: wrist_margin,
        collisions,
        check_every,
        ..Default::default()
    };
    o.check().map_err(err)?;
    Ok(o)
}

// ---------------------------------------------------------------------------------------------
// JSON-mirroring dictionaries

/// A serialisable value as the Python object of its `--json` form: checked finite, numbers at
/// full precision (the JSON rounds them to 9 significant digits), `schema_version` added to
/// an object (docs/json.md).
fn json_obj<'py, T: serde::Serialize + ?Sized>(
    py: Python<'py>,
    what: &str,
    v: &T,
) -> PyRes<Bound<'py, PyAny>> {
    printwatt::output::check_finite_json(what, v).map_err(err)?;
    let mut j = serde_json::to_value(v).map_err(err)?;
    printwatt::output::stamp_json(&mut j);
    value_to_py(py, &j)
}

/// The same without `schema_version` (a part of a document).
fn json_part<'py, T: serde::Serialize + ?Sized>(
    py: Python<'py>,
    what: &str,
    v: &T,
) -> PyRes<Bound<'py, PyAny>> {
    printwatt::output::check_finite_json(what, v).map_err(err)?;
    let j = serde_json::to_value(v).map_err(err)?;
    value_to_py(py, &j)
}

fn value_to_py<'py>(py: Python<'py>, v: &serde_json::Value) -> PyRes<Bound<'py, PyAny>> {
    use serde_json::Value as V;
    Ok(match v {
        V::Null => py.None().into_bound(py),
        V::Bool(b) => b.into_pyobject(py)?.to_owned().into_any(),
        V::Number(n) => {
            if let Some(i) = n.as_i64() {
                i.into_pyobject(py)?.into_any()
            } else if let Some(u) = n.as_u64() {
                u.into_pyobject(py)?.into_any()
            } else {
                n.as_f64().unwrap_or(f64::NAN).into_pyobject(py)?.into_any()
            }
        }
        V::String(s) => s.into_pyobject(py)?.into_any(),
        V::Array(a) => {
            let l = PyList::empty(py);
            for x in a {
                l.append(value_to_py(py, x)?)?;
            }
            l.into_any()
        }
        V::Object(o) => {
            let d = PyDict::new(py);
            for (k, x) in o {
                d.set_item(k, value_to_py(py, x)?)?;
            }
            d.into_any()
        }
    })
}

/// Reader warnings as the `warnings` list of a `--json` document (`file`, `line`, `message`;
/// the line stays inside the message).
fn warnings_list<'py>(py: Python<'py>, items: &[(&str, &[String])]) -> PyRes<Bound<'py, PyList>> {
    let l = PyList::empty(py);
    for (file, ws) in items {
        for w in ws.iter() {
            let d = PyDict::new(py);
            d.set_item("file", *file)?;
            d.set_item("line", py.None())?;
            d.set_item("message", w)?;
            l.append(d)?;
        }
    }
    Ok(l)
}

/// A row-major `len × n` vector as an `(len, n)` array.
fn rows(v: Vec<f64>, n: usize) -> Array2<f64> {
    let len = v.len().checked_div(n).unwrap_or(0);
    Array2::from_shape_vec((len, n), v).unwrap_or_else(|_| Array2::zeros((0, n)))
}

// ---------------------------------------------------------------------------------------------
// energy

/// The energy of `path` printed at placement `at`: the path is timed as the controller runs
/// it (blended corners, acceleration and jerk limits, slowed where joint limits bind), joint
/// torques come from Newton–Euler, and friction, motor and drive losses are added.
///
/// robot: a `Robot` or a name/path for `load_robot`; path: a `Toolpath` or a file for
/// `load_path`; at: (x, y, z, yaw[, spin]) in m, m, m, rad, rad — the part frame's origin in
/// the robot base frame, its rotation about the vertical, and the nozzle's rotation about its
/// own axis. period: controller interpolation period, s (the sample period); accel: TCP
/// acceleration limit, m/s²; jerk: TCP jerk limit, m/s³; regeneration: none, per_axis,
/// dc_bus or grid (default: the drive file's); payload, friction: include them.
///
/// Returns a dict mirroring `printwatt energy --json` (`robot`, `input`, `placement`,
/// `print_time_s`, `slowdowns`, `energy` with `total` and `joints`; J, W, s, N·m) plus:
/// `supply_j` (J, total supply energy), `duration_s` (s), `joint_electrical_j` and
/// `joint_mechanical_j` ((dof,) arrays, J), and per-sample float64 arrays `t` (N,) s; `q`,
/// `qd`, `qdd` (N, dof) rad, rad/s, rad/s²; `tau` (N, dof) N·m; `current` (N, dof) A;
/// `p_mech`, `p_el` (N, dof) W; `p_supply` (N,) W. Raises PrintwattError for bad input or an
/// infeasible placement (with the reason, sample, time and source line).
#[pyfunction]
#[pyo3(signature = (robot, path, at, *, period = 0.004, accel = 1.0, jerk = 10.0,
    regeneration = None, payload = true, friction = true, proc = None))]
#[allow(clippy::too_many_arguments)]
fn energy<'py>(
    py: Python<'py>,
    robot: RobotArg<'py>,
    path: PathArg<'py>,
    at: &Bound<'py, PyAny>,
    period: f64,
    accel: f64,
    jerk: f64,
    regeneration: Option<String>,
    payload: bool,
    friction: bool,
    proc: Option<String>,
) -> PyRes<Bound<'py, PyDict>> {
    let robot = robot.hold()?;
    let path = path.hold(proc)?;
    let at = placement(&float_seq(at, "at", PLACEMENT_FORM)?)?;
    let prof = profile(period, accel, jerk)?;
    let opts = energy_options(regeneration.as_deref(), payload, friction)?;
    let model: &RobotModel = &robot;
    let tp: &Toolpath = &path;
    let ev = py
        .detach(|| -> printwatt::Result<_> {
            let job = PathJob::new(model, tp, opts, prof, JointStageOptions::default())?;
            job.evaluate(&at)
        })
        .map_err(err)?
        .map_err(|why| {
            err(format!(
                "placement ({}, {}, {}, {} rad, spin {} rad) is infeasible: {why}",
                at.x, at.y, at.z, at.yaw, at.nozzle_spin
            ))
        })?;
    let e = &ev.energy;
    check_series(e, &ev.timed.traj)?;
    // The `energy --json` document (numbers at full precision), the report without its
    // per-sample series (they are the arrays below). Checked finite on the typed values:
    // serde_json would turn a NaN into null.
    printwatt::output::check_finite_json("energy", e).map_err(err)?;
    printwatt::output::check_finite_json("energy: slowdowns", &ev.timed.slowdowns).map_err(err)?;
    let mut rep = serde_json::to_value(e).map_err(err)?;
    if let Some(o) = rep.as_object_mut() {
        o.remove("series");
    }
    let mut doc = serde_json::Map::new();
    doc.insert("robot".into(), model.name().into());
    doc.insert("input".into(), tp.source.clone().into());
    let pl: serde_json::Map<String, serde_json::Value> = [
        ("x_m", at.x),
        ("y_m", at.y),
        ("z_m", at.z),
        ("yaw_deg", at.yaw.to_degrees()),
        ("nozzle_spin_deg", at.nozzle_spin.to_degrees()),
    ]
    .into_iter()
    .map(|(k, v)| (k.to_string(), v.into()))
    .collect();
    doc.insert("placement".into(), pl.into());
    doc.insert("print_time_s".into(), e.duration_s.into());
    doc.insert(
        "slowdowns".into(),
        serde_json::to_value(&ev.timed.slowdowns).map_err(err)?,
    );
    doc.insert("output_csv".into(), serde_json::Value::Null);
    doc.insert("energy".into(), rep);
    let mut doc = serde_json::Value::Object(doc);
    printwatt::output::stamp_json(&mut doc);
    let d = value_to_py(py, &doc)?.cast_into::<PyDict>()?;
    d.set_item(
        "warnings",
        warnings_list(
            py,
            &[
                (&model.source.display().to_string(), &model.warnings),
                (&tp.source, &tp.warnings),
            ],
        )?,
    )?;
    // Exact (unrounded) figures and arrays for computing with.
    let n = e.series.n;
    d.set_item("supply_j", e.total.supply_j)?;
    d.set_item("duration_s", e.duration_s)?;
    d.set_item(
        "joint_electrical_j",
        PyArray1::from_vec(py, e.joints.iter().map(|j| j.electrical_j).collect()),
    )?;
    d.set_item(
        "joint_mechanical_j",
        PyArray1::from_vec(py, e.joints.iter().map(|j| j.mechanical_j).collect()),
    )?;
    let traj = &ev.timed.traj;
    d.set_item("t", PyArray1::from_vec(py, e.series.t.clone()))?;
    d.set_item("q", rows(traj.q.clone(), traj.n).into_pyarray(py))?;
    d.set_item("qd", rows(traj.qd.clone(), traj.n).into_pyarray(py))?;
    d.set_item("qdd", rows(traj.qdd.clone(), traj.n).into_pyarray(py))?;
    d.set_item("tau", rows(e.series.tau.clone(), n).into_pyarray(py))?;
    d.set_item(
        "current",
        rows(e.series.current.clone(), n).into_pyarray(py),
    )?;
    d.set_item("p_mech", rows(e.series.p_mech.clone(), n).into_pyarray(py))?;
    d.set_item("p_el", rows(e.series.p_el.clone(), n).into_pyarray(py))?;
    d.set_item(
        "p_supply",
        PyArray1::from_vec(py, e.series.p_supply.clone()),
    )?;
    Ok(d)
}

/// Every per-sample value finite, else an error naming the quantity and the sample.
fn check_series(
    e: &printwatt::EnergyReport,
    traj: &printwatt::trajectory::JointTrajectory,
) -> PyRes<()> {
    let s = &e.series;
    for (name, v, n) in [
        ("t", &s.t, 1),
        ("q", &traj.q, traj.n),
        ("qd", &traj.qd, traj.n),
        ("qdd", &traj.qdd, traj.n),
        ("tau", &s.tau, s.n),
        ("current", &s.current, s.n),
        ("p_mech", &s.p_mech, s.n),
        ("p_el", &s.p_el, s.n),
        ("p_supply", &s.p_supply, 1),
    ] {
        if let Some(i) = v.iter().position(|x| !x.is_finite()) {
            return Err(err(format!(
                "energy: `{name}` is {} at sample {}: the model produced a number that is not a number; check the robot's drive and inertia data",
                v[i],
                i / n.max(1)
            )));
        }
    }
    Ok(())
}

// ---------------------------------------------------------------------------------------------
// sweep and optimise

fn objective(s: &str) -> PyRes<Objective> {
    s.parse().map_err(err)
}

fn reason_counts(rows: &[Evaluated]) -> std::collections::BTreeMap<String, usize> {
    let mut m = std::collections::BTreeMap::new();
    for r in rows {
        if let Err(why) = &r.outcome {
            *m.entry(why.reason.name().to_string()).or_insert(0) += 1;
        }
    }
    m
}

fn axis(name: &str, v: Vec<f64>) -> PyRes<Vec<f64>> {
    if v.is_empty() {
        return Err(err(format!("{name}: expected at least one value")));
    }
    if let Some(x) = v.iter().find(|x| !x.is_finite()) {
        return Err(err(format!("{name}: {x} is not a finite number")));
    }
    Ok(v)
}

/// Evaluate the placements of `path` on the grid `xs` × `ys` (1-D sequences, m; the part
/// frame's origin in the robot base frame) at bed height `z` (m), part yaw `yaw` (rad) and
/// nozzle spin `spin` (rad), in parallel. Each cell is timed and checked for feasibility
/// (reach with one arm configuration, joint limits and `joint_margin` (rad, default 3°),
/// `wrist_margin` (rad, default 5°: q5 kept that far from 0 and ±π on every sample; 0 lets the
/// wrist pass through the singularity), the other singularity margins, collisions with bed,
/// part and itself every `check_every` samples).
/// objective: supply, drives, mechanical, mechanical_positive or mechanical_abs (J).
///
/// Returns a dict: `xs` (nx,) and `ys` (ny,) m; `energy_j` (nx, ny) float64, the objective in
/// J, NaN where infeasible; `reason` (nx lists of ny: None or the reason name); `best` (the
/// best evaluated placement as in `sweep --json`, or None); `infeasible_by_reason` (name →
/// count); `rows` (every evaluated placement, as `sweep --json`'s `rows`, x-major).
#[pyfunction]
#[pyo3(signature = (robot, path, xs, ys, *, z = 0.0, yaw = 0.0, spin = 0.0,
    objective = "supply", period = 0.004, accel = 1.0, jerk = 10.0,
    regeneration = None, payload = true, friction = true, joint_margin = 0.05235987755982989,
    wrist_margin = 0.08726646259971647,
    collisions = true, check_every = 10, proc = None))]
#[allow(clippy::too_many_arguments)]
fn sweep<'py>(
    py: Python<'py>,
    robot: RobotArg<'py>,
    path: PathArg<'py>,
    xs: &Bound<'py, PyAny>,
    ys: &Bound<'py, PyAny>,
    z: f64,
    yaw: f64,
    spin: f64,
    objective: &str,
    period: f64,
    accel: f64,
    jerk: f64,
    regeneration: Option<String>,
    payload: bool,
    friction: bool,
    joint_margin: f64,
    wrist_margin: f64,
    collisions: bool,
    check_every: i64,
    proc: Option<String>,
) -> PyRes<Bound<'py, PyDict>> {
    let robot = robot.hold()?;
    let path = path.hold(proc)?;
    let grid = Grid {
        xs: axis("xs", float_seq(xs, "xs", "a sequence of numbers (m)")?)?,
        ys: axis("ys", float_seq(ys, "ys", "a sequence of numbers (m)")?)?,
        zs: axis("z", vec![z])?,
        yaws: axis("yaw", vec![yaw])?,
        spins: axis("spin", vec![spin])?,
    };
    let obj = self::objective(objective)?;
    let prof = profile(period, accel, jerk)?;
    let opts = energy_options(regeneration.as_deref(), payload, friction)?;
    let feas = feasibility_options(joint_margin, wrist_margin, collisions, check_every)?;
    let model: &RobotModel = &robot;
    let tp: &Toolpath = &path;
    let ps = grid.placements();
    let rows_ev = py
        .detach(|| -> printwatt::Result<Vec<Evaluated>> {
            let job = PathJob::new(model, tp, opts, prof, JointStageOptions::default())?;
            let ev = Evaluator::new(&job, feas, obj);
            ev.sweep(&ps, &|_, _| {})
        })
        .map_err(err)?;
    let (nx, ny) = (grid.xs.len(), grid.ys.len());
    let mut e = Array2::from_elem((nx, ny), f64::NAN);
    let reason = PyList::empty(py);
    for ix in 0..nx {
        let row = PyList::empty(py);
        for iy in 0..ny {
            let r = &rows_ev[grid.index(ix, iy, 0, 0, 0)];
            match &r.outcome {
                Ok(f) => {
                    e[(ix, iy)] = f.energy_j;
                    row.append(py.None())?;
                }
                Err(why) => row.append(why.reason.name())?,
            }
        }
        reason.append(row)?;
    }
    let d = PyDict::new(py);
    d.set_item("schema_version", printwatt::output::JSON_SCHEMA_VERSION)?;
    d.set_item("objective", obj.name())?;
    d.set_item("xs", PyArray1::from_vec(py, grid.xs.clone()))?;
    d.set_item("ys", PyArray1::from_vec(py, grid.ys.clone()))?;
    d.set_item("energy_j", e.into_pyarray(py))?;
    d.set_item("reason", reason)?;
    d.set_item(
        "best",
        match popt::best_of(&rows_ev) {
            Some(b) => json_part(py, "sweep: best", b)?,
            None => py.None().into_bound(py),
        },
    )?;
    d.set_item(
        "feasible",
        rows_ev.iter().filter(|r| r.cost().is_finite()).count(),
    )?;
    d.set_item(
        "infeasible_by_reason",
        json_part(py, "sweep: reasons", &reason_counts(&rows_ev))?,
    )?;
    d.set_item("rows", json_part(py, "sweep: rows", &rows_ev)?)?;
    Ok(d)
}

/// The minimum-energy placement of `path`, as `printwatt optimise` finds it (the same library
/// job, the same defaults): a grid (`xs`, `ys`, `zs` in m, `yaws` and `spins` in rad; each
/// defaults to the command's grid: 16 cells over the reach in x and y, bed heights 0, R/4,
/// R/2, yaws 0 and π/2, spin 0), then the refinement `search` (`nelder-mead`: argmin over x,
/// y, z (within `z_bounds` (min, max) m, default the grid's z range), yaw and spin; or
/// `pattern`) within `max_evals` evaluations, seeded by `seed`. The answer must hold
/// `tolerance` (±xy m, ±z m, ±yaw rad; every corner of that box re-evaluated; (0, 0, 0)
/// switches it off; default ±20 mm, ±1°). `evaluation`: `auto` (a long repeating path is
/// evaluated on representative layers and the answer re-evaluated in full), `full` or
/// `reduced`. `baseline`: (x, y, z, yaw[, spin]) m and rad, compared with the answer
/// (default: the feasible grid cell nearest the centre of the feasible region);
/// `uncertainty`: draws of the uncertainty study (seeded by `seed`); with it, the robust
/// choice minimises `robust` over the drawn robots (`expected`: the expected energy, default;
/// `regret`: the worst-case regret), with yearly figures at `prints_per_year` and
/// `grid_kg_co2_per_kwh` (kg CO₂ per kWh). Options as in `sweep`.
///
/// Returns a dict: `placement` (x, y, z, yaw, spin) in m, m, m, rad, rad; `energy_j` (the
/// objective, J); `supply_j` (J); `duration_s` (s); `best` and `best_grid` (evaluated
/// placements as in `optimise --json`); `evaluations` (grid, refinement); `feasible` and
/// `placements` (grid counts); `infeasible_by_reason` (name → count over the grid);
/// `search` (method, tolerance check, bounds, `on_bounds`, joint and wrist margins kept);
/// `summary` (the document `printwatt optimise --json` prints: baseline, savings, the
/// baseline's tolerance check, the full check of a reduced answer, the uncertainty study and
/// the decision: the robust choice, the value of measuring each parameter, bound steps, and
/// with `pareto=True` print time against energy over the acceleration and jerk limits, and
/// unless `margin_trade=False` the answer found again with other joint and wrist margins).
/// Raises PrintwattError when no grid placement is feasible, with how many failed for each
/// reason and what to try.
#[pyfunction]
#[pyo3(signature = (robot, path, *, xs = None, ys = None, zs = None, yaws = None,
    spins = None, objective = "supply", tolerance = None, z_bounds = None,
    max_evals = 120,
    seed = 42, fixed_yaw = false, fixed_spin = false,
    search = "nelder-mead", evaluation = "auto", baseline = None,
    uncertainty = None, robust = "expected",
    prints_per_year = 1000.0,
    grid_kg_co2_per_kwh = 0.4,
    pareto = false, margin_trade = true, period = 0.004, accel = 1.0, jerk = 10.0, regeneration = None,
    payload = true, friction = true, joint_margin = 0.05235987755982989,
    wrist_margin = 0.08726646259971647, collisions = true,
    check_every = 10, proc = None))]
#[allow(clippy::too_many_arguments)]
fn optimise<'py>(
    py: Python<'py>,
    robot: RobotArg<'py>,
    path: PathArg<'py>,
    xs: Option<Vec<f64>>,
    ys: Option<Vec<f64>>,
    zs: Option<Vec<f64>>,
    yaws: Option<Vec<f64>>,
    spins: Option<Vec<f64>>,
    objective: &str,
    tolerance: Option<(f64, f64, f64)>,
    z_bounds: Option<(f64, f64)>,
    max_evals: i64,
    seed: i64,
    fixed_yaw: bool,
    fixed_spin: bool,
    search: &str,
    evaluation: &str,
    baseline: Option<&Bound<'py, PyAny>>,
    uncertainty: Option<usize>,
    robust: &str,
    prints_per_year: f64,
    grid_kg_co2_per_kwh: f64,
    pareto: bool,
    margin_trade: bool,
    period: f64,
    accel: f64,
    jerk: f64,
    regeneration: Option<String>,
    payload: bool,
    friction: bool,
    joint_margin: f64,
    wrist_margin: f64,
    collisions: bool,
    check_every: i64,
    proc: Option<String>,
) -> PyRes<Bound<'py, PyDict>> {
    let robot = robot.hold()?;
    let path = path.hold(proc)?;
    let model: &RobotModel = &robot;
    let tp: &Toolpath = &path;
    let def = popt::default_grid(feasibility::reach_m(model));
    let grid = Grid {
        xs: axis("xs", xs.unwrap_or(def.xs))?,
        ys: axis("ys", ys.unwrap_or(def.ys))?,
        zs: axis("zs", zs.unwrap_or(def.zs))?,
        yaws: axis("yaws", yaws.unwrap_or(def.yaws))?,
        spins: axis("spins", spins.unwrap_or(def.spins))?,
    };
    let settings =
        OptimiseSettings {
            objective: self::objective(objective)?,
            feasibility: feasibility_options(joint_margin, wrist_margin, collisions, check_every)?,
            energy: energy_options(regeneration.as_deref(), payload, friction)?,
            profile: profile(period, accel, jerk)?,
            evaluation: evaluation.parse().map_err(err)?,
            baseline: baseline
                .map(|b| float_seq(b, "baseline", PLACEMENT_FORM).and_then(|v| placement(&v)))
                .transpose()?,
            seed: int_arg("seed", seed, 0, i64::MAX)?,
            max_evals: int_arg("max_evals", max_evals, 0, 100_000_000)?,
            fixed_yaw,
            fixed_spin,
            search: search.parse().map_err(err)?,
            tolerance: tolerance.map_or_else(Tolerance::default, |(xy_m, z_m, yaw_rad)| {
                Tolerance { xy_m, z_m, yaw_rad }
            }),
            z_bounds: z_bounds.map(|(a, b)| [a, b]),
            uncertainty,
            robust: robust.parse().map_err(err)?,
            prints_per_year,
            grid_kg_co2_per_kwh,
            pareto,
            margin_trade,
        };
    settings.check().map_err(err)?;
    let cfg = OptimiseConfig {
        robot: model.clone(),
        path: tp.clone(),
        path_file: PathBuf::from(&tp.source),
        placements: Some(PlacementSet::grid(grid)),
        settings,
    };
    let out = py
        .detach(|| printwatt::search::run(&cfg, &printwatt::search::Silent))
        .map_err(err)?;
    let rep = &out.report;
    let res = rep
        .optimise
        .as_ref()
        .ok_or_else(|| err("optimise: no answer"))?;
    let best = res
        .best
        .feasible()
        .ok_or_else(|| err("optimise: the answer is infeasible"))?;
    let d = PyDict::new(py);
    d.set_item("schema_version", printwatt::output::JSON_SCHEMA_VERSION)?;
    d.set_item("objective", cfg.settings.objective.name())?;
    d.set_item("placement", placement_tuple(&res.best.placement))?;
    d.set_item("energy_j", best.energy_j)?;
    d.set_item("supply_j", best.supply_j)?;
    d.set_item("duration_s", best.duration_s)?;
    d.set_item("best", json_part(py, "optimise: best", &res.best)?)?;
    d.set_item(
        "best_grid",
        json_part(py, "optimise: best_grid", &res.best_grid)?,
    )?;
    d.set_item("evaluations", (rep.rows.len(), res.evals))?;
    d.set_item("placements", rep.rows.len())?;
    d.set_item(
        "feasible",
        rep.rows.iter().filter(|r| r.cost().is_finite()).count(),
    )?;
    d.set_item(
        "infeasible_by_reason",
        json_part(py, "optimise: reasons", &reason_counts(&rep.rows))?,
    )?;
    d.set_item(
        "search",
        match &res.search {
            Some(s) => json_part(py, "optimise: search", s)?,
            None => py.None().into_bound(py),
        },
    )?;
    d.set_item("history_j", PyArray1::from_vec(py, res.history_j.clone()))?;
    let summary: serde_json::Value =
        serde_json::from_str(&rep.summary_json(false).map_err(err)?).map_err(err)?;
    d.set_item("summary", value_to_py(py, &summary)?)?;
    Ok(d)
}

// ---------------------------------------------------------------------------------------------
// compare, diagnose, identify

/// Robot, model (effects switched) and log, as the command line's compare/diagnose/identify.
fn load_log_model(
    robot: &RobotModel,
    log: &Path,
    effects: Option<&str>,
    without: Option<&str>,
    columns: Option<&str>,
) -> PyRes<(Model, Log)> {
    let mut model = Model::new(robot).map_err(err)?;
    pid::switch_effects(&mut model, robot.dof(), effects, without).map_err(err)?;
    let l = pid::read_log_for(robot, log, columns).map_err(err)?;
    Ok((model, l))
}

/// Compare the model with a measured log (docs/measurement-logs.md: `t`, `q1..qN`, and one of
/// `tau`, `i`, `p`, `p_total`; units in brackets, SI by default). effects: comma list of the
/// catalogue effects switched on (default: the drive file's; `viscous[2]`: on joint 2 only);
/// without: effects switched off (`viscous[2]`: off on joint 2 only);
/// columns: a column map for a log without header. Returns a dict mirroring `printwatt
/// compare --json` (RMSE and measured RMS in the signal's unit, energies in J, errors in %,
/// windows in s).
#[pyfunction]
#[pyo3(signature = (robot, log, *, effects = None, without = None, columns = None))]
fn compare<'py>(
    py: Python<'py>,
    robot: RobotArg<'py>,
    log: PathBuf,
    effects: Option<String>,
    without: Option<String>,
    columns: Option<String>,
) -> PyRes<Bound<'py, PyAny>> {
    let robot = robot.hold()?;
    let (model, l) = load_log_model(
        &robot,
        &log,
        effects.as_deref(),
        without.as_deref(),
        columns.as_deref(),
    )?;
    let mut cmp = py
        .detach(|| -> printwatt::Result<_> {
            let prep = Prepared::new(&model, &l)?;
            Ok(metrics::compare_metrics(&prep, &model))
        })
        .map_err(err)?;
    cmp.calibration = robot.effects.calibration_summary();
    let d = json_obj(py, "compare", &cmp)?;
    add_warnings(py, &d, &robot, &l)?;
    Ok(d)
}

fn add_warnings(py: Python<'_>, d: &Bound<'_, PyAny>, robot: &RobotModel, l: &Log) -> PyRes<()> {
    d.set_item(
        "warnings",
        warnings_list(
            py,
            &[
                (&robot.source.display().to_string(), &robot.warnings),
                (&l.file, &l.warnings),
            ],
        )?,
    )
}

/// Rank the catalogue's physical effects by how much of the model's residual on `log` each
/// explains on held-out time blocks (`folds` of them), with BIC and plausibility. Returns a
/// dict mirroring `printwatt diagnose --json` (RMSE and noise floor in the signal's unit,
/// times in s, parameters with their units).
#[pyfunction]
#[pyo3(signature = (robot, log, *, folds = 5, effects = None, without = None, columns = None))]
fn diagnose<'py>(
    py: Python<'py>,
    robot: RobotArg<'py>,
    log: PathBuf,
    folds: i64,
    effects: Option<String>,
    without: Option<String>,
    columns: Option<String>,
) -> PyRes<Bound<'py, PyAny>> {
    let folds: usize = int_arg("folds", folds, 2, 100)?;
    let robot = robot.hold()?;
    let (mut model, l) = load_log_model(
        &robot,
        &log,
        effects.as_deref(),
        without.as_deref(),
        columns.as_deref(),
    )?;
    let mut dg = py
        .detach(|| -> printwatt::Result<_> {
            let prep = Prepared::new(&model, &l)?;
            pid::diagnose::diagnose(&prep, &mut model, folds)
        })
        .map_err(err)?;
    dg.calibration = robot.effects.calibration_summary();
    let d = json_obj(py, "diagnose", &dg)?;
    add_warnings(py, &d, &robot, &l)?;
    Ok(d)
}

/// robot: a shipped name or a path (not a loaded `Robot`: the calibrated file records where
/// the robot came from). Fit the parameters of `effects` (comma list of catalogue names, in ladder order, e.g.
/// "coulomb,balancer"; `viscous[2]`: joint 2 only) on `log`, validated on `validate_log` or
/// the last 25 % of `log`. A calibrated robot's earlier effects are re-fitted jointly.
/// The calibrated robot (a drive .toml) is always written, as `printwatt identify` writes it:
/// to `drive_out`, else `<name>.calibrated.toml` in `out` or the current directory (an existing
/// file is replaced only with `force`; never into the shipped robots); a fit that is not
/// physically plausible writes nothing and raises `PrintwattError` naming the parameters.
/// `out`: a directory for the round's report (`report.html`, `ladder.svg`, `ladder.md`,
/// `identify.json`), as `printwatt identify --out` writes it. Returns a dict mirroring
/// `printwatt identify --json` (`identification` with the ladder (RMSE in the signal's unit,
/// energy error in %) and the parameters with their units; `calibrated_robot`: the file
/// written).
#[pyfunction]
#[pyo3(signature = (robot, log, effects, *, validate_log = None, drive_out = None,
    force = false, columns = None, out = None))]
#[allow(clippy::too_many_arguments)]
fn identify<'py>(
    py: Python<'py>,
    robot: PathBuf,
    log: PathBuf,
    effects: String,
    validate_log: Option<PathBuf>,
    drive_out: Option<PathBuf>,
    force: bool,
    columns: Option<String>,
    out: Option<PathBuf>,
) -> PyRes<Bound<'py, PyAny>> {
    let resolved = printwatt::robot::shipped::resolve(&robot).unwrap_or_else(|| robot.clone());
    let rm = load_robot_model(&robot, None)?;
    let (mut model, l) = load_log_model(&rm, &log, None, None, columns.as_deref())?;
    let plan = pid::RoundPlan::new(&rm, &model, &effects, l.kind).map_err(err)?;
    // Where the calibrated robot goes (checked against every input by the round, first).
    let dst = drive_out.clone().unwrap_or_else(|| {
        out.clone()
            .unwrap_or_else(|| PathBuf::from("."))
            .join(pid::calibrate::default_file_name(&resolved))
    });
    let mut inputs = printwatt::output::Inputs::new();
    inputs.add_robot(&resolved, Some(&rm));
    inputs.add(&log);
    if let Some(v) = &validate_log {
        inputs.add(v);
    }
    let vlog = match &validate_log {
        Some(p) => Some(pid::read_log_for(&rm, p, columns.as_deref()).map_err(err)?),
        None => None,
    };
    let installed = robots_dir();
    let job = pid::RoundJob {
        robot: &rm,
        robot_arg: &robot.display().to_string(),
        resolved: &resolved,
        log: &l,
        validation: vlog.as_ref(),
        plan: &plan,
        calibrated_to: &dst,
        installed: Some(&installed),
        force,
        report_dir: out.as_deref(),
        inputs: &inputs,
    };
    let round = py
        .detach(|| pid::run_round(&job, &mut model, &pid::NoProgress))
        .map_err(err)?;
    if let Some(refused) = round.refusal() {
        return Err(err(refused));
    }
    let id = round.id;
    let doc = serde_json::json!({
        "schema_version": printwatt::output::JSON_SCHEMA_VERSION,
        "identification": serde_json::to_value(&id).map_err(err)?,
        "calibrated_robot": dst.display().to_string(),
        "started_from": rm.effects.calibration_summary(),
        "refitted_from_earlier_rounds": plan.carried,
    });
    let d = json_obj(py, "identify", &doc)?;
    add_warnings(py, &d, &rm, &l)?;
    Ok(d)
}

// ---------------------------------------------------------------------------------------------
// stations

/// A multi-station plan for a path larger than one placement's reach, as `printwatt stations`
/// makes it: the path is split at travel moves and layer changes, every run of units is
/// evaluated from every candidate station (a grid every `station_step` m over the path's
/// footprint widened by the reach, or every `station_step` m along `track` ((x0, y0), (x1, y1))
/// m in the part frame), and dynamic programming minimises the segments' energy plus
/// `relocation_cost` J per relocation and `relocation_cost_per_m` J/m. `headings`: None faces
/// each segment's centroid, else a list of headings (rad, part frame), each a candidate. `z`:
/// the part origin's height above each station's base frame, m (default −0.5). `footprint`:
/// the radius of the floor disc a station occupies, m (default 0.2 × reach, an estimate): no
/// station stands on a wall printed before or by its segment, no way between stations crosses
/// one (the straight line on a track, the shortest way around the walls otherwise), no track
/// lies under one. Options as in `sweep`.
///
/// Returns a dict: the plan (`segments` with `units`, `moves`, `lines`, `station` (`x_m`,
/// `y_m`, `heading_rad`), `print_length_m`, `eval` (the segment's numbers, J and s);
/// `relocations`, `relocation_distance_m`, `ways` (per relocation: `points`, the polyline
/// in m, and `length_m`), `relocation_j`, `energy_j`, `total_j`, `units`, `stats`), plus `at` (per segment, the placement (x, y, z, yaw, spin) in m and rad that the
/// station amounts to, what `energy` takes) and `footprint_m`. Raises PrintwattError when no
/// plan prints the path, naming the first unit that cannot be printed and why.
#[pyfunction]
#[pyo3(signature = (robot, path, *, relocation_cost, relocation_cost_per_m = 0.0,
    station_step = 0.5, track = None, headings = None, z = -0.5, spin = 0.0, footprint = None,
    objective = "supply", period = 0.004, accel = 1.0, jerk = 10.0,
    regeneration = None, payload = true, friction = true, joint_margin = 0.05235987755982989,
    wrist_margin = 0.08726646259971647,
    collisions = true, check_every = 10, proc = None),
    // Written out: `z`'s default is negative, which the signature above cannot show.
    text_signature = "(robot, path, *, relocation_cost, relocation_cost_per_m=0.0, \
    station_step=0.5, track=None, headings=None, z=-0.5, spin=0.0, footprint=None, \
    objective='supply', period=0.004, accel=1.0, jerk=10.0, regeneration=None, payload=True, \
    friction=True, joint_margin=0.05235987755982989, wrist_margin=0.08726646259971647, \
    collisions=True, check_every=10, proc=None)")]
#[allow(clippy::too_many_arguments)]
fn stations<'py>(
    py: Python<'py>,
    robot: RobotArg<'py>,
    path: PathArg<'py>,
    relocation_cost: f64,
    relocation_cost_per_m: f64,
    station_step: f64,
    track: Option<([f64; 2], [f64; 2])>,
    headings: Option<Vec<f64>>,
    z: f64,
    spin: f64,
    footprint: Option<f64>,
    objective: &str,
    period: f64,
    accel: f64,
    jerk: f64,
    regeneration: Option<String>,
    payload: bool,
    friction: bool,
    joint_margin: f64,
    wrist_margin: f64,
    collisions: bool,
    check_every: i64,
    proc: Option<String>,
) -> PyRes<Bound<'py, PyAny>> {
    use printwatt::stations::{self as pst, Headings, Sites, StationsJob};
    let robot = robot.hold()?;
    let path = path.hold(proc)?;
    let model: &RobotModel = &robot;
    let tp: &Toolpath = &path;
    let job = StationsJob {
        energy: energy_options(regeneration.as_deref(), payload, friction)?,
        profile: profile(period, accel, jerk)?,
        feasibility: feasibility_options(joint_margin, wrist_margin, collisions, check_every)?,
        objective: self::objective(objective)?,
        sites: match track {
            Some((from, to)) => Sites::Track {
                from,
                to,
                step_m: station_step,
            },
            None => Sites::Grid {
                step_m: station_step,
            },
        },
        headings: headings.map_or(Headings::Auto, Headings::Fixed),
        z_m: z,
        spin_rad: spin,
        relocation_j_per_m: relocation_cost_per_m,
        footprint_m: footprint,
        ..StationsJob::new(model, tp, relocation_cost)
    };
    let outcome = py.detach(|| pst::run(&job, &|_, _| {})).map_err(err)?;
    let plan = outcome.plan;
    let d = json_obj(py, "stations", &plan)?;
    let at: Vec<_> = plan
        .segments
        .iter()
        .map(|s| placement_tuple(&s.station.placement))
        .collect();
    d.set_item("at", at)?;
    d.set_item("footprint_m", outcome.footprint_m)?;
    Ok(d)
}

// ---------------------------------------------------------------------------------------------

/// printwatt: where to put a 3D concrete print so the robot arm spends the least energy, and
/// how well the energy model agrees with what the robot measured. SI units throughout (m, rad,
/// s, kg, N·m, W, J); see docs/python.md.
#[pymodule]
#[pyo3(name = "printwatt")]
fn printwatt_py(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("PrintwattError", m.py().get_type::<PrintwattError>())?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add_class::<Robot>()?;
    m.add_class::<Toolpath_>()?;
    m.add_function(wrap_pyfunction!(load_robot, m)?)?;
    m.add_function(wrap_pyfunction!(shipped_robots, m)?)?;
    m.add_function(wrap_pyfunction!(load_path, m)?)?;
    m.add_function(wrap_pyfunction!(path_from_points, m)?)?;
    m.add_function(wrap_pyfunction!(energy, m)?)?;
    m.add_function(wrap_pyfunction!(sweep, m)?)?;
    m.add_function(wrap_pyfunction!(optimise, m)?)?;
    m.add_function(wrap_pyfunction!(compare, m)?)?;
    m.add_function(wrap_pyfunction!(diagnose, m)?)?;
    m.add_function(wrap_pyfunction!(identify, m)?)?;
    m.add_function(wrap_pyfunction!(stations, m)?)?;
    Ok(())
}
