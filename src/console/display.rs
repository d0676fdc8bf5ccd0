//! The display program: fills the plasma display (14) for the mode in force (patent lines
//! 170–178, 486–488; docs/panel.md).
//!
//! - Running (AUTO, MDI, SINGLE BLOCK): the source statement, the blocks generated from it
//!   (ISO lines) with `>` on the executing block, a message line and the state line.
//! - Data modes (DATA INPUT): a header, the text around the pointer (pointer line marked `>`,
//!   pointer shown as `▌`), the last command line, the result or error, the line being typed.
//! - Tool data modes: one T code per line.
//! - Manual modes (CONTINUOUS, HANDLE, STEP): positions, handwheel, tool and spindle.

use super::state::{lamps, machine_note};
use super::Console;
use crate::block::iso_line;
use crate::panel_model::{DataMode, OpMode};
use crate::pulse_core::RunKind;
use crate::store::Target;
use crate::tooldata::Magazine;

/// The pointer as drawn inside a line of text.
pub const POINTER: char = '▌';

/// The operator's name of an operation mode position.
pub fn op_name(m: OpMode) -> &'static str {
    m.name()
}

/// The mark at the end of a line that was cut to fit the display.
pub const CUT: char = '…';

/// Exactly `cols` characters: padded with blanks, or cut with [`CUT`] as its last character.
pub(crate) fn fit(s: &str, cols: usize) -> String {
    let n = s.chars().count();
    if n > cols {
        let mut out: String = s.chars().take(cols.saturating_sub(1)).collect();
        if cols > 0 {
            out.push(CUT);
        }
        return out;
    }
    let mut out = s.to_string();
    out.extend(std::iter::repeat_n(' ', cols - n));
    out
}

/// `left` and `right` on one line, `right` flush right (cut first if too long).
pub(super) fn split_line(left: &str, right: &str, cols: usize) -> String {
    let r = right.chars().count();
    let l = left.chars().count();
    if l + 1 + r <= cols {
        format!("{left}{}{right}", " ".repeat(cols - l - r))
    } else {
        fit(left, cols)
    }
}

/// A message wrapped on at most `max` lines of `cols` (words kept whole where possible); if it
/// needs more, the last line shown ends in [`CUT`].
pub(crate) fn wrap(msg: &str, cols: usize, max: usize) -> Vec<String> {
    let mut out: Vec<String> = Vec::new();
    let mut cur = String::new();
    for w in msg.split(' ') {
        let need = cur.chars().count() + usize::from(!cur.is_empty()) + w.chars().count();
        if need > cols && !cur.is_empty() {
            out.push(std::mem::take(&mut cur));
        }
        if !cur.is_empty() {
            cur.push(' ');
        }
        cur.push_str(w);
        while cur.chars().count() > cols {
            let head: String = cur.chars().take(cols).collect();
            cur = cur.chars().skip(cols).collect();
            out.push(head);
        }
    }
    if !cur.is_empty() || out.is_empty() {
        out.push(cur);
    }
    let max = max.max(1);
    if out.len() > max {
        out.truncate(max);
        if let Some(last) = out.last_mut() {
            let keep: String = last.chars().take(cols.saturating_sub(1)).collect();
            *last = format!("{keep}{CUT}");
        }
    }
    out
}

/// A page being filled: body lines between a header and the bottom lines.
pub(super) struct Page {
    rows: usize,
    cols: usize,
    /// The first line.
    pub(super) header: String,
    /// The lines between the header and the bottom lines.
    pub(super) body: Vec<String>,
    /// Bottom lines (command, message, entry or state), in order.
    pub(super) bottom: Vec<String>,
}

impl Page {
    pub(super) fn new(rows: usize, cols: usize, header: String) -> Page {
        Page {
            rows,
            cols,
            header,
            body: Vec::new(),
            bottom: Vec::new(),
        }
    }

    /// Rows left for the body.
    pub(super) fn body_rows(&self) -> usize {
        self.rows.saturating_sub(1 + self.bottom.len())
    }

