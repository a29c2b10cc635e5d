//! Alignment to the RGB view: forward-warps the depth map into the RGB camera, carries the IR-view
//! labels along and finds alignment shadows (SPEC §1).
//!
//! Each source pixel is splatted as the rectangle between the warped midpoints to its connected
//! neighbours, z-buffered, so a continuous surface tiles the target without cracks. Where two
//! horizontally adjacent pixels are not connected (a depth edge) and the left one is nearer, they
//! split apart in the RGB view: the background in the gap is seen by the RGB camera but not by the
//! IR camera — an alignment shadow. Holes are warped too, at the depth the scanline classifier
//! assumed for them, so projector shadows carry over. Target pixels nothing lands on lie outside
//! the IR camera's field of view and stay OTHER.

use crate::calib::Calibration;
use crate::labels::{ALIGNMENT, HEIGHT, NO_DEPTH, OTHER, PIXELS, VALID, WIDTH};

/// Z-buffer value of an empty target pixel.
const EMPTY: u16 = u16::MAX;
/// Z-buffer value of an alignment-shadow pixel: behind every real surface.
const GAP: u16 = u16::MAX - 1;

/// Precomputed warp for one calibration plus its scratch buffers.
pub struct Warp {
    /// Inverse depth (1/m) per raw value; 0 for "no depth".
    inv_z: Vec<f32>,
    /// `R · K_depth⁻¹ · (0, v, 1)` per source row: the rotated ray of column 0.
    row_ray: Vec<[f32; 3]>,
    /// `R · K_depth⁻¹ · (1, 0, 0)`: the ray's change per column.
    col_step: [f32; 3],
    t: [f32; 3],
    rgb_f: [f32; 2],
    rgb_c: [f32; 2],
    /// Half a source pixel's size in the target, per unit of `1/nz`.
    half_px: [f32; 2],
    /// `f·b`: disparity pixels per unit inverse depth, for the connectivity test.
    fb: f32,
    /// Disparity step (px) above which neighbours are different surfaces.
    jump: f32,
    zbuf: Vec<u16>,
    xs: Vec<f32>,
    ys: Vec<f32>,
    nz: Vec<f32>,
    disp: Vec<f32>,
    z_mm: Vec<u16>,
}

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
        let inv_z = (0..2048u16).map(|raw| calib.depth_m(raw).map_or(0.0, |z| (1.0 / z) as f32)).collect();
        Warp {
            inv_z,
            row_ray: (0..HEIGHT).map(|v| rot(-d.cx / d.fx, (v as f64 - d.cy) / d.fy, 1.0)).collect(),
            col_step: rot(1.0 / d.fx, 0.0, 0.0),
            t: [t.x as f32, t.y as f32, t.z as f32],
            rgb_f: [calib.rgb.fx as f32, calib.rgb.fy as f32],
            rgb_c: [calib.rgb.cx as f32, calib.rgb.cy as f32],
            half_px: [(0.5 * calib.rgb.fx / d.fx) as f32, (0.5 * calib.rgb.fy / d.fy) as f32],
            fb: calib.fb() as f32,
            jump: 1.5,
            zbuf: vec![EMPTY; PIXELS],
            xs: vec![0.0; WIDTH],
            ys: vec![0.0; WIDTH],
            nz: vec![0.0; WIDTH],
            disp: vec![0.0; WIDTH],
            z_mm: vec![0; WIDTH],
        }
    }

    /// Warps one frame. `filled` is the raw map with every hole given an assumed depth (from the
    /// scanline classifier), `ir` the IR-view labels; writes RGB-view labels and registered depth
    /// in millimetres (0 where the RGB pixel has no measured depth).
    pub fn apply(&mut self, filled: &[u16], ir: &[u8], rgb: &mut [u8], mm: &mut [u16]) {
        assert!(filled.len() == PIXELS && ir.len() == PIXELS && rgb.len() == PIXELS && mm.len() == PIXELS);
        self.zbuf.fill(EMPTY);
        rgb.fill(OTHER);
        mm.fill(0);
        for v in 0..HEIGHT {
            let row = v * WIDTH..(v + 1) * WIDTH;
            self.project_row(v, &filled[row.clone()]);
            self.splat_row(&ir[row], rgb, mm);
        }
    }

    /// Projects every pixel of source row `v` into the RGB image (branch-free, so it vectorises).
    fn project_row(&mut self, v: usize, filled: &[u16]) {
        let [bx, by, bz] = self.row_ray[v];
        let [sx, sy, sz] = self.col_step;
        let [tx, ty, tz] = self.t;
        for (u, &raw) in filled.iter().enumerate() {
            let iz = self.inv_z[usize::from(raw.min(NO_DEPTH))];
            let uf = u as f32;
            // X_rgb / z = R·ray + t / z, so no division by a possibly-zero inverse depth here.
            let nx = bx + uf * sx + tx * iz;
            let ny = by + uf * sy + ty * iz;
            let nz = bz + uf * sz + tz * iz;
            let inv = 1.0 / nz;
            self.xs[u] = self.rgb_f[0] * nx * inv + self.rgb_c[0];
            self.ys[u] = self.rgb_f[1] * ny * inv + self.rgb_c[1];
            self.nz[u] = nz;
            self.disp[u] = self.fb * iz;
            self.z_mm[u] = if iz > 0.0 { (1000.0 * nz / iz).clamp(1.0, 65000.0) as u16 } else { EMPTY };
        }
    }

    fn splat_row(&mut self, ir: &[u8], rgb: &mut [u8], mm: &mut [u16]) {
        let connected = |a: f32, b: f32| (a - b).abs() < self.jump;
        for u in 0..WIDTH {
            let z = self.z_mm[u];
            if z == EMPTY {
                continue;
            }
            let (x, y, inv) = (self.xs[u], self.ys[u], 1.0 / self.nz[u]);
            let (hx, hy) = (self.half_px[0] * inv, self.half_px[1] * inv);
            let d = self.disp[u];
            let left_link = u > 0 && self.z_mm[u - 1] != EMPTY && connected(self.disp[u - 1], d);
            let right_link = u + 1 < WIDTH && self.z_mm[u + 1] != EMPTY && connected(d, self.disp[u + 1]);
            let xl = if left_link { 0.5 * (self.xs[u - 1] + x) } else { x - hx };
            let xr = if right_link { 0.5 * (x + self.xs[u + 1]) } else { x + hx };
            let label = ir[u];
            let depth = if label == VALID { z } else { 0 };
            let (c0, c1) = span(xl, xr, WIDTH);
            let (r0, r1) = span(y - hy, y + hy, HEIGHT);
            for r in r0..r1 {
                let base = r * WIDTH;
                for t in base + c0..base + c1 {
                    if z < self.zbuf[t] {
                        self.zbuf[t] = z;
                        rgb[t] = label;
                        mm[t] = depth;
                    }
                }
            }
            // A nearer pixel followed by a farther one splits apart: the RGB camera, right of the
            // IR camera, sees background there that the IR camera cannot.
            if u + 1 < WIDTH && !right_link && self.z_mm[u + 1] != EMPTY && d > self.disp[u + 1] {
                let inv_b = 1.0 / self.nz[u + 1];
                let (g0, g1) = span(x + hx, self.xs[u + 1] - self.half_px[0] * inv_b, WIDTH);
                let hyb = self.half_px[1] * inv_b;
                let (r0, r1) = span(self.ys[u + 1] - hyb, self.ys[u + 1] + hyb, HEIGHT);
                for r in r0..r1 {
                    let base = r * WIDTH;
                    for t in base + g0..base + g1 {
                        if self.zbuf[t] == EMPTY {
                            self.zbuf[t] = GAP;
                            rgb[t] = ALIGNMENT;
                        }
                    }
                }
            }
        }
    }
}

