//! Safe owners of a libfreenect context and an open device. Neither is `Send`: libfreenect is
//! driven from one thread (the event thread of [`super::stream`]), which creates, uses and drops
//! both there.

use std::ffi::{c_int, c_void, CStr, CString};
use std::ptr;
use std::time::Duration;

use super::library::Library;
use super::sys;
use crate::error::{Error, Result};

/// Which Kinect to open.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Selector {
    /// The N-th device on the bus (0 = first).
    Index(u32),
    /// The device whose camera has this serial number.
    Serial(String),
}

impl std::str::FromStr for Selector {
    type Err = Error;

    /// `""` → the first device, a number of up to 3 digits → that index, anything else → a
    /// camera serial (serials are 16 characters, so the two never collide).
    fn from_str(s: &str) -> Result<Self> {
        if s.is_empty() {
            Ok(Selector::Index(0))
        } else if s.len() <= 3 && s.bytes().all(|b| b.is_ascii_digit()) {
            Ok(Selector::Index(s.parse().map_err(|_| {
                Error::Usage(format!("Kinect index {s:?} is not a number"))
            })?))
        } else if s.bytes().all(|b| b.is_ascii_alphanumeric()) {
            Ok(Selector::Serial(s.to_string()))
        } else {
            Err(Error::Usage(format!("Kinect {s:?}: expected a device index (0, 1, ...) or a camera serial (letters and digits)")))
        }
    }
}

impl std::fmt::Display for Selector {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Selector::Index(i) => write!(f, "Kinect #{i}"),
            Selector::Serial(s) => write!(f, "Kinect {s}"),
        }
    }
}

fn failed(what: &str, call: &str, rc: c_int) -> Error {
    Error::Usage(format!("{what}: {call} failed (libfreenect code {rc})"))
}

/// A `freenect_context`; shut down on drop.
pub struct Context {
    lib: &'static Library,
    ctx: *mut sys::Context,
}

impl Context {
    /// `freenect_init`, then restricts later opens to the camera subdevice (no motor or audio).
    pub fn init(lib: &'static Library) -> Result<Self> {
        let mut ctx = ptr::null_mut();
        // SAFETY: `ctx` is a valid out-pointer; a null USB context asks libfreenect for its own.
        let rc = unsafe { (lib.api.init)(&mut ctx, ptr::null_mut()) };
        if rc < 0 || ctx.is_null() {
            return Err(failed(&lib.name, "freenect_init", rc));
        }
        // SAFETY: `ctx` was just initialised and is not shut down until drop.
        unsafe { (lib.api.select_subdevices)(ctx, sys::DEVICE_CAMERA) };
        Ok(Context { lib, ctx })
    }

    /// Number of Kinects on the bus.
    pub fn num_devices(&self) -> Result<u32> {
        // SAFETY: `self.ctx` is live.
        let n = unsafe { (self.lib.api.num_devices)(self.ctx) };
        u32::try_from(n).map_err(|_| failed(&self.lib.name, "freenect_num_devices", n))
    }

    /// Camera serials of the Kinects on the bus, in bus order; empty when the library cannot list
    /// them (fakenect).
    pub fn serials(&self) -> Vec<String> {
        let (Some(list), Some(free)) = (
            self.lib.api.list_device_attributes,
            self.lib.api.free_device_attributes,
        ) else {
            return Vec::new();
        };
        let mut head = ptr::null_mut();
        // SAFETY: `self.ctx` is live and `head` is a valid out-pointer.
        let n = unsafe { list(self.ctx, &mut head) };
        let mut out = Vec::new();
        let mut node = head;
        while n > 0 && !node.is_null() {
            // SAFETY: `node` is a node of the list libfreenect just built, not yet freed; its
            // serial is null or a NUL-terminated string owned by the node.
            let (serial, next) = unsafe { ((*node).camera_serial, (*node).next) };
            if !serial.is_null() {
                // SAFETY: see above.
                out.push(
                    unsafe { CStr::from_ptr(serial) }
                        .to_string_lossy()
                        .into_owned(),
                );
            }
            node = next;
        }
        if !head.is_null() {
            // SAFETY: `head` came from freenect_list_device_attributes and is freed once.
            unsafe { free(head) };
        }
        out
    }

    /// Opens the selected device's camera.
    pub fn open(&self, which: &Selector) -> Result<Device<'_>> {
        let n = self.num_devices()?;
        let what = which.to_string();
        let mut dev = ptr::null_mut();
        let rc = match which {
            Selector::Index(i) => {
                if *i >= n {
                    return Err(Error::Usage(format!(
                        "{what}: not found ({n} Kinect(s) connected)"
                    )));
                }
                // SAFETY: `self.ctx` is live; `dev` is a valid out-pointer.
                unsafe { (self.lib.api.open_device)(self.ctx, &mut dev, *i as c_int) }
            }
            Selector::Serial(s) => {
                let c = CString::new(s.as_str())
                    .map_err(|_| Error::Usage(format!("{what}: a serial cannot contain NUL")))?;
                // SAFETY: as above, and `c` is a NUL-terminated string alive across the call.
                unsafe {
                    (self.lib.api.open_device_by_camera_serial)(self.ctx, &mut dev, c.as_ptr())
                }
            }
        };
        if rc < 0 || dev.is_null() {
            let known = self.serials();
            let hint = if known.is_empty() {
                String::new()
            } else {
                format!(" (connected: {})", known.join(", "))
            };
            return Err(Error::Usage(format!(
                "{what}: cannot open it (libfreenect code {rc}){hint}"
            )));
        }
        Ok(Device {
            ctx: self,
            dev,
            what,
        })
    }

    /// Handles pending USB events (and runs frame callbacks) for at most `timeout`. Returns
    /// libfreenect's code: negative on error, and for good at the end of a fakenect recording.
    pub fn process_events(&self, timeout: Duration) -> c_int {
        let mut tv = sys::Timeval {
            tv_sec: timeout.as_secs() as _,
            tv_usec: timeout.subsec_micros() as _,
        };
        // SAFETY: `self.ctx` is live; `tv` outlives the call.
        unsafe { (self.lib.api.process_events_timeout)(self.ctx, &mut tv) }
    }
}

