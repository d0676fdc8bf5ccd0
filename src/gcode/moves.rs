//! The moves and offsets of one line (docs/gcode.md "Arcs", "Coordinates"): straight moves
//! through cutter compensation, arcs by I J K or R, G10 work offsets and G28.

use super::canon::Canon;
use super::geom::{self, ArcFault};
use super::interp::{Exec, Mode, State, Words};
use super::OffsetChange;
use crate::block::TranslateError;
use crate::input_text::fixed;

/// The end point of a straight move in machine mm from the axis words (program frame).
pub fn target(st: &State, w: &Words) -> [f64; 3] {
    let k = st.factor();
    let p = st.prog();
    let mut e = p;
    for (i, c) in ['X', 'Y', 'Z'].into_iter().enumerate() {
        if let Some(v) = w.get(c) {
            e[i] = if st.incremental { p[i] + v * k } else { v * k };
        }
    }
    st.machine(e)
}

/// A straight move (rapid or feed by the mode) to machine point `e`, through compensation.
pub(super) fn move_to(
    st: &mut State,
    x: &mut Exec,
    e: [f64; 3],
    col: u32,
    _w: &Words,
) -> Result<(), TranslateError> {
    let rapid = st.mode == Mode::Rapid;
    let feed = st.feed;
    let from = st.cur;
    st.comp.line(x, from, e, rapid, feed, col)?;
    st.cur = e;
    Ok(())
}

/// G02/G03 with I J K or R; a helix with the normal axis's word.
pub(super) fn arc(st: &mut State, x: &mut Exec, w: &Words, col: u32) -> Result<(), TranslateError> {
    let k = st.factor();
    let plane = st.plane;
    let [a0, a1, _] = plane.axes();
    let [u, v] = plane.turn_axes();
    let names = ['I', 'J', 'K'];
    for (i, c) in names.into_iter().enumerate() {
        if i != a0 && i != a1 {
            if let Some(cc) = w.col(c) {
                return Err(x.err(
                    cc,
                    format!(
                        "{c} has no meaning for an arc in the {} plane ({})",
                        ["YZ", "XZ", "XY"][i],
                        plane.g_code()
                    ),
                ));
            }
        }
    }
    if let Some(pc) = w.col('P') {
        return Err(x.err(
            pc,
            "P (turns) on G02/G03 is not supported: one arc makes at most one full turn",
        ));
    }
    let e = target(st, w);
    let s = st.cur;
    let cw = st.mode == Mode::Cw;
    let r = w.get('R');
    let has_ijk = w.get(names[a0]).is_some() || w.get(names[a1]).is_some();
    let su = [s[u], s[v]];
    let eu = [e[u], e[v]];
    let cuv = match (r, has_ijk) {
        (Some(_), true) => {
            return Err(x.err(
                w.col('R').unwrap_or(col),
                "give the arc's centre by I J K or by R, not both",
            ));
        }
        (None, false) => {
            return Err(x.err(
                col,
                format!("an arc needs its centre: {}{} or R", names[a0], names[a1]),
            ));
        }
        (Some(r), false) => {
            let tol = if st.inch {
                geom::R_TOLERANCE_INCH * 25.4
            } else {
                geom::R_TOLERANCE_MM
            };
            geom::centre_r(su, eu, r * k, cw, tol)
                .map_err(|f| fault(x, f, w.col('R').unwrap_or(col), k))?
        }
        (None, true) => {
            let mut c = s;
            c[a0] += w.get(names[a0]).unwrap_or(0.0) * k;
            c[a1] += w.get(names[a1]).unwrap_or(0.0) * k;
            let cuv = [c[u], c[v]];
            let tol = if st.inch {
                geom::IJK_ABS_TOLERANCE_INCH * 25.4
            } else {
                geom::IJK_ABS_TOLERANCE_MM
            };
            geom::check_ijk(su, eu, cuv, tol).map_err(|f| fault(x, f, col, k))?;
            cuv
        }
    };
    let mut centre = s;
    centre[u] = cuv[0];
    centre[v] = cuv[1];
    let feed = st.feed;
    st.comp.arc(x, s, e, centre, plane, !cw, feed, col)?;
    st.cur = e;
    Ok(())
}

