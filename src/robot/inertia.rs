//! Link inertias that the URDF does not give: from the drive file's `[links.<name>]` tables,
//! else estimated from the link's collision geometry, and a check for placeholder values.
//!
//! Robots from the field (ROS-Industrial support packages) often ship a URDF without any
//! `<inertial>`, or with the same small placeholder body on every link. The energy of a
//! motion is dominated by the moving masses, so each source is recorded per link
//! ([`InertiaSource`], shown by `printwatt robots` and in its JSON) and every estimate or
//! suspicious value is a warning.
//!
//! **The estimate.** Each `<collision>` shape of the link (box, cylinder, sphere, readable
//! mesh as its convex hull) is a solid of [`ESTIMATE_DENSITY_KG_M3`], an effective density
//! for hollow cast links enveloped by their collision shapes. A link without any gets the
//! planner's collision capsule (the segment from its joint origin to the next joint origin or
//! the flange, radius from [`LinkRadii`](super::LinkRadii) times the
//! reach) as a cylinder of the capsule's volume, of [`CAPSULE_DENSITY_KG_M3`]: the capsule is a
//! clearance radius, thinner than the casting, so its density is calibrated instead, on the
//! shipped ABB IRB 6700-200/2.60, whose capsules then weigh 751 kg against its 793 kg of
//! moving links (tests/robot.rs checks 25 %). Either is a rough figure: an energy computed on
//! it can be off by tens of percent; give the drive file's `[links]` tables for numbers worth
//! comparing.

use super::model::{GeomShape, Inertial, RobotModel};
use crate::math::{Frame, M3, V3};
use serde::Serialize;

/// Effective density of links estimated from their collision shapes, kg/m³: cast iron
/// (7,200 kg/m³) filling about a sixth of a hollow cast link's outer volume, with motors and
/// gearboxes averaged in.
pub const ESTIMATE_DENSITY_KG_M3: f64 = 1_200.0;

/// Effective density of links estimated from the collision capsule, kg/m³: calibrated on the
/// shipped ABB IRB 6700-200/2.60 (its capsules' volume, 0.150 m³, carrying its moving mass).
pub(crate) const CAPSULE_DENSITY_KG_M3: f64 = 5_000.0;

/// Stated uncertainty of an estimated link mass, relative (±): the share of a cast link's
/// outer volume that is metal ranges from about a tenth to a quarter between makers and link
/// sizes (motors and gearboxes included), so the effective density is known to about ±50 %;
/// centres of mass and inertias (which also assume the mass spread evenly) are rougher still.
pub(crate) const ESTIMATE_MASS_UNCERTAINTY_REL: f64 = 0.5;

/// Where a moving link's mass, centre of mass and inertia come from.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum InertiaSource {
    /// The URDF's `<inertial>`.
    Urdf,
    /// The drive file's `[links.<name>]` table.
    DriveFile,
    /// ESTIMATE from the link's collision geometry.
    EstimateFromGeometry,
    /// ESTIMATE from the link's visual geometry (a link without collision geometry).
    EstimateFromVisual,
    /// ESTIMATE from the collision capsule between the joint origins.
    EstimateFromCapsule,
}

impl InertiaSource {
    /// Words for listings (estimates in capitals).
    pub fn words(self) -> &'static str {
        match self {
            InertiaSource::Urdf => "URDF",
            InertiaSource::DriveFile => "drive file",
            InertiaSource::EstimateFromGeometry => "ESTIMATE (collision geometry)",
            InertiaSource::EstimateFromVisual => "ESTIMATE (visual geometry)",
            InertiaSource::EstimateFromCapsule => "ESTIMATE (capsule)",
        }
    }

    /// Whether the value is an estimate.
    pub(crate) fn is_estimate(self) -> bool {
        matches!(
            self,
            InertiaSource::EstimateFromGeometry
                | InertiaSource::EstimateFromVisual
                | InertiaSource::EstimateFromCapsule
        )
    }
}

