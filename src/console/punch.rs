//! The punch key at the console (docs/tape.md, "The punch at the console"): in DATA INPUT with
//! the data selector on PROGRAM READ, the typed line names the image the current program is
//! punched to, in the ISO code or, with ` EIA` after the path, the EIA code. The image is
//! written whole or not at all, by the one write path (`store::fsutil::write_output`).

use super::tape::refuse_key;
use super::Console;
use crate::panel_model::{DataMode, OpMode};
use crate::tape::{self, Code, PunchOptions};
use std::path::PathBuf;

/// The punch key (docs/panel.md): in DATA INPUT with the data selector on PROGRAM READ, the
/// typed line names the image to punch the current program to, `PATH` (ISO) or `PATH EIA`
/// (`PATH ISO` also works); the line is used up. The image is written whole or not at all.
pub(super) fn punch_from_entry(c: &mut Console) {
    if refuse_key(c, "punch") {
        return;
    }
    if c.shell.front.op != OpMode::Data || c.data != DataMode::Read {
        c.shell.front.message = format!(
            "punch refused: it punches program memory in DATA INPUT with the data selector on PROGRAM READ (now {} / {})",
            c.shell.front.op.name(),
            c.data.name()
        );
        return;
    }
    if c.running() {
        c.shell.front.message = "punch refused: the machine is running".into();
        return;
    }
    let line = std::mem::take(&mut c.shell.front.entry);
    let name = c.mem.program_name();
    let text = c.mem.text(crate::store::Target::Program);
    c.shell.front.message = punch_program(&name, &text, &line, |p| p);
}

/// Punches program `name`'s `text` to the image the punch key's `line` names (`PATH`, `PATH
/// EIA`), the path first passed through `path` (a lathe finds its folder without regard to
/// case): what was punched, or why nothing was written. Every console's punch.
pub(crate) fn punch_program(
    name: &str,
    text: &str,
    line: &str,
    path: impl FnOnce(PathBuf) -> PathBuf,
) -> String {
    let (path, code) = match parse_punch_line(line) {
        Ok((p, code)) => (path(p), code),
        Err(e) => return e,
    };
    if text.trim().is_empty() {
        return format!("punch refused: program {name} is empty; nothing written");
    }
    let opts = PunchOptions {
        code,
        leader: tape::DEFAULT_LEADER,
        label: Some(name.to_string()),
    };
    let image = match tape::punch(text, &opts) {
        Ok(i) => i,
        Err(e) => return format!("punch refused, nothing written: program {name} line {e}"),
    };
    match crate::store::fsutil::write_output(&path, &image) {
        Ok(()) => format!(
            "punched {name} to {} in the {} code: {} frames ({:.1} m of tape)",
            path.display(),
            code.name(),
            image.len(),
            image.len() as f64 * 2.54e-3
        ),
        Err(e) => format!(
            "punch: cannot write {}: {e}; nothing written",
            path.display()
        ),
    }
}

/// The punch key's line: `PATH`, `PATH EIA` or `PATH ISO` (the code word in either case).
pub fn parse_punch_line(line: &str) -> Result<(PathBuf, Code), String> {
    let line = line.trim();
    let (path, code) = match line.rsplit_once(char::is_whitespace) {
        Some((p, w)) if Code::from_name(w).is_some() && !p.trim().is_empty() => {
            (p.trim(), Code::from_name(w).unwrap_or(Code::Iso))
        }
        _ => (line, Code::Iso),
    };
    if path.is_empty() {
        return Err(
            "punch: type the image's file path first (add EIA for the EIA code), then the punch key"
                .into(),
        );
    }
    Ok((PathBuf::from(path), code))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_punch_line_names_the_path_and_the_code() {
        assert_eq!(
            parse_punch_line("out.tape").unwrap(),
            (PathBuf::from("out.tape"), Code::Iso)
        );
        assert_eq!(
            parse_punch_line(" out.tape eia ").unwrap(),
            (PathBuf::from("out.tape"), Code::Eia)
        );
        assert_eq!(
            parse_punch_line("my tape ISO").unwrap(),
            (PathBuf::from("my tape"), Code::Iso)
        );
        assert_eq!(
            parse_punch_line("EIA").unwrap(),
            (PathBuf::from("EIA"), Code::Iso)
        );
        assert!(parse_punch_line("  ")
            .unwrap_err()
            .contains("type the image"));
    }
}
