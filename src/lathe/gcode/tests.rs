//! Unit tests of the lathe reader (docs/lathe-gcode.md): modes, spindle, threads, cycles,
//! waiting codes, and the blocks the reader hands the kernel.

use super::*;
use crate::block::{Block, Css, FeedMode, Motion, Sync};

/// The Citizen with room to turn at negative Z.
pub fn wide_desc() -> LatheDesc {
    let mut d = LatheDesc::citizen();
    for c in &mut d.channels {
        c.axes[0].travel = [-1.0, 100.0];
        c.axes[1].travel = [-200.0, 200.0];
    }
    d
}

fn read(text: &str) -> Result<Vec<Statement>, TranslateError> {
    read_program(text, &wide_desc(), 0, &ReadOptions::default())
}

fn flat(st: Vec<Statement>) -> Vec<Block> {
    st.into_iter().flat_map(|s| s.blocks).collect()
}

/// The blocks of `text` on channel 1 of [`wide_desc`].
fn blocks(text: &str) -> Vec<Block> {
    match read(text) {
        Ok(p) => flat(p),
        Err(e) => panic!("{e}"),
    }
}

/// Where a block ends, [X radius, Z] pulses.
fn end(b: &Block) -> [i64; 2] {
    [b.end[0], b.end[2]]
}

/// An arc's absolute centre, [X radius, Z] pulses.
fn centre(b: &Block) -> Option<[i64; 2]> {
    let c = b.center?;
    let s = b.start();
    Some([s[0] + c[0], s[2] + c[1]])
}

/// The moves in brief: 'R' rapid, 'F' feed line, 'T' thread pass, 'A' arc; and their ends.
fn moves(b: &[Block]) -> Vec<(char, [i64; 2])> {
    b.iter()
        .filter_map(|b| {
            let k = match b.motion {
                Motion::Rapid => 'R',
                Motion::Linear if b.thread.is_some() => 'T',
                Motion::Linear => 'F',
                Motion::ArcCw | Motion::ArcCcw => 'A',
                Motion::Dwell | Motion::Aux => return None,
            };
            Some((k, end(b)))
        })
        .collect()
}

fn ends(b: &[Block]) -> Vec<[i64; 2]> {
    moves(b).into_iter().map(|m| m.1).collect()
}

#[test]
fn a_plain_program_reads_with_percent_o_number_n_and_comments() {
    let p = read("%\nO1000 (PART)\nN5 G18 G21 G90 T0101 ; tool 1\nM3 S1000\nG0 X20 Z2\nG1 Z-10 F100\nG2 X30 Z-15 R5\nM30\n%\n").unwrap_or_default();
    // One statement per line that makes blocks, with its source text.
    let lines: Vec<(u32, &str)> = p.iter().map(|s| (s.line, s.text.as_str())).collect();
    assert_eq!(
        lines,
        [
            (3, "N5 G18 G21 G90 T0101 ; tool 1"),
            (4, "M3 S1000"),
            (5, "G0 X20 Z2"),
            (6, "G1 Z-10 F100"),
            (7, "G2 X30 Z-15 R5"),
            (8, "M30")
        ]
    );
    let b = flat(p);
    assert_eq!(b.len(), 6);
    assert!(b.iter().enumerate().all(|(i, b)| b.seq == i as u32 + 1));
    assert_eq!((b[0].t, b[0].motion), (Some(1), Motion::Aux));
    assert_eq!((b[1].m, b[1].s, b[1].css), (Some(3), Some(1000), None));
    assert_eq!(
        moves(&b),
        [
            ('R', [10000, 2000]),
            ('F', [10000, -10000]),
            ('A', [15000, -15000])
        ]
    );
    // The first move starts where the reader takes the tool to stand (`home`).
    assert_eq!(b[2].start().xyz(), [100_000, 0, 200_000]);
    for f in &b[3..5] {
        assert_eq!((f.feed, f.feed_mode), (100.0, FeedMode::PerMin));
    }
    assert_eq!(
        (b[4].motion, b[4].plane, centre(&b[4])),
        (
            Motion::ArcCw,
            crate::block::Plane::XZ,
            Some([15000, -10000])
        )
    );
    assert_eq!((b[5].m, b[5].motion), (Some(30), Motion::Aux));
}

#[test]
fn diameter_mode_is_the_default_and_g8_reads_x_as_a_radius() {
    let o = blocks("G0 X20 Z0\nG8 G0 X20\nG7 G0 X20\nG91 G0 X-4\nG8 G0 X-4\nU10 W-1\n");
    assert_eq!(
        ends(&o),
        vec![
            [10000, 0],
            [20000, 0],
            [10000, 0],
            [8000, 0],
            [4000, 0],
            [14000, -1000]
        ]
    );
    // I is always a radius (LinuxCNC): the same arc in G7 and G8.
    let a = blocks("G0 X20 Z0\nG1 F50\nG3 X30 Z-5 I0 K-5\n");
    let b = blocks("G8 G0 X10 Z0\nG1 F50\nG3 X15 Z-5 I0 K-5\n");
    assert_eq!(a, b);
    assert_eq!(
        (a[1].motion, centre(&a[1])),
        (Motion::ArcCcw, Some([10000, -5000]))
    );
    // Inches.
    let o = blocks("G20 G8 G0 X1 Z-1\n");
    assert_eq!(ends(&o), vec![[25400, -25400]]);
}

#[test]
fn feed_per_revolution_and_constant_surface_speed() {
    let o = blocks("M4 G96 S180 D2500\nG95 G0 X20 Z1\nG1 Z-5 F0.15\nG97 S800\nM5\n");
    let g96 = Some(Css {
        m_per_min: 180.0,
        limit_rpm: 2500.0,
    });
    assert_eq!((o[0].m, o[0].s, o[0].css), (Some(4), None, g96));
    assert_eq!(end(&o[2]), [10000, -5000]);
    assert_eq!((o[2].feed, o[2].feed_mode), (0.15, FeedMode::PerRev));
    // G96 is modal: every block carries it while it is in force.
    assert_eq!((o[1].css, o[2].css), (g96, g96));
    assert_eq!((o[3].m, o[3].s, o[3].css), (Some(4), Some(800), None));
    assert_eq!((o[4].m, o[4].s, o[4].css), (Some(5), Some(800), None));
    // G96 without D limits at the channel's maximum.
    let o = blocks("G96 S100 M3\n");
    assert_eq!(
        (o[0].m, o[0].css),
        (
            Some(3),
            Some(Css {
                m_per_min: 100.0,
                limit_rpm: 6000.0
            })
        )
    );
}

