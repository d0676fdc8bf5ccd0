//! The machine-description family of the fuzz command (docs/lathe.md "Machine description"):
//! a description is a file the user writes, so it is bad input like any other. Descriptions
//! of valid and broken lines, and mutations of `machines/*.machine` and the remap machine of
//! the golden tests, are parsed; a refusal names a real line with a short message, and a
//! description that parses gives a machine whose readers take a short program without a
//! panic (a remapped M code, a rotary word, a lathe's channel).

use super::harness::{check_refusal, note, Ctx};
use super::programs::mutate;
use super::rng::Rng;
use novanc::block::MachineState;
use novanc::gcode::{GcodeSource, Switches, WorkOffsets};
use novanc::lathe::desc::{parse, MachineDesc};
use novanc::lathe::gcode::{read_program_in, ReadOptions};
use novanc::tooldata::sample_magazine;

/// Description lines any machine may have.
const COMMON: &[&str] = &[
    "pulse 0.001",
    "pulse 0.0005",
    "dialect fanuc",
    "dialect linuxcnc",
    "common keep",
    "decimal calculator",
    "# a comment",
    "",
];

/// A mill's own lines.
const MILL: &[&str] = &[
    "a rotary wrap rapid 9000 accel 800",
    "b rotary travel -120 120 rapid 9000 accel 800",
    "c rotary travel -720 720 rapid 9000 accel 800",
    "spindle max 6000 accel 6000 encoder 1024",
    "toolchange z -10",
    "workpiece box 0 0 -10 10 10 0",
    "remap M6 modalgroup=6 ngc=toolchange",
    "remap M31 modalgroup=10 ngc=chip",
    "remap M33 ngc=chip",
    "remap M59 modalgroup=10 argspec=Pq ngc=relay",
    "remap M101 argspec=xyz ngc=chip",
];

/// A lathe's own lines (a second channel whole, then lines of the last channel).
const LATHE: &[&str] = &[
    "tick 50",
    "channel TWO\nx travel -2 35 rapid 12000 accel 3000\nz travel -60 60 rapid 15000 accel 3000\nspindle max 4000 accel 4000 encoder 1024",
    "tool 2 radius 0.8 tip 3",
    "tool 99 radius 0 tip 9 offset 1 2",
    "gcode system A",
    "supplier 1",
    "transfer 1 2",
    "unloader 2",
    "loading manual",
    "remap M31 modalgroup=10 ngc=chip",
    "remap M59 modalgroup=10 argspec=Pq ngc=relay",
    "remap M6 ngc=chip",
    "remap M101 ngc=chip",
    "g28 alone all",
    "g28 alone refuse",
    "g04 p point seconds",
    "g04 p point refuse",
    "g04 p point",
    "g28 sometimes",
];

/// Description lines that are wrong wherever they stand.
const BROKEN: &[&str] = &[
    "machine",
    "kind drill",
    "pulse 0",
    "pulse -1",
    "pulse 1e308",
    "tick 0",
    "x travel 10 0 rapid 12000 accel 1000",
    "z travel -1 1 rapid 0 accel 1",
    "y travel nan 5 rapid 1 accel 1",
    "c rotary travel -720 720 rapid inf accel 800",
    "a rotary",
    "spindle max -5",
    "toolchange z",
    "workpiece box 1 2 3",
    "remap M31 argspec=@ ngc=chip",
    "remap M3 ngc=x",
    "remap M999 ngc=x",
    "remap M31 modalgroup=10 ngc=../etc",
    "remap",
    "dialect klingon",
    "channel",
    "tool 0 radius -1 tip 12",
    "transfer 2 9",
];

