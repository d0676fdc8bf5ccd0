//! Machine descriptions (docs/lathe.md "Machine description"): a small text format naming a
//! machine's channels, axes, pulse size, travel, rapid rate, acceleration, spindles and tools.
//! `--machine citizen` is the embedded three-channel lathe of seed 004.

/// One axis of a lathe channel.
#[derive(Clone, Debug, PartialEq)]
pub struct AxisDesc {
    /// Travel limits, mm (X as a radius).
    pub travel: [f64; 2],
    /// Rapid rate, mm/min.
    pub rapid: f64,
    /// Acceleration, mm/s².
    pub accel: f64,
}

/// One tool on a channel's tool post.
#[derive(Clone, Debug, PartialEq)]
pub struct ToolDesc {
    /// Tool number (the T word's first two digits).
    pub number: u32,
    /// Nose radius, mm.
    pub radius: f64,
    /// Imaginary tip position 0–9 (Fanuc's and the thesis's chart, docs/lathe.md).
    pub tip: u8,
    /// Offsets of the tip, X (radius) and Z, mm, added to the programmed point.
    pub offset: [f64; 2],
}

/// One lathe channel: its axes X and Z, its spindle with an encoder, its tool post and chuck.
#[derive(Clone, Debug, PartialEq)]
pub struct ChannelDesc {
    /// The channel's name as the display shows it.
    pub name: String,
    /// X (radius) and Z.
    pub axes: [AxisDesc; 2],
    /// Spindle maximum, rpm.
    pub max_rpm: f64,
    /// Spindle acceleration, rpm per second.
    pub spindle_accel: f64,
    /// Encoder lines per revolution (one index pulse per revolution).
    pub encoder: u32,
    /// The tools on the tool post.
    pub tools: Vec<ToolDesc>,
    /// The G-code dialect its programs are read in (the description's `dialect` line in the
    /// channel, else the machine's line before the channels, else `--dialect`); `None`: not
    /// said, LinuxCNC's (docs/lathe.md "Machine description").
    pub dialect: Option<crate::settings::Dialect>,
    /// Fanuc's G code system A (the description's `gcode system A` line in the channel):
    /// G98/G99 feeds, G90/G92/G94 single cycles, G50, no G91 (docs/lathe-gcode.md "G code
    /// systems"); `false`: system B, as LinuxCNC's lathe reads. Only with the Fanuc dialect.
    pub system_a: bool,
    /// The Fanuc dialect's `common keep|clear` (parameter 6001#6 CCV): whether RESET keeps
    /// the common variables #100–#199 (the channel's line, else the machine's before the
    /// channels); `None`: not said, RESET makes them vacant.
    pub keep_common: Option<bool>,
    /// The Fanuc dialect's `decimal calculator|increments` (parameter 3401#0 DPI): a number
    /// written without a point in X, Z, U, W, I, K, R is in millimetres (`X30` is 30 mm), not
    /// least increments; the words Fanuc takes in least increments only (G74/G75 Q, G76 Q,
    /// G83 Q) stay so (the channel's line, else the machine's); `None`: not said, increments.
    pub calculator: Option<bool>,
    /// The feed mode at power-on and after RESET (`feed per-rev` G95, `feed per-minute` G94;
    /// the channel's line, else the machine's); `None`: not said, by the dialect: Fanuc's
    /// G95 (a Fanuc 0i-T powers on in G99), LinuxCNC's G94.
    pub per_rev: Option<bool>,
    /// Where `o<name> call` and `M98 P` look for a subroutine the program does not hold
    /// (`name.ngc`), in order: the channel's `subroutines` lines, then the machine's.
    pub subroutines: Vec<std::path::PathBuf>,
    /// The M codes a machine builder adds, each calling an O-word subroutine (the
    /// description's `remap M31 modalgroup=10 ngc=NAME` lines: the channel's, then the
    /// machine's before the channels; docs/lathe-gcode.md "A machine builder's M codes").
    pub remap_m: Vec<crate::settings::Remap>,
    /// `g28 alone all`: in the Fanuc dialect, a G28 that names no axis returns both, as a
    /// Haas does (the channel's line, else the machine's); `None` or `false`: it is refused,
    /// where a Fanuc moves nothing. LinuxCNC's dialect returns both either way.
    pub g28_all: Option<bool>,
    /// `g04 p point seconds`: in the Fanuc dialect, G04's P written with a point is seconds,
    /// as a Haas reads it (the channel's line, else the machine's); `None` or `false`: refused,
    /// as Fanuc refuses it (docs/gcode.md "Fanuc dialect").
    pub p_point_seconds: Option<bool>,
}

impl ChannelDesc {
    /// A channel nothing of which is described yet (travel NaN: "not given"); every
    /// setting a line may give at its default.
    pub(crate) fn unset() -> ChannelDesc {
        ChannelDesc {
            name: String::new(),
            axes: [0, 1].map(|_| AxisDesc {
                travel: [f64::NAN; 2],
                rapid: 0.0,
                accel: 0.0,
            }),
            max_rpm: 0.0,
            spindle_accel: 0.0,
            encoder: 0,
            tools: Vec::new(),
            dialect: None,
            system_a: false,
            keep_common: None,
            calculator: None,
            per_rev: None,
            subroutines: Vec::new(),
            remap_m: Vec::new(),
            g28_all: None,
            p_point_seconds: None,
        }
    }

    /// The tool numbered `n`, if the tool post has it.
    pub fn tool(&self, n: u32) -> Option<&ToolDesc> {
        self.tools.iter().find(|t| t.number == n)
    }
}

/// A lathe machine: its channels and how the work passes between their spindles.
#[derive(Clone, Debug, PartialEq)]
pub struct LatheDesc {
    /// The machine's name.
    pub name: String,
    /// mm per pulse, every axis.
    pub pulse_mm: f64,
    /// The lockstep tick of all channels, ns of machine time.
    pub tick_ns: u64,
    /// The channels, 1 to 8.
    pub channels: Vec<ChannelDesc>,
    /// The channel whose spindle the supplier (bar feeder) feeds, 0-based.
    pub supplier: usize,
    /// Transfers (from, to), 0-based channels: the work passes from spindle to spindle.
    pub transfers: Vec<(usize, usize)>,
    /// The channel that delivers to the unloader, 0-based.
    pub unloader: usize,
    /// `loading manual`: the operator loads each work by hand (one channel, no bar feeder or
    /// unloader); `loading bar` (the default) the bar feeder and M10/M11 do.
    pub manual: bool,
}

impl LatheDesc {
    /// The channel that receives from channel `ch`, or `None` if `ch` delivers to the
    /// unloader.
    pub fn receiver_of(&self, ch: usize) -> Option<usize> {
        self.transfers.iter().find(|t| t.0 == ch).map(|t| t.1)
    }

    /// The channel that supplies channel `ch`, or `None` if the supplier (bar feeder) does.
    pub fn supplier_of(&self, ch: usize) -> Option<usize> {
        self.transfers.iter().find(|t| t.1 == ch).map(|t| t.0)
    }

    /// Millimetres to pulses, rounded to the nearest.
    pub fn pulses(&self, mm: f64) -> i64 {
        (mm / self.pulse_mm).round() as i64
    }

