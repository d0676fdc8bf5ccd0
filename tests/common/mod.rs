//! Helpers shared by the integration tests: a console on a fresh state directory in virtual
//! time, keys by name, the block-end audit, and the Python check of a recording.

#![allow(dead_code)]

use novanc::console::{keys::parse_key, Console, ConsoleConfig};
use novanc::panel_model::PanelEvent;
use novanc::pulse_core::{BlockEnd, ClockMode};
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// The G-code program `src` as `novanc translate` reads it without `--state`: from machine
/// zero, the sample magazine, the default settings, no work offsets, both switches off.
pub fn gcode_source(src: &str) -> novanc::gcode::GcodeSource {
    gcode_source_in(src, novanc::settings::Dialect::LinuxCnc)
}

/// [`gcode_source`] in a dialect (docs/gcode.md "Fanuc dialect").
pub fn gcode_source_in(
    src: &str,
    dialect: novanc::settings::Dialect,
) -> novanc::gcode::GcodeSource {
    gcode_source_with(
        src,
        novanc::settings::MachineSettings {
            dialect,
            ..Default::default()
        },
    )
}

/// [`gcode_source`] on a machine of `settings` (a dialect and its settings).
pub fn gcode_source_with(
    src: &str,
    settings: novanc::settings::MachineSettings,
) -> novanc::gcode::GcodeSource {
    novanc::gcode::GcodeSource::new(
        src.into(),
        novanc::tooldata::sample_magazine(),
        settings,
        novanc::block::MachineState::at([0, 0, 0]),
        novanc::gcode::WorkOffsets::default(),
        novanc::gcode::Switches::default(),
    )
}

/// A fresh directory (a state directory, a test's files), removed when the test process
/// exits.
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
    remove_at_exit(&d);
    d
}

/// A path for a file `name` in a fresh temporary directory (removed at exit, as `temp_dir`'s).
pub fn temp_path(name: &str) -> PathBuf {
    temp_dir("file").join(name)
}

/// `text` written to a file `name` in a fresh temporary directory ([`temp_path`]).
pub fn temp_file(name: &str, text: &str) -> PathBuf {
    let p = temp_path(name);
    std::fs::write(&p, text).expect("temp file");
    p
}

/// The novanc binary this test build made, to run in the project's folder (where the tests
/// name its programs and machines from): the one way every test starts the process.
pub fn novanc_command() -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_novanc"));
    c.current_dir(env!("CARGO_MANIFEST_DIR"));
    c
}

/// `novanc ARGS` run to its end: its exit status and output.
pub fn novanc(args: &[&str]) -> Output {
    novanc_command().args(args).output().expect("run novanc")
}

/// Translates the source-language program `src` with `magazine`, statement by statement: its
/// error, after checking that the statement in error yielded no blocks and that the
/// translator hands out nothing after it (docs/language.md "Errors").
pub fn translate_error(
    src: &str,
    magazine: novanc::tooldata::Magazine,
) -> novanc::translator::TranslateError {
    let settings = novanc::settings::MachineSettings::default();
    let mut t = novanc::translator::Translator::new(src, magazine, settings, [0, 0, 0]);
    let mut seen = Vec::new();
    loop {
        match t.next() {
            Some(Ok(s)) => seen.push(s.line),
            Some(Err(e)) => {
                assert!(!seen.contains(&e.line), "line {} yielded blocks", e.line);
                assert!(t.next().is_none(), "the translator went on after {e}");
                assert!(t.next().is_none());
                return e;
            }
            None => panic!("no error in:\n{}", &src[..src.len().min(500)]),
        }
    }
}

/// A statement's blocks as ISO lines without their N words, on the default settings.
pub fn iso_words(s: &novanc::translator::Statement) -> Vec<String> {
    let st = novanc::settings::MachineSettings::default();
    s.blocks
        .iter()
        .map(|b| {
            let l = novanc::translator::iso_line(b, &st);
            l.split_once(' ')
                .map(|x| x.1.to_string())
                .unwrap_or_default()
        })
        .collect()
}

