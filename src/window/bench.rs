//! The `--bench-frames` measurement: frame intervals, eframe's frame CPU time, machine time
//! against wall time, and the pulses counted meanwhile; printed as one line.

use std::time::Instant;

/// Figures measured over a `--bench-frames` run.
#[derive(Debug, Default)]
pub struct Bench {
    started: Option<Instant>,
    machine_ns0: u64,
    last_frame: Option<Instant>,
    intervals_ms: Vec<f64>,
    cpu_ms: Vec<f64>,
    pulses: u64,
    last_pulses: Option<u64>,
}

impl Bench {
    /// Takes one frame's figures; after `n` frames, the report line.
    pub fn frame(
        &mut self,
        n: u64,
        machine_ns: u64,
        cpu_s: Option<f32>,
        pulses_now: u64,
    ) -> Option<String> {
        let now = Instant::now();
        if self.started.is_none() {
            self.started = Some(now);
            self.machine_ns0 = machine_ns;
        }
        if let Some(last) = self.last_frame {
            self.intervals_ms
                .push(now.duration_since(last).as_secs_f64() * 1e3);
        }
        self.last_frame = Some(now);
        if let Some(cpu) = cpu_s {
            self.cpu_ms.push(cpu as f64 * 1e3);
        }
        // The pulse counters restart with each run: count what they gained.
        self.pulses += match self.last_pulses {
            Some(last) if pulses_now >= last => pulses_now - last,
            Some(_) => pulses_now,
            None => 0,
        };
        self.last_pulses = Some(pulses_now);
        if (self.intervals_ms.len() as u64) < n {
            return None;
        }
        let wall = self.started.map_or(0.0, |s| s.elapsed().as_secs_f64());
        let machine = machine_ns.saturating_sub(self.machine_ns0) as f64 / 1e9;
        Some(bench_report(self, wall, machine))
    }
}

/// Median, 95th percentile and largest of a sample.
fn spread(v: &[f64]) -> (f64, f64, f64) {
    if v.is_empty() {
        return (0.0, 0.0, 0.0);
    }
    let mut s = v.to_vec();
    s.sort_by(f64::total_cmp);
    let at = |q: f64| s[((s.len() - 1) as f64 * q).round() as usize];
    (at(0.5), at(0.95), s[s.len() - 1])
}

fn bench_report(b: &Bench, wall: f64, machine: f64) -> String {
    let (i50, i95, imax) = spread(&b.intervals_ms);
    let (c50, c95, cmax) = spread(&b.cpu_ms);
    let fps = if wall > 0.0 {
        b.intervals_ms.len() as f64 / wall
    } else {
        0.0
    };
    format!(
        "bench-frames {n}: frame interval ms median {i50:.2} p95 {i95:.2} max {imax:.2} \
         ({fps:.1} fps); frame cpu ms median {c50:.2} p95 {c95:.2} max {cmax:.2}; \
         wall {wall:.2} s, machine {machine:.2} s (machine/wall {ratio:.3}); \
         pulses {p} ({rate:.0} pulses/s)",
        n = b.intervals_ms.len(),
        ratio = if wall > 0.0 { machine / wall } else { 0.0 },
        p = b.pulses,
        rate = if wall > 0.0 {
            b.pulses as f64 / wall
        } else {
            0.0
        },
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn spread_takes_median_p95_and_max() {
        assert_eq!(spread(&[3.0, 1.0, 2.0]), (2.0, 3.0, 3.0));
        assert_eq!(spread(&[]), (0.0, 0.0, 0.0));
    }

    #[test]
    fn pulses_are_counted_across_a_counter_restart_and_the_report_comes_after_n_frames() {
        let mut b = Bench::default();
        assert_eq!(b.frame(3, 0, None, 100), None);
        assert_eq!(b.frame(3, 1_000_000_000, Some(0.002), 150), None);
        assert_eq!(b.frame(3, 2_000_000_000, Some(0.002), 20), None); // a new run
        let r = b
            .frame(3, 3_000_000_000, Some(0.002), 30)
            .expect("the report after 3 frames");
        assert_eq!(b.pulses, 50 + 20 + 10);
        assert!(r.starts_with("bench-frames 3:"), "{r}");
        assert!(r.contains("machine 3.00 s"), "{r}");
        assert!(r.contains("pulses 80 "), "{r}");
    }
}
