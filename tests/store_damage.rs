//! A damaged snapshot or journal never loses an acknowledged edit when one copy of the damaged
//! record survives (both files hold every record twice), and damage beyond that is salvaged,
//! reported and both files kept aside (docs/stores.md "Damage"); the same for a lathe's
//! programs, tools and part counter, which are in the same journal.

use novanc::lathe::desc::LatheDesc;
use novanc::store::lathe::LatheStore;
use novanc::store::{Stores, Target, TABLEB};
use std::fs;
use std::path::{Path, PathBuf};

fn fresh(tag: &str) -> PathBuf {
    let d = Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("store-damage-{tag}"));
    let _ = fs::remove_dir_all(&d);
    d
}

fn open(d: &Path) -> (Stores, Vec<String>) {
    match Stores::open(d, 24) {
        Ok(x) => x,
        Err(e) => panic!("open {}: {e}", d.display()),
    }
}

/// Everything the stores show, as one string to compare.
fn dump(s: &Stores) -> String {
    let mut out = format!("current {}\n", s.current_program());
    for n in s.program_names() {
        out.push_str(&format!("program {n}\n{}", s.program_text(&n).unwrap()));
    }
    for t in [Target::Program, Target::Mdi, Target::ToolFile] {
        let b = s.buffer(t);
        out.push_str(&format!("{t:?} {}\n{}", b.pointer(), b.text()));
    }
    out.push_str(&format!("{:?}", s.magazine()));
    out
}

fn bad_copies(d: &Path) -> Vec<String> {
    let mut v: Vec<String> = fs::read_dir(d)
        .unwrap()
        .filter_map(|e| e.ok())
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .filter(|n| n.contains(".bad-"))
        .collect();
    v.sort();
    v
}

/// Position of the first `needle` in `hay`.
fn find(hay: &[u8], needle: &[u8]) -> usize {
    hay.windows(needle.len()).position(|w| w == needle).unwrap()
}

#[test]
fn the_reproducer_an_acknowledged_edit_survives_a_flipped_byte_in_the_snapshot() {
    let d = fresh("repro");
    {
        let (mut s, _) = open(&d);
        s.edit(Target::Program, "999999LI;E1*", None).unwrap(); // the display said ok
    }
    let mut snap = fs::read(d.join("state.snap")).unwrap();
    let i = find(&snap, TABLEB.lines().nth(2).unwrap().as_bytes());
    snap[i] ^= 0x01; // one byte of the program text
    fs::write(d.join("state.snap"), &snap).unwrap();
    let (s, w) = open(&d);
    assert_eq!(s.program_text("TABLEB").unwrap(), format!("{TABLEB};E1\n"));
    assert_eq!(w.len(), 1, "{w:?}");
    assert!(
        w[0].contains("state.snap was damaged")
            && w[0].contains("record checksum does not match")
            && w[0].contains("nothing is lost"),
        "{}",
        w[0]
    );
    assert_eq!(bad_copies(&d).len(), 1);
    drop(s);
    let (s, w) = open(&d);
    assert!(w.is_empty(), "{w:?}");
    assert_eq!(s.program_text("TABLEB").unwrap(), format!("{TABLEB};E1\n"));
}

