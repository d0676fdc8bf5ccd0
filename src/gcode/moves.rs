//! The moves and offsets of one line (docs/gcode.md "Arcs", "Coordinates"): end points from
//! the axis and polar words, straight moves and arcs through cutter compensation, G10, G92
//! and G28/G30.

use super::canon::Canon;
use super::comp::Comp;
use super::exec::{int_word, Event, Exec};
use super::geom::{self, ArcFault};
use super::state::{rotate, system_base, InterpState, Motion, MM_PER_INCH};
use super::words::Words;
use crate::block::TranslateError;

/// The end point of a move in machine mm from the axis words (or the polar words `@` radius
/// and `^` angle, about the program zero in G90 or the current point in G91), in the
/// program's frame.
pub fn target(st: &InterpState, x: &Exec, w: &Words) -> Result<[f64; 3], TranslateError> {
    let k = st.factor();
    let p = st.prog();
    let mut e = p;
    for (i, c) in ['X', 'Y', 'Z'].into_iter().enumerate() {
        if let Some(v) = w.get(c) {
            e[i] = if st.modal.incremental {
                p[i] + v * k
            } else {
                v * k
            };
        }
    }
    if w.get('@').is_some() || w.get('^').is_some() {
        if st.modal.plane != crate::block::Plane::XY {
            let col = w.col('@').or(w.col('^')).unwrap_or(1);
            return Err(x.err(
                col,
                "polar coordinates (@ ^) work in the XY plane (G17) only",
            ));
        }
        // LinuxCNC: absolute polar words are about the program zero; incremental ones add to
        // the current point's radius and angle about the zero.
        let (r0, a0) = (p[0].hypot(p[1]), p[1].atan2(p[0]));
        let r = match w.get('@') {
            Some(v) if st.modal.incremental => r0 + v * k,
            Some(v) => v * k,
            None => r0,
        };
        let a = match w.get('^') {
            Some(v) if st.modal.incremental => a0 + v.to_radians(),
            Some(v) => v.to_radians(),
            None => a0,
        };
        e[0] = r * a.cos();
        e[1] = r * a.sin();
    }
    Ok(st.to_machine(e))
}

