//! IR-view scanline classifier (Deng et al. 2013, §3): each row is scanned once, left to right.
//!
//! The projector sits to the right of the IR camera, so a projector shadow always lies LEFT of its
//! occluder (SPEC §1). For a hole bounded by valid pixels Sa (left) and Sb (right):
//! - if Sb is nearer than Sa, the hole is Sb's attached shadow, whose width is predicted by eq. (3)
//!   `w = disp(Sb) − disp(Sa)`, with room for the sensor's widening of up to ~7 px; a hole much
//!   wider than that is a shadow on a surface that is a hole anyway, so OTHER;
//! - otherwise a thin occluder further right may have cast it (detached shadow): its edges Fa, Fb
//!   must satisfy eqs. (4)–(5), i.e. in projector coordinates the occluder covers the hole exactly;
//! - anything else is OTHER.
//!
//! Disparity is linear in the raw value (see [`crate::calib`]), so all tests run on raw values
//! scaled by one constant. Everything is on the stack: no allocation per row or frame.

use super::align::Simd;
use super::holes::HoleMask;
use super::Params;
use crate::calib::Calibration;
use crate::labels::{ATTACHED, DETACHED, NO_DEPTH, OTHER, VALID, WIDTH};
use std::cell::Cell;

/// Most hole runs a 640-pixel row can hold.
const MAX_RUNS: usize = WIDTH / 2 + 1;

/// Per-calibration constants of the scanline classifier.
#[derive(Clone, Debug)]
pub struct ScanParams {
    /// Disparity pixels per raw unit (`f·b / numerator`).
    k: f32,
    /// Raw value of zero disparity (the model's denominator).
    den: f32,
    min_step: f32,
    over: f32,
    tol: f32,
    max_island: usize,
    /// Largest disparity (px) of a surface the sensor can measure (at [`super::NEAREST_M`]).
    max_disp: f32,
    /// Raw value assumed for holes with no valid neighbour at all (a surface at 2.5 m).
    fallback_raw: u16,
    /// Which build of the hot loops this CPU runs.
    simd: Simd,
    /// Raw-value step of a depth edge (`min_step` pixels of disparity; disparity is linear in
    /// raw, so the float test is one integer compare), for flying pixels and occluder walks.
    edge_raw: u16,
    /// The raw value at [`MIN_RANGE_M`]: no frame's range ends nearer.
    min_far: u16,
}

/// The nearest the sensor's range can end (metres). A frame's farthest value stands for that end
/// only beyond it: where a black box hides the rest of a receding back wall, its last measured
/// pixels (3.4 m) were taken for the range's end and the box's shadow on it for a wall leaving
/// the range, OTHER. The Kinect v1 measures to 4 m and more (the other simulator ends its range
/// at 4.0–5.0 m, this project's at 4.5 m): a floor at 4.0 m lost shadows in one suite whose
/// range ends there, at 3.5 m none. (Fourth simulator, 40 suites: complex IR attached F1
/// +0.044 summed, j39 +0.036, recall +0.062; simple +0.007, precision −0.003; the real frame,
/// whose farthest pixel lies at 7 m, unchanged.)
const MIN_RANGE_M: f64 = 3.5;

impl ScanParams {
    /// Derives the constants from a calibration and thresholds.
    pub fn new(calib: &Calibration, p: &Params) -> Self {
        let fallback = calib.raw_from_depth(2.5).round().clamp(0.0, 2046.0) as u16;
        ScanParams {
            k: calib.px_per_raw() as f32,
            den: calib.raw.denominator as f32,
            min_step: p.min_step_px as f32,
            over: p.attached_over_px as f32,
            tol: p.detached_tol_px as f32,
            max_island: p.max_island_px,
            max_disp: (calib.fb() / super::NEAREST_M) as f32,
            fallback_raw: fallback,
            simd: Simd::detect(),
            edge_raw: (p.min_step_px / calib.px_per_raw()).ceil().max(2.0) as u16,
            min_far: calib.raw_from_depth(MIN_RANGE_M).round().clamp(0.0, 2046.0) as u16,
        }
    }

    /// Runs the given build of the hot loops (tests compare the builds).
    #[cfg(test)]
    pub(crate) fn set_simd(&mut self, simd: Simd) {
        self.simd = simd;
    }

    /// Disparity in pixels of a raw value (eq. 3's `disp`).
    #[inline]
    pub(super) fn disp(&self, raw: u16) -> f32 {
        self.k * (self.den - f32::from(raw))
    }

    /// The smallest disparity step (pixels) read as a depth edge.
    pub(super) fn min_step(&self) -> f32 {
        self.min_step
    }

    /// How much wider than eq. (3) (pixels) an attached shadow may be.
    pub(super) fn over(&self) -> f32 {
        self.over
    }

    /// True for a measured pixel on the background at disparity `d_bg` (within two steps): lit
    /// background beside or between holes.
    #[inline]
    fn on_background(&self, raw: u16, d_bg: f32) -> bool {
        raw != NO_DEPTH && (self.disp(raw) - d_bg).abs() < 2.0 * self.min_step
    }
}

/// Classifies a whole frame row by row. `filled` receives the raw values with each hole replaced
/// by the raw value of the surface it is assumed to lie on (used to warp holes into the RGB view).
/// Returns what the frame says about the sensor, for the colour split.
pub fn classify_frame(
    p: &ScanParams,
    raw: &[u16],
    labels: &mut [u8],
    filled: &mut [u16],
) -> FrameFacts {
    // SAFETY: each build runs only when the CPU reported its features.
    #[cfg(target_arch = "x86_64")]
    match p.simd {
        Simd::Avx512 => return unsafe { classify_frame_avx512(p, raw, labels, filled) },
        Simd::Avx2 => return unsafe { classify_frame_avx2(p, raw, labels, filled) },
        Simd::Baseline => {}
    }
    classify_frame_body(p, raw, labels, filled)
}

/// [`classify_frame`] compiled for AVX2+FMA.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
unsafe fn classify_frame_avx2(
    p: &ScanParams,
    raw: &[u16],
    labels: &mut [u8],
    filled: &mut [u16],
) -> FrameFacts {
    classify_frame_body(p, raw, labels, filled)
}

/// [`classify_frame`] compiled for AVX-512.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f,avx512bw,avx512vl,avx512dq,avx2,fma")]
unsafe fn classify_frame_avx512(
    p: &ScanParams,
    raw: &[u16],
    labels: &mut [u8],
    filled: &mut [u16],
) -> FrameFacts {
    classify_frame_body(p, raw, labels, filled)
}

#[inline(always)]
fn classify_frame_body(
    p: &ScanParams,
    raw: &[u16],
    labels: &mut [u8],
    filled: &mut [u16],
) -> FrameFacts {
    // Last valid raw value seen in each column in the rows above: background for holes that touch
    // the left border, where the row itself has no Sa.
    let mut column_memory = [NO_DEPTH; WIDTH];
    let range = Range::of(raw).at_least(p.min_far);
    let mut widening = Widening::default();
    let mut too_wide = TooWide::new();
    let mut below_memory = BelowMemory::new();
    let mut holes = [Run::default(); MAX_RUNS];
    // The row above as the rules that inherit OTHER from it read it: its holes waiting on the
    // frame's widening (`too_wide`) that the widening of the rows so far would make ATTACHED are
    // a shadow (a table top's, too wide only for a Kinect), no surface the sensor cannot measure.
    let mut above_labels = [VALID; WIDTH];
    let mut pending_from = 0;
    let walks = Walks::new();
    for (v, (row, fill)) in raw
        .chunks_exact(WIDTH)
        .zip(filled.chunks_exact_mut(WIDTH))
        .enumerate()
    {
        let (done, rest) = labels.split_at_mut(v * WIDTH);
        let mut prev_labels = &done[done.len().saturating_sub(WIDTH)..];
        let pending = too_wide.since(pending_from).iter();
        // (The median is read only for the few rows under such a hole.)
        let covered = if pending.len() > 0 {
            p.over + widening.extra_over()
        } else {
            0.0
        };
        if pending.clone().any(|&(_, _, excess)| excess <= covered) {
            above_labels.copy_from_slice(prev_labels);
            let row_start = (v - 1) * WIDTH;
            for &(start, end, _) in pending.filter(|&&(_, _, excess)| excess <= covered) {
                above_labels[start as usize - row_start..end as usize - row_start].fill(ATTACHED);
            }
            prev_labels = &above_labels;
        }
        pending_from = too_wide.len;
        too_wide.row = v * WIDTH;
        classify_row_with(
            p,
            row,
            &column_memory,
            &raw[..v * WIDTH],
            prev_labels,
            &raw[(v + 1) * WIDTH..],
            range,
            &mut rest[..WIDTH],
            fill,
            &mut holes,
            &mut widening,
            Some(&mut too_wide),
            Some(&mut below_memory),
            &walks,
        );
        for (m, &r) in column_memory.iter_mut().zip(row) {
            *m = if r != NO_DEPTH { r } else { *m };
        }
    }
    too_wide.settle(p.over, widening.extra_over(), raw, labels);
    FrameFacts {
        range,
        left_widening: widening.left(),
    }
}

/// What a bounded hole is judged against besides its own row.
#[derive(Clone, Copy)]
struct Context<'a> {
    /// What the frame says about the sensor's range.
    range: Range,
    /// Per column, the last valid raw value in the rows above (or 2047).
    above: &'a [u16],
    /// The labels of the row above (empty for the first row).
    prev_labels: &'a [u8],
    /// The rows around this one.
    rows: Rows<'a>,
    /// What the hidden background's walks up and down columns found in the rows so far.
    walks: &'a Walks,
}

/// Every row above and every row below a row (whole rows of `n` values; either may be empty).
#[derive(Clone, Copy)]
struct Rows<'a> {
    up: &'a [u16],
    down: &'a [u16],
}

impl<'a> Rows<'a> {
    /// The row just above and the row just below (empty where there is none).
    fn near(&self, n: usize) -> [&'a [u16]; 2] {
        [
            &self.up[self.up.len() - self.up.len().min(n)..],
            &self.down[..self.down.len().min(n)],
        ]
    }

    /// The rows up to `k` above and `k` below, nearest first.
    fn within(&self, n: usize, k: usize) -> impl Iterator<Item = &'a [u16]> + 'a {
        let Rows { up, down } = *self;
        let (rows_up, rows_down) = (up.len() / n, down.len() / n);
        (1..=k).flat_map(move |j| {
            let a = (j <= rows_up).then(|| &up[(rows_up - j) * n..(rows_up - j + 1) * n]);
            let b = (j <= rows_down).then(|| &down[(j - 1) * n..j * n]);
            a.into_iter().chain(b)
        })
    }
}

/// A run of pixels `[start, end)`.
#[derive(Clone, Copy, Debug, Default)]
struct Run {
    start: usize,
    end: usize,
}

/// The largest valid raw value of a frame: the farthest surface the sensor measured in it, a
/// stand-in for its range limit (branch-free, vectorised).
#[inline(always)]
pub fn farthest_measured(raw: &[u16]) -> u16 {
    // Sixteen independent lanes: a single running max is a serial chain the compiler keeps scalar.
    // Inlined into each SIMD build of the frame loop: baseline x86-64 has no unsigned 16-bit max.
    let mut lanes = [0u16; 16];
    let chunks = raw.chunks_exact(16);
    let tail = chunks
        .remainder()
        .iter()
        .copied()
        .filter(|&r| r != NO_DEPTH)
        .max()
        .unwrap_or(0);
    for chunk in chunks {
        for (m, &r) in lanes.iter_mut().zip(chunk) {
            *m = (*m).max(if r == NO_DEPTH { 0 } else { r });
        }
    }
    lanes.into_iter().max().unwrap_or(0).max(tail)
}

/// What the scanline learns about the sensor from one frame, for the colour split.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FrameFacts {
    /// The sensor's range limit.
    pub range: Range,
    /// How many pixels the sensor's widening adds to a shadow's left end: half the median by
    /// which the frame's attached holes (bounded by their background on the left and their
    /// occluder on the right) are wider than eq. (3) says. About 1 px on a real Kinect (half of
    /// SPEC §1's 2 px; 1.125 px from the real NYU frame), 0 on noise-free geometry, and 0 in a
    /// frame with fewer than 16 such holes. The colour split measures a shadow from the hole's first
    /// pixel, so the occluder's shift is the width less this.
    pub left_widening: f64,
}

/// Histogram of how much wider than eq. (3) the attached holes of a frame are, in half-pixel
/// bins from −3 to +5 px. Wider holes are no sensor's widening alone: a curved occluder's
/// silhouette, seen by the projector and the camera at different tangents, makes one object's
/// every row some 5 px wider, enough rows to move a frame's median by two pixels.
#[derive(Clone, Copy, Debug, Default)]
struct Widening {
    bins: [u32; 17],
}

impl Widening {
    /// Attached holes a frame needs before its own widening is trusted; with fewer, shadows are
    /// taken as wide as geometry says (assuming a real Kinect's 1 px there cost the
    /// hand-computed black box at a slanted edge 2.7 px in a noise-free frame with no other
    /// shadow).
    const MIN_SAMPLES: u32 = 16;

    /// One attached hole, `excess` px wider than its eq. (3) width `w` (narrow ones say little).
    #[inline]
    fn record(&mut self, excess: f32, w: f32) {
        if w >= 2.0 && (-3.0..5.0).contains(&excess) {
            self.bins[((excess + 3.0) * 2.0).round() as usize] += 1;
        }
    }

    /// The median excess (px), if the frame has enough attached holes to tell.
    fn median(&self) -> Option<f64> {
        let n: u32 = self.bins.iter().sum();
        if n < Self::MIN_SAMPLES {
            return None;
        }
        let mut seen = 0;
        let bin = self
            .bins
            .iter()
            .position(|&h| {
                seen += h;
                2 * seen >= n
            })
            .unwrap_or(0);
        Some(bin as f64 / 2.0 - 3.0)
    }

    /// Half the median excess, between 0 and 2 px ([`FrameFacts::left_widening`]).
    fn left(&self) -> f64 {
        self.median().map_or(0.0, |m| (m / 2.0).clamp(0.0, 2.0))
    }

    /// How much more than `attached_over_px` a shadow may be widened in this frame: none for a
    /// Kinect (median excess 2.3 px on the real frame, 2.2 on the simulator's), more for a sensor
    /// whose correlation window widens more, whose spread of widths grows with it (three times
    /// the median's excess over 2.5 px, up to [`MAX_EXTRA_OVER`]).
    fn extra_over(&self) -> f32 {
        self.median().map_or(0.0, |m| {
            (3.0 * (m - 2.5)).clamp(0.0, MAX_EXTRA_OVER as f64) as f32
        })
    }
}

/// Most extra widening [`Widening::extra_over`] allows (pixels).
const MAX_EXTRA_OVER: f32 = 6.0;

/// Per column, the first valid pixel below the rows searched so far: a hole at the left border
/// may run down a long way (a box's shadow from the frame's top), and its rows ask the same
/// columns in turn, so each column is scanned downwards at most once per frame.
struct BelowMemory {
    /// Row of the pixel found (the frame's height if none), 0 where never searched.
    row: [u16; WIDTH],
    /// Its raw value (2047 if none) and the surface's slope there (raw units per row down).
    found: [(u16, f32); WIDTH],
}

impl BelowMemory {
    fn new() -> Self {
        BelowMemory {
            row: [0; WIDTH],
            found: [(NO_DEPTH, 0.0); WIDTH],
        }
    }

    /// [`surface_below`] for row `v`, `below` the rows under it.
    fn surface_below(&mut self, v: usize, below: &[u16], col: usize) -> Option<(u16, f32)> {
        if usize::from(self.row[col]) <= v {
            let found = first_valid_below(below, col);
            let rows = below.len() / WIDTH;
            self.row[col] = (v + 1 + found.map_or(rows, |(k, ..)| k)) as u16;
            self.found[col] = found.map_or((NO_DEPTH, 0.0), |(_, r, slope)| (r, slope));
        }
        let (r, slope) = self.found[col];
        let dist = usize::from(self.row[col]) - v;
        (r != NO_DEPTH).then(|| (r, along(r, slope, dist)))
    }
}

/// The first valid raw value in column `col` of `below` (whole rows), and the value its surface
/// would have carried up to the row above `below`: a wall that recedes upwards (a pitched camera,
/// a yawed wall's far side) may leave the sensor's range in the rows of a hole above it. (Only
/// as a test: a floor carried up meets the wall long before.)
fn surface_below(below: &[u16], col: usize) -> Option<(u16, f32)> {
    first_valid_below(below, col).map(|(k, r, slope)| (r, along(r, slope, k + 1)))
}

/// `r` carried `dist` rows up along `slope` (raw units per row down), where that slope is clearly
/// more than noise: over 32 rows, pair-averaged, a level wall's slope is off by some 0.02.
fn along(r: u16, slope: f32, dist: usize) -> f32 {
    const STEEP: f32 = 0.1;
    let r = f32::from(r);
    if slope < -STEEP {
        r - slope * dist as f32
    } else {
        r
    }
}

/// The first valid pixel of column `col` in `below` (whole rows): its row there, raw value, and
/// the slope of its surface down the column (raw units per row, over up to 32 rows of it).
fn first_valid_below(below: &[u16], col: usize) -> Option<(usize, u16, f32)> {
    const SPAN: usize = 32;
    // Raw units within which two pixels a row or two apart are one surface.
    const SAME: u16 = 4;
    let mut column = below.chunks_exact(WIDTH).map(|row| row[col]);
    let k = column.position(|r| r != NO_DEPTH)?;
    let first = below[k * WIDTH + col];
    // The surface's pixels below it, holes stepped over, until a step to another surface.
    let (mut last, mut n) = (first, 1);
    for (j, r) in column.take(SPAN).enumerate() {
        if r == NO_DEPTH {
            continue;
        }
        if r.abs_diff(last) > SAME {
            break;
        }
        last = r;
        n = j + 2;
    }
    // Ends averaged with their neighbours; a surface of fewer rows tells no slope from noise.
    let slope = if n >= 8 {
        let at = |j: usize| {
            below
                .get((k + j) * WIDTH + col)
                .copied()
                .unwrap_or(NO_DEPTH)
        };
        let pair = |j: usize| {
            let (a, b) = (at(j), at(j + 1));
            if a != NO_DEPTH && b != NO_DEPTH && a.abs_diff(b) <= SAME {
                0.5 * (f32::from(a) + f32::from(b))
            } else {
                f32::from(a.min(b))
            }
        };
        (pair(n - 2) - pair(0)) / (n - 2) as f32
    } else {
        0.0
    };
    Some((k, first, slope))
}

/// Holes that would be attached shadows but for being up to [`MAX_EXTRA_OVER`] px wider than
/// `attached_over_px` allows: attached after all if the frame's widening says so, which is known
/// only once every row is scanned. A fixed capacity: nothing is allocated per frame.
struct TooWide {
    /// `(start, end)` in the frame (pixel indices) and the hole's excess over eq. (3).
    holes: [(u32, u32, f32); Self::CAPACITY],
    len: usize,
    /// Index of the current row's first pixel.
    row: usize,
}

impl TooWide {
    const CAPACITY: usize = 1024;

    fn new() -> Self {
        TooWide {
            holes: [(0, 0, 0.0); Self::CAPACITY],
            len: 0,
            row: 0,
        }
    }

    fn push(&mut self, h: Run, excess: f32) {
        if self.len < Self::CAPACITY {
            let at = self.row as u32;
            self.holes[self.len] = (at + h.start as u32, at + h.end as u32, excess);
            self.len += 1;
        }
    }

    /// The holes pushed since the first `from`.
    fn since(&self, from: usize) -> &[(u32, u32, f32)] {
        &self.holes[from.min(self.len)..self.len]
    }

    /// Labels attached those still OTHER whose excess the frame's extra widening covers.
    fn settle(&self, over: f32, extra: f32, raw: &[u16], labels: &mut [u8]) {
        if extra <= 0.0 {
            return;
        }
        for &(start, end, excess) in &self.holes[..self.len] {
            let (start, end) = (start as usize, end as usize);
            if excess <= over + extra && labels[start] == OTHER {
                set(labels, raw, start, end, ATTACHED);
            }
        }
    }
}

/// What a frame says about the sensor's range limit.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Range {
    /// The farthest valid raw value ([`farthest_measured`]): the noisiest far pixel.
    pub far: u16,
    /// Where the values stop being common ([`range_limit`]): a surface at the limit scatters a
    /// sparse tail a raw unit or two past it.
    pub limit: u16,
}

impl Range {
    /// The range of frame `raw`.
    #[inline(always)]
    pub fn of(raw: &[u16]) -> Range {
        let far = farthest_measured(raw);
        Range {
            far,
            limit: range_limit(raw, far),
        }
    }

    /// A range with nothing known under `far`.
    pub fn at(far: u16) -> Range {
        Range { far, limit: far }
    }

    /// This range, or one ending at `floor` where it ends nearer: no sensor's range ends short
    /// of 3.5 m, so a nearer farthest value is merely the frame's farthest surface.
    pub fn at_least(self, floor: u16) -> Range {
        if self.far < floor {
            Range::at(floor)
        } else {
            self
        }
    }
}

/// Steps down from `far` while a value is under a quarter as common as the next nearer one, at
/// most three raw units, counting every fourth row (the counts are large where it matters).
#[inline(always)]
pub fn range_limit(raw: &[u16], far: u16) -> u16 {
    const STEPS: usize = 3;
    if far <= STEPS as u16 {
        return far;
    }
    let mut counts = [0u32; STEPS + 1];
    for row in raw.chunks_exact(WIDTH).step_by(4) {
        let mut c = [0u16; STEPS + 1];
        for &r in row {
            for (k, c) in c.iter_mut().enumerate() {
                *c += u16::from(r == far - k as u16);
            }
        }
        for (t, c) in counts.iter_mut().zip(c) {
            *t += u32::from(c);
        }
    }
    let mut limit = far;
    for k in 0..STEPS {
        if 4 * counts[k] >= counts[k + 1] {
            break;
        }
        limit -= 1;
    }
    limit
}

/// Classifies one row: `raw` in, `labels` and `filled` out. `above` holds, per column, the last
/// valid raw value in the rows above (or 2047); `prev` is the raw row above (empty for the first
/// row); `below` is the rest of the frame under this row (whole rows, possibly empty). They serve
/// holes that touch the left border, and the vertical check of depthless occluders. `range` is
/// the frame's [`Range`].
#[inline(always)]
#[allow(clippy::too_many_arguments)]
pub fn classify_row(
    p: &ScanParams,
    raw: &[u16],
    above: &[u16],
    prev: &[u16],
    below: &[u16],
    range: Range,
    labels: &mut [u8],
    filled: &mut [u16],
) {
    let mut holes = [Run::default(); MAX_RUNS];
    classify_row_with(
        p,
        raw,
        above,
        prev,
        &[],
        below,
        range,
        labels,
        filled,
        &mut holes,
        &mut Widening::default(),
        None,
        None,
        &Walks::new(),
    );
}

/// [`classify_row`] with the caller's scratch for the row's hole runs (zeroing 5 KB per row
/// cost a tenth of the whole scanline).
#[inline(always)]
#[allow(clippy::too_many_arguments)]
fn classify_row_with(
    p: &ScanParams,
    raw: &[u16],
    above: &[u16],
    up: &[u16],
    prev_labels: &[u8],
    below: &[u16],
    range: Range,
    labels: &mut [u8],
    filled: &mut [u16],
    holes: &mut [Run; MAX_RUNS],
    widening: &mut Widening,
    mut too_wide: Option<&mut TooWide>,
    mut below_memory: Option<&mut BelowMemory>,
    walks: &Walks,
) {
    let n = raw.len();
    filled.copy_from_slice(raw);
    for (l, &r) in labels.iter_mut().zip(raw) {
        *l = u8::from(r == NO_DEPTH) * OTHER; // VALID is 0; arithmetic, so it vectorises
    }
    snap_flying_pixels(p, raw, filled);
    let count = find_holes(raw, holes);
    let holes = merge_islands(p, raw, &mut holes[..count]);

    for h in holes.iter() {
        let left = (h.start > 0).then(|| bound_left(raw, h.start));
        let right = (h.end < n).then(|| bound_right(raw, h.end));
        match (left, right) {
            (Some(sa), Some(sb)) => {
                let context = Context {
                    range,
                    above,
                    prev_labels,
                    rows: Rows { up, down: below },
                    walks,
                };
                classify_bounded(p, raw, *h, sa, sb, context, labels, filled);
                if labels[h.start] == ATTACHED && sb.edge < sa.edge {
                    let w = p.disp(sb.edge) - p.disp(sa.edge);
                    widening.record((h.end - h.start) as f32 - w, w);
                    continue;
                }
                let split =
                    labels[h.start] == OTHER && split_merged(p, raw, *h, context, labels, filled);
                if split {
                    continue;
                }
                if let (OTHER, Some(too_wide)) = (labels[h.start], too_wide.as_deref_mut()) {
                    // Eq. (3) as classify_bounded reads it; too wide by no more than a sensor
                    // that widens more than a Kinect could make it.
                    let w = p.disp(sb.near) - p.disp(sa.far);
                    let excess = (h.end - h.start) as f32 - w;
                    if w >= p.min_step
                        && excess > p.over
                        && excess <= p.over + MAX_EXTRA_OVER
                        && !same_surface(p, raw, *h, sa, sb, p.min_step)
                        && !thin_occluder(p, raw, h.end, w, context.rows)
                    {
                        too_wide.push(*h, excess);
                    }
                }
            }
            (None, Some(sb)) => {
                let rows = Rows { up, down: below };
                let memory = below_memory.as_deref_mut();
                let context = (range, above, prev_labels, rows, memory);
                classify_left_border(p, raw, *h, sb, context, labels, filled)
            }
            (Some(sa), None) => fill(filled, *h, sa.far),
            (None, None) => fill(filled, *h, p.fallback_raw),
        }
    }
}

/// A "flying" pixel at a depth edge mixes foreground and background into a depth between them:
/// a surface that is not there, which the RGB camera never sees. For the warp (`filled` only; the
/// pixel stays VALID with its measured value) it joins the side whose depth it is nearer to, so
/// the alignment gap opens at the edge instead of around the phantom. Only between two surfaces
/// that are not themselves ramps as steep as the step: on a face receding at a pixel of disparity
/// per pixel every pixel lies between its neighbours, and snapping it would cut the face into
/// steps that the warp opens into false alignment shadows.
#[inline(always)]
fn snap_flying_pixels(p: &ScanParams, raw: &[u16], filled: &mut [u16]) {
    let big = p.edge_raw;
    let n = raw.len();
    // Five shifted views of one length and selects instead of branches: vectorises.
    let len = n - 4;
    let (a2s, as_, ms, bs, b2s) = (
        &raw[..len],
        &raw[1..1 + len],
        &raw[2..2 + len],
        &raw[3..3 + len],
        &raw[4..4 + len],
    );
    let out = &mut filled[2..2 + len];
    // A flying pixel lies between valid pixels two apart that differ by a full edge step. Most
    // blocks of a row hold no such step, and testing for one costs a fraction of the full test
    // below (both branch-free, vectorised): about 10 µs of the scanline's 0.29 ms on the real
    // frame.
    const BLOCK: usize = 64;
    let mut start = 0;
    while start < len {
        let end = (start + BLOCK).min(len);
        let any_step = as_[start..end]
            .iter()
            .zip(&bs[start..end])
            .fold(false, |any, (&a, &b)| {
                any | ((a.max(b) < NO_DEPTH) & (a.abs_diff(b) >= big))
            });
        if any_step {
            snap_block(start..end, big, [a2s, as_, ms, bs, b2s], out);
        }
        start = end;
    }
}

/// The full flying-pixel test of [`snap_flying_pixels`] on positions `at` of its five shifted
/// views (`big` the edge step), snapping `out` where it passes.
#[inline(always)]
fn snap_block(at: std::ops::Range<usize>, big: u16, views: [&[u16]; 5], out: &mut [u16]) {
    let [a2s, as_, ms, bs, b2s] = views;
    let quarter = big / 4;
    // All values are ≤ 2047, so u16 arithmetic (16 lanes per AVX2 instruction) cannot overflow;
    // where `flying` is false the wrapping differences are garbage and discarded by the select.
    for i in at {
        let (a2, a, m, b, b2) = (a2s[i], as_[i], ms[i], bs[i], b2s[i]);
        let (lo, hi) = (a.min(b), a.max(b));
        let step = hi.wrapping_sub(lo);
        // A side is flat when its next step is under a third of the edge's, or a hole.
        let flat = |x: u16, y: u16| (x.abs_diff(y) * 3 < step) | (x == NO_DEPTH);
        // Strictly between two valid sides a full edge step apart, and clear of both; holes
        // (2047) are the largest value, so `hi < NO_DEPTH` and `m < NO_DEPTH` exclude them.
        let flying = (hi < NO_DEPTH)
            & (m < NO_DEPTH)
            & (step >= big)
            & (m >= lo + quarter)
            & (m.wrapping_add(quarter) <= hi)
            & flat(a2, a)
            & flat(b2, b);
        let nearer = if m.wrapping_sub(lo) <= hi.wrapping_sub(m) {
            lo
        } else {
            hi
        };
        let f = &mut out[i];
        *f = if flying { nearer } else { *f };
    }
}

/// Robust depth of a hole's bound: the farthest (`far`) and nearest (`near`) raw value among up to
/// three valid pixels next to the hole, so one mixed edge pixel does not decide the class.
#[derive(Clone, Copy, Debug)]
struct Bound {
    /// Raw value of the pixel touching the hole.
    edge: u16,
    /// Largest raw value (farthest surface) of the samples.
    far: u16,
    /// Smallest raw value (nearest surface) of the samples.
    near: u16,
}

fn bound_left(raw: &[u16], start: usize) -> Bound {
    let edge = raw[start - 1];
    let (mut far, mut near) = (edge, edge);
    for &r in raw[..start - 1]
        .iter()
        .rev()
        .take(2)
        .take_while(|&&r| r != NO_DEPTH)
    {
        far = far.max(r);
        near = near.min(r);
    }
    Bound { edge, far, near }
}

fn bound_right(raw: &[u16], end: usize) -> Bound {
    let edge = raw[end];
    let (mut far, mut near) = (edge, edge);
    for &r in raw[end + 1..]
        .iter()
        .take(2)
        .take_while(|&&r| r != NO_DEPTH)
    {
        far = far.max(r);
        near = near.min(r);
    }
    Bound { edge, far, near }
}

/// The runs of "no depth" pixels of `raw` (at most [`WIDTH`] long), left to right, into `out`;
/// returns how many. Read off the row's [`HoleMask`], so the cost is per hole, not per pixel.
#[inline(always)]
fn find_holes(raw: &[u16], out: &mut [Run; MAX_RUNS]) -> usize {
    let mask = HoleMask::of(raw);
    let mut count = 0;
    let mut start = mask.next_hole(0);
    while start < raw.len() {
        let end = mask.next_valid(start);
        out[count] = Run { start, end };
        count += 1;
        start = mask.next_hole(end);
    }
    count
}

/// Joins holes separated by a valid island of at most `max_island` pixels, unless the island is
/// nearer than both surroundings (then it is a thin object, not noise inside a shadow).
fn merge_islands<'a>(p: &ScanParams, raw: &[u16], holes: &'a mut [Run]) -> &'a [Run] {
    if holes.is_empty() {
        return holes;
    }
    let mut kept = 0;
    for i in 1..holes.len() {
        let (prev, next) = (holes[kept], holes[i]);
        let island = &raw[prev.end..next.start];
        let mergeable = island.len() <= p.max_island && {
            let island_disp = p.disp(*island.iter().min().unwrap());
            let left = (prev.start > 0).then(|| p.disp(raw[prev.start - 1]));
            let right = raw.get(next.end).map(|&r| p.disp(r));
            let nearer = |d: Option<f32>| d.is_some_and(|d| island_disp > d + p.min_step);
            !(nearer(left) && nearer(right))
        };
        if mergeable {
            holes[kept].end = next.end;
        } else {
            kept += 1;
            holes[kept] = next;
        }
    }
    &holes[..=kept]
}

/// A hole [`merge_islands`] joined that no reading explains as one (all OTHER), read as the
/// holes either side of its first island, that island their bound, when the first of them is a
/// shadow: an edge's attached shadow, a pixel of lit wall the widening left, and a rod's
/// detached shadow past it. True (and `h` relabelled) when it is. (Not when only the second
/// is: a black rod and the attached shadow on it, beside a lit pixel, fit eq. 3 as one.)
fn split_merged(
    p: &ScanParams,
    raw: &[u16],
    h: Run,
    context: Context,
    labels: &mut [u8],
    filled: &mut [u16],
) -> bool {
    let Some(i0) = raw[h.start..h.end].iter().position(|&r| r != NO_DEPTH) else {
        return false;
    };
    // A single pixel before the island is speckle (a third of such holes on the real frame).
    // Only a hole no reading explained (a hole without an island, most of them, stops above).
    if i0 < 2
        || !labels[h.start..h.end]
            .iter()
            .all(|&l| l == OTHER || l == VALID)
    {
        return false;
    }
    let i0 = h.start + i0;
    let i1 = i0
        + raw[i0..h.end]
            .iter()
            .take_while(|&&r| r != NO_DEPTH)
            .count();
    let (first, second) = (
        Run {
            start: h.start,
            end: i0,
        },
        Run {
            start: i1,
            end: h.end,
        },
    );
    // The merged reading's assumed depths, kept to go back to (its labels are all OTHER). A
    // copy, not a second reading: most such holes of a real frame are clutter whose first part
    // is no shadow either.
    let mut kept = [0u16; WIDTH];
    let kept = &mut kept[..h.end - h.start];
    kept.copy_from_slice(&filled[h.start..h.end]);
    // The first part is read from the hole as the row's start left it.
    place(filled, raw, h, NO_DEPTH);
    classify_bounded(
        p,
        raw,
        first,
        bound_left(raw, h.start),
        bound_right(raw, i0),
        context,
        labels,
        filled,
    );
    if labels[first.start..first.end]
        .iter()
        .any(|&l| l == ATTACHED || l == DETACHED)
    {
        classify_bounded(
            p,
            raw,
            second,
            bound_left(raw, i1),
            bound_right(raw, h.end),
            context,
            labels,
            filled,
        );
        return true;
    }
    set(labels, raw, first.start, first.end, OTHER);
    filled[h.start..h.end].copy_from_slice(kept);
    false
}

fn set(labels: &mut [u8], raw: &[u16], from: usize, to: usize, code: u8) {
    // Merged islands keep their VALID label: they have depth.
    for (l, &r) in labels[from..to].iter_mut().zip(&raw[from..to]) {
        if r == NO_DEPTH {
            *l = code;
        }
    }
}

