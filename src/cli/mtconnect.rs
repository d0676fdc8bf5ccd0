//! `--mtconnect ADDR:PORT` and `--mtconnect-wait SECONDS` (docs/mtconnect.md), taken out of a
//! subcommand's arguments; the adapter they start is `crate::mtconnect::feed`.

pub use crate::mtconnect::feed::{Feed, MtcOpts};

/// Takes `--mtconnect V` / `--mtconnect=V` and `--mtconnect-wait S` out of `argv`.
pub fn take(argv: &[String]) -> Result<(MtcOpts, Vec<String>), String> {
    let mut o = MtcOpts::default();
    let (taken, rest) = super::args::take_values(argv, &["--mtconnect", "--mtconnect-wait"])?;
    for (name, v) in taken {
        if name == "--mtconnect" {
            o.addr = Some(crate::mtconnect::parse_addr(&v)?);
        } else {
            o.wait = Some(crate::mtconnect::parse_wait(&v)?);
        }
    }
    if o.wait.is_some() && o.addr.is_none() {
        return Err("--mtconnect-wait needs --mtconnect".into());
    }
    Ok((o, rest))
}
