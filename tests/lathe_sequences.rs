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
//! - the stores hold exactly the console's programs and part counter.
//!
//! CI runs `NOVANC_LATHE_SEQUENCES` sequences (default 40) of 40 steps. The long run:
//! `NOVANC_LATHE_SEQUENCES=2000 cargo test --release --test lathe_sequences -- --ignored --nocapture`.

mod common;

use novanc::lathe::console::events::Mode;
use novanc::lathe::console::LatheConsole;
use novanc::lathe::desc::LatheDesc;
use novanc::panel_model::PanelEvent;
use novanc::pulse_core::testkit::Rng;

const ROWS: usize = 12;
const COLS: usize = 40;

const MDI_LINES: [&str; 14] = [
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
];
const EDIT_LINES: [&str; 6] = ["L", "3L", "-2L", "SM10", "SNOSUCHTEXT", "2Y"];
const OFS_LINES: [&str; 4] = ["T1 X0.01", "T2 Z-0.005", "T9 X1", "T1 P12"];

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
}

fn check(s: &mut Seq, what: &str) {
    let v = s.c.view();
    assert_eq!(v.display.len(), ROWS, "{what}");
    assert!(
        v.display.iter().all(|l| l.chars().count() == COLS),
        "{what}: {:?}",
        v.display
    );
    assert_eq!(v.summary.len(), 3, "{what}");
    assert!(
        v.summary.iter().all(|l| l.chars().count() == COLS),
        "{what}: {:?}",
        v.summary
    );
    let desc = s.c.desc().clone();
    let target = s.c.counter().target;
    // Stores.
    let dir = s.dir.join("lathe-citizen");
    let parts = std::fs::read_to_string(dir.join("parts")).unwrap_or_default();
    let counts = &s.c.counter().counts;
    if !parts.is_empty() {
        let want = format!(
            "target {target}\ncounts {}\n",
            counts
                .iter()
                .map(|c| c.to_string())
                .collect::<Vec<_>>()
                .join(" ")
        );
        assert_eq!(parts, want, "{what}: the stored part counter");
    }
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
    // The message line says what the machine does only while it does it: never "runs" or
    // "START" with every channel at rest, never a feed hold or an E-STOP that is not there
    // (the acknowledgement of an action that has not yet had a tick is the one exception).
    let m = s.c.message().to_string();
    let states: Vec<&str> = v.channels.iter().map(|c| c.state.as_str()).collect();
    let any = |w: &[&str]| states.iter().any(|s| w.contains(s));
    if !s.fresh {
        if m == "START" || m == "cycle start" || m.starts_with("MDI CH") && m.ends_with(" runs") {
            assert!(
                any(&["RUN", "WAIT", "STOP"]),
                "{what}: '{m}' with {states:?}"
            );
        }
        if m.starts_with("STOP: feed hold") {
            assert!(any(&["HOLD"]), "{what}: '{m}' with {states:?}");
        }
        if m.starts_with("E-STOP") {
            assert!(any(&["ESTOP"]), "{what}: '{m}' with {states:?}");
        }
    }
    let Some(l) = s.c.cycle() else { return };
    let chans = l.channels();
    for (ch, c) in chans.iter().enumerate() {
        let pos = [c.status.pos[0], c.status.pos[2]];
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
    let moving: Vec<bool> = s.c.cycle().map_or(Vec::new(), |l| {
        l.channels().iter().map(|c| c.status.moving).collect()
    });
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

fn step(s: &mut Seq, rng: &mut Rng) -> String {
    let ev = match rng.range(0, 99) {
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
                rng.range(0, 2) as usize,
                ["tool breakage", "failed supply", "operator"][rng.range(0, 2) as usize].into(),
            )
        }
        38..=45 => PanelEvent::Channel(rng.range(0, 2) as usize),
        46..=47 => PanelEvent::Press(novanc_panel::Key::Tab),
        48..=49 => PanelEvent::Target(rng.range(1, 4) as u32),
        50..=53 => [Mode::Auto, Mode::Mdi, Mode::Data, Mode::Ofs][rng.range(0, 3) as usize].event(),
        54..=57 => PanelEvent::Type(MDI_LINES[rng.below(MDI_LINES.len())].into()),
        58..=60 => PanelEvent::Type(EDIT_LINES[rng.range(0, 5) as usize].into()),
        61 => PanelEvent::Press(novanc_panel::Key::F(8)),
        65 => PanelEvent::Type(OFS_LINES[rng.range(0, 3) as usize].into()),
        66 => PanelEvent::Override([0, 50, 100, 150][rng.range(0, 3) as usize]),
        62..=63 => PanelEvent::OptionalStop(rng.range(0, 1) == 1),
        80..=81 => {
            // Keys of the one key map, the centre's own among them: each acts or says that it
            // does nothing here (no key is lost in silence).
            use novanc_panel::Key;
            let keys = [
                Key::Alt('='),
                Key::Alt('-'),
                Key::Alt('0'),
                Key::Left,
                Key::F(2),
                Key::Alt('d'),
                Key::Alt('o'),
            ];
            let k = keys[rng.below(keys.len())];
            let silent = !matches!(k, Key::Alt('=' | '-' | 'o'));
            let line = format!("key {}", novanc::console::keys::key_name(k));
            s.fresh = true;
            s.c.handle(PanelEvent::Press(k));
            if silent {
                assert!(
                    s.c.message().contains("does nothing on the lathe console"),
                    "{line}: {}",
                    s.c.message()
                );
            }
            return line;
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
                if s.c.cycle().is_none() || s.c.view().channels.iter().all(|c| c.state != "RUN") {
                    break;
                }
            }
            return "wait".into();
        }
    };
    let line = novanc::console::script_line(&ev);
    s.fresh = true;
    s.c.handle(ev);
    line
}

fn run(n: u64, steps: usize) -> Stats {
    let mut total = Stats::default();
    for seed in 0..n {
        let dir = common::temp_dir(&format!("lathe-seq-{seed}"));
        let (c, _) = LatheConsole::open(LatheDesc::citizen(), &dir, ROWS, COLS, None).unwrap();
        let mut s = Seq {
            c,
            dir: dir.clone(),
            counts: vec![0; 3],
            stats: Stats::default(),
            fresh: false,
        };
        let mut rng = Rng::new(0x1a7e ^ seed.wrapping_mul(0x9E37_79B9));
        let mut log = Vec::new();
        for i in 0..steps {
            let what = step(&mut s, &mut rng);
            log.push(what);
            let ctx = format!("seed {seed} step {i}: {}", log.join(" | "));
            check(&mut s, &ctx);
            s.stats.steps += 1;
        }
        s.stats.parts += s.c.counter().counts[2] as u64;
        if s.c.view().channels.iter().all(|c| c.state == "DONE") {
            s.stats.batches_done += 1;
        }
        total.steps += s.stats.steps;
        total.parts += s.stats.parts;
        total.faults += s.stats.faults;
        total.estops += s.stats.estops;
        total.handovers_seen += s.stats.handovers_seen;
        total.batches_done += s.stats.batches_done;
        drop(s);
        let _ = std::fs::remove_dir_all(dir);
    }
    total
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
    let t = std::time::Instant::now();
    let st = run(count(), 60);
    println!(
        "{} sequences, {} steps, {} parts delivered, {} faults, {} E-STOPs, {} handovers seen mid-way, {} batches finished, {:.1} s",
        count(),
        st.steps,
        st.parts,
        st.faults,
        st.estops,
        st.handovers_seen,
        st.batches_done,
        t.elapsed().as_secs_f64()
    );
}
