//! Fanuc 0i-T's G83 face drilling on the lathe's centre line (docs/lathe-gcode.md "G83 face
//! drilling"): the moves of a pecked and of a one-feed hole worked out by hand from each
//! program, not by the reader; every refusal at its line and column; a one-channel Fanuc
//! program with G83 run to its end by `novanc run --machine FILE`.

mod common;

use novanc::block::{Motion, Statement};
use novanc::lathe::desc::{parse, LatheDesc, MachineDesc};
use novanc::lathe::gcode::{read_program, ReadOptions};
use std::process::Command;

/// The machine's description: one channel, X travel 0..100 (radius), Z −100..100; tool 1 with
/// offsets X 2 (radius) Z −3, tool 2 (the drill) without; in `dialect`, with `more` lines in
/// the channel.
fn desc_text(dialect: &str, more: &str) -> String {
    format!(
        "machine shop\nkind lathe\npulse 0.001\ntick 100\ndialect {dialect}\nchannel PATH-1\n{more}\
         x travel 0 100 rapid 12000 accel 3000\nz travel -100 100 rapid 15000 accel 3000\n\
         spindle max 4000 accel 4000 encoder 1024\ntool 1 radius 0 tip 3 offset 2 -3\n\
         tool 2 radius 0 tip 3\n"
    )
}

fn lathe_with(dialect: &str, more: &str) -> LatheDesc {
    match parse(&desc_text(dialect, more)) {
        Ok(MachineDesc::Lathe(d)) => d,
        Ok(MachineDesc::Mill(_)) => panic!("a mill"),
        Err(e) => panic!("{e}"),
    }
}

fn lathe(dialect: &str) -> LatheDesc {
    lathe_with(dialect, "")
}

fn read(text: &str, desc: &LatheDesc) -> Result<Vec<Statement>, String> {
    read_program(text, desc, 0, &ReadOptions::default()).map_err(|e| e.to_string())
}

/// The moves and dwells in brief: R rapid, F feed, the block's end (X a radius, Z), mm; D and
/// the dwell in ms.
fn moves(p: &[Statement]) -> Vec<String> {
    p.iter()
        .flat_map(|s| &s.blocks)
        .filter_map(|b| {
            let k = match b.motion {
                Motion::Rapid => 'R',
                Motion::Linear => 'F',
                Motion::Dwell => return Some(format!("D {}", b.dwell_ns / 1_000_000)),
                _ => return None,
            };
            Some(format!(
                "{k} X{:.3} Z{:.3}",
                b.end[0] as f64 / 1000.0,
                b.end[2] as f64 / 1000.0
            ))
        })
        .collect()
}

fn ok(text: &str, desc: &LatheDesc) -> Vec<String> {
    match read(text, desc) {
        Ok(p) => moves(&p),
        Err(e) => panic!("{e}\n{text}"),
    }
}

/// The program's error, which must start with `at` (LINE:COL) and hold `why`.
fn refused(text: &str, desc: &LatheDesc, at: &str, why: &str) {
    match read(text, desc) {
        Ok(_) => panic!("read, where {at} '{why}' was expected:\n{text}"),
        Err(e) => assert!(
            e.starts_with(&format!("{at}: ")) && e.contains(why),
            "{e}\nexpected {at}: ..{why}..\n{text}"
        ),
    }
}

/// The set-up every program below starts with: the drill (tool 2, no offsets), the spindle
/// turning, feed per revolution.
const HEAD: &str = "G21 G40 G95\nT0202\nG97 S1000 M03\n";

