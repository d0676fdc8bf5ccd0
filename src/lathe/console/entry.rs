//! The lathe console's data keys (docs/lathe.md "The panel", "Tool offsets"): what EOB does in
//! each mode (MDI lines, editor command lines, tool revisions), and the listing the plasma
//! display shows around the current line.

use super::{ofs, LatheConsole};
use crate::console::entry::To;
use crate::console::pages::{macros, msg, pos};
use crate::panel_model::{OpMode, Page};
use crate::store::lathe::{Program, MAX_MDI_LINES, MAX_PROGRAM};
use novanc_editor::{Buffer, ExecOptions};

impl LatheConsole {
    /// The lathe's use of a line entered at `to` (`crate::console::entry`, the one rule, which
    /// keeps a refused line on the entry line): on OFS a tool revision or a cell's value, on
    /// MACRO a variable; in MDI a line added to the selected channel's MDI buffer; in DATA an
    /// editor command line on its program. In another position the line stays for TARGET and
    /// FAULT, which take it in any mode.
    pub(super) fn enter_line(&mut self, to: To, line: &str, add: bool) -> Result<(), String> {
        match to {
            To::Page(Page::Ofs) => return self.cell_or_tool(line, add),
            To::Page(Page::Msg) => {
                return Err("MSG: the history is read only; Up/Down scroll it".into())
            }
            To::Page(Page::Macro) => return self.macro_input(line, add),
            To::Page(Page::Pos) => return self.pos_line(line),
            To::Page(Page::Modal) => {
                return Err(
                    "MODAL: the state is read only; MDI sets it (G91, G95, F0.1 ...)".into(),
                )
            }
            _ => {}
        }
        // POS shows positions only: a line goes where the selector sends it.
        match self.shell.front.op {
            OpMode::Mdi => self.mdi_line(line),
            OpMode::Data if line.is_empty() => Ok(()),
            OpMode::Data => self.edit(line),
            OpMode::Auto | OpMode::Single if self.desc.manual && self.desc.channels.len() == 1 => {
                self.search_line(line)
            }
            _ if line.is_empty() => Ok(()),
            // Before stop 44 this said `turn to MDI or DATA`, and the turn cleared the line.
            op => Err(format!(
                "{} takes no line; it stays for TARGET (Alt+n) or FAULT (Alt+x)",
                op.word()
            )),
        }
    }

    /// A line typed on the POS page, in the centre's words (`pages::pos::read_line`), for the
    /// selected channel: `X` zeroes its relative X, `X12.5` presets it (a diameter), `Z`,
    /// `Z-3.` the same on Z, `XZ` or `ORIGIN` zeroes both; `PARTS n` sets the total part count
    /// (the log book's, the centre's PARTS; POS shows it as TOTAL), `TARGET n` the batch's
    /// target (Alt+n's); `JOG 500`, `JOG RAPID` and `JOG` the channel's jog feed (the
    /// centre's, `manual::JogChoice`). Before stop 59 a line typed under POS went to the
    /// selector's use (an MDI line in MDI), where the centre's POS took it.
    fn pos_line(&mut self, line: &str) -> Result<(), String> {
        use pos::{read_line, rel_said, PosLine};
        const LETTERS: [char; 2] = ['X', 'Z'];
        let tip = self.chan_views()[self.sel].pos;
        let op = self.shell.front.op;
        let read = read_line(line, &LETTERS).map_err(|e| pos::refused_at(e, op))?;
        let rel = rel_said(&LETTERS, &read);
        let said = match read {
            PosLine::Zero(which) => {
                for &i in &which {
                    self.rel[self.sel][i] = tip[i];
                }
                rel
            }
            PosLine::Preset(i, v) => {
                let radius = if i == 0 { v / 2.0 } else { v };
                self.rel[self.sel][i] = tip[i] - self.desc.pulses(radius);
                rel
            }
            PosLine::Parts(n) => self.shell.set_count(true, n, self.store.dir())?,
            PosLine::Target(n) if (1..=999_999).contains(&n) => self.set_target(n as u32)?,
            PosLine::Target(n) => {
                return Err(format!("TARGET {n}: the batch's target is 1 to 999999"));
            }
            PosLine::Jog(rest) => {
                let ch = self.sel;
                let s = self.channel_settings(ch);
                let mut jog = self.jog[ch];
                jog.take(&rest, s.rapid_mm_min)?;
                // Stored first: a choice the disk did not take changes nothing.
                self.store.save_jog(ch, jog.feed, jog.rapid)?;
                self.jog[ch] = jog;
                let f = jog.rate(s.jog_mm_min, s.rapid_mm_min);
                // The channel's machine takes it for the jogs started from now on.
                self.cycle
                    .manual(ch, crate::pulse_core::Command::JogFeed(f));
                format!("CH{} {}", ch + 1, self.jog[ch].said(f))
            }
        };
        self.shell.front.message = said;
        Ok(())
    }

