//! `novanc script` (docs/cli.md): a headless panel session driven by a script of panel events,
//! on the same `Console` as the terminal, in virtual time (deterministic frames).

use super::console_opts::config_from_args;
use crate::console::{virtual_clock, Panel};
use crate::panel_model::PanelEvent;
use std::io::Write;
use std::path::{Path, PathBuf};

const HELP: &str = "\
usage: novanc script FILE [--machine citizen|FILE] [--state DIR] [--record OUT.mcap] [--pulses on|off]
                          [--rows N] [--cols N] [--mtconnect ADDR:PORT|PORT] [--mtconnect-wait SECONDS]

Runs a panel event script (one event per line, # comments):
  op CONTINUOUS|AUTO|MDI|DATA|HANDLE|STEP|SINGLE
  data SEARCH|READ|REVISE|TOOLREAD|TOOLREVISE|TCODE|MDI
  type TEXT      data keys, then EOB
  tape PATH      put a file in the tape reader (relative to the current directory,
                 else to the script's directory)
  start | stop | reset | estop | override PCT | wheel AXIS N | show
  rapidoverride 0|25|50|100   the rapid override (0 is F0)
  spindleoverride PCT         the spindle override, 50-120 in 10 % steps
  dryrun on|off | machinelock on|off | zneglect on|off
  key NAME       press a key of the terminal's key map by name: F1-F12, Alt+1-Alt+7 (and
                 the other Alt keys of the panel), Up, Down, Left, Right, PgUp, PgDn, Enter,
                 Backspace, or one character; recorded on /panel/event as `key NAME`
  wait           until the machine is idle (RUN = 0 and nothing moving, or a feed hold at
                 rest, or an e-stop)
  wait block N   until block N (its N number) of the current run starts executing, or the
                 run ends
  wait ms T      let T milliseconds of machine time pass

On a lathe (--machine citizen or a lathe description; docs/lathe.md, Panel script) the same
grammar, with the lathe's words and without the centre's own (HOME, the handwheel, the data
selector, tape, DRY RUN ... are refused with the line):
  op AUTO|MDI|DATA|OFS|STEP   channel N   type TEXT   start | stop | reset | estop   key NAME
  fault N REASON     target N    override PCT   optionalstop on|off   blockdelete on|off
  wheelscale 1|10|100|1000       the STEP increment (key Up/Down: X+/X-, Left/Right: Z-/Z+)
  wait               until every channel is at rest (finished, stopped, waiting on a stopped
                     channel, faulted, or in E-STOP)
  wait block N       until block N (counted from 1 in the program as read) of the selected
                     channel's program starts, or every channel is at rest
  show               the title, the summary lines and the selected channel's plasma

--mtconnect streams the machine's state to MTConnect agents (SHDR over TCP, docs/mtconnect.md;
port 7878 and loopback unless given); the state is sent after every event. --mtconnect-wait S
waits up to S seconds for an agent before the first event (exit 1 if none came).

The session runs in virtual time: machine time passes only inside the waits, as fast as the
machine can compute, so every run of a script gives the same frames. A wait that cannot end
(feed override 0 with a block in progress) or that is not done within 1000 hours of machine
time stops the script with an error (exit 1). `show` prints the display between `--- display`
and `---`. A bad line stops the script before anything runs (exit 1). Without --state, the session runs on a fresh temporary state directory
(the embedded defaults) that is removed afterwards; with --state DIR it uses and keeps DIR.
";

/// Runs `novanc script` on either machine (one command, one grammar, one runner: [`play`]);
/// returns the exit code.
pub fn main(argv: &[String]) -> i32 {
    let (machine, argv) = match super::args::take_machine(argv) {
        Err(e) => return super::usage_error(&format!("script: {e}")),
        Ok(x) => x,
    };
    if argv.iter().any(|a| a == "-h" || a == "--help") {
        print!("{HELP}");
        return 0;
    }
    let (mtc, argv) = match super::mtconnect::take(&argv) {
        Ok(x) => x,
        Err(e) => return super::usage_error(&format!("script: {e}")),
    };
    let argv = argv.as_slice();
    let has_state = argv
        .iter()
        .any(|a| a == "--state" || a.starts_with("--state="));
    let (mut cfg, rest) = match config_from_args(argv) {
        Ok(x) => x,
        Err(e) => return super::usage_error(&format!("script: {e}")),
    };
    let lathe = match machine {
        super::args::Machine::Lathe(d) => {
            if let Err(e) = cfg.check() {
                return super::usage_error(&format!("script: {e}"));
            }
            Some(d)
        }
        m => {
            m.apply(&mut cfg.settings);
            None
        }
    };
    let file = match rest.as_slice() {
        [f] if !f.starts_with('-') => PathBuf::from(f),
        [] => return super::usage_error("script: which script? (novanc script FILE)"),
        _ => {
            return super::usage_error(&format!(
                "script: unexpected arguments {rest:?} (see --help)"
            ))
        }
    };
    let text = match std::fs::read_to_string(&file) {
        Ok(t) => t,
        Err(e) => {
            eprintln!("novanc script: {}: {e}", file.display());
            return 1;
        }
    };
    // The one grammar, checked whole before anything opens; a lathe refuses the centre's own
    // words (and the centre a lathe's) with the line.
    let events = match crate::console::Panel::read_script(lathe.as_ref(), &text) {
        Ok(ev) => ev,
        Err((line, e)) => {
            eprintln!("novanc script: {}:{line}: {e}", file.display());
            return 1;
        }
    };
    let temp = if has_state {
        None
    } else {
        let d = fresh_temp_dir();
        cfg.state_dir = d.clone();
        Some(d)
    };
    cfg.interrupt = Some(super::signals::pending);
    super::signals::install();
    let code = run(lathe, virtual_clock(cfg), &file, events, &mtc);
    if let Some(d) = temp {
        let _ = std::fs::remove_dir_all(d);
    }
    super::signals::exit_code(code)
}

