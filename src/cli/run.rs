//! `umbra run [--config FILE] [--source SRC] [--out DIR]`: the capture daemon. Frames from a
//! Kinect (or a recording paced at its recorded speed) are classified and written until the
//! source ends or SIGINT/SIGTERM asks to stop; then the pipeline drains, sinks finish and the
//! process exits 0.
//!
//! Signals are handled with `signal-hook`: the first SIGINT/SIGTERM sets a flag the source polls;
//! a second one exits at once (status 1) in case shutdown ever hangs.

use std::path::{Path, PathBuf};
use std::str::FromStr;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::Duration;

use tracing::{info, warn};

use crate::calib::Calibration;
use crate::capture::freenect::Selector;
use crate::capture::kinect::KinectSource;
use crate::capture::pace::Paced;
use crate::capture::reconnect::{Opener, Reconnecting};
use crate::capture::replay::ReplaySource;
use crate::capture::Source;
use crate::classify::Classifier;
use crate::config::Config;
use crate::error::{Error, Result};
use crate::pipeline::{self, Options, Stats, Telemetry};
use crate::recording::Recording;
use crate::service::{self, Extra, Reporter};
use crate::sink::foreground::WithForeground;
use crate::sink::mcap::McapSink;
use crate::sink::{LabelExport, Sink, Tolerant};

/// Arguments of `umbra run`. Flags override the `[run]` keys of the config file.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Settings file (see config/umbra.toml); built-in defaults without it.
    #[arg(long, value_name = "FILE")]
    pub config: Option<PathBuf>,
    /// Validate the settings (config file, flags, source, output folder) and exit.
    #[arg(long)]
    pub check_config: bool,
    /// Where frames come from: kinect (first device), kinect:INDEX, kinect:SERIAL or replay:DIR
    /// [config: run.source, default kinect].
    #[arg(long, value_name = "SRC")]
    pub source: Option<SourceSpec>,
    /// Output folder for MCAP segments [config: run.out].
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
    /// Also write SPEC §4 label PNGs into this folder [config: run.export_labels].
    #[arg(long, value_name = "DIR")]
    pub export_labels: Option<PathBuf>,
    /// With replay:DIR, read frames as fast as possible instead of at recorded speed [config: run.fast].
    #[arg(long)]
    pub fast: bool,
    /// With replay:DIR, play the recording this many times in a row (soak tests).
    #[arg(long, value_name = "N", default_value_t = 1)]
    pub repeat: u64,
    /// Calibration file (SPEC §3 calibration.toml) to use instead of the source's own
    /// [config: run.calibration].
    #[arg(long, value_name = "FILE")]
    pub calibration: Option<PathBuf>,
}

/// The settings of one run: config file and flags merged, checked.
#[derive(Debug)]
struct Settings {
    config: Config,
    source: SourceSpec,
    out: PathBuf,
    export_labels: Option<PathBuf>,
    fast: bool,
    calibration: Option<Calibration>,
}

impl Settings {
    fn resolve(a: &Args) -> Result<Settings> {
        let config = Config::load_or_default(a.config.as_deref())?;
        let r = &config.run;
        let source = match &a.source {
            Some(s) => s.clone(),
            None => r.source.parse()?,
        };
        let out = a.out.clone().or_else(|| r.out.clone()).ok_or_else(|| {
            Error::Usage(
                "no output folder: pass --out DIR or set run.out in the config file".into(),
            )
        })?;
        check_output_folder(&out)?;
        let export_labels = a.export_labels.clone().or_else(|| r.export_labels.clone());
        if let Some(d) = &export_labels {
            check_output_folder(d)?;
        }
        let calibration = a
            .calibration
            .as_deref()
            .or(r.calibration.as_deref())
            .map(Calibration::load)
            .transpose()?;
        if a.repeat == 0 {
            return Err(Error::Usage("--repeat must be at least 1".into()));
        }
        if a.repeat > 1 && !matches!(source, SourceSpec::Replay(_)) {
            return Err(Error::Usage(
                "--repeat only applies to replay:DIR sources".into(),
            ));
        }
        Ok(Settings {
            fast: a.fast || r.fast,
            config,
            source,
            out,
            export_labels,
            calibration,
        })
    }
}

/// An output folder must be a folder we can create files in, or creatable.
fn check_output_folder(dir: &Path) -> Result<()> {
    if dir.exists() {
        if !dir.is_dir() {
            return Err(Error::input(
                dir,
                "",
                "exists and is not a folder: give a folder for the output",
            ));
        }
        let probe = dir.join(format!(".umbra-write-test-{}", std::process::id()));
        std::fs::write(&probe, b"")
            .map_err(|e| Error::io(dir, "creating a file in the output folder", e))?;
        let _ = std::fs::remove_file(&probe);
        return Ok(());
    }
    // Missing: its nearest existing ancestor must be a folder (create_dir_all makes the rest).
    let mut up = dir.parent();
    while let Some(p) = up {
        if p.as_os_str().is_empty() || p.is_dir() {
            return Ok(());
        }
        if p.exists() {
            return Err(Error::input(
                p,
                "",
                format!(
                    "is not a folder, so output folder {} cannot be created",
                    dir.display()
                ),
            ));
        }
        up = p.parent();
    }
    Ok(())
}

