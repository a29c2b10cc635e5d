//! Primitive shapes and ray intersection.
//!
//! Rays are `o + t·d` with `d` *not* normalised: a camera ray with `d.z = 1` then reports `t = z`,
//! and a segment `a → b` cast as `d = b − a` reports `t` as the fraction of the way to `b`.
//! Every intersection routine is written so that it works for any scale of `d`.

use nalgebra::{Matrix3, Vector3};

/// A 3-vector in the IR camera frame, metres.
pub type V3 = Vector3<f64>;

/// A surface hit: ray parameter and outward unit normal.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hit {
    /// Ray parameter of the hit (see the module doc for its unit).
    pub t: f64,
    /// Outward unit normal of the surface at the hit.
    pub normal: V3,
}

/// One geometric primitive.
#[derive(Clone, Debug, PartialEq)]
pub enum Shape {
    /// Infinite plane `normal · X = offset`; `normal` is unit and points towards the cameras.
    Plane {
        /// Unit normal.
        normal: V3,
        /// Signed distance of the plane from the origin along `normal`.
        offset: f64,
    },
    /// Box with centre, half-extents along its own axes, and a rotation about the y axis.
    Box {
        /// Centre.
        centre: V3,
        /// Half-extents along the box's local x, y, z axes.
        half: V3,
        /// Rotation about the camera's y axis (radians; positive turns local +z towards +x).
        yaw: f64,
    },
    /// Capped cylinder of any orientation (thin ones are rods).
    Cylinder {
        /// Centre of the axis segment.
        centre: V3,
        /// Unit axis direction.
        axis: V3,
        /// Radius.
        radius: f64,
        /// Half of the length along the axis.
        half_len: f64,
    },
    /// Sphere.
    Sphere {
        /// Centre.
        centre: V3,
        /// Radius.
        radius: f64,
    },
}

/// Rotation about the y axis by `yaw` radians (local +z turns towards +x for positive yaw).
pub fn rot_y(yaw: f64) -> Matrix3<f64> {
    let (s, c) = yaw.sin_cos();
    Matrix3::new(c, 0.0, s, 0.0, 1.0, 0.0, -s, 0.0, c)
}

/// Axis-aligned bounding box used to reject rays cheaply.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Aabb {
    /// Lower corner.
    pub min: V3,
    /// Upper corner.
    pub max: V3,
}

impl Aabb {
    /// True if the ray `o + t·d` meets the box for some `t` in `[tmin, tmax]`.
    #[inline]
    pub fn hit(&self, o: &V3, inv_d: &V3, tmin: f64, tmax: f64) -> bool {
        let mut lo = tmin;
        let mut hi = tmax;
        for i in 0..3 {
            let t1 = (self.min[i] - o[i]) * inv_d[i];
            let t2 = (self.max[i] - o[i]) * inv_d[i];
            // NaN (0·∞ for a ray lying in a slab face) must not reject: f64::min/max skip NaN.
            lo = lo.max(t1.min(t2));
            hi = hi.min(t1.max(t2));
        }
        lo <= hi
    }
}

impl Shape {
    /// Bounding box; `None` for unbounded shapes (planes).
    pub fn bounds(&self) -> Option<Aabb> {
        let (c, e) = match *self {
            Shape::Plane { .. } => return None,
            Shape::Box { centre, half, yaw } => {
                let r = rot_y(yaw).abs();
                (centre, r * half)
            }
            Shape::Cylinder {
                centre,
                axis,
                radius,
                half_len,
            } => {
                let e = V3::from_fn(|i, _| {
                    axis[i].abs() * half_len + radius * (1.0 - axis[i] * axis[i]).max(0.0).sqrt()
                });
                (centre, e)
            }
            Shape::Sphere { centre, radius } => (centre, V3::repeat(radius)),
        };
        // A hair of slack so that rounding never rejects a grazing ray that the exact test keeps.
        let e = e.add_scalar(1e-9);
        Some(Aabb {
            min: c - e,
            max: c + e,
        })
    }

    /// Nearest intersection with `o + t·d` for `t` strictly inside `(tmin, tmax)`.
    pub fn intersect(&self, o: &V3, d: &V3, tmin: f64, tmax: f64) -> Option<Hit> {
        match *self {
            Shape::Plane { normal, offset } => {
                let den = normal.dot(d);
                if den.abs() < 1e-15 {
                    return None;
                }
                let t = (offset - normal.dot(o)) / den;
                (t > tmin && t < tmax).then_some(Hit { t, normal })
            }
            Shape::Box { centre, half, yaw } => {
                intersect_box(o, d, &centre, &half, yaw, tmin, tmax)
            }
            Shape::Cylinder {
                centre,
                axis,
                radius,
                half_len,
            } => intersect_cylinder(o, d, &centre, &axis, radius, half_len, tmin, tmax),
            Shape::Sphere { centre, radius } => {
                let w = o - centre;
                let a = d.dot(d);
                let b = w.dot(d);
                let c = w.dot(&w) - radius * radius;
                let disc = b * b - a * c;
                if disc < 0.0 {
                    return None;
                }
                let s = disc.sqrt();
                let t = [(-b - s) / a, (-b + s) / a]
                    .into_iter()
                    .find(|&t| t > tmin && t < tmax)?;
                Some(Hit {
                    t,
                    normal: (w + d * t) / radius,
                })
            }
        }
    }