/// G02/G03 with I J K (incremental, or absolute under G90.1) or R, P turns; a helix with the
/// normal axis's word.
pub fn arc(
    st: &mut InterpState,
    comp: &mut Comp,
    x: &mut Exec,
    w: &Words,
    col: u32,
    inverse: Option<f64>,
) -> Result<(), TranslateError> {
    let k = st.factor();
    let plane = st.modal.plane;
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
    let turns = int_word(x, w, 'P', 1.0, 1000.0)?.unwrap_or(1);
    let e = target(st, x, w)?;
    let s = st.pos;
    let cw = st.modal.motion == Motion::Cw;
    let r = w.get('R');
    let has_ijk = w.get(names[a0]).is_some() || w.get(names[a1]).is_some();
    // The geometry is worked in the program's frame (rotation and offsets applied after).
    let sp = st.to_program(s);
    let ep = st.to_program(e);
    let su = [sp[u], sp[v]];
    let eu = [ep[u], ep[v]];
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
            let tol = if st.modal.inch {
                geom::R_TOLERANCE_INCH * MM_PER_INCH
            } else {
                geom::R_TOLERANCE_MM
            };
            geom::centre_r(su, eu, r * k, cw, tol)
                .map_err(|f| fault(x, f, w.col('R').unwrap_or(col), k))?
        }
        (None, true) => {
            let mut c = if st.modal.ijk_absolute { [0.0; 3] } else { sp };
            for a in [a0, a1] {
                match w.get(names[a]) {
                    Some(val) if st.modal.ijk_absolute => c[a] = val * k,
                    Some(val) => c[a] += val * k,
                    None if st.modal.ijk_absolute => c[a] = sp[a],
                    None => {}
                }
            }
            let cuv = [c[u], c[v]];
            let tol = if st.modal.inch {
                geom::IJK_ABS_TOLERANCE_INCH * MM_PER_INCH
            } else {
                geom::IJK_ABS_TOLERANCE_MM
            };
            geom::check_ijk_linuxcnc(su, eu, cuv, tol).map_err(|f| match f {
                ArcFault::NotOnCircle { r0, r1 } => x.err(
                    col,
                    format!(
                        "the arc's end point is not on its circle: radius {} at the start, {} at the end, farther apart than LinuxCNC allows ({} or {} and 0.1 %)",
                        in_units(r0, k),
                        in_units(r1, k),
                        in_units(tol * 100.0, k),
                        in_units(tol, k)
                    ),
                ),
                f => fault(x, f, col, k),
            })?;
            cuv
        }
    };
    let mut centre_p = sp;
    centre_p[u] = cuv[0];
    centre_p[v] = cuv[1];
    let centre = st.to_machine(centre_p);
    let length = {
        let rad = (su[0] - cuv[0]).hypot(su[1] - cuv[1]);
        let sweep =
            geom::sweep(su, eu, cuv, !cw) + 2.0 * std::f64::consts::PI * f64::from(turns - 1);
        let axial = (ep[plane.axes()[2]] - sp[plane.axes()[2]]).abs();
        (rad * sweep).hypot(axial)
    };
    let feed = super::exec::feed_rate(st, x, inverse, length, col)?;
    let r0 = (su[0] - cuv[0]).hypot(su[1] - cuv[1]);
    let r1 = (eu[0] - cuv[0]).hypot(eu[1] - cuv[1]);
    let total = geom::sweep(su, eu, cuv, !cw) + 2.0 * std::f64::consts::PI * f64::from(turns - 1);
    let pieces = geom::spiral_pieces(r0, r1, total);
    if pieces > 1 {
        if comp.active() {
            return Err(x.err(
                col,
                format!(
                    "a spiral (radius {} at the start, {} at the end) cannot be used with cutter radius compensation on",
                    in_units(r0, k),
                    in_units(r1, k)
                ),
            ));
        }
        // LinuxCNC's spiral: the radius, and the normal axis, change in proportion to the
        // angle turned. Each piece is an arc about the same centre whose ends are on it.
        let n = plane.axes()[2];
        for i in 1..pieces {
            let f = f64::from(i) / f64::from(pieces);
            let p = geom::spiral_point(su, cuv, r1, total, !cw, f);
            let mut at = sp;
            at[u] = p[0];
            at[v] = p[1];
            at[n] = sp[n] + f * (ep[n] - sp[n]);
            let m = st.to_machine(at);
            comp.arc(x, st.pos, m, centre, plane, !cw, feed, col)?;
            st.pos = m;
        }
        comp.arc(x, st.pos, e, centre, plane, !cw, feed, col)?;
        st.pos = e;
        return Ok(());
    }
    if turns > 1 {
        if comp.active() {
            return Err(x.err(
                col,
                "an arc of several turns (P) cannot be used with cutter radius compensation on",
            ));
        }
        // Whole turns first (each a full circle, the normal axis shared out by angle), then
        // the rest of the arc to the end point.
        let n = plane.axes()[2];
        let total =
            geom::sweep(su, eu, cuv, !cw) + 2.0 * std::f64::consts::PI * f64::from(turns - 1);
        let per_turn = (ep[n] - sp[n]) * 2.0 * std::f64::consts::PI / total;
        let mut at = sp;
        for _ in 1..turns {
            at[n] += per_turn;
            let m = st.to_machine(at);
            comp.arc(x, st.pos, m, centre, plane, !cw, feed, col)?;
            st.pos = m;
        }
    }
    comp.arc(x, st.pos, e, centre, plane, !cw, feed, col)?;
    st.pos = e;
    Ok(())
}

/// A length (mm) in the program's units (`k` mm each), with them named.
fn in_units(v: f64, k: f64) -> String {
    let unit = if k == 1.0 { "mm" } else { "in" };
    format!("{} {unit}", crate::input_text::fixed(v / k, 4))
}

