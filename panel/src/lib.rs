//! The terminal front panel: raw mode and the alternate screen through libc, a cell buffer
//! with diff rendering, and the drawing of the NC panel and the relay panel.
//!
//! OWNER: front panel work (issue 5).
