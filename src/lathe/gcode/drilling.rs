//! Fanuc 0i-T's face drilling cycle G83 and face tapping cycle G84 on the spindle centre line
//! (docs/lathe-gcode.md "G83 face drilling", "G84 face tapping"): the drill or tap stands
//! still on X0, the work turns. Fanuc's dialect only: LinuxCNC has no drilling cycle on a
//! lathe. Both cycles read their common words (R, P, X, Z/W, the initial level, the return
//! level) with one reader, [`hole`]. The pecking depths are the mill's
//! (`crate::gcode::cycles::peck_depths`), and G84's blocks are marked as the mill's G84 marks
//! its (`Block::tap`, docs/pulse-core.md "Tapping"): one rule for both machines.

use super::cycles::mv;
use super::exec::{err, Flow, Reader};
use super::out::{self, Kind};
use crate::block::{FeedMode, Tap, TranslateError};
use crate::gcode::cycles::{
    peck_depths, PeckFault, G84_BACKWARD, G84_STOPPED, MAX_PECKS, PECK_CLEARANCE_INCH,
};
use crate::gcode::words::Words;
use crate::input_text::{fixed, short_number};

/// What a G83 or G84 series keeps from one block to the next (Fanuc: the drilling data are
/// modal until G80 or a group 01 code).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Drill {
    /// The cycle in force: 83 (face drilling) or 84 (face tapping).
    pub code: u32,
    /// The initial level: Z (mm) where the tool stood at the series' first block.
    pub initial: f64,
    /// R: the R level's distance from the initial level, mm, its sign included.
    pub r: f64,
    /// Q: the depth of each peck, mm (0: one feed to the bottom). G83's only.
    pub q: f64,
    /// P: the dwell at the bottom, seconds.
    pub p: f64,
}

/// The centre line: an X (radius, mm) this close to 0 is on it.
const ON_CENTRE: f64 = 1e-6;

/// One hole of a G83 or G84 series as the common words give it, mm.
struct Hole {
    /// The initial level.
    initial: f64,
    /// R, from the initial level.
    rel: f64,
    /// The R level.
    level: f64,
    /// The bottom.
    bottom: f64,
    /// The dwell at the bottom, seconds.
    p: f64,
    /// Where the cycle returns to at its end: the initial level (G98) or the R level (G99).
    clear: f64,
}

