//! Alignment to the RGB view: forward-warps the depth map into the RGB camera, carries the IR-view
//! labels along and finds alignment shadows (SPEC §1).
//!
//! Each source pixel lands on its nearest target pixel, z-buffered. Where two horizontally
//! adjacent pixels are not connected (a depth edge) and the left one is nearer, they split apart
//! in the RGB view: the background in the gap between their footprints is seen by the RGB camera
//! but not by the IR camera — an alignment shadow. What is left empty inside a surface is a crack
//! of forward warping (resampling, slanted surfaces) and is filled from its neighbours, so it is
//! not mistaken for a hole. Holes are warped too, at the depth the scanline classifier assumed for
//! them, so projector shadows carry over. Target pixels nothing lands on lie outside the IR
//! camera's field of view and stay OTHER.
//!
//! The loops are shaped for speed (one frame must take well under a millisecond): a branch-free
//! projection pass per row, then one z-test per source pixel; depth edges are rare, so the gap
//! handling costs nothing on most pixels.

use super::depthless::{dimmed, hue_dist, DEAD_BAND};
use crate::calib::Calibration;
use crate::labels::{ALIGNMENT, ATTACHED, HEIGHT, NO_DEPTH, OTHER, PIXELS, VALID, WIDTH};

/// The z-buffer holds `astray << 31 | depth_mm << 16 | off_centre << 4 | parity << 3 | label`:
/// one integer compare picks what a target pixel shows, and the label travels with its depth
/// (one load and one store per splatted pixel). A source pixel whose footprint misses the
/// target's centre (`astray`) landed there only by rounding: it loses to every one whose
/// footprint holds it, whatever their depths. Two IR rows land on one RGB row every ninth row
/// (the RGB camera's pixels are larger), and where the sensor's widening swallowed an occluder's
/// edge in one of them, the nearer row's occluder hid the other's shadow where the RGB pixel's
/// centre sees the shadow (RGB attached F1 +0.005, any-shadow recall +0.007 on every simulated
/// suite). Otherwise the nearer surface wins. Sources at exactly the same depth (a hole filled
/// with its neighbour's depth, say) are neighbours: of those, the one whose footprint holds the
/// centre at all wins (`off_centre` 0), so a shadow's edge along the rows falls where the pixel
/// centres say; where neither does, the parity of `u + v`, which differs between any two
/// neighbours, decides, so the label code never does (that biased every boundary towards VALID).
const LABEL_BITS: u32 = 3;
/// Bits between label and depth; the lowest two hold the tie-breaks.
const TIE_BITS: u32 = 13;
/// The depth field: millimetres, at most [`MAX_DEPTH_MM`].
const DEPTH_MASK: u32 = 0x7fff;
/// Farthest depth a key holds (far beyond a Kinect's range; the field has 15 bits).
const MAX_DEPTH_MM: f32 = 32_000.0;
/// The `astray` bit: the source pixel's footprint misses the target's centre.
const ASTRAY_BIT: u32 = 31;
/// Empty: above every key, and its label bits are OTHER (nothing of the IR view lands there).
const EMPTY: u32 = !((1 << LABEL_BITS) - 1) | OTHER as u32;
/// Z-buffer value of an alignment-shadow pixel: behind every real surface.
const GAP: u32 = (0xfffe << (LABEL_BITS + TIE_BITS)) | ALIGNMENT as u32;
/// Z-buffer value of a pixel that sees a surface outside the IR camera's view past a near object
/// at its left border: behind every real surface too, and kept by crack filling over [`GAP`].
const OUT_OF_VIEW: u32 = (0xfffe << (LABEL_BITS + TIE_BITS)) | OTHER as u32;
// Behind every real key, astray ones too.
const _: () = assert!(
    GAP > (1 << ASTRAY_BIT) | ((MAX_DEPTH_MM as u32) << (LABEL_BITS + TIE_BITS)) | 0xffff
        && (MAX_DEPTH_MM as u32) <= DEPTH_MASK
);
/// Source columns from the IR camera's left border within which a gap's far end may be seen
/// past it (wider than any alignment strip).
const FOV_REACH: usize = 96;
/// Target index of a source pixel that lands outside the RGB image: a spare z-buffer slot.
const OUTSIDE: u32 = PIXELS as u32;

/// Precomputed warp for one calibration plus its scratch buffers.
pub struct Warp {
    /// Inverse depth is linear in raw: `iz = (denominator − raw) / numerator`.
    iz_scale: f32,
    iz_offset: f32,
    /// Which build of the hot loops this CPU runs (detected once).
    simd: Simd,
    /// The RGB camera is the IR camera moved along its x axis (no rotation, as in the NYU
    /// defaults and libfreenect's registration; the NYU toolbox's own calibration has one): every
    /// ray's z is 1, so the target row is fixed per source row and the column is linear in
    /// inverse depth, with no division.
    affine: bool,
    /// `R · K_depth⁻¹ · (0, v, 1)` per source row: the rotated ray of column 0.
    row_ray: Vec<[f32; 3]>,
    /// `R · K_depth⁻¹ · (1, 0, 0)`: the ray's change per column.
    col_step: [f32; 3],
    t: [f32; 3],
    rgb_f: [f32; 2],
    rgb_c: [f32; 2],
    /// Half a source pixel's width in the target, per unit of `1/nz`.
    half_px: f32,
    /// The same vertically.
    half_py: f32,
    /// [`Warp::half_px`] plus half of what one raw unit of depth moves a pixel in the RGB image:
    /// the sensor's noise moves neighbouring footprints apart by about that much, and a centre
    /// in such a gap is no reason for a hidden far pixel to win it (the astray bit).
    astray_px: f32,
    /// Raw-value step above which neighbours are different surfaces (1.5 px of disparity).
    jump_raw: i32,
    /// A fixed-size array, so the splat's index clamp proves every store in bounds.
    zbuf: Box<[u32; PIXELS + 1]>,
    target: Vec<u32>,
    /// Packed z-buffer key of each pixel of the current source row; `EMPTY` for no depth.
    keys: Vec<u32>,
    /// `(u & 1) << LABEL_BITS` per column, for the tie-break bit.
    parity: Vec<u32>,
    /// Per column `u`: `u·fx·col_step.x`, `u·fy·col_step.y`, `u·col_step.z`, the ray's change
    /// from column 0 in the projection's terms (products the vector loop need not form; the
    /// same f32 operations as forming them there, so the same values).
    col_x: Vec<f32>,
    col_y: Vec<f32>,
    col_z: Vec<f32>,
    /// The current source row's depth edges, from [`Warp::find_edges`] (capacity reserved once).
    edge_list: Vec<(usize, bool)>,
    /// The colour steps' factor for the frame's camera noise, in 64ths
    /// ([`step_scale`](super::noise::step_scale)).
    noise_scale: u32,
    /// Pixels the sensor's widening adds to a hole's end in the current frame
    /// ([`FrameFacts::left_widening`](super::scanline::FrameFacts::left_widening)).
    widening: f64,
    /// Depth (mm) from which a surface counts as at the range's end ([`Warp::set_range_end`]).
    range_end_mm: u16,
    /// Per RGB row, the IR view's left edge: the first column any IR pixel landed in, or
    /// [`Self::fov_past_near`]'s where that lies further right.
    fov_start: Vec<u16>,
    /// Per RGB row, the first column where the far surface past a near object at the IR view's
    /// left border is in the IR camera's view (0 where there is none): the view's left edge
    /// for that surface, right of where the near object landed.
    fov_past_near: Vec<u16>,
    /// How wide [`super::unseen`] looks for alignment shadows.
    reach: super::unseen::Reach,
    /// The far ends of this frame's alignment strips the colour placed ([`FarEnd`]).
    far_ends: Vec<FarEnd>,
    /// Per far end, the index of the same edge's in the source row or two above, and below
    /// ([`NO_LINK`] where there is none).
    far_links: Vec<[u32; 2]>,
}

/// No far end of the same edge in the rows next to this one.
const NO_LINK: u32 = u32::MAX;

/// An alignment strip's row whose near end the colour placed ([`Warp::colour_gap`]): the far
/// end follows from where inside the near pixel the depth edge lies, known to within the
/// interval `[a, b]` (source pixels from the near pixel's right footprint edge `lo`); along an
/// edge that slants, the rows around pin it better ([`Warp::refine_far_ends`]).
#[derive(Clone, Copy, Debug)]
struct FarEnd {
    /// Source row.
    v: u16,
    /// Target row the strip lies on.
    line: u16,
    /// The strip's first column (the colour edge) and the column past it (its far end).
    e0: u16,
    e1: u16,
    /// The near pixel's right footprint edge at the near depth, the far pixel's left one at the
    /// far depth (target columns, unrounded).
    lo: f32,
    hi: f32,
    /// Where inside the near pixel this row's colour and depth allow the edge.
    a: f32,
    b: f32,
    /// The far surface's z-buffer key.
    far: u32,
}

/// Strip rows [`Warp::refine_far_ends`] keeps per frame (a busy frame has a few thousand).
const FAR_ENDS: usize = 8192;
/// Source rows above and below a strip's row whose near ends [`Warp::refine_far_ends`] fits a
/// line through. At 2 the simulated suites gained a little less alignment F1; at 4 and 5
/// detached F1 lost a little more where a strip abuts a shadow.
const FAR_END_ROWS: u16 = 3;

/// The target pixel's centre lies left of the source pixel's footprint (it was rounded down).
const LEFT_OF_FOOTPRINT: u8 = 1;
/// The target pixel's centre lies right of the source pixel's footprint (it was rounded up).
const RIGHT_OF_FOOTPRINT: u8 = 2;

impl Warp {
    /// Precomputes the warp of `calib`'s depth camera into its RGB camera.
    pub fn new(calib: &Calibration) -> Self {
        let d = calib.depth;
        let r = calib.depth_to_rgb.rotation;
        let t = calib.depth_to_rgb.translation;
        let rot = |x: f64, y: f64, z: f64| {
            let v = r * nalgebra::Vector3::new(x, y, z);
            [v.x as f32, v.y as f32, v.z as f32]
        };
        let col_step = rot(1.0 / d.fx, 0.0, 0.0);
        Warp {
            iz_scale: (-1.0 / calib.raw.numerator) as f32,
            iz_offset: (calib.raw.denominator / calib.raw.numerator) as f32,
            simd: Simd::detect(),
            affine: r == nalgebra::Matrix3::identity() && t.y == 0.0 && t.z == 0.0,
            row_ray: (0..HEIGHT)
                .map(|v| rot(-d.cx / d.fx, (v as f64 - d.cy) / d.fy, 1.0))
                .collect(),
            col_step,
            t: [t.x as f32, t.y as f32, t.z as f32],
            rgb_f: [calib.rgb.fx as f32, calib.rgb.fy as f32],
            rgb_c: [calib.rgb.cx as f32, calib.rgb.cy as f32],
            half_px: (0.5 * calib.rgb.fx / d.fx) as f32,
            half_py: (0.5 * calib.rgb.fy / d.fy) as f32,
            astray_px: (0.5 * calib.rgb.fx / d.fx
                + 0.5 * calib.rgb.fx * calib.depth_to_rgb.translation.x.abs() / calib.raw.numerator)
                as f32,
            // At least one raw unit: a jump of none would make every pair of pixels an edge.
            jump_raw: ((1.5 / calib.px_per_raw()).round() as i32).max(1),
            zbuf: vec![EMPTY; PIXELS + 1]
                .into_boxed_slice()
                .try_into()
                .expect("PIXELS + 1 slots"),
            target: vec![OUTSIDE; WIDTH],
            keys: vec![EMPTY; WIDTH],
            col_x: column_terms(calib.rgb.fx as f32 * col_step[0]),
            col_y: column_terms(calib.rgb.fy as f32 * col_step[1]),
            col_z: column_terms(col_step[2]),
            edge_list: Vec::with_capacity(WIDTH),
            parity: (0..WIDTH).map(|u| ((u & 1) as u32) << LABEL_BITS).collect(),
            noise_scale: 64,
            widening: 0.0,
            range_end_mm: u16::MAX,
            fov_start: vec![0; HEIGHT],
            fov_past_near: vec![0; HEIGHT],
            reach: super::unseen::Reach {
                px_m: (calib.rgb.fx * t.x.abs()) as f32,
            },
            far_ends: Vec::with_capacity(FAR_ENDS),
            far_links: Vec::with_capacity(FAR_ENDS),
        }
    }

