//! `umbra render`: draws one classified frame as a PNG (see [`crate::render`]).

use std::path::{Path, PathBuf};

use image::ImageEncoder;

use crate::classify::{Classified, Classifier};
use crate::error::{Error, Result};
use crate::labels::PIXELS;
use crate::recording::Recording;
use crate::render::{render_panels, render_with_truth, Truth};
use crate::sink::labels::write_atomically;
use crate::sink::labels::{check_truth_dir, label_path, read_ir_label_png, read_label_png};

/// Arguments of `umbra render`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// The recording folder (with INDEX.txt).
    pub recording: PathBuf,
    /// 0-based depth frame index (SPEC §3).
    #[arg(long, value_name = "N", default_value_t = 0)]
    pub frame: usize,
    /// The PNG to write.
    #[arg(long, value_name = "FILE.png")]
    pub out: PathBuf,
    /// Settings file (see config/umbra.toml); built-in defaults without it.
    #[arg(long, value_name = "FILE")]
    pub config: Option<PathBuf>,
    /// Ground truth (SPEC §4 label PNGs, as `umbra eval --gt` reads them): adds a row with the
    /// IR view's ground truth and where each view's labels differ from it.
    #[arg(long, value_name = "DIR")]
    pub gt: Option<PathBuf>,
}

/// Runs `umbra render`.
pub fn run(a: Args) -> Result<()> {
    let params = crate::config::Config::load_or_default(a.config.as_deref())?.params();
    check_png_name(&a.out)?;
    let rec = Recording::open(&a.recording)?;
    if a.frame >= rec.len() {
        let n = rec.len();
        let valid = if n == 1 {
            "only --frame 0 exists".to_string()
        } else {
            format!("use --frame 0 to {}", n - 1)
        };
        return Err(Error::Usage(format!(
            "frame {} is out of range: {} has {n} depth frame{} ({valid})",
            a.frame,
            a.recording.display(),
            if n == 1 { "" } else { "s" },
        )));
    }
    // Ground truth first: a missing or bad file fails before any work.
    let truth = match &a.gt {
        Some(dir) => Some(read_truth(dir, a.frame)?),
        None => None,
    };
    let mut raw = vec![0u16; PIXELS];
    rec.read_depth(a.frame, &mut raw)?;
    let mut rgb = vec![0u8; PIXELS * 3];
    let has_rgb = rec.read_rgb(a.frame, &mut rgb)?;
    let mut out = Classified::default();
    Classifier::with_params(rec.calibration(), params).classify_with_rgb(
        &raw,
        has_rgb.then_some(&rgb[..]),
        &mut out,
    );
    let colour = has_rgb.then_some(&rgb[..]);
    let img = match &truth {
        Some((ir, rgb_view)) => {
            let truth = Truth {
                ir: ir.as_deref(),
                rgb: rgb_view.as_deref(),
            };
            render_with_truth(colour, &raw, rec.calibration(), &out, truth)
        }
        None => render_panels(colour, &raw, rec.calibration(), &out),
    };

    let mut png = Vec::new();
    image::codecs::png::PngEncoder::new(&mut png)
        .write_image(
            img.as_raw(),
            img.width(),
            img.height(),
            image::ExtendedColorType::Rgb8,
        )
        .map_err(|e| Error::input(&a.out, "", format!("encoding PNG failed: {e}")))?;
    // Like --export-labels, a folder that does not exist yet is made.
    if let Some(parent) = a.out.parent().filter(|p| !p.as_os_str().is_empty()) {
        std::fs::create_dir_all(parent).map_err(|e| Error::io(parent, "creating folder", e))?;
    }
    write_atomically(&a.out, &png)
}

/// The picture is a PNG whatever the name says, so a name that says otherwise (`x.jpg`, no
/// extension) is refused before any work rather than written with the wrong contents.
fn check_png_name(out: &Path) -> Result<()> {
    let is_png = out
        .extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| e.eq_ignore_ascii_case("png"));
    if is_png {
        Ok(())
    } else {
        Err(Error::Usage(format!(
            "--out {}: umbra render writes a PNG; give the file name a .png extension",
            out.display()
        )))
    }
}

/// Ground-truth label maps of the IR and the RGB view, where there is a file.
type TruthMaps = (Option<Vec<u8>>, Option<Vec<u8>>);

/// The ground-truth label maps of frame `i` in `dir`, per view, where there is a file; at least
/// one view must have one.
fn read_truth(dir: &std::path::Path, i: usize) -> Result<TruthMaps> {
    check_truth_dir(dir)?;
    let read = |view: &str| -> Result<Option<Vec<u8>>> {
        let path = label_path(dir, i, view);
        if !path.is_file() {
            return Ok(None);
        }
        let mut labels = vec![0u8; PIXELS];
        if view == "depth" {
            read_ir_label_png(&path, &mut labels)?;
        } else {
            read_label_png(&path, &mut labels)?;
        }
        Ok(Some(labels))
    };
    let (ir, rgb) = (read("depth")?, read("rgb")?);
    if ir.is_none() && rgb.is_none() {
        return Err(Error::input(
            label_path(dir, i, "depth"),
            "",
            format!("missing: no ground truth for frame {i} (expected {i:06}.depth.png and/or {i:06}.rgb.png, SPEC §4)"),
        ));
    }
    Ok((ir, rgb))
}
