//! Fanuc 0i-T's G83 face drilling and G84 face tapping on the lathe's centre line
//! (docs/lathe-gcode.md "G83 face drilling", "G84 face tapping"): the moves of a pecked and of
//! a one-feed hole, and a tap's blocks with their tap marks and spindle codes, worked out by
//! hand from each program, not by the reader; a tap run on the kernel at feed override 50 %
//! taking the time it takes at 100 %; every refusal at its line and column; one-channel Fanuc
//! programs with G83 and G84 run to their end by `novanc run --machine FILE`.

mod common;

use novanc::block::{Motion, Statement};
use novanc::lathe::desc::{parse, LatheDesc, MachineDesc};
use novanc::lathe::gcode::ReadOptions;

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

#[path = "common/lathe_moves.rs"]
mod lathe_moves;
use lathe_moves::read;

/// The moves and dwells in brief.
fn ok(text: &str, desc: &LatheDesc) -> Vec<String> {
    lathe_moves::ok(text, desc, true)
}

fn moves(p: &[Statement]) -> Vec<String> {
    lathe_moves::moves(p, true)
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
    let cases: Vec<(String, &str, &str)> =
        vec![
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
        // The other drilling cycles (G84's refusals: `g84_refusals_...` below).
        (
            at("G81 Z-10. R-1. F0.1\n"),
            "5:1",
            "the lathe's drilling cycles are G83 and G84",
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

/// `novanc run --machine M PROG --parts 2` delivers its 2 parts, exit 0.
fn runs_two_parts(m: &std::path::Path, prog: &std::path::Path) {
    let o = common::novanc_command()
        .args(["run", "--machine"])
        .arg(m)
        .arg(prog)
        .args(["--parts", "2"])
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
    runs_two_parts(&m, &prog);
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

/// Line `line`'s blocks in brief, each with its tap mark: R rapid and F feed to the end (X a
/// radius, Z, mm; a feed with its rate and mode), D a dwell (ms), M a spindle code with its S.
fn tap_blocks(p: &[Statement], line: u32) -> Vec<String> {
    use novanc::block::FeedMode;
    p.iter()
        .filter(|s| s.line == line)
        .flat_map(|s| &s.blocks)
        .map(|b| {
            let at = format!(
                "X{:.3} Z{:.3}",
                b.end[0] as f64 / 1000.0,
                b.end[2] as f64 / 1000.0
            );
            let what = match b.motion {
                Motion::Rapid => format!("R {at}"),
                Motion::Linear => format!(
                    "F {at} {}{}",
                    b.feed,
                    if b.feed_mode == FeedMode::PerMin {
                        "/min"
                    } else {
                        "/rev"
                    }
                ),
                Motion::Dwell => format!("D {}", b.dwell_ns / 1_000_000),
                _ => format!("M{} S{}", b.m.unwrap_or(0), b.s.unwrap_or(0)),
            };
            format!("{what} {:?}", b.tap)
        })
        .collect()
}

/// The tap's set-up: the tap (tool 2), the spindle forward at 500 rpm, feed per revolution.
const TAP_HEAD: &str = "G21 G40 G95\nT0202\nG97 S500 M03\n";

#[test]
fn g84_taps_with_the_mills_blocks_and_marks_and_returns_to_the_initial_level() {
    let desc = lathe("fanuc");
    let p = format!("{TAP_HEAD}G0 X0 Z5.\nG84 Z-15. R-2. P300 F1.25\nG80\nG0 X40. Z20.\nM30\n");
    // By hand. The tap stands at X0 Z5: the initial level Z5, the R level 5 − 2 = Z3, the
    // bottom Z−15. F1.25 under G95 is the lead, 1.25 mm a revolution: at S500 the tap feeds
    // 1.25 × 500 = 625 mm/min, carried per minute as the mill's G84 carries it (the pulse
    // core gears it to the spindle: 625 / 500 = 1.25 mm/rev). The mill's order and marks
    // (`gcode/cycles.rs`, `74 | 84`): Part from the feed in to the M05 out of the hole, End on
    // the M03 (the spindle forward again, the tap out at R); the rapid back to the initial
    // level (G98, the default) is no longer the tap's. P300: a 300 ms dwell after the reversal.
    let want = [
        "R X0.000 Z3.000 No",
        "F X0.000 Z-15.000 625/min Part",
        "M5 S500 Part",
        "M4 S500 Part",
        "D 300 Part",
        "F X0.000 Z3.000 625/min Part",
        "M5 S500 Part",
        "M3 S500 End",
        "R X0.000 Z5.000 No",
    ];
    let prog = read(&p, &desc).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(tap_blocks(&prog, 5), want, "{p}");
    // No block before or after the tap is marked.
    let marked: Vec<u32> = prog
        .iter()
        .flat_map(|s| &s.blocks)
        .filter(|b| b.tap != novanc::block::Tap::No)
        .map(|b| b.stmt)
        .collect();
    assert_eq!(marked, [5; 7]);
}

#[test]
fn g84_g99_returns_to_r_repeats_under_its_mode_and_reads_a_feed_per_minute_as_f_over_s() {
    let desc = lathe("fanuc");
    let p = format!(
        "{TAP_HEAD}G0 X30. Z10.\nG99 G84 X0 W-10. R-3. F1.5\nIF [#4010 NE 84] GOTO 90\nZ-6.\nG80\n\
         G94 F750\nG98 G84 Z-4. R-1.\nG80\nM30\nN90 #3000 = 1 (NOT G84)\n"
    );
    // By hand. Line 5: the tool at X30 (radius 15) Z10: a rapid to X0 at Z10, to the R level
    // 10 − 3 = Z7; W-10 from it: the bottom Z−3. F1.5 at S500: 750 mm/min. G99: the tap ends
    // out at R (the feed out goes there), no rapid after it. #4010 reads 84 (group 10). Line
    // 7 repeats under the mode, the bottom Z−6, from Z7 already at R. Line 8 cancels; line 9
    // sets feed per minute, F750: the lead is F / S = 1.5 mm, the same 750 mm/min. Line 10 a
    // new series from Z7: R-1 is Z6, the bottom Z−4, G98 back to Z7.
    let tap = |bottom: &str, r: &str| {
        vec![
            format!("F X0.000 Z{bottom} 750/min Part"),
            "M5 S500 Part".to_string(),
            "M4 S500 Part".to_string(),
            format!("F X0.000 Z{r} 750/min Part"),
            "M5 S500 Part".to_string(),
            "M3 S500 End".to_string(),
        ]
    };
    let prog = read(&p, &desc).unwrap_or_else(|e| panic!("{e}"));
    let mut want5 = vec!["R X15.000 Z10.000 No".to_string()];
    want5.extend([
        "R X0.000 Z10.000 No".to_string(),
        "R X0.000 Z7.000 No".to_string(),
    ]);
    want5.extend(tap("-3.000", "7.000"));
    assert_eq!(tap_blocks(&prog, 4).len(), 1);
    assert_eq!(tap_blocks(&prog, 5), want5[1..], "{p}");
    assert_eq!(tap_blocks(&prog, 7), tap("-6.000", "7.000"), "{p}");
    let mut want10 = vec!["R X0.000 Z6.000 No".to_string()];
    want10.extend(tap("-4.000", "6.000"));
    want10.push("R X0.000 Z7.000 No".to_string());
    assert_eq!(tap_blocks(&prog, 10), want10, "{p}");
}

#[test]
fn g84_refusals_name_their_line_column_and_reason() {
    let fanuc = lathe("fanuc");
    let at = |tail: &str| format!("{TAP_HEAD}G0 X0 Z5.\n{tail}");
    let cases: Vec<(String, &str, &str)> = vec![
        // The spindle: forward only (a right-hand tap), the mill's words; stopped; G96; no S.
        (
            "G21 G40 G95\nT0202\nG97 S500 M04\nG0 X0 Z5.\nG84 Z-10. R-1. F1.25\n".to_string(),
            "5:1",
            "G84 with the spindle turning backward (M04): right-hand tapping needs M03",
        ),
        (
            "G21 G40 G95\nT0202\nG97 S500\nG0 X0 Z5.\nG84 Z-10. R-1. F1.25\n".to_string(),
            "5:1",
            "G84 needs the spindle turning forward: give M03 first",
        ),
        (
            "G21 G40 G95\nT0202\nG96 S100 M03\nG0 X0 Z5.\nG84 Z-10. R-1. F1.25\n".to_string(),
            "5:1",
            "G84 under G96 (constant surface speed): the tap is geared to a fixed speed, give G97 S",
        ),
        (
            "G21 G40 G95\nT0202\nG97 M03\nG0 X0 Z5.\nG84 Z-10. R-1. F1.25\n".to_string(),
            "5:1",
            "G84 needs the spindle speed: give G97 S",
        ),
        // Off the centre line, the bottom not below R, no bottom.
        (
            at("G84 X20. Z-10. R-1. F1.25\n"),
            "5:5",
            "G84 at X20.000: the lathe taps on the centre line only (X0), it has no live tooling to tap off the centre",
        ),
        (
            format!("{TAP_HEAD}G0 X12. Z5.\nG84 Z-10. R-1. F1.25\n"),
            "5:1",
            "G84 with the tool at X12.000: the lathe taps on the centre line only",
        ),
        (
            at("G84 Z5. R-2. F1.25\n"),
            "5:5",
            "G84: the bottom Z5.000 is not below the R level Z3.000 (the initial level Z5.000 and R-2.000): the tap feeds towards -Z",
        ),
        (at("G84 R-2. F1.25\n"), "5:1", "G84 needs Z (or W, from the R level)"),
        // Words: Q (peck tapping), K, others; P with a point; no feed.
        (
            at("G84 Z-10. R-1. Q1000 F1.25\n"),
            "5:16",
            "G84 Q, peck tapping, is not supported",
        ),
        (
            at("G84 Z-10. R-1. K2 F1.25\n"),
            "5:16",
            "G84 K, the repeats, is not supported: the tap stands on the centre line",
        ),
        (at("G84 Z-10. R-1. J1. F1.25\n"), "5:16", "G84 takes no J word"),
        (
            at("G84 Z-10. R-1. P0.5 F1.25\n"),
            "5:16",
            "G84 P, the dwell, is in milliseconds, without a decimal point",
        ),
        (
            "G21 G40 G95\nT0202\nG97 S500 M03\nG0 X0 Z5.\nG84 Z-10. R-1.\n".to_string(),
            "5:1",
            "a feed move without a feed: give F",
        ),
        // Compensation, a group 01 code on the line, and the cycle ended by G80 and by G01.
        (
            format!("{TAP_HEAD}G0 X0 Z5.\nG42\nG84 Z-10. R-1. F1.25\n"),
            "6:1",
            "G84 with nose-radius compensation in force: give G40 first",
        ),
        (
            at("G1 G84 Z-10. R-1. F1.25\n"),
            "5:4",
            "G84 and G01 on one line",
        ),
        (
            at("G84 Z-10. R-1. F1.25\nG80\nR-3.\n"),
            "7:1",
            "I, K or R without an X or Z end point",
        ),
        (
            at("G84 Z-10. R-1. F1.25\nG1 Z4.\nR-3.\n"),
            "7:1",
            "I, K or R without an X or Z end point",
        ),
    ];
    for (p, at, why) in &cases {
        refused(p, &fanuc, at, why);
    }
    refused(
        &at("G84 X0 Z-10. R-1. F1.25\n"),
        &lathe("linuxcnc"),
        "5:1",
        "G84 is Fanuc's face tapping cycle; LinuxCNC has no drilling cycle on a lathe",
    );
}

/// A kernel of one channel running `prog` at feed override `pct`, started, the tool at home.
fn started(desc: &LatheDesc, prog: &[Statement], pct: u32) -> novanc::pulse_core::Kernel {
    use novanc::pulse_core::{Command, Kernel};
    let (chans, flow) = desc
        .kernel_channels(vec![prog.to_vec()])
        .expect("the program fits the machine");
    let mut k = Kernel::new(chans, Some(flow), 1).expect("a kernel");
    let h = novanc::lathe::gcode::home(desc, 0);
    k.set_position(0, [h[0], 0, h[1]]).expect("at rest");
    k.command(0, Command::Override(pct)).expect("override");
    k.start(None).expect("START");
    k
}

/// The start times (machine ns) of blocks `seqs` of a one-channel lathe's program at feed
/// override `pct`, read on the kernel (`run_until` stops at each start).
fn block_starts(desc: &LatheDesc, prog: &[Statement], pct: u32, seqs: &[u32]) -> Vec<u64> {
    use novanc::pulse_core::Outcome;
    let mut k = started(desc, prog, pct);
    seqs.iter()
        .map(|&seq| match k.run_until(600_000_000_000, Some((0, seq))) {
            Outcome::BlockStart { t, .. } => t,
            o => panic!("block N{seq} did not start: {o:?}"),
        })
        .collect()
}

#[test]
fn a_tap_holds_the_feed_override_at_100_percent_on_a_one_channel_lathe() {
    let desc = lathe("fanuc");
    // A feed of 1 mm at 0.1 mm/rev and 500 rpm (50 mm/min, 1.2 s at 100 %), then a tap of
    // 12 mm (the initial level Z4, R Z2, the bottom Z−10) at 1.25 mm/rev: 625 mm/min, 1.152 s
    // in and as long out.
    // M10 first: the kernel turns nothing without a work in the chuck (the bar feeder's).
    let p =
        format!("M10\n{TAP_HEAD}G0 X0 Z5.\nG1 Z4. F0.1\nG84 Z-10. R-2. F1.25\nG80\nG0 Z20.\nM30\n");
    let prog = read(&p, &desc).unwrap_or_else(|e| panic!("{e}"));
    let seq = |line: u32, i: usize| {
        prog.iter()
            .find(|s| s.line == line)
            .map(|s| s.blocks[i].seq)
            .expect("the line makes blocks")
    };
    // The G01 and the block after it; the tap's feed in (line 7, after the rapid to R), the
    // M05 after it, its feed out and the M05 after that.
    let seqs = [
        seq(6, 0),
        seq(7, 0),
        seq(7, 1),
        seq(7, 2),
        seq(7, 4),
        seq(7, 5),
    ];
    let full = block_starts(&desc, &prog, 100, &seqs);
    let half = block_starts(&desc, &prog, 50, &seqs);
    let secs = |t: &[u64], i: usize| (t[i + 1] - t[i]) as f64 / 1e9;
    // Outside the tap the override acts: the G01 takes twice as long at 50 %.
    let (g1_full, g1_half) = (secs(&full, 0), secs(&half, 0));
    assert!((g1_full - 1.2).abs() < 0.05, "G01 at 100 %: {g1_full} s");
    assert!(
        (g1_half / g1_full - 2.0).abs() < 0.05,
        "G01 at 50 %: {g1_half} s, at 100 %: {g1_full} s"
    );
    // In the tap it is held: the feed in and the feed out take the time of 100 %, at both
    // overrides alike: 12 mm at 625 mm/min = 1.152 s each, geared to the spindle's encoder.
    // The feed out starts once the spindle has reversed to −500 rpm (a cut starts at speed):
    // 1000 rpm at 4000 rpm/s, 0.25 s more in its block.
    for (i, want) in [(2, 1.152), (4, 1.152 + 0.25)] {
        let (a, b) = (secs(&full, i), secs(&half, i));
        assert!(
            (a - want).abs() < 0.01,
            "the tap's feed at 100 %: {a} s, not {want}"
        );
        assert!(
            (b - a).abs() < 0.002,
            "the tap's feed at 50 %: {b} s, at 100 %: {a} s"
        );
    }
}

#[test]
fn a_stop_during_the_tap_holds_once_the_tap_is_out_at_r_with_the_spindle_forward() {
    use novanc::pulse_core::Outcome;
    let desc = lathe("fanuc");
    let p = format!("M10\n{TAP_HEAD}G0 X0 Z5.\nG84 Z-10. R-2. F1.25\nG80\nG0 Z20.\nM30\n");
    let prog = read(&p, &desc).unwrap_or_else(|e| panic!("{e}"));
    let tap = &prog.iter().find(|s| s.line == 6).expect("line 6").blocks;
    // R to Z3, the feed in, M05, M04, the feed out, M05, M03 (the tap's End), R to Z5.
    let (feed_in, end) = (tap[1].seq, tap[6].seq);
    assert_eq!(tap[6].tap, novanc::block::Tap::End);
    let mut k = started(&desc, &prog, 100);
    let Outcome::BlockStart { t, .. } = k.run_until(60_000_000_000, Some((0, feed_in))) else {
        panic!("the feed in did not start");
    };
    // STOP half a second into the feed in, the tap in the hole.
    k.advance_to(t + 500_000_000);
    let z = k.machine(0).expect("CH1").status().pos[2];
    assert!(z < 3000 && z > -10_000, "in the hole: Z {z}");
    k.stop(Some(0)).expect("STOP");
    assert_eq!(k.run_until_idle(60_000_000_000), Outcome::Stopped);
    // The hold came after the tap's last block: out at R (Z3), the spindle forward at 500.
    let st = k.machine(0).expect("CH1").status();
    assert!(st.hold, "held");
    assert_eq!(st.pos[2], 3000, "held at the R level");
    assert_eq!(st.executed.as_ref().map(|b| b.seq), Some(end));
    // M03 is given (the spindle ramps from −500 rpm back up to 500 while the run holds).
    assert_eq!(st.spindle_programmed, 500);
    let now = k.now();
    k.advance_to(now + 1_000_000_000);
    assert_eq!(k.machine(0).expect("CH1").status().spindle, 500);
}

#[test]
fn a_fanuc_program_with_g84_runs_to_its_end() {
    let dir = common::temp_dir("lathe-tapping");
    let m = dir.join("shop.desc");
    std::fs::write(&m, desc_text("fanuc", "")).unwrap();
    // A nut: face, drill the core hole, tap it M10×1.5 (shapes of a shop program).
    let prog = dir.join("nut.nc");
    std::fs::write(
        &prog,
        "%\nO0200 (NUT)\nG21 G40 G80 G95\nM10\nG28 U0 W0\n\
         T0101\nG96 S150 D3000 M03\nG0 X42. Z2. M08\nG1 Z0 F0.15\nX-1.6\nG0 Z2.\n\
         G28 U0 W0\nT0202\nG97 S1200 M03\nG0 X0 Z5.\n\
         G83 Z-20. R-2. Q5000 F0.12\nG80\n\
         G97 S300 M03\nG84 Z-16. R-2. P200 F1.5\nG80\n\
         G0 Z20. M09\nG28 U0 W0\nM30\n%\n",
    )
    .unwrap();
    runs_two_parts(&m, &prog);
}
