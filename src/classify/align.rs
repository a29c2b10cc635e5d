//! Warp to the RGB view (stub, being written).
use crate::calib::Calibration;
/// The warp.
pub struct Warp;
impl Warp {
    /// Builds it.
    pub fn new(_c: &Calibration) -> Self { Warp }
    /// Applies it.
    pub fn apply(&mut self, _filled: &[u16], ir: &[u8], rgb: &mut [u8], mm: &mut [u16]) {
        rgb.copy_from_slice(ir);
        mm.fill(0);
    }
}
