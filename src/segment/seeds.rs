//! Foreground/background seeds: from classified shadows (Deng et al. §4) or, as the paper's
//! baseline, from depth thresholds Tf/Tb.
//!
//! Shadow seeds are derived directly in the RGB view, where the segmentation runs, from the
//! RGB-view labels and the registered depth. The warp carries the projector shadows over with
//! their geometry intact (still left of their occluder, Sa on their left and Sb on their right,
//! only narrower) and alignment shadows exist only there, so one left-to-right scan of each
//! RGB-view row sees all three kinds next to the very pixels the seeds land on. Deriving them in
//! the IR view and mapping each seed through `Warp::target()` would add a reprojection per seed and
//! its rounding at exactly the depth edges seeds sit beside, for nothing the RGB view lacks.
//!
//! Per row and per maximal run of one shadow class bounded by measured pixels:
//! - attached: Sa (left, background) and Sb (right, foreground) must be a real depth edge; fg
//!   seeds a fixed distance inside Sb, bg seeds beyond Sa, each on the same surface as its edge
//!   pixel (depth continuous from it), never across another edge;
//! - detached: the thin occluder Fa..Fb is the first nearer surface right of the shadow across
//!   the lit background strip; fg seeds between Fa and Fb, bg seeds beyond Sa and in the strip;
//! - alignment: foreground on its left, background on its right, as for attached but mirrored.
//!
//! Seeds on the wrong side (the "background" beyond Sa is another object, an occluder that is a
//! partition wall) are then rejected by clustering ([`reject_by_clusters`]).

use super::kmeans::{self, Point};
use crate::labels::{ALIGNMENT, ATTACHED, DETACHED, VALID, WIDTH};

/// Seed code: foreground.
pub const FG: u8 = 1;
/// Seed code: background.
pub const BG: u8 = 2;

/// Geometry of shadow seeds.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SeedParams {
    /// Distance (px) from the edge pixel (Sb, Sa, F, B) to the first seed: clears mixed pixels
    /// and the one-pixel misregistration of colour and depth edges.
    pub inset_px: usize,
    /// Seeds per edge and row.
    pub len_px: usize,
    /// Smallest inverse-depth step (1/m) between the two sides of a shadow for it to mark an
    /// object edge (0.04 m⁻¹ ≈ 1.7 px of IR disparity).
    pub min_step_inv_m: f32,
    /// Farthest (px) a detached shadow's thin occluder is looked for to its right.
    pub max_gap_px: usize,
}

impl Default for SeedParams {
    fn default() -> Self {
        SeedParams {
            inset_px: 3,
            len_px: 10,
            min_step_inv_m: 0.04,
            max_gap_px: 40,
        }
    }
}

/// Two neighbouring measured pixels lie on one surface: depths (mm) within 1.5 cm + 2 %.
#[inline]
fn same_surface(a: u16, b: u16) -> bool {
    let (a, b) = (i32::from(a), i32::from(b));
    (a - b).abs() <= 15 + a.max(b) / 50
}

/// `near` is in front of `far` by a depth edge.
#[inline]
fn in_front(near: u16, far: u16, p: &SeedParams) -> bool {
    near > 0 && far > 0 && 1000.0 / f32::from(near) - 1000.0 / f32::from(far) >= p.min_step_inv_m
}

/// Marks seeds walking from edge pixel `edge` in direction `step` (±1) along row `row`, on the
/// edge's surface: offsets `inset..inset + len`. Stops at a hole or a depth discontinuity.
#[allow(clippy::too_many_arguments)] // one row's slices and one walk's geometry; a struct would only rename them
fn walk(
    labels: &[u8],
    mm: &[u16],
    row: usize,
    edge: usize,
    step: isize,
    inset: usize,
    len: usize,
    code: u8,
    seeds: &mut [u8],
) {
    let mut prev = mm[row + edge];
    for j in 1..inset + len {
        let x = edge as isize + step * j as isize;
        if x < 0 || x >= WIDTH as isize {
            break;
        }
        let i = row + x as usize;
        if labels[i] != VALID || !same_surface(prev, mm[i]) {
            break;
        }
        prev = mm[i];
        if j >= inset {
            seeds[i] |= code;
        }
    }
}

