//! What the lathe console shows (docs/lathe.md "The panel"): the summary line of every channel
//! and the plasma display of the selected one. Pure text; the terminal and the window draw it.

/// The key legend beside the plasma display (the terminal's).
pub const LATHE_KEYS: [&str; 13] = [
    "F9  START   F10 STOP",
    "F11 RESET   F12 E-STOP",
    "Tab CHANNEL  Ctrl-C quit",
    "Alt+2 AUTO  Alt+3 MDI",
    "Alt+4 DATA  Ctrl+O OFS",
    "Ctrl+E MSG  Ctrl+U MACRO",
    "Alt+1 CONT Alt+5 HANDLE",
    "Alt+6 STEP  Alt+7 SINGLE",
    "Alt+x FAULT Alt+n TARGET",
    "Alt+o M01   Alt+b /DEL",
    "Alt+= Alt+- FOV Alt+f RPD",
    "Enter EOB   F8 help",
    "Alt+[ ] SOV  Alt+d DRY",
];

/// The help screen (the terminal's and the window's).
pub const LATHE_HELP: [&str; 20] = [
    "LATHE CONSOLE  (F8 or Alt+h: back; any other key closes this and acts)",
    "Tab / Alt+c   channel selector: the display, data keys and editor act on it",
    "F9  / Alt+s   START: begin the cycle (AUTO) or the MDI lines; resume after a stop",
    "F10 / Alt+p   STOP: feed hold on every channel",
    "F11 / Alt+r   RESET the selected channel (a fault or alarm); after E-STOP, the machine",
    "F12 / Alt+e   E-STOP: everything stops at once",
    "Alt+x         FAULT: stop the selected channel with the typed reason (else 'operator')",
    "Alt+n         set the part target to the typed number",
    "Alt+2/3/4     AUTO / MDI (Enter adds a line) / DATA (an editor line); Ctrl+O OFS (a value Enter, Tab adds)",
    "Ctrl+E        MSG: the alarm and message history, newest first, kept across restarts (Up/Down)",
    "Ctrl+U        MACRO: the channel's variables #1-#33, #100-#199, #500-#999; #500=12.5 Enter sets one",
    "Ctrl+G        MODAL: the channel's modal G codes, F, S, tool and the switches, read only",
    "Ctrl+P        POS: the channel's tool tip and its distance to go in the block, the parts and cycle time",
    "Alt+o, Alt+b  OPTIONAL STOP (M01), BLOCK DELETE (/); Alt+= / Alt+- feed override ±10 %",
    "The summary line: channel, state, current block or whom it waits for, parts/target",
    "Alt+7         SINGLE BLOCK: AUTO, every channel stops after each block; START runs the next",
    "Alt+1/5/6     CONTINUOUS (hold an arrow) / HANDLE (Alt+, Alt+. turn the wheel) / STEP (an increment)",
    "              Up/Down X+/X- (a radius), Left/Right Z-/Z+; Alt+w increment x1..x1000; in DATA the editor's cursor keys",
    "Alt+f, Alt+[] rapid override 100/50/25/F0, spindle override ±10 % (50-120); Alt+d DRY RUN; Alt+l MACHINE LOCK",
    "Ctrl-C or Alt+q quits; programs, MDI lines and the part counter are stored at every change",
];

/// Whether the machine runs, from its channels' state words (the RUN lamp, and how long a
/// "cycle start" message lives): a channel runs (RUN) or moves by hand (JOG), or waits on
/// another while none stands stopped between blocks or held (a channel waiting on a stopped
/// one waits on the operator).
pub fn runs(chans: &[ChanView]) -> bool {
    let any = |w: &[&str]| chans.iter().any(|c| w.contains(&c.state.as_str()));
    any(&["RUN", "JOG"]) || (any(&["WAIT"]) && !any(&["STOP", "HOLD"]))
}

/// One channel as the display shows it.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ChanView {
    /// The channel's name (`SYSTEM-1`).
    pub name: String,
    /// Its program's name.
    pub program: String,
    /// The state word: IDLE, RUN, WAIT, HOLD, STOP, FAULT, ALARM, ESTOP, DONE, JOG (a manual
    /// move).
    pub state: String,
    /// The current block's source line (0: none) and text.
    pub line: u32,
    /// The current block's text.
    pub text: String,
    /// Whom it waits for (`CH1`, `CH1 CH3`, `BAR FEEDER`), empty if not waiting.
    pub waits: String,
    /// The fault's reason or the alarm's message.
    pub note: String,
    /// Tool tip, pulses [X radius, Z].
    pub pos: [i64; 2],
    /// What is left of the block in execution, pulses [X radius, Z]: its end less the tip
    /// (0 between blocks). The POS page's DIST TO GO.
    pub to_go: [i64; 2],
    /// Spindle rpm, signed.
    pub rpm: f64,
    /// Tool number (0 none).
    pub tool: u32,
    /// The work in the spindle.
    pub work: Option<u32>,
    /// The chuck is closed.
    pub chuck: bool,
    /// Works this channel has finished.
    pub parts: u32,
    /// Coolant mist (M07) and flood (M08) on, as the kernel keeps them.
    pub coolant: (bool, bool),
}