    /// Scales the colour tests' steps for the camera noise of the frames to come, in 64ths of
    /// them ([`step_scale`](super::noise::step_scale)); 64 until set.
    pub fn set_noise_scale(&mut self, scale: u32) {
        self.noise_scale = scale;
    }

    /// Sets how many pixels the sensor's widening adds to a hole's end in the frames to come
    /// ([`FrameFacts::left_widening`](super::scanline::FrameFacts::left_widening)); 0 until set.
    pub fn set_widening(&mut self, px: f64) {
        self.widening = px;
    }

    /// Sets where the sensor's range ends in the frames to come (raw value,
    /// [`Range::limit`](super::scanline::Range::limit)); never until set.
    pub fn set_range_end(&mut self, limit: u16) {
        let iz = self.iz_offset
            + self.iz_scale * f32::from(limit.saturating_sub(super::depthless::RANGE_END));
        self.range_end_mm = if iz > 0.0 {
            (1000.0 / iz).min(f32::from(u16::MAX)) as u16
        } else {
            u16::MAX
        };
    }

    /// `step` for a far surface of colour `bg` ([`dimmed`]) and the frame's camera noise.
    #[inline]
    fn dimmed(&self, step: u32, bg: [i32; 3]) -> u32 {
        dimmed(step, bg) * self.noise_scale / 64
    }

    /// Runs the given build of the hot loops (tests compare the builds).
    #[cfg(test)]
    pub(crate) fn set_simd(&mut self, simd: Simd) {
        self.simd = simd;
    }

    /// Projects with the general formula even where the calibration allows the affine one
    /// (tests compare the two).
    #[cfg(test)]
    pub(crate) fn force_general(&mut self) {
        self.affine = false;
    }

    /// Whether the calibration allows the affine projection.
    #[cfg(test)]
    pub(crate) fn is_affine(&self) -> bool {
        self.affine
    }