    pub(super) fn lines(self) -> Vec<String> {
        let n = self.body_rows();
        let mut out = vec![fit(&self.header, self.cols)];
        for i in 0..n {
            out.push(fit(
                self.body.get(i).map(|s| s.as_str()).unwrap_or(""),
                self.cols,
            ));
        }
        for b in &self.bottom {
            out.push(fit(b, self.cols));
        }
        out.truncate(self.rows);
        while out.len() < self.rows {
            out.push(fit("", self.cols));
        }
        out
    }
}

/// The display frame for the console's state.
pub(super) fn compose(c: &Console) -> Vec<String> {
    let rows = c.cfg.rows;
    let cols = c.cfg.cols;
    let loaded = c.status.run != 0 || c.status.job.is_some();
    if c.shell.shown.page != super::pages::Page::Mode {
        return super::pages::compose(c, rows, cols);
    }
    match c.shell.front.op {
        OpMode::Auto | OpMode::Single | OpMode::Mdi => run_page(c, rows, cols),
        OpMode::Data => data_page(c, rows, cols),
        _ if loaded => run_page(c, rows, cols),
        OpMode::Continuous | OpMode::Handle | OpMode::Step => manual_page(c, rows, cols),
    }
}

/// What the run page says first when the operator has moved the axes of a stopped run.
fn jogged_note(c: &Console) -> Option<String> {
    let job = c.status.job.as_ref()?;
    let to = job.return_to?;
    let s = &c.cfg.settings;
    if job.returning {
        return Some(format!(
            "returning to X{:.3} Y{:.3} Z{:.3}, where the run stopped",
            s.to_mm(to[0]),
            s.to_mm(to[1]),
            s.to_mm(to[2])
        ));
    }
    let pos = c.status.pos;
    if pos == to {
        return None;
    }
    let moved: Vec<String> = (0..3)
        .filter(|&a| pos[a] != to[a])
        .map(|a| format!("{}{:+.3}", ["X", "Y", "Z"][a], s.to_mm(pos[a] - to[a])))
        .collect();
    Some(format!(
        "JOGGED {}: START returns to X{:.3} Y{:.3} Z{:.3} first",
        moved.join(" "),
        s.to_mm(to[0]),
        s.to_mm(to[1]),
        s.to_mm(to[2])
    ))
}

/// The message line(s): [`message_text`] wrapped to `cols`, at most `max` lines.
pub(super) fn message_lines(c: &Console, cols: usize, max: usize) -> Vec<String> {
    wrap(&message_text(c), cols, max)
}

/// What the message line says: a note on a jogged run, what the machine is doing, then the
/// alarm, then the operator message (MTConnect's `message` too, `Console::message_line`).
pub(super) fn message_text(c: &Console) -> String {
    let mut parts: Vec<String> = Vec::new();
    if let Some(n) = jogged_note(c) {
        parts.push(n);
    }
    if let Some(n) = super::gcode_run::program_stop_note(c) {
        parts.push(n);
    }
    let alarm = c
        .status
        .alarm
        .clone()
        .or_else(|| {
            c.program_alarm
                .as_ref()
                .map(|a| format!("line {}:{}: {}", a.error.line, a.error.col, a.error.message))
        })
        .or_else(|| c.tape_alarm.clone());
    if let Some(n) = machine_note(c) {
        // E-STOP is both what the machine is doing and its alarm: said once, as the alarm
        // (before stop 41 the line said the same words twice).
        if n != c.shell.front.message && alarm.as_ref() != Some(&n) {
            parts.push(n);
        }
    }
    // The newest program message that lives until acknowledged, before the last action's.
    parts.extend(super::state::unacknowledged_line(
        &c.shell.book.unacknowledged,
    ));
    match alarm {
        Some(a) if !c.shell.front.message.contains(a.as_str()) => {
            if !c.shell.front.message.is_empty() {
                parts.push(c.shell.front.message.clone());
            }
            parts.push(format!("ALARM {a}"));
        }
        _ => {
            if !c.shell.front.message.is_empty() {
                parts.push(c.shell.front.message.clone());
            }
        }
    }
    parts.join(" / ")
}

