//! What real Fanuc lathe programs (shop and course programs nobody here wrote, tried by hand
//! on a one-channel lathe) met in the reader, each in a small program of our own of the same
//! form: Fanuc 0i-T's G72 face roughing, and a G71 profile that comes back to its start's Z
//! (roughed without that move out of the stock since stop 52; refused at the line that turns
//! when the move is inside the stock). The moves are worked out by hand from each program, not
//! by the reader.

use novanc::lathe::desc::{parse, LatheDesc, MachineDesc};

#[path = "common/lathe_moves.rs"]
mod lathe_moves;
use lathe_moves::read;

/// A one-channel Fanuc lathe: X travel 0..100 (radius), Z −100..100; tools 1 and 2 with no nose
/// radius and no offsets, so the moves are the programmed points.
fn lathe() -> LatheDesc {
    let text = "machine real\nkind lathe\npulse 0.001\ntick 100\ndialect fanuc\nchannel PATH-1\n\
                x travel 0 100 rapid 12000 accel 3000\nz travel -100 100 rapid 15000 accel 3000\n\
                spindle max 4000 accel 4000 encoder 1024\ntool 1 radius 0 tip 3\n\
                tool 2 radius 0 tip 3\n";
    match parse(text) {
        Ok(MachineDesc::Lathe(d)) => d,
        Ok(MachineDesc::Mill(_)) => panic!("a mill"),
        Err(e) => panic!("{e}"),
    }
}

/// The moves in brief (no dwells).
fn ok(text: &str, desc: &LatheDesc) -> Vec<String> {
    lathe_moves::ok(text, desc, false)
}

/// A flange face: from Ø40 at Z−5 a face down to Ø20, then a taper up to Ø10 at Z0. The tool
/// starts at X40. Z2. (radius 20).
const FACE_PROFILE: &str = "N10 G0 Z-5.\nG1 X20. F0.1\nN20 X10. Z0.\n";

#[test]
fn g72_faces_in_passes_along_x_one_depth_deeper_in_z_each() {
    let desc = lathe();
    // G72 W2. R0.5: 2 mm deeper in Z each pass, 0.5 retract. No allowances: the levels are
    // Z 0, −2, −4 (the next, −6, is past the profile's first Z, −5). The taper runs from
    // (radius 10, Z−5) to (radius 5, Z0): at Z0 it is at radius 5, at Z−2 at 5 + 5·2/5 = 7,
    // at Z−4 at 9. Each pass: rapid to the level at A's X (20), feed along X to the taper,
    // 45° away by 0.5 (X +0.5, Z +0.5), rapid back to A's X. Then the profile itself from
    // A′ (radius 20, Z−5), out along Z to A's Z and back to A.
    let p =
        format!("G95 T0202 S500 M3\nG0 X40. Z2.\nG72 W2. R0.5\nG72 P10 Q20 F0.2\n{FACE_PROFILE}");
    assert_eq!(
        ok(&p, &desc),
        [
            "R X20.000 Z2.000",
            "R X20.000 Z0.000",
            "F X5.000 Z0.000",
            "R X5.500 Z0.500",
            "R X20.000 Z0.500",
            "R X20.000 Z-2.000",
            "F X7.000 Z-2.000",
            "R X7.500 Z-1.500",
            "R X20.000 Z-1.500",
            "R X20.000 Z-4.000",
            "F X9.000 Z-4.000",
            "R X9.500 Z-3.500",
            "R X20.000 Z-3.500",
            "R X20.000 Z-5.000",
            "F X10.000 Z-5.000",
            "F X5.000 Z0.000",
            "R X5.000 Z2.000",
            "R X20.000 Z2.000",
        ]
    );
}

