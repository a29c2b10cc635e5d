//! Classification allocates nothing per frame: a counting global allocator (this test binary's
//! own) sees no allocation while frames are classified after the classifier is built.

use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicUsize, Ordering};

use umbra::classify::{Classified, Classifier};
use umbra::synth::{random_scene, render_frame, sensor_for, Category};
use umbra::Calibration;

struct Counting;

static ALLOCATIONS: AtomicUsize = AtomicUsize::new(0);

// SAFETY: forwards every call to the system allocator unchanged; only counts.
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        ALLOCATIONS.fetch_add(1, Ordering::Relaxed);
        // SAFETY: same contract as the caller's.
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        // SAFETY: same contract as the caller's.
        unsafe { System.dealloc(ptr, layout) }
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

#[test]
fn classifying_frames_allocates_nothing() {
    let calib = Calibration::nyu_default();
    let frames: Vec<_> = (0..3)
        .map(|s| {
            render_frame(
                &random_scene(Category::Complex, s),
                &calib,
                &sensor_for(Category::Complex),
                s,
            )
        })
        .collect();
    let mut classifier = Classifier::new(&calib);
    let mut out = Classified::default();
    let before = ALLOCATIONS.load(Ordering::Relaxed);
    for f in frames.iter().cycle().take(9) {
        classifier.classify(&f.raw, &mut out);
    }
    let during = ALLOCATIONS.load(Ordering::Relaxed) - before;
    assert_eq!(during, 0, "{during} allocations while classifying 9 frames");
    assert!(
        out.ir_labels.iter().any(|&l| l != 0),
        "the frames were really classified"
    );
}
