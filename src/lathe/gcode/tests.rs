//! Unit tests of the lathe reader (docs/lathe-gcode.md): modes, spindle, threads, cycles,
//! waiting codes.

use super::*;
use crate::lathe::ops::{Feed, Op, SpeedMode, SpindleDir};

/// The Citizen with room to turn at negative Z.
pub fn wide_desc() -> LatheDesc {
    let mut d = LatheDesc::citizen();
    for c in &mut d.channels {
        c.axes[0].travel = [-1.0, 100.0];
        c.axes[1].travel = [-200.0, 200.0];
    }
    d
}

fn read(text: &str) -> Result<LatheProgram, TranslateError> {
    read_program("t.ngc", text, &wide_desc(), 0, &ReadOptions::default())
}

fn ops(text: &str) -> Vec<Op> {
    match read(text) {
        Ok(p) => p.steps.into_iter().map(|s| s.op).collect(),
        Err(e) => panic!("{e}"),
    }
}

fn ends(o: &[Op]) -> Vec<[i64; 2]> {
    o.iter().filter_map(Op::end).collect()
}

#[test]
fn a_plain_program_reads_with_percent_o_number_n_and_comments() {
    let o = ops("%\nO1000 (PART)\nN5 G18 G21 G90 T0101 ; tool 1\nM3 S1000\nG0 X20 Z2\nG1 Z-10 F100\nG2 X30 Z-15 R5\nM30\n%\n");
    assert_eq!(
        o,
        vec![
            Op::Tool { tool: 1 },
            Op::Spindle {
                dir: SpindleDir::Cw,
                mode: SpeedMode::Rpm(1000.0)
            },
            Op::Rapid { end: [10000, 2000] },
            Op::Line {
                end: [10000, -10000],
                feed: Feed::PerMin(100.0)
            },
            Op::Arc {
                end: [15000, -15000],
                centre: [15000, -10000],
                ccw: false,
                feed: Feed::PerMin(100.0)
            },
            Op::End { m30: true },
        ]
    );
}

#[test]
fn diameter_mode_is_the_default_and_g8_reads_x_as_a_radius() {
    let o = ops("G0 X20 Z0\nG8 G0 X20\nG7 G0 X20\nG91 G0 X-4\nG8 G0 X-4\nU10 W-1\n");
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
    let a = ops("G0 X20 Z0\nG1 F50\nG3 X30 Z-5 I0 K-5\n");
    let b = ops("G8 G0 X10 Z0\nG1 F50\nG3 X15 Z-5 I0 K-5\n");
    assert_eq!(a, b);
    assert!(matches!(
        a[1],
        Op::Arc {
            centre: [10000, -5000],
            ccw: true,
            ..
        }
    ));
    // Inches.
    let o = ops("G20 G8 G0 X1 Z-1\n");
    assert_eq!(ends(&o), vec![[25400, -25400]]);
}

#[test]
fn feed_per_revolution_and_constant_surface_speed() {
    let o = ops("M4 G96 S180 D2500\nG95 G0 X20 Z1\nG1 Z-5 F0.15\nG97 S800\nM5\n");
    assert_eq!(
        o[0],
        Op::Spindle {
            dir: SpindleDir::Ccw,
            mode: SpeedMode::Css {
                m_per_min: 180.0,
                limit_rpm: 2500.0
            }
        }
    );
    assert_eq!(
        o[2],
        Op::Line {
            end: [10000, -5000],
            feed: Feed::PerRev(0.15)
        }
    );
    assert_eq!(
        o[3],
        Op::Spindle {
            dir: SpindleDir::Ccw,
            mode: SpeedMode::Rpm(800.0)
        }
    );
    assert_eq!(
        o[4],
        Op::Spindle {
            dir: SpindleDir::Stop,
            mode: SpeedMode::Rpm(800.0)
        }
    );
    // G96 without D limits at the channel's maximum.
    let o = ops("G96 S100 M3\n");
    assert_eq!(
        o[0],
        Op::Spindle {
            dir: SpindleDir::Cw,
            mode: SpeedMode::Css {
                m_per_min: 100.0,
                limit_rpm: 6000.0
            }
        }
    );
}

