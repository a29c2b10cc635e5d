//! Attached shadows of depthless occluders that run off the IR image's left border.
//!
//! Shadows fall left of their occluders (SPEC §1). A black or glossy occluder near the left
//! border makes one hole with its attached shadow, and where that shadow reaches the border the
//! hole has no background on its left: the colour split's reading (background, then occluder)
//! has nothing to start from, and the hole stays OTHER, shadow and all.
//!
//! The RGB camera, a third of the way from the IR camera to the projector, still tells the two
//! parts apart. Read at the depth of the wall right of the hole, its row shows, from the hole's
//! right end leftwards: the wall the occluder hides from the IR camera (a third of the
//! occluder's shift wide: the occluder's right edge moves left by that much against the wall),
//! the occluder, then the wall again, lit by the room only, to the border: the shadow. The strip
//! gives the shift; the occluder's left edge, moved back by the same third, is where the shadow
//! ends. The hole is that occluder and its shadow when
//!
//! - a surface bounds the hole on the right (three pixels of it at least: between an occluder
//!   and the next hole a wall may show no wider than the strip) that does not recede out of the
//!   range towards the hole, and is not patterned so boldly that its own colours lie as far
//!   apart as a wall's and an occluder's (a textured box beside a glossy one);
//! - the strip is at least two columns wide (a black poster on the wall shows none), the
//!   occluder at least [`MIN_HOLE`] columns with a sharp left edge, and the RGB camera sees the
//!   wall's colour from the border up to that edge;
//! - the shadow's visible part is no wider than the whole shadow (eq. 3 at the strip's shift);
//! - the column through the shadow measures, above and below the hole, either nothing at all
//!   (an occluder as tall as the view) or, on one side at least, a surface no nearer than the
//!   one right of the hole: a wall beyond the range leaves a hole as a shadow does, and it
//!   reaches the image's top or bottom on one side, or ends at nearer things only (a floor);
//! - six of the eight rows around hold the same hole, and a row within two reads the
//!   occluder's edge alike (beyond the range, or on a pattern, such readings come and go).
//!
//! Where the surface right of the hole tells nothing (it is not the wall the RGB camera sees at
//! the border, is boldly patterned, or leaves no strip), the RGB camera's wider view does: it
//! sees past the IR image's left border, where the wall runs on. With the wall's colour read
//! there and its depth measured above the hole, the shadow is read from the border to the
//! occluder's edge, and ends where the least shift that starts it outside the image puts it
//! (`past_border`; the rest of a wider shadow stays OTHER).
//!
//! Rows between two that hold take their reading (as the vertical consensus would take their
//! label), so the occluder's depth hides its third of the shadow in the RGB view there too.

use super::offimage::{NEAR_FAR, SLOPE_SPAN};
use super::{hue_dist, rgb_mean3, ColourSplit, Range, COLOUR_STEP, MIN_HOLE, SAME_SURFACE, SIDE};
use super::{relabel, span_end};
use super::{SPREAD_NUM, SPREAD_SPAN};
use crate::labels::{ATTACHED, HEIGHT, NO_DEPTH, OTHER, WIDTH};

/// Narrowest strip (columns at the wall's depth) the occluder must leave right of it: one
/// column is about three pixels of shift, and a poster's edge may blend one.
const MIN_STRIP: usize = 2;
/// Most rows between two that read the hole alike (the vertical consensus's reach).
const BRIDGE_ROWS: usize = 3;
/// How far (pixels) the hole's end may move from those rows'.
const ENDS_AGREE: usize = 3;
/// Columns past the occluder's left edge that must all be unlike the wall.
const EDGE: usize = 3;
/// Fewest pixels of the surface right of the hole.
const MIN_SURFACE: usize = 3;

/// The column whose depth above or below the hole [`ColourSplit::past_border`] takes for the
/// wall's (the border column itself may hold a lens's dark edge).
const BORDER_COLUMN: usize = 1;
/// Pixels past the IR image's left border (at the wall's depth) whose colour the RGB camera's
/// wider view shows as the wall's.
const PAST: usize = 6;
/// Spots of the surface measured above or below the hole at which its colour is compared with
/// the wall's past the border, and the rows between them.
const SPOTS: usize = 4;
const SPOT_ROWS: usize = 3;

