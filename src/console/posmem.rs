//! Position memory (issue 23; docs/stores.md, "Position memory"): the machine position and the
//! tool in the spindle, kept in the state directory's `position` file so that a restart knows
//! where the axes are. The file says `moving` (written durably) before any command that can
//! move an axis is given to the pulse core, and the position with `at rest` once the axes
//! stand still; a console that died while the axes moved leaves `moving`, and the next one
//! cannot trust the position: it says so and refuses AUTO and MDI until the reference return
//! (HOME, Alt+0, script word `home`) has been made. The jog feed chosen on POS (`JOG 500`,
//! `JOG RAPID`) is kept in the same file.

use super::manual::JogChoice;
use super::Console;
use crate::pulse_core::Command;
use std::path::Path;

/// The file in the state directory.
pub const FILE: &str = "position";

/// What the file says.
#[derive(Clone, Debug, PartialEq)]
pub struct Kept {
    /// The axes were moving when it was written: the position is not to be trusted.
    pub moving: bool,
    /// Machine position, pulses.
    pub pos: crate::block::Axes,
    /// The tool in the spindle.
    pub tool: Option<u32>,
    /// The jog feed chosen on POS.
    pub jog: JogChoice,
}

impl Kept {
    fn text(&self) -> String {
        format!(
            "novanc-position 1\n{}\n{} {} {}{}\ntool {}\njog {}{}\n",
            if self.moving { "moving" } else { "at rest" },
            self.pos[0],
            self.pos[1],
            self.pos[2],
            // A, B and C, up to the last one off 0 (a 3-axis file is unchanged).
            {
                let n = (3..crate::block::MAX_AXES)
                    .rev()
                    .find(|&a| self.pos[a] != 0)
                    .map_or(3, |a| a + 1);
                self.pos[3..n]
                    .iter()
                    .map(|v| format!(" {v}"))
                    .collect::<String>()
            },
            self.tool.map_or("none".to_string(), |t| t.to_string()),
            self.jog
                .feed
                .map_or("default".to_string(), |f| f.to_string()),
            if self.jog.rapid { " rapid" } else { "" }
        )
    }

    /// Reads the file's text; None if it is not one.
    pub fn parse(text: &str) -> Option<Kept> {
        let mut l = text.lines();
        if l.next()? != "novanc-position 1" {
            return None;
        }
        let moving = match l.next()? {
            "moving" => true,
            "at rest" => false,
            _ => return None,
        };
        let p: Vec<i64> = l
            .next()?
            .split(' ')
            .map(|v| v.parse().ok())
            .collect::<Option<_>>()?;
        if !(3..=crate::block::MAX_AXES).contains(&p.len()) {
            return None;
        }
        let pos = crate::block::Axes::from_fn(|a| p.get(a).copied().unwrap_or(0));
        let tool = match l.next()?.strip_prefix("tool ")? {
            "none" => None,
            t => Some(t.parse().ok()?),
        };
        // The jog line came later: a file without it keeps the settings' jog feed.
        let jog = match l.next() {
            None => JogChoice::default(),
            Some(j) => {
                let j = j.strip_prefix("jog ")?;
                let (feed, rapid) = match j.strip_suffix(" rapid") {
                    Some(f) => (f, true),
                    None => (j, false),
                };
                let feed = match feed {
                    "default" => None,
                    f => Some(
                        f.parse::<f64>()
                            .ok()
                            .filter(|v| v.is_finite() && *v > 0.0)?,
                    ),
                };
                JogChoice { feed, rapid }
            }
        };
        Some(Kept {
            moving,
            pos,
            tool,
            jog,
        })
    }
}

/// Position memory's part of the console state.
#[derive(Debug, Default)]
pub(super) struct PosMem {
    /// What the file says now (None: nothing written yet this session, or no file).
    written: Option<Kept>,
    /// The position could not be trusted at start: AUTO and MDI wait for HOME.
    pub home_needed: bool,
    /// HOME was accepted and the return is under way.
    homing: bool,
    /// The jog feed chosen on POS (`JOG 500`, `JOG RAPID`).
    pub jog: JogChoice,
}

/// The jog feed in force, mm/min: the rapid rate with rapid jog, else the one chosen (the
/// settings' by default).
pub(super) fn jog_feed(c: &Console) -> f64 {
    let s = &c.cfg.settings;
    c.posmem.jog.rate(s.jog_mm_min, s.rapid_mm_min)
}

/// Whether a command can set an axis moving: before it is given, the file says `moving`.
pub(super) fn can_move(c: &Command) -> bool {
    matches!(
        c,
        Command::Start(_) | Command::Jog { .. } | Command::Increment { .. } | Command::Home
    )
}

