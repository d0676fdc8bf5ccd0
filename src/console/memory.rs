//! The console's view of the controller's memory (program memory, MDI buffer, tool file,
//! T-code table; patent Table A). A thin adapter over `crate::store::Stores`, so that the
//! console speaks one vocabulary: texts, windows around the pointer, command lines.

use crate::store::{Stores, Target};
use crate::tooldata::{Magazine, ToolRecord};
use novanc_editor::Buffer;
use std::path::{Path, PathBuf};
use std::sync::Arc;

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
    /// The lines are shown from a later column (scrolled sideways to the pointer).
    pub scrolled: bool,
    /// For each line shown, whether it goes on past the display.
    pub more: Vec<bool>,
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
    Stores::default_dir()
}

/// Program memory, MDI buffer, tool file and T-code table, kept by the stores.
pub struct Memory {
    stores: Stores,
    /// Counts the changes to any text or table: what was checked at one revision holds until
    /// the next.
    rev: u64,
    /// The shared texts, one per target, and what each is of (target, revision, current
    /// program).
    shared: Vec<((Target, u64, String), Arc<str>)>,
}

impl Memory {
    /// Opens the memory kept in `dir` (created on the embedded defaults when new) of a
    /// machine whose G-code dialect is `dialect`: each program stored from now on records it.
    pub fn open(
        dir: &Path,
        capacity: u32,
        dialect: crate::settings::Dialect,
    ) -> Result<(Memory, Vec<String>), String> {
        let (mut stores, warnings) = Stores::open(dir, capacity)
            .map_err(|e| format!("cannot open the memory in {}: {e}", dir.display()))?;
        stores.set_dialect(dialect);
        Ok((
            Memory {
                stores,
                rev: 0,
                shared: Vec::new(),
            },
            warnings,
        ))
    }

    /// Name of the current program in program memory.
    pub fn program_name(&self) -> String {
        self.stores.current_program().to_string()
    }

    /// The G-code dialect program `name` is read in (docs/gcode.md "Fanuc dialect"): the one
    /// it was stored in, or, when none was recorded (a program stored before programs kept
    /// their dialect), the machine's `machine`.
    pub fn program_dialect(
        &self,
        name: &str,
        machine: crate::settings::Dialect,
    ) -> crate::settings::Dialect {
        self.stores.program_dialect(name).unwrap_or(machine)
    }

    /// Names of the programs in program memory.
    pub fn program_names(&self) -> Vec<String> {
        self.stores.program_names()
    }

    /// The revision: it changes whenever a text, the tool file or the T-code table does.
    pub fn rev(&self) -> u64 {
        self.rev
    }

    fn bump<T, E>(&mut self, r: Result<T, E>) -> Result<T, E> {
        if r.is_ok() {
            self.rev += 1;
        }
        r
    }

    /// The programs in memory, with their size and first line.
    pub fn program_list(&self) -> Vec<crate::store::ProgramInfo> {
        self.stores.program_list()
    }

    /// Copies a program under a new name (made current).
    pub fn copy_program(&mut self, from: &str, to: &str) -> Result<(), String> {
        let r = self
            .stores
            .copy_program(from, to)
            .map_err(|e| e.to_string());
        self.bump(r)
    }

    /// Renames a program.
    pub fn rename_program(&mut self, from: &str, to: &str) -> Result<(), String> {
        let r = self
            .stores
            .rename_program(from, to)
            .map_err(|e| e.to_string());
        self.bump(r)
    }

    /// Deletes a program (never the last one).
    pub fn delete_program(&mut self, name: &str) -> Result<(), String> {
        let r = self.stores.delete_program(name).map_err(|e| e.to_string());
        self.bump(r)
    }

    /// Replaces the MDI buffer with one line (MDI typed at the keys), journaled.
    pub fn set_mdi(&mut self, line: &str) -> Result<(), String> {
        let mut cmd = String::from("I");
        for ch in line.chars() {
            if matches!(ch, '*' | '$' | '\\') {
                cmd.push('\\');
            }
            cmd.push(ch);
        }
        cmd.push('*');
        if !self.stores.buffer(Target::Mdi).is_empty() {
            let r = self.stores.clear_mdi().map_err(|e| e.to_string());
            self.bump(r)?;
        }
        let r = self
            .stores
            .edit(Target::Mdi, &cmd, None)
            .map(|_| ())
            .map_err(|e| e.to_string());
        self.bump(r)
    }

    /// Makes another program current.
    pub fn select_program(&mut self, name: &str) -> Result<(), String> {
        let r = self.stores.select_program(name).map_err(|e| e.to_string());
        self.bump(r)
    }