    /// SEARCH in AUTO (docs/lathe.md "SEARCH"), on a lathe of one channel loaded by hand: a
    /// line number, or text to find as whole words (the centre's `search::find_line`),
    /// positions the next START at the first block at or after that line, which runs one part
    /// from there after restoring the tool, the spindle and the coolant and taking the tool
    /// there (`glue::restart_from`); `0` or an empty line clears it. Refused while a cycle is
    /// under way, and where the program makes no block at or after the line. The message says
    /// what START will do.
    fn search_line(&mut self, line: &str) -> Result<(), String> {
        if !self.at_rest_unloaded() {
            return Err("SEARCH refused: a cycle is under way; RESET it first".into());
        }
        let text = self.programs[0].text.clone();
        let Some(n) = crate::console::search::find_line(&text, line)
            .map_err(|e| format!("SEARCH refused: {e}"))?
        else {
            self.search = None;
            self.shell.front.message = "SEARCH cleared: AUTO starts at the top".into();
            return Ok(());
        };
        let read = match self.programmed(0) {
            Some(Ok(p)) => p,
            Some(Err(e)) => return Err(format!("SEARCH refused: the program does not read: {e}")),
            None => return Err("SEARCH refused: the channel has no program".into()),
        };
        let at = self.cycle.axes().first().copied().unwrap_or([0, 0]);
        let (k, restore) = super::glue::restart_from(&read, n, at)?;
        let mm = |p: i64| crate::input_text::short_number(p as f64 * self.desc.pulse_mm);
        let mut plan: Vec<String> = Vec::new();
        for b in &restore.blocks {
            if let Some(t) = b.t {
                plan.push(format!("T{t:02}"));
            } else if let Some(m) = b.m {
                plan.push(match (m, b.s, b.css) {
                    (3 | 4, Some(s), _) => format!("S{s} M0{m}"),
                    (3 | 4, None, Some(c)) => {
                        format!(
                            "G96 S{} M0{m}",
                            crate::input_text::short_number(c.m_per_min)
                        )
                    }
                    _ => format!("M0{m}"),
                });
            } else if b.motion == crate::block::Motion::Rapid {
                plan.push(format!("G00 X{} Z{}", mm(b.end[0] * 2), mm(b.end[2])));
            }
        }
        self.search = Some(n);
        self.shell.front.message = format!(
            "SEARCH line {}: START restores {} (machine X Z), then runs one part from there",
            read[k].line,
            if plan.is_empty() {
                "nothing".to_string()
            } else {
                plan.join(", ")
            }
        );
        Ok(())
    }

    /// No channel has a run loaded (none running, held or stopped between blocks; a cycle
    /// RESET stands at its start) and none moves: where SEARCH may position the next START.
    pub(super) fn at_rest_unloaded(&self) -> bool {
        self.cycle
            .channels()
            .iter()
            .all(|c| c.status.run == 0 && !c.status.moving)
    }

    /// MDI: the line is added to the selected channel's MDI buffer (START runs its lines).
    fn mdi_line(&mut self, line: &str) -> Result<(), String> {
        if line.trim().is_empty() {
            return Err("MDI: type a block, Enter, then START".into());
        }
        // Up recalls it, stored or not (the centre's rule).
        self.shell.recall[self.sel].remember(line);
        if self.mdi[self.sel].len() >= MAX_MDI_LINES {
            return Err(format!(
                "the MDI buffer holds {MAX_MDI_LINES} lines: START or RESET it"
            ));
        }
        let mut lines = self.mdi[self.sel].clone();
        lines.push(line.to_string());
        self.set_mdi(lines)?;
        self.shell.front.message = format!(
            "MDI CH{}: {} lines; START runs them",
            self.sel + 1,
            self.mdi[self.sel].len()
        );
        Ok(())
    }

    /// The command cursor key `k` stands for on the selected channel's program at its editor
    /// pointer, a page being the plasma's listing (`Side::cursor_command`).
    pub(super) fn cursor_command(
        &self,
        k: novanc_panel::Key,
    ) -> Option<(&'static str, Result<String, String>)> {
        // Any other key is not the editor's: the program is not copied for it.
        if !crate::console::keys::is_cursor_key(k) && k != novanc_panel::Key::Delete {
            return None;
        }
        let mut buf = Buffer::from_text(&self.programs[self.sel].text);
        buf.set_pointer(self.pointers[self.sel]);
        let page = self.rows.saturating_sub(5).max(1);
        crate::console::entry::cursor_command(&buf, k, page)
    }

