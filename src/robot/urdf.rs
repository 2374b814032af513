//! URDF reader for serial arms. Reads `<link>` inertials and `<collision>` geometry (boxes,
//! cylinders, spheres, and STL/OBJ meshes whose vertices become convex hulls; mesh paths are
//! relative to the URDF, `package://` is looked up in `ROS_PACKAGE_PATH` and the URDF's
//! ancestors, a mesh that cannot be read is a warning and its link falls back to a capsule),
//! and `<joint>` origins, axes, limits and mimic tags. `<visual>` elements are kept for drawing
//! only ([`crate::robot::Visuals`]: their mesh files found, not read), and used for a link's
//! inertia only when it has neither `<inertial>` nor `<collision>`.
//!
//! What it does with the tree:
//! - the arm chain runs from the root link to `tool_link` (or, when none is named, to the leaf
//!   reached through the most actuated joints);
//! - fixed joints on the chain are merged: their transforms are composed and their links'
//!   inertials are added to the moving link before them;
//! - side branches (passive or mimic joints such as the balancer cylinder and piston of ABB
//!   URDFs) are frozen at their zero position and their mass, if any, is merged into the chain
//!   link they hang from, with a warning; massless ones are dropped silently;
//! - links before the first actuated joint belong to the fixed base.
//!
//! Limitations: one serial chain; floating and planar joints are rejected; a mimic joint on the
//! chain itself is rejected (a closed-loop drive is not modelled).

use crate::error::{Error, Result};
use crate::math::{Frame, M3, V3};
use crate::robot::model::{
    CollisionGeom, GeomShape, Inertial, Joint, JointKind, RobotInfo, RobotModel, VisualGeom,
    VisualShape, Visuals,
};
use std::collections::HashMap;
use std::path::Path;

#[derive(Debug)]
struct UJoint {
    name: String,
    kind: String,
    parent: String,
    child: String,
    origin: Frame,
    axis: V3,
    lower: f64,
    upper: f64,
    velocity: f64,
    effort: f64,
    mimic: bool,
    line: usize,
}

struct Ctx<'a> {
    doc: &'a roxmltree::Document<'a>,
    file: &'a str,
}

impl Ctx<'_> {
    fn err(&self, node: roxmltree::Node, msg: impl Into<String>) -> Error {
        let pos = self.doc.text_pos_at(node.range().start);
        Error::Parse {
            file: self.file.into(),
            line: pos.row as usize,
            column: pos.col as usize,
            msg: msg.into(),
        }
    }

    fn floats<const N: usize>(
        &self,
        node: roxmltree::Node,
        attr: &str,
        default: Option<[f64; N]>,
    ) -> Result<[f64; N]> {
        let Some(text) = node.attribute(attr) else {
            return default.ok_or_else(|| {
                self.err(
                    node,
                    format!("<{}> needs attribute `{attr}`", node.tag_name().name()),
                )
            });
        };
        let vals: Vec<&str> = text.split_whitespace().collect();
        if vals.len() != N {
            return Err(self.err(
                node,
                format!(
                    "attribute `{attr}` = \"{text}\": expected {N} numbers, got {}",
                    vals.len()
                ),
            ));
        }
        let mut out = [0.0; N];
        for (o, v) in out.iter_mut().zip(vals) {
            *o = v
                .parse::<f64>()
                .ok()
                .filter(|x| x.is_finite())
                .ok_or_else(|| {
                    self.err(
                        node,
                        format!("attribute `{attr}`: `{v}` is not a finite number"),
                    )
                })?;
        }
        Ok(out)
    }

    fn float(&self, node: roxmltree::Node, attr: &str, default: Option<f64>) -> Result<f64> {
        Ok(self.floats::<1>(node, attr, default.map(|d| [d]))?[0])
    }

    fn origin(&self, parent: roxmltree::Node) -> Result<Frame> {
        match child(parent, "origin") {
            None => Ok(Frame::identity()),
            Some(o) => Ok(Frame::from_xyz_rpy(
                self.floats(o, "xyz", Some([0.0; 3]))?,
                self.floats(o, "rpy", Some([0.0; 3]))?,
            )),
        }
    }
}

/// Deepest element nesting accepted in a URDF (real ones nest 4 or 5 levels). roxmltree
/// recurses per level, so a file nested 20,000 levels deep would overflow the stack: it is
/// refused before parsing.
pub(crate) const MAX_XML_DEPTH: usize = 256;

