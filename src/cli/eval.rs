//! `umbra eval`: classifies every frame of one recording (or of each recording in a folder) and
//! scores the labels against ground-truth label PNGs; with `--segment`, also scores foreground
//! masks of shadow seeds against the threshold baseline at its best fixed Tf/Tb.

use std::path::{Path, PathBuf};

use indicatif::ProgressBar;

use crate::classify::{Classified, Classifier};
use crate::error::{Error, Result};
use crate::eval::{read_category, Report, SegReport, SegTally, Tally};
use crate::labels::PIXELS;
use crate::recording::Recording;
use crate::segment::files::{mask_path, read_mask_png};
use crate::segment::{Params as SegParams, SeedMode, Segmenter, BG, FG};
use crate::sink::labels::{check_truth_dir, read_ir_label_png, read_label_png, write_label_png};

/// Arguments of `umbra eval`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// A recording folder (with INDEX.txt), or a folder whose subfolders are recordings.
    pub recording: PathBuf,
    /// Ground truth: <i:06>.depth.png and <i:06>.rgb.png per depth frame, optional meta.toml;
    /// for a folder of recordings, one subfolder per recording with the same name. Frames or
    /// views without their file are left out of the scores (with a warning).
    #[arg(long, value_name = "DIR")]
    pub gt: PathBuf,
    /// Print one JSON object instead of the table (per-recording scores included).
    #[arg(long)]
    pub json: bool,
    /// Also print one line of scores per recording (F1 per shadow class, any-shadow precision
    /// and recall, both views), to find the scenes that pull the totals down.
    #[arg(long)]
    pub per_recording: bool,
    /// Also write the predicted labels as SPEC §4 PNGs here (one subfolder per recording when
    /// RECORDING is a folder of recordings).
    #[arg(long, value_name = "DIR")]
    pub export_labels: Option<PathBuf>,
    /// Settings file (see config/umbra.toml); built-in defaults without it.
    #[arg(long, value_name = "FILE")]
    pub config: Option<PathBuf>,
    /// Also segment every frame (SPEC §6) with shadow seeds and with the threshold baseline over
    /// a grid of Tf/Tb pairs, and score the masks against <i:06>.fg.png: mean IoU, F-measure and
    /// seed precision per scene category, the baseline at its single best pair.
    #[arg(long)]
    pub segment: bool,
    /// With --segment: the threshold baseline's Tf (metres) instead of the grid search.
    #[arg(long, value_name = "M", requires = "segment", requires = "tb")]
    pub tf: Option<f32>,
    /// With --segment: the threshold baseline's Tb (metres) instead of the grid search.
    #[arg(long, value_name = "M", requires = "segment", requires = "tf")]
    pub tb: Option<f32>,
}

/// Tf values of the threshold grid search (metres).
const GRID_TF: [f32; 9] = [1.0, 1.25, 1.5, 1.75, 2.0, 2.25, 2.5, 2.75, 3.0];
/// Tb − Tf values of the grid search (metres).
const GRID_GAP: [f32; 4] = [0.0, 0.25, 0.5, 1.0];

/// The threshold pairs to try: the one given, or the grid.
fn threshold_pairs(a: &Args) -> Result<Vec<(f32, f32)>> {
    match (a.tf, a.tb) {
        (Some(tf), Some(tb)) if tf.is_finite() && tb.is_finite() && tf > 0.0 && tb >= tf => {
            Ok(vec![(tf, tb)])
        }
        (Some(tf), Some(tb)) => Err(Error::Usage(format!(
            "--tf {tf} --tb {tb}: expected 0 < Tf <= Tb (metres)"
        ))),
        _ => Ok(GRID_TF
            .iter()
            .flat_map(|&tf| GRID_GAP.iter().map(move |&g| (tf, tf + g)))
            .collect()),
    }
}

/// Segmenters and buffers for `--segment`: one segmenter for shadow seeds, one per worker thread
/// for the threshold pairs.
struct SegWork {
    pairs: Vec<(f32, f32)>,
    shadow: Segmenter,
    workers: Vec<Segmenter>,
    gt: Vec<u8>,
    mask: Vec<u8>,
}

impl SegWork {
    fn new(pairs: Vec<(f32, f32)>) -> Self {
        let threads = std::thread::available_parallelism()
            .map_or(1, |n| n.get())
            .clamp(1, pairs.len().max(1));
        SegWork {
            shadow: Segmenter::new(SegParams::default()),
            workers: (0..threads)
                .map(|_| Segmenter::new(SegParams::default()))
                .collect(),
            pairs,
            gt: vec![0; PIXELS],
            mask: vec![0; PIXELS],
        }
    }

