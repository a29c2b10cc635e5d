//! The `umbra` binary end to end, the way users drive it: synth a recording, replay it with
//! `--export-labels` (SPEC §4), score it with `eval`, draw it with `render`.

use std::path::Path;
use std::process::{Command, Output};

use umbra::classify::{Classified, Classifier};
use umbra::labels::{ATTACHED, PIXELS};
use umbra::recording::Recording;
use umbra::sink::labels::{label_path, read_label_png};

fn umbra(args: &[&str]) -> Output {
    let out = Command::new(env!("CARGO_BIN_EXE_umbra"))
        .args(args)
        .output()
        .expect("run umbra");
    assert!(
        out.status.success(),
        "umbra {args:?} failed: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    out
}

fn synth(dir: &Path, scene: &str, frames: &str) -> (String, String) {
    let rec = dir.join("rec").display().to_string();
    let gt = dir.join("gt").display().to_string();
    umbra(&[
        "synth", &rec, "--gt", &gt, "--scene", scene, "--frames", frames, "--seed", "5",
    ]);
    (rec, gt)
}

/// Runs `umbra` expecting it to fail; its standard error.
fn umbra_fails(args: &[&str]) -> String {
    let out = Command::new(env!("CARGO_BIN_EXE_umbra"))
        .args(args)
        .output()
        .expect("run umbra");
    let err = String::from_utf8_lossy(&out.stderr).into_owned();
    assert!(!out.status.success(), "umbra {args:?} should fail: {err}");
    err
}

/// The label codes of a label PNG.
fn labels_at(path: &Path) -> Vec<u8> {
    let mut labels = vec![0u8; PIXELS];
    read_label_png(path, &mut labels).unwrap();
    labels
}

/// Replays `rec` with `--export-labels dir`.
fn export_labels(rec: &str, dir: &Path) -> Output {
    umbra(&["replay", rec, "--export-labels", &dir.display().to_string()])
}

/// `umbra synth` of the hand-checkable box scene, one frame with the noise-free sensor, into
/// `dir/name` and `dir/name-gt`, with `extra` switches; the two folders.
fn synth_box(dir: &Path, name: &str, extra: &[&str]) -> (std::path::PathBuf, std::path::PathBuf) {
    let (rec, gt) = (dir.join(name), dir.join(format!("{name}-gt")));
    let (r, g) = (rec.display().to_string(), gt.display().to_string());
    let mut args = vec![
        "synth", &r, "--gt", &g, "--scene", "box", "--frames", "1", "--ideal",
    ];
    args.extend_from_slice(extra);
    umbra(&args);
    (rec, gt)
}

/// The mean and standard deviation of `residuals`, after checking there are at least `min`.
fn mean_and_sigma(residuals: &[f64], min: f64) -> (f64, f64) {
    let n = residuals.len() as f64;
    assert!(n > min, "{n} values, expected more than {min}");
    let mean = residuals.iter().sum::<f64>() / n;
    let sigma = (residuals.iter().map(|r| (r - mean).powi(2)).sum::<f64>() / n).sqrt();
    (mean, sigma)
}

#[test]
fn replay_exports_exactly_what_the_classifier_computes() {
    let tmp = tempfile::tempdir().unwrap();
    let (rec, _) = synth(tmp.path(), "complex", "3");
    let out_dir = tmp.path().join("labels");
    let out = export_labels(&rec, &out_dir);
    let summary = String::from_utf8_lossy(&out.stdout);
    assert!(summary.starts_with("3 frames in "), "{summary}");
    assert!(
        summary.contains("attached") && summary.contains("frames/s"),
        "{summary}"
    );

    // SPEC §4: one depth and one rgb PNG per frame, nothing else.
    let mut names: Vec<String> = std::fs::read_dir(&out_dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().into_string().unwrap())
        .collect();
    names.sort();
    assert_eq!(
        names,
        [
            "000000.depth.png",
            "000000.rgb.png",
            "000001.depth.png",
            "000001.rgb.png",
            "000002.depth.png",
            "000002.rgb.png"
        ]
    );

    let recording = Recording::open(Path::new(&rec)).unwrap();
    let mut classifier = Classifier::new(recording.calibration());
    let (mut raw, mut out, mut png) =
        (vec![0u16; PIXELS], Classified::default(), vec![0u8; PIXELS]);
    let mut rgb = vec![0u8; 3 * PIXELS];
    for i in 0..3 {
        recording.read_depth(i, &mut raw).unwrap();
        // With the paired RGB image, as the daemon classifies (the colour split reads it).
        let has_rgb = recording.read_rgb(i, &mut rgb).unwrap();
        classifier.classify_with_rgb(&raw, has_rgb.then_some(&rgb[..]), &mut out);
        read_label_png(&label_path(&out_dir, i, "depth"), &mut png).unwrap();
        assert!(
            png == out.ir_labels,
            "frame {i}: exported IR labels differ from the classifier"
        );
        read_label_png(&label_path(&out_dir, i, "rgb"), &mut png).unwrap();
        assert!(
            png == out.rgb_labels,
            "frame {i}: exported RGB labels differ from the classifier"
        );
    }
}

#[test]
fn eval_scores_the_box_scene_against_ground_truth() {
    let tmp = tempfile::tempdir().unwrap();
    let (rec, gt) = synth(tmp.path(), "box", "1");
    let out = umbra(&["eval", &rec, "--gt", &gt, "--json"]);
    let v: serde_json::Value =
        serde_json::from_slice(&out.stdout).expect("eval --json prints JSON");
    let attached = &v["groups"]["all"]["ir"]["classes"]["attached"];
    // The box scene has a real sensor's noise and widened shadows: still near-perfect.
    assert!(attached["f1"].as_f64().unwrap() > 0.97, "{attached}");
    assert!(attached["support"].as_u64().unwrap() > 5000, "{attached}");
    let any = &v["groups"]["all"]["rgb"]["any_shadow"];
    assert!(any["precision"].as_f64().unwrap() > 0.9, "{any}");

    // The ground truth is independent of the classifier: its attached pixels lie left of the box.
    let g = labels_at(&label_path(Path::new(&gt), 0, "depth"));
    assert!(g.contains(&ATTACHED));
}

/// `[gt][pred]` counts of one label PNG pair, read here rather than by `umbra eval`.
fn confusion(gt: &Path, pred: &Path) -> [[u64; 5]; 5] {
    let (g, p) = (labels_at(gt), labels_at(pred));
    let mut m = [[0u64; 5]; 5];
    for (&a, &b) in g.iter().zip(&p) {
        m[a as usize][b as usize] += 1;
    }
    m
}

fn add(a: [[u64; 5]; 5], b: [[u64; 5]; 5]) -> [[u64; 5]; 5] {
    std::array::from_fn(|i| std::array::from_fn(|j| a[i][j] + b[i][j]))
}

#[test]
fn eval_scores_the_frames_and_views_that_have_ground_truth() {
    // Hand-labelled real frames cover some frames of a recording, often one view only.
    let tmp = tempfile::tempdir().unwrap();
    let (rec, gt) = synth(tmp.path(), "complex", "3");
    let gt = Path::new(&gt);
    let labels = tmp.path().join("labels");
    export_labels(&rec, &labels);
    std::fs::remove_file(label_path(gt, 1, "rgb")).unwrap();
    std::fs::remove_file(label_path(gt, 2, "depth")).unwrap();
    std::fs::remove_file(label_path(gt, 2, "rgb")).unwrap();

    let out = umbra(&["eval", &rec, "--gt", &gt.display().to_string(), "--json"]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains("covers 2 of 3 depth frames in the IR view and 1 in the RGB view"),
        "{stderr}"
    );
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let all = &v["groups"]["all"];
    assert_eq!(all["frames"], 2, "{all}");
    assert_eq!(all["ir"]["frames"], 2);
    assert_eq!(all["rgb"]["frames"], 1);
    let matrix = |view: &str| -> [[u64; 5]; 5] {
        serde_json::from_value(all[view]["confusion"].clone()).unwrap()
    };
    let pair =
        |i: usize, view: &str| confusion(&label_path(gt, i, view), &label_path(&labels, i, view));
    assert_eq!(matrix("ir"), add(pair(0, "depth"), pair(1, "depth")));
    assert_eq!(matrix("rgb"), pair(0, "rgb"));
    // Per recording too (here the only one).
    let one = &v["recordings"][0];
    assert_eq!(one["ir"]["confusion"], all["ir"]["confusion"], "{one}");
    assert_eq!(one["rgb"]["frames"], 1);

    // The table says the views differ, and --per-recording adds the recording's line.
    let out = umbra(&[
        "eval",
        &rec,
        "--gt",
        &gt.display().to_string(),
        "--per-recording",
    ]);
    let table = String::from_utf8_lossy(&out.stdout);
    assert!(
        table.contains("2 frames (scored in the IR view 2, in the RGB view 1)"),
        "{table}"
    );
    let line = table.lines().find(|l| l.starts_with("rec ")).expect(&table);
    let any_p = format!(
        "{:.3}",
        all["ir"]["any_shadow"]["precision"].as_f64().unwrap()
    );
    assert!(
        line.contains(&any_p),
        "{line} lacks IR any-shadow precision {any_p}"
    );
}

/// Another Kinect's calibration (ROS openni defaults: other focal lengths, centres, raw model).
const OTHER_KINECT: &str = "\
[depth]
fx = 575.8157
fy = 575.8157
cx = 319.5
cy = 239.5
width = 640
height = 480
[rgb]
fx = 525.0
fy = 525.0
cx = 319.5
cy = 239.5
width = 640
height = 480
[depth_to_rgb]
rotation = [1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0]
translation = [-0.025, 0.0, 0.0]
[raw]
numerator = 325.616
denominator = 1084.6
baseline_m = 0.075
";

#[test]
fn synth_simulates_another_kinects_calibration_and_the_classifier_follows_it() {
    let tmp = tempfile::tempdir().unwrap();
    let calib_path = tmp.path().join("kinect.toml");
    std::fs::write(&calib_path, OTHER_KINECT).unwrap();
    let (rec, gt) = (tmp.path().join("rec"), tmp.path().join("gt"));
    let (rec, gt) = (rec.display().to_string(), gt.display().to_string());
    umbra(&[
        "synth",
        &rec,
        "--gt",
        &gt,
        "--scene",
        "box",
        "--frames",
        "1",
        "--calibration",
        &calib_path.display().to_string(),
        // Shadows exactly as wide as geometry, for the check by hand below.
        "--ideal",
    ]);
    // The recording carries that calibration.
    let wanted = umbra::calib::Calibration::load(&calib_path).unwrap();
    assert_eq!(
        Recording::open(Path::new(&rec)).unwrap().calibration(),
        &wanted
    );

    // The simulator uses it. By hand: the box's front face (1 m) starts at X = −0.2 m, so at
    // u = cx + fx·X/Z = 319.5 − 575.8157·0.2 = 204.3 (NYU's: 196.5), and its attached shadow on
    // the wall at 3 m is f·b·(1/1 − 1/3) = 575.8157 · 0.075 · 2/3 = 28.79 px wide, left of it.
    let g = labels_at(&label_path(Path::new(&gt), 0, "depth"));
    let row = &g[240 * 640..241 * 640];
    let start = row.iter().position(|&l| l == ATTACHED).unwrap() as f64;
    let end = row.iter().rposition(|&l| l == ATTACHED).unwrap() as f64 + 1.0;
    assert!((end - 204.3).abs() <= 1.0, "attached run [{start}, {end})");
    assert!(
        (end - start - 28.79).abs() <= 1.0,
        "attached run [{start}, {end})"
    );

    // And the classifier, reading it from the recording, still finds that shadow.
    let out = umbra(&["eval", &rec, "--gt", &gt, "--json"]);
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let attached = &v["groups"]["all"]["ir"]["classes"]["attached"];
    assert!(attached["f1"].as_f64().unwrap() > 0.97, "{attached}");
}

#[test]
fn render_draws_three_panels_with_legend() {
    let tmp = tempfile::tempdir().unwrap();
    let (rec, _) = synth(tmp.path(), "box", "2");
    let png = tmp.path().join("frame.png");
    umbra(&[
        "render",
        &rec,
        "--frame",
        "1",
        "--out",
        &png.display().to_string(),
    ]);
    let img = image::open(&png).unwrap().to_rgb8();
    assert!(
        img.width() >= 3 * 640 && img.height() > 480,
        "{}x{}",
        img.width(),
        img.height()
    );
    // Pure paper red appears (the box's attached shadow in the IR panel).
    assert!(img.pixels().any(|p| p.0 == [255, 0, 0]));
}

#[test]
fn render_against_ground_truth_marks_each_missed_pixel_in_its_true_colour() {
    let tmp = tempfile::tempdir().unwrap();
    let (rec, gt) = synth(tmp.path(), "complex", "1");
    let gt = Path::new(&gt);
    let labels = tmp.path().join("labels");
    export_labels(&rec, &labels);
    let png = tmp.path().join("truth.png");
    let render = |gt: &Path| {
        umbra(&[
            "render",
            &rec,
            "--gt",
            &gt.display().to_string(),
            "--out",
            &png.display().to_string(),
        ]);
        image::open(&png).unwrap().to_rgb8()
    };
    let img = render(gt);
    use umbra::render::{truth_panel_origin, LEGEND_HEIGHT, TITLE_HEIGHT};
    assert_eq!(img.height(), 2 * (TITLE_HEIGHT + 480) + LEGEND_HEIGHT);

    // The IR error panel, counted against the label PNGs read here: a pixel the ground truth
    // labels a shadow or other hole and the frame labels otherwise is that label's paper colour;
    // no pixel where the two agree is.
    let (truth, pred) = (
        labels_at(&label_path(gt, 0, "depth")),
        labels_at(&label_path(&labels, 0, "depth")),
    );
    let (x0, y0) = truth_panel_origin(1);
    let (mut missed, mut shown) = (0, 0);
    for i in 0..PIXELS {
        let p = img
            .get_pixel(x0 + (i % 640) as u32, y0 + (i / 640) as u32)
            .0;
        let paper = umbra::labels::COLOURS[truth[i] as usize];
        if truth[i] != pred[i] && truth[i] != 0 {
            missed += 1;
            assert_eq!(
                p, paper,
                "pixel {i}: truth {}, labelled {}",
                truth[i], pred[i]
            );
        }
        shown += usize::from(p == paper && truth[i] != 0);
    }
    assert!(missed > 100, "a complex scene has misses ({missed})");
    assert_eq!(
        shown, missed,
        "only missed pixels are drawn in their true colour"
    );

    // Without the RGB view's ground truth its panel says so; without any, a one-line error.
    std::fs::remove_file(label_path(gt, 0, "rgb")).unwrap();
    let img = render(gt);
    let (x0, y0) = truth_panel_origin(2);
    let inked = (y0 + 220..y0 + 260)
        .flat_map(|y| (x0 + 180..x0 + 460).map(move |x| (x, y)))
        .any(|(x, y)| img.get_pixel(x, y).0 == [235, 235, 235]);
    assert!(inked, "caption in the RGB error panel");
    std::fs::remove_file(label_path(gt, 0, "depth")).unwrap();
    let gt = gt.display().to_string();
    let err = umbra_fails(&[
        "render",
        &rec,
        "--gt",
        &gt,
        "--out",
        &png.display().to_string(),
    ]);
    assert!(err.contains("no ground truth for frame 0"), "{err}");
}

#[test]
fn replay_to_mcap_and_tail_back_gives_the_same_labels() {
    let tmp = tempfile::tempdir().unwrap();
    let (rec, _) = synth(tmp.path(), "complex", "2");
    let (png, mcap, back) = (
        tmp.path().join("png"),
        tmp.path().join("mcap"),
        tmp.path().join("back"),
    );
    umbra(&[
        "replay",
        &rec,
        "--export-labels",
        &png.display().to_string(),
        "--mcap",
        &mcap.display().to_string(),
    ]);
    umbra(&[
        "tail",
        &mcap.display().to_string(),
        "--export-labels",
        &back.display().to_string(),
    ]);
    let (mut a, mut b) = (vec![0u8; PIXELS], vec![0u8; PIXELS]);
    for i in 0..2 {
        for view in ["depth", "rgb"] {
            read_label_png(&label_path(&png, i, view), &mut a).unwrap();
            read_label_png(&label_path(&back, i, view), &mut b).unwrap();
            assert!(
                a == b,
                "frame {i} {view}: labels read back from MCAP differ from the export"
            );
        }
    }
}

/// `umbra bench classify` times every frame it was asked for, each also upside down, and reports
/// the plain copy beside it; what it cannot time is a one-line error naming the folder.
#[test]
fn bench_classify_times_each_frame_and_its_mirror_next_to_a_plain_copy() {
    let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/recordings/complex-room");
    let frames = Recording::open(Path::new(dir)).unwrap().len();
    // No time limit: exactly one timed pass.
    let out = umbra(&["bench", "classify", dir, "--seconds", "0"]);
    let report = String::from_utf8_lossy(&out.stdout);
    let timed: usize = report
        .split(": ")
        .nth(1)
        .and_then(|s| s.split(' ').next())
        .and_then(|n| n.parse().ok())
        .unwrap_or_else(|| panic!("no frame count in {report}"));
    assert_eq!(timed, 2 * frames, "{report}");
    assert!(
        report.contains("with RGB") && report.contains("ms per frame on one core"),
        "{report}"
    );
    assert!(
        report.contains("plain copy of a depth frame in the same run"),
        "{report}"
    );
    // Two frames asked of a three-frame recording, depth only.
    let out = umbra(&[
        "bench",
        "classify",
        dir,
        "--seconds",
        "0",
        "--frames",
        "2",
        "--no-rgb",
    ]);
    let report = String::from_utf8_lossy(&out.stdout);
    assert!(
        report.contains("(depth only, ") && report.contains("): 4 frames in "),
        "{report}"
    );

    let err = umbra_fails(&["bench", "classify", dir, "--frames", "0"]);
    assert_eq!(err.trim().lines().count(), 1, "{err}");
    assert!(
        err.contains("complex-room") && err.contains("no frames to time"),
        "{err}"
    );
}

#[test]
fn synth_takes_the_depth_sensors_noise() {
    let tmp = tempfile::tempdir().unwrap();
    let make = |name: &str, extra: &[&str]| {
        let (rec, gt) = synth_box(tmp.path(), name, extra);
        let mut raw = vec![0u16; PIXELS];
        Recording::open(&rec)
            .unwrap()
            .read_depth(0, &mut raw)
            .unwrap();
        (raw, std::fs::read_to_string(gt.join("meta.toml")).unwrap())
    };
    let (clean, _) = make("clean", &[]);
    let (noisy, meta) = make("noisy", &["--depth-noise", "3"]);
    assert!(meta.contains("noise_sigma_raw = 3.0"), "{meta}");
    // The same holes; on the measured pixels Gaussian noise of σ = 3 raw units (rounded: the
    // variance grows by 1/12).
    let residuals: Vec<f64> = clean
        .iter()
        .zip(&noisy)
        .filter_map(|(&c, &n)| {
            assert_eq!(c == 2047, n == 2047, "a hole in one frame only");
            (c != 2047).then(|| f64::from(n) - f64::from(c))
        })
        .collect();
    let (mean, sigma) = mean_and_sigma(&residuals, 0.5 * PIXELS as f64);
    // The clean frame's values are rounded once: the mean moves by their rounding, under half a unit.
    assert!(mean.abs() < 0.5, "mean residual {mean:.3}");
    assert!(
        (sigma - (9.0f64 + 1.0 / 12.0).sqrt()).abs() < 0.1,
        "noise σ {sigma:.3}"
    );
}

#[test]
fn synth_takes_the_colour_cameras_noise_exposure_and_softness() {
    let tmp = tempfile::tempdir().unwrap();
    let make = |name: &str, extra: &[&str]| {
        let args: Vec<&str> = ["--seed", "3"].iter().chain(extra).copied().collect();
        let (rec, gt) = synth_box(tmp.path(), name, &args);
        let mut rgb = vec![0u8; 3 * PIXELS];
        assert!(Recording::open(&rec)
            .unwrap()
            .read_rgb(0, &mut rgb)
            .unwrap());
        (rgb, std::fs::read_to_string(gt.join("meta.toml")).unwrap())
    };
    let (clean, _) = make("clean", &[]);
    let (dim, meta) = make("dim", &["--rgb-gain", "0.5", "--rgb-noise", "6"]);
    assert!(
        meta.contains("rgb_gain = 0.5") && meta.contains("rgb_noise_sigma = 6.0"),
        "{meta}"
    );
    // The same scene at half the exposure, plus Gaussian noise of σ = 6 on every value (away
    // from black and from clipping, where the noise is cut).
    let residuals: Vec<f64> = clean
        .iter()
        .zip(&dim)
        .filter(|&(&c, _)| (40..=240).contains(&c))
        .map(|(&c, &d)| f64::from(d) - f64::from(c) * 0.5)
        .collect();
    let (mean, sigma) = mean_and_sigma(&residuals, 0.5 * (3 * PIXELS) as f64);
    assert!(mean.abs() < 0.3, "mean residual {mean:.2}");
    assert!((sigma - 6.0).abs() < 0.3, "noise σ {sigma:.2}");

    // A soft lens: the noise-free image through the [1 2 1]/4 kernel each way, the labels
    // untouched.
    let (soft, meta) = make("soft", &["--rgb-soft"]);
    assert!(meta.contains("rgb_soft = true"), "{meta}");
    assert!(
        soft == umbra::synth::soften(&clean),
        "the sharp image, softened"
    );
    assert!(soft != clean, "a box's edges do blur");
    for view in ["depth", "rgb"] {
        let gt = |name: &str| {
            std::fs::read(tmp.path().join(format!("{name}-gt/000000.{view}.png"))).unwrap()
        };
        assert!(gt("soft") == gt("clean"), "{view} labels");
    }
}

#[test]
fn synth_refuses_out_of_range_sensor_switches() {
    // Out-of-range values are one-line errors naming the flag.
    let tmp = tempfile::tempdir().unwrap();
    let suite = tmp.path().join("x").display().to_string();
    for (flag, value) in [
        ("--rgb-noise", "100"),
        ("--rgb-gain", "0"),
        ("--rgb-gain", "nan"),
        ("--depth-noise", "20"),
    ] {
        let err = umbra_fails(&["synth", "--suite", &suite, flag, value]);
        assert!(err.contains(flag), "{flag} {value}: {err}");
    }
}

/// Every file of a folder, by name, with its bytes.
fn files(dir: &Path) -> Vec<(std::ffi::OsString, Vec<u8>)> {
    let mut v: Vec<_> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| {
            let e = e.unwrap();
            (e.file_name(), std::fs::read(e.path()).unwrap())
        })
        .collect();
    v.sort();
    v
}

