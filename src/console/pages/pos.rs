//! POS: the positions (work, relative, machine, distance to go), the feed, the spindle, the jog
//! and the tool change, and the counters (docs/panel.md, "Pages").
//!
//! - WORK G54 (or G55 … G59.3, `G55+G92` with a G92 offset): the tool tip in work coordinates
//!   of the system the console's G-code state has in force: the axis position with Z less the
//!   length in force of the tool in the spindle, less that system's offset and the G92 offset.
//!   With no run loaded the system's offset is the one stored (what the next run selects, so an
//!   OFS edit shows at once, as on a Fanuc); during a G-code run, the one the run selected (an
//!   edit applies from the next run). The source language designates its origins per statement
//!   and leaves G54 zero. The XY rotation of G10 L2 R is not applied.
//! - TOOL: the tool in the spindle and its length in force; a length revised on OFS during a
//!   run that is not in force yet is shown under it, `T02 155.000 pending: next block` (`next
//!   run` for a G-code run, whose G43 read the old one).
//! - REL: the axis position less the relative origin the operator sets: `X` INPUT zeroes X
//!   (two keys), `X12.5` presets X to 12.5, `XYZ` (or `ORIGIN`) zeroes all three.
//! - MACH: the axis position in machine coordinates.
//! - TO GO: what is left of the block executing.
//!
//! - I/O (only once something is set): `I/O OUT P2 E3=2.5 IN P3`, the outputs M62–M68 set and
//!   the inputs M66 reads (digital ones on, analog ones not 0).
//!
//! Counters: `PARTS n` sets the part count, `TARGET n` its target (0: none).

use super::super::display::{message_lines, split_line, state_line, Page as Frame};
use super::Console;

/// A line typed on the POS page, read alike on every machine (docs/panel.md "Pages"): what it
/// asks for. Each machine applies it to its own positions and counters.
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum PosLine {
    /// Zero the relative position of these axes (indices into the machine's letters): two or
    /// more axis letters (`XYZ`, a lathe's `XZ`), or `ORIGIN` (every axis).
    Zero(Vec<usize>),
    /// Preset one axis's relative position, mm (`X12.5`; `X` alone zeroes it).
    Preset(usize, f64),
    /// `PARTS n`: the part count.
    Parts(u64),
    /// `TARGET n`: the part count's target (0: none).
    Target(u64),
    /// `JOG ...`: the rest of the line (`manual::JogChoice::take` reads it).
    Jog(String),
}

/// Reads a POS line on a machine whose axes are `letters` (the centre's X Y Z and its rotary
/// axes, a lathe's X Z). A line it cannot read gives the usage.
pub(crate) fn read_line(line: &str, letters: &[char]) -> Result<PosLine, String> {
    let l = line.trim().to_ascii_uppercase();
    let all: String = letters.iter().collect();
    if l == "ORIGIN" {
        return Ok(PosLine::Zero((0..letters.len()).collect()));
    }
    let index = |ch: char| letters.iter().position(|&x| x == ch);
    // Two or more axis letters, each once.
    let which: Vec<usize> = l.chars().filter_map(index).collect();
    let once = (which.iter().enumerate()).all(|(k, i)| !which[..k].contains(i));
    if which.len() >= 2 && which.len() == l.chars().count() && once {
        return Ok(PosLine::Zero(which));
    }
    if let Some(rest) = l.strip_prefix("JOG") {
        return Ok(PosLine::Jog(rest.trim().to_string()));
    }
    for word in ["PARTS", "TARGET"] {
        if let Some(rest) = l.strip_prefix(word) {
            let n = rest
                .trim()
                .parse::<u64>()
                .map_err(|_| format!("{word} takes a whole number: {word} 100"))?;
            return Ok(match word {
                "PARTS" => PosLine::Parts(n),
                _ => PosLine::Target(n),
            });
        }
    }
    let mut chars = l.chars();
    let Some(axis) = chars.next().and_then(index) else {
        let x = letters.first().copied().unwrap_or('X');
        return Err(format!(
            "POS: type {x} (zero the relative {x}), {x}12.5 (preset it), {all}, PARTS n, TARGET n, JOG 500 or JOG RAPID, then Enter"
        ));
    };
    let rest = chars.as_str().trim();
    if rest.is_empty() {
        return Ok(PosLine::Preset(axis, 0.0));
    }
    match rest.parse::<f64>() {
        Ok(v) if v.is_finite() && v.abs() <= 1e6 => Ok(PosLine::Preset(axis, v)),
        _ => Err(format!("'{rest}' is not a position in mm")),
    }
}

