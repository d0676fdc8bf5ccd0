//! The lathe family of the fuzz command (docs/lathe-gcode.md): lathe programs of valid and
//! broken fragments, in both dialects and both G code systems, and mutations of the Citizen's
//! programs and the lathe golden programs (`tests/golden/lathe_rs274`), read by the lathe
//! reader. A program reads or is refused at a real place with a short message; every block
//! it makes ends inside the channel's travel (no bad input moves an axis past it), and every
//! thread block has a finite lead of at least a pulse.

use super::harness::{check_refusal, note, Ctx};
use super::programs::mutate;
use super::rng::Rng;
use novanc::block::Motion;
use novanc::lathe::desc::LatheDesc;
use novanc::lathe::gcode::{read_program_in, Parts, ReadOptions};
use novanc::settings::Dialect;

/// Lathe words, whole and broken: moves, arcs, threads, compensation, the cycles of both
/// forms, G53, G92 and its cancels, G28, tools, the spindle, waits, parameters.
const LATHE_FRAGMENTS: &[&str] = &[
    "G0 X20 Z5",
    "G1 Z-10 F0.1",
    "G1 X30 Z-15 F100",
    "G2 X40 Z-20 R5",
    "G3 X20 Z-5 I0 K-5",
    "G33 Z-20 K1.5",
    "G33 X22 Z-30 K2",
    "G32 Z-12. F1.5",
    "G41",
    "G42",
    "G40",
    "G41 G1 X10 Z2",
    "G42 G0 X14 Z1",
    // Arcs as entry moves, and I K arcs LinuxCNC reads as spirals (stop 51).
    "G41 G3 X24 Z1 R5",
    "G42 G2 X10 Z2 I-4 K-2",
    "G2 X100.08 Z0 I0 K-100",
    "G3 X0 Z-120.05 I-100.08 K0",
    "G42.1 D1.6 L2",
    "G41.1 D0.8 L3",
    "G42.1 L12",
    "G7",
    "G8",
    "G18",
    "G20",
    "G21",
    "G90",
    "G91",
    "G94",
    "G95",
    "G96 S150 D3000",
    "G97 S800",
    "M3 S1000",
    "M4 S500",
    "M5",
    "M8",
    "M9",
    "M10",
    "M11",
    "M100 P12",
    "M101",
    "T0101",
    "T0303",
    "T0100",
    "T1 M6 G43",
    "T2 M6 G43 H3",
    "T0",
    "G43 H8",
    "G49",
    "G53 G0 X0 Z0",
    "G53 G1 X100 F200",
    "G53 U1",
    "G92 Z0",
    "G92 X20 Z2",
    "G92.1",
    "G92.2",
    "G92.3",
    "G92 W1",
    "G28 U0 W0",
    "G28",
    "G4 P0.5",
    "G04 P3.",
    "G04 P3000",
    "M0",
    "M1",
    "M2",
    "M30",
    "G76 P1.5 Z-20 I-0.5 J0.2 K0.6 H1 Q29.5",
    "G76 P1 Z-10 I-1 J0.1 K0.5 E1 L3",
    "G76 P2 Z-15 I-1 J0.3 K2 E1.5 L2 Q30",
    "G76 P1 Z-8 I1 J0.1 K0.5 E9 L1",
    "G76 E-1 L5",
    "G71 U1 R0.5",
    "G71 P10 Q20 U0.4 W0.1 F100",
    "G71 P10 Q20 U0.4 W0.1 D1.5 F100",
    "G72 P10 Q20 D1500 F100",
    "G73 U3. W1. R3",
    "G73 P10 Q20 U0.4 W0.1 F100",
    "G73 U1 R0",
    "G71 U1 R0.5 D2",
    "N10 G0 X20",
    "N20 G1 X40 Z-20",
    "G70 P10 Q20",
    "G72 W1 R0.5",
    "G74 R1",
    "G74 Z-10 Q2000 F0.1",
    "G75 R1",
    "G75 X0 I1. F0.05",
    "G74 Z-5 K1. D0.2 F0.1",
    "G76 X10 Z-10 K1. D0.3 A60 F1.",
    "M23",
    "M24",
    "M64 P2",
    "M65 P70",
    "G10 L2 P2 X4 Z-150",
    "G10 L20 P1 Z0",
    "G10 L2 P0 X1",
    "G10 L2 P9 Z1",
    "G10 P1 X1 Z1",
    "G55",
    "G59 G0 X20 Z2",
    "G59.1",
    "#5242 = #5242 + 1",
    "#5223 = 4",
    "#5220",
    "#4014",
    "#<_coord_system>",
    ":0100",
    "%O1200",
    "G33 Z-20 F1.5",
    "M31",
    "M59 P2",
    "o<chip> sub",
    "o<chip> endsub",
    "o<chip> call",
    "G83 Z-10 Q2000 F0.1",
    "G80",
    "G50 S3000",
    "G50 X40 Z10",
    "G99 F0.2",
    "G98 F100",
    "#1 = 5",
    "X[#1 * 2]",
    "#5411",
    "#<_x>",
    "o1 if [1 GT 0]",
    "o1 endif",
    "(msg, hi)",
    "X",
    "Z",
    "U-2",
    "W-1",
    "R",
    "F",
    "Q",
    "E",
    "L",
    "-",
    ".",
    "1e9",
    "[",
    "]",
    "(",
    "/",
    "%",
    "*",
    "\u{e9}",
];