/// `--export-labels` never overwrites what it did not write: a folder holding anything but label
/// PNGs (a ground-truth folder has meta.toml) is refused with one line and left as it was; an
/// earlier export is replaced, with a warning, its frames past the new last one removed; a failed
/// run leaves no empty folder behind.
#[test]
fn export_labels_keeps_what_it_did_not_write() {
    let tmp = tempfile::tempdir().unwrap();
    let (rec, gt) = synth_box(tmp.path(), "box", &[]);
    let rec = rec.display().to_string();
    let before = files(&gt);
    let err = umbra_fails(&["replay", &rec, "--export-labels", &gt.display().to_string()]);
    assert_eq!(err.trim().lines().count(), 1, "{err}");
    assert!(
        err.contains("meta.toml") && err.contains(&*gt.display().to_string()),
        "{err}"
    );
    let after = files(&gt);
    assert!(before == after, "the ground-truth folder changed");

    // An earlier export of a longer recording: replaced, and its frames past this one's last
    // removed, so that the folder holds exactly the files of the recording exported last.
    let labels = tmp.path().join("labels");
    let room = concat!(env!("CARGO_MANIFEST_DIR"), "/recordings/complex-room");
    export_labels(room, &labels);
    assert!(label_path(&labels, 2, "rgb").exists());
    let again = export_labels(&rec, &labels);
    let warning = String::from_utf8_lossy(&again.stderr);
    assert!(
        warning.contains("replacing the label PNGs of an earlier export"),
        "{warning}"
    );
    let names: Vec<_> = files(&labels).into_iter().map(|(n, _)| n).collect();
    assert_eq!(names, ["000000.depth.png", "000000.rgb.png"]);

    let bad = tmp.path().join("bad");
    std::fs::create_dir(&bad).unwrap();
    std::fs::write(bad.join("INDEX.txt"), "d-1.0-1.pgm\n").unwrap();
    std::fs::write(bad.join("d-1.0-1.pgm"), b"P5 640 480 65535\n").unwrap();
    let never = tmp.path().join("never");
    umbra_fails(&[
        "replay",
        &bad.display().to_string(),
        "--export-labels",
        &never.display().to_string(),
    ]);
    assert!(
        !never.exists(),
        "a failed replay left {} behind",
        never.display()
    );
}

