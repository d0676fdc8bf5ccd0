//! The sync table between a kernel's channels (docs/pulse-core.md, "Channels"; seed 004 lines
//! 136–142, 288–304, 330–378): the waiting M codes, the receive (M10 on an empty spindle) and
//! delivery (M11 holding a work) points with the work handover, the chuck interlock, which
//! work each chuck holds, and the part counter.
//!
//! The table knows channels by index and sync points by [`Sync`]; it never moves an axis. The
//! kernel ([`super::Kernel`]) tells it when a channel arrives at a sync point and which
//! channels may go on, and releases the channels [`SyncTable::resolve`] names.

use crate::block::Sync;
use std::fmt;

/// Where works come from and go to: the bar feeder, the handovers between channels, the
/// unloader (the lathe description's `supplier`, `transfer` and `unloader` lines).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct WorkFlow {
    /// The channel the bar feeder supplies: its M10 on an empty spindle takes a new work.
    pub supplier: usize,
    /// (from, to): channel `from`'s M11 hands its work to channel `to`'s M10.
    pub transfers: Vec<(usize, usize)>,
    /// The channel whose M11 hands its work to the unloader.
    pub unloader: usize,
    /// The operator loads each work by hand (a one-channel lathe without a bar feeder,
    /// `loading manual`): its chuck holds a new work, closed, when each cycle begins, and the
    /// work is taken out at the program's end; M10 and M11 are refused.
    pub manual: bool,
}

impl WorkFlow {
    /// The channel `ch` delivers to, if any.
    pub fn receiver_of(&self, ch: usize) -> Option<usize> {
        self.transfers.iter().find(|t| t.0 == ch).map(|t| t.1)
    }

    /// The channel `ch` receives from, if any.
    pub fn supplier_of(&self, ch: usize) -> Option<usize> {
        self.transfers.iter().find(|t| t.1 == ch).map(|t| t.0)
    }

    /// Refuses a flow naming a channel the machine has not.
    pub fn check(&self, channels: usize) -> Result<(), String> {
        if self.manual && (channels != 1 || !self.transfers.is_empty()) {
            return Err("loading by hand is for a lathe of one channel, without transfers".into());
        }
        if self.supplier >= channels || self.unloader >= channels {
            return Err("the supplier or unloader channel is not a channel".into());
        }
        if self
            .transfers
            .iter()
            .any(|t| t.0 >= channels || t.1 >= channels || t.0 == t.1)
        {
            return Err("a transfer names a channel the machine has not".into());
        }
        Ok(())
    }
}

/// What a channel waits on at its sync point.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum WaitOn {
    /// Another channel (0-based).
    Channel(usize),
    /// The bar feeder (it has supplied the target's works).
    BarFeeder,
}

impl fmt::Display for WaitOn {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            WaitOn::Channel(c) => write!(f, "CH{}", c + 1),
            WaitOn::BarFeeder => f.write_str("BAR FEEDER"),
        }
    }
}

/// A work passing from a chuck to another (`from` None: the bar feeder; `to` None: the
/// unloader). Both chucks are closed on the work at the handover: the receiver closes first,
/// then the giver opens, in one step of the table.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Transfer {
    /// Machine time, ns.
    pub t: u64,
    /// The giving channel.
    pub from: Option<usize>,
    /// The receiving channel.
    pub to: Option<usize>,
    /// The work's number (1 = the first the bar feeder supplied).
    pub work: u32,
    /// No chuck let go of the work before the next held it: between chucks the receiver
    /// closed and the giver was closed until then (the table hands over only from a closed
    /// chuck, so this is always true there); from the bar feeder the receiver closed; to the
    /// unloader the giving chuck was closed when M11 opened it.
    pub both_closed: bool,
}

/// A channel at its sync point as the kernel sees it at the time of a resolution.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AtPoint {
    /// The sync point.
    pub point: Sync,
    /// It may go on: not held, not faulted. A channel that may not still counts as arrived
    /// at a waiting M code, but takes no part in a handover.
    pub can_go: bool,
    /// Its spindle as commanded: signed rpm (M3 +, M4 -), 0 when stopped (M5, M30, M19). A
    /// chuck closes or opens only on a stopped spindle, or in a handover between two
    /// spindles turning together (seed 004: the receiving spindle turns in the same direction
    /// at a speed synchronised with the giving one's).
    pub spindle: f64,
}

