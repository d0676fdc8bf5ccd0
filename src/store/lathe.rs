//! A lathe's part of the one store (docs/stores.md "A lathe's stores"): each channel's program,
//! each channel's tools as revised at the OFS page, and the part counter, kept in
//! `STATE/lathe-NAME/` by the same journal, snapshot and recovery as the centre's stores. Every
//! change is one journal record (`chprog`, `chtools`, `parts`), fsynced before it is
//! acknowledged and replayed at start; the snapshot holds the same records under its own
//! header (`novanc-lathe 2 GEN CHANNELS`). This replaces the lathe's own store, which rewrote
//! whole files (`chN.prog`, `chN.tools`, `parts`); those are read once, to migrate them
//! (`store::lathe_old`).

use super::frame;
use super::record::Record;
use super::state::{Base, Refusal};
use super::{fsutil, StoreError, Stores};
use crate::lathe::desc::{parse_tool, tool_line, LatheDesc, ToolDesc};
use novanc_editor::Outcome;
use std::path::Path;

/// The embedded sample programs of the Citizen lathe, one per channel.
pub const CITIZEN_PROGRAMS: [(&str, &str); 3] = [
    (
        "SYSTEM1.NGC",
        include_str!("../../programs/citizen/system1.ngc"),
    ),
    (
        "SYSTEM2.NGC",
        include_str!("../../programs/citizen/system2.ngc"),
    ),
    (
        "SYSTEM3.NGC",
        include_str!("../../programs/citizen/system3.ngc"),
    ),
];

/// Longest program a channel keeps, bytes.
pub const MAX_PROGRAM: usize = 1 << 20;

/// Longest program name, bytes.
pub const MAX_NAME: usize = 64;

/// The part counter: a target set at the console and each channel's count of finished works.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Counter {
    /// The number of parts to make (1 to 999999).
    pub target: u32,
    /// Works each channel has finished in this batch.
    pub counts: Vec<u32>,
}

impl Counter {
    /// A new batch of 5 parts, none made, on `channels` channels.
    pub fn fresh(channels: usize) -> Counter {
        Counter {
            target: 5,
            counts: vec![0; channels],
        }
    }
}

/// One channel's program: its name and text.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Program {
    /// The name the display shows (`SYSTEM1.NGC`).
    pub name: String,
    /// The text.
    pub text: String,
    /// The G-code dialect it is written in (the channel's when it was stored); `None`: not
    /// recorded (a program stored before programs kept their dialect, or a sample), read in
    /// the channel's at each run.
    pub dialect: Option<crate::settings::Dialect>,
}

impl Program {
    /// The empty program channel `ch` (0-based) starts with when it has none.
    pub fn empty(ch: usize) -> Program {
        Program {
            name: format!("CH{}.NGC", ch + 1),
            text: String::new(),
            dialect: None,
        }
    }

    /// Why the store refuses this program, if it does.
    pub fn check(&self) -> Result<(), String> {
        if self.name.is_empty() || self.name.len() > MAX_NAME || self.name.contains('\n') {
            return Err(format!(
                "the name is empty, longer than {MAX_NAME} bytes or more than one line"
            ));
        }
        if self.text.len() > MAX_PROGRAM {
            return Err(format!("the program is longer than {MAX_PROGRAM} bytes"));
        }
        Ok(())
    }
}

/// A lathe's stores in memory.
#[derive(Clone, Debug, PartialEq)]
pub struct LatheState {
    /// Each channel's program.
    pub programs: Vec<Program>,
    /// Each channel's tools as last revised at the console (`None`: the description's).
    pub tools: Vec<Option<Vec<ToolDesc>>>,
    /// The part counter.
    pub counter: Counter,
    /// Each channel's kept parameters (#500–#999), in millionths; a vacant one is not held.
    pub params: Vec<std::collections::BTreeMap<u16, i64>>,
    /// Each channel's MDI buffer: the lines typed and not yet run, each ended by a line break.
    pub mdi: Vec<String>,
    /// Each channel's editor pointer in its program, characters from the start.
    pub pointers: Vec<usize>,
    /// Each channel's jog feed chosen on POS: the feed in millionths of a mm/min (None: the
    /// machine's) and rapid jog.
    pub jogs: Vec<(Option<i64>, bool)>,
    /// Where each channel's tool post stands, and whether it was moving when this was stored
    /// (its position memory; None: never stored, the posts start at the top of their travel).
    pub posts: Option<Vec<Post>>,
}

