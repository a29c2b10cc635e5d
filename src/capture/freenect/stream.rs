//! The capture thread: opens a Kinect, streams 640×480 11-bit depth and RGB, and hands frames
//! over without ever blocking libfreenect's USB thread.
//!
//! Each stream has a fixed pool of preallocated buffers circulating over two bounded channels
//! (free → callback → full → consumer → free). A callback takes a free buffer with `try_recv`,
//! copies the frame into it and passes it on with `try_send`; with no free buffer (the consumer
//! fell behind) the frame is dropped and counted, so the callback never waits and never allocates.

use std::ffi::c_void;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::{Arc, Mutex};
use std::thread::JoinHandle;
use std::time::{Duration, Instant, SystemTime, UNIX_EPOCH};

use crossbeam_channel::{bounded, Receiver, Sender};
use tracing::{info, info_span, warn};

use super::device::{Context, Device, Selector};
use super::library::{self, Library};
use super::sys;
use crate::error::{Error, Result};
use crate::labels::PIXELS;

/// How long one `freenect_process_events_timeout` call may wait, so a stop request is seen soon.
const POLL: Duration = Duration::from_millis(100);

/// One frame as the callback delivered it.
pub struct Captured<T> {
    /// Device timestamp (32-bit, wraps).
    pub ts: u32,
    /// Host time the callback ran, seconds since the epoch.
    pub unix_time: f64,
    /// The same moment on the monotonic clock: the start of the frame's end-to-end latency.
    pub received: Instant,
    /// Frames of this stream dropped since the previous delivered one.
    pub dropped_before: u64,
    /// The pixels; give the buffer back through the stream's `*_free` sender when done.
    pub data: Vec<T>,
}

/// What the capture thread learnt about the device before streaming.
#[derive(Clone, Debug)]
pub struct DeviceInfo {
    /// Factory zero-plane numbers and `const_shift`, when the library provides them.
    pub zero_plane: Option<(sys::ZeroPlaneInfo, f64)>,
    /// Camera serials on the bus (empty when the library cannot list them).
    pub serials: Vec<String>,
}

/// Pixel types a callback may copy raw bytes into: every bit pattern is a valid value.
trait Pod: Copy + Default + Send + 'static {}
impl Pod for u8 {}
impl Pod for u16 {}

/// The callback side of one stream.
struct Lane<T: Pod> {
    free: Receiver<Vec<T>>,
    /// To put a buffer back if handing it on fails (never expected: `full` has room for all).
    refill: Sender<Vec<T>>,
    full: Sender<Captured<T>>,
    /// Elements per frame.
    len: usize,
    pending_drops: AtomicU64,
    dropped: Arc<AtomicU64>,
}

impl<T: Pod> Lane<T> {
    /// Copies one frame out of libfreenect's buffer, or drops it when no buffer is free.
    ///
    /// # Safety
    /// `src` must point to at least `len * size_of::<T>()` readable bytes (any alignment).
    unsafe fn deliver(&self, ts: u32, src: *const u8) {
        let Ok(mut buf) = self.free.try_recv() else {
            self.pending_drops.fetch_add(1, Ordering::Relaxed);
            self.dropped.fetch_add(1, Ordering::Relaxed);
            return;
        };
        buf.resize(self.len, T::default());
        // SAFETY: the caller guarantees `src` has the bytes; `buf` holds exactly `len` elements
        // of a type valid for any bytes, and the two cannot overlap (`buf` is ours).
        unsafe {
            std::ptr::copy_nonoverlapping(
                src,
                buf.as_mut_ptr().cast::<u8>(),
                self.len * size_of::<T>(),
            )
        };
        let unix_time = SystemTime::now()
            .duration_since(UNIX_EPOCH)
            .map_or(0.0, |d| d.as_secs_f64());
        let frame = Captured {
            ts,
            unix_time,
            received: Instant::now(),
            dropped_before: self.pending_drops.swap(0, Ordering::Relaxed),
            data: buf,
        };
        if let Err(e) = self.full.try_send(frame) {
            let frame = e.into_inner();
            self.pending_drops
                .fetch_add(1 + frame.dropped_before, Ordering::Relaxed);
            self.dropped.fetch_add(1, Ordering::Relaxed);
            let _ = self.refill.try_send(frame.data);
        }
    }
}

/// What the callbacks reach through `freenect_get_user`.
struct Shared {
    depth: Lane<u16>,
    video: Lane<u8>,
}