fn fault(x: &Exec, f: ArcFault, col: u32, k: f64) -> TranslateError {
    let unit = if k == 1.0 { "mm" } else { "in" };
    let m = |v: f64| v / k;
    match f {
        ArcFault::RTooSmall { half, r } => x.err(
            col,
            format!("R{} is too small for the chord: the end point is {} {unit} from the start, more than 2·R", crate::input_text::fixed(m(r), 4), crate::input_text::fixed(m(2.0 * half), 4)),
        ),
        ArcFault::RFullCircle => x.err(col, "an R arc cannot be a full circle (the end is the start): use I J K"),
        ArcFault::NotOnCircle { r0, r1 } => x.err(
            col,
            format!(
                "the arc's end point is not on its circle: radius {:.4} {unit} at the start, {:.4} {unit} at the end (at most {:.3} mm apart)",
                m(r0),
                m(r1),
                geom::NOVANC_RADIUS_DIFF_MM
            ),
        ),
        ArcFault::ZeroRadius => x.err(col, "an arc of zero radius"),
    }
}

/// Where the machine stands in coordinate system `cs` (program mm, before G92 if `with_g92`
/// is false), the tool length not counted: LinuxCNC's `find_current_in_system`.
fn current_in_system(st: &InterpState, cs: usize) -> [f64; 3] {
    let b = system_base(cs);
    let q = [
        st.pos[0] - st.tlo[0] - st.params[b + 1],
        st.pos[1] - st.tlo[1] - st.params[b + 2],
        st.pos[2] - st.tlo[2] - st.params[b + 3],
    ];
    let r = rotate([q[0], q[1]], -st.params[b + 10]);
    let mut p = [r[0], r[1], q[2]];
    if st.params[5210] != 0.0 {
        for (a, v) in p.iter_mut().enumerate() {
            *v -= st.params[5211 + a];
        }
    }
    p
}

/// Where the rotary axes stand in coordinate system `cs`, degrees, the G92 offset applied if in
/// force (LinuxCNC's `find_current_in_system`).
fn current_abc_in_system(st: &InterpState, cs: usize) -> [f64; 3] {
    let b = system_base(cs);
    std::array::from_fn(|r| {
        let g92 = if st.params[5210] != 0.0 {
            st.params[5214 + r]
        } else {
            0.0
        };
        st.abc[r] - st.params[b + 4 + r] - g92
    })
}

/// Refuses the position `v` (at column `col`) that `code` gives rotary axis `r` when the axis
/// is wrapped and `v` is a turn or more (LinuxCNC's check for G92 and G10 L20).
fn wrapped_within_a_turn(
    st: &InterpState,
    x: &Exec,
    code: &str,
    r: usize,
    (v, col): (f64, u32),
) -> Result<(), TranslateError> {
    if st.rotaries[r] == Some(true) && v.abs() >= 360.0 {
        let l = super::exec::ROTARY_LETTERS[r];
        return Err(x.err(
            col,
            format!("{code} {l}{v}: a wrapped rotary axis takes a position within ±360"),
        ));
    }
    Ok(())
}

/// Refuses a rotary axis word where a code has no use for it (`what` says why).
fn no_rotary(x: &Exec, w: &Words, what: &str) -> Result<(), TranslateError> {
    match super::exec::ROTARY_LETTERS
        .into_iter()
        .find_map(|l| Some((l, w.col(l)?)))
    {
        Some((l, c)) => Err(x.err(c, format!("{what}: {l} is not one of its words"))),
        None => Ok(()),
    }
}