/// Sets the hole pixels of `h` to `value`, whatever they were filled with before.
fn place(filled: &mut [u16], raw: &[u16], h: Run, value: u16) {
    // A select, not a branch per pixel: vectorises.
    for (f, &r) in filled[h.start..h.end].iter_mut().zip(&raw[h.start..h.end]) {
        *f = if r == NO_DEPTH { value } else { *f };
    }
}

/// Sets the pixels of `h` still without depth in `filled` to `value`.
fn fill(filled: &mut [u16], h: Run, value: u16) {
    for f in &mut filled[h.start..h.end] {
        *f = if *f == NO_DEPTH { value } else { *f };
    }
}

/// A hole with valid pixels on both sides, judged with its `context` (the rows around it among
/// them).
#[allow(clippy::too_many_arguments)]
fn classify_bounded(
    p: &ScanParams,
    raw: &[u16],
    h: Run,
    sa: Bound,
    sb: Bound,
    context: Context,
    labels: &mut [u8],
    filled: &mut [u16],
) {
    let Context {
        range,
        above,
        prev_labels,
        rows,
        ..
    } = context;
    let near = rows.near(raw.len());
    // A depthless occluder the hole before this one paired with (its detached shadow) may fill
    // this hole's left part, and Sb's attached shadow the rest (a black rod left of a
    // cylinder's shadow): the rest is read alone.
    let placed = filled[h.start..h.end]
        .iter()
        .take_while(|&&f| f != NO_DEPTH)
        .count();
    // Shadows lie on the background, so fill with the farther side's depth.
    fill(filled, h, sa.far.max(sb.far));
    // Eq. (3): the attached shadow of Sb on the surface of Sa is w = disp(Sb) − disp(Sa) wide.
    let w = p.disp(sb.near) - p.disp(sa.far);
    if placed > 0 && placed < h.end - h.start {
        let rest = Run {
            start: h.start + placed,
            end: h.end,
        };
        if w >= p.min_step && (rest.end - rest.start) as f32 <= w + p.over {
            set(labels, raw, rest.start, rest.end, ATTACHED);
        }
        return;
    }
    if w >= p.min_step && !same_surface(p, raw, h, sa, sb, p.min_step) {
        // Eq. (3) fitting is no proof: Sb, read over three pixels, reaches through a lit gap of
        // two to a rod whose width ties with its shift (its detached shadow, the gap showing in
        // this row). An occluder past a lit gap that fits eqs. (4)–(5) says detached. Holes too
        // wide for eq. (3) get that test below.
        let fits3 = (h.end - h.start) as f32 <= w + p.over;
        if fits3 && detached_beyond_sb(p, raw, h, sa, sb, rows) {
            set(labels, raw, h.start, h.end, DETACHED);
            return;
        }
        label_attached(p, raw, h, w, rows, labels);
        if fits3 && labels[h.start] == ATTACHED && labels[h.end - 1] == ATTACHED {
            if let Some(from) = nearer_shadow_past_sb(p, raw, h, sa) {
                set(labels, raw, from, h.end, DETACHED);
            }
        }
        // Too wide for Sb's shadow on Sa, the hole may be Sb's shadow on a background Sa hides
        // (below), but a thin occluder further right whose shadow it fits by eqs. (4)–(5) says
        // more: only a detached shadow fits both its ends (a rod's shadow on a box's face, beside
        // the box's thin side). Where it also covers Sb's own shadow on Sa, the projector's ray
        // meets that occluder first: its shadow, as `umbra synth` labels it. (A hole eq. (3)
        // fits had its occluder searched for above.)
        if !fits3 {
            let verdict = detached(p, raw, h, Some(sa), sb, rows);
            if verdict.measured() {
                set(labels, raw, h.start, h.end, DETACHED);
                if let Detached::OnSa { raw: at } = verdict {
                    place(filled, raw, h, at);
                }
                return;
            }
        }
        if labels[h.start] == OTHER {
            hidden_background(p, raw, h, (sa, sb), context, labels, filled);
        } else if let Some(bg) = behind_thin_sa(p, raw, h, sa, sb, w, above) {
            place(filled, raw, h, bg);
        }
        beyond_range(raw, h, range, above, prev_labels, near, labels);
        below_unmeasured(p, raw, h, (sb.near, w), (rows, above), prev_labels, labels);
        return;
    }
    // A depthless occluder a pixel or two right of its shadow shares one hole with it (the lit
    // gap between them is an island the hole merged): the parts either side of the island.
    let verdict = match detached(p, raw, h, Some(sa), sb, rows) {
        fallback @ (Detached::No | Detached::Head { .. }) => {
            match split_at_island(p, raw, h, sa, sb) {
                Some((shadow, rest)) => {
                    let d_bg = sa_sb_bg(p, sa, sb);
                    let verdict = hole_pair(p, raw, shadow, rest, d_bg)
                        .map(|pair| depthless_occluder(p, raw, shadow, pair, d_bg, rows));
                    match verdict.unwrap_or(Detached::No) {
                        Detached::Depthless { occluder, raw: at } => {
                            set(labels, raw, shadow.start, shadow.end, DETACHED);
                            // The merged hole was filled with the background's depth above; the
                            // occluder's part of it is nearer.
                            place(filled, raw, occluder, at);
                            return;
                        }
                        _ => fallback,
                    }
                }
                None => fallback,
            }
        }
        other => other,
    };
    match verdict {
        // The rest of the hole stays OTHER; where the shadow really starts, the RGB camera
        // tells (`depthless/tail.rs`).
        Detached::Tail { from } => set(labels, raw, from, h.end, DETACHED),
        Detached::No => {
            // A step under `min_step` that no detached occluder explains: a thin edge's
            // attached shadow, which the widening makes visible (eq. 3 at half the step). The
            // edge pixels themselves must show it: on a flat surface, the extremes of noisy
            // samples and a noisy slope extrapolated over the hole can make up such a step.
            let half = 0.5 * p.min_step;
            let step = p.disp(sb.edge) - p.disp(sa.edge);
            if w >= half && step >= half && !same_surface(p, raw, h, sa, sb, half) {
                label_attached(p, raw, h, w, rows, labels);
            }
            if labels[h.start] == OTHER {
                hidden_background(p, raw, h, (sa, sb), context, labels, filled);
            }
        }
        Detached::Measured => set(labels, raw, h.start, h.end, DETACHED),
        // Warped at Sa's depth: the RGB camera sees that surface there, not the wall.
        Detached::OnSa { raw: at } => {
            set(labels, raw, h.start, h.end, DETACHED);
            place(filled, raw, h, at);
        }
        Detached::Head { to } => set(labels, raw, h.start, to, DETACHED),
        Detached::Depthless { occluder, raw: at } => {
            set(labels, raw, h.start, h.end, DETACHED);
            // The occluder's hole is warped at the depth its shadow implies, so the RGB view
            // sees it where it stands and finds its alignment shadow; `fill` never overwrites.
            fill(filled, occluder, at);
        }
    }
}

/// Relabels OTHER an attached hole under an OTHER hole of the row above that starts at the same
/// column, after the same surface (Sa). That is a region the sensor cannot measure
/// (a far wall beyond range, seen past a partition's edge) running on down behind the occluder,
/// which eq. (3) fits only by chance. A shadow's first row has the lit background above it (the
/// projector is offset sideways, not up), and its other rows the shadow, labelled attached.
/// Above a region the sensor cannot measure lies no measured surface at Sa's depth: where the
/// column memory over the hole's first pixel shows one (`above`), the hole above was something
/// else on that surface, and this hole's top lies under it (an occluder's top face, seen at a
/// grazing angle, is a hole too). Nor is a hole eq. (3) fits to within the sensor's widening
/// ([`FITS_UNDER`], [`FITS_OVER`]) where the hole above runs on past its end onto Sb's own
/// surface: that is Sb's shadow there too, joined to a dropout on Sb's face (a glossy patch),
/// and the occluder stands in both rows; a region running on down behind Sb ends elsewhere
/// above it, or not at all.
/// `(sb, w)`: Sb's nearer raw value and eq. (3)'s width from it.
fn below_unmeasured(
    p: &ScanParams,
    raw: &[u16],
    h: Run,
    (sb, w): (u16, f32),
    (rows, above): (Rows, &[u16]),
    prev_labels: &[u8],
    labels: &mut [u8],
) {
    let [up, _] = rows.near(raw.len());
    let a = h.start - 1;
    // Sa's surface above must bound the hole there too: a pixel of it alone is an island inside
    // a hole of the row above that starts further left (a box's grazing top edge over the
    // shadow), which says nothing of what lies under it.
    if up.is_empty()
        || up[a] == NO_DEPTH
        || a == 0
        || up[a - 1] == NO_DEPTH
        || labels[h.start] != ATTACHED
    {
        return;
    }
    // Sa's surface measured over the hole's first column says the hole above was something
    // else on it (an occluder's top face seen at a grazing angle is a hole), unless nothing was
    // measured over the hole for [`UNMEASURED_ROWS`] rows: an opening in Sa's wall (a doorway,
    // a window onto a region beyond range), whose lintel the column memory holds, and whose
    // part a nearer object leaves may be as wide as that object's shadow (eq. 3).
    let lit_above = above
        .get(h.start)
        .is_some_and(|&q| q != NO_DEPTH && p.disp(q) > p.disp(raw[a]) - LIT_ABOVE);
    if lit_above && !unmeasured_over(rows.up, raw.len(), h) {
        return;
    }
    let same_sa = (p.disp(up[a]) - p.disp(raw[a])).abs() < p.min_step;
    // `prev_labels` is empty where the caller has no labels of the row above (`classify_row`).
    let above_other = prev_labels
        .get(h.start..h.end)
        .is_some_and(|l| l.iter().all(|&l| l == OTHER));
    if !(same_sa && above_other) {
        return;
    }
    let width = (h.end - h.start) as f32;
    let fits = (w - FITS_UNDER..=w + FITS_OVER).contains(&width);
    if !(fits && sb_all_the_way_up(p, rows.up, raw.len(), h, sb)) {
        set(labels, raw, h.start, h.end, OTHER);
    }
}

/// Whether the holes above `h` through its first column, row after row, end on Sb's surface
/// (raw `sb`) up to where that chain starts: at the hole region's top (a shadow's first row, the
/// lit background above it) or at a hole that runs on well past the one below it onto Sb (Sb's
/// own dropout joined to its shadow). A hole on the way that runs to the border or ends on another
/// surface is the unmeasured region; so is a chain longer than [`CHAIN_ROWS`], unread. `rows_up`:
/// every row above, whole rows of `width` values.
fn sb_all_the_way_up(p: &ScanParams, rows_up: &[u16], width: usize, h: Run, sb: u16) -> bool {
    let (mut end, mut on) = (h.end, sb);
    for row in rows_up.rchunks_exact(width).take(CHAIN_ROWS) {
        if row[h.start] != NO_DEPTH {
            return true;
        }
        let Some(e) = (h.start..width).find(|&u| row[u] != NO_DEPTH) else {
            return false;
        };
        // Sb's surface from row to row (a slanted occluder's moves a little).
        if (p.disp(row[e]) - p.disp(on)).abs() >= p.min_step {
            return false;
        }
        if e > end + WIDER_ABOVE {
            return true;
        }
        (end, on) = (e, row[e]);
    }
    false
}

/// Rows [`sb_all_the_way_up`] reads at most.
const CHAIN_ROWS: usize = 64;

/// Pixels by which a hole must run on past the one below it to be Sb's dropout joined to its
/// shadow: a slanted edge moves a pixel a row, a round occluder's silhouette near its top a few
/// (a sphere in this project's suite of seed 424242, whose region beyond range above it then
/// counted as shadow); a dropout patch on Sb's face runs on tens of pixels.
const WIDER_ABOVE: usize = 6;

/// Pixels by which a hole may fall short of eq. (3) and still be the shadow for
/// [`below_unmeasured`]: noise on Sa and Sb.
const FITS_UNDER: f32 = 3.0;
/// Pixels by which it may exceed eq. (3): the real sensor's widening, +2.3 px on average over a
/// pole's shadow in the NYU frame, up to 7 (SPEC §1).
const FITS_OVER: f32 = 6.0;

/// Disparity (pixels) by which the column memory over a hole may lie farther than Sa and still
/// be Sa's lit surface for [`below_unmeasured`] (a wall seen at a slant over the shadow's rows).
const LIT_ABOVE: f32 = 2.0;

/// The farthest of the last valid raw values above the hole's columns (column memory), if any.
fn farthest_above(above: &[u16], h: Run) -> Option<u16> {
    above[h.start..h.end]
        .iter()
        .copied()
        .filter(|&r| r != NO_DEPTH)
        .max()
}

/// The background below a hole with nothing measured above it (a gap between two objects from
/// the frame's top): the farthest of the first valid raw values below its columns (`below`:
/// whole rows), read in every fourth column and the last. Only where Sb's own column ends there
/// too: the shadow stops where its occluder does (a few rows later, the shadow of the
/// occluder's lower face), whereas a surface that appears while Sb goes on is no background the
/// hole hides (a box's top far below a region beyond range). Nor is a floor whose surface,
/// carried up to this row along its slope, passes the frame's range.
fn background_below(p: &ScanParams, below: &[u16], h: Run, sb: Bound, range: Range) -> Option<u16> {
    // Rows the shadow of the occluder's lower face may run on past its end.
    const FOOT_ROWS: usize = 16;
    let mut farthest: Option<(u16, usize)> = None;
    for col in (h.start..h.end)
        .step_by(4)
        .chain(std::iter::once(h.end - 1))
    {
        if let Some((k, r, slope)) = first_valid_below(below, col) {
            if along(r, slope, k + 1) > f32::from(range.far) + 0.5 {
                return None;
            }
            if farthest.is_none_or(|(f, _)| r > f) {
                farthest = Some((r, k));
            }
        }
    }
    let (bg, at) = farthest?;
    // Sb's first columns: the widening moves its edge from row to row, so Sb ends in the first
    // row where none of them shows it.
    let cols = h.end..(h.end + 4).min(WIDTH);
    let d_sb = p.disp(sb.near);
    let on_sb = |r: u16| r != NO_DEPTH && (p.disp(r) - d_sb).abs() < 2.0 * p.min_step;
    let sb_end = below
        .chunks_exact(WIDTH)
        .position(|row| !row[cols.clone()].iter().any(|&r| on_sb(r)))
        .unwrap_or(below.len() / WIDTH);
    (sb_end <= at && at <= sb_end + FOOT_ROWS).then_some(bg)
}

/// The background disparity the detached test uses for a hole between `sa` and `sb`.
fn sa_sb_bg(p: &ScanParams, sa: Bound, sb: Bound) -> f32 {
    p.disp(sa.far).min(p.disp(sb.far))
}

/// The hole `h` as a shadow run before the first lit island inside it (at most `max_island`
/// valid pixels at the background's depth), and the column where the rest starts.
fn split_at_island(
    p: &ScanParams,
    raw: &[u16],
    h: Run,
    sa: Bound,
    sb: Bound,
) -> Option<(Run, usize)> {
    // A shadow and an occluder of at least MIN_DEPTHLESS_WIDTH each, and the island (most holes
    // of a real frame are narrower and stop here).
    if h.end - h.start < 2 * MIN_DEPTHLESS_WIDTH + 1 {
        return None;
    }
    let d_bg = sa_sb_bg(p, sa, sb);
    let i0 = h.start + raw[h.start..h.end].iter().position(|&r| r != NO_DEPTH)?;
    let i1 = i0
        + raw[i0..h.end]
            .iter()
            .take_while(|&&r| r != NO_DEPTH)
            .count();
    let lit = raw[i0..i1].iter().all(|&r| p.on_background(r, d_bg));
    (lit && i1 - i0 <= p.max_island && i1 < h.end).then_some((
        Run {
            start: h.start,
            end: i0,
        },
        i1,
    ))
}

/// A hole too wide for Sb's shadow on Sa, or whose Sa is no farther than Sb: when Sa is an
/// object's right edge with a farther background behind it, the hole can be Sb's attached shadow
/// on that background, its left part hidden by Sa (eq. 3 with the background's disparity; the
/// visible part is at most as wide). The background is the farthest of the last valid pixels
/// above the hole's columns, and must lie behind Sa.
fn hidden_background(
    p: &ScanParams,
    raw: &[u16],
    h: Run,
    (sa, sb): (Bound, Bound),
    context: Context,
    labels: &mut [u8],
    filled: &mut [u16],
) {
    let Context {
        range,
        above,
        rows,
        walks,
        ..
    } = context;
    // Sa must be a surface of its own, off Sb's (a dropout inside one surface is not a shadow:
    // most holes of a real frame stop here), unless it stands apart at Sb's depth.
    let apart = || thin_sa_apart(p, raw, h, sa);
    if (p.disp(sa.near) - p.disp(sb.near)).abs() < p.min_step && !apart() {
        return;
    }
    // What the hole's own columns show above it: a surface there that is Sb itself (a hole
    // under an object's overhang) leaves no room for a shadow. The surface right of Sb is no
    // stand-in: it is as often a second object as the background. Sb above the hole's last few
    // columns only, with nothing or Sa above the rest, is Sb's edge that the widening moves
    // from row to row (a shadow running down from the frame's top), not an overhang.
    let from_above = farthest_above(above, h).filter(|&r| {
        let on = |a: u16, b: u16| (p.disp(a) - p.disp(b)).abs() < p.min_step;
        let edge_only = h.end - h.start > WIDENING as usize
            && on(r, sb.near)
            && above[h.start..h.end - WIDENING as usize]
                .iter()
                .all(|&a| a == NO_DEPTH || on(a, sa.edge));
        !edge_only
    });
    // Sb itself above: the overhang's hole, no shadow.
    if from_above.is_some_and(|r| (p.disp(r) - p.disp(sb.near)).abs() < p.min_step) {
        return;
    }
    // Sb's shadow on `bg` (eq. 3), if Sa lies before it (else nothing hides part of the shadow)
    // and it is no narrower than the hole.
    let width = (h.end - h.start) as f32;
    let fits = |bg: u16| {
        let w = p.disp(sb.near) - p.disp(bg);
        let hidden = p.disp(sa.near) - p.disp(bg) >= p.min_step;
        (hidden && w >= p.min_step && width <= w + p.over).then_some((bg, w))
    };
    // Where nothing was measured above: the row's own background left of a thin Sa, or (a gap
    // between two objects from the frame's top) the background below the gap, where it shows
    // past the shorter object's end. The latter also stands in for a value above a little
    // behind Sb, and behind Sa, that does not fit: a pixel of Sb's edge mixed with the
    // background, from a row where the hole was narrower (j24 s017, two cylinders). On Sa's
    // surface it is Sa going on above a dropout in it (a glossy box's face, j23 s000).
    let mixed = from_above.is_some_and(|r| {
        (0.0..MIXED_PX).contains(&(p.disp(sb.near) - p.disp(r)))
            && p.disp(sa.near) - p.disp(r) >= p.min_step
    });
    // A surface above nearer than Sb (a table's top over its legs) is no background of Sb's
    // shadow: read as if nothing were measured above. (Complex IR attached F1 +0.0006 summed on
    // this project's suites and on the sixth simulator's, any-shadow recall +0.0009 and
    // +0.0008, the holdout +0.0003; precision within −0.0001; the real frame unchanged.)
    let before_sb = from_above.is_some_and(|r| p.disp(r) > p.disp(sb.near) + p.min_step);
    let Some((bg, w)) = from_above
        .and_then(fits)
        .or_else(|| {
            (from_above.is_none() || before_sb)
                .then(|| beside_thin_sa(p, raw, h, sa, labels, range))
                .flatten()
                .and_then(fits)
        })
        .or_else(|| {
            // No background lies beyond the frame's farthest value: when even that one does not
            // fit, no column need be searched.
            (from_above.is_none() || mixed)
                .then_some(range.far)
                .and_then(fits)
                .and_then(|_| background_below(p, rows.down, h, sb, range))
                .and_then(fits)
        })
    else {
        return;
    };
    // Nor is a background that fits proof: the hole may be a dropout in one curved surface, or
    // run on past Sb's top or bottom (read last: they walk columns).
    if bridged(p, h, (sa, sb), above, rows, walks) || outruns_sb(p, h, sb, rows, walks) {
        return;
    }
    label_attached(p, raw, h, w, rows, labels);
    // Where Sa's and Sb's slopes carried over the hole each land on the other, Sa hides no
    // background: the hole lies on one slanted surface, and only a thin occluder right of it
    // (the detached verdict) explains it. The background above then came from far up the hole's
    // columns (a glossy rod before a turned box, its shadow on the wall above the box).
    // (Fourth simulator, 44 suites: complex IR attached F1 +0.045 summed, precision +0.062,
    // j44 +0.010; simple +0.025; this project's suites within ±0.0003, the real frame unchanged.)
    if labels[h.start] == ATTACHED && one_surface(p, raw, h, sa, sb, p.min_step) && !apart() {
        set(labels, raw, h.start, h.end, OTHER);
        return;
    }
    // The shadow lies on the background, not on Sa (`fill` keeps the first value).
    for (f, &r) in filled[h.start..h.end].iter_mut().zip(&raw[h.start..h.end]) {
        if r == NO_DEPTH {
            *f = bg;
        }
    }
}

/// True when the surface over the hole's columns bridges Sa and Sb: in [`BRIDGE_COLS`] columns
/// or more, the column memory shows a surface at the depth a line from Sa to Sb has there,
/// clear of both. The hole is then a dropout in one curved surface (a glossy cylinder's face,
/// whose slope no straight extrapolation carries over the hole), not Sb's shadow on a background
/// Sa hides: behind a shadow lies that background, and Sa's or Sb's own surface beside it.
fn bridged(
    p: &ScanParams,
    h: Run,
    (sa, sb): (Bound, Bound),
    above: &[u16],
    rows: Rows,
    walks: &Walks,
) -> bool {
    let (d_sa, d_sb) = (p.disp(sa.edge), p.disp(sb.edge));
    let span = (h.end + 1 - h.start) as f32;
    // Column `c` showing raw value `r`.
    let on_line = |c: usize, r: u16| {
        if r == NO_DEPTH {
            return false;
        }
        let d = p.disp(r);
        let line = d_sa + (d_sb - d_sa) * (c + 1 - h.start) as f32 / span;
        (d - line).abs() < p.min_step
            && (d - d_sa).abs() >= p.min_step
            && (d - d_sb).abs() >= p.min_step
    };
    // The middle half only: near its ends, Sa's and Sb's own surfaces curve away above the hole
    // (a thin rod, a cylinder's limb).
    let quarter = (h.end - h.start) / 4;
    let middle = h.start + quarter..h.end - quarter;
    let up = middle.clone().filter(|&c| on_line(c, above[c])).count();
    let v = rows.up.len() / WIDTH;
    up >= BRIDGE_COLS
        || up
            + middle
                .filter(|&c| {
                    walks
                        .first_below(v, rows.down, c)
                        .is_some_and(|r| on_line(c, r))
                })
                .count()
            >= BRIDGE_COLS
}

/// What the hidden background's walks along columns found, kept for the rows after: a shadow's
/// hole runs down many rows under the same Sb and asks the same columns in turn, so each walk
/// runs about once per frame (a tall box's shadow took a quarter more instructions on its frame
/// without).
struct Walks {
    /// Where [`outruns_sb`] last found Sb's ends, for the last few Sbs it was asked about (a row
    /// may hold more than one such hole).
    sb_ends: [Cell<Option<SbEnds>>; SB_ENDS],
    /// The slot of `sb_ends` the next new Sb takes.
    next_sb: Cell<usize>,
    /// Per column, the first valid pixel below the rows searched so far: its row in the high
    /// half (the frame's height if none; 0 where never searched), its raw value in the low.
    below: [Cell<u32>; WIDTH],
}

impl Walks {
    fn new() -> Self {
        Walks {
            sb_ends: [const { Cell::new(None) }; SB_ENDS],
            next_sb: Cell::new(0),
            below: [const { Cell::new(0) }; WIDTH],
        }
    }

    /// The first valid raw value in column `c` below row `v` (`below`: the rows under it).
    fn first_below(&self, v: usize, below: &[u16], c: usize) -> Option<u16> {
        let known = self.below[c].get();
        // Still below this row: every row between was a hole in this column.
        let r = if (known >> 16) as usize > v {
            (known & 0xffff) as u16
        } else {
            let column = below.iter().skip(c).step_by(WIDTH);
            let (k, r) = column
                .enumerate()
                .find(|&(_, &r)| r != NO_DEPTH)
                .map_or((below.len() / WIDTH, NO_DEPTH), |(k, &r)| (k, r));
            self.below[c].set(((v + 1 + k) as u32) << 16 | u32::from(r));
            r
        };
        (r != NO_DEPTH).then_some(r)
    }
}

/// True when the hole runs on past Sb's top or bottom: in the first row up (or down) its columns
/// where Sb's first columns no longer show it, the middle half of the hole's columns is a hole
/// too, ending where Sb's edge was, and so for [`RUN_ON`] rows up ([`RUN_ON_DOWN`] down). A
/// shadow spans its occluder's rows only (the projector is beside the camera, not above it), so
/// there the hole is something else that Sb happens to bound in this row (a box's side face
/// seen at a grazing angle, with a farther box right of it below and the wall above; a region
/// beyond range between two rods that stand before a box below it), and Sb's shadow would only
/// be a coincidence. `walks` holds what the row above found under the same Sb.
fn outruns_sb(p: &ScanParams, h: Run, sb: Bound, rows: Rows, walks: &Walks) -> bool {
    let (v, d_sb) = (rows.up.len() / WIDTH, p.disp(sb.near));
    let same_sb = |m: &SbEnds| {
        m.row + 1 == v
            && m.edge.abs_diff(h.end) <= EDGE_JITTER
            && (m.disp - d_sb).abs() < 2.0 * p.min_step
    };
    let slot = walks
        .sb_ends
        .iter()
        .find(|c| c.get().is_some_and(|m| same_sb(&m)));
    let (slot, known) = match slot {
        Some(slot) => (slot, slot.get()),
        None => {
            let k = walks.next_sb.get();
            walks.next_sb.set((k + 1) % SB_ENDS);
            (&walks.sb_ends[k], None)
        }
    };
    let up = rows.up.chunks_exact(WIDTH).enumerate().rev();
    let top = known.map_or_else(|| end_of_sb(p, h.end, d_sb, up), |m| m.top);
    let mut ends = SbEnds {
        row: v,
        edge: h.end,
        disp: d_sb,
        top,
        // (Found from the row above, Sb's bottom lies below this row too, unless Sb moved off
        // the window in this very row: then it is read again.)
        bottom: known
            .and_then(|m| m.bottom)
            .filter(|b| b.is_none_or(|(b, _)| b > v)),
    };
    // The hole's columns, moved with Sb's edge to where Sb ends.
    let width = h.end - h.start;
    let same_hole = |edge: usize| {
        let start = edge.checked_sub(width)?;
        let quarter = width / 4;
        let middle = start + quarter..edge - quarter;
        let near_edge = edge - EDGE_JITTER.min(quarter)..(edge + EDGE_JITTER).min(WIDTH);
        // Ending where Sb's edge was: a wider hole there is another region the sensor cannot
        // measure, which Sb's end happens to bound.
        Some(move |row: &[u16]| {
            row[middle.clone()].iter().all(|&r| r == NO_DEPTH)
                && row[near_edge.clone()].iter().any(|&r| r != NO_DEPTH)
        })
    };
    // For rows on end: an occluder's top face seen at a grazing angle is a hole of a few rows
    // across its shadow's columns; below an occluder, its lower face's shadow runs on further.
    let above = top.is_some_and(|(t, edge)| {
        t + 1 >= RUN_ON
            && same_hole(edge).is_some_and(|same| {
                (0..RUN_ON).all(|k| same(&rows.up[(t - k) * WIDTH..(t - k + 1) * WIDTH]))
            })
    });
    let outruns = above || {
        let bottom = *ends.bottom.get_or_insert_with(|| {
            let down = rows.down.chunks_exact(WIDTH).enumerate();
            end_of_sb(p, h.end, d_sb, down).map(|(k, edge)| (v + 1 + k, edge))
        });
        bottom.is_some_and(|(b, edge)| {
            let k = b - (v + 1);
            (k + RUN_ON_DOWN) * WIDTH <= rows.down.len()
                && same_hole(edge).is_some_and(|same| {
                    (k..k + RUN_ON_DOWN).all(|k| same(&rows.down[k * WIDTH..(k + 1) * WIDTH]))
                })
        })
    };
    slot.set(Some(ends));
    outruns
}

/// Where Sb ends along `rows` (numbered rows of the frame, from the current row outwards): the
/// first whose columns around Sb's edge no longer show Sb, and Sb's edge in the row before it;
/// `None` when Sb reaches the frame's border. Sb is followed row by row, its edge moving from
/// row to row (the sensor's widening, a slanted occluder), its depth drifting (one slanting
/// away).
fn end_of_sb<'a>(
    p: &ScanParams,
    end: usize,
    d_sb: f32,
    rows: impl Iterator<Item = (usize, &'a [u16])>,
) -> Option<(usize, usize)> {
    let (mut edge, mut last) = (end, d_sb);
    for (t, row) in rows {
        let window = edge.saturating_sub(EDGE_JITTER)..(edge + EDGE_JITTER + 1).min(WIDTH);
        let on_sb = window
            .clone()
            .find(|&u| row[u] != NO_DEPTH && (p.disp(row[u]) - last).abs() < 2.0 * p.min_step);
        match on_sb {
            Some(u) => (edge, last) = (u, p.disp(row[u])),
            None => return Some((t, edge)),
        }
    }
    None
}

/// Sbs whose ends [`Walks`] keeps.
const SB_ENDS: usize = 4;

/// What [`outruns_sb`] found for the hole under an Sb in one row.
#[derive(Clone, Copy, Debug)]
struct SbEnds {
    /// The row.
    row: usize,
    /// Sb's edge there (the hole's end).
    edge: usize,
    /// Sb's disparity there.
    disp: f32,
    /// [`end_of_sb`] upwards: the row above Sb's top and Sb's edge below it.
    top: Option<(usize, usize)>,
    /// The same downwards, once read (the outer `None`: not read yet).
    bottom: Option<Option<(usize, usize)>>,
}

/// Columns by which [`outruns_sb`] lets Sb's edge move from one row to the next.
const EDGE_JITTER: usize = 4;
/// Rows above Sb's top through which the hole must run on for [`outruns_sb`].
const RUN_ON: usize = 8;
/// Rows below Sb's bottom through which the hole must run on for [`outruns_sb`]: more, for an
/// occluder's lower face casts its shadow on a few rows past its end (16 at most, as
/// [`background_below`] reads them).
const RUN_ON_DOWN: usize = 24;

/// Columns of a surface between Sa and Sb that make [`bridged`] hold.
const BRIDGE_COLS: usize = 3;

/// The background an attached shadow lies on when it cannot lie on Sa: wider than Sb's shadow
/// on Sa by more than the widening, with Sa a thin object standing clear of its surroundings
/// (a hole or a farther surface left of it within [`THIN_SA`] pixels). The background is the
/// farthest of the last valid pixels above the hole's columns, if Sb's shadow on it fits the
/// hole (eq. 3). The warp then sees the depth edge at Sa and opens its alignment shadow.
#[allow(clippy::too_many_arguments)]
fn behind_thin_sa(
    p: &ScanParams,
    raw: &[u16],
    h: Run,
    sa: Bound,
    sb: Bound,
    w: f32,
    above: &[u16],
) -> Option<u16> {
    let width = (h.end - h.start) as f32;
    if width <= w + WIDENING + 1.0 {
        return None;
    }
    let d_sa = p.disp(sa.edge);
    let run = sa_run(p, raw, h, sa);
    let left = h.start.checked_sub(run + 1).map(|i| raw[i])?;
    let clear = left == NO_DEPTH || d_sa - p.disp(left) >= p.min_step;
    if run > THIN_SA || !clear {
        return None;
    }
    let bg = farthest_above(above, h)?;
    let on_bg = p.disp(sb.near) - p.disp(bg);
    (p.disp(sa.near) - p.disp(bg) >= p.min_step && width <= on_bg + p.over).then_some(bg)
}

/// The background behind a thin Sa, from the row itself: where nothing above the hole was ever
/// measured (a shadow running down from the frame's top), the surface left of Sa is what
/// continues behind it, if it lies farther than Sa, and if the holes between them are shadows on
/// it (Sa's own detached shadow, say): a hole left OTHER there may be a region beyond range,
/// which the thin object stands before with nothing behind it to take a shadow.
fn beside_thin_sa(
    p: &ScanParams,
    raw: &[u16],
    h: Run,
    sa: Bound,
    labels: &[u8],
    range: Range,
) -> Option<u16> {
    // Holes crossed on the way (a thin object's own shadow is at most this wide).
    const MAX_HOLES: usize = 64;
    let d_sa = p.disp(sa.edge);
    let run = sa_run(p, raw, h, sa);
    if run > THIN_SA {
        return None;
    }
    let left = &raw[..h.start - run];
    let holes = left
        .iter()
        .rev()
        .take(MAX_HOLES + 1)
        .take_while(|&&r| r == NO_DEPTH)
        .count();
    if holes > MAX_HOLES || holes == left.len() {
        return None;
    }
    let crossed = &labels[left.len() - holes..left.len()];
    if !crossed.iter().all(|&l| l == ATTACHED || l == DETACHED) {
        return None;
    }
    let end = left.len() - holes;
    let bg = left[end - 1];
    // A surface receding towards the hole (a side wall) that leaves the frame's range before
    // the hole's end goes on behind it no further than that: beyond it the shadow falls on
    // nothing the sensor measures (j32 s007, a side wall meeting a back wall beyond range).
    let disp = |r: u16| p.disp(r);
    // Its last BESIDE_RUN measured pixels, across the holes of a shadow on it.
    let from = (0..end)
        .rev()
        .take(BESIDE_RUN + MAX_HOLES)
        .filter(|&u| raw[u] != NO_DEPTH)
        .take(BESIDE_RUN)
        .last()
        .unwrap_or(end);
    let leaves_range = Line::through(raw, (from, end), disp)
        .filter(|line| line.slope < 0.0 && line.fits(raw, (from, end), disp, p.min_step))
        .is_some_and(|line| line.disp_at(h.end) < p.disp(range.far) - p.min_step);
    (d_sa - p.disp(bg) >= p.min_step && !leaves_range).then_some(bg)
}

