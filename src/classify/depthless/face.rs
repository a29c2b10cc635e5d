//! An occluder's own face inside its attached shadow's hole.
//!
//! A box turned a little away from the camera shows its side face at a grazing angle; the
//! sensor returns no depth there, so the face joins the box's attached shadow in one hole, and
//! eq. (3) from the box's front edge fits the whole (the shadow, cast by the face's far edge, is
//! that much narrower). The face is the occluder, not background the projector missed: a hole
//! that would be one even if lit, OTHER (SPEC §1). The RGB camera sees it: read at the
//! occluder's depth, the hole's right end shows the occluder's colour, where a shadow on the
//! background would show the background's (at that depth the RGB camera looks just left of the
//! occluder's edge, past it). The face then takes the occluder's depths for the warp, so the RGB
//! view shows it beside the occluder too.
//!
//! A box's other side face, its right one, lies right of it: a hole between the box (Sa, the
//! nearer side) and whatever is behind (Sb). The scanline may read that hole as Sb's attached
//! shadow on a background the box hides (eq. 3 with a background found above the hole, a far
//! wall above a floor). Read at the box's depth, the face shows the box's colour where the
//! shadow would show the background's.

use super::{chroma_off, hue_dist, relabel, ColourSplit, COLOUR_STEP, SAME_SURFACE, SIDE};
use crate::labels::{ATTACHED, HEIGHT, NO_DEPTH, OTHER, WIDTH};

/// Columns at the hole's right end not read: the lens blends the occluder's edge into them.
const BLEND: usize = 1;
/// Fewest columns past the blend that must show the occluder: one column is noise.
const MIN_FACE: usize = 2;
/// Chromaticity difference (thousandths, summed over R, G, B) within which a pixel has the
/// occluder's hue.
const SAME_HUE: i32 = 40;
/// Brightness (R + G + B) under which a colour's chromaticity is the camera's noise.
const LIT: i32 = 90;
/// Chromaticity difference (thousandths) from which the occluder's hue alone tells its face,
/// however dark, from the wall. A mauve box's face in shade on a brown floor lies 108 to 137
/// from it row by row (a fifth simulator's scene, k31 s018): from 120, the face was split off in
/// some rows only. From 80, simple scenes' IR attached F1 +0.011 and any-shadow precision
/// +0.024, recall −0.003, summed over 32 suites of that simulator; complex precision +0.003,
/// recall −0.002; this project's suites unchanged.
const HUED: i32 = 2 * SAME_HUE;
/// Chromaticity difference (thousandths) within which a pixel still has the occluder's hue when
/// it lies [`HUE_RATIO`] times nearer the occluder's than the wall's: a face turned to a light of
/// another colour than its front's is tinted (a purple box's face 66 from its front, 400 from the
/// wall, in a fifth simulator's scene, k5 s018).
const TINTED_HUE: i32 = 2 * SAME_HUE;
/// How many times nearer the occluder's chromaticity than the wall's a tinted face's pixel lies.
const HUE_RATIO: i32 = 3;

/// Whether colour `p` is bright enough for its chromaticity to tell.
fn lit(p: [i32; 3]) -> bool {
    p.iter().sum::<i32>() >= LIT
}

/// How a glossy object's rim is told from what lies beside it: by colour, or by hue alone where
/// the rim, turned from the light, is darker than the object's middle.
#[derive(Clone, Copy)]
pub(super) struct RimColours {
    /// The object's colour (its measured pixels beside the rim).
    object: [i32; 3],
    /// The colour of what lies beside it (the wall, the background).
    other: [i32; 3],
    /// The colour step within which a colour is the object's.
    step: u32,
    /// Whether the hue tells the object from the other: both lit, their chromaticities two
    /// [`SAME_HUE`] apart.
    hued: bool,
}

impl RimColours {
    /// The colours of an object and what lies beside it, a colour `step` telling them apart.
    pub(super) fn new(object: [i32; 3], other: [i32; 3], step: u32) -> Self {
        let hued = lit(object) && lit(other) && chroma_off(object, other) >= 2 * SAME_HUE;
        RimColours {
            object,
            other,
            step,
            hued,
        }
    }

    /// Whether colour `p` shows the object: within the step of its colour and twice as near it
    /// as the other's, or (where the hue tells) lit and of its hue, twice as near it in hue.
    pub(super) fn shows_object(&self, p: [i32; 3]) -> bool {
        let (d_obj, d_other) = (hue_dist(p, self.object), hue_dist(p, self.other));
        (d_obj < self.step && 2 * d_obj <= d_other) || self.of_object_hue(p)
    }

    /// Whether colour `p` is, where the hue tells the object from the other colour, lit and of
    /// the object's hue, twice as near it in hue: the object however shaded.
    pub(super) fn of_object_hue(&self, p: [i32; 3]) -> bool {
        self.hued && lit(p) && {
            let to_object = chroma_off(p, self.object);
            to_object <= SAME_HUE && 2 * to_object <= chroma_off(p, self.other)
        }
    }

