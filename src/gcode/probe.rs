//! G38.2–G38.5 probing and M66 (docs/gcode.md "Probing", "Inputs and outputs"): the line
//! hands the machine a straight feed move that stops where the probe trips (G38.2, G38.3) or
//! loses contact (G38.4, G38.5), and reading waits for the machine's answer before the next
//! line: #5061–#5063 get where it stopped, in the coordinates of the system in force, and
//! #5070 whether it tripped; the interpreter's position becomes the machine's. G38.2 and
//! G38.4 are errors if the probe does not trip, or if it is tripped (clear) at the start.
//!
//! [`SimMachine`] answers from the workpiece in the machine's settings, where no pulse core
//! runs (`novanc translate`, the lines before a SEARCH point); in a run the pulse core answers
//! (`console::answers`).

use super::canon::Canon;
use super::comp::Comp;
use super::exec::{low_input, Ask, Event, Exec, Machine, Probed};
use super::state::{FeedMode, InterpState};
use super::words::Words;
use crate::block::TranslateError;
use crate::settings::MachineSettings;
use crate::workpiece::{along, Touch, Workpiece};

/// The shortest probe move LinuxCNC accepts, inches (its "start point too close").
const MIN_PROBE_INCH: f64 = 0.01;

/// `G38.2` … `G38.5` for motion `g` (×10: 382 … 385), `G31` for 310 (Fanuc's skip).
fn name(g: u16) -> String {
    if g == 310 {
        return "G31".into();
    }
    format!("G38.{}", g % 10)
}

/// One probe line, motion `g` (×10: 382 … 385): the move to the programmed point, and the
/// question to the machine.
pub fn probe(
    st: &mut InterpState,
    comp: &mut Comp,
    x: &mut Exec,
    w: &Words,
    g: u16,
    col: u32,
) -> Result<(), TranslateError> {
    let name = name(g);
    if comp.active() {
        return Err(x.err(
            col,
            format!("{name} cannot be used with cutter radius compensation on"),
        ));
    }
    if st.modal.feed_mode == FeedMode::InverseTime {
        return Err(x.err(
            col,
            format!("{name} cannot be used in inverse time feed (G93)"),
        ));
    }
    if st.modal.feed <= 0.0 {
        return Err(x.err(col, format!("{name} needs a feed: give F")));
    }
    let to = super::moves::target(st, x, w)?;
    let from = st.pos;
    let d =
        ((to[0] - from[0]).powi(2) + (to[1] - from[1]).powi(2) + (to[2] - from[2]).powi(2)).sqrt();
    if d < MIN_PROBE_INCH * 25.4 {
        return Err(x.err(
            col,
            format!("{name}: the probe point is too close to the start (under 0.254 mm)"),
        ));
    }
    let (length, radius) = match st.tool {
        Some(t) if t != 0 => x
            .tool_data(t, col, "the tool in the spindle T")
            .map(|(l, d)| (l, d / 2.0))?,
        _ => (0.0, 0.0),
    };
    x.push(Canon::Probe(to, st.modal.feed, g), col);
    // Until the machine answers, the move's end; the answer puts the machine's position here.
    st.pos = to;
    x.asks.push(Ask::Probe {
        g,
        col,
        from,
        to,
        length,
        radius,
    });
    Ok(())
}

/// The machine's answer to a question of line `n`: the parameters it sets, the position after
/// a probe (returned: the machine's, machine mm), the probe's event; an error for a G38.2 or
/// G38.4 that did not find what it sought.
pub fn answer(
    st: &mut InterpState,
    m: &mut dyn Machine,
    ask: &Ask,
    n: u32,
    events: &mut Vec<Event>,
) -> Result<Option<[f64; 3]>, TranslateError> {
    let err = |col: u32, message: String| TranslateError {
        line: n,
        col,
        message,
    };
    match *ask {
        // Answered where the line that asked is read again (`GcodeSource::answer_pending`).
        Ask::Clocks { .. } => Ok(None),
        Ask::Input {
            col,
            digital,
            index,
            mode,
            timeout,
        } => {
            let v = m
                .input(digital, index, mode, timeout)
                .map_err(|e| err(col, e))?;
            st.params[5399] = v.unwrap_or(-1.0);
            Ok(None)
        }
        Ask::Probe {
            g,
            col,
            from,
            to,
            length,
            radius,
        } => {
            let toward = g <= 383;
            let r = m
                .probe(from, to, length, radius, toward)
                .map_err(|e| err(col, e))?;
            let name = name(g);
            let fails = g == 382 || g == 384;
            if r.at_start && fails {
                return Err(err(
                    col,
                    if toward {
                        format!("{name}: the probe is already tripped at the start of the move")
                    } else {
                        format!("{name}: the probe is already clear at the start of the move")
                    },
                ));
            }
            st.pos = r.at;
            let k = st.factor();
            // Fanuc's skip position (#5061–) is in work coordinates with the tool offset
            // included; LinuxCNC's probe point is in the program's frame.
            let p = if g == 310 {
                st.work_with_tool(r.at)
            } else {
                st.to_program(r.at)
            };
            for (a, v) in p.iter().enumerate() {
                st.params[5061 + a] = v / k;
            }
            for n in 5064..=5069 {
                st.params[n] = 0.0;
            }
            st.params[5070] = if r.tripped { 1.0 } else { 0.0 };
            events.push(Event::Probe {
                at: [p[0] / k, p[1] / k, p[2] / k],
                tripped: r.tripped,
            });
            if !r.tripped && fails {
                return Err(err(
                    col,
                    format!(
                        "{name}: the probe move ended without {}",
                        if toward { "contact" } else { "losing contact" }
                    ),
                ));
            }
            Ok(Some(r.at))
        }
    }
}

/// The machine as the settings describe it, without a pulse core: probes answered from the
/// workpiece (the stylus moved along the straight line, exactly), every input low (docs/gcode.md
/// "Probing"). What `novanc translate` and the lines before a SEARCH point use.
pub struct SimMachine {
    workpiece: Workpiece,
}

impl SimMachine {
    /// The machine of `settings`: its workpiece.
    pub fn new(settings: &MachineSettings) -> SimMachine {
        SimMachine {
            workpiece: settings.workpiece.clone(),
        }
    }
}

impl Machine for SimMachine {
    fn probe(
        &mut self,
        from: [f64; 3],
        to: [f64; 3],
        length: f64,
        radius: f64,
        toward: bool,
    ) -> Result<Probed, String> {
        let tip = |p: [f64; 3]| [p[0], p[1], p[2] - length];
        Ok(
            match self.workpiece.probe(tip(from), tip(to), radius, toward) {
                Touch::AtStart => Probed {
                    at: from,
                    tripped: true,
                    at_start: true,
                },
                Touch::At(t) => Probed {
                    at: along(from, to, t),
                    tripped: true,
                    at_start: false,
                },
                Touch::Never => Probed {
                    at: to,
                    tripped: false,
                    at_start: false,
                },
            },
        )
    }

    fn input(
        &mut self,
        _digital: bool,
        _index: u32,
        mode: u32,
        _timeout: f64,
    ) -> Result<Option<f64>, String> {
        Ok(low_input(mode))
    }
}
