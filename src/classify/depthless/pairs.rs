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
//! A shadow the scanline paired already (with a depthless rod's hole, which it leaves OTHER) is
//! remembered too: a hole that casts it is an occluder whole, with no attached shadow in it for
//! the colour split to find. Nor need an occluder's hole be closed by the background: a nearer
//! surface may close it, one the occluder stands before; or it may run on into another hole (a
//! nearer rod's shadow), when the RGB camera sees the occluder end where its shadow's width
//! does.
//!
//! Holes are met left to right, so each one is tried as the occluder of the recent holes of its
//! row: no search along the row, which keeps the many holes of a real frame cheap.

use super::{
    ceil, hole_span, hue_dist, in_palette, rgb_at, ColourSplit, COLOUR_STEP, SAME_SURFACE, SIDE,
    SIDES_AGREE, SPREAD_SPAN,
};
use crate::labels::{DETACHED, NO_DEPTH, OTHER, VALID, WIDTH};

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
/// An occluder's hole may be wider still, by this share of its shadow's width: another object's
/// detached shadow may join it on its left (a thin rod standing behind a near glossy one, its
/// shadow at the glossy rod's edge), and the pair's shift is read from the right edges, which
/// that leaves alone. A fresh suite's glossy rod at 0.6 m (seed 31415, scene 017): its hole 5 px
/// wider than its 37 px shadow from the thin rod's top down.
const MERGED_SHARE: usize = 4;
/// Shifts of the rows above and below may differ by this much (pixels): the sensor's widening
/// moves each row's shadow end by 0–3 px.
const ROWS_AGREE: usize = 3;
/// Holes of the current row remembered as shadow candidates.
const RECENT: usize = 8;

/// A hole `[a, b)` closed on both sides by one background, raw value `bg`; or, as a shadow, closed
/// by it on the right only, a nearer surface on its left hiding the shadow's start (`hidden`).
/// `cast`: the scanline read it as a detached shadow already. `before`: as an occluder's hole,
/// the raw value of a nearer surface closing it on the right, which the occluder stands before.
/// `cut`: as an occluder's hole, the part of a wider hole its shadow's width leaves it.
#[derive(Clone, Copy, Debug, Default)]
struct Closed {
    a: usize,
    b: usize,
    bg: u16,
    hidden: bool,
    cast: bool,
    before: Option<u16>,
    cut: bool,
}

/// The last few closed holes of the row being scanned (scratch, reused).
#[derive(Clone, Debug, Default)]
pub(super) struct Recent {
    row: usize,
    holes: [Closed; RECENT],
    len: usize,
}

