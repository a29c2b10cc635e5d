//! Detached shadows bridged across long runs of rows left OTHER: one pass over the IR view's
//! settled labels.
//!
//! A thin occluder casts its detached shadow (eqs. (4)–(5)) over every row it spans, as one
//! vertical band of holes of nearly the same extent. Where the occluder returns no depth in some
//! rows (a glossy rod between its lit patches, a dark one), those rows have no Fa/Fb to test and
//! the colour split may not pair them either, so the band alternates between DETACHED and OTHER
//! for tens of rows: longer than [`consensus`](super::consensus) bridges. Here a gap of rows
//! whose holes are all OTHER, each of like extent to the one above (ends within 3 px), between
//! DETACHED holes of like extent right above and right below it, takes DETACHED when the band
//! within 96 rows of the gap, followed row by row, holds at least twice as many DETACHED rows as
//! OTHER ones, and at least as many as the gap is long. A band that is mostly OTHER keeps its
//! stray DETACHED rows for consensus to judge: a black rod whose own hole a few rows paired with
//! the wrong shadow stays OTHER.

use crate::labels::{DETACHED, HEIGHT, OTHER, VALID, WIDTH};

/// Rows of a band read above and below a gap, and the longest gap bridged. At 12 the
/// independent simulator's glossy rods had 0.3 fewer pixels bridged, with no less harm; at 48 a
/// fifth simulator's rod lost a 73-row stretch of its band (its glossy patch) to OTHER.
const REACH: usize = 96;
/// How far (pixels) each end of a hole may lie from the row's before it: a band's sides drift
/// by the sensor's noise and a tilted occluder's slope. At 2, bands with jagged sides broke off
/// (half as many pixels bridged on one of our suites).
const DRIFT: usize = 3;
/// DETACHED rows a band needs per OTHER row beside the gap. At 1, bands of a black rod whose own
/// hole was paired in some rows (ours: 840 px wrong in one scene) turned DETACHED; at 3, a glossy
/// rod's band bridged a quarter less. (The gap's own rows once counted as OTHER here too, which
/// denied a long gap in a band with two shorter ones: it now needs as many DETACHED rows as it
/// is long.)
const MAJORITY: usize = 2;
/// Narrowest hole bridged (pixels): speckle is no band.
const MIN_WIDTH: usize = 3;
/// Marks a hole decided in this pass; read as OTHER until the pass ends, so the order rows are
/// visited in does not change what is decided.
const PENDING: u8 = 0x80 | DETACHED;

/// 64-pixel words in a row's bit masks.
const WORDS: usize = WIDTH.div_ceil(64);

/// Bridges detached bands in `labels` (whole rows of [`WIDTH`]), as the module docs say.
pub fn bridge_detached(labels: &mut [u8]) {
    let rows = labels.len() / WIDTH;
    assert!(rows <= HEIGHT, "a frame has at most {HEIGHT} rows");
    // For each row and 64-column word of it: the nearest row at or above (`up`), and at or
    // below (`down`), holding a DETACHED pixel in those columns.
    let mut up = [[i16::MIN; WORDS]; HEIGHT];
    let mut down = [[i16::MAX; WORDS]; HEIGHT];
    for v in 0..rows {
        let words = row_mask(&labels[v * WIDTH..(v + 1) * WIDTH], DETACHED);
        for k in 0..WORDS {
            up[v][k] = if words[k] != 0 {
                v as i16
            } else {
                v.checked_sub(1).map_or(i16::MIN, |w| up[w][k])
            };
        }
    }
    for v in (0..rows).rev() {
        for k in 0..WORDS {
            down[v][k] = if up[v][k] == v as i16 {
                v as i16
            } else if v + 1 < rows {
                down[v + 1][k]
            } else {
                i16::MAX
            };
        }
    }
    // Whether DETACHED lies within reach above and below row `v`, in words `lo..=hi`.
    let near = |v: usize, lo: usize, hi: usize| {
        let reach = REACH as i32;
        (lo..=hi).any(|k| i32::from(up[v - 1][k]) >= v as i32 - reach)
            && (lo..=hi).any(|k| i32::from(down[v + 1][k]) <= v as i32 + reach)
    };
    // Rows holding a decided hole (bit `v % 64` of word `v / 64`).
    let mut changed = [0u64; HEIGHT.div_ceil(64)];
    for v in 1..rows.saturating_sub(1) {
        if !near(v, 0, WORDS - 1) {
            continue;
        }
        let other = row_mask(&labels[v * WIDTH..(v + 1) * WIDTH], OTHER);
        let mut u = 0;
        // Each run of OTHER pixels that is a whole hole (VALID, or the border, on both sides).
        while let Some(a) = next_set(&other, u) {
            let row = &labels[v * WIDTH..(v + 1) * WIDTH];
            let b = next_set_of(&other, a, !0).unwrap_or(WIDTH);
            u = b;
            let whole = (a == 0 || row[a - 1] == VALID) && (b == WIDTH || row[b] == VALID);
            let words = (
                a.saturating_sub(DRIFT) / 64,
                (b + DRIFT - 1).min(WIDTH - 1) / 64,
            );
            if !whole || b - a < MIN_WIDTH || !near(v, words.0, words.1) {
                continue;
            }
            let mut gap = [(0, 0); REACH];
            let Some(rows_in_gap) = bridged_gap(labels, rows, v, (a, b), &mut gap) else {
                continue;
            };
            for (k, &(c, e)) in gap[..rows_in_gap].iter().enumerate() {
                let y = v + k;
                labels[y * WIDTH + c..y * WIDTH + e].fill(PENDING);
                changed[y / 64] |= 1 << (y % 64);
            }
        }
    }
    for v in (0..rows).filter(|v| changed[v / 64] >> (v % 64) & 1 == 1) {
        for l in labels[v * WIDTH..(v + 1) * WIDTH].iter_mut() {
            // A select, not a branch: the loop vectorises.
            *l = if *l == PENDING { DETACHED } else { *l };
        }
    }
}

