//! The C types of `libfreenect.h` and `libfreenect_registration.h` (0.5) that umbra uses, laid out
//! exactly as the headers declare them (sizes checked against the real header in the tests).

use std::ffi::{c_char, c_int, c_void};

/// `freenect_context` (opaque).
#[repr(C)]
pub struct Context {
    _opaque: [u8; 0],
}

/// `freenect_device` (opaque).
#[repr(C)]
pub struct Device {
    _opaque: [u8; 0],
}

/// `struct freenect_device_attributes`: one node of the device list.
#[repr(C)]
pub struct DeviceAttributes {
    /// Next node, or null.
    pub next: *mut DeviceAttributes,
    /// NUL-terminated camera serial.
    pub camera_serial: *const c_char,
}

/// `FREENECT_DEVICE_CAMERA` (`freenect_device_flags`).
pub const DEVICE_CAMERA: c_int = 0x02;
/// `FREENECT_RESOLUTION_MEDIUM`: 640×480.
pub const RESOLUTION_MEDIUM: c_int = 1;
/// `FREENECT_VIDEO_RGB`.
pub const VIDEO_RGB: c_int = 0;
/// `FREENECT_DEPTH_11BIT`: one u16 per pixel, host byte order.
pub const DEPTH_11BIT: c_int = 0;
/// `LIBUSB_ERROR_INTERRUPTED`, which `freenect_process_events` passes through: not a failure.
pub const LIBUSB_ERROR_INTERRUPTED: c_int = -10;

/// `freenect_frame_mode` (24 bytes; the anonymous union is one 32-bit enum).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default)]
pub struct FrameMode {
    /// Library-internal id; must be passed back untouched.
    pub reserved: u32,
    /// `freenect_resolution`.
    pub resolution: c_int,
    /// `freenect_video_format` or `freenect_depth_format`.
    pub format: c_int,
    /// Bytes in one frame.
    pub bytes: i32,
    /// Width, pixels.
    pub width: i16,
    /// Height, pixels.
    pub height: i16,
    /// Data bits per pixel.
    pub data_bits_per_pixel: i8,
    /// Padding bits per pixel.
    pub padding_bits_per_pixel: i8,
    /// Nominal frame rate, Hz.
    pub framerate: i8,
    /// Non-zero when the mode exists.
    pub is_valid: i8,
}

/// `freenect_reg_info`: 29 int32 of the device's registration line protocol (unused here).
#[repr(C)]
#[derive(Clone, Copy)]
pub struct RegInfo {
    /// The fields, in header order.
    pub fields: [i32; 29],
}

/// `freenect_reg_pad_info`.
#[repr(C)]
#[derive(Clone, Copy)]
pub struct RegPadInfo {
    /// `start_lines`.
    pub start_lines: u16,
    /// `end_lines`.
    pub end_lines: u16,
    /// `cropping_lines`.
    pub cropping_lines: u16,
}

/// `freenect_zero_plane_info`: the factory numbers umbra's calibration is derived from.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct ZeroPlaneInfo {
    /// IR camera to IR emitter, cm.
    pub dcmos_emitter_dist: f32,
    /// IR camera to RGB camera, cm.
    pub dcmos_rcmos_dist: f32,
    /// Zero-plane distance (the IR focal length), mm.
    pub reference_distance: f32,
    /// Size of one pixel on the zero plane, mm.
    pub reference_pixel_size: f32,
}

/// `freenect_registration`, returned by value from `freenect_copy_registration`; its three
/// tables are heap-allocated by the library and freed by `freenect_destroy_registration`.
#[repr(C)]
pub struct Registration {
    /// `reg_info`.
    pub reg_info: RegInfo,
    /// `reg_pad_info`.
    pub reg_pad_info: RegPadInfo,
    /// `zero_plane_info`.
    pub zero_plane_info: ZeroPlaneInfo,
    /// `const_shift`.
    pub const_shift: f64,
    /// `raw_to_mm_shift` table.
    pub raw_to_mm_shift: *mut u16,
    /// `depth_to_rgb_shift` table.
    pub depth_to_rgb_shift: *mut i32,
    /// `registration_table`: 640·480 pairs.
    pub registration_table: *mut [i32; 2],
}

/// `freenect_depth_cb` / `freenect_video_cb`.
pub type FrameCallback = unsafe extern "C" fn(dev: *mut Device, data: *mut c_void, timestamp: u32);

/// `struct timeval` on Linux.
#[repr(C)]
pub struct Timeval {
    /// Seconds.
    pub tv_sec: std::ffi::c_long,
    /// Microseconds.
    pub tv_usec: std::ffi::c_long,
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::mem::{offset_of, size_of};

    /// Numbers printed by a C program compiled against Debian's libfreenect-dev 0.5.3 headers.
    #[test]
    fn layouts_match_the_header() {
        assert_eq!(size_of::<FrameMode>(), 24);
        assert_eq!(offset_of!(FrameMode, bytes), 12);
        assert_eq!(offset_of!(FrameMode, width), 16);
        assert_eq!(offset_of!(FrameMode, is_valid), 23);
        assert_eq!(size_of::<RegInfo>(), 116);
        assert_eq!(size_of::<RegPadInfo>(), 6);
        assert_eq!(offset_of!(Registration, zero_plane_info), 124);
        assert_eq!(offset_of!(Registration, const_shift), 144);
        assert_eq!(offset_of!(Registration, raw_to_mm_shift), 152);
        assert_eq!(offset_of!(Registration, registration_table), 168);
        assert_eq!(size_of::<Registration>(), 176);
        assert_eq!(size_of::<DeviceAttributes>(), 16);
        assert_eq!(offset_of!(DeviceAttributes, camera_serial), 8);
    }
}
