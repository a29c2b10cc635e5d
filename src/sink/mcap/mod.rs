//! MCAP output: labelled frames as ROS 2 `sensor_msgs/msg/Image` messages (CDR) plus a JSON
//! stats topic, in size- and age-rotated segments that Foxglove and `ros2 bag` open as they are,
//! and that [`read`] (and so `umbra tail`) reads back while they are being written.
//!
//! Layout: [`ros2`] is the wire format, [`stats`] the JSON message, [`segment`] file names and
//! the size cap, [`writer`] one open segment, [`read`] the crash-tolerant reader; this module is
//! the [`McapSink`] that ties them together and survives a full or unwritable disk.

pub mod read;
pub mod ros2;
pub mod segment;
pub mod stats;
pub mod writer;

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant, SystemTime};

use tracing::{info, warn};

use crate::error::{Error, Result};
use crate::pipeline::Frame;
use crate::sink::Sink;
use stats::FrameStats;
use writer::{SegmentSettings, SegmentWriter};

/// Topic names.
pub mod topics {
    /// Raw 11-bit depth, IR view (`16UC1`).
    pub const DEPTH_RAW: &str = "/kinect/depth/image_raw";
    /// Labels in the IR view (`mono8`, SPEC §2 codes).
    pub const DEPTH_LABELS: &str = "/kinect/depth/shadow_labels";
    /// Depth registered to the RGB view, millimetres (`16UC1`, 0 = none).
    pub const REGISTERED_RAW: &str = "/kinect/depth_registered/image_raw";
    /// Labels in the RGB view (`mono8`).
    pub const REGISTERED_LABELS: &str = "/kinect/depth_registered/shadow_labels";
    /// The colour image (`rgb8`), when enabled and present.
    pub const RGB_RAW: &str = "/kinect/rgb/image_raw";
    /// Per-frame metadata and class counts (JSON).
    pub const FRAME_STATS: &str = "/umbra/frame_stats";
    /// Foreground masks (`mono8`, RGB view, 255 = foreground), at a configured rate.
    pub const FOREGROUND_MASK: &str = "/umbra/foreground_mask";
}

/// How [`McapSink`] writes and rotates segments.
#[derive(Clone, Debug)]
pub struct McapOptions {
    /// Start a new segment once the current one reaches this many bytes (checked after each
    /// frame, so a segment overshoots by less than one frame).
    pub segment_bytes: u64,
    /// Start a new segment once the current one is this old.
    pub segment_age: Duration,
    /// Delete the oldest `umbra-*.mcap` of the folder while their total exceeds this many bytes
    /// (checked whenever a segment is opened; the open segment is never deleted).
    pub total_cap_bytes: u64,
    /// Also write `/kinect/rgb/image_raw` for frames that carry RGB.
    pub write_rgb: bool,
    /// Declare `/umbra/foreground_mask` for [`McapSink::write_mask`].
    pub write_foreground: bool,
    /// zstd level of the chunks (1 is the fastest; higher buys a little size for much CPU).
    pub zstd_level: u32,
    /// After a write failure, wait this long before trying to open a new segment (frames in
    /// between are counted as lost), so a full disk is not hammered 30 times a second.
    pub retry_interval: Duration,
    /// `fdatasync` the open segment at most this often (`None`: leave it to the kernel).
    pub sync_interval: Option<Duration>,
}

impl Default for McapOptions {
    fn default() -> Self {
        McapOptions {
            segment_bytes: 512 << 20,
            segment_age: Duration::from_secs(600),
            total_cap_bytes: 20 << 30,
            write_rgb: false,
            write_foreground: false,
            zstd_level: 1,
            retry_interval: Duration::from_secs(1),
            sync_interval: Some(Duration::from_secs(1)),
        }
    }
}

/// Counters of an [`McapSink`], readable from any thread (status lines, tests).
#[derive(Debug, Default)]
pub struct McapCounters {
    /// Frames written completely.
    pub frames_written: AtomicU64,
    /// Frames that could not be written (disk full, folder gone...).
    pub frames_lost: AtomicU64,
    /// Bursts of failures: each began with a warning in the log.
    pub failure_bursts: AtomicU64,
    /// Segments opened.
    pub segments_opened: AtomicU64,
    /// Segments deleted by the size cap.
    pub segments_deleted: AtomicU64,
    /// Foreground masks written.
    pub masks_written: AtomicU64,
    /// Foreground masks that could not be written.
    pub masks_lost: AtomicU64,
}

