//! The hand-off for a Universal Robots arm: one URScript program (`path_base.script`) that a
//! UR controller runs as is, and the reader that checks it ([`read_urscript`]).
//!
//! The program sets the tool centre point at the nozzle tip (`set_tcp`) and the print head's
//! load with its inertia (`set_target_payload`, PolyScope 5.10 or later), moves in joint
//! space to the planned first sample (`movej`: this hands over the arm configuration printwatt
//! evaluated: a UR `movel` keeps the configuration it starts in), then one `movel` per point
//! of the base-frame path, with the move's TCP speed, the profile's TCP acceleration and the
//! move's corner zone as the blend radius.
//!
//! **Frames.** Poses are in the controller's base frame, which ROS-Industrial's UR
//! descriptions place at the URDF `base_link` turned 180° about z (`base_link` → `base`):
//! x and y change sign. Joint angles are the URDF's (zero at the same pose). Orientations are
//! rotation vectors (axis × angle, rad), as URScript poses take them.
//!
//! **Wrist singularity.** A UR controller stops a linear move that passes near the wrist
//! singularity (a protective stop "close to singularity"); there is no `SingArea` to allow
//! it. With a wrist margin the program says how far the wrist stays; without one (a round
//! nozzle makes axis 6 free) it says where a stop may happen and what to do instead.

use super::{BasePoint, JointPlan};
use crate::error::{Error, Result};
use crate::frame::Placement;
use crate::math::{M3, V3};
use crate::robot::RobotModel;

/// The arm is a Universal Robots arm (its drive file's or URDF's name says so).
pub fn is_universal_robots(model: &RobotModel) -> bool {
    let n = model.name().to_ascii_lowercase();
    n.contains("universal robots")
        || n.starts_with("ur3")
        || n.starts_with("ur5")
        || n.starts_with("ur10")
        || n.starts_with("ur16")
        || n.starts_with("ur20")
        || n.starts_with("ur30")
}

/// The controller's base frame in the URDF base frame's terms: 180° about z.
fn to_controller(p: &V3) -> V3 {
    V3::new(-p.x, -p.y, p.z)
}

fn rot_to_controller(r: &M3) -> M3 {
    M3::new(-1.0, 0.0, 0.0, 0.0, -1.0, 0.0, 0.0, 0.0, 1.0) * r
}

/// A rotation matrix as a rotation vector (axis × angle, rad).
pub(crate) fn rotation_vector(r: &M3) -> V3 {
    let q = nalgebra::UnitQuaternion::from_matrix(r);
    q.scaled_axis()
}

/// A rotation vector (axis × angle, rad) as a rotation matrix.
pub(crate) fn rotation_of(v: &V3) -> M3 {
    *nalgebra::Rotation3::new(*v).matrix()
}

fn pose(p: &V3, r: &M3) -> String {
    let v = rotation_vector(r);
    format!(
        "p[{:.6}, {:.6}, {:.6}, {:.6}, {:.6}, {:.6}]",
        p.x, p.y, p.z, v.x, v.y, v.z
    )
}