/// Before a command that can move an axis (`can_move`, or a run's START): the file says
/// `moving`, on disk, so that a console killed before its next frame leaves a position that is
/// not trusted (a refused command is followed by `at rest` again at the next status poll). If
/// it cannot be written the motion is refused (Err, why; since stop 61, a lathe's rule too):
/// a console killed during it would leave a position kept at rest that the axes no longer
/// have. Before stop 61 the axes moved and the message said the position could not be kept.
pub(super) fn before_motion(c: &mut Console) -> Result<(), String> {
    if c.posmem.written.as_ref().is_some_and(|w| w.moving) {
        return Ok(());
    }
    let s = &c.status;
    let k = Kept {
        moving: true,
        pos: s.machine_pos,
        tool: s.tool,
        jog: c.posmem.jog,
    };
    save(&c.cfg.state_dir, &k).map_err(|e| format!("the position could not be kept: {e}"))?;
    c.posmem.written = Some(k);
    Ok(())
}

/// At start: the kept position and tool are given to the core; a position kept while moving
/// is given too (the best guess) but the reference return is asked for.
pub(super) fn restore(c: &mut Console) {
    let path = c.cfg.state_dir.join(FILE);
    let text = match std::fs::read_to_string(&path) {
        Ok(t) => t,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return,
        Err(e) => {
            c.posmem.home_needed = true;
            c.shell.front.message = format!(
                "the kept position cannot be read ({e}): make the reference return (HOME, Alt+0) before AUTO or MDI"
            );
            return;
        }
    };
    let Some(k) = Kept::parse(&text) else {
        c.posmem.home_needed = true;
        c.shell.front.message = format!(
            "the kept position ({}) is damaged: make the reference return (HOME, Alt+0) before AUTO or MDI",
            path.display()
        );
        return;
    };
    // A rotary axis the machine no longer has (its description changed) is not taken: its
    // counter would stand off 0 unseen, on no POS row.
    let s = &c.cfg.settings;
    let pos = crate::block::Axes::from_fn(|a| if s.has_axis(a) { k.pos[a] } else { 0 });
    c.core.set_position(pos);
    c.core.command(Command::SetTool(k.tool));
    c.posmem.jog = k.jog;
    if k.jog != JogChoice::default() {
        c.core.set_jog_feed(jog_feed(c));
    }
    if k.moving {
        c.posmem.home_needed = true;
        c.shell.front.message = "the console stopped while the axes moved: the position is not known; make the reference return (HOME, Alt+0) before AUTO or MDI".into();
    }
    c.posmem.written = Some(k);
}

/// Why START may not run a program now: the reference return is owed.
pub(super) fn refusal(c: &Console) -> Option<String> {
    c.posmem.home_needed.then(|| {
        "START refused: the position is not known since the restart; make the reference return first (HOME, Alt+0)".to_string()
    })
}

/// HOME: the reference return.
pub(super) fn home(c: &mut Console) {
    if let Err(e) = before_motion(c) {
        c.shell.front.message = format!("HOME refused: {e}");
        return;
    }
    c.command(Command::Home);
    if let Some(n) = c.status.notice.clone() {
        c.shell.front.message = n;
        return;
    }
    c.posmem.homing = true;
    c.shell.front.message = HOMING.into();
}

/// What HOME does, said when it is pressed and, while it runs, by the machine's state
/// (`state::machine_note`).
pub(super) const HOMING: &str = "HOME: reference return, Z first, then X and Y";

/// A HOME is under way (it ends at rest: at machine zero, or stopped short by E-STOP or STOP).
pub(super) fn homing(c: &Console) -> bool {
    c.posmem.homing
}

/// After each status poll: the file follows what the axes do (written only when that
/// changes: `moving` when they start, the position when they come to rest), and a HOME that
/// has arrived at machine zero clears the owed reference return.
pub(super) fn track(c: &mut Console) {
    let s = &c.status;
    let at_rest = !s.moving && s.idle;
    if c.posmem.homing && at_rest && s.job.is_none() {
        // At rest, the return is over: made at machine zero, or stopped short (then HOME is
        // still owed, and a jog after it is not said to be HOME).
        c.posmem.homing = false;
        if s.machine_pos == [0; 3] {
            c.posmem.home_needed = false;
            c.shell.front.message =
                "HOME: the reference return is made; the position is known".into();
        }
    }
    // While the reference return is owed the file keeps saying the position is not to be
    // trusted (`moving`), at rest too: before stop 43 the first rest after a restart wrote `at
    // rest`, and a second restart before HOME forgot that the position was not known (found by
    // the random operator sequences, seed 1592590705). The best guess is still kept up to date.
    let axes_moving = s.moving || (s.job.is_some() && !s.idle);
    let now = Kept {
        moving: axes_moving || c.posmem.home_needed,
        pos: s.machine_pos,
        tool: s.tool,
        jog: c.posmem.jog,
    };
    let changed = match &c.posmem.written {
        None => true,
        Some(w) if axes_moving => !w.moving,
        Some(w) => *w != now,
    };
    if !changed {
        return;
    }
    if let Err(e) = save(&c.cfg.state_dir, &now) {
        c.shell.front.message = format!(
            "{} (the position could not be kept: {e})",
            c.shell.front.message
        );
        return;
    }
    c.posmem.written = Some(now);
}

