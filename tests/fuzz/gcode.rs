//! The G-code family of the fuzz command (docs/gcode.md "Errors", "Limits"): programs made of
//! valid and broken fragments, and mutations of `programs/*.ngc`, read and expanded into machine
//! blocks. Every line either reads or is refused with `LINE:COL: reason` at a real place, with
//! a short message, and nothing more comes after a refusal.

use super::harness::{check_refusal, note, Ctx};
use super::programs::mutate;
use super::rng::Rng;
use novanc::block::MachineState;
use novanc::gcode::{GcodeSource, Switches, WorkOffsets};
use novanc::settings::{AxisKind, Dialect, MachineSettings, Remap};
use novanc::tooldata::sample_magazine;

#[path = "../common/gcode_fragments.rs"]
mod gcode_fragments;
use gcode_fragments::{extreme_program, FANUC_FRAGMENTS, FRAGMENTS};

/// A program of up to 40 lines of random fragments, sometimes with a subprogram after M30;
/// with `fanuc`, Custom Macro B fragments among them too.
fn by_grammar(rng: &mut Rng, fanuc: bool) -> String {
    let mut s = String::new();
    for _ in 0..rng.range(1, 40) {
        for _ in 0..rng.range(0, 5) {
            if fanuc && rng.chance(0.3) {
                s.push_str(rng.pick::<&str>(FANUC_FRAGMENTS));
            } else {
                s.push_str(rng.pick::<&str>(FRAGMENTS));
            }
            s.push(' ');
        }
        s.push('\n');
    }
    if rng.chance(0.5) {
        s.push_str("M30\nO100\nG91 G1 X1 F100\nM99\n");
    }
    s
}

/// One case: a generated or mutated G-code program, read to its end or its first error.
pub fn gcode_case(rng: &mut Rng, ctx: &Ctx) -> Result<(), String> {
    // One case in four reads in the Fanuc dialect (docs/gcode.md "Fanuc dialect").
    let dialect = if rng.chance(0.25) {
        Dialect::Fanuc
    } else {
        Dialect::LinuxCnc
    };
    let fanuc = dialect == Dialect::Fanuc;
    let src = if ctx.gcode.is_empty() || rng.chance(0.4) {
        by_grammar(rng, fanuc)
    } else {
        let base = rng.pick(&ctx.gcode).clone();
        let other = if rng.chance(0.5) {
            by_grammar(rng, fanuc)
        } else {
            rng.pick(&ctx.gcode).clone()
        };
        mutate(rng, &base, &other)
    };
    read_checked(rng, &src, dialect)
}

/// One case of issue 20 (docs/limits.md): a program whose values sit at every edge (309
/// digits, 1e308, denormals, negative zero, R 1e17, Q 1e-12, L 9999 and past it, dwells and
/// feeds), read as the G-code family reads its programs.
pub fn extremes_case(rng: &mut Rng, _ctx: &Ctx) -> Result<(), String> {
    let src = extreme_program(|n| rng.below(n));
    read_checked(rng, &src, Dialect::LinuxCnc)
}

/// Reads `src` to its end or its first error: statements at real lines, a refusal at a real
/// place with a short message, nothing after it.
fn read_checked(rng: &mut Rng, src: &str, dialect: Dialect) -> Result<(), String> {
    let mut settings = MachineSettings {
        dialect,
        ..MachineSettings::default()
    };
    // One case in three on a machine with rotary axes (docs/gcode.md "Rotary axes"): each of
    // A, B, C present or not, wrapped or within ±720°.
    if rng.chance(0.33) {
        for a in 3..6 {
            if rng.chance(0.6) {
                settings.axis_kinds[a] = AxisKind::Rotary {
                    wrap: rng.chance(0.5),
                };
                settings.travel_min_mm[a] = -720.0;
                settings.travel_max_mm[a] = 720.0;
            }
        }
    }
    // One case in four on a machine whose description remaps M31 and M101 (docs/gcode.md
    // "Remapping M6 and other M codes"), their subroutine defined first or missing.
    let with_sub;
    let src = if rng.chance(0.25) {
        settings.remap_m = vec![
            Remap::new(31, "chip"),
            Remap {
                argspec: "Pq".into(),
                ..Remap::new(101, "chip")
            },
        ];
        with_sub = format!(
            "{}{src}",
            if rng.chance(0.7) {
                "o<chip> sub\nM64 P1 G0 X#<_x>\no<chip> endsub\n"
            } else {
                ""
            }
        );
        with_sub.as_str()
    } else {
        src
    };
    note(
        &format!(
            "G-code program ({dialect:?}, axes {}, remaps {:?})",
            settings.rotary_mask(),
            settings.remap_m
        ),
        src,
    );
    let lines = src.split_inclusive('\n').count() as u32 + 1;
    let g = GcodeSource::new(
        src.into(),
        sample_magazine(),
        settings,
        MachineState::at([500_000, 400_000, -300_000]),
        WorkOffsets::default(),
        Switches {
            block_delete: rng.chance(0.5),
            optional_stop: rng.chance(0.5),
        },
    )
    .line_limit(1_000_000);
    let mut refused = None;
    for r in g {
        if let Some(e) = &refused {
            return Err(format!("a statement came after the refusal {e}"));
        }
        match r {
            Ok(st) if st.line > lines => {
                return Err(format!("statement at line {} of {lines}", st.line));
            }
            Ok(_) => {}
            Err(e) => {
                check_refusal(&e, lines)?;
                refused = Some(e.to_string());
            }
        }
    }
    Ok(())
}