/// Two spindles turn together: both stopped, or the same direction at the same speed (to
/// half a percent, or 1 rpm).
fn together(a: f64, b: f64) -> bool {
    (a.abs() < 0.5 && b.abs() < 0.5)
        || (a.signum() == b.signum() && (a - b).abs() <= (0.005 * a.abs()).max(1.0))
}

/// A commanded spindle in words: `1500 rpm M3`, `stopped`.
fn turning(rpm: f64) -> String {
    if rpm.abs() < 0.5 {
        "stopped".into()
    } else {
        format!(
            "{:.0} rpm {}",
            rpm.abs(),
            if rpm > 0.0 { "M3" } else { "M4" }
        )
    }
}

/// What the table decides for a channel at its sync point.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Decision {
    /// It goes on.
    Release,
    /// The sync point cannot be run on this machine: alarm.
    Refuse(String),
}

/// One channel's row.
#[derive(Clone, Debug, Default)]
struct Seat {
    work: Option<u32>,
    closed: bool,
    parts: u32,
    /// Arrivals per waiting M code (m, count).
    arrivals: Vec<(u32, u64)>,
    /// The arrivals when the current cycle began (RESET returns to them).
    cycle_arrivals: Vec<(u32, u64)>,
    /// The arrival number at the waiting M code it stands at.
    wait_n: Option<u64>,
    waits: Option<WaitOn>,
    /// The work it cut in its current cycle (counted once per cycle).
    cycle_cut: Option<u32>,
}

impl Seat {
    fn arrived(&self, m: u32) -> u64 {
        self.arrivals.iter().find(|a| a.0 == m).map_or(0, |a| a.1)
    }
}

/// The sync table of a kernel of N channels.
#[derive(Clone, Debug)]
pub struct SyncTable {
    flow: Option<WorkFlow>,
    seats: Vec<Seat>,
    target: u32,
    supplied: u32,
    delivered: u32,
    transfers: Vec<Transfer>,
    /// Per work (index id-1): how many cycles each channel cut it.
    machined: Vec<Vec<u32>>,
}

impl SyncTable {
    /// The table of `channels` channels with this work flow (None: no chucks, e.g. a mill:
    /// M10 and M11 are refused and nothing is interlocked), to `target` parts.
    pub fn new(channels: usize, flow: Option<WorkFlow>, target: u32) -> SyncTable {
        SyncTable {
            flow,
            seats: vec![Seat::default(); channels],
            target,
            supplied: 0,
            delivered: 0,
            transfers: Vec::new(),
            machined: Vec::new(),
        }
    }

    /// Whether the operator loads the works by hand ([`WorkFlow::manual`]).
    pub fn manual(&self) -> bool {
        self.flow.as_ref().is_some_and(|f| f.manual)
    }

    /// Loading by hand, at the start of a cycle (time `t`): the operator puts a new work in
    /// the empty chuck of the one channel and closes it, while the target wants more.
    pub fn load_by_hand(&mut self, t: u64) {
        if !self.manual() || self.supplied >= self.target {
            return;
        }
        let Some(s) = self.seats.first_mut() else {
            return;
        };
        if s.work.is_some() {
            return;
        }
        self.supplied += 1;
        let w = self.supplied;
        s.work = Some(w);
        s.closed = true;
        self.transfers.push(Transfer {
            t,
            from: None,
            to: Some(0),
            work: w,
            both_closed: true,
        });
    }

    /// Whether the machine has chucks and a work flow.
    pub fn has_flow(&self) -> bool {
        self.flow.is_some()
    }

    /// Channel `ch` arrives at `point`: a waiting M code counts the arrival, so that a channel
    /// lapping round to the same code again does not meet the previous round.
    pub fn arrive(&mut self, ch: usize, point: Sync) {
        let Some(s) = self.seats.get_mut(ch) else {
            return;
        };
        s.waits = None;
        s.wait_n = None;
        if let Sync::Wait { m, .. } = point {
            let n = match s.arrivals.iter_mut().find(|a| a.0 == m) {
                Some(a) => {
                    a.1 += 1;
                    a.1
                }
                None => {
                    s.arrivals.push((m, 1));
                    1
                }
            };
            s.wait_n = Some(n);
        }
    }

