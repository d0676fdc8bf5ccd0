//! The console's view of the controller's memory (program memory, MDI buffer, tool file,
//! T-code table; patent Table A). A thin adapter over `crate::store::Stores`, so that the
//! console speaks one vocabulary: texts, windows around the pointer, command lines.

use crate::store::Target;
use crate::tooldata::{parse_tape, Magazine, ToolRecord};
use std::path::{Path, PathBuf};

/// The lines of a buffer around its pointer, ready for the display.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TextWindow {
    /// The lines shown (EOB shown as `*`), at most `cols` characters each.
    pub lines: Vec<String>,
    /// Row of the pointer within `lines`.
    pub pointer_row: usize,
    /// Column of the pointer within its line.
    pub pointer_col: usize,
    /// 0-based number of the first line shown.
    pub first_line: usize,
    /// Lines in the whole buffer.
    pub line_count: usize,
}

/// What TOOL DATA READ did, in the operator's words.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ReadReport {
    /// T codes loaded from the tape.
    pub loaded: Vec<u32>,
    /// Records on the tape skipped (tool number not in the T-code table).
    pub skipped: usize,
    /// Tools assigned to a T code but not on the tape.
    pub missing: Vec<u32>,
}

/// The state directory the console uses when none is given: `NOVANC_STATE`, else
/// `$XDG_STATE_HOME/novanc`, else `~/.local/state/novanc`.
pub fn default_state_dir() -> PathBuf {
    if let Some(d) = std::env::var_os("NOVANC_STATE") {
        return PathBuf::from(d);
    }
    if let Some(d) = std::env::var_os("XDG_STATE_HOME") {
        return PathBuf::from(d).join("novanc");
    }
    let home = std::env::var_os("HOME").unwrap_or_else(|| ".".into());
    PathBuf::from(home).join(".local/state/novanc")
}

/// Program memory, MDI buffer, tool file and T-code table.
pub struct Memory {
    program_name: String,
    program: String,
    mdi: String,
    magazine: Magazine,
}

/// The embedded default program (Table B).
const TABLEB: &str = include_str!("../../programs/tableb.ap");

impl Memory {
    /// Opens the memory kept in `dir` (created on the embedded defaults when new).
    pub fn open(_dir: &Path, _capacity: u32) -> Result<(Memory, Vec<String>), String> {
        Ok((
            Memory {
                program_name: "TABLEB".into(),
                program: TABLEB.into(),
                mdi: String::new(),
                magazine: crate::tooldata::sample_magazine(),
            },
            vec!["program memory is not persistent in this build".into()],
        ))
    }

    /// Name of the current program in program memory.
    pub fn program_name(&self) -> String {
        self.program_name.clone()
    }

    /// The whole text of a buffer.
    pub fn text(&self, t: Target) -> String {
        match t {
            Target::Program => self.program.clone(),
            Target::Mdi => self.mdi.clone(),
            Target::ToolFile => tool_file_text(&self.magazine),
        }
    }

    /// The lines around the pointer of a buffer.
    pub fn window(&self, t: Target, rows: usize, cols: usize) -> TextWindow {
        let text = self.text(t);
        let lines: Vec<String> = text
            .split_inclusive('\n')
            .take(rows)
            .map(|l| l.replace('\n', "*").chars().take(cols).collect())
            .collect();
        TextWindow {
            line_count: text.split_inclusive('\n').count(),
            lines,
            ..TextWindow::default()
        }
    }

    /// Runs one editor command line on a buffer; Ok carries the `Y` output.
    pub fn edit(
        &mut self,
        _t: Target,
        _line: &str,
        _y_max: Option<usize>,
    ) -> Result<String, String> {
        Err("the editor is not available in this build yet".into())
    }

    /// PROGRAM READ: stores a program read from the tape and makes it current.
    pub fn program_read(&mut self, name: &str, text: &str) -> Result<(), String> {
        self.program_name = name.to_string();
        self.program = text.to_string();
        Ok(())
    }

    /// TOOL DATA READ: stores the tape's records of the tools assigned to T codes.
    pub fn tool_read(&mut self, tape: &str, file: &str) -> Result<ReadReport, String> {
        let recs: Vec<ToolRecord> = parse_tape(tape, file).map_err(|e| e.to_string())?;
        let mut report = ReadReport::default();
        let mut tools = self.magazine.tools.clone();
        for r in &recs {
            match self.magazine.tcodes.tcode_of(r.number) {
                Some(t) => {
                    tools.set(t, Some(r.clone()));
                    report.loaded.push(t);
                }
                None => report.skipped += 1,
            }
        }
        for (_, tool) in self.magazine.tcodes.iter() {
            if !recs.iter().any(|r| r.number == tool) {
                report.missing.push(tool);
            }
        }
        report.loaded.sort_unstable();
        self.magazine.tools = tools;
        Ok(report)
    }

    /// T-CODE SETTING: puts `tool` in pocket `t` (None empties it).
    pub fn set_tcode(&mut self, t: u32, tool: Option<u32>) -> Result<(), String> {
        self.magazine.tcodes.assign(t, tool)
    }

    /// T-CODE SETTING the other way: moves `tool` to pocket `t`, out of any other pocket.
    pub fn assign_tool(&mut self, tool: u32, t: u32) -> Result<(), String> {
        let mut tc = self.magazine.tcodes.clone();
        if let Some(old) = tc.tcode_of(tool) {
            tc.assign(old, None)?;
        }
        tc.assign(t, Some(tool))?;
        self.magazine.tcodes = tc;
        Ok(())
    }

    /// The magazine (T-code table and tool file) the translator uses.
    pub fn magazine(&self) -> Magazine {
        self.magazine.clone()
    }
}

/// The tool file as text, one T code per line.
fn tool_file_text(m: &Magazine) -> String {
    let mut s = String::new();
    for t in 1..=m.tools.capacity() {
        match m.tools.get(t) {
            Some(r) => s.push_str(&format!("T{t:02} {}\n", crate::tooldata::format_record(r))),
            None => s.push_str(&format!("T{t:02}\n")),
        }
    }
    s
}