/// The state line: RUN, mode, feed override, T, S (EP with the error-proportional
/// interpolator; HOLD / E-STOP; the overrides away from 100 % and the switches that are on:
/// RPD (rapid), SOV (spindle), DRY, MLK, ZNG).
pub(super) fn state_line(c: &Console) -> String {
    let mode = c.shell.front.op.names().short;
    let t = match c.status.tool {
        Some(t) => format!("T{t:02}"),
        None => "T--".into(),
    };
    let mut s = format!(
        "RUN {} {mode} OVR{:>3}% {t} S{}",
        c.status.run, c.shell.front.feed_override, c.status.spindle
    );
    // What the machine is doing comes before the switches, so a narrow display that cuts the
    // line (with its mark) never cuts ESTOP or HOLD.
    let lamps = lamps(c);
    if lamps.estop {
        s.push_str(" ESTOP");
    } else if lamps.hold {
        s.push_str(" HOLD");
    }
    s.push_str(&super::switch_words(
        &c.shell.front.switches,
        &c.status.switches,
    ));
    if c.cfg.settings.interpolator != crate::settings::Interpolator::Dda {
        // The error-proportional interpolator (seed 001); the DDA is the default, unmarked.
        s.push_str(" EP");
    }
    s
}

/// The run pages (AUTO, SINGLE BLOCK, MDI): the run the core has loaded, or what START will
/// run: the statement, its blocks with the executing one marked, the message and the state.
fn run_page(c: &Console, rows: usize, cols: usize) -> Vec<String> {
    let page = if c.shell.front.op == OpMode::Mdi {
        RunKind::Mdi
    } else {
        RunKind::Auto
    };
    let job = c.status.job.as_ref();
    let shown = job.filter(|j| {
        j.kind == page
            || !matches!(
                c.shell.front.op,
                OpMode::Auto | OpMode::Single | OpMode::Mdi
            )
    });
    let mut p = Page::new(rows, cols, String::new());
    // The message takes the lines it needs, up to a third of the display; the body the rest.
    p.bottom = message_lines(c, cols, (rows / 3).max(2));
    p.bottom.push(state_line(c));
    let n = p.body_rows();
    if let Some(j) = shown {
        let exec = c.status.executing.as_ref();
        p.header = match exec {
            Some(e) => format!("L{} {}", e.stmt.line, e.stmt.text.trim()),
            None => format!("{} run {}: reading the first block", j.kind.name(), j.id),
        };
        if let Some(e) = exec {
            let blocks = &e.stmt.blocks;
            let first = if blocks.len() <= n || e.index < n / 2 {
                0
            } else {
                (e.index - n / 2).min(blocks.len() - n)
            };
            // The executing block as the machine runs it, and the blocks after it as they will
            // run: a tool length revised during the run moves their Z (docs/panel.md).
            let executed = c
                .status
                .executed
                .as_ref()
                .filter(|x| blocks.get(e.index).is_some_and(|b| b.seq == x.seq));
            let mut z = executed.map(|x| x.end[2]);
            for (i, b) in blocks.iter().enumerate().skip(first).take(n) {
                let mark = if i == e.index { '>' } else { ' ' };
                let shown = match (i.cmp(&e.index), executed, z) {
                    (std::cmp::Ordering::Equal, Some(x), _) => x.clone(),
                    (std::cmp::Ordering::Greater, _, Some(z_now)) => {
                        let mut nb = b.clone();
                        crate::pulse_core::as_executed(&mut nb, c.status.length_shift, z_now);
                        z = Some(nb.end[2]);
                        nb
                    }
                    _ => b.clone(),
                };
                p.body
                    .push(format!("{mark}{}", iso_line(&shown, &c.cfg.settings)));
            }
        }
        return p.lines();
    }
    if let Some(j) = job {
        p.header = format!("{} run loaded: RESET to run {}", j.kind.name(), page.name());
    }
    // After an E-STOP, START is refused until RESET: the header does not invite it, and
    // says the line the E-STOP stopped the run in.
    // The line of this page's run an E-STOP stopped in, listed marked until RESET (the
    // lathe's channels keep theirs so too): before stop 48 the page went back to the top of
    // the program while the axes stood where the run stopped.
    let stopped = match c.status.estop_at {
        Some((kind, line)) if kind == page && line > 0 && job.is_none() => Some(line as usize),
        _ => None,
    };
    let go = match (c.status.estop, stopped) {
        (false, _) => "press START".to_string(),
        (true, None) => "RESET, then START".to_string(),
        (true, Some(line)) => format!("E-STOP in line {line}: RESET first"),
    };
    // `n` lines of `t` from its line `first` (0-based), or around the stopped line, marked.
    let listing = |t: Target, first: usize, n: usize| -> Vec<String> {
        let first = stopped.map_or(first, |l| (l - 1).saturating_sub(n / 2));
        let lines = c.mem.lines(t, first, n);
        (lines.iter().enumerate())
            .map(|(i, l)| {
                let mark = if stopped == Some(first + i + 1) {
                    '>'
                } else {
                    ' '
                };
                format!("{mark}{l}")
            })
            .collect()
    };
    match page {
        RunKind::Mdi => {
            if job.is_none() {
                p.header = format!("MDI buffer: {go}");
            }
            if c.mem.is_blank(Target::Mdi) {
                p.body.push("(MDI: nothing to run)".into());
            }
            p.body.extend(listing(Target::Mdi, 0, n));
        }
        RunKind::Auto => {
            let name = c.mem.program_name();
            let mut skip = 0;
            match &c.search {
                Some(sp) => {
                    if job.is_none() {
                        p.header = format!("{name} from line {}: {go}", sp.line);
                    }
                    skip = sp.line.saturating_sub(1) as usize;
                    if let Some(Ok(plan)) = &c.plan_shown {
                        p.body.extend(plan.rebuilt.iter().map(|l| format!("  {l}")));
                    }
                    match &c.plan_shown {
                        Some(Ok(plan)) if !plan.restore.is_empty() => {
                            p.body.push("restore first:".into());
                            for b in &plan.restore {
                                p.body.push(format!("  {}", iso_line(b, &c.cfg.settings)));
                            }
                        }
                        Some(Err(e)) => p.body.push(format!("SEARCH: {e}")),
                        _ => {}
                    }
                }
                None => {
                    if job.is_none() {
                        p.header = format!("{name}: {go}");
                    }
                }
            }
            if c.mem.is_blank(Target::Program) {
                p.body.push("(AUTO: nothing to run)".into());
            }
            if stopped.is_some() {
                // The SEARCH point's restore plan gives way to where the run stopped.
                p.body.clear();
            }
            let left = n.saturating_sub(p.body.len());
            p.body.extend(listing(Target::Program, skip, left));
        }
    }
    p.lines()
}

