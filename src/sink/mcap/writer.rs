//! One open MCAP segment: its channels, and one frame written as one zstd chunk.
//!
//! Chunking: the `mcap` writer's automatic size-based chunking is off and [`SegmentWriter`]
//! closes a chunk after every frame instead (`Writer::flush`). A chunk is the unit a reader can
//! trust after a crash (it carries its length and CRC), so one chunk per frame means every frame
//! fully written before `kill -9` or a power cut is readable, `umbra tail --follow` sees each
//! frame as soon as it is written, and no chunk ever holds half a frame. One frame is about 2 MB
//! before compression (4 images), well within a good zstd window, so compression loses little.
//!
//! Seeking is disabled: each chunk is compressed in memory and appended whole, so the file only
//! ever grows by complete records (a crash can only leave a prefix of the last record), and a
//! reader following the file never sees a chunk header whose lengths are still placeholders.

use std::collections::BTreeMap;
use std::fs::File;
use std::io::{BufWriter, Seek, SeekFrom, Write};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

use ::mcap::records::MessageHeader;
use ::mcap::{Compression, McapError, WriteOptions};

use super::ros2::{self, ImageHeader, Pixels, IMAGE_DEFINITION, IMAGE_TYPE};
use super::stats::{self, FrameStats, STATS_TYPE};
use super::topics;
use crate::labels::{HEIGHT, WIDTH};
use crate::pipeline::Frame;

/// Optical frame of the IR (depth) camera, for the unregistered depth topics.
pub const DEPTH_FRAME_ID: &str = "kinect_depth_optical_frame";
/// Optical frame of the RGB camera, for the registered depth and RGB topics.
pub const RGB_FRAME_ID: &str = "kinect_rgb_optical_frame";

/// A failed write: what was being done and the I/O or MCAP error.
#[derive(Debug)]
pub struct WriteError {
    /// The segment file.
    pub path: PathBuf,
    /// The underlying problem, one line.
    pub message: String,
}

impl WriteError {
    fn new(path: &Path, what: &str, e: impl std::fmt::Display) -> Self {
        WriteError {
            path: path.to_path_buf(),
            message: format!("{what}: {e}"),
        }
    }
}

/// Settings a segment needs when it is opened.
#[derive(Clone, Debug)]
pub struct SegmentSettings {
    /// zstd level (1 fastest; 0 = zstd's default, 3).
    pub zstd_level: u32,
    /// Write `/kinect/rgb/image_raw` for frames that have RGB.
    pub write_rgb: bool,
    /// Declare `/umbra/foreground_mask` (masks come from [`SegmentWriter::write_mask`]).
    pub write_foreground: bool,
    /// Flush the segment to the disk itself (`fdatasync`) at most this often; `None` leaves it
    /// to the kernel. After `kill -9` the page cache keeps every complete chunk anyway; this
    /// bounds what a power cut can take.
    pub sync_interval: Option<Duration>,
}

/// One open segment file.
pub struct SegmentWriter {
    path: PathBuf,
    writer: ::mcap::Writer<BufWriter<CountingFile>>,
    /// Bytes handed to the file so far (shared with the `CountingFile` inside the writer).
    written: Arc<AtomicU64>,
    /// File length after the last complete frame: where a failed write is cut back to.
    good_len: u64,
    opened: Instant,
    channels: Channels,
    write_rgb: bool,
    /// Serialisation buffer, reused for every message.
    buf: Vec<u8>,
    frames: u64,
    /// Flushes the file to the disk in the background, so the writer never waits for it.
    sync: Option<Syncer>,
}

/// A thread that `fdatasync`s a segment when asked, at most once per interval. `fdatasync` can
/// take tens of milliseconds; on the writer thread that would be the frame latency's p99.
struct Syncer {
    every: Duration,
    last: Instant,
    ask: Option<crossbeam_channel::Sender<()>>,
    /// The first error of a background sync, reported on the next frame written.
    failed: Arc<std::sync::Mutex<Option<std::io::Error>>>,
    thread: Option<std::thread::JoinHandle<File>>,
}

