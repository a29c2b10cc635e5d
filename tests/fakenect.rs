//! `umbra run --source kinect` end to end through the REAL libfreenect API, served by
//! libfreenect's own `fakenect` replay library (Debian: libfreenect-bin / libfreenect0.5), which
//! plays a recording at its recorded speed. The environment is set here rather than through the
//! `fakenect` wrapper script, which does not exec, so signals would never reach umbra.
//!
//! The tests skip, saying why, only when the fakenect library is not installed.

mod common;

use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

use common::{fakenect_dir, umbra};
use umbra::sink::labels::{label_path, read_label_png};

/// `umbra run --source kinect --out OUT/mcap --export-labels OUT/labels` with fakenect playing `rec`.
fn under_fakenect(fakenect: &str, rec: &Path, out: &Path) -> Command {
    let mut c = umbra();
    c.env("FAKENECT_PATH", rec)
        .env("LD_LIBRARY_PATH", fakenect)
        .args(["run", "--source", "kinect", "--out"])
        .arg(out.join("mcap"));
    c.arg("--export-labels").arg(out.join("labels"));
    c
}

/// `umbra tail MCAP_DIR --export-labels DIR`: the labels as the daemon's MCAP segments hold them.
fn labels_from_mcap(mcap: &Path, dir: &Path) {
    let mut c = umbra();
    c.arg("tail").arg(mcap).arg("--export-labels").arg(dir);
    ok(c);
}

fn ok(mut c: Command) -> Output {
    let out = c.output().expect("run umbra");
    assert!(
        out.status.success(),
        "{c:?} failed: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    out
}

fn synth(dir: &Path, scene: &str, frames: usize) -> PathBuf {
    let rec = dir.join(format!("rec-{scene}-{frames}"));
    let mut c = umbra();
    c.arg("synth")
        .arg(&rec)
        .arg("--gt")
        .arg(dir.join(format!("gt-{scene}-{frames}")))
        .args(["--scene", scene, "--frames", &frames.to_string()]);
    ok(c);
    rec
}

fn files(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().into_string().unwrap())
        .collect();
    names.sort();
    names
}

/// The summary line `umbra run` prints at exit.
fn summary(out: &Output) -> String {
    let stdout = String::from_utf8_lossy(&out.stdout);
    stdout
        .lines()
        .find(|l| l.starts_with("umbra run: "))
        .unwrap_or_else(|| panic!("no summary in {stdout:?}"))
        .to_string()
}

#[test]
fn fakenect_run_writes_every_frame_with_the_labels_of_replay() {
    let Some(fakenect) = fakenect_dir() else {
        return;
    };
    let tmp = tempfile::tempdir().unwrap();
    let rec = synth(tmp.path(), "complex", 20);
    let out_dir = tmp.path().join("out");
    let t = Instant::now();
    let out = ok(under_fakenect(fakenect, &rec, &out_dir));
    let took = t.elapsed();
    let line = summary(&out);
    assert!(
        line.starts_with("umbra run: 20 frames written, 0 depth and 0 RGB frames dropped"),
        "{line}"
    );
    // 20 frames recorded at 30 fps: fakenect paces them over about 0.63 s.
    assert!(
        took >= Duration::from_millis(600),
        "fakenect should pace at recorded speed, took {took:?}"
    );

    let ref_dir = tmp.path().join("ref");
    let mut replay = umbra();
    replay
        .arg("replay")
        .arg(&rec)
        .arg("--export-labels")
        .arg(&ref_dir);
    ok(replay);
    // Both outputs of the daemon: its label PNGs, and the labels inside its MCAP segments.
    let from_mcap = tmp.path().join("from-mcap");
    labels_from_mcap(&out_dir.join("mcap"), &from_mcap);
    for dir in [out_dir.join("labels"), from_mcap] {
        let names = files(&dir);
        assert_eq!(names.len(), 40, "{names:?}");
        assert_eq!(names, files(&ref_dir));
        for name in &names {
            let (a, b) = (
                std::fs::read(dir.join(name)).unwrap(),
                std::fs::read(ref_dir.join(name)).unwrap(),
            );
            assert!(
                a == b,
                "{}/{name}: live labels differ from replay's",
                dir.display()
            );
        }
    }
}

