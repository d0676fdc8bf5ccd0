//! Recordings Foxglove draws (issue 25, docs/recording.md "Foxglove topics"): every
//! `foxglove.*` message of a recorded Table B run, and of a script with a program message and
//! an alarm, validated against Foxglove's published JSON Schemas (the `@foxglove/schemas` npm
//! package that `.ci/run` installs, read by `tests/foxglove_check.py`), the scene's path
//! against `/nc/position`, and the attachments and metadata read back.

mod common;

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// Where `.ci/run` installs `@foxglove/schemas`.
fn package() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("target/foxglove-schemas")
}

/// Runs `tests/foxglove_check.py` on a recording; its output (None: skipped, said loudly).
fn foxglove_check(rec: &Path) -> Option<String> {
    let pkg = package();
    let (ok, text) = common::python_script(
        "foxglove_check.py",
        &["mcap", "jsonschema"],
        &[rec.as_os_str(), "--package".as_ref(), pkg.as_os_str()],
    )?;
    assert!(ok, "{text}");
    Some(text)
}

/// The file's attachments (name → (media type, bytes)), metadata records (name → map), and
/// the message count and schema name of every topic.
struct Read {
    attachments: BTreeMap<String, (String, Vec<u8>)>,
    metadata: BTreeMap<String, BTreeMap<String, String>>,
    /// Every `novanc.program` record, in file order (a kernel's machine has one per channel).
    programs: Vec<BTreeMap<String, String>>,
    topics: BTreeMap<String, (String, u64)>,
    logs: Vec<String>,
    /// The messages of `/foxglove/scene` and `/foxglove/tool`.
    scene: Vec<String>,
    frames: Vec<String>,
}

fn read(path: &Path) -> Read {
    let bytes = std::fs::read(path).unwrap();
    let summary = mcap::Summary::read(&bytes).unwrap().expect("a summary");
    let mut attachments = BTreeMap::new();
    for i in &summary.attachment_indexes {
        let a = mcap::read::attachment(&bytes, i).unwrap();
        attachments.insert(a.name.clone(), (a.media_type.clone(), a.data.to_vec()));
    }
    let mut metadata = BTreeMap::new();
    let mut programs = Vec::new();
    for i in &summary.metadata_indexes {
        let m = mcap::read::metadata(&bytes, i).unwrap();
        if m.name == "novanc.program" {
            programs.push(m.metadata.clone());
        }
        metadata.insert(m.name, m.metadata);
    }
    let stats = summary.stats.as_ref().unwrap();
    let mut topics = BTreeMap::new();
    for ch in summary.channels.values() {
        let schema = ch.schema.as_ref().unwrap();
        assert_eq!(
            (schema.encoding.as_str(), ch.message_encoding.as_str()),
            ("jsonschema", "json")
        );
        let n = stats
            .channel_message_counts
            .get(&ch.id)
            .copied()
            .unwrap_or(0);
        topics.insert(ch.topic.clone(), (schema.name.clone(), n));
    }
    let on = |topic: &str| -> Vec<String> {
        mcap::MessageStream::new(&bytes)
            .unwrap()
            .map(|m| m.unwrap())
            .filter(|m| m.channel.topic == topic)
            .map(|m| String::from_utf8(m.data.to_vec()).unwrap())
            .collect()
    };
    Read {
        attachments,
        metadata,
        programs,
        topics,
        logs: on("/foxglove/log"),
        scene: on("/foxglove/scene"),
        frames: on("/foxglove/tool"),
    }
}

