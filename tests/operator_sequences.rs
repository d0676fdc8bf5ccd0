//! A model-based test of operator sequences: random sequences of panel events (START, STOP,
//! RESET, E-STOP, mode changes, SINGLE BLOCK, jog, STEP and HANDLE between blocks, SEARCH to
//! random statements, MDI runs, tool revisions, the help screen, waits, PROGRAM READ and TOOL
//! DATA READ of good and corrupted tape images, whole or abandoned) driven through the
//! `Console` the terminal uses, in virtual time.
//!
//! Invariants:
//! - at every block end the machine is on that block's programmed end point (the pulse core's
//!   audit; manual moves are undone by the return before the next block, so no shift is kept);
//! - no block takes the tool tip down below the lowest tip Z the programs run command (one
//!   session in three runs Table B in ISO G-code and MDI G-code lines: `common/seq_gcode.rs`);
//! - every pulse is recorded exactly once: the recorded pulses add up to the position;
//! - E-STOP and an alarm refuse START; one RESET clears them; the lamps agree;
//! - a tape read stores exactly what the codec decodes, or nothing: an error leaves program
//!   memory and the tool data unchanged with the ALARM lamp lit, and so does abandoning it;
//! - a stopped run the operator moved by hand says so on its run page;
//! - the screen is a function of the state (issue 23): after every step every lamp and the
//!   state line agree with the status snapshot, and no message describes a state the machine
//!   has left (running, held, returning, waiting for START, a START ignored, an e-stop);
//! - after an MDI G-code move (G-code sessions also type G91/G90, G92/G92.1, G43/G49 and G0
//!   lines in MDI, each run at once), the machine stands where the interpreter's state before
//!   the line says it goes; a refused one moves nothing and changes no mode; after an MDI
//!   G38.3 probe the interpreter reads on from where the machine stopped;
//! - the display is always rows × at most cols; nothing panics;
//! - the overrides and switches (issue 23: rapid override, spindle override, DRY RUN, MACHINE
//!   LOCK, Z NEGLECT, by their keys and script words) are random steps too: with MACHINE LOCK
//!   on all through a step the axes (`machine_pos`) do not move, with Z NEGLECT Z does not; the
//!   recorded pulses add up to where the axes are, never to the program position; a rapid, a
//!   jog or a return is never faster than its percentage of its full speed (F0: the F0 rate)
//!   once the ramp after a change has had its time; the spindle turns at programmed ×
//!   override; the state line shows each switch exactly when the status has it on.
//! - restart with position memory: the console is dropped (as if it died) and reopened on the
//!   same state directory; at rest it comes back with its position and tool; one that died
//!   while the axes moved says the position is not known, and AUTO and MDI START run nothing
//!   until HOME has brought the axes to machine zero (HOME is a random step too);
//! - OFS MEASURE (a named work offset, or the length of the tool in the spindle on its row):
//!   the work position then reads the value typed (POS's WORK Z for a length); a refused one
//!   changes nothing;
//! - E-STOP in every state (idle, in a block, feed hold, between blocks, jog or HOME, the
//!   return after an intervention, a tap, a tape read, E-STOP itself; the test fails if one is
//!   never met): the run is abandoned at once, RUN 0, spindle stopped, the reader stopped, and
//!   no axis moves after it;
//! - STOP inside a tap (the steps take a run into a G84/TAP): no hold in the hole; the hold
//!   comes with the tap back out at R and the spindle forward.
//! - the Fanuc dialect (one G-code session in two: Table B and the MDI lines with a decimal
//!   point on every length, `seq_gcode::fanuc_text`, under every invariant above): a MACRO
//!   page INPUT is taken only with the machine at rest, and in LinuxCNC's dialect never; a
//!   #500-#999 it set is kept across every restart.
//!
//! One session in four runs on the error-proportional interpolator.
//!
//! CI runs `NOVANC_SEQUENCES` sequences (default 200). The long run:
//! `NOVANC_SEQUENCES=10000 cargo test --release --test operator_sequences -- --ignored`.

mod common;
#[path = "common/seq_gcode.rs"]
mod seq_gcode;
#[path = "common/seq_stats.rs"]
mod seq_stats;

use common::temp_dir;
use novanc::block::MAX_AXES;
use novanc::console::keys::parse_key;
use novanc::console::{Console, ConsoleConfig};
use novanc::gcode::state::system_base;
use novanc::panel_model::{OpMode, PanelEvent as E};
use novanc::pulse_core::testkit::Rng;
use novanc::pulse_core::ClockMode;
use novanc::record::{Event, EventSink};
use novanc::settings::{AxisKind, Dialect, Interpolator, Remap};
use novanc::tape::{self, ReadOptions};
use novanc::tooldata::format_record;
use seq_stats::{count, run_many, Stats};
use std::path::PathBuf;
use std::sync::mpsc::Receiver;

/// MDI programs and the lowest tool-tip Z each commands, mm.
const MDI: [(&str, f64); 6] = [
    ("DRL, 105/DP20, FR60/(220, 20, -450)", -470.0),
    ("GO, 500, 300, -200", -200.0),
    ("GD, 5, -5, 0", 0.0),
    ("CL", 0.0),
    ("DRL, 106/DP10/DA1, P2", -465.0),
    (
        "P11 = (300, 300)*C11 = P11, R20*MIL, 404/DP3, LFT/DA1, C11",
        -453.0,
    ),
];

/// The rapid override in the recording: every `/nc/position` speed during a rapid block (and
/// any jog or return after it, slower still) is at most the rapid rate's share, or the F0
/// rate, once the ramp after an override change has had its time.
#[derive(Default)]
struct RapidSpeeds {
    /// The last block read is a rapid.
    in_rapid: bool,
    /// The rapid override in force and when it last changed, ns.
    pct: Option<u32>,
    changed_ns: u64,
    /// The first speed over its cap.
    broken: Option<String>,
    /// Speeds checked.
    checked: u64,
}

impl RapidSpeeds {
    fn see(&mut self, ev: &Event) {
        let s = novanc::settings::MachineSettings::default();
        match ev {
            Event::Block { text, .. } => self.in_rapid = text.contains(" G00"),
            Event::State { t_ns, switches, .. } if self.pct != Some(switches.rapid_override) => {
                self.pct = Some(switches.rapid_override);
                self.changed_ns = *t_ns;
            }
            Event::Position {
                t_ns, speed_mm_min, ..
            } if self.in_rapid && self.broken.is_none() => {
                let ramp_ns =
                    (s.rapid_mm_min / 60.0 / s.accel_mm_s2 * 1e9) as u64 + s.ncbr_period_ns;
                let pct = self.pct.unwrap_or(100);
                if *t_ns < self.changed_ns + ramp_ns {
                    return;
                }
                let cap = match pct {
                    0 => s.rapid_f0_mm_min,
                    p => s.rapid_mm_min * f64::from(p) / 100.0,
                };
                self.checked += 1;
                if *speed_mm_min > cap * 1.0001 {
                    self.broken = Some(format!(
                        "recorded speed {speed_mm_min} mm/min at {t_ns} ns in a rapid with the rapid override at {pct} %: more than {cap}"
                    ));
                }
            }
            _ => {}
        }
    }
}

/// The lowest tip Z Table B commands (the BOR: -450 - 35), mm.
const TABLE_B_LOW: f64 = -485.0;

struct Session {
    c: Console,
    /// Where the session's events go; the test sends its markers here too.
    sink: EventSink,
    /// The net recorded pulses per axis at each marker, from the thread reading the events,
    /// with the first recorded speed that broke the rapid override and the speeds checked.
    counts: Receiver<([i64; MAX_AXES], Option<String>, u64)>,
    markers: u64,
    rng: Rng,
    lowest_mm: f64,
    log: Vec<String>,
    stats: Stats,
    /// Where the session's tape images are written.
    tapes: PathBuf,
    /// The session runs Table B in G-code (`seq_gcode`).
    gcode: bool,
    /// On the error-proportional interpolator.
    ep: bool,
    /// In the Fanuc dialect (one G-code session in two): Table B and the MDI lines with a
    /// decimal point on every length, and the MACRO page takes its writes.
    fanuc: bool,
    /// The machine has a trunnion table, B and C, and a chip conveyor whose M31 and M33 its
    /// description remaps (the G-code sessions in LinuxCNC's dialect on the DDA).
    trunnion: bool,
    /// The #500-#999 the MACRO page set, and their values: kept across a restart.
    kept: std::collections::BTreeMap<usize, f64>,
    /// Machine time of the last rapid override change, ns (the ramp to the new speed takes
    /// its time).
    rapid_changed_ns: u64,
    /// The state directory (a restart reopens it).
    dir: PathBuf,
    /// The console was restarted after it died while the axes moved: AUTO and MDI are
    /// refused until a reference return has brought the axes to machine zero.
    home_owed: bool,
    /// A HOME was accepted since then.
    home_pressed: bool,
    /// What the positions restored at restarts add to the recorded pulses (a restart sets the
    /// position without pulses).
    pos_offset: [i64; MAX_AXES],
}

