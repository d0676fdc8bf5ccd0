//! The MTConnect SHDR adapter (docs/mtconnect.md): the data items derived from the pulse
//! core's status and the console's modes (`items`), the SHDR line format (`shdr`), and the TCP
//! server that streams them to agents (`server`). Plain TCP from std.

pub mod devices;
pub mod feed;
pub mod items;
pub mod options;
pub mod server;
pub mod shdr;

pub use items::{items, Modes, PathKeys};

/// A data item's key as sent: the mill's names are static, a path's prefixed ones are made.
pub type Key = std::borrow::Cow<'static, str>;
pub use options::{parse_addr, parse_wait, DEFAULT_PORT};
pub use server::Adapter;
