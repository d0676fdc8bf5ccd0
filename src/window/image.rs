//! Writing a screenshot: binary PPM (P6), or PNG (8-bit RGB, stored deflate blocks) when the
//! file name ends in `.png`. Encoded here, so no image crate is needed.

use crate::crc32::crc32;

use std::path::Path;

/// Encodes `rgb` (width × height × 3 bytes) as a binary PPM.
pub fn ppm(width: usize, height: usize, rgb: &[u8]) -> Vec<u8> {
    let mut out = format!("P6\n{width} {height}\n255\n").into_bytes();
    out.extend_from_slice(rgb);
    out
}

/// Encodes `rgb` (width × height × 3 bytes) as a PNG.
pub fn png(width: usize, height: usize, rgb: &[u8]) -> Vec<u8> {
    let mut raw = Vec::with_capacity((width * 3 + 1) * height);
    for row in rgb.chunks(width * 3).take(height) {
        raw.push(0); // filter: none
        raw.extend_from_slice(row);
    }
    let mut z = vec![0x78, 0x01];
    let mut blocks = raw.chunks(65_535).peekable();
    if blocks.peek().is_none() {
        z.extend_from_slice(&[1, 0, 0, 0xFF, 0xFF]);
    }
    while let Some(b) = blocks.next() {
        let last = blocks.peek().is_none();
        z.push(u8::from(last));
        let len = b.len() as u16;
        z.extend_from_slice(&len.to_le_bytes());
        z.extend_from_slice(&(!len).to_le_bytes());
        z.extend_from_slice(b);
    }
    z.extend_from_slice(&adler32(&raw).to_be_bytes());
    let mut out = vec![0x89, b'P', b'N', b'G', 0x0D, 0x0A, 0x1A, 0x0A];
    let mut ihdr = Vec::new();
    ihdr.extend_from_slice(&(width as u32).to_be_bytes());
    ihdr.extend_from_slice(&(height as u32).to_be_bytes());
    ihdr.extend_from_slice(&[8, 2, 0, 0, 0]);
    chunk(&mut out, b"IHDR", &ihdr);
    chunk(&mut out, b"IDAT", &z);
    chunk(&mut out, b"IEND", &[]);
    out
}

fn chunk(out: &mut Vec<u8>, kind: &[u8; 4], data: &[u8]) {
    out.extend_from_slice(&(data.len() as u32).to_be_bytes());
    let start = out.len();
    out.extend_from_slice(kind);
    out.extend_from_slice(data);
    let crc = crc32(&out[start..]);
    out.extend_from_slice(&crc.to_be_bytes());
}

fn adler32(data: &[u8]) -> u32 {
    let (mut a, mut b) = (1u32, 0u32);
    for &x in data {
        a = (a + x as u32) % 65_521;
        b = (b + a) % 65_521;
    }
    (b << 16) | a
}

/// Writes the image to `path`, PNG if it ends in `.png`, PPM otherwise.
pub fn write(path: &Path, width: usize, height: usize, rgb: &[u8]) -> std::io::Result<()> {
    let is_png = path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("png"));
    let bytes = if is_png {
        png(width, height, rgb)
    } else {
        ppm(width, height, rgb)
    };
    crate::store::fsutil::write_output(path, &bytes).map_err(std::io::Error::other)
}

/// Reads a binary PPM written by `ppm` back: (width, height, rgb).
pub fn read_ppm(bytes: &[u8]) -> Option<(usize, usize, Vec<u8>)> {
    let mut fields = Vec::new();
    let mut i = 0;
    while fields.len() < 4 && i < bytes.len() {
        while i < bytes.len() && bytes[i].is_ascii_whitespace() {
            i += 1;
        }
        let s = i;
        while i < bytes.len() && !bytes[i].is_ascii_whitespace() {
            i += 1;
        }
        fields.push(std::str::from_utf8(&bytes[s..i]).ok()?.to_string());
    }
    if fields.first().map(String::as_str) != Some("P6") || fields.get(3)? != "255" {
        return None;
    }
    let w: usize = fields[1].parse().ok()?;
    let h: usize = fields[2].parse().ok()?;
    let data = bytes.get(i + 1..i + 1 + w * h * 3)?;
    Some((w, h, data.to_vec()))
}

