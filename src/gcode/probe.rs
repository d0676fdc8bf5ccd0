//! G38.2–G38.5 probing (docs/gcode.md "Probing"): a straight feed move that stops where the
//! probe trips (G38.2, G38.3) or loses contact (G38.4, G38.5). Reading waits for the machine's
//! answer; #5061–#5063 get where it stopped, in the coordinates of the system in force, and
//! #5070 whether it tripped. G38.2 and G38.4 are errors if the probe does not trip.

use super::canon::Canon;
use super::comp::Comp;
use super::exec::{Event, Exec};
use super::state::{FeedMode, InterpState};
use super::words::Words;
use crate::block::TranslateError;

/// The shortest probe move LinuxCNC accepts, inches (its "start point too close").
const MIN_PROBE_INCH: f64 = 0.01;

/// One probe line, motion `g` (×10: 382 … 385).
pub fn probe(
    st: &mut InterpState,
    comp: &mut Comp,
    x: &mut Exec,
    w: &Words,
    g: u16,
    col: u32,
) -> Result<(), TranslateError> {
    let name = format!("G38.{}", g % 10);
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
    let toward = g <= 383;
    let hit = x
        .machine
        .probe(from, to, length, radius, toward)
        .map_err(|e| x.err(col, e))?;
    let stop = hit.unwrap_or(to);
    x.push(Canon::Probe(stop, st.modal.feed, g), col);
    st.pos = stop;
    let k = st.factor();
    let p = st.to_program(stop);
    for (a, v) in p.iter().enumerate() {
        st.params[5061 + a] = v / k;
    }
    for n in 5064..=5069 {
        st.params[n] = 0.0;
    }
    st.params[5070] = if hit.is_some() { 1.0 } else { 0.0 };
    x.events.push(Event::Probe {
        at: [p[0] / k, p[1] / k, p[2] / k],
        tripped: hit.is_some(),
    });
    if hit.is_none() && (g == 382 || g == 384) {
        return Err(x.err(
            col,
            format!(
                "{name}: the probe move ended without {}",
                if g == 382 {
                    "contact"
                } else {
                    "losing contact"
                }
            ),
        ));
    }
    Ok(())
}
