//! What a recording says about its run before the first message (docs/recording.md,
//! "Attachments"): the program (name and text), the tool data, the work offsets and the
//! machine's description, as MCAP attachments, and a `novanc.program` metadata record.

use crate::settings::MachineSettings;
use crate::tooldata::Magazine;
use std::collections::BTreeMap;
use std::fmt::Write;

/// The names of the work offsets in `RecordingInfo::work_offsets`.
pub const WORK_SYSTEMS: [&str; 6] = ["G54", "G55", "G56", "G57", "G58", "G59"];

/// The run's program and data, as the front end has them when the recording starts.
#[derive(Clone, Debug, Default)]
pub struct RecordingInfo {
    /// The program's name (a file path, or a name in program memory); empty: none.
    pub program_name: String,
    /// The program's text.
    pub program_text: String,
    /// The magazine: T codes and the tool file.
    pub magazine: Option<Magazine>,
    /// Work offsets G54 to G59: X Y Z in machine mm, then A B C in degrees (those the machine
    /// has are written).
    pub work_offsets: [[f64; crate::block::MAX_AXES]; 6],
    /// A kernel's machine (a lathe): its name (empty: the centre's single machine).
    pub machine_name: String,
    /// A kernel's channels, each with its program and tool post (empty: a single machine,
    /// whose program is `program_name`).
    pub channels: Vec<ChannelInfo>,
}

/// One channel of a kernel's machine as the recording starts (docs/recording.md,
/// "Attachments").
#[derive(Clone, Debug)]
pub struct ChannelInfo {
    /// Its name as the display shows it.
    pub name: String,
    /// Its program's name and text (an empty name: none).
    pub program_name: String,
    pub program_text: String,
    /// Its description (travel, rates, spindle, clock), as `machine.json` says the centre's.
    pub settings: MachineSettings,
    /// Its tool post: (tool number, nose radius mm, imaginary tip 0–9, X (radius) and Z
    /// offsets mm).
    pub tools: Vec<(u32, f64, u8, [f64; 2])>,
    /// Its work offsets G54 to G59 as the recording starts: X (a radius) and Z, mm from the
    /// machine's zero.
    pub work_offsets: [[f64; 2]; 6],
}