impl McapCounters {
    fn add(c: &AtomicU64, n: u64) {
        c.fetch_add(n, Ordering::Relaxed);
    }
}

/// Writes frames into rotating MCAP segments in a folder. Write failures never stop the
/// pipeline: the frame is counted as lost, the first failure of a burst is logged, and writing
/// resumes in a new segment once it works again.
pub struct McapSink {
    dir: PathBuf,
    opts: McapOptions,
    current: Option<SegmentWriter>,
    /// Index `n` of the next segment name.
    next_index: u64,
    counters: Arc<McapCounters>,
    /// Set while failing: when the burst began and when to retry.
    failing_since: Option<Instant>,
    retry_at: Option<Instant>,
}

impl McapSink {
    /// A sink writing segments into `dir` (created if missing). Nothing is written until the
    /// first frame arrives; the first segment is named after that moment.
    pub fn create(dir: &Path, opts: McapOptions) -> Result<Self> {
        if dir.exists() && !dir.is_dir() {
            return Err(Error::input(
                dir,
                "",
                "exists and is not a folder: MCAP output needs a folder for its segments",
            ));
        }
        std::fs::create_dir_all(dir).map_err(|e| Error::io(dir, "creating output folder", e))?;
        if opts.segment_bytes == 0 || opts.segment_age.is_zero() {
            return Err(Error::Usage(
                "MCAP segment size and age limits must be positive".into(),
            ));
        }
        Ok(McapSink {
            dir: dir.to_path_buf(),
            opts,
            current: None,
            next_index: 0,
            counters: Arc::default(),
            failing_since: None,
            retry_at: None,
        })
    }

    /// Shared counters (frames written and lost, segments opened and deleted).
    pub fn counters(&self) -> Arc<McapCounters> {
        self.counters.clone()
    }

    /// The segment being written, if any.
    pub fn current_segment(&self) -> Option<&Path> {
        self.current.as_ref().map(|s| s.path())
    }

    /// Writes `frame` with the given latency and drop count in its stats message. Never fails:
    /// a frame that cannot be written is counted in [`McapCounters::frames_lost`].
    pub fn write_with(&mut self, frame: &Frame, latency_ms: f64, dropped_before: u64) {
        if self.retry_at.is_some_and(|t| Instant::now() < t) {
            McapCounters::add(&self.counters.frames_lost, 1);
            return;
        }
        if self
            .current
            .as_ref()
            .is_some_and(|s| s.opened().elapsed() >= self.opts.segment_age)
        {
            self.close_current();
        }
        let stats = FrameStats::of(frame, latency_ms, dropped_before);
        let result = match self.segment() {
            Ok(seg) => seg.write_frame(frame, &stats),
            Err(e) => Err(e),
        };
        match result {
            Ok(()) => {
                McapCounters::add(&self.counters.frames_written, 1);
                if let Some(since) = self.failing_since.take() {
                    let lost = self.counters.frames_lost.load(Ordering::Relaxed);
                    info!(after = ?since.elapsed(), lost_total = lost, "MCAP writing works again");
                }
                self.retry_at = None;
                if self
                    .current
                    .as_ref()
                    .is_some_and(|s| s.len() >= self.opts.segment_bytes)
                {
                    self.close_current();
                }
            }
            Err(e) => {
                McapCounters::add(&self.counters.frames_lost, 1);
                self.failed(&e);
            }
        }
    }

    /// Writes a foreground mask of frame `seq` into the open segment. Masks follow their frames,
    /// so with no segment open (a write failure in progress) the mask is skipped; a failure here
    /// is handled like a frame's.
    pub fn write_mask(&mut self, seq: u64, unix_time: f64, mask: &[u8]) {
        let Some(seg) = self.current.as_mut() else {
            McapCounters::add(&self.counters.masks_lost, 1);
            return;
        };
        match seg.write_mask(seq, unix_time, mask) {
            Ok(()) => McapCounters::add(&self.counters.masks_written, 1),
            Err(e) => {
                McapCounters::add(&self.counters.masks_lost, 1);
                self.failed(&e);
            }
        }
    }

