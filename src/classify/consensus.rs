//! Vertical consensus of hole labels: one pass over a finished label map.
//!
//! Each row is decided on its own (the scanline, the colour split), and a row's evidence can be
//! bad where its neighbours' is good: speckle inside a shadow, a noisy bound, the widening
//! swallowing a lit gap in one row. Shadows are solids in the image, continuous from row to row,
//! so a hole pixel whose rows above and below agree on another shadow label takes theirs. Valid
//! pixels never change and no pixel becomes valid, so shadows only trade labels inside holes.
//! No shadow label is taken away: a row that found a shadow had the evidence for it, while its
//! neighbours may have had none (a colour edge the RGB camera sees only in some rows, say).
//! Applied to the IR view's finished labels before the warp carries them over (about 5 µs a
//! frame; a second pass on the RGB view's labels gained 0.001 of F1 for twice that).

use crate::labels::{OTHER, VALID, WIDTH};

/// Settles single-row disagreements in `labels` (whole rows of [`WIDTH`]), top to bottom: a row
/// is judged against the row above as already settled, and the row below as it is.
pub fn settle(labels: &mut [u8]) {
    const CHUNK: usize = 64;
    let rows = labels.len() / WIDTH;
    for v in 1..rows.saturating_sub(1) {
        let (head, tail) = labels.split_at_mut(v * WIDTH);
        let above = &head[(v - 1) * WIDTH..];
        let (row, below) = tail.split_at_mut(WIDTH);
        for ((row, above), below) in row
            .chunks_mut(CHUNK)
            .zip(above.chunks(CHUNK))
            .zip(below.chunks(CHUNK))
        {
            // Most of a frame is valid: skip such stretches (branch-free test, vectorised).
            if row.iter().fold(true, |all, &m| all & (m == VALID)) {
                continue;
            }
            for ((l, &a), &b) in row.iter_mut().zip(above).zip(below) {
                let m = *l;
                let settle = (a == b) & (m != a) & (a != VALID) & (a != OTHER) & (m != VALID);
                *l = if settle { a } else { m };
            }
        }
    }
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
    fn valid_pixels_neither_change_nor_are_grown_over() {
        let (a, z) = (ATTACHED, VALID);
        let mut labels = frame(&[[a, a, z, z], [z, a, a, z], [a, a, z, z]]);
        let before = labels.clone();
        settle(&mut labels);
        assert_eq!(labels, before);
    }
}
