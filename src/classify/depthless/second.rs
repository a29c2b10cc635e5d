//! A second depthless occluder and its attached shadow in the hole a colour split read.
//!
//! The split reads a hole from its left: the wall, a shadow, the occluder that cast it. Two
//! black objects side by side before one wall, the right one nearer or farther, make one hole of
//! the first shadow, the first occluder, the second occluder's shadow and the second occluder:
//! the split labels the first shadow and leaves the rest OTHER. The RGB camera, read at the
//! wall's depth, shows past the first occluder the wall again (that occluder's alignment strip,
//! then what it sees of the second shadow) up to the second occluder, moved left by a third of
//! its shift. The first occluder's shift (the split's) puts its right edge, where the second
//! shadow starts (the hole runs on: no lit wall between them); the second occluder's shift, read
//! at the hole's right end (the strip of wall right of it), puts the second shadow's end. Without
//! that reading nothing is claimed: the least shift that hides the shadow's start behind the
//! first occluder claimed a wall receding beyond the range, and the floor past it, as a shadow
//! and an occluder (this project's suites: complex any-shadow precision −0.08 summed).
//! A row's reading is placed once a row within two reads its second shadow alike.

use super::left_border::mostly_unlike;
use super::{hue_dist, Candidate, ColourSplit, COLOUR_STEP, MIN_HOLE};
use crate::labels::{ATTACHED, HEIGHT, NO_DEPTH, OTHER, WIDTH};

/// Columns in a row (at the wall's depth) that must show the wall past the first occluder.
const WALL_AGAIN: usize = 2;
/// Columns in a row past that wall that must all be unlike it: the second occluder's edge.
const EDGE: usize = 3;
/// Most pixels the second shadow may reach past its shift (the sensor widens its far end).
const OVER: usize = 2;
/// Rows either side within which another row must read its second shadow alike.
const ROWS_NEAR: usize = 2;
/// How far (pixels) that row's shadow's ends may lie from this row's.
const ENDS_NEAR: usize = 3;

/// The second occluder and its shadow in a split's hole.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct SecondPair {
    /// The first occluder's right edge: the second shadow's first column.
    pub(super) start: usize,
    /// The second occluder's left edge: one past the second shadow's last column.
    pub(super) end: usize,
    /// The second occluder's raw value.
    pub(super) at: u16,
}

/// A [`SecondPair`] with what placing it needs.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Placed {
    /// The reading.
    pub(super) pair: SecondPair,
    /// The first occluder's left edge and raw value.
    pub(super) occluder: (usize, u16),
    /// The wall's raw value.
    pub(super) wall: u16,
    /// The hole's end.
    pub(super) b: usize,
}

impl ColourSplit {
    /// Labels and places each row's second shadow that a row within [`ROWS_NEAR`] reads alike:
    /// two solids side by side, not a wall's pattern or a lit spot read once.
    pub(super) fn place_second_pairs(&self, raw: &[u16], labels: &mut [u8], filled: &mut [u16]) {
        if self.second.iter().all(Option::is_none) {
            return;
        }
        let alike = |p: &SecondPair, w: usize| {
            self.second[w].is_some_and(|q| {
                q.pair.start.abs_diff(p.start) <= ENDS_NEAR
                    && q.pair.end.abs_diff(p.end) <= ENDS_NEAR
            })
        };
        for v in 0..HEIGHT {
            let Some(placed) = self.second[v] else {
                continue;
            };
            let p = placed.pair;
            let near = (v.saturating_sub(ROWS_NEAR)..(v + ROWS_NEAR + 1).min(HEIGHT))
                .any(|w| w != v && alike(&p, w));
            if !near {
                continue;
            }
            let i = v * WIDTH;
            for u in p.start..p.end {
                if raw[i + u] == NO_DEPTH && labels[i + u] == OTHER {
                    labels[i + u] = ATTACHED;
                }
            }
            let (from, at) = placed.occluder;
            filled[i + from..i + p.start].fill(at);
            filled[i + p.start..i + p.end].fill(placed.wall);
            filled[i + p.end..i + placed.b].fill(p.at);
        }
    }

    /// For the split of row `v`'s candidate `c` (its shadow `s` wide, its occluder at raw value
    /// `at1`) in the hole `[c.a, b)`: a second occluder's attached shadow past the first
    /// occluder, when the RGB camera sees the wall again there (see the module's docs). `right`:
    /// the raw value the hole's right edge reads for the occluder there, if it reads one.
    pub(super) fn second_pair(
        &self,
        rgb: &[u8],
        v: usize,
        (c, s, at1): (Candidate, usize, u16),
        b: usize,
        right: Option<u16>,
    ) -> Option<SecondPair> {
        // (The cheap tests first: most splits' holes hold one occluder.)
        let at = right?;
        if c.behind || c.a < 2 {
            return None;
        }
        let bg = c.bg;
        let d_bg = self.disp(bg);
        let wall = self.probe(rgb, c.a - 2, v, bg)?;
        let step = self.dimmed(COLOUR_STEP, wall);
        let is_wall = |u: usize| self.probe(rgb, u, v, bg).map(|p| hue_dist(p, wall) < step);
        // Past the first occluder's edge, the wall again.
        let from = c.a + s + EDGE;
        let mut run = 0;
        let wall_from = (from..b).find(|&u| {
            run = if is_wall(u) == Some(true) { run + 1 } else { 0 };
            run == WALL_AGAIN
        })? + 1
            - WALL_AGAIN;
        // Then the second occluder's edge, and mostly occluder to the hole's end.
        let mut unlike = 0;
        let wall_to = (wall_from..b).find(|&u| {
            unlike = if is_wall(u) == Some(false) {
                unlike + 1
            } else {
                0
            };
            unlike == EDGE
        })? + 1
            - EDGE;
        if !mostly_unlike(wall_to..b, is_wall) {
            return None;
        }
        // Each probe blends three RGB columns, so an edge reads a column late from the occluder's
        // side and early from the wall's: each edge lies where a probe is as near the one side's
        // colour as the other's.
        let nearer_wall = |u: usize, occluder: [i32; 3]| {
            self.probe(rgb, u, v, bg)
                .is_some_and(|p| hue_dist(p, wall) < hue_dist(p, occluder))
        };
        let occluder1 = self.probe(rgb, c.a + s + EDGE, v, bg)?;
        let wall_from = (c.a + s + EDGE..wall_from)
            .rev()
            .take_while(|&u| nearer_wall(u, occluder1))
            .last()
            .unwrap_or(wall_from);
        let occluder2 = self.probe(rgb, wall_to + EDGE - 1, v, bg)?;
        let wall_to = (wall_to..wall_to + EDGE - 1)
            .find(|&u| !nearer_wall(u, occluder2))
            .unwrap_or(wall_to + EDGE - 1);
        let x_at = |u: usize, raw: u16| self.project(u as f64 - 0.5, v, raw).0;
        // The first occluder ends where the RGB camera sees its right edge, at its own depth.
        let x_start = x_at(wall_from, bg);
        let start = (c.a + s + 1..b).find(|&u| x_at(u, at1) >= x_start)?;
        // The second occluder's edge, at the shift its right edge reads, ends the shadow, which
        // is no wider than that shift.
        let end = (start..b).find(|&u| x_at(u, at) >= x_at(wall_to, bg))?;
        if (end - start) as f64 > self.disp(at) - d_bg + OVER as f64 + self.widen {
            return None;
        }
        (end > start && end + MIN_HOLE <= b).then_some(SecondPair { start, end, at })
    }
}
