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
        SeedParams { inset_px: 3, len_px: 10, min_step_inv_m: 0.04, max_gap_px: 40 }
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
fn walk(labels: &[u8], mm: &[u16], row: usize, edge: usize, step: isize, inset: usize, len: usize, code: u8, seeds: &mut [u8]) {
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
fn detached(l: &[u8], mm: &[u16], row: usize, sa: usize, right: usize, p: &SeedParams, seeds: &mut [u8]) {
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
pub fn reject_by_clusters(seeds: &mut [u8], features: &[Point], clusters: usize, max_minority: f32, s: &mut ClusterScratch) -> usize {
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
    kmeans::kmeans(&s.points, &weights, 15, &mut centres[..clusters.min(32)], &mut s.assign, &mut s.dist);
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
