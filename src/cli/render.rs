//! `umbra render`: draws one classified frame as a PNG (see [`crate::render`]).

use std::path::PathBuf;

use image::ImageEncoder;

use crate::classify::{Classified, Classifier};
use crate::error::{Error, Result};
use crate::labels::PIXELS;
use crate::recording::Recording;
use crate::render::render_panels;
use crate::sink::labels::write_atomically;

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
}

/// Runs `umbra render`.
pub fn run(a: Args) -> Result<()> {
    let params = crate::config::Config::load_or_default(a.config.as_deref())?.params();
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
    let img = render_panels(has_rgb.then_some(&rgb[..]), &raw, rec.calibration(), &out);

    let mut png = Vec::new();
    image::codecs::png::PngEncoder::new(&mut png)
        .write_image(
            img.as_raw(),
            img.width(),
            img.height(),
            image::ExtendedColorType::Rgb8,
        )
        .map_err(|e| Error::input(&a.out, "", format!("encoding PNG failed: {e}")))?;
    write_atomically(&a.out, &png)
}