    /// MACRO: a line INPUT on the selected channel's variables, by the centre's rules
    /// (`console::pages::macros::input`): `12.5` sets the variable under the cursor, `#500=12.5`
    /// the one it names, `#500` moves the cursor there. #500–#999 are stored first (the
    /// channel's kept parameters, journaled as a program's writes are); #1–#33 and #100–#199
    /// hold until RESET clears them. Taken with no cycle under way: the programs read the
    /// variables at START. +INPUT (`add`) adds to the variable, as on the centre (before stop
    /// 46 a lathe's MACRO page took +INPUT as INPUT). A refused line stays on the entry line.
    fn macro_input(&mut self, line: &str, add: bool) -> Result<(), String> {
        use crate::console::pages::macros::{input, set_message, Input};
        let ch = self.sel;
        match input(line, self.shell.shown.macro_var, &self.kept[ch].params.params, add)? {
            Input::Cursor(n) => self.shell.shown.macro_var = n,
            Input::Set(..) if !self.cycle.is_over() => return Err(
                "MACRO refused: a cycle is under way (its programs read the variables at START); RESET it first".into(),
            ),
            Input::Set(n, v) => {
                // Only the Fanuc dialect has a vacant variable: elsewhere nothing is 0.
                let fanuc = self.desc.channels[ch].dialect.unwrap_or_default()
                    == crate::settings::Dialect::Fanuc;
                let v = if v.is_nan() && !fanuc { 0.0 } else { v };
                let kept = if v.is_nan() { 0.0 } else { v };
                if crate::store::lathe::kept_param(n) {
                    (self.store.save_params(ch, &[(n, kept)]))
                        .map_err(|e| format!("MACRO refused: #{n}: {e}"))?;
                }
                self.kept[ch].params.params[n] = v;
                self.shell.shown.macro_var = n;
                self.shell.front.message = format!("CH{} {}", ch + 1, set_message(n, v));
            }
        }
        Ok(())
    }

    /// OFS: `T1 X0.02 Z-0.01 R0.8 P3` revises tool 1 of the selected channel (X offset as a
    /// diameter, Z offset, nose radius, tip position; any of them), stored at once; a batch
    /// under way takes it from the channel's next tool call, in this part or the next
    /// (`Cycle::reread`), else the programs read it from the next START.
    fn revise_tool(&mut self, line: &str) -> Result<(), String> {
        let ch = self.sel;
        let (tools, t) = ofs::revise(&self.desc.channels[ch].tools, line)?;
        (self.store.save_tools(ch, &tools)).map_err(|e| format!("{e}: the revision is refused"))?;
        // A cycle under way takes it at the channel's next tool call not yet read, in this
        // part or the next, as a real lathe takes a wear offset at the next T.
        let running = Some(&mut self.cycle).filter(|c| !c.is_over() && !c.mdi);
        self.shell.front.message = match running.map(|c| c.reread(ch, &tools)) {
            Some(Ok(Some(line))) => format!(
                "T{t:02} revised: CH{} takes it from its next tool call, line {line}",
                ch + 1
            ),
            Some(Ok(None)) => format!("T{t:02} revised: CH{} takes it from its next part", ch + 1),
            Some(Err(e)) => format!("T{t:02} revised: from the next START ({e})"),
            None => format!("T{t:02} revised: from the next START"),
        };
        self.desc.channels[ch].tools = tools;
        Ok(())
    }

    /// OFS: a line INPUT (or +INPUT with `add`): `T1 X0.02 Z-0.01 R0.8 P3` revises the tool it
    /// names; a value sets (adds to) the cell under the cursor, as the revision line of that
    /// one word (`ofs::cell_line`). Err: why it is refused (what was typed then stays on the
    /// entry line, not the line made of it).
    fn cell_or_tool(&mut self, line: &str, add: bool) -> Result<(), String> {
        if line.trim().is_empty() {
            // The centre's words (before stop 46 an empty INPUT said nothing here).
            return Err(
                "OFS: type a value, then Enter (INPUT) or Tab (+INPUT), or T1 X.. Z.. R.. P.."
                    .into(),
            );
        }
        if !add && line.trim_start().starts_with(['T', 't']) {
            return self.revise_tool(line);
        }
        if !add && line.trim_start().starts_with(['G', 'g']) {
            return self.revise_work(line);
        }
        let tools = &self.desc.channels[self.sel].tools;
        if let (Some(m), false) = (ofs::measure(line), add) {
            return match ofs::work_row(tools, self.ofs_cell) {
                Some(k) => self.measure_work(k, m?),
                None => self.measure_tool(m?),
            };
        }
        let tools = &self.desc.channels[self.sel].tools;
        let work = crate::lathe::gcode::work_offsets(&self.kept[self.sel].params.params);
        let revision = ofs::cell_line(tools, &work, self.ofs_cell, line, add)?;
        if revision.starts_with('G') {
            return self.revise_work(&revision);
        }
        self.revise_tool(&revision)
    }

