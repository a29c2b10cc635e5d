//! Bitmaps of the "no depth" pixels of one row, so that a scan goes from hole to hole at a cost
//! per hole rather than per pixel (most of a row is valid).

use crate::labels::{NO_DEPTH, WIDTH};

/// Words of a row's bitmap.
const WORDS: usize = WIDTH.div_ceil(64);

/// Which pixels of a row (at most [`WIDTH`] long) have no depth.
#[derive(Clone, Copy, Debug)]
pub(crate) struct HoleMask {
    /// Bit `j` of word `w`: pixel `64·w + j` is a hole; bits past the row are clear.
    words: [u64; WORDS],
    len: usize,
}

impl HoleMask {
    /// The mask of `raw`.
    #[inline(always)]
    pub(crate) fn of(raw: &[u16]) -> HoleMask {
        assert!(raw.len() <= WIDTH, "a row has at most {WIDTH} pixels");
        let mut words = [0u64; WORDS];
        for (word, chunk) in words.iter_mut().zip(raw.chunks(64)) {
            *word = match <&[u16; 64]>::try_from(chunk) {
                Ok(full) => word_of(full),
                Err(_) => fold_word(chunk),
            };
        }
        HoleMask {
            words,
            len: raw.len(),
        }
    }

    /// Whether pixel `u` (inside the row) is a hole: one bit test.
    #[inline(always)]
    pub(crate) fn is_hole(&self, u: usize) -> bool {
        self.words[u / 64] >> (u % 64) & 1 == 1
    }

    /// The first hole pixel at or after `from`, or the row's length when there is none.
    #[inline(always)]
    pub(crate) fn next_hole(&self, from: usize) -> usize {
        self.next(from, 0)
    }

    /// The first valid pixel at or after `from`, or the row's length when there is none.
    #[inline(always)]
    pub(crate) fn next_valid(&self, from: usize) -> usize {
        self.next(from, !0)
    }

    /// Just past the last valid pixel before `to` (at most the row's length), or 0 when there is
    /// none: where the hole run ending at `to` starts.
    #[inline(always)]
    pub(crate) fn prev_valid_end(&self, to: usize) -> usize {
        self.prev_end(to, !0)
    }

    /// Just past the last hole pixel before `to`, or 0 when there is none: where the valid run
    /// ending at `to` starts.
    #[inline(always)]
    pub(crate) fn prev_hole_end(&self, to: usize) -> usize {
        self.prev_end(to, 0)
    }

    /// One past the last bit before `to` set in the words XOR `flip`, or 0.
    #[inline(always)]
    fn prev_end(&self, to: usize, flip: u64) -> usize {
        let to = to.min(self.len);
        if to == 0 {
            return 0;
        }
        let last = to - 1;
        let mut w = last / 64;
        let mut bits = (self.words[w] ^ flip) & (!0u64 >> (63 - last % 64));
        while bits == 0 {
            if w == 0 {
                return 0;
            }
            w -= 1;
            bits = self.words[w] ^ flip;
        }
        w * 64 + 64 - bits.leading_zeros() as usize
    }

    /// The first bit at or after `from` set in the words XOR `flip`, clamped to the length.
    #[inline(always)]
    fn next(&self, from: usize, flip: u64) -> usize {
        if from >= self.len {
            return self.len;
        }
        let mut w = from / 64;
        let mut bits = (self.words[w] ^ flip) & (!0u64 << (from % 64));
        while bits == 0 {
            w += 1;
            if w == WORDS {
                return self.len;
            }
            bits = self.words[w] ^ flip;
        }
        (w * 64 + bits.trailing_zeros() as usize).min(self.len)
    }
}

/// The hole bits of 64 pixels. The compiler turns the plain fold into a shift and an OR per
/// pixel; a byte mask of compares gives sixteen bits at once: a frame's bitmap in 7.5–9 µs
/// against 18–22 µs (AVX-512 builds) and 28 µs (AVX2), and the scanline and the colour split
/// each build one.
#[cfg(target_arch = "x86_64")]
#[inline(always)]
fn word_of(chunk: &[u16; 64]) -> u64 {
    use std::arch::x86_64::{
        __m128i, _mm_cmpeq_epi16, _mm_loadu_si128, _mm_movemask_epi8, _mm_packs_epi16,
        _mm_set1_epi16,
    };
    let mut word = 0u64;
    for (k, sixteen) in chunk.chunks_exact(16).enumerate() {
        // SAFETY: SSE2 is part of x86-64 itself, so every build has it; `sixteen` holds 16 u16,
        // two unaligned 128-bit loads' worth.
        let bits = unsafe {
            let hole = _mm_set1_epi16(NO_DEPTH as i16);
            let at = sixteen.as_ptr().cast::<__m128i>();
            let (a, b) = (_mm_loadu_si128(at), _mm_loadu_si128(at.add(1)));
            // Each compare gives 0xFFFF per hole lane; packed to bytes, one bit per pixel.
            _mm_movemask_epi8(_mm_packs_epi16(
                _mm_cmpeq_epi16(a, hole),
                _mm_cmpeq_epi16(b, hole),
            ))
        };
        word |= u64::from(bits as u16) << (16 * k);
    }
    word
}