    /// The SIMD level of the hot loops this warp runs.
    pub(crate) fn simd_name(&self) -> &'static str {
        match self.simd {
            Simd::Avx512 => "AVX-512",
            Simd::Avx2 => "AVX2",
            Simd::Baseline => "baseline x86-64 loops",
        }
    }

    /// Which projection loop the calibration allows.
    pub(crate) fn projection_name(&self) -> &'static str {
        if self.affine {
            "affine warp"
        } else {
            "general warp"
        }
    }

    /// Warps one frame. `filled` is the raw map with every hole given an assumed depth (from the
    /// scanline classifier), `ir` the IR-view labels; writes RGB-view labels and registered depth
    /// in millimetres (0 where the RGB pixel has no measured depth).
    pub fn apply(&mut self, filled: &[u16], ir: &[u8], rgb: &mut [u8], mm: &mut [u16]) {
        self.apply_with_colour(filled, ir, None, rgb, mm);
    }

    /// [`Warp::apply`] with the RGB image (RGB8, 640·480·3) the labels are for: where a depth
    /// edge lands within a pixel of a colour edge, the label boundary follows the colour edge
    /// (the warp places an edge only to within the IR pixel it fell in).
    pub fn apply_with_colour(
        &mut self,
        filled: &[u16],
        ir: &[u8],
        colour: Option<&[u8]>,
        rgb: &mut [u8],
        mm: &mut [u16],
    ) {
        assert!(
            filled.len() == PIXELS
                && ir.len() == PIXELS
                && rgb.len() == PIXELS
                && mm.len() == PIXELS
                && colour.is_none_or(|c| c.len() == 3 * PIXELS)
        );
        // SAFETY: each build runs only when the CPU reported its features at construction.
        #[cfg(target_arch = "x86_64")]
        match self.simd {
            Simd::Avx512 => return unsafe { self.apply_avx512(filled, ir, colour, rgb, mm) },
            Simd::Avx2 => return unsafe { self.apply_avx2(filled, ir, colour, rgb, mm) },
            Simd::Baseline => {}
        }
        self.apply_body(filled, ir, colour, rgb, mm);
    }

    /// The same code compiled for AVX2+FMA: eight pixels per instruction in the projection.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,fma")]
    unsafe fn apply_avx2(
        &mut self,
        filled: &[u16],
        ir: &[u8],
        colour: Option<&[u8]>,
        rgb: &mut [u8],
        mm: &mut [u16],
    ) {
        self.apply_body(filled, ir, colour, rgb, mm);
    }

    /// The same code compiled for AVX-512: sixteen pixels per instruction in the projection.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx512f,avx512bw,avx512vl,avx512dq,avx2,fma")]
    unsafe fn apply_avx512(
        &mut self,
        filled: &[u16],
        ir: &[u8],
        colour: Option<&[u8]>,
        rgb: &mut [u8],
        mm: &mut [u16],
    ) {
        self.apply_body(filled, ir, colour, rgb, mm);
    }

    #[inline(always)]
    fn apply_body(
        &mut self,
        filled: &[u16],
        ir: &[u8],
        colour: Option<&[u8]>,
        rgb: &mut [u8],
        mm: &mut [u16],
    ) {
        // The z-buffer is all EMPTY here: allocated so, and reset row by row below.
        self.fov_past_near.fill(0);
        self.far_ends.clear();
        for v in 0..HEIGHT {
            let row = v * WIDTH..(v + 1) * WIDTH;
            self.project_row(v, &filled[row.clone()], &ir[row.clone()]);
            self.splat_row(v, &filled[row.clone()], &ir[row], colour);
        }
        self.refine_far_ends();
        // One pass over the z-buffer while each row is in L1: fill cracks, unpack, and reset the
        // row above (the crack test of this row still read it).
        for v in 0..HEIGHT {
            let row = v * WIDTH..(v + 1) * WIDTH;
            let (done, rest) = self.zbuf.split_at_mut(row.start);
            let (cur, below) = rest.split_at_mut(WIDTH);
            let mut above = (v > 0).then(|| &mut done[row.start - WIDTH..]);
            let below = (v + 1 < HEIGHT).then(|| &below[..WIDTH]);
            fill_cracks_row(cur, above.as_deref(), below);
            if colour.is_some() {
                let first = cur.iter().position(|&k| k != EMPTY).unwrap_or(WIDTH) as u16;
                self.fov_start[v] = first.max(self.fov_past_near[v]);
            }
            unpack_row(cur, &mut rgb[row.clone()], &mut mm[row]);
            if let Some(above) = above.as_mut() {
                above.fill(EMPTY);
            }
        }
        self.zbuf[PIXELS - WIDTH..].fill(EMPTY);
        if let Some(colour) = colour {
            let (fov, reach) = (&self.fov_start, self.reach);
            let sensor = super::unseen::Sensor {
                noise_scale: self.noise_scale,
                widening: self.widening,
                range_end_mm: self.range_end_mm,
            };
            super::unseen::open_gaps(rgb, mm, colour, fov, reach, sensor);
        }
    }

    /// Projects every pixel of source row `v` into the RGB image: `n = R·ray(u) + t·iz`, target
    /// `x = fx·nx/nz + cx`, depth along the RGB axis `nz/iz`; writes each pixel's target index
    /// and z-buffer key. The loops are branch-free, rounding with [`round_f32`] and
    /// [`round_bits`], so the compiler vectorises them.
    #[inline(always)]
    fn project_row(&mut self, v: usize, filled: &[u16], ir: &[u8]) {
        if self.affine {
            self.project_row_affine(v, filled, ir);
        } else {
            self.project_row_general(v, filled, ir);
        }
    }

    /// [`Warp::project_row`] for an [`affine`](Warp::affine) calibration: `nz = 1`, so
    /// `x = fx·(ray_x + t_x·iz) + cx`, `y` is the row's, and the depth is `1/iz`. A third fewer
    /// operations per pixel than the general loop, and no division but the depth's.
    #[inline(always)]
    fn project_row_affine(&mut self, v: usize, filled: &[u16], ir: &[u8]) {
        let [bx, by, _] = self.row_ray[v];
        let tx = self.t[0];
        let (fx, fy) = (self.rgb_f[0], self.rgb_f[1]);
        let (bx, tx) = (fx * bx, fx * tx);
        let (cx, cy) = (self.rgb_c[0], self.rgb_c[1]);
        let (w, h) = (WIDTH as f32 - 0.5, HEIGHT as f32 - 0.5);
        let (iz_scale, iz_offset) = (self.iz_scale, self.iz_offset);
        let (half_x, astray_x) = (self.half_px, self.astray_px);
        // What the general loop computes per pixel for y is the row's here.
        let y = fy * by + cy;
        let yr = round_f32(y);
        let row_inside = (y > -0.5) & (y < h);
        let y_off = (y - yr).abs() > self.half_py;
        let row_start = yr * WIDTH as f32;
        let out = self.target.iter_mut().zip(self.keys.iter_mut());
        let flip = ((v & 1) as u32) << LABEL_BITS;
        let inputs = filled.iter().zip(&self.col_x).zip(ir).zip(&self.parity);
        for ((t_out, k_out), (((&raw, &ux), &label), &parity)) in out.zip(inputs) {
            let rawf = f32::from(raw);
            let iz = rawf * iz_scale + iz_offset;
            let x = (bx + ux + tx * iz) + cx;
            let valid = (iz > 0.0) & (rawf < NO_DEPTH as f32 - 0.5);
            let inside = valid & row_inside & (x > -0.5) & (x < w);
            let xr = round_f32(x);
            let off_centre = ((x - xr).abs() > half_x) | y_off;
            let astray = ((x - xr).abs() > astray_x) | y_off;
            *t_out = if inside {
                round_bits(row_start + xr)
            } else {
                OUTSIDE
            };
            let z = round_bits(clamp_fast(1000.0 / iz, 1.0, MAX_DEPTH_MM));
            let key = (u32::from(astray) << ASTRAY_BIT)
                | (z << (LABEL_BITS + TIE_BITS))
                | (u32::from(off_centre) << (LABEL_BITS + 1))
                | (parity ^ flip)
                | u32::from(label);
            *k_out = if valid { key } else { EMPTY };
        }
    }

    /// [`Warp::project_row`] for any calibration. One division gives both quotients
    /// (`r = 1/(nz·iz)`, so `1/nz = r·iz` and `1/iz = r·nz`).
    #[inline(always)]
    fn project_row_general(&mut self, v: usize, filled: &[u16], ir: &[u8]) {
        let [bx, by, bz] = self.row_ray[v];
        let [tx, ty, tz] = self.t;
        let (fx, fy) = (self.rgb_f[0], self.rgb_f[1]);
        // The focal lengths folded into the ray once per row: two multiplies fewer per pixel.
        let (bx, tx) = (fx * bx, fx * tx);
        let (by, ty) = (fy * by, fy * ty);
        let (cx, cy) = (self.rgb_c[0], self.rgb_c[1]);
        let (w, h) = (WIDTH as f32 - 0.5, HEIGHT as f32 - 0.5);
        let (iz_scale, iz_offset) = (self.iz_scale, self.iz_offset);
        let (half_x, half_y, astray_x) = (self.half_px, self.half_py, self.astray_px);
        let out = self.target.iter_mut().zip(self.keys.iter_mut());
        // Bit LABEL_BITS holds the parity of u + v: the columns' parities, flipped on odd rows.
        let flip = ((v & 1) as u32) << LABEL_BITS;
        let columns = self.col_x.iter().zip(&self.col_y).zip(&self.col_z);
        let inputs = filled.iter().zip(columns).zip(ir).zip(&self.parity);
        for ((t_out, k_out), (((&raw, ((&ux, &uy), &uz)), &label), &parity)) in out.zip(inputs) {
            let rawf = f32::from(raw);
            let iz = rawf * iz_scale + iz_offset;
            let nz = bz + uz + tz * iz;
            let r = 1.0 / (nz * iz);
            let inv_nz = r * iz;
            let x = (bx + ux + tx * iz) * inv_nz + cx;
            let y = (by + uy + ty * iz) * inv_nz + cy;
            // The hole test on the float already at hand (one compare, no 16-bit widening).
            let valid = (iz > 0.0) & (rawf < NO_DEPTH as f32 - 0.5) & (nz > 0.0);
            // `&`, not `&&`: no short-circuit branches in the vector loop.
            let inside = valid & (x > -0.5) & (x < w) & (y > -0.5) & (y < h);
            // Lanes that are not `inside` may hold garbage here; the select below drops them.
            let (xr, yr) = (round_f32(x), round_f32(y));
            let index = yr * WIDTH as f32 + xr;
            // Of sources at one depth on one target, the one whose footprint holds the target's
            // centre wins (footprints tile, so at most one does); parity breaks what is left.
            let y_off = (y - yr).abs() > half_y;
            let off_centre = ((x - xr).abs() > half_x) | y_off;
            let astray = ((x - xr).abs() > astray_x) | y_off;
            *t_out = if inside { round_bits(index) } else { OUTSIDE };
            let z = round_bits(clamp_fast(1000.0 * nz * nz * r, 1.0, MAX_DEPTH_MM));
            let key = (u32::from(astray) << ASTRAY_BIT)
                | (z << (LABEL_BITS + TIE_BITS))
                | (u32::from(off_centre) << (LABEL_BITS + 1))
                | (parity ^ flip)
                | u32::from(label);
            *k_out = if valid { key } else { EMPTY };
        }
    }

    #[inline(always)]
    fn splat_row(&mut self, v: usize, filled: &[u16], ir: &[u8], colour: Option<&[u8]>) {
        self.find_edges(filled);
        self.drop_spikes();
        // Each pixel lands on the target pixel nearest its centre, but its footprint is a little
        // narrower than a target pixel: at a depth edge that nearest pixel's centre may lie
        // outside it, on the side where the RGB camera sees the farther surface (or the
        // alignment gap) past the edge. There the nearer pixel lands one target over, so the
        // label boundary falls where the pixel centres do.
        let mut edges = std::mem::take(&mut self.edge_list);
        for &(u, rising) in &edges {
            let near = if rising { u } else { u + 1 };
            let t = self.target[near];
            if t == OUTSIDE {
                continue;
            }
            let col = t as usize % WIDTH;
            match self.footprint_side(v, near, filled[near]) {
                RIGHT_OF_FOOTPRINT if rising && col > 0 => self.target[near] = t - 1,
                LEFT_OF_FOOTPRINT if !rising && col + 1 < WIDTH => self.target[near] = t + 1,
                _ => {}
            }
            // The far pixel beyond a rising edge opens the alignment gap: where its nearest
            // target's centre lies left of its footprint, that target shows the gap.
            if rising {
                let t = self.target[u + 1];
                if t != OUTSIDE
                    && (t as usize % WIDTH) + 1 < WIDTH
                    && self.footprint_side(v, u + 1, filled[u + 1]) == LEFT_OF_FOOTPRINT
                {
                    self.target[u + 1] = t + 1;
                }
            }
        }
        // The IR image's borders end footprints too: a target pixel whose centre lies past the
        // first (or last) pixel's footprint shows what the IR camera does not see.
        for (u, outward) in [(0, LEFT_OF_FOOTPRINT), (WIDTH - 1, RIGHT_OF_FOOTPRINT)] {
            let t = self.target[u];
            if t == OUTSIDE || self.keys[u] == EMPTY {
                continue;
            }
            let col = t as usize % WIDTH;
            if self.footprint_side(v, u, filled[u]) == outward {
                self.target[u] = match outward {
                    LEFT_OF_FOOTPRINT if col + 1 < WIDTH => t + 1,
                    RIGHT_OF_FOOTPRINT if col > 0 => t - 1,
                    _ => OUTSIDE,
                };
            }
        }
        // And its first and last rows: a target row whose centre lies above the first row's
        // footprint (below the last's) shows what the IR camera does not see; the next row in,
        // which the footprint reaches, shows that pixel.
        if v == 0 || v == HEIGHT - 1 {
            self.end_footprints_at_row(v, filled);
        }
        // The colour reads at this row's depth edges come after the scatter; the RGB image is
        // seldom in cache, so its lines are fetched now, while the scatter runs.
        #[cfg(target_arch = "x86_64")]
        if let Some(colour) = colour {
            for &(u, _) in &edges {
                let t = self.target[u + 1];
                if t != OUTSIDE {
                    let at = colour[3 * t as usize..].as_ptr();
                    // SAFETY: a prefetch only hints the cache; `at` points into `colour`.
                    unsafe {
                        std::arch::x86_64::_mm_prefetch::<{ std::arch::x86_64::_MM_HINT_T0 }>(
                            at.cast(),
                        )
                    };
                }
            }
        }
        match self.simd {
            // SAFETY: this level runs only when the CPU reported AVX-512 at construction.
            #[cfg(target_arch = "x86_64")]
            Simd::Avx512 => unsafe { scatter_avx512(&mut self.zbuf, &self.target, &self.keys) },
            _ => scatter(&mut self.zbuf, &self.target, &self.keys),
        }
        // A nearer pixel followed by a farther one splits apart: the RGB camera, right of the IR
        // camera, sees background there that the IR camera cannot.
        for &(u, rising) in &edges {
            // Background the RGB camera sees there is a hole anyway when the surface beyond the
            // edge is one (beyond range, black): that is OTHER, which empty pixels become.
            if rising && self.keys[u + 1] != EMPTY && ir[u + 1] != OTHER {
                self.mark_gap(v, u, filled, colour);
            } else if let (false, Some(colour)) = (rising, colour) {
                self.snap_near_start(u, filled, colour);
            }
        }
        let last_edge = edges.last().copied();
        edges.clear();
        self.edge_list = edges;
        if let (Some(colour), Some(edge)) = (colour, last_edge) {
            self.mark_right_border_gap(v, filled, ir, colour, edge);
        }
    }

    /// Marks the alignment shadow past a near object that runs off the IR image's right edge
    /// (the border, or the sensor's dead band before it), where no far pixel follows it to open
    /// a gap. The RGB camera, right of the IR camera, sees past the object's edge background
    /// that the object hides from the IR camera, up to where the IR camera's view ends at the
    /// background's depth: an alignment shadow (SPEC §1), which was left OTHER as outside the
    /// view. The background is the one the object's attached shadow lies on; the colour shows
    /// where the object ends (it may run on past the strip, or show its shaded rim): the strip
    /// is read where the RGB camera sees, past it, that background's colour, and from the first
    /// pixel of that colour on. (A seventh simulator written from SPEC alone, four suites: RGB
    /// alignment F1 +0.0030 summed over complex scenes, +0.0058 over simple ones (a pole
    /// leaning out of the view), any-shadow precision −0.0001; this project's fourteen suites
    /// +0.0095, precision −0.0010, recall +0.0066; the real frame unchanged.)
    fn mark_right_border_gap(
        &mut self,
        v: usize,
        filled: &[u16],
        ir: &[u8],
        colour: &[u8],
        (e, rising): (usize, bool),
    ) {
        // A dead band is the sensor's own, the same width in every row (a wider hole there is
        // something the scene holds: a black object's, past which the background is unknown).
        let band = ir.iter().rev().take_while(|&&l| l == OTHER).count();
        if band != 0 && !(DEAD_BAND..=DEAD_BAND + 1).contains(&band) {
            return;
        }
        let last = WIDTH - 1 - band;
        let t = self.target[last];
        // The row's last depth edge (`e`, `e + 1`) steps from the object's attached shadow,
        // filled at the background's depth, onto the object, which runs on to the edge.
        if rising || e >= last || ir[e] != ATTACHED || t == OUTSIDE || ir[last] != VALID {
            return;
        }
        let bg = filled[e];
        if bg == NO_DEPTH || i32::from(filled[last]) + self.jump_raw > i32::from(bg) {
            return;
        }
        let line = t as usize / WIDTH;
        let lo = self.target_x(v, last, filled[last]) + self.half_px;
        let hi = self.target_x(v, last, bg) + self.half_px;
        let (c0, c1) = span(lo, hi, WIDTH);
        if c1 < c0 + 1 || c1 + 1 >= WIDTH {
            return;
        }
        let base = line * WIDTH;
        let px = |x: usize| colour_at(colour, base + x);
        // The object's colour a few pixels inside its edge, and the colour just past the strip.
        let Some(inside) = (3..8)
            .map(|k| self.target[last - k])
            .find(|&t| t != OUTSIDE && t as usize / WIDTH == line && (t as usize % WIDTH) + 2 < c0)
            .map(|t| t as usize % WIDTH)
        else {
            return;
        };
        let (cn, cf) = (px(inside), px(c1));
        if hue_dist(cn, cf) < self.dimmed(EDGE_CONTRAST, cf) {
            return;
        }
        // Past the strip the RGB camera must see the background the shadow lies on: the wall
        // left of the shadow (Sa), not the object's shaded rim running on.
        let sa = ir[..e].iter().rposition(|&l| l != ATTACHED);
        let Some(sa) = sa.filter(|&w| ir[w] == VALID) else {
            return;
        };
        let ts = self.target[sa];
        if ts == OUTSIDE || ts as usize / WIDTH != line {
            return;
        }
        let cw = px(ts as usize % WIDTH);
        if hue_dist(cf, cw) >= self.dimmed(EDGE_CONTRAST, cw) {
            return;
        }
        // The object may end a pixel or two before the warp puts its edge (within its last
        // pixel), or further on: every pixel from where the background shows is background.
        let far = |x: usize| {
            let p = px(x);
            hue_dist(p, cf) < hue_dist(p, cn)
        };
        let Some(from) = (c0.saturating_sub(2).max(inside + 1)..c1).find(|&x| far(x)) else {
            return;
        };
        if !(from..c1).all(far) {
            return;
        }
        // The object's own pixels past the IR camera's view, before the strip: crack filling
        // must not join them to it.
        for i in base + c0..base + from {
            if self.zbuf[i] == EMPTY {
                self.zbuf[i] = OUT_OF_VIEW;
            }
        }
        let near = key_depth(self.keys[last]);
        for i in base + from..base + c1 {
            let k = self.zbuf[i];
            if k == EMPTY || key_depth(k) == near {
                self.zbuf[i] = GAP;
            }
        }
    }

    /// Moves the targets of the IR image's first (`v` = 0) or last row one row inwards where
    /// their nearest target row's centre lies outside the pixel's footprint, beyond the IR
    /// image's edge (SPEC §1: RGB pixels outside the IR camera's field of view are OTHER).
    fn end_footprints_at_row(&mut self, v: usize, filled: &[u16]) {
        for (u, &raw) in filled.iter().enumerate().take(WIDTH) {
            let t = self.target[u];
            if t == OUTSIDE || self.keys[u] == EMPTY {
                continue;
            }
            let y = self.target_y(v, u, raw);
            let off = y - round_f32(y);
            let line = t as usize / WIDTH;
            if v == 0 && off > self.half_py {
                self.target[u] = if line + 1 < HEIGHT {
                    t + WIDTH as u32
                } else {
                    OUTSIDE
                };
            } else if v == HEIGHT - 1 && off < -self.half_py {
                self.target[u] = if line > 0 { t - WIDTH as u32 } else { OUTSIDE };
            }
        }
    }

    /// Forgets the two edges around a single pixel farther than both its neighbours. That is far
    /// more often a blend of a surface's edge with what lies beyond it along the other axis (a
    /// mixed pixel in an object's top or bottom row) than a slit onto the background, and
    /// warped as a slit it opens a gap inside the nearer surface's footprint; a real slit that
    /// narrow would show a pixel of background at most.
    fn drop_spikes(&mut self) {
        let edges = &mut self.edge_list;
        let mut k = 0;
        let mut keep = 0;
        while k < edges.len() {
            let (u, rising) = edges[k];
            if rising && k + 1 < edges.len() && edges[k + 1] == (u + 1, false) {
                k += 2;
                continue;
            }
            edges[keep] = edges[k];
            keep += 1;
            k += 1;
        }
        edges.truncate(keep);
    }

    /// Lists the depth edges of a source row in `edge_list`: `(u, rising)` where pixels `u` and
    /// `u + 1` differ by a jump, rising when `u + 1` is the farther. Disparity is linear in raw,
    /// so the test runs on raw values; edges are rare, so sixteen columns' tests become two bit
    /// masks at once and only set bits are visited.
    #[inline(always)]
    fn find_edges(&mut self, filled: &[u16]) {
        let jump = self.jump_raw;
        let pairs = filled.len() - 1;
        let mut u = 0;
        #[cfg(target_arch = "x86_64")]
        while u + 17 <= filled.len() {
            let (rise, fall) = edge_masks(&filled[u..u + 17], jump);
            let mut bits = rise | fall;
            while bits != 0 {
                let k = bits.trailing_zeros();
                self.edge_list.push((u + k as usize, rise >> k & 1 == 1));
                bits &= bits - 1;
            }
            u += 16;
        }
        for u in u..pairs {
            let step = i32::from(filled[u + 1]) - i32::from(filled[u]);
            if step >= jump {
                self.edge_list.push((u, true));
            } else if step <= -jump {
                self.edge_list.push((u, false));
            }
        }
    }

    /// Marks the target pixels between the footprints of source pixels `u` (near) and `u + 1`
    /// (far) of row `v` as alignment shadow, on the far pixel's target row, where nothing else
    /// landed.
    fn mark_gap(&mut self, v: usize, u: usize, filled: &[u16], colour: Option<&[u8]>) {
        let t = self.target[u + 1];
        if t == OUTSIDE {
            return;
        }
        let line = t as usize / WIDTH;
        let lo = self.target_x(v, u, filled[u]) + self.half_px;
        let hi = self.target_x(v, u + 1, filled[u + 1]) - self.half_px;
        let (mut c0, mut c1) = span(lo, hi, WIDTH);
        let base = line * WIDTH;
        // The near surface ends at a colour edge the RGB camera sees, and where it ends tells
        // where in pixel `u` the depth edge lies, which moves the gap's far end too.
        if let Some(colour) = colour {
            if let Some((e0, e1, [a, b])) =
                self.colour_gap(u, filled, colour, line, (lo, hi), (c0, c1))
            {
                let (near, far) = (self.keys[u], self.keys[u + 1]);
                // Pixels that show either side of this edge (or nothing yet) may change hands.
                let ours = |k: u32| {
                    k == EMPTY
                        || k == GAP
                        || key_depth(k) == key_depth(near)
                        || key_depth(k) == key_depth(far)
                };
                // Each end moves to where the colour puts it if the pixels it passes show
                // either side of this edge or nothing yet: a second source row that lands on
                // this target row (one in nine does) finds the first one's far surface a few
                // millimetres off its own, which once kept the near end where depth put it too.
                let (s0, s1) = (c0.min(e0), c0.max(e0));
                if (s0..s1).all(|x| ours(self.zbuf[base + x])) {
                    for x in s0..s1 {
                        self.zbuf[base + x] = if x < e0 { near } else { EMPTY };
                    }
                    c0 = e0;
                }
                // (Left of the gap's start, whichever it is, the near surface stays.)
                let (t0, t1) = (c1.min(e1).max(c0), c1.max(e1));
                if (t0..t1).all(|x| ours(self.zbuf[base + x])) {
                    for x in t0..t1 {
                        self.zbuf[base + x] = if x >= e1 { far } else { EMPTY };
                    }
                    c1 = e1;
                    if c0 == e0 && self.far_ends.len() < FAR_ENDS {
                        self.far_ends.push(FarEnd {
                            v: v as u16,
                            line: line as u16,
                            e0: e0 as u16,
                            e1: e1 as u16,
                            lo,
                            hi,
                            a,
                            b,
                            far,
                        });
                    }
                }
            }
        }
        // Behind a near object at the IR camera's left border, the RGB camera sees far points
        // left of the IR camera's first column: outside its view, OTHER (SPEC §2), no alignment.
        if u < FOV_REACH {
            let fov = self.target_x(v, 0, filled[u + 1]) - self.half_px;
            let edge = span(fov, fov, WIDTH).0;
            // Pixels the colour took from the near surface there see the far one outside the
            // view: crack filling must not join them to the gap.
            for x in c0..edge.min(c1) {
                if self.zbuf[base + x] == EMPTY {
                    self.zbuf[base + x] = OUT_OF_VIEW;
                }
            }
            c0 = c0.max(edge).min(c1);
            // The colour reading of strips past depthless occluders stops there too.
            self.fov_past_near[line] = self.fov_past_near[line].max(edge as u16);
        }
        for i in base + c0..base + c1 {
            if self.zbuf[i] == EMPTY {
                self.zbuf[i] = GAP;
            }
        }
    }

    /// Moves each recorded strip's far end to where the rows around it put its near end's
    /// edge. One row's colour and depth place the edge within its near pixel only to an interval
    /// up to a pixel wide, and the far end, the same point at the far depth, rounds either way
    /// about as often (a fifth to a quarter of the strips' rows ended a pixel off). Along an edge
    /// that slants, the colour's near ends step from row to row, and a line through the near
    /// ends of [`FAR_END_ROWS`] source rows each way places the edge within a fraction of a
    /// pixel. Where the near ends do not step (an edge along the columns) nothing is learnt.
    fn refine_far_ends(&mut self) {
        let ends = &self.far_ends[..];
        let links = &mut self.far_links;
        links.clear();
        links.resize(ends.len(), [NO_LINK; 2]);
        // Each end's edge in the source row above, or the one above that (its colour read may
        // have failed there): the nearest near end within a pixel and two per row between. The
        // ends are in source-row order: the last two rows' ranges are kept.
        let mut above = [(u16::MAX, 0, 0); 2];
        let mut start = 0;
        while start < ends.len() {
            let v = ends[start].v;
            let mut end = start + 1;
            while end < ends.len() && ends[end].v == v {
                end += 1;
            }
            for i in start..end {
                let e0 = ends[i].e0;
                let mut best = (NO_LINK, u16::MAX);
                for &(w, a, b) in &above {
                    if w >= v || w + 2 < v {
                        continue;
                    }
                    let limit = 2 * (v - w) + 1;
                    for (j, g) in ends[a..b].iter().enumerate() {
                        let d = g.e0.abs_diff(e0);
                        if d <= limit && d < best.1 {
                            best = ((a + j) as u32, d);
                        }
                    }
                    if best.0 != NO_LINK {
                        break;
                    }
                }
                let (j, d) = best;
                if j != NO_LINK {
                    links[i][0] = j;
                    let down = links[j as usize][1];
                    if down == NO_LINK || ends[down as usize].e0.abs_diff(ends[j as usize].e0) > d {
                        links[j as usize][1] = i as u32;
                    }
                }
            }
            above = [(v, start, end), above[0]];
            start = end;
        }
        let links = &*links;
        let step = 2.0 * self.half_px;
        for (i, f) in ends.iter().enumerate() {
            // The same edge's ends within reach along the links, up (with this one) and down;
            // most edges run with the columns, and their near ends never step.
            let (mut n, mut sx, mut sy, mut sxx, mut sxy) = (0f32, 0f32, 0f32, 0f32, 0f32);
            let mut stepped = false;
            for (dir, first) in [(0, i as u32), (1, links[i][1])] {
                let mut k = first;
                while k != NO_LINK {
                    let g = &ends[k as usize];
                    if g.v.abs_diff(f.v) > FAR_END_ROWS {
                        break;
                    }
                    let (x, y) = (f32::from(g.line) - f32::from(f.line), f32::from(g.e0) - 0.5);
                    n += 1.0;
                    sx += x;
                    sy += y;
                    sxx += x * x;
                    sxy += x * y;
                    stepped |= g.e0 != f.e0;
                    k = links[k as usize][dir];
                }
            }
            // Least squares through (line, e0 − ½), each pixel boundary's middle, where six of
            // the seven rows hold one and one steps.
            let det = n * sxx - sx * sx;
            if !stepped || n < f32::from(2 * FAR_END_ROWS) || det.abs() < 1e-6 {
                continue;
            }
            let edge = (sy - (n * sxy - sx * sy) / det * sx) / n;
            // Within what this row's colour and depth allow.
            let at = ((edge - f.lo) / step).clamp(f.a.min(f.b), f.a.max(f.b));
            let e1 = ceil_clamped(f.hi + at * step, WIDTH).max(usize::from(f.e0));
            let base = usize::from(f.line) * WIDTH;
            let was = usize::from(f.e1);
            let zbuf = &mut self.zbuf[base..base + WIDTH];
            // Only pixels that still show this edge's far surface, or its gap, change hands.
            if e1 > was && zbuf[was..e1].iter().all(|&k| k == f.far) {
                zbuf[was..e1].fill(GAP);
            } else if e1 < was && zbuf[e1..was].iter().all(|&k| k == GAP) {
                zbuf[e1..was].fill(f.far);
            }
        }
    }

    /// Where a nearer surface starts after source pixel `u` (farther) of the current row: the first
    /// target pixels the warp gave the near surface show the far one's colour when the depth
    /// edge lies late in pixel `u + 1`, and then take the far side's label (a projector shadow,
    /// mostly). Only that way: an edge the colour puts earlier may be where the sensor's
    /// correlation window swallowed the near surface's first pixels, which keep the shadow's
    /// label in the RGB view too.
    fn snap_near_start(&mut self, u: usize, filled: &[u16], colour: &[u8]) {
        let t = self.target[u + 1];
        if t == OUTSIDE || u + 3 >= WIDTH {
            return;
        }
        // The near pixel's target is, after the footprint test, the first whose centre it covers.
        let (line, x) = (t as usize / WIDTH, t as usize % WIDTH);
        let base = line * WIDTH;
        if x < 3 || x + 3 >= WIDTH {
            return;
        }
        let near = self.keys[u + 1];
        let far = self.zbuf[base + x - 1];
        if far == EMPTY || far == GAP || key_depth(far) <= key_depth(near) {
            return;
        }
        // A pixel inside the near surface, two or three source pixels on.
        let Some(inside) = (2..=3)
            .take_while(|&k| self.same_surface(filled, u + k - 1))
            .map(|k| self.target[u + k])
            .find(|&t| t != OUTSIDE && t as usize / WIDTH == line && t as usize % WIDTH > x + 1)
            .map(|t| t as usize % WIDTH)
        else {
            return;
        };
        let px = |x: usize| colour_at(colour, base + x);
        let (cf, cn) = (px(x - 2), px(inside));
        if hue_dist(cn, cf) < self.dimmed(EDGE_CONTRAST, cf) {
            return;
        }
        let clearly_far = |x: usize| {
            let p = px(x);
            2 * hue_dist(p, cf) < hue_dist(p, cn)
        };
        let clearly_near = |x: usize| {
            let p = px(x);
            2 * hue_dist(p, cn) < hue_dist(p, cf)
        };
        if !clearly_far(x - 1) {
            return;
        }
        let mut e = x;
        while e < x + 2
            && e < inside
            && clearly_far(e)
            && key_depth(self.zbuf[base + e]) == key_depth(near)
        {
            e += 1;
        }
        if e > x && (e == inside || clearly_near(e)) {
            self.zbuf[base + x..base + e].fill(far);
        }
    }

    /// Source pixels `w` and `w + 1` of the current row lie on one surface (no depth jump).
    fn same_surface(&self, filled: &[u16], w: usize) -> bool {
        (i32::from(filled[w + 1]) - i32::from(filled[w])).abs() < self.jump_raw
    }

    /// The alignment gap of the depth edge after source pixel `u`, on target row `line`, placed
    /// by colour (the warp put it at `[c0, c1)`, the footprint edges `lo` and `hi` rounded): the
    /// RGB camera sees the near surface end at a colour edge within two pixels of `c0` (`lo` is
    /// pixel `u`'s right footprint edge at the near depth). That edge pins
    /// where inside pixel `u` the depth edge lies, and so the far end too (`hi`, the same point at
    /// the far depth). Also where inside pixel `u` (source pixels from `lo`) the colour and the
    /// depth edge allow the edge, `[a, b]` ([`FarEnd`]). None when the colours do not show one
    /// clean edge.
    fn colour_gap(
        &self,
        u: usize,
        filled: &[u16],
        colour: &[u8],
        line: usize,
        (lo, hi): (f32, f32),
        (c0, c1): (usize, usize),
    ) -> Option<(usize, usize, [f32; 2])> {
        // A pixel inside the near surface: the target of a source pixel before `u` on the same
        // surface (a thin rod is only two or three target pixels wide).
        let inside = (1..=2)
            .filter_map(|k| u.checked_sub(k))
            .take_while(|&w| self.same_surface(filled, w))
            .map(|w| self.target[w])
            .find(|&t| t != OUTSIDE && t as usize / WIDTH == line && (t as usize % WIDTH) + 1 < c0)
            .map(|t| t as usize % WIDTH)?;
        let far_in = c1 + 1;
        if far_in >= WIDTH || c1 < c0 + 1 {
            return None;
        }
        let px = |x: usize| colour_at(colour, line * WIDTH + x);
        let (mut inside, mut cn, cf) = (inside, px(inside), px(far_in));
        // A near surface of one colour over five source pixels is told from the far one by a
        // smaller contrast; a thin one's shading (a rod's bright middle) is no sample of its edge.
        let wide = u >= 5 && (u - 4..u).all(|w| self.same_surface(filled, w)) && {
            let t = self.target[u - 4];
            t != OUTSIDE
                && t as usize / WIDTH == line
                && hue_dist(px(t as usize % WIDTH), cn) < self.dimmed(SURFACE_AGREE, cf)
        };
        let contrast = if wide {
            self.dimmed(WIDE_EDGE_CONTRAST, cf)
        } else {
            self.dimmed(EDGE_CONTRAST, cf)
        };
        if hue_dist(cn, cf) < contrast {
            // A rod is darkest at its silhouette, where its surface turns away from the light:
            // the near pixel's own target may still show the edge clearly.
            let t = self.target[u];
            let last = t as usize % WIDTH;
            if wide
                || t == OUTSIDE
                || t as usize / WIDTH != line
                || last <= inside
                || last >= c0
                || hue_dist(px(last), cf) < self.dimmed(EDGE_CONTRAST, cf)
            {
                return None;
            }
            (inside, cn) = (last, px(last));
        }
        // Each pixel of the window sides with the colour it is nearer; the edge is the one split
        // that no pixel contradicts.
        let (w0, w1) = ((c0.saturating_sub(2)).max(inside + 1), (c0 + 2).min(far_in));
        let mut near_until = w0; // first pixel not showing the near surface
        let mut far_from = w1; // from here on every pixel shows the far surface
        for x in w0..w1 {
            let p = px(x);
            let (dn, df) = (hue_dist(p, cn), hue_dist(p, cf));
            if dn < df {
                if near_until < x {
                    return None; // near again after a pixel that was not
                }
                near_until = x + 1;
            } else if df < dn {
                far_from = far_from.min(x);
            }
        }
        if far_from < near_until {
            return None;
        }
        // The first pixel showing the far surface; where pixels between the two runs are
        // unclear (a blurred edge), the one the geometry prefers.
        let e0 = c0.clamp(near_until, far_from);
        // Pixel centres e0 − 1 (near) and e0 (far) bound the edge's target column at the near
        // depth; one source column moves it by `2·half_px` target columns. Within source pixel
        // `u` (its centre near, `u + 1`'s far) where possible.
        let step = 2.0 * self.half_px;
        let a = ((e0 as f32 - 1.0 - lo) / step).max(-0.5);
        let b = ((e0 as f32 - lo) / step).min(0.5);
        let at = if a < b {
            0.5 * (a + b)
        } else {
            (e0 as f32 - 0.5 - lo) / step
        };
        let e1 = ceil_clamped(hi + at * step, WIDTH).max(e0);
        Some((e0, e1, [a, b]))
    }

    /// Where the centre of the target pixel that source pixel (`u`, `v`) with raw value `raw`
    /// rounds to lies against the pixel's footprint: [`LEFT_OF_FOOTPRINT`],
    /// [`RIGHT_OF_FOOTPRINT`] or 0 (inside). Only depth edges need it, so it is not part of the
    /// vector loop; the arithmetic is [`Warp::project_row`]'s (either loop), operation for
    /// operation, so the rounding agrees with the target that loop chose.
    fn footprint_side(&self, v: usize, u: usize, raw: u16) -> u8 {
        let [bx, _, bz] = self.row_ray[v];
        let [tx, _, tz] = self.t;
        let fx = self.rgb_f[0];
        let (bx, tx) = (fx * bx, fx * tx);
        let iz = f32::from(raw) * self.iz_scale + self.iz_offset;
        let x = if self.affine {
            (bx + self.col_x[u] + tx * iz) + self.rgb_c[0]
        } else {
            let nz = bz + self.col_z[u] + tz * iz;
            let r = 1.0 / (nz * iz);
            let inv_nz = r * iz;
            (bx + self.col_x[u] + tx * iz) * inv_nz + self.rgb_c[0]
        };
        let off = x - round_f32(x);
        u8::from(off > self.half_px) * LEFT_OF_FOOTPRINT
            + u8::from(off < -self.half_px) * RIGHT_OF_FOOTPRINT
    }

    /// Target column (unrounded) of source pixel (`u`, `v`) with raw value `raw`; the scalar twin
    /// of the projection in [`Warp::project_row`], for the rare pixels at depth edges.
    fn target_x(&self, v: usize, u: usize, raw: u16) -> f32 {
        self.target_along(0, v, u, raw)
    }

    /// Target row (unrounded) of the same, for the IR image's first and last rows.
    fn target_y(&self, v: usize, u: usize, raw: u16) -> f32 {
        self.target_along(1, v, u, raw)
    }

    /// Target coordinate along `axis` (0: x, 1: y) of source pixel (`u`, `v`) at `raw`.
    fn target_along(&self, axis: usize, v: usize, u: usize, raw: u16) -> f32 {
        let iz = f32::from(raw) * self.iz_scale + self.iz_offset;
        let uf = u as f32;
        let (ray, step) = (self.row_ray[v], self.col_step);
        let nz = ray[2] + uf * step[2] + self.t[2] * iz;
        self.rgb_f[axis] * (ray[axis] + uf * step[axis] + self.t[axis] * iz) / nz + self.rgb_c[axis]
    }
}