impl Syncer {
    fn start(file: File, every: Duration) -> std::io::Result<Syncer> {
        let (ask, asked) = crossbeam_channel::bounded::<()>(1);
        let failed = Arc::new(std::sync::Mutex::new(None));
        let f = failed.clone();
        let thread = std::thread::Builder::new()
            .name("mcap-sync".into())
            .spawn(move || {
                for () in asked {
                    if let Err(e) = file.sync_data() {
                        f.lock().unwrap_or_else(|p| p.into_inner()).get_or_insert(e);
                    }
                }
                file
            })?;
        Ok(Syncer {
            every,
            last: Instant::now(),
            ask: Some(ask),
            failed,
            thread: Some(thread),
        })
    }

    /// Asks for a sync if the interval has passed; returns an earlier sync's failure.
    fn tick(&mut self) -> std::io::Result<()> {
        if let Some(e) = self.failed.lock().unwrap_or_else(|p| p.into_inner()).take() {
            return Err(e);
        }
        if self.last.elapsed() >= self.every {
            self.last = Instant::now();
            // A sync still running covers this request too.
            if let Some(ask) = &self.ask {
                let _ = ask.try_send(());
            }
        }
        Ok(())
    }

    /// Stops the thread and syncs once more, in the caller's thread.
    fn finish(mut self) -> std::io::Result<()> {
        self.ask = None;
        let file = self.thread.take().and_then(|t| t.join().ok());
        if let Some(e) = self.failed.lock().unwrap_or_else(|p| p.into_inner()).take() {
            return Err(e);
        }
        file.map_or(Ok(()), |f| f.sync_data())
    }
}

impl Drop for Syncer {
    fn drop(&mut self) {
        self.ask = None;
        if let Some(t) = self.thread.take() {
            let _ = t.join();
        }
    }
}

struct Channels {
    depth_raw: u16,
    depth_labels: u16,
    reg_raw: u16,
    reg_labels: u16,
    rgb: u16,
    stats: u16,
    foreground: Option<u16>,
}

impl SegmentWriter {
    /// Creates `path` (which must not exist) and writes the MCAP header, schemas and channels.
    pub fn create(path: &Path, settings: &SegmentSettings) -> Result<Self, WriteError> {
        let file = File::options()
            .write(true)
            .create_new(true)
            .open(path)
            .map_err(|e| WriteError::new(path, "creating segment", e))?;
        let sync = match settings.sync_interval {
            Some(every) => {
                let f = file
                    .try_clone()
                    .map_err(|e| WriteError::new(path, "opening segment", e))?;
                Some(
                    Syncer::start(f, every)
                        .map_err(|e| WriteError::new(path, "starting the sync thread", e))?,
                )
            }
            None => None,
        };
        let written = Arc::new(AtomicU64::new(0));
        let sink = BufWriter::with_capacity(
            1 << 16,
            CountingFile {
                file,
                written: written.clone(),
            },
        );
        let opts = WriteOptions::new()
            .profile("ros2")
            .library(format!(
                "umbra {} (mcap-rs {})",
                env!("CARGO_PKG_VERSION"),
                ::mcap::VERSION
            ))
            .compression(Some(Compression::Zstd))
            .compression_level(settings.zstd_level)
            // One compression thread per chunk would compete with the classifier for the cores.
            .compression_threads(0)
            .chunk_size(None)
            .disable_seeking(true);
        let fail = |what: &str, e: McapError| WriteError::new(path, what, e);
        let mut writer = opts
            .create(sink)
            .map_err(|e| fail("writing MCAP header", e))?;
        let image = writer
            .add_schema(IMAGE_TYPE, "ros2msg", IMAGE_DEFINITION.as_bytes())
            .map_err(|e| fail("adding schema", e))?;
        let json = writer
            .add_schema(STATS_TYPE, "jsonschema", stats::json_schema().as_bytes())
            .map_err(|e| fail("adding schema", e))?;
        let none = BTreeMap::new();
        let mut add = |schema: u16, topic: &str, encoding: &str| {
            writer
                .add_channel(schema, topic, encoding, &none)
                .map_err(|e| fail("adding channel", e))
        };
        let channels = Channels {
            depth_raw: add(image, topics::DEPTH_RAW, "cdr")?,
            depth_labels: add(image, topics::DEPTH_LABELS, "cdr")?,
            reg_raw: add(image, topics::REGISTERED_RAW, "cdr")?,
            reg_labels: add(image, topics::REGISTERED_LABELS, "cdr")?,
            rgb: add(image, topics::RGB_RAW, "cdr")?,
            stats: add(json, topics::FRAME_STATS, "json")?,
            foreground: if settings.write_foreground {
                Some(add(image, topics::FOREGROUND_MASK, "cdr")?)
            } else {
                None
            },
        };
        // Header, schemas and channels reach the disk now, so a reader sees a valid file at once.
        writer.flush().map_err(|e| fail("writing MCAP header", e))?;
        let good_len = written.load(Ordering::Relaxed);
        Ok(SegmentWriter {
            path: path.to_path_buf(),
            writer,
            written,
            good_len,
            opened: Instant::now(),
            channels,
            write_rgb: settings.write_rgb,
            buf: Vec::new(),
            frames: 0,
            sync,
        })
    }

