//! Manual moves, every console's rule (docs/panel.md "Jogging", docs/lathe.md "Moving a tool
//! post by hand"): what a jog key, a handwheel detent and the increment switch do in each
//! position of the operation selector, and what is checked before an axis moves. The
//! machining centre's console and a lathe's channel panel both decide here; each then sends
//! the move to its machine (the centre's, or the selected channel's in the one kernel) and
//! says the outcome. The machine checks again when the move starts (`Machine::jog_check`).

use crate::block::Axes;
use crate::panel_model::{Axis, OpMode};
use crate::settings::MachineSettings;

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
pub(crate) fn jog(op: OpMode, axis: Axis, dir: i8, scale: u32) -> Result<Move, String> {
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
    let (lo, hi) = s.travel_pulses(a);
    match mv {
        Move::Increment(pulses) => {
            let to = pos[a].saturating_add(pulses);
            if to < lo || to > hi {
                return Err(format!(
                    "refused: {} would go to {:.3} mm, outside travel {:.3}..{:.3}",
                    axis.letter(),
                    s.to_mm(to),
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
    format!("{:.3} mm (x{scale})", s.to_mm(i64::from(scale)))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_selector_position_gives_its_move_or_says_why_not() {
        assert_eq!(jog(OpMode::Continuous, Axis::X, -3, 100), Ok(Move::Jog(-1)));
        assert_eq!(jog(OpMode::Step, Axis::Z, 1, 100), Ok(Move::Increment(100)));
        assert!(jog(OpMode::Handle, Axis::X, 1, 100)
            .unwrap_err()
            .starts_with("HANDLE: turn the handwheel"));
        let e = jog(OpMode::Auto, Axis::Z, 1, 100).unwrap_err();
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
