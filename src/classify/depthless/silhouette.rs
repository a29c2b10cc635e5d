//! A detached hole that touches a thin occluder, where no widening can have swallowed the lit
//! gap: the attached shadow of a silhouette the projector sees wider than the camera does.
//!
//! The scanline reads a hole that touches an occluder narrower than its shadow's shift as that
//! occluder's detached shadow with the lit gap swallowed by the sensor's widening (eqs. 4–5; see
//! `thin_occluder` in the scanline). The widening swallows a pixel or three, so that reading
//! holds where the occluder falls short of its shift by about that. Where it falls short by
//! more, either something else hides the gap (a black surface under it, a region beyond range)
//! or there is no gap: the projector, 7.5 cm right of the camera, sees the occluder wider than
//! the camera does (a deep box's side face, at a wider angle) and casts one attached shadow up
//! to it. The RGB camera tells which: it sees the background lit, in the room's light,
//! over the whole hole where there is no gap to hide, and a black surface where one hides it.

use super::dark::{BEFORE_EDGE, LIT_SIDE, MIN_STEP, TIMES_DARKER, WIDEST};
use super::{ColourSplit, SAME_SURFACE, SIDE};
use crate::labels::{ATTACHED, DETACHED, NO_DEPTH, WIDTH};

/// The widest lit gap (pixels) the sensor's widening swallows: up to 3 px of an edge, and a
/// pixel of sampling. (A fifth simulator's 34 suites of complex scenes, summed: IR attached F1
/// +0.062 / +0.065 / +0.064 at 3 / 4 / 5 px, detached +0.145 / +0.156 / +0.156.)
const SWALLOWED: f64 = 4.0;
/// The least share of its shift an occluder's width must reach: the projector, 7.5 cm from the
/// camera, does not see a rod four times as wide as the camera does. A rod that thin beside such
/// a hole stands in another's shadow (this project's seed 5150: IR attached F1 −0.0025 without
/// the bound, −0.0001 with it; the fifth simulator's complex scenes +0.002 more).
const MIN_SHARE: f64 = 0.25;
/// The widest hole (pixels) right of the occluder that still ends it, a measured surface past
/// it: its own grazing edge, widened. Past a longer hole (a region without depth) the occluder
/// may go on, and its width is unknown.
const EDGE_HOLE: usize = 8;

impl ColourSplit {
    /// Relabels ATTACHED the detached hole `[a, b)` of row `v` that touches a thin occluder
    /// falling short of its shift by more than the widening swallows, where the RGB camera sees
    /// the background lit over all of the hole it sees (see the module's docs); returns whether
    /// it did.
    pub(super) fn wider_to_the_projector(
        &self,
        raw: &[u16],
        rgb: &[u8],
        labels: &mut [u8],
        v: usize,
        (a, b): (usize, usize),
    ) -> bool {
        let row = v * WIDTH;
        if a < SIDE || b + 1 >= WIDTH || b - a > WIDEST {
            return false;
        }
        let (sa, occ) = (raw[row + a - 1], raw[row + b]);
        if occ == NO_DEPTH
            || raw[row + a - SIDE..row + a].contains(&NO_DEPTH)
            || !labels[row + a..row + b].iter().all(|&l| l == DETACHED)
        {
            return false;
        }
        // Eq. (3)'s shift: the hole touches its occluder.
        let shift = self.disp(occ) - self.disp(sa);
        if shift < 2.0 * SAME_SURFACE {
            return false;
        }
        // The occluder's width: on to its first hole or step back by half the shift; past an
        // edge's hole, a measured surface must follow.
        let width = raw[row + b..row + WIDTH]
            .iter()
            .take_while(|&&r| r != NO_DEPTH && self.disp(occ) - self.disp(r) < shift / 2.0)
            .count();
        let past = b + width;
        let edge_hole = raw[row + past..row + WIDTH]
            .iter()
            .take_while(|&&r| r == NO_DEPTH)
            .count();
        let width = width as f64;
        if past + edge_hole >= WIDTH
            || edge_hole > EDGE_HOLE
            || width + SWALLOWED >= shift
            || width < MIN_SHARE * shift
        {
            return false;
        }
        // The background lit beside the hole, and no darker over it up to where the RGB camera
        // sees the occluder (a black surface hiding the gap would be: see `dark`).
        let Some(side) = self.side_brightness(rgb, v, a - SIDE..a, sa) else {
            return false;
        };
        if side < LIT_SIDE {
            return false;
        }
        let occluder_x = self.project(b as f64 - 0.5, v, occ).0 - BEFORE_EDGE;
        let mut seen = 0;
        for c in self.brightness_along(rgb, v, (a, b), sa, occluder_x) {
            match c {
                Some(c) if !(TIMES_DARKER * c < side && side - c > MIN_STEP) => seen += 1,
                _ => return false,
            }
        }
        // Most of the hole seen: not a strip beside the occluder's own edge.
        if 2 * seen < b - a {
            return false;
        }
        labels[row + a..row + b].fill(ATTACHED);
        true
    }
}
