//! Attached shadows of occluders that return no depth (black, glossy), split off by colour.
//!
//! Such an occluder and its attached shadow form one hole, so depth alone calls it all OTHER. The
//! RGB camera still sees both: the shadow is background (lit by the room, only not by the
//! projector), the occluder is whatever colour it is. For a shadow width `s` the occluder's
//! disparity is `disp(background) + s` (eq. 3), which fixes where it appears in the RGB image:
//! along the hole's row the RGB camera must see background, then the occluder (then background
//! again, the strip the occluder hides from the IR camera, when the background closes the hole on
//! the right). The split is the `s` whose layout matches the colours; it must clearly beat "no
//! shadow at all" (a black poster), and a row above or below must hold such a hole too and split
//! it alike, because an occluder is a solid (one, not both: towards a round occluder's poles its
//! edge moves several pixels per row, and its first and last rows have plain wall beyond them);
//! or, along a straight slanted edge, both split it with the same shadow width and their edges
//! average to this row's; or a row two away splits it alike. Variants of the same reading:
//!
//! - an *open* hole (running into the image border, another hole, a farther surface) is read from
//!   its left: background, then at least as much occluder as the shadow is wide;
//! - a hole whose left bound is a *nearer surface* hides part of the shadow, so the occluder's
//!   shift comes from its right edge, which the RGB camera sees moved left by a third of it;
//! - a hole with no shadow to split off still gets its occluder's depth from that right edge, so
//!   the warp finds the alignment shadow beside it;
//! - a hole at the *left border* has no background on its left: the strip of wall right of the
//!   occluder gives its shift, and the wall from the border to the occluder is its shadow
//!   (`depthless/left_border.rs`);
//! - a depthless occluder's *detached* shadow, a separate hole, is paired with the occluder's
//!   hole by colour where depth alone finds several candidates (`depthless/pairs.rs`);
//! - a hole the scanline called a thin Sb's attached shadow may hold a depthless object behind
//!   that Sb, its face and its shadow, read as a hole running on into a nearer surface
//!   (`depthless/behind_rod.rs`);
//! - an attached hole may end in its occluder's own side face, seen at a grazing angle, which
//!   the RGB camera shows in the occluder's hue (`depthless/face.rs`);
//! - a detached shadow's tail the scanline read at the right end of a hole it shares with a
//!   nearer object's dropout starts where the RGB camera sees the wall (`depthless/tail.rs`);
//! - a rod a few pixels wide and its shadow, one hole narrower than the split reads with the
//!   wall on both sides, are told apart column by column (`depthless/thin_rod.rs`).
//!
//! Runs on holes the scanline left OTHER (splits only on those at least 10 px wide, the thin
//! rod's reading on narrower ones; the thin-Sb reading on attached ones), after the scanline and
//! before the warp; nothing is allocated. A hole from the left border to a surface at the
//! range's end that shows that surface's colour over most of it is that surface beyond the
//! range: no occluder's depth is given to it.

use super::align::Simd;
use super::holes::HoleMask;
use super::scanline::{beyond_range_span, FrameFacts, Line, Range};
use crate::calib::Calibration;
use crate::labels::{ATTACHED, DETACHED, HEIGHT, NO_DEPTH, OTHER, WIDTH};

mod behind_rod;
mod cut_off;
mod dark;
mod dropouts;
mod face;
mod left_border;
mod limb;
mod offimage;
mod pairs;
mod patch;
mod rim;
mod rod_in_shadow;
mod second;
mod silhouette;
mod tail;
mod thin_rod;
mod twin;
mod unlike;

/// Narrowest merged hole considered (pixels): a shadow and an occluder of 5 px each. Narrower
/// ones are mostly the speckle of dark clutter on real frames, and cost time for little: 8, 7 or
/// 6 catch far thin black rods (complex attached F1 +0.006 on one suite of eleven, at most
/// +0.0003 on the others; at 6 also RGB alignment +0.009 on one and +0.002 on two) for +24,
/// +46 or +80 µs on the real frame.
const MIN_HOLE: usize = 10;
/// Narrowest hole with one surface on both sides [`ColourSplit::agreed_right_edge`] reads (a
/// thin glossy or black rod whose shadow is not paired with it).
const MIN_ROD_HOLE: usize = 8;
/// The least of [`ColourSplit::widened_edge`] (pixels): an open hole's shadow no wider is
/// refused whatever the frame's widening.
const MIN_OPEN_SHADOW: usize = 4;
/// Raw units past the scanline's range test at which a split-off shadow leaves the range. At
/// the scanline's own (0) a noise-free sensor (20 scenes) lost attached F1 (−0.0010): there the
/// farthest value of a frame can be a wall well within range, whose slope then reaches it a
/// fraction of a unit into the shadow. At 1, complex attached F1 +0.0217 on one suite of fourteen (a wall
/// slanting out of range behind a row of cylinders), +0.0027 on another, +0.0003 to +0.0006 on
/// six (among them one made after the change), −0.0001 on two; at 2, +0.0156 and +0.0016 on the
/// first two.
const RANGE_MARGIN: u16 = 1;
/// Raw units short of the range's limit at which a surface counts as at the range's end: the
/// last pixels of a surface receding out of range scatter that far below the limit.
pub(crate) const RANGE_END: u16 = 3;
/// Background samples taken on each side of the hole (IR pixels).
const SIDE: usize = 4;
/// Most pixels beside a hole a surface's slope is read over.
const SLOPE_RUN: usize = 24;
/// Steepest slope (disparity pixels per pixel) a plane is carried over a hole at: a surface at
/// 1 m turned 73° from facing the camera (b·tan θ / z).
const MAX_PLANE_SLOPE: f32 = 0.25;
/// Background pixels a hole at the image's left border needs left of it.
const BORDER_SIDE: usize = 2;
/// Disparity difference (pixels) within which the surfaces beside a hole are one background;
/// past it, the nearer one is another surface.
const SAME_SURFACE: f64 = 2.0;
/// Colour distance ([`hue_dist`], as every colour test here) beyond which an RGB pixel is not
/// background. Brightness alone, at 60, missed occluders as bright as the wall but of another
/// hue; with hue counted the camera's noise weighs more, and at 60 it split off one-row shadows
/// in a translucent bin on the real frame. Against brightness alone (at 60 and 45): complex IR
/// attached F1 +0.001 to +0.008 on nine suites of eleven, unchanged on two; detached +0.015 and
/// +0.005 on two; any-shadow precision −0.0015 to +0.0038; the real frame loses four one-row
/// shadows.
const COLOUR_STEP: u32 = 90;
/// Mean colour distance from the background that an occluder's RGB columns must reach: plainly
/// not background. A blue-grey glossy board on a pale wall is 100 to 110 away by brightness
/// alone; a mean of 120 missed such occluders (0.005 to 0.007 of complex scenes' attached F1).
const OCCLUDER_STEP: u32 = 90;
/// The two sides' background colours may differ by at most this much.
const SIDES_AGREE: u32 = 68;
/// Chromaticity difference (thousandths, summed over R, G, B) within which the two sides of a
/// hole are one surface in different light.
const CHROMA_AGREE: i32 = 20;
/// An occluder's contrast (colour distance from the background) per unit of the column step it
/// may raise ([`contrast_step`]): a black box (about 500 from a green wall) lets the wall's
/// columns drift by up to 125 and still count as wall. Against the plain step (with the hole's
/// first pixel read likewise): complex attached F1 +0.004 to +0.023 on eight of an independent
/// simulator's ten suites (textured and unevenly lit walls), the other two unchanged; this
/// project's 25 suites −0.0002 to +0.0036; the real frame's labels unchanged.
const CONTRAST_SHARE: u32 = 4;
/// The raised step at most, in halves of the plain one.
const CONTRAST_CAP: u32 = 4;
/// IR pixels of the wall left of a hole whose colours show its texture
/// ([`ColourSplit::wall_spread`]): at 3 m, 20 cm of wall. 24 px saw only one band of a wall
/// papered in bands as wide, and a shadow running onto the next band was cut at its edge (in runs
/// of rows, one checker square high): complex attached F1 +0.001 to +0.003 on five of the other
/// simulator's ten suites, −0.0001 on one; this project's 25 suites −0.0003 to +0.0003.
const SPREAD_SPAN: usize = 40;
/// RGB columns a closed hole's split layout may leave unexplained, however few it has.
const EDGE_MISSES: usize = 3;
/// Fewest pixels [`one_plane`] reads.
const MIN_PLANE: usize = 9;
/// How far (raw units) [`one_plane`] lets a pixel stray from the line through its span's ends:
/// the sensor's noise of a plane at a few metres. At 6 and 12, shaded objects passed for planes
/// and this project's suites lost 0.0012 and 0.0051 of complex attached F1 summed; at 1, the
/// sixth simulator's noisy walls passed for none.
const PLANE_TOLERANCE: i64 = 3;
/// The raised step at most, in halves of that texture's spread: a column may stray from the
/// wall's colour by half as much again as the wall itself does.
const SPREAD_NUM: u32 = 3;
/// How many times nearer the background's colour than the occluder's a column of an open hole
/// that strays past the step must be to count as background ([`ColourSplit::split`]). The
/// fourth simulator's 40 suites: complex IR attached F1 +0.036 summed (j39 +0.037), recall
/// +0.056, precision +0.002; at three times precision fell by 0.024 (shaded occluders' edges
/// read as background), at six the gain was a tenth. The real frame unchanged.
const NEARER_BG: u32 = 4;
/// Wall colours sampled left of an open hole ([`ColourSplit::wall_palette`]).
const PALETTE: usize = 16;
/// Pixels right of a palette sample that must hold no hole: the RGB camera sees a depthless
/// occluder a third of its shift left of its hole, over the wall there (a black rod crossing a
/// wall put its own colour into the palette, and the black box beside it was called wall).
const PALETTE_CLEAR: usize = 12;
/// How near (in halves of the colour step) a column's colour must come to one of the wall's
/// palette samples to count as wall. The samples are single pixels, whose noise alone strays by
/// tens: at one half, shadows across a checker's squares of two dim blues were cut at the first
/// square's edge (the fourth simulator: complex IR attached F1 +0.15 summed over 49 suites at
/// three halves, simple +0.03, any-shadow precision +0.001 and +0.02; at four halves complex
/// precision −0.003 more, simple attached −0.0015).
const PALETTE_MATCH: u32 = 3;
/// Columns of the background's own colour a closed hole read as an open one must show before
/// its wall's palette counts ([`ColourSplit::wall_palette`]). Three until the palette's match
/// widened to [`PALETTE_MATCH`]; two then gained complex IR attached F1 +0.0075 and simple
/// +0.012 summed over 51 suites (one: +0.012 more, but a black rod before bands of two hues came
/// out wide again, its any-shadow precision 0.964 → 0.942).
const PLAIN_FIRST: usize = 2;
/// Valid runs this short inside a hole are noise, stepped over: a lone pixel, as the scanline's
/// default ([`Params::max_island_px`](super::Params)) reads them; two are more often lit
/// background between two holes. (At 2, the fifth simulator's 28 suites: complex IR attached F1 −0.022
/// summed, detached −0.031, any-shadow precision −0.023, recall −0.014; this project's suites
/// within ±0.003.)
const MAX_ISLAND: usize = 1;
/// The occluder's left edge (hole start plus shadow width) may move by this much (pixels) from
/// row to row. Not the widths themselves: the sensor's widening moves each row's hole start by
/// 0–3 px, the occluder's edge stays put.
const ROWS_AGREE: usize = 3;
/// Share of the edge's run over the two rows around a row (pixels) that the shadow's width there
/// may stray from the row's in the straight-edge test of [`ColourSplit::agreed_split`]. Along
/// a box's top edge at a slant (nearly level, its edge 10 to 12 px further each row) a tenth
/// of a row's error in where the RGB camera sees the edge moves it a pixel, and the widths
/// strayed by 4 to 6 px: the edge's rows stayed OTHER. A colour edge slanting across a hole
/// that starts in one column narrows the shadow by its whole run from row to row, half the two
/// rows' run: a third keeps it refused (a half would not). Complex attached F1 +0.0030 on
/// seed 5150 (IR and RGB; +0.0019 at a quarter), +0.0001 to +0.0002 on seeds 9053 and
/// 27182818, the other suites and the real frame unchanged.
const SLANT_SHARE: usize = 3;
/// Occluder shifts read from the right edges of neighbouring rows may differ by this much (one
/// RGB column is about 3.4 px of shift).
const EDGE_AGREE: usize = 4;
/// Rows searched either side for a lit gap between a shadow and its occluder.
const GAP_ROWS: usize = 3;
/// Rows searched either side for a second row showing that gap in the same column. The
/// widening swallows a real gap in most rows (on simulated rods it shows every 4–6 rows); a
/// spurious valid pixel rarely has a twin within a column of it this near.
const GAP_CONFIRM_ROWS: usize = 3 * GAP_ROWS;
/// Pixels either side of the split searched for that lit gap.
const GAP_NEAR: usize = 3;
/// Narrowest dead band (pixels) along the right border that marks a real sensor's frame: the
/// NYU frame's is 8 px in every row, and just that (within a pixel) in 44 % of them.
pub(super) const DEAD_BAND: usize = 8;
/// Narrowest shadow (pixels) past the sensor's dead band that an occluder beyond the right border
/// is read to cast in a frame with the band ([`ColourSplit::off_image_attached`]), a few times
/// the band. A hole running a few pixels past the band is as often the band widened (a dark or
/// grazing surface at the border) as a shadow; a table's leg just past the border cast one of
/// 20–30 px in an independent simulator's frames, which have the band (two of its eight suites
/// changed: IR attached F1 +0.027 complex, +0.015 simple, any-shadow recall +0.045 and +0.024,
/// precision +0.0034; 16 px took a little more of the simple suite's, and claimed a panel's
/// shadow 13–16 px past the band; 8 px lost precision). The real frame: a near chair's shadow
/// at the border in six rows (135 px).
const PAST_BAND: usize = 20;
/// Narrowest open hole at the right border considered (pixels) in a frame with the sensor's dead
/// band there, wider than the band. Without the band (a simulator's frame) any hole is: a glossy
/// rod running off the border with its attached shadow made one of 30–40 px (an independent
/// simulator's suite, complex IR attached F1 0.819 → 0.861; over its 20 suites attached +0.048
/// summed, any-shadow recall +0.065, precision −0.008: a glossy box's shading at the border read
/// as an occluder).
const MIN_BORDER_HOLE: usize = 48;
/// RGB columns of occluder scored at least after the shadow of a hole that is not closed by
/// background (more for wider shadows: an attached shadow's occluder is at least as wide as it).
const OPEN_WINDOW: usize = 8;
/// Halves of the wall columns' largest distance from the wall's colour (before an open hole's
/// occluder) a pale occluder's face must keep from it to count as occluder within the column
/// step (at least half the step: a noise-free wall strays by nothing).
const FAINT_NUM: u32 = 3;
/// How many times the wall's largest distance from its own colour a pale occluder's edge must
/// step from it (its first columns past the first run of non-wall columns, within
/// [`EDGE_NEAR`]).
const PALE_EDGE: u32 = 4;
/// Pixels an open hole's occluder may fall short of its shift before it is too narrow for an
/// attached shadow ([`ColourSplit::occluder_too_narrow`]): the sensor's widening and the colour
/// edge's ±2 px (a quarter of the shift where that is more).
const NARROW_SLACK: usize = 6;
/// Pixels a closed hole's occluder must fall short of its shift (plus its right end's widening)
/// to be read as narrower than it ([`ColourSplit::gap_swallowed`]): past the colour edge's ±2 px.
/// At 2, the fifth simulator's complex attached F1 −0.017 summed against 3, at 4 −0.007 and
/// detached −0.021.
const SWALLOWED_MIN: f64 = 3.0;
/// Fewest RGB columns of alignment strip [`ColourSplit::no_strip_past`] reads.
const MIN_STRIP: usize = 6;
/// How far (RGB columns) an occluder's colour edge may lie from where a split's layout puts it.
const EDGE_NEAR: usize = 6;
/// How far (pixels) [`ColourSplit::slant_blend`] looks for the hole's start in the rows above
/// and below.
const SLANT_REACH: usize = 32;
/// Share of the frame's widening ([`ColourSplit::widen`]) by which a depthless occluder's right
/// edge lies left of its hole's end, where [`ColourSplit::right_edge`] reads it: the sensor
/// widens the hole into the surface after it too, and the RGB camera sees that surface over the
/// hole's last columns: read from the hole's end, the strip is too wide, and the occluder is
/// placed nearer than it is (each RGB column about 3.4 px of shift; a region beyond range before
/// a box, read as a black occluder, nearer than the box). Not all of the widening: the camera's
/// blur carries the occluder's colour a little past its edge. Summed over 32 fifth-simulator
/// suites, RGB alignment F1 at 0.5 / 0.7 / 1.0: complex +0.098 / +0.141 / +0.037, simple
/// +0.090 / +0.107 / +0.078 (at 1.0 complex any-shadow recall −0.024 too); this project's
/// suites −0.003 to 0.000, where only shadows widen. The RGB view's strips past depthless
/// occluders end by as much before their hole does ([`super::unseen::open_gaps`]).
pub(super) const EDGE_WIDENING: f64 = 0.7;

/// Per-calibration constants for the colour split.
#[derive(Clone, Debug)]
pub struct ColourSplit {
    /// Disparity pixels per raw unit, and the raw value of zero disparity.
    k: f64,
    den: f64,
    /// Inverse depth per raw unit (`iz = (den − raw)·iz_per_raw`).
    iz_per_raw: f64,
    /// Largest disparity of a surface the sensor can measure (at [`super::NEAREST_M`]).
    max_disp: f64,
    /// `R · K_depth⁻¹ · (0, v, 1)` per row, `R · K_depth⁻¹ · (1, 0, 0)`, and `t`: the ray of a
    /// pixel in the RGB camera's frame is `row_ray[v] + u·col_step + t·iz`.
    row_ray: Vec<[f64; 3]>,
    col_step: [f64; 3],
    t: [f64; 3],
    /// RGB focal lengths and principal point.
    rgb_f: [f64; 2],
    rgb_c: [f64; 2],
    /// Which build of the row loop this CPU runs (detected once).
    simd: Simd,
    /// The current frame's hole bitmap, one per row, made once at the start of
    /// [`ColourSplit::apply`] (spans in neighbouring rows are looked up many times).
    masks: Vec<HoleMask>,
    /// Scratch for [`ColourSplit::split`], reused so that nothing is zeroed or allocated per hole.
    prefix: Prefix,
    /// How many pixels the sensor's widening adds to a shadow's left end in the current frame
    /// ([`FrameFacts::left_widening`]).
    widen: f64,
    /// How much wider than eq. (3) an attached shadow may look (pixels): the scanline's
    /// `attached_over_px`.
    over: f64,
    /// The colour steps' factor for the current frame's camera noise, in 64ths
    /// ([`step_scale`](super::noise::step_scale)).
    noise_scale: u32,
    /// The current frame has the real sensor's dead band along its right border: narrower open
    /// holes there are that band, not shadows ([`MIN_BORDER_HOLE`]).
    dead_band: bool,
    /// Per row of the current frame, the left-border reading that held there, if one did
    /// ([`ColourSplit::left_border_attached`]).
    border: Vec<Option<left_border::BorderSplit>>,
    /// Per row of the current frame, that reading before the rows around agreed.
    border_read: Vec<Option<left_border::BorderSplit>>,
    /// Per row of the current frame, the shadow a split found there and
    /// [`ColourSplit::under_unmeasured`] refused, if one did.
    unmeasured: Vec<Option<(usize, usize)>>,
    /// Per row of the current frame, the first second occluder and shadow read in a split's
    /// hole ([`ColourSplit::second_pair`]), applied once the rows around agree.
    second: Vec<Option<second::Placed>>,
}