/// Z-tests a row's source pixels into the z-buffer. A slot keeps the smallest key (the nearest
/// surface) whatever the order, so any grouping of the stores gives the same buffer.
#[inline(always)]
fn scatter(zbuf: &mut [u32; PIXELS + 1], target: &[u32], keys: &[u32]) {
    // Off-image pixels land in the spare slot past the image: no branch per pixel.
    for (&t, &k) in target.iter().zip(keys) {
        // `t <= OUTSIDE` always; the `min` is a cmov that spares a bounds-check branch.
        let slot = &mut zbuf[(t as usize).min(PIXELS)];
        *slot = (*slot).min(k);
    }
}

/// [`scatter`] sixteen pixels at a time where a surface is smooth: the chunk lands on one target
/// row, each pixel on its predecessor's target or the next one (the RGB camera's pixels are
/// larger than the IR camera's), at most two to a target. Then each target's key is one vector
/// `min` away and the targets are consecutive slots. Those are merged into a block of sixteen
/// slots held in a register while the chunks move through it, so each block is loaded once and
/// stored once: a load overlapping a masked store just before it would wait for that store to
/// retire (that cost more than the scalar loop). Anything else (edges, cracks) is scalar.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f,avx512bw,avx512vl,avx512dq,avx2,fma")]
unsafe fn scatter_avx512(zbuf: &mut [u32; PIXELS + 1], target: &[u32], keys: &[u32]) {
    use std::arch::x86_64::*;
    const LANES: usize = 16;
    let n = target.len().min(keys.len());
    let iota = _mm512_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15);
    let none = _mm512_set1_epi32(-1);
    let base = zbuf.as_mut_ptr();
    // The block held in `cur` (its first slot), if any.
    let mut held: Option<usize> = None;
    let mut cur = none;
    let mut i = 0;
    // Lane `j + 1`'s target minus lane `j`'s needs one element past the chunk.
    while i + LANES < n {
        let (t0, t15) = (target[i], target[i + LANES - 1]);
        // SAFETY: `i + LANES < n` keeps both loads inside `target`.
        let t = unsafe { _mm512_loadu_si512(target.as_ptr().add(i).cast()) };
        let next = unsafe { _mm512_loadu_si512(target.as_ptr().add(i + 1).cast()) };
        let step = _mm512_sub_epi32(next, t);
        // Bit j: lane j + 1 lands where lane j does (bit 15 compares with the next chunk: unused).
        let same = _mm512_cmpeq_epi32_mask(step, _mm512_setzero_si512()) & 0x7fff;
        let small = _mm512_cmple_epu32_mask(step, _mm512_set1_epi32(1)) | 0x8000;
        let smooth = small == 0xffff
            && same & (same << 1) == 0
            && t15 < OUTSIDE
            && (t0 as usize % WIDTH) + ((t15 - t0) as usize) < WIDTH;
        if !smooth {
            if let Some(b) = held.take() {
                // SAFETY: `b` is a block start from below, inside the image.
                unsafe { _mm512_storeu_si512(base.add(b).cast(), cur) };
            }
            scatter(zbuf, &target[i..i + LANES], &keys[i..i + LANES]);
            i += LANES;
            continue;
        }
        // SAFETY: as above, for `keys`.
        let k = unsafe { _mm512_loadu_si512(keys.as_ptr().add(i).cast()) };
        // Lane j + 1 takes the smaller of its key and lane j's where the two share a target.
        let before = _mm512_alignr_epi32(k, _mm512_setzero_si512(), LANES as i32 - 1);
        let merged = _mm512_mask_min_epu32(k, same << 1, k, before);
        // The last lane of each target, packed: one key per consecutive slot from t0.
        let packed = _mm512_maskz_compress_epi32(!same, merged);
        let slots = _mm512_set1_epi32((t15 - t0 + 1) as i32);
        let (t0, end) = (t0 as usize, t15 as usize + 1);
        // The slots span one block or two. PIXELS is a multiple of sixteen, so no block runs past
        // the image.
        let mut block = t0 & !(LANES - 1);
        while block < end {
            if held != Some(block) {
                if let Some(b) = held {
                    // SAFETY: `b` is a block start, inside the image.
                    unsafe { _mm512_storeu_si512(base.add(b).cast(), cur) };
                }
                // SAFETY: `block + LANES <= PIXELS`.
                cur = unsafe { _mm512_loadu_si512(base.add(block).cast()) };
                held = Some(block);
            }
            // Lane j of the block is slot block + j: packed[block + j − t0], where that is one of
            // the chunk's slots.
            let from = _mm512_add_epi32(iota, _mm512_set1_epi32(block as i32 - t0 as i32));
            let lanes = _mm512_cmplt_epu32_mask(from, slots);
            cur = _mm512_min_epu32(
                cur,
                _mm512_mask_permutexvar_epi32(none, lanes, from, packed),
            );
            block += LANES;
        }
        i += LANES;
    }
    if let Some(b) = held {
        // SAFETY: as above.
        unsafe { _mm512_storeu_si512(base.add(b).cast(), cur) };
    }
    scatter(zbuf, &target[i..n], &keys[i..n]);
}

