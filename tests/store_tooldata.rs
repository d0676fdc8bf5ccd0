//! TOOL DATA READ, T-CODE SETTING and TOOL DATA REVISION through the stores: what they do, and
//! every bad input refused with its message and nothing changed (in memory and on disk).

use novanc::store::{EditFailure, Stores, Target};
use novanc::tooldata::{Magazine, ToolLookupError};
use std::fs;
use std::path::{Path, PathBuf};

fn fresh(tag: &str) -> PathBuf {
    let d = Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("store-tool-{tag}"));
    let _ = fs::remove_dir_all(&d);
    d
}

fn open(d: &Path) -> Stores {
    match Stores::open(d, 24) {
        Ok((s, w)) => {
            assert!(w.is_empty(), "{w:?}");
            s
        }
        Err(e) => panic!("open: {e}"),
    }
}

/// Everything the tool data operations could change.
#[derive(Debug, PartialEq)]
struct Seen {
    magazine: Magazine,
    text: String,
    pointer: usize,
}

fn seen(s: &Stores) -> Seen {
    let b = s.buffer(Target::ToolFile);
    Seen {
        magazine: s.magazine(),
        text: b.text(),
        pointer: b.pointer(),
    }
}

/// Runs `bad` on fresh stores, checks it failed with `want` and that nothing changed, in
/// memory and after a reopen.
fn refused(tag: &str, bad: impl FnOnce(&mut Stores) -> String, want: &str) {
    let d = fresh(tag);
    let mut s = open(&d);
    s.edit(Target::ToolFile, "2L", None).unwrap(); // pointer somewhere other than 0
    let before = seen(&s);
    let msg = bad(&mut s);
    assert!(
        msg.contains(want),
        "{tag}: message '{msg}' does not contain '{want}'"
    );
    assert_eq!(seen(&s), before, "{tag}: changed in memory");
    drop(s);
    let s = open(&d);
    assert_eq!(seen(&s), before, "{tag}: changed on disk");
}

fn tape_err(tape: &'static str) -> impl FnOnce(&mut Stores) -> String {
    move |s| match s.tool_read(tape, "t.tt") {
        Ok(r) => format!("accepted: {r:?}"),
        Err(e) => e.to_string(),
    }
}

const GOOD: &str = "00106 DR 6.5 151 41 1300 130 3.5\n";

#[test]
fn bad_tool_tapes_change_nothing() {
    refused(
        "fields",
        tape_err("00106 DR 6.2 150 40 1200 120\n"),
        "t.tt:1: a tool record has 8 fields (TOOLNO KIND DIAMETER SETLEN EFFLEN SPEED FEED DEPTH), and the tool file may add the wear (WEARLEN WEARDIA), this one has 7",
    );
    refused(
        "numeric",
        tape_err("; c\n00106 DR 6.2 abc 40 1200 120 3\n"),
        "t.tt:2: set length 'abc' is not a number",
    );
    refused(
        "kind",
        tape_err("00106 XX 6.2 150 40 1200 120 3\n"),
        "t.tt:1: unknown tool kind 'XX' (kinds: DR CD TP RM EM FM BB)",
    );
    refused(
        "negative",
        tape_err("00106 DR 6.2 150 -40 1200 120 3\n"),
        "t.tt:1: effective length -40 is negative",
    );
    refused(
        "duplicate",
        tape_err("00106 DR 6.2 150 40 1200 120 3\n\n00106 DR 6.5 150 40 1200 120 3\n"),
        "t.tt:3: duplicate tool number 00106",
    );
    // A good record before a bad one is not loaded either.
    refused(
        "partial",
        tape_err("00106 DR 9.9 150 40 1200 120 3\n00208 TP 8 150 25 300 375\n"),
        "t.tt:2: a tool record has 8 fields",
    );
}