/// Prefix counts over the RGB columns under a hole of those that look like background, and the
/// memo of recent splits.
#[derive(Clone, Debug, Default)]
struct Prefix {
    bg_count: Vec<u32>,
    /// Recent splits by row and candidate: each row's is asked for up to three times (as the
    /// row, and as the neighbour of the rows above and below), and reads the RGB image once.
    memo: [Option<(usize, Candidate, Split)>; MEMO],
    next: usize,
    /// Recent holes of the row, for [`ColourSplit::detached_pair`].
    recent: pairs::Recent,
    /// The last split's first probe (row, hole start, background raw value, and whether the
    /// hole's first pixel looked like the background beside it): a hole read again from its
    /// left meets the same probe.
    first_probe: Option<(usize, usize, u16, bool)>,
}

/// Splits remembered (rows are visited in order, so a few suffice).
const MEMO: usize = 8;

/// A split: shadow width and occluder shift, if any.
type Split = Option<(usize, usize)>;

/// How well one shadow width explains the RGB row under a hole.
#[derive(Clone, Copy, Debug, Default)]
struct Layout {
    /// RGB columns whose colour matches the layout (background or not).
    hits: usize,
    /// RGB columns the layout calls shadow (background left of the occluder).
    shadow_cols: usize,
    /// The occluder's columns: the first, and how many.
    occluder_start: usize,
    occluder_cols: usize,
}

/// A merged hole `[a, b)` of one row and its background's raw value.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Candidate {
    a: usize,
    b: usize,
    bg: u16,
    /// A background bounds the hole on the right too. Otherwise the hole runs on into
    /// something else (another hole's labels, a second occluder, a slanted or farther surface,
    /// the image border) and only its left part, shadow then occluder, can be tested.
    closed: bool,
    /// A closed hole whose left bound is a nearer surface (the shadow fell on the background
    /// behind it, beside that surface's edge): `bg` and its colour are the right side's. Tried
    /// when the left-background reading fails (on a wall slanting away, the left side is nearer
    /// too, and is the background).
    behind: bool,
    /// The raw value of a nearer surface that ends an open hole on the right, if one does: the
    /// RGB camera sees that surface over the hole's right part, which is no occluder's colour.
    nearer_right: Option<u16>,
    /// A closed hole read as an open one ([`ColourSplit::opened`]).
    opened: bool,
    /// A farther surface bounds the hole on the right: the left side may be an object whose
    /// shadow fell behind it ([`Candidate::behind`]), and its colour no background's.
    farther_right: bool,
}

impl ColourSplit {
    /// Constants for `calib`, and the scanline's `attached_over_px` (`over`).
    pub fn new(calib: &Calibration, over: f64) -> Self {
        let d = calib.depth;
        let r = calib.depth_to_rgb.rotation;
        let rot = |x: f64, y: f64, z: f64| {
            let v = r * nalgebra::Vector3::new(x, y, z);
            [v.x, v.y, v.z]
        };
        let t = calib.depth_to_rgb.translation;
        ColourSplit {
            k: calib.px_per_raw(),
            den: calib.raw.denominator,
            iz_per_raw: 1.0 / calib.raw.numerator,
            max_disp: calib.fb() / super::NEAREST_M,
            row_ray: (0..HEIGHT)
                .map(|v| rot(-d.cx / d.fx, (v as f64 - d.cy) / d.fy, 1.0))
                .collect(),
            col_step: rot(1.0 / d.fx, 0.0, 0.0),
            t: [t.x, t.y, t.z],
            rgb_f: [calib.rgb.fx, calib.rgb.fy],
            rgb_c: [calib.rgb.cx, calib.rgb.cy],
            simd: Simd::detect(),
            masks: vec![HoleMask::of(&[]); HEIGHT],
            border: vec![None; HEIGHT],
            border_read: vec![None; HEIGHT],
            second: vec![None; HEIGHT],
            unmeasured: vec![None; HEIGHT],
            prefix: Prefix {
                bg_count: vec![0; WIDTH + 1],
                ..Prefix::default()
            },
            widen: 0.0,
            over,
            noise_scale: 64,
            dead_band: false,
        }
    }

    /// Splits merged holes of frame `raw` (IR view) using the RGB image `rgb` (RGB8, 640·480):
    /// the shadow part becomes ATTACHED in `labels` (DETACHED behind an occluder narrower than
    /// its shift), and the occluder part of `filled` is set to the raw value its shadow (or its
    /// right edge) implies, so the warp puts it where it stands. `labels`, `filled` and `facts`
    /// are the scanline's ([`classify_frame`](super::scanline::classify_frame)): part of a
    /// shadow split off on a surface receding past the range is OTHER, as the scanline's own
    /// are, and a shadow's width less the sensor's widening is its occluder's shift.
    pub fn apply(
        &mut self,
        raw: &[u16],
        rgb: &[u8],
        facts: FrameFacts,
        labels: &mut [u8],
        filled: &mut [u16],
    ) {
        // SAFETY: each build runs only when the CPU reported its features at construction.
        #[cfg(target_arch = "x86_64")]
        match self.simd {
            Simd::Avx512 => return unsafe { self.apply_avx512(raw, rgb, facts, labels, filled) },
            Simd::Avx2 => return unsafe { self.apply_avx2(raw, rgb, facts, labels, filled) },
            Simd::Baseline => {}
        }
        self.apply_body(raw, rgb, facts, labels, filled);
    }

    /// The colour steps' factor the last frame's camera noise gave, in 64ths
    /// ([`step_scale`](super::noise::step_scale)); the warp's colour tests use it too.
    pub fn noise_scale(&self) -> u32 {
        self.noise_scale
    }

    /// Runs the given build of the row loop (tests compare the builds).
    #[cfg(test)]
    pub(crate) fn set_simd(&mut self, simd: Simd) {
        self.simd = simd;
    }

    /// The row loop compiled for AVX2: the rows' hole bitmaps and label scans vectorise.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,fma")]
    unsafe fn apply_avx2(
        &mut self,
        raw: &[u16],
        rgb: &[u8],
        facts: FrameFacts,
        labels: &mut [u8],
        filled: &mut [u16],
    ) {
        self.apply_body(raw, rgb, facts, labels, filled);
    }

    /// The row loop compiled for AVX-512.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx512f,avx512bw,avx512vl,avx512dq,avx2,fma")]
    unsafe fn apply_avx512(
        &mut self,
        raw: &[u16],
        rgb: &[u8],
        facts: FrameFacts,
        labels: &mut [u8],
        filled: &mut [u16],
    ) {
        self.apply_body(raw, rgb, facts, labels, filled);
    }

    #[inline(always)]
    fn apply_body(
        &mut self,
        raw: &[u16],
        rgb: &[u8],
        facts: FrameFacts,
        labels: &mut [u8],
        filled: &mut [u16],
    ) {
        let range = facts.range;
        // The range its shadows are held to: the scanline's, a raw unit further on.
        let split_range = Range {
            far: range.far.saturating_add(RANGE_MARGIN),
            limit: range.limit.saturating_add(RANGE_MARGIN),
        };
        let mut prefix = std::mem::take(&mut self.prefix);
        prefix.memo = [None; MEMO];
        prefix.recent = pairs::Recent::default();
        for (mask, row) in self.masks.iter_mut().zip(raw.chunks_exact(WIDTH)) {
            *mask = HoleMask::of(row);
        }
        self.widen = facts.left_widening;
        self.border.fill(None);
        self.border_read.fill(None);
        self.unmeasured.fill(None);
        self.second.fill(None);
        self.noise_scale = super::noise::step_scale(super::noise::rgb_noise(rgb));
        // A real sensor's dead band along the right border (8 px or more in every row) would
        // read as an occluder's shadow running into the border in every row. The band is the
        // sensor's own: wherever the scene is measured up to it, it is just that wide (the NYU
        // frame: 44 % of rows within a pixel of 8 px). A tall occluder's shadow running into the
        // border widens from row to row, and a region beyond range is wider still.
        let (mut band_rows, mut bare_rows) = (0, 0);
        for m in &self.masks {
            let hole = WIDTH - m.prev_valid_end(WIDTH);
            band_rows += usize::from(hole >= DEAD_BAND);
            bare_rows += usize::from((DEAD_BAND..=DEAD_BAND + 1).contains(&hole));
        }
        self.dead_band = 10 * band_rows >= 9 * HEIGHT && 5 * bare_rows >= HEIGHT;
        for v in 1..HEIGHT - 1 {
            let row = &raw[v * WIDTH..(v + 1) * WIDTH];
            let mask = &self.masks[v];
            // Each hole is visited once: from its first pixel, on to its end (islands of up to
            // MAX_ISLAND pixels included), going from hole to hole on the row's bitmap.
            let mut u = mask.next_hole(BORDER_SIDE);
            // Past the row's first hole, each visit starts after a span's end, where more than
            // MAX_ISLAND valid pixels precede it: its span starts at `u`.
            let mut first = true;
            // Where the camera stops seeing (the border, or the dead band along it): holes
            // further than the widest shadow from it cannot be an off-image occluder's shadow.
            let seen_to = mask.prev_valid_end(WIDTH);
            let off_image_from = seen_to.saturating_sub(self.off_image_disp(seen_to) as usize);
            while u < WIDTH - SIDE {
                let i = v * WIDTH + u;
                let (a, b) = if first {
                    hole_span(mask, row, u)
                } else {
                    (u, span_end(mask, row, u))
                };
                first = false;
                if labels[i] != OTHER {
                    let attached = labels[i] == ATTACHED;
                    if labels[i] == ATTACHED
                        && !self.unlike_its_surface(raw, rgb, labels, filled, v, (a, b))
                        && !self.occluder_behind_thin_sb(
                            raw,
                            rgb,
                            labels,
                            filled,
                            v,
                            (a, b),
                            &mut prefix,
                        )
                        && !self.rod_in_shadow(raw, rgb, labels, filled, v, (a, b))
                    {
                        // Last: a split above may leave a depthless occluder, nearer than Sa,
                        // whose face the RGB camera sees over the shadow at Sa's depth.
                        self.on_a_dark_surface(raw, rgb, labels, v, (a, b));
                    } else if labels[i] == DETACHED
                        && !self.wider_to_the_projector(raw, rgb, labels, v, (a, b))
                        && !self.detached_like_its_occluder(raw, rgb, labels, v, (a, b))
                    {
                        self.detached_on_a_dark_surface(raw, rgb, labels, v, (a, b));
                    }
                    // Whatever the readings above left of it: the occluder's own face the
                    // hole may end in.
                    if attached && labels[v * WIDTH + b - 1] == ATTACHED {
                        self.occluder_face_in_hole(raw, rgb, labels, filled, v, (a, b));
                        // Or Sa's own face, where Sa is the nearer side.
                        self.near_side_face(raw, rgb, labels, filled, v, (a, b));
                    }
                    if labels[i] == DETACHED {
                        self.remember_detached(raw, labels, &mut prefix.recent, v, (a, b));
                        // The scanline may leave a depthless occluder's part of the hole
                        // OTHER, past a thin rod's shadow (`unswallowed_gap`): it pairs whole.
                        if labels[v * WIDTH + b - 1] == OTHER {
                            self.detached_pair(
                                raw,
                                rgb,
                                labels,
                                filled,
                                &mut prefix.recent,
                                v,
                                (a, b),
                            );
                        }
                    }
                    u = mask.next_hole(b.max(u + 1));
                    continue;
                }
                // A detached shadow's tail the scanline found in the hole starts where the RGB
                // camera sees the wall.
                self.tail_on_its_wall(raw, rgb, labels, v, (a, b));
                // A shadow beside a patch without depth leaves the patch's part of the hole to
                // the colour split below: a depthless occluder's own shadow may lie left of it.
                let patched = self.shadow_beside_patch(raw, rgb, labels, v, (a, b));
                if !patched && self.dropout_pair(raw, rgb, labels, filled, v, (a, b)) {
                    u = mask.next_hole(b.max(u + 1));
                    continue;
                }
                if !patched
                    && self.detached_pair(raw, rgb, labels, filled, &mut prefix.recent, v, (a, b))
                {
                    u = mask.next_hole(b.max(u + 1));
                    continue;
                }
                if !patched && self.thin_rod_shadow(raw, rgb, labels, filled, v, (a, b)) {
                    u = mask.next_hole(b.max(u + 1));
                    continue;
                }
                if !patched
                    && a >= off_image_from
                    && self.off_image_detached(raw, rgb, v, (a, b), seen_to)
                {
                    relabel(&mut labels[v * WIDTH + a..v * WIDTH + b], OTHER, DETACHED);
                    u = mask.next_hole(b.max(u + 1));
                    continue;
                }
                if !patched
                    && b == WIDTH
                    && (!self.dead_band || b - a >= DEAD_BAND + PAST_BAND)
                    && self.off_image_attached(raw, rgb, v, (a, b), range)
                {
                    // Where the wall beside it leaves the range, so does the shadow. The
                    // sensor's dead band is no part of it (nothing is measured there, lit or not).
                    let (done, rest) = labels.split_at_mut(v * WIDTH);
                    let labels_row = &mut rest[..WIDTH];
                    let to = if self.dead_band { b - DEAD_BAND } else { b };
                    relabel(&mut labels_row[a..to], OTHER, ATTACHED);
                    beyond_range_span(
                        row,
                        (a, to),
                        split_range,
                        &done[(v - 1) * WIDTH..],
                        labels_row,
                    );
                    let span = &mut labels_row[a..to];
                    let out = span.iter().filter(|&&l| l == OTHER).count();
                    if out > span.len() - out {
                        relabel(span, ATTACHED, OTHER);
                    }
                    u = mask.next_hole(b.max(u + 1));
                    continue;
                }
                // A hole from the left border has no background on its left for the reading
                // below: a depthless occluder's strip of wall on its right tells its shift.
                if a == 0 && !patched {
                    let split = self.left_border_attached(raw, rgb, v, b, range);
                    self.border_read[v] = split;
                    if let Some(split) =
                        split.filter(|&s| self.border_agreed(raw, rgb, v, s, range))
                    {
                        split.apply(v, labels, filled);
                        self.border[v] = Some(split);
                        u = mask.next_hole(b.max(u + 1));
                        continue;
                    }
                }
                // The background on the left first; failing that, a nearer surface on the left
                // with the background behind it showing on the right.
                // A hole running into the right border where the wall beside it reaches the
                // range's end lies beyond the range (the occluder it shows is on that wall).
                // (Narrower ones are no candidates beside the dead band: the test is read only for
                // those that are.)
                let beyond = b == WIDTH
                    && (b - a >= MIN_BORDER_HOLE || !self.dead_band)
                    && a > 0
                    && self.leaves_range(raw, v, a, range) == Some(true);
                let split = (raw[i - 1] != NO_DEPTH && !beyond)
                    .then(|| {
                        [false, true].into_iter().find_map(|behind| {
                            let c = self.candidate(raw, labels, v, (u, b), false, behind)?;
                            if let Some(s) = self.agreed_split(raw, rgb, labels, v, c, &mut prefix)
                            {
                                return Some((c, s));
                            }
                            // A hole too wide for one shadow whose occluder stops short of
                            // its end, or whose sides are one surface in another light (a
                            // shaded or patterned wall), on another square of its pattern (a
                            // checker of two hues) or two surfaces at one depth: read from the
                            // left only. The left side's colour is then the background only if
                            // the RGB camera sees it on over the wall further left: over a black
                            // occluder's own hole it sees that occluder there.
                            // Two surfaces: the left one is the background, read at its own
                            // depth (the closed reading took the farther side's). One surface
                            // runs on across the hole, as the closed reading saw it.
                            let bg = c.bg;
                            if !c.closed
                                || c.behind
                                || prefix.first_probe == Some((v, c.a, bg, false))
                            {
                                return None;
                            }
                            let narrow = c.b - c.a <= self.widest(bg);
                            // The split's own probes beside the hole, read once for the three
                            // tests of its sides.
                            let sides = narrow
                                .then(|| self.side_probes(rgb, v, (c.a, b), bg))
                                .flatten();
                            let two = sides.is_some_and(|s| self.sides_two_surfaces(c.a, bg, s));
                            let dark = sides.is_some_and(|s| self.dark_between(rgb, v, &c, s));
                            let c =
                                self.opened(c, if two { raw[v * WIDTH + c.a - 1] } else { bg })?;
                            if narrow
                                && !dark
                                && !sides.is_some_and(|s| {
                                    (two || sides_differ_in_light(s)
                                        || self.sides_differ_by_texture(
                                            rgb,
                                            labels,
                                            v,
                                            (c.a, b),
                                            bg,
                                            s,
                                        ))
                                        && self.nothing_seen_before(row, rgb, v, c.a, c.bg, true)
                                })
                            {
                                return None;
                            }
                            Some((c, self.agreed_split(raw, rgb, labels, v, c, &mut prefix)?))
                        })
                    })
                    .flatten()
                    // Left of a shadow found beside a patch, the occluder ends where that shadow
                    // starts: an attached shadow's occluder is at least as wide as its shift
                    // (narrower, and the shadow is detached: a glossy rod's, before another
                    // object's shadow).
                    .filter(|&(c, (s, shift))| !patched || c.b >= c.a + s + shift)
                    .filter(|&(c, (s, _))| c.closed || s > self.widened_edge())
                    .filter(|&(c, (s, shift))| !self.occluder_too_narrow(row, c, b, s, shift));
                let split = match split {
                    Some((c, (s, shift)))
                        if !c.behind
                            && self.under_unmeasured(raw, rgb, labels, v, c, (s, shift)) =>
                    {
                        self.unmeasured[v] = Some((c.a, c.a + s));
                        None
                    }
                    split => split,
                };
                // (Beside a patch the hole's right end is Sb's shadow, no occluder's edge.)
                if split.is_none()
                    && !patched
                    && (self.limb_of_near_edge(raw, rgb, labels, filled, v, (a, b))
                        || self.rim_of_near_object(
                            raw,
                            rgb,
                            labels,
                            filled,
                            v,
                            (a, b),
                            split_range,
                        ))
                {
                    u = mask.next_hole(b.max(u + 1));
                    continue;
                }
                if split.is_none() && !patched {
                    // No shadow to split off, but an occluder's depth still places it in the RGB
                    // view, with the alignment shadow right of it. A rod narrower than MIN_HOLE
                    // the scanline paired with its shadow is placed already, by a sharper reading.
                    let placed = || {
                        b < WIDTH
                            && self.disp(filled[v * WIDTH + a])
                                > self.disp(raw[v * WIDTH + b]) + 1.0
                    };
                    let read = (b - a >= MIN_HOLE || !placed())
                        && !self.beside_a_nearer_right(raw, v, (a, b));
                    if let Some(shift) = read
                        .then(|| self.agreed_right_edge(raw, rgb, labels, v, (a, b), &mut prefix))
                        .flatten()
                    {
                        let at = self.raw_at_disp(self.disp(raw[v * WIDTH + b]) + shift as f64);
                        // A hole from the left border to a surface at the range's end may be
                        // that surface running on beyond the range, a rod standing in it: the
                        // rod's edge would read as a near occluder's, and the wall between it
                        // and the measured part as its alignment shadow.
                        let bg = raw[v * WIDTH + b];
                        let beyond = a == 0
                            && bg >= range.limit.saturating_sub(RANGE_END)
                            && self.hole_shows_background(rgb, v, (a, b), (at, bg), shift);
                        if !beyond {
                            filled[v * WIDTH + a..v * WIDTH + b].fill(at);
                        }
                    }
                }
                if let Some((c, (s, shift))) = split {
                    // An open candidate is read only so far into its hole, but the occluder may
                    // run on to the hole's end: where the RGB camera sees its right edge there
                    // at about the same shift, its depth runs on too (its alignment shadow
                    // opens). That edge may read short of the shadow's shift by up to a quarter
                    // of it (a broad glossy cylinder's: 31 against 41 px in a simulator written
                    // from SPEC alone, whose strip was lost in every row), or beyond it up to
                    // twice (a black box turned to the camera: its right edge nearer than its
                    // left; the same simulator, 27 against 17–21 px). A closed candidate's
                    // right edge is read too: a box turned away has it farther than its left
                    // (down to half the shift). So may an open one's: a black chair's back
                    // turned away, 17 against 23 px, before a striped wall whose stripes made
                    // its hole's sides differ (the sixth simulator: complex RGB alignment F1
                    // +0.0145 summed over ten suites, l1 +0.011, recall +0.008, precision
                    // −0.0011; this project's suites +0.0012, precision ±0; the real frame
                    // unchanged).
                    let read = (c.closed || (c.b < b && !patched))
                        .then(|| self.agreed_right_edge(raw, rgb, labels, v, (a, b), &mut prefix))
                        .flatten();
                    let edge = read.filter(|&t| {
                        t <= (shift + EDGE_AGREE).max(2 * shift)
                            && if c.closed {
                                2 * t >= shift
                            } else {
                                t + EDGE_AGREE.max(shift / 2) >= shift
                            }
                    });
                    let runs_on = !c.closed && edge.is_some();
                    let end = if runs_on { b } else { c.b };
                    // An occluder narrower than its shift lets the projector light background
                    // between it and its shadow (eqs. 4–5): detached. When the lit gap is a
                    // pixel or two, the sensor's widening swallows it in most rows, and its
                    // width against the shift is a tie the colour edge (±2 px) cannot break;
                    // but some row nearby shows the gap, and where it ends the occluder starts.
                    // Also for a closed hole read from the left alone (a black rod's shadow
                    // beside a wall shaded across it: an independent simulator's scene, 250 px
                    // of a frame otherwise called attached).
                    let gap = (c.closed || c.opened)
                        .then(|| self.lit_gap_near(raw, v, c.a + s, c.bg))
                        .flatten();
                    let swallowed =
                        gap.is_none() && end == b && self.gap_swallowed(c, s, shift, end);
                    let s = gap.map_or(s, |x| x - c.a);
                    let code = if gap.is_some() || swallowed {
                        DETACHED
                    } else {
                        ATTACHED
                    };
                    let widen = if c.behind { 0.0 } else { self.widen };
                    let at = self.raw_at_disp(self.disp(c.bg) + shift as f64 - widen);
                    let s = s.min(end - c.a);
                    for u in c.a..c.a + s {
                        // Islands inside keep their label.
                        let i = v * WIDTH + u;
                        if raw[i] == NO_DEPTH {
                            labels[i] = code;
                        }
                    }
                    // A shadow on the background left of the hole leaves the range where that
                    // background does (the scanline's test, from a raw unit further on). Where
                    // more of it leaves than stays, the colour change that ended the shadow is
                    // that background beyond range, not an occluder: no shadow and no occluder
                    // (an independent simulator's side walls meeting a region beyond range: with
                    // depth noise of σ 1 raw unit complex attached F1 +0.0075, RGB alignment
                    // +0.009, with σ 0.5 alignment +0.021; one of our suites attached +0.0023,
                    // alignment +0.0012, the others within ±0.0006).
                    let mut occluder = true;
                    if code == ATTACHED && !c.behind {
                        let (done, rest) = labels.split_at_mut(v * WIDTH);
                        let row = &mut rest[..WIDTH];
                        beyond_range_span(
                            &raw[v * WIDTH..(v + 1) * WIDTH],
                            (c.a, c.a + s),
                            split_range,
                            &done[(v - 1) * WIDTH..],
                            row,
                        );
                        let span = &mut row[c.a..c.a + s];
                        let out = span.iter().filter(|&&l| l == OTHER).count();
                        if out > span.len() - out {
                            relabel(span, ATTACHED, OTHER);
                            occluder = false;
                        }
                    }
                    if occluder && code == ATTACHED {
                        self.cut_off_by_thin(raw, labels, v, (c.a, c.a + s), (c.bg, shift));
                    }
                    // The occluder's pixels get its depth.
                    if occluder {
                        let span = &mut filled[v * WIDTH + c.a + s..v * WIDTH + end];
                        match edge {
                            // A face at an angle to the camera: each edge at its own shift,
                            // the depth between them on a line (the nearest corner of a turned
                            // box lies between them, so this is the farther reading there).
                            Some(t) if t.abs_diff(shift) > EDGE_AGREE && span.len() > 1 => {
                                // The left end's widening bears on the shadow's shift only.
                                let last = (span.len() - 1) as f64;
                                let d0 = self.disp(c.bg) + shift as f64 - widen;
                                let step = (self.disp(c.bg) + t as f64 - d0) / last;
                                for (k, f) in span.iter_mut().enumerate() {
                                    *f = self.raw_at_disp(d0 + step * k as f64);
                                }
                            }
                            _ => span.fill(at),
                        }
                    }
                    // The hole's right edge reads another shift than the split's occluder: a
                    // second occluder may stand there, its shadow past the first.
                    if occluder && code == ATTACHED && edge.is_none() && self.second[v].is_none() {
                        let right = read
                            .map(|t| self.raw_at_disp(self.disp(raw[v * WIDTH + b]) + t as f64));
                        self.second[v] =
                            self.second_pair(rgb, v, (c, s, at), b, right).map(|pair| {
                                second::Placed {
                                    pair,
                                    occluder: (c.a + s, at),
                                    wall: c.bg,
                                    b,
                                }
                            });
                    }
                }
                u = mask.next_hole(b.max(u + 1));
            }
        }
        self.prefix = prefix;
        self.bridge_left_border(raw, labels, filled);
        self.place_second_pairs(raw, labels, filled);
    }

