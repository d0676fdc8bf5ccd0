//! The panel model shared by every front end (terminal, window, script): the selector
//! positions, the operator's actions (panel events) and the view a front end draws.
//! The `Console` consumes `PanelEvent`s and produces a `PanelView` (docs/panel.md, docs/cli.md).

use std::fmt;
use std::path::PathBuf;

/// The names of one selector position, in every length a front end needs.
#[derive(Debug, PartialEq, Eq)]
pub struct ModeNames {
    /// The panel script word (`op AUTO`, `data TOOLREVISE`) and the `/nc/state` value.
    pub word: &'static str,
    /// The operator's name, for messages and page headers.
    pub name: &'static str,
    /// The label on the terminal's rotary selector (at most 11 characters).
    pub label: &'static str,
    /// The short form, for the state line and the window's selector (at most 8 characters).
    pub short: &'static str,
}

const fn names(
    word: &'static str,
    name: &'static str,
    label: &'static str,
    short: &'static str,
) -> ModeNames {
    ModeNames {
        word,
        name,
        label,
        short,
    }
}

/// Operation mode names, in selector order (the order of [`OpMode::ALL`]).
pub const OP_NAMES: [ModeNames; 7] = [
    names("CONTINUOUS", "CONTINUOUS", "CONTINUOUS", "CONT"),
    names("AUTO", "AUTO", "AUTO", "AUTO"),
    names("MDI", "MDI", "MDI", "MDI"),
    names("DATA", "DATA INPUT", "DATA INPUT", "DATA"),
    names("HANDLE", "HANDLE", "HANDLE", "HANDLE"),
    names("STEP", "STEP", "STEP", "STEP"),
    names("SINGLE", "SINGLE BLOCK", "SINGLE BLK", "SINGLE"),
];

/// Data-processing mode names, in selector order (the order of [`DataMode::ALL`]).
pub const DATA_NAMES: [ModeNames; 7] = [
    names("SEARCH", "SEARCH", "SEARCH", "SEARCH"),
    names("READ", "PROGRAM READ", "PROG READ", "PROG READ"),
    names("REVISE", "PROGRAM REVISION", "PROG REVISE", "PROG REV"),
    names("TOOLREAD", "TOOL DATA READ", "TOOL READ", "TOOL READ"),
    names(
        "TOOLREVISE",
        "TOOL DATA REVISION",
        "TOOL REVISE",
        "TOOL REV",
    ),
    names("TCODE", "T-CODE SETTING", "T-CODE SET", "T-CODE"),
    names("MDI", "MDI", "MDI", "MDI"),
];

/// Operation mode selector 17 (relay panel), seven positions.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum OpMode {
    /// CONTINUOUS: jog while held.
    Continuous,
    /// AUTO: run program memory.
    Auto,
    /// MDI: run the MDI buffer.
    Mdi,
    /// DATA INPUT: editing and data entry, machine stopped.
    Data,
    /// HANDLE: manual pulse generator.
    Handle,
    /// STEP: incremental jog.
    Step,
    /// SINGLE BLOCK: each START runs one block.
    Single,
}

impl OpMode {
    /// The seven positions in selector order.
    pub const ALL: [OpMode; 7] = [
        OpMode::Continuous,
        OpMode::Auto,
        OpMode::Mdi,
        OpMode::Data,
        OpMode::Handle,
        OpMode::Step,
        OpMode::Single,
    ];

    /// The names of this position: the one table every front end takes them from.
    pub fn names(self) -> &'static ModeNames {
        &OP_NAMES[self as usize]
    }

    /// The script word (`op WORD`).
    pub fn word(self) -> &'static str {
        self.names().word
    }

    /// The operator's name, as the display writes it in messages.
    pub fn name(self) -> &'static str {
        self.names().name
    }

    /// The position parsed from its script word (case-insensitive).
    pub fn from_word(w: &str) -> Option<OpMode> {
        OpMode::ALL
            .into_iter()
            .find(|m| m.word().eq_ignore_ascii_case(w))
    }
}