/// The machine states E-STOP is pressed in (`Stats::estop_states`, one bit each): every one
/// must be met, and in every one E-STOP stops everything and abandons the run.
const ESTOP_STATES: [&str; 9] = [
    "idle",
    "in a block",
    "feed hold",
    "between blocks, waiting for START",
    "manual motion (jog or HOME)",
    "return after a manual intervention",
    "in a tap",
    "reading a tape",
    "E-STOP in force",
];

/// The console of a session on `dir`: virtual time, the session's event sink, the pulse
/// core's audit on (the same at a restart).
fn console_on(
    dir: &std::path::Path,
    ep: bool,
    fanuc: bool,
    trunnion: bool,
    sink: &EventSink,
) -> Console {
    let mut cfg = ConsoleConfig::new(dir.to_path_buf());
    cfg.clock = ClockMode::Virtual;
    if trunnion {
        // A trunnion table (stop 53): B tilting within ±120°, C turning wrapped.
        let s = &mut cfg.settings;
        s.axis_kinds[4] = AxisKind::Rotary { wrap: false };
        s.travel_min_mm[4] = -120.0;
        s.travel_max_mm[4] = 120.0;
        s.axis_kinds[5] = AxisKind::Rotary { wrap: true };
        // And a chip conveyor (stop 55): M31 and M33 remapped to subroutines of the state
        // directory that set and clear output 1.
        s.remap_m = vec![Remap::new(31, "chip_on"), Remap::new(33, "chip_off")];
        let subs = dir.join("subroutines");
        std::fs::create_dir_all(&subs).unwrap();
        for (name, m) in [("chip_on", 64), ("chip_off", 65)] {
            let text = format!("o<{name}> sub\nM{m} P1\no<{name}> endsub\nM2\n");
            std::fs::write(subs.join(format!("{name}.ngc")), text).unwrap();
        }
    }
    if ep {
        cfg.settings.interpolator = Interpolator::ErrorProportional;
    }
    if fanuc {
        cfg.settings.dialect = Dialect::Fanuc;
    }
    cfg.sink = Some(sink.clone());
    let c = Console::open(cfg).unwrap().0;
    c.core().set_audit(true);
    c
}

impl Session {
    fn open(seed: u64) -> Session {
        // Room for bursts while this machine is loaded: a full queue drops (and says so).
        let (tx, rx) = std::sync::mpsc::sync_channel(1 << 17);
        let (ctx, counts) = std::sync::mpsc::channel();
        std::thread::spawn(move || {
            let mut n = [0i64; MAX_AXES];
            let mut speeds = RapidSpeeds::default();
            for ev in rx {
                match ev {
                    Event::Pulses { axis, dir, t_ns } => {
                        n[axis as usize] += dir as i64 * t_ns.len() as i64;
                    }
                    Event::PanelEvent { event, .. } if event.starts_with("#marker") => {
                        let _ = ctx.send((n, speeds.broken.take(), speeds.checked));
                    }
                    ev => speeds.see(&ev),
                }
            }
        });
        let sink = EventSink::new(tx);
        let dir = temp_dir("seq");
        // One session in four on the error-proportional interpolator (issue 12): the same
        // invariants hold whichever distributes the pulses.
        let ep = seed % 4 == 1;
        let gcode = seed.is_multiple_of(3);
        let fanuc = gcode && seed.is_multiple_of(2);
        // The G-code sessions in LinuxCNC's dialect on the DDA run a machine with a trunnion
        // table: their MDI lines turn B and C too (the reader refuses them on the other
        // interpolator, as a random MDI line found).
        let trunnion = gcode && !fanuc && !ep;
        let c = console_on(&dir, ep, fanuc, trunnion, &sink);
        let mut s = Session {
            c,
            sink,
            counts,
            markers: 0,
            rng: Rng::new(seed),
            lowest_mm: TABLE_B_LOW,
            log: Vec::new(),
            stats: Stats::default(),
            tapes: temp_dir("seq-tapes"),
            gcode,
            ep,
            fanuc,
            trunnion,
            kept: Default::default(),
            rapid_changed_ns: 0,
            dir,
            home_owed: false,
            home_pressed: false,
            pos_offset: [0; MAX_AXES],
        };
        if gcode {
            let mut path =
                std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join(seq_gcode::PROGRAM);
            if fanuc {
                let text = std::fs::read_to_string(&path).unwrap();
                path = s.tapes.join("tableb.ngc");
                std::fs::write(&path, seq_gcode::fanuc_text(&text)).unwrap();
                s.stats.fanuc_sessions += 1;
            }
            s.key("Alt+4");
            s.key("F2");
            s.ev(E::Tape(path));
            s.key("F9");
            s.ev(E::Wait);
            assert_eq!(s.c.program_name(), "TABLEB.NGC", "{}", s.c.frame_text());
            // Back to DATA INPUT REVISE, where every session starts.
            s.key("F3");
            s.stats.gcode_sessions += 1;
        }
        s
    }

    /// The net recorded pulses per axis of every event sent so far: a marker goes through the
    /// same queue after them.
    fn recorded(&mut self) -> [i64; MAX_AXES] {
        self.markers += 1;
        let mut ev = Event::PanelEvent {
            t_ns: 0,
            event: format!("#marker {}", self.markers),
        };
        loop {
            match self.sink.try_send(ev) {
                Ok(()) => break,
                Err(back) => {
                    ev = back;
                    std::thread::sleep(std::time::Duration::from_micros(100));
                }
            }
        }
        let (n, broken, checked) = self
            .counts
            .recv()
            .unwrap_or(([i64::MIN; MAX_AXES], None, 0));
        if let Some(b) = broken {
            panic!("{b}");
        }
        self.stats.rapid_checks = checked;
        n
    }

    fn ev(&mut self, e: E) {
        self.log.push(format!("{e:?}"));
        if std::env::var_os("NOVANC_SEQUENCE_LOG").is_some() {
            let st = self.c.status();
            eprintln!(
                "{e:?}  -> pos {:?} tool {:?} run {} job {:?}",
                st.pos,
                st.tool,
                st.run,
                st.job.as_ref().map(|j| j.id)
            );
        }
        let typed = match &e {
            E::Type(l) => Some(l.clone()),
            _ => None,
        };
        self.c.handle(e);
        if let Some(l) = typed {
            let entry = self.c.view().entry;
            if let Err(e) = common::typed_line_kept_or_taken(&l, &entry, self.c.message()) {
                panic!("{e}\n{}", self.c.frame_text());
            }
        }
    }

    /// A key by name. E-STOP goes through [`Session::estop`]; START with a reference return
    /// owed runs nothing in AUTO, SINGLE BLOCK or MDI; an accepted HOME is noted.
    fn key(&mut self, name: &str) {
        if name == "F12" {
            return self.estop();
        }
        let runs = self.c.status().runs;
        let op = self.c.view().op_mode;
        let typed = self.c.view().entry;
        self.press(name);
        // A turn to another position clears the line typed, and says so (stop 49): never in
        // silence.
        if name.starts_with("Alt+")
            && name.len() == 5
            && self.c.view().op_mode != op
            && !typed.trim().is_empty()
        {
            let m = self.c.message();
            assert!(
                self.c.view().entry.is_empty() && m.contains("is cleared"),
                "the turn from {op:?} took '{typed}' without a word: {m}\n{}",
                self.c.frame_text()
            );
            self.stats.turns_cleared += 1;
        }
        if name == "F9"
            && self.home_owed
            && matches!(op, OpMode::Auto | OpMode::Single | OpMode::Mdi)
        {
            assert_eq!(
                self.c.status().runs,
                runs,
                "START ran a program with the reference return owed\n{}",
                self.c.frame_text()
            );
        }
        if name == "Alt+0"
            && (common::shows(&self.c, "HOME: reference return")
                || common::shows(&self.c, "reference return is made"))
        {
            self.home_pressed = true;
        }
    }

    fn press(&mut self, name: &str) {
        self.ev(E::Press(parse_key(name).unwrap()));
    }