#[test]
fn the_reproducer_damaged_in_both_copies_reports_the_loss_and_keeps_both_files() {
    let d = fresh("repro-both");
    {
        let (mut s, _) = open(&d);
        s.edit(Target::Mdi, "IGO, 1, 2, 3*", None).unwrap();
        s.edit(Target::Program, "999999LI;E1*", None).unwrap();
        s.edit(Target::Mdi, "ICL*", None).unwrap();
    }
    let mut snap = fs::read(d.join("state.snap")).unwrap();
    let line = TABLEB.lines().nth(2).unwrap().as_bytes();
    let i = find(&snap, line);
    let j = i + 1 + find(&snap[i + 1..], line);
    snap[i] ^= 0x01;
    snap[j] ^= 0x01;
    fs::write(d.join("state.snap"), &snap).unwrap();
    let journal = fs::read(d.join("journal.log")).unwrap();
    let (s, w) = open(&d);
    assert_eq!(w.len(), 2, "{w:?}");
    assert!(
        w[0].contains("state.snap is damaged beyond repair")
            && w[0].contains("every program (program memory holds Table B again)"),
        "{}",
        w[0]
    );
    assert!(
        w[1].contains("1 of 3 journal records could not be replayed")
            && w[1]
                .contains("record 2 (an edit of program TABLEB: it was lost from the saved state)")
            && w[1].contains("It is kept as journal.log.bad-"),
        "{}",
        w[1]
    );
    // The edits that did not need the lost program are there.
    assert_eq!(s.buffer(Target::Mdi).text(), "GO, 1, 2, 3\nCL\n");
    let kept = bad_copies(&d);
    assert_eq!(kept.len(), 2, "{kept:?}");
    assert_eq!(fs::read(d.join(&kept[0])).unwrap(), journal);
    assert_eq!(fs::read(d.join(&kept[1])).unwrap(), snap);
}

/// A state directory with a snapshot holding several programs and revised tools, and a
/// journal with every kind of change after it.
fn mixed(d: &Path) -> String {
    {
        let (mut s, _) = open(d);
        s.program_read("PART7", "P1 = (1, 2)\nDRL, 106/DP5/DA1, P1\n")
            .unwrap();
        s.edit(Target::Mdi, "IGO, 1, 2, 3*", None).unwrap();
        s.edit(Target::ToolFile, "S00106$C1200$1500", None).unwrap();
    }
    let (mut s, _) = open(d);
    s.edit(Target::Program, "LIN5*", None).unwrap();
    s.select_program("TABLEB").unwrap();
    s.edit(Target::Program, "999999LI;E1*", None).unwrap();
    s.edit(Target::Mdi, "ICL*", None).unwrap();
    s.set_tcode(21, Some(999)).unwrap();
    s.move_tool(999, 22).unwrap();
    s.tool_read("00106 DR 6.5 150 40 1300 120 3\n", "t.tt")
        .unwrap();
    s.edit(Target::ToolFile, "S00106$C6.5$6.6", None).unwrap();
    s.program_read("R1", "CL\n").unwrap();
    s.tcode_read("T01 00610\nT02 00106\nT05 00999\n", "m.tc")
        .unwrap();
    s.clear_mdi().unwrap();
    dump(&s)
}

/// Flips one byte of `d`'s snapshot or journal at a time (the first 24 bytes of each and 60
/// random places), opens the stores with `open_dump` (what they hold, as one string, and the
/// warnings) and checks each time that they hold `want`, with one warning saying nothing is
/// lost and the damaged file kept aside. Returns the number of opens.
fn flips_lose_nothing(
    d: &Path,
    want: &str,
    open_dump: impl Fn(&Path) -> (String, Vec<String>),
) -> usize {
    let snap = fs::read(d.join("state.snap")).unwrap();
    let jour = fs::read(d.join("journal.log")).unwrap();
    let mut rng = novanc::pulse_core::testkit::Rng::new(0x5EED_0015);
    let mut rnd = || rng.next_u64();
    let mut opens = 0;
    for (name, data) in [("state.snap", &snap), ("journal.log", &jour)] {
        // The first record's header and 60 random places.
        let mut at: Vec<usize> = (0..24).collect();
        at.extend((0..60).map(|_| (rnd() % data.len() as u64) as usize));
        for i in at {
            let mut bad = data.clone();
            bad[i] ^= (rnd() % 255 + 1) as u8;
            fs::write(d.join("state.snap"), &snap).unwrap();
            fs::write(d.join("journal.log"), &jour).unwrap();
            fs::write(d.join(name), &bad).unwrap();
            for b in bad_copies(d) {
                fs::remove_file(d.join(b)).unwrap();
            }
            let (got, w) = open_dump(d);
            opens += 1;
            assert_eq!(got, want, "{name} byte {i}: {w:?}");
            assert_eq!(w.len(), 1, "{name} byte {i}: {w:?}");
            assert!(w[0].contains("nothing is lost"), "{name} byte {i}: {w:?}");
            assert_eq!(bad_copies(d).len(), 1, "{name} byte {i}");
        }
    }
    opens
}