    /// Segments one frame (its RGB image `rgb`) with shadow seeds and every threshold pair; adds
    /// to the tallies.
    #[allow(clippy::too_many_arguments)]
    fn frame(
        &mut self,
        name: &str,
        i: usize,
        rgb: &[u8],
        classified: &Classified,
        shadow: &mut SegTally,
        threshold: &mut [SegTally],
    ) {
        self.shadow.segment(rgb, classified, &mut self.mask);
        let mut one = SegTally::default();
        one.add_frame(&self.gt, &self.mask, self.shadow.seeds(), FG, BG);
        tracing::info!(
            "{name} frame {i}: shadow seeds IoU {:.3}, seed precision {:.3} of {}",
            one.iou_sum,
            one.seed_precision().unwrap_or(0.0),
            one.seeds
        );
        shadow.merge(&one);
        let n = self.workers.len();
        let (gt, pairs) = (&self.gt, &self.pairs);
        std::thread::scope(|scope| {
            let handles: Vec<_> = self
                .workers
                .iter_mut()
                .enumerate()
                .map(|(w, seg)| {
                    scope.spawn(move || {
                        let mut mask = vec![0u8; PIXELS];
                        let mut out = Vec::new();
                        for k in (w..pairs.len()).step_by(n) {
                            let (tf_m, tb_m) = pairs[k];
                            seg.set_seed_mode(SeedMode::Threshold { tf_m, tb_m });
                            seg.segment(rgb, classified, &mut mask);
                            let mut t = SegTally::default();
                            t.add_frame(gt, &mask, seg.seeds(), FG, BG);
                            out.push((k, t));
                        }
                        out
                    })
                })
                .collect();
            for h in handles {
                for (k, t) in h.join().expect("segmentation worker") {
                    threshold[k].merge(&t);
                }
            }
        });
    }
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
    let mut seg = if a.segment {
        Some(SegWork::new(threshold_pairs(&a)?))
    } else {
        None
    };
    let mut seg_report = seg.as_ref().map(|w| SegReport::new(w.pairs.clone()));
    for job in &jobs {
        job.rec.warn_doubts();
        bar.set_prefix(job.name.clone());
        let (tally, seg_tally) =
            score(job, params, seg.as_mut(), &bar).inspect_err(|_| bar.abandon())?;
        let category = read_category(&job.gt.join("meta.toml"))?;
        report.add_recording(job.name.clone(), category, tally);
        if let (Some(r), Some((shadow, thr))) = (seg_report.as_mut(), seg_tally) {
            r.add_recording(job.name.clone(), category, shadow, thr);
        }
    }
    bar.finish_and_clear();
    if a.json {
        let mut v = report.to_json();
        if let Some(r) = &seg_report {
            v["segmentation"] = r.to_json();
        }
        println!("{v}");
    } else {
        print!("{}", report.to_table());
        if a.per_recording {
            print!("\n{}", report.per_recording_table());
        }
        if let Some(r) = &seg_report {
            print!("{}", r.to_table());
        }
    }
    Ok(())
}

/// Works out whether RECORDING is one recording or a folder of them, and pairs each with its
/// ground-truth folder.
fn plan(a: &Args) -> Result<Vec<Job>> {
    if let Some(dir) = &a.export_labels {
        // Exported labels use the ground truth's file names: never let them overwrite it.
        if dir
            .canonicalize()
            .ok()
            .is_some_and(|d| a.gt.canonicalize().ok() == Some(d))
        {
            return Err(Error::Usage(format!(
                "--export-labels {} is the --gt folder: writing there would overwrite the ground truth; pick another folder",
                dir.display()
            )));
        }
    }
    check_truth_dir(&a.gt)?;
    if a.recording.join("INDEX.txt").is_file() {
        // `eval .` is named after the folder it is, not ".".
        let name = a
            .recording
            .canonicalize()
            .ok()
            .and_then(|p| p.file_name().map(|n| n.to_string_lossy().into_owned()))
            .unwrap_or_else(|| a.recording.display().to_string());
        let rec = Recording::open(&a.recording)?;
        return Ok(vec![Job {
            name,
            rec,
            gt: a.gt.clone(),
            export: a.export_labels.clone(),
        }]);
    }
    let entries =
        std::fs::read_dir(&a.recording).map_err(|e| Error::io(&a.recording, "listing", e))?;
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
                return Err(Error::input(
                    &gt,
                    "",
                    format!("missing: expected ground truth for recording {name} in this folder"),
                ));
            }
            let export = a.export_labels.as_ref().map(|d| d.join(&name));
            Ok(Job {
                name,
                rec,
                gt,
                export,
            })
        })
        .collect()
}

/// One recording's segmentation scores: shadow seeds, and one tally per threshold pair.
type SegScores = (SegTally, Vec<SegTally>);