/// Shadow seeds of one frame (RGB view): `seeds` gets [`FG`], [`BG`] or 0 per pixel.
pub fn shadow_seeds(labels: &[u8], mm: &[u16], p: &SeedParams, seeds: &mut [u8]) {
    seeds.fill(0);
    for row in (0..labels.len()).step_by(WIDTH) {
        let l = &labels[row..row + WIDTH];
        let mut a = 0;
        while a < WIDTH {
            let class = l[a];
            if class == VALID {
                a += 1;
                continue;
            }
            let mut b = a;
            while b < WIDTH && l[b] == class {
                b += 1;
            }
            // The run [a, b) must be bounded by measured pixels on both sides.
            if a > 0 && b < WIDTH && l[a - 1] == VALID && l[b] == VALID {
                let (left, right) = (a - 1, b);
                let (zl, zr) = (mm[row + left], mm[row + right]);
                match class {
                    ATTACHED if in_front(zr, zl, p) => {
                        walk(labels, mm, row, right, 1, p.inset_px, p.len_px, FG, seeds);
                        walk(labels, mm, row, left, -1, p.inset_px, p.len_px, BG, seeds);
                    }
                    ALIGNMENT if in_front(zl, zr, p) => {
                        walk(labels, mm, row, left, -1, p.inset_px, p.len_px, FG, seeds);
                        walk(labels, mm, row, right, 1, p.inset_px, p.len_px, BG, seeds);
                    }
                    DETACHED => detached(l, &mm[row..row + WIDTH], row, left, right, p, seeds),
                    _ => {}
                }
            }
            a = b;
        }
    }
    for s in seeds.iter_mut() {
        if *s == FG | BG {
            *s = 0; // claimed by both sides: no seed
        }
    }
}

/// Seeds of one detached shadow whose run ends at `left` (Sa) and `right` (first lit pixel).
fn detached(
    l: &[u8],
    mm: &[u16],
    row: usize,
    sa: usize,
    right: usize,
    p: &SeedParams,
    seeds: &mut [u8],
) {
    // Cross the lit background strip to the thin occluder's left edge Fa.
    let mut x = right;
    let fa = loop {
        if x + 1 >= WIDTH || x + 1 - right > p.max_gap_px || l[x + 1] != VALID {
            return;
        }
        if in_front(mm[x + 1], mm[x], p) {
            break x + 1;
        }
        if !same_surface(mm[x], mm[x + 1]) {
            return;
        }
        x += 1;
    };
    // The strip must be background like Sa, not a nearer surface.
    if in_front(mm[right], mm[sa], p) {
        return;
    }
    let mut fb = fa;
    while fb + 1 < WIDTH && l[fb + 1] == VALID && same_surface(mm[fb], mm[fb + 1]) {
        fb += 1;
    }
    // A thin occluder ends in a step back to something farther (or a hole, its alignment shadow).
    if fb + 1 < WIDTH && l[fb + 1] == VALID && !in_front(mm[fb], mm[fb + 1], p) {
        return;
    }
    let trim = usize::from(fb - fa >= 4);
    for u in fa + trim..=fb - trim {
        seeds[row + u] |= FG;
    }
    // Background: beyond Sa, and the inside of the lit strip.
    for u in right + 1..fa.saturating_sub(1) {
        seeds[row + u] |= BG;
    }
    let mut prev = mm[sa];
    for j in 1..p.inset_px + p.len_px {
        let Some(u) = sa.checked_sub(j) else { break };
        if l[u] != VALID || !same_surface(prev, mm[u]) {
            break;
        }
        prev = mm[u];
        if j >= p.inset_px {
            seeds[row + u] |= BG;
        }
    }
}

/// The paper's baseline: every measured pixel nearer than `tf_m` is foreground, every one farther
/// than `tb_m` background.
pub fn threshold_seeds(labels: &[u8], mm: &[u16], tf_m: f32, tb_m: f32, seeds: &mut [u8]) {
    let (tf, tb) = ((tf_m * 1000.0) as u32, (tb_m * 1000.0) as u32);
    for ((s, &l), &z) in seeds.iter_mut().zip(labels).zip(mm) {
        let z = u32::from(z);
        *s = if l != VALID || z == 0 {
            0
        } else if z < tf {
            FG
        } else if z > tb {
            BG
        } else {
            0
        };
    }
}