    /// Whether colour `p` is plainly not the object's: two steps off its colour, or (where the
    /// hue tells) lit and two [`SAME_HUE`] off its hue.
    pub(super) fn plainly_not_object(&self, p: [i32; 3]) -> bool {
        hue_dist(p, self.object) >= 2 * self.step
            || (self.hued && lit(p) && chroma_off(p, self.object) >= 2 * SAME_HUE)
    }
}

impl ColourSplit {
    /// Relabels OTHER the right end of the attached hole `[a, b)` of row `v` where the RGB
    /// camera sees the occluder (Sb, right of the hole) over it at the occluder's depth, and
    /// gives those pixels the face's depths in `filled` (see the module's docs).
    pub(super) fn occluder_face_in_hole(
        &self,
        raw: &[u16],
        rgb: &[u8],
        labels: &mut [u8],
        filled: &mut [u16],
        v: usize,
        (a, b): (usize, usize),
    ) {
        let row = v * WIDTH;
        let Some((sa, sb)) = hole_sides(raw, v, (a, b), BLEND + MIN_FACE + 1) else {
            return;
        };
        if self.disp(sb) < self.disp(sa) + SAME_SURFACE {
            return;
        }
        // Sb's first pixels are one surface (within a step of disparity of its edge): its colour
        // is read there.
        let on_sb = self.all_on_surface(raw, v, b..b + SIDE, sb);
        // A face is upright: the rows above and below end their hole at Sb's edge too (within
        // 2 px, a slanted edge). Where Sb's edge runs along the row (a box's bottom on a floor),
        // the RGB camera, a few millimetres lower, sees the box over the shadow's last row.
        let upright = |w: usize| {
            let r = &raw[w * WIDTH..(w + 1) * WIDTH];
            (b - 2..=b + 2).any(|e| r[e - 1] == NO_DEPTH && self.on_surface(r[e], sb))
        };
        if !on_sb || v == 0 || v + 1 >= HEIGHT || !upright(v - 1) || !upright(v + 1) {
            return;
        }
        let Some(occluder) = self.mean_colour(rgb, v, b + 1..b + SIDE, sb) else {
            return;
        };
        // Most attached holes show the wall there: two probes where the face must show, before
        // the wall's colour is read (a step as loose as a bright wall's: the test below is
        // dimmed by the wall, not by a dark occluder).
        let near = |p: [i32; 3]| {
            hue_dist(p, occluder) < self.dimmed(COLOUR_STEP, [255; 3])
                || chroma_off(p, occluder) <= SAME_HUE
        };
        if !(b - BLEND - MIN_FACE - 1..=b - BLEND - MIN_FACE)
            .any(|u| self.probe(rgb, u, v, sb).is_some_and(near))
        {
            return;
        }
        let Some(wall) = self.mean_colour(rgb, v, a - SIDE..a, sa) else {
            return;
        };
        let Some((step, hued)) = self.face_step(occluder, wall) else {
            return;
        };
        let shows_occluder = |p: [i32; 3]| {
            let (d_occ, d_wall) = (hue_dist(p, occluder), hue_dist(p, wall));
            (d_occ < step && 3 * d_occ <= d_wall && d_occ + step <= d_wall)
                || (hued && lit(p) && {
                    let (to_occluder, to_wall) = (chroma_off(p, occluder), chroma_off(p, wall));
                    (to_occluder <= SAME_HUE
                        || (to_occluder <= TINTED_HUE && HUE_RATIO * to_occluder <= to_wall))
                        && 2 * to_wall >= chroma_off(occluder, wall)
                })
        };
        // A column shows the occluder, and plainly not the wall, at Sb's depth or at the depth
        // of a far edge at `u` whose shadow starts at the hole's first pixel (eq. 3 with the
        // sensor's widening): the face recedes from Sb to that edge, and its far part shows in
        // the RGB image further right than Sb's depth puts it. (Left of the far edge both read
        // the wall: left of where the RGB camera sees the occluder's edge, at either depth.)
        let far_edge = |u: usize| {
            let d = self.disp(sa) + (u - a) as f64 - self.widen;
            (d > self.disp(sa) && d < self.disp(sb)).then(|| self.raw_at_disp(d))
        };
        let plainly_wall = |p: [i32; 3]| {
            let (d_occ, d_wall) = (hue_dist(p, occluder), hue_dist(p, wall));
            d_wall < step && 3 * d_wall <= d_occ
        };
        // Leftwards from the blend up to the first column that plainly shows the wall; the face
        // ends at the last column before it that shows the occluder. A face in shade is dark,
        // and the camera's noise puts a probe's chromaticity off now and then: most of the
        // columns must show the occluder, not all.
        let (mut face, mut shown) = (None, 0);
        for u in (a..b - BLEND).rev() {
            let at_sb = self.probe(rgb, u, v, sb);
            let at_far = || far_edge(u).and_then(|r| self.probe(rgb, u, v, r));
            if at_sb.is_some_and(shows_occluder) || at_far().is_some_and(shows_occluder) {
                (face, shown) = (Some(u), shown + 1);
            } else if at_sb.is_some_and(plainly_wall) {
                break;
            }
        }
        let face = face.filter(|&f| 3 * shown >= 2 * (b - BLEND - f));
        let Some(start) = face else {
            return;
        };
        // Some shadow is left (a hole that is all face is the occluder's dropout, which other
        // readings take).
        if b - BLEND - start < MIN_FACE || start <= a + 1 {
            return;
        }
        relabel(&mut labels[row + start..row + b], ATTACHED, OTHER);
        // The face lies at the occluder's depths: warped there, it hides the wall behind it in
        // the RGB view, as it does for the RGB camera. (At the wall's depth the occluder hid
        // the face instead, and the shadow showed where the camera sees the face.) It recedes
        // from Sb's edge to its far edge, whose shadow starts at `a` (eq. 3); each column is
        // taken at its centre.
        let near = self.disp(sb);
        let far = far_edge(start).map_or(near, |r| self.disp(r));
        let width = (b - start) as f64;
        for (k, f) in filled[row + start..row + b].iter_mut().enumerate() {
            *f = self.raw_at_disp(far + (near - far) * (k as f64 + 0.5) / width);
        }
    }