#[test]
fn tool_offsets_are_added_to_programmed_points() {
    let mut d = wide_desc();
    d.channels[0].tools[0].offset = [0.5, -1.25];
    let p = read_program(
        "T0101\nG0 X20 Z0\nT0100\nG0 X20 Z0\nT1\nG0 Z1\n",
        &d,
        0,
        &ReadOptions::default(),
    );
    let o = flat(p.unwrap_or_default());
    assert_eq!(ends(&o), vec![[10500, -1250], [10000, 0], [10500, -250]]);
}

#[test]
fn g33_is_one_thread_pass() {
    let o = blocks("M3 S500\nG0 X20 Z5\nG33 Z-20 K1.5\nG33 X22 Z-30 K2\n");
    let lead = lead_along_z();
    let passes: Vec<_> = o[2..]
        .iter()
        .map(|b| (b.motion, end(b), b.thread, b.feed, b.feed_mode))
        .collect();
    assert_eq!(
        passes,
        [
            (
                Motion::Linear,
                [10000, -20000],
                Some(1.5),
                1.5,
                FeedMode::PerRev
            ),
            (
                Motion::Linear,
                [11000, -30000],
                Some(lead),
                lead,
                FeedMode::PerRev
            )
        ]
    );
}

/// LinuxCNC measures a taper's K along its path; the kernel gears the longest axis (Z here:
/// 10 mm against 1 mm of radius), so it is given K × 10 / √101.
fn lead_along_z() -> f64 {
    2.0 * 10.0 / 10f64.hypot(1.0)
}

#[test]
fn g76_q_moves_each_pass_down_the_flank() {
    // The passes of g76_passes_by_hand with Q29.5, as LinuxCNC's convert_threading_cycle
    // makes them (rs274 prints the same): each starts depth·tan 29.5° on from Z5 (0.2, 0.4,
    // 0.6, 0.6 mm deep: 0.11315, 0.22631, 0.33946, 0.33946 mm) and ends (0.6 − depth)·tan 29.5°
    // short of Z-20, the last at Z-20.
    let o = moves(&blocks(
        "M3 S500\nG8 G0 X10 Z5\nG76 P1.5 Z-20 I-0.5 J0.2 K0.6 H1 Q29.5\n",
    ));
    let passes: Vec<(i64, i64)> = o
        .windows(2)
        .filter_map(|w| match (w[0], w[1]) {
            (('R', a), ('T', b)) => Some((a[1], b[1])),
            _ => None,
        })
        .collect();
    assert_eq!(
        passes,
        vec![
            (4887, -19774),
            (4774, -19887),
            (4661, -20000),
            (4661, -20000)
        ]
    );
}

#[test]
fn g76_passes_by_hand() {
    // Drive line X radius 10 at Z5; crest 0.5 below; J0.2, K0.6, R1, one spring pass:
    // depths 0.2, 0.4, 0.6, 0.6 → X radius 9.3, 9.1, 8.9, 8.9, each pass back at the retract
    // X 10 + (0.6 - depth), as LinuxCNC; the last retract is the drive line, so the final
    // move to (X10, Z-20) is already made.
    let o = blocks("M3 S500\nG8 G0 X10 Z5\nG76 P1.5 Z-20 I-0.5 J0.2 K0.6 H1\n");
    // In G07 I, J and K are diameters: the same passes with twice the values.
    let g7 = blocks("M3 S500\nG0 X20 Z5\nG76 P1.5 Z-20 I-1 J0.4 K1.2 H1\n");
    assert_eq!(o, g7);
    let mut want = Vec::new();
    for (x, back) in [(9300, 10400), (9100, 10200), (8900, 10000), (8900, 10000)] {
        want.push(('R', [back, 5000]));
        want.push(('R', [x, 5000]));
        want.push(('T', [x, -20000]));
        want.push(('R', [back, -20000]));
    }
    assert_eq!(moves(&o[2..]), want);
    assert!(o.iter().all(|b| b.thread.is_none_or(|l| l == 1.5)));
    // Internal thread, degression 2: J·√k below K, then K.
    let o = moves(&blocks(
        "M3 S500\nG8 G0 X10 Z5\nG76 P1 Z-10 I0.5 J0.2 K0.6 R2\n",
    ));
    let xs: Vec<i64> = o.iter().filter(|m| m.0 == 'T').map(|m| m.1[0]).collect();
    assert_eq!(
        xs,
        vec![10700, 10783, 10846, 10900, 10947, 10990, 11029, 11066, 11100]
    );
    assert_eq!(
        cycles::g76_depths(0.2, 0.6, 1.0, 0, 0.0, 0.0),
        Some(vec![0.2, 0.4, 0.6])
    );
}

