//! Where a detached shadow's tail starts, in a hole it shares with something on its left.
//!
//! Behind a nearer object, or past the left border, the scanline may read only the right end of
//! a hole as a thin occluder's detached shadow (eq. 5), from where eq. (4) puts the shadow's left
//! end; the rest of the hole is something else it merged with. That something may hide the
//! shadow's left part: the nearer object's own dropout (a glossy cylinder's) standing before it,
//! or a black surface the shadow partly falls on, which is a hole even if lit (OTHER, SPEC §1).
//! Depth cannot tell where the shadow stops showing; the RGB camera can. Over a shadow on the
//! wall it sees the wall (the room lights it, only the projector does not), over the rest
//! whatever that is. The tail starts at its first column that shows the wall's colour.

use super::{hue_dist, relabel, ColourSplit, COLOUR_STEP, SIDE};
use crate::labels::{DETACHED, NO_DEPTH, OTHER, WIDTH};

impl ColourSplit {
    /// Relabels OTHER the left part of the detached tail of the hole `[a, b)` of row `v` (OTHER
    /// from `a`, detached to `b`) that the RGB camera, looking at the wall Sb shows, does not
    /// see as that wall (see the module's docs).
    pub(super) fn tail_on_its_wall(
        &self,
        raw: &[u16],
        rgb: &[u8],
        labels: &mut [u8],
        v: usize,
        (a, b): (usize, usize),
    ) {
        let row = v * WIDTH;
        if b + SIDE > WIDTH || labels[row + b - 1] != DETACHED {
            return;
        }
        let Some(from) = labels[row + a..row + b].iter().position(|&l| l == DETACHED) else {
            return;
        };
        let from = a + from;
        // The wall the shadow lies on is Sb's surface, right of the hole.
        let sb = raw[row + b];
        // The rest must be wide enough for its colour to be read.
        if from < a + SIDE || sb == NO_DEPTH || !self.all_on_surface(raw, v, b..b + SIDE, sb) {
            return;
        }
        let (Some(wall), Some(rest)) = (
            self.mean_colour(rgb, v, b..b + SIDE, sb),
            self.mean_colour(rgb, v, a..from, sb),
        ) else {
            return;
        };
        // Where the rest looks like the wall (a dark wall, a pale dropout), colour cannot tell.
        let step = self.dimmed(COLOUR_STEP, wall);
        if hue_dist(rest, wall) < 2 * step {
            return;
        }
        let shows_wall = |p: [i32; 3]| {
            let (d_wall, d_rest) = (hue_dist(p, wall), hue_dist(p, rest));
            d_wall < step && 2 * d_wall <= d_rest
        };
        let start = (from..b)
            .find(|&u| self.probe(rgb, u, v, sb).is_some_and(shows_wall))
            .unwrap_or(b);
        relabel(&mut labels[row + from..row + start], DETACHED, OTHER);
    }
}
