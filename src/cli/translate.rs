//! `novanc translate` (docs/cli.md): translate a part program and print its blocks as an ISO 6983
//! program on stdout; errors on stderr as `PROG:LINE:COL: message`, exit 1.

use super::args::{Args, Opt};
use super::fail;
use crate::block::{IsoWriter, Statement, TranslateError};
use crate::gcode::WorkOffsets;
use crate::settings::MachineSettings;
use crate::tooldata::{parse_tape, parse_tcodes, Magazine, SAMPLE_TAPE, SAMPLE_TCODES};
use crate::translator::Translator;
use std::io::Write;

const HELP: &str = "\
usage: novanc translate PROG [--tools TAPE] [--magazine TCODES] [--block-delete]
                                [--optional-stop]
       novanc translate [PROG] --state DIR [--block-delete] [--optional-stop]

Translates the part program PROG into machine instruction blocks and prints them, one ISO
6983 line per block, in absolute millimetres. PROG is in the source language
(docs/language.md), or in ISO G-code (docs/gcode.md) when its name ends in .ngc, .nc or .iso
or its first line is % or O and a number. The output is a preamble line
'G21 G90 G17 G94 G40 G49 G80', the blocks 'N.. G.. X Y Z I J K F S T M', and 'M30'. The
printed program is G-code for a standard interpreter (Z is the machine axis: tool-tip Z plus
the tool's set length; for G-code, the gauge line: program Z plus the work offset plus the
G43 tool length). Arcs outside the XY plane say G18 or G19. The machine starts at machine
zero with no tool in the spindle; G-code starts with every work offset at zero.

options:
  --tools TAPE        tool tape (TOOLNO KIND DIAMETER SETLEN EFFLEN SPEED FEED DEPTH per line);
                      default: the sample tape tooldata/tools.tt (embedded)
  --magazine TCODES   T-code table ('Tnn TOOLNO' per line);
                      default: the sample table tooldata/magazine.tc (embedded)
  --state DIR         use a console's memory (read, never changed, even while the console
                      has it open): its tool file and T codes, and PROG names a program in
                      it (else a file); with no PROG, the program selected there
  --block-delete      G-code: skip lines that start with / (the BLOCK DELETE switch)
  --optional-stop     G-code: M01 stops (the OPTIONAL STOP switch)
  -h, --help          this help

Errors go to stderr as PROG:LINE:COL: message (or FILE:LINE: message for a bad tool tape or
T-code table), with exit code 1; nothing is printed on stdout then.
";

const OPTS: [Opt; 7] = [
    Opt::value("--tools"),
    Opt::value("--magazine"),
    Opt::value("--state"),
    Opt::flag("--block-delete"),
    Opt::flag("--optional-stop"),
    Opt::flag("--help"),
    Opt::flag("-h"),
];

/// What a command works on: the program's name (errors are reported under it), its text, the
/// tool data and the work offsets (zero without `--state`).
pub type Program = (String, String, Magazine, WorkOffsets);