/// [`word_of`] on other CPUs: the plain fold.
#[cfg(not(target_arch = "x86_64"))]
#[inline(always)]
fn word_of(chunk: &[u16; 64]) -> u64 {
    fold_word(chunk)
}

/// The hole bits of up to 64 pixels, one compare and shift each: a row's short last chunk, and
/// every chunk where SSE2 is not at hand.
#[inline(always)]
fn fold_word(chunk: &[u16]) -> u64 {
    chunk
        .iter()
        .enumerate()
        .fold(0u64, |m, (j, &r)| m | (u64::from(r == NO_DEPTH) << j))
}

/// Rows that try the searches: all holes, all valid, shorter than a frame's, runs starting,
/// ending and crossing at the 64-pixel word boundaries and at both ends, alternating pixels (the
/// most runs a row can hold), and random ones. Shared with the scanline's run tests.
#[cfg(test)]
pub(crate) fn test_rows() -> Vec<Vec<u16>> {
    let mut rows: Vec<Vec<u16>> = vec![vec![NO_DEPTH; WIDTH], vec![800; WIDTH], vec![800; 70]];
    let mut row = vec![800; WIDTH];
    for (a, b) in [
        (0, 1),
        (63, 64),
        (64, 65),
        (100, 128),
        (191, 257),
        (639, 640),
    ] {
        row[a..b].fill(NO_DEPTH);
    }
    rows.push(row);
    let mut short = vec![NO_DEPTH; 70];
    short[66] = 900;
    rows.push(short);
    rows.push(
        (0..WIDTH)
            .map(|u| if u % 2 == 0 { NO_DEPTH } else { 800 })
            .collect(),
    );
    let mut seed = 0x9e37_79b9_u32;
    for _ in 0..50 {
        rows.push(
            (0..WIDTH)
                .map(|_| {
                    seed ^= seed << 13;
                    seed ^= seed >> 17;
                    seed ^= seed << 5;
                    if seed.is_multiple_of(3) {
                        NO_DEPTH
                    } else {
                        900
                    }
                })
                .collect(),
        );
    }
    rows
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The next hole and the next valid pixel, pixel by pixel: the reference.
    fn by_hand(raw: &[u16], from: usize, hole: bool) -> usize {
        (from..raw.len())
            .find(|&u| (raw[u] == NO_DEPTH) == hole)
            .unwrap_or(raw.len())
    }

    /// Just past the last hole (or valid) pixel before `to`, pixel by pixel: the reference.
    fn back_by_hand(raw: &[u16], to: usize, hole: bool) -> usize {
        (0..to.min(raw.len()))
            .rev()
            .find(|&u| (raw[u] == NO_DEPTH) == hole)
            .map_or(0, |u| u + 1)
    }

    #[test]
    fn searches_both_ways_agree_with_a_pixel_by_pixel_scan() {
        let rows = test_rows();
        for raw in &rows {
            let mask = HoleMask::of(raw);
            for from in 0..=raw.len() + 1 {
                assert_eq!(
                    mask.next_hole(from),
                    by_hand(raw, from, true),
                    "hole from {from}"
                );
                assert_eq!(
                    mask.next_valid(from),
                    by_hand(raw, from, false),
                    "valid from {from}"
                );
                let (hole, valid) = (
                    back_by_hand(raw, from, true),
                    back_by_hand(raw, from, false),
                );
                assert_eq!(mask.prev_hole_end(from), hole, "hole before {from}");
                assert_eq!(mask.prev_valid_end(from), valid, "valid before {from}");
            }
            for (u, &r) in raw.iter().enumerate() {
                assert_eq!(mask.is_hole(u), r == NO_DEPTH, "pixel {u}");
            }
        }
    }
}
