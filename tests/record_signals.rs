//! Recordings end well (issue 15, item 5; docs/recording.md, "Interrupted runs" and
//! "Incomplete recordings"):
//! - SIGINT, SIGTERM or SIGHUP during `novanc run --record` or `novanc script --record` used to
//!   end the process at once, leaving a file with no summary or footer that Python's
//!   `make_reader` refused (`RecordLengthLimitExceeded`). Now the machine is reset, the file is
//!   closed with `complete: false`, and the exit code is 128 + the signal;
//! - `--record /dev/full` (or a small disk) used to exit 0 and count blocks and pulses that never
//!   reached the file. Now the exit code is 1 and the summary counts only what a reader gets.
//! - (issue 20, items 12 and 14) the lathe script's `wait` did not look at the signal, and the
//!   consoles in the terminal closed their recordings `complete: true` when a signal ended
//!   them mid-cycle; a process killed outright (a second signal, SIGKILL) left a recording no
//!   reader opened.

mod common;
#[path = "common/tmux.rs"]
mod tmux;
#[cfg(feature = "window")]
#[path = "common/xvfb.rs"]
mod xvfb;

use common::python_check;
use std::io::Read;
use std::os::unix::process::CommandExt;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

/// `novanc ARGS` with SIGINT, SIGTERM and SIGHUP at their default action whatever this test
/// process inherited (a shell's background job ignores SIGINT), and `ignore` ignored.
fn novanc(args: &[&str], ignore: Option<libc::c_int>) -> Command {
    let mut cmd = common::novanc_command();
    cmd.args(args)
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped());
    // SAFETY: only `signal`, which is async-signal-safe, between fork and exec.
    unsafe {
        cmd.pre_exec(move || {
            for sig in [libc::SIGINT, libc::SIGTERM, libc::SIGHUP] {
                libc::signal(sig, libc::SIG_DFL);
            }
            if let Some(sig) = ignore {
                libc::signal(sig, libc::SIG_IGN);
            }
            Ok(())
        });
    }
    cmd
}

/// Waits until the recording exists and holds something: the command has installed its
/// handlers by then (before it creates the file).
fn wait_for_file(child: &mut Child, path: &Path) {
    let deadline = Instant::now() + Duration::from_secs(20);
    loop {
        if std::fs::metadata(path).is_ok_and(|m| m.len() > 0) {
            return;
        }
        if let Ok(Some(st)) = child.try_wait() {
            panic!("novanc ended ({st}) before it created {}", path.display());
        }
        assert!(Instant::now() < deadline, "no recording after 20 s");
        std::thread::sleep(Duration::from_millis(5));
    }
}

/// Waits for the child to end (at most `secs`); its exit code, stdout and stderr.
fn finish(mut child: Child, secs: u64) -> (Option<i32>, String, String) {
    let deadline = Instant::now() + Duration::from_secs(secs);
    let status = loop {
        if let Some(st) = child.try_wait().expect("wait for novanc") {
            break st;
        }
        if Instant::now() > deadline {
            let _ = child.kill();
            let _ = child.wait();
            panic!("novanc did not end within {secs} s of the signal");
        }
        std::thread::sleep(Duration::from_millis(10));
    };
    let (mut out, mut err) = (String::new(), String::new());
    if let Some(mut s) = child.stdout.take() {
        let _ = s.read_to_string(&mut out);
    }
    if let Some(mut s) = child.stderr.take() {
        let _ = s.read_to_string(&mut err);
    }
    (status.code(), out, err)
}

fn send(child: &Child, sig: libc::c_int) {
    // SAFETY: kill on the pid of our own child, still unreaped.
    assert_eq!(unsafe { libc::kill(child.id() as libc::pid_t, sig) }, 0);
}

fn signal_name(sig: libc::c_int) -> &'static str {
    match sig {
        libc::SIGINT => "SIGINT",
        libc::SIGTERM => "SIGTERM",
        _ => "SIGHUP",
    }
}

