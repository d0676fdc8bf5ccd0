//! A model-based test of the Citizen lathe console (docs/lathe.md): random sequences of operator
//! actions — START, STOP, RESET of the selected channel, E-STOP, faults injected in random
//! channels, the channel selector, part targets, MDI lines (good and bad, with parameters,
//! expressions, messages and O-words), editor lines that
//! move the pointer or search, mode changes, the help screen and waits of random length — on the
//! `LatheConsole` the terminal uses, in virtual time.
//!
//! Invariants after every step:
//! - the display is exactly rows × cols, one summary line per channel of cols characters;
//! - every channel's tool tip is within its travel;
//! - a work is in one spindle, or in two only during a handover from a channel to the one it
//!   delivers to, both chucks closed;
//! - no machining block ever started on an empty spindle (the sample programs receive first);
//! - no channel machined any work twice;
//! - part counts never decrease within a batch and never pass the target;
//! - a channel in E-STOP does not move while the others run, nor one in FAULT once its feed
//!   hold has brought it to rest;
//! - the message line says a cycle runs, a feed hold or an E-STOP only while the machine is so;
//! - a key the lathe has no use for says so;
//! - at the end of each sequence, the stores (reopened) hold exactly the console's programs,
//!   MDI buffers, part counter, editor pointers and jog feeds.
//!
//! The same sequences run on the Citizen and on a one-channel Fanuc lathe that the operator
//! loads by hand (`loading manual`, a shop program without chuck codes).
//!
//! CI runs `NOVANC_LATHE_SEQUENCES` sequences (default 40) of 40 steps. The long run:
//! `NOVANC_LATHE_SEQUENCES=2000 cargo test --release --test lathe_sequences -- --ignored --nocapture`.

mod common;

use novanc::lathe::console::LatheConsole;
use novanc::lathe::desc::LatheDesc;
use novanc::panel_model::{OpMode, Page, PanelEvent};
use novanc::pulse_core::testkit::Rng;
use novanc::store::lathe::{LatheStore, Program};

const ROWS: usize = 12;
const COLS: usize = 40;

const MDI_LINES: [&str; 29] = [
    "G0 X30 Z20",
    // The channel keeps its modes between runs (docs/lathe-gcode.md "What a channel keeps"):
    // G91 in one MDI run makes the next one's moves increments from where the tool stands.
    "G91",
    "G90 G95 M3 S800",
    "G0 U4 W-2",
    "G97 S500 M3",
    "M5",
    "G1 X20 F0.1",
    "G0 X99999",
    "Q7",
    // What the lathe reads through the mill's flow and parameters (issue 22's one reader):
    // parameters and expressions, a message, an abort, an O-word left open in one line.
    "#1 = 25 G0 X[#1 + 5] Z[20 + SQRT[25]]",
    "#<clear> = 30 (print, clear=#<clear>)",
    "G0 X#<undefined> Z20",
    "(abort, operator abort)",
    "o1 if [1 GT 0]",
    // A program zero moved (kept until RESET or G92.1, stop 50), and put back.
    "G92 Z5",
    "G92.1",
    // Nose-radius compensation, the mill's since stop 51: an arc as the entry move, a move
    // under it, the exit (refused without a tool, or across runs as the channel keeps G41/G42).
    "G42 G2 X24 Z12 R9 F0.2",
    "G1 W-4",
    "G40 G0 X40",
    // A Haas's codes (stop 56): the chip auger remapped on the lathe loaded by hand (an
    // unknown code on the Citizen), the rest of the line after its subroutine; a bare G28.
    "M31 G0 X30 Z20",
    "G28",
    // A digital output (stop 56), and one out of range; with the motion, and an analog one
    // (stop 60).
    "M64 P2",
    "M65 P99",
    "M62 P3 G0 X30",
    "M67 E1 Q2.5",
    // Work offsets (stop 57): one set by G10 L2 and used, the system kept for the next run
    // (RESET: G54), one beyond the limit.
    "G10 L2 P2 Z-3",
    "G55 G0 X30 Z20",
    "G54",
    "G10 L2 P3 Z99999",
];
const EDIT_LINES: [&str; 6] = ["L", "3L", "-2L", "SM10", "SNOSUCHTEXT", "2Y"];
const OFS_LINES: [&str; 11] = [
    "T1 X0.01",
    "T2 Z-0.005",
    "T9 X1",
    "T1 P12",
    "-0.01",
    "0.004",
    // The work offsets under the tools (stop 57), and one the lathe has not.
    "G55 Z-2",
    "G56 X1 Z1",
    "G60 Z1",
    // A measure (Fanuc's MEASURE) where the cursor stands: on a work row it sets the offset
    // from where the tool is, elsewhere it is refused.
    "Z0",
    "X30.",
];

struct Seq {
    c: LatheConsole,
    dir: std::path::PathBuf,
    counts: Vec<u32>,
    stats: Stats,
    /// The last step was an operator action with no machine time after it.
    fresh: bool,
}

#[derive(Default)]
struct Stats {
    steps: u64,
    parts: u64,
    faults: u64,
    estops: u64,
    handovers_seen: u64,
    batches_done: u64,
    /// Manual moves made (a jog key or the handwheel that moved a tool post).
    jogs: u64,
    /// Steps that ended with MACHINE LOCK on.
    locked: u64,
    /// Selector turns that cleared a line left typed (and said so).
    turns_cleared: u64,
    /// Program files read into a channel, and programs punched (stop 52).
    reads: u64,
    punches: u64,
    /// SEARCH points set (a line typed in AUTO on the lathe loaded by hand; stop 57).
    searches: u64,
    /// Relative positions set on POS (stop 59).
    rel_set: u64,
    /// HOMEs accepted, restarts, and restarts after which a channel owed HOME (stop 61).
    homes: u64,
    restarts: u64,
    owed: u64,
}

