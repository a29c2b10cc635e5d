//! The classifier against independent ground truth: hand-computed geometry for the scenes whose
//! answer fits on paper, and the simulator's exact labels (ray-cast visibility, not the
//! classifier's equations) for random scenes.
//!
//! Thresholds on random scenes are the issue's targets where the classifier meets them on these
//! scenes, and regression floors a little under the measured value elsewhere (noted per assert).

use umbra::classify::{Classified, Classifier};
use umbra::eval::Confusion;
use umbra::labels::{ALIGNMENT, ATTACHED, DETACHED, HEIGHT, NO_DEPTH, OTHER, PIXELS, VALID, WIDTH};
use umbra::synth::scene::{slanted_wall, vertical_rod, wall};
use umbra::synth::{
    random_scene, render_frame, sensor_for, Category, Scene, SensorModel, SynthFrame,
};
use umbra::Calibration;

fn classify(calib: &Calibration, frame: &SynthFrame) -> Classified {
    let mut out = Classified::default();
    Classifier::new(calib).classify(&frame.raw, &mut out);
    out
}

/// How many of `pixels` (frame indices) `labels` gives `code`.
fn count_labelled(labels: &[u8], pixels: &[usize], code: u8) -> usize {
    pixels.iter().filter(|&&i| labels[i] == code).count()
}

fn count_in_row(labels: &[u8], v: usize, code: u8) -> usize {
    labels[v * WIDTH..(v + 1) * WIDTH]
        .iter()
        .filter(|&&l| l == code)
        .count()
}

/// Over the rows where the simulator casts an attached shadow (`frame`'s ground truth): how many
/// there are, and in how many `labels` holds attached pixels too. `check(v, n, truth)` sees each
/// such row's counts (and asserts what the test wants of them); rows where the simulator casts
/// none must have no attached pixels in `labels` either.
fn attached_rows(
    frame: &SynthFrame,
    labels: &[u8],
    mut check: impl FnMut(usize, usize, usize),
) -> (usize, usize) {
    let (mut rows, mut split) = (0, 0);
    for v in 0..HEIGHT {
        let truth = count_in_row(&frame.ir_labels, v, ATTACHED);
        let n = count_in_row(labels, v, ATTACHED);
        if truth == 0 {
            assert_eq!(n, 0, "row {v}: attached pixels where nothing casts them");
            continue;
        }
        check(v, n, truth);
        rows += 1;
        split += usize::from(n > 0);
    }
    (rows, split)
}

/// The hand-computed box (front face x = −0.2..0.2 m at 1 m) before a wall at 3 m, black: the
/// sensor measures no depth on it.
fn black_box_before_wall() -> Scene {
    let mut scene = Scene::box_before_wall(1.0, 3.0);
    scene.objects[1].material = umbra::synth::Material::black();
    scene
}

/// A scene of `description` with nothing in it but a matte wall of `colour` at `z` metres,
/// for the objects a test pushes before it.
fn before_a_wall(description: &str, z: f64, colour: [f64; 3]) -> Scene {
    let mut scene = Scene::new(description);
    scene.push("wall", wall(z), umbra::synth::Material::matte(colour));
    scene
}

/// A cylinder of `material` centred 1.5 m in front of the camera, its axis `(x, y)` in the image
/// plane, `(radius, half_len)` metres, before a grey wall at 3 m.
fn cylinder_at_1_5_m_before_a_wall(
    (x, y): (f64, f64),
    (radius, half_len): (f64, f64),
    material: umbra::synth::Material,
) -> Scene {
    let mut scene = before_a_wall("a cylinder at 1.5 m", 3.0, [0.8, 0.78, 0.7]);
    scene.push(
        "cylinder",
        umbra::synth::Shape::Cylinder {
            centre: umbra::synth::V3::new(0.0, 0.0, 1.5),
            axis: umbra::synth::V3::new(x, y, 0.0),
            radius,
            half_len,
        },
        material,
    );
    scene
}

/// Asserts that `found` of `truth` pixels of a class, `what`, over `rows` rows reach a recall of
/// `min`.
fn assert_recall(what: &str, found: usize, truth: usize, rows: usize, min: f64) {
    let recall = found as f64 / truth as f64;
    assert!(
        recall >= min,
        "{what} recall {recall:.3} ({found} of {truth} px) over {rows} rows"
    );
}

/// Over the rows where `frame`'s ground truth holds detached pixels in the columns `us`: how
/// many such rows and pixels there are, and how many of those pixels `labels` calls detached.
fn detached_in_columns(
    frame: &SynthFrame,
    labels: &[u8],
    us: std::ops::Range<usize>,
) -> (usize, usize, usize) {
    let (mut rows, mut truth, mut found) = (0, 0, 0);
    for v in 0..HEIGHT {
        let row = v * WIDTH;
        let ours = us.clone().filter(|&u| frame.ir_labels[row + u] == DETACHED);
        let (n, hit) = ours.fold((0, 0), |(n, hit), u| {
            (n + 1, hit + usize::from(labels[row + u] == DETACHED))
        });
        rows += usize::from(n > 0);
        truth += n;
        found += hit;
    }
    (rows, truth, found)
}

/// Adds a grey vertical rod of `radius` with its axis at (`x`, ·, `z`), crossing the image.
fn push_grey_rod(scene: &mut Scene, x: f64, z: f64, radius: f64) {
    scene.push(
        "rod",
        umbra::synth::Shape::Cylinder {
            centre: umbra::synth::V3::new(x, 0.0, z),
            axis: umbra::synth::V3::new(0.0, 1.0, 0.0),
            radius,
            half_len: 3.0,
        },
        umbra::synth::Material::matte([0.6, 0.6, 0.65]),
    );
}

#[test]
fn box_one_metre_before_wall_at_three() {
    let calib = Calibration::nyu_default();
    let frame = render_frame(
        &Scene::box_before_wall(1.0, 3.0),
        &calib,
        &SensorModel::ideal(),
        1,
    );
    let out = classify(&calib, &frame);
    // By hand: f·b·(1/1 − 1/3) = 582.62 · 0.075 · 2/3 = 29.13 px of attached shadow per row.
    let w = calib.fb() * (1.0 - 1.0 / 3.0);
    // RGB camera 2.5 cm right of the IR camera: f_rgb·0.025·(1/1 − 1/3) = 8.65 px of alignment,
    // and the projector shadow narrows to f_rgb·(0.075 − 0.025)·(2/3) = 17.3 px.
    let align = calib.rgb.fx * 0.025 * (1.0 - 1.0 / 3.0);
    let shadow_rgb = calib.rgb.fx * 0.05 * (1.0 - 1.0 / 3.0);
    let mut rows = 0;
    for v in 0..HEIGHT {
        let n = count_in_row(&out.ir_labels, v, ATTACHED);
        if count_in_row(&frame.ir_labels, v, ATTACHED) == 0 {
            assert_eq!(n, 0, "row {v}: attached pixels where the box casts none");
            continue;
        }
        rows += 1;
        assert!(
            (n as f64 - w).abs() <= 1.0,
            "IR row {v}: {n} attached px, hand-computed {w:.2}"
        );
    }
    assert!(rows > 100, "the box spans {rows} rows");
    let mut rgb_rows = 0;
    for v in 0..HEIGHT {
        let n = count_in_row(&out.rgb_labels, v, ALIGNMENT);
        if n == 0 {
            continue;
        }
        rgb_rows += 1;
        assert!(
            (n as f64 - align).abs() <= 1.0,
            "RGB row {v}: {n} alignment px, hand-computed {align:.2}"
        );
        let s = count_in_row(&out.rgb_labels, v, ATTACHED) as f64;
        assert!(
            (s - shadow_rgb).abs() <= 1.5,
            "RGB row {v}: {s} attached px, hand-computed {shadow_rgb:.2}"
        );
    }
    assert!(rgb_rows > 100);
    // And pixel for pixel against the simulator: the IR view is exact on this scene.
    let mut c = Confusion::default();
    c.add(&frame.ir_labels, &out.ir_labels);
    assert_eq!(c.class(ATTACHED).f1, Some(1.0));
}

#[test]
fn shadow_in_the_rgb_view_has_straight_top_and_bottom_edges() {
    // The hand-computed box, ideal sensor. The warp fills the box's shadow with the wall's depth,
    // so along the shadow's top and bottom edges a shadow pixel and a wall pixel of the next row
    // land on one RGB pixel at one depth (the RGB camera's rows are 0.89 of the IR camera's).
    // The one whose footprint holds that pixel's centre decides, not a checkerboard of parity:
    // each RGB column's first and last shadow rows are the simulator's.
    let calib = Calibration::nyu_default();
    let (mut cols, mut exact) = (0, 0);
    for seed in 0..3 {
        let mut scene = Scene::box_before_wall(1.0, 3.0);
        if let umbra::synth::Shape::Box { centre, .. } = &mut scene.objects[1].shape {
            centre.y += 0.0007 * seed as f64; // a third of an IR row each time
        }
        let frame = render_frame(&scene, &calib, &SensorModel::ideal(), 60 + seed);
        let out = classify(&calib, &frame);
        let ends = |labels: &[u8], u: usize| {
            let rows: Vec<usize> = (0..HEIGHT)
                .filter(|&v| labels[v * WIDTH + u] == ATTACHED)
                .collect();
            Some((*rows.first()?, *rows.last()?))
        };
        for u in 0..WIDTH {
            let Some(truth) = ends(&frame.rgb_labels, u) else {
                continue;
            };
            cols += 1;
            exact += usize::from(ends(&out.rgb_labels, u) == Some(truth));
        }
    }
    assert!(cols > 3 * 15, "{cols} columns of shadow");
    // Measured: 51 of 51 (27 when parity alone broke the tie).
    assert!(
        100 * exact >= 95 * cols,
        "{exact} of {cols} columns end where the simulator's shadow does"
    );
}

#[test]
fn thin_rod_casts_detached_shadow_at_hand_computed_place() {
    let calib = Calibration::nyu_default();
    // A 2 cm rod at 1 m before a wall at 3 m: 2 cm < 7.5·(1 − 1/3) = 5 cm, so the shadow is
    // detached. Its image: rod columns [Fa, Fb] shifted left by w = f·b·(1 − 1/3) = 29.1 px.
    let frame = render_frame(
        &Scene::rod_before_wall(0.0, 1.0, 0.01, 3.0),
        &calib,
        &SensorModel::ideal(),
        2,
    );
    let out = classify(&calib, &frame);
    let w = calib.fb() * (1.0 - 1.0 / 3.0);
    let rod_left = calib.depth.cx - 0.01 * calib.depth.fx; // ≈ 307.2
    let rod_right = calib.depth.cx + 0.01 * calib.depth.fx; // ≈ 318.9
    for v in (20..HEIGHT - 20).step_by(7) {
        let row = &out.ir_labels[v * WIDTH..(v + 1) * WIDTH];
        let cols: Vec<usize> = (0..WIDTH).filter(|&u| row[u] == DETACHED).collect();
        assert!(!cols.is_empty(), "row {v}: no detached shadow");
        let (a, b) = (cols[0] as f64, *cols.last().unwrap() as f64);
        assert!(
            (a - (rod_left - w)).abs() <= 1.5 && (b - (rod_right - w)).abs() <= 1.5,
            "row {v}: detached {a}..{b}, hand {:.1}..{:.1}",
            rod_left - w,
            rod_right - w
        );
        assert!(
            row.iter().all(|&l| l != ATTACHED),
            "row {v}: a detached shadow called attached"
        );
    }
}

#[test]
fn detached_shadow_whose_left_end_hides_behind_a_nearer_rod() {
    // The 2 cm rod of the test above, moved to x = 0.1 m: its detached shadow spans columns
    // cx + fx·(0.1 ± 0.01) − 29.1 = 336.4..348.1. A 1 cm rod at 1.5 m stands in its left end: its
    // columns are cx + fx·(0.0644 ± 0.005)/1.5 = 336.1..340.0, so the hole right of it is the
    // shadow's visible rest, from 340 to 348.1, with the thin rod, not the wall, on its left.
    // Eq. (4) must measure from the wall's disparity, which Sb shows, and let the shadow run on
    // behind the thin rod.
    let calib = Calibration::nyu_default();
    let mut scene = Scene::rod_before_wall(0.1, 1.0, 0.01, 3.0);
    scene.push(
        "rod",
        umbra::synth::Shape::Cylinder {
            centre: umbra::synth::V3::new(0.0644, 0.0, 1.5),
            axis: umbra::synth::V3::new(0.0, 1.0, 0.0),
            radius: 0.005,
            half_len: 3.0,
        },
        umbra::synth::Material::matte([0.3, 0.5, 0.3]),
    );
    let frame = render_frame(&scene, &calib, &SensorModel::ideal(), 3);
    let out = classify(&calib, &frame);
    let shadow_right = calib.depth.cx + 0.11 * calib.depth.fx - calib.fb() * (1.0 - 1.0 / 3.0);
    let mut rows = 0;
    for v in (20..HEIGHT - 20).step_by(5) {
        let truth = &frame.ir_labels[v * WIDTH..(v + 1) * WIDTH];
        let row = &out.ir_labels[v * WIDTH..(v + 1) * WIDTH];
        // The visible rest of the shadow: the detached run right of the thin rod.
        let rest: Vec<usize> = (341..360).filter(|&u| truth[u] == DETACHED).collect();
        assert!(
            rest.len() >= 5,
            "row {v}: the scene has the shadow's rest ({rest:?})"
        );
        let got: Vec<usize> = (341..360).filter(|&u| row[u] == DETACHED).collect();
        assert_eq!(got, rest, "row {v}: detached right of the thin rod");
        assert!((*got.last().unwrap() as f64 - shadow_right).abs() <= 1.5);
        rows += 1;
    }
    assert!(rows > 50);
}

#[test]
fn detached_shadow_whose_left_end_hides_behind_a_nearer_objects_dropout() {
    // The 2 cm rod at x = 0.1 m, 1 m, before a wall at 3 m: its detached shadow spans columns
    // cx + fx·(0.1 ± 0.01) − 29.1 = 336.4..348.1. A box at 2 m stands left of it, matte over
    // columns 290..318 and black (no depth) over 318..342, rows 200..260: the black part hides
    // the shadow's left end, and the rest of the shadow, 342..348, makes one hole with it, the
    // matte part (nearer than the wall) on its left. Eq. (5) still places the shadow's right end;
    // where it starts showing, only the RGB camera tells: black over the box, wall over the
    // shadow. (The rows above and below the box show the whole shadow as a hole of its own.)
    let calib = Calibration::nyu_default();
    let (d, z) = (&calib.depth, 2.0);
    let x = |u: f64| (u - d.cx) * z / d.fx;
    let y = |v: f64| (v - d.cy) * z / d.fy;
    let (top, bottom) = (y(200.0), y(260.0));
    let mut scene = Scene::rod_before_wall(0.1, 1.0, 0.01, 3.0);
    for (name, from, to, material) in [
        (
            "box",
            290.0,
            318.0,
            umbra::synth::Material::matte([0.3, 0.45, 0.6]),
        ),
        ("box", 318.0, 342.0, umbra::synth::Material::black()),
    ] {
        push_box(
            &mut scene,
            name,
            [(x(from) + x(to)) / 2.0, (top + bottom) / 2.0, z + 0.02],
            [(x(to) - x(from)) / 2.0, (bottom - top) / 2.0, 0.02],
            material,
        );
    }
    let frame = render_frame(&scene, &calib, &SensorModel::ideal(), 6);
    let out = classify_rgb(&calib, &frame);
    let shadow_right = d.cx + 0.11 * d.fx - calib.fb() * (1.0 - 1.0 / 3.0);
    let mut rows = 0;
    for v in 204..256 {
        let truth = &frame.ir_labels[v * WIDTH..(v + 1) * WIDTH];
        let row = &out.ir_labels[v * WIDTH..(v + 1) * WIDTH];
        let rest: Vec<usize> = (320..360).filter(|&u| truth[u] == DETACHED).collect();
        assert!(
            rest.len() >= 5
                && truth[320..rest[0]].iter().all(|&l| l == OTHER)
                && frame.raw[v * WIDTH + 317] != NO_DEPTH,
            "row {v}: the scene has the shadow's rest {rest:?} after the black part"
        );
        // The shadow's visible rest, its right end where eq. (5) puts it.
        assert!(
            (rest[0] + 1..*rest.last().unwrap()).all(|u| row[u] == DETACHED),
            "row {v}: the shadow's rest {rest:?} is detached"
        );
        let last = (320..360).rev().find(|&u| row[u] == DETACHED).unwrap();
        assert!(
            (last as f64 - shadow_right).abs() <= 1.5,
            "row {v}: ends at {last}"
        );
        // Not the black part, but for the 2.4 px the RGB camera sees the box shifted by
        // (f·0.025·(1/2 − 1/3)) over the wall.
        assert!(
            row[320..338].iter().all(|&l| l != DETACHED),
            "row {v}: the black part is no shadow"
        );
        rows += 1;
    }
    assert!(rows >= 50);
}

#[test]
fn glossy_rods_detached_shadow_is_found_where_its_limb_returns_depth() {
    // A glossy rod, r = 2 cm at x = 0, 0.7 m, before a wall at 2.1 m: no depth on it, but a
    // matte strip along its right edge (r = 3 mm, centred on that edge) returns depth over its
    // last pixels, as a glossy rod's limb does. By hand the rod spans columns
    // cx ± fx·0.02/0.7 = 296.4..329.7 (the strip to 332.2) and its shadow lies
    // f·b·(1/0.7 − 1/2.1) = 41.6 px further left, 254.8..290.6: a detached shadow (a lit gap of
    // about 6 px), the rod's hole closed on the right by the strip, not by the wall. Before, the
    // pairing of shadow and depthless occluder wanted the wall there, and the shadow was OTHER
    // in every row (a fifth simulator's glossy rod, k14 s017).
    let calib = Calibration::nyu_default();
    let shift = calib.fb() * (1.0 / 0.7 - 1.0 / 2.1);
    assert!((41.0..42.0).contains(&shift), "shift {shift}");
    let mut scene = Scene::new("a glossy rod with a measured limb before a wall");
    let cylinder = |x: f64, radius: f64| vertical_rod(x, 0.7, radius);
    scene.push(
        "wall",
        wall(2.1),
        umbra::synth::Material::matte([0.8, 0.78, 0.7]),
    );
    let colour = [0.6, 0.55, 0.3];
    scene.push(
        "rod",
        cylinder(0.0, 0.02),
        umbra::synth::Material::glossy(colour),
    );
    scene.push(
        "rod",
        cylinder(0.02, 0.003),
        umbra::synth::Material::matte(colour),
    );
    let frame = render_frame(&scene, &calib, &SensorModel::kinect(), 3);
    let out = classify_rgb(&calib, &frame);
    let (mut truth, mut found, mut wrong) = (0, 0, 0);
    for v in 100..380 {
        let row = v * WIDTH;
        // The simulator's shadow lies where the hand computation puts it, and the limb shows.
        let shadow: Vec<usize> = (240..300)
            .filter(|&u| frame.ir_labels[row + u] == DETACHED)
            .collect();
        assert!(
            shadow.len() >= 30 && shadow[0].abs_diff(255) <= 3 && frame.raw[row + 330] != NO_DEPTH,
            "row {v}: shadow {:?}..{:?}",
            shadow.first(),
            shadow.last()
        );
        truth += shadow.len();
        found += shadow
            .iter()
            .filter(|&&u| out.ir_labels[row + u] == DETACHED)
            .count();
        wrong += (300..330)
            .filter(|&u| out.ir_labels[row + u] == DETACHED)
            .count();
    }
    let recall = found as f64 / truth as f64;
    assert!(recall >= 0.85, "detached recall {recall:.3}");
    assert_eq!(wrong, 0, "pixels of the rod itself read as its shadow");
}

/// A glossy rod, r = 1.9 cm at 0.6 m, its axis on column `centre`, before a pale wall at 3 m,
/// with whatever `extra` adds: by hand it spans ±fx·0.019/0.6 ≈ ±18.4 px and its detached
/// shadow lies f·b·(1/0.6 − 1/3) ≈ 58 px further left (a lit gap of about 21 px). Renders one
/// frame (`seed`) and scores the rows 40..440 where the simulator puts a shadow of at least
/// `min_len` px among `cols` starting within 4 px of the hand computation, and `row_ok` holds
/// (a speckle's hole may join the shadow's start: such rows are not scored). Asserts that at
/// least `min_rows` rows are scored (`what` they hold), that the detached recall over them is
/// at least 0.85, and that none of the rod's own pixels is read as anything but OTHER.
fn near_glossy_rod_shadow(
    centre: f64,
    extra: impl FnOnce(&mut Scene),
    seed: u64,
    (cols, min_len): (std::ops::Range<usize>, usize),
    row_ok: impl Fn(&SynthFrame, usize) -> bool,
    (min_rows, what): (usize, &str),
) {
    let calib = Calibration::nyu_default();
    let (cx, fx, fb) = (calib.depth.cx, calib.depth.fx, calib.fb());
    let (z, r) = (0.6, 0.019);
    let shift = fb * (1.0 / z - 1.0 / 3.0);
    assert!((55.0..65.0).contains(&shift), "shift {shift}");
    let half = fx * r / z;
    let left = centre - half;
    let mut scene = before_a_wall("a near glossy rod before a wall", 3.0, [0.8, 0.78, 0.7]);
    scene.push(
        "rod",
        vertical_rod((centre - cx) * z / fx, z, r),
        umbra::synth::Material::glossy([0.3, 0.45, 0.7]),
    );
    extra(&mut scene);
    let frame = render_frame(&scene, &calib, &SensorModel::kinect(), seed);
    let out = classify_rgb(&calib, &frame);
    let (mut rows, mut truth, mut found, mut wrong) = (0, 0, 0, 0);
    for v in 40..440 {
        let row = v * WIDTH;
        let shadow: Vec<usize> = cols
            .clone()
            .filter(|&u| frame.ir_labels[row + u] == DETACHED)
            .collect();
        if !(shadow.len() >= min_len
            && (shadow[0] as f64 - (left - shift)).abs() <= 4.0
            && row_ok(&frame, v))
        {
            continue;
        }
        rows += 1;
        truth += shadow.len();
        found += shadow
            .iter()
            .filter(|&&u| out.ir_labels[row + u] == DETACHED)
            .count();
        wrong += (left as usize + 6..((centre + half) as usize).min(WIDTH))
            .filter(|&u| frame.ir_labels[row + u] == OTHER && out.ir_labels[row + u] != OTHER)
            .count();
    }
    assert!(rows >= min_rows, "{rows} of 400 rows {what}");
    let recall = found as f64 / truth.max(1) as f64;
    assert!(recall >= 0.85, "detached recall {recall:.3}");
    assert_eq!(wrong, 0, "pixels of the rod itself read as its shadow");
}

#[test]
fn glossy_rods_detached_shadow_is_found_with_the_rod_by_the_right_border() {
    // The near glossy rod with its right edge at column 635.5, 4 px from the image's right
    // border (the sensor widens its hole by about 2 px). Most rows are left to the colour
    // split's pairing of a depthless occluder and its shadow, which wanted four columns of wall
    // right of the rod's hole (the colour it reads there is the shadow's, not the occluder's);
    // the sensor's widening leaves two. The shadow was OTHER in three rows of four (detached
    // recall 0.245; 1.000 now) and the rod itself read as the shadow in some (a fresh suite's
    // near glossy rod: 10 000 px a frame).
    let calib = Calibration::nyu_default();
    let half = calib.depth.fx * 0.019 / 0.6;
    // One to three columns of wall show right of the rod.
    let wall_right = |frame: &SynthFrame, v: usize| {
        let n = frame.raw[v * WIDTH..(v + 1) * WIDTH]
            .iter()
            .rev()
            .take_while(|&&r| r != NO_DEPTH)
            .count();
        (1..4).contains(&n)
    };
    near_glossy_rod_shadow(
        635.5 - half,
        |_| {},
        5,
        (500..620, 20),
        wall_right,
        (360, "have the shadow and the wall where they belong"),
    );
}

#[test]
fn glossy_rods_detached_shadow_is_found_where_a_rod_behind_it_shadows_its_edge() {
    // The near glossy rod with its axis on column 450: its shadow by hand 373..410. A thin
    // matte rod (r = 4 mm at 1.27 m) stands behind it, hidden from the IR camera, where its own
    // shadow, f·b·(1/1.27 − 1/3) ≈ 19.7 px to its left, falls on the wall at the glossy rod's
    // left edge: the glossy rod's hole is the thin rod's shadow and itself, a few pixels wider
    // than the glossy rod's shadow, wider than the widening allows: the glossy rod's shadow
    // stayed OTHER in four rows of five (detached recall 0.204; 1.000 now), and 3 944 px of the
    // rod were read as a shadow (a fresh suite's scene: 8 600 px a frame).
    let calib = Calibration::nyu_default();
    let (cx, fx, fb) = (calib.depth.cx, calib.depth.fx, calib.fb());
    let left = 450.0 - fx * 0.019 / 0.6;
    // The thin rod's shadow ends 2 px inside the glossy rod's left edge.
    let thin_u = left + fb * (1.0 / 1.27 - 1.0 / 3.0) - 1.0;
    let thin_rod = |scene: &mut Scene| {
        scene.push(
            "thin rod",
            vertical_rod((thin_u - cx) * 1.27 / fx, 1.27, 0.004),
            umbra::synth::Material::matte([0.9, 0.8, 0.3]),
        );
    };
    // The thin rod's shadow at the glossy rod's edge, in the same hole.
    let joined = |frame: &SynthFrame, v: usize| {
        let row = v * WIDTH;
        (420..436).any(|u| frame.ir_labels[row + u] == DETACHED)
            && (428..436).all(|u| frame.raw[row + u] == NO_DEPTH)
    };
    near_glossy_rod_shadow(
        450.0,
        thin_rod,
        11,
        (340..420, 30),
        joined,
        (250, "hold both shadows where they belong"),
    );
}

#[test]
fn thin_rod_in_a_nearer_boards_shadow_keeps_its_alignment_strip() {
    // A wall at 3 m; a board 1 cm thick at 1 m whose left edge is at IR column 400 (x = 0.149 m),
    // rows 151..325; its attached shadow on the wall spans 400 − f·b·(1 − 1/3) = 370.9 to 400. A
    // 4 px rod at 1.5 m, columns 374..377 (x = 0.1608 m, r = 5.15 mm), stands in that shadow,
    // lit: the board's shadow on the rod's plane would start only at 400 − 14.6 = 385.4. So the
    // hole right of the rod, 378..398, is the board's shadow on the wall, and the RGB camera,
    // 2.5 cm to the right, sees f_rgb·0.025·(1/1.5 − 1/3) = 4.3 px of wall right of the rod that
    // the IR camera cannot: an alignment strip, which the simulator's visibility test labels.
    let calib = Calibration::nyu_default();
    let mut scene = Scene::rod_before_wall(0.1608, 1.5, 0.00515, 3.0);
    scene.push(
        "board",
        umbra::synth::Shape::Box {
            centre: umbra::synth::V3::new(0.149 + 0.05, 0.0, 1.005),
            half: umbra::synth::V3::new(0.05, 0.15, 0.005),
            yaw: 0.0,
        },
        umbra::synth::Material::matte([0.7, 0.2, 0.15]),
    );
    let frame = render_frame(&scene, &calib, &SensorModel::ideal(), 5);
    let out = classify(&calib, &frame);
    let (mut truth, mut hit) = (0, 0);
    for v in 200..300 {
        let ir = &frame.ir_labels[v * WIDTH..(v + 1) * WIDTH];
        assert!(
            ir[378..399].iter().all(|&l| l == ATTACHED),
            "row {v}: the scene has the board's shadow right of the rod"
        );
        let (t, p) = (&frame.rgb_labels[v * WIDTH..], &out.rgb_labels[v * WIDTH..]);
        for u in 330..400 {
            if t[u] == ALIGNMENT {
                truth += 1;
                hit += usize::from(p[u] == ALIGNMENT);
            }
        }
    }
    assert!(truth >= 300, "the scene has the strip: {truth} px");
    assert!(
        hit * 4 >= truth * 3,
        "{hit} of {truth} alignment pixels found"
    );
}

#[test]
fn detached_shadow_running_off_the_left_border() {
    // The 2 cm rod of the test above at x = −0.4857 m: columns cx + fx·(−0.4857 ± 0.01) =
    // 24.2..35.8, its detached shadow 29.1 px further left, −4.9..6.7. Only its right part shows,
    // from the border to 6.7, with the wall (Sb) right of it and no Sa at all.
    let calib = Calibration::nyu_default();
    let frame = render_frame(
        &Scene::rod_before_wall(-0.4857, 1.0, 0.01, 3.0),
        &calib,
        &SensorModel::ideal(),
        4,
    );
    let out = classify(&calib, &frame);
    let w = calib.fb() * (1.0 - 1.0 / 3.0);
    let shadow_right = calib.depth.cx + calib.depth.fx * (-0.4857 + 0.01) - w;
    for v in (20..HEIGHT - 20).step_by(7) {
        let truth = &frame.ir_labels[v * WIDTH..v * WIDTH + 20];
        let row = &out.ir_labels[v * WIDTH..v * WIDTH + 20];
        let cols: Vec<usize> = (0..20).filter(|&u| truth[u] == DETACHED).collect();
        assert!(
            cols.len() >= 5 && cols[0] == 0,
            "row {v}: the scene {cols:?}"
        );
        assert_eq!(
            (0..20).filter(|&u| row[u] == DETACHED).collect::<Vec<_>>(),
            cols,
            "row {v}: detached at the border"
        );
        assert!((*cols.last().unwrap() as f64 - shadow_right).abs() <= 1.5);
    }
}

/// The 2 cm rod at 1 m before a wall at 3 m, at x = 0.575 m: columns cx + fx·(0.575 ± 0.01) =
/// 642.2..653.9, past the IR image's right border, while its detached shadow, 29.1 px further
/// left, spans 613.1..624.8 with lit wall on both sides. Returns the frame and its labels with and
/// without the RGB image.
fn rod_off_the_right_border(scene: &Scene) -> (SynthFrame, Classified, Classified) {
    let calib = Calibration::nyu_default();
    let frame = render_frame(scene, &calib, &SensorModel::ideal(), 5);
    let (depth_only, out) = (classify(&calib, &frame), classify_rgb(&calib, &frame));
    (frame, depth_only, out)
}

/// Two frames of `scene` through the Kinect sensor model (seeds `seed` and `seed + 1`),
/// classified with their RGB images and scored against their labels in the RGB view (`rgb`) or
/// the IR view.
fn kinect_confusion(scene: &Scene, calib: &Calibration, seed: u64, rgb: bool) -> Confusion {
    let mut c = Confusion::default();
    for seed in seed..seed + 2 {
        let frame = render_frame(scene, calib, &SensorModel::kinect(), seed);
        let out = classify_rgb(calib, &frame);
        if rgb {
            c.add(&frame.rgb_labels, &out.rgb_labels);
        } else {
            c.add(&frame.ir_labels, &out.ir_labels);
        }
    }
    c
}

/// Tilts the rod of a [`Scene::rod_before_wall`] scene by `degrees` in the image plane.
fn tilt_rod(scene: &mut Scene, degrees: f64) {
    let tilt = degrees.to_radians();
    if let umbra::synth::Shape::Cylinder { axis, .. } = &mut scene.objects[1].shape {
        *axis = nalgebra::Vector3::new(tilt.sin(), tilt.cos(), 0.0);
    }
}

#[test]
fn detached_shadow_of_a_rod_beyond_the_right_border_is_told_by_colour() {
    let calib = Calibration::nyu_default();
    let (frame, depth_only, out) =
        rod_off_the_right_border(&Scene::rod_before_wall(0.575, 1.0, 0.01, 3.0));
    let w = calib.fb() * (1.0 - 1.0 / 3.0);
    let (left, right) = (
        calib.depth.cx + calib.depth.fx * 0.565 - w,
        calib.depth.cx + calib.depth.fx * 0.585 - w,
    );
    let mut rows = 0;
    for v in (20..HEIGHT - 20).step_by(7) {
        let cols = |labels: &[u8]| -> Vec<usize> {
            (560..WIDTH)
                .filter(|&u| labels[v * WIDTH + u] == DETACHED)
                .collect()
        };
        let truth = cols(&frame.ir_labels);
        assert!(
            truth.len() >= 10 && (truth[0] as f64 - left).abs() <= 1.5,
            "row {v}: the scene {truth:?}"
        );
        assert!((*truth.last().unwrap() as f64 - right).abs() <= 1.5);
        // Depth alone sees a hole with wall on both sides and no occluder: OTHER.
        assert!(
            cols(&depth_only.ir_labels).is_empty(),
            "row {v}: depth alone"
        );
        assert_eq!(cols(&out.ir_labels), truth, "row {v}: detached with colour");
        rows += 1;
    }
    assert!(rows > 50);
    // Carried over into the RGB view.
    let mut c = Confusion::default();
    c.add(&frame.rgb_labels, &out.rgb_labels);
    at_least(&c, Some(DETACHED), 0.95, "RGB detached beyond the border");
}

#[test]
fn slanted_detached_shadow_of_a_rod_beyond_the_right_border_is_told_by_colour() {
    // The rod above, tilted 20° in the image plane and through the Kinect sensor model: its
    // shadow moves tan 20° · 1 m / 3 m · 3 = 0.36 px a row (about 1.5 px over four rows) while
    // the sensor's widening moves each end by up to 3 px more. Rows four away from a row then
    // hold its hole a few pixels off; the rows between show it moving one way. Where the rod
    // comes into view at the border, what shows of it casts less than its shadow. Detached F1
    // 0.870 before either was allowed for, 0.947 after (floor 0.93).
    let calib = Calibration::nyu_default();
    let mut scene = Scene::rod_before_wall(0.62, 1.0, 0.01, 3.0);
    tilt_rod(&mut scene, 20.0);
    let c = kinect_confusion(&scene, &calib, 30, false);
    at_least(
        &c,
        Some(DETACHED),
        0.93,
        "IR detached of a slanted rod beyond the border",
    );
}

#[test]
fn detached_shadow_of_a_rod_beyond_the_right_border_on_a_banded_wall_is_told_by_colour() {
    // A wall at 3.5 m in olive bands 10 cm wide (16.6 px), light and a third darker, and a grey
    // rod (r = 1.6 cm, 18.6 px) at 1 m whose left edge stands just past the border (column 645):
    // its shadow, shifted f·b·(1/1 − 1/3.5) ≈ 31.2 px, covers columns 614–632, the lit wall
    // after it runs to the border. A band's edge lies at column 619: the wall beside the hole
    // is light, most of the shadow dark. The RGB camera sees the rod a third of the shift left
    // of where the IR camera would, over the shadow's right end, so the shadow's part must
    // show the wall; held to the light band beside the hole it did not, though the wall left
    // of the hole shows both bands. Measured (seeds 40–41): detached F1 0.014 → 0.788 (the
    // rest lost where the stretch further left crosses a band's edge).
    let calib = Calibration::nyu_default();
    let (light, dark) = ([0.45, 0.38, 0.22], [0.30, 0.25, 0.14]);
    let (width, z) = (0.1, 3.5);
    let edge = (619.0 - calib.depth.cx) / calib.depth.fx * z;
    let mut scene = Scene::new("rod beyond the right border before a banded wall");
    push_bands(&mut scene, (edge, width, z), -40..10, |k| {
        if k % 2 == 0 {
            dark
        } else {
            light
        }
    });
    let radius = 0.016;
    let left = (645.0 - calib.depth.cx) / calib.depth.fx;
    push_grey_rod(&mut scene, left + radius, 1.0, radius);
    let c = kinect_confusion(&scene, &calib, 40, false);
    at_least(
        &c,
        Some(DETACHED),
        0.75,
        "IR detached of a rod beyond the border on a banded wall",
    );
}

#[test]
fn detached_shadow_of_a_rod_nearer_than_the_range_at_the_right_border_is_told_by_colour() {
    // A grey rod (r = 1.5 cm) 0.4 m away, nearer than the sensor's range (0.5 m), its left edge
    // at column 625: the IR camera sees 15 px of it, as a hole running into the border. Its
    // detached shadow on a wall at 2.5 m starts f·b·(1/0.4 − 1/2.5) ≈ 91 px left of that edge,
    // further than the shift of any measurable occluder (at 0.5 m, 70 px), and covers what the
    // projector sees of the rod, f·2r/0.4 ≈ 44 px. Depth alone reads a hole on lit wall: OTHER.
    let calib = Calibration::nyu_default();
    let (z, r, z_wall) = (0.4, 0.015, 2.5);
    let x = (625.0 - calib.depth.cx) / calib.depth.fx * z + r;
    let mut scene = before_a_wall(
        "rod nearer than the range at the right border",
        z_wall,
        [0.8, 0.78, 0.7],
    );
    push_grey_rod(&mut scene, x, z, r);
    let (frame, depth_only, out) = rod_off_the_right_border(&scene);
    let w = calib.fb() * (1.0 / z - 1.0 / z_wall);
    let (left, right) = (
        calib.depth.cx + calib.depth.fx * (x - r) / z - w,
        calib.depth.cx + calib.depth.fx * (x + r) / z - w,
    );
    let mut rows = 0;
    for v in (20..HEIGHT - 20).step_by(7) {
        let cols = |labels: &[u8]| -> Vec<usize> {
            (500..WIDTH)
                .filter(|&u| labels[v * WIDTH + u] == DETACHED)
                .collect()
        };
        let truth = cols(&frame.ir_labels);
        assert!(
            truth.len() >= 30
                && (truth[0] as f64 - left).abs() <= 2.0
                && (*truth.last().unwrap() as f64 - right).abs() <= 2.0,
            "row {v}: the scene {truth:?}, by hand {left:.1}..{right:.1}"
        );
        assert!(
            cols(&depth_only.ir_labels).is_empty(),
            "row {v}: depth alone"
        );
        assert_eq!(cols(&out.ir_labels), truth, "row {v}: detached with colour");
        rows += 1;
    }
    assert!(rows > 50);
    let mut c = Confusion::default();
    c.add(&frame.rgb_labels, &out.rgb_labels);
    at_least(
        &c,
        Some(DETACHED),
        0.95,
        "RGB detached of a rod nearer than the range",
    );
}

/// A matte blue panel 1 cm thick, its front face 1 m away, from x = `x_edge` to 1 m past it and
/// 0.6 m tall (rows 65 to 415 or so), before a wall at 3 m.
fn panel_beyond_the_right_border(x_edge: f64) -> Scene {
    tall_panel_beyond_the_right_border(x_edge, 0.3)
}

/// By hand, for the panel from x = 0.58 m: the IR column of its left face's far edge and the
/// one its shadow on the wall starts at, f·b·(1/1.01 − 1/3) px left of it.
fn panel_shadow_by_hand(calib: &Calibration) -> (f64, f64) {
    let edge = calib.depth.cx + calib.depth.fx * 0.58 / 1.01;
    (edge, edge - calib.fb() * (1.0 / 1.01 - 1.0 / 3.0))
}

/// [`panel_beyond_the_right_border`], `half_height` metres above and below the camera's axis.
fn tall_panel_beyond_the_right_border(x_edge: f64, half_height: f64) -> Scene {
    let mut scene = before_a_pale_wall("panel beyond the right border");
    push_box(
        &mut scene,
        "panel",
        [x_edge + 0.5, 0.0, 1.005],
        [0.5, half_height, 0.005],
        umbra::synth::Material::matte([0.2, 0.35, 0.8]),
    );
    scene
}

#[test]
fn attached_shadow_of_a_panel_beyond_the_right_border_is_told_by_colour() {
    // The panel's left face, at x = 0.58 m, 1.00 to 1.01 m away, lies at columns cx + fx·0.58/z,
    // past the IR image's border; the projector sees it too, so the shadow on the wall at 3 m
    // is cast by its far edge, f·b·(1/1.01 − 1/3) px wide, ending where the camera sees that
    // edge: it starts inside the image and runs into the border, with nothing for eq. (3) on
    // its right. The RGB camera, a third of the way to the projector, sees the panel's edge a
    // third of that width left of where the shadow ends, over the wall: inside its image.
    let (edge, start) = panel_shadow_by_hand(&Calibration::nyu_default());
    assert!(
        edge > WIDTH as f64 && start < WIDTH as f64 - 10.0,
        "{start}..{edge}"
    );
    let scene = panel_beyond_the_right_border(0.58);
    told_by_colour_alone(
        &scene,
        |v, cols| {
            assert!(
                cols.len() > 10
                    && cols.last() == Some(&(WIDTH - 1))
                    && (cols[0] as f64 - start).abs() <= 1.0,
                "row {v}: the scene's shadow {cols:?}, by hand from {start:.1}"
            )
        },
        0.95,
        "IR attached of a panel beyond the right border",
    );
}

#[test]
fn attached_shadow_of_a_panel_beyond_the_right_border_in_every_row_is_no_dead_band() {
    // The same panel, taller than the view: its shadow runs into the border in every row, about
    // 14 px wide, as a real sensor's dead band does (8 px or more in every row), and frames
    // with the band are left alone there. The band is the sensor's own width wherever the
    // scene is measured up to it (the real frame: 44 % of its rows within a pixel of 8 px); a
    // shadow is its occluder's (attached F1 0.00 when every such frame was taken for one).
    let (_, start) = panel_shadow_by_hand(&Calibration::nyu_default());
    told_by_colour_alone(
        &tall_panel_beyond_the_right_border(0.58, 1.5),
        |v, cols| {
            assert!(
                cols.len() > 10 && (cols[0] as f64 - start).abs() <= 1.0,
                "row {v}: the scene's shadow {cols:?}, by hand from {start:.1}"
            )
        },
        0.95,
        "IR attached of a tall panel beyond the right border",
    );
}

#[test]
fn two_black_rods_side_by_side_cast_no_detached_shadow_on_each_other() {
    // Two black rods of radius 2 cm at 1.8 m, 7.2 cm apart, before a pale wall at 2 m. Each
    // casts an attached shadow of only f·b·(1/1.8 − 1/2) = 2.4 px, so each row holds two holes
    // (2.4 px of shadow and the rod's 13.0 px, 582.62·0.04/1.8), the wall lit between them for
    // 582.62·(0.072 − 0.04)/1.8 − 2.4 = 8.0 px. Depth alone fits the pair as a detached shadow
    // 15 px wide, a lit gap of 8 and a depthless rod of 13 that casts it (eqs. 4–5: 23 px of
    // shift, nearer than the rods by far). The RGB camera sees the first hole black, like
    // neither the wall left of it nor the gap, but like the second hole: no detached shadow.
    // Measured: 9 566 detached pixels in 2 frames before, 2 after.
    let calib = Calibration::nyu_default();
    let mut scene = before_a_pale_wall("two black rods side by side");
    scene.objects[0].shape = wall(2.0);
    for x in [0.0, 0.072] {
        push_grey_rod(&mut scene, x, 1.8, 0.02);
        scene.objects.last_mut().unwrap().material = umbra::synth::Material::black();
    }
    let mut detached = 0;
    for seed in 60..62 {
        let frame = render_frame(&scene, &calib, &SensorModel::kinect(), seed);
        assert_eq!(
            count_labelled(&frame.ir_labels, &(0..PIXELS).collect::<Vec<_>>(), DETACHED),
            0
        );
        let out = classify_rgb(&calib, &frame);
        detached += out.ir_labels.iter().filter(|&&l| l == DETACHED).count();
    }
    assert!(detached < 100, "{detached} detached pixels");
}

/// A red box 0.5 m tall whose front face, 1 m away, runs from x = 0.1 m to `x_right`, before a
/// pale wall at 3 m: the RGB camera sees the wall past its right edge.
fn box_off_the_right_border(x_right: f64) -> Scene {
    let mut scene = before_a_pale_wall("red box off the right border");
    push_box(
        &mut scene,
        "box",
        [(0.1 + x_right) / 2.0, 0.0, 1.1],
        [(x_right - 0.1) / 2.0, 0.25, 0.1],
        umbra::synth::Material::matte([0.7, 0.2, 0.15]),
    );
    scene
}

/// By hand, RGB columns `[from, to)` (pixel centres) of the wall that the box of
/// [`box_off_the_right_border`] hides from the IR camera and the RGB camera sees, when the IR
/// camera's view ends at IR column `edge` (639.5, or 631.5 before a dead band): from the box's
/// edge at 1 m, `f_rgb·(x_right − 0.025)`, to the view's end on the wall at 3 m. Right of it the
/// RGB camera sees wall outside the IR camera's view (OTHER).
fn border_strip_by_hand(calib: &Calibration, x_right: f64, edge: f64) -> (usize, usize) {
    let (cx, fx) = (calib.rgb.cx, calib.rgb.fx);
    let from = cx + fx * (x_right - 0.025);
    let x_wall = (edge - calib.depth.cx) / calib.depth.fx * 3.0;
    let to = cx + fx * (x_wall - 0.025) / 3.0;
    (from.ceil() as usize, to.ceil() as usize)
}

/// Over RGB rows 150–350 (the box's middle) of `scene` on the Kinect sensor model (seeds 50 and
/// 51), with the IR view's last `band` columns blanked as a dead band: the alignment pixels
/// found in the hand-computed strip `[from, to)` and those found right of the box's edge outside
/// it (a pixel of slack either side), with the strip's size.
fn border_strip_found(scene: &Scene, band: usize, (from, to): (usize, usize)) -> [usize; 3] {
    let calib = Calibration::nyu_default();
    let mut found = [0; 3];
    for seed in 50..52 {
        let mut frame = render_frame(scene, &calib, &SensorModel::kinect(), seed);
        for row in frame.raw.chunks_exact_mut(WIDTH) {
            row[WIDTH - band..].fill(NO_DEPTH);
        }
        let out = classify_rgb(&calib, &frame);
        for v in 150..350 {
            let row = &out.rgb_labels[v * WIDTH..(v + 1) * WIDTH];
            for (u, &l) in row.iter().enumerate().skip(from - 5) {
                let strip = (from..to).contains(&u);
                found[0] += usize::from(strip && l == ALIGNMENT);
                found[1] += usize::from(!(from - 1..=to).contains(&u) && l == ALIGNMENT);
                found[2] += usize::from(strip);
            }
        }
    }
    found
}

#[test]
fn box_running_off_the_right_border_leaves_its_alignment_strip_up_to_the_ir_view() {
    // The box's edge at x = 0.565 m lies at IR column 313.04 + 582.62·0.565 = 642.2, just past
    // the border, and at RGB column 325.58 + 518.86·0.540 = 605.8. The IR camera's view ends at
    // column 639.5, on the wall 3·(639.5 − 313.04)/582.62 = 1.681 m to the side, which the RGB
    // camera sees at 325.58 + 518.86·(1.681 − 0.025)/3 = 612.0. Between, 6 columns of wall the
    // box hides from the IR camera: an alignment shadow, with no farther IR pixel after the box
    // to open it. Measured: 0 of 2 400 found before (all OTHER), 2 400 after, none outside.
    let calib = Calibration::nyu_default();
    let strip = border_strip_by_hand(&calib, 0.565, 639.5);
    assert_eq!(strip, (606, 612));
    let [hit, outside, truth] = border_strip_found(&box_off_the_right_border(0.565), 0, strip);
    assert!(
        10 * hit >= 9 * truth,
        "{hit} of {truth} strip pixels ALIGNMENT"
    );
    assert_eq!(outside, 0, "alignment pixels outside the strip");
}

#[test]
fn box_running_into_a_dead_band_leaves_its_alignment_strip_up_to_the_band() {
    // A real sensor measures nothing in its last 8 columns. The box's edge at x = 0.551 m lies
    // at IR column 634.1, inside the band, and at RGB column 598.7; the IR camera's measured view
    // ends at column 631.5, on the wall at x = 1.640 m, RGB column 604.9. Between, the wall the
    // box hides: 6 columns of alignment shadow (the wall the band covers past it is OTHER).
    // Measured: 0 of 2 400 before, 2 240 after, none outside.
    let calib = Calibration::nyu_default();
    let strip = border_strip_by_hand(&calib, 0.551, 631.5);
    assert_eq!(strip, (599, 605));
    let [hit, outside, truth] = border_strip_found(&box_off_the_right_border(0.551), 8, strip);
    assert!(
        10 * hit >= 9 * truth,
        "{hit} of {truth} strip pixels ALIGNMENT"
    );
    assert_eq!(outside, 0, "alignment pixels outside the strip");
}

/// Asserts of `scene`, whose attached shadow depth alone cannot find: the ideal sensor's shadow
/// columns in every 40th row of its middle (`by_hand(v, columns)` checks them against the
/// hand-computed geometry), depth alone recalling under 5 % of it on the Kinect sensor model,
/// and the RGB image bringing its IR attached F1 to `f1` (`what` names it).
fn told_by_colour_alone(scene: &Scene, by_hand: impl Fn(usize, &[usize]), f1: f64, what: &str) {
    let calib = Calibration::nyu_default();
    // The simulator agrees (no widening on the ideal sensor).
    let ideal = render_frame(scene, &calib, &SensorModel::ideal(), 40);
    for v in (100..HEIGHT - 100).step_by(40) {
        let row = &ideal.ir_labels[v * WIDTH..(v + 1) * WIDTH];
        let cols: Vec<usize> = (0..WIDTH).filter(|&u| row[u] == ATTACHED).collect();
        by_hand(v, &cols);
    }
    colour_alone_finds_its_shadow(scene, f1, what);
}

/// `scene` on the Kinect sensor model (seeds 40 and 41): depth alone recalls under 5 % of its
/// attached shadow, and the RGB image brings its IR attached F1 to `f1` (`what` names it).
fn colour_alone_finds_its_shadow(scene: &Scene, f1: f64, what: &str) {
    let (depth_only, with_rgb) = with_and_without_colour(scene, 40..42, false, |_| {});
    let alone = depth_only.class(ATTACHED);
    assert!(
        alone.recall.unwrap_or(0.0) < 0.05,
        "depth alone has no occluder or no background beside it: {alone:?}"
    );
    at_least(&with_rgb, Some(ATTACHED), f1, what);
}

/// Checks a row's attached columns against a shadow from the left border to the occluder's
/// front face at column `u_left` (within a pixel), as the left-border tests compute it by hand.
fn shadow_from_the_border_to(u_left: f64) -> impl Fn(usize, &[usize]) {
    move |v, cols| {
        assert!(
            cols.first() == Some(&0) && (cols.len() as f64 - u_left).abs() <= 1.0,
            "row {v}: the scene's shadow {cols:?}, by hand to {u_left}"
        )
    }
}

/// A red panel 1 m wide and 0.8 m tall at 2 m, from 0.1 m behind the right edge of an occluder
/// whose front face, 1 m away, ends at x = `x_right`: the surface right of its hole is then
/// another one than the wall at the border.
fn push_red_panel_behind(scene: &mut Scene, x_right: f64) {
    push_box(
        scene,
        "panel",
        [2.0 * x_right - 0.1 + 0.5, 0.0, 2.025],
        [0.5, 0.4, 0.025],
        umbra::synth::Material::matte([0.7, 0.2, 0.15]),
    );
}

/// A black box 0.3 m wide and 0.6 m tall whose front face, 1 m away, starts at IR column
/// `u_left`, before a wall at 3 m.
fn black_box_at_the_left_border(u_left: f64) -> Scene {
    let calib = Calibration::nyu_default();
    let x_left = (u_left - calib.depth.cx) / calib.depth.fx;
    let mut scene = before_a_pale_wall("black box at the left border");
    push_black_box(
        &mut scene,
        "box",
        [x_left + 0.15, 0.0, 1.05],
        [0.15, 0.3, 0.05],
    );
    scene
}

#[test]
fn attached_shadow_of_a_black_box_running_off_the_left_border_is_told_by_colour() {
    // The box's front face starts at column 20; the projector, right of the camera, sees the
    // same corner, so the shadow on the wall is f·b·(1/1 − 1/3) = 29.1 px wide by hand and
    // starts 9 px past the left border: box and shadow are one hole from column 0, with no
    // background on its left for eq. (3) or the colour split. The RGB camera sees the box's
    // edges a third of the shift (9.7 px) left of the IR camera's: the wall over the shadow's
    // first 10 columns, the box, then a strip of wall right of it, which gives the shift.
    // Measured: IR attached F1 0.000 → 0.942 (precision 1.000, recall 0.890).
    let calib = Calibration::nyu_default();
    let u_left = 20.0;
    let start = u_left - calib.fb() * (1.0 / 1.0 - 1.0 / 3.0);
    assert!(start < -5.0, "{start}");
    let scene = black_box_at_the_left_border(u_left);
    told_by_colour_alone(
        &scene,
        shadow_from_the_border_to(u_left),
        0.9,
        "IR attached of a black box at the left border",
    );
}

#[test]
fn attached_shadow_of_a_black_box_at_the_left_border_before_another_surface_is_read_past_it() {
    // The black box of the test above, its front face from column 26, and right of it, from
    // behind its right edge, a red panel at 2 m: the hole ends at the panel, whose colour the
    // RGB camera does not see at the border (the pale wall is there), so the strip right of the
    // box tells nothing of the shadow. The shadow is f·b·(1/1 − 1/3) = 29.1 px wide by hand and
    // starts 3 px past the border. The RGB camera sees past the border, the wall running on to
    // where it sees the box, 26 − 29.1/3 = 16.3 px; the least shift that starts the shadow
    // outside the image, 16.3 / (1 − 1/3) = 24.5 px, ends it there (the wall's depth measured
    // above the box). Measured: IR attached F1 0.447 → 0.934 (recall 0.29 → 0.88, precision
    // 1.000; above and below the panel the wall beside the box told the shift already).
    let calib = Calibration::nyu_default();
    let u_left = 26.0;
    let shift = calib.fb() * (1.0 / 1.0 - 1.0 / 3.0);
    assert!(
        (u_left - shift) < -2.0 && (u_left - shift) > -4.0,
        "{shift}"
    );
    let mut scene = black_box_at_the_left_border(u_left);
    push_red_panel_behind(&mut scene, (u_left - calib.depth.cx) / calib.depth.fx + 0.3);
    told_by_colour_alone(
        &scene,
        shadow_from_the_border_to(u_left),
        0.9,
        "IR attached of a black box at the left border before a panel",
    );
}

#[test]
fn black_box_at_the_left_border_before_a_wall_in_bands_is_read_past_it() {
    // The box and panel of the test above (the box 0.38 m tall, so the panel stands right of it
    // in every row) before a wall in level bands 2.5 cm tall (5 rows at 3 m), pale and blue by
    // turns: the wall past the border shows a row's band, and the wall measured above the box's
    // top, one spot of it, the other band in half the rows. Spots 3 rows apart up the column
    // find the row's band in every row. Measured: IR attached F1 0.869 → 0.931 (recall 0.768 →
    // 0.871; rows between two readings took theirs before).
    let calib = Calibration::nyu_default();
    let u_left = 26.0;
    let mut scene = Scene::new("black box at the left border before a wall in bands");
    for k in -48..48 {
        let colour = if k % 2 == 0 {
            [0.8, 0.78, 0.7]
        } else {
            [0.45, 0.6, 0.75]
        };
        push_box(
            &mut scene,
            "wall",
            [0.0, 0.025 * (f64::from(k) + 0.5), 3.05],
            [4.0, 0.0125, 0.05],
            umbra::synth::Material::matte(colour),
        );
    }
    let x_left = (u_left - calib.depth.cx) / calib.depth.fx;
    push_black_box(
        &mut scene,
        "box",
        [x_left + 0.15, 0.0, 1.05],
        [0.15, 0.19, 0.05],
    );
    push_red_panel_behind(&mut scene, x_left + 0.3);
    // The simulator agrees: the shadow from the border to the box in the box's rows.
    let ideal = render_frame(&scene, &calib, &SensorModel::ideal(), 40);
    let by_hand = shadow_from_the_border_to(u_left);
    for v in (150..340).step_by(30) {
        let row = &ideal.ir_labels[v * WIDTH..(v + 1) * WIDTH];
        let cols: Vec<usize> = (0..WIDTH).filter(|&u| row[u] == ATTACHED).collect();
        by_hand(v, &cols);
    }
    colour_alone_finds_its_shadow(
        &scene,
        0.9,
        "IR attached of a black box at the left border before a wall in bands",
    );
}

#[test]
fn black_box_before_a_banded_wall_and_a_farther_one_keeps_its_attached_shadow() {
    // A wall at 2.5 m papered in bands 4 px wide, cream and blue by turns, up to IR column 300,
    // a pale wall at 3.5 m past its edge, and a black box whose front face, 1 m away, spans
    // columns 220–340: its hole runs from its shadow on the banded wall to the farther wall.
    // The shadow is f·b·(1/1 − 1/2.5) = 26.2 px wide by hand. The bands differ by more than the
    // plain colour step, so the shadow's columns count as wall only within the banded wall's
    // own spread; a farther surface right of the hole once left the near side's texture
    // unread (the near side might be an object whose shading is no texture). The banded side
    // is one plane, so its texture is read. Measured (seeds 40–41): IR attached F1 0.002 →
    // 0.983.
    let calib = Calibration::nyu_default();
    let mut scene = Scene::new("black box before a banded wall and a farther one");
    scene.push(
        "far wall",
        wall(3.5),
        umbra::synth::Material::matte([0.8, 0.8, 0.8]),
    );
    push_cream_and_blue_bands(&mut scene, &calib, (300.0, 4.0, 2.5), -90..0, true);
    push_black_box_over(&mut scene, (220.0, 340.0), 1.0, 0.19);
    assert_ideal_shadow_width(&scene, calib.fb() * (1.0 - 1.0 / 2.5));
    colour_alone_finds_its_shadow(
        &scene,
        0.95,
        "IR attached of a black box before a banded wall and a farther one",
    );
}

#[test]
fn black_box_whose_shadow_starts_at_a_band_edge_is_read_against_the_wall_right_of_it() {
    // A wall at 3 m in bands 140 px wide, cream and blue by turns, a cream one ending at IR
    // column 170, and a black box whose front face, 1 m away, spans columns 200–300: its
    // shadow, f·b·(1/1 − 1/3) = 29.1 px by hand, starts on the blue band's first columns, as
    // does the wall right of the hole (the band ends at 310). Beside the hole the wall is cream,
    // in it blue: the hole's first pixel was unlike the wall beside it, and the hole was left
    // OTHER. Measured (seeds 40–42): IR attached F1 0.000 → 0.863 (recall 0.76, precision 1).
    let calib = Calibration::nyu_default();
    let mut scene = Scene::new("black box whose shadow starts at a band edge");
    push_cream_and_blue_bands(&mut scene, &calib, (170.0, 140.0, 3.0), -20..20, false);
    push_black_box_over(&mut scene, (200.0, 300.0), 1.0, 0.19);
    assert_ideal_shadow_width(&scene, calib.fb() * (1.0 - 1.0 / 3.0));
    let (_, with_rgb) = with_and_without_colour(&scene, 40..43, false, |_| {});
    at_least(
        &with_rgb,
        Some(ATTACHED),
        0.8,
        "IR attached of a black box whose shadow starts at a band edge",
    );
}

#[test]
fn second_black_box_beside_the_first_gets_its_shadow_past_the_first() {
    // Two black boxes before the pale wall at 3 m: the first's front face at 1 m over IR columns
    // 200–300, the second's at 1.6 m from column 308. The first's shadow is f·b·(1/1 − 1/3) =
    // 29.1 px wide by hand, the second's f·b·(1/1.6 − 1/3) = 12.7 px, ending at column 308: its
    // first 4.7 px lie behind the first box, so the hole runs from the first shadow to the
    // second box's right edge with no lit wall in it. The split reads the first shadow and box;
    // past the first box the RGB camera sees the wall again (its alignment strip, 9.7 px, then
    // the second shadow's visible part less the 4.2 px the second box hides), and the strip
    // right of the second box gives that box's shift. Measured: the second shadow's recall
    // 0.00 → 0.79 (its start a pixel late: the first box's silhouette is its back corner's),
    // IR attached F1 0.925 → 0.979.
    let calib = Calibration::nyu_default();
    let (fx, cx) = (calib.depth.fx, calib.depth.cx);
    let x_at = |u: f64, z: f64| (u - cx) / fx * z;
    let mut scene = before_a_pale_wall("two black boxes side by side");
    push_black_box_over(&mut scene, (200.0, 300.0), 1.0, 0.3);
    push_black_box_over(&mut scene, (308.0, 408.0), 1.6, 0.3);
    let x2 = x_at(300.0, 1.0);
    let second_by_hand = 308.0 - calib.fb() * (1.0 / 1.6 - 1.0 / 3.0);
    assert!((second_by_hand - 295.3).abs() < 0.5, "{second_by_hand}");
    // The first box's right side face shows (it stands left of the optical axis): its
    // silhouette ends at its back corner, 1.1 m away.
    let first_ends = cx + fx * x2 / 1.1;
    let ideal = render_frame(&scene, &calib, &SensorModel::ideal(), 40);
    let row = &ideal.ir_labels[240 * WIDTH..241 * WIDTH];
    let second: Vec<usize> = (250..WIDTH).filter(|&u| row[u] == ATTACHED).collect();
    assert!(
        second.len() >= 6
            && (second[0] as f64 - first_ends).abs() <= 1.0
            && second.last().unwrap().abs_diff(308) <= 1
            && second.windows(2).all(|w| w[1] == w[0] + 1),
        "the second shadow's visible part {second:?}, by hand from {first_ends:.1} to 308"
    );
    let (mut found, mut truth) = (0, 0);
    let mut all = Confusion::default();
    for seed in 40..42 {
        let frame = render_frame(&scene, &calib, &SensorModel::kinect(), seed);
        let out = classify_rgb(&calib, &frame);
        all.add(&frame.ir_labels, &out.ir_labels);
        for i in (0..PIXELS).filter(|&i| i % WIDTH >= 290 && frame.ir_labels[i] == ATTACHED) {
            truth += 1;
            found += usize::from(out.ir_labels[i] == ATTACHED);
        }
    }
    let recall = found as f64 / truth as f64;
    at_least(
        &all,
        Some(ATTACHED),
        0.96,
        "IR attached of two black boxes side by side",
    );
    assert!(
        truth > 1500 && recall > 0.7,
        "second shadow: {found} of {truth}"
    );
}

#[test]
fn glossy_poster_pale_then_dark_on_the_wall_casts_no_shadow() {
    // A glossy poster on the wall at 3 m, 0.2 m wide: its left 0.13 m the wall's own colour, its
    // right 0.07 m dark. The sensor measures none of it: a hole with the wall on both sides, in
    // which the RGB camera sees the wall's colour, then a dark patch, the layout of a shadow and
    // its occluder. But the patch, 14 px at 3 m, is far narrower than the 25 px shift the
    // "shadow" before it would give it, and the wall is measured right of it: no occluder
    // narrower than its shift casts an attached shadow (it would leave a lit gap). No shadow.
    // Measured: 4 414 px claimed as attached before (seed 40), none after.
    let calib = Calibration::nyu_default();
    let mut scene = before_a_pale_wall("glossy poster, pale then dark, on the wall");
    push_box(
        &mut scene,
        "poster",
        [0.065, 0.0, 2.99],
        [0.065, 0.3, 0.005],
        umbra::synth::Material::glossy([0.8, 0.78, 0.7]),
    );
    push_box(
        &mut scene,
        "poster",
        [0.165, 0.0, 2.99],
        [0.035, 0.3, 0.005],
        umbra::synth::Material::glossy([0.12, 0.1, 0.1]),
    );
    for seed in 40..42 {
        let frame = render_frame(&scene, &calib, &SensorModel::kinect(), seed);
        let hole = frame.ir_labels.iter().filter(|&&l| l == OTHER).count();
        assert!(hole > 4_000, "the poster's hole: {hole} px");
        let out = classify_rgb(&calib, &frame);
        let claimed = out.ir_labels.iter().filter(|&&l| l == ATTACHED).count();
        assert_eq!(claimed, 0, "attached pixels claimed (seed {seed})");
    }
}

#[test]
fn black_poster_at_the_left_border_casts_no_shadow_from_colour() {
    // A black poster on the wall at 3 m, from past the left border to x = −0.9 m (column 138),
    // 1.8 m tall: a hole from column 0 with wall on its right, black in the RGB image up to its
    // right edge, where the RGB camera sees it too (it lies on the wall: no strip of wall right
    // of it). No shadow.
    let calib = Calibration::nyu_default();
    let mut scene = before_a_pale_wall("black poster at the left border");
    push_black_box(&mut scene, "poster", [-1.5, 0.0, 2.995], [0.6, 0.9, 0.005]);
    for seed in 40..42 {
        let frame = render_frame(&scene, &calib, &SensorModel::kinect(), seed);
        let hole = (0..PIXELS)
            .filter(|&i| i % WIDTH < 60 && frame.ir_labels[i] == OTHER)
            .count();
        assert!(hole > 18_000, "the poster's hole at the border: {hole} px");
        let out = classify_rgb(&calib, &frame);
        let claimed = out.ir_labels.iter().filter(|&&l| l == ATTACHED).count();
        assert_eq!(claimed, 0, "attached pixels claimed (seed {seed})");
    }
}

#[test]
fn black_box_at_the_left_border_before_a_wall_beyond_range_casts_no_shadow_there() {
    // A black box at 1.23 m from column 20 to 209, before a wall at 5.5 m (beyond the 4.5 m
    // range) with a partition at 3.2 m from column 226 on and a floor below: the hole from the
    // left border runs past the box to the partition, and the RGB camera sees the far wall,
    // pale like the partition, on both sides of the box: the layout of a shadow, a box and a
    // strip of wall 17 px wide (a shift of about 50 px, room for the 20 px left of the box).
    // But the box's shadow falls on the far wall, beyond the range: OTHER (SPEC §1), as is the
    // wall's hole above the box, which reaches the image's top while the floor ends the column
    // below.
    let calib = Calibration::nyu_default();
    let (fx, cx) = (calib.depth.fx, calib.depth.cx);
    let pale = umbra::synth::Material::matte([0.8, 0.78, 0.7]);
    let mut scene = Scene::new("black box at the left border, wall beyond range");
    scene.push("wall", umbra::synth::scene::wall(5.5), pale);
    scene.push("floor", umbra::synth::scene::floor(0.74, 0.09), pale);
    let x_partition = (226.0 - cx) / fx * 3.2;
    push_box(
        &mut scene,
        "partition",
        [x_partition + 2.0, 0.0, 3.25],
        [2.0, 3.0, 0.05],
        umbra::synth::Material::matte([0.78, 0.76, 0.7]),
    );
    let x_left = (20.0 - cx) / fx * 1.23;
    push_black_box(
        &mut scene,
        "box",
        [x_left + 0.2, -0.1, 1.28],
        [0.2, 0.25, 0.05],
    );
    for seed in 40..42 {
        let frame = render_frame(&scene, &calib, &SensorModel::kinect(), seed);
        // Left of the box, where the scene's shadow falls beyond the range (near the floor it
        // falls on the floor, in range).
        let beyond: Vec<usize> = (0..PIXELS)
            .filter(|&i| i % WIDTH < 20 && frame.ir_labels[i] == OTHER)
            .collect();
        assert!(beyond.len() > 3000, "{} px beyond the range", beyond.len());
        let out = classify_rgb(&calib, &frame);
        let claimed = count_labelled(&out.ir_labels, &beyond, ATTACHED);
        assert_eq!(
            claimed, 0,
            "attached pixels claimed beyond the range (seed {seed})"
        );
    }
}

#[test]
fn black_box_before_a_wall_beyond_range_past_a_partitions_edge_casts_no_shadow_there() {
    // A partition at 3.6 m, pale, up to column 395; right of it a wall at 5.4 m, beyond the
    // 4.5 m range, of nearly its colour; a black box at 1.8 m, columns 420..480, rows about
    // 180..260, no floor. Each of the box's rows is one hole from the partition's edge over the
    // box, and the RGB camera sees pale wall, then the black box: the layout of the box's
    // attached shadow on the partition. But the projector's shadow falls on the far wall,
    // beyond the range (OTHER, SPEC §1), as the row above the box shows: the same hole, the
    // same colour, no box. Read as a shadow, all 1 200 px of it were attached in both frames.
    let calib = Calibration::nyu_default();
    let (fx, fy, cx, cy) = (
        calib.depth.fx,
        calib.depth.fy,
        calib.depth.cx,
        calib.depth.cy,
    );
    let mut scene = before_a_wall(
        "black box before a wall beyond range, past a partition",
        5.4,
        [0.8, 0.8, 0.76],
    );
    let x_edge = (395.0 - cx) / fx * 3.6;
    push_box(
        &mut scene,
        "partition",
        [x_edge - 3.0, 0.0, 3.65],
        [3.0, 3.0, 0.05],
        umbra::synth::Material::matte([0.82, 0.8, 0.78]),
    );
    let x = |u: f64| (u - cx) / fx * 1.8;
    let y = |v: f64| (v - cy) / fy * 1.8;
    push_black_box(
        &mut scene,
        "box",
        [0.5 * (x(420.0) + x(480.0)), y(220.0), 1.85],
        [
            0.5 * (x(480.0) - x(420.0)),
            0.5 * (y(260.0) - y(180.0)),
            0.05,
        ],
    );
    for seed in 7..9 {
        let frame = render_frame(&scene, &calib, &SensorModel::kinect(), seed);
        // Between the partition's edge and the box, in the box's rows: the far wall's hole.
        let between: Vec<usize> = (190..250)
            .flat_map(|v| (398..418).map(move |u| v * WIDTH + u))
            .filter(|&i| frame.ir_labels[i] == OTHER)
            .collect();
        assert!(between.len() > 1000, "{} px of the far wall", between.len());
        let out = classify_rgb(&calib, &frame);
        let claimed = count_labelled(&out.ir_labels, &between, ATTACHED);
        assert_eq!(
            claimed, 0,
            "attached pixels claimed beyond the range (seed {seed})"
        );
    }
}

/// A pale box 20 cm deep, its face at `z` m spanning x = `left..right` and `half_height` m up
/// and down, before a dark wall at 5.5 m, beyond the sensor's range.
fn pale_box_before_a_region_beyond_range(
    (left, right): (f64, f64),
    z: f64,
    half_height: f64,
) -> Scene {
    let mut scene = Scene::new("pale box before a dark region beyond range");
    scene.push(
        "wall",
        umbra::synth::scene::wall(5.5),
        umbra::synth::Material::matte([0.06, 0.06, 0.08]),
    );
    push_box(
        &mut scene,
        "box",
        [0.5 * (left + right), 0.0, z + 0.1],
        [0.5 * (right - left), half_height, 0.1],
        umbra::synth::Material::matte([0.8, 0.78, 0.7]),
    );
    scene
}

#[test]
fn hole_between_a_far_box_and_a_near_rod_places_no_occluder_over_the_box() {
    // A pale box at 3 m, its right edge at column 180, a dark wall beyond the range (5.5 m) right
    // of it, and a grey rod 3 cm thick at 0.7 m around column 300. Between box and rod one hole:
    // the region beyond range, with the rod's attached shadow on it, which the sensor widens
    // 3 px into the rod. The RGB camera sees the rod start before the hole ends, a colour change
    // the colour split read as the right edge of a depthless occluder filling the hole, a little
    // nearer than the rod; warped at that depth, the hole's pixels covered the box's last
    // columns in the RGB view. But a hole that ends at a surface nearer than the one it starts
    // after is that surface's shadow's layout: the box keeps every column the simulator says
    // the RGB camera sees.
    let calib = Calibration::nyu_default();
    let (fx, cx) = (calib.depth.fx, calib.depth.cx);
    let right = (180.0 - cx) / fx * 3.0;
    let mut scene = pale_box_before_a_region_beyond_range((-3.0, right), 3.0, 0.6);
    push_grey_rod(&mut scene, (300.0 - cx) / fx * 0.7, 0.7, 0.015);
    for seed in 20..22 {
        let mut frame = render_frame(&scene, &calib, &SensorModel::kinect(), seed);
        // A sensor that widens every hole (the fifth simulator's) eats the rod's first columns.
        widen_every_hole(&mut frame, 0, 3);
        let out = classify_rgb(&calib, &frame);
        // The box's last 30 columns in the RGB view, as the simulator sees them, in its rows.
        let (mut seen, mut lost) = (0, 0);
        for v in 150..330 {
            let row = &frame.rgb_labels[v * WIDTH..(v + 1) * WIDTH];
            let Some(end) = (100..400).find(|&u| row[u] != VALID) else {
                continue;
            };
            for u in end.saturating_sub(30)..end {
                seen += 1;
                lost += usize::from(out.rgb_labels[v * WIDTH + u] != VALID);
            }
        }
        // Measured: 1 of 5 400 per seed (2 395 before).
        assert!(seen > 3000, "seed {seed}: {seen} box pixels");
        assert!(
            lost * 100 <= seen,
            "seed {seed}: {lost} of {seen} box pixels lost"
        );
    }
}

#[test]
fn box_edge_the_widening_took_beside_a_region_beyond_range_is_no_alignment_shadow() {
    // A pale box at 2 m, columns 250 to 350, before a dark wall beyond the range; right of it a
    // grey panel at 3 m with a grey rod at 1.2 m before it, whose shadow shows the frame's
    // widening. Every hole widened by 2 px on each end: the region beyond range left of the box
    // ends two columns into the box, which the RGB camera sees there, past a sharp edge from the
    // dark region: the layout of a black occluder's alignment strip. But no depth lies behind the
    // box (no alignment shadow, SPEC §1): those columns are the box, unmeasured.
    let calib = Calibration::nyu_default();
    let (fx, cx) = (calib.depth.fx, calib.depth.cx);
    let at = |u: f64, z: f64| (u - cx) / fx * z;
    let box_cols = (at(250.0, 2.0), at(350.0, 2.0));
    let mut scene = pale_box_before_a_region_beyond_range(box_cols, 2.0, 0.5);
    let (l, r) = (at(450.0, 3.0), at(700.0, 3.0));
    push_box(
        &mut scene,
        "panel",
        [0.5 * (l + r), 0.0, 3.05],
        [0.5 * (r - l), 2.0, 0.05],
        umbra::synth::Material::matte([0.5, 0.5, 0.55]),
    );
    push_grey_rod(&mut scene, at(560.0, 1.2), 1.2, 0.03);
    for seed in 50..52 {
        let mut frame = render_frame(&scene, &calib, &SensorModel::ideal(), seed);
        widen_every_hole(&mut frame, 2, 2);
        let out = classify_rgb(&calib, &frame);
        // Around the box's left edge in the RGB view, as the simulator sees it, in its rows.
        let (mut rows, mut strip) = (0, 0);
        for v in 0..HEIGHT {
            let row = &frame.rgb_labels[v * WIDTH..(v + 1) * WIDTH];
            let Some(edge) = (150..400).find(|&u| row[u] == VALID) else {
                continue;
            };
            assert!(
                row[edge - 15..edge].iter().all(|&l| l == OTHER),
                "row {v}: the truth has no shadow left of the box"
            );
            rows += 1;
            let span = v * WIDTH + edge - 15..v * WIDTH + edge + 5;
            strip += out.rgb_labels[span]
                .iter()
                .filter(|&&l| l == ALIGNMENT)
                .count();
        }
        // Measured: none (before, 2 px in every row: 520).
        assert!(rows > 200, "seed {seed}: {rows} rows of the box");
        assert!(
            strip <= rows / 20,
            "seed {seed}: {strip} px of alignment along {rows} rows of the box's edge"
        );
    }
}

#[test]
fn strip_of_a_box_swallowed_by_the_widening_before_a_dark_region_beyond_range_is_no_shadow() {
    // A pale box at 1.5 m, columns 250 to 350, before a dark wall at 5.5 m (beyond the 4.5 m
    // range): right of the box the hole runs to the right border. A sensor whose correlation
    // window widens every hole (a fifth simulator's; real edges into unmeasured regions do so
    // too) swallows the box's last 3 columns, which the RGB camera still sees pale, then the
    // dark wall: the layout of a 3 px shadow and a black occluder. But the box's shadow falls
    // left of it, and the strip is the box's own edge: no shadow (SPEC §1), OTHER.
    let calib = Calibration::nyu_default();
    let (fx, cx) = (calib.depth.fx, calib.depth.cx);
    let (left, right) = ((250.0 - cx) / fx * 1.5, (350.0 - cx) / fx * 1.5);
    let scene = pale_box_before_a_region_beyond_range((left, right), 1.5, 0.4);
    for seed in 40..42 {
        let mut frame = render_frame(&scene, &calib, &SensorModel::kinect(), seed);
        let mut strip = Vec::new();
        for (v, row) in frame.raw.chunks_exact_mut(WIDTH).enumerate() {
            let Some(end) = (200..400).rev().find(|&u| row[u] != NO_DEPTH) else {
                continue;
            };
            if row[end + 1..].iter().all(|&r| r == NO_DEPTH) && end > 300 {
                row[end - 2..=end].fill(NO_DEPTH);
                strip.extend((end - 2..=end).map(|u| v * WIDTH + u));
            }
        }
        assert!(strip.len() > 3 * 150, "{} px swallowed", strip.len());
        let out = classify_rgb(&calib, &frame);
        let claimed = count_labelled(&out.ir_labels, &strip, ATTACHED);
        // (Before, 930 px of seed 40's strip; a stray pixel of the scanline's may remain.)
        assert!(
            claimed * 100 <= strip.len(),
            "{claimed} px of a box's swallowed edge claimed as shadow (seed {seed})"
        );
    }
}

#[test]
fn with_a_dead_band_along_the_right_border_such_a_hole_is_not_claimed() {
    // A real sensor returns no depth in its last 8 columns, in every row (the NYU frame): a
    // hole running a little way past that band is as often the band widened as a shadow, and
    // the colour cannot tell them apart. The same panel, with such a band cut into the frame
    // (its shadow 13–16 px past the band): no shadow is claimed at the border.
    let calib = Calibration::nyu_default();
    let mut frame = render_frame(
        &panel_beyond_the_right_border(0.58),
        &calib,
        &SensorModel::kinect(),
        40,
    );
    for row in frame.raw.chunks_exact_mut(WIDTH) {
        row[WIDTH - 8..].fill(umbra::labels::NO_DEPTH);
    }
    let out = classify_rgb(&calib, &frame);
    let claimed = (0..PIXELS)
        .filter(|&i| i % WIDTH >= 560 && out.ir_labels[i] == ATTACHED)
        .count();
    assert_eq!(claimed, 0, "attached pixels at the border");
}

#[test]
fn with_a_dead_band_a_shadow_reaching_well_past_it_is_claimed() {
    // The panel nearer, its left face at x = 0.46 m, 0.80 to 0.81 m away: column
    // cx + fx·0.46/0.81 ≈ 644, past the border. Its shadow on the wall at 3 m is
    // f·b·(1/0.81 − 1/3) ≈ 39 px wide by hand, from column 605: 27 px of it left of the dead
    // band cut into the frame, too wide for the band widened. Left of the band it is attached
    // (F1 0.000 before such holes were read in frames with the band, 0.975 after); the band
    // stays OTHER. The panel is short enough that most rows show the bare band.
    let calib = Calibration::nyu_default();
    let edge = calib.depth.cx + calib.depth.fx * 0.46 / 0.81;
    let start = edge - calib.fb() * (1.0 / 0.81 - 1.0 / 3.0);
    assert!(
        edge > WIDTH as f64 && (600.0..610.0).contains(&start),
        "{start}..{edge}"
    );
    let mut scene = before_a_pale_wall("panel beyond the right border, nearer");
    push_box(
        &mut scene,
        "panel",
        [0.96, 0.0, 0.805],
        [0.5, 0.15, 0.005],
        umbra::synth::Material::matte([0.2, 0.35, 0.8]),
    );
    let ideal = render_frame(&scene, &calib, &SensorModel::ideal(), 40);
    let row = &ideal.ir_labels[240 * WIDTH..241 * WIDTH];
    let first = row.iter().position(|&l| l == ATTACHED);
    assert!(
        first.is_some_and(|u| (u as f64 - start).abs() <= 1.0) && row[WIDTH - 1] == ATTACHED,
        "the scene's shadow starts at {first:?}, by hand at {start:.1}"
    );
    let band = WIDTH - 8;
    let (mut truth, mut found, mut hit, mut in_band) = (0, 0, 0, 0);
    for seed in 40..42 {
        let mut frame = render_frame(&scene, &calib, &SensorModel::kinect(), seed);
        for row in frame.raw.chunks_exact_mut(WIDTH) {
            row[band..].fill(umbra::labels::NO_DEPTH);
        }
        let out = classify_rgb(&calib, &frame);
        for i in (0..PIXELS).filter(|&i| i % WIDTH >= 560) {
            let (t, o) = (frame.ir_labels[i] == ATTACHED, out.ir_labels[i] == ATTACHED);
            if i % WIDTH >= band {
                in_band += usize::from(o);
                continue;
            }
            truth += usize::from(t);
            found += usize::from(o);
            hit += usize::from(t && o);
        }
    }
    assert_eq!(in_band, 0, "attached pixels in the dead band");
    let f1 = 2.0 * hit as f64 / (truth + found) as f64;
    assert!(
        truth > 5_000 && f1 >= 0.9,
        "IR attached F1 {f1:.3} left of the band ({hit} of {truth}, {found} claimed)"
    );
}

/// A wall turned 12° away, z = `z0` + x·tan 12°, with a red poster on it from x = `poster_x`
/// (0.5 m wide, standing off it by at most 8 cm, so as far as the wall) and a board across the
/// top of the view, for the Kinect model, which measures to 4.5 m.
fn turned_wall_with_a_poster(z0: f64, poster_x: f64) -> Scene {
    let tilt = 12f64.to_radians();
    let mut scene = Scene::new("wall turned away, leaving the range");
    scene.push(
        "wall",
        umbra::synth::Shape::Plane {
            normal: umbra::synth::V3::new(tilt.sin(), 0.0, -tilt.cos()),
            offset: -z0 * tilt.cos(),
        },
        umbra::synth::Material::matte([0.8, 0.78, 0.7]),
    );
    let z = z0 + (poster_x + 0.25) * tilt.tan();
    push_box(
        &mut scene,
        "poster",
        [poster_x + 0.25, 0.0, z - 0.05],
        [0.25, 3.0, 0.04],
        umbra::synth::Material::matte([0.8, 0.15, 0.1]),
    );
    // A board 2 m away across the top sixth of the view: rows without a hole at the border, so
    // the frame is not taken for a real sensor's with its dead band.
    push_box(
        &mut scene,
        "board",
        [0.0, -1.0, 2.0],
        [4.0, 0.4, 0.02],
        umbra::synth::Material::matte([0.5, 0.5, 0.55]),
    );
    scene
}

#[test]
fn hole_where_a_turned_wall_leaves_the_range_stays_other() {
    // The wall reaches the sensor's 4.5 m where (u − cx)/fx = (1 − z0/4.5)/tan 12°: column 557
    // or so for z0 = 4.1 m (an 83 px hole to the border, which the colour split reads), 600
    // for z0 = 4.03 m (40 px, which the off-image test reads). Over the hole the RGB camera
    // sees the wall, then the poster, at x = 2.35 m (column 615) and 2.48 m (column 630), where
    // an occluder beyond the border, or in the hole, would stand. But the wall beside the hole
    // is the frame's farthest and recedes: the hole lies beyond the range, OTHER (SPEC §1).
    let calib = Calibration::nyu_default();
    for (z0, poster_x) in [(4.1, 2.35), (4.03, 2.48)] {
        let scene = turned_wall_with_a_poster(z0, poster_x);
        let cut = calib.depth.cx + calib.depth.fx * (1.0 - z0 / 4.5) / 12f64.to_radians().tan();
        for seed in 50..52 {
            let frame = render_frame(&scene, &calib, &SensorModel::kinect(), seed);
            let out = classify_rgb(&calib, &frame);
            let beyond = (0..PIXELS)
                .filter(|&i| i % WIDTH > cut as usize + 5)
                .filter(|&i| frame.ir_labels[i] == OTHER)
                .count();
            assert!(
                beyond > 10_000,
                "the scene's hole past column {cut:.0}: {beyond} px"
            );
            let claimed = (0..PIXELS)
                .filter(|&i| out.ir_labels[i] == ATTACHED)
                .count();
            assert_eq!(
                claimed, 0,
                "z0 {z0}, seed {seed}: attached pixels on a wall leaving the range"
            );
        }
    }
}

#[test]
fn gap_past_a_thin_rod_where_a_turned_wall_leaves_the_range_is_no_shadow() {
    // A wall turned 60° away through (0, 0, 3 m) reaches the sensor's 4.5 m at column cx + fx·(1
    // − 3/4.5)/tan 60° = 425.2. A thin rod (radius 13 mm) at 1.5 m stands over that column
    // (420.1 ± 10.1 px), a nearer one (radius 15 mm) at 0.8 m right of it (477.6 ± 10.9): between
    // them, 430..467, the wall lies beyond the range and nothing the sensor measures takes the
    // near rod's shadow: OTHER (SPEC §1). From the row alone it looks like that shadow on the
    // wall left of the thin rod, which goes on behind it (eq. 3 at the wall's last measured 4.5
    // m: 43.7·(1/0.8 − 1/4.5) = 44.9 px, wider than the gap), and nothing above the gap was ever
    // measured. The wall's slope, carried from its last measured pixels to the gap's end, leaves
    // the frame's range (a floor 1 m below keeps some rows measured to the border).
    // Measured (seed 80): 310 px of the gap called shadow before, 0 now; seed 81 31 px.
    let calib = Calibration::nyu_default();
    let mut scene = Scene::new("thin rod where a turned wall leaves the range");
    scene.push(
        "wall",
        umbra::synth::scene::slanted_wall(3.0, 60f64.to_radians()),
        umbra::synth::Material::matte([0.8, 0.78, 0.7]),
    );
    scene.push(
        "floor",
        umbra::synth::scene::floor(1.0, 0.0),
        umbra::synth::Material::matte([0.5, 0.5, 0.45]),
    );
    push_grey_rod(
        &mut scene,
        (420.1 - calib.depth.cx) * 1.5 / calib.depth.fx,
        1.5,
        0.013,
    );
    push_grey_rod(
        &mut scene,
        (477.6 - calib.depth.cx) * 0.8 / calib.depth.fx,
        0.8,
        0.015,
    );
    for seed in 80..82 {
        let frame = render_frame(&scene, &calib, &SensorModel::kinect(), seed);
        let gap = |v: usize| v * WIDTH + 433..v * WIDTH + 464;
        assert!(
            (0..300).all(|v| frame.ir_labels[gap(v)].iter().all(|&l| l == OTHER)),
            "the gap is a hole beyond the range"
        );
        for (out, what) in [
            (classify(&calib, &frame), "depth alone"),
            (classify_rgb(&calib, &frame), "with colour"),
        ] {
            let claimed = (0..300)
                .flat_map(gap)
                .filter(|&i| out.ir_labels[i] != OTHER)
                .count();
            assert!(
                claimed < 100,
                "seed {seed}, {what}: {claimed} px of the gap called shadow"
            );
        }
    }
}

#[test]
fn box_shadow_across_the_corner_of_a_side_wall_and_the_back_wall_stays_attached() {
    // A side wall at x = −1.71 m meets a back wall at 3.68 m in a corner at column
    // cx − fx·1.71/3.68 ≈ 43; a box whose front face (0.68 m, rows 112–368) starts at column 96
    // casts an attached shadow of f·b·(1/0.68 − 1/3.68) ≈ 52 px back to column 44, across the
    // corner. The side wall recedes into the hole by 0.35 raw units a pixel, its line leaving
    // the frame's farthest value (the back wall's) within a few pixels: read as a wall leaving
    // the range, most of the shadow was OTHER, first in the shadow's top row, then in every row
    // below it. The rows above show the back wall measured in those columns, as far as the
    // range's end: the receding wall meets it there. Measured (seeds 90–91): attached F1 0.147
    // → 0.992, from depth alone and with colour alike.
    let calib = Calibration::nyu_default();
    let mut scene = Scene::new("box shadow across the corner of a side wall and the back wall");
    scene.push(
        "back wall",
        umbra::synth::Shape::Plane {
            normal: umbra::synth::V3::new(0.0, 0.0, -1.0),
            offset: -3.68,
        },
        umbra::synth::Material::matte([0.8, 0.78, 0.7]),
    );
    scene.push(
        "side wall",
        umbra::synth::Shape::Plane {
            normal: umbra::synth::V3::new(1.0, 0.0, 0.0),
            offset: -1.71,
        },
        umbra::synth::Material::matte([0.6, 0.7, 0.75]),
    );
    let left = (96.0 - calib.depth.cx) * 0.68 / calib.depth.fx;
    push_box(
        &mut scene,
        "box",
        [left + 0.15, 0.0, 0.88],
        [0.15, 0.15, 0.2],
        umbra::synth::Material::matte([0.5, 0.8, 0.85]),
    );
    let (mut alone, mut colour) = (Confusion::default(), Confusion::default());
    for seed in 90..92 {
        let frame = render_frame(&scene, &calib, &SensorModel::kinect(), seed);
        alone.add(&frame.ir_labels, &classify(&calib, &frame).ir_labels);
        colour.add(&frame.ir_labels, &classify_rgb(&calib, &frame).ir_labels);
    }
    for (c, what) in [(&alone, "depth alone"), (&colour, "with colour")] {
        at_least(c, Some(ATTACHED), 0.95, what);
    }
}

#[test]
fn black_box_hiding_the_far_side_of_a_turned_wall_keeps_its_shadow() {
    // A wall through (0, 0, 3.2 m) turned 25° (its right side receding: 3.15 m at column 300,
    // 3.25 m at 340) and a black box at 0.9 m over every row from column 340 to the border: its
    // attached shadow on the wall is f·b·(1/0.9 − 1/3.2) ≈ 35 px, [305, 340), one hole with the
    // box's own to the border. The wall's last measured pixels, beside the shadow, are the
    // frame's farthest, and it recedes there: read as the range's end, the wall left the range
    // inside the hole, OTHER in many rows. No Kinect's range ends at 3.2 m. Measured (seeds
    // 100–101): attached F1 0.882 → 0.963, recall 0.816 → 0.996.
    let calib = Calibration::nyu_default();
    let mut scene = Scene::new("black box hiding the far side of a turned wall");
    scene.push(
        "wall",
        umbra::synth::scene::slanted_wall(3.2, 25f64.to_radians()),
        umbra::synth::Material::matte([0.6, 0.5, 0.7]),
    );
    let left = (340.0 - calib.depth.cx) * 0.9 / calib.depth.fx;
    push_black_box(&mut scene, "box", [left + 1.0, 0.0, 1.0], [1.0, 3.0, 0.1]);
    let mut c = Confusion::default();
    for seed in 100..102 {
        let frame = render_frame(&scene, &calib, &SensorModel::kinect(), seed);
        c.add(&frame.ir_labels, &classify_rgb(&calib, &frame).ir_labels);
    }
    at_least(&c, Some(ATTACHED), 0.93, "box's shadow on the turned wall");
}

#[test]
fn black_stripe_where_such_a_shadow_would_fall_stays_other() {
    // The same hole, made by a black strip on the wall instead (13 mm proud of it, columns
    // 613.1..624.8 at 3 m: x = (u − cx)·3/fx = 1.544..1.605 m): the RGB camera sees it dark.
    let mut scene = Scene::rod_before_wall(0.575, 1.0, 0.01, 3.0);
    scene.objects.pop();
    push_black_box(
        &mut scene,
        "strip",
        [1.5745, 0.0, 2.99],
        [0.0305, 3.0, 0.005],
    );
    let (frame, _, out) = rod_off_the_right_border(&scene);
    let holes = (0..frame.raw.len())
        .filter(|&i| i % WIDTH > 560 && frame.ir_labels[i] == OTHER)
        .count();
    assert!(holes > 5000, "the strip leaves {holes} OTHER pixels");
    assert!(
        out.ir_labels.iter().all(|&l| l != DETACHED),
        "a black strip called a shadow"
    );
}

#[test]
fn gap_between_a_panel_and_a_rod_onto_a_wall_beyond_range_is_no_shadow() {
    // A panel at 2 m ends at x = 0 (column cx = 313.0); a 2 cm rod at 1.6 m stands with its left
    // edge at x = 0.01785 m (column 313.0 + 0.01785·fx/1.6 = 319.5); behind both, a wall at 5 m,
    // beyond the sensor's range. The gap between them, 6.5 px, fits eq. (3) for Sa = panel and
    // Sb = rod: f·b·(1/1.6 − 1/2) = 5.5 px. But the rod's shadow on the panel's plane,
    // 313.0..320.4 (its columns shifted by those 5.5 px), lies past the panel's edge, on the
    // far wall, which returns no depth lit or not: OTHER. The RGB camera sees that far wall
    // through the gap, as right of the rod, not the panel.
    let calib = Calibration::nyu_default();
    let mut scene = Scene::new("panel and rod before a wall beyond range");
    scene.push(
        "wall",
        umbra::synth::scene::wall(5.0),
        umbra::synth::Material::matte([0.2, 0.35, 0.75]),
    );
    scene.push(
        "panel",
        umbra::synth::Shape::Box {
            centre: umbra::synth::V3::new(-1.0, 0.0, 2.05),
            half: umbra::synth::V3::new(1.0, 3.0, 0.05),
            yaw: 0.0,
        },
        umbra::synth::Material::matte([0.85, 0.6, 0.4]),
    );
    push_grey_rod(&mut scene, 0.02785, 1.6, 0.01);
    let frame = render_frame(&scene, &calib, &SensorModel::ideal(), 6);
    let depth_only = classify(&calib, &frame);
    let out = classify_rgb(&calib, &frame);
    let gap = |labels: &[u8], v: usize, code: u8| {
        (310..322)
            .filter(|&u| labels[v * WIDTH + u] == code)
            .count()
    };
    let rows = 20..HEIGHT - 20;
    for v in rows.clone() {
        assert_eq!(gap(&frame.ir_labels, v, ATTACHED), 0, "row {v}: the scene");
        assert!(
            gap(&frame.ir_labels, v, OTHER) >= 5,
            "row {v}: the scene's gap"
        );
        assert_eq!(gap(&out.ir_labels, v, ATTACHED), 0, "row {v}: with colour");
    }
    // The trap is real: from depth alone the gap is an attached shadow in most rows.
    let fooled = rows
        .filter(|&v| gap(&depth_only.ir_labels, v, ATTACHED) >= 5)
        .count();
    assert!(fooled > 300, "depth alone calls {fooled} rows attached");
}

/// A panel at 1 m whose right edge is column cx (x = 0), from the image's top to its bottom, and
/// right of it a board at 1.2 m with its left edge 14 px further right, from the image's top to
/// `board_bottom` (y, metres; rows run down): a gap between two objects that reach the frame's
/// top. Behind them `wall` at `wall_z`.
fn gap_below_the_top(
    calib: &Calibration,
    wall_z: f64,
    board_bottom: f64,
) -> (Scene, std::ops::Range<usize>) {
    let (fx, cx) = (calib.depth.fx, calib.depth.cx);
    let x_board = 14.0 / fx * 1.2;
    let mut scene = Scene::new("gap between a panel and a board from the frame's top");
    scene.push(
        "wall",
        umbra::synth::scene::wall(wall_z),
        umbra::synth::Material::matte([0.8, 0.78, 0.7]),
    );
    let panel = umbra::synth::Material::matte([0.85, 0.6, 0.4]);
    push_box(
        &mut scene,
        "panel",
        [-1.0, 0.0, 1.05],
        [1.0, 3.0, 0.05],
        panel,
    );
    let top = -3.0;
    push_box(
        &mut scene,
        "board",
        [x_board + 0.3, 0.5 * (top + board_bottom), 1.25],
        [0.3, 0.5 * (board_bottom - top), 0.05],
        umbra::synth::Material::matte([0.3, 0.55, 0.6]),
    );
    let u = cx.round() as usize;
    (scene, u - 2..u + 16)
}

#[test]
fn gap_between_two_objects_from_the_frames_top_holds_the_farther_ones_shadow() {
    // Panel at 1 m (Sa) ending at column cx, board at 1.2 m (Sb) from column cx + 14, both from
    // the frame's top; the board ends at y = 0 (row cy). By hand the board's shadow on the wall
    // at 3 m is f·b·(1/1.2 − 1/3) = 21.8 px wide, more than the 14 px gap: the whole gap is the
    // board's attached shadow, on a background nothing above shows (both objects reach the top)
    // and the panel, nearer than the board, hides from eq. (3). The wall shows below the board's
    // end, in the gap's own columns. Measured: attached recall in the gap 0.494 → 0.9995 (with
    // the ideal sensor 0 before: the Kinect model's stray edge pixels had given the old rule a
    // background above in most rows; 0.972 while a pixel of the board's edge, mixed with the
    // wall, still stood for the background in the others).
    let calib = Calibration::nyu_default();
    let shift = calib.fb() * (1.0 / 1.2 - 1.0 / 3.0);
    assert!(shift > 14.0 + 3.0, "{shift}");
    let (scene, gap) = gap_below_the_top(&calib, 3.0, 0.0);
    let cy = calib.depth.cy as usize;
    let (mut truth, mut found, mut wrong) = (0, 0, 0);
    for sensor in [SensorModel::ideal(), SensorModel::kinect()] {
        let frame = render_frame(&scene, &calib, &sensor, 60);
        let out = classify_rgb(&calib, &frame);
        for v in 10..cy - 10 {
            let in_gap = |labels: &[u8], code: u8| {
                gap.clone()
                    .filter(|&u| labels[v * WIDTH + u] == code)
                    .count()
            };
            assert!(
                in_gap(&frame.ir_labels, ATTACHED) >= 12,
                "row {v}: the scene"
            );
            truth += in_gap(&frame.ir_labels, ATTACHED);
            found += gap
                .clone()
                .filter(|&u| {
                    let i = v * WIDTH + u;
                    frame.ir_labels[i] == ATTACHED && out.ir_labels[i] == ATTACHED
                })
                .count();
        }
        // Below the board the wall is lit in the gap, and nothing else is claimed anywhere.
        for i in 0..PIXELS {
            wrong += usize::from(out.ir_labels[i] == ATTACHED && frame.ir_labels[i] != ATTACHED);
        }
    }
    let recall = found as f64 / truth as f64;
    assert!(recall > 0.99, "attached recall in the gap {recall:.3}");
    assert!(wrong < truth / 50, "{wrong} px claimed attached elsewhere");
}

#[test]
fn gap_from_the_frames_top_over_a_low_box_before_a_wall_beyond_range_is_no_shadow() {
    // The same gap, the board running to the bottom, before a wall at 5.5 m (beyond the range):
    // what the gap shows is the far wall, OTHER lit or not. A low box at 1.65 m stands in the
    // gap's columns from row 400 down, the board's shadow on it 9.9 px wide by hand (f·b·(1/1.2 −
    // 1/1.65)), so its top shows lit in the gap's left columns. That top is no background the
    // gap hides: the board goes on past it, while a shadow stops where its occluder does. (Taken
    // for the background, it makes the 14 px gap the board's shadow on it, within eq. (3)'s
    // tolerance for the widening.)
    let calib = Calibration::nyu_default();
    let (mut scene, gap) = gap_below_the_top(&calib, 5.5, 3.0);
    let (fy, cy) = (calib.depth.fy, calib.depth.cy);
    let y_top = (400.0 - cy) / fy * 1.65;
    push_box(
        &mut scene,
        "low box",
        [0.0, y_top + 1.0, 1.7],
        [0.5, 1.0, 0.05],
        umbra::synth::Material::matte([0.7, 0.7, 0.72]),
    );
    for seed in 60..62 {
        let frame = render_frame(&scene, &calib, &SensorModel::kinect(), seed);
        let out = classify_rgb(&calib, &frame);
        let mut holes = 0;
        for v in 10..390 {
            for u in gap.clone() {
                let i = v * WIDTH + u;
                holes += usize::from(frame.ir_labels[i] == OTHER);
                assert_ne!(
                    out.ir_labels[i], ATTACHED,
                    "row {v}, column {u} (seed {seed})"
                );
            }
        }
        assert!(holes >= 380 * 10, "the gap's far wall: {holes} px OTHER");
    }
}

/// A board at 1.4 m turned 50° away on its right (its disparity falls about 0.06 px per column),
/// and on it, side by side, two patches the sensor measures nothing on: the left one
/// (`left_px` columns) the board's own colour, the right one (`right_px`) dark. Returns the scene
/// and the columns of a row through the patches.
fn dropout_on_a_turned_board(left_px: f64, right_px: f64) -> (Scene, std::ops::Range<usize>) {
    let calib = Calibration::nyu_default();
    let (fx, cx) = (calib.depth.fx, calib.depth.cx);
    let yaw = -50f64.to_radians();
    let (s, c) = yaw.sin_cos();
    // The board's width direction (local x) and front (local −z) in the world.
    let along = |x: f64, z: f64| [c * x + s * z, 0.0, -s * x + c * z];
    let centre = [0.0, 0.0, 1.4];
    let mut scene = before_a_pale_wall("dropouts on a turned board");
    let board = umbra::synth::Material::matte([0.62, 0.46, 0.3]);
    scene.push(
        "board",
        umbra::synth::Shape::Box {
            centre: umbra::synth::V3::from(centre),
            half: umbra::synth::V3::new(0.5, 3.0, 0.01),
            yaw,
        },
        board,
    );
    // Metres along the board per image column, at its middle.
    let per_px = 1.4 / fx / c;
    let patch = |name: &'static str, from: f64, px: f64, colour: [f64; 3]| {
        let x = from + 0.5 * px * per_px;
        let [dx, _, dz] = along(x, -0.0125);
        (
            name,
            umbra::synth::Shape::Box {
                centre: umbra::synth::V3::new(centre[0] + dx, 0.0, centre[2] + dz),
                half: umbra::synth::V3::new(0.5 * px * per_px, 3.0, 0.002),
                yaw,
            },
            umbra::synth::Material {
                albedo: 0.0,
                specular: false,
                colour,
            },
        )
    };
    let start = -0.5 * (left_px + right_px) * per_px;
    for (name, shape, material) in [
        patch("same-coloured patch", start, left_px, board.colour),
        patch(
            "dark patch",
            start + left_px * per_px,
            right_px,
            [0.08, 0.07, 0.1],
        ),
    ] {
        scene.push(name, shape, material);
    }
    let half = 0.5 * (left_px + right_px) + 6.0;
    (scene, (cx - half) as usize..(cx + half) as usize)
}

#[test]
fn dropout_on_a_turned_surface_is_no_shadow_however_its_colours_fall() {
    // The two patches make one hole on one slanted surface: Sb lies a few pixels of disparity
    // behind Sa only because the board turns away, and the slope either side of the hole,
    // carried over it, lands on the other. In the RGB image the hole reads from the left as
    // background (the first patch is the board's colour) and then something dark: the layout of
    // a black occluder's attached shadow, were the hole a depth edge. (A glossy box's dropouts
    // on a fourth simulator: 9 200 false attached pixels in one simple scene.)
    let (scene, cols) = dropout_on_a_turned_board(14.0, 30.0);
    let calib = Calibration::nyu_default();
    for seed in 60..62 {
        let frame = render_frame(&scene, &calib, &SensorModel::kinect(), seed);
        let holes: usize = (100..HEIGHT - 100)
            .map(|v| {
                cols.clone()
                    .filter(|&u| frame.ir_labels[v * WIDTH + u] == OTHER)
                    .count()
            })
            .sum();
        assert!(holes > 280 * 40, "the patches' hole: {holes} px");
        let out = classify_rgb(&calib, &frame);
        let claimed: usize = (0..HEIGHT)
            .map(|v| {
                cols.clone()
                    .filter(|&u| out.ir_labels[v * WIDTH + u] == ATTACHED)
                    .count()
            })
            .sum();
        assert_eq!(
            claimed, 0,
            "attached pixels claimed in the dropout (seed {seed})"
        );
    }
}

#[test]
fn chain_of_dropouts_on_a_banded_wall_holds_no_detached_shadow() {
    // A wall at 3 m in bands 29 px wide (14.9 cm), green and mauve, and three dropouts 10 px wide
    // and 0.6 m (117 rows) tall, patches that return no IR light, in their band's colour, in the
    // middle of three bands in a row, 29 px apart: the layout of rods at f·b/(29 + f·b/3) ≈ 1 m
    // with their detached shadows. Chained, depth alone pairs none of them. Read in colour, each
    // next hole shows the other band's colour, unlike the wall beside the one before it, as a
    // rod's would; but that colour is the wall's own, shown on both sides of the pair. (Glossy
    // checkered cylinders' dropouts on a fourth simulator.) Measured (seeds 60–61): detached
    // pixels 2 285 → 1.
    let calib = Calibration::nyu_default();
    let z = 3.0;
    let per_px = z / calib.depth.fx;
    let x_of = |u: f64| (u - calib.depth.cx) * per_px;
    let (green, mauve) = ([0.4, 0.6, 0.3], [0.6, 0.35, 0.5]);
    let band = 29.0;
    let mut scene = Scene::new("dropouts on a banded wall");
    push_bands(&mut scene, (x_of(200.0), band * per_px, z), -10..20, |k| {
        if k % 2 == 0 {
            green
        } else {
            mauve
        }
    });
    for (u0, colour) in [(267.5, green), (296.5, mauve), (325.5, green)] {
        scene.push(
            "dropout",
            umbra::synth::Shape::Box {
                centre: umbra::synth::V3::new(x_of(u0 + 5.0), 0.0, z - 0.002),
                half: umbra::synth::V3::new(5.0 * per_px, 0.3, 0.002),
                yaw: 0.0,
            },
            umbra::synth::Material {
                albedo: 0.0,
                specular: false,
                colour,
            },
        );
    }
    for seed in 60..62 {
        let frame = render_frame(&scene, &calib, &SensorModel::kinect(), seed);
        let in_chain = |labels: &[u8], code: u8| {
            (0..PIXELS)
                .filter(|&i| (260..345).contains(&(i % WIDTH)) && labels[i] == code)
                .count()
        };
        assert!(
            in_chain(&frame.ir_labels, OTHER) > 3 * 8 * 100,
            "the dropouts (seed {seed})"
        );
        let out = classify_rgb(&calib, &frame);
        let claimed = out.ir_labels.iter().filter(|&&l| l == DETACHED).count();
        assert!(claimed <= 10, "{claimed} detached pixels (seed {seed})");
    }
}

#[test]
fn black_rod_before_a_turned_board_keeps_its_attached_shadow() {
    // The turned board of the dropout test without its patches, and a black rod 4 cm thick at
    // 1 m before its middle: its shadow on the board, f·b·(1/1 − 1/1.4) = 12.5 px by hand,
    // and the rod (23 px) make one hole on one slanted surface, read as closed on both sides of
    // it now as the dropout's is. The split must still find the shadow. Measured: IR attached
    // F1 0.990 read as open, 0.992 as closed (precision 0.983 → 1.000, recall 0.998 → 0.984).
    let (mut scene, _) = dropout_on_a_turned_board(0.0, 0.0);
    scene.objects.truncate(2);
    push_grey_rod(&mut scene, 0.0, 1.0, 0.02);
    scene.objects[2].material = umbra::synth::Material::black();
    let calib = Calibration::nyu_default();
    let mut c = Confusion::default();
    for seed in 60..62 {
        let frame = render_frame(&scene, &calib, &SensorModel::kinect(), seed);
        let out = classify_rgb(&calib, &frame);
        c.add(&frame.ir_labels, &out.ir_labels);
    }
    at_least(
        &c,
        Some(ATTACHED),
        0.9,
        "IR attached of a black rod before a turned board",
    );
}

#[test]
fn glossy_rod_before_a_turned_board_below_the_wall_is_no_shadow_itself() {
    // The turned board of the dropout test, cut to rows below the middle (y 0.05..0.85 m), and a
    // glossy rod 2 cm thick at 1 m before its middle over every row: no depth on the rod. On the
    // board its shadow, f·b·(1/1 − 1/1.4) ≈ 12 px, and the rod (12 px) make one hole with the
    // board's slanted face on both sides; above the board the rod's shadow falls 29 px away on
    // the wall, so the last pixels measured above the hole are the wall's. Read as Sb's shadow
    // on that wall, partly hidden by Sa, the rod's own pixels were attached, though the slope of
    // the board either side, carried over the hole, lands on the other side. Measured (seeds
    // 60–61): IR attached F1 0.887 → 0.981, OTHER called attached 4 723 → 323 px.
    let (mut scene, _) = dropout_on_a_turned_board(0.0, 0.0);
    scene.objects.truncate(2);
    if let umbra::synth::Shape::Box { centre, half, .. } = &mut scene.objects[1].shape {
        centre.y = 0.45;
        half.y = 0.4;
    }
    push_grey_rod(&mut scene, 0.0, 1.0, 0.01);
    scene.objects[2].material = umbra::synth::Material::glossy([0.9, 0.7, 0.8]);
    let calib = Calibration::nyu_default();
    let mut c = Confusion::default();
    for seed in 60..62 {
        let frame = render_frame(&scene, &calib, &SensorModel::kinect(), seed);
        c.add(&frame.ir_labels, &classify_rgb(&calib, &frame).ir_labels);
    }
    at_least(
        &c,
        Some(ATTACHED),
        0.95,
        "IR attached beside a glossy rod before a turned board",
    );
}

/// A wall at 3 m, a black box (front face at 2 m, x < −0.35 m, below y = 0.0054 m: rows from 240
/// down) running off the image's left border, and a 2 cm grey rod 60 cm long, its axis at
/// (`x`, `y`, `z`), standing before it.
fn black_box_at_the_left_border_behind_a_rod_at(x: f64, y: f64, z: f64) -> Scene {
    let mut scene = Scene::rod_before_wall(0.0, 1.0, 0.01, 3.0);
    scene.objects.pop();
    push_black_box(
        &mut scene,
        "box",
        [-0.925, 0.7527, 2.05],
        [0.575, 0.7473, 0.05],
    );
    scene.push(
        "rod",
        umbra::synth::Shape::Cylinder {
            centre: umbra::synth::V3::new(x, y, z),
            axis: umbra::synth::V3::new(0.0, 1.0, 0.0),
            radius: 0.01,
            half_len: 0.3,
        },
        umbra::synth::Material::matte([0.6, 0.6, 0.65]),
    );
    scene
}

#[test]
fn black_box_at_the_left_border_behind_a_rod_is_no_shadow_of_it() {
    // A black box (front face at 2 m, x < −0.35 m, below y = 0.0054 m: rows from 240 down)
    // before a wall at 3 m, and a 2 cm grey rod at 1.2 m standing on it from row 251 down, its
    // left edge at x = −0.5994 m: column cx + fx·(−0.5994/1.2) = 22.0. Left of the rod, the box
    // runs off the image: a hole from the border to column 22, as wide as the rod's attached
    // shadow on the wall seen above it would be, f·b·(1/1.2 − 1/3) = 21.8 px. But the box
    // returns no depth, lit or not: OTHER. The RGB camera sees the black box there, and right of
    // the rod, not the wall and not the rod.
    // (The colour split reads no row without one below it: the last is left out.)
    assert_left_border_box_is_no_shadow((-0.5894, 0.36, 1.2), 20, 260..HEIGHT - 1);
}

#[test]
fn narrow_hole_at_the_left_border_beside_a_near_rod_is_no_shadow_of_it() {
    // The black box above, and a 2 cm grey rod nearer, at 0.8 m, its left edge at
    // x = −0.4161 m: column cx + fx·(−0.4161/0.8) = 10.0. The hole left of it, 10 px, fits the
    // rod's attached shadow on the wall seen above it (f·b·(1/0.8 − 1/3) = 40.0 px, cut by the
    // border); it is the black box: OTHER. The RGB camera, a third of the way to the projector,
    // sees the rod moved left by a third of its shift (over 10 px), right over the hole; left of
    // the IR image's edge it sees the box. Measured: depth alone once called all of 199 rows
    // attached, and so did colour while only the RGB camera's view of the hole itself (the
    // rod) was read.
    assert_left_border_box_is_no_shadow((-0.4061, 0.34, 0.8), 8, 280..HEIGHT - 1);
}

/// The scene of [`black_box_at_the_left_border_behind_a_rod_at`] with the rod's axis at `rod`:
/// in every row of `rows` its first `cols` columns are OTHER by the scene and none is attached,
/// with colour or by depth alone. (Depth alone once called most of those rows attached: the
/// wall measured above the box gave the hole a background. The rows read lie 20 or more below
/// the box's top, under its region without depth, which is no shadow's background.)
fn assert_left_border_box_is_no_shadow(
    (x, y, z): (f64, f64, f64),
    cols: usize,
    rows: std::ops::Range<usize>,
) {
    let calib = Calibration::nyu_default();
    let scene = black_box_at_the_left_border_behind_a_rod_at(x, y, z);
    let frame = render_frame(&scene, &calib, &SensorModel::ideal(), 7);
    let depth_only = classify(&calib, &frame);
    let out = classify_rgb(&calib, &frame);
    let left = |labels: &[u8], v: usize, code: u8| {
        (0..cols).filter(|&u| labels[v * WIDTH + u] == code).count()
    };
    for v in rows {
        assert_eq!(left(&frame.ir_labels, v, OTHER), cols, "row {v}: the scene");
        assert_eq!(left(&out.ir_labels, v, ATTACHED), 0, "row {v}: with colour");
        assert_eq!(
            left(&depth_only.ir_labels, v, ATTACHED),
            0,
            "row {v}: by depth alone"
        );
    }
}

#[test]
fn black_rod_without_depth_still_casts_a_detached_shadow() {
    // The same rod geometry, but black: the sensor measures nothing on it, so its hole and its
    // shadow are two holes on the wall. Hand geometry: the 3 cm rod at 1.2 m spans
    // 0.03·f/1.2 = 14.6 px, its shadow lies w = f·b·(1/1.2 − 1/3) = 21.8 px further left, so a
    // 7 px lit gap separates them (detached). Scored against the simulator's exact labels with
    // the noisy Kinect sensor model.
    let (ir, rgb) = black_rod_scores((0.1, 1.2, 0.015), 40..43, classify);
    at_least(&ir, Some(DETACHED), 0.90, "IR detached of a black rod");
    at_least(&rgb, Some(DETACHED), 0.85, "RGB detached of a black rod");
    // Its depth, implied by the shadow's shift, places it in the RGB view, so the background it
    // hides from the IR camera shows up as alignment shadow right of it: f_rgb·0.025·(1/1.2 −
    // 1/3) = 6.5 px per row.
    at_least(
        &rgb,
        Some(ALIGNMENT),
        0.75,
        "RGB alignment beside a black rod",
    );
    let any = ir.any_shadow();
    assert!(any.precision.unwrap() >= 0.98, "IR any shadow {any:?}");
}

#[test]
fn black_rod_keeps_its_detached_shadow_where_the_lit_strip_after_it_closes() {
    // The black rod of `black_rod_without_depth_still_casts_a_detached_shadow` (x = 0.1 m at
    // 1.2 m, 14.6 px wide, its shadow 21.8 px to the left), and right of it a black board at 2 m
    // whose attached shadow on the wall, f·b·(1/2 − 1/3) = 7.3 px wide, starts 2.5 px right of
    // the rod's right edge: a lit strip so narrow that the widening of that shadow's left end
    // closes it in some rows, where the rod's hole runs on into the board's. The rows above and
    // below that confirm a depthless occluder's pair then show the same shadow and the rod's
    // left edge in place, but a hole past its right edge (j29 s011: a glossy rod beside a black
    // cylinder). The strip closes in 266 rows of three frames. Measured: IR detached F1 0.797 →
    // 0.944 (recall 0.663 → 0.894, precision 1.000).
    let calib = Calibration::nyu_default();
    let (fx, cx) = (calib.depth.fx, calib.depth.cx);
    let mut scene = Scene::rod_before_wall(0.1, 1.2, 0.015, 3.0);
    scene.objects[1].material = umbra::synth::Material::black();
    let rod_right = cx + fx * 0.115 / 1.2;
    let board_left = rod_right + 2.5 + calib.fb() * (1.0 / 2.0 - 1.0 / 3.0);
    let x_board = (board_left - cx) / fx * 2.0;
    push_box(
        &mut scene,
        "board",
        [x_board + 0.2, 0.0, 2.005],
        [0.2, 3.0, 0.005],
        umbra::synth::Material::black(),
    );
    let mut ir = Confusion::default();
    let mut closed = 0;
    for seed in 40..43 {
        let frame = render_frame(&scene, &calib, &SensorModel::kinect(), seed);
        let out = classify(&calib, &frame);
        ir.add(&frame.ir_labels, &out.ir_labels);
        // Rows where no lit pixel separates the rod's hole from the board's shadow.
        let strip = rod_right.floor() as usize - 1..(rod_right + 4.0) as usize;
        closed += (0..HEIGHT)
            .filter(|&v| strip.clone().all(|u| frame.raw[v * WIDTH + u] == 2047))
            .count();
    }
    assert!(closed > 100, "the lit strip closes in {closed} rows only");
    at_least(&ir, Some(DETACHED), 0.9, "IR detached of the rod");
}

/// A black rod of `radius` at x = 0.1 m, 1.2 m, before a wall at 3 m with a black poster at
/// x = 0.046..0.180 m (IR columns 322.0..348.0) that swallows the rod's shadow: RGB-view
/// confusions from depth alone and with the RGB image (seeds 40..43).
fn rod_over_poster(radius: f64) -> (Confusion, Confusion) {
    let mut scene = Scene::rod_before_wall(0.1, 1.2, radius, 3.0);
    scene.objects[1].material = umbra::synth::Material::black();
    push_black_box(
        &mut scene,
        "poster",
        [0.113, 0.0, 2.995],
        [0.067, 3.0, 0.004],
    );
    let (depth_only, with_rgb) = with_and_without_colour(&scene, 40..43, true, |frame| {
        let row = &frame.ir_labels[240 * WIDTH..241 * WIDTH];
        assert!(
            !row.contains(&DETACHED) && row[325..348].iter().all(|&l| l == OTHER),
            "the poster swallows the shadow"
        );
    });
    let r = depth_only.class(ALIGNMENT).recall.unwrap_or(0.0);
    assert!(
        r < 0.2,
        "depth alone places the rod: alignment recall {r:.3}"
    );
    (depth_only, with_rgb)
}

#[test]
fn thin_black_rod_whose_shadow_falls_on_a_black_poster_keeps_its_alignment_strip() {
    // The rod (IR columns 313.04 + 582.62·0.1/1.2 = 361.6 ± 7.3), its shadow 21.8 px left of it
    // (332.5..347.1) on the poster, whose hole swallows it: no shadow to pair the rod's 14.6 px
    // hole with, and no depth for the rod from it. The RGB camera still sees the rod's right edge
    // f_rgb·0.025·(1/1.2 − 1/3) = 6.5 px left of where the wall behind it would put it, and the
    // wall in that strip, which the IR camera cannot see (alignment, by the simulator).
    // Measured: alignment F1 0.921 (precision 1.000), 0 before narrow holes were read.
    let (_, with_rgb) = rod_over_poster(0.015);
    at_least(
        &with_rgb,
        Some(ALIGNMENT),
        0.88,
        "RGB alignment beside a black rod over a black poster",
    );
    let any = with_rgb.any_shadow();
    assert!(any.precision.unwrap() >= 0.95, "RGB any shadow {any:?}");
}

#[test]
fn black_rod_of_8_px_whose_shadow_falls_on_a_black_poster_keeps_its_alignment_strip() {
    // The same with a rod of radius 9 mm: 582.62·0.018/1.2 = 8.7 px wide (357.2..366.0), under
    // the 10 px the colour split needs of a hole it splits, but a rod's right edge is read from
    // 8 px. Measured: alignment F1 0.000 → 0.831 (precision 1.000, recall 0.711).
    let (_, with_rgb) = rod_over_poster(0.009);
    at_least(
        &with_rgb,
        Some(ALIGNMENT),
        0.80,
        "RGB alignment beside a thin black rod over a black poster",
    );
    let any = with_rgb.any_shadow();
    assert!(any.precision.unwrap() >= 0.95, "RGB any shadow {any:?}");
}

#[test]
fn box_shadow_beside_a_black_poster_is_attached_where_the_rgb_camera_sees_the_wall() {
    // The box's attached shadow, columns 167.4..196.5 (29.1 px), rows ±146, as above. A black
    // poster on the wall at x = −0.90..−0.73 m (columns 313.04 − 582.62·0.815/3 ± 582.62·0.085/3
    // = 138.3..171.3), rows ±97, reaches into it: poster and shadow make one hole of 58 px, too
    // wide for eq. (3), OTHER by depth alone. The RGB camera sees the wall over the shadow right
    // of the poster, [171.3, 196.5), up to where the box hides it (its edge f_rgb·0.025·(1/1 −
    // 1/3) = 8.6 px further left in the RGB image), and the black poster left of it.
    // Measured: IR attached recall 0.378 → 0.946 (the shadow's rows outside the poster's and
    // inside), precision 1.000 both, F1 0.549 → 0.972.
    let (depth_only, with_rgb) = box_beside_poster(umbra::synth::Material::black());
    let before = depth_only.class(ATTACHED).recall.unwrap_or(0.0);
    let after = with_rgb.class(ATTACHED).recall.unwrap_or(0.0);
    assert!(before < 0.5, "depth alone: attached recall {before:.3}");
    assert!(after >= 0.9, "attached recall {before:.3} -> {after:.3}");
    at_least(
        &with_rgb,
        Some(ATTACHED),
        0.95,
        "attached beside a black poster",
    );
    // A glossy poster of the wall's own colour: the RGB camera cannot tell where the shadow
    // starts, and nothing of the poster may become attached.
    let (depth_only, with_rgb) =
        box_beside_poster(umbra::synth::Material::glossy([0.8, 0.78, 0.7]));
    let (before, after) = (depth_only.class(ATTACHED), with_rgb.class(ATTACHED));
    assert!(after.precision.unwrap() >= 0.99, "{after:?}");
    assert!(
        after.recall.unwrap() <= before.recall.unwrap() + 0.01,
        "{before:?} -> {after:?}"
    );
}

#[test]
fn sphere_shadow_beside_a_black_poster_is_attached_where_the_rgb_camera_sees_the_wall() {
    // A sphere of radius 0.3 m centred 1 m away (x = 0) before a wall at 3 m: its limb, where
    // the IR camera's ray grazes it (asin 0.3 = 17.5° off the axis, 0.91 m away), at column
    // 313.04 − 582.62·tan 17.5° = 129.8 (the simulator's sensor measures from 132: the rays
    // graze it before); its attached shadow, f·b·(1/0.91 − 1/3) = 33.5 px at the limb's depth,
    // from column 96. A black poster on the wall from x = −1.30 to −1.07 m (columns 60..105),
    // rows ±97, covers the shadow's left end: one hole from the poster to the limb, too wide
    // for eq. (3). The RGB camera, nearer the projector, sees the sphere's outline further left
    // than the limb's depth puts it (the sphere's nearer middle hides more of the wall), so the
    // wall shows only some columns further left, then the poster.
    // Measured: in the poster's rows, attached recall 0.901 → 0.967 (none wrong) once those
    // columns of outline are skipped.
    let mut scene = before_a_pale_wall("sphere beside a black poster");
    scene.push(
        "sphere",
        umbra::synth::Shape::Sphere {
            centre: umbra::synth::V3::new(0.0, 0.0, 1.0),
            radius: 0.3,
        },
        umbra::synth::Material::matte([0.3, 0.5, 0.8]),
    );
    push_black_box(
        &mut scene,
        "poster",
        [-1.187, 0.0, 2.995],
        [0.116, 0.5, 0.004],
    );
    let calib = Calibration::nyu_default();
    // The shadow's pixels in the poster's rows (±97 around the centre row 238), and how many of
    // them the classifier calls attached.
    let (mut shadow, mut found, mut wrong) = (0, 0, 0);
    for seed in 60..63 {
        let frame = render_frame(&scene, &calib, &SensorModel::kinect(), seed);
        let row = &frame.ir_labels[240 * WIDTH..241 * WIDTH];
        assert!(
            row[62..103].iter().all(|&l| l == OTHER)
                && (107..129).all(|u| row[u] == ATTACHED)
                && (134..140).all(|u| row[u] == VALID),
            "poster, shadow, sphere: {:?}",
            &row[50..150]
        );
        let out = classify_rgb(&calib, &frame);
        for v in 150..326 {
            for u in 50..150 {
                let i = v * WIDTH + u;
                let truth = frame.ir_labels[i] == ATTACHED;
                let said = out.ir_labels[i] == ATTACHED;
                shadow += usize::from(truth);
                found += usize::from(truth && said);
                wrong += usize::from(!truth && said);
            }
        }
    }
    let recall = found as f64 / shadow as f64;
    assert!(
        recall >= 0.95 && wrong * 100 <= found,
        "attached in the poster's rows: {found} of {shadow} ({recall:.3}), {wrong} wrong"
    );
}

/// The box at 1 m before a wall at 3 m, and a poster of `material` on the wall at x = −0.90..
/// −0.73 m that reaches into the box's attached shadow (seeds 60..63): IR-view confusions from
/// depth alone and with the RGB image.
fn box_beside_poster(material: umbra::synth::Material) -> (Confusion, Confusion) {
    let mut scene = Scene::box_before_wall(1.0, 3.0);
    scene.push(
        "poster",
        umbra::synth::Shape::Box {
            centre: umbra::synth::V3::new(-0.815, 0.0, 2.995),
            half: umbra::synth::V3::new(0.085, 0.5, 0.004),
            yaw: 0.0,
        },
        material,
    );
    with_and_without_colour(&scene, 60..63, false, |frame| {
        let row = &frame.ir_labels[240 * WIDTH..241 * WIDTH];
        assert!(
            row[140..170].iter().all(|&l| l == OTHER)
                && row[173..196].iter().all(|&l| l == ATTACHED),
            "poster then shadow: {:?}",
            &row[130..200]
        );
    })
}

#[test]
fn black_poster_inside_a_box_shadow_is_other_where_the_rgb_camera_sees_it() {
    // The box's left edge (x = −0.2 m at 1 m) at IR column 313.04 − 582.62·0.2 = 196.5, the wall
    // at 3 m: an attached shadow f·b·(1/1 − 1/3) = 29.1 px wide, columns 167.4..196.5, rows
    // 238.44 ± 0.25·582.69 (±146). A black poster on the wall at x = −0.70..−0.66 m (columns
    // 177.1..184.9), 1 m tall (rows ±97), lies inside it: a hole that would be a hole even if
    // lit, OTHER (SPEC §1), though eq. (3) fits the hole around it. The RGB camera sees the wall
    // up to f_rgb·0.025·(1/1 − 1/3) = 8.6 px short of the box's edge: the poster in full.
    // Measured: attached precision 0.830 → 0.988 with the RGB image (recall 1.000 → 0.970), F1
    // 0.907 → 0.979.
    let mut scene = Scene::box_before_wall(1.0, 3.0);
    push_black_box(
        &mut scene,
        "poster",
        [-0.68, 0.0, 2.995],
        [0.02, 0.5, 0.004],
    );
    let (depth_only, with_rgb) = with_and_without_colour(&scene, 50..53, false, |frame| {
        let row = &frame.ir_labels[240 * WIDTH..241 * WIDTH];
        assert!(
            row[179..184].iter().all(|&l| l == OTHER)
                && row[170..175].iter().all(|&l| l == ATTACHED)
                && row[188..195].iter().all(|&l| l == ATTACHED),
            "the poster lies inside the shadow: {:?}",
            &row[165..200]
        );
    });
    let p = depth_only.class(ATTACHED).precision.unwrap_or(1.0);
    assert!(p < 0.9, "depth alone calls the poster attached: P {p:.3}");
    let p = with_rgb.class(ATTACHED).precision.unwrap_or(0.0);
    assert!(p >= 0.97, "attached precision with the RGB image {p:.3}");
    at_least(
        &with_rgb,
        Some(ATTACHED),
        0.95,
        "attached around a black poster",
    );
}

#[test]
fn rod_shadow_and_lit_gap_on_a_black_poster_in_a_dim_image_are_other() {
    // A grey rod of radius 2 cm at x = 0.1 m, 1 m away (IR columns 313.04 + 582.62·0.1 = 371.3
    // ± 11.7: 359.6..383.0) before a pale wall at 3 m: its shadow f·b·(1/1 − 1/3) = 29.1 px
    // left, 330.5..353.9, a lit gap of 5.7 px before the rod. A black poster on the wall from
    // x = 0.095 m (column 331.5) to behind the rod, rows ±116, swallows shadow and gap: one hole
    // from the shadow's left end to the rod, the layout and width of a detached shadow whose
    // gap closed. It would be a hole even if lit: OTHER (SPEC §1). The RGB image at 30 %
    // exposure (a dim room: the wall reads about 210, R + G + B) shows the poster black over
    // the hole past the rod, where the wall beside it reads three times as bright. Measured: IR
    // detached precision 0.507 → 0.975 (recall 1.000 both), OTHER recall 0.024 → 0.974 (depth
    // alone now calls the poster's part attached, as it touches the rod).
    let calib = Calibration::nyu_default();
    let mut scene = Scene::rod_before_wall(0.1, 1.0, 0.02, 3.0);
    push_black_box(&mut scene, "poster", [0.2, 0.0, 2.995], [0.105, 0.6, 0.004]);
    let dim = SensorModel {
        rgb_gain: 0.3,
        ..SensorModel::kinect()
    };
    let (mut depth_only, mut with_rgb) = (Confusion::default(), Confusion::default());
    for seed in 70..73 {
        let frame = render_frame(&scene, &calib, &dim, seed);
        let row = &frame.ir_labels[240 * WIDTH..241 * WIDTH];
        assert!(
            row[333..358].iter().all(|&l| l == OTHER),
            "the poster swallows shadow and gap: {:?}",
            &row[325..362]
        );
        let wall: u32 = frame.rgb[3 * (240 * WIDTH + 200)..3 * (240 * WIDTH + 220)]
            .iter()
            .map(|&c| u32::from(c))
            .sum();
        assert!(
            (150..240).contains(&(wall / 20)),
            "a dim wall: {}",
            wall / 20
        );
        depth_only.add(&frame.ir_labels, &classify(&calib, &frame).ir_labels);
        with_rgb.add(&frame.ir_labels, &classify_rgb(&calib, &frame).ir_labels);
    }
    // Depth alone reads the poster's hole as the rod's shadow (attached, touching the rod).
    let (before, after) = (depth_only.class(OTHER), with_rgb.class(DETACHED));
    assert!(before.recall.unwrap() < 0.1, "depth alone: {before:?}");
    assert!(after.precision.unwrap() >= 0.95, "{before:?} -> {after:?}");
    assert!(
        after.recall.unwrap() >= 0.99,
        "the shadow off the poster: {after:?}"
    );
    at_least(&with_rgb, Some(OTHER), 0.95, "OTHER on a black poster, dim");
}

#[test]
fn glossy_rod_in_a_box_shadow_keeps_its_detached_shadow() {
    // The hand-computed box (left edge at column 196.5, 1 m, rows ±146) before a wall at 3 m: its
    // attached shadow [167.4, 196.5). A glossy red rod at 0.8 m over [165.5, 188.5) (x = −0.1868
    // m, radius 15.8 mm) covers all but its last 8 px: rod and shadow make one hole of 31 px
    // between wall and box, which eq. (3) for the box fits. The rod's own shadow, 43.7·(1/0.8 −
    // 1/3) = 40.1 px left of it, [125.4, 148.4), lies on the wall past a lit gap of 17 px: an
    // OTHER hole from depth alone. The RGB camera sees the wall over that hole and the rod over
    // the first one's left part: the rod (OTHER), its detached shadow, the box's attached one.
    // Measured over rows 110..370 (shares of the columns): the rod's shadow detached 0.000 →
    // 0.997, the rod attached 1.000 → 0.085, the box's shadow past it attached 0.997 → 0.977.
    let mut scene = Scene::box_before_wall(1.0, 3.0);
    let rod = Scene::rod_before_wall(-0.1868, 0.8, 0.01579, 3.0).objects[1].clone();
    scene.push(
        "rod",
        rod.shape,
        umbra::synth::Material::glossy([0.8, 0.2, 0.2]),
    );
    let calib = Calibration::nyu_default();
    let rows = 110..370;
    let (mut before, mut after) = ((0.0, 0.0, 0.0), (0.0, 0.0, 0.0));
    for seed in 90..93 {
        let frame = render_frame(&scene, &calib, &SensorModel::kinect(), seed);
        let share = |labels: &[u8], cols: std::ops::Range<usize>, code: u8| {
            let n = rows
                .clone()
                .flat_map(|v| cols.clone().map(move |u| v * WIDTH + u))
                .filter(|&i| labels[i] == code)
                .count();
            n as f64 / (rows.len() * cols.len()) as f64
        };
        let truth = &frame.ir_labels;
        assert!(
            share(truth, 128..146, DETACHED) > 0.95
                && share(truth, 168..187, OTHER) > 0.95
                && share(truth, 190..195, ATTACHED) > 0.95,
            "rod shadow, rod, box shadow"
        );
        for (out, tally) in [
            (classify(&calib, &frame), &mut before),
            (classify_rgb(&calib, &frame), &mut after),
        ] {
            let labels = &out.ir_labels;
            tally.0 += share(labels, 128..146, DETACHED) / 3.0;
            tally.1 += share(labels, 168..187, ATTACHED) / 3.0;
            tally.2 += share(labels, 190..195, ATTACHED) / 3.0;
        }
    }
    assert!(before.0 < 0.1, "depth alone pairs nothing: {before:?}");
    assert!(after.0 >= 0.9, "the rod's shadow: {before:?} -> {after:?}");
    assert!(
        after.1 <= 0.1,
        "the rod called attached: {before:?} -> {after:?}"
    );
    assert!(after.2 >= 0.9, "the box's shadow past the rod: {after:?}");
}

/// Pushes onto `scene` an upright black box (a poster, a panel, a strip) named `name`, centred
/// at `centre` with half extents `half` (metres).
fn push_black_box(scene: &mut Scene, name: &'static str, centre: [f64; 3], half: [f64; 3]) {
    push_box(scene, name, centre, half, umbra::synth::Material::black());
}

/// A black box 10 cm deep whose front face, `z` m away, spans IR columns `u0..u1` (NYU
/// defaults), `half_height` m above and below the optical axis.
fn push_black_box_over(scene: &mut Scene, (u0, u1): (f64, f64), z: f64, half_height: f64) {
    let calib = Calibration::nyu_default();
    let x_at = |u: f64| (u - calib.depth.cx) / calib.depth.fx * z;
    let (x0, x1) = (x_at(u0), x_at(u1));
    push_black_box(
        scene,
        "box",
        [(x0 + x1) / 2.0, 0.0, z + 0.05],
        [(x1 - x0) / 2.0, half_height, 0.05],
    );
}

/// Checks that the ideal sensor's rows 200–280 (every 20th) of `scene` hold `width` px of
/// attached shadow, within 1.5: the simulator agrees with the width computed by hand.
fn assert_ideal_shadow_width(scene: &Scene, width: f64) {
    let ideal = render_frame(
        scene,
        &Calibration::nyu_default(),
        &SensorModel::ideal(),
        40,
    );
    for v in (200..280).step_by(20) {
        let row = &ideal.ir_labels[v * WIDTH..(v + 1) * WIDTH];
        let n = row.iter().filter(|&&l| l == ATTACHED).count() as f64;
        assert!(
            (n - width).abs() <= 1.5,
            "row {v}: {n} px of shadow, {width:.1} by hand"
        );
    }
}

/// The IR columns the simulator labels attached in row 240 of `frame`.
fn attached_in_row_240(frame: &SynthFrame) -> Vec<usize> {
    let row = &frame.ir_labels[240 * WIDTH..241 * WIDTH];
    (0..WIDTH).filter(|&u| row[u] == ATTACHED).collect()
}

/// The Kinect sensor with the RGB camera's noise at σ = 12 a channel (a dim room, the gain
/// turned up).
fn noisy_colour() -> SensorModel {
    SensorModel {
        rgb_noise_sigma: 12.0,
        ..SensorModel::kinect()
    }
}

/// A scene of `description` holding only a pale matte wall at 3 m, for the objects to stand
/// before.
fn before_a_pale_wall(description: &str) -> Scene {
    let mut scene = Scene::new(description);
    scene.push(
        "wall",
        umbra::synth::scene::wall(3.0),
        umbra::synth::Material::matte([0.8, 0.78, 0.7]),
    );
    scene
}

/// An upright box of `material` (centre and half-extents in metres, not turned).
fn push_box(
    scene: &mut Scene,
    name: &'static str,
    centre: [f64; 3],
    half: [f64; 3],
    material: umbra::synth::Material,
) {
    scene.push(
        name,
        umbra::synth::Shape::Box {
            centre: umbra::synth::V3::from(centre),
            half: umbra::synth::V3::from(half),
            yaw: 0.0,
        },
        material,
    );
}

/// Papers a wall whose face lies at `z` m (boxes 10 cm deep behind it) in vertical bands
/// `width` m wide: band `k` of `bands` starts at x = `edge + k·width`, in the colour `colour(k)`.
fn push_bands(
    scene: &mut Scene,
    (edge, width, z): (f64, f64, f64),
    bands: std::ops::Range<i32>,
    colour: impl Fn(i32) -> [f64; 3],
) {
    for k in bands {
        push_box(
            scene,
            "wall",
            [edge + width * (f64::from(k) + 0.5), 0.0, z + 0.05],
            [width / 2.0, 3.0, 0.05],
            umbra::synth::Material::matte(colour(k)),
        );
    }
}

/// [`push_bands`] for a wall at `z` in bands `band_px` IR columns wide, band 0 starting at IR
/// column `edge_u`, cream and blue by turns (the even bands cream where `cream_even`, else blue).
fn push_cream_and_blue_bands(
    scene: &mut Scene,
    calib: &Calibration,
    (edge_u, band_px, z): (f64, f64, f64),
    bands: std::ops::Range<i32>,
    cream_even: bool,
) {
    let x_at = |u: f64| (u - calib.depth.cx) / calib.depth.fx * z;
    let (cream, blue) = ([0.8, 0.78, 0.7], [0.35, 0.5, 0.7]);
    push_bands(
        scene,
        (x_at(edge_u), x_at(band_px) - x_at(0.0), z),
        bands,
        |k| {
            if (k % 2 == 0) == cream_even {
                cream
            } else {
                blue
            }
        },
    );
}

/// `scene` rendered with the noisy Kinect sensor for each seed (each frame first handed to
/// `truth`, which checks the simulator made the case), scored from depth alone and with the RGB
/// image: confusions of the RGB view with `rgb`, else of the IR view.
fn with_and_without_colour(
    scene: &Scene,
    seeds: std::ops::Range<u64>,
    rgb: bool,
    truth: impl Fn(&SynthFrame),
) -> (Confusion, Confusion) {
    with_and_without_colour_by(scene, &SensorModel::kinect(), seeds, rgb, truth)
}

/// [`with_and_without_colour`] with the sensor `sensor`.
fn with_and_without_colour_by(
    scene: &Scene,
    sensor: &SensorModel,
    seeds: std::ops::Range<u64>,
    rgb: bool,
    truth: impl Fn(&SynthFrame),
) -> (Confusion, Confusion) {
    let calib = Calibration::nyu_default();
    let (mut depth_only, mut with_rgb) = (Confusion::default(), Confusion::default());
    for seed in seeds {
        let frame = render_frame(scene, &calib, sensor, seed);
        truth(&frame);
        let (a, b) = (classify(&calib, &frame), classify_rgb(&calib, &frame));
        if rgb {
            depth_only.add(&frame.rgb_labels, &a.rgb_labels);
            with_rgb.add(&frame.rgb_labels, &b.rgb_labels);
        } else {
            depth_only.add(&frame.ir_labels, &a.ir_labels);
            with_rgb.add(&frame.ir_labels, &b.ir_labels);
        }
    }
    (depth_only, with_rgb)
}

/// A black rod at `(x, z, radius)` (metres) before a wall at 3 m, rendered with the noisy Kinect
/// sensor for each seed and labelled by `label`: IR- and RGB-view confusions against the
/// simulator.
fn black_rod_scores(
    (x, z, radius): (f64, f64, f64),
    seeds: std::ops::Range<u64>,
    label: fn(&Calibration, &SynthFrame) -> Classified,
) -> (Confusion, Confusion) {
    let calib = Calibration::nyu_default();
    let mut scene = Scene::rod_before_wall(x, z, radius, 3.0);
    scene.objects[1].material = umbra::synth::Material::black();
    let (mut ir, mut rgb) = (Confusion::default(), Confusion::default());
    for seed in seeds {
        let frame = render_frame(&scene, &calib, &SensorModel::kinect(), seed);
        assert!(
            frame.ir_labels.contains(&DETACHED),
            "the simulator casts one"
        );
        let out = label(&calib, &frame);
        ir.add(&frame.ir_labels, &out.ir_labels);
        rgb.add(&frame.rgb_labels, &out.rgb_labels);
    }
    (ir, rgb)
}

#[test]
fn two_black_rods_whose_holes_chain_are_told_apart_by_colour() {
    // Two black rods, 7 px wide, at 1 m before a wall at 3 m, 12 px apart (u ≈ 313 and 325).
    // Each shadow lies f·b·(1/1 − 1/3) = 29.1 px left of its rod: a row reads shadow A
    // (≈ 284), shadow B (≈ 296), rod A, rod B, four like holes 12 px apart, and depth alone
    // cannot say which are shadows (A's shadow pairs with B's as well as with rod A). The RGB
    // camera sees wall in the shadows and black on the rods.
    let calib = Calibration::nyu_default();
    let mut scene = Scene::rod_before_wall(0.0, 1.0, 0.006, 3.0);
    scene.objects[1].material = umbra::synth::Material::black();
    let rod_b = Scene::rod_before_wall(16.0 / calib.depth.fx, 1.0, 0.006, 3.0).objects[1].clone();
    scene.push("rod", rod_b.shape, umbra::synth::Material::black());
    let (mut depth_only, mut with_rgb) = (Confusion::default(), Confusion::default());
    for seed in 0..3 {
        let frame = render_frame(&scene, &calib, &SensorModel::kinect(), 60 + seed);
        let truth = (0..WIDTH).filter(|&u| frame.ir_labels[240 * WIDTH + u] == DETACHED);
        assert!(truth.count() >= 12, "the simulator casts both shadows");
        depth_only.add(&frame.ir_labels, &classify(&calib, &frame).ir_labels);
        with_rgb.add(&frame.ir_labels, &classify_rgb(&calib, &frame).ir_labels);
    }
    let r = depth_only.class(DETACHED).recall.unwrap_or(0.0);
    assert!(r < 0.5, "depth alone pairs them: recall {r:.3}");
    at_least(
        &with_rgb,
        Some(DETACHED),
        0.9,
        "IR detached of two chained black rods",
    );
    let any = with_rgb.any_shadow();
    assert!(any.precision.unwrap() >= 0.98, "IR any shadow {any:?}");
}

#[test]
fn two_glossy_rods_whose_holes_chain_are_told_apart_by_colour_in_a_dim_image() {
    // The two rods above, glossy brick-red instead of black, the RGB image at 45 % exposure
    // (about as dark as the real NYU frame): the rods differ from the wall by less than the bright
    // room's colour steps, which paired nothing (detached F1 0.000); the steps follow the wall's
    // brightness.
    let calib = Calibration::nyu_default();
    let red = umbra::synth::Material::glossy([0.6, 0.3, 0.25]);
    let mut scene = Scene::rod_before_wall(0.0, 1.0, 0.006, 3.0);
    scene.objects[1].material = red;
    let rod_b = Scene::rod_before_wall(16.0 / calib.depth.fx, 1.0, 0.006, 3.0).objects[1].clone();
    scene.push("rod", rod_b.shape, red);
    let dim = SensorModel {
        rgb_gain: 0.45,
        ..SensorModel::kinect()
    };
    let mut with_rgb = Confusion::default();
    for seed in 0..3 {
        let frame = render_frame(&scene, &calib, &dim, 60 + seed);
        with_rgb.add(&frame.ir_labels, &classify_rgb(&calib, &frame).ir_labels);
    }
    at_least(
        &with_rgb,
        Some(DETACHED),
        0.9,
        "IR detached of two chained glossy rods, dim",
    );
    let any = with_rgb.any_shadow();
    assert!(any.precision.unwrap() >= 0.98, "IR any shadow {any:?}");
}

#[test]
fn alignment_strip_starts_at_the_colour_edge_of_the_box() {
    // The hand-computed box, through the Kinect sensor model (noise, mixed pixels at edges). Its
    // right front edge (x = 0.2 m, z = 1 m) is at f_rgb·(0.2 − 0.025)/1 + cx_rgb = 416.4 in the
    // RGB image, so the alignment strip starts at column 417 in every row. Depth places that
    // edge only to within the IR pixel it fell in; the colour edge fixes it.
    let s = box_strip_starts(None, 80, |rgb| rgb.to_vec());
    assert_eq!(s.first, 417);
    assert!(s.rows > 300, "{} rows cross the box", s.rows);
    assert!(100 * s.exact_rgb >= 97 * s.rows, "{s:?}");
}

#[test]
fn alignment_strip_starts_at_the_colour_edge_of_the_box_through_a_soft_lens() {
    // The test above with the RGB image blurred by a [1 2 1]/4 kernel each way, about the
    // softness of a demosaiced Bayer camera: the box's last RGB pixel is a quarter wall colour,
    // the wall's first a quarter box colour. Each still sides with the colour it is nearer, so
    // the colour edge still places the strip better than depth alone.
    let s = box_strip_starts(None, 80, umbra::synth::soften);
    assert!(s.rows > 300, "{} rows cross the box", s.rows);
    // Measured: 778 of 780 (depth alone: 746).
    assert!(
        100 * s.exact_rgb >= 97 * s.rows && s.exact_rgb > s.exact_depth,
        "{s:?}"
    );
}

/// Where the alignment strips of [`box_strip_starts`] start.
#[derive(Debug)]
struct StripStarts {
    /// The column where the simulator's strip starts (in the rows that cross the box).
    first: usize,
    /// The rows that start there.
    rows: usize,
    /// How many of them the labels classified with the RGB image, and without it, start there.
    exact_rgb: usize,
    exact_depth: usize,
    /// The median colour distance across the box's edge (5 pixels in against 2 past it).
    median_contrast: u32,
}

/// The hand-computed box (of `material`, if given) through the Kinect sensor model, seeds
/// `seed0..seed0 + 3`, its RGB image passed through `camera`: where the alignment strips start.
fn box_strip_starts(
    material: Option<umbra::synth::Material>,
    seed0: u64,
    camera: impl Fn(&[u8]) -> Vec<u8>,
) -> StripStarts {
    let calib = Calibration::nyu_default();
    let first = (calib.rgb.fx * 0.175 + calib.rgb.cx).ceil() as usize;
    let (mut rows, mut exact_rgb, mut exact_depth, mut contrast) = (0, 0, 0, Vec::new());
    for seed in seed0..seed0 + 3 {
        let mut scene = Scene::box_before_wall(1.0, 3.0);
        if let Some(material) = material {
            scene.objects[1].material = material;
        }
        let mut frame = render_frame(&scene, &calib, &SensorModel::kinect(), seed);
        frame.rgb = camera(&frame.rgb);
        let (depth_only, with_rgb) = (classify(&calib, &frame), classify_rgb(&calib, &frame));
        let start =
            |labels: &[u8], v: usize| (380..WIDTH).find(|&x| labels[v * WIDTH + x] == ALIGNMENT);
        for v in 0..HEIGHT {
            if start(&frame.rgb_labels, v) != Some(first) {
                continue; // rows above and below the box
            }
            rows += 1;
            contrast.push(rgb_distance(
                &frame.rgb,
                v * WIDTH + first - 5,
                v * WIDTH + first + 2,
            ));
            exact_rgb += usize::from(start(&with_rgb.rgb_labels, v) == Some(first));
            exact_depth += usize::from(start(&depth_only.rgb_labels, v) == Some(first));
        }
    }
    contrast.sort_unstable();
    StripStarts {
        first,
        rows,
        exact_rgb,
        exact_depth,
        median_contrast: contrast.get(contrast.len() / 2).copied().unwrap_or(0),
    }
}

/// The colour distance (sum of |ΔR|+|ΔG|+|ΔB|) between pixels `a` and `b` of an RGB8 image.
fn rgb_distance(rgb: &[u8], a: usize, b: usize) -> u32 {
    rgb[3 * a..3 * a + 3]
        .iter()
        .zip(&rgb[3 * b..3 * b + 3])
        .map(|(&p, &q)| u32::from(p.abs_diff(q)))
        .sum()
}

/// The box before a wall, moved right in 17 steps of 0.1 mm (a sixth of an IR pixel at 1 m) so
/// its edges fall at every sub-pixel position, rendered with `sensor`: over the rows where
/// `read` finds something in the ground truth, how many rows it finds the same in the labels
/// classified with the RGB image, and without it.
fn box_at_sub_pixel_offsets<T: PartialEq>(
    sensor: SensorModel,
    seed: u64,
    read: impl Fn(&[u8], usize) -> Option<T>,
) -> (usize, usize, usize) {
    let calib = Calibration::nyu_default();
    let (mut rows, mut exact_rgb, mut exact_depth) = (0, 0, 0);
    for k in 0..17 {
        let mut scene = Scene::box_before_wall(1.0, 3.0);
        if let umbra::synth::Shape::Box { centre, .. } = &mut scene.objects[1].shape {
            centre.x += 1e-4 * k as f64;
        }
        let frame = render_frame(&scene, &calib, &sensor, seed + k);
        let (depth_only, with_rgb) = (classify(&calib, &frame), classify_rgb(&calib, &frame));
        for v in 0..HEIGHT {
            let truth = read(&frame.rgb_labels, v);
            if truth.is_none() {
                continue; // rows above and below the box
            }
            rows += 1;
            exact_rgb += usize::from(read(&with_rgb.rgb_labels, v) == truth);
            exact_depth += usize::from(read(&depth_only.rgb_labels, v) == truth);
        }
    }
    (rows, exact_rgb, exact_depth)
}

#[test]
fn alignment_strip_ends_where_the_ir_camera_sees_past_the_box() {
    // The box's right front edge falls at 17 sub-pixel positions of its last IR pixel (the box
    // moved right in steps of 0.1 mm, a sixth of an IR pixel at 1 m). The strip ends where the
    // IR camera's ray past that edge meets the wall, f_rgb·0.025·(1/1 − 1/3) = 8.6 RGB px right of
    // its start. Depth alone knows the edge only to within its IR pixel, so it misplaces that
    // end in about a quarter of the rows; the colour edge says where inside the pixel the box
    // ends, and so where the strip does.
    let strip = |labels: &[u8], v: usize| {
        let row = &labels[v * WIDTH..(v + 1) * WIDTH];
        let start = (380..WIDTH).find(|&x| row[x] == ALIGNMENT)?;
        Some((start, (start..WIDTH).find(|&x| row[x] != ALIGNMENT)?))
    };
    let (rows, exact_rgb, exact_depth) =
        box_at_sub_pixel_offsets(SensorModel::kinect(), 200, strip);
    assert!(rows > 17 * 250, "{rows} rows cross the box");
    // Measured: 87.6 % (depth alone 28.8 %; the colour edge fixing only the start, 51.6 %).
    assert!(
        100 * exact_rgb >= 85 * rows,
        "{exact_rgb} of {rows} strips exact at both ends (depth alone: {exact_depth})"
    );
}

#[test]
fn alignment_strip_ends_where_the_ir_camera_sees_past_a_slanted_rod() {
    // A rod (r = 5 cm) at 1.5 m before the wall at 3 m, tilted 20° from the vertical: its edge
    // crosses a pixel column every 2.7 rows. Each row's strip starts at the rod's colour edge and
    // ends f_rgb·0.025·(1/1.5 − 1/3) = 4.3 px further right, where the IR camera's ray past the
    // edge meets the wall; where inside its IR pixel the edge lies, which the far end depends
    // on, one row's colour and depth tell only to within most of a pixel. The rows around tell
    // it better: the colour edge steps from row to row along the slant, and a line through the
    // steps places it. Measured: the far end exact in 419 of 428 rows (329 from each row
    // alone), the start in 427.
    let calib = Calibration::nyu_default();
    let tilt = 20f64.to_radians();
    let scene = cylinder_at_1_5_m_before_a_wall(
        (tilt.sin(), tilt.cos()),
        (0.05, 3.0),
        umbra::synth::Material::matte([0.7, 0.2, 0.15]),
    );
    let frame = render_frame(&scene, &calib, &SensorModel::ideal(), 3);
    let out = classify_rgb(&calib, &frame);
    let strip = |labels: &[u8], v: usize| {
        let row = &labels[v * WIDTH..(v + 1) * WIDTH];
        let start = row.iter().position(|&l| l == ALIGNMENT)?;
        Some((start, (start..WIDTH).find(|&x| row[x] != ALIGNMENT)?))
    };
    let (mut rows, mut starts, mut ends) = (0, 0, 0);
    for v in 0..HEIGHT {
        let (Some(truth), Some(found)) = (strip(&frame.rgb_labels, v), strip(&out.rgb_labels, v))
        else {
            continue;
        };
        rows += 1;
        starts += usize::from(found.0 == truth.0);
        ends += usize::from(found.1 == truth.1);
    }
    assert!(rows > 400, "{rows} rows with a strip");
    assert!(100 * starts >= 98 * rows, "{starts} of {rows} starts exact");
    assert!(100 * ends >= 95 * rows, "{ends} of {rows} far ends exact");
}

#[test]
fn alignment_strip_starts_at_a_faint_colour_edge_of_a_wide_box() {
    // The box of the test above in a colour close to the wall's: its RGB pixels differ from the
    // wall's by a sum of |ΔR|+|ΔG|+|ΔB| of about 70, too little to trust beside a thin object's
    // shading, but the box shows one colour over many pixels before its edge.
    // Measured: 777 of 780 (742 when only contrasts of 90 and more were trusted).
    faint_box_strips_start_at_its_colour_edge([0.75, 0.62, 0.45], 90, 90, 98);
}

/// The strip starts of [`box_strip_starts`] for a matte box of `colour` (render seeds from
/// `seed0`), whose median contrast against the wall must be under `max_contrast`: over 300 rows
/// cross the box, and at least `percent` % of them start exactly at the colour edge.
fn faint_box_strips_start_at_its_colour_edge(
    colour: [f64; 3],
    seed0: u64,
    max_contrast: u32,
    percent: usize,
) {
    let material = umbra::synth::Material::matte(colour);
    let s = box_strip_starts(Some(material), seed0, |rgb| rgb.to_vec());
    assert!(
        s.median_contrast < max_contrast,
        "the box is not faint enough: median contrast {}",
        s.median_contrast
    );
    assert!(s.rows > 300, "{} rows cross the box", s.rows);
    assert!(100 * s.exact_rgb >= percent * s.rows, "{s:?}");
}

#[test]
fn alignment_strip_starts_at_the_colour_edge_of_a_box_as_bright_as_the_wall() {
    // The box of the tests above, as bright as the wall (matte 0.80, 0.78, 0.70) but of another
    // hue (0.72, 0.80, 0.84: bluer, less red). Its RGB pixels differ from the wall's by a sum of
    // |ΔR|+|ΔG|+|ΔB| too small to trust even beside a wide box; what sets it apart is the hue,
    // (R − G, B − G) = (−0.08, +0.04) against (+0.02, −0.08), which shading does not change.
    // Measured: 778 of 780 (744 when colours were told apart by |ΔR|+|ΔG|+|ΔB| alone; depth
    // alone 740).
    faint_box_strips_start_at_its_colour_edge([0.72, 0.8, 0.84], 120, 45, 97);
}

#[test]
fn alignment_strip_starts_at_the_colour_edge_of_a_box_as_bright_as_the_wall_in_a_dim_image() {
    // The test above with the RGB image at 45 % of its brightness (about as dark as the real NYU
    // frame): the box's hue contrast shrinks with it, under the edge tests' steps when those
    // stayed at the bright room's, and 19 of 780 rows fell back to depth alone. The steps
    // follow the wall's brightness: 780 of 780.
    let dim = |rgb: &[u8]| -> Vec<u8> {
        rgb.iter()
            .map(|&b| (f64::from(b) * 0.45).round() as u8)
            .collect()
    };
    let box_colour = umbra::synth::Material::matte([0.72, 0.8, 0.84]);
    let s = box_strip_starts(Some(box_colour), 80, dim);
    assert!(s.rows > 300, "{} rows cross the box", s.rows);
    assert!(100 * s.exact_rgb >= 99 * s.rows, "{s:?}");
}

#[test]
fn slanted_glossy_cylinder_gets_its_alignment_strip_from_its_right_edge() {
    // A glossy cylinder (r = 12 cm, at 1.5 m before the wall at 3 m) tilted 25°, with a black
    // poster on the wall left of it: its hole runs on into the poster's, so no shadow can be split
    // off, and only its right edge, where the RGB camera sees the wall again, gives its depth.
    // That edge moves about half a pixel a row; when the rows above and below had to end in the
    // very same column, most rows lost their strip (alignment F1 0.62).
    let calib = Calibration::nyu_default();
    let mut scene = Scene::rod_before_wall(0.0, 1.5, 0.12, 3.0);
    tilt_rod(&mut scene, 25.0);
    scene.objects[1].material = umbra::synth::Material::glossy([0.6, 0.3, 0.25]);
    push_black_box(&mut scene, "poster", [-0.8, 0.0, 2.95], [0.5, 2.0, 0.02]);
    let c = kinect_confusion(&scene, &calib, 70, true);
    at_least(
        &c,
        Some(ALIGNMENT),
        0.9,
        "RGB alignment of a slanted glossy cylinder",
    );
}

#[test]
fn black_box_turned_away_gets_its_alignment_strip_from_its_right_edge() {
    // A black box 50 cm wide and deep, centred 5 cm right of the axis at 1.4 m before a wall at
    // 3 m, turned about the vertical. At 15° its left edge stands at 1.22 m (shift
    // 43.67·(1/1.22 − 1/3) = 21.2 px, column 191) and its right edge at 1.58 m (13.1 px, column
    // 444); at 30°, 1.31 m (18.8 px) and 1.49 m (14.7 px). The shadow gives the left edge's
    // shift; the RGB camera sees the wall again past the right edge at that edge's own shift.
    // Held to the left's, the strip came out a third wider than it is (precision 0.74 at 15°).
    let calib = Calibration::nyu_default();
    for yaw in [15f64, 30.0] {
        let mut scene = Scene::box_before_wall(1.4, 3.0);
        scene.objects[1].shape = umbra::synth::Shape::Box {
            centre: nalgebra::Vector3::new(0.05, 0.0, 1.4),
            half: nalgebra::Vector3::new(0.25, 2.0, 0.25),
            yaw: yaw.to_radians(),
        };
        scene.objects[1].material = umbra::synth::Material::black();
        let c = kinect_confusion(&scene, &calib, 90, true);
        at_least(
            &c,
            Some(ALIGNMENT),
            0.95,
            &format!("RGB alignment of a black box turned {yaw}°"),
        );
    }
}

#[test]
fn black_box_turned_away_before_a_finely_striped_wall_gets_its_whole_alignment_strip() {
    // The black box above turned 15° (its left edge 21.2 px of shift, its right edge 13.1 px, by
    // hand) before a wall in bands 2.5 cm wide, light and a little under half as bright, one
    // starting at x = 0.677 m, where the IR camera sees the wall again past the box's right edge
    // (column 444): its strip, x = 0.652–0.677 m, lies on a light band and the wall beside it on
    // a dark one. The hole's sides differ, so it is read from the left alone (an open hole), and
    // its right edge's shift, under three quarters of the shadow's, was refused: the box's depth
    // stopped short of its right edge, and the strip was found only where its own colours showed
    // it (recall 0.940, F1 0.969). Read down to half the shadow's shift, as for a closed hole:
    // recall 0.995, F1 0.998.
    let calib = Calibration::nyu_default();
    let mut scene = Scene::new("black box turned away before a finely striped wall");
    let tan = [0.85, 0.7, 0.45];
    push_bands(&mut scene, (-0.323, 0.025, 3.0), -56..82, |k| {
        tan.map(|c| if k % 2 == 0 { 0.45 * c } else { c })
    });
    scene.push(
        "box",
        umbra::synth::Shape::Box {
            centre: nalgebra::Vector3::new(0.05, 0.0, 1.4),
            half: nalgebra::Vector3::new(0.25, 2.0, 0.25),
            yaw: 15f64.to_radians(),
        },
        umbra::synth::Material::black(),
    );
    let c = kinect_confusion(&scene, &calib, 90, true);
    let strip = c.class(ALIGNMENT);
    assert!(
        strip.recall.unwrap_or(0.0) >= 0.98,
        "the strip's recall: {strip:?}"
    );
    at_least(
        &c,
        Some(ALIGNMENT),
        0.98,
        "RGB alignment of a black box turned away before a finely striped wall",
    );
}

#[test]
fn black_box_strip_showing_the_striped_walls_other_stripe_is_found() {
    // The hand-computed black box (x = −0.2..0.2 m, front face at 1 m) before a wall at 3 m
    // papered in bands 10 cm wide, the dark ones a third as bright, one from x = 0.5 m. Past the
    // box's right edge the IR camera sees the wall from 0.2·3 = 0.6 m on, a light band; the RGB
    // camera, 2.5 cm to the right, from 0.025 + 0.175·3 = 0.55 m: its strip, 5 cm of wall
    // (about 0.025·f·(1/1 − 1/3) = 8.7 px), shows the dark band, unlike the wall beside the
    // hole. With the wall beside the hole the only background colour, the right-edge reading
    // took the dark band for the box and found no strip in most rows: alignment F1 0.308 (recall
    // 0.183); with the wall's other colours, read right of the hole, 0.940.
    let calib = Calibration::nyu_default();
    let mut scene = Scene::new("black box before a striped wall, its strip on a dark stripe");
    let green = [0.4, 0.6, 0.3];
    push_bands(&mut scene, (0.5, 0.1, 3.0), -30..30, |k| {
        green.map(|c| if k % 2 == 0 { 0.35 * c } else { c })
    });
    push_black_box(&mut scene, "box", [0.0, 0.0, 1.1], [0.2, 0.25, 0.1]);
    let mut c = Confusion::default();
    for seed in 90..92 {
        let frame = render_frame(&scene, &calib, &SensorModel::kinect(), seed);
        // The simulator's strip lies on the dark band.
        let strip: Vec<usize> = (0..PIXELS)
            .filter(|&i| frame.rgb_labels[i] == ALIGNMENT)
            .collect();
        // Lit alike, the bands differ by their paper: a strip pixel is on the dark band when
        // darker by a tenth or more than the wall the IR camera sees 3 px past the strip's end.
        let green = |i: usize| f64::from(frame.rgb[3 * i + 1]);
        let dark = strip
            .iter()
            .filter(|&&i| {
                let end = (i..i - i % WIDTH + WIDTH).find(|&j| frame.rgb_labels[j] == VALID);
                end.is_some_and(|j| green(i) < 0.9 * green(j + 3))
            })
            .count();
        assert!(
            strip.len() > 1500 && 10 * dark >= 9 * strip.len(),
            "{dark} of the strip's {} px on the dark band",
            strip.len()
        );
        c.add(&frame.rgb_labels, &classify_rgb(&calib, &frame).rgb_labels);
    }
    at_least(
        &c,
        Some(ALIGNMENT),
        0.9,
        "RGB alignment of a black box whose strip shows the wall's other stripe",
    );
}

#[test]
fn alignment_strip_starts_at_the_dark_silhouette_of_a_pale_rod() {
    // A rod 1.6 cm thick at 1.9 m before a wall at 2.7 m, through the Kinect sensor model, in a
    // colour close to the wall's: lit from beside the camera, its middle is nearly as bright as
    // the wall, and its edge, where the surface turns away from the light, stands out more.
    // Moved right in 12 steps of 0.3 mm (about a tenth of an IR pixel), so its edge falls at
    // every sub-pixel position.
    let calib = Calibration::nyu_default();
    let start = |labels: &[u8], v: usize| {
        let x = (300..WIDTH).find(|&x| labels[v * WIDTH + x] == ALIGNMENT)?;
        // The strip right of the rod, not a stray pixel of the wall.
        (labels[v * WIDTH + x + 1] == ALIGNMENT).then_some(x)
    };
    let (mut rows, mut exact, mut contrast) = (0, 0, Vec::new());
    for k in 0..12 {
        let mut scene = Scene::rod_before_wall(0.1 + 3e-4 * k as f64, 1.9, 0.008, 2.7);
        scene.objects[1].material = umbra::synth::Material::matte([0.55, 0.55, 0.7]);
        let frame = render_frame(&scene, &calib, &SensorModel::kinect(), 40 + k);
        let out = classify_rgb(&calib, &frame);
        for v in 100..380 {
            let Some(first) = start(&frame.rgb_labels, v) else {
                continue;
            };
            // Middle of the rod (three pixels in) against the wall past the strip.
            contrast.push(rgb_distance(
                &frame.rgb,
                v * WIDTH + first - 3,
                v * WIDTH + first + 8,
            ));
            rows += 1;
            exact += usize::from(start(&out.rgb_labels, v) == Some(first));
        }
    }
    contrast.sort_unstable();
    let median = contrast[contrast.len() / 2];
    assert!(median < 90, "the rod is not pale: median contrast {median}");
    assert!(rows > 12 * 250, "{rows} rows cross the rod");
    // Measured: 3313 of 3360 (3294 before the rod's edge pixel was read).
    assert!(
        100 * exact >= 97 * rows,
        "{exact} of {rows} rows start where the wall shows past the rod"
    );
}

#[test]
fn attached_shadow_in_the_rgb_view_ends_at_the_colour_edge_of_the_box() {
    // The box's left front edge at 17 sub-pixel positions of its first IR pixel (as above), an
    // ideal sensor so that no pixel of the box is lost to the correlation window. The RGB camera
    // sees the projector shadow on the wall up to the box's left edge; depth alone places that
    // edge only to within the IR pixel, the colour edge where the wall ends.
    let end = |labels: &[u8], v: usize| {
        let row = &labels[v * WIDTH..(v + 1) * WIDTH];
        let start = row.iter().position(|&l| l == ATTACHED)?;
        (start..WIDTH).find(|&x| row[x] != ATTACHED)
    };
    let (rows, exact_rgb, exact_depth) = box_at_sub_pixel_offsets(SensorModel::ideal(), 300, end);
    assert!(rows > 17 * 250, "{rows} rows cross the box");
    // Measured: 4420 of 4420 (depth alone, and before the colour edge was read here: 3120).
    assert!(
        100 * exact_rgb >= 95 * rows,
        "{exact_rgb} of {rows} shadows end at the box (depth alone: {exact_depth})"
    );
}

#[test]
fn black_sphere_crescent_is_split_off_up_to_its_poles() {
    // A black sphere (r = 0.2 m) at 0.9 m before a wall at 3 m: its attached shadow is a crescent
    // f·b·(1/0.9 − 1/3) = 34 px wide at the equator. Towards the poles the sphere's edge moves
    // several pixels from row to row, so a row's split need agree with only one neighbour.
    let calib = Calibration::nyu_default();
    let mut scene = Scene::box_before_wall(1.0, 3.0);
    scene.objects[1].shape = umbra::synth::Shape::Sphere {
        centre: umbra::synth::V3::new(0.0, 0.0, 1.1),
        radius: 0.2,
    };
    scene.objects[1].material = umbra::synth::Material::black();
    let mut c = Confusion::default();
    for seed in 0..3 {
        let frame = render_frame(&scene, &calib, &SensorModel::kinect(), 90 + seed);
        c.add(&frame.ir_labels, &classify_rgb(&calib, &frame).ir_labels);
    }
    let s = c.class(ATTACHED);
    assert!(
        s.recall.unwrap() >= 0.9,
        "IR attached of a black sphere {s:?}"
    );
    assert!(
        s.precision.unwrap() >= 0.97,
        "IR attached of a black sphere {s:?}"
    );
}

#[test]
fn black_rod_a_pixel_from_its_shadow_is_paired_where_the_sensor_swallows_the_gap() {
    // The rod of the test below with the noisy Kinect sensor: its correlation window widens the
    // shadow by 0–3 px a row, so the 1.6 px lit gap shows in some rows and not in others. Where
    // it does not, shadow and rod are one hole, which the colour split splits, with the rows
    // around it: the row below may hold the scanline's pair, already DETACHED. There the shadow
    // touches the rod: attached (SPEC §1), where the gap shows detached.
    let (ir, rgb) = black_rod_scores((0.0, 1.5, 0.0167), 60..63, classify_rgb);
    // Measured: IR detached recall 0.991, precision 0.984 (0.993 and 0.99 when every row was
    // detached; before, when the colour split wanted the row below all OTHER, recall 0.974);
    // attached recall 0.961 in the rows whose gap the widening closed. The RGB view: detached
    // F1 0.983 (0.993 when every row was detached), attached 0.955.
    let s = ir.class(DETACHED);
    assert!(s.recall.unwrap() >= 0.985, "IR detached {s:?}");
    assert!(s.precision.unwrap() >= 0.98, "IR detached {s:?}");
    let s = ir.class(ATTACHED);
    assert!(s.recall.unwrap() >= 0.95, "IR attached {s:?}");
    at_least(&rgb, Some(DETACHED), 0.98, "RGB detached of a black rod");
    at_least(&rgb, Some(ATTACHED), 0.95, "RGB attached of a black rod");
}

#[test]
fn black_rod_a_pixel_from_its_shadow_is_paired_across_the_lit_gap() {
    // A black rod 13 px wide (r = 16.7 mm at 1.5 m) before a wall at 3 m casts its shadow
    // f·b·(1/1.5 − 1/3) = 14.6 px to its left: a lit gap of 1.6 px between shadow and rod. A
    // hole merges such a gap as noise, so the shadow and the rod are one hole; its two parts
    // either side of the gap are the pair of eqs. (4)–(5), from depth alone.
    let calib = Calibration::nyu_default();
    let mut scene = Scene::rod_before_wall(0.0, 1.5, 0.0167, 3.0);
    scene.objects[1].material = umbra::synth::Material::black();
    let frame = render_frame(&scene, &calib, &SensorModel::ideal(), 7);
    let mut c = Confusion::default();
    c.add(&frame.ir_labels, &classify(&calib, &frame).ir_labels);
    at_least(
        &c,
        Some(DETACHED),
        0.9,
        "IR detached a lit pixel from a black rod",
    );
    let any = c.any_shadow();
    assert!(any.precision.unwrap() >= 0.98, "IR any shadow {any:?}");
}

/// Classifies with the frame's RGB image (the colour split of depthless occluders' shadows).
fn classify_rgb(calib: &Calibration, frame: &SynthFrame) -> Classified {
    let mut out = Classified::default();
    Classifier::new(calib).classify_with_rgb(&frame.raw, Some(&frame.rgb), &mut out);
    out
}

/// The box of the hand-computed scene, but black and moved `x` metres sideways: no depth on it,
/// so box and shadow are one hole. By hand its shadow in row `v` is f·b·(1/z_edge(v) − 1/3) px
/// wide, where `z_edge(v)` is the depth of the box edge that casts it, and the RGB image shows
/// wall there and the black box next to it. Asserts the split in the IR view row by row and
/// returns the labels.
fn black_box_split(x: f64, z_edge: impl Fn(usize) -> f64, seed: u64) -> (SynthFrame, Classified) {
    let sensor = SensorModel::ideal();
    depthless_box_split(umbra::synth::Material::black(), x, z_edge, &sensor, seed)
}

/// [`black_box_split`] with a box of another `material` the sensor cannot measure, seen by
/// `sensor` (the ideal one but for the RGB camera's noise, if any: the hand-computed widths
/// assume no widening).
fn depthless_box_split(
    material: umbra::synth::Material,
    x: f64,
    z_edge: impl Fn(usize) -> f64,
    sensor: &SensorModel,
    seed: u64,
) -> (SynthFrame, Classified) {
    let calib = Calibration::nyu_default();
    let mut scene = Scene::box_before_wall(1.0, 3.0);
    scene.objects[1].material = material;
    if let umbra::synth::Shape::Box { centre, .. } = &mut scene.objects[1].shape {
        centre.x += x;
    }
    let frame = render_frame(&scene, &calib, sensor, seed);
    let depth_only = classify(&calib, &frame);
    let out = classify_rgb(&calib, &frame);
    let (box_rows, rows) = attached_rows(&frame, &out.ir_labels, |v, n, _| {
        assert_eq!(
            count_in_row(&depth_only.ir_labels, v, ATTACHED),
            0,
            "depth alone cannot"
        );
        let w = calib.fb() * (1.0 / z_edge(v) - 1.0 / 3.0);
        // One RGB column of the colour edge is about 1.7 px of shadow width.
        assert!(
            n == 0 || (n as f64 - w).abs() <= 2.5,
            "row {v}: {n} attached px, hand-computed {w:.2}"
        );
    });
    // Nearly all rows are split; near the box's top and bottom edges the RGB camera, which sits
    // at another height, sees wall where the IR row has box, and those rows are left alone.
    assert!(box_rows > 100, "the box spans {box_rows} rows");
    assert!(10 * rows >= 9 * box_rows, "{rows} of {box_rows} rows split");
    (frame, out)
}

#[test]
fn black_box_shadow_is_split_off_its_hole_by_colour() {
    // The box's front face spans x = −0.2..0.2 m, so its front edge (1 m) casts the shadow:
    // f·b·(1/1 − 1/3) = 29.1 px.
    let (frame, out) = black_box_split(0.0, |_| 1.0, 4);
    let mut c = Confusion::default();
    c.add(&frame.rgb_labels, &out.rgb_labels);
    // In the RGB view the box now stands at its implied depth: its alignment strip appears too.
    at_least(&c, Some(ALIGNMENT), 0.8, "RGB alignment beside a black box");
    at_least(&c, Some(ATTACHED), 0.9, "RGB attached of a black box");
}

#[test]
fn narrow_black_box_before_a_wall_lit_unevenly_has_its_shadow_split_off() {
    // A black box 5 cm wide (x = −0.025..0.025 m, front face at 1 m) before a wall at 3 m whose
    // two halves meet behind it, the right half in three quarters of the left's light (one
    // colour, darker). By hand: the box spans columns cx ± 0.025·fx = 298.5..327.6, its shadow
    // f·b·(1/1 − 1/3) = 29.1 px left of it, 269.3..298.5: one hole of 58 px, narrower than the
    // widest shadow on that wall, whose two sides differ in brightness only.
    let mut scene = Scene::new("narrow black box before an unevenly lit wall");
    let green = [0.4, 0.6, 0.3];
    for (x, light) in [(-1.5, 1.0), (1.5, 0.75)] {
        scene.push(
            "wall",
            umbra::synth::Shape::Box {
                centre: umbra::synth::V3::new(x, 0.0, 3.05),
                half: umbra::synth::V3::new(1.5, 3.0, 0.05),
                yaw: 0.0,
            },
            umbra::synth::Material::matte(green.map(|c| c * light)),
        );
    }
    assert_black_box_split_as_by_hand(scene, 0.025);
}

/// Adds to `scene` (a wall at 3 m) a black box `half_width` wide each side of x = 0, its front
/// face at 1 m, and asserts its shadow's split row by row: f·b·(1/1 − 1/3) = 29.1 px by hand,
/// within 2.5 px where split, in at least nine rows of ten.
fn assert_black_box_split_as_by_hand(mut scene: Scene, half_width: f64) {
    let calib = Calibration::nyu_default();
    push_black_box(&mut scene, "box", [0.0, 0.0, 1.1], [half_width, 0.25, 0.1]);
    let frame = render_frame(&scene, &calib, &SensorModel::ideal(), 8);
    let out = classify_rgb(&calib, &frame);
    let w = calib.fb() * (1.0 - 1.0 / 3.0);
    let (box_rows, rows) = attached_rows(&frame, &out.ir_labels, |v, n, truth| {
        assert!(
            (truth as f64 - w).abs() <= 1.5,
            "row {v}: the scene's {truth}"
        );
        assert!(
            n == 0 || (n as f64 - w).abs() <= 2.5,
            "row {v}: {n} attached px, hand-computed {w:.2}"
        );
    });
    assert!(box_rows > 250, "the box spans {box_rows} rows");
    assert!(10 * rows >= 9 * box_rows, "{rows} of {box_rows} rows split");
}

#[test]
fn black_box_before_a_striped_wall_has_its_shadow_split_off() {
    // Stripes a quarter darker: each stripe's colour differs from the next by more than a
    // plain wall's noise (the column test's step) but by far less than the black box.
    black_box_before_a_striped_wall(0.75);
}

#[test]
fn black_box_before_a_boldly_striped_wall_has_its_shadow_split_off() {
    // Stripes a third darker: the hole's first pixel, on the stripe after the one beside the
    // hole, also differs from it by more than the step.
    black_box_before_a_striped_wall(0.65);
}

/// The hand-computed black box (front face x = −0.2..0.2 m at 1 m) before a wall at 3 m papered
/// in vertical stripes 5 cm wide, every other one in `dark` of the light: the shadow,
/// f·b·(1/1 − 1/3) = 29.1 px by hand, starts on a stripe's edge (x = −0.75 m on the wall) and
/// lies over three stripes. Asserts the split row by row.
fn black_box_before_a_striped_wall(dark: f64) {
    black_box_before_a_banded_wall(0.05, 0.0, dark);
}

#[test]
fn black_sphere_before_a_checkered_wall_has_its_crescent_split_off() {
    // A black sphere of radius 0.2 m at 1.2 m before a wall at 3 m papered in a checker of 20 cm
    // squares of two blues: its attached shadow, a crescent left of it, crosses from square to
    // square, and the hole's two sides often lie on different ones (read from the left, as an
    // open hole, whose columns may show any colour the wall left of it shows). The wall's colours
    // are sampled as single pixels; the camera's noise moves them by tens. Measured: attached
    // F1 0.914 → 0.927 (recall 0.868 → 0.895) once a column within one and a half colour steps
    // of a sample counts as wall (half a step before).
    let mut scene = Scene::new("black sphere before a checkered wall");
    for i in -8..8 {
        for j in -6..6 {
            let colour = if (i + j) % 2 == 0 {
                [0.2, 0.25, 0.5]
            } else {
                [0.1, 0.12, 0.28]
            };
            scene.push(
                "wall",
                umbra::synth::Shape::Box {
                    centre: umbra::synth::V3::new(
                        0.2 * (f64::from(i) + 0.5) - 0.05,
                        0.2 * (f64::from(j) + 0.5),
                        3.05,
                    ),
                    half: umbra::synth::V3::new(0.1, 0.1, 0.05),
                    yaw: 0.0,
                },
                umbra::synth::Material::matte(colour),
            );
        }
    }
    scene.push(
        "sphere",
        umbra::synth::Shape::Sphere {
            centre: umbra::synth::V3::new(0.0, 0.0, 1.4),
            radius: 0.2,
        },
        umbra::synth::Material::black(),
    );
    let calib = Calibration::nyu_default();
    let mut c = Confusion::default();
    for seed in 50..53 {
        let frame = render_frame(&scene, &calib, &SensorModel::kinect(), seed);
        c.add(&frame.ir_labels, &classify_rgb(&calib, &frame).ir_labels);
    }
    at_least(
        &c,
        Some(ATTACHED),
        0.92,
        "attached crescent on a checkered wall",
    );
    let p = c.class(ATTACHED).precision.unwrap_or(0.0);
    assert!(p >= 0.95, "attached precision {p:.3}");
}

#[test]
fn glossy_cylinder_before_bands_of_two_hues_keeps_its_attached_shadow() {
    // A glossy cylinder (radius 6 cm, no depth on it) at 1.5 m before a wall at 3 m papered in
    // vertical bands 25 cm wide, pink, green, dark green over again, edges at x = 0.15 + 0.25k:
    // its hole (x = 0.24..0.56 m on the wall: its attached shadow of f·b·(1/1.44 − 1/3) ≈ 16 px,
    // then the cylinder) has green on its left, dark green on its right: one hue in two lights,
    // so it is read from the left as an open hole. That reading first asks that the RGB camera
    // see the wall, not the cylinder, over the 36 px left of the hole (to x = 0.06), which cross
    // the pink band's edge at x = 0.15: read one probe after the other, pink stepped from green
    // as the cylinder would. Measured: attached F1 0 → 0.956 (P 0.967, R 0.945) once a probe
    // may show a colour the wall shows further left, after up to two probes blending it with
    // the last.
    let c = glossy_cylinder_before_bands(
        0.25,
        0.15,
        &[[0.09, 0.12, 0.07], [0.045, 0.06, 0.035], [0.42, 0.13, 0.18]],
        60..63,
    );
    at_least(
        &c,
        Some(ATTACHED),
        0.93,
        "attached shadow on bands of two hues",
    );
    let p = c.class(ATTACHED).precision.unwrap_or(0.0);
    assert!(p >= 0.95, "attached precision {p:.3}");
}

#[test]
fn black_rod_over_a_boxs_edge_before_a_farther_wall_holds_no_shadow() {
    // A dark box (measured, black in the RGB image) whose face (3.2 m) ends at column 330, a
    // pale blue wall at 4.1 m behind it, and a black rod (2.7 cm) at 1 m over the box's edge,
    // columns 322–338. The rod's hole runs from the box onto the wall, and its detached shadow
    // lies on the box left of it. The RGB camera sees the rod f·b'·(1/1 − 1/3.2) ≈ 10 px left
    // of where the IR camera does, so the hole, read at the box's depth, shows black (rod and
    // box alike), then the farther wall. Read from the left as background, then something
    // else, its left part was called the box's attached shadow and the wall a depthless
    // occluder; but that colour is the farther wall's, right of the hole. Measured (seeds
    // 95–97): attached pixels in the rod's hole 5818 → 162.
    let calib = Calibration::nyu_default();
    let mut scene = Scene::new("black rod over a box's edge before a farther wall");
    scene.push(
        "wall",
        umbra::synth::scene::wall(4.1),
        umbra::synth::Material::matte([0.55, 0.65, 0.8]),
    );
    let right = (330.0 - calib.depth.cx) * 3.2 / calib.depth.fx;
    push_box(
        &mut scene,
        "box",
        [right - 0.4, 0.0, 3.3],
        [0.4, 0.6, 0.1],
        umbra::synth::Material::matte([0.05, 0.05, 0.05]),
    );
    scene.push(
        "rod",
        umbra::synth::Shape::Cylinder {
            centre: umbra::synth::V3::new((330.0 - calib.depth.cx) / calib.depth.fx, 0.0, 1.0),
            axis: umbra::synth::V3::new(0.0, 1.0, 0.0),
            radius: 0.0135,
            half_len: 3.0,
        },
        umbra::synth::Material::black(),
    );
    let mut claimed = 0;
    for seed in 95..98 {
        let frame = render_frame(&scene, &calib, &SensorModel::kinect(), seed);
        let out = classify_rgb(&calib, &frame);
        claimed += (0..frame.raw.len())
            .filter(|&i| {
                (316..346).contains(&(i % WIDTH))
                    && frame.ir_labels[i] == OTHER
                    && out.ir_labels[i] == ATTACHED
            })
            .count();
    }
    assert!(
        claimed < 500,
        "{claimed} px of the rod's hole called attached"
    );
}

#[test]
fn black_box_shadow_on_a_panel_brightening_towards_it_is_split_off_whole() {
    // A green panel at 1.3 m whose right part, from column 150, is painted in 1 cm bands
    // brightening to 2.5 times by column 200 (a surface lit unevenly, as a lamp lights a curved
    // one: the fourth simulator's cylinders brighten so towards its lamp), and a black
    // box at 0.7 m over it from column 200 to the border: the box's attached shadow on the
    // panel, f·b·(1/0.7 − 1/1.3) ≈ 29 px, shares one hole with the box's own. Read at the
    // panel's depth, the shadow's columns brighten from the green beside the hole by more than
    // the colour step before the black box: the shadow was cut where the drift passed it. Far
    // nearer the panel's colour than the box's, they are background. Measured (seeds 110–111):
    // attached recall 0.952 → 0.986 (F1 0.975 → 0.993).
    let calib = Calibration::nyu_default();
    let mut scene = before_a_pale_wall("black box before a panel brightening towards it");
    let x = |u: f64, z: f64| (u - calib.depth.cx) * z / calib.depth.fx;
    // Level from its left edge (column 80) to column 150, then bands brightening to 2.5 times
    // by column 200.
    let green =
        |light: f64| umbra::synth::Material::matte([0.15 * light, 0.3 * light, 0.1 * light]);
    let (left, band) = (x(80.0, 1.3), 0.01);
    let level = x(150.0, 1.3) - left;
    push_box(
        &mut scene,
        "panel",
        [left + level / 2.0, 0.0, 1.31],
        [level / 2.0, 3.0, 0.01],
        green(1.0),
    );
    for k in 0..25 {
        let centre = left + level + band * (f64::from(k) + 0.5);
        let u = calib.depth.cx + centre * calib.depth.fx / 1.3;
        let light = 1.0 + 1.5 * ((u - 150.0) / 50.0).clamp(0.0, 1.0);
        push_box(
            &mut scene,
            "band",
            [centre, 0.0, 1.31],
            [band / 2.0, 3.0, 0.01],
            green(light),
        );
    }
    push_black_box(
        &mut scene,
        "box",
        [x(200.0, 0.7) + 1.0, 0.0, 0.8],
        [1.0, 3.0, 0.1],
    );
    let mut c = Confusion::default();
    for seed in 110..112 {
        let frame = render_frame(&scene, &calib, &SensorModel::kinect(), seed);
        c.add(&frame.ir_labels, &classify_rgb(&calib, &frame).ir_labels);
    }
    let a = c.class(ATTACHED);
    let (p, r) = (a.precision.unwrap_or(0.0), a.recall.unwrap_or(0.0));
    assert!(r >= 0.97 && p >= 0.98, "attached P {p:.3}, R {r:.3}");
}

#[test]
fn glossy_cylinder_whose_shadow_crosses_onto_the_walls_other_hue_keeps_it_whole() {
    // A glossy cylinder (radius 6 cm, no depth on it) at 1.5 m before a wall at 3 m papered in
    // bands 20 cm wide, pink and green, edges at x = 0.124 + 0.2k: its hole (x = 0.30..0.63 m
    // on the wall: its attached shadow of f·b·(1/1.44 − 1/3) ≈ 16 px, then the cylinder) has
    // pink on both sides, and its shadow crosses onto the green band at x = 0.324 after 5 px.
    // Read as one surface either side, the hole's columns had to show the sides' pink: the
    // shadow was cut at the band's edge. The wall's own colours (the 40 px left of the hole
    // reach the green band before) count as background where the hole's middle shows an
    // occluder of far greater contrast and of none of them. Measured (seeds 120–122): attached
    // F1 0.680 → 0.988.
    let c = glossy_cylinder_before_bands(
        0.2,
        0.124,
        &[[0.42, 0.13, 0.18], [0.09, 0.12, 0.07]],
        120..123,
    );
    at_least(
        &c,
        Some(ATTACHED),
        0.95,
        "attached shadow across the band's edge",
    );
    let p = c.class(ATTACHED).precision.unwrap_or(0.0);
    assert!(p >= 0.95, "attached precision {p:.3}");
}

/// A glossy cylinder (radius 6 cm, axis at x = 0.25 m, 1.5 m; no depth on it) before a wall at
/// 3 m papered in vertical bands `width` wide, edges at `edge + width·k`, in `colours` in turn
/// (the band from `edge` on the first): the IR view's confusions over `seeds`, with the RGB
/// image.
fn glossy_cylinder_before_bands(
    width: f64,
    edge: f64,
    colours: &[[f64; 3]],
    seeds: std::ops::Range<u64>,
) -> Confusion {
    let mut scene = Scene::new("glossy cylinder before bands");
    push_bands(&mut scene, (edge, width, 3.0), -12..12, |k| {
        colours[k.rem_euclid(colours.len() as i32) as usize]
    });
    scene.push(
        "cylinder",
        umbra::synth::Shape::Cylinder {
            centre: umbra::synth::V3::new(0.25, 0.0, 1.5),
            axis: umbra::synth::V3::new(0.0, 1.0, 0.0),
            radius: 0.06,
            half_len: 3.0,
        },
        umbra::synth::Material::glossy([0.8, 0.8, 0.3]),
    );
    let calib = Calibration::nyu_default();
    let mut c = Confusion::default();
    for seed in seeds {
        let frame = render_frame(&scene, &calib, &SensorModel::kinect(), seed);
        c.add(&frame.ir_labels, &classify_rgb(&calib, &frame).ir_labels);
    }
    c
}

#[test]
fn black_box_before_a_wall_of_wide_bands_has_its_shadow_split_off() {
    // Bands 24 cm wide (47 px at 3 m), one edge at x = −0.69 m: the shadow (x = −0.75..−0.60 m
    // on the wall) starts 12 cm into a light band, crosses onto a band a quarter darker after
    // 11.7 px and lies there for its last 17.4. The 24 px left of the hole (12.4 cm, to
    // x = −0.874) show the light band only; the 40 left of it (20.6 cm, to x = −0.956) reach
    // 5 px into the dark band before it.
    black_box_before_a_banded_wall(0.24, -0.69 - 0.24, 0.75);
}

/// The hand-computed black box before a wall at 3 m papered in vertical bands `width` wide from
/// `edge` on (x, metres), every other one (the first from `edge` light) in `dark` of the light.
fn black_box_before_a_banded_wall(width: f64, edge: f64, dark: f64) {
    let mut scene = Scene::new("black box before a banded wall");
    let green = [0.4, 0.6, 0.3];
    push_bands(&mut scene, (edge, width, 3.0), -50..50, |k| {
        let light = if k % 2 == 0 { 1.0 } else { dark };
        green.map(|c| c * light)
    });
    assert_black_box_split_as_by_hand(scene, 0.2);
}

#[test]
fn black_box_before_a_wall_of_two_hues_keeps_its_shadow_across_a_band_edge() {
    // The hand-computed black box, 0.56 m wide (x = −0.28..0.28 m at 1 m: columns 149.9..476.2),
    // before a wall at 3 m papered in bands 21 cm wide of two purples that differ in hue (green
    // 0.25 against 0.35), one edge at x = −0.928 m. Its shadow, f·b·(1/1 − 1/3) = 29.1 px
    // (x = −0.99..−0.84 m on the wall), starts on one purple, the wall's colour left of the hole,
    // and crosses onto the other after 12 px. The wall right of the hole (x = 0.84 m) is on the
    // other purple too, so the hole's sides differ and it is read from its left, as an open
    // hole: the band edge must not end the shadow. The wall left of the hole shows both purples.
    // Measured: 146 of the box's 292 rows split as by hand (the others short, at the band edge,
    // or not at all) → 286; 5 rows end at 21 px, where the RGB camera's slight roll puts a pixel
    // blending the two purples in the row, unlike both.
    let calib = Calibration::nyu_default();
    let edge = -0.928 - 0.21;
    let mut scene = Scene::new("black box before a wall of two hues");
    push_bands(&mut scene, (edge, 0.21, 3.0), -20..20, |k| {
        [0.45, if k % 2 == 0 { 0.35 } else { 0.25 }, 0.6]
    });
    push_black_box(&mut scene, "box", [0.0, 0.0, 1.1], [0.28, 0.25, 0.1]);
    let frame = render_frame(&scene, &calib, &SensorModel::ideal(), 8);
    let out = classify_rgb(&calib, &frame);
    let w = calib.fb() * (1.0 - 1.0 / 3.0);
    let mut right = 0;
    let (box_rows, _) = attached_rows(&frame, &out.ir_labels, |v, n, truth| {
        assert!(
            (truth as f64 - w).abs() <= 1.5,
            "row {v}: the scene's {truth}"
        );
        right += usize::from((n as f64 - w).abs() <= 2.5);
    });
    assert!(box_rows > 250, "the box spans {box_rows} rows");
    assert!(
        20 * right >= 19 * box_rows,
        "{right} of {box_rows} rows split as by hand"
    );
}

#[test]
fn black_rod_before_a_boldly_banded_wall_has_its_attached_shadow_split_off() {
    // A black rod 3.3 cm thick at 1.5 m (x = −0.2 m: columns 228.9..241.7) before a wall at
    // 2.31 m papered in bands 12 cm wide, a dark purple and a magenta bright enough to clip,
    // one edge at x = −0.33 m, behind the rod: its attached shadow, f·b·(1/1.5 − 1/2.31) =
    // 10.2 px, lies on the dark band, the wall right of the hole on the bright one. The two
    // sides differ in tone and, the bright one clipped, in chromaticity too; the wall's own
    // pattern spans that difference, and the black rod lies beyond it, but by less than twice
    // the sides' difference from the dark side (an independent simulator's magenta checker).
    // Measured: IR attached F1 0.500 → 0.965 once one and a half times that suffices.
    let (x_rod, z_rod, z_wall) = (-0.2, 1.5, 2.31);
    let mut scene = Scene::new("black rod before a boldly banded wall");
    push_bands(&mut scene, (-0.33, 0.12, z_wall), -10..10, |k| {
        if k % 2 == 0 {
            [1.0, 0.35, 1.0]
        } else {
            [0.5, 0.18, 0.45]
        }
    });
    let rod = Scene::rod_before_wall(x_rod, z_rod, 0.0165, z_wall).objects[1].clone();
    scene.push("rod", rod.shape, umbra::synth::Material::black());
    let (depth_only, with_rgb) = with_and_without_colour(&scene, 70..73, false, |_| {});
    let alone = depth_only.class(ATTACHED).recall.unwrap_or(0.0);
    assert!(
        alone < 0.2,
        "depth alone splits the hole: attached recall {alone:.3}"
    );
    at_least(
        &with_rgb,
        Some(ATTACHED),
        0.9,
        "IR attached of a black rod before a boldly banded wall",
    );
}

#[test]
fn black_rod_before_a_dim_wall_of_two_colours_has_its_attached_shadow_split_off() {
    // The rod and wall of the test above, the wall in dim olive and dim mauve bands (each side
    // of the hole about 80 of 255 a channel, too dim for their colours to be told apart as
    // two surfaces'), the rod painted a deeper black (about 22): less than half as bright as
    // either side. Its shadow, f·b·(1/1.5 − 1/2.31) = 10.2 px, lies on the olive band, the
    // wall right of the hole on the mauve one. A narrow hole whose sides differ was read from
    // the left only where they differ as lit surfaces do; a black thing in it is read too.
    // Measured (seeds 70–72): IR attached F1 0.103 → 0.985.
    let (x_rod, z_rod, z_wall) = (-0.2, 1.5, 2.31);
    let mut scene = Scene::new("black rod before a dim wall of two colours");
    push_bands(&mut scene, (-0.33, 0.12, z_wall), -10..10, |k| {
        if k % 2 == 0 {
            [0.11, 0.08, 0.09]
        } else {
            [0.10, 0.11, 0.03]
        }
    });
    let rod = Scene::rod_before_wall(x_rod, z_rod, 0.0165, z_wall).objects[1].clone();
    let paint = umbra::synth::Material {
        colour: [0.005; 3],
        ..umbra::synth::Material::black()
    };
    scene.push("rod", rod.shape, paint);
    let (depth_only, with_rgb) = with_and_without_colour(&scene, 70..73, false, |_| {});
    let alone = depth_only.class(ATTACHED).recall.unwrap_or(0.0);
    assert!(
        alone < 0.2,
        "depth alone splits the hole: attached recall {alone:.3}"
    );
    at_least(
        &with_rgb,
        Some(ATTACHED),
        0.95,
        "IR attached of a black rod before a dim wall of two colours",
    );
}

#[test]
fn black_rod_before_a_wall_in_a_noisy_colour_image_keeps_its_attached_shadow() {
    // A black rod 4 cm thick at 1.5 m before a dull wall at 2.5 m, one surface on both sides of
    // its hole, its shadow f·b·(1/1.5 − 1/2.5) = 11.7 px; the RGB camera's noise at σ = 12 a
    // channel (a dim room, the gain turned up). Each row's split then fails now and then on its
    // own, and a row whose neighbours both failed lost its shadow while it had to agree with
    // one. Measured (seeds 70–72): IR attached F1 0.936 → 0.966 (at σ = 16, 0.476 → 0.690);
    // 0.974 once a closed hole's layout could leave three columns unexplained.
    let (x_rod, z_rod, z_wall) = (-0.2, 1.5, 2.5);
    let mut scene = before_a_wall(
        "black rod before a wall in a noisy colour image",
        z_wall,
        [0.3, 0.28, 0.25],
    );
    let rod = Scene::rod_before_wall(x_rod, z_rod, 0.02, z_wall).objects[1].clone();
    scene.push("rod", rod.shape, umbra::synth::Material::black());
    let (_, with_rgb) = with_and_without_colour_by(&scene, &noisy_colour(), 70..73, false, |f| {
        let shadow = attached_in_row_240(f).len();
        assert!(
            (10..=15).contains(&shadow),
            "the simulator's shadow: {shadow} px"
        );
    });
    at_least(
        &with_rgb,
        Some(ATTACHED),
        0.955,
        "IR attached of a black rod before a wall in a noisy colour image",
    );
}

#[test]
fn black_panel_past_the_right_border_in_a_noisy_colour_image_keeps_its_attached_shadow() {
    // The noisy colour image of the test above, a black panel at 1.5 m from IR column 500 on
    // past the right border: its hole, shadow f·b·(1/1.5 − 1/2.5) = 11.7 px then panel, runs
    // into the border, an open hole. Its rows fail now and then as the rod's do. Measured
    // (seeds 70–72): IR attached F1 0.897 → 0.928 (at σ = 16, 0.721 → 0.815).
    let mut scene = before_a_wall(
        "black panel past the right border in a noisy colour image",
        2.5,
        [0.3, 0.28, 0.25],
    );
    push_black_box_over(&mut scene, (500.0, 900.0), 1.5, 0.25);
    let (_, with_rgb) = with_and_without_colour_by(&scene, &noisy_colour(), 70..73, false, |f| {
        let shadow = attached_in_row_240(f);
        assert!(
            (10..=15).contains(&shadow.len()) && shadow.last() < Some(&500),
            "the simulator's shadow: {shadow:?}"
        );
    });
    at_least(
        &with_rgb,
        Some(ATTACHED),
        0.915,
        "IR attached of a black panel past the right border in a noisy colour image",
    );
}

#[test]
fn black_rod_a_few_pixels_wide_keeps_its_attached_shadow_in_its_closed_hole() {
    // A black rod 2.4 cm thick at 2 m before the pale wall at 3 m: its shadow is
    // f·b·(1/2 − 1/3) = 7.3 px wide by hand, the rod 582.62·0.024/2 = 7.0 px, one hole of about
    // 14 px with the wall on both sides, a dozen RGB columns. The columns at the rod's two
    // edges blend it with the wall, and a layout explaining nine in ten was wanted: many rows
    // missed it by one. Measured (seeds 70–72): IR attached F1 0.938 → 0.973.
    let (x_rod, z_rod, z_wall) = (-0.2, 2.0, 3.0);
    let mut scene = before_a_pale_wall("a black rod a few pixels wide");
    let rod = Scene::rod_before_wall(x_rod, z_rod, 0.012, z_wall).objects[1].clone();
    scene.push("rod", rod.shape, umbra::synth::Material::black());
    let (_, with_rgb) = with_and_without_colour(&scene, 70..73, false, |f| {
        let shadow = attached_in_row_240(f).len();
        assert!(
            (6..=10).contains(&shadow),
            "the simulator's shadow: {shadow} px"
        );
    });
    at_least(
        &with_rgb,
        Some(ATTACHED),
        0.96,
        "IR attached of a black rod a few pixels wide",
    );
}

#[test]
fn black_rod_before_a_wall_of_two_hues_has_its_attached_shadow_split_off() {
    // A black rod 3.7 cm thick at 2.2 m before a wall at 2.9 m papered in vertical bands 6 cm
    // wide of two purples that differ in hue (green 0.25 against 0.35): thicker than
    // 7.5·(1 − 2.2/2.9) = 1.8 cm, so its shadow is attached, f·b·(1/2.2 − 1/2.9) = 4.8 px left
    // of its 582.62·0.037/2.2 = 9.8 px; its hole is about 15 px. A band edge lies behind the
    // rod's axis, so the wall left of the hole is one purple and right of it the other: the
    // two sides differ, as two surfaces would, where only the wall's pattern changes.
    // Measured: attached F1 0.934 (0.712 when such a hole was read only where its sides agree;
    // 0.925 while three columns of the left side's own colour were wanted before the wall's
    // other colours counted).
    let (x_rod, z_rod, z_wall) = (-0.2, 2.2, 2.9);
    let edge = x_rod * z_wall / z_rod;
    let mut scene = Scene::new("black rod before a wall of two hues");
    push_bands(&mut scene, (edge - 0.06, 0.06, z_wall), -40..40, |k| {
        [0.45, if k % 2 == 0 { 0.25 } else { 0.35 }, 0.6]
    });
    let rod = Scene::rod_before_wall(x_rod, z_rod, 0.0185, z_wall).objects[1].clone();
    scene.push("rod", rod.shape, umbra::synth::Material::black());
    let (depth_only, with_rgb) = with_and_without_colour(&scene, 70..73, false, |frame| {
        let row = &frame.ir_labels[240 * WIDTH..241 * WIDTH];
        let shadow = row.iter().filter(|&&l| l == ATTACHED).count();
        assert!(
            (4..=9).contains(&shadow),
            "the simulator's shadow: {shadow} px"
        );
    });
    let r = depth_only.class(ATTACHED).recall.unwrap_or(0.0);
    assert!(
        r < 0.2,
        "depth alone splits the hole: attached recall {r:.3}"
    );
    at_least(
        &with_rgb,
        Some(ATTACHED),
        0.93,
        "IR attached of a black rod before a wall of two hues",
    );
    let any = with_rgb.any_shadow();
    // (Precision 0.956: the split's edge a pixel into the rod in some rows.)
    assert!(any.precision.unwrap() >= 0.95, "IR any shadow {any:?}");
}

#[test]
fn plain_panel_beside_a_darker_wall_beyond_range_casts_no_shadow_from_colour() {
    // A plain panel at 2 m ends at x = 0 (column cx = 313.0); behind it a wall at 5 m, beyond
    // the sensor's range, of the panel's colour in 80 % of its light; a black box at 1.5 m from
    // x = 0.1 m (column 313.0 + 0.1·fx/1.5 = 351.8). One hole from the panel's edge on: far wall,
    // then box. The box's shadow on the panel's plane, f·b·(1/1.5 − 1/2) = 7.3 px left of its
    // edge, lies past the panel's edge, on the far wall: OTHER, all of it. The far wall's colour
    // differs from the panel's by more than a plain surface's noise and by far less than the
    // box: a stripe of texture on a patterned wall, but the panel shows no pattern.
    let calib = Calibration::nyu_default();
    let mut scene = Scene::new("plain panel beside a darker wall beyond range, black box");
    let green = [0.4, 0.6, 0.3];
    scene.push(
        "wall",
        umbra::synth::scene::wall(5.0),
        umbra::synth::Material::matte(green.map(|c| c * 0.8)),
    );
    scene.push(
        "panel",
        umbra::synth::Shape::Box {
            centre: umbra::synth::V3::new(-1.5, 0.0, 2.05),
            half: umbra::synth::V3::new(1.5, 3.0, 0.05),
            yaw: 0.0,
        },
        umbra::synth::Material::matte(green),
    );
    push_black_box(&mut scene, "box", [0.3, 0.0, 1.6], [0.2, 0.25, 0.1]);
    let frame = render_frame(&scene, &calib, &SensorModel::ideal(), 8);
    let out = classify_rgb(&calib, &frame);
    let (mut box_rows, mut wrong) = (0, 0);
    for v in 0..HEIGHT {
        let count = |labels: &[u8], code: u8| {
            (300..360)
                .filter(|&u| labels[v * WIDTH + u] == code)
                .count()
        };
        assert_eq!(count(&frame.ir_labels, ATTACHED), 0, "row {v}: the scene");
        if frame.raw[v * WIDTH + 360] == 2047 && frame.raw[v * WIDTH + 300] != 2047 {
            box_rows += 1;
            wrong += count(&out.ir_labels, ATTACHED) + count(&out.ir_labels, DETACHED);
        }
    }
    assert!(box_rows > 250, "the box spans {box_rows} rows");
    assert_eq!(wrong, 0, "shadow labels beside the panel's edge");
}

#[test]
fn black_box_near_the_left_border_has_its_shadow_split_off() {
    // The hand-computed black box moved left until its shadow, f·b·(1/1 − 1/3) = 29.1 px, starts
    // in column 2.6: its left edge at column 31.7, x = (31.7 − cx)/fx m. Two columns of wall
    // show left of the hole, fewer than a hole elsewhere needs.
    let calib = Calibration::nyu_default();
    let x = (31.7 - calib.depth.cx) / calib.depth.fx + 0.2;
    let (frame, out) = black_box_split(x, |_| 1.0, 6);
    let first_hole = |v: usize| (0..WIDTH).find(|&u| frame.raw[v * WIDTH + u] == 2047);
    let rows = (0..HEIGHT)
        .filter(|&v| count_in_row(&out.ir_labels, v, ATTACHED) > 0)
        .filter(|&v| first_hole(v).is_some_and(|u| u <= 3))
        .count();
    assert!(
        rows > 100,
        "{rows} rows split with the hole starting by column 3"
    );
}

#[test]
fn black_box_shadow_is_split_off_whole_when_the_sensor_widens_shadows() {
    // The hand-computed black box (front face at 1 m, wall at 3 m: a shadow of
    // f·b·(1/1 − 1/3) = 29.1 px), and a grey rod (r = 5 cm at x = −0.6 m, z = 1.5 m) whose
    // measured edges show the sensor. Every shadow is widened by exactly 2 px on its left end, as
    // a real Kinect's correlation window does (SPEC §1): the box's shadow is 31 px in truth. The
    // split measures it from the hole's first pixel; read as the occluder's shift, those 2 px
    // put the box nearer than it is and its colour edge elsewhere. The frame's attached holes
    // (the rod's) say by how much the sensor widens.
    let calib = Calibration::nyu_default();
    let mut scene = black_box_before_wall();
    push_grey_rod(&mut scene, -0.6, 1.5, 0.05);
    let mut frame = render_frame(&scene, &calib, &SensorModel::ideal(), 4);
    for v in 0..HEIGHT {
        let row = v * WIDTH;
        for u in 2..WIDTH {
            let starts = frame.ir_labels[row + u] == ATTACHED
                && frame.ir_labels[row + u - 1] == VALID
                && frame.ir_labels[row + u - 2] == VALID;
            if starts {
                for x in u - 2..u {
                    frame.ir_labels[row + x] = ATTACHED;
                    frame.raw[row + x] = 2047;
                }
            }
        }
    }
    let out = classify_rgb(&calib, &frame);
    // The box's shadow rows (columns 150..300; the rod's shadow is left of column 80).
    let (mut rows, mut split, mut err) = (0, 0, 0i64);
    for v in 0..HEIGHT {
        let count = |labels: &[u8]| {
            (150..300)
                .filter(|&u| labels[v * WIDTH + u] == ATTACHED)
                .count() as i64
        };
        let truth = count(&frame.ir_labels);
        if truth == 0 {
            continue;
        }
        // Near the box's top and bottom the RGB camera sees wall where the IR row has box, and
        // those rows are left alone.
        rows += 1;
        let n = count(&out.ir_labels);
        if n == 0 {
            continue;
        }
        assert!(
            (n - truth).abs() <= 2,
            "row {v}: {n} attached px, {truth} in truth"
        );
        split += 1;
        err += n - truth;
    }
    assert!(rows > 250, "the box spans {rows} rows");
    assert!(10 * split >= 9 * rows, "{split} of {rows} rows split");
    // Measured: every split row as wide as the truth; 2 px short in every row while the split
    // took the hole's width for the occluder's shift.
    let bias = err as f64 / split as f64;
    assert!(
        bias.abs() <= 0.5,
        "shadows {bias:+.2} px off the truth on average"
    );
}

#[test]
fn a_stray_valid_pixel_beside_a_black_box_is_no_lit_gap() {
    // The hand-computed black box (front face x = −0.2..0.2 m at 1 m, wall at 3 m) casts an
    // attached shadow of f·b·(1/1 − 1/3) = 29.1 px. The real sensor now and then reports a value
    // inside a shadow (the simulator: 0.2 % of shadow pixels). One such pixel at the wall's
    // depth, just left of the box, looks like the lit gap a thin occluder leaves between it and
    // its detached shadow; but a lit gap runs down the occluder's edge, and a stray pixel has no
    // twin in the rows near it.
    let calib = Calibration::nyu_default();
    let scene = black_box_before_wall();
    let mut frame = render_frame(&scene, &calib, &SensorModel::ideal(), 4);
    // A row well inside the box, where the split holds in the rows around it without the stray
    // pixel (measured: before this check, rows 197–203 were all detached with it).
    let v = 200;
    let row = v * WIDTH;
    let shadow = (0..WIDTH)
        .filter(|&u| frame.ir_labels[row + u] == ATTACHED)
        .collect::<Vec<_>>();
    let w = calib.fb() * (1.0 - 1.0 / 3.0);
    assert!(
        (shadow.len() as f64 - w).abs() <= 1.5,
        "{} px",
        shadow.len()
    );
    let (start, end) = (shadow[0], shadow[shadow.len() - 1] + 1);
    assert_eq!(
        frame.ir_labels[row + end],
        OTHER,
        "the box right of its shadow"
    );
    // The stray pixel, one column left of the box, at the wall's raw value.
    frame.raw[row + end - 1] = frame.raw[row + start - 1];
    frame.ir_labels[row + end - 1] = VALID;
    let out = classify_rgb(&calib, &frame);
    for y in v - 3..=v + 3 {
        let truth = count_in_row(&frame.ir_labels, y, ATTACHED);
        assert_eq!(
            count_in_row(&out.ir_labels, y, DETACHED),
            0,
            "row {y}: detached"
        );
        let n = count_in_row(&out.ir_labels, y, ATTACHED);
        assert!(
            n.abs_diff(truth) <= 2,
            "row {y}: {n} attached px, {truth} in truth"
        );
    }
}

#[test]
fn black_box_whose_hole_runs_on_into_a_rods_shadow_has_its_shadow_split_off() {
    // A black box 0.2 m wide at 1 m before a wall at 3 m: IR columns 313.04 ± 582.62·0.1 =
    // 254.8..371.3, and an attached shadow of f·b·(1/1 − 1/3) = 29.1 px left of it. Right of the
    // box, a grey rod (radius 2 cm, axis at x = 0.1742 m, z = 1.2 m) from column
    // 313.04 + 582.62·0.1542/1.2 = 387.9 casts its detached shadow f·b·(1/1.2 − 1/3) = 21.9 px to
    // the left, from about column 366: behind the box's right edge. So one hole runs from the
    // box's shadow over the box into the rod's shadow, about 160 px, with the wall on both sides.
    // The colour split's closed reading wants the box up to the hole's end and finds the wall's
    // colour over its last 14 px and the box's alignment strip; the hole is wider than any one
    // shadow on that wall (f·b/0.4 − f·b/3 = 94 px), so an occluder stands in it, and it is read
    // from the left: shadow, then box.
    let calib = Calibration::nyu_default();
    let mut scene = black_box_before_wall();
    if let umbra::synth::Shape::Box { half, .. } = &mut scene.objects[1].shape {
        half.x = 0.1;
    }
    push_grey_rod(&mut scene, 0.1742, 1.2, 0.02);
    let frame = render_frame(&scene, &calib, &SensorModel::ideal(), 4);
    let v = HEIGHT / 2 - 40;
    let row = &frame.raw[v * WIDTH..(v + 1) * WIDTH];
    let hole = (150..450).filter(|&u| row[u] == 2047).collect::<Vec<_>>();
    let (a, b) = (hole[0], hole[hole.len() - 1] + 1);
    assert_eq!(hole.len(), b - a, "one hole: {a}..{b}");
    assert!(
        (a as f64 - 225.7).abs() <= 2.0 && (b as f64 - 385.4).abs() <= 2.0,
        "{a}..{b}"
    );
    assert_eq!(
        count_in_row(&frame.ir_labels, v, DETACHED),
        (371..b)
            .filter(|&u| frame.ir_labels[v * WIDTH + u] == DETACHED)
            .count(),
        "the rod's shadow is the hole's right end"
    );
    let w = calib.fb() * (1.0 - 1.0 / 3.0);
    let out = classify_rgb(&calib, &frame);
    let (mut rows, mut split) = (0, 0);
    for y in 0..HEIGHT {
        if count_in_row(&frame.ir_labels, y, ATTACHED) == 0 {
            continue;
        }
        rows += 1;
        let n = count_in_row(&out.ir_labels, y, ATTACHED) as f64;
        split += usize::from((n - w).abs() <= 2.5);
    }
    // Measured: 290 of 292 rows; none when a closed hole was never read as open.
    assert!(rows > 100, "the box spans {rows} rows");
    assert!(
        10 * split >= 9 * rows,
        "{split} of {rows} rows split at {w:.1} px"
    );
}

#[test]
fn black_box_behind_a_thin_rod_keeps_its_face_out_of_the_rods_shadow() {
    // The black box 0.2 m wide at 1 m before a wall at 3 m: IR columns 313.04 ± 582.62·0.1 =
    // 254.8..371.3, its attached shadow f·b·(1/1 − 1/3) = 29.1 px left of it, from 225.7. Before
    // the box, a grey rod (radius 1 cm, axis at x = −0.055 m, z = 0.8 m) from column
    // 313.04 + 582.62·(−0.065/0.8) = 265.7, 14.6 px wide. In the box's rows one hole runs from
    // 225.7 to the rod, 40.0 px: as wide as the rod's own attached shadow on the wall would be
    // by eq. (3), f·b·(1/0.8 − 1/3) = 40.0 px. But only 29.1 px of it are shadow on the wall
    // (the rod's and the box's); the rest, 254.8..265.7, is the box's face, which returns no
    // depth lit or not: OTHER. The RGB camera sees the black box there, left of the rod.
    let calib = Calibration::nyu_default();
    let mut scene = black_box_before_wall();
    if let umbra::synth::Shape::Box { half, .. } = &mut scene.objects[1].shape {
        half.x = 0.1;
    }
    push_grey_rod(&mut scene, -0.055, 0.8, 0.01);
    let frame = render_frame(&scene, &calib, &SensorModel::ideal(), 5);
    let depth_only = classify(&calib, &frame);
    let out = classify_rgb(&calib, &frame);
    let (face, shadow) = (256..265, 227..254);
    let count = |labels: &[u8], v: usize, us: std::ops::Range<usize>, codes: &[u8]| {
        us.filter(|&u| codes.contains(&labels[v * WIDTH + u]))
            .count()
    };
    let (mut rows, mut face_px, mut fooled, mut attached) = (0, 0, 0, 0);
    let (mut shadow_px, mut kept) = (0, 0);
    for v in 1..HEIGHT - 1 {
        // The box's rows, by the scene: its face left of the rod is OTHER, the wall left of it
        // shadow.
        let truth_face = count(&frame.ir_labels, v, face.clone(), &[OTHER]);
        let truth_shadow = count(&frame.ir_labels, v, shadow.clone(), &[ATTACHED, DETACHED]);
        if truth_face != face.len() || truth_shadow != shadow.len() {
            continue;
        }
        rows += 1;
        face_px += face.len();
        fooled += count(&depth_only.ir_labels, v, face.clone(), &[ATTACHED]);
        attached += count(&out.ir_labels, v, face.clone(), &[ATTACHED]);
        shadow_px += shadow.len();
        kept += count(&out.ir_labels, v, shadow.clone(), &[ATTACHED, DETACHED]);
    }
    assert!(rows > 250, "the box spans {rows} rows");
    // The trap is real: depth alone calls the face part of the rod's shadow (in the box's top
    // and bottom 40 rows it calls the whole hole detached, from the rod's shadow on the wall
    // above and below; measured: 1908 of 2628 px attached).
    assert!(
        3 * fooled >= 2 * face_px,
        "depth alone: {fooled} of {face_px} px attached"
    );
    // With the colour, the face is OTHER but in those top and bottom 40 rows, where the rod's
    // shadow above and below makes the whole hole its shadow, touching the rod: attached there
    // (detached before the rule of SPEC §1 was kept; measured: 720 px, 9 a row).
    assert!(
        attached <= 9 * 80 + face_px / 100,
        "{attached} of {face_px} face px attached"
    );
    assert!(
        100 * kept >= 99 * shadow_px,
        "{kept} of {shadow_px} shadow px kept"
    );
}

/// Rows `rows` of `frame` whose columns `us` are all DETACHED by the scene, and how many of
/// those pixels `labels` calls DETACHED.
fn detached_in(
    frame: &SynthFrame,
    labels: &[u8],
    rows: std::ops::Range<usize>,
    us: std::ops::Range<usize>,
) -> (usize, usize) {
    let (mut truth, mut found) = (0, 0);
    for v in rows {
        let at = |l: &[u8], u: usize| l[v * WIDTH + u] == DETACHED;
        if us.clone().all(|u| at(&frame.ir_labels, u)) {
            truth += us.len();
            found += us.clone().filter(|&u| at(labels, u)).count();
        }
    }
    (truth, found)
}

#[test]
fn chained_black_rods_shadow_half_hidden_by_a_nearer_rod_is_detached() {
    // The two chained black rods (7 px wide at 1 m before a wall at 3 m, IR columns 309.5..316.5
    // and 325.5..332.5, their shadows f·b·(1/1 − 1/3) = 29.1 px left: 280.4..287.4 and
    // 296.4..303.4), and a grey rod at 2 m (radius 11.16 mm, axis at x = −0.11256 m: columns
    // 277.0..283.5) hiding the left part of rod A's shadow: its visible part, 283.5..287.4, has
    // a nearer surface on its left and the wall on its right.
    let calib = Calibration::nyu_default();
    let mut scene = Scene::rod_before_wall(0.0, 1.0, 0.006, 3.0);
    scene.objects[1].material = umbra::synth::Material::black();
    let rod_b = Scene::rod_before_wall(16.0 / calib.depth.fx, 1.0, 0.006, 3.0).objects[1].clone();
    scene.push("rod", rod_b.shape, umbra::synth::Material::black());
    push_grey_rod(&mut scene, -0.11256, 2.0, 0.01116);
    let frame = render_frame(&scene, &calib, &SensorModel::ideal(), 6);
    let out = classify_rgb(&calib, &frame);
    let (truth, found) = detached_in(&frame, &out.ir_labels, 1..HEIGHT - 1, 284..287);
    // Measured: 1434 of 1434 px; none when only holes with one background on both sides were
    // shadows.
    assert!(truth > 3 * 400, "the shadow shows in {} rows", truth / 3);
    assert!(10 * found >= 9 * truth, "{found} of {truth} px detached");
}

#[test]
fn black_rod_before_a_boxs_edge_has_its_shadow_on_the_box_detached() {
    // A grey box whose front face (2 m) ends at x = 0 (IR column 313.04) before a wall at 3 m,
    // and a black rod (radius 1 cm) at 1.2 m, axis at x = −0.00626 m: columns
    // 313.04 + 582.62·(−0.00626 ± 0.01)/1.2 = 305.1..314.8, across the box's edge. Its shadow
    // falls on the box, f·b·(1/1.2 − 1/2) = 14.6 px left: 290.5..300.2, then a lit gap of 4.9 px:
    // detached. The rod's hole has the box on its left and the farther wall on its right.
    let calib = Calibration::nyu_default();
    let mut scene = Scene::rod_before_wall(-0.00626, 1.2, 0.01, 3.0);
    scene.objects[1].material = umbra::synth::Material::black();
    scene.push(
        "box",
        umbra::synth::Shape::Box {
            centre: umbra::synth::V3::new(-0.75, 0.0, 2.05),
            half: umbra::synth::V3::new(0.75, 3.0, 0.05),
            yaw: 0.0,
        },
        umbra::synth::Material::matte([0.45, 0.5, 0.6]),
    );
    let frame = render_frame(&scene, &calib, &SensorModel::ideal(), 6);
    let out = classify_rgb(&calib, &frame);
    let (truth, found) = detached_in(&frame, &out.ir_labels, 1..HEIGHT - 1, 292..299);
    // Measured: 3346 of 3346 px; none when an occluder's hole had to have one background on
    // both sides.
    assert!(truth > 7 * 400, "the shadow shows in {} rows", truth / 7);
    assert!(10 * found >= 9 * truth, "{found} of {truth} px detached");
}

#[test]
fn glossy_box_of_modest_contrast_has_its_shadow_split_off() {
    // The hand-computed box, glossy (no depth) and grey-blue on the pale wall: in the RGB image
    // it differs from the wall by 90 to 120 (sum of |ΔR|, |ΔG|, |ΔB|), plainly another surface
    // but less than twice the step that tells background from not (60). Its shadow is split off
    // all the same, at the hand-computed f·b·(1/1 − 1/3) = 29.1 px.
    glossy_box_shadow_split([0.42, 0.56, 0.82], 4, 90..120);
}

/// The hand-computed box, glossy, of `colour`, rendered with `seed`: its RGB contrast with the
/// wall (sum of |ΔR|, |ΔG|, |ΔB|) must lie in `contrast`, and its shadow is split off row by row
/// ([`depthless_box_split`]), with attached F1 at least 0.9.
fn glossy_box_shadow_split(colour: [f64; 3], seed: u64, contrast: std::ops::Range<u32>) {
    glossy_box_shadow_split_seen_by(colour, &SensorModel::ideal(), seed, contrast);
}

/// [`glossy_box_shadow_split`] with the RGB image of `sensor`.
fn glossy_box_shadow_split_seen_by(
    colour: [f64; 3],
    sensor: &SensorModel,
    seed: u64,
    contrast: std::ops::Range<u32>,
) {
    let glossy = umbra::synth::Material::glossy(colour);
    let (frame, out) = depthless_box_split(glossy, 0.0, |_| 1.0, sensor, seed);
    // RGB columns 150 and 280 of the middle row: the wall left of the shadow, the box's face.
    let row = HEIGHT / 2 * WIDTH;
    let seen = rgb_distance(&frame.rgb, row + 150, row + 280);
    assert!(contrast.contains(&seen), "contrast {seen}");
    let mut c = Confusion::default();
    c.add(&frame.ir_labels, &out.ir_labels);
    at_least(&c, Some(ATTACHED), 0.9, "IR attached of a glossy box");
}

#[test]
fn glossy_box_shadow_is_split_off_through_a_noisy_rgb_camera() {
    // The box of modest contrast again, its RGB image with noise of σ = 5 per channel (the
    // simulator's is 2; the real frame's smooth regions show 1.3 to 4.8): single pixels then stray from the wall's colour by 35 to 50 on
    // average, as far as the shadow test's limit, and 55 of 292 rows were left unsplit. The
    // shadow's mean colour, and three-column probes, see through the noise.
    let noisy = SensorModel {
        rgb_noise_sigma: 8.0,
        ..SensorModel::ideal()
    };
    glossy_box_shadow_split_seen_by([0.42, 0.56, 0.82], &noisy, 4, 60..140);
}

#[test]
fn shadow_along_a_depthless_cylinders_slanted_edge_is_split_through_a_soft_lens() {
    // A dark grey cylinder that returns no depth (r = 12 cm, 1 m long) at 1.5 m before the wall
    // at 3 m, its axis tilted 8° from the horizontal: along its lower edge each row's hole holds
    // its attached shadow (f·b·(1/1.5 − 1/3) = 14.6 px) and then the cylinder. Through a soft
    // lens ([1 2 1]/4 each way) the row above shows the cylinder over the shadow's last seven
    // columns (the edge moves 7.1 px a row), and they blend into this row's: the shadow's mean
    // colour strayed past the background's step in many rows, which stayed OTHER.
    let calib = Calibration::nyu_default();
    let angle = 8f64.to_radians();
    let scene = cylinder_at_1_5_m_before_a_wall(
        (angle.cos(), angle.sin()),
        (0.12, 0.5),
        umbra::synth::Material {
            colour: [0.3, 0.3, 0.33],
            ..umbra::synth::Material::black()
        },
    );
    let mut frame = render_frame(&scene, &calib, &SensorModel::ideal(), 7);
    frame.rgb = umbra::synth::soften(&frame.rgb);
    let out = classify_rgb(&calib, &frame);
    let mut c = Confusion::default();
    c.add(&frame.ir_labels, &out.ir_labels);
    // Measured: recall 0.771 (0.661 with the blended columns read); precision 0.990. The rest
    // are rows whose split took the blend for the cylinder: 7 px of shadow instead of 15.
    let s = c.class(ATTACHED);
    let recall = s.recall.unwrap_or(0.0);
    assert!(recall >= 0.72, "IR attached recall {recall:.3}");
    at_least(
        &c,
        Some(ATTACHED),
        0.84,
        "IR attached along a slanted depthless cylinder",
    );
}

#[test]
fn narrow_shadow_of_a_black_rod_is_split_off_through_a_soft_lens() {
    // A black rod (r = 5 cm) at 2.3 m before the wall at 3 m: its attached shadow is about 5 px
    // wide, three RGB columns. Through a soft lens ([1 2 1]/4 each way) the column beside the rod
    // blends wall and black, so the split explains only one or two more columns than "no
    // shadow"; it used to ask for two more than half the shadow's columns and split no row.
    let calib = Calibration::nyu_default();
    let mut scene = Scene::rod_before_wall(0.0, 2.3, 0.05, 3.0);
    scene.objects[1].material = umbra::synth::Material::black();
    let mut frame = render_frame(&scene, &calib, &SensorModel::ideal(), 6);
    frame.rgb = umbra::synth::soften(&frame.rgb);
    let out = classify_rgb(&calib, &frame);
    let (rows, split) = attached_rows(&frame, &out.ir_labels, |v, n, truth| {
        assert!(
            n == 0 || n.abs_diff(truth) <= 2,
            "row {v}: {n} attached px, simulator {truth}"
        );
    });
    assert!(rows > 400, "the rod spans {rows} rows");
    assert!(10 * split >= 9 * rows, "{split} of {rows} rows split");
}

#[test]
fn black_box_shadow_through_a_soft_lens_is_split_as_in_a_sharp_image() {
    // The hand-computed black box (front face at 1 m, wall at 3 m: f·b·(1/1 − 1/3) = 29.1 px of
    // shadow), its RGB image sharp and through a soft lens ([1 2 1]/4 each way). The real
    // frame's strong edges rise over two pixels (10 % to 90 %), as the softened image's do, the
    // simulator's over none. The column where the box's edge falls then blends wall and box,
    // and the edge lies where the blend is half way: the column is the wall's side while it is
    // less than half as far from the wall as the column beyond it.
    let calib = Calibration::nyu_default();
    let frame = render_frame(&black_box_before_wall(), &calib, &SensorModel::ideal(), 4);
    let sharp = classify_rgb(&calib, &frame);
    let soft_frame = SynthFrame {
        rgb: umbra::synth::soften(&frame.rgb),
        ..frame.clone()
    };
    let soft = classify_rgb(&calib, &soft_frame);
    let w = calib.fb() * (1.0 - 1.0 / 3.0);
    let (mut split, mut diff) = (0, 0i64);
    let (rows, _) = attached_rows(&frame, &soft.ir_labels, |v, n, _| {
        let m = count_in_row(&sharp.ir_labels, v, ATTACHED);
        if n > 0 && m > 0 {
            assert!(
                (n as f64 - w).abs() <= 2.5,
                "row {v}: {n} attached px, hand-computed {w:.2}"
            );
            split += 1;
            diff += n as i64 - m as i64;
        }
    });
    assert!(rows > 250, "the box spans {rows} rows");
    assert!(10 * split >= 9 * rows, "{split} of {rows} rows split");
    // Measured: the same width in every row (with the blend counted as box, 2 px narrower in
    // nearly every row: 26 px against 28, and 3.1 px under the hand-computed width).
    let bias = diff as f64 / split as f64;
    assert!(
        bias.abs() <= 0.3,
        "{bias:+.2} px against the sharp image on average"
    );
}

#[test]
fn glossy_box_shadow_is_split_off_in_a_dim_colour_image() {
    // The hand-computed box, glossy and grey, its RGB image at 45 % of the brightness (a dim
    // room, an auto-exposure that keeps it dark: the real frame's median is 81 against 208
    // here). Every colour difference shrinks with it, the box's from the wall from 117 to about
    // 54, and the colour steps must shrink too: with the bright room's no row was split (290 of
    // 292 now).
    let dim = SensorModel {
        rgb_gain: 0.45,
        ..SensorModel::ideal()
    };
    glossy_box_shadow_split_seen_by([0.5, 0.5, 0.48], &dim, 4, 45..65);
}

#[test]
fn pale_glossy_box_shadow_is_split_off_left_of_a_nearer_rod() {
    // The hand-computed box, glossy (no depth) and a pale blue near the wall's grey, a grey rod
    // (r = 3 cm) standing before it at 0.8 m: in every row of the box its hole runs from the
    // shadow into the box and ends at the rod, so it is read from its left (an open hole). The
    // box's columns stray from the wall by 1.2 to 1.5 colour steps, within the 1.5 steps that
    // a sample of the wall left of the hole excuses, and every column was read as wall: no row
    // was split. The box starts at a step from the column before it, which the wall's shading
    // and noise do not make; past it only a colour of the wall plainly unlike its own (a
    // pattern's other hue) excuses a column.
    let calib = Calibration::nyu_default();
    let mut scene = Scene::box_before_wall(1.0, 3.0);
    scene.objects[1].material = umbra::synth::Material::glossy([0.7, 0.72, 0.8]);
    push_grey_rod(&mut scene, 0.05, 0.8, 0.03);
    let frame = render_frame(&scene, &calib, &SensorModel::ideal(), 4);
    let out = classify_rgb(&calib, &frame);
    // By hand: f·b·(1/1 − 1/3) = 29.13 px of shadow in each of the box's rows (the rod's own
    // shadow falls on the box there, which is OTHER).
    let w = calib.fb() * (1.0 - 1.0 / 3.0);
    let (mut rows, mut split) = (0, 0);
    for v in 0..HEIGHT {
        if count_in_row(&frame.ir_labels, v, OTHER) == 0 {
            continue;
        }
        rows += 1;
        let n = count_in_row(&out.ir_labels, v, ATTACHED);
        if n > 0 {
            assert!(
                (n as f64 - w).abs() <= 2.5,
                "row {v}: {n} attached px, hand-computed {w:.2}"
            );
            split += 1;
        }
    }
    assert!(rows > 250, "the box spans {rows} rows");
    assert!(10 * split >= 9 * rows, "{split} of {rows} rows split");
}

#[test]
fn glossy_box_nearly_as_bright_as_the_wall_has_its_shadow_split_off_by_hue() {
    // The hand-computed box, glossy (no depth), nearly as bright as the pale wall but more
    // yellow: in the RGB image it differs from the wall by a sum of |ΔR|, |ΔG|, |ΔB| of 60 to 90,
    // other than background but not plainly so by brightness alone; by its hue, (R − G, B − G),
    // much more. Its shadow is split off at the hand-computed
    // f·b·(1/1 − 1/3) = 29.1 px, in every row (38 of 292 rows were split when occluders were
    // told from the wall by brightness alone).
    glossy_box_shadow_split([0.8, 0.62, 0.42], 5, 60..90);
}

#[test]
fn glossy_box_as_bright_as_the_wall_has_its_shadow_split_off_by_hue() {
    // As above, a glossy box as bright as the wall, bluer (0.70, 0.72, 0.90 against 0.80, 0.78,
    // 0.70): by |ΔR|, |ΔG|, |ΔB| less than 60 from it, under the step by which brightness alone
    // told background from not, so every column of it looked like wall and no row was split; its
    // hue tells it apart.
    glossy_box_shadow_split([0.7, 0.72, 0.9], 5, 0..60);
}

/// Renders three frames of the random complex scene `seed` (one with a region beyond range) and
/// counts the IR pixels the simulator calls OTHER that the classifier, with the RGB image, calls
/// attached.
fn other_called_attached_beyond_range(seed: u64) -> usize {
    let calib = Calibration::nyu_default();
    let scene = random_scene(Category::Complex, seed);
    assert!(scene.description.contains("beyond range"));
    let mut wrong = 0;
    for k in 0..3 {
        let frame = render_frame(
            &scene.at_frame(k),
            &calib,
            &sensor_for(Category::Complex),
            k as u64,
        );
        let out = classify_rgb(&calib, &frame);
        wrong += frame
            .ir_labels
            .iter()
            .zip(&out.ir_labels)
            .filter(|&(&t, &l)| t == OTHER && l == ATTACHED)
            .count();
    }
    wrong
}

#[test]
fn nearer_box_seen_over_its_own_shadow_is_no_depthless_occluder() {
    // A random complex scene (seed 424243272747) that a weaker colour test broke: a box at 1.06 m
    // before a wall slanting out of range. Its attached shadow falls where the wall is beyond
    // range, a hole that is OTHER (SPEC §1) between the wall and the box. The RGB camera, 2.5 cm to
    // the right, sees the box's own colour over the right third of that hole: were it read as a
    // depthless occluder, the hole's left part would become a shadow.
    let wrong = other_called_attached_beyond_range(424_243_272_747);
    // Measured: 514 (other holes of the scene); 6306 when the box's colour is read as an occluder.
    assert!(wrong < 1000, "{wrong} OTHER pixels called attached");
}

#[test]
fn wall_beside_a_grey_object_of_its_brightness_is_no_shadow() {
    // A random complex scene (seed 8675335025948: a beige wall slanting out of range on the
    // left, a grey cylinder before it). In some rows one hole runs from the wall over the part
    // beyond range to the cylinder's side, and the RGB camera sees beige, then grey. By brightness
    // alone the grey is near enough the beige (a sum of |ΔR|, |ΔG|, |ΔB| of about 75) that the
    // hole's first 50 columns read as background, a shadow; its hue, (R − G, B − G) = (0, 0)
    // against (+10, −22), says it is another surface.
    let wrong = other_called_attached_beyond_range(8_675_335_025_948);
    // Measured: 679 (other holes of the scene); 2689 when the colours were compared by
    // brightness alone.
    assert!(wrong < 1000, "{wrong} OTHER pixels called attached");
}

#[test]
fn shadow_split_off_by_colour_is_other_where_its_wall_leaves_the_range() {
    // A random complex scene (seed 1618004873): a wall slanting steeply out of range behind a row
    // of cylinders and rods. Between the last measured part of the wall and a rod, the holes are
    // the wall beyond range. The colour split read some of those rows as a shadow and an occluder
    // (the RGB camera sees the wall there, lit); a shadow there would fall beyond the range, so
    // it is OTHER, as the scanline already said; where the wall leaves the range within the
    // first half of such a shadow, the rest is no shadow either: the colour change that ended it
    // is the wall beyond range, not an occluder.
    let wrong = other_called_attached_beyond_range(1_618_004_873);
    // Measured: 977 (other holes of the scene); 2472 while the in-range part of such a shadow
    // was kept, 11 784 before the split tested the range.
    assert!(wrong < 1500, "{wrong} OTHER pixels called attached");
}

#[test]
fn alignment_strips_are_bridged_across_rows_the_warp_misses() {
    // A random complex scene (seed 5150015487: spheres and cylinders before a slanted wall) whose
    // alignment strips the warp leaves broken in runs of one to three rows. Strips are solids in
    // the RGB view as shadows are in the IR view: a run of OTHER rows between the same label
    // above and below takes it. Measured: F1 0.781, precision 0.947 (0.729 and 0.942 without).
    let calib = Calibration::nyu_default();
    let scene = random_scene(Category::Complex, 5_150_015_487);
    let mut c = Confusion::default();
    for k in 0..3 {
        let frame = render_frame(
            &scene.at_frame(k),
            &calib,
            &sensor_for(Category::Complex),
            k as u64,
        );
        c.add(&frame.rgb_labels, &classify_rgb(&calib, &frame).rgb_labels);
    }
    at_least(&c, Some(ALIGNMENT), 0.76, "RGB alignment");
    let precision = c.class(ALIGNMENT).precision.unwrap_or(0.0);
    assert!(precision >= 0.93, "RGB alignment precision {precision:.3}");
}

#[test]
fn black_box_split_survives_the_sensors_ragged_shadow_edge() {
    // The same black box through the Kinect sensor model: its widening moves each row's hole
    // start by 0–3 px at random, so the shadow width changes from row to row while the box's
    // edge does not. Nearly every row must still be split, at f·b·(1/1 − 1/3) = 29.1 px plus
    // the widening.
    let calib = Calibration::nyu_default();
    let scene = black_box_before_wall();
    let frame = render_frame(&scene, &calib, &SensorModel::kinect(), 11);
    let out = classify_rgb(&calib, &frame);
    let w = calib.fb() * (1.0 - 1.0 / 3.0);
    let (rows, split) = attached_rows(&frame, &out.ir_labels, |v, n, _| {
        assert!(
            n == 0 || (n as f64 >= w - 2.5 && n as f64 <= w + 5.5),
            "row {v}: {n} attached px, hand-computed {w:.2} plus 0–3 px of widening"
        );
    });
    assert!(rows > 100, "the box spans {rows} rows");
    assert!(10 * split >= 9 * rows, "{split} of {rows} rows split");
}

#[test]
fn black_box_across_the_right_border_is_split_from_its_left_side() {
    // Box from x = 0.3 to 0.7 m at 1 m: the image ends at (640 − cx)/fx = 0.56 m, so the hole runs
    // off the border and only the wall on its left bounds it. The projector (x = 0.075 m) sees the
    // box's left face (x = 0.3 m, z = 1..1.2 m, |y| ≤ 0.25 m), so the shadow is cast by the far end
    // of that face in the row's plane y = z·(v − cy)/fy: z = 1.2 m (21.8 px) in the middle rows,
    // less towards the top and bottom, where the plane leaves the face at |y| = 0.25 m.
    let calib = Calibration::nyu_default();
    let z_edge = |v: usize| {
        let slope = ((v as f64 - calib.depth.cy) / calib.depth.fy).abs();
        (0.25 / slope).clamp(1.0, 1.2)
    };
    let (frame, out) = black_box_split(0.5, z_edge, 5);
    let mut c = Confusion::default();
    c.add(&frame.rgb_labels, &out.rgb_labels);
    at_least(
        &c,
        Some(ATTACHED),
        0.9,
        "RGB attached of a black box at the border",
    );
}

#[test]
fn black_panel_across_the_right_border_and_the_whole_height_keeps_its_shadow() {
    // A black panel 10 cm thick from x = 0.3 m to beyond the right border (0.56 m at 1 m), 1.0 to
    // 1.1 m away and taller than the view, before a wall at 3 m, the frame's farthest surface:
    // its shadow, cast by its left face's far edge, f·b·(1/1.1 − 1/3) = 25.2 px (and the
    // sensor's widening), runs from the frame's top to its bottom, and no row above ever
    // measures its columns, as none measures a wall that leaves the sensor's range there.
    // The wall left of it is measured, and in range: the shadow is a shadow. (A rule that read
    // such holes as a wall leaving the range, tried on 2026-12-04, lost all of it under a
    // noise-free sensor.) Measured: attached F1 0.967 (precision 0.939: the split's edge a pixel
    // or two into the panel's hole).
    let mut scene = before_a_pale_wall("black panel across the right border");
    push_black_box(&mut scene, "panel", [0.8, 0.0, 1.05], [0.5, 3.0, 0.05]);
    let (_, with_rgb) = with_and_without_colour(&scene, 90..93, false, |frame| {
        let row = &frame.ir_labels[240 * WIDTH..241 * WIDTH];
        let shadow = row.iter().filter(|&&l| l == ATTACHED).count();
        assert!(
            (25..=30).contains(&shadow),
            "the simulator's shadow: {shadow} px"
        );
    });
    at_least(
        &with_rgb,
        Some(ATTACHED),
        0.95,
        "IR attached of a black panel across the right border",
    );
}

#[test]
fn black_box_at_the_right_border_keeps_its_shadow_across_a_striped_wall() {
    // A black board 1 cm thick, 1 m away, from x = 0.2 m to past the right border (its left
    // edge at column cx + fx·0.2/1.01), before a wall at 3 m striped every 12 cm with 6 cm of a
    // darker tone of the wall's own colour: one hole from the shadow's start to the border. The
    // shadow is f·b·(1/1.01 − 1/3) px wide (28.7 px), from x = 0.46 m on the wall, and a dark
    // stripe crosses it at x = 0.50–0.56 m. Read from the left, the stripe looks like the
    // board's first columns; but the wall shows that tone left of the hole too (a stripe at
    // 0.38–0.44 m), so it is wall. Attached F1 0.450 before the wall's colours were sampled
    // (recall 0.29), 0.989 after (floor 0.9).
    let mut scene = Scene::new("black box at the right border before a striped wall");
    scene.push(
        "wall",
        umbra::synth::scene::wall(3.0),
        umbra::synth::Material::matte([0.6, 0.42, 0.3]),
    );
    for k in -2..12 {
        let x = 0.26 + 0.12 * f64::from(k);
        push_box(
            &mut scene,
            "poster",
            [x, 0.0, 2.998],
            [0.03, 3.0, 0.002],
            umbra::synth::Material::matte([0.3, 0.21, 0.15]),
        );
    }
    push_black_box(&mut scene, "box", [0.7, 0.0, 1.005], [0.5, 0.3, 0.005]);
    let calib = Calibration::nyu_default();
    // Cast by the box's far left edge, 1.01 m away (the camera sees its 1 cm side face).
    let start =
        calib.depth.cx + calib.depth.fx * 0.2 / 1.01 - calib.fb() * (1.0 / 1.01 - 1.0 / 3.0);
    let (_, with_rgb) = with_and_without_colour(&scene, 60..62, false, |frame| {
        let row = &frame.ir_labels[240 * WIDTH..241 * WIDTH];
        let cols: Vec<usize> = (0..WIDTH).filter(|&u| row[u] == ATTACHED).collect();
        assert!(
            cols.len() >= 29 && (cols[0] as f64 - start).abs() <= 4.0,
            "the scene's shadow {cols:?}, by hand from {start:.1}"
        );
    });
    at_least(
        &with_rgb,
        Some(ATTACHED),
        0.9,
        "IR attached of a black box before a striped wall",
    );
}

/// A black pipe (r = 1.5 cm, `2·half_len` long) centred at 1 m before a wall at 3 m, its axis
/// rising `slope` per unit across: its edge moves 1/slope px a row.
fn black_pipe_before_wall(slope: f64, half_len: f64) -> Scene {
    let mut scene = before_a_pale_wall("black pipe slanting before a wall");
    scene.push(
        "pipe",
        umbra::synth::Shape::Cylinder {
            centre: umbra::synth::V3::new(0.0, 0.0, 1.0),
            axis: umbra::synth::V3::new(1.0, slope, 0.0).normalize(),
            radius: 0.015,
            half_len,
        },
        umbra::synth::Material::black(),
    );
    scene
}

#[test]
fn black_pipe_slanting_five_pixels_a_row_still_has_its_shadow_split_off() {
    // A black pipe (r = 1.5 cm, 60 cm long) at 1 m before a wall at 3 m, its axis 11° from
    // horizontal: its edge moves 5 px a row, more than two rows' splits may differ when one
    // neighbour has to agree; a straight edge through three rows is what the rows must show. By
    // hand each row's shadow is f·b·(1/1 − 1/3) = 29.1 px wide. The RGB row nearest an IR row
    // lies up to half a row off it, which along this edge is ±2.5 RGB columns: ±3 px of width.
    // (Rows are still lost where the long hole's two sides differ in shading by more than the
    // closed reading allows.)
    let calib = Calibration::nyu_default();
    let scene = black_pipe_before_wall(0.2, 0.3);
    let frame = render_frame(&scene, &calib, &SensorModel::ideal(), 12);
    let out = classify_rgb(&calib, &frame);
    let w = calib.fb() * (1.0 - 1.0 / 3.0);
    let (mut rows, mut split) = (0, 0);
    for v in 0..HEIGHT {
        if count_in_row(&frame.ir_labels, v, ATTACHED) < 20 {
            continue; // the pipe's rims and ends: slivers, not this test's subject
        }
        rows += 1;
        let n = count_in_row(&out.ir_labels, v, ATTACHED);
        split += usize::from((n as f64 - w).abs() <= 4.5);
    }
    assert!(rows >= 60, "the pipe's shadow spans {rows} rows");
    // Measured: 68 of 76 rows, F1 0.925 (one neighbour alone: 27 rows, F1 0.51).
    assert!(5 * split >= 4 * rows, "{split} of {rows} rows split");
    let mut c = Confusion::default();
    c.add(&frame.ir_labels, &out.ir_labels);
    at_least(
        &c,
        Some(ATTACHED),
        0.9,
        "IR attached of a slanting black pipe",
    );
}

#[test]
fn black_pipe_slanting_eight_pixels_a_row_into_a_nearer_board_is_split_off() {
    // A black pipe (r = 1.5 cm) at 1 m before a wall at 3 m, 7° from horizontal, so its edge
    // moves 8 px a row; its right end runs behind a board at 0.8 m, so each hole is open (the
    // board, not the wall, closes it). The rows above and below must show the hole too, and
    // theirs starts 8 px off this row's. By hand each row's shadow is f·b·(1/1 − 1/3) = 29.1 px
    // wide; the board's edge (x = 0.15 m at 0.8 m) is at column cx + fx·0.15/0.8 = 422 and its
    // own shadow 40 px wide, so left of column 370 every shadow pixel is the pipe's.
    let calib = Calibration::nyu_default();
    let mut scene = black_pipe_before_wall(0.125, 0.4);
    scene.push(
        "board",
        umbra::synth::Shape::Box {
            centre: umbra::synth::V3::new(0.35, 0.0, 0.8),
            half: umbra::synth::V3::new(0.2, 0.3, 0.01),
            yaw: 0.0,
        },
        umbra::synth::Material::matte([0.2, 0.4, 0.8]),
    );
    let frame = render_frame(&scene, &calib, &SensorModel::ideal(), 13);
    let out = classify_rgb(&calib, &frame);
    let w = calib.fb() * (1.0 - 1.0 / 3.0);
    let pipe_side = |labels: &[u8], v: usize| {
        labels[v * WIDTH..v * WIDTH + 370]
            .iter()
            .filter(|&&l| l == ATTACHED)
            .count()
    };
    let (mut rows, mut split) = (0, 0);
    for v in 0..HEIGHT {
        if pipe_side(&frame.ir_labels, v) < 20 {
            continue; // the pipe's rims and ends: slivers, not this test's subject
        }
        rows += 1;
        split += usize::from((pipe_side(&out.ir_labels, v) as f64 - w).abs() <= 4.5);
    }
    assert!(rows >= 30, "the pipe's shadow spans {rows} rows");
    // Measured: 38 of 51 rows (24 when the rows around are searched only near the hole's start).
    // The rest are lost where two IR rows take the same RGB row (it has 0.89 times as many):
    // along this edge their splits then land 8 px apart and no neighbour agrees.
    assert!(3 * split >= 2 * rows, "{split} of {rows} rows split");
}

#[test]
fn black_box_shadow_beside_a_nearer_box_is_split_against_the_wall_right_of_it() {
    // The black box of the hand-computed scene, and a thin matte board at 0.7 m whose right edge
    // hides the left end of the black box's shadow: the hole has the board on its left and the
    // wall only on its right. By hand: the board's edge (x = −0.166 m at z = 0.72 m) is at column
    // cx + fx·(−0.166/0.72) = 178.7, the black box's (−0.2 m at 1 m) at 196.5, so 17.8 px of the
    // 29.1 px shadow show. The width that shows is no measure of the box's depth here; the box's
    // right edge is (the RGB camera sees it f_rgb·0.025/1 m = 13 px left of where the IR camera
    // does), and with it the colour edge fixes where the box starts.
    let calib = Calibration::nyu_default();
    let mut scene = black_box_before_wall();
    scene.push(
        "board",
        umbra::synth::Shape::Box {
            centre: umbra::synth::V3::new(-0.266, 0.0, 0.71),
            half: umbra::synth::V3::new(0.1, 0.3, 0.01),
            yaw: 0.0,
        },
        umbra::synth::Material::matte([0.2, 0.4, 0.8]),
    );
    let frame = render_frame(&scene, &calib, &SensorModel::ideal(), 7);
    let out = classify_rgb(&calib, &frame);
    let visible = calib.depth.cx + calib.depth.fx * (-0.166 / 0.72);
    let visible = calib.depth.cx - calib.depth.fx * 0.2 - visible;
    // The board's own shadow lies left of it: only columns right of the board count.
    let count = |labels: &[u8], v: usize| {
        labels[v * WIDTH + 170..v * WIDTH + 320]
            .iter()
            .filter(|&&l| l == ATTACHED)
            .count()
    };
    let (mut rows, mut split) = (0, 0);
    for v in 0..HEIGHT {
        let truth = count(&frame.ir_labels, v);
        let n = count(&out.ir_labels, v);
        if truth == 0 {
            assert_eq!(n, 0, "row {v}: attached pixels where the box casts none");
            continue;
        }
        rows += 1;
        if n > 0 {
            split += 1;
            assert!(
                (n as f64 - visible).abs() <= 2.5,
                "row {v}: {n} attached px, {visible:.1} visible"
            );
        }
    }
    assert!(
        rows > 100 && 10 * split >= 8 * rows,
        "{split} of {rows} rows split"
    );
}

#[test]
fn black_box_across_the_left_border_stands_at_its_depth_in_the_rgb_view() {
    // Box from x = −0.75 to −0.35 m at 1 m, across the left border: its hole starts at the border,
    // so no shadow can be split off, and depth alone warps it as far as the wall. Its right edge
    // tells its depth: the IR camera sees the box's right face, so the edge is its back corner
    // (−0.35 m, 1.2 m), and the RGB camera 2.5 cm to the right sees wall past it in a strip of
    // f_rgb·0.025·(1/1.2 − 1/3) = 6.5 px per row, the alignment shadow.
    let calib = Calibration::nyu_default();
    let mut scene = black_box_before_wall();
    if let umbra::synth::Shape::Box { centre, .. } = &mut scene.objects[1].shape {
        centre.x -= 0.55;
    }
    let frame = render_frame(&scene, &calib, &SensorModel::ideal(), 8);
    let strip = calib.rgb.fx * 0.025 * (1.0 / 1.2 - 1.0 / 3.0);
    let rows = (0..HEIGHT)
        .filter(|&v| count_in_row(&frame.rgb_labels, v, ALIGNMENT) > 0)
        .collect::<Vec<_>>();
    assert!(rows.len() > 100, "the box spans {} RGB rows", rows.len());
    let mid = rows[rows.len() / 2];
    let truth = count_in_row(&frame.rgb_labels, mid, ALIGNMENT) as f64;
    assert!(
        (truth - strip).abs() <= 1.0,
        "simulator: {truth} px, by hand {strip:.1}"
    );
    let (mut with, mut without) = (Confusion::default(), Confusion::default());
    with.add(&frame.rgb_labels, &classify_rgb(&calib, &frame).rgb_labels);
    without.add(&frame.rgb_labels, &classify(&calib, &frame).rgb_labels);
    at_least(
        &with,
        Some(ALIGNMENT),
        0.8,
        "RGB alignment right of a black box",
    );
    let blind = without.class(ALIGNMENT).recall.unwrap_or(0.0);
    assert!(blind < 0.3, "depth alone finds {blind:.2} of it");
}

#[test]
fn black_box_before_a_wall_turning_towards_the_camera_keeps_its_alignment_strip() {
    // The hand-computed black box (front face x = −0.2..0.2 m at 1 m) before a wall through
    // (0, 0, 3 m) turned by −0.35 rad, its right side nearer. The ray through the box's right
    // corner (0.2, 0, 1) meets the wall at z = 3·cos(yaw) / (cos(yaw) − 0.2·sin(yaw)) = 2.80 m,
    // and through its left corner at z = 3·cos(yaw) / (cos(yaw) + 0.2·sin(yaw)) = 3.24 m: the
    // wall right of the hole is nearer than left of it by f·b·(1/2.80 − 1/3.24) = 2.1 px of
    // disparity and more (the shadow's start lies further left). The colour split reads such an
    // open hole only some way in, not to the box's right edge; the RGB camera's view of that
    // edge at the same shift carries the box's depth on to it, and its alignment strip,
    // f_rgb·0.025·(1/1 − 1/2.80) px wide, opens.
    let calib = Calibration::nyu_default();
    let yaw: f64 = -0.35;
    let mut scene = Scene::box_before_wall(1.0, 3.0);
    scene.objects[0].shape = umbra::synth::scene::slanted_wall(3.0, yaw);
    scene.objects[1].material = umbra::synth::Material::black();
    let frame = render_frame(&scene, &calib, &SensorModel::ideal(), 4);
    let z_at = |x: f64| 3.0 * yaw.cos() / (yaw.cos() - x * yaw.sin());
    let (z_right, z_left) = (z_at(0.2), z_at(-0.2));
    assert!((z_right - 2.80).abs() < 0.01 && (z_left - 3.24).abs() < 0.01);
    assert!(calib.fb() * (1.0 / z_right - 1.0 / z_left) > 2.0);
    let strip = calib.rgb.fx * 0.025 * (1.0 - 1.0 / z_right);
    let rows = (0..HEIGHT)
        .filter(|&v| count_in_row(&frame.rgb_labels, v, ALIGNMENT) > 0)
        .collect::<Vec<_>>();
    assert!(rows.len() > 100, "the box spans {} RGB rows", rows.len());
    let truth = count_in_row(&frame.rgb_labels, rows[rows.len() / 2], ALIGNMENT) as f64;
    assert!(
        (truth - strip).abs() <= 1.0,
        "simulator: {truth} px, by hand {strip:.1}"
    );
    let out = classify_rgb(&calib, &frame);
    let mut c = Confusion::default();
    c.add(&frame.ir_labels, &out.ir_labels);
    at_least(&c, Some(ATTACHED), 0.9, "IR attached of the black box");
    let mut c = Confusion::default();
    c.add(&frame.rgb_labels, &out.rgb_labels);
    // Measured: F1 0.996; 0.045 when the box's depth stops where the colour split stopped reading.
    at_least(
        &c,
        Some(ALIGNMENT),
        0.95,
        "RGB alignment right of the black box",
    );
}

#[test]
fn black_box_mostly_hidden_by_a_nearer_rod_keeps_its_alignment_strip() {
    // The hand-computed black box (front face x = −0.2..0.2 m at 1 m, before a wall at 3 m) with
    // a grey rod (radius 1 cm) at 0.7 m in front of it, its right side at x = 0.1232 m: IR column
    // 313.04 + 582.62·0.1232/0.7 = 415.6, where the box's right edge is at
    // 313.04 + 582.62·0.2/1 = 429.6. Only a 14 px strip of the box shows right of the rod, but
    // that is its right edge, and the RGB camera, 2.5 cm to the right, sees wall past it in a
    // strip of f_rgb·0.025·(1/1 − 1/3) = 8.6 px, from RGB column
    // 325.58 + 518.86·(0.2 − 0.025)/1 = 416.4 on.
    let calib = Calibration::nyu_default();
    let mut scene = black_box_before_wall();
    push_grey_rod(&mut scene, 0.1132, 0.7, 0.01);
    let frame = render_frame(&scene, &calib, &SensorModel::ideal(), 4);
    let v = HEIGHT / 2;
    let row = &frame.raw[v * WIDTH..(v + 1) * WIDTH];
    let holes = (400..440).filter(|&u| row[u] == 2047).collect::<Vec<_>>();
    assert!(
        holes.first() >= Some(&414) && holes.last() <= Some(&430) && holes.len() >= 12,
        "the box's strip right of the rod: {holes:?}"
    );
    let strip = calib.rgb.fx * 0.025 * (1.0 - 1.0 / 3.0);
    let truth = (410..440)
        .filter(|&x| frame.rgb_labels[v * WIDTH + x] == ALIGNMENT)
        .collect::<Vec<_>>();
    assert!(
        (truth.len() as f64 - strip).abs() <= 1.0 && truth[0].abs_diff(417) <= 1,
        "simulator: {truth:?}, by hand {strip:.1} px from 416.4"
    );
    // Scored right of the box, in the rows where it stands (the rod runs on above and below).
    let out = classify_rgb(&calib, &frame);
    let window = |labels: &[u8]| {
        (0..HEIGHT)
            .filter(|&y| count_in_row(&frame.ir_labels, y, ATTACHED) > 0)
            .flat_map(|y| labels[y * WIDTH + 410..y * WIDTH + 440].to_vec())
            .collect::<Vec<_>>()
    };
    let mut c = Confusion::default();
    c.add(&window(&frame.rgb_labels), &window(&out.rgb_labels));
    // Measured: F1 0.939; 0.076 when a hole under 20 px is never taken for an occluder's edge.
    at_least(
        &c,
        Some(ALIGNMENT),
        0.9,
        "RGB alignment right of the hidden black box",
    );
}

#[test]
fn colour_split_leaves_posters_alone() {
    // A black poster and a pale glossy one on the wall: holes with no shadow in them (SPEC: OTHER
    // even if lit). Neither has a background-coloured part that a shadow could be.
    let calib = Calibration::nyu_default();
    let mut scene = Scene::box_before_wall(1.0, 3.0);
    scene.objects.retain(|o| o.kind == "wall");
    for (x, material) in [
        (-0.5, umbra::synth::Material::black()),
        (0.5, umbra::synth::Material::glossy([0.42, 0.56, 0.82])),
    ] {
        scene.push(
            "poster",
            umbra::synth::Shape::Box {
                centre: umbra::synth::V3::new(x, 0.0, 2.99),
                half: umbra::synth::V3::new(0.3, 0.3, 0.004),
                yaw: 0.0,
            },
            material,
        );
    }
    for seed in 0..2 {
        let frame = render_frame(&scene, &calib, &SensorModel::kinect(), 50 + seed);
        let out = classify_rgb(&calib, &frame);
        assert!(out
            .ir_labels
            .iter()
            .all(|&l| l != ATTACHED && l != DETACHED));
        assert!(out
            .rgb_labels
            .iter()
            .all(|&l| l != ATTACHED && l != DETACHED));
    }
}

#[test]
fn black_rod_before_a_glossy_poster_casts_no_attached_shadow_over_it() {
    // A random complex scene (seed 777002336) that once broke the colour split: a black rod at
    // 0.84 m crosses a glossy poster the RGB camera cannot tell from the wall, so from the poster's
    // left edge on the RGB row shows wall, then the rod, in one hole. Read as an attached shadow it
    // is far wider than the 2 cm rod, which an attached shadow's occluder cannot be; the rod's
    // shadow on the poster is OTHER (SPEC §1).
    let calib = Calibration::nyu_default();
    let scene = random_scene(Category::Complex, 777_002_336);
    assert!(scene.objects.iter().any(|o| o.kind == "poster"));
    let frame = render_frame(&scene, &calib, &sensor_for(Category::Complex), 1);
    let out = classify_rgb(&calib, &frame);
    let mut ir = Confusion::default();
    ir.add(&frame.ir_labels, &out.ir_labels);
    let any = ir.any_shadow();
    assert!(any.precision.unwrap() >= 0.98, "IR any shadow {any:?}");
}

#[test]
fn holes_without_depth_edge_are_never_shadows() {
    // A bare wall with the Kinect noise model: only speckle holes, all OTHER.
    let calib = Calibration::nyu_default();
    let mut scene = Scene::box_before_wall(1.0, 3.0);
    scene.objects.retain(|o| o.kind == "wall");
    let frame = render_frame(&scene, &calib, &SensorModel::kinect(), 3);
    assert!(
        frame.raw.iter().filter(|&&r| r == 2047).count() > 100,
        "the noise model makes speckle"
    );
    let out = classify(&calib, &frame);
    assert!(out.ir_labels.iter().all(|&l| l == VALID || l == OTHER));
    assert!(out.rgb_labels.iter().all(|&l| l == VALID || l == OTHER));
}

/// Scores `n` random scenes of a category (two frames each) in both views.
fn score(category: Category, n: u64) -> (Confusion, Confusion) {
    score_with(&Calibration::nyu_default(), category, n)
}

/// [`score`] for a Kinect with calibration `calib`: the simulator renders with it and the
/// classifier reads it.
fn score_with(calib: &Calibration, category: Category, n: u64) -> (Confusion, Confusion) {
    let calib = *calib;
    let sensor = sensor_for(category);
    let (mut ir, mut rgb) = (Confusion::default(), Confusion::default());
    let mut classifier = Classifier::new(&calib);
    let mut out = Classified::default();
    for seed in 0..n {
        let scene = random_scene(category, 9000 + seed);
        for k in 0..2 {
            let frame = render_frame(&scene.at_frame(k), &calib, &sensor, seed * 10 + k as u64);
            assert_eq!(frame.raw.len(), PIXELS);
            classifier.classify(&frame.raw, &mut out);
            ir.add(&frame.ir_labels, &out.ir_labels);
            rgb.add(&frame.rgb_labels, &out.rgb_labels);
        }
    }
    (ir, rgb)
}

fn at_least(c: &Confusion, code: Option<u8>, f1: f64, what: &str) {
    let s = match code {
        Some(code) => c.class(code),
        None => c.any_shadow(),
    };
    let got = s.f1.unwrap_or(0.0);
    assert!(
        got >= f1,
        "{what}: F1 {got:.3} < {f1} (P {:?}, R {:?}, support {})",
        s.precision,
        s.recall,
        s.support
    );
}

#[test]
fn simple_scenes_meet_the_issue_targets_in_the_ir_view() {
    let (ir, rgb) = score(Category::Simple, 8);
    at_least(&ir, Some(ATTACHED), 0.95, "IR attached");
    at_least(&ir, Some(DETACHED), 0.90, "IR detached");
    let any = ir.any_shadow();
    assert!(
        any.precision.unwrap() >= 0.98 && any.recall.unwrap() >= 0.95,
        "IR any shadow {any:?}"
    );
    // RGB view: attached and detached meet 0.95/0.90; alignment strips of 1–2 px lose pixels to
    // edge quantisation (measured 0.91 on 40 scenes), so these are regression floors.
    at_least(&rgb, Some(ATTACHED), 0.93, "RGB attached");
    at_least(&rgb, Some(DETACHED), 0.90, "RGB detached");
    at_least(&rgb, Some(ALIGNMENT), 0.85, "RGB alignment");
    let any = rgb.any_shadow();
    assert!(
        any.precision.unwrap() >= 0.96 && any.recall.unwrap() >= 0.92,
        "RGB any shadow {any:?}"
    );
}

/// Another Kinect v1 than NYU's: other focal lengths and centres, the RGB camera turned by
/// about a degree and offset in all three axes, another raw-to-depth fit (libfreenect's).
fn another_kinect() -> Calibration {
    let mut c = Calibration::nyu_default();
    c.depth.fx = 594.2;
    c.depth.fy = 591.0;
    c.depth.cx = 339.3;
    c.depth.cy = 242.7;
    c.rgb.fx = 529.2;
    c.rgb.fy = 525.6;
    c.rgb.cx = 328.9;
    c.rgb.cy = 267.5;
    c.depth_to_rgb.rotation =
        *nalgebra::Rotation3::from_euler_angles(0.012, -0.018, 0.0015).matrix();
    c.depth_to_rgb.translation = nalgebra::Vector3::new(-0.0199, 0.0007, 0.0109);
    c.raw.numerator = 325.6;
    c.raw.denominator = 1084.6;
    c.validate().expect("a valid calibration");
    c
}

#[test]
fn another_kinects_calibration_scores_like_the_nyu_one() {
    // Nothing in the classifier may lean on the NYU numbers: the same floors as the NYU test
    // above (measured: IR attached 0.997, detached 0.994, any shadow P 1.000 / R 0.997; RGB
    // attached 0.986, detached 0.980, alignment 0.899, any shadow P 0.975 / R 0.957). Classified
    // with the NYU calibration instead, these frames score 0.000 RGB attached.
    let (ir, rgb) = score_with(&another_kinect(), Category::Simple, 8);
    at_least(&ir, Some(ATTACHED), 0.95, "IR attached");
    at_least(&ir, Some(DETACHED), 0.90, "IR detached");
    let any = ir.any_shadow();
    assert!(
        any.precision.unwrap() >= 0.98 && any.recall.unwrap() >= 0.95,
        "IR any shadow {any:?}"
    );
    at_least(&rgb, Some(ATTACHED), 0.93, "RGB attached");
    at_least(&rgb, Some(DETACHED), 0.90, "RGB detached");
    at_least(&rgb, Some(ALIGNMENT), 0.85, "RGB alignment");
    let any = rgb.any_shadow();
    assert!(
        any.precision.unwrap() >= 0.96 && any.recall.unwrap() >= 0.92,
        "RGB any shadow {any:?}"
    );
}

#[test]
fn complex_scenes_keep_shadow_precision() {
    // Complex scenes include black and glossy occluders with no depth at all, whose shadows a
    // depth-only classifier cannot attribute; precision is what must hold. Regression floors a
    // little under the measured values (IR any shadow P 0.997 / R 0.852, detached F1 0.945,
    // other F1 0.977; RGB any shadow P 0.982).
    let (ir, rgb) = score(Category::Complex, 6);
    let any = ir.any_shadow();
    assert!(any.precision.unwrap() >= 0.99, "IR any shadow {any:?}");
    assert!(any.recall.unwrap() >= 0.82, "IR any shadow {any:?}");
    assert!(
        rgb.any_shadow().precision.unwrap() >= 0.96,
        "RGB any shadow {:?}",
        rgb.any_shadow()
    );
    at_least(&ir, Some(DETACHED), 0.92, "IR detached");
    at_least(&ir, Some(OTHER), 0.96, "IR other");
}

/// Scores `n` random complex scenes (two frames each) in the IR view, classified with the RGB
/// image, their colour camera's noise `rgb_sigma` (8-bit units per channel).
fn complex_ir_with_rgb_noise(n: u64, rgb_sigma: f64) -> Confusion {
    let calib = Calibration::nyu_default();
    let sensor = SensorModel {
        rgb_noise_sigma: rgb_sigma,
        ..sensor_for(Category::Complex)
    };
    let mut ir = Confusion::default();
    for seed in 0..n {
        let scene = random_scene(Category::Complex, 9100 + seed);
        for k in 0..2 {
            let frame = render_frame(&scene.at_frame(k), &calib, &sensor, seed * 10 + k as u64);
            ir.add(&frame.ir_labels, &classify_rgb(&calib, &frame).ir_labels);
        }
    }
    ir
}

#[test]
fn a_noisier_colour_camera_costs_little_attached_f1() {
    // The colour split reads the RGB image: with noise of σ = 5 per channel (the simulator's
    // default is 2, the real frame's 1.3 to 4.8) its tests once left many rows unsplit, and
    // complex attached F1 fell by 0.065 on 20 scenes. Measured on these 8 scenes: 0.930 at σ = 2,
    // 0.931 at σ = 5 (0.917 before). At σ = 8 fixed colour steps let noise pass for edges
    // (0.907); with steps that follow the noise each frame shows, 0.934 at σ = 5 and 0.933 at
    // σ = 8.
    let f1 = |c: &Confusion| c.class(ATTACHED).f1.unwrap_or(0.0);
    let clean = f1(&complex_ir_with_rgb_noise(8, 2.0));
    for sigma in [5.0, 8.0] {
        let noisy = f1(&complex_ir_with_rgb_noise(8, sigma));
        assert!(
            noisy >= clean - 0.01,
            "attached F1 {noisy:.3} at σ = {sigma}, {clean:.3} at σ = 2"
        );
    }
}

/// A black rod of radius `r` at 1.5 m before a wall at 3 m, through the Kinect sensor model
/// (widened shadows), classified with RGB over three seeds.
fn black_rod_tie(r: f64) -> Confusion {
    let calib = Calibration::nyu_default();
    let mut scene = Scene::rod_before_wall(0.0, 1.5, r, 3.0);
    scene.objects[1].material = umbra::synth::Material::black();
    let mut c = Confusion::default();
    for seed in 0..3 {
        let frame = render_frame(&scene, &calib, &SensorModel::kinect(), 90 + seed);
        let out = classify_rgb(&calib, &frame);
        c.add(&frame.ir_labels, &out.ir_labels);
    }
    c
}

#[test]
fn black_rod_just_narrower_than_its_shift_keeps_a_detached_shadow_where_widening_hides_the_gap() {
    // Radius 16.7 mm: 2·r·f/z = 13.0 px wide, its shadow shifted f·b·(1/1.5 − 1/3) = 14.6 px, so
    // a lit gap of 1.6 px, which the sensor's widening swallows in most rows (hole = shadow +
    // rod). The rows where the gap shows make the whole shadow detached.
    let c = black_rod_tie(0.0167);
    at_least(
        &c,
        Some(DETACHED),
        0.9,
        "IR detached, rod 1.6 px narrower than its shift",
    );
    let any = c.any_shadow();
    assert!(any.precision.unwrap() >= 0.98, "IR any shadow {any:?}");
}

/// Widens every hole run of `frame`'s IR view by `left` valid pixels on its left end and
/// `right` on its right, as a sensor whose correlation window grows every hole does (a fifth
/// simulator's model); grown pixels take the truth of the run end they join. Runs are read
/// before any grows, so a lit gap of up to `left + right` pixels between two runs closes.
fn widen_every_hole(frame: &mut SynthFrame, left: usize, right: usize) {
    for v in 0..HEIGHT {
        let row = v * WIDTH;
        let hole = |u: usize| frame.raw[row + u] == NO_DEPTH;
        let mut runs = Vec::new();
        let mut u = 0;
        while u < WIDTH {
            if !hole(u) {
                u += 1;
                continue;
            }
            let start = u;
            while u < WIDTH && hole(u) {
                u += 1;
            }
            runs.push((start, u));
        }
        for (start, end) in runs {
            let (first, last) = (frame.ir_labels[row + start], frame.ir_labels[row + end - 1]);
            for x in start.saturating_sub(left)..start {
                if frame.raw[row + x] != NO_DEPTH {
                    frame.raw[row + x] = NO_DEPTH;
                    frame.ir_labels[row + x] = first;
                }
            }
            for x in end..(end + right).min(WIDTH) {
                if frame.raw[row + x] != NO_DEPTH {
                    frame.raw[row + x] = NO_DEPTH;
                    frame.ir_labels[row + x] = last;
                }
            }
        }
    }
}

/// A black rod of r = 14 mm at 1.5 m before a wall at 3 m (lit alike on both sides of the rod's
/// axis, or dimmer right of it by `dim`), and a grey rod (r = 5 cm at x = −0.6 m) that shows the
/// frame's widening; rendered by the ideal sensor, every hole then widened by 2 px on each end,
/// and classified with RGB over two seeds: the IR-view confusion. The widening here comes after
/// the simulator labelled the frame, so the truth is brought to its rule here: the black rod's
/// shadow, which the widening joins to the rod in every row, is attached (SPEC §1: the hole
/// touches its occluder).
fn black_rod_with_swallowed_gap(dim: f64) -> Confusion {
    let calib = Calibration::nyu_default();
    let mut scene = Scene::new("black rod before a wall, its lit gap swallowed");
    push_bands(&mut scene, (0.0, 3.0, 3.0), -1..1, |k| {
        let light = if k < 0 { 1.0 } else { dim };
        [0.5 * light, 0.6 * light, 0.7 * light]
    });
    let rod = Scene::rod_before_wall(0.0, 1.5, 0.014, 3.0).objects[1].clone();
    scene.push("rod", rod.shape, umbra::synth::Material::black());
    push_grey_rod(&mut scene, -0.6, 1.5, 0.05);
    let mut c = Confusion::default();
    for seed in 0..2 {
        let mut frame = render_frame(&scene, &calib, &SensorModel::ideal(), 60 + seed);
        assert!(
            frame.ir_labels.contains(&DETACHED),
            "the simulator casts one"
        );
        widen_every_hole(&mut frame, 2, 2);
        // No lit pixel is left between the black rod's shadow and the rod.
        let (cx, fx) = (calib.depth.cx, calib.depth.fx);
        let rod = (cx - 0.014 * fx / 1.5) as usize;
        for v in 100..380 {
            let row = &frame.raw[v * WIDTH..(v + 1) * WIDTH];
            assert!(
                row[rod - 10..rod + 2].iter().all(|&r| r == NO_DEPTH),
                "row {v}: {:?}",
                &row[rod - 24..rod + 12]
            );
        }
        for l in frame.ir_labels.iter_mut().filter(|l| **l == DETACHED) {
            *l = ATTACHED;
        }
        c.add(&frame.ir_labels, &classify_rgb(&calib, &frame).ir_labels);
    }
    c
}

#[test]
fn black_box_whose_hole_the_widening_grows_into_the_wall_is_placed_at_its_own_shift() {
    // The black box of the hand-computed scene at 1.5 m, 0.3 m to the right, before the wall at
    // 3 m, with a grey rod (r = 5 cm at 1.5 m) whose shadow shows the frame's widening; every hole
    // widened by 2 px on each end, as a sensor whose correlation window grows every hole does.
    // The box's hole then runs 2 px into the wall right of it, and the RGB camera sees the wall
    // over those columns: read from the hole's end, the box's right edge gives a strip too
    // wide, a shift too large (each column about 3.4 px), and the box, warped that much nearer,
    // an alignment strip right of it wider than the truth's (332 px too many over two seeds).
    // Its edge is read where the frame's widening puts it.
    let calib = Calibration::nyu_default();
    let mut scene = black_box_before_wall();
    let umbra::synth::Shape::Box { centre, .. } = &mut scene.objects[1].shape else {
        panic!("the hand-computed scene's second object is its box");
    };
    centre.x += 0.3;
    centre.z += 0.5;
    push_grey_rod(&mut scene, -0.6, 1.5, 0.05);
    let mut c = Confusion::default();
    for seed in 0..2 {
        let mut frame = render_frame(&scene, &calib, &SensorModel::ideal(), seed);
        widen_every_hole(&mut frame, 2, 2);
        c.add(&frame.rgb_labels, &classify_rgb(&calib, &frame).rgb_labels);
    }
    // Measured: precision 0.935, recall 0.858 (before, 0.882 and 0.858).
    let s = c.class(ALIGNMENT);
    assert!(s.precision.unwrap() >= 0.92, "RGB alignment {s:?}");
    assert!(s.recall.unwrap() >= 0.84, "RGB alignment {s:?}");
}

#[test]
fn black_rod_whose_lit_gap_the_widening_swallows_in_every_row_casts_an_attached_shadow() {
    // The rod is 2·r·f/z = 10.9 px wide, its shadow shifted f·b·(1/1.5 − 1/3) = 14.6 px, so the
    // projector lights a gap of 3.7 px between shadow and rod (eqs. 4–5). Widening every hole by
    // 2 px on each end swallows the gap in every row: one hole of about 30 px, shadow and rod,
    // the shadow touching the rod: attached (SPEC §1). The hole must still be split where the
    // rod begins: read whole as one shadow it would leave the rod's columns shadow too. On a
    // wall lit alike on both sides the hole is closed (one background on both sides); where the
    // wall right of the rod is dimmer, it is read as an open hole.
    for dim in [1.0, 0.6] {
        let c = black_rod_with_swallowed_gap(dim);
        // Measured (with the grey rod's attached shadow): recall 0.998, precision 0.943 on both
        // walls (the split reads the shadow as wide as the shift, so the swallowed gap's pixels
        // go with it, where the truth gives half of them to the rod). None left detached; before
        // the rule of SPEC §1 was kept, every one of them was.
        let s = c.class(ATTACHED);
        assert!(s.recall.unwrap() >= 0.98, "light {dim}: IR attached {s:?}");
        assert!(
            s.precision.unwrap() >= 0.92,
            "light {dim}: IR attached {s:?}"
        );
        assert_eq!(c.class(DETACHED).predicted, 0, "light {dim}");
    }
}

#[test]
fn black_rod_just_wider_than_its_shift_casts_an_attached_shadow() {
    // Radius 21.9 mm: 17.0 px wide against the same 14.6 px shift: no lit gap in any row.
    let c = black_rod_tie(0.0219);
    at_least(
        &c,
        Some(ATTACHED),
        0.9,
        "IR attached, rod 2.4 px wider than its shift",
    );
}

#[test]
fn black_box_before_a_wall_dashed_every_other_row_has_its_shadow_split_off() {
    // The hand-computed black box before a plain wall at 3 m, with a dark dash 3 cm wide (6 px)
    // in its shadow (x = −0.74..−0.71 m) on every other IR row: each dash is 2 mm tall, at the
    // height of the RGB row the colour split reads for that IR row (row cy' + (v − cy)·fy'/fy of
    // the RGB camera, which sits beside the IR camera, so rows map to rows), and RGB rows lie
    // 5.8 mm apart on the wall. A dashed row's shadow shows a dark stripe, neither wall nor
    // box, and its split fails; each row between has a dashed row above and below. (Fails
    // without the rows two away: no row of 292 split.)
    let calib = Calibration::nyu_default();
    let mut scene = Scene::new("black box before a wall dashed every other row");
    scene.push(
        "wall",
        umbra::synth::scene::wall(3.0),
        umbra::synth::Material::matte([0.4, 0.6, 0.3]),
    );
    let (ir, rgb) = (&calib.depth, &calib.rgb);
    for v in (0..HEIGHT).step_by(2) {
        let y = (rgb.cy + (v as f64 - ir.cy) * rgb.fy / ir.fy).round();
        scene.push(
            "dash",
            umbra::synth::Shape::Box {
                centre: umbra::synth::V3::new(-0.725, (y - rgb.cy) / rgb.fy * 3.0, 2.999),
                half: umbra::synth::V3::new(0.015, 0.001, 0.0005),
                yaw: 0.0,
            },
            umbra::synth::Material::matte([0.05, 0.05, 0.05]),
        );
    }
    assert_black_box_split_as_by_hand(scene, 0.2);
}

#[test]
fn black_box_before_a_wall_has_its_shadow_split_in_its_top_row() {
    // The hand-computed black box: its top edge (y = −0.25 m at 1 m) lies at row
    // cy − 0.25·fy = 92.8, and so does the top of its shadow on the wall (y = −0.75 m at 3 m:
    // the projector sits beside the camera, not above it), so row 93 is the first to hold both.
    // The RGB camera reads it at row cy' + (93 − cy)·fy'/fy = 124.1, whose centre (y = −0.2498 m
    // at 1 m) still shows the box. The row above holds no hole: the row below alone must confirm
    // the split.
    let calib = Calibration::nyu_default();
    let frame = render_frame(&black_box_before_wall(), &calib, &SensorModel::ideal(), 8);
    let out = classify_rgb(&calib, &frame);
    let w = calib.fb() * (1.0 - 1.0 / 3.0);
    let top = (calib.depth.cy - 0.25 * calib.depth.fy).ceil() as usize;
    assert_eq!(top, 93);
    assert_eq!(
        count_in_row(&frame.ir_labels, top - 1, ATTACHED),
        0,
        "the scene"
    );
    let truth = count_in_row(&frame.ir_labels, top, ATTACHED);
    assert!((truth as f64 - w).abs() <= 1.5, "the scene's {truth}");
    let n = count_in_row(&out.ir_labels, top, ATTACHED);
    assert!(
        (n as f64 - w).abs() <= 2.5,
        "row {top}: {n} attached px, hand-computed {w:.2}"
    );
}

#[test]
fn glossy_rods_attached_shadow_is_split_off_beside_a_wall_shaded_towards_the_left() {
    // A glossy rod (radius 2.5 cm) at 1.3 m before a wall at 3 m returns no depth: 22 px wide,
    // wider than its shift f·b·(1/1.3 − 1/3) = 19.0 px, so its shadow is attached and shares
    // one hole with it. Shaded: the two sides of the hole differ in brightness, so the shadow
    // is read from the left alone, and the wall left of it, drifting in colour with no step,
    // is no occluder the RGB camera sees there.
    let (plain, shaded) = glossy_rod_beside_a_shaded_wall(0.025);
    at_least(
        &plain,
        Some(ATTACHED),
        0.95,
        "IR attached beside an evenly lit wall",
    );
    at_least(
        &shaded,
        Some(ATTACHED),
        0.95,
        "IR attached beside a shaded wall",
    );
}

#[test]
fn glossy_rods_attached_shadow_is_split_off_where_the_rod_runs_off_the_right_border() {
    // The glossy rod (radius 2.5 cm, 22 px wide, at 1.3 m before the wall at 3 m) with its axis
    // on the right border: half of it shows, 11 px, and its attached shadow, 19 px by eq. (3)
    // and the sensor's widening, runs into it. One hole of about 33 px runs into the border. A
    // real sensor's dead band there (8 px or more in every row) is no shadow, and open holes at
    // the border narrower than 48 px were never read; a frame without the band has none
    // (attached F1 0.97 over three frames; 0 before).
    let calib = Calibration::nyu_default();
    let x = (WIDTH as f64 - 0.5 - calib.depth.cx) * 1.3 / calib.depth.fx;
    let mut scene = Scene::rod_before_wall(x, 1.3, 0.025, 3.0);
    scene.objects[1].material = umbra::synth::Material::glossy([0.3, 0.2, 0.4]);
    // 0.8 m long, about 360 rows: a rod in every row at the border would look like the band.
    if let umbra::synth::Shape::Cylinder { half_len, .. } = &mut scene.objects[1].shape {
        *half_len = 0.4;
    }
    let mut c = Confusion::default();
    for seed in 0..3 {
        let frame = render_frame(&scene, &calib, &SensorModel::kinect(), 90 + seed);
        let row = &frame.raw[240 * WIDTH..241 * WIDTH];
        let hole = row.iter().rev().take_while(|&&r| r == NO_DEPTH).count();
        assert!((25..48).contains(&hole), "hole of {hole} px at the border");
        c.add(&frame.ir_labels, &classify_rgb(&calib, &frame).ir_labels);
    }
    at_least(&c, Some(ATTACHED), 0.9, "IR attached beside the border");
}

/// A glossy rod of `radius` at 1.3 m before a wall at 3 m, with the noisy Kinect model: IR-view
/// confusions with the simulator's RGB image, and with that image's wall shaded towards the
/// left, from 80 % of its light left of the hole's start down to 45 % some 35 px further left,
/// and full light right of the rod (a lamp's edge, a cylinder turned from the light).
fn glossy_rod_beside_a_shaded_wall(radius: f64) -> (Confusion, Confusion) {
    let calib = Calibration::nyu_default();
    let mut scene = Scene::rod_before_wall(0.0, 1.3, radius, 3.0);
    scene.objects[1].material = umbra::synth::Material::glossy([0.3, 0.2, 0.4]);
    let (mut plain, mut shaded) = (Confusion::default(), Confusion::default());
    for seed in 0..3 {
        let mut frame = render_frame(&scene, &calib, &SensorModel::kinect(), 80 + seed);
        plain.add(&frame.ir_labels, &classify_rgb(&calib, &frame).ir_labels);
        // The RGB camera sees the hole's start about 12 columns right of the IR camera.
        let row = &frame.ir_labels[240 * WIDTH..241 * WIDTH];
        let start = 12
            + row
                .iter()
                .position(|&l| l == ATTACHED || l == DETACHED)
                .expect("the simulator casts a shadow");
        for px in frame.rgb.chunks_exact_mut(3 * WIDTH) {
            for (x, c) in px.chunks_exact_mut(3).enumerate() {
                let t = (x as f64 - (start as f64 - 35.0)) / 35.0;
                let gain = if x >= start + 40 {
                    1.0
                } else {
                    0.45 + 0.35 * t.clamp(0.0, 1.0)
                };
                c.iter_mut()
                    .for_each(|v| *v = (f64::from(*v) * gain).round() as u8);
            }
        }
        shaded.add(&frame.ir_labels, &classify_rgb(&calib, &frame).ir_labels);
    }
    (plain, shaded)
}

#[test]
fn box_side_face_seen_at_a_grazing_angle_is_no_shadow() {
    // A blue box, lit well: read at the front edge's depth alone, the face's far part shows in
    // the RGB image further right than that depth puts it (76 % of the face was told so, 97 %
    // with the far edge's depth; none before).
    let (face, shadow) = grazing_side_face(
        [0.15, 0.35, 0.75],
        SensorModel::kinect().rgb_noise_sigma,
        40,
    );
    assert!(face >= 0.9, "{face:.3} of the face's pixels OTHER");
    assert!(
        shadow >= 0.98,
        "{shadow:.3} of the shadow's pixels attached"
    );
}

#[test]
fn dark_box_side_face_in_shade_is_no_shadow_through_its_noisy_columns() {
    // A dark brown box: its face in shade is so dim (R + G + B about 110) that the camera's
    // noise puts a probe's chromaticity off the front's now and then. The face was read only
    // up to the first such column, or not at all where the one probe before the reading fell
    // on one (0.89 of its pixels OTHER over three frames, 0.84 in the worst; 0.99 now).
    let (mut face, mut shadow) = (0.0, 1.0f64);
    for seed in 41..44 {
        let (f, s) = grazing_side_face(
            [0.1, 0.05, 0.03],
            SensorModel::kinect().rgb_noise_sigma,
            seed,
        );
        face += f / 3.0;
        shadow = shadow.min(s);
    }
    assert!(face >= 0.95, "{face:.3} of the face's pixels OTHER");
    // The dark face also passes for a black surface the shadow runs onto, in some rows (the
    // RGB camera sees it over the shadow's right part): 0.88 in the worst frame, as before.
    assert!(
        shadow >= 0.85,
        "{shadow:.3} of the shadow's pixels attached"
    );
}

#[test]
fn bluish_box_side_face_whose_hue_lies_near_the_walls_is_no_shadow() {
    // A blue-grey box before the pale wall: its front and the wall, as the camera sees them, lie
    // 111 to 114 thousandths apart in chromaticity. The face in shade is far darker than the
    // front, so only its hue tells it from the wall, and the hue was trusted only from 120 apart
    // (none of the face OTHER before, in both frames).
    for seed in 40..42 {
        let (face, shadow) = grazing_side_face(
            [0.35, 0.45, 0.65],
            SensorModel::kinect().rgb_noise_sigma,
            seed,
        );
        assert!(
            face >= 0.9,
            "seed {seed}: {face:.3} of the face's pixels OTHER"
        );
        assert!(
            shadow >= 0.98,
            "seed {seed}: {shadow:.3} of the shadow's pixels attached"
        );
    }
}

#[test]
fn box_side_face_in_another_light_is_no_shadow() {
    // The purple box's face lit by a light of another colour than its front (a tenth less green
    // in the RGB image). On a face this dark the camera's noise then puts many of its pixels past
    // the 40 thousandths of chromaticity within which a pixel had the occluder's hue, though they
    // lie far nearer the front's than the wall's.
    let mut face = 0.0;
    for seed in 40..45 {
        let (f, shadow) = grazing_side_face_tinted(
            [0.3, 0.1, 0.25],
            SensorModel::kinect().rgb_noise_sigma,
            seed,
            [1.0, 0.9, 1.0],
        );
        face += f / 5.0;
        assert!(
            shadow >= 0.85,
            "seed {seed}: {shadow:.3} of the shadow's pixels attached"
        );
    }
    // Measured: 0.936 of the face OTHER over five frames (0.763 before).
    assert!(face >= 0.9, "{face:.3} of the face's pixels OTHER");
}

/// A box of `colour`, x = 0.1..0.3 m, z = 0.9..1.1 m, before a pale wall at 3 m, with the noisy
/// Kinect model (noise `seed`): the shares of its grazing side face's pixels called OTHER and of
/// its attached shadow's middle called attached, in 80 rows about the box's middle.
///
/// Its left face (x = 0.1) faces the camera at a grazing angle (cos 0.1 at its middle) and
/// returns no depth: by hand it spans columns cx + fx·0.1/1.1 to cx + fx·0.1/0.9 (53 to 65 px
/// right of cx). The projector (7.5 cm right) lights it, so its far edge casts the shadow on the
/// wall, f·b·(1/1.1 − 1/3) = 25 px left of that edge. Face and shadow are one hole, which eq.
/// (3) from the front edge (34 px) fits as a whole: the RGB camera sees the face there, darker
/// than the front (turned from the light) but of its hue.
fn grazing_side_face(colour: [f64; 3], rgb_noise: f64, seed: u64) -> (f64, f64) {
    grazing_side_face_tinted(colour, rgb_noise, seed, [1.0; 3])
}

/// [`grazing_side_face`], with the face's pixels in the RGB image (the simulator's OTHER there)
/// scaled by `tint` per channel: a face lit by a light of another colour than the front's.
fn grazing_side_face_tinted(
    colour: [f64; 3],
    rgb_noise: f64,
    seed: u64,
    tint: [f64; 3],
) -> (f64, f64) {
    let (calib, frame) = grazing_side_face_frame(colour, rgb_noise, seed, tint);
    let (fx, cx) = (calib.depth.fx, calib.depth.cx);
    let u_back = cx + fx * 0.1 / 1.1;
    let shadow = (calib.fb() * (1.0 / 1.1 - 1.0 / 3.0)).round() as usize;
    assert_eq!(shadow, 25);
    let (mut face, mut shade) = (Vec::new(), Vec::new());
    for v in 200..280 {
        face.extend(grazing_face_cols(&calib).map(|u| v * WIDTH + u));
        // The shadow's middle, clear of both its ends (the sensor's widening, the face's edge).
        let end = u_back.floor() as usize;
        shade.extend((end - shadow + 4..end - 3).map(|u| v * WIDTH + u));
    }
    let out = classify_rgb(&calib, &frame);
    let share =
        |px: &[usize], code| count_labelled(&out.ir_labels, px, code) as f64 / px.len() as f64;
    (share(&face, OTHER), share(&shade, ATTACHED))
}

/// The face's columns in the IR view, wholly inside it: cx + fx·0.1/1.1 to cx + fx·0.1/0.9.
fn grazing_face_cols(calib: &Calibration) -> std::ops::Range<usize> {
    let (fx, cx) = (calib.depth.fx, calib.depth.cx);
    (cx + fx * 0.1 / 1.1).ceil() as usize + 1..(cx + fx * 0.1 / 0.9).floor() as usize
}

/// The frame of [`grazing_side_face_tinted`], with the face's pixels blanked in rows 200..280
/// of the raw map (no depth at a grazing angle), and its calibration.
fn grazing_side_face_frame(
    colour: [f64; 3],
    rgb_noise: f64,
    seed: u64,
    tint: [f64; 3],
) -> (Calibration, SynthFrame) {
    let calib = Calibration::nyu_default();
    let mut scene = Scene::new("box with a grazing side face");
    scene.push(
        "wall",
        umbra::synth::scene::wall(3.0),
        umbra::synth::Material::matte([0.8, 0.8, 0.75]),
    );
    push_box(
        &mut scene,
        "box",
        [0.2, 0.0, 1.0],
        [0.1, 0.3, 0.1],
        umbra::synth::Material::matte(colour),
    );
    let sensor = SensorModel {
        rgb_noise_sigma: rgb_noise,
        ..SensorModel::kinect()
    };
    let mut frame = render_frame(&scene, &calib, &sensor, seed);
    // The face (x = 0.1 m, z = 0.9..1.1 m) in the RGB image, between its far and near edges.
    let x_rgb = |z: f64| calib.rgb.fx * (0.1 + calib.depth_to_rgb.translation.x) / z + calib.rgb.cx;
    for v in 150..330 {
        for u in x_rgb(1.1).ceil() as usize..=x_rgb(0.9).floor() as usize {
            let i = v * WIDTH + u;
            for (k, t) in tint.iter().enumerate() {
                let c = &mut frame.rgb[3 * i + k];
                *c = (f64::from(*c) * t).round().clamp(0.0, 255.0) as u8;
            }
        }
    }
    let face_cols = grazing_face_cols(&calib);
    assert!(face_cols.len() >= 8, "face {face_cols:?}");
    for v in 200..280 {
        frame.raw[v * WIDTH..(v + 1) * WIDTH][face_cols.clone()].fill(NO_DEPTH);
    }
    (calib, frame)
}

#[test]
fn glossy_pole_rim_in_its_shadows_hole_before_a_banded_wall_leaves_the_shadow_attached() {
    // A dark green pole (radius 5 cm) at 1.2 m before a wall at 2.5 m papered in cream and blue
    // bands 4 px wide. Its left rim returns no depth (14 columns blanked, as a glossy pole's
    // do), so its attached shadow, f·b·(1/1.2 − 1/2.5) = 19 px by eq. (3), and the rim are one
    // hole of about 33 px: too wide for eq. (3), and the banded wall gives the colour split no
    // one colour to end the shadow by. Read at the pole's depth, the RGB camera shows the
    // pole's green over the rim and not over the shadow: that split, where eq. (3) puts it.
    // (Measured over three frames: 0.37 of the shadow's pixels attached before, read by the
    // colour split in some rows; 0.98 now. 0.97 of the rim OTHER, 1.00 before.)
    let calib = Calibration::nyu_default();
    let w = calib.fb() * (1.0 / 1.2 - 1.0 / 2.5);
    assert!((w - 19.0).abs() < 0.5, "eq. (3) gives {w:.2} px");
    let scene = green_pole_before_banded_wall(&calib, 200.0..440.0);
    let (shadow, rim) = rim_left_of_pole_shares(&calib, &scene, 60..63, |_, _, _, _| {});
    assert!(shadow >= 0.9, "{shadow:.3} of the shadow's pixels attached");
    assert!(rim >= 0.9, "{rim:.3} of the rim's pixels OTHER");
}

#[test]
fn glossy_pole_rim_beside_a_narrow_strip_of_wall_reads_the_walls_slope_on_the_wall_alone() {
    // The glossy pole of the test above, and left of its shadow a grey panel at 2 m whose right
    // edge (IR column 328) leaves a strip of the banded wall between it and the shadow (the
    // pole's silhouette at 380 − f·0.05/1.2 = 355.7, its shadow 19 px left of it): 4 to 9 px
    // wide with the sensor's widening. Eq. (3) is carried over the shadow with the wall's slope
    // read left of the hole: read over 10 px, that crossed the panel's edge (f·b·(1/2 − 1/2.5)
    // = 4.4 px of disparity) and took it for a wall receding at the clamp's 0.5 px per pixel,
    // which put the shadow's end 9 px past the rim's start, and no rim was read. A step between
    // neighbours that parts two surfaces is no slope: the wall is read as level there.
    // (Measured over three frames: 0.001 of the shadow's pixels attached before, 0.98 now; of
    // the rim, 1.00 OTHER before, 0.97 now.)
    let (shadow, rim) = pole_beside_panel_shares(328.0, 4..10);
    assert!(shadow >= 0.9, "{shadow:.3} of the shadow's pixels attached");
    assert!(rim >= 0.9, "{rim:.3} of the rim's pixels OTHER");
}

#[test]
fn glossy_pole_rim_beside_a_strip_of_wall_a_pixel_or_two_wide_is_read() {
    // The scene of the test above with the panel's edge at IR column 332: the strip of wall
    // between it and the pole's shadow is 0 to 5 px wide (the sensor's widening moves the
    // shadow's left end by 0–3 px a row). The rim reading read the wall's colour over the 4 px
    // left of the hole, and refused the row where those were not all wall. It reads them over
    // as many as are. (Measured over three frames: 0.964 of the shadow's pixels attached, 0.970
    // of the rim's OTHER; before, 0.149 and 0.994.)
    let (shadow, rim) = pole_beside_panel_shares(332.0, 0..6);
    assert!(shadow >= 0.9, "{shadow:.3} of the shadow's pixels attached");
    assert!(rim >= 0.9, "{rim:.3} of the rim's pixels OTHER");
}

/// [`rim_left_of_pole_shares`] for the glossy pole before the banded wall with a grey panel at
/// 2 m from IR column 240 to `edge` left of the pole's shadow, each row's strip of wall between
/// them checked to be `strip` pixels wide.
fn pole_beside_panel_shares(edge: f64, strip: std::ops::Range<usize>) -> (f64, f64) {
    let calib = Calibration::nyu_default();
    let mut scene = green_pole_before_banded_wall(&calib, 200.0..440.0);
    let x_at = |u: f64, z: f64| (u - calib.depth.cx) / calib.depth.fx * z;
    let (left, right) = (x_at(240.0, 2.0), x_at(edge, 2.0));
    push_box(
        &mut scene,
        "panel",
        [(left + right) / 2.0, 0.0, 2.0],
        [(right - left) / 2.0, 1.0, 0.01],
        umbra::synth::Material::matte([0.5, 0.5, 0.5]),
    );
    let near = calib.raw_from_depth(1.6) as u16;
    rim_left_of_pole_shares(&calib, &scene, 80..83, |v, row, truth, first| {
        // The strip of wall between the panel and the shadow.
        let wall = (300..first)
            .filter(|&u| truth[u] == VALID && row[u] > near)
            .filter(|&u| calib.depth_m(row[u]).is_some_and(|z| z > 2.3))
            .count();
        assert!(strip.contains(&wall), "row {v}: a strip of {wall} px");
    })
}

/// Over frames `seeds` of a scene with the glossy green pole at 1.2 m over IR column 380 (the
/// tests above), the first 14 measured columns of its left side blanked in IR rows 200..280 as a
/// glossy rim's are: the shares of the shadow's pixels left of the pole (the simulator's
/// IR-view truth, columns 300..400) labelled attached and of the blanked rim's labelled OTHER.
/// `check(v, row, truth, first)` sees each row's raw values after the blanking, its truth and
/// the pole's first measured column.
fn rim_left_of_pole_shares(
    calib: &Calibration,
    scene: &Scene,
    seeds: std::ops::Range<u64>,
    check: impl Fn(usize, &[u16], &[u8], usize),
) -> (f64, f64) {
    const RIM: usize = 14;
    let near = calib.raw_from_depth(1.6) as u16;
    let (mut shadow, mut shadow_hit, mut rim, mut rim_hit) = (0, 0, 0, 0);
    for seed in seeds {
        let mut frame = render_frame(scene, calib, &SensorModel::kinect(), seed);
        let truth = frame.ir_labels.clone();
        let mut rims = Vec::new();
        for v in 200..280 {
            let row = &mut frame.raw[v * WIDTH..(v + 1) * WIDTH];
            // The pole's first measured column (nothing else in the row is as near).
            let first = (300..WIDTH)
                .find(|&u| row[u] < near)
                .expect("the pole's left edge");
            row[first..first + RIM].fill(NO_DEPTH);
            rims.extend((first..first + RIM).map(|u| v * WIDTH + u));
            check(v, row, &truth[v * WIDTH..(v + 1) * WIDTH], first);
        }
        let out = classify_rgb(calib, &frame);
        let shade: Vec<usize> = (200..280)
            .flat_map(|v| (300..400).map(move |u| v * WIDTH + u))
            .filter(|&i| truth[i] == ATTACHED)
            .collect();
        assert!(shade.len() >= 80 * 15, "{} shadow pixels", shade.len());
        shadow += shade.len();
        shadow_hit += count_labelled(&out.ir_labels, &shade, ATTACHED);
        rim += rims.len();
        rim_hit += count_labelled(&out.ir_labels, &rims, OTHER);
    }
    (
        shadow_hit as f64 / shadow as f64,
        rim_hit as f64 / rim as f64,
    )
}

#[test]
fn glossy_pole_rim_right_of_its_middle_keeps_the_alignment_strip_past_it() {
    // A dark green pole (radius 5 cm) at 1.2 m before a banded wall at 2.5 m, its right rim
    // without depth (9 columns blanked, as a glossy pole's are). The RGB camera, 2.5 cm right,
    // sees the wall past the pole's right edge in a strip the IR camera cannot:
    // t·f_rgb·(1/1.2 − 1/2.5) = 5.6 px by hand. Filled at the wall's depth, the rim landed where
    // the strip is; read at the pole's depth, every rim column shows the pole (darker where it
    // turns from the light, its hue the same), and there it is warped. (Measured over three
    // frames: 0.15 of the strip's pixels alignment before, 0.99 now.)
    let calib = Calibration::nyu_default();
    let strip = calib.rgb.fx * 0.025 * (1.0 / 1.2 - 1.0 / 2.5);
    assert!((strip - 5.6).abs() < 0.1, "the strip is {strip:.2} px");
    let scene = green_pole_before_banded_wall(&calib, 300.0..620.0);
    let share = strip_past_blanked_right_rim(&calib, &scene, &SensorModel::kinect(), 9);
    assert!(share >= 0.85, "{share:.3} of the strip's pixels alignment");
}

#[test]
fn glossy_pole_narrow_rim_right_of_its_middle_keeps_the_alignment_strip_past_it() {
    // The dark green pole of the tests above (radius 5 cm, 1.2 m) before a plain cream wall at
    // 2.5 m, its right rim without depth over 4 columns: the strip the RGB camera sees past it
    // is 5.6 px by hand, as above. The hole is narrow enough to be the edge's own limb, which is
    // filled at the pole's depth where, read at that depth, its first column shows the pole; but
    // the rim, turned from the light, is darker than the pole's middle by more than half a
    // colour step, and was filled at the wall's depth: the warp saw the depth edge next to an
    // OTHER pixel and took the strip for a hole's. Its hue is the pole's, which the cream wall's
    // is not. (Measured over three frames: 0.85 of the strip's pixels alignment before, 0.99
    // now.)
    let share = strip_past_rim_before_cream_wall([0.1, 0.3, 0.15], false, 4);
    assert!(share >= 0.95, "{share:.3} of the strip's pixels alignment");
}

#[test]
fn grey_pole_narrow_rim_blended_by_the_lens_keeps_the_alignment_strip_past_it() {
    // A grey pole (no hue to tell it from the cream wall) like the green one above, its right
    // rim without depth over 3 columns, seen through a soft lens: the strip past it is 5.6 px by
    // hand. Read at the pole's depth, the rim's first column blends the pole with the wall past
    // it, more than half a colour step from the pole's middle, and it was filled at the wall's
    // depth, the strip lost as above. Blended, it is still twice as near the pole's colour as
    // the wall's. (Measured over three frames: 0.67 of the strip's pixels alignment before,
    // 0.99 now.)
    let share = strip_past_rim_before_cream_wall([0.3, 0.3, 0.3], true, 3);
    assert!(share >= 0.95, "{share:.3} of the strip's pixels alignment");
}

#[test]
fn black_pole_rim_blended_over_two_columns_keeps_the_alignment_strip_past_it() {
    // A black pole like the grey one above, 6 columns of its right rim without depth, a soft
    // lens: the strip past it is 5.6 px by hand. Read at the wall's depth the hole's columns must
    // show the wall (the near edge's blend allowed in the first): the lens spreads the black
    // pole's edge over the second too, which then lay more than half a step from the wall, and
    // the hole was filled at the wall's depth, the strip lost. Twice as near the wall's colour
    // as the pole's, it shows the wall. (Measured over three frames: 0.86 of the strip's pixels
    // alignment before, 0.99 now.)
    let share = strip_past_rim_before_cream_wall([0.1, 0.1, 0.1], true, 6);
    assert!(share >= 0.95, "{share:.3} of the strip's pixels alignment");
}

#[test]
fn glossy_pole_rim_wider_than_its_strip_keeps_the_alignment_strip_past_it() {
    // The green pole before the plain cream wall, 8 columns of its right rim without depth:
    // wider than the 5.6 px strip past it, so read at the wall's depth the hole's last columns
    // show the pole, not the wall, and holes of up to 8 px were read only so (as the edge's
    // limb). Read at the pole's depth every column shows the pole, as the rim reading asks of
    // wider holes: the hole takes the pole's depth and the strip opens past it. (Measured over
    // three frames: 0.83 of the strip's pixels alignment before, 0.99 now.)
    let share = strip_past_rim_before_cream_wall([0.1, 0.3, 0.15], false, 8);
    assert!(share >= 0.95, "{share:.3} of the strip's pixels alignment");
}

/// [`strip_past_blanked_right_rim`] for a pole (radius 5 cm) at 1.2 m over IR column 380, of
/// matte `colour`, before a plain cream wall at 2.5 m, seen by the NYU defaults' cameras through
/// a sharp lens or (`soft`) a soft one.
fn strip_past_rim_before_cream_wall(colour: [f64; 3], soft: bool, rim: usize) -> f64 {
    let calib = Calibration::nyu_default();
    let mut scene = Scene::new("pole before a plain wall");
    let cream = umbra::synth::Material::matte([0.8, 0.78, 0.7]);
    scene.push("wall", wall(2.5), cream);
    let x = (380.0 - calib.depth.cx) / calib.depth.fx * 1.2;
    let pole = umbra::synth::Material::matte(colour);
    scene.push("pole", vertical_rod(x, 1.2, 0.05), pole);
    let mut sensor = SensorModel::kinect();
    sensor.rgb_soft = soft;
    strip_past_blanked_right_rim(&calib, &scene, &sensor, rim)
}

/// Over three frames of a pole at 1.2 m (the scenes above), with the last `rim` measured
/// columns of its right side blanked in IR rows 200..280 as a glossy rim's are: the share of
/// the alignment strip's pixels (the simulator's RGB-view truth, RGB rows 210..270) that umbra
/// labels alignment.
fn strip_past_blanked_right_rim(
    calib: &Calibration,
    scene: &Scene,
    sensor: &SensorModel,
    rim: usize,
) -> f64 {
    let near = calib.raw_from_depth(1.6) as u16;
    let (mut total, mut found) = (0, 0);
    for seed in 70..73 {
        let mut frame = render_frame(scene, calib, sensor, seed);
        let truth = frame.rgb_labels.clone();
        for v in 200..280 {
            let row = &mut frame.raw[v * WIDTH..(v + 1) * WIDTH];
            // The pole's last measured column before the wall.
            let last = (300..WIDTH - 1)
                .rev()
                .find(|&u| row[u] < near)
                .expect("the pole's right edge");
            row[last + 1 - rim..=last].fill(NO_DEPTH);
        }
        let out = classify_rgb(calib, &frame);
        let strip: Vec<usize> = (210 * WIDTH..270 * WIDTH)
            .filter(|&i| truth[i] == ALIGNMENT)
            .collect();
        assert!(strip.len() >= 60 * 4, "{} strip pixels", strip.len());
        total += strip.len();
        found += count_labelled(&out.rgb_labels, &strip, ALIGNMENT);
    }
    found as f64 / total as f64
}

/// A dark green pole (radius 5 cm) at 1.2 m over IR column 380 before a wall at 2.5 m papered
/// in cream and blue bands 4 px wide over the IR columns `cols`: the scene of the glossy rim
/// tests, whose rims are blanked in the frames rendered from it.
fn green_pole_before_banded_wall(calib: &Calibration, cols: std::ops::Range<f64>) -> Scene {
    let mut scene = Scene::new("pole before a banded wall");
    let bands = ((cols.end - cols.start) / 4.0) as i32;
    push_cream_and_blue_bands(&mut scene, calib, (cols.start, 4.0, 2.5), 0..bands, true);
    let x = (380.0 - calib.depth.cx) / calib.depth.fx * 1.2;
    scene.push(
        "pole",
        vertical_rod(x, 1.2, 0.05),
        umbra::synth::Material::matte([0.1, 0.3, 0.15]),
    );
    scene
}

#[test]
fn box_side_face_hides_the_wall_behind_it_in_the_rgb_view_too() {
    // The blue box of `box_side_face_seen_at_a_grazing_angle_is_no_shadow`. The RGB camera sees
    // the face (OTHER) from where its far edge (1.1 m) lands to where its front edge (0.9 m)
    // does, x_rgb(z) = f_rgb·(0.1 + t_x)/z + c_x (the NYU defaults move it along x only); left
    // of that, the shadow's wall at 3 m from IR column u_back − 25 on. Warped at the wall's depth
    // the face landed under the box, which hid it, and the shadow showed over the face's columns
    // (none of them OTHER before, all of them now).
    let (calib, frame) = grazing_side_face_frame(
        [0.15, 0.35, 0.75],
        SensorModel::kinect().rgb_noise_sigma,
        40,
        [1.0; 3],
    );
    let out = classify_rgb(&calib, &frame);
    let (t_x, f_rgb, c_rgb) = (calib.depth_to_rgb.translation.x, calib.rgb.fx, calib.rgb.cx);
    let x_rgb = |x: f64, z: f64| f_rgb * (x + t_x) / z + c_rgb;
    let (fx, cx) = (calib.depth.fx, calib.depth.cx);
    let shadow_start = (cx + fx * 0.1 / 1.1) - calib.fb() * (1.0 / 1.1 - 1.0 / 3.0);
    let wall_x = (shadow_start - cx) * 3.0 / fx;
    let (s0, f0, f1) = (x_rgb(wall_x, 3.0), x_rgb(0.1, 1.1), x_rgb(0.1, 0.9));
    assert!(
        f1 - f0 >= 6.0,
        "the face spans {f0:.1}..{f1:.1} in the RGB view"
    );
    // RGB rows inside the blanked IR rows 200..280, a few rows clear of their ends (the NYU
    // defaults move the RGB camera along x only, so an IR row lands on one RGB row whatever
    // the depth).
    let v_rgb = |v: f64| calib.rgb.fy * (v - calib.depth.cy) / calib.depth.fy + calib.rgb.cy;
    let rows = v_rgb(200.0).ceil() as usize + 3..v_rgb(279.0).floor() as usize - 3;
    assert!(rows.len() >= 50, "RGB rows {rows:?}");
    let (mut face, mut shade) = (Vec::new(), Vec::new());
    for v in rows {
        face.extend((f0.ceil() as usize + 1..f1.floor() as usize).map(|u| v * WIDTH + u));
        shade.extend((s0.ceil() as usize + 4..f0.floor() as usize - 3).map(|u| v * WIDTH + u));
    }
    let share =
        |px: &[usize], code| count_labelled(&out.rgb_labels, px, code) as f64 / px.len() as f64;
    let (face, shade) = (share(&face, OTHER), share(&shade, ATTACHED));
    assert!(face >= 0.9, "{face:.3} of the face's RGB pixels OTHER");
    assert!(
        shade >= 0.95,
        "{shade:.3} of the shadow's RGB pixels attached"
    );
}

#[test]
fn box_right_side_face_above_a_floor_is_no_shadow_on_the_wall_it_hides() {
    // A green box on a floor 0.5 m below the camera, x = −0.3..−0.1 m, z = 0.9..1.1 m, before a
    // pale wall at 4 m. Left of the camera, its right face (x = −0.1) faces the IR camera at a
    // grazing angle and returns no depth (blanked here, as the grazing test above does): by hand
    // it spans columns cx − fx·0.1/0.9 to cx − fx·0.1/1.1 (248.3 to 260.1). Right of it lies the
    // floor, nearer than the wall the face hides above the box: where the floor is near enough
    // (z = 0.5·fy/(v − cy) under 1.9 m, row 392 on), eq. (3) for the floor's shadow on that wall
    // fits the hole, and the scanline reads it so. The RGB camera shows the box's green there at
    // the box's depth. In the rows below, none of the face was OTHER before in either view (all
    // of it attached in the IR view), all of it is now.
    let calib = Calibration::nyu_default();
    let (fx, cx, fy, cy) = (
        calib.depth.fx,
        calib.depth.cx,
        calib.depth.fy,
        calib.depth.cy,
    );
    let mut scene = Scene::new("box with a grazing right face on a floor");
    scene.push(
        "wall",
        umbra::synth::scene::wall(4.0),
        umbra::synth::Material::matte([0.8, 0.8, 0.75]),
    );
    scene.push(
        "floor",
        umbra::synth::scene::floor(0.5, 0.0),
        umbra::synth::Material::matte([0.6, 0.5, 0.45]),
    );
    push_box(
        &mut scene,
        "box",
        [-0.2, 0.2, 1.0],
        [0.1, 0.3, 0.1],
        umbra::synth::Material::matte([0.2, 0.6, 0.25]),
    );
    let (u_front, u_back) = (cx - fx * 0.1 / 0.9, cx - fx * 0.1 / 1.1);
    let mut frame = render_frame(&scene, &calib, &SensorModel::kinect(), 40);
    // From above the box's top (y = −0.1 m: row 173.7 at its front) down: no depth on the face.
    let blank = u_front.ceil() as usize..u_back.floor() as usize + 1;
    assert_eq!(blank, 249..261);
    for v in 170..HEIGHT {
        frame.raw[v * WIDTH..(v + 1) * WIDTH][blank.clone()].fill(NO_DEPTH);
    }
    let first_row = (cy + 0.5 * fy / 1.9).ceil() as usize;
    assert_eq!(first_row, 392);
    let face: Vec<usize> = (first_row..470)
        .flat_map(|v| (blank.start + 1..blank.end - 1).map(move |u| v * WIDTH + u))
        .collect();
    let out = classify_rgb(&calib, &frame);
    let other = count_labelled(&out.ir_labels, &face, OTHER) as f64 / face.len() as f64;
    assert!(other >= 0.9, "{other:.3} of the face's pixels OTHER");
    // The RGB camera sees the face from its front edge, x_rgb = f_rgb·(−0.1 + t_x)/0.9 + c_x
    // (253.4), to its back edge (266.6); the face's first 8 columns there, in the RGB rows of
    // those IR rows (the NYU defaults move the RGB camera along x only).
    let (t_x, f_rgb, c_rgb) = (calib.depth_to_rgb.translation.x, calib.rgb.fx, calib.rgb.cx);
    let front = f_rgb * (-0.1 + t_x) / 0.9 + c_rgb;
    let v_rgb = |v: f64| calib.rgb.fy * (v - cy) / fy + calib.rgb.cy;
    let rgb_face: Vec<usize> = (v_rgb(first_row as f64).ceil() as usize + 1
        ..v_rgb(469.0).floor() as usize)
        .flat_map(|v| {
            (front.ceil() as usize + 1..front.ceil() as usize + 9).map(move |u| v * WIDTH + u)
        })
        .collect();
    let rgb_other =
        count_labelled(&out.rgb_labels, &rgb_face, OTHER) as f64 / rgb_face.len() as f64;
    assert!(
        rgb_other >= 0.9,
        "{rgb_other:.3} of the face's RGB pixels OTHER"
    );
}

#[test]
fn strip_past_a_box_whose_right_edge_returns_no_depth_is_alignment() {
    // A grey-brown box, front face x = −0.2..0.1 m at 1 m, before the pale wall at 3 m. Its last
    // 6 mm (about 3.5 px) are glossy: the same colour in the RGB image, no depth in the IR one, as
    // a turned-away edge or a cylinder's limb gives. Past that edge the RGB camera sees wall the
    // IR camera cannot, f_rgb·0.025·(1/1 − 1/3) = 8.6 px of it per row: alignment (the
    // simulator's labels, ray-cast). The box is too close to the wall in colour for the reading
    // after the warp (a strip after a high-contrast edge) to find it.
    let calib = Calibration::nyu_default();
    let mut scene = before_a_pale_wall("box with a glossy right edge");
    let colour = [0.5, 0.45, 0.38];
    push_box(
        &mut scene,
        "box",
        [-0.05, 0.0, 1.1],
        [0.15, 0.3, 0.1],
        umbra::synth::Material::matte(colour),
    );
    push_box(
        &mut scene,
        "box",
        [0.103, 0.0, 1.1],
        [0.003, 0.3, 0.1],
        umbra::synth::Material::glossy(colour),
    );
    let strip = calib.rgb.fx * 0.025 * (1.0 - 1.0 / 3.0);
    assert!((8.0..9.0).contains(&strip), "{strip}");
    let c = kinect_confusion(&scene, &calib, 60, true);
    let alignment = c.class(ALIGNMENT);
    let (f1, p, r) = (
        alignment.f1.unwrap_or(0.0),
        alignment.precision.unwrap_or(0.0),
        alignment.recall.unwrap_or(0.0),
    );
    // 0.994 measured; 0.051 when the hole is warped at the wall's depth.
    assert!(f1 >= 0.9, "alignment F1 {f1:.3} (P {p:.3} R {r:.3})");
}

#[test]
fn detached_shadow_whose_right_end_hides_behind_a_nearer_rod() {
    // A 3 cm rod at 1.2 m (x = 0.1 m) before the pale wall at 3 m: its shift is
    // f·b·(1/1.2 − 1/3) = 21.8 px, more than its width (14.6 px), so its shadow is detached:
    // columns cx + fx·0.085/1.2 − 21.8 = cx + 19.5 to cx + 26.8, then a lit gap up to the rod at
    // cx + 41.3. A 2 cm rod at 0.7 m (x = 0.05 m) stands before that gap, from cx + fx·0.04/0.7
    // = cx + 33.3 to cx + 50.0: it hides the gap, the shadow's last pixel or so and the far rod's
    // left part. The hole left of it is the far rod's shadow (the simulator's labels), whose right
    // end eq. (5) must measure against the wall, not against the near rod. (The near rod's own
    // shadow lies 48 px left of it, on lit wall, apart.)
    let calib = Calibration::nyu_default();
    let mut scene = before_a_pale_wall("a rod before a rod");
    push_grey_rod(&mut scene, 0.1, 1.2, 0.015);
    push_grey_rod(&mut scene, 0.05, 0.7, 0.01);
    let shift = calib.fb() * (1.0 / 1.2 - 1.0 / 3.0);
    assert!((21.0..22.5).contains(&shift), "{shift}");
    let near_rod = (calib.depth.cx + 33.3).round() as usize;
    // The hole touching the near rod's left edge (within the widening), by the labels.
    let [(truth, got)] = depth_hits(
        &scene,
        &calib,
        70..72,
        (40..HEIGHT - 40, near_rod - 25..near_rod + 3),
        [DETACHED],
    );
    assert!(truth >= 2 * 300 * 5, "{truth} shadow pixels in the scene");
    // 12 933 of 12 934 measured; 5 without the test against the wall (the hole was OTHER).
    assert!(got * 10 >= truth * 9, "{got} of {truth} detached");
}

#[test]
fn black_rod_whose_hole_merges_with_a_box_shadow_keeps_its_detached_shadow() {
    // A grey box, front face at 1 m from x = −0.05 m (column cx − 29.1), before the pale wall at
    // 3 m: its attached shadow, f·b·(1/1 − 1/3) = 29.1 px, spans cx − 58.2 to cx − 29.1. A black
    // rod of 3 cm at 1.2 m stands just left of it, columns cx + fx·(−0.1349 ± 0.015)/1.2 =
    // cx − 72.8 to cx − 58.2: its hole and the shadow are one hole, closed by the box, too wide
    // for eq. (3). The rod's own shadow, shifted f·b·(1/1.2 − 1/3) = 21.8 px, lies at cx − 94.6
    // to cx − 80.0, a lit gap of 7 px before the rod's hole: a detached shadow, which pairs with
    // the part of the merged hole left once the box's attached shadow (eq. 3) is taken off its
    // right end; that end is then the box's attached shadow. Depth alone: the scanline's reading.
    let calib = Calibration::nyu_default();
    let mut scene = before_a_pale_wall("a black rod beside a box's shadow");
    push_box(
        &mut scene,
        "box",
        [0.2, 0.0, 1.1],
        [0.25, 0.35, 0.1],
        umbra::synth::Material::matte([0.6, 0.6, 0.65]),
    );
    scene.push(
        "rod",
        umbra::synth::Shape::Cylinder {
            centre: umbra::synth::V3::new(-0.1349, 0.0, 1.2),
            axis: umbra::synth::V3::new(0.0, 1.0, 0.0),
            radius: 0.015,
            half_len: 3.0,
        },
        umbra::synth::Material::black(),
    );
    let (box_shadow, rod_shift) = (
        calib.fb() * (1.0 - 1.0 / 3.0),
        calib.fb() * (1.0 / 1.2 - 1.0 / 3.0),
    );
    assert!((box_shadow - 29.1).abs() < 0.2 && (rod_shift - 21.8).abs() < 0.2);
    let cx = calib.depth.cx;
    let [(det, det_ok), (att, att_ok)] = depth_hits(
        &scene,
        &calib,
        80..82,
        (180..300, (cx - 100.0) as usize..(cx - 20.0) as usize),
        [DETACHED, ATTACHED],
    );
    // Measured: 97 % detached, 94 % attached; without the pairing, 1 % and none (all OTHER).
    assert!(
        det >= 2 * 120 * 14 && att >= 2 * 120 * 28,
        "the scene: {det} detached, {att} attached"
    );
    assert!(det_ok * 10 >= det * 9, "{det_ok} of {det} detached");
    assert!(att_ok * 10 >= att * 9, "{att_ok} of {att} attached");
}

#[test]
fn glossy_box_dropout_before_its_own_other_colour_is_no_shadow() {
    // A matte purple box, front face at 1 m from x = −0.15 to 0 m, before the pale wall at 3 m.
    // On its right it runs on glossy: purple to x = 0.05 m (29 px), then green to 0.08 m
    // (17 px). The IR camera gets no depth there (the simulator's labels: OTHER), and the RGB
    // camera, read at the box's depth, sees purple beside the hole, purple, then green: a
    // shadow on the box's face and a nearer depthless occluder, to colour alone. But such an
    // occluder would stand 29 px of disparity before the box, and an attached shadow's occluder
    // is at least as wide as its shift: the IR camera, seeing the wall from x = 0.08 m on,
    // would have seen 29 px of it, not 17.
    // 0 of 25 761 measured; 23 521 without the test of the occluder's width.
    glossy_box_dropouts_are_no_shadow(0.08, 80..82, 40);
}

#[test]
fn black_rods_detached_shadow_pairs_with_its_hole_widened_by_a_black_strip() {
    // A black rod 2.4 cm thick at 1.2 m (x = 0.1 m) before the pale wall at 3 m: no depth on it,
    // fx·0.024/1.2 = 11.6 px wide, shift f·b·(1/1.2 − 1/3) = 21.8 px, so its shadow is detached,
    // a 10 px lit gap left of the rod. A black strip 4 px wide on the wall right behind the rod's
    // right edge joins the rod's hole: 15.6 px, wider than the shadow's 11.6 px plus the
    // sensor's widening in most rows, as a real sensor's own widening of the rod's hole makes it.
    let calib = Calibration::nyu_default();
    let mut scene = before_a_pale_wall("black rod beside a black strip");
    let (x, z, r) = (0.1, 1.2, 0.012);
    scene.push(
        "rod",
        umbra::synth::Shape::Cylinder {
            centre: umbra::synth::V3::new(x, 0.0, z),
            axis: umbra::synth::V3::new(0.0, 1.0, 0.0),
            radius: r,
            half_len: 3.0,
        },
        umbra::synth::Material::black(),
    );
    // Where the camera sees the rod's right edge on the wall, and 4 px of wall from there.
    let x0 = (x + r) * 3.0 / z;
    let w = 4.0 * 3.0 / calib.depth.fx;
    push_box(
        &mut scene,
        "strip",
        [x0 + w / 2.0, 0.0, 2.995],
        [w / 2.0, 3.0, 0.004],
        umbra::synth::Material::black(),
    );
    let width = calib.depth.fx * 2.0 * r / z;
    let shift = calib.fb() * (1.0 / z - 1.0 / 3.0);
    assert!((11.0..12.0).contains(&width) && (21.0..22.5).contains(&shift));
    let c = kinect_confusion(&scene, &calib, 0, false);
    let detached = c.class(DETACHED);
    let (truth, recall) = (detached.support, detached.recall.unwrap_or(0.0));
    assert!(
        truth >= 2 * 400 * 10,
        "{truth} detached pixels in the scene"
    );
    // 0.91 measured; 0.04 when a shadow may look at most 1 px narrower than its occluder's hole.
    assert!(recall >= 0.85, "detached recall {recall:.3} of {truth}");
}

#[test]
fn glossy_box_dropout_with_no_strip_past_its_other_colour_is_no_shadow() {
    // The purple box of `glossy_box_dropout_before_its_own_other_colour_is_no_shadow`, its
    // glossy purple part (29 px) then glossy green on to x = 0.13 m (46 px): an occluder as wide
    // as a 29 px shift needs. But a depthless occluder 29 px of disparity before the box would
    // show the RGB camera a strip of wall past its right edge, its shift over the wall's a third
    // wide (f_rgb·0.025·(1/0.55 − 1/3) ≈ 21 px, at the depth that shift gives); the RGB camera
    // sees green over the first half of it, up to where the box's own depth puts the edge.
    // 0 of 42 000 measured; 23 520 without the strip's test.
    glossy_box_dropouts_are_no_shadow(0.13, 84..86, 70);
}

/// A matte purple box, front face at 1 m from x = −0.15 to 0 m, before the pale wall at 3 m,
/// running on glossy (no depth) on its right: purple to x = 0.05 m, then green to `green_to`.
fn glossy_box_in_two_colours(green_to: f64) -> Scene {
    let mut scene = before_a_pale_wall("glossy box in two colours");
    let purple = [0.45, 0.25, 0.5];
    let parts = [
        (-0.15, 0.0, umbra::synth::Material::matte(purple)),
        (0.0, 0.05, umbra::synth::Material::glossy(purple)),
        (
            0.05,
            green_to,
            umbra::synth::Material::glossy([0.25, 0.5, 0.2]),
        ),
    ];
    for (from, to, material) in parts {
        let (centre, half) = ((from + to) / 2.0, (to - from) / 2.0);
        push_box(
            &mut scene,
            "box",
            [centre, 0.0, 1.1],
            [half, 0.3, 0.1],
            material,
        );
    }
    scene
}

/// Asserts that the dropouts of [`glossy_box_in_two_colours`]`(green_to)` are no shadow: through
/// the Kinect sensor model, one frame per seed, classified with the RGB image, at least
/// `min_cols` columns of hole pixels the simulator labels OTHER in each of 280 rows per frame
/// (from 2 px left of the image's centre to the green part's end), and at most one in fifty of
/// them called attached.
fn glossy_box_dropouts_are_no_shadow(green_to: f64, seeds: std::ops::Range<u64>, min_cols: usize) {
    let calib = Calibration::nyu_default();
    let scene = glossy_box_in_two_colours(green_to);
    let cx = calib.depth.cx;
    let cols = (cx - 2.0).round() as usize..(cx + calib.depth.fx * green_to + 2.0).round() as usize;
    let (mut holes, mut attached) = (0, 0);
    let frames = (seeds.end - seeds.start) as usize;
    for seed in seeds {
        let frame = render_frame(&scene, &calib, &SensorModel::kinect(), seed);
        let out = classify_rgb(&calib, &frame);
        for v in 100..HEIGHT - 100 {
            for i in cols.clone().map(|u| v * WIDTH + u) {
                if frame.raw[i] == NO_DEPTH && frame.ir_labels[i] == OTHER {
                    holes += 1;
                    attached += usize::from(out.ir_labels[i] == ATTACHED);
                }
            }
        }
    }
    assert!(
        holes >= frames * 280 * min_cols,
        "{holes} dropout pixels in the scene"
    );
    assert!(
        attached * 50 <= holes,
        "{attached} of {holes} dropout pixels called attached"
    );
}

/// `scene` through the Kinect sensor model, one frame per seed, classified from depth alone:
/// per code of `codes`, how many hole pixels in the window (rows, columns) the simulator labels
/// so, and how many of them the classifier labels so too.
fn depth_hits<const N: usize>(
    scene: &Scene,
    calib: &Calibration,
    seeds: std::ops::Range<u64>,
    (rows, cols): (std::ops::Range<usize>, std::ops::Range<usize>),
    codes: [u8; N],
) -> [(usize, usize); N] {
    let mut hits = [(0, 0); N];
    for seed in seeds {
        let frame = render_frame(scene, calib, &SensorModel::kinect(), seed);
        let out = classify(calib, &frame);
        for v in rows.clone() {
            for i in cols.clone().map(|u| v * WIDTH + u) {
                if frame.raw[i] != NO_DEPTH {
                    continue;
                }
                for (&code, (truth, got)) in codes.iter().zip(&mut hits) {
                    if frame.ir_labels[i] == code {
                        *truth += 1;
                        *got += usize::from(out.ir_labels[i] == code);
                    }
                }
            }
        }
    }
    hits
}

/// A matte cylinder 0.2 m in radius, its axis upright at 1 m, before a pale wall at 3 m, and a
/// black plate `width` metres wide lying on its face `phi` degrees left of the camera's line of
/// sight, from above the cylinder's top down to its middle: a dropout in a curved surface that
/// runs off the surface's top. Returns the scene and, by hand, the image columns the plate
/// covers and the rows where it lies on the cylinder.
fn dropout_on_a_cylinder_over_its_top(
    phi: f64,
    width: f64,
) -> (Scene, std::ops::Range<usize>, std::ops::Range<usize>) {
    let calib = Calibration::nyu_default();
    let d = calib.depth;
    let (axis, radius) = ([0.1, 0.0, 1.0], 0.2);
    let mut scene = before_a_pale_wall("dropout on a cylinder, over its top");
    scene.push(
        "cylinder",
        umbra::synth::Shape::Cylinder {
            centre: umbra::synth::V3::from(axis),
            axis: umbra::synth::V3::new(0.0, 1.0, 0.0),
            radius,
            half_len: 0.3,
        },
        umbra::synth::Material::matte([0.45, 0.5, 0.62]),
    );
    // Tangent to the face at `phi`: its front is the surface's outward normal there.
    let (s, c) = phi.to_radians().sin_cos();
    let at = |off: f64, along: f64| [axis[0] - off * s - along * c, axis[2] - off * c + along * s];
    let [x, z] = at(radius + 0.002, 0.0);
    let (top, bottom) = (-0.4, 0.0);
    scene.push(
        "black plate",
        umbra::synth::Shape::Box {
            centre: umbra::synth::V3::new(x, 0.5 * (top + bottom), z),
            half: umbra::synth::V3::new(0.5 * width, 0.5 * (bottom - top), 0.002),
            yaw: phi.to_radians(),
        },
        umbra::synth::Material::black(),
    );
    // Columns of the plate's edges, rows of the cylinder's top and the plate's bottom.
    let col = |[x, z]: [f64; 2]| d.fx * x / z + d.cx;
    let (left, right) = (col(at(radius, 0.5 * width)), col(at(radius, -0.5 * width)));
    let row = |y: f64, z: f64| d.fy * y / z + d.cy;
    let z_near = at(radius, -0.5 * width)[1];
    let rows = row(-0.3, z_near).ceil() as usize + 2..row(bottom, z) as usize - 2;
    (scene, left.ceil() as usize..right as usize, rows)
}

#[test]
fn dropout_on_a_cylinder_running_off_its_top_is_no_shadow_on_the_wall_above() {
    // In the plate's rows on the cylinder, the hole is bounded by the cylinder either side, Sb
    // nearer than Sa: too wide for eq. (3), and the face's curve carries no straight slope over
    // it. The column memory above the hole shows the wall (the plate hides the cylinder's top),
    // on which Sb's shadow would fit the hole, Sa hiding its start. Below the hole the cylinder
    // goes on at the depths between Sa and Sb: one surface, a dropout. (A glossy cylinder's
    // dropouts on a fifth simulator: 4 400 false attached pixels in one scene.)
    let calib = Calibration::nyu_default();
    let (scene, cols, rows) = dropout_on_a_cylinder_over_its_top(35.0, 0.06);
    for seed in 70..72 {
        let frame = render_frame(&scene, &calib, &SensorModel::kinect(), seed);
        let count = |labels: &[u8], code: u8| -> usize {
            rows.clone()
                .map(|v| {
                    cols.clone()
                        .filter(|&u| labels[v * WIDTH + u] == code)
                        .count()
                })
                .sum()
        };
        let area = rows.len() * cols.len();
        assert!(
            count(&frame.ir_labels, OTHER) > area * 9 / 10,
            "the plate's hole by the simulator: {} of {area} px",
            count(&frame.ir_labels, OTHER)
        );
        let out = classify_rgb(&calib, &frame);
        let claimed = count(&out.ir_labels, ATTACHED);
        assert!(
            claimed < area / 50,
            "attached pixels claimed in the dropout (seed {seed}): {claimed} of {area}"
        );
    }
}

#[test]
fn box_side_face_above_a_farther_box_is_no_shadow_of_that_box() {
    // A tall box, front face x = −0.35..−0.15 m at 1.15 m, 0.2 m deep, left of the camera: the
    // camera sees its right side face, x = −0.15, at a grazing angle, between columns
    // cx − fx·0.15/1.15 and cx − fx·0.15/1.35, about 11 px, and the sensor measures nothing there
    // (blanked by hand, as a real sensor loses such a face). Right of the face, from the middle
    // of the frame down, a lower box at 1.45 m; above it, the wall at 3 m. Below the lower
    // box's top the hole lies between the tall box (Sa) and the lower box (Sb), with the wall
    // above it in its columns: Sb's shadow on that wall, f·b·(1/1.45 − 1/3) ≈ 15 px, would fit
    // the hole with Sa hiding its start. But the hole runs on up past the lower box's top with
    // the same columns, and a shadow spans its occluder's rows only: it is the face, OTHER.
    // (A fifth simulator's simple scene: 2 000 false attached pixels.)
    let calib = Calibration::nyu_default();
    let (fx, fy, cx, cy) = (
        calib.depth.fx,
        calib.depth.fy,
        calib.depth.cx,
        calib.depth.cy,
    );
    let mut scene = before_a_pale_wall("box side face above a farther box");
    push_box(
        &mut scene,
        "tall box",
        [-0.25, 0.0, 1.25],
        [0.1, 0.45, 0.1],
        umbra::synth::Material::matte([0.35, 0.2, 0.12]),
    );
    push_box(
        &mut scene,
        "lower box",
        [0.03, 0.25, 1.55],
        [0.2, 0.25, 0.1],
        umbra::synth::Material::matte([0.55, 0.5, 0.4]),
    );
    let (u_front, u_back) = (cx - fx * 0.15 / 1.15, cx - fx * 0.15 / 1.35);
    let face = u_front.ceil() as usize..u_back.floor() as usize + 1;
    assert!(face.len() >= 9, "face {face:?}");
    // Rows of the tall box (its front's top and bottom edges); the lower box's top is at y = 0,
    // row cy.
    let rows = (cy - fy * 0.45 / 1.15).ceil() as usize..(cy + fy * 0.45 / 1.15) as usize;
    let lower_top = cy as usize;
    for seed in 80..82 {
        let mut frame = render_frame(&scene, &calib, &SensorModel::kinect(), seed);
        for v in rows.clone() {
            frame.raw[v * WIDTH..(v + 1) * WIDTH][face.clone()].fill(NO_DEPTH);
        }
        let out = classify_rgb(&calib, &frame);
        let below: Vec<usize> = (lower_top + 4..rows.end - 4)
            .flat_map(|v| face.clone().map(move |u| v * WIDTH + u))
            .collect();
        let claimed = count_labelled(&out.ir_labels, &below, ATTACHED);
        assert!(
            claimed * 50 < below.len(),
            "the face below the lower box's top called attached (seed {seed}): {claimed} of {} px",
            below.len()
        );
    }
}

#[test]
fn narrow_deep_box_whose_side_the_projector_sees_casts_an_attached_shadow() {
    // A narrow, deep box left of the camera: front face x = −0.100..−0.083 m at z = 1.0 m, 0.3 m
    // deep, before the pale wall at 3 m. The camera sees its front face and its right side face
    // (the box lies left of it): from −58.3 to −37.3 px of cx, 21 px, narrower by 8 px than the
    // shift of its front edge, f·b·(1/1 − 1/3) = 29.1 px. Had it no depth, that 8 px gap between
    // shadow and box would be lit (a detached shadow), far more than the sensor's widening
    // swallows. But the projector sees the side face too, and its back edge's shadow,
    // f·b·(1/1.3 − 1/3) = 19.0 px left of −37.3, ends at −56.3, behind the box: the whole hole
    // is one attached shadow, as the simulator's ray casting labels it. The RGB camera sees the
    // wall lit over all of it.
    let calib = Calibration::nyu_default();
    let (fx, fb) = (calib.depth.fx, calib.fb());
    let (x0, x1, z0, z1) = (-0.100, -0.0832, 1.0, 1.3);
    let width = fx * (x1 / z1 - x0 / z0);
    let (w_front, w_back) = (fb * (1.0 / z0 - 1.0 / 3.0), fb * (1.0 / z1 - 1.0 / 3.0));
    assert!(
        width + 4.0 < w_front && width > w_back,
        "{width:.1} {w_front:.1} {w_back:.1}"
    );
    let mut scene = before_a_pale_wall("narrow deep box");
    push_box(
        &mut scene,
        "box",
        [(x0 + x1) / 2.0, 0.0, (z0 + z1) / 2.0],
        [(x1 - x0) / 2.0, 0.3, (z1 - z0) / 2.0],
        umbra::synth::Material::matte([0.3, 0.45, 0.6]),
    );
    let (mut shadow, mut attached, mut detached) = (0, 0, 0);
    for seed in 70..73 {
        let frame = render_frame(&scene, &calib, &SensorModel::kinect(), seed);
        let out = classify_rgb(&calib, &frame);
        let truth: Vec<usize> = (0..frame.ir_labels.len())
            .filter(|&i| frame.ir_labels[i] == ATTACHED)
            .collect();
        shadow += truth.len();
        attached += count_labelled(&out.ir_labels, &truth, ATTACHED);
        detached += count_labelled(&out.ir_labels, &truth, DETACHED);
    }
    assert!(
        shadow > 3 * 20 * 300,
        "{shadow} attached pixels in the truth"
    );
    let share = attached as f64 / shadow as f64;
    // Measured: 0.997 attached over three frames (none before: all detached).
    assert!(
        share >= 0.9,
        "{share:.3} of the shadow attached, {detached} pixels detached"
    );
}

#[test]
fn shadow_on_a_receding_wall_past_the_frames_farthest_value_stays_attached() {
    // A wall turned 30° away to the right, z = 3.31 m + x·tan 30°, and a panel at 1 m covering
    // the view from column 560 (x = 0.424 m) to the right border, its attached shadow on the wall
    // about 35 px wide. Along a row the wall lies at 3.31 / (1 − tan 30°·(u − cx)/fx): 4.17 m at
    // column 521, where the shadow starts, and 4.38 m at 560, behind the panel's edge. So the
    // whole shadow lies on the wall inside the sensor's 4.5 m, though past the farthest value
    // the frame measures (the wall just left of the shadow). Carried over the shadow, the wall's
    // slope, read off 16 noisy pixels, crossed that value in a fifth of the shadow's pixels.
    let calib = Calibration::nyu_default();
    let tilt = 30f64.to_radians();
    let mut scene = Scene::new("panel before a wall receding towards the range's end");
    scene.push(
        "wall",
        umbra::synth::Shape::Plane {
            normal: umbra::synth::V3::new(tilt.sin(), 0.0, -tilt.cos()),
            offset: -3.31 * tilt.cos(),
        },
        umbra::synth::Material::matte([0.8, 0.78, 0.7]),
    );
    push_box(
        &mut scene,
        "panel",
        [0.424 + 0.3, 0.0, 1.0],
        [0.3, 3.0, 0.02],
        umbra::synth::Material::matte([0.3, 0.45, 0.6]),
    );
    let mut c = Confusion::default();
    for seed in 0..8 {
        let frame = render_frame(&scene, &calib, &SensorModel::kinect(), seed);
        c.add(&frame.ir_labels, &classify(&calib, &frame).ir_labels);
    }
    let attached = c.class(ATTACHED);
    assert!(
        attached.support > 100_000,
        "the scene has the shadow: {} px",
        attached.support
    );
    assert!(
        attached.recall.unwrap() >= 0.95,
        "{:?} of the shadow's pixels attached",
        attached.recall
    );
}

#[test]
fn black_rod_before_a_boxs_edge_is_its_detached_shadows_occluder_whole() {
    // A teal wall at 2.2 m; a black rod, r = 2.1 cm at x = 0, 0.61 m; a green box whose front
    // face (0.98 m) starts at x = 0.034 m, just right of the rod. By hand the rod spans
    // cx ± fx·0.021/0.61 = ±20.1 px and its shadow lies f·b·(1/0.61 − 1/2.2) = 51.8 px further
    // left: a detached shadow as wide as the rod, a lit gap of about 12 px, then the rod's hole,
    // closed on the right by the box, not by the wall. (The box's own shadow, 24.7 px wide, lies
    // behind the rod.) A pale stripe on the wall behind the rod, which the RGB camera sees
    // between the rod and the box, passed for a thin occluder right of a 36 px attached shadow
    // in every row, as in a fifth simulator's scene (k9 s017).
    let calib = Calibration::nyu_default();
    let shift = calib.fb() * (1.0 / 0.61 - 1.0 / 2.2);
    assert!((51.0..53.0).contains(&shift), "shift {shift}");
    let (cx, half) = (calib.depth.cx, calib.depth.fx * 0.021 / 0.61);
    assert!((20.0..20.3).contains(&half), "rod half-width {half}");
    let rod = (cx - half).ceil() as usize..(cx + half) as usize;
    let shadow = (cx - half - shift).ceil() as usize..(cx + half - shift) as usize;
    let mut scene = Scene::new("a black rod before a box's edge, before a wall");
    scene.push(
        "wall",
        wall(2.2),
        umbra::synth::Material::matte([0.09, 0.39, 0.42]),
    );
    scene.push(
        "rod",
        vertical_rod(0.0, 0.61, 0.021),
        umbra::synth::Material::black(),
    );
    let stripe = umbra::synth::Shape::Box {
        centre: umbra::synth::V3::new(0.01, 0.0, 2.195),
        half: umbra::synth::V3::new(0.07, 3.0, 0.004),
        yaw: 0.0,
    };
    scene.push(
        "stripe",
        stripe,
        umbra::synth::Material::matte([0.38, 0.53, 0.57]),
    );
    let box_shape = umbra::synth::Shape::Box {
        centre: umbra::synth::V3::new(0.034 + 0.1, 0.0, 0.98 + 0.05),
        half: umbra::synth::V3::new(0.1, 0.15, 0.05),
        yaw: 0.0,
    };
    scene.push(
        "box",
        box_shape,
        umbra::synth::Material::matte([0.18, 0.51, 0.36]),
    );
    // Camera noise (σ, 8-bit): at 8 a dim wall's pixels stray past the colour step here and
    // there, in the shadow too.
    for (sigma, most_wrong) in [(4.0, 0.0), (8.0, 0.25)] {
        let sensor = SensorModel {
            rgb_noise_sigma: sigma,
            ..SensorModel::kinect()
        };
        let frame = render_frame(&scene, &calib, &sensor, 3);
        let out = classify_rgb(&calib, &frame);
        let (mut rows, mut truth, mut found, mut wrong) = (0, 0, 0, 0);
        for v in 180..300 {
            let row = v * WIDTH;
            // The simulator's rod and shadow lie where the hand computation puts them.
            let count = |labels: &[u8], us: &std::ops::Range<usize>, code| {
                us.clone().filter(|&u| labels[row + u] == code).count()
            };
            if count(&frame.ir_labels, &rod, OTHER) + 4 < rod.len()
                || count(&frame.ir_labels, &shadow, DETACHED) + 6 < shadow.len()
            {
                continue;
            }
            rows += 1;
            truth += shadow.len();
            found += count(&out.ir_labels, &shadow, DETACHED);
            wrong += count(&out.ir_labels, &rod, ATTACHED);
        }
        assert!(
            rows >= 100,
            "σ {sigma}: the scene has the pair in {rows} rows"
        );
        let recall = found as f64 / truth as f64;
        assert!(recall >= 0.9, "σ {sigma}: detached recall {recall:.3}");
        let share = wrong as f64 / (rows * rod.len()) as f64;
        assert!(
            share <= most_wrong,
            "σ {sigma}: {share:.3} of the rod read as a shadow"
        );
    }
}

#[test]
fn black_rods_hole_run_into_another_rods_shadow_still_pairs_with_its_own_shadow() {
    // A pale wall at 2 m; black rod A, r = 1.5 cm at x = 0, 0.8 m; black rod B, r = 1.2 cm at
    // 0.6 m, x = 0.0757 m. By hand A spans cx ± fx·0.015/0.8 = ±10.9 px and casts its shadow
    // f·b·(1/0.8 − 1/2) = 32.8 px further left, cx − 43.7..cx − 21.9 (detached). B spans
    // cx + 73.5 ± 11.65 px and casts its shadow f·b·(1/0.6 − 1/2) = 51.0 px left, from
    // cx + 10.9: right where A's hole ends. So A's hole runs on into B's shadow, one hole of
    // 45 px that no 22 px shadow pairs with, and A's shadow was OTHER in every row.
    let calib = Calibration::nyu_default();
    let (cx, fx, fb) = (calib.depth.cx, calib.depth.fx, calib.fb());
    let (a_half, a_shift) = (fx * 0.015 / 0.8, fb * (1.0 / 0.8 - 1.0 / 2.0));
    let (b_left, b_shift) = (fx * (0.0757 - 0.012) / 0.6, fb * (1.0 / 0.6 - 1.0 / 2.0));
    assert!(
        (b_left - b_shift - a_half).abs() < 0.5,
        "B's shadow starts where A ends"
    );
    let shadow = (cx - a_half - a_shift).ceil() as usize + 1..(cx + a_half - a_shift) as usize - 1;
    let mut scene = Scene::new("a black rod whose hole runs into another rod's shadow");
    scene.push(
        "wall",
        wall(2.0),
        umbra::synth::Material::matte([0.75, 0.72, 0.62]),
    );
    for (x, z, r) in [(0.0, 0.8, 0.015), (0.0757, 0.6, 0.012)] {
        scene.push(
            "rod",
            vertical_rod(x, z, r),
            umbra::synth::Material::black(),
        );
    }
    let frame = render_frame(&scene, &calib, &SensorModel::kinect(), 3);
    let out = classify_rgb(&calib, &frame);
    let (mut rows, mut truth, mut found, mut wrong) = (0, 0, 0, 0);
    for v in 100..380 {
        let row = v * WIDTH;
        let count =
            |labels: &[u8], code| shadow.clone().filter(|&u| labels[row + u] == code).count();
        // The simulator's shadow lies where the hand computation puts it, and the holes merge.
        let merged = ((cx + a_half) as usize..(cx + a_half) as usize + 20)
            .all(|u| frame.raw[row + u] == NO_DEPTH);
        if count(&frame.ir_labels, DETACHED) < shadow.len() || !merged {
            continue;
        }
        rows += 1;
        truth += shadow.len();
        found += count(&out.ir_labels, DETACHED);
        wrong += ((cx - a_half) as usize + 1..(cx + a_half) as usize)
            .filter(|&u| out.ir_labels[row + u] == DETACHED)
            .count();
    }
    assert!(rows >= 200, "the scene has the merged holes in {rows} rows");
    assert_recall("detached", found, truth, rows, 0.9);
    assert_eq!(wrong, 0, "pixels of rod A read as a shadow");
}

#[test]
fn rods_attached_shadow_leaves_the_part_a_nearer_box_shades_to_the_box() {
    // A pale wall at 2 m; a matte rod, r = 2 cm at x = 0, 1.2 m; a box at 0.8 m whose left face
    // starts 14 px right of the image centre. By hand the rod spans cx ± fx·0.02/1.2 = ±9.7 px
    // and its shadow on the wall lies f·b·(1/1.2 − 1/2) = 14.6 px further left: cx − 24.3 ..
    // cx − 9.7, beside it. The box shades the rod from cx + 14 − f·b·(1/0.8 − 1/1.2) = cx − 4.2
    // (a lit strip of rod 5.5 px wide is left), and the wall from cx + 14 − f·b·(1/0.8 − 1/2) =
    // cx − 18.8: across the rod and into the rod's own shadow. There the projector's ray meets
    // the box first: cx − 18.8 .. cx − 9.7 is the box's detached shadow, and one hole of 14.6 px
    // eq. (3) fits for the rod was read attached from end to end.
    let calib = Calibration::nyu_default();
    let (cx, fx, fb) = (calib.depth.cx, calib.depth.fx, calib.fb());
    let rod_left = cx - fx * 0.02 / 1.2;
    let box_left = cx + 14.0;
    let box_from = box_left - fb * (1.0 / 0.8 - 1.0 / 2.0);
    let strip_ends = box_left - fb * (1.0 / 0.8 - 1.0 / 1.2);
    assert!(
        box_from < rod_left - 5.0 && strip_ends > rod_left + 4.0,
        "the box's shadow reaches past a lit strip of the rod"
    );
    let detached = box_from.ceil() as usize + 1..rod_left as usize - 1;
    let attached = (rod_left - fb * (1.0 / 1.2 - 1.0 / 2.0)).ceil() as usize..box_from as usize - 1;
    let mut scene = Scene::new("a rod before a wall, a box's shadow across it");
    scene.push(
        "wall",
        wall(2.0),
        umbra::synth::Material::matte([0.75, 0.72, 0.62]),
    );
    scene.push(
        "rod",
        vertical_rod(0.0, 1.2, 0.02),
        umbra::synth::Material::matte([0.3, 0.4, 0.7]),
    );
    // A thin board, so the camera sees next to nothing of its left side.
    let (half, thick) = (0.15, 0.01);
    scene.push(
        "box",
        umbra::synth::Shape::Box {
            centre: umbra::synth::V3::new(14.0 / fx * 0.8 + half, 0.0, 0.8 + thick),
            half: umbra::synth::V3::new(half, 0.4, thick),
            yaw: 0.0,
        },
        umbra::synth::Material::matte([0.8, 0.3, 0.2]),
    );
    let frame = render_frame(&scene, &calib, &SensorModel::kinect(), 4);
    let out = classify_rgb(&calib, &frame);
    let (mut rows, mut truth, mut found, mut kept, mut att) = (0, 0, 0, 0, 0);
    for v in 60..420 {
        let row = v * WIDTH;
        let count = |labels: &[u8], cols: &std::ops::Range<usize>, code| {
            cols.clone().filter(|&u| labels[row + u] == code).count()
        };
        // The simulator puts both shadows where the hand computation does.
        if count(&frame.ir_labels, &detached, DETACHED) < detached.len()
            || count(&frame.ir_labels, &attached, ATTACHED) < attached.len()
        {
            continue;
        }
        rows += 1;
        truth += detached.len();
        found += count(&out.ir_labels, &detached, DETACHED);
        att += attached.len();
        kept += count(&out.ir_labels, &attached, ATTACHED);
    }
    assert!(rows >= 250, "the scene shows both shadows in {rows} rows");
    assert_recall("detached", found, truth, rows, 0.9);
    let attached_recall = kept as f64 / att as f64;
    assert!(
        attached_recall >= 0.9,
        "attached recall {attached_recall:.3} over {rows} rows"
    );
}

#[test]
fn wall_beyond_the_range_past_a_black_rod_is_no_alignment_shadow() {
    // A pale wall through (0, 0, 3.57 m) turned by −0.64 rad, its left side receding: along
    // the ray of column u it lies at z = 3.57 / (1 − tan(−0.64)·(u − cx)/fx), which passes the
    // sensor's 4.5 m at u = cx + fx·(3.57/4.5 − 1)/0.745 = cx − 161.6: left of that the IR
    // camera measures nothing, the wall beyond its range. A black rod, r = 2 cm at 1.94 m,
    // stands in that region with its right edge 15 px left of where the wall leaves the range.
    // The RGB camera sees the wall, in its own colour, from the rod up to the measured part:
    // the wall beyond range (OTHER), not a strip the rod hides from the IR camera. Read as
    // that strip, the wall was an alignment shadow in every row twice over: the colour split
    // placed the hole at the depth the strip's width gives a rod whose edge is the hole's
    // (about 0.65 m), and the warp's colour reading took the strip for one on its own.
    let calib = Calibration::nyu_default();
    let (cx, fx) = (calib.depth.cx, calib.depth.fx);
    let (z0, yaw) = (3.57, -0.64_f64);
    let leaves = cx + fx * (z0 / 4.5 - 1.0) / -yaw.tan();
    let rod_right = leaves - 15.0;
    let (z_rod, r) = (1.94, 0.02);
    let x_rod = (rod_right - cx) / fx * z_rod - r;
    let mut scene = Scene::new("a black rod before a wall that leaves the range on the left");
    scene.push(
        "wall",
        slanted_wall(z0, yaw),
        umbra::synth::Material::matte([0.75, 0.74, 0.70]),
    );
    scene.push(
        "rod",
        vertical_rod(x_rod, z_rod, r),
        umbra::synth::Material::black(),
    );
    let frame = render_frame(&scene, &calib, &SensorModel::kinect(), 6);
    // The simulator's wall leaves the range where the hand computation says.
    for v in [100, 240, 380] {
        let first = (0..WIDTH)
            .find(|&u| frame.ir_labels[v * WIDTH + u] == VALID)
            .unwrap();
        assert!(
            (first as f64 - leaves).abs() <= 2.0,
            "row {v}: the wall is measured from {first}, by hand from {leaves:.1}"
        );
    }
    let out = classify_rgb(&calib, &frame);
    let rows = 60..420;
    let count = |labels: &[u8], code| {
        rows.clone()
            .flat_map(|v| v * WIDTH..(v + 1) * WIDTH)
            .filter(|&i| labels[i] == code)
            .count()
    };
    assert_eq!(
        count(&frame.rgb_labels, ALIGNMENT),
        0,
        "the scene has no alignment shadow"
    );
    let wrong = count(&out.rgb_labels, ALIGNMENT);
    assert!(
        wrong <= rows.len(),
        "{wrong} pixels of the wall beyond the range read as alignment shadow"
    );
}

#[test]
fn thin_black_rods_attached_shadow_is_split_off_its_narrow_hole() {
    // A pale wall at 2.7 m and a black rod, r = 0.8 cm at 2.2 m. By hand the rod spans
    // cx ± fx·0.008/2.2 = ±2.1 px and shifts f·b·(1/2.2 − 1/2.7) = 3.7 px: its shadow and the
    // rod make one hole of about 8 px with the wall on both sides, narrower than the colour
    // split reads (10 px), and every row of it stayed OTHER.
    let calib = Calibration::nyu_default();
    let (cx, fx, fb) = (calib.depth.cx, calib.depth.fx, calib.fb());
    let (half, shift) = (fx * 0.008 / 2.2, fb * (1.0 / 2.2 - 1.0 / 2.7));
    assert!((3.5..3.9).contains(&shift) && (2.0..2.2).contains(&half));
    let mut scene = Scene::new("a thin black rod before a wall");
    scene.push(
        "wall",
        wall(2.7),
        umbra::synth::Material::matte([0.75, 0.72, 0.62]),
    );
    scene.push(
        "rod",
        vertical_rod(0.0, 2.2, 0.008),
        umbra::synth::Material::black(),
    );
    let frame = render_frame(&scene, &calib, &SensorModel::kinect(), 8);
    let out = classify_rgb(&calib, &frame);
    let cols = (cx - half - shift - 4.0) as usize..(cx + half + 2.0) as usize;
    let (mut truth, mut found, mut rod, mut wrong) = (0, 0, 0, 0);
    for v in 40..440 {
        for u in cols.clone() {
            let (gt, got) = (frame.ir_labels[v * WIDTH + u], out.ir_labels[v * WIDTH + u]);
            // The simulator's shadow lies left of the rod, as the hand computation says.
            assert!(
                gt != ATTACHED || (u as f64) < cx - half + 1.0,
                "row {v}, column {u}"
            );
            truth += usize::from(gt == ATTACHED);
            found += usize::from(gt == ATTACHED && got == ATTACHED);
            rod += usize::from(gt == OTHER);
            wrong += usize::from(gt == OTHER && got != OTHER);
        }
    }
    assert!(truth >= 400 * 2, "the scene has its shadow ({truth} px)");
    let recall = found as f64 / truth as f64;
    assert!(
        recall >= 0.5,
        "attached recall {recall:.3} ({found} of {truth})"
    );
    let stray = wrong as f64 / rod as f64;
    assert!(stray <= 0.05, "{wrong} of {rod} rod pixels read as shadow");
}

/// A glossy blue rod (r = 2 cm at 1.2 m) just right of the edge of a cyan board whose edge is
/// at `z_edge` (turned by `turn` radians about the vertical, its left part nearer), before a
/// pale wall at 2.0 m: by hand the rod spans ±fx·0.02/1.2 = ±9.7 px, and its shadow on the
/// board is f·b·(1/1.2 − 1/z_edge) px wide: one hole from the board to the wall, its sides one
/// surface by depth but plainly two by colour. Asserts the simulator puts the shadow there and
/// returns the attached recall over 400 rows and the share of the rod read as shadow.
fn glossy_rod_at_a_boards_edge(z_edge: f64, turn: f64) -> (f64, f64) {
    let calib = Calibration::nyu_default();
    let (cx, fx, fb) = (calib.depth.cx, calib.depth.fx, calib.fb());
    let half = fx * 0.02 / 1.2;
    assert!((9.0..10.4).contains(&half));
    let rod_u = cx + 3.0;
    let mut scene = Scene::new("a glossy rod before a cyan board's edge and a pale wall");
    scene.push(
        "wall",
        wall(2.0),
        umbra::synth::Material::matte([0.85, 0.85, 0.88]),
    );
    // The board's right edge lies on the centre column's ray.
    let (w, edge) = (1.5, umbra::synth::V3::new(0.0, 0.0, z_edge));
    scene.push(
        "board",
        umbra::synth::Shape::Box {
            centre: edge - w * umbra::synth::V3::new(turn.cos(), 0.0, turn.sin()),
            half: umbra::synth::V3::new(w, 3.0, 0.01),
            yaw: -turn,
        },
        umbra::synth::Material::matte([0.1, 0.65, 0.65]),
    );
    scene.push(
        "rod",
        vertical_rod((rod_u - cx) * 1.2 / fx, 1.2, 0.02),
        umbra::synth::Material::glossy([0.35, 0.5, 0.9]),
    );
    let frame = render_frame(&scene, &calib, &SensorModel::kinect(), 8);
    let out = classify_rgb(&calib, &frame);
    let shift = fb * (1.0 / 1.2 - 1.0 / z_edge);
    let cols = (rod_u - half - shift - 4.0) as usize..(rod_u + half + 2.0) as usize;
    let (mut truth, mut found, mut rod, mut wrong) = (0, 0, 0, 0);
    for v in 40..440 {
        for u in cols.clone() {
            let (gt, got) = (frame.ir_labels[v * WIDTH + u], out.ir_labels[v * WIDTH + u]);
            // The simulator's shadow ends where the rod starts, and lies on the board.
            if gt == ATTACHED {
                assert!(
                    (u as f64) < rod_u - half + 1.0 && (u as f64) < cx,
                    "row {v}, column {u}"
                );
            }
            truth += usize::from(gt == ATTACHED);
            found += usize::from(gt == ATTACHED && got == ATTACHED);
            rod += usize::from(gt == OTHER);
            wrong += usize::from(gt == OTHER && got != OTHER);
        }
    }
    assert!(truth >= 400 * 10, "the scene has its shadow ({truth} px)");
    (found as f64 / truth as f64, wrong as f64 / rod as f64)
}

#[test]
fn glossy_rods_shadow_on_a_coloured_board_beside_a_pale_wall_is_split_off() {
    // The board at 1.94 m, facing the camera: its shadow is 13.8 px wide, the sides 0.7 px apart
    // in disparity. Read as one background, the split found no layout and every row stayed
    // OTHER.
    let (recall, stray) = glossy_rod_at_a_boards_edge(1.94, 0.0);
    assert!(recall >= 0.8, "attached recall {recall:.3}");
    assert!(stray <= 0.05, "{stray:.3} of the rod read as shadow");
}

#[test]
fn glossy_rods_shadow_on_a_turned_board_is_read_against_the_board() {
    // The board turned 27° from the camera, its left part nearer: its edge lies 1.8 px nearer in
    // disparity than the wall, the two still one surface by depth, but the board further left
    // is more than 2 px nearer than the wall. Read against the wall's depth, the board beside
    // the hole counted as no surface of its background, and the shadow stayed OTHER.
    let fb = Calibration::nyu_default().fb();
    let z_edge = 1.0 / (0.5 + 1.8 / fb);
    let (recall, stray) = glossy_rod_at_a_boards_edge(z_edge, 27f64.to_radians());
    assert!(recall >= 0.8, "attached recall {recall:.3}");
    assert!(stray <= 0.05, "{stray:.3} of the rod read as shadow");
}

#[test]
fn box_shadow_beside_a_wide_glossy_poster_is_attached_where_the_rgb_camera_sees_the_wall() {
    // The box at 1 m before the wall at 3 m, its attached shadow columns 167.4..196.5 as above,
    // and a pale blue glossy poster from x = −1.27 to −0.73 m (columns 66..171), rows ±97: one
    // hole of about 130 px in the poster's rows. The wall's colour is read beside the hole,
    // 100 px from the shadow, and the wall's texture drifts over that: read against it alone,
    // the wall in the shadow broke off in some rows a few pixels from Sb's edge (attached recall
    // 0.843 over three frames).
    let calib = Calibration::nyu_default();
    let mut scene = Scene::box_before_wall(1.0, 3.0);
    scene.push(
        "poster",
        umbra::synth::Shape::Box {
            centre: umbra::synth::V3::new(-1.0, 0.0, 2.995),
            half: umbra::synth::V3::new(0.27, 0.5, 0.004),
            yaw: 0.0,
        },
        umbra::synth::Material::glossy([0.55, 0.62, 0.8]),
    );
    let mut c = Confusion::default();
    for seed in 60..63 {
        let frame = render_frame(&scene, &calib, &SensorModel::kinect(), seed);
        let row = &frame.ir_labels[240 * WIDTH..241 * WIDTH];
        assert!(
            row[68..169].iter().all(|&l| l == OTHER)
                && row[173..196].iter().all(|&l| l == ATTACHED),
            "poster then shadow: {:?}",
            &row[60..200]
        );
        let out = classify_rgb(&calib, &frame);
        // The poster's rows.
        for v in 150..330 {
            let r = v * WIDTH..(v + 1) * WIDTH;
            c.add(&frame.ir_labels[r.clone()], &out.ir_labels[r]);
        }
    }
    let attached = c.class(ATTACHED);
    assert!(
        attached.recall.unwrap() >= 0.93 && attached.precision.unwrap() >= 0.99,
        "attached in the poster's rows: {attached:?}"
    );
}

#[test]
fn black_boxs_shadow_along_its_slanted_top_edge_is_split_off() {
    // A black box 0.5 m wide, 0.8 m away, turned 17° from the camera, its top 0.25 m above the
    // optical axis: by perspective its top edge runs across the image at a slant (nearer, so
    // higher, at its left end). In the rows it crosses, the hole is the box's attached shadow
    // and a few pixels of box, and the box's edge moves 10 px or more from row to row; the
    // shadow's width read by colour strays by a few pixels with it, and those rows stayed
    // OTHER (attached recall 0.26 in them over three frames; 0.70 with a quarter of the
    // edge's run allowed, 0.81 with a third). Since a row of a hole with one surface on both
    // sides needs no neighbour to agree: 0.929, and 38 px wrongly claimed where 22 were (a
    // row's edge read a pixel or two off stands on its own).
    let calib = Calibration::nyu_default();
    let mut scene = before_a_pale_wall("a black box turned from the camera, above its centre");
    scene.push(
        "box",
        umbra::synth::Shape::Box {
            centre: umbra::synth::V3::new(0.05, -0.15, 0.8),
            half: umbra::synth::V3::new(0.25, 0.1, 0.1),
            yaw: 0.3,
        },
        umbra::synth::Material::black(),
    );
    let (mut found, mut truth, mut wrong) = (0, 0, 0);
    for seed in 90..93 {
        let frame = render_frame(&scene, &calib, &SensorModel::kinect(), seed);
        let out = classify_rgb(&calib, &frame);
        // The rows the top edge crosses: the simulator's row holds shadow and box, the box's
        // part less than three times as wide as the shadow.
        for v in 0..HEIGHT {
            let row = &frame.ir_labels[v * WIDTH..(v + 1) * WIDTH];
            let shadow = row.iter().filter(|&&l| l == ATTACHED).count();
            let other = row.iter().filter(|&&l| l == OTHER).count();
            if shadow == 0 || other == 0 || other >= 3 * shadow {
                continue;
            }
            for (u, &gt) in row.iter().enumerate() {
                let said = out.ir_labels[v * WIDTH + u] == ATTACHED;
                truth += usize::from(gt == ATTACHED);
                found += usize::from(gt == ATTACHED && said);
                wrong += usize::from(gt != ATTACHED && said);
            }
        }
    }
    assert!(
        truth >= 1500,
        "the top edge's rows hold its shadow ({truth} px)"
    );
    let recall = found as f64 / truth as f64;
    assert!(
        recall >= 0.75 && wrong * 100 <= 3 * found,
        "attached along the top edge: {found} of {truth} ({recall:.3}), {wrong} wrong"
    );
}

#[test]
fn pale_glossy_cylinders_shadow_on_a_wall_of_nearly_its_colour_is_split_off() {
    // A glossy cylinder, r = 8 cm at 1.3 m, pale green before a beige wall at 2.9 m: the cylinder
    // returns no depth, so it and its attached shadow are one hole. By hand the cylinder spans
    // ±fx·0.08/1.3 ≈ ±36 px and its shadow is f·b·(1/1.3 − 1/2.9) ≈ 18 px wide. The RGB camera
    // sees the wall, then the cylinder's shaded side, a strong step, then its lit face, within
    // the colour step of the wall but plainly farther from it than the wall's noise: read as
    // wall, the face left no layout explaining nine columns in ten, and the shadow stayed OTHER
    // in half the rows (attached recall 0.485 over two frames; 0.930 now).
    let calib = Calibration::nyu_default();
    let (cx, fx, fb) = (calib.depth.cx, calib.depth.fx, calib.fb());
    let (z, r, z_wall) = (1.3, 0.08, 2.9);
    let centre_u = cx + 20.0;
    let shadow = fb * (1.0 / z - 1.0 / z_wall);
    assert!((15.0..21.0).contains(&shadow), "{shadow}");
    let mut scene = before_a_wall(
        "a pale glossy cylinder before a beige wall",
        z_wall,
        [0.88, 0.85, 0.80],
    );
    scene.push(
        "cylinder",
        vertical_rod((centre_u - cx) * z / fx, z, r),
        umbra::synth::Material::glossy([0.82, 0.88, 0.81]),
    );
    let (mut truth, mut found, mut face, mut wrong) = (0, 0, 0, 0);
    for seed in 1..=2 {
        let frame = render_frame(&scene, &calib, &SensorModel::kinect(), seed);
        let out = classify_rgb(&calib, &frame);
        let left = centre_u - fx * r / z;
        let cols = (left - shadow - 6.0) as usize..(centre_u + fx * r / z + 4.0) as usize;
        for v in 40..440 {
            for u in cols.clone() {
                let (gt, got) = (frame.ir_labels[v * WIDTH + u], out.ir_labels[v * WIDTH + u]);
                // The simulator's shadow lies left of the cylinder.
                if gt == ATTACHED {
                    assert!((u as f64) < left + 2.0, "row {v}, column {u}");
                }
                truth += usize::from(gt == ATTACHED);
                found += usize::from(gt == ATTACHED && got == ATTACHED);
                face += usize::from(gt == OTHER);
                wrong += usize::from(gt == OTHER && got != OTHER);
            }
        }
    }
    assert!(
        truth >= 2 * 400 * 14,
        "the scene has its shadow ({truth} px)"
    );
    let (recall, stray) = (found as f64 / truth as f64, wrong as f64 / face as f64);
    assert!(recall >= 0.85, "attached recall {recall:.3}");
    assert!(stray <= 0.03, "{stray:.3} of the cylinder read as shadow");
}

#[test]
fn black_rods_hole_closed_by_a_thin_rod_behind_it_is_no_shadow_of_that_rod() {
    // A pale wall at 2 m; a black rod, r = 1 cm at x = 0, 0.8 m; a thin matte rod, r = 1.5 mm at
    // 1.2 m, standing just right of the black rod's edge. By hand the black rod spans
    // cx ± fx·0.01/0.8 = ±7.3 px and casts its shadow f·b·(1/0.8 − 1/2) = 32.8 px further left,
    // cx − 40.1..cx − 25.5 (detached). The thin rod, about 1.5 px wide, shifts its shadow
    // f·b·(1/1.2 − 1/2) = 14.6 px, onto the black rod's left edge: the black rod's hole, closed
    // by the thin rod on its right, is as wide as that shift, so eq. (3)'s width fits it, and it
    // was read as the thin rod's detached shadow in every row, the black rod's own shadow OTHER.
    // A 1.5 px rod casts no 15 px shadow: the lit gap of 13 px between them would show.
    let calib = Calibration::nyu_default();
    let (cx, fx, fb) = (calib.depth.cx, calib.depth.fx, calib.fb());
    let (half, shift) = (fx * 0.01 / 0.8, fb * (1.0 / 0.8 - 1.0 / 2.0));
    let (t_half, t_shift) = (fx * 0.0015 / 1.2, fb * (1.0 / 1.2 - 1.0 / 2.0));
    assert!(
        (2.0 * half - t_shift).abs() < 1.5,
        "the thin rod's shift {t_shift:.1} is about the black rod's width {:.1}",
        2.0 * half
    );
    let t_centre = cx + half + 0.3 + t_half;
    let shadow = (cx - half - shift).ceil() as usize + 1..(cx + half - shift) as usize - 1;
    let rod = (cx - half) as usize + 3..(cx + half) as usize - 1;
    let mut scene = before_a_wall(
        "a black rod closed by a thin rod behind it",
        2.0,
        [0.75, 0.72, 0.62],
    );
    scene.push(
        "black rod",
        vertical_rod(0.0, 0.8, 0.01),
        umbra::synth::Material::black(),
    );
    scene.push(
        "thin rod",
        vertical_rod((t_centre - cx) * 1.2 / fx, 1.2, 0.0015),
        umbra::synth::Material::matte([0.8, 0.55, 0.3]),
    );
    let frame = render_frame(&scene, &calib, &SensorModel::kinect(), 11);
    let out = classify_rgb(&calib, &frame);
    let (mut rows, mut truth, mut found, mut wrong) = (0, 0, 0, 0);
    for v in 100..380 {
        let row = v * WIDTH;
        let count = |labels: &[u8], code, us: &std::ops::Range<usize>| {
            us.clone().filter(|&u| labels[row + u] == code).count()
        };
        // The simulator's shadow and rod lie where the hand computation puts them, and the thin
        // rod closes the black rod's hole.
        let closed = frame.raw[row + (t_centre as usize)] != NO_DEPTH
            && frame.raw[row + (cx + half) as usize - 1] == NO_DEPTH;
        if count(&frame.ir_labels, DETACHED, &shadow) < shadow.len()
            || count(&frame.ir_labels, OTHER, &rod) < rod.len()
            || !closed
        {
            continue;
        }
        rows += 1;
        truth += shadow.len();
        found += count(&out.ir_labels, DETACHED, &shadow);
        wrong += rod.len() - count(&out.ir_labels, OTHER, &rod);
    }
    assert!(
        rows >= 200,
        "the scene has the shadow and the closed hole in {rows} rows"
    );
    assert_recall("detached", found, truth, rows, 0.9);
    assert!(
        wrong <= rows,
        "{wrong} pixels of the black rod over {rows} rows read as a shadow"
    );
}

#[test]
fn black_boxs_shadow_cut_off_by_a_thin_rod_standing_in_it_is_detached() {
    // The hand-computed black box (front face x = −0.2..0.2 m at 1 m, wall at 3 m): its attached
    // shadow is f·b·(1/1 − 1/3) = 29.1 px wide, left of its left edge at cx − fx·0.2. A thin
    // matte rod, r = 5 mm at 0.9 m (nearer than the box, so the projector lights it), stands in
    // the shadow's middle. The projector's rays to the wall left of the rod pass it and meet the
    // box: that part is the box's shadow too, cut
    // off from the box by the rod (detached, as `umbra synth` labels it). The colour split
    // finds the box and the part of its shadow right of the rod; the part left of it was left
    // OTHER, or read as the rod's own attached shadow.
    let calib = Calibration::nyu_default();
    let (cx, fx, fb) = (calib.depth.cx, calib.depth.fx, calib.fb());
    let edge = cx - fx * 0.2;
    let shift = fb * (1.0 / 1.0 - 1.0 / 3.0);
    assert!((28.0..30.0).contains(&shift), "shift {shift}");
    let rod_px = edge - shift / 2.0;
    let mut scene = black_box_before_wall();
    scene.push(
        "thin rod",
        vertical_rod((rod_px - cx) * 0.9 / fx, 0.9, 0.005),
        umbra::synth::Material::matte([0.3, 0.7, 0.8]),
    );
    let frame = render_frame(&scene, &calib, &SensorModel::kinect(), 17);
    let out = classify_rgb(&calib, &frame);
    let part = (edge - shift).ceil() as usize + 1..rod_px as usize - 1;
    let (mut rows, mut truth, mut found) = (0, 0, 0);
    for v in 100..380 {
        let row = v * WIDTH;
        let count = |labels: &[u8]| {
            part.clone()
                .filter(|&u| labels[row + u] == DETACHED)
                .count()
        };
        // The simulator's cut-off part lies where the hand computation puts it, a hole.
        if count(&frame.ir_labels) < part.len() || frame.raw[row + rod_px as usize] == NO_DEPTH {
            continue;
        }
        rows += 1;
        truth += part.len();
        found += count(&out.ir_labels);
    }
    assert!(rows >= 150, "the scene has the cut-off part in {rows} rows");
    // 0.77 (0.000 before): rows where the colour split finds no box leave their cut-off
    // part to the rows around, less its ends, which differ from row to row.
    assert_recall("detached", found, truth, rows, 0.7);
}

#[test]
fn box_shadow_beside_a_thin_rod_at_the_boxs_depth_is_attached() {
    // The hand-computed box moved to 1.6 m (front face x = −0.2..0.2 m) before a wall at 3 m: its
    // attached shadow is f·b·(1/1.6 − 1/3) = 12.7 px wide, left of its left edge at
    // cx − fx·0.2/1.6 = cx − 72.8. A thin rod, r = 6 mm (4.4 px) at the box's depth, stands at
    // that shadow's left end with a pixel of lit wall left of it: the hole between rod and box is
    // the box's shadow, about 10 px, with Sa (the rod) and Sb (the box) at one depth. Read as a
    // dropout inside one surface, it was OTHER (attached recall 0.58). The rod's own shadow falls
    // 12.7 px further left (it is narrower than its shift, so it casts no attached one).
    let calib = Calibration::nyu_default();
    let (cx, fx, fb) = (calib.depth.cx, calib.depth.fx, calib.fb());
    let (z, r) = (1.6, 0.006);
    let w = fb * (1.0 / z - 1.0 / 3.0);
    let box_left = cx - fx * 0.2 / z;
    let rod_half = fx * r / z;
    let rod_centre = box_left - w - 1.0 + rod_half;
    let mut scene = Scene::box_before_wall(z, 3.0);
    scene.push(
        "thin rod",
        vertical_rod((rod_centre - cx) * z / fx, z, r),
        umbra::synth::Material::matte([0.6, 0.6, 0.65]),
    );
    let frame = render_frame(&scene, &calib, &SensorModel::kinect(), 5);
    let out = classify(&calib, &frame);
    let between = (rod_centre + rod_half).ceil() as usize + 1..box_left as usize;
    let (mut rows, mut truth, mut found, mut wrong) = (0, 0, 0, 0);
    for v in 0..HEIGHT {
        let row = v * WIDTH;
        let attached = |labels: &[u8]| {
            between
                .clone()
                .filter(|&u| labels[row + u] == ATTACHED)
                .count()
        };
        // Rows where the simulator puts the box's shadow between rod and box, the rod measured,
        // and lit wall left of it.
        let left = (rod_centre - rod_half).floor() as usize - 1;
        if attached(&frame.ir_labels) < between.len()
            || frame.raw[row + rod_centre as usize] == NO_DEPTH
            || frame.raw[row + left] == NO_DEPTH
        {
            // Nothing casts an attached shadow here (the rod's is detached).
            wrong += count_in_row(&out.ir_labels, v, ATTACHED)
                * usize::from(count_in_row(&frame.ir_labels, v, ATTACHED) == 0);
            continue;
        }
        rows += 1;
        truth += between.len();
        found += attached(&out.ir_labels);
    }
    assert!(
        rows >= 120,
        "the scene has the box's shadow beside the rod in {rows} rows"
    );
    assert_recall("attached", found, truth, rows, 0.95);
    assert_eq!(wrong, 0, "attached pixels in rows without the box's shadow");
}

#[test]
fn rods_shadow_mostly_hidden_by_a_thin_rod_before_it_is_detached() {
    // A wall at 3 m; rod A, r = 8 mm at 1.5 m (6.2 px wide), casts its detached shadow
    // f·b·(1/1.5 − 1/3) = 14.6 px left of itself. Rod B, r = 7 mm at 1.55 m (5.3 px), stands
    // with its left edge 2 px into that shadow: 2 px of it show between the wall and B, 4 px
    // lie behind B. B is narrower than its own shift (13.6 px), so it casts no attached shadow
    // there: the hole is A's. The search must pass B to reach A, which it did not for a hole
    // under six pixels (speckle), and eq. (5) holds against the wall with the shadow's right
    // end anywhere behind B (4 px past the hole's end, beyond the tolerance): it was OTHER.
    let calib = Calibration::nyu_default();
    let (cx, fx, fb) = (calib.depth.cx, calib.depth.fx, calib.fb());
    let (z_a, r_a, z_b, r_b) = (1.5, 0.008, 1.55, 0.007);
    let (half_a, shift_a) = (fx * r_a / z_a, fb * (1.0 / z_a - 1.0 / 3.0));
    let half_b = fx * r_b / z_b;
    let u_a = cx + 40.0;
    let b_left = u_a - half_a - shift_a + 2.0;
    let u_b = b_left + half_b;
    let mut scene = before_a_wall(
        "a rod's shadow mostly hidden by a thin rod",
        3.0,
        [0.8, 0.78, 0.7],
    );
    push_grey_rod(&mut scene, (u_a - cx) * z_a / fx, z_a, r_a);
    push_grey_rod(&mut scene, (u_b - cx) * z_b / fx, z_b, r_b);
    let frame = render_frame(&scene, &calib, &SensorModel::kinect(), 3);
    let out = classify(&calib, &frame);
    // What shows of A's shadow: from its left end to B.
    let shadow = (u_a - half_a - shift_a).floor() as usize - 3..b_left.ceil() as usize;
    let (rows, truth, found) = detached_in_columns(&frame, &out.ir_labels, shadow);
    assert!(rows >= 400, "A's shadow shows beside B in {rows} rows");
    assert_recall("detached", found, truth, rows, 0.9);
}

#[test]
fn shadow_of_a_rod_cut_by_the_border_behind_a_thin_rod_is_detached() {
    // A wall at 2.5 m; rod A, r = 1 cm at 0.8 m (14.6 px wide), standing at the image's right
    // border with only its left 3 px in view. Its shadow lies f·b·(1/0.8 − 1/2.5) = 37.1 px left
    // of it, a lit gap of 22 px between (A is narrower than its shift). A rod B, r = 8 mm at
    // 1.5 m (6.2 px), stands over the shadow's left 6 px. What shows of the shadow (about 10 px)
    // is wider than what shows of A: eqs. (4)–(5) fit it (eq. 4 reaching behind B), but the test
    // of a shadow cut by a nearer surface (no wider than its occluder plus the widening) read
    // A's 3 px as its width: OTHER in every row.
    let calib = Calibration::nyu_default();
    let (cx, fx, fb) = (calib.depth.cx, calib.depth.fx, calib.fb());
    let (z_a, r_a, z_b, r_b) = (0.8, 0.01, 1.5, 0.008);
    let (half_a, shift_a) = (fx * r_a / z_a, fb * (1.0 / z_a - 1.0 / 2.5));
    let u_a = WIDTH as f64 - 3.0 + fx * 0.01 / 0.8;
    let shadow_from = u_a - half_a - shift_a;
    let half_b = fx * r_b / z_b;
    let u_b = shadow_from + 6.0 - fx * 0.008 / 1.5;
    let mut scene = before_a_wall(
        "a rod cut by the border, its shadow behind a thin rod",
        2.5,
        [0.8, 0.78, 0.7],
    );
    push_grey_rod(&mut scene, (u_a - cx) * z_a / fx, z_a, r_a);
    push_grey_rod(&mut scene, (u_b - cx) * z_b / fx, z_b, r_b);
    let frame = render_frame(&scene, &calib, &SensorModel::kinect(), 9);
    let out = classify(&calib, &frame);
    // What shows of A's shadow: from B's right edge to its geometric end.
    let shadow = (u_b + half_b).ceil() as usize + 1..(u_a + half_a - shift_a) as usize;
    let (rows, truth, found) = detached_in_columns(&frame, &out.ir_labels, shadow);
    assert!(rows >= 400, "A's shadow shows right of B in {rows} rows");
    assert_recall("detached", found, truth, rows, 0.9);
}

#[test]
fn shadow_falling_on_a_thin_nearer_leg_up_to_its_edge_is_detached() {
    // Two boards 4 cm wide, 1 cm thick, floor to ceiling, before a wall at 3 m: the front one
    // at 0.6 m (columns 320.0..358.8), the back one at 1 m (columns 286.7..310.0). The front
    // board's shadow lies 43.67·(1/0.6 − 1/1) = 29.1 px left of it on the back board
    // (columns 290.9..329.7) and 43.67·(1/0.6 − 1/3) = 58.2 px left of it on the wall
    // (261.8..300.6, behind the back board and in the hole left of it). So the back board shows
    // 4 px lit, then 19 px in the shadow up to its right edge; the wall beyond it is lit up to
    // the front board. Eq. (5) on the wall ends the shadow 9.4 px short of that hole's end (at
    // 300.6): it was OTHER in every row. On the back board it ends at 329.7, past it: detached,
    // and warped at the board's depth the RGB view finds it there too (1 657 of 3 315 px at the
    // wall's depth, 3 046 at the board's).
    let calib = Calibration::nyu_default();
    let (fx, cx) = (calib.depth.fx, calib.depth.cx);
    let x_at = |u: f64, z: f64| (u - cx) * z / fx;
    let mut scene = before_a_pale_wall("a board in a nearer board's shadow up to its edge");
    let board = |scene: &mut Scene, name, right: f64, z: f64| {
        let x = x_at(right, z);
        push_box(
            scene,
            name,
            [x - 0.02, 0.0, z + 0.005],
            [0.02, 2.0, 0.005],
            umbra::synth::Material::matte([0.6, 0.5, 0.4]),
        );
    };
    board(&mut scene, "back board", 310.0, 1.0);
    board(&mut scene, "front board", 320.0 + 0.04 * fx / 0.6, 0.6);
    let (mut rows, mut board_px, mut board_found) = (0, 0, 0);
    for seed in 40..42 {
        let frame = render_frame(&scene, &calib, &SensorModel::kinect(), seed);
        let out = classify_rgb(&calib, &frame);
        for v in 100..380 {
            // The hole on the back board: the simulator's detached pixels in columns 292..309.
            let row = v * WIDTH;
            let truth = (292..309)
                .filter(|&u| frame.ir_labels[row + u] == DETACHED)
                .count();
            assert!(
                truth >= 14,
                "row {v}: {truth} detached px on the back board"
            );
            let found = (292..309)
                .filter(|&u| out.ir_labels[row + u] == DETACHED)
                .count();
            rows += usize::from(found + 2 >= truth);
        }
        // The RGB view: the shadow on the back board, right of its lit sliver (the one valid
        // pixel between the simulator's detached runs), warped at the board's depth.
        for v in 100..380 {
            let gt = &frame.rgb_labels[v * WIDTH..(v + 1) * WIDTH];
            let Some(sliver) = (260..330)
                .find(|&x| gt[x] == VALID && gt[x - 1] == DETACHED && gt[x + 1] == DETACHED)
            else {
                continue;
            };
            for x in (sliver + 1..WIDTH).take_while(|&x| gt[x] == DETACHED) {
                board_px += 1;
                board_found += usize::from(out.rgb_labels[v * WIDTH + x] == DETACHED);
            }
        }
    }
    assert!(
        rows >= 9 * 2 * 280 / 10,
        "{rows} of 560 rows detached on the back board"
    );
    assert!(
        board_px > 2000 && 10 * board_found >= 9 * board_px,
        "RGB view: {board_found} of the board's {board_px} shadowed px detached"
    );
}

#[test]
fn rod_whose_lit_gap_is_a_sliver_of_a_slanted_wall_keeps_its_detached_shadow() {
    // A rod 3.5 cm thick at 1 m before a wall through (0, 0, 2 m) turned 58°, its right side
    // nearer: the rod (raw 736–740) shifts 0.1336·(934 − 740) = 25.9 px against the wall left of
    // its shadow, and is 2·0.0175·582.6/1 = 20.4 px wide, so its detached shadow leaves a lit gap
    // of two pixels. Over the shadow's 22 px the wall comes 11–12 raw units nearer, 1.5 px of
    // disparity: past the step, so the gap's two pixels read as foreground and began the
    // occluder's run, and eq. (4) measured from them missed by 21 px: the hole was read as the
    // rod's attached shadow (the rod read as Sb through the gap). Two pixels that far from the
    // rod and that near the wall are a sliver of the wall, stepped over.
    let calib = Calibration::nyu_default();
    let mut scene = Scene::new("a rod before a steeply slanted wall, its lit gap two pixels");
    scene.push(
        "wall",
        slanted_wall(2.0, -58f64.to_radians()),
        umbra::synth::Material::matte([0.8, 0.78, 0.7]),
    );
    scene.push(
        "rod",
        vertical_rod(0.0, 1.0, 0.0175),
        umbra::synth::Material::matte([0.6, 0.6, 0.65]),
    );
    let frame = render_frame(&scene, &calib, &SensorModel::ideal(), 8);
    let out = classify_rgb(&calib, &frame);
    let mut rows = 0;
    for v in 40..440 {
        let row = &frame.raw[v * WIDTH..(v + 1) * WIDTH];
        let a = (200..400)
            .find(|&u| row[u] == NO_DEPTH)
            .expect("the shadow");
        let b = (a..WIDTH).find(|&u| row[u] != NO_DEPTH).expect("its end");
        // The simulator's shadow, the two pixels of wall after it, the rod.
        assert!(
            (a..b).all(|u| frame.ir_labels[v * WIDTH + u] == DETACHED)
                && row[b + 1] != NO_DEPTH
                && row[b + 2] + 150 < row[b],
            "row {v}: the scene"
        );
        rows += usize::from((a..b).all(|u| out.ir_labels[v * WIDTH + u] == DETACHED));
    }
    assert!(rows >= 390, "{rows} of 400 rows detached");
}

#[test]
fn shadow_beside_a_thin_nearer_rod_under_a_nearer_board_keeps_its_background() {
    // A box's left face at 1.2 m (x = 0.0555 m: column 340) before a wall at 3 m casts an
    // attached shadow of 43.67·(1/1.2 − 1/3) = 21.8 px, columns 318–340; a rod at 0.9 m (0.8 cm
    // thick: columns 320–330) stands in it, so 9–10 px of it show between the rod and the box.
    // A board at 0.8 m spans the frame's top rows above both (rows 0–56), hiding the box's top:
    // the only surface ever measured above the hole is that board, nearer than the box, which
    // can be no background of the box's shadow. It was taken as the one reading above, and the
    // hole left OTHER in every row; the row's own background left of the thin rod (its detached
    // shadow on the wall between) now stands in, as where nothing was measured above.
    let calib = Calibration::nyu_default();
    let mut scene = before_a_pale_wall("a box's shadow beside a rod, under a nearer board");
    let matte = umbra::synth::Material::matte;
    push_box(
        &mut scene,
        "board",
        [0.0, -0.28, 0.81],
        [1.5, 0.03, 0.01],
        matte([0.5, 0.45, 0.4]),
    );
    push_box(
        &mut scene,
        "box",
        [0.2055, 0.8, 1.25],
        [0.15, 1.4, 0.05],
        matte([0.6, 0.5, 0.4]),
    );
    scene.push(
        "rod",
        vertical_rod(0.0182, 0.9, 0.008),
        matte([0.6, 0.6, 0.65]),
    );
    let frame = render_frame(&scene, &calib, &SensorModel::ideal(), 8);
    let out = classify_rgb(&calib, &frame);
    let mut rows = 0;
    for v in 80..440 {
        let row = &frame.raw[v * WIDTH..(v + 1) * WIDTH];
        let at = |u: usize| frame.ir_labels[v * WIDTH + u];
        // The hole between the rod's right edge and the box, by the simulator all attached.
        let b = (300..400).find(|&u| row[u] != NO_DEPTH && row[u] > 750 && row[u] < 850);
        let b = b.expect("the box");
        let a = (b - 20..b)
            .rev()
            .find(|&u| row[u] != NO_DEPTH)
            .expect("the rod")
            + 1;
        assert!(
            (7..=12).contains(&(b - a)) && (a..b).all(|u| at(u) == ATTACHED),
            "row {v}: the scene ({a}..{b})"
        );
        rows += usize::from((a..b).all(|u| out.ir_labels[v * WIDTH + u] == ATTACHED));
    }
    assert!(rows >= 350, "{rows} of 360 rows attached");
}

#[test]
fn thin_rods_shadow_is_attached_in_rows_that_touch_it_detached_where_the_gap_shows() {
    // A grey rod r = 23.5 mm at 1 m before a wall at 3 m: 27.4 px wide against its shift of
    // f·b·(1/1 − 1/3) = 29.1 px (SPEC §1: thin, 4.7 cm < 5 cm), so the projector lights a gap of
    // about 1.5 px between shadow and rod, which the Kinect's widening (0–3 px a row) closes in
    // some rows. Where it does the hole touches the rod: attached (SPEC §1); where a pixel of
    // wall shows between them, detached. Each row by its own raw map, as the simulator labels it.
    let calib = Calibration::nyu_default();
    let scene = Scene::rod_before_wall(0.0, 1.0, 0.0235, 3.0);
    let (mut touching, mut apart) = ([0usize; 2], [0usize; 2]);
    let mut rgb = Confusion::default();
    for seed in 0..2 {
        let frame = render_frame(&scene, &calib, &SensorModel::kinect(), 40 + seed);
        let out = classify_rgb(&calib, &frame);
        rgb.add(&frame.rgb_labels, &out.rgb_labels);
        for v in 20..HEIGHT - 20 {
            let (gt, got) = (
                &frame.ir_labels[v * WIDTH..(v + 1) * WIDTH],
                &out.ir_labels[v * WIDTH..(v + 1) * WIDTH],
            );
            let shadow: Vec<usize> = (200..320)
                .filter(|&u| gt[u] == ATTACHED || gt[u] == DETACHED)
                .collect();
            let (Some(&first), Some(&last)) = (shadow.first(), shadow.last()) else {
                continue;
            };
            if last - first + 1 != shadow.len() {
                continue; // a speckle or spurious pixel inside: not one run
            }
            // Past any other hole, the rod (raw about 744 at 1 m) or the wall (about 975).
            let raw = &frame.raw[v * WIDTH..(v + 1) * WIDTH];
            let next = (last + 1..WIDTH).find(|&u| raw[u] != NO_DEPTH).unwrap();
            if (760..960).contains(&raw[next]) {
                continue; // a mixed pixel of the sensor's between them: neither surface
            }
            let touches = raw[next] < 760;
            let code = if touches { ATTACHED } else { DETACHED };
            assert!(
                shadow.iter().all(|&u| gt[u] == code),
                "row {v}: the simulator's rule: {:?} {:?}",
                &gt[first - 2..next + 2],
                &raw[first - 2..next + 2]
            );
            let right = shadow.iter().filter(|&&u| got[u] == code).count();
            let tally = if touches { &mut touching } else { &mut apart };
            tally[0] += shadow.len();
            tally[1] += right;
        }
    }
    // Measured: all 7 222 pixels of the touching rows attached (none before: the rows around
    // show the gap, so the rod reads thin and every row detached), all 16 852 of the others
    // detached. The RGB view, whose rows carry these over: attached F1 0.988, detached 0.994
    // (0.171 and 0.846 when its consensus made rows of one kind take their neighbours').
    assert!(
        touching[0] > 3000 && apart[0] > 3000,
        "{touching:?} {apart:?}"
    );
    assert!(
        100 * touching[1] >= 90 * touching[0],
        "touching rows {touching:?}"
    );
    assert!(
        100 * apart[1] >= 90 * apart[0],
        "rows with the gap {apart:?}"
    );
    at_least(&rgb, Some(ATTACHED), 0.95, "RGB attached of a thin rod");
    at_least(&rgb, Some(DETACHED), 0.95, "RGB detached of a thin rod");
}
