//! Ray casting one frame: the IR view (depth, projector shadows, exact labels) and the RGB view
//! (colour image, alignment shadows, exact labels).
//!
//! Ground-truth conventions (see also the module doc of [`super`]):
//! - IR view: a pixel with depth is VALID. A pixel whose surface is measurable (albedo, range,
//!   not specular) but not lit by the projector is a projector shadow: ATTACHED if the first pixel
//!   to its right that is not in geometric shadow shows the occluder (the first object on the
//!   projector→surface segment), else DETACHED. A shadow that runs off the right border is
//!   followed past it, on rays of columns beyond the image, to its first lit pixel: ATTACHED
//!   when that shows the occluder (SPEC §1: the hole touches its occluder, which the border
//!   hides), DETACHED when lit background comes first. After the sensor's effects, a DETACHED
//!   run from which the occluder is reached walking right over holes alone (the widening
//!   swallowed the lit gap, or it fell on a surface that is a hole anyway) is ATTACHED: SPEC §1's
//!   attached shadow is a hole that touches its occluder, and its detached one leaves visible
//!   background between them.
//!   Every other hole is OTHER, including unlit surfaces that would be holes even if lit.
//! - RGB view: the nearest surface along the RGB pixel's ray, projected into the IR image. Outside
//!   the IR image or no surface: OTHER. Hidden from the IR camera: ALIGNMENT if the surface is
//!   measurable, else OTHER (it would be a hole even if the IR camera saw it, like a shadow on a
//!   black poster). Otherwise the IR label at the nearest IR pixel.

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use super::geometry::{Aabb, Hit, Shape, V3};
use super::scene::{Material, Scene};
use super::sensor::{self, SensorModel};
use crate::calib::Calibration;
use crate::labels::{ALIGNMENT, ATTACHED, DETACHED, HEIGHT, NO_DEPTH, OTHER, PIXELS, VALID, WIDTH};

/// One simulated frame with its exact ground truth.
#[derive(Clone, Debug, PartialEq)]
pub struct SynthFrame {
    /// Raw 11-bit depth, 640·480, 2047 = no depth.
    pub raw: Vec<u16>,
    /// RGB image, 640·480·3 bytes.
    pub rgb: Vec<u8>,
    /// Ground-truth labels in the IR (depth) view.
    pub ir_labels: Vec<u8>,
    /// Ground-truth labels in the RGB view.
    pub rgb_labels: Vec<u8>,
    /// Ground-truth foreground in the RGB view (SPEC §6): 255 where the RGB camera sees an object
    /// that is part of no room surface ([`super::Object::is_foreground`]), else 0.
    pub fg: Vec<u8>,
}

/// Where a segment ends short of its end point: the fraction `1 − SEG_EPS` keeps a surface from
/// shadowing itself at the very point being tested (3 µm at 3 m).
const SEG_EPS: f64 = 1e-6;
/// No object index.
const NONE: u32 = u32::MAX;

/// The scene's shapes with cached bounding boxes.
struct Tracer<'a> {
    shapes: Vec<&'a Shape>,
    bounds: Vec<Option<Aabb>>,
}

impl<'a> Tracer<'a> {
    fn new(scene: &'a Scene) -> Self {
        let shapes: Vec<&Shape> = scene.objects.iter().map(|o| &o.shape).collect();
        let bounds = shapes.iter().map(|s| s.bounds()).collect();
        Tracer { shapes, bounds }
    }

    /// Nearest hit on `o + t·d`, `t ∈ (tmin, tmax)`: object index and hit.
    fn nearest(&self, o: &V3, d: &V3, tmin: f64, mut tmax: f64) -> Option<(usize, Hit)> {
        let inv = d.map(|x| 1.0 / x);
        let mut best = None;
        for (i, (s, b)) in self.shapes.iter().zip(&self.bounds).enumerate() {
            if b.is_some_and(|b| !b.hit(o, &inv, tmin, tmax)) {
                continue;
            }
            if let Some(h) = s.intersect(o, d, tmin, tmax) {
                tmax = h.t;
                best = Some((i, h));
            }
        }
        best
    }

