//! The lathe console's part of the one panel language (docs/lathe.md "Panel script", "Keys"):
//! which events of the one grammar (`PanelEvent`, the centre's and the lathe's alike) the lathe
//! takes, and what a key of the one key map (`crate::console::keys::map_key`) does on it.
//! `novanc script --machine citizen` reads the one grammar, and `/panel/event` records each
//! action as its script line (`crate::console::script_line`).

use crate::console::keys::{self, Action};
use crate::panel_model::{Axis, OpMode, Page, PanelEvent};
use novanc_panel::Key;

/// Whether the operation selector's position moves a tool post by hand (CONTINUOUS, HANDLE,
/// STEP). The lathe's selector is the centre's (`OpMode`); OFS is a page over it, as the
/// centre's tool-offset page is.
pub fn manual(m: OpMode) -> bool {
    matches!(m, OpMode::Continuous | OpMode::Handle | OpMode::Step)
}

/// What a key does on the lathe console (docs/lathe.md "Keys"): the one key map of every
/// console (`crate::console::keys::map_key`, whose Alt+1 to Alt+7 turn the operation selector
/// here as on the centre, and whose Tab, Alt+c, Alt+x, Alt+n are a machine's with several
/// channels), with the lathe's jog keys laid out as its tool post moves on the screen, the
/// data keys in capitals, Ctrl+O the OFS page as a script's `op OFS`, and the centre's words
/// it has no use for as [`Action::None`].
pub fn map_key(k: Key) -> Action {
    match k {
        Key::Ctrl('o') => Action::Event(PanelEvent::OfsMode),
        // The lathe's jog keys as its tool post moves on the screen: X up and down, Z along
        // the spindle left and right (PgUp and PgDn are Z too, as on the centre).
        Key::Up => Action::Move(Axis::X, 1),
        Key::Down => Action::Move(Axis::X, -1),
        Key::Left => Action::Move(Axis::Z, -1),
        Key::Right => Action::Move(Axis::Z, 1),
        Key::Char(c) if !c.is_control() => Action::Event(PanelEvent::Key(c.to_ascii_uppercase())),
        k => match keys::map_key(k) {
            Action::Event(e) if takes(&e).is_err() || matches!(e, PanelEvent::Press(_)) => {
                Action::None
            }
            // (Alt+a, the handwheel's axis selector: the lathe's jog keys turn the wheel on
            // their own axis in HANDLE.)
            Action::Move(Axis::Y, _)
            | Action::ZNeglect
            | Action::WheelAxis
            | Action::Page(Page::Prog | Page::Io) => Action::None,
            a => a,
        },
    }
}

/// The key of an axis direction on the lathe (the inverse of [`map_key`]'s jog keys): X+ Up,
/// X- Down, Z+ Right, Z- Left, as the tool post moves on the screen.
pub fn jog_key(axis: Axis, dir: i8) -> Key {
    match (axis, dir > 0) {
        (Axis::X, true) => Key::Up,
        (Axis::X, false) => Key::Down,
        (_, true) => Key::Right,
        (_, false) => Key::Left,
    }
}