    /// The whole text of a buffer.
    pub fn text(&self, t: Target) -> String {
        self.stores.buffer(t).text()
    }

    /// Up to `n` lines of a buffer from line `first` (0-based), without their end of block:
    /// what a display shows, without copying the whole text.
    pub fn lines(&self, t: Target, first: usize, n: usize) -> Vec<String> {
        let b = self.stores.buffer(t);
        let count = b.line_count();
        if first >= count || n == 0 {
            return Vec::new();
        }
        let start = b.line_start(first);
        let end = if first + n >= count {
            b.len()
        } else {
            b.line_start(first + n)
        };
        b.slice(start, end)
            .lines()
            .take(n)
            .map(|l| l.to_string())
            .collect()
    }

    /// Whether a buffer holds nothing but blanks (looked at in its first lines only when long).
    pub fn is_blank(&self, t: Target) -> bool {
        let b = self.stores.buffer(t);
        b.is_empty() || (b.len() < 4096 && b.text().trim().is_empty())
    }

    /// Lines in a buffer.
    pub fn line_count(&self, t: Target) -> usize {
        self.stores.buffer(t).line_count()
    }

    /// The whole text of a buffer, shared: made once per revision (START of a long program
    /// copies nothing the second time).
    pub fn text_shared(&mut self, t: Target) -> Arc<str> {
        let key = (t, self.rev, self.program_name());
        if let Some((_, text)) = self.shared.iter().find(|(k, _)| *k == key) {
            return text.clone();
        }
        let text = self.stores.buffer(t).text_shared();
        self.shared.retain(|(k, _)| k.0 != t);
        self.shared.push((key, text.clone()));
        text
    }

    /// The lines around the pointer of a buffer.
    pub fn window(&self, t: Target, rows: usize, cols: usize) -> TextWindow {
        let b = self.stores.buffer(t);
        let v = b.view(rows, cols);
        let count = b.line_count();
        let more = v
            .lines
            .iter()
            .enumerate()
            .map(|(i, l)| {
                let n = v.first_line + i;
                let start = b.line_start(n);
                let end = if n + 1 >= count {
                    b.len()
                } else {
                    b.line_start(n + 1)
                };
                v.first_col + l.chars().count() < end.saturating_sub(start)
            })
            .collect();
        TextWindow {
            lines: v.lines,
            pointer_row: v.pointer_row,
            pointer_col: v.pointer_col,
            first_line: v.first_line,
            line_count: count,
            scrolled: v.first_col > 0,
            more,
        }
    }

    /// Buffer `t` as stored.
    pub fn buffer(&self, t: Target) -> &Buffer {
        self.stores.buffer(t)
    }

    /// Runs one editor command line on a buffer (journaled before it returns Ok); Ok carries
    /// the `Y` output.
    pub fn edit(&mut self, t: Target, line: &str, y_max: Option<usize>) -> Result<String, String> {
        let o = self
            .stores
            .edit(t, line, y_max)
            .map_err(|e| e.to_string())?;
        if o.changed {
            self.rev += 1;
        }
        Ok(o.y_output)
    }

    /// PROGRAM READ of the tape file `file`: stores it as the program named after the file
    /// (`store::program_name_from_file`) and makes it current.
    pub fn program_read_file(
        &mut self,
        file: &str,
        text: &str,
    ) -> Result<crate::store::ProgramReadReport, String> {
        let r = self
            .stores
            .program_read_file(file, text)
            .map_err(|e| e.to_string());
        self.bump(r)
    }

    /// PROGRAM READ of a Fanuc DNC file's programs (`gcode::flow::dnc_programs`): each is
    /// stored as `O<number>.NGC`, the first made current. A number already in program memory
    /// (or twice in the file) refuses the whole read before anything is stored, naming it and
    /// its line, as Fanuc's alarm "program number already in use" stops the read there.
    pub fn program_read_dnc(
        &mut self,
        file: &str,
        programs: &[(u32, usize, String)],
    ) -> Result<Vec<String>, String> {
        let mut names: Vec<String> = Vec::with_capacity(programs.len());
        for (n, line, _) in programs {
            let name = format!("O{n}.NGC");
            if names.contains(&name) || self.stores.program_text(&name).is_some() {
                return Err(format!(
                    "{file}:{line}: program number O{n} already in use (program {name}); nothing stored: delete it first"
                ));
            }
            names.push(name);
        }
        for (name, (_, _, text)) in names.iter().zip(programs) {
            let r = self
                .stores
                .program_read(name, text)
                .map_err(|e| e.to_string());
            self.bump(r)?;
        }
        if let Some(first) = names.first() {
            let r = self.stores.select_program(first).map_err(|e| e.to_string());
            self.bump(r)?;
        }
        Ok(names)
    }