/// Refuse XML nested deeper than `max` elements, naming the line where the limit is passed.
/// A light scan (comments, CDATA, processing instructions, DOCTYPE and quoted attribute values
/// skipped); well-formedness is left to the parser.
pub(crate) fn check_xml_depth(text: &str, file: &str, max: usize) -> Result<()> {
    let b = text.as_bytes();
    let mut depth: usize = 0;
    let mut line = 1;
    let mut i = 0;
    let skip_to = |i: usize, pat: &[u8], line: &mut usize| -> usize {
        let mut j = i;
        while j < b.len() {
            if b[j..].starts_with(pat) {
                return j + pat.len();
            }
            if b[j] == b'\n' {
                *line += 1;
            }
            j += 1;
        }
        b.len()
    };
    while i < b.len() {
        match b[i] {
            b'\n' => {
                line += 1;
                i += 1;
            }
            b'<' => {
                let rest = &b[i + 1..];
                if rest.starts_with(b"!--") {
                    i = skip_to(i + 4, b"-->", &mut line);
                } else if rest.starts_with(b"![CDATA[") {
                    i = skip_to(i + 9, b"]]>", &mut line);
                } else if rest.starts_with(b"?") {
                    i = skip_to(i + 2, b"?>", &mut line);
                } else if rest.starts_with(b"!") {
                    i = skip_to(i + 2, b">", &mut line);
                } else if rest.starts_with(b"/") {
                    depth = depth.saturating_sub(1);
                    i = skip_to(i + 2, b">", &mut line);
                } else {
                    // A start tag: find its end outside quotes.
                    let mut j = i + 1;
                    let mut quote: Option<u8> = None;
                    while j < b.len() {
                        let c = b[j];
                        if c == b'\n' {
                            line += 1;
                        }
                        match quote {
                            Some(q) if c == q => quote = None,
                            Some(_) => {}
                            None if c == b'"' || c == b'\'' => quote = Some(c),
                            None if c == b'>' => break,
                            None => {}
                        }
                        j += 1;
                    }
                    let self_closing = j > 0 && j < b.len() && b[j - 1] == b'/';
                    if !self_closing {
                        depth += 1;
                        if depth > max {
                            return Err(Error::Parse {
                                file: file.into(),
                                line,
                                column: 1,
                                msg: format!(
                                    "XML nested deeper than {max} elements: not a URDF (refused before parsing)"
                                ),
                            });
                        }
                    }
                    i = j + 1;
                }
            }
            _ => i += 1,
        }
    }
    Ok(())
}

fn child<'a, 'i>(n: roxmltree::Node<'a, 'i>, tag: &str) -> Option<roxmltree::Node<'a, 'i>> {
    n.children()
        .find(|c| c.is_element() && c.tag_name().name() == tag)
}

/// Parse URDF text into a model (no drive data). `file` names the source in errors;
/// `tool_link` ends the chain when given.
pub fn parse_urdf(text: &str, file: &str, tool_link: Option<&str>) -> Result<RobotModel> {
    check_xml_depth(text, file, MAX_XML_DEPTH)?;
    let doc = roxmltree::Document::parse(text).map_err(|e| {
        let p = e.pos();
        Error::Parse {
            file: file.into(),
            line: p.row as usize,
            column: p.col as usize,
            msg: format!("not well-formed XML: {e}"),
        }
    })?;
    let cx = Ctx { doc: &doc, file };
    let root = doc.root_element();
    if root.tag_name().name() != "robot" {
        return Err(cx.err(
            root,
            format!(
                "expected a <robot> root element, found <{}>",
                root.tag_name().name()
            ),
        ));
    }
    let robot_name = root.attribute("name").unwrap_or("robot").to_string();
    let mut links = read_links(&cx, root)?;
    let joints = read_joints(&cx, root, &links.inertials, &mut links.warnings)?;
    let tree = Tree::new(file, &joints, &links.order)?;
    let tip = pick_tip(file, &tree, &links, tool_link)?;
    let path = tree.path_to(&tip)?;
    for &k in &path {
        if joints[k].mimic {
            return Err(Error::Parse {
                file: file.into(),
                line: joints[k].line,
                column: 1,
                msg: format!("joint `{}` on the arm chain is a mimic joint: closed-loop drives are not supported", joints[k].name),
            });
        }
    }
    let on_path: std::collections::HashSet<&str> = std::iter::once(tree.root_link.as_str())
        .chain(path.iter().map(|&k| joints[k].child.as_str()))
        .collect();
    let mut chain = Chain::new(&mut links, &tree.root_link);
    for &k in &path {
        chain.add_joint(&joints[k], &joints, &mut links, &on_path);
    }
    if chain.joints.is_empty() {
        return Err(Error::Invalid(format!(
            "{file}: no actuated joint between `{}` and `{tip}`",
            tree.root_link
        )));
    }
    note_drawing_meshes(&doc, &mut links.warnings);
    Ok(chain.into_model(robot_name, file, tip, links))
}

