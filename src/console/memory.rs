//! The console's view of the controller's memory (program memory, MDI buffer, tool file,
//! T-code table; patent Table A). A thin adapter over `crate::store::Stores`, so that the
//! console speaks one vocabulary: texts, windows around the pointer, command lines.

use crate::store::Target;
use crate::tooldata::{parse_record, parse_tape, Magazine, TCodeTable, ToolFile, ToolRecord};
use novanc_editor::{Buffer, ExecOptions};
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
    program: Buffer,
    mdi: Buffer,
    /// The tool file as edited text (pointer kept between revisions).
    tool_text: Buffer,
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
                program: Buffer::from_text(TABLEB),
                mdi: Buffer::new(),
                tool_text: Buffer::from_text(&tool_file_text(&crate::tooldata::sample_magazine())),
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
            Target::Program => self.program.text(),
            Target::Mdi => self.mdi.text(),
            Target::ToolFile => self.tool_text.text(),
        }
    }

    fn buffer(&self, t: Target) -> &Buffer {
        match t {
            Target::Program => &self.program,
            Target::Mdi => &self.mdi,
            Target::ToolFile => &self.tool_text,
        }
    }

    /// The lines around the pointer of a buffer.
    pub fn window(&self, t: Target, rows: usize, cols: usize) -> TextWindow {
        let b = self.buffer(t);
        let v = b.view(rows, cols);
        TextWindow {
            lines: v.lines,
            pointer_row: v.pointer_row,
            pointer_col: v.pointer_col,
            first_line: v.first_line,
            line_count: b.line_count(),
        }
    }

    /// Runs one editor command line on a buffer; Ok carries the `Y` output.
    pub fn edit(&mut self, t: Target, line: &str, y_max: Option<usize>) -> Result<String, String> {
        let cap = self.magazine.tools.capacity();
        let tcodes = self.magazine.tcodes.clone();
        let check = move |b: &Buffer| parse_tool_text(&b.text(), cap, &tcodes).map(|_| ());
        let opts = ExecOptions {
            y_max_lines: y_max,
            validator: if t == Target::ToolFile {
                Some(&check)
            } else {
                None
            },
        };
        let buf = match t {
            Target::Program => &mut self.program,
            Target::Mdi => &mut self.mdi,
            Target::ToolFile => &mut self.tool_text,
        };
        let out = buf.execute(line, &opts).map_err(|e| e.to_string())?;
        if t == Target::ToolFile && out.changed {
            let tools = parse_tool_text(&self.tool_text.text(), cap, &self.magazine.tcodes)?;
            self.magazine.tools = tools;
        }
        Ok(out.y_output)
    }

    /// PROGRAM READ: stores a program read from the tape and makes it current.
    pub fn program_read(&mut self, name: &str, text: &str) -> Result<(), String> {
        self.program_name = name.to_string();
        self.program = Buffer::from_text(text);
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
        self.tool_text = Buffer::from_text(&tool_file_text(&self.magazine));
        Ok(report)
    }

    /// T-CODE SETTING: puts `tool` in pocket `t` (None empties it). The pocket's tool data
    /// goes with its old tool.
    pub fn set_tcode(&mut self, t: u32, tool: Option<u32>) -> Result<(), String> {
        let mut tc = self.magazine.tcodes.clone();
        tc.assign(t, tool)?;
        self.retable(tc);
        Ok(())
    }

    /// T-CODE SETTING the other way: moves `tool` to pocket `t`, out of any other pocket; its
    /// tool data moves with it.
    pub fn assign_tool(&mut self, tool: u32, t: u32) -> Result<(), String> {
        let mut tc = self.magazine.tcodes.clone();
        if let Some(old) = tc.tcode_of(tool) {
            tc.assign(old, None)?;
        }
        tc.assign(t, Some(tool))?;
        self.retable(tc);
        Ok(())
    }

    /// Puts a new T-code table in force: each tool's data follows it to its pocket.
    fn retable(&mut self, tc: TCodeTable) {
        let old = self.magazine.tools.clone();
        let mut tools = ToolFile::new(tc.capacity());
        for (t, n) in tc.iter() {
            if let Some((_, r)) = old.iter().find(|(_, r)| r.number == n) {
                tools.set(t, Some(r.clone()));
            }
        }
        self.magazine = Magazine { tcodes: tc, tools };
        self.tool_text = Buffer::from_text(&tool_file_text(&self.magazine));
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

/// Parses the tool file text: exactly one line per T code, in order, each `Tnn` alone (empty
/// pocket) or `Tnn RECORD` whose tool number is the one the T-code table puts there.
fn parse_tool_text(text: &str, cap: u32, tcodes: &TCodeTable) -> Result<ToolFile, String> {
    let lines: Vec<&str> = text.lines().collect();
    if lines.len() != cap as usize {
        return Err(format!(
            "the tool file has one line per T code ({cap}); lines cannot be added or removed"
        ));
    }
    let mut tf = ToolFile::new(cap);
    for (i, l) in lines.iter().enumerate() {
        let t = i as u32 + 1;
        let head = format!("T{t:02}");
        let rest = l
            .trim()
            .strip_prefix(&head)
            .ok_or_else(|| format!("line {} must start with {head}", i + 1))?;
        if rest.trim().is_empty() {
            continue;
        }
        let rec = parse_record(rest).map_err(|e| format!("{head}: {e}"))?;
        match tcodes.tool_in(t) {
            Some(n) if n == rec.number => {}
            Some(n) => {
                return Err(format!(
                    "{head} holds tool {n:05}, not {:05}: change it in T-CODE SETTING",
                    rec.number
                ))
            }
            None => {
                return Err(format!(
                    "{head} is empty in the T-code table: assign it in T-CODE SETTING"
                ))
            }
        }
        tf.set(t, Some(rec));
    }
    Ok(tf)
}
