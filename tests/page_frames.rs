//! Golden frames of the whole terminal panel on each page (POS, PROG, OFS, MSG and the mode
//! page) at the smallest terminal the default display fits (79×24) and at a larger display
//! (`--rows 20 --cols 64`, 103×32), during a feed hold with an alarm in the history. The
//! frames are in `tests/golden/pages/`; `UPDATE_GOLDEN=1` rewrites them. Dates and clock times
//! (the PROG page's CHANGED column, the MSG page's times) are replaced by fixed letters, since
//! they come from the wall clock.

mod common;

use common::{keys, temp_dir, type_line};
use novanc::console::{Console, ConsoleConfig};
use novanc::panel_model::PanelEvent;
use novanc::pulse_core::ClockMode;
use novanc::settings::Dialect;
use novanc::terminal::layout::{draw_panel, panel_size};
use novanc_panel::Screen;
use std::path::Path;

/// A console on the defaults with a `rows`×`cols` display, in virtual time, reading `dialect`.
fn console(rows: usize, cols: usize, dialect: Dialect) -> Console {
    let mut cfg = ConsoleConfig::new(temp_dir(&format!("pages-{rows}x{cols}-{dialect:?}")));
    cfg.clock = ClockMode::Virtual;
    cfg.rows = rows;
    cfg.cols = cols;
    cfg.settings.dialect = dialect;
    Console::open(cfg).unwrap().0
}

/// The whole panel as the terminal draws it, in the smallest terminal it fits.
fn frame(c: &Console) -> String {
    let (w, h) = panel_size(c.config().rows, c.config().cols);
    let mut s = Screen::new(w, h);
    draw_panel(&mut s, &c.view());
    s.to_text()
}

/// Replaces every digit of a date or time of day (`2026-11-22`, `11-22`, `23:41`,
/// `23:41:07`) with a letter, so the frame does not depend on the wall clock.
fn normalize(text: &str) -> String {
    let b: Vec<char> = text.chars().collect();
    let mut out = b.clone();
    let digit = |i: usize| b.get(i).is_some_and(|c| c.is_ascii_digit());
    let mut i = 0;
    while i + 4 < b.len() {
        // dd-dd, dd:dd (with an optional leading dddd- or trailing :dd), not part of a number.
        let sep = b[i + 2];
        if (sep == '-' || sep == ':')
            && digit(i)
            && digit(i + 1)
            && digit(i + 3)
            && digit(i + 4)
            && !digit(i + 5)
            && (i == 0 || !digit(i - 1) || (i >= 5 && b[i - 1] == '-' && digit(i - 2)))
            && !(sep == '-' && i >= 1 && b[i - 1] == '.')
        {
            let letter = if sep == '-' { 'D' } else { 'h' };
            for k in [i, i + 1, i + 3, i + 4] {
                out[k] = letter;
            }
            if sep == '-' && i >= 5 && b[i - 1] == '-' && (1..=4).all(|k| digit(i - 1 - k)) {
                for k in 1..=4 {
                    out[i - 1 - k] = 'Y';
                }
            }
            if sep == ':' && b.get(i + 5) == Some(&':') && digit(i + 6) && digit(i + 7) {
                out[i + 6] = 'h';
                out[i + 7] = 'h';
            }
            i += 5;
            continue;
        }
        i += 1;
    }
    out.into_iter().collect()
}

/// The scene every page is shown in: an E-STOP and RESET in the history, a bad editor
/// command, Table B copied as PART2 on the PROG page (so it has a change time), PART2 started
/// in AUTO and held in the first feed of the first hole.
fn scene(c: &mut Console) {
    keys(c, &["F12", "F11"]);
    keys(c, &["Alt+4", "F3"]);
    type_line(c, "Q");
    keys(c, &["Ctrl+D"]);
    type_line(c, "C PART2");
    keys(c, &["Ctrl+D"]);
    keys(c, &["Alt+2", "F9"]);
    c.handle(PanelEvent::WaitBlock(5));
    c.handle(PanelEvent::WaitMs(400));
    keys(c, &["F10"]);
    assert!(c.wait_error().is_none(), "{:?}", c.wait_error());
}

/// Checks (or with `UPDATE_GOLDEN=1` rewrites) the golden frame `name`.
fn golden(name: &str, text: &str) {
    let p = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/golden/pages")
        .join(format!("{name}.frame"));
    if std::env::var_os("UPDATE_GOLDEN").is_some() {
        std::fs::create_dir_all(p.parent().unwrap()).unwrap();
        std::fs::write(&p, text).unwrap();
        return;
    }
    let want = std::fs::read_to_string(&p)
        .unwrap_or_else(|e| panic!("{}: {e} (UPDATE_GOLDEN=1 writes it)", p.display()));
    assert!(
        want == text,
        "{name} differs from {}:\n--- now\n{text}\n--- golden\n{want}",
        p.display()
    );
}

