//! Replays a fakenect recording as fast as the frames can be read.

use crate::capture::Source;
use crate::error::Result;
use crate::pipeline::Frame;
use crate::recording::Recording;

/// Reads the frames of a [`Recording`] in order.
pub struct ReplaySource {
    recording: Recording,
    next: usize,
    with_rgb: bool,
    /// File bytes, reused frame after frame.
    scratch: Vec<u8>,
    /// Passes over the recording still to start after the current one.
    passes_left: u64,
    /// Pass number, and how far each pass shifts the times.
    pass: u64,
    period: f64,
}

impl ReplaySource {
    /// A source over `recording`; RGB frames are read only when `with_rgb` (the classifier's
    /// colour split and the RGB sinks use them; benchmarks of the depth path go without).
    pub fn new(recording: Recording, with_rgb: bool) -> Self {
        let f = recording.frames();
        let span = match (f.first(), f.last()) {
            (Some(a), Some(b)) => b.depth.unix_time - a.depth.unix_time,
            _ => 0.0,
        };
        // One pass lasts its span plus one mean frame interval (1/30 s for a single frame).
        let step = if f.len() > 1 {
            span / (f.len() - 1) as f64
        } else {
            1.0 / 30.0
        };
        let period = if (span + step).is_finite() && span + step > 0.0 {
            span + step
        } else {
            1.0 / 30.0
        };
        ReplaySource {
            recording,
            next: 0,
            with_rgb,
            scratch: Vec::new(),
            passes_left: 0,
            pass: 0,
            period,
        }
    }

    /// Plays the recording `passes` times in a row (soak tests: 100 000 frames from a short
    /// recording). Later passes carry times and timestamps shifted by whole passes, so pacing
    /// and device-timestamp pairing see one continuous (wrapping) stream.
    pub fn repeat(mut self, passes: u64) -> Self {
        self.passes_left = passes.saturating_sub(1);
        self
    }
}

impl Source for ReplaySource {
    fn next_frame(&mut self, frame: &mut Frame) -> Result<bool> {
        if self.next == self.recording.len() && self.passes_left > 0 {
            self.passes_left -= 1;
            self.pass += 1;
            self.next = 0;
        }
        let Some(meta) = self.recording.frames().get(self.next) else {
            return Ok(false);
        };
        let shift = self.pass as f64 * self.period;
        // The Kinect's timestamp counts a 60 MHz clock (2 000 000 ticks per frame at 30 fps) and
        // wraps every 71.6 s, as a long live run does.
        frame.device_ts = meta
            .depth
            .device_ts
            .wrapping_add((shift * 60e6) as u64 as u32);
        frame.unix_time = meta.depth.unix_time + shift;
        self.recording
            .read_depth_with(self.next, &mut self.scratch, &mut frame.depth)?;
        frame.has_rgb = self.with_rgb
            && self
                .recording
                .read_rgb_with(self.next, &mut self.scratch, &mut frame.rgb)?;
        self.next += 1;
        Ok(true)
    }

    fn len_hint(&self) -> Option<usize> {
        Some(self.recording.len() * (self.pass + self.passes_left + 1) as usize)
    }
}
