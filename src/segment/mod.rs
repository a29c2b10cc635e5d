//! Shadow-assisted automatic foreground segmentation (Deng et al., ICCVW 2013, §4): classified
//! shadows say where object edges are and on which side the object lies, which gives
//! foreground/background seeds with no clicks and no training ([`seeds`]); wrong seeds are
//! rejected by k-means on depth and colour ([`kmeans`]); background seeds grow over the room
//! surfaces (large planes) they lie on; GrabCut with depth as a 4th channel ([`gmm`]) and a grid
//! max-flow ([`maxflow`]) turn the seeds into a mask. Pixels without depth are scored on colour,
//! against a uniform outlier model for the foreground (black and glossy objects have no depth
//! and often no seed, but do not look like the room).
//!
//! For the daemon: build one [`Segmenter`] per thread with [`Segmenter::new`] and call
//! [`Segmenter::segment`]`(rgb, &classified, &mut mask)` per frame; it allocates nothing per frame
//! after the first (the seed scratch vectors reach their size on the first frames).
//!
//! Everything runs in the RGB view on the colour image and the depth registered to it, and writes
//! SPEC §6 masks (255 foreground, 0 background). [`Segmenter`] holds every buffer, so the daemon
//! can call [`Segmenter::segment`] per frame without allocating.

pub mod files;
pub mod gmm;
pub mod kmeans;
pub mod maxflow;
pub mod seeds;

use crate::classify::Classified;
use crate::labels::{ALIGNMENT, ATTACHED, DETACHED, HEIGHT, PIXELS, VALID, WIDTH};
use gmm::{Gmm, Stats};
use kmeans::Point;
use maxflow::GridFlow;
pub use seeds::{SeedParams, BG, FG};

/// Where the seeds come from.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SeedMode {
    /// From the classified shadows (the paper's method).
    Shadow,
    /// The paper's baseline: measured pixels nearer than Tf (metres) are foreground, farther than
    /// Tb background.
    Threshold {
        /// Tf, metres.
        tf_m: f32,
        /// Tb, metres.
        tb_m: f32,
    },
}

/// Settings of the segmenter; the defaults are the measured best on simulated scenes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Params {
    /// Seed source.
    pub seeds: SeedMode,
    /// Geometry of shadow seeds.
    pub shadow: SeedParams,
    /// Room-surface planes that grow background shadow seeds (`max_planes` 0: off).
    pub planes: seeds::PlaneParams,
    /// k of the k-means that rejects wrong shadow seeds (0: keep every seed).
    pub clusters: usize,
    /// Largest share of the minority side in a cluster before the whole cluster is dropped.
    pub max_minority: f32,
    /// Gaussians per mixture (GrabCut: 5).
    pub components: usize,
    /// GrabCut iterations (fit mixtures, cut).
    pub iterations: usize,
    /// Weight of the smoothness term (GrabCut: 50).
    pub gamma: f32,
    /// σ (cm) of the depth factor `exp(−Δd² / (2σ²))` that joins the colour contrast term of the
    /// smoothness weight where both neighbours have depth: cuts are cheap across depth edges.
    pub depth_sigma_cm: f32,
}

impl Default for Params {
    fn default() -> Self {
        Params {
            seeds: SeedMode::Shadow,
            shadow: SeedParams::default(),
            planes: seeds::PlaneParams::default(),
            clusters: 12,
            max_minority: 0.2,
            components: 5,
            iterations: 3,
            gamma: 50.0,
            depth_sigma_cm: 5.0,
        }
    }
}

/// What one call of [`Segmenter::segment`] did.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Outcome {
    /// Foreground seeds used.
    pub fg_seeds: usize,
    /// Background seeds used.
    pub bg_seeds: usize,
    /// Seeds rejected by clustering.
    pub rejected: usize,
    /// Foreground pixels in the mask.
    pub fg_pixels: usize,
}

