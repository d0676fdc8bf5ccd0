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
}

impl ChannelDesc {
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
}