    /// The settings and blocks of every channel running `programs` (each channel's
    /// statements, as the lathe G-code reader makes them), and the work flow, for
    /// [`crate::pulse_core::Kernel::new`]. Errors: a program count other than the channel
    /// count.
    #[allow(clippy::type_complexity)]
    pub fn kernel_channels(
        &self,
        programs: Vec<Vec<crate::block::Statement>>,
    ) -> Result<
        (
            Vec<(
                crate::settings::MachineSettings,
                Vec<crate::block::Statement>,
            )>,
            crate::pulse_core::WorkFlow,
        ),
        String,
    > {
        if programs.len() != self.channels.len() {
            return Err(format!(
                "{} programs for {} channels: give one program per channel",
                programs.len(),
                self.channels.len()
            ));
        }
        let mut chans = Vec::new();
        for (ch, p) in programs.into_iter().enumerate() {
            let s = crate::settings::MachineSettings::lathe_channel(self, ch)
                .ok_or_else(|| format!("no channel {}", ch + 1))?;
            chans.push((s, p));
        }
        Ok((chans, self.work_flow()))
    }

    /// How works pass between the channels' chucks: the bar feeder, the handovers, the
    /// unloader (the kernel's sync table).
    pub fn work_flow(&self) -> crate::pulse_core::WorkFlow {
        crate::pulse_core::WorkFlow {
            supplier: self.supplier,
            transfers: self.transfers.clone(),
            unloader: self.unloader,
            manual: self.manual,
        }
    }
}

/// The embedded three-channel Citizen lathe (`--machine citizen`).
pub const CITIZEN: &str = include_str!("../../machines/citizen.machine");
/// The embedded machining centre (`--machine centre`, the default).
pub const CENTRE: &str = include_str!("../../machines/centre.machine");
/// The centre with a rotary table A, wrapped (`--machine centre4`).
pub const CENTRE4: &str = include_str!("../../machines/centre4.machine");

/// Most channels a description may have (the summary line and `with` masks are sized by it).
pub const MAX_CHANNELS: usize = 8;
/// Most tools on one tool post.
pub const MAX_TOOLS: usize = 99;

/// A parsed machine description.
#[derive(Clone, Debug, PartialEq)]
// Made once when a command starts: a mill's settings inline cost nothing worth a box.
#[allow(clippy::large_enum_variant)]
pub enum MachineDesc {
    /// A machining centre: the pulse core's settings (axes X Y Z, and A if described).
    Mill(crate::settings::MachineSettings),
    /// A lathe with one or more channels.
    Lathe(LatheDesc),
}

impl LatheDesc {
    /// The embedded Citizen lathe.
    pub fn citizen() -> LatheDesc {
        match parse(CITIZEN) {
            Ok(MachineDesc::Lathe(d)) => d,
            // The embedded file is checked by a unit test; this arm is never taken.
            _ => unreachable!("machines/citizen.machine is a lathe description"),
        }
    }
}

/// Loads a machine by name (`citizen`, `centre`) or from a description file.
pub fn load(name: &str) -> Result<MachineDesc, String> {
    let (text, src) = match name {
        "citizen" => (CITIZEN.to_string(), "citizen".to_string()),
        "centre" | "center" => (CENTRE.to_string(), "centre".to_string()),
        "centre4" | "center4" => (CENTRE4.to_string(), "centre4".to_string()),
        path => match std::fs::read(path) {
            Ok(b) => match String::from_utf8(b) {
                Ok(t) => (t, path.to_string()),
                Err(_) => return Err(format!("{path}: not a text file")),
            },
            Err(e) => {
                return Err(format!(
                "{path}: {e} (a machine is 'citizen', 'centre' or a description file; 'centre4' is the centre with a rotary A)"
            ))
            }
        },
    };
    parse(&text).map_err(|e| format!("{src}:{e}"))
}

fn num(w: Option<&&str>, what: &str) -> Result<f64, String> {
    let w = w.ok_or_else(|| format!("{what} is missing"))?;
    match w.parse::<f64>() {
        Ok(v) if v.is_finite() => Ok(v),
        _ => Err(format!("{what}: '{w}' is not a number")),
    }
}

fn channel_no(w: Option<&&str>, n: usize, what: &str) -> Result<usize, String> {
    let v = num(w, what)?;
    if v.fract() != 0.0 || v < 1.0 || v as usize > n {
        return Err(format!(
            "{what}: channel {v} does not exist (channels 1 to {n})"
        ));
    }
    Ok(v as usize - 1)
}

/// Reads a mill's rotary axis A, B or C: `a rotary [wrap] [travel MIN MAX] rapid DEG/MIN
/// accel DEG/S2` (degrees); a wrapped axis has no travel limits, any other needs them. Whether
/// it is wrapped.
fn rotary(words: &[&str]) -> Result<(AxisDesc, bool), String> {
    if words.get(1) != Some(&"rotary") {
        let l = words[0];
        return Err(format!(
            "axis {} is rotary: {l} rotary [wrap] travel MIN MAX rapid DEG/MIN accel DEG/S2",
            l.to_ascii_uppercase()
        ));
    }
    let wrap = words.get(2) == Some(&"wrap");
    let rest = &words[if wrap { 3 } else { 2 }..];
    let mut line = vec!["a"];
    line.extend_from_slice(rest);
    if wrap && !rest.contains(&"travel") {
        line.extend_from_slice(&["travel", "0", "360"]);
    }
    let a = axis(&line)?;
    Ok((a, wrap))
}

/// Reads `travel A B rapid R accel A` after an axis letter.
fn axis(words: &[&str]) -> Result<AxisDesc, String> {
    let mut a = AxisDesc {
        travel: [f64::NAN; 2],
        rapid: f64::NAN,
        accel: f64::NAN,
    };
    let mut i = 1;
    while i < words.len() {
        match words[i] {
            "travel" => {
                a.travel = [
                    num(words.get(i + 1), "travel")?,
                    num(words.get(i + 2), "travel")?,
                ];
                i += 3;
            }
            "rapid" => {
                a.rapid = num(words.get(i + 1), "rapid")?;
                i += 2;
            }
            "accel" => {
                a.accel = num(words.get(i + 1), "accel")?;
                i += 2;
            }
            w => {
                return Err(format!(
                    "'{w}': an axis takes travel MIN MAX, rapid MM/MIN, accel MM/S2"
                ))
            }
        }
    }
    if a.travel.iter().any(|v| v.is_nan()) || a.rapid.is_nan() || a.accel.is_nan() {
        return Err("an axis needs travel MIN MAX, rapid MM/MIN and accel MM/S2".into());
    }
    if a.travel[0] >= a.travel[1] || a.travel[0].abs() > 10_000.0 || a.travel[1].abs() > 10_000.0 {
        return Err(format!(
            "travel {} {}: the minimum must be below the maximum, both within ±10000 mm",
            a.travel[0], a.travel[1]
        ));
    }
    if !(1.0..=100_000.0).contains(&a.rapid) {
        return Err(format!("rapid {}: 1 to 100000 mm/min", a.rapid));
    }
    if !(1.0..=100_000.0).contains(&a.accel) {
        return Err(format!("accel {}: 1 to 100000 mm/s2", a.accel));
    }
    Ok(a)
}