/// What a reader gets out of a recording, with chunk CRCs checked, stopping at the first
/// unreadable record (a file cut short by a disk error has no footer): messages per topic,
/// pulses, the last `/nc/state` message and the closing metadata.
struct Readback {
    counts: std::collections::BTreeMap<String, u64>,
    pulses: u64,
    last_state: String,
    /// The `/foxglove/log` messages' texts.
    logs: Vec<String>,
}

fn read_back(path: &Path) -> Readback {
    let bytes = std::fs::read(path).expect("read the recording");
    let mut r = Readback {
        counts: Default::default(),
        pulses: 0,
        last_state: String::new(),
        logs: Vec::new(),
    };
    let Ok(stream) = mcap::MessageStream::new_with_options(
        &bytes,
        mcap::read::Options::IgnoreEndMagic | mcap::read::Options::ValidateChunkCrcs,
    ) else {
        return r;
    };
    for m in stream {
        let Ok(m) = m else { break };
        *r.counts.entry(m.channel.topic.clone()).or_default() += 1;
        let text = String::from_utf8_lossy(&m.data).into_owned();
        match m.channel.topic.as_str() {
            "/nc/pulses" => {
                let times = text.split("\"t_ns\":[").nth(1).unwrap_or("");
                r.pulses += times.split(',').filter(|t| !t.trim().is_empty()).count() as u64;
            }
            "/nc/state" => r.last_state = text,
            "/foxglove/log" => r.logs.push(text),
            _ => {}
        }
    }
    r
}

/// The closing `novanc.recording` metadata of a finished recording (summary section read).
fn closing_metadata(path: &Path) -> std::collections::BTreeMap<String, String> {
    let bytes = std::fs::read(path).expect("read the recording");
    assert!(
        mcap::Summary::read(&bytes)
            .expect("a summary section")
            .is_some(),
        "the recording has a summary section"
    );
    mcap::read::LinearReader::new(&bytes)
        .expect("an MCAP file")
        .filter_map(|r| match r.expect("a good record") {
            mcap::records::Record::Metadata(m) if m.name == "novanc.recording" => Some(m.metadata),
            _ => None,
        })
        .next()
        .expect("the closing novanc.recording metadata")
}

/// Checks an interrupted recording: finished (summary and footer), CRCs good, `complete:
/// false` and the signal named; the machine stopped by E-STOP, on every machine (RUN 0 last,
/// and `EMERGENCY STOP` in `/foxglove/log`; before stop 46 the centre was RESET); Python's
/// reader accepts it.
fn check_interrupted(path: &Path, sig: libc::c_int) {
    let name = signal_name(sig);
    let meta = closing_metadata(path);
    assert_eq!(meta["complete"], "false", "{meta:?}");
    assert_eq!(meta["interrupted"], format!("interrupted by {name}"));
    let back = read_back(path);
    assert!(
        back.last_state.contains("\"run\":0"),
        "the machine was stopped: last state {}",
        back.last_state
    );
    assert!(
        back.logs.iter().any(|l| l.contains("EMERGENCY STOP")),
        "the machine was stopped by E-STOP: {:?}",
        back.logs
    );
    if let Some((ok, text)) = python_check(path, &[]) {
        assert!(
            ok,
            "mcap_check.py refused the interrupted recording:\n{text}"
        );
        assert!(
            text.contains("'complete': 'false'")
                && text.contains(&format!("'interrupted': 'interrupted by {name}'")),
            "{text}"
        );
    }
}

#[test]
fn run_closes_the_recording_on_sigint_sigterm_and_sighup() {
    for sig in [libc::SIGINT, libc::SIGTERM, libc::SIGHUP] {
        let name = signal_name(sig);
        let path = common::temp_path(&format!("run-{name}.mcap"));
        let _ = std::fs::remove_file(&path);
        let p = path.to_str().unwrap();
        // Table B in real time takes 227 s: the signal comes in the middle.
        let mut child = novanc(
            &["run", "programs/tableb.ap", "--realtime", "--record", p],
            None,
        )
        .spawn()
        .expect("start novanc run");
        wait_for_file(&mut child, &path);
        std::thread::sleep(Duration::from_millis(300));
        send(&child, sig);
        let (code, out, err) = finish(child, 20);
        assert_eq!(code, Some(128 + sig), "{name}: {out}\n{err}");
        assert!(
            err.contains(&format!(
                "novanc: interrupted by {name}: stopping the machine and closing the recording"
            )),
            "{err}"
        );
        assert!(out.contains("recording complete: NO"), "{out}");
        assert!(
            out.contains(&format!(
                "RECORDING INCOMPLETE {p}: interrupted by {name}; in the file:"
            )),
            "{out}"
        );
        assert!(!out.contains("blocks executed: 101"), "{out}");
        check_interrupted(&path, sig);
        let _ = std::fs::remove_file(&path);
    }
}

