//! Frame sources: where raw depth (and RGB) comes from. [`replay`] reads fakenect recordings;
//! [`kinect`] captures from a live Kinect (or libfreenect's fakenect) through the [`freenect`]
//! binding, behind the same [`Source`] trait.

pub mod freenect;
pub mod kinect;
pub mod pace;
pub mod reconnect;
pub mod replay;

use crate::error::Result;
use crate::pipeline::Frame;

/// Something that produces frames, one at a time, into recycled buffers.
pub trait Source: Send {
    /// Fills `frame` (depth, RGB if any, timestamps) with the next frame; `Ok(false)` at the end.
    /// `frame.seq` is set by the pipeline.
    fn next_frame(&mut self, frame: &mut Frame) -> Result<bool>;

    /// Number of frames this source will produce, when known (progress bars).
    fn len_hint(&self) -> Option<usize> {
        None
    }
}