/// Integer units per nat of energy in the graph.
const SCALE: f32 = 16.0;
/// Terminal capacity of a hard seed: more than any cut through its neighbours can cost.
const HARD: i32 = 1 << 24;
/// Cost of a pixel under a mixture that has no component.
const EMPTY_COST: f32 = 30.0;
/// Highest data cost difference (nats): one pixel's evidence never outweighs everything.
const MAX_COST: f32 = 60.0;
/// Cost of a colour under the uniform density over the 8-bit RGB cube: 3·ln 256 nats.
const UNIFORM_COLOUR_COST: f32 = 16.64;
/// At most this many seeds initialise a mixture (evenly subsampled).
const INIT_SAMPLES: usize = 4096;

/// The segmenter: settings plus every per-frame buffer.
pub struct Segmenter {
    params: Params,
    features: Vec<Point>,
    seeds: Vec<u8>,
    fg_side: Vec<bool>,
    right: Vec<i32>,
    down: Vec<i32>,
    flow: GridFlow,
    fg: Gmm,
    bg: Gmm,
    stats_fg: Stats,
    stats_bg: Stats,
    cluster: seeds::ClusterScratch,
    plane: seeds::PlaneScratch,
    samples: Vec<Point>,
    assign: Vec<u8>,
    dist: Vec<f32>,
}

impl Segmenter {
    /// A segmenter with all buffers for 640×480 frames allocated.
    pub fn new(params: Params) -> Self {
        let mut flow = GridFlow::new();
        flow.reset(WIDTH, HEIGHT);
        Segmenter {
            params,
            features: vec![[0.0; 4]; PIXELS],
            seeds: vec![0; PIXELS],
            fg_side: vec![false; PIXELS],
            right: vec![0; PIXELS],
            down: vec![0; PIXELS],
            flow,
            fg: Gmm::default(),
            bg: Gmm::default(),
            stats_fg: Stats::default(),
            stats_bg: Stats::default(),
            cluster: seeds::ClusterScratch::default(),
            plane: seeds::PlaneScratch::default(),
            samples: Vec::with_capacity(INIT_SAMPLES),
            assign: vec![0; INIT_SAMPLES],
            dist: vec![0.0; INIT_SAMPLES],
        }
    }

    /// The settings.
    pub fn params(&self) -> &Params {
        &self.params
    }

    /// Changes the seed source (the threshold grid search of `umbra eval` reuses one segmenter).
    pub fn set_seed_mode(&mut self, mode: SeedMode) {
        self.params.seeds = mode;
    }

    /// The seeds of the last frame (RGB view): [`FG`], [`BG`] or 0 per pixel, after rejection.
    pub fn seeds(&self) -> &[u8] {
        &self.seeds
    }

    /// Segments one frame: `rgb` is the RGB image (640·480·3), `classified` the classifier's
    /// output for the same frame; writes `mask` (640·480, 255 foreground, 0 background).
    pub fn segment(&mut self, rgb: &[u8], classified: &Classified, mask: &mut [u8]) -> Outcome {
        assert!(
            rgb.len() == 3 * PIXELS && mask.len() == PIXELS,
            "a frame is 640x480"
        );
        let labels = &classified.rgb_labels;
        let mm = &classified.registered_mm;
        fill_features(rgb, labels, mm, &mut self.features);
        let mut out = Outcome::default();
        match self.params.seeds {
            SeedMode::Shadow => {
                seeds::shadow_seeds(labels, mm, &self.params.shadow, &mut self.seeds);
                if self.params.clusters > 0 {
                    out.rejected = seeds::reject_by_clusters(
                        &mut self.seeds,
                        &self.features,
                        self.params.clusters,
                        self.params.max_minority,
                        &mut self.cluster,
                    );
                }
                if self.params.planes.max_planes > 0 {
                    seeds::plane_seeds(
                        labels,
                        mm,
                        &self.params.planes,
                        &mut self.seeds,
                        &mut self.plane,
                    );
                }
            }
            SeedMode::Threshold { tf_m, tb_m } => {
                seeds::threshold_seeds(labels, mm, tf_m, tb_m, &mut self.seeds)
            }
        }
        out.fg_seeds = self.seeds.iter().filter(|&&s| s == FG).count();
        out.bg_seeds = self.seeds.iter().filter(|&&s| s == BG).count();
        if out.fg_seeds == 0 {
            // Nothing salient found: an empty mask is the honest answer.
            mask.fill(0);
            return out;
        }
        self.init_mixtures(out.bg_seeds > 0);
        self.smoothness();
        for it in 0..self.params.iterations.max(1) {
            self.cut();
            if it + 1 < self.params.iterations {
                self.refit();
            }
        }
        for (m, &f) in mask.iter_mut().zip(&self.fg_side) {
            *m = if f { 255 } else { 0 };
        }
        out.fg_pixels = self.fg_side.iter().filter(|&&f| f).count();
        out
    }

