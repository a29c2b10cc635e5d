//! Reads umbra MCAP segments back into frames, tolerating files that are still being written or
//! whose writer was killed.
//!
//! Records are walked with the `mcap` crate's sans-I/O `LinearReader` (chunks yielded whole,
//! start magic checked here) so that this module knows the byte offset where every complete
//! record ends. A chunk is decoded only once all its bytes are present and its CRC checks out,
//! so what a crash leaves at the end of a file (a prefix of the last record, or zeros after a
//! power cut) is never returned as data: it is reported as [`End::Torn`] with its offset, and
//! [`SegmentReader::poll`] resumes at that offset when called again (for `tail --follow`).
//! Anything else that does not parse is a SPEC §5 error naming the file and the byte offset.

use std::collections::HashMap;
use std::fs::File;
use std::io::{Read, Seek, SeekFrom};
use std::path::{Path, PathBuf};

use ::mcap::records::Record;
use ::mcap::sans_io::linear_reader::{LinearReadEvent, LinearReader, LinearReaderOptions};

use super::ros2::{self, ImageHeader};
use super::stats::FrameStats;
use super::topics;
use crate::error::{Error, Result};
use crate::labels::{HEIGHT, PIXELS, WIDTH};
use crate::pipeline::Frame;

/// Largest non-chunk record accepted; a larger length field means the file is not what it claims.
const RECORD_LIMIT: usize = 64 << 20;
/// Bytes read from the file per read call.
const READ_STEP: usize = 1 << 20;

/// A frame read back from a segment, with its stats message.
#[derive(Clone, Debug)]
pub struct Recorded {
    /// Depth, labels of both views, registered depth, RGB if it was written.
    pub frame: Frame,
    /// The `/umbra/frame_stats` message of the frame.
    pub stats: FrameStats,
}

/// How a pass over a segment ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum End {
    /// Summary, footer and closing magic read: the writer finished this segment.
    Complete,
    /// The file ends between two records without a summary: still being written, or its writer
    /// stopped without closing it. Every frame in it was returned.
    Open,
    /// The file ends inside a record: a write in progress or a crash's torn tail. Bytes from
    /// `offset` on (`tail` of them) were not returned.
    Torn {
        /// Where the incomplete record starts (the end of the last complete one).
        offset: u64,
        /// Bytes from there to the end of the file.
        tail: u64,
    },
}

/// The one-line warning for a torn tail.
pub fn torn_warning(path: &Path, offset: u64, tail: u64) -> String {
    format!("{}: byte {offset}: torn tail, the last {tail} bytes are an incomplete record (writer interrupted) and were skipped", path.display())
}

/// Reads all frames of one segment; returns them with how the file ended.
pub fn read_segment(path: &Path) -> Result<(Vec<Recorded>, End)> {
    let mut frames = Vec::new();
    let end = SegmentReader::new(path).poll(&mut |r| {
        frames.push(r);
        Ok(())
    })?;
    Ok((frames, end))
}

/// Which frame field a channel fills.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Slot {
    DepthRaw,
    DepthLabels,
    RegisteredRaw,
    RegisteredLabels,
    Rgb,
    Stats,
    /// A channel umbra does not write: skipped.
    Other,
}

impl Slot {
    fn of(topic: &str) -> Slot {
        match topic {
            topics::DEPTH_RAW => Slot::DepthRaw,
            topics::DEPTH_LABELS => Slot::DepthLabels,
            topics::REGISTERED_RAW => Slot::RegisteredRaw,
            topics::REGISTERED_LABELS => Slot::RegisteredLabels,
            topics::RGB_RAW => Slot::Rgb,
            topics::FRAME_STATS => Slot::Stats,
            _ => Slot::Other,
        }
    }

