//! The placement value: where the toolpath's part frame sits in the robot base frame and how
//! the nozzle is turned. It depends on nothing but the math module, so that every stage that
//! needs a placement (timing follows the path at one, the readers of placement sets build
//! them) takes this one value.

use crate::math::{rot_z, Frame, M3, V3};

/// A coordinate at least this far from the base (m) is taken for millimetres by
/// [`Placement::check_metres`]: no arm reaches 50 m.
pub(crate) const MAX_PLAUSIBLE_M: f64 = 50.0;

/// A placement coordinate no arm reaches, as [`Placement::check_metres`] finds it.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("{axis} = {value_m} m: no robot reaches that far; placements are in metres — did you mean {} m (the value in mm)?", value_m / 1000.0)]
pub struct PlacementUnitsError {
    /// `x`, `y` or `z`.
    pub axis: char,
    /// The value given, m.
    pub value_m: f64,
}

/// Where the part sits in the robot's base frame, and how the nozzle is turned: the one value
/// every placement signature takes (timing, evaluation, sweep, optimiser, export).
///
/// `base = Rz(yaw) · part + (x, y, z)`: the part frame is turned by `yaw` (rad) about the
/// vertical and its origin moved to `(x, y, z)` (m). `z` is the height of the nozzle tip at the
/// part-frame origin above the base-frame origin (so the print bed height is folded into `z`).
///
/// **Spin** has one meaning in printwatt: `nozzle_spin` (rad) is the rotation of the nozzle
/// about its own vertical axis *relative to the part frame*, held fixed along the whole path (a
/// round nozzle does not care; the robot's wrist does). The nozzle's rotation in the base frame
/// is therefore `yaw + nozzle_spin` ([`Placement::nozzle_yaw`]): turning the part turns the
/// nozzle with it. The command line's `--at x,y,z,yaw,spin` and `--spin` (deg), the
/// `nozzle_spin` column of a placement set and JSON's `spin_deg`/`nozzle_spin_deg` all mean this
/// same angle, in degrees.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Placement {
    /// Translation along base x, m.
    pub x: f64,
    /// Translation along base y, m.
    pub y: f64,
    /// Translation along base z (nozzle tip height of the part origin), m.
    pub z: f64,
    /// Rotation of the part about the vertical, rad.
    pub yaw: f64,
    /// Fixed rotation of the nozzle about its vertical axis, relative to the part frame, rad.
    pub nozzle_spin: f64,
}

impl Placement {
    /// A placement without nozzle spin: position in m, yaw in rad.
    pub fn new(x: f64, y: f64, z: f64, yaw: f64) -> Self {
        Placement {
            x,
            y,
            z,
            yaw,
            nozzle_spin: 0.0,
        }
    }

    /// The part → base transform (m).
    pub fn frame(&self) -> Frame {
        Frame::new(rot_z(self.yaw), V3::new(self.x, self.y, self.z))
    }

    /// Map a part-frame point (m) to the base frame (m).
    pub fn apply(&self, p: &V3) -> V3 {
        self.frame().apply(p)
    }

    /// The nozzle's rotation about the vertical in the base frame, rad: `yaw + nozzle_spin`
    /// (the tool x axis points along `(cos, sin, 0)` of it; see
    /// [`nozzle_target`]).
    #[inline]
    pub fn nozzle_yaw(&self) -> f64 {
        self.yaw + self.nozzle_spin
    }

    /// The nozzle pose (base frame) with its tip at the part-frame point `p` (m): the tip at
    /// `self.apply(p)`, the nozzle pointing down and turned by [`Placement::nozzle_yaw`].
    pub fn nozzle_target(&self, p: &V3) -> Frame {
        nozzle_target(&self.apply(p), self.nozzle_yaw())
    }

    /// This placement with `spin` (rad) as its nozzle spin.
    pub fn with_spin(self, spin: f64) -> Placement {
        Placement {
            nozzle_spin: spin,
            ..self
        }
    }