/// The program to work on and the tool data, from the files given or from a console's memory
/// (`--state DIR`, whose work offsets a G-code program uses). `Err` is the exit code after a
/// message.
pub fn program_and_tools(
    args: &Args,
    settings: &MachineSettings,
    what: &str,
) -> Result<Program, i32> {
    let prog = match args.positional.as_slice() {
        [p] => Some(p.clone()),
        [] => None,
        _ => {
            return Err(super::usage_error(&format!(
                "{what} takes one program (see --help)"
            )))
        }
    };
    let Some(dir) = args.value("--state") else {
        let Some(prog) = prog else {
            return Err(super::usage_error(&format!(
                "{what}: which program? (see --help)"
            )));
        };
        let magazine = load_magazine(args.value("--tools"), args.value("--magazine"), settings)
            .map_err(|e| fail(&e))?;
        let source = read(&prog).map_err(|e| fail(&e))?;
        return Ok((prog, source, magazine, WorkOffsets::default()));
    };
    if args.value("--tools").is_some() || args.value("--magazine").is_some() {
        return Err(super::usage_error(&format!(
            "{what}: --state uses the console's tool file and T codes; leave out --tools and --magazine"
        )));
    }
    let view =
        crate::store::MemoryView::read(std::path::Path::new(dir), settings.magazine_capacity)
            .map_err(|e| fail(&format!("novanc: {e}")))?;
    for w in &view.warnings {
        eprintln!("novanc: {dir}: {w}");
    }
    let name = prog.unwrap_or_else(|| view.current.clone());
    if let Some((n, text)) = view
        .programs
        .iter()
        .find(|(n, _)| n.eq_ignore_ascii_case(&name))
    {
        return Ok((n.clone(), text.clone(), view.magazine, view.offsets));
    }
    if std::path::Path::new(&name).is_file() {
        let source = read(&name).map_err(|e| fail(&e))?;
        return Ok((name, source, view.magazine, view.offsets));
    }
    let names: Vec<&str> = view.programs.keys().map(|n| n.as_str()).collect();
    Err(fail(&format!(
        "novanc: {name} is neither a program in {dir} ({}) nor a file",
        names.join(", ")
    )))
}

/// Reads a program, tape or table file as PROGRAM READ reads a tape: UTF-8 (a bad byte is named
/// by line, column and byte offset), CR and CR LF as line ends.
pub fn read(path: &str) -> Result<String, String> {
    crate::input_text::read_tape_file(path)
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

/// The printed program of `source` (named `name`, whose extension or first line says its
/// language), or its first error. It is built as text statement by statement, each
/// statement's blocks dropped once printed, so the memory it takes is about that of the text
/// it prints (docs/language.md, *Limits*).
pub fn iso_text(
    name: &str,
    source: &str,
    magazine: Magazine,
    settings: &MachineSettings,
    switches: crate::gcode::Switches,
) -> Result<String, TranslateError> {
    iso_text_at(
        name,
        source,
        magazine,
        settings,
        switches,
        WorkOffsets::default(),
    )
}

/// [`iso_text`] with the work offsets G54..G59 a G-code program starts with.
pub fn iso_text_at(
    name: &str,
    source: &str,
    magazine: Magazine,
    settings: &MachineSettings,
    switches: crate::gcode::Switches,
    offsets: WorkOffsets,
) -> Result<String, TranslateError> {
    let mut out = String::with_capacity(source.len() * 2);
    let mut w = IsoWriter::new(&mut out);
    let mut print = |r: Result<Statement, TranslateError>| -> Result<(), TranslateError> {
        w.statement(&mut out, &r?, settings);
        Ok(())
    };
    if crate::gcode::is_gcode(name, source) {
        crate::gcode::GcodeSource::new(
            source.into(),
            magazine,
            settings.clone(),
            crate::block::MachineState::at([0, 0, 0]),
            offsets,
            switches,
        )
        .try_for_each(&mut print)?;
    } else {
        Translator::new(source, magazine, settings.clone(), [0, 0, 0]).try_for_each(&mut print)?;
    }
    w.finish(&mut out);
    Ok(out)
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
    let settings = MachineSettings::default();
    let (prog, source, magazine, offsets) = match program_and_tools(&args, &settings, "translate") {
        Ok(x) => x,
        Err(code) => return code,
    };
    let switches = crate::gcode::Switches {
        block_delete: args.flag("--block-delete"),
        optional_stop: args.flag("--optional-stop"),
    };
    let out = match iso_text_at(&prog, &source, magazine, &settings, switches, offsets) {
        Ok(t) => t,
        Err(e) => return fail(&format!("{prog}:{e}")),
    };
    let mut stdout = std::io::stdout().lock();
    if stdout.write_all(out.as_bytes()).is_err() {
        return 1;
    }
    0
}
