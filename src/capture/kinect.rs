//! The live Kinect v1 [`Source`]: depth frames from libfreenect, each paired with the nearest RGB
//! frame by device timestamp, with the device's factory calibration.
//!
//! Under libfreenect's `fakenect` replay library the "device" is the recording in
//! `FAKENECT_PATH`, and its calibration is that recording's (as `umbra replay` reads it), so a
//! fakenect run labels exactly as a replay does.

use std::collections::VecDeque;
use std::path::Path;
use std::sync::atomic::AtomicBool;
use std::sync::Arc;
use std::time::Duration;

use crossbeam_channel::RecvTimeoutError;
use tracing::{info, warn};

use super::freenect::{library, Captured, DropCounters, Selector, Stream};
use super::Source;
use crate::calib::Calibration;
use crate::error::{Error, Result};
use crate::pipeline::Frame;
use crate::recording::{device_json, Recording, MAX_RGB_GAP_S};

/// Buffers per stream between the USB callbacks and the pipeline: about a quarter second at 30 fps.
const POOL: usize = 8;
/// RGB frames kept to pair with depth; the streams run at the same rate, so two suffice.
const RECENT_RGB: usize = 2;
/// The next RGB frame is waited for when it is due this soon after the depth frame (fraction of
/// a frame period, 3.3 ms at 30 fps) and would be nearer to it than the last one received. The
/// streams run at one rate with a fixed phase, so this costs latency only when that phase is
/// small, and then only until the frame arrives; under fakenect RGB follows depth by 2 ms, and
/// without the wait the colour split would see the previous RGB frame where a replay sees the
/// nearest.
const RGB_DUE_FRACTION: f64 = 0.1;
/// Until two RGB frames have arrived there is no rate to tell when the next is due: the first
/// depth frames wait this long for one.
const FIRST_RGB_WAIT: Duration = Duration::from_millis(20);
/// Longest wait for an RGB frame that is due: on a loaded machine it may arrive well after its
/// device time (5 ms was too short for fakenect on two busy cores, and the colour split then saw
/// the previous frame). Under a frame period, so the pipeline keeps pace; only this stage waits,
/// the USB thread goes on filling its buffers.
const MAX_RGB_WAIT_S: f64 = 0.02;

/// A live (or fakenect) Kinect v1.
pub struct KinectSource {
    stream: Stream,
    recent: VecDeque<Captured<u8>>,
    calibration: Calibration,
    calibration_origin: String,
    video_drops_reported: u64,
    stall_timeout: Duration,
}

/// Default for [`KinectSource::set_stall_timeout`].
pub const DEFAULT_STALL_TIMEOUT: Duration = Duration::from_secs(5);

impl KinectSource {
    /// Opens `which` and starts streaming; capture stops when `stop` is set (or the source is
    /// dropped). Fails with one line when libfreenect is missing or the device cannot be opened.
    pub fn open(which: Selector, stop: Arc<AtomicBool>) -> Result<Self> {
        let lib = library::load()?;
        // Under fakenect, check the recording before libfreenect sees it: fakenect exit()s on a
        // missing FAKENECT_PATH or file.
        let recording = if lib.fakenect {
            let path = std::env::var_os("FAKENECT_PATH").ok_or_else(|| {
                Error::Usage(format!("{} is libfreenect's fakenect replay library and FAKENECT_PATH is not set: set it to a recording folder", lib.name))
            })?;
            let rec = Recording::open(Path::new(&path))?;
            if let Some((line, name)) = rec.missing_accelerometer_file() {
                return Err(Error::input(
                    rec.dir().join("INDEX.txt"),
                    format!("line {line}"),
                    format!("names {name} which does not exist: fakenect stops the process on a missing file (umbra replay ignores it)"),
                ));
            }
            Some(rec)
        } else {
            None
        };
        let stream = Stream::start(which.clone(), POOL, stop)?;
        let (calibration, calibration_origin) = match (&recording, stream.info.zero_plane) {
            (Some(rec), _) => (
                *rec.calibration(),
                format!(
                    "fakenect recording {} ({:?})",
                    rec.dir().display(),
                    rec.calibration_source()
                ),
            ),
            (None, Some((z, const_shift))) => {
                let zp = device_json::ZeroPlane {
                    dcmos_emitter_distance: z.dcmos_emitter_dist.into(),
                    dcmos_rcmos_distance: z.dcmos_rcmos_dist.into(),
                    reference_distance: z.reference_distance.into(),
                    reference_pixel_size: z.reference_pixel_size.into(),
                };
                let origin = format!("{which} factory calibration");
                match device_json::from_zero_plane(&zp, Some(const_shift), Path::new(&origin)) {
                    Ok(c) => (c, origin),
                    Err(e) => {
                        warn!("{e}; using NYU Kinect v1 defaults");
                        (
                            Calibration::nyu_default(),
                            "NYU Kinect v1 defaults".to_string(),
                        )
                    }
                }
            }
            (None, None) => (
                Calibration::nyu_default(),
                "NYU Kinect v1 defaults (no registration data)".to_string(),
            ),
        };
        info!(device = %which, serials = ?stream.info.serials, calibration = %calibration_origin, "Kinect open");
        Ok(KinectSource {
            stream,
            recent: VecDeque::with_capacity(RECENT_RGB + 1),
            calibration,
            calibration_origin,
            video_drops_reported: 0,
            stall_timeout: DEFAULT_STALL_TIMEOUT,
        })
    }

