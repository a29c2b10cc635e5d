//! A detached hole the RGB camera sees in the colour of the hole it pairs with, unlike the wall
//! on either side of it: two objects without depth side by side, not a depthless occluder and
//! its detached shadow.
//!
//! The scanline pairs a hole with the next hole right of it, past a lit gap, as a detached
//! shadow and the depthless occluder that casts it wherever eqs. (4)–(5) fit and the rows
//! above and below repeat the pair (`depthless_occluder` there). Two black objects a few
//! centimetres apart (a chair's legs before a wall), each with its own shadow of a pixel or
//! two, fit as well. The RGB camera tells them apart: over a detached shadow it sees the
//! background, in Sa's colour, or, where the occluder is near, the occluder over the hole's
//! right part and then over the lit gap as well (it shows a third of its shift left of where
//! its hole lands); over two objects it sees the first object's colour in the hole, the
//! second's (alike) in the next hole, and the wall in the gap between. (A seventh simulator
//! written from SPEC alone, six suites: complex IR detached F1 +0.099 summed, any-shadow
//! precision +0.024, recall −0.002; this project's fourteen suites −0.0003, recall −0.0001;
//! the real frame unchanged.)

use super::{hue_dist, ColourSplit, COLOUR_STEP, SAME_SURFACE, SIDE};
use crate::labels::{DETACHED, NO_DEPTH, OTHER, WIDTH};

/// The widest lit gap (pixels) between a detached shadow and its depthless occluder read here.
const WIDEST_GAP: usize = 40;
/// The narrowest occluder hole (pixels) read here: its middle third must be seen clear of its
/// edges' blends.
const MIN_OCCLUDER: usize = 6;

impl ColourSplit {
    /// Relabels OTHER the detached hole `[a, b)` of row `v` whose middle the RGB camera sees in
    /// the colour of the next hole's middle, past a lit gap, and a step from the colours of
    /// the gap and of the wall left of the hole (see the module's docs); returns whether it
    /// did.
    pub(super) fn detached_like_its_occluder(
        &self,
        raw: &[u16],
        rgb: &[u8],
        labels: &mut [u8],
        v: usize,
        (a, b): (usize, usize),
    ) -> bool {
        let row = v * WIDTH;
        let r = &raw[row..row + WIDTH];
        if a < SIDE || b + 2 >= WIDTH || b - a < 4 {
            return false;
        }
        if !labels[row + a..row + b].iter().all(|&l| l == DETACHED) {
            return false;
        }
        // Sa and Sb on one surface, the background: Sb the lit gap, not a nearer occluder the
        // hole touches (its lit gap swallowed by the widening), and Sa no nearer object whose
        // colour is no background's. (Disparity is linear in raw: the test runs on raw values.)
        let bg = r[b];
        let tol = (SAME_SURFACE / self.k) as u16;
        let on_bg = |x: u16| x != NO_DEPTH && x.abs_diff(bg) <= tol;
        if !on_bg(r[a - 1]) {
            return false;
        }
        // The lit gap runs on the background from Sb up to the next hole (a measured occluder
        // would end it with a step nearer).
        let gap = r[b..].iter().take_while(|&&x| on_bg(x)).count();
        let o0 = b + gap;
        if gap == 0 || gap > WIDEST_GAP || o0 >= WIDTH || r[o0] != NO_DEPTH {
            return false;
        }
        let occ = r[o0..].iter().take_while(|&&x| x == NO_DEPTH).count();
        if occ < MIN_OCCLUDER || o0 + occ >= WIDTH {
            return false;
        }
        // Middle thirds, clear of the edges' blends; all at the background's depth but Sa. Each
        // read only when the one before it passed (most holes fail the first).
        let third = |lo: usize, n: usize| lo + n / 3..lo + n - n / 3;
        let Some(hole) = self.mean_colour(rgb, v, third(a, b - a), bg) else {
            return false;
        };
        let unlike = |p: [i32; 3]| hue_dist(hole, p) >= self.dimmed(COLOUR_STEP, p);
        if !self
            .mean_colour(rgb, v, a - SIDE..a, r[a - 1])
            .is_some_and(unlike)
            || !self.mean_colour(rgb, v, b..o0, bg).is_some_and(unlike)
            || self
                .mean_colour(rgb, v, third(o0, occ), bg)
                .is_none_or(unlike)
        {
            return false;
        }
        labels[row + a..row + b].fill(OTHER);
        true
    }
}