    /// After a failed write: cut the segment back to its last complete record, say so once per
    /// burst, and wait `retry_interval` before trying a new segment.
    fn failed(&mut self, e: &writer::WriteError) {
        if let Some(seg) = self.current.take() {
            seg.abandon();
        }
        if self.failing_since.is_none() {
            self.failing_since = Some(Instant::now());
            McapCounters::add(&self.counters.failure_bursts, 1);
            warn!(file = %e.path.display(), "MCAP write failed, frames are dropped until it works again: {}", e.message);
        }
        self.retry_at = Some(Instant::now() + self.opts.retry_interval);
    }

    /// The open segment, opening a new one (and applying the size cap) if there is none.
    fn segment(&mut self) -> Result<&mut SegmentWriter, writer::WriteError> {
        if self.current.is_none() {
            let settings = SegmentSettings {
                zstd_level: self.opts.zstd_level,
                write_rgb: self.opts.write_rgb,
                write_foreground: self.opts.write_foreground,
                sync_interval: self.opts.sync_interval,
            };
            let mut path;
            loop {
                path = self
                    .dir
                    .join(segment::segment_name(SystemTime::now(), self.next_index));
                self.next_index += 1;
                // A name taken by an earlier run in the same second: take the next index.
                if !path.exists() {
                    break;
                }
            }
            let seg = match SegmentWriter::create(&path, &settings) {
                Ok(seg) => seg,
                Err(e) => {
                    // A file whose header could not be written is of no use to anyone.
                    let _ = std::fs::remove_file(&path);
                    return Err(e);
                }
            };
            McapCounters::add(&self.counters.segments_opened, 1);
            info!(file = %path.display(), "MCAP segment opened");
            match segment::enforce_cap(&self.dir, self.opts.total_cap_bytes, Some(&path)) {
                Ok(deleted) => {
                    for d in &deleted {
                        info!(file = %d.display(), "MCAP segment deleted (output size cap)");
                    }
                    McapCounters::add(&self.counters.segments_deleted, deleted.len() as u64);
                }
                Err(e) => warn!("{e}"),
            }
            self.current = Some(seg);
        }
        Ok(self.current.as_mut().expect("opened above"))
    }

    /// Finishes the open segment (summary, footer). A failure is logged and the segment kept
    /// as far as it is readable.
    fn close_current(&mut self) {
        if let Some(seg) = self.current.take() {
            match seg.finish() {
                Ok(path) => info!(file = %path.display(), "MCAP segment closed"),
                Err(e) => {
                    warn!(file = %e.path.display(), "closing MCAP segment failed: {}", e.message)
                }
            }
        }
    }
}

impl Sink for McapSink {
    /// Latency runs from the frame's `received` instant (the USB callback for live capture) to
    /// now; without one, from its `unix_time`. A frame marked as a discontinuity (the device was
    /// lost and reopened) starts a new segment.
    fn write(&mut self, frame: &Frame) -> Result<()> {
        let latency_ms = match frame.received {
            Some(r) => r.elapsed().as_secs_f64() * 1e3,
            None => {
                let now = std::time::SystemTime::now()
                    .duration_since(std::time::UNIX_EPOCH)
                    .map_or(0.0, |d| d.as_secs_f64());
                ((now - frame.unix_time) * 1e3).max(0.0)
            }
        };
        if frame.discontinuity {
            self.close_current();
        }
        self.write_with(frame, latency_ms, frame.dropped_before);
        Ok(())
    }

    /// Closes the open segment with its summary. A failure here is returned (the run is over,
    /// and the last segment then lacks its summary, though every frame in it stays readable).
    fn finish(&mut self) -> Result<()> {
        if let Some(seg) = self.current.take() {
            let path = seg.finish().map_err(|e| Error::Io {
                path: e.path,
                action: "closing MCAP segment",
                source: std::io::Error::other(e.message),
            })?;
            info!(file = %path.display(), "MCAP segment closed");
        }
        Ok(())
    }
}

impl Drop for McapSink {
    fn drop(&mut self) {
        self.close_current();
    }
}
