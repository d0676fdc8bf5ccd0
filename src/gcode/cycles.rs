//! Canned cycles G73, G81, G82, G83, G84, G85, G86 and G89 in the XY plane, expanded into
//! moves as LinuxCNC 2.9 expands them (docs/gcode.md "Canned cycles").
//!
//! R, Z, P and Q are sticky until G80. The initial level is Z where the series of cycles
//! began; G98 retracts to it (or to R if that is higher), G99 to R. Under G91, R is measured
//! from the initial level, Z from R, and X Y from the hole before; L repeats the hole (G91:
//! steps on by X Y each time).

use super::canon::Canon;
use super::interp::{Exec, State, Words};
use crate::block::{Plane, TranslateError};
use crate::input_text::fixed;
use crate::limits::{MAX_BLOCKS, MAX_DWELL_S, MAX_REPEATS};

/// The most pecks one G73 or G83 hole may take (bounded work, docs/limits.md).
pub use crate::limits::MAX_PECKS;

/// Why a G73/G83 hole cannot be pecked.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum PeckFault {
    /// More than [`MAX_PECKS`] pecks.
    TooMany,
    /// A peck of Q does not go deeper: Q is below the resolution of the numbers at that depth.
    NoDeeper,
}

/// The depth after each peck of a G73/G83 hole from `r` down by `q` to `bottom`, as rs274 2.9
/// steps them (`depth − q` until the bottom); at most [`MAX_PECKS`] of them.
pub fn peck_depths(r: f64, bottom: f64, q: f64) -> Result<Vec<f64>, PeckFault> {
    let mut depths = Vec::new();
    let mut depth = r;
    loop {
        let next = (depth - q).max(bottom);
        depths.push(next);
        if next <= bottom {
            return Ok(depths);
        }
        if depths.len() >= MAX_PECKS as usize {
            return Err(PeckFault::TooMany);
        }
        if next >= depth {
            return Err(PeckFault::NoDeeper);
        }
        depth = next;
    }
}

/// G73 and G83 retract this far above the last depth before the next peck, inches.
const PECK_CLEARANCE_INCH: f64 = 0.010;