    /// E-STOP, in whatever state the machine is: the state is noted; at once the run is
    /// abandoned, RUN is 0, the spindle stops, the tape reader stops, and nothing moves after.
    fn estop(&mut self) {
        let st = self.c.status().clone();
        let class = if st.estop {
            8
        } else if self.c.tape_reading() {
            7
        } else if st.switches.override_locked && st.run != 0 {
            6
        } else if st.job.as_ref().is_some_and(|j| j.returning) {
            5
        } else if st.hold {
            2
        } else if st.job.is_some() && st.run != 0 {
            1
        } else if st.job.is_some() {
            3
        } else if st.moving {
            4
        } else {
            0
        };
        self.stats.estop_states |= 1 << class;
        self.press("F12");
        let after = self.c.status().clone();
        let what = ESTOP_STATES[class];
        assert!(after.estop && self.c.view().lamps.estop, "E-STOP {what}");
        assert!(
            after.job.is_none() && after.run == 0 && !after.hold,
            "E-STOP {what} abandons the run: {after:?}"
        );
        assert_eq!(after.spindle, 0, "E-STOP {what} stops the spindle");
        assert!(
            !self.c.tape_reading(),
            "E-STOP {what} stops the tape reader"
        );
        self.ev(E::WaitMs(200));
        let later = self.c.status();
        assert_eq!(
            later.machine_pos, after.machine_pos,
            "E-STOP {what}: an axis moved after it"
        );
        assert!(!later.moving, "E-STOP {what}: still moving");
    }

    /// The console is dropped (as if it died) and reopened on the same state directory. A
    /// console at rest comes back with the position and tool it had and no reference return
    /// owed; one that died while the axes moved says the position is not known and refuses
    /// AUTO and MDI until HOME has brought the axes to machine zero.
    fn restart(&mut self) {
        let st = self.c.status().clone();
        let at_rest = st.idle && !st.moving && !self.c.tape_reading();
        let moving = st.moving || (st.job.is_some() && !st.idle);
        // The dying console lets go of the state directory before the new one opens it; a
        // stand-in on a directory of its own holds the place meanwhile.
        let mut spare = ConsoleConfig::new(temp_dir("seq-spare"));
        spare.clock = ClockMode::Virtual;
        let dead = std::mem::replace(&mut self.c, Console::open(spare).unwrap().0);
        drop(dead);
        self.c = console_on(&self.dir, self.ep, self.fanuc, self.trunnion, &self.sink);
        self.log.push("restart".into());
        self.stats.restarts += 1;
        let now = self.c.status().clone();
        let frame = self.c.frame_text();
        let owed = common::shows(&self.c, "the position is not known");
        if moving {
            assert!(owed, "a console that died moving asks for HOME\n{frame}");
            self.stats.restarts_moving += 1;
            self.home_owed = true;
            self.home_pressed = false;
        } else if at_rest {
            assert_eq!(
                now.machine_pos, st.machine_pos,
                "the position is kept\n{frame}"
            );
            assert_eq!(now.tool, st.tool, "the tool in the spindle is kept");
            assert_eq!(owed, self.home_owed, "HOME is owed only as before\n{frame}");
        }
        self.home_owed |= owed;
        // The macro variables #500-#999 the MACRO page set are kept (journaled).
        for (&n, &v) in &self.kept {
            assert_eq!(
                self.c.interp_state().params[n],
                v,
                "#{n} set on the MACRO page is kept across a restart"
            );
            self.stats.macro_kept += 1;
        }
        let rec = self.recorded();
        self.pos_offset = std::array::from_fn(|a| now.machine_pos[a] - rec[a]);
        if self.home_owed {
            for (op, what) in [("Alt+2", "AUTO"), ("Alt+3", "MDI")] {
                self.key(op);
                self.key("F9");
                assert!(
                    common::shows(&self.c, "START refused"),
                    "{what} START with HOME owed\n{}",
                    self.c.frame_text()
                );
            }
            if self.rng.range(0, 1) == 0 {
                self.home();
            }
        }
    }

    /// HOME: the reference return, Z first; sometimes E-STOP during it.
    fn home(&mut self) {
        let st = self.c.status().clone();
        if st.job.is_some() || st.estop {
            // RESET first, as the refusal says.
            self.key("F11");
        }
        let from = self.c.status().machine_pos;
        self.key("Alt+0");
        if !common::shows(&self.c, "HOME: reference return, Z first") {
            // Refused (MACHINE LOCK, an axis moving), or made at once at machine zero.
            return;
        }
        if from != [0; 3] && self.rng.range(0, 3) == 0 {
            let t = self.rng.range(1, 200) as u64;
            self.ev(E::WaitMs(t));
            self.estop();
            return;
        }
        self.ev(E::Wait);
        let st = self.c.status();
        if st.machine_pos == [0; 3] && st.job.is_none() && !st.moving {
            assert!(
                common::shows(&self.c, "reference return is made") || !self.home_owed,
                "{}",
                self.c.frame_text()
            );
            self.stats.homes += 1;
        }
    }

    /// STOP (or E-STOP) inside a tap: the run is taken to a tap in AUTO (waits until the
    /// overrides are held), then STOP: no hold in the hole; the hold comes once the tap is
    /// back out at R with the spindle forward.
    fn tap_stop(&mut self) {
        let st = self.c.status().clone();
        if st.estop || st.alarm.is_some() || self.home_owed {
            return;
        }
        if st.job.is_none() {
            self.key("Alt+2");
            self.key("F9");
        } else if st.run == 0 || st.hold || st.single_block {
            return;
        }
        for _ in 0..800 {
            let s = self.c.status();
            if s.switches.override_locked || s.run == 0 || s.hold || s.job.is_none() {
                break;
            }
            self.ev(E::WaitMs(250));
        }
        let st = self.c.status().clone();
        if !st.switches.override_locked || st.run == 0 || st.hold || st.single_block {
            return;
        }
        if self.rng.range(0, 3) == 0 {
            return self.estop();
        }
        // R: where the tap's feed in began or its feed out ends (the higher end of a feed
        // block of the tap); unknown at the spindle reversal.
        let r = st
            .executed
            .as_ref()
            .filter(|b| b.delta[2] != 0 && b.delta[0] == 0 && b.delta[1] == 0)
            .map(|b| b.end[2].max(b.end[2] - b.delta[2]));
        let z = st.pos[2];
        self.key("F10");
        let s = self.c.status().clone();
        assert!(
            s.hold_after_tap && !s.hold,
            "STOP in a tap holds only after it: {s:?}"
        );
        // The invariants hold in the deferral too (and `tap_holds` counts it).
        self.check();
        self.ev(E::Wait);
        let s = self.c.status().clone();
        assert!(
            s.hold,
            "the hold came once the tap was out\n{}",
            self.c.frame_text()
        );
        assert!(!s.switches.override_locked, "held out of the tap");
        assert!(
            s.spindle > 0
                && s.spindle == s.spindle_programmed * i64::from(s.switches.spindle_override) / 100,
            "held with the spindle forward: {} rpm",
            s.spindle
        );
        assert!(
            s.pos[2] >= z,
            "the tap came up, not down: Z {} from {z}",
            s.pos[2]
        );
        if let Some(r) = r {
            assert_eq!(s.pos[2], r, "held at R");
        }
        self.stats.tap_stops += 1;
    }

    /// OFS MEASURE, with the machine at rest and no run loaded: a work offset (G59, by name)
    /// set so that X and Y read the typed values here, or the length of the tool in the
    /// spindle set by its tip at a typed Z (its row must be the cursor's, else refused and
    /// nothing changes). Afterwards the work position reads what was typed.
    fn measure(&mut self) {
        let st = self.c.status().clone();
        if st.job.is_some() || st.moving || !st.idle || self.c.tape_reading() {
            return;
        }
        let mag = self.c.magazine();
        let offsets = self.c.work_offsets();
        self.key("Ctrl+O");
        if self.c.view().page != novanc::panel_model::Page::Ofs {
            self.key("Ctrl+O");
        }
        let s = self.c.settings().clone();
        let (vx, vy) = (self.rng.range(-200, 200), self.rng.range(-200, 200));
        // On a work offset row `MEASURE Z..` measures that row's system; a tool's length is
        // measured on a tool row.
        let work_rows = self.c.frame_text().starts_with("OFS WORK");
        let tool_row = self.rng.range(0, 1) == 0 && !work_rows;
        let line = if tool_row {
            format!("MEASURE Z{}", self.rng.range(-20, 80))
        } else {
            format!("MEASURE G59 X{vx} Y{vy}")
        };
        self.ev(E::Type(line.clone()));
        let said = self.c.frame_text();
        let refused = common::shows(&self.c, "refused");
        if refused {
            assert_eq!(self.c.magazine(), mag, "{line} refused changes no tool");
            assert_eq!(
                self.c.work_offsets(),
                offsets,
                "{line} refused changes no offset"
            );
        } else if tool_row {
            // POS's WORK Z: the tip in the work system in force reads the value.
            let want: f64 = line["MEASURE Z".len()..].parse().unwrap();
            self.key("Ctrl+P");
            let f = self.c.frame_text();
            let z = f
                .lines()
                .find(|l| l.starts_with("Z "))
                .and_then(|l| l.split_whitespace().nth(1))
                .and_then(|v| v.parse::<f64>().ok())
                .unwrap_or(f64::NAN);
            assert!(
                (z - want).abs() < 1e-3,
                "{line}: WORK Z reads {z}\n{f}\nafter the INPUT:\n{said}"
            );
            self.stats.measures += 1;
        } else {
            let zero = self.c.work_offsets().0[5];
            let g92 = self.c.interp_state().g92;
            for (a, v) in [(0, vx), (1, vy)] {
                let work = s.to_mm(st.pos[a]) - zero[a] - g92[a];
                assert!(
                    (work - v as f64).abs() < 1e-3,
                    "{line}: axis {a} reads {work}"
                );
            }
            self.stats.measures += 1;
        }
    }

