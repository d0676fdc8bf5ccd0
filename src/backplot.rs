//! Backplot: the programmed path of a program as drawable segments, for the window.
//!
//! OWNER: window work (issue 6).