/// The POS page's axis table, every machine's: the work system's heading (`WORK G54`) over
/// the relative, machine and to-go columns, then a row an axis: its letter and the four
/// positions, mm (a lathe's X as a diameter).
pub(crate) fn axis_table(
    work: &str,
    rows: impl IntoIterator<Item = (char, [f64; 4])>,
) -> Vec<String> {
    let mut l = vec![format!(" {work:>9}{:>9}{:>9}{:>9}", "REL", "MACH", "TO GO")];
    l.extend(
        (rows.into_iter())
            .map(|(a, v)| format!("{a}{:>9.3}{:>9.3}{:>9.3}{:>9.3}", v[0], v[1], v[2], v[3])),
    );
    l
}

/// A POS refusal `e` with the selector at `op`: in MDI or DATA INPUT, where a line goes with
/// the page down, it says how to put the page down (an operator typing an MDI line under POS
/// sees why it is POS's).
pub(crate) fn refused_at(e: String, op: crate::panel_model::OpMode) -> String {
    use crate::panel_model::OpMode;
    match op {
        OpMode::Mdi | OpMode::Data => {
            format!("{e} (POS is up: Ctrl+P puts it down for {})", op.name())
        }
        _ => e,
    }
}

/// What setting the relative position said, on every machine: `relative X Y Z zeroed`,
/// `relative X preset to 12.500` (empty for a line that sets none).
pub(crate) fn rel_said(letters: &[char], line: &PosLine) -> String {
    match line {
        PosLine::Zero(which) => {
            let names: Vec<String> = which.iter().map(|&i| letters[i].to_string()).collect();
            format!("relative {} zeroed", names.join(" "))
        }
        PosLine::Preset(i, v) => format!("relative {} preset to {v:.3}", letters[*i]),
        _ => String::new(),
    }
}

/// A POS page command line: what it did, or why it is refused (nothing changed).
pub(super) fn enter(c: &mut Console, line: &str) -> Result<String, String> {
    let s = c.cfg.settings.clone();
    let pos = c.status.pos;
    let axes: Vec<usize> = s.axis_list().collect();
    let letters: Vec<char> = axes
        .iter()
        .map(|&a| crate::settings::AXIS_NAMES[a])
        .collect();
    let op = c.shell.front.op;
    let read = read_line(line, &letters).map_err(|e| refused_at(e, op))?;
    let said = rel_said(&letters, &read);
    match read {
        PosLine::Zero(which) => {
            for &i in &which {
                c.pages.rel_origin[axes[i]] = pos[axes[i]];
            }
            Ok(said)
        }
        PosLine::Preset(i, value) => {
            c.pages.rel_origin[axes[i]] = pos[axes[i]] - s.to_pulses(value);
            Ok(said)
        }
        PosLine::Parts(n) => c.shell.set_count(true, n, &c.cfg.state_dir),
        PosLine::Target(n) => c.shell.set_count(false, n, &c.cfg.state_dir),
        PosLine::Jog(rest) => jog(c, &rest),
    }
}

/// `JOG 500` (the jog feed, mm/min, up to the rapid rate), `JOG RAPID` (rapid jog), `JOG`
/// (back to the jog feed from rapid jog).
fn jog(c: &mut Console, rest: &str) -> Result<String, String> {
    c.posmem.jog.take(rest, c.cfg.settings.rapid_mm_min)?;
    let f = super::super::posmem::jog_feed(c);
    c.core.set_jog_feed(f);
    Ok(c.posmem.jog.said(f))
}

/// POS's jog line on every machine: the jog feed in force `f` (RAPID with rapid jog) and the
/// increment of STEP and HANDLE, `step` mm.
pub(crate) fn jog_line(jog: &crate::console::manual::JogChoice, f: f64, step: f64) -> String {
    let rapid = if jog.rapid { " RAPID" } else { "" };
    format!("JOG{rapid} {f:.0} mm/min STEP {step:.3} mm")
}