/// One attachment: name, media type, bytes.
pub type Attachment = (String, &'static str, Vec<u8>);

impl RecordingInfo {
    /// (T code, cutting diameter, length) of every tool in the tool file, mm: the sizes the
    /// scene draws.
    pub fn tool_sizes(&self) -> Vec<(u32, f64, f64)> {
        self.magazine
            .iter()
            .flat_map(|m| m.tools.iter())
            .map(|(t, r)| (t, r.cutting_diameter(), r.length()))
            .collect()
    }

    /// The attachments, in file order: `program/NAME` (when there is a program),
    /// `tooldata.csv`, `work_offsets.csv`, `machine.json`.
    pub fn attachments(&self, settings: &MachineSettings) -> Vec<Attachment> {
        let mut out = Vec::new();
        if !self.program_name.is_empty() {
            out.push((
                format!("program/{}", self.program_name),
                "text/plain",
                self.program_text.as_bytes().to_vec(),
            ));
        }
        out.push((
            "tooldata.csv".to_string(),
            "text/csv",
            self.tool_csv().into_bytes(),
        ));
        // A column for each axis the machine has: X Y Z in mm, a rotary axis in degrees.
        let axes: Vec<usize> = settings.axis_list().collect();
        let mut wpo = String::from("system");
        for &a in &axes {
            let letter = crate::pulse_core::axis_name(a).to_ascii_lowercase();
            let _ = write!(wpo, ",{letter}_{}", settings.unit(a));
        }
        wpo.push('\n');
        for (n, o) in WORK_SYSTEMS.iter().zip(self.work_offsets.iter()) {
            wpo.push_str(n);
            for &a in &axes {
                let _ = write!(wpo, ",{}", o[a]);
            }
            wpo.push('\n');
        }
        out.push(("work_offsets.csv".to_string(), "text/csv", wpo.into_bytes()));
        out.push((
            "machine.json".to_string(),
            "application/json",
            machine_json(settings).into_bytes(),
        ));
        for (i, c) in self.channels.iter().enumerate() {
            let n = i + 1;
            if !c.program_name.is_empty() {
                out.push((
                    format!("channel{n}/program/{}", c.program_name),
                    "text/plain",
                    c.program_text.as_bytes().to_vec(),
                ));
            }
            let mut tools = String::from("tool,nose_radius_mm,tip,x_offset_mm,z_offset_mm\n");
            for (t, r, tip, o) in &c.tools {
                let _ = writeln!(tools, "{t},{r},{tip},{},{}", o[0], o[1]);
            }
            out.push((
                format!("channel{n}/tooldata.csv"),
                "text/csv",
                tools.into_bytes(),
            ));
            let mut wpo = String::from("system,x_mm,z_mm\n");
            for (s, [x, z]) in WORK_SYSTEMS.iter().zip(&c.work_offsets) {
                let _ = writeln!(wpo, "{s},{x},{z}");
            }
            out.push((
                format!("channel{n}/work_offsets.csv"),
                "text/csv",
                wpo.into_bytes(),
            ));
            out.push((
                format!("channel{n}/machine.json"),
                "application/json",
                machine_json(&c.settings).into_bytes(),
            ));
        }
        out
    }

    /// What `novanc.settings` adds for a kernel's machine: `machine` (its name) and `channels`
    /// (how many); nothing for a single machine.
    pub fn settings_metadata(&self) -> Vec<(String, String)> {
        if self.channels.is_empty() {
            return Vec::new();
        }
        vec![
            ("machine".to_string(), self.machine_name.clone()),
            ("channels".to_string(), self.channels.len().to_string()),
        ]
    }

    /// The tool file as CSV: one line per T code with data.
    fn tool_csv(&self) -> String {
        let mut s = String::from(
            "tcode,tool,kind,diameter_mm,set_length_mm,wear_diameter_mm,wear_length_mm,effective_length_mm,speed_rpm,feed_mm_min,depth_mm\n",
        );
        if let Some(m) = &self.magazine {
            for (t, r) in m.tools.iter() {
                let _ = writeln!(
                    s,
                    "{t},{},{:?},{},{},{},{},{},{},{},{}",
                    r.number,
                    r.kind,
                    r.diameter,
                    r.set_length,
                    r.wear_diameter,
                    r.wear_length,
                    r.effective_length,
                    r.speed,
                    r.feed,
                    r.depth
                );
            }
        }
        s
    }

    /// The `novanc.program` metadata records: `name`, `bytes`, `lines` (of the program text),
    /// `tools` (T codes with data); a kernel's machine has one per channel, which adds
    /// `channel` (1-based) and `channel_name`, `tools` counting its tool post.
    pub fn metadata(&self) -> Vec<mcap::records::Metadata> {
        let record = |name: &str, text: &str, tools: usize| mcap::records::Metadata {
            name: "novanc.program".to_string(),
            metadata: BTreeMap::from([
                ("name".to_string(), name.to_string()),
                ("bytes".to_string(), text.len().to_string()),
                ("lines".to_string(), text.lines().count().to_string()),
                ("tools".to_string(), tools.to_string()),
            ]),
        };
        if self.channels.is_empty() {
            let tools = self.magazine.as_ref().map_or(0, |m| m.tools.iter().count());
            return vec![record(&self.program_name, &self.program_text, tools)];
        }
        self.channels
            .iter()
            .enumerate()
            .map(|(i, c)| {
                let mut m = record(&c.program_name, &c.program_text, c.tools.len());
                m.metadata
                    .insert("channel".to_string(), (i + 1).to_string());
                m.metadata
                    .insert("channel_name".to_string(), c.name.clone());
                m
            })
            .collect()
    }
}

/// The machine's description as a JSON object: travel, rates, pulse, magazine, clock.
fn machine_json(s: &MachineSettings) -> String {
    let mut o = Vec::new();
    let num = |o: &mut Vec<u8>, k: &str, v: f64| {
        if o.len() > 1 {
            o.push(b',');
        }
        super::json::push_str(o, k);
        o.push(b':');
        super::json::push_decimal(o, v, 9);
    };
    o.push(b'{');
    num(&mut o, "pulse_mm", s.pulse_mm);
    num(&mut o, "rapid_mm_min", s.rapid_mm_min);
    num(&mut o, "accel_mm_s2", s.accel_mm_s2);
    for (i, axis) in ["x", "y", "z"].iter().enumerate() {
        num(&mut o, &format!("{axis}_min_mm"), s.travel_min_mm[i]);
        num(&mut o, &format!("{axis}_max_mm"), s.travel_max_mm[i]);
        // The axis's own rapid rate (the path's where it has none of its own).
        let own = s.axis_rate[i].min(s.rapid_mm_min);
        num(&mut o, &format!("{axis}_rapid_mm_min"), own);
        let own = s.axis_accel[i].min(s.accel_mm_s2);
        num(&mut o, &format!("{axis}_accel_mm_s2"), own);
    }
    num(&mut o, "jog_mm_min", s.jog_mm_min);
    num(&mut o, "rapid_f0_mm_min", s.rapid_f0_mm_min);
    num(&mut o, "tool_change_z_mm", s.tool_change_z_mm);
    num(&mut o, "tool_change_s", s.tool_change_ns as f64 / 1e9);
    num(&mut o, "spindle_s", s.spindle_ns as f64 / 1e9);
    num(&mut o, "magazine_capacity", f64::from(s.magazine_capacity));
    num(&mut o, "b1_capacity", s.b1_capacity as f64);
    num(&mut o, "ncbr_period_ns", s.ncbr_period_ns as f64);
    num(&mut o, "ep_l_pulses", s.ep_l_pulses as f64);
    o.extend_from_slice(b",\"interpolator\":");
    super::json::push_str(&mut o, s.interpolator.name());
    o.push(b'}');
    String::from_utf8(o).unwrap_or_default()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::settings::AxisKind;

    fn offsets_csv(settings: &MachineSettings, info: &RecordingInfo) -> String {
        let all = info.attachments(settings);
        let (_, _, bytes) = all.iter().find(|a| a.0 == "work_offsets.csv").unwrap();
        String::from_utf8(bytes.clone()).unwrap()
    }

    /// `work_offsets.csv` has a column for each axis the machine has: a 3-axis machine's file
    /// is as it was, a trunnion's adds B and C in degrees (stop 55; before, a table's zero was
    /// not in the recording).
    #[test]
    fn the_work_offsets_have_a_column_for_each_axis_the_machine_has() {
        let mut info = RecordingInfo::default();
        info.work_offsets[1] = [10.0, 20.0, -5.5, 0.0, -5.0, 30.0];
        let centre = MachineSettings::default();
        let csv = offsets_csv(&centre, &info);
        assert!(
            csv.starts_with("system,x_mm,y_mm,z_mm\nG54,0,0,0\nG55,10,20,-5.5\n"),
            "{csv}"
        );
        let mut trunnion = MachineSettings::default();
        trunnion.axis_kinds[4] = AxisKind::Rotary { wrap: false };
        trunnion.axis_kinds[5] = AxisKind::Rotary { wrap: true };
        let csv = offsets_csv(&trunnion, &info);
        assert!(
            csv.starts_with(
                "system,x_mm,y_mm,z_mm,b_deg,c_deg\nG54,0,0,0,0,0\nG55,10,20,-5.5,-5,30\n"
            ),
            "{csv}"
        );
    }
}