#[test]
fn g71_roughs_by_hand_and_g70_finishes() {
    let text = "T0101 M3 S1000\nG0 X40 Z2\nG71 U2 R0.5\nG71 P10 Q20 U0.4 W0.1 F100\nN10 G0 X20\nG1 Z-10\nN20 G1 X40 Z-20\nG70 P10 Q20\nM30\n";
    let o = blocks(text);
    assert_eq!((o[0].t, o[1].m, o[1].s), (Some(1), Some(3), Some(1000)));
    let mut want = vec![('R', [20000, 2000])];
    // Levels X 18, 16, 14, 12 (radius) meet the taper shifted by U0.2/W0.1 at
    // Z = -9.9 - (X - 10.2).
    for (x, z) in [
        (18000, -17700),
        (16000, -15700),
        (14000, -13700),
        (12000, -11700),
    ] {
        want.push(('R', [x, 2000]));
        want.push(('F', [x, z]));
        want.push(('R', [x + 500, z + 500]));
        want.push(('R', [x + 500, 2000]));
    }
    want.extend([
        ('R', [10200, 2000]),
        ('R', [10200, 2100]),
        ('F', [10200, -9900]),
        ('F', [20200, -19900]),
        ('R', [20200, 2000]),
        ('R', [20000, 2000]),
        // G70: the profile as written, then back to the start.
        ('R', [10000, 2000]),
        ('F', [10000, -10000]),
        ('F', [20000, -20000]),
        ('R', [20000, 2000]),
    ]);
    assert_eq!(moves(&o), want);
    assert_eq!(o.len(), want.len() + 3, "T, M3 and M30 besides the moves");
    assert!(o
        .iter()
        .filter(|b| b.motion == Motion::Linear)
        .all(|b| (b.feed, b.feed_mode) == (100.0, FeedMode::PerMin)));
    assert_eq!(o.last().and_then(|b| b.m), Some(30));
}

#[test]
fn g71_follows_an_arc_in_its_profile() {
    let text =
        "G0 X40 Z2\nG71 U3 R0\nG71 P1 Q3 F100\nN1 G0 X10\nN2 G1 Z0\nN3 G2 X40 Z-15 R15\nM30\n";
    let o = moves(&blocks(text));
    // The arc from (Z0, X5) to (Z-15, X20) clockwise, R15, has its centre at (Z0, X20):
    // level X meets it at Z = -sqrt(225 - (X-20)^2). Levels X radius 17, 14, 11, 8.
    let lines: Vec<[i64; 2]> = o.iter().filter(|m| m.0 == 'F').map(|m| m.1).collect();
    let z = |x: f64| (-(225.0 - (x - 20.0) * (x - 20.0)).sqrt() * 1000.0).round() as i64;
    assert_eq!(lines[0], [17000, z(17.0)]);
    assert_eq!(lines[3], [8000, z(8.0)]);
}

#[test]
fn waiting_codes_list_channels_by_digits() {
    let o = blocks("M100 P12\nM101 P123\nM102\nM103 P1\n");
    let syncs: Vec<Option<Sync>> = o.iter().map(|b| b.sync).collect();
    assert_eq!(
        syncs,
        vec![
            Some(Sync::Wait {
                m: 100,
                with: 0b011
            }),
            Some(Sync::Wait {
                m: 101,
                with: 0b111
            }),
            Some(Sync::Wait {
                m: 102,
                with: 0b111
            }),
            Some(Sync::Wait {
                m: 103,
                with: 0b001
            }),
        ]
    );
    let p = read_program("M150 P23\n", &wide_desc(), 1, &ReadOptions::default());
    assert_eq!(
        p.ok()
            .map(flat)
            .and_then(|b| b.first().and_then(|b| b.sync)),
        Some(Sync::Wait {
            m: 150,
            with: 0b110
        })
    );
}

#[test]
fn chuck_stops_block_delete_and_optional_stop() {
    let text = "M10\n/M11\nM0\nM1\nG4 P1.5\nM2\nG0 X1\n";
    // A deleted line is not even read when BLOCK DELETE is on.
    let on = ReadOptions {
        block_delete: true,
        optional_stop: false,
        parts: None,
    };
    assert!(read_program("/G0 X1 X2\nM2\n", &wide_desc(), 0, &on).is_ok());
    assert!(read("/G0 X1 X2\nM2\n").is_err());
    // (sync, M, dwell ns) of each block.
    let brief = |b: Vec<Block>| -> Vec<(Option<Sync>, Option<u8>, u64)> {
        b.iter().map(|b| (b.sync, b.m, b.dwell_ns)).collect()
    };
    assert_eq!(
        brief(blocks(text)),
        vec![
            (Some(Sync::ChuckClose), None, 0),
            (Some(Sync::ChuckOpen), None, 0),
            (None, Some(0), 0),
            (None, None, 1_500_000_000),
            (None, Some(2), 0),
        ]
    );
    let d = wide_desc();
    let opts = ReadOptions {
        block_delete: true,
        optional_stop: true,
        parts: None,
    };
    let p = read_program(text, &d, 0, &opts).unwrap_or_default();
    assert_eq!(
        brief(flat(p)),
        vec![
            (Some(Sync::ChuckClose), None, 0),
            (None, Some(0), 0),
            (None, Some(1), 0),
            (None, None, 1_500_000_000),
            (None, Some(2), 0),
        ]
    );
}

#[test]
fn operations_under_compensation_wait_behind_the_held_moves() {
    let o = blocks("T0101 M3 S1000\nG0 X30 Z5\nG42 G0 X10 Z2\nG1 Z0 F100\nM10\nG1 X20 Z-10\nG40 G0 X40 Z5\nM30\n");
    let kinds: Vec<&str> = o
        .iter()
        .map(|b| match (b.motion, b.sync) {
            (Motion::Rapid, _) => "rapid",
            (Motion::Linear, _) => "line",
            (Motion::ArcCw | Motion::ArcCcw, _) => "arc",
            (_, Some(Sync::ChuckClose)) => "M10",
            _ => "other",
        })
        .collect();
    assert_eq!(
        kinds,
        ["other", "other", "rapid", "rapid", "line", "M10", "line", "rapid", "other"]
    );
    // The held M10 keeps its own line, and stands where the tool is when it is reached.
    assert_eq!((o[5].stmt, o[5].start(), o[5].end), (5, o[4].end, o[4].end));
    // The exit move ends where it is programmed.
    assert_eq!(end(&o[7]), [20000, 5000]);
}

