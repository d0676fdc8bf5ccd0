//! SEARCH on a lathe of one channel loaded by hand (docs/lathe.md "SEARCH"; stop 57, when the
//! lathe could only start a part from its first line): a line typed in AUTO positions the
//! next START; START restores the tool, the spindle and the coolant the lines before it set,
//! takes the tool there (out in X, along Z, in), and runs the rest of that one part, which
//! counts on with the batch the E-STOP interrupted. RESET lets the point go; a cycle under
//! way refuses it; a lathe of several channels keeps AUTO's line for TARGET and FAULT.

mod common;

use novanc::lathe::console::LatheConsole;
use novanc::lathe::desc::{parse, LatheDesc, MachineDesc};
use novanc::panel_model::{OpMode, PanelEvent};

fn shop() -> LatheDesc {
    let text = "machine shop\nkind lathe\npulse 0.001\ntick 100\nloading manual\ndialect fanuc\n\
                channel PATH-1\ngcode system A\nx travel -5 200 rapid 18000 accel 3000\n\
                z travel -600 100 rapid 24000 accel 3000\nspindle max 6000 accel 3000 encoder 1024\n\
                tool 1 radius 0 tip 3\n";
    match parse(text) {
        Ok(MachineDesc::Lathe(d)) => d,
        other => panic!("{other:?}"),
    }
}

/// Two passes along Z; line 8 (`X36.`) begins the second.
const PROGRAM: &str = "G21 G99 G18\nT0101\nG97 S800 M03\nG00 X40. Z5. M08\nG01 Z-20. F0.2\n\
                       G00 X45.\nZ5.\nX36.\nG01 Z-20.\nG00 X45.\nZ5.\nM09\nM30\n";

fn loaded(dir: &std::path::Path) -> LatheConsole {
    let mut c = LatheConsole::open(shop(), dir, 20, 60, None)
        .unwrap_or_else(|e| panic!("{e}"))
        .0;
    let prog = dir.join("p.nc");
    std::fs::write(&prog, PROGRAM).unwrap();
    c.handle(PanelEvent::Op(OpMode::Data));
    c.handle(PanelEvent::Tape(prog));
    c.handle(PanelEvent::Op(OpMode::Auto));
    c
}