/// One case: a description of random lines, or a mutation of a real one, parsed; what parses
/// reads a short program.
pub fn description_case(rng: &mut Rng, ctx: &Ctx) -> Result<(), String> {
    let text = if ctx.descriptions.is_empty() || rng.chance(0.4) {
        // A machine that parses, most of the time, then lines whole and broken.
        let mut s = String::new();
        if rng.chance(0.8) {
            s.push_str("machine fuzz\n");
        }
        let mill = rng.chance(0.6);
        if s.is_empty() || rng.chance(0.9) {
            s.push_str(if mill {
                "kind mill\nx travel 0 1000 rapid 12000 accel 1000\n\
                 y travel 0 800 rapid 12000 accel 1000\nz travel -600 0 rapid 12000 accel 1000\n"
            } else {
                "kind lathe\nchannel ONE\nx travel -2 35 rapid 12000 accel 3000\n\
                 z travel -60 60 rapid 15000 accel 3000\n\
                 spindle max 6000 accel 6000 encoder 1024\ntool 1 radius 0.4 tip 3\n"
            });
        }
        for _ in 0..rng.range(0, 8) {
            let own = if mill { MILL } else { LATHE };
            let list = match rng.below(10) {
                0 => BROKEN,
                1..=3 => COMMON,
                _ => own,
            };
            s.push_str(rng.pick::<&str>(list));
            s.push('\n');
        }
        s
    } else {
        let base = rng.pick(&ctx.descriptions).clone();
        let other = [COMMON, MILL, LATHE, BROKEN].concat().join("\n");
        mutate(rng, &base, &other)
    };
    note("machine description", &text);
    let lines = text.split_inclusive('\n').count() as u32 + 1;
    match parse(&text) {
        Err(e) => {
            // `N: reason`, N a line of the text.
            let (n, why) = e
                .split_once(": ")
                .ok_or_else(|| format!("a refusal without its line: {e}"))?;
            let n: u32 = n
                .parse()
                .map_err(|_| format!("a refusal without its line: {e}"))?;
            if n == 0 || n > lines || why.is_empty() || e.len() > 400 {
                return Err(format!("refusal at line {n} of {lines}: {e}"));
            }
        }
        Ok(MachineDesc::Mill(s)) => {
            if !(s.pulse_mm > 0.0 && s.pulse_mm.is_finite()) {
                return Err(format!("a mill with pulse {}", s.pulse_mm));
            }
            for a in s.axis_list() {
                let (lo, hi) = (s.travel_min_mm[a], s.travel_max_mm[a]);
                if lo.is_nan() || hi.is_nan() || lo > hi {
                    return Err(format!("axis {a}: travel {:?}", s.travel_min_mm));
                }
            }
            let src =
                "G21 G90 G54\nM31 G0 X1 Y1\nM59 P2 Q3\nM101 X1 Y2 Z-3\nA10 B-5 C20\nT2 M6\nM2\n";
            let g = GcodeSource::new(
                src.into(),
                sample_magazine(),
                s,
                MachineState::at([0, 0, 0]),
                WorkOffsets::default(),
                Switches::default(),
            )
            .line_limit(10_000);
            for r in g {
                if let Err(e) = r {
                    check_refusal(&e, 8)?;
                    break;
                }
            }
        }
        Ok(MachineDesc::Lathe(d)) => {
            if d.channels.is_empty() {
                return Err("a lathe without a channel".into());
            }
            // Remapped codes (their subroutines in the program), a bare G28 and G75's
            // one-block form, on every channel.
            let src = "o<chip> sub\nG0 U1\no<chip> endsub\no<relay> sub\nG0 W[#<p>]\no<relay> endsub\n\
                       G18 G21 G90\nG0 X10 Z5\nM31 G1 Z-5 F0.1\nM59 P2 Q3\nG28\nG0 X10 Z0\nG75 X0 I1. F0.05\nM30\n";
            for ch in 0..d.channels.len() {
                if let Err(e) = read_program_in(src, &d, ch, &ReadOptions::default(), None) {
                    check_refusal(&e, 15)?;
                }
            }
        }
    }
    Ok(())
}