/// Every message of `topic` in the recording `rec`: its log time and its text (JSON).
pub fn recorded(rec: &Path, topic: &str) -> Vec<(u64, String)> {
    let bytes = std::fs::read(rec).unwrap_or_else(|e| panic!("{e}"));
    mcap::MessageStream::new(&bytes)
        .unwrap_or_else(|e| panic!("{e}"))
        .map(|m| m.unwrap_or_else(|e| panic!("{e}")))
        .filter(|m| m.channel.topic == topic)
        .map(|m| (m.log_time, String::from_utf8_lossy(&m.data).into_owned()))
        .collect()
}

/// The temporary directories this test process made, removed when it exits.
static MADE: std::sync::Mutex<Vec<PathBuf>> = std::sync::Mutex::new(Vec::new());

/// Removes `dir` when the test process exits (pass or fail): the suite made 35,000 of them,
/// 16 GB, on one machine in a day before this. `NOVANC_KEEP_TEMP=1` keeps them for a look.
fn remove_at_exit(dir: &Path) {
    static HOOK: std::sync::Once = std::sync::Once::new();
    extern "C" fn remove_all() {
        if std::env::var_os("NOVANC_KEEP_TEMP").is_some() {
            return;
        }
        if let Ok(made) = MADE.lock() {
            for d in made.iter() {
                let _ = std::fs::remove_dir_all(d);
            }
        }
    }
    HOOK.call_once(|| {
        // SAFETY: `remove_all` is a plain function that lives as long as the process.
        unsafe {
            libc::atexit(remove_all);
        }
    });
    if let Ok(mut made) = MADE.lock() {
        made.push(dir.to_path_buf());
    }
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

/// The Citizen lathe's console on `state` (created or reopened), virtual time, 20×60, no
/// recording: the lathe tests' machine.
pub fn open_citizen(state: &Path) -> novanc::lathe::console::LatheConsole {
    let desc = novanc::lathe::desc::LatheDesc::citizen();
    novanc::lathe::console::LatheConsole::open(desc, state, 20, 60, None)
        .unwrap_or_else(|e| panic!("{e}"))
        .0
}

/// Both machines on fresh state directories, for a rule that is one on every machine: the
/// Citizen's console on `lathe-NAME` (its directory, to remove) and the centre's on
/// `centre-NAME`.
pub fn both_machines(name: &str) -> (PathBuf, novanc::lathe::console::LatheConsole, Console) {
    let dir = temp_dir(&format!("lathe-{name}"));
    let c = open_citizen(&dir);
    (dir, c, open(&format!("centre-{name}")))
}

/// The console on an existing state directory (a restart), virtual time.
pub fn reopen(dir: &Path) -> Console {
    reopen_in(dir, novanc::settings::Dialect::LinuxCnc)
}

/// [`reopen`] with programs read in a dialect (docs/gcode.md "Fanuc dialect").
pub fn reopen_in(dir: &Path, dialect: novanc::settings::Dialect) -> Console {
    reopen_with(dir, |s| s.dialect = dialect)
}

/// [`reopen`] with the console's settings changed by `set` (a dialect and its settings).
pub fn reopen_with(
    dir: &Path,
    set: impl FnOnce(&mut novanc::settings::MachineSettings),
) -> Console {
    let mut cfg = ConsoleConfig::new(dir.to_path_buf());
    cfg.clock = ClockMode::Virtual;
    set(&mut cfg.settings);
    // A child process that another test of this binary is starting holds a copy of the
    // directory's lock (an open file of this process) from its fork to its exec (`serial`):
    // a restart right after the console before it was dropped may meet that copy. It lasts
    // milliseconds; a second console really holding the lock is still refused.
    let until = std::time::Instant::now() + std::time::Duration::from_secs(5);
    loop {
        match Console::open(cfg.clone()) {
            Ok((c, _)) => return c,
            Err(e) if e.contains("another novanc") && std::time::Instant::now() < until => {
                std::thread::sleep(std::time::Duration::from_millis(20))
            }
            Err(e) => panic!("{e}"),
        }
    }
}

/// The program read runs one block in SINGLE, is RESET, then runs again in AUTO to its end
/// (a restart after RESET reads from the top). Checks the one block and the end.
pub fn one_block_reset_then_run(c: &mut Console) {
    use novanc::panel_model::OpMode;
    c.handle(PanelEvent::Op(OpMode::Single));
    c.handle(PanelEvent::Start);
    c.handle(PanelEvent::Wait);
    assert_eq!(audit(c).len(), 1, "{}", c.frame_text());
    c.handle(PanelEvent::Reset);
    c.handle(PanelEvent::Wait);
    c.handle(PanelEvent::Op(OpMode::Auto));
    c.handle(PanelEvent::Start);
    c.handle(PanelEvent::Wait);
    assert!(shows(c, "program end"), "{}", c.frame_text());
}

/// One MDI line: typed in MDI, START, and waited for.
pub fn mdi(c: &mut Console, line: &str) {
    c.handle(PanelEvent::Op(novanc::panel_model::OpMode::Mdi));
    type_line(c, line);
    c.handle(PanelEvent::Start);
    c.handle(PanelEvent::Wait);
}

/// PROGRAM READ of a file into program memory: DATA, READ, the file in the reader, START, and
/// waited for.
pub fn read_program(c: &mut Console, path: PathBuf) {
    c.handle(PanelEvent::Op(novanc::panel_model::OpMode::Data));
    c.handle(PanelEvent::Data(novanc::panel_model::DataMode::Read));
    c.handle(PanelEvent::Tape(path));
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

/// Nothing typed is lost, on every console (docs/panel.md "Rules and choices"): after a whole
/// `line` typed and entered, with `entry` on the entry line and `message` on the message line,
/// either the line acted (the entry line is empty), or it was refused with the reason said and
/// stays on the entry line to be corrected, or the data keys were refused before it was read
/// (`'LINE' refused: ...`). Err: what broke the rule.
pub fn typed_line_kept_or_taken(line: &str, entry: &str, message: &str) -> Result<(), String> {
    if message.starts_with(&format!("'{line}' refused")) {
        return Ok(());
    }
    if entry.is_empty() && !message.is_empty() {
        return Ok(());
    }
    if entry == line && !message.is_empty() {
        return Ok(());
    }
    Err(format!(
        "typed {line:?}: the entry line holds {entry:?} and the message says {message:?}"
    ))
}

/// Runs `tests/mcap_check.py` on a recording; `None` if python3 or its `mcap` module is
/// missing and `CI` is unset (a skip, said loudly). With `CI` set the module is required.
pub fn python_check(path: &Path, extra: &[&str]) -> Option<(bool, String)> {
    let mut args = vec![path.as_os_str()];
    args.extend(extra.iter().map(std::ffi::OsStr::new));
    python_script("mcap_check.py", &["mcap"], &args)
}

/// Runs the Python check `tests/SCRIPT` with `args` (a recording, an agent's port…): whether
/// it passed, and what it printed. `None` if python3 or one of its `modules` is missing, or the
/// script says so itself (exit status 2: something it needs is not installed), and `CI` is
/// unset (a skip, said loudly); with `CI` set all of it is required (`.ci/run` installs it).
pub fn python_script(
    script: &str,
    modules: &[&str],
    args: &[&std::ffi::OsStr],
) -> Option<(bool, String)> {
    let skip = |why: &str| {
        if std::env::var_os("CI").is_some() {
            panic!("{script}: {why}: required in CI (.ci/run installs it)");
        }
        eprintln!("\n!!!!! SKIPPED {script}: {why}; .ci/run shows how to install it !!!!!\n");
    };
    let import = format!("import {}", modules.join(", "));
    let has_modules = Command::new("python3")
        .args(["-c", &import])
        .output()
        .map(|o| o.status.success())
        .unwrap_or(false);
    if !has_modules {
        skip(&format!(
            "python3 or one of its modules {modules:?} is missing"
        ));
        return None;
    }
    let script_path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests")
        .join(script);
    let out = Command::new("python3")
        .arg(script_path)
        .args(args)
        .output()
        .expect("run a Python check");
    let text = format!(
        "{}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    if out.status.code() == Some(2) {
        skip(text.trim());
        return None;
    }
    Some((out.status.success(), text))
}

/// Makes `cmd` run as the user `nobody` (65534) when the tests run as root: root ignores file
/// modes, so a read-only directory or an unreadable file is one only to another user. As any
/// other user the command runs as it is.
pub fn unprivileged(cmd: &mut Command) -> &mut Command {
    use std::os::unix::process::CommandExt;
    // SAFETY: geteuid has no preconditions.
    if unsafe { libc::geteuid() } != 0 {
        return cmd;
    }
    // SAFETY: only async-signal-safe calls (setgroups, setgid, setuid) between fork and exec.
    unsafe {
        cmd.pre_exec(|| {
            if libc::setgroups(0, std::ptr::null()) != 0
                || libc::setgid(65534) != 0
                || libc::setuid(65534) != 0
            {
                return Err(std::io::Error::last_os_error());
            }
            Ok(())
        })
    }
}

/// Sets the mode bits of `path`.
pub fn chmod(path: &Path, mode: u32) {
    use std::os::unix::fs::PermissionsExt;
    std::fs::set_permissions(path, std::fs::Permissions::from_mode(mode)).unwrap();
}

/// Holds the tests of one test binary that take a directory lock one at a time: a child
/// process forked by one test holds a copy of every descriptor of the test process until it
/// execs, among them another test's lock (`flock` is per open file), which would then refuse
/// that test's reopen as "another novanc is using this state directory".
pub fn serial() -> std::sync::MutexGuard<'static, ()> {
    static SERIAL: std::sync::Mutex<()> = std::sync::Mutex::new(());
    SERIAL.lock().unwrap_or_else(|e| e.into_inner())
}

/// Runs the test `test` of this test binary as a child process, with `env` set (the child
/// does its work only when it finds its variables) and as the user `nobody` when
/// `unprivileged` (see [`unprivileged`]); checks that it succeeded and printed `child done`.
pub fn run_child(test: &str, env: &[(&str, &std::ffi::OsStr)], unprivileged: bool) {
    let mut cmd = Command::new(std::env::current_exe().unwrap());
    cmd.args(["--exact", test, "--nocapture", "--test-threads=1"]);
    for (k, v) in env {
        cmd.env(k, v);
    }
    if unprivileged {
        self::unprivileged(&mut cmd);
    }
    let out = cmd.output().unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success() && stdout.contains("\nchild done"),
        "child {test} {env:?} failed:\n{stdout}\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

/// Sets the file size limit of this process (SIGXFSZ ignored, so writes fail with EFBIG), as
/// on a full disk.
pub fn limit_file_size(bytes: u64) {
    // SAFETY: plain libc calls with valid arguments.
    unsafe {
        libc::signal(libc::SIGXFSZ, libc::SIG_IGN);
        let lim = libc::rlimit {
            rlim_cur: bytes,
            rlim_max: libc::RLIM_INFINITY,
        };
        assert_eq!(libc::setrlimit(libc::RLIMIT_FSIZE, &lim), 0);
    }
}

/// The names in a directory, sorted.
pub fn names(d: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(d)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

/// The environment of a child started by [`run_child_on`]: what it is to do, and where.
const CHILD_WHAT: &str = "NOVANC_TEST_CHILD";
const CHILD_DIR: &str = "NOVANC_TEST_CHILD_DIR";

/// Runs the test `test` of this test binary as a child that does `what` in `dir` (it reads
/// them with [`child_on`]); see [`run_child`].
pub fn run_child_on(test: &str, what: &str, dir: &Path, unprivileged: bool) {
    let env = [
        (CHILD_WHAT, std::ffi::OsStr::new(what)),
        (CHILD_DIR, dir.as_os_str()),
    ];
    run_child(test, &env, unprivileged);
}

/// In a child started by [`run_child_on`]: what it is to do, and where; None in a normal run.
pub fn child_on() -> Option<(String, PathBuf)> {
    let what = std::env::var(CHILD_WHAT).ok()?;
    Some((what, PathBuf::from(std::env::var_os(CHILD_DIR)?)))
}

/// Every file of `d` with its bytes, sorted: equal before and after, nothing changed.
pub fn contents(d: &Path) -> Vec<(String, Vec<u8>)> {
    names(d)
        .into_iter()
        .map(|n| {
            let bytes = std::fs::read(d.join(&n)).unwrap_or_default();
            (n, bytes)
        })
        .collect()
}

/// Runs `novanc script` on `script_text` in `dir` (its own state directory `dir/state`) with a
/// recording `dir/r.mcap`: the recording's path and the script's stdout and stderr, after
/// checking that it exited 0.
pub fn recorded_script(dir: &Path, script_text: &str) -> (PathBuf, String) {
    recorded_script_with(dir, script_text, &[])
}

/// [`recorded_script`] with more options for `novanc script` (`--dialect fanuc`).
pub fn recorded_script_with(dir: &Path, script_text: &str, args: &[&str]) -> (PathBuf, String) {
    let s = dir.join("s.panel");
    std::fs::write(&s, script_text).unwrap();
    let rec = dir.join("r.mcap");
    let out = novanc_command()
        .arg("script")
        .arg(&s)
        .args(args)
        .arg("--state")
        .arg(dir.join("state"))
        .arg("--record")
        .arg(&rec)
        .output()
        .unwrap();
    let text = format!(
        "{}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    assert_eq!(out.status.code(), Some(0), "{text}");
    (rec, text)
}

/// `novanc ARGS PROG EXTRA..` on `text` written as `name` in a fresh directory (an EXTRA
/// word not starting with `--` is a file in that directory): the exit code, stdout and
/// stderr, and the directory.
pub fn novanc_on(
    args: &[&str],
    name: &str,
    text: &str,
    extra: &[&str],
) -> (Option<i32>, String, String, std::path::PathBuf) {
    let dir = temp_dir("cli");
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    let out = novanc_command()
        .args(args)
        .arg(&p)
        .args(extra.iter().map(|e| match e.starts_with("--") {
            true => std::path::PathBuf::from(e),
            false => dir.join(e),
        }))
        .output()
        .unwrap();
    (
        out.status.code(),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
        dir,
    )
}

/// The cursor keys: the arrows, PgUp/PgDn, Home/End.
pub const CURSOR_KEYS: [novanc_panel::Key; 8] = {
    use novanc_panel::Key;
    [
        Key::Up,
        Key::Down,
        Key::Left,
        Key::Right,
        Key::PageUp,
        Key::PageDown,
        Key::Home,
        Key::End,
    ]
};

/// Every key an operator can press at the terminal but quit (Ctrl+C, Alt+Q): F1–F12, Alt with
/// each letter, digit and the overrides' and handwheel's signs, Ctrl with each letter, the
/// cursor and editing keys, and two data keys.
pub fn all_keys() -> Vec<novanc_panel::Key> {
    use novanc_panel::Key;
    let mut keys: Vec<Key> = (1..=12).map(Key::F).collect();
    keys.extend(
        "abcdefghijklmnoprstuvwxyz0123456789=-[],."
            .chars()
            .map(Key::Alt),
    );
    keys.extend("abdefghijklmnopqrstuvwxyz".chars().map(Key::Ctrl));
    keys.extend(CURSOR_KEYS);
    keys.extend([
        Key::Insert,
        Key::Delete,
        Key::Esc,
        Key::Enter,
        Key::Backspace,
        Key::Tab,
        Key::Char('#'),
        Key::Char('5'),
    ]);
    keys
}
