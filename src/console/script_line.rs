//! A panel event as its panel-script line (docs/cli.md, `novanc script`): what the recording
//! keeps of each operator action, and what a refusal names.

use crate::panel_model::PanelEvent;
use novanc_panel::Key;

/// An event as its panel-script line (for the recording).
pub fn script_line(ev: &PanelEvent) -> String {
    match ev {
        PanelEvent::Op(m) => format!("op {}", m.word()),
        PanelEvent::Data(m) => format!("data {}", m.word()),
        PanelEvent::Type(t) => format!("type {t}"),
        PanelEvent::Key(c) => format!("key {c}"),
        PanelEvent::Rubout => "rubout".into(),
        PanelEvent::Eob => "eob".into(),
        PanelEvent::PlusInput => "plusinput".into(),
        PanelEvent::Tape(p) => format!("tape {}", p.display()),
        PanelEvent::Start => "start".into(),
        PanelEvent::Stop => "stop".into(),
        PanelEvent::Home => "home".into(),
        PanelEvent::Reset => "reset".into(),
        PanelEvent::EStop => "estop".into(),
        PanelEvent::Override(p) => format!("override {p}"),
        PanelEvent::RapidOverride(p) => format!("rapidoverride {p}"),
        PanelEvent::SpindleOverride(p) => format!("spindleoverride {p}"),
        PanelEvent::DryRun(on) => format!("dryrun {}", on_off(*on)),
        PanelEvent::MachineLock(on) => format!("machinelock {}", on_off(*on)),
        PanelEvent::ZNeglect(on) => format!("zneglect {}", on_off(*on)),
        PanelEvent::Wheel(a, n) => format!("wheel {} {n}", a.letter()),
        PanelEvent::WheelScale(s) => format!("wheelscale {s}"),
        PanelEvent::BlockDelete(on) => format!("blockdelete {}", on_off(*on)),
        PanelEvent::OptionalStop(on) => format!("optionalstop {}", on_off(*on)),
        PanelEvent::Jog(a, d) => format!("jog {}{}", a.letter(), if *d < 0 { '-' } else { '+' }),
        PanelEvent::JogRelease => "jogrelease".into(),
        PanelEvent::Press(k) => format!("key {}", key_name(*k)),
        PanelEvent::Wait => "wait".into(),
        PanelEvent::WaitBlock(n) => format!("wait block {n}"),
        PanelEvent::WaitMs(t) => format!("wait ms {t}"),
        PanelEvent::Show => "show".into(),
        PanelEvent::Channel(c) => format!("channel {}", c + 1),
        PanelEvent::Fault(c, why) => format!("fault {} {why}", c + 1),
        PanelEvent::Target(n) => format!("target {n}"),
        PanelEvent::OfsMode => "op OFS".into(),
        PanelEvent::Input {
            digital: true,
            index,
            value,
        } => format!("input P{index} {}", on_off(*value != 0.0)),
        PanelEvent::Input {
            digital: false,
            index,
            value,
        } => format!("input E{index} {value}"),
    }
}

/// A key's name in the panel script (`key NAME`) and the recording (`keys::parse_key` reads
/// it back).
pub fn key_name(k: Key) -> String {
    match k {
        Key::Char(c) => c.to_string(),
        Key::Enter => "Enter".into(),
        Key::Backspace => "Backspace".into(),
        Key::Tab => "Tab".into(),
        Key::Esc => "Esc".into(),
        Key::Up => "Up".into(),
        Key::Down => "Down".into(),
        Key::Left => "Left".into(),
        Key::Right => "Right".into(),
        Key::PageUp => "PgUp".into(),
        Key::PageDown => "PgDn".into(),
        Key::Home => "Home".into(),
        Key::End => "End".into(),
        Key::Insert => "Insert".into(),
        Key::Delete => "Delete".into(),
        Key::F(n) => format!("F{n}"),
        Key::Alt(c) => format!("Alt+{c}"),
        Key::Ctrl(c) => format!("Ctrl+{c}"),
        Key::Unknown => "Unknown".into(),
    }
}

fn on_off(on: bool) -> &'static str {
    if on {
        "on"
    } else {
        "off"
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::panel_model::{Axis, DataMode, OpMode};

    /// Every event the consoles record reads back as itself: a recording's `/panel/event`
    /// lines are a script (a data key reads back as the key that types it).
    #[test]
    fn every_recorded_event_reads_back_as_a_script_line() {
        let evs = [
            PanelEvent::Op(OpMode::Handle),
            PanelEvent::Data(DataMode::Revise),
            PanelEvent::Type("G0 X10".into()),
            PanelEvent::Rubout,
            PanelEvent::Eob,
            PanelEvent::PlusInput,
            PanelEvent::Tape("/tmp/t.tape".into()),
            PanelEvent::Start,
            PanelEvent::Stop,
            PanelEvent::Home,
            PanelEvent::Reset,
            PanelEvent::EStop,
            PanelEvent::Override(70),
            PanelEvent::RapidOverride(25),
            PanelEvent::SpindleOverride(110),
            PanelEvent::DryRun(true),
            PanelEvent::MachineLock(false),
            PanelEvent::ZNeglect(true),
            PanelEvent::Wheel(Axis::Z, -3),
            PanelEvent::WheelScale(100),
            PanelEvent::BlockDelete(true),
            PanelEvent::OptionalStop(false),
            PanelEvent::Jog(Axis::X, 1),
            PanelEvent::Jog(Axis::Z, -1),
            PanelEvent::JogRelease,
            PanelEvent::Press(Key::Alt('5')),
            PanelEvent::Wait,
            PanelEvent::WaitBlock(12),
            PanelEvent::WaitMs(250),
            PanelEvent::Show,
            PanelEvent::Channel(1),
            PanelEvent::Fault(2, "tool breakage".into()),
            PanelEvent::Target(5),
            PanelEvent::OfsMode,
            PanelEvent::Input {
                digital: true,
                index: 3,
                value: 1.0,
            },
            PanelEvent::Input {
                digital: false,
                index: 2,
                value: 4.5,
            },
        ];
        for ev in evs {
            let line = script_line(&ev);
            assert_eq!(
                PanelEvent::parse_script_line_on(&line, 3),
                Ok(Some(ev.clone())),
                "{line}"
            );
        }
        assert_eq!(
            PanelEvent::parse_script_line(&script_line(&PanelEvent::Key('G'))),
            Ok(Some(PanelEvent::Press(Key::Char('G'))))
        );
        for bad in ["jog X", "jog +", "jog Q+", "jog X+ Z+", "jogrelease now"] {
            assert!(PanelEvent::parse_script_line(bad).is_err(), "{bad}");
        }
    }
}