fn spindle(words: &[&str], ch: &mut ChannelDesc) -> Result<(), String> {
    let mut i = 1;
    while i < words.len() {
        let v = num(words.get(i + 1), words[i])?;
        match words[i] {
            "max" if (1.0..=100_000.0).contains(&v) => ch.max_rpm = v,
            "accel" if (1.0..=1_000_000.0).contains(&v) => ch.spindle_accel = v,
            "encoder" if v.fract() == 0.0 && (1.0..=1_000_000.0).contains(&v) => {
                ch.encoder = v as u32
            }
            "max" => return Err(format!("spindle max {v}: 1 to 100000 rpm")),
            "accel" => return Err(format!("spindle accel {v}: 1 to 1000000 rpm/s")),
            "encoder" => return Err(format!("spindle encoder {v}: 1 to 1000000 lines")),
            w => {
                return Err(format!(
                    "'{w}': a spindle takes max RPM, accel RPM/S, encoder LINES"
                ))
            }
        }
        i += 2;
    }
    Ok(())
}

fn tool(words: &[&str]) -> Result<ToolDesc, String> {
    let n = num(words.get(1), "tool number")?;
    if n.fract() != 0.0 || !(1.0..=MAX_TOOLS as f64).contains(&n) {
        return Err(format!("tool {n}: tool numbers are 1 to {MAX_TOOLS}"));
    }
    let mut t = ToolDesc {
        number: n as u32,
        radius: 0.0,
        tip: 0,
        offset: [0.0; 2],
    };
    let mut i = 2;
    while i < words.len() {
        match words[i] {
            "radius" => {
                t.radius = num(words.get(i + 1), "radius")?;
                if !(0.0..=10.0).contains(&t.radius) {
                    return Err(format!("radius {}: a nose radius is 0 to 10 mm", t.radius));
                }
                i += 2;
            }
            "tip" => {
                let v = num(words.get(i + 1), "tip")?;
                if v.fract() != 0.0 || !(0.0..=9.0).contains(&v) {
                    return Err(format!("tip {v}: tip positions are 0 to 9"));
                }
                t.tip = v as u8;
                i += 2;
            }
            "offset" => {
                t.offset = [
                    num(words.get(i + 1), "offset X")?,
                    num(words.get(i + 2), "offset Z")?,
                ];
                if t.offset.iter().any(|v| v.abs() > 1000.0) {
                    return Err("offset: within ±1000 mm".into());
                }
                i += 3;
            }
            w => {
                return Err(format!(
                    "'{w}': a tool takes radius MM, tip 0-9, offset X Z"
                ))
            }
        }
    }
    Ok(t)
}

/// Parses one `tool N radius R tip P offset X Z` line (the description's tool statement, as
/// the lathe stores keep a channel's revised tools).
pub fn parse_tool(line: &str) -> Result<ToolDesc, String> {
    let words: Vec<&str> = line.split_whitespace().collect();
    match words.first() {
        Some(&"tool") => tool(&words),
        _ => Err(format!("'{line}' is not a tool line")),
    }
}

/// A tool as its description line (what `parse_tool` reads back).
pub fn tool_line(t: &ToolDesc) -> String {
    format!(
        "tool {} radius {} tip {} offset {} {}",
        t.number, t.radius, t.tip, t.offset[0], t.offset[1]
    )
}