/// Data-processing mode selector 16 (NC panel), seven positions.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum DataMode {
    /// SEARCH: position the program at a statement.
    Search,
    /// PROGRAM READ: tape to program memory.
    Read,
    /// PROGRAM REVISION: the editor on program memory.
    Revise,
    /// TOOL DATA READ: tool tape to the tool file.
    ToolRead,
    /// TOOL DATA REVISION: the editor on the tool file.
    ToolRevise,
    /// T-CODE SETTING: assign tool numbers to T codes.
    TCode,
    /// MDI: the editor on the MDI buffer.
    Mdi,
}

impl DataMode {
    /// The seven positions in selector order.
    pub const ALL: [DataMode; 7] = [
        DataMode::Search,
        DataMode::Read,
        DataMode::Revise,
        DataMode::ToolRead,
        DataMode::ToolRevise,
        DataMode::TCode,
        DataMode::Mdi,
    ];

    /// The names of this position: the one table every front end takes them from.
    pub fn names(self) -> &'static ModeNames {
        &DATA_NAMES[self as usize]
    }

    /// The script word (`data WORD`).
    pub fn word(self) -> &'static str {
        self.names().word
    }

    /// The operator's name, as the display writes it in headers and messages.
    pub fn name(self) -> &'static str {
        self.names().name
    }

    /// The position parsed from its script word (case-insensitive).
    pub fn from_word(w: &str) -> Option<DataMode> {
        DataMode::ALL
            .into_iter()
            .find(|m| m.word().eq_ignore_ascii_case(w))
    }
}

/// The page on the plasma display: the mode's display program, or an operator page chosen by
/// the row of page keys (docs/panel.md, "Pages").
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Page {
    /// The display program of the selectors' modes (the patent's).
    #[default]
    Mode,
    /// POS: positions, feed, spindle, counters.
    Pos,
    /// PROG: the programs in memory.
    Prog,
    /// OFS: the tool offsets.
    Ofs,
    /// MSG: the alarm and message history.
    Msg,
    /// MODAL: the modal state in force, the overrides and the switches.
    Modal,
    /// I/O: the outputs M62–M68 set and the inputs M66 reads (Fanuc's PMC signal page).
    Io,
    /// MACRO: the Fanuc dialect's macro variables.
    Macro,
}

impl Page {
    /// The pages of the row of page keys, in order.
    pub const KEYS: [Page; 7] = [
        Page::Pos,
        Page::Prog,
        Page::Ofs,
        Page::Msg,
        Page::Modal,
        Page::Io,
        Page::Macro,
    ];

    /// The key's label.
    pub fn label(self) -> &'static str {
        match self {
            Page::Mode => "MODE",
            Page::Pos => "POS",
            Page::Prog => "PROG",
            Page::Ofs => "OFS",
            Page::Msg => "MSG",
            Page::Modal => "MODAL",
            Page::Io => "I/O",
            Page::Macro => "MACRO",
        }
    }
}

/// A machine axis.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Axis {
    /// X axis.
    X,
    /// Y axis.
    Y,
    /// Z axis.
    Z,
    /// The rotary axis A (on a machine whose description has it).
    A,
    /// The rotary axis B.
    B,
    /// The rotary axis C.
    C,
}

impl Axis {
    /// Every axis, in index order.
    pub const ALL: [Axis; 6] = [Axis::X, Axis::Y, Axis::Z, Axis::A, Axis::B, Axis::C];

    /// Index 0, 1, 2 (X Y Z), 3, 4, 5 (A B C): the kernel's axis arrays'.
    pub fn index(self) -> usize {
        match self {
            Axis::X => 0,
            Axis::Y => 1,
            Axis::Z => 2,
            Axis::A => 3,
            Axis::B => 4,
            Axis::C => 5,
        }
    }

    /// The axis letter parsed (case-insensitive).
    pub fn from_word(w: &str) -> Option<Axis> {
        let mut cs = w.chars();
        match (cs.next(), cs.next()) {
            (Some(c), None) => Axis::ALL
                .into_iter()
                .find(|a| a.letter() == c.to_ascii_uppercase()),
            _ => None,
        }
    }

