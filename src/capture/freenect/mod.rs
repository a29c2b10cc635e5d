//! A small binding to libfreenect 0.5, loaded at run time: [`library`] finds the functions,
//! [`sys`] declares the C types, [`device`] owns a context and a device, [`stream`] runs the
//! capture thread and hands frames over through fixed buffer pools.

pub mod device;
pub mod library;
pub mod stream;
pub mod sys;

pub use device::Selector;
pub use stream::{Captured, DeviceInfo, DropCounters, Stream};
