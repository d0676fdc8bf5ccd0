//! The lathe console's operator events and their panel-script lines (docs/lathe.md "Panel
//! script"): what `novanc script --machine citizen` reads and `/panel/event` records.

use crate::panel_model::{OpMode, PanelEvent};
use novanc_panel::Key;

/// The lathe console's modes (the operation selector's AUTO, MDI and DATA positions).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Mode {
    /// AUTO: START runs every channel's program, to the part target.
    Auto,
    /// MDI: the data keys fill the selected channel's MDI buffer; START runs it.
    Mdi,
    /// DATA: the data keys take editor command lines on the selected channel's program.
    Data,
    /// OFS: the data keys revise the selected channel's tools (`T1 X0.02 Z-0.01 R0.8 P3`).
    Ofs,
}

impl Mode {
    /// The script word.
    pub fn word(self) -> &'static str {
        match self {
            Mode::Auto => "AUTO",
            Mode::Mdi => "MDI",
            Mode::Data => "DATA",
            Mode::Ofs => "OFS",
        }
    }
}

/// One operator action on the lathe console.
#[derive(Clone, Debug, PartialEq)]
pub enum LatheEv {
    /// `op AUTO|MDI|DATA`.
    Mode(Mode),
    /// `channel N`: the channel selector (1-based in the script, 0-based here).
    Channel(usize),
    /// The channel selector's next position (Tab).
    NextChannel,
    /// `type TEXT`: data keys, then EOB.
    Type(String),
    /// One data key.
    Key(char),
    /// Rub out the last typed character.
    Rubout,
    /// The EOB key.
    Eob,
    /// `start`: cycle start.
    Start,
    /// `stop`: feed hold on every channel.
    Stop,
    /// `reset`: RESET of the selected channel (after an E-STOP, of the machine).
    Reset,
    /// `estop`: emergency stop of the whole machine.
    EStop,
    /// `fault N REASON`: a fault in channel N (0-based here).
    Fault(usize, String),
    /// `target N`: the part target.
    Target(u32),
    /// `optionalstop on|off`.
    OptionalStop(bool),
    /// `override PCT`: the feed override of every channel's feed moves, 0 to 150 %.
    Override(u32),
    /// `blockdelete on|off`.
    BlockDelete(bool),
    /// The help screen on or off.
    Help,
}

impl LatheEv {
    /// The event as a panel-script line.
    pub fn script_line(&self) -> String {
        let on = |b: bool| if b { "on" } else { "off" };
        match self {
            LatheEv::Mode(m) => format!("op {}", m.word()),
            LatheEv::Channel(c) => format!("channel {}", c + 1),
            LatheEv::NextChannel => "key Tab".into(),
            LatheEv::Type(t) => format!("type {t}"),
            LatheEv::Key(c) => format!("key {c}"),
            LatheEv::Rubout => "rubout".into(),
            LatheEv::Eob => "eob".into(),
            LatheEv::Start => "start".into(),
            LatheEv::Stop => "stop".into(),
            LatheEv::Reset => "reset".into(),
            LatheEv::EStop => "estop".into(),
            LatheEv::Fault(c, r) => format!("fault {} {r}", c + 1),
            LatheEv::Target(n) => format!("target {n}"),
            LatheEv::OptionalStop(b) => format!("optionalstop {}", on(*b)),
            LatheEv::Override(p) => format!("override {p}"),
            LatheEv::BlockDelete(b) => format!("blockdelete {}", on(*b)),
            LatheEv::Help => "key F8".into(),
        }
    }
}