/// What the `<link>` elements say: inertials, collision and visual geometry, in document order.
struct Links {
    /// Each link's inertial in its own frame (None: no `<inertial>`).
    inertials: HashMap<String, Option<Inertial>>,
    /// Link names in document order.
    order: Vec<String>,
    warnings: Vec<String>,
    collisions: HashMap<String, Vec<CollisionGeom>>,
    /// Visual geometry of links without any <collision>: only for estimating a missing inertia.
    visuals: HashMap<String, Vec<CollisionGeom>>,
    /// Every link's <visual> elements, for drawing.
    drawn: HashMap<String, Vec<VisualGeom>>,
    drawn_skipped: Vec<String>,
}

/// Read every `<link>` of the robot: its inertial, collision geometry and drawn visuals.
fn read_links(cx: &Ctx, root: roxmltree::Node) -> Result<Links> {
    let mut out = Links {
        inertials: HashMap::new(),
        order: Vec::new(),
        warnings: Vec::new(),
        collisions: HashMap::new(),
        visuals: HashMap::new(),
        drawn: HashMap::new(),
        drawn_skipped: Vec::new(),
    };
    for l in root
        .children()
        .filter(|n| n.is_element() && n.tag_name().name() == "link")
    {
        let name = l
            .attribute("name")
            .ok_or_else(|| cx.err(l, "<link> needs a `name`"))?
            .to_string();
        let inertial = match child(l, "inertial") {
            None => None,
            Some(inn) => Some(read_inertial(cx, inn, &name, &mut out.warnings)?),
        };
        let geoms = collision_of(cx, l, &name, "collision", &mut out.warnings)?;
        if geoms.is_empty() && inertial.is_none() {
            // Meshes a visual cannot give (COLLADA) are no news: the warning is dropped.
            let v = collision_of(cx, l, &name, "visual", &mut Vec::new())?;
            out.visuals.insert(name.clone(), v);
        }
        out.collisions.insert(name.clone(), geoms);
        let drawn = visuals_of(cx, l, &name, &mut out.drawn_skipped);
        out.drawn.insert(name.clone(), drawn);
        if out.inertials.insert(name.clone(), inertial).is_some() {
            return Err(cx.err(l, format!("link `{name}` is defined twice")));
        }
        out.order.push(name);
    }
    if out.inertials.is_empty() {
        return Err(cx.err(root, "the URDF has no <link>"));
    }
    Ok(out)
}

/// Read one link's `<inertial>` element, expressed in the link frame.
fn read_inertial(
    cx: &Ctx,
    inn: roxmltree::Node,
    name: &str,
    warnings: &mut Vec<String>,
) -> Result<Inertial> {
    let f = cx.origin(inn)?;
    let m = child(inn, "mass").ok_or_else(|| cx.err(inn, "<inertial> needs <mass value=...>"))?;
    let mass = cx.float(m, "value", None)?;
    if mass < 0.0 {
        return Err(cx.err(m, format!("link `{name}`: negative mass {mass}")));
    }
    let i = child(inn, "inertia").ok_or_else(|| cx.err(inn, "<inertial> needs <inertia .../>"))?;
    let g = |a: &str| cx.float(i, a, Some(0.0));
    let (ixx, iyy, izz) = (g("ixx")?, g("iyy")?, g("izz")?);
    let (ixy, ixz, iyz) = (g("ixy")?, g("ixz")?, g("iyz")?);
    let ic = M3::new(ixx, ixy, ixz, ixy, iyy, iyz, ixz, iyz, izz);
    if ixx < 0.0 || iyy < 0.0 || izz < 0.0 {
        return Err(cx.err(i, format!("link `{name}`: negative principal moment")));
    }
    if ixx + iyy < izz - 1e-12 || ixx + izz < iyy - 1e-12 || iyy + izz < ixx - 1e-12 {
        warnings.push(format!(
            "link `{name}`: inertia violates the triangle inequality (kept as given; \
             published PUMA 560 data do this)"
        ));
    }
    Ok(Inertial {
        mass,
        com: V3::zeros(),
        inertia: ic,
    }
    .transformed(&f))
}

/// Read every `<joint>` of the robot, in document order.
fn read_joints(
    cx: &Ctx,
    root: roxmltree::Node,
    links: &HashMap<String, Option<Inertial>>,
    warnings: &mut Vec<String>,
) -> Result<Vec<UJoint>> {
    let mut joints: Vec<UJoint> = Vec::new();
    for j in root
        .children()
        .filter(|n| n.is_element() && n.tag_name().name() == "joint")
    {
        joints.push(read_joint(cx, j, links, warnings)?);
    }
    Ok(joints)
}

