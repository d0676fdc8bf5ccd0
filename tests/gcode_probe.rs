//! G38.2–G38.5 against the workpiece of the machine's settings where no pulse core runs
//! (docs/gcode.md "Probing"): `novanc translate` of a touch-off, the probe results #5061–#5070,
//! the stylus of the tool in the spindle, the errors, and LinuxCNC's probing examples read
//! through.

use novanc::gcode::{Event, GcodeSource};

mod common;

/// `src` from machine zero with no offsets, the sample magazine and the default settings.
fn source(src: &str) -> GcodeSource {
    common::gcode_source(src)
}

/// `src` read from machine zero with no offsets: its statements (or first error) and the
/// state after it.
fn read(src: &str) -> (Result<usize, String>, GcodeSource) {
    let mut g = source(src);
    let mut n = 0;
    for r in g.by_ref() {
        match r {
            Ok(_) => n += 1,
            Err(e) => return (Err(e.to_string()), g),
        }
    }
    (Ok(n), g)
}

fn param(g: &GcodeSource, n: usize) -> f64 {
    g.state().params[n]
}

fn near(got: f64, want: f64) {
    assert!((got - want).abs() < 1e-6, "{got} vs {want}");
}

/// A touch-off on the default workpiece (X 300..700, Y 200..600, Z −550..−450, machine mm)
/// with no tool (a point stylus at the gauge line), G54 at machine zero: down onto the top,
/// set Z0 there, then find the X− face from the side and set X0 there; the moves after it use
/// the new zero and #5063 (the second probe's Z in G54).
const TOUCH_OFF: &str = "G21 G90 G17 G40 G49 G80\n\
     G10 L2 P1 X0 Y0 Z0\n\
     G54 G0 X500 Y400 Z-400\n\
     G38.2 Z-480 F100\n\
     G10 L20 P1 Z0\n\
     G0 Z10\n\
     G0 X280\n\
     G0 Z-10\n\
     G38.2 X320 F500\n\
     G10 L20 P1 X0\n\
     G0 X-5 Z#5063\n\
     G1 X20 F200\n\
     M30\n";

/// `novanc translate` of [`TOUCH_OFF`], answered from the workpiece.
#[test]
fn translate_touches_off_on_the_default_workpiece() {
    let (code, text, stderr, _) = common::novanc_on(&["translate"], "touch.ngc", TOUCH_OFF, &[]);
    assert_eq!(code, Some(0), "{stderr}");
    // The top is at machine Z −450: G54 Z0 there, so Z10 is −440 and Z−10 is −460 (beside
    // the block, X 280 < 300). The X− face is at machine X 300: X0 there, X−5 is 295; the
    // second probe stopped at Z −10 in G54, so Z#5063 is machine −460 again.
    assert_eq!(
        text,
        "G21 G90 G17 G94 G40 G49 G80\n\
         N1 G00 X500.000 Y400.000 Z-400.000\n\
         N2 G38.2 Z-480.000 F100\n\
         N3 G00 Z-440.000\n\
         N4 G00 X280.000\n\
         N5 G00 Z-460.000\n\
         N6 G38.2 X320.000 F500\n\
         N7 G00 X295.000\n\
         N8 G01 X320.000 F200\n\
         N9 M30\n"
    );
}

/// The results in the program's coordinates (G54 at X100 Y100 Z−400), #5070 set, and an
/// event for each probe; G38.3 that misses is no error and leaves #5070 at 0.
#[test]
fn results_are_in_program_coordinates_and_g38_3_may_miss() {
    let (r, mut g) = read(
        "G21 G90 G10 L2 P1 X100 Y100 Z-400\n\
         G0 X400 Y300 Z0\n\
         G38.2 Z-100 F100\n\
         #100=#5061 #101=#5062 #102=#5063 #103=#5070\n\
         G0 Z0\n\
         G0 X700 Y300\n\
         G38.3 Z-20 F100\n\
         M30\n",
    );
    assert!(r.is_ok(), "{r:?}");
    near(param(&g, 100), 400.0);
    near(param(&g, 101), 300.0);
    // The top, machine −450, is Z −50 in G54.
    near(param(&g, 102), -50.0);
    near(param(&g, 103), 1.0);
    // X700 Y300 in G54 is machine X800: beside the block.
    near(param(&g, 5070), 0.0);
    near(param(&g, 5063), -20.0);
    let probes: Vec<_> = g
        .take_events()
        .into_iter()
        .filter(|e| matches!(e, Event::Probe { .. }))
        .collect();
    assert_eq!(
        probes,
        vec![
            Event::Probe {
                at: [400.0, 300.0, -50.0],
                tripped: true
            },
            Event::Probe {
                at: [700.0, 300.0, -20.0],
                tripped: false
            }
        ]
    );
}

