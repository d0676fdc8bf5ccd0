//! Stores: embedded defaults, persistence across reopen, journal replay and compaction, a
//! corrupt or truncated journal tail, a damaged snapshot, the directory lock.

use novanc::store::{Stores, Target, TABLEB};
use novanc::tooldata::sample_magazine;
use std::fs;
use std::path::{Path, PathBuf};

fn fresh(tag: &str) -> PathBuf {
    let d = Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("store-persist-{tag}"));
    let _ = fs::remove_dir_all(&d);
    d
}

fn open(d: &Path) -> (Stores, Vec<String>) {
    match Stores::open(d, 24) {
        Ok(x) => x,
        Err(e) => panic!("open {}: {e}", d.display()),
    }
}

fn text(s: &Stores, t: Target) -> String {
    s.buffer(t).text()
}

#[test]
fn a_new_directory_starts_on_the_embedded_defaults() {
    let d = fresh("defaults");
    let (s, w) = open(&d);
    assert!(w.is_empty(), "{w:?}");
    assert_eq!(s.program_names(), vec!["TABLEB".to_string()]);
    assert_eq!(s.current_program(), "TABLEB");
    assert_eq!(text(&s, Target::Program), TABLEB);
    assert_eq!(text(&s, Target::Mdi), "");
    assert_eq!(s.magazine(), sample_magazine());
    let tf = text(&s, Target::ToolFile);
    assert_eq!(tf.lines().count(), 24);
    assert!(tf.starts_with("T01 00610  BB"), "{tf}");
    assert!(tf.ends_with("T24\n"), "{tf}");
    assert!(d.join("state.snap").exists() && d.join("journal.log").exists());
}

#[test]
fn every_store_survives_a_reopen() {
    let d = fresh("reopen");
    {
        let (mut s, _) = open(&d);
        s.edit(Target::Program, "IN1*", None).unwrap();
        s.edit(Target::Mdi, "IGO, 10, 20, 30*CL*$-3M", None)
            .unwrap();
        s.program_read("part7", "P1 = (1, 2)\r\nDRL, 106/DP5/DA1, P1\r\n")
            .unwrap();
        s.edit(Target::Program, "SDRL", None).unwrap();
        s.new_program("empty").unwrap();
        s.select_program("Part7").unwrap();
        s.set_tcode(21, Some(999)).unwrap();
        s.edit(Target::ToolFile, "S00106$C1200$1500", None).unwrap();
    }
    let (s, w) = open(&d);
    assert!(w.is_empty(), "{w:?}");
    assert_eq!(s.program_names(), ["EMPTY", "PART7", "TABLEB"]);
    assert_eq!(s.current_program(), "PART7");
    assert_eq!(
        text(&s, Target::Program),
        "P1 = (1, 2)\nDRL, 106/DP5/DA1, P1\n"
    );
    assert_eq!(s.buffer(Target::Program).pointer(), 15);
    assert_eq!(s.program_text("tableb").unwrap(), format!("N1\n{TABLEB}"));
    assert_eq!(text(&s, Target::Mdi), "GO, 10, 20, 30\nCL\n");
    assert_eq!(s.buffer(Target::Mdi).pointer(), 15);
    let m = s.magazine();
    assert_eq!(m.tcodes.tool_in(21), Some(999));
    assert_eq!(m.find(106).unwrap().1.speed, 1500.0);
    assert!(text(&s, Target::ToolFile).contains("\nT21 00999\n"));
}

#[test]
fn the_journal_is_replayed_then_compacted() {
    let d = fresh("replay");
    {
        let (mut s, _) = open(&d);
        for i in 0..20 {
            s.edit(Target::Mdi, &format!("IN{i}*"), None).unwrap();
        }
        // A line that changes nothing (Y only) is not journaled.
        let before = fs::metadata(d.join("journal.log")).unwrap().len();
        let out = s.edit(Target::Mdi, "-2L2Y", None).unwrap();
        assert_eq!(out.y_output, "N18\nN19\n");
        let mid = fs::metadata(d.join("journal.log")).unwrap().len();
        assert!(mid > before, "pointer move is journaled");
        s.edit(Target::Mdi, "0Y", None).unwrap();
        assert_eq!(fs::metadata(d.join("journal.log")).unwrap().len(), mid);
    }
    let big = fs::metadata(d.join("journal.log")).unwrap().len();
    let (s, w) = open(&d);
    assert!(w.is_empty(), "{w:?}");
    let want: String = (0..20).map(|i| format!("N{i}\n")).collect();
    assert_eq!(text(&s, Target::Mdi), want);
    assert_eq!(s.buffer(Target::Mdi).pointer(), want.len() - 8);
    let small = fs::metadata(d.join("journal.log")).unwrap().len();
    assert!(small < big / 10, "compacted: {small} vs {big}");
}

