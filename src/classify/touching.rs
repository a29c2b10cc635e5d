//! Detached shadows that touch their occluder made attached: one pass over the IR view's settled
//! labels.
//!
//! SPEC §1: an attached shadow is a hole that touches its occluder; a detached one is cast by a
//! thin occluder that leaves visible background between shadow and occluder. A rod narrower than
//! its shift by a pixel or two leaves a lit gap that the sensor's correlation window swallows in
//! most rows: the hole then runs from the shadow into the rod, and no background shows. The
//! readings before this pass call those rows detached (the rod is thin, eqs. 4–5, and the gap
//! seen in a row nearby is evidence their neighbours share); here each row is judged by what it
//! shows. A run of shadow labels that starts a hole after a measured pixel (Sa) and holds
//! DETACHED becomes ATTACHED when the first surface past it, over any other hole (a black
//! poster the gap fell on), is nearer than Sa and able to cast it: the run and that hole span
//! its shift (eq. 3) less the widening, and no more than an attached shadow may. That surface
//! may be an occluder without depth, where the colour split placed its depth. Also the few
//! pixels past a lit gap's island, the widening's, before the occluder. A run that mixes both
//! kinds is another object's shadow cut off by this one unless its end was read attached. Rows
//! where the gap shows keep DETACHED: the first surface past them is the lit background.
//!
//! Two of the three simulators written from SPEC alone label those rows so (a thin rod's row
//! whose lit gap the widening closed is attached; the fifth did not), and so does the paper's
//! scanline, which reads the hole's width against eq. (3). This project's simulator does since
//! 2026-12-08. Complex scenes, the seventh simulator's eight suites: IR attached F1 +0.100
//! summed, detached +0.489, RGB attached +0.098 (with [`super::consensus::settle_apart`]); its
//! simple ones +0.034, +0.471. This project's fourteen suites, their truth made again: complex
//! +0.350, +0.830, RGB +0.356; simple +0.164, +0.981. Any-shadow precision and recall within
//! 0.0008 on all. The real frame: 3 pixels.

use super::scanline::{ScanParams, SWALLOWED_GAP_SLACK};
use crate::labels::{ATTACHED, DETACHED, NO_DEPTH, WIDTH};

/// Relabels ATTACHED each run of DETACHED in `labels` (whole rows of [`WIDTH`]) that touches a
/// surface able to cast it, as the module docs say. `raw` is the frame, `filled` its holes'
/// assumed depths (raw values) where the readings placed one.
pub fn attach_touching(p: &ScanParams, raw: &[u16], filled: &[u16], labels: &mut [u8]) {
    let shadow = |l: u8| l == ATTACHED || l == DETACHED;
    for (v, row) in labels.chunks_exact_mut(WIDTH).enumerate() {
        if next_detached(row, 0).is_none() {
            continue;
        }
        let raw = &raw[v * WIDTH..(v + 1) * WIDTH];
        let filled = &filled[v * WIDTH..(v + 1) * WIDTH];
        let mut from = 0;
        // Each run of shadow labels in a hole that holds DETACHED, found from its DETACHED
        // pixels (a frame's rows are mostly without), must start the hole after a measured pixel.
        while let Some(d) = next_detached(row, from) {
            let in_run = |x: usize| shadow(row[x]) && raw[x] == NO_DEPTH;
            let start = (0..d).rev().find(|&x| !in_run(x)).map_or(0, |x| x + 1);
            let u = (d..WIDTH).find(|&x| !in_run(x)).unwrap_or(WIDTH);
            from = u.max(d + 1);
            // A run that mixes both kinds is one shadow only where its end, touching, was read
            // attached (the start may be another object's shadow, cut off by this one).
            if u == d
                || start == 0
                || u == WIDTH
                || raw[start - 1] == NO_DEPTH
                || (row[start..u].contains(&ATTACHED) && row[u - 1] != ATTACHED)
            {
                continue;
            }
            // The next pixel measured or placed (an occluder without depth the colour split
            // read) past any other hole (a black poster the gap fell on) must be nearer than the
            // surface the run lies on.
            let sa = raw[start - 1];
            let placed =
                |x: usize| filled[x] != NO_DEPTH && p.disp(filled[x]) > p.disp(sa) + p.min_step();
            let Some(end) = (u..WIDTH).find(|&x| raw[x] != NO_DEPTH || placed(x)) else {
                continue;
            };
            let next = if raw[end] == NO_DEPTH {
                filled[end]
            } else {
                raw[end]
            };
            let (shift, width, reach) = (
                p.disp(next) - p.disp(sa),
                (u - start) as f32,
                (end - start) as f32,
            );
            // Past a lit gap's island (a pixel or two of the shadow's own surface measured right
            // after it), the rest of the hole, a few pixels, is the widening's.
            let island = width <= SWALLOWED_GAP_SLACK
                && (2..=3).any(|k| {
                    start > k
                        && raw[start - k] == NO_DEPTH
                        && shadow(row[start - k])
                        && raw[start - k + 1..start].iter().all(|&r| r != NO_DEPTH)
                        && raw[..start - k]
                            .iter()
                            .rev()
                            .find(|&&r| r != NO_DEPTH)
                            .is_some_and(|&r| (p.disp(r) - p.disp(sa)).abs() < 2.0 * p.min_step())
                });
            if shift > p.min_step()
                && (island || (reach + SWALLOWED_GAP_SLACK >= shift && reach <= shift + p.over()))
            {
                for l in &mut row[start..u] {
                    *l = ATTACHED;
                }
            }
        }
    }
}