fn check(s: &mut Seq, what: &str) {
    let v = s.c.view();
    assert_eq!(v.display.len(), ROWS, "{what}");
    assert!(
        v.display.iter().all(|l| l.chars().count() == COLS),
        "{what}: {:?}",
        v.display
    );
    assert_eq!(v.summary.len(), s.c.desc().channels.len(), "{what}");
    assert!(
        v.summary.iter().all(|l| l.chars().count() == COLS),
        "{what}: {:?}",
        v.summary
    );
    let desc = s.c.desc().clone();
    let target = s.c.counter().target;
    let counts = &s.c.counter().counts;
    for (i, c) in counts.iter().enumerate() {
        assert!(*c <= target, "{what}: CH{} counted {c} of {target}", i + 1);
        if *c < s.counts[i] {
            // Only a new batch (all counts back to 0) may lower a count.
            assert!(
                counts.iter().all(|&x| x == 0),
                "{what}: counts went {:?} -> {counts:?}",
                s.counts
            );
        }
    }
    s.counts = counts.clone();
    // Each channel's summary counts what the part counter counts (stop 61: after a SEARCH the
    // summary counted the cycle's parts only, beside the title's batch).
    for (ch, c) in v.channels.iter().enumerate() {
        assert_eq!(c.parts, counts[ch], "{what}: CH{}'s summary count", ch + 1);
    }
    // The programmed path the window draws (stop 51: what START would run, the MDI lines in
    // MDI), every seventh step: it reads, or says why at a real line; what it reads ends
    // inside the channel's travel.
    if s.stats.steps.is_multiple_of(7) {
        for (ch, cd) in desc.channels.iter().enumerate() {
            match s.c.programmed(ch).expect("every channel has a path") {
                Ok(st) => {
                    let p = |mm: f64| desc.pulses(mm);
                    let (x, z) = (cd.axes[0].travel, cd.axes[1].travel);
                    for b in st.iter().flat_map(|s| &s.blocks) {
                        assert!(
                            (p(x[0])..=p(x[1])).contains(&b.end[0])
                                && (p(z[0])..=p(z[1])).contains(&b.end[2]),
                            "{what}: CH{}'s programmed path leaves the travel: {b:?}",
                            ch + 1
                        );
                    }
                }
                Err(e) => assert!(e.line >= 1 && !e.message.is_empty(), "{what}: {e:?}"),
            }
        }
    }
    // The message line says what the machine does only while it does it: never "runs" or
    // "START" with every channel at rest, never a feed hold or an E-STOP that is not there
    // (the acknowledgement of an action that has not yet had a tick is the one exception).
    let m = s.c.message().to_string();
    let states: Vec<&str> = v.channels.iter().map(|c| c.state.as_str()).collect();
    let any = |w: &[&str]| states.iter().any(|s| w.contains(s));
    if !s.fresh {
        if m == "START"
            || m.starts_with("cycle start")
            || m.starts_with("MDI CH") && m.ends_with(" runs")
        {
            assert!(
                any(&["RUN", "WAIT", "STOP"]),
                "{what}: '{m}' with {states:?}"
            );
        }
        if m.starts_with("feed hold") {
            assert!(any(&["HOLD"]), "{what}: '{m}' with {states:?}");
        }
        if m.starts_with("EMERGENCY STOP") {
            assert!(any(&["ESTOP"]), "{what}: '{m}' with {states:?}");
        }
    }
    // Each channel's fault or alarm in force, and an E-STOP, is in the history the MSG page
    // shows (the centre's rule: put there when it comes, whatever the screen was doing); an
    // E-STOP is the machine's (one entry, not a channel's).
    for (i, c) in v.channels.iter().enumerate() {
        let text = match c.state.as_str() {
            "FAULT" | "ALARM" => format!("CH{} {}: {}", i + 1, c.state, c.note),
            "ESTOP" => "EMERGENCY STOP: pulses stopped; press RESET".to_string(),
            _ => continue,
        };
        {
            assert!(
                s.c.history()
                    .iter()
                    .any(|e| e.kind == novanc::store::history::Kind::Alarm && e.text == text),
                "{what}: '{text}' is not in the history"
            );
        }
    }
    let l = s.c.cycle();
    let chans = l.channels();
    // The rapid and spindle overrides, DRY RUN and MACHINE LOCK the console shows are every
    // channel's machine's (MACHINE LOCK on all or none).
    let mlk = s.c.machine_switches().machine_lock;
    assert_eq!(v.title.contains(" MLK"), mlk, "{what}: {}", v.title);
    s.stats.locked += u64::from(mlk);
    for c in chans {
        let sw = &c.status.switches;
        assert_eq!(
            (
                sw.rapid_override,
                sw.spindle_override,
                sw.dry_run,
                sw.machine_lock
            ),
            (
                s.c.rapid_spindle().0,
                s.c.rapid_spindle().1,
                s.c.dry_run(),
                mlk
            ),
            "{what}"
        );
    }
    for (ch, c) in chans.iter().enumerate() {
        let pos = [c.status.pos[0], c.status.pos[2]];
        // The screen shows what each channel's machine does, whether or not the run under
        // way has a program for it (stop 41: a channel outside an MDI run showed S 0 with its
        // spindle turning): its spindle, coolant and tool post, and E-STOP on every channel.
        let shown = &v.channels[ch];
        assert_eq!(
            (shown.rpm, shown.coolant, shown.pos),
            (c.status.spindle as f64, c.status.coolant, pos),
            "{what}: CH{} shown otherwise than its machine",
            ch + 1
        );
        // Its work system is known, and the plasma's X and Z are the tip in it (stop 57).
        let Some((system, _)) = shown.system else {
            panic!("{what}: CH{} has no work system", ch + 1);
        };
        assert!(system < 6, "{what}");
        if ch == v.selected && v.display[0].starts_with("CH") {
            let w = shown.work_pos();
            let mm = |p: i64| format!("{:9.3}", p as f64 * desc.pulse_mm);
            let xz = format!("X{} Z{}", mm(w[0] * 2), mm(w[1]));
            assert!(
                v.display[1].starts_with(&xz),
                "{what}: {:?} for {xz}",
                v.display[1]
            );
        }
        if c.status.estop {
            assert_eq!(shown.state, "ESTOP", "{what}: CH{}", ch + 1);
        }
        // A channel that owes the reference return runs no program (stop 61).
        if s.c.home_owed()[ch] {
            assert!(
                !["RUN", "WAIT", "HOLD"].contains(&shown.state.as_str()),
                "{what}: CH{} owes HOME and is {}",
                ch + 1,
                shown.state
            );
        }
        for (a, ax) in desc.channels[ch].axes.iter().enumerate() {
            let lo = desc.pulses(ax.travel[0]);
            let hi = desc.pulses(ax.travel[1]);
            assert!(
                (lo..=hi).contains(&pos[a]),
                "{what}: CH{} axis {a} at {} outside {lo}..{hi}",
                ch + 1,
                pos[a]
            );
        }
        // The cut interlock refuses a cutting block on an empty or open chuck: it is an
        // alarm, never a cut (the sample programs receive their work first).
        if let Some(a) = &c.status.alarm {
            assert!(
                !a.contains("chuck") && !a.contains("no work"),
                "{what}: CH{} cut on an empty spindle: {a}",
                ch + 1
            );
        }
    }
    let works: Vec<(u32, usize)> = chans
        .iter()
        .enumerate()
        .filter_map(|(ch, c)| Some((c.sync.as_ref()?.work?, ch)))
        .collect();
    let mut ids: Vec<u32> = works.iter().map(|w| w.0).collect();
    ids.sort();
    ids.dedup();
    let closed = |ch: usize| chans[ch].sync.as_ref().is_some_and(|v| v.closed);
    for id in ids {
        let at: Vec<usize> = works.iter().filter(|w| w.0 == id).map(|w| w.1).collect();
        match at.as_slice() {
            [_] => {}
            [a, b] => {
                let (a, b) = (*a.min(b), *a.max(b));
                assert_eq!(
                    desc.receiver_of(a),
                    Some(b),
                    "{what}: W{id} in CH{} and CH{}",
                    a + 1,
                    b + 1
                );
                assert!(
                    closed(a) && closed(b),
                    "{what}: W{id} handed over with a chuck open"
                );
                s.stats.handovers_seen += 1;
            }
            more => panic!("{what}: W{id} in {more:?}"),
        }
        let m = l.machined(id);
        assert!(
            m.iter().all(|&n| n <= 1),
            "{what}: W{id} machined {m:?} times per channel"
        );
    }
}

