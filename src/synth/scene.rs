//! Scenes: objects with shapes and materials, hand-built test scenes, and frame-to-frame motion.

use super::geometry::{Shape, V3};

/// Surface properties the sensor and the RGB camera care about.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Material {
    /// IR reflectance in `[0, 1]`; below [`super::SensorModel::min_albedo`] the pattern is lost.
    pub albedo: f64,
    /// Mirror-like surface: the projector's pattern is reflected away, so no depth anywhere on it.
    pub specular: bool,
    /// Visible colour, linear RGB in `[0, 1]`.
    pub colour: [f64; 3],
}

impl Material {
    /// A matte surface of the given colour that the sensor measures well.
    pub fn matte(colour: [f64; 3]) -> Self {
        Material {
            albedo: 0.8,
            specular: false,
            colour,
        }
    }

    /// A black (low-IR-albedo) surface: never any depth, dark in the RGB image.
    pub fn black() -> Self {
        Material {
            albedo: 0.02,
            specular: false,
            colour: [0.04, 0.04, 0.045],
        }
    }

    /// A mirror-like surface of the given colour: never any depth.
    pub fn glossy(colour: [f64; 3]) -> Self {
        Material {
            albedo: 0.9,
            specular: true,
            colour,
        }
    }
}

/// One object of a scene.
#[derive(Clone, Debug, PartialEq)]
pub struct Object {
    /// Identifier, unique within its scene (its index in [`Scene::objects`]).
    pub id: u32,
    /// What it is ("wall", "floor", "box", "rod", ...), for descriptions.
    pub kind: &'static str,
    /// Geometry at frame 0.
    pub shape: Shape,
    /// Surface.
    pub material: Material,
    /// Displacement per frame, metres (multi-frame recordings).
    pub velocity: V3,
    /// Turn per frame about the vertical axis through the object's centre, radians.
    pub spin: f64,
}

/// A static arrangement of objects (plus their per-frame motion).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Scene {
    /// The objects; `objects[i].id == i`.
    pub objects: Vec<Object>,
    /// A short human-readable description (written to `meta.toml`).
    pub description: String,
}

/// A wall facing the camera: the plane `z = z_wall`.
pub fn wall(z_wall: f64) -> Shape {
    Shape::Plane {
        normal: V3::new(0.0, 0.0, -1.0),
        offset: -z_wall,
    }
}

/// A vertical rod: a cylinder of `radius` with its axis at `(x, ·, z)`, long enough to cross the
/// whole image.
pub fn vertical_rod(x: f64, z: f64, radius: f64) -> Shape {
    Shape::Cylinder {
        centre: V3::new(x, 0.0, z),
        axis: V3::new(0.0, 1.0, 0.0),
        radius,
        half_len: 3.0,
    }
}

/// A wall through `(0, 0, z_wall)` turned by `yaw` about the vertical axis (positive: its right
/// side recedes).
pub fn slanted_wall(z_wall: f64, yaw: f64) -> Shape {
    let normal = V3::new(yaw.sin(), 0.0, -yaw.cos());
    Shape::Plane {
        normal,
        offset: normal.dot(&V3::new(0.0, 0.0, z_wall)),
    }
}

/// A floor `h` metres below the camera, seen by a camera pitched `pitch` radians down: in the
/// camera frame (y down) the floor's up vector is `(0, −cos pitch, −sin pitch)`, so the optical
/// axis meets the floor `h / sin(pitch)` metres away.
pub fn floor(h: f64, pitch: f64) -> Shape {
    Shape::Plane {
        normal: V3::new(0.0, -pitch.cos(), -pitch.sin()),
        offset: -h,
    }
}

impl Object {
    /// True for salient objects, the foreground of SPEC §6: everything but the room's surfaces.
    /// Walls, floors and partitions (a room wall in front of a farther one) are background, and
    /// so are posters: a few millimetres thick on a wall, they are part of it for a segmenter.
    pub fn is_foreground(&self) -> bool {
        !matches!(self.kind, "wall" | "floor" | "partition" | "poster")
    }
}

impl Scene {
    /// An empty scene with a description.
    pub fn new(description: impl Into<String>) -> Self {
        Scene {
            objects: Vec::new(),
            description: description.into(),
        }
    }

    /// The same scene with every surface the sensor cannot measure (black, glossy) made matte in
    /// its own colour: the shadows' geometry without occluders that return no depth, to tell the
    /// classifier's misses on those apart from the rest.
    pub fn all_matte(mut self) -> Scene {
        let mut changed = 0;
        for o in &mut self.objects {
            let m = o.material;
            if m.specular || m.albedo < super::SensorModel::kinect().min_albedo {
                o.material = Material::matte(m.colour);
                changed += 1;
            }
        }
        match changed {
            0 => {}
            1 => self.description += "; 1 black or glossy surface made matte",
            n => self.description += &format!("; {n} black or glossy surfaces made matte"),
        }
        self
    }

    /// Adds a static object and returns it for further tweaks (motion).
    pub fn push(&mut self, kind: &'static str, shape: Shape, material: Material) -> &mut Object {
        let id = self.objects.len() as u32;
        self.objects.push(Object {
            id,
            kind,
            shape,
            material,
            velocity: V3::zeros(),
            spin: 0.0,
        });
        self.objects.last_mut().expect("just pushed")
    }

    /// A matte box, 40 cm wide, 50 cm tall, 20 cm deep, centred on the optical axis with its
    /// front face at `z_box`, before a wall at `z_wall`. Centred so that neither camera nor
    /// projector sees a side face: the attached shadow is then exactly `f·b·(1/z_box − 1/z_wall)`
    /// pixels wide and the RGB alignment strip `f_rgb·|t|·(1/z_box − 1/z_wall)`.
    pub fn box_before_wall(z_box: f64, z_wall: f64) -> Scene {
        let mut s = Scene::new(format!(
            "box 0.4x0.5x0.2 m, front face at {z_box} m, before a wall at {z_wall} m"
        ));
        s.push("wall", wall(z_wall), Material::matte([0.8, 0.78, 0.7]));
        s.push(
            "box",
            Shape::Box {
                centre: V3::new(0.0, 0.0, z_box + BOX_HALF.z),
                half: BOX_HALF,
                yaw: 0.0,
            },
            Material::matte([0.7, 0.2, 0.15]),
        );
        s
    }

    /// A vertical rod (cylinder of `radius`) with its axis at `(x, ·, z_rod)`, long enough to cross
    /// the whole image, before a wall at `z_wall`.
    pub fn rod_before_wall(x: f64, z_rod: f64, radius: f64, z_wall: f64) -> Scene {
        let mut s = Scene::new(format!(
            "vertical rod r={radius} m at x={x} m, z={z_rod} m, before a wall at {z_wall} m"
        ));
        s.push("wall", wall(z_wall), Material::matte([0.8, 0.78, 0.7]));
        s.push(
            "rod",
            vertical_rod(x, z_rod, radius),
            Material::matte([0.6, 0.6, 0.65]),
        );
        s
    }

    /// The scene as it is at frame `k`: every object moved by `k` steps of its motion.
    pub fn at_frame(&self, k: usize) -> Scene {
        let k = k as f64;
        let objects = self
            .objects
            .iter()
            .map(|o| Object {
                shape: o.shape.moved(&(o.velocity * k), o.spin * k),
                ..o.clone()
            })
            .collect();
        Scene {
            objects,
            description: self.description.clone(),
        }
    }
}

/// Half-extents of the box of [`Scene::box_before_wall`].
pub const BOX_HALF: V3 = V3::new(0.2, 0.25, 0.1);