fn pages_at(rows: usize, cols: usize) {
    let mut c = console(rows, cols, Dialect::LinuxCnc);
    scene(&mut c);
    let (w, h) = panel_size(rows, cols);
    // Each page's frame: its size, its mark (the lit key, or the I/O page's title, whose key
    // has no button on the terminal panel), and the golden.
    let check = |c: &Console, page: &str, mark: &str| {
        let text = normalize(&frame(c));
        assert_eq!(text.lines().count(), h, "{page}: the frame is {h} lines");
        assert!(
            text.lines().all(|l| l.chars().count() <= w),
            "{page}: a line is wider than {w}:\n{text}"
        );
        assert!(text.contains(mark), "{page}: {mark} is not shown:\n{text}");
        golden(&format!("{page}_{w}x{h}"), &text);
    };
    for (key, page) in [
        ("Ctrl+P", "pos"),
        ("Ctrl+D", "prog"),
        ("Ctrl+O", "ofs"),
        ("Ctrl+G", "modal"),
        ("Ctrl+E", "msg"),
    ] {
        keys(&mut c, &[key]);
        check(&c, page, &format!("[{}]", page.to_uppercase()));
    }
    // The same page key again returns to the selectors' display program.
    keys(&mut c, &["Ctrl+E"]);
    golden(&format!("mode_{w}x{h}"), &normalize(&frame(&c)));
    // I/O, with two inputs set on it (after the others: POS shows the inputs too).
    keys(&mut c, &["Ctrl+T"]);
    type_line(&mut c, "P5 ON");
    type_line(&mut c, "E2 4.5");
    check(&c, "io", "IN E M66 E2=4.5");
}

/// The MACRO page (Fanuc dialect): values set by INPUT at the cursor and by `#n=`, a vacant
/// one blank; #500 kept across a restart; what it refuses, with the reason.
#[test]
fn the_macro_page_lists_and_sets_the_fanuc_variables() {
    let mut c = console(12, 40, Dialect::Fanuc);
    let dir = c.config().state_dir.clone();
    keys(&mut c, &["Ctrl+U"]);
    type_line(&mut c, "#500=12.5");
    type_line(&mut c, "#101=3");
    keys(&mut c, &["Down"]);
    type_line(&mut c, "-2.25");
    // +INPUT adds, as on OFS.
    type_line(&mut c, "#101");
    c.handle(PanelEvent::Press(novanc_panel::Key::Char('1')));
    c.handle(PanelEvent::Press(novanc_panel::Key::Tab));
    assert_eq!(c.interp_state().params[101], 4.0);
    assert_eq!(c.interp_state().params[102], -2.25);
    let (w, h) = panel_size(12, 40);
    let text = normalize(&frame(&c));
    assert_eq!(text.lines().count(), h);
    assert!(text.lines().all(|l| l.chars().count() <= w), "{text}");
    golden(&format!("macro_{w}x{h}"), &text);
    for (line, why) in [
        ("#50=1", "'#50' is not a variable of this page"),
        ("#500=x", "'x' is not a value"),
    ] {
        type_line(&mut c, line);
        assert!(common::shows(&c, why), "{line}:\n{}", c.frame_text());
    }
    // #500 is journaled: read back after a restart; #101 is not kept.
    drop(c);
    let c = common::reopen_in(&dir, Dialect::Fanuc);
    assert_eq!(c.interp_state().params[500], 12.5);
    assert!(c.interp_state().params[101].is_nan());
    // In LinuxCNC's dialect the page says whose variables they are and sets nothing.
    let mut c = console(12, 40, Dialect::LinuxCnc);
    keys(&mut c, &["Ctrl+U"]);
    type_line(&mut c, "#500=1");
    assert!(
        common::shows(&c, "the macro variables are the Fanuc dialect's"),
        "{}",
        c.frame_text()
    );
}

#[test]
fn every_page_at_79_by_24() {
    pages_at(12, 40);
}

#[test]
fn every_page_at_103_by_32() {
    pages_at(20, 64);
}

#[test]
fn dates_and_times_are_normalized_and_nothing_else() {
    assert_eq!(
        normalize("TABLEB  2026-11-22 23:41  X-12.500 N10 11-22 07:05:09 3-4"),
        "TABLEB  YYYY-DD-DD hh:hh  X-12.500 N10 DD-DD hh:hh:hh 3-4"
    );
    assert_eq!(normalize("Z-265.000 F60 10-20"), "Z-265.000 F60 DD-DD");
}