#[test]
fn g72_leaves_its_allowances_and_g70_finishes_the_profile() {
    let desc = lathe();
    // U0.4 (0.2 on the radius) and W0.2: the profile shifted to (20.2, −4.8) (10.2, −4.8)
    // (5.2, 0.2). Levels Z 0, −2, −4 (−4 is still above −4.8). The shifted taper at Z0 is at
    // 10.2 − 5·4.8/5 = 5.4, at Z−2 at 10.2 − 2.8 = 7.4, at Z−4 at 10.2 − 0.8 = 9.4. The last
    // pass rapids to the shifted A′ (X 20.2) before following the profile.
    // G70 then runs the profile as written and rapids back to where it began.
    let p = format!(
        "G95 T0202 S500 M3\nG0 X40. Z2.\nG72 W2. R0.5\nG72 P10 Q20 U0.4 W0.2 F0.2\n{FACE_PROFILE}G70 P10 Q20\n"
    );
    assert_eq!(
        ok(&p, &desc),
        [
            "R X20.000 Z2.000",
            "R X20.000 Z0.000",
            "F X5.400 Z0.000",
            "R X5.900 Z0.500",
            "R X20.000 Z0.500",
            "R X20.000 Z-2.000",
            "F X7.400 Z-2.000",
            "R X7.900 Z-1.500",
            "R X20.000 Z-1.500",
            "R X20.000 Z-4.000",
            "F X9.400 Z-4.000",
            "R X9.900 Z-3.500",
            "R X20.000 Z-3.500",
            "R X20.000 Z-4.800",
            "R X20.200 Z-4.800",
            "F X10.200 Z-4.800",
            "F X5.200 Z0.200",
            "R X5.200 Z2.000",
            "R X20.000 Z2.000",
            // G70: the profile as written, then back to the start.
            "R X20.000 Z-5.000",
            "F X10.000 Z-5.000",
            "F X5.000 Z0.000",
            "R X20.000 Z2.000",
        ]
    );
}

#[test]
fn g72_refusals_name_g72_and_its_words() {
    let desc = lathe();
    let start = "G95 T0202 S500 M3\nG0 X40. Z2.\n";
    // The first block's depth is W; a U there is G71's word, not G72's.
    assert_eq!(
        read(&format!("{start}G72 W0 R0.5\n"), &desc)
            .err()
            .as_deref(),
        Some("3:5: G72 W, the depth of cut, must be above 0")
    );
    assert!(read(&format!("{start}G72 U2. R0.5\n"), &desc)
        .err()
        .is_some_and(|e| e.starts_with("3:5: ") && e.contains("G72 W R")));
    // Type I: the profile's first move is along Z only (G71's is along X).
    let p = format!("{start}G72 W2. R0.5\nG72 P10 Q20 F0.2\nN10 G0 X30. Z-5.\nN20 G1 X10. Z0.\n");
    assert_eq!(
        read(&p, &desc).err().as_deref(),
        Some("5:5: the G72 profile's first move must move Z only (Fanuc type I)")
    );
    // A profile that turns back in X (radius 10 out to 12) is refused at the line that turns.
    let p = format!("{start}G72 W2. R0.5\nG72 P10 Q20 F0.2\nN10 G0 Z-5.\nG1 X20. F0.1\nX24. Z-3.\nN20 X10. Z0.\n");
    assert_eq!(
        read(&p, &desc).err().as_deref(),
        Some("7:1: the G72 profile must be monotonic: this move turns back in X")
    );
}