/// The depth-edge bits of the sixteen pairs of `seventeen` raw values: bit `k` of the first mask
/// where value `k + 1` exceeds value `k` by `jump` or more, of the second where it falls short by
/// as much. Unsigned saturating differences, exact for any u16; SSE2 is part of x86-64 itself,
/// so every build has it.
#[cfg(target_arch = "x86_64")]
#[inline(always)]
fn edge_masks(seventeen: &[u16], jump: i32) -> (u32, u32) {
    use std::arch::x86_64::{
        __m128i, _mm_cmpeq_epi16, _mm_loadu_si128, _mm_movemask_epi8, _mm_packs_epi16,
        _mm_set1_epi16, _mm_setzero_si128, _mm_subs_epu16,
    };
    assert!(seventeen.len() >= 17);
    let below = (jump.clamp(1, 65535) - 1) as u16 as i16;
    // SAFETY: SSE2 is always present on x86-64; the four unaligned loads read values 0..16 and
    // 1..17 of `seventeen`, which holds at least 17.
    let (short_up, short_down) = unsafe {
        let at = seventeen.as_ptr();
        let a0 = _mm_loadu_si128(at.cast::<__m128i>());
        let a1 = _mm_loadu_si128(at.add(8).cast::<__m128i>());
        let b0 = _mm_loadu_si128(at.add(1).cast::<__m128i>());
        let b1 = _mm_loadu_si128(at.add(9).cast::<__m128i>());
        let (below, zero) = (_mm_set1_epi16(below), _mm_setzero_si128());
        // A lane is all ones where the step falls short of the jump: (d ⊖ (jump − 1)) = 0.
        let short = |x: __m128i, y: __m128i| {
            _mm_cmpeq_epi16(_mm_subs_epu16(_mm_subs_epu16(x, y), below), zero)
        };
        (
            _mm_movemask_epi8(_mm_packs_epi16(short(b0, a0), short(b1, a1))),
            _mm_movemask_epi8(_mm_packs_epi16(short(a0, b0), short(a1, b1))),
        )
    };
    (!short_up as u32 & 0xFFFF, !short_down as u32 & 0xFFFF)
}

