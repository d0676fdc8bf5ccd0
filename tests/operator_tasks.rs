//! The three daily tasks of issue 14 as panel scripts (`tests/golden/tasks/`), with the keys
//! counted and the outcome checked. A key is one `key NAME`, one selector or relay word, or one
//! character of a `type` line plus its EOB; waits and `show` cost nothing (docs/operator.md,
//! "Keystrokes").

mod common;

use common::{audit, open};
use novanc::block::Motion;
use novanc::console::Console;
use novanc::panel_model::PanelEvent;
use novanc::pulse_core::BlockEnd;
use novanc::settings::MachineSettings;
use novanc::translator::Translator;
use std::path::Path;

/// The events of a task script.
fn script(name: &str) -> Vec<PanelEvent> {
    let p = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/golden/tasks")
        .join(name);
    let text = std::fs::read_to_string(&p).unwrap();
    PanelEvent::parse_script(&text).unwrap_or_else(|e| panic!("{}: {e:?}", p.display()))
}

/// Keys an event costs the operator.
fn keys_of(e: &PanelEvent) -> usize {
    match e {
        PanelEvent::Type(t) => t.chars().count() + 1,
        PanelEvent::Wait | PanelEvent::WaitBlock(_) | PanelEvent::WaitMs(_) | PanelEvent::Show => 0,
        PanelEvent::Tape(_) => 0,
        _ => 1,
    }
}

/// Runs a script; `check(console, n)` is called at its n-th `show`. Returns the keys pressed.
fn run(
    c: &mut Console,
    events: Vec<PanelEvent>,
    mut check: impl FnMut(&mut Console, usize),
) -> usize {
    let mut keys = 0;
    let mut shows = 0;
    for e in events {
        keys += keys_of(&e);
        if e == PanelEvent::Show {
            check(c, shows);
            shows += 1;
        } else {
            c.handle(e);
            assert!(c.wait_error().is_none(), "{:?}", c.wait_error());
        }
    }
    keys
}

#[test]
fn task1_edit_dp20_insert_a_statement_delete_a_line_in_19_keys() {
    let mut c = open("task1");
    c.handle(PanelEvent::Op(novanc::panel_model::OpMode::Auto));
    let before = c.program_text();
    let keys = run(&mut c, script("task1_edit.script"), |c, _| {
        assert!(!c.alarm_lit(), "{}", c.frame_text());
    });
    let want = before
        .replace("DRL, 106/DP20/PAT1\n", "DRL, 106/DP22/PAT1\nCL\n")
        .replace("TAP, 208/DP16/PAT1\n", "");
    assert_eq!(c.program_text(), want);
    assert_eq!(keys, 19);
    assert!(keys <= 31, "target: at most 31 keys (Fanuc 0i about 31)");
}

/// Every block of `text` with the tool number in the spindle when it runs.
fn listing(text: &str, c: &Console) -> Vec<(u32, novanc::block::Block)> {
    let m = c.magazine();
    let mut tool = 0;
    let mut out = Vec::new();
    for s in Translator::new(text, m.clone(), MachineSettings::default(), [0, 0, 0]) {
        for b in s.unwrap().blocks {
            if let Some(t) = b.t {
                tool = t;
            }
            out.push((tool, b));
        }
    }
    out
}

#[test]
fn task2_three_single_blocks_auto_hold_resume_reset_in_9_keys() {
    let mut c = open("task2");
    let blocks = listing(&c.program_text(), &c);
    let mut ends: Vec<BlockEnd> = Vec::new();
    let keys = run(&mut c, script("task2_single_block.script"), |c, n| {
        ends.extend(audit(c));
        match n {
            // After each single block: the machine stands on that block's end point.
            0..=2 => {
                assert_eq!(ends.len(), n + 1, "one block per START");
                assert_eq!(c.status().pos, blocks[n].1.end, "block {n}");
                assert!(
                    c.status().job.is_some(),
                    "the run stays loaded between single blocks"
                );
            }
            // Feed hold: RUN 1, HOLD lit, stopped on the path.
            3 => {
                assert!(c.view().lamps.hold, "{}", c.frame_text());
                assert!(!c.status().moving);
                assert!(ends.len() > 3, "AUTO went on past the single blocks");
            }
            // RESET: the run is abandoned, the machine stops where it is.
            _ => {
                assert_eq!(c.status().run, 0);
                assert!(c.status().job.is_none());
                assert!(!c.status().moving);
            }
        }
    });
    // Every block that ended, ended on its programmed point, in the listing's order.
    for (i, e) in ends.iter().enumerate() {
        assert_eq!(e.end, blocks[i].1.end, "block {i}");
    }
    assert_eq!(keys, 9);
    assert!(keys <= 10, "target: at most 10 keys (Fanuc 0i about 10)");
}