/// The words G83 and G84 share (`code` 83 or 84, `c` the column of the code, or of the first
/// axis word on a block that repeats the cycle under its mode): the dialect, the state the
/// cycle needs (no profile, no compensation, the spindle turning), the words neither takes,
/// P in milliseconds, R from the initial level, X on the centre line only, the bottom Z (W:
/// from the R level) below R, and the return level. R and P and the initial level are the
/// series' when not given (a first block: R 0, no dwell, the level the tool stands at).
fn hole(r: &Reader, w: &Words, n: u32, c: u32, code: u32) -> Result<Hole, TranslateError> {
    let name = format!("G{code}");
    let (cycle, tool, verb) = if code == 84 {
        ("face tapping", "tap", "taps")
    } else {
        ("face drilling", "drill", "drills")
    };
    if !r.fanuc {
        return Err(err(
            n,
            c,
            format!("{name} is Fanuc's {cycle} cycle; LinuxCNC has no drilling cycle on a lathe: read the program in the Fanuc dialect (`dialect fanuc`)"),
        ));
    }
    if r.in_cycle {
        return Err(err(n, c, format!("{name} inside a G70/G71 profile")));
    }
    if r.out.comp_on() {
        return Err(err(
            n,
            c,
            format!("{name} with nose-radius compensation in force: give G40 first"),
        ));
    }
    if let Some(col) = w.col('K') {
        return Err(err(
            n,
            col,
            format!("{name} K, the repeats, is not supported: the {tool} stands on the centre line, a repeat would {} the same hole", if code == 84 { "tap" } else { "drill" }),
        ));
    }
    if code == 84 {
        if let Some(col) = w.col('Q') {
            return Err(err(
                n,
                col,
                "G84 Q, peck tapping, is not supported: the tap feeds to the bottom in one move",
            ));
        }
    }
    for l in ['I', 'J', 'H', 'E', 'L', 'D'] {
        if let Some(col) = w.col(l) {
            return Err(err(n, col, format!("{name} takes no {l} word")));
        }
    }
    for l in ['P', 'Q'] {
        if r.written_with_point(l) {
            let what = match (l, r.st.inch) {
                ('P', _) => format!("{name} P, the dwell, is in milliseconds, without a decimal point (P500 is 0.5 s)"),
                (_, false) => "G83 Q, the depth of each peck, is in least increments, without a decimal point (Q5000 is 5.000 mm)".to_string(),
                (_, true) => "G83 Q, the depth of each peck, is in least increments, without a decimal point (Q1000 is 0.1000 inch under G20)".to_string(),
            };
            return Err(err(n, w.col(l).unwrap_or(c), what));
        }
    }
    match (code, r.st.dir) {
        (84, 5) => return Err(err(n, c, G84_STOPPED)),
        (84, 4) => return Err(err(n, c, G84_BACKWARD)),
        (_, 5) => {
            return Err(err(
                n,
                c,
                "G83 with the spindle stopped: the work turns and the drill stands still, give M03 or M04",
            ))
        }
        _ => {}
    }
    let f = r.st.factor();
    let start = r.out.pos;
    let kept = r.st.drill;
    let initial = kept.map_or(start[0], |d| d.initial);
    // R and P: given, else the series' (a first block: R 0, no dwell).
    let rel = match w.get('R') {
        Some(v) => v * f,
        None => kept.map_or(0.0, |d| d.r),
    };
    if !(rel.is_finite() && rel.abs() <= 1000.0) {
        return Err(err(
            n,
            w.col('R').unwrap_or(c),
            format!("{name} R, the R level's distance from the initial level, is at most 1000 mm"),
        ));
    }
    let p = match w.get('P') {
        Some(v) if v.fract() == 0.0 && v >= 0.0 && v / 1000.0 <= crate::limits::MAX_DWELL_S => {
            v / 1000.0
        }
        Some(v) if v.fract() == 0.0 && v > 0.0 => {
            return Err(err(
                n,
                w.col('P').unwrap_or(c),
                crate::limits::dwell_too_long(&format!("P{}", short_number(v))),
            ))
        }
        Some(v) => {
            return Err(err(
                n,
                w.col('P').unwrap_or(c),
                format!(
                    "{name} P{}: the dwell is a whole number of milliseconds, not negative",
                    short_number(v)
                ),
            ))
        }
        None => kept.map_or(0.0, |d| d.p),
    };
    // X: the centre line only (X0, U to it, or no X with the tool on it).
    let x_col = w.col('X').or(w.col('U'));
    let end = r.target(w, n)?;
    if end[1].abs() > ON_CENTRE {
        // X as programmed, and where that is from the spindle's centre line when a work offset
        // (or a shift) moves X0 off it.
        let at = fixed((end[1] - r.zero()[1]) * 2.0 / f, 3);
        let off = if r.zero()[1].abs() > ON_CENTRE {
            format!(
                ", X{} from the spindle's centre line",
                fixed(end[1] * 2.0 / f, 3)
            )
        } else {
            String::new()
        };
        let (col, why) = match x_col {
            Some(col) => (col, format!("{name} at X{at}{off}")),
            None => (c, format!("{name} with the tool at X{at}{off}")),
        };
        return Err(err(
            n,
            col,
            format!("{why}: the lathe {verb} on the centre line only (X0), it has no live tooling to {tool} off the centre"),
        ));
    }
    let level = initial + rel;
    let bottom = if let Some(v) = w.get('W') {
        level + v * f
    } else if let Some(v) = w.get('Z') {
        if r.st.absolute {
            r.zero()[0] + v * f
        } else {
            level + v * f
        }
    } else {
        return Err(err(
            n,
            x_col.unwrap_or(c),
            format!("{name} needs Z (or W, from the R level), the bottom of the hole"),
        ));
    };
    let z_col = w.col('Z').or(w.col('W')).unwrap_or(c);
    if !(bottom.is_finite() && bottom.abs() < 1e6) {
        return Err(err(
            n,
            z_col,
            "the bottom of the hole is not a reasonable number",
        ));
    }
    if bottom >= level {
        return Err(err(
            n,
            z_col,
            format!(
                "{name}: the bottom Z{} is not below the R level Z{} (the initial level Z{} and R{}): the {tool} feeds towards -Z",
                fixed((bottom - r.zero()[0]) / f, 3),
                fixed((level - r.zero()[0]) / f, 3),
                fixed((initial - r.zero()[0]) / f, 3),
                fixed(rel / f, 3)
            ),
        ));
    }
    let clear = if r.st.drill_to_r && !r.system_a {
        level
    } else {
        initial
    };
    Ok(Hole {
        initial,
        rel,
        level,
        bottom,
        p,
        clear,
    })
}

