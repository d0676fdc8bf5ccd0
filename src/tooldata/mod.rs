//! Tool data: tool records, the tool tape format, the T-code table and the tool file
//! (patent lines 197–203 and 279–281, Figs. 6 and 8; docs/stores.md).
//!
//! The tool file is indexed by T code (magazine pocket). The T-code table says which tool number
//! sits in which pocket. TOOL DATA READ stores only the tape records whose tool number is in the
//! T-code table, each in its T code's slot.

mod tape;
mod tcode;

pub use tape::{format_record, parse_record, parse_tape, TapeError};
pub use tcode::{parse_tcodes, TCodeTable};

use std::fmt;

/// The kind of a tool, as the two-letter code on the tape.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ToolKind {
    /// DR: twist drill.
    Drill,
    /// CD: centre drill.
    CentreDrill,
    /// TP: tap.
    Tap,
    /// RM: reamer.
    Reamer,
    /// EM: end mill.
    EndMill,
    /// FM: face mill.
    FaceMill,
    /// BB: boring bar.
    BoringBar,
}

impl ToolKind {
    /// Every kind, in tape-code order.
    pub const ALL: [ToolKind; 7] = [
        ToolKind::Drill,
        ToolKind::CentreDrill,
        ToolKind::Tap,
        ToolKind::Reamer,
        ToolKind::EndMill,
        ToolKind::FaceMill,
        ToolKind::BoringBar,
    ];

    /// The two-letter tape code.
    pub fn code(self) -> &'static str {
        match self {
            ToolKind::Drill => "DR",
            ToolKind::CentreDrill => "CD",
            ToolKind::Tap => "TP",
            ToolKind::Reamer => "RM",
            ToolKind::EndMill => "EM",
            ToolKind::FaceMill => "FM",
            ToolKind::BoringBar => "BB",
        }
    }

    /// The kind for a tape code, if it is one.
    pub fn from_code(code: &str) -> Option<ToolKind> {
        ToolKind::ALL.into_iter().find(|k| k.code() == code)
    }
}

impl fmt::Display for ToolKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.code())
    }
}

/// One tool's data (Fig. 6): number, kind, sizes, speed, feed and normal depth.
#[derive(Clone, Debug, PartialEq)]
pub struct ToolRecord {
    /// Tool number, up to 5 digits (1..=99999).
    pub number: u32,
    /// Tool kind.
    pub kind: ToolKind,
    /// Diameter, mm.
    pub diameter: f64,
    /// Set length (gauge line to tip), mm; carried by the machine Z axis.
    pub set_length: f64,
    /// Effective (cutting) length, mm.
    pub effective_length: f64,
    /// Spindle speed, rpm.
    pub speed: f64,
    /// Feed rate, mm/min.
    pub feed: f64,
    /// Normal depth, mm (used by `SDP` with no value).
    pub depth: f64,
    /// Length wear, mm, added to the set length (the OFS page; 0 on a tape).
    pub wear_length: f64,
    /// Diameter wear, mm, added to the diameter (the OFS page; 0 on a tape).
    pub wear_diameter: f64,
}

/// The largest length or diameter wear, mm, either way.
pub const MAX_WEAR_MM: f64 = 10.0;

impl ToolRecord {
    /// The length the Z axis carries: set length plus length wear, mm.
    pub fn length(&self) -> f64 {
        self.set_length + self.wear_length
    }

    /// The diameter that cuts: diameter plus diameter wear, mm.
    pub fn cutting_diameter(&self) -> f64 {
        self.diameter + self.wear_diameter
    }
}

/// The tool file: one optional record per T code, slots 1..=capacity.
#[derive(Clone, Debug, PartialEq)]
pub struct ToolFile {
    slots: Vec<Option<ToolRecord>>,
}

impl ToolFile {
    /// An empty tool file for a magazine of `capacity` pockets.
    pub fn new(capacity: u32) -> ToolFile {
        ToolFile {
            slots: vec![None; capacity as usize],
        }
    }