    /// Whether the shadow a split puts at `[c.a, c.a + s)` of row `v` (its occluder at `shift`)
    /// lies under a hole of the row above that the split left OTHER over all of it, after the
    /// same surface: a region the sensor cannot measure (a far wall beyond range, seen past a
    /// partition's edge) running on down past a depthless object that stands in it, its colour
    /// like the partition's, so that the RGB camera sees the layout of a shadow and its
    /// occluder. A projector shadow's first row has the lit background above it (the projector
    /// is offset sideways, not up), its other rows the shadow. The region shows above the
    /// occluder's top: nothing measured up the hole's first column to the image's top, and past
    /// the occluder's last row up the same colour over the shadow's and occluder's columns.
    /// Each refused row is remembered for the next. (The scanline's `below_unmeasured`, for
    /// Sb's shadows, does the same from the rows' labels.) A fresh suite's black box before a
    /// far wall (seed 31415, scene 039): complex IR and RGB attached F1 +0.016, any-shadow
    /// precision +0.022 and +0.014; the six other suites within 8 px, the real frame unchanged.
    fn under_unmeasured(
        &self,
        raw: &[u16],
        rgb: &[u8],
        labels: &[u8],
        v: usize,
        c: Candidate,
        (s, shift): (usize, usize),
    ) -> bool {
        let (a, up) = (c.a, (v - 1) * WIDTH);
        let sa = raw[v * WIDTH + a - 1];
        // Sa's surface bounds the hole above too, over two pixels (one alone is an island in a
        // hole of the row above that starts further left); the row above is one the split read
        // (not the image's first), and its hole runs on at least as far as this one: a region,
        // not a shadow's ragged end.
        if v < 2
            || a < 2
            || s == 0
            || !self.on_surface(raw[up + a - 1], sa)
            || !self.on_surface(raw[up + a - 2], sa)
            || !labels[up + a..up + a + s].iter().all(|&l| l == OTHER)
        {
            return false;
        }
        let above = &raw[up..up + WIDTH];
        if span_end(&self.masks[v - 1], above, a) < c.b {
            return false;
        }
        // The RGB camera sees one surface over both: the shadow's first half (over the rest it
        // may see the occluder) and the hole above it. Below a depthless occluder's slanted or
        // rounded bottom, the hole above is that occluder, in its own colour.
        let half = a..a + s.div_ceil(2);
        let (Some(here), Some(there)) = (
            self.mean_colour(rgb, v, half.clone(), sa),
            self.mean_colour(rgb, v - 1, half, sa),
        ) else {
            return false;
        };
        if hue_dist(here, there) >= self.dimmed(COLOUR_STEP, here) {
            return false;
        }
        // Nothing measured up the hole's first column, to the image's top.
        if !(0..v - 1).all(|w| raw[w * WIDTH + a] == NO_DEPTH) {
            return false;
        }
        // The row above was refused so, and this row continues it; or, up the occluder's
        // columns to where the RGB camera stops seeing it, the row past its top shows the
        // region's colour over both the shadow's and the occluder's columns, and is a hole
        // there: no shadow above the occluder, the region running on. (A tall occluder's split
        // may fail in a row, and its shadow run on up the image past it: the walk reaches the
        // image's top, or the occluder's own colour.)
        if self.unmeasured[v - 1].is_some_and(|(l, r)| l < a + s && a < r) {
            return true;
        }
        let at = self.raw_at_disp(self.disp(c.bg) + shift as f64 - self.widen);
        let occluder = a + s..(a + s + OPEN_WINDOW).min(c.b);
        let colour = |w: usize, us: std::ops::Range<usize>, r: u16| self.mean_colour(rgb, w, us, r);
        let Some(seen) = colour(v, occluder.clone(), at) else {
            return false;
        };
        let like = |p: Option<[i32; 3]>, q: [i32; 3]| {
            p.is_some_and(|p| hue_dist(p, q) < self.dimmed(COLOUR_STEP, q))
        };
        let Some(top) = (1..v)
            .rev()
            .find(|&w| !like(colour(w, occluder.clone(), at), seen))
        else {
            return false;
        };
        // A row further up: the first row past the occluder may blend its edge with the region.
        let Some(past) = top.checked_sub(1).filter(|&w| w > 0) else {
            return false;
        };
        raw[past * WIDTH + a..past * WIDTH + a + s]
            .iter()
            .all(|&r| r == NO_DEPTH)
            && like(colour(past, a..a + s.div_ceil(2), sa), here)
            && like(colour(past, occluder, at), here)
    }

    /// Whether the depthless occluder an open hole's split puts right of its shadow (`s`
    /// pixels from `c.a`, at `shift`) is plainly narrower than its shift, where a surface
    /// farther than the occluder is measured from the hole's end `b` on: nothing nearer hides
    /// its right part there, so the IR camera sees all of it. So for a closed hole read as an
    /// open one, the wall on both sides (a glossy surface's dropout, its own colour and then a
    /// darker square of its pattern, read as a shadow and its occluder: the sixth simulator's
    /// twelve suites, complex IR attached F1 +0.011 summed, any-shadow precision +0.022, recall
    /// −0.001; this project's suites +0.002, recall −0.003; the real frame 1 px attached →
    /// OTHER). An attached shadow's occluder is at least as wide as its shift (narrower, and a
    /// lit gap parts them: detached), so the colour
    /// change the split read is no such occluder's edge (a glossy box's dropouts past its
    /// measured part show the box's own colour, then the next object's). An independent
    /// simulator's 16 suites: complex IR attached F1 +0.070 summed, any-shadow precision +0.090,
    /// recall −0.009 (k8 −0.002 at most: a rod's detached shadow it had called attached); this
    /// project's suites and the real frame unchanged.
    fn occluder_too_narrow(
        &self,
        row: &[u16],
        c: Candidate,
        b: usize,
        s: usize,
        shift: usize,
    ) -> bool {
        if c.closed || c.behind || c.b != b || b >= WIDTH || row[b] == NO_DEPTH {
            return false;
        }
        // Nearer the background than the occluder (the occluder's own measured part reads up to
        // the sensor's overestimate and widening short of its shift).
        let farther = self.disp(row[b]) < self.disp(c.bg) + shift as f64 / 2.0;
        let width = b.saturating_sub(c.a + s);
        farther && width + NARROW_SLACK.max(shift / 4) < shift
    }

    /// Whether a closed hole's depthless occluder (read as closed, or as open where the sides
    /// differ in light), right of a shadow `s` pixels wide at `shift` and ending at `end`, the
    /// hole's end, is plainly narrower than its shift, by no more than the widening of both ends
    /// of a lit gap swallows: then the projector lights a gap between occluder and shadow
    /// (eqs. 4–5), which no row shows. An attached shadow's occluder is at least as wide as its
    /// shift plus the widening of its right end. Narrower by more than the widening swallows, the
    /// gap would show, so another object's shadow covers it, and the run, touching its occluder,
    /// stays attached (a rod before a second rod's shadow). The frame's widening of a shadow's
    /// left end, the one it measures, stands for either end's. The fifth simulator's 30 suites:
    /// complex IR attached F1 +0.067 summed, detached +0.118, RGB attached +0.071, detached
    /// +0.112, any-shadow recall −0.009 (rows at the threshold become detached fragments that the
    /// consensus takes away); this project's suites within ±0.0007. (Closed readings alone:
    /// attached +0.053, detached +0.102.)
    fn gap_swallowed(&self, c: Candidate, s: usize, shift: usize, end: usize) -> bool {
        if !(c.closed || c.opened) || c.behind {
            return false;
        }
        let occluder = end.saturating_sub(c.a + s) as f64;
        let short = shift as f64 + self.widen - occluder;
        short > SWALLOWED_MIN && short <= 2.0 * self.widen + SWALLOWED_MIN
    }

    /// Whether the hole `[a, b)` of row `v` ends at a surface nearer than the one it starts after
    /// (by more than [`SAME_SURFACE`]): the layout of that nearer surface's attached shadow,
    /// whatever else the hole holds (a region beyond range, say). A colour change where the hole
    /// ends is then that surface's own edge, not a depthless occluder's right edge: where the
    /// sensor widened the shadow into the surface, the RGB camera sees the surface start a column
    /// or two before the hole ends, which read as an occluder a little nearer than the surface,
    /// filling the hole. Warped there, the hole's pixels covered the farther left surface's last
    /// columns in the RGB view (a fifth simulator's wall beside a region beyond range, a rod at
    /// 0.7 m right of it: 15 columns of wall read OTHER in every row). The fifth simulator's 30
    /// suites: complex RGB alignment F1 +0.051 summed, any-shadow precision +0.036, recall
    /// −0.001; this project's suites within 0.0001, the real frame unchanged.
    fn beside_a_nearer_right(&self, raw: &[u16], v: usize, (a, b): (usize, usize)) -> bool {
        let row = &raw[v * WIDTH..(v + 1) * WIDTH];
        a > 0
            && b < WIDTH
            && row[a - 1] != NO_DEPTH
            && self.disp(row[b]) > self.disp(row[a - 1]) + SAME_SURFACE
    }

    /// Where the nearest row to `v` (at most [`GAP_ROWS`] away) shows a lit gap within
    /// [`GAP_NEAR`] pixels of column `x`: a valid island (at most [`MAX_ISLAND`] pixels, at the
    /// background's depth `bg`) inside a hole, which another row within [`GAP_CONFIRM_ROWS`]
    /// shows ending in the same column (±1). Returns the column just past the island, where the
    /// occluder starts.
    fn lit_gap_near(&self, raw: &[u16], v: usize, x: usize, bg: u16) -> Option<usize> {
        let d_bg = self.disp(bg);
        let in_row = |w: usize| {
            let row = &raw[w * WIDTH..(w + 1) * WIDTH];
            (x.saturating_sub(GAP_NEAR).max(1)..(x + GAP_NEAR + 1).min(WIDTH - 1)).find_map(|u| {
                if row[u] == NO_DEPTH || row[u - 1] != NO_DEPTH {
                    return None;
                }
                let len = row[u..]
                    .iter()
                    .take(MAX_ISLAND + 1)
                    .take_while(|&&r| r != NO_DEPTH)
                    .count();
                (len <= MAX_ISLAND
                    && u + len < WIDTH
                    && row[u + len] == NO_DEPTH
                    && (self.disp(row[u]) - d_bg).abs() < SAME_SURFACE)
                    .then_some(u + len)
            })
        };
        let nearest = (0..=GAP_ROWS).find_map(|k| {
            let up = v.checked_sub(k).and_then(in_row);
            up.or_else(|| (v + k < HEIGHT).then(|| in_row(v + k)).flatten())
        })?;
        // A second row must show it in the same column: the sensor's spurious valid pixels
        // inside a shadow are single and scattered, a lit gap runs down the occluder's edge.
        let rows = v.saturating_sub(GAP_CONFIRM_ROWS)..(v + GAP_CONFIRM_ROWS + 1).min(HEIGHT);
        let seen = rows
            .filter(|&w| in_row(w).is_some_and(|end| end.abs_diff(nearest) <= 1))
            .count();
        (seen >= 2).then_some(nearest)
    }