#[test]
fn a_flipped_byte_anywhere_in_either_file_loses_no_acknowledged_edit() {
    let d = fresh("flips");
    let want = mixed(&d);
    let opens = flips_lose_nothing(&d, &want, |d| {
        let (s, w) = open(d);
        (dump(&s), w)
    });
    eprintln!("{opens} opens with a flipped byte: no acknowledged edit lost");
}

/// Opens the Citizen's lathe stores in `state`: what they hold, as one string, and the
/// warnings.
fn lathe_open(state: &Path) -> (String, Vec<String>) {
    match LatheStore::open(state, &LatheDesc::citizen()) {
        Ok(o) => (
            format!(
                "{:?}\n{:?}\n{:?}\n{:?}",
                o.programs, o.tools, o.counter, o.posts
            ),
            o.warnings,
        ),
        Err(e) => panic!("open {}: {e}", state.display()),
    }
}

/// A lathe's state directory with revised programs, tools and counter in the snapshot, and a
/// journal with every kind of lathe change after it. Returns the directory `lathe-citizen/`.
fn lathe_mixed(state: &Path) -> PathBuf {
    let desc = LatheDesc::citizen();
    let mut tools = desc.channels[1].tools.clone();
    for round in 0..2 {
        let mut o = LatheStore::open(state, &desc).unwrap();
        let ch = round * 2;
        let mut p = o.programs[ch].clone();
        p.text.push_str(&format!("(ROUND {round})\n"));
        o.store.save_program(ch, &p).unwrap();
        tools[0].offset = [0.01 * (round + 1) as f64, -0.25];
        o.store.save_tools(1, &tools).unwrap();
        let mut c = o.counter.clone();
        c.counts[ch] += 2;
        o.store.save_counter(&c).unwrap();
        // The position memory (stop 61): a post about to move, then every post at rest.
        let post = |moving, x| novanc::store::lathe::Post {
            moving,
            pos: [x, -1_250],
        };
        let x = 20_000 + round as i64;
        o.store
            .save_posts(&[post(false, x), post(true, x), post(false, x)])
            .unwrap();
        o.store.save_posts(&[post(false, x); 3]).unwrap();
    }
    state.join("lathe-citizen")
}

/// Issue 22: the lathe's programs, tools and part counter are in the one journal, so a byte
/// flipped anywhere in the lathe's snapshot or journal loses nothing either.
#[test]
fn a_flipped_byte_in_a_lathes_files_loses_no_acknowledged_change() {
    let state = fresh("lathe-flips");
    let d = lathe_mixed(&state);
    let (want, w) = lathe_open(&state);
    assert!(w.is_empty(), "{w:?}");
    assert!(want.contains("(ROUND 1)") && want.contains("counts: [2, 0, 2]"));
    assert!(want.contains("pos: [20001, -1250]"), "{want}");
    // Put back the files as they were before that open compacted them.
    let d2 = lathe_mixed(&fresh("lathe-flips"));
    assert_eq!(d, d2);
    let opens = flips_lose_nothing(&d, &want, |_| lathe_open(&state));
    eprintln!("{opens} opens of a lathe's stores with a flipped byte: no acknowledged change lost");
}