    /// Fits both mixtures to the seeds (k-means per side for the initial components). Without
    /// background seeds, every unseeded pixel stands in for the background.
    fn init_mixtures(&mut self, have_bg: bool) {
        let k = self.params.components.clamp(1, gmm::MAX_COMPONENTS);
        for side in [FG, BG] {
            let want = |s: u8| {
                if side == BG && !have_bg {
                    s == 0
                } else {
                    s == side
                }
            };
            let n = self.seeds.iter().filter(|&&s| want(s)).count();
            let stride = n.div_ceil(INIT_SAMPLES).max(1);
            self.samples.clear();
            for (j, f) in self
                .seeds
                .iter()
                .zip(&self.features)
                .filter(|(&s, f)| want(s) && f[3] > 0.0)
                .map(|(_, f)| f)
                .enumerate()
            {
                if j % stride == 0 && self.samples.len() < INIT_SAMPLES {
                    self.samples.push(*f);
                }
            }
            let stats = if side == FG {
                &mut self.stats_fg
            } else {
                &mut self.stats_bg
            };
            stats.clear();
            let m = self.samples.len();
            let mut centres = [[0.0f32; 4]; gmm::MAX_COMPONENTS];
            let used = kmeans::kmeans(
                &self.samples,
                &[1.0; 4],
                10,
                &mut centres[..k],
                &mut self.assign[..m],
                &mut self.dist[..m],
            );
            if used > 0 {
                for (&a, p) in self.assign[..m].iter().zip(&self.samples) {
                    stats.add(a as usize, p);
                }
            }
            let g = if side == FG {
                &mut self.fg
            } else {
                &mut self.bg
            };
            g.fit(stats);
        }
    }

    /// Contrast-sensitive smoothness weights of the right and down edges (GrabCut's
    /// `γ·exp(−β‖Δc‖²)`, β from the image's mean contrast), times a depth term where both pixels
    /// have depth, so cuts follow colour and depth edges.
    fn smoothness(&mut self) {
        let f = &self.features;
        let mut sum = 0.0f64;
        let mut count = 0u64;
        for v in 0..HEIGHT {
            for u in 0..WIDTH {
                let p = v * WIDTH + u;
                if u + 1 < WIDTH {
                    sum += f64::from(colour_d2(&f[p], &f[p + 1]));
                    count += 1;
                }
                if v + 1 < HEIGHT {
                    sum += f64::from(colour_d2(&f[p], &f[p + WIDTH]));
                    count += 1;
                }
            }
        }
        let beta = if sum > 0.0 {
            (count as f64 / (2.0 * sum)) as f32
        } else {
            0.0
        };
        let beta_d = 1.0 / (2.0 * self.params.depth_sigma_cm * self.params.depth_sigma_cm);
        let g = self.params.gamma * SCALE;
        let weight = |a: &Point, b: &Point| {
            let mut e = beta * colour_d2(a, b);
            if a[3] > 0.0 && b[3] > 0.0 {
                let d = a[3] - b[3];
                e += beta_d * d * d;
            }
            (g * (-e).exp()).round() as i32
        };
        for v in 0..HEIGHT {
            for u in 0..WIDTH {
                let p = v * WIDTH + u;
                self.right[p] = if u + 1 < WIDTH {
                    weight(&f[p], &f[p + 1])
                } else {
                    0
                };
                self.down[p] = if v + 1 < HEIGHT {
                    weight(&f[p], &f[p + WIDTH])
                } else {
                    0
                };
            }
        }
    }

