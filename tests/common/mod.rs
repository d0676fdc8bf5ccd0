//! Helpers shared by the integration tests that check recordings.

use std::path::Path;
use std::process::Command;

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