/// A shop's profile that ends with a rapid back to the start's Z (line 8, its G0), out of the
/// stock at the start's X: stop 49 refused it at that line (`turns back in Z`); since stop 52
/// the roughing leaves it out (no level reaches it) and moves as for the profile without it.
/// Back along Z inside the stock, the same line is still refused where it turns.
#[test]
fn a_g71_profile_that_comes_back_to_its_start_z_out_of_the_stock_is_roughed_without_it() {
    let desc = lathe();
    let head = "G95 T0202 S500 M3\nG0 X40. Z2.\nG71 U2. R0.5\nG71 P10 Q20 F0.2\n";
    let ends = |p: &str| -> Vec<novanc::block::Axes> {
        match read(p, &desc) {
            Ok(st) => st.iter().flat_map(|s| &s.blocks).map(|b| b.end).collect(),
            Err(e) => panic!("{e}\n{p}"),
        }
    };
    let back = format!("{head}N10 G0 X20.\nG1 Z-10. F0.1\nX40.\nN20 G0 Z2.\n");
    let plain = format!("{head}N10 G0 X20.\nG1 Z-10. F0.1\nN20 X40.\n");
    assert_eq!(ends(&back), ends(&plain));
    // Back along Z below the start's X: in the stock, refused at the line that turns.
    let p = format!("{head}N10 G0 X20.\nG1 Z-10. F0.1\nX36.\nN20 G0 Z2.\n");
    assert_eq!(
        read(&p, &desc).err().as_deref(),
        Some("8:5: the G71 profile must be monotonic: this move turns back in Z")
    );
    // A profile with no move along Z at all is still refused at its first move.
    let p = "G95 T0202 S500 M3\nG0 X40. Z2.\nG71 U2. R0.5\nG71 P10 Q20 F0.2\n\
             N10 G0 X20.\nN20 G1 X30. F0.1\n";
    assert_eq!(
        read(p, &desc).err().as_deref(),
        Some("5:5: the G71 profile must move along Z after its first move")
    );
}

/// The leads of the thread passes of `text` read on `desc`, mm per revolution, in order.
fn leads(text: &str, desc: &LatheDesc) -> Vec<f64> {
    match read(text, desc) {
        Ok(p) => p
            .iter()
            .flat_map(|s| &s.blocks)
            .filter_map(|b| b.thread)
            .collect(),
        Err(e) => panic!("{e}\n{text}"),
    }
}

#[test]
fn g32_cuts_a_thread_pass_with_the_lead_in_f_kept_for_the_next_pass() {
    let desc = lathe();
    // A course's threading by hand: two passes of G32, the second without F (the lead kept,
    // as Fanuc's F is modal), each in to the depth, along Z, out and back. A thread pass is a
    // feed block (F) with its lead: 1.5 mm per revolution both times.
    let p = "G95 T0202 S500 M3\nG0 X30. Z5.\nX29.\nG32 Z-20. F1.5\nG0 X32.\nZ5.\nX28.6\n\
             G32 Z-20.\nG0 X32.\nZ5.\n";
    assert_eq!(
        ok(p, &desc),
        [
            "R X15.000 Z5.000",
            "R X14.500 Z5.000",
            "F X14.500 Z-20.000",
            "R X16.000 Z-20.000",
            "R X16.000 Z5.000",
            "R X14.300 Z5.000",
            "F X14.300 Z-20.000",
            "R X16.000 Z-20.000",
            "R X16.000 Z5.000",
        ]
    );
    assert_eq!(leads(p, &desc), [1.5, 1.5]);
    // A taper thread: X and Z in one G32 (Ø29 to Ø31 over 25 mm), lead 2; in inches, the lead
    // is inches per revolution (F0.0625 is 1.5875 mm).
    let p = "G95 T0202 S500 M3\nG0 X29. Z5.\nG32 X31. Z-20. F2.\n";
    assert_eq!(ok(p, &desc)[1], "F X15.500 Z-20.000");
    assert_eq!(leads(p, &desc), [2.0]);
    let p = "G20 G95 T0202 S500 M3\nG0 X1. Z.2\nG32 Z-1. F.0625\n";
    assert!((leads(p, &desc)[0] - 1.5875).abs() < 1e-9);
}

