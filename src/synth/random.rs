//! Random scene generator: deterministic per seed, two categories (the paper reports simple and
//! complex scenes separately).

use std::f64::consts::PI;

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use super::geometry::{rot_y, Shape, V3};
use super::scene::{floor, slanted_wall, Material, Scene};

/// Scene category, written to `meta.toml` as `category`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Category {
    /// One matte object before a back wall, maybe a floor.
    Simple,
    /// 3–8 objects at overlapping depths, thin rods, black/specular surfaces, far regions.
    Complex,
}

impl Category {
    /// The name used in `meta.toml` and on the command line.
    pub fn as_str(self) -> &'static str {
        match self {
            Category::Simple => "simple",
            Category::Complex => "complex",
        }
    }
}

/// Tangent of the IR camera's half field of view (NYU calibration), used to place objects on
/// screen without needing the calibration: horizontal, vertical.
const TAN_HALF_FOV: (f64, f64) = (0.54, 0.41);

/// A random scene of `category`, the same for the same seed.
pub fn random_scene(category: Category, seed: u64) -> Scene {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    match category {
        Category::Simple => simple(&mut rng),
        Category::Complex => complex(&mut rng),
    }
}

/// The back wall: depth on the optical axis and yaw; `wall_z_at(x)` is its depth at lateral `x`.
#[derive(Clone, Copy)]
struct Wall {
    z: f64,
    yaw: f64,
}

impl Wall {
    fn z_at(&self, x: f64) -> f64 {
        self.z + x * self.yaw.tan()
    }
}

/// The floor: camera height above it and the camera's downward pitch (the floor plane is tilted
/// in the camera frame, so it shows from about 1.5 m on, as for a Kinect on a table or tripod).
#[derive(Clone, Copy)]
struct Floor {
    h: f64,
    pitch: f64,
}

impl Floor {
    fn random(rng: &mut ChaCha8Rng) -> Self {
        Floor {
            h: rng.random_range(0.7..1.3),
            pitch: rng.random_range(0.05..0.2),
        }
    }

    /// The y of the floor under the point at depth `z`.
    fn y_at(&self, z: f64) -> f64 {
        (self.h - z * self.pitch.sin()) / self.pitch.cos()
    }

    fn push(&self, s: &mut Scene, rng: &mut ChaCha8Rng, parts: &mut Vec<String>) {
        s.push(
            "floor",
            floor(self.h, self.pitch),
            Material::matte(pale(rng)),
        );
        parts.push(format!(
            "floor {:.2} m below (camera pitched {:.2} rad down)",
            self.h, self.pitch
        ));
    }
}

fn simple(rng: &mut ChaCha8Rng) -> Scene {
    let wall = Wall {
        z: rng.random_range(2.2..4.2),
        yaw: rng.random_range(-0.15..0.15),
    };
    let mut parts = vec![format!("wall at {:.2} m (yaw {:.2})", wall.z, wall.yaw)];
    let mut s = Scene::new("");
    s.push(
        "wall",
        slanted_wall(wall.z, wall.yaw),
        Material::matte(pale(rng)),
    );
    let ground = rng.random_bool(0.5).then(|| Floor::random(rng));
    if let Some(f) = ground {
        f.push(&mut s, rng, &mut parts);
    }
    let kind = ["box", "cylinder", "sphere", "rod"][rng.random_range(0..4)];
    let z_front = rng.random_range(0.8..(wall.z - 0.6).min(3.2));
    let x = rng.random_range(-0.25..0.25) * z_front;
    let mut shape = random_shape(rng, kind, x, z_front, ground);
    keep_before_wall(&mut shape, &wall);
    parts.push(format!("{kind} at {:.2} m", front_z(&shape)));
    let o = s.push(
        kind,
        shape,
        Material {
            albedo: rng.random_range(0.4..0.95),
            ..Material::matte(vivid(rng))
        },
    );
    set_motion(rng, o);
    s.description = format!("simple: {}", parts.join(", "));
    s
}