    /// True if anything lies on `o + t·d`, `t ∈ (tmin, tmax)`.
    fn any(&self, o: &V3, d: &V3, tmin: f64, tmax: f64) -> bool {
        let inv = d.map(|x| 1.0 / x);
        self.shapes.iter().zip(&self.bounds).any(|(s, b)| {
            b.is_none_or(|b| b.hit(o, &inv, tmin, tmax)) && s.intersect(o, d, tmin, tmax).is_some()
        })
    }
}

/// Per-pixel geometry of the IR view before any sensor effect.
#[derive(Clone, Debug)]
pub struct IrGeometry {
    /// Object seen at each pixel, `u32::MAX` for none.
    pub object: Vec<u32>,
    /// Depth (z) of that surface, `+∞` for none.
    pub z: Vec<f64>,
    /// First object on the projector→surface segment, `u32::MAX` if the surface is lit.
    pub occluder: Vec<u32>,
    /// Would the surface yield depth if lit (albedo, range, not specular)?
    pub measurable: Vec<bool>,
    /// Per row whose last pixel is in shadow: the object seen at the first lit column past the
    /// right border (`u32::MAX` for none within 256 columns), where that shadow ends.
    pub beyond: Vec<u32>,
}

/// Columns past the right border a shadow is followed (the widest shadow, of an occluder at the
/// sensor's nearest range, is under 120 px).
const BEYOND: usize = 256;

impl IrGeometry {
    /// True if pixel `i` sees a surface the projector does not light.
    pub fn in_shadow(&self, i: usize) -> bool {
        self.object[i] != NONE && self.occluder[i] != NONE
    }
}

/// Ray direction (z = 1) of integer pixel `(u, v)` for intrinsics `(fx, fy, cx, cy)`.
fn pixel_ray(k: &crate::calib::Intrinsics, u: usize, v: usize) -> V3 {
    V3::new((u as f64 - k.cx) / k.fx, (v as f64 - k.cy) / k.fy, 1.0)
}

/// Casts the IR camera's rays and the projector's shadow rays.
pub fn trace_ir(scene: &Scene, calib: &Calibration, sensor: &SensorModel) -> IrGeometry {
    let tracer = Tracer::new(scene);
    let projector = V3::new(calib.raw.baseline_m, 0.0, 0.0);
    let mut g = IrGeometry {
        object: vec![NONE; PIXELS],
        z: vec![f64::INFINITY; PIXELS],
        occluder: vec![NONE; PIXELS],
        measurable: vec![false; PIXELS],
        beyond: vec![NONE; HEIGHT],
    };
    // What pixel (u, v) sees (object, depth), and what shades it from the projector.
    let cast = |u: usize, v: usize| {
        let d = pixel_ray(&calib.depth, u, v);
        let (obj, hit) = tracer.nearest(&V3::zeros(), &d, 0.0, f64::INFINITY)?;
        let p = d * hit.t; // d.z = 1, so t is the depth
        let occ = tracer.nearest(&projector, &(p - projector), 0.0, 1.0 - SEG_EPS);
        Some((obj, hit.t, occ.map(|(o, _)| o)))
    };
    for v in 0..HEIGHT {
        for u in 0..WIDTH {
            let i = v * WIDTH + u;
            let Some((obj, z, occ)) = cast(u, v) else {
                continue;
            };
            let m: &Material = &scene.objects[obj].material;
            g.object[i] = obj as u32;
            g.z[i] = z;
            g.measurable[i] = sensor.measurable(z, m.albedo, m.specular);
            g.occluder[i] = occ.map_or(NONE, |o| o as u32);
        }
        if g.in_shadow(v * WIDTH + WIDTH - 1) {
            g.beyond[v] = (WIDTH..WIDTH + BEYOND)
                .find_map(|u| match cast(u, v) {
                    Some((_, _, Some(_))) => None,
                    Some((obj, _, None)) => Some(obj as u32),
                    None => Some(NONE),
                })
                .unwrap_or(NONE);
        }
    }
    g
}

