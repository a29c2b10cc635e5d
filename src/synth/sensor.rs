//! The Kinect v1 measurement model: what makes a pixel measurable, raw-value noise, and the
//! artefacts of the real sensor (shadow widening by the correlation window, mixed pixels at depth
//! edges, speckle dropouts, spurious valid pixels inside shadows).
//!
//! Every artefact keeps the ground truth exact: a pixel turned into a hole gets the label of the
//! hole it joins, a pixel that gains a value becomes VALID.

use rand::Rng;
use rand_distr::{Distribution, Normal};

use crate::calib::Calibration;
use crate::labels::{ATTACHED, DETACHED, HEIGHT, NO_DEPTH, OTHER, VALID, WIDTH};

/// Switchable sensor effects; [`SensorModel::ideal`] turns every random effect off.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SensorModel {
    /// Nearest measurable depth, metres.
    pub z_min: f64,
    /// Farthest measurable depth, metres.
    pub z_max: f64,
    /// IR albedo below which the projected pattern is too faint to decode.
    pub min_albedo: f64,
    /// Standard deviation of Gaussian noise on the raw value, raw units.
    pub noise_sigma_raw: f64,
    /// Largest number of valid pixels a shadow run swallows on its left end (correlation window).
    pub widen_left_max: u32,
    /// Largest number of valid pixels a shadow run swallows on its right end.
    pub widen_right_max: u32,
    /// Probability that a row's shadow run is widened by one more pixel on each end (the real
    /// sensor's occasional +6–7 px).
    pub widen_burst_prob: f64,
    /// Probability that a depth edge (neighbours whose raw values differ by at least
    /// `mixed_min_step_raw`) gets a mixed pixel with an intermediate value.
    pub mixed_prob: f64,
    /// Raw step that counts as a depth discontinuity for mixed pixels.
    pub mixed_min_step_raw: f64,
    /// Per-pixel probability that a speckle dropout (OTHER hole) starts at a pixel.
    pub speckle_prob: f64,
    /// Largest radius, pixels, of a speckle cluster (0: single pixels).
    pub speckle_cluster_max: u32,
    /// Per-pixel probability that a measurable shadow pixel still reports a (spurious) value.
    pub spurious_prob: f64,
    /// Standard deviation of RGB pixel noise, 8-bit units.
    pub rgb_noise_sigma: f64,
    /// Exposure of the RGB camera: every 8-bit value is scaled by it before the noise (1: a
    /// pale wall near 200; the real NYU frame's median is about 0.4 of the simulator's).
    pub rgb_gain: f64,
    /// A soft lens: the image is blurred by [`soften`] before the noise. The real NYU frame's
    /// strong edges rise over two pixels (10 % to 90 %), as this makes them; off, the
    /// simulator's rise within one.
    pub rgb_soft: bool,
}

impl Default for SensorModel {
    fn default() -> Self {
        Self::kinect()
    }
}

impl SensorModel {
    /// A Kinect v1 as seen on real frames (SPEC §1: shadows about 2.3 px wider than geometry).
    pub fn kinect() -> Self {
        SensorModel {
            z_min: 0.5,
            z_max: 4.5,
            min_albedo: 0.1,
            noise_sigma_raw: 0.5,
            widen_left_max: 3,
            widen_right_max: 2,
            widen_burst_prob: 0.04,
            mixed_prob: 0.1,
            mixed_min_step_raw: 16.0,
            speckle_prob: 2e-4,
            speckle_cluster_max: 1,
            spurious_prob: 0.002,
            rgb_noise_sigma: 2.0,
            rgb_gain: 1.0,
            rgb_soft: false,
        }
    }

    /// Noise-free geometry: exact raw values, shadows exactly as wide as geometry says, no
    /// artefacts. Range and albedo limits stay.
    pub fn ideal() -> Self {
        SensorModel {
            noise_sigma_raw: 0.0,
            widen_left_max: 0,
            widen_right_max: 0,
            widen_burst_prob: 0.0,
            mixed_prob: 0.0,
            speckle_prob: 0.0,
            spurious_prob: 0.0,
            rgb_noise_sigma: 0.0,
            ..Self::kinect()
        }
    }

