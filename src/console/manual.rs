//! Manual moves, every console's rule (docs/panel.md "Jogging", docs/lathe.md "Moving a tool
//! post by hand"): what a jog key, a handwheel detent and the increment switch do in each
//! position of the operation selector, what is checked before an axis moves, how a move is
//! told to the machine (the centre's, or the selected channel's in the one kernel) and what
//! is said of it, and how a CONTINUOUS key held on a terminal jogs (`HeldJog`). Written once
//! over `Side` (issue 22: each console had its own copy of the flow before stop 44, and they
//! said different things). The machine checks again when the move starts
//! (`Machine::jog_check`).
//!
//! In virtual time (a script) machine time passes only in a wait and a CONTINUOUS tap
//! (docs/cli.md "Time"): a STEP or a handwheel detent is queued in the machine and moves at
//! the next wait (before stop 44 a lathe's ran to rest at once).

use super::side::Side;
use crate::block::Axes;
use crate::panel_model::{Axis, OpMode, PanelEvent};
use crate::pulse_core::{ClockMode, Command};
use crate::settings::MachineSettings;
use std::time::Instant;

/// Machine time a CONTINUOUS tap's increment gets to come to rest in virtual time (1 mm at
/// the slowest jog feed takes far less).
pub(crate) const SETTLE_LIMIT_NS: u64 = 60_000_000_000;

/// The jog feed an operator chose on POS (`JOG 500`, `JOG RAPID`, `JOG`), every machine's
/// rule: the centre's kept in its position memory, each lathe channel's its own (docs/panel.md
/// POS, docs/lathe.md "POS").
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct JogChoice {
    /// The jog feed chosen, mm/min (None: the machine's).
    pub feed: Option<f64>,
    /// Rapid jog (`JOG RAPID`): jogs at the rapid rate until `JOG` or a feed.
    pub rapid: bool,
}

impl JogChoice {
    /// Takes the rest of a POS `JOG` line, on a machine of `rapid` mm/min: `500` (a feed, 1
    /// to the rapid rate), `RAPID`, or nothing (back to the feed from rapid jog). Err: why
    /// not, nothing changed.
    pub fn take(&mut self, rest: &str, rapid: f64) -> Result<(), String> {
        match rest {
            "RAPID" => self.rapid = true,
            "" => self.rapid = false,
            _ => match rest.parse::<f64>() {
                Ok(v) if v.is_finite() && v >= 1.0 && v <= rapid => {
                    self.feed = Some(v);
                    self.rapid = false;
                }
                _ => {
                    return Err(format!(
                        "JOG refused: '{rest}' is not a jog feed (1 to {rapid:.0} mm/min), or RAPID"
                    ))
                }
            },
        }
        Ok(())
    }

    /// The jog feed in force, mm/min: the rapid rate `rapid` with rapid jog, else the one
    /// chosen, else the machine's `default`.
    pub fn rate(&self, default: f64, rapid: f64) -> f64 {
        match (self.rapid, self.feed) {
            (true, _) => rapid,
            (false, f) => f.unwrap_or(default),
        }
    }

    /// What a `JOG` line taken says, at the rate `f` now in force.
    pub fn said(&self, f: f64) -> String {
        if self.rapid {
            format!("rapid jog: {f:.0} mm/min")
        } else {
            format!("jog feed {f:.0} mm/min")
        }
    }
}

/// Where a manual move acts (`Side::manual_target`).
pub(crate) struct ManualTarget {
    /// The channel.
    pub ch: usize,
    /// Where its axes stand.
    pub pos: Axes,
    /// How the message line names the channel: `CH2 ` on a machine of several, empty on one.
    pub label: String,
    /// X is a radius (a lathe's): said so when an increment would leave the travel.
    pub x_radius: bool,
}

/// A jog event (`jog X+`, a window's jog button): CONTINUOUS jogs until released, STEP moves
/// one increment; refused, with the reason, in another position.
pub(crate) fn jog<C: Side>(c: &mut C, axis: Axis, dir: i8) {
    let f = c.front();
    let what = if f.op == OpMode::Step { "STEP" } else { "jog" };
    match jog_move(f.op, axis, dir, f.wheel.1) {
        Ok(mv) => {
            motion(c, axis, mv, what);
        }
        Err(e) => f.message = e,
    }
}

