//! The codes every shop lathe program carries around its cuts (docs/lathe-gcode.md "Shop
//! codes"): G28 U0 W0, coolant M08/M09, G80 and G54 in a safe-start line, Fanuc's G74/G75
//! peck cycles and a G71 whose Q is written without a point. Moves worked out by hand from
//! each program, not by the reader.

use novanc::lathe::desc::{parse, LatheDesc, MachineDesc};

/// A one-channel lathe: X travel 0..100 (radius), Z −100..100; tool 1 with offsets X 2 (radius)
/// Z −3, tool 2 without; in `dialect`.
fn lathe(dialect: &str) -> LatheDesc {
    lathe_with(dialect, "")
}

/// [`lathe`] with `more` lines of the description before its channel.
fn lathe_with(dialect: &str, more: &str) -> LatheDesc {
    let text = format!(
        "machine shop\nkind lathe\npulse 0.001\ntick 100\ndialect {dialect}\n{more}channel PATH-1\n\
         x travel 0 100 rapid 12000 accel 3000\nz travel -100 100 rapid 15000 accel 3000\n\
         spindle max 4000 accel 4000 encoder 1024\ntool 1 radius 0 tip 3 offset 2 -3\n\
         tool 2 radius 0 tip 3\n"
    );
    lathe_desc(&text)
}

/// The lathe a description's `text` describes; a description that does not parse, or a mill,
/// fails the test.
fn lathe_desc(text: &str) -> LatheDesc {
    match parse(text) {
        Ok(MachineDesc::Lathe(d)) => d,
        other => panic!("{other:?}"),
    }
}

#[path = "common/lathe_moves.rs"]
mod lathe_moves;
use lathe_moves::read;

/// The moves in brief (no dwells).
fn ok(text: &str, desc: &LatheDesc) -> Vec<String> {
    lathe_moves::ok(text, desc, false)
}

#[test]
fn g28_returns_the_axes_named_through_the_intermediate_point_to_the_reference() {
    let desc = lathe("fanuc");
    // Tool 1's offsets (X +2 radius, Z −3) move every programmed point: X40. Z5. is the slide
    // at X 20+2 = 22, Z 5−3 = 2. The reference is the top of the travels: X100 Z100.
    let p = "G95 T0101\nG0 X40. Z5.\nG28 U0 W0\n";
    assert_eq!(
        ok(p, &desc),
        ["R X22.000 Z2.000", "R X100.000 Z100.000"],
        "U0 W0: the intermediate point is where the tool stands, then both axes home"
    );
    // One axis named: only it returns; the intermediate point X30. (radius 15 + 2 = 17) first.
    let p = "G95 T0101\nG0 X40. Z5.\nG28 X30.\n";
    assert_eq!(
        ok(p, &desc),
        ["R X22.000 Z2.000", "R X17.000 Z2.000", "R X100.000 Z2.000"]
    );
    // After G28 the program goes on from the reference: W-10. is 10 mm below it, the offset
    // still applied (the slide at Z 90).
    let p = "G95 T0101\nG28 G0 U0 W0\nW-10.\n";
    assert_eq!(ok(p, &desc), ["R X100.000 Z90.000"]);
    // Fanuc returns only the axes named: G28 alone is refused, where LinuxCNC's dialect
    // returns both (its G28 goes to the stored position, here the reference).
    assert_eq!(
        read("G0 X40. Z5.\nG28\n", &desc).err().as_deref(),
        Some("2:1: G28 names no axis: give the axes to return, U0 W0 (a Fanuc returns only the axes named; a description's 'g28 alone all' returns both, as a Haas does)")
    );
    // A Haas returns every axis: the description says so with `g28 alone all`.
    let haas = lathe_with("fanuc", "g28 alone all\n");
    assert_eq!(
        ok("G0 X40. Z5.\nG28\n", &haas),
        ["R X20.000 Z5.000", "R X100.000 Z100.000"]
    );
    let lcnc = lathe("linuxcnc");
    assert_eq!(
        ok("G0 X40 Z5\nG28\n", &lcnc),
        ["R X20.000 Z5.000", "R X100.000 Z100.000"]
    );
    // Under nose-radius compensation the reference is refused: it is the slide's.
    let e = read("T0202\nG42 G0 X40. Z5.\nG28 U0 W0\n", &desc).err();
    assert!(
        e.as_deref()
            .is_some_and(|e| e.starts_with("3:1: G28 under nose-radius compensation")),
        "{e:?}"
    );
}

