//! SPEC §5 through the real `umbra` binary: every malformed input (recording folder, INDEX.txt,
//! depth PGM, RGB PPM, calibration.toml, device.json, config, ground truth, output path, frame
//! request) must end with a non-zero exit status and exactly ONE stderr line
//! `umbra: error: <file>: <place>: <what was expected>`, no panic or backtrace, and nothing
//! already written may be lost or damaged.
//!
//! Each case simulates a valid two-frame recording and its ground truth (`umbra synth`) in its
//! own temporary folder and breaks one thing.

mod common;

use std::path::{Path, PathBuf};
use std::process::Command;

const W: usize = 640;
const H: usize = 480;
const DEPTH_HEADER: &[u8] = b"P5 640 480 65535\n";

/// Runs `umbra` with `args`; returns (success, stderr).
fn umbra(args: &[&str]) -> (bool, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_umbra"))
        .args(args)
        .env_remove("RUST_LOG")
        .output()
        .expect("run the umbra binary");
    (
        out.status.success(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

fn s(p: &Path) -> String {
    p.display().to_string()
}

/// One case's scratch folder with its own valid recording (`rec/`) and ground truth (`gt/`),
/// simulated afresh (about 0.2 s) so that every case is independent and leaves nothing behind.
struct Case {
    tmp: tempfile::TempDir,
}

impl Case {
    fn new() -> Self {
        let tmp = tempfile::tempdir().unwrap();
        let (rec, gt) = (tmp.path().join("rec"), tmp.path().join("gt"));
        let (ok, err) = umbra(&[
            "synth",
            &s(&rec),
            "--gt",
            &s(&gt),
            "--scene",
            "box",
            "--frames",
            "2",
            "--seed",
            "1",
        ]);
        assert!(ok, "umbra synth failed: {err}");
        Case { tmp }
    }

    fn path(&self, name: &str) -> PathBuf {
        self.tmp.path().join(name)
    }

    fn rec(&self) -> PathBuf {
        self.path("rec")
    }

    fn gt(&self) -> PathBuf {
        self.path("gt")
    }

    /// The recording's files of one stream (`"d-"` or `"r-"`), in INDEX.txt order.
    fn stream(&self, prefix: &str) -> Vec<PathBuf> {
        let index = std::fs::read_to_string(self.rec().join("INDEX.txt")).unwrap();
        index
            .lines()
            .filter(|l| l.starts_with(prefix))
            .map(|l| self.rec().join(l.trim()))
            .collect()
    }

    fn depth(&self, i: usize) -> PathBuf {
        self.stream("d-").remove(i)
    }

    fn calibration(&self) -> PathBuf {
        self.rec().join("calibration.toml")
    }

    /// Rewrites the recording's INDEX.txt with `edit` of its text; its path and the number of
    /// lines it had.
    fn edit_index(&self, edit: impl FnOnce(&str) -> String) -> (PathBuf, usize) {
        let index = self.rec().join("INDEX.txt");
        let text = std::fs::read_to_string(&index).unwrap();
        std::fs::write(&index, edit(&text)).unwrap();
        (index, text.lines().count())
    }

    /// Replaces the recording's calibration.toml by a device.json holding `text`; its path.
    fn device_json(&self, text: &str) -> PathBuf {
        std::fs::remove_file(self.calibration()).unwrap();
        let path = self.rec().join("device.json");
        std::fs::write(&path, text).unwrap();
        path
    }

    /// Replaces the first `from` in the recording's calibration.toml by `to`.
    fn edit_calibration(&self, from: &str, to: &str) {
        let text = std::fs::read_to_string(self.calibration()).unwrap();
        assert!(
            text.contains(from),
            "fixture changed: calibration.toml has no {from:?}:\n{text}"
        );
        std::fs::write(self.calibration(), text.replacen(from, to, 1)).unwrap();
    }

    fn replay(&self) -> (bool, String) {
        umbra(&["replay", &s(&self.rec())])
    }

    /// Replays a recording that must load despite its flaw: both frames are classified, and the
    /// returned stderr holds only the warnings.
    fn replay_ok(&self) -> String {
        let (ok, out, err) = common::run(&["replay", &s(&self.rec())]);
        assert!(ok, "replay failed: {err}");
        assert!(out.starts_with("2 frames in "), "{out}");
        assert!(!err.contains("error"), "{err}");
        err
    }
}

fn copy_dir(from: &Path, to: &Path) {
    std::fs::create_dir_all(to).unwrap();
    for e in std::fs::read_dir(from).unwrap() {
        let e = e.unwrap();
        std::fs::copy(e.path(), to.join(e.file_name())).unwrap();
    }
}

#[track_caller]
fn one_line_error((ok, stderr): (bool, String), needles: &[&str]) {
    common::one_line_error(ok, &stderr, needles);
}

fn read(p: &Path) -> Vec<u8> {
    std::fs::read(p).unwrap_or_else(|e| panic!("{}: {e}", p.display()))
}

/// Every file of a folder, by name, with its bytes.
fn snapshot(dir: &Path) -> Vec<(String, Vec<u8>)> {
    let mut v: Vec<(String, Vec<u8>)> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| {
            let e = e.unwrap();
            (
                e.file_name().to_string_lossy().into_owned(),
                read(&e.path()),
            )
        })
        .collect();
    v.sort();
    v
}

fn write_gray_png(path: &Path, w: u32, h: u32, pixels: Vec<u8>) {
    image::GrayImage::from_raw(w, h, pixels)
        .unwrap()
        .save(path)
        .unwrap();
}

// ---------------------------------------------------------------- 1. recording folder, INDEX.txt

#[test]
fn recording_folder_missing() {
    let c = Case::new();
    let nope = c.path("no-such-recording");
    one_line_error(
        umbra(&["replay", &s(&nope)]),
        &[&s(&nope), "not a recording folder", "INDEX.txt"],
    );
}

#[test]
fn recording_folder_without_index() {
    let c = Case::new();
    std::fs::remove_file(c.rec().join("INDEX.txt")).unwrap();
    one_line_error(c.replay(), &[&s(&c.rec().join("INDEX.txt")), "missing"]);
}

#[test]
fn index_bad_line_names_the_line() {
    let c = Case::new();
    let (index, lines) = c.edit_index(|text| format!("{text}x-1-2.pgm\n"));
    let line = lines + 1;
    one_line_error(
        c.replay(),
        &[
            &s(&index),
            &format!(": line {line}: "),
            "'x-1-2.pgm'",
            "d-<unix_time>-<device_ts>.pgm",
        ],
    );
}

#[test]
fn index_naming_a_missing_file() {
    let c = Case::new();
    let index = c.rec().join("INDEX.txt");
    let text = std::fs::read_to_string(&index).unwrap();
    // Remove the second depth frame but keep its line (the third of the file).
    let gone = c.depth(1);
    let name = gone.file_name().unwrap().to_str().unwrap().to_string();
    let line = text.lines().position(|l| l == name).unwrap() + 1;
    std::fs::remove_file(&gone).unwrap();
    one_line_error(
        c.replay(),
        &[
            &s(&index),
            &format!(": line {line}: "),
            &name,
            "does not exist",
        ],
    );
}

#[test]
fn index_naming_a_folder() {
    let c = Case::new();
    let index = c.rec().join("INDEX.txt");
    let d = c.depth(0);
    let name = d.file_name().unwrap().to_str().unwrap().to_string();
    std::fs::remove_file(&d).unwrap();
    std::fs::create_dir(&d).unwrap();
    one_line_error(
        c.replay(),
        &[&s(&index), ": line 1: ", &name, "is not a regular file"],
    );
}

#[test]
fn index_listing_no_depth_frame() {
    let c = Case::new();
    let index = c.rec().join("INDEX.txt");
    let rgb_only: String = std::fs::read_to_string(&index)
        .unwrap()
        .lines()
        .filter(|l| l.starts_with("r-"))
        .map(|l| format!("{l}\n"))
        .collect();
    assert!(!rgb_only.is_empty());
    std::fs::write(&index, rgb_only).unwrap();
    one_line_error(c.replay(), &[&s(&index), "no depth frame"]);
}

#[test]
fn index_not_utf8_names_the_byte() {
    let c = Case::new();
    let index = c.rec().join("INDEX.txt");
    let mut bytes = read(&index);
    let at = bytes.len();
    bytes.extend_from_slice(b"\xff\xfe\n");
    std::fs::write(&index, bytes).unwrap();
    one_line_error(c.replay(), &[&s(&index), &format!("byte {at}"), "UTF-8"]);
}

#[test]
fn index_with_a_byte_order_mark_is_read() {
    // Windows editors start a saved INDEX.txt with a UTF-8 BOM.
    let c = Case::new();
    let index = c.rec().join("INDEX.txt");
    std::fs::write(&index, [b"\xef\xbb\xbf".as_slice(), &read(&index)].concat()).unwrap();
    assert_eq!(c.replay_ok(), "");
}

#[test]
fn index_comment_line_is_named_as_such() {
    let c = Case::new();
    let (index, _) = c.edit_index(|text| format!("# recorded by hand\n{text}"));
    one_line_error(
        c.replay(),
        &[
            &s(&index),
            ": line 1: '# recorded by hand': ",
            "comment lines are not part of fakenect's INDEX.txt format",
        ],
    );
}

#[test]
fn index_naming_missing_accelerometer_files_warns_once() {
    // umbra never reads a-*.dump: a lost one is no reason to refuse the recording.
    let c = Case::new();
    let (index, lines) = c.edit_index(|text| {
        format!("{text}a-1700000000.040000-3.dump\na-1700000000.050000-4.dump\n")
    });
    let line = lines + 1;
    let err = c.replay_ok();
    assert_eq!(
        err.lines().count(),
        1,
        "one warning for the recording: {err}"
    );
    for needle in [
        "WARN",
        &format!("{}: line {line}: ", s(&index)),
        "2 missing accelerometer files, the first a-1700000000.040000-3.dump",
    ] {
        assert!(err.contains(needle), "{needle:?} missing from: {err}");
    }
}

// ---------------------------------------------------------------- 2. depth PGM

#[test]
fn depth_truncated() {
    let c = Case::new();
    let d = c.depth(1); // the second frame: the error comes mid-replay, after frame 0 went through
    let bytes = read(&d);
    let cut = bytes.len() - 1000;
    std::fs::write(&d, &bytes[..cut]).unwrap();
    one_line_error(
        c.replay(),
        &[&s(&d), &format!("byte {cut}"), "truncated", "614400"],
    );
}

#[test]
fn depth_wrong_magic() {
    let c = Case::new();
    let d = c.depth(0);
    let mut bytes = read(&d);
    assert!(bytes.starts_with(DEPTH_HEADER), "fixture changed");
    bytes[1] = b'6';
    std::fs::write(&d, bytes).unwrap();
    one_line_error(c.replay(), &[&s(&d), "byte 0", "'P6'", "'P5'"]);
}

#[test]
fn depth_wrong_size_header() {
    let c = Case::new();
    let d = c.depth(0);
    let bytes = read(&d);
    let body = &bytes[DEPTH_HEADER.len()..];
    std::fs::write(&d, [b"P5 320 240 65535\n".as_slice(), body].concat()).unwrap();
    one_line_error(c.replay(), &[&s(&d), "header", "320x240", "640x480"]);
}

#[test]
fn depth_sample_above_2047_names_the_pixel() {
    let c = Case::new();
    let d = c.depth(0);
    let mut bytes = read(&d);
    let (x, y) = (123, 45);
    let at = DEPTH_HEADER.len() + 2 * (y * W + x);
    bytes[at..at + 2].copy_from_slice(&0x0900u16.to_le_bytes()); // 2304
    std::fs::write(&d, bytes).unwrap();
    one_line_error(
        c.replay(),
        &[
            &s(&d),
            &format!("pixel ({x}, {y})"),
            &format!("byte {at}"),
            "2304",
            "2047",
        ],
    );
}

#[test]
fn depth_empty_or_bad_header() {
    for (bytes, needles) in [
        (&b""[..], &["byte 0", "'P5'"][..]),
        (b"P5 640 480 255\n", &["header", "maxval 255", "65535"]),
        (b"P5 640 480 65535", &["byte 16", "whitespace"]),
    ] {
        let c = Case::new();
        let d = c.depth(0);
        std::fs::write(&d, bytes).unwrap();
        let mut all = vec![s(&d)];
        all.extend(needles.iter().map(|n| n.to_string()));
        one_line_error(
            c.replay(),
            &all.iter().map(String::as_str).collect::<Vec<_>>(),
        );
    }
}

#[test]
fn depth_trailing_bytes() {
    let c = Case::new();
    let d = c.depth(0);
    let mut bytes = read(&d);
    let end = bytes.len();
    bytes.extend_from_slice(b"garbage");
    std::fs::write(&d, bytes).unwrap();
    one_line_error(
        c.replay(),
        &[&s(&d), &format!("byte {end}"), "7 unexpected bytes"],
    );
}

#[test]
fn depth_header_with_windows_line_ending() {
    let c = Case::new();
    let d = c.depth(0);
    let bytes = read(&d);
    let body = &bytes[DEPTH_HEADER.len()..];
    std::fs::write(&d, [b"P5 640 480 65535\r\n".as_slice(), body].concat()).unwrap();
    one_line_error(
        c.replay(),
        &[
            &s(&d),
            "byte 16",
            "header ends in \\r\\n (Windows line ending)",
            "fakenect writes a single \\n",
        ],
    );
}

// ---------------------------------------------------------------- 3. RGB PPM

#[test]
fn rgb_truncated_seen_by_render() {
    let c = Case::new();
    let r = c.stream("r-").remove(0);
    let bytes = read(&r);
    let cut = bytes.len() - 1000;
    std::fs::write(&r, &bytes[..cut]).unwrap();
    let out = c.path("x.png");
    one_line_error(
        umbra(&["render", &s(&c.rec()), "--frame", "0", "--out", &s(&out)]),
        &[&s(&r), &format!("byte {cut}"), "truncated", "921600"],
    );
    assert!(
        !out.exists(),
        "a failed render must not leave an output file"
    );
}

// ---------------------------------------------------------------- 4. calibration.toml, device.json

#[test]
fn calibration_syntax_error_gives_line_and_column() {
    let c = Case::new();
    c.edit_calibration("fx = 582.62", "fx = = 582.62"); // line 2 of the file
    one_line_error(c.replay(), &[&s(&c.calibration()), "line 2, column "]);
}

#[test]
fn calibration_unknown_key() {
    let c = Case::new();
    c.edit_calibration("baseline_m = 0.075", "baseline_m = 0.075\nfocal_length = 3");
    let line = std::fs::read_to_string(c.calibration())
        .unwrap()
        .lines()
        .position(|l| l.starts_with("focal_length"))
        .unwrap()
        + 1;
    one_line_error(
        c.replay(),
        &[
            &s(&c.calibration()),
            &format!("line {line}, column "),
            "focal_length",
        ],
    );
}

#[test]
fn calibration_missing_key_names_its_table() {
    let c = Case::new();
    c.edit_calibration("fy = 519.47\n", ""); // [rgb]'s; [depth] keeps its own
    one_line_error(
        c.replay(),
        &[&format!("{}: [rgb]: missing key fy", s(&c.calibration()))],
    );
    let c = Case::new();
    let text = std::fs::read_to_string(c.calibration()).unwrap();
    let raw = text.find("[raw]").expect("fixture changed: no [raw] table");
    std::fs::write(c.calibration(), &text[..raw]).unwrap();
    one_line_error(
        c.replay(),
        &[
            &format!("{}: [raw]: missing table", s(&c.calibration())),
            "numerator, denominator, baseline_m",
        ],
    );
}

#[test]
fn calibration_nan_focal_length() {
    let c = Case::new();
    c.edit_calibration("fx = 582.62", "fx = nan");
    one_line_error(c.replay(), &[&s(&c.calibration()), "key depth.fx", "NaN"]);
}

#[test]
fn calibration_absurd_baseline() {
    let c = Case::new();
    c.edit_calibration("baseline_m = 0.075", "baseline_m = 7.5");
    one_line_error(
        c.replay(),
        &[&s(&c.calibration()), "key raw.baseline_m", "7.5"],
    );
}

#[test]
fn calibration_non_rotation_matrix() {
    let identity = "rotation = [1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0]";
    for bad in [
        "rotation = [1.0, 0.5, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0]", // not orthogonal
        "rotation = [1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, -1.0]", // a reflection
    ] {
        let c = Case::new();
        c.edit_calibration(identity, bad);
        one_line_error(
            c.replay(),
            &[
                &s(&c.calibration()),
                "key depth_to_rgb.rotation",
                "not a proper rotation",
            ],
        );
    }
}

const DEVICE_JSON_OK: &str = r#"{"reg_info":{"zero_plane_info":{"dcmos_emitter_distance":7.5,"dcmos_rcmos_distance":2.4,"reference_distance":120,"reference_pixel_size":0.1042}}}"#;

#[test]
fn device_json_used_only_without_calibration_toml() {
    // With calibration.toml present, a broken device.json is never read.
    let c = Case::new();
    std::fs::write(c.rec().join("device.json"), "{ not json").unwrap();
    let (ok, e) = c.replay();
    assert!(
        ok,
        "calibration.toml takes precedence over device.json: {e}"
    );
    // Without it, a good device.json is accepted.
    c.device_json(DEVICE_JSON_OK);
    let (ok, e) = c.replay();
    assert!(ok, "a valid device.json must load: {e}");
}

#[test]
fn device_json_without_registration_data_means_defaults() {
    // libfreenect's record of a device with no registration data: every zero-plane value 0.
    let c = Case::new();
    let dj = c.device_json(r#"{"reg_info":{"zero_plane_info":{"dcmos_emitter_distance":0,"dcmos_rcmos_distance":0,"reference_distance":0,"reference_pixel_size":0}},"const_shift":0}"#);
    let err = c.replay_ok();
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(
        err.contains("WARN")
            && err.contains(&s(&dj))
            && err.contains("no registration data")
            && err.contains("NYU Kinect v1 default calibration"),
        "{err}"
    );
}

#[test]
fn device_json_zero_reference_distance_reads_as_a_range() {
    let c = Case::new();
    let dj = c.device_json(
        &DEVICE_JSON_OK.replace("\"reference_distance\":120", "\"reference_distance\":0"),
    );
    one_line_error(
        c.replay(),
        &[
            &s(&dj),
            "key reg_info.zero_plane_info.reference_distance",
            "value 0 must be greater than 0 and less than 10000 mm",
        ],
    );
}

#[test]
fn device_json_invalid() {
    let c = Case::new();
    let dj = c.device_json("{\"reg_info\": {\"zero_plane_info\": [1, 2,\n");
    let (ok, e) = c.replay();
    assert!(
        !e.contains(" at line "),
        "the place is given once, in front: {e}"
    );
    one_line_error((ok, e), &[&s(&dj), ": line 2, column "]);
}

#[test]
fn device_json_negative_emitter_distance() {
    let c = Case::new();
    let dj = c.device_json(&DEVICE_JSON_OK.replace(
        "\"dcmos_emitter_distance\":7.5",
        "\"dcmos_emitter_distance\":-7.5",
    ));
    one_line_error(
        c.replay(),
        &[
            &s(&dj),
            "reg_info.zero_plane_info.dcmos_emitter_distance",
            "-7.5",
        ],
    );
}

#[test]
fn device_json_absurd_emitter_distance_names_its_key() {
    // 750 cm is positive but no Kinect: reported under the file's key, not a derived one.
    let c = Case::new();
    let dj = c.device_json(&DEVICE_JSON_OK.replace(
        "\"dcmos_emitter_distance\":7.5",
        "\"dcmos_emitter_distance\":750",
    ));
    one_line_error(
        c.replay(),
        &[
            &s(&dj),
            "key reg_info.zero_plane_info.dcmos_emitter_distance",
            "750",
            "cm",
        ],
    );
}

#[test]
fn config_unknown_key() {
    let c = Case::new();
    let cfg = c.path("umbra.toml");
    std::fs::write(&cfg, "[classifier]\nmin_stp_px = 1.0\n").unwrap();
    one_line_error(
        umbra(&["replay", &s(&c.rec()), "--config", &s(&cfg)]),
        &[&s(&cfg), "line 2, column 1", "min_stp_px"],
    );
}

// ---------------------------------------------------------------- 5. frame request

#[test]
fn render_frame_out_of_range() {
    let c = Case::new();
    let out = c.path("x.png");
    one_line_error(
        umbra(&["render", &s(&c.rec()), "--frame", "99", "--out", &s(&out)]),
        &[
            "frame 99",
            "out of range",
            &s(&c.rec()),
            "2 depth frames",
            "--frame 0 to 1",
        ],
    );
    assert!(!out.exists());
}

// ---------------------------------------------------------------- 6. ground truth

#[test]
fn eval_ground_truth_wrong_size() {
    let c = Case::new();
    let (ok, e) = umbra(&["eval", &s(&c.rec()), "--gt", &s(&c.gt())]);
    assert!(ok, "eval on the pristine copy must pass: {e}");
    let bad = c.gt().join("000001.rgb.png");
    write_gray_png(&bad, 320, 240, vec![0; 320 * 240]);
    one_line_error(
        umbra(&["eval", &s(&c.rec()), "--gt", &s(&c.gt())]),
        &[&s(&bad), "320x240", "640x480"],
    );
}

#[test]
fn eval_ground_truth_meta_syntax_error() {
    let c = Case::new();
    let meta = c.gt().join("meta.toml");
    std::fs::write(&meta, "category = = \"simple\"\n").unwrap();
    one_line_error(
        umbra(&["eval", &s(&c.rec()), "--gt", &s(&c.gt())]),
        &[&s(&meta), "line 1, column "],
    );
}

#[test]
fn eval_ground_truth_value_not_a_label() {
    let c = Case::new();
    let bad = c.gt().join("000000.depth.png");
    let mut px = image::open(&bad).unwrap().into_luma8().into_raw();
    assert_eq!(px.len(), W * H);
    let (x, y) = (10, 20);
    px[y * W + x] = 7;
    write_gray_png(&bad, W as u32, H as u32, px);
    one_line_error(
        umbra(&["eval", &s(&c.rec()), "--gt", &s(&c.gt())]),
        &[&s(&bad), &format!("pixel ({x}, {y})"), "value 7", "0-4"],
    );
}

#[test]
fn eval_reads_16_bit_ground_truth_as_the_8_bit_one() {
    // numpy and OpenCV write uint16 label arrays as 16-bit grey PNGs: the same codes.
    let c = Case::new();
    let json = || {
        let out = Command::new(env!("CARGO_BIN_EXE_umbra"))
            .args(["eval", &s(&c.rec()), "--gt", &s(&c.gt()), "--json"])
            .output()
            .unwrap();
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        out.stdout
    };
    let eight = json();
    let path = c.gt().join("000000.depth.png");
    let codes = image::open(&path).unwrap().into_luma8().into_raw();
    let wide: Vec<u16> = codes.iter().map(|&v| u16::from(v)).collect();
    let save = |px: Vec<u16>| {
        image::ImageBuffer::<image::Luma<u16>, _>::from_raw(W as u32, H as u32, px)
            .unwrap()
            .save(&path)
            .unwrap()
    };
    save(wide.clone());
    assert_eq!(json(), eight, "same scores from the 16-bit file");
    let mut bad = wide;
    bad[5 * W + 7] = 300;
    save(bad);
    one_line_error(
        umbra(&["eval", &s(&c.rec()), "--gt", &s(&c.gt())]),
        &[&s(&path), "pixel (7, 5)", "300"],
    );
    // Colour label pictures are not label maps.
    image::RgbImage::new(W as u32, H as u32)
        .save(&path)
        .unwrap();
    one_line_error(
        umbra(&["eval", &s(&c.rec()), "--gt", &s(&c.gt())]),
        &[&s(&path), "colour type", "8-bit grey"],
    );
}

#[test]
fn eval_ground_truth_for_no_frame_of_the_recording() {
    let c = Case::new();
    // Label files there are, but numbered past the recording's frames: another recording's.
    for view in ["depth", "rgb"] {
        for i in 0..2 {
            let from = c.gt().join(format!("{i:06}.{view}.png"));
            std::fs::rename(&from, c.gt().join(format!("{:06}.{view}.png", i + 40))).unwrap();
        }
    }
    let first = c.gt().join("000000.depth.png");
    one_line_error(
        umbra(&["eval", &s(&c.rec()), "--gt", &s(&c.gt())]),
        &[&s(&first), "no ground truth for any", "up to frame 41"],
    );
}

// ---------------------------------------------------------------- 7. nothing already written is lost

#[test]
fn failed_export_keeps_earlier_labels() {
    let c = Case::new();
    let out = c.path("labels");
    let (ok, e) = umbra(&["replay", &s(&c.rec()), "--export-labels", &s(&out)]);
    assert!(ok, "{e}");
    let before = snapshot(&out);
    let names: Vec<&str> = before.iter().map(|(n, _)| n.as_str()).collect();
    assert_eq!(
        names,
        [
            "000000.depth.png",
            "000000.rgb.png",
            "000001.depth.png",
            "000001.rgb.png"
        ]
    );

    // Frame 1 of a second recording is cut short; the export runs into the same folder.
    // Frames are written in order and atomically (temp file + rename), so frame 0 is rewritten
    // whole (with the same labels: the recordings agree on it), frame 1 is never touched and no
    // `.part` file is left behind.
    let bad = c.path("bad");
    copy_dir(&c.rec(), &bad);
    let d = bad.join(c.depth(1).file_name().unwrap());
    std::fs::write(&d, &read(&d)[..300_000]).unwrap();
    let (ok, e) = umbra(&["replay", &s(&bad), "--export-labels", &s(&out)]);
    // Replacing an earlier export is said first (a warning), then the error in one line.
    let (warnings, error): (Vec<&str>, Vec<&str>) = e.lines().partition(|l| l.contains(" WARN "));
    assert!(
        warnings.len() == 1
            && warnings[0].contains("replacing the label PNGs of an earlier export"),
        "{e}"
    );
    let error: String = error.iter().map(|l| format!("{l}\n")).collect();
    one_line_error((ok, error), &[&s(&d), "truncated"]);

    let after = snapshot(&out);
    let names_after: Vec<&str> = after.iter().map(|(n, _)| n.as_str()).collect();
    assert_eq!(names_after, names, "the failed run added or removed files");
    for ((name, a), (_, b)) in before.iter().zip(&after) {
        assert!(a == b, "{name} changed in the failed run");
        let img =
            image::load_from_memory(b).unwrap_or_else(|e| panic!("{name} is not a whole PNG: {e}"));
        assert_eq!((img.width(), img.height()), (W as u32, H as u32), "{name}");
    }
}

#[test]
fn failed_render_keeps_existing_output() {
    let c = Case::new();
    let out = c.path("frame.png");
    let (ok, e) = umbra(&["render", &s(&c.rec()), "--frame", "0", "--out", &s(&out)]);
    assert!(ok, "{e}");
    let before = read(&out);
    let d = c.depth(0);
    std::fs::write(&d, &read(&d)[..DEPTH_HEADER.len() + 10]).unwrap();
    one_line_error(
        umbra(&["render", &s(&c.rec()), "--frame", "0", "--out", &s(&out)]),
        &[&s(&d), "truncated"],
    );
    assert!(read(&out) == before, "the earlier render was damaged");
}

// ---------------------------------------------------------------- 8. unwritable output

#[test]
fn export_labels_into_a_regular_file() {
    let c = Case::new();
    let file = c.path("not-a-folder");
    std::fs::write(&file, "keep me").unwrap();
    one_line_error(
        umbra(&["replay", &s(&c.rec()), "--export-labels", &s(&file)]),
        &[&s(&file), "not a folder"],
    );
    assert_eq!(read(&file), b"keep me");
    let below = file.join("labels");
    one_line_error(
        umbra(&["replay", &s(&c.rec()), "--export-labels", &s(&below)]),
        &[&s(&below)],
    );
    assert_eq!(read(&file), b"keep me");
}

#[test]
fn render_into_a_missing_folder_makes_it() {
    // As --export-labels does.
    let c = Case::new();
    let out = c.path("no-such-dir").join("x.png");
    let (ok, e) = umbra(&["render", &s(&c.rec()), "--frame", "0", "--out", &s(&out)]);
    assert!(ok && out.is_file(), "{e}");
}

#[test]
fn render_onto_a_folder() {
    let c = Case::new();
    let out = c.path("a-folder");
    std::fs::create_dir(&out).unwrap();
    std::fs::write(out.join("inside"), "keep me").unwrap();
    one_line_error(
        umbra(&["render", &s(&c.rec()), "--frame", "0", "--out", &s(&out)]),
        &[&s(&out)],
    );
    assert_eq!(read(&out.join("inside")), b"keep me");
    let leftovers: Vec<_> = std::fs::read_dir(c.tmp.path())
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .filter(|n| n.to_string_lossy().ends_with(".part"))
        .collect();
    assert!(
        leftovers.is_empty(),
        "temporary files left behind: {leftovers:?}"
    );
}

/// Depth that does not fit the raw model is no malformed file, but the labels would be quietly
/// wrong: a zero-disparity value under most of the frame's raw values, or a millimetre stream's
/// zeros, are warned about (replay still runs).
#[test]
fn depth_the_raw_model_cannot_read_is_warned_about() {
    let c = Case::new();
    c.edit_calibration("denominator = 1092.5", "denominator = 500.0");
    let err = c.replay_ok();
    assert!(err.contains("zero disparity (500)"), "{err}");

    let c = Case::new();
    for i in 0..2 {
        let d = c.depth(i);
        let mut bytes = read(&d);
        let header = bytes.len() - 2 * 640 * 480;
        // Half the frame at 0, as a millimetre stream's holes are.
        for px in bytes[header..].chunks_exact_mut(2).step_by(2) {
            px.copy_from_slice(&0u16.to_le_bytes());
        }
        std::fs::write(&d, bytes).unwrap();
    }
    let err = c.replay_ok();
    assert!(err.contains("millimetre"), "{err}");

    let c = Case::new();
    let err = c.replay_ok();
    assert!(!err.contains("WARN"), "a plain recording: {err}");
}
