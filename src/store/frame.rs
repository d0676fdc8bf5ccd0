//! Record framing for the journal and the snapshot: each record is a header line
//! `@ LEN CRC32\n`, then LEN bytes of payload, then `\n`. The checksum (CRC-32, IEEE) covers the
//! payload. A reader stops at the first record that is truncated or does not check, and says
//! where and why, so a torn tail is reported and skipped, never fatal.
//!
//! Format 2 of both files writes every frame twice in a row (`encode_pair`), so that damage to
//! one copy (a flipped byte anywhere, header included) is made good by the other
//! (`decode_paired`; docs/stores.md "Damage").

pub use crate::crc32::crc32;

/// One payload framed for appending to a file.
pub fn encode(payload: &[u8]) -> Vec<u8> {
    let mut out = format!("@ {} {:08x}\n", payload.len(), crc32(payload)).into_bytes();
    out.extend_from_slice(payload);
    out.push(b'\n');
    out
}

/// One payload framed twice in a row: the copy that survives when the other is damaged.
pub fn encode_pair(payload: &[u8]) -> Vec<u8> {
    let one = encode(payload);
    let mut out = Vec::with_capacity(2 * one.len());
    out.extend_from_slice(&one);
    out.extend_from_slice(&one);
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

/// The records of paired framed data (format 2), with the damage the second copies made good.
#[derive(Clone, Debug, Default)]
pub struct Paired<'a> {
    /// The payloads read, in order, one per pair.
    pub records: Vec<&'a [u8]>,
    /// Byte length of the part read (up to `damage`).
    pub good_len: usize,
    /// Damaged copies whose other copy was used: nothing lost.
    pub repaired: Vec<Damage>,
    /// The first record neither copy of which could be read; reading stopped there.
    pub damage: Option<Damage>,
    /// Records found further on, past `damage` (by looking for the next intact pair): they
    /// exist but follow one that was lost.
    pub after: Vec<&'a [u8]>,
}

/// How many bytes a damaged first copy may differ from the intact second one for the two to
/// be taken as one pair (a flipped byte is 1; a short burst of damage a few).
const MAX_COPY_DIFF: usize = 8;

/// Splits paired framed data into payloads, taking the second copy of a record whose first
/// copy is damaged (and ignoring a damaged or cut-short second copy). Stops at the first
/// record neither copy of which reads, then looks on for intact pairs (`after`).
pub fn decode_paired(data: &[u8]) -> Paired<'_> {
    let mut d = Paired::default();
    let mut pos = 0;
    while pos < data.len() {
        let record = d.records.len();
        match decode_one(&data[pos..]) {
            Ok((payload, used)) => {
                let copy = pos + used;
                if copy + used > data.len() {
                    d.repaired.push(Damage {
                        offset: copy,
                        record,
                        reason: format!(
                            "its second copy is cut short ({} of {used} bytes)",
                            data.len() - copy
                        ),
                    });
                } else if data[copy..copy + used] != data[pos..copy] {
                    d.repaired.push(Damage {
                        offset: copy,
                        record,
                        reason: "its second copy does not match".to_string(),
                    });
                }
                d.records.push(payload);
                pos = (copy + used).min(data.len());
            }
            Err(reason) => match find_copy(data, pos) {
                Some((payload, used)) => {
                    d.repaired.push(Damage {
                        offset: pos,
                        record,
                        reason,
                    });
                    d.records.push(payload);
                    pos += 2 * used;
                }
                None => {
                    d.damage = Some(Damage {
                        offset: pos,
                        record,
                        reason,
                    });
                    break;
                }
            },
        }
    }
    d.good_len = pos;
    if let Some(dmg) = &d.damage {
        d.after = resync(data, dmg.offset + 1);
    }
    d
}

/// The intact second copy of a damaged record at `p`: a frame starting where the first copy,
/// of the same length, would end, and differing from it in a few bytes at most.
fn find_copy(data: &[u8], p: usize) -> Option<(&[u8], usize)> {
    for q in p + 1..data.len() {
        let used = q - p;
        if q + used > data.len() {
            return None;
        }
        if data[q] != b'@' {
            continue;
        }
        if let Ok((payload, u)) = decode_one(&data[q..]) {
            let diff = data[p..q]
                .iter()
                .zip(&data[q..q + used])
                .filter(|(a, b)| a != b)
                .count();
            if u == used && diff <= MAX_COPY_DIFF {
                return Some((payload, used));
            }
        }
    }
    None
}

/// The records of the first intact pair at or after `from`, and of everything after it.
fn resync(data: &[u8], from: usize) -> Vec<&[u8]> {
    for q in from..data.len() {
        if data[q] != b'@' {
            continue;
        }
        if let Ok((_, used)) = decode_one(&data[q..]) {
            if q + 2 * used <= data.len() && data[q..q + used] == data[q + used..q + 2 * used] {
                let rest = decode_paired(&data[q..]);
                let mut out = rest.records;
                out.extend(rest.after);
                return out;
            }
        }
    }
    Vec::new()
}

/// The payload of the first record, if it reads.
pub fn first_record(data: &[u8]) -> Option<&[u8]> {
    decode_one(data).ok().map(|(p, _)| p)
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

    fn paired(payloads: &[&[u8]]) -> Vec<u8> {
        payloads.iter().flat_map(|p| encode_pair(p)).collect()
    }

    #[test]
    fn every_single_flipped_byte_is_made_good_by_the_second_copy() {
        let recs: [&[u8]; 4] = [
            b"novanc-journal 2 7",
            b"edit M\nIG00*",
            b"select A",
            b"x\n@ 1 0\n",
        ];
        let data = paired(&recs);
        let clean = decode_paired(&data);
        assert_eq!(clean.records, recs);
        assert!(clean.repaired.is_empty() && clean.damage.is_none());
        for i in 0..data.len() {
            for x in [0x01u8, 0x20, 0xff] {
                let mut bad = data.clone();
                bad[i] ^= x;
                let d = decode_paired(&bad);
                assert_eq!(d.records, recs, "byte {i} ^ {x:#x}");
                assert!(d.damage.is_none(), "byte {i} ^ {x:#x}: {:?}", d.damage);
                assert_eq!(d.repaired.len(), 1, "byte {i} ^ {x:#x}");
                assert_eq!(d.good_len, bad.len());
            }
        }
    }

    #[test]
    fn a_torn_tail_and_a_record_lost_in_both_copies() {
        let recs: [&[u8]; 3] = [b"head", b"one", b"two"];
        let data = paired(&recs);
        // Cut inside the last record's second copy: the record is kept, noted as repaired.
        let d = decode_paired(&data[..data.len() - 2]);
        assert_eq!(d.records, recs);
        assert!(
            d.repaired[0].reason.contains("cut short"),
            "{:?}",
            d.repaired
        );
        // Cut inside its first copy: it is gone, nothing after it.
        let one = encode(b"two").len();
        let d = decode_paired(&data[..data.len() - one - 2]);
        assert_eq!(d.records, &recs[..2]);
        assert!(d.damage.unwrap().reason.contains("truncated"));
        assert!(d.after.is_empty());
        // Both copies of "one" damaged: reading stops there; "two" is found after it.
        let mut bad = data.clone();
        let at = encode_pair(b"head").len();
        bad[at + 16] ^= 1;
        bad[at + one + 16] ^= 1;
        let d = decode_paired(&bad);
        assert_eq!(d.records, &recs[..1]);
        assert_eq!(d.damage.unwrap().record, 1);
        assert_eq!(d.after, &recs[2..]);
    }
}