#[test]
fn table_b_recording_draws_in_foxglove_with_the_published_schemas() {
    let dir = common::temp_dir("foxglove-tableb");
    let rec = dir.join("t.mcap");
    let prog = Path::new(env!("CARGO_MANIFEST_DIR")).join("programs/tableb.ap");
    let out = common::novanc_command()
        .arg("run")
        .arg(&prog)
        .arg("--record")
        .arg(&rec)
        .args(["--pulses", "off"])
        .output()
        .unwrap();
    assert!(out.status.success(), "{out:?}");
    let r = read(&rec);

    // The topics, beside the existing ones.
    let topic = |t: &str| r.topics.get(t).cloned().unwrap_or_default();
    assert_eq!(topic("/foxglove/scene").0, "foxglove.SceneUpdate");
    assert_eq!(topic("/foxglove/tool").0, "foxglove.FrameTransform");
    assert_eq!(topic("/foxglove/log").0, "foxglove.Log");
    assert_eq!(topic("/nc/position").0, "novanc.Position");
    // A transform every 40 ms of motion and at every rest, not one per position.
    let (tools, positions) = (topic("/foxglove/tool").1, topic("/nc/position").1);
    assert!(
        tools > positions / 8 && tools < positions / 3,
        "{tools} {positions}"
    );
    assert!(topic("/foxglove/scene").1 > topic("/nc/block").1 / 2);

    // The attachments: the program as it was run, the tool data, the offsets, the machine.
    let text = std::fs::read(&prog).unwrap();
    let name = format!("program/{}", prog.display());
    assert_eq!(
        r.attachments.get(&name),
        Some(&("text/plain".to_string(), text.clone())),
        "{:?}",
        r.attachments.keys()
    );
    let (media, tools) = &r.attachments["tooldata.csv"];
    assert_eq!(media, "text/csv");
    let tools = String::from_utf8(tools.clone()).unwrap();
    let magazine = novanc::tooldata::sample_magazine();
    assert_eq!(tools.lines().count(), magazine.tools.iter().count() + 1);
    for (t, rec) in magazine.tools.iter() {
        let line = format!(
            "{t},{},{:?},{},{},",
            rec.number, rec.kind, rec.diameter, rec.set_length
        );
        assert!(tools.contains(&line), "{line} not in\n{tools}");
    }
    let (media, wpo) = &r.attachments["work_offsets.csv"];
    assert_eq!(media, "text/csv");
    assert!(String::from_utf8_lossy(wpo).contains("\nG54,0,0,0\n"));
    let (media, machine) = &r.attachments["machine.json"];
    assert_eq!(media, "application/json");
    let machine = String::from_utf8_lossy(machine);
    assert!(
        machine.starts_with("{\"pulse_mm\":0.001,") && machine.contains("\"z_min_mm\":-600,"),
        "{machine}"
    );
    let p = &r.metadata["novanc.program"];
    assert_eq!(p["name"], prog.display().to_string());
    assert_eq!(p["bytes"], text.len().to_string());
    assert_eq!(p["tools"], magazine.tools.iter().count().to_string());
    assert!(r.metadata.contains_key("novanc.settings"));

    // Every Foxglove message against the published schemas; the path against /nc/position.
    if let Some(text) = foxglove_check(&rec) {
        for s in ["foxglove.SceneUpdate", "foxglove.FrameTransform"] {
            assert!(text.contains(&format!("foxglove {s} ")), "{text}");
        }
        assert!(text.contains("\nOK"), "{text}");
    }
    // And the file is still what every other reader expects.
    if let Some((ok, text)) = common::python_check(&rec, &["--expect-complete"]) {
        assert!(ok, "{text}");
    }
}

/// A program with an arc, a message, and an E-STOP in its last feed.
#[test]
fn messages_and_alarms_go_to_the_foxglove_log() {
    let dir = common::temp_dir("foxglove-log");
    let p = dir.join("p.ngc");
    std::fs::write(
        &p,
        "G0 X10 Y10\n(MSG, check the clamps)\nG1 X100 F3000\nG2 X150 Y60 R50\nG1 X400 F300\nG0 X20\nM30\n",
    )
    .unwrap();
    let script = format!(
        "op DATA\ndata READ\ntape {}\nstart\nwait\nop AUTO\nstart\nwait ms 5000\nestop\nreset\n",
        p.display()
    );
    let (rec, _) = common::recorded_script(&dir, &script);
    let r = read(&rec);
    let has = |level: u8, text: &str| {
        r.logs.iter().any(|l| {
            l.contains(&format!("\"level\":{level},"))
                && l.contains(text)
                && l.contains("\"name\":\"console\",\"file\":\"P.NGC\"")
        })
    };
    assert!(has(2, "MSG: check the clamps"), "{:#?}", r.logs);
    assert!(has(4, "EMERGENCY STOP"), "{:#?}", r.logs);
    // The program in memory when the recording started (the console's sample, none read yet),
    // and its tool file.
    let p = &r.metadata["novanc.program"];
    let (media, text) = &r.attachments[&format!("program/{}", p["name"])];
    assert_eq!(
        (media.as_str(), text.len().to_string()),
        ("text/plain", p["bytes"].clone())
    );
    assert!(!p["name"].is_empty() && p["tools"] != "0", "{p:?}");
    assert!(r.attachments.contains_key("tooldata.csv"));
    if let Some(text) = foxglove_check(&rec) {
        assert!(text.contains("foxglove foxglove.Log "), "{text}");
        assert!(text.contains("\nOK"), "{text}");
    }
}