#[test]
fn tool_data_read_loads_only_the_magazine_tools() {
    let d = fresh("read");
    let mut s = open(&d);
    let tape = format!(
        "{GOOD}00999 EM 8 120 20 4000 600 4 ; not in the magazine\n00208 TP 8 150 25 300 375 16\n"
    );
    let r = s.tool_read(&tape, "new.tt").unwrap();
    assert_eq!(r.loaded, [2, 3]);
    assert_eq!(r.skipped, 1);
    assert_eq!(r.missing.len(), 18);
    assert_eq!(r.missing[0], (1, 610));
    assert!(r.summary().starts_with(
        "2 tools loaded, 1 skipped (not in the magazine); not on the tape: T01 00610, T04 00105"
    ));
    let check = |s: &Stores| {
        let m = s.magazine();
        let (t, rec) = m.find(106).unwrap();
        assert_eq!((t, rec.diameter, rec.speed), (2, 6.5, 1300.0));
        // Tools not on the tape keep their data.
        assert_eq!(m.find(610).unwrap().1.diameter, 40.0);
        assert!(matches!(
            m.find(999),
            Err(ToolLookupError::NotInMagazine(999))
        ));
        let line = s
            .buffer(Target::ToolFile)
            .text()
            .lines()
            .nth(1)
            .unwrap()
            .to_string();
        assert_eq!(
            line,
            "T02 00106  DR      6.5    151.0     41.0  1300.0   130.0     3.5"
        );
    };
    check(&s);
    drop(s);
    check(&open(&d));
}

fn tcode_err(t: u32, tool: Option<u32>) -> impl FnOnce(&mut Stores) -> String {
    move |s| match s.set_tcode(t, tool) {
        Ok(()) => "accepted".to_string(),
        Err(e) => e,
    }
}

#[test]
fn bad_tcode_settings_change_nothing() {
    refused(
        "tc-pocket",
        tcode_err(25, Some(1)),
        "T25 is not a pocket (the magazine has T01 to T24)",
    );
    refused(
        "tc-zero",
        tcode_err(0, None),
        "T00 is not a pocket (the magazine has T01 to T24)",
    );
    refused(
        "tc-twice",
        tcode_err(3, Some(106)),
        "tool 00106 is already in T02",
    );
    refused(
        "tc-digits",
        tcode_err(21, Some(100_000)),
        "tool number 100000 is not 1 to 5 digits",
    );
    refused(
        "tc-nought",
        tcode_err(21, Some(0)),
        "tool number 0 is not 1 to 5 digits",
    );
    refused(
        "tc-notool",
        |s| match s.assign_tool(777, None) {
            Ok(()) => "accepted".into(),
            Err(e) => e,
        },
        "tool 00777 is in no T code",
    );
    refused(
        "tc-by-tool",
        |s| match s.assign_tool(610, Some(22)) {
            Ok(()) => "accepted".into(),
            Err(e) => e,
        },
        "tool 00610 is already in T01",
    );
}

#[test]
fn tcode_setting_both_ways() {
    let d = fresh("tcode");
    let mut s = open(&d);
    s.set_tcode(21, Some(999)).unwrap();
    s.assign_tool(111, Some(22)).unwrap();
    s.assign_tool(106, None).unwrap(); // takes 106 out of T02
    s.set_tcode(3, Some(207)).unwrap(); // T03 changes tool: its data is cleared
    s.set_tcode(1, Some(610)).unwrap(); // same tool: nothing changes, data kept
    let check = |s: &Stores| {
        let m = s.magazine();
        assert_eq!(m.tcodes.tool_in(21), Some(999));
        assert_eq!(m.tcodes.tool_in(22), Some(111));
        assert_eq!(m.tcodes.tool_in(2), None);
        assert!(matches!(
            m.find(207),
            Err(ToolLookupError::NoData {
                tool: 207,
                tcode: 3
            })
        ));
        assert_eq!(m.find(610).unwrap().0, 1);
        let text = s.buffer(Target::ToolFile).text();
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(lines[1], "T02");
        assert_eq!(lines[2], "T03 00207");
        assert_eq!(lines[20], "T21 00999");
    };
    check(&s);
    drop(s);
    check(&open(&d));
}

fn revise(line: &'static str) -> impl FnOnce(&mut Stores) -> String {
    move |s| match s.edit(Target::ToolFile, line, None) {
        Ok(o) => format!("accepted: {o:?}"),
        Err(EditFailure::Command(e)) => e.to_string(),
        Err(e) => format!("store failure: {e}"),
    }
}