#[test]
fn g32_refusals() {
    let desc = lathe();
    let start = "G95 T0202 S500 M3\nG0 X30. Z5.\n";
    // No lead at all.
    assert_eq!(
        read(&format!("{start}G32 Z-20.\n"), &desc).err().as_deref(),
        Some("3:1: G32 needs F, the lead in mm per revolution")
    );
    // A thread is cut along Z.
    assert_eq!(
        read(&format!("{start}G32 X20. F1.5\n"), &desc)
            .err()
            .as_deref(),
        Some("3:1: G32 needs a Z move (F is the lead along Z)")
    );
    // The spindle must turn.
    assert_eq!(
        read("G95 T0202\nG0 X30. Z5.\nG32 Z-20. F1.5\n", &desc)
            .err()
            .as_deref(),
        Some("3:1: G32 with the spindle stopped: give M03 or M04")
    );
    // LinuxCNC has no G32: its thread pass is G33 K.
    let lcnc = {
        let text = "machine real\nkind lathe\npulse 0.001\ntick 100\nchannel PATH-1\n\
                    x travel 0 100 rapid 12000 accel 3000\nz travel -100 100 rapid 15000 accel 3000\n\
                    spindle max 4000 accel 4000 encoder 1024\ntool 2 radius 0 tip 3\n";
        match parse(text) {
            Ok(MachineDesc::Lathe(d)) => d,
            _ => panic!("not a lathe"),
        }
    };
    assert!(read("G95 T0202 S500 M3\nG0 X30 Z5\nG32 Z-20 F1.5\n", &lcnc)
        .err()
        .is_some_and(|e| e.starts_with("3:1: G32 is Fanuc's thread cutting")));
}

/// A Fanuc 0T example of an editor's (TOKARKA, system B): `%O1200(...)` on its first line, and
/// its threads cut by G33 with the lead in F, as Fanuc's G code systems B and C name G32. Both
/// were refused until stop 57 (`a word letter was expected, not '%'`, `G33 needs K`).
#[test]
fn fanuc_g33_takes_its_lead_in_f_as_g32_does_and_a_tape_may_start_with_its_number() {
    let desc = lathe();
    let g32 = "G95 T0202 S500 M3\nG0 X30. Z5.\nX29.\nG32 Z-20. F1.5\nG0 X32.\nZ5.\nX28.6\n\
               G32 Z-20.\nG0 X32.\nZ5.\n";
    let g33 = g32.replace("G32", "G33");
    assert_eq!(ok(&g33, &desc), ok(g32, &desc));
    assert_eq!(leads(&g33, &desc), [1.5, 1.5]);
    // K, where given, is still the lead (a LinuxCNC program read in Fanuc's dialect).
    let p = "G95 T0202 S500 M3\nG0 X30. Z5.\nG33 Z-20. K2. F0.2\n";
    assert_eq!(leads(p, &desc), [2.0]);
    assert_eq!(
        read("G95 T0202 S500 M3\nG0 X30. Z5.\nG33 Z-20.\n", &desc)
            .err()
            .as_deref(),
        Some("3:1: G33 needs F, the lead in mm per revolution")
    );
    // The tape's leader and number on one line, ISO's `:` for O, and a `:` subprogram found
    // by M98: the same moves as the program written with `%` alone and O.
    let plain = "%\nO1200\nG95 T0202 S500 M3\nG0 X30. Z5.\nM98 P200\nM30\nO200\nG0 X20.\nM99\n%\n";
    let iso =
        "%O1200(TOKARKA)\nG95 T0202 S500 M3\nG0 X30. Z5.\nM98 P200\nM30\n:200\nG0 X20.\nM99\n%\n";
    assert_eq!(ok(iso, &desc), ok(plain, &desc));
    assert_eq!(ok(iso, &desc).len(), 2);
    // `:` is a program number and nothing else; after `%` only a number may stand.
    let e = read("%\n:100 sub\n", &desc).err();
    assert_eq!(
        e.as_deref(),
        Some("2:1: ':' is ISO's program number: a number alone")
    );
    let e = read("%G0 X10.\n", &desc).err().unwrap_or_default();
    assert!(
        e.starts_with("1:1: a word letter was expected, not '%'"),
        "{e}"
    );
    // LinuxCNC's dialect has neither, and its G33 wants K.
    let lcnc = linuxcnc_lathe();
    let e = read("%\n:100\n", &lcnc).err().unwrap_or_default();
    assert!(
        e.starts_with("2:1: a word letter was expected, not ':'"),
        "{e}"
    );
    let e = read("G0 X30 Z5\nM3 S500\nG33 Z-20 F1.5\n", &lcnc).err();
    assert_eq!(
        e.as_deref(),
        Some("3:1: G33 needs K, the lead in mm per revolution (in Fanuc's dialect, F: `dialect fanuc`)")
    );
}