    /// Encoding, bytes per pixel and topic of an image slot.
    fn image(self) -> (&'static str, u32, &'static str) {
        match self {
            Slot::DepthRaw => ("16UC1", 2, topics::DEPTH_RAW),
            Slot::DepthLabels => ("mono8", 1, topics::DEPTH_LABELS),
            Slot::RegisteredRaw => ("16UC1", 2, topics::REGISTERED_RAW),
            Slot::RegisteredLabels => ("mono8", 1, topics::REGISTERED_LABELS),
            _ => ("rgb8", 3, topics::RGB_RAW),
        }
    }
}

/// A frame whose messages are arriving.
struct Partial {
    sequence: u32,
    frame: Frame,
    /// Which of the four image topics every frame has were seen.
    seen: [bool; 4],
}

/// Reads one segment incrementally: each [`poll`](Self::poll) returns the frames completed since
/// the last one.
pub struct SegmentReader {
    path: PathBuf,
    /// Where the next unread record starts (0 before the magic is checked).
    offset: u64,
    channels: HashMap<u16, Slot>,
    pending: Option<Partial>,
    complete: bool,
}

impl SegmentReader {
    /// A reader positioned at the start of `path` (nothing is read yet).
    pub fn new(path: &Path) -> Self {
        SegmentReader {
            path: path.to_path_buf(),
            offset: 0,
            channels: HashMap::new(),
            pending: None,
            complete: false,
        }
    }

    /// The segment's file.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Reads from where the last poll stopped to the current end of the file, calling `on_frame`
    /// for each complete frame (an error from it stops the poll and is returned).
    pub fn poll(&mut self, on_frame: &mut dyn FnMut(Recorded) -> Result<()>) -> Result<End> {
        if self.complete {
            return Ok(End::Complete);
        }
        let mut file =
            File::open(&self.path).map_err(|e| Error::io(&self.path, "opening segment", e))?;
        if self.offset == 0 {
            let mut magic = [0u8; 8];
            let n = read_full(&mut file, &mut magic)
                .map_err(|e| Error::io(&self.path, "reading", e))?;
            if magic[..n] != ::mcap::MAGIC[..n] {
                return Err(Error::input(
                    &self.path,
                    "byte 0",
                    "not an MCAP file: expected the magic bytes 89 4D 43 41 50 30 0D 0A",
                ));
            }
            if n < magic.len() {
                return Ok(if n == 0 {
                    End::Open
                } else {
                    End::Torn {
                        offset: 0,
                        tail: n as u64,
                    }
                });
            }
            self.offset = magic.len() as u64;
        }
        file.seek(SeekFrom::Start(self.offset))
            .map_err(|e| Error::io(&self.path, "reading", e))?;
        let mut reader = LinearReader::new_with_options(
            LinearReaderOptions::default()
                .with_skip_start_magic(true)
                .with_emit_chunks(true)
                .with_record_length_limit(RECORD_LIMIT),
        );
        let mut fed = self.offset;
        loop {
            match reader.next_event() {
                None => {
                    self.complete = true;
                    return Ok(End::Complete);
                }
                Some(Ok(LinearReadEvent::ReadRequest(need))) => {
                    let buf = reader.insert(need.min(READ_STEP));
                    let n = read_full(&mut file, buf)
                        .map_err(|e| Error::io(&self.path, "reading", e))?;
                    if n == 0 {
                        return Ok(if fed == self.offset {
                            End::Open
                        } else {
                            End::Torn {
                                offset: self.offset,
                                tail: fed - self.offset,
                            }
                        });
                    }
                    reader.notify_read(n);
                    fed += n as u64;
                }
                Some(Ok(LinearReadEvent::Record { opcode, data })) => {
                    let len = 9 + data.len() as u64;
                    if opcode == 0 {
                        // Opcode 0 is reserved: after a power cut, the end of a file can read
                        // back as zeros. Zeros to the end are a torn tail; anything else is damage.
                        return if zeros_from(&mut file, self.offset).unwrap_or(false) {
                            let size = file.metadata().map_or(fed, |m| m.len());
                            Ok(End::Torn {
                                offset: self.offset,
                                tail: size - self.offset,
                            })
                        } else {
                            Err(Error::input(
                                &self.path,
                                format!("byte {}", self.offset),
                                "record with opcode 0x00, which MCAP reserves: not a valid record",
                            ))
                        };
                    }
                    let offset = self.offset;
                    self.record(opcode, data, on_frame).map_err(|e| match e {
                        Problem::Bad(problem) => {
                            Error::input(&self.path, format!("byte {offset}"), problem)
                        }
                        Problem::Stop(e) => e,
                    })?;
                    self.offset += len;
                }
                Some(Err(e)) => {
                    return Err(Error::input(
                        &self.path,
                        format!("byte {}", self.offset),
                        format!("not a readable MCAP record: {e}"),
                    ));
                }
            }
        }
    }