#[test]
fn g71_bores_and_g70_finishes_with_compensation() {
    // A bore: the start (X10, radius 5) is below the profile's first X (radius 10); levels
    // rise by U1 to X radius 6, 7, 8, 9, each cut the whole length to Z-5.
    let text = "T0303 M3 S1000\nG0 X10 Z2\nG71 U1 R0\nG71 P1 Q2 F50\nN1 G41 G0 X20\nN2 G1 Z-5\nG40 G0 X10\nG70 P1 Q2\nM30\n";
    let o = moves(&blocks(text));
    let cuts: Vec<[i64; 2]> = o.iter().filter(|m| m.0 == 'F').map(|m| m.1).collect();
    assert_eq!(
        cuts[..5],
        [
            [6000, -5000],
            [7000, -5000],
            [8000, -5000],
            [9000, -5000],
            [10000, -5000]
        ]
    );
    // G70 under G41 with tool 3 (radius 0.2, tip 2): the bore wall is cut by P on X radius
    // 10 (tip 2 touches the wall above the centre).
    let finish = cuts[5];
    assert_eq!(finish[0], 10000, "{o:?}");
}

#[test]
fn a_citizen_channel_program_reads_on_the_embedded_machine() {
    // Channel 2 of the Citizen: Z travel -2..120 (the work lies at +Z), receive, machine
    // towards +Z with G41 (the nose above the work when travelling +Z), deliver.
    let text = "O2000\nM10\nM100 P12\nT0101\nG96 S120 D4000 M3\nG95 G0 X14 Z-1\nG41 G1 X10 Z0 F0.1\nG1 Z8\nG3 X14 Z10 R2\nG1 Z20\nG40 G0 X30 Z21\nM5\nM11\nM30\n";
    let d = LatheDesc::citizen();
    let p = match read_program(text, &d, 1, &ReadOptions::default()) {
        Ok(p) => p,
        Err(e) => panic!("{e}"),
    };
    assert_eq!(p.last().map(|s| s.line), Some(14), "M30 on the last line");
    let z_cut = p
        .iter()
        .find(|s| s.line == 8)
        .and_then(|s| s.blocks.iter().find(|b| b.motion == Motion::Linear));
    let b = flat(p.clone());
    assert_eq!(b[0].sync, Some(Sync::ChuckClose));
    assert_eq!(
        b[1].sync,
        Some(Sync::Wait {
            m: 100,
            with: 0b011
        })
    );
    assert!(b.iter().any(|b| b.motion == Motion::ArcCcw));
    assert_eq!(b[b.len() - 2].sync, Some(Sync::ChuckOpen));
    // Tool 1 of channel 2: radius 0.4, tip 3. On the Z cut (line 8) P runs 0.4 above the
    // profile's X radius 5 less 0.4 (tip 3 looks down): on X radius 5 exactly.
    assert_eq!(z_cut.map(|b| b.end[0]), Some(5000));
}

#[test]
fn a_corner_join_shorter_than_a_pulse_is_dropped_not_made_a_full_circle() {
    // G42 turning -Z: the profile dips by 0.002 mm on the diameter over 10 mm, an outside
    // corner of 0.0002 rad whose join arc (0.8 mm radius) is 0.00016 mm long.
    let o = moves(&blocks(
        "T0101 M3 S1000\nG0 X30 Z5\nG42 G0 X10 Z2\nG1 Z-10 F100\nG1 X9.996 Z-20\nG40 G0 X30\nM30\n",
    ));
    assert!(!o.iter().any(|m| m.0 == 'A'), "{o:?}");
    let e: Vec<[i64; 2]> = o.iter().map(|m| m.1).collect();
    assert!(e.windows(2).all(|w| w[0] != w[1]), "{e:?}");
}

#[test]
fn the_side_changes_without_g40_as_the_thesis_allows() {
    // Towards -Z under G42, then G41 without G40: the held moves end one radius off their
    // last point, then a new entry move on the other side.
    let o = blocks("T0303 M3 S1000\nG8 G0 X30 Z5\nG42 G0 X10 Z2\nG1 Z-10 F100\nG41 G1 X20 Z-12\nG1 Z-20\nG40 G0 X30\nM30\n");
    let e = ends(&o);
    // Tool 3: radius 0.2, tip 2 (P = C + 0.2·(+X, -Z)). Under G42 travelling -Z, C is 0.2
    // above X10, so the held run ends with P at (X10.4, Z-10.2).
    assert!(e.contains(&[10400, -10200]), "{e:?}");
    // Under G41 travelling -Z, C is 0.2 below X20: P on X 20.0, Z-20.2.
    assert!(e.contains(&[20000, -20200]), "{e:?}");
}

#[test]
fn m98_calls_a_subprogram_and_abort_stops_at_its_line() {
    // One reader's flow (docs/lathe-gcode.md "One reader, two dialects"): M98 runs O100 twice.
    let called = blocks("M3 S500\nG0 X20 Z0\nM98 P100 L2\nM30\nO100\nG0 W-1\nM99\n");
    let flat = blocks("M3 S500\nG0 X20 Z0\nG0 W-1\nG0 W-1\nM30\n");
    assert_eq!(moves(&called), moves(&flat));
    assert_eq!(moves(&called).last().map(|m| m.1), Some([10_000, -2_000]));
    let e = read("G0 X20 Z0\n#1 = 2\n(abort, depth #1 is too deep)\nG0 X10\n")
        .err()
        .map(|e| e.to_string());
    assert_eq!(
        e.as_deref(),
        Some("3:1: (ABORT) depth 2.000000 is too deep")
    );
    let e = read("G0 X20 Z0\nG71 U1\nG71 P1 Q2 F1\nN1 G0 X10\nN2 M98 P100\n")
        .err()
        .map(|e| e.to_string());
    assert!(e.as_deref().is_some_and(|e| e.starts_with("5:")), "{e:?}");
}