#[test]
fn search_runs_the_rest_of_the_interrupted_part_and_it_counts_with_the_batch() {
    let dir = common::temp_dir("lathe-search");
    let mut c = loaded(&dir);
    c.handle(PanelEvent::Target(3));
    // A full part (machine time, for comparison), then the second part cut short by E-STOP.
    // (A part takes about 19.7 s: two passes of 25 mm at 0.2 mm a revolution, 800 rpm.)
    c.handle(PanelEvent::Start);
    c.handle(PanelEvent::WaitMs(21_000));
    assert_eq!(c.counter().counts, [1]);
    c.handle(PanelEvent::WaitMs(3_000));
    c.handle(PanelEvent::EStop);
    c.handle(PanelEvent::Reset);
    assert_eq!(c.counter().counts, [1]);
    // SEARCH line 8: what START will do. The E-STOP left the tool in the first pass (X40
    // Z-5.394): it goes out in X to the second pass's X45 first, then along Z to Z5.
    c.handle(PanelEvent::Type("8".into()));
    assert_eq!(
        c.message(),
        "SEARCH line 8: START restores T01, S800 M03, M08, G00 X45 Z-5.394, G00 X45 Z5 (machine X Z), then runs one part from there",
        "{:#?}",
        c.view().display
    );
    // The listing stands where START will begin.
    assert!(
        c.view().display.iter().any(|l| l.starts_with(">0008 X36.")),
        "{:#?}",
        c.view().display
    );
    let t0 = c.machine_ns();
    c.handle(PanelEvent::Start);
    // Its part is one more whatever the batch's target: a target below it is refused.
    c.handle(PanelEvent::Target(1));
    assert_eq!(c.message(), "target 1: the part SEARCH runs makes 2");
    c.handle(PanelEvent::Wait);
    // The rest of the part: the second pass and the retract, counted as the batch's second.
    assert_eq!(c.counter().counts, [2]);
    let v = c.view();
    assert_eq!(v.channels[0].pos, [22_500, 5_000]);
    assert_eq!(v.channels[0].tool, 1);
    let took = c.machine_ns() - t0;
    assert!(
        (9_000_000_000..13_000_000_000).contains(&took),
        "{took} ns: one pass and the approach, where the whole part takes about 19.7 s"
    );
    // The point is used: the next START goes on with the batch from the program's top, to
    // its target of 3 (one whole part), and no further.
    c.handle(PanelEvent::Start);
    c.tick(1_000_000);
    // The channel's summary counts the batch, as the title does (it said 0 of 3 here).
    assert_eq!(c.view().channels[0].parts, 2);
    // A target the parts made before this cycle reach is refused: the cycle makes one more
    // (before, it was taken, and the batch ended at 3 of 2: the random operator sequences).
    c.handle(PanelEvent::Target(2));
    assert_eq!(
        c.message(),
        "target 2: 2 made before this cycle, which makes one more (RESET it first)"
    );
    assert_eq!(c.counter().target, 3);
    c.handle(PanelEvent::Wait);
    assert_eq!(c.counter().counts, [3]);
    let whole = c.machine_ns() - t0 - took;
    assert!(whole > 19_000_000_000, "{whole} ns");
    c.handle(PanelEvent::Start);
    assert!(
        c.message().contains("the target of 3 parts is reached"),
        "{}",
        c.message()
    );
    c.close(None).unwrap();
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn search_is_refused_under_way_let_go_at_reset_and_said_where_it_cannot_be() {
    let dir = common::temp_dir("lathe-search-refused");
    let mut c = loaded(&dir);
    c.handle(PanelEvent::Type("99".into()));
    assert_eq!(
        c.message(),
        "SEARCH: the program makes no block at or after line 99"
    );
    c.handle(PanelEvent::Type("NOSUCH".into()));
    assert_eq!(
        c.message(),
        "SEARCH refused: 'NOSUCH' is not in the program"
    );
    // Text: the first line with the word (line 8's X36.).
    c.handle(PanelEvent::Type("X36.".into()));
    assert!(c.message().starts_with("SEARCH line 8:"), "{}", c.message());
    // START while a tool post still moves (a jog coming to rest) is refused and the point
    // kept; at rest, START runs it from where the tool now stands.
    c.handle(PanelEvent::Op(OpMode::Continuous));
    c.handle(PanelEvent::Jog(novanc::panel_model::Axis::Z, -1));
    c.handle(PanelEvent::WaitMs(300));
    c.handle(PanelEvent::JogRelease);
    c.handle(PanelEvent::Op(OpMode::Auto));
    c.handle(PanelEvent::Start);
    assert!(
        c.message().starts_with(
            "START refused: a run is loaded or a tool post moves; SEARCH line 8 is kept"
        ),
        "{}",
        c.message()
    );
    c.handle(PanelEvent::Wait);
    c.handle(PanelEvent::Start);
    c.handle(PanelEvent::Wait);
    assert_eq!(c.counter().counts, [1]);
    c.handle(PanelEvent::Reset);
    c.handle(PanelEvent::Type("0".into()));
    assert_eq!(c.message(), "SEARCH cleared: AUTO starts at the top");
    c.handle(PanelEvent::Start);
    c.handle(PanelEvent::WaitMs(2_000));
    c.handle(PanelEvent::Type("8".into()));
    assert_eq!(
        c.message(),
        "SEARCH refused: a cycle is under way; RESET it first"
    );
    c.close(None).unwrap();
    // The Citizen (three channels, bar-fed): AUTO's line is for TARGET and FAULT, as before.
    let dir2 = common::temp_dir("lathe-search-citizen");
    let mut c = LatheConsole::open(LatheDesc::citizen(), &dir2, 20, 60, None)
        .unwrap_or_else(|e| panic!("{e}"))
        .0;
    c.handle(PanelEvent::Type("8".into()));
    assert!(
        c.message().contains("AUTO takes no line"),
        "{}",
        c.message()
    );
    c.close(None).unwrap();
    let _ = std::fs::remove_dir_all(&dir);
    let _ = std::fs::remove_dir_all(&dir2);
}
