//! A lathe's position memory and reference return (docs/lathe.md "Position memory"): the
//! centre's rule (`crate::console::posmem`) for each tool post, kept in the lathe's journaled
//! stores (`posts`, docs/stores.md). Before anything can set a tool post moving (a cycle's or
//! an MDI run's START, a resume, a jog, a STEP or handwheel increment, HOME) the stores say
//! `moving` for it, on disk; once it stands still they say `rest` with where it stands. A
//! console that died while a post moved leaves `moving`: the next one places the post where it
//! was last kept (its best guess) but owes that channel's reference return, and refuses AUTO
//! and the channel's MDI until HOME (Alt+0, script word `home`) has taken the post to the top
//! of its travel, X first, then Z.

use super::LatheConsole;
use crate::lathe::desc::LatheDesc;
use crate::store::lathe::Post;

/// The position memory's part of the lathe console.
#[derive(Debug, Default)]
pub(super) struct Posts {
    /// What the stores say now (None: nothing kept yet).
    written: Option<Vec<Post>>,
    /// Each channel owes the reference return: its position was not known at the opening.
    owed: Vec<bool>,
    /// Each channel's HOME under way.
    homing: Vec<bool>,
}

/// What HOME does on a lathe's channel, said when it is pressed.
pub(super) fn homing_said(ch: usize) -> String {
    format!("CH{} HOME: reference return, X first, then Z", ch + 1)
}

/// Whether `pos` (pulses [X radius, Z]) lies inside channel `ch`'s travel.
fn within_travel(desc: &LatheDesc, ch: usize, pos: [i64; 2]) -> bool {
    desc.channels.get(ch).is_some_and(|c| {
        (c.axes.iter().zip(pos))
            .all(|(a, p)| (desc.pulses(a.travel[0])..=desc.pulses(a.travel[1])).contains(&p))
    })
}

/// The channels as `CH1, CH3`.
fn names(chs: &[usize]) -> String {
    let v: Vec<String> = chs.iter().map(|c| format!("CH{}", c + 1)).collect();
    v.join(", ")
}

impl Posts {
    /// At the opening: where each channel's tool post starts (where the stores kept it, else
    /// the top of its travel) and the position memory, with what the operator must be told.
    /// A post kept while moving starts there (the best guess) and owes HOME; one kept outside
    /// its channel's travel (the description changed) starts at the top and owes HOME too.
    pub(super) fn restore(
        desc: &LatheDesc,
        kept: Option<Vec<Post>>,
    ) -> (Posts, Vec<[i64; 2]>, Option<String>) {
        let n = desc.channels.len();
        let mut pos: Vec<[i64; 2]> = (0..n).map(|ch| super::glue::home(desc, ch)).collect();
        let mut owed = vec![false; n];
        let (mut moved, mut outside) = (Vec::new(), Vec::new());
        for (ch, p) in kept.iter().flatten().enumerate().take(n) {
            if !within_travel(desc, ch, p.pos) {
                owed[ch] = true;
                outside.push(ch);
            } else {
                pos[ch] = p.pos;
                owed[ch] = p.moving;
                if p.moving {
                    moved.push(ch);
                }
            }
        }
        let said = if !outside.is_empty() {
            Some(format!(
                "{}: the kept position is outside the travel; the post starts at the top of it, not known: make the reference return (HOME, Alt+0) before AUTO or MDI",
                names(&outside)
            ))
        } else if !moved.is_empty() {
            Some(format!(
                "the console stopped while {} moved: the position is not known; make the reference return (HOME, Alt+0) on each before AUTO or MDI",
                names(&moved)
            ))
        } else {
            None
        };
        let posts = Posts {
            written: kept,
            owed,
            homing: vec![false; n],
        };
        (posts, pos, said)
    }

    /// The channels that owe the reference return, of `chs`.
    fn owing(&self, chs: impl IntoIterator<Item = usize>) -> Vec<usize> {
        chs.into_iter()
            .filter(|&c| self.owed.get(c).copied().unwrap_or(false))
            .collect()
    }
}

impl LatheConsole {
    /// Which channels owe the reference return (their position was not known at the opening,
    /// and HOME has not yet been made).
    pub fn home_owed(&self) -> &[bool] {
        &self.posts.owed
    }

    /// Why START may not run channels `chs` now: one owes the reference return.
    pub(super) fn home_refusal(&self, chs: impl IntoIterator<Item = usize>) -> Option<String> {
        let owing = self.posts.owing(chs);
        (!owing.is_empty()).then(|| {
            format!(
                "START refused: {}'s position is not known since the restart; make the reference return first (HOME, Alt+0)",
                names(&owing)
            )
        })
    }

