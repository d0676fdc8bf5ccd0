//! LinuxCNC 2.9's words (its G-code quick reference: every G code, M code, letter and comment
//! command), each in a small program (docs/gcode.md "Words"): novanc either acts on it, and
//! the effect is checked, or refuses it at its own line and column with a reason that names
//! it. And no line is accepted with a word that none of its codes uses.

mod common;

use novanc::block::{Block, Io, Motion as B, Plane, TranslateError};
use novanc::gcode::state::{CompSide, FeedMode, Motion, PathMode};
use novanc::gcode::{Event, InterpState};

/// Six lines: units, G54 in the middle of the travel, tool 13 (an 8 mm end mill) with its
/// length, a point above the part, a feed and the spindle on. The word's line is line 7.
const PRE: &str =
    "G21 G90\nG10 L2 P1 X300 Y300 Z-400\nG54\nT13 M6 G43 H13\nG0 X10 Y10 Z-10\nF100 S1000 M3\n";

/// What reading `PRE` and the word's lines (as MDI: no end needed) gave.
struct Run {
    /// The blocks of line 7 and after.
    blocks: Vec<Block>,
    state: InterpState,
    events: Vec<Event>,
    err: Option<TranslateError>,
}

fn run(lines: &str) -> Run {
    let mut g = common::gcode_source(&format!("{PRE}{lines}\n")).mdi();
    let mut blocks = Vec::new();
    let mut err = None;
    for r in g.by_ref() {
        match r {
            Ok(s) => blocks.extend(s.blocks.into_iter().filter(|b| b.stmt >= 7)),
            Err(e) => {
                err = Some(e);
                break;
            }
        }
    }
    let events = g.take_events();
    Run {
        blocks,
        state: g.into_state(),
        events,
        err,
    }
}

fn moves(r: &Run, kind: B) -> bool {
    r.blocks.iter().any(|b| b.motion == kind)
}

fn feeds(r: &Run) -> bool {
    moves(r, B::Linear)
}

fn m(r: &Run, code: u8) -> bool {
    r.blocks.iter().any(|b| b.m == Some(code))
}

fn io(r: &Run, f: fn(&Io) -> bool) -> bool {
    r.blocks.iter().any(|b| b.io.as_ref().is_some_and(f))
}

/// Output 1 set `on`, with the next move (`synced`, M62/M63) or at once (M64/M65).
fn digital_out(r: &Run, on: bool, synced: bool) -> bool {
    r.blocks.iter().any(|b| {
        b.io == Some(Io::Digital {
            index: 1,
            on,
            synced,
        })
    })
}

fn motion(r: &Run) -> u16 {
    r.state.modal.motion.code()
}

fn message(r: &Run, kind: &str) -> bool {
    r.events
        .iter()
        .any(|e| matches!(e, Event::Message { kind: k, .. } if *k == kind))
}

/// A LOG message that starts with `text`.
fn says(r: &Run, text: &str) -> bool {
    r.events
        .iter()
        .any(|e| matches!(e, Event::Message { kind: "LOG", text: t } if t.starts_with(text)))
}

fn param(r: &Run, n: usize) -> f64 {
    r.state.params[n]
}

enum Want {
    /// novanc acts: the check holds.
    Acts(fn(&Run) -> bool),
    /// novanc refuses on line 7, at the column of this text in the line, with a message
    /// naming the word (the second text).
    Refused(&'static str, &'static str),
}
use Want::{Acts, Refused};

