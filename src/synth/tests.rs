//! The simulator checked against geometry worked out by hand from the calibration (SPEC §1), not
//! against its own output.

use super::*;
use crate::calib::Calibration;
use crate::labels::{ALIGNMENT, ATTACHED, DETACHED, NO_DEPTH, OTHER, VALID, WIDTH};

fn row(labels: &[u8], v: usize) -> &[u8] {
    &labels[v * WIDTH..(v + 1) * WIDTH]
}

/// Positions of `code` in a row.
fn cols(r: &[u8], code: u8) -> Vec<usize> {
    r.iter()
        .enumerate()
        .filter(|(_, &l)| l == code)
        .map(|(u, _)| u)
        .collect()
}

#[test]
fn box_before_wall_attached_width_matches_hand_computation() {
    let c = Calibration::nyu_default();
    let (zf, zb) = (1.0, 3.0);
    let f = render_frame(
        &Scene::box_before_wall(zf, zb),
        &c,
        &SensorModel::ideal(),
        0,
    );
    let (fx, cx, b) = (c.depth.fx, c.depth.cx, c.raw.baseline_m);
    // SPEC §1: w = f·b·(1/z_f − 1/z_b) ≈ 29.13 px.
    let w = fx * b * (1.0 / zf - 1.0 / zb);
    // The box's left edge x_L = −0.2 m hides the wall from u_L on; the projector's ray past that
    // edge meets the wall at x = b + (x_L − b)·z_b/z_f, so the shadow spans [u_s, u_L).
    let x_l = -scene::BOX_HALF.x;
    let u_l = fx * x_l / zf + cx;
    let u_s = fx * (b + (x_l - b) * zb / zf) / zb + cx;
    assert!((u_l - u_s - w).abs() < 1e-9, "hand formulas agree");
    let (raw_box, raw_wall) = (
        c.raw_from_depth(zf).round() as u16,
        c.raw_from_depth(zb).round() as u16,
    );
    let half_rows = c.depth.fy * scene::BOX_HALF.y / zf;
    let rows = (c.depth.cy - half_rows).ceil() as usize + 1
        ..=(c.depth.cy + half_rows).floor() as usize - 1;
    assert!(rows.clone().count() > 250);
    for v in rows {
        let r = row(&f.ir_labels, v);
        let att = cols(r, ATTACHED);
        assert!(
            (att.len() as f64 - w).abs() < 1.0,
            "row {v}: {} attached px, expected {w:.2}",
            att.len()
        );
        assert_eq!(*att.first().unwrap(), u_s.ceil() as usize, "row {v}");
        assert_eq!(*att.last().unwrap(), u_l.ceil() as usize - 1, "row {v}");
        assert_eq!(
            att.last().unwrap() - att.first().unwrap() + 1,
            att.len(),
            "row {v}: one run"
        );
        assert!(
            cols(r, DETACHED).is_empty() && cols(r, OTHER).is_empty(),
            "row {v}"
        );
        let raw = &f.raw[v * WIDTH..(v + 1) * WIDTH];
        assert_eq!(raw[att[0] - 1], raw_wall);
        assert_eq!(raw[att[0] + att.len()], raw_box);
        assert!(att.iter().all(|&u| raw[u] == NO_DEPTH));
    }
    // Outside the shadow everything is measured: only the shadow is a hole.
    let holes = f.raw.iter().filter(|&&r| r == NO_DEPTH).count();
    assert_eq!(
        holes,
        f.ir_labels.iter().filter(|&&l| l == ATTACHED).count()
    );
}