/// `render` writes a PNG: another extension is refused before any work, and a folder that does
/// not exist yet is made.
#[test]
fn render_writes_png_files_only_and_makes_their_folder() {
    let tmp = tempfile::tempdir().unwrap();
    let (rec, _) = synth_box(tmp.path(), "box", &[]);
    let rec = rec.display().to_string();
    let jpg = tmp.path().join("x.jpg");
    let err = umbra_fails(&["render", &rec, "--out", &jpg.display().to_string()]);
    assert!(err.contains(".png"), "{err}");
    assert!(!jpg.exists());
    let png = tmp.path().join("new").join("deeper").join("x.png");
    umbra(&["render", &rec, "--out", &png.display().to_string()]);
    assert!(image::open(&png).is_ok());
}

/// Printing into a pipe whose reader has gone (`umbra eval … | head -1`) ends quietly, as other
/// command-line tools do, with no panic message.
#[test]
fn a_closed_stdout_pipe_ends_quietly() {
    let rec = concat!(env!("CARGO_MANIFEST_DIR"), "/recordings/complex-room");
    let gt = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/recordings/ground-truth/complex-room"
    );
    let mut child = Command::new(env!("CARGO_BIN_EXE_umbra"))
        .args(["eval", rec, "--gt", gt, "--per-recording"])
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    drop(child.stdout.take());
    let out = child.wait_with_output().unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        !err.contains("panicked") && !err.contains("Broken pipe"),
        "{err}"
    );
}