/// Whether half the columns `us` or more read unlike the wall (`is_wall` false), read only until
/// that is decided: a black occluder near the camera spans hundreds of columns.
pub(super) fn mostly_unlike(
    us: std::ops::Range<usize>,
    is_wall: impl Fn(usize) -> Option<bool>,
) -> bool {
    let half = us.len().div_ceil(2);
    let (mut unlike, mut other) = (0, 0);
    for u in us.clone() {
        if is_wall(u) == Some(false) {
            unlike += 1;
        } else {
            other += 1;
        }
        if unlike >= half || other > us.len() - half {
            break;
        }
    }
    unlike >= half
}

/// Why the strip beside a hole gave no reading.
enum Unread {
    /// The surface right of the hole tells nothing of the occluder; `solid` once the hole was
    /// found to be a solid's (read before the colours, and not again).
    Beside { solid: bool },
    /// The hole is no occluder and shadow.
    Refuted,
}

/// A hole `[0, b)` at the left border read as a depthless occluder `[end, b)` (raw value `at`)
/// and its attached shadow `[0, end)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct BorderSplit {
    b: u16,
    end: u16,
    at: u16,
    /// Read past the border ([`ColourSplit::past_border`]): the raw values of the wall the shadow
    /// lies on and of the surface right of the hole. The occluder's right edge is not known to
    /// lie at the hole's end there.
    past: Option<(u16, u16)>,
}

impl BorderSplit {
    /// Labels the shadow of row `v` (its OTHER pixels) and gives the occluder its depth.
    pub(super) fn apply(self, v: usize, labels: &mut [u8], filled: &mut [u16]) {
        let (row, end, b) = (v * WIDTH, usize::from(self.end), usize::from(self.b));
        relabel(&mut labels[row..row + end], OTHER, ATTACHED);
        let occluder = &mut filled[row + end..row + b];
        match self.past {
            None => occluder.fill(self.at),
            // The occluder's depth at its left edge, which hides its third of the shadow from
            // the RGB camera, running to the depth beside the hole at its end: where the
            // occluder ends inside the hole is unknown, and a step there would open an
            // alignment gap the colours never showed (one at the hole's end cost the sixth
            // simulator's RGB alignment F1 0.014 summed over its complex suites).
            Some((wall, beside)) => {
                let (near, far) = (f32::from(self.at), f32::from(beside));
                let n = occluder.len() as f32;
                for (i, f) in occluder.iter_mut().enumerate() {
                    *f = (near + (far - near) * i as f32 / n).round() as u16;
                }
                // The shadow lies on the wall read past the border, not on the surface beside.
                filled[row..row + end].fill(wall);
            }
        }
    }
}

impl ColourSplit {
    /// For the hole `[0, b)` of row `v` at the left border: where its attached shadow ends (the
    /// occluder's left edge) and the occluder's raw value, when the hole is a depthless occluder
    /// and its shadow running off the border (see the module's docs).
    pub(super) fn left_border_attached(
        &self,
        raw: &[u16],
        rgb: &[u8],
        v: usize,
        b: usize,
        range: Range,
    ) -> Option<BorderSplit> {
        if b < 2 * MIN_HOLE || b + SPREAD_SPAN > WIDTH {
            return None;
        }
        match self.by_strip(raw, rgb, v, b, range) {
            Ok(split) => Some(split),
            Err(Unread::Beside { solid }) => self.past_border(raw, rgb, v, b, range, solid),
            Err(Unread::Refuted) => None,
        }
    }