/// The URScript program of `points` (the base-frame path at `at`) with the joints of `plan`,
/// for `model`, moving with TCP acceleration `accel` (m/s²).
pub fn urscript(
    points: &[BasePoint],
    at: &Placement,
    model: &RobotModel,
    plan: &JointPlan,
    accel: f64,
) -> String {
    let mut s = String::new();
    s.push_str("def printwatt_path():\n");
    s.push_str(&format!(
        "  # printwatt: path of {} re-expressed in the controller's base frame (m, rad)\n",
        model.name()
    ));
    s.push_str(&format!(
        "  # placement: x = {:.4} m, y = {:.4} m, z = {:.4} m, part yaw = {:.4} deg, nozzle spin = {:.4} deg (URDF base_link frame)\n",
        at.x,
        at.y,
        at.z,
        at.yaw.to_degrees(),
        at.nozzle_spin.to_degrees()
    ));
    s.push_str(
        "  # base: the URDF base_link turned 180 deg about z (ROS-Industrial UR convention)\n",
    );
    if plan.wrist_through {
        s.push_str("  # wrist: the plan may pass through the wrist singularity (wrist margin 0); a UR controller\n");
        s.push_str("  # stops a movel close to it (protective stop): keep a wrist margin, or run those moves with movej\n");
    } else {
        let min5 = plan
            .points
            .iter()
            .chain(std::iter::once(&plan.start))
            .filter_map(|q| q.get(4))
            .map(|q5| q5.sin().abs().asin().to_degrees())
            .fold(f64::INFINITY, f64::min);
        s.push_str(&format!(
            "  # wrist: axis 5 stays at least {min5:.2} deg from the wrist singularity at the exported points\n"
        ));
    }
    tool_lines(&mut s, model);
    let q0: Vec<String> = plan.start.iter().map(|v| format!("{v:.6}")).collect();
    s.push_str(&format!(
        "  # start: the planned first sample's joints (rad)\n  movej([{}], a=1.0, v=0.5)\n",
        q0.join(", ")
    ));
    let spin = at.nozzle_yaw();
    let mut line = 0;
    for b in points {
        if b.line != line {
            s.push_str(&format!("  # source line {}\n", b.line));
            line = b.line;
        }
        let t = crate::kinematics::nozzle_target(&b.p, spin);
        s.push_str(&format!(
            "  movel({}, a={:.4}, v={:.6}, r={:.4})\n",
            pose(&to_controller(&t.pos), &rot_to_controller(&t.rot)),
            accel,
            b.speed.max(1e-4),
            b.zone
        ));
    }
    s.push_str("end\nprintwatt_path()\n");
    s
}

/// Write the program's tool lines: `set_tcp`, and `set_target_payload` when the robot
/// carries a payload.
fn tool_lines(s: &mut String, model: &RobotModel) {
    s.push_str(&format!(
        "  set_tcp({})\n",
        pose(&model.tool.pos, &model.tool.rot)
    ));
    if let Some(p) = model.payload.filter(|p| p.mass > 0.0) {
        let i = p.inertia;
        s.push_str(&format!(
            "  set_target_payload({:.4}, [{:.6}, {:.6}, {:.6}], [{:.6}, {:.6}, {:.6}, {:.6}, {:.6}, {:.6}])\n",
            p.mass,
            p.com.x,
            p.com.y,
            p.com.z,
            i[(0, 0)],
            i[(1, 1)],
            i[(2, 2)],
            i[(0, 1)],
            i[(0, 2)],
            i[(1, 2)]
        ));
    }
}

/// One `movel` of a URScript program.
#[derive(Clone, Debug, PartialEq)]
pub struct UrMove {
    /// TCP position in the controller's base frame, m.
    pub p: V3,
    /// TCP rotation vector in the controller's base frame, rad.
    pub r: V3,
    /// TCP acceleration, m/s².
    pub a: f64,
    /// TCP speed, m/s.
    pub v: f64,
    /// Blend radius, m.
    pub blend: f64,
    /// Line in the program.
    pub line: usize,
}

impl UrMove {
    /// The TCP position in the URDF base frame, m.
    pub fn p_urdf_base(&self) -> V3 {
        to_controller(&self.p)
    }

    /// The TCP rotation in the URDF base frame.
    pub fn rot_urdf_base(&self) -> M3 {
        rot_to_controller(&rotation_of(&self.r))
    }
}

/// What [`read_urscript`] read.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct UrProgram {
    /// The name of the function defined.
    pub name: String,
    /// The `set_tcp` pose (x, y, z m; rotation vector rad).
    pub tcp: Option<[f64; 6]>,
    /// `set_target_payload`: mass (kg), centre of mass (m), inertia (kg·m²: Ixx, Iyy, Izz,
    /// Ixy, Ixz, Iyz).
    pub payload: Option<(f64, [f64; 3], [f64; 6])>,
    /// Joint targets of the `movej`s, rad.
    pub movej: Vec<[f64; 6]>,
    /// The `movel`s, in order.
    pub movel: Vec<UrMove>,
    /// The defined function is called after its definition.
    pub called: bool,
}