    /// Handles one complete top-level record.
    fn record(
        &mut self,
        opcode: u8,
        data: &[u8],
        on_frame: &mut dyn FnMut(Recorded) -> Result<()>,
    ) -> Result<(), Problem> {
        match ::mcap::parse_record(opcode, data).map_err(|e| {
            Problem::Bad(format!(
                "record with opcode {opcode:#04x} does not parse: {e}"
            ))
        })? {
            Record::Chunk { header, data } => {
                // All records first: the chunk's CRC is checked at its end, and nothing of a
                // damaged chunk may be returned.
                let records = ::mcap::read::ChunkReader::new(header, &data)
                    .and_then(|r| r.collect::<Result<Vec<_>, _>>())
                    .map_err(|e| Problem::Bad(format!("chunk: {e}")))?;
                records
                    .into_iter()
                    .try_for_each(|r| self.inner(r, on_frame))
            }
            other => self.inner(other, on_frame),
        }
    }

    /// Handles a record from inside a chunk (or one written outside chunks).
    fn inner(
        &mut self,
        r: Record<'_>,
        on_frame: &mut dyn FnMut(Recorded) -> Result<()>,
    ) -> Result<(), Problem> {
        match r {
            Record::Channel(c) => {
                let slot = Slot::of(&c.topic);
                let want = if slot == Slot::Stats { "json" } else { "cdr" };
                if slot != Slot::Other && c.message_encoding != want {
                    return Err(Problem::Bad(format!(
                        "channel {} has message encoding {:?}, expected {want:?}",
                        c.topic, c.message_encoding
                    )));
                }
                self.channels.insert(c.id, slot);
                Ok(())
            }
            Record::Message { header, data } => {
                let Some(&slot) = self.channels.get(&header.channel_id) else {
                    return Err(Problem::Bad(format!(
                        "message {} on channel {} that was never declared",
                        header.sequence, header.channel_id
                    )));
                };
                self.message(slot, header.sequence, &data, on_frame)
            }
            _ => Ok(()),
        }
    }