/// One tool post in a lathe's position memory (docs/stores.md "A lathe's stores").
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Post {
    /// It was moving (or its position was not known) when stored: not to be trusted.
    pub moving: bool,
    /// Machine position, pulses [X radius, Z].
    pub pos: [i64; 2],
}

/// The most lines a lathe channel's MDI buffer holds.
pub const MAX_MDI_LINES: usize = 64;

/// The parameters a lathe channel keeps in the stores: the Fanuc dialect's #500–#999 (and its
/// work offsets, [`kept_param`]).
pub const KEPT_PARAMS: std::ops::RangeInclusive<usize> = 500..=999;

/// Whether a lathe channel keeps parameter `n` in the stores: #500–#999 and the parameters of
/// its work offsets G54–G59 (`crate::lathe::gcode::work_params`, LinuxCNC's #5221–).
pub fn kept_param(n: usize) -> bool {
    KEPT_PARAMS.contains(&n) || crate::lathe::gcode::all_work_params().any(|w| w == n)
}

/// Every parameter a lathe channel keeps in the stores.
pub fn kept_params() -> impl Iterator<Item = usize> {
    KEPT_PARAMS.chain(crate::lathe::gcode::all_work_params())
}

/// The tool lines of a table, as the journal and the snapshot keep them.
pub fn tools_text(tools: &[ToolDesc]) -> String {
    tools.iter().map(|t| tool_line(t) + "\n").collect()
}

/// Reads tool lines (`tool N radius R tip P offset X Z`); the error names the line.
pub fn parse_tools(text: &str) -> Result<Vec<ToolDesc>, String> {
    text.lines()
        .enumerate()
        .map(|(i, l)| parse_tool(l).map_err(|e| format!("line {}: {e}", i + 1)))
        .collect()
}

impl LatheState {
    /// What a lathe of `desc` holds before anything is stored: the Citizen's sample programs
    /// (other machines' channels start empty), the description's tools, 0 of 5 parts.
    pub fn defaults(desc: &LatheDesc) -> LatheState {
        let n = desc.channels.len();
        LatheState {
            programs: (0..n)
                .map(|ch| match (desc.name.as_str(), CITIZEN_PROGRAMS.get(ch)) {
                    ("citizen", Some((name, text))) => Program {
                        name: name.to_string(),
                        text: text.to_string(),
                        dialect: None,
                    },
                    _ => Program::empty(ch),
                })
                .collect(),
            tools: vec![None; n],
            counter: Counter::fresh(n),
            params: vec![Default::default(); n],
            mdi: vec![String::new(); n],
            pointers: vec![0; n],
            jogs: vec![(None, false); n],
            posts: None,
        }
    }

    /// The records that rebuild this state (the snapshot's body).
    pub fn records(&self) -> Vec<Record> {
        let mut out = Vec::new();
        for (ch, p) in self.programs.iter().enumerate() {
            out.push(Record::ChannelProgram {
                ch,
                name: p.name.clone(),
                text: p.text.clone(),
                dialect: p.dialect,
            });
        }
        for (ch, t) in self.tools.iter().enumerate() {
            out.push(Record::ChannelTools {
                ch,
                text: t.as_deref().map(tools_text),
            });
        }
        for (ch, ps) in self.params.iter().enumerate() {
            if !ps.is_empty() {
                out.push(Record::ChannelParams {
                    ch,
                    params: ps.iter().map(|(&n, &v)| (n, v)).collect(),
                });
            }
        }
        for (ch, &at) in self.pointers.iter().enumerate() {
            if at > 0 {
                out.push(Record::ChannelPointer { ch, at });
            }
        }
        for (ch, &(feed, rapid)) in self.jogs.iter().enumerate() {
            if (feed, rapid) != (None, false) {
                out.push(Record::ChannelJog { ch, feed, rapid });
            }
        }
        if let Some(posts) = &self.posts {
            out.push(Record::Posts(posts.clone()));
        }
        for (ch, text) in self.mdi.iter().enumerate() {
            if !text.is_empty() {
                out.push(Record::ChannelMdi {
                    ch,
                    text: text.clone(),
                });
            }
        }
        out.push(Record::Parts {
            target: self.counter.target,
            counts: self.counter.counts.clone(),
        });
        out
    }

