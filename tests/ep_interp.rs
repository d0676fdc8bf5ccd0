//! The error-proportional interpolator (seed 001) through the machine, on virtual time:
//! random lines in every direction within 1 pulse of the path and exactly on their end, pulse
//! totals equal to the counters, no pulse after the end, axis rates in the ratio of the
//! remaining errors, the exponential tail against L / f_r, feed, override, hold, E-STOP and
//! the same pulses tick by tick as whole blocks. docs/pulse-core.md, "The error-proportional
//! interpolator".

use novanc::pulse_core::testkit::{linear, Rng};
use novanc::pulse_core::{Command, Machine, PulseRec, RunKind, VecSource};
use novanc::settings::{Interpolator, MachineSettings, EP_CYCLE_NS, EP_L_DEFAULT};

const MID: [i64; 3] = [500_000, 400_000, -300_000];
const HOUR: u64 = 3_600_000_000_000;

fn settings() -> MachineSettings {
    MachineSettings {
        interpolator: Interpolator::ErrorProportional,
        ..MachineSettings::default()
    }
}

fn machine(s: MachineSettings) -> Machine {
    let mut m = Machine::new(s);
    assert!(m.set_position(MID));
    m.set_recording(None, true);
    m.set_audit(true);
    m
}

fn run(m: &mut Machine, blocks: Vec<novanc::block::Block>) -> Vec<PulseRec> {
    let mut src = VecSource::from_blocks(blocks);
    m.command(Command::Start(RunKind::Auto));
    m.run_until_idle(&mut src, HOUR);
    assert!(m.is_idle());
    assert_eq!(m.status().alarm, None);
    m.take_pulses()
}

/// The position after all the pulses of each distinct time, with the time.
fn positions(start: [i64; 3], pulses: &[PulseRec]) -> Vec<(u64, [i64; 3])> {
    novanc::pulse_core::testkit::steps(start, pulses)
}

/// The position after each window of `w` ns (the pulses grouped by window), with the time.
fn positions_per(start: [i64; 3], pulses: &[PulseRec], w: u64) -> Vec<(u64, [i64; 3])> {
    let mut out = Vec::new();
    let mut p = start;
    let mut i = 0;
    while i < pulses.len() {
        let t = pulses[i].t_ns / w;
        while i < pulses.len() && pulses[i].t_ns / w == t {
            p[pulses[i].axis as usize] += pulses[i].dir as i64;
            i += 1;
        }
        out.push((t * w, p));
    }
    out
}

/// Distance of `p` from the line through `a` along `d`, pulses.
fn off_line(p: [i64; 3], a: [i64; 3], d: [i64; 3]) -> f64 {
    let v = [
        (p[0] - a[0]) as f64,
        (p[1] - a[1]) as f64,
        (p[2] - a[2]) as f64,
    ];
    let d = [d[0] as f64, d[1] as f64, d[2] as f64];
    let dd = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
    let k = (v[0] * d[0] + v[1] * d[1] + v[2] * d[2]) / dd;
    let w = [v[0] - k * d[0], v[1] - k * d[1], v[2] - k * d[2]];
    (w[0] * w[0] + w[1] * w[1] + w[2] * w[2]).sqrt()
}