    /// A jog key. With the machine at rest (no run, or a held one), a jog key in CONTINUOUS
    /// (a tap), STEP or HANDLE moves its axis by exactly one increment or not at all, and no
    /// other axis; in any other mode it moves nothing.
    fn manual_key(&mut self, name: &str) {
        let st = self.c.status().clone();
        let v = self.c.view();
        let at_rest = st.idle && !st.moving && (st.job.is_none() || st.hold);
        self.key(name);
        if !at_rest {
            return;
        }
        if self.c.status().moving && self.rng.range(0, 7) == 0 {
            // E-STOP during the jog.
            return self.estop();
        }
        self.ev(E::Wait);
        let axis = match name {
            "Left" | "Right" => 0,
            "Up" | "Down" => 1,
            // The handwheel's keys turn its selected axis (a rotary one on a trunnion).
            "Alt+." | "Alt+," => v.wheel.0.index(),
            _ => 2,
        };
        // The axes (a run under MACHINE LOCK or Z NEGLECT leaves the program position apart
        // from them until the next motion brings it back).
        let now = self.c.status().machine_pos;
        let moved: Vec<i64> = (0..MAX_AXES).map(|a| now[a] - st.machine_pos[a]).collect();
        // The arrows and pages are a page's cursor keys; the handwheel's keys, which no page
        // takes, turn the wheel in HANDLE and jog in CONTINUOUS and STEP whatever page is up
        // (a pendant's buttons do not follow the screen).
        let wheel_key = name.starts_with("Alt+");
        let manual = matches!(
            v.op_mode,
            OpMode::Continuous | OpMode::Step | OpMode::Handle
        ) && (wheel_key
            || matches!(
                v.page,
                novanc::panel_model::Page::Mode | novanc::panel_model::Page::Pos
            ));
        for (a, d) in moved.iter().enumerate() {
            if a == axis && manual {
                assert!(
                    *d == 0 || d.abs() == i64::from(v.wheel.1),
                    "{name} in {:?} moved {d} pulses, not one increment of {}",
                    v.op_mode,
                    v.wheel.1
                );
            } else {
                assert_eq!(*d, 0, "{name} in {:?} moved axis {a}", v.op_mode);
            }
        }
    }

