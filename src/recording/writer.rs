//! Writes a recording in the fakenect format (SPEC §3), frame by frame, so that a recording cut
//! short (crash, power loss, Ctrl-C) is still a valid recording of the frames before the cut:
//! every frame file is complete before its line is appended to INDEX.txt.

use std::fs::File;
use std::io::Write;
use std::path::{Path, PathBuf};

use crate::calib::Calibration;
use crate::error::{Error, Result};
use crate::recording::pnm;

/// An open recording folder being written.
#[derive(Debug)]
pub struct RecordingWriter {
    dir: PathBuf,
    index: File,
    index_path: PathBuf,
    depth_frames: u64,
    rgb_frames: u64,
}

impl RecordingWriter {
    /// Creates `dir` (and parents). An existing folder must be empty: a recording is never
    /// mixed into another one.
    pub fn create(dir: &Path) -> Result<Self> {
        if dir.exists() {
            if !dir.is_dir() {
                return Err(Error::input(
                    dir,
                    "",
                    "exists and is not a folder: give a new folder for the recording",
                ));
            }
            let mut entries =
                std::fs::read_dir(dir).map_err(|e| Error::io(dir, "reading folder", e))?;
            if entries.next().is_some() {
                return Err(Error::input(
                    dir,
                    "",
                    "is not empty: give a new or empty folder for the recording",
                ));
            }
        }
        std::fs::create_dir_all(dir).map_err(|e| Error::io(dir, "creating folder", e))?;
        let index_path = dir.join("INDEX.txt");
        let index = File::options()
            .create_new(true)
            .append(true)
            .open(&index_path)
            .map_err(|e| Error::io(&index_path, "creating", e))?;
        Ok(RecordingWriter {
            dir: dir.to_path_buf(),
            index,
            index_path,
            depth_frames: 0,
            rgb_frames: 0,
        })
    }

    /// The recording folder.
    pub fn dir(&self) -> &Path {
        &self.dir
    }

    /// Depth and RGB frames written so far.
    pub fn counts(&self) -> (u64, u64) {
        (self.depth_frames, self.rgb_frames)
    }

    /// Writes one 640×480 11-bit depth frame received at `unix_time` with device timestamp `ts`.
    pub fn write_depth(&mut self, unix_time: f64, ts: u32, depth: &[u16]) -> Result<()> {
        let name = file_name('d', unix_time, ts, "pgm");
        pnm::write_depth(&self.dir.join(&name), depth)?;
        self.append(&name)?;
        self.depth_frames += 1;
        Ok(())
    }

    /// Writes one 640×480 RGB frame received at `unix_time` with device timestamp `ts`.
    pub fn write_rgb(&mut self, unix_time: f64, ts: u32, rgb: &[u8]) -> Result<()> {
        let name = file_name('r', unix_time, ts, "ppm");
        pnm::write_rgb(&self.dir.join(&name), rgb)?;
        self.append(&name)?;
        self.rgb_frames += 1;
        Ok(())
    }

    /// Writes `calibration.toml` and flushes INDEX.txt to the disk.
    pub fn finish(self, calibration: &Calibration) -> Result<()> {
        let path = self.dir.join("calibration.toml");
        std::fs::write(&path, calibration.to_toml_string())
            .map_err(|e| Error::io(&path, "writing", e))?;
        self.index
            .sync_all()
            .map_err(|e| Error::io(&self.index_path, "flushing", e))
    }

    fn append(&mut self, name: &str) -> Result<()> {
        writeln!(self.index, "{name}").map_err(|e| Error::io(&self.index_path, "appending to", e))
    }
}

/// libfreenect's `%c-%f-%u.%s` file name.
pub fn file_name(kind: char, unix_time: f64, ts: u32, ext: &str) -> String {
    format!("{kind}-{unix_time:.6}-{ts}.{ext}")
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::labels::PIXELS;
    use crate::recording::Recording;

    #[test]
    fn a_written_recording_reads_back_and_names_follow_fakenect() {
        assert_eq!(
            file_name('d', 1316653580.471513, 1316138413, "pgm"),
            "d-1316653580.471513-1316138413.pgm"
        );
        let tmp = tempfile::tempdir().unwrap();
        let dir = tmp.path().join("rec");
        let mut w = RecordingWriter::create(&dir).unwrap();
        let depth: Vec<Vec<u16>> = (0..3)
            .map(|k| (0..PIXELS).map(|i| ((i * 7 + k) % 2048) as u16).collect())
            .collect();
        let rgb: Vec<u8> = (0..PIXELS * 3).map(|i| (i % 251) as u8).collect();
        for (k, d) in depth.iter().enumerate() {
            let t = 1.8e9 + k as f64 / 30.0;
            w.write_depth(
                t,
                (u32::MAX - 1_000_000).wrapping_add(2_000_000 * k as u32),
                d,
            )
            .unwrap();
            w.write_rgb(t + 0.002, 7 + k as u32, &rgb).unwrap();
        }
        assert_eq!(w.counts(), (3, 3));
        let calib = Calibration::nyu_default();
        w.finish(&calib).unwrap();
        let rec = Recording::open(&dir).unwrap();
        assert_eq!(rec.len(), 3);
        assert_eq!(*rec.calibration(), calib);
        let mut back = vec![0u16; PIXELS];
        for (k, d) in depth.iter().enumerate() {
            rec.read_depth_with(k, &mut Vec::new(), &mut back).unwrap();
            assert!(back == *d, "depth frame {k}");
        }
        assert_eq!(
            rec.frames()[2].depth.device_ts,
            (u32::MAX - 1_000_000).wrapping_add(4_000_000),
            "timestamps wrap as the device's do"
        );
        assert!(RecordingWriter::create(&dir)
            .unwrap_err()
            .to_string()
            .contains("is not empty"));
    }
}