    /// A measure is taken with channel `ch`'s tool at rest: why not, if it moves.
    fn measured_at_rest(&self, ch: usize) -> Result<(), String> {
        if (self.cycle.channels().get(ch)).is_some_and(|c| c.status.moving) {
            return Err(format!(
                "measure refused: CH{} is moving; measure with the tool at rest",
                ch + 1
            ));
        }
        Ok(())
    }

    /// OFS, `Z0` INPUT on work offset `k`'s row (Fanuc's MEASURE): the offset is set so that
    /// the tool in place, where it stands, reads that value (its offsets and a G50/G92 shift
    /// taken off, as `G10 L20` sets it); X a diameter. Refused while the channel moves.
    fn measure_work(&mut self, k: usize, (letter, value): (char, f64)) -> Result<(), String> {
        use crate::lathe::gcode::work_offsets;
        let ch = self.sel;
        self.measured_at_rest(ch)?;
        let views = self.chan_views();
        let v = &views[ch];
        let mm = |p: i64| p as f64 * self.desc.pulse_mm;
        let (sys, zero) = v.system.unwrap_or((0, [0, 0]));
        let offs = work_offsets(&self.kept[ch].params.params);
        // [X radius, Z]: where the tool's programmed point is from the machine's zero, and the
        // G50/G92 shift on top of the system in force.
        let point = [mm(v.pos[0] - v.offset[0]), mm(v.pos[1] - v.offset[1])];
        let shift = [mm(zero[0]) - offs[sys][1], mm(zero[1]) - offs[sys][0]];
        let set = match letter {
            'X' => 2.0 * (point[0] - shift[0] - value / 2.0),
            _ => point[1] - shift[1] - value,
        };
        let set = (set * 1000.0).round() / 1000.0;
        self.revise_work(&format!("G{} {letter}{set}", 54 + k))?;
        let said = std::mem::take(&mut self.shell.front.message);
        self.shell.front.message = format!(
            "measured, T{:02} at {letter}{}: {said}",
            v.tool,
            crate::input_text::short_number(value)
        );
        Ok(())
    }

    /// OFS, `X50.` INPUT on a tool's row (Fanuc's MEASURE of a tool offset): the tool, which
    /// must be the one in place, gets the offset that makes it read that value where it stands
    /// in the work system in force (a diameter just turned and measured, a face touched); X a
    /// diameter. Refused while the channel moves, or for a tool not in place.
    fn measure_tool(&mut self, (letter, value): (char, f64)) -> Result<(), String> {
        let ch = self.sel;
        self.measured_at_rest(ch)?;
        let tools = &self.desc.channels[ch].tools;
        let row = self.ofs_cell.0.min(tools.len().saturating_sub(1));
        let Some(t) = tools.get(row).map(|t| t.number) else {
            return Err("OFS: the channel has no tools".into());
        };
        let views = self.chan_views();
        let v = &views[ch];
        if v.tool != t {
            return Err(format!(
                "measure T{t:02} refused: the tool in place is T{:02}; index T{t:02} (MDI T{t:02}{t:02}) and measure where it cuts",
                v.tool
            ));
        }
        let mm = |p: i64| p as f64 * self.desc.pulse_mm;
        let zero = v.system.map_or([0, 0], |s| s.1);
        let set = match letter {
            'X' => 2.0 * (mm(v.pos[0] - zero[0]) - value / 2.0),
            _ => mm(v.pos[1] - zero[1]) - value,
        };
        let set = (set * 1000.0).round() / 1000.0;
        self.revise_tool(&format!("T{t} {letter}{set}"))?;
        let said = std::mem::take(&mut self.shell.front.message);
        self.shell.front.message = format!(
            "measured, T{t:02} at {letter}{}: {said}",
            crate::input_text::short_number(value)
        );
        Ok(())
    }

    /// OFS: `G55 X0 Z-150.` revises work offset G55 of the selected channel (X as a diameter,
    /// Z; either), stored at once as the channel's kept parameters (docs/lathe-gcode.md "Work
    /// offsets"). A cycle under way keeps the offsets its programs were read with: the next
    /// START (or MDI run) reads the revised one.
    fn revise_work(&mut self, line: &str) -> Result<(), String> {
        use crate::lathe::gcode::{set_work_offsets, work_offsets, work_params};
        let ch = self.sel;
        let params = &self.kept[ch].params.params;
        let (work, k) = ofs::revise_work(&work_offsets(params), line)?;
        let pairs: Vec<(usize, f64)> = work_params(k).into_iter().zip(work[k]).collect();
        (self.store.save_params(ch, &pairs))
            .map_err(|e| format!("{e}: the revision is refused"))?;
        set_work_offsets(&mut self.kept[ch].params.params, &work);
        let [z, x] = work[k];
        let under_way = !self.cycle.is_over();
        self.shell.front.message = format!(
            "G{} X{} Z{} (CH{}): {}",
            54 + k,
            crate::input_text::short_number(x * 2.0),
            crate::input_text::short_number(z),
            ch + 1,
            if under_way {
                "from the next START (the run under way keeps the offsets it was read with)"
            } else {
                "from the next START"
            }
        );
        Ok(())
    }