/// True when Sa is an object of its own narrower than its shift, with the lit background
/// directly left of it: an object's left edge has its attached shadow directly left (the
/// projector lies to the right), so a strip of Sb's own surface left of a dropout would have a
/// hole there. Such an Sa is apart from Sb even at Sb's depth (a rod beside a box, standing in
/// the box's shadow, its own shadow detached further left).
///
/// The background must go on left of its first pixel (past the holes of Sa's shadow on it): a
/// lone outlier of a noisy surface is no background.
fn thin_sa_apart(p: &ScanParams, raw: &[u16], h: Run, sa: Bound) -> bool {
    // Most holes asked are dropouts inside one surface, whose run is long: counted only as far
    // as a thin object may reach, in raw units (disparity is linear in them).
    let (sa_raw, step) = (f32::from(sa.edge), p.min_step / p.k);
    let run = raw[..h.start]
        .iter()
        .rev()
        .take(THIN_APART + 1)
        .take_while(|&&r| r != NO_DEPTH && (f32::from(r) - sa_raw).abs() < step)
        .count();
    if run > THIN_APART {
        return false;
    }
    let Some(at) = h.start.checked_sub(run + 1) else {
        return false;
    };
    let left = raw[at];
    let shift = p.disp(sa.edge) - p.disp(left);
    let goes_on = || {
        raw[..at]
            .iter()
            .rev()
            .find(|&&r| r != NO_DEPTH)
            .is_some_and(|&r| (p.disp(r) - p.disp(left)).abs() < p.min_step)
    };
    left != NO_DEPTH && shift >= p.min_step && (run as f32) < shift && goes_on()
}

/// Widest Sa (pixels) [`thin_sa_apart`] takes for an object apart from Sb: a rod 2 cm thick at
/// 0.7 m, whose shift against a wall 3 m away would be 48 px.
const THIN_APART: usize = 16;

/// Measured pixels of the surface left of a thin Sa through which [`beside_thin_sa`] draws its
/// slope.
const BESIDE_RUN: usize = 24;

/// How many valid pixels on Sa's surface lie left of the hole, counted up to one past
/// [`THIN_SA`] (more means Sa is no thin object).
fn sa_run(p: &ScanParams, raw: &[u16], h: Run, sa: Bound) -> usize {
    let d_sa = p.disp(sa.edge);
    raw[..h.start]
        .iter()
        .rev()
        .take(THIN_SA + 1)
        .take_while(|&&r| r != NO_DEPTH && (p.disp(r) - d_sa).abs() < p.min_step)
        .count()
}

/// Widest object (pixels) [`behind_thin_sa`] takes for a thin one: a rod of 4 cm at 0.65 m.
const THIN_SA: usize = 36;

/// Disparity (pixels) within which a value behind Sb in the column memory above a hole may be a
/// pixel mixing Sb's edge with what lies behind it, from a row where the hole was narrower.
const MIXED_PX: f32 = 3.0;

/// How far the sensor's correlation window moves each end of a shadow beyond its geometric place
/// (pixels; real frames: about 2.3 px in all, SPEC §1).
const WIDENING: f32 = 3.0;

/// Widest measured part (pixels) of an occluder without depth that [`hole_pair`] takes for its
/// limb: a glossy rod's edge returns depth over a pixel or few. (Without the limit a thin
/// measured rod paired the holes either side of it, this project's holdout 005: complex IR
/// detached F1 −0.001.)
const OWN_LIMB: usize = 4;

/// Narrowest hole (pixels) taken for an occluder without depth: narrower ones are dropouts.
const MIN_DEPTHLESS_WIDTH: usize = 3;
/// Rows above and below a depthless occluder's shadow, partly hidden by a nearer surface, that
/// must show the same pair.
const HIDDEN_PAIR_ROWS: usize = 4;

/// Widest dropout (pixels) the detached test's search steps over in the lit gap between a shadow
/// and its occluder, when it is no depthless occluder's hole. A wider hole that ends on a nearer
/// surface is stepped over too: an independent simulator's leaning rods, one hiding the other
/// from the camera (complex IR detached F1 +0.068 on one suite of eight, ±0.002 on the others;
/// without the nearer surface, −0.026 on another: a far occluder fitted by chance).
const MAX_GAP_DROPOUT: usize = 16;
/// How many such dropouts it steps over (a real frame's noisy walls have many).
const MAX_GAP_STEPS: usize = 2;
/// Narrowest shadow hole for which it does (most holes of a real frame are speckle, and the
/// longer search costs time).
const MIN_STEP_OVER: usize = 6;
/// Nearer objects the search goes past when eqs. (4)–(5) do not fit them (for shadow holes of
/// at least MIN_STEP_OVER pixels: on the NYU frame, passing objects for every speckle hole cost
/// 15 % of the scanline's time). One gained 0.001 to 0.003 of detached F1 on complex scenes (ten
/// suites), with no precision lost; two, nothing more.
const MAX_PASSED_OBJECTS: usize = 1;

/// Pixels past where eq. (5) puts a shadow's right end (ideally one left of it) that still
/// count as its own, for [`Detached::Head`]: that pixel and the sensor's widening of the end.
/// An independent simulator's rods whose shadows merge with black rods: complex detached F1
/// +0.018, +0.019, +0.020 on the suite with most of them at 1, 2, 3 px (taken); others alike.
const HEAD_SLACK: f32 = 3.0;

/// Occluders whose shadows one merged hole may hold (rods side by side, a post and its bracket).
const MAX_CHAINED: usize = 4;

/// Outcome of [`detached`].
#[derive(Clone, Copy)]
enum Detached {
    /// Not a detached shadow.
    No,
    /// Cast by a measured occluder [Fa, Fb] (eqs. 4–5).
    Measured,
    /// Cast by a measured occluder onto the nearer surface at Sa (raw value `raw`), which runs
    /// on through the hole to its right end: eq. (5) on that surface puts the shadow's end at
    /// or past the hole's.
    OnSa { raw: u16 },
    /// Cast by an occluder with no depth of its own (black or glossy), seen as the hole
    /// `occluder` whose depth the shift implies (`raw`).
    Depthless { occluder: Run, raw: u16 },
    /// At the left border, or behind a nearer surface at Sa ([`TAIL_HIDER`]): a measured
    /// occluder's shadow (eq. 5 at the hole's right end) fills the hole from column `from` on;
    /// the rest, left of it, is something else (a region beyond range, the sensor's dead band,
    /// the nearer object's dropout) that the shadow merged with.
    Tail { from: usize },
    /// A measured occluder's shadow fits the hole's left end (eq. 4) and ends, by eq. (5),
    /// before column `to` short of the hole's end: the rest is something else the shadow merged
    /// with (an object that returns no depth). Found when no further occluder's shadow goes on
    /// from there.
    Head { to: usize },
}

impl Detached {
    /// Cast by a measured occluder, on whichever surface.
    fn measured(self) -> bool {
        matches!(self, Detached::Measured | Detached::OnSa { .. })
    }
}

/// How many valid pixels just left of column `at` (up to `limit`) are nearer than disparity `d`
/// by more than a step: the width of a nearer object standing there.
fn nearer_before(p: &ScanParams, raw: &[u16], at: usize, d: f32, limit: usize) -> usize {
    raw[..at]
        .iter()
        .rev()
        .take(limit)
        .take_while(|&&r| r != NO_DEPTH && p.disp(r) > d + p.min_step)
        .count()
}

/// True when Sb continues the surface of Sa across the hole (a hole on a slanted surface rising
/// towards the camera, not a depth edge): Sa's slope extrapolated over the hole lands within
/// `tol` pixels of disparity of Sb.
fn same_surface(p: &ScanParams, raw: &[u16], h: Run, sa: Bound, sb: Bound, tol: f32) -> bool {
    let predicted =
        p.disp(sa.edge) + outward_slope(p, raw, h.start - 1, -1) * (h.end + 1 - h.start) as f32;
    (p.disp(sb.edge) - predicted).abs() < tol
}

/// [`same_surface`] read from both ends: Sb's slope extrapolated back over the hole lands on Sa
/// too. Two curved edges (a rod's and a cylinder's, receding from each other) can meet one
/// extrapolation by chance, not both.
fn one_surface(p: &ScanParams, raw: &[u16], h: Run, sa: Bound, sb: Bound, tol: f32) -> bool {
    let predicted =
        p.disp(sb.edge) + outward_slope(p, raw, h.end, 1) * (h.end + 1 - h.start) as f32;
    same_surface(p, raw, h, sa, sb, tol) && (p.disp(sa.edge) - predicted).abs() < tol
}

/// The disparity change per pixel towards the pixel `at` at a hole's edge, read over the pixels
/// beyond it (`dir` −1: left of it, 1: right); 0 where they are not all measured.
fn outward_slope(p: &ScanParams, raw: &[u16], at: usize, dir: isize) -> f32 {
    const SPAN: usize = 4;
    let far = at as isize + dir * (SPAN as isize + 1);
    if far < 0 || far as usize >= raw.len() {
        return 0.0;
    }
    let span = if dir < 0 {
        far as usize..=at
    } else {
        at..=far as usize
    };
    if raw[span].contains(&NO_DEPTH) {
        return 0.0;
    }
    let px = |k: usize| p.disp(raw[(at as isize + dir * k as isize) as usize]);
    // Pairs of pixels at both ends of the span: half the noise of single ones.
    let near_end = px(0) + px(1);
    let far_end = px(SPAN) + px(SPAN + 1);
    ((near_end - far_end) / (2 * SPAN) as f32).clamp(-0.5, 0.5)
}

/// Labels an attached shadow of predicted width `w` ending at the occluder (`h.end`). A hole much
/// wider than eq. (3) allows is not one shadow: most often the shadow falls on a surface that is a
/// hole anyway (beyond range, black, glossy), which is OTHER by definition (SPEC §1).
fn label_attached(p: &ScanParams, raw: &[u16], h: Run, w: f32, rows: Rows, labels: &mut [u8]) {
    let width = (h.end - h.start) as f32;
    if width <= w + p.over {
        let gap = lit_gap(p, raw, h, w);
        let code = if gap.is_some() || thin_occluder(p, raw, h.end, w, rows) {
            // A detached shadow touches its thin occluder only when the widening swallowed the
            // lit gap: the hole then spans shadow and gap, the whole shift. A much narrower
            // hole beside a thin occluder lies where the projector lit the background (that
            // rod's shadow is farther left): something else, a black rod say, OTHER; unless
            // the gap shows on the background itself (the occluder's own right part hidden
            // in a dropout: the hole is its shadow, as wide as it).
            if width + SWALLOWED_GAP_SLACK < w {
                if gap == Some(true)
                    || cut_by_thin_occluder(p, raw, h)
                    || behind_thin_sb(p, raw, h, rows)
                {
                    set(labels, raw, h.start, h.end, DETACHED);
                }
                return;
            }
            // Nor a hole much wider than the occluder: its lit gap would show (see
            // [`UNSWALLOWED_GAP`]). The shadow is the hole's left part; the rest is something
            // else, a depthless object the colour split may pair with its own shadow.
            // (A lit gap that shows is no swallowed one.)
            let shadow_end = match gap {
                None => unswallowed_gap(p, raw, h, w),
                Some(_) => None,
            };
            if let Some(to) = shadow_end {
                set(labels, raw, h.start, to, DETACHED);
                return;
            }
            DETACHED
        } else {
            ATTACHED
        };
        set(labels, raw, h.start, h.end, code);
    }
}

/// Where, inside the hole `h` that eq. (3) fits, the shadow of a nearer surface X right of Sb
/// begins: Sb is a strip of some surface, then comes the hole X's attached shadow makes on that
/// strip, then X. X's shadow on Sa's surface starts `disp(X) − disp(Sa)` pixels left of X's edge
/// (eq. 3 again); where that lies inside the hole, the projector's ray meets X before Sb, so
/// that part is X's detached shadow (`umbra synth` labels a pixel by the first object on the
/// projector's ray), the rest Sb's attached one. Without this, a thin rod's attached shadow
/// swallows the detached shadow of the box behind it.
fn nearer_shadow_past_sb(p: &ScanParams, raw: &[u16], h: Run, sa: Bound) -> Option<usize> {
    // X's shadow reaches into the hole only from within the widest shift of its start.
    let widest = (p.max_disp - p.disp(sa.far)).max(0.0) as usize;
    let reach = raw.len().min(h.start + widest + 1);
    // The strip: Sb's surface up to the next hole, pixel to pixel without a depth edge. Without
    // a hole after it, a nearer X right of the strip is more often the same object turning
    // towards the camera (a slanted face's steps) than an occluder standing in front.
    let gap = hole_after(raw, h.end, reach.checked_sub(h.end)?)?;
    if raw[h.end..gap]
        .windows(2)
        .any(|w| w[0].abs_diff(w[1]) > p.edge_raw)
    {
        return None;
    }
    let strip = raw[gap - 1];
    // The hole X shades on the strip, then X.
    let q = gap
        + raw[gap..reach]
            .iter()
            .take_while(|&&r| r == NO_DEPTH)
            .count();
    if q >= reach {
        return None;
    }
    // X stands before the strip, and the hole between is no wider than X's attached shadow
    // on it (eq. 3).
    let x = raw[q];
    let on_strip = p.disp(x) - p.disp(strip);
    if on_strip < p.min_step || (q - gap) as f32 > on_strip + p.over {
        return None;
    }
    // Eq. (3) for X over Sa: where X's shadow on Sa's surface begins.
    let from = q as f32 - (p.disp(x) - p.disp(sa.far));
    if from <= h.start as f32 || from >= h.end as f32 {
        return None;
    }
    Some(from.round() as usize)
}

/// True when the hole `h`, left of a thin occluder (Sb), is the detached shadow of an object
/// right of that occluder whose left part it hides from the camera (a rod behind a rod): the
/// shadow's right end lies behind the occluder too, so eq. (5) holds against the background
/// (Sa's), not against Sb; eq. (4) may reach behind the occluder by its width.
fn behind_thin_sb(p: &ScanParams, raw: &[u16], h: Run, rows: Rows) -> bool {
    if h.start == 0 {
        return false;
    }
    let sa = bound_left(raw, h.start);
    let bg = Bound {
        edge: sa.far,
        far: sa.far,
        near: sa.far,
    };
    search_occluder(p, raw, h, Some(sa), bg, rows, Search::BehindThinSb).measured()
}

/// Eqs. (4)–(5) read off the row: the lit gap between a detached shadow `h` and its occluder,
/// where the sensor's widening left a pixel or two of it. The pixel right of the hole lies no
/// nearer than Sa (by under `min_step`) and the occluder, nearer than it by over half the shift
/// `w`, starts within two more pixels. `Some(true)` when that pixel lies on Sa's surface (within
/// a quarter of the shift), `Some(false)` on a farther one seen past Sa's edge.
/// (The fourth simulator: rods in front of other rods, a glossy rod's measured sliver; complex
/// IR attached F1 +0.027 and detached +0.055 summed over its 40 suites, simple +0.016 and
/// +0.015; any-shadow precision within ±0.0002; this project's suites up to +0.002; the real
/// frame unchanged.)
fn lit_gap(p: &ScanParams, raw: &[u16], h: Run, w: f32) -> Option<bool> {
    if h.start == 0 {
        return None;
    }
    let d_gap = p.disp(*raw.get(h.end).filter(|&&r| r != NO_DEPTH)?);
    let d_sa = p.disp(raw[h.start - 1]);
    let occluder = (1..=2).any(|k| {
        raw.get(h.end + k)
            .is_some_and(|&r| r != NO_DEPTH && p.disp(r) - d_gap > 0.5 * w)
    });
    (d_gap <= d_sa + p.min_step && occluder).then_some(d_gap >= d_sa - 0.25 * w)
}

/// True when the hole `h`, left of a thin occluder, is the left part of a farther object's
/// attached shadow on the background that the occluder, standing in it, cuts off: that object
/// (Z) lies right of the hole after the occluder, and its shadow on the background (eq. 3
/// against Sa) reaches back over the occluder to `h`. Cut off from Z, the part is detached.
fn cut_by_thin_occluder(p: &ScanParams, raw: &[u16], h: Run) -> bool {
    let n = raw.len();
    let end = h.end + raw[h.end..].iter().take_while(|&&r| r != NO_DEPTH).count();
    let next = end + raw[end..].iter().take_while(|&&r| r == NO_DEPTH).count();
    if h.start == 0 || end == h.end || end == next || next >= n {
        return false;
    }
    let background = bound_left(raw, h.start).far;
    let z = bound_right(raw, next).near;
    let w_z = p.disp(z) - p.disp(background);
    w_z >= p.min_step
        && (next - end) as f32 <= w_z + p.over
        && h.start as f32 + w_z + WIDENING + 1.0 >= next as f32
}

/// True when the occluder starting at `sb` is narrower than its shadow's shift `w`, with the
/// background it stands before visible right of it: then the projector saw the background
/// between shadow and occluder (eqs. 4–5), so the shadow is detached, and the hole touches the
/// occluder only because the sensor's widening swallowed that lit gap. The widening also eats
/// 0–3 px of the occluder's left edge, a different amount in each row, so the occluder's width
/// is the widest run of this row and the rows just above and below (`rows`; where another hole
/// hides the occluder's end, the nearest rows where it shows).
fn thin_occluder(p: &ScanParams, raw: &[u16], sb: usize, w: f32, rows: Rows) -> bool {
    // Narrower by at least this much (pixels), against depth noise in `w`.
    const MARGIN: f32 = 0.5;
    // Narrower by this much, no lit gap needs to show: the widening eats up to 3 px of the
    // occluder's edge, and `w` (from the nearest occluder and the farthest Sa pixels) runs a
    // pixel over where the surface behind the occluder is nearer than Sa (a turned box's corner).
    const TIE: f32 = 4.0;
    let d_occ = p.disp(raw[sb]);
    let Some(end) = occluder_end(p, raw, sb, d_occ, w) else {
        return false; // at least as wide as the shift: attached
    };
    if (end - sb) as f32 + MARGIN >= w {
        return false;
    }
    // The occluder in `row`, starting within a few pixels of `sb`: its run, if it has one.
    let occluder_in = |row: &[u16]| -> Option<(usize, Option<usize>)> {
        let lo = sb.saturating_sub(3).min(row.len());
        let hi = (sb + 4).min(row.len());
        let k = row[lo..hi]
            .iter()
            .position(|&r| r != NO_DEPTH && p.disp(r) >= d_occ - w / 2.0)?;
        Some((lo + k, occluder_end(p, row, lo + k, d_occ, w)))
    };
    // Its end must show the background behind it (the same the shadow falls on).
    let background_after = |row: &[u16], end: usize| {
        row[end] != NO_DEPTH && d_occ - p.disp(row[end]) > w - 2.0 * p.min_step
    };
    // Or a hole that a surface right of it, nearer than the background, explains as its
    // attached shadow on the background (eq. 3, within its tolerance), but not as its shadow on
    // the occluder (wider than that by more than the widening, or the surface is farther than
    // the occluder): had the occluder gone on behind the hole, it would show there. A surface
    // at the occluder's own depth is that occluder going on past a hole in it (a dropout,
    // another rod's shadow on it), not a second object at the very same depth. Nor is a
    // curved or slanted one (a sphere) whose slope, carried over the hole, lands there.
    let shadowed_after = |row: &[u16], end: usize| {
        let next = end + row[end..].iter().take_while(|&&r| r == NO_DEPTH).count();
        row[end] == NO_DEPTH && next < row.len() && {
            // Both ends read conservatively: slanted surfaces, mixed edge pixels.
            let occluder_end = d_occ.min(p.disp(row[end - 1]));
            let on_occluder = p.disp(bound_right(row, next).near) - occluder_end;
            let width = (next - end) as f32;
            on_occluder.abs() >= p.min_step
                && on_occluder + w >= p.min_step
                && width > on_occluder + WIDENING + 1.0
                && width <= on_occluder + w + p.over
                && !occluder_goes_on(p, &row[sb..=next], end - sb)
        }
    };
    // Or a step back to a surface between it and the background (a box it stands before): it
    // ends there too, and narrower than its shift by more than the tie it is thin whatever
    // hides the lit gap (that box's own shadow, say).
    let ends_clearly_thin = raw[end] != NO_DEPTH && (end - sb) as f32 + TIE < w;
    if !background_after(raw, end) && !shadowed_after(raw, end) && !ends_clearly_thin {
        // Another hole (a black object behind it, say) hides where the occluder ends here: its
        // width is read in the nearest rows above or below where the background shows, and
        // within TIE of the shift it takes a lit gap near this row, as below.
        let mut gap_near = None;
        return occluder_width_nearby(raw.len(), rows, |row| {
            let (start, end) = occluder_in(row)?;
            Some(match end {
                None => Some(false), // wider than the shift there
                Some(end) if background_after(row, end) => {
                    let width = (end - start) as f32;
                    Some(
                        width + MARGIN < w
                            && (width + TIE < w
                                || *gap_near.get_or_insert_with(|| {
                                    rows.within(raw.len(), GAP_ROWS)
                                        .any(|row| lit_gap_before(p, row, sb, d_occ, w))
                                })),
                    )
                }
                Some(_) => None,
            })
        });
    }
    // In a neighbouring row the occluder starts within a few pixels of `sb`.
    let narrower = rows
        .near(raw.len())
        .iter()
        .all(|row| match occluder_in(row) {
            None => true, // no occluder there: this row has no say
            Some((start, end)) => end.is_some_and(|end| ((end - start) as f32) + MARGIN < w),
        });
    // Within TIE of the shift the widths cannot tell (the widening eats 0–3 px of the
    // occluder's edge, a different amount in each row): the lit gap itself must show in a row
    // nearby where the widening left it, unless no row nearby shows the occluder at all.
    if !narrower || (end - sb) as f32 + TIE < w {
        return narrower;
    }
    let mut occluder_seen = false;
    for row in rows.within(raw.len(), GAP_ROWS) {
        if lit_gap_before(p, row, sb, d_occ, w) {
            return true;
        }
        occluder_seen |= occluder_in(row).is_some();
    }
    !occluder_seen
}

/// True when the surface right of a hole in an occluder is the occluder itself going on: `seg`
/// holds the occluder's run up to `hole_at`, the hole, and the first valid pixel after it. That
/// pixel must lie between the occluder's last depth and where the slope of the occluder's last
/// pixels carries it (a sphere's limb flattens towards its middle), within a step either way.
fn occluder_goes_on(p: &ScanParams, seg: &[u16], hole_at: usize) -> bool {
    // Pixels fitted for the slope, the mixed pixel at the hole's edge left out.
    const FIT: usize = 8;
    if hole_at < 4 {
        return false;
    }
    let first = hole_at.saturating_sub(FIT + 1);
    let fit = &seg[first..hole_at - 1];
    if fit.contains(&NO_DEPTH) {
        return false;
    }
    // Least squares over the fit, about its middle.
    let mid = (fit.len() - 1) as f32 / 2.0;
    let mean = fit.iter().map(|&r| p.disp(r)).sum::<f32>() / fit.len() as f32;
    let (mut sxy, mut sxx) = (0.0, 0.0);
    for (i, &r) in fit.iter().enumerate() {
        let x = i as f32 - mid;
        sxy += x * (p.disp(r) - mean);
        sxx += x * x;
    }
    let slope = sxy / sxx;
    // The fitted line at the hole's edge pixel, and carried on to the first pixel after it.
    let at_edge = mean + slope * ((hole_at - 1 - first) as f32 - mid);
    let last = seg.len() - 1;
    let carried = at_edge + slope * (last - (hole_at - 1)) as f32;
    let beyond = p.disp(seg[last]);
    beyond >= at_edge.min(carried) - p.min_step && beyond <= at_edge.max(carried) + p.min_step
}

/// Rows searched either side for a lit gap between a shadow and its occluder.
const GAP_ROWS: usize = 5;

/// How much narrower than the shift (pixels) a hole touching a thin occluder may be and still be
/// its shadow with the lit gap swallowed: the widening and pixel sampling of either end.
pub(super) const SWALLOWED_GAP_SLACK: f32 = WIDENING + 1.0;

/// Widest lit gap (pixels: the shift less the occluder's width) that the widening can swallow:
/// its own at the shadow's right end and the occluder's left edge it eats, each up to
/// [`WIDENING`], and a pixel of sampling at either end.
const UNSWALLOWED_GAP: f32 = 2.0 * WIDENING + 2.0;

/// Where the detached shadow in the hole `h` ends, when its thin occluder (Sb, shift `w`) is so
/// much narrower than the hole that the lit gap between them could not have been swallowed:
/// then something without depth (a black rod, which Sb stands behind) fills the hole's right
/// part. The occluder must be one surface, narrower than half its shift (a sphere's cap reads
/// narrow in its top rows while its limb casts the shadow), and end on the background, so its
/// whole width shows. (A fresh suite, seed 14142: a black rod closed by a thin rod behind it,
/// its own shadow OTHER for want of its hole; complex detached F1 +0.013 IR, +0.015 RGB.)
fn unswallowed_gap(p: &ScanParams, raw: &[u16], h: Run, w: f32) -> Option<usize> {
    let d_occ = p.disp(raw[h.end]);
    let end = occluder_end(p, raw, h.end, d_occ, w)?;
    let o = (end - h.end) as f32;
    let one_surface = raw[h.end..end]
        .iter()
        .all(|&r| (p.disp(r) - d_occ).abs() < p.min_step);
    let background = raw[end] != NO_DEPTH && d_occ - p.disp(raw[end]) > w - 2.0 * p.min_step;
    if !(w - o > UNSWALLOWED_GAP && 2.0 * o < w && one_surface && background) {
        return None;
    }
    // Nor may a nearer surface further right cast a shadow reaching the hole (a box past a
    // strip of background: the hole is its detached shadow, the thin rod's merged into it).
    let d_bg = p.disp(raw[end]);
    let reach = ((p.max_disp - d_bg).max(0.0) as usize + 2).min(raw.len() - end);
    let nearer_casts = raw[end..end + reach].iter().enumerate().any(|(k, &r)| {
        r != NO_DEPTH && {
            let shift = p.disp(r) - d_bg;
            shift >= p.min_step && (end + k) as f32 - shift <= h.end as f32
        }
    });
    (!nearer_casts).then(|| {
        // The occluder's right edge shifted by `w`: the shadow's right end.
        ((h.end as f32 - w + o).round().max(0.0) as usize).clamp(h.start, h.end)
    })
}

/// True when `row` shows, within a few pixels of `sb`, a lit gap before the occluder (at
/// disparity `d_occ`, shift `w`): a hole, then one or two valid pixels at the background's
/// depth, then the occluder.
fn lit_gap_before(p: &ScanParams, row: &[u16], sb: usize, d_occ: f32, w: f32) -> bool {
    let d_bg = d_occ - w;
    let lo = sb.saturating_sub(3).max(1);
    let hi = (sb + 4).min(row.len().saturating_sub(3));
    (lo..hi).any(|j| {
        let lit = |r: u16| p.on_background(r, d_bg);
        if row[j - 1] != NO_DEPTH || !lit(row[j]) {
            return false;
        }
        let len = 1 + usize::from(lit(row[j + 1]));
        let r = row[j + len];
        r != NO_DEPTH && p.disp(r) >= d_occ - w / 2.0
    })
}

/// The first answer `judge` gives in the rows above and below, nearest first, up to 40 rows
/// away; false when none answers. `judge` says
/// `None` where the occluder is gone (that direction ends), `Some(None)` where it has no answer.
fn occluder_width_nearby(
    n: usize,
    Rows { up, down }: Rows,
    mut judge: impl FnMut(&[u16]) -> Option<Option<bool>>,
) -> bool {
    const LOOK: usize = 40;
    let (rows_up, rows_down) = (up.len() / n, down.len() / n);
    let (mut go_up, mut go_down) = (true, true);
    for k in 1..=LOOK {
        go_up &= k <= rows_up;
        go_down &= k <= rows_down;
        if !go_up && !go_down {
            break;
        }
        if go_up {
            match judge(&up[(rows_up - k) * n..(rows_up - k + 1) * n]) {
                None => go_up = false,
                Some(Some(answer)) => return answer,
                Some(None) => {}
            }
        }
        if go_down {
            match judge(&down[(k - 1) * n..k * n]) {
                None => go_down = false,
                Some(Some(answer)) => return answer,
                Some(None) => {}
            }
        }
    }
    false
}

/// End of the occluder's run that starts at `start` (at disparity `d_occ`): the first hole or
/// step back by half the shift `w`; `None` when the run is longer than `w`.
fn occluder_end(p: &ScanParams, row: &[u16], start: usize, d_occ: f32, w: f32) -> Option<usize> {
    let limit = (start + w as usize + 1).min(row.len() - 1);
    // disp(r) < d_occ − w/2  ⇔  r > past (disparity falls as raw grows); holes (2047) are always
    // past it, so one integer compare per pixel.
    let past = (p.den - (d_occ - w / 2.0) / p.k)
        .floor()
        .clamp(0.0, f32::from(NO_DEPTH - 1)) as u16;
    row[start..=limit]
        .iter()
        .position(|&r| r > past)
        .map(|k| start + k)
}

/// A shadow falling on a surface that recedes past the sensor's range would be a hole even if
/// lit, so it is OTHER (SPEC §1): extrapolate Sa's surface across the hole and give back to OTHER
/// the pixels where it lies farther than anything measured in the frame (`far`), or past the
/// range limit under `far`'s noise tail where no row above measured anything in that column.
/// [`beyond_range`] for the shadow `[start, end)` of row `raw` that the colour split labelled,
/// with nothing known of the rows above but their labels.
pub(crate) fn beyond_range_span(
    raw: &[u16],
    (start, end): (usize, usize),
    range: Range,
    prev_labels: &[u8],
    labels: &mut [u8],
) {
    beyond_range(
        raw,
        Run { start, end },
        range,
        &[],
        prev_labels,
        [&[], &[]],
        labels,
    );
}

fn beyond_range(
    raw: &[u16],
    h: Run,
    Range { far, limit }: Range,
    above: &[u16],
    prev_labels: &[u8],
    near: [&[u16]; 2],
    labels: &mut [u8],
) {
    const SPAN: usize = 16;
    // Raw units (half a pixel of disparity) within which two pixels are one surface.
    const SAME: u16 = 4;
    let a = h.start - 1;
    // The baseline stays on Sa's surface: it stops at holes and at steps of more than SAME raw
    // units, so a depth edge left of Sa cannot fake a steep slope.
    let mut k = 0;
    while k < SPAN
        && a > k
        && raw[a - k - 1] != NO_DEPTH
        && raw[a - k].abs_diff(raw[a - k - 1]) <= SAME
    {
        k += 1;
    }
    if k < 4 {
        return;
    }
    // Raw units per pixel; a long baseline keeps the 1/8-px quantisation noise small, and pairs
    // of pixels at both ends halve the raw noise (the extrapolation starts between the pair).
    // Each baseline pixel is averaged with the rows above and below where they show the same
    // surface: one row's noise can tilt a level wall's baseline enough to leave the range.
    let at_col = |x: usize| {
        let r = raw[x];
        let (mut sum, mut n) = (u32::from(r), 1u32);
        for row in near {
            if let Some(&q) = row.get(x) {
                if q != NO_DEPTH && q.abs_diff(r) <= SAME {
                    sum += u32::from(q);
                    n += 1;
                }
            }
        }
        sum as f32 / n as f32
    };
    let pair = |i: usize| at_col(i) + at_col(i + 1);
    let slope = (pair(a - 1) - pair(a - k)) / (2 * (k - 1)) as f32;
    // Read off at most SPAN noisy pixels, the slope is that uncertain (raw units per pixel), and
    // its error grows with the distance it is carried. A wall receding at 0.08 a pixel, its
    // farther part hidden by the occluder, read 0.1 to 0.15 now and then, crossed the frame's
    // farthest value inside a 38 px shadow, and the rule below carried that down the rows under
    // it: most of the shadow went OTHER (the fifth simulator's k38 s005), though the frame's
    // farthest value only bounds the range from below. Only the slope beyond the noise is
    // carried.
    const SLOPE_NOISE: f32 = 0.05;
    if slope <= SLOPE_NOISE {
        return; // level or approaching: it cannot leave the range inside the hole
    }
    let rise = slope - SLOPE_NOISE;
    let base = 0.5 * pair(a - 1) + 0.5 * slope;
    // `far` is the frame's noisiest far value, so the surface leaves the range a little before
    // it: within NEAR_LIMIT of it, a pixel under one the row above left OTHER (the same surface
    // out of range there, not a shadow) is out of range too.
    const NEAR_LIMIT: f32 = 3.0;
    for (i, l) in labels[h.start..h.end].iter_mut().enumerate() {
        // Where the rows above show a surface measured as far as the range's end in this
        // column (a back wall), the receding one meets it in a corner: no more leaving the range.
        // (A box's shadow across such a corner was OTHER from its first row down. The fourth
        // simulator's 40 suites: complex IR attached F1 +0.045 summed, j39 +0.024, j3 +0.013;
        // any-shadow precision +0.005, recall +0.059; the rest, the real frame unchanged.)
        if above
            .get(h.start + i)
            .is_some_and(|&q| q != NO_DEPTH && q + SAME >= limit)
        {
            continue;
        }
        let at = base + rise * (i + 1) as f32;
        let out = at > f32::from(far) + 0.5
            || (at > f32::from(limit) + 0.5 && above.get(h.start + i) == Some(&NO_DEPTH))
            || (at > f32::from(far) - NEAR_LIMIT && prev_labels.get(h.start + i) == Some(&OTHER));
        if out && *l != VALID {
            *l = OTHER;
        }
    }
}

/// Detached test, eqs. (4)–(5): look right of the hole for a nearer run [Fa, Fb] whose edges,
/// shifted by their disparity relative to Sa and Sb, land on the hole's edges (the first such
/// run, or the next one when the first does not fit).
fn detached(
    p: &ScanParams,
    raw: &[u16],
    h: Run,
    sa: Option<Bound>,
    sb: Bound,
    rows: Rows,
) -> Detached {
    search_occluder(p, raw, h, sa, sb, rows, Search::Any)
}

/// [`detached`] with Sb itself ruled out as the occluder: only one standing clear of the hole,
/// past a lit gap, counts. A hole that eq. (3) fits as Sb's attached shadow and eqs. (4)–(5) as
/// such an occluder's detached shadow is that occluder's: it covers Sb's shadow, and the
/// projector's rays meet it first (it is the nearer, its shift being the larger).
fn detached_beyond_sb(
    p: &ScanParams,
    raw: &[u16],
    h: Run,
    sa: Bound,
    sb: Bound,
    rows: Rows,
) -> bool {
    // Sb's surface must end within a few pixels (a lit gap, a narrow step): what lies past a
    // wide surface seldom casts this hole, and walking it costs.
    let d = p.disp(sb.edge);
    let sb_run = raw[h.end..]
        .iter()
        .take(THIN_SB + 1)
        .take_while(|&&r| r != NO_DEPTH && (p.disp(r) - d).abs() < p.min_step)
        .count();
    sb_run <= THIN_SB && search_occluder(p, raw, h, Some(sa), sb, rows, Search::BeyondSb).measured()
}