/// Read one `<joint>`: its type, the links it joins, origin, axis and limits.
fn read_joint(
    cx: &Ctx,
    j: roxmltree::Node,
    links: &HashMap<String, Option<Inertial>>,
    warnings: &mut Vec<String>,
) -> Result<UJoint> {
    let name = j
        .attribute("name")
        .ok_or_else(|| cx.err(j, "<joint> needs a `name`"))?
        .to_string();
    let kind = j
        .attribute("type")
        .ok_or_else(|| cx.err(j, format!("joint `{name}` needs a `type`")))?
        .to_string();
    if !matches!(
        kind.as_str(),
        "revolute" | "continuous" | "prismatic" | "fixed"
    ) {
        return Err(cx.err(j, format!("joint `{name}`: type `{kind}` is not supported (expected revolute, continuous, prismatic or fixed)")));
    }
    let parent = joint_link(cx, j, &name, "parent", links)?;
    let childl = joint_link(cx, j, &name, "child", links)?;
    let origin = cx.origin(j)?;
    let axis = match child(j, "axis") {
        None => V3::x(),
        Some(a) => {
            let v = V3::from(cx.floats::<3>(a, "xyz", Some([1.0, 0.0, 0.0]))?);
            let n = v.norm();
            if n < 1e-12 {
                return Err(cx.err(a, format!("joint `{name}`: zero axis")));
            }
            v / n
        }
    };
    let (lower, upper, velocity, effort) = joint_limits(cx, j, &name, &kind, warnings)?;
    let line = cx.doc.text_pos_at(j.range().start).row as usize;
    Ok(UJoint {
        mimic: child(j, "mimic").is_some(),
        name,
        kind,
        parent,
        child: childl,
        origin,
        axis,
        lower,
        upper,
        velocity,
        effort,
        line,
    })
}

/// The link a joint's `<parent>` or `<child>` (`tag`) names, which must be defined.
fn joint_link(
    cx: &Ctx,
    j: roxmltree::Node,
    name: &str,
    tag: &str,
    links: &HashMap<String, Option<Inertial>>,
) -> Result<String> {
    let n =
        child(j, tag).ok_or_else(|| cx.err(j, format!("joint `{name}` needs <{tag} link=...>")))?;
    let l = n
        .attribute("link")
        .ok_or_else(|| cx.err(n, format!("<{tag}> needs `link`")))?;
    if !links.contains_key(l) {
        return Err(cx.err(
            n,
            format!("joint `{name}`: {tag} link `{l}` is not defined"),
        ));
    }
    Ok(l.to_string())
}

/// A joint's `<limit>`: (lower, upper, velocity, effort), with an unknown speed as infinite.
fn joint_limits(
    cx: &Ctx,
    j: roxmltree::Node,
    name: &str,
    kind: &str,
    warnings: &mut Vec<String>,
) -> Result<(f64, f64, f64, f64)> {
    let (mut lower, mut upper, mut velocity, mut effort) =
        (f64::NEG_INFINITY, f64::INFINITY, f64::INFINITY, 0.0);
    if let Some(l) = child(j, "limit") {
        if kind != "continuous" {
            lower = cx.float(l, "lower", Some(0.0))?;
            upper = cx.float(l, "upper", Some(0.0))?;
        }
        velocity = cx.float(l, "velocity", Some(f64::INFINITY))?;
        effort = cx.float(l, "effort", Some(0.0))?;
        if lower > upper {
            return Err(cx.err(
                l,
                format!("joint `{name}`: lower limit {lower} > upper limit {upper}"),
            ));
        }
    } else if kind == "revolute" || kind == "prismatic" {
        return Err(cx.err(j, format!("joint `{name}`: a {kind} joint needs <limit>")));
    }
    if velocity == 0.0 && kind != "fixed" {
        // Hand-written and textbook URDFs write `velocity="0"` for "not given": read as
        // unknown (as if omitted), with a warning; the commands that need a speed limit
        // say so where they need it.
        warnings.push(format!(
            "joint `{name}`: velocity=\"0\" read as no velocity limit given (commands that only evaluate logs never use it)"
        ));
        velocity = f64::INFINITY;
    }
    // `effort="0"` (ROS-Industrial's URDFs write it) reads as no effort limit given: the
    // drive file's torque limits apply, and nothing else uses the URDF's effort.
    if velocity <= 0.0 && kind != "fixed" {
        let l = child(j, "limit").unwrap_or(j);
        return Err(cx.err(
            l,
            format!(
                "joint `{name}`: velocity limit {velocity}: a joint limit must be > 0 (the \
                 joint's rated speed, rad/s or m/s); omit `velocity` if it is unknown"
            ),
        ));
    }
    if velocity <= 0.0 {
        velocity = f64::INFINITY;
    }
    Ok((lower, upper, velocity, effort))
}

