//! The rapid and spindle overrides and the DRY RUN, MACHINE LOCK and Z NEGLECT switches
//! (issue 23; docs/pulse-core.md, "Overrides and switches"), each driven by its script word
//! through `novanc script` and checked in the recording: the pulse times (the speeds), the
//! positions, the pulse counters and `/nc/state`. And what `novanc run` records: its modes, and
//! `--pulses off`.

mod common;

use std::path::{Path, PathBuf};

/// What a recording holds, by topic: JSON texts in log order, and every pulse (axis, time).
struct Rec {
    positions: Vec<String>,
    states: Vec<String>,
    pulses: Vec<(char, u64)>,
    pulse_messages: usize,
}

fn read(path: &Path) -> Rec {
    let bytes = std::fs::read(path).unwrap();
    let mut r = Rec {
        positions: Vec::new(),
        states: Vec::new(),
        pulses: Vec::new(),
        pulse_messages: 0,
    };
    for m in mcap::MessageStream::new(&bytes).unwrap() {
        let m = m.unwrap();
        let text = String::from_utf8(m.data.to_vec()).unwrap();
        match m.channel.topic.as_str() {
            "/nc/position" => r.positions.push(text),
            "/nc/state" => r.states.push(text),
            "/nc/pulses" => {
                r.pulse_messages += 1;
                let axis = text
                    .split("\"axis\":\"")
                    .nth(1)
                    .unwrap()
                    .chars()
                    .next()
                    .unwrap();
                let list = text.split("\"t_ns\":[").nth(1).unwrap();
                let list = list.split(']').next().unwrap();
                r.pulses.extend(
                    list.split(',')
                        .filter(|s| !s.is_empty())
                        .map(|t| (axis, t.parse::<u64>().unwrap())),
                );
            }
            _ => {}
        }
    }
    r.pulses.sort_by_key(|p| p.1);
    r
}

/// A number field of a JSON text.
fn num(json: &str, key: &str) -> f64 {
    let v = json
        .split(&format!("\"{key}\":"))
        .nth(1)
        .unwrap_or_else(|| panic!("no {key} in {json}"));
    v.split([',', '}']).next().unwrap().parse().unwrap()
}

/// The `pulses` counters of a `/nc/position` text.
fn counters(json: &str) -> [i64; 3] {
    let v = json.split("\"pulses\":[").nth(1).unwrap();
    let v: Vec<i64> = v
        .split(']')
        .next()
        .unwrap()
        .split(',')
        .map(|s| s.parse().unwrap())
        .collect();
    [v[0], v[1], v[2]]
}

/// Writes `prog` and runs `script` (`PROG` standing for the program's path) with a recording;
/// the recording and the script's output.
fn script(name: &str, prog: &str, script: &str) -> (Rec, String) {
    let dir = common::temp_dir(name);
    let p = dir.join("p.ngc");
    std::fs::write(&p, prog).unwrap();
    let (rec, text) =
        common::recorded_script(&dir, &script.replace("PROG", &p.display().to_string()));
    (read(&rec), text)
}

/// The program read in, then `before` (switch words), then AUTO START to the end.
fn run_with(before: &str) -> String {
    format!("op DATA\ndata READ\ntape PROG\nstart\nwait\n{before}\nop AUTO\nstart\nwait\nshow\n")
}

/// The fastest path speed of axis `a` alone, mm/min, from the gap between its pulses (1 µm).
fn top_speed(r: &Rec, a: char) -> f64 {
    let t: Vec<u64> = r.pulses.iter().filter(|p| p.0 == a).map(|p| p.1).collect();
    let gap = t.windows(2).map(|w| w[1] - w[0]).min().unwrap();
    0.001 / (gap as f64 * 1e-9) * 60.0
}

const RAPID_X: &str = "G21 G90\nG0 X100\nM30\n";