/// Read a URScript program of the subset printwatt writes: `def NAME():` … `end` with
/// `set_tcp`, `set_target_payload`, `movej`, `movel`, `textmsg` and comments, then `NAME()`.
/// Anything else is an error naming the file and line.
pub fn read_urscript(text: &str, file: &str) -> Result<UrProgram> {
    let err = |line: usize, m: String| Error::Invalid(format!("{file}:{line}: {m}"));
    let mut prog = UrProgram::default();
    let mut inside = false;
    let mut ended = false;
    for (k, raw) in text.lines().enumerate() {
        let n = k + 1;
        let l = raw.trim();
        if l.is_empty() || l.starts_with('#') {
            continue;
        }
        if !inside && !ended {
            let name = l
                .strip_prefix("def ")
                .and_then(|r| r.strip_suffix("():"))
                .ok_or_else(|| err(n, format!("expected `def NAME():`, found `{l}`")))?;
            if name.is_empty() || !name.chars().all(|c| c.is_ascii_alphanumeric() || c == '_') {
                return Err(err(n, format!("bad function name `{name}`")));
            }
            prog.name = name.to_string();
            inside = true;
            continue;
        }
        if ended {
            if l == format!("{}()", prog.name) && !prog.called {
                prog.called = true;
                continue;
            }
            return Err(err(n, format!("unexpected `{l}` after `end`")));
        }
        if l == "end" {
            inside = false;
            ended = true;
            continue;
        }
        if !raw.starts_with("  ") {
            return Err(err(n, "a statement inside `def` must be indented".into()));
        }
        let (fname, args) = l
            .strip_suffix(')')
            .and_then(|r| r.split_once('('))
            .ok_or_else(|| err(n, format!("expected a call `name(…)`, found `{l}`")))?;
        let args = split_args(args).map_err(|m| err(n, m))?;
        read_statement(&mut prog, fname, &args, n).map_err(|m| err(n, m))?;
    }
    if inside {
        return Err(Error::Invalid(format!(
            "{file}: `def {}():` has no `end`",
            prog.name
        )));
    }
    if prog.name.is_empty() {
        return Err(Error::Invalid(format!("{file}: no `def NAME():` found")));
    }
    Ok(prog)
}

/// Read the statement `fname(args)` at line `line` inside the program's `def` into `prog`;
/// an error says what is wrong with it.
fn read_statement(
    prog: &mut UrProgram,
    fname: &str,
    args: &[String],
    line: usize,
) -> std::result::Result<(), String> {
    match fname {
        "set_tcp" => {
            let [a] = args else {
                return Err("set_tcp takes one pose".into());
            };
            prog.tcp = Some(pose_arg(a)?);
        }
        "set_target_payload" => {
            let [m, c, i] = args else {
                return Err("set_target_payload takes mass, centre of gravity and inertia".into());
            };
            prog.payload = Some((number(m)?, list::<3>(c)?, list::<6>(i)?));
        }
        "movej" => {
            let (pos, kw) = positional(args, &["a", "v"])?;
            let _ = kw;
            prog.movej.push(list::<6>(pos)?);
        }
        "movel" => {
            let (pos, kw) = positional(args, &["a", "v", "r"])?;
            let p = pose_arg(pos)?;
            let get = |k: &str| kw.iter().find(|(n, _)| *n == k).map(|(_, v)| *v);
            prog.movel.push(UrMove {
                p: V3::new(p[0], p[1], p[2]),
                r: V3::new(p[3], p[4], p[5]),
                a: get("a").unwrap_or(1.2),
                v: get("v").unwrap_or(0.25),
                blend: get("r").unwrap_or(0.0),
                line,
            });
        }
        "textmsg" => {}
        other => return Err(format!("unsupported statement `{other}(…)`")),
    }
    Ok(())
}