/// The POS page.
pub(super) fn compose(c: &Console, rows: usize, cols: usize) -> Vec<String> {
    let s = &c.cfg.settings;
    let st = &c.status;
    let mut p = Frame::new(
        rows,
        cols,
        split_line("POS", "X12.5 / X: rel preset, zero", cols),
    );
    p.bottom = message_lines(c, cols, (rows / 4).max(1));
    p.bottom.push(state_line(c));
    let togo = st
        .executing
        .as_ref()
        .filter(|_| st.in_block)
        .and_then(|e| e.block())
        .map(|b| crate::block::Axes::from_fn(|a| b.end[a] - st.pos[a]))
        .unwrap_or_default();
    let (in_force, pending) = length_in_force(c);
    let (name, origin) = work_origin(c);
    let origin_abc = rotary_work_offset(c);
    let rows = s.axis_list().map(|a| {
        // A rotary axis's WORK is its machine position less its work and G92 offsets
        // (docs/gcode.md "Rotary axes").
        let o = match a.checked_sub(crate::block::FIRST_ROTARY) {
            Some(r) => origin_abc[r],
            None => origin[a],
        };
        let work = st.pos[a] - s.to_pulses(o);
        let row = [work, st.pos[a] - c.pages.rel_origin[a], st.pos[a], togo[a]];
        (crate::settings::AXIS_NAMES[a], row.map(|p| s.to_mm(p)))
    });
    p.body.extend(axis_table(&name, rows));
    // The I/O, when a program or a script has set any: the outputs M62-M68 set, the inputs M66
    // reads (digital ones on, analog ones not 0).
    let (outs, ins) = (signal_list(&st.outputs), signal_list(&st.inputs));
    if !(outs.is_empty() && ins.is_empty()) {
        let none = |l: String| if l.is_empty() { "-".to_string() } else { l };
        p.body
            .push(format!("I/O OUT {} IN {}", none(outs), none(ins)));
    }
    let feed = st
        .executing
        .as_ref()
        .filter(|_| st.in_block)
        .and_then(|e| e.block())
        .map_or(0.0, |b| b.feed);
    let oriented;
    let dir = match (st.spindle, st.orient) {
        (0, Some(a)) => {
            oriented = format!("oriented M19 R{}", crate::input_text::short_number(a));
            oriented.as_str()
        }
        (0, None) => "stopped",
        (s, _) if s > 0 => "CW M03",
        _ => "CCW M04",
    };
    p.body.push(format!(
        "F {feed:.0} act {:.0} S {} {dir}",
        st.speed_mm_min,
        st.spindle.abs()
    ));
    p.body.push(jog_line(
        &c.posmem.jog,
        super::super::posmem::jog_feed(c),
        s.to_mm(c.shell.front.wheel.1 as i64),
    ));
    let tool = match (st.tool, st.changing_tool) {
        (_, Some(t)) => format!("TOOL CHANGE to T{t:02} in progress"),
        (Some(t), None) => format!("TOOL T{t:02} length {in_force:.3}"),
        (None, None) => "TOOL none".to_string(),
    };
    p.body.push(tool);
    if let (Some(t), None, Some((v, when))) = (st.tool, st.changing_tool, pending) {
        p.body.push(format!("  T{t:02} {v:.3} pending: {when}"));
    }
    let k = &c.shell.book.counters;
    let target = if k.target > 0 {
        format!("/{}", k.target)
    } else {
        String::new()
    };
    p.body
        .push(format!("PARTS {}{target} {}", k.parts, k.times()));
    p.lines()
}

/// The signals that are set: `P1 P2 E3=2.5` (digital ones on, analog ones not 0).
fn signal_list(s: &crate::pulse_core::Signals) -> String {
    let digital = (0..64u32)
        .filter(|&i| s.digital & (1 << i) != 0)
        .map(|i| format!("P{i}"));
    let analog = s
        .analog
        .iter()
        .enumerate()
        .filter(|(_, &v)| v != 0.0)
        .map(|(i, v)| format!("E{i}={}", crate::input_text::short_number(*v)));
    digital.chain(analog).collect::<Vec<_>>().join(" ")
}

/// The work system's heading (`WORK G55`, `G55+G92`) and its zero with the G92 offset,
/// machine mm: the system the console's G-code state has in force; its stored offset with no
/// run loaded, the one the G-code run selected during a run.
fn work_system(c: &Console) -> (String, [f64; 3]) {
    let st = &c.interp;
    let cs = st.modal.cs;
    let sys = crate::gcode::state::SYSTEM_NAMES
        .get(cs)
        .copied()
        .unwrap_or("G54");
    let origin = if c.status.job.is_some() {
        st.origin
    } else {
        c.mem.system_offset(cs)
    };
    let g92 = st.g92 != [0.0; 3];
    let name = match (g92, sys.len()) {
        (true, _) => format!("{sys}+G92"),
        (false, n) if n <= 4 => format!("WORK {sys}"),
        (false, _) => sys.to_string(),
    };
    let zero = [0, 1, 2].map(|a| origin[a] + st.g92[a]);
    (name, zero)
}