/// DATA INPUT pages, by data-processing mode.
fn data_page(c: &Console, rows: usize, cols: usize) -> Vec<String> {
    let name = c.data.name();
    let mut bottom = vec![format!("cmd: {}", c.last_line)];
    bottom.extend(message_lines(c, cols, (rows / 3).max(3)));
    let entry_room = cols.saturating_sub(3);
    let typed: Vec<char> = c.shell.front.entry.chars().collect();
    let shown: String = typed[typed.len().saturating_sub(entry_room)..]
        .iter()
        .collect();
    bottom.push(format!("> {shown}_"));
    let mut p = Page::new(rows, cols, String::new());
    p.bottom = bottom;
    let n = p.body_rows();
    match c.data {
        DataMode::Revise | DataMode::Mdi | DataMode::ToolRevise => {
            let target = match c.data {
                DataMode::Revise => Target::Program,
                DataMode::Mdi => Target::Mdi,
                _ => Target::ToolFile,
            };
            let what = match target {
                Target::Program => c.mem.program_name(),
                Target::Mdi => "buffer".into(),
                Target::ToolFile => "tool file".into(),
            };
            // Line numbers (the numbers SEARCH takes) in a gutter, when the screen has room.
            let count = c.mem.line_count(target).max(1);
            let digits = count.to_string().len().max(2);
            let gutter = if cols >= 30 { digits + 1 } else { 0 };
            let w = c.mem.window(target, n, cols.saturating_sub(2 + gutter));
            let number = |i: usize| -> String {
                match gutter {
                    0 => String::new(),
                    _ => format!("{:>digits$} ", w.first_line + i + 1),
                }
            };
            p.header = split_line(
                &format!("{name} {what}"),
                &format!(
                    "L{}/{}",
                    w.first_line + w.pointer_row + 1,
                    w.line_count.max(1)
                ),
                cols,
            );
            match &c.shell.front.y_output {
                Some(y) => {
                    for l in y.split_inclusive('\n').take(n) {
                        p.body.push(format!(" {}", l.replace('\n', "*")));
                    }
                }
                None => {
                    for (i, l) in w.lines.iter().enumerate() {
                        let mut chars: Vec<char> = l.chars().collect();
                        let pointer = (i == w.pointer_row).then_some(w.pointer_col);
                        // A line cut at either side says so, where the pointer is not.
                        if w.scrolled && !chars.is_empty() && pointer != Some(0) {
                            chars[0] = CUT;
                        }
                        let last = chars.len().saturating_sub(1);
                        if w.more.get(i) == Some(&true) && pointer.is_none_or(|c| c < last) {
                            if let Some(ch) = chars.last_mut() {
                                *ch = CUT;
                            }
                        }
                        match pointer {
                            Some(at) => {
                                chars.insert(at.min(chars.len()), POINTER);
                                p.body.push(format!(
                                    "{}>{}",
                                    number(i),
                                    chars.iter().collect::<String>()
                                ));
                            }
                            None => p.body.push(format!(
                                "{} {}",
                                number(i),
                                chars.iter().collect::<String>()
                            )),
                        }
                    }
                }
            }
        }
        DataMode::TCode => {
            let m = c.mem.magazine();
            p.header = split_line(
                name,
                &format!(
                    "{}/{} pockets",
                    m.tcodes.iter().count(),
                    m.tcodes.capacity()
                ),
                cols,
            );
            p.body = tool_lines(&m, c.tool_focus, n);
        }
        DataMode::ToolRead | DataMode::Read if c.tape_view().is_some() => {
            // The tape passing under the read head (docs/tape.md, "At the console").
            p.header = split_line(name, &tape_name(c), cols);
            p.body = super::tape::page_body(c, n, cols).unwrap_or_default();
        }
        DataMode::ToolRead => {
            let tape = tape_name(c);
            p.header = split_line(name, &tape, cols);
            let m = c.mem.magazine();
            p.body = c.read_report.clone();
            let left = n.saturating_sub(p.body.len());
            p.body.extend(tool_lines(&m, c.tool_focus, left));
        }
        DataMode::Read => {
            p.header = split_line(name, &tape_name(c), cols);
            p.body.push(format!(
                "program memory: {} ({} lines)",
                c.mem.program_name(),
                c.mem.line_count(Target::Program)
            ));
            for l in c.mem.lines(Target::Program, 0, n.saturating_sub(1)) {
                p.body.push(format!(" {l}"));
            }
        }
        DataMode::Search => {
            p.header = split_line(name, &c.mem.program_name(), cols);
            match &c.search {
                Some(sp) => {
                    p.body.push(format!(">L{} {}", sp.line, sp.text.trim()));
                    if let Some(Ok(plan)) = &c.plan_shown {
                        if !plan.rebuilt.is_empty() {
                            p.body.push(format!("state as read through L{}:", sp.line));
                            p.body.extend(plan.rebuilt.iter().map(|l| format!("  {l}")));
                        }
                    }
                    match &c.plan_shown {
                        Some(Ok(plan)) if plan.restore.is_empty() => p
                            .body
                            .push("nothing to restore: the machine is ready".into()),
                        Some(Ok(plan)) => {
                            p.body
                                .push("START restores first (machine as it is now):".into());
                            for b in &plan.restore {
                                p.body.push(format!("  {}", iso_line(b, &c.cfg.settings)));
                            }
                        }
                        Some(Err(e)) => p.body.push(format!("SEARCH: {e}")),
                        None => {}
                    }
                }
                None => {
                    p.body.push("AUTO starts at the top.".into());
                    p.body.push("Type a line number or text, EOB:".into());
                    p.body.push("AUTO will start at that statement.".into());
                }
            }
        }
    }
    p.lines()
}

