//! Attached shadows beside a patch of the background that returns no depth.
//!
//! A black or glossy poster on the wall just left of a nearer object's attached shadow merges
//! with that shadow into one hole, too wide for eq. (3) between Sa (the wall) and Sb (the
//! object), which the scanline leaves OTHER. The RGB camera sees the wall in the shadow (lit by
//! the room, only not by the projector) and the poster left of it: the pixels from the hole's
//! right end leftwards that show Sa's colour, up to a clear step to another colour, are the
//! shadow, when eq. (3) with the sensor's widening puts its left end at or left of that step.
//! Sa's colour beside the hole only finds the shadow's first pixels; the step is read against
//! the shadow's own colour (a wide patch puts the two 100 px apart, and a wall's texture and
//! light drift that far: holdout complex IR attached F1 +0.0011, the other suites within
//! ±0.0001, the real frame unchanged).
//! A hole onto a farther surface (a wall beyond range seen past Sa's edge) shows that surface's
//! colour over the shadow, which may be Sa's too (walls painted alike): so the same shadow must
//! also show plainly, Sb's attached shadow on Sa's surface, in a row above or below the patch.
//! (Without that, this project's seed 5150 lost 0.004 IR attached F1 to such walls.)
//! A round Sb (a sphere) hides more of the wall from the RGB camera than its edge at Sb's depth
//! says, its nearer middle standing out past the limb: the first columns read may still show
//! it. A lit island inside the part read is a gap between two shadows (a rod's detached one
//! left of Sb's): no reading. The part of the hole left of the shadow is then read by the
//! colour split like any other hole (a depthless occluder's own shadow may lie there).

use super::{hue_dist, relabel, ColourSplit, COLOUR_STEP, SIDE};
use crate::labels::{ATTACHED, HEIGHT, NO_DEPTH, OTHER, WIDTH};

/// Narrowest shadow (eq. 3, pixels) looked for.
const MIN_SHADOW: f64 = 3.0;
/// Colour distance ([`hue_dist`], dimmed) within which a pixel shows Sa's surface.
const WALL: u32 = COLOUR_STEP / 2;
/// RGB columns left of where the RGB camera sees Sb's edge that are not read (its blend).
const PAST_SB: f64 = 2.0;
/// Colour distance ([`hue_dist`], dimmed) of the patch from Sa's surface: a glossy poster on a
/// wall of a like tone reads 75 to 110 from it.
const PATCH: u32 = 60;
/// Pixels over which the lens blends the patch's edge into the wall.
const BLEND: usize = 4;
/// Rows above and below in which [`ColourSplit::shadow_past_patch`] looks for the shadow: from
/// the middle of a poster 1.6 m tall 3 m away. (At 64, the test's poster of 1 m lost its
/// middle rows.)
const CLEAR_ROWS: usize = 160;
/// Pixels Sb's edge may move between that row and this one.
const MAX_SLANT: usize = 16;

