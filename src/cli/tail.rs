//! `umbra tail PATH [--follow] [--json] [--export-labels DIR] [--png DIR]`: print (and export)
//! the frames of MCAP segments, optionally following them while the daemon writes, like
//! `tail -F`: polling, resuming after the last complete chunk, moving on across rotation.

use std::io::Write;
use std::path::{Path, PathBuf};
use std::time::Duration;

use image::ImageEncoder;
use tracing::{info, warn};

use crate::calib::Calibration;
use crate::error::{Error, Result};
use crate::labels::{ALIGNMENT, CLASSES, NAMES, VALID};
use crate::render::render_panels;
use crate::sink::labels::write_atomically;
use crate::sink::mcap::read::{torn_warning, End, Recorded, SegmentReader};
use crate::sink::mcap::segment::{list_segments, segment_key};
use crate::sink::mcap::stats::ClassCounts;
use crate::sink::{LabelExport, Sink};

/// Arguments of `umbra tail`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// An MCAP segment, or the output folder (all its umbra-*.mcap, oldest first).
    pub path: PathBuf,
    /// Keep reading as frames are appended and new segments appear (Ctrl-C stops).
    #[arg(short, long)]
    pub follow: bool,
    /// Print one JSON object per frame instead of a line of text.
    #[arg(long)]
    pub json: bool,
    /// Write SPEC §4 label PNGs (<seq:06>.depth.png, <seq:06>.rgb.png) into this folder.
    #[arg(long, value_name = "DIR")]
    pub export_labels: Option<PathBuf>,
    /// Write a picture per frame (<seq:06>.png: RGB | IR-view labels | RGB-view labels).
    #[arg(long, value_name = "DIR")]
    pub png: Option<PathBuf>,
    /// How often --follow looks for new data, milliseconds.
    #[arg(long, default_value_t = 200, value_name = "MS")]
    pub poll_ms: u64,
}

/// Runs `umbra tail`.
pub fn run(a: Args) -> Result<()> {
    let mut out = Output::new(&a)?;
    let result = if a.path.is_dir() {
        tail_folder(&a, &mut out)
    } else if a.path.is_file() {
        tail_file(&a, &mut out)
    } else {
        Err(Error::input(&a.path, "", "no such segment or folder: expected an umbra-*.mcap file or the folder `umbra run` writes"))
    };
    match result {
        // Whoever read our output went away (`umbra tail ... | head`): not an error.
        Err(_) if out.closed => Ok(()),
        // Read to the end: an earlier export's frames past the last one read go (SPEC §4).
        Ok(()) => match &mut out.labels {
            Some(labels) => labels.finish(),
            None => Ok(()),
        },
        r => r,
    }
}

fn tail_file(a: &Args, out: &mut Output) -> Result<()> {
    let mut reader = SegmentReader::new(&a.path);
    loop {
        match reader.poll(&mut |r| out.frame(r))? {
            End::Complete => return Ok(()),
            end if !a.follow => {
                report_end(&reader, end);
                return Ok(());
            }
            _ => std::thread::sleep(Duration::from_millis(a.poll_ms)),
        }
    }
}

fn tail_folder(a: &Args, out: &mut Output) -> Result<()> {
    let dir = &a.path;
    let key = |p: &Path| p.file_name().and_then(|n| n.to_str()).and_then(segment_key);
    // The last segment read to its end: the next one is the first with a larger key.
    let mut done: Option<(String, u64)> = None;
    let mut current: Option<SegmentReader> = None;
    loop {
        let segments = list_segments(dir)?;
        let reader = match current.as_mut() {
            Some(r) => r,
            None => match segments.iter().map(|(p, _)| p).find(|p| key(p) > done) {
                Some(p) => current.insert(SegmentReader::new(p)),
                None if a.follow => {
                    std::thread::sleep(Duration::from_millis(a.poll_ms));
                    continue;
                }
                None => return Ok(()),
            },
        };
        let this = key(reader.path());
        // Checked before reading: the writer opens a new segment only after it stopped writing
        // this one, so if a newer one exists now, what this poll reads is all there will be.
        let superseded = segments.iter().any(|(p, _)| key(p) > this);
        let end = match reader.poll(&mut |r| out.frame(r)) {
            Ok(end) => end,
            Err(Error::Io { source, .. })
                if source.kind() == std::io::ErrorKind::NotFound && !out.closed =>
            {
                warn!(
                    "{}: deleted before it was read to its end (output size cap?)",
                    reader.path().display()
                );
                End::Complete
            }
            Err(e) => return Err(e),
        };
        if end == End::Complete || !a.follow || superseded {
            report_end(reader, end);
            done = this;
            current = None;
        } else {
            std::thread::sleep(Duration::from_millis(a.poll_ms));
        }
    }
}