#[test]
fn a_safe_start_line_and_coolant_are_read_and_act() {
    let desc = lathe("fanuc");
    // G18 G21 G40 G80 G99-style safe start: G80 and G54 are accepted (no drilling cycle can be
    // in force, and G54 is the lathe's one work system); coolant makes its blocks.
    let p = read(
        "G0 G18 G21 G40 G80 G54\nM08\nG95 M03 S500\nG1 X10. Z0 F0.1 M09\n",
        &desc,
    )
    .unwrap_or_else(|e| panic!("{e}"));
    let ms: Vec<u8> = p
        .iter()
        .flat_map(|s| &s.blocks)
        .filter_map(|b| b.m)
        .collect();
    assert_eq!(
        ms,
        [8, 3, 9],
        "M08 and M09 each make a block with their code"
    );
    // G54–G59 are the lathe's work systems since stop 57 (docs/lathe-gcode.md "Work
    // offsets"); LinuxCNC's G59.1–G59.3 are refused with what the lathe has instead.
    assert!(read("G55\n", &desc).is_ok());
    assert_eq!(
        read("G59.1\n", &desc).err().as_deref(),
        Some("1:1: unknown or unsupported code G59.1 (the lathe's work systems are G54 to G59)")
    );
}

#[test]
fn g53_moves_the_slide_to_machine_positions_without_the_tools_offsets() {
    // Tool 1's offsets (X +2 radius, Z −3) are not added: G53 X0 Z50 is the slide at X 0,
    // Z 50, where X0 Z50 is the slide at X 2, Z 47. X is a diameter in G07 (X40. is a radius
    // of 20). A Fanuc moves at rapid whatever the mode (the Haas form `G53 G00 X0.` too).
    let fanuc = lathe("fanuc");
    let p = "G95 T0101 M3 S500\nG0 X40. Z5.\nG1 Z0. F0.1\nG53 X40. Z50.\nG53 G00 X0.\nX40.\n";
    assert_eq!(
        ok(p, &fanuc),
        [
            "R X22.000 Z2.000",
            "F X22.000 Z-3.000",
            "R X20.000 Z50.000",
            "R X0.000 Z50.000",
            "R X22.000 Z50.000"
        ],
        "after G53 the program goes on from where the slide stands, the offsets applied again"
    );
    // LinuxCNC moves in the G00 or G01 in force, in radius under G08 (ngcgui's
    // `G53 G0 X0 Z0` at the end of its lathe subroutines).
    let lcnc = lathe("linuxcnc");
    let p = "T1 M6 G43\nG8 G0 X20 Z5\nG53 G1 X10 Z20 F100\nG53 G0 X0 Z0\n";
    assert_eq!(
        ok(p, &lcnc),
        ["R X22.000 Z2.000", "F X10.000 Z20.000", "R X0.000 Z0.000"]
    );
    for (text, want) in [
        ("G0 X20 Z5\nG53 G2 X10 Z0 R5\n", "2:1: G53 moves in G00 or G01 only: give one on the line"),
        ("G0 X20 Z5\nG53 G0 U10\n", "2:8: G53 takes X and Z, machine positions: U and W are increments"),
        ("G0 X20 Z5\nG91 G53 G0 X10\n", "2:5: G53 in incremental distance (G91): give G90"),
        ("G0 X20 Z5\nG53 G0\n", "2:1: G53 names no axis: give X or Z, machine positions"),
        ("T1 M6 G43\nG0 X20 Z5\nG42 G1 X10 F100\nG53 G1 X30\n", "4:1: G53 under nose-radius compensation: give G40 first (machine coordinates are the slide's, not the nose's)"),
    ] {
        assert_eq!(read(text, &lcnc).err().as_deref(), Some(want), "{text}");
    }
}

