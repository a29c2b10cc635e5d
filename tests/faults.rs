//! Fault injection through the daemon's seams (issue 3): scripted [`Source`]s that lose the
//! device and come back, stall, deliver frames of the wrong size or timestamps that wrap, and
//! sinks that fail, all run through the real pipeline, reconnect logic and MCAP writer.
//! Truth is independent of the pipeline: each frame's labels are what the classifier gives when
//! called directly on the same depth, and the counts are the script's.

use std::collections::VecDeque;
use std::path::Path;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use umbra::capture::reconnect::{Backoff, Opener, Reconnecting};
use umbra::capture::Source;
use umbra::classify::{Classified, Classifier};
use umbra::error::{Error, Result};
use umbra::labels::{NO_DEPTH, PIXELS, WIDTH};
use umbra::pipeline::{self, Frame, Options, Telemetry};
use umbra::sink::mcap::read::{read_segment, Recorded};
use umbra::sink::mcap::segment::list_segments;
use umbra::sink::mcap::{McapOptions, McapSink};
use umbra::sink::{Sink, Tolerant};
use umbra::Calibration;

/// One step of a scripted device.
#[derive(Clone)]
enum Step {
    /// Deliver frame `k` of [`depth`] with this device timestamp.
    Frame(usize, u32),
    /// Block this long first (a stalled USB stream), then go on.
    Stall(Duration),
    /// A depth buffer of this many pixels (a broken driver).
    WrongDepth(usize),
    /// A good depth frame `k` with an RGB buffer of the wrong size.
    WrongRgb(usize),
    /// The device fails (unplugged, libusb error).
    Fail,
}

/// A box before a wall that moves one step per `k`, with speckle: a different frame for each k.
fn depth(k: usize) -> Vec<u16> {
    let calib = Calibration::nyu_default();
    let (wall, near) = (
        calib.raw_from_depth(3.0).round() as u16,
        calib.raw_from_depth(1.2).round() as u16,
    );
    (0..PIXELS)
        .map(|i| {
            let (x, y) = (i % WIDTH, i / WIDTH);
            if (i * 7919 + k * 31).is_multiple_of(1009) {
                NO_DEPTH
            } else if (150 + 9 * k..330 + 9 * k).contains(&x) && (120..360).contains(&y) {
                near
            } else {
                wall + (y / 80) as u16
            }
        })
        .collect()
}

/// The classifier's labels for frame `k`, computed directly (the reference).
fn reference(k: usize) -> Classified {
    let mut c = Classifier::new(&Calibration::nyu_default());
    let mut out = Classified::default();
    c.classify(&depth(k), &mut out);
    out
}

struct Scripted {
    steps: VecDeque<Step>,
}

impl Source for Scripted {
    fn next_frame(&mut self, f: &mut Frame) -> Result<bool> {
        loop {
            let Some(step) = self.steps.pop_front() else {
                return Ok(false);
            };
            let (k, ts, depth_len, rgb_len) = match step {
                Step::Stall(d) => {
                    std::thread::sleep(d);
                    continue;
                }
                Step::Fail => {
                    return Err(Error::Usage(
                        "scripted device: LIBUSB_ERROR_NO_DEVICE".into(),
                    ))
                }
                Step::Frame(k, ts) => (k, ts, PIXELS, PIXELS * 3),
                Step::WrongDepth(n) => (0, 0, n, PIXELS * 3),
                Step::WrongRgb(k) => (k, k as u32, PIXELS, 1234),
            };
            f.depth.clear();
            f.depth.extend(
                depth(k)
                    .into_iter()
                    .chain(std::iter::repeat(NO_DEPTH))
                    .take(depth_len),
            );
            f.rgb.resize(rgb_len, k as u8);
            f.has_rgb = true;
            f.device_ts = ts;
            f.unix_time = 1.8e9 + k as f64 / 30.0;
            return Ok(true);
        }
    }
}

fn scripted(steps: &[Step]) -> Box<dyn Source> {
    Box::new(Scripted {
        steps: steps.iter().cloned().collect(),
    })
}

/// Frames in the MCAP folder, per segment, in order.
fn segments(dir: &Path) -> Vec<Vec<Recorded>> {
    list_segments(dir)
        .unwrap()
        .into_iter()
        .map(|(p, _)| read_segment(&p).unwrap().0)
        .collect()
}

