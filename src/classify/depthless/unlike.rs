//! Attached shadows whose hole shows, in the RGB image, a surface that returns no depth.
//!
//! The scanline calls a hole attached when its width fits eq. (3) between Sa and Sb. A gap
//! between two objects onto a surface that returns no depth (a wall beyond range, a black one)
//! can fit it too: a rod standing just right of a panel's edge, or two rods before a far wall. A
//! projector shadow is lit by the room, so the RGB camera sees the surface it lies on there;
//! through such a gap it sees the far surface. The hole is OTHER where its colour (one colour
//! over the first half of it) is plainly not Sa's, nor that of any pixel along Sa, but is that of
//! a hole beyond Sa or Sb, a few pixels away, that the scanline left OTHER (the far surface
//! showing on the other side of a thin object). Unlike Sa's colour alone is no reason: a shadow
//! across a corner lies on the next surface, and one beside a thin Sa on the wall behind it;
//! and the RGB camera may see an occluder without depth over Sa's last pixels.

use super::{hue_dist, relabel, ColourSplit, COLOUR_STEP, SAME_SURFACE, SIDE};
use crate::labels::{ATTACHED, NO_DEPTH, OTHER, WIDTH};

/// Narrowest hole read (pixels): two columns of its first half, past the first (an edge's
/// blend), are compared. At 6 rather than 4, a 4 px gap between a panel's edge and a rod before a
/// wall beyond range stayed attached (one suite of the other simulator: attached F1 −0.005).
const MIN_WIDTH: usize = 4;
/// Widest object (pixels) across which a hole beyond it is looked for.
const THIN: usize = 24;
/// IR pixels left of where the RGB camera sees Sb's edge at which the surface past it is read:
/// the edge's blended columns and three columns' mean. At 2 the hand-made scene (a rod at
/// 0.8 m) read the blend in every row.
const PAST_SB: f64 = 4.0;

impl ColourSplit {
    /// Relabels the attached pixels of the hole `[a, b)` of row `v` OTHER when the RGB camera sees
    /// a surface without depth over it, not Sa's (see the module's docs). True when it did.
    pub(super) fn unlike_its_surface(
        &self,
        raw: &[u16],
        rgb: &[u8],
        labels: &mut [u8],
        filled: &[u16],
        v: usize,
        (a, b): (usize, usize),
    ) -> bool {
        let row = v * WIDTH;
        if b - a < MIN_WIDTH || b >= WIDTH {
            return false;
        }
        if a == 0 {
            return self.left_border_unlike(raw, rgb, labels, filled, v, b);
        }
        if a < SIDE {
            return false;
        }
        let sa = raw[row + a - 1];
        // Only where the scanline put the shadow on Sa's own surface (not on a background hidden
        // behind a thin Sa), read on Sa's pixels.
        let on_sa = |r: u16| r != NO_DEPTH && (self.disp(r) - self.disp(sa)).abs() <= SAME_SURFACE;
        if !on_sa(filled[row + a]) || !(a - SIDE..a).all(|u| on_sa(raw[row + u])) {
            return false;
        }
        // Depth and labels first (most attached holes have no such hole beyond): the RGB image
        // is read only where the far surface may show.
        let far = [
            self.hole_beyond(labels, v, a - 1, true),
            self.hole_beyond(labels, v, b, false),
        ];
        if far.iter().all(Option::is_none) {
            return false;
        }
        let Some(surface) = self.mean_colour(rgb, v, a - SIDE..a, sa) else {
            return false;
        };
        let Some(hole) = self.one_colour(rgb, v, (a, b), sa) else {
            return false;
        };
        let unlike_sa = |c: [i32; 3]| hue_dist(c, surface) >= 2 * self.dimmed(COLOUR_STEP, surface);
        if !unlike_sa(hole) {
            return false;
        }
        // Nor anywhere along Sa (the RGB camera may see an occluder without depth over Sa's
        // last pixels, a third of its shift left of its shadow). The run's end pixels are left
        // out: the RGB camera may see past a thin Sa's edge there.
        let run = (1..=THIN)
            .map_while(|k| a.checked_sub(k))
            .take_while(|&u| on_sa(raw[row + u]))
            .count();
        let along_sa = (a + 1 - run..a - 1).any(|u| {
            let (x, y) = self.project(u as f64, v, sa);
            super::rgb_at(rgb, x, y)
                .is_some_and(|p| hue_dist(p, hole) < self.dimmed(COLOUR_STEP, hole))
        });
        if along_sa {
            return false;
        }
        // The far surface: unlike Sa too (a shadow beyond Sa shows Sa's colour), and like the hole.
        if !far
            .into_iter()
            .flatten()
            .filter_map(|us| self.mean_colour(rgb, v, us, sa))
            .any(|c| unlike_sa(c) && hue_dist(hole, c) < self.dimmed(COLOUR_STEP, c))
        {
            return false;
        }
        relabel(&mut labels[row + a..row + b], ATTACHED, OTHER);
        true
    }

