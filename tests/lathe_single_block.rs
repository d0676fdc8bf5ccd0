//! SINGLE BLOCK on the lathe console (docs/lathe.md "SINGLE BLOCK"): the centre's operation
//! selector position, on every channel of the one kernel. Each START runs one block of every
//! channel stopped between blocks; the summary line says STOP and the message line what START
//! does; AUTO turned mid-cycle, then START, runs on. A cycle stepped block by block ends where the same
//! cycle run in AUTO ends, with the same parts.

mod common;

use novanc::lathe::console::LatheConsole;
use novanc::lathe::desc::LatheDesc;
use novanc::panel_model::{OpMode, Page, PanelEvent};

fn open(state: &std::path::Path) -> LatheConsole {
    let (mut c, _) = LatheConsole::open(LatheDesc::citizen(), state, 20, 60, None)
        .unwrap_or_else(|e| panic!("{e}"));
    c.handle(PanelEvent::Target(1));
    c
}

fn states(c: &LatheConsole) -> Vec<String> {
    c.view().channels.iter().map(|v| v.state.clone()).collect()
}

fn over(c: &LatheConsole) -> bool {
    c.cycle().is_over()
}

/// Every tool post and the work it holds, and each channel's part count.
type End = (Vec<([i64; 2], Option<u32>)>, Vec<u32>);

/// Where one part in AUTO leaves every tool post, and the counts.
fn auto_run() -> End {
    let dir = common::temp_dir("lathe-single-auto");
    let mut c = open(&dir);
    c.handle(PanelEvent::Op(OpMode::Auto));
    c.handle(PanelEvent::Start);
    c.handle(PanelEvent::Wait);
    assert!(over(&c), "{}", c.frame_text());
    let out = (c.tips(), c.counter().counts.clone());
    let _ = std::fs::remove_dir_all(&dir);
    out
}

