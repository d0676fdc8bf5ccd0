//! MODAL (Ctrl-G): the modal state in force, as Fanuc's PROGRAM CHECK / MODAL screen and
//! LinuxCNC's "Active G-codes" show it: the active G codes of every modal group, F, S, T, H, D,
//! the offsets in force (the work system's zero, G92, the tool length), then the overrides and
//! the switches. The G-code state is the console's (what MDI and the last run left, the run's
//! own once a G-code run has started a block). Read only: MDI sets the state.

use super::super::display::{message_lines, split_line, state_line, Page as Frame};
use super::super::search::state_lines;
use super::Console;
use crate::panel_model::OpMode;

/// The overrides and switches, as (name, setting): one list, so a new override or switch is
/// one more entry.
fn switches(c: &Console) -> Vec<(&'static str, String)> {
    let on = |b: bool| if b { "ON" } else { "off" }.to_string();
    let s = &c.status;
    let locked = if s.switches.override_locked {
        " (held 100%: tap)"
    } else {
        ""
    };
    vec![
        ("FEED OVR", format!("{}%{locked}", c.feed_override)),
        (
            "RAPID OVR",
            match s.switches.rapid_override {
                0 => "F0".to_string(),
                p => format!("{p}%"),
            },
        ),
        (
            "SPINDLE OVR",
            format!("{}%{locked}", s.switches.spindle_override),
        ),
        ("DRY RUN", on(s.switches.dry_run)),
        ("MACHINE LOCK", on(s.switches.machine_lock)),
        ("Z NEGLECT", on(s.switches.z_neglect)),
        ("SINGLE BLOCK", on(c.op == OpMode::Single)),
        ("BLOCK DELETE", on(c.switches.block_delete)),
        ("OPT STOP M01", on(c.switches.optional_stop)),
    ]
}

/// Words joined with blanks into lines of at most `cols` characters.
pub(super) fn fill(words: &[&str], cols: usize) -> Vec<String> {
    let mut out = Vec::new();
    let mut line = String::new();
    for w in words {
        if !line.is_empty() && line.chars().count() + 1 + w.chars().count() > cols {
            out.push(std::mem::take(&mut line));
        }
        if !line.is_empty() {
            line.push(' ');
        }
        line.push_str(w);
    }
    if !line.is_empty() {
        out.push(line);
    }
    out
}

/// The MODAL page.
pub(super) fn compose(c: &Console, rows: usize, cols: usize) -> Vec<String> {
    let mut p = Frame::new(rows, cols, split_line("MODAL", "the state in force", cols));
    p.bottom = message_lines(c, cols, (rows / 4).max(1));
    p.bottom.push(state_line(c));
    let st = &c.interp;
    let lines = state_lines(st);
    // The G codes of the modal groups, then the offsets and the tool/spindle line.
    for l in &lines {
        let words: Vec<&str> = l.split_whitespace().collect();
        p.body.extend(fill(&words, cols));
    }
    let h = st
        .tlo_tool
        .map_or("H--".to_string(), |t| format!("H{t:02}"));
    let d = st
        .comp_tool
        .map_or("D--".to_string(), |t| format!("D{t:02}"));
    p.body.push(format!("{h} {d} R{:.3}", st.comp_radius));
    // The machine's own: the tool in the spindle and the spindle speed (a source-language run
    // does not change the G-code state above).
    let m = &c.status;
    let tool = m.tool.map_or("T--".to_string(), |t| format!("T{t:02}"));
    let oriented = m.orient.map_or(String::new(), |a| {
        format!(" ORIENTED M19 R{}", crate::input_text::short_number(a))
    });
    p.body
        .push(format!("SPINDLE {tool} S{}{oriented}", m.spindle));
    let sw: Vec<String> = switches(c)
        .into_iter()
        .map(|(n, v)| format!("{n} {v}"))
        .collect();
    // Each setting whole on its line: join with two blanks.
    let mut line = String::new();
    for s in &sw {
        if !line.is_empty() && line.chars().count() + 2 + s.chars().count() > cols {
            p.body.push(std::mem::take(&mut line));
        }
        if !line.is_empty() {
            line.push_str("  ");
        }
        line.push_str(s);
    }
    if !line.is_empty() {
        p.body.push(line);
    }
    p.lines()
}