    /// Applies a lathe record; whether anything changed. A refused record changes nothing.
    pub fn apply(&mut self, rec: &Record) -> Result<(Outcome, bool), Refusal> {
        let n = self.programs.len();
        let chan = |ch: usize| match ch < n {
            true => Ok(ch),
            false => Err(Refusal::Other(format!(
                "channel {} is not one of this lathe's {n}",
                ch + 1
            ))),
        };
        let changed = match rec {
            Record::ChannelProgram {
                ch,
                name,
                text,
                dialect,
            } => {
                let ch = chan(*ch)?;
                let p = Program {
                    name: name.clone(),
                    text: text.clone(),
                    dialect: *dialect,
                };
                p.check().map_err(Refusal::Other)?;
                let changed = self.programs[ch] != p;
                // A pointer past the new text's end stands at its end.
                let len = p.text.chars().count();
                self.pointers[ch] = self.pointers[ch].min(len);
                self.programs[ch] = p;
                changed
            }
            Record::ChannelTools { ch, text } => {
                let ch = chan(*ch)?;
                let tools = match text {
                    Some(t) => Some(parse_tools(t).map_err(Refusal::Other)?),
                    None => None,
                };
                let changed = self.tools[ch] != tools;
                self.tools[ch] = tools;
                changed
            }
            Record::ChannelParams { ch, params } => {
                let ch = chan(*ch)?;
                if let Some((n, _)) = params.iter().find(|(n, _)| !kept_param(usize::from(*n))) {
                    return Err(Refusal::Other(format!(
                        "#{n} is not a parameter a lathe channel keeps (#500-#999, the work offsets #5221-)"
                    )));
                }
                if let Some((n, v)) = params
                    .iter()
                    .find(|(_, v)| v.abs() > super::state::PARAM_LIMIT)
                {
                    return Err(Refusal::Other(format!(
                        "#{n} = {v} millionths is beyond the stores' limit"
                    )));
                }
                let kept = &mut self.params[ch];
                let mut changed = false;
                for &(n, v) in params {
                    changed |= kept.get(&n).copied().unwrap_or(0) != v;
                    if v == 0 {
                        kept.remove(&n);
                    } else {
                        kept.insert(n, v);
                    }
                }
                changed
            }
            Record::ChannelPointer { ch, at } => {
                let ch = chan(*ch)?;
                let len = self.programs[ch].text.chars().count();
                if *at > len {
                    return Err(Refusal::Other(format!(
                        "a pointer at {at} is past channel {}'s program of {len} characters",
                        ch + 1
                    )));
                }
                let changed = self.pointers[ch] != *at;
                self.pointers[ch] = *at;
                changed
            }
            Record::ChannelMdi { ch, text } => {
                let ch = chan(*ch)?;
                if text.len() > MAX_PROGRAM
                    || text.lines().count() > MAX_MDI_LINES
                    || !(text.is_empty() || text.ends_with('\n'))
                {
                    return Err(Refusal::Other(format!(
                        "an MDI buffer is at most {MAX_MDI_LINES} whole lines"
                    )));
                }
                let changed = self.mdi[ch] != *text;
                self.mdi[ch] = text.clone();
                changed
            }
            Record::ChannelJog { ch, feed, rapid } => {
                let ch = chan(*ch)?;
                if let Some(f) = feed.filter(|f| !(1..=super::state::PARAM_LIMIT).contains(f)) {
                    return Err(Refusal::Other(format!(
                        "a jog feed of {f} millionths of a mm/min is not one"
                    )));
                }
                let changed = self.jogs[ch] != (*feed, *rapid);
                self.jogs[ch] = (*feed, *rapid);
                changed
            }
            Record::Posts(posts) => {
                if posts.len() != n {
                    return Err(Refusal::Other(format!(
                        "{} tool posts for this lathe's {n} channels",
                        posts.len()
                    )));
                }
                let changed = self.posts.as_ref() != Some(posts);
                self.posts = Some(posts.clone());
                changed
            }
            Record::Parts { target, counts } => {
                if !(1..=999_999).contains(target) {
                    return Err(Refusal::Other(format!(
                        "the part target {target} is not a number of parts from 1 to 999999"
                    )));
                }
                if counts.len() != n {
                    return Err(Refusal::Other(format!(
                        "the part counter has {} counts for {n} channels",
                        counts.len()
                    )));
                }
                let c = Counter {
                    target: *target,
                    counts: counts.clone(),
                };
                let changed = self.counter != c;
                self.counter = c;
                changed
            }
            _ => {
                return Err(Refusal::Other(
                    "a record of the centre's stores is not kept in a lathe's".to_string(),
                ))
            }
        };
        Ok((Outcome::default(), changed))
    }
}