/// What is subtracted from the rotary axes' machine positions to give their WORK positions,
/// degrees: the system's offset and G92's, as `work_system` takes them for X Y Z.
pub(crate) fn rotary_work_offset(c: &Console) -> [f64; 3] {
    let st = &c.interp;
    let s = &c.cfg.settings;
    let b = crate::gcode::state::system_base(st.modal.cs);
    std::array::from_fn(|r| {
        if !s.rotary(crate::block::FIRST_ROTARY + r) {
            return 0.0;
        }
        let system = if c.status.job.is_some() {
            st.origin_abc[r]
        } else {
            c.mem.param(b + 4 + r)
        };
        system + st.g92_abc[r]
    })
}

/// The work system's heading and what is subtracted from the axis position (machine mm) to
/// give the tool tip in that system, as the WORK column shows it: the system's zero with the
/// G92 offset, and on Z the length in force of the tool in the spindle (the MTConnect adapter's
/// `Xact`/`Yact`/`Zact` use it too).
pub(crate) fn work_origin(c: &Console) -> (String, [f64; 3]) {
    let (name, zero) = work_system(c);
    let (len, _) = length_in_force(c);
    (name, [zero[0], zero[1], zero[2] + len])
}

/// The length in force of the tool in the spindle (mm), and a revised one not yet in force
/// with when it applies.
pub(in crate::console) fn length_in_force(c: &Console) -> (f64, Option<(f64, &'static str)>) {
    let st = &c.status;
    match &c.pages.pending_len {
        Some(p)
            if st.job.is_some()
                && st.tool == Some(p.tool)
                && (p.gcode || st.blocks_done == p.blocks_done) =>
        {
            let when = if p.gcode { "next run" } else { "next block" };
            (p.in_force, Some((p.revised, when)))
        }
        // With no run loaded, the tool file's length is what the next run takes (an OFS
        // edit reaches the pulse core at START).
        _ if st.job.is_none() => {
            let m = c.mem.magazine();
            let len = st.tool.and_then(|t| m.tools.get(t)).map(|r| r.length());
            (len.unwrap_or(st.tool_set_length), None)
        }
        _ => (st.tool_set_length, None),
    }
}

#[cfg(test)]
mod tests {
    use super::{read_line, PosLine};

    #[test]
    fn a_pos_line_is_read_alike_on_every_machine() {
        let centre = ['X', 'Y', 'Z', 'A'];
        let lathe = ['X', 'Z'];
        assert_eq!(read_line("xyz", &centre), Ok(PosLine::Zero(vec![0, 1, 2])));
        assert_eq!(read_line("ORIGIN", &lathe), Ok(PosLine::Zero(vec![0, 1])));
        assert_eq!(read_line("ZX", &lathe), Ok(PosLine::Zero(vec![1, 0])));
        assert_eq!(read_line("A90", &centre), Ok(PosLine::Preset(3, 90.0)));
        assert_eq!(read_line(" z ", &lathe), Ok(PosLine::Preset(1, 0.0)));
        assert_eq!(read_line("TARGET 5", &lathe), Ok(PosLine::Target(5)));
        assert_eq!(
            read_line("JOG 500", &centre),
            Ok(PosLine::Jog("500".into()))
        );
        // A letter twice is not a zero of both; an axis the machine lacks is not one.
        assert_eq!(
            read_line("XZX", &lathe),
            Err("'ZX' is not a position in mm".into())
        );
        let usage = read_line("Y1", &lathe).unwrap_err();
        assert!(
            usage.starts_with("POS: type X") && usage.contains(" XZ, "),
            "{usage}"
        );
        assert!(usage.contains("JOG 500 or JOG RAPID"), "{usage}");
        assert_eq!(read_line("jog", &lathe), Ok(PosLine::Jog(String::new())));
        assert!(read_line("X1e9", &centre).is_err());
        assert!(read_line("PARTS -1", &centre).is_err());
    }
}