#[test]
fn task3_tool_length_run_and_restart_from_drl_105_in_14_keys() {
    // The program as it runs with the length of 150, for comparison.
    let mut base = open("task3-base");
    base.handle(PanelEvent::Op(novanc::panel_model::OpMode::Auto));
    base.handle(PanelEvent::Start);
    base.wait_idle();
    let base_ends = audit(&base);
    let base_blocks = listing(&base.program_text(), &base);
    assert_eq!(base_ends.len(), base_blocks.len());

    let mut c = open("task3");
    let mut runs: Vec<Vec<BlockEnd>> = Vec::new();
    let keys = run(&mut c, script("task3_tool_length.script"), |c, n| match n {
        0 => {
            assert!(c.frame_text().contains("155"), "{}", c.frame_text());
            let t02 = c.magazine().tools.get(2).cloned().unwrap();
            assert_eq!(t02.set_length, 155.0);
        }
        _ => runs.push(audit(c)),
    });
    assert_eq!(keys, 14);
    assert!(keys <= 22, "target: at most 22 keys (Fanuc 0i about 22)");

    // The whole run: every T02 (tool 00106) block with a Z is 5.000 mm higher on the axis, so
    // the tip goes where it went; every other block is where it was.
    let blocks = listing(&c.program_text(), &c);
    let full = &runs[0];
    assert_eq!(full.len(), base_ends.len());
    let mut moved = 0;
    for (i, (e, b)) in full.iter().zip(&base_ends).enumerate() {
        let (tool, blk) = &blocks[i];
        assert_eq!(
            blocks[i].1.end, e.end,
            "the listing says where block {i} goes"
        );
        let dz = e.end[2] - b.end[2];
        let shifted = *tool == 2 && blk.t.is_none() && blk.motion != Motion::Aux && e.end[2] != 0;
        if shifted {
            assert_eq!(dz, 5000, "T02 block {i} (N{}) moved by 5.000 mm", e.seq);
            moved += 1;
        } else {
            assert_eq!(
                e.end, b.end,
                "block {i} (N{}) not under T02 is unchanged",
                e.seq
            );
        }
        assert_eq!([e.end[0], e.end[1]], [b.end[0], b.end[1]]);
    }
    assert!(moved >= 6, "the six DRL, 106 holes: {moved} blocks moved");

    // The restart from line 8: once at its first point (the tool changed and the spindle
    // started where the machine stood), its blocks end where the whole run's blocks of lines 8
    // and 9 did.
    let restart = &runs[1];
    assert!(restart.iter().all(|e| e.stmt >= 8), "{restart:?}");
    let first_xy = full
        .iter()
        .filter(|e| e.stmt >= 8)
        .find(|e| e.end[..2] != e.start[..2])
        .map(|e| [e.end[0], e.end[1]])
        .unwrap();
    let from_first_point = |ends: &[BlockEnd]| -> Vec<[i64; 3]> {
        ends.iter()
            .filter(|e| e.stmt >= 8)
            .skip_while(|e| e.end[..2] != first_xy)
            .map(|e| e.end.xyz())
            .collect()
    };
    assert_eq!(from_first_point(restart), from_first_point(full));
    assert!(from_first_point(restart).len() >= 20);
    assert_eq!(
        c.status().pos,
        base.status().pos,
        "the restart ends where a whole run ends"
    );
}

/// The `/nc/block` texts and `/panel/event` texts of a recording, in log-time order, as
/// (topic, log time, text).
fn recorded(path: &Path) -> Vec<(String, u64, String)> {
    let bytes = std::fs::read(path).unwrap();
    let mut out = Vec::new();
    for m in mcap::MessageStream::new(&bytes).unwrap() {
        let m = m.unwrap();
        let topic = m.channel.topic.clone();
        if topic != "/nc/block" && topic != "/panel/event" {
            continue;
        }
        let json = String::from_utf8_lossy(&m.data).into_owned();
        out.push((topic, m.log_time, json));
    }
    out.sort_by_key(|(_, t, _)| *t);
    out
}

