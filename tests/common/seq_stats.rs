//! What the operator-sequence test (tests/operator_sequences.rs) counts, and how it runs many
//! sequences: each by its seed, the failing seed named with the command that replays it.

/// What the sequences exercised, so a run that tested nothing cannot pass.
#[derive(Clone, Copy, Debug, Default)]
pub struct Stats {
    /// Block ends audited.
    pub block_ends: u64,
    /// Runs begun.
    pub runs: u64,
    /// Steps that ended in a feed hold.
    pub holds: u64,
    /// Steps with a stopped run moved by hand.
    pub jogged_stops: u64,
    /// Steps with a return to the stopped run in progress.
    pub returns: u64,
    /// SEARCHes that positioned the program.
    pub searches: u64,
    /// Steps that ended in an emergency stop.
    pub estops: u64,
    /// Tape reads started.
    pub tape_reads: u64,
    /// Tape reads that stopped at an error.
    pub tape_alarms: u64,
    /// Tape reads abandoned part way.
    pub tape_abandoned: u64,
    /// Tool data changed on the OFS page with a run loaded (held or between single blocks).
    pub ofs_in_run: u64,
    /// Sessions that ran Table B in G-code.
    pub gcode_sessions: u64,
    /// Steps of those sessions after which their last run had reached its end.
    pub gcode_ends: u64,
    /// Block ends checked in sessions on the error-proportional interpolator.
    pub ep_block_ends: u64,
    /// MDI G-code lines run (G-code sessions).
    pub mdi_gcode: u64,
    /// Of those, G0 moves that ended where the interpreter's state said.
    pub mdi_moves: u64,
    /// MDI G38.3 probes after which the interpreter read on from where the machine stopped.
    pub mdi_probes: u64,
    /// MDI G33.1 rigid taps run in and out, ending where they started (stop 48).
    pub mdi_taps: u64,
    /// Selector turns that cleared a typed line and said so.
    pub turns_cleared: u64,
    /// Steps that ended with a STOP kept for the end of a tap.
    pub tap_holds: u64,
    /// Steps taken with MACHINE LOCK or Z NEGLECT on all through, the axes checked still.
    pub locked_steps: u64,
    /// Steps that ended in a rapid, jog or return, its speed checked against the rapid
    /// override.
    pub rapid_checks: u64,
    /// Override and switch changes (keys and script words).
    pub switch_changes: u64,
    /// STOPs given inside a tap, whose hold came at R with the spindle forward.
    pub tap_stops: u64,
    /// Console restarts on the same state directory (position memory).
    pub restarts: u64,
    /// Of those, restarts of a console that died while the axes moved (HOME owed).
    pub restarts_moving: u64,
    /// Reference returns (HOME) made to machine zero.
    pub homes: u64,
    /// OFS MEASURE inputs the console accepted (work offset or tool length).
    pub measures: u64,
    /// Sessions in the Fanuc dialect (Table B with a decimal point on every length).
    pub fanuc_sessions: u64,
    /// MACRO page writes the console took (Fanuc sessions), and #500-#999 found kept after
    /// a restart.
    pub macro_writes: u64,
    pub macro_kept: u64,
    /// MDI moves that turned the rotary axes B and C (sessions on a trunnion machine).
    pub rotary_moves: u64,
    /// MDI G92 B0 C0 and G10 L20 P0 C0 that set the table's zero where it stands (the rotary
    /// work offsets, stop 54).
    pub rotary_zeros: u64,
    /// MDI M31 and M33 that ran their remap subroutines (the conveyor's output 1 on, off;
    /// stop 55).
    pub remap_calls: u64,
    /// The machine states E-STOP was pressed in, one bit each (`ESTOP_STATES` in the test).
    pub estop_states: u32,
}

