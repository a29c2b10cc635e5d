//! SPEC §5: every malformed input ends in ONE line naming the file, the place in it and what was
//! expected, with a non-zero exit status; no panic; and what was already written stays intact.

use std::path::{Path, PathBuf};
use std::process::Command;

fn umbra(args: &[&str]) -> (bool, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_umbra")).args(args).output().expect("run umbra");
    (out.status.success(), String::from_utf8_lossy(&out.stderr).into_owned())
}

/// A valid two-frame recording made by the simulator, copied per case so each can be broken.
struct Fixture {
    dir: tempfile::TempDir,
}

impl Fixture {
    fn new() -> Self {
        let dir = tempfile::tempdir().unwrap();
        let (ok, err) = umbra(&["synth", &p(&dir.path().join("good")), "--gt", &p(&dir.path().join("gt")), "--scene", "box", "--frames", "2"]);
        assert!(ok, "{err}");
        Fixture { dir }
    }

    /// A copy of the good recording named `name`.
    fn copy(&self, name: &str) -> PathBuf {
        let to = self.dir.path().join(name);
        std::fs::create_dir_all(&to).unwrap();
        for e in std::fs::read_dir(self.dir.path().join("good")).unwrap() {
            let e = e.unwrap();
            std::fs::copy(e.path(), to.join(e.file_name())).unwrap();
        }
        to
    }

    fn depth_files(&self, rec: &Path) -> Vec<PathBuf> {
        let mut v: Vec<PathBuf> = std::fs::read_dir(rec).unwrap().map(|e| e.unwrap().path()).filter(|p| p.extension().is_some_and(|x| x == "pgm")).collect();
        v.sort();
        v
    }
}

fn p(path: &Path) -> String {
    path.display().to_string()
}

/// Asserts a failed run printed exactly one `umbra: error:` line containing every `needle`.
fn one_line_error(ok: bool, stderr: &str, needles: &[&str]) {
    assert!(!ok, "expected failure, got success; stderr: {stderr}");
    assert!(!stderr.contains("panicked") && !stderr.contains("RUST_BACKTRACE"), "{stderr}");
    let lines: Vec<&str> = stderr.lines().collect();
    assert_eq!(lines.len(), 1, "expected one line: {stderr}");
    assert!(lines[0].starts_with("umbra: error: "), "{stderr}");
    for n in needles {
        assert!(lines[0].contains(n), "{n:?} missing from: {stderr}");
    }
}

#[test]
fn recording_folder_problems() {
    let f = Fixture::new();
    let (ok, e) = umbra(&["replay", &p(&f.dir.path().join("nope"))]);
    one_line_error(ok, &e, &["nope", "INDEX.txt"]);

    let rec = f.copy("bad_index");
    std::fs::write(rec.join("INDEX.txt"), format!("{}garbage line\n", std::fs::read_to_string(rec.join("INDEX.txt")).unwrap())).unwrap();
    let (ok, e) = umbra(&["replay", &p(&rec)]);
    one_line_error(ok, &e, &["INDEX.txt", "line 5", "garbage line"]);

    let rec = f.copy("missing_frame");
    let last = f.depth_files(&rec).pop().unwrap();
    std::fs::remove_file(&last).unwrap();
    let (ok, e) = umbra(&["replay", &p(&rec)]);
    one_line_error(ok, &e, &["INDEX.txt", "line 3", last.file_name().unwrap().to_str().unwrap(), "does not exist"]);
}

