//! G5 (cubic), G5.1 (quadratic) and G5.2 … G5.3 (NURBS) splines in the XY plane, read as
//! LinuxCNC 2.9 reads them (docs/gcode.md "Splines"), and moved along as straight feed moves
//! (chords) that stay within a stated tolerance of the curve.
//!
//! - G5 X Y I J P Q: a cubic Bézier from where the machine stands to X Y; I J is the first
//!   control point from the start, P Q the second from the end. Without I J, the curve
//!   continues the previous G5's tangent: its first control point is the previous second one
//!   mirrored about the join.
//! - G5.1 X Y I J: a quadratic Bézier, I J its control point from the start.
//! - G5.2 X Y P [L] … G5.3: a NURBS. The machine's position is the first control point; each
//!   G5.2 line (or a line of X Y P while G5.2 is in force) adds one with its weight P; L on the
//!   first line is the order (3 if absent). G5.3 moves along the curve, on LinuxCNC's clamped
//!   uniform knots, to the last control point.
//!
//! The curve geometry is in [`curve`]; this module checks the words, keeps what the state must
//! keep between lines ([`PendingNurbs`], the G5 tangent), and emits the chords through cutter
//! compensation's `line` (which refuses nothing here: splines are refused under compensation).

pub mod curve;
#[cfg(test)]
mod tests;

use super::comp::Comp;
use super::exec::{feed_rate, int_word, Exec};
use super::moves;
use super::state::{FeedMode, InterpState, Motion, PathMode, PendingNurbs};
use super::words::Words;
use crate::block::{Plane, TranslateError};
use crate::settings::MachineSettings;

/// The most chords one spline may make (docs/gcode.md "Limits").
pub const MAX_CHORDS: usize = 100_000;
/// The most control points of one NURBS, the start included.
pub const MAX_CONTROL_POINTS: usize = 10_000;
/// The highest NURBS order L (degree + 1).
pub const MAX_ORDER: usize = 16;
/// The farthest a control point may lie from the program zero, mm.
const FAR: f64 = 1e9;

/// How far a chord may stray from the curve, mm: G64 P when it is in force and not below one
/// pulse (the path may leave the program by that much anyway), else one pulse, the machine's
/// least input increment.
pub fn tolerance(st: &InterpState, settings: &MachineSettings) -> f64 {
    match st.modal.path {
        PathMode::Blend { p: Some(p), .. } if p > settings.pulse_mm => p,
        _ => settings.pulse_mm,
    }
}

/// One line of G5, G5.1 or G5.2 (motion `g` ×10: 50, 51, 52).
pub fn spline(
    st: &mut InterpState,
    comp: &mut Comp,
    x: &mut Exec,
    w: &Words,
    g: u16,
    col: u32,
    inverse: Option<f64>,
) -> Result<(), TranslateError> {
    usable_here(st, comp, x, col)?;
    if st.modal.feed_mode == FeedMode::PerMinute {
        // A zero F is refused on every spline line, as LinuxCNC does.
        feed_rate(st, x, inverse, 0.0, col)?;
    }
    if let Some(c) = w.col('Z') {
        return Err(x.err(
            c,
            "a spline moves in X and Y only: no Z on a G5, G5.1 or G5.2 line",
        ));
    }
    match g {
        50 | 51 => bezier_line(st, comp, x, w, g == 50, col, inverse),
        _ => nurbs_point(st, x, w, col),
    }
}

/// G5.3: moves along the NURBS the G5.2 lines gave. `motion` is the line's motion (a G5.2 on
/// the line starts the next NURBS after this one ends, as in LinuxCNC).
pub fn end_nurbs(
    st: &mut InterpState,
    comp: &mut Comp,
    x: &mut Exec,
    w: &Words,
    motion: Option<Motion>,
    col: u32,
    inverse: Option<f64>,
) -> Result<(), TranslateError> {
    match motion {
        Some(Motion::Spline(52)) if w.has_g(52).is_none() => {
            return Err(x.err(
                col,
                "G5.3 takes no X or Y: it ends the NURBS at its last control point",
            ))
        }
        Some(Motion::Spline(52)) | None => {}
        Some(_) => return Err(x.err(
            col,
            "between G5.2 and G5.3 only more G5.2 lines may come: no other motion on the G5.3 line",
        )),
    }
    let Some(n) = st.nurbs.take() else {
        return Err(x.err(col, "G5.3 without G5.2 first: there is no NURBS to end"));
    };
    usable_here(st, comp, x, col)?;
    if n.points.len() < n.order {
        return Err(x.err(
            col,
            format!(
                "the NURBS has {} control points (the start included): its order L{} needs at least {}",
                n.points.len(),
                n.order,
                n.order
            ),
        ));
    }
    let start = n.points[0];
    if (start[0] - st.pos[0]).hypot(start[1] - st.pos[1]) > 1e-6 {
        return Err(x.err(
            col,
            format!(
                "the machine has moved since the NURBS began on line {}: it starts where its first G5.2 line found the machine",
                n.line
            ),
        ));
    }
    let last = n.points[n.points.len() - 1];
    let end = [last[0], last[1], st.pos[2]];
    let pieces = curve::nurbs(&n.points, &n.weights, n.order);
    follow(st, comp, x, &pieces, end, inverse, col)?;
    st.modal.motion = Motion::None;
    Ok(())
}

