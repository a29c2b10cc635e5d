//! `umbra synth`: simulate Kinect v1 recordings with exact ground-truth labels (see
//! [`crate::synth`]). One recording (`OUT_REC --gt GT_DIR`) or a suite (`--suite DIR`).

use std::path::PathBuf;
use std::time::Instant;

use indicatif::{ProgressBar, ProgressStyle};

use crate::calib::Calibration;
use crate::error::{Error, Result};
use crate::labels::{CLASSES, NAMES};
use crate::synth::{random_scene, sensor_for, write, write_job, Category, Job, Scene, SensorModel};

/// Which scene `umbra synth` builds.
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum SceneArg {
    /// One object before a back wall (random, per seed).
    Simple,
    /// 3–8 objects, thin rods, black and glossy surfaces, far regions (random, per seed).
    Complex,
    /// The hand-checkable box 1 m before a wall at 3 m.
    Box,
}

/// Arguments of `umbra synth`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Recording folder to create (fakenect format); must be absent or empty.
    #[arg(value_name = "OUT_REC", conflicts_with = "suite")]
    pub out: Option<PathBuf>,
    /// Ground-truth folder to create: 000000.depth.png, 000000.rgb.png, … per frame, meta.toml.
    #[arg(long, value_name = "GT_DIR", conflicts_with = "suite")]
    pub gt: Option<PathBuf>,
    /// Scene to simulate.
    #[arg(long, value_enum, default_value = "simple")]
    pub scene: SceneArg,
    /// Depth frames per recording (objects drift between frames).
    #[arg(long, default_value_t = 3)]
    pub frames: usize,
    /// Seed of scenes and sensor noise: the same seed gives the same files.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Noise-free sensor: exact raw values, shadows exactly as wide as geometry, no dropouts.
    #[arg(long)]
    pub ideal: bool,
    /// Make every black or glossy surface matte in its own colour, so the sensor measures it:
    /// the same scenes without occluders that return no depth.
    #[arg(long)]
    pub all_matte: bool,
    /// Write a suite of scenes (half simple, half complex) to DIR/recordings and DIR/gt.
    #[arg(long, value_name = "DIR")]
    pub suite: Option<PathBuf>,
    /// Number of scenes in a suite.
    #[arg(long, default_value_t = 10, requires = "suite")]
    pub count: usize,
    /// Noise of the RGB camera, σ in 8-bit units per channel (default: the sensor model's, 2;
    /// the real NYU frame's smooth regions show 1.3 to 4.8), to see how the colour steps hold up.
    #[arg(long, value_name = "SIGMA")]
    pub rgb_noise: Option<f64>,
    /// Noise of the raw depth values, σ in raw units (default: the sensor model's, 0.5; the
    /// real NYU frame's second differences read as about 0.25, the simulator's as 0.55), to see
    /// how the depth tests hold up on a noisier sensor.
    #[arg(long, value_name = "SIGMA")]
    pub depth_noise: Option<f64>,
    /// How far the sensor's correlation window widens each projector shadow: up to LEFT valid
    /// pixels swallowed at its left end and RIGHT at its right, drawn per row, small widths a
    /// little likelier (default 3,2: about +2.2 px on average, as SPEC §1's real frame shows),
    /// to see how the shadow tests hold up on a sensor that widens more.
    #[arg(long, value_name = "LEFT,RIGHT", value_parser = widening_arg)]
    pub shadow_widening: Option<(u32, u32)>,
    /// Exposure of the RGB camera: every colour value scaled by this (default 1; 0.45 makes the
    /// simulated room about as dark as the real NYU frame).
    #[arg(long, value_name = "GAIN")]
    pub rgb_gain: Option<f64>,
    /// A soft RGB lens: the image blurred by [1 2 1]/4 along rows and columns before the noise,
    /// so that strong edges rise over two pixels, as on the real NYU frame (without it they rise
    /// within one).
    #[arg(long)]
    pub rgb_soft: bool,
    /// Simulate a Kinect with this calibration (SPEC §3 TOML, as `calibration.toml` of a
    /// recording) instead of the NYU defaults; it is written into every recording made.
    #[arg(long, value_name = "FILE")]
    pub calibration: Option<PathBuf>,
}

/// Parses `--shadow-widening LEFT,RIGHT`: pixels, 0 to 12 each.
fn widening_arg(s: &str) -> std::result::Result<(u32, u32), String> {
    let parse = |v: &str| v.trim().parse::<u32>().ok().filter(|&n| n <= 12);
    match s.split_once(',') {
        Some((l, r)) => match (parse(l), parse(r)) {
            (Some(l), Some(r)) => Ok((l, r)),
            _ => Err(format!(
                "'{s}': expected LEFT,RIGHT in pixels, 0 to 12 each (as 3,2)"
            )),
        },
        None => Err(format!("'{s}': expected LEFT,RIGHT in pixels (as 3,2)")),
    }
}