/// The cycle of `code` (83 or 84) on this line: [`g83`] or [`g84`].
pub fn cycle(r: &mut Reader, w: &Words, n: u32, c: u32, code: u32) -> Result<Flow, TranslateError> {
    if code == 84 {
        g84(r, w, n, c)
    } else {
        g83(r, w, n, c)
    }
}

/// Emits one move of a cycle on the centre line to `to` (`[Z, X]` mm) from `at`, none if the
/// tool is there already.
fn go(
    r: &mut Reader,
    at: &mut [f64; 2],
    kind: Kind,
    to: [f64; 2],
    n: u32,
    c: u32,
) -> Result<(), TranslateError> {
    if to != *at {
        r.out.motion(mv(kind, to, n, c))?;
        *at = to;
    }
    Ok(())
}

/// The dwell of P seconds at the bottom, if any.
fn dwell(r: &mut Reader, p: f64, n: u32, c: u32) -> Result<(), TranslateError> {
    if p > 0.0 {
        let dwell = crate::block::Block {
            motion: crate::block::Motion::Dwell,
            dwell_ns: (p * 1e9).round() as u64,
            ..out::aux()
        };
        r.out.op(n, c, dwell)?;
    }
    Ok(())
}

/// `G83 X(U) Z(W) R Q P F` (the common words as [`hole`] reads them; Q kept for the series
/// too). From where the tool stands: a rapid to X0 if X is given and the tool is not on it,
/// a rapid to the R level, the feed to the bottom in pecks of Q (Fanuc's high-speed peck
/// drilling, parameter 5101#2 RTR = 0: after each peck the drill rapids back d = 0.254 mm,
/// the mill's clearance), the dwell P (milliseconds) at the bottom, and a rapid back to the
/// initial level (G98) or to the R level (G99, in G code system B).
pub fn g83(r: &mut Reader, w: &Words, n: u32, c: u32) -> Result<Flow, TranslateError> {
    let h = hole(r, w, n, c, 83)?;
    let f = r.st.factor();
    let q = match w.get('Q').map(|v| r.in_increments('Q', v)) {
        Some(v) if v.is_finite() && v > 0.0 => v * f,
        Some(v) => {
            return Err(err(
                n,
                w.col('Q').unwrap_or(c),
                format!(
                    "G83 Q{}: the depth of each peck must be above 0 (leave Q out to drill in one feed)",
                    short_number(r.as_written('Q', w.get('Q').unwrap_or(v)))
                ),
            ))
        }
        None => r.st.drill.map_or(0.0, |d| d.q),
    };
    let pecks = if q > 0.0 {
        peck_depths(h.level, h.bottom, q).map_err(|fault| {
            let qs = short_number(q / f);
            err(
                n,
                w.col('Q').unwrap_or(c),
                match fault {
                    PeckFault::TooMany => {
                        format!("G83: Q{qs} would make more than {MAX_PECKS} pecks")
                    }
                    PeckFault::NoDeeper => {
                        format!("G83: Q{qs} is below the resolution of the numbers: a peck would not go deeper")
                    }
                },
            )
        })?
    } else {
        Vec::new()
    };
    let feed = r.feed_in_force(n, c)?;
    r.st.drill = Some(Drill {
        code: 83,
        initial: h.initial,
        r: h.rel,
        q,
        p: h.p,
    });
    let back = PECK_CLEARANCE_INCH * 25.4;
    let start = r.out.pos;
    let mut at = start;
    // To the centre line at the level the tool stands, then to the R level.
    go(r, &mut at, Kind::Rapid, [start[0], 0.0], n, c)?;
    go(r, &mut at, Kind::Rapid, [h.level, 0.0], n, c)?;
    for &depth in &pecks {
        go(r, &mut at, Kind::Line(feed), [depth, 0.0], n, c)?;
        go(r, &mut at, Kind::Rapid, [depth + back, 0.0], n, c)?;
    }
    go(r, &mut at, Kind::Line(feed), [h.bottom, 0.0], n, c)?;
    dwell(r, h.p, n, c)?;
    go(r, &mut at, Kind::Rapid, [h.clear, 0.0], n, c)?;
    Ok(Flow::Next)
}