    /// The axis letter.
    pub fn letter(self) -> char {
        crate::settings::AXIS_NAMES[self.index()]
    }
}

/// One operator action at the panel. The script format of docs/cli.md maps line for line onto it;
/// interactive front ends add per-key events.
#[derive(Clone, Debug, PartialEq)]
pub enum PanelEvent {
    /// Turn the operation mode selector 17.
    Op(OpMode),
    /// Turn the data-processing mode selector 16.
    Data(DataMode),
    /// Data keys: a whole line, then EOB (`type TEXT`).
    Type(String),
    /// One data key (interactive typing).
    Key(char),
    /// Rub out the last typed character (interactive typing).
    Rubout,
    /// The end-of-block key (Enter).
    Eob,
    /// +INPUT: the line typed is added to the cell under a page's cursor (OFS, MACRO), as a
    /// Fanuc's +INPUT soft key; the keyboard's Tab on such a page (`plusinput`).
    PlusInput,
    /// Put a file in the tape reader.
    Tape(PathBuf),
    /// Cycle start.
    Start,
    /// Feed hold.
    Stop,
    /// Reference return (HOME): Z up to machine zero, then X and Y (`home`, Alt+0).
    Home,
    /// Reset.
    Reset,
    /// Emergency stop.
    EStop,
    /// Feed override, percent (0–150, 10 % steps).
    Override(u32),
    /// Rapid override, percent: 0 (F0), 25, 50 or 100 (`rapidoverride PCT`).
    RapidOverride(u32),
    /// Spindle override, percent: 50–120 in 10 % steps (`spindleoverride PCT`).
    SpindleOverride(u32),
    /// The DRY RUN switch on or off (`dryrun on|off`).
    DryRun(bool),
    /// The MACHINE LOCK switch on or off (`machinelock on|off`).
    MachineLock(bool),
    /// The Z NEGLECT switch on or off (`zneglect on|off`).
    ZNeglect(bool),
    /// Handwheel: N detents on an axis, at the selected increment (×1/×10/×100/×1000).
    Wheel(Axis, i32),
    /// The increment selector, in pulses (1, 10, 100 or 1000): per handwheel detent and per
    /// STEP key, and a CONTINUOUS tap.
    WheelScale(u32),
    /// The BLOCK DELETE switch on or off: a G-code run skips lines starting with `/`.
    BlockDelete(bool),
    /// Sets a simulated machine input (script only): digital P0–P63 (value 0 or 1) or analog
    /// E0–E63, which M66 reads.
    Input {
        /// Digital (P) or analog (E).
        digital: bool,
        /// Input 0–63.
        index: u8,
        /// The value (a digital input: 1 on, 0 off).
        value: f64,
    },
    /// The OPTIONAL STOP switch on or off: a G-code run stops at M01.
    OptionalStop(bool),
    /// Jog button pressed (CONTINUOUS: move while held; STEP: one increment), +1 or -1.
    Jog(Axis, i8),
    /// Jog button released.
    JogRelease,
    /// A key of the terminal's key map, pressed and released (`key NAME`).
    Press(novanc_panel::Key),
    /// Wait until the machine is idle (script only).
    Wait,
    /// Wait until block N (its N number) of the current run starts executing, or the run
    /// ends (script only: `wait block N`).
    WaitBlock(u32),
    /// Let T milliseconds of machine time pass (script only: `wait ms T`).
    WaitMs(u64),
    /// Print the display frame (script only).
    Show,
    /// The channel selector of a machine with several channels (`channel N`; 0-based here).
    Channel(usize),
    /// A fault injected into a channel (`fault N REASON`: tool breakage, failed supply, ...),
    /// a machine with several channels; 0-based here.
    Fault(usize, String),
    /// The part target of a machine with a work flow (`target N`).
    Target(u32),
    /// The tool-offset mode of a machine with several channels (`op OFS`).
    OfsMode,
}

/// The longest `wait ms` a script may ask for, ms (100 hours of machine time).
pub const MAX_WAIT_MS: u64 = 360_000_000;