/// What a key of the terminal does on the lathe console (docs/lathe.md "Keys").
pub fn map_key(k: Key, optional_stop: bool, block_delete: bool) -> Option<LatheEv> {
    Some(match k {
        Key::F(9) | Key::Alt('s') => LatheEv::Start,
        Key::F(10) | Key::Alt('p') => LatheEv::Stop,
        Key::F(11) | Key::Alt('r') => LatheEv::Reset,
        Key::F(12) | Key::Alt('e') => LatheEv::EStop,
        Key::F(8) | Key::Alt('h') => LatheEv::Help,
        Key::Alt('2') => LatheEv::Mode(Mode::Auto),
        Key::Alt('3') => LatheEv::Mode(Mode::Mdi),
        Key::Alt('4') => LatheEv::Mode(Mode::Data),
        Key::Alt('5') => LatheEv::Mode(Mode::Ofs),
        Key::Tab | Key::Alt('c') => LatheEv::NextChannel,
        Key::Alt('o') => LatheEv::OptionalStop(!optional_stop),
        Key::Alt('b') => LatheEv::BlockDelete(!block_delete),
        Key::Enter => LatheEv::Eob,
        Key::Backspace => LatheEv::Rubout,
        Key::Char(c) if !c.is_control() => LatheEv::Key(c.to_ascii_uppercase()),
        _ => return None,
    })
}

/// Parses one panel-script line of the lathe console with the one grammar of every console
/// (`PanelEvent::parse_script_line_on`); `Ok(None)` for a blank or comment line. Waits
/// (`wait`, `wait ms T`, `wait block N`) and `show` are the script runner's, not events: they are refused here
/// and taken by [`parse_script`].
pub fn parse_line(line: &str, channels: usize) -> Result<Option<LatheEv>, String> {
    match PanelEvent::parse_script_line_on(line, channels.max(2))? {
        None => Ok(None),
        Some(ev) => match from_panel(ev)? {
            ScriptStep::Ev(e) => Ok(Some(e)),
            _ => Err(format!("'{}' is the script runner's word", line.trim())),
        },
    }
}

/// A panel event of the one grammar as the lathe console's: a mode, a channel, a key, ...
/// The centre's own words (HOME, the handwheel, the data selector, tape, DRY RUN ...) are
/// refused with what they are.
fn from_panel(ev: PanelEvent) -> Result<ScriptStep, String> {
    let e = match ev {
        PanelEvent::Op(OpMode::Auto) => LatheEv::Mode(Mode::Auto),
        PanelEvent::Op(OpMode::Mdi) => LatheEv::Mode(Mode::Mdi),
        PanelEvent::Op(OpMode::Data) => LatheEv::Mode(Mode::Data),
        PanelEvent::OfsMode => LatheEv::Mode(Mode::Ofs),
        PanelEvent::Op(m) => {
            return Err(format!(
                "op {}: the lathe's modes are AUTO, MDI, DATA and OFS",
                m.word()
            ))
        }
        PanelEvent::Channel(c) => LatheEv::Channel(c),
        PanelEvent::Type(t) => LatheEv::Type(t),
        PanelEvent::Key(c) => LatheEv::Key(c),
        PanelEvent::Rubout => LatheEv::Rubout,
        PanelEvent::Eob => LatheEv::Eob,
        PanelEvent::Start => LatheEv::Start,
        PanelEvent::Stop => LatheEv::Stop,
        PanelEvent::Reset => LatheEv::Reset,
        PanelEvent::EStop => LatheEv::EStop,
        PanelEvent::Fault(c, why) => LatheEv::Fault(c, why),
        PanelEvent::Target(n) => LatheEv::Target(n),
        PanelEvent::OptionalStop(b) => LatheEv::OptionalStop(b),
        PanelEvent::BlockDelete(b) => LatheEv::BlockDelete(b),
        PanelEvent::Override(p) => LatheEv::Override(p),
        PanelEvent::Press(Key::Tab) => LatheEv::NextChannel,
        PanelEvent::Press(k) => match map_key(k, false, false) {
            Some(ev) => ev,
            None => {
                return Err(format!(
                    "key {}: the lathe console has no use for it",
                    crate::console::keys::key_name(k)
                ))
            }
        },
        PanelEvent::Wait => return Ok(ScriptStep::Wait),
        PanelEvent::WaitMs(ms) => return Ok(ScriptStep::WaitMs(ms)),
        // The lathe's blocks are numbered from 1 (docs/lathe.md "Headless"); the centre's
        // block 0 is a SEARCH's restore block, which the lathe has not.
        PanelEvent::WaitBlock(0) => {
            return Err("wait block 0: the lathe's blocks are numbered from 1".into())
        }
        PanelEvent::WaitBlock(n) => return Ok(ScriptStep::WaitBlock(n)),
        PanelEvent::Show => return Ok(ScriptStep::Show),
        other => {
            return Err(format!(
                "'{}' is the machining centre's; the lathe console has no use for it",
                crate::console::script_line(&other)
            ))
        }
    };
    Ok(ScriptStep::Ev(e))
}

