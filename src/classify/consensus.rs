//! Vertical consensus of hole labels: one pass over a finished label map.
//!
//! Each row is decided on its own (the scanline, the colour split), and a row's evidence can be
//! bad where its neighbours' is good: speckle inside a shadow, a noisy bound, the widening
//! swallowing a lit gap in one row. Shadows are solids in the image, continuous from row to row,
//! so a hole pixel whose rows above and below agree on another shadow label takes theirs, and so
//! does a run of up to three rows (`MAX_GAP_ROWS`; left OTHER, or given the other shadow label)
//! between the same shadow label above and below. Valid pixels never change and no pixel
//! becomes valid, so shadows only trade labels inside holes.
//! No shadow label is taken away: a row that found a shadow had the evidence for it, while its
//! neighbours may have had none (a colour edge the RGB camera sees only in some rows, say).
//! Applied to the IR view's finished labels before the warp carries them over, and to the RGB
//! view's after it (15 to 18 µs each on the NYU frame; the RGB pass: +0.002 to +0.006 of
//! complex scenes' alignment F1, −0.001 to −0.002 of their RGB any-shadow precision, simple
//! scenes unchanged or better).

use crate::labels::{OTHER, VALID, WIDTH};

/// Most rows in a run of hole pixels that the same shadow label above and below bridges. Rows
/// fail in short runs, not only alone: bridging up to 3 rows left OTHER gained 0.001 to 0.008 of
/// complex scenes' IR any-shadow recall for 0.000 to 0.003 of precision (10 suites), and runs of
/// the other shadow label a further 0.001 to 0.004 of detached F1; 4 rows bought little more
/// recall for more precision.
const MAX_GAP_ROWS: usize = 3;

/// Settles disagreements in `labels` (whole rows of [`WIDTH`]), top to bottom: a row is judged
/// against the row above as already settled, and the rows below as they are.
pub fn settle(labels: &mut [u8]) {
    const CHUNK: usize = 64;
    let rows = labels.len() / WIDTH;
    for v in 1..rows.saturating_sub(1) {
        let (head, tail) = labels.split_at_mut(v * WIDTH);
        let above = &head[(v - 1) * WIDTH..];
        let (row, rest) = tail.split_at_mut(WIDTH);
        let rest: &[u8] = rest;
        for (k, (row, above)) in row.chunks_mut(CHUNK).zip(above.chunks(CHUNK)).enumerate() {
            // Most of a frame is valid, and a pixel can change only below a shadow label it does
            // not share: skip stretches with neither (branch-free tests, vectorised).
            if row.iter().fold(true, |all, &m| all & (m == VALID)) {
                continue;
            }
            let open = |(&m, &a): (&u8, &u8)| (a != VALID) & (a != OTHER) & (m != a) & (m != VALID);
            if !row.iter().zip(above).fold(false, |any, p| any | open(p)) {
                continue;
            }
            for (j, (l, &a)) in row.iter_mut().zip(above).enumerate() {
                if open((l, &a)) && bridged(rest, k * CHUNK + j, *l, a) {
                    *l = a;
                }
            }
        }
    }
}

/// True when column `u` of the rows in `rest` (those below the current row, whose label there
/// is `run`) goes on with `run` for fewer than [`MAX_GAP_ROWS`] rows in all, then shows `label`.
fn bridged(rest: &[u8], u: usize, run: u8, label: u8) -> bool {
    rest.iter()
        .skip(u)
        .step_by(WIDTH)
        .take(MAX_GAP_ROWS)
        .find(|&&l| l != run)
        == Some(&label)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::labels::{ATTACHED, DETACHED};

    fn frame(rows: &[[u8; 4]]) -> Vec<u8> {
        rows.iter()
            .flat_map(|r| {
                let mut row = vec![VALID; WIDTH];
                row[100..104].copy_from_slice(r);
                row
            })
            .collect()
    }

    /// The four columns of [`frame`]`(rows)` after [`settle`], top to bottom.
    fn settled_columns(rows: &[[u8; 4]]) -> [Vec<u8>; 4] {
        let mut labels = frame(rows);
        settle(&mut labels);
        std::array::from_fn(|u| {
            (0..rows.len())
                .map(|v| labels[v * WIDTH + 100 + u])
                .collect()
        })
    }

    #[test]
    fn a_row_that_disagrees_with_both_neighbours_takes_their_shadow_label() {
        let (a, d, o, z) = (ATTACHED, DETACHED, OTHER, VALID);
        let mut labels = frame(&[
            [z, d, d, z],
            [z, o, a, z], // one noisy row inside a detached shadow
            [z, d, d, z],
            [z, z, z, z],
            [z, o, o, z],
            [z, a, d, z], // OTHER above and below: keeps its shadow labels
            [z, o, o, z],
            [z, z, z, z],
            [z, a, d, a],
            [z, d, a, d], // neighbours disagree, or are valid
            [z, d, a, z], // the last row has no row below
        ]);
        settle(&mut labels);
        let row = |v: usize| &labels[v * WIDTH + 100..v * WIDTH + 104];
        assert_eq!(row(0), &[z, d, d, z], "the first row has no row above");
        assert_eq!(row(1), &[z, d, d, z]);
        assert_eq!(row(5), &[z, a, d, z]);
        assert_eq!(row(9), &[z, d, a, d]);
        assert_eq!(row(10), &[z, d, a, z]);
    }

    #[test]
    fn a_run_of_up_to_three_other_rows_between_one_shadow_label_takes_it() {
        let (a, d, o, z) = (ATTACHED, DETACHED, OTHER, VALID);
        let column = settled_columns(&[
            [a, d, a, a],
            [o, o, o, o],
            [o, o, o, o],
            [o, d, o, o],
            [a, z, d, o],
            [z, z, a, o],
            [z, z, z, a],
        ]);
        // Three OTHER rows between ATTACHED above and below.
        assert_eq!(column[0], [a, a, a, a, a, z, z]);
        // Two between DETACHED and DETACHED.
        assert_eq!(column[1], [d, d, d, d, z, z, z]);
        // ATTACHED above, DETACHED below: no consensus.
        assert_eq!(column[2], [a, o, o, o, d, a, z]);
        // Five OTHER rows: too long a run to bridge.
        assert_eq!(column[3], [a, o, o, o, o, o, a]);
    }

    #[test]
    fn a_short_run_of_the_other_shadow_label_between_one_label_takes_it() {
        let (a, d, o, z) = (ATTACHED, DETACHED, OTHER, VALID);
        let column = settled_columns(&[
            [d, a, d, d],
            [a, d, a, a],
            [a, d, o, a],
            [d, a, a, a],
            [z, z, d, a],
            [z, z, z, d],
        ]);
        assert_eq!(column[0], [d, d, d, d, z, z]);
        assert_eq!(column[1], [a, a, a, a, z, z]);
        // A mixed run is no run: ATTACHED, OTHER, ATTACHED between DETACHED rows (only the
        // OTHER row, between two ATTACHED ones, changes).
        assert_eq!(column[2], [d, a, a, a, d, z]);
        // Four rows of ATTACHED: too long a run.
        assert_eq!(column[3], [d, a, a, a, a, d]);
    }

    #[test]
    fn valid_pixels_neither_change_nor_are_grown_over() {
        let (a, z) = (ATTACHED, VALID);
        let mut labels = frame(&[[a, a, z, z], [z, a, a, z], [a, a, z, z]]);
        let before = labels.clone();
        settle(&mut labels);
        assert_eq!(labels, before);
    }
}
