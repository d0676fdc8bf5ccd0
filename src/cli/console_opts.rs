//! The console's options on the command line (`--state`, `--rows`, `--cols`, `--record`),
//! shared by the terminal, the window and `novanc script`.

use super::args::{Args, Opt};
use crate::console::ConsoleConfig;
use std::path::PathBuf;

/// The options the console understands (other options are left to the caller).
const OPTS: [&str; 7] = [
    "--state",
    "--rows",
    "--cols",
    "--record",
    "--pulses",
    "--interpolator",
    "--ep-l",
];

/// Parses `--state DIR`, `--rows N`, `--cols N` and `--record OUT.mcap` out of `argv`; returns
/// the configuration (real time, default settings) and every other argument, in order.
pub fn config_from_args(argv: &[String]) -> Result<(ConsoleConfig, Vec<String>), String> {
    let mut mine = Vec::new();
    let mut rest = Vec::new();
    let mut i = 0;
    while i < argv.len() {
        let a = &argv[i];
        let name = a.split_once('=').map(|(n, _)| n).unwrap_or(a.as_str());
        if OPTS.contains(&name) {
            mine.push(a.clone());
            if !a.contains('=') {
                if let Some(v) = argv.get(i + 1) {
                    mine.push(v.clone());
                    i += 1;
                }
            }
        } else {
            rest.push(a.clone());
        }
        i += 1;
    }
    let opts: Vec<Opt> = OPTS
        .iter()
        .map(|n| Opt {
            name: n,
            takes_value: true,
        })
        .collect();
    let args = Args::parse(&mine, &opts)?;
    let state = match args.value("--state") {
        Some(d) => PathBuf::from(d),
        None => crate::console::default_state_dir(),
    };
    let mut cfg = ConsoleConfig::new(state);
    if let Some(r) = args.value("--rows") {
        cfg.rows = r
            .parse()
            .map_err(|_| format!("--rows '{r}' is not a whole number"))?;
    }
    if let Some(c) = args.value("--cols") {
        cfg.cols = c
            .parse()
            .map_err(|_| format!("--cols '{c}' is not a whole number"))?;
    }
    cfg.record = args.value("--record").map(PathBuf::from);
    if let Some(p) = args.value("--pulses") {
        cfg.record_pulses = super::pulses_option(p)?;
    }
    if let Some(i) = args.value("--interpolator") {
        cfg.settings.interpolator =
            crate::settings::Interpolator::parse(i).map_err(|e| format!("--interpolator: {e}"))?;
    }
    if let Some(l) = args.value("--ep-l") {
        cfg.settings.ep_l_pulses =
            crate::settings::parse_ep_l(l).map_err(|e| format!("--ep-l: {e}"))?;
    }
    cfg.check()?;
    Ok((cfg, rest))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn v(s: &[&str]) -> Vec<String> {
        s.iter().map(|x| x.to_string()).collect()
    }

    #[test]
    fn parses_console_options_and_keeps_the_rest() {
        let (cfg, rest) = config_from_args(&v(&[
            "--state",
            "/tmp/s",
            "--window",
            "--rows=16",
            "--cols",
            "48",
            "x.txt",
        ]))
        .unwrap();
        assert_eq!(cfg.state_dir, PathBuf::from("/tmp/s"));
        assert_eq!((cfg.rows, cfg.cols), (16, 48));
        assert_eq!(rest, v(&["--window", "x.txt"]));
        assert!(cfg.record.is_none());
    }

    #[test]
    fn refuses_bad_sizes_and_missing_values() {
        let e = config_from_args(&v(&["--state", "/t", "--rows", "3"])).unwrap_err();
        assert!(e.contains("--rows 3"), "{e}");
        let e = config_from_args(&v(&["--state", "/t", "--cols", "x"])).unwrap_err();
        assert!(e.contains("not a whole number"), "{e}");
        let e = config_from_args(&v(&["--state"])).unwrap_err();
        assert!(e.contains("needs a value"), "{e}");
    }
}