/// `--seconds` takes what a `Duration` can hold: `inf` was a panic.
#[test]
fn bench_refuses_seconds_it_cannot_wait() {
    let rec = concat!(env!("CARGO_MANIFEST_DIR"), "/recordings/complex-room");
    for s in ["inf", "1e30", "nan"] {
        let err = umbra_fails(&["bench", "classify", rec, "--seconds", s]);
        assert!(
            err.contains("--seconds") && !err.contains("panicked"),
            "{s}: {err}"
        );
    }
}

/// The IR view has no alignment shadows (SPEC §2): an IR-view ground-truth PNG holding code 3
/// (an RGB-view file under the wrong name, most likely) is an error naming the pixel, not
/// pixels silently left out of every score.
#[test]
fn eval_refuses_alignment_in_ir_view_ground_truth() {
    let tmp = tempfile::tempdir().unwrap();
    let (rec, gt) = synth_box(tmp.path(), "box", &[]);
    let depth = label_path(&gt, 0, "depth");
    let mut labels = labels_at(&depth);
    labels[7 * 640 + 5] = 3;
    umbra::sink::labels::write_label_png(&depth, &labels).unwrap();
    let err = umbra_fails(&[
        "eval",
        &rec.display().to_string(),
        "--gt",
        &gt.display().to_string(),
    ]);
    assert!(
        err.contains("000000.depth.png") && err.contains("pixel (5, 7)"),
        "{err}"
    );
}

