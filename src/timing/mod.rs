//! Time parameterisation of a toolpath the way a robot controller runs it.

pub mod budget;
pub(crate) mod geometry;
pub mod joint;
pub mod profile;
mod reach;

pub use geometry::{blend_path, blend_path_with_dwells, Move, Piece, Prim};
pub use joint::{
    time_at, time_at_planned, time_path, time_path_planned, Buffers, JointStageOptions, LimitKind,
    PathTiming, Plan, Slowdown, TimedPath, TimingFailure,
};
pub use profile::{CartesianMotion, ProfileOptions};

/// Moves shorter than this are dropped before timing (extruder-only moves, duplicates), m.
pub(crate) const MIN_MOVE_LENGTH_M: f64 = 1e-7;

/// The programmed moves of a toolpath as timing primitives (part frame, m). Moves of zero
/// length (extruder-only lines, duplicates) are dropped.
pub fn moves_from_toolpath(path: &crate::toolpath::Toolpath) -> Vec<Move> {
    let mut out = Vec::with_capacity(path.moves.len());
    for (i, m) in path.moves.iter().enumerate() {
        let prim = prim_of(path, i);
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

/// The geometry of toolpath move `i` as a timing primitive (part frame, m).
fn prim_of(path: &crate::toolpath::Toolpath, i: usize) -> Prim {
    use crate::toolpath::MoveKind;
    let m = &path.moves[i];
    let p0 = path.move_start(i);
    match m.kind {
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
    }
}

/// The dwells of a toolpath as `(timing move index, seconds)` for [`blend_path_with_dwells`]: the index
/// is that of the timing move (see [`moves_from_toolpath`]) the dwell follows, `None` before
/// the first one (at the start point). Dwells of zero seconds are dropped.
pub(crate) fn dwells_from_toolpath(path: &crate::toolpath::Toolpath) -> Vec<(Option<usize>, f64)> {
    if path.dwells.is_empty() {
        return Vec::new();
    }
    // Timing move index after each toolpath move (zero-length moves are dropped there).
    let mut after: Vec<Option<usize>> = Vec::with_capacity(path.moves.len());
    let mut kept: Option<usize> = None;
    for i in 0..path.moves.len() {
        if prim_of(path, i).length() >= MIN_MOVE_LENGTH_M {
            kept = Some(kept.map_or(0, |k| k + 1));
        }
        after.push(kept);
    }
    path.dwells
        .iter()
        .filter(|d| d.seconds > 0.0)
        .map(|d| {
            let k = d
                .after_move
                .and_then(|i| after.get(i.min(after.len().saturating_sub(1))).copied())
                .flatten();
            (k, d.seconds)
        })
        .collect()
}