#[test]
fn sigterm_mid_run_drains_and_exits_zero_within_two_seconds() {
    let Some(fakenect) = fakenect_dir() else {
        return;
    };
    let tmp = tempfile::tempdir().unwrap();
    let rec = synth(tmp.path(), "simple", 60);
    let out_dir = tmp.path().join("out");
    let mut child = under_fakenect(fakenect, &rec, &out_dir)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    // Signal once a few frames are on disk, well before the 2 s recording ends.
    let t = Instant::now();
    while !out_dir.join("labels/000005.rgb.png").exists() {
        assert!(t.elapsed() < Duration::from_secs(10), "no frames written");
        std::thread::sleep(Duration::from_millis(5));
    }
    assert!(Command::new("kill")
        .args(["-TERM", &child.id().to_string()])
        .status()
        .unwrap()
        .success());
    let signalled = Instant::now();
    let status = loop {
        if let Some(s) = child.try_wait().unwrap() {
            break s;
        }
        assert!(
            signalled.elapsed() < Duration::from_secs(2),
            "still running 2 s after SIGTERM"
        );
        std::thread::sleep(Duration::from_millis(5));
    };
    let out = child.wait_with_output().unwrap();
    assert!(
        status.success(),
        "exit {status:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    let line = summary(&out);
    assert!(
        line.contains("(stopped by signal)") && line.contains(" 0 depth and 0 RGB frames dropped"),
        "{line}"
    );
    let n: usize = line["umbra run: ".len()..]
        .split(' ')
        .next()
        .unwrap()
        .parse()
        .unwrap();
    assert!((6..60).contains(&n), "{line}");
    // Complete files: exactly frames 0..n, both views, each a whole label image, in the PNG
    // export and in the closed MCAP segment.
    let from_mcap = tmp.path().join("from-mcap");
    labels_from_mcap(&out_dir.join("mcap"), &from_mcap);
    for dir in [out_dir.join("labels"), from_mcap] {
        let names = files(&dir);
        assert_eq!(names.len(), 2 * n, "{}: {names:?}", dir.display());
        let mut labels = vec![0u8; 640 * 480];
        for i in 0..n {
            for view in ["depth", "rgb"] {
                read_label_png(&label_path(&dir, i, view), &mut labels)
                    .unwrap_or_else(|e| panic!("frame {i} {view}: {e}"));
            }
        }
    }
}

#[test]
fn missing_libfreenect_is_one_line_naming_the_package() {
    let tmp = tempfile::tempdir().unwrap();
    let out_dir = tmp.path().join("out");
    let out = umbra()
        .env("UMBRA_LIBFREENECT", "/nonexistent/libfreenect.so.0.5")
        .args(["run", "--source", "kinect", "--out"])
        .arg(&out_dir)
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(stderr, "umbra: error: /nonexistent/libfreenect.so.0.5 not found: install it with 'apt-get install libfreenect0.5'\n");
    assert!(
        !out_dir.exists(),
        "nothing is created when capture cannot start"
    );
}

#[test]
fn fakenect_without_a_recording_is_one_line() {
    let Some(fakenect) = fakenect_dir() else {
        return;
    };
    let tmp = tempfile::tempdir().unwrap();
    let out = umbra()
        .env("LD_LIBRARY_PATH", fakenect)
        .args(["run", "--out"])
        .arg(tmp.path().join("out"))
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(stderr.lines().count(), 1, "{stderr}");
    assert!(
        stderr.contains("fakenect") && stderr.contains("FAKENECT_PATH is not set"),
        "{stderr}"
    );
}

/// `umbra replay` ignores an accelerometer file INDEX.txt names but that is missing (umbra never
/// reads one); fakenect exits the process on it, so under fakenect it is refused first, in one
/// line naming the line and the file.
#[test]
fn fakenect_recording_with_a_missing_accelerometer_file_is_one_line() {
    let Some(fakenect) = fakenect_dir() else {
        return;
    };
    let tmp = tempfile::tempdir().unwrap();
    let rec = synth(tmp.path(), "box", 2);
    let index = rec.join("INDEX.txt");
    let text = std::fs::read_to_string(&index).unwrap();
    std::fs::write(&index, format!("{text}a-1700000000.100000-7.dump\n")).unwrap();
    let line = text.lines().count() + 1;
    let out = under_fakenect(fakenect, &rec, &tmp.path().join("out"))
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1));
    let stderr = String::from_utf8_lossy(&out.stderr);
    let errors: Vec<&str> = stderr.lines().filter(|l| !l.contains(" WARN ")).collect();
    assert_eq!(errors.len(), 1, "{stderr}");
    assert!(
        errors[0].contains(&format!("line {line}"))
            && errors[0].contains("a-1700000000.100000-7.dump")
            && errors[0].contains("fakenect"),
        "{stderr}"
    );
}

#[test]
fn devices_lists_the_fakenect_kinect_with_its_source_name() {
    let Some(fakenect) = fakenect_dir() else {
        return;
    };
    let tmp = tempfile::tempdir().unwrap();
    let rec = synth(tmp.path(), "box", 2);
    let mut c = umbra();
    c.env("FAKENECT_PATH", &rec)
        .env("LD_LIBRARY_PATH", fakenect)
        .arg("devices");
    let stdout = String::from_utf8_lossy(&ok(c).stdout).into_owned();
    assert!(
        stdout.starts_with("1 Kinect(s) found through libfreenect.so.0.5 (fakenect replay)"),
        "{stdout}"
    );
    assert!(stdout.contains("--source kinect:0"), "{stdout}");
    let out = umbra()
        .env("LD_LIBRARY_PATH", fakenect)
        .arg("devices")
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        !out.status.success()
            && stderr.lines().count() == 1
            && stderr.contains("FAKENECT_PATH is not set"),
        "{stderr}"
    );
}
