//! Position memory (issue 23; docs/stores.md, "Position memory"): the machine position and the
//! tool in the spindle, kept in the state directory's `position` file so that a restart knows
//! where the axes are. The file says `moving` as soon as the console sees an axis move and the
//! position with `at rest` once they stand still; a console that died while the axes moved
//! leaves `moving`, and the next one cannot trust the position: it says so and refuses AUTO
//! and MDI until the reference return (HOME, Alt+0, script word `home`) has been made.

use super::Console;
use crate::pulse_core::Command;
use std::path::Path;

/// The file in the state directory.
pub const FILE: &str = "position";

/// What the file says.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Kept {
    /// The axes were moving when it was written: the position is not to be trusted.
    pub moving: bool,
    /// Machine position, pulses.
    pub pos: [i64; 3],
    /// The tool in the spindle.
    pub tool: Option<u32>,
}

impl Kept {
    fn text(&self) -> String {
        format!(
            "novanc-position 1\n{}\n{} {} {}\ntool {}\n",
            if self.moving { "moving" } else { "at rest" },
            self.pos[0],
            self.pos[1],
            self.pos[2],
            self.tool.map_or("none".to_string(), |t| t.to_string())
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
        let pos: [i64; 3] = p.try_into().ok()?;
        let tool = match l.next()?.strip_prefix("tool ")? {
            "none" => None,
            t => Some(t.parse().ok()?),
        };
        Some(Kept { moving, pos, tool })
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
            c.message = format!(
                "the kept position cannot be read ({e}): make the reference return (HOME, Alt+0) before AUTO or MDI"
            );
            return;
        }
    };
    let Some(k) = Kept::parse(&text) else {
        c.posmem.home_needed = true;
        c.message = format!(
            "the kept position ({}) is damaged: make the reference return (HOME, Alt+0) before AUTO or MDI",
            path.display()
        );
        return;
    };
    c.core.set_position(k.pos);
    c.core.command(Command::SetTool(k.tool));
    if k.moving {
        c.posmem.home_needed = true;
        c.message = "the console stopped while the axes moved: the position is not known; make the reference return (HOME, Alt+0) before AUTO or MDI".into();
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
    c.command(Command::Home);
    if let Some(n) = c.status.notice.clone() {
        c.message = n;
        return;
    }
    c.posmem.homing = true;
    c.message = "HOME: reference return, Z first, then X and Y".into();
}

/// After each status poll: the file follows what the axes do (written only when that
/// changes: `moving` when they start, the position when they come to rest), and a HOME that
/// has arrived at machine zero clears the owed reference return.
pub(super) fn track(c: &mut Console) {
    let s = &c.status;
    let at_rest = !s.moving && s.idle;
    if c.posmem.homing && at_rest && s.job.is_none() && s.machine_pos == [0; 3] {
        c.posmem.homing = false;
        c.posmem.home_needed = false;
        c.message = "HOME: the reference return is made; the position is known".into();
    }
    let now = Kept {
        moving: s.moving || (s.job.is_some() && !s.idle),
        pos: s.machine_pos,
        tool: s.tool,
    };
    let changed = match &c.posmem.written {
        None => true,
        Some(w) if now.moving => !w.moving,
        Some(w) => *w != now,
    };
    if !changed {
        return;
    }
    if let Err(e) = save(&c.cfg.state_dir, &now) {
        c.message = format!("{} (the position could not be kept: {e})", c.message);
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

    #[test]
    fn the_file_reads_back_what_it_wrote_and_nothing_else() {
        for k in [
            Kept {
                moving: false,
                pos: [1, -2, -300_000],
                tool: Some(106),
            },
            Kept {
                moving: true,
                pos: [0; 3],
                tool: None,
            },
        ] {
            assert_eq!(Kept::parse(&k.text()), Some(k));
        }
        for bad in [
            "",
            "novanc-position 1\nmoving\n1 2\ntool none\n",
            "x\nat rest\n0 0 0\ntool 1\n",
        ] {
            assert_eq!(Kept::parse(bad), None, "{bad:?}");
        }
    }
}