/// Parses a machine description (docs/lathe.md "Machine description"). Errors are
/// `LINE: message`.
pub fn parse(text: &str) -> Result<MachineDesc, String> {
    let mut name = None;
    let mut kind = None;
    let mut pulse_mm = 0.001;
    let mut tick_us = 100.0;
    let mut mill_axes: [Option<AxisDesc>; 3] = [None, None, None];
    // The rotary axes A, B and C of a mill.
    let mut rotaries: [Option<(AxisDesc, bool)>; 3] = Default::default();
    // A mill's spindle line: (max rpm, accel rpm/s, encoder lines), 0 where not given.
    let mut mill_spindle: Option<ChannelDesc> = None;
    let mut channels: Vec<ChannelDesc> = Vec::new();
    let mut links: Vec<(usize, &str, Vec<&str>)> = Vec::new();
    let mut remap_m6 = None;
    let mut remap_m = Vec::new();
    let mut workpiece = crate::workpiece::Workpiece::default();
    let mut tool_change_z = None;
    let mut dialect = None;
    // Each channel's `gcode system A` line, by channel index: its line number.
    let mut system_a: Vec<(usize, usize)> = Vec::new();
    let mut fanuc: (Option<bool>, Option<bool>) = (None, None);
    let mut feed = None;
    let mut sub_path: Vec<std::path::PathBuf> = Vec::new();
    // A lathe's remaps and G28 setting before the channels: every channel's.
    let mut lathe_remaps: Vec<crate::settings::Remap> = Vec::new();
    let mut g28_all = None;
    // `g04 p point seconds|refuse`: the machine's (a mill's), or every lathe channel's.
    let mut p_point = None;
    for (i, raw) in text.lines().enumerate() {
        let ln = i + 1;
        let line = raw.split('#').next().unwrap_or("");
        let words: Vec<&str> = line.split_whitespace().collect();
        let Some(&head) = words.first() else { continue };
        let e = |m: String| format!("{ln}: {m}");
        let in_channel = kind == Some("lathe") && !channels.is_empty();
        match head {
            "machine" => match words.get(1) {
                Some(n) if words.len() == 2 && n.len() <= 32 => {
                    // The name names the machine's store directory (`lathe-NAME/`).
                    crate::store::fsutil::check_file_name(n)
                        .map_err(|m| e(format!("machine name {m}")))?;
                    name = Some(n.to_string())
                }
                _ => return Err(e("machine takes one name of at most 32 characters".into())),
            },
            "kind" => match words.get(1) {
                Some(&k @ ("lathe" | "mill")) if kind.is_none() => kind = Some(k),
                Some(&("lathe" | "mill")) => return Err(e("the kind is given twice".into())),
                _ => return Err(e("kind is lathe or mill".into())),
            },
            "pulse" => {
                pulse_mm = num(words.get(1), "pulse").map_err(e)?;
                if !(0.0001..=0.1).contains(&pulse_mm) {
                    return Err(e(format!("pulse {pulse_mm}: 0.0001 to 0.1 mm")));
                }
            }
            "tick" => {
                tick_us = num(words.get(1), "tick").map_err(e)?;
                if !(10.0..=10_000.0).contains(&tick_us) || tick_us.fract() != 0.0 {
                    return Err(e(format!("tick {tick_us}: 10 to 10000 whole microseconds")));
                }
            }
            "supplier" | "transfer" | "unloader" | "loading" => {
                links.push((ln, head, words.clone()))
            }
            "channel" => {
                if kind != Some("lathe") {
                    return Err(e(
                        "channels belong to a lathe: say 'kind lathe' first".into()
                    ));
                }
                if channels.len() == MAX_CHANNELS {
                    return Err(e(format!("at most {MAX_CHANNELS} channels")));
                }
                let n = channels.len() + 1;
                let cname = words
                    .get(1)
                    .map(|s| s.to_string())
                    .unwrap_or(format!("CH{n}"));
                if cname.len() > 12 {
                    return Err(e("a channel name has at most 12 characters".into()));
                }
                channels.push(ChannelDesc {
                    name: cname,
                    ..ChannelDesc::unset()
                });
            }
            "dialect" => {
                let d = match words.as_slice() {
                    [_, d] => crate::settings::Dialect::parse(d).map_err(e)?,
                    _ => return Err(e("dialect takes fanuc or linuxcnc".into())),
                };
                // In a lathe's channel, the channel's dialect; before the channels (or on a
                // mill), the machine's.
                set_here(
                    &mut channels,
                    in_channel,
                    |ch| &mut ch.dialect,
                    &mut dialect,
                    d,
                    "the dialect",
                )
                .map_err(e)?;
            }
            "gcode" => {
                let a = match words.as_slice() {
                    [_, "system", s] if s.eq_ignore_ascii_case("a") => true,
                    [_, "system", s] if s.eq_ignore_ascii_case("b") => false,
                    _ => {
                        return Err(e(
                            "gcode takes system A or system B (Fanuc's lathe G code systems)"
                                .into(),
                        ))
                    }
                };
                if !in_channel {
                    return Err(e(
                        "gcode system: a lathe channel's line (write 'channel NAME' first)".into(),
                    ));
                }
                let ch = channels.len() - 1;
                if system_a.iter().any(|&(c, _)| c == ch) {
                    return Err(e("the gcode system is given twice in this channel".into()));
                }
                // System B is kept as said (0), so that a second line is refused.
                system_a.push((ch, if a { ln } else { 0 }));
            }
            "feed" if kind == Some("lathe") => {
                let v = match words.as_slice() {
                    [_, "per-rev"] => true,
                    [_, "per-minute"] => false,
                    _ => return Err(e("feed takes per-rev or per-minute".into())),
                };
                // In a channel, the channel's; before the channels, the machine's.
                set_here(
                    &mut channels,
                    in_channel,
                    |ch| &mut ch.per_rev,
                    &mut feed,
                    v,
                    "feed",
                )
                .map_err(e)?;
            }
            "subroutines" if kind == Some("lathe") => {
                let dir = match words.as_slice() {
                    [_, d] => std::path::PathBuf::from(d),
                    _ => return Err(e("subroutines takes one folder (no spaces)".into())),
                };
                // In a channel, the channel's; before the channels, every channel's (after
                // its own).
                match channels.last_mut() {
                    Some(ch) if in_channel => ch.subroutines.push(dir),
                    _ => sub_path.push(dir),
                }
            }
            "common" | "decimal" => {
                // Fanuc's parameters 6001#6 and 3401#0 (docs/gcode.md "Fanuc dialect").
                let (slot, words_are) = if head == "common" {
                    (&mut fanuc.0, ["keep", "clear"])
                } else {
                    (&mut fanuc.1, ["calculator", "increments"])
                };
                // On a lathe, `common` and `decimal` are the channel's (in a channel) or the
                // machine's (before the channels), as `dialect` is.
                let lathe_common = kind == Some("lathe");
                let slot = match channels.last_mut() {
                    Some(ch) if lathe_common && in_channel && head == "common" => {
                        &mut ch.keep_common
                    }
                    Some(ch) if lathe_common && in_channel => &mut ch.calculator,
                    _ => slot,
                };
                let v = match words.as_slice() {
                    [_, w] if *w == words_are[0] => true,
                    [_, w] if *w == words_are[1] => false,
                    _ => {
                        return Err(e(format!(
                            "{head} takes {} or {} (the Fanuc dialect's setting)",
                            words_are[0], words_are[1]
                        )))
                    }
                };
                set_once(slot, v, head, lathe_common && in_channel).map_err(e)?;
                if kind != Some("mill") && !lathe_common {
                    return Err(e(format!(
                        "{head}: a setting of the Fanuc dialect: say 'kind mill' or 'kind lathe' first"
                    )));
                }
            }
            "remap" if kind == Some("lathe") => {
                let r = remap(&words, true).map_err(e)?;
                // In a channel, the channel's; before the channels, every channel's that does
                // not remap the code itself.
                let (list, whose) = match channels.last_mut() {
                    Some(ch) if in_channel => (&mut ch.remap_m, " in this channel"),
                    _ => (&mut lathe_remaps, ""),
                };
                if list.iter().any(|o| o.code == r.code) {
                    return Err(e(format!("M{} is remapped twice{whose}", r.code)));
                }
                list.push(r);
            }
            "g28" if kind == Some("lathe") => {
                let all = match words.as_slice() {
                    [_, "alone", "all"] => true,
                    [_, "alone", "refuse"] => false,
                    _ => return Err(e("g28 takes alone all or alone refuse (what a G28 that names no axis does in the Fanuc dialect)".into())),
                };
                set_here(
                    &mut channels,
                    in_channel,
                    |ch| &mut ch.g28_all,
                    &mut g28_all,
                    all,
                    "g28",
                )
                .map_err(e)?;
            }
            "g04" => {
                let seconds = match words.as_slice() {
                    [_, "p", "point", "seconds"] => true,
                    [_, "p", "point", "refuse"] => false,
                    _ => return Err(e("g04 takes p point seconds or p point refuse (what G04's P written with a decimal point is in the Fanuc dialect: a Haas's seconds, or refused as Fanuc refuses it)".into())),
                };
                set_here(
                    &mut channels,
                    in_channel,
                    |ch| &mut ch.p_point_seconds,
                    &mut p_point,
                    seconds,
                    "g04",
                )
                .map_err(e)?;
            }
            "remap" if kind == Some("mill") => match remap(&words, false).map_err(e)? {
                r if r.code == 6 && remap_m6.is_some() => {
                    return Err(e("M6 is remapped twice".into()))
                }
                r if r.code == 6 => remap_m6 = Some(r.ngc),
                r if remap_m
                    .iter()
                    .any(|o: &crate::settings::Remap| o.code == r.code) =>
                {
                    return Err(e(format!("M{} is remapped twice", r.code)))
                }
                r => remap_m.push(r),
            },
            "workpiece" if kind == Some("mill") => {
                workpiece.boxes.push(work_box(&words).map_err(e)?);
            }
            "toolchange" if kind == Some("mill") => {
                tool_change_z = Some(match words.as_slice() {
                    [_, "z", v] => (ln, num(Some(v), "toolchange z").map_err(e)?),
                    _ => return Err(e("toolchange takes z and a machine Z, mm".into())),
                });
            }
            "remap" => {
                return Err(e(
                    "remap belongs to a mill or a lathe: say 'kind mill' or 'kind lathe' first"
                        .into(),
                ))
            }
            "workpiece" | "toolchange" => {
                return Err(e(format!(
                    "{head} belongs to a mill: say 'kind mill' first"
                )))
            }
            "x" | "y" | "z" if kind == Some("mill") => {
                let a = axis(&words).map_err(e)?;
                mill_axes[match head {
                    "x" => 0,
                    "y" => 1,
                    _ => 2,
                }] = Some(a);
            }
            "a" | "b" | "c" if kind == Some("mill") => {
                let r = usize::from(head.as_bytes()[0] - b'a');
                if rotaries[r].is_some() {
                    return Err(e(format!(
                        "axis {} is described twice",
                        head.to_ascii_uppercase()
                    )));
                }
                rotaries[r] = Some(rotary(&words).map_err(e)?);
            }
            "x" | "z" if in_channel => {
                let a = axis(&words).map_err(e)?;
                if let Some(ch) = channels.last_mut() {
                    ch.axes[usize::from(head == "z")] = a;
                }
            }
            "spindle" if kind == Some("mill") => {
                if mill_spindle.is_some() {
                    return Err(e("the spindle is described twice".into()));
                }
                let mut ch = ChannelDesc::unset();
                spindle(&words, &mut ch).map_err(e)?;
                mill_spindle = Some(ch);
            }
            "spindle" if in_channel => {
                if let Some(ch) = channels.last_mut() {
                    spindle(&words, ch).map_err(e)?;
                }
            }
            "tool" if in_channel => {
                let t = tool(&words).map_err(e)?;
                if let Some(ch) = channels.last_mut() {
                    if ch.tool(t.number).is_some() {
                        return Err(e(format!("tool {} is given twice", t.number)));
                    }
                    if ch.tools.len() == MAX_TOOLS {
                        return Err(e(format!("at most {MAX_TOOLS} tools per channel")));
                    }
                    ch.tools.push(t);
                }
            }
            "x" | "y" | "z" | "a" | "spindle" | "tool" => {
                return Err(e(format!(
                    "'{head}' belongs to {}",
                    if kind == Some("lathe") {
                        "a channel (write 'channel NAME' first)"
                    } else {
                        "a described machine: say 'kind lathe' or 'kind mill' first"
                    }
                )))
            }
            w => {
                return Err(e(format!(
                    "'{w}' is not a description word (docs/lathe.md)"
                )))
            }
        }
    }
    let name = name.ok_or("1: the description has no 'machine NAME' line")?;
    match kind {
        Some("mill") => {
            let mut m = mill(&name, pulse_mm, mill_axes, &links)?;
            if let MachineDesc::Mill(s) = &mut m {
                for (r, given) in rotaries.iter().enumerate() {
                    let Some((a, wrap)) = given else { continue };
                    // A rotary axis: degrees, one pulse `pulse` degrees; its rate and
                    // acceleration are its own, and slow a move that turns it
                    // (docs/pulse-core.md, "Axes"). Until stop 54 they joined the path's
                    // along X Y Z, which slowed every rapid and limited no turn.
                    let i = crate::block::FIRST_ROTARY + r;
                    s.axis_kinds[i] = crate::settings::AxisKind::Rotary { wrap: *wrap };
                    s.travel_min_mm[i] = a.travel[0];
                    s.travel_max_mm[i] = a.travel[1];
                    s.axis_rate[i] = a.rapid;
                    s.axis_accel[i] = a.accel;
                }
                if let Some(sp) = &mill_spindle {
                    // The same words as a lathe channel's spindle (one description format):
                    // what is not given keeps the built-in (at speed at once, 1024 lines).
                    if sp.max_rpm > 0.0 {
                        s.spindle_max_rpm = sp.max_rpm;
                    }
                    s.spindle_accel_rpm_s = sp.spindle_accel;
                    if sp.encoder > 0 {
                        s.spindle_encoder_lines = sp.encoder;
                    }
                }
                s.remap_m6 = remap_m6;
                s.remap_m = remap_m;
                s.dialect = dialect.unwrap_or_default();
                s.fanuc = crate::settings::FanucSettings {
                    keep_common: fanuc.0.unwrap_or(false),
                    calculator: fanuc.1.unwrap_or(false),
                    p_point_seconds: p_point.unwrap_or(false),
                };
                s.workpiece = workpiece;
                if let Some((ln, z)) = tool_change_z {
                    if !(s.travel_min_mm[2]..=s.travel_max_mm[2]).contains(&z) {
                        return Err(format!(
                            "{ln}: toolchange z {z}: outside the Z travel {} to {}",
                            s.travel_min_mm[2], s.travel_max_mm[2]
                        ));
                    }
                    s.tool_change_z_mm = z;
                } else {
                    s.tool_change_z_mm = s.travel_max_mm[2];
                }
            }
            Ok(m)
        }
        Some(_) => {
            // The machine's dialect line says it for the channels that do not.
            for ch in &mut channels {
                ch.dialect = ch.dialect.or(dialect);
                ch.keep_common = ch.keep_common.or(fanuc.0);
                ch.calculator = ch.calculator.or(fanuc.1);
                ch.per_rev = ch.per_rev.or(feed);
                ch.subroutines.extend(sub_path.iter().cloned());
                ch.g28_all = ch.g28_all.or(g28_all);
                ch.p_point_seconds = ch.p_point_seconds.or(p_point);
                for r in &lathe_remaps {
                    if ch.remap_m.iter().all(|o| o.code != r.code) {
                        ch.remap_m.push(r.clone());
                    }
                }
            }
            // System A is Fanuc's: LinuxCNC's lathe has system B only.
            for &(c, ln) in system_a.iter().filter(|s| s.1 > 0) {
                let Some(ch) = channels.get_mut(c) else {
                    continue;
                };
                if ch.dialect != Some(crate::settings::Dialect::Fanuc) {
                    return Err(format!(
                        "{ln}: gcode system A is Fanuc's G code system: give 'dialect fanuc' in this channel or before the channels (LinuxCNC's lathe reads system B only)"
                    ));
                }
                ch.system_a = true;
            }
            lathe(name, pulse_mm, tick_us, channels, &links)
        }
        None => Err("1: the description has no 'kind lathe' or 'kind mill' line".into()),
    }
}

