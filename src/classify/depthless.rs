//! Attached shadows of occluders that return no depth (black, glossy), split off by colour.
//!
//! Such an occluder and its attached shadow form one hole with the same background on both sides,
//! so depth alone calls it all OTHER. The RGB camera still sees both: the shadow is background
//! (lit by the room, only not by the projector), the occluder is whatever colour it is. For a
//! shadow width `s` the occluder's disparity is `disp(background) + s` (eq. 3), which fixes where
//! it appears in the RGB image: along the hole's row the RGB camera must see background, then
//! the occluder, then background again (the strip the occluder hides from the IR camera). The
//! split is the `s` whose layout matches the colours; it must clearly beat "no shadow at all" (a
//! black poster) and agree with the rows above and below, because an occluder is a solid.
//!
//! Runs on candidate holes only (OTHER, at least [`MIN_HOLE`] wide, one background on both
//! sides), after the scanline and before the warp; nothing is allocated.

use crate::calib::Calibration;
use crate::labels::{ATTACHED, HEIGHT, NO_DEPTH, OTHER, WIDTH};

/// Narrowest merged hole considered (pixels): a shadow and an occluder of 3 px each.
const MIN_HOLE: usize = 6;
/// Background samples taken on each side of the hole (IR pixels).
const SIDE: usize = 4;
/// Colour distance (sum of |ΔR|+|ΔG|+|ΔB|) beyond which an RGB pixel is not background.
const COLOUR_STEP: u32 = 60;
/// The two sides' background colours may differ by at most this much.
const SIDES_AGREE: u32 = 45;
/// Valid runs this short inside a hole are noise, stepped over.
const MAX_ISLAND: usize = 2;
/// Shadow widths of neighbouring rows may differ by this much (pixels).
const ROWS_AGREE: usize = 3;

/// Per-calibration constants for the colour split.
#[derive(Clone, Debug)]
pub struct ColourSplit {
    /// Disparity pixels per raw unit, and the raw value of zero disparity.
    k: f64,
    den: f64,
    /// Inverse depth per raw unit (`iz = (den − raw)·iz_per_raw`).
    iz_per_raw: f64,
    /// Largest disparity of a surface the sensor can measure (about 0.4 m).
    max_disp: f64,
    /// `R · K_depth⁻¹ · (0, v, 1)` per row, `R · K_depth⁻¹ · (1, 0, 0)`, and `t`: the ray of a
    /// pixel in the RGB camera's frame is `row_ray[v] + u·col_step + t·iz`.
    row_ray: Vec<[f64; 3]>,
    col_step: [f64; 3],
    t: [f64; 3],
    /// RGB focal lengths and principal point.
    rgb_f: [f64; 2],
    rgb_c: [f64; 2],
}

/// How well one shadow width explains the RGB row under a hole.
#[derive(Clone, Copy, Debug, Default)]
struct Layout {
    /// RGB columns whose colour matches the layout (background or not).
    hits: usize,
    /// RGB columns the layout calls shadow (background left of the occluder) and their summed
    /// colour distance from the background.
    shadow_cols: usize,
    shadow_sum: u32,
    /// The same for the occluder's columns.
    occluder_cols: usize,
    occluder_sum: u32,
}

/// A merged hole `[a, b)` of one row and its background's raw value.
#[derive(Clone, Copy, Debug)]
struct Candidate {
    a: usize,
    b: usize,
    bg: u16,
}

impl ColourSplit {
    /// Constants for `calib`.
    pub fn new(calib: &Calibration) -> Self {
        let d = calib.depth;
        let r = calib.depth_to_rgb.rotation;
        let rot = |x: f64, y: f64, z: f64| {
            let v = r * nalgebra::Vector3::new(x, y, z);
            [v.x, v.y, v.z]
        };
        let t = calib.depth_to_rgb.translation;
        ColourSplit {
            k: calib.px_per_raw(),
            den: calib.raw.denominator,
            iz_per_raw: 1.0 / calib.raw.numerator,
            max_disp: calib.fb() / 0.4,
            row_ray: (0..HEIGHT)
                .map(|v| rot(-d.cx / d.fx, (v as f64 - d.cy) / d.fy, 1.0))
                .collect(),
            col_step: rot(1.0 / d.fx, 0.0, 0.0),
            t: [t.x, t.y, t.z],
            rgb_f: [calib.rgb.fx, calib.rgb.fy],
            rgb_c: [calib.rgb.cx, calib.rgb.cy],
        }
    }

