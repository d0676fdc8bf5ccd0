//! `novanc tape` (docs/tape.md): `read` decodes a tape image (or a plain text file) to text on
//! stdout; `punch` writes a program or a tool tape as a tape image in ISO or EIA code.

use super::args::{Args, Opt};
use super::{fail, usage_error};
use crate::tape::{self, Code, PunchOptions, ReadOptions};
use std::io::Write;

const HELP: &str = "\
usage: novanc tape read IMAGE [--block-parity] [--holes]
       novanc tape punch FILE --code iso|eia [--leader N] [--label TEXT] -o IMAGE

read   decodes an 8-channel tape image (one byte a frame, channel n = bit n-1) and prints its
       text on stdout, one line per block; the code (ISO or EIA), the label and the counts go
       to stderr. The code is recognized at the first end of block; every frame's parity is
       checked. A plain text file is printed as it is. An error (parity, a character not in
       the code, a missing end of block) names the frame, the block, the character and the
       frame's holes, prints no text, and exits 1.
         --block-parity   also check that every block has an even number of characters
         --holes          print every frame as a row of holes with its meaning instead

punch  writes FILE (a part program or a tool tape) as a tape image: leader, the label,
       the rewind stop (ISO %, EIA ER), one block per line, the rewind stop, trailer.
         --code iso|eia   the code (required)
         --leader N       blank frames before and after the data, 1-10000 (default 100)
         --label TEXT     a label before the rewind stop
         -o IMAGE         the image to write (required)

The codes and the image format: docs/tape.md.
";

/// Runs `novanc tape`; returns the exit code.
pub fn main(argv: &[String]) -> i32 {
    match argv.first().map(|s| s.as_str()) {
        Some("read") => read(&argv[1..]),
        Some("punch") => punch(&argv[1..]),
        Some("-h") | Some("--help") | None => {
            print!("{HELP}");
            if argv.is_empty() {
                2
            } else {
                0
            }
        }
        Some(other) => usage_error(&format!(
            "tape: unknown action '{other}': read or punch (see novanc tape --help)"
        )),
    }
}

const READ_OPTS: [Opt; 4] = [
    Opt::flag("--block-parity"),
    Opt::flag("--holes"),
    Opt::flag("--help"),
    Opt::flag("-h"),
];

/// `novanc tape read IMAGE`.
fn read(argv: &[String]) -> i32 {
    let args = match Args::parse(argv, &READ_OPTS) {
        Ok(a) => a,
        Err(e) => return usage_error(&format!("tape read: {e}")),
    };
    if args.flag("--help") || args.flag("-h") {
        print!("{HELP}");
        return 0;
    }
    let path = match args.positional.as_slice() {
        [p] => p,
        [] => return usage_error("tape read: which image? (novanc tape read IMAGE)"),
        _ => return usage_error("tape read takes one image (see novanc tape --help)"),
    };
    let image = match std::fs::read(path) {
        Ok(b) => b,
        Err(e) => return fail(&format!("novanc: cannot read {path}: {e}")),
    };
    let opts = ReadOptions {
        block_parity: args.flag("--block-parity"),
    };
    let result = tape::read_image(&image, opts);
    if args.flag("--holes") {
        let code = match &result {
            Ok(t) => t.code,
            Err(e) => e.code,
        };
        let Some(code) = code else {
            return fail(&format!(
                "novanc: {path}: no code recognized, nothing to draw"
            ));
        };
        let drawing = tape::draw(&image, code);
        let _ = std::io::stdout().lock().write_all(drawing.as_bytes());
        return match result {
            Ok(_) => 0,
            Err(e) => fail(&format!("{path}: {e}")),
        };
    }
    let t = match result {
        Ok(t) => t,
        Err(e) => return fail(&format!("{path}: {e}")),
    };
    let mut out = std::io::stdout().lock();
    if let Err(e) = out.write_all(t.text.as_bytes()).and_then(|()| out.flush()) {
        return fail(&format!("novanc: writing the text: {e}"));
    }
    let label = if t.label.is_empty() {
        String::new()
    } else {
        format!(", label '{}'", t.label)
    };
    let what = match t.code {
        Some(c) => format!("{} code{label}", c.name()),
        None => "a plain text file".to_string(),
    };
    let _ = writeln!(
        std::io::stderr(),
        "{path}: {what}, {} blocks, {} frames",
        t.blocks,
        t.frames
    );
    0
}

const PUNCH_OPTS: [Opt; 6] = [
    Opt::value("--code"),
    Opt::value("--leader"),
    Opt::value("--label"),
    Opt::value("-o"),
    Opt::flag("--help"),
    Opt::flag("-h"),
];

/// `novanc tape punch FILE --code iso|eia [--leader N] [--label TEXT] -o IMAGE`.
fn punch(argv: &[String]) -> i32 {
    let args = match Args::parse(argv, &PUNCH_OPTS) {
        Ok(a) => a,
        Err(e) => return usage_error(&format!("tape punch: {e}")),
    };
    if args.flag("--help") || args.flag("-h") {
        print!("{HELP}");
        return 0;
    }
    let file = match args.positional.as_slice() {
        [f] => f,
        [] => return usage_error("tape punch: which file? (see novanc tape --help)"),
        _ => return usage_error("tape punch takes one file (see novanc tape --help)"),
    };
    let code = match args.value("--code") {
        Some(c) => match Code::from_name(c) {
            Some(code) => code,
            None => {
                return usage_error(&format!(
                    "tape punch: --code '{c}': the codes are iso and eia"
                ))
            }
        },
        None => return usage_error("tape punch: which code? --code iso or --code eia"),
    };
    let Some(out_path) = args.value("-o") else {
        return usage_error("tape punch: where to? -o IMAGE");
    };
    let leader = match args.value("--leader") {
        None => tape::DEFAULT_LEADER,
        Some(v) => match v.trim().parse::<usize>() {
            Ok(n) if (1..=tape::MAX_LEADER).contains(&n) => n,
            _ => {
                return usage_error(&format!(
                    "tape punch: --leader '{v}' is not a number of frames from 1 to {}",
                    tape::MAX_LEADER
                ))
            }
        },
    };
    let text = match std::fs::read_to_string(file) {
        Ok(t) => t,
        Err(e) => return fail(&format!("novanc: cannot read {file}: {e}")),
    };
    let opts = PunchOptions {
        code,
        leader,
        label: args.value("--label").map(str::to_string),
    };
    let image = match tape::punch(&text, &opts) {
        Ok(i) => i,
        Err(e) => return fail(&format!("{file}:{e}")),
    };
    if let Err(e) = crate::store::fsutil::write_output(std::path::Path::new(out_path), &image) {
        return fail(&format!("novanc: cannot write {out_path}: {e}"));
    }
    let _ = writeln!(
        std::io::stderr(),
        "{out_path}: {} frames in the {} code ({:.1} m of tape)",
        image.len(),
        code.name(),
        image.len() as f64 * 2.54e-3
    );
    0
}
