//! Scoring labels against ground truth: confusion matrices, per-class and "any shadow" scores
//! (Deng et al., Table 1), and the ground-truth files `umbra synth` writes (SPEC §4 label PNGs
//! plus an optional `meta.toml` naming the scene's category).
//!
//! Foreground masks (SPEC §6) are scored too: [`MaskCounts`], [`SegTally`], [`SegReport`].
//!
//! The scoring core ([`Confusion`], [`Score`], [`Report`], and the segmentation scores) is pure;
//! [`read_category`] is the only I/O here (label PNGs are read and written by
//! [`crate::sink::labels`], masks by [`crate::segment::files`]).

use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::Path;

use serde::Serialize;

use crate::error::{Error, Result};
use crate::labels::{self, ALIGNMENT, ATTACHED, CLASSES, DETACHED, OTHER};

/// Pixel counts of ground truth (rows) against prediction (columns), for one view.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Confusion {
    counts: [[u64; CLASSES]; CLASSES],
}

impl Confusion {
    /// Counts every pixel pair `(gt[i], pred[i])`. Pairs with a code outside `0..CLASSES` are
    /// skipped (ground truth is checked on reading, so this only guards against a buggy
    /// classifier); slices of different lengths are compared over the shorter one.
    pub fn add(&mut self, gt: &[u8], pred: &[u8]) {
        for (&g, &p) in gt.iter().zip(pred) {
            if let Some(row) = self.counts.get_mut(g as usize) {
                if let Some(c) = row.get_mut(p as usize) {
                    *c += 1;
                }
            }
        }
    }

    /// Adds another matrix's counts to this one (frames, recordings, categories pooled).
    pub fn merge(&mut self, other: &Confusion) {
        for (row, orow) in self.counts.iter_mut().zip(&other.counts) {
            for (c, o) in row.iter_mut().zip(orow) {
                *c += o;
            }
        }
    }

    /// Pixels labelled `gt` in ground truth and `pred` by the classifier.
    pub fn get(&self, gt: u8, pred: u8) -> u64 {
        self.counts
            .get(gt as usize)
            .and_then(|r| r.get(pred as usize))
            .copied()
            .unwrap_or(0)
    }

    /// The full matrix, `[gt][pred]`.
    pub fn counts(&self) -> &[[u64; CLASSES]; CLASSES] {
        &self.counts
    }

    /// Pixels counted.
    pub fn total(&self) -> u64 {
        self.counts.iter().flatten().sum()
    }

    /// One class against all others.
    pub fn class(&self, code: u8) -> Score {
        self.binary(|c| c == code)
    }

    /// The paper's "any shadow" score: attached, detached and alignment pooled into one positive
    /// class, so confusing one shadow kind with another is not an error here.
    pub fn any_shadow(&self) -> Score {
        self.binary(labels::is_shadow)
    }

    fn binary(&self, positive: impl Fn(u8) -> bool) -> Score {
        let (mut tp, mut support, mut predicted) = (0, 0, 0);
        for g in 0..CLASSES as u8 {
            for p in 0..CLASSES as u8 {
                let n = self.get(g, p);
                if positive(g) {
                    support += n;
                }
                if positive(p) {
                    predicted += n;
                }
                if positive(g) && positive(p) {
                    tp += n;
                }
            }
        }
        Score::from_counts(tp, support, predicted)
    }
}

/// Precision, recall and F1 of one positive class. A ratio whose denominator is zero is `None`
/// (shown as "—", `null` in JSON) rather than NaN.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Score {
    /// Correct predictions over all predictions of the class; `None` if it was never predicted.
    pub precision: Option<f64>,
    /// Correct predictions over ground-truth pixels of the class; `None` if there are none.
    pub recall: Option<f64>,
    /// `2·TP / (2·TP + FP + FN)`: 0 when the classifier misses everything or invents everything,
    /// `None` only when the class is absent from both ground truth and prediction.
    pub f1: Option<f64>,
    /// Ground-truth pixels of the class.
    pub support: u64,
    /// Pixels the classifier gave the class.
    pub predicted: u64,
    /// Pixels in both.
    pub true_positives: u64,
}

