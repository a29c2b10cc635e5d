//! The daemon's foreground-mask stage (issue 4, item 4): masks are made at a configured rate on
//! a thread of their own, from copies of written frames, and written into the MCAP segment on
//! `/umbra/foreground_mask` as they finish.
//!
//! The stage never slows the label path: a frame is offered only when its rate says one is due,
//! and it is taken only when the worker is idle (a one-slot hand-over with `try_send`);
//! otherwise it is skipped and counted. Buffers are made once, when the stage starts.

use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Arc;
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use crossbeam_channel::{bounded, Receiver, Sender, TrySendError};
use tracing::{info_span, warn};

use super::mcap::McapSink;
use super::Sink;
use crate::error::Result;
use crate::labels::PIXELS;
use crate::pipeline::telemetry::Histogram;
use crate::pipeline::Frame;

/// Makes a foreground mask from a classified frame: RGB view, `PIXELS` bytes, 255 foreground,
/// 0 background.
pub trait MaskMaker: Send {
    /// Fills `mask` (length `PIXELS`) for `frame`.
    fn make(&mut self, frame: &Frame, mask: &mut [u8]) -> Result<()>;
}

/// The paper's §4 segmentation: shadow seeds, GrabCut on colour and depth.
impl MaskMaker for crate::segment::Segmenter {
    fn make(&mut self, frame: &Frame, mask: &mut [u8]) -> Result<()> {
        if !frame.has_rgb {
            return Err(crate::error::Error::Usage(format!(
                "frame {} has no RGB image paired with it",
                frame.seq
            )));
        }
        self.segment(&frame.rgb, &frame.labels, mask);
        Ok(())
    }
}

/// A finished mask on its way to the writer.
struct Done {
    seq: u64,
    unix_time: f64,
    mask: Vec<u8>,
}

/// What the stage did, shared (status, tests).
#[derive(Debug, Default)]
pub struct ForegroundCounters {
    /// Masks made.
    pub made: AtomicU64,
    /// Due frames skipped because the worker was still busy.
    pub skipped: AtomicU64,
    /// Frames whose mask could not be made (the maker failed).
    pub failed: AtomicU64,
    /// Time to make one mask.
    pub latency: Histogram,
}

/// An [`McapSink`] that also writes foreground masks made on a worker thread.
pub struct WithForeground {
    inner: McapSink,
    every: Duration,
    next_due: Option<Instant>,
    offer: Option<Sender<Box<Frame>>>,
    /// The worker's input buffer comes back here when it is done with it.
    idle: Receiver<Box<Frame>>,
    done: Receiver<Done>,
    mask_back: Sender<Vec<u8>>,
    counters: Arc<ForegroundCounters>,
    worker: Option<JoinHandle<()>>,
}

impl WithForeground {
    /// Wraps `inner`; `maker` runs on its own thread for at most `rate_hz` frames per second.
    pub fn new(inner: McapSink, mut maker: Box<dyn MaskMaker>, rate_hz: f64) -> Self {
        let (offer, offered) = bounded::<Box<Frame>>(1);
        let (idle_tx, idle) = bounded::<Box<Frame>>(1);
        let (done_tx, done) = bounded::<Done>(2);
        let (mask_back, masks) = bounded::<Vec<u8>>(2);
        idle_tx
            .send(Box::default())
            .expect("room for the one buffer");
        for _ in 0..2 {
            mask_back
                .send(vec![0; PIXELS])
                .expect("room for both masks");
        }
        let counters = Arc::new(ForegroundCounters::default());
        let c = counters.clone();
        let worker = std::thread::Builder::new()
            .name("foreground".into())
            .spawn(move || {
                let _span = info_span!("foreground").entered();
                // The buffer of a failed attempt is reused for the next one.
                let mut spare = None;
                for frame in offered {
                    let mut mask = match spare.take() {
                        Some(m) => m,
                        None => match masks.recv() {
                            Ok(m) => m,
                            Err(_) => break,
                        },
                    };
                    let t = Instant::now();
                    match maker.make(&frame, &mut mask) {
                        Ok(()) => {
                            c.latency.record(t.elapsed());
                            c.made.fetch_add(1, Ordering::Relaxed);
                            if done_tx
                                .send(Done {
                                    seq: frame.seq,
                                    unix_time: frame.unix_time,
                                    mask,
                                })
                                .is_err()
                            {
                                break;
                            }
                        }
                        Err(e) => {
                            if c.failed.fetch_add(1, Ordering::Relaxed) == 0 {
                                warn!(
                                    seq = frame.seq,
                                    "foreground mask failed (further failures are counted): {e}"
                                );
                            }
                            spare = Some(mask);
                        }
                    }
                    if idle_tx.send(frame).is_err() {
                        break;
                    }
                }
            })
            .ok();
        let every = Duration::from_secs_f64(1.0 / rate_hz.clamp(1e-6, 1e6));
        WithForeground {
            inner,
            every,
            next_due: None,
            offer: Some(offer),
            idle,
            done,
            mask_back,
            counters,
            worker,
        }
    }