    /// A device that delivers no depth frame for this long is reported as failed (so that a
    /// reconnecting caller reopens it) instead of being waited for forever.
    pub fn set_stall_timeout(&mut self, t: Duration) {
        self.stall_timeout = t;
    }

    /// The raw capture stream and the calibration, for clients that want every depth and RGB
    /// frame as delivered rather than depth frames paired with RGB (`umbra record`).
    pub fn into_stream(self) -> (Stream, Calibration, String) {
        (self.stream, self.calibration, self.calibration_origin)
    }

    /// The device's calibration and where it came from.
    pub fn calibration(&self) -> (&Calibration, &str) {
        (&self.calibration, &self.calibration_origin)
    }

    /// Depth and RGB frames dropped so far because the pipeline fell behind.
    pub fn dropped(&self) -> (u64, u64) {
        self.stream.dropped()
    }

    /// Depth and RGB drop counters that outlive the source (for the end-of-run summary).
    pub fn drop_counters(&self) -> DropCounters {
        self.stream.drop_counters()
    }

    /// Moves every RGB frame received so far into `recent`, recycling the oldest.
    fn take_rgb(&mut self) {
        while let Ok(rgb) = self.stream.video.try_recv() {
            self.keep_rgb(rgb);
        }
    }

    fn keep_rgb(&mut self, rgb: Captured<u8>) {
        self.recent.push_back(rgb);
        if self.recent.len() > RECENT_RGB {
            if let Some(old) = self.recent.pop_front() {
                let _ = self.stream.video_free.try_send(old.data);
            }
        }
    }

    /// Waits briefly for the RGB frame due just after the depth frame at `depth_ts`, when it will
    /// be a nearer pair than any received ([`RGB_DUE_FRACTION`]).
    fn wait_for_due_rgb(&mut self, depth_ts: u32) {
        let n = self.recent.len();
        if n < 2 {
            // No rate yet (the first frames of a stream): one short wait, once or twice.
            let newest_before = self
                .recent
                .back()
                .is_none_or(|r| (r.ts.wrapping_sub(depth_ts) as i32) < 0);
            if newest_before {
                if let Ok(rgb) = self.stream.video.recv_timeout(FIRST_RGB_WAIT) {
                    self.keep_rgb(rgb);
                }
            }
            return;
        }
        let (prev, newest) = (&self.recent[n - 2], &self.recent[n - 1]);
        if !rgb_due(prev.ts, newest.ts, depth_ts) {
            return;
        }
        let host_period = newest.unix_time - prev.unix_time;
        let wait = (0.6 * host_period).clamp(0.0, MAX_RGB_WAIT_S);
        if let Ok(rgb) = self
            .stream
            .video
            .recv_timeout(Duration::from_secs_f64(wait))
        {
            self.keep_rgb(rgb);
        }
    }
}

/// True when the RGB frame after `newest` (device timestamps; the one before it was `prev`) is
/// due within [`RGB_DUE_FRACTION`] of a period after the depth frame at `depth_ts`, and would be
/// nearer to it than `newest`.
fn rgb_due(prev: u32, newest: u32, depth_ts: u32) -> bool {
    let period = newest.wrapping_sub(prev) as i32;
    let ahead = newest.wrapping_sub(depth_ts) as i32;
    if period <= 0 || ahead >= 0 {
        return false; // no rate yet, or a frame at or after the depth frame is already here
    }
    let next = ahead + period; // the next frame's timestamp minus the depth frame's
    next >= 0 && f64::from(next) <= RGB_DUE_FRACTION * f64::from(period) && next < -ahead
}

/// Distance between two 32-bit device timestamps, across a wrap.
pub fn ts_distance(a: u32, b: u32) -> u32 {
    (a.wrapping_sub(b) as i32).unsigned_abs()
}