#[test]
fn thin_rod_casts_a_detached_shadow_where_predicted() {
    let c = Calibration::nyu_default();
    let (fx, cx, b) = (c.depth.fx, c.depth.cx, c.raw.baseline_m);
    let (x0, zf, zb, r) = (0.0, 1.0, 3.0, 0.01);
    // SPEC §1: detached iff 2r < b·(1 − z_f/z_b): 0.02 < 0.05.
    assert!(2.0 * r < b * (1.0 - zf / zb));
    let f = render_frame(
        &Scene::rod_before_wall(x0, zf, r, zb),
        &c,
        &SensorModel::ideal(),
        0,
    );
    // Projector rays past the rod's edges x0 ± r (tangent points, to < 0.1 mm) meet the wall at
    // x = b + (x0 ± r − b)·z_b/z_f; the camera sees the rod over fx·(x0 ± r)/z_f + cx.
    let wall_u = |x: f64| fx * x / zb + cx;
    let (s0, s1) = (
        wall_u(b + (x0 - r - b) * zb / zf),
        wall_u(b + (x0 + r - b) * zb / zf),
    );
    let (r0, r1) = (fx * (x0 - r) / zf + cx, fx * (x0 + r) / zf + cx);
    for v in (0..480).step_by(7) {
        let l = row(&f.ir_labels, v);
        let det = cols(l, DETACHED);
        assert!(
            cols(l, ATTACHED).is_empty() && cols(l, OTHER).is_empty(),
            "row {v}"
        );
        assert!(
            (det[0] as f64 - s0).abs() <= 1.0 && (*det.last().unwrap() as f64 - s1).abs() <= 1.0,
            "row {v}: {det:?} vs {s0:.1}..{s1:.1}"
        );
        assert_eq!(det.last().unwrap() - det[0] + 1, det.len());
        // Lit wall between shadow and rod: the w_b of eqs. 4–5.
        let gap = (*det.last().unwrap() + 1..r0.ceil() as usize).count() as f64;
        assert!(
            (gap - (r0 - s1)).abs() <= 1.5,
            "row {v}: gap {gap} vs {:.1}",
            r0 - s1
        );
        let raw_rod = c.raw_from_depth(zf - r).round() as u16;
        assert_eq!(
            f.raw[v * WIDTH + ((r0 + r1) / 2.0).round() as usize],
            raw_rod,
            "row {v}: rod front"
        );
    }
    // A rod too thick for a gap (2r = 8 cm > 5 cm) leaves an attached shadow of f·b·(1/z_f − 1/z_b).
    let r = 0.04;
    let f = render_frame(
        &Scene::rod_before_wall(x0, zf, r, zb),
        &c,
        &SensorModel::ideal(),
        0,
    );
    let w = fx * b * (1.0 / zf - 1.0 / zb); // both silhouettes are the rod's sides, at about z_f
    for v in (0..480).step_by(11) {
        let l = row(&f.ir_labels, v);
        assert!(cols(l, DETACHED).is_empty(), "row {v}");
        let n = cols(l, ATTACHED).len() as f64;
        assert!((n - w).abs() <= 1.5, "row {v}: {n} attached vs {w:.1}");
    }
}

/// A rod narrower than its shift by about a pixel and a half leaves a lit gap that a sensor
/// widening shadows by up to 2 px on their right swallows in some rows: there the hole touches
/// the rod, and SPEC §1's attached shadow is a hole that touches its occluder. Each row of the
/// rod's shadow is labelled by what its raw map shows: attached where the hole runs into the rod,
/// detached where a measured pixel of wall lies between them.
#[test]
fn a_thin_rods_shadow_is_attached_in_rows_whose_hole_touches_it() {
    let c = Calibration::nyu_default();
    let (fx, cx, b) = (c.depth.fx, c.depth.cx, c.raw.baseline_m);
    let (x0, zf, zb, r) = (0.0, 1.0, 3.0, 0.0235);
    assert!(2.0 * r < b * (1.0 - zf / zb), "a thin rod by SPEC §1");
    // The lit gap between the shadow's right end (the projector's ray past the rod's right side,
    // on the wall) and the rod's left side, as in `thin_rod_casts_a_detached_shadow_where_predicted`.
    let s1 = fx * (b + (x0 + r - b) * zb / zf) / zb + cx;
    let r0 = fx * (x0 - r) / zf + cx;
    assert!((1.0..2.0).contains(&(r0 - s1)), "gap {:.2} px", r0 - s1);
    let sensor = SensorModel {
        widen_right_max: 2,
        ..SensorModel::ideal()
    };
    let f = render_frame(&Scene::rod_before_wall(x0, zf, r, zb), &c, &sensor, 5);
    let (mut touching, mut apart) = (0, 0);
    for v in 0..480 {
        let (raw, l) = (&f.raw[v * WIDTH..(v + 1) * WIDTH], row(&f.ir_labels, v));
        let shadow = cols(l, ATTACHED)
            .into_iter()
            .chain(cols(l, DETACHED))
            .collect::<Vec<_>>();
        let (first, last) = (*shadow.iter().min().unwrap(), *shadow.iter().max().unwrap());
        assert_eq!(last - first + 1, shadow.len(), "row {v}: one run");
        // The rod's first measured column (its near side, about 1 m).
        let rod = (last + 1..WIDTH)
            .find(|&u| raw[u] != NO_DEPTH && raw[u] < c.raw_from_depth(1.5) as u16)
            .unwrap();
        let code = if raw[last + 1..rod].contains(&NO_DEPTH) || last + 1 == rod {
            touching += 1;
            ATTACHED
        } else {
            apart += 1;
            DETACHED
        };
        assert!(
            l[first..=last].iter().all(|&x| x == code),
            "row {v}: {:?} before the rod at {rod}",
            &l[first..=last]
        );
    }
    assert!(
        touching > 50 && apart > 50,
        "{touching} rows touch, {apart} do not"
    );
}