    /// The stage's counters.
    pub fn counters(&self) -> Arc<ForegroundCounters> {
        self.counters.clone()
    }

    /// Writes every finished mask.
    fn drain(&mut self) {
        while let Ok(d) = self.done.try_recv() {
            self.inner.write_mask(d.seq, d.unix_time, &d.mask);
            let _ = self.mask_back.try_send(d.mask);
        }
    }

    /// Hands `frame` to the worker if a mask is due and the worker is idle.
    fn offer(&mut self, frame: &Frame) {
        let now = Instant::now();
        if self.next_due.is_some_and(|t| now < t) {
            return;
        }
        let Ok(mut buf) = self.idle.try_recv() else {
            self.counters.skipped.fetch_add(1, Ordering::Relaxed);
            return;
        };
        copy_frame(frame, &mut buf);
        match self.offer.as_ref().map(|o| o.try_send(buf)) {
            // Keep the cadence, but after a busy spell do not owe the missed masks.
            Some(Ok(())) => {
                self.next_due = Some((self.next_due.unwrap_or(now) + self.every).max(now))
            }
            Some(Err(TrySendError::Full(_) | TrySendError::Disconnected(_))) | None => {
                self.counters.skipped.fetch_add(1, Ordering::Relaxed);
            }
        }
    }
}

/// Copies what a mask needs (inputs and labels) into a preallocated frame, without allocating.
fn copy_frame(from: &Frame, to: &mut Frame) {
    to.seq = from.seq;
    to.device_ts = from.device_ts;
    to.unix_time = from.unix_time;
    to.has_rgb = from.has_rgb;
    to.depth.copy_from_slice(&from.depth);
    to.rgb.copy_from_slice(&from.rgb);
    to.labels.ir_labels.copy_from_slice(&from.labels.ir_labels);
    to.labels
        .rgb_labels
        .copy_from_slice(&from.labels.rgb_labels);
    to.labels
        .registered_mm
        .copy_from_slice(&from.labels.registered_mm);
}

impl Sink for WithForeground {
    fn write(&mut self, frame: &Frame) -> Result<()> {
        self.inner.write(frame)?;
        self.drain();
        self.offer(frame);
        Ok(())
    }

    /// Waits for the mask in progress, writes it, then closes the segment.
    fn finish(&mut self) -> Result<()> {
        self.offer = None;
        if let Some(w) = self.worker.take() {
            // Keep draining while waiting: the worker may need a mask buffer back to finish.
            while !w.is_finished() {
                self.drain();
                std::thread::sleep(Duration::from_millis(1));
            }
            let _ = w.join();
        }
        self.drain();
        self.inner.finish()
    }
}