/// The joint tree: which joint each link hangs from, and the one root link.
struct Tree<'a> {
    file: &'a str,
    joints: &'a [UJoint],
    parent_joint: HashMap<&'a str, usize>,
    root_link: String,
}

impl<'a> Tree<'a> {
    /// Check that the joints join all links into one tree and find its root.
    fn new(file: &'a str, joints: &'a [UJoint], link_order: &[String]) -> Result<Tree<'a>> {
        let mut parent_joint: HashMap<&str, usize> = HashMap::new();
        for (k, j) in joints.iter().enumerate() {
            if let Some(prev) = parent_joint.insert(j.child.as_str(), k) {
                return Err(Error::Parse {
                    file: file.into(),
                    line: j.line,
                    column: 1,
                    msg: format!(
                        "link `{}` is the child of two joints (`{}` and `{}`): not a tree",
                        j.child, joints[prev].name, j.name
                    ),
                });
            }
        }
        let roots: Vec<&String> = link_order
            .iter()
            .filter(|l| !parent_joint.contains_key(l.as_str()))
            .collect();
        if roots.len() != 1 {
            let names: Vec<String> = roots.iter().map(|l| format!("`{l}`")).collect();
            return Err(Error::Field {
                file: file.into(),
                field: if names.is_empty() {
                    "<joint> parent/child".into()
                } else {
                    format!("<link name> {}", names.join(", "))
                },
                msg: format!(
                    "expected one root link (a link that is no joint's child), found {}: the \
                     joints must join all links into one tree",
                    roots.len()
                ),
            });
        }
        let root_link = roots[0].clone();
        Ok(Tree {
            file,
            joints,
            parent_joint,
            root_link,
        })
    }

    /// The joints from the root link down to `leaf`, root first.
    fn path_to(&self, leaf: &str) -> Result<Vec<usize>> {
        let mut path = Vec::new();
        let mut cur = leaf.to_string();
        while let Some(&k) = self.parent_joint.get(cur.as_str()) {
            path.push(k);
            cur = self.joints[k].parent.clone();
            if path.len() > self.joints.len() {
                return Err(Error::Invalid(format!(
                    "{}: the joint graph has a cycle",
                    self.file
                )));
            }
        }
        path.reverse();
        Ok(path)
    }
}

/// A joint that drives the arm: neither fixed nor a mimic of another.
fn actuated(j: &UJoint) -> bool {
    j.kind != "fixed" && !j.mimic
}

/// The link the arm chain ends at: `tool_link` when given, else the leaf reached through the
/// most actuated joints, extended through fixed joints to the flange.
fn pick_tip(file: &str, tree: &Tree, links: &Links, tool_link: Option<&str>) -> Result<String> {
    if let Some(t) = tool_link {
        if !links.inertials.contains_key(t) {
            return Err(Error::Invalid(format!(
                "{file}: tool_link `{t}` is not a link of this URDF"
            )));
        }
        return Ok(t.to_string());
    }
    let joints = tree.joints;
    // The leaf reached through the most actuated joints; first in document order wins ties.
    let mut best: Option<(usize, String)> = None;
    for l in &links.order {
        let n = tree
            .path_to(l)?
            .iter()
            .filter(|&&k| actuated(&joints[k]))
            .count();
        if best.as_ref().is_none_or(|(b, _)| n > *b) {
            best = Some((n, l.clone()));
        }
    }
    // Extend through fixed joints to the deepest fixed descendant (the flange / tool0).
    let mut t = best.map(|b| b.1).unwrap_or(tree.root_link.clone());
    loop {
        let next = joints.iter().find(|j| j.parent == t && j.kind == "fixed");
        match next {
            Some(j) => t = j.child.clone(),
            None => break,
        }
    }
    Ok(t)
}

/// Inertial of a side subtree hanging from `link`, frozen at zero joint positions, expressed
/// in `link`'s frame; the names of the moving joints inside are added to `moving`.
fn subtree(
    link: &str,
    joints: &[UJoint],
    links: &HashMap<String, Option<Inertial>>,
    on_path: &std::collections::HashSet<&str>,
    moving: &mut Vec<String>,
) -> Inertial {
    let mut acc = Inertial::zero();
    for j in joints
        .iter()
        .filter(|j| j.parent == link && !on_path.contains(j.child.as_str()))
    {
        if j.kind != "fixed" {
            moving.push(j.name.clone());
        }
        let mut body = links[&j.child].unwrap_or(Inertial::zero());
        body = body.merged(&subtree(&j.child, joints, links, on_path, moving));
        acc = acc.merged(&body.transformed(&j.origin));
    }
    acc
}

