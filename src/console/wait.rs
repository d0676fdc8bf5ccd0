//! A script's waits, every console's one rule (docs/cli.md "Time"; issue 22: each console
//! had its own before stop 44): `wait` runs the machine until it is at rest, `wait block N`
//! until the selected channel's block N starts, `wait ms T` for T ms of machine time. Each
//! machine runs itself (`Side::run_wait`: the centre lets a tape read end first); a wait that
//! cannot end says why on the message line and in `Front::wait_error`, which ends a script.

use super::side::Side;
use crate::pulse_core::Reached;

/// The most machine time a script `wait` (or `wait block`) runs before it gives up: 1000 hours.
pub const WAIT_LIMIT_NS: u64 = 1000 * 3600 * 1_000_000_000;

/// What a script wait runs until.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum WaitFor {
    /// Every channel at rest (`wait`).
    Idle,
    /// The selected channel's block N starts, or every channel is at rest (`wait block N`).
    Block(u32),
    /// This many ms of machine time (`wait ms T`).
    Ms(u64),
}

/// A script's wait.
pub(crate) fn wait<C: Side>(c: &mut C, w: WaitFor) {
    c.front().wait_error = None;
    let e = match c.run_wait(w) {
        Reached::Stalled => format!("wait: {}", stalled_note(0)),
        Reached::Limit => wait_limit_note(WAIT_LIMIT_NS),
        Reached::Interrupted => "wait: interrupted".into(),
        _ => return,
    };
    let f = c.front();
    f.message = e.clone();
    f.wait_error = Some(e);
}

/// Why nothing moves and nothing will until the operator acts, on every console and front
/// end: a block in progress (a feed move) at feed override `feed_override` (0).
pub(crate) fn stalled_note(feed_override: u32) -> String {
    format!("the machine stands still at feed override {feed_override} %; raise the override")
}

/// Why a script's wait of at most `limit_ns` of machine time ended without its condition, on
/// every console.
pub(crate) fn wait_limit_note(limit_ns: u64) -> String {
    format!(
        "wait: not done within {} hours of machine time",
        limit_ns / 3_600_000_000_000
    )
}