/// With T1 (tool 610: diameter 40, length 220) and G43, the stylus is a ball of radius 20
/// centred on the tip 220 below the gauge line: it meets the top (machine −450) with the
/// tip at −430, the gauge line at −210; #5063 is the tip's Z, −430.
#[test]
fn the_stylus_is_the_tool_in_the_spindle() {
    let (r, g) = read("G21 G90\nT1 M6\nG43\nG0 X500 Y400 Z-300\nG38.2 Z-480 F100\nM30\n");
    assert!(r.is_ok(), "{r:?}");
    near(param(&g, 5063), -430.0);
    near(g.state().pos[2], -210.0);
}

/// G38.4 finds where the stylus comes free: from inside the block up, free at the top.
#[test]
fn g38_4_finds_where_contact_is_lost() {
    // #5070 may be set by a program, as in LinuxCNC (smartprobe.ngc loops on it).
    let (r, g) =
        read("G21 G90\n#5070=7\nG0 X500 Y400 Z-400\nG1 Z-460 F100\nG38.4 Z-420 F50\nM30\n");
    assert!(r.is_ok(), "{r:?}");
    near(param(&g, 5063), -450.0);
    near(param(&g, 5070), 1.0);
}

/// A G38.2 that misses, a G38.2 already in contact and a G38.4 already clear are errors at
/// the G code, after the probe line's move and before anything after it.
#[test]
fn a_probe_that_cannot_do_its_work_is_an_error() {
    let miss = "G21 G90\nG0 X100 Y100 Z-400\nG38.2 Z-480 F100\nG0 Z-300\nM30\n";
    assert_eq!(
        read(miss).0,
        Err("3:1: G38.2: the probe move ended without contact".into())
    );
    let inside = "G21 G90\nG0 X500 Y400 Z-400\nG1 Z-460 F100\nG38.2 Z-480 F100\nM30\n";
    assert_eq!(
        read(inside).0,
        Err("4:1: G38.2: the probe is already tripped at the start of the move".into())
    );
    let clear = "G21 G90\nG0 X500 Y400 Z-400\nG38.4 Z-480 F100\nM30\n";
    assert_eq!(
        read(clear).0,
        Err("3:1: G38.4: the probe is already clear at the start of the move".into())
    );
    // G38.3 and G38.5 are not errors in those cases.
    let (r, g) = read("G21 G90\nG0 X100 Y100 Z-400\nG38.3 Z-480 F100\nG0 Z-300\nM30\n");
    assert!(r.is_ok(), "{r:?}");
    near(param(&g, 5070), 0.0);
}

/// A SEARCH point after a probe: the lines before it take their probe results from the
/// workpiece, so the work offset set from #5063 is the one a full run sets.
#[test]
fn search_past_a_probe_keeps_its_result() {
    let src = "G21 G90\nG0 X500 Y400 Z-400\nG38.2 Z-480 F100\nG10 L20 P1 Z0\nG0 Z10\nM30\n";
    let mut g = source(src).resume_at(5);
    for r in g.by_ref() {
        r.unwrap();
    }
    near(g.offsets().0[0][2], -450.0);
}

/// LinuxCNC's probing examples, with G54 put on the default workpiece's top (the corpus's
/// "pass B" offsets in X and Y): read through to their end. Skipped when the corpus is absent.
/// (smartprobe.ngc is left out: its first G38.5 starts at its end point, which rs274 refuses
/// too, "Start point too close to probe point".)
#[test]
fn linuxcnc_probing_examples_read_through() {
    let base = std::path::Path::new("/work/corpus/lcnc/nc_files");
    if !base.exists() {
        eprintln!("SKIPPED: no corpus at {}", base.display());
        return;
    }
    for name in [
        "gridprobe.ngc",
        "probe/gtk_probe/gtk_probe_down.ngc",
        "probe/gtk_probe/gtk_probe_xplus.ngc",
        "probe/gtk_probe/gtk_probe_yminus.ngc",
    ] {
        let text = std::fs::read_to_string(base.join(name)).unwrap();
        let src = format!("G10 L2 P1 X508 Y406.4 Z-450\n{text}");
        let (r, _) = read(&src);
        assert!(r.is_ok(), "{name}: {r:?}");
    }
}

