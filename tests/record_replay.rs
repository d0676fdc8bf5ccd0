//! The recording is the operator's log: the `/panel/event` lines of a session driven by keys,
//! as the terminal presses them, read back as a panel script (`Panel::read_script`) and played
//! on a fresh console, end where the session ended: the same display, program, MDI lines and
//! tools. Random key sequences on the centre and on the Citizen lathe. Before stop 39 the
//! centre's recording lost the keys a page took (OFS revisions typed at the terminal) and
//! doubled a script's page keys.

mod common;

use novanc::console::{ConsoleConfig, Panel};
use novanc::lathe::desc::LatheDesc;
use novanc::panel_model::PanelEvent;
use novanc::pulse_core::testkit::Rng;
use novanc::pulse_core::ClockMode;
use novanc_panel::Key;
use std::path::Path;

/// The keys a session is made of: the data keys, EOB and RUBOUT, the page keys, the cursor
/// keys, both selectors, START, STOP, RESET, the overrides and switches, the handwheel.
fn keys() -> Vec<Key> {
    let mut k: Vec<Key> = "G0X1Z-5.T2M3#=".chars().map(Key::Char).collect();
    k.extend([
        Key::Enter,
        Key::Enter,
        Key::Backspace,
        Key::Tab,
        Key::Esc,
        Key::Delete,
    ]);
    k.extend("podegu".chars().map(Key::Ctrl));
    k.extend(common::CURSOR_KEYS);
    k.extend((1..=7).map(Key::F));
    k.extend([Key::F(8), Key::F(9), Key::F(10), Key::F(11)]);
    // The tape reader key takes the typed line (a path no file has: refused, said).
    k.extend("1234567=-wf[]db,.cxnt".chars().map(Key::Alt));
    k
}

/// The console of `lathe` (None: the centre) on `state`, virtual time, recording to `rec`.
fn open(lathe: Option<&LatheDesc>, state: &Path, rec: Option<&Path>) -> Panel {
    let mut cfg = ConsoleConfig::new(state.to_path_buf());
    cfg.clock = ClockMode::Virtual;
    cfg.record = rec.map(Path::to_path_buf);
    Panel::open(lathe.cloned(), cfg)
        .unwrap_or_else(|e| panic!("{e}"))
        .0
}

/// The `/panel/event` lines of a recording, as a panel script.
fn script_of(rec: &Path) -> String {
    let bytes = std::fs::read(rec).unwrap_or_else(|e| panic!("{e}"));
    let mut out = String::new();
    for m in mcap::MessageStream::new(&bytes).unwrap_or_else(|e| panic!("{e}")) {
        let m = m.unwrap_or_else(|e| panic!("{e}"));
        if m.channel.topic != "/panel/event" {
            continue;
        }
        let j = String::from_utf8_lossy(&m.data).into_owned();
        let line = j
            .strip_prefix("{\"event\":\"")
            .and_then(|l| l.strip_suffix("\"}"))
            .unwrap_or_else(|| panic!("an event line: {j}"));
        out.push_str(&line.replace("\\\"", "\"").replace("\\\\", "\\"));
        out.push('\n');
    }
    out
}

/// What the replay must end with: the frame, unless the MSG page is up (its entries carry the
/// time of day).
fn end_state(p: &mut Panel) -> String {
    let f = p.frame_text();
    if f.lines().any(|l| l.starts_with("MSG ")) {
        String::new()
    } else {
        f
    }
}

fn replays(lathe: Option<LatheDesc>, seed: u64, n: usize) {
    let keys = keys();
    let mut rng = Rng::new(seed);
    let dir = common::temp_dir(&format!("replay-{}-{seed}", lathe.is_some()));
    let rec = dir.join("r.mcap");
    let mut a = open(lathe.as_ref(), &dir.join("a"), Some(&rec));
    let mut pressed = Vec::new();
    for _ in 0..n {
        if rng.chance(0.1) {
            let ms = [5, 50, 500][rng.below(3)];
            a.handle(PanelEvent::WaitMs(ms));
            pressed.push(format!("wait ms {ms}"));
        } else {
            let k = *rng.pick(&keys);
            a.press(k);
            pressed.push(format!("key {}", novanc::console::keys::key_name(k)));
        }
    }
    a.handle(PanelEvent::Wait);
    let want = end_state(&mut a);
    assert!(a.close(None).is_ok());
    let script = script_of(&rec);
    let events = Panel::read_script(lathe.as_ref(), &script)
        .unwrap_or_else(|(l, e)| panic!("line {l}: {e}\n{script}"));
    let mut b = open(lathe.as_ref(), &dir.join("b"), None);
    for ev in events {
        b.handle(ev);
    }
    let got = end_state(&mut b);
    assert_eq!(
        got,
        want,
        "seed {seed}: the replay ends elsewhere\npressed:\n{}\nrecorded:\n{script}",
        pressed.join("\n")
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_centre_session_replayed_from_its_recording_ends_where_it_ended() {
    for seed in 1..=seeds() {
        replays(None, seed, 80);
    }
}

#[test]
fn a_lathe_session_replayed_from_its_recording_ends_where_it_ended() {
    for seed in 1..=seeds() {
        replays(Some(LatheDesc::citizen()), seed, 80);
    }
}

/// How many sessions of each machine (`NOVANC_REPLAYS`, 12 unless set).
fn seeds() -> u64 {
    std::env::var("NOVANC_REPLAYS")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(12)
}