#[test]
fn tool_offsets_are_added_to_programmed_points() {
    let mut d = wide_desc();
    d.channels[0].tools[0].offset = [0.5, -1.25];
    let p = read_program(
        "t",
        "T0101\nG0 X20 Z0\nT0100\nG0 X20 Z0\nT1\nG0 Z1\n",
        &d,
        0,
        &ReadOptions::default(),
    );
    let o: Vec<Op> = p
        .unwrap_or_default()
        .steps
        .into_iter()
        .map(|s| s.op)
        .collect();
    assert_eq!(ends(&o), vec![[10500, -1250], [10000, 0], [10500, -250]]);
}

#[test]
fn g33_is_one_thread_pass() {
    let o = ops("M3 S500\nG0 X20 Z5\nG33 Z-20 K1.5\nG33 X22 Z-30 K2\n");
    assert_eq!(
        o[2..],
        [
            Op::Thread {
                end: [10000, -20000],
                lead: 1.5
            },
            Op::Thread {
                end: [11000, -30000],
                lead: 2.0
            }
        ]
    );
}

#[test]
fn g76_q_moves_each_pass_down_the_flank() {
    // The passes of g76_passes_by_hand with Q29.5: each starts and ends (depth - 0.2)·tan 29.5°
    // further along -Z: 0, 0.11315, 0.22631, 0.22631 mm.
    let o = ops("M3 S500\nG8 G0 X10 Z5\nG76 P1.5 Z-20 I-0.5 J0.2 K0.6 H1 Q29.5\n");
    let passes: Vec<(i64, i64)> = o
        .windows(2)
        .filter_map(|w| match (&w[0], &w[1]) {
            (Op::Rapid { end: a }, Op::Thread { end: b, .. }) => Some((a[1], b[1])),
            _ => None,
        })
        .collect();
    assert_eq!(
        passes,
        vec![
            (5000, -20000),
            (4887, -20113),
            (4774, -20226),
            (4774, -20226)
        ]
    );
}

#[test]
fn g76_passes_by_hand() {
    // Drive line X radius 10 at Z5; crest 0.5 below; J0.2, K0.6, R1, one spring pass:
    // depths 0.2, 0.4, 0.6, 0.6 → X radius 9.3, 9.1, 8.9, 8.9, each pass back at the retract
    // X 10 + (0.6 - depth), as LinuxCNC; the last retract is the drive line, so the final
    // move to (X10, Z-20) is already made.
    let o = ops("M3 S500\nG8 G0 X10 Z5\nG76 P1.5 Z-20 I-0.5 J0.2 K0.6 H1\n");
    // In G07 I, J and K are diameters: the same passes with twice the values.
    let g7 = ops("M3 S500\nG0 X20 Z5\nG76 P1.5 Z-20 I-1 J0.4 K1.2 H1\n");
    assert_eq!(o, g7);
    let mut want = Vec::new();
    for (x, back) in [(9300, 10400), (9100, 10200), (8900, 10000), (8900, 10000)] {
        want.push(Op::Rapid { end: [back, 5000] });
        want.push(Op::Rapid { end: [x, 5000] });
        want.push(Op::Thread {
            end: [x, -20000],
            lead: 1.5,
        });
        want.push(Op::Rapid {
            end: [back, -20000],
        });
    }
    assert_eq!(o[2..], want[..]);
    // Internal thread, degression 2: J·√k below K, then K.
    let o = ops("M3 S500\nG8 G0 X10 Z5\nG76 P1 Z-10 I0.5 J0.2 K0.6 R2\n");
    let xs: Vec<i64> = o
        .iter()
        .filter_map(|op| match op {
            Op::Thread { end, .. } => Some(end[0]),
            _ => None,
        })
        .collect();
    assert_eq!(
        xs,
        vec![10700, 10783, 10846, 10900, 10947, 10990, 11029, 11066, 11100]
    );
    assert_eq!(
        cycles::g76_depths(0.2, 0.6, 1.0, 0),
        Some(vec![0.2, 0.4, 0.6])
    );
}

