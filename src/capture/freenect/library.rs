//! Loads `libfreenect.so.0.5` at run time, once per process, and keeps it loaded for good, so the
//! function pointers below are valid for the rest of the program (callbacks rely on that).
//!
//! `UMBRA_LIBFREENECT` overrides the file name (a path, or a name the loader searches for);
//! `LD_LIBRARY_PATH` works as usual, which is how libfreenect's `fakenect` replay library is used.

use std::ffi::{c_char, c_int, c_void};
use std::sync::OnceLock;

use super::sys::{
    Context, Device, DeviceAttributes, FrameCallback, FrameMode, Registration, Timeval,
};
use crate::error::{Error, Result};

/// The library file loaded when `UMBRA_LIBFREENECT` is not set.
pub const DEFAULT_NAME: &str = "libfreenect.so.0.5";
/// Environment variable naming another library file.
pub const ENV_VAR: &str = "UMBRA_LIBFREENECT";
const INSTALL: &str = "install it with 'apt-get install libfreenect0.5'";

/// The libfreenect functions umbra calls. The last four are absent from Debian's fakenect 0.5.3.
pub struct Api {
    /// `freenect_init`.
    pub init: unsafe extern "C" fn(*mut *mut Context, *mut c_void) -> c_int,
    /// `freenect_shutdown`.
    pub shutdown: unsafe extern "C" fn(*mut Context) -> c_int,
    /// `freenect_select_subdevices`.
    pub select_subdevices: unsafe extern "C" fn(*mut Context, c_int),
    /// `freenect_num_devices`.
    pub num_devices: unsafe extern "C" fn(*mut Context) -> c_int,
    /// `freenect_open_device`.
    pub open_device: unsafe extern "C" fn(*mut Context, *mut *mut Device, c_int) -> c_int,
    /// `freenect_open_device_by_camera_serial`.
    pub open_device_by_camera_serial:
        unsafe extern "C" fn(*mut Context, *mut *mut Device, *const c_char) -> c_int,
    /// `freenect_close_device`.
    pub close_device: unsafe extern "C" fn(*mut Device) -> c_int,
    /// `freenect_find_depth_mode`.
    pub find_depth_mode: unsafe extern "C" fn(c_int, c_int) -> FrameMode,
    /// `freenect_find_video_mode`.
    pub find_video_mode: unsafe extern "C" fn(c_int, c_int) -> FrameMode,
    /// `freenect_set_depth_mode`.
    pub set_depth_mode: unsafe extern "C" fn(*mut Device, FrameMode) -> c_int,
    /// `freenect_set_video_mode`.
    pub set_video_mode: unsafe extern "C" fn(*mut Device, FrameMode) -> c_int,
    /// `freenect_set_depth_callback`.
    pub set_depth_callback: unsafe extern "C" fn(*mut Device, Option<FrameCallback>),
    /// `freenect_set_video_callback`.
    pub set_video_callback: unsafe extern "C" fn(*mut Device, Option<FrameCallback>),
    /// `freenect_set_user`.
    pub set_user: unsafe extern "C" fn(*mut Device, *mut c_void),
    /// `freenect_get_user`.
    pub get_user: unsafe extern "C" fn(*mut Device) -> *mut c_void,
    /// `freenect_start_depth`.
    pub start_depth: unsafe extern "C" fn(*mut Device) -> c_int,
    /// `freenect_start_video`.
    pub start_video: unsafe extern "C" fn(*mut Device) -> c_int,
    /// `freenect_stop_depth`.
    pub stop_depth: unsafe extern "C" fn(*mut Device) -> c_int,
    /// `freenect_stop_video`.
    pub stop_video: unsafe extern "C" fn(*mut Device) -> c_int,
    /// `freenect_process_events_timeout`.
    pub process_events_timeout: unsafe extern "C" fn(*mut Context, *mut Timeval) -> c_int,
    /// `freenect_list_device_attributes`.
    pub list_device_attributes:
        Option<unsafe extern "C" fn(*mut Context, *mut *mut DeviceAttributes) -> c_int>,
    /// `freenect_free_device_attributes`.
    pub free_device_attributes: Option<unsafe extern "C" fn(*mut DeviceAttributes)>,
    /// `freenect_copy_registration`.
    pub copy_registration: Option<unsafe extern "C" fn(*mut Device) -> Registration>,
    /// `freenect_destroy_registration`.
    pub destroy_registration: Option<unsafe extern "C" fn(*mut Registration) -> c_int>,
}

/// A loaded libfreenect (the real one or fakenect).
pub struct Library {
    /// The functions; valid as long as `_lib` is loaded, which is forever (see [`load`]).
    pub api: Api,
    /// File name or path it was loaded from.
    pub name: String,
    /// Whether this is libfreenect's `fakenect` replay library (it exports its own timing helpers).
    pub fakenect: bool,
    _lib: libloading::Library,
}

static LIBRARY: OnceLock<std::result::Result<Library, String>> = OnceLock::new();