impl Score {
    /// Scores from true positives, ground-truth count and predicted count.
    pub fn from_counts(tp: u64, support: u64, predicted: u64) -> Score {
        let ratio = |n: u64, d: u64| (d > 0).then(|| n as f64 / d as f64);
        Score {
            precision: ratio(tp, predicted),
            recall: ratio(tp, support),
            // FP + FN = (predicted − tp) + (support − tp).
            f1: ratio(2 * tp, support + predicted),
            support,
            predicted,
            true_positives: tp,
        }
    }
}

/// One camera view's labels.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum View {
    /// The IR (depth) camera's view: `<i>.depth.png`.
    Ir,
    /// The RGB camera's view: `<i>.rgb.png`.
    Rgb,
}

impl View {
    /// Both views, in report order.
    pub const ALL: [View; 2] = [View::Ir, View::Rgb];

    /// Short name used in tables and JSON.
    pub fn name(self) -> &'static str {
        match self {
            View::Ir => "ir",
            View::Rgb => "rgb",
        }
    }

    /// The hole classes scored in this view: alignment shadows exist only in the RGB view.
    pub fn classes(self) -> &'static [u8] {
        match self {
            View::Ir => &[ATTACHED, DETACHED, OTHER],
            View::Rgb => &[ATTACHED, DETACHED, ALIGNMENT, OTHER],
        }
    }
}

/// Scene category from the ground truth's `meta.toml` (the paper reports both separately).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Category {
    /// A few objects in front of a wall.
    Simple,
    /// Cluttered scenes.
    Complex,
}

impl Category {
    /// The name used in `meta.toml`, tables and JSON.
    pub fn name(self) -> &'static str {
        match self {
            Category::Simple => "simple",
            Category::Complex => "complex",
        }
    }
}

/// Both views' confusion matrices over some set of frames.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Tally {
    /// Frames counted (in either view).
    pub frames: u64,
    /// Frames counted in the IR view (ground truth may cover one view only).
    pub ir_frames: u64,
    /// Frames counted in the RGB view.
    pub rgb_frames: u64,
    /// IR-view matrix.
    pub ir: Confusion,
    /// RGB-view matrix.
    pub rgb: Confusion,
}

impl Tally {
    /// Counts one frame: ground truth and prediction in both views.
    pub fn add_frame(&mut self, gt_ir: &[u8], pred_ir: &[u8], gt_rgb: &[u8], pred_rgb: &[u8]) {
        self.add_views(Some((gt_ir, pred_ir)), Some((gt_rgb, pred_rgb)));
    }

    /// Counts one frame in the views that have ground truth, as `(ground truth, prediction)`
    /// (hand-labelled real frames often have it for one view only).
    pub fn add_views(&mut self, ir: Option<(&[u8], &[u8])>, rgb: Option<(&[u8], &[u8])>) {
        if ir.is_none() && rgb.is_none() {
            return;
        }
        self.frames += 1;
        if let Some((gt, pred)) = ir {
            self.ir_frames += 1;
            self.ir.add(gt, pred);
        }
        if let Some((gt, pred)) = rgb {
            self.rgb_frames += 1;
            self.rgb.add(gt, pred);
        }
    }

    /// Adds another tally.
    pub fn merge(&mut self, other: &Tally) {
        self.frames += other.frames;
        self.ir_frames += other.ir_frames;
        self.rgb_frames += other.rgb_frames;
        self.ir.merge(&other.ir);
        self.rgb.merge(&other.rgb);
    }

    /// Frames counted in view `v`.
    pub fn view_frames(&self, v: View) -> u64 {
        match v {
            View::Ir => self.ir_frames,
            View::Rgb => self.rgb_frames,
        }
    }

    /// The matrix of one view.
    pub fn view(&self, v: View) -> &Confusion {
        match v {
            View::Ir => &self.ir,
            View::Rgb => &self.rgb,
        }
    }
}

/// Accumulates tallies per recording and groups them into "all" and per-category results.
#[derive(Clone, Debug, Default)]
pub struct Report {
    recordings: Vec<(String, Option<Category>, Tally)>,
}

impl Report {
    /// Adds one recording's tally under its name and category (`None`: no `meta.toml`).
    pub fn add_recording(
        &mut self,
        name: impl Into<String>,
        category: Option<Category>,
        tally: Tally,
    ) {
        self.recordings.push((name.into(), category, tally));
    }