#[test]
fn shadows_running_off_the_right_border_are_labelled_by_what_lies_past_it() {
    // Rods 1 m away past the border (their left sides at column cx + fx·(x0 − r) ≥ 640),
    // before a wall at 3 m, cast their shadows about f·b·(1/z_f − 1/z_b) = 29 px to the left,
    // into the image. A thin one (2r = 2 cm < 5 cm, its side at column 662) leaves lit wall
    // between shadow and rod: detached, though that gap lies past the border; a thick one
    // (8 cm, its side at column 645) none: attached.
    let c = Calibration::nyu_default();
    let (fx, cx, b) = (c.depth.fx, c.depth.cx, c.raw.baseline_m);
    let (zf, zb) = (1.0, 3.0);
    for (r, side, code) in [(0.01, 662.0, DETACHED), (0.04, 645.0, ATTACHED)] {
        let x0 = (side - cx) / fx + r;
        let f = render_frame(
            &Scene::rod_before_wall(x0, zf, r, zb),
            &c,
            &SensorModel::ideal(),
            0,
        );
        // The projector ray tangent to the rod's left side: turned from the ray through its
        // axis by asin(r / distance); it meets the wall at x = b + z_b·tan θ.
        let (dx, dz) = (x0 - b, zf);
        let theta = dx.atan2(dz) - (r / dx.hypot(dz)).asin();
        let s0 = fx * (b + zb * theta.tan()) / zb + cx;
        assert!(s0 < 636.0, "the shadow starts at {s0:.1}");
        for v in (0..480).step_by(13) {
            let l = row(&f.ir_labels, v);
            let shadow = cols(l, code);
            assert!(
                !shadow.is_empty()
                    && (shadow[0] as f64 - s0).abs() <= 1.0
                    && *shadow.last().unwrap() == WIDTH - 1,
                "r {r}, row {v}: {shadow:?} from {s0:.1}"
            );
            assert_eq!(shadow.len() + cols(l, VALID).len(), WIDTH, "r {r}, row {v}");
        }
    }
}

