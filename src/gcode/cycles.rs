//! Canned cycles G73, G74, G81–G86 and G89 in the three planes (docs/gcode.md "Canned
//! cycles"), expanded into moves as LinuxCNC 2.9 expands them.
//!
//! The cycles work in the plane's coordinates: `aa` and `bb` the plane's axes, `cc` the axis
//! along which the hole is drilled (Z in G17, Y in G18, X in G19). R, the bottom (the `cc`
//! word), P and Q are sticky while the same cycle goes on. The initial level is `cc` where the
//! series began; G98 retracts to it (or to R if that is higher), G99 to R. Under G91, R is
//! measured from the initial level, the bottom from R, and the plane's words step on from
//! the hole before at each L repeat.
//!
//! One departure from rs274 2.9, on purpose: a hole that starts below its clear level (after
//! G99 holes, a G98 one) first rises straight to the clear level, then crosses; rs274 rises
//! diagonally while crossing, which its own documentation does not describe
//! (docs/gcode.md "Canned cycles").

use super::canon::Canon;
use super::exec::{int_word, Exec};
use super::state::{FeedMode, InterpState};
use super::words::Words;
use crate::block::{Plane, Tap, TranslateError};

use crate::input_text::{fixed, short_number};
/// The most pecks one G73 or G83 hole may take (bounded work, docs/limits.md).
pub use crate::limits::MAX_PECKS;
use crate::limits::{MAX_BLOCKS, MAX_DWELL_S};

/// Why G84 is refused with the spindle stopped, on the mill and on the lathe (one tapping
/// rule for both machines).
pub const G84_STOPPED: &str = "G84 needs the spindle turning forward: give M03 first";

/// Why G84 is refused with the spindle turning backward (a right-hand tap), on both machines.
pub const G84_BACKWARD: &str =
    "G84 with the spindle turning backward (M04): right-hand tapping needs M03";

/// Why a G73/G83 hole cannot be pecked.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum PeckFault {
    /// More than [`MAX_PECKS`] pecks.
    TooMany,
    /// A peck of Q does not go deeper: Q is below the resolution of the numbers at that depth.
    NoDeeper,
}

/// The depths a G73/G83 hole pecks to from `r` down by `q` before its last feed to `bottom`,
/// as rs274 2.9 steps them (`r − q`, `r − 2q`, … while above the bottom); at most
/// [`MAX_PECKS`] of them, each deeper than the one before.
pub fn peck_depths(r: f64, bottom: f64, q: f64) -> Result<Vec<f64>, PeckFault> {
    let mut depths = Vec::new();
    let mut depth = r - q;
    let mut last = r;
    while depth > bottom {
        if depth >= last {
            return Err(PeckFault::NoDeeper);
        }
        if depths.len() + 1 >= MAX_PECKS as usize {
            return Err(PeckFault::TooMany);
        }
        depths.push(depth);
        last = depth;
        depth -= q;
    }
    Ok(depths)
}

/// G73 and G83 retract this far above the last depth before the next peck, inches (rs274
/// 2.9's clearance; the lathe's G83 backs off as far, docs/lathe-gcode.md "G83").
pub const PECK_CLEARANCE_INCH: f64 = 0.010;

/// The plane's axes as (aa, bb, cc) indices into X Y Z, and their letters.
fn axes(plane: Plane) -> ([usize; 3], [char; 3]) {
    match plane {
        Plane::XY => ([0, 1, 2], ['X', 'Y', 'Z']),
        Plane::XZ => ([2, 0, 1], ['Z', 'X', 'Y']),
        Plane::YZ => ([1, 2, 0], ['Y', 'Z', 'X']),
    }
}

/// A cycle's name, `G81`.
#[derive(Clone, Copy)]
struct CycleName(u16);

impl std::fmt::Display for CycleName {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "G{}", self.0)
    }
}