    /// Splits merged holes of frame `raw` (IR view) using the RGB image `rgb` (RGB8, 640·480):
    /// the shadow part becomes ATTACHED in `labels`, and the occluder part of `filled` is set to
    /// the raw value its shadow implies, so the warp puts it where it stands.
    pub fn apply(&self, raw: &[u16], rgb: &[u8], labels: &mut [u8], filled: &mut [u16]) {
        for v in 1..HEIGHT - 1 {
            let row = &raw[v * WIDTH..(v + 1) * WIDTH];
            let mut u = SIDE;
            while u < WIDTH - SIDE {
                // Valid stretches 16 pixels at a time (branch-free test, vectorised).
                if u + 16 <= WIDTH
                    && !row[u..u + 16]
                        .iter()
                        .fold(false, |any, &r| any | (r == NO_DEPTH))
                {
                    u += 16;
                    continue;
                }
                let i = v * WIDTH + u;
                if raw[i] != NO_DEPTH {
                    u += 1;
                    continue;
                }
                // Each hole is visited once: from its first pixel, on to its end.
                let (_, b) = hole_span(row, u);
                if labels[i] != OTHER || raw[i - 1] == NO_DEPTH {
                    u = b.max(u + 1);
                    continue;
                }
                if let Some(c) = self.candidate(raw, labels, v, u, b, false) {
                    if let Some(s) = self.agreed_split(raw, rgb, labels, v, c) {
                        let at = self.raw_at_disp(self.disp(c.bg) + s as f64);
                        for u in c.a..c.b {
                            let i = v * WIDTH + u;
                            // Islands inside keep their label; the occluder's pixels its depth.
                            if raw[i] == NO_DEPTH && u < c.a + s {
                                labels[i] = ATTACHED;
                            } else if u >= c.a + s {
                                filled[i] = at;
                            }
                        }
                    }
                }
                u = b.max(u + 1);
            }
        }
    }

    fn disp(&self, raw: u16) -> f64 {
        self.k * (self.den - f64::from(raw))
    }

    fn raw_at_disp(&self, d: f64) -> u16 {
        (self.den - d / self.k)
            .round()
            .clamp(0.0, f64::from(NO_DEPTH - 1)) as u16
    }

    /// The hole `[a, b)` of row `v` as a candidate: all OTHER (or, in a row already split, OTHER
    /// and ATTACHED), wide enough, inside the image, with measured pixels of one background
    /// (within 2 px of disparity) on both sides.
    fn candidate(
        &self,
        raw: &[u16],
        labels: &[u8],
        v: usize,
        a: usize,
        b: usize,
        split_already: bool,
    ) -> Option<Candidate> {
        let row = v * WIDTH;
        // Inside the image with room to sample both sides (a hole off the right border is as
        // often the sensor's dead band there as an occluder straddling it).
        if a < SIDE || b + SIDE > WIDTH || b - a < MIN_HOLE {
            return None;
        }
        let allowed = |l: u8| l == OTHER || (split_already && l == ATTACHED);
        let holes = labels[row + a..row + b].iter().zip(&raw[row + a..row + b]);
        if !holes
            .filter(|(_, &r)| r == NO_DEPTH)
            .all(|(&l, _)| allowed(l))
        {
            return None;
        }
        let (left, right) = (raw[row + a - 1], raw[row + b]);
        if (self.disp(left) - self.disp(right)).abs() > 2.0 {
            return None;
        }
        Some(Candidate {
            a,
            b,
            bg: left.max(right),
        })
    }