    fn pick<'a>(&mut self, xs: &[&'a str]) -> &'a str {
        xs[self.rng.range(0, xs.len() as i64 - 1) as usize]
    }

    /// One random operator action.
    fn step(&mut self) {
        let r = self.rng.range(0, 106);
        match r {
            0..=11 => {
                let k = self.pick(&["Alt+2", "Alt+7", "Alt+3", "Alt+6", "Alt+5", "Alt+1"]);
                self.key(k)
            }
            12..=24 => {
                let before = self.c.status().clone();
                let tape_alarm = self.c.tape_alarm().is_some();
                self.key("F9");
                let after = self.c.status();
                if tape_alarm {
                    assert_eq!(after.runs, before.runs, "START acted with a tape alarm");
                }
                if before.estop || before.alarm.is_some() {
                    assert!(
                        after.job.is_none() || after.job == before.job,
                        "START acted with the ALARM lamp lit"
                    );
                }
            }
            25..=30 => self.key("F10"),
            31..=33 => {
                self.key("F11");
                let st = self.c.status();
                assert!(!st.estop && st.alarm.is_none() && st.job.is_none());
                assert!(!self.c.view().lamps.alarm, "one RESET clears the alarm");
            }
            34 => {
                if self.rng.range(0, 2) == 0 {
                    self.key("F12")
                } else {
                    self.intervene()
                }
            }
            35..=37 => {
                self.key("F8");
                let k = self.pick(&["F10", "F12", "F11", "F9", "x"]);
                self.key(k)
            }
            38..=51 => {
                let k = if self.trunnion && self.rng.chance(0.3) {
                    // The handwheel on a trunnion: its axis selector goes round X Y Z B C.
                    if self.rng.chance(0.4) {
                        self.key("Alt+a");
                    }
                    self.pick(&["Alt+.", "Alt+,"])
                } else {
                    self.pick(&["Left", "Right", "Up", "Down", "PgUp", "PgDn"])
                };
                self.manual_key(k);
            }
            52..=54 => {
                let k = self.pick(&["Alt+w", "Alt+=", "Alt+-"]);
                self.key(k)
            }
            55..=57 => self.intervene(),
            58..=66 => self.ev(E::Wait),
            67..=74 => {
                let t = self.rng.range(5, 20_000) as u64;
                self.ev(E::WaitMs(t))
            }
            75..=79 => {
                let n = self.rng.range(1, 110) as u32;
                self.ev(E::WaitBlock(n))
            }
            80..=85 => {
                // SEARCH to a random statement of Table B.
                self.key("Alt+4");
                self.key("F1");
                let what = if self.rng.range(0, 1) == 0 {
                    self.rng.range(0, 10).to_string()
                } else {
                    let words = if self.gcode {
                        seq_gcode::SEARCH
                    } else {
                        ["DRL, 105", "tap, 206", "PAT1", "BOR"]
                    };
                    self.pick(&words).to_string()
                };
                self.ev(E::Type(what));
                self.stats.searches += u64::from(self.c.frame_text().contains("AUTO starts at"));
            }
            86..=89 if self.gcode => {
                for _ in 0..self.rng.range(1, 4) {
                    self.mdi_gcode();
                }
            }
            86..=91 => {
                // An MDI program.
                let g = self.gcode && self.rng.range(0, 1) == 0;
                let (text, low) = if g {
                    seq_gcode::MDI[self.rng.range(0, 3) as usize]
                } else {
                    MDI[self.rng.range(0, MDI.len() as i64 - 1) as usize]
                };
                self.lowest_mm = self.lowest_mm.min(low);
                self.key("Alt+4");
                self.key("F7");
                let text = if g && self.fanuc {
                    seq_gcode::fanuc_text(text)
                } else {
                    text.to_string()
                };
                self.ev(E::Type(format!("-999L999KI{text}")));
                self.key("Alt+3");
            }
            92..=95 => {
                // A tool revision: a set length of one of the Table B tools.
                let t = self.rng.range(1, 5) as u32;
                let m = self.c.magazine();
                if let Some(r) = m.tools.get(t) {
                    let mut r = r.clone();
                    r.set_length = self.rng.range(100, 230) as f64;
                    let line = format!("T{t:02} {}", format_record(&r));
                    self.key("Alt+4");
                    self.key("F5");
                    let down = if t > 1 {
                        format!("{}L", t - 1)
                    } else {
                        String::new()
                    };
                    self.ev(E::Type(format!("-99L{down}KI{line}*")));
                }
            }
            96..=98 => self.page_action(),
            99 => self.switch_step(),
            100..=101 => self.tape_read(),
            102 => self.restart(),
            103 => self.home(),
            104 => self.tap_stop(),
            105 => self.measure(),
            _ => {
                // Junk on the data keys, in whatever mode.
                let k = self.pick(&["Q", "7", "Enter", "Backspace", "*", "Alt+t"]);
                self.key(k);
            }
        }
    }

    /// An override or switch, by its key or its script word; sometimes a value the word
    /// refuses (the console refuses it the same way when it comes as an event).
    fn switch_step(&mut self) {
        self.stats.switch_changes += 1;
        let before = self.c.status().switches.rapid_override;
        if self.rng.range(0, 1) == 0 {
            let k = self.pick(&["Alt+f", "Alt+[", "Alt+]", "Alt+d", "Alt+l", "Alt+z"]);
            self.key(k);
        } else {
            let on = self.rng.range(0, 1) == 0;
            let e = match self.rng.range(0, 5) {
                // F0 is slow: a Table B run at 400 mm/min rapids takes long in machine time.
                0 => E::RapidOverride([25, 50, 100, 100, 0][self.rng.range(0, 4) as usize]),
                1 => E::SpindleOverride(self.rng.range(4, 13) as u32 * 10),
                2 => E::DryRun(on),
                3 => E::MachineLock(on),
                _ => E::ZNeglect(on),
            };
            self.ev(e);
        }
        if self.c.status().switches.rapid_override != before {
            self.rapid_changed_ns = self.c.status().machine_ns;
        }
    }

    /// An MDI G-code line run at once with the machine at rest and no run loaded: a modal
    /// change (G91/G90, G92/G92.1, G43/G49) or a G0 move in X and Y. The interpreter's state
    /// carries from line to line: after a move, the machine stands where the state before it
    /// says the line goes (G90 or G91, G92, the work offset, the tool length; Z does not
    /// move); a move refused before it started leaves the machine and the state as they were.
    fn mdi_gcode(&mut self) {
        let mut st = self.c.status().clone();
        if st.job.is_some() || st.estop || st.alarm.is_some() || st.moving || st.run != 0 {
            return;
        }
        if st.pos != st.machine_pos {
            // After a run under MACHINE LOCK the program position is where the program left
            // it; RESET brings it back to the axes, where the next line starts anyway.
            self.key("F11");
            st = self.c.status().clone();
        }
        // On a trunnion, one line in two is a move (the table turns with it).
        let pick = if self.trunnion && self.rng.chance(0.5) {
            11
        } else if self.trunnion && self.rng.chance(0.3) {
            // The chip conveyor's remapped codes.
            12
        } else if self.trunnion && self.rng.chance(0.3) {
            // The table's zero set where it stands (G92 or G10 L20), more often than one
            // line in eleven (stop 54: 11 in 1,000 sequences at first).
            if self.rng.chance(0.5) {
                2
            } else {
                6
            }
        } else {
            self.rng.range(0, 11)
        };
        let line = match pick {
            // A rigid tap 5 mm down from where the tool stands and back (stop 48): it ends
            // where it started, the tip 5 mm lower at the bottom.
            10 => {
                let len = st
                    .tool
                    .and_then(|t| self.c.magazine().tools.get(t).map(|r| r.length()))
                    .unwrap_or(0.0);
                let tip = self.c.settings().to_mm(st.machine_pos[2]) - len;
                self.lowest_mm = self.lowest_mm.min(tip - 5.001);
                "S300 M3 G91 G33.1 Z-5 K1.25".to_string()
            }
            // 20 mm down, incremental: a probe that stays above the lowest tip the
            // programs command (the invariant below), tripping where the stock is.
            9 => {
                // It commands the tip 20 mm below where it stands, which may already be low
                // (a run stopped in the bore, then abandoned): the bound follows.
                let len = st
                    .tool
                    .and_then(|t| self.c.magazine().tools.get(t).map(|r| r.length()))
                    .unwrap_or(0.0);
                let tip = self.c.settings().to_mm(st.machine_pos[2]) - len;
                self.lowest_mm = self.lowest_mm.min(tip - 20.001);
                "G91 G38.3 Z-20 F3000".to_string()
            }
            0 => "G91".to_string(),
            1 => "G90".to_string(),
            // On a trunnion, G92 sets the table's zero where it stands too (stop 54).
            2 if self.trunnion && self.rng.chance(0.5) => "G92 X0 Y0 B0 C0".to_string(),
            2 => "G92 X0 Y0".to_string(),
            // And G10 L20 makes the system in force read C0 where the table stands.
            6 if self.trunnion => "G10 L20 P0 C0".to_string(),
            12 => ["M31", "M33", "M8 M31 G4 P0.1", "M9 M33"][self.rng.below(4)].to_string(),
            3 => "G92.1".to_string(),
            4 => "G43 H2".to_string(),
            5 => "G49".to_string(),
            _ => {
                let mut l = format!(
                    "G0 X{} Y{}",
                    self.rng.range(-100, 400),
                    self.rng.range(-100, 300)
                );
                if self.trunnion && self.rng.chance(0.7) {
                    // B within and past its travel (G91 adds up), C anywhere a wrapped
                    // axis's absolute word may be, its sign the direction.
                    l += &format!(
                        " B{} C{}",
                        self.rng.range(-140, 140),
                        self.rng.range(-359, 359)
                    );
                }
                l
            }
        };
        let before = self.c.interp_state().clone();
        let pos = st.pos;
        self.key("Alt+4");
        self.key("F7");
        let typed = if self.fanuc {
            seq_gcode::fanuc_text(&line)
        } else {
            line.clone()
        };
        self.ev(E::Type(format!("-999L999KI{typed}")));
        self.key("Alt+3");
        self.key("F9");
        self.ev(E::Wait);
        self.stats.mdi_gcode += 1;
        let now = self.c.status().clone();
        let ended = self.c.frame_text().contains("program end");
        if line.contains("G33.1") {
            // A rigid tap ends where it started, run in and out or refused (beyond the
            // travel): under every invariant of the step, MACHINE LOCK and DRY RUN among them.
            assert_eq!(now.pos, pos, "MDI {line} did not end where it started");
            if ended {
                self.stats.mdi_taps += 1;
            }
            return;
        }
        if line.contains("G38.3") {
            // A probe toward the workpiece: where it stopped (on the stock, or at the move's
            // end) is where the interpreter reads on from, and #5070 says which.
            let after = self.c.interp_state();
            if ended {
                let settings = self.c.settings();
                for a in 0..3 {
                    assert!(
                        (settings.to_pulses(after.pos[a]) - now.pos[a]).abs() <= 1,
                        "after MDI {line} the machine is at {:?}, the interpreter at {:?}",
                        now.pos,
                        after.pos
                    );
                }
                assert!(after.params[5070] == 0.0 || after.params[5070] == 1.0);
                self.stats.mdi_probes += 1;
            } else {
                assert_eq!(
                    now.pos[0..2],
                    pos[0..2],
                    "a refused MDI {line} moved X or Y"
                );
            }
            // The MDI buffer keeps its text, and START in MDI runs it again: 20 mm lower each
            // time, with no bound. An operator types the next line; here, one that moves
            // nothing.
            self.key("Alt+4");
            self.key("F7");
            self.ev(E::Type("-999L999KIG90".into()));
            self.key("Alt+3");
            return;
        }
        if (line.contains("M31") || line.contains("M33")) && ended {
            // A remapped code ran its subroutine: the conveyor's output 1 says which.
            let on = now.outputs.digital & 2 != 0;
            assert_eq!(
                on,
                line.contains("M31"),
                "after MDI {line} output 1 is {on}\n{}",
                self.c.frame_text()
            );
            self.stats.remap_calls += 1;
        }
        let Some(xy) = line.strip_prefix("G0 ") else {
            assert_eq!(now.pos, pos, "MDI {line} moved the machine");
            if ended && (line.contains(" C0") || line.contains(" B0")) {
                // The table reads 0 where it stands on the axes the line names.
                let after = self.c.interp_state().prog_abc();
                let named = [(1, " B0"), (2, " C0")];
                for (r, w) in named.into_iter().filter(|(_, w)| line.contains(w)) {
                    assert!(
                        after[r].abs() < 1e-9,
                        "after MDI {line} the program position{w} reads {}",
                        after[r]
                    );
                }
                self.stats.rotary_zeros += 1;
            }
            return;
        };
        if !ended {
            // Refused (beyond the travel): nothing moved, the state is as it was.
            assert_eq!(now.pos, pos, "MDI {line} was refused but moved");
            let after = self.c.interp_state();
            assert_eq!(
                after.modal,
                before.modal,
                "a refused MDI {line} changed the modes\n{}",
                self.c.frame_text()
            );
            assert_eq!(after.g92, before.g92);
            return;
        }
        let words: Vec<f64> = xy.split(' ').map(|w| w[1..].parse().unwrap()).collect();
        let rotary_words = words.get(2..4).map(|w| [w[0], w[1]]);
        let settings = self.c.settings().clone();
        let mut b = before;
        // A run takes its work system's zero from the stores, as POS shows it; the G-code
        // state's copy is the last run's (seed 1592591439, stop 43: G54 set on the work
        // offset page between two MDI runs, which the model had not seen).
        if let Some(o) = self.c.work_offsets().0.get(b.modal.cs) {
            b.origin = *o;
        }
        b.pos = pos.xyz().map(|v| settings.to_mm(v));
        let here = b.prog();
        let target = if b.modal.incremental {
            [here[0] + words[0], here[1] + words[1], here[2]]
        } else {
            [words[0], words[1], here[2]]
        };
        let want = b.to_machine(target).map(|v| settings.to_pulses(v));
        for a in 0..3 {
            assert!(
                (now.pos[a] - want[a]).abs() <= 1,
                "MDI {line} with the state {:?} G92 {:?} TLO {:?}: machine at {:?}, the state says {want:?}",
                b.modal,
                b.g92,
                b.tlo,
                now.pos
            );
        }
        // B and C: G91 adds; G90 puts B at the word, and C (wrapped) at the nearest position
        // ≡ |word| (mod 360) in the direction of its sign (LinuxCNC's rule, worked out here),
        // in the program frame: the machine's is that plus the system's offset and G92's
        // (stop 54).
        let settings_deg = |p: i64| settings.to_mm(p);
        let off = [1, 2].map(|r| b.params[system_base(b.modal.cs) + 4 + r] + b.g92_abc[r]);
        let (b0, c0) = (settings_deg(pos[4]) - off[0], settings_deg(pos[5]) - off[1]);
        let (want_b, want_c) = match rotary_words {
            None => (b0, c0),
            Some([wb, wc]) if b.modal.incremental => (b0 + wb, c0 + wc),
            Some([wb, wc]) => {
                let mut r = (c0 / 360.0).floor() * 360.0 + wc.abs();
                if wc.is_sign_negative() && r > c0 {
                    r -= 360.0;
                }
                if !wc.is_sign_negative() && r < c0 {
                    r += 360.0;
                }
                (wb, r)
            }
        };
        let (want_b, want_c) = (want_b + off[0], want_c + off[1]);
        assert_eq!(
            [now.pos[4], now.pos[5]],
            [settings.to_pulses(want_b), settings.to_pulses(want_c)],
            "MDI {line}: B and C at {:?}, from {:?}",
            &now.pos[4..],
            &pos[4..]
        );
        if rotary_words.is_some() {
            self.stats.rotary_moves += 1;
        }
        self.stats.mdi_moves += 1;
    }

    /// A page key and what an operator types on that page: an OFS value with INPUT or
    /// +INPUT (a length during a hold applies from the next block), a POS preset, a PROG
    /// copy, rename or delete. Tool data and program memory change only with the machine at
    /// rest (a hold, between single blocks, or no run), and a PROG change never with a run
    /// loaded.
    fn page_action(&mut self) {
        if self.c.status().job.is_some() && self.c.status().hold {
            // Let a feed hold come to rest, as an operator waits for it.
            self.ev(E::Wait);
        }
        let st = self.c.status().clone();
        let mag = self.c.magazine();
        let text = self.c.program_text();
        // With a run stopped at rest, mostly a length revision: the case that moves blocks.
        let stopped = st.idle && !st.moving && (st.hold || st.run == 0);
        let held = st.job.is_some() && stopped && self.rng.range(0, 2) != 0;
        let page = if held {
            "Ctrl+O"
        } else if self.fanuc && self.rng.range(0, 1) == 0 {
            "Ctrl+U"
        } else {
            self.pick(&["Ctrl+P", "Ctrl+D", "Ctrl+O", "Ctrl+E", "Ctrl+U"])
        };
        self.key(page);
        match page {
            "Ctrl+O" => {
                for _ in 0..self.rng.range(0, 3) {
                    let k = if held {
                        self.pick(&["Down", "Up"])
                    } else {
                        self.pick(&["Down", "Up", "Right", "Left"])
                    };
                    self.key(k);
                }
                let v = if self.gcode && !held && self.rng.range(0, 3) == 0 {
                    self.pick(&seq_gcode::OFFSETS).to_string()
                } else if self.rng.range(0, 1) == 0 {
                    self.rng.range(100, 230).to_string()
                } else {
                    format!("{:.3}", self.rng.range(-500, 500) as f64 / 1000.0)
                };
                if self.rng.range(0, 1) == 0 {
                    self.ev(E::Type(v));
                } else {
                    for ch in v.chars() {
                        self.ev(E::Key(ch));
                    }
                    // +INPUT: the keyboard's Tab or the keypad's key, one rule.
                    if self.rng.range(0, 1) == 0 {
                        self.key("Tab");
                    } else {
                        self.ev(E::PlusInput);
                    }
                }
            }
            "Ctrl+P" => {
                let w = self.pick(&["X", "Y12.5", "Z-3", "XYZ", "PARTS 0", "TARGET 0"]);
                self.ev(E::Type(w.into()));
            }
            "Ctrl+D" => {
                let w = self.pick(&["", "C P2", "R P3", "D", "D"]);
                self.ev(E::Type(w.into()));
            }
            "Ctrl+U" => self.macro_input(),
            _ => {}
        }
        let at_rest = st.job.is_none() || stopped;
        if self.c.magazine() != mag {
            assert!(
                at_rest,
                "the tool data changed with a run not stopped at rest"
            );
            self.stats.ofs_in_run += u64::from(st.job.is_some());
            if self.gcode && st.job.is_some() {
                // Any tool's: the run may load a revised tool later (seed 1592590347, stop
                // 53: tool 1 lengthened before Table B's T1 M6, with no tool in the spindle).
                let after = self.c.magazine();
                let longer = (1..=after.tools.capacity())
                    .filter_map(|t| Some(after.tools.get(t)?.length() - mag.tools.get(t)?.length()))
                    .fold(0.0, f64::max);
                self.lowest_mm = seq_gcode::revised_in_run(self.lowest_mm, 0.0, longer);
            }
        }
        if st.job.is_some() {
            assert_eq!(
                self.c.program_text(),
                text,
                "program memory changed with a run loaded"
            );
        }
        if self.rng.range(0, 1) == 0 {
            self.key(page);
        }
    }

    /// A MACRO page INPUT, `#n=v`, of a local, a common or a kept variable. In the Fanuc
    /// dialect the console takes it with the machine at rest (as OFS's) and sets the
    /// variable, a #500-#999 journaled (the restart checks it is kept); with the machine
    /// moving, or in LinuxCNC's dialect, it is refused and nothing changes.
    fn macro_input(&mut self) {
        let n = match self.rng.range(0, 3) {
            0 => self.rng.range(1, 33),
            1 => self.rng.range(100, 199),
            _ => self.rng.range(500, 999),
        } as usize;
        let v = self.rng.range(-99_999, 99_999) as f64 / 1000.0;
        let rest = |st: &novanc::pulse_core::Status| {
            (st.job.is_none() || (st.idle && (st.hold || st.run == 0))) && !st.moving
        };
        // The page key toggles: an earlier step may have left the page up.
        if !self.c.frame_text().starts_with("MACRO") {
            self.key("Ctrl+U");
        }
        let before = self.c.interp_state().params[n];
        let rest_before = rest(self.c.status());
        // A tape read in progress takes no typed line at all (docs/tape.md "At the console"):
        // the machine stands, but the page's INPUT is refused (seed 1592590764, stop 43).
        let reading = self.c.tape_reading();
        self.ev(E::Type(format!("#{n}={v}")));
        let rest_after = rest(self.c.status());
        let after = self.c.interp_state().params[n];
        let changed = after.to_bits() != before.to_bits();
        if self.fanuc && rest_before && rest_after && !reading {
            assert_eq!(after, v, "MACRO #{n}={v} at rest\n{}", self.c.frame_text());
        }
        if changed {
            assert!(
                self.fanuc && (rest_before || rest_after),
                "MACRO #{n}={v} was taken moving or in LinuxCNC's dialect\n{}",
                self.c.frame_text()
            );
            self.stats.macro_writes += 1;
            if n >= 500 {
                self.kept.insert(n, v);
                // Sometimes the console dies right after: the write was acknowledged.
                if self.rng.range(0, 2) == 0 {
                    self.restart();
                }
            }
        } else if before != v {
            let tape = reading && common::shows(&self.c, "the tape reader");
            assert!(
                common::shows(&self.c, "MACRO refused") || tape,
                "MACRO #{n}={v}: neither taken nor refused\n{}",
                self.c.frame_text()
            );
        }
    }

    /// PROGRAM READ (or TOOL DATA READ) of a tape image, good or with one bit flipped, read to
    /// its end or abandoned part way by STOP, RESET, E-STOP or a selector turn.
    fn tape_read(&mut self) {
        let tools = self.rng.range(0, 3) == 0;
        let good = match (tools, self.rng.range(0, 1)) {
            (true, 0) => "tests/golden/tools.iso.tape",
            (true, _) => "tests/golden/tools.eia.tape",
            (false, 0) => "tests/golden/tableb.iso.tape",
            (false, _) => "tests/golden/tableb.eia.tape",
        };
        let mut image =
            std::fs::read(std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join(good)).unwrap();
        // Mostly corrupted: a good read stores (and fsyncs), which costs the most time.
        if self.rng.range(0, 2) != 0 {
            let i = self.rng.range(0, image.len() as i64 - 1) as usize;
            image[i] ^= 1 << self.rng.range(0, 7);
        }
        let path = self.tapes.join("tape.tape");
        if self.c.tape_reading() {
            // A START earlier in the sequence is still reading a tape (seed 1592590655): the
            // reader is not reloaded while it moves, and the read goes on to its end.
            self.ev(E::Tape(self.tapes.join("other.tape")));
            let shown = self.c.frame_text();
            let words = shown.split_whitespace().collect::<Vec<_>>().join(" ");
            assert!(
                words.contains("refused: the tape reader is reading tape.tape"),
                "a tape change is refused while the reader moves:\n{shown}"
            );
            assert!(self.c.tape_reading(), "the read goes on");
            self.ev(E::Wait);
            assert!(!self.c.tape_reading(), "wait lets the read end");
        }
        std::fs::write(&path, &image).unwrap();
        let expect = tape::read_image(&image, ReadOptions::default());
        let program = self.c.program_text();
        let magazine = self.c.magazine();
        let alarm_before = self.c.tape_alarm().is_some();
        self.key("Alt+4");
        self.key(if tools { "F4" } else { "F2" });
        self.ev(E::Tape(path));
        self.key("F9");
        if !self.c.tape_reading() {
            assert!(alarm_before, "START in a READ mode starts the tape");
            assert_eq!(self.c.program_text(), program);
            return;
        }
        self.stats.tape_reads += 1;
        if self.rng.range(0, 1) == 0 {
            let t = self.rng.range(1, 3000) as u64;
            self.ev(E::WaitMs(t));
            if self.c.tape_reading() {
                let k = self.pick(&["F10", "F11", "F12", "F12", "Alt+2", "F3"]);
                self.key(k);
                assert!(!self.c.tape_reading(), "{k} abandons the read");
                assert_eq!(self.c.program_text(), program, "{k}: nothing stored");
                assert_eq!(self.c.magazine(), magazine, "{k}: nothing stored");
                self.stats.tape_abandoned += 1;
                return;
            }
        } else {
            self.ev(E::Wait);
        }
        assert!(!self.c.tape_reading(), "wait lets the read end");
        match expect {
            Ok(t) => {
                assert!(self.c.tape_alarm().is_none());
                if !tools {
                    assert_eq!(self.c.program_text(), t.text, "the tape's text is stored");
                }
            }
            Err(e) => {
                self.stats.tape_alarms += 1;
                assert_eq!(self.c.tape_alarm(), Some(e.to_string().as_str()));
                assert!(self.c.view().lamps.alarm, "a tape error lights ALARM");
                assert_eq!(self.c.program_text(), program, "nothing stored");
                assert_eq!(self.c.magazine(), magazine, "nothing stored");
            }
        }
    }

    /// A manual intervention: hold the run mid-block (or stop it between single blocks), move
    /// the axes by hand, and START again from AUTO or SINGLE BLOCK.
    fn intervene(&mut self) {
        if self.c.status().job.is_none() {
            self.key("Alt+2");
            self.key("F9");
        }
        let t = self.rng.range(100, 30_000) as u64;
        self.ev(E::WaitMs(t));
        self.key("F10");
        self.ev(E::Wait);
        let k = self.pick(&["Alt+6", "Alt+5", "Alt+1"]);
        self.key(k);
        for _ in 0..self.rng.range(1, 6) {
            let k = self.pick(&["Left", "Right", "Up", "Down", "PgUp", "PgDn", "Alt+w"]);
            self.key(k);
            self.ev(E::Wait);
        }
        let k = self.pick(&["Alt+2", "Alt+7"]);
        self.key(k);
        self.check();
        self.key("F9");
        if self.rng.range(0, 3) == 0 && self.c.status().job.as_ref().is_some_and(|j| j.returning) {
            // E-STOP during the return.
            let t = self.rng.range(1, 300) as u64;
            self.ev(E::WaitMs(t));
            self.estop();
        }
    }

    /// The overrides and switches: the spindle speed, the speed of a rapid, jog or return, and
    /// the state line.
    fn check_switches(
        &mut self,
        st: &novanc::pulse_core::Status,
        s: &novanc::settings::MachineSettings,
    ) {
        // During a tap the override is held at 100 % (docs/pulse-core.md, "Tapping").
        let pct = if st.switches.override_locked {
            100
        } else {
            i64::from(st.switches.spindle_override)
        };
        assert_eq!(
            st.spindle,
            st.spindle_programmed * pct / 100,
            "the spindle turns at programmed x override (held at 100 % in a tap)"
        );
        if st.hold_after_tap {
            self.stats.tap_holds += 1;
        }
        assert!(
            (50..=120).contains(&st.switches.spindle_override)
                && st.switches.spindle_override.is_multiple_of(10)
        );
        assert!(matches!(st.switches.rapid_override, 0 | 25 | 50 | 100));
        // The time to come down from the rapid rate to any lower speed, and a tick.
        let ramp_ns = (s.rapid_mm_min / 60.0 / s.accel_mm_s2 * 1e9) as u64 + s.ncbr_period_ns;
        let settled = st.machine_ns >= self.rapid_changed_ns + ramp_ns;
        let rapid_block = st.in_block
            && st
                .executed
                .as_ref()
                .is_some_and(|b| b.motion == novanc::block::Motion::Rapid);
        let manual = !st.in_block && st.moving;
        if settled && st.moving && (rapid_block || manual) {
            let full = if rapid_block {
                s.rapid_mm_min
            } else {
                s.jog_mm_min
            };
            let cap = match st.switches.rapid_override {
                0 => s.rapid_f0_mm_min.min(full),
                p => full * f64::from(p) / 100.0,
            };
            assert!(
                st.speed_mm_min <= cap * 1.0001,
                "{} at {} mm/min with the rapid override at {} %: more than {cap}",
                if rapid_block {
                    "a rapid"
                } else {
                    "a jog or return"
                },
                st.speed_mm_min,
                st.switches.rapid_override
            );
        }
        let v = self.c.view();
        assert_eq!(
            (
                v.switches.rapid_override,
                v.switches.spindle_override,
                v.switches.dry_run,
                v.switches.machine_lock,
                v.switches.z_neglect
            ),
            (
                st.switches.rapid_override,
                st.switches.spindle_override,
                st.switches.dry_run,
                st.switches.machine_lock,
                st.switches.z_neglect
            ),
            "the view shows the status's switches"
        );
        if let Some(line) = v.display.iter().find(|l| l.starts_with("RUN ")) {
            // The marks (in order, so a narrow display cuts them from the end).
            let marks = [
                (st.switches.dry_run, " DRY"),
                (st.switches.machine_lock, " MLK"),
                (st.switches.z_neglect && !st.switches.machine_lock, " ZNG"),
            ];
            let full = line.trim_end().len() < self.c.config().cols;
            for (on, m) in marks {
                if on && full {
                    assert!(line.contains(m), "{m} missing from the state line: {line}");
                }
                if !on {
                    assert!(
                        !line.contains(m),
                        "{m} on the state line with it off: {line}"
                    );
                }
            }
        }
    }

    /// The invariants after each step.
    fn check(&mut self) {
        let settings = self.c.settings().clone();
        for e in self.c.core().take_audit() {
            self.stats.block_ends += 1;
            self.stats.ep_block_ends += self.ep as u64;
            assert_eq!(
                e.pos, e.end,
                "run {} N{} (line {}) ended off its programmed point",
                e.run, e.seq, e.stmt
            );
            // A block that takes Z down must not take the tip below what the programs
            // command, by the tool length it was planned with. (A block that does not descend
            // may end lower: the tool was already there, or a tool revision changed what its
            // tip is. A length revised while a block runs applies from the next block.)
            assert!(
                e.pos[2] >= e.start[2] || e.tip_planned >= settings.to_pulses(self.lowest_mm),
                "run {} N{}: tip Z {:.3} is below {:.3} ({e:?})",
                e.run,
                e.seq,
                settings.to_mm(e.tip_planned),
                self.lowest_mm
            );
        }
        let st = self.c.status().clone();
        assert!(!self.sink.is_incomplete(), "no event was dropped");
        let rec = self.recorded();
        assert_eq!(
            std::array::from_fn::<i64, MAX_AXES, _>(|a| rec[a] + self.pos_offset[a]),
            st.machine_pos.0,
            "the recorded pulses (and the positions restored at restarts) add up to where the axes are"
        );
        if self.home_pressed
            && st.machine_pos == [0; 3]
            && st.job.is_none()
            && !st.moving
            && st.idle
        {
            // The reference return is made (the console's rule: HOME accepted since, and the
            // axes at rest at machine zero).
            self.home_owed = false;
        }
        if !st.switches.machine_lock && !st.switches.z_neglect && st.job.is_some() {
            assert_eq!(st.pos, st.machine_pos, "unlocked, a run moves the axes");
        }
        self.check_switches(&st, &settings);
        let v = self.c.view();
        assert_eq!(v.lamps.estop, st.estop);
        assert_eq!(v.lamps.run, st.run != 0);
        self.screen_agrees(&st);
        assert_eq!(v.display.len(), self.c.config().rows);
        for l in &v.display {
            assert!(l.chars().count() <= self.c.config().cols, "{l:?}");
        }
        self.stats.runs = st.runs;
        if self.gcode {
            self.stats.gcode_ends += u64::from(
                st.last_end
                    .as_ref()
                    .is_some_and(|e| e.cause == novanc::pulse_core::EndCause::ProgramEnd),
            );
        }
        self.stats.holds += u64::from(st.hold);
        self.stats.estops += u64::from(st.estop);
        if let Some(j) = &st.job {
            self.stats.returns += u64::from(j.returning);
            let moved = j.return_to.is_some_and(|to| to != st.pos) && !j.returning;
            self.stats.jogged_stops += u64::from(moved);
            if moved && matches!(v.op_mode, OpMode::Auto | OpMode::Single) {
                assert!(
                    v.display.iter().any(|l| l.contains("JOGGED")),
                    "a jogged run says so:\n{}",
                    self.c.frame_text()
                );
            }
        }
    }
}