fn run(source: Box<dyn Source>, sinks: &mut [Box<dyn Sink>]) -> (pipeline::Stats, Arc<Telemetry>) {
    let tel = Arc::new(Telemetry::default());
    let classifier = Classifier::new(&Calibration::nyu_default());
    let stats = pipeline::run(
        source,
        classifier,
        sinks,
        Options {
            telemetry: tel.clone(),
            ..Options::default()
        },
        |_| {},
    )
    .unwrap();
    (stats, tel)
}

fn mcap(dir: &Path) -> Box<dyn Sink> {
    Box::new(
        McapSink::create(
            dir,
            McapOptions {
                retry_interval: Duration::ZERO,
                ..McapOptions::default()
            },
        )
        .unwrap(),
    )
}

#[test]
fn a_lost_device_is_reopened_with_backoff_and_capture_resumes_in_a_new_segment() {
    let tmp = tempfile::tempdir().unwrap();
    let first = scripted(&[
        Step::Frame(0, 10),
        Step::Frame(1, 20),
        Step::Frame(2, 30),
        Step::Fail,
    ]);
    // The device is still gone at the first attempt, back at the second.
    let attempts = Arc::new(AtomicUsize::new(0));
    let a = attempts.clone();
    let opener: Opener = Box::new(move || match a.fetch_add(1, Ordering::SeqCst) {
        0 => Err(Error::Usage("no Kinect found".into())),
        _ => Ok(scripted(&[Step::Frame(3, 40), Step::Frame(4, 50)])),
    });
    let backoff = Backoff {
        initial: Duration::from_millis(40),
        max: Duration::from_millis(100),
    };
    let stop = Arc::new(AtomicBool::new(false));
    let source = Reconnecting::new(first, opener, backoff, stop);
    let reconnects = source.reconnect_counter();
    let t = Instant::now();
    let (stats, tel) = run(Box::new(source), &mut [mcap(tmp.path())]);
    // Two waits: 40 ms before the failed attempt, 80 ms before the good one.
    assert!(
        t.elapsed() >= Duration::from_millis(120),
        "{:?}",
        t.elapsed()
    );
    assert_eq!(attempts.load(Ordering::SeqCst), 2);
    assert_eq!(reconnects.load(Ordering::SeqCst), 1);
    assert_eq!(
        (stats.frames, tel.frames_malformed.load(Ordering::SeqCst)),
        (5, 0)
    );
    let segs = segments(tmp.path());
    let ks: Vec<Vec<u64>> = segs
        .iter()
        .map(|s| s.iter().map(|r| r.frame.seq).collect())
        .collect();
    assert_eq!(
        ks,
        [vec![0, 1, 2], vec![3, 4]],
        "a new segment after the reconnect"
    );
    for (k, r) in segs.iter().flatten().enumerate() {
        let want = reference(k);
        assert!(
            r.frame.labels.ir_labels == want.ir_labels
                && r.frame.labels.rgb_labels == want.rgb_labels,
            "labels of frame {k}"
        );
        assert_eq!(r.frame.device_ts, 10 * (k as u32 + 1));
    }
}

#[test]
fn a_stop_during_the_backoff_ends_the_run_at_once() {
    let opener: Opener = Box::new(|| Err(Error::Usage("no Kinect found".into())));
    let backoff = Backoff {
        initial: Duration::from_secs(60),
        max: Duration::from_secs(60),
    };
    let stop = Arc::new(AtomicBool::new(false));
    let source = Reconnecting::new(
        scripted(&[Step::Frame(0, 1), Step::Fail]),
        opener,
        backoff,
        stop.clone(),
    );
    let s = stop.clone();
    std::thread::spawn(move || {
        std::thread::sleep(Duration::from_millis(200));
        s.store(true, Ordering::SeqCst);
    });
    let t = Instant::now();
    let (stats, _) = run(Box::new(source), &mut []);
    assert_eq!(stats.frames, 1);
    assert!(
        t.elapsed() < Duration::from_secs(2),
        "took {:?} with a 60 s backoff pending",
        t.elapsed()
    );
}

