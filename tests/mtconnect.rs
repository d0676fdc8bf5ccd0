//! The MTConnect SHDR adapter (docs/mtconnect.md): `novanc script --mtconnect` streams to
//! agents; a stand-in agent here reads the dump, the changes and the heartbeat. An
//! adapter-level test, not agent conformance.

mod common;
#[path = "common/tmux.rs"]
mod tmux;

use novanc::mtconnect::Adapter;
use std::io::{BufRead, BufReader, Read, Write};
use std::net::{TcpListener, TcpStream};
use std::process::Stdio;
use std::time::{Duration, Instant};

fn free_port() -> u16 {
    TcpListener::bind("127.0.0.1:0")
        .unwrap()
        .local_addr()
        .unwrap()
        .port()
}

fn connect(port: u16) -> TcpStream {
    let end = Instant::now() + Duration::from_secs(30);
    loop {
        match TcpStream::connect(("127.0.0.1", port)) {
            Ok(s) => {
                s.set_read_timeout(Some(Duration::from_secs(60))).unwrap();
                return s;
            }
            Err(e) if Instant::now() > end => panic!("no adapter on {port}: {e}"),
            Err(_) => std::thread::sleep(Duration::from_millis(20)),
        }
    }
}

/// Every line until the adapter closes.
fn read_all(s: TcpStream) -> Vec<String> {
    BufReader::new(s).lines().map_while(Result::ok).collect()
}

/// The values `key` took, in order, in SHDR data lines (not conditions or PONG).
fn values(lines: &[String], key: &str) -> Vec<String> {
    let mut out = Vec::new();
    for l in lines.iter().filter(|l| !l.starts_with('*')) {
        let f: Vec<&str> = l.split('|').collect();
        let mut i = 1;
        while i + 1 < f.len() {
            if f[i] == key {
                out.push(f[i + 1].to_string());
            }
            i += 2;
        }
    }
    out
}

/// Table B in single block for three blocks, then AUTO with a feed hold, to M30, then E-STOP
/// and RESET, then T02's length revised on OFS, streamed to two stand-in agents (tests/mtconnect_agent.py: the heartbeat, every
/// key and value against the shipped Devices.xml and the MTConnect enumerations, Execution,
/// every block's line in order, partcount, the E-STOP's FAULT, the revised tool table, the
/// last position against the same run's recording, in work and machine coordinates). An adapter-level test, not agent conformance.
#[test]
fn table_b_streams_to_the_stand_in_agent() {
    let d = common::temp_dir("mtc-agent");
    let script = d.join("run.script");
    std::fs::write(
        &script,
        "op SINGLE\nstart\nwait\nstart\nwait\nstart\nwait\nop AUTO\nstart\nwait ms 2000\nstop\nwait\nstart\nwait\nestop\nreset\nkey Ctrl+O\nkey Down\ntype 155\n",
    )
    .unwrap();
    let rec = d.join("r.mcap");
    let state = d.join("state");
    let args = [
        "--state".as_ref(),
        state.as_os_str(),
        "--record".as_ref(),
        rec.as_os_str(),
    ];
    script_to_the_stand_in_agent(&script, &args, "Devices.xml", &[], &[rec.as_os_str()]);
}

/// The Citizen's three channels as three paths of one device: START, 3 s, E-STOP, RESET,
/// streamed to the stand-in agent (tests/mtconnect_agent.py --citizen: every key and value
/// against docs/mtconnect/Devices-citizen.xml, three paths, WAIT on CH2 while CH1 runs, estop
/// TRIGGERED then ARMED, the `system` FAULT and NORMAL).
#[test]
fn the_citizen_streams_three_paths_to_the_stand_in_agent() {
    let d = common::temp_dir("mtc-citizen");
    let script = d.join("run.script");
    std::fs::write(&script, "start\nwait ms 3000\nestop\nreset\n").unwrap();
    let state = d.join("state");
    let args = [
        "--machine".as_ref(),
        "citizen".as_ref(),
        "--state".as_ref(),
        state.as_os_str(),
    ];
    script_to_the_stand_in_agent(
        &script,
        &args,
        "Devices-citizen.xml",
        &["--citizen".as_ref()],
        &[],
    );
}