/// Scratch for [`reject_by_clusters`], allocated once.
#[derive(Clone, Debug, Default)]
pub struct ClusterScratch {
    index: Vec<u32>,
    points: Vec<Point>,
    assign: Vec<u8>,
    dist: Vec<f32>,
}

/// Rejects wrong seeds by clustering (the paper's k-means on depth and colour): seeds of both
/// sides are clustered together; a cluster is one surface kind, so in a cluster that both sides
/// claim the minority is wrong. A cluster whose minority exceeds `max_minority` is ambiguous (a
/// far object that is "background" beyond one shadow and "foreground" inside its own) and loses
/// all its seeds. Returns the number of seeds rejected.
pub fn reject_by_clusters(
    seeds: &mut [u8],
    features: &[Point],
    clusters: usize,
    max_minority: f32,
    s: &mut ClusterScratch,
) -> usize {
    s.index.clear();
    s.points.clear();
    for (i, (&seed, f)) in seeds.iter().zip(features).enumerate() {
        if seed != 0 && f[3] > 0.0 {
            s.index.push(i as u32);
            s.points.push(*f);
        }
    }
    let n = s.points.len();
    if n < 2 * clusters {
        return 0;
    }
    s.assign.resize(n, 0);
    s.dist.resize(n, 0.0);
    // Depth in cm against colour in 8-bit units: 10 cm of depth weigh like 10 levels of colour.
    let weights = [1.0, 1.0, 1.0, 1.0];
    let mut centres = [[0.0f32; 4]; 32];
    kmeans::kmeans(
        &s.points,
        &weights,
        15,
        &mut centres[..clusters.min(32)],
        &mut s.assign,
        &mut s.dist,
    );
    let mut votes = [[0u32; 2]; 32];
    for (&a, &i) in s.assign.iter().zip(&s.index) {
        votes[a as usize][usize::from(seeds[i as usize] == BG)] += 1;
    }
    let mut rejected = 0;
    for (&a, &i) in s.assign.iter().zip(&s.index) {
        let [f, b] = votes[a as usize];
        let minority = f.min(b) as f32 / (f + b) as f32;
        let majority = if f >= b { FG } else { BG };
        let seed = &mut seeds[i as usize];
        if minority > max_minority || *seed != majority {
            *seed = 0;
            rejected += 1;
        }
    }
    rejected
}

/// Room-surface planes found by [`plane_seeds`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PlaneParams {
    /// Planes looked for at most.
    pub max_planes: usize,
    /// Smallest share of the measured pixels a plane must hold to be a room surface.
    pub min_share: f32,
    /// Inlier tolerance in inverse depth (1/m); the Kinect's raw noise is about 0.0015 1/m there.
    pub tol_inv_m: f32,
    /// Largest share of foreground among the shadow seeds on a plane.
    pub max_fg_share: f32,
    /// Fewest background shadow seeds a plane must hold.
    pub min_bg_seeds: usize,
    /// RANSAC hypotheses per plane.
    pub hypotheses: usize,
}

impl Default for PlaneParams {
    fn default() -> Self {
        PlaneParams {
            max_planes: 4,
            min_share: 0.06,
            tol_inv_m: 0.005,
            max_fg_share: 0.02,
            min_bg_seeds: 10,
            hypotheses: 150,
        }
    }
}

/// Scratch for [`plane_seeds`], allocated once.
#[derive(Clone, Debug, Default)]
pub struct PlaneScratch {
    /// Subsampled measured pixels: u, v, inverse depth (1/m).
    samples: Vec<[f32; 3]>,
}