/// Advances `ns` and checks that a faulted or E-stopped channel did not move meanwhile.
fn advance(s: &mut Seq, ns: u64) {
    s.fresh = false;
    let state = |s: &Seq| -> Vec<(String, [i64; 2])> {
        s.c.view()
            .channels
            .iter()
            .map(|c| (c.state.clone(), c.pos))
            .collect()
    };
    // E-STOP stops at once; a fault is a feed hold, which decelerates first: once at rest,
    // a faulted channel stays there.
    let moving: Vec<bool> = (s.c.cycle().channels().iter())
        .map(|c| c.status.moving)
        .collect();
    let frozen: Vec<(usize, [i64; 2])> = state(s)
        .into_iter()
        .enumerate()
        .filter(|(ch, (st, _))| {
            st == "ESTOP" || (st == "FAULT" && !moving.get(*ch).copied().unwrap_or(false))
        })
        .map(|(ch, (_, pos))| (ch, pos))
        .collect();
    s.c.tick(ns);
    let now = state(s);
    for (ch, pos) in frozen {
        assert_eq!(now[ch].1, pos, "CH{} moved while {}", ch + 1, now[ch].0);
    }
}

/// HOME (stop 61) on channel `ch`, selected: its reference return, X out to the top of its
/// travel, then Z; refused, and said, with a cycle under way, in E-STOP or under MACHINE LOCK.
/// Run to rest, an accepted return ends at the top of the travel with the channel's position
/// known.
fn home(s: &mut Seq, ch: usize) {
    s.c.handle(PanelEvent::Home);
    let m = s.c.message().to_string();
    let top = [
        s.c.desc().pulses(s.c.desc().channels[ch].axes[0].travel[1]),
        s.c.desc().pulses(s.c.desc().channels[ch].axes[1].travel[1]),
    ];
    // (At the top already: made at once.)
    if m.starts_with(&format!("CH{} HOME: ", ch + 1)) {
        s.stats.homes += 1;
        // (At POS's slowest jog feed here, JOG 300, the Citizen's longest return takes 31 s.)
        for _ in 0..400 {
            advance(s, 500_000_000);
            let c = &s.c.cycle().channels()[ch].status;
            if !c.moving && c.idle {
                break;
            }
        }
        let at = s.c.cycle().axes()[ch];
        assert_eq!(
            at,
            top,
            "home: CH{} ended off the top: {}",
            ch + 1,
            s.c.message()
        );
        assert!(!s.c.home_owed()[ch], "home: CH{} still owes it", ch + 1);
    } else {
        assert!(
            m.starts_with(&format!("CH{} ", ch + 1)) && m.contains("HOME refused"),
            "home: {m}"
        );
    }
}

