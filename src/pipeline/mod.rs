//! Runs frames from a [`Source`] through the classifier into [`Sink`]s on three threads
//! (read → classify → write) joined by bounded crossbeam channels.
//!
//! A fixed pool of [`Frame`] buffers circulates through the stages and back, so nothing is
//! allocated per frame and a slow stage holds back the reader instead of growing a queue.

use std::time::{Duration, Instant};

use crossbeam_channel::{bounded, Receiver, Sender};
use tracing::{debug, info_span};

use crate::capture::Source;
use crate::classify::{Classified, Classifier};
use crate::error::{Error, Result};
use crate::labels::{histogram, CLASSES, PIXELS};
use crate::sink::Sink;

/// One frame travelling through the pipeline: input buffers, metadata and labels.
#[derive(Clone, Debug)]
pub struct Frame {
    /// 0-based frame index (SPEC §3's frame index for recordings).
    pub seq: u64,
    /// Device timestamp of the depth frame (32-bit, wraps).
    pub device_ts: u32,
    /// Host time the depth frame was received, seconds since the epoch.
    pub unix_time: f64,
    /// Raw 11-bit depth, 640·480.
    pub depth: Vec<u16>,
    /// RGB8, 640·480·3; meaningful only when `has_rgb`.
    pub rgb: Vec<u8>,
    /// Whether `rgb` holds an image paired with this depth frame.
    pub has_rgb: bool,
    /// Depth frames the source dropped just before this one (live capture that fell behind).
    /// The pipeline skips that many `seq` numbers, so `seq` keeps counting device frames.
    pub dropped_before: u64,
    /// Classifier output.
    pub labels: Classified,
}

impl Default for Frame {
    fn default() -> Self {
        Frame {
            seq: 0,
            device_ts: 0,
            unix_time: 0.0,
            depth: vec![0; PIXELS],
            rgb: vec![0; PIXELS * 3],
            has_rgb: false,
            dropped_before: 0,
            labels: Classified::default(),
        }
    }
}

/// What a finished run measured.
#[derive(Clone, Debug, Default)]
pub struct Stats {
    /// Frames written to every sink.
    pub frames: u64,
    /// Frames the source dropped (summed `Frame::dropped_before`).
    pub dropped: u64,
    /// Pixel counts per class, IR view.
    pub ir: [u64; CLASSES],
    /// Pixel counts per class, RGB view.
    pub rgb: [u64; CLASSES],
    /// Wall time from start to the last frame written.
    pub elapsed: Duration,
    /// Time spent classifying, summed over frames.
    pub classify_time: Duration,
}

impl Stats {
    /// Frames per second over the whole run.
    pub fn fps(&self) -> f64 {
        self.frames as f64 / self.elapsed.as_secs_f64().max(1e-9)
    }
}

/// Pipeline settings.
pub struct Options {
    /// Frame buffers in circulation (at least 3: one per stage).
    pub pool: usize,
}

impl Default for Options {
    fn default() -> Self {
        Options { pool: 4 }
    }
}

enum Msg {
    Frame(Box<Frame>),
    Failed(Error),
}

/// Runs `source` to its end through the classifier into `sinks`. `on_frame` is called on the
/// writer thread after each frame is written (progress bars). Stops at the first error and
/// returns it; frames written before it stay written.
pub fn run(
    mut source: Box<dyn Source>,
    mut classifier: Classifier,
    sinks: &mut [Box<dyn Sink>],
    opts: Options,
    mut on_frame: impl FnMut(&Frame),
) -> Result<Stats> {
    let pool = opts.pool.max(3);
    let (free_tx, free_rx) = bounded::<Box<Frame>>(pool);
    for _ in 0..pool {
        free_tx.send(Box::default()).expect("pool channel has room");
    }
    let (read_tx, read_rx) = bounded::<Msg>(pool);
    let (done_tx, done_rx) = bounded::<Msg>(pool);
    let start = Instant::now();
    let mut stats = Stats::default();

    std::thread::scope(|scope| {
        scope.spawn(move || read_stage(source.as_mut(), free_rx, read_tx));
        let classify_time = scope.spawn(move || classify_stage(&mut classifier, read_rx, done_tx));
        let result = write_stage(sinks, done_rx, &free_tx, &mut stats, &mut on_frame);
        // Dropping the pool's sender and the receiver (inside write_stage) unblocks the others.
        drop(free_tx);
        stats.classify_time = classify_time.join().unwrap_or_default();
        stats.elapsed = start.elapsed();
        result
    })?;
    for sink in sinks.iter_mut() {
        sink.finish()?;
    }
    Ok(stats)
}

fn read_stage(source: &mut dyn Source, free: Receiver<Box<Frame>>, out: Sender<Msg>) {
    let _span = info_span!("read").entered();
    let mut seq = 0;
    while let Ok(mut frame) = free.recv() {
        frame.dropped_before = 0;
        match source.next_frame(&mut frame) {
            Ok(true) => {
                seq += frame.dropped_before;
                frame.seq = seq;
                seq += 1;
                if out.send(Msg::Frame(frame)).is_err() {
                    return;
                }
            }
            Ok(false) => return,
            Err(e) => {
                let _ = out.send(Msg::Failed(e));
                return;
            }
        }
    }
}

fn classify_stage(classifier: &mut Classifier, input: Receiver<Msg>, out: Sender<Msg>) -> Duration {
    let _span = info_span!("classify").entered();
    let mut busy = Duration::ZERO;
    for msg in input {
        let msg = match msg {
            Msg::Frame(mut f) => {
                let t = Instant::now();
                let Frame { depth, labels, .. } = f.as_mut();
                classifier.classify(depth, labels);
                busy += t.elapsed();
                Msg::Frame(f)
            }
            failed => failed,
        };
        if out.send(msg).is_err() {
            break;
        }
    }
    busy
}

fn write_stage(
    sinks: &mut [Box<dyn Sink>],
    input: Receiver<Msg>,
    free: &Sender<Box<Frame>>,
    stats: &mut Stats,
    on_frame: &mut impl FnMut(&Frame),
) -> Result<()> {
    let _span = info_span!("write").entered();
    for msg in input {
        let frame = match msg {
            Msg::Frame(f) => f,
            Msg::Failed(e) => return Err(e),
        };
        for sink in sinks.iter_mut() {
            sink.write(&frame)?;
        }
        for (total, n) in stats.ir.iter_mut().zip(histogram(&frame.labels.ir_labels)) {
            *total += n;
        }
        for (total, n) in stats.rgb.iter_mut().zip(histogram(&frame.labels.rgb_labels)) {
            *total += n;
        }
        stats.frames += 1;
        stats.dropped += frame.dropped_before;
        on_frame(&frame);
        debug!(seq = frame.seq, "frame written");
        let _ = free.send(frame);
    }
    Ok(())
}
