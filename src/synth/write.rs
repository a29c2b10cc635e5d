//! Writing a simulated recording (SPEC §3 fakenect folder) and its ground truth (SPEC §4 label
//! PNGs plus `meta.toml`). The only I/O of the simulator.

use std::fmt::Write as _;
use std::path::Path;

use super::random::Category;
use super::render::{render_frame, SynthFrame};
use super::scene::Scene;
use super::sensor::SensorModel;
use crate::calib::Calibration;
use crate::error::{Error, Result};
use crate::labels::{self, CLASSES};
use crate::recording::pnm;

/// Host time of frame 0 of every simulated recording (deterministic output).
const T0: f64 = 1_700_000_000.0;
/// Frame period of the Kinect v1, seconds.
const FRAME_S: f64 = 1.0 / 30.0;

/// Everything needed to simulate one recording.
#[derive(Clone, Debug)]
pub struct Job {
    /// The scene at frame 0 (objects move by their velocity each frame).
    pub scene: Scene,
    /// Category written to `meta.toml`.
    pub category: Category,
    /// Seed of the scene and of the sensor noise.
    pub seed: u64,
    /// Number of depth (and RGB) frames.
    pub frames: usize,
    /// Sensor effects.
    pub sensor: SensorModel,
    /// Camera calibration (also written as `calibration.toml`).
    pub calib: Calibration,
}

/// Checks that `dir` can receive output without overwriting anything: absent, or an empty folder.
pub fn check_free(dir: &Path) -> Result<()> {
    match std::fs::read_dir(dir) {
        Ok(mut entries) => match entries.next() {
            Some(_) => Err(Error::input(
                dir,
                "",
                "already exists and is not empty; refusing to overwrite it (pick a new folder)",
            )),
            None => Ok(()),
        },
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(()),
        Err(_) if dir.exists() => Err(Error::input(dir, "", "exists and is not a folder")),
        Err(e) => Err(Error::io(dir, "reading folder", e)),
    }
}

/// Creates `dir` (and its parents) after [`check_free`].
pub fn prepare_dir(dir: &Path) -> Result<()> {
    check_free(dir)?;
    std::fs::create_dir_all(dir).map_err(|e| Error::io(dir, "creating folder", e))
}

