//! MODAL (Ctrl-G): the modal state in force, as Fanuc's PROGRAM CHECK / MODAL screen and
//! LinuxCNC's "Active G-codes" show it: the active G codes of every modal group, F, S, T, H, D,
//! the offsets in force (the work system's zero, G92, the tool length), then the overrides and
//! the switches. The G-code state is the console's (what MDI and the last run left, the run's
//! own once a G-code run has started a block). Read only: MDI sets the state.

use super::super::display::{message_lines, split_line, state_line, wrap, Page as Frame};
use super::super::search::state_lines;
use super::Console;
use crate::panel_model::OpMode;

/// The overrides and switches, as (name, setting): one list, so a new override or switch is
/// one more entry.
fn switches(c: &Console) -> Vec<(&'static str, String)> {
    let s = &c.status.switches;
    let panel = (
        c.shell.front.op == OpMode::Single,
        c.shell.front.switches.block_delete,
        c.shell.front.switches.optional_stop,
    );
    let mut l = switch_list(c.shell.front.feed_override, s, panel);
    let on = |b: bool| if b { "ON" } else { "off" }.to_string();
    l.insert(4, ("MACHINE LOCK", on(s.machine_lock)));
    l.insert(5, ("Z NEGLECT", on(s.z_neglect)));
    l
}

/// The overrides and the switches every machine has, as (name, setting), for the MODAL pages
/// (the centre's, a lathe channel's): the feed override, the machine's `sw` (a tap holding
/// them at 100 % said), then DRY RUN, SINGLE BLOCK, BLOCK DELETE and OPTIONAL STOP
/// (`panel`: single block, block delete, optional stop).
pub(crate) fn switch_list(
    feed_override: u32,
    sw: &crate::record::Switches,
    (single, block_delete, optional_stop): (bool, bool, bool),
) -> Vec<(&'static str, String)> {
    let on = |b: bool| if b { "ON" } else { "off" }.to_string();
    let locked = if sw.override_locked {
        " (held 100%: tap)"
    } else {
        ""
    };
    vec![
        ("FEED OVR", format!("{feed_override}%{locked}")),
        (
            "RAPID OVR",
            match sw.rapid_override {
                0 => "F0".to_string(),
                p => format!("{p}%"),
            },
        ),
        ("SPINDLE OVR", format!("{}%{locked}", sw.spindle_override)),
        ("DRY RUN", on(sw.dry_run)),
        ("SINGLE BLOCK", on(single)),
        ("BLOCK DELETE", on(block_delete)),
        ("OPT STOP M01", on(optional_stop)),
    ]
}

/// The settings `list` joined two blanks apart into lines of at most `cols` characters, each
/// whole on its line.
pub(crate) fn setting_lines(list: &[(&str, String)], cols: usize) -> Vec<String> {
    let mut out = Vec::new();
    let mut line = String::new();
    for (n, v) in list {
        let s = format!("{n} {v}");
        if !line.is_empty() && line.chars().count() + 2 + s.chars().count() > cols {
            out.push(std::mem::take(&mut line));
        }
        if !line.is_empty() {
            line.push_str("  ");
        }
        line.push_str(&s);
    }
    if !line.is_empty() {
        out.push(line);
    }
    out
}

/// Words joined with blanks into lines of at most `cols` characters (none for no words).
pub(crate) fn fill(words: &[&str], cols: usize) -> Vec<String> {
    if words.is_empty() {
        return Vec::new();
    }
    wrap(&words.join(" "), cols, usize::MAX)
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
    p.body.extend(setting_lines(&switches(c), cols));
    p.lines()
}