/// Refuses `what` (a motion other than G5.2, or the program's end) while a NURBS waits for
/// its G5.3: its points would be lost.
pub fn unfinished(st: &InterpState, line: u32, col: u32, what: &str) -> Result<(), TranslateError> {
    match &st.nurbs {
        Some(n) => Err(TranslateError {
            line,
            col,
            message: format!(
                "{what} before G5.3: the NURBS begun on line {} must be ended by G5.3 first",
                n.line
            ),
        }),
        None => Ok(()),
    }
}

/// Splines are refused under cutter compensation and outside the XY plane, as in LinuxCNC.
fn usable_here(st: &InterpState, comp: &Comp, x: &Exec, col: u32) -> Result<(), TranslateError> {
    if comp.active() && !comp.pending_exit() {
        return Err(x.err(
            col,
            "splines (G5, G5.1, G5.2) cannot be used with cutter radius compensation on",
        ));
    }
    if st.modal.plane != Plane::XY {
        return Err(x.err(col, "splines work in the XY plane (G17) only"));
    }
    Ok(())
}

/// The value of an offset word (I J P Q) in mm, if given.
fn offset(st: &InterpState, x: &Exec, w: &Words, c: char) -> Result<Option<f64>, TranslateError> {
    match w.get(c) {
        Some(v) => {
            let mm = v * st.factor();
            if !mm.is_finite() || mm.abs() > FAR {
                return Err(x.err(w.col(c).unwrap_or(1), format!("{c} is out of all range")));
            }
            Ok(Some(mm))
        }
        None => Ok(None),
    }
}

/// Both of two offset words, or neither.
fn pair(
    st: &InterpState,
    x: &Exec,
    w: &Words,
    names: [char; 2],
    col: u32,
    message: &str,
) -> Result<Option<[f64; 2]>, TranslateError> {
    match (offset(st, x, w, names[0])?, offset(st, x, w, names[1])?) {
        (Some(a), Some(b)) => Ok(Some([a, b])),
        (None, None) => Ok(None),
        _ => Err(x.err(col, message)),
    }
}

/// The machine XY of a point of the program frame (mm) at the current program Z.
fn machine_xy(st: &InterpState, p: [f64; 2]) -> [f64; 2] {
    let m = st.to_machine([p[0], p[1], st.prog()[2]]);
    [m[0], m[1]]
}

fn add(a: [f64; 2], d: [f64; 2]) -> [f64; 2] {
    [a[0] + d[0], a[1] + d[1]]
}

/// G5 (`cubic`) or G5.1: the Bézier curve from the start through I J (from the start) and,
/// for G5, P Q (from the end) to X Y.
fn bezier_line(
    st: &mut InterpState,
    comp: &mut Comp,
    x: &mut Exec,
    w: &Words,
    cubic: bool,
    col: u32,
    inverse: Option<f64>,
) -> Result<(), TranslateError> {
    let ij = if cubic {
        let message =
            "G5 takes both I and J, or neither (then it continues the previous G5's tangent)";
        pair(st, x, w, ['I', 'J'], col, message)?.unwrap_or(st.g5_tangent)
    } else {
        let message = "G5.1 needs both I and J, the control point from the start";
        pair(st, x, w, ['I', 'J'], col, message)?.ok_or_else(|| x.err(col, message))?
    };
    let end = moves::target(st, x, w)?;
    let s = st.prog();
    let mut points = vec![
        [st.pos[0], st.pos[1]],
        machine_xy(st, add([s[0], s[1]], ij)),
    ];
    let pq = if cubic {
        let message = "G5 needs both P and Q, the second control point from the end";
        let pq = pair(st, x, w, ['P', 'Q'], col, message)?.ok_or_else(|| x.err(col, message))?;
        let e = st.to_program(end);
        points.push(machine_xy(st, add([e[0], e[1]], pq)));
        Some(pq)
    } else {
        None
    };
    points.push([end[0], end[1]]);
    follow(st, comp, x, &[curve::bezier(&points)], end, inverse, col)?;
    if let Some(pq) = pq {
        st.g5_tangent = [-pq[0], -pq[1]];
    }
    Ok(())
}

