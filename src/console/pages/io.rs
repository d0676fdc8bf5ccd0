//! I/O (Ctrl-T): the machine's signals, as a Fanuc's PMC signal status page (DGN) shows them:
//! the outputs a program set (M62–M65 digital, M67/M68 analog) and the simulated inputs M66
//! reads (docs/panel.md "Pages"). The digital signals are rows of 16 bits, signal 0 first
//! (`1` on, `.` off); the analog ones that are not 0 are listed with their values.
//!
//! Typing `P3 ON`, `P3 OFF` or `E2 4.5` and INPUT sets an input, as the script word
//! `input P3 on` does (one parser, `PanelEvent::parse_input`): it is a simulated machine's
//! switch, which a real control's diagnosis page can only show. The outputs are the program's.

use super::super::display::{message_lines, split_line, state_line, Page as Frame};
use super::Console;
use crate::panel_model::PanelEvent;
use crate::pulse_core::Signals;

/// 16 digital signals from `from`, in two groups of 8: `1` on, `.` off.
fn bits(s: &Signals, from: usize) -> String {
    let mut out = String::with_capacity(17);
    for i in from..from + 16 {
        if i == from + 8 {
            out.push(' ');
        }
        out.push(if s.digital >> i & 1 == 1 { '1' } else { '.' });
    }
    out
}

/// The analog signals that are not 0: `E3=4.5 E7=-1.25`, or `all 0`.
fn analog(s: &Signals) -> String {
    let set: Vec<String> = (0..64)
        .filter(|&i| s.analog[i] != 0.0)
        .map(|i| format!("E{i}={}", crate::input_text::short_number(s.analog[i])))
        .collect();
    if set.is_empty() {
        "all 0".into()
    } else {
        set.join(" ")
    }
}

/// The I/O page.
pub(super) fn compose(c: &Console, rows: usize, cols: usize) -> Vec<String> {
    let mut p = Frame::new(rows, cols, split_line("I/O", "outputs / inputs", cols));
    p.bottom = message_lines(c, cols, (rows / 4).max(1));
    p.bottom.push(state_line(c));
    let (o, i) = (&c.status.outputs, &c.status.inputs);
    p.body.push("   OUT P M62-M65     IN P  M66".into());
    for from in (0..64).step_by(16) {
        p.body
            .push(format!("{from:2} {}  {}", bits(o, from), bits(i, from)));
    }
    // The analog signals, named as the digital ones are: outputs set by M67/M68, inputs that
    // M66 E waits on.
    for (name, s) in [("OUT E M67-M68", o), ("IN E M66", i)] {
        let line = format!("{name} {}", analog(s));
        p.body.extend(super::modal::fill(
            &line.split_whitespace().collect::<Vec<_>>(),
            cols,
        ));
    }
    p.lines()
}

/// INPUT on the I/O page: `P3 ON`, `P3 OFF` or `E2 4.5` sets a simulated input.
pub(super) fn enter(c: &mut Console, line: &str) -> Result<String, String> {
    let words: Vec<&str> = line.split_whitespace().collect();
    let ev = PanelEvent::parse_input(&words)
        .map_err(|e| format!("I/O: refused: {e} (type P3 ON, P3 OFF or E2 4.5, then INPUT)"))?;
    let said = format!("I/O: {}", super::super::script_line::script_line(&ev));
    super::super::tape::apply(c, ev);
    Ok(said)
}