    /// Number of T codes (pockets).
    pub fn capacity(&self) -> u32 {
        self.slots.len() as u32
    }

    /// The record in T code `t`, if any.
    pub fn get(&self, t: u32) -> Option<&ToolRecord> {
        let i = (t as usize).checked_sub(1)?;
        self.slots.get(i)?.as_ref()
    }

    /// Store or clear the record of T code `t`; false if `t` is not a pocket.
    pub fn set(&mut self, t: u32, rec: Option<ToolRecord>) -> bool {
        match (t as usize)
            .checked_sub(1)
            .and_then(|i| self.slots.get_mut(i))
        {
            Some(slot) => {
                *slot = rec;
                true
            }
            None => false,
        }
    }

    /// (T code, record) for every filled slot, in T-code order.
    pub fn iter(&self) -> impl Iterator<Item = (u32, &ToolRecord)> {
        self.slots
            .iter()
            .enumerate()
            .filter_map(|(i, r)| r.as_ref().map(|r| (i as u32 + 1, r)))
    }
}

/// Why a tool number could not be used at a cutting statement.
#[derive(Clone, Debug, PartialEq)]
pub enum ToolLookupError {
    /// No T code holds this tool number.
    NotInMagazine(u32),
    /// The tool is assigned to a T code but its data was never read into the tool file.
    NoData { tool: u32, tcode: u32 },
}

impl fmt::Display for ToolLookupError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ToolLookupError::NotInMagazine(n) => {
                write!(f, "tool {n:05} is not in the magazine (no T code holds it)")
            }
            ToolLookupError::NoData { tool, tcode } => write!(
                f,
                "tool {tool:05} is in T{tcode:02} but the tool file has no data for it; read the tool tape"
            ),
        }
    }
}

/// What the translator sees of the tool data: the T-code table and the tool file together.
#[derive(Clone, Debug, PartialEq)]
pub struct Magazine {
    /// Which tool number sits in which pocket.
    pub tcodes: TCodeTable,
    /// The data of the tools in the pockets.
    pub tools: ToolFile,
}

impl Magazine {
    /// Builds the magazine by TOOL DATA READ of `tape` through `tcodes`.
    pub fn load(tcodes: TCodeTable, tape: &[ToolRecord]) -> Magazine {
        let mut tools = ToolFile::new(tcodes.capacity());
        for rec in tape {
            if let Some(t) = tcodes.tcode_of(rec.number) {
                tools.set(t, Some(rec.clone()));
            }
        }
        Magazine { tcodes, tools }
    }

    /// Looks a tool number up through the T-code table: (T code, record).
    pub fn find(&self, tool: u32) -> Result<(u32, &ToolRecord), ToolLookupError> {
        let t = self
            .tcodes
            .tcode_of(tool)
            .ok_or(ToolLookupError::NotInMagazine(tool))?;
        match self.tools.get(t) {
            Some(rec) if rec.number == tool => Ok((t, rec)),
            _ => Err(ToolLookupError::NoData { tool, tcode: t }),
        }
    }
}

/// The sample tool tape shipped in `tooldata/tools.tt`, embedded.
pub const SAMPLE_TAPE: &str = include_str!("../../tooldata/tools.tt");
/// The sample T-code table shipped in `tooldata/magazine.tc`, embedded.
pub const SAMPLE_TCODES: &str = include_str!("../../tooldata/magazine.tc");

/// The embedded default magazine: the sample T-code table loaded from the sample tape.
pub fn sample_magazine() -> Magazine {
    let tape = parse_tape(SAMPLE_TAPE, "tools.tt").unwrap_or_default();
    let tcodes =
        parse_tcodes(SAMPLE_TCODES, "magazine.tc", 24).unwrap_or_else(|_| TCodeTable::new(24));
    Magazine::load(tcodes, &tape)
}