/// One canned-cycle line: motion `g` (×10).
pub fn cycle(
    st: &mut InterpState,
    x: &mut Exec,
    w: &Words,
    g: u16,
    col: u32,
) -> Result<(), TranslateError> {
    let kind = g / 10;
    // Written out only in a message (a string made for every cycle line was 3 % of a
    // program of hole rows).
    let name = CycleName(kind);
    if matches!(kind, 87 | 88) {
        return Err(x.err(col, format!("{name} (back boring, manual retract) is not supported: it needs an operator at the spindle; use G86 or G89")));
    }
    let k = st.factor();
    let plane = st.modal.plane;
    let ([ia, ib, ic], [la, lb, lc]) = axes(plane);
    if kind == 76 && plane != Plane::XY {
        return Err(x.err(
            col,
            "G76 shifts the tool along X off the bore's wall: G17 only",
        ));
    }
    if kind == 76 && (st.rotation != 0.0 || st.g68.is_some()) {
        // The oriented tool's edge points along the machine's X; a turned program's +X is
        // not that way, and the shift could push the tool into the wall.
        return Err(x.err(
            col,
            "G76 in a rotated coordinate system (G68 or G10 L2 R): the shift would not follow the oriented tool; cancel the rotation first",
        ));
    }
    let same = st.modal.motion == super::state::Motion::Cycle(g);
    if st.modal.feed_mode == FeedMode::PerMinute && st.modal.feed <= 0.0 {
        return Err(x.err(col, "a feed move without F: canned cycles feed, give F"));
    }
    // R, the bottom, P and Q: given, or kept from the same cycle.
    let r_in = match w.get('R') {
        Some(r) => r * k,
        None if same => st.cycle.r.ok_or_else(|| x.err(col, format!("{name} needs R")))?,
        None => {
            return Err(x.err(col, format!("{name} needs R, the level where the feed starts (R is kept only while the same cycle repeats)")))
        }
    };
    let cc_in = match w.get(lc) {
        Some(v) => v * k,
        None if same => st.cycle.z.ok_or_else(|| x.err(col, format!("{name} needs {lc}, the bottom of the hole")))?,
        None => {
            return Err(x.err(col, format!("{name} needs {lc}, the bottom of the hole ({lc} is kept only while the same cycle repeats)")))
        }
    };
    // Fanuc's P is in milliseconds, a whole number (P1000 is 1 s); LinuxCNC's in seconds.
    let fanuc = x.settings.dialect == crate::settings::Dialect::Fanuc;
    let unit = if fanuc { "milliseconds" } else { "seconds" };
    let p = match w.get('P') {
        Some(p) if fanuc && p.fract() != 0.0 => {
            return Err(x.err(
                w.col('P').unwrap_or(col),
                format!(
                    "{name} P{}: P is a whole number of milliseconds in the Fanuc dialect (P1500 is 1.5 s)",
                    short_number(p)
                ),
            ))
        }
        Some(p) if fanuc => Some(p / 1000.0),
        other => other,
    };
    let p = match p {
        Some(p) if p < 0.0 => return Err(x.err(w.col('P').unwrap_or(col), "a negative dwell P")),
        Some(p) if p > MAX_DWELL_S => {
            let written = if fanuc { p * 1000.0 } else { p };
            return Err(x.err(
                w.col('P').unwrap_or(col),
                crate::limits::dwell_too_long(&format!("P{}", short_number(written))),
            ));
        }
        Some(p) => p,
        None if matches!(kind, 82 | 86 | 89) && !same => {
            return Err(x.err(
                col,
                format!("{name} needs P, the dwell at the bottom in {unit}"),
            ))
        }
        None => st.cycle.p,
    };
    // Q: the peck of G73 and G83, the shift off the wall of Fanuc's G76.
    let what = if kind == 76 { "shift" } else { "peck" };
    let q = match kind {
        73 | 76 | 83 => Some(match w.get('Q') {
            Some(q) if q <= 0.0 => {
                return Err(x.err(
                    w.col('Q').unwrap_or(col),
                    format!("the {what} Q must be greater than 0, not {q}"),
                ))
            }
            Some(q) => q * k,
            None if same => st
                .cycle
                .q
                .ok_or_else(|| x.err(col, format!("{name} needs Q, the {what}")))?,
            None => return Err(x.err(col, format!("{name} needs Q, the {what} (greater than 0)"))),
        }),
        _ => None,
    };
    // Fanuc 0i's K is the number of repeats (its L on older controls, and LinuxCNC's).
    let rep = match (fanuc, w.col('K'), w.col('L')) {
        (true, Some(_), Some(c)) => {
            return Err(x.err(
                c,
                format!("{name}: K and L both give the number of repeats: give one"),
            ))
        }
        (true, Some(_), None) => 'K',
        _ => 'L',
    };
    let l = match w.get(rep) {
        Some(_) => int_word(x, w, rep, 1.0, super::MAX_REPEATS as f64)
            .map_err(|e| {
                x.err(
                    e.col,
                    format!(
                        "{} ({rep}0 makes no hole; the most is {})",
                        e.message,
                        super::MAX_REPEATS
                    ),
                )
            })?
            .unwrap_or(1),
        None => 1,
    };
    let spindle = st.modal.spindle;
    // Fanuc's rigid tapping (M29 S before the cycle): the cycle turns the spindle itself.
    let rigid = st.cycle.rigid && matches!(kind, 74 | 84);
    match kind {
        _ if rigid => {}
        84 if spindle != 1 => {
            return Err(x.err(
                col,
                if spindle == 0 {
                    G84_STOPPED
                } else {
                    G84_BACKWARD
                },
            ))
        }
        74 if spindle != -1 => {
            return Err(x.err(
                col,
                if spindle == 0 {
                    "G74 needs the spindle turning backward: give M04 first"
                } else {
                    "G74 with the spindle turning forward (M03): left-hand tapping needs M04"
                },
            ))
        }
        86 | 76 if spindle == 0 => {
            return Err(x.err(
                col,
                format!("{name} needs the spindle turning: give M03 (or M04) first"),
            ))
        }
        _ => {}
    }
    let feed = match st.modal.feed_mode {
        FeedMode::PerRevolution => {
            if st.modal.speed <= 0.0 {
                return Err(x.err(col, "feed per revolution (G95) needs S"));
            }
            st.modal.feed * st.modal.speed
        }
        _ => st.modal.feed,
    };
    // In the program frame.
    let prog = st.prog();
    let il = *st.cycle.il.get_or_insert(prog[ic]);
    let mut old = il;
    let (r, bottom) = if st.modal.incremental {
        (il + r_in, il + r_in + cc_in)
    } else {
        (r_in, cc_in)
    };
    if bottom > r {
        return Err(x.err(
            col,
            format!(
                "{name}: the bottom {lc}{} is above R{}",
                fixed(bottom / k, 4),
                fixed(r / k, 4)
            ),
        ));
    }
    // The pecks of a hole, the same for every hole of the line.
    let pecks = match q.filter(|_| kind != 76).map(|q| peck_depths(r, bottom, q)) {
        None => Vec::new(),
        Some(Ok(d)) => d,
        Some(Err(fault)) => {
            let qs = short_number(q.unwrap_or(1.0) / k);
            return Err(x.err(
                w.col('Q').unwrap_or(col),
                match fault {
                    PeckFault::TooMany => format!("{name}: Q{qs} would make more than {MAX_PECKS} pecks"),
                    PeckFault::NoDeeper => format!(
                        "{name}: Q{qs} is below the resolution of the numbers near R{}: a peck would not go deeper",
                        fixed(r / k, 3)
                    ),
                },
            ));
        }
    };
    // What the line makes, counted from its words before anything is made (docs/limits.md):
    // a rise to R first for a series below it, then per hole the approach (a rise to the
    // clear level, the crossing, the descent to R) and the cycle's own moves.
    let n = pecks.len() as u64;
    let below = il < r;
    let (old_est, cur_est) = if below { (r, r) } else { (il, prog[ic]) };
    let clear_est = if st.modal.retract_r { r } else { old_est };
    // A Fanuc's tap feeds out to R only, then rapids to the initial level (G98).
    let tap_rapid = fanuc && clear_est > r;
    let own: u64 = match kind {
        81 => 2,
        82 | 85 | 89 => 3,
        73 => 2 * n + 2,
        83 => 3 * n + 2,
        74 | 84 => 6 + u64::from(p > 0.0) + u64::from(tap_rapid),
        76 => 6 + u64::from(p > 0.0),
        _ => 5,
    };
    let down = u64::from(clear_est > r);
    let first = if cur_est > r {
        2
    } else {
        u64::from(cur_est < clear_est) + 1 + down
    };
    let per_hole = own + 1 + down;
    let total = u64::from(below) + first + own + u64::from(l - 1) * per_hole;
    if total > MAX_BLOCKS as u64 {
        return Err(x.err(
            w.col('L').unwrap_or(col),
            format!(
                "{name} L{l} makes {total} blocks ({l} holes of {per_hole}), more than the {MAX_BLOCKS} one line may make: split the holes over several lines"
            ),
        ));
    }
    let holes_mm = [prog[ia], prog[ib]];
    // Polar words (G17 only): about the program zero; under G91 each repeat turns the hole
    // by ^ and moves it out by @ (LinuxCNC's bolt circle: `G91 G81 ... ^60 L6`).
    let polar = w.get('@').is_some() || w.get('^').is_some();
    if polar && plane != Plane::XY {
        return Err(x.err(
            col,
            "polar coordinates (@ ^) work in the XY plane (G17) only",
        ));
    }
    let (mut aa, mut bb, da, db) = if st.modal.incremental {
        (
            holes_mm[0],
            holes_mm[1],
            w.get(la).map_or(0.0, |v| v * k),
            w.get(lb).map_or(0.0, |v| v * k),
        )
    } else if polar {
        let r = w.get('@').map_or(holes_mm[0].hypot(holes_mm[1]), |v| v * k);
        let a = w
            .get('^')
            .map_or(holes_mm[1].atan2(holes_mm[0]), f64::to_radians);
        (r * a.cos(), r * a.sin(), 0.0, 0.0)
    } else {
        (
            w.get(la).map_or(holes_mm[0], |v| v * k),
            w.get(lb).map_or(holes_mm[1], |v| v * k),
            0.0,
            0.0,
        )
    };
    let (dr, dt) = if st.modal.incremental {
        (
            w.get('@').map_or(0.0, |v| v * k),
            w.get('^').map_or(0.0, f64::to_radians),
        )
    } else {
        (0.0, 0.0)
    };
    let mut pos = prog;
    let mk = |a: f64, b: f64, c: f64| {
        let mut p = [0.0; 3];
        p[ia] = a;
        p[ib] = b;
        p[ic] = c;
        p
    };
    let to_m = |p: [f64; 3]| st.to_machine(p);
    let mut out: Vec<Canon> = Vec::with_capacity(total as usize);
    let rapid = |out: &mut Vec<Canon>, pos: &mut [f64; 3], p: [f64; 3]| {
        out.push(Canon::Rapid(to_m(p)));
        *pos = p;
    };
    let feed_to = |out: &mut Vec<Canon>, pos: &mut [f64; 3], p: [f64; 3]| {
        out.push(Canon::Feed(to_m(p), feed));
        *pos = p;
    };
    // Below R: rise straight to R first (once).
    let mut current_cc = prog[ic];
    if old < r {
        let up = mk(pos[ia], pos[ib], r);
        rapid(&mut out, &mut pos, up);
        old = r;
        current_cc = r;
    }
    let clear = if st.modal.retract_r { r } else { old };
    let clearance = PECK_CLEARANCE_INCH * 25.4;
    let aux = |m: u8| Canon::Aux {
        s: None,
        t: None,
        m: Some(m),
    };
    for rep in 0..l {
        aa += da;
        bb += db;
        if dr != 0.0 || dt != 0.0 {
            if aa == 0.0 && bb == 0.0 {
                return Err(x.err(
                    col,
                    "incremental polar words (@ ^) at the program zero have no direction",
                ));
            }
            let (r, t) = (aa.hypot(bb) + dr, bb.atan2(aa) + dt);
            aa = r * t.cos();
            bb = r * t.sin();
        }
        if rep == 0 && current_cc > r {
            rapid(&mut out, &mut pos, mk(aa, bb, current_cc));
            rapid(&mut out, &mut pos, mk(aa, bb, r));
        } else {
            if pos[ic] < clear {
                // novanc: rise straight to the clear level before crossing.
                let up = mk(pos[ia], pos[ib], clear);
                rapid(&mut out, &mut pos, up);
            }
            rapid(&mut out, &mut pos, mk(aa, bb, clear));
            if clear > r {
                rapid(&mut out, &mut pos, mk(aa, bb, r));
            }
        }
        let at = |c: f64| mk(aa, bb, c);
        match kind {
            81 => {
                feed_to(&mut out, &mut pos, at(bottom));
                rapid(&mut out, &mut pos, at(clear));
            }
            82 => {
                feed_to(&mut out, &mut pos, at(bottom));
                out.push(Canon::Dwell(p));
                rapid(&mut out, &mut pos, at(clear));
            }
            73 | 83 => {
                for &depth in &pecks {
                    feed_to(&mut out, &mut pos, at(depth));
                    if kind == 83 {
                        rapid(&mut out, &mut pos, at(r));
                    }
                    rapid(&mut out, &mut pos, at(depth + clearance));
                }
                feed_to(&mut out, &mut pos, at(bottom));
                rapid(&mut out, &mut pos, at(clear));
            }
            74 | 84 => {
                let (back, fwd) = if kind == 84 { (4, 3) } else { (3, 4) };
                let turning = spindle == if kind == 84 { 1 } else { -1 };
                // The tap's blocks, up to the spindle forward again out of the hole: the
                // overrides held, a feed hold kept for the end (docs/pulse-core.md "Tapping").
                out.push(Canon::Tap(Tap::Part));
                if !turning {
                    // Rigid tapping from a spindle stopped (or turning the other way): the
                    // cycle starts it in its direction at the tap's S.
                    out.push(Canon::Aux {
                        s: Some(st.modal.speed.round() as u32),
                        t: None,
                        m: Some(fwd),
                    });
                }
                feed_to(&mut out, &mut pos, at(bottom));
                out.push(aux(5));
                out.push(aux(back));
                if p > 0.0 {
                    out.push(Canon::Dwell(p));
                }
                // Out at the tap's feed to the clear level (LinuxCNC's G84), or to R in the
                // Fanuc dialect, whose G98 then rapids up to the initial level.
                feed_to(&mut out, &mut pos, at(if tap_rapid { r } else { clear }));
                if turning {
                    out.push(aux(5));
                    out.push(Canon::Tap(Tap::End));
                    out.push(aux(fwd));
                } else {
                    // And leaves it stopped, as a Fanuc's rigid tap does.
                    out.push(Canon::Tap(Tap::End));
                    out.push(aux(5));
                }
                if tap_rapid {
                    rapid(&mut out, &mut pos, at(clear));
                }
            }
            85 => {
                feed_to(&mut out, &mut pos, at(bottom));
                feed_to(&mut out, &mut pos, at(r));
                rapid(&mut out, &mut pos, at(clear));
            }
            86 => {
                feed_to(&mut out, &mut pos, at(bottom));
                out.push(Canon::Dwell(p));
                out.push(aux(5));
                rapid(&mut out, &mut pos, at(clear));
                out.push(aux(if spindle == 1 { 3 } else { 4 }));
            }
            76 => {
                // Fanuc's fine boring: bore, dwell, orient the spindle (M19, the tool's
                // edge to a known angle), shift the tool off the wall by Q along +X (the
                // direction of parameters RD1 = RD2 = 0), rapid out, shift back, restart.
                let shift = q.unwrap_or(0.0);
                feed_to(&mut out, &mut pos, at(bottom));
                if p > 0.0 {
                    out.push(Canon::Dwell(p));
                }
                out.push(Canon::Io(crate::block::Io::Orient { angle: 0.0, dir: 0 }));
                let off = |c: f64| mk(aa + shift, bb, c);
                rapid(&mut out, &mut pos, off(bottom));
                rapid(&mut out, &mut pos, off(clear));
                rapid(&mut out, &mut pos, at(clear));
                out.push(aux(if spindle == 1 { 3 } else { 4 }));
            }
            _ => {
                // G89: bore, dwell, feed out to the clear level.
                feed_to(&mut out, &mut pos, at(bottom));
                out.push(Canon::Dwell(p));
                feed_to(&mut out, &mut pos, at(clear));
            }
        }
    }
    debug_assert_eq!(
        out.iter().filter(|c| !matches!(c, Canon::Tap(_))).count() as u64,
        total,
        "the count of {name}"
    );
    x.push_all(out, col);
    st.pos = st.to_machine(pos);
    st.cycle.r = Some(r_in);
    st.cycle.z = Some(cc_in);
    st.cycle.p = p;
    if rigid && spindle != if kind == 84 { 1 } else { -1 } {
        // A rigid tap started the spindle and stopped it again.
        st.modal.spindle = 0;
    }
    if let Some(q) = q {
        st.cycle.q = Some(q);
    }
    Ok(())
}