impl ColourSplit {
    /// Relabels ATTACHED the right part of the OTHER hole `[a, b)` of row `v` that the RGB camera
    /// sees as Sa's surface, when it is Sb's attached shadow beside a patch without depth (see
    /// the module's docs). True when it did.
    pub(super) fn shadow_beside_patch(
        &self,
        raw: &[u16],
        rgb: &[u8],
        labels: &mut [u8],
        v: usize,
        (a, b): (usize, usize),
    ) -> bool {
        let row = v * WIDTH;
        if a < SIDE || b >= WIDTH {
            return false;
        }
        let (sa, sb) = (raw[row + a - 1], raw[row + b]);
        if sa == NO_DEPTH || sb == NO_DEPTH {
            return false;
        }
        // Eq. (3): Sb's shadow on Sa's surface; the hole is wider than it may look.
        let w = self.disp(sb) - self.disp(sa);
        if w < MIN_SHADOW || ((b - a) as f64) <= w + self.over {
            return false;
        }
        let Some(wall) = self.mean_colour(rgb, v, a - SIDE..a, sa) else {
            return false;
        };
        let (agree, step) = (self.dimmed(WALL, wall), self.dimmed(PATCH, wall));
        // The RGB camera sees Sb over the shadow's right part: read from where it no longer does.
        let edge = self.project(b as f64 - 0.5, v, sb).0 - PAST_SB;
        let mut u = b - 1;
        while u > a && self.project(u as f64, v, sa).0 > edge {
            u -= 1;
        }
        let first = b as f64 - w;
        if (u as f64) < first {
            return false;
        }
        // Leftwards from there while the wall shows (two pixels at least).
        let far = |x: usize| {
            self.probe(rgb, x, v, sa)
                .map_or(u32::MAX, |c| hue_dist(c, wall))
        };
        // A round occluder's outline as the RGB camera sees it lies further left than its edge
        // at Sb's depth puts it (its nearer middle hides more of the wall): skip up to a third
        // of the shadow of it.
        let Some(u) = (0..=(w / 3.0) as usize)
            .map_while(|k| u.checked_sub(k).filter(|&x| x > a))
            .find(|&x| far(x) <= agree)
        else {
            return false;
        };
        // From there on the wall's colour is the shadow's own: a wide patch puts the wall beside
        // the hole far from the shadow, and the wall's texture and light drift over that.
        let Some(shade) = self.probe(rgb, u, v, sa) else {
            return false;
        };
        let off_shade = |x: usize| {
            self.probe(rgb, x, v, sa)
                .map_or(u32::MAX, |c| hue_dist(c, shade))
        };
        let mut c = u;
        while c > a && off_shade(c - 1) <= agree {
            c -= 1;
        }
        // A lens blends the edge over a few columns: the other colour within BLEND of it, and on
        // average over the patch.
        if u - c < 1 || c < a + BLEND + 1 || (c - BLEND..c).all(|x| off_shade(x) <= step) {
            return false;
        }
        let patch = (a..c - BLEND)
            .map(|x| off_shade(x).min(4 * step))
            .sum::<u32>();
        if patch < step * (c - BLEND - a) as u32 {
            return false;
        }
        // A lit island inside is a gap between two shadows: Sb's ends there.
        if raw[row + c..row + b].iter().any(|&r| r != NO_DEPTH) {
            return false;
        }
        // The widening moves the shadow's left end further left, never right.
        if (c as f64) < first - self.over - self.widen {
            return false;
        }
        // A wall beyond range seen past Sa's edge may show Sa's colour too: the same shadow must
        // show plainly, Sb's on Sa, in a row past the patch's end.
        if !self.shadow_past_patch(raw, labels, v, b, sa) {
            return false;
        }
        relabel(&mut labels[row + c..row + b], OTHER, ATTACHED);
        true
    }

    /// Whether a row within [`CLEAR_ROWS`] of `v` holds an ATTACHED hole ending near `b` (at Sb's
    /// edge, whatever its depth there: a box's side seen at a slant starts at another depth in
    /// each row) whose left side is Sa's surface (raw `sa`).
    fn shadow_past_patch(&self, raw: &[u16], labels: &[u8], v: usize, b: usize, sa: u16) -> bool {
        let on_sa = |r: u16| self.on_surface(r, sa);
        // Sb's edge may slant, up to half a pixel a row and MAX_SLANT pixels in all.
        let plain = |w: usize, d: usize| {
            let (r, l) = (
                &raw[w * WIDTH..(w + 1) * WIDTH],
                &labels[w * WIDTH..(w + 1) * WIDTH],
            );
            let slack = 2 + (d / 2).min(MAX_SLANT);
            (b.saturating_sub(slack)..(b + slack + 1).min(WIDTH)).any(|e| {
                if e == 0 || r[e - 1] != NO_DEPTH || r[e] == NO_DEPTH || l[e - 1] != ATTACHED {
                    return false;
                }
                let start = r[..e]
                    .iter()
                    .rposition(|&x| x != NO_DEPTH)
                    .map_or(0, |k| k + 1);
                start > 0 && on_sa(r[start - 1]) && l[start..e].iter().all(|&x| x == ATTACHED)
            })
        };
        (1..=CLEAR_ROWS).any(|d| (d <= v && plain(v - d, d)) || (v + d < HEIGHT && plain(v + d, d)))
    }
}
