//! umbra's own Kinect v1 simulator: ray-cast scenes into fakenect recordings (SPEC §3) with exact
//! ground-truth labels in both views (SPEC §2, §4).
//!
//! Geometry (metres, IR camera frame: x right, y down, z forward): the IR camera sits at the
//! origin, the IR projector at `(+b, 0, 0)`, the RGB camera at `−Rᵀt` for `X_rgb = R·X + t`.
//! A pixel is lit if the projector→surface segment is clear; it has depth if lit and measurable
//! (albedo, range, not specular) and no random dropout hits it. The ground-truth conventions are
//! documented in [`render`]; sensor artefacts and how they keep the labels exact in [`sensor`].
//!
//! Layout: [`geometry`] (shapes, ray intersection), [`scene`] (objects, hand-built scenes, motion),
//! [`random`] (seeded scene generator), [`sensor`] (measurement model), [`render`] (ray casting,
//! labels), [`write`](mod@write) (files). Independent of [`crate::classify`] on purpose: it is the yardstick.

pub mod geometry;
pub mod random;
pub mod render;
pub mod scene;
pub mod sensor;
pub mod write;

#[cfg(test)]
mod tests;

pub use geometry::{Shape, V3};
pub use random::{random_scene, Category};
pub use render::{render_frame, SynthFrame};
pub use scene::{Material, Object, Scene};
pub use sensor::{soften, SensorModel};
pub use write::{job_frame, write_job, Job};

/// The sensor model that goes with a scene category: complex scenes get more speckle.
pub fn sensor_for(category: Category) -> SensorModel {
    match category {
        Category::Simple => SensorModel::kinect(),
        Category::Complex => SensorModel {
            speckle_prob: 6e-4,
            speckle_cluster_max: 2,
            ..SensorModel::kinect()
        },
    }
}