/// The arm chain being assembled, joint by joint from the root link.
struct Chain {
    joints: Vec<Joint>,
    links: Vec<Option<Inertial>>,
    link_names: Vec<String>,
    /// From the last actuated joint's frame (or base) to the current link.
    acc: Frame,
    base_collision: Vec<CollisionGeom>,
    link_collision: Vec<Vec<CollisionGeom>>,
    link_visual: Vec<Vec<CollisionGeom>>,
    drawn_base: Vec<VisualGeom>,
    drawn_links: Vec<Vec<VisualGeom>>,
}

impl Chain {
    /// An empty chain whose base carries the root link's geometry.
    fn new(links: &mut Links, root_link: &str) -> Chain {
        Chain {
            joints: Vec::new(),
            links: Vec::new(),
            link_names: Vec::new(),
            acc: Frame::identity(),
            base_collision: links.collisions.remove(root_link).unwrap_or_default(),
            link_collision: Vec::new(),
            link_visual: Vec::new(),
            drawn_base: links.drawn.remove(root_link).unwrap_or_default(),
            drawn_links: Vec::new(),
        }
    }

    /// Add the next joint on the path: an actuated joint starts a new moving link, a fixed
    /// one merges its child link into the current one.
    fn add_joint(
        &mut self,
        j: &UJoint,
        joints: &[UJoint],
        links: &mut Links,
        on_path: &std::collections::HashSet<&str>,
    ) {
        let origin_in_last = self.acc.compose(&j.origin); // child link frame at q=0, in last joint frame
        let own = links.inertials[&j.child];
        let mut moving = Vec::new();
        let side = subtree(&j.child, joints, &links.inertials, on_path, &mut moving);
        let side_has_mass = side.mass > 0.0 || side.inertia.norm() > 0.0;
        // Massless passive or mimic joints (a balancer's cylinder drawn for show) change no
        // torque: they are left out without a word. Ones with mass are frozen, and said.
        if !moving.is_empty() && side_has_mass {
            links.warnings.push(format!(
                "passive/mimic joints {moving:?} carry mass: frozen at their zero position and merged into link `{}`",
                j.child
            ));
        }
        let body = match own {
            Some(b) => Some(b.merged(&side)),
            None if side_has_mass => Some(side),
            None => None,
        };
        if actuated(j) {
            self.push_actuated(j, origin_in_last, body, links);
        } else {
            self.merge_fixed(j, origin_in_last, body, links);
        }
    }

    /// Start a new moving link after an actuated joint.
    fn push_actuated(
        &mut self,
        j: &UJoint,
        origin_in_last: Frame,
        body: Option<Inertial>,
        links: &mut Links,
    ) {
        let kind = if j.kind == "prismatic" {
            JointKind::Prismatic
        } else {
            JointKind::Revolute
        };
        self.joints.push(Joint {
            name: j.name.clone(),
            kind,
            origin: origin_in_last,
            axis: j.axis,
            lower: j.lower,
            upper: j.upper,
            velocity_limit: j.velocity,
            acceleration_limit: f64::INFINITY,
            jerk_limit: f64::INFINITY,
            effort_limit: (j.effort > 0.0).then_some(j.effort),
        });
        self.links.push(body);
        self.link_names.push(j.child.clone());
        self.link_collision
            .push(links.collisions.remove(&j.child).unwrap_or_default());
        self.link_visual
            .push(links.visuals.remove(&j.child).unwrap_or_default());
        self.drawn_links
            .push(links.drawn.remove(&j.child).unwrap_or_default());
        self.acc = Frame::identity();
    }