#[test]
fn g83_pecks_by_q_backs_off_and_returns_to_the_initial_level() {
    let desc = lathe("fanuc");
    let p = format!("{HEAD}G0 X0 Z5.\nG83 Z-12. R-2. Q4000 P500 F0.1\nG80\nG0 X40. Z20.\nM30\n");
    // By hand. The tool stands at X0 Z5: the initial level is Z5. R-2 is the R level's
    // distance from it: Z3. Q4000 is 4.000 mm (least increments). The pecks go to 3 − 4 = −1,
    // −5, −9 (−13 would pass the bottom −12); after each the drill rapids back 0.254 mm
    // (0.010 inch, high-speed peck drilling), then feeds to the next. At the bottom −12 it
    // dwells P500 = 500 ms, then rapids back to the initial level Z5 (G98, the default).
    let want = [
        "R X0.000 Z5.000", // line 4, G0 X0 Z5.
        "R X0.000 Z3.000",
        "F X0.000 Z-1.000",
        "R X0.000 Z-0.746",
        "F X0.000 Z-5.000",
        "R X0.000 Z-4.746",
        "F X0.000 Z-9.000",
        "R X0.000 Z-8.746",
        "F X0.000 Z-12.000",
        "D 500",
        "R X0.000 Z5.000",
        "R X20.000 Z20.000", // line 7, after G80: G00 again.
    ];
    let got = ok(&p, &desc);
    assert_eq!(got, want, "{p}");
    // The moves are line 5's, at the column of G83.
    let prog = read(&p, &desc).unwrap();
    let s = prog
        .iter()
        .find(|s| s.line == 5)
        .expect("line 5 makes blocks");
    assert_eq!(s.blocks.len(), 10);
    // Each feed is per revolution at F0.1, the drill geared to nothing else.
    for b in s.blocks.iter().filter(|b| b.motion == Motion::Linear) {
        assert_eq!(b.feed_mode, novanc::block::FeedMode::PerRev);
        assert!((b.feed - 0.1).abs() < 1e-12, "{}", b.feed);
        assert!(b.thread.is_none());
    }
}

#[test]
fn g83_without_q_drills_in_one_feed_and_g99_returns_to_r_with_a_modal_repeat() {
    let desc = lathe("fanuc");
    let p = format!(
        "{HEAD}G0 X30. Z10.\nG99 G83 X0 W-15. R-3. F0.08\nZ-20.\nG80\nG98 G83 Z-25. R-1. F0.08\nG0 X40.\nM30\n"
    );
    // By hand. Line 5: the tool at X30 (radius 15) Z10, the initial level Z10. X0: a rapid
    // to the centre line at Z10, then to the R level 10 − 3 = Z7. W-15 is measured from the R
    // level: the bottom is 7 − 15 = Z−8. No Q: one feed to the bottom, no dwell, and G99
    // returns to the R level Z7. Line 6 (Z only, G83 modal): the same initial level and R,
    // the bottom Z−20: from Z7 (already on the R level) a feed to −20 and back to Z7. Line 7
    // cancels; line 8 begins a new series where the tool stands, Z7: R-1 is Z6, the bottom
    // −25, G98 back to the initial level Z7. Line 9: G00 again after G83 (a group 01 code
    // ends the cycle): X40 is a radius of 20 at Z7.
    let want = [
        "R X15.000 Z10.000",
        "R X0.000 Z10.000",
        "R X0.000 Z7.000",
        "F X0.000 Z-8.000",
        "R X0.000 Z7.000",
        "F X0.000 Z-20.000",
        "R X0.000 Z7.000",
        "R X0.000 Z6.000",
        "F X0.000 Z-25.000",
        "R X0.000 Z7.000",
        "R X20.000 Z7.000",
    ];
    assert_eq!(ok(&p, &desc), want, "{p}");
}