    /// Decides, at time `t`, for every channel at a sync point (`at[ch]`, None for a channel
    /// not at one), which go on, until nothing more changes. Channels neither released nor
    /// refused wait (their [`SyncTable::waits_on`] says on what).
    pub fn resolve(&mut self, t: u64, at: &[Option<AtPoint>]) -> Vec<(usize, Decision)> {
        let n = self.seats.len().min(at.len());
        let mut out: Vec<(usize, Decision)> = Vec::new();
        let mut open: Vec<bool> = (0..n).map(|i| at[i].is_some()).collect();
        loop {
            let mut changed = false;
            for i in 0..n {
                let Some(p) = at[i].filter(|_| open[i]) else {
                    continue;
                };
                if !p.can_go {
                    continue;
                }
                let step = self.decide(t, i, p.point, at, &open);
                let mut done = Vec::new();
                match step {
                    Step::Wait(w) => self.seats[i].waits = Some(w),
                    Step::Go => done.push((i, Decision::Release)),
                    Step::Both(other) => {
                        done.push((i, Decision::Release));
                        done.push((other, Decision::Release));
                    }
                    Step::Refuse(why) => done.push((i, Decision::Refuse(why))),
                }
                for (k, d) in done {
                    self.seats[k].waits = None;
                    open[k] = false;
                    out.push((k, d));
                    changed = true;
                }
            }
            if !changed {
                return out;
            }
        }
    }

    fn decide(
        &mut self,
        t: u64,
        i: usize,
        point: Sync,
        at: &[Option<AtPoint>],
        open: &[bool],
    ) -> Step {
        // Another channel standing at `want` and free to take part in a handover.
        let ready = |o: usize, want: Sync| {
            open.get(o).copied().unwrap_or(false)
                && at
                    .get(o)
                    .copied()
                    .flatten()
                    .is_some_and(|p| p.point == want && p.can_go)
        };
        match point {
            Sync::Wait { m, with } => {
                let n = self.seats[i].wait_n.unwrap_or(1);
                for (c, s) in self.seats.iter().enumerate() {
                    let listed = c < 8 && (with >> c) & 1 == 1;
                    if listed && s.arrived(m) < n {
                        return Step::Wait(WaitOn::Channel(c));
                    }
                }
                Step::Go
            }
            Sync::ChuckClose | Sync::ChuckOpen if self.flow.is_none() => Step::Refuse(format!(
                "M{}: this machine has no chuck",
                if point == Sync::ChuckClose { 10 } else { 11 }
            )),
            Sync::ChuckClose | Sync::ChuckOpen if self.manual() => Step::Refuse(format!(
                "M{}: the operator loads this lathe by hand (loading manual); its program does not work the chuck",
                if point == Sync::ChuckClose { 10 } else { 11 }
            )),
            Sync::ChuckClose | Sync::ChuckOpen if !self.may_work_chuck(i, point, at, open) => {
                Step::Refuse(self.chuck_refusal(i, point, at))
            }
            Sync::ChuckClose => {
                if self.seats[i].work.is_some() {
                    self.seats[i].closed = true;
                    return Step::Go;
                }
                let Some(flow) = &self.flow else {
                    return Step::Refuse("M10: this machine has no chuck".into());
                };
                match flow.supplier_of(i) {
                    None if i == flow.supplier => {
                        if self.supplied >= self.target {
                            return Step::Wait(WaitOn::BarFeeder);
                        }
                        self.supplied += 1;
                        let w = self.supplied;
                        let s = &mut self.seats[i];
                        s.work = Some(w);
                        s.closed = true;
                        self.transfers.push(Transfer {
                            t,
                            from: None,
                            to: Some(i),
                            work: w,
                            both_closed: true,
                        });
                        Step::Go
                    }
                    None => Step::Refuse(format!(
                        "M10 on an empty spindle: CH{} has no supplier",
                        i + 1
                    )),
                    Some(p) => {
                        if ready(p, Sync::ChuckOpen) && self.can_hand(p) {
                            self.hand_over(t, p, i);
                            Step::Both(p)
                        } else {
                            Step::Wait(WaitOn::Channel(p))
                        }
                    }
                }
            }
            Sync::ChuckOpen => {
                let Some(w) = self.seats[i].work else {
                    self.seats[i].closed = false;
                    return Step::Go;
                };
                let Some(flow) = &self.flow else {
                    return Step::Refuse("M11: this machine has no chuck".into());
                };
                match flow.receiver_of(i) {
                    None if i == flow.unloader => {
                        self.delivered += 1;
                        let s = &mut self.seats[i];
                        let both_closed = s.closed;
                        s.work = None;
                        s.closed = false;
                        self.transfers.push(Transfer {
                            t,
                            from: Some(i),
                            to: None,
                            work: w,
                            both_closed,
                        });
                        Step::Go
                    }
                    None => {
                        Step::Refuse(format!("M11 holding work {w}: CH{} has no receiver", i + 1))
                    }
                    Some(r) => {
                        if ready(r, Sync::ChuckClose)
                            && self.seats[r].work.is_none()
                            && self.can_hand(i)
                        {
                            self.hand_over(t, i, r);
                            Step::Both(r)
                        } else {
                            Step::Wait(WaitOn::Channel(r))
                        }
                    }
                }
            }
        }
    }