    /// The widest attached shadow on a background at `raw` (pixels): its occluder at the
    /// nearest measurable depth.
    fn widest(&self, raw: u16) -> usize {
        (self.max_disp - self.disp(raw)).max(0.0) as usize
    }

    /// `step` for a background of colour `bg` ([`dimmed`]) and the current frame's noise.
    #[inline]
    fn dimmed(&self, step: u32, bg: [i32; 3]) -> u32 {
        dimmed(step, bg) * self.noise_scale / 64
    }

    fn disp(&self, raw: u16) -> f64 {
        self.k * (self.den - f64::from(raw))
    }

    /// Whether raw value `r` is measured and on the surface of raw value `s` (within
    /// [`SAME_SURFACE`] of disparity).
    fn on_surface(&self, r: u16, s: u16) -> bool {
        r != NO_DEPTH && (self.disp(r) - self.disp(s)).abs() < SAME_SURFACE
    }

    /// Whether IR pixels `us` of row `v` all lie on the surface of raw value `s`
    /// ([`Self::on_surface`]): one surface there, whose colour may be read over them.
    fn all_on_surface(&self, raw: &[u16], v: usize, us: std::ops::Range<usize>, s: u16) -> bool {
        raw[v * WIDTH + us.start..v * WIDTH + us.end]
            .iter()
            .all(|&r| self.on_surface(r, s))
    }

    /// Where (IR column, continuous) a depthless occluder filling a hole up to `b` ends: the
    /// hole's last pixel's right side, less [`EDGE_WIDENING`] of the frame's widening.
    fn occluder_right_edge(&self, b: usize) -> f64 {
        b as f64 - 0.5 - EDGE_WIDENING * self.widen
    }

    /// The widest strip (pixels) an open hole's left end may be its left surface's own edge,
    /// swallowed by the sensor's widening: the frame's median widening and a pixel, 4 at least
    /// (a Kinect's median is 2.3). A box's receding side before a region the sensor cannot
    /// measure shows its colour there in the RGB image, then the region's: a shadow that
    /// narrow with a dark occluder after it. (A fifth simulator, whose sensor widens every
    /// hole: any-shadow precision +0.006 to +0.030 on eight groups of scenes, recall at most
    /// −0.004; this project's suites unchanged within 0.001.)
    fn widened_edge(&self) -> usize {
        (2.0 * self.widen + 1.0).max(MIN_OPEN_SHADOW as f64).round() as usize
    }

    fn raw_at_disp(&self, d: f64) -> u16 {
        round(self.den - d / self.k).clamp(0, i64::from(NO_DEPTH - 1)) as u16
    }

    /// The hole `[a, b)` of row `v` as a candidate: wide enough, inside the image, with a
    /// measured background on its left; [`Candidate::closed`] when the same background (within
    /// 2 px of disparity) bounds it on the right. Its pixels must be OTHER, or, in a `neighbour`
    /// row, OTHER and shadow labels (the colour split's in the row above, the scanline's depthless
    /// pairs in the row below, which the scanline finds where a lit gap shows); a hole that runs
    /// on into pixels labelled otherwise is cut there and is open.
    fn candidate(
        &self,
        raw: &[u16],
        labels: &[u8],
        v: usize,
        (a, b): (usize, usize),
        neighbour: bool,
        behind: bool,
    ) -> Option<Candidate> {
        let row = v * WIDTH;
        // Two pixels of background suffice at the left border (the probe beside the hole reads
        // the second); elsewhere a hole starts after more.
        if a < BORDER_SIDE || b - a < MIN_HOLE {
            return None;
        }
        // The real sensor's dead band along the right border (25 to 34 px on the NYU frame) is an
        // open hole in every row: only wider ones can hold an occluder's shadow and part of it.
        // (A frame without the band, a simulator's or another sensor's, has no such holes.)
        if b == WIDTH && self.dead_band && b - a < MIN_BORDER_HOLE {
            return None;
        }
        let left = raw[row + a - 1];
        // A hole off the right border is as often the sensor's dead band there as an occluder
        // straddling it: only its left part is tested.
        let right = (b + SIDE <= WIDTH).then(|| raw[row + b]);
        let step = right.map_or(0.0, |r| self.disp(left) - self.disp(r));
        // One slanted surface on both sides (a turned glossy box's dropout) continues across the
        // hole: either side's slope, carried over it, lands on the other.
        let same_right = right.is_some()
            && (step.abs() <= SAME_SURFACE || self.slope_continues(&raw[row..row + WIDTH], a, b));
        if behind && !(right.is_some() && step > SAME_SURFACE) {
            return None;
        }
        // An open hole is read no further than its widest shadow and an occluder as wide.
        let reach = if same_right || behind {
            b
        } else {
            b.min(a + 2 * self.widest(left) + OPEN_WINDOW)
        };
        let allowed = |l: u8| l == OTHER || (neighbour && (l == ATTACHED || l == DETACHED));
        // Branch-free over the whole run first (vectorised); most runs are all allowed.
        let (rs, ls) = (&raw[row + a..row + reach], &labels[row + a..row + reach]);
        let blocked = |(&r, &l): (&u16, &u8)| (r == NO_DEPTH) & !allowed(l);
        let cut = if rs.iter().zip(ls).fold(false, |any, p| any | blocked(p)) {
            a + rs.iter().zip(ls).position(blocked).unwrap_or(reach - a)
        } else {
            reach
        };
        if cut - a < MIN_HOLE || (behind && cut < b) {
            return None;
        }
        let closed = (same_right || behind) && cut == b;
        let bg = match right {
            Some(r) if behind => r,
            Some(r) if closed => left.max(r),
            _ => left,
        };
        let nearer_right = right.filter(|&r| {
            !same_right && !closed && cut == b && r != NO_DEPTH && step < -SAME_SURFACE
        });
        Some(Candidate {
            a,
            b: cut,
            bg,
            closed,
            behind,
            opened: false,
            nearer_right,
            farther_right: right.is_some() && !same_right && step > SAME_SURFACE,
        })
    }

    /// Whether the surface on one side of the hole `[a, b)` of `row`, a plane over up to
    /// [`SLOPE_RUN`] valid pixels beside the hole ([`Line`]: at least 8, carried no further than
    /// three times that), lands within [`SAME_SURFACE`] of the first pixel on the other side.
    fn slope_continues(&self, row: &[u16], a: usize, b: usize) -> bool {
        let disp = |r: u16| self.disp(r) as f32;
        let (left, right) = (disp(row[a - 1]), disp(row[b]));
        // No plane this steep or gentler climbs the step between the sides over the hole.
        let across = (b - a + 1) as f32;
        if (left - right).abs() > MAX_PLANE_SLOPE * across + SAME_SURFACE as f32 {
            return false;
        }
        // Not so steep that a pixel's noise moves the landing by a step, and every pixel of the
        // run within half a pixel of the line (a round object's limb bends away from it); the
        // fit read last, as most holes fail the landing.
        let lands = |run: (usize, usize), at: usize, target: f32| {
            Line::through(row, run, disp).is_some_and(|line| {
                line.slope.abs() <= MAX_PLANE_SLOPE
                    && line.reach.contains(&at)
                    && (line.disp_at(at) - target).abs() <= SAME_SURFACE as f32
                    && line.fits(row, run, disp, 0.5)
            })
        };
        let valid = |side: &mut dyn Iterator<Item = &u16>| {
            side.take(SLOPE_RUN).take_while(|&&r| r != NO_DEPTH).count()
        };
        let run_left = valid(&mut row[..a].iter().rev());
        if lands((a - run_left, a), b, right) {
            return true;
        }
        let run_right = valid(&mut row[b..].iter());
        lands((b, b + run_right), a - 1, left)
    }

    /// The split of candidate `c` in row `v` (shadow width, occluder shift), if a row above or
    /// below holds a candidate; for an open hole a farther surface ends, one that splits alike.
    fn agreed_split(
        &self,
        raw: &[u16],
        rgb: &[u8],
        labels: &[u8],
        v: usize,
        c: Candidate,
        prefix: &mut Prefix,
    ) -> Split {
        // Depth first (the raw rows are in cache, the RGB image often is not): the rows above and
        // below must hold a candidate hole through the same column (the middle of a closed hole,
        // near the start of an open one, which may run on far past the occluder).
        let mid = if c.closed {
            (c.a + c.b) / 2
        } else {
            c.a + MIN_HOLE / 2
        };
        let neighbour = |w: usize| {
            let row = &raw[w * WIDTH..(w + 1) * WIDTH];
            // A lit island inside the neighbour's hole may sit right on `mid`.
            let at = [mid, mid - 1, mid + 1, mid - 2, mid + 2]
                .into_iter()
                .find(|&m| row[m] == NO_DEPTH)
                .or_else(|| {
                    // An open hole's start moves with a slanted edge, up to several pixels a
                    // row: the neighbour's hole may begin past `mid`.
                    let to = (mid + MIN_HOLE).min(WIDTH);
                    (!c.closed)
                        .then(|| (mid + 3..to).find(|&m| row[m] == NO_DEPTH))
                        .flatten()
                })?;
            let (a, b) = hole_span(&self.masks[w], row, at);
            let n = self.candidate(raw, labels, w, (a, b), true, c.behind)?;
            // An opened hole's neighbours are read the same way, where they are as wide: at
            // their left side's depth where this one is read at its own.
            let at_left = c.bg == raw[v * WIDTH + c.a - 1];
            Some(if c.opened {
                let bg = if at_left { row[n.a - 1] } else { n.bg };
                self.opened(n, bg).unwrap_or(n)
            } else {
                n
            })
        };
        // One suffices: the first and last rows of an occluder have plain wall beyond them, and a
        // neighbour's hole may be cut short (a speckle's lit pixels). Both were once wanted:
        // complex attached F1 +0.0001 to +0.0010 on the other simulator's ten suites and +0.0000
        // to +0.0020 on this project's 25, precision −0.0001 at most; the real frame unchanged.
        let (above, below) = (neighbour(v - 1), neighbour(v + 1));
        if above.is_none() && below.is_none() {
            return None;
        }
        // With one, the RGB camera must see the occluder in the hole's middle: its row may pass
        // just beyond an occluder's first or last row, and read a patterned wall's next band
        // as the occluder.
        if (above.is_none() || below.is_none()) && !self.occluder_in_middle(rgb, v, c) {
            return None;
        }
        let s = self.split_memo(raw, rgb, v, c, prefix)?;
        // Only an open hole that a farther surface ends on the right needs a row to split
        // alike: its left side may be an object whose shadow fell behind it, read as a wall.
        // Any other's split stands alone: the rows of a black rod's hole before a patterned
        // wall, or in a noisy colour image, each fail now and then in their own way, and lost
        // their shadows to their neighbours'. (The sixth simulator, twelve suites: complex IR
        // attached F1 +0.0207 summed for holes with one surface on both sides or read from the
        // left, any-shadow recall +0.0363, precision −0.0052; this project's suites +0.0083,
        // +0.0219, −0.0073, none worse than −0.0014. Then holes that run on into a nearer
        // surface, another hole or the border: +0.0166, +0.0303, −0.0055 and +0.0052, +0.0169,
        // −0.0080, none worse than −0.0020; the holdout's RGB precision 0.9810 → 0.9808 →
        // 0.9805; the real frame unchanged. Those ended by a farther surface as well: +0.0015,
        // precision −0.0062, RGB alignment −0.0044.)
        if c.closed || c.opened || !c.farther_right {
            return Some(s);
        }
        // Where each row's split puts the occluder's edge, and how wide its shadow is.
        let edge = c.a + s.0;
        let mut split_in = |w: usize, n: Candidate| {
            self.split_memo(raw, rgb, w, n, prefix)
                .map(|(t, _)| (n.a + t, t))
        };
        let up = above.and_then(|n| split_in(v - 1, n));
        if up.is_some_and(|(e, _)| e.abs_diff(edge) <= ROWS_AGREE) {
            return Some(s);
        }
        let down = below.and_then(|n| split_in(v + 1, n));
        let alike = down.is_some_and(|(e, _)| e.abs_diff(edge) <= ROWS_AGREE);
        // Or a straight slanted edge through all three rows, moving up to several pixels a row:
        // the neighbours' edges average to this one, and the hole's start moves with the edge,
        // so the shadow keeps its width (a colour edge slanting across a hole that starts in
        // one column would narrow the shadow row by row), within a share of the edge's run
        // ([`SLANT_SHARE`]).
        let straight = match (up, down) {
            (Some((eu, su)), Some((ed, sd))) => {
                let tol = ROWS_AGREE.max(eu.abs_diff(ed) / SLANT_SHARE);
                (eu + ed).abs_diff(2 * edge) <= ROWS_AGREE
                    && su.abs_diff(s.0) <= tol
                    && sd.abs_diff(s.0) <= tol
            }
            _ => false,
        };
        if alike || straight {
            return Some(s);
        }
        // On a textured wall every other row may fail its own split (a checker square's edge in
        // the hole), and then so did the rows between: a row two away that splits alike
        // confirms this one (the vertical consensus may fill the row between). Complex attached
        // F1 +0.0001 to +0.0016 on eight of the other simulator's ten suites, and on this
        // project's 25 −0.0001 to +0.0017 (any-shadow recall up to +0.0046, precision down to
        // −0.0011); on the real frame 6 px in two rows join the shadow the two rows above had.
        let two_away = [v.checked_sub(2), Some(v + 2).filter(|&w| w < HEIGHT)];
        two_away
            .into_iter()
            .flatten()
            .filter_map(|w| split_in(w, neighbour(w)?))
            .any(|(e, _)| e.abs_diff(edge) <= ROWS_AGREE)
            .then_some(s)
    }

    /// True when the RGB camera sees, in the middle of candidate `c`'s hole in row `v`, a colour
    /// plainly unlike the background beside it.
    fn occluder_in_middle(&self, rgb: &[u8], v: usize, c: Candidate) -> bool {
        let probe = |u: usize| self.probe(rgb, u, v, c.bg);
        let (Some(beside), Some(middle)) = (
            probe(if c.behind { c.b + 1 } else { c.a - 2 }),
            probe((c.a + c.b) / 2),
        ) else {
            return false;
        };
        hue_dist(middle, beside) >= self.dimmed(OCCLUDER_STEP, beside)
    }

    /// The colours beside the hole `[a, b)` of row `v` (at raw value `bg`) the tests of its
    /// sides compare: the split's own probes, left and right of it.
    fn side_probes(
        &self,
        rgb: &[u8],
        v: usize,
        (a, b): (usize, usize),
        bg: u16,
    ) -> Option<([i32; 3], [i32; 3])> {
        let probe = |u: usize| self.probe(rgb, u, v, bg);
        Some((probe(a - 2)?, probe((b + 1).min(WIDTH - 1))?))
    }

    /// True when the sides of the narrow closed hole `c` of row `v` (colours `l`, `r` from
    /// [`ColourSplit::side_probes`]) differ in colour, and the RGB camera sees something less
    /// than half as bright as either three quarters of the way along the hole, where an
    /// occluder standing in it would be: a black rod before a checkered or banded wall, whose
    /// shadow on the left is read from the left, however dimly the sides are lit. (Sides of one
    /// colour are one surface, and a dark patch between them a dropout's: a turned board's.)
    /// Not within a third of the widest shift of the left border
    /// ([`ColourSplit::sides_two_surfaces`]), nor beside sides too dim to show a darker thing
    /// (half of [`DIM_FLOOR`]: without it a real basement frame's dark ceiling, by a darker
    /// pipe, had 54 px called shadows). The sixth simulator: complex IR attached F1 +0.0166
    /// summed over twelve suites, detached +0.0030, any-shadow precision +0.0011, recall
    /// +0.0251; this project's suites +0.0006.
    fn dark_between(
        &self,
        rgb: &[u8],
        v: usize,
        c: &Candidate,
        (l, r): ([i32; 3], [i32; 3]),
    ) -> bool {
        if c.a < self.widest(c.bg) / 3 + SIDE {
            return false;
        }
        let bright = |p: [i32; 3]| p.iter().sum::<i32>();
        let lit = bright(l).min(bright(r));
        2 * lit >= DIM_FLOOR
            && hue_dist(l, r) > self.dimmed(SIDES_AGREE, l)
            && self
                .probe(rgb, (c.a + 3 * c.b) / 4, v, c.bg)
                .is_some_and(|q| 2 * bright(q) < lit)
    }

    /// True when the sides of a hole starting at `a` (raw value `bg`; colours `l`, `r` from
    /// [`ColourSplit::side_probes`]), one surface by depth, are two by colour, both lit well enough to tell: an occluder without depth stands
    /// where one surface ends before another a few centimetres behind it (a glossy rod at a
    /// cyan sphere's edge before a white wall), and its shadow on the left one must be read
    /// from the left. Not within a third of the widest shift of the left border, where the
    /// wall [`ColourSplit::nothing_seen_before`] reads is cut short: there the left side may
    /// be a near rod itself, seen by the RGB camera over the wall (a pale rod beside the
    /// border: seed 424242 lost 0.0055 of complex IR attached F1 and 0.0083 of precision).
    /// Nor on dark sides: black clutter's hues are the camera's noise (the real frame: 182 px
    /// of its holes called attached). Complex IR attached F1 +0.0010 on seed 5150 and +0.0002
    /// on seed 9053 (both sensors), the other suites within ±0.0001; on the real frame three
    /// RGB-view pixels at the end of one dark hole change.
    fn sides_two_surfaces(&self, a: usize, bg: u16, (l, r): ([i32; 3], [i32; 3])) -> bool {
        if a < self.widest(bg) / 3 + SIDE {
            return false;
        }
        let lit = |p: [i32; 3]| p.iter().sum::<i32>() >= DIM_FLOOR;
        lit(l) && lit(r) && hue_dist(l, r) > self.dimmed(SIDES_AGREE, l)
    }

