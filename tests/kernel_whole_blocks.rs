//! The whole-block fast-forward with a live spindle (docs/pulse-core.md, "Whole blocks at
//! once"): on the Citizen, a spindle with a ramp turns through most of every cycle, and a block
//! whose ticks cannot change the spindle's target or the feed per revolution runs whole. A
//! watcher keeps every such block tick by tick (it would see the state at every tick), so the
//! same kernel with and without one must make the same pulses at the same times, end the same
//! blocks at the same times and deliver the parts at the same machine time.

use novanc::lathe::desc::{load, MachineDesc};
use novanc::lathe::testkit::{citizen_programs, kernel};
use novanc::pulse_core::{Kernel, Outcome};

const HOUR: u64 = 3_600_000_000_000;

/// The Citizen with its own programs to `parts`, every channel capturing its pulses and block
/// ends; with a watcher that is told nothing useful if `ticks`.
fn citizen(parts: u32, ticks: bool) -> Kernel {
    let desc = match load("citizen") {
        Ok(MachineDesc::Lathe(d)) => d,
        _ => panic!("the Citizen is a lathe"),
    };
    let programs = citizen_programs(&desc).expect("the Citizen's programs read");
    let mut k = kernel(&desc, programs, parts, None).expect("the kernel");
    for ch in 0..k.channels() {
        let m = k.machine_mut(ch).expect("channel");
        m.set_recording(None, true);
        m.set_audit(true);
    }
    if ticks {
        k.set_watch(Some(std::sync::Arc::new(|_: &[_]| {})));
    }
    k.start(None).expect("START");
    k
}

#[test]
fn the_citizen_runs_the_same_with_blocks_run_whole_and_tick_by_tick() {
    let parts = 3;
    let (mut whole, mut ticked) = (citizen(parts, false), citizen(parts, true));
    let done = whole.run_until_idle(HOUR);
    assert_eq!(done, Outcome::Finished { parts });
    assert_eq!(ticked.run_until_idle(HOUR), done);
    assert_eq!(whole.finished_at(), ticked.finished_at(), "the parts' time");
    for ch in 0..whole.channels() {
        let (a, b) = (
            whole.machine_mut(ch).expect("channel"),
            ticked.machine_mut(ch).expect("channel"),
        );
        let (pa, pb) = (a.take_pulses(), b.take_pulses());
        assert!(pa.len() > 10_000, "channel {ch} moved");
        assert!(pa == pb, "channel {ch}: the pulses and their times");
        assert_eq!(
            a.take_audit(),
            b.take_audit(),
            "channel {ch}: the block ends"
        );
        assert_eq!(a.spindle(), b.spindle(), "channel {ch}: the spindle");
    }
}