    /// [`ColourSplit::unlike_its_surface`] for a hole `[0, b)` at the left border, which has no
    /// Sa: the scanline took its background from the rows above. It is OTHER when it shows one
    /// colour, that of an OTHER hole just beyond a thin Sb, and not Sb's own (which the RGB
    /// camera may see over a shadow's right part). Where the RGB camera sees Sb over all of a
    /// narrow hole, what it sees left of the IR image's edge, past Sb, is read instead.
    fn left_border_unlike(
        &self,
        raw: &[u16],
        rgb: &[u8],
        labels: &mut [u8],
        filled: &[u16],
        v: usize,
        b: usize,
    ) -> bool {
        let row = v * WIDTH;
        let (bg, sb) = (filled[row], raw[row + b]);
        if bg == NO_DEPTH || sb == NO_DEPTH {
            return false;
        }
        let Some(far) = self.hole_beyond(labels, v, b, false) else {
            return false;
        };
        let (Some(far), Some(occluder)) = (
            self.mean_colour(rgb, v, far, bg),
            self.mean_colour(rgb, v, b..b + 2, sb),
        ) else {
            return false;
        };
        let unlike_occluder =
            |c: [i32; 3]| hue_dist(c, occluder) >= 2 * self.dimmed(COLOUR_STEP, c);
        // Over a narrow hole beside a near Sb the RGB camera sees Sb (moved left by a third of
        // its shift); it sees the hole's surface go on left of the IR image's edge, past that.
        let hole = self
            .one_colour(rgb, v, (0, b), bg)
            .filter(|&c| unlike_occluder(c))
            .or_else(|| {
                let sb_seen = b as f64 - (self.disp(sb) - self.disp(bg)) / 3.0;
                let (x, y) = self.project(sb_seen.min(0.0) - PAST_SB, v, bg);
                super::rgb_mean3(rgb, x, y)
            });
        let Some(hole) = hole else {
            return false;
        };
        if hue_dist(hole, far) >= self.dimmed(COLOUR_STEP, hole) || !unlike_occluder(hole) {
            return false;
        }
        relabel(&mut labels[row..row + b], ATTACHED, OTHER);
        true
    }

    /// The colour the RGB camera sees over the first half of the hole `[a, b)` of row `v` (at
    /// raw value `at`), if it is one: the RGB camera, a third of the way to the projector, sees
    /// an occluder over a shadow's last third, so only the first half is read, less a column of
    /// blend at its start, in two parts that must agree (one far surface; not a black object
    /// beside a shadow).
    fn one_colour(
        &self,
        rgb: &[u8],
        v: usize,
        (a, b): (usize, usize),
        at: u16,
    ) -> Option<[i32; 3]> {
        let q = (b - a) / 4;
        let part = |us: std::ops::Range<usize>| self.mean_colour(rgb, v, us, at);
        let (first, second) = (part(a + 1..a + 1 + q)?, part(a + 1 + q..a + 1 + 2 * q)?);
        (hue_dist(first, second) < self.dimmed(COLOUR_STEP, first))
            .then(|| std::array::from_fn(|k| (first[k] + second[k]) / 2))
    }

    /// The [`SIDE`] pixels of the OTHER hole next to the valid run of row `v` through column
    /// `from`, on its left (`left`) or right, if that run is at most [`THIN`] pixels wide.
    pub(super) fn hole_beyond(
        &self,
        labels: &[u8],
        v: usize,
        from: usize,
        left: bool,
    ) -> Option<std::ops::Range<usize>> {
        let mask = &self.masks[v];
        // The hole's pixels next to the run, read off the row's bitmap.
        let us = if left {
            let start = mask.prev_hole_end(from + 1);
            let hole = mask.prev_valid_end(start);
            (from + 1 - start <= THIN && start >= hole + SIDE).then(|| start - SIDE..start)?
        } else {
            let end = mask.next_hole(from);
            let hole = mask.next_valid(end);
            (end - from <= THIN && hole >= end + SIDE).then(|| end..end + SIDE)?
        };
        let row = &labels[v * WIDTH..(v + 1) * WIDTH];
        row[us.clone()].iter().all(|&l| l == OTHER).then_some(us)
    }
}
