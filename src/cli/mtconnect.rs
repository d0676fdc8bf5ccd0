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

const DEVICES_HELP: &str = "\
usage: novanc mtconnect-devices [--machine centre|centre4|citizen|FILE]

Prints the MTConnect device file (Devices.xml) of the machine for an agent (cppagent 2.x):
its axes (X Y Z, its rotary axes A B C in degrees; a lathe's X and Z per channel), each
path's spindle, the controller and one path per channel. Every data item id is a key the
adapter sends (`--mtconnect`, docs/mtconnect.md). Without --machine, the centre.
";

/// `novanc mtconnect-devices [--machine M]`.
pub fn devices_main(argv: &[String]) -> i32 {
    use super::args::{Args, Opt};
    let opts = [
        Opt::value("--machine"),
        Opt::flag("--help"),
        Opt::flag("-h"),
    ];
    let args = match Args::parse(argv, &opts) {
        Ok(a) => a,
        Err(e) => return super::usage_error(&format!("mtconnect-devices: {e}")),
    };
    if args.flag("--help") || args.flag("-h") {
        print!("{DEVICES_HELP}");
        return 0;
    }
    if !args.positional.is_empty() {
        return super::usage_error(
            "mtconnect-devices takes no file (see novanc mtconnect-devices --help)",
        );
    }
    let m = args.value("--machine").unwrap_or("centre");
    let desc = match crate::lathe::desc::load(m) {
        Ok(d) => d,
        Err(e) => return super::fail(&format!("novanc: {e}")),
    };
    // The description's own name (`machine NAME`), a built-in's its name.
    let named = std::fs::read_to_string(m)
        .ok()
        .and_then(|t| {
            t.lines().find_map(|l| {
                let mut w = l.split('#').next()?.split_whitespace();
                (w.next() == Some("machine")).then(|| w.next().map(str::to_string))?
            })
        })
        .unwrap_or_else(|| m.to_string());
    let machine = match &desc {
        crate::lathe::desc::MachineDesc::Mill(s) => crate::mtconnect::devices::Machine::Mill {
            name: &named,
            rotary_mask: s.rotary_mask(),
        },
        crate::lathe::desc::MachineDesc::Lathe(d) => crate::mtconnect::devices::Machine::Lathe {
            name: &named,
            channels: d.channels.len(),
        },
    };
    print!("{}", crate::mtconnect::devices::xml(&machine));
    0
}