/// Why a script word is not a whole number of its type.
#[derive(Debug)]
enum Whole {
    /// Not a whole number at all.
    Not(String),
    /// A whole number beyond the type's range.
    Range(String),
}

impl From<Whole> for String {
    fn from(w: Whole) -> String {
        match w {
            Whole::Not(m) | Whole::Range(m) => m,
        }
    }
}

/// A script word as a whole number of type `T`, whose range is `lo` to `hi`: a number beyond
/// it is said to be out of range, not "not a whole number".
fn whole<T>(s: &str, what: &str, lo: T, hi: T) -> Result<T, Whole>
where
    T: std::str::FromStr<Err = std::num::ParseIntError> + std::fmt::Display,
{
    use std::num::IntErrorKind::{NegOverflow, PosOverflow};
    s.parse()
        .map_err(|e: std::num::ParseIntError| match e.kind() {
            PosOverflow | NegOverflow => Whole::Range(format!(
                "{what} {} is out of range ({lo} to {hi})",
                crate::input_text::quote_plain(s)
            )),
            _ => Whole::Not(format!(
                "{what} {} is not a whole number",
                crate::input_text::quote(s)
            )),
        })
}

/// A bad panel-script line.
#[derive(Clone, Debug, PartialEq)]
pub struct ScriptError {
    /// 1-based line in the script.
    pub line: u32,
    /// What is wrong.
    pub message: String,
}

impl fmt::Display for ScriptError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "line {}: {}", self.line, self.message)
    }
}

impl PanelEvent {
    /// A simulated machine input, as the script word `input` and the I/O page's INPUT take it
    /// (`P3 on`, `P3 off`, `E2 4.5`; docs/cli.md "Panel scripts", docs/panel.md "Pages").
    pub fn parse_input(args: &[&str]) -> Result<PanelEvent, String> {
        let [which, v] = args else {
            return Err("'input' takes P0-P63 on|off or E0-E63 and a value".into());
        };
        let (digital, n) = match which.chars().next() {
            Some('P' | 'p') => (true, &which[1..]),
            Some('E' | 'e') => (false, &which[1..]),
            _ => return Err(format!("input: '{which}' is not P0-P63 or E0-E63")),
        };
        let index: u8 = match n.parse() {
            Ok(i) if i <= 63 => i,
            _ => return Err(format!("input: '{which}' is not P0-P63 or E0-E63")),
        };
        let value = if digital {
            match v.to_ascii_lowercase().as_str() {
                "on" => 1.0,
                "off" => 0.0,
                a => return Err(format!("input {which}: takes on or off, not '{a}'")),
            }
        } else {
            match v.parse::<f64>() {
                Ok(x) if x.is_finite() => x,
                _ => return Err(format!("input {which}: '{v}' is not a number")),
            }
        };
        Ok(PanelEvent::Input {
            digital,
            index,
            value,
        })
    }

    /// Parses one script line (docs/cli.md) of a machine with one channel (the machining
    /// centre). `Ok(None)` for a blank or comment line.
    pub fn parse_script_line(raw: &str) -> Result<Option<PanelEvent>, String> {
        PanelEvent::parse_script_line_on(raw, 1)
    }