    /// Before a command that can set the tool posts of `chs` moving: the stores say `moving`
    /// for them, on disk. If they cannot, the move is refused (Err, why): a console killed
    /// during it would leave a position kept at rest that the post no longer has.
    pub(super) fn before_motion(&mut self, chs: &[usize]) -> Result<(), String> {
        let axes = self.cycle.axes();
        let mut next: Vec<Post> = match &self.posts.written {
            Some(w) if w.len() == axes.len() => w.clone(),
            _ => (axes.iter().zip(&self.posts.owed))
                .map(|(&pos, &owed)| Post { moving: owed, pos })
                .collect(),
        };
        if chs.iter().all(|&c| next.get(c).is_some_and(|p| p.moving))
            && self.posts.written.is_some()
        {
            return Ok(());
        }
        for &c in chs {
            if let Some(p) = next.get_mut(c) {
                p.moving = true;
            }
        }
        self.store.save_posts(&next)?;
        self.posts.written = Some(next);
        Ok(())
    }

    /// HOME: the selected channel's reference return, X out to the top of its travel, then Z.
    pub(super) fn home(&mut self) {
        let ch = self.sel;
        let c = &mut self.cycle;
        c.refresh();
        if c.channels().iter().any(|s| s.status.estop) {
            self.shell.front.message = format!(
                "CH{} HOME refused: EMERGENCY STOP in force, press RESET",
                ch + 1
            );
            return;
        }
        if c.loaded() && !c.is_over() {
            self.shell.front.message = format!(
                "CH{} HOME refused: a cycle is under way (RESET it first)",
                ch + 1
            );
            return;
        }
        if let Err(e) = self.before_motion(&[ch]) {
            self.shell.front.message = format!("CH{} HOME refused: {e}", ch + 1);
            return;
        }
        self.cycle.manual(ch, crate::pulse_core::Command::Home);
        let notice = (self.cycle.channels().get(ch)).and_then(|s| s.status.notice.clone());
        if let Some(n) = notice {
            self.shell.front.message = format!("CH{} {n}", ch + 1);
            return;
        }
        self.posts.homing[ch] = true;
        self.shell.front.message = homing_said(ch);
    }

    /// After each step of the machine: the stores follow what the tool posts do (written
    /// only when that changes: `moving` when one starts, where they stand when they come to
    /// rest), and a HOME that arrived at the top of the travel settles that channel's
    /// position. While a channel owes HOME its post stays `moving` in the stores, at rest too
    /// (the centre's rule, found by its random operator sequences): a second restart still
    /// owes it.
    pub(super) fn track_posts(&mut self) {
        let chans = self.cycle.channels();
        let axes = self.cycle.axes();
        let mut now = Vec::with_capacity(chans.len());
        let mut moving_now = Vec::with_capacity(chans.len());
        for (ch, (c, &pos)) in chans.iter().zip(&axes).enumerate() {
            let s = &c.status;
            let progressing = c.sync.as_ref().is_some_and(|v| v.progressing);
            let moving = s.moving || (s.job.is_some() && !s.idle) || progressing;
            if !moving && self.posts.homing.get(ch).copied().unwrap_or(false) {
                // At rest, the return is over: made at the top of the travel, or stopped
                // short by E-STOP or STOP (then HOME is still owed).
                self.posts.homing[ch] = false;
                if pos == super::glue::home(&self.desc, ch) {
                    self.posts.owed[ch] = false;
                    self.shell.front.message = format!(
                        "CH{} HOME: the reference return is made; the position is known",
                        ch + 1
                    );
                }
            }
            let owed = self.posts.owed.get(ch).copied().unwrap_or(false);
            moving_now.push(moving);
            now.push(Post {
                moving: moving || owed,
                pos,
            });
        }
        let changed = match &self.posts.written {
            // Nothing kept yet: the posts stand where the opening put them until one moves.
            None => moving_now.iter().any(|&m| m),
            Some(w) if w.len() != now.len() => true,
            // While a post moves only its turn to `moving` is written, not each position; at
            // rest (HOME owed or not) where it stands.
            Some(w) => {
                (w.iter().zip(&now).zip(&moving_now))
                    .any(|((w, n), &moving)| if moving { !w.moving } else { w != n })
            }
        };
        if !changed {
            return;
        }
        match self.store.save_posts(&now) {
            Ok(()) => self.posts.written = Some(now),
            Err(e) => self.shell.front.say_failure(&e, self.now_ns),
        }
    }
}
