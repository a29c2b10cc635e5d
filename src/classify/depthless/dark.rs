//! Shadows that fall, in part or whole, on a black surface: OTHER there (SPEC §1: a hole that
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
//!
//! A thin occluder's detached shadow and the lit gap after it, both on a black poster, make one
//! hole the scanline reads as that shadow: the same test, on the whole hole, makes it OTHER.

use super::{ColourSplit, SAME_SURFACE, SIDE};
use crate::labels::{ATTACHED, DETACHED, NO_DEPTH, OTHER, WIDTH};

/// Brightness (R + G + B) of Sa's side under which the hole is not read: in a dim room
/// everything is near black (the real NYU frame's floor, whose shadows' sides read 60 to 150).
/// A pale wall in a room a third as bright reads about 200.
pub(super) const LIT_SIDE: i32 = 150;
/// A pixel is dark when Sa's side is this many times as bright as it...
pub(super) const TIMES_DARKER: i32 = 3;
/// ...and brighter by this much (the camera's noise on a dim side).
pub(super) const MIN_STEP: i32 = 60;
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
pub(super) const WIDEST: usize = 128;
/// Pixels at either end of a detached hole that need not be black (see
/// [`ColourSplit::detached_on_a_dark_surface`]).
const EDGE: usize = 4;
/// Pixels right of a side of a detached hole that must hold no nearer surface for the RGB
/// camera to see that side (f_rgb·b_rgb·(1/0.7 − 1/4) ≈ 15 px at most before a far wall).
const GUARD: usize = 16;
/// RGB columns before the occluder's edge at which the hole stops being read (the edge's blend).
pub(super) const BEFORE_EDGE: f64 = 1.5;

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
        // Sa's side, seen at Sa's depth.
        let Some(side) = self.side_brightness(rgb, v, a - SIDE..a, sa) else {
            return;
        };
        if side < LIT_SIDE {
            return;
        }
        let occluder_x = self.project(b as f64 - 0.5, v, sb).0 - BEFORE_EDGE;
        // Dark pixels of the visible part, a bit per pixel from `a`.
        let mut dark = 0u128;
        let mut black = 0u128;
        let mut seen = 0;
        for (j, c) in self
            .brightness_along(rgb, v, (a, b), sa, occluder_x)
            .enumerate()
        {
            let Some(c) = c else {
                break;
            };
            let d = TIMES_DARKER * c < side && side - c > MIN_STEP;
            dark |= u128::from(d) << j;
            black |= u128::from(d && c < BLACK) << j;
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

    /// Relabels OTHER the detached hole `[a, b)` of row `v` when the RGB camera sees it black
    /// wherever it sees it: a thin occluder's shadow and lit gap both on a black poster make one
    /// hole between the background and the occluder (or the next object), the shadow's layout
    /// and width, that would be a hole even if lit. The background is the farther of Sa and Sb;
    /// the hole must be black throughout but for [`EDGE`] pixels at its ends (a sliver of the
    /// shadow on the lit wall, the poster's blend), and its sides lit: a dark square of a
    /// patterned wall runs on past the hole, a poster's hole ends where the poster does.
    pub(super) fn detached_on_a_dark_surface(
        &self,
        raw: &[u16],
        rgb: &[u8],
        labels: &mut [u8],
        v: usize,
        (a, b): (usize, usize),
    ) {
        let row = v * WIDTH;
        if a < SIDE || b + SIDE + GUARD > WIDTH || b - a <= 2 * MIN_RUN || b - a > WIDEST {
            return;
        }
        let (sa, sb) = (raw[row + a - 1], raw[row + b]);
        if sa == NO_DEPTH
            || sb == NO_DEPTH
            || !labels[row + a..row + b].iter().all(|&l| l == DETACHED)
        {
            return;
        }
        // Each side on the background (the farther of Sa and Sb, or both where they are one
        // surface) must show it lit, in full view of the RGB camera: a nearer object within
        // GUARD pixels right of a side hides it (the RGB camera sees near objects shifted left),
        // and a thin lit gap beside the occluder would read the occluder's colour.
        let bg = sa.max(sb);
        // Cheapest first: most detached holes lie on a lit wall, which their middle shows.
        let (x, y) = self.project((a + b) as f64 / 2.0, v, bg);
        if super::rgb_at(rgb, x, y).is_none_or(|p| p.iter().sum::<i32>() >= BLACK) {
            return;
        }
        let far = |r: u16| self.disp(r) - self.disp(bg) < SAME_SURFACE;
        let mut side = i32::MAX;
        // Right of Sa's side lies the hole itself; right of Sb's, GUARD pixels must be clear.
        for (on_bg, px, clear) in [
            (far(sa), a - SIDE..a, a - SIDE..a),
            (far(sb), b..b + SIDE, b..b + SIDE + GUARD),
        ] {
            if !on_bg {
                continue;
            }
            if raw[row + clear.start..row + clear.end]
                .iter()
                .any(|&r| r == NO_DEPTH || !far(r))
            {
                return;
            }
            let Some(lit) = self.side_brightness(rgb, v, px, bg) else {
                return;
            };
            side = side.min(lit);
        }
        if side < LIT_SIDE {
            return;
        }
        // With Sa the background, the RGB camera sees the nearer Sb over the hole's right part.
        let to_x = if sa > sb {
            self.project(b as f64 - 0.5, v, sb).0 - BEFORE_EDGE
        } else {
            f64::INFINITY
        };
        // The black run, bar up to EDGE pixels at either end: a sliver of the shadow on the
        // lit wall past the poster's edge, or the edge's blend.
        let (mut first, mut last, mut seen) = (None, 0, 0);
        for (u, c) in (a..b).zip(self.brightness_along(rgb, v, (a, b), bg, to_x)) {
            let Some(c) = c else {
                return;
            };
            seen += 1;
            if TIMES_DARKER * c < side && side - c > MIN_STEP && c < BLACK {
                if first.is_none() {
                    first = Some(u);
                } else if u > last + 1 {
                    return;
                }
                last = u;
            } else if first.is_none() && u - a >= EDGE {
                return;
            }
        }
        let Some(first) = first else {
            return;
        };
        // Most of the hole seen (not a strip beside the occluder's own dark edge), black on to
        // its last pixel seen bar the edge.
        if 2 * seen >= b - a && a + seen <= last + 1 + EDGE {
            let to = if a + seen < b { b } else { last + 1 };
            labels[row + first..row + to].fill(OTHER);
        }
    }

    /// The mean brightness (R + G + B) of the probes of IR pixels `px` of row `v` at raw value
    /// `raw`, if all lie inside the RGB image.
    pub(super) fn side_brightness(
        &self,
        rgb: &[u8],
        v: usize,
        px: std::ops::Range<usize>,
        raw: u16,
    ) -> Option<i32> {
        let n = px.len() as i32;
        let mut sum = 0;
        for u in px {
            sum += self.probe(rgb, u, v, raw)?.iter().sum::<i32>();
        }
        Some(sum / n)
    }

    /// The brightness (R + G + B) of the RGB pixel over each IR pixel of `[a, b)` in row `v` at
    /// raw value `raw`, from `a` on while the RGB column stays at or left of `to_x` (`None`
    /// outside the image). Over a hole the projection is linear in the column to well under a
    /// pixel: two divisions, not one per pixel.
    pub(super) fn brightness_along<'a>(
        &'a self,
        rgb: &'a [u8],
        v: usize,
        (a, b): (usize, usize),
        raw: u16,
        to_x: f64,
    ) -> impl Iterator<Item = Option<i32>> + 'a {
        let (xa, ya) = self.project(a as f64, v, raw);
        let (xb, yb) = self.project(b as f64, v, raw);
        let span = (b - a) as f64;
        let (dx, dy) = ((xb - xa) / span, (yb - ya) / span);
        (0..b - a)
            .map(move |k| (xa + k as f64 * dx, ya + k as f64 * dy))
            .take_while(move |&(x, _)| x <= to_x)
            .map(|(x, y)| super::rgb_at(rgb, x, y).map(|p| p.iter().sum::<i32>()))
    }
}
