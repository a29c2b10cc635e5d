//! Attached shadows that fall, in part, on a black surface: OTHER there (SPEC §1: a hole that
//! would be a hole even if lit).
//!
//! From depth a shadow on a black poster, or behind a black rod standing in it, looks like any
//! attached shadow: eq. (3) fits the hole between Sa and Sb. The RGB camera sees the background
//! there in room light, so a shadow on Sa's surface shows Sa's colour, and a black surface shows
//! as one far darker than Sa beside it. Only the part of the hole the RGB camera sees past the
//! occluder is read (it sees the occluder over the hole's right part), at Sa's depth; a dark run
//! that reaches the occluder runs on behind it to the hole's end. A dark Sa is no reference: in
//! a dim room everything is near black (the real NYU frame's shadows along the floor). Nor is Sa
//! always the shadow's surface: past a pale box's edge the shadow may lie on a darker wall
//! behind it, so a run with no lit stretch of the hole before it must be black in itself, and
//! one that reaches the occluder needs a few pixels of Sa's surface before it.

use super::{ColourSplit, SIDE};
use crate::labels::{ATTACHED, NO_DEPTH, OTHER, WIDTH};

/// Brightness (R + G + B) of Sa's side under which the hole is not read.
const LIT_SIDE: i32 = 240;
/// A pixel is dark when Sa's side is this many times as bright as it...
const TIMES_DARKER: i32 = 3;
/// ...and brighter by this much (the camera's noise on a dim side).
const MIN_STEP: i32 = 60;
/// Brightness (R + G + B) under which a run that starts at the hole's first pixel counts: the RGB
/// camera then never sees Sa's surface in the hole, and the shadow may lie on a farther, darker
/// surface than Sa (a dark wall past a pale box's edge) rather than on a black one.
const BLACK: i32 = 120;
/// Shortest dark run (pixels) taken: single pixels are noise or an edge's blend.
const MIN_RUN: usize = 2;
/// Pixels of Sa's surface a run that reaches the occluder needs before it: past a pale box's
/// edge (its blend, two pixels) the shadow may lie on a farther, darker wall.
const LEAD: usize = 4;
/// Widest hole read (pixels): eq. (3) gives more only for an occluder nearer than the sensor's
/// range (about 0.35 m before a far wall).
const WIDEST: usize = 128;
/// RGB columns before the occluder's edge at which the hole stops being read (the edge's blend).
const BEFORE_EDGE: f64 = 1.5;

impl ColourSplit {
    /// Relabels OTHER the pixels of the attached hole `[a, b)` of row `v` that lie on a black
    /// surface (see the module's docs).
    pub(super) fn on_a_dark_surface(
        &self,
        raw: &[u16],
        rgb: &[u8],
        labels: &mut [u8],
        v: usize,
        (a, b): (usize, usize),
    ) {
        let row = v * WIDTH;
        if a < SIDE || b >= WIDTH || b - a <= MIN_RUN || b - a > WIDEST {
            return;
        }
        let (sa, sb) = (raw[row + a - 1], raw[row + b]);
        if sb == NO_DEPTH
            || raw[row + a - SIDE..row + a].contains(&NO_DEPTH)
            || !labels[row + a..row + b].iter().all(|&l| l == ATTACHED)
        {
            return;
        }
        // Sa's side, seen at Sa's depth: the mean of its probes.
        let mut side = 0;
        for u in a - SIDE..a {
            let Some(p) = self.probe(rgb, u, v, sa) else {
                return;
            };
            side += p.iter().sum::<i32>();
        }
        let side = side / SIDE as i32;
        if side < LIT_SIDE {
            return;
        }
        let occluder_x = self.project(b as f64 - 0.5, v, sb).0 - BEFORE_EDGE;
        // Dark pixels of the visible part, a bit per pixel from `a`. Over a hole the projection
        // is linear in the column to well under a pixel: two divisions, not one per pixel.
        let (xa, ya) = self.project(a as f64, v, sa);
        let (xb, yb) = self.project(b as f64, v, sa);
        let span = (b - a) as f64;
        let (dx, dy) = ((xb - xa) / span, (yb - ya) / span);
        let mut dark = 0u128;
        let mut black = 0u128;
        let mut seen = 0;
        for u in a..b {
            let k = (u - a) as f64;
            let (x, y) = (xa + k * dx, ya + k * dy);
            if x > occluder_x {
                break;
            }
            let Some(p) = super::rgb_at(rgb, x, y) else {
                break;
            };
            let c = p.iter().sum::<i32>();
            let d = TIMES_DARKER * c < side && side - c > MIN_STEP;
            dark |= u128::from(d) << (u - a);
            black |= u128::from(d && c < BLACK) << (u - a);
            seen += 1;
        }
        let mut k = 0;
        while k < seen {
            let start = k + (dark >> k).trailing_zeros() as usize;
            if start >= seen {
                break;
            }
            let end = (start + (!(dark >> start)).trailing_zeros() as usize).min(seen);
            // From the hole's first pixel it must be black; on to the occluder, after Sa's
            // surface shown over a few pixels (not an edge's blend).
            let ok = if start == 0 {
                (start..end).all(|j| black >> j & 1 == 1)
            } else {
                end < seen || start >= LEAD
            };
            if end - start >= MIN_RUN && ok {
                let to = if end == seen { b - a } else { end };
                labels[row + a + start..row + a + to].fill(OTHER);
            }
            k = end;
        }
    }
}
