//! A [`Source`] that survives losing its device: when the inner source fails (unplugged Kinect,
//! libusb error, a stall), it is dropped and reopened with exponential backoff until it works
//! again or a stop is requested. The first frame after a reopen carries
//! [`Frame::discontinuity`], so segmenting sinks start a new segment there.

use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

use tracing::{info, warn};

use super::Source;
use crate::error::Result;
use crate::pipeline::Frame;

/// Waits between attempts to reopen a lost device.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Backoff {
    /// Wait before the first attempt.
    pub initial: Duration,
    /// The wait doubles after each failed attempt up to this.
    pub max: Duration,
}

impl Default for Backoff {
    fn default() -> Self {
        Backoff {
            initial: Duration::from_millis(500),
            max: Duration::from_secs(30),
        }
    }
}

impl Backoff {
    /// The wait before attempt `n` (0-based).
    pub fn delay(&self, n: u32) -> Duration {
        self.initial.saturating_mul(1u32 << n.min(20)).min(self.max)
    }
}

/// Opens a source; called again after each failure.
pub type Opener = Box<dyn FnMut() -> Result<Box<dyn Source>> + Send>;

/// Wraps an [`Opener`]: reopens its source whenever it fails, until `stop` is set.
pub struct Reconnecting {
    open: Opener,
    current: Option<Box<dyn Source>>,
    backoff: Backoff,
    stop: Arc<AtomicBool>,
    reconnects: Arc<AtomicU64>,
    /// Set when the next delivered frame follows a reopen.
    after_gap: bool,
}

impl Reconnecting {
    /// Wraps an already opened `first` source (so that a device missing at start is still an
    /// immediate error for the caller); `open` makes the next ones.
    pub fn new(
        first: Box<dyn Source>,
        open: Opener,
        backoff: Backoff,
        stop: Arc<AtomicBool>,
    ) -> Self {
        Reconnecting {
            open,
            current: Some(first),
            backoff,
            stop,
            reconnects: Arc::default(),
            after_gap: false,
        }
    }

    /// Counts successful reopens (shared, for status lines).
    pub fn reconnect_counter(&self) -> Arc<AtomicU64> {
        self.reconnects.clone()
    }

    /// Sleeps `d`, waking early when a stop is requested; true if it was.
    fn sleep_unless_stopped(&self, d: Duration) -> bool {
        let until = Instant::now() + d;
        loop {
            if self.stop.load(Ordering::SeqCst) {
                return true;
            }
            let now = Instant::now();
            if now >= until {
                return false;
            }
            std::thread::sleep((until - now).min(Duration::from_millis(50)));
        }
    }

    /// Reopens the source, retrying with backoff; false if a stop came first.
    fn reopen(&mut self) -> bool {
        let lost = Instant::now();
        for attempt in 0u32.. {
            if self.sleep_unless_stopped(self.backoff.delay(attempt)) {
                return false;
            }
            match (self.open)() {
                Ok(s) => {
                    self.current = Some(s);
                    self.after_gap = true;
                    self.reconnects.fetch_add(1, Ordering::Relaxed);
                    info!(
                        attempts = attempt + 1,
                        down_s = lost.elapsed().as_secs_f64(),
                        "device back, capture resumed"
                    );
                    return true;
                }
                Err(e) if attempt == 0 => warn!(
                    "reopening the device failed, retrying with backoff up to {:?}: {e}",
                    self.backoff.max
                ),
                Err(e) => tracing::debug!(attempt, "reopening failed: {e}"),
            }
        }
        unreachable!("the attempt counter does not end")
    }
}

impl Source for Reconnecting {
    fn next_frame(&mut self, frame: &mut Frame) -> Result<bool> {
        loop {
            if self.stop.load(Ordering::SeqCst) {
                return Ok(false);
            }
            let Some(src) = self.current.as_mut() else {
                if !self.reopen() {
                    return Ok(false);
                }
                continue;
            };
            match src.next_frame(frame) {
                Ok(true) => {
                    frame.discontinuity = std::mem::take(&mut self.after_gap);
                    return Ok(true);
                }
                // The source ended for good (a stop request, or the end of a fakenect recording).
                Ok(false) => return Ok(false),
                Err(e) => {
                    warn!("device lost, reconnecting: {e}");
                    // Drop it first: a Kinect must be closed before it can be opened again.
                    self.current = None;
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn backoff_doubles_up_to_its_cap() {
        let b = Backoff {
            initial: Duration::from_millis(100),
            max: Duration::from_secs(1),
        };
        let d: Vec<u128> = (0..6).map(|n| b.delay(n).as_millis()).collect();
        assert_eq!(d, [100, 200, 400, 800, 1000, 1000]);
        assert_eq!(
            b.delay(1000),
            Duration::from_secs(1),
            "no overflow on long outages"
        );
    }
}
