//! Issue #2's speed target: IR-view classification + alignment + RGB-view labels of one 640×480
//! frame in ≤ 1 ms on one core, timed next to a plain copy of the frame in the same run.

use criterion::{criterion_group, criterion_main, Criterion};
use std::hint::black_box;
use umbra::classify::{Classified, Classifier};
use umbra::labels::{upside_down, NO_DEPTH, PIXELS, WIDTH};
use umbra::Calibration;

/// A busy frame built by hand: wall at 3 m, boxes and rods at 1–2 m with their shadows, a dark
/// patch and sparse speckle, so every branch of the classifier runs.
fn busy_frame(c: &Calibration) -> Vec<u16> {
    let raw = |z: f64| c.raw_from_depth(z).round() as u16;
    let mut f = vec![raw(3.0); PIXELS];
    let objects = [
        (100, 220, 60, 400, 1.2),
        (300, 330, 0, 480, 1.0),
        (420, 560, 200, 420, 1.8),
        (600, 606, 50, 300, 1.5),
    ];
    for &(u0, u1, v0, v1, z) in &objects {
        let w = (c.fb() * (1.0 / z - 1.0 / 3.0)).round() as usize;
        for v in v0..v1 {
            for u in u0..u1 {
                f[v * WIDTH + u] = raw(z);
            }
            for u in u0.saturating_sub(w)..u0 {
                if f[v * WIDTH + u] == raw(3.0) {
                    f[v * WIDTH + u] = NO_DEPTH;
                }
            }
        }
    }
    let mut seed = 0x2545_f491_u32;
    for px in f.iter_mut() {
        seed ^= seed << 13;
        seed ^= seed >> 17;
        seed ^= seed << 5;
        if seed.is_multiple_of(97) {
            *px = NO_DEPTH;
        }
    }
    for v in 380..440 {
        for u in 20..80 {
            f[v * WIDTH + u] = NO_DEPTH;
        }
    }
    for v in 0..480 {
        for u in 632..640 {
            f[v * WIDTH + u] = NO_DEPTH; // the Kinect's dead right band
        }
    }
    f
}

/// A recording's first frame (depth, and RGB when paired) and calibration, if the folder exists.
fn recorded(dir: &str) -> Option<(Vec<u16>, Option<Vec<u8>>, Calibration)> {
    let rec = umbra::recording::Recording::open(std::path::Path::new(dir)).ok()?;
    let mut raw = vec![0u16; PIXELS];
    rec.read_depth(0, &mut raw).ok()?;
    let mut rgb = vec![0u8; 3 * PIXELS];
    let has_rgb = rec.read_rgb(0, &mut rgb).ok()?;
    Some((raw, has_rgb.then_some(rgb), *rec.calibration()))
}

fn bench(c: &mut Criterion) {
    let calib = Calibration::nyu_default();
    let mut frames = vec![("synthetic_busy", busy_frame(&calib), None, calib)];
    let root = env!("CARGO_MANIFEST_DIR");
    // The bundled simulated room, and the real NYU frame when the shared data is beside the repo.
    for (name, dir) in [
        ("complex_room", format!("{root}/recordings/complex-room")),
        (
            "nyu_basement_real",
            format!("{root}/../shared/data/nyu-basement"),
        ),
    ] {
        if let Some((raw, rgb, cal)) = recorded(&dir) {
            frames.push((name, raw, rgb, cal));
        }
    }
    let mut g = c.benchmark_group("frame_640x480");
    let mut copy = vec![0u16; PIXELS];
    g.bench_function("plain_copy", |b| {
        b.iter(|| copy.copy_from_slice(black_box(&frames[0].1)))
    });
    for (name, frame, rgb, cal) in &frames {
        let mut classifier = Classifier::new(cal);
        let mut out = Classified::default();
        // The whole classifier as the daemon runs it: with the paired RGB image when there is one
        // (the colour split of depthless occluders' shadows).
        g.bench_function(format!("classify_ir_align_rgb/{name}"), |b| {
            b.iter(|| classifier.classify_with_rgb(black_box(frame), rgb.as_deref(), &mut out))
        });
        // A stream: the frame and its upside-down mirror in turn, one per iteration. The same frame
        // over and over lets the branch predictor learn its holes, which a camera never allows
        // (on the NYU frame the scanline alone runs 40 % faster that way).
        let flipped = (
            upside_down(frame, WIDTH),
            rgb.as_deref().map(|c| upside_down(c, 3 * WIDTH)),
        );
        let mut turn = false;
        g.bench_function(format!("classify_stream/{name}"), |b| {
            b.iter(|| {
                turn = !turn;
                let (f, c) = if turn {
                    (&flipped.0, flipped.1.as_deref())
                } else {
                    (frame, rgb.as_deref())
                };
                classifier.classify_with_rgb(black_box(f), c, &mut out)
            })
        });
        let params = umbra::classify::Params::default();
        let scan = umbra::classify::scanline::ScanParams::new(cal, &params);
        let mut filled = vec![0u16; PIXELS];
        g.bench_function(format!("stage_scanline_ir/{name}"), |b| {
            b.iter(|| {
                umbra::classify::scanline::classify_frame(
                    &scan,
                    black_box(frame),
                    &mut out.ir_labels,
                    &mut filled,
                )
            })
        });
        // Each later stage is timed on what the stages before it make of this frame, computed
        // here whichever benchmarks a filter selects (restored before each run, untimed).
        let (mut labels, mut fill) = (vec![0u8; PIXELS], vec![0u16; PIXELS]);
        let facts = umbra::classify::scanline::classify_frame(&scan, frame, &mut labels, &mut fill);
        if let Some(rgb) = rgb {
            let mut split =
                umbra::classify::depthless::ColourSplit::new(cal, params.attached_over_px);
            g.bench_function(format!("stage_colour_split/{name}"), |b| {
                b.iter_batched_ref(
                    || (labels.clone(), fill.clone()),
                    |(l, f)| split.apply(black_box(frame), rgb, facts, l, f),
                    criterion::BatchSize::LargeInput,
                )
            });
            split.apply(frame, rgb, facts, &mut labels, &mut fill);
        }
        // The vertical consensus of the IR view's labels, as the classifier first runs it.
        g.bench_function(format!("stage_consensus/{name}"), |b| {
            b.iter_batched_ref(
                || labels.clone(),
                |l| umbra::classify::consensus::settle(black_box(l)),
                criterion::BatchSize::LargeInput,
            )
        });
        umbra::classify::consensus::settle(&mut labels);
        // The warp with the colour image when there is one, as the classifier runs it.
        let mut warp = umbra::classify::align::Warp::new(cal);
        g.bench_function(format!("stage_warp_rgb/{name}"), |b| {
            b.iter(|| {
                warp.apply_with_colour(
                    black_box(&fill),
                    &labels,
                    rgb.as_deref(),
                    &mut out.rgb_labels,
                    &mut out.registered_mm,
                )
            })
        });
    }
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
