//! A depthless rod standing in a nearer object's attached shadow.
//!
//! A black or glossy rod before a box's left edge covers most of the box's attached shadow on
//! the wall: in the IR image its hole and what shows of that shadow make one hole between the
//! wall (Sa) and the box (Sb), as wide as eq. (3) says the box's shadow is, so the scanline
//! calls it all attached. The rod's own detached shadow lies left of it on the wall, past a lit
//! gap, as an OTHER hole of about the rod's width. The RGB camera tells the two readings apart:
//! over a shadow on the wall it sees the wall (the room lights it), and over the rod it sees the
//! rod. Where the hole's first pixels, seen at the depth the left hole's shift gives them, are
//! plainly not the wall, while the left hole shows the wall, they are the rod (OTHER, placed at
//! that depth) and the left hole its detached shadow; the rest stays the box's shadow.
//! (An independent simulator's scene: a glossy rod at 0.75 m before a box at 0.86 m, 30 000
//! pixels of the rod's shadow OTHER and of the rod attached.)

use super::{hue_dist, relabel, ColourSplit, COLOUR_STEP, SAME_SURFACE, SIDE};
use crate::labels::{ATTACHED, DETACHED, NO_DEPTH, OTHER, WIDTH};

/// Narrowest left hole (pixels) read as a rod's shadow: narrower ones are speckle.
const MIN_SHADOW: usize = 8;
/// Widest lit gap (pixels) between the rod's shadow and the attached hole.
const MAX_GAP: usize = 48;
/// Pixels past its shadow's width that the rod's image may reach.
const EDGE_SLACK: usize = 4;
/// Pixels of the box's shadow the hole must keep past the rod: with none, the hole is the rod's
/// (the pairing of depthless occluders reads that).
const MIN_REST: usize = 2;

impl ColourSplit {
    /// Splits the attached hole `[a, b)` of row `v` into a depthless rod and what shows of the
    /// nearer Sb's shadow, and makes the OTHER hole left of it the rod's detached shadow (see the
    /// module's docs). True when it did.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn rod_in_shadow(
        &self,
        raw: &[u16],
        rgb: &[u8],
        labels: &mut [u8],
        filled: &mut [u16],
        v: usize,
        (a, b): (usize, usize),
    ) -> bool {
        let row = v * WIDTH;
        if a < SIDE + 2 || b >= WIDTH {
            return false;
        }
        let (sa, sb) = (raw[row + a - 1], raw[row + b]);
        if sa == NO_DEPTH || sb == NO_DEPTH || self.disp(sb) - self.disp(sa) <= SAME_SURFACE {
            return false;
        }
        let d_bg = self.disp(sa);
        let on_bg = |u: usize| {
            let r = raw[row + u];
            r != NO_DEPTH && (self.disp(r) - d_bg).abs() < SAME_SURFACE
        };
        // The lit gap, then the left hole, OTHER throughout, with the wall before it.
        let gap = (1..=MAX_GAP.min(a)).take_while(|&k| on_bg(a - k)).count();
        if gap == 0 || gap == MAX_GAP.min(a) || raw[row + a - gap - 1] != NO_DEPTH {
            return false;
        }
        let h0b = a - gap;
        let w0 = (1..=h0b)
            .take_while(|&k| raw[row + h0b - k] == NO_DEPTH)
            .count();
        let h0a = h0b - w0;
        if w0 < MIN_SHADOW
            || h0a < SIDE
            || !(h0a - SIDE..h0a).all(on_bg)
            || !labels[row + h0a..row + h0b].iter().all(|&l| l == OTHER)
            || !labels[row + a..row + b]
                .iter()
                .zip(&raw[row + a..row + b])
                .all(|(&l, &r)| r != NO_DEPTH || l == ATTACHED)
        {
            return false;
        }
        // The rod: as wide as its shadow but for the widening, shifted by the left edges.
        let rod = w0
            .saturating_sub(self.widen.round() as usize)
            .max(MIN_SHADOW / 2);
        if a + rod + MIN_REST > b {
            return false;
        }
        let shift = (a - h0a) as f64 - self.widen;
        let at = self.raw_at_disp(d_bg + shift);
        // The same layout in the rows above and below (a rod stands over many rows); the row
        // above may have been split so already.
        let repeats = |w: usize| {
            let i = w * WIDTH;
            let lit = raw[i + a - gap / 2 - 1];
            let (shadow, hole) = (labels[i + h0a + w0 / 2], labels[i + a + rod / 2]);
            (shadow == OTHER || shadow == DETACHED)
                && (hole == ATTACHED || hole == OTHER)
                && raw[i + h0a + w0 / 2] == NO_DEPTH
                && raw[i + a + rod / 2] == NO_DEPTH
                && lit != NO_DEPTH
                && (self.disp(lit) - d_bg).abs() < SAME_SURFACE
        };
        if !repeats(v - 1) || !repeats(v + 1) {
            return false;
        }
        // The wall before the left hole, the left hole itself at the wall's depth, and the rod
        // at its own.
        let Some(wall) = self.mean_colour(rgb, v, h0a - SIDE..h0a, sa) else {
            return false;
        };
        let step = self.dimmed(COLOUR_STEP, wall);
        // Most probes (the camera's noise, a glossy rod's highlight) plainly so.
        // (Read until a quarter of them have said no: most attached holes are no rod's.)
        let most = |cols: std::ops::Range<usize>, raw: u16, like: bool| {
            let n = cols.len().div_ceil(2);
            let mut no = 0;
            for u in cols.step_by(2) {
                let Some(p) = self.probe(rgb, u, v, raw) else {
                    return false;
                };
                no += usize::from((hue_dist(p, wall) < step) != like);
                if 4 * no > n {
                    return false;
                }
            }
            n > 0
        };
        if !most(a + 1..a + rod - 1, at, false) || !most(h0a + 1..h0b - 1, sa, true) {
            return false;
        }
        // The rod's right edge: where the RGB camera stops seeing it (a round rod's shadow may be
        // narrower than its image), a few pixels past its shadow's width at most.
        let mut end = a + rod;
        while end + MIN_REST < b
            && end < a + w0 + EDGE_SLACK
            && self
                .probe(rgb, end, v, at)
                .is_some_and(|p| hue_dist(p, wall) >= step)
        {
            end += 1;
        }
        relabel(&mut labels[row + h0a..row + h0b], OTHER, DETACHED);
        relabel(&mut labels[row + a..row + end], ATTACHED, OTHER);
        filled[row + a..row + end].fill(at);
        true
    }
}