#[test]
fn g76_e_and_l_taper_into_and_out_of_the_groove_as_one_pass() {
    // LinuxCNC's threading_pass with E1 L3, worked by hand for the first pass (J 0.2 deep,
    // radius mode): from the retract X 10 + 0.6 − 0.2 = 10.4, in to the crest's height above
    // the cut (X 9.9) and down 1 mm of Z to the cut (X 9.3), along Z, and up 1 mm of Z to
    // X 9.9 at Z-20. LinuxCNC gears the tapers at 1.5 × √(1² + 0.6²) / 1 along their path:
    // the kernel, which gears a block's longest axis, is given 1.74929 for the move in
    // (X alone) and 1.5 for the tapers (Z the longer: 1.74929 × 1 / √1.36). Each block but the
    // last goes on in the next (`Tap::Part`): the pass is one helix from its index.
    let o = blocks("M3 S500\nG8 G0 X10 Z5\nG76 P1.5 Z-20 I-0.5 J0.2 K0.6 E1 L3\n");
    let pass: Vec<_> = o[2..8]
        .iter()
        .map(|b| (moves(std::slice::from_ref(b))[0], b.thread, b.tap))
        .collect();
    let taper_pitch = 1.5 * 1f64.hypot(0.6) / 1.0;
    use crate::block::Tap;
    assert_eq!(
        pass,
        [
            (('R', [10400, 5000]), None, Tap::No),
            (('T', [9900, 5000]), Some(taper_pitch), Tap::Part),
            (('T', [9300, 4000]), Some(1.5), Tap::Part),
            (('T', [9300, -19000]), Some(1.5), Tap::Part),
            (('T', [9900, -20000]), Some(1.5), Tap::No),
            (('R', [10400, -20000]), None, Tap::No),
        ]
    );
    // L1: the start only; L2: the end only; E without L: neither (as LinuxCNC).
    for (l, threads) in [(" L1", 3), (" L2", 2), ("", 1)] {
        let o = blocks(&format!(
            "M3 S500\nG8 G0 X10 Z5\nG76 P1.5 Z-20 I-0.5 J0.2 K0.6 E1{l}\n"
        ));
        let first: Vec<_> = o
            .iter()
            .skip_while(|b| b.thread.is_none())
            .take_while(|b| b.thread.is_some())
            .collect();
        assert_eq!(first.len(), threads, "L{l}");
    }
}

#[test]
fn linuxcnc_reads_5411_in_its_own_numbering() {
    // Tool 1 of the Citizen is tip 3 (Fanuc's chart, +X up): LinuxCNC's Q2, the same tool in
    // its chart drawn with +X down. Tool 3, tip 2, is its Q3.
    for (t, q) in [(1, 2), (3, 3)] {
        let o = blocks(&format!("T{t} M6 G43\n#1=#5411\nG8 G0 X[#1] Z0\n"));
        let m = moves(&o);
        assert_eq!(m.last().map(|m| m.1[0]), Some(q * 1000), "tool {t}");
    }
    assert_eq!(
        (0..=9).map(comp::linuxcnc_orientation).collect::<Vec<_>>(),
        [0, 4, 3, 2, 1, 5, 8, 7, 6, 9]
    );
}

/// G71's one-block form (Fanuc's FS15 format, Haas): `G71 P Q U W D F`, D the depth of cut, the
/// retract the last first block's, else `cycles::ONE_BLOCK_RETRACT_MM`; G72's the same along Z.
/// Before, it was refused, and a D on the second block of the two-block form was taken as G96's
/// speed limit (`D.025`: 0.025 rpm).
#[test]
fn g71_and_g72_read_the_one_block_form_with_d_the_depth_of_cut() {
    let profile = "N10 G0 X20\nG1 Z-10\nN20 G1 X40 Z-20\nM30\n";
    let two = blocks(&format!(
        "G0 X40 Z2\nG71 U2 R0.5\nG71 P10 Q20 U0.4 W0.1 F100\n{profile}"
    ));
    let one = blocks(&format!(
        "G0 X40 Z2\nG71 P10 Q20 U0.4 W0.1 D2. F100\n{profile}"
    ));
    assert_eq!(moves(&one), moves(&two), "R 0.5 is the default retract");
    assert_eq!(cycles::ONE_BLOCK_RETRACT_MM, 0.5);
    // The last first block's retract holds, as a Fanuc's parameter 5133 does.
    let kept = blocks(&format!(
        "G0 X40 Z2\nG71 U3 R1\nG71 P10 Q20 U0.4 W0.1 D2. F100\n{profile}"
    ));
    let r1 = blocks(&format!(
        "G0 X40 Z2\nG71 U2 R1\nG71 P10 Q20 U0.4 W0.1 F100\n{profile}"
    ));
    assert_eq!(moves(&kept), moves(&r1), "D the depth, R the kept retract");
    // D is the depth, not the G96 limit: the spindle's limit stays the channel's.
    let css = blocks(&format!(
        "G96 S100 M3\nG0 X40 Z2\nG71 U2 R0.5\nG71 P10 Q20 U0.4 W0.1 D2. F100\n{profile}"
    ));
    assert!(css
        .iter()
        .all(|b| b.css.is_none_or(|c| c.limit_rpm > 1000.0)));
    // G72: the depth along Z.
    let face = "N10 G0 Z-10\nG1 X10\nN20 X5 Z0\nM30\n";
    let two = blocks(&format!("G0 X40 Z2\nG72 W2 R0.5\nG72 P10 Q20 F100\n{face}"));
    let one = blocks(&format!("G0 X40 Z2\nG72 P10 Q20 D2. F100\n{face}"));
    assert_eq!(moves(&one), moves(&two));
    // Refused: D on a first block; no depth at all; D of 0.
    for (text, says) in [
        ("G0 X40 Z2\nG71 U2 R0.5 D1\n", "takes no D word"),
        ("G0 X40 Z2\nG71 P10 Q20 F100\n", "or D on this line"),
        (
            "G0 X40 Z2\nG71 P10 Q20 D0 F100\n",
            "the depth of cut, must be above 0 and under",
        ),
    ] {
        let e = read(&format!("{text}{profile}")).unwrap_err();
        assert!(e.message.contains(says), "{text}: {e}");
    }
}

