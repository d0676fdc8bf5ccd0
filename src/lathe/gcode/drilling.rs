//! Fanuc 0i-T's face drilling cycle G83 on the spindle centre line (docs/lathe-gcode.md "G83
//! face drilling"): the drill stands still on X0, the work turns. Fanuc's dialect only:
//! LinuxCNC has no drilling cycle on a lathe. The pecking depths are the mill's
//! (`crate::gcode::cycles::peck_depths`), one rule for both machines.

use super::cycles::mv;
use super::exec::{err, Flow, Reader};
use super::out::{self, Kind};
use crate::block::TranslateError;
use crate::gcode::cycles::{peck_depths, PeckFault, MAX_PECKS, PECK_CLEARANCE_INCH};
use crate::gcode::words::Words;
use crate::input_text::{fixed, short_number};

/// What a G83 series keeps from one block to the next (Fanuc: the drilling data are modal
/// until G80 or a group 01 code).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Drill {
    /// The initial level: Z (mm) where the tool stood at the series' first block.
    pub initial: f64,
    /// R: the R level's distance from the initial level, mm, its sign included.
    pub r: f64,
    /// Q: the depth of each peck, mm (0: one feed to the bottom).
    pub q: f64,
    /// P: the dwell at the bottom, seconds.
    pub p: f64,
}

/// The centre line: an X (radius, mm) this close to 0 is on it.
const ON_CENTRE: f64 = 1e-6;