#[test]
fn g83_in_system_a_returns_to_the_initial_level_and_reads_g99_as_the_feed() {
    let desc = lathe_with("fanuc", "gcode system A\n");
    let p =
        "G21 G40 G99\nT0202\nG97 S1000 M03\nG0 X0 Z2.\nG83 Z-6. R-1. Q2500 F0.1\nZ-8.\nG80\nM30\n";
    // By hand. G99 is system A's feed per revolution. The initial level Z2, the R level Z1,
    // Q 2.5 mm: pecks at −1.5, −4 (−6.5 passes −6), each backing off 0.254; the bottom −6;
    // system A returns to the initial level Z2. Line 6 repeats with the bottom −8 from Z2:
    // rapid to Z1, pecks at −1.5, −4, −6.5 (−9 passes −8), the bottom −8, back to Z2.
    let want = [
        "R X0.000 Z2.000",
        "R X0.000 Z1.000",
        "F X0.000 Z-1.500",
        "R X0.000 Z-1.246",
        "F X0.000 Z-4.000",
        "R X0.000 Z-3.746",
        "F X0.000 Z-6.000",
        "R X0.000 Z2.000",
        "R X0.000 Z1.000",
        "F X0.000 Z-1.500",
        "R X0.000 Z-1.246",
        "F X0.000 Z-4.000",
        "R X0.000 Z-3.746",
        "F X0.000 Z-6.500",
        "R X0.000 Z-6.246",
        "F X0.000 Z-8.000",
        "R X0.000 Z2.000",
    ];
    assert_eq!(ok(p, &desc), want, "{p}");
    let prog = read(p, &desc).unwrap();
    assert!(prog
        .iter()
        .flat_map(|s| &s.blocks)
        .filter(|b| b.motion == Motion::Linear)
        .all(|b| b.feed_mode == novanc::block::FeedMode::PerRev));
}

#[test]
fn g83_refusals_name_their_line_column_and_reason() {
    let fanuc = lathe("fanuc");
    let at = |tail: &str| format!("{HEAD}G0 X0 Z5.\n{tail}");
    let cases: Vec<(String, &str, &str)> = vec![
        // Off the centre line: no live tooling.
        (
            at("G83 X20. Z-10. R-1. F0.1\n"),
            "5:5",
            "G83 at X20.000: the lathe drills on the centre line only (X0), it has no live tooling",
        ),
        (
            format!("{HEAD}G0 X12. Z5.\nG83 Z-10. R-1. F0.1\n"),
            "5:1",
            "G83 with the tool at X12.000: the lathe drills on the centre line only",
        ),
        (
            at("G83 U4. Z-10. R-1. F0.1\n"),
            "5:5",
            "G83 at X4.000",
        ),
        // P and Q without a decimal point.
        (
            at("G83 Z-10. R-1. Q2000 P0.5 F0.1\n"),
            "5:22",
            "G83 P, the dwell, is in milliseconds, without a decimal point",
        ),
        (
            at("G83 Z-10. R-1. Q2. F0.1\n"),
            "5:16",
            "G83 Q, the depth of each peck, is in least increments, without a decimal point",
        ),
        // Q 0, a negative Q, a P not whole.
        (
            at("G83 Z-10. R-1. Q0 F0.1\n"),
            "5:16",
            "G83 Q0: the depth of each peck must be above 0",
        ),
        (
            at("G83 Z-10. R-1. Q-1000 F0.1\n"),
            "5:16",
            "G83 Q-1000: the depth of each peck must be above 0",
        ),
        // The bottom not below the R level.
        (
            at("G83 Z5. R-2. F0.1\n"),
            "5:5",
            "G83: the bottom Z5.000 is not below the R level Z3.000",
        ),
        (
            at("G83 W2. R-2. F0.1\n"),
            "5:5",
            "the bottom Z5.000 is not below the R level Z3.000",
        ),
        (at("G83 R-2. F0.1\n"), "5:1", "G83 needs Z (or W, from the R level)"),
        // K repeats, other words.
        (
            at("G83 Z-10. R-1. K2 F0.1\n"),
            "5:16",
            "G83 K, the repeats, is not supported",
        ),
        (at("G83 Z-10. R-1. I1. F0.1\n"), "5:16", "G83 takes no I word"),
        // Compensation, a stopped spindle, no feed, one line with G01.
        (
            "G21 G40 G95\nT0202\nG97 S1000 M03\nG0 X0 Z5.\nG42\nG83 Z-10. R-1. F0.1\n".to_string(),
            "6:1",
            "G83 with nose-radius compensation in force: give G40 first",
        ),
        (
            "G21 G95\nT0202\nG0 X0 Z5.\nG83 Z-10. R-1. F0.1\n".to_string(),
            "4:1",
            "G83 with the spindle stopped",
        ),
        (
            at("G1 G83 Z-10. R-1. F0.1\n"),
            "5:4",
            "G83 and G01 on one line",
        ),
        // Under the mode: R without an end point, Q without one.
        (
            at("G83 Z-10. R-1. F0.1\nR-3.\n"),
            "6:1",
            "I, K or R without an X or Z end point",
        ),
        (
            at("G83 Z-10. R-1. F0.1\nQ1000\n"),
            "6:1",
            "the Q word is not used by anything on this line",
        ),
        // G98/G99 in system B out of G83's mode are still system A's feeds.
        (at("G99\n"), "5:1", "G98 and G99 are the feeds of Fanuc's G code system A"),
        (
            at("G83 Z-10. R-1. F0.1\nG80\nG98\n"),
            "7:1",
            "G98 and G99 are the feeds of Fanuc's G code system A",
        ),
        // G84 and the other drilling cycles.
        (
            at("G84 Z-10. R-1. F1.25\n"),
            "5:1",
            "G84 face tapping is not supported: the kernel reverses the spindle only between blocks",
        ),
        (
            at("G81 Z-10. R-1. F0.1\n"),
            "5:1",
            "the lathe's one drilling cycle is G83",
        ),
    ];
    for (p, at, why) in &cases {
        refused(p, &fanuc, at, why);
    }
    // LinuxCNC's dialect has no drilling cycle on the lathe (G98/G99 stay refused there).
    let lcnc = lathe("linuxcnc");
    refused(
        &at("G83 X0 Z-10. R-1. F0.1\n"),
        &lcnc,
        "5:1",
        "G83 is Fanuc's face drilling cycle; LinuxCNC has no drilling cycle on a lathe",
    );
    refused(
        &at("G99 G83 X0 Z-10. R-1. F0.1\n"),
        &lcnc,
        "5:1",
        "G98 and G99 are the feeds of Fanuc's G code system A",
    );
}