    /// The chuck interlock at channel `i`'s M10 or M11: its spindle is stopped, or the chuck
    /// acts in a handover with a partner standing ready whose spindle turns together with it.
    /// (With the partner not yet there, the channel waits; the partner's arrival decides.)
    fn may_work_chuck(&self, i: usize, point: Sync, at: &[Option<AtPoint>], open: &[bool]) -> bool {
        let me = at.get(i).copied().flatten().map_or(0.0, |p| p.spindle);
        let partner = self.handover_partner(i, point);
        match partner {
            Some(o) if open.get(o).copied().unwrap_or(false) => {
                match at.get(o).copied().flatten() {
                    Some(p) if p.can_go && p.point != point => together(me, p.spindle),
                    // Not at its side of the handover yet: this one waits for it (decided then).
                    _ => true,
                }
            }
            Some(_) => true,
            None => me.abs() < 0.5,
        }
    }

    /// The other chuck of the handover channel `i`'s chuck point takes part in: its supplier
    /// at M10 on an empty chuck, its receiver at M11 holding a work. None: the chuck acts
    /// alone (the bar feeder, the unloader, a work already held, an empty chuck opening).
    fn handover_partner(&self, i: usize, point: Sync) -> Option<usize> {
        let flow = self.flow.as_ref()?;
        let holds = self.seats.get(i)?.work.is_some();
        match point {
            Sync::ChuckClose if !holds => flow.supplier_of(i),
            Sync::ChuckOpen if holds => flow.receiver_of(i),
            _ => None,
        }
    }

    /// Why the chuck interlock refuses channel `i`'s M10 or M11.
    fn chuck_refusal(&self, i: usize, point: Sync, at: &[Option<AtPoint>]) -> String {
        let m = if point == Sync::ChuckClose { 10 } else { 11 };
        let spindle = |c: usize| at.get(c).copied().flatten().map_or(0.0, |p| p.spindle);
        match self.handover_partner(i, point) {
            Some(o) => format!(
                "M{m}: the spindles of the handover do not turn together (CH{} {}, CH{} {}): both stopped, or the same direction and speed",
                i + 1,
                turning(spindle(i)),
                o + 1,
                turning(spindle(o))
            ),
            None => format!(
                "M{m}: the spindle of CH{} turns ({}): a chuck closes and opens on a stopped spindle (give M05 first)",
                i + 1,
                turning(spindle(i))
            ),
        }
    }

    /// Channel `from` holds a work in a closed chuck.
    fn can_hand(&self, from: usize) -> bool {
        let s = &self.seats[from];
        s.work.is_some() && s.closed
    }

    /// The receiver closes on the giver's work, then the giver opens: one step.
    fn hand_over(&mut self, t: u64, from: usize, to: usize) {
        let Some(w) = self.seats[from].work.take() else {
            return;
        };
        let both_closed = std::mem::replace(&mut self.seats[from].closed, false);
        let r = &mut self.seats[to];
        r.work = Some(w);
        r.closed = true;
        self.transfers.push(Transfer {
            t,
            from: Some(from),
            to: Some(to),
            work: w,
            both_closed,
        });
    }

    /// Channel `ch` reached its program's end (M2/M30): it counts its work. True when its
    /// count has reached the target (the channel has finished); otherwise its next cycle
    /// begins.
    /// Loading by hand (at time `t`), the work is taken out and the next one put in.
    pub fn program_end(&mut self, ch: usize, t: u64) -> bool {
        let target = self.target;
        let manual = self.manual();
        let Some(s) = self.seats.get_mut(ch) else {
            return true;
        };
        s.parts += 1;
        s.cycle_arrivals = s.arrivals.clone();
        s.cycle_cut = None;
        let done = s.parts >= target;
        if manual {
            if let Some(w) = s.work.take() {
                let both_closed = std::mem::replace(&mut s.closed, false);
                self.delivered += 1;
                self.transfers.push(Transfer {
                    t,
                    from: Some(ch),
                    to: None,
                    work: w,
                    both_closed,
                });
            }
            if !done {
                self.load_by_hand(t);
            }
        }
        done
    }

