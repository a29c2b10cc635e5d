//! `umbra eval`: classifies every frame of one recording (or of each recording in a folder) and
//! scores the labels against ground-truth label PNGs.

use std::path::{Path, PathBuf};

use indicatif::ProgressBar;

use crate::classify::{Classified, Classifier};
use crate::error::{Error, Result};
use crate::eval::{read_category, Report, Tally};
use crate::sink::labels::{read_label_png, write_label_png};
use crate::labels::PIXELS;
use crate::recording::Recording;

/// Arguments of `umbra eval`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// A recording folder (with INDEX.txt), or a folder whose subfolders are recordings.
    pub recording: PathBuf,
    /// Ground truth: <i:06>.depth.png and <i:06>.rgb.png per depth frame, optional meta.toml;
    /// for a folder of recordings, one subfolder per recording with the same name.
    #[arg(long, value_name = "DIR")]
    pub gt: PathBuf,
    /// Print one JSON object instead of the table.
    #[arg(long)]
    pub json: bool,
    /// Also write the predicted labels as SPEC §4 PNGs here (one subfolder per recording when
    /// RECORDING is a folder of recordings).
    #[arg(long, value_name = "DIR")]
    pub export_labels: Option<PathBuf>,
    /// Settings file (see config/umbra.toml); built-in defaults without it.
    #[arg(long, value_name = "FILE")]
    pub config: Option<PathBuf>,
}

/// One recording to score, with where its ground truth and exported labels go.
struct Job {
    name: String,
    rec: Recording,
    gt: PathBuf,
    export: Option<PathBuf>,
}

/// Runs `umbra eval`.
pub fn run(a: Args) -> Result<()> {
    let params = crate::config::Config::load_or_default(a.config.as_deref())?.params();
    let jobs = plan(&a)?;
    let total: u64 = jobs.iter().map(|j| j.rec.len() as u64).sum();
    let bar = super::progress_bar(total, "frames");
    let mut report = Report::default();
    for job in &jobs {
        bar.set_prefix(job.name.clone());
        let tally = score(job, params, &bar)?;
        let category = read_category(&job.gt.join("meta.toml"))?;
        report.add_recording(job.name.clone(), category, tally);
    }
    bar.finish_and_clear();
    if a.json {
        println!("{}", report.to_json());
    } else {
        print!("{}", report.to_table());
    }
    Ok(())
}

/// Works out whether RECORDING is one recording or a folder of them, and pairs each with its
/// ground-truth folder.
fn plan(a: &Args) -> Result<Vec<Job>> {
    if let Some(dir) = &a.export_labels {
        // Exported labels use the ground truth's file names: never let them overwrite it.
        if dir.canonicalize().ok().is_some_and(|d| a.gt.canonicalize().ok() == Some(d)) {
            return Err(Error::Usage(format!(
                "--export-labels {} is the --gt folder: writing there would overwrite the ground truth; pick another folder",
                dir.display()
            )));
        }
    }
    if a.recording.join("INDEX.txt").is_file() {
        let name = a.recording.file_name().map_or_else(|| a.recording.display().to_string(), |n| n.to_string_lossy().into_owned());
        let rec = Recording::open(&a.recording)?;
        return Ok(vec![Job { name, rec, gt: a.gt.clone(), export: a.export_labels.clone() }]);
    }
    let entries = std::fs::read_dir(&a.recording).map_err(|e| Error::io(&a.recording, "listing", e))?;
    let mut names = Vec::new();
    for entry in entries {
        let entry = entry.map_err(|e| Error::io(&a.recording, "listing", e))?;
        if entry.path().join("INDEX.txt").is_file() {
            names.push(entry.file_name().to_string_lossy().into_owned());
        }
    }
    if names.is_empty() {
        return Err(Error::input(
            &a.recording,
            "",
            "is neither a recording (no INDEX.txt) nor a folder of recordings (no subfolder has INDEX.txt)",
        ));
    }
    names.sort();
    names
        .into_iter()
        .map(|name| {
            let rec = Recording::open(&a.recording.join(&name))?;
            let gt = a.gt.join(&name);
            if !gt.is_dir() {
                return Err(Error::input(&gt, "", format!("missing: expected ground truth for recording {name} in this folder")));
            }
            let export = a.export_labels.as_ref().map(|d| d.join(&name));
            Ok(Job { name, rec, gt, export })
        })
        .collect()
}

/// Classifies every frame of one recording and counts it against ground truth.
fn score(job: &Job, params: crate::classify::Params, bar: &ProgressBar) -> Result<Tally> {
    if let Some(dir) = &job.export {
        std::fs::create_dir_all(dir).map_err(|e| Error::io(dir, "creating", e))?;
    }
    let mut classifier = Classifier::with_params(job.rec.calibration(), params);
    let mut out = Classified::default();
    let mut raw = vec![0u16; PIXELS];
    let (mut gt_ir, mut gt_rgb) = (vec![0u8; PIXELS], vec![0u8; PIXELS]);
    let mut tally = Tally::default();
    for i in 0..job.rec.len() {
        // Read ground truth first: a missing file fails before any work on the frame.
        read_label_png(&gt_path(&job.gt, i, "depth"), &mut gt_ir)?;
        read_label_png(&gt_path(&job.gt, i, "rgb"), &mut gt_rgb)?;
        job.rec.read_depth(i, &mut raw)?;
        classifier.classify(&raw, &mut out);
        tally.add_frame(&gt_ir, &out.ir_labels, &gt_rgb, &out.rgb_labels);
        if let Some(dir) = &job.export {
            write_label_png(&gt_path(dir, i, "depth"), &out.ir_labels)?;
            write_label_png(&gt_path(dir, i, "rgb"), &out.rgb_labels)?;
        }
        bar.inc(1);
    }
    Ok(tally)
}

/// `<dir>/<i:06>.<view>.png`, the SPEC §4 name.
fn gt_path(dir: &Path, i: usize, view: &str) -> PathBuf {
    crate::sink::labels::label_path(dir, i, view)
}