/// A program of up to 30 lines of random lathe fragments.
fn by_grammar(rng: &mut Rng) -> String {
    let mut s = String::new();
    for _ in 0..rng.range(1, 30) {
        for _ in 0..rng.range(0, 4) {
            s.push_str(rng.pick::<&str>(LATHE_FRAGMENTS));
            s.push(' ');
        }
        s.push('\n');
    }
    if rng.chance(0.5) {
        s.push_str("M30\n");
    }
    s
}

/// The Citizen with room to turn (its channel 1; system A on one case in four, read in
/// Fanuc's dialect there, as a description allows only then).
fn lathe(system_a: bool, haas: bool) -> LatheDesc {
    let mut d = LatheDesc::citizen();
    for c in &mut d.channels {
        c.axes[0].travel = [-1.0, 100.0];
        c.axes[1].travel = [-200.0, 200.0];
        c.system_a = system_a;
        if haas {
            // A Haas's codes: the chip auger and a relay remapped, G28 alone returns both.
            c.g28_all = Some(true);
            for (code, ngc, argspec) in [(31, "chip", ""), (59, "relay", "Pq")] {
                c.remap_m.push(novanc::settings::Remap {
                    code,
                    ngc: ngc.into(),
                    argspec: argspec.into(),
                });
            }
        }
    }
    d
}

/// One case: a generated or mutated lathe program, read to its end or its first error.
pub fn lathe_case(rng: &mut Rng, ctx: &Ctx) -> Result<(), String> {
    let system_a = rng.chance(0.25);
    let dialect = if system_a || rng.chance(0.3) {
        Dialect::Fanuc
    } else {
        Dialect::LinuxCnc
    };
    let src = if ctx.lathe.is_empty() || rng.chance(0.5) {
        by_grammar(rng)
    } else {
        let base = rng.pick(&ctx.lathe).clone();
        let other = if rng.chance(0.5) {
            by_grammar(rng)
        } else {
            rng.pick(&ctx.lathe).clone()
        };
        mutate(rng, &base, &other)
    };
    // The program's subroutines for the remapped codes, one case in four.
    let haas = rng.chance(0.25);
    let src = if haas {
        format!(
            "o<chip> sub\nG0 U1\no<chip> endsub\no<relay> sub\nG0 W[#<p>]\no<relay> endsub\n{src}"
        )
    } else {
        src
    };
    note(
        &format!("lathe program ({dialect:?}, system A {system_a}, Haas codes {haas})"),
        &src,
    );
    let desc = lathe(system_a, haas);
    let opts = ReadOptions {
        block_delete: rng.chance(0.5),
        optional_stop: rng.chance(0.5),
        parts: Some(Parts::new(&[], 5)),
    };
    let lines = src.split_inclusive('\n').count() as u32 + 1;
    match read_program_in(&src, &desc, 0, &opts, Some(dialect)) {
        Err(e) => check_refusal(&e, lines),
        Ok(statements) => {
            let c = &desc.channels[0];
            let pulses = |mm: f64| desc.pulses(mm);
            let (x, z) = (c.axes[0].travel, c.axes[1].travel);
            for st in &statements {
                if st.line < 1 || st.line > lines {
                    return Err(format!("statement at line {} of {lines}", st.line));
                }
                for b in &st.blocks {
                    let (bx, bz) = (b.end[0], b.end[2]);
                    if bx < pulses(x[0])
                        || bx > pulses(x[1])
                        || bz < pulses(z[0])
                        || bz > pulses(z[1])
                    {
                        return Err(format!(
                            "line {}: a block ends outside the travel: X {bx} Z {bz} pulses",
                            st.line
                        ));
                    }
                    if let Some(lead) = b.thread {
                        if b.motion != Motion::Linear
                            || !(lead.is_finite() && lead >= desc.pulse_mm)
                        {
                            return Err(format!("line {}: a thread block of lead {lead}", st.line));
                        }
                    }
                }
            }
            Ok(())
        }
    }
}