/// Grows background seeds over the room's surfaces: the background beyond Sa is a wall or a
/// floor, and a wall or floor is a large plane. Planes are found by RANSAC in (u, v, 1/z) space
/// (a 3-D plane is linear in inverse depth, so no calibration is needed); one counts as a room
/// surface only if it is large, holds background shadow seeds and (almost) no foreground ones.
/// Its measured pixels then become background seeds, its foreground seeds are dropped. This also
/// reaches floor and wall parts no shadow touches (the floor before an object). Returns the
/// number of planes used.
pub fn plane_seeds(
    labels: &[u8],
    mm: &[u16],
    p: &PlaneParams,
    seeds: &mut [u8],
    s: &mut PlaneScratch,
) -> usize {
    const STRIDE: usize = 4;
    s.samples.clear();
    for v in (0..labels.len() / WIDTH).step_by(STRIDE) {
        for u in (0..WIDTH).step_by(STRIDE) {
            let i = v * WIDTH + u;
            if labels[i] == VALID && mm[i] > 0 {
                s.samples
                    .push([u as f32, v as f32, 1000.0 / f32::from(mm[i])]);
            }
        }
    }
    let total = s.samples.len();
    let mut rng = 0x2545_f491u32;
    let mut planes = 0;
    for _ in 0..p.max_planes {
        let n = s.samples.len();
        if n < 3 || (n as f32) < p.min_share * total as f32 {
            break;
        }
        let mut best: Option<([f32; 3], usize)> = None;
        for _ in 0..p.hypotheses {
            let pick = |rng: &mut u32| s.samples[(next(rng) as usize) % n];
            let (a, b, c) = (pick(&mut rng), pick(&mut rng), pick(&mut rng));
            let Some(pl) = plane_through(&a, &b, &c) else {
                continue;
            };
            let count = s
                .samples
                .iter()
                .filter(|x| (x[2] - eval(&pl, x[0], x[1])).abs() < p.tol_inv_m)
                .count();
            if best.is_none_or_smaller(count) {
                best = Some((pl, count));
            }
        }
        let Some((pl, count)) = best else { break };
        if (count as f32) < p.min_share * total as f32 {
            break;
        }
        let on = |i: usize| {
            labels[i] == VALID && mm[i] > 0 && {
                let (u, v) = ((i % WIDTH) as f32, (i / WIDTH) as f32);
                (1000.0 / f32::from(mm[i]) - eval(&pl, u, v)).abs() < p.tol_inv_m
            }
        };
        let (mut fg, mut bg) = (0usize, 0usize);
        for (i, &sd) in seeds.iter().enumerate() {
            if sd != 0 && on(i) {
                if sd == FG {
                    fg += 1;
                } else {
                    bg += 1;
                }
            }
        }
        // Whatever the verdict, this plane's samples are done with.
        s.samples
            .retain(|x| (x[2] - eval(&pl, x[0], x[1])).abs() >= p.tol_inv_m);
        if bg < p.min_bg_seeds || fg as f32 > p.max_fg_share * (fg + bg) as f32 {
            continue;
        }
        for (i, sd) in seeds.iter_mut().enumerate() {
            if on(i) {
                *sd = BG;
            }
        }
        planes += 1;
    }
    planes
}

/// `None`-or-fewer test for the RANSAC best so far.
trait BestCount {
    fn is_none_or_smaller(&self, count: usize) -> bool;
}

impl BestCount for Option<([f32; 3], usize)> {
    fn is_none_or_smaller(&self, count: usize) -> bool {
        self.is_none_or(|(_, c)| count > c)
    }
}

/// Inverse depth of plane `pl` at pixel (u, v): `a·u + b·v + c`.
#[inline]
fn eval(pl: &[f32; 3], u: f32, v: f32) -> f32 {
    pl[0] * u + pl[1] * v + pl[2]
}

/// The plane `iz = a·u + b·v + c` through three samples; `None` if they are (nearly) collinear.
fn plane_through(p: &[f32; 3], q: &[f32; 3], r: &[f32; 3]) -> Option<[f32; 3]> {
    let (du1, dv1, dz1) = (q[0] - p[0], q[1] - p[1], q[2] - p[2]);
    let (du2, dv2, dz2) = (r[0] - p[0], r[1] - p[1], r[2] - p[2]);
    let det = du1 * dv2 - du2 * dv1;
    if det.abs() < 100.0 {
        return None; // the three pixels span less than a 10×10 px triangle's worth
    }
    let a = (dz1 * dv2 - dz2 * dv1) / det;
    let b = (du1 * dz2 - du2 * dz1) / det;
    Some([a, b, p[2] - a * p[0] - b * p[1]])
}

/// xorshift32 for the RANSAC draws (deterministic).
fn next(state: &mut u32) -> u32 {
    *state ^= *state << 13;
    *state ^= *state >> 17;
    *state ^= *state << 5;
    *state
}