    /// True if a lit surface at depth `z` with this albedo/specularity yields depth.
    pub fn measurable(&self, z: f64, albedo: f64, specular: bool) -> bool {
        !specular && albedo >= self.min_albedo && z >= self.z_min && z <= self.z_max
    }

    /// The raw value the sensor reports for depth `z`: model value plus noise, rounded and
    /// clamped to the valid range `[0, 2046]`.
    pub fn raw_value(&self, calib: &Calibration, z: f64, rng: &mut impl Rng) -> u16 {
        let noise = if self.noise_sigma_raw > 0.0 {
            gauss(rng) * self.noise_sigma_raw
        } else {
            0.0
        };
        (calib.raw_from_depth(z) + noise)
            .round()
            .clamp(0.0, f64::from(NO_DEPTH - 1)) as u16
    }
}

/// A standard normal sample.
pub(crate) fn gauss(rng: &mut impl Rng) -> f64 {
    Normal::new(0.0, 1.0).expect("unit normal").sample(rng)
}

/// Draws `0..=max`, small values a little more likely than large ones (weight `max + 4 − k`), so
/// that left 0–3 plus right 0–2 plus bursts average about +2.2 px, like the real sensor's +2.3.
fn widen_amount(max: u32, rng: &mut impl Rng) -> usize {
    if max == 0 {
        return 0;
    }
    let weights: Vec<u32> = (0..=max).map(|k| max + 4 - k).collect();
    let total: u32 = weights.iter().sum();
    let mut x = rng.random_range(0..total);
    for (k, w) in weights.iter().enumerate() {
        if x < *w {
            return k;
        }
        x -= w;
    }
    max as usize
}

/// An RGB8 image (640·480) through a soft lens: blurred by the kernel [1 2 1]/4 along rows,
/// then along columns, edges clamped, rounded to the nearest value.
pub fn soften(rgb: &[u8]) -> Vec<u8> {
    assert_eq!(
        rgb.len(),
        3 * WIDTH * HEIGHT,
        "an RGB image has 640x480x3 bytes"
    );
    // One pass of the kernel along rows or along columns, on sums (no rounding between passes).
    fn pass(img: &[u16], along_rows: bool) -> Vec<u16> {
        let mut out = vec![0u16; img.len()];
        for y in 0..HEIGHT {
            for x in 0..WIDTH {
                let (before, after) = if along_rows {
                    ((y, x.saturating_sub(1)), (y, (x + 1).min(WIDTH - 1)))
                } else {
                    ((y.saturating_sub(1), x), ((y + 1).min(HEIGHT - 1), x))
                };
                for c in 0..3 {
                    let at = |(yy, xx): (usize, usize)| u32::from(img[3 * (yy * WIDTH + xx) + c]);
                    let sum = at(before) + 2 * at((y, x)) + at(after);
                    // Four times the value on the first pass, sixteen on the second.
                    out[3 * (y * WIDTH + x) + c] = sum as u16;
                }
            }
        }
        out
    }
    let wide: Vec<u16> = rgb.iter().map(|&b| u16::from(b)).collect();
    let blurred = pass(&pass(&wide, true), false);
    blurred.iter().map(|&s| ((s + 8) / 16) as u8).collect()
}

