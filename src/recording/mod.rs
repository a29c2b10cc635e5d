//! Reading recordings in libfreenect's fakenect folder format (SPEC §3).
//!
//! `Recording::open` checks the whole INDEX.txt up front (names, order of fields, files present) so
//! that a long replay never dies half way on a typo; frame files are read on demand into
//! caller-owned buffers so the pipeline can recycle them.

pub mod device_json;
pub mod pnm;
pub mod writer;

use std::path::{Path, PathBuf};

use crate::calib::Calibration;
use crate::error::{Error, Result};

/// Which stream an INDEX.txt entry belongs to.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Stream {
    /// `d-*.pgm`: 11-bit depth.
    Depth,
    /// `r-*.ppm`: RGB.
    Rgb,
    /// `a-*.dump`: accelerometer state.
    Accel,
}

/// One line of INDEX.txt, parsed from `%c-%f-%u.%s`.
#[derive(Clone, Debug, PartialEq)]
pub struct Entry {
    /// The stream.
    pub stream: Stream,
    /// Host time the frame was received, seconds since the epoch.
    pub unix_time: f64,
    /// The device's 32-bit frame timestamp (wraps).
    pub device_ts: u32,
    /// File name as written in INDEX.txt.
    pub name: String,
    /// 1-based line number in INDEX.txt, for error messages.
    pub line: usize,
}

/// A depth frame and the RGB frame paired with it.
#[derive(Clone, Debug)]
pub struct Frame {
    /// 0-based frame index among the depth lines (SPEC §3).
    pub index: usize,
    /// The depth entry.
    pub depth: Entry,
    /// The RGB entry nearest in time, if the recording has RGB.
    pub rgb: Option<Entry>,
}

/// Where a recording's calibration came from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CalibrationSource {
    /// The recording's `calibration.toml`.
    File,
    /// Derived from the recording's `device.json` (libfreenect's registration record).
    DeviceJson,
    /// NYU Kinect v1 defaults.
    Default,
}

/// An opened, validated recording.
#[derive(Clone, Debug)]
pub struct Recording {
    dir: PathBuf,
    frames: Vec<Frame>,
    calibration: Calibration,
    calibration_source: CalibrationSource,
    /// The first accelerometer file INDEX.txt names that is absent: its line and name.
    missing_accel: Option<(usize, String)>,
}

