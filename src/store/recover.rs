//! Opening a state directory: the snapshot read, the journal replayed onto it, and what is done
//! when either is damaged (docs/stores.md "Damage"). Pure: bytes in, state and notes out; the
//! caller reads the files and keeps the damaged ones aside.

use super::journal::JournalRead;
use super::record::{EditTarget, Record};
use super::snapshot;
use super::state::{Base, Refusal, State};

/// A warning for the operator, and the file it is about when that file is to be kept aside.
#[derive(Clone, Debug, PartialEq)]
pub struct Note {
    /// The file (in the state directory) to keep as `NAME.bad-SECONDS`, if any.
    pub file: Option<&'static str>,
    /// What happened, in the operator's words (without a final full stop).
    pub text: String,
}

/// What opening found.
#[derive(Debug)]
pub struct Loaded {
    /// The state: the snapshot (or what could be read of it) with the journal replayed.
    pub state: State,
    /// The highest generation seen; the next snapshot is one more.
    pub gen: u64,
    /// Warnings, each with the file it asks to keep aside.
    pub notes: Vec<Note>,
    /// Whether the files should be rewritten (anything replayed, damaged, missing or old).
    pub compact: bool,
}

/// Builds the state from the snapshot's bytes (None if there is no snapshot) and the journal
/// read (None if there is none). `base` says whose store it is (the centre's, with its
/// magazine capacity, or a lathe's) and what it holds with nothing saved. `snap` and `jour`
/// name the two files for the notes.
pub fn recover(
    snap: Option<&[u8]>,
    journal: Option<JournalRead>,
    base: &Base,
    files: (&'static str, &'static str),
) -> Loaded {
    let capacity = base.capacity();
    let (snap_file, jour_file) = files;
    let mut notes = Vec::new();
    let mut note = |file: Option<&'static str>, text: String| notes.push(Note { file, text });
    let mut compact = false;
    // The base: the snapshot, or what could be read of it, or the embedded defaults.
    let (mut state, snap_gen, salvaged, unreadable, stand_ins) = match snap {
        None => {
            compact = true;
            (base.defaults(), Some(0), false, false, Vec::new())
        }
        Some(bytes) => {
            let r = snapshot::read_base(bytes, base);
            compact |= r.old_format || !r.repaired.is_empty() || !r.lost.is_empty();
            if !r.repaired.is_empty() {
                note(
                    Some(snap_file),
                    format!(
                        "the saved state {snap_file} was damaged ({}); each damaged record was read from its other copy, nothing is lost",
                        r.repaired.join("; ")
                    ),
                );
            }
            if r.nothing {
                note(
                    Some(snap_file),
                    format!(
                        "the saved state {snap_file} cannot be read ({}); starting on the embedded defaults",
                        if r.lost.is_empty() { "no record in it reads".to_string() } else { r.lost.join("; ") }
                    ),
                );
            } else if !r.lost.is_empty() {
                note(
                    Some(snap_file),
                    format!(
                        "the saved state {snap_file} is damaged beyond repair; what could be read is used. Lost or rebuilt: {}",
                        r.lost.join("; ")
                    ),
                );
            }
            let salvaged = !r.lost.is_empty() && !r.nothing;
            (r.state, r.gen, salvaged, r.nothing, r.stand_ins)
        }
    };
    let mut gen = snap_gen.unwrap_or(0);
    match journal {
        None => compact = true,
        Some(j) => {
            compact |= j.old_format || !j.repaired.is_empty() || j.damage.is_some();
            for r in &j.repaired {
                note(Some(jour_file), r.clone());
            }
            let n = j.records.len();
            let replay_it = match (snap_gen, j.gen) {
                (_, None) => false,
                _ if unreadable => {
                    note(
                        Some(jour_file),
                        format!("the journal ({n} records) was not replayed: there is no saved state to replay it onto"),
                    );
                    false
                }
                (None, Some(jg)) => {
                    note(
                        Some(jour_file),
                        format!("the saved state's generation is unreadable, so the journal (generation {jg}) was taken to continue it"),
                    );
                    true
                }
                (Some(g), Some(jg)) if jg == g => true,
                (Some(g), Some(jg)) if jg > g => {
                    note(
                        Some(jour_file),
                        format!("the journal is newer than the saved state (generation {jg} > {g}); it was not replayed"),
                    );
                    false
                }
                // An older journal is already in the snapshot (a crash during compaction).
                _ => false,
            };
            if let Some(jg) = j.gen {
                gen = gen.max(jg);
            }
            // A journal not replayed must be replaced before anything is appended to it.
            compact |= !replay_it;
            if replay_it {
                let skipped = replay(&mut state, &j.records, stand_ins);
                compact |= n > 0;
                if !skipped.is_empty() {
                    let list: Vec<&str> = skipped.iter().take(6).map(String::as_str).collect();
                    let more = if skipped.len() > 6 { ", ..." } else { "" };
                    note(
                        Some(jour_file),
                        format!(
                            "{} of {n} journal records could not be replayed and were skipped: {}{more}",
                            skipped.len(),
                            list.join(", ")
                        ),
                    );
                } else if salvaged {
                    note(
                        Some(jour_file),
                        format!("the journal was replayed onto what could be read of the saved state: all {n} records"),
                    );
                }
            }
            if let Some(d) = j.damage {
                let torn = j.lost_after == 0 && j.gen.is_some();
                let tail = if torn {
                    ". This is what a crash while writing leaves; edits before it are kept"
                } else {
                    ""
                };
                note(Some(jour_file), format!("{d}{tail}"));
            }
        }
    }
    if state.tcodes.capacity() != capacity {
        for w in state.resize(capacity) {
            note(None, w);
        }
        compact = true;
    }
    Loaded {
        state,
        gen,
        notes,
        compact,
    }
}