#[test]
fn g71_roughs_by_hand_and_g70_finishes() {
    let text = "T0101 M3 S1000\nG0 X40 Z2\nG71 U2 R0.5\nG71 P10 Q20 U0.4 W0.1 F100\nN10 G0 X20\nG1 Z-10\nN20 G1 X40 Z-20\nG70 P10 Q20\nM30\n";
    let o = ops(text);
    let f = Feed::PerMin(100.0);
    let mut want = vec![
        Op::Tool { tool: 1 },
        Op::Spindle {
            dir: SpindleDir::Cw,
            mode: SpeedMode::Rpm(1000.0),
        },
        Op::Rapid { end: [20000, 2000] },
    ];
    // Levels X 18, 16, 14, 12 (radius) meet the taper shifted by U0.2/W0.1 at
    // Z = -9.9 - (X - 10.2).
    for (x, z) in [
        (18000, -17700),
        (16000, -15700),
        (14000, -13700),
        (12000, -11700),
    ] {
        want.push(Op::Rapid { end: [x, 2000] });
        want.push(Op::Line {
            end: [x, z],
            feed: f,
        });
        want.push(Op::Rapid {
            end: [x + 500, z + 500],
        });
        want.push(Op::Rapid {
            end: [x + 500, 2000],
        });
    }
    want.extend([
        Op::Rapid { end: [10200, 2000] },
        Op::Rapid { end: [10200, 2100] },
        Op::Line {
            end: [10200, -9900],
            feed: f,
        },
        Op::Line {
            end: [20200, -19900],
            feed: f,
        },
        Op::Rapid { end: [20200, 2000] },
        Op::Rapid { end: [20000, 2000] },
        // G70: the profile as written, then back to the start.
        Op::Rapid { end: [10000, 2000] },
        Op::Line {
            end: [10000, -10000],
            feed: f,
        },
        Op::Line {
            end: [20000, -20000],
            feed: f,
        },
        Op::Rapid { end: [20000, 2000] },
        Op::End { m30: true },
    ]);
    assert_eq!(o, want);
}

#[test]
fn g71_follows_an_arc_in_its_profile() {
    let text =
        "G0 X40 Z2\nG71 U3 R0\nG71 P1 Q3 F100\nN1 G0 X10\nN2 G1 Z0\nN3 G2 X40 Z-15 R15\nM30\n";
    let o = ops(text);
    // The arc from (Z0, X5) to (Z-15, X20) clockwise, R15, has its centre at (Z0, X20):
    // level X meets it at Z = -sqrt(225 - (X-20)^2). Levels X radius 17, 14, 11, 8.
    let lines: Vec<[i64; 2]> = o
        .iter()
        .filter_map(|op| match op {
            Op::Line { end, .. } => Some(*end),
            _ => None,
        })
        .collect();
    let z = |x: f64| (-(225.0 - (x - 20.0) * (x - 20.0)).sqrt() * 1000.0).round() as i64;
    assert_eq!(lines[0], [17000, z(17.0)]);
    assert_eq!(lines[3], [8000, z(8.0)]);
}

