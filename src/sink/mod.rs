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
    /// The folder did not exist before: if nothing is written into it (the run failed first),
    /// it goes again rather than being left behind empty.
    created: bool,
    /// How many label PNGs an earlier export left in the folder.
    earlier: usize,
    /// Added to each frame's number: past an earlier session's frames when appending.
    offset: usize,
    /// The highest frame written so far.
    last: Option<usize>,
}

impl LabelExport {
    /// Creates `dir` (and parents) if needed. A folder that holds anything but SPEC §4 label
    /// PNGs (a ground-truth folder has `meta.toml`, say) is refused, since its files would be
    /// overwritten; the label PNGs of an earlier export are replaced, with a warning, and those
    /// past this export's last frame are removed when it finishes, so that the folder holds
    /// exactly SPEC §4's files for the recording exported last (a run that fails keeps them).
    pub fn create(dir: &Path) -> Result<Self> {
        let export = Self::open(dir)?;
        if export.earlier > 0 {
            warn!(
                folder = %dir.display(),
                "replacing the label PNGs of an earlier export ({} files)",
                export.earlier
            );
        }
        Ok(export)
    }

    /// The folder made or checked, what an earlier export left in it counted.
    fn open(dir: &Path) -> Result<Self> {
        if dir.exists() && !dir.is_dir() {
            return Err(Error::input(dir, "", "exists and is not a folder: label export needs a folder to write <i>.depth.png and <i>.rgb.png into"));
        }
        let created = !dir.exists();
        let earlier = if created { 0 } else { earlier_labels(dir)? };
        std::fs::create_dir_all(dir).map_err(|e| Error::io(dir, "creating folder", e))?;
        Ok(LabelExport {
            dir: dir.to_path_buf(),
            buf: Vec::new(),
            created,
            earlier,
            offset: 0,
            last: None,
        })
    }

    /// For the daemon, which numbers its frames from 0 at every start: like [`LabelExport::create`],
    /// but an earlier session's label PNGs are kept and this session's frames numbered after
    /// them (a service restart must not overwrite the labels of the run before).
    pub fn append(dir: &Path) -> Result<Self> {
        let mut export = Self::open(dir)?;
        if export.earlier > 0 {
            export.offset = last_label_frame(dir)?.map_or(0, |i| i + 1);
            export.earlier = 0; // nothing of theirs is replaced or removed
            warn!(
                folder = %dir.display(),
                "keeping an earlier session's label PNGs: this session's frame 0 is written as {:06}",
                export.offset
            );
        }
        Ok(export)
    }

    /// Removes the earlier export's label PNGs numbered past this export's last frame.
    fn remove_stale(&self) -> Result<()> {
        let Some(last) = self.last else {
            return Ok(());
        };
        let entries =
            std::fs::read_dir(&self.dir).map_err(|e| Error::io(&self.dir, "reading folder", e))?;
        let mut removed = 0;
        for entry in entries.flatten() {
            if label_frame(&entry.file_name().to_string_lossy()).is_some_and(|i| i > last) {
                std::fs::remove_file(entry.path())
                    .map_err(|e| Error::io(entry.path(), "removing", e))?;
                removed += 1;
            }
        }
        if removed > 0 {
            info!(folder = %self.dir.display(), "removed {removed} label PNGs of the earlier export past frame {last}");
        }
        Ok(())
    }
}

/// How many SPEC §4 label PNGs `dir` holds; an error naming the first entry that is something
/// else.
fn earlier_labels(dir: &Path) -> Result<usize> {
    let entries = std::fs::read_dir(dir).map_err(|e| Error::io(dir, "reading folder", e))?;
    let mut labels = 0;
    for entry in entries {
        let entry = entry.map_err(|e| Error::io(dir, "reading folder", e))?;
        let name = entry.file_name();
        if label_frame(&name.to_string_lossy()).is_some() {
            labels += 1;
        } else {
            return Err(Error::input(
                dir,
                "",
                format!(
                    "holds {}, which is not a label PNG of an earlier export: exporting labels here would overwrite what it holds (a ground-truth folder, say); choose a new or empty folder",
                    name.to_string_lossy()
                ),
            ));
        }
    }
    Ok(labels)
}

/// The highest frame number among `dir`'s label PNGs, if any.
fn last_label_frame(dir: &Path) -> Result<Option<usize>> {
    let entries = std::fs::read_dir(dir).map_err(|e| Error::io(dir, "reading folder", e))?;
    Ok(entries
        .flatten()
        .filter_map(|e| label_frame(&e.file_name().to_string_lossy()))
        .max())
}

/// The frame number of a SPEC §4 label PNG's name (`<6 digits>.depth.png` or `.rgb.png`; more
/// digits past frame 999 999), or of such a file's `.part` left by an export that was killed
/// while writing it; `None` for any other name.
fn label_frame(name: &str) -> Option<usize> {
    let name = name.strip_suffix(".part").unwrap_or(name);
    let stem = name
        .strip_suffix(".depth.png")
        .or_else(|| name.strip_suffix(".rgb.png"))?;
    if stem.len() >= 6 && stem.bytes().all(|b| b.is_ascii_digit()) {
        stem.parse().ok()
    } else {
        None
    }
}

impl Drop for LabelExport {
    fn drop(&mut self) {
        if self.created {
            // Fails (and leaves it) unless the folder is empty.
            let _ = std::fs::remove_dir(&self.dir);
        }
    }
}

impl Sink for LabelExport {
    fn write(&mut self, frame: &Frame) -> Result<()> {
        let i = frame.seq as usize + self.offset;
        labels::write_label_png_with(
            &labels::label_path(&self.dir, i, "depth"),
            &frame.labels.ir_labels,
            &mut self.buf,
        )?;
        labels::write_label_png_with(
            &labels::label_path(&self.dir, i, "rgb"),
            &frame.labels.rgb_labels,
            &mut self.buf,
        )?;
        self.last = self.last.max(Some(i));
        Ok(())
    }

    fn finish(&mut self) -> Result<()> {
        if self.earlier > 0 {
            self.remove_stale()?;
        }
        Ok(())
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
