//! The per-frame algorithm: IR-view scanline classification ([`scanline`]), then the warp into the
//! RGB camera that carries labels over and finds alignment shadows ([`align`]).
//!
//! Everything here is pure computation on caller-owned buffers: no I/O, no per-frame allocation.

pub mod align;
pub mod bands;
pub mod consensus;
pub mod depthless;
mod holes;
pub mod noise;
pub mod scanline;
pub mod touching;
mod unseen;

use crate::calib::Calibration;
use crate::labels::PIXELS;

/// The nearest a surface may stand before the camera (metres): where the Kinect v1's working
/// range begins (libfreenect reports no depth nearer). An occluder that returns no depth, placed
/// nearer than that by its shadow's width, is a misreading: a glossy cylinder's dropouts beside
/// a near object read as a depthless occluder and its shadow. (At 0.4 m: the fifth simulator's
/// 28 suites, complex IR attached F1 −0.042 summed, any-shadow precision −0.047, recall −0.064;
/// RGB precision −0.111.)
pub(crate) const NEAREST_M: f64 = 0.5;

/// Tunable thresholds of the classifier; defaults fit the Kinect v1 (see each field).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Params {
    /// Smallest disparity step (pixels) between a hole's bounds that counts as a depth edge.
    pub min_step_px: f64,
    /// How much wider than predicted an attached shadow may look before its far part is OTHER;
    /// the real sensor's correlation window widens shadows by up to ~7 px (SPEC §1).
    pub attached_over_px: f64,
    /// Tolerance (pixels) on each of the two detached-shadow equations (4)–(5).
    pub detached_tol_px: f64,
    /// Valid runs this short between two holes are treated as noise inside one hole. One pixel:
    /// a spurious return inside a shadow is a lone pixel; two are more often lit background
    /// between two holes (a shadow beside a black poster), which the bound of each must see.
    pub max_island_px: usize,
}

impl Default for Params {
    fn default() -> Self {
        Params {
            min_step_px: 1.0,
            attached_over_px: 8.0,
            detached_tol_px: 4.0,
            max_island_px: 1,
        }
    }
}

/// Output buffers of one classified frame, allocated once and reused.
#[derive(Clone, Debug)]
pub struct Classified {
    /// Labels in the IR (depth) view, SPEC §2 codes.
    pub ir_labels: Vec<u8>,
    /// Labels in the RGB view.
    pub rgb_labels: Vec<u8>,
    /// Depth registered to the RGB view, millimetres, 0 = none.
    pub registered_mm: Vec<u16>,
}

impl Default for Classified {
    fn default() -> Self {
        Classified {
            ir_labels: vec![0; PIXELS],
            rgb_labels: vec![0; PIXELS],
            registered_mm: vec![0; PIXELS],
        }
    }
}

/// Classifies whole frames with a fixed calibration; holds scratch buffers so that
/// [`Classifier::classify`] never allocates.
pub struct Classifier {
    scan: scanline::ScanParams,
    colour: depthless::ColourSplit,
    warp: align::Warp,
    /// Raw values with holes filled by the depth they are assumed to lie at (for the warp).
    filled: Vec<u16>,
}

impl Classifier {
    /// A classifier for `calib` with default [`Params`].
    pub fn new(calib: &Calibration) -> Self {
        Self::with_params(calib, Params::default())
    }

    /// A classifier with explicit thresholds.
    pub fn with_params(calib: &Calibration, params: Params) -> Self {
        Classifier {
            scan: scanline::ScanParams::new(calib, &params),
            colour: depthless::ColourSplit::new(calib, params.attached_over_px),
            warp: align::Warp::new(calib),
            filled: vec![0; PIXELS],
        }
    }

    /// Which builds of the hot loops this classifier runs, for speed reports: the SIMD level this
    /// CPU allows and the warp's projection (see [`align::Warp`]).
    pub fn hot_loops(&self) -> String {
        format!("{}, {}", self.warp.simd_name(), self.warp.projection_name())
    }

    /// Labels one raw 640×480 frame in both views, from depth alone.
    pub fn classify(&mut self, raw: &[u16], out: &mut Classified) {
        self.classify_with_rgb(raw, None, out);
    }