    fn message(
        &mut self,
        slot: Slot,
        sequence: u32,
        data: &[u8],
        on_frame: &mut dyn FnMut(Recorded) -> Result<()>,
    ) -> Result<(), Problem> {
        if slot == Slot::Other {
            return Ok(());
        }
        // Messages of one frame share its sequence number; a new number starts a new frame (one
        // left incomplete by a foreign writer is dropped, never returned half-filled).
        if !matches!(&self.pending, Some(p) if p.sequence == sequence) {
            self.pending = Some(Partial {
                sequence,
                frame: Frame::default(),
                seen: [false; 4],
            });
        }
        let p = self.pending.as_mut().expect("set above");
        if slot == Slot::Stats {
            let stats: FrameStats = serde_json::from_slice(data).map_err(|e| {
                Problem::Bad(format!("{} message {sequence}: {e}", topics::FRAME_STATS))
            })?;
            if let Some(i) = p.seen.iter().position(|s| !s) {
                let topic = [
                    Slot::DepthRaw,
                    Slot::DepthLabels,
                    Slot::RegisteredRaw,
                    Slot::RegisteredLabels,
                ][i]
                    .image()
                    .2;
                return Err(Problem::Bad(format!(
                    "frame {}: stats message before any {topic} message",
                    stats.seq
                )));
            }
            let mut p = self.pending.take().expect("set above");
            p.frame.seq = stats.seq;
            p.frame.device_ts = stats.device_ts;
            p.frame.unix_time = stats.unix_time;
            return on_frame(Recorded {
                frame: p.frame,
                stats,
            })
            .map_err(Problem::Stop);
        }
        let (encoding, bpp, topic) = slot.image();
        let bad = |what: String| Problem::Bad(format!("{topic} message {sequence}: {what}"));
        let (h, pixels) = ros2::decode_image(data).map_err(bad)?;
        check_image(&h, pixels.len(), encoding, bpp).map_err(bad)?;
        let f = &mut p.frame;
        match slot {
            Slot::DepthRaw => unpack_u16(pixels, &mut f.depth),
            Slot::DepthLabels => f.labels.ir_labels.copy_from_slice(pixels),
            Slot::RegisteredRaw => unpack_u16(pixels, &mut f.labels.registered_mm),
            Slot::RegisteredLabels => f.labels.rgb_labels.copy_from_slice(pixels),
            _ => {
                f.rgb.copy_from_slice(pixels);
                f.has_rgb = true;
            }
        }
        if let Some(i) = [
            Slot::DepthRaw,
            Slot::DepthLabels,
            Slot::RegisteredRaw,
            Slot::RegisteredLabels,
        ]
        .iter()
        .position(|&s| s == slot)
        {
            p.seen[i] = true;
        }
        Ok(())
    }
}

/// Why handling a record stopped: the file is wrong, or the frame callback failed.
enum Problem {
    Bad(String),
    Stop(Error),
}

/// Checks an image is what umbra writes on that topic: 640×480, the encoding, packed rows.
fn check_image(h: &ImageHeader<'_>, len: usize, encoding: &str, bpp: u32) -> Result<(), String> {
    if (h.width, h.height) != (WIDTH as u32, HEIGHT as u32) {
        return Err(format!(
            "size {}x{} is wrong, expected {WIDTH}x{HEIGHT}",
            h.width, h.height
        ));
    }
    if h.encoding != encoding || h.is_bigendian != 0 {
        return Err(format!(
            "encoding {:?} (big-endian {}) is wrong, expected {encoding:?} little-endian",
            h.encoding, h.is_bigendian
        ));
    }
    if h.step != WIDTH as u32 * bpp || len != PIXELS * bpp as usize {
        return Err(format!(
            "step {} and {len} data bytes are wrong, expected {} and {}",
            h.step,
            WIDTH as u32 * bpp,
            PIXELS * bpp as usize
        ));
    }
    Ok(())
}

fn unpack_u16(bytes: &[u8], out: &mut [u16]) {
    for (o, b) in out.iter_mut().zip(bytes.chunks_exact(2)) {
        *o = u16::from_le_bytes([b[0], b[1]]);
    }
}

/// Reads until `buf` is full or the file ends; returns the bytes read.
fn read_full(file: &mut File, buf: &mut [u8]) -> std::io::Result<usize> {
    let mut n = 0;
    while n < buf.len() {
        match file.read(&mut buf[n..]) {
            Ok(0) => break,
            Ok(k) => n += k,
            Err(e) if e.kind() == std::io::ErrorKind::Interrupted => {}
            Err(e) => return Err(e),
        }
    }
    Ok(n)
}

/// Whether every byte of `file` from `offset` on is zero.
fn zeros_from(file: &mut File, offset: u64) -> std::io::Result<bool> {
    file.seek(SeekFrom::Start(offset))?;
    let mut buf = vec![0u8; READ_STEP];
    loop {
        let n = read_full(file, &mut buf)?;
        if n == 0 {
            return Ok(true);
        }
        if buf[..n].iter().any(|&b| b != 0) {
            return Ok(false);
        }
    }
}
