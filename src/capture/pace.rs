//! [`Paced`]: wraps any [`Source`] to deliver frames at the pace of their `unix_time` (recorded
//! speed) and to end early when a stop flag is set (SIGINT/SIGTERM in `umbra run`).

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

use super::Source;
use crate::error::Result;
use crate::pipeline::Frame;

/// Longest single sleep, so a stop request is honoured quickly.
const SLICE: Duration = Duration::from_millis(20);

/// A source that waits until each frame is due and stops when asked.
pub struct Paced<S> {
    inner: S,
    stop: Arc<AtomicBool>,
    realtime: bool,
    /// Wall clock and frame time of the first frame.
    origin: Option<(Instant, f64)>,
}

impl<S: Source> Paced<S> {
    /// Wraps `inner`; with `realtime` false frames come as fast as `inner` reads them.
    pub fn new(inner: S, stop: Arc<AtomicBool>, realtime: bool) -> Self {
        Paced {
            inner,
            stop,
            realtime,
            origin: None,
        }
    }
}

impl<S: Source> Source for Paced<S> {
    fn next_frame(&mut self, frame: &mut Frame) -> Result<bool> {
        if self.stop.load(Ordering::SeqCst) || !self.inner.next_frame(frame)? {
            return Ok(false);
        }
        if !self.realtime {
            return Ok(true);
        }
        let (t0, u0) = *self.origin.get_or_insert((Instant::now(), frame.unix_time));
        // Times that go backwards (or are not finite) play at once rather than never.
        let offset = frame.unix_time - u0;
        let due = t0 + Duration::try_from_secs_f64(offset).unwrap_or(Duration::ZERO);
        loop {
            if self.stop.load(Ordering::SeqCst) {
                return Ok(false);
            }
            let now = Instant::now();
            if now >= due {
                return Ok(true);
            }
            std::thread::sleep((due - now).min(SLICE));
        }
    }

    fn len_hint(&self) -> Option<usize> {
        self.inner.len_hint()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    struct Times(Vec<f64>);

    impl Source for Times {
        fn next_frame(&mut self, frame: &mut Frame) -> Result<bool> {
            if self.0.is_empty() {
                return Ok(false);
            }
            frame.unix_time = self.0.remove(0);
            Ok(true)
        }
    }

    #[test]
    fn paces_by_frame_time_and_stops_on_request() {
        let stop = Arc::new(AtomicBool::new(false));
        let mut p = Paced::new(Times(vec![100.0, 100.05, 100.1, 99.0]), stop.clone(), true);
        let mut f = Frame::default();
        let t = Instant::now();
        for _ in 0..4 {
            assert!(p.next_frame(&mut f).unwrap());
        }
        let took = t.elapsed();
        assert!(
            took >= Duration::from_millis(100) && took < Duration::from_millis(400),
            "{took:?}"
        );
        stop.store(true, Ordering::SeqCst);
        let mut p = Paced::new(Times(vec![1.0]), stop, true);
        assert!(!p.next_frame(&mut f).unwrap());
    }
}