/// LinuxCNC 2.9's G codes, M codes, letters and comment commands, each with a line using it.
fn cases() -> Vec<(&'static str, Want)> {
    vec![
        ("G0 X20", Acts(|r| moves(r, B::Rapid))),
        ("G1 X20", Acts(feeds)),
        ("G2 X20 Y20 I5 J5", Acts(|r| moves(r, B::ArcCw))),
        ("G3 X20 Y20 I5 J5", Acts(|r| moves(r, B::ArcCcw))),
        (
            "G4 P0.5",
            Acts(|r| r.blocks.iter().any(|b| b.dwell_ns == 500_000_000)),
        ),
        ("G5 X20 Y20 I1 J1 P-1 Q-1", Acts(feeds)),
        ("G5.1 X20 Y20 I1 J1", Acts(feeds)),
        (
            "G5.2 X20 Y20 P1 L3\nX30 Y10 P1\nX40 Y20 P1\nG5.3",
            Acts(feeds),
        ),
        ("G5.3", Refused("G5.3", "G5.3")),
        ("G7", Refused("G7", "G07")),
        ("G8", Refused("G8", "G08")),
        ("G10 L0 P1 Z0", Refused("L0", "G10 L0")),
        (
            "G10 L1 P13 R2",
            Acts(|r| {
                r.events.iter().any(|e| matches!(e, Event::Tool { t: 13, diameter, .. } if (*diameter - 4.0).abs() < 1e-9))
            }),
        ),
        ("G10 L2 P2 X1", Acts(|r| param(r, 5241) == 1.0)),
        (
            "G10 L10 P13 Z1",
            Acts(|r| {
                r.events
                    .iter()
                    .any(|e| matches!(e, Event::Tool { t: 13, .. }))
            }),
        ),
        (
            "G10 L11 P13 Z1",
            Acts(|r| {
                r.events
                    .iter()
                    .any(|e| matches!(e, Event::Tool { t: 13, .. }))
            }),
        ),
        ("G10 L20 P2 X1", Acts(|r| param(r, 5241) != 0.0)),
        ("G18\nG17", Acts(|r| r.state.modal.plane == Plane::XY)),
        ("G17.1", Refused("G17.1", "G17.1")),
        ("G18", Acts(|r| r.state.modal.plane == Plane::XZ)),
        ("G18.1", Refused("G18.1", "G18.1")),
        ("G19", Acts(|r| r.state.modal.plane == Plane::YZ)),
        ("G19.1", Refused("G19.1", "G19.1")),
        ("G20", Acts(|r| r.state.modal.inch)),
        ("G20\nG21", Acts(|r| !r.state.modal.inch)),
        ("G28", Acts(|r| moves(r, B::Rapid))),
        ("G28.1", Acts(|r| param(r, 5163) != 0.0)),
        ("G30", Acts(|r| moves(r, B::Rapid))),
        ("G30.1", Acts(|r| param(r, 5183) != 0.0)),
        // A thread pass geared to the spindle (stop 48); a taper's K is along the path, as
        // LinuxCNC's: the kernel's longest axis is given its share.
        (
            "G33 Z-20 K1",
            Acts(|r| {
                r.blocks.iter().any(|b| b.thread == Some(1.0))
                    && r.state.modal.motion == Motion::Thread
            }),
        ),
        (
            "G33 X20 Z-20 K1",
            Acts(|r| {
                r.blocks.iter().any(|b| {
                    let d = b.delta.xyz().map(|v| v as f64);
                    let share = d.iter().fold(0.0f64, |m, v| m.max(v.abs()))
                        / d.iter().map(|v| v * v).sum::<f64>().sqrt();
                    b.thread.is_some_and(|l| (l - share).abs() < 1e-9) && d[0] != 0.0
                })
            }),
        ),
        // Rigid tapping (stop 48): in geared at K × S, the spindle reversed, out to where
        // the tool stood, the spindle forward again, every block marked as a tap's.
        (
            "G33.1 Z-20 K1",
            Acts(|r| {
                let taps: Vec<_> = r
                    .blocks
                    .iter()
                    .filter(|b| b.tap != novanc::block::Tap::No)
                    .collect();
                taps.len() == 6
                    && taps[0].feed == 1000.0
                    && taps[0].end[2] < taps[3].end[2]
                    && taps[5].m == Some(3)
                    && taps[5].tap == novanc::block::Tap::End
                    && r.state.modal.motion == Motion::RigidTap
            }),
        ),
        ("G33.1 Z-20 K0", Refused("K0", "G33.1 K0")),
        // Probing with nothing to touch: a move that ends without contact is refused
        // (G38.2, G38.4), one that may is a probe move (G38.3, G38.5).
        ("G38.2 Z-30", Refused("G38.2", "G38.2")),
        (
            "G38.3 Z-30",
            Acts(|r| r.blocks.iter().any(|b| b.probe == Some(383))),
        ),
        ("G38.4 Z-30", Refused("G38.4", "G38.4")),
        (
            "G38.5 Z-30",
            Acts(|r| r.blocks.iter().any(|b| b.probe == Some(385))),
        ),
        (
            "G41 D13\nG40",
            Acts(|r| r.state.modal.comp == CompSide::Off),
        ),
        (
            "G41 D13",
            Acts(|r| r.state.modal.comp == CompSide::Left && r.state.comp_radius == 4.0),
        ),
        (
            "G41.1 D5",
            Acts(|r| r.state.modal.comp == CompSide::Left && r.state.comp_radius == 2.5),
        ),
        ("G42 D13", Acts(|r| r.state.modal.comp == CompSide::Right)),
        (
            "G42.1 D5",
            Acts(|r| r.state.modal.comp == CompSide::Right && r.state.comp_radius == 2.5),
        ),
        ("G43 H14", Acts(|r| r.state.tlo_tool == Some(14))),
        ("G43.1 Z1", Acts(|r| r.state.tlo[2] == 1.0)),
        ("G43.2 H14", Acts(|r| r.state.tlo[2] > 0.0)),
        ("G49", Acts(|r| r.state.tlo == [0.0; 3])),
        ("G52 X1", Acts(|r| r.state.g92[0] == 1.0)),
        (
            "G53 G0 Z0",
            Acts(|r| r.blocks.iter().any(|b| b.end[2] == 0)),
        ),
        ("G55", Acts(|r| r.state.modal.cs == 1)),
        ("G56", Acts(|r| r.state.modal.cs == 2)),
        ("G57", Acts(|r| r.state.modal.cs == 3)),
        ("G58", Acts(|r| r.state.modal.cs == 4)),
        ("G59", Acts(|r| r.state.modal.cs == 5)),
        ("G59.1", Acts(|r| r.state.modal.cs == 6)),
        ("G59.2", Acts(|r| r.state.modal.cs == 7)),
        ("G59.3", Acts(|r| r.state.modal.cs == 8)),
        ("G55\nG54", Acts(|r| r.state.modal.cs == 0)),
        ("G61", Acts(|r| r.state.modal.path == PathMode::ExactPath)),
        ("G61.1", Acts(|r| r.state.modal.path == PathMode::ExactStop)),
        (
            "G64 P0.01",
            Acts(|r| matches!(r.state.modal.path, PathMode::Blend { p: Some(_), .. })),
        ),
        ("G70 P1 Q2", Refused("G70", "G70")),
        ("G71 P1 Q2 D1", Refused("G71", "G71")),
        ("G72 P1 Q2 D1", Refused("G72", "G72")),
        ("G73 Z-20 R-5 Q2", Acts(|r| motion(r) == 730 && feeds(r))),
        ("M4\nG74 Z-20 R-5", Acts(|r| motion(r) == 740 && feeds(r))),
        ("G76 P1 Z-20 I1 J1 K1", Refused("G76", "G76")),
        (
            "G81 Z-20 R-5\nG80",
            Acts(|r| r.state.modal.motion == Motion::None),
        ),
        ("G81 Z-20 R-5", Acts(|r| motion(r) == 810 && feeds(r))),
        (
            "G82 Z-20 R-5 P1",
            Acts(|r| motion(r) == 820 && moves(r, B::Dwell)),
        ),
        ("G83 Z-20 R-5 Q2", Acts(|r| motion(r) == 830 && feeds(r))),
        ("G84 Z-20 R-5", Acts(|r| motion(r) == 840 && feeds(r))),
        ("G85 Z-20 R-5", Acts(|r| motion(r) == 850 && feeds(r))),
        ("G86 Z-20 R-5 P1", Acts(|r| motion(r) == 860 && feeds(r))),
        ("G87 Z-20 R-5 I1 J1 K1", Refused("G87", "G87")),
        ("G88 Z-20 R-5 P1", Refused("G88", "G88")),
        ("G89 Z-20 R-5 P1", Acts(|r| motion(r) == 890 && feeds(r))),
        ("G91\nG90", Acts(|r| !r.state.modal.incremental)),
        ("G90.1", Acts(|r| r.state.modal.ijk_absolute)),
        ("G91", Acts(|r| r.state.modal.incremental)),
        ("G90.1\nG91.1", Acts(|r| !r.state.modal.ijk_absolute)),
        (
            "G92 X0",
            Acts(|r| r.state.g92[0] == 10.0 && param(r, 5210) == 1.0),
        ),
        (
            "G92 X0\nG92.1",
            Acts(|r| r.state.g92[0] == 0.0 && param(r, 5211) == 0.0),
        ),
        (
            "G92 X0\nG92.2",
            Acts(|r| r.state.g92[0] == 0.0 && param(r, 5211) == 10.0),
        ),
        ("G92 X0\nG92.2\nG92.3", Acts(|r| r.state.g92[0] == 10.0)),
        (
            "G93",
            Acts(|r| r.state.modal.feed_mode == FeedMode::InverseTime),
        ),
        (
            "G93\nG94",
            Acts(|r| r.state.modal.feed_mode == FeedMode::PerMinute),
        ),
        (
            "G95",
            Acts(|r| r.state.modal.feed_mode == FeedMode::PerRevolution),
        ),
        ("G96 S100", Refused("G96", "G96")),
        ("G97", Acts(|r| r.state.modal.speed == 1000.0)),
        ("G98", Acts(|r| !r.state.modal.retract_r)),
        ("G99", Acts(|r| r.state.modal.retract_r)),
        ("M0", Acts(|r| m(r, 0))),
        ("M1", Acts(|r| m(r, 1) || r.blocks.is_empty())),
        ("M2", Acts(|r| m(r, 2))),
        ("M3", Acts(|r| r.state.modal.spindle == 1)),
        ("M4", Acts(|r| r.state.modal.spindle == -1)),
        ("M5", Acts(|r| r.state.modal.spindle == 0)),
        ("M6 T14", Acts(|r| r.state.tool == Some(14))),
        ("M7", Acts(|r| r.state.modal.mist)),
        ("M8", Acts(|r| r.state.modal.flood)),
        (
            "M8\nM9",
            Acts(|r| !r.state.modal.flood && !r.state.modal.mist),
        ),
        (
            "M19 R90",
            Acts(|r| io(r, |i| matches!(i, Io::Orient { .. }))),
        ),
        (
            "M48",
            Acts(|r| r.state.modal.feed_override && r.state.modal.speed_override),
        ),
        (
            "M49",
            Acts(|r| !r.state.modal.feed_override && !r.state.modal.speed_override),
        ),
        ("M50 P0", Acts(|r| !r.state.modal.feed_override)),
        ("M51 P0", Acts(|r| !r.state.modal.speed_override)),
        ("M52 P1", Acts(|r| r.state.modal.adaptive_feed)),
        ("M53 P1", Acts(|r| r.state.modal.feed_hold)),
        // M60: the pallet shuttle is not there; the program stop is (docs/gcode.md "M codes").
        ("M60", Acts(|r| m(r, 0))),
        ("M61 Q14", Acts(|r| r.state.tool == Some(14))),
        ("M62 P1", Acts(|r| digital_out(r, true, true))),
        ("M63 P1", Acts(|r| digital_out(r, false, true))),
        ("M64 P1", Acts(|r| digital_out(r, true, false))),
        ("M65 P1", Acts(|r| digital_out(r, false, false))),
        (
            "M66 P1 L0",
            Acts(|r| {
                io(r, |i| {
                    matches!(
                        i,
                        Io::Wait {
                            digital: true,
                            index: 1,
                            ..
                        }
                    )
                })
            }),
        ),
        (
            "M67 E1 Q1",
            Acts(|r| {
                io(r, |i| {
                    matches!(
                        i,
                        Io::Analog {
                            index: 1,
                            synced: true,
                            ..
                        }
                    )
                })
            }),
        ),
        (
            "M68 E1 Q1",
            Acts(|r| {
                io(r, |i| {
                    matches!(
                        i,
                        Io::Analog {
                            index: 1,
                            synced: false,
                            ..
                        }
                    )
                })
            }),
        ),
        ("M70\nG20\nM72", Acts(|r| !r.state.modal.inch)),
        ("M70\nM71\nG20\nM72", Refused("M72", "M72")),
        ("M70", Acts(|r| r.state.saved.iter().any(|s| s.is_some()))),
        ("M73", Acts(|r| r.state.saved.iter().any(|s| s.is_some()))),
        ("M98 P100\nM30\nO100\nG1 X1\nM99", Acts(feeds)),
        ("M99", Refused("M99", "M99")),
        // M100–M199 and $ with the reason (before stop 51 "unknown or unsupported").
        (
            "M100",
            Refused("M100", "user programs of a LinuxCNC configuration"),
        ),
        ("M150 P1", Refused("M150", "USER_M_PATH")),
        ("M199", Refused("M199", "M199")),
        // Letters: the axes novanc does not have, the polar words, spindle selection.
        ("G0 A1", Refused("A1", "word A")),
        ("G0 B1", Refused("B1", "word B")),
        ("G0 C1", Refused("C1", "word C")),
        ("G0 U1", Refused("U1", "word U")),
        ("G0 V1", Refused("V1", "word V")),
        ("G0 W1", Refused("W1", "word W")),
        (
            "G1 @20 ^0",
            Acts(|r| r.blocks.iter().any(|b| b.end[0] == 320_000)),
        ),
        ("M3 $1", Refused("$1", "several spindles")),
        ("E1", Refused("E1", "E word")),
        ("N10 G1 X20", Acts(|r| r.state.line_number == 10.0)),
        ("(MSG, hello)", Acts(|r| message(r, "MSG"))),
        ("(PRINT, hello)", Acts(|r| message(r, "PRINT"))),
        ("#5599=1\n(DEBUG, hello)", Acts(|r| message(r, "DEBUG"))),
        ("(LOG, hello)", Acts(|r| message(r, "LOG"))),
        ("(ABORT, stop here)", Refused("(ABORT", "ABORT")),
        // No file is written: the operator is told so, and where the lines go.
        (
            "(LOGOPEN, log.txt)",
            Acts(|r| says(r, "(LOGOPEN,log.txt): novanc writes no log file")),
        ),
        (
            "(LOGAPPEND, log.txt)",
            Acts(|r| says(r, "(LOGAPPEND,log.txt): novanc writes no log file")),
        ),
        (
            "(LOGCLOSE)",
            Acts(|r| says(r, "(LOGCLOSE): novanc writes no log file")),
        ),
        (
            "(PROBEOPEN probe.txt)",
            Acts(|r| says(r, "(PROBEOPEN): novanc writes no probe file")),
        ),
        (
            "(PROBECLOSE)",
            Acts(|r| says(r, "(PROBECLOSE): novanc writes no probe file")),
        ),
    ]
}

