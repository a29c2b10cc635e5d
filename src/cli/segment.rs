//! `umbra segment REC [--frame N] --out DIR [--seeds shadow|threshold]`: automatic foreground
//! masks (SPEC §6) and overlay pictures, see [`crate::segment`].

use std::path::PathBuf;
use std::time::Instant;

use crate::classify::{Classified, Classifier};
use crate::error::{Error, Result};
use crate::labels::PIXELS;
use crate::recording::Recording;
use crate::segment::files::{mask_path, overlay, overlay_path, write_mask_png, write_rgb_png};
use crate::segment::{Params, SeedMode, Segmenter};

/// Where seeds come from.
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum SeedsArg {
    /// From classified shadows (Deng et al. §4).
    Shadow,
    /// The paper's baseline: nearer than --tf is foreground, farther than --tb background.
    Threshold,
}

/// Default Tf of the threshold baseline, metres: the best fixed pair found by `umbra eval
/// --segment` on simulated scenes.
pub const DEFAULT_TF_M: f32 = 2.0;
/// Default Tb of the threshold baseline, metres.
pub const DEFAULT_TB_M: f32 = 2.0;

/// Arguments of `umbra segment`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// The recording folder (with INDEX.txt).
    pub recording: PathBuf,
    /// Only this 0-based depth frame (SPEC §3); every frame without it.
    #[arg(long, value_name = "N")]
    pub frame: Option<usize>,
    /// Folder for <i:06>.fg.png (255 foreground, 0 background) and <i:06>.overlay.png.
    #[arg(long, value_name = "DIR")]
    pub out: PathBuf,
    /// Seed source.
    #[arg(long, value_enum, default_value = "shadow")]
    pub seeds: SeedsArg,
    /// Tf for --seeds threshold, metres.
    #[arg(long, value_name = "M", default_value_t = DEFAULT_TF_M)]
    pub tf: f32,
    /// Tb for --seeds threshold, metres.
    #[arg(long, value_name = "M", default_value_t = DEFAULT_TB_M)]
    pub tb: f32,
    /// Settings file (see config/umbra.toml); built-in defaults without it.
    #[arg(long, value_name = "FILE")]
    pub config: Option<PathBuf>,
}

/// Runs `umbra segment`.
pub fn run(a: Args) -> Result<()> {
    let classify_params = crate::config::Config::load_or_default(a.config.as_deref())?.params();
    let rec = Recording::open(&a.recording)?;
    let frames: Vec<usize> = match a.frame {
        Some(f) if f >= rec.len() => {
            let n = rec.len();
            return Err(Error::Usage(format!(
                "frame {f} is out of range: {} has {n} depth frame{} (use --frame 0 to {})",
                a.recording.display(),
                if n == 1 { "" } else { "s" },
                n - 1
            )));
        }
        Some(f) => vec![f],
        None => (0..rec.len()).collect(),
    };
    let mode = match a.seeds {
        SeedsArg::Shadow => SeedMode::Shadow,
        SeedsArg::Threshold => {
            if !(a.tf.is_finite() && a.tb.is_finite() && a.tf > 0.0 && a.tb >= a.tf) {
                return Err(Error::Usage(format!(
                    "--tf {} --tb {}: expected 0 < Tf <= Tb (metres)",
                    a.tf, a.tb
                )));
            }
            SeedMode::Threshold {
                tf_m: a.tf,
                tb_m: a.tb,
            }
        }
    };
    std::fs::create_dir_all(&a.out).map_err(|e| Error::io(&a.out, "creating folder", e))?;

    let mut classifier = Classifier::with_params(rec.calibration(), classify_params);
    let mut segmenter = Segmenter::new(Params {
        seeds: mode,
        ..Params::default()
    });
    let mut classified = Classified::default();
    let (mut raw, mut rgb, mut mask) =
        (vec![0u16; PIXELS], vec![0u8; 3 * PIXELS], vec![0u8; PIXELS]);
    let (mut png, mut picture, mut scratch) = (Vec::new(), Vec::new(), Vec::new());
    let bar = super::progress_bar(frames.len() as u64, "frames");
    let started = Instant::now();
    let mut seg_time = 0.0f64;
    let (mut fg_pixels, mut seeds) = (0usize, 0usize);
    for &i in &frames {
        rec.read_depth_with(i, &mut scratch, &mut raw)
            .inspect_err(|_| bar.abandon())?;
        if !rec
            .read_rgb_with(i, &mut scratch, &mut rgb)
            .inspect_err(|_| bar.abandon())?
        {
            bar.abandon();
            let index = rec.dir().join("INDEX.txt");
            return Err(Error::input(
                index,
                "",
                format!("depth frame {i} has no RGB frame to segment (expected r-*.ppm lines)"),
            ));
        }
        classifier.classify_with_rgb(&raw, Some(&rgb), &mut classified);
        let t = Instant::now();
        let out = segmenter.segment(&rgb, &classified, &mut mask);
        seg_time += t.elapsed().as_secs_f64();
        fg_pixels += out.fg_pixels;
        seeds += out.fg_seeds + out.bg_seeds;
        write_mask_png(&mask_path(&a.out, i), &mask, &mut png).inspect_err(|_| bar.abandon())?;
        overlay(&rgb, &mask, segmenter.seeds(), &mut picture);
        write_rgb_png(&overlay_path(&a.out, i), &picture, &mut png)
            .inspect_err(|_| bar.abandon())?;
        bar.inc(1);
    }
    bar.finish_and_clear();
    let n = frames.len() as f64;
    println!(
        "segment: {} frame{} of {} to {} in {:.1} s ({} seeds): {:.1}% foreground, {:.0} seeds and {:.1} ms of segmentation per frame",
        frames.len(),
        if frames.len() == 1 { "" } else { "s" },
        a.recording.display(),
        a.out.display(),
        started.elapsed().as_secs_f64(),
        match a.seeds {
            SeedsArg::Shadow => "shadow".to_string(),
            SeedsArg::Threshold => format!("threshold Tf {} m, Tb {} m", a.tf, a.tb),
        },
        100.0 * fg_pixels as f64 / (n * PIXELS as f64),
        seeds as f64 / n,
        1e3 * seg_time / n
    );
    Ok(())
}