/// Bit `j` of word `k`: pixel `64·k + j` of `row` (a whole row) is `label`.
pub(super) fn row_mask(row: &[u8], label: u8) -> [u64; WORDS] {
    let mut words = [0u64; WORDS];
    for (word, chunk) in words.iter_mut().zip(row.chunks(64)) {
        *word = word_of(chunk, label);
    }
    words
}

/// [`row_mask`]'s word for up to 64 pixels: four SSE2 compares of 16 bytes where x86-64 has them.
#[cfg(target_arch = "x86_64")]
fn word_of(chunk: &[u8], label: u8) -> u64 {
    use std::arch::x86_64::{
        __m128i, _mm_cmpeq_epi8, _mm_loadu_si128, _mm_movemask_epi8, _mm_set1_epi8,
    };
    let Ok(full) = <&[u8; 64]>::try_from(chunk) else {
        return fold_word(chunk, label);
    };
    let mut word = 0u64;
    for (k, sixteen) in full.chunks_exact(16).enumerate() {
        // SAFETY: SSE2 is part of x86-64 itself; `sixteen` holds 16 bytes, one unaligned load.
        let bits = unsafe {
            let at = _mm_loadu_si128(sixteen.as_ptr().cast::<__m128i>());
            _mm_movemask_epi8(_mm_cmpeq_epi8(at, _mm_set1_epi8(label as i8)))
        };
        word |= u64::from(bits as u16) << (16 * k);
    }
    word
}

/// [`word_of`] on other CPUs.
#[cfg(not(target_arch = "x86_64"))]
fn word_of(chunk: &[u8], label: u8) -> u64 {
    fold_word(chunk, label)
}

/// The bits of up to 64 pixels, one compare and shift each.
fn fold_word(chunk: &[u8], label: u8) -> u64 {
    chunk
        .iter()
        .enumerate()
        .fold(0, |m, (j, &l)| m | u64::from(l == label) << j)
}

/// The first set bit of `words` at or after `from`.
fn next_set(words: &[u64; WORDS], from: usize) -> Option<usize> {
    next_set_of(words, from, 0)
}

/// The first bit at or after `from` that is set in `words` XOR `flip` (`!0`: the first clear
/// bit); None past the row's end.
fn next_set_of(words: &[u64; WORDS], from: usize, flip: u64) -> Option<usize> {
    let mut k = from / 64;
    let mut word = (*words.get(k)? ^ flip) & (!0u64 << (from % 64));
    while word == 0 {
        k += 1;
        word = *words.get(k)? ^ flip;
    }
    Some(64 * k + word.trailing_zeros() as usize).filter(|&u| u < WIDTH)
}

