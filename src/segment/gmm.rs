//! Gaussian mixtures over colour and depth, GrabCut-style (Rother et al. 2004): hard assignment of
//! each pixel to its most likely component, then re-estimation from the assigned pixels.
//!
//! A pixel with depth is scored on all four dimensions (r, g, b, depth cm); one without depth
//! (OTHER holes: black, glossy, out-of-range surfaces, the border outside the IR view) on the
//! colour marginal of each component, so depth is a 4th channel where it exists and missing depth
//! never counts as evidence. The cost of a pixel is the negative log-density of its best
//! component (the max-component approximation of the mixture, as GrabCut's assignment step uses):
//! no `exp` per component and pixel.

use nalgebra::{Matrix3, Matrix4};

use super::kmeans::Point;

/// Most components a mixture can have (GrabCut uses 5).
pub const MAX_COMPONENTS: usize = 8;
/// Variance added to each colour dimension (8-bit units²): keeps flat synthetic colours and few
/// samples from giving singular covariances.
const REG_COLOUR: f64 = 9.0;
/// Variance added to the depth dimension (cm²): about the Kinect's noise at 2–3 m.
const REG_DEPTH: f64 = 4.0;
/// Components with fewer samples are dropped.
const MIN_SAMPLES: f64 = 8.0;

/// Sufficient statistics of each component, accumulated from assigned samples.
#[derive(Clone, Debug, Default)]
pub struct Stats {
    /// Samples with depth: count, sums, sums of products (upper triangle, 10 entries).
    n4: [f64; MAX_COMPONENTS],
    s4: [[f64; 4]; MAX_COMPONENTS],
    q4: [[f64; 10]; MAX_COMPONENTS],
    /// All samples, colour only.
    n3: [f64; MAX_COMPONENTS],
    s3: [[f64; 3]; MAX_COMPONENTS],
    q3: [[f64; 6]; MAX_COMPONENTS],
}

impl Stats {
    /// Forgets every sample.
    pub fn clear(&mut self) {
        *self = Stats::default();
    }

    /// Adds sample `x` (depth `x[3] == 0` means none) to component `k`.
    #[inline]
    pub fn add(&mut self, k: usize, x: &Point) {
        let c = [
            f64::from(x[0]),
            f64::from(x[1]),
            f64::from(x[2]),
            f64::from(x[3]),
        ];
        self.n3[k] += 1.0;
        let mut t = 0;
        for i in 0..3 {
            self.s3[k][i] += c[i];
            for j in i..3 {
                self.q3[k][t] += c[i] * c[j];
                t += 1;
            }
        }
        if x[3] > 0.0 {
            self.n4[k] += 1.0;
            let mut t = 0;
            for i in 0..4 {
                self.s4[k][i] += c[i];
                for j in i..4 {
                    self.q4[k][t] += c[i] * c[j];
                    t += 1;
                }
            }
        }
    }
}

/// One component, ready to score: `cost(x) = bias + ½ (x − μ)ᵀ Σ⁻¹ (x − μ)`.
#[derive(Clone, Copy, Debug, Default)]
struct Comp {
    /// The [`Stats`] slot it was fitted from: assignments refer to slots, so the full and the
    /// colour-only component of one slot stay one component.
    slot: u8,
    mean: [f32; 4],
    /// Upper triangle of Σ⁻¹ (4-D: 10 entries; colour marginal: first 6 as 3-D).
    icov: [f32; 10],
    bias: f32,
}

/// A mixture of up to [`MAX_COMPONENTS`] Gaussians.
#[derive(Clone, Debug, Default)]
pub struct Gmm {
    full: [Comp; MAX_COMPONENTS],
    nfull: usize,
    colour: [Comp; MAX_COMPONENTS],
    ncolour: usize,
}

impl Gmm {
    /// True when the mixture has no component (no samples).
    pub fn is_empty(&self) -> bool {
        self.nfull == 0 && self.ncolour == 0
    }

    /// Fits the mixture to `stats` (components with too few samples are left out).
    pub fn fit(&mut self, stats: &Stats) {
        let total4: f64 = stats.n4.iter().sum();
        let total3: f64 = stats.n3.iter().sum();
        self.nfull = 0;
        self.ncolour = 0;
        for k in 0..MAX_COMPONENTS {
            let n = stats.n4[k];
            if n >= MIN_SAMPLES {
                let mean: [f64; 4] = std::array::from_fn(|i| stats.s4[k][i] / n);
                let mut m = Matrix4::<f64>::zeros();
                let mut t = 0;
                for i in 0..4 {
                    for j in i..4 {
                        let c = stats.q4[k][t] / n - mean[i] * mean[j];
                        m[(i, j)] = c;
                        m[(j, i)] = c;
                        t += 1;
                    }
                }
                for i in 0..3 {
                    m[(i, i)] += REG_COLOUR;
                }
                m[(3, 3)] += REG_DEPTH;
                if let Some(comp) = comp4(&m, &mean, n / total4) {
                    self.full[self.nfull] = Comp {
                        slot: k as u8,
                        ..comp
                    };
                    self.nfull += 1;
                }
            }
            let n = stats.n3[k];
            if n >= MIN_SAMPLES {
                let mean: [f64; 3] = std::array::from_fn(|i| stats.s3[k][i] / n);
                let mut m = Matrix3::<f64>::zeros();
                let mut t = 0;
                for i in 0..3 {
                    for j in i..3 {
                        let c = stats.q3[k][t] / n - mean[i] * mean[j];
                        m[(i, j)] = c;
                        m[(j, i)] = c;
                        t += 1;
                    }
                    m[(i, i)] += REG_COLOUR;
                }
                if let Some(comp) = comp3(&m, &mean, n / total3) {
                    self.colour[self.ncolour] = Comp {
                        slot: k as u8,
                        ..comp
                    };
                    self.ncolour += 1;
                }
            }
        }
    }