/// Sets a setting a description may give once (in a lathe's channel, once there): `what is
/// given twice`, else.
/// [`set_once`] on the channel being described (`field` of the last channel, in a lathe's
/// channel) or else on the machine's `machine`: a setting a lathe gives per channel or, before
/// its channels, for every channel (a mill's is the machine's).
fn set_here<T>(
    channels: &mut [ChannelDesc],
    in_channel: bool,
    field: fn(&mut ChannelDesc) -> &mut Option<T>,
    machine: &mut Option<T>,
    v: T,
    what: &str,
) -> Result<(), String> {
    let slot = match channels.last_mut() {
        Some(ch) if in_channel => field(ch),
        _ => machine,
    };
    set_once(slot, v, what, in_channel)
}

fn set_once<T>(slot: &mut Option<T>, v: T, what: &str, in_channel: bool) -> Result<(), String> {
    if slot.is_some() {
        let whose = if in_channel { " in this channel" } else { "" };
        return Err(format!("{what} is given twice{whose}"));
    }
    *slot = Some(v);
    Ok(())
}

/// `workpiece box X1 Y1 Z1 X2 Y2 Z2`: a box of stock between two corners, machine mm of the
/// tool tip (docs/gcode.md "Probing").
fn work_box(words: &[&str]) -> Result<crate::workpiece::Cuboid, String> {
    if words.len() != 8 || words[1] != "box" {
        return Err("workpiece takes box and two corners: X1 Y1 Z1 X2 Y2 Z2 (machine mm)".into());
    }
    let mut v = [0.0; 6];
    for (i, w) in words[2..].iter().enumerate() {
        v[i] = num(Some(w), "workpiece box")?;
    }
    if (0..3).any(|a| v[a] == v[a + 3]) {
        return Err("workpiece box: the corners must differ on every axis".into());
    }
    Ok(crate::workpiece::Cuboid::new(
        [v[0], v[1], v[2]],
        [v[3], v[4], v[5]],
    ))
}