/// Most pixels of an occluder's other limb past the hole its right part runs into (a glossy
/// cylinder measured at its two edges only) that count towards its width.
const LIMB_MAX: usize = 16;
/// How far (in steps of `min_step`) that limb's disparity may lie from the occluder's right end's.
const LIMB_STEPS: f32 = 3.0;

/// Fewest pixels of a nearer surface left of a hole (Sa's) behind which a detached shadow's
/// left part may hide, merged with the surface's own dropout: a single nearer pixel is more
/// often a sliver between two holes (a black poster's) than an object.
const TAIL_HIDER: f32 = 3.0;

/// Widest sliver of a slanted background before an occluder that [`search_occluder`] steps
/// over (pixels).
const SLIVER: usize = 2;

/// Where an occluder whose foreground run starts at `u` starts: past a sliver of up to
/// [`SLIVER`] pixels within a step of each other when the three after it stand nearer than the
/// sliver by more than the sliver stands before the background (`d_bg`): a slanted background
/// coming nearer over the hole, past the step, in a narrow lit gap. Else `u`.
fn after_sliver(p: &ScanParams, raw: &[u16], u: usize, d_bg: f32) -> usize {
    let d0 = p.disp(raw[u]);
    let sliver = raw[u..]
        .iter()
        .take(SLIVER + 1)
        .take_while(|&&q| q != NO_DEPTH && (p.disp(q) - d0).abs() < p.min_step)
        .count();
    let stands_before = |next: &[u16]| {
        next.iter()
            .all(|&q| q != NO_DEPTH && p.disp(q) - d0 > (d0 - d_bg).max(p.min_step))
    };
    if sliver <= SLIVER
        && raw
            .get(u + sliver..u + sliver + 3)
            .is_some_and(stands_before)
    {
        u + sliver
    } else {
        u
    }
}

/// Widest run of Sb's surface [`detached_beyond_sb`] looks past. What it catches shows a lit
/// gap of a pixel or two, or a narrow step: every suite of both simulators scored the same with
/// 8 px, 24 px or no limit, and 8 px took most of the test's cost off a frame full of attached
/// shadows (counted instructions of the benchmark's busy frame +4.7 % without a limit, +2.0 %).
const THIN_SB: usize = 8;

/// What [`search_occluder`] looks for.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Search {
    /// Any occluder, one without depth too ([`detached`]).
    Any,
    /// A measured occluder only: holes in the lit gap are stepped over as dropouts, never
    /// paired as a depthless occluder and its shadow.
    Measured,
    /// [`detached_beyond_sb`].
    BeyondSb,
    /// [`behind_thin_sb`]: a measured occluder past Sb, which stands before the shadow's right
    /// end. Sb is passed even for a narrow hole (what shows of a shadow Sb hides may be a
    /// pixel or two), which the search does not do for others: speckle beside a nearer
    /// surface is common, a thin Sb clear of its own shadow is not. Eq. (5) then puts the
    /// shadow's right end anywhere behind Sb, up to its width past the hole.
    BehindThinSb,
}

/// Eqs. (4)–(5): the occluder right of the hole `h` whose detached shadow it is, if any.
fn search_occluder(
    p: &ScanParams,
    raw: &[u16],
    h: Run,
    sa: Option<Bound>,
    sb: Bound,
    rows: Rows,
    search: Search,
) -> Detached {
    let pairs = matches!(search, Search::Any | Search::BeyondSb);
    let beyond_sb = search == Search::BeyondSb;
    let n = raw.len();
    let d_sb = p.disp(sb.far);
    // A hole at the left border (no Sa) lies on the background Sb shows.
    let d_bg = sa.map_or(d_sb, |sa| sa_sb_bg(p, sa, sb));
    // A nearer surface at Sa (a thin object standing in the shadow) hides the shadow's left end:
    // eq. (4) then measures from the background Sb shows, and the shadow may run on behind that
    // surface, up to its width further left; past the image's left border, any way.
    let nearer = |sa: &Bound| p.disp(sa.far) > d_sb + p.min_step;
    let (d_sa, hidden) = match sa {
        None => (d_sb, f32::INFINITY),
        Some(sa) if nearer(&sa) => (
            d_sb,
            nearer_before(p, raw, h.start, d_sb, usize::MAX) as f32,
        ),
        Some(sa) => (p.disp(sa.far), 0.0),
    };
    let reach = (p.max_disp - d_bg).max(0.0) as usize + 2;
    let stop = (h.end + reach).min(n);
    // Nor need a shadow hidden so start behind that nearer surface: it may run on past it into
    // the hole left of it (a thin leg standing in a nearer leg's shadow, the thin leg's own
    // shadow merged with the first part), where eq. (4) then puts its start.
    // (Read only for an occluder eq. (4) puts that far left: most searches never ask.)
    let hole_before = std::cell::OnceCell::new();
    let starts_behind = |e4: f32| {
        let before = hole_before.get_or_init(|| {
            (hidden > 0.0 && hidden.is_finite())
                .then(|| {
                    let end = h.start - hidden as usize;
                    let len = raw[..end]
                        .iter()
                        .rev()
                        .take_while(|&&r| r == NO_DEPTH)
                        .count();
                    (len > 0).then(|| (end - len) as f32..end as f32)
                })
                .flatten()
        });
        let start = h.start as f32 - 1.0 + e4;
        before
            .as_ref()
            .is_some_and(|b| start >= b.start - p.tol - WIDENING && start < b.end)
    };
    // disp(r) > d_bg + min_step  ⇔  r < fg_below (disparity falls as raw grows); holes (2047)
    // are never below it.
    let fg_below = p.den - (d_bg + p.min_step) / p.k;
    // Raw steps this much under 2·min_step of disparity cannot reach it (one unit of margin
    // against rounding), so they end no occluder below.
    let edge_raw = ((2.0 * p.min_step / p.k) as u32).saturating_sub(1);
    // For whole raw values, r < fg_below  ⇔  r < ⌈fg_below⌉: one 16-bit compare (vectorises
    // twice as wide as a float one). Capped at NO_DEPTH, which is never foreground.
    let fg_lim = fg_below.ceil().clamp(0.0, f32::from(NO_DEPTH)) as u16;
    let is_fg = |r: u16| r < fg_lim;
    let edge_step = edge_raw.min(u32::from(NO_DEPTH)) as u16;
    let mut u = h.end;
    let mut gap_holes = 0;
    let mut stepped = 0;
    let mut passed = 0;
    // Behind a thin Sb the search passed, the shadow's right end may lie anywhere up to Sb's end.
    let mut behind_sb = 0.0;
    // Right end (pixels) of the shadows of a chain of occluders whose first fits eq. (4) and
    // whose shadows overlap: thin objects side by side cast one merged hole (SPEC §1).
    let mut chain: Option<f32> = None;
    let mut chained = 0;
    let mut head: Option<usize> = None;
    let no = |head: Option<usize>| head.map_or(Detached::No, |to| Detached::Head { to });
    let mut next_skip = u;
    while u < stop {
        // Most of the search crosses plain background: skip 16 pixels at a time when none of
        // them is foreground or a hole (branch-free test, vectorised), trying once per block.
        if u >= next_skip && u + 16 <= stop {
            let clean = raw[u..u + 16]
                .iter()
                .fold(true, |ok, &r| ok & !is_fg(r) & (r != NO_DEPTH));
            if clean {
                gap_holes = 0;
                u += 16;
                continue;
            }
            next_skip = u + 16;
        }
        let r = raw[u];
        if r == NO_DEPTH {
            // Small dropouts in the lit gap are fine; a large hole ends the search, unless it is
            // an occluder without depth that cast this hole.
            gap_holes += 1;
            if gap_holes > 2 {
                // A hole narrower than a depthless occluder's smallest shadow ends it here.
                if h.end - h.start + 1 < MIN_DEPTHLESS_WIDTH {
                    return Detached::No;
                }
                let start = u + 1 - gap_holes;
                // A hole that could be this shadow's depthless occluder by its geometry decides
                // (also when it chains or is not repeated: then no one can tell). Any other is a
                // dropout in the lit gap: the search goes on past it.
                let end = u + raw[u..].iter().take_while(|&&r| r == NO_DEPTH).count();
                if let Some(pair) = pairs.then(|| hole_pair(p, raw, h, start, d_bg)).flatten() {
                    // Unless that hole is itself a measured occluder's detached shadow (two
                    // rods' shadows side by side): then it is no occluder, and the search goes
                    // on past it.
                    let other_shadow = end < n
                        && search_occluder(
                            p,
                            raw,
                            Run { start, end },
                            Some(bound_left(raw, start)),
                            bound_right(raw, end),
                            rows,
                            Search::Measured,
                        )
                        .measured();
                    if !other_shadow {
                        return depthless_occluder(p, raw, h, pair, d_bg, rows);
                    }
                }
                stepped += 1;
                // A wider hole ending on a nearer surface is that surface's shadow, or the
                // shadow of an object it hides from the camera (two leaning rods): the
                // projector's ray to this shadow passed left of both, so the search goes on to
                // that surface. Past any other, the occluder would be a guess.
                let before_fg = end < n && is_fg(raw[end]);
                if (end - start > MAX_GAP_DROPOUT && !before_fg)
                    || stepped > MAX_GAP_STEPS
                    || h.end - h.start < MIN_STEP_OVER
                {
                    return Detached::No;
                }
                u = end;
                gap_holes = 0;
                continue;
            }
            u += 1;
            continue;
        }
        gap_holes = 0;
        if is_fg(r) {
            let start = u;
            // A slanted background comes nearer over the hole: past the step, the pixel or two
            // of it in a narrow lit gap are foreground, and began the occluder's run, eq. (4)
            // measured from them (a rod's shadow then read as its attached one). Those much
            // nearer the background than the surface after them are stepped over. (Sixth
            // simulator, a leaning rod before a turned wall: complex IR detached F1 +0.022 on
            // its suite; this project's suites +0.0071 summed, attached +0.0030, simple +0.0025,
            // nothing lower than −0.0003; the real frame unchanged.)
            // (Most runs are one surface over their first three pixels, no sliver: an integer
            // test first.)
            let plain_start = raw.get(u + 1..u + 3).is_some_and(|next| {
                next.iter()
                    .all(|&q| q != NO_DEPTH && q.abs_diff(r) < p.edge_raw)
            });
            let fa = if plain_start {
                u
            } else {
                after_sliver(p, raw, u, d_bg)
            };
            let mut fb = fa;
            // The occluder ends where the foreground does, or where a second surface before the
            // background (another object, a floor) takes over at a depth edge: at least three
            // pixels of each, off the occluder's last two, so a mixed or stray pixel is neither.
            let takes_over = |at: usize| {
                // Most steps inside an occluder are far under the edge: an integer test first.
                if i32::from(raw[at]).abs_diff(i32::from(raw[at - 1])) < edge_raw {
                    return false;
                }
                let d = p.disp(raw[at]);
                let off = |r: u16| (d - p.disp(r)).abs() >= 2.0 * p.min_step;
                off(raw[at - 1])
                    && off(raw[at - 2])
                    && raw.get(at..at + 3).is_some_and(|next| {
                        next.iter()
                            .all(|&r| is_fg(r) && (p.disp(r) - d).abs() < p.min_step)
                    })
            };
            let mut next_block = fb;
            loop {
                // Inside a wide occluder: 16 pixels at a time while each is foreground and no
                // step reaches `edge_raw` (then no pixel can take over; branch-free, vectorised),
                // trying once per block.
                if fb >= next_block && fb + 17 <= n {
                    let (next, prev) = (&raw[fb + 1..fb + 17], &raw[fb..fb + 16]);
                    let smooth = next.iter().zip(prev).fold(true, |ok, (&b, &a)| {
                        ok & is_fg(b) & (b.abs_diff(a) < edge_step)
                    });
                    if smooth {
                        fb += 16;
                        continue;
                    }
                    next_block = fb + 16;
                }
                if fb + 1 < n && is_fg(raw[fb + 1]) && !(fb >= fa + 2 && takes_over(fb + 1)) {
                    fb += 1;
                } else {
                    break;
                }
            }
            // A surface turned towards the camera (a box's face) rises out of the lit gap by
            // less than a step a pixel: no occluder starts there, and it is not passed as one.
            if fa > h.end
                && raw[fa - 1] != NO_DEPTH
                && (p.disp(raw[fa]) - p.disp(raw[fa - 1])).abs() < p.min_step
            {
                u = fb + 1;
                continue;
            }
            let d_fa = p.disp(raw[fa]).max(p.disp(raw[(fa + 1).min(fb)]));
            let d_fb = p
                .disp(raw[fb])
                .max(p.disp(raw[fb.saturating_sub(1).max(fa)]));
            // Eq. (4): Fa − Sa = w_s + w_b; eq. (5): Fb − Sb = w_b + w_f (pixel positions).
            let e4 = (fa as f32 - (h.start as f32 - 1.0)) - (d_fa - d_sa);
            let e5 = (fb as f32 - h.end as f32) - (d_fb - d_sb);
            // Pixel sampling puts e4 at about +1 and e5 at about −1 for an ideal shadow. The
            // sensor's widening moves the hole's left end left (e4 grows) and its right end right
            // (e5 shrinks), never the other way: the tolerance is that much wider on that side.
            // A nearer object just left of the occluder (a rod before a rod) may hide the
            // occluder's left edge, up to its own width: its shadow may start that much further
            // left than what shows of it casts (never further right). Counted only when needed.
            let over4 = e4 - 1.0 - (p.tol + WIDENING);
            let fits4 = (e4 - 1.0 >= -p.tol - hidden || starts_behind(e4))
                && (over4 <= 0.0 || nearer_before(p, raw, fa, d_fa, usize::MAX) as f32 >= over4);
            // An occluder running off the right border shows only part of its width: its
            // shadow may end further right than what shows of it casts (never further left).
            let cut = fb + 1 == n;
            // Likewise one running into a hole (its right part black, or in another object's
            // shadow): up to that hole's end.
            let hidden_right = if !cut && raw[fb + 1] == NO_DEPTH {
                let gap = raw[fb + 1..].iter().take_while(|&&r| r == NO_DEPTH).count();
                // Past the hole, the occluder's other limb at about its depth (a glossy
                // cylinder measured at its two edges only): its width runs on through it.
                let limb = raw[fb + 1 + gap..]
                    .iter()
                    .take(LIMB_MAX)
                    .take_while(|&&r| {
                        r != NO_DEPTH && (p.disp(r) - d_fb).abs() <= LIMB_STEPS * p.min_step
                    })
                    .count();
                (gap + limb) as f32
            } else {
                0.0
            };
            // A shadow cut by a nearer surface shows no more than the occluder's width (plus the
            // widening of its right end): the tolerances of both equations must not add up. What
            // shows of an occluder cut by the border or a hole bounds its width from below only.
            let width = (h.end - h.start) as f32;
            let shown = (fb + 1 - fa) as f32 + WIDENING + 1.0;
            let cut_fits = hidden == 0.0 || cut || width <= shown + hidden_right;
            let fits5 = e5 + 1.0 <= p.tol + behind_sb
                && (cut || e5 + hidden_right + 1.0 >= -p.tol - WIDENING);
            // Behind a thin nearer surface at Sa the shadow may fall on that surface itself
            // (a chair's back leg in its front leg's shadow): Sa's surface runs on in the dark,
            // and the hole ends with it, short of where eq. (5) on the wall would end it, at or
            // before where eq. (5) on Sa's surface does. (Sixth simulator: a fresh suite's chair,
            // simple IR detached F1 +0.062 there; this project's suites, complex, +0.0047
            // summed, RGB +0.0041 with the hole warped at Sa's depth; nothing lower.)
            let on_sa = || {
                (h.end - h.start >= MIN_STEP_OVER
                    && hidden > 0.0
                    && hidden.is_finite()
                    && e5 + 1.0 <= p.tol)
                    .then_some(sa)
                    .flatten()
                    .filter(|sa| {
                        let d = p.disp(sa.far);
                        d_fa.min(d_fb) > d + p.min_step
                            && (fb as f32 - h.end as f32) - (d_fb - d) + 1.0 >= -p.tol
                    })
            };
            // Sb's first pixels are no occluder standing clear of the hole.
            if fits4 && cut_fits && !(beyond_sb && start == fa && fa <= h.end + 1) {
                if fits5 {
                    return Detached::Measured;
                }
                if let Some(sa) = on_sa() {
                    return Detached::OnSa { raw: sa.far };
                }
            }
            // Where this occluder's shadow ends (eq. 5 with Fb − Sb solved for Sb).
            let shadow_end = h.end as f32 + e5;
            // Eq. (4) solved for Sa: where its shadow starts.
            let shadow_start = h.start as f32 - 1.0 + e4;
            // Past the left border, or behind a nearer object standing left of the hole, the
            // hole's left part may be something else the shadow merged with (a region beyond
            // range, the nearer object's own dropout): only eq. (5) can be read.
            if hidden >= TAIL_HIDER && fits5 && width > shown {
                // The widening moves the shadow's left end left as well.
                let from = (shadow_start - WIDENING).floor().max(h.start as f32) as usize;
                if from > h.start && from < h.end && shows_its_start(p, rows, from, h.end) {
                    return Detached::Tail { from };
                }
            }
            match chain {
                // A merged hole: the first occluder's shadow fits its left end and stops short
                // of its right end, so the next occluder's shadow goes on from there.
                None if fits4 && hidden == 0.0 && e5 + 1.0 < -p.tol - WIDENING => {
                    if sa.is_some() {
                        let to = (shadow_end + HEAD_SLACK).round() as usize;
                        head = (to > h.start + 1 && to < h.end).then_some(to);
                    }
                    chain = Some(shadow_end);
                    chained = 1;
                    u = fb + 1;
                    continue;
                }
                Some(end) if shadow_start <= end + 1.0 + p.tol && chained < MAX_CHAINED => {
                    if fits5 {
                        return Detached::Measured;
                    }
                    if e5 + 1.0 > p.tol {
                        return no(head);
                    }
                    chain = Some(end.max(shadow_end));
                    chained += 1;
                    u = fb + 1;
                    continue;
                }
                _ => {}
            }
            // Not this one: the projector's ray may have passed beside it to an occluder further
            // right (a thin rod before a box, the box's own shadow between them).
            passed += 1;
            let past_sb = search == Search::BehindThinSb && fa == h.end;
            if passed > MAX_PASSED_OBJECTS || (h.end - h.start < MIN_STEP_OVER && !past_sb) {
                return no(head);
            }
            if past_sb {
                behind_sb = (fb + 1 - fa) as f32;
            }
            u = fb + 1;
            continue;
        }
        u += 1;
    }
    no(head)
}

/// Eqs. (4)–(5) for an occluder that returns no depth (black, glossy): its shadow on a plane
/// is its own image shifted left by `w = disp(occluder) − disp(background)`, so the hole `h` is
/// its detached shadow when a hole of the same width (plus the sensor's widening), on the same
/// background, lies right of it, and the shift puts the occluder within the sensor's range: the
/// `(shift, occluder)` pair [`hole_pair`] found. Nothing else in the row tells this pair from two
/// chance dropouts, so the rows above and below (`rows`) must both repeat it with the same
/// shift: an occluder is a solid.
fn depthless_occluder(
    p: &ScanParams,
    raw: &[u16],
    h: Run,
    (shift, occluder): (f32, Run),
    d_bg: f32,
    rows: Rows,
) -> Detached {
    // Several such holes in a row (two black rods: shadow, shadow, rod, rod) chain up, and
    // nothing in the depth map says which pairs belong together: when the hole left of `h`
    // pairs with `h`, or the occluder pairs with the hole after it, none is labelled.
    let reach = (p.max_disp - d_bg).max(0.0) as usize + 2;
    let chained_left = hole_before(raw, h.start, reach)
        .is_some_and(|before| hole_pair(p, raw, before, h.start, d_bg).is_some());
    // (An occluder that shares its hole with a nearer surface's shadow chains with nothing.)
    let chained_right = raw.get(occluder.end).is_some_and(|&r| r != NO_DEPTH)
        && hole_after(raw, occluder.end, reach)
            .is_some_and(|after| hole_pair(p, raw, occluder, after, d_bg).is_some());
    if chained_left || chained_right {
        return Detached::No;
    }
    // This row's lit gap after the occluder, narrow enough for the widening to close it.
    let narrow_gap_after = hole_after(raw, occluder.end, WIDENING as usize + 1).is_some();
    // Whether `row` repeats the pair, and whether only with the occluder's hole run on.
    let repeats_how = |row: &[u16]| -> (bool, bool) {
        // The same pair in a neighbouring row: holes through both centres, shifted alike (the
        // widening moves each row's shadow end by 0–3 px).
        let (Some(s), Some(o)) = (
            hole_around(row, (h.start + h.end) / 2),
            hole_around(row, (occluder.start + occluder.end) / 2),
        ) else {
            return (false, false);
        };
        if s.start == o.start {
            // One hole through both: the widening swallowed a lit gap of a pixel or two there.
            // It must span the same shadow and occluder, on the same background.
            let same = s.start > 0
                && s.end < row.len()
                && (s.start as f32 - h.start as f32).abs() <= WIDENING
                && s.end.abs_diff(occluder.end) <= 1
                && p.on_background(row[s.start - 1], d_bg)
                && p.on_background(row[s.end], d_bg);
            return (same, false);
        }
        if s.end >= o.start {
            return (false, false);
        }
        if hole_pair(p, row, s, o.start, d_bg).is_some_and(|(w, _)| (w - shift).abs() <= WIDENING) {
            return (true, false);
        }
        // The occluder's hole running on into the next hole (the lit gap after it closed in
        // that row: a glossy rod beside a black cylinder): the same shadow, with the lit gap and
        // the occluder's left edge in place, still repeats the pair, in one of the two rows, if
        // this row's shadow is as wide as its occluder but for the widening (not merely within
        // eq. (3)'s tolerance: holes in clutter on a real frame).
        let run_on = narrow_gap_after
            && o.end > occluder.end + 1
            && h.end - h.start <= occluder.end - occluder.start + WIDENING as usize + 1
            && s.end.abs_diff(h.end) <= 1
            && (s.start as f32 - h.start as f32).abs() <= WIDENING
            && o.start.abs_diff(occluder.start) <= 1
            && (s.start == 0 || p.on_background(row[s.start - 1], d_bg))
            && p.on_background(row[s.end], d_bg)
            && p.on_background(row[o.start - 1], d_bg);
        (run_on, run_on)
    };
    // The rows beside a hidden shadow (below) repeat it in full.
    let repeats = |row: &[u16]| repeats_how(row) == (true, false);
    let [above, below] = rows.near(raw.len());
    let up = repeats_how(above);
    if !up.0 {
        return Detached::No;
    }
    let down = repeats_how(below);
    if !down.0 || (up.1 && down.1) {
        return Detached::No;
    }
    // A shadow whose left part a nearer surface hides may be any hole that happens to lie
    // beside that surface (on a real frame, the top rows of a translucent bin's dropouts beside
    // a pole, five rows high): the rod that casts it stands over more rows than that.
    let hidden = nearer_left_of(p, raw, h, d_bg);
    if hidden {
        // Beside a nearer surface a hole pairs as readily with another object's detached shadow
        // as with a rod: a measured rod right of the "occluder" that casts it takes it.
        if occluder.end < raw.len() {
            let (oa, ob) = (
                bound_left(raw, occluder.start),
                bound_right(raw, occluder.end),
            );
            if detached(p, raw, occluder, Some(oa), ob, rows).measured() {
                return Detached::No;
            }
        }
        // Nearest rows first (the rows just beside passed above), so a blob stops early.
        let mut alike = 0;
        for row in rows.within(raw.len(), HIDDEN_PAIR_ROWS).skip(2) {
            if !repeats(row) {
                return Detached::No;
            }
            alike += 1;
        }
        if alike < 2 * (HIDDEN_PAIR_ROWS - 1) {
            return Detached::No;
        }
    }
    let d_occ = d_bg + shift;
    let at = (p.den - d_occ / p.k)
        .round()
        .clamp(0.0, f32::from(NO_DEPTH - 1)) as u16;
    Detached::Depthless { occluder, raw: at }
}

/// The geometric test of [`depthless_occluder`] in one row: the hole from `start` to the next
/// valid pixel is a candidate occluder for shadow `h`. Returns the shift (pixels) and the hole.
fn hole_pair(p: &ScanParams, raw: &[u16], h: Run, start: usize, d_bg: f32) -> Option<(f32, Run)> {
    let n = raw.len();
    let end = raw[start..]
        .iter()
        .position(|&r| r != NO_DEPTH)
        .map_or(n, |k| start + k);
    // An occluder running off the right border shows only part of its width; a shadow running
    // off the left border, only part of its own.
    let at_border = end == n;
    let at_left = h.start == 0;
    if end - start < MIN_DEPTHLESS_WIDTH || (at_left && at_border) {
        return None;
    }
    // A nearer surface left of the shadow may hide its left part, as the border does (a black
    // rod beside a box before a wall: complex IR detached F1 +0.011, +0.007 and +0.004 on three
    // of this project's suites, RGB any-shadow recall +0.013, +0.013 and +0.003; the other
    // fifteen within 0.0001).
    let nearer_left = nearer_left_of(p, raw, h, d_bg);
    // Both holes lie on the same background: lit pixels of its depth on either side of each, or,
    // on a slanted wall, all on the line the lit gap between them draws.
    let level = |u: usize| p.on_background(raw[u], d_bg);
    // A nearer surface may close the occluder's hole (a black rod before a box's edge, j32
    // s001), if the hole is wider than that surface's own attached shadow there could be, and
    // the shadow's own left side shows the background (one side of each hole must).
    let (occluder_w, shadow_w) = ((end - start) as f32, (h.end - h.start) as f32);
    let nearer_end = !at_border && !at_left && !nearer_left && !level(end) && {
        let step = p.disp(raw[end]) - d_bg;
        step >= p.min_step && occluder_w > step + p.over
    };
    // Or the occluder's own measured part closes it: a glossy rod's limb that returns depth, a
    // few pixels before the background resumes, at the disparity the pair's right edges give
    // (eqs. 4–5), within 2 px, or up to twice the widening more (the widening of the shadow's
    // right end makes that shift read short; the limb lies a little off the silhouette's edge).
    let own_end = !at_border && !at_left && {
        let off = p.disp(raw[end]) - d_bg - (end - h.end) as f32;
        (-2.0..=2.0 * WIDENING).contains(&off)
            && (end + 1..n.min(end + OWN_LIMB + 1))
                .find(|&u| raw[u] == NO_DEPTH || level(u))
                .is_some_and(|u| raw[u] != NO_DEPTH)
    };
    let on_one = |background: &dyn Fn(usize) -> bool| {
        (at_left || nearer_left || background(h.start - 1))
            && background(h.end)
            && background(start - 1)
            && (at_border || nearer_end || own_end || background(end))
    };
    // On a plane whose disparity grows by `slope` per column, a projector ray meeting the
    // occluder at column x_o meets the plane at x_s = (x_o − const) / (1 − slope): the shadow is
    // the occluder's image stretched by 1 / (1 − slope), plus the widening. The stripes of a
    // glossy cylinder, which bends away from any line, seldom fit that (an independent
    // simulator's simple scenes: detached F1 −0.045 without this check, −0.008 with it).
    let on_plane = |line: Line| {
        let stretched = occluder_w / (1.0 - line.slope).max(0.5);
        on_one(&|u| line.holds(p, raw, u, 2.0))
            && (at_left || at_border || nearer_left || shadow_w <= stretched + WIDENING + 1.0)
    };
    // A lit gap too narrow to draw the line through draws it with the surface past the
    // occluder (a black rod's shadow on a side wall, 7 px from it: j33 s019), each measured
    // pixel of both on it.
    let narrow = start - h.end < MIN_SLANT_GAP;
    let past_line = || {
        let to = end
            + raw[end..]
                .iter()
                .take(SLANT_RUN)
                .take_while(|&&r| r != NO_DEPTH)
                .count();
        (narrow && to >= end + MIN_SLANT_GAP)
            .then(|| gap_line(p, raw, h.end, to))
            .flatten()
    };
    // Or the surface before the shadow alone draws it (at the border nothing lies past the
    // occluder), over a run long enough not to take a thin object there for the wall: two
    // runs of a few pixels draw a line through any two rods before a region beyond range.
    // (Read at most once: the border test below asks again.)
    let before = std::cell::OnceCell::new();
    let before_line = || {
        *before.get_or_init(|| {
            let run = raw[..h.start]
                .iter()
                .rev()
                .take(SLANT_RUN)
                .take_while(|&&r| r != NO_DEPTH)
                .count();
            narrow
                && run >= SLANT_RUN
                && gap_line(p, raw, h.start - run, h.start).is_some_and(on_plane)
        })
    };
    let sides = on_one(&level)
        || gap_line(p, raw, h.end, start).is_some_and(on_plane)
        || (!at_border && past_line().is_some_and(on_plane))
        || before_line();
    if !sides {
        return None;
    }
    // At the border nothing closes the occluder's hole, so the lit gap must be the very surface
    // the shadow lies on (within a step of the shadow's left side), not merely near its depth:
    // two thin objects before a wall beyond range bound its holes at depths near each other.
    // On a slanted wall, the line the surface before the shadow draws must reach the gap.
    if at_border
        && (p.disp(raw[start - 1]) - p.disp(raw[h.start - 1])).abs() >= p.min_step
        && !before_line()
    {
        return None;
    }
    // Widening only ever adds to the shadow (up to `over`); one pixel of sampling either way.
    // At the border the occluder may be wider than what shows, so its shadow too; but a real
    // sensor's dead band there (8 px or more in every row) would pair with any hole within reach,
    // so the lit gap must be no wider than the shadow (an occluder at least half as wide as its
    // shift, as a rod close to the wall).
    if at_left {
        // The right edges give the shift; the whole shadow, the occluder shifted by it, must
        // reach past the border (within the widening of its right end), and what shows of it
        // is at most as wide as the occluder and its widening.
        let shift = (end - h.end) as f32;
        let cut = shadow_w <= occluder_w + p.over && start as f32 - shift <= WIDENING;
        return (cut && d_bg + shift <= p.max_disp).then_some((shift, Run { start, end }));
    }
    // A thin occluder's whole shadow may lie just beside a nearer surface (a rod's shadow
    // right of a cylinder): the plain test below, with the rows around that
    // [`depthless_occluder`] then asks for (an independent simulator's suite with the NYU
    // rotation: complex detached F1 +0.020, any-shadow recall +0.023). A wide "occluder" there
    // pairs as readily with any hole (a black poster and a region beyond range).
    let whole_beside = shadow_w >= occluder_w - 1.0 && occluder_w <= THIN_SA as f32;
    if nearer_left && !whole_beside {
        // The right edges give the shift. The whole shadow, the occluder shifted by it, starts
        // at `h.end − occluder_w` (less the widening of its right end): the surface must be wide
        // enough to hide what of it does not show. Hidden shadows are the narrower ones.
        if at_border || shadow_w >= occluder_w - 1.0 {
            return None;
        }
        let hidden = h.start as f32 - (h.end as f32 - occluder_w);
        let cover = nearer_before(p, raw, h.start, d_bg, hidden as usize + 2);
        let shift = (end - h.end) as f32;
        return (cover as f32 + 1.0 >= hidden && d_bg + shift <= p.max_disp)
            .then_some((shift, Run { start, end }));
    }
    // Closed by a nearer surface, the occluder's hole may hold that surface's attached shadow
    // too, on its right (eq. 3, up to `over` wider): the occluder is the rest (a black rod left
    // of a cylinder's shadow).
    let sb_shadow = if nearer_end {
        p.disp(raw[end]) - d_bg
    } else {
        0.0
    };
    let rest = occluder_w - sb_shadow;
    let fits = |w: f32, slack: f32| shadow_w >= w - slack - 1.0 && shadow_w <= w + p.over;
    let mut end = end;
    if at_border {
        if shadow_w < occluder_w - 1.0 || (start - h.end) as f32 > shadow_w {
            return None;
        }
    } else if !fits(occluder_w, 0.0) {
        if !(nearer_end && rest >= MIN_DEPTHLESS_WIDTH as f32 && fits(rest, p.over)) {
            return None;
        }
        end = start + (rest.round() as usize).min(end - start);
    }
    // The shadow's right edge is the occluder's, shifted (plus up to 2 px of widening); at the
    // border the left edges give it (plus the widening of the shadow's left end). The implied
    // occluder must lie within the sensor's range.
    // Where a nearer surface closes the occluder's hole, its right end may be that surface's
    // shadow: the left edges give it too.
    let shift = if at_border || nearer_end {
        (start - h.start) as f32
    } else {
        (end - h.end) as f32
    };
    (d_bg + shift <= p.max_disp).then_some((shift, Run { start, end }))
}

/// A plane's disparity is affine in the image column, so a wall turned away from the camera (a
/// side wall) draws a line along a row: a detached shadow and its depthless occluder 50 px apart
/// on it lie at disparities 3 px apart, past [`ScanParams::on_background`]'s reach.
pub(crate) struct Line {
    /// Column and disparity (pixels) of one point on it.
    at: f32,
    disp: f32,
    /// Disparity change per column.
    pub(crate) slope: f32,
    /// Columns it reaches: extrapolated no further than [`SLANT_REACH`] times the run it was
    /// drawn through.
    pub(crate) reach: std::ops::Range<usize>,
}

impl Line {
    /// The line through the ends of `raw[from..to]` (three pixels averaged at each, against the
    /// sensor's noise; `disp` gives a raw value's disparity), if the run is at least
    /// [`MIN_SLANT_GAP`] wide and each end holds a measured pixel. Whether the run lies on it is
    /// [`Line::fits`]'s question.
    pub(crate) fn through(
        raw: &[u16],
        (from, to): (usize, usize),
        disp: impl Fn(u16) -> f32,
    ) -> Option<Line> {
        if to < from + MIN_SLANT_GAP {
            return None;
        }
        let run = &raw[from..to];
        let mean = |part: &[u16]| {
            let (sum, n) = part
                .iter()
                .filter(|&&r| r != NO_DEPTH)
                .fold((0.0, 0.0), |(s, n), &r| (s + disp(r), n + 1.0));
            (n > 0.0).then(|| sum / n)
        };
        let (a, b) = (mean(&run[..3])?, mean(&run[run.len() - 3..])?);
        Some(Line {
            at: from as f32 + 1.0,
            disp: a,
            slope: (b - a) / (run.len() - 3) as f32,
            reach: from.saturating_sub(SLANT_REACH * run.len())..to + SLANT_REACH * run.len(),
        })
    }

    /// Its disparity at column `u`.
    pub(crate) fn disp_at(&self, u: usize) -> f32 {
        self.disp + self.slope * (u as f32 - self.at)
    }

    /// Whether each measured pixel of `raw[from..to]` lies within `tol` pixels of disparity of
    /// it: one smooth surface.
    pub(crate) fn fits(
        &self,
        raw: &[u16],
        (from, to): (usize, usize),
        disp: impl Fn(u16) -> f32,
        tol: f32,
    ) -> bool {
        (from..to).all(|u| raw[u] == NO_DEPTH || (disp(raw[u]) - self.disp_at(u)).abs() < tol)
    }

