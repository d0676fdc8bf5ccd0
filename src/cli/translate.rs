//! `novanc translate` (docs/cli.md): translate a part program and print its blocks as an ISO 6983
//! program on stdout; errors on stderr as `PROG:LINE:COL: message`, exit 1.

use super::args::{Args, Opt};
use super::fail;
use crate::block::{IsoWriter, Statement, TranslateError};
use crate::settings::MachineSettings;
use crate::tooldata::{parse_tape, parse_tcodes, Magazine, SAMPLE_TAPE, SAMPLE_TCODES};
use crate::translator::Translator;
use std::io::Write;

const HELP: &str = "\
usage: novanc translate PROG [--tools TAPE] [--magazine TCODES] [--block-delete]
                                [--optional-stop]

Translates the part program PROG into machine instruction blocks: the source language
(docs/language.md), or ISO G-code (docs/gcode.md) when PROG ends in .ngc, .nc or .iso or its
first line is % or O and a number. It prints the blocks and prints them, one ISO 6983 line per block, in absolute millimetres:
a preamble line 'G21 G90 G17 G94 G40 G49 G80', the blocks 'N.. G.. X Y Z I J F S T M',
and 'M30'. The printed program is G-code for a standard interpreter (Z is the machine
axis: tool-tip Z plus the tool's set length; for G-code, the gauge line: program Z plus
the work offset plus the G43 tool length). Arcs outside the XY plane say G18 or G19. The
machine starts at machine zero with no tool in the spindle; G-code starts with every work
offset at zero.

options:
  --tools TAPE        tool tape (TOOLNO KIND DIAMETER SETLEN EFFLEN SPEED FEED DEPTH per line);
                      default: the sample tape tooldata/tools.tt (embedded)
  --magazine TCODES   T-code table ('Tnn TOOLNO' per line);
                      default: the sample table tooldata/magazine.tc (embedded)
  --block-delete      G-code: skip lines that start with / (the BLOCK DELETE switch)
  --optional-stop     G-code: M01 stops (the OPTIONAL STOP switch)
  -h, --help          this help

Errors go to stderr as PROG:LINE:COL: message (or FILE:LINE: message for a bad tool tape or
T-code table), with exit code 1; nothing is printed on stdout then.
";

const OPTS: [Opt; 6] = [
    Opt::value("--tools"),
    Opt::value("--magazine"),
    Opt::flag("--block-delete"),
    Opt::flag("--optional-stop"),
    Opt::flag("--help"),
    Opt::flag("-h"),
];

fn read(path: &str) -> Result<String, String> {
    std::fs::read_to_string(path).map_err(|e| format!("novanc: cannot read {path}: {e}"))
}

/// Loads the magazine from the given tape and T-code files, or the embedded samples.
pub fn load_magazine(
    tools: Option<&str>,
    tcodes: Option<&str>,
    settings: &MachineSettings,
) -> Result<Magazine, String> {
    let (tape_text, tape_name) = match tools {
        Some(p) => (read(p)?, p.to_string()),
        None => (SAMPLE_TAPE.to_string(), "tooldata/tools.tt".to_string()),
    };
    let (tc_text, tc_name) = match tcodes {
        Some(p) => (read(p)?, p.to_string()),
        None => (
            SAMPLE_TCODES.to_string(),
            "tooldata/magazine.tc".to_string(),
        ),
    };
    let tape = parse_tape(&tape_text, &tape_name).map_err(|e| e.to_string())?;
    let table =
        parse_tcodes(&tc_text, &tc_name, settings.magazine_capacity).map_err(|e| e.to_string())?;
    Ok(Magazine::load(table, &tape))
}

/// Runs `novanc translate`; returns the exit code.
pub fn main(argv: &[String]) -> i32 {
    let args = match Args::parse(argv, &OPTS) {
        Ok(a) => a,
        Err(e) => return super::usage_error(&e),
    };
    if args.flag("--help") || args.flag("-h") {
        print!("{HELP}");
        return 0;
    }
    let prog = match args.positional.as_slice() {
        [p] => p.clone(),
        [] => return super::usage_error("translate: which program? (see --help)"),
        _ => return super::usage_error("translate takes one program (see --help)"),
    };
    let settings = MachineSettings::default();
    let magazine = match load_magazine(args.value("--tools"), args.value("--magazine"), &settings) {
        Ok(m) => m,
        Err(e) => return fail(&e),
    };
    let source = match read(&prog) {
        Ok(s) => s,
        Err(e) => return fail(&e),
    };
    // Statements are printed as they come, into memory: nothing reaches stdout on an error.
    let mut out = String::with_capacity(source.len() * 2);
    let mut w = IsoWriter::new(&mut out);
    let mut print = |r: Result<Statement, TranslateError>| -> Result<(), TranslateError> {
        w.statement(&mut out, &r?, &settings);
        Ok(())
    };
    let result = if crate::gcode::is_gcode(&prog, &source) {
        let switches = crate::gcode::Switches {
            block_delete: args.flag("--block-delete"),
            optional_stop: args.flag("--optional-stop"),
        };
        crate::gcode::GcodeSource::new(
            source.into(),
            magazine,
            settings.clone(),
            crate::block::MachineState::at([0, 0, 0]),
            crate::gcode::WorkOffsets::default(),
            switches,
        )
        .try_for_each(&mut print)
    } else {
        Translator::new(&source, magazine, settings.clone(), [0, 0, 0]).try_for_each(&mut print)
    };
    match result {
        Ok(()) => {
            w.finish(&mut out);
            let mut stdout = std::io::stdout().lock();
            if stdout.write_all(out.as_bytes()).is_err() {
                return 1;
            }
            0
        }
        Err(e) => fail(&format!("{prog}:{e}")),
    }
}