impl Drop for WithForeground {
    fn drop(&mut self) {
        self.offer = None;
        if let Some(w) = self.worker.take() {
            while !w.is_finished() {
                // Dropping finished masks unblocks a worker waiting for a buffer.
                while let Ok(d) = self.done.try_recv() {
                    let _ = self.mask_back.try_send(d.mask);
                }
                std::thread::sleep(Duration::from_millis(1));
            }
            let _ = w.join();
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::labels::{ATTACHED, VALID};
    use crate::sink::mcap::{topics, McapOptions};

    /// Marks valid RGB-view pixels as foreground; blocks until `go` says so, to hold the worker busy.
    struct Gated {
        go: Receiver<()>,
    }

    impl MaskMaker for Gated {
        fn make(&mut self, frame: &Frame, mask: &mut [u8]) -> Result<()> {
            self.go
                .recv()
                .map_err(|_| crate::error::Error::Usage("gate closed".into()))?;
            for (m, &l) in mask.iter_mut().zip(&frame.labels.rgb_labels) {
                *m = if l == VALID { 255 } else { 0 };
            }
            Ok(())
        }
    }

    fn frame(seq: u64) -> Frame {
        let mut f = Frame {
            seq,
            unix_time: 1.8e9 + seq as f64,
            ..Frame::default()
        };
        // A different label pattern per frame, so each mask can be traced to its frame.
        for (i, l) in f.labels.rgb_labels.iter_mut().enumerate() {
            *l = if i % 7 == seq as usize % 7 {
                ATTACHED
            } else {
                VALID
            };
        }
        f
    }

    #[test]
    fn a_busy_worker_never_holds_frames_back_and_masks_follow_their_frames() {
        let tmp = tempfile::tempdir().unwrap();
        let opts = McapOptions {
            write_foreground: true,
            ..McapOptions::default()
        };
        let (go, gate) = bounded(8);
        // A rate high enough that every frame is due: only the busy worker limits it.
        let mut sink = WithForeground::new(
            McapSink::create(tmp.path(), opts).unwrap(),
            Box::new(Gated { go: gate }),
            1e6,
        );
        let counters = sink.counters();
        for seq in 0..10 {
            sink.write(&frame(seq)).unwrap();
        }
        // The worker is stuck on frame 0: the other nine frames were written, none waited.
        assert_eq!(counters.made.load(Ordering::SeqCst), 0);
        assert_eq!(counters.skipped.load(Ordering::SeqCst), 9);
        go.send(()).unwrap();
        while counters.made.load(Ordering::SeqCst) == 0 {
            std::thread::sleep(Duration::from_millis(1));
        }
        go.send(()).unwrap();
        sink.write(&frame(10)).unwrap();
        sink.finish().unwrap();
        drop(sink);

        let seg = std::fs::read_dir(tmp.path())
            .unwrap()
            .next()
            .unwrap()
            .unwrap()
            .path();
        let bytes = std::fs::read(seg).unwrap();
        let mut masks = Vec::new();
        let mut frames = 0;
        for m in ::mcap::MessageStream::new(&bytes).unwrap() {
            let m = m.unwrap();
            match m.channel.topic.as_str() {
                topics::FOREGROUND_MASK => masks.push((m.sequence, m.data.into_owned())),
                topics::FRAME_STATS => frames += 1,
                _ => {}
            }
        }
        assert_eq!(frames, 11);
        assert_eq!(masks.iter().map(|(s, _)| *s).collect::<Vec<_>>(), [0, 10]);
        for (seq, data) in masks {
            let (h, pixels) = crate::sink::mcap::ros2::decode_image(&data).unwrap();
            assert_eq!((h.encoding, h.width, h.height), ("mono8", 640, 480));
            let want: Vec<u8> = frame(seq.into())
                .labels
                .rgb_labels
                .iter()
                .map(|&l| if l == VALID { 255 } else { 0 })
                .collect();
            assert!(pixels == want.as_slice(), "mask of frame {seq}");
        }
    }

    #[test]
    fn the_rate_limits_how_many_frames_are_offered() {
        let tmp = tempfile::tempdir().unwrap();
        let opts = McapOptions {
            write_foreground: true,
            ..McapOptions::default()
        };
        let (go, gate) = bounded(100);
        for _ in 0..100 {
            go.send(()).unwrap();
        }
        // One mask per hour: only the first frame is due.
        let mut sink = WithForeground::new(
            McapSink::create(tmp.path(), opts).unwrap(),
            Box::new(Gated { go: gate }),
            1.0 / 3600.0,
        );
        let counters = sink.counters();
        for seq in 0..20 {
            sink.write(&frame(seq)).unwrap();
        }
        sink.finish().unwrap();
        assert_eq!(counters.made.load(Ordering::SeqCst), 1);
        assert_eq!(counters.skipped.load(Ordering::SeqCst), 0);
    }
}