#[test]
fn g74_pecks_along_z_and_g75_along_x_as_fanuc_0i_t() {
    let desc = lathe("fanuc");
    // Peck drilling on the centre line with tool 2 (no offsets): from Z2., 4 mm pecks to Z-10.,
    // backing off 1 mm (the first block's R) after each peck but the last, then back to Z2.
    let p = "T0202 G95 M03 S800\nG0 X0 Z2.\nG74 R1.\nG74 Z-10. Q4000 F0.1\nG0 X50.\n";
    assert_eq!(
        ok(p, &desc),
        [
            "R X0.000 Z2.000",
            "F X0.000 Z-2.000",
            "R X0.000 Z-1.000",
            "F X0.000 Z-6.000",
            "R X0.000 Z-5.000",
            "F X0.000 Z-10.000",
            "R X0.000 Z2.000",
            "R X25.000 Z2.000",
        ]
    );
    // Grooving: from X30. Z-20. (radius 15) to X20. (radius 10) in pecks 2 mm deeper each
    // (P2000, a radius), backing off 0.5 after each; a second groove 3 mm on (Q3000), which
    // is the last, at Z-23.
    let p = "T0202 G95 M03 S800\nG0 X30. Z-20.\nG75 R0.5\nG75 X20. Z-23. P2000 Q3000 F0.05\n";
    assert_eq!(
        ok(p, &desc),
        [
            "R X15.000 Z-20.000",
            "F X13.000 Z-20.000",
            "R X13.500 Z-20.000",
            "F X11.000 Z-20.000",
            "R X11.500 Z-20.000",
            "F X10.000 Z-20.000",
            "R X15.000 Z-20.000",
            "R X15.000 Z-23.000",
            "F X13.000 Z-23.000",
            "R X13.500 Z-23.000",
            "F X11.000 Z-23.000",
            "R X11.500 Z-23.000",
            "F X10.000 Z-23.000",
            "R X15.000 Z-23.000",
            "R X15.000 Z-20.000",
        ]
    );
    // The one-block form (Fanuc's Series 15 format, a Haas's): I, K and D are the second
    // block's P, Q and R as lengths, `I2.` for `P2000`; the return is the first block's R.
    let one = "T0202 G95 M03 S800\nG0 X30. Z-20.\nG75 R0.5\nG75 X20. Z-23. I2. K3. F0.05\n";
    let two = "T0202 G95 M03 S800\nG0 X30. Z-20.\nG75 R0.5\nG75 X20. Z-23. P2000 Q3000 F0.05\n";
    assert_eq!(ok(one, &desc), ok(two, &desc));
    // Without a point, I and K are least increments, as on an arc; with G74, K pecks along Z.
    let p = "T0202 G95 M03 S800\nG0 X0 Z2.\nG74 R1.\nG74 Z-10. K4000 F0.1\nG0 X50.\n";
    let q = "T0202 G95 M03 S800\nG0 X0 Z2.\nG74 R1.\nG74 Z-10. Q4000 F0.1\nG0 X50.\n";
    assert_eq!(ok(p, &desc), ok(q, &desc));
    // A Haas parting line: from X0.05 (inch, a radius of 0.635 mm), pecks of 0.01 in
    // (0.254 mm) to the centre, with no return before a first block (each peck follows the
    // last without backing off), then back out.
    let p = "G20 T0202 G95 M03 S800\nG0 X0.05 Z0.\nG75 X0. I0.01 F0.002\n";
    assert_eq!(
        ok(p, &desc),
        [
            "R X0.635 Z0.000",
            "F X0.381 Z0.000",
            "F X0.127 Z0.000",
            "F X0.000 Z0.000",
            "R X0.635 Z0.000",
        ]
    );
    // Refusals, each at its place.
    for (text, want) in [
        (
            "T0202 G95 M03 S800\nG0 X30. Z-20.\nG75 X20. Z-23. I2. Q3000 F0.05\n",
            "3:20: G75 Q beside I: give the one-block form's I, K and D or the two-block form's P, Q and R",
        ),
        (
            "T0202 G95 M03 S800\nG0 X30. Z-20.\nG75 X20. Z-23. I2. F0.05\n",
            "3:1: G75 needs K, the shift between grooves, above 0",
        ),
        (
            "T0202 G95 M03 S800\nG0 X0 Z2.\nG74 Z-10. Q4. F0.1\n",
            "3:11: G74 Q: in least increments, without a decimal point (P1000 is 1.000 mm)",
        ),
        (
            "T0202 G95 M03 S800\nG0 X0 Z2.\nG74 Z-10. F0.1\n",
            "3:1: G74 needs Q, the depth of each peck, above 0",
        ),
        (
            "T0202 G95 M03 S800\nG0 X30. Z-20.\nG75 X20. Z-23. P2000 F0.05\n",
            "3:1: G75 needs Q, the shift between grooves, above 0",
        ),
    ] {
        assert_eq!(read(text, &desc).err().as_deref(), Some(want), "{text}");
    }
    // LinuxCNC has no G74: its dialect refuses it and says which reads it.
    let e = read("G0 X0 Z2\nG74 Z-10 Q4 F100\n", &lathe("linuxcnc")).err();
    assert!(
        e.as_deref()
            .is_some_and(|e| e.starts_with("2:1: G74 is Fanuc's peck cycle")),
        "{e:?}"
    );
}