    /// The groups to report, in order: `all`, then each category that occurs.
    pub fn groups(&self) -> Vec<(&'static str, Tally)> {
        let mut all = Tally::default();
        let mut by_cat: BTreeMap<Category, Tally> = BTreeMap::new();
        for (_, cat, t) in &self.recordings {
            all.merge(t);
            if let Some(c) = cat {
                by_cat.entry(*c).or_default().merge(t);
            }
        }
        let mut out = vec![("all", all)];
        out.extend(by_cat.into_iter().map(|(c, t)| (c.name(), t)));
        out
    }

    /// An aligned plain-text table: one block per group, one row per view and class, then the
    /// view's "any shadow" row.
    pub fn to_table(&self) -> String {
        let mut s = String::new();
        let n = self.recordings.len();
        let frames: u64 = self.recordings.iter().map(|r| r.2.frames).sum();
        let _ = writeln!(
            s,
            "{n} recording{}, {frames} frame{}",
            plural(n as u64),
            plural(frames)
        );
        for (name, tally) in self.groups() {
            let recs = self
                .recordings
                .iter()
                .filter(|r| name == "all" || r.1.map(Category::name) == Some(name))
                .count();
            let views = if tally.ir_frames == tally.frames && tally.rgb_frames == tally.frames {
                String::new()
            } else {
                format!(
                    " (scored in the IR view {}, in the RGB view {})",
                    tally.ir_frames, tally.rgb_frames
                )
            };
            let _ = writeln!(
                s,
                "\n{name}: {recs} recording{}, {} frame{}{views}",
                plural(recs as u64),
                tally.frames,
                plural(tally.frames)
            );
            let _ = writeln!(
                s,
                "{:<5} {:<11} {:>9} {:>9} {:>9} {:>12} {:>12}",
                "view", "class", "precision", "recall", "f1", "support", "predicted"
            );
            for v in View::ALL {
                let m = tally.view(v);
                let rows = v
                    .classes()
                    .iter()
                    .map(|&c| (labels::NAMES[c as usize], m.class(c)));
                for (class, sc) in rows.chain([("any shadow", m.any_shadow())]) {
                    let _ = writeln!(
                        s,
                        "{:<5} {:<11} {:>9} {:>9} {:>9} {:>12} {:>12}",
                        v.name(),
                        class,
                        fmt_ratio(sc.precision),
                        fmt_ratio(sc.recall),
                        fmt_ratio(sc.f1),
                        sc.support,
                        sc.predicted
                    );
                }
            }
        }
        s
    }

    /// One line per recording, to find the scenes that pull a group's scores down: frames, the
    /// F1 of each shadow class and the "any shadow" precision and recall, per view.
    pub fn per_recording_table(&self) -> String {
        let mut s = String::new();
        let width = self
            .recordings
            .iter()
            .map(|r| r.0.chars().count())
            .max()
            .unwrap_or(0)
            .max("recording".len());
        let _ = writeln!(
            s,
            "{:<width$} {:<8} {:>6}  {:>7} {:>6} {:>6} {:>6}  {:>7} {:>6} {:>6} {:>6} {:>6}",
            "recording",
            "category",
            "frames",
            "IR att",
            "det",
            "any P",
            "any R",
            "RGB att",
            "det",
            "ali",
            "any P",
            "any R"
        );
        let f1 = |m: &Confusion, c: u8| fmt_ratio(m.class(c).f1);
        for (name, cat, t) in &self.recordings {
            let (ir, rgb) = (&t.ir, &t.rgb);
            let _ = writeln!(
                s,
                "{:<width$} {:<8} {:>6}  {:>7} {:>6} {:>6} {:>6}  {:>7} {:>6} {:>6} {:>6} {:>6}",
                name,
                cat.map_or("-", Category::name),
                t.frames,
                f1(ir, labels::ATTACHED),
                f1(ir, labels::DETACHED),
                fmt_ratio(ir.any_shadow().precision),
                fmt_ratio(ir.any_shadow().recall),
                f1(rgb, labels::ATTACHED),
                f1(rgb, labels::DETACHED),
                f1(rgb, labels::ALIGNMENT),
                fmt_ratio(rgb.any_shadow().precision),
                fmt_ratio(rgb.any_shadow().recall),
            );
        }
        s
    }