/// `G84 X(U) Z(W) R P F` (the common words as [`hole`] reads them), Fanuc 0i-T's face
/// tapping with a right-hand tap: the spindle turning forward (M03) at a fixed speed (G97 S).
/// F is the lead: per revolution (G95, system A's G99) F itself, per minute (G94, G98) F / S,
/// as Fanuc's rigid tapping reads it; either way the feed is lead × S per minute, as the
/// mill's G84 gives it, so that the pulse core gears it to the spindle. From where the tool
/// stands: a rapid to X0 if X is given, a rapid to the R level; then the tap's blocks, the
/// mill's G84's in its order and with its `Block::tap` marks (docs/pulse-core.md "Tapping":
/// the overrides held at 100 %, a feed hold kept for the end, the feed geared to the
/// encoder): the feed to the bottom, M05, M04, the dwell P (milliseconds), the feed out to
/// the R level, M05, and M03 (the tap's last block); then a rapid to the initial level (G98)
/// or none (G99: the tap is out at R).
pub fn g84(r: &mut Reader, w: &Words, n: u32, c: u32) -> Result<Flow, TranslateError> {
    let h = hole(r, w, n, c, 84)?;
    if r.st.css {
        return Err(err(
            n,
            c,
            "G84 under G96 (constant surface speed): the tap is geared to a fixed speed, give G97 S",
        ));
    }
    let s = r.st.s;
    if s <= 0.0 {
        return Err(err(
            n,
            c,
            "G84 needs the spindle speed: give G97 S, the tap's rpm",
        ));
    }
    let (f, mode) = r.feed_in_force(n, c)?;
    // The feed per minute the tap's blocks carry: the lead × S.
    let mm_min = match mode {
        FeedMode::PerRev => f * s,
        FeedMode::PerMin => f,
    };
    let feed = (mm_min, FeedMode::PerMin);
    let q = r.st.drill.map_or(0.0, |d| d.q);
    r.st.drill = Some(Drill {
        code: 84,
        initial: h.initial,
        r: h.rel,
        q,
        p: h.p,
    });
    let start = r.out.pos;
    let mut at = start;
    go(r, &mut at, Kind::Rapid, [start[0], 0.0], n, c)?;
    go(r, &mut at, Kind::Rapid, [h.level, 0.0], n, c)?;
    // The tap, as the mill's G84 (`gcode::cycles`, the `74 | 84` arm).
    r.out.set_tap(Tap::Part);
    go(r, &mut at, Kind::Line(feed), [h.bottom, 0.0], n, c)?;
    r.out.spindle(n, c, 5, s, None)?;
    r.out.spindle(n, c, 4, s, None)?;
    dwell(r, h.p, n, c)?;
    go(r, &mut at, Kind::Line(feed), [h.level, 0.0], n, c)?;
    r.out.spindle(n, c, 5, s, None)?;
    r.out.set_tap(Tap::End);
    r.out.spindle(n, c, 3, s, None)?;
    go(r, &mut at, Kind::Rapid, [h.clear, 0.0], n, c)?;
    Ok(Flow::Next)
}