/// In Fanuc's dialect D written without a decimal point is in least increments, as X and Z
/// are (`D1500` is 1.5 mm, the FS15 format's textbook form); with `decimal calculator`, as
/// written.
#[test]
fn a_one_block_g71_d_without_a_point_is_in_least_increments_in_fanucs_dialect() {
    let profile = "N10 G0 X20.\nG1 Z-10.\nN20 G1 X40. Z-20.\nM30\n";
    let on = |d: &LatheDesc, text: &str| {
        let st = read_program(text, d, 0, &ReadOptions::default()).unwrap();
        moves(&flat(st))
    };
    let mut d = wide_desc();
    d.channels[0].dialect = Some(crate::settings::Dialect::Fanuc);
    let want = on(
        &d,
        &format!("G94 G0 X40. Z2.\nG71 P10 Q20 D1.5 F100.\n{profile}"),
    );
    let got = on(
        &d,
        &format!("G94 G0 X40. Z2.\nG71 P10 Q20 D1500 F100.\n{profile}"),
    );
    assert_eq!(got, want);
    d.channels[0].calculator = Some(true);
    let calc = on(
        &d,
        &format!("G94 G0 X40 Z2\nG71 P10 Q20 D1.5 F100\n{profile}"),
    );
    assert_eq!(calc, want);
    let text = format!("G94 G0 X40 Z2\nG71 P10 Q20 D1500 F100\n{profile}");
    let e = read_program(&text, &d, 0, &ReadOptions::default()).unwrap_err();
    assert_eq!((e.line, e.col), (2, 13), "{e}");
    assert!(e.message.contains("under 1000 mm"), "{e}");
}

/// A G71 profile that ends with moves out of the stock, at or beyond the start's X (a rapid
/// out to the start's X, then back along Z to the start's Z, before G40), is roughed as the
/// profile without them: no level reaches them, and the cycle's way out is the same. Shop
/// programs write it so; until stop 52 it was refused as turning back in Z. A move back that
/// dips into the stock is still refused at its line; G70 runs the lines as written.
#[test]
fn a_g71_profile_may_end_with_moves_out_of_the_stock() {
    let profile = "N10 G0 X20\nG1 Z-10\nG1 X40 Z-20\n";
    let plain = blocks(&format!(
        "G0 X40 Z2\nG71 U2 R0.5\nG71 P10 Q20 U0.4 W0.1 F100\n{profile}N20 G1 X40 Z-20\nM30\n"
    ));
    let out = blocks(&format!(
        "G0 X40 Z2\nG71 U2 R0.5\nG71 P10 Q20 U0.4 W0.1 F100\n{profile}G0 X40\nN20 G0 Z2\nM30\n"
    ));
    assert_eq!(moves(&out), moves(&plain));
    // With G70 after it, the finishing runs the rapid out and back as written.
    let fin = blocks(&format!(
        "G0 X40 Z2\nG71 U2 R0.5\nG71 P10 Q20 U0.4 W0.1 F100\n{profile}G0 X42\nN20 G0 Z2\nG70 P10 Q20\nM30\n"
    ));
    let m = moves(&fin);
    assert_eq!(
        &m[m.len() - 3..],
        &[
            ('R', [21_000, -20_000]),
            ('R', [21_000, 2_000]),
            ('R', [20_000, 2_000])
        ]
    );
    // Back along Z below the start's X: into the stock, refused where it turns.
    let e = read(
        "G0 X40 Z2\nG71 U2 R0.5\nG71 P10 Q20 U0.4 W0.1 F100\nN10 G0 X20\nG1 Z-10\nG1 X36 Z-20\nN20 G0 Z2\nM30\n",
    )
    .unwrap_err();
    assert_eq!(e.line, 7, "{e}");
    assert!(e.message.contains("turns back in Z"), "{e}");
}

/// G73, Fanuc 0i-T's pattern repeating (stop 52; refused before): the profile cut R times,
/// shifted by the relief U W (a radius) shared out evenly, the last pass at the allowances
/// alone; each pass from the start point, its first move in its own mode, then out to the
/// start's X (or the pass's end X, farther out), along Z and back. Worked out by hand.
#[test]
fn g73_repeats_the_profile_shifted_by_the_relief_shared_out() {
    let mut d = wide_desc();
    d.channels[0].dialect = Some(crate::settings::Dialect::Fanuc);
    let on = |d: &LatheDesc, text: &str| read_program(text, d, 0, &ReadOptions::default());
    let text = "G94 G0 X44. Z2.\nG73 U3. W1. R3\nG73 P10 Q20 U0.4 W0.1 F100.\n\
                N10 G0 X20. Z2.\nG1 Z-10.\nG2 X30. Z-15. R5.\nG1 X40. Z-25.\nN20 X44.\nM30\n";
    let got = moves(&flat(on(&d, text).unwrap()));
    let mut want = vec![('R', [22_000, 2_000])];
    // Radius offsets 3 + 0.2, 1.5 + 0.2, 0 + 0.2; along Z 1 + 0.1, 0.5 + 0.1, 0.1.
    for (ox, oz) in [(3_200, 1_100), (1_700, 600), (200, 100)] {
        want.extend([
            ('R', [10_000 + ox, 2_000 + oz]),
            ('F', [10_000 + ox, -10_000 + oz]),
            ('A', [15_000 + ox, -15_000 + oz]),
            ('F', [20_000 + ox, -25_000 + oz]),
            ('F', [22_000 + ox, -25_000 + oz]),
            // Out: the pass ends beyond the start's X, so along Z there, then in to the start.
            ('R', [22_000 + ox, 2_000]),
            ('R', [22_000, 2_000]),
        ]);
    }
    assert_eq!(got, want);
    // The relief and count are kept for the next G73 P Q, and R1 is one pass at the allowances.
    let once = "G94 G0 X44. Z2.\nG73 U3. W1. R1\nG73 P10 Q20 F100.\n\
                N10 G0 X20. Z2.\nN20 G1 Z-10.\nM30\n";
    let got = moves(&flat(on(&d, once).unwrap()));
    assert_eq!(
        got,
        [
            ('R', [22_000, 2_000]),
            ('R', [10_000, 2_000]),
            ('F', [10_000, -10_000]),
            ('R', [22_000, -10_000]),
            ('R', [22_000, 2_000]),
        ]
    );
    // Refused, each at its place and with its reason.
    let p = "N10 G0 X20. Z2.\nN20 G1 Z-10.\nM30\n";
    for (text, place, says) in [
        (
            "G94 G0 X44. Z2.\nG73 P10 Q20 F100.\n",
            (2, 1),
            "needs the first G73 block",
        ),
        (
            "G94 G0 X44. Z2.\nG73 U3. W1. R2.5\n",
            (2, 13),
            "a whole number 1 to 100",
        ),
        (
            "G94 G0 X44. Z2.\nG73 U3. W1. R0\n",
            (2, 13),
            "a whole number 1 to 100",
        ),
        (
            "G94 G0 X44. Z2.\nG73 U3. W1.\n",
            (2, 1),
            "G73 (first block) needs R",
        ),
        (
            "G94 G0 X44. Z2.\nG73 U3. R2 X1.\n",
            (2, 12),
            "G73 U W R takes no X word",
        ),
    ] {
        let e = on(&d, &format!("{text}{p}")).unwrap_err();
        assert_eq!((e.line, e.col), place, "{text}: {e}");
        assert!(e.message.contains(says), "{text}: {e}");
    }
    // An arc as the first move would not be the arc written once made from the start point.
    let e = on(
        &d,
        "G94 G0 X44. Z2.\nG73 U3. W1. R2\nG73 P10 Q20 F100.\nN10 G2 X20. Z-5. R20.\nN20 G1 Z-10.\nM30\n",
    )
    .unwrap_err();
    assert_eq!(e.line, 4, "{e}");
    assert!(e.message.contains("first move must be G00 or G01"), "{e}");
    // In LinuxCNC's dialect G73 is a mill's drilling cycle: refused, saying so.
    let e = read("G0 X44 Z2\nG73 U3 W1 R3\n").unwrap_err();
    assert!(e.message.contains("Fanuc's dialect only"), "{e}");
}