#[test]
fn a_fanuc_g71_q_without_a_point_is_a_sequence_number() {
    let desc = lathe("fanuc");
    // `Q20` would be 0.020 mm as a length; in G71 and G70 it is N20.
    let p = "T0202 G95 M03 S800\nG0 X52. Z2.\nG71 U2. R0.5\nG71 P10 Q20 U0 W0 F0.2\n\
             N10 G0 X46.\nG1 Z-10. F0.1\nN20 X52.\nG70 P10 Q20\n";
    let m = ok(p, &desc);
    // Roughing from radius 26 to 23 in 2 mm cuts: radius 24 then 23 (the profile), ...
    assert!(m.contains(&"F X24.000 Z-10.000".to_string()), "{m:?}");
    // ... and G70's finishing pass runs N10..N20 and returns to the start.
    assert_eq!(
        m[m.len() - 4..],
        [
            "R X23.000 Z2.000",
            "F X23.000 Z-10.000",
            "F X26.000 Z-10.000",
            "R X26.000 Z2.000"
        ]
    );
}

mod common;

/// A lathe of one channel that the operator loads by hand, in Fanuc's dialect.
const BY_HAND: &str = "machine byhand\nkind lathe\npulse 0.001\ntick 100\ndialect fanuc\n\
    loading manual\nchannel PATH-1\nx travel 0 100 rapid 12000 accel 3000\n\
    z travel -100 100 rapid 15000 accel 3000\nspindle max 4000 accel 4000 encoder 1024\n\
    tool 1 radius 0 tip 3\n";