/// `synth --shadow-widening L,R` simulates a sensor whose correlation window widens shadows
/// more: the box scene's attached shadow (29.1 px by eq. (3)) comes out wider on average than
/// with the default 3,2 by about what the larger bounds add, and meta.toml says so; bad values
/// are refused.
#[test]
fn synth_shadow_widening_widens_shadows() {
    let tmp = tempfile::tempdir().unwrap();
    let mean_width = |extra: &[&str], name: &str| {
        let (_, gt) = synth_box(tmp.path(), name, extra);
        let labels = labels_at(&label_path(&gt, 0, "depth"));
        let widths: Vec<f64> = labels
            .chunks(640)
            .map(|r| r.iter().filter(|&&l| l == ATTACHED).count() as f64)
            .filter(|&n| n > 0.0)
            .collect();
        let meta = std::fs::read_to_string(gt.join("meta.toml")).unwrap();
        (widths.iter().sum::<f64>() / widths.len() as f64, meta)
    };
    // --ideal leaves every artefact out but the widening asked for.
    let (plain, _) = mean_width(&["--shadow-widening", "0,0"], "none");
    let (kinect, _) = mean_width(&["--shadow-widening", "3,2"], "kinect");
    let (wide, meta) = mean_width(&["--shadow-widening", "6,6"], "wide");
    assert!((plain - 29.1).abs() < 0.6, "no widening: {plain}");
    assert!(
        (1.5..3.0).contains(&(kinect - plain)),
        "3,2: +{}",
        kinect - plain
    );
    assert!(
        (4.0..6.5).contains(&(wide - plain)),
        "6,6: +{}",
        wide - plain
    );
    assert!(meta.contains("shadow_widening_max_px = [6, 6]"), "{meta}");
    let err = umbra_fails(&["synth", "--scene", "box", "--shadow-widening", "13,2"]);
    assert!(err.contains("--shadow-widening"), "{err}");
}

