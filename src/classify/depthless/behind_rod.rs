//! Attached shadows of depthless occluders seen through to a thin object standing before them.
//!
//! A rod before a black (or glossy) box cuts the box's hole: in the rows it crosses, the hole that
//! starts with the box's attached shadow on the wall ends at the rod, a nearer surface. If its
//! width happens to fit eq. (3) for the rod, the scanline calls all of it the rod's attached
//! shadow, the box's face included. The RGB camera tells them apart: the rod's own shadow shows the
//! wall up to where the RGB camera sees the rod; the box's shadow shows the wall only up to where
//! it sees the box, which the rod does not hide. So the hole is read as the colour split reads a
//! hole that runs on into a nearer surface: background, then an occluder, both left of where the
//! RGB camera sees the rod. Where that finds an occluder, farther than the rod, after a shadow
//! shorter than the hole, the rest of the hole is that occluder (OTHER, at its depth).
//!
//! Only where the rod is thin and the hole of the box goes on beyond it, which keeps it off the
//! attached shadows of rods before a wall.

use super::{relabel, ColourSplit, Prefix, SAME_SURFACE};
use crate::labels::{ATTACHED, NO_DEPTH, OTHER, WIDTH};

/// Occluder pixels the split must leave at the hole's end: fewer are an edge's blend.
const MIN_OCCLUDER: usize = 4;

impl ColourSplit {
    /// Splits the attached hole `[a, b)` of row `v` into the attached shadow of a depthless
    /// occluder and that occluder, when a thin nearer surface closing the hole stands before it
    /// (see the module's docs). True when it did.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn occluder_behind_thin_sb(
        &self,
        raw: &[u16],
        rgb: &[u8],
        labels: &mut [u8],
        filled: &mut [u16],
        v: usize,
        (a, b): (usize, usize),
        prefix: &mut Prefix,
    ) -> bool {
        let row = v * WIDTH;
        if a == 0 || b >= WIDTH || b - a < super::MIN_HOLE {
            return false;
        }
        let (sa, sb) = (raw[row + a - 1], raw[row + b]);
        if sa == NO_DEPTH || sb == NO_DEPTH || self.disp(sb) - self.disp(sa) <= SAME_SURFACE {
            return false;
        }
        // The hole goes on beyond Sb, and the whole hole is the scanline's one attached shadow.
        if self.hole_beyond(labels, v, b, false).is_none()
            || raw[row + a..row + b]
                .iter()
                .zip(&labels[row + a..row + b])
                .any(|(&r, &l)| r == NO_DEPTH && l != ATTACHED)
        {
            return false;
        }
        // Read as the colour split reads an open hole ending at a nearer surface (its shadow
        // labels let through, as in a neighbouring row's candidate).
        let split = self
            .candidate(raw, labels, v, (a, b), true, false)
            .filter(|c| !c.closed && c.b == b && c.nearer_right == Some(sb))
            .and_then(|c| Some((c, self.agreed_split(raw, rgb, labels, v, c, prefix)?)))
            .map(|(_, (s, shift))| (s, self.disp(sa) + shift as f64 - self.widen))
            .filter(|&(s, d)| a + s + MIN_OCCLUDER <= b && d < self.disp(sb) - SAME_SURFACE);
        let Some((s, d)) = split else {
            return false;
        };
        relabel(&mut labels[row + a + s..row + b], ATTACHED, OTHER);
        filled[row + a + s..row + b].fill(self.raw_at_disp(d));
        true
    }
}
