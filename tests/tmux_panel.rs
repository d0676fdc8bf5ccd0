//! The terminal panel in a real terminal: tmux runs `novanc`; `send-keys` switches modes, edits
//! Table B, runs it in single block, revises a tool, presses bad keys and resizes to 20×5;
//! `capture-pane` checks the screen. Afterwards `stty -a` is what it was before.
//! Without tmux the test fails when CI=true and is skipped (loudly) otherwise.

mod common;
#[path = "common/tmux.rs"]
mod tmux;

use common::temp_dir;
use std::process::Command;
use tmux::{assert_stty_unchanged, session, shell, tmux_or_skip, wait_file, with_pid};

#[test]
fn the_panel_works_in_tmux_and_hands_the_terminal_back() {
    if !tmux_or_skip("terminal panel") {
        return;
    }
    let d = temp_dir("tmux");
    let exe = env!("CARGO_BIN_EXE_novanc");
    let t = session(
        "test",
        &d,
        &format!("'{exe}' --state '{}/state'", d.display()),
    );
    t.wait_for(
        &["PLASMA DISPLAY 14", "◉━4 DATA INPUT", "◉━3 PROG REVISE"],
        20,
    );

    // Edit Table B in PROGRAM REVISION.
    t.type_line("2L");
    t.type_line("SPAT1$CNH6$NH5");
    t.wait_for(&["PAT1 = DA1, NH5▌, P1", "cmd: SPAT1$CNH6$NH5", "│ok"], 10);
    // A failing command line changes nothing and says why.
    t.type_line("0LSxyz$");
    t.wait_for(&["'xyz' not found", "PAT1 = DA1, NH5▌, P1"], 10);

    // A bad key: data keys in CONTINUOUS are refused.
    t.keys(&["M-1"]);
    t.wait_for(&["◉━1 CONTINUOUS"], 10);
    t.keys(&["x"]);
    t.wait_for(&["refused: data keys work in DATA"], 10);

    // SINGLE BLOCK: one block per START (F9).
    t.keys(&["M-7"]);
    t.wait_for(&["◉━7 SINGLE BLK", "TABLEB: press START"], 10);
    t.keys(&["F9"]);
    t.wait_for(&[">N1 T01 M06", "RUN 0 SINGLE", "RUN 0  T01"], 20);
    t.keys(&["F9"]);
    t.wait_for(
        &[">N2 G00 X350.000 Y130.000", "X    350.000", "RUN 0 SINGLE"],
        20,
    );

    // Revise a tool: DATA INPUT clears RUN, TOOL DATA REVISION (F5).
    t.keys(&["M-4"]);
    t.wait_for(&["◉━4 DATA INPUT"], 10);
    t.keys(&["F5"]);
    t.wait_for(&["TOOL DATA REVISION", "◉━5 TOOL REVISE"], 10);
    t.type_line("1LS6.2$C150$155");
    t.wait_for(&["T02 00106  DR      6.2    155▌", "│ok"], 10);

    // Too small, then big again: the panel comes back whole.
    t.run(&["resize-window", "-t", "0", "-x", "20", "-y", "5"]);
    t.wait_for(&["enlarge to 79x24", "(now 20x5)"], 10);
    t.run(&["resize-window", "-t", "0", "-x", "80", "-y", "24"]);
    t.wait_for(&["PLASMA DISPLAY 14", "T02 00106  DR      6.2    155▌"], 10);

    // STEP: one press, one 0.1 mm increment (the default x100); HANDLE x100: one detent,
    // 0.1 mm; Alt+w to x1000: 1 mm.
    t.keys(&["M-6"]);
    t.wait_for(&["◉━6 STEP", "0.100 mm (x100) per jog key"], 10);
    t.keys(&["Right"]);
    t.wait_for(&["X    350.100"], 10);
    t.keys(&["M-5"]);
    t.wait_for(&["◉━5 HANDLE", "HANDWHEEL X x100"], 10);
    t.keys(&["Up"]);
    t.wait_for(&["Y    130.100"], 10);
    t.keys(&["M-w"]);
    t.wait_for(&["HANDWHEEL Y x1000"], 10);
    t.keys(&["Up"]);
    t.wait_for(&["Y    131.100"], 10);

    // Help and back.
    t.keys(&["F8"]);
    t.wait_for(&["novanc terminal panel: keys"], 10);
    t.keys(&["Space"]);
    t.wait_for(&["PLASMA DISPLAY 14"], 10);

    // Every page of the row of page keys, and back to the mode's display.
    t.keys(&["C-p"]);
    t.wait_for(&["WORK G54      REL     MACH    TO GO", "JOG "], 10);
    t.keys(&["C-d"]);
    t.wait_for(&["NAME", "LNG", "CHANGED", "*TABLEB"], 10);
    t.keys(&["C-o"]);
    t.wait_for(&["OFS", "Enter INPUT", "T02 00106"], 10);
    t.keys(&["C-e"]);
    t.wait_for(&["MSG", "entries"], 10);
    t.keys(&["C-e"]);
    t.wait_for(&["HANDLE", "wheel Y"], 10);

    // Quit; the terminal is handed back as it was.
    t.keys(&["C-c"]);
    let exit = wait_file(&d.join("exit"), 20);
    assert_eq!(exit.trim(), "exit=0");
    assert_stty_unchanged(&d);
    let s = t.screen();
    assert!(!s.contains("PLASMA DISPLAY"), "alternate screen left:\n{s}");
    let _ = std::fs::remove_dir_all(&d);
}

