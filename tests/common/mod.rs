//! Helpers shared by the integration tests: a console on a fresh state directory in virtual
//! time, keys by name, the block-end audit, and the Python check of a recording.

#![allow(dead_code)]

use novanc::console::{keys::parse_key, Console, ConsoleConfig};
use novanc::panel_model::PanelEvent;
use novanc::pulse_core::{BlockEnd, ClockMode};
use std::path::{Path, PathBuf};
use std::process::Command;

/// A fresh state directory.
pub fn temp_dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!(
        "novanc-{name}-{}-{}",
        std::process::id(),
        std::time::SystemTime::now()
            .duration_since(std::time::UNIX_EPOCH)
            .map(|d| d.as_nanos())
            .unwrap_or(0)
    ));
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// A console on a fresh state directory (the embedded defaults), virtual time, 12×40, with the
/// pulse core's audit of block ends on.
pub fn open(name: &str) -> Console {
    let mut cfg = ConsoleConfig::new(temp_dir(name));
    cfg.clock = ClockMode::Virtual;
    let c = Console::open(cfg).unwrap().0;
    c.core().set_audit(true);
    c
}

/// The console on an existing state directory (a restart), virtual time.
pub fn reopen(dir: &Path) -> Console {
    let mut cfg = ConsoleConfig::new(dir.to_path_buf());
    cfg.clock = ClockMode::Virtual;
    Console::open(cfg).unwrap().0
}

/// One MDI line: typed in MDI, START, and waited for.
pub fn mdi(c: &mut Console, line: &str) {
    c.handle(PanelEvent::Op(novanc::panel_model::OpMode::Mdi));
    type_line(c, line);
    c.handle(PanelEvent::Start);
    c.handle(PanelEvent::Wait);
}

/// Presses keys by their script names (`F9`, `Alt+2`, `Right`, `x`, ...).
pub fn keys(c: &mut Console, names: &[&str]) {
    for n in names {
        let k = parse_key(n).unwrap_or_else(|e| panic!("{e}"));
        c.handle(PanelEvent::Press(k));
    }
}

/// Types a line on the data keys and ends it with EOB.
pub fn type_line(c: &mut Console, line: &str) {
    c.handle(PanelEvent::Type(line.to_string()));
}

/// Every block end since the last call; each must have ended on its programmed point.
pub fn audit(c: &Console) -> Vec<BlockEnd> {
    let a = c.core().take_audit();
    for e in &a {
        assert_eq!(
            e.pos, e.end,
            "run {} N{} (line {}) ended off its programmed point",
            e.run, e.seq, e.stmt
        );
    }
    a
}

/// Millimetres to pulses at the default 0.001 mm.
pub fn p(mm: f64) -> i64 {
    (mm * 1000.0).round() as i64
}

/// Whether the display shows `text` somewhere (lines joined with spaces, so a wrapped
/// message is found too).
pub fn shows(c: &Console, text: &str) -> bool {
    let joined = c
        .frame_text()
        .lines()
        .map(|l| l.trim())
        .collect::<Vec<_>>()
        .join(" ");
    joined.contains(text)
}

/// Runs `tests/mcap_check.py` on a recording; `None` if python3 or its `mcap` module is
/// missing and `CI` is unset (a skip, said loudly). With `CI` set the module is required.
pub fn python_check(path: &Path, extra: &[&str]) -> Option<(bool, String)> {
    let has_mcap = Command::new("python3")
        .args(["-c", "import mcap"])
        .output()
        .map(|o| o.status.success())
        .unwrap_or(false);
    if !has_mcap {
        if std::env::var_os("CI").is_some() {
            panic!("python3 with the `mcap` module is required in CI (pip install mcap)");
        }
        eprintln!(
            "\n!!!!! SKIPPED: python3 or its `mcap` module is missing; \
             `python3 -m pip install mcap` to run the Python reader check !!!!!\n"
        );
        return None;
    }
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/mcap_check.py");
    let out = Command::new("python3")
        .arg(script)
        .arg(path)
        .args(extra)
        .output()
        .expect("run mcap_check.py");
    let text = format!(
        "{}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    Some((out.status.success(), text))
}