/// The tape in the reader, for a header.
fn tape_name(c: &Console) -> String {
    match &c.tape {
        Some(t) => format!(
            "tape {}",
            t.file_name()
                .map(|n| n.to_string_lossy().into_owned())
                .unwrap_or_default()
        ),
        None => "reader empty".into(),
    }
}

/// One T code per line, `n` lines around `focus` (marked `>`).
pub fn tool_lines(m: &Magazine, focus: u32, n: usize) -> Vec<String> {
    let cap = m.tcodes.capacity();
    if n == 0 || cap == 0 {
        return Vec::new();
    }
    let focus = focus.clamp(1, cap);
    let first = focus
        .saturating_sub((n as u32) / 3)
        .max(1)
        .min(cap.saturating_sub(n as u32 - 1).max(1));
    (first..=cap)
        .take(n)
        .map(|t| {
            let mark = if t == focus { '>' } else { ' ' };
            let body = match m.tcodes.tool_in(t) {
                None => "-----".to_string(),
                Some(n) => match m.tools.get(t) {
                    Some(r) if r.number == n => format!(
                        "{n:05} {} D{} L{} S{} F{}",
                        r.kind.code(),
                        r.diameter,
                        r.set_length,
                        r.speed,
                        r.feed
                    ),
                    _ => format!("{n:05} (no data: TOOL DATA READ)"),
                },
            };
            format!("{mark}T{t:02} {body}")
        })
        .collect()
}

