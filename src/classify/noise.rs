//! How noisy the colour camera is, read off each frame: the colour tests' steps must stay above
//! its noise, and need be no higher.
//!
//! A pixel's second difference along its row, `p[x−1] − 2·p[x] + p[x+1]`, cancels a surface's
//! shading (linear across three pixels) and keeps the noise: with independent noise of σ per
//! channel its mean magnitude is `σ·√6·√(2/π)`. Differences past `EDGE` are an edge, not noise,
//! and left out. Texture counts as noise here, which errs the safe way: a textured scene's steps
//! go up, and fewer colour edges are trusted.

use crate::labels::{HEIGHT, WIDTH};

/// Rows sampled: every `ROW_STEP`-th (30 rows of 640 pixels, a few microseconds).
const ROW_STEP: usize = 16;
/// Second differences at least this large (per channel) are an edge.
const EDGE: u16 = 64;
/// Bytes per block of the row loop.
const LANES: usize = 32;
/// `√6·√(2/π)`: the mean magnitude of a second difference over σ.
const MEAN_ABS_OVER_SIGMA: f32 = 1.954;

/// The colour camera's noise, σ per channel in 8-bit units (the channels' mean), estimated from
/// the RGB8 image `rgb` (640·480·3 bytes).
#[inline(always)]
pub fn rgb_noise(rgb: &[u8]) -> f32 {
    assert_eq!(
        rgb.len(),
        3 * WIDTH * HEIGHT,
        "an RGB image has 640x480x3 bytes"
    );
    let (mut sum, mut n) = (0u32, 0u32);
    for row in rgb
        .chunks_exact(3 * WIDTH)
        .skip(ROW_STEP / 2)
        .step_by(ROW_STEP)
    {
        // Each channel's neighbours are 3 bytes apart. Lanes of 16-bit sums, reduced once per
        // row (at most 60 blocks of 63 each: no overflow), vectorise; a row's last few bytes
        // that fill no block are left out.
        let m = row.len() - 6;
        let (left, mid, right) = (&row[..m], &row[3..m + 3], &row[6..]);
        let (mut s, mut k) = ([0u16; LANES], [0u16; LANES]);
        for ((a, b), c) in left
            .chunks_exact(LANES)
            .zip(mid.chunks_exact(LANES))
            .zip(right.chunks_exact(LANES))
        {
            for j in 0..LANES {
                let d = (i16::from(a[j]) + i16::from(c[j]) - 2 * i16::from(b[j])).unsigned_abs();
                let small = u16::from(d < EDGE);
                s[j] += d * small;
                k[j] += small;
            }
        }
        sum += s.iter().map(|&x| u32::from(x)).sum::<u32>();
        n += k.iter().map(|&x| u32::from(x)).sum::<u32>();
    }
    if n == 0 {
        return 0.0;
    }
    sum as f32 / n as f32 / MEAN_ABS_OVER_SIGMA
}

/// Camera noise (σ per channel, as [`rgb_noise`] reads it) for which the colour tests' steps hold
/// as they are: the simulator's default camera (σ = 2, plus its surfaces' texture) reads 2.8, the
/// real NYU frame 2.6.
const REFERENCE_NOISE: f32 = 2.8;
/// How much a colour step of 90 ([`hue_dist`](super::depthless::hue_dist) units) grows per unit
/// of σ over [`REFERENCE_NOISE`]: the noise's share of it.
const NOISE_WEIGHT: f32 = 10.0;
/// A step of 90 in the split and the warp.
const BASE_STEP: f32 = 90.0;

/// The factor, in 64ths, by which the colour tests' steps follow camera noise `sigma` (from
/// [`rgb_noise`]): 64 at the reference camera, more with more noise, less for a clean one. With
/// σ = 8 a step of 90 let noise pass for edges: on the holdout suite's complex scenes a fixed
/// 120 gained 0.018 attached F1, following the noise 0.022 (σ = 5: −0.005 and +0.003). Never
/// under 0.85 times: the rest of a step is for the surfaces' contrast, and through a blurring
/// lens lower steps count an edge's blended column as the occluder.
pub fn step_scale(sigma: f32) -> u32 {
    let f = (BASE_STEP + NOISE_WEIGHT * (sigma - REFERENCE_NOISE)) / BASE_STEP;
    (64.0 * f.clamp(0.85, 2.0)).round() as u32
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::labels::PIXELS;
    use rand::{Rng, SeedableRng};

    /// A shaded image (a gradient with steps, as walls and objects make) plus Gaussian noise of
    /// `sigma` per channel, drawn independently.
    fn image(sigma: f64, seed: u64) -> Vec<u8> {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
        let mut out = vec![0u8; 3 * PIXELS];
        for (i, px) in out.chunks_exact_mut(3).enumerate() {
            let (x, y) = (i % WIDTH, i / WIDTH);
            // Objects every 80 columns: strong edges, which the estimate must ignore.
            let base = 60.0
                + 0.1 * x as f64
                + 0.05 * y as f64
                + if (x / 80) % 2 == 1 { 90.0 } else { 0.0 };
            for (k, c) in px.iter_mut().enumerate() {
                // Box–Muller, so the test does not depend on the simulator's sampler.
                let (u1, u2): (f64, f64) = (rng.random_range(1e-12..1.0), rng.random());
                let g = (-2.0 * u1.ln()).sqrt() * (2.0 * std::f64::consts::PI * u2).cos();
                *c = (base + 10.0 * k as f64 + sigma * g)
                    .round()
                    .clamp(0.0, 255.0) as u8;
            }
        }
        out
    }

    #[test]
    fn estimates_the_noise_it_was_given() {
        for (sigma, seed) in [(2.0, 1), (5.0, 2), (8.0, 3)] {
            let est = rgb_noise(&image(sigma, seed));
            assert!(
                (f64::from(est) - sigma).abs() < 0.1 * sigma,
                "σ {sigma}: estimated {est}"
            );
        }
    }

    #[test]
    fn steps_follow_the_noise_from_the_reference_camera_on() {
        assert_eq!(step_scale(REFERENCE_NOISE), 64);
        // σ = 8: (90 + 10·5.2) / 90 of the steps.
        assert_eq!(step_scale(8.0), (64.0 * 142.0 / 90.0_f32).round() as u32);
        assert!(step_scale(2.0) < 64 && step_scale(3.5) > 64);
        // Clean and absurd cameras: the bounds.
        assert_eq!(step_scale(0.0), (64.0 * 0.85_f32).round() as u32);
        assert_eq!(step_scale(100.0), 128);
    }

    #[test]
    fn a_clean_image_has_next_to_no_noise() {
        // Rounding alone: well under one unit.
        assert!(rgb_noise(&image(0.0, 4)) < 0.5);
        assert_eq!(rgb_noise(&vec![128; 3 * PIXELS]), 0.0);
    }
}