/// Starts `novanc script SCRIPT ARGS --mtconnect PORT --mtconnect-wait 30` on a free port: the
/// port and the process, which waits for an agent.
fn script_for_an_agent(
    script: &std::path::Path,
    args: &[&std::ffi::OsStr],
) -> (u16, std::process::Child) {
    let port = free_port();
    let child = common::novanc_command()
        .arg("script")
        .arg(script)
        .args(args)
        .args(["--mtconnect", &format!("127.0.0.1:{port}")])
        .args(["--mtconnect-wait", "30"])
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    (port, child)
}

/// Runs `novanc script SCRIPT ARGS --mtconnect PORT --mtconnect-wait 30` and the stand-in
/// agent `tests/mtconnect_agent.py FLAGS PORT docs/mtconnect/DEVICES REST` on it; both must
/// pass. Returns quietly when Python is missing outside CI (the helper says so loudly).
fn script_to_the_stand_in_agent(
    script: &std::path::Path,
    args: &[&std::ffi::OsStr],
    devices: &str,
    flags: &[&std::ffi::OsStr],
    rest: &[&std::ffi::OsStr],
) {
    let (port, child) = script_for_an_agent(script, args);
    let devices = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("docs/mtconnect")
        .join(devices);
    let port = port.to_string();
    let mut agent_args = flags.to_vec();
    agent_args.extend([port.as_ref(), devices.as_os_str()]);
    agent_args.extend(rest);
    let modules: &[&str] = if rest.is_empty() {
        &["socket"]
    } else {
        &["mcap"]
    };
    let agent = common::python_script("mtconnect_agent.py", modules, &agent_args);
    let Some((ok, text)) = agent else {
        // No Python (outside CI, said loudly by the helper): no agent will come.
        let mut child = child;
        let _ = child.kill();
        let _ = child.wait();
        return;
    };
    let out = child.wait_with_output().unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(0), "{err}");
    assert!(err.contains("mtconnect: listening on 127.0.0.1:"), "{err}");
    assert!(ok, "{text}");
    eprintln!("{text}");
}

#[test]
fn bad_adapter_options_are_refused() {
    for args in [
        vec!["--mtconnect", "70000"],
        vec!["--mtconnect", "host:x"],
        vec!["--mtconnect-wait", "5"],
        vec!["--mtconnect", "7000", "--mtconnect-wait", "-1"],
        vec!["--mtconnect"],
    ] {
        let out = common::novanc_command()
            .arg("script")
            .arg("nothing.script")
            .args(&args)
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert_ne!(out.status.code(), Some(0), "{args:?}");
        assert!(err.contains("mtconnect"), "{args:?}: {err}");
    }
}

#[test]
fn no_agent_within_the_wait_stops_the_script() {
    let d = common::temp_dir("mtc-nowait");
    let script = d.join("s.script");
    std::fs::write(&script, "op AUTO\n").unwrap();
    let out = common::novanc_command()
        .args(["script", script.to_str().unwrap()])
        .args([
            "--mtconnect",
            &free_port().to_string(),
            "--mtconnect-wait",
            "0.2",
        ])
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert!(err.contains("no agent connected within 0.2 s"), "{err}");
}

fn typical_items(i: u64) -> Vec<(&'static str, String)> {
    let mut v: Vec<(&'static str, String)> = vec![
        ("avail", "AVAILABLE".into()),
        ("exec", "ACTIVE".into()),
        ("Xact", format!("{:.3}", i as f64 * 0.001)),
        ("Yact", format!("{:.3}", i as f64 * 0.002)),
        ("Zact", "-1.000".into()),
        (
            "block",
            format!("N{i} G01 X{i} F300 {}", "(padding) ".repeat(100)),
        ),
    ];
    v.push(("system", "NORMAL||||".into()));
    v
}

