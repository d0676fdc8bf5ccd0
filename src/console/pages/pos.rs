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

/// A POS page command line: what it did, or why it is refused (nothing changed).
pub(super) fn enter(c: &mut Console, line: &str) -> Result<String, String> {
    let l = line.trim().to_ascii_uppercase();
    let s = c.cfg.settings.clone();
    let pos = c.status.pos;
    if l == "XYZ" || l == "ORIGIN" {
        c.pages.rel_origin = pos;
        return Ok("relative X Y Z zeroed".into());
    }
    if let Some(rest) = l.strip_prefix("JOG") {
        return jog(c, rest.trim());
    }
    for (word, set) in [("PARTS", true), ("TARGET", false)] {
        if let Some(rest) = l.strip_prefix(word) {
            let n = rest
                .trim()
                .parse::<u64>()
                .map_err(|_| format!("{word} takes a whole number: {word} 100"))?;
            let was = c.shell.book.counters;
            if set {
                c.shell.book.counters.parts = n;
            } else {
                c.shell.book.counters.target = n;
            }
            if let Err(e) = c.shell.book.counters.save(&c.cfg.state_dir) {
                // Not kept: nothing changed.
                c.shell.book.counters = was;
                return Err(e);
            }
            return Ok(format!("{} {n}", word.to_ascii_lowercase()));
        }
    }
    let mut chars = l.chars();
    let axis = match chars.next() {
        Some('X') => 0,
        Some('Y') => 1,
        Some('Z') => 2,
        _ => return Err("POS: type X (zero the relative X), X12.5 (preset it), XYZ, PARTS n, TARGET n, JOG 500 or JOG RAPID, then Enter".into()),
    };
    let rest: String = chars.collect();
    let value = if rest.trim().is_empty() {
        0.0
    } else {
        match rest.trim().parse::<f64>() {
            Ok(v) if v.is_finite() && v.abs() <= 1e6 => v,
            _ => return Err(format!("'{}' is not a position in mm", rest.trim())),
        }
    };
    c.pages.rel_origin[axis] = pos[axis] - s.to_pulses(value);
    Ok(format!(
        "relative {} preset to {value:.3}",
        ["X", "Y", "Z"][axis]
    ))
}

/// `JOG 500` (the jog feed, mm/min, up to the rapid rate), `JOG RAPID` (rapid jog), `JOG`
/// (back to the jog feed from rapid jog).
fn jog(c: &mut Console, rest: &str) -> Result<String, String> {
    let rapid = c.cfg.settings.rapid_mm_min;
    if rest == "RAPID" {
        c.posmem.rapid_jog = true;
    } else if rest.is_empty() {
        c.posmem.rapid_jog = false;
    } else {
        match rest.parse::<f64>() {
            Ok(v) if v.is_finite() && v >= 1.0 && v <= rapid => {
                c.posmem.jog_feed = Some(v);
                c.posmem.rapid_jog = false;
            }
            _ => {
                return Err(format!(
                    "JOG refused: '{rest}' is not a jog feed (1 to {rapid:.0} mm/min), or RAPID"
                ))
            }
        }
    }
    let f = super::super::posmem::jog_feed(c);
    c.core.set_jog_feed(f);
    Ok(if c.posmem.rapid_jog {
        format!("rapid jog: {f:.0} mm/min")
    } else {
        format!("jog feed {f:.0} mm/min")
    })
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
    p.body.push(format!(
        " {:>9}{:>9}{:>9}{:>9}",
        name, "REL", "MACH", "TO GO"
    ));
    for a in s.axis_list() {
        // A rotary axis's WORK is its machine position less its work and G92 offsets
        // (docs/gcode.md "Rotary axes").
        let o = match a.checked_sub(crate::block::FIRST_ROTARY) {
            Some(r) => origin_abc[r],
            None => origin[a],
        };
        let work = st.pos[a] - s.to_pulses(o);
        p.body.push(format!(
            "{}{:>9.3}{:>9.3}{:>9.3}{:>9.3}",
            crate::settings::AXIS_NAMES[a],
            s.to_mm(work),
            s.to_mm(st.pos[a] - c.pages.rel_origin[a]),
            s.to_mm(st.pos[a]),
            s.to_mm(togo[a])
        ));
    }
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
    let rapid = if c.posmem.rapid_jog { " RAPID" } else { "" };
    p.body.push(format!(
        "JOG{rapid} {:.0} mm/min STEP {:.3} mm",
        super::super::posmem::jog_feed(c),
        s.to_mm(c.shell.front.wheel.1 as i64)
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