#[test]
fn bad_tool_file_revisions_change_nothing() {
    refused(
        "rev-number",
        revise("-9LC00106$00107"),
        "T02 holds tool 00106, not 00107; change it in T-CODE SETTING",
    );
    refused(
        "rev-kind",
        revise("-9LS00106$CDR$XX"),
        "T02: unknown tool kind 'XX' (kinds: DR CD TP RM EM FM BB)",
    );
    refused(
        "rev-numeric",
        revise("-9LS00106$C6.2$6,2"),
        "T02: diameter '6,2' is not a number",
    );
    refused(
        "rev-negative",
        revise("-9LS00106$C150.0$-150.0"),
        "T02: set length -150.0 is negative",
    );
    refused(
        "rev-fields",
        revise("-9LS00106$C3.0*$*"),
        "T02: a tool record has 8 fields",
    );
    refused(
        "rev-add",
        revise("-99LIT00*"),
        "command 2 'IT00*': the tool file has one line per T code (T01 to T24); a line cannot be added",
    );
    refused(
        "rev-remove",
        revise("K"),
        "line 3 must start with T03 (found 'T04')",
    );
    refused("rev-last", revise("99LIT25*"), "a line cannot be added");
    refused(
        "rev-swap",
        revise("-9LKLIT01*"),
        "line 1 must start with T01 (found 'T02'); lines cannot be renumbered or reordered",
    );
    refused(
        "rev-join",
        revise("S*$-1D"),
        "T03: a tool record has 8 fields",
    );
    refused(
        "rev-empty",
        revise("-9LST02$0KKIT02*"),
        "T02 holds tool 00106; a pocket is emptied in T-CODE SETTING",
    );
    refused(
        "rev-fill",
        revise("ST21$I 00999"),
        "T21 is an empty pocket; assign tool 00999 to it in T-CODE SETTING",
    );
    refused(
        "rev-comment",
        revise("-9LS00106$I ; mine"),
        "T02: comments are not kept in the tool file",
    );
    // A bad editor command line: the editor's own message, naming the command.
    refused("rev-editor", revise("LSnothere"), "command 2");
}

#[test]
fn a_tool_file_revision_reaches_the_translator_and_survives() {
    let d = fresh("revise");
    let mut s = open(&d);
    s.set_tcode(21, Some(999)).unwrap();
    // Data typed for a tool that was assigned without data.
    s.edit(
        Target::ToolFile,
        "ST21 00999$I EM 8 120 20 4000 600 4",
        None,
    )
    .unwrap();
    s.edit(Target::ToolFile, "-99LS00106$C1200.0$1500", None)
        .unwrap();
    let check = |s: &Stores| {
        let m = s.magazine();
        assert_eq!(m.find(106).unwrap().1.speed, 1500.0);
        let (t, r) = m.find(999).unwrap();
        assert_eq!((t, r.diameter, r.feed), (21, 8.0, 600.0));
    };
    check(&s);
    drop(s);
    check(&open(&d));
}

fn tcode_file(text: &'static str) -> impl FnOnce(&mut Stores) -> String {
    move |s| match s.tcode_read(text, "m.tc") {
        Ok(()) => "accepted".to_string(),
        Err(e) => e.to_string(),
    }
}

#[test]
fn bad_tcode_files_change_nothing() {
    refused(
        "tf-dup",
        tcode_file("T01 00106\n# c\nT02 00106\n"),
        "m.tc:3: tool 00106 is already in T01",
    );
    refused(
        "tf-twice",
        tcode_file("T01 00106\nT01 00107\n"),
        "m.tc:2: T01 is assigned twice",
    );
    refused(
        "tf-pocket",
        tcode_file("T25 00106\n"),
        "m.tc:1: T25 is not a pocket (the magazine has T01 to T24)",
    );
    refused(
        "tf-form",
        tcode_file("T01 00106 DR\n"),
        "m.tc:1: expected 'Tnn TOOLNO', found 'T01 00106 DR'",
    );
    refused(
        "tf-tcode",
        tcode_file("X01 00106\n"),
        "m.tc:1: 'X01' is not a T code like T05",
    );
    refused(
        "tf-tool",
        tcode_file("T01 1234567\n"),
        "m.tc:1: '1234567' is not a tool number of 1 to 5 digits",
    );
}