    /// The same numbers as [`Report::to_table`] as one JSON value, plus each view's confusion
    /// matrix (`[gt][pred]`, codes 0–4), and per recording its name, category, frame count and
    /// the same scores of its own.
    pub fn to_json(&self) -> serde_json::Value {
        #[derive(Serialize)]
        struct ViewJson {
            frames: u64,
            pixels: u64,
            classes: BTreeMap<&'static str, Score>,
            any_shadow: Score,
            confusion: [[u64; CLASSES]; CLASSES],
        }
        #[derive(Serialize)]
        struct GroupJson {
            frames: u64,
            ir: ViewJson,
            rgb: ViewJson,
        }
        #[derive(Serialize)]
        struct RecJson<'a> {
            name: &'a str,
            category: Option<Category>,
            frames: u64,
            ir: ViewJson,
            rgb: ViewJson,
        }
        let view = |t: &Tally, v: View| ViewJson {
            frames: t.view_frames(v),
            pixels: t.view(v).total(),
            classes: v
                .classes()
                .iter()
                .map(|&c| (labels::NAMES[c as usize], t.view(v).class(c)))
                .collect(),
            any_shadow: t.view(v).any_shadow(),
            confusion: *t.view(v).counts(),
        };
        let groups: BTreeMap<&str, GroupJson> = self
            .groups()
            .into_iter()
            .map(|(name, t)| {
                (
                    name,
                    GroupJson {
                        frames: t.frames,
                        ir: view(&t, View::Ir),
                        rgb: view(&t, View::Rgb),
                    },
                )
            })
            .collect();
        let recs: Vec<RecJson> = self
            .recordings
            .iter()
            .map(|(n, c, t)| RecJson {
                name: n,
                category: *c,
                frames: t.frames,
                ir: view(t, View::Ir),
                rgb: view(t, View::Rgb),
            })
            .collect();
        serde_json::json!({ "recordings": recs, "groups": groups })
    }
}

/// Foreground masks against ground truth (SPEC §6): pixel counts of one or more frames. A mask
/// pixel is foreground when non-zero.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
pub struct MaskCounts {
    /// Foreground in both.
    pub tp: u64,
    /// Predicted foreground, background in ground truth.
    pub fp: u64,
    /// Ground-truth foreground the mask missed.
    pub fn_: u64,
}

impl MaskCounts {
    /// Counts one frame.
    pub fn of(gt: &[u8], pred: &[u8]) -> MaskCounts {
        let mut m = MaskCounts::default();
        for (&g, &p) in gt.iter().zip(pred) {
            match (g != 0, p != 0) {
                (true, true) => m.tp += 1,
                (false, true) => m.fp += 1,
                (true, false) => m.fn_ += 1,
                (false, false) => {}
            }
        }
        m
    }

    /// Intersection over union; 1 when both masks are empty (nothing to find, nothing found).
    pub fn iou(&self) -> f64 {
        let union = self.tp + self.fp + self.fn_;
        if union == 0 {
            1.0
        } else {
            self.tp as f64 / union as f64
        }
    }

    /// F-measure (F1 of the foreground class); 1 when both masks are empty.
    pub fn f_measure(&self) -> f64 {
        let d = 2 * self.tp + self.fp + self.fn_;
        if d == 0 {
            1.0
        } else {
            2.0 * self.tp as f64 / d as f64
        }
    }
}

/// Segmentation results of some frames: per-frame IoU and F-measure summed (the report shows
/// their means), and how many seeds fell on the side ground truth gives them.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct SegTally {
    /// Frames counted.
    pub frames: u64,
    /// Sum of per-frame IoU.
    pub iou_sum: f64,
    /// Sum of per-frame F-measure.
    pub f_sum: f64,
    /// Seeds (foreground and background) used.
    pub seeds: u64,
    /// Seeds whose side matches ground truth.
    pub seeds_right: u64,
}

impl SegTally {
    /// Counts one frame: ground-truth mask, predicted mask, and the seed map (`fg_code` and
    /// `bg_code` mark seeds, anything else is none).
    pub fn add_frame(&mut self, gt: &[u8], pred: &[u8], seeds: &[u8], fg_code: u8, bg_code: u8) {
        let m = MaskCounts::of(gt, pred);
        self.frames += 1;
        self.iou_sum += m.iou();
        self.f_sum += m.f_measure();
        for (&g, &s) in gt.iter().zip(seeds) {
            if s == fg_code || s == bg_code {
                self.seeds += 1;
                self.seeds_right += u64::from((s == fg_code) == (g != 0));
            }
        }
    }

