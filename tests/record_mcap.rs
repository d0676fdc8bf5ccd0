//! The recorder writes docs/recording.md MCAP that Python's `mcap` reader accepts (`tests/mcap_check.py`:
//! CRCs, encodings, required fields, log-time order), and the script rejects what it should.

use novanc::record::testkit::synthetic_run;
use novanc::record::{Event, Recorder};
use novanc::settings::MachineSettings;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

mod common;
use common::python_check;

fn temp_path(name: &str) -> PathBuf {
    common::temp_path(&format!("{name}.mcap"))
}

fn record(path: &Path, evs: &[Event]) -> novanc::record::RecordSummary {
    let rec = Recorder::start(path, &MachineSettings::default()).expect("start the recorder");
    let sink = rec.sink();
    for ev in evs {
        sink.send(ev.clone());
    }
    rec.finish().expect("finish the recording")
}

// ---------------------------------------------------------------- Python's mcap reader

const ALL_TOPICS: [&str; 7] = [
    "--expect-topics",
    "/nc/block",
    "/nc/position",
    "/nc/pulses",
    "/nc/state",
    "/panel/display",
    "/panel/event",
];

#[test]
fn python_mcap_reader_accepts_the_recording() {
    let path = temp_path("record-python");
    let evs = synthetic_run(7, 400);
    let summary = record(&path, &evs);
    assert!(!summary.incomplete, "{summary}");
    let mut args = ALL_TOPICS.to_vec();
    args.push("--expect-complete");
    let result = python_check(&path, &args);
    let _ = std::fs::remove_file(&path);
    let Some((ok, text)) = result else { return };
    assert!(ok, "mcap_check.py failed:\n{text}");
    eprintln!("{text}");
    let pulses = summary.pulses;
    assert!(text.contains("OK "), "{text}");
    // The script's per-topic counts match the recorder's.
    for topic in &ALL_TOPICS[1..] {
        let line = text
            .lines()
            .find(|l| l.starts_with(topic) && l.ends_with("messages"))
            .unwrap_or_else(|| panic!("no count for {topic}:\n{text}"));
        let n: u64 = line.split_whitespace().nth(1).unwrap().parse().unwrap();
        assert_eq!(n, summary.count(topic), "{topic}");
    }
    let axes = text.lines().find(|l| l.starts_with("pulses")).unwrap();
    let total: u64 = axes
        .split_whitespace()
        .filter_map(|w| w.parse::<u64>().ok())
        .sum();
    assert_eq!(total, pulses);
}

#[test]
fn python_check_fails_on_a_corrupted_chunk_and_a_missing_topic() {
    let path = temp_path("record-corrupt");
    let evs = synthetic_run(9, 50);
    record(&path, &evs);
    // A missing topic is reported.
    let result = python_check(&path, &["--expect-topics", "/nc/nothing"]);
    let Some((ok, text)) = result else {
        let _ = std::fs::remove_file(&path);
        return;
    };
    assert!(!ok && text.contains("no message on /nc/nothing"), "{text}");
    // One flipped digit inside a pulse time breaks the chunk CRC.
    let mut bytes = std::fs::read(&path).unwrap();
    let at = bytes
        .windows(6)
        .position(|w| w == b"t_ns\":")
        .expect("a pulse message")
        + 8;
    bytes[at] = if bytes[at] == b'1' { b'2' } else { b'1' };
    std::fs::write(&path, &bytes).unwrap();
    let (ok, text) = python_check(&path, &[]).unwrap();
    let _ = std::fs::remove_file(&path);
    assert!(!ok, "a corrupted file passed:\n{text}");
    assert!(text.to_lowercase().contains("crc"), "{text}");
}

/// Writes a small MCAP by hand: one channel on `topic` with the given encodings and messages
/// (log time, JSON text).
fn hand_made(path: &Path, topic: &str, schema_enc: &str, msg_enc: &str, msgs: &[(u64, &str)]) {
    let file = std::io::BufWriter::new(std::fs::File::create(path).unwrap());
    let mut w = mcap::WriteOptions::new()
        .compression(None)
        .create(file)
        .unwrap();
    let schema = w
        .add_schema(
            "x",
            schema_enc,
            br#"{"type":"object","required":["seq","stmt","text"]}"#,
        )
        .unwrap();
    let ch = w
        .add_channel(schema, topic, msg_enc, &BTreeMap::new())
        .unwrap();
    for (i, (t, text)) in msgs.iter().enumerate() {
        let header = mcap::records::MessageHeader {
            channel_id: ch,
            sequence: i as u32,
            log_time: *t,
            publish_time: *t,
        };
        w.write_to_known_channel(&header, text.as_bytes()).unwrap();
    }
    w.finish().unwrap();
}

/// Topic, schema encoding, message encoding, (log time, JSON) messages, expected complaint
/// (empty: the file is good).
type Case<'a> = (&'a str, &'a str, &'a str, Vec<(u64, &'a str)>, &'a str);

#[test]
fn python_check_rejects_bad_encodings_missing_fields_and_time_going_back() {
    let path = temp_path("record-handmade");
    let good = r#"{"seq":1,"stmt":1,"text":"N1"}"#;
    let cases: [Case; 5] = [
        (
            "/nc/block",
            "jsonschema",
            "json",
            vec![(1, good), (2, good)],
            "",
        ),
        (
            "/nc/block",
            "jsonschema",
            "cbor",
            vec![(1, good)],
            "not 'json'",
        ),
        (
            "/nc/block",
            "protobuf",
            "json",
            vec![(1, good)],
            "not 'jsonschema'",
        ),
        (
            "/nc/block",
            "jsonschema",
            "json",
            vec![(1, r#"{"seq":1,"text":"N1"}"#)],
            "lacks 'stmt'",
        ),
        (
            "/nc/block",
            "jsonschema",
            "json",
            vec![(5, good), (4, good)],
            "log time goes back",
        ),
    ];
    for (topic, schema_enc, msg_enc, msgs, want) in cases {
        hand_made(&path, topic, schema_enc, msg_enc, &msgs);
        let Some((ok, text)) = python_check(&path, &[]) else {
            let _ = std::fs::remove_file(&path);
            return;
        };
        if want.is_empty() {
            assert!(ok, "a good file was refused:\n{text}");
        } else {
            assert!(!ok && text.contains(want), "expected {want:?}:\n{text}");
        }
    }
    let _ = std::fs::remove_file(&path);
}
