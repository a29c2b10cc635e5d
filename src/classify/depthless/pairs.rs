//! Detached shadows of depthless occluders that depth alone cannot pair.
//!
//! A black rod before a wall leaves two holes in a row: its detached shadow and, `shift` pixels to
//! its right, the rod itself (eqs. 4–5 with the occluder's disparity unknown). The scanline pairs
//! them when nothing else is near; with two rods (shadow, shadow, rod, rod) or another shadow
//! within reach, the holes chain up and depth cannot tell shadows from occluders, so it leaves
//! them all OTHER. The RGB camera can: a shadow shows the background's colour, an occluder its
//! own. A hole is a detached shadow when it looks like the background and a hole to its right,
//! of a width the shadow could have, looks unlike it at the depth the shift implies; the rows
//! above and below must hold the same pair, because an occluder is a solid.
//!
//! A shadow's start may be hidden by a nearer surface on its left (then only its right end and
//! the background right of it are read), and an occluder's hole may have a farther surface on
//! its right (a rod before an object's edge): the background of its shadow is the one on its left.
//!
//! Holes are met left to right, so each one is tried as the occluder of the recent holes of its
//! row: no search along the row, which keeps the many holes of a real frame cheap.

use super::{
    ceil, hole_span, hue_dist, in_palette, rgb_at, ColourSplit, COLOUR_STEP, SAME_SURFACE, SIDE,
    SIDES_AGREE, SPREAD_SPAN,
};
use crate::labels::{DETACHED, NO_DEPTH, OTHER, WIDTH};

/// Narrowest shadow and occluder holes considered (pixels), as the scanline's.
const MIN_WIDTH: usize = 3;
/// How much wider than its occluder a shadow may look: the sensor's widening (the scanline's
/// default `attached_over_px`).
const OVER: usize = 8;
/// How much narrower than its occluder's hole a shadow may look (pixels): the sensor widens
/// both holes, each end by its own 0–3 px in each row. (At 1, a fifth simulator's glossy rods,
/// whose holes it widens like their shadows', lost whole rows of their shadows to OTHER: at 3,
/// complex IR detached F1 +0.032 summed over its 16 suites, k14 +0.021, recall +0.024, RGB
/// any-shadow precision −0.002; this project's suites unchanged, the real frame 3 px OTHER →
/// detached.)
const NARROWER: usize = 3;
/// Shifts of the rows above and below may differ by this much (pixels): the sensor's widening
/// moves each row's shadow end by 0–3 px.
const ROWS_AGREE: usize = 3;
/// Holes of the current row remembered as shadow candidates.
const RECENT: usize = 8;

/// A hole `[a, b)` closed on both sides by one background, raw value `bg`; or, as a shadow, closed
/// by it on the right only, a nearer surface on its left hiding the shadow's start (`hidden`).
#[derive(Clone, Copy, Debug, Default)]
struct Closed {
    a: usize,
    b: usize,
    bg: u16,
    hidden: bool,
}

/// The last few closed holes of the row being scanned (scratch, reused).
#[derive(Clone, Debug, Default)]
pub(super) struct Recent {
    row: usize,
    holes: [Closed; RECENT],
    len: usize,
}

impl Recent {
    /// Remembers `h`, forgetting the oldest hole when full.
    fn push(&mut self, h: Closed) {
        if self.len == RECENT {
            self.holes.copy_within(1.., 0);
            self.len -= 1;
        }
        self.holes[self.len] = h;
        self.len += 1;
    }
}