    /// Whether pixel `u` is measured and lies on the line within `steps` of `min_step`.
    fn holds(&self, p: &ScanParams, raw: &[u16], u: usize, steps: f32) -> bool {
        self.reach.contains(&u)
            && raw.get(u).is_some_and(|&r| r != NO_DEPTH)
            && (p.disp(raw[u]) - self.disp_at(u)).abs() < steps * p.min_step
    }
}

/// The line through the lit gap `[from, to)` between a shadow and its occluder, when the gap is
/// one smooth surface: each measured pixel within a step of the line through its ends.
fn gap_line(p: &ScanParams, raw: &[u16], from: usize, to: usize) -> Option<Line> {
    let disp = |r: u16| p.disp(r);
    Line::through(raw, (from, to), disp).filter(|line| line.fits(raw, (from, to), disp, p.min_step))
}

/// Narrowest lit gap [`gap_line`] draws a line through: over fewer pixels the sensor's noise
/// tilts it too much to extrapolate across a shadow.
const MIN_SLANT_GAP: usize = 8;
/// Measured pixels past a depthless occluder, or before its shadow, that [`hole_pair`] draws a
/// slanted wall's line through when the lit gap is too narrow for [`gap_line`].
const SLANT_RUN: usize = 24;
/// How many times the run's width a [`Line`] is extrapolated at most, either side.
const SLANT_REACH: usize = 3;

/// Whether the pixel left of shadow `h` is a surface nearer than the background (disparity
/// `d_bg`) rather than the background itself: one that may hide the shadow's left part. The one
/// reading of [`hole_pair`] and [`depthless_occluder`].
fn nearer_left_of(p: &ScanParams, raw: &[u16], h: Run, d_bg: f32) -> bool {
    h.start > 0 && {
        let r = raw[h.start - 1];
        r != NO_DEPTH && !p.on_background(r, d_bg) && p.disp(r) > d_bg
    }
}

/// The hole run that ends at most `reach` pixels left of `start`, with only valid pixels between.
fn hole_before(raw: &[u16], start: usize, reach: usize) -> Option<Run> {
    let lo = start.saturating_sub(reach);
    let end = raw[lo..start].iter().rposition(|&r| r == NO_DEPTH)? + lo + 1;
    let first = raw[..end]
        .iter()
        .rposition(|&r| r != NO_DEPTH)
        .map_or(0, |k| k + 1);
    Some(Run { start: first, end })
}

/// The start of the first hole at most `reach` pixels right of `end`, with only valid pixels
/// between.
fn hole_after(raw: &[u16], end: usize, reach: usize) -> Option<usize> {
    let hi = (end + reach).min(raw.len());
    raw[end..hi]
        .iter()
        .position(|&r| r == NO_DEPTH)
        .map(|k| end + k)
}

/// True when a row nearby (the nearest that answers, up to 40 rows away) shows the left end of
/// the shadow `[from, end)` that this row's hole merged with something on its left: the hole
/// through the shadow's middle there is a whole detached shadow (eqs. 4–5) starting near
/// `from`. Eq. (5) alone fits where an object's left edge happens to lie where a rod's shadow on
/// it would end (a shadow that never falls on that object, in any row). A row whose hole there
/// starts well left of `from` is merged too, and has no say.
fn shows_its_start(p: &ScanParams, rows: Rows, from: usize, end: usize) -> bool {
    let mid = (from + end) / 2;
    let none = Rows { up: &[], down: &[] };
    occluder_width_nearby(WIDTH, rows, |row| {
        Some(match hole_around(row, mid) {
            Some(run) if run.start > 0 && (run.start as f32 + 2.0 * WIDENING) < from as f32 => None,
            Some(run) if run.start > 0 && run.end < row.len() => Some(
                run.start < mid
                    && search_occluder(
                        p,
                        row,
                        run,
                        Some(bound_left(row, run.start)),
                        bound_right(row, run.end),
                        none,
                        Search::Measured,
                    )
                    .measured(),
            ),
            _ => None,
        })
    })
}

/// The hole run of `row` containing column `u` or a neighbour of it, if any.
fn hole_around(row: &[u16], u: usize) -> Option<Run> {
    let u = [u, u.saturating_sub(1), u + 1]
        .into_iter()
        .find(|&k| row.get(k) == Some(&NO_DEPTH))?;
    let start = row[..u]
        .iter()
        .rposition(|&r| r != NO_DEPTH)
        .map_or(0, |k| k + 1);
    let end = row[u..]
        .iter()
        .position(|&r| r != NO_DEPTH)
        .map_or(row.len(), |k| u + k);
    Some(Run { start, end })
}

/// Rows above a hole whose columns, all without depth, make it the continuation of a region the
/// sensor does not measure ([`classify_left_border`], [`below_unmeasured`]). At 4 the real frame
/// lost 50 px of an attached shadow under a 13 px hole two rows tall at an object's top corner.
const UNMEASURED_ROWS: usize = 8;

/// Whether the [`UNMEASURED_ROWS`] rows above (`rows_up`: whole rows of `width` values) hold no
/// depth over the columns of `h`.
fn unmeasured_over(rows_up: &[u16], width: usize, h: Run) -> bool {
    rows_up.len() >= UNMEASURED_ROWS * width
        && rows_up
            .rchunks_exact(width)
            .take(UNMEASURED_ROWS)
            .all(|row| row[h.start..h.end].iter().all(|&r| r == NO_DEPTH))
}

/// What [`classify_left_border`] reads besides the row: the last valid value above each column,
/// the labels of the row above, the rows around, and the frame's memory of the rows below.
type LeftBorderContext<'a, 'm> = (
    Range,
    &'a [u16],
    &'a [u8],
    Rows<'a>,
    Option<&'m mut BelowMemory>,
);

/// A hole touching the left border: Sa is outside the image, so the background the shadow falls
/// on is estimated from what surrounds the hole: the surface just right of the occluder (the
/// background usually continues behind it), and the nearest valid pixels above and below in the
/// hole's columns, however far (but not where the surface found, carried up its slope, would be
/// beyond the range). The farthest estimate wins: the shadow lies on the background. Where Sb
/// is not nearer than that, or the hole is too wide for Sb's attached shadow, the hole may hold
/// the right part of a detached shadow (eqs. 4–5 with the left end open).
fn classify_left_border(
    p: &ScanParams,
    raw: &[u16],
    h: Run,
    sb: Bound,
    (range, above, prev_labels, rows, mut memory): LeftBorderContext,
    labels: &mut [u8],
    filled: &mut [u16],
) {
    let below = rows.down;
    let from_above = farthest_above(above, h);
    let v = rows.up.len() / WIDTH;
    // However far down: a box's shadow may run from the frame's top to its middle.
    let mut down = |col: usize| {
        match memory.as_deref_mut() {
            Some(memory) => memory.surface_below(v, below, col),
            None => surface_below(below, col),
        }
        // Past the farthest the frame measured: beyond the range in this row.
        .filter(|&(_, here)| here <= f32::from(range.far) + 0.5)
        .map(|(r, _)| r)
    };
    // Most left-border holes are the sensor's dead band, the same in every row: the rows above
    // already answer, unless all they show is the occluder itself (a hole a pixel wider than
    // the one above it).
    let behind = |r: u16| p.disp(sb.near) - p.disp(r) >= p.min_step;
    let from_below = if from_above.is_some_and(behind) {
        None
    } else {
        down(h.start).max(down(h.end - 1))
    };
    let beside = background_right_of(p, raw, h.end);
    let bg = [from_above, from_below, beside.map(|(_, r)| r)]
        .into_iter()
        .flatten()
        .max();
    fill(filled, h, bg.map_or(sb.far, |bg| bg.max(sb.far)));
    // Nothing ever measured above the hole's columns, and the row above an OTHER hole across
    // them: a region the sensor cannot measure (a wall beyond range) reaching down to Sb, not a
    // shadow on the surface found below. (A shadow running down from the frame's top row is
    // labelled there, and its rows below follow it.) A wide surface past the occluder, where
    // nothing was ever measured above its first pixel either, says otherwise: the unmeasured
    // region ends in this row on both sides of the occluder, as where a floor comes into range.
    // Nothing measured over the hole's columns for [`UNMEASURED_ROWS`] rows above counts too:
    // a value measured further up (an object above a region beyond range) is no background of
    // this row's hole, and where the occluder's edge slants the region narrows row by row until
    // it fits the shadow that value would give.
    let unmeasured_above = (from_above.is_none() || unmeasured_over(rows.up, WIDTH, h))
        && beside.is_none_or(|(u, _)| above[u] != NO_DEPTH)
        && prev_labels.len() >= h.end
        && prev_labels[h.start..h.end].iter().all(|&l| l == OTHER);
    let attached_w = bg
        .map(|bg| p.disp(sb.near) - p.disp(bg))
        .filter(|&w| w >= p.min_step && !unmeasured_above);
    if let Some(w) = attached_w {
        label_attached(
            p,
            raw,
            h,
            w,
            Rows {
                up: &[],
                down: below,
            },
            labels,
        );
    }
    // Where Sb is the background (nothing farther shows), or the hole is too wide for Sb's
    // attached shadow (a region beyond range runs off the border behind it), a detached shadow
    // on Sb's surface whose left end lies past the border or merged with that region.
    if attached_w.is_none_or(|w| (h.end - h.start) as f32 > w + p.over) {
        match detached(p, raw, h, None, sb, rows) {
            Detached::Measured | Detached::OnSa { .. } => {
                set(labels, raw, h.start, h.end, DETACHED)
            }
            // The same cast by an occluder that returns no depth: it is warped where it stands.
            Detached::Depthless { occluder, raw: at } => {
                set(labels, raw, h.start, h.end, DETACHED);
                fill(filled, occluder, at);
            }
            Detached::Tail { from } => set(labels, raw, from, h.end, DETACHED),
            Detached::No | Detached::Head { .. } => {}
        }
    }
}

/// The surface behind the occluder that starts at `start`: follow the occluder along the row
/// while it stays continuous (dropouts of up to [`MAX_DROPOUT`] are stepped over) and return the
/// raw value just past its right edge, if that is farther and runs on as a wide surface (a wall
/// or floor, which a left-border shadow falls on too, not a narrow object in front of it), with
/// the column where it starts.
fn background_right_of(p: &ScanParams, raw: &[u16], start: usize) -> Option<(usize, u16)> {
    let n = raw.len();
    let mut last = raw[start];
    let mut gap = 0;
    for u in start + 1..n {
        let r = raw[u];
        if r == NO_DEPTH {
            gap += 1;
            if gap > MAX_EDGE_GAP {
                return None; // a region with no depth, not a dropout: nothing behind in sight
            }
            continue;
        }
        let step = i32::from(r) - i32::from(last);
        // Past a dropout the occluder must go on; past a longer hole only its edge may lie.
        if gap > MAX_DROPOUT && step < i32::from(p.edge_raw) {
            return None;
        }
        gap = 0;
        if step >= i32::from(p.edge_raw) {
            if !wide_surface(p, &raw[u..]) {
                return None;
            }
            // Falling edge: robust background from up to three pixels past it.
            let bg = raw[u..].iter().take(3).take_while(|&&r| r != NO_DEPTH);
            return bg.copied().max().map(|bg| (u, bg));
        }
        if step <= -i32::from(p.edge_raw) {
            return None; // something nearer still: no background in sight
        }
        last = r;
    }
    None
}

/// Dropouts a surface walk steps over (pixels); a longer hole is a region of its own.
const MAX_DROPOUT: usize = 6;

/// A longer hole a surface walk crosses only where a farther surface follows it (pixels): the
/// occluder's right face, grazing or dark, and the sensor's widening of it, before the
/// background. A box 1.2 m away showed 6 or 7 px of it in an independent simulator.
const MAX_EDGE_GAP: usize = 16;

/// Measured pixels a surface needs to count as the wide background of a row.
const WIDE_SURFACE: usize = 64;