/// The handwheel (`wheel X 3`): `n` detents on `axis`, an increment each, in HANDLE only.
/// No detent (`wheel B 0`, Alt+a) turns the wheel's axis selector alone, in any position.
pub(crate) fn turn_wheel<C: Side>(c: &mut C, axis: Axis, n: i32) {
    if n == 0 {
        let s = c.axis_settings();
        let f = c.front();
        f.message = if s.has_axis(axis.index()) {
            f.wheel.0 = axis;
            format!("handwheel on {}", axis.letter())
        } else {
            format!("this machine has no {} axis", axis.letter())
        };
        return;
    }
    let f = c.front();
    f.wheel.0 = axis;
    match wheel(f.op, n, f.wheel.1) {
        Ok(0) => {}
        Ok(pulses) => {
            motion(c, axis, Move::Increment(pulses), "HANDLE");
        }
        Err(e) => f.message = e,
    }
}

/// A CONTINUOUS key tapped (`keys::press`): one increment of `axis` at jog feed, run to rest
/// in virtual time.
pub(crate) fn tap<C: Side>(c: &mut C, axis: Axis, dir: i8) {
    let pulses = i64::from(dir.signum()) * i64::from(c.front().wheel.1);
    if let Some(ch) = motion(c, axis, Move::Increment(pulses), "CONTINUOUS") {
        if c.clock() == ClockMode::Virtual {
            c.settle(ch);
        }
    }
}

/// Once a frame: a held CONTINUOUS key that stopped repeating lets its jog go (recorded as
/// the key let go); a jog a front end's button holds is kept alive while it moves (docs/panel.md
/// "The jog deadman": a front end that stops drawing lets the machine stop it).
pub(crate) fn keep<C: Side>(c: &mut C) {
    if c.front().jog_key.expired(Instant::now()) {
        c.record(&PanelEvent::JogRelease);
        release(c, true);
    }
    let f = c.front();
    if let (Some(ch), true) = (f.jogging, f.jog_key.is_none()) {
        let moving = c.channels().get(ch).is_some_and(|s| s.moving);
        if moving && c.clock() == ClockMode::RealTime {
            c.tell(ch, Command::JogAlive(super::deadman_ms()));
        }
    }
}

/// Lets a CONTINUOUS jog go: the machine is told when one was begun, or `always` (a jog the
/// console lost track of must still stop; told to the selected channel then).
pub(crate) fn release<C: Side>(c: &mut C, always: bool) {
    let f = c.front();
    f.jog_key.clear();
    let jogging = f.jogging.take();
    if always || jogging.is_some() {
        let ch = jogging.unwrap_or_else(|| c.selected());
        c.tell(ch, Command::JogRelease);
    }
}