/// The seed of frame `i`'s sensor noise: a SplitMix64 step of the recording seed and the index.
fn frame_seed(seed: u64, i: usize) -> u64 {
    let mut z = seed
        ^ (i as u64)
            .wrapping_add(1)
            .wrapping_mul(0x9e37_79b9_7f4a_7c15);
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

/// Renders frame `i` of a job (pure).
pub fn job_frame(job: &Job, i: usize) -> SynthFrame {
    render_frame(
        &job.scene.at_frame(i),
        &job.calib,
        &job.sensor,
        frame_seed(job.seed, i),
    )
}

/// Simulates `job` into `rec_dir` (recording) and `gt_dir` (labels `<i:06>.depth.png`,
/// `<i:06>.rgb.png`, foreground masks `<i:06>.fg.png`, `meta.toml`); both must be empty or absent.
/// Calls `tick` after each frame. Returns the pixel count per label class over both views.
pub fn write_job(
    job: &Job,
    rec_dir: &Path,
    gt_dir: &Path,
    tick: &mut dyn FnMut(),
) -> Result<[u64; CLASSES]> {
    check_free(rec_dir)?;
    check_free(gt_dir)?;
    prepare_dir(rec_dir)?;
    prepare_dir(gt_dir)?;
    write_text(
        &rec_dir.join("calibration.toml"),
        &job.calib.to_toml_string(),
    )?;
    write_text(&gt_dir.join("meta.toml"), &meta_toml(job))?;
    let mut index = String::new();
    let mut totals = [0u64; CLASSES];
    for i in 0..job.frames {
        let f = job_frame(job, i);
        let t = T0 + i as f64 * FRAME_S;
        // Device ticks at 60 MHz: 2 000 000 a frame.
        let ts = 100_000u32.wrapping_add((i as u32).wrapping_mul(2_000_000));
        let d = format!("d-{t:.6}-{ts}.pgm");
        // RGB 2 ms after depth (120 000 ticks) so that pairing by nearest time is unambiguous.
        let r = format!("r-{:.6}-{}.ppm", t + 0.002, ts.wrapping_add(120_000));
        pnm::write_depth(&rec_dir.join(&d), &f.raw)?;
        pnm::write_rgb(&rec_dir.join(&r), &f.rgb)?;
        write_label_png(&label_path(gt_dir, i, "depth"), &f.ir_labels)?;
        write_label_png(&label_path(gt_dir, i, "rgb"), &f.rgb_labels)?;
        // SPEC §6 ground truth; label_path's naming gives <i:06>.fg.png.
        write_label_png(&label_path(gt_dir, i, "fg"), &f.fg)?;
        let _ = writeln!(index, "{d}\n{r}");
        for (t, h) in totals.iter_mut().zip(
            labels::histogram(&f.ir_labels)
                .iter()
                .zip(labels::histogram(&f.rgb_labels)),
        ) {
            *t += h.0 + h.1;
        }
        tick();
    }
    // INDEX.txt last: a recording interrupted half way is not mistaken for a complete one.
    write_text(&rec_dir.join("INDEX.txt"), &index)?;
    Ok(totals)
}

/// `meta.toml` of the ground truth: category, description, seed, frames, sensor switches.
fn meta_toml(job: &Job) -> String {
    let s = &job.sensor;
    let mut t = toml::Table::new();
    t.insert("category".into(), job.category.as_str().into());
    t.insert("description".into(), job.scene.description.clone().into());
    t.insert("seed".into(), toml::Value::Integer(job.seed as i64));
    t.insert("frames".into(), toml::Value::Integer(job.frames as i64));
    t.insert("ideal_sensor".into(), (*s == SensorModel::ideal()).into());
    t.insert(
        "z_range_m".into(),
        toml::Value::Array(vec![s.z_min.into(), s.z_max.into()]),
    );
    t.insert("noise_sigma_raw".into(), s.noise_sigma_raw.into());
    t.insert(
        "shadow_widening_max_px".into(),
        toml::Value::Array(vec![
            i64::from(s.widen_left_max).into(),
            i64::from(s.widen_right_max).into(),
        ]),
    );
    t.insert("rgb_noise_sigma".into(), s.rgb_noise_sigma.into());
    t.insert("rgb_gain".into(), s.rgb_gain.into());
    t.insert("rgb_soft".into(), s.rgb_soft.into());
    // The objects the description lists; walls, floor and posters are surfaces of the room.
    let objects = job
        .scene
        .objects
        .iter()
        .filter(|o| o.is_foreground())
        .count();
    t.insert("objects".into(), (objects as i64).into());
    t.insert(
        "surfaces".into(),
        ((job.scene.objects.len() - objects) as i64).into(),
    );
    toml::to_string(&t).expect("a flat table always serialises")
}

fn write_text(path: &Path, text: &str) -> Result<()> {
    std::fs::write(path, text).map_err(|e| Error::io(path, "writing", e))
}

use crate::sink::labels::label_path;
pub use crate::sink::labels::write_label_png;

#[cfg(test)]
mod tests {
    use super::*;
    use crate::labels::PIXELS;
    use crate::recording::Recording;

    #[test]
    fn writes_a_readable_recording_and_refuses_to_clobber() {
        let tmp = tempfile::tempdir().unwrap();
        let (rec, gt) = (tmp.path().join("rec"), tmp.path().join("gt"));
        let job = Job {
            scene: Scene::box_before_wall(1.0, 3.0),
            category: Category::Simple,
            seed: 5,
            frames: 2,
            sensor: SensorModel::kinect(),
            calib: Calibration::nyu_default(),
        };
        let mut ticks = 0;
        let totals = write_job(&job, &rec, &gt, &mut || ticks += 1).unwrap();
        assert_eq!(ticks, 2);
        assert_eq!(totals.iter().sum::<u64>(), 2 * 2 * PIXELS as u64);
        let r = Recording::open(&rec).unwrap();
        assert_eq!(r.len(), 2);
        assert_eq!(r.calibration(), &job.calib);
        let mut raw = vec![0u16; PIXELS];
        r.read_depth(1, &mut raw).unwrap();
        assert_eq!(raw, job_frame(&job, 1).raw);
        assert_eq!(r.frames()[1].rgb.as_ref().unwrap().device_ts, 2_220_000);
        let png = image::open(gt.join("000001.depth.png"))
            .unwrap()
            .into_luma8();
        assert_eq!(png.as_raw(), &job_frame(&job, 1).ir_labels);
        let fg = image::open(gt.join("000001.fg.png")).unwrap().into_luma8();
        assert_eq!(fg.as_raw(), &job_frame(&job, 1).fg);
        assert!(fg.as_raw().contains(&255) && fg.as_raw().iter().all(|&m| m == 0 || m == 255));
        let meta = std::fs::read_to_string(gt.join("meta.toml")).unwrap();
        assert!(meta.contains("category = \"simple\""), "{meta}");
        // A second run into the same folders must fail without touching them.
        let e = write_job(&job, &rec, &gt, &mut || {})
            .unwrap_err()
            .to_string();
        assert!(e.contains("not empty") && e.contains("rec"), "{e}");
        assert!(!e.contains('\n'));
        let file = tmp.path().join("f");
        std::fs::write(&file, "x").unwrap();
        assert!(prepare_dir(&file)
            .unwrap_err()
            .to_string()
            .contains("not a folder"));
    }
}