/// M66 where no pulse core runs: every input is low, so L0 and L4 read 0 at once and a wait
/// for a rise, a fall or high times out: #5399 is −1 (LinuxCNC's timeout value). The value
/// is there for the next line, not the M66 line's own assignments.
#[test]
fn m66_reads_the_simulated_inputs_low() {
    let (r, g) = read(
        "G21 G90\n#5399=9\nM66 P3 L0\n#1=#5399\nM66 E1 L0\n#2=#5399\n\
         M66 P3 L4 Q1\n#3=#5399\nM66 P3 L3 Q0.5\n#4=#5399\nM30\n",
    );
    assert!(r.is_ok(), "{r:?}");
    near(param(&g, 1), 0.0);
    near(param(&g, 2), 0.0);
    near(param(&g, 3), 0.0);
    near(param(&g, 4), -1.0);
}

/// `novanc run` of [`TOUCH_OFF`]: the pulse core stops each probe move where the point stylus
/// meets the workpiece (the top at machine Z −450, the X− face at X 300), reading waits for
/// its answer, and the program goes on from there: `G0 X-5 Z#5063` goes to machine X 295,
/// Z −460, then X20 is machine 320. The pulses count the moves as the core made them:
/// X 500 + 220 + 20 + 5 + 25, Z 400 + 50 + 10 + 20.
#[test]
fn a_run_stops_the_probe_on_the_workpiece_and_reads_on_from_the_answer() {
    let (code, text, stderr, _) = common::novanc_on(&["run"], "run.ngc", TOUCH_OFF, &[]);
    assert_eq!(code, Some(0), "{stderr}");
    assert!(
        text.contains("pulses: X 770000 Y 400000 Z 480000"),
        "{text}"
    );
    assert!(
        text.contains("final position: X 320.000 Y 400.000 Z -460.000 mm"),
        "{text}"
    );
}

/// A probe that misses in a run: the probe move is made to its end, then the run stops with
/// the error and nothing after it moves.
#[test]
fn a_run_whose_probe_misses_stops_after_the_probe_move() {
    let (code, stdout, stderr, _) = common::novanc_on(
        &["run"],
        "miss.ngc",
        "G21 G90\nG0 X100 Y100 Z-400\nG38.2 Z-480 F500\nG0 Z-300\nM30\n",
        &[],
    );
    let text = stdout;
    assert_eq!(code, Some(1));
    assert!(
        stderr.contains("miss.ngc:3:1: G38.2: the probe move ended without contact"),
        "{stderr}"
    );
    assert!(text.contains("blocks executed: 2"), "{text}");
    assert!(
        text.contains("final position: X 100.000 Y 100.000 Z -480.000 mm"),
        "{text}"
    );
}

