//! Where classified frames go. [`labels`] holds the SPEC §4 label files and the
//! [`LabelExport`] sink that writes them.

pub mod foreground;
pub mod labels;
pub mod mcap;

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Arc;

use tracing::{info, warn};

use crate::error::{Error, Result};
use crate::pipeline::Frame;

/// Something that consumes classified frames in order.
pub trait Sink: Send {
    /// Writes one frame. An error stops the pipeline.
    fn write(&mut self, frame: &Frame) -> Result<()>;

    /// Called once after the last frame (flush, close files).
    fn finish(&mut self) -> Result<()> {
        Ok(())
    }
}

/// Writes SPEC §4 files: `<dir>/<i:06>.depth.png` and `<dir>/<i:06>.rgb.png` per frame.
pub struct LabelExport {
    dir: PathBuf,
    /// PNG bytes, reused frame after frame.
    buf: Vec<u8>,
}

impl LabelExport {
    /// Creates `dir` (and parents) if needed.
    pub fn create(dir: &Path) -> Result<Self> {
        if dir.exists() && !dir.is_dir() {
            return Err(Error::input(dir, "", "exists and is not a folder: label export needs a folder to write <i>.depth.png and <i>.rgb.png into"));
        }
        std::fs::create_dir_all(dir).map_err(|e| Error::io(dir, "creating folder", e))?;
        Ok(LabelExport {
            dir: dir.to_path_buf(),
            buf: Vec::new(),
        })
    }
}

impl Sink for LabelExport {
    fn write(&mut self, frame: &Frame) -> Result<()> {
        let i = frame.seq as usize;
        labels::write_label_png_with(
            &labels::label_path(&self.dir, i, "depth"),
            &frame.labels.ir_labels,
            &mut self.buf,
        )?;
        labels::write_label_png_with(
            &labels::label_path(&self.dir, i, "rgb"),
            &frame.labels.rgb_labels,
            &mut self.buf,
        )
    }
}

/// Makes a sink's write errors non-fatal, for the daemon: a frame that cannot be written (disk
/// full, folder gone) is counted as lost, the first failure of a burst is logged, and the next
/// frame is tried again. Capture never stops because of the output.
pub struct Tolerant<S> {
    inner: S,
    name: &'static str,
    lost: Arc<AtomicU64>,
    failing: bool,
}

impl<S: Sink> Tolerant<S> {
    /// Wraps `inner`; `name` says which output failed in logs.
    pub fn new(inner: S, name: &'static str) -> Self {
        Tolerant {
            inner,
            name,
            lost: Arc::default(),
            failing: false,
        }
    }

    /// Frames this sink failed to write (shared, for status lines).
    pub fn lost_counter(&self) -> Arc<AtomicU64> {
        self.lost.clone()
    }
}

impl<S: Sink> Sink for Tolerant<S> {
    fn write(&mut self, frame: &Frame) -> Result<()> {
        match self.inner.write(frame) {
            Ok(()) => {
                if std::mem::take(&mut self.failing) {
                    info!(
                        output = self.name,
                        lost_total = self.lost.load(Ordering::Relaxed),
                        "writing works again"
                    );
                }
            }
            Err(e) => {
                self.lost.fetch_add(1, Ordering::Relaxed);
                if !std::mem::replace(&mut self.failing, true) {
                    warn!(
                        output = self.name,
                        seq = frame.seq,
                        "write failed, frames are counted as lost until it works again: {e}"
                    );
                }
            }
        }
        Ok(())
    }

    fn finish(&mut self) -> Result<()> {
        self.inner.finish()
    }
}