    /// Cost (negative log-density, nats) of `x` under its best component, and that component's
    /// [`Stats`] slot. `x[3] == 0` scores on colour only. An empty mixture costs
    /// `empty_cost`.
    #[inline]
    pub fn cost(&self, x: &Point, empty_cost: f32) -> (f32, u8) {
        let mut best = (empty_cost, 0u8);
        if x[3] > 0.0 && self.nfull > 0 {
            best.0 = f32::INFINITY;
            for c in &self.full[..self.nfull] {
                let d = [
                    x[0] - c.mean[0],
                    x[1] - c.mean[1],
                    x[2] - c.mean[2],
                    x[3] - c.mean[3],
                ];
                let a = &c.icov;
                let q = a[0] * d[0] * d[0]
                    + a[4] * d[1] * d[1]
                    + a[7] * d[2] * d[2]
                    + a[9] * d[3] * d[3]
                    + 2.0
                        * (a[1] * d[0] * d[1]
                            + a[2] * d[0] * d[2]
                            + a[3] * d[0] * d[3]
                            + a[5] * d[1] * d[2]
                            + a[6] * d[1] * d[3]
                            + a[8] * d[2] * d[3]);
                let e = c.bias + 0.5 * q;
                if e < best.0 {
                    best = (e, c.slot);
                }
            }
        } else if self.ncolour > 0 {
            best.0 = f32::INFINITY;
            for c in &self.colour[..self.ncolour] {
                let d = [x[0] - c.mean[0], x[1] - c.mean[1], x[2] - c.mean[2]];
                let a = &c.icov;
                let q = a[0] * d[0] * d[0]
                    + a[3] * d[1] * d[1]
                    + a[5] * d[2] * d[2]
                    + 2.0 * (a[1] * d[0] * d[1] + a[2] * d[0] * d[2] + a[4] * d[1] * d[2]);
                let e = c.bias + 0.5 * q;
                if e < best.0 {
                    best = (e, c.slot);
                }
            }
        }
        best
    }
}

fn comp4(m: &Matrix4<f64>, mean: &[f64; 4], weight: f64) -> Option<Comp> {
    let inv = m.try_inverse()?;
    comp(m.determinant(), |i, j| inv[(i, j)], 4, *mean, weight)
}

fn comp3(m: &Matrix3<f64>, mean: &[f64; 3], weight: f64) -> Option<Comp> {
    let inv = m.try_inverse()?;
    comp(
        m.determinant(),
        |i, j| inv[(i, j)],
        3,
        [mean[0], mean[1], mean[2], 0.0],
        weight,
    )
}

/// A component of dimension `n` (3 or 4) from its covariance's determinant and inverse: the
/// upper triangle of the inverse, and the constant part of the negative log-likelihood.
fn comp(
    det: f64,
    inv: impl Fn(usize, usize) -> f64,
    n: usize,
    mean: [f64; 4],
    weight: f64,
) -> Option<Comp> {
    if det <= 0.0 || !det.is_finite() {
        return None;
    }
    let mut icov = [0.0f32; 10];
    let mut t = 0;
    for i in 0..n {
        for j in i..n {
            icov[t] = inv(i, j) as f32;
            t += 1;
        }
    }
    let bias = -weight.ln() + 0.5 * det.ln() + 0.5 * n as f64 * (2.0 * std::f64::consts::PI).ln();
    Some(Comp {
        slot: 0,
        mean: mean.map(|v| v as f32),
        icov,
        bias: bias as f32,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fitted_mixture_prefers_its_own_samples_and_scores_colour_without_depth() {
        // Component 0: reddish near (100 cm); component 1: grey far (300 cm).
        let mut s = Stats::default();
        for i in 0..200 {
            let e = (i % 11) as f32 - 5.0;
            s.add(0, &[200.0 + e, 40.0 - e, 30.0 + e, 100.0 + e * 0.5]);
            s.add(1, &[150.0 + e, 150.0 + e, 145.0 - e, 300.0 - e]);
        }
        let mut g = Gmm::default();
        g.fit(&s);
        let (near, k0) = g.cost(&[200.0, 40.0, 30.0, 100.0], 99.0);
        let (_, k1) = g.cost(&[150.0, 150.0, 145.0, 300.0], 99.0);
        assert_ne!(k0, k1);
        let (off, _) = g.cost(&[200.0, 40.0, 30.0, 300.0], 99.0);
        assert!(
            off > near + 20.0,
            "a red pixel at the grey depth is unlikely: {off} vs {near}"
        );
        // No depth: colour alone decides, and a red pixel is as likely as with its right depth.
        let (c, _) = g.cost(&[200.0, 40.0, 30.0, 0.0], 99.0);
        assert!(c < off);
        assert_eq!(Gmm::default().cost(&[1.0; 4], 7.0).0, 7.0);
    }
}
