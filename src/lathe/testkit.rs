//! Hand-built lathe machines and programs for the tests and the benchmark: a three-channel
//! Citizen-like lathe (seed 004's three systems, spindles 1 → 2 → 3 → unloader) and a sample
//! part (docs/pulse-core.md "Channels", "The sample run"), run on the kernel through
//! `lathe::blocks::kernel_channels`.

use crate::lathe::desc::{AxisDesc, ChannelDesc, LatheDesc, ToolDesc};
use crate::lathe::ops::{Feed, LatheProgram, Op, SpeedMode, SpindleDir, Step};

/// Millimetres to pulses of the test machine (0.001 mm).
pub fn mm(v: f64) -> i64 {
    (v * 1000.0).round() as i64
}

/// A point [X radius, Z] in mm as pulses.
pub fn pt(x: f64, z: f64) -> [i64; 2] {
    [mm(x), mm(z)]
}

/// One channel of the test machine.
pub fn channel(name: &str) -> ChannelDesc {
    let axis = |lo: f64, hi: f64| AxisDesc {
        travel: [lo, hi],
        rapid: 24_000.0,
        accel: 3_000.0,
    };
    ChannelDesc {
        name: name.to_string(),
        axes: [axis(-1.0, 60.0), axis(-80.0, 60.0)],
        max_rpm: 6_000.0,
        spindle_accel: 8_000.0,
        encoder: 1_000,
        tools: (1..=4)
            .map(|number| ToolDesc {
                number,
                radius: 0.4,
                tip: 3,
                offset: [0.0, 0.0],
            })
            .collect(),
    }
}

/// A Citizen-like lathe of `n` channels: 0.001 mm pulses, a 100 µs tick, the bar feeder on
/// channel 1, transfers 1 → 2 → … → n, channel n to the unloader.
pub fn citizen_like(n: usize) -> LatheDesc {
    LatheDesc {
        name: "citizen-like".to_string(),
        pulse_mm: 0.001,
        tick_ns: 100_000,
        channels: (1..=n).map(|i| channel(&format!("SYS{i}"))).collect(),
        supplier: 0,
        transfers: (1..n).map(|i| (i - 1, i)).collect(),
        unloader: n.saturating_sub(1),
    }
}

/// A program named `name` of the given operations, one source line each.
pub fn program(name: &str, ops: Vec<Op>) -> LatheProgram {
    let lines = ops.iter().map(|op| format!("{op:?}")).collect();
    let steps = ops
        .into_iter()
        .enumerate()
        .map(|(k, op)| Step {
            line: k as u32 + 1,
            op,
        })
        .collect();
    LatheProgram {
        name: name.to_string(),
        lines,
        steps,
    }
}

/// A rapid to (x, z) mm.
pub fn rapid(x: f64, z: f64) -> Op {
    Op::Rapid { end: pt(x, z) }
}

/// A feed line to (x, z) mm at `f` mm/rev.
pub fn line_rev(x: f64, z: f64, f: f64) -> Op {
    Op::Line {
        end: pt(x, z),
        feed: Feed::PerRev(f),
    }
}

/// Spindle clockwise at `rpm`.
pub fn rpm(rpm: f64) -> Op {
    Op::Spindle {
        dir: SpindleDir::Cw,
        mode: SpeedMode::Rpm(rpm),
    }
}

/// Spindle clockwise at `v` m/min constant surface speed, at most `limit` rpm.
pub fn css(v: f64, limit: f64) -> Op {
    Op::Spindle {
        dir: SpindleDir::Cw,
        mode: SpeedMode::Css {
            m_per_min: v,
            limit_rpm: limit,
        },
    }
}

/// A thread pass to (x, z) mm with `lead` mm/rev.
pub fn thread(x: f64, z: f64, lead: f64) -> Op {
    Op::Thread {
        end: pt(x, z),
        lead,
    }
}

/// System 1: receives the bar, faces under G96 and turns a diameter, delivers to system 2.
pub fn system1() -> LatheProgram {
    program(
        "sys1",
        vec![
            Op::ChuckClose,
            Op::Tool { tool: 1 },
            css(150.0, 4_000.0),
            rapid(12.0, 0.0),
            line_rev(0.0, 0.0, 0.1),
            rapid(10.0, 1.0),
            line_rev(10.0, -20.0, 0.2),
            rapid(15.0, 1.0),
            Op::ChuckOpen,
            Op::End { m30: true },
        ],
    )
}

/// System 2: receives from system 1, back-works (a turned step and a G03 round), delivers.
pub fn system2() -> LatheProgram {
    program(
        "sys2",
        vec![
            Op::ChuckClose,
            Op::Tool { tool: 1 },
            rpm(2_000.0),
            rapid(9.0, 1.0),
            line_rev(9.0, -8.0, 0.1),
            rapid(6.0, 1.0),
            line_rev(6.0, 0.0, 0.1),
            Op::Arc {
                end: pt(8.0, -2.0),
                centre: pt(6.0, -2.0),
                ccw: true,
                feed: Feed::PerRev(0.1),
            },
            rapid(12.0, 1.0),
            Op::ChuckOpen,
            Op::End { m30: true },
        ],
    )
}

/// System 3: receives from system 2, cuts a 1.5 mm thread in three passes, delivers to the
/// unloader.
pub fn system3() -> LatheProgram {
    let mut ops = vec![Op::ChuckClose, Op::Tool { tool: 2 }, rpm(1_000.0)];
    for x in [9.7, 9.5, 9.35] {
        ops.push(rapid(x, 2.0));
        ops.push(thread(x, -15.0, 1.5));
        ops.push(rapid(11.0, -15.0));
        ops.push(rapid(11.0, 2.0));
    }
    ops.push(rapid(15.0, 5.0));
    ops.push(Op::ChuckOpen);
    ops.push(Op::End { m30: true });
    program("sys3", ops)
}

/// The three sample programs.
pub fn sample_programs() -> Vec<LatheProgram> {
    vec![system1(), system2(), system3()]
}

/// The kernel running `programs` on `desc` to `target` parts (`blocks::kernel_channels`),
/// every tool at `at` ([X, Z] pulses) or, if None, at its home (`gcode::home`); not started.
pub fn kernel(
    desc: &LatheDesc,
    programs: &[LatheProgram],
    target: u32,
    at: Option<[i64; 2]>,
) -> Result<crate::pulse_core::Kernel, String> {
    let (chans, flow) = crate::lathe::blocks::kernel_channels(desc, programs)?;
    let mut k = crate::pulse_core::Kernel::new(chans, Some(flow), target)?;
    for ch in 0..desc.channels.len() {
        let p = at.unwrap_or_else(|| crate::lathe::gcode::home(desc, ch));
        k.set_position(ch, [p[0], 0, p[1]])?;
    }
    Ok(k)
}

/// The sample (`citizen_like(3)`, [`sample_programs`]) to `target` parts, every tool at
/// X 20 Z 5 mm, not started.
pub fn sample_kernel(target: u32) -> Result<crate::pulse_core::Kernel, String> {
    kernel(
        &citizen_like(3),
        &sample_programs(),
        target,
        Some(pt(20.0, 5.0)),
    )
}