/// Exact IR-view labels of noise-free geometry (before sensor artefacts).
pub fn ir_labels(g: &IrGeometry) -> Vec<u8> {
    let mut labels = vec![OTHER; PIXELS];
    for v in 0..HEIGHT {
        // Right-to-left, remembering what the nearest non-shadow pixel to the right shows
        // (past the border, for a shadow that runs off it).
        let mut right_obj = g.beyond[v];
        for u in (0..WIDTH).rev() {
            let i = v * WIDTH + u;
            if g.in_shadow(i) {
                labels[i] = match (g.measurable[i], g.occluder[i] == right_obj) {
                    (false, _) => OTHER,
                    (true, true) => ATTACHED,
                    (true, false) => DETACHED,
                };
            } else {
                labels[i] = if g.object[i] != NONE && g.measurable[i] {
                    VALID
                } else {
                    OTHER
                };
                right_obj = g.object[i];
            }
        }
    }
    labels
}

/// Relabels ATTACHED each run of DETACHED pixels in `labels` from whose right end, walking over
/// holes of the final `raw` map alone, a pixel of the object that shadows one of its pixels comes
/// before any valid pixel of another: no background shows between that shadow and its occluder.
fn touching_runs_attached(g: &IrGeometry, raw: &[u16], labels: &mut [u8]) {
    for v in 0..HEIGHT {
        let row = v * WIDTH;
        let mut u = 0;
        while u < WIDTH {
            if labels[row + u] != DETACHED {
                u += 1;
                continue;
            }
            let start = u;
            while u < WIDTH && labels[row + u] == DETACHED {
                u += 1;
            }
            let casts = |obj: u32| (start..u).any(|x| g.occluder[row + x] == obj);
            let touches = (u..WIDTH)
                .find(|&x| raw[row + x] != NO_DEPTH || casts(g.object[row + x]))
                .is_some_and(|x| g.object[row + x] != NONE && casts(g.object[row + x]));
            if touches {
                labels[row + start..row + u].fill(ATTACHED);
            }
        }
    }
}

/// Renders one frame of `scene`. `seed` drives every random sensor effect, so the same inputs
/// always give the same frame.
pub fn render_frame(
    scene: &Scene,
    calib: &Calibration,
    sensor: &SensorModel,
    seed: u64,
) -> SynthFrame {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let g = trace_ir(scene, calib, sensor);
    let mut labels = ir_labels(&g);
    let mut raw: Vec<u16> = labels
        .iter()
        .zip(&g.z)
        .map(|(&l, &z)| {
            if l == VALID {
                sensor.raw_value(calib, z, &mut rng)
            } else {
                NO_DEPTH
            }
        })
        .collect();
    sensor::widen_shadows(sensor, &mut labels, &mut raw, &mut rng);
    sensor::mixed_pixels(sensor, &labels, &mut raw, &mut rng);
    sensor::speckle(sensor, &mut labels, &mut raw, &mut rng);
    sensor::spurious(sensor, calib, &g.z, &mut labels, &mut raw, &mut rng);
    touching_runs_attached(&g, &raw, &mut labels);
    let (rgb, rgb_labels, fg) = render_rgb(scene, calib, sensor, &labels, &mut rng);
    SynthFrame {
        raw,
        rgb,
        ir_labels: labels,
        rgb_labels,
        fg,
    }
}