/// Classifies every frame of one recording and counts it against ground truth; with `seg`, also
/// segments it and scores the masks.
fn score(
    job: &Job,
    params: crate::classify::Params,
    mut seg: Option<&mut SegWork>,
    bar: &ProgressBar,
) -> Result<(Tally, Option<SegScores>)> {
    if let Some(dir) = &job.export {
        std::fs::create_dir_all(dir).map_err(|e| Error::io(dir, "creating", e))?;
    }
    let mut classifier = Classifier::with_params(job.rec.calibration(), params);
    let mut out = Classified::default();
    let mut raw = vec![0u16; PIXELS];
    let mut colour = vec![0u8; 3 * PIXELS];
    let (mut gt_ir, mut gt_rgb) = (vec![0u8; PIXELS], vec![0u8; PIXELS]);
    let mut tally = Tally::default();
    let mut shadow = SegTally::default();
    let mut threshold = vec![SegTally::default(); seg.as_ref().map_or(0, |w| w.pairs.len())];
    let covered = coverage(job)?;
    for (i, &(has_ir, has_rgb_gt)) in covered.iter().enumerate() {
        if !has_ir && !has_rgb_gt && job.export.is_none() {
            bar.inc(1);
            continue;
        }
        // Read ground truth first: a bad file fails before any work on the frame.
        if has_ir {
            read_ir_label_png(&gt_path(&job.gt, i, "depth"), &mut gt_ir)?;
        }
        if has_rgb_gt {
            read_label_png(&gt_path(&job.gt, i, "rgb"), &mut gt_rgb)?;
        }
        let scored = has_ir || has_rgb_gt;
        if let (Some(w), true) = (seg.as_deref_mut(), scored) {
            read_mask_png(&mask_path(&job.gt, i), &mut w.gt)?;
        }
        // One read serves the classifier's colour split and the segmenter.
        let has_rgb = job.rec.read_rgb(i, &mut colour)?;
        if seg.is_some() && !has_rgb {
            let index = job.rec.dir().join("INDEX.txt");
            return Err(Error::input(
                index,
                "",
                format!("depth frame {i} has no RGB frame to segment (expected r-*.ppm lines)"),
            ));
        }
        job.rec.read_depth(i, &mut raw)?;
        classifier.classify_with_rgb(&raw, has_rgb.then_some(&colour[..]), &mut out);
        tally.add_views(
            has_ir.then_some((&gt_ir[..], &out.ir_labels[..])),
            has_rgb_gt.then_some((&gt_rgb[..], &out.rgb_labels[..])),
        );
        if let (Some(w), true) = (seg.as_deref_mut(), scored) {
            w.frame(&job.name, i, &colour, &out, &mut shadow, &mut threshold);
        }
        if let Some(dir) = &job.export {
            write_label_png(&gt_path(dir, i, "depth"), &out.ir_labels)?;
            write_label_png(&gt_path(dir, i, "rgb"), &out.rgb_labels)?;
        }
        bar.inc(1);
    }
    Ok((tally, seg.map(|_| (shadow, threshold))))
}

/// Which views of each depth frame of `job` have ground truth, `(IR, RGB)`. Hand-labelled real
/// frames often cover a few frames of a recording, or one view: those are scored and the rest
/// named in a warning. No ground truth at all is an error (most likely the wrong folder), and so
/// is none for the frames there are (label files only past the recording's end).
fn coverage(job: &Job) -> Result<Vec<(bool, bool)>> {
    let n = job.rec.len();
    let covered: Vec<(bool, bool)> = (0..n)
        .map(|i| {
            (
                gt_path(&job.gt, i, "depth").is_file(),
                gt_path(&job.gt, i, "rgb").is_file(),
            )
        })
        .collect();
    let ir = covered.iter().filter(|c| c.0).count();
    let rgb = covered.iter().filter(|c| c.1).count();
    let beyond = last_labelled_frame(&job.gt).filter(|&i| i >= n);
    if ir == 0 && rgb == 0 {
        let found = beyond.map_or(String::new(), |i| {
            format!(" (it has labels up to frame {i}: is it this recording's?)")
        });
        return Err(Error::input(
            gt_path(&job.gt, 0, "depth"),
            "",
            format!(
                "missing: no ground truth for any of the recording's {n} depth frames{found}; expected <frame:06>.depth.png and/or <frame:06>.rgb.png per frame (SPEC §4)"
            ),
        ));
    }
    if ir < n || rgb < n {
        tracing::warn!(
            "{}: ground truth covers {ir} of {n} depth frames in the IR view and {rgb} in the RGB view; only those are scored",
            job.name
        );
    }
    if let Some(i) = beyond {
        tracing::warn!(
            "{}: {} has labels up to frame {i} but the recording has {n} depth frames; are the two paired?",
            job.name,
            job.gt.display()
        );
    }
    Ok(covered)
}

/// The highest frame number among `<i:06>.depth.png` / `<i:06>.rgb.png` files in `dir`, if any.
fn last_labelled_frame(dir: &Path) -> Option<usize> {
    std::fs::read_dir(dir)
        .ok()?
        .filter_map(|e| {
            let name = e.ok()?.file_name().into_string().ok()?;
            let stem = name
                .strip_suffix(".depth.png")
                .or_else(|| name.strip_suffix(".rgb.png"))?;
            (stem.len() == 6)
                .then(|| stem.parse::<usize>().ok())
                .flatten()
        })
        .max()
}

/// `<dir>/<i:06>.<view>.png`, the SPEC §4 name.
fn gt_path(dir: &Path, i: usize, view: &str) -> PathBuf {
    crate::sink::labels::label_path(dir, i, view)
}