impl ChanView {
    /// The coolant as the display says it: ` M07`, ` M08`, ` M07 M08`, or nothing when off.
    pub fn coolant_text(&self) -> &'static str {
        match self.coolant {
            (false, false) => "",
            (true, false) => " M07",
            (false, true) => " M08",
            (true, true) => " M07 M08",
        }
    }
}

/// Pads or cuts `s` to exactly `w` characters.
pub fn fit(s: &str, w: usize) -> String {
    crate::console::display::fit(s, w)
}

/// The summary line of channel `i` (0-based), `w` characters: number, state, current block,
/// whom it waits for, part count. `sel` marks the selected channel.
pub fn summary_line(i: usize, c: &ChanView, target: u32, sel: bool, w: usize) -> String {
    let mark = if sel { '>' } else { ' ' };
    let what = if !c.waits.is_empty() {
        format!("waits {}", c.waits)
    } else if !c.note.is_empty() {
        c.note.clone()
    } else if c.line > 0 {
        format!("{:04} {}", c.line, c.text.trim())
    } else {
        String::new()
    };
    let tail = format!(" parts {}/{}", c.parts, target);
    let head = format!("{mark}CH{} {:<5} ", i + 1, c.state);
    let room = w.saturating_sub(head.chars().count() + tail.chars().count());
    fit(&format!("{head}{}{tail}", fit(&what, room)), w)
}

/// Millimetres with three decimals, pulses × `pulse_mm`.
fn mm(p: i64, pulse_mm: f64) -> String {
    format!("{:9.3}", p as f64 * pulse_mm)
}

/// The plasma display of the selected channel: `rows` lines of `cols` characters. `listing`
/// is the program (or the editor's view) around the current line; `message` and `entry` the
/// last two lines.
#[allow(clippy::too_many_arguments)]
pub fn plasma(
    ch: usize,
    c: &ChanView,
    mode: &str,
    pulse_mm: f64,
    listing: &[String],
    message: &str,
    entry: &str,
    rows: usize,
    cols: usize,
) -> Vec<String> {
    let mut out = Vec::with_capacity(rows);
    out.push(fit(
        &format!("CH{} {} {} {}", ch + 1, c.name, c.program, mode),
        cols,
    ));
    out.push(fit(
        &format!(
            "X{} Z{} S{:6.0}",
            mm(c.pos[0] * 2, pulse_mm),
            mm(c.pos[1], pulse_mm),
            c.rpm
        ),
        cols,
    ));
    let work = match c.work {
        Some(w) => format!("W{w}"),
        None => "EMPTY".to_string(),
    };
    let chuck = if c.chuck { "CLOSED" } else { "OPEN" };
    out.push(fit(
        &format!(
            "T{:02} {work} CHUCK {chuck} {}{}",
            c.tool,
            c.state,
            c.coolant_text()
        ),
        cols,
    ));
    // The message takes the lines it needs, up to a third of the display (the centre's
    // wrapping: words kept whole, a cut said), the listing the rest.
    let said = crate::console::display::wrap(message, cols, (rows / 3).max(1));
    let body = rows.saturating_sub(out.len() + 1 + said.len());
    for l in listing.iter().take(body) {
        out.push(fit(l, cols));
    }
    while out.len() < rows.saturating_sub(1 + said.len()) {
        out.push(fit("", cols));
    }
    out.extend(said.iter().map(|l| fit(l, cols)));
    out.push(fit(&format!("> {entry}"), cols));
    out.truncate(rows);
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn summary_lines_fit_and_say_whom_a_channel_waits_for() {
        let mut c = ChanView {
            state: "WAIT".into(),
            waits: "CH1".into(),
            parts: 2,
            ..Default::default()
        };
        let l = summary_line(1, &c, 5, true, 40);
        assert_eq!(l.chars().count(), 40);
        assert!(l.starts_with(">CH2 WAIT  waits CH1"), "{l}");
        assert!(l.ends_with("parts 2/5"), "{l}");
        c.waits.clear();
        c.line = 17;
        c.text = "G1 Z-12 F0.12".into();
        let l = summary_line(0, &c, 5, false, 30);
        // The block is cut to fit, and the cut says so (the centre's rule).
        assert_eq!(l, " CH1 WAIT  0017 G1 … parts 2/5");
    }

    #[test]
    fn the_plasma_has_exactly_its_rows_and_columns() {
        let c = ChanView {
            name: "SYSTEM-1".into(),
            pos: [10_500, -12_000],
            ..Default::default()
        };
        let d = plasma(
            0,
            &c,
            "AUTO",
            0.001,
            &["0001 G0 X40".into()],
            "msg",
            "ab",
            12,
            40,
        );
        assert_eq!(d.len(), 12);
        assert!(d.iter().all(|l| l.chars().count() == 40));
        assert!(
            d[1].contains("21.000") && d[1].contains("-12.000"),
            "X shows the diameter: {}",
            d[1]
        );
        assert_eq!(d[11].trim_end(), "> ab");
        // A long message wraps on up to a third of the rows, the listing giving way.
        let long = "key Alt+0 does nothing on the lathe console (F8 shows the keys)";
        let d = plasma(
            0,
            &c,
            "AUTO",
            0.001,
            &["0001 G0 X40".into()],
            long,
            "",
            12,
            40,
        );
        assert_eq!(d.len(), 12);
        assert_eq!(d[9].trim_end(), "key Alt+0 does nothing on the lathe");
        assert_eq!(d[10].trim_end(), "console (F8 shows the keys)");
    }
}