fn complex(rng: &mut ChaCha8Rng) -> Scene {
    let mut s = Scene::new("");
    let mut parts = Vec::new();
    // Background: a plain wall, a wall slanted until part of it is beyond range, or a far wall
    // beyond range with a partition panel in front of one side.
    let variant = rng.random_range(0..3);
    let (wall, poster_wall) = match variant {
        0 => {
            let w = Wall {
                z: rng.random_range(2.8..4.2),
                yaw: rng.random_range(-0.3..0.3),
            };
            parts.push(format!("wall at {:.2} m (yaw {:.2})", w.z, w.yaw));
            (w, w)
        }
        1 => {
            let sign = if rng.random_bool(0.5) { 1.0 } else { -1.0 };
            let w = Wall {
                z: rng.random_range(3.2..4.0),
                yaw: sign * rng.random_range(0.45..0.75),
            };
            parts.push(format!(
                "slanted wall at {:.2} m (yaw {:.2}), far side beyond range",
                w.z, w.yaw
            ));
            (w, w)
        }
        _ => {
            let far = Wall {
                z: rng.random_range(4.8..6.0),
                yaw: rng.random_range(-0.1..0.1),
            };
            let panel = Wall {
                z: rng.random_range(2.6..3.8),
                yaw: rng.random_range(-0.2..0.2),
            };
            let side = if rng.random_bool(0.5) { 1.0 } else { -1.0 };
            let reach = rng.random_range(0.0..0.8);
            parts.push(format!(
                "far wall at {:.2} m beyond range, partition at {:.2} m on the {} side",
                far.z,
                panel.z,
                if side > 0.0 { "right" } else { "left" }
            ));
            // The partition: a thin panel along `panel`, from the image edge to `reach` past the axis.
            let half_w = 2.0;
            let a = side * (half_w - reach);
            let centre = V3::new(a * panel.yaw.cos(), 0.0, panel.z + a * panel.yaw.sin());
            s.push(
                "partition",
                Shape::Box {
                    centre,
                    half: V3::new(half_w, 3.0, 0.03),
                    yaw: -panel.yaw,
                },
                Material::matte(pale(rng)),
            );
            s.push(
                "wall",
                slanted_wall(far.z, far.yaw),
                Material::matte(pale(rng)),
            );
            // Objects and posters must stay before the nearer of the two.
            (
                Wall {
                    z: panel.z.min(far.z),
                    yaw: 0.0,
                },
                panel,
            )
        }
    };
    if variant != 2 {
        s.push(
            "wall",
            slanted_wall(wall.z, wall.yaw),
            Material::matte(pale(rng)),
        );
    }
    let ground = rng.random_bool(0.7).then(|| Floor::random(rng));
    if let Some(f) = ground {
        f.push(&mut s, rng, &mut parts);
    }
    if rng.random_bool(0.5) {
        // A black (or, sometimes, glossy) poster a few mm before the wall: shadows falling on it
        // are OTHER holes.
        let glossy = rng.random_bool(0.25);
        let (hw, hh) = (rng.random_range(0.15..0.45), rng.random_range(0.15..0.4));
        let a = rng.random_range(-0.35..0.35) * poster_wall.z;
        let y = rng.random_range(-0.25..0.15) * poster_wall.z;
        let (sy, cy) = poster_wall.yaw.sin_cos();
        let normal = V3::new(sy, 0.0, -cy);
        let centre = V3::new(a * cy, y, poster_wall.z + a * sy) + normal * 0.006;
        let shape = Shape::Box {
            centre,
            half: V3::new(hw, hh, 0.004),
            yaw: -poster_wall.yaw,
        };
        let m = if glossy {
            Material::glossy([0.7, 0.75, 0.8])
        } else {
            Material::black()
        };
        s.push("poster", shape, m);
        parts.push(format!(
            "{} poster",
            if glossy { "glossy" } else { "black" }
        ));
    }
    let n = rng.random_range(3..=8);
    let cluster = rng.random_range(0.9..2.4);
    let mut objs = Vec::new();
    for k in 0..n {
        let kind = if k == 0 && rng.random_bool(0.6) {
            "rod"
        } else {
            [
                "box", "box", "box", "cylinder", "cylinder", "sphere", "sphere", "rod", "rod",
                "rod",
            ][rng.random_range(0..10)]
        };
        let z_front = (cluster + rng.random_range(-0.4..0.7f64)).clamp(0.6, 3.4);
        let x = if rng.random_bool(0.25) {
            // Straddle the left or right image border.
            (if rng.random_bool(0.5) { -1.0 } else { 1.0 }) * TAN_HALF_FOV.0 * z_front
        } else {
            rng.random_range(-0.45..0.45) * z_front
        };
        let mut shape = random_shape(rng, kind, x, z_front, ground);
        keep_before_wall(&mut shape, &wall);
        let roll = rng.random::<f64>();
        let (material, tag) = if roll < 0.12 {
            (
                Material {
                    colour: dark(rng),
                    ..Material::black()
                },
                " (black)",
            )
        } else if roll < 0.22 {
            (Material::glossy(vivid(rng)), " (glossy)")
        } else {
            (
                Material {
                    albedo: rng.random_range(0.35..0.95),
                    ..Material::matte(vivid(rng))
                },
                "",
            )
        };
        objs.push(format!("{kind} at {:.2} m{tag}", front_z(&shape)));
        let o = s.push(kind, shape, material);
        set_motion(rng, o);
    }
    s.description = format!(
        "complex: {}; {} objects: {}",
        parts.join(", "),
        n,
        objs.join(", ")
    );
    s
}

