//! IR-view scanline classifier (stub, being written).
use crate::calib::Calibration;
use super::Params;
/// Precomputed per-calibration constants.
pub struct ScanParams;
impl ScanParams {
    /// Builds them.
    pub fn new(_c: &Calibration, _p: &Params) -> Self { ScanParams }
}
/// Classifies a frame.
pub fn classify_frame(_p: &ScanParams, raw: &[u16], labels: &mut [u8], filled: &mut [u16]) {
    for ((l, f), r) in labels.iter_mut().zip(filled.iter_mut()).zip(raw) {
        *l = if *r == 2047 { crate::labels::OTHER } else { 0 };
        *f = *r;
    }
}