/// Work offsets G54–G59 in Fanuc's dialect (docs/lathe-gcode.md "Work offsets"; stop 57,
/// refused before): G10 L2 with X on the diameter, Fanuc's #5221/#5222 numbering (X on the
/// diameter, Z) read and written at once, #4014 and #5001/#5002 in the program's coordinates,
/// and a G92 shift on top of the work system in force, kept when it changes. Worked by hand:
/// the machine X (radius) and Z of each move.
#[test]
fn work_offsets_in_fanuc_s_dialect_move_the_program_s_zero() {
    let desc = lathe();
    let p = "G10 L2 P1 X0 Z-50.\nG10 L2 P2 X4. Z-80.\nT0101\n\
             G0 X20. Z2.\nG55 G0 X20. Z2.\n#5242 = #5242 + 10.\nG0 X20. Z2.\n#5241 = 0\nG0 X20.\n\
             #1 = #5001\n#2 = #5002\n#3 = #4014\nG0 X[#1 + #3 - 55.] Z[#2 + 1.]\n\
             G92 X30. Z5.\nG0 X20. Z0\nG54 G0 X20. Z0\nM30\n";
    assert_eq!(
        ok(p, &desc),
        [
            // G54: Z -50.
            "R X10.000 Z-48.000",
            // G55: X +2 (a radius: X4. is a diameter), Z -80.
            "R X12.000 Z-78.000",
            // #5242 (G55's Z) written: -70 at once.
            "R X12.000 Z-68.000",
            // #5241 (G55's X) written 0.
            "R X10.000 Z-68.000",
            // #5001 = 20 (the diameter), #5002 = 2, #4014 = 55: X20 Z3.
            "R X10.000 Z-67.000",
            // G92 X30. Z5. where the tool stands: the zero shifted by X -5 (radius), Z -2.
            "R X5.000 Z-72.000",
            // G54 with the same shift on top.
            "R X5.000 Z-52.000",
        ]
    );
    // Fanuc's external offset and G10 without L (its tool offsets) are refused.
    assert_eq!(
        read("G10 L2 P0 Z1.\n", &desc).err().as_deref(),
        Some("1:8: G10 L2 P0: Fanuc's external work offset (shifting every work system) is not on this lathe: set G54–G59 with P1–P6")
    );
    let e = read("#1 = #5201\n", &desc).err().unwrap_or_default();
    assert!(
        e.starts_with("1:6: #5201: Fanuc's external work offset"),
        "{e}"
    );
    let e = read("G10 P1 X1. Z1.\n", &desc).err().unwrap_or_default();
    assert!(
        e.starts_with("1:1: G10 P X Z without L is Fanuc's tool offset setting"),
        "{e}"
    );
    // Fanuc's L20 is its additional work systems (G54.1), not LinuxCNC's measure.
    let e = read("G10 L20 P1 Z0\n", &desc).err().unwrap_or_default();
    assert!(
        e.starts_with("1:5: G10 L20 sets Fanuc's additional work systems (G54.1 P1–P48): the lathe has G54–G59"),
        "{e}"
    );
}