fn step(s: &mut Seq, rng: &mut Rng) -> String {
    let ev = match rng.range(0, 104) {
        0..=14 => PanelEvent::Start,
        15..=19 => PanelEvent::Stop,
        20..=26 => PanelEvent::Reset,
        27..=29 => {
            s.stats.estops += 1;
            PanelEvent::EStop
        }
        30..=37 => {
            s.stats.faults += 1;
            PanelEvent::Fault(
                rng.below(s.c.desc().channels.len() + 1),
                ["tool breakage", "failed supply", "operator"][rng.range(0, 2) as usize].into(),
            )
        }
        // One past the last channel now and then: refused, said.
        38..=45 => PanelEvent::Channel(rng.below(s.c.desc().channels.len() + 1)),
        46..=47 => PanelEvent::Press(novanc_panel::Key::Tab),
        48..=49 => PanelEvent::Target(rng.range(1, 4) as u32),
        50..=53 => [
            PanelEvent::Op(OpMode::Auto),
            PanelEvent::Op(OpMode::Mdi),
            PanelEvent::Op(OpMode::Data),
            PanelEvent::OfsMode,
            PanelEvent::Op(OpMode::Step),
            PanelEvent::Op(OpMode::Continuous),
            PanelEvent::Op(OpMode::Handle),
            PanelEvent::Op(OpMode::Single),
            PanelEvent::Press(novanc_panel::Key::Ctrl('e')),
            PanelEvent::Press(novanc_panel::Key::Ctrl('u')),
            PanelEvent::Press(novanc_panel::Key::Ctrl('g')),
            PanelEvent::Press(novanc_panel::Key::Ctrl('p')),
        ][rng.range(0, 11) as usize]
            .clone(),
        54..=57 => PanelEvent::Type(MDI_LINES[rng.below(MDI_LINES.len())].into()),
        58..=60 => PanelEvent::Type(EDIT_LINES[rng.range(0, 5) as usize].into()),
        61 => PanelEvent::Press(novanc_panel::Key::F(8)),
        65 => PanelEvent::Type(OFS_LINES[rng.below(OFS_LINES.len())].into()),
        // A variable set (on MACRO), an MDI line or an editor line refused elsewhere.
        86 => PanelEvent::Type(format!("#{}={}", 500 + rng.range(0, 2), rng.range(0, 9))),
        // The keypad's +INPUT: adds on OFS and MACRO, refused elsewhere; never a channel turn.
        87 => PanelEvent::PlusInput,
        66 => PanelEvent::Override([0, 50, 100, 150][rng.range(0, 3) as usize]),
        62..=63 => PanelEvent::OptionalStop(rng.range(0, 1) == 1),
        80..=81 => {
            // Keys of the one key map, the centre's own among them: each acts or says that it
            // does nothing here (no key is lost in silence).
            use novanc_panel::Key;
            let keys = [
                Key::Alt('='),
                Key::Alt('-'),
                Key::Alt('z'),
                Key::F(2),
                Key::Alt('d'),
                Key::Alt('l'),
                Key::Alt('o'),
                Key::Alt('f'),
                Key::Alt('['),
                Key::Alt(']'),
            ];
            let k = keys[rng.below(keys.len())];
            let silent = !matches!(k, Key::Alt('=' | '-' | 'o' | 'f' | '[' | ']' | 'd' | 'l'));
            let line = format!("key {}", novanc::console::keys::key_name(k));
            s.fresh = true;
            s.c.handle(PanelEvent::Press(k));
            if silent {
                assert!(
                    s.c.message().contains(" does nothing in "),
                    "{line}: {}",
                    s.c.message()
                );
            }
            return line;
        }
        82..=85 => {
            // A jog key or the handwheel's: in STEP, CONTINUOUS (a tap, in virtual time) or
            // HANDLE (a detent) with no cycle under way, the selected channel's tool post
            // moves one increment on one axis and nothing else moves; otherwise it is refused
            // with the reason and nothing moves.
            use novanc_panel::Key;
            let k = [
                Key::Up,
                Key::Down,
                Key::Left,
                Key::Right,
                Key::Alt(','),
                Key::Alt('.'),
                Key::Delete,
            ][rng.range(0, 6) as usize];
            let line = format!("key {}", novanc::console::keys::key_name(k));
            let posts =
                |c: &LatheConsole| -> Vec<[i64; 2]> { c.tips().into_iter().map(|t| t.0).collect() };
            let before = posts(&s.c);
            let sel = s.c.selected();
            s.fresh = true;
            s.c.handle(PanelEvent::Press(k));
            let said = s.c.message().to_string();
            let mut line = line;
            if ["STEP CH", "HANDLE CH"].iter().any(|w| said.starts_with(w)) {
                // In virtual time a STEP or a detent moves at the next wait (docs/cli.md
                // "Time"); a CONTINUOUS tap runs to rest at once.
                if rng.below(4) == 0 {
                    // E-STOP before the wait: the increment queued is dropped, and nothing
                    // moves (stop 44).
                    s.stats.estops += 1;
                    s.c.handle(PanelEvent::EStop);
                    s.c.handle(PanelEvent::Wait);
                    assert_eq!(posts(&s.c), before, "{line} | estop | wait: {said}");
                    return format!("{line} | estop | wait");
                }
                s.c.handle(PanelEvent::Wait);
                line.push_str(" | wait");
            }
            let after = posts(&s.c);
            let arrow = matches!(
                k,
                Key::Up | Key::Down | Key::Left | Key::Right | Key::Delete
            );
            if arrow
                && k != Key::Delete
                && matches!(s.c.page(), Page::Msg | Page::Macro | Page::Ofs)
            {
                // On the MSG, MACRO and OFS pages the arrows scroll or move the cursor (the
                // centre's page rule; on OFS they jogged a tool post before stop 40).
                assert_eq!(after, before, "{line}: {said}");
                return line;
            }
            if matches!(k, Key::Up | Key::Down) && s.c.mode() == OpMode::Mdi {
                // In MDI, Up and Down recall the channel's lines typed (the centre's recall),
                // on the mode display and under a page that has no use for the arrows (POS,
                // MODAL; one rule since stop 45): nothing said but that, or what the machine
                // is doing.
                let notes = [
                    "MDI: no line to recall",
                    "EMERGENCY STOP",
                    "feed hold",
                    "STOP: ",
                    "SINGLE BLOCK",
                    "JOG",
                ];
                assert!(
                    said.is_empty() || notes.iter().any(|w| said.starts_with(w)),
                    "{line}: {said}"
                );
                assert_eq!(after, before, "{line}: {said}");
                return line;
            }
            if arrow && s.c.mode() == OpMode::Data && s.c.page() == Page::Mode {
                // In DATA the arrows and Delete are the editor's cursor keys: the pointer moves
                // or a character goes (nothing said but what the machine is doing), or they
                // say why not; no tool post moves.
                let notes = [
                    "EMERGENCY STOP",
                    "feed hold",
                    "STOP: ",
                    "SINGLE BLOCK",
                    "JOG",
                ];
                let keys = ["Up: ", "Down: ", "Left: ", "Right: ", "Delete: "];
                assert!(
                    said.is_empty() || keys.iter().chain(&notes).any(|w| said.starts_with(w)),
                    "{line}: {said}"
                );
                assert_eq!(after, before, "{line}: {said}");
                return line;
            }
            if ["STEP CH", "CONTINUOUS CH", "HANDLE CH"]
                .iter()
                .any(|w| said.starts_with(w))
            {
                s.stats.jogs += 1;
                for (ch, (b, a)) in before.iter().zip(&after).enumerate() {
                    let moved: Vec<i64> = (0..2).map(|i| (a[i] - b[i]).abs()).collect();
                    let want: &[i64] = match (ch == sel, k) {
                        (false, _) => &[0, 0],
                        (true, Key::Up | Key::Down) => &[10, 0],
                        // The handwheel turns the axis last turned.
                        (true, Key::Alt(_)) if moved[0] != 0 => &[10, 0],
                        (true, _) => &[0, 10],
                    };
                    assert_eq!(moved, want, "{line}: CH{} {b:?} -> {a:?} ({said})", ch + 1);
                }
            } else {
                assert!(
                    said.contains("refused")
                        || said.contains("(Alt+6) to move a tool post")
                        || said.contains("turn the operation selector to HANDLE")
                        || said.starts_with("HANDLE: turn the handwheel")
                        || (k == Key::Delete && said.contains(" does nothing in ")),
                    "{line}: {said}"
                );
                assert_eq!(after, before, "{line}: {said}");
            }
            return line;
        }
        88..=89 => {
            // PROGRAM READ (stop 52): the selected channel's own program from a file (so the
            // cycle stays what the machine can run), or a file that is refused. Read: the
            // channel's program is the file's text, its pointer at the start; refused: the
            // program is unchanged and the message says why.
            let ch = s.c.selected();
            let before = s.c.programs()[ch].clone();
            let good = s.dir.join(format!("read-ch{}.nc", ch + 1));
            std::fs::write(&good, &before.text).unwrap();
            let bad = s.dir.join("read-binary.nc");
            std::fs::write(&bad, [0u8, 0x13, 0xff]).unwrap();
            let path = [good, bad, s.dir.join("no-such.nc"), s.dir.clone()]
                [rng.range(0, 3) as usize]
                .clone();
            let mut line = format!("tape {}", path.display());
            s.fresh = true;
            if rng.range(0, 1) == 1 {
                // Where it reads: DATA INPUT (its typed line, if any, cleared and said).
                s.c.handle(PanelEvent::Op(OpMode::Data));
                line = format!("op DATA\n{line}");
            }
            s.c.handle(PanelEvent::Tape(path));
            let m = s.c.message().to_string();
            let now = &s.c.programs()[ch];
            if m.starts_with("read ") {
                s.stats.reads += 1;
                assert_eq!(now.text, before.text, "{line}: {m}");
                assert_eq!(s.c.pointer(ch), 0, "{line}: {m}");
            } else {
                assert!(m.starts_with("PROGRAM READ refused: "), "{line}: {m}");
                assert_eq!(*now, before, "{line}: {m}");
            }
            return line;
        }
        90 => {
            // The punch key (stop 52): the selected channel's program to an image that reads
            // back as its text; refused outside DATA INPUT or with a cycle under way.
            let ch = s.c.selected();
            let text = s.c.programs()[ch].text.clone();
            let out = s.dir.join("punched.tape");
            let _ = std::fs::remove_file(&out);
            let code = ["", " EIA"][rng.range(0, 1) as usize];
            let turn = rng.range(0, 1) == 1;
            if turn {
                s.c.handle(PanelEvent::Op(OpMode::Data));
            }
            s.c.handle(PanelEvent::Type(format!("{}{code}", out.display())));
            s.fresh = true;
            s.c.handle(PanelEvent::Press(novanc_panel::Key::Alt('u')));
            let m = s.c.message().to_string();
            if m.starts_with("punched ") {
                s.stats.punches += 1;
                let image = std::fs::read(&out).unwrap();
                let back = novanc::tape::read_image(&image, Default::default()).unwrap();
                assert_eq!(back.text, text, "{m}");
            } else {
                assert!(
                    m.starts_with("punch refused") || m.starts_with("punch:"),
                    "{m}"
                );
                assert!(!out.exists(), "{m}");
            }
            let turned = if turn { "op DATA\n" } else { "" };
            return format!("{turned}type {}{code}\nkey Alt+u", out.display());
        }
        91 => {
            // SEARCH (stop 57): a line of the program typed in AUTO positions the next START
            // on the lathe loaded by hand (it runs the rest of one part from there); refused
            // with a cycle under way, or past the program's last block; on the Citizen,
            // AUTO's line stays for TARGET and FAULT.
            s.c.handle(PanelEvent::Op(OpMode::Auto));
            let n = rng.range(0, 40);
            s.c.handle(PanelEvent::Type(n.to_string()));
            s.fresh = true;
            let m = s.c.message().to_string();
            if m.starts_with("SEARCH line ") {
                s.stats.searches += 1;
                assert_eq!(s.c.desc().channels.len(), 1, "{m}");
            } else {
                assert!(
                    m.starts_with("SEARCH") || m.contains("AUTO takes no line"),
                    "{m}"
                );
            }
            return format!("op AUTO\ntype {n}");
        }
        92 => {
            // POS (stop 59): the centre's words set the selected channel's relative position
            // (shown in its REL column) and the counters; nothing moves, and a line POS cannot
            // read stays typed with the words it takes.
            use novanc_panel::Key;
            let mut line = String::new();
            if s.c.page() != Page::Pos {
                s.c.handle(PanelEvent::Press(Key::Ctrl('p')));
                line += "key Ctrl+P\n";
            }
            let l = [
                "X",
                "X12.5",
                "Z-3.5",
                "XZ",
                "ORIGIN",
                "PARTS 2",
                "TARGET 3",
                "Q7",
                "XZX",
                "JOG 300",
                "JOG RAPID",
                "JOG",
                "JOG 0",
            ][rng.range(0, 12) as usize];
            let posts =
                |c: &LatheConsole| -> Vec<[i64; 2]> { c.tips().into_iter().map(|t| t.0).collect() };
            let before = posts(&s.c);
            s.c.handle(PanelEvent::Type(l.into()));
            s.fresh = true;
            let m = s.c.message().to_string();
            line += &format!("type {l}");
            assert_eq!(posts(&s.c), before, "{line}: {m}");
            if let Err(e) = common::typed_line_kept_or_taken(l, s.c.entry(), &m) {
                panic!("{line}: {e}");
            }
            let rel = |axis: &str| -> f64 {
                let d = s.c.view().display;
                let row = (d.iter().rev())
                    .find(|r| r.starts_with(axis))
                    .expect("a POS row");
                row[1..]
                    .split_whitespace()
                    .nth(1)
                    .expect("REL")
                    .parse()
                    .expect("a number")
            };
            s.stats.rel_set += u64::from(m.starts_with("relative "));
            match (l, m.as_str()) {
                ("X12.5", "relative X preset to 12.500") => assert_eq!(rel("X"), 12.5, "{line}"),
                ("Z-3.5", "relative Z preset to -3.500") => assert_eq!(rel("Z"), -3.5, "{line}"),
                ("XZ" | "ORIGIN", "relative X Z zeroed") | ("X", "relative X preset to 0.000") => {
                    assert_eq!(rel("X"), 0.0, "{line}")
                }
                ("PARTS 2", "parts 2") => assert_eq!(s.c.counters().parts, 2, "{line}"),
                ("TARGET 3", _) if m == "part target 3" || m.starts_with("target 3: ") => {}
                ("Q7" | "XZX", _) if s.c.entry() == l && !m.is_empty() => {}
                // JOG (stop 60): the selected channel's jog feed, said; nothing moves.
                ("JOG 300", _) if m.ends_with(" jog feed 300 mm/min") => {}
                ("JOG RAPID", _) if m.contains(" rapid jog: ") => {}
                ("JOG", _) if m.contains(" jog feed ") => {}
                ("JOG 0", _) if s.c.entry() == l && m.starts_with("JOG refused") => {}
                _ => panic!("{line}: {m}"),
            }
            return line;
        }
        100 => {
            let ch = s.c.selected();
            home(s, ch);
            return "home".into();
        }
        101 => {
            // A restart (stop 61): the console closed, or dropped as a kill -9 leaves it, and
            // opened again on the same state. A post at rest and known is where it was; one
            // that moved at the kill, or owed HOME before, owes it now.
            let before = s.c.cycle().axes();
            let moving: Vec<bool> = (s.c.cycle().channels().iter())
                .map(|c| {
                    let st = &c.status;
                    st.moving
                        || (st.job.is_some() && !st.idle)
                        || c.sync.as_ref().is_some_and(|v| v.progressing)
                })
                .collect();
            let owed = s.c.home_owed().to_vec();
            let kill = rng.range(0, 1) == 1;
            let desc = s.c.desc().clone();
            let dir = s.dir.clone();
            let c = std::mem::replace(
                &mut s.c,
                // A stand-in while the console is gone: the state directory is the sequence's.
                LatheConsole::open(desc.clone(), &dir.join("standin"), ROWS, COLS, None)
                    .unwrap()
                    .0,
            );
            if kill {
                drop(c);
            } else {
                let _ = c.close(None);
            }
            s.c = LatheConsole::open(desc, &dir, ROWS, COLS, None).unwrap().0;
            s.stats.restarts += 1;
            let after = s.c.cycle().axes();
            for ch in 0..before.len() {
                let now = s.c.home_owed()[ch];
                if moving[ch] || owed[ch] {
                    assert!(
                        now,
                        "restart: CH{} moved (or owed HOME) and does not owe it",
                        ch + 1
                    );
                } else {
                    assert!(!now, "restart: CH{} at rest owes HOME", ch + 1);
                    assert_eq!(
                        after[ch],
                        before[ch],
                        "restart: CH{} is not where it was",
                        ch + 1
                    );
                }
            }
            let mut said = String::new();
            if s.c.home_owed().iter().any(|&o| o) {
                s.stats.owed += 1;
                assert!(
                    s.c.message().contains("HOME, Alt+0"),
                    "restart: {}",
                    s.c.message()
                );
                // Half the time the operator makes each owed return at once (else the
                // sequence goes on with AUTO refused until a HOME step makes them).
                if rng.range(0, 1) == 1 {
                    let owing: Vec<usize> =
                        (0..before.len()).filter(|&c| s.c.home_owed()[c]).collect();
                    for ch in owing {
                        s.c.handle(PanelEvent::Channel(ch));
                        home(s, ch);
                        said += &format!(" channel {} home wait", ch + 1);
                    }
                }
            }
            s.fresh = true;
            return format!(
                "{}{said}",
                if kill {
                    "(killed, opened again)"
                } else {
                    "(closed, opened again)"
                }
            );
        }
        64 | 67..=79 => {
            let ms = [1, 7, 50, 400, 2_000, 9_000][rng.range(0, 5) as usize];
            advance(s, ms * 1_000_000);
            return format!("wait ms {ms}");
        }
        _ => {
            // Run to rest, a slice at a time so the frozen-channel check sees every slice.
            for _ in 0..200 {
                advance(s, 500_000_000);
                if s.c.view().channels.iter().all(|c| c.state != "RUN") {
                    break;
                }
            }
            return "wait".into();
        }
    };
    let line = novanc::console::script_line(&ev);
    s.fresh = true;
    let typed = match &ev {
        PanelEvent::Type(l) => Some(l.clone()),
        _ => None,
    };
    let (sel, plus) = (s.c.selected(), ev == PanelEvent::PlusInput);
    let (op, left) = (s.c.mode(), s.c.entry().to_string());
    let target = match ev {
        PanelEvent::Target(n) => Some(n),
        _ => None,
    };
    s.c.handle(ev);
    if let Some(n) = target {
        // With no cycle under way (none loaded, or the batch over) a target is taken: it
        // begins a new batch (stop 52: a finished batch refused every new target, while START
        // said to set one). During a cycle it may be refused where it would strand a work.
        let m = s.c.message();
        let under_way = s.c.cycle().loaded() && !s.c.cycle().is_over() && !s.c.cycle().mdi;
        assert!(
            m == format!("part target {n}") || under_way && m.starts_with(&format!("target {n}: ")),
            "{line}: {m} (counts {:?})",
            s.counts
        );
    }
    // A turn to another position clears a line left typed, and says so (stop 49): never in
    // silence.
    if s.c.mode() != op && !left.trim().is_empty() {
        let m = s.c.message();
        assert!(
            s.c.entry().is_empty() && m.contains("is cleared"),
            "the turn from {op:?} took '{left}' without a word: {m}\n{}",
            s.c.frame_text()
        );
        s.stats.turns_cleared += 1;
    }
    if let Some(l) = typed {
        if let Err(e) = common::typed_line_kept_or_taken(&l, s.c.entry(), s.c.message()) {
            panic!("{e}\n{}", s.c.frame_text());
        }
    }
    // The keypad's +INPUT never turns the channel selector (the keyboard's Tab may).
    assert!(
        !plus || s.c.selected() == sel,
        "plusinput turned the channel"
    );
    line
}

