//! fakenect's frame files: `P5 640 480 65535` with *little-endian* u16 samples (not standard PGM)
//! and `P6 640 480 255` RGB. Readers fill caller-owned buffers so frames can be pooled.

use std::io::Write;
use std::path::Path;

use crate::error::{Error, Result};
use crate::labels::{HEIGHT, NO_DEPTH, PIXELS, WIDTH};

/// Parsed `Pn width height maxval` header and the offset of the first sample byte.
struct Header {
    magic: [u8; 2],
    width: usize,
    height: usize,
    maxval: usize,
    data_start: usize,
}

fn parse_header(path: &Path, bytes: &[u8]) -> Result<Header> {
    if bytes.len() < 2 || bytes[0] != b'P' {
        return Err(Error::input(
            path,
            "byte 0",
            "not a PNM file: expected a header starting with 'P5' or 'P6'",
        ));
    }
    let magic = [bytes[0], bytes[1]];
    let mut pos = 2;
    let mut fields = [0usize; 3];
    for (i, field) in fields.iter_mut().enumerate() {
        // Whitespace and `#` comments may separate header fields.
        loop {
            match bytes.get(pos) {
                Some(b) if b.is_ascii_whitespace() => pos += 1,
                Some(b'#') => {
                    while bytes.get(pos).is_some_and(|&b| b != b'\n') {
                        pos += 1;
                    }
                }
                _ => break,
            }
        }
        let start = pos;
        while bytes.get(pos).is_some_and(u8::is_ascii_digit) {
            pos += 1;
        }
        let name = ["width", "height", "maxval"][i];
        if start == pos || pos - start > 9 {
            return Err(Error::input(
                path,
                format!("byte {start}"),
                format!("header: expected the {name} as a decimal number"),
            ));
        }
        *field = std::str::from_utf8(&bytes[start..pos])
            .unwrap()
            .parse()
            .unwrap();
    }
    if !bytes.get(pos).is_some_and(u8::is_ascii_whitespace) {
        return Err(Error::input(
            path,
            format!("byte {pos}"),
            "header: expected one whitespace byte before the samples",
        ));
    }
    Ok(Header {
        magic,
        width: fields[0],
        height: fields[1],
        maxval: fields[2],
        data_start: pos + 1,
    })
}

/// Reads a whole file into `buf`, reusing its allocation (frames are read every 33 ms).
fn read_file_into(path: &Path, buf: &mut Vec<u8>) -> Result<()> {
    use std::io::Read;
    buf.clear();
    std::fs::File::open(path)
        .and_then(|mut f| f.read_to_end(buf))
        .map_err(|e| Error::io(path, "reading", e))?;
    Ok(())
}

fn check_body(
    path: &Path,
    h: &Header,
    bytes: &[u8],
    want_magic: &[u8; 2],
    want_max: usize,
    bytes_per_px: usize,
) -> Result<()> {
    if &h.magic != want_magic {
        return Err(Error::input(
            path,
            "byte 0",
            format!(
                "header magic '{}' is wrong, expected '{}'",
                String::from_utf8_lossy(&h.magic),
                String::from_utf8_lossy(want_magic)
            ),
        ));
    }
    if h.width != WIDTH || h.height != HEIGHT {
        return Err(Error::input(
            path,
            "header",
            format!(
                "size {}x{} is not supported, expected {WIDTH}x{HEIGHT}",
                h.width, h.height
            ),
        ));
    }
    if h.maxval != want_max {
        return Err(Error::input(
            path,
            "header",
            format!("maxval {} is wrong, expected {want_max}", h.maxval),
        ));
    }
    let want = PIXELS * bytes_per_px;
    let got = bytes.len() - h.data_start;
    if got < want {
        return Err(Error::input(
            path,
            format!("byte {}", bytes.len()),
            format!("truncated: {got} sample bytes, expected {want}"),
        ));
    }
    if got > want {
        return Err(extra_bytes_error(path, h, bytes, got - want, want));
    }
    Ok(())
}