impl Recording {
    /// Opens a recording folder: parses INDEX.txt, checks every named depth and RGB file exists
    /// (missing accelerometer files are only warned about), pairs RGB with depth and loads the
    /// calibration (`calibration.toml`, else `device.json`, else defaults).
    pub fn open(dir: &Path) -> Result<Self> {
        if !dir.is_dir() {
            return Err(Error::input(
                dir,
                "",
                "not a recording folder (expected a folder with INDEX.txt)",
            ));
        }
        let index_path = dir.join("INDEX.txt");
        let text = match std::fs::read(&index_path) {
            Ok(b) => String::from_utf8(b).map_err(|e| {
                Error::input(
                    &index_path,
                    format!("byte {}", e.utf8_error().valid_up_to()),
                    "not UTF-8 text",
                )
            })?,
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
                return Err(Error::input(
                    &index_path,
                    "",
                    "missing: a fakenect recording needs INDEX.txt listing its frames",
                ))
            }
            Err(e) => return Err(Error::io(&index_path, "reading", e)),
        };
        let entries = parse_index(&index_path, &text)?;
        let mut missing_accel: Vec<&Entry> = Vec::new();
        for e in &entries {
            let file = dir.join(&e.name);
            if !file.is_file() {
                // umbra never reads accelerometer dumps: a lost one costs nothing.
                if e.stream == Stream::Accel {
                    missing_accel.push(e);
                    continue;
                }
                let why = if file.exists() {
                    "is not a regular file"
                } else {
                    "does not exist"
                };
                return Err(Error::input(
                    &index_path,
                    format!("line {}", e.line),
                    format!("names {} which {why} in {}", e.name, dir.display()),
                ));
            }
        }
        warn_missing_accel(&index_path, &missing_accel);
        let missing_accel = missing_accel.first().map(|e| (e.line, e.name.clone()));
        let frames = pair_frames(&entries);
        if frames.is_empty() {
            return Err(Error::input(
                &index_path,
                "",
                "lists no depth frame (d-*.pgm)",
            ));
        }
        let (calibration, calibration_source) = load_calibration(dir)?;
        Ok(Recording {
            dir: dir.to_path_buf(),
            frames,
            calibration,
            calibration_source,
            missing_accel,
        })
    }

    /// The recording folder.
    pub fn dir(&self) -> &Path {
        &self.dir
    }

    /// Depth frames in order, each with its paired RGB frame.
    pub fn frames(&self) -> &[Frame] {
        &self.frames
    }

    /// Number of depth frames.
    pub fn len(&self) -> usize {
        self.frames.len()
    }

    /// True when the recording has no depth frame (never, for an opened recording).
    pub fn is_empty(&self) -> bool {
        self.frames.is_empty()
    }

    /// Depth frames with no RGB frame within [`MAX_RGB_GAP_S`]: those are classified from depth
    /// alone.
    pub fn frames_without_rgb(&self) -> usize {
        self.frames.iter().filter(|f| f.rgb.is_none()).count()
    }

    /// Warns (tracing) when depth frames have no RGB frame to pair with, which costs them the
    /// colour split: a user replaying a recording whose colour stream stopped should know.
    fn warn_missing_rgb(&self) {
        let (missing, n) = (self.frames_without_rgb(), self.len());
        if missing == n {
            tracing::warn!(
                "{}: no RGB frames: classified from depth alone (occluders that return no depth are not split off their shadows)",
                self.dir.display()
            );
        } else if missing > 0 {
            tracing::warn!(
                "{}: {missing} of {n} depth frames have no RGB frame within {} ms: those are classified from depth alone",
                self.dir.display(),
                (MAX_RGB_GAP_S * 1e3).round()
            );
        }
    }

    /// Warns (tracing) when the first depth frame does not look like what the raw model of
    /// [`Recording::calibration`] describes: raw 0 (a Kinect v1's 11-bit stream never sends it,
    /// a millimetre stream's "no depth" is 0) or values past the model's zero disparity (which
    /// it maps to no depth). Either way the labels would be quietly wrong.
    fn warn_implausible_depth(&self) {
        let mut raw = vec![0u16; crate::labels::PIXELS];
        if self.read_depth(0, &mut raw).is_err() {
            return; // The frame's own error comes when it is classified.
        }
        let den = self.calibration.raw.denominator;
        let zero = raw.iter().filter(|&&r| r == 0).count();
        let beyond = raw
            .iter()
            .filter(|&&r| r != crate::labels::NO_DEPTH && f64::from(r) >= den - 0.5)
            .count();
        let share = |n: usize| 100.0 * n as f64 / raw.len() as f64;
        if share(zero) > 1.0 {
            tracing::warn!(
                "{}: {:.0}% of the first depth frame's pixels are 0, which a Kinect v1's 11-bit stream never sends: is this a millimetre (FREENECT_DEPTH_MM or registered) recording? umbra needs FREENECT_DEPTH_11BIT",
                self.dir.display(),
                share(zero)
            );
        }
        if share(beyond) > 5.0 {
            tracing::warn!(
                "{}: {:.0}% of the first depth frame's pixels are at or past the raw model's zero disparity ({den}), which it reads as no depth: check [raw] in the calibration",
                self.dir.display(),
                share(beyond)
            );
        }
    }

    /// Warns (tracing) about what makes this recording's labels poorer or doubtful before any
    /// frame is classified: depth frames without RGB, depth the raw model cannot read.
    pub fn warn_doubts(&self) {
        self.warn_missing_rgb();
        self.warn_implausible_depth();
    }

    /// The calibration to classify with.
    pub fn calibration(&self) -> &Calibration {
        &self.calibration
    }

    /// Where [`Recording::calibration`] came from.
    pub fn calibration_source(&self) -> CalibrationSource {
        self.calibration_source
    }

    /// The first accelerometer file INDEX.txt names that does not exist (its line and name):
    /// umbra's reader ignores it, libfreenect's fakenect exits on it.
    pub fn missing_accelerometer_file(&self) -> Option<(usize, &str)> {
        self.missing_accel.as_ref().map(|(l, n)| (*l, n.as_str()))
    }

    /// Reads depth frame `i` into `out` (640·480 raw values).
    pub fn read_depth(&self, i: usize, out: &mut [u16]) -> Result<()> {
        self.read_depth_with(i, &mut Vec::new(), out)
    }

    /// [`Recording::read_depth`] reusing `scratch` for the file's bytes.
    pub fn read_depth_with(&self, i: usize, scratch: &mut Vec<u8>, out: &mut [u16]) -> Result<()> {
        pnm::read_depth_with(&self.dir.join(&self.frames[i].depth.name), scratch, out)
    }

    /// Reads the RGB frame paired with depth frame `i` into `out`; `Ok(false)` if there is none.
    pub fn read_rgb(&self, i: usize, out: &mut [u8]) -> Result<bool> {
        self.read_rgb_with(i, &mut Vec::new(), out)
    }

    /// [`Recording::read_rgb`] reusing `scratch` for the file's bytes.
    pub fn read_rgb_with(&self, i: usize, scratch: &mut Vec<u8>, out: &mut [u8]) -> Result<bool> {
        match &self.frames[i].rgb {
            Some(e) => pnm::read_rgb_with(&self.dir.join(&e.name), scratch, out).map(|_| true),
            None => Ok(false),
        }
    }
}