    /// TOOL DATA READ: stores the tape's records of the tools assigned to T codes.
    pub fn tool_read(&mut self, tape: &str, file: &str) -> Result<ReadReport, String> {
        let r = self.stores.tool_read(tape, file).map_err(|e| e.to_string());
        let r = self.bump(r)?;
        Ok(ReadReport {
            loaded: r.loaded,
            skipped: r.skipped,
            missing: r.missing.into_iter().map(|(_, n)| n).collect(),
        })
    }

    /// T-CODE SETTING: puts `tool` in pocket `t` (None empties it).
    pub fn set_tcode(&mut self, t: u32, tool: Option<u32>) -> Result<(), String> {
        let r = self.stores.set_tcode(t, tool);
        self.bump(r)
    }

    /// T-CODE SETTING the other way: moves `tool` to pocket `t`, out of any other pocket, with
    /// its tool data, as one journaled change (a crash cannot leave it in no pocket).
    pub fn assign_tool(&mut self, tool: u32, t: u32) -> Result<(), String> {
        if self.stores.magazine().tcodes.tcode_of(tool) == Some(t) {
            return Ok(());
        }
        let r = self.stores.move_tool(tool, t);
        self.bump(r)
    }

    /// The magazine (T-code table and tool file) the translator uses.
    pub fn magazine(&self) -> Magazine {
        self.stores.magazine()
    }

    /// The work offsets G54 to G59, machine mm.
    pub fn work_offsets(&self) -> crate::gcode::WorkOffsets {
        self.stores.work_offsets()
    }

    /// The G-code interpreter's persistent parameters that are not zero (number, value).
    pub fn params(&self) -> Vec<(usize, f64)> {
        self.stores.params()
    }

    /// One persistent parameter as the stores keep it (0 when not kept; #5220 then 1).
    pub fn param(&self, n: usize) -> f64 {
        self.stores.param(n)
    }

    /// Sets persistent parameters of the G-code interpreter together, journaled.
    pub fn set_params(&mut self, ps: &[(usize, f64)]) -> Result<(), String> {
        let r = self.stores.set_params(ps).map_err(|e| e.to_string());
        self.bump(r)
    }

    /// Replaces T code `t`'s line of the tool file (holding `tool`) with `rec`: one journaled
    /// revision of the tool file, through TOOL DATA REVISION's validator.
    pub fn revise_tool(&mut self, t: u32, tool: u32, rec: &ToolRecord) -> Result<(), String> {
        let text = crate::store::toolfile::format_line(t, Some(tool), Some(rec));
        let up = if t > 1 {
            format!("{}L", t - 1)
        } else {
            String::new()
        };
        self.edit(Target::ToolFile, &format!("-99999L{up}KI{text}*"), None)
            .map(|_| ())
    }

    /// G10 L1/L10/L11: T code `t`'s tool gets `length` and `diameter` (mm, wear included: the
    /// set values become these less the wear), one journaled revision of the tool file.
    pub fn set_tool_size(&mut self, t: u32, length: f64, diameter: f64) -> Result<(), String> {
        let Some(rec) = self.magazine().tools.get(t).cloned() else {
            return Err(format!("T{t:02} holds no tool with data"));
        };
        let (wl, wd) = (rec.wear_length, rec.wear_diameter);
        self.set_tool_offsets(t, [length - wl, diameter - wd, wl, wd])
    }

    /// T code `t`'s tool gets its set length, diameter, length wear and diameter wear (mm,
    /// in that order; Fanuc's #2001–/#10001– tool offset variables, and G10 through
    /// [`Memory::set_tool_size`]): one journaled revision of the tool file.
    pub fn set_tool_offsets(&mut self, t: u32, v: [f64; 4]) -> Result<(), String> {
        let m = self.magazine();
        let (Some(tool), Some(rec)) = (m.tcodes.tool_in(t), m.tools.get(t)) else {
            return Err(format!("T{t:02} holds no tool with data"));
        };
        let mut new = rec.clone();
        // Three decimals at most, as the tool file writes numbers.
        let r3 = |v: f64| (v * 1000.0).round() / 1000.0;
        new.set_length = r3(v[0]);
        new.diameter = r3(v[1]);
        new.wear_length = r3(v[2]);
        new.wear_diameter = r3(v[3]);
        if new == *rec {
            return Ok(());
        }
        self.revise_tool(t, tool, &new)
    }

    /// The zero of coordinate system `cs` (0 = G54 … 8 = G59.3), machine mm.
    pub fn system_offset(&self, cs: usize) -> [f64; 3] {
        self.stores.system_offset(cs)
    }