    /// Labels one raw 640×480 frame in both views; with the paired RGB image (RGB8, 640·480·3),
    /// also the attached shadows of occluders that return no depth ([`depthless`]).
    pub fn classify_with_rgb(&mut self, raw: &[u16], rgb: Option<&[u8]>, out: &mut Classified) {
        assert_eq!(raw.len(), PIXELS, "a frame has 640x480 raw values");
        let facts = scanline::classify_frame(&self.scan, raw, &mut out.ir_labels, &mut self.filled);
        if let Some(rgb) = rgb {
            assert_eq!(rgb.len(), 3 * PIXELS, "an RGB image has 640x480x3 bytes");
            self.colour
                .apply(raw, rgb, facts, &mut out.ir_labels, &mut self.filled);
            self.warp.set_noise_scale(self.colour.noise_scale());
            self.warp.set_widening(facts.left_widening);
            self.warp.set_range_end(facts.range.limit);
        }
        consensus::settle(&mut out.ir_labels);
        bands::bridge_detached(&mut out.ir_labels);
        touching::attach_touching(&self.scan, raw, &self.filled, &mut out.ir_labels);
        self.warp.apply_with_colour(
            &self.filled,
            &out.ir_labels,
            rgb,
            &mut out.rgb_labels,
            &mut out.registered_mm,
        );
        // Alignment strips are solids too, and the warp's edge placement fails in runs of rows.
        consensus::settle_apart(&mut out.rgb_labels);
    }
}

#[cfg(test)]
mod tests {
    use super::align::Simd;
    use super::*;
    use crate::labels::{ALIGNMENT, HEIGHT, NO_DEPTH, OTHER, VALID, WIDTH};
    use crate::synth::{random_scene, render_frame, sensor_for, Category};
    use rand::Rng;

    /// The warp's projection without division, for a calibration whose RGB camera is only
    /// shifted along x, places every pixel where the general projection does: on busy simulated
    /// frames the labels agree, and registered depth within the millimetre of its rounding.
    #[test]
    fn affine_projection_agrees_with_the_general_one() {
        let calib = Calibration::nyu_default();
        for seed in [3, 8] {
            let scene = random_scene(Category::Complex, seed);
            let frame = render_frame(&scene, &calib, &sensor_for(Category::Complex), seed);
            let mut outputs = Vec::new();
            for general in [false, true] {
                let mut c = Classifier::new(&calib);
                assert!(c.warp.is_affine(), "the NYU defaults have no rotation");
                if general {
                    c.warp.force_general();
                }
                let mut out = Classified::default();
                c.classify_with_rgb(&frame.raw, Some(&frame.rgb), &mut out);
                outputs.push(out);
            }
            let (affine, general) = (&outputs[0], &outputs[1]);
            let moved = affine
                .rgb_labels
                .iter()
                .zip(&general.rgb_labels)
                .filter(|(a, b)| a != b)
                .count();
            assert_eq!(moved, 0, "RGB labels that differ (seed {seed})");
            let worst = affine
                .registered_mm
                .iter()
                .zip(&general.registered_mm)
                .map(|(&a, &b)| a.abs_diff(b))
                .max()
                .unwrap_or(0);
            assert!(
                worst <= 1,
                "registered depth differs by {worst} mm (seed {seed})"
            );
            assert!(affine.registered_mm.iter().filter(|&&d| d > 0).count() > PIXELS / 2);
        }
    }

    /// Every build of the hot loops (baseline, AVX2, AVX-512, whichever this CPU runs) labels
    /// busy simulated frames identically, bit for bit, in both views and in registered depth.
    #[test]
    fn every_simd_build_gives_identical_output() {
        let calib = Calibration::nyu_default();
        for seed in [3, 8] {
            let scene = random_scene(Category::Complex, seed);
            let frame = render_frame(&scene, &calib, &sensor_for(Category::Complex), seed);
            let mut outputs = Vec::new();
            for level in simd_levels() {
                let c = &mut with_simd(&calib, level);
                let mut out = Classified::default();
                c.classify_with_rgb(&frame.raw, Some(&frame.rgb), &mut out);
                // A second frame through the same classifier: its scratch state resets cleanly.
                c.classify_with_rgb(&frame.raw, Some(&frame.rgb), &mut out);
                outputs.push((level, out));
            }
            let (base_level, base) = &outputs[0];
            assert!(base.ir_labels.iter().any(|&l| l != 0), "a busy frame");
            for (level, out) in &outputs[1..] {
                assert!(
                    base.ir_labels == out.ir_labels,
                    "IR labels: {level:?} vs {base_level:?}"
                );
                assert!(
                    base.rgb_labels == out.rgb_labels,
                    "RGB labels: {level:?} vs {base_level:?}"
                );
                assert!(
                    base.registered_mm == out.registered_mm,
                    "registered depth: {level:?} vs {base_level:?}"
                );
            }
        }
    }

