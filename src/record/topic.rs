//! The docs/recording.md topics: their MCAP names, and the JSON schema of each topic's messages (a
//! public interface: Foxglove, `tests/mcap_check.py` and other helpers' tests read them).

use super::Event;

/// How many topics every recording declares ([`Topic::ALL`]).
pub const TOPICS: usize = 9;

/// Every topic, the lathe's `/lathe/event` included ([`Topic::EVERY`]): a recording of a
/// kernel's channels declares it with its first message.
pub const ALL_TOPICS: usize = TOPICS + 1;

/// The docs/recording.md topics, in channel order.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Topic {
    /// `/nc/block`: a block starts executing.
    Block,
    /// `/nc/position`: axis positions.
    Position,
    /// `/nc/pulses`: a batch of pulses of one axis.
    Pulses,
    /// `/nc/state`: RUN, modes, override, tool, spindle.
    State,
    /// `/panel/display`: the display frame.
    Display,
    /// `/panel/event`: an operator action.
    PanelEvent,
    /// `/nc/probe`: a probe block ended (issue 21).
    Probe,
    /// `/nc/io`: an output set (issue 21).
    Io,
    /// `/foxglove/log`: operator and program messages and alarms (issue 25).
    Log,
    /// `/lathe/event`: a lathe channel's transfers, cuts, thread passes, parts, waits, faults
    /// and alarms (issue 22). Declared in a file only once it has a message, so a
    /// machining centre's recording has no such channel.
    LatheEvent,
}

/// The JSON schema of `/lathe/event`.
pub const LATHE_EVENT_SCHEMA: &str = concat!(
    r#"{"$schema":"https://json-schema.org/draft/2020-12/schema","title":"novanc.LatheEvent","#,
    r#""description":"A lathe channel's event besides motion","type":"object","#,
    r#""properties":{"channel":{"type":"integer","description":"1-based channel"},"#,
    r#""event":{"type":"string","description":"transfer, thread, cut, part, wait, fault, alarm, reset, done, ..."},"#,
    r#""work":{"type":"integer","description":"the work piece, 1-based, if the event concerns one"},"#,
    r#""value":{"type":"integer","description":"the event's number: the receiving channel of a transfer, the encoder index of a thread pass, the count of a part"},"#,
    r#""text":{"type":"string","description":"the event in words"}},"#,
    r#""required":["channel","event","text"]}"#
);

impl Topic {
    /// The topics every recording declares, in channel order.
    pub const ALL: [Topic; TOPICS] = [
        Topic::Block,
        Topic::Position,
        Topic::Pulses,
        Topic::State,
        Topic::Display,
        Topic::PanelEvent,
        Topic::Probe,
        Topic::Io,
        Topic::Log,
    ];

    /// Every topic, in slot order ([`Topic::index`]): [`Topic::ALL`], then `/lathe/event`.
    pub const EVERY: [Topic; ALL_TOPICS] = [
        Topic::Block,
        Topic::Position,
        Topic::Pulses,
        Topic::State,
        Topic::Display,
        Topic::PanelEvent,
        Topic::Probe,
        Topic::Io,
        Topic::Log,
        Topic::LatheEvent,
    ];