impl Stats {
    /// Adds another sequence's counts.
    pub fn add(&mut self, o: &Stats) {
        self.block_ends += o.block_ends;
        self.runs += o.runs;
        self.holds += o.holds;
        self.jogged_stops += o.jogged_stops;
        self.returns += o.returns;
        self.searches += o.searches;
        self.estops += o.estops;
        self.tape_reads += o.tape_reads;
        self.tape_alarms += o.tape_alarms;
        self.tape_abandoned += o.tape_abandoned;
        self.ofs_in_run += o.ofs_in_run;
        self.gcode_sessions += o.gcode_sessions;
        self.gcode_ends += o.gcode_ends;
        self.ep_block_ends += o.ep_block_ends;
        self.mdi_gcode += o.mdi_gcode;
        self.mdi_moves += o.mdi_moves;
        self.rotary_moves += o.rotary_moves;
        self.rotary_zeros += o.rotary_zeros;
        self.remap_calls += o.remap_calls;
        self.mdi_probes += o.mdi_probes;
        self.mdi_taps += o.mdi_taps;
        self.turns_cleared += o.turns_cleared;
        self.tap_holds += o.tap_holds;
        self.locked_steps += o.locked_steps;
        self.rapid_checks += o.rapid_checks;
        self.switch_changes += o.switch_changes;
        self.tap_stops += o.tap_stops;
        self.restarts += o.restarts;
        self.restarts_moving += o.restarts_moving;
        self.homes += o.homes;
        self.measures += o.measures;
        self.fanuc_sessions += o.fanuc_sessions;
        self.macro_writes += o.macro_writes;
        self.macro_kept += o.macro_kept;
        self.estop_states |= o.estop_states;
    }
}

/// Runs `n` sequences of `len` steps from the seed `NOVANC_SEQUENCE_SEED` on, spread over the
/// machine's cores (each sequence has its own console and state directory, and its outcome
/// depends on its seed alone); a failure panics with its seed and the command that replays it
/// (the lowest failing seed of those run, whatever order the threads met them in).
pub fn run_many(n: u64, len: usize, sequence: fn(u64, usize) -> Stats) -> Stats {
    use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
    use std::sync::Mutex;
    let base = std::env::var("NOVANC_SEQUENCE_SEED")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(0x5EED_0001);
    let threads = std::thread::available_parallelism()
        .map_or(1, |t| t.get())
        .min(n.max(1) as usize);
    let next = AtomicU64::new(0);
    let failed = AtomicBool::new(false);
    let total = Mutex::new(Stats::default());
    let failure: Mutex<Option<(u64, String)>> = Mutex::new(None);
    std::thread::scope(|s| {
        for _ in 0..threads {
            s.spawn(|| loop {
                let i = next.fetch_add(1, Ordering::Relaxed);
                if i >= n || failed.load(Ordering::Relaxed) {
                    break;
                }
                let seed = base + i;
                match std::panic::catch_unwind(|| sequence(seed, len)) {
                    Ok(st) => total.lock().unwrap_or_else(|e| e.into_inner()).add(&st),
                    Err(e) => {
                        let msg = e
                            .downcast_ref::<String>()
                            .cloned()
                            .or_else(|| e.downcast_ref::<&str>().map(|s| s.to_string()))
                            .unwrap_or_default();
                        let mut f = failure.lock().unwrap_or_else(|e| e.into_inner());
                        if f.as_ref().is_none_or(|(s, _)| seed < *s) {
                            *f = Some((seed, msg));
                        }
                        failed.store(true, Ordering::Relaxed);
                    }
                }
            });
        }
    });
    if let Some((seed, msg)) = failure.into_inner().unwrap_or_else(|e| e.into_inner()) {
        panic!("sequence with seed {seed} failed: {msg}\n(replay: NOVANC_SEQUENCE_SEED={seed} NOVANC_SEQUENCES=1; NOVANC_SEQUENCE_LOG=1 prints the events)");
    }
    let total = total.into_inner().unwrap_or_else(|e| e.into_inner());
    eprintln!("{n} sequences of {len} steps on {threads} threads: {total:?}");
    total
}

/// `NOVANC_SEQUENCES`, else `default`.
pub fn count(default: u64) -> u64 {
    std::env::var("NOVANC_SEQUENCES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(default)
}