/// What G33 and G33.1 (`name`) share: refused under cutter compensation, in inverse time,
/// with an A word, the spindle stopped or without S, and K not above 0. Returns the pitch (mm
/// per revolution), the spindle's M code (3 or 4) and S.
fn geared(
    st: &InterpState,
    comp_on: bool,
    x: &Exec,
    w: &Words,
    col: u32,
    name: &str,
) -> Result<(f64, u8, f64), TranslateError> {
    if comp_on {
        return Err(x.err(
            col,
            format!("{name} cannot be used with cutter radius compensation on: G40 first"),
        ));
    }
    if st.modal.feed_mode == FeedMode::InverseTime {
        return Err(x.err(
            col,
            format!(
                "{name} cannot be used in inverse time feed (G93): the feed follows the spindle"
            ),
        ));
    }
    if let Some(c) = w.col('A') {
        return Err(x.err(
            c,
            format!("{name} moves along X, Y and Z: an A word cannot follow the spindle"),
        ));
    }
    let pitch = match w.get('K') {
        Some(v) if v > 0.0 && v.is_finite() => v * st.factor(),
        Some(v) => {
            return Err(x.err(
                w.col('K').unwrap_or(col),
                format!("{name} K{}: the pitch must be above 0", short_number(v)),
            ))
        }
        None => return Err(x.err(col, format!("{name} needs K, the pitch"))),
    };
    let m = match st.modal.spindle {
        1 => 3,
        -1 => 4,
        _ => {
            return Err(x.err(
                col,
                format!(
                    "{name} needs the spindle turning: M03 (right-hand) or M04 (left-hand) first"
                ),
            ))
        }
    };
    let s = st.modal.speed;
    if s.is_nan() || s < 1.0 {
        return Err(x.err(col, format!("{name} needs the spindle speed: give S")));
    }
    Ok((pitch, m, s))
}