/// A lathe's recorded run (`novanc run --machine citizen --record`): each channel's path and
/// tool post drawn in its own frame `channelN`, placed once in `machine`, every derived message
/// carrying its `"channel"`; the metadata names the machine and its channels, and each
/// channel's program, tool post and description are attached (docs/recording.md).
#[test]
fn a_lathe_recording_draws_each_channel_and_names_the_machine() {
    let dir = common::temp_dir("foxglove-lathe");
    let rec = dir.join("l.mcap");
    let progs = Path::new(env!("CARGO_MANIFEST_DIR")).join("programs/citizen");
    let out = common::novanc_command()
        .args(["run", "--machine", "citizen"])
        .arg(&progs)
        .args(["--parts", "2", "--record"])
        .arg(&rec)
        .output()
        .unwrap();
    assert!(out.status.success(), "{out:?}");
    let r = read(&rec);
    for n in 1..=3 {
        let tag = format!("{{\"channel\":{n},");
        let strips = r
            .scene
            .iter()
            .filter(|m| {
                m.starts_with(&tag)
                    && m.contains(&format!(
                        "\"frame_id\":\"channel{n}\",\"id\":\"channel{n}/N"
                    ))
            })
            .count();
        assert!(strips > 5, "channel {n}: {strips} strips");
        assert!(
            r.scene
                .iter()
                .any(|m| m.starts_with(&tag) && m.contains(&format!("\"id\":\"channel{n}/tool\""))),
            "channel {n}: no tool"
        );
        let placed = format!("\"parent_frame_id\":\"machine\",\"child_frame_id\":\"channel{n}\"");
        assert_eq!(
            r.frames.iter().filter(|m| m.contains(&placed)).count(),
            1,
            "channel {n}"
        );
        let post =
            format!("\"parent_frame_id\":\"channel{n}\",\"child_frame_id\":\"channel{n}/tool\"");
        assert!(
            r.frames
                .iter()
                .any(|m| m.starts_with(&tag) && m.contains(&post)),
            "channel {n}"
        );
    }
    // No channel's message is drawn as the single machine's.
    assert!(!r
        .scene
        .iter()
        .any(|m| m.contains("\"frame_id\":\"machine\"")));

    // The machine and its channels, each channel's program, tool post and description.
    let s = &r.metadata["novanc.settings"];
    assert_eq!(
        (s["machine"].as_str(), s["channels"].as_str()),
        ("citizen", "3")
    );
    assert_eq!(r.programs.len(), 3, "{:?}", r.programs);
    for (i, p) in r.programs.iter().enumerate() {
        let n = i + 1;
        assert_eq!(p["channel"], n.to_string());
        assert!(!p["channel_name"].is_empty(), "{p:?}");
        let file = progs.join(format!("system{n}.ngc"));
        let text = std::fs::read(&file).unwrap();
        assert_eq!(p["name"], file.display().to_string());
        assert_eq!(p["bytes"], text.len().to_string());
        assert_eq!(
            r.attachments[&format!("channel{n}/program/{}", file.display())],
            ("text/plain".to_string(), text)
        );
        let (media, tools) = &r.attachments[&format!("channel{n}/tooldata.csv")];
        let tools = String::from_utf8_lossy(tools);
        assert_eq!(media, "text/csv");
        assert!(tools.starts_with("tool,nose_radius_mm,tip,x_offset_mm,z_offset_mm\n"));
        assert_eq!(
            tools.lines().count().to_string(),
            (p["tools"].parse::<usize>().unwrap() + 1).to_string()
        );
        assert!(p["tools"] != "0", "{p:?}");
        // Its work offsets G54–G59 as the recording starts (stop 57): the Citizen's are 0.
        let (media, wpo) = &r.attachments[&format!("channel{n}/work_offsets.csv")];
        assert_eq!(media, "text/csv");
        assert_eq!(
            String::from_utf8_lossy(wpo),
            "system,x_mm,z_mm\nG54,0,0\nG55,0,0\nG56,0,0\nG57,0,0\nG58,0,0\nG59,0,0\n"
        );
        let (media, machine) = &r.attachments[&format!("channel{n}/machine.json")];
        assert_eq!(media, "application/json");
        assert!(
            String::from_utf8_lossy(machine).contains("\"ncbr_period_ns\":100000,"),
            "{}",
            String::from_utf8_lossy(machine)
        );
    }

    // Every Foxglove message against the published schemas; each channel's path against its
    // own /nc/position.
    if let Some(text) = foxglove_check(&rec) {
        assert!(text.contains("channels drawn 3"), "{text}");
        for n in 1..=3 {
            assert!(
                text.contains(&format!("channel {n}: path points")),
                "{text}"
            );
        }
        assert!(text.contains("\nOK"), "{text}");
    }
    if let Some((ok, text)) = common::python_check(&rec, &["--expect-complete"]) {
        assert!(ok, "{text}");
    }
}