    /// Adds another tally.
    pub fn merge(&mut self, o: &SegTally) {
        self.frames += o.frames;
        self.iou_sum += o.iou_sum;
        self.f_sum += o.f_sum;
        self.seeds += o.seeds;
        self.seeds_right += o.seeds_right;
    }

    /// Mean per-frame IoU; `None` without frames.
    pub fn mean_iou(&self) -> Option<f64> {
        (self.frames > 0).then(|| self.iou_sum / self.frames as f64)
    }

    /// Mean per-frame F-measure; `None` without frames.
    pub fn mean_f(&self) -> Option<f64> {
        (self.frames > 0).then(|| self.f_sum / self.frames as f64)
    }

    /// Fraction of seeds on their ground-truth side; `None` without seeds.
    pub fn seed_precision(&self) -> Option<f64> {
        (self.seeds > 0).then(|| self.seeds_right as f64 / self.seeds as f64)
    }
}

/// Shadow seeds against threshold seeds: each recording's shadow-seed tally and one tally per
/// (Tf, Tb) pair of the threshold baseline's grid.
#[derive(Clone, Debug, Default)]
pub struct SegReport {
    /// The (Tf, Tb) pairs tried, metres.
    pub pairs: Vec<(f32, f32)>,
    recordings: Vec<(String, Option<Category>, SegTally, Vec<SegTally>)>,
}

impl SegReport {
    /// An empty report over the threshold pairs `pairs`.
    pub fn new(pairs: Vec<(f32, f32)>) -> Self {
        SegReport {
            pairs,
            recordings: Vec::new(),
        }
    }

    /// Adds one recording: its shadow-seed tally and one threshold tally per pair (same order).
    pub fn add_recording(
        &mut self,
        name: impl Into<String>,
        category: Option<Category>,
        shadow: SegTally,
        threshold: Vec<SegTally>,
    ) {
        assert_eq!(
            threshold.len(),
            self.pairs.len(),
            "one threshold tally per pair"
        );
        self.recordings
            .push((name.into(), category, shadow, threshold));
    }

    /// The index of the single best fixed pair for the whole benchmark: highest mean IoU over all
    /// frames (ties: the first).
    pub fn best_pair(&self) -> Option<usize> {
        (0..self.pairs.len()).max_by(|&a, &b| {
            let t = |k: usize| {
                let mut all = SegTally::default();
                for r in &self.recordings {
                    all.merge(&r.3[k]);
                }
                all.mean_iou().unwrap_or(0.0)
            };
            t(a).total_cmp(&t(b)).then(b.cmp(&a))
        })
    }