/// The buffer an edit record changes, in words.
fn describe(t: &EditTarget) -> String {
    match t {
        EditTarget::Program(n) => format!("program {n}"),
        EditTarget::Mdi => "the MDI buffer".to_string(),
        EditTarget::ToolFile => "the tool file".to_string(),
    }
}

/// Replays journal records in order. A record that cannot be replayed is skipped, and so are
/// the later edits of the buffer it concerned (they would land in the wrong place) until a
/// whole new text replaces that buffer; the same for the buffers in `stand_ins` (lost from the
/// snapshot). Returns what was skipped and why.
fn replay(state: &mut State, records: &[Record], stand_ins: Vec<EditTarget>) -> Vec<String> {
    let mut broken: Vec<(EditTarget, &str)> = stand_ins
        .into_iter()
        .map(|t| (t, "it was lost from the saved state"))
        .collect();
    let mut skipped = Vec::new();
    for (i, rec) in records.iter().enumerate() {
        let n = i + 1;
        let target = match rec {
            Record::Edit { target, .. } => Some(target.clone()),
            _ => None,
        };
        if let Some((t, why)) = broken.iter().find(|(b, _)| Some(b) == target.as_ref()) {
            skipped.push(format!("record {n} (an edit of {}: {why})", describe(t)));
            continue;
        }
        match state.apply(rec, None) {
            Ok(_) => {
                let whole = match rec {
                    Record::ProgramRead { name, .. } | Record::NewProgram { name, .. } => {
                        Some(EditTarget::Program(name.clone()))
                    }
                    Record::ClearMdi => Some(EditTarget::Mdi),
                    Record::ToolFile(_) => Some(EditTarget::ToolFile),
                    _ => None,
                };
                if let Some(w) = whole {
                    broken.retain(|(t, _)| *t != w);
                }
            }
            Err(e) => {
                let why = match e {
                    Refusal::Edit(e) => e.to_string(),
                    Refusal::Other(m) => m,
                };
                skipped.push(format!("record {n} ({why})"));
                if let Some(t) = target {
                    broken.push((t, "it follows a skipped edit of it"));
                }
            }
        }
    }
    skipped
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::store::journal::parse;
    use crate::store::{Stores, Target};

    /// splitmix64, the seeded PRNG of the tests.
    use crate::pulse_core::testkit::Rng;

    /// A state directory with two programs, MDI text and revised tools in the snapshot, and
    /// every kind of journal record after it. Returns (snapshot, journal) bytes.
    fn files(tag: &str) -> (Vec<u8>, Vec<u8>) {
        let d = std::env::temp_dir().join(format!("novanc-recover-{tag}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        {
            let (mut s, _) = Stores::open(&d, 24).unwrap();
            s.edit(Target::Program, "999999LI;E1*", None).unwrap();
            s.program_read("PART7", "P1 = (1, 2)\nDRL, 106/DP5/DA1, P1\n")
                .unwrap();
            s.edit(Target::Mdi, "IGO, 1, 2, 3*", None).unwrap();
            s.edit(Target::ToolFile, "S00106$C1200$1500", None).unwrap();
        }
        let (mut s, _) = Stores::open(&d, 24).unwrap();
        s.edit(Target::Program, "IN5*", None).unwrap();
        s.select_program("TABLEB").unwrap();
        s.edit(Target::Program, "2LIN7*", None).unwrap();
        s.edit(Target::Mdi, "ICL*", None).unwrap();
        s.edit(Target::ToolFile, "L", None).unwrap();
        s.set_tcode(21, Some(999)).unwrap();
        s.move_tool(999, 22).unwrap();
        s.tool_read("00106 DR 6.5 150 40 1300 120 3\n", "t.tt")
            .unwrap();
        s.new_program("EMPTY").unwrap();
        s.program_read("R1", "CL\n").unwrap();
        s.delete_program("EMPTY").unwrap();
        s.clear_mdi().unwrap();
        s.edit(Target::Mdi, "IGO, 4, 5, 6*", None).unwrap();
        s.tcode_read("T01 00610\nT02 00106\nT05 00999\n", "m.tc")
            .unwrap();
        drop(s);
        let snap = std::fs::read(d.join("state.snap")).unwrap();
        let jour = std::fs::read(d.join("journal.log")).unwrap();
        let _ = std::fs::remove_dir_all(&d);
        (snap, jour)
    }

    fn open(snap: &[u8], jour: &[u8]) -> Loaded {
        recover(
            Some(snap),
            Some(parse(jour)),
            &Base::Centre(24),
            ("state.snap", "journal.log"),
        )
    }

    #[test]
    fn any_single_flipped_byte_in_either_file_loses_nothing() {
        let (snap, jour) = files("flip");
        let clean = open(&snap, &jour);
        assert!(clean.notes.is_empty(), "{:?}", clean.notes);
        let want = snapshot::encode(&clean.state, 0);
        assert!(clean.state.programs.contains_key("R1"));
        let mut rng = Rng::new(0x5EED_0015);
        for which in 0..2 {
            let data = if which == 0 { &snap } else { &jour };
            for i in 0..data.len() {
                let mut bad = data.clone();
                bad[i] ^= (rng.next_u64() % 255 + 1) as u8;
                let l = if which == 0 {
                    open(&bad, &jour)
                } else {
                    open(&snap, &bad)
                };
                let file = ["state.snap", "journal.log"][which];
                assert!(
                    snapshot::encode(&l.state, 0) == want,
                    "{file} byte {i}: state differs; notes {:?}",
                    l.notes
                );
                assert_eq!(l.notes.len(), 1, "{file} byte {i}: {:?}", l.notes);
                assert_eq!(l.notes[0].file, Some(file));
                assert!(
                    l.notes[0].text.contains("nothing is lost"),
                    "{file} byte {i}: {}",
                    l.notes[0].text
                );
                assert!(l.compact);
            }
        }
    }

    #[test]
    fn an_older_journal_is_ignored_and_replaced() {
        // A crash between writing snapshot G+1 and the journal of G+1: the journal of G is
        // already in the snapshot. It must not be replayed, nor appended to (it would be
        // ignored again at the next open, with whatever was appended).
        let s = State::defaults(24);
        let snap = snapshot::encode(&s, 8);
        let mut jour = crate::store::frame::encode_pair(b"novanc-journal 2 7");
        jour.extend(crate::store::frame::encode_pair(b"edit M\nIX*"));
        let l = open(&snap, &jour);
        assert!(l.notes.is_empty(), "{:?}", l.notes);
        assert_eq!(l.state.mdi.text(), "");
        assert_eq!(l.gen, 8);
        assert!(l.compact, "the old journal is replaced at open");
    }

    /// The same records in format 1: one copy each, the header's version 1.
    fn format_1(data: &[u8], head: &[u8]) -> Vec<u8> {
        let d = crate::store::frame::decode_paired(data);
        assert!(d.damage.is_none());
        let mut out = Vec::new();
        for (i, r) in d.records.iter().enumerate() {
            let mut p = r.to_vec();
            if i == 0 {
                p.splice(..head.len(), head.iter().copied());
            }
            out.extend(crate::store::frame::encode(&p));
        }
        out
    }

    #[test]
    fn format_1_files_are_read_and_rewritten() {
        let (snap, jour) = files("v1");
        let want = snapshot::encode(&open(&snap, &jour).state, 0);
        let snap1 = format_1(&snap, b"novanc-state 1");
        let jour1 = format_1(&jour, b"novanc-journal 1");
        assert!(snap1.len() < snap.len() * 6 / 10);
        let l = open(&snap1, &jour1);
        assert!(l.notes.is_empty(), "{:?}", l.notes);
        assert!(snapshot::encode(&l.state, 0) == want);
        assert!(l.compact, "rewritten as format 2");
        // A damaged format 1 snapshot: what reads before the damage is kept and said.
        let mut bad = snap1.clone();
        let at = bad.windows(13).position(|w| w == b"program PART7").unwrap();
        bad[at + 9] ^= 1;
        let l = open(&bad, &jour1);
        assert!(
            l.notes[0].text.contains("format 1 keeps one copy"),
            "{:?}",
            l.notes
        );
    }

    #[test]
    fn damage_in_both_copies_is_salvaged_and_reported() {
        let (snap, jour) = files("both");
        // Both copies of program PART7's record in the snapshot.
        let at = snap
            .windows(13)
            .position(|w| w == b"program PART7")
            .unwrap();
        let len = snap[at..].iter().position(|&b| b == b'@').unwrap() + at;
        let mut bad = snap.clone();
        bad[at + 10] ^= 1;
        let second = at
            + snap[at..]
                .windows(13)
                .skip(1)
                .position(|w| w == b"program PART7")
                .unwrap()
            + 1;
        assert!(second > len);
        bad[second + 10] ^= 1;
        let l = open(&bad, &jour);
        let texts: Vec<&str> = l.notes.iter().map(|n| n.text.as_str()).collect();
        assert!(texts[0].contains("damaged beyond repair"), "{texts:?}");
        // PART7's edit in the journal cannot be replayed; everything else is.
        assert!(
            texts[1].contains("1 of 14 journal records could not be replayed"),
            "{texts:?}"
        );
        assert!(texts[1].contains("record 1 (no program PART7"), "{texts:?}");
        assert_eq!(l.notes[0].file, Some("state.snap"));
        assert_eq!(l.notes[1].file, Some("journal.log"));
        assert!(!l.state.programs.contains_key("PART7"));
        assert_eq!(l.state.mdi.text(), "GO, 4, 5, 6\n");
        assert!(l.state.programs["TABLEB"].text().contains("N7\n"));
        assert_eq!(l.state.tcodes.tool_in(5), Some(999));
    }
}
