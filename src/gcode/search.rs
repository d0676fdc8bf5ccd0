//! SEARCH and the iterator (docs/gcode.md "SEARCH"): the lines before the SEARCH point run
//! for their state only, then a restore statement brings the machine there from where it is.

use super::canon::{Canon, Emitter};
use super::{restore_text, GcodeSource, Switches, WorkOffsets};
use crate::block::{Block, MachineState, Statement, TranslateError};
use crate::settings::MachineSettings;
use crate::tooldata::Magazine;

impl GcodeSource {
    /// Whether main-program line `line` (1-based) holds an M06 (read without evaluating
    /// anything that could fail: a line that does not read simply does not count).
    fn line_changes_tool(&self, line: u32) -> bool {
        let Some(raw) = self.flow.units[0].nth_line(line as usize - 1) else {
            return false;
        };
        let p = super::read::Params::default();
        let Ok(l) = super::read::read_line(raw, line, &p) else {
            return raw.to_ascii_uppercase().contains("M6")
                || raw.to_ascii_uppercase().contains("M06");
        };
        l.words
            .iter()
            .any(|w| w.letter == 'M' && (w.value - 6.0).abs() < 1e-9)
    }

    /// The restore statement before `line`: from the machine's actual state to the state the
    /// lines before it left.
    pub(super) fn restore(&mut self, line: u32) -> Result<Statement, TranslateError> {
        // The line searched to changes the tool itself: no tool is restored first, and Z
        // stays up (M06 goes to the tool-change height anyway), as docs/gcode.md "SEARCH" says.
        let changes_tool = self.line_changes_tool(line);
        if !self.z_moved || changes_tool {
            // No line before moved Z: the program commanded no height yet, and the machine's
            // (with perhaps another tool) is not one to go back down to. Z stays at machine
            // zero, and the program goes on from there.
            self.st.pos[2] = 0.0;
        }
        let st = &self.settings;
        let p = |v: f64| st.to_pulses(v);
        let target = [p(self.st.pos[0]), p(self.st.pos[1]), p(self.st.pos[2])];
        let mut items = Vec::new();
        let here = self.start.pos;
        let mm = |v: i64| st.to_mm(v);
        items.push((Canon::Rapid([mm(here[0]), mm(here[1]), 0.0]), line, 1));
        if self.st.tool != self.start.tool && !changes_tool {
            if let Some(t) = self.st.tool {
                if self.start.spindle != 0 {
                    // The machine's tool change: the spindle stops first.
                    items.push((
                        Canon::Aux {
                            s: None,
                            t: None,
                            m: Some(5),
                        },
                        line,
                        1,
                    ));
                }
                items.push((
                    Canon::Aux {
                        s: None,
                        t: Some(t),
                        m: Some(6),
                    },
                    line,
                    1,
                ));
            }
        }
        let s = Some(self.st.modal.speed.round() as u32);
        match self.st.modal.spindle {
            1 => items.push((
                Canon::Aux {
                    s,
                    t: None,
                    m: Some(3),
                },
                line,
                1,
            )),
            -1 => items.push((
                Canon::Aux {
                    s,
                    t: None,
                    m: Some(4),
                },
                line,
                1,
            )),
            _ if self.start.spindle != 0 => items.push((
                Canon::Aux {
                    s: None,
                    t: None,
                    m: Some(5),
                },
                line,
                1,
            )),
            _ => {}
        }
        // The coolant the lines before left, from the machine's: M9 first if one is on that
        // should not be, then M7 and M8.
        let (mist, flood) = (self.st.modal.mist, self.st.modal.flood);
        let (mut had_mist, mut had_flood) = (self.start.mist, self.start.flood);
        let aux = |m: u8| {
            (
                Canon::Aux {
                    s: None,
                    t: None,
                    m: Some(m),
                },
                line,
                1,
            )
        };
        if (had_mist && !mist) || (had_flood && !flood) {
            items.push(aux(9));
            (had_mist, had_flood) = (false, false);
        }
        if mist && !had_mist {
            items.push(aux(7));
        }
        if flood && !had_flood {
            items.push(aux(8));
        }
        items.push((Canon::Rapid([mm(target[0]), mm(target[1]), 0.0]), line, 1));
        items.push((
            Canon::Rapid([mm(target[0]), mm(target[1]), mm(target[2])]),
            line,
            1,
        ));
        let mut em = Emitter::new(here, 0, crate::block::Tap::No);
        let mut blocks: Vec<Block> = Vec::new();
        em.emit(&items, st, &mut blocks)?;
        for b in &mut blocks {
            b.seq = 0;
        }
        self.emitter.pos = em.pos;
        Ok(Statement {
            line,
            text: restore_text(line),
            blocks,
        })
    }
}

impl Iterator for GcodeSource {
    type Item = Result<Statement, TranslateError>;

    fn next(&mut self) -> Option<Self::Item> {
        if let Some(s) = self.held.take() {
            return Some(Ok(s));
        }
        let Some(at) = self.resume_at else {
            return self.step();
        };
        // SEARCH: run the lines before `at` for their state only (the settings' machine
        // answers their probes and inputs).
        self.searching = true;
        loop {
            let main = self.flow.level() == 0 && self.flow.pc.unit == 0;
            let before = main && (self.flow.pc.line as u32 + 1) < at;
            if !before && main {
                break;
            }
            match self.step() {
                Some(Ok(_)) => {
                    let z = self.settings.to_pulses(self.st.pos[2]);
                    self.z_moved |= z != self.start.pos[2];
                }
                Some(Err(e)) => {
                    self.searching = false;
                    return Some(Err(e));
                }
                None => {
                    self.searching = false;
                    return Some(Err(TranslateError {
                        line: at,
                        col: 1,
                        message: format!(
                            "no line to run at or after line {at}: the program ends before it"
                        ),
                    }));
                }
            }
        }
        let answered = self.answer_pending();
        self.searching = false;
        if let Err(e) = answered {
            return self.fail(e);
        }
        self.resume_at = None;
        let restore = match self.restore(at) {
            Ok(r) => r,
            Err(e) => return self.fail(e),
        };
        match self.step() {
            Some(Ok(s)) => {
                if restore.blocks.is_empty() {
                    return Some(Ok(s));
                }
                self.held = Some(s);
                Some(Ok(restore))
            }
            other => other,
        }
    }
}

/// Reads a whole G-code program from machine zero state `start`, G54 offsets `offsets` and
/// both switches off; the first error fails it.
pub fn translate_all(
    source: &str,
    magazine: &Magazine,
    settings: &MachineSettings,
    start: [i64; 3],
    offsets: WorkOffsets,
) -> Result<Vec<Statement>, TranslateError> {
    GcodeSource::new(
        source.into(),
        magazine.clone(),
        settings.clone(),
        MachineState::at(start),
        offsets,
        Switches::default(),
    )
    .collect()
}
