//! Where state lives: `NOVANC_STATE`, else `$XDG_STATE_HOME/novanc`, else
//! `~/.local/state/novanc`. One test in its own binary, because it changes the environment.

use novanc::store::Stores;
use std::path::PathBuf;

#[test]
fn the_state_directory_is_chosen_in_order() {
    std::env::set_var("HOME", "/home/op");
    std::env::set_var("XDG_STATE_HOME", "/xdg/state");
    std::env::set_var("NOVANC_STATE", "/srv/novanc");
    assert_eq!(Stores::default_dir(), PathBuf::from("/srv/novanc"));
    std::env::set_var("NOVANC_STATE", "");
    assert_eq!(Stores::default_dir(), PathBuf::from("/xdg/state/novanc"));
    std::env::remove_var("NOVANC_STATE");
    assert_eq!(Stores::default_dir(), PathBuf::from("/xdg/state/novanc"));
    // A relative XDG_STATE_HOME is invalid (XDG spec) and ignored.
    std::env::set_var("XDG_STATE_HOME", "relative");
    assert_eq!(
        Stores::default_dir(),
        PathBuf::from("/home/op/.local/state/novanc")
    );
    std::env::remove_var("XDG_STATE_HOME");
    assert_eq!(
        Stores::default_dir(),
        PathBuf::from("/home/op/.local/state/novanc")
    );
    std::env::remove_var("HOME");
    assert_eq!(Stores::default_dir(), PathBuf::from("novanc-state"));
}