#[test]
fn a_signal_ignored_at_start_stays_ignored() {
    // `nohup novanc run … &` must survive the hangup.
    let path = common::temp_path("nohup.mcap");
    let _ = std::fs::remove_file(&path);
    let p = path.to_str().unwrap();
    let mut child = novanc(
        &["run", "programs/tableb.ap", "--realtime", "--record", p],
        Some(libc::SIGHUP),
    )
    .spawn()
    .expect("start novanc run");
    wait_for_file(&mut child, &path);
    send(&child, libc::SIGHUP);
    std::thread::sleep(Duration::from_millis(300));
    assert!(
        child.try_wait().expect("poll novanc").is_none(),
        "an ignored SIGHUP stopped the run"
    );
    send(&child, libc::SIGTERM);
    let (code, out, err) = finish(child, 20);
    assert_eq!(code, Some(128 + libc::SIGTERM), "{out}\n{err}");
    check_interrupted(&path, libc::SIGTERM);
    let _ = std::fs::remove_file(&path);
}

#[test]
fn script_closes_the_recording_on_a_signal() {
    for sig in [libc::SIGINT, libc::SIGTERM, libc::SIGHUP] {
        let name = signal_name(sig);
        let path = common::temp_path(&format!("script-{name}.mcap"));
        let script = common::temp_path(&format!("script-{name}.panel"));
        let _ = std::fs::remove_file(&path);
        // Table B one block at a time, six times over: several seconds in virtual time.
        let mut text = String::from("op SINGLE\n");
        for _ in 0..600 {
            text.push_str("start\nwait\n");
        }
        std::fs::write(&script, text).unwrap();
        let p = path.to_str().unwrap();
        let mut child = novanc(&["script", script.to_str().unwrap(), "--record", p], None)
            .spawn()
            .expect("start novanc script");
        wait_for_file(&mut child, &path);
        std::thread::sleep(Duration::from_millis(100));
        send(&child, sig);
        let (code, out, err) = finish(child, 20);
        let _ = std::fs::remove_file(&script);
        assert_eq!(code, Some(128 + sig), "{name}: {out}\n{err}");
        assert!(
            err.contains(&format!("novanc: interrupted by {name}")),
            "{err}"
        );
        assert!(
            err.contains(&format!(
                "RECORDING INCOMPLETE {p}: interrupted by {name}; in the file:"
            )),
            "{err}"
        );
        check_interrupted(&path, sig);
        let events = read_back(&path).counts.get("/panel/event").copied();
        assert!(
            events.unwrap_or(0) < 1201,
            "the script stopped early: {events:?} panel events"
        );
        let _ = std::fs::remove_file(&path);
    }
}

/// The counts of the summary line's `in the file:` part: blocks, positions, pulses, pulse
/// batches, states.
fn summary_counts(out: &str) -> [u64; 5] {
    let tail = out
        .split("in the file: ")
        .nth(1)
        .unwrap_or_else(|| panic!("no counts in:\n{out}"));
    let n: Vec<u64> = tail
        .split([' ', ','])
        .filter_map(|w| w.parse().ok())
        .take(5)
        .collect();
    [n[0], n[1], n[2], n[3], n[4]]
}