    /// The segment's file.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Bytes written to the file so far.
    pub fn len(&self) -> u64 {
        self.written.load(Ordering::Relaxed)
    }

    /// Whether no frame has been written yet.
    pub fn is_empty(&self) -> bool {
        self.frames == 0
    }

    /// When the segment was opened.
    pub fn opened(&self) -> Instant {
        self.opened
    }

    /// Writes a foreground mask (RGB view, `mono8`, 255 = foreground) of frame `seq` taken at
    /// `unix_time`, in a chunk of its own. Nothing is written if the segment was opened without
    /// the foreground channel.
    pub fn write_mask(&mut self, seq: u64, unix_time: f64, mask: &[u8]) -> Result<(), WriteError> {
        let Some(channel) = self.channels.foreground else {
            return Ok(());
        };
        let (sec, nanosec) = ros2::stamp(unix_time);
        let time = u64::from(sec as u32) * 1_000_000_000 + u64::from(nanosec);
        let w = WIDTH as u32;
        let h = ImageHeader {
            sec,
            nanosec,
            frame_id: RGB_FRAME_ID,
            height: HEIGHT as u32,
            width: w,
            encoding: "mono8",
            is_bigendian: 0,
            step: w,
        };
        self.buf.clear();
        ros2::encode_image(&h, Pixels::U8(mask), &mut self.buf);
        let header = MessageHeader {
            channel_id: channel,
            sequence: seq as u32,
            log_time: time,
            publish_time: time,
        };
        let result = self
            .writer
            .write_to_known_channel(&header, &self.buf)
            .and_then(|()| self.end_chunk());
        result.map_err(|e| {
            WriteError::new(
                &self.path,
                &format!("writing the foreground mask of frame {seq}"),
                e,
            )
        })
    }

    /// Closes the chunk (the unit a reader trusts after a crash), asks for a background sync when
    /// due, and remembers the file length as the last good one.
    fn end_chunk(&mut self) -> Result<(), McapError> {
        self.writer.flush()?;
        if let Some(sync) = &mut self.sync {
            sync.tick()?;
        }
        self.good_len = self.len();
        Ok(())
    }