/// A shape of `kind` whose nearest point is at about `z_front`, centred laterally at `x`; half of
/// the time when there is a floor it stands on it (if it then still shows in the image).
fn random_shape(
    rng: &mut ChaCha8Rng,
    kind: &str,
    x: f64,
    z_front: f64,
    ground: Option<Floor>,
) -> Shape {
    let wants_floor = rng.random_bool(0.5);
    // Floating: anywhere in the middle of the image, but above the floor.
    let free_y = |rng: &mut ChaCha8Rng, z: f64, hh: f64| {
        let y = rng.random_range(-0.6..0.6) * TAN_HALF_FOV.1 * z_front;
        ground.map_or(y, |f| y.min(f.y_at(z) - hh - 0.02))
    };
    // Centre y standing on the floor at depth z with half-height hh, if its top is in view.
    let on_floor = |z: f64, hh: f64| {
        let f = ground.filter(|_| wants_floor)?;
        let y = f.y_at(z) - hh - 0.001;
        (y - hh < 0.8 * TAN_HALF_FOV.1 * z).then_some(y)
    };
    match kind {
        "box" => {
            let half = V3::new(
                rng.random_range(0.08..0.3),
                rng.random_range(0.08..0.35),
                rng.random_range(0.05..0.2),
            );
            let z = z_front + half.z;
            let y = on_floor(z, half.y).unwrap_or_else(|| free_y(rng, z, half.y));
            Shape::Box {
                centre: V3::new(x, y, z),
                half,
                yaw: rng.random_range(-0.7..0.7),
            }
        }
        "sphere" => {
            let r = rng.random_range(0.07..0.3);
            let y = on_floor(z_front + r, r).unwrap_or_else(|| free_y(rng, z_front + r, r));
            Shape::Sphere {
                centre: V3::new(x, y, z_front + r),
                radius: r,
            }
        }
        "cylinder" | "rod" => {
            let rod = kind == "rod";
            let r = if rod {
                rng.random_range(0.004..0.02)
            } else {
                rng.random_range(0.04..0.18)
            };
            let half_len = if rod {
                rng.random_range(0.4..1.5)
            } else {
                rng.random_range(0.15..0.5)
            };
            let tilted = rng.random_bool(if rod { 0.4 } else { 0.3 });
            let axis = if tilted {
                // Lean in the image plane, a little towards or away from the camera.
                let lean: f64 = rng.random_range(-0.6..0.6);
                let nod: f64 = rng.random_range(-0.2..0.2);
                V3::new(lean.sin(), lean.cos() * nod.cos(), lean.cos() * nod.sin()).normalize()
            } else {
                V3::new(0.0, 1.0, 0.0)
            };
            let dz = r + half_len * axis.z.abs();
            let hh = half_len * axis.y.abs() + r;
            let y = if tilted {
                None
            } else {
                on_floor(z_front + dz, half_len)
            }
            .unwrap_or_else(|| free_y(rng, z_front + dz, hh));
            Shape::Cylinder {
                centre: V3::new(x, y, z_front + dz),
                axis,
                radius: r,
                half_len,
            }
        }
        _ => unreachable!("unknown kind {kind}"),
    }
}