    /// Positions no arm reaches (|x|, |y| or |z| ≥ 50 m) are almost always millimetres typed
    /// where metres are expected: `Err` with the coordinate, its value in m and the value
    /// divided by 1000 (see [`PlacementUnitsError`]).
    pub fn check_metres(&self) -> std::result::Result<(), PlacementUnitsError> {
        for (axis, v) in [('x', self.x), ('y', self.y), ('z', self.z)] {
            if v.abs() >= MAX_PLAUSIBLE_M {
                return Err(PlacementUnitsError { axis, value_m: v });
            }
        }
        Ok(())
    }

    /// Parse the text form `x,y,z,yaw[,spin]`: x, y, z in m, yaw and the optional nozzle spin
    /// in degrees (spin 0 when absent). Every item must be a finite number (no `nan`, no
    /// `inf`, no empty item). The one parser of placements given as text.
    pub fn parse(s: &str) -> std::result::Result<Placement, PlacementParseError> {
        let mut v = Vec::with_capacity(5);
        for (i, t) in s.split(',').enumerate() {
            let t = t.trim();
            let item = i + 1;
            if t.is_empty() {
                return Err(PlacementParseError::Empty { item });
            }
            let x: f64 = t.parse().map_err(|_| PlacementParseError::NotANumber {
                item,
                text: t.to_string(),
            })?;
            if !x.is_finite() {
                return Err(PlacementParseError::NotFinite {
                    item,
                    text: t.to_string(),
                });
            }
            v.push(x);
        }
        if v.len() != 4 && v.len() != 5 {
            return Err(PlacementParseError::Count { got: v.len() });
        }
        Ok(Placement {
            x: v[0],
            y: v[1],
            z: v[2],
            yaw: v[3].to_radians(),
            nozzle_spin: v.get(4).copied().unwrap_or(0.0).to_radians(),
        })
    }
}

impl std::str::FromStr for Placement {
    type Err = PlacementParseError;
    fn from_str(s: &str) -> std::result::Result<Self, Self::Err> {
        Placement::parse(s)
    }
}

/// Why a placement text (`x,y,z,yaw[,spin]`, see [`Placement::parse`]) does not parse. Items
/// are numbered from 1.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum PlacementParseError {
    /// An item is empty (`1.7,,0,90`).
    #[error(
        "item {item} is empty; expected x,y,z,yaw (m, m, m, deg) and an optional nozzle spin (deg)"
    )]
    Empty {
        /// 1-based item.
        item: usize,
    },
    /// An item is not a number.
    #[error("item {item} `{text}` is not a number")]
    NotANumber {
        /// 1-based item.
        item: usize,
        /// The text of the item.
        text: String,
    },
    /// An item is NaN or infinite.
    #[error("item {item} `{text}` is not a finite number")]
    NotFinite {
        /// 1-based item.
        item: usize,
        /// The text of the item.
        text: String,
    },
    /// Not 4 or 5 items.
    #[error("{got} numbers: expected x,y,z,yaw (m, m, m, deg) and an optional nozzle spin (deg)")]
    Count {
        /// Number of items given.
        got: usize,
    },
}

/// A placement with a name, as read by [`load_placements`].
#[derive(Clone, Debug, PartialEq)]
pub struct NamedPlacement {
    /// Name from the file (e.g. `P1`).
    pub name: String,
    /// The placement (m, rad).
    pub placement: Placement,
}

/// Tool pose for printing: nozzle tip at `tip` (base frame, m), nozzle (tool +z) pointing
/// straight down (−Z of the base), turned by `spin` (rad) about the nozzle axis (tool +x =
/// `(cos spin, sin spin, 0)`).
pub fn nozzle_target(tip: &V3, spin: f64) -> Frame {
    let (s, c) = spin.sin_cos();
    Frame {
        rot: M3::new(c, s, 0.0, s, -c, 0.0, 0.0, 0.0, -1.0),
        pos: *tip,
    }
}
