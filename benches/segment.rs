//! Issue 4's speed target: automatic foreground segmentation (shadow seeds, k-means rejection,
//! room planes, GrabCut with colour+depth mixtures and max-flow) of one 640×480 frame in
//! ≤ 100 ms on one core. Classification is done once outside the timed loop.

use criterion::{criterion_group, criterion_main, Criterion};
use std::hint::black_box;
use std::path::Path;
use umbra::classify::{Classified, Classifier};
use umbra::labels::PIXELS;
use umbra::recording::Recording;
use umbra::segment::{Params, SeedMode, Segmenter};

/// Frame 0 of a bundled recording: RGB image and classifier output.
fn frame(dir: &str) -> (Vec<u8>, Classified) {
    let rec = Recording::open(Path::new(dir)).expect("bundled recording");
    let mut raw = vec![0u16; PIXELS];
    let mut rgb = vec![0u8; 3 * PIXELS];
    rec.read_depth(0, &mut raw).expect("depth");
    assert!(
        rec.read_rgb(0, &mut rgb).expect("rgb"),
        "bundled recordings have RGB"
    );
    let mut out = Classified::default();
    Classifier::new(rec.calibration()).classify(&raw, &mut out);
    (rgb, out)
}

fn bench(c: &mut Criterion) {
    let root = env!("CARGO_MANIFEST_DIR");
    let mut g = c.benchmark_group("segment_640x480");
    g.sample_size(20);
    for name in ["complex-room", "box-before-wall"] {
        let (rgb, classified) = frame(&format!("{root}/recordings/{name}"));
        let mut mask = vec![0u8; PIXELS];
        let mut seg = Segmenter::new(Params::default());
        g.bench_function(format!("shadow_seeds/{name}"), |b| {
            b.iter(|| seg.segment(black_box(&rgb), &classified, &mut mask))
        });
        let mut seg = Segmenter::new(Params {
            seeds: SeedMode::Threshold {
                tf_m: 2.0,
                tb_m: 2.5,
            },
            ..Params::default()
        });
        g.bench_function(format!("threshold_seeds/{name}"), |b| {
            b.iter(|| seg.segment(black_box(&rgb), &classified, &mut mask))
        });
    }
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