/// A parsed `--source`.
#[derive(Clone, Debug, PartialEq)]
pub enum SourceSpec {
    /// A Kinect through libfreenect (or fakenect).
    Kinect(Selector),
    /// A recording folder.
    Replay(PathBuf),
}

impl std::fmt::Display for SourceSpec {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            SourceSpec::Kinect(which) => write!(f, "kinect ({which})"),
            SourceSpec::Replay(dir) => write!(f, "replay:{}", dir.display()),
        }
    }
}

impl FromStr for SourceSpec {
    type Err = Error;

    fn from_str(s: &str) -> Result<Self> {
        match s.split_once(':') {
            None if s == "kinect" => Ok(SourceSpec::Kinect(Selector::Index(0))),
            Some(("kinect", which)) => Ok(SourceSpec::Kinect(which.parse()?)),
            Some(("replay", dir)) if !dir.is_empty() => Ok(SourceSpec::Replay(PathBuf::from(dir))),
            _ => Err(Error::Usage(format!(
                "--source {s:?}: expected kinect, kinect:INDEX, kinect:SERIAL or replay:DIR"
            ))),
        }
    }
}

/// Runs `umbra run`.
pub fn run(a: Args) -> Result<()> {
    let settings = Settings::resolve(&a)?;
    if a.check_config {
        return check_config(&a, &settings);
    }
    let stop = Arc::new(AtomicBool::new(false));
    install_signal_handlers(&stop)?;
    let Settings {
        config,
        source,
        out,
        export_labels,
        fast,
        calibration: override_calibration,
    } = settings;
    let mcap_opts = config.mcap_options();

    let mut extra = Extra::default();
    let (source, calibration): (Box<dyn Source>, Calibration) = match &source {
        SourceSpec::Kinect(which) => {
            let stall = Duration::from_secs_f64(config.device.stall_timeout_s);
            let open_kinect = {
                let (which, stop) = (which.clone(), stop.clone());
                move || -> Result<Box<dyn Source>> {
                    let mut k = KinectSource::open(which.clone(), stop.clone())?;
                    k.set_stall_timeout(stall);
                    Ok(Box::new(k))
                }
            };
            let mut first = KinectSource::open(which.clone(), stop.clone())?;
            first.set_stall_timeout(stall);
            let (calib, origin) = first.calibration();
            let calib = *calib;
            if override_calibration.is_none() {
                info!(calibration = %origin, "calibration from the device");
            }
            let r = Reconnecting::new(
                Box::new(first),
                Box::new(open_kinect) as Opener,
                config.backoff(),
                stop.clone(),
            );
            extra.reconnects = Some(r.reconnect_counter());
            (Box::new(r), calib)
        }
        SourceSpec::Replay(dir) => {
            let rec = Recording::open(dir)?;
            let calib = *rec.calibration();
            info!(
                frames = rec.len(),
                passes = a.repeat,
                realtime = !fast,
                "replaying {}",
                dir.display()
            );
            // The classifier's colour split reads the RGB image, as it does live.
            let replay = ReplaySource::new(rec, true).repeat(a.repeat);
            (Box::new(Paced::new(replay, stop.clone(), !fast)), calib)
        }
    };
    let calibration = override_calibration.unwrap_or(calibration);

    let mcap = McapSink::create(&out, mcap_opts)?;
    let mcap_counters = mcap.counters();
    let rate_hz = config.foreground.rate_hz;
    let mut sinks: Vec<Box<dyn Sink>> = if rate_hz > 0.0 {
        info!(
            rate_hz,
            "foreground masks on {}",
            crate::sink::mcap::topics::FOREGROUND_MASK
        );
        let segmenter = crate::segment::Segmenter::new(crate::segment::Params::default());
        vec![Box::new(WithForeground::new(
            mcap,
            Box::new(segmenter),
            rate_hz,
        ))]
    } else {
        vec![Box::new(mcap)]
    };
    if let Some(dir) = &export_labels {
        let labels = Tolerant::new(LabelExport::append(dir)?, "label PNGs");
        let lost = labels.lost_counter();
        extra
            .lost
            .push(Box::new(move || lost.load(Ordering::Relaxed)));
        sinks.push(Box::new(labels));
    }
    let c = mcap_counters.clone();
    extra
        .lost
        .push(Box::new(move || c.frames_lost.load(Ordering::Relaxed)));

    let telemetry = Arc::new(Telemetry::default());
    let reporter = Reporter::start(
        telemetry.clone(),
        extra,
        Duration::from_secs_f64(config.run.status_interval_s),
    );
    service::notify_ready();
    info!(out = %out.display(), "capturing");
    let cpu0 = pipeline::telemetry::process_cpu_time();
    let classifier = Classifier::with_params(&calibration, config.params());
    let opts = Options {
        telemetry: telemetry.clone(),
        ..Options::default()
    };
    let result = pipeline::run(source, classifier, &mut sinks, opts, |_| {});
    service::notify_stopping();
    drop(reporter);
    let stats = result?;
    let cpu = pipeline::telemetry::process_cpu_time().saturating_sub(cpu0);
    let lost = mcap_counters.frames_lost.load(Ordering::Relaxed);
    let line = summary(&stats, lost, cpu, stop.load(Ordering::SeqCst));
    info!("{line}");
    println!("{line}");
    if lost > 0 {
        warn!(lost, "frames could not be written to {}", out.display());
    }
    Ok(())
}