/// The error for `extra` bytes past the samples. A header ending in "\r\n" ends at its CR (the
/// one whitespace byte), so its LF shifts the samples by one: report the line ending, not the byte.
fn extra_bytes_error(path: &Path, h: &Header, bytes: &[u8], extra: usize, want: usize) -> Error {
    let cr_at = h.data_start - 1;
    if extra == 1 && bytes[cr_at] == b'\r' && bytes.get(h.data_start) == Some(&b'\n') {
        return Error::input(
            path,
            format!("byte {cr_at}"),
            "header ends in \\r\\n (Windows line ending); fakenect writes a single \\n",
        );
    }
    let s = if extra == 1 { "" } else { "s" };
    Error::input(
        path,
        format!("byte {}", h.data_start + want),
        format!("{extra} unexpected byte{s} after the {want} sample bytes"),
    )
}

/// Reads a fakenect depth frame into `out` (640·480 raw values, 2047 = no depth).
/// Values above 2047 are rejected: they cannot come from an 11-bit sensor.
pub fn read_depth(path: &Path, out: &mut [u16]) -> Result<()> {
    read_depth_with(path, &mut Vec::new(), out)
}

/// [`read_depth`] reusing `scratch` for the file's bytes, so a replay allocates nothing per frame.
pub fn read_depth_with(path: &Path, scratch: &mut Vec<u8>, out: &mut [u16]) -> Result<()> {
    read_file_into(path, scratch)?;
    decode_depth(path, scratch, out)
}

/// Decodes the bytes of a depth PGM (see [`read_depth`]).
pub fn decode_depth(path: &Path, bytes: &[u8], out: &mut [u16]) -> Result<()> {
    assert_eq!(out.len(), PIXELS);
    let h = parse_header(path, bytes)?;
    check_body(path, &h, bytes, b"P5", 65535, 2)?;
    let body = &bytes[h.data_start..];
    for (i, (o, b)) in out.iter_mut().zip(body.chunks_exact(2)).enumerate() {
        let v = u16::from_le_bytes([b[0], b[1]]);
        if v > NO_DEPTH {
            return Err(Error::input(
                path,
                format!(
                    "pixel ({}, {}) at byte {}",
                    i % WIDTH,
                    i / WIDTH,
                    h.data_start + 2 * i
                ),
                format!("raw value {v} is above 2047 (11-bit depth, little-endian expected)"),
            ));
        }
        *o = v;
    }
    Ok(())
}

/// Reads a fakenect RGB frame into `out` (640·480·3 bytes).
pub fn read_rgb(path: &Path, out: &mut [u8]) -> Result<()> {
    read_rgb_with(path, &mut Vec::new(), out)
}

/// [`read_rgb`] reusing `scratch` for the file's bytes.
pub fn read_rgb_with(path: &Path, scratch: &mut Vec<u8>, out: &mut [u8]) -> Result<()> {
    read_file_into(path, scratch)?;
    let bytes: &[u8] = scratch;
    assert_eq!(out.len(), PIXELS * 3);
    let h = parse_header(path, bytes)?;
    check_body(path, &h, bytes, b"P6", 255, 3)?;
    out.copy_from_slice(&bytes[h.data_start..]);
    Ok(())
}

/// Writes a depth frame in fakenect's format.
pub fn write_depth(path: &Path, depth: &[u16]) -> Result<()> {
    assert_eq!(depth.len(), PIXELS);
    let mut buf = Vec::with_capacity(PIXELS * 2 + 20);
    writeln!(buf, "P5 {WIDTH} {HEIGHT} 65535").unwrap();
    for v in depth {
        buf.extend_from_slice(&v.to_le_bytes());
    }
    std::fs::write(path, buf).map_err(|e| Error::io(path, "writing", e))
}