impl Drop for Context {
    fn drop(&mut self) {
        // SAFETY: `self.ctx` is live; every Device borrowed it and is therefore already closed.
        unsafe { (self.lib.api.shutdown)(self.ctx) };
    }
}

/// An open `freenect_device`; streams stopped and device closed on drop.
pub struct Device<'c> {
    ctx: &'c Context,
    dev: *mut sys::Device,
    what: String,
}

impl Device<'_> {
    fn api(&self) -> &'static super::library::Api {
        &self.ctx.lib.api
    }

    /// Selects 640×480 11-bit depth and 640×480 RGB.
    pub fn set_modes(&self) -> Result<()> {
        let api = self.api();
        // SAFETY: plain value-returning lookups of libfreenect's mode tables.
        let (depth, video) = unsafe {
            (
                (api.find_depth_mode)(sys::RESOLUTION_MEDIUM, sys::DEPTH_11BIT),
                (api.find_video_mode)(sys::RESOLUTION_MEDIUM, sys::VIDEO_RGB),
            )
        };
        let expect = |m: &sys::FrameMode, bytes: i32, name: &str| {
            if m.is_valid == 0 || m.width != 640 || m.height != 480 || m.bytes != bytes {
                Err(Error::Usage(format!(
                    "{}: libfreenect has no 640x480 {name} mode (got {}x{}, {} bytes)",
                    self.what, m.width, m.height, m.bytes
                )))
            } else {
                Ok(())
            }
        };
        expect(&depth, 640 * 480 * 2, "11-bit depth")?;
        expect(&video, 640 * 480 * 3, "RGB")?;
        // SAFETY: `self.dev` is open; the modes came from libfreenect's own tables.
        let rc = unsafe { (api.set_depth_mode)(self.dev, depth) };
        if rc < 0 {
            return Err(failed(&self.what, "freenect_set_depth_mode", rc));
        }
        // SAFETY: as above.
        let rc = unsafe { (api.set_video_mode)(self.dev, video) };
        if rc < 0 {
            return Err(failed(&self.what, "freenect_set_video_mode", rc));
        }
        Ok(())
    }

    /// Installs the frame callbacks and the pointer they receive through `freenect_get_user`.
    ///
    /// # Safety
    /// `user` must stay valid, and be what the callbacks expect, until this device is dropped.
    pub unsafe fn set_callbacks(
        &self,
        user: *mut c_void,
        depth: sys::FrameCallback,
        video: sys::FrameCallback,
    ) {
        let api = self.api();
        // SAFETY: `self.dev` is open; the caller vouches for `user`.
        unsafe {
            (api.set_user)(self.dev, user);
            (api.set_depth_callback)(self.dev, Some(depth));
            (api.set_video_callback)(self.dev, Some(video));
        }
    }

    /// Starts both streams.
    pub fn start(&self) -> Result<()> {
        let api = self.api();
        // SAFETY: `self.dev` is open with modes and callbacks set.
        let rc = unsafe { (api.start_depth)(self.dev) };
        if rc < 0 {
            return Err(failed(&self.what, "freenect_start_depth", rc));
        }
        // SAFETY: as above.
        let rc = unsafe { (api.start_video)(self.dev) };
        if rc < 0 {
            return Err(failed(&self.what, "freenect_start_video", rc));
        }
        Ok(())
    }

    /// Stops both streams (harmless when already stopped).
    pub fn stop(&self) {
        let api = self.api();
        // SAFETY: `self.dev` is open.
        unsafe {
            (api.stop_depth)(self.dev);
            (api.stop_video)(self.dev);
        }
    }

    /// The factory zero-plane numbers and `const_shift` (`freenect_copy_registration`), when the
    /// library has them.
    pub fn zero_plane(&self) -> Option<(sys::ZeroPlaneInfo, f64)> {
        let api = self.api();
        let (copy, destroy) = (api.copy_registration?, api.destroy_registration?);
        // SAFETY: `self.dev` is open; the copy owns three tables that `destroy` frees, once.
        unsafe {
            let mut reg = copy(self.dev);
            let factory = (reg.zero_plane_info, reg.const_shift);
            destroy(&mut reg);
            Some(factory)
        }
    }

    /// `freenect_get_user`, for the callbacks.
    ///
    /// # Safety
    /// `dev` must be a device libfreenect passed to a callback.
    pub unsafe fn user_of(lib: &Library, dev: *mut sys::Device) -> *mut c_void {
        // SAFETY: the caller passes a live device.
        unsafe { (lib.api.get_user)(dev) }
    }
}

impl Drop for Device<'_> {
    fn drop(&mut self) {
        self.stop();
        let api = self.api();
        // SAFETY: `self.dev` is open and closed exactly once, here; callbacks only run inside
        // process_events on this thread, so none is running now.
        unsafe {
            (api.set_depth_callback)(self.dev, None);
            (api.set_video_callback)(self.dev, None);
            (api.close_device)(self.dev);
        }
    }
}
