//! `novanc edit` (docs/stores.md "novanc edit"): batch editing of a file with the editor's
//! command lines. The pointer starts at 0; the command lines run in order; `Y` output goes to
//! stdout. With `--write` the file is written (through a symlink, keeping hard links), and only
//! if every command line succeeded. The file is locked from before it is read until after it
//! is written, so that several `novanc edit --write` of one file take turns.

use super::args::{Args, Opt};
use crate::store::fsutil::lock_file;
use novanc_editor::{Buffer, ExecOptions};
use std::io::Write;
use std::path::Path;

const HELP: &str = "\
usage: novanc edit FILE -c 'CMDLINE' [-c 'CMDLINE' ..] [--write]

Applies editor command lines (docs/editor.md) to the text of FILE, in order, with the pointer
starting at 0. Commands: nL (line), mM (move), nK (kill lines), nD (delete characters),
Itext (insert), Stext (search), Cold$new (substitute), nY (display). In text arguments
'*' is the end of block (a newline) and '$' ends the argument.

  -c CMDLINE   a command line; repeat for several, run in order
  --write      write the result to FILE: atomically (temporary file, fsync, rename), or,
               if FILE has other hard links, in place after the whole result is saved
               beside it; a symlink is followed. FILE is locked from before it is read
               until after it is written: several editors of one file take turns
  -h, --help   this help

Y output goes to stdout. If a command line fails, its message goes to stderr as
'novanc edit: command line N: command M 'X': reason', the file is left unchanged
and the exit code is 1. Usage errors exit 2.
";

/// Runs `novanc edit`; returns the exit code.
pub fn main(argv: &[String]) -> i32 {
    let opts = [
        Opt::value("-c"),
        Opt::flag("--write"),
        Opt::flag("-h"),
        Opt::flag("--help"),
    ];
    let args = match Args::parse(argv, &opts) {
        Ok(a) => a,
        Err(e) => return super::usage_error(&format!("edit: {e}")),
    };
    if args.flag("-h") || args.flag("--help") {
        print!("{HELP}");
        return 0;
    }
    let file = match args.positional.as_slice() {
        [f] => f.as_str(),
        [] => return super::usage_error("edit: no FILE given (see --help)"),
        _ => return super::usage_error("edit: give exactly one FILE (see --help)"),
    };
    let fail = |msg: String| {
        let _ = writeln!(std::io::stderr(), "novanc edit: {msg}");
        1
    };
    // The lock is held from before the file is read until after it is written (dropped at
    // the end of this function), so two editors of one file never both read the old text.
    let locked = match lock_file(Path::new(file)) {
        Ok(l) => l,
        Err(e) => return fail(format!("cannot read {file}: {e}")),
    };
    match locked.settle() {
        Ok(None) => {}
        Ok(Some(note)) => {
            let _ = writeln!(std::io::stderr(), "novanc edit: warning: {note}");
        }
        Err(e) => {
            let msg = format!(
                "cannot finish the rewrite in place of {file} that an earlier 'novanc edit --write' was killed in: {e}"
            );
            if args.flag("--write") {
                return fail(format!("{msg} (nothing was written)"));
            }
            let _ = writeln!(std::io::stderr(), "novanc edit: warning: {msg}");
        }
    }
    let bytes = match locked.read() {
        Ok(b) => b,
        Err(e) => return fail(format!("cannot read {file}: {e}")),
    };
    let text = match crate::input_text::decode(&bytes) {
        Ok(t) => t.to_string(),
        Err(e) => return fail(format!("{file}:{e}")),
    };
    let mut buf = Buffer::from_text(&text);
    let exec = ExecOptions::default();
    let mut out = std::io::stdout().lock();
    for (i, line) in args.values("-c").iter().enumerate() {
        match buf.execute(line, &exec) {
            Ok(o) => {
                if out.write_all(o.y_output.as_bytes()).is_err() {
                    return fail("cannot write to stdout".to_string());
                }
            }
            Err(e) => {
                let _ = out.flush();
                return fail(format!("command line {}: {e}", i + 1));
            }
        }
    }
    let _ = out.flush();
    if args.flag("--write") {
        if let Err(e) = locked.write(buf.text().as_bytes()) {
            let note = match e.torn {
                None => " (the file is unchanged)",
                Some(_) => "",
            };
            return fail(format!("cannot write {file}: {e}{note}"));
        }
    }
    0
}
