//! MACRO (Ctrl-U): the Fanuc dialect's variables, as a Fanuc's macro variable page shows them
//! (docs/panel.md "Pages"): the locals #1–#33 as the interpreter left them (the main
//! program's level between runs), the common #100–#199 and the kept #500–#999, one a row, a
//! vacant (null) one blank. Up/Down move the cursor, PageUp/PageDown a screenful, Home/End
//! to #1/#999. As on OFS: a value typed then INPUT sets the variable under the cursor, +INPUT
//! adds to it; `#500=12.5` INPUT sets the one it names from any row (`#500=` makes it
//! vacant); `#500` alone moves the cursor there. A write to #500–#999 is journaled with the
//! stores' parameters, as a program's `#500=` is; it is taken with the machine at rest (as
//! OFS's) and a G-code run reads it from its next START.

use super::super::display::{message_lines, split_line, Page as Frame};
use super::Console;
use crate::gcode::state::is_fanuc_kept;
use crate::settings::Dialect;

/// The variables listed, in order.
fn numbers() -> impl Iterator<Item = usize> {
    (1..=33).chain(100..=199).chain(500..=999)
}

/// Whether the page lists variable `n`.
fn listed(n: usize) -> bool {
    matches!(n, 1..=33 | 100..=199 | 500..=999)
}

/// The variable under the cursor after key `k`, from `var`, `rows` a screenful (every console's
/// MACRO page: the centre's, and a lathe channel's).
pub(crate) fn cursor_moved(var: usize, k: novanc_panel::Key, rows: usize) -> usize {
    use novanc_panel::Key;
    let all: Vec<usize> = numbers().collect();
    let at = all.iter().position(|&n| n == var).unwrap_or(0);
    let page = rows.max(1);
    let to = match k {
        Key::Up => at.saturating_sub(1),
        Key::Down => at + 1,
        Key::PageUp => at.saturating_sub(page),
        Key::PageDown => at + page,
        Key::Home => 0,
        Key::End => all.len() - 1,
        _ => at,
    };
    all[to.min(all.len() - 1)]
}

/// A number typed for a variable (empty: vacant).
fn value(text: &str) -> Result<f64, String> {
    let t = text.trim();
    if t.is_empty() {
        return Ok(f64::NAN);
    }
    t.parse::<f64>()
        .ok()
        .filter(|v| v.is_finite() && v.abs() < 1e12)
        .ok_or_else(|| format!("'{t}' is not a value (a number below 10^12, or nothing: vacant)"))
}

/// What a line INPUT on a MACRO page asks: the cursor to a variable, or a variable set.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Input {
    /// `#500` alone: the cursor there.
    Cursor(usize),
    /// Variable `n` set to the value (NaN: vacant).
    Set(usize, f64),
}

/// A line INPUT (or +INPUT with `add`) on a MACRO page whose cursor is on `var`, over the
/// variables `params`, on every console: what it asks, or why it is refused.
pub(crate) fn input(line: &str, var: usize, params: &[f64], add: bool) -> Result<Input, String> {
    let t = line.trim();
    let (n, text) = match t.strip_prefix('#') {
        Some(rest) => {
            let (num, val) = match rest.split_once('=') {
                Some((a, b)) => (a.trim(), Some(b)),
                None => (rest.trim(), None),
            };
            let n = match num.parse::<usize>() {
                Ok(n) if listed(n) => n,
                _ => return Err(format!(
                    "MACRO refused: '#{num}' is not a variable of this page (#1-#33, #100-#199, #500-#999)"
                )),
            };
            match val {
                Some(v) => (n, v),
                None => return Ok(Input::Cursor(n)),
            }
        }
        None if t.is_empty() => return Err("MACRO: type a value, or #500=12.5, then INPUT".into()),
        None => (var, t),
    };
    let mut v = value(text).map_err(|e| format!("MACRO refused: {e}"))?;
    if add {
        let was = params.get(n).copied().unwrap_or(f64::NAN);
        v = if was.is_nan() { 0.0 } else { was } + if v.is_nan() { 0.0 } else { v };
    }
    Ok(Input::Set(n, v))
}

/// What the message line says of variable `n` set to `v`.
pub(crate) fn set_message(n: usize, v: f64) -> String {
    if v.is_nan() {
        format!("#{n} vacant")
    } else {
        format!("#{n} = {}", crate::input_text::short_number(v))
    }
}

/// INPUT (or +INPUT with `add`) on the MACRO page.
pub(super) fn enter(c: &mut Console, line: &str, add: bool) -> Result<String, String> {
    if c.cfg.settings.dialect != Dialect::Fanuc {
        return Err(
            "MACRO refused: the macro variables are the Fanuc dialect's (--dialect fanuc)".into(),
        );
    }
    let (n, v) = match input(line, c.shell.shown.macro_var, &c.interp.params, add)? {
        Input::Cursor(n) => {
            c.shell.shown.macro_var = n;
            return Ok(format!("MACRO: #{n}"));
        }
        Input::Set(n, v) => (n, v),
    };
    super::workofs::at_rest(c, "MACRO")?;
    if is_fanuc_kept(n) {
        // Kept by the stores; a vacant one is kept as nothing (0), as a program's write is.
        let kept = if v.is_nan() { 0.0 } else { v };
        c.mem
            .set_params(&[(n, kept)])
            .map_err(|e| format!("MACRO refused: #{n}: {e}"))?;
    }
    c.interp.params[n] = v;
    c.shell.shown.macro_var = n;
    Ok(set_message(n, v))
}

/// The MACRO page.
pub(super) fn compose(c: &Console, rows: usize, cols: usize) -> Vec<String> {
    let mut p = Frame::new(
        rows,
        cols,
        split_line("MACRO", "#500=12.5 / Enter INPUT  Tab +INPUT", cols),
    );
    p.bottom = message_lines(c, cols, (rows / 4).max(1));
    p.bottom.push(format!("> {}_", c.shell.front.entry));
    if c.cfg.settings.dialect != Dialect::Fanuc {
        p.body
            .push("(the Fanuc dialect's variables: --dialect fanuc)".into());
        return p.lines();
    }
    p.body = variable_rows(&c.interp.params, c.shell.shown.macro_var, p.body_rows());
    p.lines()
}

/// The screenful of variables the cursor on `var` falls in, `fit` rows, one a row: the value
/// of each in `params`, a vacant (NaN) one blank, the cursor's row marked `>`.
pub(crate) fn variable_rows(params: &[f64], var: usize, fit: usize) -> Vec<String> {
    let fit = fit.max(1);
    let all: Vec<usize> = numbers().collect();
    let at = all.iter().position(|&n| n == var).unwrap_or(0);
    // The cursor's row in view: the screenful it falls in.
    let first = at / fit * fit;
    all.iter()
        .skip(first)
        .take(fit)
        .map(|&n| {
            let v = params.get(n).copied().unwrap_or(f64::NAN);
            let shown = if v.is_nan() {
                String::new()
            } else {
                crate::input_text::short_number(v)
            };
            let mark = if n == var { '>' } else { ' ' };
            format!("{mark}#{n:<4}{shown:>14}")
        })
        .collect()
}
