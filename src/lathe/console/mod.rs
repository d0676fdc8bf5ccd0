//! The lathe console (docs/lathe.md "The panel").

pub mod events;
pub mod view;