#[test]
fn a_client_that_stops_reading_is_dropped_and_never_slows_publishing() {
    let ad = Adapter::start("127.0.0.1:0".parse().unwrap()).unwrap();
    ad.publish(typical_items(0), std::time::SystemTime::now());
    let port = ad.local_addr().port();
    let silent = connect(port);
    let mut reader = connect(port);
    let end = Instant::now() + Duration::from_secs(10);
    while ad.clients() < 2 {
        assert!(Instant::now() < end, "clients never accepted");
        std::thread::sleep(Duration::from_millis(5));
    }
    let t = std::thread::spawn(move || {
        let mut buf = vec![0u8; 1 << 16];
        let mut n = 0usize;
        while let Ok(k) = reader.read(&mut buf) {
            if k == 0 {
                break;
            }
            n += k;
        }
        n
    });
    // ~1 KB a snapshot: the silent client's buffers fill within some thousands.
    let t0 = Instant::now();
    let mut worst = Duration::ZERO;
    let mut i = 1;
    while ad.dropped() == 0 {
        assert!(i < 200_000, "the silent client was never dropped");
        let s = Instant::now();
        ad.publish(typical_items(i), std::time::SystemTime::now());
        worst = worst.max(s.elapsed());
        i += 1;
    }
    let per = t0.elapsed() / i as u32;
    eprintln!("mtconnect: {i} snapshots until the silent client was dropped, {per:?} each, worst {worst:?}");
    assert_eq!(ad.clients(), 1, "the reading client stays");
    assert!(
        worst < Duration::from_millis(200),
        "a publish took {worst:?}"
    );
    drop(silent);
    drop(ad);
    assert!(t.join().unwrap() > 0);
}

/// A burst larger than the kernel's socket buffers (a script's virtual time makes one) reaches
/// an agent that reads only after it, every change in order: what the socket cannot take waits
/// in the client's queue (up to `QUEUE_LIMIT`), and publishing never blocks.
#[test]
fn a_burst_waits_in_the_queue_for_an_agent_that_reads_late() {
    let ad = Adapter::start("127.0.0.1:0".parse().unwrap()).unwrap();
    ad.publish(typical_items(0), std::time::SystemTime::now());
    let late = connect(ad.local_addr().port());
    let end = Instant::now() + Duration::from_secs(10);
    while ad.clients() < 1 {
        assert!(Instant::now() < end, "client never accepted");
        std::thread::sleep(Duration::from_millis(5));
    }
    // About 5 MB: more than loopback buffers hold for a client that reads nothing (about
    // 3.6 MB here), less than that plus the queue.
    let n = 5_000;
    let t0 = Instant::now();
    for i in 1..=n {
        ad.publish(typical_items(i), std::time::SystemTime::now());
    }
    let took = t0.elapsed();
    assert_eq!(ad.dropped(), 0, "the late reader was dropped");
    let t = std::thread::spawn(move || read_all(late));
    std::thread::sleep(Duration::from_millis(200));
    drop(ad);
    let lines = t.join().unwrap();
    let x = values(&lines, "Xact");
    let want: Vec<String> = (0..=n)
        .map(|i| format!("{:.3}", i as f64 * 0.001))
        .collect();
    assert_eq!(x.len(), want.len(), "{} of {} changes", x.len(), want.len());
    assert!(x == want, "changes out of order");
    eprintln!("mtconnect: a {n}-snapshot burst published in {took:?}");
}

#[test]
fn novanc_run_streams_its_program_to_an_agent() {
    let d = common::temp_dir("mtc-run");
    let prog = d.join("p.ngc");
    std::fs::write(&prog, "G21 G90\nG0 X10 Y5\nG1 Z-1 F300\nM30\n").unwrap();
    let lines = streamed(&["run".as_ref(), prog.as_os_str()]);
    assert_eq!(values(&lines, "mode"), ["AUTOMATIC"], "{lines:?}");
    assert_eq!(
        values(&lines, "exec").last().map(|s| s.as_str()),
        Some("PROGRAM_COMPLETED"),
        "{lines:?}"
    );
    assert_eq!(
        values(&lines, "Xact").last().map(|s| s.as_str()),
        Some("10.000")
    );
    assert_eq!(
        values(&lines, "Zact").last().map(|s| s.as_str()),
        Some("-1.000")
    );
    assert_eq!(
        values(&lines, "partcount").last().map(|s| s.as_str()),
        Some("1")
    );
}

