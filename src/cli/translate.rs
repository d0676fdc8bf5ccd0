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
                                [--optional-stop] [--subroutines DIR]...
                                [--machine FILE] [--dialect fanuc|linuxcnc]
       novanc translate [PROG] --state DIR [--block-delete] [--optional-stop]
       novanc translate PROG --machine citizen|LATHE [--channel N] [--dialect D]
                                [--block-delete] [--optional-stop]

Translates the part program PROG into machine instruction blocks and prints them, one ISO
6983 line per block, in absolute millimetres. PROG is in the source language
(docs/language.md), or in ISO G-code (docs/gcode.md) when its name ends in .ngc, .nc, .iso,
.tap, .gcode or .cnc or its first line is % or O and a number. The output is a preamble line
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
  --subroutines DIR   G-code: a folder where 'o<name> call' finds name.ngc, after the
                      program's own folder (repeatable: searched in order)
  --dialect D         G-code dialect: linuxcnc (the default, or the machine's) or fanuc
                      (Custom Macro B; docs/gcode.md \"Fanuc dialect\")
  --machine FILE      a machining centre's description (docs/lathe.md \"Machine
                      description\"): its travel, and its M6 remap (docs/gcode.md)
  -h, --help          this help

On a lathe (--machine citizen or a lathe's description), PROG is read as channel N's program
(--channel, default 1; docs/lathe-gcode.md) and its blocks printed after the preamble
'G21 G90 G18 G8 G94 G40 G80': X is the radius (G8) of the tool post's imaginary tip with the
tool's offsets and the nose-radius compensation applied, Z as the machine has it, starting at
the channel's reference position (the top of both travels); a thread pass is 'G33 Z K', K its
lead along its longest axis; the meeting codes print as 'M101 P12' (the channels that meet),
the chuck as M10 and M11. The part counter reads as at the start of a batch of 5. With
--state DIR, the lathe console's tools as revised at OFS and its parameters and work offsets
(read, never changed), as `novanc run --state` takes them.

Errors go to stderr as PROG:LINE:COL: message (or FILE:LINE: message for a bad tool tape or
T-code table), with exit code 1; nothing is printed on stdout then.
";

const OPTS: [Opt; 8] = [
    Opt::value("--tools"),
    Opt::value("--subroutines"),
    Opt::value("--magazine"),
    Opt::value("--state"),
    Opt::flag("--block-delete"),
    Opt::flag("--optional-stop"),
    Opt::flag("--help"),
    Opt::flag("-h"),
];

/// What a command works on: the program's name (errors are reported under it), its text, the
/// tool data, the work offsets (zero without `--state`) and the console's persistent G-code
/// parameters (G92, the system in force, G28/G30 homes, rotations: none without `--state`).
pub type Program = (String, String, Magazine, WorkOffsets, Vec<(usize, f64)>);

/// The program to work on and the tool data, from the files given or from a console's memory
/// (`--state DIR`, whose work offsets a G-code program uses). A program taken from the memory
/// is read in the dialect it was stored in, as START reads it: `settings.dialect` becomes that
/// dialect; a file, or a program stored without one, keeps the command line's (or the
/// description's). `Err` is the exit code after a message.
pub fn program_and_tools(
    args: &Args,
    settings: &mut MachineSettings,
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
        return Ok((prog, source, magazine, WorkOffsets::default(), Vec::new()));
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
        if let Some(&d) = view.dialects.get(n) {
            settings.dialect = d;
        }
        return Ok((
            n.clone(),
            text.clone(),
            view.magazine,
            view.offsets,
            view.params,
        ));
    }
    if std::path::Path::new(&name).is_file() {
        let source = read(&name).map_err(|e| fail(&e))?;
        return Ok((name, source, view.magazine, view.offsets, view.params));
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
    let mut out = Vec::new();
    match print_iso(
        name,
        source,
        magazine,
        settings,
        switches,
        WorkOffsets::default(),
        &[],
        &[],
        usize::MAX,
        &mut out,
    ) {
        Err(PrintError::Program(e)) => Err(e),
        // Writing to a Vec does not fail, and the listing is ASCII.
        _ => Ok(String::from_utf8_lossy(&out).into_owned()),
    }
}

/// The most bytes of a listing `novanc translate` holds before printing it. A longer listing is
/// translated twice: once to the end to find any error (nothing is printed then), once to
/// print it as it is made. So the memory a program takes stays bounded however many blocks
/// its repeats make (docs/limits.md).
pub const HOLD_BYTES: usize = 32 << 20;

/// What [`HOLD_BYTES`] counts a block's line as, before it is printed: more than any line
/// takes but one with a number of hundreds of digits.
const BYTES_PER_LINE: usize = 128;

/// Why [`print_iso`] printed nothing, or stopped.
#[derive(Debug)]
pub enum PrintError {
    /// The program is refused: nothing was printed.
    Program(TranslateError),
    /// Writing the listing failed.
    Write(std::io::Error),
}

/// Prints the listing of `source` to `out`, as `novanc translate` does, or refuses it with its
/// first error having printed nothing. A listing of up to `hold` bytes is held and written at
/// once; a longer one is translated again and written as it is made ([`HOLD_BYTES`]).
#[allow(clippy::too_many_arguments)]
pub fn print_iso(
    name: &str,
    source: &str,
    magazine: Magazine,
    settings: &MachineSettings,
    switches: crate::gcode::Switches,
    offsets: WorkOffsets,
    params: &[(usize, f64)],
    subroutines: &[std::path::PathBuf],
    hold: usize,
    out: &mut dyn Write,
) -> Result<(), PrintError> {
    let run = Listing {
        name,
        source,
        magazine,
        settings,
        switches,
        offsets,
        params,
        subroutines: subroutine_path(name, subroutines),
    };
    if let Some(text) = run.held(hold).map_err(PrintError::Program)? {
        return out.write_all(&text).map_err(PrintError::Write);
    }
    // Too long to hold, and without an error: made again, and written a piece at a time.
    let mut buf = Vec::new();
    let mut w = IsoWriter::new(&mut buf);
    let mut statements = run.statements();
    while let Some(r) = statements.next() {
        let st = r.map_err(PrintError::Program)?;
        w.statement(&mut buf, &st, settings);
        statements.recycle(st);
        if buf.len() > 1 << 20 {
            out.write_all(&buf).map_err(PrintError::Write)?;
            buf.clear();
        }
    }
    w.finish(&mut buf);
    out.write_all(&buf).map_err(PrintError::Write)
}

/// A program's statements, each handed back once printed so that the next is made in its
/// memory (no allocation per line).
trait Statements: Iterator<Item = Result<Statement, TranslateError>> {
    fn recycle(&mut self, _st: Statement) {}
}

impl Statements for crate::gcode::GcodeSource {
    fn recycle(&mut self, st: Statement) {
        crate::gcode::GcodeSource::recycle(self, st);
    }
}

impl Statements for Translator {}

/// One program to list, with what it is translated with.
struct Listing<'a> {
    name: &'a str,
    source: &'a str,
    magazine: Magazine,
    settings: &'a MachineSettings,
    switches: crate::gcode::Switches,
    offsets: WorkOffsets,
    params: &'a [(usize, f64)],
    subroutines: Vec<std::path::PathBuf>,
}

/// Where `o<name> call` finds `name.ngc` for the program file `name` (docs/gcode.md
/// "Subroutine files"): the program's own folder, then `extra` (`--subroutines`), in order.
pub fn subroutine_path(name: &str, extra: &[std::path::PathBuf]) -> Vec<std::path::PathBuf> {
    let file = std::path::Path::new(name);
    let own = file.is_file().then(|| match file.parent() {
        Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
        _ => std::path::PathBuf::from("."),
    });
    own.into_iter().chain(extra.iter().cloned()).collect()
}

impl Listing<'_> {
    /// The program's statements, in its language.
    fn statements(&self) -> Box<dyn Statements> {
        if crate::gcode::is_gcode(self.name, self.source) {
            Box::new(
                if self.params.is_empty() {
                    crate::gcode::GcodeSource::new(
                        self.source.into(),
                        self.magazine.clone(),
                        self.settings.clone(),
                        crate::block::MachineState::at([0, 0, 0]),
                        self.offsets,
                        self.switches,
                    )
                } else {
                    // A console's memory: its G92, system in force and homes too.
                    crate::gcode::GcodeSource::with_state(
                        self.source.into(),
                        self.magazine.clone(),
                        self.settings.clone(),
                        crate::block::MachineState::at([0, 0, 0]),
                        crate::gcode::InterpState::with_persistent(self.params, [0.0; 3], None),
                        self.switches,
                    )
                }
                .subroutines(Box::new(crate::gcode::SubPath(self.subroutines.clone())))
                // Only the blocks are printed.
                .without_texts(),
            )
        } else {
            Box::new(Translator::new(
                self.source,
                self.magazine.clone(),
                self.settings.clone(),
                [0, 0, 0],
            ))
        }
    }

    /// The whole listing, translated to the end; `None` (the program without an error) once
    /// it is longer than `hold` bytes, the text then dropped.
    fn held(&self, hold: usize) -> Result<Option<Vec<u8>>, TranslateError> {
        let mut out = Vec::with_capacity(self.source.len().saturating_mul(2).min(hold));
        let mut w = IsoWriter::new(&mut out);
        let mut held = true;
        let mut statements = self.statements();
        while let Some(r) = statements.next() {
            let st = r?;
            if held && out.len() + st.blocks.len() * BYTES_PER_LINE > hold {
                held = false;
                out = Vec::new();
            }
            if held {
                w.statement(&mut out, &st, self.settings);
            }
            statements.recycle(st);
        }
        if !held {
            return Ok(None);
        }
        w.finish(&mut out);
        Ok(Some(out))
    }
}

/// The options of `novanc translate --machine LATHE`.
const LATHE_OPTS: [Opt; 6] = [
    Opt::value("--channel"),
    Opt::value("--state"),
    Opt::flag("--block-delete"),
    Opt::flag("--optional-stop"),
    Opt::flag("--help"),
    Opt::flag("-h"),
];

/// `novanc translate --machine LATHE PROG [--channel N]`: one channel's program as its blocks
/// (docs/cli.md "On a lathe"), read as START reads it in a batch of the run's default
/// target, the tool post starting at the channel's reference position.
fn lathe(mut desc: crate::lathe::desc::LatheDesc, argv: &[String]) -> i32 {
    let args = match Args::parse(argv, &LATHE_OPTS) {
        Ok(a) => a,
        Err(e) => return super::usage_error(&e),
    };
    if args.flag("--help") || args.flag("-h") {
        print!("{HELP}");
        return 0;
    }
    let n = desc.channels.len();
    let ch = match args.value("--channel").map(|v| v.trim().parse::<usize>()) {
        None => 0,
        Some(Ok(c)) if (1..=n).contains(&c) => c - 1,
        Some(_) => {
            return super::usage_error(&format!(
                "translate: --channel: {} has channels 1 to {n}",
                desc.name
            ))
        }
    };
    let [prog] = args.positional.as_slice() else {
        return super::usage_error("translate takes one program (see --help)");
    };
    let source = match read(prog) {
        Ok(s) => s,
        Err(e) => return fail(&e),
    };
    let opts = crate::lathe::gcode::ReadOptions {
        block_delete: args.flag("--block-delete"),
        optional_stop: args.flag("--optional-stop"),
        parts: Some(crate::lathe::gcode::Parts::new(&[], 5)),
    };
    // `--state DIR`: the lathe console's tools and work offsets, as `novanc run` reads them.
    let stored = match super::lathe_stores(&mut desc, args.value("--state")) {
        Ok(s) => s,
        Err(e) => return fail(&e),
    };
    let kept = crate::lathe::gcode::Kept::from_stores(&desc, ch, stored.get(ch).map_or(&[], |v| v));
    let read = crate::lathe::gcode::read_kept(&source, &desc, ch, &opts, None, &kept, None);
    let statements = match read {
        Ok(r) => r.statements,
        Err(e) => return fail(&format!("{prog}:{e}")),
    };
    let Some(settings) = MachineSettings::lathe_channel(&desc, ch) else {
        return fail("novanc: the machine has no channel");
    };
    let mut out = Vec::new();
    let mut w = IsoWriter::lathe(&mut out);
    for st in &statements {
        w.statement(&mut out, st, &settings);
    }
    w.finish(&mut out);
    match std::io::stdout().lock().write_all(&out) {
        Ok(()) => 0,
        Err(_) => 1,
    }
}

/// Runs `novanc translate`; returns the exit code.
pub fn main(argv: &[String]) -> i32 {
    // --machine: a mill's description (its M6 remap, travel, tool change); not a lathe.
    let (settings, argv) = match super::args::take_machine(argv) {
        Err(e) => return super::usage_error(&format!("translate: {e}")),
        Ok((super::args::Machine::Lathe(d), rest)) => return lathe(d, &rest),
        Ok((m, rest)) => (m.settings(), rest),
    };
    let mut settings = settings;
    let argv = argv.as_slice();
    let args = match Args::parse(argv, &OPTS) {
        Ok(a) => a,
        Err(e) => return super::usage_error(&e),
    };
    if args.flag("--help") || args.flag("-h") {
        print!("{HELP}");
        return 0;
    }
    let (prog, source, magazine, offsets, params) =
        match program_and_tools(&args, &mut settings, "translate") {
            Ok(x) => x,
            Err(code) => return code,
        };
    let switches = crate::gcode::Switches {
        block_delete: args.flag("--block-delete"),
        optional_stop: args.flag("--optional-stop"),
    };
    let subs: Vec<std::path::PathBuf> = args
        .values("--subroutines")
        .iter()
        .map(std::path::PathBuf::from)
        .collect();
    let mut stdout = std::io::stdout().lock();
    let r = print_iso(
        &prog,
        &source,
        magazine,
        &settings,
        switches,
        offsets,
        &params,
        &subs,
        HOLD_BYTES,
        &mut stdout,
    );
    match r {
        Ok(()) => 0,
        Err(PrintError::Program(e)) => fail(&format!("{prog}:{e}")),
        Err(PrintError::Write(_)) => 1,
    }
}