    /// One graph cut with the current mixtures; seeds are hard constraints, so the mixtures are
    /// only evaluated on unseeded pixels.
    fn cut(&mut self) {
        let flow = &mut self.flow;
        flow.reset(WIDTH, HEIGHT);
        for p in 0..PIXELS {
            match self.seeds[p] {
                FG => flow.set_terminals(p, HARD, 0),
                BG => flow.set_terminals(p, 0, HARD),
                _ => {
                    let x = &self.features[p];
                    let (mut cf, _) = self.fg.cost(x, EMPTY_COST);
                    if x[3] == 0.0 {
                        // No depth: foreground is anything the background does not explain (a
                        // uniform outlier colour model), so black and glossy objects that no seed
                        // reaches stand out against the room's colours.
                        cf = cf.min(UNIFORM_COLOUR_COST);
                    }
                    let (cb, _) = self.bg.cost(x, EMPTY_COST);
                    // Source side = foreground: ending on the sink side costs the bg cost.
                    let d = (cb - cf).clamp(-MAX_COST, MAX_COST);
                    let (src, snk) = if d > 0.0 { (d, 0.0) } else { (0.0, -d) };
                    flow.set_terminals(
                        p,
                        (src * SCALE).round() as i32,
                        (snk * SCALE).round() as i32,
                    );
                }
            }
            if p % WIDTH + 1 < WIDTH {
                flow.set_edge(p, 0, self.right[p], self.right[p]);
            }
            if p + WIDTH < PIXELS {
                flow.set_edge(p, 1, self.down[p], self.down[p]);
            }
        }
        flow.maxflow();
        for (p, f) in self.fg_side.iter_mut().enumerate() {
            *f = flow.is_source(p);
        }
    }

    /// GrabCut's re-estimation: pixels join the best component of their side's mixture, and the
    /// mixtures are refitted. Every other pixel in a checkerboard is enough for the statistics.
    fn refit(&mut self) {
        self.stats_fg.clear();
        self.stats_bg.clear();
        for v in 0..HEIGHT {
            for p in (v * WIDTH + (v & 1)..(v + 1) * WIDTH).step_by(2) {
                let x = &self.features[p];
                if self.fg_side[p] {
                    let (_, k) = self.fg.cost(x, EMPTY_COST);
                    self.stats_fg.add(k as usize, x);
                } else {
                    let (_, k) = self.bg.cost(x, EMPTY_COST);
                    self.stats_bg.add(k as usize, x);
                }
            }
        }
        self.fg.fit(&self.stats_fg);
        self.bg.fit(&self.stats_bg);
    }
}

#[inline]
fn colour_d2(a: &Point, b: &Point) -> f32 {
    let (r, g, bl) = (a[0] - b[0], a[1] - b[1], a[2] - b[2]);
    r * r + g * g + bl * bl
}

/// Per-pixel features (r, g, b, depth cm). Shadow pixels get the depth of the surface they lie
/// on: projector shadows that of the measured pixel on their left (Sa, the background they fall
/// on), alignment shadows that of the pixel on their right. Other holes keep none.
pub fn fill_features(rgb: &[u8], labels: &[u8], mm: &[u16], out: &mut [Point]) {
    for v in 0..HEIGHT {
        let row = v * WIDTH;
        let mut carry = 0.0f32;
        for u in 0..WIDTH {
            let i = row + u;
            let l = labels[i];
            let d = if l == VALID {
                carry = f32::from(mm[i]) / 10.0;
                carry
            } else if l == ATTACHED || l == DETACHED {
                carry
            } else {
                carry = 0.0;
                0.0
            };
            out[i] = [
                f32::from(rgb[3 * i]),
                f32::from(rgb[3 * i + 1]),
                f32::from(rgb[3 * i + 2]),
                d,
            ];
        }
        let mut carry = 0.0f32;
        for u in (0..WIDTH).rev() {
            let i = row + u;
            match labels[i] {
                VALID => carry = out[i][3],
                ALIGNMENT => out[i][3] = carry,
                _ => carry = 0.0,
            }
        }
    }
}