/// A solid body of density `rho` filling a shape, in the shape's frame (about its centre of
/// mass); `None` for a shape with no volume to estimate from.
fn solid(shape: &GeomShape, rho: f64) -> Option<Inertial> {
    let diag = |a: f64, b: f64, c: f64| M3::from_diagonal(&V3::new(a, b, c));
    Some(match shape {
        GeomShape::Box { size_m: [a, b, c] } => {
            let m = rho * a * b * c;
            Inertial {
                mass: m,
                com: V3::zeros(),
                inertia: diag(b * b + c * c, a * a + c * c, a * a + b * b) * (m / 12.0),
            }
        }
        GeomShape::Cylinder { radius_m, length_m } => cylinder(*radius_m, *length_m, rho),
        GeomShape::Sphere { radius_m: r } => {
            let m = rho * 4.0 / 3.0 * std::f64::consts::PI * r.powi(3);
            let i = 0.4 * m * r * r;
            Inertial {
                mass: m,
                com: V3::zeros(),
                inertia: diag(i, i, i),
            }
        }
        GeomShape::Hull { points, .. } => {
            use parry3d_f64::shape::Shape;
            let pts: Vec<parry3d_f64::math::Point<f64>> =
                points.iter().map(|p| (*p).into()).collect();
            let hull = parry3d_f64::shape::ConvexPolyhedron::from_convex_hull(&pts)?;
            let mp = hull.mass_properties(rho);
            let m = mp.mass();
            if !(m.is_finite() && m > 0.0) {
                return None;
            }
            Inertial {
                mass: m,
                com: mp.local_com.coords,
                inertia: mp.reconstruct_inertia_matrix(),
            }
        }
    })
}

/// A solid cylinder along z, centred on the origin.
fn cylinder(r: f64, l: f64, rho: f64) -> Inertial {
    let m = rho * std::f64::consts::PI * r * r * l;
    let ix = m * (3.0 * r * r + l * l) / 12.0;
    Inertial {
        mass: m,
        com: V3::zeros(),
        inertia: M3::from_diagonal(&V3::new(ix, ix, 0.5 * m * r * r)),
    }
}

/// The frame of a cylinder along `a → b` (z along the segment, origin at the midpoint).
fn segment_frame(a: &V3, b: &V3) -> Frame {
    let d = b - a;
    let z = d / d.norm();
    let helper = if z.x.abs() < 0.9 { V3::x() } else { V3::y() };
    let x = helper.cross(&z).normalize();
    let y = z.cross(&x);
    Frame {
        rot: M3::from_columns(&[x, y, z]),
        pos: (a + b) * 0.5,
    }
}

/// Fill every moving link without an inertial with an ESTIMATE (one warning per link, naming
/// the density and how to give the real values) and record each link's source in
/// [`crate::robot::RobotInfo::inertia_sources`] (entries already set, e.g. by the drive file,
/// are kept); then warn about placeholder values ([`placeholder_warnings`]).
pub fn complete(model: &mut RobotModel) {
    let n = model.dof();
    model.info.inertia_sources.resize(n, InertiaSource::Urdf);
    let reach = super::reach_m(model);
    let radii = super::LinkRadii::default();
    let mut estimated = Vec::new();
    for i in 0..n {
        if model.links[i].is_some() {
            continue;
        }
        let (body, source) = estimate_link(model, i, reach, &radii);
        estimated.push(format!(
            "`{}` {:.1} kg ({})",
            model.link_names[i],
            body.mass,
            match source {
                InertiaSource::EstimateFromVisual => format!(
                    "visual shapes (no collision geometry) at {ESTIMATE_DENSITY_KG_M3:.0} kg/m³"
                ),
                InertiaSource::EstimateFromGeometry => {
                    format!("collision shapes at {ESTIMATE_DENSITY_KG_M3:.0} kg/m³")
                }
                _ => format!("collision capsule at {CAPSULE_DENSITY_KG_M3:.0} kg/m³"),
            }
        ));
        model.links[i] = Some(body);
        model.info.inertia_sources[i] = source;
    }
    if !estimated.is_empty() {
        warn_estimates(model, &estimated);
    }
    let w = placeholder_warnings(model);
    model.warnings.extend(w);
}