/// G10: L1/L10/L11 the tool table, L2/L20 a coordinate system (with R, its rotation).
pub fn g10(
    st: &mut InterpState,
    comp: &Comp,
    x: &mut Exec,
    w: &Words,
    col: u32,
) -> Result<(), TranslateError> {
    let l = int_word(x, w, 'L', 0.0, 20.0)?;
    if x.settings.dialect == crate::settings::Dialect::Fanuc {
        match l {
            Some(l @ 10..=13) => return fanuc_g10_offset(st, comp, x, w, l, col),
            // LinuxCNC's L20 (a system set from the current point) is another thing there.
            Some(20) => {
                return Err(x.err(
                    w.col('L').unwrap_or(col),
                    "G10 L20 sets Fanuc's additional work systems (G54.1 P1–P48): novanc has G54–G59.3, set with G10 L2 P1–P9",
                ))
            }
            _ => {}
        }
    }
    let l = match l {
        Some(l @ (1 | 2 | 10 | 11 | 20)) => l,
        Some(0) => {
            return Err(x.err(
                w.col('L').unwrap_or(col),
                "G10 L0 reloads LinuxCNC's tool table file: novanc's tool data is its own store (change it with G10 L1, L10, L11)",
            ))
        }
        Some(l) => {
            return Err(x.err(
                w.col('L').unwrap_or(col),
                format!(
                "G10 L{l}: novanc has L1, L10, L11 (tool table), L2 and L20 (coordinate systems)"
            ),
            ))
        }
        None => {
            return Err(x.err(
                col,
                "G10 needs L: L1, L10 or L11 (tool table), L2 or L20 (coordinate systems)",
            ))
        }
    };
    let pcol = w.col('P').unwrap_or(col);
    let p = w
        .get('P')
        .ok_or_else(|| x.err(col, format!("G10 L{l} needs P")))?;
    let pi = p.round();
    if (p - pi).abs() > 0.0002 {
        return Err(x.err(pcol, format!("G10 P{p} must be a whole number")));
    }
    if comp.active() {
        return Err(x.err(col, "G10 cannot be used with cutter radius compensation on"));
    }
    let k = st.factor();
    if matches!(l, 1 | 10 | 11) {
        return g10_tool(st, x, w, l, pi, col);
    }
    if l == 2 && pi == 0.0 && x.settings.dialect == crate::settings::Dialect::Fanuc {
        return Err(x.err(pcol, format!("G10 L2 P0: {}", super::sysvars::EXOFS)));
    }
    if !(0.0..=9.0).contains(&pi) {
        return Err(x.err(
            pcol,
            format!("G10 L{l} P{p}: P1 (G54) to P9 (G59.3), or P0 for the one in force"),
        ));
    }
    if w.get('I').is_some() || w.get('J').is_some() {
        return Err(x.err(
            w.col('I').or(w.col('J')).unwrap_or(col),
            "I and J are not allowed with G10 L2 or L20",
        ));
    }
    let cs = if pi == 0.0 {
        st.modal.cs
    } else {
        pi as usize - 1
    };
    let b = system_base(cs);
    let cur = current_in_system(st, cs);
    let r = match w.get('R') {
        Some(_) if l == 20 => {
            return Err(x.err(w.col('R').unwrap_or(col), "R is not allowed with G10 L20"))
        }
        Some(r) => r,
        None => st.params[b + 10],
    };
    let rotary = super::exec::rotary_given(st, x, w)?;
    let cur_abc = current_abc_in_system(st, cs);
    let mut o_abc: [f64; 3] = std::array::from_fn(|r| st.params[b + 4 + r]);
    for (r, given) in rotary.into_iter().enumerate() {
        let Some((v, vcol)) = given else {
            continue;
        };
        if l == 20 {
            wrapped_within_a_turn(st, x, "G10 L20", r, (v, vcol))?;
            o_abc[r] = cur_abc[r] + st.params[b + 4 + r] - v;
        } else {
            o_abc[r] = v;
        }
        if !o_abc[r].is_finite() || o_abc[r].abs() > 1e9 {
            return Err(x.err(
                vcol,
                "the rotary axis's work offset would be out of all range",
            ));
        }
    }
    let mut o = [st.params[b + 1], st.params[b + 2], st.params[b + 3]];
    if l == 2 {
        for (i, c) in ['X', 'Y', 'Z'].into_iter().enumerate() {
            if let Some(v) = w.get(c) {
                o[i] = v * k;
            }
        }
    } else {
        let want = [
            w.get('X').map_or(cur[0], |v| v * k),
            w.get('Y').map_or(cur[1], |v| v * k),
        ];
        let old = rotate([cur[0], cur[1]], r);
        let new = rotate(want, r);
        if w.get('X').is_some() || w.get('Y').is_some() {
            o[0] = old[0] + st.params[b + 1] - new[0];
            o[1] = old[1] + st.params[b + 2] - new[1];
        }
        if let Some(z) = w.get('Z') {
            o[2] = cur[2] + st.params[b + 3] - z * k;
        }
    }
    for (a, &v) in o.iter().enumerate() {
        if !v.is_finite() || v.abs() > 1e5 {
            return Err(x.err(
                col,
                format!(
                    "work offset {} of {} mm is not usable (at most 100,000 mm)",
                    ["X", "Y", "Z"][a],
                    crate::input_text::short_number(v)
                ),
            ));
        }
    }
    if !r.is_finite() || r.abs() > 1e6 {
        return Err(x.err(
            w.col('R').unwrap_or(col),
            format!(
                "rotation R{} is not usable",
                crate::input_text::short_number(r)
            ),
        ));
    }
    for (i, v) in o.iter().enumerate() {
        st.params[b + 1 + i] = *v;
        x.events.push(Event::Param(b + 1 + i, *v));
    }
    st.params[b + 10] = r;
    x.events.push(Event::Param(b + 10, r));
    for (r, v) in o_abc.into_iter().enumerate() {
        if rotary[r].is_some() {
            st.params[b + 4 + r] = v;
            x.events.push(Event::Param(b + 4 + r, v));
        }
    }
    if cs == st.modal.cs {
        st.select_system(cs);
    }
    Ok(())
}