/// Issue 22: a lathe's snapshot record damaged in both copies (channel 2's program) is said,
/// that program starts empty (never the sample in its place), everything else is kept, the
/// journal is replayed onto it, and the snapshot is kept aside.
#[test]
fn a_lathe_program_lost_from_both_copies_is_said_and_starts_empty() {
    let state = fresh("lathe-both");
    let d = lathe_mixed(&state);
    let mut snap = fs::read(d.join("state.snap")).unwrap();
    let line = b"chprog 2\n";
    let i = find(&snap, line);
    let j = i + 1 + find(&snap[i + 1..], line);
    snap[i + 20] ^= 0x01;
    snap[j + 20] ^= 0x01;
    fs::write(d.join("state.snap"), &snap).unwrap();
    let o = LatheStore::open(&state, &LatheDesc::citizen()).unwrap();
    assert_eq!(o.programs[1].text, "", "channel 2 got a program it lost");
    assert_eq!(o.programs[1].name, "CH2.NGC");
    assert!(o.programs[0].text.ends_with("(ROUND 0)\n"));
    assert!(o.programs[2].text.ends_with("(ROUND 1)\n"));
    assert_eq!(o.counter.counts, [2, 0, 2]);
    assert_eq!(o.tools[1].as_ref().unwrap()[0].offset, [0.02, -0.25]);
    assert_eq!(o.warnings.len(), 2, "{:?}", o.warnings);
    assert!(
        o.warnings[0].contains("state.snap is damaged beyond repair")
            && o.warnings[0].contains("channel 2's program (it starts empty)")
            && o.warnings[0].contains("It is kept as state.snap.bad-"),
        "{}",
        o.warnings[0]
    );
    assert!(
        o.warnings[1].contains("the journal was replayed onto what could be read"),
        "{}",
        o.warnings[1]
    );
    assert_eq!(bad_copies(&d).len(), 2);
}

/// Issue 22: a lathe's journal record damaged in both copies: the changes before it are
/// replayed, the loss is reported with the number of records after it, and the journal is
/// kept aside; nothing is half-applied.
#[test]
fn a_lathe_journal_record_lost_from_both_copies_is_reported() {
    let state = fresh("lathe-journal");
    let d = lathe_mixed(&state);
    let jour = fs::read(d.join("journal.log")).unwrap();
    // The second round's journal: its program, its tools, its counter, its two `posts`.
    // Damage the tools.
    let line = b"chtools 2\n";
    let i = find(&jour, line);
    let j = i + 1 + find(&jour[i + 1..], line);
    let mut bad = jour.clone();
    bad[i + 12] ^= 0x01;
    bad[j + 12] ^= 0x01;
    fs::write(d.join("journal.log"), &bad).unwrap();
    let o = LatheStore::open(&state, &LatheDesc::citizen()).unwrap();
    assert!(
        o.programs[2].text.ends_with("(ROUND 1)\n"),
        "before it: kept"
    );
    assert_eq!(o.tools[1].as_ref().unwrap()[0].offset, [0.01, -0.25]);
    assert_eq!(o.counter.counts, [2, 0, 0], "after it: not replayed");
    let kept = o.posts.expect("the first round's posts, from the snapshot");
    assert_eq!(kept[1].pos, [20_000, -1_250], "after it: not replayed");
    assert_eq!(o.warnings.len(), 1, "{:?}", o.warnings);
    assert!(
        o.warnings[0].contains("journal record 2")
            && o.warnings[0]
                .contains("in both copies; it and the 3 records after it cannot be replayed")
            && o.warnings[0].contains("It is kept as journal.log.bad-"),
        "{}",
        o.warnings[0]
    );
    assert_eq!(fs::read(d.join(&bad_copies(&d)[0])).unwrap(), bad);
}

#[test]
fn a_state_path_that_is_a_file_is_named_as_such() {
    let d = fresh("afile");
    fs::create_dir_all(&d).unwrap();
    let f = d.join("afile");
    fs::write(&f, b"keep me").unwrap();
    for p in [f.clone(), f.join("sub")] {
        let e = Stores::open(&p, 24).err().unwrap();
        assert_eq!(
            e.message,
            format!("{} is a regular file, not a directory", f.display())
        );
    }
    assert_eq!(fs::read(&f).unwrap(), b"keep me");
}