#[test]
fn stalls_wrong_sizes_and_wrapping_timestamps_lose_nothing_else() {
    let tmp = tempfile::tempdir().unwrap();
    let near_wrap = u32::MAX - 2_000_000;
    let steps = [
        Step::Frame(0, near_wrap),
        Step::Stall(Duration::from_millis(300)),
        Step::Frame(1, near_wrap.wrapping_add(2_000_000)),
        Step::WrongDepth(640 * 479),
        Step::Frame(2, near_wrap.wrapping_add(6_000_000)),
        Step::WrongRgb(3),
        Step::WrongDepth(PIXELS + 1),
        Step::Frame(4, near_wrap.wrapping_add(12_000_000)),
    ];
    let (stats, tel) = run(scripted(&steps), &mut [mcap(tmp.path())]);
    assert_eq!(tel.frames_malformed.load(Ordering::SeqCst), 2);
    assert_eq!(
        stats.frames,
        4 + 1,
        "frames 0-4, one of them without its broken RGB"
    );
    let back: Vec<Recorded> = segments(tmp.path()).into_iter().flatten().collect();
    let got: Vec<(u64, u32)> = back
        .iter()
        .map(|r| (r.frame.seq, r.frame.device_ts))
        .collect();
    // seq keeps counting device frames (the malformed ones take a number), timestamps wrap.
    assert_eq!(
        got,
        [
            (0, near_wrap),
            (1, near_wrap.wrapping_add(2_000_000)),
            (3, near_wrap.wrapping_add(6_000_000)),
            (4, 3),
            (6, near_wrap.wrapping_add(12_000_000))
        ]
    );
    assert!(got[4].1 < got[0].1, "the timestamp wrapped");
    for (r, k) in back.iter().zip([0, 1, 2, 3, 4]) {
        let want = reference(k);
        assert!(
            r.frame.labels.ir_labels == want.ir_labels
                && r.frame.labels.rgb_labels == want.rgb_labels,
            "labels of frame {k}"
        );
    }
    // The stall is upstream of the pipeline: no frame waited in it.
    assert!(
        tel.total_latency.max_ms() < 250.0,
        "{}",
        tel.total_latency.summary()
    );
    assert_eq!(tel.in_flight(), 0);
}

/// A sink that fails for the frames whose seq is in `fail`, recording the others.
struct Flaky {
    fail: Vec<u64>,
    written: Arc<Mutex<Vec<u64>>>,
}

impl Sink for Flaky {
    fn write(&mut self, f: &Frame) -> Result<()> {
        if self.fail.contains(&f.seq) {
            return Err(Error::io(
                Path::new("/flaky/out"),
                "writing",
                std::io::Error::from_raw_os_error(28),
            ));
        }
        self.written.lock().unwrap().push(f.seq);
        Ok(())
    }
}

#[test]
fn write_errors_are_counted_and_writing_resumes_while_other_outputs_get_every_frame() {
    let tmp = tempfile::tempdir().unwrap();
    let written = Arc::new(Mutex::new(Vec::new()));
    let flaky = Tolerant::new(
        Flaky {
            fail: vec![1, 2, 3, 6],
            written: written.clone(),
        },
        "flaky",
    );
    let lost = flaky.lost_counter();
    let steps: Vec<Step> = (0..8).map(|k| Step::Frame(k, k as u32)).collect();
    let (stats, _) = run(scripted(&steps), &mut [Box::new(flaky), mcap(tmp.path())]);
    assert_eq!(stats.frames, 8);
    assert_eq!(lost.load(Ordering::SeqCst), 4);
    assert_eq!(*written.lock().unwrap(), [0, 4, 5, 7]);
    let seqs: Vec<u64> = segments(tmp.path())
        .into_iter()
        .flatten()
        .map(|r| r.frame.seq)
        .collect();
    assert_eq!(
        seqs,
        (0..8).collect::<Vec<u64>>(),
        "the MCAP output lost nothing"
    );
}

#[test]
fn without_tolerance_a_failing_output_stops_an_offline_run_with_its_error() {
    let steps: Vec<Step> = (0..4).map(|k| Step::Frame(k, k as u32)).collect();
    let flaky: Box<dyn Sink> = Box::new(Flaky {
        fail: vec![2],
        written: Arc::default(),
    });
    let classifier = Classifier::new(&Calibration::nyu_default());
    let err = pipeline::run(
        scripted(&steps),
        classifier,
        &mut [flaky],
        Options::default(),
        |_| {},
    )
    .unwrap_err()
    .to_string();
    assert!(err.starts_with("/flaky/out: writing failed:"), "{err}");
}