    /// [`Self::left_border_attached`] by the strip of the surface right of the hole.
    fn by_strip(
        &self,
        raw: &[u16],
        rgb: &[u8],
        v: usize,
        b: usize,
        range: Range,
    ) -> Result<BorderSplit, Unread> {
        use Unread::{Beside, Refuted};
        let row = &raw[v * WIDTH..(v + 1) * WIDTH];
        // (A hole ends at a valid pixel, or at the border, which `b` is short of.)
        let bg = row[b];
        let beside = b..(b + SLOPE_SPAN).min(WIDTH);
        if self.wall_leaves_range(raw, v, bg, beside, true, range) != Some(false) {
            return Err(Beside { solid: false });
        }
        let d_bg = self.disp(bg);
        let widest = self.widest(bg);
        // A surface beside the hole, not the sensor's noise: a few pixels of one (between an
        // occluder and the next hole the wall may show only as wide as the RGB strip).
        let on_wall = |r: u16| r != NO_DEPTH && (self.disp(r) - d_bg).abs() <= SAME_SURFACE;
        let run = row[b..b + SPREAD_SPAN]
            .iter()
            .take_while(|&&r| on_wall(r))
            .count();
        // (The depth tests before the colour ones: they are cheaper, and most holes fail them.)
        if run < MIN_SURFACE {
            return Err(Beside { solid: false });
        }
        if !self.solid(raw, v, (0, b)) {
            return Err(Refuted);
        }
        let wall = self
            .mean_colour(rgb, v, b..b + run.min(SIDE), bg)
            .ok_or(Beside { solid: true })?;
        // A patterned wall's stripes are no occluder: the step rises to the wall's own spread
        // (over the surface's own run: a nearer object beside it is no part of its pattern).
        let spread = self.wall_spread(rgb, v, b..b + run, bg, wall);
        let base = self.dimmed(COLOUR_STEP, wall);
        let step = base.max(spread * SPREAD_NUM / 2);
        // Past four times the plain step the pattern itself holds colours as far apart as a
        // wall's and an occluder's (a patterned box beside the hole): nothing reads against it.
        if step > 4 * base {
            return Err(Beside { solid: true });
        }
        let is_wall = |u: usize| self.probe(rgb, u, v, bg).map(|p| hue_dist(p, wall) < step);
        // From the hole's right end leftwards: the strip, the occluder, the shadow.
        let strip = (0..b)
            .rev()
            .take_while(|&u| is_wall(u) == Some(true))
            .count();
        if strip < MIN_STRIP || 3 * strip > widest + 3 {
            return Err(Beside { solid: true });
        }
        let occluder_end = b - strip;
        // The shadow from the border on: the wall's colour up to the occluder's left edge,
        // read from this side (a round occluder's shaded face may match a dark wall in places).
        // (No further than the widest shadow the strip allows: one column of it is about three
        // pixels of shift.)
        let reach = occluder_end.min(3 * (strip + 1) + 4 + self.widen.ceil() as usize);
        let mut seen = 0;
        let mut occluder_start = None;
        for u in 0..reach {
            match is_wall(u) {
                Some(true) => seen += 1,
                Some(false) => {
                    occluder_start = Some(u);
                    break;
                }
                None => {}
            }
        }
        // The wall seen at the border is not the surface beside the hole.
        if seen < MIN_STRIP {
            return Err(Beside { solid: true });
        }
        let occluder_start = occluder_start.ok_or(Refuted)?;
        if occluder_end - occluder_start < MIN_HOLE {
            return Err(Refuted);
        }
        // An edge, then mostly occluder (read until that is decided: a black sphere near the
        // camera spans hundreds of columns).
        if (occluder_start..occluder_start + EDGE).any(|u| is_wall(u) != Some(false)) {
            return Err(Refuted);
        }
        if !mostly_unlike(occluder_start..occluder_end, is_wall) {
            return Err(Refuted);
        }
        // The shift that moves the occluder's right edge (IR column `b`) onto the strip's start;
        // its left edge moves as far, which puts it in the IR image.
        let x_at = |u: usize, raw: u16| self.project(u as f64 - 0.5, v, raw).0;
        let x_strip = x_at(occluder_end, bg);
        let shift = (MIN_STRIP..=widest)
            .min_by(|&s, &t| {
                let off = |s: usize| (x_at(b, self.raw_at_disp(d_bg + s as f64)) - x_strip).abs();
                off(s).total_cmp(&off(t))
            })
            .ok_or(Refuted)?;
        let at = self.raw_at_disp(d_bg + shift as f64);
        let x_left = x_at(occluder_start, bg);
        let end = (occluder_start..b)
            .find(|&u| x_at(u, at) >= x_left)
            .ok_or(Refuted)?;
        // The visible part is no wider than the whole shadow (one column of the strip is about
        // three pixels of shift, the sensor widens the shadow's far end).
        if end > shift + 3 + self.widen.ceil() as usize {
            return Err(Refuted);
        }
        // The column through the shadow's middle, above and below the hole: nothing measured on
        // either side, or a surface no nearer than the one right of the hole on one of them.
        let at_middle = |w: usize| Some(raw[w * WIDTH + end / 2]).filter(|&r| r != NO_DEPTH);
        let up = (0..v).rev().find_map(at_middle);
        let down = (v + 1..HEIGHT).find_map(at_middle);
        let behind = |r: Option<u16>| r.is_some_and(|r| self.disp(r) <= d_bg + SAME_SURFACE);
        if up.is_some() != down.is_some() || (up.is_some() && !behind(up) && !behind(down)) {
            return Err(Refuted);
        }
        Ok(BorderSplit {
            b: b as u16,
            end: end as u16,
            at,
            past: None,
        })
    }