/// The Citizen's console runs in the same terminal loop as the centre's: while the terminal
/// is too small only the relay panel acts (E-STOP stops every channel), and another key is
/// refused by name on the notice, as the centre's are (it was dropped in silence).
#[test]
fn the_lathe_console_in_a_terminal_too_small_takes_only_the_relay_panel() {
    if !tmux_or_skip("lathe terminal panel") {
        return;
    }
    let d = temp_dir("tmux-lathe");
    let exe = env!("CARGO_BIN_EXE_novanc");
    let t = session(
        "lathe",
        &d,
        &format!("'{exe}' --machine citizen --state '{}/state'", d.display()),
    );
    t.wait_for(
        &["CITIZEN 3 CHANNELS", "PLASMA DISPLAY 14", ">CH1 IDLE"],
        20,
    );
    t.keys(&["F9"]);
    t.wait_for(&["CH1 RUN"], 20);
    t.run(&["resize-window", "-t", "0", "-x", "30", "-y", "8"]);
    t.wait_for(&["enlarge to 68x18", "(now 30x8)"], 10);
    // Tab (the channel selector) is refused and says so; E-STOP (F12) acts.
    t.keys(&["Tab"]);
    t.wait_for(&["key Tab ignored: the terminal", "is too small"], 10);
    t.keys(&["F12"]);
    t.run(&["resize-window", "-t", "0", "-x", "80", "-y", "24"]);
    t.wait_for(&[">CH1 ESTOP", " CH2 ESTOP", " CH3 ESTOP"], 10);
    t.keys(&["C-c"]);
    let exit = wait_file(&d.join("exit"), 20);
    assert_eq!(exit.trim(), "exit=0");
    assert_stty_unchanged(&d);
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn sigterm_hands_the_terminal_back() {
    if !tmux_or_skip("SIGTERM") {
        return;
    }
    let d = temp_dir("tmux");
    let exe = env!("CARGO_BIN_EXE_novanc");
    let t = session(
        "term",
        &d,
        &format!(
            "sh -c 'echo $$ > {d}/pid; exec {exe} --state {d}/state'",
            d = d.display()
        ),
    );
    t.wait_for(&["PLASMA DISPLAY 14"], 20);
    let pid = wait_file(&d.join("pid"), 10);
    let ok = Command::new("kill")
        .args(["-TERM", pid.trim()])
        .status()
        .unwrap();
    assert!(ok.success());
    let exit = wait_file(&d.join("exit"), 20);
    assert_eq!(exit.trim(), "exit=143");
    assert_stty_unchanged(&d);
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn a_panic_hands_the_terminal_back() {
    if !tmux_or_skip("panic") {
        return;
    }
    let d = temp_dir("tmux");
    let exe = env!("CARGO_BIN_EXE_novanc");
    let t = session(
        "panic",
        &d,
        &format!(
            "NOVANC_TEST_PANIC=1 '{exe}' --state '{d}/state' 2> '{d}/stderr'",
            d = d.display()
        ),
    );
    let exit = wait_file(&d.join("exit"), 20);
    assert_eq!(exit.trim(), "exit=101");
    let stderr = std::fs::read_to_string(d.join("stderr")).unwrap();
    assert!(stderr.contains("NOVANC_TEST_PANIC"), "{stderr}");
    assert_stty_unchanged(&d);
    let s = t.screen();
    assert!(!s.contains("PLASMA DISPLAY"), "alternate screen left:\n{s}");
    let _ = std::fs::remove_dir_all(&d);
}

/// `stty -a` typed in the shell of the pane shows a cooked terminal (canonical input, echo).
fn assert_cooked(t: &tmux::Tmux, when: &str) {
    t.type_line("clear; stty -a");
    let s = t.wait_for(&["icanon"], 10);
    assert!(
        s.contains(" icanon")
            && !s.contains("-icanon")
            && s.contains(" echo ")
            && !s.contains("-echo "),
        "{when}: the terminal is not cooked:\n{s}"
    );
    t.type_line("clear");
}

fn kill(pid: &str, sig: &str) {
    let ok = Command::new("kill")
        .args([&format!("-{sig}"), pid.trim()])
        .status()
        .unwrap();
    assert!(ok.success());
}

#[test]
fn sigtstp_hands_the_terminal_back_fg_redraws_and_sigquit_restores() {
    // Issue 20, item 13: after SIGTSTP and `fg` the panel stayed in cooked mode, undrawn;
    // SIGQUIT left the terminal raw on the alternate screen. An interactive shell with job
    // control runs novanc, as an operator's terminal does.
    if !tmux_or_skip("SIGTSTP") {
        return;
    }
    let d = temp_dir("tmux-tstp");
    let exe = env!("CARGO_BIN_EXE_novanc");
    let t = shell("tstp");
    t.type_line(&with_pid(
        &d,
        &format!("{exe} --state {}/state", d.display()),
    ));
    t.wait_for(&["PLASMA DISPLAY 14", "◉━3 PROG REVISE"], 20);
    let pid = wait_file(&d.join("pid"), 10);

    // SIGTSTP: the shell's prompt on the main screen, the terminal cooked.
    kill(&pid, "TSTP");
    let s = t.wait_for(&["Stopped"], 10);
    assert!(!s.contains("PLASMA DISPLAY"), "alternate screen left:\n{s}");
    assert_cooked(&t, "after SIGTSTP");

    // fg: the whole panel drawn again, in raw mode (Alt+1 acts at once).
    t.type_line("fg");
    t.wait_for(
        &["PLASMA DISPLAY 14", "◉━3 PROG REVISE", "RELAY PANEL 12"],
        10,
    );
    t.keys(&["M-1"]);
    t.wait_for(&["◉━1 CONTINUOUS"], 10);

    // SIGQUIT: the process ends at once, the terminal handed back first.
    kill(&pid, "QUIT");
    t.type_line("echo status=$?");
    let s = t.wait_for(&["status=131"], 10);
    assert!(!s.contains("PLASMA DISPLAY"), "alternate screen left:\n{s}");
    assert_cooked(&t, "after SIGQUIT");
    let _ = std::fs::remove_dir_all(&d);
}

/// Issue 23, position memory: a console killed (SIGKILL) while an axis moves leaves the
/// position marked as moving; the next one says the position is not known, refuses AUTO and
/// MDI, and HOME (Alt+0) makes the reference return, after which START runs again. A clean
/// end keeps the position and the tool at rest.
#[test]
fn a_console_killed_while_moving_asks_for_the_reference_return() {
    if !tmux_or_skip("position memory") {
        return;
    }
    let d = temp_dir("tmux-posmem");
    let exe = env!("CARGO_BIN_EXE_novanc");
    let state = d.join("state");
    let t = session(
        "posmem",
        &d,
        &with_pid(&d, &format!("{exe} --state {}", state.display())),
    );
    t.wait_for(&["PLASMA DISPLAY 14"], 20);
    // MDI: a long rapid (600 mm, about 3 s), killed half a second in.
    t.keys(&["M-3"]);
    t.type_line("G0 X600");
    t.keys(&["F9"]);
    t.wait_for(&["RUN 2"], 10);
    std::thread::sleep(std::time::Duration::from_millis(500));
    let pid = wait_file(&d.join("pid"), 10);
    kill(&pid, "KILL");
    wait_file(&d.join("exit"), 20);
    let kept = std::fs::read_to_string(state.join("position")).unwrap();
    assert!(kept.contains("moving"), "{kept}");

    let d2 = temp_dir("tmux-posmem2");
    let t2 = session(
        "posmem2",
        &d2,
        &format!("'{exe}' --state '{}'", state.display()),
    );
    t2.wait_for(&["the console stopped while the axes"], 20);
    t2.keys(&["M-2", "F9"]);
    t2.wait_for(&["START refused: the position is"], 10);
    t2.keys(&["M-0"]);
    t2.wait_for(&["reference return is made"], 30);
    t2.keys(&["M-2", "F9"]);
    t2.wait_for(&["RUN 1"], 10);
    t2.keys(&["F11", "C-c"]);
    wait_file(&d2.join("exit"), 20);
    let kept = std::fs::read_to_string(state.join("position")).unwrap();
    assert!(kept.contains("at rest"), "{kept}");
    let _ = std::fs::remove_dir_all(&d);
    let _ = std::fs::remove_dir_all(&d2);
}
