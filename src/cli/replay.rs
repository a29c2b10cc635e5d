//! `umbra replay REC [--export-labels DIR]`: classify a recording as fast as possible.

use std::path::PathBuf;

use crate::capture::replay::ReplaySource;
use crate::classify::Classifier;
use crate::config::Config;
use crate::labels::{CLASSES, NAMES};
use crate::pipeline::{self, Options, Stats};
use crate::recording::Recording;
use crate::sink::mcap::{McapOptions, McapSink};
use crate::sink::{LabelExport, Sink};

/// Arguments of `umbra replay`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Recording folder (fakenect format: INDEX.txt, d-*.pgm, r-*.ppm).
    pub recording: PathBuf,
    /// Write SPEC §4 label PNGs (<i:06>.depth.png, <i:06>.rgb.png) into this folder.
    #[arg(long, value_name = "DIR")]
    pub export_labels: Option<PathBuf>,
    /// Also write the frames as MCAP segments (ROS 2 sensor_msgs/Image topics) into this folder,
    /// for Foxglove, `ros2 bag` or `umbra tail`.
    #[arg(long, value_name = "DIR")]
    pub mcap: Option<PathBuf>,
    /// Settings file (see config/umbra.toml); built-in defaults without it.
    #[arg(long, value_name = "FILE")]
    pub config: Option<PathBuf>,
}

/// A replay is not live: there is no capture latency and nothing is dropped, so frames go to the
/// MCAP sink with latency 0 and no drops (its `Sink::write` would derive latency from the
/// recording's old timestamps).
struct ReplayMcap(McapSink);

impl Sink for ReplayMcap {
    fn write(&mut self, frame: &crate::pipeline::Frame) -> crate::Result<()> {
        self.0.write_with(frame, 0.0, 0);
        Ok(())
    }

    fn finish(&mut self) -> crate::Result<()> {
        self.0.finish()
    }
}

/// Runs `umbra replay`.
pub fn run(a: Args) -> crate::Result<()> {
    let config = Config::load_or_default(a.config.as_deref())?;
    let rec = Recording::open(&a.recording)?;
    rec.warn_doubts();
    let classifier = Classifier::with_params(rec.calibration(), config.params());
    tracing::info!(frames = rec.len(), calibration = ?rec.calibration_source(), "replaying {}", a.recording.display());
    let mut sinks: Vec<Box<dyn Sink>> = Vec::new();
    if let Some(dir) = &a.export_labels {
        sinks.push(Box::new(LabelExport::create(dir)?));
    }
    let mcap_counters = match &a.mcap {
        Some(dir) => {
            let sink = McapSink::create(dir, McapOptions::default())?;
            let counters = sink.counters();
            sinks.push(Box::new(ReplayMcap(sink)));
            Some(counters)
        }
        None => None,
    };
    let bar = super::progress_bar(rec.len() as u64, "frames");
    // With RGB: the classifier's colour split reads it, as it does in the daemon.
    let source = Box::new(ReplaySource::new(rec, true));
    let stats = pipeline::run(source, classifier, &mut sinks, Options::default(), |_| {
        bar.inc(1)
    });
    bar.finish_and_clear();
    let stats = stats?;
    print!("{}", summary(&stats));
    if let Some(dir) = &a.export_labels {
        println!("labels written to {}", dir.display());
    }
    if let (Some(dir), Some(c)) = (&a.mcap, mcap_counters) {
        // The MCAP sink keeps going through write errors (a daemon must); a replay must not
        // pretend it wrote everything.
        let lost = c.frames_lost.load(std::sync::atomic::Ordering::Relaxed);
        if lost > 0 {
            return Err(crate::Error::input(
                dir,
                "",
                format!(
                    "{lost} of {} frames could not be written (see the warnings above)",
                    stats.frames
                ),
            ));
        }
        println!("MCAP segments written to {}", dir.display());
    }
    Ok(())
}

/// The end-of-run summary: frames, per-class pixel shares per view, speed.
pub fn summary(s: &Stats) -> String {
    let mut out = format!(
        "{} in {:.2} s: {:.1} frames/s overall, classification {:.2} ms/frame\n",
        super::count(s.frames, "frame"),
        s.elapsed.as_secs_f64(),
        s.fps(),
        1e3 * s.classify_time.as_secs_f64() / (s.frames.max(1) as f64)
    );
    out.push_str(&format!("{:<6}", "view"));
    for name in NAMES {
        out.push_str(&format!("{name:>11}"));
    }
    out.push('\n');
    for (view, counts) in [("ir", &s.ir), ("rgb", &s.rgb)] {
        let total: u64 = counts.iter().sum();
        out.push_str(&format!("{view:<6}"));
        for (c, &n) in counts.iter().enumerate().take(CLASSES) {
            let share = 100.0 * n as f64 / total.max(1) as f64;
            if view == "ir" && c == crate::labels::ALIGNMENT as usize {
                out.push_str(&format!("{:>11}", "-"));
            } else {
                out.push_str(&format!("{share:>10.2}%"));
            }
        }
        out.push('\n');
    }
    out
}