impl Recent {
    /// Starts row `v` afresh, unless it is the row being scanned.
    fn at_row(&mut self, v: usize) {
        if self.row != v {
            (self.row, self.len) = (v, 0);
        }
    }

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
        recent.at_row(v);
        let row = &raw[v * WIDTH..(v + 1) * WIDTH];
        // (A shadow whose start a nearer surface hides has a farther surface on its right, so
        // it is tried as an occluder's hole first, and remembered as a shadow below.)
        let Some(whole) = self.occluder(row, (a, b)) else {
            return false;
        };
        for k in (0..recent.len).rev() {
            let h = recent.holes[k];
            let o = self.cut_to(h, whole);
            let Some(shift) = self.pair(h, o) else {
                continue;
            };
            // A shadow the scanline paired may have a measured occluder, and so may one left of
            // a hole a nearer surface closes: no nearer surface may stand between the holes.
            let near = self.disp(h.bg).max(self.disp(o.bg)) + SAME_SURFACE;
            if (h.cast || o.before.is_some())
                && row[h.b..o.a]
                    .iter()
                    .any(|&r| r != NO_DEPTH && self.disp(r) > near)
            {
                continue;
            }
            if cast(labels, v, (h.a, h.b)) != Some(h.cast)
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
            if let Some(cast) = cast(labels, v, (a, b)) {
                recent.push(Closed { cast, ..h });
            }
        }
        false
    }

    /// Remembers the hole `[a, b)` of row `v`, which the scanline read as a detached shadow, for
    /// the holes right of it: a depthless hole that casts it is that shadow's occluder, whole,
    /// and no attached shadow for the colour split to find in it. (The scanline pairs such a
    /// shadow with a depthless rod's hole, but labels only the shadow.)
    pub(super) fn remember_detached(
        &self,
        raw: &[u16],
        labels: &[u8],
        recent: &mut Recent,
        v: usize,
        (a, b): (usize, usize),
    ) {
        recent.at_row(v);
        let row = &raw[v * WIDTH..(v + 1) * WIDTH];
        if let Some(h) = self.shadow(row, (a, b)) {
            if cast(labels, v, (a, b)) == Some(true) {
                recent.push(Closed { cast: true, ..h });
            }
        }
    }

    /// `[a, b)` as a closed hole: wide enough, with valid pixels of one depth on both sides (on
    /// its right at least `right` of them before the image's edge).
    fn closed(&self, row: &[u16], (a, b): (usize, usize), right: usize) -> Option<Closed> {
        let (l, r, step) = self.sides(row, (a, b), right)?;
        (step.abs() <= SAME_SURFACE).then(|| Closed {
            a,
            b,
            bg: l.max(r),
            ..Closed::default()
        })
    }

    /// `[a, b)` as a shadow whose start a nearer surface on its left hides: the background
    /// closes it on the right only. (A projector shadow lies left of its occluder, so the nearer
    /// surface is not its occluder.)
    fn hidden_shadow(&self, row: &[u16], (a, b): (usize, usize)) -> Option<Closed> {
        let (_, r, step) = self.sides(row, (a, b), SIDE)?;
        (step > SAME_SURFACE).then_some(Closed {
            a,
            b,
            bg: r,
            hidden: true,
            ..Closed::default()
        })
    }

    /// `[a, b)` as an occluder's hole: [`ColourSplit::closed`], or closed on its right by another
    /// surface, farther (a rod standing before an object's edge) or nearer (`before`): the
    /// background of its shadow is then the one on its left.
    ///
    /// Its right side is only read for its depth: a pixel of it before the image's edge will
    /// do (a near rod by the right border, its shadow well inside the image).
    fn occluder(&self, row: &[u16], (a, b): (usize, usize)) -> Option<Closed> {
        let (l, r, step) = self.sides(row, (a, b), 1)?;
        let background_left = Closed {
            a,
            b,
            bg: l,
            ..Closed::default()
        };
        if step > SAME_SURFACE {
            return Some(background_left);
        }
        // Or a nearer surface on its right, when the occluder stands before that surface too
        // ([`ColourSplit::pair`] asks, knowing the occluder's depth).
        if step < -SAME_SURFACE {
            return Some(Closed {
                before: Some(r),
                ..background_left
            });
        }
        self.closed(row, (a, b), 1)
    }

    /// The valid pixels either side of the hole `[a, b)` (wide enough, inside the image, `right`
    /// pixels of it right of the hole) and how much nearer the left one is, in pixels of
    /// disparity.
    fn sides(&self, row: &[u16], (a, b): (usize, usize), right: usize) -> Option<(u16, u16, f64)> {
        if a < SIDE || b + right > WIDTH || b - a < MIN_WIDTH {
            return None;
        }
        let (l, r) = (row[a - 1], row[b]);
        (l != NO_DEPTH && r != NO_DEPTH).then(|| (l, r, self.disp(l) - self.disp(r)))
    }

    /// `[a, b)` as a shadow: [`ColourSplit::closed`] or [`ColourSplit::hidden_shadow`].
    fn shadow(&self, row: &[u16], hole: (usize, usize)) -> Option<Closed> {
        self.closed(row, hole, SIDE)
            .or_else(|| self.hidden_shadow(row, hole))
    }

    /// The shift of occluder `o` casting shadow `h`, when the geometry allows it: one background,
    /// a shadow as wide as the occluder (up to [`NARROWER`] narrower, and a [`MERGED_SHARE`] of
    /// its width more; or narrower still, its start hidden) or up to the widening wider, the
    /// right edges `shift` apart, within the sensor's range.
    fn pair(&self, h: Closed, o: Closed) -> Option<usize> {
        let (hw, ow) = (h.b - h.a, o.b - o.a);
        let shift = o.b.checked_sub(h.b)?;
        let at = self.disp(h.bg) + shift as f64;
        // An occluder's hole closed by a nearer surface (a black rod before a box's edge) pairs
        // only where the occluder stands before that surface.
        let before_ok = o.before.is_none_or(|r| at > self.disp(r) + SAME_SURFACE);
        (h.b <= o.a
            && (hw + NARROWER + hw / MERGED_SHARE >= ow || h.hidden)
            && hw <= ow + OVER
            && (self.disp(h.bg) - self.disp(o.bg)).abs() <= SAME_SURFACE
            && at <= self.max_disp
            && before_ok)
            .then_some(shift)
    }

    /// `o` cut to the width of shadow `h` where it is wider than the widening allows: a
    /// depthless occluder's hole run on into another hole right of it (another object's shadow).
    fn cut_to(&self, h: Closed, o: Closed) -> Closed {
        let (hw, ow) = (h.b - h.a, o.b - o.a);
        if !h.hidden && ow > hw + NARROWER + OVER {
            Closed {
                b: o.a + hw,
                before: None,
                cut: true,
                ..o
            }
        } else {
            o
        }
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
            self.pair(h2, self.cut_to(h2, o2))
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
        // A shadow the scanline paired already is known by its geometry: three quarters of its
        // third will do, as a dim background's camera noise strays past the step here and there.
        let third = h.a..h.a + (h.b - h.a).div_ceil(3);
        let n = third.len();
        let mut plain = 0;
        for u in third {
            let (x, y) = self.project(u as f64, v, h.bg);
            plain += usize::from(colour_at(x, y).is_some_and(|p| hue_dist(p, bg) < step));
        }
        let shadow_plain = if h.cast {
            4 * plain >= 3 * n
        } else {
            plain == n
        };
        // An occluder showing a colour the surface itself shows beside the pair is that surface:
        // two dropouts on a patterned glossy surface, the second on its other colour. The
        // surface's colours are read where no depthless occluder's image can lie over it (a
        // third of the widest shift left of a hole): a black rod nearby would pass for its own.
        // (Fourth simulator, 46 suites: simple IR detached F1 +0.037 summed, j19 +0.030,
        // precision +0.012; complex +0.013, precision +0.0065; this project's suites up to
        // +0.009, the real frame unchanged.)
        let occluder = acc.map(|a| a / cols as i32);
        // A cut occluder ends where the cut puts it: the RGB camera sees something else there.
        let ends = !o.cut || {
            let past = (x1..x1 + 3)
                .filter(|&x| colour_at(x as f64, y).is_some_and(|p| hue_dist(p, occluder) >= step))
                .count();
            past >= 2
        };
        shadow_plain && ends && {
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

/// How the scanline read the hole `[a, b)` of row `v`: as a detached shadow (true: three
/// quarters of its pixels or more, a pixel or two of it left OTHER), or not at all (false: all
/// OTHER); None when it read part of it otherwise, or as a shadow in part only.
fn cast(labels: &[u8], v: usize, (a, b): (usize, usize)) -> Option<bool> {
    // A hole's lit islands are VALID, its pixels anything else: one pass over the labels alone
    // (the compiler vectorises it), no raw values.
    let (mut valid, mut detached, mut other) = (0, 0, 0);
    for &l in &labels[v * WIDTH + a..v * WIDTH + b] {
        valid += usize::from(l == VALID);
        detached += usize::from(l == DETACHED);
        other += usize::from(l == OTHER);
    }
    let holes = b - a - valid;
    if detached + other != holes {
        return None;
    }
    match detached {
        0 => Some(false),
        d if 4 * d >= 3 * holes => Some(true),
        _ => None,
    }
}
