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

use tracing::info;

use crate::calib::Calibration;
use crate::capture::freenect::{DropCounters, Selector};
use crate::capture::kinect::KinectSource;
use crate::capture::pace::Paced;
use crate::capture::replay::ReplaySource;
use crate::capture::Source;
use crate::classify::Classifier;
use crate::config::Config;
use crate::error::{Error, Result};
use crate::pipeline::{self, Options, Stats};
use crate::recording::Recording;
use crate::sink::{LabelExport, Sink};

/// Arguments of `umbra run`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Settings file (see config/umbra.toml); built-in defaults without it.
    #[arg(long, value_name = "FILE")]
    pub config: Option<PathBuf>,
    /// Where frames come from: kinect (first device), kinect:INDEX, kinect:SERIAL or replay:DIR.
    #[arg(long, value_name = "SRC", default_value = "kinect")]
    pub source: SourceSpec,
    /// Output folder.
    #[arg(long, value_name = "DIR")]
    pub out: PathBuf,
    /// With replay:DIR, read frames as fast as possible instead of at recorded speed.
    #[arg(long)]
    pub fast: bool,
    /// Calibration file (SPEC §3 calibration.toml) to use instead of the source's own.
    #[arg(long, value_name = "FILE")]
    pub calibration: Option<PathBuf>,
}

/// A parsed `--source`.
#[derive(Clone, Debug, PartialEq)]
pub enum SourceSpec {
    /// A Kinect through libfreenect (or fakenect).
    Kinect(Selector),
    /// A recording folder.
    Replay(PathBuf),
}

impl FromStr for SourceSpec {
    type Err = Error;

    fn from_str(s: &str) -> Result<Self> {
        match s.split_once(':') {
            None if s == "kinect" => Ok(SourceSpec::Kinect(Selector::Index(0))),
            Some(("kinect", which)) => Ok(SourceSpec::Kinect(which.parse()?)),
            Some(("replay", dir)) if !dir.is_empty() => Ok(SourceSpec::Replay(PathBuf::from(dir))),
            _ => Err(Error::Usage(format!("--source {s:?}: expected kinect, kinect:INDEX, kinect:SERIAL or replay:DIR"))),
        }
    }
}

/// Runs `umbra run`.
pub fn run(a: Args) -> Result<()> {
    let config = Config::load_or_default(a.config.as_deref())?;
    let override_calibration = a.calibration.as_deref().map(Calibration::load).transpose()?;
    let stop = Arc::new(AtomicBool::new(false));
    install_signal_handlers(&stop)?;

    let (source, calibration, drops): (Box<dyn Source>, Calibration, Option<DropCounters>) = match &a.source {
        SourceSpec::Kinect(which) => {
            let k = KinectSource::open(which.clone(), stop.clone())?;
            let (calib, origin) = k.calibration();
            let calib = *calib;
            if override_calibration.is_none() {
                info!(calibration = %origin, "calibration from the device");
            }
            let drops = k.drop_counters();
            (Box::new(k), calib, Some(drops))
        }
        SourceSpec::Replay(dir) => {
            let rec = Recording::open(dir)?;
            let calib = *rec.calibration();
            info!(frames = rec.len(), realtime = !a.fast, "replaying {}", dir.display());
            (Box::new(Paced::new(ReplaySource::new(rec, false), stop.clone(), !a.fast)), calib, None)
        }
    };
    let calibration = override_calibration.unwrap_or(calibration);
    let mut sinks = build_sinks(&a.out)?;
    let classifier = Classifier::with_params(&calibration, config.params());
    let stats = pipeline::run(source, classifier, &mut sinks, Options::default(), |_| {})?;
    let (depth_dropped, rgb_dropped) = drops.map_or((stats.dropped, 0), |(d, r)| (d.load(Ordering::Relaxed), r.load(Ordering::Relaxed)));
    let line = summary(&stats, depth_dropped, rgb_dropped, stop.load(Ordering::SeqCst));
    info!("{line}");
    println!("{line}");
    Ok(())
}

/// The sinks `umbra run` writes to. This is the one place to add more (the MCAP segment writer).
fn build_sinks(out: &Path) -> Result<Vec<Box<dyn Sink>>> {
    let sinks: Vec<Box<dyn Sink>> = vec![Box::new(LabelExport::create(out)?)];
    Ok(sinks)
}

/// First SIGINT/SIGTERM: set `stop`. Second: exit at once with status 1.
fn install_signal_handlers(stop: &Arc<AtomicBool>) -> Result<()> {
    use signal_hook::consts::{SIGINT, SIGTERM};
    for sig in [SIGINT, SIGTERM] {
        // The shutdown action goes first so that it only fires once the flag is already set.
        signal_hook::flag::register_conditional_shutdown(sig, 1, stop.clone())
            .and_then(|_| signal_hook::flag::register(sig, stop.clone()))
            .map_err(|e| Error::Usage(format!("cannot install the signal handlers: {e}")))?;
    }
    Ok(())
}

/// The one-line end-of-run summary.
pub fn summary(s: &Stats, depth_dropped: u64, rgb_dropped: u64, stopped: bool) -> String {
    format!(
        "umbra run: {} frames written, {} depth and {} RGB frames dropped, {:.1} frames/s over {:.2} s{}",
        s.frames,
        depth_dropped,
        rgb_dropped,
        s.fps(),
        s.elapsed.as_secs_f64(),
        if stopped { " (stopped by signal)" } else { "" }
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_sources() {
        assert_eq!("kinect".parse::<SourceSpec>().unwrap(), SourceSpec::Kinect(Selector::Index(0)));
        assert_eq!("kinect:2".parse::<SourceSpec>().unwrap(), SourceSpec::Kinect(Selector::Index(2)));
        assert_eq!("kinect:A00362A09433114A".parse::<SourceSpec>().unwrap(), SourceSpec::Kinect(Selector::Serial("A00362A09433114A".into())));
        assert_eq!("replay:/tmp/rec".parse::<SourceSpec>().unwrap(), SourceSpec::Replay("/tmp/rec".into()));
        for bad in ["kinekt", "replay:", "kinect:a b", "usb:1"] {
            assert!(bad.parse::<SourceSpec>().is_err(), "{bad}");
        }
    }
}