/// Fanuc's G10 L10–L13 P R (the Fanuc dialect): a tool offset of memory C set to R, or R added
/// under G91 (`sysvars::g10_offset`). Before stop 48 the dialect read them as LinuxCNC's L10
/// and L11, whose R is the tool's radius: `G10 L10 P1 R100.` (H1 = 100 mm) made T1 200 mm
/// across.
fn fanuc_g10_offset(
    st: &InterpState,
    comp: &Comp,
    x: &mut Exec,
    w: &Words,
    l: u32,
    col: u32,
) -> Result<(), TranslateError> {
    if comp.active() {
        return Err(x.err(col, "G10 cannot be used with cutter radius compensation on"));
    }
    no_rotary(x, w, &format!("G10 L{l} sets a tool offset"))?;
    for c in ['X', 'Y', 'Z', 'I', 'J', 'K', 'Q'] {
        if let Some(cc) = w.col(c) {
            return Err(x.err(
                cc,
                format!("G10 L{l}: {c} is not a word of a Fanuc tool offset (P the offset, R its value)"),
            ));
        }
    }
    let pcol = w.col('P').unwrap_or(col);
    let p = match w.get('P') {
        Some(p) if p.fract() == 0.0 && (1.0..=999.0).contains(&p) => p as u32,
        Some(p) => {
            return Err(x.err(
                pcol,
                format!(
                    "G10 L{l} P{}: P is the offset number, 1 to 999",
                    crate::input_text::short_number(p)
                ),
            ))
        }
        None => return Err(x.err(col, format!("G10 L{l} needs P, the offset number"))),
    };
    let Some(r) = w.get('R') else {
        return Err(x.err(col, format!("G10 L{l} needs R, the offset's value")));
    };
    let r_mm = r * st.factor();
    super::sysvars::g10_offset(l, p, r_mm, st.modal.incremental, x.magazine, &mut x.events)
        .map_err(|e| x.err(w.col('R').unwrap_or(col), format!("G10 L{l} P{p}: {e}")))
}