/// The snapshot of a lathe's state at generation `gen` (format 2: every record twice).
pub fn encode_snapshot(l: &LatheState, gen: u64) -> Vec<u8> {
    let mut out = Vec::new();
    let mut put = |p: String| out.extend(frame::encode_pair(p.as_bytes()));
    put(format!("novanc-lathe 2 {gen} {}", l.programs.len()));
    for r in l.records() {
        put(r.encode());
    }
    put("end".to_string());
    out
}

/// What reading a lathe's snapshot found (as `snapshot::SnapRead`).
pub struct LatheSnapRead {
    /// The generation in the header.
    pub gen: Option<u64>,
    /// The state read, whole or salvaged.
    pub state: LatheState,
    /// Damaged copies whose other copy was used.
    pub repaired: Vec<String>,
    /// Damage nothing could make good, and what was lost because of it.
    pub lost: Vec<String>,
    /// Whether no record at all could be read.
    pub nothing: bool,
}

/// Reads a lathe's snapshot onto `base` (the lathe's defaults). Never fails: a record damaged
/// in one copy is read from the other; what is lost in both is said in `lost` and stands
/// in as when nothing was stored, except a lost program, which starts empty (a sample never
/// takes the place of the operator's program).
pub fn read_snapshot(data: &[u8], base: &LatheState) -> LatheSnapRead {
    let d = frame::decode_paired(data);
    let where_ =
        |d: &frame::Damage| format!("record {} at byte {}: {}", d.record + 1, d.offset, d.reason);
    let repaired: Vec<String> = d.repaired.iter().map(where_).collect();
    let mut lost = Vec::new();
    if let Some(dmg) = &d.damage {
        let after = if d.after.is_empty() {
            "nothing after it could be read".to_string()
        } else {
            format!("{} records after it were read", d.after.len())
        };
        lost.push(format!("{}, in both copies; {after}", where_(dmg)));
    }
    let damaged = !lost.is_empty();
    let mut records = d.records;
    records.extend(d.after);
    let nothing = records.is_empty();
    let n = base.programs.len();
    let mut state = base.clone();
    let (mut gen, mut end) = (None, false);
    let mut seen_prog = vec![false; n];
    let mut seen_tools = vec![false; n];
    let mut seen_parts = false;
    for (i, r) in records.iter().enumerate() {
        let Ok(r) = std::str::from_utf8(r) else {
            lost.push("a record that is not text".to_string());
            continue;
        };
        if i == 0 {
            let f: Vec<&str> = r.split(' ').collect();
            if let ["novanc-lathe", "2", g, c] = f.as_slice() {
                match g.parse::<u64>() {
                    Ok(g) => gen = Some(g),
                    Err(_) => lost.push(format!("the header '{r}' does not read")),
                }
                if c.parse() != Ok(n) {
                    // The description changed: what does not fit is refused below.
                    lost.push(format!("the header says {c} channels; this lathe has {n}"));
                }
            }
            if gen.is_some() || r.starts_with("novanc-lathe ") {
                continue;
            }
        }
        if r == "end" {
            end = true;
            continue;
        }
        match Record::decode(r) {
            Ok(rec) => {
                let seen = match &rec {
                    Record::ChannelProgram { ch, .. } => seen_prog.get_mut(*ch),
                    Record::ChannelTools { ch, .. } => seen_tools.get_mut(*ch),
                    Record::Parts { .. } => Some(&mut seen_parts),
                    _ => None,
                };
                match state.apply(&rec) {
                    Ok(_) => {
                        if let Some(s) = seen {
                            *s = true;
                        }
                    }
                    Err(e) => lost.push(format!("a record that does not apply ({})", e.text())),
                }
            }
            Err(e) => lost.push(format!("a record that does not read ({e})")),
        }
    }
    if nothing {
        return LatheSnapRead {
            gen,
            state: base.clone(),
            repaired,
            lost,
            nothing,
        };
    }
    if gen.is_none() {
        lost.push("the header (its generation is unknown)".to_string());
    }
    if !end && !damaged {
        lost.push("the end of the file (it is cut short)".to_string());
    }
    for ch in 0..n {
        if !seen_prog[ch] {
            state.programs[ch] = Program::empty(ch);
            lost.push(format!("channel {}'s program (it starts empty)", ch + 1));
        }
        if !seen_tools[ch] {
            state.tools[ch] = None;
            lost.push(format!(
                "channel {}'s tool revisions (the description's tools apply: check the offsets on the OFS page before START)",
                ch + 1
            ));
        }
    }
    if !seen_parts {
        state.counter = Counter::fresh(n);
        lost.push("the part counter (it starts at 0 of 5)".to_string());
    }
    LatheSnapRead {
        gen,
        state,
        repaired,
        lost,
        nothing,
    }
}