    /// The same shape moved by `shift` and turned by `spin` radians about the vertical axis
    /// through its centre (planes only shift).
    pub fn moved(&self, shift: &V3, spin: f64) -> Shape {
        match *self {
            Shape::Plane { normal, offset } => Shape::Plane {
                normal,
                offset: offset + normal.dot(shift),
            },
            Shape::Box { centre, half, yaw } => Shape::Box {
                centre: centre + shift,
                half,
                yaw: yaw + spin,
            },
            Shape::Cylinder {
                centre,
                axis,
                radius,
                half_len,
            } => Shape::Cylinder {
                centre: centre + shift,
                axis: rot_y(spin) * axis,
                radius,
                half_len,
            },
            Shape::Sphere { centre, radius } => Shape::Sphere {
                centre: centre + shift,
                radius,
            },
        }
    }
}

#[allow(clippy::too_many_arguments)]
fn intersect_box(
    o: &V3,
    d: &V3,
    centre: &V3,
    half: &V3,
    yaw: f64,
    tmin: f64,
    tmax: f64,
) -> Option<Hit> {
    // Work in the box's frame, where it is axis-aligned: slab test.
    let rt = rot_y(yaw).transpose();
    let lo_ = rt * (o - centre);
    let ld = rt * d;
    let (mut near, mut far) = (f64::NEG_INFINITY, f64::INFINITY);
    let (mut near_axis, mut far_axis) = (0usize, 0usize);
    let (mut near_sign, mut far_sign) = (0.0, 0.0);
    for i in 0..3 {
        if ld[i].abs() < 1e-300 {
            if lo_[i].abs() > half[i] {
                return None;
            }
            continue;
        }
        let inv = 1.0 / ld[i];
        let (mut t1, mut t2) = ((-half[i] - lo_[i]) * inv, (half[i] - lo_[i]) * inv);
        // Entering through the face whose outward normal opposes the ray.
        let (mut s1, mut s2) = (-1.0, 1.0);
        if t1 > t2 {
            std::mem::swap(&mut t1, &mut t2);
            std::mem::swap(&mut s1, &mut s2);
        }
        if t1 > near {
            near = t1;
            near_axis = i;
            near_sign = s1;
        }
        if t2 < far {
            far = t2;
            far_axis = i;
            far_sign = s2;
        }
    }
    if near > far {
        return None;
    }
    let (t, axis, sign) = if near > tmin && near < tmax {
        (near, near_axis, near_sign)
    } else if far > tmin && far < tmax {
        (far, far_axis, far_sign)
    } else {
        return None;
    };
    let mut n = V3::zeros();
    n[axis] = sign;
    Some(Hit {
        t,
        normal: rot_y(yaw) * n,
    })
}