/// The estimate of moving link `i` without an inertial: solids filling its collision shapes,
/// else its visual shapes, else the collision capsule; with where it came from.
fn estimate_link(
    model: &RobotModel,
    i: usize,
    reach: f64,
    radii: &super::LinkRadii,
) -> (Inertial, InertiaSource) {
    let rho = ESTIMATE_DENSITY_KG_M3;
    let mut body = Inertial::zero();
    let mut any = false;
    let mut from_visual = false;
    for (geoms, visual) in [(&model.link_collision, false), (&model.link_visual, true)] {
        if any {
            break;
        }
        for g in geoms.get(i).into_iter().flatten() {
            if let Some(b) = solid(&g.shape, rho) {
                body = body.merged(&b.transformed(&g.origin));
                any = true;
                from_visual = visual;
            }
        }
    }
    if any && from_visual {
        (body, InertiaSource::EstimateFromVisual)
    } else if any {
        (body, InertiaSource::EstimateFromGeometry)
    } else {
        // The capsule of the collision model: this joint's origin to the next (or the
        // flange), radius by the index of the joint the segment ends at.
        let end = model
            .joints
            .get(i + 1)
            .map_or(model.flange.pos, |j| j.origin.pos);
        // The segment ends at joint i + 1: base up to joint 1, arm up to joint 3.
        let end_joint = i + 1;
        let r = reach
            * if end_joint <= 1 {
                radii.base
            } else if end_joint <= 3 {
                radii.arm
            } else {
                radii.wrist
            };
        let len = end.norm();
        // A cylinder of the capsule's volume (πr²L + 4/3 πr³); a zero-length segment
        // (a wrist joint on the previous one's origin) is a sphere of radius r.
        let b = if len > 1e-9 {
            cylinder(r, len + 4.0 / 3.0 * r, CAPSULE_DENSITY_KG_M3)
                .transformed(&segment_frame(&V3::zeros(), &end))
        } else {
            solid(&GeomShape::Sphere { radius_m: r }, CAPSULE_DENSITY_KG_M3)
                .unwrap_or(Inertial::zero())
        };
        (b, InertiaSource::EstimateFromCapsule)
    }
}

/// The warning listing the estimated links (`estimated`), their total mass, and how it was
/// scaled to the robot's stated mass or how uncertain it is.
fn warn_estimates(model: &mut RobotModel, estimated: &[String]) {
    let n = model.dof();
    let total: f64 = (0..n)
        .filter(|&i| model.info.inertia_sources[i].is_estimate())
        .filter_map(|i| model.links[i].map(|l| l.mass))
        .sum();
    let scaled = model
        .info
        .mass_kg
        .map(|m| scale_to_stated_mass(model, m, total));
    let uncertainty = match &scaled {
        Some(Ok(s)) => format!(
            "{total:.0} kg in all before scaling, scaled by {:.3} to {:.0} kg so that, with \
             the fixed base estimated the same way ({:.0} kg before scaling){}, the robot \
             weighs the drive file's [robot] mass_kg = {} kg (the datasheet's mass): the \
             total is the datasheet's, its split between the links and the centres of mass \
             and inertias remain ESTIMATEs (the inertias scaled with the masses)",
            s.factor,
            s.factor * total,
            s.base_kg,
            if s.given_kg > 0.0 {
                format!(" and the links given ({:.0} kg)", s.given_kg)
            } else {
                String::new()
            },
            s.stated_kg
        ),
        Some(Err(why)) => format!(
            "{total:.0} kg in all, not scaled to the drive file's [robot] mass_kg ({why}), \
             uncertain by about ±{:.0} % in mass and more in centre of mass and inertia",
            100.0 * ESTIMATE_MASS_UNCERTAINTY_REL
        ),
        None => format!(
            "{total:.0} kg in all, uncertain by about ±{:.0} % in mass and more in centre \
             of mass and inertia (the effective density stands for metal filling a sixth of \
             the outer volume, motors and gearboxes averaged in; the drive file's [robot] \
             mass_kg, the datasheet's mass, would scale them to it)",
            100.0 * ESTIMATE_MASS_UNCERTAINTY_REL
        ),
    };
    model.warnings.push(format!(
        "ESTIMATE: link inertias missing from the URDF estimated as solids (hollow cast \
         links) filling their collision shapes (their convex hulls): {}; {uncertainty}; the \
         energy is only as good as these; give the real values in the drive file's \
         [links.<name>] tables (docs/drive-file.md)",
        estimated.join(", "),
    ));
}