    /// The split of candidate `c` in row `v`, if the rows above and below agree.
    fn agreed_split(
        &self,
        raw: &[u16],
        rgb: &[u8],
        labels: &[u8],
        v: usize,
        c: Candidate,
    ) -> Option<usize> {
        // Depth first (the raw rows are in cache, the RGB image often is not): the rows above and
        // below must hold a candidate hole through the same middle column.
        let mid = (c.a + c.b) / 2;
        let neighbour = |w: usize| {
            let row = &raw[w * WIDTH..(w + 1) * WIDTH];
            if row[mid] != NO_DEPTH {
                return None;
            }
            let (a, b) = hole_span(row, mid);
            self.candidate(raw, labels, w, a, b, w < v)
        };
        let (above, below) = (neighbour(v - 1)?, neighbour(v + 1)?);
        let s = self.split(rgb, v, c)?;
        let agrees = |w: usize, n: Candidate| {
            self.split(rgb, w, n)
                .is_some_and(|t| t.abs_diff(s) <= ROWS_AGREE)
        };
        (agrees(v - 1, above) && agrees(v + 1, below)).then_some(s)
    }

    /// RGB column and row of IR pixel (`u`, `v`) at raw value `raw` (one division).
    fn project(&self, u: f64, v: usize, raw: u16) -> (f64, f64) {
        let iz = (self.den - f64::from(raw)) * self.iz_per_raw;
        let n: [f64; 3] =
            std::array::from_fn(|k| self.row_ray[v][k] + u * self.col_step[k] + self.t[k] * iz);
        let inv = 1.0 / n[2];
        (
            self.rgb_f[0] * n[0] * inv + self.rgb_c[0],
            self.rgb_f[1] * n[1] * inv + self.rgb_c[1],
        )
    }