#[test]
fn compaction_during_a_session_loses_nothing() {
    let d = fresh("limit");
    {
        let (mut s, _) = open(&d);
        s.set_journal_limit(3);
        for i in 0..10 {
            s.edit(Target::Program, &format!("IX{i}*"), None).unwrap();
        }
        assert!(fs::metadata(d.join("journal.log")).unwrap().len() < 200);
    }
    let (s, _) = open(&d);
    let want: String = (0..10).map(|i| format!("X{i}\n")).collect();
    assert_eq!(text(&s, Target::Program), format!("{want}{TABLEB}"));
}

/// Three MDI edits, then the journal as left on disk.
fn three_edits(d: &Path) -> Vec<u8> {
    let (mut s, _) = open(d);
    for l in ["IA*", "IB*", "IC*"] {
        s.edit(Target::Mdi, l, None).unwrap();
    }
    drop(s);
    fs::read(d.join("journal.log")).unwrap()
}

fn bad_copies(d: &Path) -> usize {
    fs::read_dir(d)
        .unwrap()
        .filter(|e| {
            e.as_ref()
                .map(|e| e.file_name().to_string_lossy().contains(".bad-"))
                .unwrap_or(false)
        })
        .count()
}

/// The byte length of one copy of the journal record of an MDI edit `line`.
fn one_copy(line: &str) -> usize {
    let payload = format!("edit M\n{line}");
    format!("@ {} 01234567\n", payload.len()).len() + payload.len() + 1
}

#[test]
fn a_truncated_journal_tail_is_reported_and_skipped() {
    let d = fresh("trunc");
    let j = three_edits(&d);
    // Cut inside the first copy of the last record: a crash while it was being written.
    let cut = j.len() - one_copy("IC*") - 4;
    fs::write(d.join("journal.log"), &j[..cut]).unwrap();
    let (s, w) = open(&d);
    assert_eq!(w.len(), 1, "{w:?}");
    assert!(
        w[0].starts_with("journal record 3 at byte") && w[0].contains("truncated"),
        "{}",
        w[0]
    );
    assert!(w[0].contains("edits before it are kept"), "{}", w[0]);
    assert!(w[0].contains("It is kept as journal.log.bad-"), "{}", w[0]);
    assert_eq!(text(&s, Target::Mdi), "A\nB\n");
    assert_eq!(bad_copies(&d), 1, "the damaged journal is kept");
    drop(s);
    let (s, w) = open(&d);
    assert!(w.is_empty(), "second open is clean: {w:?}");
    assert_eq!(text(&s, Target::Mdi), "A\nB\n");
}

#[test]
fn a_journal_cut_in_the_second_copy_keeps_the_record() {
    let d = fresh("trunc2");
    let j = three_edits(&d);
    fs::write(d.join("journal.log"), &j[..j.len() - 4]).unwrap();
    let (s, w) = open(&d);
    assert_eq!(w.len(), 1, "{w:?}");
    assert!(
        w[0].starts_with("journal record 3: its second copy is cut short")
            && w[0].contains("its first copy was used, nothing is lost"),
        "{}",
        w[0]
    );
    assert_eq!(text(&s, Target::Mdi), "A\nB\nC\n");
}

#[test]
fn a_corrupt_journal_record_is_read_from_its_second_copy() {
    let d = fresh("flip");
    let mut j = three_edits(&d);
    // Flip a byte inside the second edit record's first copy ("IB*").
    let i = j.windows(3).position(|w| w == b"IB*").unwrap();
    j[i + 1] = b'X';
    fs::write(d.join("journal.log"), &j).unwrap();
    let (s, w) = open(&d);
    assert_eq!(w.len(), 1, "{w:?}");
    assert!(
        w[0].starts_with("journal record 2 at byte")
            && w[0].contains("checksum does not match")
            && w[0].contains("its second copy was used, nothing is lost"),
        "{}",
        w[0]
    );
    assert_eq!(text(&s, Target::Mdi), "A\nB\nC\n");
    assert_eq!(bad_copies(&d), 1);
}

#[test]
fn a_journal_record_damaged_in_both_copies_stops_replay_there() {
    let d = fresh("flip2");
    let mut j = three_edits(&d);
    let i = j.windows(3).position(|w| w == b"IB*").unwrap();
    j[i + 1] = b'X';
    j[i + 1 + one_copy("IB*")] = b'X';
    fs::write(d.join("journal.log"), &j).unwrap();
    let (s, w) = open(&d);
    assert_eq!(w.len(), 1, "{w:?}");
    assert!(
        w[0].contains("in both copies; it and the 1 records after it cannot be replayed"),
        "{}",
        w[0]
    );
    assert!(!w[0].contains("crash while writing"), "{}", w[0]);
    assert_eq!(text(&s, Target::Mdi), "A\n");
    assert_eq!(bad_copies(&d), 1);
}