/// The RGB camera's image, labels and foreground mask, given the final IR-view labels. The mask
/// takes no random draw, so adding it left the image and labels byte-identical.
pub fn render_rgb(
    scene: &Scene,
    calib: &Calibration,
    sensor: &SensorModel,
    ir: &[u8],
    rng: &mut impl Rng,
) -> (Vec<u8>, Vec<u8>, Vec<u8>) {
    let tracer = Tracer::new(scene);
    let rt = calib.depth_to_rgb.rotation.transpose();
    let centre = -(rt * calib.depth_to_rgb.translation);
    // A lamp a little above the camera, so faces get Lambert shading and no visible light shadows.
    let lamp = centre + V3::new(0.05, -0.3, 0.0);
    let k = &calib.depth;
    let mut rgb = vec![0u8; PIXELS * 3];
    let mut labels = vec![OTHER; PIXELS];
    let mut fg = vec![0u8; PIXELS];
    for v in 0..HEIGHT {
        for u in 0..WIDTH {
            let i = v * WIDTH + u;
            let d = rt * pixel_ray(&calib.rgb, u, v);
            let Some((obj, hit)) = tracer.nearest(&centre, &d, 0.0, f64::INFINITY) else {
                rgb[3 * i..3 * i + 3].copy_from_slice(&[8, 8, 10]);
                continue;
            };
            let p = centre + d * hit.t;
            if scene.objects[obj].is_foreground() {
                fg[i] = 255;
            }
            let m = &scene.objects[obj].material;
            shade(
                &mut rgb[3 * i..3 * i + 3],
                &p,
                &hit.normal,
                &d,
                &lamp,
                m,
                obj,
                (
                    sensor.rgb_gain,
                    if sensor.rgb_soft {
                        0.0
                    } else {
                        sensor.rgb_noise_sigma
                    },
                ),
                rng,
            );
            if p.z <= 0.0 {
                continue;
            }
            let (fu, fv) = (k.fx * p.x / p.z + k.cx, k.fy * p.y / p.z + k.cy);
            let (iu, iv) = (fu.round(), fv.round());
            if iu < 0.0 || iv < 0.0 || iu >= WIDTH as f64 || iv >= HEIGHT as f64 {
                continue;
            }
            labels[i] = if tracer.any(&V3::zeros(), &p, 0.0, 1.0 - SEG_EPS) {
                if sensor.measurable(p.z, m.albedo, m.specular) {
                    ALIGNMENT
                } else {
                    OTHER
                }
            } else {
                ir[iv as usize * WIDTH + iu as usize]
            };
        }
    }
    if sensor.rgb_soft {
        // The lens before the sensor's noise.
        rgb = sensor::soften(&rgb);
        if sensor.rgb_noise_sigma > 0.0 {
            for b in &mut rgb {
                let noisy = f64::from(*b) + sensor::gauss(rng) * sensor.rgb_noise_sigma;
                *b = noisy.round().clamp(0.0, 255.0) as u8;
            }
        }
    }
    (rgb, labels, fg)
}

/// Colour of one RGB pixel: material colour × (ambient + Lambert) × a little 3-D texture,
/// gamma-encoded, times the camera's gain, plus noise of σ (the pair `(gain, noise)`).
#[allow(clippy::too_many_arguments)]
fn shade(
    out: &mut [u8],
    p: &V3,
    normal: &V3,
    d: &V3,
    lamp: &V3,
    m: &Material,
    obj: usize,
    (gain, noise): (f64, f64),
    rng: &mut impl Rng,
) {
    let n = if normal.dot(d) > 0.0 {
        -normal
    } else {
        *normal
    };
    let lambert = n.dot(&(lamp - p).normalize()).max(0.0);
    let tex = 1.0 + 0.12 * (texture(p, obj, 0.02) - 0.5) + 0.08 * (texture(p, obj, 0.1) - 0.5);
    let light = (0.25 + 0.75 * lambert) * tex;
    for (o, colour) in out.iter_mut().zip(m.colour) {
        let lin = (colour * light).clamp(0.0, 1.0);
        let n = if noise > 0.0 {
            sensor::gauss(rng) * noise
        } else {
            0.0
        };
        *o = (255.0 * gain * lin.powf(1.0 / 2.2) + n)
            .round()
            .clamp(0.0, 255.0) as u8;
    }
}

/// Blocky value noise in `[0, 1)`: a hash of the `cell`-sized 3-D cell containing `p`.
fn texture(p: &V3, obj: usize, cell: f64) -> f64 {
    let q = p / cell;
    let mut h: u64 = 0x9e37_79b9_7f4a_7c15 ^ obj as u64;
    for x in [q.x.floor() as i64, q.y.floor() as i64, q.z.floor() as i64] {
        h = (h ^ x as u64).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        h ^= h >> 31;
    }
    (h >> 11) as f64 / (1u64 << 53) as f64
}
