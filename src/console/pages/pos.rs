//! POS: the positions (work, relative, machine, distance to go), the feed, the spindle, the jog
//! and the tool change, and the counters (docs/panel.md, "Pages").
//!
//! - WORK G54: the tool tip in work coordinates: the axis position with Z less the length of the
//!   tool in the spindle, less the G54 work offset (G-code's system at the start of a program;
//!   zero unless set on the OFS page or by G10; the source language designates its origins per
//!   statement and leaves it zero). The heading names G54 because the page cannot see which
//!   system a G-code run has selected since (the source reads ahead of the machine).
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

/// A POS page command line.
pub(super) fn enter(c: &mut Console, line: &str) {
    let l = line.trim().to_ascii_uppercase();
    let s = c.cfg.settings.clone();
    let pos = c.status.pos;
    if l == "XYZ" || l == "ORIGIN" {
        c.pages.rel_origin = pos;
        c.message = "relative X Y Z zeroed".into();
        return;
    }
    for (word, set) in [("PARTS", true), ("TARGET", false)] {
        if let Some(rest) = l.strip_prefix(word) {
            match rest.trim().parse::<u64>() {
                Ok(n) => {
                    if set {
                        c.pages.counters.parts = n;
                    } else {
                        c.pages.counters.target = n;
                    }
                    c.message = match c.pages.counters.save(&c.cfg.state_dir) {
                        Ok(()) => format!("{} {n}", word.to_ascii_lowercase()),
                        Err(e) => e,
                    };
                }
                Err(_) => c.message = format!("{word} takes a whole number: {word} 100"),
            }
            return;
        }
    }
    let mut chars = l.chars();
    let axis = match chars.next() {
        Some('X') => 0,
        Some('Y') => 1,
        Some('Z') => 2,
        _ => {
            c.message = "POS: type X (zero the relative X), X12.5 (preset it), XYZ, PARTS n or TARGET n, then Enter".into();
            return;
        }
    };
    let rest: String = chars.collect();
    let value = if rest.trim().is_empty() {
        0.0
    } else {
        match rest.trim().parse::<f64>() {
            Ok(v) if v.is_finite() && v.abs() <= 1e6 => v,
            _ => {
                c.message = format!("'{}' is not a position in mm", rest.trim());
                return;
            }
        }
    };
    c.pages.rel_origin[axis] = pos[axis] - s.to_pulses(value);
    c.message = format!("relative {} preset to {value:.3}", ["X", "Y", "Z"][axis]);
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
        .map(|b| {
            [
                b.end[0] - st.pos[0],
                b.end[1] - st.pos[1],
                b.end[2] - st.pos[2],
            ]
        })
        .unwrap_or([0; 3]);
    let len = s.to_pulses(st.tool_set_length);
    p.body.push(format!(
        " {:>9}{:>9}{:>9}{:>9}",
        "WORK G54", "REL", "MACH", "TO GO"
    ));
    let g54 = c.mem.work_offsets().0[0];
    for a in 0..3 {
        let work = st.pos[a] - if a == 2 { len } else { 0 } - s.to_pulses(g54[a]);
        p.body.push(format!(
            "{}{:>9.3}{:>9.3}{:>9.3}{:>9.3}",
            ["X", "Y", "Z"][a],
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
    let dir = match st.spindle {
        0 => "stopped",
        s if s > 0 => "CW M03",
        _ => "CCW M04",
    };
    p.body.push(format!(
        "F {feed:.0} act {:.0} S {} {dir}",
        st.speed_mm_min,
        st.spindle.abs()
    ));
    p.body.push(format!(
        "JOG {:.0} mm/min STEP {:.3} mm",
        s.jog_mm_min,
        s.to_mm(c.wheel.1 as i64)
    ));
    let tool = match (st.tool, st.changing_tool) {
        (_, Some(t)) => format!("TOOL CHANGE to T{t:02} in progress"),
        (Some(t), None) => format!("TOOL T{t:02} length {:.3}", st.tool_set_length),
        (None, None) => "TOOL none".to_string(),
    };
    p.body.push(tool);
    let k = &c.pages.counters;
    let target = if k.target > 0 {
        format!("/{}", k.target)
    } else {
        String::new()
    };
    p.body.push(format!(
        "PARTS {}{target} CYCLE {:.1} s RUN {:.2} h",
        k.parts,
        k.last_cycle_ns as f64 / 1e9,
        k.run_ns as f64 / 3.6e12
    ));
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