    /// Relabels OTHER the attached hole `[a, b)` of row `v` right of a nearer surface (Sa) where
    /// the RGB camera sees Sa's own colour over it at Sa's depth, and gives it Sa's depth in
    /// `filled` (see the module's docs).
    pub(super) fn near_side_face(
        &self,
        raw: &[u16],
        rgb: &[u8],
        labels: &mut [u8],
        filled: &mut [u16],
        v: usize,
        (a, b): (usize, usize),
    ) {
        let row = v * WIDTH;
        let Some((sa, sb)) = hole_sides(raw, v, (a, b), BLEND + MIN_FACE) else {
            return;
        };
        if self.disp(sa) < self.disp(sb) + SAME_SURFACE
            || !labels[row + a..row + b].iter().all(|&l| l == ATTACHED)
        {
            return;
        }
        // Both sides one surface each over a few pixels, their colours read there (Sa's but for
        // its edge's blended column).
        if !self.all_on_surface(raw, v, a - SIDE..a, sa)
            || !self.all_on_surface(raw, v, b..b + SIDE, sb)
        {
            return;
        }
        let Some(near) = self.mean_colour(rgb, v, a - SIDE..a - BLEND, sa) else {
            return;
        };
        // The background the shadow would lie on, as the scanline placed it: what the RGB camera
        // shows over the hole at that depth (the face itself in part, the rest beyond it).
        let Some(wall) = self.mean_colour(rgb, v, a..b, filled[row + a]) else {
            return;
        };
        let Some((step, hued)) = self.face_step(near, wall) else {
            return;
        };
        let shows_near = |p: [i32; 3]| {
            let (d_near, d_wall) = (hue_dist(p, near), hue_dist(p, wall));
            (d_near < step && 3 * d_near <= d_wall)
                || (hued && lit(p) && {
                    let (to_near, to_wall) = (chroma_off(p, near), chroma_off(p, wall));
                    to_near <= TINTED_HUE && HUE_RATIO * to_near <= to_wall
                })
        };
        // Half the columns past the edge's blend: a face in shade is dark and noisy (above).
        let cols = a + BLEND..b;
        let n = cols.len();
        let shown = cols
            .filter(|&u| self.probe(rgb, u, v, sa).is_some_and(shows_near))
            .count();
        if 2 * shown >= n {
            relabel(&mut labels[row + a..row + b], ATTACHED, OTHER);
            // The face recedes from Sa's edge; at Sa's depth the warp puts it beside Sa.
            filled[row + a..row + b].fill(sa);
        }
    }

    /// How a face of colour `face` is told from the wall of colour `wall`: the step within
    /// which a colour is the face's (as loose as the wall is dim: the tests that use it are
    /// dimmed by the wall, not by a dark occluder), and whether the face's hue alone tells it
    /// (it is turned from the front face, and lit otherwise). `None` when neither colour nor
    /// hue does.
    fn face_step(&self, face: [i32; 3], wall: [i32; 3]) -> Option<(u32, bool)> {
        let step = self.dimmed(COLOUR_STEP, wall);
        let hued = chroma_off(face, wall) >= HUED && lit(face);
        (hue_dist(face, wall) >= 2 * step || hued).then_some((step, hued))
    }
}

/// Sa and Sb, the measured pixels either side of the hole `[a, b)` of row `v`, where the hole is
/// at least `min` pixels wide and [`SIDE`] pixels on each side of it lie in the image.
fn hole_sides(raw: &[u16], v: usize, (a, b): (usize, usize), min: usize) -> Option<(u16, u16)> {
    let row = v * WIDTH;
    if a < SIDE || b + SIDE > WIDTH || b - a < min {
        return None;
    }
    let (sa, sb) = (raw[row + a - 1], raw[row + b]);
    (sa != NO_DEPTH && sb != NO_DEPTH).then_some((sa, sb))
}