    /// The shadow width whose layout (background, occluder, background) best explains the RGB row
    /// under the hole, when it explains nearly all of it and clearly better than no shadow.
    fn split(&self, rgb: &[u8], v: usize, c: Candidate) -> Option<usize> {
        let colour = |x: f64, y: f64| -> Option<[i32; 3]> {
            let (x, y) = (x.round(), y.round());
            if x < 0.0 || y < 0.0 || x >= WIDTH as f64 || y >= HEIGHT as f64 {
                return None;
            }
            let i = 3 * (y as usize * WIDTH + x as usize);
            Some([rgb[i].into(), rgb[i + 1].into(), rgb[i + 2].into()])
        };
        let dist =
            |p: [i32; 3], q: [i32; 3]| p.iter().zip(&q).map(|(a, b)| a.abs_diff(*b)).sum::<u32>();
        // Background colour: the mean of each side, which must agree.
        let side = |us: std::ops::Range<usize>| -> Option<[i32; 3]> {
            let mut sum = [0i32; 3];
            for u in us.clone() {
                let (x, y) = self.project(u as f64, v, c.bg);
                let p = colour(x, y)?;
                for k in 0..3 {
                    sum[k] += p[k];
                }
            }
            let n = us.len() as i32;
            Some(sum.map(|s| s / n))
        };
        // Cheap probes first (most holes of a real frame fail here): the hole's first pixel must
        // look like the background beside it, and its middle or right half like something else.
        let probe = |u: usize| {
            let (x, y) = self.project(u as f64, v, c.bg);
            colour(x, y)
        };
        let beside = probe(c.a - 2)?;
        if dist(probe(c.b + 1)?, beside) > SIDES_AGREE
            || dist(probe(c.a)?, beside) >= COLOUR_STEP
            || (dist(probe((c.a + c.b) / 2)?, beside) < COLOUR_STEP
                && dist(probe((c.a + 3 * c.b) / 4)?, beside) < COLOUR_STEP)
        {
            return None;
        }
        let left = side(c.a - SIDE..c.a)?;
        let right = side(c.b..c.b + SIDE)?;
        if dist(left, right) > SIDES_AGREE {
            return None;
        }
        let bg: [i32; 3] = std::array::from_fn(|k| (left[k] + right[k]) / 2);
        // The RGB columns the hole covers at the background's depth, and which are background.
        let (x0, y) = self.project(c.a as f64 - 0.5, v, c.bg);
        let (x1, _) = self.project(c.b as f64 - 0.5, v, c.bg);
        let (x0, x1) = (x0.ceil() as i64, x1.ceil() as i64);
        if x0 < 0 || x1 > WIDTH as i64 || x1 - x0 < MIN_HOLE as i64 - 1 {
            return None;
        }
        // Prefix sums over the RGB columns from x0: background columns, and colour distance, so
        // each layout scores in constant time.
        let n = (x1 - x0) as usize;
        let (mut bg_count, mut dist_sum) = ([0u32; WIDTH + 1], [0u32; WIDTH + 1]);
        for k in 0..n {
            let dx = dist(colour((x0 + k as i64) as f64, y)?, bg);
            bg_count[k + 1] = bg_count[k] + u32::from(dx < COLOUR_STEP);
            dist_sum[k + 1] = dist_sum[k] + dx;
        }
        // Score of a layout: RGB columns it explains, and the colour distance of the columns it
        // calls shadow and occluder. Shadow width s puts the occluder at disparity disp(bg) + s,
        // covering RGB columns [xo0, xo1).
        let d_bg = self.disp(c.bg);
        let score = |s: usize| -> Layout {
            let at = self.raw_at_disp(d_bg + s as f64);
            let xo0 = self.project(c.a as f64 + s as f64 - 0.5, v, at).0.ceil() as i64;
            let xo1 = self.project(c.b as f64 - 0.5, v, at).0.ceil() as i64;
            let (o0, o1) = (
                (xo0 - x0).clamp(0, n as i64) as usize,
                (xo1 - x0).clamp(0, n as i64) as usize,
            );
            let o1 = o1.max(o0);
            let occluder_cols = o1 - o0;
            let occluder_bg = (bg_count[o1] - bg_count[o0]) as usize;
            let outside_bg = bg_count[n] as usize - occluder_bg;
            Layout {
                hits: outside_bg + occluder_cols - occluder_bg,
                shadow_cols: o0,
                shadow_sum: dist_sum[o0],
                occluder_cols,
                occluder_sum: dist_sum[o1] - dist_sum[o0],
            }
        };
        let width = c.b - c.a;
        let no_shadow = score(0).hits;
        let mut best: Option<(Layout, usize)> = None;
        for s in 3..=width - 3 {
            if d_bg + s as f64 > self.max_disp {
                break;
            }
            let l = score(s);
            if best.is_none_or(|(b, _)| l.hits > b.hits) {
                best = Some((l, s));
            }
        }
        let (l, s) = best?;
        // Nearly every column explained, clearly better than no shadow; the shadow's columns are
        // plainly background and the occluder's plainly not (a pale poster on a white wall is
        // neither).
        let clear = l.shadow_cols >= 2
            && l.occluder_cols >= 2
            && 2 * l.shadow_sum <= COLOUR_STEP * l.shadow_cols as u32
            && l.occluder_sum >= 2 * COLOUR_STEP * l.occluder_cols as u32;
        (clear && 10 * l.hits >= 9 * n && l.hits >= no_shadow + l.shadow_cols / 2 + 2).then_some(s)
    }
}

/// The hole through column `u` of `row` (a hole pixel), stepping over valid islands of up to
/// [`MAX_ISLAND`] pixels (speckle, spurious returns inside a shadow): `[a, b)`.
fn hole_span(row: &[u16], u: usize) -> (usize, usize) {
    let run_end = |from: usize| {
        row[from..]
            .iter()
            .position(|&r| r != NO_DEPTH)
            .map_or(row.len(), |k| from + k)
    };
    let run_start = |to: usize| {
        row[..to]
            .iter()
            .rposition(|&r| r != NO_DEPTH)
            .map_or(0, |k| k + 1)
    };
    let mut b = run_end(u);
    while b < row.len() {
        let island = row[b..]
            .iter()
            .take(MAX_ISLAND + 1)
            .take_while(|&&r| r != NO_DEPTH)
            .count();
        if island > MAX_ISLAND || b + island >= row.len() {
            break;
        }
        b = run_end(b + island);
    }
    let mut a = run_start(u);
    while a > 0 {
        let island = row[..a]
            .iter()
            .rev()
            .take(MAX_ISLAND + 1)
            .take_while(|&&r| r != NO_DEPTH)
            .count();
        if island > MAX_ISLAND || island >= a {
            break;
        }
        a = run_start(a - island);
    }
    (a, b)
}
