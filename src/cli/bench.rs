//! `umbra bench`: the classifier's speed, and the floors that `umbra run`'s CPU use is judged
//! against, measured on this machine with the same data.
//!
//! - `umbra bench receive`: a client that only receives depth and RGB through libfreenect (the
//!   same binding and buffer pools as `umbra run`) and does nothing else. Under fakenect this
//!   includes fakenect's own file reading, as `umbra run` does.
//! - `umbra bench zstd REC`: zstd alone compressing the bytes `umbra run` writes per frame (the
//!   four image messages and the stats message, CDR-encoded), one shot per frame at the level
//!   of the MCAP chunks.
//!
//! Both print CPU per frame and the share of one core at 30 fps, comparable line for line with
//! the CPU summary of `umbra run`.
//!
//! - `umbra bench classify REC`: the classifier alone (IR view, colour split, warp, RGB view) on a
//!   recording's frames held in memory, next to a plain copy of a depth frame timed in the same
//!   run: the project's speed figure, measured on any machine and any recording.

use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

use crate::capture::freenect::{Selector, Stream};
use crate::capture::replay::ReplaySource;
use crate::capture::Source;
use crate::classify::Classifier;
use crate::error::{Error, Result};
use crate::labels::{upside_down, HEIGHT, PIXELS, WIDTH};
use crate::pipeline::telemetry::{process_cpu_time, thread_cpu_time};
use crate::pipeline::Frame;
use crate::recording::Recording;
use crate::sink::mcap::ros2::{self, ImageHeader, Pixels};
use crate::sink::mcap::stats::FrameStats;
use crate::sink::mcap::writer::{DEPTH_FRAME_ID, RGB_FRAME_ID};

/// Arguments of `umbra bench`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// What to measure.
    #[command(subcommand)]
    pub what: What,
}

/// The measurements.
#[derive(clap::Subcommand, Debug)]
pub enum What {
    /// Receive frames through libfreenect and do nothing else (run it under fakenect to replay a
    /// recording).
    Receive {
        /// kinect, kinect:INDEX or kinect:SERIAL.
        #[arg(long, default_value = "kinect")]
        source: String,
        /// Stop after this many seconds (a fakenect recording may end earlier).
        #[arg(long, default_value_t = 60.0, value_parser = super::seconds_arg)]
        seconds: f64,
    },
    /// Time the classifier on a recording's frames held in memory, next to a plain frame copy.
    Classify {
        /// Recording folder.
        rec: PathBuf,
        /// Use at most this many frames, from the first; each is also classified upside down, so
        /// that no frame repeats back to back (a camera never repeats one).
        #[arg(long, default_value_t = 30)]
        frames: usize,
        /// Keep timing this long (at least one pass over the frames).
        #[arg(long, default_value_t = 3.0, value_parser = super::seconds_arg)]
        seconds: f64,
        /// Classify from depth alone, without the paired RGB images.
        #[arg(long)]
        no_rgb: bool,
    },
    /// Compress the bytes umbra writes per frame of a recording with zstd alone.
    Zstd {
        /// Recording folder.
        rec: PathBuf,
        /// zstd level (the MCAP writer's default is 1).
        #[arg(long, default_value_t = 1)]
        level: i32,
        /// Also compress the colour image (as with `[mcap] rgb = true`).
        #[arg(long)]
        rgb: bool,
        /// Play the recording this many times (short recordings give noisy figures).
        #[arg(long, default_value_t = 1)]
        repeat: u64,
    },
}

/// Runs `umbra bench`.
pub fn run(a: Args) -> Result<()> {
    match a.what {
        What::Receive { source, seconds } => receive(&source, seconds),
        What::Classify {
            rec,
            frames,
            seconds,
            no_rgb,
        } => classify_speed(rec, frames, seconds, !no_rgb),
        What::Zstd {
            rec,
            level,
            rgb,
            repeat,
        } => zstd_floor(rec, level, rgb, repeat),
    }
}

