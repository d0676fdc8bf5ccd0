//! The NC editor core (SPEC §5; patent lines 437–485, Figs. 21–29): a text buffer with a
//! pointer, and atomic command lines of `L M K D I S C Y`. Pure: no I/O, no threads.
//!
//! OWNER: editor work (issue 2).