/// How the estimated link masses were scaled to the robot's stated mass.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct MassScaling {
    /// The factor applied to every estimated link's mass and inertia.
    pub factor: f64,
    /// The fixed base's mass estimated from its collision (else visual) shapes, before
    /// scaling, kg (0 when it has none).
    pub base_kg: f64,
    /// The moving links given by the URDF or the drive file, kg.
    pub given_kg: f64,
    /// The robot's stated mass, kg.
    pub stated_kg: f64,
}

/// Scale the estimated moving links (mass and inertia; centres of mass kept) so that they,
/// the fixed base estimated the same way and the links given weigh `stated_kg`. The factor is
/// `(stated − given) / (estimated links + estimated base)`. `Err` (nothing changed) when the
/// links given already weigh the stated mass or more.
fn scale_to_stated_mass(
    model: &mut RobotModel,
    stated_kg: f64,
    estimated_kg: f64,
) -> std::result::Result<MassScaling, String> {
    let n = model.dof();
    let est = |i: usize| model.info.inertia_sources[i].is_estimate();
    let given_kg: f64 = (0..n)
        .filter(|&i| !est(i))
        .filter_map(|i| model.links[i].map(|l| l.mass))
        .sum();
    let mut base_kg: f64 = model
        .base_collision
        .iter()
        .filter_map(|g| solid(&g.shape, ESTIMATE_DENSITY_KG_M3).map(|b| b.mass))
        .sum();
    if !base_kg.is_finite() {
        base_kg = 0.0;
    }
    let factor = (stated_kg - given_kg) / (estimated_kg + base_kg);
    if !(factor.is_finite() && factor > 0.0) {
        return Err(format!(
            "the links given weigh {given_kg:.0} kg, not less than the stated {stated_kg} kg"
        ));
    }
    for i in 0..n {
        if est(i) {
            if let Some(l) = model.links[i].as_mut() {
                l.mass *= factor;
                l.inertia *= factor;
            }
        }
    }
    Ok(MassScaling {
        factor,
        base_kg,
        given_kg,
        stated_kg,
    })
}

/// Warnings for link inertias that look like placeholders: the same mass on every moving
/// link given by the URDF or the drive file (three or more links), or a total moving mass
/// below the rated payload.
pub(crate) fn placeholder_warnings(model: &RobotModel) -> Vec<String> {
    let mut out = Vec::new();
    let given: Vec<(usize, f64)> = model
        .links
        .iter()
        .enumerate()
        .filter(|(i, _)| {
            !model
                .info
                .inertia_sources
                .get(*i)
                .is_some_and(|s| s.is_estimate())
        })
        .filter_map(|(i, l)| l.map(|l| (i, l.mass)))
        .collect();
    if given.len() >= 3 && given.len() == model.dof() {
        let m0 = given[0].1;
        if given
            .iter()
            .all(|(_, m)| (m - m0).abs() <= 1e-9 * m0.abs().max(1.0))
        {
            out.push(format!(
                "every moving link has the same mass, {m0} kg: placeholder inertias? The \
                 energy computed on them is not the robot's; give the real values in the drive \
                 file's [links.<name>] tables (docs/drive-file.md)"
            ));
        }
    }
    let total: f64 = model.links.iter().flatten().map(|l| l.mass).sum();
    if let Some(p) = model.info.rated_payload_kg.filter(|p| *p > 0.0) {
        if total < p {
            out.push(format!(
                "the moving links weigh {total:.1} kg in all, less than the rated payload of \
                 {p} kg: placeholder inertias? Give the real values in the drive file's \
                 [links.<name>] tables (docs/drive-file.md)"
            ));
        }
    }
    out
}