/// A lathe to run the sequences on: its description and the program stored for each channel
/// before the console opens (`None`: the stores' defaults, the Citizen's samples).
struct Machine {
    desc: LatheDesc,
    programs: Option<Vec<Program>>,
    tag: &'static str,
}

fn citizen() -> Machine {
    Machine {
        desc: LatheDesc::citizen(),
        programs: None,
        tag: "citizen",
    }
}

/// A one-channel lathe in Fanuc's dialect that the operator loads by hand, with a shop program
/// that works no chuck (docs/lathe.md "Loading by hand").
fn by_hand() -> Machine {
    let desc = match novanc::lathe::desc::parse(
        "machine byhand\nkind lathe\npulse 0.001\ntick 100\ndialect fanuc\n\
         loading manual\ng28 alone all\nremap M31 modalgroup=10 ngc=chip_on\n\
         remap M33 modalgroup=10 ngc=chip_off\nchannel PATH-1\nx travel 0 100 rapid 12000 accel 3000\n\
         z travel -100 100 rapid 15000 accel 3000\nspindle max 4000 accel 4000 encoder 1024\n\
         tool 1 radius 0.4 tip 3\ntool 2 radius 0 tip 8\n",
    ) {
        Ok(novanc::lathe::desc::MachineDesc::Lathe(d)) => d,
        other => panic!("{other:?}"),
    };
    // The chip auger's subroutines (a Haas's M31 and M33): a simulated lathe has no auger,
    // and a subroutine that moves the slide back and forth by nothing is read all the same.
    let subs = common::temp_dir("lathe-seq-chip");
    for (name, body) in [("chip_on", "G0 U0 W0"), ("chip_off", "")] {
        let text = format!("o<{name}> sub\n{body}\no<{name}> endsub\n");
        std::fs::write(subs.join(format!("{name}.ngc")), text).unwrap();
    }
    let mut desc = desc;
    desc.channels[0].subroutines.push(subs);
    // A G71 of type II (its profile's first line names Z) roughs a groove: RESET, E-STOP and
    // the switches meet the cycle inside its pocket too.
    let text = "O1000\nG28\nM31\nG21 G40 G80 G95\nG28 U0 W0\nT0101\nG96 S120 M03\nM08\n\
                G0 X42. Z2.\nG71 U2. R0.5\nG71 P10 Q20 U0.2 W0.1 F0.3\nN10 G0 X20. Z2.\n\
                G1 Z-5.\nX34.\nX26. Z-9.\nZ-13.\nX34. Z-16.\nN20 X42.\n\
                G0 X42. Z2.\nG1 Z-20. F0.2\nX46.\nG0 Z2.\nG28 U0 W0\nT0202\nG97 S800\n\
                G0 X0 Z5.\nG1 Z-10. F0.1\nG0 Z5.\nG28 U0 W0\nM09 M05\nM33\nM30\n";
    Machine {
        desc,
        programs: Some(vec![Program {
            name: "O1000.NC".into(),
            text: text.into(),
            dialect: None,
        }]),
        tag: "byhand",
    }
}