    /// [`Self::left_border_attached`] where the surface right of the hole tells nothing of the
    /// occluder (it leaves the range, shows a few pixels only, is boldly patterned, leaves no
    /// strip, or is not the surface the RGB camera sees at the border): the RGB camera's view
    /// reaches past the IR image's left border, and there it shows the wall the shadow lies on
    /// running on. Read from there, the wall's colour runs from the border to the occluder's
    /// left edge. The occluder's shift is unknown (no strip tells it), and the least that puts
    /// the shadow's start outside the image, the shadow starting at the border, puts its end
    /// nearest: where the occluder at that shift is seen at that edge, moved left by a third of
    /// the shift. A shadow reaching further past the border ends further right; the rest of it
    /// stays OTHER.
    fn past_border(
        &self,
        raw: &[u16],
        rgb: &[u8],
        v: usize,
        b: usize,
        range: Range,
        solid: bool,
    ) -> Option<BorderSplit> {
        // The wall at the border, measured above the hole, or below it where that is farther (a
        // floor below is nearer than the wall). Not measured above, or at the range's end, it
        // may lie beyond the range, as the hole then does: a far wall leaves holes up to the
        // image's top (the sixth simulator's l8, a checkered wall's squares read as a shadow and
        // an occluder; the same rule lost a black rod's shadow from the top corner there).
        let measured = |w: usize| {
            let r = raw[w * WIDTH + BORDER_COLUMN];
            (r != NO_DEPTH).then_some((w, r))
        };
        let up = (0..v).rev().find_map(measured)?;
        let down = (v + 1..HEIGHT).find_map(measured);
        let bg = down.map_or(up.1, |(_, r)| r.max(up.1));
        if bg + 3 * NEAR_FAR >= range.far || !(solid || self.solid(raw, v, (0, b))) {
            return None;
        }
        let d_bg = self.disp(bg);
        let widest = self.widest(bg);
        // The wall past the border, inside the RGB image and plain.
        let mut past = [[0; 3]; PAST];
        for (k, p) in past.iter_mut().enumerate() {
            let (x, y) = self.project(-1.0 - k as f64, v, bg);
            *p = rgb_mean3(rgb, x, y)?;
        }
        let wall: [i32; 3] =
            std::array::from_fn(|c| past.iter().map(|p| p[c]).sum::<i32>() / PAST as i32);
        let step = self.dimmed(COLOUR_STEP, wall);
        if past.iter().any(|&p| hue_dist(p, wall) >= step) {
            return None;
        }
        // And it is the surface measured there: past the border the RGB camera may see the
        // occluder itself (a glossy sphere's shaded side, the hole's highlight its "edge").
        // (At a few spots of it, 3 rows apart: a wall in bands or blotches shows the row's colour
        // at one of them, if not at the first.)
        let alike = |(w, r): (usize, u16)| {
            (0..SPOTS).any(|k| {
                let w = if w < v {
                    w.checked_sub(SPOT_ROWS * k)
                } else {
                    Some(w + SPOT_ROWS * k).filter(|&w| w < HEIGHT)
                };
                w.is_some_and(|w| {
                    let q = raw[w * WIDTH + BORDER_COLUMN];
                    self.on_surface(q, r)
                        && self
                            .probe(rgb, BORDER_COLUMN, w, q)
                            .is_some_and(|p| hue_dist(p, wall) < step)
                })
            })
        };
        if !alike(up) && !down.is_some_and(alike) {
            return None;
        }
        let is_wall = |u: usize| self.probe(rgb, u, v, bg).map(|p| hue_dist(p, wall) < step);
        // From the border: the wall (the shadow, as the RGB camera sees it), an edge, then mostly
        // occluder.
        let seen = (0..b.min(widest))
            .take_while(|&u| is_wall(u) == Some(true))
            .count();
        if seen < MIN_STRIP
            || b < seen + MIN_HOLE
            || (seen..seen + EDGE).any(|u| is_wall(u) != Some(false))
        {
            return None;
        }
        if !mostly_unlike(seen..b, is_wall) {
            return None;
        }
        // The shadow's end: the occluder's left edge at the shift that starts it at the border.
        let x_at = |u: usize, raw: u16| self.project(u as f64 - 0.5, v, raw).0;
        let x_left = x_at(seen, bg);
        let end = (seen..b.min(widest + 1))
            .find(|&e| x_at(e, self.raw_at_disp(d_bg + e as f64)) >= x_left)?;
        if b < end + MIN_HOLE {
            return None;
        }
        Some(BorderSplit {
            b: b as u16,
            end: end as u16,
            at: self.raw_at_disp(d_bg + end as f64),
            past: Some((bg, raw[v * WIDTH + b])),
        })
    }