    /// The zero of coordinate system `cs` on every axis, X Y Z (mm) then A B C (degrees).
    pub fn system_offset_all(&self, cs: usize) -> [f64; crate::block::MAX_AXES] {
        let (l, r) = (self.stores.system_offset(cs), self.stores.rotary_offset(cs));
        [l[0], l[1], l[2], r[0], r[1], r[2]]
    }

    /// Sets a work offset (0 = G54 … 8 = G59.3): X Y Z (mm), then A B C (degrees) as many as
    /// given, journaled as one record.
    pub fn set_work_offset(&mut self, system: usize, offs: &[f64]) -> Result<(), String> {
        if system < crate::gcode::state::SYSTEMS
            && self
                .system_offset_all(system)
                .iter()
                .zip(offs)
                .all(|(a, b)| a == b)
        {
            return Ok(());
        }
        let r = self
            .stores
            .set_work_offset(system, offs)
            .map_err(|e| e.to_string());
        self.bump(r)
    }

    /// Where a G-code run's `o<name> call` finds `name.ngc`: the G-code programs in program
    /// memory named `NAME.NGC` (docs/gcode.md "O-words and subprograms"), then the folder
    /// `subroutines` of the state directory.
    pub fn subroutines(&self) -> crate::gcode::SubPrograms {
        let programs = self
            .stores
            .program_names()
            .into_iter()
            .filter(|n| n.ends_with(".NGC"))
            .filter_map(|n| {
                let t = self.stores.program_text(&n)?;
                Some((n, Arc::from(t)))
            })
            .collect();
        crate::gcode::SubPrograms {
            programs,
            path: crate::gcode::SubPath(vec![self.stores.dir().join("subroutines")]),
        }
    }

    /// Whether the current program is ISO G-code (by its name or first line).
    pub fn program_is_gcode(&self) -> bool {
        let name = self.program_name();
        let b = self.stores.buffer(Target::Program);
        let head = if b.line_count() > 16 {
            b.slice(0, b.line_start(16))
        } else {
            b.text()
        };
        crate::gcode::is_gcode(&name, &head)
    }
}

/// Where an editor cursor key takes the pointer of a buffer: a character left or right,
/// a line (or `page` lines) up or down keeping the column where the line is long enough,
/// the start or the end of the line (docs/editor.md, "Cursor keys"). Err says why the
/// pointer cannot go there (at the start or the end of the buffer). Every console's editor
/// (the centre's buffers, a lathe channel's program).
pub(crate) fn cursor_target(b: &Buffer, k: Cursor, page: usize) -> Result<usize, String> {
    let p = b.pointer();
    let count = b.line_count().max(1);
    let line = b.line_of(p);
    let start = |l: usize| b.line_start(l.min(count));
    // The end of line `l`: before its end of block, or the buffer's end for the last.
    let end = |l: usize| {
        if l + 1 >= count {
            let s = start(l);
            let e = b.len();
            if e > s && b.slice(e - 1, e) == "\n" {
                e - 1
            } else {
                e
            }
        } else {
            start(l + 1) - 1
        }
    };
    let col = p - start(line);
    let to_line = |l: usize| (start(l) + col).min(end(l));
    match k {
        Cursor::Left if p == 0 => Err("the pointer is at the start of the buffer".into()),
        Cursor::Left => Ok(p - 1),
        Cursor::Right if p >= b.len() => Err("the pointer is at the end of the buffer".into()),
        Cursor::Right => Ok(p + 1),
        Cursor::Up | Cursor::PageUp if line == 0 => Err("the pointer is on the first line".into()),
        Cursor::Down | Cursor::PageDown if line + 1 >= count => {
            Err("the pointer is on the last line".into())
        }
        Cursor::Up => Ok(to_line(line - 1)),
        Cursor::Down => Ok(to_line(line + 1)),
        Cursor::PageUp => Ok(to_line(line.saturating_sub(page.max(1)))),
        Cursor::PageDown => Ok(to_line((line + page.max(1)).min(count - 1))),
        Cursor::Home => Ok(start(line)),
        Cursor::End => Ok(end(line)),
    }
}

/// An editor cursor key (docs/editor.md, "Cursor keys").
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Cursor {
    /// One character back.
    Left,
    /// One character on.
    Right,
    /// The line before, same column.
    Up,
    /// The line after, same column.
    Down,
    /// A screenful of lines back.
    PageUp,
    /// A screenful of lines on.
    PageDown,
    /// The start of the line.
    Home,
    /// The end of the line (before its end of block).
    End,
}