/// A new, empty temporary directory for one script's state.
fn fresh_temp_dir() -> PathBuf {
    let nanos = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map(|d| d.as_nanos())
        .unwrap_or(0);
    std::env::temp_dir().join(format!("novanc-script-{}-{nanos}", std::process::id()))
}

/// A tape path: as given if it exists, else relative to the script's directory.
fn resolve_tape(p: PathBuf, script: &Path) -> PathBuf {
    if p.is_absolute() || p.exists() {
        return p;
    }
    match script.parent() {
        Some(dir) if dir.join(&p).exists() => dir.join(p),
        _ => p,
    }
}

/// Opens the console of the machine (`lathe`: a lathe's description; None: the centre of
/// `cfg`) on `cfg` (its state directory, display size, recording, virtual clock), starts the
/// MTConnect adapter, and plays the events with the one runner; returns the exit code.
fn run(
    lathe: Option<crate::lathe::desc::LatheDesc>,
    cfg: crate::console::ConsoleConfig,
    file: &Path,
    events: Vec<PanelEvent>,
    mtc: &super::mtconnect::MtcOpts,
) -> i32 {
    let (mut console, warnings) = match Panel::open(lathe, cfg) {
        Ok(x) => x,
        Err(e) => return super::fail(&format!("novanc script: {e}")),
    };
    for w in warnings {
        eprintln!("novanc script: warning: {w}");
    }
    // A stop signal ends the script before its next line, and a wait between two steps of
    // 10 ms of machine time (`cfg.interrupt`).
    let feed = match console.start_feed(mtc, "novanc script", true) {
        Ok(f) => f,
        Err(e) => {
            let _ = console.close(None);
            return super::fail(&format!("novanc script: {e}"));
        }
    };
    let events = events
        .into_iter()
        .map(|ev| match ev {
            PanelEvent::Tape(p) => PanelEvent::Tape(resolve_tape(p, file)),
            ev => ev,
        })
        .collect();
    play(console, events, feed)
}

/// The one script runner: plays `events` on the console, one after another, publishing
/// after each; a wait that cannot end stops the script (exit 1), a stop signal ends it before
/// its next event. Returns the exit code.
fn play(
    mut console: Panel,
    events: Vec<PanelEvent>,
    mut feed: Option<super::mtconnect::Feed>,
) -> i32 {
    let stdout = std::io::stdout();
    let mut out = stdout.lock();
    for (i, ev) in events.into_iter().enumerate() {
        if super::signals::caught().is_some() {
            break;
        }
        let waits = matches!(
            ev,
            PanelEvent::Wait | PanelEvent::WaitBlock(_) | PanelEvent::WaitMs(_)
        );
        match ev {
            PanelEvent::Show => {
                let _ = writeln!(out, "--- display\n{}\n---", console.frame_text());
            }
            ev => console.handle(ev),
        }
        if let Some(f) = feed.as_mut() {
            console.publish(f);
        }
        if super::signals::caught().is_some() {
            break;
        }
        if let Some(e) = console.front().wait_error.as_deref().filter(|_| waits) {
            let _ = out.flush();
            eprintln!("novanc script: event {}: {e}", i + 1);
            let _ = console.close(None);
            return 1;
        }
    }
    let _ = out.flush();
    let interrupted = super::signals::caught_reason();
    match console.close(interrupted.as_deref()) {
        Ok(Some(summary)) => {
            eprintln!("novanc script: {summary}");
            0
        }
        Ok(None) => 0,
        Err(e) => {
            eprintln!("novanc script: {e}");
            1
        }
    }
}