#[test]
fn every_word_of_linuxcnc_acts_or_is_refused_with_its_place_and_reason() {
    let mut bad = Vec::new();
    for (lines, want) in cases() {
        let r = run(lines);
        match want {
            Acts(check) => {
                if let Some(e) = &r.err {
                    bad.push(format!("{lines:?}: refused: {e}"));
                } else if !check(&r) {
                    bad.push(format!("{lines:?}: accepted, but without its effect"));
                }
            }
            Refused(at, name) => {
                // Line and column of the word: the case's last line holds it.
                let n = 6 + lines.lines().count() as u32;
                let last = lines.lines().last().unwrap_or("");
                let col = last.find(at).map(|c| c as u32 + 1);
                match &r.err {
                    None => bad.push(format!("{lines:?}: accepted, not refused")),
                    Some(e) if e.line != n || Some(e.col) != col || !e.message.contains(name) => {
                        bad.push(format!(
                            "{lines:?}: refused as {e}, not at {n}:{} naming {name}",
                            col.unwrap_or(0)
                        ))
                    }
                    Some(_) => {}
                }
            }
        }
    }
    assert!(bad.is_empty(), "{}", bad.join("\n"));
}

/// Codes that use none of the value letters D E H I J K L P Q R: each of those letters on
/// their line is refused at its column, naming the letter (rs274 2.9 refuses them all too:
/// "D word with no G code that uses it", ...).
#[test]
fn no_line_is_accepted_with_a_word_its_codes_do_not_use() {
    let plain = [
        "G0 X20", "G1 X20", "G17", "G18", "G20", "G21", "G40", "G49", "G54", "G61", "G80", "G90",
        "G91", "G94", "G97", "G98", "G99", "M3", "M5", "M7", "M8", "M9", "M48", "M49",
    ];
    let mut bad = Vec::new();
    for code in plain {
        for letter in ['D', 'E', 'H', 'I', 'J', 'K', 'L', 'P', 'Q', 'R'] {
            let line = format!("{code} {letter}1");
            let r = run(&line);
            let col = code.len() as u32 + 2;
            match &r.err {
                Some(e) if e.line == 7 && e.col == col && e.message.contains(letter) => {}
                Some(e) => bad.push(format!("{line}: {e}")),
                None => bad.push(format!("{line}: accepted with {letter} unused")),
            }
        }
    }
    assert!(bad.is_empty(), "{}", bad.join("\n"));
}
