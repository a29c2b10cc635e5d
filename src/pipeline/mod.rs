//! Runs frames from a [`Source`] through the classifier into [`Sink`]s on three threads
//! (read → classify → write) joined by bounded crossbeam channels.
//!
//! A fixed pool of [`Frame`] buffers circulates through the stages and back, so nothing is
//! allocated per frame and a slow stage holds back the reader instead of growing a queue.
//! [`telemetry`] records per-stage latency, queue depths and CPU time as frames pass.

pub mod telemetry;

use std::sync::atomic::Ordering;
use std::sync::Arc;
use std::time::{Duration, Instant};

use crossbeam_channel::{bounded, Receiver, Sender};
use tracing::{debug, info_span, warn};

use crate::capture::Source;
use crate::classify::{Classified, Classifier};
use crate::error::{Error, Result};
use crate::labels::{histogram, CLASSES, PIXELS};
use crate::sink::Sink;
pub use telemetry::Telemetry;

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
    /// RGB frames the source dropped since the previous frame.
    pub rgb_dropped_before: u64,
    /// When the frame reached umbra (the USB callback, or the read from disk): the start of its
    /// end-to-end latency. `None` lets the read stage stamp it.
    pub received: Option<Instant>,
    /// First frame after the source lost its device and reopened it: segmenting sinks start a
    /// new segment here.
    pub discontinuity: bool,
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
            rgb_dropped_before: 0,
            received: None,
            discontinuity: false,
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
    /// Latencies, queue depths and counters of the run.
    pub telemetry: Arc<Telemetry>,
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
    /// Where the run's measurements go; share it to watch a run from another thread.
    pub telemetry: Arc<Telemetry>,
}

impl Default for Options {
    fn default() -> Self {
        Options {
            pool: 4,
            telemetry: Arc::default(),
        }
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
    let tel = opts.telemetry;
    let mut stats = Stats {
        telemetry: tel.clone(),
        ..Stats::default()
    };

    std::thread::scope(|scope| {
        let t = &tel;
        let free_back = free_tx.clone();
        scope.spawn(move || {
            on_thread(t, 0, || {
                read_stage(source.as_mut(), free_rx, &free_back, read_tx, t)
            })
        });
        let classify_time = scope.spawn(move || {
            on_thread(t, 1, || {
                classify_stage(&mut classifier, read_rx, done_tx, t)
            })
        });
        let result = on_thread(t, 2, || {
            write_stage(sinks, done_rx, &free_tx, &mut stats, &mut on_frame, t)
        });
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

/// Runs a stage's body and stores the CPU time its thread used in `tel.cpu_us[stage]`.
fn on_thread<T>(tel: &Telemetry, stage: usize, body: impl FnOnce() -> T) -> T {
    let t0 = telemetry::thread_cpu_time();
    let r = body();
    tel.cpu_us[stage].store(
        (telemetry::thread_cpu_time().saturating_sub(t0)).as_micros() as u64,
        Ordering::Relaxed,
    );
    r
}

/// Why a frame from a source cannot be classified, if it cannot.
fn malformed(frame: &Frame) -> Option<String> {
    if frame.depth.len() != PIXELS {
        return Some(format!(
            "depth frame of {} pixels, expected {PIXELS} (640x480)",
            frame.depth.len()
        ));
    }
    None
}

fn read_stage(
    source: &mut dyn Source,
    free: Receiver<Box<Frame>>,
    free_back: &Sender<Box<Frame>>,
    out: Sender<Msg>,
    tel: &Telemetry,
) {
    let _span = info_span!("read").entered();
    let mut seq = 0;
    let mut malformed_burst = false;
    while let Ok(mut frame) = free.recv() {
        frame.dropped_before = 0;
        frame.rgb_dropped_before = 0;
        frame.received = None;
        frame.discontinuity = false;
        match source.next_frame(&mut frame) {
            Ok(true) => {
                frame.received.get_or_insert_with(Instant::now);
                seq += frame.dropped_before;
                frame.seq = seq;
                seq += 1;
                tel.frames_read.fetch_add(1, Ordering::Relaxed);
                tel.frames_dropped
                    .fetch_add(frame.dropped_before, Ordering::Relaxed);
                tel.rgb_dropped
                    .fetch_add(frame.rgb_dropped_before, Ordering::Relaxed);
                if let Some(why) = malformed(&frame) {
                    // A broken frame must not take the pool's buffer shapes (or the run) with it.
                    tel.frames_malformed.fetch_add(1, Ordering::Relaxed);
                    if !malformed_burst {
                        warn!(seq = frame.seq, "frame skipped: {why} (further ones are counted, not logged, until a good frame)");
                        malformed_burst = true;
                    }
                    frame.depth.resize(PIXELS, crate::labels::NO_DEPTH);
                    let _ = free_back.send(frame);
                    continue;
                }
                malformed_burst = false;
                if frame.has_rgb && frame.rgb.len() != PIXELS * 3 {
                    warn!(
                        seq = frame.seq,
                        bytes = frame.rgb.len(),
                        "RGB frame of the wrong size ignored"
                    );
                    frame.has_rgb = false;
                    frame.rgb.resize(PIXELS * 3, 0);
                }
                tel.classify_queue.sample(out.len());
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

fn classify_stage(
    classifier: &mut Classifier,
    input: Receiver<Msg>,
    out: Sender<Msg>,
    tel: &Telemetry,
) -> Duration {
    let _span = info_span!("classify").entered();
    let mut busy = Duration::ZERO;
    for msg in input {
        let msg = match msg {
            Msg::Frame(mut f) => {
                let t = Instant::now();
                if let Some(r) = f.received {
                    tel.queue_latency.record(t.saturating_duration_since(r));
                }
                let Frame {
                    depth,
                    rgb,
                    has_rgb,
                    labels,
                    ..
                } = f.as_mut();
                classifier.classify_with_rgb(depth, has_rgb.then_some(&rgb[..]), labels);
                let took = t.elapsed();
                tel.classify_latency.record(took);
                busy += took;
                Msg::Frame(f)
            }
            failed => failed,
        };
        tel.write_queue.sample(out.len());
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
    tel: &Telemetry,
) -> Result<()> {
    let _span = info_span!("write").entered();
    for msg in input {
        let frame = match msg {
            Msg::Frame(f) => f,
            Msg::Failed(e) => return Err(e),
        };
        let t = Instant::now();
        for sink in sinks.iter_mut() {
            sink.write(&frame)?;
        }
        let done = Instant::now();
        tel.write_latency.record(done - t);
        if let Some(r) = frame.received {
            tel.total_latency.record(done.saturating_duration_since(r));
        }
        tel.frames_written.fetch_add(1, Ordering::Relaxed);
        for (total, n) in stats.ir.iter_mut().zip(histogram(&frame.labels.ir_labels)) {
            *total += n;
        }
        for (total, n) in stats
            .rgb
            .iter_mut()
            .zip(histogram(&frame.labels.rgb_labels))
        {
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