/// What a band's row holds in its hole.
#[derive(Clone, Copy, PartialEq)]
enum Kind {
    /// More than four fifths DETACHED.
    Detached,
    /// All OTHER (or decided in this pass).
    Other,
    /// Anything else: the band ends there.
    Mixed,
}

fn kind(pixels: &[u8]) -> Kind {
    let n = pixels.iter().filter(|&&l| l == DETACHED).count();
    if 5 * n > 4 * pixels.len() {
        Kind::Detached
    } else if pixels.iter().all(|&l| l == OTHER || l == PENDING) {
        Kind::Other
    } else {
        Kind::Mixed
    }
}

/// Whether hole `(a, b)` of row `v` starts a gap (DETACHED above it) of OTHER rows in a band
/// that goes on DETACHED below it, and the band within [`REACH`] of the gap is DETACHED by a
/// [`MAJORITY`] of its other rows and in at least as many rows as the gap holds: then the gap's
/// rows (their holes written to `gap`).
fn bridged_gap(
    labels: &[u8],
    rows: usize,
    v: usize,
    (a, b): (usize, usize),
    gap: &mut [(usize, usize); REACH],
) -> Option<usize> {
    let row = |y: usize| &labels[y * WIDTH..(y + 1) * WIDTH];
    let top = like_hole(row(v - 1), (a, b))?;
    if kind(&row(v - 1)[top.0..top.1]) != Kind::Detached {
        return None;
    }
    gap[0] = (a, b);
    let mut len = 1;
    let bottom = loop {
        let y = v + len;
        if y >= rows {
            return None;
        }
        let hole = like_hole(row(y), gap[len - 1])?;
        match kind(&row(y)[hole.0..hole.1]) {
            Kind::Detached => break hole,
            Kind::Other if len < REACH => {
                gap[len] = hole;
                len += 1;
            }
            _ => return None,
        }
    };
    let mut detached = 0;
    let mut other = 0;
    for (start, hole, up) in [(v - 1, top, true), (v + len, bottom, false)] {
        let mut hole = hole;
        for k in 0..REACH {
            let y = if up {
                start.checked_sub(k)
            } else {
                Some(start + k)
            };
            let Some(y) = y.filter(|&y| y < rows) else {
                break;
            };
            if k > 0 {
                match like_hole(row(y), hole) {
                    Some(like) => hole = like,
                    None => break,
                }
            }
            match kind(&row(y)[hole.0..hole.1]) {
                Kind::Detached => detached += 1,
                Kind::Other => other += 1,
                Kind::Mixed => break,
            }
        }
    }
    (detached >= MAJORITY * other && detached >= len).then_some(len)
}