fn fault(x: &Exec, f: ArcFault, col: u32, k: f64) -> TranslateError {
    let unit = if k == 1.0 { "mm" } else { "in" };
    let m = |v: f64| v / k;
    match f {
        ArcFault::RTooSmall { half, r } => x.err(
            col,
            format!("R{} is too small for the chord: the end point is {} {unit} from the start, more than 2·R", fixed(m(r), 4), fixed(m(2.0 * half), 4)),
        ),
        ArcFault::RFullCircle => x.err(col, "an R arc cannot be a full circle (the end is the start): use I J K"),
        ArcFault::NotOnCircle { r0, r1 } => x.err(
            col,
            format!(
                "the arc's end point is not on its circle: radius {} {unit} at the start, {} {unit} at the end (at most {:.3} mm apart)",
                fixed(m(r0), 4),
                fixed(m(r1), 4),
                geom::NOVANC_RADIUS_DIFF_MM
            ),
        ),
        ArcFault::ZeroRadius => x.err(col, "an arc of zero radius"),
    }
}

/// G10 L2 P (set a work offset) and G10 L20 P (set it so the current point reads X Y Z).
pub(super) fn g10(st: &mut State, x: &mut Exec, w: &Words, col: u32) -> Result<(), TranslateError> {
    let l = w.get('L');
    let lcol = w.col('L').unwrap_or(col);
    let l = match l {
        Some(l) if l == 2.0 || l == 20.0 => l as u32,
        Some(l) => {
            return Err(x.err(
                lcol,
                format!(
                    "G10 L{} is not supported: G10 L2 or L20 set work offsets",
                    crate::input_text::short_number(l)
                ),
            ))
        }
        None => return Err(x.err(col, "G10 needs L2 or L20 (work offsets)")),
    };
    let pcol = w.col('P').unwrap_or(col);
    let p = w.get('P').ok_or_else(|| {
        x.err(
            col,
            "G10 needs P, the coordinate system: P1 (G54) to P6 (G59), P0 the one in force",
        )
    })?;
    if p.fract() != 0.0 || !(0.0..=6.0).contains(&p) {
        return Err(x.err(
            pcol,
            format!(
                "bad G10 P{}: P1 (G54) to P6 (G59), or P0 for the one in force",
                crate::input_text::short_number(p)
            ),
        ));
    }
    if st.comp.active() {
        return Err(x.err(col, "G10 cannot be used with cutter radius compensation on"));
    }
    let idx = if p == 0.0 { st.cs } else { p as usize - 1 };
    let k = st.factor();
    let mut o = st.offsets.0[idx];
    for (i, c) in ['X', 'Y', 'Z'].into_iter().enumerate() {
        if let Some(v) = w.get(c) {
            o[i] = if l == 2 {
                v * k
            } else {
                let tl = if i == 2 { st.tlo } else { 0.0 };
                st.cur[i] - tl - v * k
            };
        }
    }
    for (a, &v) in o.iter().enumerate() {
        if !v.is_finite() || v.abs() > 1e6 {
            return Err(x.err(
                col,
                format!(
                    "work offset {} of {} mm is not usable",
                    ["X", "Y", "Z"][a],
                    crate::input_text::short_number(v)
                ),
            ));
        }
    }
    st.offsets.0[idx] = o;
    x.changes.push(OffsetChange {
        system: idx,
        offset: o,
    });
    Ok(())
}

/// G28: through the intermediate point (the named axes) to machine zero (those axes; all
/// three when none is named).
pub(super) fn g28(st: &mut State, x: &mut Exec, w: &Words, col: u32) {
    let mut home = st.cur;
    if w.has_axis() {
        let mid = target(st, w);
        // Only the named axes move to the intermediate point.
        let mut m = st.cur;
        for (i, c) in ['X', 'Y', 'Z'].into_iter().enumerate() {
            if w.get(c).is_some() {
                m[i] = mid[i];
                home[i] = 0.0;
            }
        }
        x.push(Canon::Rapid(m), col);
        st.cur = m;
    } else {
        home = [0.0; 3];
    }
    x.push(Canon::Rapid(home), col);
    st.cur = home;
}