/// Each rapid override: the rapid reaches its percentage of the 12 000 mm/min rapid rate and
/// never more; F0 is the 400 mm/min F0 rate.
#[test]
fn rapid_override_sets_the_rapid_speed() {
    for (pct, want) in [(100, 12_000.0), (50, 6_000.0), (25, 3_000.0), (0, 400.0)] {
        let (r, out) = script(
            &format!("rapid-{pct}"),
            RAPID_X,
            &run_with(&format!("rapidoverride {pct}")),
        );
        let v = top_speed(&r, 'X');
        assert!(v <= want * 1.01, "{pct} %: {v} mm/min > {want}\n{out}");
        assert!(v >= want * 0.99, "{pct} %: {v} mm/min < {want}\n{out}");
        let last = r.states.last().unwrap();
        assert_eq!(num(last, "rapid_override"), pct as f64, "{last}");
    }
}

/// A STEP jog (1 mm at the 1000 mm/min jog feed) goes at a quarter of it under 25 %.
#[test]
fn rapid_override_acts_on_a_jog() {
    let (r, out) = script(
        "rapid-jog",
        RAPID_X,
        "rapidoverride 25\nop STEP\nwheelscale 1000\nkey Right\nwait\nshow\n",
    );
    let v = top_speed(&r, 'X');
    assert!((247.5..=252.5).contains(&v), "{v} mm/min\n{out}");
    assert_eq!(r.pulses.len(), 1000, "{out}");
}

/// The return after a manual intervention goes at the jog feed times the rapid override.
#[test]
fn rapid_override_acts_on_the_return() {
    let (r, out) = script(
        "rapid-return",
        "G21 G90\nG1 X20 F600\nM30\n",
        "op DATA\ndata READ\ntape PROG\nstart\nwait\nop AUTO\nstart\nwait ms 1000\nstop\nwait\n\
         op STEP\nwheelscale 1000\nkey Up\nwait\nrapidoverride 50\nop AUTO\nstart\nwait\nshow\n",
    );
    // The Y pulses: 1 mm out by hand at the full jog feed, then 1 mm back at half of it.
    let y: Vec<u64> = r
        .pulses
        .iter()
        .filter(|p| p.0 == 'Y')
        .map(|p| p.1)
        .collect();
    assert_eq!(y.len(), 2000, "{out}");
    let gap = |t: &[u64]| t.windows(2).map(|w| w[1] - w[0]).min().unwrap();
    let out_speed = 60.0e6 / gap(&y[..1000]) as f64;
    let back_speed = 60.0e6 / gap(&y[1000..]) as f64;
    assert!((990.0..=1010.0).contains(&out_speed), "{out_speed}\n{out}");
    assert!((495.0..=505.0).contains(&back_speed), "{back_speed}\n{out}");
}

/// The spindle turns at the programmed speed times the override, in `/nc/state`; a value off
/// the 10 % steps is refused before anything runs.
#[test]
fn spindle_override_scales_the_recorded_speed() {
    let (r, out) = script(
        "spindle-80",
        "G21 G90\nS1000 M03\nG1 X5 F500\nM05\nM30\n",
        &run_with("spindleoverride 80"),
    );
    let top = r
        .states
        .iter()
        .map(|s| num(s, "spindle"))
        .fold(0.0, f64::max);
    assert_eq!(top, 800.0, "{out}");
    assert!(r.states.iter().any(|s| num(s, "spindle_override") == 80.0));
    for bad in ["130", "45", "85", "x"] {
        let e =
            novanc::panel_model::PanelEvent::parse_script_line(&format!("spindleoverride {bad}"))
                .unwrap_err();
        assert!(e.contains("50 to 120"), "{e}");
    }
}

/// DRY RUN: G1 F100 runs at the jog feed (1000 mm/min), scaled by the feed override; the rapid
/// is unchanged.
#[test]
fn dry_run_feeds_at_the_jog_feed() {
    let prog = "G21 G90\nG1 X10 F100\nG0 Y50\nM30\n";
    let (r, out) = script("dry", prog, &run_with("dryrun on"));
    let v = top_speed(&r, 'X');
    assert!((990.0..=1010.0).contains(&v), "{v}\n{out}");
    assert!(top_speed(&r, 'Y') > 11_800.0, "{out}");
    assert!(r.states.iter().any(|s| s.contains("\"dry_run\":true")));
    let (r, out) = script("dry-50", prog, &run_with("dryrun on\noverride 50"));
    let v = top_speed(&r, 'X');
    assert!((495.0..=505.0).contains(&v), "{v}\n{out}");
    let (r, _) = script("dry-off", prog, &run_with("dryrun off"));
    let v = top_speed(&r, 'X');
    assert!((99.0..=101.0).contains(&v), "{v}");
}