/// The lathe stores of one machine, as the lathe console uses them: the one store opened on
/// `STATE/lathe-NAME/`.
pub struct LatheStore {
    stores: Stores,
}

impl std::fmt::Debug for LatheStore {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "LatheStore({})", self.stores.dir().display())
    }
}

/// What the stores held when opened.
#[derive(Debug)]
pub struct Opened {
    /// The stores.
    pub store: LatheStore,
    /// Each channel's program.
    pub programs: Vec<Program>,
    /// The part counter.
    pub counter: Counter,
    /// Each channel's tools as last revised at the console (`None`: the description's).
    pub tools: Vec<Option<Vec<ToolDesc>>>,
    /// Each channel's kept parameters (#500–#999) that are not vacant, (number, value).
    pub params: Vec<Vec<(usize, f64)>>,
    /// Each channel's MDI buffer, its lines (typed and not yet run).
    pub mdi: Vec<Vec<String>>,
    /// Each channel's editor pointer in its program, characters from the start.
    pub pointers: Vec<usize>,
    /// Each channel's jog feed chosen on POS, mm/min (None: the machine's), and rapid jog.
    pub jogs: Vec<(Option<f64>, bool)>,
    /// Each channel's tool post as the position memory kept it (None: never kept).
    pub posts: Option<Vec<Post>>,
    /// What the operator should know (damage found and kept aside, a migration).
    pub warnings: Vec<String>,
}

/// What the command line reads of a lathe console's stores (`novanc run --machine LATHE
/// --state DIR`): each channel's tools as revised at OFS and its kept parameters (#500–#999
/// and the work offsets), read without locking or writing the directory, so a console may have
/// it open, as `store::MemoryView` reads the centre's.
#[derive(Clone, Debug)]
pub struct LatheView {
    /// Each channel's tools as last revised at the console (`None`: the description's).
    pub tools: Vec<Option<Vec<ToolDesc>>>,
    /// Each channel's kept parameters that are not vacant, (number, value).
    pub params: Vec<Vec<(usize, f64)>>,
    /// What the reading found (a damaged file read around, a journal tail skipped).
    pub warnings: Vec<String>,
}