    /// The builds of the hot loops this CPU runs.
    fn simd_levels() -> Vec<Simd> {
        let mut levels = vec![Simd::Baseline];
        #[cfg(target_arch = "x86_64")]
        {
            if std::is_x86_feature_detected!("avx2") && std::is_x86_feature_detected!("fma") {
                levels.push(Simd::Avx2);
            }
            if Simd::detect() == Simd::Avx512 {
                levels.push(Simd::Avx512);
            }
        }
        levels
    }

    /// A classifier for `calib` running the `level` build of every hot loop.
    fn with_simd(calib: &Calibration, level: Simd) -> Classifier {
        let mut c = Classifier::new(calib);
        c.scan.set_simd(level);
        c.colour.set_simd(level);
        c.warp.set_simd(level);
        c
    }

    /// An RGB camera that sees the IR image's first column and first row a third of a pixel left
    /// of and above its own image (a rotation, or an offset sideways or up, gives such corners):
    /// those pixels land in its first column and row, in every build. They used to be rounded
    /// to −0.5 and put at a negative index: out of the image, and out of bounds of the colour
    /// image the warp prefetches at depth edges (a panic), found by feeding random valid
    /// calibrations.
    #[test]
    fn pixels_a_hair_outside_the_rgb_image_land_in_its_first_row_and_column() {
        let mut calib = Calibration::nyu_default();
        // By hand at 2 m: IR column 0 lands at x = 518.86·(−313.04/582.62 − 0.025/2) + cx
        // = cx − 285.27, IR row 0 at y = 519.47·(−238.44/582.69) + cy = cy − 212.57: both at
        // −0.35, whose footprints (0.89 RGB px wide) cover the first column's and row's centres.
        calib.rgb.cx = 284.92;
        calib.rgb.cy = 212.22;
        let wall = calib.raw_from_depth(2.0).round() as u16;
        let mut raw = vec![wall; PIXELS];
        // A box at 1 m in the top left: depth edges in the first rows, where the warp reads the
        // colour image.
        let near = calib.raw_from_depth(1.0).round() as u16;
        for v in 0..100 {
            raw[v * WIDTH + 100..v * WIDTH + 200].fill(near);
        }
        let rgb = vec![128u8; 3 * PIXELS];
        for level in simd_levels() {
            let mut out = Classified::default();
            with_simd(&calib, level).classify_with_rgb(&raw, Some(&rgb), &mut out);
            let at = |v: usize, u: usize| out.registered_mm[v * WIDTH + u];
            for k in 0..60 {
                for (v, u) in [(0, k), (k + 100, 0)] {
                    assert!(
                        at(v, u).abs_diff(2000) <= 10,
                        "{level:?}: RGB ({u}, {v}) at {} mm",
                        at(v, u)
                    );
                }
            }
        }
    }

