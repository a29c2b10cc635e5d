//! Issue 4: shadow-assisted foreground segmentation, checked against the simulator's exact
//! foreground masks and hand-computed geometry, and the `umbra segment` / `umbra eval --segment`
//! tools end to end.

mod common;

use common::{bundled, one_line_error, run, s};
use umbra::classify::{Classified, Classifier};
use umbra::eval::{MaskCounts, SegTally};
use umbra::labels::{PIXELS, WIDTH};
use umbra::segment::files::read_mask_png;
use umbra::segment::{Params, SeedMode, Segmenter, BG, FG};
use umbra::synth::{
    random_scene, render_frame, sensor_for, Category, Scene, SensorModel, SynthFrame,
};
use umbra::Calibration;

/// Classifies and segments one simulated frame; returns the mask and its score.
fn segment(calib: &Calibration, f: &SynthFrame, mode: SeedMode) -> (Vec<u8>, SegTally) {
    let mut out = Classified::default();
    Classifier::new(calib).classify(&f.raw, &mut out);
    let mut seg = Segmenter::new(Params {
        seeds: mode,
        ..Params::default()
    });
    let mut mask = vec![0u8; PIXELS];
    seg.segment(&f.rgb, &out, &mut mask);
    let mut t = SegTally::default();
    t.add_frame(&f.fg, &mask, seg.seeds(), FG, BG);
    (mask, t)
}

/// Foreground columns of one row of a mask: first and last.
fn extent(mask: &[u8], v: usize) -> (usize, usize) {
    let row = &mask[v * WIDTH..(v + 1) * WIDTH];
    (
        row.iter().position(|&m| m != 0).unwrap(),
        row.iter().rposition(|&m| m != 0).unwrap(),
    )
}

#[test]
fn box_before_wall_is_segmented_where_geometry_puts_it() {
    let calib = Calibration::nyu_default();
    let f = render_frame(
        &Scene::box_before_wall(1.0, 3.0),
        &calib,
        &SensorModel::kinect(),
        7,
    );
    // By hand: the box's front face spans x ∈ [−0.2, 0.2] m at z = 1 m in the IR frame; the RGB
    // camera sits 2.5 cm to the right, so in its view x ∈ [−0.225, 0.175] m, columns
    // u = 518.86·x + 325.58 ∈ [208.8, 416.4]; rows y ∈ [−0.25, 0.25] m → v ∈ [123.9, 383.6].
    let (u0, u1) = (
        calib.rgb.fx * -0.225 + calib.rgb.cx,
        calib.rgb.fx * 0.175 + calib.rgb.cx,
    );
    let (gt0, gt1) = extent(&f.fg, 250);
    assert!(
        (gt0 as f64 - u0).abs() <= 1.0 && (gt1 as f64 - u1).abs() <= 1.0,
        "ground truth {gt0}..{gt1}, by hand {u0:.1}..{u1:.1}"
    );
    let (mask, t) = segment(&calib, &f, SeedMode::Shadow);
    for v in [130, 200, 250, 300, 375] {
        let (a, b) = extent(&mask, v);
        assert!(
            (a as f64 - u0).abs() <= 2.5 && (b as f64 - u1).abs() <= 2.5,
            "row {v}: mask {a}..{b}, by hand {u0:.1}..{u1:.1}"
        );
    }
    let iou = t.mean_iou().unwrap();
    assert!(iou >= 0.97, "IoU {iou:.3}");
    assert!(
        t.seed_precision().unwrap() >= 0.99,
        "seed precision {:?}",
        t.seed_precision()
    );
    assert!(mask.iter().all(|&m| m == 0 || m == 255));
}

#[test]
fn shadow_seeds_beat_threshold_seeds_on_random_scenes() {
    let calib = Calibration::nyu_default();
    let (mut shadow, mut threshold) = ([SegTally::default(); 2], [SegTally::default(); 2]);
    for (c, cat) in [Category::Simple, Category::Complex]
        .into_iter()
        .enumerate()
    {
        for seed in 900..903 {
            let f = render_frame(&random_scene(cat, seed), &calib, &sensor_for(cat), seed);
            shadow[c].merge(&segment(&calib, &f, SeedMode::Shadow).1);
            threshold[c].merge(
                &segment(
                    &calib,
                    &f,
                    SeedMode::Threshold {
                        tf_m: 2.0,
                        tb_m: 2.5,
                    },
                )
                .1,
            );
        }
    }
    for (c, name) in ["simple", "complex"].iter().enumerate() {
        let (s_iou, t_iou) = (
            shadow[c].mean_iou().unwrap(),
            threshold[c].mean_iou().unwrap(),
        );
        assert!(
            s_iou > t_iou,
            "{name}: shadow {s_iou:.3} vs threshold {t_iou:.3}"
        );
        assert!(
            shadow[c].seed_precision().unwrap() >= 0.98,
            "{name}: seed precision {:?}",
            shadow[c].seed_precision()
        );
    }
    assert!(
        shadow[0].mean_iou().unwrap() >= 0.9,
        "simple IoU {:?}",
        shadow[0].mean_iou()
    );
}

#[test]
fn no_shadow_means_no_foreground() {
    // A bare wall: no shadow, no seed, nothing salient.
    let calib = Calibration::nyu_default();
    let mut scene = Scene::new("bare wall");
    scene.push(
        "wall",
        umbra::synth::scene::wall(2.5),
        umbra::synth::Material::matte([0.8, 0.8, 0.7]),
    );
    let f = render_frame(&scene, &calib, &SensorModel::kinect(), 1);
    assert!(f.fg.iter().all(|&m| m == 0));
    let (mask, t) = segment(&calib, &f, SeedMode::Shadow);
    assert!(mask.iter().all(|&m| m == 0));
    assert_eq!(t.mean_iou(), Some(1.0));
    assert_eq!(MaskCounts::of(&f.fg, &mask).iou(), 1.0);
}