const LOCKED: &str = "G21 G90\nG0 X100 Y50 Z-10\nG1 X20 F1000\nM30\n";

/// MACHINE LOCK: the program runs and `/nc/position` follows it, but no pulse is recorded and
/// the counters stay at 0; `/nc/state` says so. The next run, unlocked, starts from where the
/// axes really are (0), not from where the locked program left off (X20).
#[test]
fn machine_lock_moves_the_position_not_the_axes() {
    let (r, out) = script(
        "lock",
        LOCKED,
        &format!(
            "{}machinelock off\nstart\nwait\nshow\n",
            run_with("machinelock on")
        ),
    );
    // The first run: positions along the program, counters still.
    let first: Vec<&String> = r
        .positions
        .iter()
        .take_while(|p| counters(p) == [0, 0, 0])
        .collect();
    assert!(
        first
            .iter()
            .any(|p| num(p, "x") == 100.0 && num(p, "z") == -10.0),
        "{out}"
    );
    assert!(first.iter().any(|p| num(p, "x") == 20.0), "{out}");
    assert!(r.states.iter().any(|s| s.contains("\"machine_lock\":true")));
    // The second run moved the axes from 0: X 100 + 80, Y 50, Z 10 mm of pulses.
    let count = |a: char| r.pulses.iter().filter(|p| p.0 == a).count();
    assert_eq!(
        [count('X'), count('Y'), count('Z')],
        [180_000, 50_000, 10_000]
    );
    let last = r.positions.last().unwrap();
    assert_eq!(counters(last), [20_000, 50_000, -10_000], "{last}");
    assert_eq!(num(last, "x"), 20.0);
}

/// After a locked run, RESET brings the program position back to the axes, and an
/// incremental program then starts from the axes' position.
#[test]
fn reset_after_a_locked_run_brings_the_position_back() {
    let (r, out) = script(
        "lock-reset",
        "G21 G91\nG0 X30 Z-5\nM30\n",
        &format!(
            "{}reset\nmachinelock off\nstart\nwait\nshow\n",
            run_with("machinelock on")
        ),
    );
    let last = r.positions.last().unwrap();
    assert_eq!(counters(last), [30_000, 0, -5_000], "{last}\n{out}");
    assert_eq!(num(last, "x"), 30.0, "{out}");
}

/// Z NEGLECT: X and Y move, Z's program position moves but the Z axis does not.
#[test]
fn z_neglect_holds_z_alone() {
    let (r, out) = script("zneglect", LOCKED, &run_with("zneglect on"));
    let count = |a: char| r.pulses.iter().filter(|p| p.0 == a).count();
    assert_eq!(
        [count('X'), count('Y'), count('Z')],
        [180_000, 50_000, 0],
        "{out}"
    );
    let last = r.positions.last().unwrap();
    assert_eq!(counters(last), [20_000, 50_000, 0], "{last}");
    assert_eq!(num(last, "z"), -10.0, "{last}");
    assert!(r.states.iter().any(|s| s.contains("\"z_neglect\":true")));
}

/// MACHINE LOCK cannot change with a run loaded: the switch stays and the message says why.
#[test]
fn machine_lock_is_refused_with_a_run_loaded() {
    let (r, out) = script(
        "lock-refused",
        "G21 G90\nG1 X20 F600\nM30\n",
        "op DATA\ndata READ\ntape PROG\nstart\nwait\nop AUTO\nstart\nwait ms 500\nstop\nwait\n\
         machinelock on\nshow\nstart\nwait\n",
    );
    assert!(out.contains("MACHINE LOCK refused"), "{out}");
    assert!(r
        .states
        .iter()
        .all(|s| s.contains("\"machine_lock\":false")));
    assert_eq!(r.pulses.len(), 20_000);
}