/// The consumer side of a running capture; stops the capture thread when dropped.
pub struct Stream {
    /// Depth frames (640·480 raw 11-bit values), oldest first.
    pub depth: Receiver<Captured<u16>>,
    /// Where depth buffers go back.
    pub depth_free: Sender<Vec<u16>>,
    /// RGB frames (640·480·3), oldest first.
    pub video: Receiver<Captured<u8>>,
    /// Where RGB buffers go back.
    pub video_free: Sender<Vec<u8>>,
    /// What the device reported when opened.
    pub info: DeviceInfo,
    depth_dropped: Arc<AtomicU64>,
    video_dropped: Arc<AtomicU64>,
    /// Set on drop; separate from the caller's flag, which means "a signal asked to stop".
    halt: Arc<AtomicBool>,
    failure: Arc<Mutex<Option<Error>>>,
    thread: Option<JoinHandle<()>>,
}

/// Depth and RGB counters of frames dropped because every buffer was in use.
pub type DropCounters = (Arc<AtomicU64>, Arc<AtomicU64>);

/// A stream's callback side, its consumer's two channel ends and its drop counter.
type LaneParts<T> = (
    Lane<T>,
    Receiver<Captured<T>>,
    Sender<Vec<T>>,
    Arc<AtomicU64>,
);

/// A pool of `pool` buffers of `len` elements and the channels it circulates on.
fn lane<T: Pod>(pool: usize, len: usize) -> LaneParts<T> {
    let (free_tx, free_rx) = bounded(pool);
    for _ in 0..pool {
        free_tx
            .send(vec![T::default(); len])
            .expect("pool channel has room for the whole pool");
    }
    let (full_tx, full_rx) = bounded(pool);
    let dropped = Arc::new(AtomicU64::new(0));
    let lane = Lane {
        free: free_rx,
        refill: free_tx.clone(),
        full: full_tx,
        len,
        pending_drops: AtomicU64::new(0),
        dropped: dropped.clone(),
    };
    (lane, full_rx, free_tx, dropped)
}

impl Stream {
    /// Loads libfreenect, opens `which` on a new capture thread and starts streaming into pools of
    /// `pool` buffers per stream. The thread ends when `stop` is set, at the end of a fakenect
    /// recording, or on a device error (then [`Stream::take_failure`] says which).
    pub fn start(which: Selector, pool: usize, stop: Arc<AtomicBool>) -> Result<Stream> {
        let lib = library::load()?;
        let pool = pool.max(2);
        let (depth, depth_rx, depth_free, depth_dropped) = lane::<u16>(pool, PIXELS);
        let (video, video_rx, video_free, video_dropped) = lane::<u8>(pool, PIXELS * 3);
        let shared = Arc::new(Shared { depth, video });
        let failure = Arc::new(Mutex::new(None));
        let halt = Arc::new(AtomicBool::new(false));
        let (ready_tx, ready_rx) = bounded(1);
        let thread = {
            let (halt, failure) = (halt.clone(), failure.clone());
            std::thread::Builder::new()
                .name("freenect".into())
                .spawn(move || {
                    // Setup errors go back to `start`; later ones reach the consumer via `failure`.
                    if let Err(e) =
                        capture(lib, &which, shared, [&stop, &halt], &ready_tx, &failure)
                    {
                        let _ = ready_tx.send(Err(e));
                    }
                })
                .map_err(|e| Error::Usage(format!("cannot start the capture thread: {e}")))?
        };
        let info = match ready_rx.recv() {
            Ok(Ok(info)) => info,
            Ok(Err(e)) => {
                let _ = thread.join();
                return Err(e);
            }
            Err(_) => {
                let _ = thread.join();
                return Err(Error::Usage(
                    "the capture thread ended before the device was ready".into(),
                ));
            }
        };
        Ok(Stream {
            depth: depth_rx,
            depth_free,
            video: video_rx,
            video_free,
            info,
            depth_dropped,
            video_dropped,
            halt,
            failure,
            thread: Some(thread),
        })
    }

    /// The device error that ended the capture thread, if any (once).
    pub fn take_failure(&self) -> Option<Error> {
        self.failure
            .lock()
            .unwrap_or_else(|p| p.into_inner())
            .take()
    }

    /// Depth and RGB frames dropped so far because every buffer was in use.
    pub fn dropped(&self) -> (u64, u64) {
        (
            self.depth_dropped.load(Ordering::Relaxed),
            self.video_dropped.load(Ordering::Relaxed),
        )
    }