/// A file with one `/foxglove/log` message `msg` under the schema text `schema`.
fn one_log(dir: &Path, name: &str, schema: &str, msg: &str) -> PathBuf {
    let path = dir.join(name);
    let mut w = mcap::Writer::new(std::io::BufWriter::new(
        std::fs::File::create(&path).unwrap(),
    ))
    .unwrap();
    let s = w
        .add_schema("foxglove.Log", "jsonschema", schema.as_bytes())
        .unwrap();
    let c = w
        .add_channel(s, "/foxglove/log", "json", &BTreeMap::new())
        .unwrap();
    let header = mcap::records::MessageHeader {
        channel_id: c,
        sequence: 0,
        log_time: 5,
        publish_time: 5,
    };
    w.write_to_known_channel(&header, msg.as_bytes()).unwrap();
    w.finish().unwrap();
    path
}

#[test]
fn the_foxglove_check_fails_on_a_bad_message_a_wrong_time_and_a_hand_copied_schema() {
    let dir = common::temp_dir("foxglove-bad");
    let schema = novanc::record::foxglove::LOG_SCHEMA;
    let msg = |level: u8, nsec: u64| {
        format!(
            r#"{{"timestamp":{{"sec":0,"nsec":{nsec}}},"level":{level},"message":"m","name":"n","file":"","line":0}}"#
        )
    };
    let run = |name: &str, schema: &str, msg: &str| {
        let path = one_log(&dir, name, schema, msg);
        let pkg = package();
        common::python_script(
            "foxglove_check.py",
            &["mcap", "jsonschema"],
            &[path.as_os_str(), "--package".as_ref(), pkg.as_os_str()],
        )
    };
    let Some((ok, text)) = run("good.mcap", schema, &msg(2, 5)) else {
        return;
    };
    assert!(ok, "{text}");
    let (ok, text) = run("level.mcap", schema, &msg(7, 5)).unwrap();
    assert!(!ok && text.contains("['level']"), "{text}");
    let (ok, text) = run("time.mcap", schema, &msg(2, 6)).unwrap();
    assert!(!ok && text.contains("is not the log time 5"), "{text}");
    let copy = schema.replace("\"Log message\"", "\"Log msg\"");
    let (ok, text) = run("copy.mcap", &copy, &msg(2, 5)).unwrap();
    assert!(!ok && text.contains("is not the package's"), "{text}");
}