/// `G33 X Y Z K`, LinuxCNC's spindle-synchronised motion: one straight thread pass from where
/// the tool stands to the end point, geared to the spindle at K per revolution: the pass waits
/// for the encoder's index, then follows the spindle's position (docs/pulse-core.md "Thread
/// passes (G33)"), the overrides held at 100 %. A taper (X or Y moving too) keeps its lead as
/// the dialect measures it: along the path (LinuxCNC), along the longest axis (Fanuc). Refused
/// as [`geared`] says, and with the end point where the tool stands.
pub fn thread(
    st: &mut InterpState,
    comp_on: bool,
    x: &mut Exec,
    w: &Words,
    col: u32,
) -> Result<(), TranslateError> {
    let (pitch, _, _) = geared(st, comp_on, x, w, col, "G33")?;
    let end = super::moves::target(st, x, w)?;
    if end == st.pos {
        return Err(x.err(col, "G33: the end of the pass is where the tool stands"));
    }
    // A taper (X or Y moving too): the kernel gears its longest axis to the spindle at the
    // lead it is given, as a Fanuc measures G32's F. LinuxCNC measures K along the path
    // (its nc_files/threading.ngc leaves a thread at 45° with K √2 × the pitch, so that Z
    // keeps the pitch), so its K is given to the kernel as the longest axis's share of it.
    let d: [f64; 3] = std::array::from_fn(|i| end[i] - st.pos[i]);
    let lead = if x.settings.dialect == crate::settings::Dialect::Fanuc {
        pitch
    } else {
        super::geom::lead_on_longest(pitch, &d)
    };
    x.push_all(vec![Canon::Thread(end, lead)], col);
    st.pos = end;
    Ok(())
}