/// Whether the lathe console takes `ev`, an event of the one grammar; if not, why (the
/// centre's own words: the data selector, Z NEGLECT ...). A `key
/// NAME` is taken when the key does something on the lathe.
pub fn takes(ev: &PanelEvent) -> Result<(), String> {
    match ev {
        PanelEvent::Op(
            OpMode::Continuous
            | OpMode::Auto
            | OpMode::Mdi
            | OpMode::Data
            | OpMode::Handle
            | OpMode::Step
            | OpMode::Single,
        )
        | PanelEvent::OfsMode
        | PanelEvent::Jog(Axis::X | Axis::Z, _)
        | PanelEvent::Wheel(Axis::X | Axis::Z, _)
        | PanelEvent::JogRelease
        | PanelEvent::WheelScale(_)
        | PanelEvent::Channel(_)
        | PanelEvent::Type(_)
        | PanelEvent::Key(_)
        | PanelEvent::Rubout
        | PanelEvent::Eob
        | PanelEvent::PlusInput
        | PanelEvent::Home
        | PanelEvent::Start
        | PanelEvent::Stop
        | PanelEvent::Reset
        | PanelEvent::EStop
        | PanelEvent::Fault(..)
        | PanelEvent::Target(_)
        | PanelEvent::Tape(_)
        | PanelEvent::OptionalStop(_)
        | PanelEvent::BlockDelete(_)
        | PanelEvent::Override(_)
        | PanelEvent::RapidOverride(_)
        | PanelEvent::SpindleOverride(_)
        | PanelEvent::DryRun(_)
        | PanelEvent::MachineLock(_)
        | PanelEvent::Wait
        | PanelEvent::WaitMs(_)
        | PanelEvent::Show => Ok(()),
        PanelEvent::Jog(..) | PanelEvent::Wheel(..) => Err(format!(
            "{}: the lathe's axes are X and Z",
            crate::console::script_line(ev)
        )),
        // The lathe's blocks are numbered from 1 (docs/lathe.md "Headless"); the centre's
        // block 0 is a SEARCH's restore block, which the lathe has not.
        PanelEvent::WaitBlock(0) => {
            Err("wait block 0: the lathe's blocks are numbered from 1".into())
        }
        PanelEvent::WaitBlock(_) => Ok(()),
        // Any key, as on the centre: one the lathe has no use for says so when it is played,
        // as when it is pressed, and the console records it so. A recording's `/panel/event`
        // is a script that plays back (before stop 39 such a key was refused here, and a
        // lathe recording with one in it could not be replayed).
        PanelEvent::Press(_) => Ok(()),
        other => Err(format!(
            "'{}' is the machining centre's; the lathe console has no use for it",
            crate::console::script_line(other)
        )),
    }
}

/// Parses one panel-script line for the lathe console with the one grammar of every console
/// (`PanelEvent::parse_script_line_on`); `Ok(None)` for a blank or comment line.
pub fn parse_line(line: &str, channels: usize) -> Result<Option<PanelEvent>, String> {
    let ev = PanelEvent::parse_script_line_on(line, channels.max(2))?;
    if let Some(e) = &ev {
        takes(e)?;
    }
    Ok(ev)
}