/// Warns, once for the recording, about accelerometer files INDEX.txt names but that are absent.
fn warn_missing_accel(index_path: &Path, missing: &[&Entry]) {
    let Some(first) = missing.first() else {
        return;
    };
    let what = match missing.len() {
        1 => format!("names {} which is missing", first.name),
        n => format!(
            "names {n} missing accelerometer files, the first {}",
            first.name
        ),
    };
    tracing::warn!(
        "{}: line {}: {what}; ignored, as umbra does not read accelerometer data",
        index_path.display(),
        first.line
    );
}

/// What every INDEX.txt line must be, for error messages.
const INDEX_LINE: &str = "expected d-<unix_time>-<device_ts>.pgm, r-….ppm or a-….dump";

/// Parses INDEX.txt; blank lines are skipped, anything else must be a fakenect frame name.
/// A leading UTF-8 byte-order mark (Windows editors add one) is ignored.
pub fn parse_index(path: &Path, text: &str) -> Result<Vec<Entry>> {
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let mut out = Vec::new();
    for (i, raw_line) in text.lines().enumerate() {
        let line = raw_line.trim();
        if line.is_empty() {
            continue;
        }
        if line.starts_with('#') {
            return Err(Error::input(
                path,
                format!("line {}", i + 1),
                format!("'{line}': comment lines are not part of fakenect's INDEX.txt format; {INDEX_LINE}"),
            ));
        }
        let entry = parse_name(line, i + 1).map_err(|why| {
            Error::input(
                path,
                format!("line {}", i + 1),
                format!("'{line}' {why}; {INDEX_LINE}"),
            )
        })?;
        out.push(entry);
    }
    Ok(out)
}

fn parse_name(name: &str, line: usize) -> std::result::Result<Entry, &'static str> {
    if name.contains('/') || name.contains('\\') {
        return Err("is a path, not a file name");
    }
    let (stem, ext) = name.rsplit_once('.').ok_or("has no extension")?;
    let mut parts = stem.splitn(3, '-');
    let kind = parts.next().ok_or("is empty")?;
    let time = parts.next().ok_or("has no time field")?;
    let ts = parts.next().ok_or("has no device timestamp field")?;
    let stream = match (kind, ext) {
        ("d", "pgm") => Stream::Depth,
        ("r", "ppm") => Stream::Rgb,
        ("a", "dump") => Stream::Accel,
        ("d" | "r" | "a", _) => return Err("has the wrong extension for its stream"),
        _ => return Err("does not start with d-, r- or a-"),
    };
    let unix_time: f64 = time
        .parse()
        .map_err(|_| "has a time field that is not a number")?;
    if !unix_time.is_finite() || unix_time < 0.0 {
        return Err("has a negative or non-finite time");
    }
    let device_ts: u32 = ts
        .parse()
        .map_err(|_| "has a device timestamp that is not a 32-bit unsigned number")?;
    Ok(Entry {
        stream,
        unix_time,
        device_ts,
        name: name.to_string(),
        line,
    })
}

/// An RGB frame further than this from a depth frame (host time, seconds) is not its pair: the
/// colour stream stopped or dropped frames, and a stale image would misplace every colour edge.
/// The live source holds to the same, so a replay pairs as the daemon did.
pub const MAX_RGB_GAP_S: f64 = 0.1;

