//! `umbra record --out DIR [--seconds S | --frames N]`: records a live Kinect (or fakenect) as a
//! fakenect-format recording (SPEC §3) with the device's `calibration.toml`, so users make their
//! own CI data. Every depth and RGB frame is written as delivered; a disk too slow to keep up
//! makes the capture pools drop frames (counted and reported), never block the USB thread.

use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

use tracing::info;

use crate::calib::Calibration;
use crate::capture::kinect::KinectSource;
use crate::cli::run::{install_signal_handlers, SourceSpec};
use crate::error::{Error, Result};
use crate::recording::writer::RecordingWriter;

/// Arguments of `umbra record`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// New (or empty) folder for the recording.
    #[arg(long, value_name = "DIR")]
    pub out: PathBuf,
    /// Which Kinect: kinect (first), kinect:INDEX or kinect:SERIAL.
    #[arg(long, value_name = "SRC", default_value = "kinect")]
    pub source: SourceSpec,
    /// Stop after this many seconds.
    #[arg(long, value_name = "S", conflicts_with = "frames", value_parser = super::seconds_arg)]
    pub seconds: Option<f64>,
    /// Stop after this many depth frames.
    #[arg(long, value_name = "N")]
    pub frames: Option<u64>,
    /// Write this calibration (SPEC §3 calibration.toml) instead of the device's.
    #[arg(long, value_name = "FILE")]
    pub calibration: Option<PathBuf>,
}

/// Runs `umbra record`; without --seconds or --frames it records until SIGINT/SIGTERM.
pub fn run(a: Args) -> Result<()> {
    let SourceSpec::Kinect(which) = &a.source else {
        return Err(Error::Usage(
            "umbra record records a Kinect: --source kinect, kinect:INDEX or kinect:SERIAL".into(),
        ));
    };
    if a.seconds == Some(0.0) {
        return Err(Error::Usage("--seconds 0: expected more than 0".into()));
    }
    if a.frames == Some(0) {
        return Err(Error::Usage("--frames 0: expected at least 1".into()));
    }
    let override_calibration = a
        .calibration
        .as_deref()
        .map(Calibration::load)
        .transpose()?;
    // Refuse a used folder before touching the device; leave nothing behind if it cannot start.
    let existed = a.out.exists();
    let mut writer = RecordingWriter::create(&a.out)?;
    let stop = Arc::new(AtomicBool::new(false));
    install_signal_handlers(&stop)?;
    let kinect = match KinectSource::open(which.clone(), stop.clone()) {
        Ok(k) => k,
        Err(e) => {
            drop(writer);
            let _ = std::fs::remove_file(a.out.join("INDEX.txt"));
            if !existed {
                let _ = std::fs::remove_dir(&a.out);
            }
            return Err(e);
        }
    };
    let (stream, device_calibration, origin) = kinect.into_stream();
    let calibration = override_calibration.unwrap_or(device_calibration);
    info!(calibration = %origin, out = %a.out.display(), "recording");

    let limit = a.seconds.map(Duration::from_secs_f64);
    let bar = crate::cli::progress_bar(
        a.frames
            .unwrap_or_else(|| (a.seconds.unwrap_or(0.0) * 30.0).ceil() as u64),
        "depth frames",
    );
    bar.set_prefix("record");
    let t0 = Instant::now();
    let mut ended = false;
    let result = loop {
        let done = stop.load(Ordering::SeqCst)
            || limit.is_some_and(|l| t0.elapsed() >= l)
            || a.frames.is_some_and(|n| writer.counts().0 >= n);
        if done || ended {
            break Ok(());
        }
        crossbeam_channel::select! {
            recv(stream.depth) -> m => match m {
                Ok(f) => {
                    let r = writer.write_depth(f.unix_time, f.ts, &f.data);
                    let _ = stream.depth_free.try_send(f.data);
                    if let Err(e) = r { break Err(e); }
                    bar.inc(1);
                }
                Err(_) => ended = true,
            },
            recv(stream.video) -> m => match m {
                Ok(f) => {
                    let r = writer.write_rgb(f.unix_time, f.ts, &f.data);
                    let _ = stream.video_free.try_send(f.data);
                    if let Err(e) = r { break Err(e); }
                }
                Err(_) => ended = true,
            },
            default(Duration::from_millis(100)) => {}
        }
    };
    bar.finish_and_clear();
    let failure = stream.take_failure();
    let (dropped_depth, dropped_rgb) = stream.dropped();
    drop(stream);
    let elapsed = t0.elapsed().as_secs_f64();
    let (depth, rgb) = writer.counts();
    // What was recorded stays a valid recording, whatever ended it.
    writer.finish(&calibration)?;
    result?;
    if let Some(e) = failure {
        return Err(e);
    }
    println!(
        "umbra record: {depth} depth and {rgb} RGB frames in {elapsed:.1} s to {} ({dropped_depth} depth and {dropped_rgb} RGB frames dropped{})",
        a.out.display(),
        if stop.load(Ordering::SeqCst) { ", stopped by signal" } else { "" }
    );
    Ok(())
}