/// The hole of `row` whose ends both lie within [`DRIFT`] of `(a, b)`'s, if any.
fn like_hole(row: &[u8], (a, b): (usize, usize)) -> Option<(usize, usize)> {
    let lo = a.saturating_sub(DRIFT);
    let hi = (a + DRIFT).min(row.len() - 1);
    (lo..=hi)
        .filter(|&s| row[s] != VALID && (s == 0 || row[s - 1] == VALID))
        .map(|s| {
            let e = row[s..]
                .iter()
                .position(|&l| l == VALID)
                .map_or(row.len(), |k| s + k);
            (s, e)
        })
        .find(|&(_, e)| e.abs_diff(b) <= DRIFT)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::labels::ATTACHED;

    /// A frame whose rows hold, at columns 100.., the given hole (`label` over `width` pixels
    /// starting at `100 + shift`), or nothing (`None`).
    fn frame(rows: &[Option<(u8, usize, usize)>]) -> Vec<u8> {
        let mut labels = vec![VALID; rows.len() * WIDTH];
        for (v, r) in rows.iter().enumerate() {
            if let Some((label, shift, width)) = *r {
                let s = v * WIDTH + 100 + shift;
                labels[s..s + width].fill(label);
            }
        }
        labels
    }

    fn label_at(labels: &[u8], v: usize, u: usize) -> u8 {
        labels[v * WIDTH + u]
    }

    /// A glossy rod's band: 30 DETACHED rows, 20 OTHER, 30 DETACHED, the sides drifting by a
    /// pixel: the OTHER rows become DETACHED.
    #[test]
    fn a_long_run_of_other_rows_inside_a_detached_band_is_bridged() {
        let (d, o) = (DETACHED, OTHER);
        let rows: Vec<_> = (0..80)
            .map(|v| Some((if (30..50).contains(&v) { o } else { d }, v % 2, 12)))
            .collect();
        let mut labels = frame(&rows);
        bridge_detached(&mut labels);
        for v in 0..80 {
            let shift = v % 2;
            assert_eq!(label_at(&labels, v, 100 + shift), d, "row {v}");
            assert_eq!(label_at(&labels, v, 100 + shift + 11), d, "row {v}");
            assert_eq!(label_at(&labels, v, 100 + shift + 12), VALID, "row {v}");
        }
    }

    /// A glossy rod's band with three dull stretches, as a simulator's rod drew it: 100 DETACHED
    /// rows, 19 OTHER, 62 DETACHED, 73 OTHER, 89 DETACHED, 22 OTHER, 35 DETACHED. The long
    /// stretch is bridged too, though the band beside it holds the short ones.
    #[test]
    fn a_long_gap_beside_shorter_ones_in_one_band_is_bridged() {
        let (d, o) = (DETACHED, OTHER);
        let stretches = [
            (d, 100),
            (o, 19),
            (d, 62),
            (o, 73),
            (d, 89),
            (o, 22),
            (d, 35),
        ];
        let rows: Vec<_> = stretches
            .iter()
            .flat_map(|&(l, n)| std::iter::repeat_n(Some((l, 0, 26)), n))
            .collect();
        assert_eq!(rows.len(), 400);
        let mut labels = frame(&rows);
        bridge_detached(&mut labels);
        for v in 0..400 {
            assert_eq!(label_at(&labels, v, 100), d, "row {v}");
            assert_eq!(label_at(&labels, v, 125), d, "row {v}");
        }
    }

    /// A band that is mostly OTHER (a black rod's hole, a few rows paired by chance) keeps its
    /// OTHER rows; so does a band DETACHED on one side only, or broken by a valid row, or by a
    /// hole of another extent.
    #[test]
    fn bands_without_a_detached_majority_on_both_sides_stay() {
        let (d, o) = (DETACHED, OTHER);
        // 10 DETACHED, 30 OTHER, 10 DETACHED: a minority.
        let rows: Vec<_> = (0..50)
            .map(|v| Some((if (10..40).contains(&v) { o } else { d }, 0, 6)))
            .collect();
        let mut labels = frame(&rows);
        let before = labels.clone();
        bridge_detached(&mut labels);
        assert_eq!(labels, before, "a minority of DETACHED rows");

        // DETACHED above only.
        let rows: Vec<_> = (0..60)
            .map(|v| Some((if v < 40 { d } else { o }, 0, 8)))
            .collect();
        let mut labels = frame(&rows);
        let before = labels.clone();
        bridge_detached(&mut labels);
        assert_eq!(labels, before, "one side only");

        // A valid row, and a row whose hole is twice as wide, between the two halves.
        for gap in [None, Some((o, 0, 16))] {
            let rows: Vec<_> = (0..60)
                .map(|v| match v {
                    30 => gap,
                    25..=35 => Some((o, 0, 8)),
                    _ => Some((d, 0, 8)),
                })
                .collect();
            let mut labels = frame(&rows);
            bridge_detached(&mut labels);
            assert_eq!(label_at(&labels, 28, 100), o, "broken band {gap:?}");
            assert_eq!(label_at(&labels, 33, 100), o, "broken band {gap:?}");
        }
    }

    /// Holes of another shadow label, or partly labelled, are not OTHER holes and stay.
    #[test]
    fn only_holes_wholly_other_change() {
        let (a, d, o) = (ATTACHED, DETACHED, OTHER);
        let mut rows: Vec<_> = (0..60).map(|_| Some((d, 0, 8))).collect();
        rows[29] = Some((a, 0, 8));
        rows[30] = Some((o, 0, 8));
        let mut labels = frame(&rows);
        labels[31 * WIDTH + 100..31 * WIDTH + 104].fill(o);
        bridge_detached(&mut labels);
        assert_eq!(label_at(&labels, 29, 100), a);
        // Row 30 walks up into an ATTACHED hole (a mixed band stops there): no DETACHED above.
        assert_eq!(label_at(&labels, 30, 100), o);
        assert_eq!(label_at(&labels, 31, 100), o, "half OTHER, half DETACHED");
        assert_eq!(label_at(&labels, 31, 104), d);
    }
}