/// The Z word of a block's ISO line in a `/nc/block` message, if it has one.
fn z_word(json: &str) -> Option<String> {
    let text = json.split("\"text\":\"").nth(1)?.split('"').next()?;
    text.split(' ')
        .find(|w| w.starts_with('Z'))
        .map(str::to_string)
}

#[test]
fn a_length_revised_on_the_ofs_page_during_a_feed_hold_applies_from_the_next_block() {
    let dir = common::temp_dir("ofs-hold");
    let rec = dir.join("hold.mcap");
    let mut cfg = novanc::console::ConsoleConfig::new(dir.join("state"));
    cfg.clock = novanc::pulse_core::ClockMode::Virtual;
    cfg.record = Some(rec.clone());
    let mut c = Console::open(cfg).unwrap().0;
    c.core().set_audit(true);
    let blocks = listing(&c.program_text(), &c);
    // The T02 blocks (the six DRL, 106 holes) that move Z to a height of the tool's tip.
    let t02: Vec<usize> = (0..blocks.len())
        .filter(|&i| {
            let (t, b) = &blocks[i];
            *t == 2 && b.tool_z && b.delta[2] != 0
        })
        .collect();
    assert!(t02.len() >= 12);
    // Hold in the middle of the third T02 feed.
    let held_at = t02[2];
    let seq = blocks[held_at].1.seq;
    common::keys(&mut c, &["Alt+2", "F9"]);
    c.handle(PanelEvent::WaitBlock(seq));
    c.handle(PanelEvent::WaitMs(20));
    common::keys(&mut c, &["F10"]);
    c.wait_idle();
    assert!(c.view().lamps.hold);
    assert_eq!(
        c.status()
            .executing
            .as_ref()
            .map(|e| e.stmt.blocks[e.index].seq),
        Some(seq)
    );
    // OFS: T02's set length 150 -> 155, during the hold; the run stays loaded.
    common::keys(&mut c, &["Ctrl+O", "Down", "1", "5", "5", "Enter"]);
    assert!(c.status().job.is_some(), "{}", c.frame_text());
    assert_eq!(c.magazine().tools.get(2).unwrap().set_length, 155.0);
    common::keys(&mut c, &["Ctrl+O", "F9"]);
    c.wait_idle();
    let ends = audit(&c);
    assert_eq!(
        ends.len(),
        blocks.len(),
        "the run completed:\n{}\n{:?}",
        c.frame_text(),
        c.status()
    );
    c.finish().unwrap();

    // In the recording: the T02 blocks that started before the INPUT have the listing's Z; the
    // one held finishes at it; every T02 block after it has the listing's Z + 5.000.
    let events = recorded(&rec);
    let input_at = events
        .iter()
        .find(|(topic, _, j)| topic == "/panel/event" && j.contains("Enter"))
        .map(|(_, t, _)| *t)
        .expect("the INPUT key is recorded");
    let started: Vec<(u64, Option<String>)> = events
        .iter()
        .filter(|(topic, _, _)| topic == "/nc/block")
        .map(|(_, t, j)| (*t, z_word(j)))
        .collect();
    assert_eq!(started.len(), blocks.len());
    let s = c_settings();
    let mut after = 0;
    for &i in &t02 {
        let (t, z) = &started[i];
        let listed = s.to_mm(blocks[i].1.end[2]);
        let want = if *t < input_at { listed } else { listed + 5.0 };
        assert_eq!(
            z.as_deref(),
            Some(format!("Z{want:.3}").as_str()),
            "T02 block {i} started at {t} (INPUT at {input_at})"
        );
        assert_eq!(
            ends[i].end[2],
            s.to_pulses(want),
            "block {i} ended at its Z"
        );
        if *t > input_at {
            after += 1;
        }
    }
    assert!(
        i_before(&t02, held_at) && after >= 9,
        "{after} T02 blocks after the edit"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

fn c_settings() -> MachineSettings {
    MachineSettings::default()
}

fn i_before(t02: &[usize], held: usize) -> bool {
    t02.iter().filter(|&&i| i <= held).count() == 3
}