#[test]
fn a_lathe_loaded_by_hand_runs_a_program_without_chuck_codes_part_after_part() {
    // A shop program: no M10/M11 (the operator loads the work and closes the chuck).
    let prog = "O1000\nG21 G40 G80 G95\nG28 U0 W0\nT0101\nG97 S1000 M03\nM08\n\
                G0 X42. Z2.\nG1 Z-20. F0.2\nG0 X50.\nG28 U0 W0\nM09 M05\nM30\n";
    let dir = common::temp_dir("byhand");
    std::fs::write(dir.join("byhand.machine"), BY_HAND).unwrap();
    std::fs::write(dir.join("o1000.nc"), prog).unwrap();
    let run = |machine: &str| {
        let out = common::novanc_command()
            .args(["run", "--machine"])
            .arg(dir.join(machine))
            .arg(dir.join("o1000.nc"))
            .args(["--parts", "3"])
            .output()
            .unwrap();
        (
            out.status.code(),
            format!(
                "{}{}",
                String::from_utf8_lossy(&out.stdout),
                String::from_utf8_lossy(&out.stderr)
            ),
        )
    };
    let (code, text) = run("byhand.machine");
    assert_eq!(code, Some(0), "{text}");
    assert!(text.contains("parts: 3"), "{text}");
    // The recording says who loaded each work: the operator (its chunks are not compressed,
    // so the event texts stand in the file as written).
    let rec = dir.join("byhand.mcap");
    let out = common::novanc_command()
        .args(["run", "--machine"])
        .arg(dir.join("byhand.machine"))
        .arg(dir.join("o1000.nc"))
        .args(["--parts", "2", "--record"])
        .arg(&rec)
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(0));
    let bytes = std::fs::read(&rec).unwrap_or_default();
    let count = |needle: &str| {
        bytes
            .windows(needle.len())
            .filter(|w| *w == needle.as_bytes())
            .count()
    };
    assert_eq!(count("W1 OPERATOR -> CH1"), 1);
    assert_eq!(count("W2 CH1 -> OPERATOR (both chucks closed)"), 1);
    assert_eq!(count("BAR FEEDER"), 0);
    // The same lathe with the bar feeder's loading (the default) refuses the first cut: no
    // work in the spindle, as the chuck interlock says; nothing was cut.
    std::fs::write(
        dir.join("bar.machine"),
        BY_HAND.replace("loading manual\n", ""),
    )
    .unwrap();
    let (code, text) = run("bar.machine");
    assert_ne!(code, Some(0), "{text}");
    assert!(text.contains("no work in the spindle of CH1"), "{text}");
    // Loaded by hand, the program does not work the chuck: M10 is refused with why.
    std::fs::write(dir.join("o1000.nc"), prog.replace("M08\n", "M10\n")).unwrap();
    let (code, text) = run("byhand.machine");
    assert_ne!(code, Some(0), "{text}");
    assert!(
        text.contains("M10: the operator loads this lathe by hand"),
        "{text}"
    );
}

#[test]
fn loading_by_hand_is_for_a_lathe_of_one_channel() {
    let three = novanc::lathe::desc::CITIZEN.replacen("tick 100", "tick 100\nloading manual", 1);
    let e = parse(&three).err();
    assert!(
        e.as_deref()
            .is_some_and(|e| e.contains("loading manual: a lathe of one channel")),
        "{e:?}"
    );
    let e = parse(&BY_HAND.replace("loading manual", "loading auto")).err();
    assert!(
        e.as_deref().is_some_and(|e| e.starts_with("6: loading:")),
        "{e:?}"
    );
}

#[test]
fn a_work_loaded_by_hand_is_the_operators_in_the_lathes_events() {
    use novanc::pulse_core::KernelEvent;
    use novanc::record::Event;
    let text = |from, to, by_hand| match (KernelEvent::Transfer {
        t: 0,
        from,
        to,
        work: 1,
        both_closed: true,
        by_hand,
    })
    .record(None)
    {
        Some(Event::Lathe { text, .. }) => text,
        _ => String::new(),
    };
    assert_eq!(text(None, Some(0), true), "W1 OPERATOR -> CH1");
    assert_eq!(
        text(Some(0), None, true),
        "W1 CH1 -> OPERATOR (both chucks closed)"
    );
    assert_eq!(text(None, Some(0), false), "W1 BAR FEEDER -> CH1");
    assert_eq!(
        text(Some(0), None, false),
        "W1 CH1 -> UNLOADER (both chucks closed)"
    );
}

