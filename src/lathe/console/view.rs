//! What the lathe console shows (docs/lathe.md "The panel"): the summary line of every channel
//! and the plasma display of the selected one. Pure text; the terminal and the window draw it.

/// Whether the machine runs, from its channels' state words (the RUN lamp, and how long a
/// "cycle start" message lives): a channel runs (RUN), moves by hand (JOG) or makes its
/// reference return (HOME), or waits on
/// another while none stands stopped between blocks or held (a channel waiting on a stopped
/// one waits on the operator).
pub fn runs(chans: &[ChanView]) -> bool {
    let any = |w: &[&str]| chans.iter().any(|c| w.contains(&c.state.as_str()));
    any(&["RUN", "JOG", "HOME"]) || (any(&["WAIT"]) && !any(&["STOP", "HOLD"]))
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
    /// The digital outputs on (M64/M65), bit n output n, as the kernel keeps them.
    pub outputs: u64,
    /// The work system in force (0 for G54 to 5 for G59) and the program's zero, pulses [X
    /// radius, Z] from the machine's zero: the block executing's while a program runs, else
    /// the one the channel's next MDI run starts in (docs/lathe-gcode.md "Work offsets").
    pub system: Option<(usize, [i64; 2])>,
    /// The offsets of the tool in place, pulses [X radius, Z]: with the zero, what the display
    /// takes off the tip to show the programmed point.
    pub offset: [i64; 2],
}

impl ChanView {
    /// The programmed point in the program's coordinates: the tip less the zero (the work
    /// system's and a G50/G92 shift's) and the offsets of the tool in place, pulses [X radius,
    /// Z], as a Fanuc's ABSOLUTE position: what the display's X and Z say.
    pub fn work_pos(&self) -> [i64; 2] {
        let z = self.system.map_or([0, 0], |s| s.1);
        let o = self.offset;
        [self.pos[0] - z[0] - o[0], self.pos[1] - z[1] - o[1]]
    }

    /// Takes `d` as what the tip is measured from (`lathe::gcode::Datum`, `[Z, X]` mm).
    pub fn set_datum(
        &mut self,
        desc: &crate::lathe::desc::LatheDesc,
        d: &crate::lathe::gcode::Datum,
    ) {
        let p = |v: [f64; 2]| [desc.pulses(v[1]), desc.pulses(v[0])];
        self.system = Some((d.work, p(d.zero)));
        self.offset = p(d.offset);
    }

    /// The coolant and the outputs as the display says them: ` M07`, ` M08`, ` M07 M08`, then
    /// ` OUT 1 3` for the digital outputs on (spaces: a plasma comma reads as a point); nothing
    /// when all are off.
    pub fn aux_text(&self) -> String {
        let mut s = match self.coolant {
            (false, false) => "",
            (true, false) => " M07",
            (false, true) => " M08",
            (true, true) => " M07 M08",
        }
        .to_string();
        let on: Vec<String> = (0..64)
            .filter(|i| self.outputs >> i & 1 == 1)
            .map(|i| i.to_string())
            .collect();
        if !on.is_empty() {
            s += &format!(" OUT {}", on.join(" "));
        }
        s
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
            mm(c.work_pos()[0] * 2, pulse_mm),
            mm(c.work_pos()[1], pulse_mm),
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
            c.aux_text()
        ),
        cols,
    ));
    // The message takes the lines it needs, up to a third of the display (the centre's
    // wrapping: words kept whole, a cut said), the listing the rest.
    let said = crate::console::display::wrap(message, cols, (rows / 3).max(1));
    let body = rows.saturating_sub(out.len() + 1 + said.len());
    for (i, l) in listing.iter().take(body).enumerate() {
        if i + 1 == body && listing.len() > body {
            // A page longer than the room left: its last line shown says so.
            let keep: String = l.chars().take(cols.saturating_sub(1)).collect();
            out.push(fit(
                &format!("{keep}{}", crate::console::display::CUT),
                cols,
            ));
        } else {
            out.push(fit(l, cols));
        }
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
        let long = "key Alt+z does nothing on the lathe console (F8 shows the keys)";
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
        assert_eq!(d[9].trim_end(), "key Alt+z does nothing on the lathe");
        assert_eq!(d[10].trim_end(), "console (F8 shows the keys)");
    }
}
