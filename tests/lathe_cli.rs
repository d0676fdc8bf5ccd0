//! The Citizen lathe from the command line (docs/lathe.md "Headless"): the 5-part run of the
//! samples, recorded and read back; a fault in channel 1 during part 3 from a panel script;
//! and the refusals of bad machines, programs and scripts.

mod common;

use common::novanc;

use novanc::lathe::desc::LatheDesc;
use novanc::store::lathe::{tools_text, LatheStore};
use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};
use std::process::Output;

/// `novanc script SCRIPT --machine citizen --state STATE` and `more` arguments.
fn citizen_script(script: &Path, state: &Path, more: &[&str]) -> Output {
    let mut args = vec![
        "script",
        script.to_str().unwrap(),
        "--machine",
        "citizen",
        "--state",
        state.to_str().unwrap(),
    ];
    args.extend_from_slice(more);
    novanc(&args)
}

/// Plays the panel script `body` on the Citizen with `dir/state` (written to `dir/play.panel`):
/// it must succeed; what it printed.
fn played(dir: &Path, body: &str) -> String {
    let script = dir.join("play.panel");
    std::fs::write(&script, body).unwrap();
    let o = citizen_script(&script, &dir.join("state"), &[]);
    let so = text(&o.stdout);
    assert!(o.status.success(), "{so}{}", text(&o.stderr));
    so
}

fn text(b: &[u8]) -> String {
    String::from_utf8_lossy(b).into_owned()
}

/// One message of a lathe recording: topic, log time, JSON text.
struct Msg {
    topic: String,
    t: u64,
    json: String,
}

fn read(path: &Path) -> Vec<Msg> {
    let bytes = std::fs::read(path).expect("the recording exists");
    let mut out = Vec::new();
    for m in mcap::MessageStream::new(&bytes).expect("an MCAP file") {
        let m = m.expect("every message reads");
        out.push(Msg {
            topic: m.channel.topic.clone(),
            t: m.log_time,
            json: String::from_utf8(m.data.to_vec()).expect("JSON text"),
        });
    }
    out
}

/// The value of a JSON integer field `"key":N` (the recorder writes flat objects).
fn int(json: &str, key: &str) -> Option<i64> {
    let at = json.find(&format!("\"{key}\":"))? + key.len() + 3;
    let rest = &json[at..];
    let end = rest.find([',', '}']).unwrap_or(rest.len());
    rest[..end].parse().ok()
}

fn string<'a>(json: &'a str, key: &str) -> Option<&'a str> {
    let at = json.find(&format!("\"{key}\":\""))? + key.len() + 4;
    let rest = &json[at..];
    Some(&rest[..rest.find('"')?])
}

/// What a recording says of the run: parts per channel, transfers, cuts per (channel, work),
/// thread pass indexes.
#[derive(Default, Debug)]
struct Audit {
    parts: BTreeMap<i64, i64>,
    transfers: Vec<String>,
    cuts: BTreeMap<(i64, i64), u32>,
    cuts_without_work: u32,
    thread_indexes: BTreeSet<i64>,
    faults: Vec<String>,
    alarms: Vec<String>,
    last_t: u64,
}

fn audit(msgs: &[Msg]) -> Audit {
    let mut a = Audit::default();
    for m in msgs {
        a.last_t = a.last_t.max(m.t);
        if m.topic != "/lathe/event" {
            continue;
        }
        let ch = int(&m.json, "channel").expect("a channel");
        match string(&m.json, "event") {
            Some("part") => {
                a.parts.insert(ch, int(&m.json, "value").unwrap());
            }
            Some("transfer") => a
                .transfers
                .push(string(&m.json, "text").unwrap().to_string()),
            Some("cut") => match int(&m.json, "work") {
                Some(w) => *a.cuts.entry((ch, w)).or_default() += 1,
                None => a.cuts_without_work += 1,
            },
            Some("thread") => {
                a.thread_indexes
                    .insert(int(&m.json, "value").unwrap() % 1024);
            }
            Some("fault") => a.faults.push(m.json.clone()),
            Some("alarm") => a.alarms.push(m.json.clone()),
            _ => {}
        }
    }
    a
}

/// Every channel machined every work the same number of blocks (none twice, none skipped).
fn each_work_machined_once(a: &Audit) {
    for ch in 1..=3 {
        let per_work: Vec<u32> = (1..=5)
            .map(|w| a.cuts.get(&(ch, w)).copied().unwrap_or(0))
            .collect();
        assert!(per_work[0] > 0, "CH{ch} cut nothing: {:?}", a.cuts);
        assert!(
            per_work.iter().all(|&n| n == per_work[0]),
            "CH{ch} cut blocks per work {per_work:?}"
        );
    }
}