impl LatheView {
    /// Reads `STATE/lathe-NAME/` as the console of `desc` would open it, without changing a
    /// byte; a directory with no lathe stores of that name is refused (a name mistyped must
    /// not run on the description's offsets unsaid).
    pub fn read(state: &Path, desc: &LatheDesc) -> Result<LatheView, String> {
        fsutil::check_file_name(&desc.name).map_err(|e| format!("machine name {e}"))?;
        let dir = state.join(format!("lathe-{}", desc.name));
        if !dir.is_dir() {
            return Err(format!(
                "{} holds no stores of the lathe {} ({} is not a directory)",
                state.display(),
                desc.name,
                dir.display()
            ));
        }
        let l =
            super::load(&dir, &Base::Lathe(LatheState::defaults(desc))).map_err(|e| e.message)?;
        let warnings = l.notes.iter().map(|n| n.text.clone()).collect();
        let s = l.state.lathe.unwrap_or_else(|| LatheState::defaults(desc));
        Ok(LatheView {
            tools: s.tools,
            params: s.params.iter().map(super::params::params_of).collect(),
            warnings,
        })
    }
}

impl LatheStore {
    /// Opens (creating) `STATE/lathe-NAME/`, replaying its journal. A new store starts on the
    /// defaults (`LatheState::defaults`); a directory that has no journaled store yet but the
    /// files of the lathe's old store is migrated: those files are read once (damaged ones
    /// kept aside and said) and their contents become the first snapshot. A machine name
    /// that could name a path outside the state directory is refused.
    pub fn open(state: &Path, desc: &LatheDesc) -> Result<Opened, String> {
        fsutil::check_file_name(&desc.name).map_err(|e| format!("machine name {e}"))?;
        let dir = state.join(format!("lathe-{}", desc.name));
        fsutil::make_dir(&dir)?;
        let mut warnings = Vec::new();
        let mut base = LatheState::defaults(desc);
        if Stores::is_new(&dir) {
            if let Some(old) = super::lathe_old::read_old(&dir, desc, &base) {
                base = old.state;
                warnings.extend(old.warnings);
            }
        }
        let (stores, w) = Stores::open_base(&dir, Base::Lathe(base)).map_err(|e| e.message)?;
        warnings.extend(w);
        let l = stores
            .lathe()
            .cloned()
            .unwrap_or_else(|| LatheState::defaults(desc));
        Ok(Opened {
            store: LatheStore { stores },
            programs: l.programs,
            counter: l.counter,
            tools: l.tools,
            params: l.params.iter().map(super::params::params_of).collect(),
            pointers: l.pointers.clone(),
            jogs: (l.jogs.iter())
                .map(|&(f, rapid)| (f.map(|f| f as f64 / 1e6), rapid))
                .collect(),
            posts: l.posts.clone(),
            mdi: l
                .mdi
                .iter()
                .map(|t| t.lines().map(str::to_string).collect())
                .collect(),
            warnings,
        })
    }

    /// Stores channel `ch`'s kept parameters (#500–#999) together, as one journaled record,
    /// before it returns Ok; a vacant one (NaN) is 0, which the stores do not hold. Values
    /// that already stand are left out. A value that is not a number within the stores'
    /// limit refuses the whole change.
    pub fn save_params(&mut self, ch: usize, ps: &[(usize, f64)]) -> Result<(), String> {
        let kept = self.stores.lathe().and_then(|l| l.params.get(ch));
        let mut rec = Vec::with_capacity(ps.len());
        for &(n, v) in ps {
            let v = if v.is_nan() { 0.0 } else { v };
            let m = super::params::to_millionths(n, v)?;
            let k = u16::try_from(n).map_err(|_| format!("#{n} is not kept"))?;
            if kept.and_then(|p| p.get(&k)).copied().unwrap_or(0) != m {
                rec.retain(|&(j, _)| j != k);
                rec.push((k, m));
            }
        }
        if rec.is_empty() {
            return Ok(());
        }
        self.commit(Record::ChannelParams { ch, params: rec })
            .map_err(|e| {
                format!(
                    "channel {}: the parameters could not be stored: {e}",
                    ch + 1
                )
            })
    }