/// `u · step` for every column `u`, in f32.
fn column_terms(step: f32) -> Vec<f32> {
    (0..WIDTH).map(|u| u as f32 * step).collect()
}

/// The depth part of a z-buffer key.
fn key_depth(key: u32) -> u32 {
    (key >> (LABEL_BITS + TIE_BITS)) & DEPTH_MASK
}

/// The RGB8 pixel at index `i` of `colour`, as signed components for [`hue_dist`].
pub(super) fn colour_at(colour: &[u8], i: usize) -> [i32; 3] {
    [
        colour[3 * i].into(),
        colour[3 * i + 1].into(),
        colour[3 * i + 2].into(),
    ]
}

/// Colour contrast (by [`hue_dist`]) two surfaces need before their edge is trusted. Counting hue
/// in every colour test of the warp: RGB alignment F1 +0.005 to +0.011 on the complex scenes of
/// eleven simulated suites, −0.0014 on the ideal-sensor one (20 scenes); 0.09 % of the real
/// frame's RGB labels move, by a pixel. These steps are for a bright background and shrink with a
/// dim one's brightness ([`dimmed`], as the colour split's): at 45 % exposure RGB alignment F1
/// +0.002 on the holdout suite, the bright suites unchanged, 129 of the real frame's RGB labels
/// move.
const EDGE_CONTRAST: u32 = 90;
/// The same for a near surface whose colour holds over several pixels before the edge.
const WIDE_EDGE_CONTRAST: u32 = 45;
/// Colour distance within which two pixels are taken to show one surface's colour.
const SURFACE_AGREE: u32 = 30;

/// Unpacks one z-buffer row into labels and registered depth (where a measured pixel won);
/// branch-free, so it vectorises. EMPTY carries OTHER in its label bits.
#[inline(always)]
fn unpack_row(keys: &[u32], rgb: &mut [u8], mm: &mut [u16]) {
    for ((m, l), &k) in mm.iter_mut().zip(rgb.iter_mut()).zip(keys) {
        let label = k & ((1 << LABEL_BITS) - 1);
        *l = label as u8;
        let measured = u32::from(label == u32::from(VALID)).wrapping_neg();
        *m = ((k >> (LABEL_BITS + TIE_BITS)) & DEPTH_MASK & measured) as u16;
    }
}

/// Fills forward-warping cracks in one row: an empty pixel between two filled ones in its row (up
/// to two pixels wide) or in its column takes the farther neighbour's value, so a crack beside an
/// alignment gap joins the gap and a crack inside a surface joins the surface. Empty runs at the
/// ends of the row (outside the IR field of view) are left alone.
#[inline(always)]
fn fill_cracks_row(cur: &mut [u32], above: Option<&[u32]>, below: Option<&[u32]>) {
    let vertical = |cur: &mut [u32], from: usize, to: usize| {
        if let (Some(a), Some(b)) = (above, below) {
            for i in from..to {
                if cur[i] == EMPTY && a[i] != EMPTY && b[i] != EMPTY {
                    cur[i] = a[i].max(b[i]);
                }
            }
        }
    };
    let Some(first) = cur.iter().position(|&k| k != EMPTY) else {
        // A whole empty row between two covered ones (RGB focal length above the IR one).
        vertical(cur, 0, WIDTH);
        return;
    };
    let last = cur.iter().rposition(|&k| k != EMPTY).unwrap();
    // Most rows have no crack: a branch-free count lets them skip the scan.
    if cur[first..last]
        .iter()
        .fold(0u32, |n, &k| n + u32::from(k == EMPTY))
        == 0
    {
        return;
    }
    let mut u = first + 1;
    while u < last {
        // Skip filled stretches 16 pixels at a time (branch-free test).
        if u + 16 <= last
            && !cur[u..u + 16]
                .iter()
                .fold(false, |any, &k| any | (k == EMPTY))
        {
            u += 16;
            continue;
        }
        if cur[u] != EMPTY {
            u += 1;
            continue;
        }
        let end = (u..last).find(|&k| cur[k] != EMPTY).unwrap_or(last);
        if end - u <= 2 {
            let fill = cur[u - 1].max(cur[end]);
            cur[u..end].fill(fill);
        } else {
            vertical(cur, u, end);
        }
        u = end;
    }
}

const MAGIC: f32 = 8_388_608.0; // 2^23

/// Nearest integer of `x ∈ [0, 2²³)` as bits, without a float-to-int cast (costly to vectorise):
/// adding 2²³ pushes the integer part into the mantissa.
#[inline(always)]
fn round_bits(x: f32) -> u32 {
    (x + MAGIC).to_bits() & 0x7f_ffff
}

/// Nearest integer of `x` as a float, for `|x| < 2²²`: adding 1.5·2²³ leaves the sum in
/// [2²³, 2²⁴), where floats are the integers, for either sign of `x`. (With 2²³, as
/// [`round_bits`] adds, a small negative `x` lands below 2²³, among the halves, and rounded to
/// −0.5: a pixel a hair left of the RGB image's first column or above its first row, which a
/// calibration with a rotation or a sideways offset of the RGB camera gives, was then put at
/// index −0.5 and scattered out of the image.)
#[inline(always)]
fn round_f32(x: f32) -> f32 {
    const MAGIC_SIGNED: f32 = 12_582_912.0; // 1.5·2^23
    (x + MAGIC_SIGNED) - MAGIC_SIGNED
}

/// `x` clamped to `[lo, hi]` with plain compares (one vector min/max each; NaN gives `lo`),
/// where `f32::clamp` pays for IEEE NaN rules.
#[inline(always)]
fn clamp_fast(x: f32, lo: f32, hi: f32) -> f32 {
    let x = if x > lo { x } else { lo };
    if x < hi {
        x
    } else {
        hi
    }
}

/// The widest build of the hot loops this CPU can run (the classifier's two stages each compile
/// their loops once per level and pick one at construction).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Simd {
    /// AVX-512 (F, BW, VL, DQ) with AVX2 and FMA: sixteen f32 lanes.
    Avx512,
    /// AVX2 and FMA: eight f32 lanes.
    Avx2,
    /// Whatever the compile target guarantees (SSE2 on x86-64).
    Baseline,
}

impl Simd {
    /// Detects the widest level this CPU supports; `UMBRA_SIMD=avx2|baseline` caps it (to compare
    /// builds, or to dodge a CPU that clocks down under AVX-512).
    pub(crate) fn detect() -> Simd {
        let cap = std::env::var("UMBRA_SIMD").unwrap_or_default();
        #[cfg(target_arch = "x86_64")]
        {
            let avx2 =
                std::is_x86_feature_detected!("avx2") && std::is_x86_feature_detected!("fma");
            let avx512 = avx2
                && std::is_x86_feature_detected!("avx512f")
                && std::is_x86_feature_detected!("avx512bw")
                && std::is_x86_feature_detected!("avx512vl")
                && std::is_x86_feature_detected!("avx512dq");
            match cap.as_str() {
                "baseline" => Simd::Baseline,
                _ if avx512 && cap != "avx2" => Simd::Avx512,
                _ if avx2 => Simd::Avx2,
                _ => Simd::Baseline,
            }
        }
        #[cfg(not(target_arch = "x86_64"))]
        {
            let _ = cap;
            Simd::Baseline
        }
    }
}

/// Target pixels whose centres lie in `[lo, hi)`, clipped to `0..len`.
#[inline]
fn span(lo: f32, hi: f32, len: usize) -> (usize, usize) {
    let a = ceil_clamped(lo, len);
    let b = ceil_clamped(hi, len);
    (a, b.max(a))
}