#[test]
fn a_fanuc_program_with_g83_runs_to_its_end() {
    let dir = common::temp_dir("lathe-drilling");
    let m = dir.join("shop.desc");
    std::fs::write(&m, desc_text("fanuc", "")).unwrap();
    // A bush: face, centre-drill-deep pecked hole, turn, part off (shapes of a shop program).
    let prog = dir.join("bush.nc");
    std::fs::write(
        &prog,
        "%\nO0100 (BUSH)\nG21 G40 G80 G95\nM10\nG28 U0 W0\n\
         T0101\nG96 S150 D3000 M03\nG0 X42. Z2. M08\nG1 Z0 F0.15\nX-1.6\nG0 Z2.\n\
         G28 U0 W0\nT0202\nG97 S1200 M03\nG0 X0 Z5.\n\
         G83 Z-30. R-2. Q6000 P200 F0.12\nZ-35.\nG80\n\
         G0 Z20. M09\nG28 U0 W0\nM30\n%\n",
    )
    .unwrap();
    let o = Command::new(env!("CARGO_BIN_EXE_novanc"))
        .args([
            "run",
            "--machine",
            m.to_str().unwrap(),
            prog.to_str().unwrap(),
            "--parts",
            "2",
        ])
        .output()
        .expect("novanc runs");
    let out = String::from_utf8_lossy(&o.stdout).into_owned();
    let err = String::from_utf8_lossy(&o.stderr).into_owned();
    assert_eq!(o.status.code(), Some(0), "{out}\n{err}");
    assert!(out.contains("parts: 2"), "{out}");
    assert!(out.contains("CH1 PATH-1:"), "{out}");
    assert!(out.contains(", parts 2"), "{out}");
}