impl Session {
    /// The lamps, the state line and every message that describes the machine agree with the
    /// status snapshot (issue 23, "The screen is a function of the state").
    fn screen_agrees(&self, st: &novanc::pulse_core::Status) {
        let v = self.c.view();
        let frame = self.c.frame_text();
        let returning = st.job.as_ref().is_some_and(|j| j.returning);
        assert_eq!(v.lamps.hold, st.hold && !returning, "HOLD lamp\n{frame}");
        assert_eq!(
            v.lamps.alarm,
            st.alarm.is_some() || self.c.program_alarm().is_some() || self.c.tape_alarm().is_some(),
            "ALARM lamp\n{frame}"
        );
        if v.page != novanc::panel_model::Page::Mode {
            // The pages show history and program text, not the machine's state.
            return;
        }
        // The state line is the display's last line that starts "RUN " (a wrapped message
        // such as "DRY / RUN on: ..." may start a line with it too).
        if let Some(line) = v
            .display
            .iter()
            .rev()
            .map(|l| l.trim_end())
            .find(|l| l.starts_with("RUN "))
        {
            assert!(
                line.starts_with(&format!("RUN {} ", st.run)),
                "{line}\n{frame}"
            );
            // ESTOP and HOLD come before the switches, so only a cut line may lose them.
            let cut = line.ends_with('…');
            let estop_shown = line.contains(" ESTOP");
            let hold_shown = line.contains(" HOLD");
            assert!(!estop_shown || st.estop, "ESTOP on the state line\n{frame}");
            assert!(estop_shown || !st.estop || cut, "no ESTOP\n{frame}");
            assert!(
                !hold_shown || v.lamps.hold,
                "HOLD on the state line\n{frame}"
            );
            assert!(
                hold_shown || !v.lamps.hold || st.estop || cut,
                "no HOLD on the state line\n{frame}"
            );
        }
        let text = frame
            .lines()
            .map(|l| l.trim())
            .collect::<Vec<_>>()
            .join(" ");
        let says = |what: &str| text.contains(what);
        let stands_for_start = st.job.is_some() && st.run == 0 && !st.in_block && !st.moving;
        // Something moves by hand (or HOME's return) with no run loaded (stop 44).
        let by_hand = st.job.is_none() && (st.moving || !st.idle);
        // The run page's header invites START only with the machine at rest and out of
        // E-STOP (stop 48).
        let at_rest = !st.moving && st.idle && !st.estop;
        let checks: [(&str, bool); 10] = [
            (": press START", at_rest || st.job.is_some()),
            ("JOG: an axis moves by hand", by_hand),
            ("HOME: reference return, Z first", by_hand),
            ("START: returning", false),
            ("returning to X", returning),
            ("press START to continue", stands_for_start),
            ("feed hold: press START to resume", st.hold && !returning),
            ("START ignored", st.run != 0 && !st.hold),
            ("the machine stops after this block", st.in_block),
            ("EMERGENCY STOP", st.estop || st.alarm.is_some()),
        ];
        for (what, true_now) in checks {
            assert!(
                !says(what) || true_now,
                "the screen says '{what}' but the machine has left that state ({st:?})\n{frame}"
            );
        }
    }
}