    /// Parses one script line of a machine with `channels` channels: the one panel-script
    /// grammar of every console (docs/cli.md; docs/lathe.md "Panel script"). The words of a
    /// machine with several channels (`channel`, `fault`, `target`, `op OFS`) are refused with
    /// one channel; `override` takes 0–150 in 10 % steps with one channel (the centre's
    /// switch), any whole percentage to 150 with several (the lathe's).
    pub fn parse_script_line_on(raw: &str, channels: usize) -> Result<Option<PanelEvent>, String> {
        let line = raw.trim_end_matches(['\r', '\n']);
        let trimmed = line.trim_start();
        if trimmed.is_empty() || trimmed.starts_with('#') {
            return Ok(None);
        }
        let (word, rest) = match trimmed.find(char::is_whitespace) {
            Some(i) => (&trimmed[..i], &trimmed[i + 1..]),
            None => (trimmed, ""),
        };
        // `type` keeps its text verbatim (a `#` there is data); other lines may carry comments.
        if word == "type" {
            return Ok(Some(PanelEvent::Type(rest.to_string())));
        }
        let rest = rest.split('#').next().unwrap_or("").trim();
        let args: Vec<&str> = rest.split_whitespace().collect();
        let one = |what: &str| -> Result<&str, String> {
            match args.as_slice() {
                [a] => Ok(*a),
                _ => Err(format!("'{word}' takes one {what}")),
            }
        };
        let none = || -> Result<(), String> {
            if args.is_empty() {
                Ok(())
            } else {
                Err(format!("'{word}' takes no argument"))
            }
        };
        let multi = channels > 1;
        let channel = |a: &str| -> Result<usize, String> {
            if !multi {
                return Err(format!(
                    "'{word}' is for a machine with several channels; this one has one"
                ));
            }
            match a.parse::<usize>() {
                Ok(n) if (1..=channels).contains(&n) => Ok(n - 1),
                _ => Err(format!("'{a}' is not a channel (1 to {channels})")),
            }
        };
        let ev = match word {
            "op" if multi => match one("position")? {
                "OFS" => PanelEvent::OfsMode,
                a => PanelEvent::Op(OpMode::from_word(a).ok_or_else(|| {
                    format!("op {a}: the lathe's modes are AUTO, MDI, DATA and OFS")
                })?),
            },
            "channel" => PanelEvent::Channel(channel(one("channel number")?)?),
            "fault" => {
                let (c, why) = rest.split_once(char::is_whitespace).unwrap_or((rest, ""));
                let ch = channel(c)?;
                let why = why.trim();
                if why.is_empty() {
                    return Err(
                        "fault CH REASON: say why (tool breakage, failed supply, ...)".into(),
                    );
                }
                PanelEvent::Fault(ch, why.chars().take(40).collect())
            }
            "target" if multi => match one("part count")?.parse::<u32>() {
                Ok(n) if (1..=999_999).contains(&n) => PanelEvent::Target(n),
                _ => return Err(format!("target '{rest}': a part count from 1 to 999999")),
            },
            "target" => {
                return Err(
                    "'target' is the part target of a machine with a work flow (the lathe)".into(),
                )
            }
            "override" if multi => match one("percentage")?.trim_end_matches('%').parse::<u32>() {
                Ok(p) if p <= 150 => PanelEvent::Override(p),
                _ => return Err(format!("override '{rest}': a percentage from 0 to 150")),
            },
            "op" => {
                let a = one("position")?;
                PanelEvent::Op(OpMode::from_word(a).ok_or_else(|| {
                    format!("unknown operation mode '{a}' (CONTINUOUS AUTO MDI DATA HANDLE STEP SINGLE)")
                })?)
            }
            "data" => {
                let a = one("position")?;
                PanelEvent::Data(DataMode::from_word(a).ok_or_else(|| {
                    format!("unknown data mode '{a}' (SEARCH READ REVISE TOOLREAD TOOLREVISE TCODE MDI)")
                })?)
            }
            "tape" => {
                if rest.is_empty() {
                    return Err("'tape' takes a file path".into());
                }
                PanelEvent::Tape(PathBuf::from(rest))
            }
            "start" => none().map(|_| PanelEvent::Start)?,
            "home" => none().map(|_| PanelEvent::Home)?,
            "stop" => none().map(|_| PanelEvent::Stop)?,
            "reset" => none().map(|_| PanelEvent::Reset)?,
            "estop" => none().map(|_| PanelEvent::EStop)?,
            "wait" => match args.as_slice() {
                [] => PanelEvent::Wait,
                ["block", n] => PanelEvent::WaitBlock(
                    n.parse()
                        .map_err(|_| format!("wait block: '{n}' is not a block number"))?,
                ),
                ["ms", t] => match whole(t, "wait ms:", 0, u64::MAX) {
                    Ok(ms) if ms <= MAX_WAIT_MS => PanelEvent::WaitMs(ms),
                    // Too many digits for a u64 is more than the longest wait too.
                    Ok(_) | Err(Whole::Range(_)) => {
                        return Err(format!(
                            "wait ms: {} is more than {MAX_WAIT_MS} ms (100 hours)",
                            crate::input_text::quote_plain(t)
                        ))
                    }
                    Err(Whole::Not(_)) => {
                        return Err(format!(
                            "wait ms: '{t}' is not a whole number of milliseconds"
                        ))
                    }
                },
                _ => return Err("'wait' takes nothing, 'block N' or 'ms T'".into()),
            },
            "key" => {
                // The key name is taken as written: a single character may be '#' or ' '.
                let raw = trimmed[word.len()..].strip_prefix(' ').unwrap_or("");
                let name = if raw.chars().count() == 1 {
                    raw
                } else {
                    raw.split('#').next().unwrap_or("").trim()
                };
                if name.is_empty() {
                    return Err(
                        "'key' takes a key name (F1-F12, Alt+1, Up, Enter, a character, ...)"
                            .into(),
                    );
                }
                PanelEvent::Press(crate::console::keys::parse_key(name)?)
            }
            "show" => none().map(|_| PanelEvent::Show)?,
            "override" => {
                let a = one("percentage")?;
                let p: u32 = a
                    .trim_end_matches('%')
                    .parse()
                    .map_err(|_| format!("override '{a}' is not a whole percentage"))?;
                if p > 150 || !p.is_multiple_of(10) {
                    return Err(format!("override {p} % is not 0 to 150 in 10 % steps"));
                }
                PanelEvent::Override(p)
            }
            "wheel" => match args.as_slice() {
                [a, n] => {
                    let axis = Axis::from_word(a)
                        .ok_or_else(|| format!("unknown axis '{a}' (X, Y, Z, A, B or C)"))?;
                    let n: i32 = whole(n, "detents", i32::MIN, i32::MAX).map_err(String::from)?;
                    PanelEvent::Wheel(axis, n)
                }
                _ => return Err("'wheel' takes an axis and a number of detents".into()),
            },
            // A jog button pressed (CONTINUOUS: the axis jogs until `jogrelease`; STEP: one
            // increment), as the recording names it.
            "jog" => {
                let a = one("axis and direction (jog X+, jog Z-)")?;
                let bad = || format!("jog '{a}': an axis and + or - (jog X+, jog Z-)");
                let dir = match a.chars().last() {
                    Some('+') => 1,
                    Some('-') => -1,
                    _ => return Err(bad()),
                };
                let axis = Axis::from_word(&a[..a.len() - 1]).ok_or_else(bad)?;
                PanelEvent::Jog(axis, dir)
            }
            "jogrelease" => none().map(|_| PanelEvent::JogRelease)?,
            // The data keys RUBOUT and EOB as the window's buttons give them.
            "rubout" => none().map(|_| PanelEvent::Rubout)?,
            "eob" => none().map(|_| PanelEvent::Eob)?,
            "plusinput" => none().map(|_| PanelEvent::PlusInput)?,
            "wheelscale" => {
                let a = one("increment")?;
                let n: u32 = a
                    .trim_start_matches(['x', 'X'])
                    .parse()
                    .map_err(|_| format!("increment '{a}' is not 1, 10, 100 or 1000"))?;
                PanelEvent::WheelScale(n)
            }
            "rapidoverride" => {
                let a = one("percentage")?;
                match a.trim_end_matches('%').parse::<u32>() {
                    Ok(p @ (0 | 25 | 50 | 100)) => PanelEvent::RapidOverride(p),
                    _ => return Err(format!("rapidoverride '{a}' is not 0 (F0), 25, 50 or 100")),
                }
            }
            "spindleoverride" => {
                let a = one("percentage")?;
                match a.trim_end_matches('%').parse::<u32>() {
                    Ok(p) if (50..=120).contains(&p) && p.is_multiple_of(10) => {
                        PanelEvent::SpindleOverride(p)
                    }
                    _ => {
                        return Err(format!(
                            "spindleoverride '{a}' is not 50 to 120 in 10 % steps"
                        ))
                    }
                }
            }
            "blockdelete" | "optionalstop" | "dryrun" | "machinelock" | "zneglect" => {
                let on = match one("on or off")?.to_ascii_lowercase().as_str() {
                    "on" => true,
                    "off" => false,
                    a => return Err(format!("'{word}' takes on or off, not '{a}'")),
                };
                match word {
                    "blockdelete" => PanelEvent::BlockDelete(on),
                    "optionalstop" => PanelEvent::OptionalStop(on),
                    "dryrun" => PanelEvent::DryRun(on),
                    "machinelock" => PanelEvent::MachineLock(on),
                    _ => PanelEvent::ZNeglect(on),
                }
            }
            "input" => PanelEvent::parse_input(&args)?,
            other => return Err(format!("unknown script word '{other}'")),
        };
        Ok(Some(ev))
    }