    /// RESET of channel `ch` abandoned its run: it returns to the start of its cycle (its
    /// waiting M codes counted as when the cycle began), keeping its work and its count.
    pub fn reset(&mut self, ch: usize) {
        if let Some(s) = self.seats.get_mut(ch) {
            s.arrivals = s.cycle_arrivals.clone();
            s.wait_n = None;
            s.waits = None;
        }
    }

    /// Channel `ch` left its sync point other than by a release (E-STOP, RESET).
    pub fn leave(&mut self, ch: usize) {
        if let Some(s) = self.seats.get_mut(ch) {
            s.waits = None;
        }
    }

    /// Channel `ch` started a cutting block: notes which work it cuts in this cycle.
    pub fn cut(&mut self, ch: usize) {
        let n = self.seats.len();
        let Some(s) = self.seats.get_mut(ch) else {
            return;
        };
        let Some(w) = s.work else { return };
        if s.cycle_cut == Some(w) {
            return;
        }
        s.cycle_cut = Some(w);
        let idx = (w as usize).saturating_sub(1);
        if self.machined.len() <= idx {
            self.machined.resize(idx + 1, Vec::new());
        }
        let row = &mut self.machined[idx];
        row.resize(n, 0);
        row[ch] += 1;
    }

    /// The chuck interlock of channel `ch`: why a cut is refused now (None: it may cut).
    /// Without a work flow nothing is interlocked.
    pub fn interlock(&self, ch: usize) -> Option<String> {
        self.flow.as_ref()?;
        let s = self.seats.get(ch)?;
        if s.work.is_none() {
            Some(format!("no work in the spindle of CH{}", ch + 1))
        } else if !s.closed {
            Some(format!("the chuck of CH{} is open", ch + 1))
        } else {
            None
        }
    }

    /// The work channel `ch`'s chuck holds, and whether it is closed.
    pub fn work(&self, ch: usize) -> (Option<u32>, bool) {
        self.seats
            .get(ch)
            .map_or((None, false), |s| (s.work, s.closed))
    }

    /// What channel `ch` waits on at its sync point.
    pub fn waits_on(&self, ch: usize) -> Option<WaitOn> {
        self.seats.get(ch).and_then(|s| s.waits)
    }

    /// Parts channel `ch` has counted.
    pub fn parts(&self, ch: usize) -> u32 {
        self.seats.get(ch).map_or(0, |s| s.parts)
    }

    /// The part target.
    pub fn target(&self) -> u32 {
        self.target
    }

    /// Sets the part target; refused below the works already supplied.
    pub fn set_target(&mut self, n: u32) -> Result<(), String> {
        if n < self.supplied {
            return Err(format!(
                "target {n}: the bar feeder has already supplied {} works",
                self.supplied
            ));
        }
        self.target = n;
        Ok(())
    }

    /// Works the bar feeder supplied.
    pub fn supplied(&self) -> u32 {
        self.supplied
    }

    /// Parts delivered to the unloader.
    pub fn delivered(&self) -> u32 {
        self.delivered
    }

    /// Every handover so far, in order.
    pub fn transfers(&self) -> &[Transfer] {
        &self.transfers
    }

    /// How many cycles each channel cut work `id` (index = channel).
    pub fn machined(&self, id: u32) -> Vec<u32> {
        let i = (id as usize).wrapping_sub(1);
        self.machined.get(i).cloned().unwrap_or_default()
    }

    /// Every chuck holding a work: (work, channel).
    pub fn works(&self) -> Vec<(u32, usize)> {
        self.seats
            .iter()
            .enumerate()
            .filter_map(|(i, s)| s.work.map(|w| (w, i)))
            .collect()
    }
}

/// One channel's outcome in a pass of [`SyncTable::resolve`].
enum Step {
    Wait(WaitOn),
    Go,
    /// A handover: this channel and the other go on.
    Both(usize),
    Refuse(String),
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_table_of_more_channels_than_the_mask_holds_waits_only_on_those_listed() {
        let mut t = SyncTable::new(9, None, 1);
        let w = Sync::Wait { m: 100, with: 0b1 };
        t.arrive(0, w);
        let mut at = vec![None; 9];
        at[0] = Some(AtPoint {
            point: w,
            can_go: true,
            spindle: 0.0,
        });
        assert_eq!(t.resolve(0, &at), vec![(0, Decision::Release)]);
    }
}