/// A manual move the selector allowed, of the selected channel's `axis`: checked (E-STOP,
/// the machine's own refusal, the travel), told to the machine and said. The channel it was
/// told to, if it was.
fn motion<C: Side>(c: &mut C, axis: Axis, mv: Move, what: &str) -> Option<usize> {
    let said = |c: &mut C, m: String| {
        c.front().message = m;
        None
    };
    if c.channels().iter().any(|s| s.estop) {
        return said(
            c,
            format!("{what} refused: EMERGENCY STOP in force, press RESET"),
        );
    }
    let t = match c.manual_target(axis, what) {
        Ok(t) => t,
        Err(e) => return said(c, e),
    };
    if let Err(e) = check(&c.axis_settings(), t.pos, axis, mv) {
        return said(
            c,
            match mv {
                Move::Increment(_) if t.x_radius => {
                    format!("{what} {}", e.replacen("X would", "X (a radius) would", 1))
                }
                Move::Increment(_) => format!("{what} {e}"),
                Move::Jog(_) => e,
            },
        );
    }
    let a = axis.index();
    c.tell(
        t.ch,
        match mv {
            Move::Increment(pulses) => Command::Increment { axis: a, pulses },
            Move::Jog(dir) => Command::Jog { axis: a, dir },
        },
    );
    // The machine's refusal, in its words.
    if let Some(n) = c.channels().get(t.ch).and_then(|s| s.notice.clone()) {
        return said(c, n);
    }
    let sign = |n: i64| if n < 0 { '-' } else { '+' };
    let now = c.now_ns();
    let (text, life) = match mv {
        Move::Jog(dir) => {
            c.front().jogging = Some(t.ch);
            if c.clock() == ClockMode::RealTime {
                // Hold-to-run: the key's repeats (a button's frames) keep the jog alive, or
                // the machine stops it.
                c.tell(t.ch, Command::JogAlive(super::deadman_ms()));
            }
            (
                format!(
                    "CONTINUOUS {}{}{}: jogging",
                    t.label,
                    axis.letter(),
                    sign(i64::from(dir))
                ),
                super::MsgLife::WhileRunning,
            )
        }
        Move::Increment(pulses) => {
            let scale = c.front().wheel.1;
            let detents = pulses.unsigned_abs() / u64::from(scale.max(1));
            let times = if detents > 1 {
                format!("{detents} × ")
            } else {
                String::new()
            };
            let inc = increment_on(&c.axis_settings(), scale, Some(axis.index()));
            (
                format!(
                    "{what} {}{}{} {times}{inc}",
                    t.label,
                    axis.letter(),
                    sign(pulses)
                ),
                super::MsgLife::NextKey,
            )
        }
    };
    c.front().say(text, life, now);
    Some(t.ch)
}

/// The increments, in pulses: the handwheel per detent, STEP per key and a CONTINUOUS tap
/// (docs/panel.md, "Jogging"): 0.001, 0.01, 0.1 and 1 mm at the default pulse of 0.001 mm.
pub(crate) const SCALES: [u32; 4] = [1, 10, 100, 1000];

/// A manual move the selector allows.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Move {
    /// This many pulses at jog feed: STEP, a CONTINUOUS tap, handwheel detents.
    Increment(i64),
    /// At jog feed in this direction (−1 or 1) until released or at the travel limit:
    /// CONTINUOUS.
    Jog(i8),
}

/// What a jog event (`jog X+`, a window's jog button) does in selector position `op` with the
/// increment `scale`: the move, or why none. In HANDLE a jog key turns the handwheel before it
/// gets here (the key map), so an event here is refused.
pub(crate) fn jog_move(op: OpMode, axis: Axis, dir: i8, scale: u32) -> Result<Move, String> {
    let dir: i8 = if dir < 0 { -1 } else { 1 };
    match op {
        OpMode::Continuous => Ok(Move::Jog(dir)),
        OpMode::Step => Ok(Move::Increment(i64::from(dir) * i64::from(scale))),
        OpMode::Handle => {
            Err("HANDLE: turn the handwheel (Alt+, Alt+.; a jog key turns it on its axis)".into())
        }
        _ => Err(format!(
            "jog {} refused in {}: turn to CONTINUOUS (Alt+1), HANDLE (Alt+5) or STEP (Alt+6)",
            axis.letter(),
            op.name()
        )),
    }
}

/// A handwheel turn of `n` detents in selector position `op`: the pulses, or why none (HANDLE
/// only).
pub(crate) fn wheel(op: OpMode, n: i32, scale: u32) -> Result<i64, String> {
    if op != OpMode::Handle {
        return Err(format!(
            "handwheel refused: turn the operation selector to HANDLE (now {})",
            op.name()
        ));
    }
    Ok(i64::from(n) * i64::from(scale))
}