#[test]
fn g92_sets_where_the_tool_stands_and_g92_1_puts_the_zero_back() {
    // System B's G92 X Z (LinuxCNC's G92 offset; a Fanuc's coordinate system setting in
    // system B, its system A's G50): the point where the tool stands becomes X Z, nothing
    // moves. LinuxCNC's lathe-g76.ngc threads at `G0 Z1.3 / G92 Z0`, then `G92.1`.
    for dialect in ["linuxcnc", "fanuc"] {
        let desc = lathe(dialect);
        // Tool 2 (no offsets), radius mode: at X20 Z10, G92 Z0 makes that Z the zero: Z-5
        // is the slide at Z5. X is untouched. After G92.1 Z-5 is Z-5 again.
        let p = "G95 T0202\nG8 G0 X20. Z10.\nG92 Z0.\nG0 Z-5.\nG92.1\nG0 Z-5.\n";
        assert_eq!(
            ok(p, &desc),
            ["R X20.000 Z10.000", "R X20.000 Z5.000", "R X20.000 Z-5.000"],
            "{dialect}"
        );
        // X as a diameter under G07: G92 X10. at radius 20 puts X 0 at radius 15.
        let p = "G95 T0202\nG7 G0 X40. Z10.\nG92 X10.\nG0 X20.\nG92.2\nG0 X20.\n";
        assert_eq!(
            ok(p, &desc),
            [
                "R X20.000 Z10.000",
                "R X25.000 Z10.000",
                "R X10.000 Z10.000"
            ],
            "{dialect}"
        );
    }
    let lcnc = lathe("linuxcnc");
    for (text, want) in [
        ("G0 X20 Z5\nG92\n", "2:1: G92 needs X or Z: what the point where the tool stands is to be"),
        ("G0 X20 Z5\nG92 W1\n", "2:5: G92 W: shifting the coordinate system by increments is not supported: give G92 X Z, where the tool stands"),
        ("G0 X20 Z5\nG92.1 Z0\n", "2:7: G92.1 takes no axis word"),
        ("G0 X20 Z5\nG92.3\n", "2:1: unknown or unsupported code G92.3 (the lathe keeps no G92 parameters to restore: give G92 X Z)"),
    ] {
        assert_eq!(read(text, &lcnc).err().as_deref(), Some(want), "{text}");
    }
}

/// A machine builder's M codes on a lathe (docs/lathe-gcode.md "A machine builder's M
/// codes"): a Haas's chip conveyor M31 and M33, remapped to subroutines, run where LinuxCNC
/// runs modal group 10 (after the spindle and the coolant, before the dwell and the move), the
/// rest of the line on the return; argspec's words are the subroutine's `#<p>`. Worked out by
/// hand: the subroutines move, so the order shows in the moves.
#[test]
fn a_lathe_calls_the_subroutine_of_an_m_code_its_description_remaps() {
    let desc = lathe_with(
        "fanuc",
        "remap M31 modalgroup=10 ngc=chip_on\nremap M59 modalgroup=10 argspec=Pq ngc=relay\n",
    );
    let subs = "o<chip_on> sub\nG0 U2.\no<chip_on> endsub\n\
                o<relay> sub\nG0 X[#<p>]\no<relay> endsub\n";
    // The subroutine's U2. (1 mm of radius out) comes before the line's dwell (D, ms) and
    // its move, as on LinuxCNC.
    let p = format!("{subs}G95 G0 X40. Z5.\nM8 M31 G4 P500\nM31 G0 X20. Z2.\nM30\n");
    assert_eq!(
        lathe_moves::ok(&p, &desc, true),
        [
            "R X20.000 Z5.000",
            "R X21.000 Z5.000",
            "D 500",
            "R X22.000 Z5.000",
            "R X10.000 Z2.000"
        ]
    );
    // The coolant came before the call: its block stands before the subroutine's move.
    let st = read(&p, &desc).unwrap();
    let blocks: Vec<_> = st.iter().flat_map(|s| &s.blocks).collect();
    let m8 = blocks.iter().position(|b| b.m == Some(8));
    let sub = blocks.iter().position(|b| b.end[0] == 21_000);
    assert!(m8.is_some() && m8 < sub, "{m8:?} {sub:?}");
    // A Haas relay, M59 P1101, as a subroutine that switches an output (the lathe's M64).
    let relay = "o<relay> sub\nM64 P[#<p> - 1100]\no<relay> endsub\nG95 M59 P1101.\nM30\n";
    let st = read(relay, &desc).unwrap_or_else(|e| panic!("{e}"));
    let io: Vec<_> = st
        .iter()
        .flat_map(|s| &s.blocks)
        .filter_map(|b| b.io)
        .collect();
    assert_eq!(
        io,
        [novanc::block::Io::Digital {
            index: 1,
            on: true,
            synced: false
        }]
    );
    // argspec=Pq: P required, given to the subroutine as #<p>.
    let p = format!("{subs}G95 G0 X40. Z5.\nM59 P50.\nM30\n");
    assert_eq!(
        lathe_moves::ok(&p, &desc, false),
        ["R X20.000 Z5.000", "R X25.000 Z5.000"]
    );
    let refused = |text: String, d: &LatheDesc| read(&format!("{subs}{text}"), d).err();
    let e = refused("M59 Q3.\nM30\n".into(), &desc);
    assert!(
        e.as_deref()
            .is_some_and(|e| e.contains("its subroutine needs P on the line (argspec=Pq)")),
        "{e:?}"
    );
    // A word the code's argspec does not name is not the subroutine's: refused once the
    // line's rest runs, not dropped.
    let e = refused("G0 X40. Z5.\nM31 P5\nM30\n".into(), &desc);
    assert_eq!(
        e.as_deref(),
        Some("8:5: the P word is not used by anything on this line")
    );
    // Without the description's line, M31 is the lathe's unknown code.
    let e = refused("M31\nM30\n".into(), &lathe("fanuc"));
    assert_eq!(e.as_deref(), Some("7:1: unknown or unsupported code M31"));
    // Inside its own subroutine it means nothing: refused.
    let own = "o<chip_on> sub\nM31\no<chip_on> endsub\nM31\nM30\n";
    let e = read(own, &desc).err();
    assert!(
        e.as_deref()
            .is_some_and(|e| e.contains("M31 inside a remap subroutine")),
        "{e:?}"
    );
    // A subroutine nowhere to be found: an error of the code, at its place.
    let e = read("G0 X40. Z5.\nM31\nM30\n", &desc).err();
    assert!(
        e.as_deref().is_some_and(|e| e.starts_with(
            "2:1: M31 (remapped to o<chip_on> by the machine description): subroutine o<chip_on>"
        )),
        "{e:?}"
    );
    // In a G71 profile: refused at its line.
    let g71 = "G0 X40. Z2.\nG71 U1. R0.5\nG71 P10 Q20 U0.2 W0.1 F0.2\nN10 G0 X20. M31\nG1 Z-10.\nN20 X40.\nM30\n";
    let e = refused(g71.into(), &desc);
    assert!(
        e.as_deref()
            .is_some_and(|e| e.contains("inside a G70/G71 profile")),
        "{e:?}"
    );
}