#[test]
fn a_tcode_file_replaces_the_table_and_keeps_unchanged_pockets_data() {
    let d = fresh("tcfile");
    let mut s = open(&d);
    s.tcode_read("T01 00610 ; same\nT02 00107\nT05 00999\n", "m.tc")
        .unwrap();
    let check = |s: &Stores| {
        let m = s.magazine();
        assert_eq!(m.tcodes.iter().count(), 3);
        assert_eq!(m.find(610).unwrap().1.diameter, 40.0);
        assert!(matches!(m.find(107), Err(ToolLookupError::NoData { .. })));
        assert!(matches!(
            m.find(106),
            Err(ToolLookupError::NotInMagazine(106))
        ));
        let text = s.buffer(Target::ToolFile).text();
        assert_eq!(text.lines().nth(1), Some("T02 00107"));
        assert_eq!(text.lines().nth(2), Some("T03"));
    };
    check(&s);
    drop(s);
    check(&open(&d));
}

#[test]
fn moving_a_tool_keeps_its_data_in_one_change() {
    let d = fresh("move");
    let mut s = open(&d);
    s.move_tool(106, 22).unwrap(); // from T02, into an empty pocket
    s.move_tool(610, 3).unwrap(); // from T01 onto T03's 00208, which leaves the magazine
    s.move_tool(777, 1).unwrap(); // a tool from nowhere: assigned, no data
    let check = |s: &Stores| {
        let m = s.magazine();
        let (t, r) = m.find(106).unwrap();
        assert_eq!((t, r.diameter), (22, 6.2));
        assert_eq!(m.find(610).unwrap().0, 3);
        assert!(matches!(
            m.find(208),
            Err(ToolLookupError::NotInMagazine(208))
        ));
        assert!(matches!(
            m.find(777),
            Err(ToolLookupError::NoData { tcode: 1, .. })
        ));
        assert_eq!(m.tcodes.tool_in(2), None);
    };
    check(&s);
    drop(s);
    check(&open(&d));
}

#[test]
fn bad_moves_change_nothing() {
    let mv = |tool: u32, t: u32| {
        move |s: &mut Stores| match s.move_tool(tool, t) {
            Ok(()) => "accepted".to_string(),
            Err(e) => e,
        }
    };
    refused(
        "mv-pocket",
        mv(106, 25),
        "T25 is not a pocket (the magazine has T01 to T24)",
    );
    refused("mv-number", mv(0, 21), "tool number 0 is not 1 to 5 digits");
}

#[test]
fn a_t_code_change_keeps_the_spacing_typed_on_the_other_lines() {
    let d = fresh("spacing");
    let mut s = open(&d);
    let tf = |s: &Stores| s.buffer(Target::ToolFile).text();
    let t02 = tf(&s).lines().nth(1).unwrap().to_string();
    // TOOL DATA REVISION: T02 retyped with single spaces, T01 with extra ones.
    s.edit(
        Target::ToolFile,
        "LKIT02 00106 DR 6.2 150 40 1200 120 3*",
        None,
    )
    .unwrap();
    s.edit(Target::ToolFile, "-2LSBB$I   ", None).unwrap();
    let typed = tf(&s);
    assert!(
        !typed.contains(&t02) && typed.starts_with("T01 00610  BB   "),
        "{typed}"
    );
    let lines = |t: &str| t.lines().map(str::to_string).collect::<Vec<_>>();
    let want = lines(&typed);
    // Every kind of T-CODE SETTING, and a TOOL DATA READ that does not change T01 or T02.
    s.set_tcode(21, Some(999)).unwrap();
    s.move_tool(999, 23).unwrap();
    s.assign_tool(108, None).unwrap();
    s.tcode_read(
        &s.magazine()
            .tcodes
            .to_text()
            .replace("T23 00999", "T24 00999"),
        "m.tc",
    )
    .unwrap();
    s.tool_read(
        "00610 BB 40 220 80 400 60 25\n00106 DR 6.2 150 40 1200 120 3\n",
        "t.tt",
    )
    .unwrap();
    let after = lines(&tf(&s));
    assert_eq!(
        after[..2],
        want[..2],
        "T01 and T02 keep their typed spacing"
    );
    assert_eq!(after[19], "T20");
    assert_eq!(after[20], "T21");
    assert_eq!(after[23], "T24 00999");
    drop(s);
    let s = open(&d);
    assert_eq!(lines(&tf(&s)), after, "the same after replay");
}