/// `G83 X(U) Z(W) R Q P F` (`c` the column of G83, or of the first axis word on a block that
/// repeats the cycle under its mode; R, Q, P and the initial level are kept for the series
/// until G80 or a group 01 code). From where the tool stands (the initial level, kept for the
/// series): a rapid to X0 if X is given and the tool
/// is not on it, a rapid to the R level (R is the distance from the initial level, its sign
/// included), the feed to the bottom Z (W: from the R level) in pecks of Q (Fanuc's
/// high-speed peck drilling, parameter 5101#2 RTR = 0: after each peck the drill rapids back
/// d = 0.254 mm, the mill's clearance), the dwell P (milliseconds) at the bottom, and a rapid
/// back to the initial level (G98) or to the R level (G99, in G code system B).
pub fn g83(r: &mut Reader, w: &Words, n: u32, c: u32) -> Result<Flow, TranslateError> {
    if !r.fanuc {
        return Err(err(
            n,
            c,
            "G83 is Fanuc's face drilling cycle; LinuxCNC has no drilling cycle on a lathe: read the program in the Fanuc dialect (`dialect fanuc`)",
        ));
    }
    if r.in_cycle {
        return Err(err(n, c, "G83 inside a G70/G71 profile"));
    }
    if r.out.comp_on() {
        return Err(err(
            n,
            c,
            "G83 with nose-radius compensation in force: give G40 first",
        ));
    }
    if let Some(col) = w.col('K') {
        return Err(err(
            n,
            col,
            "G83 K, the repeats, is not supported: the drill stands on the centre line, a repeat would drill the same hole",
        ));
    }
    for l in ['I', 'J', 'H', 'E', 'L', 'D'] {
        if let Some(col) = w.col(l) {
            return Err(err(n, col, format!("G83 takes no {l} word")));
        }
    }
    for l in ['P', 'Q'] {
        if r.written_with_point(l) {
            let what = match (l, r.st.inch) {
                ('P', _) => "G83 P, the dwell, is in milliseconds, without a decimal point (P500 is 0.5 s)",
                (_, false) => "G83 Q, the depth of each peck, is in least increments, without a decimal point (Q5000 is 5.000 mm)",
                (_, true) => "G83 Q, the depth of each peck, is in least increments, without a decimal point (Q1000 is 0.1000 inch under G20)",
            };
            return Err(err(n, w.col(l).unwrap_or(c), what));
        }
    }
    if r.st.stopped() {
        return Err(err(
            n,
            c,
            "G83 with the spindle stopped: the work turns and the drill stands still, give M03 or M04",
        ));
    }
    let f = r.st.factor();
    let start = r.out.pos;
    let kept = r.st.drill;
    let initial = kept.map_or(start[0], |d| d.initial);
    // R, Q and P: given, else the series' (a first block: R 0, no pecks, no dwell).
    let rel = match w.get('R') {
        Some(v) => v * f,
        None => kept.map_or(0.0, |d| d.r),
    };
    if !(rel.is_finite() && rel.abs() <= 1000.0) {
        return Err(err(
            n,
            w.col('R').unwrap_or(c),
            "G83 R, the R level's distance from the initial level, is at most 1000 mm",
        ));
    }
    let q = match w.get('Q') {
        Some(v) if v.is_finite() && v > 0.0 => v * f,
        Some(v) => {
            return Err(err(
                n,
                w.col('Q').unwrap_or(c),
                format!(
                    "G83 Q{}: the depth of each peck must be above 0 (leave Q out to drill in one feed)",
                    short_number(r.as_written('Q', v))
                ),
            ))
        }
        None => kept.map_or(0.0, |d| d.q),
    };
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
                    "G83 P{}: the dwell is a whole number of milliseconds, not negative",
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
        let (col, why) = match x_col {
            Some(col) => (col, format!("G83 at X{}", fixed(end[1] * 2.0 / f, 3))),
            None => (
                c,
                format!("G83 with the tool at X{}", fixed(end[1] * 2.0 / f, 3)),
            ),
        };
        return Err(err(
            n,
            col,
            format!("{why}: the lathe drills on the centre line only (X0), it has no live tooling to drill off the centre"),
        ));
    }
    let level = initial + rel;
    let bottom = if let Some(v) = w.get('W') {
        level + v * f
    } else if let Some(v) = w.get('Z') {
        if r.st.absolute {
            r.st.origin[0] + v * f
        } else {
            level + v * f
        }
    } else {
        return Err(err(
            n,
            x_col.unwrap_or(c),
            "G83 needs Z (or W, from the R level), the bottom of the hole",
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
                "G83: the bottom Z{} is not below the R level Z{} (the initial level Z{} and R{}): the drill feeds towards -Z",
                fixed((bottom - r.st.origin[0]) / f, 3),
                fixed((level - r.st.origin[0]) / f, 3),
                fixed((initial - r.st.origin[0]) / f, 3),
                fixed(rel / f, 3)
            ),
        ));
    }
    let pecks = if q > 0.0 {
        peck_depths(level, bottom, q).map_err(|fault| {
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
    let clear = if r.st.drill_to_r && !r.system_a {
        level
    } else {
        initial
    };
    r.st.drill = Some(Drill {
        initial,
        r: rel,
        q,
        p,
    });
    let back = PECK_CLEARANCE_INCH * 25.4;
    let mut at = start;
    let mut go = |r: &mut Reader, kind: Kind, to: [f64; 2]| -> Result<(), TranslateError> {
        if to != at {
            r.out.motion(mv(kind, to, n, c))?;
            at = to;
        }
        Ok(())
    };
    // To the centre line at the level the tool stands, then to the R level.
    go(r, Kind::Rapid, [start[0], 0.0])?;
    go(r, Kind::Rapid, [level, 0.0])?;
    for &depth in &pecks {
        go(r, Kind::Line(feed), [depth, 0.0])?;
        go(r, Kind::Rapid, [depth + back, 0.0])?;
    }
    go(r, Kind::Line(feed), [bottom, 0.0])?;
    if p > 0.0 {
        let dwell = crate::block::Block {
            motion: crate::block::Motion::Dwell,
            dwell_ns: (p * 1e9).round() as u64,
            ..out::aux()
        };
        r.out.op(n, c, dwell)?;
    }
    go(r, Kind::Rapid, [clear, 0.0])?;
    Ok(Flow::Next)
}