#[test]
fn recording_to_a_full_disk_fails_and_counts_nothing() {
    // The reproducer: `--record /dev/full` exited 0.
    if !Path::new("/dev/full").exists() {
        eprintln!("\n!!!!! SKIPPED: no /dev/full on this system !!!!!\n");
        return;
    }
    let child = novanc(
        &["run", "programs/tableb.ap", "--record", "/dev/full"],
        None,
    )
    .spawn()
    .expect("start novanc run");
    let (code, out, err) = finish(child, 60);
    assert_eq!(code, Some(1), "{out}\n{err}");
    assert!(
        err.contains("DISK ERROR writing /dev/full: No space left on device"),
        "{err}"
    );
    assert!(out.contains("recording complete: NO"), "{out}");
    assert_eq!(summary_counts(&out), [0; 5], "{out}");
    // The run itself went to its end: only the recording failed.
    assert!(out.contains("blocks executed: 101"), "{out}");
}

/// `novanc run` Table B recording to a file that may not grow beyond `limit` bytes (as on a
/// disk that fills up); exit code, stdout, stderr.
fn run_with_file_limit(path: &Path, limit: u64) -> (Option<i32>, String, String) {
    let mut cmd = novanc(
        &[
            "run",
            "programs/tableb.ap",
            "--record",
            path.to_str().unwrap(),
        ],
        None,
    );
    // SAFETY: setrlimit and signal are async-signal-safe.
    unsafe {
        cmd.pre_exec(move || {
            let lim = libc::rlimit {
                rlim_cur: limit as libc::rlim_t,
                rlim_max: limit as libc::rlim_t,
            };
            libc::setrlimit(libc::RLIMIT_FSIZE, &lim);
            // Over the limit, write fails with EFBIG instead of the process being killed.
            libc::signal(libc::SIGXFSZ, libc::SIG_IGN);
            Ok(())
        });
    }
    finish(cmd.spawn().expect("start novanc run"), 60)
}

#[test]
fn a_disk_that_fills_up_fails_the_run_and_the_summary_counts_only_what_is_on_disk() {
    // 64 KiB (the tmpfs: the header and the settings fit, no chunk does) and 10 MB
    // (two 4 MB chunks fit, the third is cut short).
    for limit in [64 * 1024, 10_000_000] {
        let path = common::temp_path(&format!("limit-{limit}.mcap"));
        let _ = std::fs::remove_file(&path);
        let (code, out, err) = run_with_file_limit(&path, limit);
        assert_eq!(code, Some(1), "{limit}: {out}\n{err}");
        assert!(err.contains("DISK ERROR writing"), "{err}");
        assert!(out.contains("recording complete: NO"), "{out}");
        let said = summary_counts(&out);
        let back = read_back(&path);
        let _ = std::fs::remove_file(&path);
        let got = |t: &str| back.counts.get(t).copied().unwrap_or(0);
        let on_disk = [
            got("/nc/block"),
            got("/nc/position"),
            back.pulses,
            got("/nc/pulses"),
            got("/nc/state"),
        ];
        assert_eq!(said, on_disk, "limit {limit}: the summary says\n{out}");
        if limit > 1_000_000 {
            assert!(on_disk[2] > 0, "the first chunks reached the file");
        } else {
            assert_eq!(on_disk, [0; 5]);
        }
    }
}

/// Whether the python check (when python3 has `mcap`) reads an unfinished recording: streamed
/// and through `make_reader`, with its CRCs good and `complete: false`.
fn python_reads_unfinished(path: &Path) {
    if let Some((ok, text)) = python_check(path, &["--unfinished"]) {
        assert!(ok, "mcap_check.py --unfinished refused it:\n{text}");
        assert!(text.contains("'complete': 'false'"), "{text}");
    }
}

/// The `novanc.recording` metadata wherever it is in the file (a finished file's closing one, or
/// the provisional one at the end of a file whose process was killed), read record by record.
fn recording_metadata(path: &Path) -> std::collections::BTreeMap<String, String> {
    let bytes = std::fs::read(path).expect("read the recording");
    mcap::read::LinearReader::new(&bytes)
        .expect("an MCAP file with its end magic")
        .filter_map(|r| match r.expect("a good record") {
            mcap::records::Record::Metadata(m) if m.name == "novanc.recording" => Some(m.metadata),
            _ => None,
        })
        .last()
        .expect("the novanc.recording metadata")
}