/// Bad values of the switch words are refused with a message, before anything runs.
#[test]
fn switch_words_refuse_other_values() {
    use novanc::panel_model::PanelEvent;
    for (line, want) in [
        ("rapidoverride 75", "0 (F0), 25, 50 or 100"),
        ("rapidoverride", "takes one percentage"),
        ("dryrun yes", "takes on or off"),
        ("machinelock 1", "takes on or off"),
        ("zneglect", "takes one on or off"),
    ] {
        let e = PanelEvent::parse_script_line(line).unwrap_err();
        assert!(e.contains(want), "{line}: {e}");
    }
}

fn run_cmd(name: &str, extra: &[&str]) -> (PathBuf, Rec) {
    let dir = common::temp_dir(name);
    let p = dir.join("p.ngc");
    std::fs::write(&p, "G21 G90\nG0 X10 Y5\nG1 X0 F2000\nM30\n").unwrap();
    let rec = dir.join("r.mcap");
    let out = common::novanc_command()
        .arg("run")
        .arg(&p)
        .arg("--record")
        .arg(&rec)
        .args(extra)
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(0), "{out:?}");
    let r = read(&rec);
    (rec, r)
}

/// `novanc run` records the modes it runs in: AUTO, from memory (not SEARCH).
#[test]
fn run_records_auto_memory() {
    let (_, r) = run_cmd("run-modes", &[]);
    assert!(!r.states.is_empty());
    for s in &r.states {
        assert!(s.contains("\"op_mode\":\"AUTO\""), "{s}");
        assert!(s.contains("\"data_mode\":\"MEMORY\""), "{s}");
    }
}

/// `--pulses off` leaves `/nc/pulses` out; the positions are all there.
#[test]
fn pulses_off_leaves_the_pulses_out() {
    let (rec_on, on) = run_cmd("pulses-on", &[]);
    let (rec_off, off) = run_cmd("pulses-off", &["--pulses", "off"]);
    assert!(on.pulse_messages > 0);
    assert_eq!(off.pulse_messages, 0);
    assert_eq!(on.positions, off.positions);
    let size = |p: &Path| std::fs::metadata(p).unwrap().len();
    assert!(size(&rec_off) < size(&rec_on));
    let out = common::novanc_command()
        .args(["run", "x.ngc", "--pulses", "maybe"])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2), "{out:?}");
    assert!(String::from_utf8_lossy(&out.stderr).contains("--pulses takes on or off"));
}

/// `novanc script --pulses off` too.
#[test]
fn script_pulses_off() {
    let dir = common::temp_dir("script-pulses-off");
    let p = dir.join("p.ngc");
    std::fs::write(&p, RAPID_X).unwrap();
    let s = dir.join("s.panel");
    std::fs::write(&s, run_with("").replace("PROG", &p.display().to_string())).unwrap();
    let rec = dir.join("r.mcap");
    let out = common::novanc_command()
        .arg("script")
        .arg(&s)
        .args(["--pulses", "off", "--record"])
        .arg(&rec)
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(0), "{out:?}");
    let r = read(&rec);
    assert_eq!(r.pulse_messages, 0);
    assert_eq!(num(r.positions.last().unwrap(), "x"), 100.0);
}

/// After a locked run left the program position away from the axes, a jog starts from where
/// the axes are: the travel limit is theirs. Table: the program went to X100 while the axes
/// stayed at X0; a 1 mm STEP in X- is beyond the limit (X0) and refused, not run from X100.
#[test]
fn a_jog_after_a_locked_run_starts_from_the_axes() {
    let (r, out) = script(
        "lock-jog",
        "G21 G90\nG0 X100\nM30\n",
        &format!(
            "{}machinelock off\nop STEP\nwheelscale 1000\nkey Left\nwait\nshow\n",
            run_with("machinelock on")
        ),
    );
    assert!(r.pulses.is_empty(), "{out}");
    assert!(out.contains("would go to -1.000 mm"), "{out}");
}