#[allow(clippy::too_many_arguments)]
fn intersect_cylinder(
    o: &V3,
    d: &V3,
    centre: &V3,
    axis: &V3,
    r: f64,
    h: f64,
    tmin: f64,
    tmax: f64,
) -> Option<Hit> {
    let w = o - centre;
    let (wa, da) = (w.dot(axis), d.dot(axis));
    let wp = w - axis * wa;
    let dp = d - axis * da;
    let mut best: Option<Hit> = None;
    let mut consider = |t: f64, normal: V3| {
        if t > tmin && t < tmax && best.is_none_or(|b| t < b.t) {
            best = Some(Hit { t, normal });
        }
    };
    // Side: |wp + t·dp| = r with the axial coordinate inside the caps.
    let a = dp.dot(&dp);
    if a > 1e-300 {
        let b = wp.dot(&dp);
        let c = wp.dot(&wp) - r * r;
        let disc = b * b - a * c;
        if disc >= 0.0 {
            let s = disc.sqrt();
            for t in [(-b - s) / a, (-b + s) / a] {
                if (wa + t * da).abs() <= h {
                    consider(t, (wp + dp * t) / r);
                }
            }
        }
    }
    // Caps: the planes at ±h along the axis, inside the radius.
    if da.abs() > 1e-300 {
        for sign in [-1.0, 1.0] {
            let t = (sign * h - wa) / da;
            let q = wp + dp * t;
            if q.dot(&q) <= r * r {
                consider(t, axis * sign);
            }
        }
    }
    best
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: f64, b: f64) -> bool {
        (a - b).abs() < 1e-9
    }

    #[test]
    fn plane_hit_gives_z_for_camera_rays() {
        let p = Shape::Plane {
            normal: V3::new(0.0, 0.0, -1.0),
            offset: -3.0,
        };
        let h = p
            .intersect(&V3::zeros(), &V3::new(0.3, -0.2, 1.0), 0.0, f64::INFINITY)
            .unwrap();
        assert!(close(h.t, 3.0));
    }

    #[test]
    fn box_faces_and_yaw() {
        let b = Shape::Box {
            centre: V3::new(0.0, 0.0, 2.0),
            half: V3::new(0.5, 0.5, 0.5),
            yaw: 0.0,
        };
        let h = b
            .intersect(&V3::zeros(), &V3::new(0.0, 0.0, 1.0), 0.0, f64::INFINITY)
            .unwrap();
        assert!(close(h.t, 1.5) && h.normal == V3::new(0.0, 0.0, -1.0));
        // Turned 45°: the front edge now points at the camera, at z = 2 − 0.5·√2.
        let b = Shape::Box {
            centre: V3::new(0.0, 0.0, 2.0),
            half: V3::new(0.5, 0.5, 0.5),
            yaw: std::f64::consts::FRAC_PI_4,
        };
        let h = b
            .intersect(&V3::zeros(), &V3::new(1e-9, 0.0, 1.0), 0.0, f64::INFINITY)
            .unwrap();
        assert!((h.t - (2.0 - 0.5 * 2f64.sqrt())).abs() < 1e-6, "{}", h.t);
        assert!(b
            .intersect(&V3::zeros(), &V3::new(0.0, 1.0, 1.0), 0.0, f64::INFINITY)
            .is_none());
        // Segment stops short of the box.
        assert!(b
            .intersect(&V3::zeros(), &V3::new(0.0, 0.0, 1.0), 0.0, 1.0)
            .is_none());
    }

    #[test]
    fn cylinder_side_and_caps() {
        let c = Shape::Cylinder {
            centre: V3::new(0.0, 0.0, 2.0),
            axis: V3::new(0.0, 1.0, 0.0),
            radius: 0.1,
            half_len: 0.5,
        };
        let h = c
            .intersect(&V3::zeros(), &V3::new(0.0, 0.0, 1.0), 0.0, f64::INFINITY)
            .unwrap();
        assert!(close(h.t, 1.9) && (h.normal - V3::new(0.0, 0.0, -1.0)).norm() < 1e-12);
        // From below along the axis: the bottom cap (y = +0.5 is "down").
        let h = c
            .intersect(
                &V3::new(0.0, 2.0, 2.0),
                &V3::new(0.0, -1.0, 0.0),
                0.0,
                f64::INFINITY,
            )
            .unwrap();
        assert!(close(h.t, 1.5) && h.normal == V3::new(0.0, 1.0, 0.0));
        // Above the top: miss.
        assert!(c
            .intersect(&V3::zeros(), &V3::new(0.0, -0.3, 1.0), 0.0, f64::INFINITY)
            .is_none());
        let bb = c.bounds().unwrap();
        assert!((bb.max - V3::new(0.1, 0.5, 2.1)).norm() < 1e-6);
    }

    #[test]
    fn sphere_near_and_inside() {
        let s = Shape::Sphere {
            centre: V3::new(0.0, 0.0, 3.0),
            radius: 1.0,
        };
        let h = s
            .intersect(&V3::zeros(), &V3::new(0.0, 0.0, 2.0), 0.0, f64::INFINITY)
            .unwrap();
        assert!(close(h.t, 1.0));
        let h = s
            .intersect(
                &V3::new(0.0, 0.0, 3.0),
                &V3::new(1.0, 0.0, 0.0),
                0.0,
                f64::INFINITY,
            )
            .unwrap();
        assert!(close(h.t, 1.0) && h.normal == V3::new(1.0, 0.0, 0.0));
    }

    #[test]
    fn aabb_rejects_and_keeps() {
        let s = Shape::Sphere {
            centre: V3::new(0.0, 0.0, 3.0),
            radius: 1.0,
        };
        let bb = s.bounds().unwrap();
        let d = V3::new(0.0, 0.0, 1.0);
        let inv = d.map(|x| 1.0 / x);
        assert!(bb.hit(&V3::zeros(), &inv, 0.0, f64::INFINITY));
        assert!(!bb.hit(&V3::zeros(), &inv, 0.0, 1.5));
        let d = V3::new(1.0, 0.0, 1.0);
        assert!(!bb.hit(&V3::zeros(), &d.map(|x| 1.0 / x), 0.0, f64::INFINITY));
    }
}