/// What a lathe's description may remap, and what it refuses with its line.
#[test]
fn a_lathe_description_remaps_only_codes_the_lathe_does_not_define() {
    let refusal = |more: &str| {
        match parse(&format!(
        "machine shop\nkind lathe\ndialect fanuc\n{more}channel P\nx travel 0 100 rapid 12000 accel 3000\n\
         z travel -100 100 rapid 15000 accel 3000\nspindle max 4000 accel 4000 encoder 1024\n"
    )) {
        Ok(_) => String::new(),
        Err(e) => e,
    }
    };
    assert_eq!(refusal("remap M31 modalgroup=10 ngc=chip_on\n"), "");
    assert_eq!(
        refusal("remap M3 modalgroup=10 ngc=x\n"),
        "4: remap M3: the lathe defines M3 itself; remap an M code it does not define"
    );
    assert!(refusal("remap M101 modalgroup=10 ngc=x\n")
        .starts_with("4: remap M101: M100 to M199 are the lathe's waiting codes"));
    assert!(refusal("remap M6 modalgroup=6 ngc=x\n")
        .starts_with("4: remap M6: the lathe's M6 indexes the turret"));
    assert_eq!(
        refusal("remap M31 modalgroup=10 ngc=a\nremap M31 modalgroup=10 ngc=b\n"),
        "5: M31 is remapped twice"
    );
    assert_eq!(
        refusal("g28 alone maybe\n"),
        "4: g28 takes alone all or alone refuse (what a G28 that names no axis does in the Fanuc dialect)"
    );
    // A channel's own line says it for that channel, beside the machine's.
    let d = lathe_desc(
        "machine shop\nkind lathe\ntransfer 1 2\nremap M31 modalgroup=10 ngc=a\nchannel P\nremap M33 modalgroup=10 ngc=b\n\
         x travel 0 100 rapid 12000 accel 3000\nz travel -100 100 rapid 15000 accel 3000\n\
         spindle max 4000 accel 4000 encoder 1024\nchannel Q\nx travel 0 100 rapid 12000 accel 3000\n\
         z travel -100 100 rapid 15000 accel 3000\nspindle max 4000 accel 4000 encoder 1024\n",
    );
    let codes = |c: usize| {
        d.channels[c]
            .remap_m
            .iter()
            .map(|r| r.code)
            .collect::<Vec<_>>()
    };
    assert_eq!((codes(0), codes(1)), (vec![33, 31], vec![31]));
}