/// Every cycle measures from the program's zero: a program with G71/G70 (an arc in its
/// profile), G83, G74, G76 (both blocks) and G32 read in G55 (Z -40) cuts the same moves as in
/// G54, each one shifted by the offset and nothing else (after its first move, which starts
/// from the reference position): the same arc centres, feeds and leads. A work offset in X
/// puts X0 off the spindle's centre line, where the drill cannot go: G83 says so.
#[test]
fn every_cycle_is_cut_at_the_work_offset_s_zero() {
    let desc = lathe();
    let body = "G21 G95\nT0101\nG97 S800 M3\nG0 X30. Z2.\nG1 Z-20. F0.2\nG0 X40. Z2.\n\
                G71 U1. R0.5\nG71 P10 Q20 U0.2 W0.1 F0.2\nN10 G0 X20.\nG1 Z-10.\n\
                G3 X26. Z-13. R3.\nN20 G1 X30.\nG70 P10 Q20\nG0 X0 Z5.\nG83 Z-10. Q2000 F0.1\n\
                G80\nG0 X0 Z5.\nG74 R1.\nG74 Z-6. Q3000 F0.1\nG0 X40. Z5.\nT0202\nG0 X32. Z4.\n\
                G76 P010060 Q100 R0.02\nG76 X27.4 Z-15. P1300 Q400 F2.\nG0 X30. Z5.\n\
                G32 Z-20. F1.5\nG0 X40. Z5.\nM30\n";
    let plain = lathe_moves::read(body, &desc).unwrap_or_else(|e| panic!("{e}"));
    let shifted = lathe_moves::read(&format!("G10 L2 P2 X0 Z-40.\nG55\n{body}"), &desc)
        .unwrap_or_else(|e| panic!("{e}"));
    let blocks = |p: &[novanc::block::Statement]| -> Vec<novanc::block::Block> {
        p.iter().flat_map(|s| s.blocks.clone()).collect()
    };
    let (a, b) = (blocks(&plain), blocks(&shifted));
    assert_eq!(a.len(), b.len());
    assert!(a.len() > 100, "{}", a.len());
    let mut moves = 0;
    for (i, (a, b)) in a.iter().zip(&b).enumerate().skip(1) {
        use novanc::block::Motion;
        assert_eq!(a.motion, b.motion, "block {i}");
        if matches!(a.motion, Motion::Aux | Motion::Dwell) {
            continue;
        }
        moves += 1;
        assert_eq!(
            [b.end[0] - a.end[0], b.end[2] - a.end[2]],
            [0, -40_000],
            "block {i}: {a:?}\n{b:?}"
        );
        // An arc's centre is from its start: the same.
        assert_eq!(a.center, b.center, "block {i}");
        assert_eq!((a.feed, a.thread), (b.feed, b.thread), "block {i}");
    }
    assert!(moves > 100, "{moves}");
    let e = lathe_moves::read(&format!("G10 L2 P2 X6. Z-40.\nG55\n{body}"), &desc)
        .err()
        .unwrap_or_default();
    assert!(
        e.starts_with("17:1: G83 with the tool at X0.000, X6.000 from the spindle's centre line: the lathe drills on the centre line only"),
        "{e}"
    );
}

/// The same lathe with calculator-type input (`decimal calculator`, Fanuc's 3401#0 DPI = 1).
fn calculator_lathe() -> LatheDesc {
    let mut d = lathe();
    d.channels[0].calculator = Some(true);
    d
}

/// A program written without decimal points (a real Spanish course program threads and turns
/// that way) reads on a calculator-type lathe as the same program with its points reads on
/// the default one: `X30` is 30 mm. The words Fanuc takes in least increments only (G74,
/// G76 and G83's Q, G76's P) stay in increments, and G70/G71's P and Q stay sequence numbers.
#[test]
fn calculator_type_input_reads_a_program_without_points_as_written() {
    let pointed = "G21 G95\nT0101\nG97 S800 M3\nG0 X30. Z2.\nG1 Z-20. F0.2\nG0 X40.\n\
                   G71 U1. R0.5\nG71 P10 Q20 U0.2 W0.1 F0.2\nN10 G0 X20.\nG1 Z-10.\nN20 X30.\n\
                   G70 P10 Q20\nG0 X0 Z5.\nG83 Z-10. Q2000 F0.1\nG80\nG0 X0 Z5.\n\
                   G74 R1.\nG74 Z-6. Q3000 F0.1\nG0 X40. Z5.\nT0202\nG0 X32. Z4.\n\
                   G76 P010060 Q100 R0.02\nG76 X27.4 Z-15. P1300 Q400 F2.\nG0 X40. Z5.\nM30\n";
    let plain = pointed.replace(".\n", "\n").replace(". ", " ");
    assert!(plain.contains("G0 X30 Z2\n") && plain.contains("G83 Z-10 Q2000"));
    let want = ok(pointed, &lathe());
    assert_eq!(ok(&plain, &calculator_lathe()), want);
    // Without calculator-type input the same plain program is read in least increments
    // (X30 is 0.030 mm): another program.
    assert_ne!(
        lathe_moves::read(&plain, &lathe()).map(|p| lathe_moves::moves(&p, false)),
        Ok(want)
    );
}