/// `novanc run --machine citizen DIR --parts 1` streamed to one agent: every line it got.
fn citizen_run_streamed(dir: &std::path::Path) -> Vec<String> {
    streamed(&[
        "run".as_ref(),
        "--machine".as_ref(),
        "citizen".as_ref(),
        dir.as_os_str(),
        "--parts".as_ref(),
        "1".as_ref(),
    ])
}

/// `novanc ARGS --mtconnect PORT --mtconnect-wait 30`, which must exit 0: every line one
/// agent got.
fn streamed(args: &[&std::ffi::OsStr]) -> Vec<String> {
    let port = free_port();
    let child = common::novanc_command()
        .args(args)
        .args(["--mtconnect", &format!("127.0.0.1:{port}")])
        .args(["--mtconnect-wait", "30"])
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let a = connect(port);
    let t = std::thread::spawn(move || read_all(a));
    let out = child.wait_with_output().unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(0), "{err}");
    t.join().unwrap()
}

/// `novanc run --machine citizen` streams each channel as a path, every change as the kernel
/// makes it: every path completes its part, and CH2 and CH3 wait at their sync points.
#[test]
fn novanc_run_streams_the_citizens_three_paths() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("programs/citizen");
    let lines = citizen_run_streamed(&dir);
    for p in ["p1_", "p2_", "p3_"] {
        let ex = values(&lines, &format!("{p}exec"));
        assert_eq!(
            ex.first().map(|s| s.as_str()),
            Some("ACTIVE"),
            "{p}: {ex:?}"
        );
        assert_eq!(
            ex.last().map(|s| s.as_str()),
            Some("PROGRAM_COMPLETED"),
            "{p}: {ex:?}"
        );
        assert_eq!(values(&lines, &format!("{p}partcount")), ["0", "1"], "{p}");
        assert_eq!(values(&lines, &format!("{p}mode")), ["AUTOMATIC"], "{p}");
        if p != "p1_" {
            assert!(ex.iter().any(|e| e == "WAIT"), "{p}: {ex:?}");
        }
    }
    assert_eq!(values(&lines, "estop"), ["ARMED"]);
}

/// In virtual time every change of state is sent, none merged away: three dwells of 2, 3 and
/// 4 ms in a row on CH1 (each shorter than the 10 ms steps the lathe once published at) each
/// appear as CH1's block and line, in order, while the other channels run on.
#[test]
fn a_lathe_change_shorter_than_10_ms_is_streamed() {
    let src = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("programs/citizen");
    let d = common::temp_dir("mtc-short");
    for f in ["system1.ngc", "system2.ngc", "system3.ngc"] {
        let mut text = std::fs::read_to_string(src.join(f)).unwrap();
        if f == "system1.ngc" {
            text = text.replacen("\nM10\n", "\nM10\nG4 P0.002\nG4 P0.003\nG4 P0.004\n", 1);
        }
        std::fs::write(d.join(f), text).unwrap();
    }
    let lines = citizen_run_streamed(&d);
    let blocks = values(&lines, "p1_block");
    let dwells: Vec<&str> = blocks
        .iter()
        .map(|b| b.as_str())
        .filter(|b| b.starts_with("G4"))
        .collect();
    assert_eq!(
        dwells,
        ["G4 P0.002", "G4 P0.003", "G4 P0.004"],
        "{blocks:?}"
    );
    let line = values(&lines, "p1_line");
    for n in ["8", "9", "10"] {
        assert!(line.iter().any(|l| l == n), "line {n}: {line:?}");
    }
    // Stamped in machine time, never backwards.
    let ts: Vec<&str> = lines
        .iter()
        .filter(|l| !l.starts_with('*'))
        .filter_map(|l| l.split('|').next())
        .collect();
    assert!(ts.windows(2).all(|w| w[0] <= w[1]), "{ts:?}");
}

#[test]
fn the_terminal_console_streams_its_mode_to_an_agent() {
    // The dump: DATA INPUT is EDIT; Alt+2 turns the selector to AUTO.
    console_streams(
        "mtc-console",
        "",
        &[(&[], "|mode|EDIT"), (&["M-2"], "|mode|AUTOMATIC")],
    );
}

