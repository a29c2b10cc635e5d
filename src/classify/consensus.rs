//! Vertical consensus of hole labels: one pass over a finished label map.
//!
//! Each row is decided on its own (the scanline, the colour split), and a row's evidence can be
//! bad where its neighbours' is good: speckle inside a shadow, a noisy bound, the widening
//! swallowing a lit gap in one row. Shadows are solids in the image, continuous from row to row,
//! so a hole pixel whose rows above and below agree on another shadow label takes theirs, and so
//! does a run of up to three rows (`MAX_GAP_ROWS`; left OTHER, or given the other shadow label)
//! between the same shadow label above and below. Valid pixels never change and no pixel
//! becomes valid, so shadows only trade labels inside holes.
//! A shadow label is taken away in one case only: a short run of it in a column, with holes left
//! OTHER right above and below it: at most four rows of detached (`MAX_FRAGMENT_ROWS`), two of
//! attached (`MAX_ATTACHED_FRAGMENT_ROWS`). A shadow is cast by an object and follows it over
//! many rows; a fragment inside an OTHER hole is a chance pairing of holes in clutter (156 of the
//! real NYU frame's 214 detached pixels, in translucent storage bins and a dark shelf), or a
//! glossy object's dropout that one row's colours split like an occluder's shadow. Otherwise a row that found a shadow had the
//! evidence for it, while its neighbours may have had none (a colour edge the RGB camera sees
//! only in some rows, say).
//! Applied to the IR view's finished labels before the warp carries them over, and to the RGB
//! view's after it, there without trading attached for detached ([`settle_apart`]; the RGB
//! pass: +0.002 to +0.006 of complex scenes' alignment F1, −0.001 to −0.002 of their RGB
//! any-shadow precision, simple scenes unchanged or better). Each pass takes
//! 25 to 40 µs inside the classifier on the development VM, on the real NYU frame and on the
//! bundled complex room alike; the room's took 60 to 90 µs while the fragment pass still read
//! every chunk that held a detached label (most are the insides of long runs).

use crate::labels::{ATTACHED, DETACHED, HEIGHT, OTHER, VALID, WIDTH};

/// Most rows in a run of hole pixels that the same shadow label above and below bridges. Rows
/// fail in short runs, not only alone: bridging up to 3 rows left OTHER gained 0.001 to 0.008 of
/// complex scenes' IR any-shadow recall for 0.000 to 0.003 of precision (10 suites), and runs of
/// the other shadow label a further 0.001 to 0.004 of detached F1; 4 rows bought little more
/// recall for more precision.
const MAX_GAP_ROWS: usize = 3;

/// Most rows of a detached fragment (see the module docs). The simulator's ground truth holds
/// next to no shadow runs of up to three rows between OTHER holes (69 to 172 pixels in 20
/// complex scenes, of 0.5 to 0.7 million shadow pixels). Taking away detached ones: complex
/// scenes' detached F1 +0.0001 to +0.0015 on ten suites of fourteen (among them one made after
/// the change), unchanged on two, −0.0003 and −0.0009 on two; any-shadow precision up to
/// +0.0011, recall down to −0.0011. Four rows rather than three
/// took as much on the suites and 44 more clutter pixels on the real frame; five lost detached
/// F1. Taking away attached fragments as well gained as much attached F1 but cost 0.001 to 0.002
/// of any-shadow recall.
const MAX_FRAGMENT_ROWS: usize = 4;

/// Most rows of an attached fragment. Taking these away once cost 0.001 to 0.002 of any-shadow
/// recall for as much attached F1; a fourth simulator's glossy objects, whose dropouts the
/// colour split reads as shadows in single rows, changed that: over its 48 suites and this
/// project's 13, complex IR attached F1 +0.022 summed, any-shadow precision +0.076, recall
/// −0.055, RGB attached +0.084; this project's suites alone +0.002, precision +0.010, recall
/// −0.010; simple scenes alike. One row took half of it, three lost more recall than they
/// gained precision. The real frame: 28 attached pixels in clutter become OTHER.
const MAX_ATTACHED_FRAGMENT_ROWS: usize = 2;

/// Columns tested at once for a label that needs work (the rest of a frame is passed over).
const CHUNK: usize = 64;

/// Settles disagreements in `labels` (whole rows of [`WIDTH`]), top to bottom: a row is judged
/// against the row above as already settled, and the rows below as they are.
pub fn settle(labels: &mut [u8]) {
    settle_with::<true>(labels);
}