    /// True when the wall left of the hole `[a, b)` of row `v` (raw value `bg`; colours `l`, `r`
    /// beside it from [`ColourSplit::side_probes`]) strays from its colour beside the hole as
    /// far as the wall right of the hole does: a patterned wall (a
    /// checker of two hues), whose next square the hole's right side may show. (An independent
    /// simulator's checkered walls: a black rod's attached shadow was left whole in most rows,
    /// complex IR attached F1 +0.0065 on its suite with a rotated RGB camera; the rest of its
    /// suites and this project's within +0.0001.)
    fn sides_differ_by_texture(
        &self,
        rgb: &[u8],
        labels: &[u8],
        v: usize,
        (a, b): (usize, usize),
        bg: u16,
        (l, r): ([i32; 3], [i32; 3]),
    ) -> bool {
        // A hole just right of a detached shadow is that shadow's occluder, whose image the RGB
        // camera sees moved left over the lit gap: no wall's pattern.
        let widest = self.widest(bg);
        if labels[v * WIDTH + a.saturating_sub(widest)..v * WIDTH + a].contains(&DETACHED) {
            return false;
        }
        // The wall's stretch, not the one next to the hole, where the RGB camera may see the
        // occluder.
        let Some(end) = a.checked_sub(widest / 3) else {
            return false;
        };
        let Some(start) = end.checked_sub(SPREAD_SPAN) else {
            return false;
        };
        let Some(m) = self.probe(rgb, (a + b) / 2, v, bg) else {
            return false;
        };
        // And an occluder beyond the texture's range shows in the hole (a black rod before a
        // checker; a glossy surface's dropouts show that surface's own pattern): one and a half
        // times it from the left side (twice, as this once asked, lost a black rod's shadow
        // before a magenta checker whose bright squares clip, in an independent simulator's
        // simple scenes: IR attached F1 +0.019 on j4, +0.006 and +0.005 on two more, complex
        // +0.013 summed over its 28 suites; this project's suites unchanged). The cheap
        // necessary test first: the wall's spread is at least the sides' difference. Under
        // twice, the occluder must also lie beyond the other side (the real frame's shelf: a
        // pale box between two dark sides was split; that simulator's j15 −0.0019, j7
        // +0.0007).
        let (sides, middle) = (hue_dist(l, r), hue_dist(m, l));
        // Under twice, beyond the other side too: a colour between the two is more of the
        // pattern (or of clutter between dark sides: a pale box in the real frame's shelf).
        if 2 * middle < 3 * sides || (middle < 2 * sides && hue_dist(m, r) < sides) {
            return false;
        }
        let spread = self.wall_spread(rgb, v, start..end, bg, l);
        sides <= spread && 2 * middle >= 3 * spread
    }

    /// The closed candidate `c` read as an open one (read no further than twice its widest
    /// shadow and a window). The closed layout wants the occluder to fill the hole up to the
    /// background on the right, which fails where something else runs the hole on (another
    /// object's detached shadow beside a glossy sphere, say), or where the two sides differ in
    /// light; read as open, only the shadow and a window of occluder after it must show. The
    /// caller decides when: a hole wider than any one shadow on its background (so an occluder
    /// stands in it), or one whose sides are one surface in different light or two surfaces at
    /// one depth.
    ///
    /// Its background is `bg`: the caller's. Where the sides are two surfaces it is the left
    /// side's raw value, no longer the farther of the two: against the right side's depth a
    /// left side up to 2 px nearer in disparity, and receding towards the hole, counted as no
    /// surface of the background, and the wall [`ColourSplit::nothing_seen_before`] reads was
    /// skipped (a glossy rod at a cyan sphere's edge: holdout complex IR attached F1 +0.0015,
    /// RGB +0.0014, RGB any-shadow precision −0.0002; the other suites within +0.0002, the
    /// real frame unchanged). Where they are one surface, that surface runs on across the hole
    /// and keeps the closed reading's depth: read at the nearer side's, two dropouts on a board
    /// turned from the camera, the first of its colour, the second dark, read as a black
    /// occluder's shadow.
    fn opened(&self, c: Candidate, bg: u16) -> Option<Candidate> {
        let widest = self.widest(bg);
        if !c.closed || c.behind {
            return None;
        }
        Some(Candidate {
            closed: false,
            opened: true,
            b: c.b.min(c.a + 2 * widest + OPEN_WINDOW),
            bg,
            ..c
        })
    }

    /// The shift of an occluder filling the hole `[a, b)` of row `v` up to the background on its
    /// right, read from where the RGB camera sees that edge ([`ColourSplit::right_edge`]), if
    /// the rows above and below, holes ending within a pixel of `b`, agree. (They once had to
    /// end at `b` itself, which a slanted edge denies every other row: complex RGB alignment F1
    /// +0.0004 to +0.019 on twelve suites of fourteen, the others unchanged, for about 2 % more
    /// instructions on the real frame, whose ragged hole ends reach the colour test more often.)
    fn agreed_right_edge(
        &self,
        raw: &[u16],
        rgb: &[u8],
        labels: &[u8],
        v: usize,
        (a, b): (usize, usize),
        prefix: &mut Prefix,
    ) -> Option<usize> {
        // Most holes this narrow are no occluder's, and are ruled out before any search. But a
        // nearer surface left of one (a rod before a black box) may hide all but a strip of it,
        // and a thin black rod before a wall leaves one as narrow, one surface on both sides
        // (its shadow not paired with it: on a black poster, or chained with other holes).
        let cur = &raw[v * WIDTH..(v + 1) * WIDTH];
        let step = (a > 0 && b < WIDTH && cur[a - 1] != NO_DEPTH)
            .then(|| self.disp(cur[a - 1]) - self.disp(cur[b]));
        let hidden = step.is_some_and(|s| s > SAME_SURFACE);
        let closed = step.is_some_and(|s| s.abs() <= SAME_SURFACE);
        let min_w = if closed {
            MIN_ROD_HOLE
        } else if hidden {
            MIN_HOLE
        } else {
            2 * MIN_HOLE
        };
        // The hole of row `w` through column `b − 1` (or `b − 2`), if it ends within `slant` of
        // `b` (a slanted edge moves a pixel or so a row) and the edge can be read from it.
        let hole = |w: usize, slant: usize| {
            let row = &raw[w * WIDTH..(w + 1) * WIDTH];
            let at = [b - 1, b - 2]
                .into_iter()
                .take(slant + 1)
                .find(|&x| row[x] == NO_DEPTH)?;
            let (a, end) = hole_span(&self.masks[w], row, at);
            if end.abs_diff(b) > slant || end + SIDE > WIDTH || row[end] == NO_DEPTH {
                return None;
            }
            let others = labels[w * WIDTH + a..w * WIDTH + end]
                .iter()
                .zip(&row[a..end])
                .any(|(&l, &r)| r == NO_DEPTH && l != OTHER && w >= v);
            (end - a >= min_w && !others).then_some((a, end))
        };
        // This row's hole is `[a, b)` itself.
        if b - a < min_w {
            return None;
        }
        hole(v, 0)?;
        let (above, below) = (hole(v - 1, 1)?, hole(v + 1, 1)?);
        // Along a slanted edge the ends move one way through the three rows.
        let ends = (above.1, below.1);
        if !(ends.0 <= b && b <= ends.1 || ends.0 >= b && b >= ends.1) {
            return None;
        }
        // A narrow one is a rod's only where both its ends run on through the three rows (the
        // sensor's own small holes in clutter do not; a speckle cluster this wide is rare).
        if closed && b - a < 2 * MIN_HOLE && (above.0.abs_diff(a) > 2 || below.0.abs_diff(a) > 2) {
            return None;
        }
        let t = self.right_edge(rgb, v, (a, b), raw, prefix)?;
        let mut agrees = |w: usize, span: (usize, usize)| {
            self.right_edge(rgb, w, span, raw, prefix)
                .is_some_and(|u| u.abs_diff(t) <= EDGE_AGREE)
        };
        (agrees(v - 1, above) && agrees(v + 1, below)).then_some(t)
    }

    /// The shift (disparity above the background right of it, `raw` at `b`) of an occluder whose
    /// right edge is the end `b` of the hole `[a, b)` in row `v`: the RGB camera, 2.5 cm to the
    /// right, sees background past that edge, in a strip as wide as a third of the shift (the
    /// alignment shadow). Requires occluder colour left of the strip and background colour in it
    /// and beyond.
    fn right_edge(
        &self,
        rgb: &[u8],
        v: usize,
        (a, b): (usize, usize),
        raw: &[u16],
        prefix: &mut Prefix,
    ) -> Option<usize> {
        let bg = raw[v * WIDTH + b];
        let d_bg = self.disp(bg);
        let widest = self.widest(bg);
        if widest < 3 {
            return None;
        }
        // RGB columns from the nearest occluder's edge minus a window to a few past the edge at
        // the background's depth.
        let edge = self.occluder_right_edge(b);
        let (xb, y) = self.project(edge, v, bg);
        let (xb, y) = (ceil(xb), round(y));
        let near = ceil(
            self.project(edge, v, self.raw_at_disp(d_bg + widest as f64))
                .0,
        );
        // The RGB camera sees an occluder left of where its hole lies at the background's
        // depth, by a third of its shift: left of the hole's own columns when the occluder is
        // narrower than that (a thin black rod). The window reaches there for a narrow hole with
        // one surface on both sides; a nearer surface on its left would fill the window with its
        // own colour, and a wider hole's left side is the occluder's.
        let thin = a > 0 && b - a < 2 * MIN_HOLE && {
            let left = raw[v * WIDTH + a - 1];
            left != NO_DEPTH && (self.disp(left) - d_bg).abs() <= SAME_SURFACE
        };
        let far_left = ceil(self.project(a as f64 - 0.5, v, bg).0);
        let x0 = if thin {
            near - OPEN_WINDOW as i64
        } else {
            (near - OPEN_WINDOW as i64).max(far_left)
        };
        let x1 = xb + SIDE as i64;
        if x0 < 0
            || x1 > WIDTH as i64
            || !(0..HEIGHT as i64).contains(&y)
            || x1 - x0 < MIN_HOLE as i64
        {
            return None;
        }
        let row = &rgb[3 * y as usize * WIDTH..3 * (y as usize + 1) * WIDTH];
        let px = |x: i64| -> [i32; 3] {
            let i = 3 * x as usize;
            [row[i].into(), row[i + 1].into(), row[i + 2].into()]
        };
        // Background colour: the measured pixels right of the hole.
        let mut sum = [0i32; 3];
        for u in b..b + SIDE {
            let (x, _) = self.project(u as f64, v, bg);
            let p = px(round(x).clamp(0, WIDTH as i64 - 1));
            for k in 0..3 {
                sum[k] += p[k];
            }
        }
        let bg_colour = sum.map(|s| s / SIDE as i32);
        let n = (x1 - x0) as usize;
        let bg_count = &mut prefix.bg_count[..];
        bg_count[0] = 0;
        let step = self.dimmed(COLOUR_STEP, bg_colour);
        // A patterned wall shows its other colours in the strip too (a black chair's strip on a
        // striped wall, its darker stripe: the edge was read a stripe early, no strip found).
        // Those of the wall right of the hole count as background where two of its samples
        // show them (a pattern repeats; a box's shaded side beside the hole does not), unlike
        // every column where the occluder should be (a doorway's far view), and not alone
        // between unlike columns (an edge's blend). The sixth simulator: RGB alignment F1
        // +0.033 summed over six suites, any-shadow recall +0.016, precision +0.0003; this
        // project's suites +0.009, +0.006, ±0. (Counted instructions of the real frame +5 %:
        // its textured walls put many colours in the palette, and most of its holes' right
        // edges are read: the palette is read only when a column past the window strays from
        // the background, and each column's verdict kept for its neighbours' tests.)
        let window: [[i32; 3]; OPEN_WINDOW / 2] = std::array::from_fn(|j| px(x0 + j as i64));
        let unlike = std::cell::OnceCell::new();
        let memo = std::cell::Cell::new([(-1i64, false); 4]);
        let striped = |k: i64| {
            if !(window.len() as i64..n as i64).contains(&k) {
                return false;
            }
            let slot = (k & 3) as usize;
            let mut seen = memo.get();
            if seen[slot].0 == k {
                return seen[slot].1;
            }
            let (qs, m) = unlike.get_or_init(|| {
                let (qs, m) = self.wall_palette(
                    &raw[v * WIDTH..(v + 1) * WIDTH],
                    rgb,
                    v,
                    b..(b + SPREAD_SPAN).min(WIDTH),
                    bg,
                );
                other_stripes(&qs[..m], bg_colour, step)
            });
            let p = px(x0 + k);
            let is = qs[..*m]
                .iter()
                .any(|&q| 2 * hue_dist(p, q) < PALETTE_MATCH * step)
                && window.iter().all(|&w| hue_dist(p, w) >= step);
            seen[slot] = (k, is);
            memo.set(seen);
            is
        };
        let plain = |k: i64| (0..n as i64).contains(&k) && hue_dist(px(x0 + k), bg_colour) < step;
        let columns = background_columns(n, step, |k| {
            let d = hue_dist(px(x0 + k as i64), bg_colour);
            let k = k as i64;
            if d >= step && striped(k) && (plain(k - 1) || striped(k - 1) || striped(k + 1)) {
                0
            } else {
                d
            }
        });
        for (k, is_bg) in columns.enumerate() {
            bg_count[k + 1] = bg_count[k] + u32::from(is_bg);
        }
        let (misses, t, o1) = self.fit_right_edge(&bg_count[..=n], x0, v, b, bg)?;
        let lo = o1.saturating_sub(OPEN_WINDOW);
        let occluder_cols = (o1 - lo) as u32;
        // A clean edge, an alignment strip of at least two columns, an occluder plainly not
        // background (a black poster's edge does not move: no strip).
        let strip = (xb - x0) as usize - o1.min((xb - x0) as usize);
        (misses <= 1
            && strip >= 2
            && occluder_cols >= (OPEN_WINDOW / 2) as u32
            && (lo..o1)
                .map(|k| hue_dist(px(x0 + k as i64), bg_colour))
                .sum::<u32>()
                >= self.dimmed(OCCLUDER_STEP, bg_colour) * occluder_cols)
            .then_some(t)
    }

    /// The occluder shift `t` whose right edge (IR column `b`, background `bg` beyond it) best
    /// explains the RGB columns from `x0` (prefix counts of background-coloured columns in
    /// `bg_count`, one more than the columns): at shift t the edge lands on column o1(t), with
    /// occluder in the window left of it and background from it on. o1 falls as t grows; the best
    /// column first (largest of the fewest misses: the smallest shift), then its shift by
    /// bisection. Returns the misses, the shift and the column.
    fn fit_right_edge(
        &self,
        bg_count: &[u32],
        x0: i64,
        v: usize,
        b: usize,
        bg: u16,
    ) -> Option<(u32, usize, usize)> {
        let (d_bg, widest, n) = (self.disp(bg), self.widest(bg), bg_count.len() - 1);
        if widest < 3 {
            return None;
        }
        let right = self.occluder_right_edge(b);
        let edge = |t: usize| {
            let at = self.raw_at_disp(d_bg + t as f64);
            (ceil(self.project(right, v, at).0) - x0).clamp(0, n as i64) as usize
        };
        let (lowest, highest) = (edge(widest), edge(3));
        let misses = |o: usize| {
            let lo = o.saturating_sub(OPEN_WINDOW);
            (bg_count[o] - bg_count[lo]) + ((n - o) as u32 - (bg_count[n] - bg_count[o]))
        };
        let (misses, o1) = (lowest..=highest)
            .map(|o| (misses(o), o))
            .min_by_key(|&(m, o)| (m, std::cmp::Reverse(o)))?;
        let (mut t, mut hi) = (3, widest);
        while t < hi {
            let mid = (t + hi) / 2;
            if edge(mid) > o1 {
                t = mid + 1;
            } else {
                hi = mid;
            }
        }
        // Every shift up to the one that moves the edge a column further lands on `o1` (one RGB
        // column is about 3.4 px of shift, so a few steps): the middle of them, not the
        // smallest, unbiased. (At column 0 the edge is clamped: no such range.)
        let mut past = t + 1;
        while o1 > 0 && past <= widest && edge(past) >= o1 {
            past += 1;
        }
        Some((misses, (t + past - 1) / 2, o1))
    }

    /// [`ColourSplit::split`], remembered for the rows around the current one.
    fn split_memo(
        &self,
        raw: &[u16],
        rgb: &[u8],
        v: usize,
        c: Candidate,
        prefix: &mut Prefix,
    ) -> Split {
        if let Some(&(_, _, hit)) = prefix.memo.iter().flatten().find(|m| m.0 == v && m.1 == c) {
            return hit;
        }
        let result = self.split(raw, rgb, v, c, prefix);
        prefix.memo[prefix.next] = Some((v, c, result));
        prefix.next = (prefix.next + 1) % MEMO;
        result
    }

    /// The mean colour the RGB camera sees at IR pixels `us` of row `v`, taken at raw value `raw`.
    #[inline]
    fn mean_colour(
        &self,
        rgb: &[u8],
        v: usize,
        us: std::ops::Range<usize>,
        raw: u16,
    ) -> Option<[i32; 3]> {
        let mut sum = [0i32; 3];
        for u in us.clone() {
            let (x, y) = self.project(u as f64, v, raw);
            let p = rgb_at(rgb, x, y)?;
            (0..3).for_each(|k| sum[k] += p[k]);
        }
        Some(sum.map(|s| s / us.len() as i32))
    }

    /// True when the RGB camera, looking at the hole `[a, b)` of row `v` as if an occluder at
    /// raw value `at` (`shift` px before the surface right of it, raw `bg`) stood there, sees
    /// that surface's colour over more of it than the occluder's attached shadow could cover
    /// (eq. 3 with the sensor's widening): then the hole is mostly that surface unmeasured (a
    /// wall running on beyond the range, shaded as it recedes) with an occluder somewhere in it
    /// at most, not an occluder and its shadow. A column shows the surface when its colour is
    /// nearer the surface's than the occluder's (read a few columns in from the hole's end).
    fn hole_shows_background(
        &self,
        rgb: &[u8],
        v: usize,
        (a, b): (usize, usize),
        (at, bg): (u16, u16),
        shift: usize,
    ) -> bool {
        const STEP: usize = 2;
        let shadow = shift as f64 + self.over + self.widen;
        if ((b - a) as f64) <= shadow {
            return false;
        }
        let wall = (b + SIDE <= WIDTH)
            .then(|| self.mean_colour(rgb, v, b..b + SIDE, bg))
            .flatten();
        // A few columns in from the occluder's right edge, which the reading places to ±2 px.
        let inside = b.saturating_sub(4).max(a);
        let (Some(wall), Some(occluder)) = (wall, self.probe(rgb, inside, v, at)) else {
            return false;
        };
        let like = (a..b)
            .step_by(STEP)
            .filter_map(|u| self.probe(rgb, u, v, at))
            .filter(|&c| hue_dist(c, wall) < hue_dist(c, occluder))
            .count();
        (STEP * like) as f64 > shadow
    }