    /// Groups in report order (`all`, then each category): shadow tally and best-pair tally.
    pub fn groups(&self) -> Vec<(&'static str, SegTally, SegTally)> {
        let best = self.best_pair();
        let mut out: Vec<(&'static str, SegTally, SegTally)> =
            vec![("all", SegTally::default(), SegTally::default())];
        for (_, cat, shadow, thr) in &self.recordings {
            let b = best.map(|k| thr[k]).unwrap_or_default();
            for name in ["all"].into_iter().chain(cat.map(Category::name)) {
                let slot = match out.iter().position(|g| g.0 == name) {
                    Some(i) => i,
                    None => {
                        out.push((name, SegTally::default(), SegTally::default()));
                        out.len() - 1
                    }
                };
                out[slot].1.merge(shadow);
                out[slot].2.merge(&b);
            }
        }
        // Categories in their fixed order after "all".
        out[1..].sort_by_key(|g| if g.0 == "simple" { 0 } else { 1 });
        out
    }

    /// The plain-text table: mean IoU, mean F-measure and seed precision per group for shadow
    /// seeds and for the best fixed threshold pair.
    pub fn to_table(&self) -> String {
        let mut s = String::new();
        let best = self.best_pair();
        match best {
            Some(k) => {
                let _ = writeln!(
                    s,
                    "\nsegmentation: threshold baseline at the best fixed pair of {} tried, Tf {:.2} m, Tb {:.2} m",
                    self.pairs.len(),
                    self.pairs[k].0,
                    self.pairs[k].1
                );
            }
            None => {
                let _ = writeln!(s, "\nsegmentation: no threshold pair tried");
            }
        }
        let _ = writeln!(
            s,
            "{:<8} {:<10} {:>7} {:>9} {:>9} {:>14}",
            "group", "seeds", "frames", "mean IoU", "mean F", "seed precision"
        );
        for (name, shadow, thr) in self.groups() {
            for (label, t) in [("shadow", shadow), ("threshold", thr)] {
                let _ = writeln!(
                    s,
                    "{:<8} {:<10} {:>7} {:>9} {:>9} {:>14}",
                    name,
                    label,
                    t.frames,
                    fmt_ratio(t.mean_iou()),
                    fmt_ratio(t.mean_f()),
                    fmt_ratio(t.seed_precision())
                );
            }
        }
        s
    }

    /// The same as one JSON value, plus the mean IoU of every pair tried.
    pub fn to_json(&self) -> serde_json::Value {
        let one = |t: &SegTally| {
            serde_json::json!({
                "frames": t.frames,
                "mean_iou": t.mean_iou(),
                "mean_f": t.mean_f(),
                "seed_precision": t.seed_precision(),
                "seeds": t.seeds,
            })
        };
        let groups: serde_json::Map<String, serde_json::Value> = self
            .groups()
            .iter()
            .map(|(n, sh, th)| {
                (
                    n.to_string(),
                    serde_json::json!({ "shadow": one(sh), "threshold": one(th) }),
                )
            })
            .collect();
        let grid: Vec<serde_json::Value> = (0..self.pairs.len())
            .map(|k| {
                let mut all = SegTally::default();
                for r in &self.recordings {
                    all.merge(&r.3[k]);
                }
                serde_json::json!({ "tf_m": self.pairs[k].0, "tb_m": self.pairs[k].1, "mean_iou": all.mean_iou() })
            })
            .collect();
        let best = self
            .best_pair()
            .map(|k| serde_json::json!({ "tf_m": self.pairs[k].0, "tb_m": self.pairs[k].1 }));
        serde_json::json!({ "best_threshold": best, "groups": groups, "threshold_grid": grid })
    }
}

fn plural(n: u64) -> &'static str {
    if n == 1 {
        ""
    } else {
        "s"
    }
}

/// Three decimals, or "—" for an undefined ratio.
fn fmt_ratio(r: Option<f64>) -> String {
    r.map_or_else(|| "—".to_string(), |v| format!("{v:.3}"))
}

/// Reads the `category` key of a ground-truth `meta.toml`; `Ok(None)` when the file or the key is
/// absent. Other keys are ignored.
pub fn read_category(path: &Path) -> Result<Option<Category>> {
    let text = match std::fs::read_to_string(path) {
        Ok(t) => t,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(None),
        Err(e) => return Err(Error::io(path, "reading", e)),
    };
    parse_category(&text, path)
}