/// CONTINUOUS, HANDLE, STEP: positions, handwheel, tool and spindle.
fn manual_page(c: &Console, rows: usize, cols: usize) -> Vec<String> {
    let v = c.view();
    // The arrows jog X Y Z in mm; Alt+, and Alt+. the handwheel's axis, in degrees when it is
    // rotary: the increment is the same number of pulses on both.
    let unit = match c.cfg.settings.unit(v.wheel.0.index()) {
        "deg" => "mm/deg",
        u => u,
    };
    let tap = c.cfg.settings.to_mm(i64::from(v.wheel.1));
    let hint = match c.shell.front.op {
        OpMode::Continuous => format!("tap {tap:.3} {unit}, hold jogs"),
        OpMode::Step => format!("{tap:.3} {unit} (x{}) per jog key", v.wheel.1),
        _ => format!(
            "wheel {} {:.3} {} x{}",
            v.wheel.0.letter(),
            c.cfg.settings.to_mm(i64::from(v.wheel.1)),
            c.cfg.settings.unit(v.wheel.0.index()),
            v.wheel.1
        ),
    };
    let mut p = Page::new(
        rows,
        cols,
        split_line(op_name(c.shell.front.op), &hint, cols),
    );
    p.bottom = message_lines(c, cols, 2);
    p.bottom.push(state_line(c));
    for (i, a) in ["X", "Y", "Z"].iter().enumerate() {
        p.body.push(format!(
            "{a} {:>10.3}   tip {a} {:>10.3}",
            v.axis_mm[i], v.tip_mm[i]
        ));
    }
    for (r, deg) in &v.rotary_deg {
        p.body.push(format!("{r} {deg:>10.3} deg"));
    }
    p.lines()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fit_and_wrap_keep_widths() {
        assert_eq!(fit("abc", 5), "abc  ");
        assert_eq!(fit("abcdef", 4), "abc…");
        assert_eq!(split_line("L", "R", 5), "L   R");
        let w = wrap("one two three four", 9, 3);
        assert_eq!(w, vec!["one two", "three", "four"]);
        assert_eq!(wrap("abcdefghij", 4, 2), vec!["abcd", "efg…"]);
        assert_eq!(wrap("one two three", 20, 1), vec!["one two three"]);
        assert_eq!(wrap("one two three four", 9, 2), vec!["one two", "three…"]);
        assert_eq!(wrap("", 4, 2), vec![""]);
    }

    #[test]
    fn tool_lines_centre_on_the_focus_and_mark_it() {
        let m = crate::tooldata::sample_magazine();
        let l = tool_lines(&m, 10, 6);
        assert_eq!(l.len(), 6);
        assert!(l.iter().any(|s| s.starts_with(">T10 00209 TP")), "{l:?}");
        let l = tool_lines(&m, 24, 6);
        assert!(l.last().unwrap().starts_with(">T24 -----"), "{l:?}");
        let l = tool_lines(&m, 1, 3);
        assert!(l[0].starts_with(">T01 00610 BB"), "{l:?}");
    }
}
