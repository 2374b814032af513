//! Time parameterisation of a toolpath the way a robot controller runs it.

pub mod budget;
pub mod geometry;
pub mod joint;
pub mod profile;

pub use geometry::{blend_path, Move, Piece, Prim};
pub use joint::{
    time_at, time_at_planned, time_path, time_path_planned, Buffers, JointStageOptions, LimitKind,
    Plan, Slowdown, TimedPath, TimingFailure,
};
pub use profile::{CartesianMotion, ProfileOptions};

/// Moves shorter than this are dropped before timing (extruder-only moves, duplicates), m.
pub const MIN_MOVE_LENGTH_M: f64 = 1e-7;

/// The programmed moves of a toolpath as timing primitives (part frame, m). Moves of zero
/// length (extruder-only lines, duplicates) are dropped.
pub fn moves_from_toolpath(path: &crate::toolpath::Toolpath) -> Vec<Move> {
    use crate::toolpath::MoveKind;
    let mut out = Vec::with_capacity(path.moves.len());
    for (i, m) in path.moves.iter().enumerate() {
        let p0 = path.move_start(i);
        let prim = match m.kind {
            MoveKind::Line => Prim::Line { a: p0, b: m.end },
            MoveKind::Arc {
                centre,
                normal,
                radius,
                sweep,
                axial,
            } => {
                let u = (p0 - centre).normalize();
                let w = normal.cross(&u);
                Prim::Arc {
                    centre,
                    u,
                    w,
                    radius,
                    sweep,
                    rise: normal * axial,
                }
            }
        };
        if prim.length() < MIN_MOVE_LENGTH_M {
            continue;
        }
        out.push(Move {
            prim,
            speed: m.speed,
            zone: m.zone.radius(),
            print: m.print,
            line: m.line,
        });
    }
    out
}