/// `G33.1 X Y Z K I`, LinuxCNC's rigid tapping: from where the tool stands, straight to the end
/// point geared to the spindle at K per revolution (K × S per minute), the spindle reversed,
/// straight back to the start geared the same (at I × S if I is given, LinuxCNC's faster
/// return), and the spindle forward again at S. The blocks carry the tap's marks, as G84's do
/// (docs/pulse-core.md "Tapping": the overrides held at 100 %, a feed hold kept until the tap
/// is out, the feed geared to the encoder on a spindle that ramps). The tool ends where it
/// started. A left-hand tap turns M04 in and M03 out. Refused as [`geared`] says, and with I
/// below 1 or the end point where the tool stands (a line without X, Y or Z is refused before,
/// as every motion's is).
pub fn rigid_tap(
    st: &mut InterpState,
    comp_on: bool,
    x: &mut Exec,
    w: &Words,
    col: u32,
) -> Result<(), TranslateError> {
    let (pitch, fwd, s) = geared(st, comp_on, x, w, col, "G33.1")?;
    let back = if fwd == 3 { 4 } else { 3 };
    let faster = match w.get('I') {
        Some(v) if v >= 1.0 && v.is_finite() => v,
        Some(v) => {
            return Err(x.err(
                w.col('I').unwrap_or(col),
                format!(
                    "G33.1 I{}: the return's speed multiplier is 1 or more (LinuxCNC takes a smaller one as 1)",
                    short_number(v)
                ),
            ))
        }
        None => 1.0,
    };
    let start = st.pos;
    let end = super::moves::target(st, x, w)?;
    if end == start {
        return Err(x.err(col, "G33.1: the end of the tap is where the tool stands"));
    }
    let out_s = (s * faster).round();
    if out_s > u32::MAX as f64 {
        return Err(x.err(
            w.col('I').unwrap_or(col),
            "G33.1: I × S is beyond any spindle",
        ));
    }
    let aux = |s: Option<u32>, m: u8| Canon::Aux {
        s,
        t: None,
        m: Some(m),
    };
    let speed_out = (faster != 1.0).then_some(out_s as u32);
    let out = vec![
        Canon::Tap(Tap::Part),
        Canon::Feed(end, pitch * s),
        aux(None, 5),
        aux(speed_out, back),
        Canon::Feed(start, pitch * out_s),
        aux(None, 5),
        Canon::Tap(Tap::End),
        aux(speed_out.map(|_| s.round() as u32), fwd),
    ];
    x.push_all(out, col);
    Ok(())
}
