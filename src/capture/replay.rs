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
}

impl ReplaySource {
    /// A source over `recording`; RGB frames are read only when `with_rgb` (a sink needs them).
    pub fn new(recording: Recording, with_rgb: bool) -> Self {
        ReplaySource { recording, next: 0, with_rgb, scratch: Vec::new() }
    }
}

impl Source for ReplaySource {
    fn next_frame(&mut self, frame: &mut Frame) -> Result<bool> {
        let Some(meta) = self.recording.frames().get(self.next) else { return Ok(false) };
        frame.device_ts = meta.depth.device_ts;
        frame.unix_time = meta.depth.unix_time;
        self.recording.read_depth_with(self.next, &mut self.scratch, &mut frame.depth)?;
        frame.has_rgb = self.with_rgb && self.recording.read_rgb_with(self.next, &mut self.scratch, &mut frame.rgb)?;
        self.next += 1;
        Ok(true)
    }

    fn len_hint(&self) -> Option<usize> {
        Some(self.recording.len())
    }
}