/// `remap M6 modalgroup=6 ngc=NAME`, or `remap Mn modalgroup=10 [argspec=LETTERS] ngc=NAME`
/// for an M code novanc does not define (M0–M199): LinuxCNC's `REMAP=...` line (docs/gcode.md
/// "Remapping M6 and other M codes").
fn remap(words: &[&str], lathe: bool) -> Result<crate::settings::Remap, String> {
    let code = words.get(1).and_then(|c| {
        let c = c.strip_prefix(['M', 'm'])?;
        c.parse::<u32>().ok()
    });
    let m = match code {
        // The lathe's M6 indexes the turret at once (docs/lathe-gcode.md "T").
        Some(6) if lathe => {
            return Err(
                "remap M6: the lathe's M6 indexes the turret (T0101 M6): remap an M code the lathe does not define".into(),
            )
        }
        Some(6) => 6,
        Some(m) if (100..200).contains(&m) && lathe => {
            return Err(format!(
                "remap M{m}: M100 to M199 are the lathe's waiting codes (docs/lathe.md); remap an M code below M100 it does not define"
            ))
        }
        Some(m) if m < 200 && lathe && crate::lathe::gcode::m_code_known(m) => {
            return Err(format!(
                "remap M{m}: the lathe defines M{m} itself; remap an M code it does not define"
            ))
        }
        Some(m) if m < 200 && !lathe && crate::gcode::words::m_code_known(m) => {
            return Err(format!(
                "remap M{m}: novanc defines M{m} itself; remap M6, or an M code it does not define"
            ))
        }
        Some(m) if m < 200 => m,
        _ if lathe => {
            return Err(
                "remap: name an M code the lathe does not define, M0 to M99 (remap M31 modalgroup=10 ngc=NAME)"
                    .into(),
            )
        }
        _ => {
            return Err(
                "remap: name M6 or an M code novanc does not define, M0 to M199 (remap M6 modalgroup=6 ngc=NAME, remap M31 modalgroup=10 ngc=NAME)"
                    .into(),
            )
        }
    };
    let group = if m == 6 { "6" } else { "10" };
    let mut ngc = None;
    let mut argspec = String::new();
    for w in &words[2..] {
        match w.split_once('=') {
            Some(("modalgroup", g)) if g == group => {}
            Some(("modalgroup", g)) => {
                return Err(match m {
                    6 => format!("remap M6: modalgroup={g}: M6 is in modal group 6"),
                    _ if lathe => format!(
                        "remap M{m}: modalgroup={g}: the lathe remaps M codes in modal group 10 (run after the coolant, chuck and waiting codes, before G4)"
                    ),
                    _ => format!(
                        "remap M{m}: modalgroup={g}: novanc remaps other M codes in modal group 10 (run after M48–M53, before G4)"
                    ),
                })
            }
            Some(("ngc", n)) => {
                let n = n.to_ascii_lowercase();
                let ok = !n.is_empty()
                    && n.len() <= 64
                    && n.bytes().all(|b| b.is_ascii_alphanumeric() || b == b'_' || b == b'-');
                if !ok {
                    return Err(format!(
                        "remap M{m}: ngc={n}: a subroutine name of letters, digits, _ and -"
                    ));
                }
                ngc = Some(n);
            }
            Some(("argspec", _)) if m == 6 => {
                return Err(
                    "remap M6: argspec= is read for the other M codes only (M6's subroutine gets #<selected_tool> and #<tool_in_spindle>)"
                        .into(),
                )
            }
            Some(("argspec", a)) => argspec = remap_argspec(m, a)?,
            Some((k @ ("prolog" | "epilog" | "python"), _)) => {
                return Err(format!(
                    "remap M{m}: {k}= names a Python function: novanc runs none (an M6 subroutine gets #<selected_tool> and #<tool_in_spindle> as LinuxCNC's change_prolog gives them)"
                ))
            }
            _ => {
                return Err(format!(
                    "remap M{m}: '{w}' is not modalgroup={group}, argspec=LETTERS or ngc=NAME"
                ))
            }
        }
    }
    let ngc =
        ngc.ok_or_else(|| format!("remap M{m} needs ngc=NAME, the O-word subroutine M{m} calls"))?;
    Ok(crate::settings::Remap {
        code: m,
        ngc,
        argspec,
    })
}

/// A remap's `argspec=` (LinuxCNC's): the letters of the line its subroutine gets as locals
/// (`#<p>`), a capital one required; `-` means none. LinuxCNC's `@` (positional arguments),
/// `>`, `^` and `N` (a feed, a speed, the line number) are not read, and are refused.
fn remap_argspec(m: u32, a: &str) -> Result<String, String> {
    let mut out = String::new();
    for c in a.chars() {
        match c {
            '-' => {}
            'A'..='F' | 'H'..='L' | 'P'..='T' | 'X'..='Z' | 'a'..='f' | 'h'..='l' | 'p'..='t'
            | 'x'..='z' => {
                if out.chars().any(|o| o.eq_ignore_ascii_case(&c)) {
                    return Err(format!("remap M{m}: argspec={a}: {c} is given twice"));
                }
                out.push(c);
            }
            '@' | '>' | '^' | 'N' | 'n' => {
                return Err(format!(
                    "remap M{m}: argspec={a}: '{c}' is not read (novanc passes the words as named locals #<p> only)"
                ))
            }
            _ => {
                return Err(format!(
                    "remap M{m}: argspec={a}: '{c}' is not a word a line may give (A-F, H-L, P-T, X-Z)"
                ))
            }
        }
    }
    Ok(out)
}

fn mill(
    _name: &str,
    pulse_mm: f64,
    axes: [Option<AxisDesc>; 3],
    links: &[(usize, &str, Vec<&str>)],
) -> Result<MachineDesc, String> {
    if let Some((ln, w, _)) = links.first() {
        return Err(format!("{ln}: '{w}' belongs to a lathe with channels"));
    }
    let mut s = crate::settings::MachineSettings {
        pulse_mm,
        ..crate::settings::MachineSettings::builtin()
    };
    // Each axis its own rate and acceleration (the path's the highest, each axis held to its
    // own).
    let mut rapid = 0.0f64;
    let mut accel = 0.0f64;
    for (i, a) in axes.iter().enumerate() {
        let a = a
            .as_ref()
            .ok_or(format!("1: axis {} is not described", ['X', 'Y', 'Z'][i]))?;
        s.travel_min_mm[i] = a.travel[0];
        s.travel_max_mm[i] = a.travel[1];
        s.axis_rate[i] = a.rapid;
        s.axis_accel[i] = a.accel;
        rapid = rapid.max(a.rapid);
        accel = accel.max(a.accel);
    }
    s.rapid_mm_min = rapid;
    s.accel_mm_s2 = accel;
    Ok(MachineDesc::Mill(s))
}