/// Whether `mv` of `axis` from `pos` keeps inside the travel of `s`: an increment must end
/// inside it, a jog must have room to go; if not, the operator's message.
pub(crate) fn check(s: &MachineSettings, pos: Axes, axis: Axis, mv: Move) -> Result<(), String> {
    let a = axis.index();
    if !s.has_axis(a) {
        return Err(format!("this machine has no {} axis", axis.letter()));
    }
    if s.wrapped(a) {
        // A wrapped rotary axis turns without end.
        return Ok(());
    }
    let (lo, hi) = s.travel_pulses(a);
    match mv {
        Move::Increment(pulses) => {
            let to = pos[a].saturating_add(pulses);
            if to < lo || to > hi {
                return Err(format!(
                    "refused: {} would go to {:.3} {}, outside travel {:.3}..{:.3}",
                    axis.letter(),
                    s.to_mm(to),
                    s.unit(a),
                    s.to_mm(lo),
                    s.to_mm(hi)
                ));
            }
        }
        Move::Jog(dir) => {
            if (dir < 0 && pos[a] <= lo) || (dir > 0 && pos[a] >= hi) {
                return Err(format!(
                    "jog refused: {} is at its travel limit",
                    axis.letter()
                ));
            }
        }
    }
    Ok(())
}

/// The increment switch set to `scale` (`wheelscale N`): the message, or why not.
pub(crate) fn set_scale(s: &MachineSettings, scale: u32) -> Result<String, String> {
    if !SCALES.contains(&scale) {
        return Err(format!("increment x{scale}: only x1, x10, x100, x1000"));
    }
    Ok(format!(
        "increment {}: a STEP, a handwheel detent and a CONTINUOUS tap",
        increment_text(s, scale)
    ))
}

/// The increment switch's next position (Alt+w): after x1000, x1 again.
pub(crate) fn next_scale(scale: u32) -> u32 {
    let i = SCALES.iter().position(|&k| k == scale).unwrap_or(0);
    SCALES[(i + 1) % SCALES.len()]
}

/// An increment as the operator reads it: "0.100 mm (x100)".
pub(crate) fn increment_text(s: &MachineSettings, scale: u32) -> String {
    increment_on(s, scale, None)
}

/// [`increment_text`] on `axis` (an index into X Y Z A B C): in degrees on a rotary axis.
pub(crate) fn increment_on(s: &MachineSettings, scale: u32, axis: Option<usize>) -> String {
    let unit = axis.map_or("mm", |a| s.unit(a));
    format!("{:.3} {unit} (x{scale})", s.to_mm(i64::from(scale)))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_selector_position_gives_its_move_or_says_why_not() {
        assert_eq!(
            jog_move(OpMode::Continuous, Axis::X, -3, 100),
            Ok(Move::Jog(-1))
        );
        assert_eq!(
            jog_move(OpMode::Step, Axis::Z, 1, 100),
            Ok(Move::Increment(100))
        );
        assert!(jog_move(OpMode::Handle, Axis::X, 1, 100)
            .unwrap_err()
            .starts_with("HANDLE: turn the handwheel"));
        let e = jog_move(OpMode::Auto, Axis::Z, 1, 100).unwrap_err();
        assert!(e.starts_with("jog Z refused in AUTO"), "{e}");
        assert_eq!(wheel(OpMode::Handle, -3, 10), Ok(-30));
        assert!(wheel(OpMode::Step, 1, 10).is_err());
        assert_eq!(next_scale(1000), 1);
        assert_eq!(next_scale(10), 100);
        let s = MachineSettings::default();
        assert!(set_scale(&s, 7).is_err());
        assert!(set_scale(&s, 10).unwrap().contains("0.010 mm (x10)"));
    }

    #[test]
    fn the_travel_is_checked_before_a_move() {
        let s = MachineSettings::default();
        let (lo, hi) = s.travel_pulses(0);
        let at_hi = Axes::from([hi, 0, 0]);
        assert!(check(&s, at_hi, Axis::X, Move::Increment(1)).is_err());
        assert!(check(&s, at_hi, Axis::X, Move::Increment(-1)).is_ok());
        assert!(check(&s, at_hi, Axis::X, Move::Jog(1)).is_err());
        assert!(check(&s, Axes::from([lo, 0, 0]), Axis::X, Move::Jog(1)).is_ok());
    }
}