/// Parses the `category` key of `meta.toml` text; `path` is only used in error messages.
pub fn parse_category(text: &str, path: &Path) -> Result<Option<Category>> {
    // A syntax error names its line and column (SPEC §5), like calibration.toml's.
    let table: toml::Table =
        toml::from_str(text).map_err(|e| crate::calib::toml_error(path, text, &e))?;
    match table.get("category") {
        None => Ok(None),
        Some(toml::Value::String(s)) if s == "simple" => Ok(Some(Category::Simple)),
        Some(toml::Value::String(s)) if s == "complex" => Ok(Some(Category::Complex)),
        Some(v) => Err(Error::input(
            path,
            "key category",
            format!("value {v} is wrong, expected \"simple\" or \"complex\""),
        )),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::labels::VALID;

    const A: u8 = ATTACHED;
    const D: u8 = DETACHED;
    const G: u8 = ALIGNMENT;
    const O: u8 = OTHER;
    const V: u8 = VALID;

    fn close(a: Option<f64>, b: f64) -> bool {
        a.is_some_and(|a| (a - b).abs() < 1e-12)
    }

    #[test]
    fn per_class_scores_by_hand() {
        //            0  1  2  3  4  5  6  7  8  9
        let gt = [A, A, A, A, D, D, O, V, V, O];
        let pr = [A, A, A, D, D, O, O, A, V, V];
        let mut m = Confusion::default();
        m.add(&gt, &pr);
        assert_eq!(m.total(), 10);
        // Attached: gt at 0..4 (4), predicted at 0,1,2,7 (4), both at 0,1,2 (3).
        let a = m.class(A);
        assert_eq!((a.true_positives, a.support, a.predicted), (3, 4, 4));
        assert!(close(a.precision, 0.75) && close(a.recall, 0.75) && close(a.f1, 0.75));
        // Detached: gt 4,5; predicted 3,4; both 4 → P = R = 1/2.
        let d = m.class(D);
        assert!(close(d.precision, 0.5) && close(d.recall, 0.5) && close(d.f1, 0.5));
        // Other: gt 6,9; predicted 5,6 → P = 1/2, R = 1/2.
        let o = m.class(O);
        assert!(close(o.precision, 0.5) && close(o.recall, 0.5));
        // Any shadow: gt {0..5} = 6, predicted {0,1,2,3,4,7} = 6, both {0..4} = 5.
        let s = m.any_shadow();
        assert_eq!((s.true_positives, s.support, s.predicted), (5, 6, 6));
        assert!(close(s.precision, 5.0 / 6.0) && close(s.recall, 5.0 / 6.0));
    }

    #[test]
    fn any_shadow_pools_shadow_kinds() {
        // Every shadow pixel gets the wrong shadow kind: per-class scores are 0, pooled are 1.
        let gt = [A, D, G, V];
        let pr = [D, G, A, V];
        let mut m = Confusion::default();
        m.add(&gt, &pr);
        assert!(close(m.class(A).recall, 0.0) && close(m.class(A).f1, 0.0));
        let s = m.any_shadow();
        assert!(close(s.precision, 1.0) && close(s.recall, 1.0) && close(s.f1, 1.0));
    }

    #[test]
    fn precision_and_recall_differ() {
        // Alignment: 2 in gt, predicted 4 times, 2 right → P = 1/2, R = 1, F1 = 2/3.
        let gt = [G, G, V, V, O, V];
        let pr = [G, G, G, G, O, V];
        let mut m = Confusion::default();
        m.add(&gt, &pr);
        let g = m.class(G);
        assert!(close(g.precision, 0.5) && close(g.recall, 1.0) && close(g.f1, 2.0 / 3.0));
    }

    #[test]
    fn absent_classes_are_undefined_not_nan() {
        let mut m = Confusion::default();
        m.add(&[V, O], &[V, O]);
        let d = m.class(D);
        assert_eq!((d.precision, d.recall, d.f1), (None, None, None));
        // Never predicted but present: recall 0, precision undefined, F1 0.
        m.add(&[A], &[V]);
        let a = m.class(A);
        assert_eq!((a.precision, a.recall, a.f1), (None, Some(0.0), Some(0.0)));
        let table = {
            let mut r = Report::default();
            let mut t = Tally::default();
            t.add_frame(&[V, O], &[V, O], &[V, O], &[V, O]);
            r.add_recording("x", None, t);
            r.to_table()
        };
        assert!(table.contains('—') && !table.contains("NaN"), "{table}");
        let json = Report::default().to_json().to_string();
        assert!(!json.contains("NaN"), "{json}");
    }

    #[test]
    fn merge_adds_counts_and_skips_bad_codes() {
        let mut a = Confusion::default();
        a.add(&[A, V, 9], &[A, 7, V]);
        assert_eq!(a.total(), 1);
        let mut b = Confusion::default();
        b.add(&[A, O], &[O, O]);
        a.merge(&b);
        assert_eq!(a.get(A, A), 1);
        assert_eq!(a.get(A, O), 1);
        assert_eq!(a.get(O, O), 1);
        assert_eq!(a.total(), 3);
    }

    #[test]
    fn report_groups_by_category() {
        let frame = |gt: u8, pr: u8| {
            let mut t = Tally::default();
            t.add_frame(&[gt], &[pr], &[gt], &[pr]);
            t
        };
        let mut r = Report::default();
        r.add_recording("s1", Some(Category::Simple), frame(A, A));
        r.add_recording("c1", Some(Category::Complex), frame(A, V));
        r.add_recording("n", None, frame(D, D));
        let g = r.groups();
        let names: Vec<_> = g.iter().map(|(n, _)| *n).collect();
        assert_eq!(names, ["all", "simple", "complex"]);
        assert_eq!(g[0].1.frames, 3);
        assert!(close(g[0].1.ir.class(A).recall, 0.5));
        assert!(close(g[1].1.ir.class(A).recall, 1.0));
        assert!(close(g[2].1.rgb.class(A).recall, 0.0));
        let j = r.to_json();
        assert_eq!(
            j["groups"]["simple"]["ir"]["classes"]["attached"]["recall"],
            1.0
        );
        assert_eq!(
            j["groups"]["all"]["rgb"]["classes"]["detached"]["precision"],
            1.0
        );
        assert!(j["groups"]["all"]["ir"]["classes"]
            .get("alignment")
            .is_none());
        assert_eq!(j["recordings"][1]["category"], "complex");
        let t = r.to_table();
        assert!(t.starts_with("3 recordings, 3 frames"), "{t}");
        assert!(t.contains("\nsimple: 1 recording, 1 frame\n"), "{t}");
    }

    #[test]
    fn table_columns_line_up() {
        let mut r = Report::default();
        let mut t = Tally::default();
        t.add_frame(&[A, V], &[A, A], &[G, V], &[V, G]);
        r.add_recording("x", None, t);
        let table = r.to_table();
        let widths: Vec<usize> = table
            .lines()
            .filter(|l| l.starts_with("ir ") || l.starts_with("rgb ") || l.starts_with("view"))
            .map(|l| l.chars().count())
            .collect();
        assert_eq!(widths.len(), 1 + 4 + 5);
        assert!(widths.iter().all(|&w| w == widths[0]), "{table}");
    }

    #[test]
    fn mask_scores_by_hand_and_best_pair() {
        // gt fg at 0..4, predicted fg at 2..6: tp 2, fp 2, fn 2 → IoU 1/3, F 1/2.
        let gt = [255, 255, 255, 255, 0, 0, 0, 0];
        let pr = [0, 0, 255, 255, 255, 255, 0, 0];
        let m = MaskCounts::of(&gt, &pr);
        assert_eq!((m.tp, m.fp, m.fn_), (2, 2, 2));
        assert!((m.iou() - 1.0 / 3.0).abs() < 1e-12 && (m.f_measure() - 0.5).abs() < 1e-12);
        assert_eq!(MaskCounts::of(&[0, 0], &[0, 0]).iou(), 1.0);
        // Seeds: fg seed on gt fg (right), bg seed on gt fg (wrong), bg seed on gt bg (right).
        let seeds = [1, 2, 0, 0, 0, 0, 2, 9];
        let mut t = SegTally::default();
        t.add_frame(&gt, &pr, &seeds, 1, 2);
        assert_eq!((t.seeds, t.seeds_right), (3, 2));
        let mut r = SegReport::new(vec![(1.0, 2.0), (2.0, 3.0)]);
        let perfect = {
            let mut t = SegTally::default();
            t.add_frame(&gt, &gt, &seeds, 1, 2);
            t
        };
        r.add_recording("a", Some(Category::Simple), t, vec![t, perfect]);
        r.add_recording("b", Some(Category::Complex), perfect, vec![t, t]);
        // Pair 1: mean IoU (1 + 1/3) / 2 beats pair 0's 1/3.
        assert_eq!(r.best_pair(), Some(1));
        let g = r.groups();
        assert_eq!(
            g.iter().map(|g| g.0).collect::<Vec<_>>(),
            ["all", "simple", "complex"]
        );
        assert!(
            (g[1].2.mean_iou().unwrap() - 1.0).abs() < 1e-12
                && (g[2].1.mean_iou().unwrap() - 1.0).abs() < 1e-12
        );
        let table = r.to_table();
        assert!(
            table.contains("Tf 2.00 m, Tb 3.00 m") && !table.contains("NaN"),
            "{table}"
        );
    }

    #[test]
    fn meta_category() {
        let p = Path::new("meta.toml");
        assert_eq!(
            parse_category("category = \"simple\"\nseed = 3\n", p).unwrap(),
            Some(Category::Simple)
        );
        assert_eq!(
            parse_category("category = \"complex\"", p).unwrap(),
            Some(Category::Complex)
        );
        assert_eq!(parse_category("seed = 3", p).unwrap(), None);
        let e = parse_category("category = \"hard\"", p)
            .unwrap_err()
            .to_string();
        assert!(
            e.starts_with("meta.toml: key category:") && e.contains("simple"),
            "{e}"
        );
        assert!(parse_category("category = ", p).is_err());
        assert_eq!(
            read_category(Path::new("/nonexistent/meta.toml")).unwrap(),
            None
        );
    }
}
