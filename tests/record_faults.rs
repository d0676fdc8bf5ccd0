//! Recording never blocks the producers: a full disk (`/dev/full`) or a recorder that falls
//! behind (a tiny queue) marks the recording incomplete, the producer carries on, and the
//! summary tells the operator what was lost.

mod common;

use novanc::record::{Event, Recorder};
use novanc::settings::MachineSettings;
use std::path::Path;
use std::time::{Duration, Instant};

fn batch(i: u64, n: u64) -> Event {
    Event::Pulses {
        axis: (i % 3) as u8,
        dir: 1,
        t_ns: (0..n).map(|k| i * 1_000_000 + k * 100).collect(),
    }
}

#[test]
fn full_disk_marks_the_recording_incomplete_and_never_blocks_the_producer() {
    let full = Path::new("/dev/full");
    if !full.exists() {
        eprintln!("\n!!!!! SKIPPED: no /dev/full on this system !!!!!\n");
        return;
    }
    let rec = Recorder::start(full, &MachineSettings::default())
        .expect("/dev/full opens; only writes fail");
    let sink = rec.sink();
    // About 60 MB of JSON: far beyond any buffer, so writes must reach the device and fail.
    let events = 2_000u64;
    let started = Instant::now();
    let mut worst_send = Duration::ZERO;
    for i in 0..events {
        let ev = batch(i, 2_000);
        let t = Instant::now();
        sink.send(ev);
        worst_send = worst_send.max(t.elapsed());
    }
    sink.send(Event::PanelEvent {
        t_ns: 1,
        event: "key STOP".into(),
    });
    // The operator sees it during the run, not only at the end.
    let deadline = Instant::now() + Duration::from_secs(10);
    while !sink.is_incomplete() && Instant::now() < deadline {
        std::thread::sleep(Duration::from_millis(5));
    }
    assert!(
        sink.is_incomplete(),
        "a disk error marks the recording incomplete"
    );
    assert!(rec.is_incomplete());
    let summary = rec
        .close()
        .expect("the recorder thread survives a disk error");
    eprintln!(
        "{summary}\n(sent {} events in {:?}, worst send {:?})",
        events + 1,
        started.elapsed(),
        worst_send
    );
    assert!(summary.incomplete);
    let err = summary
        .disk_error
        .as_deref()
        .expect("the disk error is reported");
    assert!(err.contains("/dev/full"), "{err}");
    assert!(err.contains("No space left on device"), "{err}");
    // Every event was taken off the queue: written before the error, dropped by a full queue,
    // or counted as lost to the disk error.
    assert_eq!(
        summary.total_messages() + summary.dropped + summary.lost_to_disk_error,
        events + 1
    );
    assert!(summary.lost_to_disk_error > 0);
    let line = summary.to_string();
    assert!(
        line.starts_with("RECORDING INCOMPLETE /dev/full:"),
        "{line}"
    );
    assert!(line.contains("DISK ERROR"), "{line}");
    // Sending afterwards neither blocks nor panics.
    sink.send(batch(0, 10));
}

#[test]
fn finish_fails_after_a_disk_error_with_the_operators_line() {
    if !Path::new("/dev/full").exists() {
        eprintln!("\n!!!!! SKIPPED: no /dev/full on this system !!!!!\n");
        return;
    }
    let rec = Recorder::start(Path::new("/dev/full"), &MachineSettings::default())
        .expect("/dev/full opens; only writes fail");
    rec.sink().send(batch(0, 10));
    let err = match rec.finish() {
        Ok(s) => panic!("finish reported success on /dev/full: {s}"),
        Err(e) => e,
    };
    assert!(
        err.starts_with(
            "RECORDING INCOMPLETE /dev/full: DISK ERROR writing /dev/full: No space left on device"
        ),
        "{err}"
    );
    assert!(err.contains("in the file: 0 blocks"), "{err}");
}

#[test]
fn a_recorder_that_falls_behind_drops_events_counts_them_and_keeps_a_valid_file() {
    let path = common::temp_path("overflow.mcap");
    let rec = Recorder::start_with_capacity(&path, &MachineSettings::default(), 1)
        .expect("start the recorder");
    assert_eq!(rec.capacity(), 1);
    let sink = rec.sink();
    let sent = 20_000u64;
    for i in 0..sent {
        sink.send(batch(i, 50));
    }
    assert!(sink.is_incomplete(), "a one-event queue overflows");
    let summary = rec.finish().expect("finish");
    eprintln!("{summary}");
    assert!(summary.incomplete);
    assert!(summary.dropped > 0);
    assert_eq!(summary.disk_error, None);
    assert_eq!(
        summary.total_messages() + summary.dropped,
        sent,
        "{summary}"
    );
    assert!(summary.to_string().contains(&format!(
        "{} events dropped (the recorder fell behind)",
        summary.dropped
    )));

    // The file is a complete MCAP that says it is an incomplete recording.
    let bytes = std::fs::read(&path).expect("read the recording");
    let _ = std::fs::remove_file(&path);
    let stream = mcap::MessageStream::new_with_options(
        &bytes,
        mcap::read::Options::ValidateChunkCrcs.into(),
    )
    .expect("a readable MCAP");
    let mut n = 0u64;
    for m in stream {
        m.expect("a good message");
        n += 1;
    }
    assert_eq!(n, summary.count("/nc/pulses"));
    let needle = b"dropped_events";
    assert!(bytes.windows(needle.len()).any(|w| w == needle));
    let text = String::from_utf8_lossy(&bytes);
    assert!(text.contains("complete"), "closing metadata present");
    let summary_meta = mcap::Summary::read(&bytes).unwrap().unwrap();
    assert!(summary_meta
        .metadata_indexes
        .iter()
        .any(|m| m.name == "novanc.recording"));
}

#[test]
fn a_file_that_cannot_be_created_is_refused_at_start() {
    let err = match Recorder::start(
        Path::new("/nonexistent-novanc-dir/run.mcap"),
        &MachineSettings::default(),
    ) {
        Ok(_) => panic!("started a recording in a missing directory"),
        Err(e) => e,
    };
    assert!(err.contains("/nonexistent-novanc-dir/run.mcap"), "{err}");
}