#[test]
fn the_samples_make_five_parts_with_every_transfer_interlocked() {
    let out = common::temp_dir("lathe-run").join("run.mcap");
    let o = novanc(&[
        "run",
        "--machine",
        "citizen",
        "programs/citizen",
        "--record",
        out.to_str().unwrap(),
    ]);
    let so = text(&o.stdout);
    assert!(o.status.success(), "{so}\n{}", text(&o.stderr));
    assert!(so.contains("parts: 5\n"), "{so}");
    let secs: f64 = so
        .lines()
        .find_map(|l| l.strip_prefix("machine time: "))
        .and_then(|s| s.trim_end_matches(" s").parse().ok())
        .expect("the machine time is printed");
    for ch in 1..=3 {
        assert!(so.contains(&format!("CH{ch} SYSTEM-{ch}: blocks ")), "{so}");
    }
    // The recording's end, as the centre's run says it (one function since stop 50).
    assert!(so.contains("\nrecording complete: yes\nrecording "), "{so}");
    let a = audit(&read(&out));
    assert_eq!(a.parts, BTreeMap::from([(1, 5), (2, 5), (3, 5)]));
    // 1→2 and 2→3 for each work, and 3 to the unloader: 15 handovers, every one with both
    // chucks closed on the work (the unloader's catcher counts as closed).
    assert_eq!(a.transfers.len(), 15, "{:?}", a.transfers);
    assert!(
        a.transfers
            .iter()
            .all(|t| t.ends_with("(both chucks closed)")),
        "{:?}",
        a.transfers
    );
    assert_eq!(
        a.cuts_without_work, 0,
        "a machining block started on an empty spindle"
    );
    assert!(a.alarms.is_empty(), "{:?}", a.alarms);
    assert_eq!(
        a.thread_indexes,
        BTreeSet::from([0]),
        "every thread pass on the encoder index"
    );
    each_work_machined_once(&a);
    // The recording's last message is at the end of the machine time printed (the last part
    // done), or just after it: the spindles coast down, sampled every 10 ms, until the run
    // sees every channel at rest (within 0.1 s: the kernel looks every 1,000 ticks).
    let last = a.last_t as f64 * 1e-9;
    assert!(
        last > secs - 0.01 && last < secs + 0.11,
        "{} vs {secs}",
        a.last_t
    );
}

/// Runs a Citizen panel script with a recording in a fresh directory `tag`: the directory,
/// the recording's path and the script's stdout (the run must succeed).
fn recorded_script(tag: &str, script_text: &str) -> (PathBuf, PathBuf, String) {
    let dir = common::temp_dir(tag);
    let script = dir.join("s.panel");
    let rec = dir.join("r.mcap");
    std::fs::write(&script, script_text).unwrap();
    let o = citizen_script(
        &script,
        &dir.join("state"),
        &["--record", rec.to_str().unwrap()],
    );
    let so = text(&o.stdout);
    assert!(o.status.success(), "{so}\n{}", text(&o.stderr));
    (dir, rec, so)
}

#[test]
fn a_fault_in_channel_1_during_part_3_stops_only_what_needs_it() {
    // Work 3 reaches spindle 1 about 14.6 s into the run and leaves it about 24.5 s in.
    let (dir, rec, so) = recorded_script(
        "lathe-fault",
        "start\nwait ms 20000\nfault 1 tool breakage\nshow\nwait\nshow\nreset\nstart\nwait\nshow\n",
    );
    let frames: Vec<&str> = so.split("--- display\n").skip(1).collect();
    assert_eq!(frames.len(), 3, "{so}");
    // At the fault: channel 1 holds work 3.
    assert!(
        frames[0].contains(">CH1 FAULT tool breakage"),
        "{}",
        frames[0]
    );
    assert!(
        frames[0].contains(" W3 CHUCK CLOSED FAULT"),
        "{}",
        frames[0]
    );
    // The others finished the works they held, then wait at their queue points, and say on
    // whom.
    assert!(frames[1].contains(" CH2 WAIT  waits CH1"), "{}", frames[1]);
    assert!(frames[1].contains(" CH3 WAIT  waits CH2"), "{}", frames[1]);
    assert!(frames[1].contains("parts 2/5"), "{}", frames[1]);
    // RESET and START: the run ends with 5 parts, none machined twice.
    assert!(frames[2].contains("PARTS 5/5"), "{}", frames[2]);
    let a = audit(&read(&rec));
    assert_eq!(a.parts, BTreeMap::from([(1, 5), (2, 5), (3, 5)]));
    assert_eq!(a.faults.len(), 1, "{:?}", a.faults);
    assert_eq!(a.cuts_without_work, 0);
    each_work_machined_once(&a);
    // The part counter is in the stores.
    let o = LatheStore::open(&dir.join("state"), &LatheDesc::citizen()).unwrap();
    assert_eq!(
        (o.counter.target, &o.counter.counts[..]),
        (5, &[5, 5, 5][..])
    );
}