/// Index of the frame in `recent` nearest to `depth` by device timestamp, if any is close in host
/// time. Only frames already received count: waiting for a later one would delay every frame.
fn nearest_rgb(recent: &VecDeque<Captured<u8>>, depth_ts: u32, depth_time: f64) -> Option<usize> {
    recent
        .iter()
        .enumerate()
        .filter(|(_, r)| (r.unix_time - depth_time).abs() <= MAX_RGB_GAP_S)
        .min_by_key(|(_, r)| ts_distance(r.ts, depth_ts))
        .map(|(i, _)| i)
}

impl Source for KinectSource {
    fn next_frame(&mut self, frame: &mut Frame) -> Result<bool> {
        let mut depth = match self.stream.depth.recv_timeout(self.stall_timeout) {
            Ok(d) => d,
            // The capture thread ended: a device error, or the end of a fakenect recording.
            Err(RecvTimeoutError::Disconnected) => {
                return self.stream.take_failure().map_or(Ok(false), Err)
            }
            Err(RecvTimeoutError::Timeout) => {
                return Err(Error::Usage(format!(
                    "no depth frame for {:.1} s: the device stalled",
                    self.stall_timeout.as_secs_f64()
                )));
            }
        };
        frame.device_ts = depth.ts;
        frame.unix_time = depth.unix_time;
        frame.dropped_before = depth.dropped_before;
        frame.received = Some(depth.received);
        if frame.depth.len() == depth.data.len() {
            // Swap buffers instead of copying: the pool gets the frame's old one back.
            std::mem::swap(&mut frame.depth, &mut depth.data);
        } else {
            frame.depth.clear();
            frame.depth.extend_from_slice(&depth.data);
        }
        let _ = self.stream.depth_free.try_send(depth.data);
        if depth.dropped_before > 0 {
            warn!(
                dropped = depth.dropped_before,
                "pipeline fell behind: depth frames dropped"
            );
        }
        self.take_rgb();
        self.wait_for_due_rgb(frame.device_ts);
        frame.has_rgb = match nearest_rgb(&self.recent, frame.device_ts, frame.unix_time) {
            Some(i) => {
                let rgb = &self.recent[i].data;
                frame.rgb.resize(rgb.len(), 0);
                frame.rgb.copy_from_slice(rgb);
                true
            }
            None => false,
        };
        let (_, video_drops) = self.stream.dropped();
        if video_drops > self.video_drops_reported {
            frame.rgb_dropped_before = video_drops - self.video_drops_reported;
            warn!(
                dropped = frame.rgb_dropped_before,
                "pipeline fell behind: RGB frames dropped"
            );
            self.video_drops_reported = video_drops;
        }
        Ok(true)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rgb(ts: u32, t: f64) -> Captured<u8> {
        Captured {
            ts,
            unix_time: t,
            received: std::time::Instant::now(),
            dropped_before: 0,
            data: Vec::new(),
        }
    }

    #[test]
    fn distance_wraps() {
        assert_eq!(ts_distance(5, u32::MAX - 4), 10);
        assert_eq!(ts_distance(u32::MAX - 4, 5), 10);
        assert_eq!(ts_distance(100, 40), 60);
    }

    #[test]
    fn waits_only_for_an_rgb_frame_due_just_after_the_depth_frame() {
        // 30 fps on a 60 MHz clock: 2 000 000 ticks per frame. Timestamps relative to the depth
        // frame's, wrapped to 32 bits as the device's are.
        let p = 2_000_000i64;
        let due =
            |prev: i64, newest: i64, depth: i64| rgb_due(prev as u32, newest as u32, depth as u32);
        // RGB follows depth by 4 000 ticks (as under fakenect): the next one is worth the wait.
        assert!(due(4_000 - 2 * p, 4_000 - p, 0));
        // Due half a frame later: the one received is as near, no wait.
        assert!(!due(p / 2 - 2 * p, p / 2 - p, 0));
        // Already received one after the depth frame: no wait.
        assert!(!due(1_000 - p, 1_000, 0));
        // Across the 32-bit wrap.
        assert!(due(10 - 2 * p, 10 - p, 5));
        assert!(due(
            u32::MAX as i64 - 2 * p,
            u32::MAX as i64 - p,
            u32::MAX as i64 - 4_000
        ));
        // No rate yet (two frames with one timestamp).
        assert!(!due(7, 7, 100));
    }

    #[test]
    fn pairs_nearest_across_the_wrap_and_skips_stale() {
        let recent: VecDeque<_> = [rgb(u32::MAX - 1000, 10.0), rgb(2000, 10.03)].into();
        assert_eq!(nearest_rgb(&recent, 100, 10.0), Some(0));
        assert_eq!(nearest_rgb(&recent, 1900, 10.03), Some(1));
        assert_eq!(
            nearest_rgb(&recent, 1900, 11.0),
            None,
            "RGB from a second ago is not a pair"
        );
        assert_eq!(nearest_rgb(&VecDeque::new(), 0, 0.0), None);
    }
}