/// [`settle`], but attached and detached pixels keep their kind: only OTHER and alignment take
/// a shadow label from their neighbours (and shadow fragments still go). For the RGB view, whose
/// rows carry over the IR view's: there a thin occluder's shadow is attached in rows where it
/// touches the occluder and detached where the lit gap shows ([`super::touching`]), and a row of
/// one between rows of the other is no error to mend. (This project's suites, complex RGB
/// attached F1 +0.154 summed over fourteen; the seventh simulator's +0.022 over eight.)
pub fn settle_apart(labels: &mut [u8]) {
    settle_with::<false>(labels);
}

/// [`settle`]; `TRADE` false keeps attached and detached pixels from taking each other's label
/// (a constant, so each form's test stays branch-free and vectorised).
fn settle_with<const TRADE: bool>(labels: &mut [u8]) {
    let rows = labels.len() / WIDTH;
    // Which rows hold, once settled, the top of a shadow run (OTHER above it): where the
    // fragment pass can start one (bit `v % 64` of word `v / 64`). That pass only turns shadow
    // pixels with OTHER below them into OTHER, so it makes no new tops. A frame has at most HEIGHT
    // rows, and rows past that are looked at anyway.
    let mut top_rows = [0u64; HEIGHT.div_ceil(64)];
    for v in 1..rows.saturating_sub(1) {
        let (head, tail) = labels.split_at_mut(v * WIDTH);
        let above = &head[(v - 1) * WIDTH..];
        let (row, rest) = tail.split_at_mut(WIDTH);
        let rest: &[u8] = rest;
        let mut top = false;
        for (k, (row, above)) in row.chunks_mut(CHUNK).zip(above.chunks(CHUNK)).enumerate() {
            // Most of a frame is valid, and a pixel can change only below a shadow label it does
            // not share: skip stretches with neither (branch-free tests, vectorised).
            if row.iter().fold(true, |all, &m| all & (m == VALID)) {
                continue;
            }
            let open = |(&m, &a): (&u8, &u8)| {
                let kinds =
                    ((m == ATTACHED) | (m == DETACHED)) & ((a == ATTACHED) | (a == DETACHED));
                (a != VALID) & (a != OTHER) & (m != a) & (m != VALID) & (TRADE | !kinds)
            };
            if row.iter().zip(above).fold(false, |any, p| any | open(p)) {
                for (j, (l, &a)) in row.iter_mut().zip(above).enumerate() {
                    if open((l, &a)) && bridged(rest, k * CHUNK + j, *l, a) {
                        *l = a;
                    }
                }
            }
            top |= has_shadow_top(row, above);
        }
        if let Some(word) = top_rows.get_mut(v / 64) {
            *word |= u64::from(top) << (v % 64);
        }
    }
    drop_fragments(labels, |v| {
        top_rows
            .get(v / 64)
            .is_none_or(|word| word >> (v % 64) & 1 == 1)
    });
}

/// Relabels OTHER each detached run of at most [`MAX_FRAGMENT_ROWS`] rows, and each attached run
/// of at most [`MAX_ATTACHED_FRAGMENT_ROWS`], in a column that has OTHER right above and right
/// below it (not the image's border: a shadow may run on past it). Only rows `v` for which
/// `may_hold(v)` can start one.
fn drop_fragments(labels: &mut [u8], may_hold: impl Fn(usize) -> bool) {
    let rows = labels.len() / WIDTH;
    for v in 1..rows.saturating_sub(1) {
        if !may_hold(v) {
            continue;
        }
        for chunk in (v * WIDTH..(v + 1) * WIDTH).step_by(CHUNK) {
            let end = (chunk + CHUNK).min((v + 1) * WIDTH);
            // Branch-free (vectorised) test first: few chunks of a row hold the top of a shadow
            // run with OTHER above it (a cluttered frame has many chunks of shadow labels, but
            // those are mostly the insides of runs).
            let (row, above) = (&labels[chunk..end], &labels[chunk - WIDTH..end - WIDTH]);
            if !has_shadow_top(row, above) {
                continue;
            }
            for i in chunk..end {
                let most = match labels[i] {
                    DETACHED => MAX_FRAGMENT_ROWS,
                    ATTACHED => MAX_ATTACHED_FRAGMENT_ROWS,
                    _ => continue,
                };
                if labels[i - WIDTH] != OTHER {
                    continue; // not the first row of a run with OTHER above
                }
                let label = labels[i];
                let len = labels[i..]
                    .iter()
                    .step_by(WIDTH)
                    .take(most + 1)
                    .take_while(|&&l| l == label)
                    .count();
                if len <= most && labels.get(i + len * WIDTH) == Some(&OTHER) {
                    for k in 0..len {
                        labels[i + k * WIDTH] = OTHER;
                    }
                }
            }
        }
    }
}

