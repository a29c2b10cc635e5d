//! umbra: classifies the holes of Kinect v1 depth maps as projector shadows (attached, detached),
//! alignment shadows or other holes, after Deng et al., "Kinect Shadow Detection and
//! Classification", ICCV Workshops 2013. See SPEC.md §1 for the geometry and §2 for label codes.
//!
//! Layout: [`recording`] reads fakenect folders, [`classify`] holds the pure per-frame algorithm,
//! [`pipeline`] runs frames through it on threads with recycled buffers, [`sink`] writes results,
//! [`synth`] is the simulator with exact ground truth, [`eval`] scores labels against it,
//! [`render`] draws a frame for people, [`cli`] is the `umbra` command.

#![warn(missing_docs)]

pub mod calib;
pub mod capture;
pub mod classify;
pub mod cli;
pub mod config;
pub mod error;
pub mod eval;
pub mod labels;
pub mod pipeline;
pub mod recording;
pub mod render;
pub mod segment;
pub mod service;
pub mod sink;
pub mod synth;

pub use calib::Calibration;
pub use error::{Error, Result};