    /// Runs an editor command line on the selected channel's program and stores what it
    /// changed (and the pointer); the message says so. Err: why it is refused (the program
    /// and the pointer unchanged).
    pub(super) fn edit(&mut self, line: &str) -> Result<(), String> {
        if !self.cycle.is_over() {
            return Err("the programs are in use: RESET the cycle before editing".into());
        }
        // The program's lines may move: a SEARCH point is let go.
        self.search = None;
        let ch = self.sel;
        let mut buf = Buffer::from_text(&self.programs[ch].text);
        buf.set_pointer(self.pointers[ch]);
        let opts = ExecOptions {
            y_max_lines: Some(self.rows),
            validator: None,
        };
        let out = buf
            .execute(line, &opts)
            .map_err(|e| format!("{}: {}", e.command, e.reason))?;
        let text = buf.text();
        if text.len() > MAX_PROGRAM {
            return Err("the program would pass 1 MB: refused".into());
        }
        let p = self.to_store(ch, self.programs[ch].name.clone(), text);
        if out.changed {
            self.store
                .save_program(ch, &p)
                .map_err(|e| format!("{e}: the edit is refused"))?;
            self.programs[ch] = p;
        }
        // The pointer is kept across a restart, as the centre's is.
        if let Err(e) = self.store.save_pointer(ch, buf.pointer()) {
            if !out.changed {
                // A move alone that cannot be stored is refused: the pointer stays.
                return Err(format!("{e}: the line is refused"));
            }
            self.shell.front.message = e;
        }
        // `Y` type-out is shown in place of the listing until the next line or mode (the
        // centre's rule): what the operator asked to see is not dropped.
        self.shell.front.y_output = (!out.y_output.is_empty()).then_some(out.y_output);
        self.pointers[ch] = buf.pointer();
        self.edit_line[ch] = buf.line_of(buf.pointer()) + 1;
        if self.shell.front.message.is_empty() {
            self.shell.front.message = if out.changed {
                "stored".into()
            } else {
                "ok".into()
            };
        }
        Ok(())
    }

    /// Channel `ch`'s program `name` with `text` as it is stored: in the dialect the channel
    /// reads now, which the program keeps (docs/lathe.md "Stores").
    fn to_store(&self, ch: usize, name: String, text: String) -> Program {
        let dialect = self.desc.channels.get(ch).and_then(|c| c.dialect);
        Program {
            name,
            text,
            dialect: Some(dialect.unwrap_or_default()),
        }
    }

    /// PROGRAM READ on a lathe (the tape key, a script's `tape PATH`, in DATA INPUT): the file
    /// at `path` becomes the selected channel's program, stored (journaled) before it is
    /// taken, named after the file, in the dialect the channel reads now, the editor's pointer
    /// at its start. A text file is taken as it is, line ends made `\n`; a punched tape image
    /// is decoded as the centre's reader decodes it (`tape::read_image`), at once: the lathe
    /// has no tape reader to pass it. What was read is said, and whether it reads as START
    /// would read it. Err: why not (nothing changed).
    pub(super) fn program_read(&mut self, path: &std::path::Path) -> Result<String, String> {
        let ch = self.sel;
        self.search = None;
        if self.shell.front.op != OpMode::Data {
            return Err(format!(
                "{}: turn the selector to DATA INPUT to read a program into CH{}",
                self.shell.front.op.name(),
                ch + 1
            ));
        }
        if !self.cycle.is_over() {
            return Err("the programs are in use: RESET the cycle first".into());
        }
        // The data keys type capitals: the path is found without regard to case.
        let path = &path_ignoring_case(path)?;
        let file = path
            .file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_default();
        if path.is_dir() {
            return Err(format!(
                "{file} is a folder: a channel takes one program file"
            ));
        }
        let image = crate::console::tape::load(path).map_err(|e| format!("{file}: {e}"))?;
        let tape = crate::tape::read_image(&image, Default::default())
            .map_err(|e| format!("{file}: {e}"))?;
        let how = match tape.code {
            None => "text",
            Some(crate::tape::Code::Iso) => "ISO tape",
            Some(crate::tape::Code::Eia) => "EIA tape",
        };
        let text = tape.text.replace("\r\n", "\n");
        if text.len() > MAX_PROGRAM {
            return Err(format!("{file}: a program of more than 1 MB"));
        }
        // Named as the centre's PROGRAM READ names a file (`shaft.nc` is `SHAFT.NC`).
        let name = crate::store::program_name_from_file(&file)?.name;
        let p = self.to_store(ch, name, text);
        self.store.save_program(ch, &p)?;
        let lines = p.text.lines().count();
        let said = format!(
            "read {file} ({how}): CH{}'s program {}, {lines} lines",
            ch + 1,
            p.name
        );
        self.programs[ch] = p;
        self.pointers[ch] = 0;
        self.edit_line[ch] = 1;
        self.shell.front.y_output = None;
        let kept = match self.store.save_pointer(ch, 0) {
            Ok(()) => String::new(),
            Err(e) => format!("; {e}"),
        };
        // Whether it reads as START would read it: said now, not at START.
        let reads = match self.programmed(ch) {
            Some(Err(e)) => format!(
                "; it does not read: line {}:{}: {}",
                e.line, e.col, e.message
            ),
            _ => String::new(),
        };
        Ok(format!("{said}{reads}{kept}"))
    }