/// The process-wide libfreenect, loaded on first use. Fails with one line naming the Debian
/// package when the library is missing.
pub fn load() -> Result<&'static Library> {
    LIBRARY
        .get_or_init(open)
        .as_ref()
        .map_err(|msg| Error::Usage(msg.clone()))
}

fn open() -> std::result::Result<Library, String> {
    let name = std::env::var(ENV_VAR).unwrap_or_else(|_| DEFAULT_NAME.to_string());
    // SAFETY: loading libfreenect runs its (and libusb's) initialisers, which have no
    // preconditions; the library is never unloaded, so nothing it hands out can dangle.
    let lib = unsafe { libloading::Library::new(&name) }.map_err(|e| {
        let why = e.to_string();
        if why.contains("No such file") {
            format!("{name} not found: {INSTALL}")
        } else {
            format!(
                "{name} cannot be loaded ({}): {INSTALL}",
                why.split_whitespace().collect::<Vec<_>>().join(" ")
            )
        }
    })?;
    let need = |sym: &str| format!("{name}: symbol {sym} missing: not libfreenect 0.5? {INSTALL}");
    // SAFETY: each symbol is read as the type of the `Api` field it fills, which is its
    // signature in libfreenect.h 0.5, and `lib` stays loaded for good.
    let api = unsafe {
        Api {
            init: sym(&lib, "freenect_init").ok_or_else(|| need("freenect_init"))?,
            shutdown: sym(&lib, "freenect_shutdown").ok_or_else(|| need("freenect_shutdown"))?,
            select_subdevices: sym(&lib, "freenect_select_subdevices")
                .ok_or_else(|| need("freenect_select_subdevices"))?,
            num_devices: sym(&lib, "freenect_num_devices")
                .ok_or_else(|| need("freenect_num_devices"))?,
            open_device: sym(&lib, "freenect_open_device")
                .ok_or_else(|| need("freenect_open_device"))?,
            open_device_by_camera_serial: sym(&lib, "freenect_open_device_by_camera_serial")
                .ok_or_else(|| need("freenect_open_device_by_camera_serial"))?,
            close_device: sym(&lib, "freenect_close_device")
                .ok_or_else(|| need("freenect_close_device"))?,
            find_depth_mode: sym(&lib, "freenect_find_depth_mode")
                .ok_or_else(|| need("freenect_find_depth_mode"))?,
            find_video_mode: sym(&lib, "freenect_find_video_mode")
                .ok_or_else(|| need("freenect_find_video_mode"))?,
            set_depth_mode: sym(&lib, "freenect_set_depth_mode")
                .ok_or_else(|| need("freenect_set_depth_mode"))?,
            set_video_mode: sym(&lib, "freenect_set_video_mode")
                .ok_or_else(|| need("freenect_set_video_mode"))?,
            set_depth_callback: sym(&lib, "freenect_set_depth_callback")
                .ok_or_else(|| need("freenect_set_depth_callback"))?,
            set_video_callback: sym(&lib, "freenect_set_video_callback")
                .ok_or_else(|| need("freenect_set_video_callback"))?,
            set_user: sym(&lib, "freenect_set_user").ok_or_else(|| need("freenect_set_user"))?,
            get_user: sym(&lib, "freenect_get_user").ok_or_else(|| need("freenect_get_user"))?,
            start_depth: sym(&lib, "freenect_start_depth")
                .ok_or_else(|| need("freenect_start_depth"))?,
            start_video: sym(&lib, "freenect_start_video")
                .ok_or_else(|| need("freenect_start_video"))?,
            stop_depth: sym(&lib, "freenect_stop_depth")
                .ok_or_else(|| need("freenect_stop_depth"))?,
            stop_video: sym(&lib, "freenect_stop_video")
                .ok_or_else(|| need("freenect_stop_video"))?,
            process_events_timeout: sym(&lib, "freenect_process_events_timeout")
                .ok_or_else(|| need("freenect_process_events_timeout"))?,
            list_device_attributes: sym(&lib, "freenect_list_device_attributes"),
            free_device_attributes: sym(&lib, "freenect_free_device_attributes"),
            copy_registration: sym(&lib, "freenect_copy_registration"),
            destroy_registration: sym(&lib, "freenect_destroy_registration"),
        }
    };
    // SAFETY: only the symbol's presence is checked; it is never called.
    let fakenect = unsafe { lib.get::<unsafe extern "C" fn()>(b"sleep_highres\0") }.is_ok();
    Ok(Library {
        api,
        name,
        fakenect,
        _lib: lib,
    })
}

/// Reads symbol `name` as a `T`, or `None` when the library lacks it.
///
/// # Safety
/// `T` must be the symbol's true type (a function pointer with its C signature).
unsafe fn sym<T: Copy>(lib: &libloading::Library, name: &str) -> Option<T> {
    let mut cname = name.as_bytes().to_vec();
    cname.push(0);
    // SAFETY: the caller guarantees `T` is the symbol's type.
    unsafe { lib.get::<T>(&cname) }.ok().map(|s| *s)
}