    /// A calibration `validate` accepts, picked at random among the kinds of change it allows
    /// (any rotation, offsets up to half a metre, focal lengths and principal points anywhere in
    /// range, other raw models).
    fn random_calibration(rng: &mut impl Rng) -> Calibration {
        let mut c = Calibration::nyu_default();
        match rng.random_range(0..5) {
            0 => {}
            1 => {
                let axis = nalgebra::Vector3::from_fn(|_, _| rng.random::<f64>() - 0.5);
                let angle = rng.random_range(-3.1..3.1);
                c.depth_to_rgb.rotation = *nalgebra::Rotation3::from_axis_angle(
                    &nalgebra::Unit::new_normalize(axis),
                    angle,
                )
                .matrix();
            }
            2 => {
                c.depth_to_rgb.translation =
                    nalgebra::Vector3::from_fn(|_, _| rng.random_range(-0.49..0.49));
            }
            3 => {
                for k in [&mut c.depth, &mut c.rgb] {
                    k.fx = rng.random_range(51.0..4999.0);
                    k.fy = (k.fx * rng.random_range(0.85..1.15)).clamp(51.0, 4999.0);
                    k.cx = rng.random_range(0.0..640.0);
                    k.cy = rng.random_range(0.0..480.0);
                }
            }
            _ => {
                c.raw.numerator = rng.random_range(11.0..9999.0);
                c.raw.denominator = rng.random_range(101.0..4096.0);
                c.raw.baseline_m = rng.random_range(0.011..0.49);
            }
        }
        c.validate().expect("a valid calibration");
        c
    }

    /// A raw frame of one of several kinds no sensor makes: uniform noise, noise with holes,
    /// random rectangles, all holes, one value, alternating hole columns.
    fn random_frame(rng: &mut impl Rng) -> Vec<u16> {
        let mut raw = vec![0u16; PIXELS];
        match rng.random_range(0..6) {
            0 => raw.fill_with(|| rng.random_range(0..=2047)),
            1 => raw.fill_with(|| {
                if rng.random_bool(0.3) {
                    NO_DEPTH
                } else {
                    rng.random_range(0..NO_DEPTH)
                }
            }),
            2 => {
                raw.fill(rng.random_range(0..NO_DEPTH));
                for _ in 0..rng.random_range(1..60) {
                    let (u0, v0) = (rng.random_range(0..WIDTH), rng.random_range(0..HEIGHT));
                    let (w, h) = (rng.random_range(1..200), rng.random_range(1..200));
                    let value = if rng.random_bool(0.4) {
                        NO_DEPTH
                    } else {
                        rng.random_range(0..NO_DEPTH)
                    };
                    for v in v0..(v0 + h).min(HEIGHT) {
                        raw[v * WIDTH + u0..v * WIDTH + (u0 + w).min(WIDTH)].fill(value);
                    }
                }
            }
            3 => raw.fill(NO_DEPTH),
            4 => raw.fill(rng.random_range(0..NO_DEPTH)),
            _ => {
                for (i, r) in raw.iter_mut().enumerate() {
                    *r = if i % 2 == 0 {
                        NO_DEPTH
                    } else {
                        (i % 2047) as u16
                    };
                }
            }
        }
        raw
    }

    /// Whatever valid calibration and whatever frame and colour image, with or without the
    /// colour image, in every build: no panic, and the labels keep their contract. In the IR view
    /// a pixel is VALID exactly when it has depth and never ALIGNMENT; in the RGB view a pixel is
    /// VALID exactly when it has registered depth. (This found the warp's rounding of pixels a
    /// hair outside the RGB image, above.)
    #[test]
    fn random_valid_calibrations_and_frames_keep_the_label_contract() {
        use rand::SeedableRng;
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(2026);
        for case in 0..24 {
            let calib = random_calibration(&mut rng);
            let raw = random_frame(&mut rng);
            let rgb: Vec<u8> = (0..3 * PIXELS).map(|_| rng.random()).collect();
            for level in simd_levels() {
                let c = &mut with_simd(&calib, level);
                let mut out = Classified::default();
                for colour in [Some(&rgb[..]), None] {
                    c.classify_with_rgb(&raw, colour, &mut out);
                    let what = format!("case {case}, {level:?}, colour {}", colour.is_some());
                    for (&l, &r) in out.ir_labels.iter().zip(&raw) {
                        assert!(l <= OTHER && l != ALIGNMENT, "{what}: IR label {l}");
                        assert_eq!(l == VALID, r != NO_DEPTH, "{what}: IR label {l}, raw {r}");
                    }
                    for (&l, &mm) in out.rgb_labels.iter().zip(&out.registered_mm) {
                        assert!(l <= OTHER, "{what}: RGB label {l}");
                        assert_eq!(l == VALID, mm > 0, "{what}: RGB label {l}, {mm} mm");
                    }
                }
            }
        }
    }
}