    /// The punch key (Alt+u) in DATA INPUT: the selected channel's program punched whole to the
    /// image the typed line names (`PATH`, `PATH EIA`), as the centre punches its current
    /// program (`console::punch::punch_program`); the folder is found without regard to case,
    /// as PROGRAM READ finds a file. What was punched, or why not (the typed line stays when
    /// the key is refused for the mode or a cycle).
    pub(super) fn punch(&mut self) -> String {
        let ch = self.sel;
        if self.shell.front.op != OpMode::Data {
            return format!(
                "punch refused: it punches CH{}'s program in DATA INPUT (now {})",
                ch + 1,
                self.shell.front.op.name()
            );
        }
        if !self.cycle.is_over() {
            return "punch refused: the programs are in use: RESET the cycle first".into();
        }
        let line = std::mem::take(&mut self.shell.front.entry);
        let p = &self.programs[ch];
        crate::console::punch::punch_program(&p.name, &p.text, &line, |path| {
            match (path.parent(), path.file_name()) {
                (Some(d), Some(f)) if !d.as_os_str().is_empty() => {
                    path_ignoring_case(d).map_or(path.clone(), |d| d.join(f))
                }
                _ => path,
            }
        })
    }

    /// The MODAL page of the selected channel (Ctrl+G, the centre's page key): the modal G codes
    /// in the channel's own code system, F, S and the tool as its last read left them (what
    /// its next MDI line starts from; a cycle reads its programs whole at START, so while one
    /// is under way this is the state its read ends in, as the header says), the spindle as
    /// the machine has it, then the overrides and switches in the centre's words
    /// (`console::pages::modal::switch_list`).
    fn modal_lines(&self) -> Vec<String> {
        use crate::console::pages::modal::{fill, setting_lines, switch_list};
        use crate::input_text::short_number;
        let ch = self.sel;
        let cd = &self.desc.channels[ch];
        let k = &self.kept[ch];
        let m = &k.modal;
        let fanuc = cd.dialect.unwrap_or_default() == crate::settings::Dialect::Fanuc;
        let sys_a = fanuc && cd.system_a;
        let cols = self.cols;
        let running = !self.cycle.is_over() && !self.cycle.mdi;
        let mut l = vec![if running {
            format!("MODAL CH{} at the end of the cycle's read", ch + 1)
        } else {
            format!("MODAL CH{} the state in force", ch + 1)
        }];
        let motion = match m.motion {
            None => "G--".to_string(),
            Some(330) if sys_a => "G32".to_string(),
            Some(v) if v % 10 == 0 => format!("G{:02}", v / 10),
            Some(v) => format!("G{}.{}", v / 10, v % 10),
        };
        let pick = |b: bool, on: &'static str, off: &'static str| if b { on } else { off };
        let mut g = vec![motion.as_str()];
        if !sys_a {
            g.push(pick(m.absolute, "G90", "G91"));
        }
        if !fanuc {
            g.push(pick(m.diameter, "G7", "G8"));
        }
        g.push(pick(m.inch, "G20", "G21"));
        g.push(match (sys_a, m.per_rev) {
            (true, true) => "G99",
            (true, false) => "G98",
            (false, true) => "G95",
            (false, false) => "G94",
        });
        g.push(pick(m.css, "G96", "G97"));
        let drill = m.drill.map(|d| format!("G{}", d.code));
        if let Some(d) = &drill {
            g.push(d);
        }
        let work = format!("G{}", 54 + m.work);
        g.push(&work);
        l.extend(fill(&g, cols));
        let feed = m
            .feed
            .map_or("F--".to_string(), |f| format!("F{}", short_number(f)));
        let speed = if m.css {
            format!(
                "S{} m/min (max {} rpm)",
                short_number(m.s),
                short_number(m.limit)
            )
        } else {
            format!("S{}", short_number(m.s))
        };
        // The spindle as the machine turns it (under G96 too, where no rpm is programmed).
        let rpm = (self.cycle.channels().get(ch)).map_or(0.0, |s| s.status.spindle as f64);
        let spindle = if rpm > 0.0 {
            "M03"
        } else if rpm < 0.0 {
            "M04"
        } else {
            "M05"
        };
        // The tool the reader keeps with its offset (`T0303`, `T0300` with the offset
        // cancelled), or, with none kept (power-on, RESET), the turret's station and no
        // offset: RESET cancels the offset and does not turn the turret.
        let turret = (self.cycle.channels().get(ch)).and_then(|s| s.status.tool);
        let tool = match (k.tool, turret) {
            (Some((t, on)), _) => format!("T{t:02}{:02}", if on { t } else { 0 }),
            (None, Some(t)) => format!("T{t:02}00"),
            (None, None) => "T--".to_string(),
        };
        l.extend(fill(&[&feed, &speed, spindle, &tool], cols));
        let offset = crate::lathe::gcode::work_offsets(&k.params.params)[m.work];
        if offset != [0.0, 0.0] {
            // The work offset in force, as the OFS page has it (X a diameter).
            l.push(format!(
                "G{} OFFSET Z{} X{}",
                54 + m.work,
                short_number(offset[0]),
                short_number(offset[1] * 2.0)
            ));
        }
        if m.origin != [0.0, 0.0] {
            // The program zero a G50 X Z (system A) or a G92 X Z (system B) moved, until
            // RESET (or G92.1): named by the code that moves it on this channel.
            let a = self.desc.channels.get(ch).is_some_and(|c| c.system_a);
            l.push(format!(
                "{} ORIGIN Z{} X{}",
                if a { "G50" } else { "G92" },
                short_number(m.origin[0]),
                short_number(m.origin[1] * 2.0)
            ));
        }
        let panel = (
            self.shell.front.op == OpMode::Single,
            self.shell.front.switches.block_delete,
            self.shell.front.switches.optional_stop,
        );
        l.extend(setting_lines(
            &switch_list(
                self.shell.front.feed_override,
                &self.machine_switches(),
                panel,
            ),
            cols,
        ));
        l
    }

