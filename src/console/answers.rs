//! The machine a run's G-code source asks (docs/gcode.md "Probing", docs/pulse-core.md "The
//! machine's answers"): on the translator thread, a probe waits until the pulse core has run
//! the probe block and says where it stopped, an M66 until it has read its input, a Fanuc
//! clock read until it has run every block before the line. Reading does not run ahead of
//! that answer.

use crate::gcode::{Clocks, Machine, Probed};
use crate::pulse_core::{Answer, MachineLink};

/// The pulse core of the run this translator thread feeds.
pub struct RunMachine {
    link: MachineLink,
    pulse_mm: f64,
}

impl RunMachine {
    /// The machine of the run made on this thread (`None` off a translator thread: a caller
    /// then keeps the settings' simulation). `pulse_mm`: the settings' pulse.
    pub fn here(pulse_mm: f64) -> Option<RunMachine> {
        MachineLink::here().map(|link| RunMachine { link, pulse_mm })
    }
}

impl Machine for RunMachine {
    fn probe(
        &mut self,
        _from: [f64; 3],
        _to: [f64; 3],
        _length: f64,
        _radius: f64,
        _toward: bool,
    ) -> Result<Probed, String> {
        match self.link.wait_answer()? {
            Answer::Probe {
                at,
                tripped,
                at_start,
            } => Ok(Probed {
                at: at.xyz().map(|v| v as f64 * self.pulse_mm),
                tripped,
                at_start,
            }),
            a => Err(mismatch(&a, "a probe")),
        }
    }

    /// M66: the core reads its simulated input when the block is reached, waiting (L1–L4) up
    /// to the timeout in machine time; `None` on a timeout.
    fn input(
        &mut self,
        _digital: bool,
        _index: u32,
        _mode: u32,
        _timeout: f64,
    ) -> Result<Option<f64>, String> {
        match self.link.wait_answer()? {
            Answer::Input(v) => Ok(v),
            a => Err(mismatch(&a, "an M66")),
        }
    }

    fn keeps_time(&self) -> bool {
        true
    }

    /// #3001/#3002: the core's machine time (virtual in scripts and `novanc run`, real at the
    /// terminal) and cycle-start lamp time when it ended the clocks block.
    fn clocks(&mut self) -> Result<Clocks, String> {
        match self.link.wait_answer()? {
            Answer::Clocks {
                machine_ns,
                cycle_ns,
            } => Ok(Clocks {
                machine_ns,
                cycle_ns,
            }),
            a => Err(mismatch(&a, "its clocks")),
        }
    }
}

/// The answers come in block order, one for each question: another answer than the one
/// asked for is an internal fault, said as such (the run stops).
fn mismatch(got: &Answer, asked: &str) -> String {
    let got = match got {
        Answer::Probe { .. } => "a probe",
        Answer::Input(_) => "an M66",
        Answer::Clocks { .. } => "its clocks",
    };
    format!("the machine answered {got} where {asked} was asked")
}