/// True when a pixel of `row` tops a shadow run: DETACHED or ATTACHED under OTHER in `above`
/// (branch-free, so it vectorises).
fn has_shadow_top(row: &[u8], above: &[u8]) -> bool {
    row.iter().zip(above).fold(false, |any, (&l, &a)| {
        any | (((l == DETACHED) | (l == ATTACHED)) & (a == OTHER))
    })
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
            [z, a, d, z], // OTHER above and below: fragments of either label
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
        assert_eq!(row(5), &[z, o, o, z]);
        assert_eq!(row(9), &[z, d, a, d]);
        assert_eq!(row(10), &[z, d, a, z]);
    }

    /// The RGB view's pass: a row of one shadow kind between rows of the other keeps its kind
    /// (a thin rod's row where its lit gap shows, between rows where the widening closed it);
    /// OTHER between them still takes theirs.
    #[test]
    fn apart_attached_and_detached_keep_their_kind_and_other_still_takes_theirs() {
        let (a, d, o, z) = (ATTACHED, DETACHED, OTHER, VALID);
        let rows = [[z, a, a, z], [z, d, o, z], [z, a, a, z]];
        let mut labels = frame(&rows);
        settle_apart(&mut labels);
        assert_eq!(&labels[WIDTH + 100..WIDTH + 104], &[z, d, a, z]);
        let mut labels = frame(&rows);
        settle(&mut labels);
        assert_eq!(&labels[WIDTH + 100..WIDTH + 104], &[z, a, a, z]);
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
    fn a_detached_fragment_inside_an_other_hole_becomes_other() {
        let (d, o, z) = (DETACHED, OTHER, VALID);
        let column = settled_columns(&[
            [o, o, o, z],
            [d, d, d, d],
            [d, d, o, d],
            [d, d, o, d],
            [d, z, o, d],
            [o, o, o, d],
            [o, z, o, d],
        ]);
        // Four rows between OTHER holes: a fragment.
        assert_eq!(column[0], [o, o, o, o, o, o, o]);
        // Valid below: the edge of a shadow, not a fragment.
        assert_eq!(column[1], [o, d, d, d, z, o, z]);
        // One row is a fragment too.
        assert_eq!(column[2], [o, o, o, o, o, o, o]);
        // Valid above, and a run that reaches the image's last row: kept.
        assert_eq!(column[3], [z, d, d, d, d, d, d]);
    }

    #[test]
    fn an_attached_fragment_of_two_rows_becomes_other_and_three_rows_stay() {
        let (a, o, z) = (ATTACHED, OTHER, VALID);
        let column = settled_columns(&[
            [o, o, o, o],
            [a, a, a, a],
            [o, a, a, a],
            [o, o, a, z],
            [o, o, o, a],
            [o, o, o, o],
        ]);
        // One and two rows between OTHER holes: a glossy surface's dropout read as a shadow.
        assert_eq!(column[0], [o, o, o, o, o, o]);
        assert_eq!(column[1], [o, o, o, o, o, o]);
        // Three rows: a shadow's end (an occluder's top or bottom rows), kept.
        assert_eq!(column[2], [o, a, a, a, o, o]);
        // Valid below: the edge of a shadow, not a fragment (and a new run under it).
        assert_eq!(column[3], [o, a, a, z, a, o]);
    }

    #[test]
    fn a_detached_run_longer_than_a_fragment_stays() {
        let (d, o) = (DETACHED, OTHER);
        let rows: Vec<[u8; 4]> = std::iter::once([o; 4])
            .chain(std::iter::repeat_n([d, o, o, o], MAX_FRAGMENT_ROWS + 1))
            .chain(std::iter::once([o; 4]))
            .collect();
        let column = settled_columns(&rows);
        assert!(column[0][1..=MAX_FRAGMENT_ROWS + 1].iter().all(|&l| l == d));
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