    /// Merge a fixed joint's child link (its shapes and mass) into the current moving link.
    fn merge_fixed(
        &mut self,
        j: &UJoint,
        origin_in_last: Frame,
        body: Option<Inertial>,
        links: &mut Links,
    ) {
        let acc = origin_in_last;
        self.acc = acc;
        // The child's shapes, moved into the current link's frame.
        let moved = |shapes: &mut HashMap<String, Vec<CollisionGeom>>| {
            shapes
                .remove(&j.child)
                .unwrap_or_default()
                .into_iter()
                .map(|g| CollisionGeom {
                    origin: acc.compose(&g.origin),
                    shape: g.shape,
                })
                .collect::<Vec<_>>()
        };
        let c = moved(&mut links.collisions);
        match self.link_collision.last_mut() {
            Some(l) => l.extend(c),
            None => self.base_collision.extend(c),
        }
        let v = moved(&mut links.visuals);
        if let Some(l) = self.link_visual.last_mut() {
            l.extend(v);
        }
        let d = links
            .drawn
            .remove(&j.child)
            .unwrap_or_default()
            .into_iter()
            .map(|g| VisualGeom {
                origin: acc.compose(&g.origin),
                ..g
            });
        match self.drawn_links.last_mut() {
            Some(l) => l.extend(d),
            None => self.drawn_base.extend(d),
        }
        if let Some(cur) = self.links.last_mut() {
            if let Some(b) = body {
                let b = b.transformed(&acc);
                *cur = Some(cur.unwrap_or(Inertial::zero()).merged(&b));
            }
        }
    }

    /// The finished model; the last fixed offset becomes the flange.
    fn into_model(self, robot_name: String, file: &str, tip: String, links: Links) -> RobotModel {
        // A link with zero mass and zero inertia that had no <inertial> anywhere stays None.
        RobotModel {
            info: RobotInfo {
                name: robot_name,
                ..Default::default()
            },
            source: Path::new(file).to_path_buf(),
            joints: self.joints,
            link_names: self.link_names,
            links: self.links,
            flange: self.acc,
            flange_link: tip,
            tool: Frame::identity(),
            payload: None,
            gravity: V3::new(0.0, 0.0, -9.81),
            drive: None,
            effects: Default::default(),
            opw: None,
            base_collision: self.base_collision,
            link_collision: self.link_collision,
            link_visual: self.link_visual,
            visuals: Visuals {
                base: self.drawn_base,
                links: self.drawn_links,
                skipped: links.drawn_skipped,
            },
            tool_geometry: None,
            warnings: links.warnings,
        }
    }
}

/// Say how many visual meshes are kept for drawing only.
fn note_drawing_meshes(doc: &roxmltree::Document, warnings: &mut Vec<String>) {
    let ignored_meshes = doc
        .descendants()
        .filter(|n| n.tag_name().name() == "visual")
        .filter(|v| v.descendants().any(|n| n.tag_name().name() == "mesh"))
        .count();
    if ignored_meshes > 0 {
        warnings.push(format!(
            "{ignored_meshes} visual mesh references used for drawing only (the checks use <collision> geometry, and a link's <visual> for its inertia when it has neither <inertial> nor <collision>)"
        ));
    }
}

/// The `<visual>` elements of one link, in the link frame, for drawing: an element that
/// cannot be drawn (bad numbers, a mesh not found, outside its directory or of another format)
/// is left out and said in `skipped`; a URDF is never refused for its visual elements.
fn visuals_of(
    cx: &Ctx,
    link: roxmltree::Node,
    name: &str,
    skipped: &mut Vec<String>,
) -> Vec<VisualGeom> {
    let mut out = Vec::new();
    let urdf_dir = Path::new(cx.file).parent().unwrap_or(Path::new("."));
    for v in link
        .children()
        .filter(|n| n.is_element() && n.tag_name().name() == "visual")
    {
        let shape = (|| -> std::result::Result<VisualShape, String> {
            let g = child(v, "geometry").ok_or("no <geometry>")?;
            let s = g
                .children()
                .find(|n| n.is_element())
                .ok_or("empty <geometry>")?;
            let pos = |v: f64, what: &str| {
                if v.is_finite() && v > 0.0 {
                    Ok(v)
                } else {
                    Err(format!("{what} must be > 0, got {v}"))
                }
            };
            let num = |a: &str| cx.float(s, a, None).map_err(|e| e.to_string());
            Ok(match s.tag_name().name() {
                "box" => {
                    let size = cx.floats::<3>(s, "size", None).map_err(|e| e.to_string())?;
                    for x in size {
                        pos(x, "box size")?;
                    }
                    VisualShape::Box { size_m: size }
                }
                "cylinder" => VisualShape::Cylinder {
                    radius_m: pos(num("radius")?, "cylinder radius")?,
                    length_m: pos(num("length")?, "cylinder length")?,
                },
                "sphere" => VisualShape::Sphere {
                    radius_m: pos(num("radius")?, "sphere radius")?,
                },
                "mesh" => {
                    let f = s.attribute("filename").ok_or("<mesh> without `filename`")?;
                    let scale = cx
                        .floats::<3>(s, "scale", Some([1.0; 3]))
                        .map_err(|e| e.to_string())?;
                    if scale.contains(&0.0) {
                        return Err(format!("mesh `{f}`: a zero scale"));
                    }
                    let (path, format) = super::mesh::visual_mesh_file(f, urdf_dir)
                        .map_err(|e| format!("mesh `{f}`: {e}"))?;
                    VisualShape::Mesh {
                        filename: f.to_string(),
                        path,
                        format,
                        scale,
                    }
                }
                other => return Err(format!("<{other}> is not drawn")),
            })
        })();
        match (shape, cx.origin(v)) {
            (Ok(shape), Ok(origin)) => out.push(VisualGeom {
                origin,
                shape,
                link: name.to_string(),
            }),
            (Err(e), _) => skipped.push(format!("link `{name}`: visual {e}")),
            (_, Err(e)) => skipped.push(format!("link `{name}`: visual {e}")),
        }
    }
    out
}