#[test]
fn rgb_view_has_alignment_strip_right_of_box() {
    let c = Calibration::nyu_default();
    let (zf, zb) = (1.0, 3.0);
    let f = render_frame(
        &Scene::box_before_wall(zf, zb),
        &c,
        &SensorModel::ideal(),
        0,
    );
    let k = c.rgb;
    let tx = -c.depth_to_rgb.translation.x; // RGB camera at x = +0.025 m in the IR frame
                                            // The RGB camera sees the box's right edge x_R at u1; the IR camera's ray past that edge meets
                                            // the wall at x_R·z_b/z_f, which the RGB camera sees at u2: the strip [u1, u2) is ALIGNMENT.
    let x_r = scene::BOX_HALF.x;
    let u1 = k.fx * (x_r - tx) / zf + k.cx;
    let u2 = k.fx * (x_r * zb / zf - tx) / zb + k.cx;
    let w = k.fx * tx * (1.0 / zf - 1.0 / zb);
    assert!((u2 - u1 - w).abs() < 1e-9);
    // Projector shadow carried over: the IR shadow [b + (x_L − b)·3, 3·x_L] on the wall, of which
    // the RGB camera sees up to where its ray past the box's left edge lands.
    let x_l = -scene::BOX_HALF.x;
    let b = c.raw.baseline_m;
    let att_w = k.fx * ((x_l - tx) / zf - (b + (x_l - b) * zb / zf - tx) / zb);
    for v in 150..350 {
        let l = row(&f.rgb_labels, v);
        let al = cols(l, ALIGNMENT);
        assert!(
            (al.len() as f64 - w).abs() < 1.0,
            "row {v}: {} alignment px vs {w:.2}",
            al.len()
        );
        assert_eq!(al[0], u1.ceil() as usize, "row {v}");
        assert_eq!(al.last().unwrap() - al[0] + 1, al.len());
        let att = cols(l, ATTACHED);
        assert!(
            (att.len() as f64 - att_w).abs() <= 1.5,
            "row {v}: {} attached vs {att_w:.1}",
            att.len()
        );
        assert!(cols(l, DETACHED).is_empty(), "row {v}");
        // The RGB camera sees wider than the IR camera: OTHER only beyond the IR field of view,
        // whose edges x/z = −cx/fx and (640 − cx)/fx land on the wall at these RGB columns.
        let edge = |x: f64| k.fx * (x * zb - tx) / zb + k.cx;
        let (e0, e1) = (
            edge(-c.depth.cx / c.depth.fx),
            edge((640.0 - c.depth.cx) / c.depth.fx),
        );
        let other = cols(l, OTHER);
        assert!(
            other
                .iter()
                .all(|&u| (u as f64) < e0 + 1.0 || (u as f64) > e1 - 1.0),
            "row {v}: {e0:.1} {e1:.1} {other:?}"
        );
        assert!(
            other.len() as f64 >= e0.floor() + (639.0 - e1.ceil()),
            "row {v}"
        );
    }
}

/// A black poster on the wall at 3 m where the box of [`Scene::box_before_wall`] casts its
/// shadow (wall x ∈ [−1.0, −0.4]).
fn push_black_poster(s: &mut Scene) {
    s.push(
        "poster",
        Shape::Box {
            centre: V3::new(-0.7, 0.0, 2.99),
            half: V3::new(0.3, 0.6, 0.005),
            yaw: 0.0,
        },
        Material::black(),
    );
}

#[test]
fn shadows_on_black_or_out_of_range_surfaces_are_other() {
    let c = Calibration::nyu_default();
    // A black poster on the wall where the box's shadow falls (wall x ∈ [−0.75, −0.6] at 3 m).
    let mut s = Scene::box_before_wall(1.0, 3.0);
    push_black_poster(&mut s);
    let f = render_frame(&s, &c, &SensorModel::ideal(), 0);
    let r = row(&f.ir_labels, 240);
    assert!(cols(r, ATTACHED).is_empty() && cols(r, DETACHED).is_empty());
    assert!(r[168..197].iter().all(|&l| l == OTHER));
    // Wall beyond the 4.5 m range: its shadow is no different from the rest of it.
    let f = render_frame(
        &Scene::box_before_wall(1.0, 5.0),
        &c,
        &SensorModel::ideal(),
        0,
    );
    assert!(f.ir_labels.iter().all(|&l| l == VALID || l == OTHER));
    assert!(
        f.rgb_labels.iter().all(|&l| l == VALID || l == OTHER),
        "alignment on an unmeasurable wall is OTHER"
    );
    // A glossy box: no depth on it, and it still casts a projector shadow on the wall.
    let mut s = Scene::box_before_wall(1.0, 3.0);
    s.objects[1].material = Material::glossy([0.5, 0.5, 0.5]);
    let f = render_frame(&s, &c, &SensorModel::ideal(), 0);
    let r = row(&f.ir_labels, 240);
    assert!(r[200..400].iter().all(|&l| l == OTHER));
    // Its right neighbour is the box, a hole but the occluder: still ATTACHED.
    assert!(r[168..197].iter().all(|&l| l == ATTACHED));
}