/// Runs `umbra synth`.
pub fn run(a: Args) -> Result<()> {
    if a.frames == 0 || a.frames > 100_000 {
        return Err(Error::Usage(format!(
            "--frames {} is out of range, expected 1 to 100000",
            a.frames
        )));
    }
    if let Some(s) = a.rgb_noise.filter(|s| !(0.0..=64.0).contains(s)) {
        return Err(Error::Usage(format!(
            "--rgb-noise {s} is out of range, expected 0 to 64 (8-bit units)"
        )));
    }
    if let Some(s) = a.depth_noise.filter(|s| !(0.0..=16.0).contains(s)) {
        return Err(Error::Usage(format!(
            "--depth-noise {s} is out of range, expected 0 to 16 (raw units)"
        )));
    }
    if let Some(g) = a.rgb_gain.filter(|g| !(*g > 0.0 && *g <= 4.0)) {
        return Err(Error::Usage(format!(
            "--rgb-gain {g} is out of range, expected more than 0 and at most 4"
        )));
    }
    let calib = match &a.calibration {
        Some(path) => Calibration::load(path)?,
        None => Calibration::nyu_default(),
    };
    let started = Instant::now();
    // (recording dir, gt dir, job) for every recording to write.
    let mut work: Vec<(PathBuf, PathBuf, Job)> = Vec::new();
    let describe_target;
    if let Some(dir) = &a.suite {
        if a.count == 0 {
            return Err(Error::Usage(
                "--count 0: a suite needs at least one scene".into(),
            ));
        }
        write::prepare_dir(dir)?;
        for i in 0..a.count {
            // Alternate so that any prefix of the suite is balanced.
            let cat = if i % 2 == 0 {
                Category::Simple
            } else {
                Category::Complex
            };
            let seed = a.seed.wrapping_mul(1_000_003).wrapping_add(i as u64);
            let name = format!("{i:03}-{}", cat.as_str());
            let job = make_job(random_scene(cat, seed), cat, seed, &a, calib);
            work.push((
                dir.join("recordings").join(&name),
                dir.join("gt").join(&name),
                job,
            ));
        }
        describe_target = format!(
            "{} to {}",
            super::count(a.count as u64, "recording"),
            dir.display()
        );
    } else {
        let (Some(out), Some(gt)) = (&a.out, &a.gt) else {
            return Err(Error::Usage(
                "umbra synth needs OUT_REC and --gt GT_DIR, or --suite DIR".into(),
            ));
        };
        // Ground truth is kept apart from the recording (a recording folder holds what a Kinect
        // would record, and replaying it must not see the answers).
        let abs = |p: &PathBuf| std::path::absolute(p).unwrap_or_else(|_| p.clone());
        let (out_abs, gt_abs) = (abs(out), abs(gt));
        if out_abs == gt_abs {
            return Err(Error::Usage(format!(
                "OUT_REC and --gt are the same folder {}",
                out.display()
            )));
        }
        if gt_abs.starts_with(&out_abs) || out_abs.starts_with(&gt_abs) {
            return Err(Error::Usage(format!(
                "--gt {} and OUT_REC {} are one inside the other: keep the ground truth outside the recording folder",
                gt.display(),
                out.display()
            )));
        }
        let (scene, cat) = match a.scene {
            SceneArg::Simple => (random_scene(Category::Simple, a.seed), Category::Simple),
            SceneArg::Complex => (random_scene(Category::Complex, a.seed), Category::Complex),
            SceneArg::Box => (Scene::box_before_wall(1.0, 3.0), Category::Simple),
        };
        // Check both folders before writing anything into either.
        write::check_free(out)?;
        write::check_free(gt)?;
        work.push((
            out.clone(),
            gt.clone(),
            make_job(scene, cat, a.seed, &a, calib),
        ));
        describe_target = format!(
            "1 recording to {} (labels in {})",
            out.display(),
            gt.display()
        );
    }

    let total_frames = (work.len() * a.frames) as u64;
    let bar = ProgressBar::new(total_frames);
    bar.set_style(
        ProgressStyle::with_template(
            "{spinner} synth [{bar:30}] {pos}/{len} frames {msg} eta {eta}",
        )
        .expect("valid template")
        .progress_chars("=> "),
    );
    let mut totals = [0u64; CLASSES];
    for (rec, gt, job) in &work {
        bar.set_message(
            rec.file_name()
                .map(|n| n.to_string_lossy().into_owned())
                .unwrap_or_default(),
        );
        let t = write_job(job, rec, gt, &mut || bar.inc(1)).inspect_err(|_| bar.abandon())?;
        for (a, b) in totals.iter_mut().zip(t) {
            *a += b;
        }
    }
    bar.finish_and_clear();
    let all: u64 = totals.iter().sum::<u64>().max(1);
    let shares: Vec<String> = NAMES
        .iter()
        .zip(totals)
        .map(|(n, c)| format!("{n} {:.1}%", 100.0 * c as f64 / all as f64))
        .collect();
    println!(
        "synth: wrote {describe_target}, {} in {:.1} s; labels (both views): {}",
        super::count(total_frames, "frame"),
        started.elapsed().as_secs_f64(),
        shares.join(", ")
    );
    Ok(())
}

fn make_job(scene: Scene, category: Category, seed: u64, a: &Args, calib: Calibration) -> Job {
    let mut sensor = if a.ideal {
        SensorModel::ideal()
    } else {
        sensor_for(category)
    };
    if let Some(s) = a.rgb_noise {
        sensor.rgb_noise_sigma = s;
    }
    if let Some(g) = a.rgb_gain {
        sensor.rgb_gain = g;
    }
    if let Some(s) = a.depth_noise {
        sensor.noise_sigma_raw = s;
    }
    if let Some((left, right)) = a.shadow_widening {
        sensor.widen_left_max = left;
        sensor.widen_right_max = right;
    }
    sensor.rgb_soft = a.rgb_soft;
    Job {
        scene: if a.all_matte {
            scene.all_matte()
        } else {
            scene
        },
        category,
        seed,
        frames: a.frames,
        sensor,
        calib,
    }
}