    /// The POS page of the selected channel (`c`): its tool tip as the plasma shows it (X as
    /// a diameter) and what is left of the block in execution (Fanuc's DIST TO GO, what an
    /// operator watches proving out a first part at a low override), then its spindle and
    /// tool, its jog feed, the parts and the last cycle's time.
    fn pos_lines(&self, c: &super::view::ChanView) -> Vec<String> {
        // The work position (the program's coordinates), the relative one, the machine's, and
        // what is left of the block (docs/lathe-gcode.md "Work offsets"), X as a diameter: the
        // centre's table.
        let work = c.work_pos();
        let rel = self.rel[self.sel];
        let rows = [0, 1].map(|i| {
            let scale = self.desc.pulse_mm * if i == 0 { 2.0 } else { 1.0 };
            let row = [work[i], c.pos[i] - rel[i], c.pos[i], c.to_go[i]];
            (['X', 'Z'][i], row.map(|p| p as f64 * scale))
        });
        let system = c.system.map_or(0, |s| s.0);
        // The batch's count and target on the heading: the plasma's twelve lines hold the
        // page under a message of one line (a line of its own cut TOTAL off, stop 60).
        let mut l = vec![format!(
            "POS CH{}  X DIAMETER  PARTS {}/{}",
            self.sel + 1,
            c.parts,
            self.counter.target
        )];
        l.extend(pos::axis_table(&format!("WORK G{}", 54 + system), rows));
        l.push(format!("S {:.0} rpm  T{:02}  {}", c.rpm, c.tool, c.state));
        let s = self.channel_settings(self.sel);
        let jog = &self.jog[self.sel];
        let f = jog.rate(s.jog_mm_min, s.rapid_mm_min);
        l.push(pos::jog_line(
            jog,
            f,
            s.to_mm(self.shell.front.wheel.1 as i64),
        ));
        // The counters every console keeps (the centre's POS words): parts delivered in every
        // batch, the last cycle, the run hours.
        let k = &self.shell.book.counters;
        l.push(format!("TOTAL {} {}", k.parts, k.times()));
        l
    }