    /// Whether a row within two of `v` reads its left-border hole alike (the occluder's edge
    /// within [`ENDS_AGREE`] of `split`'s): an occluder is a solid; a wall beyond the range, or
    /// a surface's pattern, gives such a reading in a row here and there.
    pub(super) fn border_agreed(
        &self,
        raw: &[u16],
        rgb: &[u8],
        v: usize,
        split: BorderSplit,
        range: Range,
    ) -> bool {
        let alike = |s: Option<BorderSplit>| {
            s.is_some_and(|s| usize::from(s.end).abs_diff(usize::from(split.end)) <= ENDS_AGREE)
        };
        // Rows above were read already; rows below are read now.
        let read = |w: usize| {
            let row = &raw[w * WIDTH..(w + 1) * WIDTH];
            (row[0] == NO_DEPTH)
                .then(|| {
                    let b = span_end(&self.masks[w], row, 0);
                    self.left_border_attached(raw, rgb, w, b, range)
                })
                .flatten()
        };
        (1..=2).any(|k| v >= k && alike(self.border_read[v - k]))
            || (1..=2).any(|k| v + k < HEIGHT - 1 && alike(read(v + k)))
    }

    /// Rows between two that read their left-border hole as an occluder and its shadow (at most
    /// [`BRIDGE_ROWS`] apart, the hole's end within [`ENDS_AGREE`] of theirs) take the nearer
    /// one's reading: the vertical consensus would label their shadow anyway, and without the
    /// occluder's depth the warp would show all of it in the RGB view, where the occluder
    /// hides a third of it.
    pub(super) fn bridge_left_border(&self, raw: &[u16], labels: &mut [u8], filled: &mut [u16]) {
        // Most frames hold no reading at all: nothing to bridge.
        if self.border.iter().all(Option::is_none) {
            return;
        }
        for v in 1..HEIGHT - 1 {
            let row = &raw[v * WIDTH..(v + 1) * WIDTH];
            if self.border[v].is_some() || row[0] != NO_DEPTH {
                continue;
            }
            let b = span_end(&self.masks[v], row, 0);
            let near = |w: Option<usize>| {
                let s = self.border[w?]?;
                (usize::from(s.b).abs_diff(b) <= ENDS_AGREE && usize::from(s.end) < b).then_some(s)
            };
            let above = (1..=BRIDGE_ROWS).find_map(|k| near(v.checked_sub(k)).map(|s| (k, s)));
            let below = (1..=BRIDGE_ROWS)
                .find_map(|k| near((v + k < HEIGHT).then_some(v + k)).map(|s| (k, s)));
            if let (Some((ka, sa)), Some((kb, sb))) = (above, below) {
                let s = if ka <= kb { sa } else { sb };
                let past = s.past.map(|(wall, _)| (wall, row[b]));
                BorderSplit {
                    b: b as u16,
                    past,
                    ..s
                }
                .apply(v, labels, filled);
            }
        }
    }
}