/// One line of a lathe panel script: an event, or one of the runner's own words.
#[derive(Clone, Debug, PartialEq)]
pub enum ScriptStep {
    /// An operator action.
    Ev(LatheEv),
    /// `wait`: until every channel is at rest (`LatheConsole::at_rest`).
    Wait,
    /// `wait ms T`: T milliseconds of machine time.
    WaitMs(u64),
    /// `wait block N`: until block N (its sequence number) of the selected channel's program
    /// starts, or every channel is at rest.
    WaitBlock(u32),
    /// `show`: print the display.
    Show,
}

/// Reads a whole lathe panel script (`novanc script --machine M`, the lathe window's
/// `--script`); a bad line gives its number (1-based) and why, and nothing is returned.
pub fn parse_script(text: &str, channels: usize) -> Result<Vec<ScriptStep>, (usize, String)> {
    let mut steps = Vec::new();
    for (i, l) in text.lines().enumerate() {
        let step = PanelEvent::parse_script_line_on(l, channels.max(2))
            .and_then(|ev| ev.map(from_panel).transpose())
            .map_err(|e| (i + 1, e))?;
        steps.extend(step);
    }
    Ok(steps)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn script_lines_read_back_as_the_same_event() {
        for ev in [
            LatheEv::Mode(Mode::Mdi),
            LatheEv::Channel(2),
            LatheEv::Type("G0 X10".into()),
            LatheEv::Start,
            LatheEv::Stop,
            LatheEv::Reset,
            LatheEv::EStop,
            LatheEv::Fault(0, "tool breakage".into()),
            LatheEv::Target(5),
            LatheEv::OptionalStop(true),
            LatheEv::Override(70),
            LatheEv::NextChannel,
        ] {
            assert_eq!(
                parse_line(&ev.script_line(), 3),
                Ok(Some(ev.clone())),
                "{ev:?}"
            );
        }
        assert!(parse_line("fault 4 x", 3)
            .unwrap_err()
            .contains("not a channel"));
        assert!(parse_line("fault 1", 3).unwrap_err().contains("say why"));
        assert!(parse_line("target 0", 3).is_err());
        assert!(parse_line("op HANDLE", 3)
            .unwrap_err()
            .contains("AUTO, MDI, DATA and OFS"));
        assert_eq!(parse_line("  # note", 3), Ok(None));
    }

    #[test]
    fn a_script_reads_whole_or_names_its_bad_line() {
        let s = parse_script("# c\nstart\nwait ms 250\n\nwait block 7\nwait\nshow\n", 3).unwrap();
        assert_eq!(
            s,
            [
                ScriptStep::Ev(LatheEv::Start),
                ScriptStep::WaitMs(250),
                ScriptStep::WaitBlock(7),
                ScriptStep::Wait,
                ScriptStep::Show
            ]
        );
        assert_eq!(
            parse_script("start\nwait block 0\n", 3).unwrap_err(),
            (
                2,
                "wait block 0: the lathe's blocks are numbered from 1".into()
            )
        );
        assert_eq!(
            parse_script("start\nwait ms x\n", 3).unwrap_err().0,
            2,
            "the bad line's number"
        );
        assert!(parse_script("fault 9 x\n", 3)
            .unwrap_err()
            .1
            .contains("not a channel"));
    }
}