#[test]
fn g83_stays_in_force_from_one_read_to_the_next_until_m30() {
    use novanc::lathe::gcode::{read_kept, Kept};
    let desc = lathe("fanuc");
    let opts = ReadOptions::default();
    let kept = Kept::power_on(&desc, 0, None);
    let first = format!("{HEAD}G0 X0 Z5.\nG83 Z-10. R-2. F0.1\n");
    let r = read_kept(&first, &desc, 0, &opts, None, &kept, None).unwrap_or_else(|e| panic!("{e}"));
    assert!(
        r.kept.modal.drill.is_some(),
        "G83 is modal, as an MDI line leaves it"
    );
    // The next read (an MDI line) starts where the last left the tool, on Z5, and `Z-12.`
    // repeats the cycle: initial level Z5, R level Z3, one feed to −12, back to Z5.
    let at = Some([0, 5000]);
    let spin = "M03\nZ-12.\n";
    let r2 = read_kept(spin, &desc, 0, &opts, None, &r.kept, at).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(
        moves(&r2.statements),
        ["R X0.000 Z3.000", "F X0.000 Z-12.000", "R X0.000 Z5.000"]
    );
    // M30 resets the cycle: the next program's `Z-12.` is a G00 move.
    let r3 = read_kept(
        "G80\nM03\nG83 Z-10. R-2. F0.1\nM30\n",
        &desc,
        0,
        &opts,
        None,
        &r2.kept,
        at,
    )
    .unwrap_or_else(|e| panic!("{e}"));
    assert!(r3.kept.modal.drill.is_none());
    let r4 = read_kept(spin, &desc, 0, &opts, None, &r3.kept, at).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(moves(&r4.statements), ["R X0.000 Z-12.000"]);
}

#[test]
fn g83_under_g20_reads_q_in_ten_thousandths_and_r_from_the_initial_level() {
    let desc = lathe("fanuc");
    // A Haas-styled line (R the plane's position, Q with a point) is refused at Q, in inch
    // terms; Fanuc's form of it reads.
    refused(
        "G20 G40 G95\nT0202\nG97 S1000 M03\nG0 X0 Z0.2\nG83 X0 Z-1.3 R.1 Q0.3125 F.006\n",
        &desc,
        "5:18",
        "(Q1000 is 0.1000 inch under G20)",
    );
    let p = "G20 G40 G95\nT0202\nG97 S1000 M03\nG0 X0 Z0.2\nG83 X0 Z-1.3 R-.1 Q5000 F.006\nG80\n";
    // By hand, in mm: the initial level 0.2 in = Z5.08, R-.1 in = −2.54: the R level Z2.54;
    // Q5000 = 0.5 in = 12.7 mm: pecks at 2.54 − 12.7 = −10.16 and −22.86 (−35.56 passes the
    // bottom −1.3 in = −33.02), each backing off 0.254; the bottom −33.02; back to Z5.08.
    let want = [
        "R X0.000 Z5.080",
        "R X0.000 Z2.540",
        "F X0.000 Z-10.160",
        "R X0.000 Z-9.906",
        "F X0.000 Z-22.860",
        "R X0.000 Z-22.606",
        "F X0.000 Z-33.020",
        "R X0.000 Z5.080",
    ];
    assert_eq!(ok(p, &desc), want, "{p}");
}

#[test]
fn a_program_reads_g83_and_its_return_level_as_fanucs_modal_information() {
    let desc = lathe("fanuc");
    // #4010 is group 10 (G80 or G83), #4011 group 11 (G98 or G99): a macro that checks them
    // passes the alarms only when both are what the lines before set.
    let p = format!(
        "{HEAD}G0 X0 Z5.\nIF [#4010 NE 80] GOTO 90\nG99 G83 Z-10. R-2. F0.1\n\
         IF [#4010 NE 83] GOTO 90\nIF [#4011 NE 99] GOTO 90\nG80\nIF [#4010 NE 80] GOTO 90\n\
         M30\nN90 #3000 = 1 (MODAL INFORMATION WRONG)\n"
    );
    let got = ok(&p, &desc);
    assert_eq!(got.len(), 4, "{got:?}");
}