/// True when `seg` starts with at least [`WIDE_SURFACE`] measured pixels of one surface.
fn wide_surface(p: &ScanParams, seg: &[u16]) -> bool {
    let mut last = seg[0];
    let (mut seen, mut gap) = (0, 0);
    for &r in seg {
        if r == NO_DEPTH {
            gap += 1;
            if gap > MAX_DROPOUT {
                return false;
            }
            continue;
        }
        if r.abs_diff(last) >= p.edge_raw {
            return false;
        }
        (last, gap) = (r, 0);
        seen += 1;
        if seen >= WIDE_SURFACE {
            return true;
        }
    }
    false
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::labels::{ALIGNMENT, HEIGHT, PIXELS};

    fn params() -> (Calibration, ScanParams) {
        let c = Calibration::nyu_default();
        let p = ScanParams::new(&c, &Params::default());
        (c, p)
    }

    fn raw_at(c: &Calibration, z: f64) -> u16 {
        c.raw_from_depth(z).round() as u16
    }

    /// Classifies the middle one of three rows (above, row, below); labels and filled values.
    fn run_with_neighbours(above: &[u16], row: &[u16], below: &[u16]) -> (Vec<u8>, Vec<u16>) {
        let (_, p) = params();
        let mut labels = vec![ALIGNMENT; row.len()];
        let mut filled = vec![0; row.len()];
        classify_row(
            &p,
            row,
            &[NO_DEPTH; WIDTH],
            above,
            below,
            Range::at(2046),
            &mut labels,
            &mut filled,
        );
        (labels, filled)
    }

    /// A wall at 3 m with holes `[a, b)` (no depth).
    fn wall_with_holes(c: &Calibration, holes: &[(usize, usize)]) -> Vec<u16> {
        let mut row = vec![raw_at(c, 3.0); WIDTH];
        for &(a, b) in holes {
            row[a..b].fill(NO_DEPTH);
        }
        row
    }

    /// The hole runs of a row, pixel by pixel: the reference for the bitmap version.
    fn runs_by_hand(raw: &[u16]) -> Vec<(usize, usize)> {
        let mut runs = Vec::new();
        let mut start = None;
        for (u, &r) in raw.iter().chain([&0]).enumerate() {
            match (r == NO_DEPTH, start) {
                (true, None) => start = Some(u),
                (false, Some(s)) => {
                    runs.push((s, u));
                    start = None;
                }
                _ => {}
            }
        }
        runs
    }

    /// A frame (whole rows) of a wall at 3 m with a box at 1.2 m left of column 300, a hole
    /// `[300, 330)` in rows `hole_rows`, and an occluder at 0.8 m from column 330 on in rows
    /// `sb_rows`: where the hole runs on past the occluder, the wall bounds it.
    fn hole_beside(
        c: &Calibration,
        hole_rows: std::ops::Range<usize>,
        sb_rows: std::ops::Range<usize>,
    ) -> Vec<u16> {
        let (wall, sa, sb) = (raw_at(c, 3.0), raw_at(c, 1.2), raw_at(c, 0.8));
        let mut frame = vec![wall; PIXELS];
        for (v, row) in frame.chunks_exact_mut(WIDTH).enumerate() {
            row[200..300].fill(sa);
            if hole_rows.contains(&v) {
                row[300..330].fill(NO_DEPTH);
            }
            if sb_rows.contains(&v) {
                row[330..400].fill(sb);
            }
        }
        frame
    }

    #[test]
    fn a_hole_running_on_past_its_occluders_end_outruns_it_and_a_shadow_does_not() {
        // The hole in row 200, between the box and the occluder, as the hidden background reads
        // it; the occluder spans rows 100..260.
        let (c, p) = params();
        let outruns = |hole_rows: std::ops::Range<usize>, sb_rows: std::ops::Range<usize>| {
            let frame = hole_beside(&c, hole_rows, sb_rows);
            let v = 200;
            let raw = &frame[v * WIDTH..(v + 1) * WIDTH];
            let h = Run {
                start: 300,
                end: 330,
            };
            let rows = Rows {
                up: &frame[..v * WIDTH],
                down: &frame[(v + 1) * WIDTH..],
            };
            outruns_sb(&p, h, bound_right(raw, h.end), rows, &Walks::new())
        };
        // A shadow: the hole ends with its occluder (and a few rows after, below it: the
        // shadow of its lower face).
        assert!(!outruns(100..260, 100..260));
        assert!(!outruns(100..276, 100..260));
        // The same hole from the frame's top, or down to its bottom, past the occluder's ends:
        // something else the occluder happens to bound.
        assert!(outruns(0..260, 100..260));
        assert!(outruns(100..400, 100..260));
        // Past the occluder's bottom for fewer rows than a lower face's shadow may run on.
        assert!(!outruns(100..280, 100..260));
        // A hole that widens past the occluder's end over where it stood is another region.
        let mut frame = hole_beside(&c, 100..400, 100..260);
        for row in frame.chunks_exact_mut(WIDTH).skip(260) {
            row[300..360].fill(NO_DEPTH);
        }
        let raw = &frame[200 * WIDTH..201 * WIDTH];
        let rows = Rows {
            up: &frame[..200 * WIDTH],
            down: &frame[201 * WIDTH..],
        };
        let h = Run {
            start: 300,
            end: 330,
        };
        assert!(!outruns_sb(
            &p,
            h,
            bound_right(raw, 330),
            rows,
            &Walks::new()
        ));
    }

    #[test]
    fn first_pixel_below_kept_from_row_to_row_is_the_one_a_scan_finds() {
        // Columns of long holes (a shadow running down many rows) with single valid pixels and
        // runs of them between, read row by row from the top in a few columns each row, as the
        // hidden background reads them: the kept answer must be the column scanned afresh.
        use rand::{Rng, SeedableRng};
        let mut rng = rand::rngs::StdRng::seed_from_u64(7);
        let frame: Vec<u16> = (0..PIXELS)
            .map(|_| {
                if rng.random_bool(0.93) {
                    NO_DEPTH
                } else {
                    rng.random_range(400..1000)
                }
            })
            .collect();
        let walks = Walks::new();
        for v in 0..HEIGHT {
            let below = &frame[(v + 1) * WIDTH..];
            for _ in 0..40 {
                let c = rng.random_range(0..WIDTH);
                let scanned = below
                    .chunks_exact(WIDTH)
                    .map(|row| row[c])
                    .find(|&r| r != NO_DEPTH);
                assert_eq!(
                    walks.first_below(v, below, c),
                    scanned,
                    "row {v}, column {c}"
                );
            }
        }
    }

    #[test]
    fn hole_runs_are_found_across_word_boundaries_and_at_both_ends() {
        let rows = crate::classify::holes::test_rows();
        let mut out = [Run::default(); MAX_RUNS];
        for raw in &rows {
            let n = find_holes(raw, &mut out);
            let found: Vec<_> = out[..n].iter().map(|r| (r.start, r.end)).collect();
            assert_eq!(found, runs_by_hand(raw));
        }
    }

    #[test]
    fn hole_behind_a_nearer_object_wider_than_the_occluders_shadow_is_not_detached() {
        // Disparities (raw = 1092.5 − d / 0.1244): wall 10 px, an object at 28 px, then a 9 px
        // hole, 8 px of wall and a 4 px rod at 25 px. Measured from the wall, both equations fit
        // within their tolerances, but the rod's shadow is 4 px wide: cut by the object on its
        // left it could only show less, and a 9 px hole is something else.
        let raw = |d: f64| (1092.5 - d / 0.1244_f64).round() as u16;
        let mut row = vec![raw(10.0); WIDTH];
        row[50..59].fill(raw(28.0));
        row[59..68].fill(NO_DEPTH);
        row[76..80].fill(raw(25.0));
        let labels = run(&row);
        assert!(
            labels[59..68].iter().all(|&l| l != DETACHED),
            "{:?}",
            &labels[59..68]
        );
    }

    #[test]
    fn depthless_rod_gets_its_detached_shadow_and_the_depth_the_shift_implies() {
        // A black rod at 1 m before a wall at 3 m returns no depth: its 8 px hole at [300, 308)
        // and its shadow, the same 8 px shifted left by w = f·b·(1/1 − 1/3) = 29.1 px, plus 2 px
        // of the sensor's widening: [270, 279).
        let (c, _) = params();
        let row = wall_with_holes(&c, &[(270, 279), (300, 308)]);
        let (labels, filled) = run_with_neighbours(&row, &row, &row);
        assert!(
            labels[270..279].iter().all(|&l| l == DETACHED),
            "{:?}",
            &labels[265..312]
        );
        assert!(
            labels[300..308].iter().all(|&l| l == OTHER),
            "the rod itself is a hole"
        );
        // The rod is warped at the depth of a 29 px shift: 1/(1/3 + 29/(f·b)) ≈ 1.00 m.
        assert_placed_at(&c, &filled, 303, 1.0, 0.03);
        // The lit wall and the shadow stay at the wall's depth.
        assert_eq!(filled[275], raw_at(&c, 3.0));
    }

    /// The side wall of the slanted-wall tests below, turned away from the camera: 1/z(x) = 1/3 +
    /// β·(x − 400) over [300, 640), with f·b·β = 0.06 px of disparity per column (left of 300, a
    /// wall at 4.6 m), and where a projector ray past a rod at 0.8 m meets it: from column x_o on
    /// the rod, x_s = (x_o − f·b·(1/0.8 − α)) / (1 − f·b·β) with α = 1/3 − 400·β.
    fn side_wall(fb: f64) -> (impl Fn(usize) -> f64, impl Fn(f64) -> f64) {
        let beta = 0.06 / fb;
        let alpha = 1.0 / 3.0 - 400.0 * beta;
        (
            move |x: usize| alpha + beta * x.max(300) as f64,
            move |x_o: f64| (x_o - fb * (1.0 / 0.8 - alpha)) / (1.0 - fb * beta),
        )
    }

    #[test]
    fn depthless_rods_shadow_on_a_slanted_side_wall_is_detached() {
        // A side wall turned away from the camera: on a plane 1/z is affine in the column,
        // 1/z(x) = 1/3 + β·(x − 400) over [300, 640) (4.6 m at 300, 2.2 m at 639), with f·b·β =
        // 0.06 px of disparity per column; left of 300, a wall at 4.6 m. A black rod at 0.8 m
        // over [460, 470). A projector ray meets the rod at x_o and the wall at x_s where
        // x_s − f·b/z(x_s) = x_o − f·b/0.8, so x_s = (x_o − f·b·(1/0.8 − α)) / (1 − f·b·β) with
        // α = 1/3 − 400·β; f·b = 43.70: the shadow is [421.2, 431.9), 10.6 px, 38 px left of
        // the rod.
        let (c, _) = params();
        let fb = c.fb();
        let (inv_z, x_s) = side_wall(fb);
        let (from, to) = (x_s(460.0), x_s(470.0));
        assert!((from - 421.2).abs() < 0.05 && (to - 431.9).abs() < 0.05);
        let shadow = from.floor() as usize..to.ceil() as usize;
        let mut row: Vec<u16> = (0..WIDTH).map(|x| raw_at(&c, 1.0 / inv_z(x))).collect();
        row[shadow.clone()].fill(NO_DEPTH);
        row[460..470].fill(NO_DEPTH);
        // The wall's disparity at the shadow's left side and at the rod's right side lie 3 px
        // apart: no single background depth holds both.
        let (left, right) = (shadow.start - 1, 470);
        assert!(fb * (inv_z(right) - inv_z(left)) > 2.9);
        let (labels, filled) = run_with_neighbours(&row, &row, &row);
        assert_run(&labels, shadow, DETACHED);
        assert_run(&labels, 460..470, OTHER);
        // Placed by the shift from the background at the shadow: 1/(1/z + 38/(f·b)) ≈ 0.81 m.
        assert_placed_at(&c, &filled, 465, 0.8, 0.03);
        // The same holes with the lit gap between them not one plane (a pipe along the wall,
        // 1.8 px of disparity nearer over [440, 452), too little to be an occluder): no line
        // runs through it, and the shadow's sides stay 3 px apart.
        let mut bumped = row.clone();
        for (x, r) in bumped.iter_mut().enumerate().take(452).skip(440) {
            *r = raw_at(&c, 1.0 / (inv_z(x) + 1.8 / fb));
        }
        let (labels, _) = run_with_neighbours(&bumped, &bumped, &bumped);
        assert!(labels[422..431].iter().all(|&l| l != DETACHED));
        // A hole of 16 px there is wider than the rod's image stretched by the slant,
        // 10/(1 − 0.06) = 10.6 px, and the widening: a curved glossy surface's stripe, not the
        // shadow (on a level wall, holes up to the rod's width plus `attached_over_px` pair).
        let mut wide = row.clone();
        wide[416..432].fill(NO_DEPTH);
        let (labels, _) = run_with_neighbours(&wide, &wide, &wide);
        assert!(labels[416..432].iter().all(|&l| l != DETACHED));
    }

    #[test]
    fn depthless_rods_shadow_on_a_slanted_side_wall_a_few_pixels_from_it_is_detached() {
        // The side wall above (f·b·β = 0.06 px of disparity per column), a black rod at 0.8 m
        // over [460, 490): its shadow [x_s(460), x_s(490)) = [421.2, 453.1), a lit gap of 6.9
        // px before the rod, too narrow to draw the wall's line through; the wall past the rod
        // draws it with the gap. And a thinner rod over [630, 650), off the right border: its
        // shadow [602.1, 623.3), a 6.7 px gap; nothing past the rod, the wall before the shadow
        // draws the line.
        let (c, _) = params();
        let fb = c.fb();
        let (inv_z, x_s) = side_wall(fb);
        let wall: Vec<u16> = (0..WIDTH).map(|x| raw_at(&c, 1.0 / inv_z(x))).collect();
        for (rod, shadow) in [(460..490, (421.2, 453.1)), (630..WIDTH, (602.1, 623.3))] {
            let to = if rod.end == WIDTH {
                650.0
            } else {
                rod.end as f64
            };
            let (from, end) = (x_s(rod.start as f64), x_s(to));
            assert!((from - shadow.0).abs() < 0.05 && (end - shadow.1).abs() < 0.05);
            let hole = from.floor() as usize..end.ceil() as usize;
            assert!(rod.start - hole.end < MIN_SLANT_GAP);
            let mut row = wall.clone();
            row[hole.clone()].fill(NO_DEPTH);
            row[rod.clone()].fill(NO_DEPTH);
            let (labels, _) = run_with_neighbours(&row, &row, &row);
            assert_run(&labels, hole, DETACHED);
            assert_run(&labels, rod, OTHER);
        }
    }

    #[test]
    fn depthless_rod_before_a_nearer_boxs_edge_keeps_its_detached_shadow() {
        // A black rod at 1 m over [300, 317) before a wall at 3 m: its shadow 29.1 px left,
        // [271, 288), the lit wall between. A box at 2 m starts right of the rod (its own
        // attached shadow, 43.7·(1/2 − 1/3) = 7.3 px, hidden behind the rod): the rod's hole is
        // closed by the box, not the wall, and is too wide to be the box's shadow. The shift
        // comes from the left edges, 300 − 271 = 29 px: the rod is placed at about 1 m.
        let (c, _) = params();
        let mut row = wall_with_holes(&c, &[(271, 288), (300, 317)]);
        row[317..400].fill(raw_at(&c, 2.0));
        let (labels, filled) = run_with_neighbours(&row, &row, &row);
        assert_run(&labels, 271..288, DETACHED);
        assert_run(&labels, 300..317, OTHER);
        assert_placed_at(&c, &filled, 308, 1.0, 0.05);
        // A hole no wider than the box's own shadow there is that shadow, no occluder.
        let mut narrow = wall_with_holes(&c, &[(271, 278), (300, 307)]);
        narrow[307..400].fill(raw_at(&c, 2.0));
        let (labels, _) = run_with_neighbours(&narrow, &narrow, &narrow);
        assert!(labels[271..278].iter().all(|&l| l != DETACHED));
    }

    #[test]
    fn depthless_rods_shadow_partly_hidden_by_a_nearer_box_is_detached() {
        // The rod of the test above (8 px at [300, 308), 1 m, before a wall at 3 m) casts its
        // shadow over [270, 279) (29.1 px of shift, widening included), but a box at 0.8 m
        // stands over [262, 275): the camera sees only [275, 279) of the shadow, 4 px against
        // the rod's 8, its left end hidden behind the box. The shift still comes from the right
        // edges, 308 − 279 = 29 px: the rod is warped at about 1 m. Rod and box stand over the
        // row and the HIDDEN_PAIR_ROWS rows above and below it.
        let (c, _) = params();
        let mut row = wall_with_holes(&c, &[(275, 279), (300, 308)]);
        row[262..275].fill(raw_at(&c, 0.8));
        let around = row.repeat(HIDDEN_PAIR_ROWS);
        let (labels, filled) = run_with_neighbours(&around, &row, &around);
        assert_run(&labels, 275..279, DETACHED);
        assert_run(&labels, 300..308, OTHER);
        assert_placed_at(&c, &filled, 303, 1.0, 0.03);
        // The same over fewer rows is as likely a blob of dropouts beside the box.
        let fewer = row.repeat(HIDDEN_PAIR_ROWS - 1);
        let (labels, _) = run_with_neighbours(&fewer, &row, &around);
        assert_run(&labels, 275..279, OTHER);
        // A box of 2 px, [273, 275), could hide only those 2 of the 4 px the shadow lacks (the
        // wall left of it is lit where the shadow would be): two chance holes, not a pair.
        let mut row = wall_with_holes(&c, &[(275, 279), (300, 308)]);
        row[273..275].fill(raw_at(&c, 0.8));
        let around = row.repeat(HIDDEN_PAIR_ROWS);
        let (labels, filled) = run_with_neighbours(&around, &row, &around);
        assert_run(&labels, 275..279, OTHER);
        assert_eq!(filled[303], raw_at(&c, 3.0), "no rod placed");
    }

    #[test]
    fn hole_beside_a_nearer_box_is_no_hidden_shadow_of_a_measured_rods_shadow() {
        // A measured rod at 1 m over [300, 308) casts its detached shadow [270, 279) on the wall
        // at 3 m. A box at 0.8 m over [250, 262) has a 4 px dropout beside it, [262, 266). Read
        // as the hidden part of a depthless occluder's shadow, the dropout pairs with the rod's
        // shadow: 4 px against 9, shift 279 − 266 = 13 px, 5 px hidden behind the box's 12. But
        // that hole is the rod's shadow (eqs. 4–5 hold for it), not an occluder.
        let (c, _) = params();
        let mut row = wall_with_holes(&c, &[(262, 266), (270, 279)]);
        row[250..262].fill(raw_at(&c, 0.8));
        row[300..308].fill(raw_at(&c, 1.0));
        let around = row.repeat(HIDDEN_PAIR_ROWS);
        let (labels, filled) = run_with_neighbours(&around, &row, &around);
        assert_run(&labels, 270..279, DETACHED);
        assert_run(&labels, 262..266, OTHER);
        assert_eq!(
            filled[274],
            raw_at(&c, 3.0),
            "the rod's shadow stays on the wall"
        );
    }

    #[test]
    fn depthless_rod_running_off_the_right_border_still_gets_its_detached_shadow() {
        // A 15 px black rod at 1 m before a wall at 3 m stands at [630, 645): only 10 px of it
        // show. Its shadow is all of it shifted left by w = 29.1 px, plus 1 px of widening:
        // [600, 616), with the lit wall [616, 630) between.
        let (c, _) = params();
        let row = wall_with_holes(&c, &[(600, 616), (630, WIDTH)]);
        let (labels, filled) = run_with_neighbours(&row, &row, &row);
        assert_run(&labels, 600..616, DETACHED);
        assert_run(&labels, 630..WIDTH, OTHER); // the rod itself
                                                // The shift comes from the left edges (30 px, the widening included): about 1 m.
        assert_placed_at(&c, &filled, 635, 1.0, 0.05);
        // A visible part wider than the shadow is no occluder of it.
        let row = wall_with_holes(&c, &[(600, 608), (620, WIDTH)]);
        let (labels, _) = run_with_neighbours(&row, &row, &row);
        assert_run(&labels, 600..608, OTHER);
        // A real sensor's dead band (8 px at the border in every row, as on the NYU frame) with
        // an 8 px dropout 64 px left of it: a rod would have to be 0.5 m away and 8 px wide for
        // that; the lit gap is far wider than the shadow, so no pair.
        let row = wall_with_holes(&c, &[(560, 568), (632, WIDTH)]);
        let (labels, _) = run_with_neighbours(&row, &row, &row);
        assert_run(&labels, 560..568, OTHER);
    }

    #[test]
    fn depthless_rods_shadow_cut_by_the_left_border_is_detached() {
        // A black rod 11 px wide at about 1.3 m before a wall at 3 m stands at [15, 26); its
        // shadow, shifted left by their right edges' distance, 17 px, would span [-2, 9): the
        // border cuts it to [0, 9), with the lit wall [9, 15) between. The rod is warped at the
        // depth of that shift: 1 / (1/3 + 17/(f·b)) = 1.38 m.
        let (c, _) = params();
        let row = wall_with_holes(&c, &[(0, 9), (15, 26)]);
        let (labels, filled) = run_with_neighbours(&row, &row, &row);
        assert_run(&labels, 0..9, DETACHED);
        assert_run(&labels, 15..26, OTHER); // the rod itself
        assert_placed_at(&c, &filled, 20, 1.38, 0.05);
        // A hole whose shifted self would not reach the border casts no such shadow: a 4 px
        // dropout [30, 34) is 25 px right of the hole's end, and shifted by that it covers
        // [5, 9), which leaves [0, 5) unexplained (more than the widening).
        let row = wall_with_holes(&c, &[(0, 9), (30, 34)]);
        let (labels, _) = run_with_neighbours(&row, &row, &row);
        assert_run(&labels, 0..9, OTHER);
    }

    #[test]
    fn hole_between_two_rods_before_a_wall_beyond_range_is_no_shadow_of_the_border() {
        // Two rods before a wall beyond range (all holes): one at 2.43 m over [512, 520), one
        // at 2.65 m over [590, 594): raw 948 and 960, f·b·(1/2.43 − 1/2.65) = 1.5 px apart.
        // Read as a depthless occluder's detached shadow, [520, 590) would pair with the hole
        // running off the border, [594, 640): shift 74 px, lit gap 4 px, "background" within
        // 2 px on all sides. But the lit gap is not the surface the shadow would lie on (the
        // rods are 1.5 px apart, a step more than the shadow's own surface allows): OTHER.
        let (c, _) = params();
        let (near, far) = (raw_at(&c, 2.43), raw_at(&c, 2.65));
        assert_eq!((near, far), (948, 960));
        let mut row = vec![NO_DEPTH; WIDTH];
        row[512..520].fill(near);
        row[590..594].fill(far);
        let (labels, _) = run_with_neighbours(&row, &row, &row);
        assert_run(&labels, 520..590, OTHER);
        assert_run(&labels, 594..WIDTH, OTHER);
    }

    #[test]
    fn depthless_rod_behind_a_swallowed_lit_gap_is_placed_at_its_depth() {
        // A black rod 8 px wide whose shift is w = 10 px leaves a 2 px lit gap, [279, 281),
        // between its shadow [270, 279) and itself [281, 289): the hole merges the gap as noise.
        // Split at the island, the shadow is detached, and the rod is warped at the depth of a
        // 10 px shift, 1/(1/3 + 10/(f·b)) = 1.78 m, not at the wall's 3 m.
        let (c, _) = params();
        let row = wall_with_holes(&c, &[(270, 279), (281, 289)]);
        let (labels, filled) = run_with_neighbours(&row, &row, &row);
        assert_run(&labels, 270..279, DETACHED);
        assert_placed_at(&c, &filled, 285, 1.78, 0.05);
        assert_eq!(filled[279], row[279], "the lit gap keeps its depth");
    }

    #[test]
    fn depthless_pair_needs_the_rows_above_and_below() {
        // The same pair in one row only (chance dropouts): nothing is a shadow.
        let (c, _) = params();
        let row = wall_with_holes(&c, &[(270, 279), (300, 308)]);
        let plain = wall_with_holes(&c, &[]);
        for (above, below) in [(&plain, &row), (&row, &plain)] {
            let (labels, _) = run_with_neighbours(above, &row, below);
            assert!(labels[270..308].iter().all(|&l| l != DETACHED));
        }
        // Holes of different widths are no occluder-and-shadow pair either.
        let row = wall_with_holes(&c, &[(270, 290), (300, 308)]);
        let (labels, _) = run_with_neighbours(&row, &row, &row);
        assert!(labels[270..308].iter().all(|&l| l != DETACHED));
        // Nor a shift beyond the sensor's range: an occluder nearer than 0.5 m.
        let row = wall_with_holes(&c, &[(200, 208), (300, 308)]);
        let (labels, _) = run_with_neighbours(&row, &row, &row);
        assert!(labels[200..308].iter().all(|&l| l != DETACHED));
    }

    #[test]
    fn depthless_pair_places_no_occluder_nearer_than_the_sensors_range() {
        // A black rod 8 px wide before a wall at 3 m, its shadow the same 8 px (plus 2 px of
        // widening) shifted left by w = f·b·(1/z − 1/3) (eq. 4–5 for an occluder without
        // depth). At 0.55 m (w = 65 px) the pair is the rod and its detached shadow; at 0.45 m
        // (w = 83 px) the rod would stand nearer than the Kinect measures anything (0.5 m): two
        // holes that far apart are no such pair.
        let (c, _) = params();
        for (z, paired) in [(0.55, true), (0.45, false)] {
            let w = (c.fb() * (1.0 / z - 1.0 / 3.0)).round() as usize;
            let shadow = (400 - w - 2, 400 - w + 8);
            let row = wall_with_holes(&c, &[shadow, (400, 408)]);
            let (labels, _) = run_with_neighbours(&row, &row, &row);
            let detached = labels[shadow.0..shadow.1].iter().all(|&l| l == DETACHED);
            assert_eq!(detached, paired, "rod at {z} m, shift {w} px");
        }
    }

    #[test]
    fn attached_shadow_partly_hidden_by_a_nearer_rod() {
        // Wall at 3 m, box at 1 m from column 400: its shadow on the wall is f·b·(1/1 − 1/3) =
        // 29.1 px wide, [371, 400). A rod at 0.8 m over [380, 386) hides the left part of it (and
        // casts its own 40 px shadow left of it). The visible part [386, 400) lies between a
        // nearer rod and the box: eq. (3) with Sa (the rod) gives nothing; with the wall seen
        // above those columns it is the box's attached shadow.
        let (c, p) = params();
        let mut row = wall_with_holes(&c, &[(340, 380), (386, 400)]);
        row[380..386].fill(raw_at(&c, 0.8));
        row[400..500].fill(raw_at(&c, 1.0));
        let classify = |memory: &[u16]| {
            let (mut labels, mut filled) = (vec![VALID; WIDTH], vec![0; WIDTH]);
            classify_row(
                &p,
                &row,
                memory,
                &[],
                &[],
                Range::at(2046),
                &mut labels,
                &mut filled,
            );
            (labels, filled)
        };
        let (labels, filled) = classify(&wall_with_holes(&c, &[]));
        assert!(
            labels[386..400].iter().all(|&l| l == ATTACHED),
            "{:?}",
            &labels[380..402]
        );
        assert_eq!(filled[390], raw_at(&c, 3.0), "the shadow lies on the wall");
        // Nothing known above (a shadow running from the frame's top): the wall left of the
        // rod, past the rod's own shadow, is what continues behind it, the same answer.
        let (labels, _) = classify(&[NO_DEPTH; WIDTH]);
        assert!(labels[386..400].iter().all(|&l| l == ATTACHED));
        // The box itself above those columns (the hole is under its overhang): no shadow.
        let mut memory = wall_with_holes(&c, &[]);
        memory[380..400].fill(raw_at(&c, 1.0));
        let (labels, _) = classify(&memory);
        assert!(labels[386..400].iter().all(|&l| l == OTHER));
    }

    #[test]
    fn chained_depthless_pairs_are_left_alone() {
        // Two black rods whose shadows interleave (shadow, shadow, rod, rod): which shadow goes
        // with which rod is ambiguous in depth alone, so none is labelled (precision first).
        let (c, _) = params();
        let row = wall_with_holes(&c, &[(262, 270), (274, 282), (291, 299), (303, 311)]);
        let (labels, _) = run_with_neighbours(&row, &row, &row);
        assert!(
            labels[255..315].iter().all(|&l| l != DETACHED),
            "{:?}",
            &labels[255..315]
        );
    }

    /// Asserts that `labels[at]` are all `code`, showing a few pixels around them if not.
    /// The hole pixel `u` is warped at `z` metres (within `tol`): where its occluder stands.
    fn assert_placed_at(c: &Calibration, filled: &[u16], u: usize, z: f64, tol: f64) {
        let at = c.depth_m(filled[u]).unwrap();
        assert!((at - z).abs() < tol, "rod placed at {at:.3} m, not {z} m");
    }

    fn assert_run(labels: &[u8], at: std::ops::Range<usize>, code: u8) {
        let around = at.start.saturating_sub(5)..(at.end + 5).min(labels.len());
        assert!(
            labels[at.clone()].iter().all(|&l| l == code),
            "{at:?} not all {code}: {:?} at {around:?}",
            &labels[around.clone()]
        );
    }

    fn run(row: &[u16]) -> Vec<u8> {
        let (labels, filled) = run_with_neighbours(&[], row, &[]);
        assert!(
            filled.iter().all(|&f| f < NO_DEPTH),
            "every hole gets an assumed depth"
        );
        labels
    }

    /// Box edge at 1 m before a wall at 3 m: hand-computed width f·b·(1/1 − 1/3) px.
    fn box_row(extra: usize) -> (Vec<u16>, usize, usize) {
        let c = Calibration::nyu_default();
        let w = (c.fb() * (1.0 - 1.0 / 3.0)).round() as usize; // 582.62·0.075·2/3 = 29.1 → 29
        assert_eq!(w, 29);
        let mut row = vec![raw_at(&c, 3.0); WIDTH];
        let edge = 300;
        for r in &mut row[edge..500] {
            *r = raw_at(&c, 1.0);
        }
        let start = edge - w - extra;
        for r in &mut row[start..edge] {
            *r = NO_DEPTH;
        }
        (row, start, edge)
    }

    #[test]
    fn the_frame_tells_how_much_the_sensor_widens_a_shadows_left_end() {
        // The box row (a 29.1 px shadow by hand, eq. (3) from the raw values 29.1 px too) with
        // its shadow `extra` px wider, in every other row of a frame of wall: half the excess is
        // the left end's, the other half the right end's (a correlation window is symmetric).
        let (c, p) = params();
        let wall = raw_at(&c, 3.0);
        for (extra, rows, widen) in [(0, 40, 0.0), (2, 40, 1.0), (3, 40, 1.5), (3, 7, 0.0)] {
            let (row, _, _) = box_row(extra);
            let mut raw = vec![wall; PIXELS];
            for v in (100..100 + 2 * rows).step_by(2) {
                raw[v * WIDTH..(v + 1) * WIDTH].copy_from_slice(&row);
            }
            let (mut labels, mut filled) = (vec![0u8; PIXELS], vec![0u16; PIXELS]);
            let facts = classify_frame(&p, &raw, &mut labels, &mut filled);
            assert_eq!(labels[100 * WIDTH + 299], ATTACHED, "extra {extra}");
            // Half-pixel bins of the excess (eq. (3) here is 29.1 px, the hole an integer): a
            // quarter pixel either way; too few holes (7 rows) to tell: none.
            assert!(
                (facts.left_widening - widen).abs() <= 0.25,
                "extra {extra}, {rows} rows: {}",
                facts.left_widening
            );
        }
    }

    #[test]
    fn a_sensor_that_widens_more_than_a_kinect_gets_more_room() {
        // The box row (eq. (3): 29.1 px) in 40 rows with its shadow `typical` px wider, and in 4
        // more rows 11 px wider: past `attached_over_px` (8). On a Kinect (typical 2 px, SPEC §1's
        // 2.3 px on average) such a hole is a shadow on a surface that is a hole anyway, OTHER.
        // A sensor whose shadows are 4 to 5 px wider (a larger correlation window) makes such
        // rows too: the frame's median excess, about 4.4 px, gives 3·(4.4 − 2.5) ≈ 5.7 px more
        // room; at 3 to 4 px (median 3.4, 2.7 px more) 11 is still too wide.
        let (c, p) = params();
        let wall = raw_at(&c, 3.0);
        for (typical, wide_attached) in [(2, false), (4, false), (5, true)] {
            let mut raw = vec![wall; PIXELS];
            for k in 0..44 {
                let extra = if k < 40 { typical - k % 2 } else { 11 };
                let v = 100 + 2 * k;
                raw[v * WIDTH..(v + 1) * WIDTH].copy_from_slice(&box_row(extra).0);
            }
            let (mut labels, mut filled) = (vec![0u8; PIXELS], vec![0u16; PIXELS]);
            classify_frame(&p, &raw, &mut labels, &mut filled);
            assert_eq!(labels[100 * WIDTH + 299], ATTACHED, "typical {typical}");
            let wide = labels[(100 + 2 * 42) * WIDTH + 299];
            let want = if wide_attached { ATTACHED } else { OTHER };
            assert_eq!(wide, want, "typical {typical}");
        }
    }

    #[test]
    fn one_row_with_the_raw_row_above_and_no_labels_of_it_is_classified() {
        // `classify_row` has no labels of the row above: a box at 1 m before a wall at 3 m,
        // the same in the row above, makes the attached shadow [270.9, 300) (43.67·(1 − 1/3) =
        // 29.1 px). It once panicked reading the row above's labels.
        let c = Calibration::nyu_default();
        let mut row = wall_with_holes(&c, &[(271, 300)]);
        row[300..400].fill(raw_at(&c, 1.0));
        let (labels, _) = run_with_neighbours(&row, &row, &[]);
        assert!(
            labels[271..300].iter().all(|&l| l == ATTACHED),
            "{:?}",
            &labels[271..300]
        );
    }

    #[test]
    fn attached_shadow_of_box_before_wall() {
        for extra in [0, 2, 6] {
            let (row, start, edge) = box_row(extra);
            let l = run(&row);
            assert!(
                l[start..edge].iter().all(|&x| x == ATTACHED),
                "extra {extra}: {:?}",
                &l[start..edge]
            );
            assert!(l[..start].iter().chain(&l[edge..]).all(|&x| x == VALID));
        }
    }

    #[test]
    fn sub_pixel_step_shows_its_attached_shadow_through_the_widening() {
        // A box at 2.20 m before a wall at 2.30 m: w = f·b·(1/2.20 − 1/2.30) = 0.86 px, under
        // `min_step`, yet the sensor's widening makes a 3 px hole left of the box's edge.
        let c = Calibration::nyu_default();
        let w = c.fb() * (1.0 / 2.20 - 1.0 / 2.30);
        assert!((0.85..0.87).contains(&w), "{w}");
        let mut row = vec![raw_at(&c, 2.30); WIDTH];
        row[300..500].fill(raw_at(&c, 2.20));
        row[297..300].fill(NO_DEPTH);
        let l = run(&row);
        assert_eq!(&l[297..300], &[ATTACHED; 3]);
        // The same hole with the wall on both sides is a dropout, not a shadow.
        let mut flat = vec![raw_at(&c, 2.30); WIDTH];
        flat[297..300].fill(NO_DEPTH);
        assert_eq!(&run(&flat)[297..300], &[OTHER; 3]);
        // A dropout [300, 304) on that wall whose bounds are noisy: the edge pixels 2 raw units
        // farther and nearer (4 units apart: 0.498 px of disparity), a sample beside each 3
        // units off. The extremes of the samples differ by 0.62 px and the slope read left of
        // the hole extrapolates to 1.3 px, but the edges are under half a step apart: OTHER.
        assert!(c.px_per_raw() * 4.0 < 0.5);
        let r = raw_at(&c, 2.30);
        let mut noisy = vec![r; WIDTH];
        noisy[295] = r - 3;
        noisy[299] = r + 2;
        noisy[300..304].fill(NO_DEPTH);
        noisy[304] = r - 2;
        noisy[305] = r - 3;
        assert_eq!(&run(&noisy)[300..304], &[OTHER; 4]);
    }

    #[test]
    fn widening_that_closes_a_thin_occluders_gap_leaves_its_shadow_detached() {
        // Rod at 1 m before a wall at 3 m: shift w = f·b·(1 − 1/3) = 29.1 px. A 27 px rod at
        // [300, 327) casts its shadow on [271, 298); the 2 px lit gap [298, 300) is swallowed by
        // the sensor's widening, so the hole [269, 300) touches the rod. The rod is narrower
        // than w: the projector saw the wall there, so detached (eqs. 4–5), not attached.
        let (c, _) = params();
        let mut row = vec![raw_at(&c, 3.0); WIDTH];
        row[300..327].fill(raw_at(&c, 1.0));
        row[269..300].fill(NO_DEPTH);
        assert_run(&run(&row), 269..300, DETACHED);
        // A 40 px box (wider than w) with the same hole: attached.
        row[300..340].fill(raw_at(&c, 1.0));
        assert_run(&run(&row), 269..300, ATTACHED);
    }

    #[test]
    fn narrow_hole_beside_a_thin_rod_is_not_its_shadow() {
        // A 6 px rod at 1 m before a wall at 3 m (shift w = 29.1 px) casts its detached shadow
        // on [271, 277). A 5 px hole right beside the rod, [295, 300), is lit wall by that
        // geometry (a black rod there, say): not the rod's shadow, whose hole would span the
        // whole shift if the widening had swallowed the lit gap.
        let (c, _) = params();
        let mut row = vec![raw_at(&c, 3.0); WIDTH];
        row[300..306].fill(raw_at(&c, 1.0));
        row[271..277].fill(NO_DEPTH);
        row[295..300].fill(NO_DEPTH);
        let labels = run(&row);
        assert_run(&labels, 295..300, OTHER);
        assert_run(&labels, 271..277, DETACHED);
    }

    #[test]
    fn too_wide_hole_is_other() {
        // 29 px predicted, 69 px observed: the shadow falls on something unmeasurable.
        let (row, start, edge) = box_row(40);
        assert!(run(&row)[start..edge].iter().all(|&x| x == OTHER));
    }

    #[test]
    fn hole_on_flat_wall_is_other() {
        let c = Calibration::nyu_default();
        let mut row = vec![raw_at(&c, 2.0); WIDTH];
        for r in &mut row[100..110] {
            *r = NO_DEPTH;
        }
        let l = run(&row);
        assert!(l[100..110].iter().all(|&x| x == OTHER));
    }

    #[test]
    fn hole_right_of_object_is_other() {
        // Projector shadows never lie right of their occluder.
        let c = Calibration::nyu_default();
        let mut row = vec![raw_at(&c, 3.0); WIDTH];
        for r in &mut row[100..200] {
            *r = raw_at(&c, 1.0);
        }
        for r in &mut row[200..220] {
            *r = NO_DEPTH;
        }
        assert!(run(&row)[200..220].iter().all(|&x| x == OTHER));
    }

    #[test]
    fn detached_shadow_of_thin_rod() {
        // Rod 6 px wide at 1 m before a wall at 3 m: w = 29 px > 6 px, so its shadow [Fa−w, Fb−w]
        // is detached, with 23 px of lit wall between shadow and rod.
        let c = Calibration::nyu_default();
        let w = 29;
        let mut row = vec![raw_at(&c, 3.0); WIDTH];
        let (fa, fb) = (300, 305);
        for r in &mut row[fa..=fb] {
            *r = raw_at(&c, 1.0);
        }
        for r in &mut row[fa - w..=fb - w] {
            *r = NO_DEPTH;
        }
        let l = run(&row);
        assert!(
            l[fa - w..=fb - w].iter().all(|&x| x == DETACHED),
            "{:?}",
            &l[fa - w - 1..=fb - w + 1]
        );
    }

    #[test]
    fn glossy_rod_measured_at_its_two_limbs_casts_its_whole_detached_shadow() {
        // A rod 24 px wide at 0.6 m before a wall at 3 m, glossy: the sensor measures its two
        // limbs (4 and 10 px) and nothing between. By hand its shadow is shifted w = f·b·(1/0.6 −
        // 1/3) = 58 px left, [fa − 58, fb − 58], lit wall between it and the rod. Read from the
        // left limb and the rod's hole past it, eq. (5) ends the shadow 10 px short of the
        // hole's end (the rest was OTHER); the limb past that hole, at the same depth, is the
        // same rod.
        let c = Calibration::nyu_default();
        let w = (c.fb() * (1.0 / 0.6 - 1.0 / 3.0)).round() as usize;
        assert_eq!(w, 58);
        let mut row = vec![raw_at(&c, 3.0); WIDTH];
        let (fa, fb) = (300, 323);
        row[fa..=fb].fill(raw_at(&c, 0.6));
        row[fa + 4..=fb - 10].fill(NO_DEPTH);
        row[fa - w..=fb - w].fill(NO_DEPTH);
        let l = run(&row);
        assert_run(&l, fa - w..fb - w + 1, DETACHED);
    }

    #[test]
    fn detached_shadow_merged_with_a_black_poster_right_of_it_keeps_its_width() {
        // A 12 px rod at 1 m before a wall at 3 m: by hand its shadow is shifted w = f·b·(1/1 −
        // 1/3) = 29 px left, [fa − 29, fb − 29]. A black poster on the wall, 8 px right of the
        // shadow's end, returns no depth either: one hole, too wide for eq. (5). Eq. (4) still
        // places the shadow; the poster beyond it, past the widening's slack, is OTHER.
        let c = Calibration::nyu_default();
        let w = 29;
        let mut row = vec![raw_at(&c, 3.0); WIDTH];
        let (fa, fb) = (300, 311);
        row[fa..=fb].fill(raw_at(&c, 1.0));
        let poster_end = fb - w + 1 + 8;
        row[fa - w..poster_end].fill(NO_DEPTH);
        let l = run(&row);
        assert_run(&l, fa - w..fb - w + 1, DETACHED);
        assert_run(&l, fb - w + 1 + 3..poster_end, OTHER);
    }

    #[test]
    fn rods_shadow_on_a_boxs_face_beside_its_thin_side_is_detached() {
        // A box's face at 1.36 m, its side showing as a 10 px strip at 1.48 m left of the hole,
        // a wall at 4 m left of that; a 12 px rod at 0.6 m right of the box. By hand the rod's
        // shadow on the face is shifted f·b·(1/0.6 − 1/1.36) = 40.7 px left: the hole
        // [553, 566). Sb's shadow on Sa would be 2.6 px; on the wall that the thin Sa could
        // hide, 21 px, which the hole also fits. Eqs. (4)–(5) fit the rod: detached.
        let c = Calibration::nyu_default();
        let mut row = vec![raw_at(&c, 4.0); WIDTH];
        row[543..553].fill(raw_at(&c, 1.48));
        row[553..566].fill(NO_DEPTH);
        row[566..594].fill(raw_at(&c, 1.36));
        row[594..606].fill(raw_at(&c, 0.6));
        assert_run(&run(&row), 553..566, DETACHED);
    }

    #[test]
    fn rods_shadow_two_pixels_short_of_the_rod_is_detached_though_sb_reads_the_rod() {
        // A row of this project's simulator (holdout scenes with depth noise σ 2, scene 7, row
        // 285 from column 483): a wall at about raw 1008 (4.16 m), a 20 px hole, the wall lit
        // for two pixels, an 18 px rod at about raw 836 (1.37 m). By hand the rod's shift is
        // (1008 − 836)/8 = 21.5 px: the hole is its detached shadow, the two pixels its lit gap
        // (the simulator's ground truth says so). Sb, read over three pixels, takes the rod's
        // first: eq. (3) fits the hole as the rod's attached shadow, and the rod's width ties
        // with its shift. The gap shows in this row, and eqs. (4)-(5) fit the rod past it.
        const N: u16 = NO_DEPTH;
        let recorded = [
            1013, 1006, 1008, 1007, 1008, 1010, 1007, 1007, 1011, 1006, 1012, 1008, 1008, 1009,
            1007, 1012, 1012, 1010, 1010, N, N, N, N, N, N, N, N, N, N, N, N, N, N, N, N, N, N, N,
            N, 1007, 1006, 839, 842, 835, 835, 836, 836, 836, 835, 838, 836, 837, 838, 833, 833,
            837, 837, 833, 835, 1010, 1011, 1008, 1005, 1011, 1012, 1012, 1005, 1010, 1009, 1009,
        ];
        let mut row = vec![1008u16; WIDTH];
        row[483..483 + recorded.len()].copy_from_slice(&recorded);
        assert_run(&run(&row), 502..522, DETACHED);
    }

    #[test]
    fn lit_gap_of_a_pixel_shows_a_shadow_detached_where_the_rods_width_cannot() {
        // A panel at 3.7 m whose edge lies inside the hole, a wall at 4.2 m behind it, and a rod
        // at 1.25 m whose left part shows at [290, 299); its right part is hidden (a black strip
        // over it, no depth) up to the wall at 310, so its width cannot be read. By hand its
        // shift is w = f·b·(1/1.25 − 1/3.7) = 23.1 px against the panel, 24.6 px against the
        // wall: its shadow [267, 288) ends a pixel before the wall lit at 289, 1.4 px of
        // disparity behind the panel. Read over three pixels Sb is the rod, and eq. (3) fits
        // the 22 px hole as its attached shadow; but the projector lit the wall at 289, between
        // shadow and rod: eqs. (4)-(5), detached.
        let (c, _) = params();
        let mut row = vec![raw_at(&c, 4.2); WIDTH];
        row[..267].fill(raw_at(&c, 3.7));
        row[267..289].fill(NO_DEPTH);
        row[290..299].fill(raw_at(&c, 1.25));
        row[299..310].fill(NO_DEPTH);
        let (labels, _) = run_with_neighbours(&row, &row, &row);
        assert_run(&labels, 267..289, DETACHED);
    }

    #[test]
    fn detached_shadow_whose_occluder_stands_beyond_a_nearer_box() {
        // A 6 px rod at 0.7 m, [360, 366), and an 8 px box at 2 m, [330, 338), before a wall at
        // 3 m. By hand: the rod's shift is f·b·(1/0.7 − 1/3) = 47.8 px, so its shadow [312, 318]
        // is detached; the box's is 7.3 px, as wide as the box: attached, [323, 330). The
        // projector's rays to the rod's shadow cross the box's depth at 319–325, left of the box,
        // so the box is not its occluder though it stands between shadow and rod.
        let (c, _) = params();
        let mut row = vec![raw_at(&c, 3.0); WIDTH];
        row[312..319].fill(NO_DEPTH);
        row[323..330].fill(NO_DEPTH);
        row[330..338].fill(raw_at(&c, 2.0));
        row[360..366].fill(raw_at(&c, 0.7));
        let l = run(&row);
        assert_run(&l, 312..319, DETACHED);
        assert_run(&l, 323..330, ATTACHED);
    }

    #[test]
    fn noisy_wall_left_of_a_shadow_is_one_surface_with_its_lit_gap() {
        // A 12 px rod at 1.5 m, [300, 312), before a wall at 3 m: shift 14.6 px, shadow
        // [286, 298), lit gap [298, 300), of which the widening swallows 298: hole [286, 299),
        // wall at 299, then the rod. The wall left of the hole is noisy: 1 unit farther at 285,
        // 2 nearer at 281. One sample each way gives a slope of 0.093 px/px, which over the
        // 14 px to 299 predicts the wall 1.3 px nearer than 299 shows, and the hole becomes an
        // attached shadow of the lit pixel. Pairs of samples halve the noise (0.65 px, under a
        // step): the wall goes on across the hole, and the rod's shadow is detached.
        let (c, _) = params();
        let r = raw_at(&c, 3.0);
        let mut row = vec![r; WIDTH];
        row[281] = r - 2;
        row[285] = r + 1;
        row[286..299].fill(NO_DEPTH);
        row[300..312].fill(raw_at(&c, 1.5));
        assert_run(&run(&row), 286..299, DETACHED);
    }

    #[test]
    fn detached_shadow_of_a_rod_with_a_farther_box_touching_its_right_side() {
        // A 10 px rod at 1.5 m, [300, 310), before a wall at 3 m: shift f·b·(1/1.5 − 1/3) =
        // 14.6 px, so its shadow [286, 296) is detached. A box at 2 m touches the rod's right
        // side, [310, 400) (its own shadow, 7.3 px, falls behind the rod). The box is nearer
        // than the wall too, but it is not the rod: eq. (5) measures the rod's right edge, 309,
        // with or without a mixed pixel between the two, and a stray value inside the rod is no
        // such edge.
        let (c, _) = params();
        let w = c.fb() * (1.0 / 1.5 - 1.0 / 3.0);
        assert!((14.5..14.7).contains(&w));
        for (at, z) in [(None, 0.0), (Some(310), 1.75), (Some(305), 2.2)] {
            let mut row = vec![raw_at(&c, 3.0); WIDTH];
            row[286..296].fill(NO_DEPTH);
            row[300..310].fill(raw_at(&c, 1.5));
            row[310..400].fill(raw_at(&c, 2.0));
            if let Some(at) = at {
                row[at] = raw_at(&c, z);
            }
            assert_run(&run(&row), 286..296, DETACHED);
        }
    }

    #[test]
    fn edge_shadow_and_rod_shadow_a_lit_pixel_apart_are_read_apart() {
        // A partition at 2.3 m from column 400 before a wall at 3.4 m: its edge's attached
        // shadow is f·b·(1/2.3 − 1/3.4) = 6 px wide. A rod 24 px wide at 0.64 m stands before
        // the partition: its shadow there lies f·b·(1/0.64 − 1/2.3) = 49 px left of it, 4 px
        // past the partition's edge. A sensor that widens holes by 4 px on the left (3 into the
        // lit gap) leaves one lit pixel between the two, and the holes merge over it: the whole
        // is too wide for eq. (3), and its left end too far from the rod for eq. (4).
        let c = Calibration::nyu_default();
        let w1 = (c.fb() * (1.0 / 2.3 - 1.0 / 3.4)).round() as usize; // 43.70·0.1407 = 6.15
        let w2 = (c.fb() * (1.0 / 0.64 - 1.0 / 2.3)).round() as usize; // 43.70·1.1277 = 49.3
        assert_eq!((w1, w2), (6, 49));
        let (edge, gap, widen) = (400, 4, 3);
        let (fa, fb) = (edge + gap + w2, edge + gap + w2 + 23);
        let mut row = vec![raw_at(&c, 3.4); WIDTH];
        row[edge..].fill(raw_at(&c, 2.3));
        row[fa..=fb].fill(raw_at(&c, 0.64));
        let attached = edge - w1 - widen - 1..edge;
        let detached = fa - w2 - widen..fb - w2 + 1;
        row[attached.clone()].fill(NO_DEPTH);
        row[detached.clone()].fill(NO_DEPTH);
        assert_eq!(detached.start, edge + 1, "one lit pixel between the holes");
        let l = run(&row);
        assert_run(&l, attached, ATTACHED);
        assert_run(&l, detached, DETACHED);
    }

    #[test]
    fn rod_whose_right_part_is_a_hole_still_casts_its_detached_shadow() {
        // A rod 14 px wide at 1 m before a wall at 3 m: w = 29 px, its shadow [Fa−w, Fb−w]
        // detached. Its right 10 px return no depth (black tape), and so does a black panel
        // right of it: the rod shows as [Fa, Fa+3] only, and eq. (5) read at Fa+3 puts the
        // shadow's end 10 px short. The hole may hide the rod's true right edge.
        let c = Calibration::nyu_default();
        let w = 29;
        let (fa, fb) = (300, 313);
        let mut row = vec![raw_at(&c, 3.0); WIDTH];
        row[fa..=fb].fill(raw_at(&c, 1.0));
        row[fa - w..=fb - w].fill(NO_DEPTH);
        row[fa + 4..fb + 30].fill(NO_DEPTH);
        assert_run(&run(&row), fa - w..fb - w + 1, DETACHED);
    }

    #[test]
    fn shadow_of_a_rod_hidden_behind_the_measured_one_does_not_hide_its_shadow() {
        // A rod 18 px wide at 0.6 m before a wall at 3 m: w = f·b·(1/0.6 − 1/3) = 58 px, so its
        // shadow [Fa−w, Fb−w] is detached with 40 px of wall before the rod. A second rod the
        // first hides from the camera casts a 20 px hole ending on the first rod: too wide for
        // a dropout, yet the first rod's shadow is still its own (two leaning rods).
        let c = Calibration::nyu_default();
        let w = (c.fb() * (1.0 / 0.6 - 1.0 / 3.0)).round() as usize; // 43.70·1.333 = 58.3
        assert_eq!(w, 58);
        let (fa, fb) = (528, 545);
        let mut row = vec![raw_at(&c, 3.0); WIDTH];
        row[fa..=fb].fill(raw_at(&c, 0.6));
        row[fa - w..=fb - w].fill(NO_DEPTH);
        row[fa - 20..fa].fill(NO_DEPTH);
        let l = run(&row);
        assert_run(&l, fa - w..fb - w + 1, DETACHED);
        // Nothing measured tells what casts the second hole.
        assert_run(&l, fa - 20..fa, OTHER);
    }

    #[test]
    fn dropout_in_the_lit_gap_does_not_hide_the_rod_from_its_shadow() {
        // A rod 14 px wide at 1 m before a wall at 3 m: w = 29 px, so its shadow [Fa−w, Fb−w] is
        // detached with 15 px of lit wall before the rod. One or two 3 px dropouts there (too
        // narrow to be a depthless rod casting a 14 px shadow) do not end the search for the rod.
        let c = Calibration::nyu_default();
        let w = 29;
        let (fa, fb) = (300, 313);
        for dropouts in [&[288][..], &[288, 294]] {
            let mut row = vec![raw_at(&c, 3.0); WIDTH];
            row[fa..=fb].fill(raw_at(&c, 1.0));
            row[fa - w..=fb - w].fill(NO_DEPTH);
            for &at in dropouts {
                row[at..at + 3].fill(NO_DEPTH);
            }
            let l = run(&row);
            assert!(
                l[fa - w..=fb - w].iter().all(|&x| x == DETACHED),
                "dropouts at {dropouts:?}: {:?}",
                &l[fa - w - 1..=fb - w + 1]
            );
            assert!(dropouts
                .iter()
                .all(|&at| l[at..at + 3].iter().all(|&x| x == OTHER)));
        }
    }

    #[test]
    fn speckle_far_from_rod_is_other() {
        let c = Calibration::nyu_default();
        let mut row = vec![raw_at(&c, 3.0); WIDTH];
        for r in &mut row[300..306] {
            *r = raw_at(&c, 1.0);
        }
        for r in &mut row[250..256] {
            *r = NO_DEPTH; // 50 px left of the rod: not where its shadow (29 px) falls
        }
        assert!(run(&row)[250..256].iter().all(|&x| x == OTHER));
    }

    #[test]
    fn a_noisy_pixel_at_the_farthest_walls_edge_does_not_send_its_shadow_out_of_range() {
        // The box of `attached_shadow_of_box_before_wall` (1 m, wall at 3 m, shadow [271, 300)),
        // on a wall that is the frame's farthest surface, with the pixel left of the shadow one
        // raw unit farther in every row (so the frame's farthest value is that pixel's). From
        // that pixel alone, the wall recedes at 1/16 unit a pixel and leaves the range 8 px into
        // the shadow; pairs of pixels at both ends of the baseline see it level.
        let (c, p) = params();
        let r = raw_at(&c, 3.0);
        let mut raw = vec![r; PIXELS];
        for v in 100..380 {
            let row = &mut raw[v * WIDTH..(v + 1) * WIDTH];
            row[270] = r + 1;
            row[271..300].fill(NO_DEPTH);
            row[300..400].fill(raw_at(&c, 1.0));
        }
        let (mut labels, mut filled) = (vec![0; PIXELS], vec![0; PIXELS]);
        classify_frame(&p, &raw, &mut labels, &mut filled);
        for v in [101, 240, 379] {
            assert_run(&labels[v * WIDTH..(v + 1) * WIDTH], 271..300, ATTACHED);
        }
    }

    #[test]
    fn one_rows_noise_on_a_level_farthest_wall_sends_no_shadow_out_of_range() {
        // A level wall at 3 m is the frame's farthest surface (raw r, every third pixel r + 1:
        // the range limit is r + 1), and a rod at 1.5 m casts its attached shadow from the top
        // row to the bottom, so no row above ever measured the shadow's columns. Eq. (3) gives
        // the width by hand: f·b·(1/1.5 − 1/3) px. In one row the two pixels left of Sa read
        // r + 1 and r + 2: alone, that row's baseline rises 0.1 unit a pixel and passes the limit
        // inside the shadow; the rows above and below see the wall level. Before, that row went
        // OTHER, and every row under it followed (a hole under an OTHER hole after the same
        // surface is an unmeasured region): 240 rows of shadow lost.
        let (c, p) = params();
        let r = raw_at(&c, 3.0);
        let w = (c.fb() * (1.0 / 1.5 - 1.0 / 3.0)).round() as usize;
        let (start, end) = (320 - w, 320);
        let mut raw: Vec<u16> = (0..PIXELS)
            .map(|i| r + u16::from((i % WIDTH + i / WIDTH).is_multiple_of(3)))
            .collect();
        for v in 0..HEIGHT {
            let row = &mut raw[v * WIDTH..(v + 1) * WIDTH];
            row[start..end].fill(NO_DEPTH);
            row[end..end + 12].fill(raw_at(&c, 1.5));
        }
        let tilted = &mut raw[240 * WIDTH..241 * WIDTH];
        tilted[start - 17..start - 2].fill(r);
        tilted[start - 2] = r + 1;
        tilted[start - 1] = r + 2;
        assert_eq!(
            Range::of(&raw),
            Range {
                far: r + 2,
                limit: r + 1
            }
        );
        let (mut labels, mut filled) = (vec![0; PIXELS], vec![0; PIXELS]);
        classify_frame(&p, &raw, &mut labels, &mut filled);
        for v in [0, 239, 240, 241, 360, HEIGHT - 1] {
            assert_run(&labels[v * WIDTH..(v + 1) * WIDTH], start..end, ATTACHED);
        }
    }

    /// A table before a level wall at 3 m, on a sensor that widens shadows 4 px past eq. (3):
    /// forty rows of boxes at 1.5 m teach the frame that widening before the table's rows;
    /// then the table top at 1.2 m, whose shadow is 3 px wider than `attached_over_px` allows
    /// (OTHER until the frame's widening is known at its end), and under it its leg at 2 m,
    /// whose shadow starts at the same column after the same wall. The leg's shadow is no
    /// unmeasured region running down from the table top's: it stays ATTACHED (before, every
    /// row of it went OTHER after the hole above it).
    #[test]
    fn a_leg_shadow_under_a_table_top_shadow_waiting_on_the_widening_stays_attached() {
        let (c, p) = params();
        let wall = raw_at(&c, 3.0);
        let width = |z: f64| c.fb() * (1.0 / z - 1.0 / 3.0);
        let mut raw = vec![wall; PIXELS];
        let box_hole = (width(1.5) + 4.0).round() as usize;
        for v in 0..40 {
            let row = &mut raw[v * WIDTH..(v + 1) * WIDTH];
            row[400 - box_hole..400].fill(NO_DEPTH);
            row[400..440].fill(raw_at(&c, 1.5));
        }
        let top_hole = (width(1.2) + p.over as f64 + 3.0).round() as usize;
        let leg_hole = (width(2.0) + 4.0).round() as usize;
        let start = 100;
        for v in 100..110 {
            let row = &mut raw[v * WIDTH..(v + 1) * WIDTH];
            row[start..start + top_hole].fill(NO_DEPTH);
            row[start + top_hole..start + top_hole + 200].fill(raw_at(&c, 1.2));
        }
        for v in 110..200 {
            let row = &mut raw[v * WIDTH..(v + 1) * WIDTH];
            row[start..start + leg_hole].fill(NO_DEPTH);
            row[start + leg_hole..start + leg_hole + 16].fill(raw_at(&c, 2.0));
        }
        let (mut labels, mut filled) = (vec![0; PIXELS], vec![0; PIXELS]);
        classify_frame(&p, &raw, &mut labels, &mut filled);
        assert_run(
            &labels[20 * WIDTH..21 * WIDTH],
            400 - box_hole..400,
            ATTACHED,
        );
        assert_run(
            &labels[105 * WIDTH..106 * WIDTH],
            start..start + top_hole,
            ATTACHED,
        );
        for v in [110, 111, 150, 199] {
            assert_run(
                &labels[v * WIDTH..(v + 1) * WIDTH],
                start..start + leg_hole,
                ATTACHED,
            );
        }
    }

    /// One row of a wall at 3 m with `objects` (columns `[a, b)` at depth z) before it, lit by the
    /// projector: a pixel whose centre x + 0.5 sees depth z is a hole where x + 0.5 − f·b/z falls
    /// in a nearer object's projector columns `[a − f·b/z_o, b − f·b/z_o)`.
    fn projected_row(c: &Calibration, objects: &[(f64, f64, f64)]) -> Vec<u16> {
        let fb = c.fb();
        (0..WIDTH)
            .map(|x| {
                let xc = x as f64 + 0.5;
                let z = objects
                    .iter()
                    .filter(|&&(a, b, _)| (a..b).contains(&xc))
                    .map(|o| o.2)
                    .fold(3.0, f64::min);
                let q = xc - fb / z;
                let lit = objects
                    .iter()
                    .all(|&(a, b, zo)| zo >= z || !(a - fb / zo..b - fb / zo).contains(&q));
                if lit {
                    raw_at(c, z)
                } else {
                    NO_DEPTH
                }
            })
            .collect()
    }

    #[test]
    fn shadow_behind_a_nearer_rod_from_the_frames_top_lies_on_the_wall_left_of_it() {
        // A box at 1.5 m from column 330 on, before a wall at 3 m, in every row: its attached
        // shadow on the wall, f·b·(1/1.5 − 1/3) = 14.6 px, covers 315..=329. A rod at 1 m over
        // [318, 322), nearer than the box, hides part of it: 315..=317 stay a hole left of the
        // rod (cut off from the box: detached), 322..=329 right of it; the rod's own shadow
        // falls on the wall at 289..=292. The hole right of the rod is bounded by the rod and
        // the box, and nothing above it was ever measured (the shadow runs from the frame's top
        // row): the wall left of the rod, beyond its cut-off shadow, is what the box's shadow
        // lies on, and eq. (3) against it fits. With a region the sensor does not measure left
        // of the rod (48 px, too wide for any shadow there: OTHER), the wall beyond it says
        // nothing of what stands behind the rod: OTHER.
        let (c, p) = params();
        let row = projected_row(&c, &[(330.0, 640.0, 1.5), (318.0, 322.0, 1.0)]);
        let hole = |a: usize, b: usize| (a..b).all(|x| row[x] == NO_DEPTH);
        assert!(
            hole(315, 318) && hole(322, 330) && hole(289, 293),
            "worked by hand"
        );
        assert!(row[314] != NO_DEPTH && row[288] != NO_DEPTH && row[293] != NO_DEPTH);
        let classify = |row: &[u16]| {
            let raw: Vec<u16> = (0..HEIGHT).flat_map(|_| row.iter().copied()).collect();
            let (mut labels, mut filled) = (vec![0; PIXELS], vec![0; PIXELS]);
            classify_frame(&p, &raw, &mut labels, &mut filled);
            labels
        };
        let labels = classify(&row);
        for v in [0, 240, HEIGHT - 1] {
            let l = &labels[v * WIDTH..(v + 1) * WIDTH];
            assert_run(l, 322..330, ATTACHED);
            assert_run(l, 315..318, DETACHED);
        }
        let mut beyond = row.clone();
        beyond[270..318].fill(NO_DEPTH);
        let labels = classify(&beyond);
        assert_run(&labels[240 * WIDTH..241 * WIDTH], 322..330, OTHER);
    }

    #[test]
    fn rods_detached_shadow_on_a_box_merged_with_the_boxs_attached_shadow() {
        // Wall at 3 m, a box at 2 m from column 300, a rod at 0.8 m over columns [333, 345). By
        // the projector's columns (pixel centre x + 0.5 lies in shadow where x + 0.5 − f·b/z
        // falls in an occluder's [a − f·b/z_o, b − f·b/z_o)): the box hides the wall's 293..=299
        // from the projector (its attached shadow, f·b·(1/2 − 1/3) = 7.3 px), the rod the box's
        // 300..=311 (shift f·b·(1/0.8 − 1/2) = 32.8 px), and the box is lit again from 312 up to
        // the rod: one hole 293..312. The rod's shift onto the wall, f·b·(1/0.8 − 1/3) = 40.1 px,
        // puts its shadow there at 293..=304: the projector's rays to 293..=299 meet the rod
        // before the box, so the whole hole is the rod's detached shadow (the occluder nearest
        // the projector owns a pixel, as `umbra synth` labels it), eqs. (4)–(5) at both ends.
        let (c, p) = params();
        let row = projected_row(&c, &[(300.0, 400.0, 2.0), (333.0, 345.0, 0.8)]);
        let hole: Vec<usize> = (0..WIDTH).filter(|&x| row[x] == NO_DEPTH).collect();
        assert_eq!(
            hole,
            (293..312).collect::<Vec<_>>(),
            "the geometry worked by hand"
        );
        let raw: Vec<u16> = (0..HEIGHT).flat_map(|_| row.iter().copied()).collect();
        let (mut labels, mut filled) = (vec![0; PIXELS], vec![0; PIXELS]);
        classify_frame(&p, &raw, &mut labels, &mut filled);
        for v in [1, 240, HEIGHT - 2] {
            assert_run(&labels[v * WIDTH..(v + 1) * WIDTH], 293..312, DETACHED);
        }
    }

    #[test]
    fn shadow_on_wall_receding_out_of_range_is_other_beyond_it() {
        // Wall receding to the right, last measured at raw 1014 (4.47 m): the box at raw 806
        // predicts w = 0.1244·(1014 − 806) = 25.9 px, but the wall leaves the range after a few
        // pixels of the 28 px hole. Only the in-range part is shadow.
        let (_, p) = params();
        let mut row: Vec<u16> = (0..WIDTH).map(|u| 1000 + (u as u16) / 6).collect();
        let (start, end) = (455, 483);
        for r in &mut row[start..end] {
            *r = NO_DEPTH;
        }
        for r in &mut row[end..] {
            *r = 806;
        }
        let far = *row[..start].iter().max().unwrap();
        let (mut labels, mut filled) = (vec![0; WIDTH], vec![0; WIDTH]);
        classify_row(
            &p,
            &row,
            &[NO_DEPTH; WIDTH],
            &[],
            &[],
            Range::at(far),
            &mut labels,
            &mut filled,
        );
        // Slope 1/6 raw per px (0.133 read off the staircase's last 16 px): within 0.5 raw of
        // `far` for the first 3 pixels. Only the slope beyond its noise margin (0.05) is carried,
        // which keeps up to 2 px more of the hole as shadow (5 here).
        assert!(
            labels[start..start + 3].iter().all(|&x| x == ATTACHED),
            "{:?}",
            &labels[start..end]
        );
        assert!(
            labels[start + 6..end].iter().all(|&x| x == OTHER),
            "{:?}",
            &labels[start..end]
        );
        // The same hole on a level wall is all shadow.
        let mut level = vec![1014u16; WIDTH];
        level[start..end].fill(NO_DEPTH);
        level[end..].fill(806);
        classify_row(
            &p,
            &level,
            &[NO_DEPTH; WIDTH],
            &[],
            &[],
            Range::at(1014),
            &mut labels,
            &mut filled,
        );
        assert!(labels[start..end].iter().all(|&x| x == ATTACHED));
    }

    #[test]
    fn range_limit_steps_past_a_sparse_noise_tail_only() {
        // Counts per raw value on the rows `range_limit` reads (every fourth): a surface at the
        // range limit 1014, its noise reaching 1015 (a tenth as often) and 1016 (4 pixels).
        let frame = |counts: &[(u16, usize)]| {
            let mut raw = vec![NO_DEPTH; PIXELS];
            let mut slots = (0..HEIGHT)
                .step_by(4)
                .flat_map(|v| (0..WIDTH).map(move |u| v * WIDTH + u));
            for &(value, n) in counts {
                for i in slots.by_ref().take(n) {
                    raw[i] = value;
                }
            }
            raw
        };
        let raw = frame(&[
            (1012, 3500),
            (1013, 3400),
            (1014, 2000),
            (1015, 300),
            (1016, 4),
        ]);
        assert_eq!(
            Range::of(&raw),
            Range {
                far: 1016,
                limit: 1014
            }
        );
        // A wall within range ends as steeply, but its last value is a third as common as the
        // one before it, not a tenth: nothing to step past.
        let raw = frame(&[(1008, 6900), (1009, 2500)]);
        assert_eq!(
            Range::of(&raw),
            Range {
                far: 1009,
                limit: 1009
            }
        );
        let raw = frame(&[(1008, 6900), (1009, 15)]);
        assert_eq!(range_limit(&raw, 1009), 1008);
    }

    #[test]
    fn shadow_where_the_wall_passes_the_range_limit_is_other_if_nothing_above_was_measured() {
        // The receding wall of the test above (raw 1000 + u/6, last measured 1075 at column 454),
        // now with noise reaching 2 raw units past that limit: `far` alone (1077) would keep
        // the whole hole as shadow (its slope carried beyond the 0.05 noise margin). Where no
        // row above measured anything in the hole's columns, the wall is out of range past the
        // limit there (3 px in by the slope, 5 px with the margin); where the rows above saw a
        // surface, that rule stays out of it.
        let (_, p) = params();
        let mut row: Vec<u16> = (0..WIDTH).map(|u| 1000 + (u as u16) / 6).collect();
        let (start, end) = (455, 483);
        row[start..end].fill(NO_DEPTH);
        row[end..].fill(806);
        let limit = *row[..start].iter().max().unwrap();
        let range = Range {
            far: limit + 2,
            limit,
        };
        let shadow = |above: &[u16]| {
            let (mut labels, mut filled) = (vec![0; WIDTH], vec![0; WIDTH]);
            classify_row(&p, &row, above, &[], &[], range, &mut labels, &mut filled);
            assert!(labels[start..end]
                .iter()
                .all(|&x| x == ATTACHED || x == OTHER));
            labels[start..end]
                .iter()
                .filter(|&&x| x == ATTACHED)
                .count()
        };
        let nothing_above = shadow(&[NO_DEPTH; WIDTH]);
        assert!(
            (1..=6).contains(&nothing_above),
            "{nothing_above} px of shadow"
        );
        let seen_above = shadow(&vec![1070u16; WIDTH]);
        assert!(seen_above >= 10, "{seen_above} px of shadow");
    }

    #[test]
    fn shadow_under_an_out_of_range_region_is_other_despite_a_noisy_far_value() {
        // The wall of the test above in every row, out of range from column 461 on (raw 1016.8
        // and beyond). Rows 100.. hold a box from column 480: its 19 px hole [461, 480) lies
        // where the wall is out of range, as the rows above show. One noisy pixel reads 2 raw
        // units farther than the wall ever does, so `far` alone calls only the hole's far end
        // out of range.
        let (_, p) = params();
        let wall = |u: usize| 940 + (u as u16) / 6;
        let mut raw = vec![NO_DEPTH; PIXELS];
        for v in 0..HEIGHT {
            for u in 0..461 {
                raw[v * WIDTH + u] = wall(u);
            }
            if v >= 100 {
                raw[v * WIDTH + 480..(v + 1) * WIDTH].fill(806);
            }
        }
        raw[5 * WIDTH + 10] = wall(460) + 2;
        let (mut labels, mut filled) = (vec![0; PIXELS], vec![0; PIXELS]);
        classify_frame(&p, &raw, &mut labels, &mut filled);
        for v in [100, 101, 250, 479] {
            let hole = &labels[v * WIDTH + 461..v * WIDTH + 480];
            assert!(hole.iter().all(|&l| l == OTHER), "row {v}: {hole:?}");
        }
        // Without the out-of-range rows above, the same hole is the box's attached shadow.
        let mut lower = raw.clone();
        for v in 0..100 {
            lower[v * WIDTH + 461..(v + 1) * WIDTH].fill(wall(460));
        }
        classify_frame(&p, &lower, &mut labels, &mut filled);
        let hole = &labels[250 * WIDTH + 461..250 * WIDTH + 480];
        assert!(hole[..10].iter().all(|&l| l == ATTACHED), "{hole:?}");
    }

    #[test]
    fn shadow_under_a_grazing_top_edge_is_no_unmeasured_region_running_down() {
        // A wall at 3 m; a box at 1.5 m fills columns [100, 230) from row 200 down; a post at
        // 1 m, [230, 290), stands before both from row 100. By hand (eq. 3) its shadow is
        // f·b·(1/1 − 1/3) px wide on the wall and f·b·(1/1 − 1/1.5) px on the box. Row 199 is the
        // box's top face seen edge-on, a hole from column 100 to the post, in which one pixel of
        // the box shows, just left of where the shadow on the box starts: that row is OTHER (no
        // reading explains a hole that wide). The rows under it hold the post's shadow on the
        // box. Before, the pixel above Sa made the edge's hole read as one that starts after Sa,
        // and every row under it inherited OTHER down to the frame's bottom.
        let (c, p) = params();
        let (wall, boxed, post) = (raw_at(&c, 3.0), raw_at(&c, 1.5), raw_at(&c, 1.0));
        let on_wall = (c.fb() * (1.0 - 1.0 / 3.0)).round() as usize;
        let on_box = (c.fb() * (1.0 - 1.0 / 1.5)).round() as usize;
        let mut raw = vec![wall; PIXELS];
        for v in 100..HEIGHT {
            let row = &mut raw[v * WIDTH..(v + 1) * WIDTH];
            if v >= 200 {
                row[100..230].fill(boxed);
            }
            let shadow = if v >= 200 { on_box } else { on_wall };
            row[230 - shadow..230].fill(NO_DEPTH);
            row[230..290].fill(post);
        }
        let edge = &mut raw[199 * WIDTH..200 * WIDTH];
        edge[100..230].fill(NO_DEPTH);
        edge[230 - on_box - 1] = boxed;
        assert_eq!((on_wall, on_box), (29, 15));
        let (mut labels, mut filled) = (vec![0; PIXELS], vec![0; PIXELS]);
        classify_frame(&p, &raw, &mut labels, &mut filled);
        assert_run(
            &labels[199 * WIDTH..200 * WIDTH],
            100..230 - on_box - 1,
            OTHER,
        );
        for v in [150, 200, 201, 300, 479] {
            let shadow = if v >= 200 { on_box } else { on_wall };
            assert_run(
                &labels[v * WIDTH..(v + 1) * WIDTH],
                230 - shadow..230,
                ATTACHED,
            );
        }
    }

    #[test]
    fn hole_below_an_unmeasured_region_beside_a_partition_continues_it() {
        // A partition at 3 m fills columns [0, 300) of every row; past its edge the room is out of
        // range. Rows 100.. hold a box at 2 m, [308, 400). By hand its shadow on the partition
        // would be f·b·(1/2 − 1/3) = 7.3 px, so the 8 px hole [300, 308) fits eq. (3). But the
        // rows above show that hole as the unmeasured region, starting at the same edge.
        let (c, p) = params();
        let (wall, boxed) = (raw_at(&c, 3.0), raw_at(&c, 2.0));
        let w = c.fb() * (1.0 / 2.0 - 1.0 / 3.0);
        assert!((7.0..8.0).contains(&w), "shadow width {w}");
        let frame = |partition_above: usize| {
            let mut raw = vec![NO_DEPTH; PIXELS];
            for v in 0..HEIGHT {
                let end = if v < 100 { partition_above } else { 300 };
                raw[v * WIDTH..v * WIDTH + end].fill(wall);
                if v >= 100 {
                    raw[v * WIDTH + 308..v * WIDTH + 400].fill(boxed);
                }
            }
            let (mut labels, mut filled) = (vec![0; PIXELS], vec![0; PIXELS]);
            classify_frame(&p, &raw, &mut labels, &mut filled);
            labels
        };
        let labels = frame(300);
        for v in [100, 101, 250, 479] {
            let hole = &labels[v * WIDTH + 300..v * WIDTH + 308];
            assert!(hole.iter().all(|&l| l == OTHER), "row {v}: {hole:?}");
        }
        // Where the partition reaches on past the box's left edge above it (its end hidden behind
        // the box below), the hole has the lit partition above it: the box's attached shadow.
        let labels = frame(320);
        for v in [100, 101, 250, 479] {
            let hole = &labels[v * WIDTH + 300..v * WIDTH + 308];
            assert!(hole.iter().all(|&l| l == ATTACHED), "row {v}: {hole:?}");
        }
    }

    #[test]
    fn shadow_below_the_occluders_dropout_joined_to_it_stays_attached() {
        // A wall at 2 m; a post at 0.7 m fills columns [264, 400) of every row. By hand (eq. 3)
        // its shadow is f·b·(1/0.7 − 1/2) = 40.6 px wide: the hole [223, 264). Over rows
        // [150, 194) the post's left part, [264, 362), is a glossy patch without depth, joined
        // to the shadow in one hole that ends on the post: no reading explains it (OTHER). Under
        // it, the shadow alone again, after the same wall, under that OTHER hole. It is no region
        // running down behind the post: the post stands in both rows, the hole above ends on it,
        // and eq. (3) fits. Before, every row under the patch inherited OTHER, down to the
        // frame's bottom (a fifth simulator's k35 s019: 2 700 px).
        let (c, p) = params();
        let (wall, post) = (raw_at(&c, 2.0), raw_at(&c, 0.7));
        let w = c.fb() * (1.0 / 0.7 - 1.0 / 2.0);
        assert!((40.0..41.0).contains(&w), "shadow width {w}");
        let start = 264 - w.round() as usize;
        let mut raw = vec![wall; PIXELS];
        for v in 0..HEIGHT {
            let row = &mut raw[v * WIDTH..(v + 1) * WIDTH];
            row[start..264].fill(NO_DEPTH);
            row[264..400].fill(post);
            if (150..194).contains(&v) {
                row[264..362].fill(NO_DEPTH);
            }
        }
        let (mut labels, mut filled) = (vec![0; PIXELS], vec![0; PIXELS]);
        classify_frame(&p, &raw, &mut labels, &mut filled);
        for v in [100, 194, 195, 300, 479] {
            assert_run(&labels[v * WIDTH..(v + 1) * WIDTH], start..264, ATTACHED);
        }
    }

    #[test]
    fn shadow_under_a_box_top_seen_at_a_grazing_angle_stays_attached() {
        // A box at 1 m, [300, 400), from row 100 down before a wall at 3 m: by hand its shadow
        // is f·b·(1/1 − 1/3) = 29 px, [271, 300). Its top face, seen at a grazing angle, returns
        // no depth over rows [96, 100), from the shadow's first column to the box's right end.
        // The first shadow row lies under that OTHER hole, after the same wall, but the wall
        // measured above the hole says it is no unmeasured region running down.
        let (c, p) = params();
        let w = (c.fb() * (1.0 - 1.0 / 3.0)).round() as usize;
        assert_eq!(w, 29);
        let mut raw = vec![raw_at(&c, 3.0); PIXELS];
        for v in 96..HEIGHT {
            let row = &mut raw[v * WIDTH..(v + 1) * WIDTH];
            if v < 100 {
                row[300 - w..400].fill(NO_DEPTH);
            } else {
                row[300 - w..300].fill(NO_DEPTH);
                row[300..400].fill(raw_at(&c, 1.0));
            }
        }
        let (mut labels, mut filled) = (vec![0; PIXELS], vec![0; PIXELS]);
        classify_frame(&p, &raw, &mut labels, &mut filled);
        for v in [100, 101, 250, 479] {
            let shadow = &labels[v * WIDTH + 300 - w..v * WIDTH + 300];
            assert!(shadow.iter().all(|&l| l == ATTACHED), "row {v}: {shadow:?}");
        }
    }

    #[test]
    fn depthless_rod_is_paired_in_rows_whose_neighbours_swallow_the_lit_gap() {
        // A black rod at 2 m, [300, 306), before a wall at 3 m: by hand its shadow lies
        // f·b·(1/2 − 1/3) = 7.3 px further left, [293, 299), with a lit pixel at 299. In every
        // other row the widening swallows that pixel: one hole [293, 306).
        let (c, p) = params();
        let w = c.fb() * (1.0 / 2.0 - 1.0 / 3.0);
        assert!((7.0..7.5).contains(&w), "shift {w}");
        let pair = wall_with_holes(&c, &[(293, 299), (300, 306)]);
        let merged = |end: usize| wall_with_holes(&c, &[(293, end)]);
        let frame = |odd: &[u16]| {
            let mut raw = Vec::with_capacity(PIXELS);
            for v in 0..HEIGHT {
                raw.extend_from_slice(if v % 2 == 0 { &pair } else { odd });
            }
            let (mut labels, mut filled) = (vec![0; PIXELS], vec![0; PIXELS]);
            classify_frame(&p, &raw, &mut labels, &mut filled);
            labels
        };
        let labels = frame(&merged(306));
        for v in [100, 240, 300] {
            let row = &labels[v * WIDTH..(v + 1) * WIDTH];
            assert_run(row, 293..299, DETACHED);
            assert_run(row, 300..306, OTHER);
        }
        // Neighbours whose one hole runs on past the rod hold no such pair.
        let labels = frame(&merged(312));
        let row = &labels[240 * WIDTH..241 * WIDTH];
        assert_run(row, 293..299, OTHER);
    }

    #[test]
    fn detached_shadow_widened_on_its_left_is_still_detached() {
        // A 13 px rod at 1 m, [300, 313), before a wall at 3 m: its shadow is the rod shifted
        // left by f·b·(1/1 − 1/3) = 29.1 px, [271, 284). The sensor widens it by 5 px on the
        // left, [266, 284): eq. (4) is then off by 5 px, all of it on the widening's side.
        let (c, _) = params();
        let row_with = |a: usize| {
            let mut row = wall_with_holes(&c, &[(a, 284)]);
            row[300..313].fill(raw_at(&c, 1.0));
            row
        };
        let row = row_with(266);
        let (labels, _) = run_with_neighbours(&row, &row, &row);
        assert!(
            labels[266..284].iter().all(|&l| l == DETACHED),
            "{:?}",
            &labels[260..290]
        );
        // A hole 5 px short of the shadow's left end is no such shadow: widening never shrinks.
        let row = row_with(276);
        let (labels, _) = run_with_neighbours(&row, &row, &row);
        assert!(labels[276..284].iter().all(|&l| l != DETACHED));
    }

    #[test]
    fn thin_rod_before_a_black_object_is_judged_where_the_wall_shows_behind_it() {
        // A 10 px rod at 1.645 m before a wall at 3 m: shift f·b·(1/1.645 − 1/3) = 12 px > 10 px,
        // so its shadow [288, 298) is detached; the sensor's widening swallows the 2 px lit gap
        // in most rows (not every fourth), and the hole [288, 300) touches the rod [300, 310). In
        // rows 200..260 a black object right of the rod, [310, 360), hides where the rod ends;
        // the rows above and below show it (up to 40 rows away).
        let (c, p) = params();
        let mut raw = vec![raw_at(&c, 3.0); PIXELS];
        for v in 0..HEIGHT {
            let row = &mut raw[v * WIDTH..(v + 1) * WIDTH];
            row[288..if v % 4 == 0 { 298 } else { 300 }].fill(NO_DEPTH);
            row[300..310].fill(raw_at(&c, 1.645));
            if (200..260).contains(&v) {
                row[310..360].fill(NO_DEPTH);
            }
        }
        let (mut labels, mut filled) = (vec![0; PIXELS], vec![0; PIXELS]);
        classify_frame(&p, &raw, &mut labels, &mut filled);
        for v in [101, 201, 229, 259, 479] {
            let hole = &labels[v * WIDTH + 288..v * WIDTH + 300];
            assert!(hole.iter().all(|&l| l == DETACHED), "row {v}: {hole:?}");
        }
        // A rod wider than its shift (14 px) casts an attached shadow, black object or not, and
        // no lit gap shows.
        for v in 0..HEIGHT {
            raw[v * WIDTH + 288..v * WIDTH + 300].fill(NO_DEPTH);
            raw[v * WIDTH + 300..v * WIDTH + 314].fill(raw_at(&c, 1.645));
            if (200..260).contains(&v) {
                raw[v * WIDTH + 314..v * WIDTH + 360].fill(NO_DEPTH);
            }
        }
        classify_frame(&p, &raw, &mut labels, &mut filled);
        for v in [100, 229] {
            let hole = &labels[v * WIDTH + 288..v * WIDTH + 300];
            assert!(hole.iter().all(|&l| l == ATTACHED), "row {v}: {hole:?}");
        }
    }

    #[test]
    fn thin_rod_before_a_nearer_objects_shadow_is_judged_by_that_shadows_width() {
        // The rod of the test above (10 px at 1.645 m, shift 12 px, shadow [288, 298), lit gap
        // swallowed in three rows of four), with a box at 1 m from column `zc` on: its attached
        // shadow on the wall, [zc − 29.1, zc), hides the wall right of the rod in every row.
        // Had the rod gone on behind that hole, the box's shadow on the rod would be only
        // f·b·(1/1 − 1/1.645) = 17.1 px wide: a hole [310, 336) is wider (by more than the
        // widening), so the rod ends at 310 and is thin: detached. A hole [310, 328) could be
        // the box's shadow on a wider rod: nothing tells, and it stays attached, but for its
        // last pixel: the box's shadow on the wall starts at 328 − 29.1 = 298.9, and there the
        // projector's ray meets the box first (`nearer_shadow_past_sb`).
        let (c, p) = params();
        for (zc, code) in [(336, DETACHED), (328, ATTACHED)] {
            let mut raw = vec![raw_at(&c, 3.0); PIXELS];
            for v in 0..HEIGHT {
                let row = &mut raw[v * WIDTH..(v + 1) * WIDTH];
                row[288..if v % 4 == 0 { 298 } else { 300 }].fill(NO_DEPTH);
                row[300..310].fill(raw_at(&c, 1.645));
                row[310..zc].fill(NO_DEPTH);
                row[zc..zc + 60].fill(raw_at(&c, 1.0));
            }
            let (mut labels, mut filled) = (vec![0; PIXELS], vec![0; PIXELS]);
            classify_frame(&p, &raw, &mut labels, &mut filled);
            for v in [101, 229, 479] {
                let to = if code == ATTACHED { 298 } else { 300 };
                let hole = &labels[v * WIDTH + 288..v * WIDTH + to];
                assert!(
                    hole.iter().all(|&l| l == code),
                    "zc {zc}, row {v}: {hole:?}"
                );
                if code == ATTACHED {
                    assert_eq!(labels[v * WIDTH + 299], DETACHED, "zc {zc}, row {v}");
                }
            }
        }
    }

    #[test]
    fn a_thin_rod_standing_in_a_farther_objects_shadow_cuts_off_a_detached_part() {
        // A wall at 3 m; a box at 1 m from column 400 (rows 200..300) casts its attached shadow
        // on the wall over [400 − 29.1, 400) = columns 371..399. An 8 px rod at 0.75 m, [380,
        // 388) (rows 100..400), stands in that shadow, nearer than the box, so lit: it cuts the
        // shadow in two (the rows above and below the box show where the rod ends). The part right of it touches the box: attached. The part left of it,
        // [371, 380), is cut off from the box: detached. The rod's own shadow lies 43.7 px
        // left of it, [337, 345): detached, past a lit gap.
        let (c, p) = params();
        let (w_box, w_rod) = (
            c.fb() * (1.0 - 1.0 / 3.0),
            c.fb() * (1.0 / 0.75 - 1.0 / 3.0),
        );
        assert!((29.0..29.2).contains(&w_box) && (43.6..43.8).contains(&w_rod));
        let mut raw = vec![raw_at(&c, 3.0); PIXELS];
        for v in 100..400 {
            let row = &mut raw[v * WIDTH..(v + 1) * WIDTH];
            row[337..345].fill(NO_DEPTH);
            row[380..388].fill(raw_at(&c, 0.75));
            if (200..300).contains(&v) {
                row[371..380].fill(NO_DEPTH);
                row[388..400].fill(NO_DEPTH);
                row[400..460].fill(raw_at(&c, 1.0));
            }
        }
        let (mut labels, mut filled) = (vec![0; PIXELS], vec![0; PIXELS]);
        classify_frame(&p, &raw, &mut labels, &mut filled);
        for v in [201, 250, 299] {
            let row = &labels[v * WIDTH..(v + 1) * WIDTH];
            assert_run(row, 337..345, DETACHED);
            assert_run(row, 371..380, DETACHED);
            assert_run(row, 388..400, ATTACHED);
        }
    }

    /// A wall at 3 m in every row, with `draw(v, row)` painted over row `v`: the labels
    /// `classify_frame` gives that frame.
    fn wall_frame(draw: impl Fn(usize, &mut [u16])) -> Vec<u8> {
        let (c, p) = params();
        let mut raw = vec![raw_at(&c, 3.0); PIXELS];
        for (v, row) in raw.chunks_exact_mut(WIDTH).enumerate() {
            draw(v, row);
        }
        let (mut labels, mut filled) = (vec![0; PIXELS], vec![0; PIXELS]);
        classify_frame(&p, &raw, &mut labels, &mut filled);
        labels
    }

    /// Asserts that columns `cols` of each row in `rows` all hold `code`.
    fn assert_rows(labels: &[u8], rows: &[usize], cols: std::ops::Range<usize>, code: u8) {
        for &v in rows {
            let span = &labels[v * WIDTH + cols.start..v * WIDTH + cols.end];
            assert!(span.iter().all(|&l| l == code), "row {v}: {span:?}");
        }
    }

    #[test]
    fn shadow_behind_a_thin_nearer_leg_is_found_where_it_runs_on_into_the_hole_before() {
        // A leg B at 0.67 m over [340, 375) before a wall at 3 m: shift 43.67·(1/0.67 − 1/3) =
        // 50.6 px, wider than B, so its shadow [289, 324) is detached (lit wall [324, 340)). A
        // thinner leg A at 1.2 m over [303, 310) stands in it (lit: B's shadow at A's depth,
        // shifted 28.8 px, covers [311, 346)), and A's own shadow, 21.8 px left of A, merges
        // with B's: one hole [281, 303), A, then [310, 324). Eq. (4) puts B's shadow's start
        // 21 px left of the second hole's, behind A (7 px) and on in the hole before it; the
        // second hole was OTHER.
        let (c, _) = params();
        let (leg_a, leg_b) = (raw_at(&c, 1.2), raw_at(&c, 0.67));
        let labels = wall_frame(|v, row| {
            if (100..300).contains(&v) {
                row[281..303].fill(NO_DEPTH);
                row[303..310].fill(leg_a);
                row[310..324].fill(NO_DEPTH);
                row[340..375].fill(leg_b);
            }
        });
        assert_rows(&labels, &[100, 150, 200, 299], 310..324, DETACHED);
    }

    #[test]
    fn rod_within_the_tie_of_its_shift_is_judged_alike_where_a_hole_hides_its_end() {
        // A 10 px rod [300, 310) at 1.645 m before a wall at 3 m: shift 12 px, within the 4 px
        // tie of its measured width (the widening eats up to 3 px of its left edge, so it may be
        // as wide as its shift). No row shows a lit gap between the hole [288, 300) and the rod:
        // attached where the wall shows right of the rod. In rows 200..260 a hole [310, 330)
        // (another rod's shadow) hides where the rod ends; its width is read in the rows
        // around, and the same tie holds: attached there too, not detached.
        let (c, _) = params();
        let rod = |gap_every: Option<usize>| {
            move |v: usize, row: &mut [u16]| {
                row[288..300].fill(NO_DEPTH);
                row[300..310].fill(raw_at(&c, 1.645));
                if (200..260).contains(&v) {
                    row[310..330].fill(NO_DEPTH);
                }
                // A lit gap [298, 300) in every `gap_every`-th row.
                if gap_every.is_some_and(|k| v.is_multiple_of(k)) {
                    row[298..300].fill(raw_at(&c, 3.0));
                }
            }
        };
        let labels = wall_frame(rod(None));
        assert_rows(&labels, &[100, 201, 229, 259, 300], 288..300, ATTACHED);
        // A lit gap in every fourth row breaks the tie: detached in every row.
        let labels = wall_frame(rod(Some(4)));
        assert_rows(&labels, &[101, 201, 229, 259, 301], 288..300, DETACHED);
    }

    #[test]
    fn rod_clearly_narrower_than_its_shift_is_thin_before_a_farther_box_too() {
        // A 6 px rod [300, 306) at 1.645 m before a wall at 3 m: shift 12 px, twice its width,
        // so its shadow [288, 294) is detached (SPEC §1). A box at 2.2 m starts behind it, at
        // column 300: its own attached shadow, 43.7·(1/2.2 − 1/3) = 5.3 px wide, [294.7, 300),
        // covers the lit gap, so the hole [288, 300) touches the rod, and right of the rod the
        // box shows, not the wall. The rod still ends at 306, at a step back to the box: its
        // width is measured there, and it is thin.
        let (c, _) = params();
        let labels = wall_frame(|_, row| {
            row[288..300].fill(NO_DEPTH);
            row[300..306].fill(raw_at(&c, 1.645));
            row[306..360].fill(raw_at(&c, 2.2));
        });
        assert_rows(&labels, &[1, 100, 241, 478], 288..300, DETACHED);
    }

    #[test]
    fn two_rods_side_by_side_cast_one_detached_hole() {
        // Rod A at 0.8 m, 22 px [300, 322): shift 43.67·(1/0.8 − 1/3) = 40.0 px, shadow
        // [260, 282). Rod B at 0.75 m, 12 px [322, 334), before A's right end: shift 43.67 px,
        // shadow [278.3, 290.3), and its attached shadow on A, 43.67·(1/0.75 − 1/0.8) = 3.6 px,
        // hides A's last four columns [318, 322). The two detached shadows overlap into one
        // hole [260, 290); the lit gap [290, 300) stays lit. Neither rod alone fits both of its
        // ends (eqs. 4–5): A its left, B its right.
        let (c, _) = params();
        let labels = wall_frame(|_, row| {
            row[260..290].fill(NO_DEPTH);
            row[300..318].fill(raw_at(&c, 0.8));
            row[318..322].fill(NO_DEPTH);
            row[322..334].fill(raw_at(&c, 0.75));
        });
        assert_rows(&labels, &[1, 100, 241, 478], 260..290, DETACHED);
        assert_rows(&labels, &[1, 100, 241, 478], 318..322, ATTACHED);
    }

    #[test]
    fn depthless_rods_whole_shadow_beside_a_nearer_box_is_detached() {
        // A black rod, 8 px [314, 322), shift 14 px (at 43.67 / (43.67/3 + 14) = 1.53 m): its
        // shadow on the wall at 3 m, [300, 308) and 3 px of widening, lies whole just right of
        // a box at 2 m that ends at column 300 (the box's own shadow is on its left). The hole
        // beside the nearer box is no hidden part of a shadow; it is the rod's whole shadow.
        // Beside a nearer surface the pair must show in HIDDEN_PAIR_ROWS rows each way.
        let (c, _) = params();
        let labels = wall_frame(|_, row| {
            row[193..200].fill(NO_DEPTH);
            row[200..300].fill(raw_at(&c, 2.0));
            row[300..311].fill(NO_DEPTH);
            row[314..322].fill(NO_DEPTH);
        });
        assert_rows(&labels, &[4, 100, 241, 475], 300..311, DETACHED);
        assert_rows(&labels, &[1, 100, 241, 478], 193..200, ATTACHED);
    }

    #[test]
    fn rod_running_off_the_right_border_keeps_its_detached_shadow() {
        // A rod at 0.6 m, 50 px wide [600, 650), before a wall at 3 m: shift
        // 43.67·(1/0.6 − 1/3) = 58.2 px, shadow [541.8, 591.8), lit gap [592, 600). The camera
        // sees only [600, 640) of it: eq. (5) from what shows puts the shadow's end 10 px
        // short of where it is. The part beyond the border casts the rest.
        let (c, _) = params();
        let labels = wall_frame(|_, row| {
            row[542..592].fill(NO_DEPTH);
            row[600..640].fill(raw_at(&c, 0.6));
        });
        assert_rows(&labels, &[1, 100, 241, 478], 542..592, DETACHED);
    }

    #[test]
    fn rod_within_four_pixels_of_its_shift_before_a_nearer_box_is_attached() {
        // An 8 px rod [300, 308) at 1.645 m: against the wall at 3 m left of its hole its shift
        // is 12.0 px (eq. 3), 4 px more than its width. But behind it stands a box at 2.4 m,
        // its left edge hidden in the hole, on which the shift is 43.67·(1/1.645 − 1/2.4) =
        // 8.35 px: no lit gap between the rod and its shadow's end. Within 4 px the widths
        // cannot tell, and no row shows a gap: attached.
        let (c, _) = params();
        let labels = wall_frame(|_, row| {
            row[288..300].fill(NO_DEPTH);
            row[300..308].fill(raw_at(&c, 1.645));
            row[308..360].fill(raw_at(&c, 2.4));
        });
        assert_rows(&labels, &[1, 100, 241, 478], 288..300, ATTACHED);
    }

    #[test]
    fn rod_half_hidden_behind_a_nearer_rod_keeps_its_detached_shadow() {
        // Before a wall at 3 m: rod A at 0.8 m over [300, 312) (shift 43.67·(1/0.8 − 1/3) =
        // 40.0 px, shadow [260, 272)), and rod B at 1.2 m over [302, 316) (shift 21.8 px,
        // shadow [280.2, 294.2)), whose first 10 columns A hides. From what shows of B,
        // [312, 316), its shadow would start 10 px further right than it does; A's width
        // bounds how much of B it can hide.
        let (c, _) = params();
        let labels = wall_frame(|_, row| {
            row[260..272].fill(NO_DEPTH);
            row[280..294].fill(NO_DEPTH);
            row[300..312].fill(raw_at(&c, 0.8));
            row[312..316].fill(raw_at(&c, 1.2));
        });
        assert_rows(&labels, &[1, 100, 241, 478], 260..272, DETACHED);
        assert_rows(&labels, &[1, 100, 241, 478], 280..294, DETACHED);
    }

    #[test]
    fn rod_with_a_hole_then_its_own_depth_on_its_right_goes_on_behind_the_hole() {
        // A 6 px run [300, 306) at 1.645 m before a wall at 3 m (shift 12 px), then a 10 px hole
        // and the same depth again from 316 on: one surface with a hole in it (a dropout,
        // another rod's shadow on it), not a 6 px rod whose lit gap a second object at the
        // very same depth shadows. The hole [288, 300) left of it is its attached shadow.
        let (c, _) = params();
        let labels = wall_frame(|_, row| {
            row[288..300].fill(NO_DEPTH);
            row[300..370].fill(raw_at(&c, 1.645));
            row[306..316].fill(NO_DEPTH);
        });
        assert_rows(&labels, &[1, 100, 241, 478], 288..300, ATTACHED);
    }

    #[test]
    fn turned_board_whose_left_part_a_rods_shadow_cuts_short_keeps_its_attached_shadow() {
        // A board turned to the camera over [300, 440) before a wall at 3 m: its disparity
        // d(u) = 36.39 + 0.1·(u − 300) px (a plane's disparity is affine in u; 1.2 m at its left
        // edge), so its attached shadow on the wall is d(300) − 43.67/3 = 21.8 px, [278, 300).
        // A rod at 0.6 m (disparity 72.78) over [350, 364) shadows the board where
        // u = a − 72.78 + d(u), i.e. u = (a − 66.39)/0.9: [315, 331). What shows of the board
        // left of that, 15 px, is narrower than the board's shift, and the board goes on right
        // of the rod's shadow 1.7 px nearer, as its slope carries it: the same surface, not a
        // second object whose shadow hides a lit gap. The board's shadow is attached.
        let (c, _) = params();
        let board = |u: usize| raw_at(&c, c.fb() / (36.39 + 0.1 * (u as f64 - 300.0)));
        let labels = wall_frame(|_, row| {
            row[278..300].fill(NO_DEPTH);
            for (u, r) in row.iter_mut().enumerate().take(440).skip(300) {
                *r = board(u);
            }
            row[315..331].fill(NO_DEPTH);
            row[350..364].fill(raw_at(&c, 0.6));
        });
        assert_rows(&labels, &[1, 100, 241, 478], 278..300, ATTACHED);
        assert_rows(&labels, &[1, 100, 241, 478], 315..331, DETACHED);
    }

    #[test]
    fn rods_shadow_on_a_turned_board_is_found_past_the_board_rising_towards_the_camera() {
        // A board turned to the camera over [250, 400) before a wall at 3 m, its disparity
        // d(u) = 7.5 + 0.05·u px (20 px, 2.18 m, at its left edge; attached shadow [245, 250)).
        // A rod at 0.8 m (disparity 54.59) over [340, 350) shadows it where
        // u = a − 54.59 + d(u), i.e. u = (a − 47.09)/0.95: [308.3, 318.9). Between the shadow
        // and the rod the board rises by more than a pixel of disparity over the wall-side
        // background, and sensor noise cuts that rise in two (column 333 half a pixel back):
        // neither part is an occluder, and the rod's eqs. (4)–(5) make the hole detached.
        let (c, _) = params();
        let board = |u: usize, dip: f64| raw_at(&c, c.fb() / (7.5 + 0.05 * u as f64 - dip));
        let labels = wall_frame(|_, row| {
            row[245..250].fill(NO_DEPTH);
            for (u, r) in row.iter_mut().enumerate().take(400).skip(250) {
                *r = board(u, if u == 333 { 0.5 } else { 0.0 });
            }
            row[309..319].fill(NO_DEPTH);
            row[340..350].fill(raw_at(&c, 0.8));
        });
        assert_rows(&labels, &[1, 100, 241, 478], 309..319, DETACHED);
    }

    #[test]
    fn shadows_of_two_rods_side_by_side_are_not_a_black_rod_and_its_shadow() {
        // Before a wall at 3 m: rod A at 1 m over [300, 312) (shift 43.67·(1 − 1/3) = 29.1 px,
        // shadow [270.9, 282.9)) and rod B at 1.1 m right against it over [312, 322) (shift
        // 25.1 px, shadow [286.9, 296.9)). The two shadows, 12 and 10 px wide 14 px apart, look
        // like a black rod 43.67/(14.56 + 14) = 1.53 m away and its shadow; but B's hole is a
        // measured rod's detached shadow, a hole in the lit wall, so it is no occluder: both
        // are detached, and B's shadow keeps the wall's depth for the warp.
        let (c, p) = params();
        let wall = raw_at(&c, 3.0);
        let mut raw = vec![wall; PIXELS];
        for row in raw.chunks_exact_mut(WIDTH) {
            row[271..283].fill(NO_DEPTH);
            row[287..297].fill(NO_DEPTH);
            row[300..312].fill(raw_at(&c, 1.0));
            row[312..322].fill(raw_at(&c, 1.1));
        }
        let (mut labels, mut filled) = (vec![0; PIXELS], vec![0; PIXELS]);
        classify_frame(&p, &raw, &mut labels, &mut filled);
        assert_rows(&labels, &[1, 100, 241, 478], 271..283, DETACHED);
        assert_rows(&labels, &[1, 100, 241, 478], 287..297, DETACHED);
        for v in [1, 100, 241, 478] {
            let b = &filled[v * WIDTH + 287..v * WIDTH + 297];
            assert!(b.iter().all(|&f| f == wall), "row {v}: {b:?}, wall {wall}");
        }
    }

    #[test]
    fn rods_shadow_merged_with_a_region_beyond_range_at_the_left_border_is_detached() {
        // A rod at 1 m over [200, 212) before a wall at 3 m: shift 43.67·(1 − 1/3) = 29.1 px,
        // shadow [170.9, 182.9). Left of it the wall is beyond range: columns [0, 150) in rows
        // from 240 down, [0, 175) above them, where the two holes merge into one from the left
        // border. Its right part is the rod's shadow (eq. 5 at its end, eq. 4 where a row
        // below shows the whole shadow); the rest is OTHER.
        let (c, _) = params();
        let labels = wall_frame(|v, row| {
            row[..if v < 240 { 175 } else { 150 }].fill(NO_DEPTH);
            row[171..183].fill(NO_DEPTH);
            row[200..212].fill(raw_at(&c, 1.0));
        });
        assert_rows(&labels, &[210, 239, 241, 400], 171..183, DETACHED);
        assert_rows(&labels, &[210, 239], 0..165, OTHER);
        // Where no row shows the shadow's left end, eq. (5) alone cannot tell it from a wall
        // whose measured part begins where a rod's shadow on it would end: left OTHER.
        let labels = wall_frame(|_, row| {
            row[..183].fill(NO_DEPTH);
            row[200..212].fill(raw_at(&c, 1.0));
        });
        assert_rows(&labels, &[1, 210, 478], 0..183, OTHER);
    }

    #[test]
    fn rods_shadow_half_hidden_by_a_nearer_rod_down_from_the_top_is_attached() {
        // A board at 1.2 m over [150, 400) before a wall at 3 m; rod A at 0.6 m over [200, 220),
        // rod B at 0.9 m from 226 to 241, both through every row. B's shift on the board is
        // 43.67·(1/0.9 − 1/1.2) = 12.1 px: its attached shadow [214, 226) lies behind A up to
        // 220. The widening moves B's left edge by 0–2 px from row to row, so the rows above
        // show B over the hole's last columns, and nothing at all over the rest: no overhang of
        // B, and the background is the board left of A.
        let (c, _) = params();
        let labels = wall_frame(|v, row| {
            row[150..400].fill(raw_at(&c, 1.2));
            row[128..150].fill(NO_DEPTH);
            row[164..184].fill(NO_DEPTH);
            row[200..220].fill(raw_at(&c, 0.6));
            row[220..226 + v % 3].fill(NO_DEPTH);
            row[226 + v % 3..241].fill(raw_at(&c, 0.9));
        });
        assert_rows(&labels, &[1, 100, 241, 478], 220..226, ATTACHED);
    }

    #[test]
    fn drums_shadow_half_hidden_by_a_30_px_rod_is_attached() {
        // A rod at 0.71 m over [400, 430) (3.7 cm) and a drum at 1.3 m from 448 on, both through
        // every row, before a wall at 3 m. The rod's own shadow lies 43.67·(1/0.71 − 1/3) =
        // 47.0 px left of it, at [353, 383), detached. The drum's, 43.67·(1/1.3 − 1/3) = 19.0 px,
        // lies at [429, 448), behind the rod up to 430: the hole [430, 448) between the nearer
        // rod and the farther drum is the drum's attached shadow on the wall seen left of the
        // rod. A rod of 30 px counts as thin (it used to need 24 or fewer: an independent
        // simulator's drum behind such a rod, complex IR attached F1 +0.008 on that suite).
        let (c, _) = params();
        let labels = wall_frame(|_, row| {
            row[353..383].fill(NO_DEPTH);
            row[400..430].fill(raw_at(&c, 0.71));
            row[430..448].fill(NO_DEPTH);
            row[448..600].fill(raw_at(&c, 1.3));
        });
        assert_rows(&labels, &[0, 1, 240, 479], 353..383, DETACHED);
        assert_rows(&labels, &[0, 1, 240, 479], 430..448, ATTACHED);
    }

    #[test]
    fn rod_as_wide_as_its_shift_stays_attached_where_the_widening_eats_its_edge_in_every_row() {
        // A 12 px rod [300, 312) at 1.645 m before a wall at 3 m: shift 12 px, as wide as the
        // rod, so its shadow [288, 300) is attached. The sensor's widening eats 1–2 px of the
        // rod's left edge in every row, so no row measures it 12 px wide; but no row shows a lit
        // gap between shadow and rod either.
        let (c, p) = params();
        let mut raw = vec![raw_at(&c, 3.0); PIXELS];
        for v in 0..HEIGHT {
            let eaten = 1 + v % 2;
            let row = &mut raw[v * WIDTH..(v + 1) * WIDTH];
            row[300..312].fill(raw_at(&c, 1.645));
            row[287..300 + eaten].fill(NO_DEPTH);
        }
        let (mut labels, mut filled) = (vec![0; PIXELS], vec![0; PIXELS]);
        classify_frame(&p, &raw, &mut labels, &mut filled);
        for v in [1, 100, 241, 478] {
            let hole = &labels[v * WIDTH + 287..v * WIDTH + 301];
            assert!(hole.iter().all(|&l| l == ATTACHED), "row {v}: {hole:?}");
        }
    }

    #[test]
    fn flying_pixel_joins_the_nearer_side_for_the_warp_only() {
        // Foreground 800, one mixed pixel at 830, background 900: 830 is nearer to 800.
        let mut row = vec![900u16; WIDTH];
        row[100..200].fill(800);
        row[200] = 830;
        row[300] = 880; // a gentle slope step elsewhere is no flying pixel
        let (labels, filled) = run_with_neighbours(&[], &row, &[]);
        assert_eq!(filled[200], 800);
        assert_eq!(labels[200], VALID, "the measured pixel keeps its label");
        assert_eq!(filled[300], 880);
        assert_eq!(&filled[..200], &row[..200]);
    }

    #[test]
    fn a_flying_pixel_is_snapped_in_any_column() {
        // The test skips blocks of columns without an edge step: an edge in any column, the
        // blocks' first and last included, still has its mixed pixel snapped. The step is just
        // over the edge step, so only the pair of pixels around the mixed one shows it.
        let (_, p) = params();
        let step = p.edge_raw + 2;
        for at in 3..WIDTH - 3 {
            let mut row = vec![800 + step; WIDTH];
            row[..at].fill(800);
            row[at] = 800 + step / 2 - 1;
            let (_, filled) = run_with_neighbours(&[], &row, &[]);
            assert_eq!(filled[at], 800, "mixed pixel in column {at}");
            assert_eq!(&filled[..at], &row[..at]);
            assert_eq!(&filled[at + 1..], &row[at + 1..]);
        }
    }

    #[test]
    fn a_steeply_receding_face_is_no_row_of_flying_pixels() {
        // A box face receding at 8 raw units (about a pixel of disparity) per pixel, from a
        // front face at 700 to a wall at 900: each of its pixels lies between its neighbours a
        // full edge step apart, yet it is a surface, and the warp must see it unbroken.
        let mut row = vec![900u16; WIDTH];
        row[100..200].fill(700);
        for (k, r) in row[200..225].iter_mut().enumerate() {
            *r = 700 + 8 * k as u16;
        }
        let (_, filled) = run_with_neighbours(&[], &row, &[]);
        assert_eq!(&filled[195..230], &row[195..230]);
    }

    #[test]
    fn shadow_two_lit_pixels_past_a_black_poster_is_read_on_its_own() {
        // A wall at 3 m, a box at 2 m over [100, 300) in rows 100..380: by hand (eq. 3) its
        // attached shadow is f·b·(1/2 − 1/3) px wide, left of column 100. A black poster on the
        // wall (no depth) ends two pixels of lit wall before the shadow: from the left border,
        // or from column 40. Read as one hole with the poster over those two pixels, the whole
        // was too wide for the box's shadow (or a border hole) and all of it OTHER.
        let (c, p) = params();
        let w = (c.fb() * (1.0 / 2.0 - 1.0 / 3.0)).round() as usize;
        assert_eq!(w, 7);
        for poster_from in [0, 40] {
            let mut raw = vec![raw_at(&c, 3.0); PIXELS];
            for v in 100..380 {
                let row = &mut raw[v * WIDTH..(v + 1) * WIDTH];
                row[poster_from..100 - w - 2].fill(NO_DEPTH);
                row[100 - w..100].fill(NO_DEPTH);
                row[100..300].fill(raw_at(&c, 2.0));
            }
            let (mut labels, mut filled) = (vec![0; PIXELS], vec![0; PIXELS]);
            classify_frame(&p, &raw, &mut labels, &mut filled);
            for v in [100, 240, 379] {
                let row = &labels[v * WIDTH..(v + 1) * WIDTH];
                assert_run(row, 100 - w..100, ATTACHED);
                assert_run(row, poster_from..100 - w - 2, OTHER);
            }
        }
    }

    #[test]
    fn noise_island_inside_shadow_does_not_split_it() {
        let (mut row, start, edge) = box_row(2);
        row[start + 10] = row[0]; // one spurious wall pixel inside the shadow
        let l = run(&row);
        assert_eq!(l[start + 10], VALID);
        assert!(l[start..edge]
            .iter()
            .enumerate()
            .all(|(i, &x)| i == 10 || x == ATTACHED));
    }

    #[test]
    fn right_border_and_full_rows_are_other() {
        let c = Calibration::nyu_default();
        let mut row = vec![raw_at(&c, 2.0); WIDTH];
        for r in &mut row[632..] {
            *r = NO_DEPTH;
        }
        assert!(run(&row)[632..].iter().all(|&x| x == OTHER));
        assert!(run(&[NO_DEPTH; WIDTH]).iter().all(|&x| x == OTHER));
    }

    #[test]
    fn left_border_uses_rows_above() {
        let c = Calibration::nyu_default();
        let (_, p) = params();
        let wall = raw_at(&c, 3.0);
        let mut row = vec![wall; WIDTH];
        for r in &mut row[20..200] {
            *r = raw_at(&c, 1.0);
        }
        for r in &mut row[..20] {
            *r = NO_DEPTH; // shadow cut by the border: 20 px of a 29 px shadow visible
        }
        let mut labels = vec![0; WIDTH];
        let mut filled = vec![0; WIDTH];
        classify_row(
            &p,
            &row,
            &[wall; WIDTH],
            &[],
            &[],
            Range::at(2046),
            &mut labels,
            &mut filled,
        );
        assert!(labels[..20].iter().all(|&x| x == ATTACHED));
        for r in &mut row[200..] {
            *r = raw_at(&c, 1.0); // the occluder reaches the right border: no background beside it
        }
        classify_row(
            &p,
            &row,
            &[NO_DEPTH; WIDTH],
            &[],
            &[],
            Range::at(2046),
            &mut labels,
            &mut filled,
        );
        assert!(
            labels[..20].iter().all(|&x| x == OTHER),
            "no background known: cannot tell"
        );
    }

    #[test]
    fn left_border_hole_under_a_region_never_measured_is_other() {
        // A frame of a wall at 3 m with a box at 1 m over columns [20, 200), rows [200, 400);
        // left of the box, columns [0, 20) of those rows are a hole, as wide as its attached
        // shadow there can show.
        let c = Calibration::nyu_default();
        let (_, p) = params();
        let (wall, near) = (raw_at(&c, 3.0), raw_at(&c, 1.0));
        let frame = |top_left: u16, box_rows: std::ops::Range<usize>| {
            let mut raw = vec![wall; PIXELS];
            for v in box_rows {
                raw[v * WIDTH + 20..v * WIDTH + 200].fill(near);
                raw[v * WIDTH..v * WIDTH + 20].fill(NO_DEPTH);
            }
            for v in 0..200 {
                // Above the box, the top left shows `top_left` (NO_DEPTH: beyond range).
                if raw[v * WIDTH] != NO_DEPTH {
                    raw[v * WIDTH..v * WIDTH + 40].fill(top_left);
                }
            }
            raw
        };
        let classify = |raw: &[u16]| {
            let (mut labels, mut filled) = (vec![0; PIXELS], vec![0; PIXELS]);
            classify_frame(&p, raw, &mut labels, &mut filled);
            labels
        };
        // The wall above measured: the box's attached shadow (the wall beside it the background).
        let labels = classify(&frame(wall, 200..400));
        for v in [200, 300, 399] {
            assert_run(&labels[v * WIDTH..(v + 1) * WIDTH], 0..20, ATTACHED);
        }
        // A wall beyond range above it (OTHER, nothing ever measured in those columns) reaching
        // down to the box: the same hole is that region, not a shadow with no lit wall above it.
        let labels = classify(&frame(NO_DEPTH, 200..400));
        for v in [200, 300, 399] {
            assert_run(&labels[v * WIDTH..(v + 1) * WIDTH], 0..20, OTHER);
        }
        // A box reaching the frame's top: its shadow runs down from the first row, whose label
        // the rows below follow.
        let labels = classify(&frame(wall, 0..400));
        for v in [0, 1, 200, 399] {
            assert_run(&labels[v * WIDTH..(v + 1) * WIDTH], 0..20, ATTACHED);
        }
    }

    #[test]
    fn left_border_hole_under_a_tall_unmeasured_region_is_other_where_it_narrows() {
        // A wall at 3 m, measured over rows [0, 100). Below, from the left border to a box at
        // 1 m whose left edge slants (column 80 at row 100 to 10 at row 450), a region beyond
        // range: every row's hole runs from the border to the box. Its attached shadow on the
        // wall would be 29.1 px (eq. 3), which the hole fits from row 300 or so on; the value
        // measured above (the wall, 200 rows up) once made those rows attached, though the
        // hole is the same region as in the rows above.
        let c = Calibration::nyu_default();
        let (_, p) = params();
        let (wall, near) = (raw_at(&c, 3.0), raw_at(&c, 1.0));
        let edge = |v: usize| 80 - (v - 100) / 5;
        let mut raw = vec![wall; PIXELS];
        for v in 100..HEIGHT {
            let e = edge(v);
            raw[v * WIDTH..v * WIDTH + e].fill(NO_DEPTH);
            raw[v * WIDTH + e..v * WIDTH + 400].fill(near);
        }
        let (mut labels, mut filled) = (vec![0; PIXELS], vec![0; PIXELS]);
        classify_frame(&p, &raw, &mut labels, &mut filled);
        for v in [100, 200, 300, 350, 400, 450] {
            assert_run(&labels[v * WIDTH..(v + 1) * WIDTH], 0..edge(v), OTHER);
        }
    }

    #[test]
    fn doorway_beyond_range_narrowed_by_a_nearer_object_to_its_shadows_width_stays_other() {
        // A wall at 3 m with a doorway onto a region beyond range: columns [200, 300), rows
        // [100, 400). From row 160 on a box at 1.4 m covers the doorway's columns from 223:
        // 43.67·(1/1.4 − 1/3) = 16.6 px is the attached shadow eq. (3) gives it on the wall,
        // and the 23 px of doorway left of it fit that within the widening eq. (3) allows. The
        // wall measured above the doorway (its lintel, in the column memory) once made the
        // doorway's rows beside the box attached.
        let c = Calibration::nyu_default();
        let (_, p) = params();
        let (wall, near) = (raw_at(&c, 3.0), raw_at(&c, 1.4));
        let mut raw = vec![wall; PIXELS];
        for v in 100..400 {
            raw[v * WIDTH + 200..v * WIDTH + 300].fill(NO_DEPTH);
            if v >= 160 {
                raw[v * WIDTH + 223..v * WIDTH + 330].fill(near);
            }
        }
        let (mut labels, mut filled) = (vec![0; PIXELS], vec![0; PIXELS]);
        classify_frame(&p, &raw, &mut labels, &mut filled);
        for v in [100, 159, 160, 161, 200, 300, 399] {
            let end = if v < 160 { 300 } else { 223 };
            assert_run(&labels[v * WIDTH..(v + 1) * WIDTH], 200..end, OTHER);
        }
        // The box's own attached shadow where the wall is lit, below the doorway, is found.
        let v = 420;
        let shadow = ((f64::from(wall) - f64::from(near)) / 8.0).round() as usize;
        assert!((16..=18).contains(&shadow), "{shadow}");
        raw[v * WIDTH + 223 - shadow..v * WIDTH + 223].fill(NO_DEPTH);
        raw[v * WIDTH + 223..v * WIDTH + 330].fill(near);
        classify_frame(&p, &raw, &mut labels, &mut filled);
        assert_run(
            &labels[v * WIDTH..(v + 1) * WIDTH],
            223 - shadow..223,
            ATTACHED,
        );
    }

    #[test]
    fn left_border_shadow_running_down_from_the_top_finds_the_wall_far_below() {
        // A box at 1.2 m over columns [10, 300), rows [0, 300), before a wall at 3 m: its
        // attached shadow, 43.67·(1/1.2 − 1/3) = 21.8 px, shows [0, 10) at the border (a pixel
        // more in odd rows, as the widening moves its edge). Nothing beside the box within 200 px
        // and nothing above: only the wall 300 rows below tells the background.
        let (c, _) = params();
        let labels = wall_frame(|v, row| {
            if v < 300 {
                let edge = 10 + v % 2;
                row[..edge].fill(NO_DEPTH);
                row[edge..300].fill(raw_at(&c, 1.2));
            }
        });
        assert_rows(&labels, &[0, 1, 150, 299], 0..10, ATTACHED);
        // The same wall receding upwards (half a raw unit a row) and beyond the sensor's range
        // above row 300, where only the box shows: carried up, the wall leaves the range long
        // before the box's rows, so the hole is that region, not a shadow on a lit wall.
        let labels = wall_frame(|v, row| {
            if v < 300 {
                row.fill(NO_DEPTH);
                row[10..300].fill(raw_at(&c, 1.2));
            } else {
                row.fill(raw_at(&c, 3.0) + ((HEIGHT - v) / 2) as u16);
            }
        });
        assert_rows(&labels, &[0, 1, 150, 299], 0..10, OTHER);
    }

    #[test]
    fn rods_shadow_on_a_board_merged_with_a_region_beyond_range_is_found_past_the_boards_shadow() {
        // A board at 2.2 m from column 150 before a wall at 3 m: attached shadow
        // 43.67·(1/2.2 − 1/3) = 5.3 px, [144, 150) where the wall shows, from row 240 down.
        // A rod at 1 m over [180, 192) casts on the board a shadow shifted by
        // 43.67·(1 − 1/2.2) = 23.8 px: [156, 168). Above row 240 the wall is beyond range and
        // the board's left part is missing, so one hole [0, 168) runs from the border: far too
        // wide for the board's attached shadow on the wall below, and its right part is the
        // rod's (eq. 5 at its end; the rows below, within 40, show the whole shadow).
        let (c, _) = params();
        let labels = wall_frame(|v, row| {
            row[150..400].fill(raw_at(&c, 2.2));
            row[if v < 240 { 0 } else { 144 }..150].fill(NO_DEPTH);
            row[if v < 240 { 150 } else { 156 }..168].fill(NO_DEPTH);
            row[180..192].fill(raw_at(&c, 1.0));
        });
        assert_rows(&labels, &[241, 400], 156..168, DETACHED);
        assert_rows(&labels, &[200, 239], 156..168, DETACHED);
        assert_rows(&labels, &[130, 200, 239], 0..140, OTHER);
    }

    #[test]
    fn left_border_shadow_on_a_floor_seen_only_past_a_wide_occluder_is_attached() {
        // A drum at 0.7 m over columns [20, 330) from row 100 down, in a room whose far wall is
        // beyond range: above row 300 nothing past the drum is measured; from row 300 a floor
        // nears from 3 m to 1.5 m at the bottom, the same depth across each row. The hole
        // [0, 20) at the border is narrower than the drum's attached shadow on the floor,
        // 43.67·(1/0.7 − 1/3) = 47.8 px at row 300 to 43.67·(1/0.7 − 1/1.5) = 33.3 px at the
        // bottom: the floor is lit up to the shadow, which runs on past the border. Only the
        // floor past the drum, 310 px right of the hole, tells it.
        let (c, _) = params();
        let floor = |v: usize| raw_at(&c, 3.0 - 1.5 * (v - 300) as f64 / 179.0);
        let labels = wall_frame(|v, row| {
            row.fill(if v < 300 { NO_DEPTH } else { floor(v) });
            if v >= 100 {
                row[..20].fill(NO_DEPTH);
                row[20..330].fill(raw_at(&c, 0.7));
            }
        });
        assert_rows(&labels, &[300, 301, 400, 479], 0..20, ATTACHED);
        // Above the floor the shadow falls beyond range: OTHER (SPEC §1).
        assert_rows(&labels, &[100, 200, 299], 0..20, OTHER);
        // Past the drum only a 30 px box at 2 m, then the region beyond range: no floor in
        // sight, so no background to measure the hole against.
        let labels = wall_frame(|v, row| {
            row.fill(NO_DEPTH);
            if v >= 100 {
                row[20..330].fill(raw_at(&c, 0.7));
                row[330..360].fill(raw_at(&c, 2.0));
            }
        });
        assert_rows(&labels, &[100, 300, 479], 0..20, OTHER);
    }

    #[test]
    fn left_border_finds_the_background_past_the_occluders_dark_right_face() {
        // A box at 1.2 m over columns [8, 170) before a wall at 3 m, its right face a hole
        // [170, 182) (grazing, or dark), and above it the box only. The hole [0, 8) is 8 px of
        // its attached shadow, 43.67·(1/1.2 − 1/3) = 21.8 px: the wall past the face tells it.
        let (c, p) = params();
        let classify = |face: usize, past: u16| {
            let mut row = vec![raw_at(&c, 3.0); WIDTH];
            row[..8].fill(NO_DEPTH);
            row[8..170].fill(raw_at(&c, 1.2));
            row[170..170 + face].fill(NO_DEPTH);
            row[170 + face..].fill(past);
            let (mut labels, mut filled) = (vec![0; WIDTH], vec![0; WIDTH]);
            let above = [raw_at(&c, 1.2); WIDTH];
            classify_row(
                &p,
                &row,
                &above,
                &[],
                &[],
                Range::at(2046),
                &mut labels,
                &mut filled,
            );
            labels
        };
        assert_run(&classify(12, raw_at(&c, 3.0)), 0..8, ATTACHED);
        // Past the hole the box's own depth: a region with no depth across the box, not its
        // edge; and a hole as wide as a region beyond range: no background in sight either.
        assert_run(&classify(12, raw_at(&c, 1.2)), 0..8, OTHER);
        assert_run(&classify(40, raw_at(&c, 3.0)), 0..8, OTHER);
    }

    #[test]
    fn left_border_uses_background_beside_the_occluder() {
        // The real NYU pole runs into the left border: rows above hold the pole, not the wall.
        let c = Calibration::nyu_default();
        let (_, p) = params();
        let mut row = vec![raw_at(&c, 3.4); WIDTH];
        for r in &mut row[8..30] {
            *r = raw_at(&c, 1.45);
        }
        for r in &mut row[..8] {
            *r = NO_DEPTH; // 8 of the pole's 17 px shadow
        }
        let (mut labels, mut filled) = (vec![0; WIDTH], vec![0; WIDTH]);
        classify_row(
            &p,
            &row,
            &[raw_at(&c, 1.45); WIDTH],
            &[],
            &[],
            Range::at(2046),
            &mut labels,
            &mut filled,
        );
        assert!(
            labels[..8].iter().all(|&x| x == ATTACHED),
            "{:?}",
            &labels[..10]
        );
    }
}