    /// Channel `ch`'s kept parameters as the stores hold them (number, value; a vacant one
    /// is not listed).
    pub fn params(&self, ch: usize) -> Vec<(usize, f64)> {
        self.stores
            .lathe()
            .and_then(|l| l.params.get(ch))
            .map(super::params::params_of)
            .unwrap_or_default()
    }

    /// Stores channel `ch`'s program; when this returns Ok it is on disk.
    pub fn save_program(&mut self, ch: usize, p: &Program) -> Result<(), String> {
        let rec = Record::ChannelProgram {
            ch,
            name: p.name.clone(),
            text: p.text.clone(),
            dialect: p.dialect,
        };
        self.commit(rec)
            .map_err(|e| format!("channel {}: the program could not be stored: {e}", ch + 1))
    }

    /// Stores channel `ch`'s tools.
    pub fn save_tools(&mut self, ch: usize, tools: &[ToolDesc]) -> Result<(), String> {
        let text = tools_text(tools);
        // What is stored must read back as it was given (a NaN, say, would not).
        if parse_tools(&text).ok().as_deref() != Some(tools) {
            return Err(format!(
                "channel {}: the tools could not be stored: they do not read back as given",
                ch + 1
            ));
        }
        let rec = Record::ChannelTools {
            ch,
            text: Some(text),
        };
        self.commit(rec)
            .map_err(|e| format!("channel {}: the tools could not be stored: {e}", ch + 1))
    }

    /// Stores channel `ch`'s MDI buffer, whole (empty: cleared); when this returns Ok it is
    /// on disk.
    pub fn save_mdi(&mut self, ch: usize, lines: &[String]) -> Result<(), String> {
        let text: String = lines.iter().map(|l| format!("{l}\n")).collect();
        if lines.iter().any(|l| l.contains('\n')) {
            return Err(format!("channel {}: an MDI line is one line", ch + 1));
        }
        self.commit(Record::ChannelMdi { ch, text }).map_err(|e| {
            format!(
                "channel {}: the MDI buffer could not be stored: {e}",
                ch + 1
            )
        })
    }

    /// Stores channel `ch`'s jog feed chosen on POS (`feed` mm/min, None: the machine's) and
    /// rapid jog, as one journaled record; when this returns Ok it is on disk.
    pub fn save_jog(&mut self, ch: usize, feed: Option<f64>, rapid: bool) -> Result<(), String> {
        let feed = feed.map(|f| (f * 1e6).round() as i64);
        self.commit(Record::ChannelJog { ch, feed, rapid })
            .map_err(|e| format!("the jog feed could not be stored: {e}"))
    }

    /// Stores where every tool post stands and which ones move (the position memory), as one
    /// journaled record; when this returns Ok it is on disk.
    pub fn save_posts(&mut self, posts: &[Post]) -> Result<(), String> {
        self.commit(Record::Posts(posts.to_vec()))
            .map_err(|e| format!("the tool posts' positions could not be stored: {e}"))
    }

    /// Stores channel `ch`'s editor pointer (characters from its program's start); when this
    /// returns Ok it is on disk.
    pub fn save_pointer(&mut self, ch: usize, at: usize) -> Result<(), String> {
        if self.stores.lathe().and_then(|l| l.pointers.get(ch)) == Some(&at) {
            return Ok(());
        }
        self.commit(Record::ChannelPointer { ch, at })
            .map_err(|e| format!("channel {}: the pointer could not be stored: {e}", ch + 1))
    }

    /// Stores the part counter.
    pub fn save_counter(&mut self, c: &Counter) -> Result<(), String> {
        let rec = Record::Parts {
            target: c.target,
            counts: c.counts.clone(),
        };
        self.commit(rec)
            .map_err(|e| format!("the part counter could not be stored: {e}"))
    }

    fn commit(&mut self, rec: Record) -> Result<(), StoreError> {
        self.stores.commit_record(rec)
    }

    /// Sets after how many journal records the journal is compacted (default 4096).
    pub fn set_journal_limit(&mut self, records: usize) {
        self.stores.set_journal_limit(records);
    }

    /// The directory.
    pub fn dir(&self) -> &Path {
        self.stores.dir()
    }
}