#[test]
fn garbage_after_the_journal_is_skipped() {
    let d = fresh("garbage");
    let mut j = three_edits(&d);
    j.extend_from_slice(b"\0\0\0\x7f garbage that is no record");
    fs::write(d.join("journal.log"), &j).unwrap();
    let (s, w) = open(&d);
    assert_eq!(w.len(), 1, "{w:?}");
    assert!(w[0].contains("record 4"), "{}", w[0]);
    assert_eq!(text(&s, Target::Mdi), "A\nB\nC\n");
}

#[test]
fn an_unreadable_journal_header_is_reported() {
    let d = fresh("header");
    let _ = three_edits(&d);
    fs::write(d.join("journal.log"), b"not a journal at all").unwrap();
    let (s, w) = open(&d);
    assert_eq!(w.len(), 1, "{w:?}");
    assert!(w[0].contains("journal header is unreadable"), "{}", w[0]);
    // The snapshot (taken at the open before the edits) is what remains.
    assert_eq!(text(&s, Target::Mdi), "");
    assert_eq!(text(&s, Target::Program), TABLEB);
}

#[test]
fn a_damaged_snapshot_is_read_from_its_second_copies_and_kept() {
    let d = fresh("snap");
    {
        let (mut s, _) = open(&d);
        s.edit(Target::Program, "IN1*", None).unwrap();
    }
    drop(open(&d)); // compacts the edit into the snapshot
    let mut snap = fs::read(d.join("state.snap")).unwrap();
    let n = snap.len();
    snap[n / 2] ^= 0x55;
    fs::write(d.join("state.snap"), &snap).unwrap();
    let (s, w) = open(&d);
    assert_eq!(w.len(), 1, "{w:?}");
    assert!(
        w[0].starts_with("the saved state state.snap was damaged (record ")
            && w[0].contains("nothing is lost. It is kept as state.snap.bad-"),
        "{}",
        w[0]
    );
    assert_eq!(text(&s, Target::Program), format!("N1\n{TABLEB}"));
    assert_eq!(bad_copies(&d), 1);
}

#[test]
fn an_unreadable_snapshot_starts_on_the_defaults_and_keeps_the_journal() {
    let d = fresh("snap-gone");
    {
        let (mut s, _) = open(&d);
        s.edit(Target::Program, "IN1*", None).unwrap();
    }
    fs::write(d.join("state.snap"), b"not a snapshot").unwrap();
    let (s, w) = open(&d);
    assert_eq!(w.len(), 2, "{w:?}");
    assert!(
        w[0].contains("cannot be read") && w[0].contains("embedded defaults"),
        "{}",
        w[0]
    );
    assert!(
        w[1].contains("the journal (1 records) was not replayed")
            && w[1].contains("kept as journal.log.bad-"),
        "{}",
        w[1]
    );
    assert_eq!(text(&s, Target::Program), TABLEB);
    assert_eq!(bad_copies(&d), 2);
}

#[test]
fn a_second_console_on_the_same_directory_is_refused() {
    let d = fresh("lock");
    let (_s, _) = open(&d);
    let e = Stores::open(&d, 24).err().unwrap();
    assert!(e.message.contains("another novanc"), "{e}");
}

#[test]
fn a_smaller_magazine_drops_the_pockets_beyond_it() {
    let d = fresh("capacity");
    {
        let (mut s, _) = open(&d);
        s.set_tcode(22, Some(777)).unwrap();
    }
    let (s, w) = Stores::open(&d, 20).unwrap();
    assert_eq!(
        w,
        ["T22 (tool 00777) is beyond the magazine's 20 pockets; it was removed from the T-code table"]
    );
    assert_eq!(s.capacity(), 20);
    assert_eq!(text(&s, Target::ToolFile).lines().count(), 20);
    assert_eq!(s.magazine().tcodes.tool_in(20), Some(108));
    assert!(Stores::open(&fresh("cap0"), 0).is_err());
}

#[test]
fn program_memory_refusals_change_nothing() {
    let d = fresh("programs");
    let (mut s, _) = open(&d);
    let e = s.select_program("NOPE").unwrap_err();
    assert_eq!(e.message, "no program NOPE in program memory");
    let e = s.program_read("bad name", "X").unwrap_err();
    assert_eq!(
        e.message,
        "program name 'BAD NAME' may not contain ' ' (letters, digits, _ - . only)"
    );
    let e = s.new_program("TABLEB").unwrap_err();
    assert_eq!(e.message, "program TABLEB is already in program memory");
    assert_eq!(s.program_names(), ["TABLEB"]);
    assert_eq!(s.current_program(), "TABLEB");
    // PROGRAM READ of an existing name replaces it.
    s.program_read("tableb", "CL\r").unwrap();
    assert_eq!(text(&s, Target::Program), "CL\n");
}

