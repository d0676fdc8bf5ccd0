//! The Citizen multi-spindle lathe (seed 004) and the UNAM thesis lathe (seed 003): lathe
//! channels, each with its own spindle, tool post, chuck and program, run by the one kernel
//! (`crate::pulse_core::Kernel`, one thread, one NCBR clock; docs/lathe.md, docs/pulse-core.md
//! "Channels").
//!
//! - [`desc`]: the machine description (a small text format; `--machine citizen` is embedded),
//!   and each channel's settings for the kernel (`LatheDesc::kernel_channels`).
//! - [`gcode`]: the lathe G-code reader; it hands the kernel its blocks (`crate::block`, the
//!   one interface between the language readers and the kernel), as the mill's reader does.
//! - [`console`]: the lathe's panel (it records with `crate::record`, as the centre's does);
//!   its stores are `crate::store::lathe` (the one journal, which reads the old whole-file
//!   store once, to migrate it).
//! - [`testkit`]: a Citizen-like machine and a sample part, for the tests and the benchmark.

pub mod console;
pub mod desc;
pub mod gcode;
pub mod testkit;