/// The vertices of a collision mesh file, when found, readable and spanning a convex hull;
/// else why not.
fn read_hull_mesh(f: &str, urdf_dir: &Path) -> std::result::Result<Vec<V3>, String> {
    super::mesh::resolve_mesh_path(f, urdf_dir)
        .ok_or_else(|| "package not found (set ROS_PACKAGE_PATH)".to_string())
        .and_then(|p| super::mesh::read_vertices(&p).map_err(|e| e.to_string()))
        .and_then(|pts| {
            // Points on a line (or one point) have no convex hull to collide with.
            let hull: Vec<parry3d_f64::math::Point<f64>> =
                pts.iter().map(|p| (*p).into()).collect();
            match parry3d_f64::shape::ConvexPolyhedron::from_convex_hull(&hull) {
                Some(_) => Ok(pts),
                None => Err("degenerate: no convex hull".to_string()),
            }
        })
}

/// The `<collision>` (or, `tag` = `visual`, the `<visual>`) elements of one link, in the link
/// frame. Bad sizes are errors; a mesh that cannot be found or read is a warning (the element
/// is skipped, so a link left without geometry falls back to a capsule).
fn collision_of(
    cx: &Ctx,
    link: roxmltree::Node,
    name: &str,
    tag: &str,
    warnings: &mut Vec<String>,
) -> Result<Vec<CollisionGeom>> {
    let mut out = Vec::new();
    let urdf_dir = Path::new(cx.file).parent().unwrap_or(Path::new("."));
    for c in link
        .children()
        .filter(|n| n.is_element() && n.tag_name().name() == tag)
    {
        let origin = cx.origin(c)?;
        let g = child(c, "geometry")
            .ok_or_else(|| cx.err(c, format!("link `{name}`: <{tag}> needs <geometry>")))?;
        let Some(s) = g.children().find(|n| n.is_element()) else {
            return Err(cx.err(g, format!("link `{name}`: empty <geometry>")));
        };
        let positive = |v: f64, what: &str| -> Result<f64> {
            if v.is_finite() && v > 0.0 {
                Ok(v)
            } else {
                Err(cx.err(
                    s,
                    format!("link `{name}`: {tag} {what} must be > 0, got {v}"),
                ))
            }
        };
        let shape = match s.tag_name().name() {
            "box" => {
                let size = cx.floats::<3>(s, "size", None)?;
                for v in size {
                    positive(v, "box size")?;
                }
                GeomShape::Box { size_m: size }
            }
            "cylinder" => GeomShape::Cylinder {
                radius_m: positive(cx.float(s, "radius", None)?, "cylinder radius")?,
                length_m: positive(cx.float(s, "length", None)?, "cylinder length")?,
            },
            "sphere" => GeomShape::Sphere {
                radius_m: positive(cx.float(s, "radius", None)?, "sphere radius")?,
            },
            "mesh" => {
                let f = s
                    .attribute("filename")
                    .ok_or_else(|| cx.err(s, format!("link `{name}`: <mesh> needs `filename`")))?;
                let scale = cx.floats::<3>(s, "scale", Some([1.0; 3]))?;
                match read_hull_mesh(f, urdf_dir) {
                    Ok(pts) => GeomShape::Hull {
                        points: pts
                            .into_iter()
                            .map(|p| V3::new(p.x * scale[0], p.y * scale[1], p.z * scale[2]))
                            .collect(),
                        source: f.to_string(),
                    },
                    Err(e) => {
                        warnings.push(format!(
                            "link `{name}`: collision mesh `{f}` not used ({e}); a capsule stands in"
                        ));
                        continue;
                    }
                }
            }
            other => {
                warnings.push(format!(
                    "link `{name}`: collision geometry <{other}> is not supported; skipped"
                ));
                continue;
            }
        };
        out.push(CollisionGeom { origin, shape });
    }
    Ok(out)
}