#[test]
fn deleting_programs() {
    let d = fresh("delete");
    let (mut s, _) = open(&d);
    assert_eq!(
        s.delete_program("TABLEB").unwrap_err().message,
        "TABLEB is the only program; program memory keeps at least one"
    );
    assert_eq!(
        s.delete_program("NOPE").unwrap_err().message,
        "no program NOPE in program memory"
    );
    assert_eq!(text(&s, Target::Program), TABLEB);
    s.program_read("A1", "CL\n").unwrap();
    s.delete_program("a1").unwrap();
    assert_eq!(s.current_program(), "TABLEB");
    s.program_read("A2", "CL\n").unwrap();
    s.delete_program("TABLEB").unwrap();
    drop(s);
    let (s, _) = open(&d);
    assert_eq!(s.program_names(), ["A2"]);
    assert_eq!(s.current_program(), "A2");
}

#[test]
fn the_mdi_buffer_can_be_cleared_and_names_are_normalised() {
    let d = fresh("mdi-clear");
    let (mut s, _) = open(&d);
    s.edit(Target::Mdi, "IGO, 1, 2, 3*", None).unwrap();
    s.clear_mdi().unwrap();
    s.program_read("two", "CL\n").unwrap();
    s.select_program("  tableb ").unwrap();
    drop(s);
    let (s, w) = open(&d);
    assert!(w.is_empty(), "{w:?}");
    assert_eq!(text(&s, Target::Mdi), "");
    assert_eq!(s.current_program(), "TABLEB");
}

#[test]
fn program_read_of_a_file_names_the_program_and_never_replaces_a_lookalike() {
    let d = fresh("read-file");
    let (mut s, _) = open(&d);
    // The reproducer: PRF exists; prüf.ap used to become PRF and silently replace it.
    s.program_read("PRF", "CL\n").unwrap();
    let r = s
        .program_read_file("/tapes/prüf.ap", "DA1 = (1, 2, 3)\n")
        .unwrap();
    assert_eq!(r.name, "PRUF");
    assert_eq!(r.changes, ["ü → U"]);
    assert!(!r.replaced);
    assert_eq!(s.program_text("PRF").unwrap(), "CL\n");
    // pruf.ap would be PRUF too, but with no change: the same tape read again replaces it.
    let r = s.program_read_file("pruf.ap", "X\r").unwrap();
    assert!(r.replaced && r.changes.is_empty());
    // prüf.ap again: PRUF exists and the name had to be changed: refused, nothing changed.
    let before = (s.program_names(), s.current_program().to_string());
    let e = s.program_read_file("prüf.ap", "Y\n").unwrap_err();
    assert_eq!(
        e.message,
        "tape prüf.ap is named PRUF (ü → U), and program memory already holds a program PRUF: it is not replaced, since the names match only because the file name was changed; rename the file, or delete PRUF first"
    );
    let e = s.program_read_file("prüf€.ap", "Y\n").unwrap_err();
    assert!(e.message.contains("'€' has no equivalent"), "{e}");
    assert_eq!((s.program_names(), s.current_program().to_string()), before);
    assert_eq!(s.program_text("PRUF").unwrap(), "X\n");
    drop(s);
    let (s, _) = open(&d);
    assert_eq!(s.program_names(), ["PRF", "PRUF", "TABLEB"]);
}

/// A program as large as a journal may grow (a CAM file read at file speed) is written once,
/// as a snapshot, not journaled and then compacted: it survives a reopen, and so do the
/// changes journaled after it.
#[test]
fn a_program_larger_than_the_journal_is_kept_by_a_snapshot() {
    let d = fresh("large");
    let mut big = String::new();
    let mut i = 0u32;
    while big.len() < 5 << 20 {
        big.push_str(&format!("G1 X{} Y{} F500\n", i % 500, i % 300));
        i += 1;
    }
    {
        let (mut s, _) = open(&d);
        s.program_read("cam5mb", &big).unwrap();
        let journal = fs::metadata(d.join("journal.log")).map_or(0, |m| m.len());
        assert!(
            journal < 1 << 20,
            "the program went to the snapshot, not the journal ({journal} bytes)"
        );
        s.edit(Target::Program, "IN1*", None).unwrap();
    }
    let (s, w) = open(&d);
    assert!(w.is_empty(), "{w:?}");
    assert_eq!(s.current_program(), "CAM5MB");
    assert_eq!(text(&s, Target::Program), format!("N1\n{big}"));
}