/// Reads a PNG written by `png` back (8-bit RGB, no filters, stored deflate blocks):
/// (width, height, rgb). Any other PNG, or a damaged one, gives `None`.
pub fn read_png(bytes: &[u8]) -> Option<(usize, usize, Vec<u8>)> {
    if bytes.get(..8)? != [0x89, b'P', b'N', b'G', 0x0D, 0x0A, 0x1A, 0x0A] {
        return None;
    }
    let (mut i, mut w, mut h, mut z) = (8, 0, 0, Vec::new());
    while i + 12 <= bytes.len() {
        let len = u32::from_be_bytes(bytes[i..i + 4].try_into().ok()?) as usize;
        let kind = &bytes[i + 4..i + 8];
        let data = bytes.get(i + 8..i + 8 + len)?;
        match kind {
            b"IHDR" => {
                w = u32::from_be_bytes(data.get(0..4)?.try_into().ok()?) as usize;
                h = u32::from_be_bytes(data.get(4..8)?.try_into().ok()?) as usize;
                if data.get(8..13)? != [8, 2, 0, 0, 0] {
                    return None;
                }
            }
            b"IDAT" => z.extend_from_slice(data),
            b"IEND" => break,
            _ => {}
        }
        i += 12 + len;
    }
    // zlib header, then stored blocks: BFINAL/BTYPE byte, LEN, NLEN, the bytes.
    let mut raw = Vec::with_capacity((w * 3 + 1) * h);
    let mut j = 2;
    loop {
        let head = *z.get(j)?;
        if head & 0b110 != 0 {
            return None;
        }
        let len = u16::from_le_bytes(z.get(j + 1..j + 3)?.try_into().ok()?) as usize;
        raw.extend_from_slice(z.get(j + 5..j + 5 + len)?);
        j += 5 + len;
        if head & 1 == 1 {
            break;
        }
    }
    if raw.len() != (w * 3 + 1) * h || adler32(&raw).to_be_bytes() != *z.get(j..j + 4)? {
        return None;
    }
    let mut rgb = Vec::with_capacity(w * h * 3);
    for row in raw.chunks(w * 3 + 1) {
        if row[0] != 0 {
            return None;
        }
        rgb.extend_from_slice(&row[1..]);
    }
    Some((w, h, rgb))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn crc_and_adler_match_known_values() {
        assert_eq!(crc32(b"IEND"), 0xAE42_6082);
        assert_eq!(adler32(b"Wikipedia"), 0x11E6_0398);
    }

    #[test]
    fn ppm_round_trips_and_png_is_well_formed() {
        let rgb: Vec<u8> = (0..2 * 3 * 3).map(|i| i as u8 * 10).collect();
        let p = ppm(2, 3, &rgb);
        assert_eq!(read_ppm(&p), Some((2, 3, rgb.clone())));
        assert_eq!(read_ppm(b"P5\n1 1\n255\n\0"), None);
        let g = png(2, 3, &rgb);
        assert_eq!(&g[..8], &[0x89, b'P', b'N', b'G', 0x0D, 0x0A, 0x1A, 0x0A]);
        assert_eq!(&g[12..16], b"IHDR");
        assert_eq!(&g[g.len() - 8..g.len() - 4], b"IEND");
        // The IDAT payload holds the filtered rows verbatim (stored blocks).
        let filtered_len = (2 * 3 + 1) * 3;
        assert!(g.len() > filtered_len + 8 + 25 + 12);
        assert_eq!(read_png(&g), Some((2, 3, rgb.clone())));
        // Damaged: a changed byte in the pixels breaks the checksum.
        let mut bad = g.clone();
        let k = bad.len() - 12 - 4 - 4 - 1; // the last pixel byte, before Adler-32 and CRC
        bad[k] ^= 1;
        assert_eq!(read_png(&bad), None);
        assert_eq!(read_png(&p), None);
    }

    #[test]
    fn a_large_png_spans_several_stored_blocks_and_reads_back() {
        let (w, h) = (300, 100); // 90,100 filtered bytes: two blocks
        let rgb: Vec<u8> = (0..w * h * 3).map(|i| (i * 7 % 251) as u8).collect();
        assert_eq!(read_png(&png(w, h, &rgb)), Some((w, h, rgb)));
    }
}