/// The description's `decimal calculator` line, machine-wide or in a channel.
#[test]
fn a_lathe_description_takes_decimal_calculator() {
    let base = "machine m\nkind lathe\npulse 0.001\ndialect fanuc\n";
    let chan =
        "channel A\nx travel 0 100 rapid 1000 accel 100\nz travel -100 100 rapid 1000 accel 100\n\
                spindle max 1000 accel 1000 encoder 100\n";
    for (text, want) in [
        (format!("{base}decimal calculator\n{chan}"), Some(true)),
        (format!("{base}{chan}decimal calculator\n"), Some(true)),
        (format!("{base}{chan}decimal increments\n"), Some(false)),
        (format!("{base}{chan}"), None),
    ] {
        match parse(&text) {
            Ok(MachineDesc::Lathe(d)) => assert_eq!(d.channels[0].calculator, want, "{text}"),
            other => panic!("{text}: {other:?}"),
        }
    }
}

/// A one-channel lathe in LinuxCNC's dialect, loaded by hand; tools 7 and 9 with their own tip
/// offsets (X a radius, Z), no nose radius.
fn linuxcnc_lathe() -> LatheDesc {
    let text = "machine lcnc\nkind lathe\npulse 0.001\ntick 100\nloading manual\nchannel PATH-1\n\
                x travel -100 100 rapid 12000 accel 3000\nz travel -100 100 rapid 15000 accel 3000\n\
                spindle max 4000 accel 4000 encoder 1024\ntool 7 radius 0 tip 3 offset 1 2\n\
                tool 9 radius 0 tip 3 offset 3 5\n";
    match parse(text) {
        Ok(MachineDesc::Lathe(d)) => d,
        Ok(MachineDesc::Mill(_)) => panic!("a mill"),
        Err(e) => panic!("{e}"),
    }
}

/// LinuxCNC's own lathe samples (`nc_files/lathecomp.ngc`, `tests/ccomp/lathe-comp`, from its
/// repository, not in ours) begin with `T0 M6`, LinuxCNC's empty pocket, and take tool 9's
/// offsets on tool 7 with `T7 M6` then `G43 H9`. Both were refused (stop 49): T0 as a tool not
/// on the post, H9 as not the tool in place. T0 now cancels the offsets of the tool in place
/// and indexes nothing; G43 H of another tool puts that tool's offsets on the tool in place,
/// until the next T. `G91.1` (arc centres from the start, the lathe's one mode, as
/// LinuxCNC's gmoccapy `drilling.ngc` writes it) is read.
#[test]
fn t0_and_g43_with_another_tool_s_h_read_as_linuxcnc_reads_them() {
    let desc = linuxcnc_lathe();
    // Offsets add to the programmed point: tool 7's (X 1, Z 2), then tool 9's (X 3, Z 5).
    let moves = ok(
        "G18 G21 G90 G91.1\nT0 M6\nG0 X10 Z10\nT7 M6\nG43\nG0 X10 Z10\nG43 H9\nG0 X20 Z10\n\
         T0\nG0 X20 Z20\nM30\n",
        &desc,
    );
    assert_eq!(
        moves,
        [
            "R X5.000 Z10.000",
            "R X6.000 Z12.000",
            "R X13.000 Z15.000",
            "R X10.000 Z20.000"
        ]
    );
    // An H that names no tool on the post is refused at its word.
    let e = lathe_moves::read("T7 M6\nG43 H8\nM30\n", &desc).unwrap_err();
    assert_eq!(e, "2:5: G43 H8: no tool 8 on channel 1's tool post");
}