/// `ceil(x)` clamped to `0..=len`; `f32::ceil` is a libm call on baseline x86-64 (no SSE4.1).
#[inline]
fn ceil_clamped(x: f32, len: usize) -> usize {
    let x = x.clamp(0.0, len as f32);
    let i = x as usize;
    i + usize::from((i as f32) < x)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::classify::{Classified, Classifier};
    use crate::labels::histogram;

    /// The edge list is what a pixel-pair scan of the definition gives: steps of exactly the jump
    /// and one short of it, both ways, at every column (the 16-column blocks and the tail they
    /// leave), values up to u16's top, random rows, for jumps from 1 to past any raw step.
    #[test]
    fn depth_edges_are_the_pairs_whose_step_reaches_the_jump() {
        let mut warp = Warp::new(&Calibration::nyu_default());
        let mut seed = 0x2545_f491_u32;
        let mut next = move || {
            seed ^= seed << 13;
            seed ^= seed >> 17;
            seed ^= seed << 5;
            seed
        };
        for jump in [1, 2, 12, 13, 2047, 2048, 65535] {
            let mut rows = Vec::new();
            for base in [0u16, 700, 2047, 62000] {
                // Teeth of the jump and of one short of it: a rise and a fall at every pair,
                // the tooth's height changing every few columns, so across the blocks' seams.
                let row: Vec<u16> = (0..WIDTH)
                    .map(|u| {
                        let tooth = if (u / 3) % 2 == 0 { jump } else { jump - 1 };
                        let top = (i32::from(base) + tooth).min(65535) as u16;
                        if u % 2 == 1 {
                            top
                        } else {
                            base
                        }
                    })
                    .collect();
                rows.push(row);
            }
            rows.push((0..WIDTH).map(|_| (next() % 2100) as u16).collect());
            rows.push((0..WIDTH).map(|_| next() as u16).collect());
            warp.jump_raw = jump;
            for row in &rows {
                let by_hand: Vec<(usize, bool)> = (0..WIDTH - 1)
                    .filter_map(|u| {
                        let step = i32::from(row[u + 1]) - i32::from(row[u]);
                        (step.abs() >= jump).then_some((u, step > 0))
                    })
                    .collect();
                warp.edge_list.clear();
                warp.find_edges(row);
                assert_eq!(warp.edge_list, by_hand, "jump {jump}");
                assert!(
                    !by_hand.is_empty() || jump > 2047,
                    "the row tries no edge (jump {jump})"
                );
            }
        }
    }

    #[test]
    fn rgb_rows_two_ir_rows_land_on_start_their_strip_at_the_colour_edge_too() {
        // A wall at 1 m left of IR column 300 and one at 3 m from it on, whose raw value moves by
        // a unit from row to row (as noise does). The near wall's edge, IR column 299.5, lands at
        // RGB column 518.86·((299.5 − 313.04)/582.62 − 0.025) + 325.58 = 300.55, so depth alone
        // starts the alignment strip at RGB column 301; the colour image's edge at column 300
        // (dark before it, pale from it) moves it to 300. The RGB camera's rows are a little
        // taller than the IR camera's, so one RGB row in nine gets two IR rows, whose far walls
        // differ by that unit: the second once found the first one's far wall not its own and
        // left the start where depth put it (44 of 360 rows).
        let c = Calibration::nyu_default();
        let (near, far) = (raw_at(&c, 1.0), raw_at(&c, 3.0));
        let mut raw = vec![near; PIXELS];
        for v in 0..HEIGHT {
            raw[v * WIDTH + 300..(v + 1) * WIDTH].fill(far + (v % 2) as u16);
        }
        let mut rgb = vec![200u8; 3 * PIXELS];
        for v in 0..HEIGHT {
            rgb[3 * v * WIDTH..3 * (v * WIDTH + 300)].fill(40);
        }
        let mut out = Classified::default();
        Classifier::new(&c).classify_with_rgb(&raw, Some(&rgb), &mut out);
        for v in 60..420 {
            let start = (0..WIDTH).find(|&x| out.rgb_labels[v * WIDTH + x] == ALIGNMENT);
            assert_eq!(start, Some(300), "RGB row {v}");
        }
    }

    #[test]
    fn an_rgb_row_shows_the_ir_row_whose_footprint_holds_its_centre() {
        // A box at 1 m from IR column 300 on before a wall at 3 m, its attached shadow of
        // fb·(1 − 1/3) = 29 px left of it; in odd rows the sensor's widening swallowed the box's
        // first pixel too (a hole of the shadow, as SPEC §1's widening makes). The RGB camera's
        // rows are taller than the IR camera's: RGB row r's centre lies in the footprint of IR row
        // v = round((r − cy_rgb)/fy_rgb·fy + cy), and where pixel (300, v) lands, 518.86·((300 −
        // 313.04)/582.62 − 0.025) + 325.58 = 301.0, the RGB camera sees what that pixel shows:
        // the shadow in odd rows, the box in even ones. One RGB row in nine gets a second IR row
        // whose footprint misses its centre; its box once hid the shadow there (near wins).
        let c = Calibration::nyu_default();
        let (near, far) = (raw_at(&c, 1.0), raw_at(&c, 3.0));
        let w = (c.fb() * (1.0 - 1.0 / 3.0)).round() as usize;
        let mut raw = vec![far; PIXELS];
        for v in 0..HEIGHT {
            let row = &mut raw[v * WIDTH..(v + 1) * WIDTH];
            row[300..500].fill(near);
            row[300 - w..300 + v % 2].fill(NO_DEPTH);
        }
        let mut out = Classified::default();
        Classifier::new(&c).classify(&raw, &mut out);
        let (mut wrong, mut shared) = (Vec::new(), 0);
        for r in 60..420 {
            let v = ((r as f64 - c.rgb.cy) / c.rgb.fy * c.depth.fy + c.depth.cy).round() as usize;
            let (x, y) = rgb_xy(&c, 300.0, v as f64, near);
            assert_eq!((y.round() as usize, x.round() as usize), (r, 301));
            let want = if v % 2 == 1 { ATTACHED } else { VALID };
            let other = [v - 1, v + 1]
                .into_iter()
                .any(|o| rgb_xy(&c, 300.0, o as f64, near).1.round() as usize == r);
            shared += usize::from(other);
            if out.rgb_labels[r * WIDTH + 301] != want {
                wrong.push((r, v, other));
            }
        }
        assert!(shared >= 30, "{shared} RGB rows with two IR rows");
        assert!(
            wrong.is_empty(),
            "(RGB row, IR row, two IR rows): {wrong:?}"
        );
    }

    #[test]
    fn a_single_far_pixel_in_a_surface_opens_no_gap_but_a_slit_does() {
        // A wall at 1 m with, in rows 100..380, single pixels at 3 m every 40 columns (mixed
        // pixels, as a real sensor leaves along an object's top and bottom rows) and one slit
        // 3 px wide onto a wall at 3 m. Through the slit the RGB camera sees background the IR
        // camera cannot: f_rgb·0.025·(1 − 1/3) = 8.6 px of parallax, of which the slit's own
        // width at 1 m, about 2.7 RGB columns, stays uncovered by the near wall.
        let c = Calibration::nyu_default();
        let (near, far) = (raw_at(&c, 1.0), raw_at(&c, 3.0));
        let mut raw = vec![near; PIXELS];
        for v in 100..380 {
            for u in (60..580).step_by(40) {
                raw[v * WIDTH + u] = far;
            }
            raw[v * WIDTH + 301..v * WIDTH + 304].fill(far);
        }
        let mut out = Classified::default();
        Classifier::new(&c).classify(&raw, &mut out);
        let (mut in_slit, mut elsewhere) = (0, 0);
        for v in 0..HEIGHT {
            for u in 0..WIDTH {
                if out.rgb_labels[v * WIDTH + u] == ALIGNMENT {
                    // The slit, IR columns 300.5..303.5, spans RGB columns 518.86·((300.5 −
                    // 313.04)/582.62 − 0.025) + 325.58 = 301.4 to 304.1 at 1 m.
                    if (300..310).contains(&u) {
                        in_slit += 1;
                    } else {
                        elsewhere += 1;
                    }
                }
            }
        }
        assert_eq!(elsewhere, 0, "alignment pixels away from the slit");
        // Measured: 1000 (4 a row); without the spike test, also 2500 away from the slit.
        assert!(
            in_slit >= 250 * 2,
            "{in_slit} alignment pixels in the slit's rows"
        );
    }

    fn raw_at(c: &Calibration, z: f64) -> u16 {
        c.raw_from_depth(z).round() as u16
    }

    #[test]
    fn flat_wall_warps_without_cracks() {
        let c = Calibration::nyu_default();
        let raw = vec![raw_at(&c, 2.0); PIXELS];
        let mut out = Classified::default();
        Classifier::new(&c).classify(&raw, &mut out);
        // By hand at 2 m: IR column 0 lands at u' = 518.86·(−313.04/582.62 − 0.0125) + 325.58 ≈ 40.5,
        // column 639 at ≈ 609.5; rows 0 and 479 at v' ≈ 41.2 and ≈ 468.2. Inside that: no cracks.
        for v in 42..468 {
            for u in 41..609 {
                let i = v * WIDTH + u;
                assert_eq!(out.rgb_labels[i], VALID, "crack at ({u}, {v})");
                assert!(
                    (out.registered_mm[i] as i32 - 2000).abs() < 10,
                    "{}",
                    out.registered_mm[i]
                );
            }
        }
        // The IR camera's field of view ends inside the RGB image: the border outside it is OTHER.
        assert_eq!(out.rgb_labels[5 * WIDTH + 5], OTHER);
        assert_eq!(out.rgb_labels[250 * WIDTH + 39], OTHER);
        assert_eq!(out.rgb_labels[250 * WIDTH + 611], OTHER);
        assert_eq!(histogram(&out.rgb_labels)[ALIGNMENT as usize], 0);
    }

    /// RGB position (x, y) of the point at IR column `u` (continuous), row `v`, raw value `raw`:
    /// pinhole back-projection, the extrinsics, pinhole projection (independent of the warp).
    fn rgb_xy(c: &Calibration, u: f64, v: f64, raw: u16) -> (f64, f64) {
        let z = c.depth_m(raw).unwrap();
        let d = &c.depth;
        let p = nalgebra::Vector3::new((u - d.cx) / d.fx * z, (v - d.cy) / d.fy * z, z);
        let q = c.depth_to_rgb.rotation * p + c.depth_to_rgb.translation;
        (
            c.rgb.fx * q.x / q.z + c.rgb.cx,
            c.rgb.fy * q.y / q.z + c.rgb.cy,
        )
    }

    /// A wall at raw `wall` with a post at raw `post` over IR columns `0..cols`, rows 150..350.
    fn post_at_left_border(wall: u16, post: u16, cols: usize) -> Vec<u16> {
        let mut raw = vec![wall; PIXELS];
        for v in 150..350 {
            raw[v * WIDTH..v * WIDTH + cols].fill(post);
        }
        raw
    }

    /// Where, in the RGB row of IR row 250, [`post_at_left_border`]'s post ends, the IR image's
    /// left edge lands on the wall, and the wall's first lit column's left edge lands; and that
    /// row.
    fn left_border_edges(
        c: &Calibration,
        wall: u16,
        post: u16,
        cols: usize,
    ) -> (f64, f64, f64, usize) {
        let right = cols as f64 - 0.5;
        let (post_edge, y) = rgb_xy(c, right, 250.0, post);
        let (fov_edge, _) = rgb_xy(c, -0.5, 250.0, wall);
        let (wall_edge, _) = rgb_xy(c, right, 250.0, wall);
        (post_edge, fov_edge, wall_edge, y.round() as usize)
    }

    #[test]
    fn the_ir_field_of_view_ends_where_the_border_pixels_footprints_do() {
        // A flat wall at 81 depths from 2 to 4 m, so the IR image's borders land at every
        // sub-pixel position in the RGB image. The RGB camera sees the wall where the IR camera
        // does at a pixel whose centre lies within the IR image's outer edges, columns −0.5 and
        // 639.5: from ceil(x(−0.5)) to floor(x(639.5)), and nothing outside.
        let c = Calibration::nyu_default();
        let mut classifier = Classifier::new(&c);
        let mut out = Classified::default();
        let mut wrong = Vec::new();
        for k in 0..81 {
            let raw = raw_at(&c, 2.0 + 0.025 * k as f64);
            classifier.classify(&vec![raw; PIXELS], &mut out);
            let (left, y) = rgb_xy(&c, -0.5, 240.0, raw);
            let (right, _) = rgb_xy(&c, 639.5, 240.0, raw);
            let row = &out.rgb_labels[y.round() as usize * WIDTH..][..WIDTH];
            let first = row.iter().position(|&l| l == VALID);
            let last = row.iter().rposition(|&l| l == VALID);
            let want = (left.ceil() as usize, right.floor() as usize);
            if (first, last) != (Some(want.0), Some(want.1)) {
                wrong.push(format!("raw {raw}: {first:?}..={last:?}, want {want:?}"));
            }
        }
        assert!(wrong.is_empty(), "{wrong:?}");
    }

    #[test]
    fn the_ir_field_of_view_ends_where_the_first_and_last_rows_footprints_do() {
        // The same wall, the RGB camera also 1.2 mm lower and 1.6 mm behind the IR camera (a
        // calibrated Kinect's offsets), so the IR image's top and bottom edges land at every
        // sub-pixel height too: the RGB camera sees the wall from ceil(y(−0.5)) to floor(y(479.5)).
        let mut c = Calibration::nyu_default();
        c.depth_to_rgb.translation.y = 0.0012;
        c.depth_to_rgb.translation.z = 0.0016;
        let mut classifier = Classifier::new(&c);
        let mut out = Classified::default();
        let mut wrong = Vec::new();
        for k in 0..81 {
            let raw = raw_at(&c, 2.0 + 0.025 * k as f64);
            classifier.classify(&vec![raw; PIXELS], &mut out);
            let (x, top) = rgb_xy(&c, 320.0, -0.5, raw);
            let (_, bottom) = rgb_xy(&c, 320.0, 479.5, raw);
            let column = |y: usize| out.rgb_labels[y * WIDTH + x.round() as usize];
            let first = (0..HEIGHT).find(|&y| column(y) == VALID);
            let last = (0..HEIGHT).rev().find(|&y| column(y) == VALID);
            let want = (top.ceil() as usize, bottom.floor() as usize);
            if (first, last) != (Some(want.0), Some(want.1)) {
                wrong.push(format!("raw {raw}: {first:?}..={last:?}, want {want:?}"));
            }
        }
        assert!(wrong.is_empty(), "{wrong:?}");
    }

    #[test]
    fn past_a_near_object_at_the_left_border_the_strip_ends_at_the_ir_view() {
        // A post at 1 m over IR columns 0..3 before a wall at 3 m. Right of the post the RGB
        // camera sees wall the IR camera cannot: the pixels whose centres lie between the post's
        // right edge (column 2.5 at 1 m) and the wall's first lit column's left edge (2.5 at
        // 3 m). Of those, the ones left of where the IR image's own left edge (−0.5 at 3 m)
        // lands see wall outside the IR camera's view: OTHER; the rest the post hides from it:
        // alignment. With the NYU defaults: 36.05, 42.01 and 44.69, so RGB columns 37–42 are
        // OTHER and 43–44 alignment.
        let c = Calibration::nyu_default();
        let (wall, post) = (raw_at(&c, 3.0), raw_at(&c, 1.0));
        let raw = post_at_left_border(wall, post, 3);
        let mut out = Classified::default();
        Classifier::new(&c).classify(&raw, &mut out);
        let (post_edge, fov_edge, wall_edge, y) = left_border_edges(&c, wall, post, 3);
        assert!(
            post_edge + 5.0 < fov_edge && fov_edge + 2.0 < wall_edge,
            "{post_edge:.2} {fov_edge:.2} {wall_edge:.2}"
        );
        let row = &out.rgb_labels[y * WIDTH..][..WIDTH];
        let want = |x: usize| {
            let x = x as f64;
            if x > post_edge && x < fov_edge {
                OTHER
            } else {
                ALIGNMENT
            }
        };
        let gap = post_edge.ceil() as usize..wall_edge.ceil() as usize;
        let got: Vec<u8> = row[gap.clone()].to_vec();
        let wanted: Vec<u8> = gap.clone().map(want).collect();
        assert_eq!(got, wanted, "RGB columns {gap:?}: post edge {post_edge:.2}, IR view's edge {fov_edge:.2}, wall {wall_edge:.2}");
    }

    #[test]
    fn past_a_near_object_at_the_left_border_the_colour_reading_stays_in_the_ir_view() {
        // The post of the test above before a pale wall with a dark stripe over RGB columns
        // 38–39. Right of the stripe the wall's colour runs on to the end of an OTHER run, as
        // past a black rod. But RGB columns 37–42 show wall outside the IR camera's view (left
        // of 42.01, where the IR image's left edge lands on the wall): OTHER, not the alignment
        // shadow of an occluder without depth.
        let c = Calibration::nyu_default();
        let (wall, post) = (raw_at(&c, 3.0), raw_at(&c, 1.0));
        let raw = post_at_left_border(wall, post, 3);
        let mut rgb = [[210u8, 212, 207]; PIXELS];
        for y in 120..380 {
            rgb[y * WIDTH..y * WIDTH + 37].fill([120, 60, 200]);
            rgb[y * WIDTH + 38..y * WIDTH + 40].fill([60, 60, 65]);
        }
        let mut out = Classified::default();
        Classifier::new(&c).classify_with_rgb(&raw, Some(rgb.as_flattened()), &mut out);
        let (post_edge, fov_edge, wall_edge, y) = left_border_edges(&c, wall, post, 3);
        assert!(
            post_edge < 37.0 && fov_edge > 42.0 && fov_edge < 43.0 && wall_edge > 44.0,
            "{post_edge:.2} {fov_edge:.2} {wall_edge:.2}"
        );
        for y in [y - 40, y, y + 40] {
            let row = &out.rgb_labels[y * WIDTH..][..WIDTH];
            assert_eq!(row[37..43], [OTHER; 6], "RGB row {y}: {:?}", &row[34..48]);
            assert_eq!(
                row[43..45],
                [ALIGNMENT; 2],
                "RGB row {y}: {:?}",
                &row[34..48]
            );
        }
    }

    #[test]
    fn wall_outside_the_ir_view_in_a_narrow_crack_past_a_near_object_stays_other() {
        // A post at 1.41 m (raw 843) over IR columns 0..5 before a wall at 4.36 m (raw 1012)
        // (the NYU defaults, as in this project's simulator). Its right edge lands at RGB
        // column 41.60, the IR image's left edge on the wall at 43.38 and the wall's first lit
        // column's left edge at 47.83. RGB columns 42–43 see wall outside the IR camera's view
        // (OTHER), 44–47 wall the post hides from it (alignment). The first two are empty after
        // the warp, as narrow as a crack in a surface: they must not be filled from the gap
        // beside them.
        let c = Calibration::nyu_default();
        let (wall, post) = (1012, 843);
        let raw = post_at_left_border(wall, post, 5);
        let mut out = Classified::default();
        Classifier::new(&c).classify(&raw, &mut out);
        let (post_edge, fov_edge, wall_edge, y) = left_border_edges(&c, wall, post, 5);
        assert!(
            (41.0..42.0).contains(&post_edge)
                && (43.0..44.0).contains(&fov_edge)
                && (47.0..48.0).contains(&wall_edge),
            "{post_edge:.2} {fov_edge:.2} {wall_edge:.2}"
        );
        for y in [y - 60, y, y + 60] {
            let row = &out.rgb_labels[y * WIDTH..][..WIDTH];
            assert_eq!(row[42..44], [OTHER; 2], "RGB row {y}: {:?}", &row[38..50]);
            assert_eq!(
                row[44..48],
                [ALIGNMENT; 4],
                "RGB row {y}: {:?}",
                &row[38..50]
            );
        }
    }

    #[test]
    fn label_boundaries_at_depth_edges_fall_where_the_pixel_centres_do() {
        // A box before a wall at 3 m, at 41 depths from 0.9 to 1.7 m, so its edges land at every
        // sub-pixel position in the RGB image. The RGB camera sees, at a pixel, whatever its
        // centre's ray meets: a pixel whose centre lies left of the box's left edge shows the
        // wall, one right of its right edge the alignment gap.
        let c = Calibration::nyu_default();
        let mut classifier = Classifier::new(&c);
        let mut out = Classified::default();
        let wall = raw_at(&c, 3.0);
        let mut wrong = Vec::new();
        for k in 0..41 {
            let z = 0.9 + 0.02 * k as f64;
            let near = raw_at(&c, z);
            let mut raw = vec![wall; PIXELS];
            for v in 150..350 {
                raw[v * WIDTH + 250..v * WIDTH + 400].fill(near);
            }
            classifier.classify(&raw, &mut out);
            let (left, y) = rgb_xy(&c, 249.5, 250.0, near);
            let (right, _) = rgb_xy(&c, 399.5, 250.0, near);
            let row = y.round() as usize * WIDTH;
            let (l, r) = (left.ceil() as usize, right.floor() as usize);
            let box_mm = (z * 1000.0) as u16;
            let near_box = |i: usize| out.registered_mm[row + i].abs_diff(box_mm) < 40;
            // Left edge: pixel l − 1 (centre left of it) is wall, pixel l box.
            if near_box(l - 1) || !near_box(l) {
                wrong.push(format!("z {z:.2}: left edge at {left:.2}"));
            }
            // Right edge: pixel r (centre left of it) is box, pixel r + 1 the alignment gap.
            if !near_box(r) || out.rgb_labels[row + r + 1] != ALIGNMENT {
                wrong.push(format!("z {z:.2}: right edge at {right:.2}"));
            }
        }
        assert!(wrong.is_empty(), "{wrong:?}");
    }

    #[test]
    fn box_before_wall_has_alignment_strip_of_predicted_width() {
        // Box 1 m, wall 3 m: the RGB camera (2.5 cm right) sees f_rgb·0.025·(1/1 − 1/3) ≈ 8.6 px of
        // wall right of the box that the IR camera cannot.
        let c = Calibration::nyu_default();
        let mut raw = vec![raw_at(&c, 3.0); PIXELS];
        for v in 150..350 {
            for u in 250..400 {
                raw[v * WIDTH + u] = raw_at(&c, 1.0);
            }
            for u in 221..250 {
                raw[v * WIDTH + u] = NO_DEPTH; // its 29 px attached shadow
            }
        }
        let mut out = Classified::default();
        Classifier::new(&c).classify(&raw, &mut out);
        let predicted = c.rgb.fx * 0.025 * (1.0 - 1.0 / 3.0);
        let row = 250 * WIDTH;
        let strip = out.rgb_labels[row..row + WIDTH]
            .iter()
            .filter(|&&l| l == ALIGNMENT)
            .count() as f64;
        assert!(
            (strip - predicted).abs() <= 1.5,
            "strip {strip} px, predicted {predicted:.1}"
        );
        // The projector shadow carries over, narrowed by the RGB camera's own viewpoint to about
        // f_rgb·(0.075 − 0.025)·(1/1 − 1/3) px.
        let shadow = out.rgb_labels[row..row + WIDTH]
            .iter()
            .filter(|&&l| l == ATTACHED)
            .count() as f64;
        let predicted = c.rgb.fx * 0.05 * (1.0 - 1.0 / 3.0);
        assert!(
            (shadow - predicted).abs() <= 2.0,
            "shadow {shadow} px, predicted {predicted:.1}"
        );
        // Alignment pixels sit right of the box, attached ones left of it.
        let first_align = out.rgb_labels[row..row + WIDTH]
            .iter()
            .position(|&l| l == ALIGNMENT)
            .unwrap();
        let last_attached = out.rgb_labels[row..row + WIDTH]
            .iter()
            .rposition(|&l| l == ATTACHED)
            .unwrap();
        assert!(first_align > last_attached + 100);
    }
}