    /// The program lines around `line` (the current block's), or around the editor's pointer
    /// in DATA mode, marked `>`, or the page shown: at most `room` lines, the plasma's body
    /// under the channel's lines and above the message (`view::plasma`), so that the marked
    /// line and a page's cut mark are on the screen whatever the message takes.
    pub(super) fn listing(&self, c: &super::view::ChanView, room: usize) -> Vec<String> {
        let room = room.max(1);
        let line = c.line;
        match self.shell.shown.page {
            Page::Pos => return self.pos_lines(c),
            Page::Ofs => {
                let work = crate::lathe::gcode::work_offsets(&self.kept[self.sel].params.params);
                return ofs::table(
                    &self.desc.channels[self.sel].tools,
                    &work,
                    self.ofs_cell,
                    room.max(2),
                );
            }
            Page::Macro => {
                // The centre's MACRO page, of the selected channel's variables.
                let room = (room - 1).max(1);
                let mut l = vec![format!("MACRO CH{} #500=12.5 Enter INPUT", self.sel + 1)];
                let params = &self.kept[self.sel].params.params;
                l.extend(macros::variable_rows(
                    params,
                    self.shell.shown.macro_var,
                    room,
                ));
                return l;
            }
            Page::Modal => return self.modal_lines(),
            Page::Msg => {
                // The centre's MSG page under the channel's lines: every entry in full,
                // newest first.
                let all = self.shell.book.log.history.entries();
                let room = (room - 1).max(1);
                let mut l = vec![format!("MSG {} entries, newest first (Up/Down)", all.len())];
                l.extend(msg::body(all, self.shell.shown.msg_first, room, self.cols));
                return l;
            }
            _ => {}
        }
        if let (OpMode::Data, Some(y)) = (self.shell.front.op, &self.shell.front.y_output) {
            return y
                .split_inclusive('\n')
                .take(room)
                .map(|l| format!(" {}", l.replace('\n', "*")))
                .collect();
        }
        // An MDI run under way lists what it runs, its block marked, as a cycle does (the
        // buffer is cleared at START: before stop 40 the display went blank while it ran).
        let running = Some(&self.cycle).filter(|c| !c.is_over());
        let run_lines = running.and_then(|c| c.mdi_lines(self.sel));
        let text = match (self.shell.front.op, run_lines) {
            (OpMode::Mdi, Some(l)) if self.mdi[self.sel].is_empty() => l.join("\n"),
            (OpMode::Mdi, _) => self.mdi[self.sel].join("\n"),
            _ => self.programs[self.sel].text.clone(),
        };
        let lines: Vec<&str> = text.lines().collect();
        let cur = match (self.shell.front.op, self.search) {
            (OpMode::Data, _) => self.edit_line[self.sel],
            // A SEARCH point: the listing stands where START will begin.
            (OpMode::Auto | OpMode::Single, Some(n)) => n.max(1) as usize,
            _ => line.max(1) as usize,
        };
        let first = cur.saturating_sub(room / 2).max(1);
        (first..first + room)
            .filter_map(|n| {
                lines
                    .get(n - 1)
                    .map(|l| format!("{}{:04} {l}", if n == cur { '>' } else { ' ' }, n))
            })
            .collect()
    }
}

/// `path`, or where a part of it is not there as written the one entry of its folder whose
/// name is the same without regard to case: the lathe's data keys type capitals
/// (`/TMP/SHAFT.NC` finds `/tmp/shaft.nc`), as a memory card's file names are read. Err: no
/// such file, or two names that differ only in case.
fn path_ignoring_case(path: &std::path::Path) -> Result<std::path::PathBuf, String> {
    use std::path::{Component, PathBuf};
    if path.exists() {
        return Ok(path.to_path_buf());
    }
    let mut at = PathBuf::new();
    for part in path.components() {
        let Component::Normal(name) = part else {
            at.push(part);
            continue;
        };
        if at.join(name).exists() {
            at.push(name);
            continue;
        }
        let folder = if at.as_os_str().is_empty() {
            PathBuf::from(".")
        } else {
            at.clone()
        };
        let want = name.to_string_lossy();
        let alike: Vec<_> = std::fs::read_dir(&folder)
            .map(|d| d.flatten().map(|e| e.file_name()).collect::<Vec<_>>())
            .unwrap_or_default()
            .into_iter()
            .filter(|n| n.to_string_lossy().eq_ignore_ascii_case(&want))
            .collect();
        match &alike[..] {
            [one] => at.push(one),
            [] => return Err(format!("{}: no such file or folder", path.display())),
            [a, b, ..] => {
                return Err(format!(
                    "{}: {} and {} differ only in case: rename one",
                    path.display(),
                    a.to_string_lossy(),
                    b.to_string_lossy()
                ))
            }
        }
    }
    Ok(at)
}