/// The time from `since` until the child ends (at most `secs`); its exit status.
fn ended_within(
    child: &mut Child,
    since: Instant,
    secs: u64,
) -> (std::process::ExitStatus, Duration) {
    loop {
        if let Some(st) = child.try_wait().expect("wait for novanc") {
            return (st, since.elapsed());
        }
        if since.elapsed() > Duration::from_secs(secs) {
            let _ = child.kill();
            let _ = child.wait();
            panic!("novanc did not end within {secs} s of the signal");
        }
        std::thread::sleep(Duration::from_millis(2));
    }
}

/// A lathe panel script that runs a long batch: START, then `wait` until every channel is at
/// rest (999999 parts: hours of machine time).
fn long_lathe_script(name: &str) -> PathBuf {
    let script = common::temp_path(&format!("{name}.panel"));
    std::fs::write(&script, "target 999999\nstart\nwait\nshow\n").unwrap();
    script
}

#[test]
fn lathe_script_ends_on_a_signal_during_wait() {
    // Issue 20, item 12: the lathe script's `wait` never looked at the signal; a second
    // SIGTERM then killed it with the recording unreadable.
    for sig in [libc::SIGTERM, libc::SIGINT, libc::SIGHUP] {
        let name = signal_name(sig);
        let path = common::temp_path(&format!("lathe-wait-{name}.mcap"));
        let script = long_lathe_script(&format!("lathe-wait-{name}"));
        let _ = std::fs::remove_file(&path);
        let p = path.to_str().unwrap();
        let s = script.to_str().unwrap();
        let mut child = novanc(&["script", s, "--machine", "citizen", "--record", p], None)
            .spawn()
            .expect("start novanc script --machine citizen");
        wait_for_file(&mut child, &path);
        std::thread::sleep(Duration::from_millis(300));
        let sent = Instant::now();
        send(&child, sig);
        let (st, took) = ended_within(&mut child, sent, 20);
        let (code, out, err) = finish(child, 1);
        let _ = std::fs::remove_file(&script);
        assert_eq!(st.code(), Some(128 + sig), "{name}: {out}\n{err}");
        assert_eq!(code, Some(128 + sig));
        assert!(
            took < Duration::from_secs(1),
            "{name}: ended {took:?} after the signal"
        );
        eprintln!(
            "lathe script in wait: exit {} {took:?} after {name}",
            128 + sig
        );
        assert!(
            err.contains(&format!(
                "novanc: interrupted by {name}: stopping the machine and closing the recording"
            )),
            "{err}"
        );
        assert!(!out.contains("--- display"), "the script went on: {out}");
        check_interrupted(&path, sig);
        let _ = std::fs::remove_file(&path);
    }
}

#[test]
fn lathe_run_stops_the_machine_and_names_the_signal() {
    // The lathe's headless run wrote `interrupted by signal 15` and left the channels running
    // in the recording; now E-STOP, `interrupted by SIGTERM`, as the centre's run.
    let path = common::temp_path("lathe-run.mcap");
    let _ = std::fs::remove_file(&path);
    let p = path.to_str().unwrap();
    let mut child = novanc(
        &[
            "run",
            "--machine",
            "citizen",
            "programs/citizen",
            "--parts",
            "999999",
            "--record",
            p,
        ],
        None,
    )
    .spawn()
    .expect("start novanc run --machine citizen");
    wait_for_file(&mut child, &path);
    std::thread::sleep(Duration::from_millis(300));
    let sent = Instant::now();
    send(&child, libc::SIGTERM);
    let (st, took) = ended_within(&mut child, sent, 20);
    let (_, out, err) = finish(child, 1);
    assert_eq!(st.code(), Some(143), "{out}\n{err}");
    assert!(
        took < Duration::from_secs(1),
        "ended {took:?} after SIGTERM"
    );
    // The one recorder's summary line, as the centre's `novanc run` prints it.
    assert!(
        out.contains("RECORDING INCOMPLETE") && out.contains("interrupted by SIGTERM"),
        "{out}"
    );
    check_interrupted(&path, libc::SIGTERM);
    let _ = std::fs::remove_file(&path);
}