    /// The MCAP topic name.
    pub fn name(self) -> &'static str {
        match self {
            Topic::Block => "/nc/block",
            Topic::Position => "/nc/position",
            Topic::Pulses => "/nc/pulses",
            Topic::State => "/nc/state",
            Topic::Display => "/panel/display",
            Topic::PanelEvent => "/panel/event",
            Topic::Probe => "/nc/probe",
            Topic::Io => "/nc/io",
            Topic::Log => "/foxglove/log",
            Topic::LatheEvent => "/lathe/event",
        }
    }

    /// Index 0..[`ALL_TOPICS`] (channel order; `/lathe/event` last).
    pub fn index(self) -> usize {
        self as usize
    }

    /// The topic an event is recorded on.
    pub fn of(ev: &Event) -> Topic {
        match ev {
            Event::Block { .. } => Topic::Block,
            Event::Position { .. } => Topic::Position,
            Event::Pulses { .. } => Topic::Pulses,
            Event::State { .. } => Topic::State,
            Event::Display { .. } => Topic::Display,
            Event::PanelEvent { .. } => Topic::PanelEvent,
            Event::Probe { .. } => Topic::Probe,
            Event::Io { .. } => Topic::Io,
            Event::Log { .. } => Topic::Log,
            Event::Lathe { .. } => Topic::LatheEvent,
            Event::OnChannel { ev, .. } => Topic::of(ev),
        }
    }

    /// The schema name (shown by Foxglove and `mcap info`).
    pub fn schema_name(self) -> &'static str {
        match self {
            Topic::Block => "novanc.Block",
            Topic::Position => "novanc.Position",
            Topic::Pulses => "novanc.Pulses",
            Topic::State => "novanc.State",
            Topic::Display => "novanc.PanelDisplay",
            Topic::PanelEvent => "novanc.PanelEvent",
            Topic::Probe => "novanc.Probe",
            Topic::Io => "novanc.Io",
            Topic::Log => "foxglove.Log",
            Topic::LatheEvent => "novanc.LatheEvent",
        }
    }

    /// [`Topic::schema`] on a machine with the rotary axes of `rotary` (a mask: bit 0 A, bit 1
    /// B, bit 2 C): `/nc/position` and `/nc/probe` also give `a`, `b`, `c` (degrees) and a
    /// counter each for those it has, and `/nc/pulses` names them (added, never changed: a
    /// 3-axis machine's schema is `schema()`, and an A-axis machine's is as it was).
    pub fn schema_for(self, rotary: u8) -> std::borrow::Cow<'static, str> {
        let s = self.schema();
        if rotary & 7 == 0 || !matches!(self, Topic::Position | Topic::Probe | Topic::Pulses) {
            return s.into();
        }
        let names: Vec<&str> = (0..3)
            .filter(|r| rotary & (1 << r) != 0)
            .map(|r| ["A", "B", "C"][r])
            .collect();
        let quoted: String = names.iter().map(|l| format!(",\"{l}\"")).collect();
        let fields: String = names
            .iter()
            .map(|l| {
                format!(
                    r#""{}":{{"type":"number","description":"{l}, degrees (a rotary axis; only on a machine that has it)"}},"#,
                    l.to_ascii_lowercase()
                )
            })
            .collect();
        let n = 3 + names.len();
        s.replace(
            r#""axis":{"type":"string","enum":["X","Y","Z"]}"#,
            &format!(r#""axis":{{"type":"string","enum":["X","Y","Z"{quoted}]}}"#),
        )
        .replace(
            r#""pulses":{"type":"array","items":{"type":"integer"},"minItems":3,"maxItems":3,"#,
            &format!(
                r#"{fields}"pulses":{{"type":"array","items":{{"type":"integer"}},"minItems":{n},"maxItems":{n},"#
            ),
        )
        .replace(
            "pulse counters X, Y, Z",
            &format!("pulse counters X, Y, Z, {}", names.join(", ")),
        )
        .into()
    }

    /// The JSON schema of the topic's messages: draft 2020-12 for novanc's own, Foxglove's
    /// published schema for `foxglove.Log`.
    pub fn schema(self) -> &'static str {
        match self {
            Topic::Block => concat!(
                r#"{"$schema":"https://json-schema.org/draft/2020-12/schema","title":"novanc.Block","#,
                r#""description":"A block starts executing","type":"object","#,
                r#""properties":{"seq":{"type":"integer","description":"block sequence number"},"#,
                r#""stmt":{"type":"integer","description":"source statement line, 1-based"},"#,
                r#""text":{"type":"string","description":"the block's ISO line"}},"#,
                r#""required":["seq","stmt","text"]}"#
            ),
            Topic::Position => concat!(
                r#"{"$schema":"https://json-schema.org/draft/2020-12/schema","title":"novanc.Position","#,
                r#""description":"Axis positions, machine coordinates","type":"object","#,
                r#""properties":{"x":{"type":"number","description":"X, mm (program position: moves under machine lock)"},"#,
                r#""y":{"type":"number","description":"Y, mm (program position)"},"#,
                r#""z":{"type":"number","description":"Z, mm (program position)"},"#,
                r#""pulses":{"type":"array","items":{"type":"integer"},"minItems":3,"maxItems":3,"#,
                r#""description":"pulse counters X, Y, Z (the axes: they do not move under machine lock)"},"#,
                r#""speed":{"type":"number","description":"commanded path speed, mm/min (not in files written before it was added)"}},"#,
                r#""required":["x","y","z","pulses"]}"#
            ),
            Topic::Pulses => concat!(
                r#"{"$schema":"https://json-schema.org/draft/2020-12/schema","title":"novanc.Pulses","#,
                r#""description":"A batch of feed pulses of one axis in one direction","type":"object","#,
                r#""properties":{"axis":{"type":"string","enum":["X","Y","Z"]},"#,
                r#""dir":{"type":"integer","enum":[1,-1]},"#,
                r#""t_ns":{"type":"array","items":{"type":"integer"},"#,
                r#""description":"pulse times, ns of machine time, ascending"}},"#,
                r#""required":["axis","dir","t_ns"]}"#
            ),
            Topic::State => concat!(
                r#"{"$schema":"https://json-schema.org/draft/2020-12/schema","title":"novanc.State","#,
                r#""description":"Machine state, written on change","type":"object","#,
                r#""properties":{"run":{"type":"integer","description":"RUN: 0 stopped, 1 AUTO, 2 MDI"},"#,
                r#""op_mode":{"type":"string"},"data_mode":{"type":"string"},"#,
                r#""feed_override":{"type":"integer","description":"percent"},"#,
                r#""tool":{"type":"integer","description":"T code in the spindle, 0 none"},"#,
                r#""spindle":{"type":"integer","description":"rpm, negative reverse, 0 stopped (programmed x spindle override)"},"#,
                r#""rapid_override":{"type":"integer","description":"percent, 0 = F0 (not in files written before it was added)"},"#,
                r#""spindle_override":{"type":"integer","description":"percent"},"#,
                r#""dry_run":{"type":"boolean"},"machine_lock":{"type":"boolean"},"z_neglect":{"type":"boolean"},"override_locked":{"type":"boolean","description":"a tap is in progress: feed and spindle overrides held at 100 %"}},"#,
                r#""required":["run","op_mode","data_mode","feed_override","tool","spindle"]}"#
            ),
            Topic::Display => concat!(
                r#"{"$schema":"https://json-schema.org/draft/2020-12/schema","title":"novanc.PanelDisplay","#,
                r#""description":"The panel display frame","type":"object","#,
                r#""properties":{"lines":{"type":"array","items":{"type":"string"}}},"#,
                r#""required":["lines"]}"#
            ),
            Topic::PanelEvent => concat!(
                r#"{"$schema":"https://json-schema.org/draft/2020-12/schema","title":"novanc.PanelEvent","#,
                r#""description":"An operator action, as a panel-script line","type":"object","#,
                r#""properties":{"event":{"type":"string"}},"#,
                r#""required":["event"]}"#
            ),
            Topic::Probe => concat!(
                r#"{"$schema":"https://json-schema.org/draft/2020-12/schema","title":"novanc.Probe","#,
                r#""description":"A probe block (G38.x) ended: where the machine stopped","type":"object","#,
                r#""properties":{"seq":{"type":"integer","description":"block sequence number"},"#,
                r#""stmt":{"type":"integer","description":"source statement line, 1-based"},"#,
                r#""x":{"type":"number","description":"X, mm"},"#,
                r#""y":{"type":"number","description":"Y, mm"},"#,
                r#""z":{"type":"number","description":"Z, mm (the gauge line)"},"#,
                r#""pulses":{"type":"array","items":{"type":"integer"},"minItems":3,"maxItems":3,"#,
                r#""description":"pulse counters X, Y, Z"},"#,
                r#""tripped":{"type":"boolean","description":"the probe found what it sought (contact, or for G38.4/G38.5 its loss)"},"#,
                r#""at_start":{"type":"boolean","description":"it was so at the start: nothing moved"}},"#,
                r#""required":["seq","stmt","x","y","z","pulses","tripped","at_start"]}"#
            ),
            Topic::Io => concat!(
                r#"{"$schema":"https://json-schema.org/draft/2020-12/schema","title":"novanc.Io","#,
                r#""description":"A block set an output (M62-M65, M67, M68), or the operator or a script set a simulated input (dir in)","type":"object","#,
                r#""properties":{"seq":{"type":"integer","description":"block sequence number"},"#,
                r#""stmt":{"type":"integer","description":"source statement line, 1-based"},"#,
                r#""kind":{"type":"string","enum":["digital","analog"]},"#,
                r#""index":{"type":"integer","minimum":0,"maximum":63,"description":"output (or input) number"},"#,
                r#""value":{"type":"number","description":"a digital output 1 on, 0 off; an analog one its value (6 decimals)"},"#,
                r#""synced":{"type":"boolean","description":"with the motion (M62, M63, M67: when the block's motion starts) or at once (M64, M65, M68: when the block is read); false for an input"},"#,
                r#""dir":{"type":"string","enum":["out","in"],"description":"in: an input the operator or a script set (seq and stmt: the block then executing, 0 if none; synced false); absent on an output a block set"}},"#,
                r#""required":["seq","stmt","kind","index","value","synced"]}"#
            ),
            Topic::Log => super::foxglove::LOG_SCHEMA,
            Topic::LatheEvent => LATHE_EVENT_SCHEMA,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn schemas_name_every_required_field() {
        let required: [&[&str]; TOPICS] = [
            &["seq", "stmt", "text"],
            &["x", "y", "z", "pulses"],
            &["axis", "dir", "t_ns"],
            &[
                "run",
                "op_mode",
                "data_mode",
                "feed_override",
                "tool",
                "spindle",
            ],
            &["lines"],
            &["event"],
            &[
                "seq", "stmt", "x", "y", "z", "pulses", "tripped", "at_start",
            ],
            &["seq", "stmt", "kind", "index", "value", "synced"],
            &["timestamp", "level", "message", "name", "file", "line"],
        ];
        for (topic, fields) in Topic::ALL.iter().zip(required) {
            let schema = topic.schema();
            for f in fields {
                assert!(schema.contains(&format!("\"{f}\"")), "{topic:?} lacks {f}");
            }
            assert!(schema.contains(topic.schema_name()));
        }
        for f in ["channel", "event", "text"] {
            assert!(Topic::LatheEvent.schema().contains(&format!("\"{f}\"")));
        }
    }
}