/// RESET while reading waits for a probe's answer: SINGLE BLOCK stops the run after the
/// rapid before the probe (the translator has handed on the probe block and waits for the
/// machine); RESET abandons the run, the wait ends, and the next run of the program goes
/// through to its end (no hang).
#[test]
fn reset_during_a_probe_wait_abandons_the_run_without_a_hang() {
    let mut c = common::open("probe-reset");
    let f = common::temp_dir("probe-reset-prog").join("touch.ngc");
    std::fs::write(
        &f,
        "G21 G90\nG0 X500 Y400 Z-400\nG38.2 Z-480 F100\nG0 Z#5063\nM30\n",
    )
    .unwrap();
    common::read_program(&mut c, f);
    common::one_block_reset_then_run(&mut c);
    let ends: Vec<[i64; 3]> = common::audit(&c).iter().map(|e| e.end.xyz()).collect();
    // The second run starts where the first stopped (its rapid makes no block): the probe
    // stops on the top (machine Z −450), `G0 Z#5063` stays there, then M30.
    let top = [500_000, 400_000, -450_000];
    assert_eq!(&ends[ends.len() - 2..], &[top, top][..], "{ends:?}");
    // The first run's translator thread, abandoned while it waited, has ended too (the only
    // console of this test binary; the other tests make no translator thread in process).
    let translators = || {
        std::fs::read_dir("/proc/self/task")
            .map(|d| {
                d.filter_map(|t| std::fs::read_to_string(t.ok()?.path().join("comm")).ok())
                    .filter(|n| n.trim() == "translator")
                    .count()
            })
            .unwrap_or(0)
    };
    let t0 = std::time::Instant::now();
    while translators() > 0 && t0.elapsed() < std::time::Duration::from_secs(3) {
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    assert_eq!(translators(), 0, "a translator thread is still waiting");
}

/// The probe result on the recording: `/nc/probe` after the probe block's `/nc/block`, with
/// where the machine stopped (the top, machine Z −450) and `tripped`; the file passes the
/// Python reader's check with the new topic.
#[test]
fn a_run_records_the_probe_result() {
    let (code, stdout, stderr, dir) = common::novanc_on(
        &["run"],
        "rec.ngc",
        "G21 G90\nG0 X500 Y400 Z-400\nG38.2 Z-480 F100\nG0 Z-300\nM30\n",
        &["--record", "rec.mcap"],
    );
    assert_eq!(code, Some(0), "{stderr} {stdout}");
    let rec = dir.join("rec.mcap");
    let bytes = std::fs::read(&rec).unwrap();
    let mut seen = Vec::new();
    for m in mcap::MessageStream::new(&bytes).unwrap() {
        let m = m.unwrap();
        let topic = m.channel.topic.clone();
        if topic == "/nc/block" || topic == "/nc/probe" {
            seen.push((topic, String::from_utf8(m.data.to_vec()).unwrap()));
        }
    }
    let i = seen
        .iter()
        .position(|(t, _)| t == "/nc/probe")
        .unwrap_or_else(|| panic!("no /nc/probe message: {seen:?}"));
    assert_eq!(
        seen[i].1,
        r#"{"seq":2,"stmt":3,"x":500,"y":400,"z":-450,"pulses":[500000,400000,-450000],"tripped":true,"at_start":false}"#
    );
    assert!(seen[i - 1].1.contains("G38.2"), "{seen:?}");
    assert!(seen[i + 1].1.contains("G00 Z-300"), "{seen:?}");
    if let Some((ok, text)) = common::python_check(&rec, &["--expect-topics", "/nc/probe"]) {
        assert!(ok, "{text}");
    }
}

/// The stock comes from the machine description: `machines/centre.machine` gives the
/// defaults, a `--machine` file with its stock 50 mm higher stops the same probe 50 mm higher,
/// and one without `workpiece` lines has no stock (the probe ends without contact).
#[test]
fn the_machine_description_gives_the_workpiece() {
    let prog = "G21 G90 G49\nG0 X500 Y400 Z-300\nG38.2 Z-500 F100\nG0 Z[#5063 + 10]\nM2\n";
    let centre = include_str!("../machines/centre.machine");
    let stock = "workpiece box 300 200 -550 700 600 -450";
    assert!(centre.contains(stock));
    let d = common::temp_dir("probe-machine");
    let higher = d.join("higher.machine");
    std::fs::write(
        &higher,
        centre.replace(stock, "workpiece box 300 200 -550 700 600 -400"),
    )
    .unwrap();
    let bare = d.join("bare.machine");
    std::fs::write(&bare, centre.replace(stock, "")).unwrap();
    for (machine, want) in [
        (None, "N3 G00 Z-440.000"),
        (Some(&higher), "N3 G00 Z-390.000"),
        (
            Some(&bare),
            "3:1: G38.2: the probe move ended without contact",
        ),
    ] {
        let m = machine.map(|p| p.to_string_lossy().into_owned());
        let extra: Vec<&str> = match &m {
            Some(p) => vec!["--machine", p.as_str()],
            None => vec![],
        };
        let (_, out, err, _) = common::novanc_on(&["translate"], "probe.ngc", prog, &extra);
        assert!(
            out.contains(want) || err.contains(want),
            "{machine:?}: {out}{err}"
        );
    }
}