/// Widens every run of projector-shadow pixels in each row by a random 0–`widen_left_max` valid
/// pixels on its left and 0–`widen_right_max` on its right; swallowed pixels become holes with
/// the label of the run end they join.
pub(crate) fn widen_shadows(
    m: &SensorModel,
    labels: &mut [u8],
    raw: &mut [u16],
    rng: &mut impl Rng,
) {
    if m.widen_left_max == 0 && m.widen_right_max == 0 && m.widen_burst_prob <= 0.0 {
        return;
    }
    let is_shadow = |l: u8| l == ATTACHED || l == DETACHED;
    for v in 0..HEIGHT {
        let row = v * WIDTH;
        let mut u = 0;
        while u < WIDTH {
            if !is_shadow(labels[row + u]) {
                u += 1;
                continue;
            }
            let start = u;
            while u < WIDTH && is_shadow(labels[row + u]) {
                u += 1;
            }
            let end = u; // exclusive
            let burst =
                usize::from(m.widen_burst_prob > 0.0 && rng.random_bool(m.widen_burst_prob));
            let left = widen_amount(m.widen_left_max, rng) + burst;
            let right = widen_amount(m.widen_right_max, rng) + burst;
            let (ll, rl) = (labels[row + start], labels[row + end - 1]);
            for k in 1..=left {
                let Some(x) = start.checked_sub(k) else { break };
                if labels[row + x] != VALID {
                    break;
                }
                labels[row + x] = ll;
                raw[row + x] = NO_DEPTH;
            }
            let mut grown = 0;
            while grown < right && u < WIDTH && labels[row + u] == VALID {
                labels[row + u] = rl;
                raw[row + u] = NO_DEPTH;
                grown += 1;
                u += 1;
            }
        }
    }
}

/// At depth edges between two valid neighbours (horizontal or vertical), with probability
/// `mixed_prob` replaces one of the two values by an intermediate one. Labels stay VALID.
pub(crate) fn mixed_pixels(m: &SensorModel, labels: &[u8], raw: &mut [u16], rng: &mut impl Rng) {
    if m.mixed_prob <= 0.0 {
        return;
    }
    let snapshot = raw.to_vec(); // decide on the unmixed map so edges do not cascade
    for i in 0..raw.len() {
        let (u, v) = (i % WIDTH, i / WIDTH);
        for j in [
            (u + 1 < WIDTH).then_some(i + 1),
            (v + 1 < HEIGHT).then_some(i + WIDTH),
        ]
        .into_iter()
        .flatten()
        {
            if labels[i] != VALID || labels[j] != VALID {
                continue;
            }
            let (a, b) = (f64::from(snapshot[i]), f64::from(snapshot[j]));
            if (a - b).abs() < m.mixed_min_step_raw || !rng.random_bool(m.mixed_prob) {
                continue;
            }
            let w = rng.random_range(0.2..0.8);
            let target = if rng.random_bool(0.5) { i } else { j };
            let own = f64::from(snapshot[target]);
            let other = if target == i { b } else { a };
            raw[target] = (own + w * (other - own)).round() as u16;
        }
    }
}

/// Speckle dropouts: small clusters of valid pixels become OTHER holes.
pub(crate) fn speckle(m: &SensorModel, labels: &mut [u8], raw: &mut [u16], rng: &mut impl Rng) {
    if m.speckle_prob <= 0.0 {
        return;
    }
    let expected = m.speckle_prob * (WIDTH * HEIGHT) as f64;
    let mut count = expected.floor() as usize;
    if rng.random_bool(expected.fract()) {
        count += 1;
    }
    for _ in 0..count {
        let (cu, cv) = (
            rng.random_range(0..WIDTH) as i64,
            rng.random_range(0..HEIGHT) as i64,
        );
        let r = rng.random_range(0..=m.speckle_cluster_max) as i64;
        for dv in -r..=r {
            for du in -r..=r {
                let (u, v) = (cu + du, cv + dv);
                if du * du + dv * dv > r * r
                    || u < 0
                    || v < 0
                    || u >= WIDTH as i64
                    || v >= HEIGHT as i64
                {
                    continue;
                }
                let i = v as usize * WIDTH + u as usize;
                if labels[i] == VALID {
                    labels[i] = OTHER;
                    raw[i] = NO_DEPTH;
                }
            }
        }
    }
}

