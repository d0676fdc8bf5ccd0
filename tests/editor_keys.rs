//! The editor's cursor keys in DATA INPUT (docs/editor.md, "Cursor keys"): arrows, PgUp/PgDn,
//! Home/End and Delete move the pointer of the buffer being revised (or delete after it) as
//! the letter commands would, beside them; a key that cannot act says why; the line being
//! typed stays on the entry line.

mod common;

use common::{keys, open, shows, type_line};
use novanc::panel_model::PanelEvent;

fn revise(c: &mut novanc::console::Console) {
    keys(c, &["Alt+4", "F3"]); // DATA INPUT, PROGRAM REVISION
}

#[test]
fn cursor_keys_move_the_pointer_as_the_letter_commands_do() {
    let mut c = open("editor-keys");
    revise(&mut c);
    // Three lines before Table B; the pointer ends at the start of Table B's first line.
    type_line(&mut c, "IAB*CDEF*GH*");
    keys(&mut c, &["Up", "End", "Up"]); // end of GH, then line CDEF at column 2
    type_line(&mut c, "IX");
    keys(&mut c, &["Home"]);
    type_line(&mut c, "IY");
    keys(&mut c, &["Up"]); // column 1 of AB
    type_line(&mut c, "IZ");
    keys(&mut c, &["Delete"]); // the B
    assert!(
        c.program_text().starts_with("AZ\nYCDXEF\nGH\n"),
        "{:?}",
        &c.program_text()[..20]
    );
    // At the first line, PgUp and Up say so; at the start, Left says so; nothing changes.
    let before = c.program_text();
    keys(&mut c, &["PgUp"]);
    assert!(
        shows(&c, "the pointer is on the first line"),
        "{}",
        c.frame_text()
    );
    keys(&mut c, &["Left", "Left", "Left"]);
    assert!(
        shows(&c, "at the start of the buffer"),
        "{}",
        c.frame_text()
    );
    assert_eq!(c.program_text(), before);
    // PgDn goes a screenful of lines on; Down keeps the column where the line is long enough.
    keys(&mut c, &["PgDn"]);
    type_line(&mut c, "I#");
    let text = c.program_text();
    let rows = text
        .lines()
        .position(|l| l.starts_with('#'))
        .expect("# inserted");
    assert!(rows > 3, "PgDn moved {rows} lines");
}

#[test]
fn a_cursor_key_keeps_the_line_being_typed() {
    let mut c = open("editor-keys-entry");
    revise(&mut c);
    type_line(&mut c, "IAB*CD*");
    keys(&mut c, &["Up", "Up", "I", "Q"]); // typing, not yet entered
    keys(&mut c, &["Right"]); // the pointer moves; the entry line keeps "IQ"
    c.handle(PanelEvent::Eob);
    assert!(
        c.program_text().starts_with("AQB\nCD\n"),
        "{:?}",
        &c.program_text()[..10]
    );
}

#[test]
fn cursor_keys_outside_data_input_still_jog() {
    let mut c = open("editor-keys-jog");
    keys(&mut c, &["Alt+6", "Right"]); // STEP: Right is +X
    c.handle(PanelEvent::Wait);
    assert!(c.status().pos[0] > 0, "STEP Right moved X");
}
