//! The adapter from a lathe channel's operations to the kernel's blocks (issue 22: one `Block`
//! between the language readers and the kernel; docs/pulse-core.md, "Channels"). Until the
//! lathe G-code reader emits blocks itself, a `LatheProgram` read by it runs on the
//! multi-channel kernel through this.
//!
//! - X (a radius) is axis 0, Z axis 2, Y stays 0;
//! - arcs are in `Plane::XZ`, their centre relative to the start as (I, K); an op's `ccw`
//!   turns from +Z towards +X, which is G18's counter-clockwise (`Plane::XZ.turn_axes()` is
//!   Z → X), so `ccw` is `ArcCcw`;
//! - a per-revolution feed is `feed_mode: PerRev`, G96 is `css` on every block while it is in
//!   force (it is modal, as the kernel reads it), a thread pass is a `Linear`
//!   block with `thread` (its lead, also its per-revolution feed);
//! - the spindle's state is M3/M4/M5 with `s` (G97) or `css` (G96); a tool is `t` alone (a
//!   turret indexes, no M6);
//! - M10, M11 and the waiting M codes are `sync` blocks; M00/M01 are m 0/1 (the reader has
//!   already dropped M01 with OPTIONAL STOP off); the end is m 2 or 30, and nothing after it
//!   is run (the reader's program ends there too).

use super::desc::LatheDesc;
use super::ops::{Feed, LatheProgram, Op, SpeedMode, SpindleDir};
use crate::block::{Block, Css, FeedMode, Motion, Plane, Statement, Sync};

/// Channel `ch`'s program as blocks, one statement per source line, starting from the point
/// the reader takes the tool to stand at (`gcode::home`).
pub fn blocks(prog: &LatheProgram, desc: &LatheDesc, ch: usize) -> Vec<Statement> {
    let home = super::gcode::home(desc, ch);
    let mut pos = [home[0], 0, home[1]];
    let mut out: Vec<Statement> = Vec::new();
    let mut seq = 0u32;
    // G96 is modal: every block carries it while it is in force (the kernel follows X then).
    let mut css: Option<Css> = None;
    for step in &prog.steps {
        seq += 1;
        let mut b = Block::aux(seq, step.line, pos);
        let at = |p: [i64; 2]| [p[0], 0, p[1]];
        let feed = |b: &mut Block, f: Feed| match f {
            Feed::PerMin(f) => b.feed = f,
            Feed::PerRev(f) => {
                b.feed = f;
                b.feed_mode = FeedMode::PerRev;
            }
        };
        let mut end = false;
        match &step.op {
            Op::Rapid { end } => {
                b.motion = Motion::Rapid;
                b.end = at(*end).into();
            }
            Op::Line { end, feed: f } => {
                b.motion = Motion::Linear;
                b.end = at(*end).into();
                feed(&mut b, *f);
            }
            Op::Arc {
                end,
                centre,
                ccw,
                feed: f,
            } => {
                b.motion = if *ccw { Motion::ArcCcw } else { Motion::ArcCw };
                b.plane = Plane::XZ;
                b.end = at(*end).into();
                // (I, K): the plane's axes in X Y Z order.
                b.center = Some([centre[0] - pos[0], centre[1] - pos[2]]);
                feed(&mut b, *f);
            }
            Op::Thread { end, lead } => {
                b.motion = Motion::Linear;
                b.end = at(*end).into();
                b.feed = *lead;
                b.feed_mode = FeedMode::PerRev;
                b.thread = Some(*lead);
            }
            Op::Dwell { ns } => {
                b.motion = Motion::Dwell;
                b.dwell_ns = *ns;
            }
            Op::Spindle { dir, mode } => {
                b.m = Some(match dir {
                    SpindleDir::Cw => 3,
                    SpindleDir::Ccw => 4,
                    SpindleDir::Stop => 5,
                });
                match *mode {
                    SpeedMode::Rpm(r) => {
                        b.s = Some(r.clamp(0.0, f64::from(u32::MAX)) as u32);
                        css = None;
                    }
                    SpeedMode::Css {
                        m_per_min,
                        limit_rpm,
                    } => {
                        css = Some(Css {
                            m_per_min,
                            limit_rpm,
                        })
                    }
                }
            }
            Op::Tool { tool } => b.t = Some(*tool),
            Op::Wait { m, with } => b.sync = Some(Sync::Wait { m: *m, with: *with }),
            Op::ChuckClose => b.sync = Some(Sync::ChuckClose),
            Op::ChuckOpen => b.sync = Some(Sync::ChuckOpen),
            Op::Stop { optional } => b.m = Some(u8::from(*optional)),
            Op::End { m30 } => {
                b.m = Some(if *m30 { 30 } else { 2 });
                end = true;
            }
        }
        b.css = css;
        b.delta = [b.end[0] - pos[0], 0, b.end[2] - pos[2]].into();
        pos = b.end.xyz();
        match out.last_mut() {
            Some(s) if s.line == step.line => s.blocks.push(b),
            _ => out.push(Statement {
                line: step.line,
                text: prog
                    .lines
                    .get((step.line as usize).wrapping_sub(1))
                    .cloned()
                    .unwrap_or_default(),
                blocks: vec![b],
            }),
        }
        if end {
            break;
        }
    }
    out
}

/// The settings and blocks of every channel of `desc` running `programs`, and the work flow,
/// for [`crate::pulse_core::Kernel::new`]. Errors: a program count other than the channel
/// count.
#[allow(clippy::type_complexity)]
pub fn kernel_channels(
    desc: &LatheDesc,
    programs: &[LatheProgram],
) -> Result<
    (
        Vec<(crate::settings::MachineSettings, Vec<Statement>)>,
        crate::pulse_core::WorkFlow,
    ),
    String,
> {
    if programs.len() != desc.channels.len() {
        return Err(format!(
            "{} programs for {} channels: give one program per channel",
            programs.len(),
            desc.channels.len()
        ));
    }
    let mut chans = Vec::new();
    for (ch, p) in programs.iter().enumerate() {
        let s = crate::settings::MachineSettings::lathe_channel(desc, ch)
            .ok_or_else(|| format!("no channel {}", ch + 1))?;
        chans.push((s, blocks(p, desc, ch)));
    }
    let flow = crate::pulse_core::WorkFlow {
        supplier: desc.supplier,
        transfers: desc.transfers.clone(),
        unloader: desc.unloader,
    };
    Ok((chans, flow))
}
