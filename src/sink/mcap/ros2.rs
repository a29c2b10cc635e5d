//! `sensor_msgs/msg/Image` as ROS 2 puts it on the wire and in bags: the `ros2msg` definition
//! text that `ros2 bag record` stores as the MCAP schema, and the message's CDR serialisation
//! (what the `cdr` message encoding means), written and parsed by hand so that umbra needs no ROS.
//!
//! CDR (OMG XCDR1, little-endian, as rmw_fastrtps and rmw_cyclonedds emit it): a 4-byte
//! encapsulation header `00 01 00 00`, then the fields in order, each primitive aligned to its
//! own size counted from the end of that header; strings are a u32 length including the NUL
//! terminator, the bytes and the NUL; `sequence<uint8>` is a u32 count and the bytes.

/// Schema name of the image topics, as ROS 2 spells the type.
pub const IMAGE_TYPE: &str = "sensor_msgs/msg/Image";

/// The complete `ros2msg` definition of `sensor_msgs/msg/Image`: the type's fields first, then
/// each dependency after a line of 80 `=` and a `MSG: <type>` line, in the order rosbag2's
/// `LocalMessageDefinitionSource` emits them (depth first, as met). Comments are left out;
/// parsers ignore them.
pub const IMAGE_DEFINITION: &str = "std_msgs/Header header
uint32 height
uint32 width
string encoding
uint8 is_bigendian
uint32 step
uint8[] data

================================================================================
MSG: std_msgs/Header
builtin_interfaces/Time stamp
string frame_id

================================================================================
MSG: builtin_interfaces/Time
int32 sec
uint32 nanosec
";

/// The CDR encapsulation header for little-endian plain CDR.
pub const CDR_LE: [u8; 4] = [0x00, 0x01, 0x00, 0x00];

/// Pixel data of an image: 8-bit (mono8, rgb8) or 16-bit (16UC1, stored little-endian).
#[derive(Clone, Copy, Debug)]
pub enum Pixels<'a> {
    /// One byte per channel.
    U8(&'a [u8]),
    /// One little-endian u16 per pixel.
    U16(&'a [u16]),
}

impl Pixels<'_> {
    fn byte_len(&self) -> usize {
        match self {
            Pixels::U8(p) => p.len(),
            Pixels::U16(p) => 2 * p.len(),
        }
    }
}

/// Everything of an `Image` but its pixels, borrowed.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ImageHeader<'a> {
    /// `header.stamp.sec`.
    pub sec: i32,
    /// `header.stamp.nanosec`.
    pub nanosec: u32,
    /// `header.frame_id`: the optical frame the pixels are in.
    pub frame_id: &'a str,
    /// Rows.
    pub height: u32,
    /// Columns.
    pub width: u32,
    /// `mono8`, `16UC1`, `rgb8`...
    pub encoding: &'a str,
    /// 0: multi-byte pixels are little-endian.
    pub is_bigendian: u8,
    /// Bytes per row.
    pub step: u32,
}

/// Splits seconds since the epoch into a ROS `builtin_interfaces/Time` (sec, nanosec).
/// Negative or out-of-range times clamp to the representable range instead of wrapping.
pub fn stamp(unix_time: f64) -> (i32, u32) {
    let ns = (unix_time * 1e9).round().clamp(0.0, i32::MAX as f64 * 1e9) as u64;
    ((ns / 1_000_000_000) as i32, (ns % 1_000_000_000) as u32)
}

/// Appends the CDR serialisation of an `Image` (encapsulation header included) to `out`.
pub fn encode_image(h: &ImageHeader<'_>, pixels: Pixels<'_>, out: &mut Vec<u8>) {
    let base = out.len() + CDR_LE.len();
    out.reserve(64 + h.frame_id.len() + h.encoding.len() + pixels.byte_len());
    out.extend_from_slice(&CDR_LE);
    let mut w = CdrWriter { out, base };
    w.u32(h.sec as u32);
    w.u32(h.nanosec);
    w.string(h.frame_id);
    w.u32(h.height);
    w.u32(h.width);
    w.string(h.encoding);
    w.out.push(h.is_bigendian);
    w.u32(h.step);
    w.u32(pixels.byte_len() as u32);
    match pixels {
        Pixels::U8(p) => w.out.extend_from_slice(p),
        Pixels::U16(p) => {
            let start = w.out.len();
            w.out.resize(start + 2 * p.len(), 0);
            for (d, v) in w.out[start..].chunks_exact_mut(2).zip(p) {
                d.copy_from_slice(&v.to_le_bytes());
            }
        }
    }
}

