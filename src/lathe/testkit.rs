//! Hand-built lathe machines and programs for the tests and the benchmark: a three-channel
//! Citizen-like lathe (seed 004's three systems, spindles 1 → 2 → 3 → unloader) and a sample
//! part in G-code (docs/pulse-core.md "Channels", "The sample run"), run on the kernel through
//! `LatheDesc::kernel_channels`.

use crate::lathe::desc::{AxisDesc, ChannelDesc, LatheDesc, ToolDesc};

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
        ..ChannelDesc::unset()
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
        manual: false,
    }
}

/// Channel `ch`'s program `text` read by the lathe G-code reader on `desc`.
pub fn program(
    desc: &LatheDesc,
    ch: usize,
    text: &str,
) -> Result<Vec<crate::block::Statement>, String> {
    crate::lathe::gcode::read_program(text, desc, ch, &Default::default())
        .map_err(|e| format!("CH{}:{e}", ch + 1))
}

/// System 1: receives the bar, faces under G96 and turns a diameter, delivers to system 2.
/// X is a radius (G08), one block a line.
pub const SYSTEM1: &str = "G8 G95 M10
T0101
G96 S150 D4000 M3
G0 X12 Z0
G1 X0 Z0 F0.1
G0 X10 Z1
G1 Z-20 F0.2
G0 X15 Z1
M5
M11
M30
";

/// System 2: receives from system 1, back-works (a turned step and a G03 round), delivers.
pub const SYSTEM2: &str = "G8 G95 M10
T0101
M3 S2000
G0 X9 Z1
G1 Z-8 F0.1
G0 X6 Z1
G1 Z0
G3 X8 Z-2 I0 K-2
G0 X12 Z1
M5
M11
M30
";

/// System 3: receives from system 2, cuts a 1.5 mm thread in three passes, delivers to the
/// unloader.
pub const SYSTEM3: &str = "G8 G95 M10
T0202
M3 S1000
G0 X9.7 Z2
G33 Z-15 K1.5
G0 X11
Z2
G0 X9.5
G33 Z-15 K1.5
G0 X11
Z2
G0 X9.35
G33 Z-15 K1.5
G0 X11
Z2
G0 X15 Z5
M5
M11
M30
";

/// The three sample programs as read on `citizen_like(3)` (the reader's checks of them are
/// tests/lathe_reader_blocks.rs's).
pub fn sample_programs() -> Vec<Vec<crate::block::Statement>> {
    let desc = citizen_like(3);
    [SYSTEM1, SYSTEM2, SYSTEM3]
        .iter()
        .enumerate()
        .map(|(ch, text)| program(&desc, ch, text).unwrap_or_default())
        .collect()
}

/// The Citizen's programs (`programs/citizen/system{1,2,3}.ngc`, embedded as
/// `store::lathe::CITIZEN_PROGRAMS`) read on `desc`, one per channel.
pub fn citizen_programs(desc: &LatheDesc) -> Result<Vec<Vec<crate::block::Statement>>, String> {
    crate::store::lathe::CITIZEN_PROGRAMS
        .iter()
        .enumerate()
        .map(|(ch, (name, text))| program(desc, ch, text).map_err(|e| format!("{name} {e}")))
        .collect()
}

/// The kernel running `programs` on `desc` to `target` parts (`LatheDesc::kernel_channels`),
/// every tool at `at` ([X, Z] pulses) or, if None, at its home (`gcode::home`); not started.
pub fn kernel(
    desc: &LatheDesc,
    programs: Vec<Vec<crate::block::Statement>>,
    target: u32,
    at: Option<[i64; 2]>,
) -> Result<crate::pulse_core::Kernel, String> {
    let (chans, flow) = desc.kernel_channels(programs)?;
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
        sample_programs(),
        target,
        Some(pt(20.0, 5.0)),
    )
}