/// Ground truth stays outside the recording folder (replaying it must not see the answers):
/// `--gt` inside OUT_REC, or OUT_REC inside `--gt`, is refused before anything is written.
#[test]
fn synth_keeps_ground_truth_outside_the_recording() {
    let tmp = tempfile::tempdir().unwrap();
    let rec = tmp.path().join("rec");
    for (out, gt) in [(rec.clone(), rec.join("gt")), (rec.join("r"), rec.clone())] {
        let (o, g) = (out.display().to_string(), gt.display().to_string());
        let err = umbra_fails(&["synth", &o, "--gt", &g, "--scene", "box"]);
        assert!(err.contains("outside the recording folder"), "{err}");
        assert!(!rec.exists(), "{} was written", rec.display());
    }
}

/// A `--gt` folder that does not exist is said so, by eval and by render, in one line.
#[test]
fn a_missing_ground_truth_folder_is_named() {
    let rec = concat!(env!("CARGO_MANIFEST_DIR"), "/recordings/complex-room");
    let tmp = tempfile::tempdir().unwrap();
    let gt = tmp.path().join("no-such-gt").display().to_string();
    let png = tmp.path().join("x.png").display().to_string();
    for args in [
        vec!["eval", rec, "--gt", &gt],
        vec!["render", rec, "--gt", &gt, "--out", &png],
    ] {
        let err = umbra_fails(&args);
        assert_eq!(err.trim().lines().count(), 1, "{err}");
        assert!(err.contains("no-such-gt: no such folder"), "{err}");
    }
}