/// The first DETACHED pixel of `row` from column `from` on. Most of a frame holds none: the
/// row is passed over 64 bytes at a time with a branch-free (vectorised) test.
fn next_detached(row: &[u8], from: usize) -> Option<usize> {
    let mut at = from;
    while at < row.len() {
        let end = ((at / 64 + 1) * 64).min(row.len());
        let chunk = &row[at..end];
        if chunk.iter().fold(false, |any, &l| any | (l == DETACHED)) {
            return chunk.iter().position(|&l| l == DETACHED).map(|k| at + k);
        }
        at = end;
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::calib::Calibration;
    use crate::classify::Params;
    use crate::labels::OTHER;

    /// One row: wall at raw 960, a hole, then `after` (the pixel right of the hole, raw) and the
    /// wall again; the hole's labels given, the filled map equal to the raw one.
    fn row(hole: &[u8], after: u16) -> (Vec<u16>, Vec<u8>) {
        let mut raw = vec![960u16; WIDTH];
        let mut labels = vec![crate::labels::VALID; WIDTH];
        raw[100..100 + hole.len()].fill(NO_DEPTH);
        labels[100..100 + hole.len()].copy_from_slice(hole);
        raw[100 + hole.len()..100 + hole.len() + 4].fill(after);
        (raw, labels)
    }

    fn pass(raw: &[u16], labels: &mut [u8]) {
        let calib = Calibration::nyu_default();
        let p = ScanParams::new(&calib, &Params::default());
        attach_touching(&p, raw, raw, labels);
    }

    /// A rod at raw 900 before the wall at 960: shift (960 − 900) · f·b / 351.3 ≈ 7.5 px on the
    /// NYU calibration (eq. 3). A detached run of 7 px reaching it touches it: attached. One of
    /// 2 px cannot be its shadow (the rod's ray lit the wall there): it stays.
    #[test]
    fn a_detached_run_touching_a_rod_that_can_cast_it_becomes_attached() {
        let calib = Calibration::nyu_default();
        let shift = calib.px_per_raw() * 60.0;
        assert!((7.0..8.0).contains(&shift), "{shift}");
        let (raw, mut labels) = row(&[DETACHED; 7], 900);
        pass(&raw, &mut labels);
        assert_eq!(&labels[100..107], &[ATTACHED; 7]);
        let (raw, mut labels) = row(&[DETACHED; 2], 900);
        pass(&raw, &mut labels);
        assert_eq!(&labels[100..102], &[DETACHED; 2]);
    }

    /// Where the lit gap shows (the next measured pixel lies on the wall), the run stays detached,
    /// after another hole or not; where only another hole (OTHER: the gap fell on a black poster)
    /// lies between it and the rod, it touches the rod.
    #[test]
    fn a_detached_run_before_the_lit_gap_stays_one_past_another_hole_touches() {
        let (raw, mut labels) = row(&[DETACHED; 7], 961);
        pass(&raw, &mut labels);
        assert_eq!(&labels[100..107], &[DETACHED; 7], "the gap shows");
        let mut hole = [DETACHED; 9];
        hole[7..].fill(OTHER);
        for (after, code) in [(961, DETACHED), (900, ATTACHED)] {
            let (raw, mut labels) = row(&hole, after);
            pass(&raw, &mut labels);
            assert_eq!(&labels[100..107], &[code; 7], "past another hole: {after}");
            assert_eq!(&labels[107..109], &[OTHER; 2]);
        }
    }

    /// A hole whose start is attached to something else and whose end is detached (another
    /// object's shadow cut off by the rod's) keeps its detached part; the same hole read attached
    /// at its end is one shadow.
    #[test]
    fn a_mixed_run_is_one_shadow_only_where_its_end_was_read_attached() {
        let mut hole = [DETACHED; 8];
        hole[..3].fill(ATTACHED);
        let (raw, mut labels) = row(&hole, 900);
        pass(&raw, &mut labels);
        assert_eq!(&labels[100..108], &hole);
        hole[6..].fill(ATTACHED);
        let (raw, mut labels) = row(&hole, 900);
        pass(&raw, &mut labels);
        assert_eq!(&labels[100..108], &[ATTACHED; 8]);
    }

    /// Placed depth counts as a surface only where the colour split put an occluder there,
    /// nearer than the shadow's surface: a hole's fill at the background's depth is passed over.
    #[test]
    fn an_occluder_without_depth_is_found_by_its_placed_depth() {
        let mut hole = [DETACHED; 9];
        hole[7..].fill(OTHER);
        let (raw, mut labels) = row(&hole, 961);
        let calib = Calibration::nyu_default();
        let p = ScanParams::new(&calib, &Params::default());
        let mut filled = raw.clone();
        filled[107..109].fill(960);
        attach_touching(&p, &raw, &filled, &mut labels);
        assert_eq!(&labels[100..107], &[DETACHED; 7]);
        filled[107..109].fill(900);
        attach_touching(&p, &raw, &filled, &mut labels);
        assert_eq!(&labels[100..107], &[ATTACHED; 7]);
    }
}
