//! The hole cycles DRL, TAP, REM and BOR, the tool change and the move between holes
//! (patent subroutine AP11, Fig. 13, and the cycle table of Table C: T, F, S, the rapid-advance
//! end Xa Ya Za, the cutting-feed end Xb Yb Zb and the rapid-retract end Xc Yc Zc).

use super::emit::{Loaded, Out, Spindle};
use super::parse::CycleKind;
use crate::block::Tap;

/// Distance above the bottom of the previous peck where a DH peck re-enters at rapid, mm.
pub const PECK_REENTRY_MM: f64 = 0.5;

/// The resolved conditions of one cutting statement (the cycle table's fixed part).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Cycle {
    /// Which cycle.
    pub kind: CycleKind,
    /// T code of the tool.
    pub tcode: u32,
    /// Set length of the tool, pulses.
    pub set: i64,
    /// Cutting feed F, mm/min.
    pub feed: f64,
    /// Spindle speed S, rpm.
    pub speed: u32,
    /// Cutting depth below the surface, mm (DP, or from DI).
    pub depth: f64,
    /// Clearance SCL above the surface, mm.
    pub scl: f64,
    /// Rapid-feed depth SDP below the surface, mm, if given.
    pub sdp: Option<f64>,
    /// Dwell at the bottom, seconds.
    pub dwell: Option<f64>,
    /// Peck step DH, mm.
    pub peck: Option<f64>,
}

/// The heights of one hole, tool-tip Z in pulses (Table C).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Heights {
    /// Za: end of the rapid advance.
    pub za: i64,
    /// Zb: end of the cutting feed.
    pub zb: i64,
    /// Zc: end of the rapid retract (= Za).
    pub zc: i64,
    /// The clearance plane zs + SCL, the lowest height for moving to or from this hole.
    pub clear: i64,
}

impl Cycle {
    /// The heights for a hole whose surface is at tool-tip Z `zs` (mm, machine coordinates).
    pub fn heights(&self, o: &Out, zs: f64) -> Heights {
        let za_mm = match self.sdp {
            Some(d) => zs - d,
            None => zs + self.scl,
        };
        let za = o.p(za_mm);
        Heights {
            za,
            zb: o.p(zs - self.depth),
            zc: za,
            clear: o.p(zs + self.scl),
        }
    }
}

/// Puts tool `tcode` in the spindle unless it is there: rapid Z to machine zero, spindle stop
/// (if running), then `T.. M06`.
pub fn tool_change(o: &mut Out, tcode: u32, set: i64) {
    if o.m.tool.map(|t| t.tcode) == Some(tcode) {
        return;
    }
    o.rapid_home(None);
    if o.m.spindle != Spindle::Stopped {
        o.aux(None, None, Some(5));
        o.m.spindle = Spindle::Stopped;
    }
    o.aux(None, Some(tcode), Some(6));
    o.m.tool = Some(Loaded { tcode, set });
    o.m.clear = None;
}

/// Moves to above a hole or contour start at (x, y) pulses: rise first to the higher of the
/// clearance plane being left and the one being entered (never lower than where the tool is),
/// then X Y at rapid, start the spindle if needed, then rapid down to Za.
pub fn approach(o: &mut Out, x: i64, y: i64, za: i64, clear: i64, speed: u32) {
    let tip = o.m.tip();
    let h = tip.max(clear).max(o.m.clear.unwrap_or(i64::MIN));
    if h > tip {
        o.rapid_tip(h);
    }
    let z = o.m.pos[2];
    o.rapid([x, y, z]);
    o.spindle_forward(speed);
    o.rapid_tip(za);
}

/// One hole of DRL, TAP, REM or BOR at machine (x, y) pulses with surface tip Z `zs` mm.
pub fn hole(o: &mut Out, c: &Cycle, x: i64, y: i64, zs: f64) {
    let h = c.heights(o, zs);
    approach(o, x, y, h.za, h.clear, c.speed);
    match c.kind {
        CycleKind::Drl => {
            if let Some(step) = c.peck {
                peck(o, c, &h, zs, step);
            } else {
                o.feed_tip(h.zb, c.feed);
            }
            if let Some(s) = c.dwell {
                o.dwell(s);
            }
            o.rapid_tip(h.zc);
        }
        CycleKind::Tap => {
            let first = o.blocks.len();
            o.feed_tip(h.zb, c.feed);
            o.aux(None, None, Some(4));
            o.m.spindle = Spindle::Reverse;
            o.feed_tip(h.zc, c.feed);
            o.spindle_forward(c.speed);
            // The tap's blocks, up to the spindle forward again out of the hole: the
            // overrides held, a feed hold kept for the end (docs/pulse-core.md "Tapping").
            let n = o.blocks.len();
            for (i, b) in o.blocks[first..].iter_mut().enumerate() {
                b.tap = if first + i + 1 == n {
                    Tap::End
                } else {
                    Tap::Part
                };
            }
        }
        CycleKind::Rem => {
            o.feed_tip(h.zb, c.feed);
            if let Some(s) = c.dwell {
                o.dwell(s);
            }
            o.feed_tip(h.zc, c.feed);
        }
        CycleKind::Bor => {
            o.feed_tip(h.zb, c.feed);
            if let Some(s) = c.dwell {
                o.dwell(s);
            }
            o.aux(None, None, Some(5));
            o.m.spindle = Spindle::Stopped;
            o.rapid_tip(h.zc);
        }
        CycleKind::Mil => {}
    }
    o.m.clear = Some(h.clear);
}

/// DRL with DH: pecks of `step` mm measured down from Za, back to Za at rapid between pecks,
/// then down at rapid to `PECK_REENTRY_MM` above the last bottom before feeding again.
fn peck(o: &mut Out, c: &Cycle, h: &Heights, zs: f64, step: f64) {
    let za_mm = match c.sdp {
        Some(d) => zs - d,
        None => zs + c.scl,
    };
    let zb_mm = zs - c.depth;
    let mut k = 1.0;
    let mut last: Option<i64> = None;
    loop {
        let target_mm = (za_mm - k * step).max(zb_mm);
        let target = if target_mm <= zb_mm {
            h.zb
        } else {
            o.p(target_mm)
        };
        if let Some(prev) = last {
            o.rapid_tip(h.za);
            let reentry = (prev + o.p(PECK_REENTRY_MM)).min(h.za);
            o.rapid_tip(reentry);
        }
        o.feed_tip(target, c.feed);
        if target == h.zb {
            break;
        }
        last = Some(target);
        k += 1.0;
    }
}