    /// The mean colour of the three RGB columns nearest IR pixel (`u`, `v`) seen at raw value
    /// `raw` ([`rgb_mean3`]), if inside the image: one probe, less noisy than a single pixel.
    fn probe(&self, rgb: &[u8], u: usize, v: usize, raw: u16) -> Option<[i32; 3]> {
        let (x, y) = self.project(u as f64, v, raw);
        rgb_mean3(rgb, x, y)
    }

    /// True when the RGB camera, past where it would see the right edge of the open hole `c`'s
    /// occluder at raw value `at` (at the hole's end, a farther surface measured past it), shows
    /// the occluder's colour `occluder` rather than that surface's: an occluder that near leaves
    /// a strip of the farther surface the IR camera does not see (the alignment shadow, a third
    /// of the shift wide); none there, the colour change the split read lies at about the farther
    /// surface's depth (a glossy box's dropouts, then its next face). Only strips of
    /// [`MIN_STRIP`] columns or more are read; most columns of the strip's first half must be
    /// twice as close to the occluder's colour as to the surface's (merely closer, a mottled
    /// wall's other colour in a real strip passed for the occluder). (An independent simulator's 16 suites: complex IR
    /// attached F1 +0.064 summed, any-shadow precision +0.087, recall −0.005, RGB alignment
    /// +0.066; k3 precision +0.033, k10 +0.021; this project's suites and the real frame
    /// unchanged.)
    fn no_strip_past(
        &self,
        raw: &[u16],
        rgb: &[u8],
        v: usize,
        c: Candidate,
        at: u16,
        occluder: [i32; 3],
    ) -> bool {
        if c.b + SIDE > WIDTH {
            return false;
        }
        let r = raw[v * WIDTH + c.b];
        if r == NO_DEPTH {
            return false;
        }
        let (xo, yo) = self.project(c.b as f64 - 0.5, v, at);
        let (xf, yf) = self.project(c.b as f64 - 0.5, v, r);
        if xf - xo < MIN_STRIP as f64 {
            return false;
        }
        let Some(far) = self.mean_colour(rgb, v, c.b..c.b + SIDE, r) else {
            return false;
        };
        // The strip's first half, past the column the lens blends (a surface at about the
        // farther one's depth ends further right, and a real strip may hold its edge's blend).
        let (x0, x1) = (ceil(xo) + 1, ceil((xo + xf) / 2.0));
        let y = (yo + yf) / 2.0;
        let mut like = 0;
        for x in x0..x1 {
            let Some(p) = rgb_at(rgb, x as f64, y) else {
                return false;
            };
            like += i64::from(2 * hue_dist(p, occluder) < hue_dist(p, far));
        }
        2 * like > x1 - x0
    }

    /// True when `colour`, read where a layout puts the occluder of the open hole `c` (row
    /// `v`), is the colour of the farther surface right of the hole: that surface, seen through
    /// the hole (its own dropouts, or a shadow on it), not an occluder nearer than the
    /// background.
    fn shows_farther_right(
        &self,
        raw: &[u16],
        rgb: &[u8],
        v: usize,
        c: Candidate,
        colour: [i32; 3],
    ) -> bool {
        let row = &raw[v * WIDTH..(v + 1) * WIDTH];
        let Some(&r) = row.get(c.b).filter(|&&r| r != NO_DEPTH) else {
            return false;
        };
        let end = (c.b + SIDE).min(WIDTH);
        if row[c.b..end].contains(&NO_DEPTH) {
            return false;
        }
        self.mean_colour(rgb, v, c.b..end, r)
            .is_some_and(|q| hue_dist(colour, q) < self.dimmed(COLOUR_STEP, q))
    }

    /// Up to [`PALETTE`] colours the RGB camera sees on the wall at IR pixels `wall` of row `v`,
    /// evenly spread over it: single pixels, of those on the background (raw value `bg`, within
    /// [`SAME_SURFACE`]; a farther wall or an object beside it is no part of its pattern).
    pub(super) fn wall_palette(
        &self,
        row: &[u16],
        rgb: &[u8],
        v: usize,
        wall: std::ops::Range<usize>,
        bg: u16,
    ) -> ([[i32; 3]; PALETTE], usize) {
        self.wall_palette_clear(row, rgb, v, wall, bg, PALETTE_CLEAR)
    }

    /// [`Self::wall_palette`] with pixels within `clear` of a hole on their right left out.
    pub(super) fn wall_palette_clear(
        &self,
        row: &[u16],
        rgb: &[u8],
        v: usize,
        wall: std::ops::Range<usize>,
        bg: u16,
        clear: usize,
    ) -> ([[i32; 3]; PALETTE], usize) {
        let mut out = ([[0; 3]; PALETTE], 0);
        let step = (wall.len() / PALETTE).max(1);
        let d_bg = self.disp(bg);
        for u in wall.step_by(step) {
            let r = row[u];
            // Left of a hole the RGB camera may see its depthless occluder over the wall.
            if out.1 == PALETTE
                || r == NO_DEPTH
                || (self.disp(r) - d_bg).abs() > SAME_SURFACE
                || self.masks[v].next_hole(u) <= u + clear
            {
                continue;
            }
            let (x, y) = self.project(u as f64, v, bg);
            if let Some(p) = rgb_at(rgb, x, y) {
                out.0[out.1] = p;
                out.1 += 1;
            }
        }
        out
    }

    /// How far the RGB camera sees the wall at IR pixels `wall` of row `v` (raw value `raw`;
    /// its holes left out) stray from the colour `bg` beside the hole: the second largest colour
    /// distance (one stray pixel aside).
    fn wall_spread(
        &self,
        rgb: &[u8],
        v: usize,
        wall: std::ops::Range<usize>,
        raw: u16,
        bg: [i32; 3],
    ) -> u32 {
        if wall.is_empty() {
            return 0;
        }
        let mask = &self.masks[v];
        let (mut first, mut second) = (0, 0);
        // Over a few dozen pixels the projection is linear in the column to well under a pixel:
        // two divisions, not one per pixel.
        let (start, last) = (wall.start, wall.end - 1);
        let (xa, ya) = self.project(start as f64, v, raw);
        let (xb, yb) = self.project(last as f64, v, raw);
        let span = (last - start).max(1) as f64;
        let (dx, dy) = ((xb - xa) / span, (yb - ya) / span);
        for u in wall {
            if mask.is_hole(u) {
                continue;
            }
            let k = (u - start) as f64;
            if let Some(p) = rgb_at(rgb, xa + k * dx, ya + k * dy) {
                let d = hue_dist(p, bg);
                if d > first {
                    (first, second) = (d, first);
                } else if d > second {
                    second = d;
                }
            }
        }
        second
    }

    /// RGB column and row of IR pixel (`u`, `v`) at raw value `raw` (one division).
    fn project(&self, u: f64, v: usize, raw: u16) -> (f64, f64) {
        let iz = (self.den - f64::from(raw)) * self.iz_per_raw;
        let n: [f64; 3] =
            std::array::from_fn(|k| self.row_ray[v][k] + u * self.col_step[k] + self.t[k] * iz);
        let inv = 1.0 / n[2];
        (
            self.rgb_f[0] * n[0] * inv + self.rgb_c[0],
            self.rgb_f[1] * n[1] * inv + self.rgb_c[1],
        )
    }

    /// How many of a split's shadow columns next to the occluder a soft lens may blend with it
    /// where its edge slants: the pixels the hole's start moves from row to row (half its move
    /// from the row above to the row below; 0 behind a nearer surface or where either row has no
    /// hole start within [`SLANT_REACH`]). The lens blurs across rows too, and along an edge
    /// that moves several pixels a row the rows next to this one show the occluder over as many
    /// of its columns: a black box's top edge at a sixth of a pixel's rise per column left the
    /// last five columns of its shadow 40 darker than the wall, and its mean past the
    /// background's step (the noisier sensor and soft lens, seed 24680, scene 029).
    fn slant_blend(&self, raw: &[u16], v: usize, c: Candidate) -> usize {
        if c.behind || v == 0 || v + 1 >= HEIGHT {
            return 0;
        }
        let start = |w: usize| {
            let row = &raw[w * WIDTH..(w + 1) * WIDTH];
            if row[c.a] == NO_DEPTH {
                let reach = c.a.saturating_sub(SLANT_REACH);
                (reach..c.a)
                    .rev()
                    .find(|&x| row[x] != NO_DEPTH)
                    .map(|x| x + 1)
            } else {
                (c.a..(c.a + SLANT_REACH).min(c.b)).find(|&x| row[x] == NO_DEPTH)
            }
        };
        match (start(v - 1), start(v + 1)) {
            (Some(up), Some(down)) => up.abs_diff(down) / 2,
            _ => 0,
        }
    }