impl ColourSplit {
    /// Tries the hole `[a, b)` of row `v` as the depthless occluder of a recent hole left of it.
    /// On success that hole becomes DETACHED, this one's pixels of `filled` get the depth the
    /// shift implies, and true is returned. A closed hole that pairs with none is remembered.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn detached_pair(
        &self,
        raw: &[u16],
        rgb: &[u8],
        labels: &mut [u8],
        filled: &mut [u16],
        recent: &mut Recent,
        v: usize,
        (a, b): (usize, usize),
    ) -> bool {
        if recent.row != v {
            (recent.row, recent.len) = (v, 0);
        }
        let row = &raw[v * WIDTH..(v + 1) * WIDTH];
        // (A shadow whose start a nearer surface hides has a farther surface on its right, so
        // it is tried as an occluder's hole first, and remembered as a shadow below.)
        let Some(o) = self.occluder(row, (a, b)) else {
            return false;
        };
        for k in (0..recent.len).rev() {
            let h = recent.holes[k];
            let Some(shift) = self.pair(h, o) else {
                continue;
            };
            if labels[v * WIDTH + h.a..v * WIDTH + h.b]
                .iter()
                .zip(&row[h.a..h.b])
                .any(|(&l, &r)| r == NO_DEPTH && l != OTHER)
                || !self.repeats(raw, v, h, o, shift)
                || !self.colours_fit(raw, rgb, v, h, o, shift)
            {
                continue;
            }
            let base = v * WIDTH;
            for u in h.a..h.b {
                if raw[base + u] == NO_DEPTH {
                    labels[base + u] = DETACHED;
                }
            }
            let at = self.raw_at_disp(self.disp(o.bg) + shift as f64);
            filled[base + o.a..base + o.b].fill(at);
            return true;
        }
        // Remembered as a shadow for the holes right of it.
        if let Some(h) = self.shadow(row, (a, b)) {
            recent.push(h);
        }
        false
    }

    /// `[a, b)` as a closed hole: wide enough, with valid pixels of one depth on both sides.
    fn closed(&self, row: &[u16], (a, b): (usize, usize)) -> Option<Closed> {
        let (l, r, step) = self.sides(row, (a, b))?;
        (step.abs() <= SAME_SURFACE).then(|| Closed {
            a,
            b,
            bg: l.max(r),
            hidden: false,
        })
    }

    /// `[a, b)` as a shadow whose start a nearer surface on its left hides: the background
    /// closes it on the right only. (A projector shadow lies left of its occluder, so the nearer
    /// surface is not its occluder.)
    fn hidden_shadow(&self, row: &[u16], (a, b): (usize, usize)) -> Option<Closed> {
        let (_, r, step) = self.sides(row, (a, b))?;
        (step > SAME_SURFACE).then_some(Closed {
            a,
            b,
            bg: r,
            hidden: true,
        })
    }

    /// `[a, b)` as an occluder's hole: [`ColourSplit::closed`], or with a farther surface on its
    /// right (a rod standing before an object's edge), the background of its shadow on its left.
    fn occluder(&self, row: &[u16], (a, b): (usize, usize)) -> Option<Closed> {
        let (l, _, step) = self.sides(row, (a, b))?;
        if step > SAME_SURFACE {
            return Some(Closed {
                a,
                b,
                bg: l,
                hidden: false,
            });
        }
        self.closed(row, (a, b))
    }

    /// The valid pixels either side of the hole `[a, b)` (wide enough, inside the image) and how
    /// much nearer the left one is, in pixels of disparity.
    fn sides(&self, row: &[u16], (a, b): (usize, usize)) -> Option<(u16, u16, f64)> {
        if a < SIDE || b + SIDE > WIDTH || b - a < MIN_WIDTH {
            return None;
        }
        let (l, r) = (row[a - 1], row[b]);
        (l != NO_DEPTH && r != NO_DEPTH).then(|| (l, r, self.disp(l) - self.disp(r)))
    }

    /// `[a, b)` as a shadow: [`ColourSplit::closed`] or [`ColourSplit::hidden_shadow`].
    fn shadow(&self, row: &[u16], hole: (usize, usize)) -> Option<Closed> {
        self.closed(row, hole)
            .or_else(|| self.hidden_shadow(row, hole))
    }

    /// The shift of occluder `o` casting shadow `h`, when the geometry allows it: one background,
    /// a shadow as wide as the occluder (up to [`NARROWER`] narrower; or narrower still, its
    /// start hidden) or up to the widening wider, the right edges `shift` apart, within the
    /// sensor's range.
    fn pair(&self, h: Closed, o: Closed) -> Option<usize> {
        let (hw, ow) = (h.b - h.a, o.b - o.a);
        let shift = o.b.checked_sub(h.b)?;
        (h.b <= o.a
            && (hw + NARROWER >= ow || h.hidden)
            && hw <= ow + OVER
            && (self.disp(h.bg) - self.disp(o.bg)).abs() <= SAME_SURFACE
            && self.disp(h.bg) + shift as f64 <= self.max_disp)
            .then_some(shift)
    }

    /// The rows above and below hold the same pair: closed holes through both centres, shifted
    /// alike.
    fn repeats(&self, raw: &[u16], v: usize, h: Closed, o: Closed, shift: usize) -> bool {
        [v - 1, v + 1].into_iter().all(|w| {
            let row = &raw[w * WIDTH..(w + 1) * WIDTH];
            let hole = |u: usize| (row[u] == NO_DEPTH).then(|| hole_span(&self.masks[w], row, u));
            let (Some(hs), Some(os)) = (hole((h.a + h.b) / 2), hole((o.a + o.b) / 2)) else {
                return false;
            };
            let (Some(h2), Some(o2)) = (self.shadow(row, hs), self.occluder(row, os)) else {
                return false;
            };
            self.pair(h2, o2)
                .is_some_and(|t| t.abs_diff(shift) <= ROWS_AGREE)
        })
    }

    /// The shadow looks like the background beside it (its left third), and the occluder, where
    /// the RGB camera sees it at the depth the shift implies, plainly does not, nor like any
    /// colour the surface shows beside the pair.
    fn colours_fit(
        &self,
        raw: &[u16],
        rgb: &[u8],
        v: usize,
        h: Closed,
        o: Closed,
        shift: usize,
    ) -> bool {
        let colour_at = |x: f64, y: f64| rgb_at(rgb, x, y);
        let mean = |us: std::ops::Range<usize>, bg: u16| self.mean_colour(rgb, v, us, bg);
        // The background's colour left of the shadow (right of it the RGB camera may see a
        // nearer occluder moved left over it), and right too when that agrees; right of it only
        // when a nearer surface hides the shadow's start.
        let side = if h.hidden {
            h.b..h.b + SIDE
        } else {
            h.a - SIDE..h.a
        };
        let Some(left) = mean(side, h.bg) else {
            return false;
        };
        let bg = match mean(h.b..h.b + SIDE, h.bg) {
            Some(right) if hue_dist(left, right) <= self.dimmed(SIDES_AGREE, left) => {
                std::array::from_fn(|k| (left[k] + right[k]) / 2)
            }
            _ => left,
        };
        // The colour steps for this background's brightness.
        let step = self.dimmed(COLOUR_STEP, bg);
        // The occluder's RGB columns.
        let at = self.raw_at_disp(self.disp(o.bg) + shift as f64);
        let (x0, y) = self.project(o.a as f64 - 0.5, v, at);
        let (x1, _) = self.project(o.b as f64 - 0.5, v, at);
        let (x0, x1) = (ceil(x0), ceil(x1));
        if x1 <= x0 {
            return false;
        }
        let (mut far, mut sum, mut acc) = (0u32, 0u32, [0i32; 3]);
        for x in x0..x1 {
            let Some(p) = colour_at(x as f64, y) else {
                return false;
            };
            let d = hue_dist(p, bg);
            far += u32::from(d >= step);
            sum += d;
            (0..3).for_each(|k| acc[k] += p[k]);
        }
        let cols = (x1 - x0) as u32;
        if 2 * far < cols + 1 || sum < 2 * step * cols {
            return false;
        }
        // The shadow's left third: the RGB camera may see a nearer occluder right of it moved
        // left over the rest. (The occluder's test above is what tells a shadow from a rod: a
        // thin rod's own hole shows background too, its image being moved left of it.)
        let shadow_plain = (h.a..h.a + (h.b - h.a).div_ceil(3)).all(|u| {
            let (x, y) = self.project(u as f64, v, h.bg);
            colour_at(x, y).is_some_and(|p| hue_dist(p, bg) < step)
        });
        // An occluder showing a colour the surface itself shows beside the pair is that surface:
        // two dropouts on a patterned glossy surface, the second on its other colour. The
        // surface's colours are read where no depthless occluder's image can lie over it (a
        // third of the widest shift left of a hole): a black rod nearby would pass for its own.
        // (Fourth simulator, 46 suites: simple IR detached F1 +0.037 summed, j19 +0.030,
        // precision +0.012; complex +0.013, precision +0.0065; this project's suites up to
        // +0.009, the real frame unchanged.)
        shadow_plain && {
            let occluder = acc.map(|a| a / cols as i32);
            let row = &raw[v * WIDTH..(v + 1) * WIDTH];
            let clear = ((self.max_disp - self.disp(h.bg)) / 3.0).ceil() as usize;
            let beside = [
                h.a.saturating_sub(SPREAD_SPAN)..h.a,
                o.b..(o.b + SPREAD_SPAN).min(WIDTH),
            ];
            !beside.into_iter().any(|span| {
                let (qs, m) = self.wall_palette_clear(row, rgb, v, span, h.bg, clear);
                in_palette(&qs[..m], occluder, step)
            })
        }
    }
}