#[test]
fn a_recording_stays_readable_when_the_process_is_killed() {
    // A second stop signal (or SIGKILL) ends the process at once. The recording keeps what
    // was committed (every chunk, closed at 4 MB or after a second), ends with a footer, and
    // says it is not complete.
    let script = long_lathe_script("killed");
    let s = script.to_str().unwrap().to_string();
    let runs: [(&str, Vec<&str>); 2] = [
        (
            "run",
            vec!["run", "programs/tableb.ap", "--realtime", "--record"],
        ),
        (
            "lathe",
            vec!["script", &s, "--machine", "citizen", "--record"],
        ),
    ];
    for (what, args) in runs {
        let path = common::temp_path(&format!("killed-{what}.mcap"));
        let _ = std::fs::remove_file(&path);
        let mut args = args.clone();
        args.push(path.to_str().unwrap());
        let mut child = novanc(&args, None).spawn().expect("start novanc");
        wait_for_file(&mut child, &path);
        std::thread::sleep(Duration::from_millis(1500));
        send(&child, libc::SIGKILL);
        let (st, _) = ended_within(&mut child, Instant::now(), 20);
        assert_eq!(
            std::os::unix::process::ExitStatusExt::signal(&st),
            Some(libc::SIGKILL)
        );
        let meta = recording_metadata(&path);
        assert_eq!(meta["complete"], "false", "{what}: {meta:?}");
        assert!(
            meta["interrupted"].contains("not closed"),
            "{what}: {meta:?}"
        );
        let back = read_back(&path);
        assert!(
            back.counts.values().sum::<u64>() > 0,
            "{what}: nothing readable"
        );
        python_reads_unfinished(&path);
        let _ = std::fs::remove_file(&path);
    }
    let _ = std::fs::remove_file(&script);
}

#[test]
fn a_second_signal_leaves_a_readable_recording() {
    // The first signal is noted, the second (30 ms later, before the run has closed its
    // recording, or just after) ends the process at once: either way the file reads.
    let path = common::temp_path("second.mcap");
    let _ = std::fs::remove_file(&path);
    let p = path.to_str().unwrap();
    let mut child = novanc(
        &["run", "programs/tableb.ap", "--realtime", "--record", p],
        None,
    )
    .spawn()
    .expect("start novanc run");
    wait_for_file(&mut child, &path);
    std::thread::sleep(Duration::from_millis(300));
    send(&child, libc::SIGTERM);
    std::thread::sleep(Duration::from_millis(30));
    // SAFETY: kill on the pid of our own child, maybe already ended but not reaped.
    unsafe { libc::kill(child.id() as libc::pid_t, libc::SIGTERM) };
    let (st, _) = ended_within(&mut child, Instant::now(), 20);
    let killed = std::os::unix::process::ExitStatusExt::signal(&st) == Some(libc::SIGTERM);
    assert!(killed || st.code() == Some(143), "{st}");
    let meta = recording_metadata(&path);
    assert_eq!(meta["complete"], "false", "{meta:?}");
    python_reads_unfinished(&path);
    let _ = std::fs::remove_file(&path);
}