    /// The depth and RGB drop counters themselves, readable after the stream is gone.
    pub fn drop_counters(&self) -> DropCounters {
        (self.depth_dropped.clone(), self.video_dropped.clone())
    }
}

impl Drop for Stream {
    fn drop(&mut self) {
        self.halt.store(true, Ordering::SeqCst);
        if let Some(t) = self.thread.take() {
            let _ = t.join();
        }
    }
}

/// The capture thread's body: every libfreenect call happens here, on one thread. Errors before
/// streaming are returned; once `ready` has been told, they are stored in `failure` instead.
fn capture(
    lib: &'static Library,
    which: &Selector,
    shared: Arc<Shared>,
    stop: [&AtomicBool; 2],
    ready: &Sender<Result<DeviceInfo>>,
    failure: &Mutex<Option<Error>>,
) -> Result<()> {
    let _span = info_span!("capture", device = %which).entered();
    let ctx = Context::init(lib)?;
    let serials = ctx.serials();
    let dev = ctx.open(which)?;
    dev.set_modes()?;
    // SAFETY: `shared` outlives `dev` (declared before it in this function, and `dev` is
    // dropped, closing the device, before it returns); the callbacks read it as `Shared`.
    unsafe { dev.set_callbacks(Arc::as_ptr(&shared) as *mut c_void, on_depth, on_video) };
    let info = DeviceInfo {
        zero_plane: dev.zero_plane(),
        serials,
    };
    dev.start()?;
    info!(library = %lib.name, fakenect = lib.fakenect, "streaming 640x480 11-bit depth and RGB");
    let _ = ready.send(Ok(info));
    let result = loop {
        if stop.iter().any(|s| s.load(Ordering::SeqCst)) {
            info!("stop requested");
            break Ok(());
        }
        let rc = ctx.process_events(POLL);
        if rc >= 0 || rc == sys::LIBUSB_ERROR_INTERRUPTED {
            continue;
        }
        if lib.fakenect {
            // fakenect returns a negative value for good once INDEX.txt is exhausted.
            info!("end of the fakenect recording");
            break Ok(());
        }
        warn!(code = rc, "USB event processing failed");
        break Err(Error::Usage(format!(
            "{which}: USB event processing failed (libfreenect code {rc})"
        )));
    };
    dev.stop();
    drop(dev);
    drop(ctx);
    if let Err(e) = result {
        *failure.lock().unwrap_or_else(|p| p.into_inner()) = Some(e);
    }
    // The channels' senders go with `shared`, after `failure` is set: the consumer sees the end
    // once it has drained them, and then the reason.
    drop(shared);
    Ok(())
}

/// The `Shared` behind a device's user pointer.
///
/// # Safety
/// `dev` must be a device whose user pointer was set by [`capture`].
unsafe fn shared_of<'a>(dev: *mut sys::Device) -> Option<&'a Shared> {
    let lib = library::load().ok()?;
    // SAFETY: the caller passes a live device; its user pointer is an `Arc<Shared>`'s pointee
    // that `capture` keeps alive until the device is closed.
    unsafe { Device::user_of(lib, dev).cast::<Shared>().as_ref() }
}

unsafe extern "C" fn on_depth(dev: *mut sys::Device, data: *mut c_void, ts: u32) {
    // A panic must not unwind into C; there is nothing to recover, the frame is lost.
    let _ = std::panic::catch_unwind(|| {
        // SAFETY: libfreenect calls this only for the device `capture` set up.
        let Some(shared) = (unsafe { shared_of(dev) }) else {
            return;
        };
        if data.is_null() {
            return;
        }
        // SAFETY: `data` holds one frame of the mode `set_modes` checked: 640·480 u16, possibly
        // unaligned (fakenect passes a pointer just past the PGM header), hence a byte copy.
        unsafe { shared.depth.deliver(ts, data.cast::<u8>()) };
    });
}

unsafe extern "C" fn on_video(dev: *mut sys::Device, data: *mut c_void, ts: u32) {
    // A panic must not unwind into C; there is nothing to recover, the frame is lost.
    let _ = std::panic::catch_unwind(|| {
        // SAFETY: libfreenect calls this only for the device `capture` set up.
        let Some(shared) = (unsafe { shared_of(dev) }) else {
            return;
        };
        if data.is_null() {
            return;
        }
        // SAFETY: `data` holds one frame of the mode `set_modes` checked: 640·480·3 bytes.
        unsafe { shared.video.deliver(ts, data.cast::<u8>()) };
    });
}