/// Rare spurious measurements inside projector shadows: the pixel reports its own surface's depth
/// (plus noise) and is then VALID. `z` is the per-pixel depth of the surface the camera sees.
pub(crate) fn spurious(
    m: &SensorModel,
    calib: &Calibration,
    z: &[f64],
    labels: &mut [u8],
    raw: &mut [u16],
    rng: &mut impl Rng,
) {
    if m.spurious_prob <= 0.0 {
        return;
    }
    for i in 0..labels.len() {
        if (labels[i] == ATTACHED || labels[i] == DETACHED)
            && z[i].is_finite()
            && rng.random_bool(m.spurious_prob)
        {
            labels[i] = VALID;
            raw[i] = m.raw_value(calib, z[i], rng);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::SeedableRng;
    use rand_chacha::ChaCha8Rng;

    #[test]
    fn soften_blurs_a_step_over_two_pixels() {
        // A vertical edge, 200 left of column 300 and 40 from it on: the kernel [1 2 1]/4 along
        // the row gives 200·3/4 + 40/4 = 160 and 200/4 + 40·3/4 = 80 either side of it, and the
        // pass along the columns changes nothing (every column is uniform).
        let mut rgb = vec![200u8; 3 * WIDTH * HEIGHT];
        for v in 0..HEIGHT {
            rgb[3 * (v * WIDTH + 300)..3 * (v + 1) * WIDTH].fill(40);
        }
        let soft = soften(&rgb);
        for v in [0, 240, HEIGHT - 1] {
            let row = |u: usize| soft[3 * (v * WIDTH + u)];
            assert_eq!(
                [
                    row(0),
                    row(298),
                    row(299),
                    row(300),
                    row(301),
                    row(WIDTH - 1)
                ],
                [200, 200, 160, 80, 40, 40]
            );
        }
    }

    #[test]
    fn widening_averages_about_two_px() {
        let m = SensorModel::kinect();
        let mut rng = ChaCha8Rng::seed_from_u64(1);
        let n = 20_000;
        let (mut sum, mut max) = (0usize, 0usize);
        for _ in 0..n {
            let burst = usize::from(rng.random_bool(m.widen_burst_prob));
            let w = widen_amount(m.widen_left_max, &mut rng)
                + widen_amount(m.widen_right_max, &mut rng)
                + 2 * burst;
            sum += w;
            max = max.max(w);
        }
        let mean = sum as f64 / n as f64;
        assert!((1.9..2.6).contains(&mean), "mean widening {mean}");
        assert_eq!(max, 7);
    }

    #[test]
    fn widening_swallows_only_valid_pixels_and_keeps_labels() {
        let m = SensorModel {
            widen_left_max: 3,
            widen_right_max: 2,
            widen_burst_prob: 1.0,
            ..SensorModel::ideal()
        };
        let mut labels = vec![VALID; WIDTH * HEIGHT];
        let mut raw = vec![700u16; WIDTH * HEIGHT];
        // Row 0: OTHER at 8, ATTACHED at 10..20, VALID elsewhere.
        labels[8] = OTHER;
        for l in &mut labels[10..20] {
            *l = ATTACHED;
        }
        for (r, &l) in raw.iter_mut().zip(&labels) {
            if l != VALID {
                *r = NO_DEPTH;
            }
        }
        let mut rng = ChaCha8Rng::seed_from_u64(3);
        widen_shadows(&m, &mut labels, &mut raw, &mut rng);
        assert_eq!(labels[8], OTHER, "never overwrite another hole");
        let right = labels[20..].iter().take_while(|&&l| l == ATTACHED).count();
        assert!((1..=3).contains(&right), "{right}");
        assert!(labels
            .iter()
            .zip(&raw)
            .all(|(&l, &r)| (l == VALID) == (r != NO_DEPTH)));
    }

    #[test]
    fn ideal_raw_is_exact() {
        let c = Calibration::nyu_default();
        let mut rng = ChaCha8Rng::seed_from_u64(0);
        let r = SensorModel::ideal().raw_value(&c, 2.0, &mut rng);
        assert_eq!(r, c.raw_from_depth(2.0).round() as u16);
    }
}