#[test]
fn estop_abandons_every_channels_run_and_reset_returns_them_to_their_program_start() {
    // At 20 s CH1 cuts work 3 (line 0018), CH2 work 2 (0018), CH3 threads work 1 (0012).
    let (_, rec, so) = recorded_script(
        "lathe-estop",
        "start\nwait ms 20000\nestop\nreset\nshow\nstart\nwait ms 500\nshow\nwait\nshow\n",
    );
    let frames: Vec<&str> = so.split("--- display\n").skip(1).collect();
    assert_eq!(frames.len(), 3, "{so}");
    // After RESET: every channel stopped at the start of its program, spindle stopped, the
    // work still in the chuck.
    assert!(frames[0].contains(">0006 G0 X40 Z10"), "{}", frames[0]);
    assert!(frames[0].contains(" S     0"), "{}", frames[0]);
    assert!(frames[0].contains("W3 CHUCK CLOSED IDLE"), "{}", frames[0]);
    for ch in 1..=3 {
        // The run is abandoned: each channel stands at its program's start, not running.
        assert!(
            frames[0].contains(&format!("CH{ch} IDLE  ")),
            "{}",
            frames[0]
        );
    }
    // START begins a new cycle: no interrupted block is resumed.
    assert!(!frames[1].contains("0018 X18 Z-16"), "{}", frames[1]);
    assert!(!frames[1].contains("0018 G2 X16"), "{}", frames[1]);
    assert!(
        frames[1].contains(">CH1 RUN   0012 G1 X-1"),
        "{}",
        frames[1]
    );
    // The run still ends with 5 parts, every work cut by every channel.
    assert!(frames[2].contains("PARTS 5/5"), "{}", frames[2]);
    let a = audit(&read(&rec));
    assert_eq!(a.parts, BTreeMap::from([(1, 5), (2, 5), (3, 5)]));
    assert_eq!(a.cuts_without_work, 0);
    for ch in 1..=3 {
        for w in 1..=5 {
            assert!(a.cuts.contains_key(&(ch, w)), "CH{ch} W{w}: {:?}", a.cuts);
        }
    }
}

#[test]
fn wait_block_stops_with_the_tick_the_selected_channels_block_starts() {
    // `wait block 12` on channel 2: the 12th block of system2.ngc as read (its N number in
    // the recording's `/nc/block`, as the centre's listing numbers its blocks).
    let (dir, rec, so) = recorded_script(
        "lathe-wait-block",
        "channel 2\nstart\nwait block 12\nshow\nchannel 2\nwait block 9999\nshow\n",
    );
    let frames: Vec<&str> = so.split("--- display\n").skip(1).collect();
    assert_eq!(frames.len(), 2, "{so}");
    let msgs = read(&rec);
    let starts: Vec<&Msg> = msgs
        .iter()
        .filter(|m| {
            m.topic == "/nc/block"
                && int(&m.json, "channel") == Some(2)
                && int(&m.json, "seq") == Some(12)
        })
        .collect();
    assert_eq!(starts.len(), 5, "once per part");
    let (tb, line) = (starts[0].t, int(&starts[0].json, "stmt").unwrap());
    let program = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("programs/citizen/system2.ngc"),
    )
    .unwrap();
    let source = program.lines().nth(line as usize - 1).unwrap().to_string();
    // The first frame: CH2 executes that block, selected.
    assert!(
        frames[0].contains(&format!(">CH2 RUN   {line:04} {source}")),
        "{}",
        frames[0]
    );
    // Exactly at the end of the NCBR tick it started in (the Citizen's 100 µs): the panel
    // event after the wait is recorded then.
    let after: Vec<u64> = msgs
        .iter()
        .filter(|m| m.topic == "/panel/event" && m.json.contains("channel 2"))
        .map(|m| m.t)
        .collect();
    assert_eq!(after.len(), 2, "{after:?}");
    assert_eq!(after[1], tb + 100_000, "block 12 of CH2 started at {tb}");
    // A block the program never reaches: the wait ends when every channel is at rest.
    assert!(frames[1].contains("PARTS 5/5"), "{}", frames[1]);
    assert!(frames[1].contains(">CH2 DONE"), "{}", frames[1]);

    // A block number the lathe has not is refused at its line, before anything runs.
    for (bad, why) in [
        (
            "wait block 0",
            "wait block 0: the lathe's blocks are numbered from 1",
        ),
        ("wait block x", "wait block: 'x' is not a block number"),
    ] {
        let s = dir.join("bad.panel");
        std::fs::write(&s, format!("start\n{bad}\nshow\n")).unwrap();
        let o = citizen_script(&s, &dir.join("st"), &[]);
        assert_eq!(o.status.code(), Some(1));
        assert!(text(&o.stdout).is_empty(), "{}", text(&o.stdout));
        assert!(
            text(&o.stderr).contains(&format!("bad.panel:2: {why}")),
            "{}",
            text(&o.stderr)
        );
    }
}

