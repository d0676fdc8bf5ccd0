//! Lathe simulator benchmark (issue 13): the three-channel, 5-part sample run
//! (`novanc::lathe::sim::testkit`) in process: ticks per second, axis pulses per second and
//! the machine time, with event recording on (1 ms samples, drained as a recorder would) and
//! off. Best of 5 runs each.
//!
//! Run with `cargo bench --bench lathe`.

use novanc::lathe::sim::testkit::sample_lathe;
use novanc::lathe::sim::Outcome;
use std::time::Instant;

/// One 5-part run: (wall seconds, ticks, axis pulses, machine ns, events).
fn run(record: bool) -> Result<(f64, u64, u64, u64, usize), String> {
    let mut l = sample_lathe(5)?;
    l.set_recording(record, 1_000_000);
    l.start();
    let t0 = Instant::now();
    let mut events = 0;
    let outcome = loop {
        // A recorder drains the events every 100 ms of machine time.
        let o = l.run_until_idle(100_000_000);
        events += l.drain_events().len();
        if o != Outcome::TimeLimit {
            break o;
        }
    };
    let wall = t0.elapsed().as_secs_f64();
    if outcome != (Outcome::Finished { parts: 5 }) {
        return Err(format!("the sample run ended {outcome:?}"));
    }
    let s = l.stats();
    let pulses = s.channels.iter().flat_map(|c| c.pulses).sum();
    Ok((wall, s.ticks, pulses, s.machine_ns, events))
}

fn main() {
    for record in [false, true] {
        let mut best: Option<(f64, u64, u64, u64, usize)> = None;
        for _ in 0..5 {
            match run(record) {
                Ok(r) => {
                    if best.is_none_or(|b| r.0 < b.0) {
                        best = Some(r);
                    }
                }
                Err(e) => {
                    eprintln!("lathe bench: {e}");
                    std::process::exit(1);
                }
            }
        }
        if let Some((wall, ticks, pulses, machine, events)) = best {
            println!(
                "lathe 5-part run, recording {}: {:.1} ms wall, {} ticks ({:.2} M ticks/s), \
                 {} axis pulses ({:.2} M pulses/s), machine time {:.3} s ({:.0}x real time), \
                 {} events",
                if record { "on " } else { "off" },
                wall * 1e3,
                ticks,
                ticks as f64 / wall / 1e6,
                pulses,
                pulses as f64 / wall / 1e6,
                machine as f64 * 1e-9,
                machine as f64 * 1e-9 / wall,
                events
            );
        }
    }
}