/// How many random lines: `NOVANC_EP_LINES` (default 48). The long run:
/// `NOVANC_EP_LINES=5000 cargo test --release --test ep_interp random_lines -- --nocapture`.
fn line_count() -> usize {
    std::env::var("NOVANC_EP_LINES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(48)
}

/// Random lines on 1, 2 or 3 axes in every direction: every point within 1 pulse of the
/// line, every axis within 1 pulse of the point on the line where the largest error stands
/// (the axis errors stay in the programmed ratio: each axis's rate is f_a · E_axis / (E_m + L)),
/// pulse totals equal to the amounts and the counters, every pulse toward the end, none after
/// it, the end exact.
#[test]
fn random_lines_in_every_direction_stay_on_the_path_and_end_exactly() {
    let mut rng = Rng::new(12);
    let mut worst: f64 = 0.0;
    let mut worst_ratio: f64 = 0.0;
    let mut worst_slow: f64 = 0.0;
    let mut worst2: f64 = 0.0;
    for case in 0..line_count() {
        let n_axes = case % 3 + 1;
        let mut delta = [0i64; 3];
        let mut axes = [0usize, 1, 2];
        for k in 0..3 {
            let j = rng.range(k as i64, 2) as usize;
            axes.swap(k, j);
        }
        let big = if case % 4 == 0 { 200_000 } else { 30_000 };
        for &a in &axes[..n_axes] {
            while delta[a] == 0 {
                delta[a] = rng.range(-big, big);
            }
        }
        let feed = [300.0, 3000.0, 12_000.0][case % 3];
        // docs/pulse-core.md, "Path accuracy": the bound, every point within 1 pulse
        // of the line. Each axis against the largest error's point: its own quantisation and
        // that of the largest error, half a pulse each, and the drift of the clamp (1.11 at
        // most over 10,000 lines), so 1.5.
        let bound = 1.0;
        let ratio_bound = 1.5;
        // The default L, and servos ten and thirty times stiffer (docs/pulse-core.md, "Path
        // accuracy", gives stiffer ones).
        let l = [EP_L_DEFAULT, 3_000, 1_000][(case / 3) % 3];
        let mut m = machine(MachineSettings {
            ep_l_pulses: l,
            ..settings()
        });
        let pulses = run(&mut m, vec![linear(1, MID, delta, feed)]);
        let end = [MID[0] + delta[0], MID[1] + delta[1], MID[2] + delta[2]];
        assert_eq!(m.pos(), end, "end exact for {delta:?}");
        let mut count = [0i64; 3];
        for p in &pulses {
            count[p.axis as usize] += 1;
            assert_eq!(
                p.dir as i64,
                delta[p.axis as usize].signum(),
                "toward the end"
            );
        }
        for a in 0..3 {
            assert_eq!(count[a], delta[a].abs(), "axis {a} of {delta:?}");
            assert_eq!(m.status().pulses[a] as i64, count[a], "counter of axis {a}");
        }
        let audit = m.take_audit();
        assert_eq!(audit.len(), 1);
        assert_eq!(audit[0].pos, end);
        let pts = positions(MID, &pulses);
        assert_eq!(pts.last().map(|p| p.1), Some(end), "no pulse after the end");
        for &(_, p) in &positions_per(MID, &pulses, 2 * EP_CYCLE_NS) {
            worst2 = worst2.max(off_line(p, MID, delta));
        }
        let major = (0..3).max_by_key(|&a| (delta[a].abs(), 3 - a)).unwrap_or(0);
        for &(_, p) in &pts {
            let d = off_line(p, MID, delta);
            worst = worst.max(d);
            if feed <= 3000.0 {
                worst_slow = worst_slow.max(d);
            }
            assert!(
                d <= bound,
                "{delta:?} F{feed} L {l}: {p:?} is {d} pulses off the line"
            );
            let em = (end[major] - p[major]).abs() as f64;
            for a in 0..3 {
                let ideal = em * delta[a].abs() as f64 / delta[major].abs() as f64;
                let e = (end[a] - p[a]).abs() as f64;
                worst_ratio = worst_ratio.max((e - ideal).abs());
                assert!(
                    (e - ideal).abs() < ratio_bound,
                    "{delta:?}: axis {a} error {e} for {ideal}"
                );
            }
        }
    }
    eprintln!(
        "largest distance from the line {worst:.3} pulses ({worst_slow:.3} at F3000 and below); axis error off the ratio {worst_ratio:.3}; {worst2:.3} with the pulses of two cycles together"
    );
}

/// The axis rates, counted over windows of 200 pulses of the largest axis, stand in the ratio
/// of the remaining errors (the programmed ratio, on a line) within the quantisation: each
/// end of a window is within a pulse of the ratio, so ±2 pulses per window.
#[test]
fn axis_rates_are_in_the_ratio_of_the_remaining_errors() {
    let delta = [90_000, -37_000, 11_000];
    let mut m = machine(settings());
    let pulses = run(&mut m, vec![linear(1, MID, delta, 2000.0)]);
    let mut n = [0i64; 3];
    let mut windows = 0;
    for p in &pulses {
        n[p.axis as usize] += 1;
        if n[0] == 200 {
            for a in 1..3 {
                let want = 200.0 * delta[a].abs() as f64 / delta[0].abs() as f64;
                assert!((n[a] as f64 - want).abs() <= 2.0, "{n:?} for {want}");
            }
            n = [0; 3];
            windows += 1;
        }
    }
    assert_eq!(windows, 450);
}

/// The tail: near the end the gates open every cycle and each remaining pulse n comes after
/// (L + n) / n cycles (rate f_r · n / (n + L)), so from E1 down to E2 the time is
/// (L · (H(E1) − H(E2)) + E1 − E2) / f_r, H the harmonic numbers: for E ≪ L an exponential
/// with time constant L / f_r. The time constant is measured by least squares over every pulse
/// of the tail and compared with L / f_r; the tail is hundreds of pulses long.
#[test]
fn the_tail_decays_with_time_constant_l_over_f_r() {
    let f_r = 1e9 / EP_CYCLE_NS as f64;
    for (l, feed) in [(30_000i64, 1000.0), (8_000, 6000.0), (30_000, 12_000.0)] {
        let s = MachineSettings {
            ep_l_pulses: l,
            ..settings()
        };
        let total = 300_000i64;
        let mut m = machine(s);
        let pulses = run(&mut m, vec![linear(1, MID, [total, 0, 0], feed)]);
        // The gates open every cycle once f_r · E / (E + L) falls below the feed.
        let fp = feed / 60.0 / 0.001;
        let e_sat = (l as f64 * fp / (f_r - fp)) as i64;
        assert!(e_sat > 300, "the tail is hundreds of pulses: {e_sat}");
        let (e1, e2) = (e_sat / 2, 20i64);
        // Pulse k leaves E = total − k − 1.
        let h = |n: i64| (1..=n).map(|k| 1.0 / k as f64).sum::<f64>();
        let (mut sx, mut sy, mut sxx, mut sxy, mut n) = (0.0, 0.0, 0.0, 0.0, 0.0);
        let t1 = pulses[(total - e1 - 1) as usize].t_ns as f64 * 1e-9;
        let h1 = h(e1);
        let mut hk = h1;
        for e in (e2..e1).rev() {
            hk -= 1.0 / (e + 1) as f64;
            let t = pulses[(total - e - 1) as usize].t_ns as f64 * 1e-9 - t1;
            let x = h1 - hk;
            let y = t - (e1 - e) as f64 / f_r;
            sx += x;
            sy += y;
            sxx += x * x;
            sxy += x * y;
            n += 1.0;
        }
        let tau = (n * sxy - sx * sy) / (n * sxx - sx * sx);
        let want = l as f64 / f_r;
        // Two points only, with the plain exponential: the figure a plot would give.
        let te = |e: i64| pulses[(total - e - 1) as usize].t_ns as f64 * 1e-9;
        let raw = (te(e2) - te(e1)) / (e1 as f64 / e2 as f64).ln();
        eprintln!(
            "L {l}, F{feed}: tail from {e_sat} pulses; time constant {:.3} ms (least squares), {:.3} ms (two points, plain exponential), L/f_r {:.3} ms",
            tau * 1e3,
            raw * 1e3,
            want * 1e3
        );
        assert!((tau / want - 1.0).abs() < 0.01, "{tau} vs {want}");
        assert!((raw / want - 1.0).abs() < 0.05, "{raw} vs {want}");
    }
}

/// Away from the end the regulator holds the path speed at the feed (Equation II's
/// approximation of the vector: exact on one axis, within 8 % on two or three).
#[test]
fn the_regulator_holds_the_feed_away_from_the_end() {
    for (delta, feed, ovr) in [
        ([300_000i64, 0, 0], 2000.0, 100u32),
        ([300_000, 0, 0], 2000.0, 50),
        ([0, 300_000, 300_000], 3000.0, 100),
        ([-300_000, 120_000, 0], 1500.0, 100),
        ([200_000, 200_000, -200_000], 6000.0, 100),
        ([0, 0, -300_000], 12_000.0, 100),
    ] {
        let mut m = machine(settings());
        m.command(Command::Override(ovr));
        let pulses = run(&mut m, vec![linear(1, MID, delta, feed)]);
        let pts = positions(MID, &pulses);
        let n = pts.len();
        let (a, b) = (pts[n / 10], pts[n / 2]);
        let len = |p: [i64; 3]| {
            (((p[0] - MID[0]).pow(2) + (p[1] - MID[1]).pow(2) + (p[2] - MID[2]).pow(2)) as f64)
                .sqrt()
        };
        let v = (len(b.1) - len(a.1)) * 0.001 / ((b.0 - a.0) as f64 * 1e-9) * 60.0;
        let want = feed * ovr as f64 / 100.0;
        // Equation II: 2.5 V = 2.5 G + M + 0.75 S, the counter's estimate of the path length.
        let mut e: Vec<f64> = delta.iter().map(|d| d.abs() as f64).collect();
        e.sort_by(|x, y| y.total_cmp(x));
        let approx = e[0] + 0.4 * e[1] + 0.3 * e[2];
        let exact = (e[0] * e[0] + e[1] * e[1] + e[2] * e[2]).sqrt();
        let expect = want * exact / approx;
        eprintln!("{delta:?} F{feed} {ovr}%: {v:.1} mm/min, Equation II gives {expect:.1}");
        assert!((v / expect - 1.0).abs() < 0.01, "{v} vs {expect}");
        assert!((v / want - 1.0).abs() < 0.08, "{v} vs {want}");
    }
}

/// A feed hold freezes the gates mid-block; START resumes with no pulse lost or added; the
/// machine time of the run grows by the time held.
#[test]
fn a_feed_hold_freezes_the_gates_and_resume_loses_no_pulse() {
    let delta = [120_000, -50_000, 7_000];
    let mut m = machine(settings());
    let mut src = VecSource::from_blocks(vec![linear(1, MID, delta, 3000.0)]);
    m.command(Command::Start(RunKind::Auto));
    m.advance_to(1_000_000_000, &mut src);
    m.command(Command::Stop);
    m.run_until_idle(&mut src, HOUR);
    let held = m.pos();
    assert!(m.status().hold && !m.status().moving);
    assert!(held != MID && held != [MID[0] + delta[0], MID[1] + delta[1], MID[2] + delta[2]]);
    let before = m.take_pulses();
    let t_hold = m.now();
    m.advance_to(t_hold + 2_000_000_000, &mut src);
    assert_eq!(m.pos(), held, "nothing moves in the hold");
    m.command(Command::Start(RunKind::Auto));
    m.run_until_idle(&mut src, HOUR);
    let after = m.take_pulses();
    assert!(after
        .first()
        .is_some_and(|p| p.t_ns >= t_hold + 2_000_000_000));
    let mut n = [0i64; 3];
    for p in before.iter().chain(&after) {
        n[p.axis as usize] += p.dir as i64;
    }
    assert_eq!(n, delta);
    assert_eq!(
        m.pos(),
        [MID[0] + delta[0], MID[1] + delta[1], MID[2] + delta[2]]
    );
    // The path never left the line, hold or not.
    let mut all = before;
    all.extend(after);
    for (_, p) in positions(MID, &all) {
        assert!(off_line(p, MID, delta) <= 1.0);
    }
}

/// E-STOP: no pulse at or after it; the run abandoned.
#[test]
fn an_emergency_stop_ends_the_pulses_at_once() {
    let mut m = machine(settings());
    let mut src = VecSource::from_blocks(vec![linear(1, MID, [200_000, 90_000, 0], 6000.0)]);
    m.command(Command::Start(RunKind::Auto));
    m.advance_to(700_000_000, &mut src);
    let t = m.now();
    m.command(Command::EStop);
    m.advance_to(t + 1_000_000_000, &mut src);
    let p = m.take_pulses();
    assert!(p.iter().all(|r| r.t_ns < t));
    assert!(m.status().estop);
}

/// SINGLE BLOCK: each START runs one block, which ends on its point; rapids go by the
/// interpolator too, and ticks or whole blocks give the same pulses at the same times.
#[test]
fn single_blocks_rapids_and_ticks_give_the_same_pulses() {
    let a = [MID[0] + 40_000, MID[1] - 30_000, MID[2]];
    let mut rapid = linear(2, a, [-10_000, 0, 25_000], 0.0);
    rapid.motion = novanc::block::Motion::Rapid;
    let blocks = vec![linear(1, MID, [40_000, -30_000, 0], 2500.0), rapid];
    let whole = {
        let mut m = machine(settings());
        run(&mut m, blocks.clone())
    };
    let mut m = machine(settings());
    m.command(Command::SingleBlock(true));
    let mut src = VecSource::from_blocks(blocks);
    let mut ticks = Vec::new();
    for k in 0..2 {
        m.command(Command::Start(RunKind::Auto));
        let mut n = 0;
        while !m.is_idle() || n == 0 {
            m.tick(&mut src);
            n += 1;
            assert!(n < 100_000);
        }
        ticks.extend(m.take_pulses());
        let want = if k == 0 {
            a
        } else {
            [a[0] - 10_000, a[1], a[2] + 25_000]
        };
        assert_eq!(m.pos(), want, "block {k} ends on its point");
    }
    assert_eq!(ticks.len(), whole.len());
    // Single block waits between the blocks, so compare each block's pulses from its start.
    let split = whole.iter().position(|p| p.axis == 2).unwrap_or(0);
    let split_t = ticks.iter().position(|p| p.axis == 2).unwrap_or(0);
    assert_eq!(split, split_t);
    assert_eq!(whole[..split], ticks[..split]);
    let off = ticks[split].t_ns - whole[split].t_ns;
    assert!(whole[split..]
        .iter()
        .zip(&ticks[split..])
        .all(|(w, t)| t.t_ns - w.t_ns == off && t.axis == w.axis && t.dir == w.dir));
}

/// `/nc/position` carries the commanded path speed: the feed while the regulator governs, then
/// f_r · |E| / (E_m + L) in the tail, 0 at the block's end (docs/recording.md).
#[test]
fn the_recorded_position_carries_the_commanded_speed() {
    use novanc::record::{Event, EventSink};
    let (tx, rx) = std::sync::mpsc::sync_channel::<Event>(1 << 20);
    let mut m = Machine::new(settings());
    assert!(m.set_position(MID));
    m.set_recording(Some(EventSink::new(tx)), false);
    let total = 100_000i64;
    let mut src = VecSource::from_blocks(vec![linear(1, MID, [total, 0, 0], 1200.0)]);
    m.command(Command::Start(RunKind::Auto));
    m.run_until_idle(&mut src, HOUR);
    drop(m);
    let pos: Vec<(i64, f64)> = rx
        .try_iter()
        .filter_map(|e| match e {
            Event::Position {
                pulses,
                speed_mm_min,
                ..
            } => Some((MID[0] + total - pulses[0], speed_mm_min)),
            _ => None,
        })
        .collect();
    assert!(pos.len() > 100);
    let (l, f_r) = (30_000.0, 1e9 / EP_CYCLE_NS as f64);
    let (mut cruise, mut tail) = (0, 0);
    for &(e, v) in &pos[..pos.len() - 1] {
        let sat = f_r * e as f64 / (e as f64 + l) * 60.0 * 0.001;
        let want = sat.min(1200.0);
        assert!(
            (v - want).abs() < 1e-6 * want.max(1.0),
            "E {e}: {v} vs {want}"
        );
        if sat > 1200.0 {
            cruise += 1;
        } else if e > 0 {
            tail += 1;
        }
    }
    assert!(cruise > 100 && tail > 10, "{cruise} {tail}");
    assert_eq!(pos.last().map(|p| p.1), Some(0.0));
}

/// Path speed against time for one block, from the pulse times, in bins of `bin` ns.
fn profile(s: MachineSettings, delta: [i64; 3], feed: f64, bin: u64) -> Vec<f64> {
    let mut m = machine(s);
    let pulses = run(&mut m, vec![linear(1, MID, delta, feed)]);
    let end = pulses.last().map_or(0, |p| p.t_ns);
    let mut out = Vec::new();
    let (mut p, mut k) = ([0i64; 3], 0);
    let mut last = [0i64; 3];
    let mut t = bin;
    while t <= end + bin {
        while k < pulses.len() && pulses[k].t_ns < t {
            p[pulses[k].axis as usize] += pulses[k].dir as i64;
            k += 1;
        }
        let d: f64 = (0..3)
            .map(|a| ((p[a] - last[a]) as f64).powi(2))
            .sum::<f64>()
            .sqrt();
        out.push(d * 0.001 / (bin as f64 * 1e-9) * 60.0);
        last = p;
        t += bin;
    }
    out
}

/// The figure of docs/pulse-core.md: the same block by both interpolators, path speed
/// against time. `cargo test --test ep_interp -- --ignored --nocapture figure`
#[test]
#[ignore]
fn figure_dda_against_error_proportional() {
    let (delta, feed, bin) = ([20_000i64, 8_000, 0], 3000.0, 10_000_000u64);
    let dda = profile(MachineSettings::default(), delta, feed, bin);
    let ep = profile(settings(), delta, feed, bin);
    let cols = dda.len().max(ep.len());
    let rows = 12;
    let top = 3300.0;
    println!("N1 G01 X20. Y8. F3000 from rest: path speed (mm/min) against time, 10 ms a column");
    for (name, v) in [
        ("DDA (KT ramps, 1000 mm/s²)", &dda),
        ("error-proportional (L 30000, f_r 500 kHz)", &ep),
    ] {
        println!("{name}:");
        for r in (0..rows).rev() {
            let lo = top * r as f64 / rows as f64;
            let label = if r % 3 == 0 {
                format!("{:>5.0}", lo)
            } else {
                "     ".into()
            };
            let line: String = (0..cols)
                .map(|c| match v.get(c) {
                    Some(&x) if x > lo => '#',
                    _ => ' ',
                })
                .collect();
            println!("{label} |{}", line.trim_end());
        }
        println!("      +{}", "-".repeat(cols));
        let ticks: String = (0..cols)
            .map(|c| if c % 20 == 0 { '|' } else { ' ' })
            .collect();
        println!("       {}", ticks.trim_end());
        let labels: String = (0..cols)
            .step_by(20)
            .map(|c| format!("{:<20}", format!("{:.1} s", c as f64 * bin as f64 * 1e-9)))
            .collect();
        println!("       {}", labels.trim_end());
    }
}

/// Real time: the error-proportional interpolator paced to the wall clock ends on the point
/// (the line's time at the feed plus its tail), and an E-STOP stops the pulses at once with
/// every recorded pulse counted (the step queue's rollback replays the registers exactly).
#[test]
fn real_time_runs_and_stops_the_error_proportional_interpolator() {
    use novanc::block::Statement;
    use novanc::pulse_core::{ClockMode, MakeRun, PulseCore};
    use novanc::record::{Event, EventSink};
    use std::time::{Duration, Instant};
    fn once(stmt: Statement) -> Option<MakeRun> {
        Some(Box::new(move |_| Box::new(std::iter::once(Ok(stmt)))))
    }
    let stmt = |d: [i64; 3], f: f64| Statement {
        line: 1,
        text: "line".into(),
        blocks: vec![linear(1, MID, d, f)],
    };
    let core = PulseCore::spawn(settings(), ClockMode::RealTime, None);
    core.set_position(MID);
    let t0 = Instant::now();
    // 10 mm at F3000: 0.2 s at the feed, then the tail (about 0.3 s).
    core.start(RunKind::Auto, once(stmt([10_000, 4_000, 0], 3000.0)));
    let st = core.wait_idle(Duration::from_secs(20)).expect("idle");
    let wall = t0.elapsed().as_secs_f64();
    assert_eq!(st.pos, [MID[0] + 10_000, MID[1] + 4_000, MID[2]]);
    assert!(wall > 0.4 && wall < 3.0, "{wall}");
    drop(core);

    let (tx, rx) = std::sync::mpsc::sync_channel(1 << 20);
    let core = PulseCore::spawn(settings(), ClockMode::RealTime, Some(EventSink::new(tx)));
    core.set_position(MID);
    core.start(RunKind::Auto, once(stmt([100_000, 0, 0], 6000.0)));
    std::thread::sleep(Duration::from_millis(300));
    core.command(Command::EStop);
    let st = core.wait_idle(Duration::from_secs(20)).expect("idle");
    assert!(st.estop && st.pos[0] > MID[0] && st.pos[0] < MID[0] + 100_000);
    std::thread::sleep(Duration::from_millis(50));
    assert_eq!(core.status().pos, st.pos, "nothing moves after the e-stop");
    drop(core);
    let evs: Vec<Event> = rx.try_iter().collect();
    let stop_t = evs
        .iter()
        .filter_map(|e| match e {
            Event::Position { t_ns, .. } => Some(*t_ns),
            _ => None,
        })
        .max()
        .unwrap_or(0);
    let pulses: Vec<u64> = evs
        .iter()
        .filter_map(|e| match e {
            Event::Pulses { t_ns, .. } => Some(t_ns.clone()),
            _ => None,
        })
        .flatten()
        .collect();
    assert!(
        pulses.iter().all(|&t| t < stop_t),
        "no pulse after the e-stop"
    );
    assert_eq!(
        pulses.len() as i64,
        st.pos[0] - MID[0],
        "recorded = counted"
    );
}