    /// The shadow width whose layout (background, occluder, background) best explains the RGB row
    /// under the hole, when it explains nearly all of it and clearly better than no shadow; and
    /// the occluder's shift (its disparity above the background's), the same unless part of the
    /// shadow is hidden ([`Candidate::behind`]).
    fn split(&self, raw: &[u16], rgb: &[u8], v: usize, c: Candidate, prefix: &mut Prefix) -> Split {
        // Background colour: the mean of each side, which must agree.
        let side = |us: std::ops::Range<usize>| self.mean_colour(rgb, v, us, c.bg);
        // Cheap probes first (most holes of a real frame fail here): the hole's first pixel must
        // look like the background beside it, and its middle or right half like something else.
        // Each probe is the mean of three RGB columns: a camera's noise moves one pixel's colour
        // distance by tens (at σ = 5 per channel, 35 to 50 on average between two pixels).
        let probe = |u: usize| self.probe(rgb, u, v, c.bg);
        let beside = probe(if c.behind { c.b + 1 } else { c.a - 2 })?;
        // A closed hole whose first pixel is not the colour beside it but is the colour right of
        // it (the sides themselves unlike): the shadow starts on a checker's or a band's next
        // square, which the wall right of the hole shows too. It is read against the right
        // side, as a hole behind a nearer surface is. (The sixth simulator, fourteen suites:
        // complex IR attached F1 +0.0091 summed, any-shadow recall +0.0151, precision −0.0003,
        // RGB alignment +0.0021, no suite lower than −0.0003; this project's suites +0.0008,
        // precision −0.0002; the real frame unchanged.)
        let first = probe(c.a)?;
        let right = if c.closed { probe(c.b + 1) } else { None };
        let from_right = !c.behind
            && right.is_some_and(|right| {
                let step = self.dimmed(COLOUR_STEP, beside);
                hue_dist(first, beside) >= step
                    && hue_dist(first, right) < step
                    && hue_dist(right, beside) > self.dimmed(SIDES_AGREE, beside)
            });
        let beside = if from_right { right? } else { beside };
        let step = self.dimmed(COLOUR_STEP, beside);
        // The wall whose texture may excuse a colour that strays from the probe beside the hole:
        // left of it, or right of it behind a nearer surface. Where a farther surface bounds the
        // hole on the right, the left side may be an object whose shadow fell behind it, and
        // its shading is no wall's texture: only a plane's is read there ([`one_plane`]; a
        // banded wall beside a doorway. The sixth simulator: complex IR attached F1 +0.0072
        // summed over twelve suites, precision +0.0010, recall +0.0103, RGB alignment −0.0016;
        // this project's suites +0.0004. Every such side read: +0.013 there, but −0.0064 and
        // precision −0.0033 on this project's holdout, whose shaded boxes and spheres stand
        // before farther walls.)
        let wall = if c.behind || from_right {
            Some(c.b..(c.b + SPREAD_SPAN).min(WIDTH))
        } else {
            let left = c.a.saturating_sub(SPREAD_SPAN)..c.a;
            (!c.farther_right || one_plane(&raw[v * WIDTH..(v + 1) * WIDTH], left.clone()))
                .then_some(left)
        };
        // Read once, against the probe beside the hole, for this test and the column test below.
        let mut spread = None;
        let mut spread_of = || {
            *spread.get_or_insert_with(|| {
                wall.clone()
                    .map_or(0, |w| self.wall_spread(rgb, v, w, c.bg, beside))
            })
        };
        // The probe in the hole's middle, read at most once for the two tests below.
        let mut middle = None;
        let mut middle_of = || *middle.get_or_insert_with(|| probe((c.a + c.b) / 2));
        let d_first = hue_dist(first, beside);
        // Only beside an occluder of far greater contrast (the column step rises for no other),
        // which the probe in the hole's middle shows.
        let first_ok = d_first < step
            || (d_first < CONTRAST_CAP * step / 2
                && middle_of().is_some_and(|p| hue_dist(p, beside) >= CONTRAST_SHARE * step)
                && 2 * d_first <= SPREAD_NUM * spread_of());
        if !c.behind {
            prefix.first_probe = Some((v, c.a, c.bg, first_ok));
        }
        if !first_ok
            || (c.closed
                && (hue_dist(right?, beside) > self.dimmed(SIDES_AGREE, beside)
                    || (hue_dist(middle_of()?, beside) < step
                        && hue_dist(probe((c.a + 3 * c.b) / 4)?, beside) < step)))
        {
            return None;
        }
        let bg = if c.behind || from_right {
            side(c.b..c.b + SIDE)?
        } else if c.closed {
            let (left, right) = (side(c.a.saturating_sub(SIDE)..c.a)?, side(c.b..c.b + SIDE)?);
            if hue_dist(left, right) > self.dimmed(SIDES_AGREE, beside) {
                return None;
            }
            std::array::from_fn(|k| (left[k] + right[k]) / 2)
        } else {
            side(c.a.saturating_sub(SIDE)..c.a)?
        };
        // An open hole is read only as far as its widest shadow and a window of occluder.
        let d_bg = self.disp(c.bg);
        let b = c.b;
        // The RGB columns the hole covers at the background's depth, and which are background.
        let (x0, y) = self.project(c.a as f64 - 0.5, v, c.bg);
        let (x1, _) = self.project(b as f64 - 0.5, v, c.bg);
        let (x0, mut x1) = (ceil(x0), ceil(x1));
        if !c.closed {
            x1 = x1.min(WIDTH as i64);
            // Right of where the RGB camera sees a nearer surface's left edge, it sees that
            // surface, which is no occluder of this hole.
            if let Some(r) = c.nearer_right {
                x1 = x1.min(ceil(self.project(b as f64 - 0.5, v, r).0));
            }
        }
        let y = round(y);
        if x0 < 0
            || x1 > WIDTH as i64
            || x1 - x0 < MIN_HOLE as i64 - 1
            || !(0..HEIGHT as i64).contains(&y)
        {
            return None;
        }
        let pixels =
            &rgb[3 * (y as usize * WIDTH + x0 as usize)..3 * (y as usize * WIDTH + x1 as usize)];
        // Prefix counts of background columns from x0, so each layout scores in constant time.
        // An open hole must show its occluder: the shadow can only end just before the first run
        // of non-background columns, so the columns are read only a window past it, and only
        // widths near it are scored (this keeps the many open holes of a real frame cheap).
        let mut n = (x1 - x0) as usize;
        let bg_count = &mut prefix.bg_count[..];
        bg_count[0] = 0;
        let mut first = None;
        let colour = |k: usize| [3 * k, 3 * k + 1, 3 * k + 2].map(|i| i32::from(pixels[i]));
        // A textured or unevenly lit wall drifts in colour along the hole by more than a plain
        // one's noise: beside an occluder of far greater contrast, its columns count as wall
        // while they stray no further than the wall beside the hole does ([`Self::wall_spread`]
        // first: a few dozen pixels against every column, and a plain wall, most, needs no more).
        let spread = spread_of();
        // An open hole's first run of other columns ends its shadow: on a patterned wall that is
        // the pattern's next patch unless columns showing a colour the wall itself shows left of
        // the hole (within [`PALETTE_MATCH`] half steps of one of a few samples) count as wall,
        // up to the first column unlike the wall and all of its colours: the occluder, past
        // which the RGB camera may see the wall's other colours again. A closed hole read as an
        // open one (its sides differ in hue or light) must first show the background's own
        // colour over [`PLAIN_FIRST`] columns: a rod's shadow lying on a wall's other hue from
        // its first column was all excused so, and came out 3 px too wide (the sensor's widening
        // of its left end then reads as a larger shift); over two columns the shadow's start is
        // read plainly.
        // (The fourth simulator: complex IR attached F1 +0.016 summed over 28 suites, j6
        // +0.0064, j1r +0.0037; this project's suites unchanged.)
        // (Read once, and only when a column strays from the background by a step.)
        let palette = std::cell::OnceCell::new();
        let occluder_seen = std::cell::Cell::new(false);
        let plain = |k: usize| hue_dist(colour(k), bg);
        let col_step = if SPREAD_NUM * spread / 2 > step {
            contrast_step(pixels.len() / 3, step, plain).min(SPREAD_NUM * spread / 2)
        } else {
            step
        };
        // Columns so far within the step of the background.
        let plain_seen = std::cell::Cell::new(0usize);
        // The occluder's colour, where the hole's middle shows one of far greater contrast:
        // until it shows, a column of an open hole far nearer the background's colour than the
        // occluder's is background, however far it strays (a lit cylinder brightening into the
        // hole beside a black box: the shadow was cut where the drift passed the step). (Not in
        // a closed hole, whose occluder fills it: the blend at a rod's edge read as wall.)
        let contrasting = (!c.opened)
            .then(middle_of)
            .flatten()
            .filter(|&m| hue_dist(m, bg) >= CONTRAST_SHARE * step);
        let occluder_colour = contrasting.filter(|_| !c.closed);
        let dist = |k: usize| {
            let p = colour(k);
            let d = hue_dist(p, bg);
            if d < col_step {
                plain_seen.set(plain_seen.get() + 1);
                return d;
            }
            if occluder_colour
                .is_some_and(|o| !occluder_seen.get() && NEARER_BG * d < hue_dist(p, o))
            {
                plain_seen.set(plain_seen.get() + 1);
                return 0;
            }
            // A closed hole's columns are its sides' colour, but where its middle shows an
            // occluder of far greater contrast they may show the wall's other colours too: its
            // shadow crossing onto a checker's other square before the occluder (none where the
            // occluder's colour is one of the wall's: a glossy box's dropouts show its own).
            // (Fourth simulator, 40 suites: simple IR attached F1 +0.055 summed, j39 +0.045;
            // complex +0.024, j34 +0.014; any-shadow precision within ±0.0013. Without the
            // occluder's test, j31's glossy checkered box lost 0.013 and precision 0.019.)
            if (c.closed && contrasting.is_none())
                || (c.opened && plain_seen.get() < PLAIN_FIRST)
                || occluder_seen.get()
            {
                return d;
            }
            let Some(w) = wall.clone() else {
                return d;
            };
            let (qs, m) = palette.get_or_init(|| {
                self.wall_palette(&raw[v * WIDTH..(v + 1) * WIDTH], rgb, v, w, c.bg)
            });
            let qs = &qs[..*m];
            if c.closed && contrasting.is_some_and(|o| in_palette(qs, o, step)) {
                return d;
            }
            // A step from the column before into a colour near the wall's is an occluder's
            // edge, which the wall's shading and noise, drifting, do not make: past it only the
            // wall's colours plainly unlike the background (a pattern's other hue) excuse one.
            // (A pale glossy box 1.2 to 1.5 steps from a grey wall, its hole ended by a sphere
            // before it, was wall in every column: seed 16180's scene 037. Complex IR attached F1
            // +0.0026 there, +0.0012 on 11235 with precision +0.0013, +0.0008 on 57721, +0.0006
            // on 9053; no suite lower, simple scenes and the real frame unchanged.)
            let edge = k > 0 && hue_dist(p, colour(k - 1)) >= step;
            let wall_colour = if edge {
                in_palette_unlike(qs, p, bg, step)
            } else {
                in_palette(qs, p, step)
            };
            if wall_colour {
                0
            } else {
                occluder_seen.set(true);
                d
            }
        };
        let columns = background_columns(pixels.len() / 3, col_step, dist);
        for (k, is_bg) in columns.enumerate() {
            bg_count[k + 1] = bg_count[k] + u32::from(is_bg);
            if !c.closed && first.is_none() && k >= 2 && bg_count[k + 1] == bg_count[k - 2] {
                first = Some(k - 2);
            }
            // The occluder's RGB columns: at least as many as the IR shadow's, which are about
            // 1.7 times its visible RGB columns (`f`).
            if first.is_some_and(|f| k + 1 >= f + 3 + OPEN_WINDOW.max(2 * f)) {
                n = k + 1;
                break;
            }
        }
        // A pale occluder: past its edge, a strong step from the wall (its shaded side), its face
        // may come back within the column step of the wall's colour, yet stay plainly farther
        // from it than the wall's columns before the edge stray (the camera's noise and the
        // wall's texture); such columns are occluder. (Else the window of occluder an open
        // hole's layout scores read as wall, and wider shadows, whose window reaches further
        // into the face, scored worse: a pale green glossy cylinder before a beige wall, seed
        // 9053's scene 005, noisier sensor and default one: complex IR attached F1 +0.010 and
        // +0.011, RGB alignment +0.002 and +0.004, RGB any-shadow precision −0.001; the other
        // suites within ±0.0001.)
        let mut pale = None;
        if let Some(f) = first.filter(|&f| !c.closed && f >= 3) {
            let d = |k: usize| hue_dist(colour(k), bg);
            let edge = (f..(f + EDGE_NEAR).min(n)).map(d).max().unwrap_or(0);
            // The column before the edge may blend wall and occluder.
            let noise = (0..f - 1).map(d).max().unwrap_or(0);
            if edge >= PALE_EDGE * noise {
                let floor = (FAINT_NUM * noise / 2).max(step / 2);
                pale = Some(floor);
                let mut moved = 0;
                for k in f..n {
                    let was_bg = bg_count[k + 1] > bg_count[k] + moved;
                    moved += u32::from(was_bg && d(k) >= floor);
                    bg_count[k + 1] -= moved;
                }
            }
        }
        let bg_count = &*bg_count;
        let near = match (c.closed, first) {
            (true, _) => 0..n,
            (false, Some(first)) => first.saturating_sub(2)..first + 3,
            (false, None) => return None,
        };
        // Score of a layout: RGB columns it explains, and the colour distance of the columns it
        // calls shadow and occluder. Shadow width s puts the occluder at disparity disp(bg) + s,
        // covering RGB columns [xo0, xo1); in an open hole only a window of it is scored, and so
        // is nothing after it.
        // Behind a nearer surface the shadow's left end is hidden, so its visible width is not
        // the occluder's shift; the occluder's right edge gives the shift instead (the RGB camera
        // sees that edge move left by a third of it): background right of it, occluder left.
        let shift = if c.behind {
            Some(self.fit_right_edge(&bg_count[..=n], x0, v, b, c.bg)?.1)
        } else {
            None
        };
        let start = |s: usize| -> (u16, usize) {
            let at = self.raw_at_disp(d_bg + shift.map_or(s as f64 - self.widen, |t| t as f64));
            let xo0 = ceil(self.project(c.a as f64 + s as f64 - 0.5, v, at).0);
            (at, (xo0 - x0).clamp(0, n as i64) as usize)
        };
        let score = |s: usize| -> (Layout, usize) {
            let (at, o0) = start(s);
            let o1 = if c.closed {
                let xo1 = ceil(self.project(c.b as f64 - 0.5, v, at).0);
                ((xo1 - x0).clamp(0, n as i64) as usize).max(o0)
            } else {
                // An attached shadow's occluder is at least as wide as the shift (else the shadow
                // would be detached and narrower): a thin rod before a hole is no occluder here.
                let xs = ceil(self.project((c.a + 2 * s) as f64 - 0.5, v, at).0);
                let wide = ((xs - x0).max(0) as usize).saturating_sub(o0);
                (o0 + OPEN_WINDOW.max(wide)).min(n)
            };
            let end = if c.closed { n } else { o1 };
            let occluder_cols = o1 - o0;
            let occluder_bg = (bg_count[o1] - bg_count[o0]) as usize;
            let outside_bg = bg_count[end] as usize - occluder_bg;
            let layout = Layout {
                hits: outside_bg + occluder_cols - occluder_bg,
                shadow_cols: o0,
                occluder_start: o0,
                occluder_cols,
            };
            (layout, end)
        };
        let width = b - c.a;
        let no_shadow = score(0).0.hits;
        let mut best: Option<(Layout, usize, usize)> = None;
        // The occluder's start moves right with the shadow width: in an open hole, the first
        // width that reaches the window, by bisection.
        let (mut lo, mut hi) = (3, width.saturating_sub(3).max(3));
        while !c.closed && lo < hi {
            let mid = (lo + hi) / 2;
            if start(mid).1 < near.start {
                lo = mid + 1;
            } else {
                hi = mid;
            }
        }
        for s in lo..=width.saturating_sub(3) {
            if d_bg + s as f64 > self.max_disp || shift.is_some_and(|t| s > t) {
                break;
            }
            if !c.closed && start(s).1 >= near.end {
                break;
            }
            let (l, end) = score(s);
            // Closed holes: the layout explaining most columns. Open ones are scored over
            // windows of different lengths: the fewest columns unexplained.
            let better = |b: &(Layout, usize, usize)| {
                if c.closed {
                    l.hits > b.0.hits
                } else {
                    end - l.hits < b.2 - b.0.hits
                }
            };
            if best.as_ref().is_none_or(better) {
                best = Some((l, s, end));
            }
        }
        let (l, s, n) = best?;
        if !c.closed && l.occluder_cols < OPEN_WINDOW / 2 {
            return None;
        }
        // Nearly every column explained, and by half the shadow's columns more than with no
        // shadow (a soft lens blends the column beside the occluder: two more than half, as
        // this once asked, left narrow shadows whole; complex attached F1 +0.0001 to +0.0011 on
        // fourteen suites, +0.0026 with the RGB image blurred); the shadow's columns are
        // plainly background and the occluder's plainly not (a pale poster on a white wall is
        // neither), read for this one layout only. The shadow's test is on its mean colour: the
        // mean of its pixels' distances grows with the camera's noise (at σ = 5 per channel it
        // alone reaches the limit), the distance of their mean does not. Against the mean of
        // distances: complex attached F1 +0.06 on scenes with that noise, −0.0009 on noise-free
        // ones, ±0.0005 on the other twelve suites.
        let sum = |cols: std::ops::Range<usize>| cols.map(|k| hue_dist(colour(k), bg)).sum::<u32>();
        let occluder = l.occluder_start..l.occluder_start + l.occluder_cols;
        let mean = |cols: std::ops::Range<usize>| {
            let n = cols.len() as i32;
            let mut acc = [0i32; 3];
            for k in cols {
                let c = colour(k);
                (0..3).for_each(|i| acc[i] += c[i]);
            }
            acc.map(|a| a / n)
        };
        // The shadow's column beside the occluder may be a soft edge's blend ([`soft_edge`]).
        let shadow_read = if l.shadow_cols >= 3 {
            l.shadow_cols - 1
        } else {
            l.shadow_cols
        };
        // An occluder's edge is a step in colour near where the layout puts it (two columns
        // either side of it differ by at least half the occluder's contrast with the shadow);
        // a curved surface's shading ramps over many columns. On a glossy sphere whose
        // dropouts leave lit patches, a hole after a patch read its highlight as background and
        // the sphere's shaded rim as an occluder (an independent simulator: complex IR attached
        // precision +0.013 and +0.017 on two suites, F1 +0.010 and +0.016; −0.002 on a third,
        // whose side wall darkens towards a black box's edge row by row; this project's suites
        // unchanged).
        let ramp = || {
            let o0 = l.occluder_start;
            o0 >= 3 && l.occluder_cols >= 4 && {
                let contrast = hue_dist(mean(occluder.clone()), mean(0..shadow_read));
                !steps_near(mean, o0, n, contrast)
            }
        };
        let clear = l.shadow_cols >= 2
            && l.occluder_cols >= 2
            && !ramp()
            && {
                // Not the columns the lens blends with the occluder along a slanted edge.
                let read = shadow_read
                    .saturating_sub(self.slant_blend(raw, v, c))
                    .max(shadow_read.min(2));
                let d = hue_dist(mean(0..read), bg);
                // Over a textured wall, within the wall's own spread.
                2 * d <= self.dimmed(COLOUR_STEP, bg) || (col_step > step && d <= spread)
            }
            && sum(occluder.clone())
                >= pale.map_or(self.dimmed(OCCLUDER_STEP, bg), |f| {
                    f.min(self.dimmed(OCCLUDER_STEP, bg))
                }) * l.occluder_cols as u32
            // An occluder showing the colour of the farther surface right of the hole is that
            // surface (a black rod's hole over a dark box's edge, the wall behind seen through
            // its right part; a glossy box's dropouts before its own farther face). The fourth
            // simulator's 40 suites: complex IR attached F1 +0.011 summed (j14 +0.005, j18
            // +0.005), precision +0.015, recall −0.002, RGB alignment +0.012; this project's
            // suites within ±0.0005; the real frame unchanged.
            && !(c.farther_right && {
                // Past the occluder's first column, which may blend it with the shadow.
                let from = occluder.start + usize::from(occluder.len() >= 3);
                self.shows_farther_right(raw, rgb, v, c, mean(from..occluder.end))
            })
            // An open hole's occluder, nearer by its shift, whose right edge the RGB camera sees
            // where the farther surface's depth puts it, with no strip of that surface past it.
            && !(c.farther_right
                && !c.closed
                && self.no_strip_past(raw, rgb, v, c, start(s).0, mean(occluder.clone())))
            // An open hole's occluder that is its background in more light is a glossy surface's
            // highlight past a dropout on it. (Fourth simulator, 46 suites: complex IR attached
            // F1 +0.016 summed, precision +0.024; simple +0.009 and +0.014; this project's
            // suites and the real frame unchanged.)
            && (c.closed || !highlight_of(mean(occluder.clone()), bg));
        // Nine columns in ten explained, or in a closed hole all but [`EDGE_MISSES`]: the RGB
        // camera sees the occluder's two edges inside it, each a column blending it with the
        // wall, and the layout's edges fall on whole columns. A narrow rod's dozen columns
        // missed nine in ten by one in many rows. (A share of two in ten instead let a turned
        // board's two dropouts, its own colour then a dark patch, pass for a shadow and its
        // occluder: forty-odd columns, the five of the strip such an occluder would show right
        // of it missing. The sixth simulator, fourteen suites: complex IR attached F1 +0.0009
        // summed, detached +0.0051, RGB alignment +0.0021, any-shadow precision +0.0006,
        // recall +0.0010; this project's suites +0.0016, +0.0040, +0.0013, +0.0007, +0.0048;
        // no suite lower than −0.0004; the real frame unchanged.)
        let explained = 10 * l.hits >= 9 * n || (c.closed && l.hits + EDGE_MISSES >= n);
        (clear && explained && l.hits >= no_shadow + l.shadow_cols / 2)
            .then_some((s, shift.unwrap_or(s)))
    }
}

/// Whether the colours `mean` gives for column ranges step by at least half of `contrast` near
/// column `o0` (within [`EDGE_NEAR`], `n` columns in all): two columns either side of some
/// column, the column itself and its left neighbour skipped (a soft lens blends them).
fn steps_near(
    mean: impl Fn(std::ops::Range<usize>) -> [i32; 3],
    o0: usize,
    n: usize,
    contrast: u32,
) -> bool {
    let hi = (o0 + EDGE_NEAR).min(n.saturating_sub(3));
    (o0.saturating_sub(EDGE_NEAR).max(3)..=hi)
        .any(|e| 2 * hue_dist(mean(e + 1..e + 3), mean(e - 3..e - 1)) >= contrast)
}

/// Whether the raw depths of `row` over `span` (at least [`MIN_PLANE`] pixels) are all measured
/// and within [`PLANE_TOLERANCE`] of the straight line between its two ends: one plane, which
/// disparity (linear in raw units) makes a line along a row. A box's face turned away, a
/// cylinder or a sphere curve away from it.
fn one_plane(row: &[u16], span: std::ops::Range<usize>) -> bool {
    if span.len() < MIN_PLANE {
        return false;
    }
    let (first, last) = (span.start, span.end - 1);
    let (r0, r1) = (i64::from(row[first]), i64::from(row[last]));
    let n = (last - first) as i64;
    row[span].iter().enumerate().all(|(k, &r)| {
        let k = k as i64;
        r != NO_DEPTH && (i64::from(r) * n - (r0 * (n - k) + r1 * k)).abs() <= PLANE_TOLERANCE * n
    })
}

/// The pixels of `labels` labelled `from` take `to` (the others, valid islands among them, keep
/// theirs).
fn relabel(labels: &mut [u8], from: u8, to: u8) {
    for l in labels.iter_mut().filter(|l| **l == from) {
        *l = to;
    }
}

/// Whether each of `n` RGB columns shows the background, column `k` being `dist(k)` from its
/// colour: within `step`, or the background's side of a soft edge ([`soft_edge`]). Through a soft
/// lens (the real frame's edges rise over two pixels) the blended column once counted as the
/// occluder, and 2 px of shadow were lost.
#[inline]
fn background_columns(
    n: usize,
    step: u32,
    dist: impl Fn(usize) -> u32,
) -> impl Iterator<Item = bool> {
    let at = move |k: usize| if k < n { dist(k) } else { u32::MAX };
    let (mut d_prev, mut d) = (u32::MAX, at(0));
    (0..n).map(move |k| {
        let d_next = at(k + 1);
        let is_bg = d < step || soft_edge(d_prev, d, d_next, step);
        (d_prev, d) = (d, d_next);
        is_bg
    })
}

/// The step by which each of `n` RGB columns (column `k` being `dist(k)` from the background's
/// colour) may be background: `step`, raised towards a [`CONTRAST_SHARE`] of the contrast of an
/// occluder among them (the least of two neighbouring columns, so one noisy pixel raises
/// nothing), to at most [`CONTRAST_CAP`] halves of `step`.
#[inline]
fn contrast_step(n: usize, step: u32, dist: impl Fn(usize) -> u32) -> u32 {
    let mut prev = dist(0);
    let mut peak = 0;
    for k in 1..n {
        let d = dist(k);
        peak = peak.max(d.min(prev));
        prev = d;
    }
    (peak / CONTRAST_SHARE).clamp(step, CONTRAST_CAP * step / 2)
}

/// True when a column `d` from the background's colour is the background's side of a soft edge:
/// beside a background column (`d_prev` or `d_next` within `step`) and less than half as far from
/// the background as the column on its other side. A lens blends the column an edge falls in;
/// the edge lies where the blend is half way.
#[inline]
fn soft_edge(d_prev: u32, d: u32, d_next: u32, step: u32) -> bool {
    (d_prev < step && 2 * d < d_next) || (d_next < step && 2 * d < d_prev)
}

/// The RGB8 pixel nearest to (`x`, `y`), if inside the image.
#[inline]
fn rgb_at(rgb: &[u8], x: f64, y: f64) -> Option<[i32; 3]> {
    let (x, y) = (round(x), round(y));
    if x < 0 || y < 0 || x >= WIDTH as i64 || y >= HEIGHT as i64 {
        return None;
    }
    let i = 3 * (y as usize * WIDTH + x as usize);
    Some([rgb[i].into(), rgb[i + 1].into(), rgb[i + 2].into()])
}

/// The mean of the RGB8 pixel nearest to (`x`, `y`) and its left and right neighbours (those
/// inside the image), if that pixel is inside.
#[inline]
fn rgb_mean3(rgb: &[u8], x: f64, y: f64) -> Option<[i32; 3]> {
    let (x, y) = (round(x), round(y));
    if x < 0 || y < 0 || x >= WIDTH as i64 || y >= HEIGHT as i64 {
        return None;
    }
    let (x, row) = (x as usize, y as usize * WIDTH);
    let cols = x.saturating_sub(1)..(x + 2).min(WIDTH);
    let n = cols.len() as i32;
    let mut sum = [0i32; 3];
    for i in cols {
        (0..3).for_each(|k| sum[k] += i32::from(rgb[3 * (row + i) + k]));
    }
    // Sums are never negative, and a division by a constant is a multiply (by `n` it is an
    // integer division, three a probe, on the colour split's busiest path).
    Some(sum.map(|s| if n == 3 { s / 3 } else { s / n }))
}

/// Brightness (R + G + B) of a background at and above which the colour steps apply as they are
/// (a pale wall in room light); below it they shrink in proportion, down to [`DIM_FLOOR`]: in an
/// image half as bright every colour difference is half as large.
const BRIGHT: i32 = 540;
/// Brightness below which the steps shrink no further (the camera's noise does not).
const DIM_FLOOR: i32 = 240;

/// `step` for a background of colour `bg` (see [`BRIGHT`]).
#[inline]
pub(crate) fn dimmed(step: u32, bg: [i32; 3]) -> u32 {
    let b = (bg[0] + bg[1] + bg[2]).clamp(DIM_FLOOR, BRIGHT);
    step * b as u32 / BRIGHT as u32
}

/// Brightness part of [`hue_dist`]: the sum of |ΔR| + |ΔG| + |ΔB|.
#[inline]
fn dist(p: [i32; 3], q: [i32; 3]) -> u32 {
    p.iter().zip(&q).map(|(a, b)| a.abs_diff(*b)).sum()
}