/// G10 L1 (set a tool's data), L10 (so the current point reads X Y Z with that tool's
/// length), L11 (the same, as if G59.3 were in force).
fn g10_tool(
    st: &mut InterpState,
    x: &mut Exec,
    w: &Words,
    l: u32,
    p: f64,
    col: u32,
) -> Result<(), TranslateError> {
    let k = st.factor();
    let pcol = w.col('P').unwrap_or(col);
    if !(1.0..=999.0).contains(&p) {
        return Err(x.err(pcol, format!("G10 L{l} P{p}: P is the T code, 1 or more")));
    }
    let t = p as u32;
    no_rotary(x, w, &format!("G10 L{l} sets a tool's data"))?;
    for c in ['X', 'Y', 'I', 'J', 'Q'] {
        if let Some(cc) = w.col(c) {
            return Err(x.err(cc, format!("G10 L{l}: {c} is not kept in this machine's tool file (it has a length Z and a diameter R)")));
        }
    }
    let Some(rec) = x.magazine.tools.get(t).cloned() else {
        return Err(x.err(
            pcol,
            format!("G10 L{l} P{t}: T code {t} has no tool data in the tool file"),
        ));
    };
    let mut length = rec.length();
    let mut diameter = rec.cutting_diameter();
    if let Some(r) = w.get('R') {
        if r < 0.0 {
            return Err(x.err(w.col('R').unwrap_or(col), "G10: a negative tool radius R"));
        }
        diameter = 2.0 * r * k;
    }
    if let Some(z) = w.get('Z') {
        length = match l {
            1 => z * k,
            _ => {
                // The length that makes the current point read Z: in the system in force
                // (L10) or in G59.3 (L11), without G92 for L11.
                let cs = if l == 10 { st.modal.cs } else { 8 };
                let b = system_base(cs);
                let g92 = if l == 10 && st.params[5210] != 0.0 {
                    st.params[5213]
                } else {
                    0.0
                };
                st.pos[2] - st.params[b + 3] - g92 - z * k
            }
        };
    }
    if !length.is_finite() || length.abs() > 1e5 || !diameter.is_finite() || diameter > 1e5 {
        return Err(x.err(col, "G10: the tool length or diameter is out of range"));
    }
    let mut new = rec.clone();
    new.set_length = length - rec.wear_length;
    new.diameter = diameter - rec.wear_diameter;
    x.magazine.tools.set(t, Some(new));
    x.events.push(Event::Tool {
        t,
        length,
        diameter,
    });
    if st.tlo_tool == Some(t) {
        // LinuxCNC applies a changed length at the next G43; so does novanc.
    }
    Ok(())
}

/// G52 (the local offset X Y Z as given, kept in the G92 offset, as LinuxCNC keeps it), G92
/// (offsets so the current point reads the words), G92.1 (cancel and clear), G92.2 (cancel,
/// keep the parameters), G92.3 (apply the parameters again).
pub fn g92(
    st: &mut InterpState,
    comp: &Comp,
    x: &mut Exec,
    w: &Words,
    col: u32,
) -> Result<(), TranslateError> {
    if comp.active() {
        return Err(x.err(
            col,
            "G52 and G92 cannot be used with cutter radius compensation on",
        ));
    }
    let k = st.factor();
    let rotary = super::exec::rotary_given(st, x, w)?;
    let set = |st: &mut InterpState, x: &mut Exec, on: bool| {
        st.params[5210] = if on { 1.0 } else { 0.0 };
        x.events.push(Event::Param(5210, st.params[5210]));
        for a in 0..3 {
            st.params[5211 + a] = st.g92[a];
            x.events.push(Event::Param(5211 + a, st.g92[a]));
        }
        // The rotary axes the machine has (an A/B/C parameter of an axis it lacks stays).
        for r in (0..3).filter(|&r| st.rotaries[r].is_some()) {
            st.params[5214 + r] = st.g92_abc[r];
            x.events.push(Event::Param(5214 + r, st.g92_abc[r]));
        }
    };
    let in_range = |st: &InterpState| {
        st.g92.iter().all(|v| v.is_finite() && v.abs() <= 1e5)
            && st.g92_abc.iter().all(|v| v.is_finite() && v.abs() <= 1e9)
    };
    let was = (st.g92, st.g92_abc);
    if w.has_g(520).is_some() {
        // G52: the local offset, given as it is, in the G92 offset (LinuxCNC's).
        for (i, c) in ['X', 'Y', 'Z'].into_iter().enumerate() {
            if let Some(v) = w.get(c) {
                st.g92[i] = v * k;
            }
        }
        for (r, given) in rotary.into_iter().enumerate() {
            if let Some((v, _)) = given {
                st.g92_abc[r] = v;
            }
        }
        if !in_range(st) {
            (st.g92, st.g92_abc) = was;
            return Err(x.err(col, "G52: the offset would be out of range"));
        }
        set(st, x, true);
    } else if w.has_g(920).is_some() {
        if !w.has_axis() && rotary.iter().all(Option::is_none) {
            let names = match st.axes_named() {
                n if st.rotaries == [None; 3] => n.replace(", Z", " and Z"),
                n => n,
            };
            return Err(x.err(col, format!("G92 needs at least one of {names}")));
        }
        for (r, given) in rotary.into_iter().enumerate() {
            if let Some(word) = given {
                wrapped_within_a_turn(st, x, "G92", r, word)?;
            }
        }
        let p = st.prog();
        let pa = st.prog_abc();
        for (i, c) in ['X', 'Y', 'Z'].into_iter().enumerate() {
            if let Some(v) = w.get(c) {
                st.g92[i] = p[i] + st.g92[i] - v * k;
            }
        }
        for (r, given) in rotary.into_iter().enumerate() {
            if let Some((v, _)) = given {
                st.g92_abc[r] = pa[r] + st.g92_abc[r] - v;
            }
        }
        if !in_range(st) {
            (st.g92, st.g92_abc) = was;
            return Err(x.err(col, "G92: the offset would be out of range"));
        }
        set(st, x, true);
    } else if w.has_g(921).is_some() {
        st.g92 = [0.0; 3];
        st.g92_abc = [0.0; 3];
        set(st, x, false);
    } else if w.has_g(922).is_some() {
        st.g92 = [0.0; 3];
        st.g92_abc = [0.0; 3];
        st.params[5210] = 0.0;
        x.events.push(Event::Param(5210, 0.0));
    } else {
        st.g92 = [st.params[5211], st.params[5212], st.params[5213]];
        st.g92_abc = std::array::from_fn(|r| {
            if st.rotaries[r].is_some() {
                st.params[5214 + r]
            } else {
                0.0
            }
        });
        st.params[5210] = 1.0;
        x.events.push(Event::Param(5210, 1.0));
    }
    Ok(())
}