/// `--check-config`: everything that can be checked without starting capture.
fn check_config(a: &Args, s: &Settings) -> Result<()> {
    match &s.source {
        SourceSpec::Replay(dir) => {
            Recording::open(dir)?;
        }
        SourceSpec::Kinect(_) => {
            // Whether the device is there is a run-time matter; the library must be.
            if let Err(e) = crate::capture::freenect::library::load() {
                warn!("{e}");
            }
        }
    }
    let file = a
        .config
        .as_ref()
        .map_or("built-in defaults".to_string(), |p| p.display().to_string());
    println!(
        "config OK ({file}): source {}, out {}, label PNGs {}, {}",
        s.source,
        s.out.display(),
        s.export_labels
            .as_ref()
            .map_or("off".to_string(), |p| p.display().to_string()),
        if s.calibration.is_some() {
            "calibration from file"
        } else {
            "calibration from the source"
        }
    );
    Ok(())
}

/// First SIGINT/SIGTERM: set `stop`. Second: exit at once with status 1.
pub(crate) fn install_signal_handlers(stop: &Arc<AtomicBool>) -> Result<()> {
    use signal_hook::consts::{SIGINT, SIGTERM};
    for sig in [SIGINT, SIGTERM] {
        // The shutdown action goes first so that it only fires once the flag is already set.
        signal_hook::flag::register_conditional_shutdown(sig, 1, stop.clone())
            .and_then(|_| signal_hook::flag::register(sig, stop.clone()))
            .map_err(|e| Error::Usage(format!("cannot install the signal handlers: {e}")))?;
    }
    Ok(())
}

/// The end-of-run summary: counts, rates, latency and CPU per stage.
pub fn summary(s: &Stats, lost: u64, cpu: Duration, stopped: bool) -> String {
    let t = &s.telemetry;
    let n = s.frames.max(1) as f64;
    let per_frame = |us: u64| us as f64 / 1e3 / n;
    let cpu_us = |i: usize| t.cpu_us[i].load(Ordering::Relaxed);
    format!(
        "umbra run: {} frames written, {} depth and {} RGB frames dropped, {} lost by outputs, {} malformed, {:.1} frames/s over {:.2} s{}\n\
         latency mean/p50/p99/max: received->written {}, queue {}, classify {}, write {}\n\
         queue depth mean/max: to classify {:.2}/{}, to write {:.2}/{}\n\
         CPU per frame: {:.2} ms total ({:.1}% of a core at 30 fps): read {:.2} ms, classify {:.2} ms, write {:.2} ms, \
         capture and other threads {:.2} ms",
        s.frames,
        t.frames_dropped.load(Ordering::Relaxed),
        t.rgb_dropped.load(Ordering::Relaxed),
        lost,
        t.frames_malformed.load(Ordering::Relaxed),
        s.fps(),
        s.elapsed.as_secs_f64(),
        if stopped { " (stopped by signal)" } else { "" },
        t.total_latency.summary(),
        t.queue_latency.summary(),
        t.classify_latency.summary(),
        t.write_latency.summary(),
        t.classify_queue.mean(),
        t.classify_queue.max(),
        t.write_queue.mean(),
        t.write_queue.max(),
        cpu.as_secs_f64() * 1e3 / n,
        cpu.as_secs_f64() / n * 30.0 * 100.0,
        per_frame(cpu_us(0)),
        per_frame(cpu_us(1)),
        per_frame(cpu_us(2)),
        // The libfreenect event thread (USB or fakenect's file reads, our callbacks' copies),
        // the status reporter and the MCAP sync thread: what the process used beyond the stages.
        (cpu.as_secs_f64() * 1e3 / n - per_frame(cpu_us(0) + cpu_us(1) + cpu_us(2))).max(0.0),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_sources() {
        assert_eq!(
            "kinect".parse::<SourceSpec>().unwrap(),
            SourceSpec::Kinect(Selector::Index(0))
        );
        assert_eq!(
            "kinect:2".parse::<SourceSpec>().unwrap(),
            SourceSpec::Kinect(Selector::Index(2))
        );
        assert_eq!(
            "kinect:A00362A09433114A".parse::<SourceSpec>().unwrap(),
            SourceSpec::Kinect(Selector::Serial("A00362A09433114A".into()))
        );
        assert_eq!(
            "replay:/tmp/rec".parse::<SourceSpec>().unwrap(),
            SourceSpec::Replay("/tmp/rec".into())
        );
        for bad in ["kinekt", "replay:", "kinect:a b", "usb:1"] {
            assert!(bad.parse::<SourceSpec>().is_err(), "{bad}");
        }
    }
}