/// Pairs each depth entry with the RGB entry nearest in host time, if one is within
/// [`MAX_RGB_GAP_S`].
fn pair_frames(entries: &[Entry]) -> Vec<Frame> {
    let mut rgb: Vec<&Entry> = entries.iter().filter(|e| e.stream == Stream::Rgb).collect();
    rgb.sort_by(|a, b| a.unix_time.total_cmp(&b.unix_time));
    entries
        .iter()
        .filter(|e| e.stream == Stream::Depth)
        .enumerate()
        .map(|(index, d)| {
            let at = rgb.partition_point(|r| r.unix_time < d.unix_time);
            let best = [at.checked_sub(1), Some(at)]
                .into_iter()
                .flatten()
                .filter_map(|k| rgb.get(k))
                .filter(|r| (r.unix_time - d.unix_time).abs() <= MAX_RGB_GAP_S)
                .min_by(|a, b| {
                    (a.unix_time - d.unix_time)
                        .abs()
                        .total_cmp(&(b.unix_time - d.unix_time).abs())
                });
            Frame {
                index,
                depth: d.clone(),
                rgb: best.map(|e| (*e).clone()),
            }
        })
        .collect()
}

fn load_calibration(dir: &Path) -> Result<(Calibration, CalibrationSource)> {
    let toml_path = dir.join("calibration.toml");
    if toml_path.exists() {
        return Ok((Calibration::load(&toml_path)?, CalibrationSource::File));
    }
    let json_path = dir.join("device.json");
    if json_path.exists() {
        match device_json::load(&json_path)? {
            Some(c) => return Ok((c, CalibrationSource::DeviceJson)),
            None => tracing::warn!(
                "{}: reg_info.zero_plane_info is all zero (the device reported no registration data): using the NYU Kinect v1 default calibration",
                json_path.display()
            ),
        }
    }
    Ok((Calibration::nyu_default(), CalibrationSource::Default))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_fakenect_names() {
        let e = parse_index(
            Path::new("INDEX.txt"),
            "d-1316653580.471513-1316138413.pgm\n\nr-1.5-7.ppm\na-2.0-9.dump\n",
        )
        .unwrap();
        assert_eq!(e.len(), 3);
        assert_eq!(e[0].stream, Stream::Depth);
        assert_eq!(e[0].device_ts, 1316138413);
        assert!((e[0].unix_time - 1316653580.471513).abs() < 1e-6);
        assert_eq!(e[1].line, 3);
    }

    #[test]
    fn bad_lines_name_the_line() {
        let err = parse_index(Path::new("rec/INDEX.txt"), "d-1.0-2.pgm\nx-1-2.pgm\n")
            .unwrap_err()
            .to_string();
        assert!(
            err.starts_with("rec/INDEX.txt: line 2: 'x-1-2.pgm'"),
            "{err}"
        );
        let err = parse_index(Path::new("I"), "d-1.0-99999999999.pgm\n")
            .unwrap_err()
            .to_string();
        assert!(err.contains("32-bit"), "{err}");
    }

    #[test]
    fn a_leading_byte_order_mark_is_ignored() {
        let e = parse_index(Path::new("I"), "\u{feff}d-1.0-2.pgm\r\nr-1.01-3.ppm\r\n").unwrap();
        assert_eq!(e.len(), 2);
        assert_eq!((e[0].name.as_str(), e[0].line), ("d-1.0-2.pgm", 1));
    }

    #[test]
    fn comment_lines_are_named_as_such() {
        let err = parse_index(Path::new("rec/INDEX.txt"), "d-1.0-2.pgm\n# by hand\n")
            .unwrap_err()
            .to_string();
        assert_eq!(
            err,
            "rec/INDEX.txt: line 2: '# by hand': comment lines are not part of fakenect's INDEX.txt format; expected d-<unix_time>-<device_ts>.pgm, r-….ppm or a-….dump"
        );
    }

    /// A recording of `index` lines in a fresh folder, with every `d-` file written.
    fn recording(index: &str) -> tempfile::TempDir {
        let dir = tempfile::tempdir().unwrap();
        for name in index.lines().filter(|l| l.starts_with("d-")) {
            pnm::write_depth(&dir.path().join(name), &vec![800; crate::labels::PIXELS]).unwrap();
        }
        std::fs::write(dir.path().join("INDEX.txt"), index).unwrap();
        dir
    }

    /// Runs `f` and returns what it logged (tracing, plain text).
    fn logged<T>(f: impl FnOnce() -> T) -> (T, String) {
        #[derive(Clone, Default)]
        struct Buf(std::sync::Arc<std::sync::Mutex<Vec<u8>>>);
        impl std::io::Write for Buf {
            fn write(&mut self, b: &[u8]) -> std::io::Result<usize> {
                self.0.lock().unwrap().extend_from_slice(b);
                Ok(b.len())
            }
            fn flush(&mut self) -> std::io::Result<()> {
                Ok(())
            }
        }
        let buf = Buf::default();
        let writer = buf.clone();
        let subscriber = tracing_subscriber::fmt()
            .with_writer(move || writer.clone())
            .with_ansi(false)
            .finish();
        let out = tracing::subscriber::with_default(subscriber, f);
        let text = String::from_utf8(buf.0.lock().unwrap().clone()).unwrap();
        (out, text)
    }

    #[test]
    fn missing_accelerometer_files_are_warned_about_once() {
        let dir = recording("a-0.9-1.dump\nd-1.0-2.pgm\na-1.1-3.dump\nd-1.2-4.pgm\n");
        let (rec, log) = logged(|| Recording::open(dir.path()));
        let rec = rec.unwrap();
        let mut depth = vec![0u16; crate::labels::PIXELS];
        for i in 0..rec.len() {
            rec.read_depth(i, &mut depth).unwrap();
        }
        assert_eq!((rec.len(), depth[0]), (2, 800));
        assert_eq!(log.lines().count(), 1, "{log}");
        assert!(
            log.contains("WARN")
                && log.contains("INDEX.txt: line 1: names 2 missing accelerometer files, the first a-0.9-1.dump; ignored"),
            "{log}"
        );
        // A missing depth file stays an error.
        std::fs::remove_file(dir.path().join("d-1.2-4.pgm")).unwrap();
        let err = Recording::open(dir.path()).unwrap_err().to_string();
        assert!(
            err.contains("line 4: names d-1.2-4.pgm which does not exist"),
            "{err}"
        );
    }

    #[test]
    fn device_json_without_registration_data_means_default_calibration() {
        let dir = recording("d-1.0-2.pgm\n");
        std::fs::write(
            dir.path().join("device.json"),
            r#"{"reg_info":{"zero_plane_info":{"dcmos_emitter_distance":0,"dcmos_rcmos_distance":0,
            "reference_distance":0,"reference_pixel_size":0}},"const_shift":0}"#,
        )
        .unwrap();
        let (rec, log) = logged(|| Recording::open(dir.path()));
        let rec = rec.unwrap();
        assert_eq!(rec.calibration_source(), CalibrationSource::Default);
        assert_eq!(*rec.calibration(), Calibration::nyu_default());
        rec.read_depth(0, &mut vec![0u16; crate::labels::PIXELS])
            .unwrap();
        assert!(
            log.contains("WARN")
                && log.contains("device.json: reg_info.zero_plane_info is all zero"),
            "{log}"
        );
    }

    #[test]
    fn pairs_nearest_rgb_by_time() {
        let e = parse_index(
            Path::new("I"),
            "r-0.0-0.ppm\nd-0.04-1.pgm\nr-0.033-2.ppm\nd-0.07-3.pgm\nr-0.1-4.ppm\n",
        )
        .unwrap();
        let f = pair_frames(&e);
        assert_eq!(f.len(), 2);
        assert_eq!(f[0].rgb.as_ref().unwrap().device_ts, 2);
        assert_eq!(f[1].rgb.as_ref().unwrap().device_ts, 4);
    }

    #[test]
    fn a_stale_rgb_frame_is_no_pair() {
        // The colour stream stopped after its first frame: the depth frames 0.15 s and 1 s on
        // get none, the one 0.05 s on still pairs.
        let e = parse_index(
            Path::new("I"),
            "r-10.0-0.ppm\nd-10.05-1.pgm\nd-10.15-2.pgm\nd-11.0-3.pgm\n",
        )
        .unwrap();
        let f = pair_frames(&e);
        assert_eq!(f[0].rgb.as_ref().unwrap().device_ts, 0);
        assert!(f[1].rgb.is_none() && f[2].rgb.is_none());
    }
}