#[test]
fn depth_file_problems() {
    let f = Fixture::new();
    let rec = f.copy("truncated");
    let d = f.depth_files(&rec).remove(0);
    let bytes = std::fs::read(&d).unwrap();
    std::fs::write(&d, &bytes[..bytes.len() - 1000]).unwrap();
    let (ok, e) = umbra(&["replay", &p(&rec)]);
    one_line_error(ok, &e, &[d.file_name().unwrap().to_str().unwrap(), "truncated", "614400"]);

    // 0x0900 little-endian at pixel (3, 2): 2304 > 2047.
    let rec = f.copy("too_big");
    let d = f.depth_files(&rec).remove(0);
    let mut bytes = std::fs::read(&d).unwrap();
    let header = bytes.len() - 640 * 480 * 2;
    let at = header + 2 * (2 * 640 + 3);
    bytes[at] = 0x00;
    bytes[at + 1] = 0x09;
    std::fs::write(&d, bytes).unwrap();
    let (ok, e) = umbra(&["replay", &p(&rec)]);
    one_line_error(ok, &e, &["pixel (3, 2)", "2304", "above 2047"]);

    let rec = f.copy("wrong_size");
    let d = f.depth_files(&rec).remove(0);
    std::fs::write(&d, [b"P5 320 240 65535\n".as_slice(), &vec![0u8; 320 * 240 * 2]].concat()).unwrap();
    let (ok, e) = umbra(&["replay", &p(&rec)]);
    one_line_error(ok, &e, &["320x240", "640x480"]);
}

#[test]
fn calibration_problems() {
    let f = Fixture::new();
    for (name, from, to, needles) in [
        ("syntax", "fx = 582.62", "fx = = 1", vec!["calibration.toml", "line 2, column"]),
        ("nan", "fx = 582.62", "fx = nan", vec!["calibration.toml", "key depth.fx"]),
        ("baseline", "baseline_m = 0.075", "baseline_m = 7.5", vec!["calibration.toml", "raw.baseline_m"]),
        ("unknown_key", "fx = 582.62", "fx = 582.62\nfocal = 3", vec!["calibration.toml", "focal"]),
    ] {
        let rec = f.copy(name);
        let c = std::fs::read_to_string(rec.join("calibration.toml")).unwrap();
        assert!(c.contains(from), "{name}: fixture changed");
        std::fs::write(rec.join("calibration.toml"), c.replacen(from, to, 1)).unwrap();
        let (ok, e) = umbra(&["replay", &p(&rec)]);
        one_line_error(ok, &e, &needles);
    }
    let rec = f.copy("device_json");
    std::fs::remove_file(rec.join("calibration.toml")).unwrap();
    std::fs::write(rec.join("device.json"), "{\"reg_info\": {").unwrap();
    let (ok, e) = umbra(&["replay", &p(&rec)]);
    one_line_error(ok, &e, &["device.json", "line"]);
}

#[test]
fn request_and_output_problems_and_nothing_lost() {
    let f = Fixture::new();
    let good = p(&f.dir.path().join("good"));
    let (ok, e) = umbra(&["render", &good, "--frame", "9", "--out", &p(&f.dir.path().join("x.png"))]);
    one_line_error(ok, &e, &["frame 9", "2 depth frames"]);

    let file = f.dir.path().join("a_file");
    std::fs::write(&file, "x").unwrap();
    let (ok, e) = umbra(&["replay", &good, "--export-labels", &p(&file)]);
    one_line_error(ok, &e, &["a_file", "not a folder"]);

    // A good export, then a failing one into the same folder: the first run's files survive whole.
    let out = f.dir.path().join("labels");
    let (ok, e) = umbra(&["replay", &good, "--export-labels", &p(&out)]);
    assert!(ok, "{e}");
    let before: Vec<Vec<u8>> = ["000000.depth.png", "000001.rgb.png"].iter().map(|n| std::fs::read(out.join(n)).unwrap()).collect();
    let bad = f.copy("bad_second_frame");
    let d = f.depth_files(&bad).pop().unwrap();
    std::fs::write(&d, b"P5 640 480 65535\n").unwrap();
    let (ok, e) = umbra(&["replay", &p(&bad), "--export-labels", &p(&out)]);
    one_line_error(ok, &e, &["truncated"]);
    let after = std::fs::read(out.join("000001.rgb.png")).unwrap();
    assert_eq!(after, before[1], "frame 1 of the good run was overwritten or damaged");
    assert!(image::open(out.join("000000.depth.png")).is_ok(), "frame 0 must stay a whole PNG");
}