fn lathe(
    name: String,
    pulse_mm: f64,
    tick_us: f64,
    channels: Vec<ChannelDesc>,
    links: &[(usize, &str, Vec<&str>)],
) -> Result<MachineDesc, String> {
    if channels.is_empty() {
        return Err("1: a lathe needs at least one 'channel'".into());
    }
    for (i, c) in channels.iter().enumerate() {
        let n = i + 1;
        for (a, l) in c.axes.iter().zip(['X', 'Z']) {
            if a.travel[0].is_nan() {
                return Err(format!(
                    "1: channel {n} has no {l} axis ('{} travel ..')",
                    l.to_ascii_lowercase()
                ));
            }
        }
        if c.encoder == 0 || c.max_rpm == 0.0 || c.spindle_accel == 0.0 {
            return Err(format!(
                "1: channel {n} needs 'spindle max RPM accel RPM/S encoder LINES'"
            ));
        }
    }
    let n = channels.len();
    let mut d = LatheDesc {
        name,
        pulse_mm,
        tick_ns: tick_us as u64 * 1000,
        channels,
        supplier: 0,
        transfers: Vec::new(),
        unloader: n - 1,
        manual: false,
    };
    for (ln, w, words) in links {
        let e = |m: String| format!("{ln}: {m}");
        match *w {
            "loading" => {
                d.manual = match (words.get(1).copied(), words.len()) {
                    (Some("manual"), 2) => true,
                    (Some("bar"), 2) => false,
                    _ => return Err(e(
                        "loading: 'loading manual' (the operator loads each work) or 'loading bar'"
                            .into(),
                    )),
                };
                if d.manual && n != 1 {
                    return Err(e(format!(
                        "loading manual: a lathe of one channel is loaded by hand; this one has {n}"
                    )));
                }
            }
            "supplier" => d.supplier = channel_no(words.get(1), n, "supplier").map_err(e)?,
            "unloader" => d.unloader = channel_no(words.get(1), n, "unloader").map_err(e)?,
            _ => {
                let a = channel_no(words.get(1), n, "transfer").map_err(e)?;
                let b = channel_no(words.get(2), n, "transfer").map_err(e)?;
                if a == b || d.receiver_of(a).is_some() || d.supplier_of(b).is_some() {
                    return Err(e(format!(
                        "transfer {} {}: each channel passes to one other and receives from one other",
                        a + 1,
                        b + 1
                    )));
                }
                d.transfers.push((a, b));
            }
        }
    }
    // The work must flow in one line from the supplier to the unloader.
    let mut ch = d.supplier;
    let mut seen = 1;
    while let Some(next) = d.receiver_of(ch) {
        ch = next;
        seen += 1;
        if seen > n {
            return Err("1: the transfers make a loop".into());
        }
    }
    if ch != d.unloader {
        return Err(format!(
            "1: the work from the supplier (channel {}) ends at channel {}, not at the unloader's channel {}",
            d.supplier + 1,
            ch + 1,
            d.unloader + 1
        ));
    }
    Ok(MachineDesc::Lathe(d))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_embedded_machines_parse() {
        let c = LatheDesc::citizen();
        assert_eq!(c.channels.len(), 3);
        assert_eq!(c.transfers, vec![(0, 1), (1, 2)]);
        assert_eq!((c.supplier, c.unloader, c.tick_ns), (0, 2, 100_000));
        assert_eq!(
            c.channels[0].tool(1).map(|t| (t.radius, t.tip)),
            Some((0.8, 3))
        );
        assert_eq!(c.channels[2].encoder, 1024);
        match load("centre") {
            Ok(MachineDesc::Mill(s)) => assert_eq!(s, crate::settings::MachineSettings::default()),
            other => panic!("centre: {other:?}"),
        }
    }

    #[test]
    fn bad_descriptions_name_their_line() {
        let base = "machine m\nkind lathe\nchannel A\nx travel 0 10 rapid 100 accel 100\nz travel 0 10 rapid 100 accel 100\nspindle max 100 accel 100 encoder 10\n";
        assert!(matches!(parse(base), Ok(MachineDesc::Lathe(_))));
        for (extra, want) in [
            ("tool 1 radius -1\n", "7: radius -1"),
            ("tool 1 tip 10\n", "7: tip 10"),
            ("tool 1\ntool 1\n", "8: tool 1 is given twice"),
            ("bogus\n", "7: 'bogus' is not"),
            ("transfer 1 2\n", "7: transfer: channel 2 does not exist"),
            ("x travel 5 1 rapid 1 accel 1\n", "7: travel 5 1"),
            ("spindle encoder 0.5\n", "7: spindle encoder 0.5"),
            ("unloader 1\nsupplier 1\ntransfer 1 1\n", "9: transfer 1 1"),
        ] {
            let text = format!("{base}{extra}");
            match parse(&text) {
                Err(m) => assert!(m.starts_with(want), "{extra:?}: {m}"),
                Ok(d) => panic!("{extra:?} accepted: {d:?}"),
            }
        }
        assert!(parse("kind lathe\n")
            .unwrap_err()
            .contains("no 'machine NAME'"));
        assert!(parse("machine m\nkind lathe\n")
            .unwrap_err()
            .contains("at least one"));
        assert!(parse("machine m\ntool 1\n")
            .unwrap_err()
            .starts_with("2: 'tool' belongs"));
        assert!(load("/nonexistent/m.machine")
            .unwrap_err()
            .contains("a machine is"));
    }

    #[test]
    fn tool_lines_read_back() {
        let t = ToolDesc {
            number: 7,
            radius: 0.4,
            tip: 2,
            offset: [0.025, -0.01],
        };
        assert_eq!(parse_tool(&tool_line(&t)), Ok(t));
        assert!(parse_tool("tool 7 tip 12").unwrap_err().contains("tip 12"));
        assert!(parse_tool("axis").is_err());
    }

    #[test]
    fn a_mill_spindle_line_is_a_lathe_channels_words() {
        let base = "machine m\nkind mill\nx travel 0 300 rapid 8000 accel 500\ny travel 0 200 rapid 9000 accel 400\nz travel -100 0 rapid 5000 accel 800\n";
        match parse(&format!("{base}spindle max 6000 accel 2000 encoder 4096\n")) {
            Ok(MachineDesc::Mill(s)) => {
                assert_eq!(s.spindle_max_rpm, 6000.0);
                assert_eq!(s.spindle_accel_rpm_s, 2000.0);
                assert_eq!(s.spindle_encoder_lines, 4096);
                assert!(!s.tool_turret, "a mill changes tools with M6");
            }
            other => panic!("{other:?}"),
        }
        // Without the line the spindle is the built-in one: at speed at once.
        match parse(base) {
            Ok(MachineDesc::Mill(s)) => {
                let b = crate::settings::MachineSettings::builtin();
                assert_eq!(s.spindle_accel_rpm_s, b.spindle_accel_rpm_s);
                assert_eq!(s.spindle_encoder_lines, b.spindle_encoder_lines);
            }
            other => panic!("{other:?}"),
        }
        assert!(parse(&format!("{base}spindle max 6000\nspindle accel 1\n"))
            .unwrap_err()
            .starts_with("7: the spindle is described twice"));
        assert!(parse(&format!("{base}spindle encoder 0.5\n"))
            .unwrap_err()
            .contains("spindle encoder 0.5"));
    }

    #[test]
    fn a_mill_description_sets_the_centres_axes() {
        let t = "machine small\nkind mill\npulse 0.002\nx travel 0 300 rapid 8000 accel 500\ny travel 0 200 rapid 9000 accel 400\nz travel -100 0 rapid 5000 accel 800\n";
        match parse(t) {
            Ok(MachineDesc::Mill(s)) => {
                assert_eq!(s.pulse_mm, 0.002);
                assert_eq!(s.travel_max_mm, [300.0, 200.0, 0.0]);
                // Each axis its own rate and acceleration, the path's the highest.
                assert_eq!((s.rapid_mm_min, s.accel_mm_s2), (9000.0, 800.0));
                assert_eq!(s.axis_rate[..3], [8000.0, 9000.0, 5000.0]);
                assert_eq!(s.axis_accel[..3], [500.0, 400.0, 800.0]);
                assert!(s.axis_rate[3..].iter().all(|r| r.is_infinite()));
            }
            other => panic!("{other:?}"),
        }
    }

    #[test]
    fn a_mill_description_remaps_m6_as_linuxcnc_writes_it() {
        let base = "machine m\nkind mill\nx travel 0 300 rapid 8000 accel 500\ny travel 0 200 rapid 9000 accel 400\nz travel -100 0 rapid 5000 accel 800\n";
        match parse(&format!(
            "{base}remap M6 modalgroup=6 ngc=ToolChange\nremap M31 modalgroup=10 ngc=conveyor_on\nremap m33 ngc=Conveyor_off\nremap M59 modalgroup=10 argspec=P-q ngc=relay\n"
        )) {
            Ok(MachineDesc::Mill(s)) => {
                assert_eq!(s.remap_m6.as_deref(), Some("toolchange"));
                let relay = crate::settings::Remap {
                    argspec: "Pq".into(),
                    ..crate::settings::Remap::new(59, "relay")
                };
                assert_eq!(
                    s.remap_m,
                    [
                        crate::settings::Remap::new(31, "conveyor_on"),
                        crate::settings::Remap::new(33, "conveyor_off"),
                        relay
                    ]
                );
            }
            other => panic!("{other:?}"),
        }
        for (line, want) in [
            ("remap M3 ngc=x", "6: remap M3: novanc defines M3 itself"),
            ("remap M98 ngc=x", "6: remap M98: novanc defines M98 itself"),
            ("remap G12 ngc=x", "6: remap: name M6 or an M code"),
            ("remap M200 ngc=x", "6: remap: name M6 or an M code"),
            (
                "remap M31 modalgroup=6 ngc=x",
                "6: remap M31: modalgroup=6: novanc remaps other",
            ),
            ("remap M31 modalgroup=10", "6: remap M31 needs ngc=NAME"),
            (
                "remap M31 argspec=@P ngc=x",
                "6: remap M31: argspec=@P: '@' is not read",
            ),
            (
                "remap M31 argspec=PG ngc=x",
                "6: remap M31: argspec=PG: 'G' is not a word",
            ),
            (
                "remap M31 argspec=Pp ngc=x",
                "6: remap M31: argspec=Pp: p is given twice",
            ),
            (
                "remap M6 argspec=P ngc=x",
                "6: remap M6: argspec= is read for the other",
            ),
            (
                "remap M31 ngc=a\nremap M31 ngc=b",
                "7: M31 is remapped twice",
            ),
            ("remap M6 modalgroup=5 ngc=x", "6: remap M6: modalgroup=5"),
            ("remap M6 modalgroup=6", "6: remap M6 needs ngc=NAME"),
            ("remap M6 ngc=../x", "6: remap M6: ngc=../x"),
            (
                "remap M6 prolog=change_prolog ngc=x",
                "6: remap M6: prolog= names a Python",
            ),
            ("remap M6 ngc=a\nremap M6 ngc=b", "7: M6 is remapped twice"),
        ] {
            let e = parse(&format!("{base}{line}\n")).unwrap_err();
            assert!(e.starts_with(want), "{line}: {e}");
        }
        // A lathe's M6 indexes the turret: a lathe remaps other codes only
        // (tests/lathe_shop_codes.rs).
        assert!(parse("machine m\nkind lathe\nremap M6 ngc=x\n")
            .unwrap_err()
            .starts_with("3: remap M6: the lathe's M6 indexes the turret"));
        assert!(parse("machine m\nremap M31 ngc=x\n")
            .unwrap_err()
            .starts_with("2: remap belongs to a mill or a lathe"));
    }

    #[test]
    fn the_centre_description_is_the_default_settings() {
        let s = crate::settings::MachineSettings::default();
        assert_eq!(s.workpiece.boxes.len(), 1);
        assert_eq!(s.workpiece.boxes[0].max, [700.0, 600.0, -450.0]);
        assert_eq!(s.tool_change_z_mm, 0.0);
        // What the description does not give is the builtin's.
        let b = crate::settings::MachineSettings::builtin();
        assert!(b.workpiece.boxes.is_empty());
        assert_eq!((s.jog_mm_min, s.spindle_ns), (b.jog_mm_min, b.spindle_ns));
        let base = "machine m\nkind mill\nx travel 0 300 rapid 8000 accel 500\ny travel 0 200 rapid 9000 accel 400\nz travel -100 -10 rapid 5000 accel 800\n";
        match parse(&format!(
            "{base}workpiece box 0 0 -100 10 10 -90\nworkpiece box 20 0 -100 30 10 -80\n"
        )) {
            Ok(MachineDesc::Mill(s)) => {
                assert_eq!(s.workpiece.boxes.len(), 2);
                // No toolchange line: the top of the Z travel.
                assert_eq!(s.tool_change_z_mm, -10.0);
            }
            other => panic!("{other:?}"),
        }
        for (line, want) in [
            ("workpiece box 0 0 0 1 1", "6: workpiece takes box"),
            ("workpiece box 0 0 0 1 1 0", "6: workpiece box: the corners"),
            ("workpiece box 0 0 0 1 1 x", "6: workpiece box: 'x' is not"),
            ("toolchange z", "6: toolchange takes z"),
            ("toolchange z 5", "6: toolchange z 5: outside the Z travel"),
        ] {
            let e = parse(&format!("{base}{line}\n")).unwrap_err();
            assert!(e.starts_with(want), "{line}: {e}");
        }
        assert!(parse("machine m\nkind lathe\nworkpiece box 0 0 0 1 1 1\n")
            .unwrap_err()
            .starts_with("3: workpiece belongs to a mill"));
    }
}