    /// Parses a whole script of a machine with one channel; the first bad line fails it.
    pub fn parse_script(text: &str) -> Result<Vec<PanelEvent>, ScriptError> {
        PanelEvent::parse_script_on(text, 1)
    }

    /// Parses a whole script of a machine with `channels` channels; the first bad line fails it.
    pub fn parse_script_on(text: &str, channels: usize) -> Result<Vec<PanelEvent>, ScriptError> {
        let mut out = Vec::new();
        for (i, l) in text.lines().enumerate() {
            match PanelEvent::parse_script_line_on(l, channels) {
                Ok(Some(e)) => out.push(e),
                Ok(None) => {}
                Err(message) => {
                    return Err(ScriptError {
                        line: i as u32 + 1,
                        message,
                    })
                }
            }
        }
        Ok(out)
    }
}

/// The lamps of the relay panel.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Lamps {
    /// RUN ≠ 0.
    pub run: bool,
    /// Feed hold in force.
    pub hold: bool,
    /// Emergency stop in force (RESET required).
    pub estop: bool,
    /// An alarm is shown (fault, travel limit, translation error).
    pub alarm: bool,
}

/// Everything a front end draws: produced by the console, identical for terminal and window.
#[derive(Clone, Debug, PartialEq)]
pub struct PanelView {
    /// The plasma display: exactly `rows` lines of exactly `cols` characters.
    pub display: Vec<String>,
    /// Operation mode selector position.
    pub op_mode: OpMode,
    /// Data-processing mode selector position.
    pub data_mode: DataMode,
    /// RUN flag: 0 stopped, 1 AUTO, 2 MDI.
    pub run: u8,
    /// Relay panel lamps.
    pub lamps: Lamps,
    /// Feed override, percent.
    pub feed_override: u32,
    /// The rapid and spindle overrides, DRY RUN, MACHINE LOCK and Z NEGLECT (the pulse core's
    /// status snapshot's).
    pub switches: crate::record::Switches,
    /// BLOCK DELETE and OPTIONAL STOP (the console's: a G-code run reads them at START).
    pub program_switches: crate::gcode::Switches,
    /// Axis positions, mm (machine coordinates).
    pub axis_mm: [f64; 3],
    /// Tool-tip position, mm (Z less the length of the tool in the spindle that POS's WORK Z
    /// takes: the tool file's with no run loaded, the one in force during a run).
    pub tip_mm: [f64; 3],
    /// The machine's rotary axes (A, B, C, those it has) and where they stand, degrees: the
    /// readouts show them beside X Y Z (none on a 3-axis machine).
    pub rotary_deg: Vec<(char, f64)>,
    /// T code in the spindle, if any.
    pub tool: Option<u32>,
    /// Spindle speed, rpm, signed; 0 stopped.
    pub spindle: i64,
    /// Handwheel axis and pulses per detent.
    pub wheel: (Axis, u32),
    /// The line being typed on the data keys.
    pub entry: String,
    /// Machine time, ns.
    pub machine_ns: u64,
    /// The help screen page up (0: none; the terminal draws it instead of the panel).
    pub help: u8,
    /// The page on the plasma display.
    pub page: Page,
    /// The last key ignored while the terminal was too small, for its notice.
    pub ignored: Option<String>,
}