/// Reads a whole lathe panel script (`novanc script --machine M`, the lathe window's
/// `--script`); a bad line gives its number (1-based) and why, and nothing is returned.
pub fn parse_script(text: &str, channels: usize) -> Result<Vec<PanelEvent>, (usize, String)> {
    let mut steps = Vec::new();
    for (i, l) in text.lines().enumerate() {
        steps.extend(parse_line(l, channels).map_err(|e| (i + 1, e))?);
    }
    Ok(steps)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::console::script_line;

    #[test]
    fn script_lines_read_back_as_the_same_event() {
        for ev in [
            PanelEvent::Op(OpMode::Mdi),
            PanelEvent::OfsMode,
            PanelEvent::Channel(2),
            PanelEvent::Type("G0 X10".into()),
            PanelEvent::Start,
            PanelEvent::Stop,
            PanelEvent::Reset,
            PanelEvent::EStop,
            PanelEvent::Fault(0, "tool breakage".into()),
            PanelEvent::Target(5),
            PanelEvent::OptionalStop(true),
            PanelEvent::Override(70),
            PanelEvent::Press(Key::Tab),
            PanelEvent::Press(Key::F(8)),
        ] {
            assert_eq!(
                parse_line(&script_line(&ev), 3),
                Ok(Some(ev.clone())),
                "{ev:?}"
            );
        }
        assert!(parse_line("fault 4 x", 3)
            .unwrap_err()
            .contains("not a channel"));
        assert!(parse_line("fault 1", 3).unwrap_err().contains("say why"));
        assert!(parse_line("target 0", 3).is_err());
        assert_eq!(
            parse_line("op SINGLE", 3),
            Ok(Some(PanelEvent::Op(OpMode::Single)))
        );
        assert_eq!(
            parse_line("op HANDLE", 3),
            Ok(Some(PanelEvent::Op(OpMode::Handle)))
        );
        assert_eq!(
            parse_line("jog Z-", 3),
            Ok(Some(PanelEvent::Jog(Axis::Z, -1)))
        );
        assert_eq!(
            parse_line("jog Y+", 3),
            Err("jog Y+: the lathe's axes are X and Z".into())
        );
        // HOME is every machine's (the selected channel's reference return, since stop 61).
        assert_eq!(parse_line("home", 3), Ok(Some(PanelEvent::Home)));
        assert!(parse_line("data SEARCH", 3)
            .unwrap_err()
            .contains("machining centre's"));
        assert_eq!(
            parse_line("key Alt+l", 3),
            Ok(Some(PanelEvent::Press(Key::Alt('l'))))
        );
        assert_eq!(
            parse_line("key Alt+d", 3),
            Ok(Some(PanelEvent::Press(Key::Alt('d'))))
        );
        assert_eq!(parse_line("  # note", 3), Ok(None));
    }

    #[test]
    fn a_script_reads_whole_or_names_its_bad_line() {
        let s = parse_script("# c\nstart\nwait ms 250\n\nwait block 7\nwait\nshow\n", 3).unwrap();
        assert_eq!(
            s,
            [
                PanelEvent::Start,
                PanelEvent::WaitMs(250),
                PanelEvent::WaitBlock(7),
                PanelEvent::Wait,
                PanelEvent::Show
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

    #[test]
    fn the_lathe_keys_sit_on_the_one_key_map() {
        assert_eq!(map_key(Key::F(9)), Action::Event(PanelEvent::Start));
        assert_eq!(
            map_key(Key::Alt('3')),
            Action::Event(PanelEvent::Op(OpMode::Mdi))
        );
        // The operation selector's keys are the centre's; OFS is the centre's OFS page key.
        assert_eq!(
            map_key(Key::Alt('5')),
            Action::Event(PanelEvent::Op(OpMode::Handle))
        );
        assert_eq!(
            map_key(Key::Alt('1')),
            Action::Event(PanelEvent::Op(OpMode::Continuous))
        );
        assert_eq!(map_key(Key::Ctrl('o')), Action::Event(PanelEvent::OfsMode));
        assert_eq!(map_key(Key::Alt('.')), Action::Wheel(1));
        assert_eq!(map_key(Key::Tab), Action::NextChannel);
        assert_eq!(map_key(Key::Char('g')), Action::Event(PanelEvent::Key('G')));
        assert_eq!(map_key(Key::Alt('o')), Action::OptionalStop);
        assert_eq!(map_key(Key::Ctrl('e')), Action::Page(Page::Msg));
        assert_eq!(map_key(Key::Ctrl('u')), Action::Page(Page::Macro));
        assert_eq!(map_key(Key::Ctrl('g')), Action::Page(Page::Modal));
        // The centre's own keys do nothing here, and say so (not dropped in silence).
        assert_eq!(
            map_key(Key::Alt('7')),
            Action::Event(PanelEvent::Op(OpMode::Single))
        );
        assert_eq!(map_key(Key::Alt('0')), Action::Event(PanelEvent::Home));
        for k in [Key::Alt('z'), Key::F(2), Key::Ctrl('d'), Key::Ctrl('t')] {
            assert_eq!(map_key(k), Action::None, "{k:?}");
        }
        assert_eq!(map_key(Key::Ctrl('p')), Action::Page(Page::Pos));
        // The centre's switches the lathe takes: the same keys.
        assert_eq!(map_key(Key::Alt('d')), Action::DryRun);
        assert_eq!(map_key(Key::Alt('l')), Action::MachineLock);
        assert_eq!(map_key(Key::Alt('f')), Action::RapidOverride);
        assert_eq!(map_key(Key::Alt('x')), Action::Fault);
        // The jog keys as a lathe's tool post moves on the screen; STEP and its increment.
        for (k, axis, dir) in [
            (Key::Up, Axis::X, 1),
            (Key::Down, Axis::X, -1),
            (Key::Left, Axis::Z, -1),
            (Key::Right, Axis::Z, 1),
            (Key::PageUp, Axis::Z, 1),
            (Key::PageDown, Axis::Z, -1),
        ] {
            assert_eq!(map_key(k), Action::Move(axis, dir), "{k:?}");
        }
        assert_eq!(
            map_key(Key::Alt('6')),
            Action::Event(PanelEvent::Op(OpMode::Step))
        );
        assert_eq!(map_key(Key::Alt('w')), Action::WheelScale);
        for (axis, dir) in [(Axis::X, 1), (Axis::X, -1), (Axis::Z, 1), (Axis::Z, -1)] {
            assert_eq!(map_key(jog_key(axis, dir)), Action::Move(axis, dir));
        }
    }
}