/// The lathe's terminal console streams its three channels as paths: idle and READY, the
/// rapid and spindle overrides turned, then START (Alt+s) runs all three.
#[test]
fn the_lathe_console_streams_its_paths_to_an_agent() {
    console_streams(
        "mtc-lathe",
        "--machine citizen",
        &[
            (&[], "|p3_exec|READY"),
            // The centre's rapid and spindle override keys, on every channel (stop 38).
            (&["M-f"], "|p3_Rovr|50"),
            (&["M-]"], "|p2_Sovr|110"),
            (&["M-2"], "|p1_mode|AUTOMATIC"),
            (&["M-s"], "|p2_exec|ACTIVE"),
        ],
    );
}

/// Runs `novanc ARGS --mtconnect PORT` in tmux, connects as an agent and, for each step,
/// presses its keys and reads until a line contains its text; then the heartbeat, and Ctrl-C
/// ends the console with exit 0.
fn console_streams(name: &str, args: &str, steps: &[(&[&str], &str)]) {
    if !tmux::tmux_or_skip("mtconnect console") {
        return;
    }
    let d = common::temp_dir(name);
    let port = free_port();
    let run = format!(
        "{} {args} --state {} --mtconnect {port}",
        env!("CARGO_BIN_EXE_novanc"),
        d.join("state").display()
    );
    let t = tmux::session(name, &d, &run);
    let mut a = connect(port);
    a.set_read_timeout(Some(Duration::from_secs(10))).unwrap();
    let mut r = BufReader::new(a.try_clone().unwrap());
    let mut seen = Vec::new();
    let mut line = String::new();
    let mut read_until = |want: &dyn Fn(&str) -> bool, seen: &mut Vec<String>| {
        while !seen.iter().any(|l| want(l)) {
            line.clear();
            assert!(r.read_line(&mut line).unwrap() > 0, "{seen:?}");
            seen.push(line.clone());
        }
    };
    for (keys, text) in steps {
        if !keys.is_empty() {
            t.keys(keys);
        }
        read_until(&|l: &str| l.contains(text), &mut seen);
    }
    a.write_all(b"* PING\n").unwrap();
    read_until(&|l: &str| l.starts_with("* PONG 10000"), &mut seen);
    t.keys(&["C-c"]);
    assert!(tmux::wait_file(&d.join("exit"), 20).contains("exit=0"));
}

/// The centre's `partcount` is the console's part counter, what its POS page shows and keeps
/// across restarts, as a lathe path's is its channel's counter: a second session on the same
/// state starts from the first's count (stop 50; before, it counted the runs that ended since
/// the adapter started, 0 at every start). It still rises when the program completes.
#[test]
fn the_centres_partcount_is_the_consoles_part_counter() {
    let d = common::temp_dir("mtc-parts");
    let script = d.join("run.script");
    std::fs::write(&script, "op AUTO\nstart\nwait\n").unwrap();
    let state = d.join("state");
    for want in [["0", "1"], ["1", "2"]] {
        let lines = streamed(&[
            "script".as_ref(),
            script.as_os_str(),
            "--state".as_ref(),
            state.as_os_str(),
        ]);
        assert_eq!(values(&lines, "partcount"), want, "{lines:?}");
        let done = lines.iter().find(|l| l.contains("|exec|PROGRAM_COMPLETED"));
        let rose = lines
            .iter()
            .find(|l| l.contains(&format!("|partcount|{}", want[1])));
        let stamp = |l: Option<&String>| l.and_then(|l| l.split('|').next().map(str::to_string));
        assert!(done.is_some() && rose.is_some(), "{lines:?}");
        assert_eq!(
            stamp(done),
            stamp(rose),
            "partcount rises with the program's end"
        );
    }
}