/// An arc of a G71 profile whose end is written a hair past the circle's extreme (a Haas
/// program's `G02 X1.114 Z-1.7261 R0.564`, its end 0.0001 inch past the top) comes back by
/// nanometres: it is roughed as the arc that ends on the top, not refused as turning back. An
/// arc that really comes back (by more than a pulse) is still refused at its line.
#[test]
fn a_g71_arc_a_hair_past_its_top_is_not_a_turn_back() {
    let prog = |arc: &str| {
        format!("G0 X40 Z2\nG71 U2 R0.5\nG71 P10 Q20 U0.4 W0.1 F100\nN10 G0 X10\nG1 Z-10\n{arc}\nN20 G1 X40\nM30\n")
    };
    let on_top = blocks(&prog("G3 X20 Z-15 R5"));
    let past = blocks(&prog("G3 X20 Z-15.0003 R5"));
    let (a, b) = (moves(&on_top), moves(&past));
    assert_eq!(a.len(), b.len());
    for (x, y) in a.iter().zip(&b) {
        assert!(
            x.0 == y.0 && (x.1[0] - y.1[0]).abs() <= 1 && (x.1[1] - y.1[1]).abs() <= 1,
            "{x:?} {y:?}"
        );
    }
    let e = read(&prog("G3 X20 Z-15.5 R5")).unwrap_err();
    assert_eq!(e.line, 6, "{e}");
    assert!(e.message.contains("an arc that turns back"), "{e}");
}

