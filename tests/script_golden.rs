//! Golden display frames: each `tests/golden/frames/NAME.script` runs through
//! `novanc script` on a fresh state directory; its output must equal `NAME.frames`.
//! Set `UPDATE_GOLDEN=1` to rewrite the golden files after a deliberate change.

mod common;

use std::path::Path;

/// Runs one script and compares (or updates) its frames.
fn check(name: &str) {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/golden/frames");
    let script = dir.join(format!("{name}.script"));
    let golden = dir.join(format!("{name}.frames"));
    let state = common::temp_dir(name);
    let out = common::novanc_command()
        .arg("script")
        .arg(&script)
        .arg("--state")
        .arg(&state)
        .output()
        .unwrap();
    let _ = std::fs::remove_dir_all(&state);
    let stdout = String::from_utf8_lossy(&out.stdout).into_owned();
    assert!(
        out.status.success(),
        "{name}: exit {:?}\nstderr: {}",
        out.status,
        String::from_utf8_lossy(&out.stderr)
    );
    if std::env::var_os("UPDATE_GOLDEN").is_some() {
        std::fs::write(&golden, &stdout).unwrap();
        return;
    }
    let want = std::fs::read_to_string(&golden)
        .unwrap_or_else(|e| panic!("{}: {e} (run with UPDATE_GOLDEN=1)", golden.display()));
    if stdout != want {
        panic!(
            "{name}: frames differ from {}\n--- got:\n{stdout}\n--- want:\n{want}",
            golden.display()
        );
    }
}

#[test]
fn single_block_tableb() {
    check("single_block_tableb");
}

#[test]
fn edit_error() {
    check("edit_error");
}

#[test]
fn tool_revision() {
    check("tool_revision");
}

#[test]
fn tcode_setting() {
    check("tcode_setting");
}

#[test]
fn tool_data_read() {
    check("tool_data_read");
}

#[test]
fn mdi() {
    check("mdi");
}

#[test]
fn search() {
    check("search");
}

#[test]
fn bad_keys() {
    check("bad_keys");
}

#[test]
fn program_read() {
    check("program_read");
}

#[test]
fn tape_read_image() {
    check("tape_read_image");
}

#[test]
fn tape_read_error() {
    check("tape_read_error");
}

#[test]
fn tape_read_stop() {
    check("tape_read_stop");
}

#[test]
fn gcode_single_block() {
    check("gcode_single_block");
}