/// Runs one sequence of `len` steps; panics (with the seed in the message) on a broken
/// invariant. Returns what it exercised.
fn sequence(seed: u64, len: usize) -> Stats {
    let mut s = Session::open(seed);
    for _ in 0..len {
        let before = s.c.status().clone();
        s.step();
        let after = s.c.status().clone();
        if before.switches.machine_lock && after.switches.machine_lock {
            assert_eq!(
                after.machine_pos,
                before.machine_pos,
                "the axes moved under MACHINE LOCK ({:?})",
                s.log.last()
            );
            s.stats.locked_steps += 1;
        } else if before.switches.z_neglect && after.switches.z_neglect {
            assert_eq!(
                after.machine_pos[2],
                before.machine_pos[2],
                "Z moved under Z NEGLECT ({:?})",
                s.log.last()
            );
            s.stats.locked_steps += 1;
        }
        s.check();
    }
    // Whatever was left running ends: the invariants hold to the end.
    s.key("F11");
    s.key("Alt+2");
    s.key("F9");
    s.ev(E::Wait);
    s.check();
    let Session { c, stats, .. } = s;
    let _ = c.finish();
    stats
}

#[test]
fn random_operator_sequences_keep_every_block_on_its_programmed_point() {
    let n = count(200);
    let st = run_many(n, 30, sequence);
    if n >= 100 {
        assert!(st.block_ends > 1000, "{st:?}");
        assert!(st.jogged_stops > 0 && st.returns > 0, "{st:?}");
        assert!(st.holds > 0 && st.searches > 0 && st.estops > 0, "{st:?}");
        assert!(
            st.tape_reads > 0 && st.tape_alarms > 0 && st.tape_abandoned > 0,
            "{st:?}"
        );
        assert!(st.ofs_in_run > 0, "{st:?}");
        assert!(st.gcode_sessions > 0 && st.gcode_ends > 0, "{st:?}");
        assert!(st.mdi_moves > 0, "{st:?}");
        assert!(st.rotary_moves > 0 && st.rotary_zeros > 0, "{st:?}");
        assert!(st.remap_calls > 0, "{st:?}");
        assert!(st.mdi_probes > 0, "{st:?}");
        assert!(st.mdi_taps > 0, "{st:?}");
        assert!(st.turns_cleared > 0, "{st:?}");
        assert!(st.ep_block_ends > 100, "{st:?}");
        assert!(st.switch_changes > 0 && st.locked_steps > 0, "{st:?}");
        assert!(st.rapid_checks > 0, "{st:?}");
        assert!(st.tap_stops > 0 && st.tap_holds > 0, "{st:?}");
        assert!(
            st.restarts > 0 && st.restarts_moving > 0 && st.homes > 0,
            "{st:?}"
        );
        assert!(st.measures > 0, "{st:?}");
        assert!(st.fanuc_sessions > 0 && st.macro_writes > 0, "{st:?}");
        assert!(st.macro_kept > 0, "{st:?}");
        let missed: Vec<&str> = (0..ESTOP_STATES.len())
            .filter(|b| st.estop_states & (1 << b) == 0)
            .map(|b| ESTOP_STATES[b])
            .collect();
        assert!(
            missed.is_empty(),
            "E-STOP never pressed: {missed:?} ({st:?})"
        );
    }
}

#[test]
#[ignore]
fn ten_thousand_operator_sequences() {
    run_many(count(10_000), 60, sequence);
}