/// G28 and G30: through the intermediate point given by the axis words (program frame; the
/// rotary axes' `mid_abc`, those named in `named_abc`) to the home position (#5161–#5166 or
/// #5181–#5186, machine mm and degrees) of the named axes, or of every axis the machine has
/// when none is named (LinuxCNC's rule: a bare G28 brings A, B and C home too; before stop 53
/// novanc left them where they stood).
pub fn home(
    st: &mut InterpState,
    x: &mut Exec,
    w: &Words,
    g30: bool,
    col: u32,
    (mid_abc, named_abc): ([f64; 3], [bool; 3]),
) -> Result<(), TranslateError> {
    let base = if g30 { 5181 } else { 5161 };
    let home = [st.params[base], st.params[base + 1], st.params[base + 2]];
    let mid = target(st, x, w).unwrap_or(st.pos);
    rapid_to(st, x, mid, mid_abc, col)?;
    let (mut end, mut end_abc) = (mid, mid_abc);
    let any = w.has_axis() || named_abc.contains(&true);
    for (i, c) in ['X', 'Y', 'Z'].into_iter().enumerate() {
        if !any || w.get(c).is_some() {
            end[i] = home[i];
        }
    }
    for r in 0..3 {
        if st.rotaries[r].is_some() && (!any || named_abc[r]) {
            end_abc[r] = st.params[base + 3 + r];
        }
    }
    rapid_to(st, x, end, end_abc, col)
}

/// A rapid to `to` (machine mm) with the rotary axes to `abc` (a plain rapid when they stay).
/// Turning them is refused here on the error-proportional interpolator, whose registers are
/// X Y Z (a bare G28 brings them home unasked: the kernel would refuse the block after the
/// line had been read).
fn rapid_to(
    st: &mut InterpState,
    x: &mut Exec,
    to: [f64; 3],
    abc: [f64; 3],
    col: u32,
) -> Result<(), TranslateError> {
    if abc != st.abc && x.settings.interpolator != crate::settings::Interpolator::Dda {
        return Err(x.err(
            col,
            format!(
                "the rotary axes go home with G28 and G30 on the DDA interpolator only (this machine runs the {} one)",
                x.settings.interpolator.name()
            ),
        ));
    }
    if abc == st.abc {
        x.push(Canon::Rapid(to), col);
    } else {
        x.push(
            Canon::Turn {
                end: to,
                abc,
                feed: None,
            },
            col,
        );
        st.abc = abc;
    }
    st.pos = to;
    Ok(())
}