/// Split call arguments at top-level commas.
fn split_args(s: &str) -> std::result::Result<Vec<String>, String> {
    let mut out = Vec::new();
    let mut depth = 0i32;
    let mut cur = String::new();
    for c in s.chars() {
        match c {
            '[' | '(' => depth += 1,
            ']' | ')' => depth -= 1,
            _ => {}
        }
        if depth < 0 {
            return Err("unbalanced brackets".into());
        }
        if c == ',' && depth == 0 {
            out.push(cur.trim().to_string());
            cur.clear();
        } else {
            cur.push(c);
        }
    }
    if depth != 0 {
        return Err("unbalanced brackets".into());
    }
    if !cur.trim().is_empty() {
        out.push(cur.trim().to_string());
    }
    Ok(out)
}

type Keywords<'a> = Vec<(&'a str, f64)>;

/// The one positional argument and the keyword arguments (only `allowed` names).
fn positional<'a>(
    args: &'a [String],
    allowed: &[&'a str],
) -> std::result::Result<(&'a str, Keywords<'a>), String> {
    let (first, rest) = args.split_first().ok_or("a target is needed")?;
    if first.contains('=') {
        return Err("the target must come first".into());
    }
    let mut kw = Vec::new();
    for a in rest {
        let (k, v) = a
            .split_once('=')
            .ok_or_else(|| format!("expected name=value, found `{a}`"))?;
        let k = k.trim();
        let Some(name) = allowed.iter().find(|n| **n == k) else {
            return Err(format!("unknown argument `{k}`"));
        };
        kw.push((*name, number(v)?));
    }
    Ok((first, kw))
}

fn number(s: &str) -> std::result::Result<f64, String> {
    let v: f64 = s
        .trim()
        .parse()
        .map_err(|_| format!("`{}` is not a number", s.trim()))?;
    if v.is_finite() {
        Ok(v)
    } else {
        Err(format!("`{}` is not finite", s.trim()))
    }
}

fn list<const N: usize>(s: &str) -> std::result::Result<[f64; N], String> {
    let inner = s
        .trim()
        .strip_prefix('[')
        .and_then(|r| r.strip_suffix(']'))
        .ok_or_else(|| format!("expected a list [..], found `{s}`"))?;
    let v: Vec<f64> = inner
        .split(',')
        .map(number)
        .collect::<std::result::Result<_, _>>()?;
    v.try_into()
        .map_err(|v: Vec<f64>| format!("expected {N} numbers, found {}", v.len()))
}

fn pose_arg(s: &str) -> std::result::Result<[f64; 6], String> {
    let s = s.trim();
    let l = s
        .strip_prefix('p')
        .ok_or_else(|| format!("expected a pose p[x, y, z, rx, ry, rz], found `{s}`"))?;
    list::<6>(l)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_rotation_vector_round_trips_through_its_matrix() {
        for v in [
            V3::new(0.1, -0.2, 0.3),
            V3::new(3.0, 0.1, 0.0),
            V3::new(0.0, 0.0, 0.0),
        ] {
            let r = rotation_of(&v);
            assert!((rotation_of(&rotation_vector(&r)) - r).norm() < 1e-12);
        }
    }

    #[test]
    fn statements_outside_the_subset_are_refused_with_the_line() {
        let e = read_urscript("def f():\n  popup(\"x\")\nend\n", "t.script").unwrap_err();
        assert!(e.to_string().contains("t.script:2"), "{e}");
        let e = read_urscript("def f():\n  movel(p[1, 2, 3], a=1)\nend\n", "t.script").unwrap_err();
        assert!(e.to_string().contains("expected 6 numbers"), "{e}");
        let e = read_urscript("def f():\n  movej([0,0,0,0,0,0])\n", "t.script").unwrap_err();
        assert!(e.to_string().contains("no `end`"), "{e}");
    }
}