/// Target pixels whose centres lie in `[lo, hi)`, clipped to `0..len`.
#[inline]
fn span(lo: f32, hi: f32, len: usize) -> (usize, usize) {
    let a = lo.ceil().clamp(0.0, len as f32) as usize;
    let b = hi.ceil().clamp(0.0, len as f32) as usize;
    (a, b.max(a))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::classify::{Classified, Classifier};
    use crate::labels::{histogram, ATTACHED};

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
                assert!((out.registered_mm[i] as i32 - 2000).abs() < 10, "{}", out.registered_mm[i]);
            }
        }
        // The IR camera's field of view ends inside the RGB image: the border outside it is OTHER.
        assert_eq!(out.rgb_labels[5 * WIDTH + 5], OTHER);
        assert_eq!(out.rgb_labels[250 * WIDTH + 39], OTHER);
        assert_eq!(out.rgb_labels[250 * WIDTH + 611], OTHER);
        assert_eq!(histogram(&out.rgb_labels)[ALIGNMENT as usize], 0);
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
        let strip = out.rgb_labels[row..row + WIDTH].iter().filter(|&&l| l == ALIGNMENT).count() as f64;
        assert!((strip - predicted).abs() <= 1.5, "strip {strip} px, predicted {predicted:.1}");
        // The projector shadow carries over, narrowed by the RGB camera's own viewpoint to about
        // f_rgb·(0.075 − 0.025)·(1/1 − 1/3) px.
        let shadow = out.rgb_labels[row..row + WIDTH].iter().filter(|&&l| l == ATTACHED).count() as f64;
        let predicted = c.rgb.fx * 0.05 * (1.0 - 1.0 / 3.0);
        assert!((shadow - predicted).abs() <= 2.0, "shadow {shadow} px, predicted {predicted:.1}");
        // Alignment pixels sit right of the box, attached ones left of it.
        let first_align = out.rgb_labels[row..row + WIDTH].iter().position(|&l| l == ALIGNMENT).unwrap();
        let last_attached = out.rgb_labels[row..row + WIDTH].iter().rposition(|&l| l == ATTACHED).unwrap();
        assert!(first_align > last_attached + 100);
    }
}