/// Says how a segment ended when it is left for good.
fn report_end(reader: &SegmentReader, end: End) {
    match end {
        End::Torn { offset, tail } => warn!("{}", torn_warning(reader.path(), offset, tail)),
        End::Open => info!(
            "{}: ends without its summary (still being written, or its writer stopped)",
            reader.path().display()
        ),
        End::Complete => {}
    }
}

/// Where frames go: stdout (a line or JSON), label PNGs, pictures.
struct Output {
    stdout: std::io::BufWriter<std::io::Stdout>,
    json: bool,
    labels: Option<LabelExport>,
    png: Option<PathBuf>,
    /// Calibration for the depth greys of pictures: MCAP segments do not carry one, so the
    /// default Kinect v1 model (SPEC §1) shades them; labels are unaffected.
    calib: Calibration,
    png_buf: Vec<u8>,
    /// Set when stdout was closed by the reader.
    closed: bool,
}

impl Output {
    fn new(a: &Args) -> Result<Self> {
        let labels = a
            .export_labels
            .as_deref()
            .map(LabelExport::create)
            .transpose()?;
        if let Some(dir) = &a.png {
            if dir.exists() && !dir.is_dir() {
                return Err(Error::input(
                    dir,
                    "",
                    "exists and is not a folder: --png needs a folder to write <seq>.png into",
                ));
            }
            std::fs::create_dir_all(dir).map_err(|e| Error::io(dir, "creating folder", e))?;
        }
        let stdout = std::io::BufWriter::new(std::io::stdout());
        Ok(Output {
            stdout,
            json: a.json,
            labels,
            png: a.png.clone(),
            calib: Calibration::nyu_default(),
            png_buf: Vec::new(),
            closed: false,
        })
    }

    fn frame(&mut self, r: Recorded) -> Result<()> {
        if let Some(labels) = &mut self.labels {
            labels.write(&r.frame)?;
        }
        if let Some(dir) = &self.png {
            let f = &r.frame;
            let img = render_panels(
                f.has_rgb.then_some(f.rgb.as_slice()),
                &f.depth,
                &self.calib,
                &f.labels,
            );
            let path = dir.join(format!("{:06}.png", f.seq));
            self.png_buf.clear();
            image::codecs::png::PngEncoder::new(&mut self.png_buf)
                .write_image(
                    img.as_raw(),
                    img.width(),
                    img.height(),
                    image::ExtendedColorType::Rgb8,
                )
                .map_err(|e| Error::input(&path, "", format!("encoding PNG failed: {e}")))?;
            write_atomically(&path, &self.png_buf)?;
        }
        let line = if self.json {
            serde_json::to_string(&r.stats).expect("stats serialise to JSON")
        } else {
            human_line(&r)
        };
        // Flushed per frame so that a pipe (`| jq`) sees frames as they come in --follow.
        let written = writeln!(self.stdout, "{line}").and_then(|_| self.stdout.flush());
        written.map_err(|e| {
            self.closed = e.kind() == std::io::ErrorKind::BrokenPipe;
            Error::io("<stdout>", "writing", e)
        })
    }
}

/// `seq 12  ts 4096  t 1795349700.123  latency 3.2 ms  dropped 0  ir: attached 1.20% ...`
fn human_line(r: &Recorded) -> String {
    let s = &r.stats;
    let mut line = format!(
        "seq {}  ts {}  t {:.3}  latency {:.1} ms  dropped {}",
        s.seq, s.device_ts, s.unix_time, s.latency_ms, s.dropped_before
    );
    for (view, counts) in [("ir", &s.ir), ("rgb", &s.rgb)] {
        line.push_str(&format!("  {view}:"));
        line.push_str(&shares(view, counts));
    }
    line
}

/// Share of each hole class (valid pixels and, in the IR view, alignment are left out).
fn shares(view: &str, counts: &ClassCounts) -> String {
    let total = counts.0.iter().sum::<u64>().max(1) as f64;
    (0..CLASSES)
        .filter(|&c| c != VALID as usize && !(view == "ir" && c == ALIGNMENT as usize))
        .map(|c| format!(" {} {:.2}%", NAMES[c], 100.0 * counts.0[c] as f64 / total))
        .collect()
}