/// The console in a terminal (tmux), recording, killed by SIGTERM mid-cycle: `args` after
/// `--state DIR/state --record DIR/rec.mcap`, `keys` start the cycle, `running` is on the
/// screen while it runs. Checks exit 143 within a second of the signal, the terminal handed
/// back, and the recording closed `complete: false` with the signal named.
fn console_killed_mid_cycle(name: &str, args: &str, keys: &[&str], running: &[&str]) {
    if !tmux::tmux_or_skip(name) {
        return;
    }
    let d = common::temp_dir(name);
    let rec = d.join("rec.mcap");
    let exe = env!("CARGO_BIN_EXE_novanc");
    let run = tmux::with_pid(
        &d,
        &format!(
            "{exe} --state {d}/state --record {r} {args}",
            d = d.display(),
            r = rec.display()
        ),
    );
    let t = tmux::session(name, &d, &run);
    t.wait_for(&[running[0]], 20);
    t.keys(keys);
    t.wait_for(running, 20);
    std::thread::sleep(Duration::from_millis(500));
    let pid: libc::pid_t = tmux::wait_file(&d.join("pid"), 10).trim().parse().unwrap();
    let sent = Instant::now();
    // SAFETY: kill on novanc's pid, which the shell of our own tmux session started.
    assert_eq!(unsafe { libc::kill(pid, libc::SIGTERM) }, 0);
    let exit = tmux::wait_file(&d.join("exit"), 20);
    let took = sent.elapsed();
    assert_eq!(exit.trim(), "exit=143");
    assert!(
        took < Duration::from_secs(1),
        "ended {took:?} after SIGTERM"
    );
    eprintln!("{name}: exit 143 {took:?} after SIGTERM");
    tmux::assert_stty_unchanged(&d);
    check_interrupted(&rec, libc::SIGTERM);
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn the_console_closes_its_recording_when_sigterm_ends_it_mid_cycle() {
    // Issue 20, item 14: the recording said `complete: true`, no interruption noted. Table B
    // in AUTO (Alt+2), START (F9): 227 s of machine time in real time.
    console_killed_mid_cycle(
        "console-term",
        "",
        &["M-2", "F9"],
        &["PLASMA DISPLAY 14", "RUN 1"],
    );
}

#[test]
fn the_lathe_console_closes_its_recording_when_sigterm_ends_it_mid_cycle() {
    // The Citizen's console in AUTO, START (F9): five parts, minutes in real time.
    console_killed_mid_cycle(
        "lathe-console-term",
        "--machine citizen",
        &["F9"],
        &["PLASMA DISPLAY 14", "CH1 RUN"],
    );
}

#[cfg(feature = "window")]
#[test]
fn the_window_closes_its_recording_when_sigterm_ends_it_mid_cycle() {
    // The console in the window ignored stop signals: SIGTERM ended it at once, the recording
    // not closed. Table B in AUTO, started by the script, then in real time.
    let Some(x) = xvfb::xvfb_or_skip("window SIGTERM") else {
        return;
    };
    let d = common::temp_dir("window-term");
    let (rec, script, state) = (d.join("rec.mcap"), d.join("s.panel"), d.join("state"));
    std::fs::write(&script, "op AUTO\nstart\n").unwrap();
    let mut cmd = novanc(
        &[
            "--window",
            "--state",
            state.to_str().unwrap(),
            "--record",
            rec.to_str().unwrap(),
            "--script",
            script.to_str().unwrap(),
            "--size",
            "1400x860",
        ],
        None,
    );
    xvfb::on_xvfb(&mut cmd, &x);
    let mut child = cmd.spawn().expect("start novanc --window");
    wait_for_file(&mut child, &rec);
    // Running: the recording has blocks (committed within a second of being written).
    let deadline = Instant::now() + Duration::from_secs(60);
    while read_back(&rec)
        .counts
        .get("/nc/block")
        .copied()
        .unwrap_or(0)
        == 0
    {
        if let Ok(Some(st)) = child.try_wait() {
            panic!("novanc --window ended ({st}) before the cycle ran");
        }
        assert!(Instant::now() < deadline, "no block recorded after 60 s");
        std::thread::sleep(Duration::from_millis(50));
    }
    let sent = Instant::now();
    send(&child, libc::SIGTERM);
    let (st, took) = ended_within(&mut child, sent, 20);
    let (_, out, err) = finish(child, 1);
    assert_eq!(st.code(), Some(143), "{out}\n{err}");
    assert!(
        took < Duration::from_secs(1),
        "ended {took:?} after SIGTERM"
    );
    eprintln!("window: exit 143 {took:?} after SIGTERM");
    assert!(err.contains("RECORDING INCOMPLETE"), "{err}");
    check_interrupted(&rec, libc::SIGTERM);
    let _ = std::fs::remove_dir_all(&d);
}
