//! The MTConnect device file (`Devices.xml`) of a machine, made from what the adapter sends:
//! each data item's id is the key `items` sends, so the file and the stream cannot disagree
//! (docs/mtconnect.md "The device file"). `novanc mtconnect-devices --machine M` prints it;
//! the shipped `docs/mtconnect/Devices.xml` (the centre) and `Devices-citizen.xml` are its
//! output. Before stop 54 they were written by hand and had X Y Z only: a machine with rotary
//! axes sent no position of its table.

use super::items::{device_controller_items, device_items, Place};
use super::PathKeys;
use std::fmt::Write;

/// The machine a device file describes.
pub enum Machine<'a> {
    /// A mill (the machining centre) named `name`, with the rotary axes of `rotary_mask` (A 1,
    /// B 2, C 4).
    Mill { name: &'a str, rotary_mask: u8 },
    /// A lathe named `name` with `channels` channels (paths).
    Lathe { name: &'a str, channels: usize },
}

/// The device file of `m`, for the reference agent's 2.x schema (`MTConnectDevices_2.0.xsd`).
///
/// - The device is named after the machine (`uuid novanc-NAME-1`).
/// - `Axes`: a `Linear` X, Y, Z (a lathe's X and Z per channel, `X1`, `Z2`) with their work and
///   machine positions in mm; a `Rotary` A, B, C with their angles in degrees; each path's
///   spindle a `Rotary` `C` (`C1`, `C2` on a lathe; `S` on a mill whose table axis is C) with its
///   speed and override.
/// - `Controller`: E-STOP, the message and the system condition; one `Path` per channel with
///   its mode, execution, program, block, line, feed, overrides, tool, part count, conditions,
///   and on a mill the work and tool offset tables.
pub fn xml(m: &Machine) -> String {
    let (name, kind, paths, tables): (&str, String, Vec<PathKeys>, bool) = match *m {
        Machine::Mill { name, rotary_mask } => {
            (name, "mill".into(), vec![PathKeys::mill(rotary_mask)], true)
        }
        Machine::Lathe { name, channels } => (
            name,
            format!("lathe of {channels} channels"),
            (1..=channels).map(PathKeys::lathe).collect(),
            false,
        ),
    };
    let several = paths.len() > 1;
    let suffix = |p: usize| {
        if several {
            (p + 1).to_string()
        } else {
            String::new()
        }
    };
    let item = |out: &mut String, indent: usize, id: &str, attrs: &str| {
        // The schema's attributes in the shipped files' order: category, id, the rest.
        let (category, rest) = attrs.split_once(' ').unwrap_or((attrs, ""));
        let pad = " ".repeat(indent);
        let rest = if rest.is_empty() {
            String::new()
        } else {
            format!(" {rest}")
        };
        let _ = writeln!(out, r#"{pad}<DataItem {category} id="{id}"{rest}/>"#);
    };
    let items: Vec<_> = paths.iter().map(|k| device_items(k, tables)).collect();
    let mut o = String::new();
    // (An XML comment may not hold a double hyphen: the comment names no option.)
    let _ = write!(
        o,
        r#"<?xml version="1.0" encoding="UTF-8"?>
<!-- novanc's machine {name} ({kind}) as one MTConnect device, for the reference agent
     (cppagent 2.x), made by `novanc mtconnect-devices` for that machine. Data item ids equal
     the SHDR keys novanc sends (docs/mtconnect.md). -->
<MTConnectDevices xmlns="urn:mtconnect.org:MTConnectDevices:2.0"
                  xmlns:m="urn:mtconnect.org:MTConnectDevices:2.0"
                  xmlns:xsi="http://www.w3.org/2001/XMLSchema-instance"
                  xsi:schemaLocation="urn:mtconnect.org:MTConnectDevices:2.0 http://schemas.mtconnect.org/schemas/MTConnectDevices_2.0.xsd">
  <Header creationTime="2026-11-26T00:00:00Z" sender="novanc" instanceId="1" version="2.0" deviceModelChangeTime="2026-11-26T00:00:00Z" bufferSize="131072" assetBufferSize="1024" assetCount="0"/>
  <Devices>
    <Device id="{name}" name="{name}" uuid="novanc-{name}-1">
      <Description manufacturer="novanc" model="{name}">novanc CNC operator console, {kind}</Description>
      <DataItems>
"#
    );
    let controller = device_controller_items();
    for (id, attrs) in controller.iter().take(1) {
        item(&mut o, 8, id, attrs);
    }
    o.push_str("      </DataItems>\n      <Components>\n        <Axes id=\"axes\" name=\"axes\">\n          <Components>\n");
    // A table's C takes the letter: the spindle is then S.
    let table_c = paths.iter().any(|k| {
        k.axes()
            .iter()
            .any(|&(a, _)| a == crate::block::FIRST_ROTARY + 2)
    });
    for (p, k) in paths.iter().enumerate() {
        for (i, &(a, letter)) in k.axes().iter().enumerate() {
            let element = if a >= crate::block::FIRST_ROTARY {
                "Rotary"
            } else {
                "Linear"
            };
            let (id, nm) = (
                format!("{}{}", letter.to_ascii_lowercase(), suffix(p)),
                format!("{letter}{}", suffix(p)),
            );
            let _ = writeln!(
                o,
                "            <{element} id=\"{id}\" name=\"{nm}\">\n              <DataItems>"
            );
            for (_, key, attrs) in items[p].iter().filter(|(pl, ..)| *pl == Place::Axis(i)) {
                item(&mut o, 16, key, attrs);
            }
            let _ = writeln!(o, "              </DataItems>\n            </{element}>");
        }
    }
    for (p, spindle) in items.iter().enumerate() {
        let letter = if table_c { "S" } else { "C" };
        let _ = writeln!(
            o,
            "            <Rotary id=\"{}{}\" name=\"{letter}{}\">\n              <DataItems>",
            letter.to_ascii_lowercase(),
            suffix(p),
            suffix(p)
        );
        for (_, key, attrs) in spindle.iter().filter(|(pl, ..)| *pl == Place::Spindle) {
            item(&mut o, 16, key, attrs);
        }
        o.push_str("              </DataItems>\n            </Rotary>\n");
    }
    o.push_str("          </Components>\n        </Axes>\n        <Controller id=\"cont\" name=\"controller\">\n          <DataItems>\n");
    for (id, attrs) in controller.iter().skip(1) {
        item(&mut o, 12, id, attrs);
    }
    o.push_str("          </DataItems>\n          <Components>\n");
    for (p, path) in items.iter().enumerate() {
        let _ = writeln!(
            o,
            "            <Path id=\"path{0}\" name=\"path{0}\">\n              <DataItems>",
            p + 1
        );
        for (_, key, attrs) in path.iter().filter(|(pl, ..)| *pl == Place::Path) {
            item(&mut o, 16, key, attrs);
        }
        o.push_str("              </DataItems>\n            </Path>\n");
    }
    o.push_str("          </Components>\n        </Controller>\n      </Components>\n    </Device>\n  </Devices>\n</MTConnectDevices>\n");
    o
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The shipped device files are the generator's output, byte for byte.
    #[test]
    fn the_shipped_device_files_are_what_the_generator_makes() {
        let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/docs/mtconnect/");
        let centre = xml(&Machine::Mill {
            name: "centre",
            rotary_mask: 0,
        });
        let citizen = xml(&Machine::Lathe {
            name: "citizen",
            channels: 3,
        });
        for (file, made) in [("Devices.xml", centre), ("Devices-citizen.xml", citizen)] {
            let shipped = std::fs::read_to_string(format!("{dir}{file}")).unwrap();
            assert_eq!(
                shipped, made,
                "{file}: run `novanc mtconnect-devices` again"
            );
        }
    }

    #[test]
    fn a_trunnion_s_table_axes_are_rotary_components_and_its_spindle_is_s() {
        let x = xml(&Machine::Mill {
            name: "trunnion",
            rotary_mask: 0b110,
        });
        assert!(x.contains(r#"<Rotary id="b" name="B">"#), "{x}");
        assert!(x.contains(r#"<DataItem category="SAMPLE" id="Cmach" type="ANGLE" subType="ACTUAL" units="DEGREE" coordinateSystem="MACHINE"/>"#), "{x}");
        assert!(x.contains(r#"<Rotary id="s" name="S">"#), "{x}");
        assert!(!x.contains(r#"id="Aact""#), "{x}");
        // Every id once.
        let mut ids: Vec<&str> = x
            .split(" id=\"")
            .skip(1)
            .map(|r| r.split('"').next().unwrap())
            .collect();
        let n = ids.len();
        ids.sort();
        ids.dedup();
        assert_eq!(ids.len(), n, "{x}");
    }
}