#[test]
fn umbra_segment_writes_masks_and_overlays() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("out");
    let (ok, stdout, stderr) = run(&[
        "segment",
        &bundled("box-before-wall"),
        "--frame",
        "1",
        "--out",
        &s(&out),
    ]);
    assert!(ok, "{stderr}");
    assert!(
        stdout.starts_with("segment: 1 frame of ") && stdout.lines().count() == 1,
        "{stdout}"
    );
    assert!(!out.join("000000.fg.png").exists());
    let mut mask = vec![0u8; PIXELS];
    read_mask_png(&out.join("000001.fg.png"), &mut mask).unwrap();
    let mut gt = vec![0u8; PIXELS];
    read_mask_png(
        &std::path::Path::new(&bundled("ground-truth/box-before-wall")).join("000001.fg.png"),
        &mut gt,
    )
    .unwrap();
    let iou = MaskCounts::of(&gt, &mask).iou();
    assert!(iou >= 0.97, "IoU {iou:.3}");
    let overlay = image::open(out.join("000001.overlay.png")).unwrap();
    assert_eq!((overlay.width(), overlay.height()), (640, 480));

    // Every frame, threshold seeds.
    let (ok, _, stderr) = run(&[
        "segment",
        &bundled("complex-room"),
        "--out",
        &s(&out),
        "--seeds",
        "threshold",
        "--tf",
        "1.8",
        "--tb",
        "2.6",
    ]);
    assert!(ok, "{stderr}");
    for i in 0..3 {
        read_mask_png(&out.join(format!("{i:06}.fg.png")), &mut mask).unwrap();
    }
}

#[test]
fn umbra_segment_bad_input_is_one_line() {
    let tmp = tempfile::tempdir().unwrap();
    let out = s(&tmp.path().join("o"));
    let (ok, _, err) = run(&[
        "segment",
        &bundled("box-before-wall"),
        "--frame",
        "2",
        "--out",
        &out,
    ]);
    one_line_error(ok, &err, &["frame 2 is out of range", "box-before-wall"]);
    let missing = s(&tmp.path().join("nope"));
    let (ok, _, err) = run(&["segment", &missing, "--out", &out]);
    one_line_error(ok, &err, &["nope"]);
    let file = tmp.path().join("file");
    std::fs::write(&file, "x").unwrap();
    let (ok, _, err) = run(&["segment", &bundled("box-before-wall"), "--out", &s(&file)]);
    one_line_error(ok, &err, &["file", "creating folder"]);
    let (ok, _, err) = run(&[
        "segment",
        &bundled("box-before-wall"),
        "--out",
        &out,
        "--seeds",
        "threshold",
        "--tf",
        "3",
        "--tb",
        "2",
    ]);
    one_line_error(ok, &err, &["--tf 3 --tb 2"]);
}

#[test]
fn umbra_eval_segment_reports_both_seed_kinds() {
    let (ok, stdout, stderr) = run(&[
        "eval",
        &bundled("box-before-wall"),
        "--gt",
        &bundled("ground-truth/box-before-wall"),
        "--segment",
        "--tf",
        "1.5",
        "--tb",
        "2.5",
    ]);
    assert!(ok, "{stderr}");
    assert!(stdout.contains("segmentation: threshold baseline at the best fixed pair of 1 tried, Tf 1.50 m, Tb 2.50 m"), "{stdout}");
    let row = stdout
        .lines()
        .find(|l| l.starts_with("simple   shadow"))
        .expect("simple shadow row");
    let iou: f64 = row.split_whitespace().nth(3).unwrap().parse().unwrap();
    assert!(iou >= 0.97, "{row}");
    let (ok, stdout, _) = run(&[
        "eval",
        &bundled("box-before-wall"),
        "--gt",
        &bundled("ground-truth/box-before-wall"),
        "--segment",
        "--tf",
        "1.5",
        "--tb",
        "2.5",
        "--json",
    ]);
    assert!(ok);
    let v: serde_json::Value = serde_json::from_str(&stdout).unwrap();
    assert!(
        v["segmentation"]["groups"]["simple"]["shadow"]["mean_iou"]
            .as_f64()
            .unwrap()
            >= 0.97
    );
    assert_eq!(
        v["segmentation"]["best_threshold"]["tf_m"].as_f64(),
        Some(1.5)
    );
    // Without --segment the output is what it always was: no segmentation block.
    let (_, stdout, _) = run(&[
        "eval",
        &bundled("box-before-wall"),
        "--gt",
        &bundled("ground-truth/box-before-wall"),
    ]);
    assert!(!stdout.contains("segmentation"));
    // Ground truth without masks: one line naming the missing file.
    let tmp = tempfile::tempdir().unwrap();
    for f in [
        "000000.depth.png",
        "000000.rgb.png",
        "000001.depth.png",
        "000001.rgb.png",
    ] {
        std::fs::copy(
            std::path::Path::new(&bundled("ground-truth/box-before-wall")).join(f),
            tmp.path().join(f),
        )
        .unwrap();
    }
    let (ok, _, err) = run(&[
        "eval",
        &bundled("box-before-wall"),
        "--gt",
        &s(tmp.path()),
        "--segment",
        "--tf",
        "1.5",
        "--tb",
        "2.5",
    ]);
    one_line_error(ok, &err, &["000000.fg.png", "missing"]);
}
