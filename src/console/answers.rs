//! The machine a run's G-code source asks (docs/gcode.md "Probing", docs/pulse-core.md "The
//! machine's answers"): on the translator thread, a probe waits until the pulse core has run
//! the probe block and says where it stopped. Reading does not run ahead of that answer.

use crate::gcode::{Machine, Probed};
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
            Answer::Input(_) => Err("the machine answered an M66 where a probe was asked".into()),
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
            Answer::Probe { .. } => {
                Err("the machine answered a probe where an M66 was asked".into())
            }
        }
    }
}