fn receive(source: &str, seconds: f64) -> Result<()> {
    let which = match source.split_once(':') {
        None if source == "kinect" => Selector::Index(0),
        Some(("kinect", w)) => w.parse()?,
        _ => {
            return Err(Error::Usage(format!(
                "--source {source:?}: expected kinect, kinect:INDEX or kinect:SERIAL"
            )))
        }
    };
    let stop = Arc::new(AtomicBool::new(false));
    let cpu0 = process_cpu_time();
    let stream = Stream::start(which, 8, stop.clone())?;
    let t0 = Instant::now();
    let limit = Duration::from_secs_f64(seconds.max(0.0));
    let (mut depth, mut rgb) = (0u64, 0u64);
    while t0.elapsed() < limit {
        crossbeam_channel::select! {
            recv(stream.depth) -> m => match m {
                Ok(f) => { depth += 1; let _ = stream.depth_free.try_send(f.data); }
                Err(_) => break,
            },
            recv(stream.video) -> m => match m {
                Ok(f) => { rgb += 1; let _ = stream.video_free.try_send(f.data); }
                Err(_) => break,
            },
            default(Duration::from_millis(100)) => {}
        }
    }
    stop.store(true, Ordering::SeqCst);
    let (dropped_depth, dropped_rgb) = stream.dropped();
    let elapsed = t0.elapsed();
    drop(stream);
    let cpu = process_cpu_time().saturating_sub(cpu0);
    let per = cpu.as_secs_f64() * 1e3 / depth.max(1) as f64;
    println!(
        "receive floor: {depth} depth + {rgb} RGB frames in {:.1} s ({dropped_depth}/{dropped_rgb} dropped): CPU {per:.2} ms per depth frame ({:.1}% of a core at 30 fps)",
        elapsed.as_secs_f64(),
        per * 30.0 / 10.0
    );
    Ok(())
}

/// One frame of `umbra bench classify`: depth and, when paired and wanted, RGB.
struct Held {
    depth: Vec<u16>,
    rgb: Option<Vec<u8>>,
}

fn classify_speed(dir: PathBuf, frames: usize, seconds: f64, use_rgb: bool) -> Result<()> {
    let rec = Recording::open(&dir)?;
    if frames == 0 || rec.is_empty() {
        return Err(Error::Usage(format!(
            "{}: no frames to time (the recording has {}, --frames {frames})",
            dir.display(),
            rec.len()
        )));
    }
    let mut held = Vec::new();
    let mut scratch = Vec::new();
    for i in 0..frames.min(rec.len()) {
        let mut depth = vec![0u16; PIXELS];
        rec.read_depth_with(i, &mut scratch, &mut depth)?;
        let mut rgb = vec![0u8; 3 * PIXELS];
        let rgb = (use_rgb && rec.read_rgb_with(i, &mut scratch, &mut rgb)?).then_some(rgb);
        let mirror = Held {
            depth: upside_down(&depth, WIDTH),
            rgb: rgb.as_deref().map(|c| upside_down(c, 3 * WIDTH)),
        };
        held.push(Held { depth, rgb });
        held.push(mirror);
    }
    let with_rgb = held.iter().filter(|h| h.rgb.is_some()).count() / 2;
    let mut classifier = Classifier::new(rec.calibration());
    let mut out = crate::classify::Classified::default();
    let mut copy = vec![0u16; PIXELS];
    let n = held.len() / 2;
    eprintln!(
        "timing {n} frame{} of {} ({with_rgb} with RGB) and their mirrors for {seconds:.1} s...",
        if n == 1 { "" } else { "s" },
        dir.display()
    );
    // One untimed pass: page faults and cold caches are not the classifier's.
    for h in &held {
        classifier.classify_with_rgb(&h.depth, h.rgb.as_deref(), &mut out);
    }
    let (mut times, mut copies) = (Vec::new(), Vec::new());
    let limit = Duration::from_secs_f64(seconds.max(0.0));
    let t0 = Instant::now();
    while times.is_empty() || t0.elapsed() < limit {
        for h in &held {
            let t = Instant::now();
            classifier.classify_with_rgb(
                std::hint::black_box(&h.depth),
                h.rgb.as_deref(),
                &mut out,
            );
            times.push(t.elapsed());
        }
        // The plain copy between passes, at the same clock: a batch of copies of one frame, its
        // source in cache after the first, as the criterion benchmark times it.
        const BATCH: u32 = 32;
        let t = Instant::now();
        for _ in 0..BATCH {
            copy.copy_from_slice(std::hint::black_box(&held[0].depth));
            std::hint::black_box(&copy);
        }
        copies.push(t.elapsed() / BATCH);
    }
    let ms = |d: Duration| d.as_secs_f64() * 1e3;
    let (median, p99) = (percentile(&mut times, 0.5), percentile(&mut times, 0.99));
    let mean = times.iter().sum::<Duration>() / times.len() as u32;
    let copy = percentile(&mut copies, 0.5);
    println!(
        "classify {} ({}, {}, {}): {} frames in {:.1} s, median {:.3} ms, mean {:.3} ms, p99 {:.3} ms per frame on one core",
        dir.display(),
        if with_rgb > 0 { "with RGB" } else { "depth only" },
        match rec.calibration_source() {
            crate::recording::CalibrationSource::File => "calibration.toml",
            crate::recording::CalibrationSource::DeviceJson => "calibration from device.json",
            crate::recording::CalibrationSource::Default => "NYU default calibration",
        },
        classifier.hot_loops(),
        times.len(),
        t0.elapsed().as_secs_f64(),
        ms(median),
        ms(mean),
        ms(p99),
    );
    println!(
        "plain copy of a depth frame in the same run: {:.1} µs (the median frame takes {:.0}× that)",
        copy.as_secs_f64() * 1e6,
        median.as_secs_f64() / copy.as_secs_f64().max(1e-9)
    );
    Ok(())
}