#[test]
fn all_matte_makes_black_and_glossy_surfaces_measurable_and_keeps_the_rest() {
    let c = Calibration::nyu_default();
    // The black poster where the box's shadow falls, and a glossy box, as above.
    let mut s = Scene::box_before_wall(1.0, 3.0);
    s.objects[1].material = Material::glossy([0.5, 0.5, 0.5]);
    push_black_poster(&mut s);
    let wall = s.objects[0].material;
    let s = s.all_matte();
    assert_eq!(
        s.objects[0].material, wall,
        "the matte wall is left as it was"
    );
    assert!(s
        .description
        .contains("2 black or glossy surfaces made matte"));
    let f = render_frame(&s, &c, &SensorModel::ideal(), 0);
    let r = row(&f.ir_labels, 240);
    // The box has depth now, and its shadow on the poster (5 mm before the wall) is attached.
    assert!(r[200..400].iter().all(|&l| l == VALID));
    assert!(r[168..197].iter().all(|&l| l == ATTACHED));
    assert!(f.raw[240 * 640 + 300] < 2047);
}

#[test]
fn kinect_sensor_widens_shadows_by_about_two_px() {
    let c = Calibration::nyu_default();
    let s = Scene::box_before_wall(1.0, 3.0);
    let ideal = render_frame(&s, &c, &SensorModel::ideal(), 0);
    let m = SensorModel {
        speckle_prob: 0.0,
        spurious_prob: 0.0,
        mixed_prob: 0.0,
        ..SensorModel::kinect()
    };
    let (mut sum, mut n, mut max) = (0.0, 0.0, 0usize);
    for seed in 0..3 {
        let f = render_frame(&s, &c, &m, seed);
        for v in 100..380 {
            let extra = cols(row(&f.ir_labels, v), ATTACHED).len()
                - cols(row(&ideal.ir_labels, v), ATTACHED).len();
            sum += extra as f64;
            n += 1.0;
            max = max.max(extra);
            let raw = &f.raw[v * WIDTH..(v + 1) * WIDTH];
            assert!(row(&f.ir_labels, v)
                .iter()
                .zip(raw)
                .all(|(&l, &r)| (l == VALID) == (r != NO_DEPTH)));
        }
    }
    let mean = sum / n;
    assert!((1.8..2.8).contains(&mean), "mean widening {mean}");
    assert!((5..=7).contains(&max), "max widening {max}");
}

#[test]
fn random_scenes_have_consistent_labels_and_are_deterministic() {
    let c = Calibration::nyu_default();
    let mut shadows = 0;
    for (cat, seed) in [
        (Category::Simple, 3),
        (Category::Complex, 4),
        (Category::Complex, 11),
    ] {
        let job = Job {
            scene: random_scene(cat, seed),
            category: cat,
            seed,
            frames: 2,
            sensor: sensor_for(cat),
            calib: c,
        };
        let f = job_frame(&job, 1);
        assert_eq!(f, job_frame(&job, 1), "deterministic");
        assert_ne!(f.raw, job_frame(&job, 0).raw, "frames differ");
        for (&l, &r) in f.ir_labels.iter().zip(&f.raw) {
            assert_eq!(l == VALID, r != NO_DEPTH, "{}", job.scene.description);
            assert!(l != ALIGNMENT && l <= OTHER);
        }
        assert!(f.rgb_labels.iter().all(|&l| l <= OTHER));
        shadows += f
            .ir_labels
            .iter()
            .filter(|&&l| l == ATTACHED || l == DETACHED)
            .count();
    }
    assert!(shadows > 1000, "{shadows}");
}

/// Timing, not a check: `cargo test --release --lib synth::tests::render_time -- --ignored --nocapture`.
#[test]
#[ignore]
fn render_time() {
    let c = Calibration::nyu_default();
    for (cat, seed) in [
        (Category::Simple, 1),
        (Category::Complex, 2),
        (Category::Complex, 5),
    ] {
        let scene = random_scene(cat, seed);
        let t = std::time::Instant::now();
        let n = 5;
        for k in 0..n {
            std::hint::black_box(render_frame(
                &scene.at_frame(k),
                &c,
                &sensor_for(cat),
                k as u64,
            ));
        }
        eprintln!(
            "{} ({} objects): {:.0} ms/frame",
            cat.as_str(),
            scene.objects.len(),
            t.elapsed().as_secs_f64() * 1e3 / n as f64
        );
    }
}