/// Fanuc's G92 in G code system B is system A's G50: `G92 S` limits the spindle under G96
/// (a course program's `G92 S3000`, refused before stop 56 as a G92 without X or Z), and
/// `G92 X Z` sets the coordinate system, as before.
#[test]
fn fanucs_g92_s_in_system_b_limits_the_spindle_as_g50_s_in_system_a() {
    let a = lathe_desc(
        "machine shop\nkind lathe\ndialect fanuc\nchannel P\ngcode system A\n\
         x travel 0 100 rapid 12000 accel 3000\nz travel -100 100 rapid 15000 accel 3000\n\
         spindle max 4000 accel 4000 encoder 1024\ntool 1 radius 0 tip 3\n",
    );
    let b = lathe("fanuc");
    let speeds = |text: &str, d: &LatheDesc| -> Vec<String> {
        let st = read(text, d).unwrap_or_else(|e| panic!("{e}"));
        st.iter()
            .flat_map(|s| &s.blocks)
            .filter_map(|b| b.css.map(|c| format!("{} {}", c.m_per_min, c.limit_rpm)))
            .collect()
    };
    let in_a = speeds("T0101\nG50 S1500\nG96 S200 M3\nG0 X40. Z5.\n", &a);
    let in_b = speeds("T0101\nG92 S1500\nG96 S200 M3\nG0 X40. Z5.\n", &b);
    assert_eq!(in_b, in_a);
    assert!(in_b.iter().any(|s| s.ends_with(" 1500")), "{in_b:?}");
    for (text, want) in [
        ("G92\n", "1:1: G92 needs S (the spindle limit under G96, rpm) or X Z"),
        ("G92 S9000\n", "1:5: G92 S9000: the G96 speed limit must be above 0 and at most the spindle's maximum 4000 rpm"),
    ] {
        let e = read(text, &b).err().unwrap_or_default();
        assert!(e.starts_with(want), "{text}: {e}");
    }
    // LinuxCNC's G92 takes no S: its limit is D.
    let e = read("G92 S1500\n", &lathe("linuxcnc"))
        .err()
        .unwrap_or_default();
    assert!(e.starts_with("1:1: G92 needs X or Z"), "{e}");
}

/// A Haas lathe's `G04 P3.` (three seconds: a Haas reads P with a point as seconds) with the
/// description's `g04 p point seconds` (stop 57; the Haas course programs of
/// docs/lathe-gcode.md "Agreement with LinuxCNC" stopped there), as the channel's line or
/// every channel's; `P3000` stays milliseconds. Without the line it is refused, as Fanuc does.
#[test]
fn a_haas_lathe_reads_g04_p_with_a_point_as_seconds() {
    let dwells = |desc: &LatheDesc| -> Result<Vec<String>, String> {
        let p = read("G04 P3.\nG04 P3000\nG04 U1.5\n", desc)?;
        Ok(lathe_moves::moves(&p, true))
    };
    let haas = lathe_with("fanuc", "g04 p point seconds\n");
    assert_eq!(dwells(&haas).unwrap(), ["D 3000", "D 3000", "D 1500"]);
    let e = dwells(&lathe("fanuc")).unwrap_err();
    assert!(e.starts_with("1:5: G04 P3: P is in milliseconds"), "{e}");
    let d = lathe_desc(
        "machine m\nkind lathe\npulse 0.001\ntick 100\ndialect fanuc\ng04 p point seconds\n\
         channel A\nx travel 0 100 rapid 12000 accel 3000\nz travel -100 100 rapid 15000 accel 3000\n\
         spindle max 4000 accel 4000 encoder 1024\ntool 1 radius 0 tip 3\n",
    );
    assert_eq!(d.channels[0].p_point_seconds, Some(true));
}
