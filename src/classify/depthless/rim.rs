//! A near object's depthless rim inside its attached shadow's hole, the two too wide for eq. (3).
//!
//! A glossy or curved object returns no depth where its surface turns away from the camera: a
//! pole's rim, a figure's limbs. On the object's left side the rim joins the attached shadow in
//! one hole, bounded by the background on the left (Sa) and the object's measured middle on the
//! right (Sb). Eq. (3) from Sa and Sb gives the shadow's width, but the hole is the shadow and the
//! rim, wider than the scanline's tolerance: it left the whole hole OTHER, and so did the colour
//! split where the wall behind is patterned (no one colour to tell the shadow by).
//!
//! The RGB camera sees the rim as the object: read at Sb's depth, the columns from the hole's
//! right end leftwards show the object's colour up to its edge, and the wall's or anything else
//! beyond. Where those columns end just where eq. (3) says the shadow does, counted from the
//! hole's left end, the hole is read as the shadow and the rim: the shadow ATTACHED, the rim OTHER
//! at the object's depth. The colour is asked only of the object (its pixels right of the hole,
//! a rim shaded darker still has its hue), the width only of eq. (3): a patterned wall may show
//! any colour in the shadow's part, but the object's colour ending at eq. (3)'s width by chance
//! is rare. Rarer still in two rows: the row above or below must read its rim's start within
//! [`AGREE`] pixels. Nor may the shadow's part show the object (a black box, depthless but for a
//! patch, is the object throughout).
//!
//! (The seventh simulator, whose glossy objects return depth only near their middles: complex IR
//! attached F1 +0.018 summed over six suites, any-shadow recall +0.029, precision −0.004, RGB
//! alignment +0.013; on two suites made afterwards attached +0.003, recall +0.006, precision
//! −0.0004. This project's suites and the real frame unchanged.)

use super::face::RimColours;
use super::{hole_span, relabel, ColourSplit, COLOUR_STEP, SIDE};
use crate::classify::scanline::{beyond_range_span, Range};
use crate::labels::{ATTACHED, HEIGHT, NO_DEPTH, OTHER, WIDTH};

/// Columns at the hole's right end not read: the lens blends the object's edge into them.
const BLEND: usize = 1;
/// Fewest columns of rim that must show the object (past the blend).
const MIN_RIM: usize = 3;
/// Pixels by which the shadow's part may differ from eq. (3)'s width (with the sensor's
/// widening): the rim's first pixel and the shadow's last blend, and the object's edge is a
/// little farther than its measured middle.
const FIT: f64 = 3.0;
/// Columns not showing the object, one after another, at which the rim is taken to end.
const GAP: usize = 2;
/// Pixels left of the hole over which the background's slope is read.
const SLOPE_RUN: usize = 10;
/// Steepest background slope carried over the shadow (pixels of disparity per pixel).
const MAX_SLOPE: f64 = 0.5;
/// Pixels by which the rim's start may move from row to row (a slanted edge).
const AGREE: usize = 2;

