//! Synthetic recordings for tests and benchmarks: a seeded run of events on every topic, with
//! the awkward parts a real run has (pulse batches of several axes whose first pulses are out of
//! order, unicode and characters that need escaping in display lines).

use super::Event;
use crate::pulse_core::testkit::Rng;

/// A run of `slices` NCBR ticks (5 ms): a block now and then, pulses of every axis in each tick
/// (sent Z, Y, X, so a later axis can start earlier than the batch before it), a position per
/// tick, states, display frames with unicode and characters that need escaping, panel events.
pub fn synthetic_run(seed: u64, slices: u64) -> Vec<Event> {
    let mut rng = Rng::new(seed | 1);
    let mut evs = Vec::new();
    let mut pos = [0i64; 3];
    let tick = 5_000_000u64;
    evs.push(Event::PanelEvent {
        t_ns: 0,
        event: "key START".into(),
    });
    evs.push(Event::State {
        t_ns: 0,
        run: 1,
        op_mode: "AUTO".into(),
        data_mode: "RUN".into(),
        feed_override: 100,
        tool: 0,
        spindle: 0,
        switches: Default::default(),
    });
    for s in 0..slices {
        let t0 = s * tick;
        if s % 7 == 0 {
            evs.push(Event::Block {
                t_ns: t0,
                seq: (s / 7) as u32,
                stmt: (s / 7 + 1) as u32,
                text: format!("N{} G01 X{}. Y-2.5 F300 (\"quoted\" \\ path)", s / 7, s),
            });
        }
        for axis in [2u8, 1, 0] {
            let n = rng.next_u64() % 400;
            if n == 0 {
                continue;
            }
            let dir: i8 = if rng.next_u64().is_multiple_of(2) {
                1
            } else {
                -1
            };
            let start = t0 + rng.next_u64() % (tick / 2);
            let step = (tick / 2) / n;
            let times: Vec<u64> = (0..n).map(|k| start + k * step).collect();
            pos[axis as usize] += dir as i64 * n as i64;
            evs.push(Event::Pulses {
                axis,
                dir,
                t_ns: times,
            });
        }
        evs.push(Event::Position {
            t_ns: t0 + tick,
            pulses: pos.into(),
            held: Default::default(),
            speed_mm_min: 1000.0,
        });
        if s % 10 == 0 {
            evs.push(Event::Display {
                t_ns: t0,
                lines: vec![
                    format!(
                        "X {:>10.3}  Y {:>10.3}",
                        pos[0] as f64 / 1e3,
                        pos[1] as f64 / 1e3
                    ),
                    "ÄÖÜ ß Ø20 ±0.01 µm → «ok» 工具 🛠".into(),
                    "tab\there \"q\" back\\slash \u{1} bell\u{7}".into(),
                    String::new(),
                ],
            });
            evs.push(Event::State {
                t_ns: t0,
                run: 1,
                op_mode: "AUTO".into(),
                data_mode: "RUN".into(),
                feed_override: (s % 150) as u32,
                tool: (s % 24) as u32,
                spindle: if s % 20 == 0 { -1200 } else { 800 },
                switches: Default::default(),
            });
        }
        if s % 17 == 0 {
            evs.push(Event::Probe {
                t_ns: t0 + tick,
                seq: s as u32,
                stmt: (s / 2) as u32,
                pulses: pos.into(),
                tripped: s % 34 == 0,
                at_start: s % 51 == 0,
            });
        }
        if s % 19 == 0 {
            evs.push(Event::Io {
                t_ns: t0 + tick,
                seq: s as u32,
                stmt: (s / 2) as u32,
                digital: s % 38 == 0,
                index: (s % 64) as u8,
                value: (s % 7) as f64 * 0.5,
                synced: s % 57 == 0,
                input: s % 95 == 0,
            });
        }
        if s % 23 == 0 {
            evs.push(Event::Log {
                t_ns: t0 + 2,
                level: 2 + (s % 3) as u8,
                name: "console".into(),
                message: format!("MSG: \"{s}\" ±0.01 → ok\ttab"),
                file: "O0001".into(),
                line: (s / 3) as u32,
            });
        }
        if s % 13 == 0 {
            evs.push(Event::PanelEvent {
                t_ns: t0 + 1,
                event: format!("override {}", s % 150),
            });
        }
    }
    evs
}