/// One canned-cycle line.
pub fn cycle(
    st: &mut State,
    x: &mut Exec,
    w: &Words,
    kind: u8,
    col: u32,
) -> Result<(), TranslateError> {
    if st.plane != Plane::XY {
        return Err(x.err(col, "canned cycles work in the XY plane (G17)"));
    }
    if st.comp.active() {
        return Err(x.err(
            col,
            "canned cycles cannot be used with cutter radius compensation on",
        ));
    }
    let k = st.factor();
    let name = format!("G{kind}");
    // A new cycle (or the first) must say its R and Z; they are sticky within one cycle.
    if st.cycle_kind != Some(kind) {
        if w.get('R').is_none() {
            return Err(x.err(col, format!("{name} needs R, the level where the feed starts (R is kept only while the same cycle repeats)")));
        }
        if w.get('Z').is_none() {
            return Err(x.err(col, format!("{name} needs Z, the bottom of the hole (Z is kept only while the same cycle repeats)")));
        }
        if matches!(kind, 82 | 86 | 89) && w.get('P').is_none() {
            return Err(x.err(
                col,
                format!("{name} needs P, the dwell at the bottom in seconds"),
            ));
        }
        st.cycle_kind = Some(kind);
    }
    if let Some(r) = w.get('R') {
        st.cycle_r = Some(r * k);
    }
    if let Some(z) = w.get('Z') {
        st.cycle_z = Some(z * k);
    }
    if let Some(p) = w.get('P') {
        let pc = w.col('P').unwrap_or(col);
        if p < 0.0 {
            return Err(x.err(pc, "a negative dwell P"));
        }
        if p > MAX_DWELL_S {
            return Err(x.err(
                pc,
                crate::limits::dwell_too_long(&format!("P{}", crate::input_text::short_number(p))),
            ));
        }
        st.cycle_p = p;
    }
    if let Some(q) = w.get('Q') {
        if q <= 0.0 {
            return Err(x.err(
                w.col('Q').unwrap_or(col),
                format!(
                    "the peck Q must be greater than 0, not {}",
                    crate::input_text::short_number(q)
                ),
            ));
        }
        st.cycle_q = Some(q * k);
    }
    let r_in = st.cycle_r.ok_or_else(|| {
        x.err(
            col,
            format!("{name} needs R, the level where the feed starts"),
        )
    })?;
    let z_in = st
        .cycle_z
        .ok_or_else(|| x.err(col, format!("{name} needs Z, the bottom of the hole")))?;
    let q = match kind {
        73 | 83 => Some(
            st.cycle_q
                .ok_or_else(|| x.err(col, format!("{name} needs Q, the peck (greater than 0)")))?,
        ),
        _ => None,
    };
    if st.feed <= 0.0 {
        return Err(x.err(col, "a feed move without F: canned cycles feed, give F"));
    }
    if matches!(kind, 84 | 86) && st.spindle == 0 {
        return Err(x.err(
            col,
            format!("{name} needs the spindle turning: give M03 (or M04) first"),
        ));
    }
    let l = match (w.get('L'), w.col('L')) {
        (Some(l), Some(lc)) => {
            if l.fract() != 0.0 || l < 0.0 || l > f64::from(MAX_REPEATS) {
                return Err(x.err(
                    lc,
                    format!(
                        "L{} must be a whole number of repeats from 0 to {MAX_REPEATS}",
                        crate::input_text::short_number(l)
                    ),
                ));
            }
            l as u32
        }
        _ => 1,
    };
    let prog = st.prog();
    let series_starts = st.cycle_il.is_none();
    let il = *st.cycle_il.get_or_insert(prog[2]);
    let (r, bottom) = if st.incremental {
        (il + r_in, il + r_in + z_in)
    } else {
        (r_in, z_in)
    };
    if bottom > r {
        return Err(x.err(
            col,
            format!(
                "{name}: the bottom Z{} is above R{}",
                fixed(bottom / k, 4),
                fixed(r / k, 4)
            ),
        ));
    }
    // The pecks of a hole, the same for every hole of the line.
    let pecks = match q.map(|q| peck_depths(r, bottom, q)) {
        None => Vec::new(),
        Some(Ok(d)) => d,
        Some(Err(fault)) => {
            let q = crate::input_text::short_number(q.unwrap_or(1.0) / k);
            return Err(x.err(
                w.col('Q').unwrap_or(col),
                match fault {
                    PeckFault::TooMany => {
                        format!("{name}: Q{q} would make more than {MAX_PECKS} pecks")
                    }
                    PeckFault::NoDeeper => format!(
                        "{name}: Q{q} is below the resolution of the numbers near R{}: a peck would not go deeper",
                        fixed(r / k, 3)
                    ),
                },
            ));
        }
    };
    // What the line will make, counted from its words before anything is made: a rapid to R
    // first for a series that starts below it, then per hole a rapid to X Y, one to R, the
    // cycle's own moves and the rapid to the clear level.
    let n = pecks.len() as u64;
    let own: u64 = match kind {
        81 | 85 => 1 + u64::from(kind == 85),
        82 => 2,
        73 => 2 * n - 1,
        83 => 3 * n - 2,
        84 => 4 + u64::from(st.cycle_p > 0.0),
        86 => 4 + u64::from(st.cycle_p > 0.0),
        _ => 3,
    };
    let per_hole = own + 3;
    let first = u64::from(series_starts && prog[2] < r);
    let total = first + u64::from(l) * per_hole;
    if total > MAX_BLOCKS as u64 {
        return Err(x.err(
            w.col('L').unwrap_or(col),
            format!(
                "{name} L{l} makes {total} blocks ({l} holes of {per_hole}), more than the {MAX_BLOCKS} one line may make: split the holes over several lines"
            ),
        ));
    }
    x.out.reserve(total as usize);
    let made_before = x.out.len();
    let clear = if st.retract_r { r } else { il.max(r) };
    let clearance = PECK_CLEARANCE_INCH * 25.4;
    let feed = st.feed;
    // Work in program coordinates; `go` converts.
    let mut pos = prog;
    let frame = st.frame();
    let m = |p: [f64; 3]| [p[0] + frame[0], p[1] + frame[1], p[2] + frame[2]];
    let rapid = |x: &mut Exec, pos: &mut [f64; 3], p: [f64; 3]| {
        x.push(Canon::Rapid(m(p)), col);
        *pos = p;
    };
    let feed_to = |x: &mut Exec, pos: &mut [f64; 3], p: [f64; 3]| {
        x.push(Canon::Feed(m(p), feed), col);
        *pos = p;
    };
    // Below R: the first cycle of a series rises to R first; a later one rises on the way to
    // its first hole (as rs274 2.9 does).
    if pos[2] < r {
        if series_starts {
            let to = [pos[0], pos[1], r];
            rapid(x, &mut pos, to);
        } else {
            pos[2] = r;
        }
    }
    let spindle_m = |dir: i8| -> Option<u8> {
        match dir {
            1 => Some(3),
            -1 => Some(4),
            _ => None,
        }
    };
    for i in 0..l {
        let (hx, hy) = if st.incremental {
            (
                pos[0] + w.get('X').unwrap_or(0.0) * k,
                pos[1] + w.get('Y').unwrap_or(0.0) * k,
            )
        } else {
            let _ = i;
            (
                w.get('X').map_or(pos[0], |v| v * k),
                w.get('Y').map_or(pos[1], |v| v * k),
            )
        };
        let to = [hx, hy, pos[2]];
        rapid(x, &mut pos, to);
        rapid(x, &mut pos, [hx, hy, r]);
        let at = |z: f64| [hx, hy, z];
        match kind {
            81 => {
                feed_to(x, &mut pos, at(bottom));
            }
            82 => {
                feed_to(x, &mut pos, at(bottom));
                x.push(Canon::Dwell(st.cycle_p), col);
            }
            73 | 83 => {
                for (i, &next) in pecks.iter().enumerate() {
                    feed_to(x, &mut pos, at(next));
                    if i + 1 == pecks.len() {
                        break;
                    }
                    if kind == 83 {
                        rapid(x, &mut pos, at(r));
                    }
                    rapid(x, &mut pos, at(next + clearance));
                }
            }
            84 => {
                feed_to(x, &mut pos, at(bottom));
                x.push(
                    Canon::Aux {
                        s: None,
                        t: None,
                        m: Some(4),
                    },
                    col,
                );
                if st.cycle_p > 0.0 {
                    x.push(Canon::Dwell(st.cycle_p), col);
                }
                feed_to(x, &mut pos, at(clear));
                x.push(
                    Canon::Aux {
                        s: None,
                        t: None,
                        m: spindle_m(st.spindle).or(Some(3)),
                    },
                    col,
                );
            }
            85 => {
                feed_to(x, &mut pos, at(bottom));
                feed_to(x, &mut pos, at(r));
            }
            86 => {
                feed_to(x, &mut pos, at(bottom));
                if st.cycle_p > 0.0 {
                    x.push(Canon::Dwell(st.cycle_p), col);
                }
                x.push(
                    Canon::Aux {
                        s: None,
                        t: None,
                        m: Some(5),
                    },
                    col,
                );
                rapid(x, &mut pos, at(clear));
                if let Some(mm) = spindle_m(st.spindle) {
                    x.push(
                        Canon::Aux {
                            s: None,
                            t: None,
                            m: Some(mm),
                        },
                        col,
                    );
                }
            }
            _ => {
                // G89: bore, dwell, feed out to the clear level.
                feed_to(x, &mut pos, at(bottom));
                x.push(Canon::Dwell(st.cycle_p), col);
                feed_to(x, &mut pos, at(clear));
            }
        }
        rapid(x, &mut pos, at(clear));
    }
    debug_assert_eq!(
        (x.out.len() - made_before) as u64,
        total,
        "the count of {name}"
    );
    st.cur = m(pos);
    Ok(())
}