/// At the end of a sequence: the stores, reopened, hold exactly what the console held.
fn stores_hold_the_console(s: Seq, m: &Machine, what: &str) {
    let n = m.desc.channels.len();
    let programs = s.c.programs().to_vec();
    let mdi: Vec<Vec<String>> = (0..n).map(|ch| s.c.mdi_lines(ch).to_vec()).collect();
    let counter = s.c.counter().clone();
    let pointers: Vec<usize> = (0..n).map(|ch| s.c.pointer(ch)).collect();
    let jogs = s.c.jogs();
    let dir = s.dir.clone();
    drop(s);
    let o = LatheStore::open(&dir, &m.desc).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(o.programs, programs, "{what}: the stored programs");
    assert_eq!(o.mdi, mdi, "{what}: the stored MDI buffers");
    assert_eq!(o.counter, counter, "{what}: the stored part counter");
    assert_eq!(o.pointers, pointers, "{what}: the stored editor pointers");
    assert_eq!(o.jogs, jogs, "{what}: the stored jog feeds");
}

fn run_on(m: &Machine, n: u64, steps: usize) -> Stats {
    let mut total = Stats::default();
    let channels = m.desc.channels.len();
    for seed in 0..n {
        let dir = common::temp_dir(&format!("lathe-seq-{}-{seed}", m.tag));
        if let Some(ps) = &m.programs {
            let mut o = LatheStore::open(&dir, &m.desc).unwrap_or_else(|e| panic!("{e}"));
            for (ch, p) in ps.iter().enumerate() {
                o.store
                    .save_program(ch, p)
                    .unwrap_or_else(|e| panic!("{e}"));
            }
        }
        let (c, _) = LatheConsole::open(m.desc.clone(), &dir, ROWS, COLS, None).unwrap();
        let mut s = Seq {
            c,
            dir: dir.clone(),
            counts: vec![0; channels],
            stats: Stats::default(),
            fresh: false,
        };
        let mut rng = Rng::new(0x1a7e ^ seed.wrapping_mul(0x9E37_79B9));
        let mut log = Vec::new();
        for i in 0..steps {
            let what = step(&mut s, &mut rng);
            log.push(what);
            let ctx = format!("{} seed {seed} step {i}: {}", m.tag, log.join(" | "));
            check(&mut s, &ctx);
            s.stats.steps += 1;
        }
        s.stats.parts += s.c.counter().counts[m.desc.unloader] as u64;
        if s.c.view().channels.iter().all(|c| c.state == "DONE") {
            s.stats.batches_done += 1;
        }
        total.steps += s.stats.steps;
        total.parts += s.stats.parts;
        total.faults += s.stats.faults;
        total.estops += s.stats.estops;
        total.handovers_seen += s.stats.handovers_seen;
        total.batches_done += s.stats.batches_done;
        total.jogs += s.stats.jogs;
        total.locked += s.stats.locked;
        total.turns_cleared += s.stats.turns_cleared;
        total.reads += s.stats.reads;
        total.punches += s.stats.punches;
        total.searches += s.stats.searches;
        total.rel_set += s.stats.rel_set;
        total.homes += s.stats.homes;
        total.restarts += s.stats.restarts;
        total.owed += s.stats.owed;
        stores_hold_the_console(s, m, &format!("{} seed {seed}", m.tag));
        let _ = std::fs::remove_dir_all(dir);
    }
    total
}