/// Colour distance for telling two surfaces apart: [`dist`] plus twice the change of hue,
/// `|Δ(R − G)| + |Δ(B − G)|`. Shading and texture move a surface's brightness far more than its
/// hue, so a hue difference is the surer sign of another surface. The camera's noise weighs
/// more in it too, so its steps are half as large again as brightness alone would need.
#[inline]
pub(crate) fn hue_dist(p: [i32; 3], q: [i32; 3]) -> u32 {
    let hue = (p[0] - p[1]).abs_diff(q[0] - q[1]) + (p[2] - p[1]).abs_diff(q[2] - q[1]);
    dist(p, q) + 2 * hue
}

/// True when colour `p` lies within [`PALETTE_MATCH`] half steps (`step`, the colour step) of
/// one of the wall's palette samples `qs` ([`ColourSplit::wall_palette`]).
fn in_palette(qs: &[[i32; 3]], p: [i32; 3], step: u32) -> bool {
    qs.iter()
        .any(|&q| 2 * hue_dist(p, q) < PALETTE_MATCH * step)
}

/// [`in_palette`] for the samples of `qs` a `step` or more from the background's colour `bg`:
/// the wall's other colours, not its own one strayed.
fn in_palette_unlike(qs: &[[i32; 3]], p: [i32; 3], bg: [i32; 3], step: u32) -> bool {
    qs.iter()
        .any(|&q| hue_dist(q, bg) >= step && 2 * hue_dist(p, q) < PALETTE_MATCH * step)
}

/// True when the colours beside a hole, `l` and `r` ([`ColourSplit::side_probes`]), show one
/// chromaticity in different brightness: one surface, lit or patterned differently, not two. Or
/// one side is the other brightened until the camera clipped it ([`brightened_into_clipping`]):
/// a black rod's hole on a cream sphere, its highlight white right of it. (Fourth simulator, 44
/// suites: complex IR attached F1 +0.029 summed, j44 +0.018, j14 +0.012; precision −0.004, at
/// most −0.002 on one suite; simple +0.003; this project's suites and the real frame
/// unchanged.)
fn sides_differ_in_light((l, r): ([i32; 3], [i32; 3])) -> bool {
    let (sl, sr) = (l.iter().sum::<i32>().max(1), r.iter().sum::<i32>().max(1));
    // Chromaticity in thousandths.
    let off: i32 = (0..3)
        .map(|k| (1000 * l[k] / sl - 1000 * r[k] / sr).abs())
        .sum();
    off <= CHROMA_AGREE || brightened_into_clipping(l, r)
}

/// True when the brighter of `l` and `r` is the other in up to [`MAX_BRIGHTEN`] times the light,
/// with the camera clipping it: its clipped channels (from [`CLIPPED`]) would have reached
/// the top, its others grow by one factor (within [`CHROMA_RATIO`]). Clipping breaks
/// chromaticity: a cream surface's highlight reads plain white.
fn brightened_into_clipping(l: [i32; 3], r: [i32; 3]) -> bool {
    let (lo, hi) = if l.iter().sum::<i32>() <= r.iter().sum::<i32>() {
        (l, r)
    } else {
        (r, l)
    };
    // A channel the brighter light clipped (clipped on both sides, it hides a change of hue).
    if !(0..3).any(|k| hi[k] >= CLIPPED && lo[k] < CLIPPED) || lo.iter().any(|&c| c <= 0) {
        return false;
    }
    // The light's factor, from the channels the camera did not clip (in thousandths).
    let ratios = (0..3)
        .filter(|&k| hi[k] < CLIPPED)
        .map(|k| 1000 * hi[k] / lo[k]);
    let (min, max) = ratios.fold((i32::MAX, 0), |(a, b), x| (a.min(x), b.max(x)));
    let factor = if max == 0 {
        1000 * CLIPPED / lo.iter().min().unwrap()
    } else {
        max
    };
    (1000..=MAX_BRIGHTEN).contains(&factor)
        && (max == 0 || max - min <= CHROMA_RATIO)
        && (0..3).all(|k| hi[k] < CLIPPED || lo[k] * factor >= (CLIPPED - CLIP_MARGIN) * 1000)
}

/// True when `o` is the saturated colour `bg` in more light: brighter, of the same chromaticity
/// (within [`CHROMA_AGREE`]) or brightened into clipping. A grey's chromaticity says nothing (a
/// black or white occluder has it too), so `bg` must be saturated: its weakest channel under
/// [`SATURATED`] of its strongest.
fn highlight_of(o: [i32; 3], bg: [i32; 3]) -> bool {
    let (so, sb) = (o.iter().sum::<i32>().max(1), bg.iter().sum::<i32>().max(1));
    let (lo, hi) = (*bg.iter().min().unwrap(), *bg.iter().max().unwrap());
    if so <= sb || 100 * lo > SATURATED * hi {
        return false;
    }
    chroma_off(o, bg) <= CHROMA_AGREE || brightened_into_clipping(o, bg)
}

/// Chromaticity difference of colours `p` and `q`: thousandths of their brightness (R + G + B),
/// summed over R, G, B.
pub(crate) fn chroma_off(p: [i32; 3], q: [i32; 3]) -> i32 {
    let (sp, sq) = (p.iter().sum::<i32>().max(1), q.iter().sum::<i32>().max(1));
    (0..3)
        .map(|k| (1000 * p[k] / sp - 1000 * q[k] / sq).abs())
        .sum()
}

/// Percentage of its strongest channel under which a colour's weakest makes it saturated.
const SATURATED: i32 = 60;

/// Channel value from which a camera pixel counts as clipped.
const CLIPPED: i32 = 250;
/// Channel values short of [`CLIPPED`] that a clipped channel, brightened by the factor the
/// others show, may fall (their noise and rounding).
const CLIP_MARGIN: i32 = 30;
/// Largest light factor (thousandths) [`brightened_into_clipping`] allows: a highlight, not a
/// dark surface's colour washed out.
const MAX_BRIGHTEN: i32 = 1500;
/// How far (thousandths) the unclipped channels' factors may differ.
const CHROMA_RATIO: i32 = 80;

/// The colours among a wall's `samples` unlike its colour `bg` (by `step` or more) that two
/// samples or more show, one per stripe: samples within half a step of a stripe's first join
/// it. A pattern repeats; a lone sample (a box's shaded side beside the hole) is no stripe. A
/// column is then compared with a few colours, not every sample.
#[inline]
fn other_stripes(samples: &[[i32; 3]], bg: [i32; 3], step: u32) -> ([[i32; 3]; PALETTE], usize) {
    let mut groups = ([([0; 3], 0u8); PALETTE], 0);
    for &q in samples.iter().filter(|&&q| hue_dist(q, bg) >= step) {
        let (gs, n) = &mut groups;
        match gs[..*n].iter_mut().find(|g| 2 * hue_dist(q, g.0) < step) {
            Some(g) => g.1 += 1,
            None => {
                gs[*n] = (q, 1);
                *n += 1;
            }
        }
    }
    let mut out = ([[0; 3]; PALETTE], 0);
    for &(q, _) in groups.0[..groups.1].iter().filter(|g| g.1 >= 2) {
        out.0[out.1] = q;
        out.1 += 1;
    }
    out
}

/// `x.round()` as an integer, without the libm call the baseline x86-64 target makes for it
/// (ties away from zero, as `f64::round`; only for |x| well inside i64).
fn round(x: f64) -> i64 {
    let t = x as i64;
    let f = x - t as f64;
    t + i64::from(f >= 0.5) - i64::from(f <= -0.5)
}

/// `x.ceil()` as an integer, without the libm call (only for |x| well inside i64).
fn ceil(x: f64) -> i64 {
    let t = x as i64;
    t + i64::from((t as f64) < x)
}

/// The hole through column `u` of `row` (a hole pixel), stepping over valid islands of up to
/// [`MAX_ISLAND`] pixels (speckle, spurious returns inside a shadow): `[a, b)`. The runs' ends
/// are read off the row's [`HoleMask`] a word at a time.
fn hole_span(mask: &HoleMask, row: &[u16], u: usize) -> (usize, usize) {
    let b = span_end(mask, row, u);
    let mut a = mask.prev_valid_end(u);
    while a > 0 {
        let island = a - mask.prev_hole_end(a);
        if island > MAX_ISLAND || island >= a {
            break;
        }
        a = mask.prev_valid_end(a - island);
    }
    (a, b)
}

/// The end of [`hole_span`] alone: where the hole through column `u` ends, islands of up to
/// [`MAX_ISLAND`] pixels stepped over.
#[inline]
fn span_end(mask: &HoleMask, row: &[u16], u: usize) -> usize {
    let mut b = mask.next_valid(u);
    while b < row.len() {
        let island = mask.next_hole(b) - b;
        if island > MAX_ISLAND || b + island >= row.len() {
            break;
        }
        b = mask.next_valid(b + island);
    }
    b
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn other_stripes_keep_colours_two_samples_show_one_per_stripe() {
        let wall = [200, 180, 120];
        let dark = [80, 72, 48];
        let samples = [
            wall,
            [202, 179, 121],
            dark,
            [82, 70, 49],
            wall,
            [79, 73, 47],
            // One sample of a box's blue side beside the hole: no stripe.
            [40, 60, 160],
        ];
        let step = 60;
        let (qs, m) = other_stripes(&samples, wall, step);
        assert_eq!(m, 1, "{:?}", &qs[..m]);
        assert_eq!(qs[0], dark, "the stripe's first sample stands for it");
    }

    /// [`steps_near`] over a row of RGB columns given one per column.
    fn steps_in(cols: &[[i32; 3]], o0: usize, contrast: u32) -> bool {
        let mean = |r: std::ops::Range<usize>| {
            let n = r.len() as i32;
            let mut acc = [0; 3];
            for c in &cols[r] {
                (0..3).for_each(|k| acc[k] += c[k]);
            }
            acc.map(|a| a / n)
        };
        steps_near(mean, o0, cols.len(), contrast)
    }

    #[test]
    fn a_surface_brightened_into_clipping_is_one_surface_in_other_light() {
        // A cream surface (230, 230, 190) in 1.2 times the light: 276, 276, 228 before the
        // camera clips red and green at 255. Chromaticity (thousandths) moves by 33, past
        // CHROMA_AGREE; the unclipped blue grows by the factor, the clipped channels would
        // have passed the top.
        let cream = [230, 230, 190];
        let lit = [255, 255, 228];
        let chroma = |c: [i32; 3]| c.map(|x| 1000 * x / c.iter().sum::<i32>());
        let off: i32 = (0..3)
            .map(|k| (chroma(cream)[k] - chroma(lit)[k]).abs())
            .sum();
        assert!(off > CHROMA_AGREE, "chromaticity moved by {off}");
        assert!(brightened_into_clipping(cream, lit));
        assert!(brightened_into_clipping(lit, cream), "either order");
        // Already clipped red and green, blue clipped in 1.2 times the light: plain white.
        assert!(brightened_into_clipping([255, 255, 212], [255, 255, 255]));
        // Tan (180, 150, 120) in 4/3 the light: 240, 200, 160, red within the clipping margin.
        assert!(brightened_into_clipping([180, 150, 120], [255, 200, 160]));
        // Not so: green grown by 1 and blue by 4/3 (another hue); a dark red washed out to
        // white (6 times the light, no highlight); green clipped on both sides already, which
        // hides how its hue moved; no channel clipped at all (the chromaticity test's case).
        assert!(!brightened_into_clipping([180, 150, 120], [255, 150, 160]));
        assert!(!brightened_into_clipping([200, 60, 40], [255, 255, 255]));
        assert!(!brightened_into_clipping([86, 255, 148], [103, 255, 178]));
        assert!(!brightened_into_clipping([100, 100, 80], [120, 120, 96]));
    }

    #[test]
    fn a_saturated_surfaces_highlight_is_no_occluder_but_a_grey_ones_may_be() {
        // A glossy green cylinder beside a dropout, and its highlight (12 % more light).
        let green = [133, 229, 100];
        assert!(highlight_of([149, 255, 112], green));
        // Clipped in green: the other channels still grow alike.
        assert!(highlight_of([160, 255, 120], green));
        // Darker is no highlight; nor is another hue, however bright.
        assert!(!highlight_of([110, 190, 83], green));
        assert!(!highlight_of([200, 230, 100], green));
        // On a grey wall, a white glossy rod and a black one keep the wall's (lack of) hue.
        assert!(!highlight_of([240, 240, 240], [128, 128, 128]));
        assert!(!highlight_of([20, 20, 20], [128, 128, 128]));
    }

    #[test]
    fn a_plane_is_a_line_of_raw_depths_and_a_curve_is_not() {
        // A wall turned away: raw 900 → 939 over 40 px, the sensor's ±2 on pixels between.
        let wall: Vec<u16> = (0..40u16)
            .map(|k| match k % 6 {
                2 => 902 + k,
                4 => 898 + k,
                _ => 900 + k,
            })
            .collect();
        assert!(one_plane(&wall, 0..40));
        // A cylinder's face: its middle 12 raw units nearer than its sides, a parabola.
        let curve: Vec<u16> = (0..40)
            .map(|k: i32| 900 - (12 - 12 * (k - 20).pow(2) / 400) as u16)
            .collect();
        assert!(!one_plane(&curve, 0..40));
        // A hole in it, or too few pixels to tell.
        let mut holed = wall.clone();
        holed[17] = NO_DEPTH;
        assert!(!one_plane(&holed, 0..40));
        assert!(!one_plane(&wall, 0..MIN_PLANE - 1));
        assert!(one_plane(&wall, 5..5 + MIN_PLANE));
    }

    #[test]
    fn an_occluders_edge_steps_and_a_shaded_curve_ramps() {
        // 40 columns from grey 200 to grey 120: hue_dist of the two is 3·80 = 240.
        let grey = |g: i32| [g, g, g];
        let contrast = 240;
        // A step at column 20, one blended column (a soft lens) between.
        let step: Vec<_> = (0..40)
            .map(|k| {
                grey(if k < 20 {
                    200
                } else if k == 20 {
                    160
                } else {
                    120
                })
            })
            .collect();
        // The layout may put the occluder's start a few columns off the edge.
        for o0 in [14, 20, 26] {
            assert!(steps_in(&step, o0, contrast), "step, layout at {o0}");
        }
        assert!(
            !steps_in(&step, 6, contrast),
            "an edge 14 columns away is not near"
        );
        // The same fall spread evenly over 30 columns (shading round a cylinder): 2.7 a column,
        // so two columns either side of one differ by 4 columns' worth, 3·10.7 = 32 < 120.
        let ramp: Vec<_> = (0..40)
            .map(|k| grey(200 - (80 * (k - 5).clamp(0, 30)) / 30))
            .collect();
        for o0 in [10, 20, 30] {
            assert!(!steps_in(&ramp, o0, contrast), "ramp, layout at {o0}");
        }
    }

    #[test]
    fn integer_round_and_ceil_match_the_float_ones() {
        for k in -4000i64..4000 {
            let x = k as f64 / 16.0 + [0.0, 1e-9, -1e-9][k.rem_euclid(3) as usize];
            assert_eq!(round(x), x.round() as i64, "round({x})");
            assert_eq!(ceil(x), x.ceil() as i64, "ceil({x})");
        }
    }

    /// [`hole_span`] pixel by pixel: the reference.
    fn hole_span_by_pixels(row: &[u16], u: usize) -> (usize, usize) {
        let run_end = |from: usize| {
            row[from..]
                .iter()
                .position(|&r| r != NO_DEPTH)
                .map_or(row.len(), |k| from + k)
        };
        let run_start = |to: usize| {
            row[..to]
                .iter()
                .rposition(|&r| r != NO_DEPTH)
                .map_or(0, |k| k + 1)
        };
        let mut b = run_end(u);
        while b < row.len() {
            let island = row[b..]
                .iter()
                .take(MAX_ISLAND + 1)
                .take_while(|&&r| r != NO_DEPTH)
                .count();
            if island > MAX_ISLAND || b + island >= row.len() {
                break;
            }
            b = run_end(b + island);
        }
        let mut a = run_start(u);
        while a > 0 {
            let island = row[..a]
                .iter()
                .rev()
                .take(MAX_ISLAND + 1)
                .take_while(|&&r| r != NO_DEPTH)
                .count();
            if island > MAX_ISLAND || island >= a {
                break;
            }
            a = run_start(a - island);
        }
        (a, b)
    }

    #[test]
    fn a_lone_lit_pixel_joins_two_holes_and_two_pixels_part_them() {
        let mut row = vec![900u16; WIDTH];
        row[100..110].fill(NO_DEPTH);
        row[111..120].fill(NO_DEPTH); // one pixel apart: one hole
        row[200..210].fill(NO_DEPTH);
        row[212..220].fill(NO_DEPTH); // two pixels apart: two
        let mask = HoleMask::of(&row);
        assert_eq!(hole_span(&mask, &row, 105), (100, 120));
        assert_eq!(hole_span(&mask, &row, 115), (100, 120));
        assert_eq!(hole_span(&mask, &row, 205), (200, 210));
        assert_eq!(hole_span(&mask, &row, 215), (212, 220));
    }

    #[test]
    fn hole_span_on_the_bitmap_matches_the_pixel_scan() {
        // Holes and valid islands of 1 to 5 pixels (some merge, some do not), up to both ends.
        let mut seed = 0x2545_f491_u32;
        for _ in 0..200 {
            let mut row = Vec::with_capacity(WIDTH);
            while row.len() < WIDTH {
                seed ^= seed << 13;
                seed ^= seed >> 17;
                seed ^= seed << 5;
                let len = 1 + (seed >> 8) as usize % 5;
                let value = if seed.is_multiple_of(2) {
                    NO_DEPTH
                } else {
                    900
                };
                row.extend(std::iter::repeat_n(value, len));
            }
            row.truncate(WIDTH);
            let mask = HoleMask::of(&row);
            for u in (0..WIDTH).filter(|&u| row[u] == NO_DEPTH) {
                assert_eq!(
                    hole_span(&mask, &row, u),
                    hole_span_by_pixels(&row, u),
                    "at {u}"
                );
            }
            // The colour split's walk from span to span: after the first, every span starts
            // where the walk arrives, so its start need not be searched for.
            let mut u = mask.next_hole(SIDE);
            let mut first = true;
            while u < WIDTH - SIDE {
                let (a, b) = hole_span_by_pixels(&row, u);
                if !first {
                    assert_eq!(a, u, "a span of the walk starts where it arrives");
                }
                assert_eq!(span_end(&mask, &row, u), b, "at {u}");
                first = false;
                u = mask.next_hole(b.max(u + 1));
            }
        }
    }
}