/// `message` means one thing on both machines (stop 51): the operator's message line as the
/// console shows it. The same script gives the same words from the centre and from the
/// Citizen. Before, the centre sent the pulse core's latest notice, which the feed override's
/// turn and a refused START never made, and the lathe its console's message line.
#[test]
fn message_is_the_consoles_message_line_on_both_machines() {
    let d = common::temp_dir("mtc-message");
    let script = d.join("msg.script");
    std::fs::write(
        &script,
        "override 70\nwait ms 20\nop DATA\nstart\nwait ms 20\n",
    )
    .unwrap();
    for machine in ["centre", "citizen"] {
        let state = d.join(format!("state-{machine}"));
        let lines = streamed(&[
            "script".as_ref(),
            script.as_os_str(),
            "--machine".as_ref(),
            machine.as_ref(),
            "--state".as_ref(),
            state.as_os_str(),
        ]);
        // A message goes on a line of its own: `TIME|message|NATIVE_CODE|TEXT`.
        let said: Vec<&str> = lines
            .iter()
            .filter_map(|l| l.split_once("|message|"))
            .filter_map(|(_, v)| v.split_once('|').map(|(_, text)| text))
            .collect();
        assert!(said.contains(&"feed override 70 %"), "{machine}: {said:?}");
        assert!(
            said.iter().any(|m| m.starts_with("START")),
            "{machine}: {said:?}"
        );
    }
}

/// A machine with a trunnion table (B and C) streams their angles (stop 54; before, the
/// adapter sent X Y Z only): `Bact`/`Cact` in the work system, `Bmach`/`Cmach` on the machine,
/// degrees, every key a DataItem id of the device file `novanc mtconnect-devices` makes for
/// that machine, where the table's C takes the letter and the spindle is `S`.
#[test]
fn a_trunnion_streams_its_table_s_angles_as_its_device_file_names_them() {
    let d = common::temp_dir("mtc-trunnion");
    let desc = d.join("trunnion.machine");
    std::fs::write(
        &desc,
        "machine trunnion\nkind mill\npulse 0.001\nx travel 0 1000 rapid 12000 accel 1000\ny travel 0 800 rapid 12000 accel 1000\nz travel -600 0 rapid 12000 accel 1000\nb rotary travel -120 120 rapid 9000 accel 800\nc rotary wrap rapid 9000 accel 800\n",
    )
    .unwrap();
    let out = common::novanc_command()
        .args(["mtconnect-devices", "--machine"])
        .arg(&desc)
        .output()
        .unwrap();
    assert!(out.status.success());
    let xml = String::from_utf8(out.stdout).unwrap();
    let ids: Vec<&str> = xml
        .split(" id=\"")
        .skip(1)
        .filter_map(|r| r.split('"').next())
        .collect();
    for id in ["Bact", "Bmach", "Cact", "Cmach", "Srpm", "Xact"] {
        assert!(ids.contains(&id), "{id} in\n{xml}");
    }
    assert!(!ids.contains(&"Aact") && xml.contains(r#"<Rotary id="s" name="S">"#));
    let script = d.join("turn.script");
    std::fs::write(
        &script,
        "op MDI\ntype G10 L2 P1 C30\nstart\nwait\ntype G54 G0 X10 B20 C15\nstart\nwait\n",
    )
    .unwrap();
    let state = d.join("state");
    let (port, child) = script_for_an_agent(
        &script,
        &[
            "--machine".as_ref(),
            desc.as_os_str(),
            "--state".as_ref(),
            state.as_os_str(),
        ],
    );
    let lines = read_all(connect(port));
    let out = child.wait_with_output().unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let last = |k: &str| values(&lines, k).last().cloned();
    assert_eq!(last("Bact").as_deref(), Some("20.000"), "{lines:?}");
    assert_eq!(last("Bmach").as_deref(), Some("20.000"));
    assert_eq!(last("Cact").as_deref(), Some("15.000"));
    assert_eq!(last("Cmach").as_deref(), Some("45.000"));
    assert_eq!(last("Xmach").as_deref(), Some("10.000"));
    // The work offset table has the table's axes too.
    let wpo = last("wpo").unwrap_or_default();
    assert!(
        wpo.starts_with("G54={X=0.000 Y=0.000 Z=0.000 B=0.000 C=30.000} G55={X=0.000"),
        "{wpo}"
    );
    // Every key of the data lines is one of the device file's ids (a condition's line, or a
    // message's, carries one key and its fields).
    for l in lines.iter().filter(|l| !l.starts_with('*')) {
        let f: Vec<&str> = l.split('|').collect();
        let key = f.get(1).copied().unwrap_or("");
        assert!(ids.contains(&key), "{key} of {l} is not in the device file");
    }
    let _ = std::fs::remove_dir_all(d);
}