/// A G5.2 line: the first begins a NURBS at the machine's position (P alone weighs that
/// point), each adds the control point X Y with weight P.
fn nurbs_point(
    st: &mut InterpState,
    x: &mut Exec,
    w: &Words,
    col: u32,
) -> Result<(), TranslateError> {
    if let Some(c) = w.col('@').or(w.col('^')) {
        return Err(x.err(
            c,
            "G5.2 control points are given by X and Y, not by polar words (@ ^)",
        ));
    }
    let xy = match (w.get('X'), w.get('Y')) {
        (Some(_), Some(_)) => true,
        (None, None) => false,
        _ => return Err(x.err(col, "a G5.2 control point needs both X and Y")),
    };
    let p = w.get('P');
    let p_col = w.col('P').unwrap_or(col);
    if let Some(p) = p {
        if !(p > 0.0 && p <= FAR) {
            return Err(x.err(
                p_col,
                format!("P{p}: a control point's weight must be greater than 0"),
            ));
        }
    }
    if xy && p.is_none() {
        return Err(x.err(
            col,
            "every control point needs its weight P, greater than 0",
        ));
    }
    let first = st.nurbs.is_none();
    let order = match int_word(x, w, 'L', 0.0, 1e9)? {
        Some(_) if !first => {
            return Err(x.err(
                w.col('L').unwrap_or(col),
                "L (the NURBS's order) is given on its first G5.2 line only",
            ))
        }
        Some(l) if (l as usize) < 3 || l as usize > MAX_ORDER => {
            return Err(x.err(
                w.col('L').unwrap_or(col),
                format!("L{l}: a NURBS's order is 3 (quadratic) to {MAX_ORDER}"),
            ))
        }
        Some(l) => l as usize,
        None => 3,
    };
    if first {
        st.nurbs = Some(PendingNurbs {
            points: vec![[st.pos[0], st.pos[1]]],
            weights: vec![if xy { 1.0 } else { p.unwrap_or(1.0) }],
            order,
            line: x.n,
        });
    } else if !xy {
        return Err(x.err(
            col,
            "a G5.2 line after the first gives a control point: X, Y and its weight P (P alone weighs the start, on the first line)",
        ));
    }
    let (true, Some(p)) = (xy, p) else {
        return Ok(());
    };
    let at = moves::target(st, x, w)?;
    let Some(n) = st.nurbs.as_mut() else {
        return Ok(());
    };
    if n.points.len() >= MAX_CONTROL_POINTS {
        return Err(x.err(
            col,
            format!("a NURBS of more than {MAX_CONTROL_POINTS} control points: end it with G5.3 and begin another"),
        ));
    }
    n.points.push([at[0], at[1]]);
    n.weights.push(p);
    Ok(())
}

/// Moves along `pieces` from the machine's position to `end` (machine mm, exact): the chords
/// within the tolerance, at the feed the mode in force gives for their whole length.
fn follow(
    st: &mut InterpState,
    comp: &mut Comp,
    x: &mut Exec,
    pieces: &[curve::Piece],
    end: [f64; 3],
    inverse: Option<f64>,
    col: u32,
) -> Result<(), TranslateError> {
    let tol = tolerance(st, x.settings);
    let chords = curve::flatten(pieces, tol, MAX_CHORDS).map_err(|_| {
        x.err(
            col,
            format!("this spline needs more than {MAX_CHORDS} chords to stay within {tol} mm of its curve: split it, or allow more with G64 P"),
        )
    })?;
    let z = st.pos[2];
    let mut ends: Vec<[f64; 3]> = chords.iter().map(|c| [c.at[0], c.at[1], z]).collect();
    match ends.last_mut() {
        Some(last) => *last = [end[0], end[1], z],
        None => ends.push([end[0], end[1], z]),
    }
    if ends
        .iter()
        .flatten()
        .any(|v| !v.is_finite() || v.abs() > FAR)
    {
        return Err(x.err(col, "the spline's curve is out of all range"));
    }
    let mut length = 0.0;
    let mut from = st.pos;
    for e in &ends {
        length += (e[0] - from[0]).hypot(e[1] - from[1]);
        from = *e;
    }
    let feed = feed_rate(st, x, inverse, length, col)?;
    if comp.pending_exit() {
        // After G40: the exit move goes to where the curve starts, then the chords follow it.
        comp.line(x, st.pos, st.pos, false, feed, col)?;
    }
    for e in ends {
        if e != st.pos {
            comp.line(x, st.pos, e, false, feed, col)?;
            st.pos = e;
        }
    }
    Ok(())
}