#[test]
fn a_cycle_stepped_block_by_block_ends_as_the_same_cycle_in_auto() {
    let want = auto_run();
    let dir = common::temp_dir("lathe-single");
    let mut c = open(&dir);
    c.press(novanc_panel::Key::Alt('7'));
    assert!(
        c.view().display[0].trim_end().ends_with("SINGLE"),
        "{:?}",
        c.view().display[0]
    );
    let mut starts = 0;
    loop {
        c.handle(PanelEvent::Start);
        c.handle(PanelEvent::Wait);
        starts += 1;
        assert!(starts < 5_000, "stepping does not end: {}", c.frame_text());
        if over(&c) {
            break;
        }
        // Nothing runs between two STARTs: each channel stopped after its block, waits on
        // one that did, or is done; and the screen says what START does.
        let s = states(&c);
        assert!(
            s.iter()
                .all(|w| ["STOP", "WAIT", "DONE"].contains(&w.as_str())),
            "after START {starts}: {s:?}\n{}",
            c.frame_text()
        );
        if s.iter().any(|w| w == "STOP") {
            assert!(
                c.message().starts_with("SINGLE BLOCK:"),
                "after START {starts}: {}",
                c.message()
            );
        }
    }
    // CH3 alone has 55 blocks a part: one START a block, give or take the waits.
    assert!(starts > 50, "{starts} STARTs");
    eprintln!("one part of the Citizen in SINGLE BLOCK: {starts} STARTs");
    assert_eq!((c.tips(), c.counter().counts.clone()), want);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn auto_turned_mid_cycle_runs_on_to_the_end() {
    let want = auto_run();
    let dir = common::temp_dir("lathe-single-then-auto");
    let mut c = open(&dir);
    c.handle(PanelEvent::Op(OpMode::Single));
    for _ in 0..5 {
        c.handle(PanelEvent::Start);
        c.handle(PanelEvent::Wait);
    }
    assert!(!over(&c));
    let at = c.tips();
    // AUTO turned: nothing runs on until START (the centre's rule).
    c.handle(PanelEvent::Op(OpMode::Auto));
    c.handle(PanelEvent::Wait);
    assert_eq!(c.tips(), at);
    c.handle(PanelEvent::Start);
    c.handle(PanelEvent::Wait);
    assert!(over(&c), "{}", c.frame_text());
    assert_eq!((c.tips(), c.counter().counts.clone()), want);
    // And back: SINGLE BLOCK turned on in a running cycle stops every channel after its block.
    c.handle(PanelEvent::Reset);
    c.handle(PanelEvent::Target(2));
    c.handle(PanelEvent::Start);
    c.run_for(300_000_000, novanc::lathe::console::RunUntil::Time, || {
        false
    });
    c.handle(PanelEvent::Op(OpMode::Single));
    c.handle(PanelEvent::Wait);
    assert!(!over(&c));
    let s = states(&c);
    assert!(
        s.iter()
            .all(|w| ["STOP", "WAIT", "DONE"].contains(&w.as_str()))
            && s.contains(&"STOP".into()),
        "{s:?}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// A mode other than AUTO and SINGLE BLOCK turned while a cycle runs is a feed hold on every
/// channel, said on the message line (the centre's rule; before stop 42 the lathe's cycle ran
/// on under MDI, DATA or a manual mode, and START resumed it in any mode). START in that mode
/// is refused in the centre's words; AUTO turned back and START go on to the end, with the
/// same tool posts, works and counts as a cycle left alone.
#[test]
fn a_mode_turned_while_the_cycle_runs_holds_every_channel() {
    let want = auto_run();
    for m in [OpMode::Mdi, OpMode::Data, OpMode::Continuous] {
        let dir = common::temp_dir("lathe-turn-holds");
        let mut c = open(&dir);
        c.handle(PanelEvent::Op(OpMode::Auto));
        c.handle(PanelEvent::Start);
        c.run_for(
            3_000_000_000,
            novanc::lathe::console::RunUntil::Time,
            || false,
        );
        assert!(states(&c).contains(&"RUN".into()), "{:?}", states(&c));
        c.handle(PanelEvent::Op(m));
        assert_eq!(
            c.message(),
            format!("feed hold: mode changed to {} while running", m.name())
        );
        c.handle(PanelEvent::Wait);
        let s = states(&c);
        assert!(
            s.iter().all(|w| w != "RUN") && s.contains(&"HOLD".into()),
            "{m:?}: {s:?}"
        );
        let at = c.tips();
        c.run_for(
            2_000_000_000,
            novanc::lathe::console::RunUntil::Time,
            || false,
        );
        assert_eq!(c.tips(), at, "{m:?}: held, nothing moves");
        // START in that mode does not resume the cycle: the centre's words.
        c.handle(PanelEvent::Start);
        let refused = match m {
            OpMode::Mdi => "START refused: an AUTO run is loaded; press RESET first".into(),
            m => format!(
                "START refused in {}: use AUTO, MDI or SINGLE BLOCK",
                m.name()
            ),
        };
        assert_eq!(c.message(), refused);
        c.run_for(
            1_000_000_000,
            novanc::lathe::console::RunUntil::Time,
            || false,
        );
        assert_eq!(c.tips(), at, "{m:?}: START refused, nothing moves");
        c.handle(PanelEvent::Op(OpMode::Auto));
        c.handle(PanelEvent::Start);
        c.handle(PanelEvent::Wait);
        assert!(over(&c), "{m:?}: {}", c.frame_text());
        assert_eq!((c.tips(), c.counter().counts.clone()), want, "{m:?}");
        let _ = std::fs::remove_dir_all(&dir);
    }
}

/// OFS is a page over the operation selector, as the centre's tool-offset page is: called up
/// in AUTO while the cycle runs, it shows the channel's tools and takes a revision without
/// stopping anything; START still acts (the mode is AUTO); a mode key leaves the page.
#[test]
fn the_ofs_page_stands_over_a_running_cycle() {
    let dir = common::temp_dir("lathe-ofs-page");
    let mut c = open(&dir);
    c.handle(PanelEvent::Target(2));
    c.handle(PanelEvent::Start);
    c.run_for(500_000_000, novanc::lathe::console::RunUntil::Time, || {
        false
    });
    c.press(novanc_panel::Key::Ctrl('o'));
    assert!((c.page() == Page::Ofs) && c.mode() == OpMode::Auto);
    let v = c.view();
    assert!(v.display[0].contains(" OFS"), "{:?}", v.display[0]);
    assert!(
        v.display.iter().any(|l| l.starts_with("T01")),
        "{:?}",
        v.display
    );
    assert!(states(&c).contains(&"RUN".to_string()), "{:?}", states(&c));
    c.handle(PanelEvent::Type("T1 X0.02".into()));
    assert!(c.message().contains("T01 revised"), "{}", c.message());
    c.handle(PanelEvent::Stop);
    c.handle(PanelEvent::Start);
    assert_eq!(c.message(), "START");
    c.press(novanc_panel::Key::Ctrl('o'));
    assert!(
        !(c.page() == Page::Ofs),
        "the page key again leaves the page"
    );
    c.press(novanc_panel::Key::Ctrl('o'));
    assert!((c.page() == Page::Ofs));
    c.press(novanc_panel::Key::Alt('2'));
    assert!(!(c.page() == Page::Ofs));
    assert!(c.view().display[0].trim_end().ends_with("AUTO"));
    c.handle(PanelEvent::Wait);
    assert!(over(&c), "the cycle ran on to its target");
    let _ = std::fs::remove_dir_all(&dir);
}

/// CH1's tool post where block `seq` of its program starts, the `nth` time (1: part 1).
fn at_block(c: &mut LatheConsole, seq: u32, nth: usize) -> [i64; 2] {
    let mut seen = 0;
    for _ in 0..10_000 {
        if c.step(20_000_000, novanc::lathe::console::RunUntil::Block(0, seq)) {
            seen += 1;
            if seen == nth {
                return c.tips()[0].0;
            }
            // On past the block's start.
            c.step(1_000_000, novanc::lathe::console::RunUntil::Time);
        }
    }
    panic!("block {seq} did not start {nth} times: {}", c.frame_text());
}

/// A wear offset revised on the OFS page for the tool that cuts, which the part under way does
/// not call again, takes effect from the channel's next part (a real lathe takes it at the
/// next T call): the part under way is cut as it was read, the next with the revised offset;
/// the batch does not stop.
#[test]
fn a_wear_offset_revised_mid_batch_takes_effect_at_the_next_part() {
    // CH1: T0303, then `G0 X22 Z0.5` (line 11): where its 6th block (line 12, `G1 X-1`)
    // starts, T3's tip stands at X22 Z0.5.
    let plain = {
        let dir = common::temp_dir("lathe-wear-plain");
        let mut c = open(&dir);
        c.handle(PanelEvent::Target(2));
        c.handle(PanelEvent::Start);
        let p = [at_block(&mut c, 6, 1), at_block(&mut c, 6, 1)];
        let _ = std::fs::remove_dir_all(&dir);
        p
    };
    let dir = common::temp_dir("lathe-wear");
    let mut c = open(&dir);
    c.handle(PanelEvent::Target(2));
    c.handle(PanelEvent::Start);
    let first = at_block(&mut c, 6, 1);
    assert_eq!(first, plain[0]);
    assert_eq!(plain, [[11_000, 500]; 2], "the same place in both parts");
    // Part 1 is under way: T3's X wear offset +0.1 mm on the diameter.
    c.handle(PanelEvent::OfsMode);
    c.handle(PanelEvent::Type("T3 X0.1".into()));
    assert_eq!(c.message(), "T03 revised: CH1 takes it from its next part");
    let second = at_block(&mut c, 6, 1);
    // 0.1 mm on the diameter is 0.05 mm, 50 pulses, on the radius; Z as it was.
    assert_eq!(
        (second[0] - plain[1][0]).abs(),
        50,
        "{second:?} against {:?}",
        plain[1]
    );
    assert_eq!(second[1], plain[1][1]);
    c.handle(PanelEvent::Wait);
    assert!(over(&c), "the batch ran to its target: {}", c.frame_text());
    assert_eq!(c.counter().counts, vec![2, 2, 2]);
    let _ = std::fs::remove_dir_all(&dir);
}

/// A wear offset revised for a tool the part under way has still to call takes effect at that
/// call, in this part: CH1 cuts with T3 (block 6, line 12) when T1's X wear is revised, and
/// T1, called at line 14, already stands where the revision puts it in part 1.
#[test]
fn a_wear_offset_revised_before_its_tool_is_called_takes_effect_at_the_call() {
    // Block 9 (line 15, `G0 X14 Z1`, T1's approach) ends where block 10 starts.
    let plain = {
        let dir = common::temp_dir("lathe-wear-call-plain");
        let mut c = open(&dir);
        c.handle(PanelEvent::Target(1));
        c.handle(PanelEvent::Start);
        let p = at_block(&mut c, 10, 1);
        let _ = std::fs::remove_dir_all(&dir);
        p
    };
    let dir = common::temp_dir("lathe-wear-call");
    let mut c = open(&dir);
    c.handle(PanelEvent::Target(1));
    c.handle(PanelEvent::Start);
    at_block(&mut c, 6, 1);
    c.handle(PanelEvent::OfsMode);
    c.handle(PanelEvent::Type("T1 X0.1".into()));
    assert_eq!(
        c.message(),
        "T01 revised: CH1 takes it from its next tool call, line 14"
    );
    let revised = at_block(&mut c, 10, 1);
    // 0.1 mm on the diameter is 50 pulses on the radius, in this part; Z as it was.
    assert_eq!(
        (revised[0] - plain[0]).abs(),
        50,
        "{revised:?} against {plain:?}"
    );
    assert_eq!(revised[1], plain[1]);
    c.handle(PanelEvent::Wait);
    assert!(over(&c), "the part was made: {}", c.frame_text());
    assert_eq!(c.counter().counts, vec![1, 1, 1]);
    let _ = std::fs::remove_dir_all(&dir);
}

/// The selector turned to the position it is at does nothing, on both machines (one rule,
/// `console::selector`): the line being typed stays. Before stop 43 the lathe cleared it (and
/// said the mode again), so a second press of Alt+3 in MDI lost what the operator had typed.
/// A turn to another position clears it on both: it was typed for the mode left. It is said,
/// and an MDI line comes back with Up in MDI (stop 49: it went without a word).
#[test]
fn a_turn_to_the_selectors_own_position_keeps_the_typed_line_on_both_machines() {
    let dir = common::temp_dir("lathe-same-turn");
    let mut c = open(&dir);
    c.handle(PanelEvent::Op(OpMode::Mdi));
    for ch in "G0X12".chars() {
        c.handle(PanelEvent::Key(ch));
    }
    assert!(c.frame_text().contains("G0X12"), "{}", c.frame_text());
    c.press(novanc_panel::Key::Alt('3'));
    assert_eq!(c.mode(), OpMode::Mdi);
    assert!(c.frame_text().contains("G0X12"), "{}", c.frame_text());
    c.handle(PanelEvent::Op(OpMode::Auto));
    let said = "the line typed in MDI, 'G0X12', is cleared (Up recalls it in MDI)";
    assert_eq!(c.message(), said);
    assert_eq!(c.view().display.last().map(|l| l.trim_end()), Some(">"));
    c.handle(PanelEvent::Op(OpMode::Mdi));
    c.press(novanc_panel::Key::Up);
    assert!(c.frame_text().contains("> G0X12"), "{}", c.frame_text());
    let _ = std::fs::remove_dir_all(&dir);

    let mut m = common::open("centre-same-turn");
    m.handle(PanelEvent::Op(OpMode::Mdi));
    for ch in "G0X12".chars() {
        m.handle(PanelEvent::Key(ch));
    }
    m.press(novanc_panel::Key::Alt('3'));
    assert_eq!(m.view().entry, "G0X12");
    m.handle(PanelEvent::Op(OpMode::Auto));
    assert_eq!(m.view().entry, "");
    assert_eq!(m.message(), said);
    m.handle(PanelEvent::Op(OpMode::Mdi));
    m.press(novanc_panel::Key::Up);
    assert_eq!(m.view().entry, "G0X12");
}