#[test]
fn waiting_codes_list_channels_by_digits() {
    let o = ops("M100 P12\nM101 P123\nM102\nM103 P1\n");
    assert_eq!(
        o,
        vec![
            Op::Wait {
                m: 100,
                with: 0b011
            },
            Op::Wait {
                m: 101,
                with: 0b111
            },
            Op::Wait {
                m: 102,
                with: 0b111
            },
            Op::Wait {
                m: 103,
                with: 0b001
            },
        ]
    );
    let p = read_program("t", "M150 P23\n", &wide_desc(), 1, &ReadOptions::default());
    assert_eq!(
        p.map(|p| p.steps[0].op.clone()).ok(),
        Some(Op::Wait {
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
    };
    assert!(read_program("t", "/G0 X1 X2\nM2\n", &wide_desc(), 0, &on).is_ok());
    assert!(read("/G0 X1 X2\nM2\n").is_err());
    assert_eq!(
        ops(text),
        vec![
            Op::ChuckClose,
            Op::ChuckOpen,
            Op::Stop { optional: false },
            Op::Dwell { ns: 1_500_000_000 },
            Op::End { m30: false },
        ]
    );
    let d = wide_desc();
    let opts = ReadOptions {
        block_delete: true,
        optional_stop: true,
    };
    let p = read_program("t", text, &d, 0, &opts).unwrap_or_default();
    let o: Vec<Op> = p.steps.into_iter().map(|s| s.op).collect();
    assert_eq!(
        o,
        vec![
            Op::ChuckClose,
            Op::Stop { optional: false },
            Op::Stop { optional: true },
            Op::Dwell { ns: 1_500_000_000 },
            Op::End { m30: false },
        ]
    );
}

#[test]
fn operations_under_compensation_wait_behind_the_held_moves() {
    let o = ops("T0101 M3 S1000\nG0 X30 Z5\nG42 G0 X10 Z2\nG1 Z0 F100\nM10\nG1 X20 Z-10\nG40 G0 X40 Z5\nM30\n");
    let kinds: Vec<&str> = o
        .iter()
        .map(|op| match op {
            Op::Rapid { .. } => "rapid",
            Op::Line { .. } => "line",
            Op::Arc { .. } => "arc",
            Op::ChuckClose => "M10",
            _ => "other",
        })
        .collect();
    assert_eq!(
        kinds,
        ["other", "other", "rapid", "rapid", "line", "M10", "line", "rapid", "other"]
    );
    // The exit move ends where it is programmed.
    assert_eq!(o[7].end(), Some([20000, 5000]));
}

#[test]
fn g71_bores_and_g70_finishes_with_compensation() {
    // A bore: the start (X10, radius 5) is below the profile's first X (radius 10); levels
    // rise by U1 to X radius 6, 7, 8, 9, each cut the whole length to Z-5.
    let text = "T0303 M3 S1000\nG0 X10 Z2\nG71 U1 R0\nG71 P1 Q2 F50\nN1 G41 G0 X20\nN2 G1 Z-5\nG40 G0 X10\nG70 P1 Q2\nM30\n";
    let o = ops(text);
    let cuts: Vec<[i64; 2]> = o
        .iter()
        .filter_map(|op| match op {
            Op::Line { end, .. } => Some(*end),
            _ => None,
        })
        .collect();
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
    let p = read_program("c2.ngc", text, &d, 1, &ReadOptions::default());
    let p = match p {
        Ok(p) => p,
        Err(e) => panic!("{e}"),
    };
    let ops: Vec<&Op> = p.steps.iter().map(|s| &s.op).collect();
    assert_eq!(ops[0], &Op::ChuckClose);
    assert_eq!(
        ops[1],
        &Op::Wait {
            m: 100,
            with: 0b011
        }
    );
    assert!(ops.iter().any(|o| matches!(o, Op::Arc { ccw: true, .. })));
    assert_eq!(ops[ops.len() - 2], &Op::ChuckOpen);
    assert_eq!(p.lines.len(), 14);
    // Tool 1 of channel 2: radius 0.4, tip 3. On the Z cut (line 8) P runs 0.4 above the
    // profile's X radius 5 less 0.4 (tip 3 looks down): on X radius 5 exactly.
    let z_cut = p
        .steps
        .iter()
        .find(|s| s.line == 8 && matches!(s.op, Op::Line { .. }));
    assert_eq!(z_cut.and_then(|s| s.op.end()).map(|e| e[0]), Some(5000));
}

#[test]
fn a_corner_join_shorter_than_a_pulse_is_dropped_not_made_a_full_circle() {
    // G42 turning -Z: the profile dips by 0.002 mm on the diameter over 10 mm, an outside
    // corner of 0.0002 rad whose join arc (0.8 mm radius) is 0.00016 mm long.
    let o = ops(
        "T0101 M3 S1000\nG0 X30 Z5\nG42 G0 X10 Z2\nG1 Z-10 F100\nG1 X9.996 Z-20\nG40 G0 X30\nM30\n",
    );
    assert!(!o.iter().any(|op| matches!(op, Op::Arc { .. })), "{o:?}");
    let e = ends(&o);
    assert!(e.windows(2).all(|w| w[0] != w[1]), "{e:?}");
}

#[test]
fn the_side_changes_without_g40_as_the_thesis_allows() {
    // Towards -Z under G42, then G41 without G40: the held moves end one radius off their
    // last point, then a new entry move on the other side.
    let o = ops("T0303 M3 S1000\nG8 G0 X30 Z5\nG42 G0 X10 Z2\nG1 Z-10 F100\nG41 G1 X20 Z-12\nG1 Z-20\nG40 G0 X30\nM30\n");
    let e = ends(&o);
    // Tool 3: radius 0.2, tip 2 (P = C + 0.2·(+X, -Z)). Under G42 travelling -Z, C is 0.2
    // above X10, so the held run ends with P at (X10.4, Z-10.2).
    assert!(e.contains(&[10400, -10200]), "{e:?}");
    // Under G41 travelling -Z, C is 0.2 below X20: P on X 20.0, Z-20.2.
    assert!(e.contains(&[20000, -20200]), "{e:?}");
}