/// Fanuc's type II G71 (the profile's first line names Z): a profile with a pocket, X turning
/// back, is roughed level by level, each level cutting its stretch from the start's Z and
/// then each pocket below it, reached over the profile at the start's X, down its near side
/// to the last level and in at the feed. Worked out by hand (docs/lathe-gcode.md "Type II:
/// pockets"): radius 5 at the face, a shoulder at 15, a pocket down to 8 between Z-12 and
/// Z-18, out to 20 at Z-20; U2.5 (radius) levels from 20: 17.5, 15, 12.5, 10, 7.5.
#[test]
fn a_type_ii_g71_roughs_the_pocket_level_by_level() {
    let profile = "N10 G0 X10 Z2\nG1 Z-5\nX30\nZ-10\nX16 Z-12\nZ-18\nX30 Z-20\nN20 X40\n";
    let got = moves(&blocks(&format!(
        "G0 X40 Z2\nG71 U2.5 R0.5\nG71 P10 Q20 F100\n{profile}M30\n"
    )));
    let p = |x: f64| (x * 1000.0).round() as i64;
    let (r, f) = ('R', 'F');
    // [kind, X radius, Z] mm.
    #[rustfmt::skip]
    let want: Vec<(char, f64, f64)> = vec![
        // The program's own move to the start.
        (r, 20.0, 2.0),
        // 17.5: one stretch, as type I.
        (r, 17.5, 2.0), (f, 17.5, -20.0), (r, 18.0, -19.5), (r, 18.0, 2.0),
        // 15: to the shoulder, then the pocket from where the profile goes down at Z-10.
        (r, 15.0, 2.0), (f, 15.0, -5.0), (r, 15.5, -4.5), (r, 20.0, -4.5),
        (r, 20.0, -10.0), (r, 18.0, -10.0), (f, 15.0, -10.0), (f, 15.0, -20.0),
        (r, 15.5, -19.5), (r, 20.0, -19.5), (r, 20.0, 2.0),
        // 12.5: the pocket's sides cross the level at Z-10.714 and Z-19.286.
        (r, 12.5, 2.0), (f, 12.5, -5.0), (r, 13.0, -4.5), (r, 20.0, -4.5),
        (r, 20.0, -10.0 - 2.0 * 2.5 / 7.0), (r, 15.5, -10.0 - 2.0 * 2.5 / 7.0),
        (f, 12.5, -10.0 - 2.0 * 2.5 / 7.0), (f, 12.5, -18.0 - 2.0 * 4.5 / 7.0),
        (r, 13.0, -17.5 - 2.0 * 4.5 / 7.0), (r, 20.0, -17.5 - 2.0 * 4.5 / 7.0),
        (r, 20.0, 2.0),
        // 10: Z-11.429 and Z-18.571.
        (r, 10.0, 2.0), (f, 10.0, -5.0), (r, 10.5, -4.5), (r, 20.0, -4.5),
        (r, 20.0, -10.0 - 2.0 * 5.0 / 7.0), (r, 13.0, -10.0 - 2.0 * 5.0 / 7.0),
        (f, 10.0, -10.0 - 2.0 * 5.0 / 7.0), (f, 10.0, -18.0 - 2.0 * 2.0 / 7.0),
        (r, 10.5, -17.5 - 2.0 * 2.0 / 7.0), (r, 20.0, -17.5 - 2.0 * 2.0 / 7.0),
        (r, 20.0, 2.0),
        // 7.5: above the pocket's bottom (8): the face stretch only, as type I.
        (r, 7.5, 2.0), (f, 7.5, -5.0), (r, 8.0, -4.5), (r, 8.0, 2.0),
        // The pass along the profile, then out and back to the start.
        (r, 5.0, 2.0), (f, 5.0, -5.0), (f, 15.0, -5.0), (f, 15.0, -10.0), (f, 8.0, -12.0),
        (f, 8.0, -18.0), (f, 15.0, -20.0), (f, 20.0, -20.0), (r, 20.0, 2.0),
    ];
    assert_eq!(got.len(), want.len(), "{got:?}");
    for (g, w) in got.iter().zip(&want) {
        let ok = g.0 == w.0 && (g.1[0] - p(w.1)).abs() <= 1 && (g.1[1] - p(w.2)).abs() <= 1;
        assert!(ok, "got {g:?}, want {w:?}\n{got:?}");
    }
    // The same profile with an X-only first line is type I: refused where it turns back,
    // with what to write.
    let e = read(&format!(
        "G0 X40 Z2\nG71 U2.5 R0.5\nG71 P10 Q20 F100\n{}M30\n",
        profile.replace("N10 G0 X10 Z2", "N10 G0 X10")
    ))
    .unwrap_err();
    assert_eq!(e.line, 8, "{e}");
    assert!(
        e.message
            .contains("name Z or W0 in the profile's first block"),
        "{e}"
    ); // The type is the P line's, as read: an empty P line (`N10`, the Z on the next) names
       // no Z, so the pocket is refused as type I's.
    let e = read(&format!(
        "G0 X40 Z2\nG71 U2.5 R0.5\nG71 P10 Q20 F100\nN10\n{}M30\n",
        profile.replace("N10 G0 X10 Z2", "G0 X10 Z2")
    ))
    .unwrap_err();
    assert!(
        e.message
            .contains("name Z or W0 in the profile's first block"),
        "{e}"
    );
}

/// Type II on profiles nobody worked by hand: 300 random pocketed profiles (Z always on, X
/// up and down between the face and the start's X). No roughing move, rapid or feed, passes
/// below the profile (into the part), and every level's cut stays within the stock.
#[test]
fn type_ii_roughing_never_enters_the_part() {
    let mut seed = 0x2545_f491_4f6c_dd1du64;
    let mut rnd = move || {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        (seed >> 11) as f64 / (1u64 << 53) as f64
    };
    for case in 0..300 {
        // The profile, [Z, X radius] mm: from the face at Z2 down the start's Z, then Z always on.
        let mut pts = vec![[2.0, 2.0 + 8.0 * rnd()]];
        let mut z = 2.0;
        for _ in 0..(2 + (rnd() * 6.0) as usize) {
            z -= 0.5 + 6.0 * rnd();
            pts.push([z, 1.0 + 17.0 * rnd()]);
        }
        let end = [z - 1.0, 20.0];
        pts.push(end);
        let mut text = format!(
            "G0 X40 Z2\nG71 U{:.3} R0.3\nG71 P10 Q20 F100\n",
            0.5 + 2.0 * rnd()
        );
        text += &format!("N10 G1 X{:.4} Z2\n", 2.0 * pts[0][1]);
        for (i, q) in pts[1..].iter().enumerate() {
            let n = if i + 2 == pts.len() { "N20 " } else { "" };
            text += &format!("{n}X{:.4} Z{:.4}\n", 2.0 * q[1], q[0]);
        }
        text += "M30\n";
        let b = blocks(&text);
        // The profile's X at `z` (pulses), by its lines.
        let under = |zq: f64| -> f64 {
            for w in pts.windows(2) {
                let (a, c) = (w[0], w[1]);
                if zq <= a[0] + 1e-9 && zq >= c[0] - 1e-9 {
                    let t = if (a[0] - c[0]).abs() < 1e-12 {
                        1.0
                    } else {
                        (a[0] - zq) / (a[0] - c[0])
                    };
                    return a[1] + t * (c[1] - a[1]);
                }
            }
            0.0
        };
        // The roughing: every move before the finishing pass (the last moves follow the
        // profile itself).
        let m = moves(&b);
        let rough = &m[..m.len() - pts.len() - 1];
        let mut at = [20_000i64, 2_000i64];
        for &(k, e) in rough {
            for step in 0..=20 {
                let t = step as f64 / 20.0;
                let x = (at[0] as f64 + t * (e[0] - at[0]) as f64) / 1000.0;
                let zq = (at[1] as f64 + t * (e[1] - at[1]) as f64) / 1000.0;
                if zq < end[0] - 1e-6 || zq > 2.0 + 1e-6 {
                    continue;
                }
                // Within two pulses, either way (a steep wall's crossing rounded to a pulse).
                let near = pts.iter().map(|q| q[0]).filter(|q| (q - zq).abs() <= 0.002);
                let floor = [zq - 0.002, zq, zq + 0.002]
                    .into_iter()
                    .chain(near)
                    .map(under)
                    .fold(f64::INFINITY, f64::min);
                assert!(
                    x >= floor - 0.002,
                    "case {case}: {k} to {e:?} passes X {x:.4} at Z {zq:.4}, below the profile's {:.4}\n{text}",
                    under(zq)
                );
            }
            at = e;
        }
    }
}