fn run(n: u64, steps: usize) -> Stats {
    run_on(&citizen(), n, steps)
}

fn count() -> u64 {
    std::env::var("NOVANC_LATHE_SEQUENCES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(40)
}

#[test]
fn random_operator_sequences_keep_the_lathe_invariants() {
    let st = run(count(), 40);
    // The sequences must reach what they are meant to test.
    assert!(
        st.parts > 0 && st.faults > 0 && st.estops > 0 && st.jogs > 0 && st.turns_cleared > 0,
        "parts {} faults {} estops {} jogs {} turns that cleared a line {}",
        st.parts,
        st.faults,
        st.estops,
        st.jogs,
        st.turns_cleared
    );
}

#[test]
fn random_operator_sequences_keep_the_invariants_on_a_lathe_loaded_by_hand() {
    let st = run_on(&by_hand(), count() / 2, 40);
    assert!(
        st.parts > 0 && st.faults > 0 && st.estops > 0,
        "parts {} faults {} estops {}",
        st.parts,
        st.faults,
        st.estops
    );
}

#[test]
#[ignore]
fn many_random_operator_sequences() {
    for m in [citizen(), by_hand()] {
        let t = std::time::Instant::now();
        let st = run_on(&m, count(), 60);
        println!(
            "{}: {} sequences, {} steps, {} parts delivered, {} faults, {} E-STOPs, {} handovers seen mid-way, {} batches finished, {} manual moves, {} steps under MACHINE LOCK, {} turns that cleared a typed line, {} program files read, {} punched, {} SEARCH points, {} relative positions set on POS, {} HOMEs made, {} restarts ({} owing HOME), {:.1} s",
            m.tag,
            count(),
            st.steps,
            st.parts,
            st.faults,
            st.estops,
            st.handovers_seen,
            st.batches_done,
            st.jogs,
            st.locked,
            st.turns_cleared,
            st.reads,
            st.punches,
            st.searches,
            st.rel_set,
            st.homes,
            st.restarts,
            st.owed,
            t.elapsed().as_secs_f64()
        );
    }
}
