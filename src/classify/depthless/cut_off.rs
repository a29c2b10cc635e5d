//! The part of a depthless occluder's attached shadow that a thin object standing in it cuts off.
//!
//! A thin rod standing in a black box's attached shadow, nearer than the wall, splits the
//! shadow's hole in two: the part between rod and box, which the colour split finds, and the
//! part left of the rod. The projector's rays to that left part pass the rod and meet the box,
//! so it is the box's shadow too, cut off from it: detached (SPEC §1). The scanline's
//! `cut_by_thin_occluder` reads this where the occluder has depth; without depth, only the shift
//! the colour split found tells how far left the shadow reaches. (A fresh suite, seed 14142,
//! scene 001: a cyan rod before a black box; complex IR detached F1 +0.0034, RGB attached
//! +0.0006; eight other suites and the real frame unchanged.)

use super::{ColourSplit, SAME_SURFACE};
use crate::labels::{ATTACHED, DETACHED, NO_DEPTH, OTHER, WIDTH};

/// Widest object (pixels) standing in a shadow that cuts part of it off: a rod, not a box (a
/// wider one's own shadow covers the part).
const THIN: usize = 8;
/// How far left of eq. (3)'s place (pixels) the cut-off part may start: the sensor's widening.
const WIDENED: usize = 3;

impl ColourSplit {
    /// Relabels DETACHED the hole left of a thin object standing right before the shadow
    /// `[s, occ)` of row `v` that the colour split found (its occluder from `occ`, `shift` px
    /// before the background at raw `bg`), where that hole lies within the shadow's full width.
    pub(super) fn cut_off_by_thin(
        &self,
        raw: &[u16],
        labels: &mut [u8],
        v: usize,
        (s, occ): (usize, usize),
        (bg, shift): (u16, usize),
    ) {
        let row = v * WIDTH;
        let d_bg = self.disp(bg);
        let nearer = |r: u16| r != NO_DEPTH && self.disp(r) > d_bg + SAME_SURFACE;
        let thin = (1..=THIN + 1)
            .map_while(|k| s.checked_sub(k))
            .take_while(|&u| nearer(raw[row + u]))
            .count();
        if thin == 0 || thin > THIN {
            return;
        }
        // The hole left of the thin object, closed by the background on its left.
        let b = s - thin;
        let a = b
            - (1..=b)
                .take_while(|&k| raw[row + b - k] == NO_DEPTH)
                .count();
        let start = occ.saturating_sub(shift + WIDENED);
        if a == b || a == 0 || a < start {
            return;
        }
        let left = raw[row + a - 1];
        if left == NO_DEPTH || (self.disp(left) - d_bg).abs() > SAME_SURFACE {
            return;
        }
        let span = &mut labels[row + a..row + b];
        if span.iter().all(|&l| l == OTHER || l == ATTACHED) {
            span.fill(DETACHED);
        }
    }
}