struct CdrWriter<'a> {
    out: &'a mut Vec<u8>,
    /// Index in `out` where alignment is counted from (just after the encapsulation header).
    base: usize,
}

impl CdrWriter<'_> {
    fn align(&mut self, n: usize) {
        while !(self.out.len() - self.base).is_multiple_of(n) {
            self.out.push(0);
        }
    }
    fn u32(&mut self, v: u32) {
        self.align(4);
        self.out.extend_from_slice(&v.to_le_bytes());
    }
    fn string(&mut self, s: &str) {
        self.u32(s.len() as u32 + 1);
        self.out.extend_from_slice(s.as_bytes());
        self.out.push(0);
    }
}

/// Parses a CDR `Image`; returns its header and pixel bytes (borrowed from `bytes`).
/// Errors are a one-line description of what is wrong and where (byte offset in the message).
pub fn decode_image(bytes: &[u8]) -> Result<(ImageHeader<'_>, &[u8]), String> {
    match bytes.get(..4) {
        Some(h) if h == CDR_LE => {}
        Some(&[0x00, 0x00, _, _]) => {
            return Err(
                "big-endian CDR is not supported, expected encapsulation 00 01 (CDR_LE)".into(),
            )
        }
        Some(h) => {
            return Err(format!(
                "encapsulation header {h:02x?} is not CDR, expected 00 01 00 00"
            ))
        }
        None => {
            return Err(format!(
                "{} bytes is too short for a CDR message",
                bytes.len()
            ))
        }
    }
    let mut r = CdrReader {
        buf: &bytes[4..],
        pos: 0,
    };
    let sec = r.u32("header.stamp.sec")? as i32;
    let nanosec = r.u32("header.stamp.nanosec")?;
    let frame_id = r.string("header.frame_id")?;
    let height = r.u32("height")?;
    let width = r.u32("width")?;
    let encoding = r.string("encoding")?;
    let is_bigendian = r.take(1, "is_bigendian")?[0];
    let step = r.u32("step")?;
    let n = r.u32("data length")? as usize;
    let data = r.take(n, "data")?;
    Ok((
        ImageHeader {
            sec,
            nanosec,
            frame_id,
            height,
            width,
            encoding,
            is_bigendian,
            step,
        },
        data,
    ))
}

struct CdrReader<'a> {
    buf: &'a [u8],
    pos: usize,
}

impl<'a> CdrReader<'a> {
    fn take(&mut self, n: usize, field: &str) -> Result<&'a [u8], String> {
        let end = self.pos.checked_add(n).filter(|&e| e <= self.buf.len());
        let Some(end) = end else {
            return Err(format!(
                "{field} at byte {} needs {n} bytes, the message ends at {}",
                self.pos + 4,
                self.buf.len() + 4
            ));
        };
        let s = &self.buf[self.pos..end];
        self.pos = end;
        Ok(s)
    }
    fn u32(&mut self, field: &str) -> Result<u32, String> {
        self.pos = self.pos.next_multiple_of(4);
        let b = self.take(4, field)?;
        Ok(u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
    }
    fn string(&mut self, field: &str) -> Result<&'a str, String> {
        let n = self.u32(field)? as usize;
        let at = self.pos + 4;
        let b = self.take(n, field)?;
        match b.split_last() {
            Some((0, s)) => {
                std::str::from_utf8(s).map_err(|_| format!("{field} at byte {at} is not UTF-8"))
            }
            _ => Err(format!(
                "{field} at byte {at} is not a NUL-terminated string"
            )),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stamp_splits_and_clamps() {
        assert_eq!(stamp(1.5), (1, 500_000_000));
        assert_eq!(stamp(-3.0), (0, 0));
        assert_eq!(stamp(1e12).0, i32::MAX);
    }

    #[test]
    fn decode_rejects_short_and_foreign_messages() {
        let h = ImageHeader {
            sec: 1,
            nanosec: 2,
            frame_id: "f",
            height: 1,
            width: 2,
            encoding: "mono8",
            is_bigendian: 0,
            step: 2,
        };
        let mut buf = Vec::new();
        encode_image(&h, Pixels::U8(&[7, 8]), &mut buf);
        let (back, data) = decode_image(&buf).unwrap();
        assert_eq!((back, data), (h, &[7u8, 8][..]));
        for cut in 0..buf.len() {
            assert!(decode_image(&buf[..cut]).is_err(), "cut at {cut}");
        }
        buf[0] = 7;
        assert!(decode_image(&buf).unwrap_err().contains("encapsulation"));
    }
}