/// The `q` quantile of `times` (sorted in place): exact, where the pipeline's telemetry
/// histogram would round to its 20 µs buckets, a few percent of a frame's time.
fn percentile(times: &mut [Duration], q: f64) -> Duration {
    times.sort_unstable();
    let i = ((times.len() - 1) as f64 * q).round() as usize;
    times[i]
}

fn zstd_floor(dir: PathBuf, level: i32, rgb: bool, repeat: u64) -> Result<()> {
    let rec = Recording::open(&dir)?;
    let mut classifier = Classifier::new(rec.calibration());
    let mut source = ReplaySource::new(rec, rgb).repeat(repeat.max(1));
    let mut compressor = zstd::bulk::Compressor::new(level)
        .map_err(|e| Error::Usage(format!("zstd level {level}: {e}")))?;
    let mut frame = Frame::default();
    let (mut bytes, mut out, mut scratch) = (Vec::new(), Vec::new(), Vec::new());
    let (mut n, mut raw_total, mut packed_total, mut cpu) = (0u64, 0usize, 0usize, Duration::ZERO);
    while source.next_frame(&mut frame)? {
        classifier.classify(&frame.depth, &mut frame.labels);
        frame_bytes(&frame, rgb, &mut bytes, &mut scratch);
        out.clear();
        out.reserve(zstd::zstd_safe::compress_bound(bytes.len()));
        let t = thread_cpu_time();
        let packed = compressor
            .compress_to_buffer(&bytes, &mut out)
            .map_err(|e| Error::Usage(format!("zstd: {e}")))?;
        cpu += thread_cpu_time().saturating_sub(t);
        n += 1;
        raw_total += bytes.len();
        packed_total += packed;
    }
    let per = cpu.as_secs_f64() * 1e3 / n.max(1) as f64;
    println!(
        "zstd floor ({}, level {level}): {n} frames, {:.2} MB -> {:.2} MB per frame ({:.1}x): CPU {per:.2} ms per frame ({:.1}% of a core at 30 fps)",
        dir.display(),
        raw_total as f64 / n.max(1) as f64 / 1e6,
        packed_total as f64 / n.max(1) as f64 / 1e6,
        raw_total as f64 / packed_total.max(1) as f64,
        per * 30.0 / 10.0
    );
    Ok(())
}

/// The message bytes `umbra run` writes for `frame`, back to back.
fn frame_bytes(frame: &Frame, rgb: bool, out: &mut Vec<u8>, scratch: &mut Vec<u8>) {
    out.clear();
    let (sec, nanosec) = ros2::stamp(frame.unix_time);
    let w = WIDTH as u32;
    let image = |frame_id, encoding, bytes_pp: u32| ImageHeader {
        sec,
        nanosec,
        frame_id,
        height: HEIGHT as u32,
        width: w,
        encoding,
        is_bigendian: 0,
        step: w * bytes_pp,
    };
    ros2::encode_image(
        &image(DEPTH_FRAME_ID, "16UC1", 2),
        Pixels::U16(&frame.depth),
        out,
    );
    ros2::encode_image(
        &image(DEPTH_FRAME_ID, "mono8", 1),
        Pixels::U8(&frame.labels.ir_labels),
        out,
    );
    ros2::encode_image(
        &image(RGB_FRAME_ID, "16UC1", 2),
        Pixels::U16(&frame.labels.registered_mm),
        out,
    );
    ros2::encode_image(
        &image(RGB_FRAME_ID, "mono8", 1),
        Pixels::U8(&frame.labels.rgb_labels),
        out,
    );
    if rgb && frame.has_rgb {
        ros2::encode_image(&image(RGB_FRAME_ID, "rgb8", 3), Pixels::U8(&frame.rgb), out);
    }
    scratch.clear();
    let _ = serde_json::to_writer(&mut *scratch, &FrameStats::of(frame, 0.0, 0));
    out.extend_from_slice(scratch);
}