#[test]
fn bad_machines_programs_and_scripts_are_refused_whole() {
    let dir = common::temp_dir("lathe-bad");
    let o = novanc(&["run", "--machine", "nowhere", "programs/citizen"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        text(&o.stderr).contains("a machine is 'citizen', 'centre' or a description file"),
        "{}",
        text(&o.stderr)
    );

    let m = dir.join("bad.machine");
    std::fs::write(&m, "machine x\nkind lathe\nchannel A\ntool 1 radius -2\n").unwrap();
    let o = novanc(&["run", "--machine", m.to_str().unwrap(), "programs/citizen"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        text(&o.stderr).contains("bad.machine:4: radius -2"),
        "{}",
        text(&o.stderr)
    );

    // Two programs for three channels.
    let two = dir.join("two");
    std::fs::create_dir_all(&two).unwrap();
    for n in ["a.ngc", "b.ngc"] {
        std::fs::write(two.join(n), "G0 X10\nM2\n").unwrap();
    }
    let o = novanc(&["run", "--machine", "citizen", two.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        text(&o.stderr).contains("2 programs (.ngc, .nc, .iso) for 3 channels"),
        "{}",
        text(&o.stderr)
    );

    // A program error names the file, line and column; nothing runs and nothing is recorded.
    let progs = dir.join("progs");
    std::fs::create_dir_all(&progs).unwrap();
    for (i, p) in ["system1.ngc", "system2.ngc", "system3.ngc"]
        .iter()
        .enumerate()
    {
        let mut t = std::fs::read_to_string(PathBuf::from("programs/citizen").join(p)).unwrap();
        if i == 1 {
            t = t.replace("G1 Z-4 F0.1", "G1 Z-4 F0.1 Q");
        }
        std::fs::write(progs.join(p), t).unwrap();
    }
    let rec = dir.join("none.mcap");
    let o = novanc(&[
        "run",
        "--machine",
        "citizen",
        progs.to_str().unwrap(),
        "--record",
        rec.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(1), "{}", text(&o.stdout));
    let e = text(&o.stderr);
    assert!(e.contains("system2.ngc:17:"), "{e}");
    assert!(
        text(&o.stdout).is_empty(),
        "nothing ran: {}",
        text(&o.stdout)
    );
    assert!(
        read(&rec).iter().all(|m| m.topic != "/nc/position"),
        "nothing moved"
    );

    // A bad script line stops the script before anything runs.
    let s = dir.join("bad.panel");
    std::fs::write(&s, "start\nfault 7 smoke\n").unwrap();
    let o = citizen_script(&s, &dir.join("st"), &[]);
    assert_eq!(o.status.code(), Some(1));
    assert!(
        text(&o.stderr).contains("bad.panel:2: '7' is not a channel (1 to 3)"),
        "{}",
        text(&o.stderr)
    );
    assert!(!dir.join("st/lathe-citizen").exists(), "nothing was opened");

    let o = novanc(&[
        "run",
        "--machine",
        "citizen",
        "programs/citizen",
        "--parts",
        "0",
    ]);
    assert_eq!(o.status.code(), Some(2));
}

/// One console entry (`novanc [--machine M] [--window] ...`): the console's arguments are
/// parsed once, whatever the machine and the front end, so a bad one is the same usage error
/// (exit 2), in the same words, before anything opens. (They were parsed twice: the window
/// called a stray argument an "unknown option", the terminal an "unexpected argument".)
#[test]
fn the_console_takes_the_same_arguments_on_every_machine_and_front_end() {
    let dir = common::temp_dir("lathe-console-args");
    let state = dir.join("state");
    let fronts: &[&[&str]] = if cfg!(feature = "window") {
        &[&[], &["--window"]]
    } else {
        &[&[]]
    };
    for machine in [&[][..], &["--machine", "citizen"], &["--machine", "centre"]] {
        for front in fronts {
            for (bad, said) in [
                (&["--rows", "1"][..], "--rows 1 is outside"),
                (&["--bogus"], "unexpected argument '--bogus'"),
                (
                    &["--mtconnect-wait", "1"],
                    "--mtconnect-wait needs --mtconnect",
                ),
            ] {
                let mut args: Vec<&str> = machine.to_vec();
                args.extend_from_slice(front);
                args.extend_from_slice(&["--state", state.to_str().unwrap()]);
                args.extend_from_slice(bad);
                // No display: a window that got as far as opening would fail (exit 1).
                let o = common::novanc_command()
                    .args(&args)
                    .env_remove("DISPLAY")
                    .env_remove("WAYLAND_DISPLAY")
                    .stdin(std::process::Stdio::null())
                    .output()
                    .expect("novanc runs");
                let e = text(&o.stderr);
                assert_eq!(o.status.code(), Some(2), "{args:?}: {e}");
                assert!(e.contains(said), "{args:?}: {e}");
            }
        }
    }
    assert!(!state.exists(), "nothing was opened");
    let _ = std::fs::remove_dir_all(&dir);
}

/// A program that opens a chuck on a turning spindle stops at that block with an alarm that
/// says why (the chuck interlock on the spindle), nothing delivered; the channel's summary and
/// its listing stand at the block that stopped it, not at the program's start, until RESET.
#[test]
fn a_chuck_opened_on_a_turning_spindle_stops_the_channel_at_that_block() {
    let dir = common::temp_dir("lathe-chuck-spindle");
    let script = dir.join("m3.script");
    // CH3's M5 before its delivery (line 14) becomes M3: M11 (line 16) opens on 1200 rpm.
    std::fs::write(
        &script,
        "channel 3\nop DATA\ntype SX40 Z10\nkey Enter\ntype CM5$M3\nkey Enter\n\
         op AUTO\ntarget 1\nstart\nwait\nshow\nreset\nshow\n",
    )
    .unwrap();
    let o = citizen_script(&script, &dir.join("state"), &[]);
    let out = text(&o.stdout);
    assert!(o.status.success(), "{out}\n{}", text(&o.stderr));
    let shows: Vec<&str> = out.split("--- display").skip(1).collect();
    assert_eq!(shows.len(), 2, "{out}");
    let alarm = shows[0].replace('\n', " ");
    assert!(
        alarm.contains("CH3 ALARM line 16:")
            && alarm.contains("M11: the spindle of CH3 turns (1200 rpm M3)")
            && alarm.contains("T02 W1 CHUCK CLOSED ALARM"),
        "{}",
        shows[0]
    );
    assert!(shows[0].contains("\n>0016 M11\n"), "{}", shows[0]);
    // RESET: the channel back at its program's start.
    assert!(shows[1].contains("\n>0005 G0 X40 Z10\n"), "{}", shows[1]);
    let _ = std::fs::remove_dir_all(&dir);
}

/// `novanc run` is one command: the options of a run (override, real time, the pulses in a
/// recording, the two switches) act on a lathe as on the centre, and an option only one
/// machine has is refused on the other with the reason, before anything runs.
#[test]
fn run_takes_the_same_options_on_every_machine() {
    let secs = |o: &Output| -> f64 {
        let so = text(&o.stdout);
        assert!(o.status.success(), "{so}\n{}", text(&o.stderr));
        so.lines()
            .find_map(|l| l.strip_prefix("machine time: "))
            .and_then(|s| s.trim_end_matches(" s").parse().ok())
            .expect("the machine time is printed")
    };
    let lathe = |more: &[&str]| {
        let mut a = vec![
            "run",
            "--machine",
            "citizen",
            "programs/citizen",
            "--parts",
            "1",
        ];
        a.extend_from_slice(more);
        novanc(&a)
    };
    // The feed override slows the cuts (not the rapids): longer, not twice as long.
    let full = secs(&lathe(&[]));
    let half = secs(&lathe(&["--feed-override", "50"]));
    assert!(
        half > full * 1.2 && half < full * 2.0,
        "{full} s vs {half} s at 50 %"
    );
    // --pulses off: the recording keeps no /nc/pulses, and says so.
    let dir = common::temp_dir("lathe-run-options");
    let rec = dir.join("no-pulses.mcap");
    let o = lathe(&["--record", rec.to_str().unwrap(), "--pulses", "off"]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    assert!(
        text(&o.stdout).contains(" 0 pulses in 0 batches"),
        "{}",
        text(&o.stdout)
    );
    assert!(!read(&rec).iter().any(|m| m.topic == "/nc/pulses"));
    // The switches are taken on both machines.
    for machine in [
        &["--machine", "citizen", "programs/citizen"][..],
        &["programs/pocket.ngc"],
    ] {
        let mut a = vec!["run"];
        a.extend_from_slice(machine);
        a.extend_from_slice(&["--optional-stop", "--block-delete"]);
        let o = novanc(&a);
        assert!(o.status.success(), "{a:?}: {}", text(&o.stderr));
    }
    // One machine's options on the other: refused, exit 2, nothing printed.
    for (args, said) in [
        (
            &[
                "run",
                "--machine",
                "citizen",
                "programs/citizen",
                "--tools",
                "x.tt",
            ][..],
            "--tools is the machining centre's",
        ),
        (
            &[
                "run",
                "--machine",
                "citizen",
                "programs/citizen",
                "--interpolator",
                "dda",
            ],
            "--interpolator is the machining centre's",
        ),
        (
            &["run", "programs/pocket.ngc", "--parts", "3"],
            "--parts is a lathe's part target",
        ),
        (
            &[
                "run",
                "--machine",
                "citizen",
                "programs/citizen",
                "--feed-override",
                "0",
            ],
            "--feed-override: '0' is not a percentage from 1 to 150",
        ),
    ] {
        let o = novanc(args);
        assert_eq!(o.status.code(), Some(2), "{args:?}");
        assert!(
            text(&o.stderr).contains(said),
            "{args:?}: {}",
            text(&o.stderr)
        );
        assert!(o.stdout.is_empty(), "{args:?}");
    }
    // One help, on either machine.
    let a = text(&novanc(&["run", "--help"]).stdout);
    let b = text(&novanc(&["run", "--machine", "citizen", "--help"]).stdout);
    assert_eq!(a, b);
    assert!(a.contains("--parts N") && a.contains("--tools TAPE"), "{a}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_centre_description_sets_the_centres_travel() {
    let dir = common::temp_dir("lathe-centre");
    // The embedded centre runs Table B as before.
    let o = novanc(&["run", "--machine", "centre", "programs/tableb.ap"]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    // A smaller centre refuses it at its travel limit.
    let m = dir.join("small.machine");
    std::fs::write(
        &m,
        "machine small\nkind mill\nx travel 0 100 rapid 9000 accel 800\ny travel 0 100 rapid 9000 accel 800\nz travel -100 0 rapid 9000 accel 800\n",
    )
    .unwrap();
    let o = novanc(&[
        "run",
        "--machine",
        m.to_str().unwrap(),
        "programs/tableb.ap",
    ]);
    assert_eq!(o.status.code(), Some(1));
    assert!(text(&o.stderr).contains("travel"), "{}", text(&o.stderr));
}

#[test]
fn tool_offsets_revised_on_ofs_are_stored_per_channel() {
    let dir = common::temp_dir("lathe-ofs");
    let state = dir.join("state");
    let script = dir.join("ofs.panel");
    std::fs::write(
        &script,
        "op OFS\nchannel 2\ntype T1 X0.04 Z-0.01\ntype T9 X1\nshow\n",
    )
    .unwrap();
    let run = || citizen_script(&script, &state, &[]);
    let o = run();
    let so = text(&o.stdout);
    assert!(o.status.success(), "{so}{}", text(&o.stderr));
    // The cursor (the centre's OFS page's, since stop 40) stands on T01's X.
    assert!(so.contains("T01 0.400 3>   0.040  -0.010"), "{so}");
    assert!(so.contains("T9 is not on this tool post"), "{so}");
    let o = LatheStore::open(&state, &LatheDesc::citizen()).unwrap();
    assert_eq!(
        o.tools[1].as_deref().map(tools_text).as_deref(),
        Some("tool 1 radius 0.4 tip 3 offset 0.02 -0.01\ntool 2 radius 0.2 tip 2 offset 0 0\n")
    );
    assert_eq!(o.tools[0], None, "channel 1 untouched");
    drop(o);
    // A new session reads them back.
    std::fs::write(&script, "op OFS\nchannel 2\nshow\n").unwrap();
    let so = text(&run().stdout);
    assert!(so.contains("T01 0.400 3>   0.040  -0.010"), "{so}");
}

/// Every file below `dir`, by path, with its bytes: what a read-only use must leave alone.
fn files(dir: &Path) -> BTreeMap<PathBuf, Vec<u8>> {
    let mut out = BTreeMap::new();
    let mut todo = vec![dir.to_path_buf()];
    while let Some(d) = todo.pop() {
        for e in std::fs::read_dir(&d).unwrap().flatten() {
            let p = e.path();
            if p.is_dir() {
                todo.push(p);
            } else {
                out.insert(p.clone(), std::fs::read(&p).unwrap());
            }
        }
    }
    out
}

/// `novanc run --machine citizen --state DIR` (stop 57): the lathe console's stores, read and
/// never changed, give the batch the tools revised at OFS and the work offsets (before, a
/// lathe's run refused --state as the centre's). G54's Z set on the console's OFS page moves
/// channel 1's program by it: its pulses change, its parts do not, `translate --state` prints
/// every Z 0.5 mm lower, and the recording's `channel1/work_offsets.csv` says it; a directory
/// with no stores of this lathe is refused.
#[test]
fn run_reads_the_lathe_console_s_offsets_from_its_state_and_leaves_it_alone() {
    let dir = common::temp_dir("lathe-run-state");
    let state = dir.join("state");
    let so = played(&dir, "op OFS\ntype G54 Z-0.5\nshow\ntype T1 X0.04\n");
    assert!(so.contains("G54 X0 Z-0.5 (CH1): from the next START"));
    let before = files(&state);
    let run = |more: &[&str]| {
        let mut a = vec![
            "run",
            "--machine",
            "citizen",
            "programs/citizen",
            "--parts",
            "2",
        ];
        a.extend_from_slice(more);
        novanc(&a)
    };
    let pulses = |o: &Output| -> String {
        let so = text(&o.stdout);
        so.lines()
            .find(|l| l.starts_with("CH1 "))
            .unwrap_or_default()
            .to_string()
    };
    let plain = run(&[]);
    let stored = run(&["--state", state.to_str().unwrap()]);
    assert!(
        plain.status.success() && stored.status.success(),
        "{}",
        text(&stored.stderr)
    );
    assert_ne!(pulses(&plain), pulses(&stored));
    assert!(
        text(&stored.stdout).contains("parts: 2"),
        "{}",
        text(&stored.stdout)
    );
    // `translate --state` reads channel 1's program at the same zero: the same blocks, each Z
    // 0.5 mm lower.
    let tr = |more: &[&str]| {
        let mut a = vec![
            "translate",
            "programs/citizen/system1.ngc",
            "--machine",
            "citizen",
        ];
        a.extend_from_slice(more);
        text(&novanc(&a).stdout)
    };
    let (a, b) = (tr(&[]), tr(&["--state", state.to_str().unwrap()]));
    let zs = |t: &str| -> Vec<f64> {
        t.split_whitespace()
            .filter_map(|w| w.strip_prefix('Z')?.parse().ok())
            .collect()
    };
    let (za, zb) = (zs(&a), zs(&b));
    assert!(!za.is_empty() && za.len() == zb.len(), "{a}\n{b}");
    assert!(
        za.iter().zip(&zb).all(|(a, b)| (a - 0.5 - b).abs() < 1e-9),
        "{za:?}\n{zb:?}"
    );
    // The recording says the offsets it ran with (channel 1's G54 Z -0.5).
    let rec = dir.join("run.mcap");
    let o = run(&[
        "--state",
        state.to_str().unwrap(),
        "--record",
        rec.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    let bytes = std::fs::read(&rec).unwrap();
    let summary = mcap::Summary::read(&bytes).unwrap().unwrap();
    let wpo: Vec<String> = (summary.attachment_indexes.iter())
        .map(|i| mcap::read::attachment(&bytes, i).unwrap())
        .filter(|a| a.name == "channel1/work_offsets.csv")
        .map(|a| String::from_utf8_lossy(&a.data).into_owned())
        .collect();
    assert_eq!(wpo.len(), 1);
    assert!(
        wpo[0].starts_with("system,x_mm,z_mm\nG54,0,-0.5\nG55,0,0\n"),
        "{}",
        wpo[0]
    );
    // Read, never changed.
    assert_eq!(files(&state), before);
    let o = run(&["--state", dir.join("none").to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(1));
    assert!(
        text(&o.stderr).contains("holds no stores of the lathe"),
        "{}",
        text(&o.stderr)
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// Issue 20, item 17: a recording on a full disk says why in the operator's words ("No space
/// left on device"), not the MCAP writer's wrapping of it.
#[test]
fn a_recording_on_a_full_disk_says_no_space() {
    if !Path::new("/dev/full").exists() {
        eprintln!("\n!!!!! SKIPPED: no /dev/full on this system !!!!!\n");
        return;
    }
    let dir = common::temp_dir("lathe-full");
    let script = dir.join("one.panel");
    std::fs::write(&script, "start\nwait ms 100\n").unwrap();
    let o = citizen_script(&script, &dir.join("state"), &["--record", "/dev/full"]);
    let e = text(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{e}");
    assert!(
        e.contains("/dev/full: No space left on device") && !e.contains("compression"),
        "{e}"
    );
}

/// The lathe window opens as the centre's does (`window::before_opening`) and takes the same
/// options: `--bench-frames` too since stop 51 (it was refused, exit 2, "the lathe window has
/// no benchmark"); without a display it says so, as the centre's does.
#[cfg(feature = "window")]
#[test]
fn the_lathe_window_takes_a_benchmark_as_the_centres_does() {
    let d = common::temp_dir("lathe-bench-nodisplay");
    let o = common::novanc_command()
        .args([
            "--window",
            "--machine",
            "citizen",
            "--bench-frames",
            "5",
            "--state",
        ])
        .arg(d.join("state"))
        .env_remove("DISPLAY")
        .env_remove("WAYLAND_DISPLAY")
        .output()
        .expect("novanc runs");
    let e = text(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{e}");
    assert!(e.contains("no display") && !e.contains("benchmark"), "{e}");
}

#[test]
fn a_wait_at_feed_override_0_with_a_cut_in_progress_stops_the_script_as_the_centres_does() {
    // Before: the wait ran on for 1000 hours of machine time (hours of CPU) while no channel
    // could move. Now it stops at once with the centre's words, and the script exits 1.
    let dir = common::temp_dir("lathe-ov0");
    let script = dir.join("ov0.panel");
    std::fs::write(&script, "start\nwait ms 3000\noverride 0\nwait\nshow\n").unwrap();
    let t0 = std::time::Instant::now();
    let o = citizen_script(&script, &dir.join("state"), &[]);
    let err = text(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{err}");
    assert!(
        err.contains(
            "novanc script: event 4: wait: the machine stands still at feed override 0 %; raise the override"
        ),
        "{err}"
    );
    assert!(
        !text(&o.stdout).contains("--- display"),
        "the show after it did not run"
    );
    assert!(t0.elapsed() < std::time::Duration::from_secs(60));
    // At 10 % the same script waits the cycle out.
    std::fs::write(
        &script,
        "start\nwait ms 3000\noverride 10\nwait ms 1000\noverride 100\nwait\n",
    )
    .unwrap();
    let o = citizen_script(&script, &dir.join("state2"), &[]);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o.stderr));
}

/// The lathe console on the one grammar: an editor command line's `Y` type-out is shown (the
/// lathe dropped it), and a centre word or a key with no use here is refused with the line
/// before anything runs. (A key pressed at the console says it does nothing: the
/// model-based sequences check that after every such key.)
#[test]
fn the_lathe_shows_the_editors_type_out_and_refuses_the_centres_words_whole() {
    let dir = common::temp_dir("lathe-keys");
    let script = dir.join("keys.panel");
    std::fs::write(&script, "op DATA\ntype 2L\ntype 1Y\nshow\ntype 1L\nshow\n").unwrap();
    let o = citizen_script(&script, &dir.join("state"), &[]);
    let so = text(&o.stdout);
    assert!(o.status.success(), "{so}{}", text(&o.stderr));
    let frames: Vec<&str> = so.split("--- display").skip(1).collect();
    assert_eq!(frames.len(), 2, "{so}");
    // 2L then 1Y: the third line, shown in place of the listing (no `>` pointer line).
    assert!(
        frames[0].contains(" (seed 004: receive block P11"),
        "{}",
        frames[0]
    );
    assert!(!frames[0].contains(">0003"), "{}", frames[0]);
    // The next line brings the listing back, the pointer on line 4.
    assert!(frames[1].contains(">0004 G18"), "{}", frames[1]);
    std::fs::write(&script, "start\ndata SEARCH\n").unwrap();
    let o = citizen_script(&script, &dir.join("state"), &[]);
    let err = text(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{err}");
    assert!(
        err.contains("keys.panel:2: 'data SEARCH' is the machining centre's"),
        "{err}"
    );
    assert!(!err.contains("START"), "nothing ran: {err}");
    // A key is read whatever it is (a recording keeps the keys that do nothing, and plays
    // back): played, it says that it does nothing, as when pressed (refused here before
    // stop 39).
    std::fs::write(&script, "key Alt+z\nshow\n").unwrap();
    let o = citizen_script(&script, &dir.join("state"), &[]);
    let so = text(&o.stdout);
    assert!(o.status.success(), "{so}{}", text(&o.stderr));
    assert!(so.contains("key Alt+z does nothing in AUTO"), "{so}");
}

/// The screen says what the machine does: a channel's coolant (M07 mist, M08 flood), which the
/// kernel keeps per channel, is on its plasma's tool line until M09 turns it off.
#[test]
fn the_plasma_shows_the_channels_coolant() {
    let dir = common::temp_dir("lathe-coolant");
    let so = played(
        &dir,
        "op MDI\ntype M8\nstart\nwait\nshow\ntype M7\ntype M8\nstart\nwait\nshow\ntype M9\nstart\nwait\nshow\nkey Tab\nshow\n",
    );
    let tool_lines: Vec<&str> = so.lines().filter(|l| l.starts_with("T00 ")).collect();
    assert_eq!(
        tool_lines,
        [
            "T00 EMPTY CHUCK OPEN IDLE M08",
            "T00 EMPTY CHUCK OPEN IDLE M07 M08",
            "T00 EMPTY CHUCK OPEN IDLE",
            // Channel 2's coolant was never on.
            "T00 EMPTY CHUCK OPEN IDLE",
        ],
        "{so}"
    );
}

/// The DATA pointer of each channel is kept across a restart, as the centre's is: the editor
/// goes on where the operator left it.
#[test]
fn the_editor_pointer_of_each_channel_is_kept_across_a_restart() {
    let dir = common::temp_dir("lathe-pointer");
    let so = played(&dir, "op DATA\ntype 3L\nchannel 2\ntype 5L\nshow\n");
    assert!(so.contains(">0006 "), "{so}");
    let so = played(&dir, "op DATA\nshow\nchannel 2\nshow\n");
    let frames: Vec<&str> = so.split("--- display").skip(1).collect();
    assert!(frames[0].contains(">0004 "), "CH1 at line 4: {}", frames[0]);
    assert!(frames[1].contains(">0006 "), "CH2 at line 6: {}", frames[1]);
}

/// `novanc translate --machine LATHE`: one channel's program as the blocks the kernel gets,
/// X a radius, the lathe's preamble, the meeting and chuck codes as the program wrote them.
#[test]
fn translate_lists_a_lathe_channels_blocks() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let prog = root.join("programs/citizen/system1.ngc");
    let prog = prog.to_str().expect("utf-8 path");
    let out = novanc(&["translate", "--machine", "citizen", prog]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let listing = text(&out.stdout);
    let lines: Vec<&str> = listing.lines().collect();
    assert_eq!(lines[0], "G21 G90 G18 G8 G94 G40 G80");
    assert_eq!(lines[1], "N1 G00 X20.000 Z10.000");
    assert_eq!(lines[2], "N2 M10");
    // G96 and the feed per revolution once, where they begin; the arc in the turning plane
    // without a G18 of its own; the wait for system 2 with the channels it names.
    assert!(lines.contains(&"N4 G96 S150 D4000 M03"), "{listing}");
    assert!(lines.contains(&"N6 G95 G01 X-0.500 F0.08"), "{listing}");
    assert!(lines.contains(&"N7 G00 Z2.000"), "{listing}");
    assert!(
        lines
            .iter()
            .any(|l| l.starts_with("N12 G03 X9.000 Z-16.800 I")),
        "{listing}"
    );
    assert!(lines.contains(&"N17 M101 P12"), "{listing}");
    assert_eq!(lines.last(), Some(&"M30"));
    // Channel 3's program on channel 3; a channel the machine does not have is refused.
    let prog3 = root.join("programs/citizen/system3.ngc");
    let prog3 = prog3.to_str().expect("utf-8 path");
    let out = novanc(&["translate", "--machine", "citizen", "--channel", "3", prog3]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    assert!(text(&out.stdout).contains(" G33 Z-13.649 K1.5"));
    let out = novanc(&["translate", "--machine", "citizen", "--channel", "4", prog3]);
    assert_eq!(out.status.code(), Some(2));
    assert!(text(&out.stderr).contains("--channel: citizen has channels 1 to 3"));
    // A program error: PROG:LINE:COL: message, nothing on stdout.
    let dir = common::temp_dir("lathe-translate");
    let bad = dir.join("bad.ngc");
    std::fs::write(&bad, "G0 X10 Z5\nG2 X20 Z0\nM30\n").expect("write");
    let out = novanc(&[
        "translate",
        "--machine",
        "citizen",
        bad.to_str().expect("utf-8"),
    ]);
    assert_eq!(out.status.code(), Some(1));
    assert!(out.stdout.is_empty());
    assert!(
        text(&out.stderr).starts_with(&format!("{}:2:1: ", bad.display())),
        "{}",
        text(&out.stderr)
    );
}
