//! Record framing for the journal and the snapshot: each record is a header line
//! `@ LEN CRC32\n`, then LEN bytes of payload, then `\n`. The checksum (CRC-32, IEEE) covers the
//! payload. A reader stops at the first record that is truncated or does not check, and says
//! where and why, so a torn tail is reported and skipped, never fatal.

pub use crate::crc32::crc32;

/// One payload framed for appending to a file.
pub fn encode(payload: &[u8]) -> Vec<u8> {
    let mut out = format!("@ {} {:08x}\n", payload.len(), crc32(payload)).into_bytes();
    out.extend_from_slice(payload);
    out.push(b'\n');
    out
}

/// Why reading stopped before the end of the data.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Damage {
    /// Byte offset of the first record that could not be read.
    pub offset: usize,
    /// Index (0-based) of that record.
    pub record: usize,
    /// What is wrong with it.
    pub reason: String,
}

/// The records of a framed file, and where reading stopped if it stopped early.
#[derive(Clone, Debug, Default)]
pub struct Decoded<'a> {
    /// The payloads that checked, in order.
    pub records: Vec<&'a [u8]>,
    /// Byte length of the good prefix.
    pub good_len: usize,
    /// The first damaged record, if the data does not end cleanly.
    pub damage: Option<Damage>,
}

/// Splits framed data into payloads, stopping at the first damaged record.
pub fn decode(data: &[u8]) -> Decoded<'_> {
    let mut d = Decoded::default();
    let mut pos = 0;
    while pos < data.len() {
        match decode_one(&data[pos..]) {
            Ok((payload, used)) => {
                d.records.push(payload);
                pos += used;
            }
            Err(reason) => {
                d.damage = Some(Damage {
                    offset: pos,
                    record: d.records.len(),
                    reason,
                });
                break;
            }
        }
    }
    d.good_len = pos;
    d
}

/// One record at the start of `data`: (payload, bytes used).
fn decode_one(data: &[u8]) -> Result<(&[u8], usize), String> {
    let nl = data
        .iter()
        .take(40)
        .position(|&b| b == b'\n')
        .ok_or_else(|| "record header is cut off or garbled".to_string())?;
    let header = std::str::from_utf8(&data[..nl]).map_err(|_| "record header is garbled")?;
    let mut f = header.split(' ');
    let (at, len, crc) = (f.next(), f.next(), f.next());
    if at != Some("@") || f.next().is_some() {
        return Err("record header is garbled".to_string());
    }
    let len: usize = len
        .and_then(|s| s.parse().ok())
        .ok_or_else(|| "record length is garbled".to_string())?;
    let crc = crc
        .filter(|s| s.len() == 8)
        .and_then(|s| u32::from_str_radix(s, 16).ok())
        .ok_or_else(|| "record checksum is garbled".to_string())?;
    let start = nl + 1;
    let end = start
        .checked_add(len)
        .filter(|&e| e < data.len())
        .ok_or_else(|| {
            format!(
                "record is truncated ({} of {} bytes)",
                data.len() - start,
                len + 1
            )
        })?;
    if data[end] != b'\n' {
        return Err("record does not end where its length says".to_string());
    }
    let payload = &data[start..end];
    if crc32(payload) != crc {
        return Err("record checksum does not match".to_string());
    }
    Ok((payload, end + 1))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn round_trip_and_damage() {
        let mut data = encode(b"edit M\nIG00*");
        data.extend(encode(b"select TABLEB"));
        data.extend(encode(b"with\nnewlines\n"));
        let d = decode(&data);
        assert_eq!(d.records.len(), 3);
        assert_eq!(d.records[2], b"with\nnewlines\n");
        assert_eq!(d.good_len, data.len());
        assert!(d.damage.is_none());

        // Truncated tail: the first two survive.
        let cut = &data[..data.len() - 3];
        let d = decode(cut);
        assert_eq!(d.records.len(), 2);
        let dmg = d.damage.unwrap();
        assert_eq!(dmg.record, 2);
        assert!(dmg.reason.contains("truncated"), "{}", dmg.reason);

        // A flipped payload byte in the middle: reading stops there.
        let mut bad = data.clone();
        let i = encode(b"edit M\nIG00*").len() + 16;
        bad[i] ^= 0x20;
        let d = decode(&bad);
        assert_eq!(d.records.len(), 1);
        assert!(d.damage.unwrap().reason.contains("checksum"));

        // Garbage appended.
        let mut g = data.clone();
        g.extend_from_slice(b"\x00\x00\x00garbage");
        let d = decode(&g);
        assert_eq!(d.records.len(), 3);
        assert_eq!(d.good_len, data.len());
        assert!(d.damage.is_some());
    }
}