/// Writes an RGB frame in fakenect's format.
pub fn write_rgb(path: &Path, rgb: &[u8]) -> Result<()> {
    assert_eq!(rgb.len(), PIXELS * 3);
    let mut buf = Vec::with_capacity(PIXELS * 3 + 20);
    writeln!(buf, "P6 {WIDTH} {HEIGHT} 255").unwrap();
    buf.extend_from_slice(rgb);
    std::fs::write(path, buf).map_err(|e| Error::io(path, "writing", e))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn pgm(header: &str, samples: usize) -> Vec<u8> {
        let mut v = header.as_bytes().to_vec();
        v.extend(std::iter::repeat_n([0xff, 0x07], samples).flatten());
        v
    }

    #[test]
    fn reads_little_endian() {
        let mut b = pgm("P5 640 480 65535\n", PIXELS);
        let s = b.len() - PIXELS * 2;
        b[s] = 0x34;
        b[s + 1] = 0x03; // 0x0334 = 820 little-endian
        let mut out = vec![0u16; PIXELS];
        decode_depth(Path::new("d.pgm"), &b, &mut out).unwrap();
        assert_eq!(out[0], 820);
        assert_eq!(out[1], 2047);
    }

    #[test]
    fn rejects_truncated_and_wrong_size_and_big_values() {
        let mut out = vec![0u16; PIXELS];
        let e = decode_depth(
            Path::new("d.pgm"),
            &pgm("P5 640 480 65535\n", PIXELS - 1),
            &mut out,
        )
        .unwrap_err()
        .to_string();
        assert!(
            e.starts_with("d.pgm: byte ") && e.contains("truncated"),
            "{e}"
        );
        let e = decode_depth(
            Path::new("d.pgm"),
            &pgm("P5 320 240 65535\n", 320 * 240),
            &mut out,
        )
        .unwrap_err()
        .to_string();
        assert!(e.contains("320x240"), "{e}");
        let mut b = pgm("P5 640 480 65535\n", PIXELS);
        let n = b.len();
        b[n - 1] = 0x08; // last pixel 0x08ff = 2303 > 2047
        let e = decode_depth(Path::new("d.pgm"), &b, &mut out)
            .unwrap_err()
            .to_string();
        assert!(e.contains("pixel (639, 479)") && e.contains("2303"), "{e}");
        let e = decode_depth(Path::new("d.pgm"), b"P6 640 480 255\n", &mut out)
            .unwrap_err()
            .to_string();
        assert!(e.contains("magic"), "{e}");
    }

    #[test]
    fn names_a_windows_line_ending_in_the_header() {
        let mut out = vec![0u16; PIXELS];
        let e = decode_depth(
            Path::new("d.pgm"),
            &pgm("P5 640 480 65535\r\n", PIXELS),
            &mut out,
        )
        .unwrap_err()
        .to_string();
        assert_eq!(
            e,
            "d.pgm: byte 16: header ends in \\r\\n (Windows line ending); fakenect writes a single \\n"
        );
        let mut rgb = b"P6 640 480 255\r\n".to_vec();
        rgb.resize(rgb.len() + PIXELS * 3, 0);
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("r.ppm");
        std::fs::write(&path, rgb).unwrap();
        let e = read_rgb(&path, &mut vec![0u8; PIXELS * 3])
            .unwrap_err()
            .to_string();
        assert!(e.contains("byte 14: header ends in \\r\\n"), "{e}");
    }

    #[test]
    fn counts_extra_bytes_in_good_grammar() {
        let mut out = vec![0u16; PIXELS];
        let mut b = pgm("P5 640 480 65535\n", PIXELS);
        b.push(0);
        let e = decode_depth(Path::new("d.pgm"), &b, &mut out)
            .unwrap_err()
            .to_string();
        assert!(
            e.ends_with("byte 614417: 1 unexpected byte after the 614400 sample bytes"),
            "{e}"
        );
        b.push(0);
        let e = decode_depth(Path::new("d.pgm"), &b, &mut out)
            .unwrap_err()
            .to_string();
        assert!(e.contains("2 unexpected bytes"), "{e}");
    }
}