fn save(dir: &Path, k: &Kept) -> std::io::Result<()> {
    crate::store::fsutil::write_atomic(&dir.join(FILE), k.text().as_bytes())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::panel_model::{OpMode, PanelEvent};
    use crate::pulse_core::{ClockMode, RunKind};

    /// A state directory of this test's own.
    fn state_dir(name: &str) -> std::path::PathBuf {
        let dir = std::env::temp_dir().join(format!(
            "novanc-posmem-{name}-{}-{:?}",
            std::process::id(),
            std::time::SystemTime::now()
        ));
        std::fs::create_dir_all(&dir).unwrap();
        dir
    }

    /// The centre's console on `dir`, in virtual time.
    fn open(dir: &Path) -> Console {
        let mut cfg = crate::console::ConsoleConfig::new(dir.to_path_buf());
        cfg.clock = ClockMode::Virtual;
        Console::open(cfg).unwrap().0
    }

    /// `moving` is on disk before the pulse core is given a command that can move an axis (a
    /// console killed between the command and its next frame leaves a position not trusted),
    /// and `at rest` after.
    #[test]
    fn moving_is_on_disk_before_a_motion_is_commanded() {
        let dir = state_dir("order");
        let mut c = open(&dir);
        let said = || Kept::parse(&std::fs::read_to_string(dir.join(FILE)).unwrap()).unwrap();
        assert!(!said().moving);
        for cmd in [
            Command::Increment {
                axis: 0,
                pulses: 5000,
            },
            Command::Jog { axis: 1, dir: 1 },
            Command::Home,
        ] {
            // As the console gives it, before any status poll.
            c.command(cmd.clone());
            assert!(said().moving, "{cmd:?}");
            c.command(Command::JogRelease);
            c.wait_idle();
            assert!(!said().moving, "{cmd:?}");
        }
        c.handle(PanelEvent::Op(OpMode::Mdi));
        c.handle(PanelEvent::Type("G0 X5".into()));
        super::super::run::start_program(&mut c, RunKind::Mdi);
        assert!(said().moving, "START");
        c.wait_idle();
        let k = said();
        assert!(
            !k.moving && k.pos[0] == c.settings().to_pulses(5.0),
            "{k:?}"
        );
        let _ = std::fs::remove_dir_all(&dir);
    }

    /// A restart while the axes moved owes the reference return; the file keeps saying so
    /// across the rests, manual moves and restarts that come before HOME, and only HOME's
    /// arrival at machine zero writes `at rest` again.
    #[test]
    fn home_owed_is_kept_until_home_across_restarts() {
        let dir = state_dir("owed");
        let open = || open(&dir);
        let said = || Kept::parse(&std::fs::read_to_string(dir.join(FILE)).unwrap()).unwrap();
        drop(open());
        // As a console that died moving leaves it.
        let mut k = said();
        k.moving = true;
        k.pos = [10_000, 20_000, -5_000].into();
        save(&dir, &k).unwrap();
        for restart in 0..3 {
            let mut c = open();
            assert!(c.posmem.home_needed, "restart {restart}");
            c.handle(PanelEvent::Op(OpMode::Step));
            c.handle(PanelEvent::Jog(crate::panel_model::Axis::X, 1));
            c.wait_idle();
            c.tick();
            let k = said();
            assert!(k.moving, "restart {restart}: still not trusted at rest");
            assert_eq!(k.pos, c.status.machine_pos, "the best guess follows");
            c.handle(PanelEvent::Op(OpMode::Auto));
            c.handle(PanelEvent::Start);
            assert!(c.message().starts_with("START refused"), "{}", c.message());
        }
        let mut c = open();
        c.handle(PanelEvent::Home);
        c.wait_idle();
        c.tick();
        assert!(!c.posmem.home_needed, "{}", c.message());
        assert!(!said().moving);
        drop(c);
        assert!(!open().posmem.home_needed);
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn the_file_reads_back_what_it_wrote_and_nothing_else() {
        for k in [
            Kept {
                moving: false,
                pos: [1, -2, -300_000].into(),
                tool: Some(106),
                jog: JogChoice {
                    feed: Some(512.5),
                    rapid: false,
                },
            },
            Kept {
                moving: true,
                pos: [0; 3].into(),
                tool: None,
                jog: JogChoice {
                    feed: None,
                    rapid: true,
                },
            },
        ] {
            assert_eq!(Kept::parse(&k.text()), Some(k));
        }
        // A file written before the jog line: the settings' jog feed.
        let old = Kept::parse("novanc-position 1\nat rest\n1 2 3\ntool 2\n").unwrap();
        assert_eq!((old.pos, old.jog), ([1, 2, 3].into(), JogChoice::default()));
        for bad in [
            "",
            "novanc-position 1\nmoving\n1 2\ntool none\n",
            "x\nat rest\n0 0 0\ntool 1\n",
            "novanc-position 1\nat rest\n0 0 0\ntool 1\njog -5\n",
            "novanc-position 1\nat rest\n0 0 0\ntool 1\nfeed 5\n",
        ] {
            assert_eq!(Kept::parse(bad), None, "{bad:?}");
        }
    }
}