    /// Writes one frame's messages and closes the chunk, so the frame is on disk (in the page
    /// cache) and readable when this returns.
    pub fn write_frame(&mut self, frame: &Frame, stats: &FrameStats) -> Result<(), WriteError> {
        let (sec, nanosec) = ros2::stamp(frame.unix_time);
        let time = u64::from(sec as u32) * 1_000_000_000 + u64::from(nanosec);
        let w = WIDTH as u32;
        let image = |frame_id, encoding, bytes_pp: u32| ImageHeader {
            sec,
            nanosec,
            frame_id,
            height: HEIGHT as u32,
            width: w,
            encoding,
            is_bigendian: 0,
            step: w * bytes_pp,
        };
        let c = &self.channels;
        let mut messages: Vec<(u16, ImageHeader<'_>, Pixels<'_>)> = vec![
            (
                c.depth_raw,
                image(DEPTH_FRAME_ID, "16UC1", 2),
                Pixels::U16(&frame.depth),
            ),
            (
                c.depth_labels,
                image(DEPTH_FRAME_ID, "mono8", 1),
                Pixels::U8(&frame.labels.ir_labels),
            ),
            (
                c.reg_raw,
                image(RGB_FRAME_ID, "16UC1", 2),
                Pixels::U16(&frame.labels.registered_mm),
            ),
            (
                c.reg_labels,
                image(RGB_FRAME_ID, "mono8", 1),
                Pixels::U8(&frame.labels.rgb_labels),
            ),
        ];
        if self.write_rgb && frame.has_rgb {
            messages.push((
                c.rgb,
                image(RGB_FRAME_ID, "rgb8", 3),
                Pixels::U8(&frame.rgb),
            ));
        }
        // MCAP's per-channel sequence is 32-bit; the full seq is in the stats message.
        let header = |channel_id| MessageHeader {
            channel_id,
            sequence: frame.seq as u32,
            log_time: time,
            publish_time: time,
        };
        let result = (|| -> Result<(), McapError> {
            for (channel, h, pixels) in &messages {
                self.buf.clear();
                ros2::encode_image(h, *pixels, &mut self.buf);
                self.writer
                    .write_to_known_channel(&header(*channel), &self.buf)?;
            }
            self.buf.clear();
            serde_json::to_writer(&mut self.buf, stats).expect("stats serialise to JSON");
            self.writer
                .write_to_known_channel(&header(self.channels.stats), &self.buf)?;
            self.end_chunk()
        })();
        result
            .map_err(|e| WriteError::new(&self.path, &format!("writing frame {}", frame.seq), e))?;
        self.frames += 1;
        Ok(())
    }

    /// Writes the summary section and footer and closes the file. On failure the segment is
    /// [abandoned](Self::abandon).
    pub fn finish(mut self) -> Result<PathBuf, WriteError> {
        let result = self.writer.finish().and_then(|_| {
            self.sync
                .take()
                .map_or(Ok(()), |s| s.finish().map_err(McapError::from))
        });
        match result {
            Ok(()) => Ok(self.path),
            Err(e) => {
                let err = WriteError::new(&self.path, "writing the segment summary", e);
                self.abandon();
                Err(err)
            }
        }
    }

    /// Closes the file after a failed write and cuts it back to its last complete frame, so it
    /// ends on a record boundary instead of a torn chunk. Best effort: on a full disk shrinking
    /// works; where the folder has vanished nothing does, and readers report the torn tail.
    pub fn abandon(self) {
        let SegmentWriter {
            path,
            writer,
            good_len,
            ..
        } = self;
        // Dropping the writer flushes what its buffer still holds: cut only after that.
        drop(writer);
        if let Ok(f) = File::options().write(true).open(&path) {
            let _ = f.set_len(good_len);
        }
    }
}

/// The segment file, counting the bytes written through it (the segment's size for rotation,
/// without a `stat` per frame).
struct CountingFile {
    file: File,
    written: Arc<AtomicU64>,
}

impl Write for CountingFile {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        let n = self.file.write(buf)?;
        self.written.fetch_add(n as u64, Ordering::Relaxed);
        Ok(n)
    }
    fn flush(&mut self) -> std::io::Result<()> {
        self.file.flush()
    }
}

impl Seek for CountingFile {
    // Never called with seeking disabled; forwarded so the type satisfies `mcap::Writer`'s bound.
    fn seek(&mut self, pos: SeekFrom) -> std::io::Result<u64> {
        self.file.seek(pos)
    }
}