/// Moves `shape` towards the camera if it would poke into the wall (10 cm margin).
fn keep_before_wall(shape: &mut Shape, wall: &Wall) {
    let b = shape.bounds().expect("objects are bounded");
    let limit = wall.z_at(b.min.x).min(wall.z_at(b.max.x)) - 0.1;
    if b.max.z > limit {
        *shape = shape.moved(&V3::new(0.0, 0.0, limit - b.max.z), 0.0);
    }
}

/// Depth of the nearest point of a shape's bounding box.
fn front_z(shape: &Shape) -> f64 {
    shape.bounds().map_or(f64::NAN, |b| b.min.z)
}

/// A slow drift of a few mm to 1.5 cm per frame and a small turn, so frames differ.
fn set_motion(rng: &mut ChaCha8Rng, o: &mut super::scene::Object) {
    let dir =
        rot_y(rng.random_range(0.0..2.0 * PI)) * V3::new(1.0, rng.random_range(-0.5..0.5), 0.0);
    o.velocity = dir.normalize() * rng.random_range(0.002..0.015);
    o.spin = rng.random_range(-0.02..0.02);
}

fn vivid(rng: &mut ChaCha8Rng) -> [f64; 3] {
    let mut c = [
        rng.random_range(0.1..0.9),
        rng.random_range(0.1..0.9),
        rng.random_range(0.1..0.9),
    ];
    c[rng.random_range(0..3)] = rng.random_range(0.7..0.95);
    c
}

fn pale(rng: &mut ChaCha8Rng) -> [f64; 3] {
    let base = rng.random_range(0.6..0.85);
    [
        base + rng.random_range(-0.05..0.05),
        base,
        base + rng.random_range(-0.08..0.03),
    ]
}

fn dark(rng: &mut ChaCha8Rng) -> [f64; 3] {
    let b = rng.random_range(0.02..0.06);
    [b, b, b + rng.random_range(0.0..0.02)]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn deterministic_per_seed_and_plausible() {
        for seed in 0..40 {
            for cat in [Category::Simple, Category::Complex] {
                let a = random_scene(cat, seed);
                assert_eq!(a, random_scene(cat, seed));
                for o in &a.objects {
                    if let Some(b) = o.shape.bounds() {
                        assert!(
                            b.min.z > 0.45 && b.max.z < 4.6,
                            "{seed} {cat:?} {} {:?}",
                            o.kind,
                            b
                        );
                    }
                }
                let n = a
                    .objects
                    .iter()
                    .filter(|o| !matches!(o.kind, "wall" | "floor" | "partition" | "poster"))
                    .count();
                match cat {
                    Category::Simple => assert_eq!(n, 1),
                    Category::Complex => assert!((3..=8).contains(&n)),
                }
            }
        }
        assert_ne!(
            random_scene(Category::Complex, 1),
            random_scene(Category::Complex, 2)
        );
    }
}