impl ColourSplit {
    /// Labels the left part of the OTHER hole `[a, b)` of row `v` attached and gives the rest
    /// Sb's depth in `filled` where the RGB camera shows it as a near object's rim, and the row
    /// above or below reads its rim starting within [`AGREE`] pixels (see the module's docs),
    /// and most of the shadow lies on a background within the frame's `range`; returns whether
    /// it did.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn rim_of_near_object(
        &self,
        raw: &[u16],
        rgb: &[u8],
        labels: &mut [u8],
        filled: &mut [u16],
        v: usize,
        (a, b): (usize, usize),
        range: Range,
    ) -> bool {
        let row = v * WIDTH;
        if v == 0 || v + 1 >= HEIGHT {
            return false;
        }
        let Some(start) = self.rim_start(raw, rgb, v, (a, b)) else {
            return false;
        };
        if labels[row + a..row + b].iter().any(|&l| l != OTHER) {
            return false;
        }
        // One row's colours may end a run of the object's anywhere; an edge runs on.
        let agrees = |w: usize| {
            let line = &raw[w * WIDTH..(w + 1) * WIDTH];
            (start.saturating_sub(AGREE)..=start + AGREE)
                .find(|&u| u < WIDTH && line[u] == NO_DEPTH)
                .map(|u| hole_span(&self.masks[w], line, u))
                .and_then(|span| self.rim_start(raw, rgb, w, span))
                .is_some_and(|s| s.abs_diff(start) <= AGREE)
        };
        if !agrees(v - 1) && !agrees(v + 1) {
            return false;
        }
        // Islands inside keep their label and depth.
        let holes = |r: std::ops::Range<usize>| r.filter(|&u| raw[row + u] == NO_DEPTH);
        for u in holes(a..start) {
            labels[row + u] = ATTACHED;
        }
        // A background receding past the range under the shadow would be a hole anyway: no
        // shadow there, and what ended it was no rim (a gap onto a wall beyond the range).
        let (done, rest) = labels.split_at_mut(row);
        let line = &mut rest[..WIDTH];
        beyond_range_span(
            &raw[row..row + WIDTH],
            (a, start),
            range,
            &done[row - WIDTH..],
            line,
        );
        let span = &mut line[a..start];
        let out = span.iter().filter(|&&l| l == OTHER).count();
        if out > span.len() - out {
            relabel(span, ATTACHED, OTHER);
            return false;
        }
        for u in holes(start..b) {
            filled[row + u] = raw[row + b];
        }
        true
    }

    /// Where the near object's rim starts in the hole `[a, b)` of row `v` (Sa left of it, Sb,
    /// nearer, right of it), if the RGB camera shows one there and the part left of it fits
    /// eq. (3) as Sb's attached shadow.
    fn rim_start(
        &self,
        raw: &[u16],
        rgb: &[u8],
        v: usize,
        (a, b): (usize, usize),
    ) -> Option<usize> {
        let row = v * WIDTH;
        if a < SIDE || b + SIDE > WIDTH {
            return None;
        }
        let (sa, sb) = (raw[row + a - 1], raw[row + b]);
        if sa == NO_DEPTH || sb == NO_DEPTH {
            return None;
        }
        // Eq. (3): the shadow's width, with the sensor's widening.
        let w = self.disp(sb) - self.disp(sa) + self.widen;
        if w < MIN_RIM as f64 || ((b - a) as f64) < w + (MIN_RIM + BLEND) as f64 {
            return None;
        }
        // The object is a surface over a few pixels. The background's colour is read over as
        // many of the SIDE pixels left of the hole as lie on Sa's surface: a nearer surface's
        // edge may leave a strip of a pixel or two of it (the seventh simulator's shadows beside
        // such a strip kept 0.62 of their attached pixels where it was one pixel wide, 0.91
        // where twelve or more).
        let side = (1..=SIDE)
            .take_while(|&k| self.on_surface(raw[row + a - k], sa))
            .count();
        if !self.all_on_surface(raw, v, b..b + SIDE, sb) {
            return None;
        }
        let object = self.mean_colour(rgb, v, b + 1..b + SIDE, sb)?;
        let wall = self.mean_colour(rgb, v, a - side..a, sa)?;
        let colours = RimColours::new(object, wall, self.dimmed(COLOUR_STEP, object));
        // Leftwards from the blend: the rim's columns, up to GAP that are not.
        let (mut start, mut shown, mut off) = (b - BLEND, 0, 0);
        for u in (a..b - BLEND).rev() {
            if colours.shows_object(self.probe(rgb, u, v, sb)?) {
                (start, shown, off) = (u, shown + 1, 0);
            } else {
                off += 1;
                if off == GAP {
                    break;
                }
            }
        }
        let rim = b - BLEND - start;
        if shown < MIN_RIM || 3 * shown < 2 * rim || start <= a {
            return None;
        }
        // The shadow's part shows the wall, or whatever lies behind: plainly not the object. A
        // hole that is the object throughout (a black box, a patch of its depth in it) shows the
        // object there too, and noise ends its run of object columns anywhere; so does a wall
        // of about the object's colour.
        let before = start.saturating_sub(GAP);
        let unlike = (a + 1..before)
            .filter(|&u| {
                self.probe(rgb, u, v, sb)
                    .is_some_and(|p| colours.plainly_not_object(p))
            })
            .count();
        if 3 * unlike < 2 * before.saturating_sub(a + 1) {
            return None;
        }
        // The background may recede under the shadow (a wall seen aslant): eq. (3) at the rim's
        // start, the background's disparity carried on from Sa's side over the shadow.
        let shadow = (start - a) as f64;
        let w_end = w - self.wall_slope(raw, v, a) * shadow;
        if (shadow - w_end).abs() > FIT {
            return None;
        }
        // The colour's run of the object may start a pixel or two late where the rim's first
        // columns blend with what lies left of it: eq. (3) ends the shadow no later.
        Some(start.min(a + w_end.round() as usize).max(a + 1))
    }

    /// The background's disparity change per pixel towards the hole at `a` in row `v`, read over
    /// the [`SLOPE_RUN`] pixels left of it (their ends' pairs averaged); 0 where those are not all
    /// measured or not one surface (each within [`super::SAME_SURFACE`] of the next: read across
    /// a nearer surface's edge, a narrow strip of background beside the hole took that edge's
    /// step for its slope; the seventh simulator's complex IR attached F1 +0.0044 on the suite
    /// with a pole before a patchwork poster beside a panel, nothing else moved), and at most
    /// [`MAX_SLOPE`] either way.
    fn wall_slope(&self, raw: &[u16], v: usize, a: usize) -> f64 {
        if a < SLOPE_RUN + 1 {
            return 0.0;
        }
        let run = &raw[v * WIDTH + a - SLOPE_RUN..v * WIDTH + a];
        if run.contains(&NO_DEPTH) || run.windows(2).any(|p| !self.on_surface(p[1], p[0])) {
            return 0.0;
        }
        let d = |k: usize| self.disp(run[k]);
        let rise = (d(SLOPE_RUN - 1) + d(SLOPE_RUN - 2)) - (d(0) + d(1));
        (rise / (2 * (SLOPE_RUN - 2)) as f64).clamp(-MAX_SLOPE, MAX_SLOPE)
    }
}
