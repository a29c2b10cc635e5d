//! `umbra record` (issue 3, item 5) through the REAL libfreenect API served by Debian's fakenect:
//! the recording it makes must hold exactly the frames fakenect played (pixels, order, device
//! timestamps), the calibration of the source, and label exactly as the original under replay.
//! Skips, saying why, only when the fakenect library is not installed.

mod common;

use std::path::{Path, PathBuf};
use std::process::Command;

use common::{fakenect_dir, one_line_error, s, umbra};
use umbra::recording::Recording;

fn ok(mut c: Command) -> String {
    let out = c.output().unwrap();
    assert!(
        out.status.success(),
        "{c:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8_lossy(&out.stdout).into_owned()
}

fn synth(dir: &Path, frames: usize) -> PathBuf {
    let rec = dir.join("source");
    let mut c = umbra();
    c.args([
        "synth",
        &s(&rec),
        "--gt",
        &s(&dir.join("gt")),
        "--scene",
        "complex",
        "--frames",
        &frames.to_string(),
    ]);
    ok(c);
    rec
}

fn record(fakenect: &str, from: &Path, to: &Path, extra: &[&str]) -> String {
    let mut c = umbra();
    c.env("FAKENECT_PATH", from)
        .env("LD_LIBRARY_PATH", fakenect)
        .args(["record", "--out", &s(to)])
        .args(extra);
    ok(c)
}

/// Names of the d- (or r-) files of a recording's INDEX.txt, in order.
fn index(rec: &Path, kind: char) -> Vec<String> {
    std::fs::read_to_string(rec.join("INDEX.txt"))
        .unwrap()
        .lines()
        .filter(|l| l.starts_with(kind))
        .map(str::to_string)
        .collect()
}

/// Device timestamp and pixel bytes (after the header) of a PGM/PPM named in INDEX.txt.
fn frame(rec: &Path, name: &str) -> (String, Vec<u8>) {
    let ts = name
        .rsplit_once('-')
        .unwrap()
        .1
        .split_once('.')
        .unwrap()
        .0
        .to_string();
    let bytes = std::fs::read(rec.join(name)).unwrap();
    let header = bytes.iter().position(|&b| b == b'\n').unwrap() + 1;
    (ts, bytes[header..].to_vec())
}

#[test]
fn a_recording_of_fakenect_holds_exactly_what_it_played() {
    let Some(fakenect) = fakenect_dir() else {
        return;
    };
    let tmp = tempfile::tempdir().unwrap();
    let source = synth(tmp.path(), 12);
    let copy = tmp.path().join("copy");
    let summary = record(fakenect, &source, &copy, &[]);
    assert!(
        summary.starts_with("umbra record: 12 depth and 12 RGB frames"),
        "{summary}"
    );
    for kind in ['d', 'r'] {
        let (a, b) = (index(&source, kind), index(&copy, kind));
        assert_eq!(a.len(), b.len(), "{kind} frames");
        for (x, y) in a.iter().zip(&b) {
            assert!(
                frame(&source, x) == frame(&copy, y),
                "{y} differs from {x} (pixels or device timestamp)"
            );
        }
    }
    let (a, b) = (
        Recording::open(&source).unwrap(),
        Recording::open(&copy).unwrap(),
    );
    assert_eq!(
        a.calibration(),
        b.calibration(),
        "calibration.toml of the device (fakenect: the recording's)"
    );
    // Labels under replay: the copy is the original.
    let (la, lb) = (tmp.path().join("labels-a"), tmp.path().join("labels-b"));
    for (rec, out) in [(&source, &la), (&copy, &lb)] {
        let mut c = umbra();
        c.args(["replay", &s(rec), "--export-labels", &s(out)]);
        ok(c);
    }
    for i in 0..12 {
        for view in ["depth", "rgb"] {
            let n = format!("{i:06}.{view}.png");
            assert!(
                std::fs::read(la.join(&n)).unwrap() == std::fs::read(lb.join(&n)).unwrap(),
                "{n}"
            );
        }
    }
}

#[test]
fn frames_limit_stops_after_exactly_n_depth_frames() {
    let Some(fakenect) = fakenect_dir() else {
        return;
    };
    let tmp = tempfile::tempdir().unwrap();
    let source = synth(tmp.path(), 15);
    let copy = tmp.path().join("copy");
    let summary = record(fakenect, &source, &copy, &["--frames", "6"]);
    assert!(
        summary.starts_with("umbra record: 6 depth and "),
        "{summary}"
    );
    let (a, b) = (index(&source, 'd'), index(&copy, 'd'));
    assert_eq!(b.len(), 6);
    for (x, y) in a.iter().zip(&b) {
        assert!(frame(&source, x) == frame(&copy, y), "{y}");
    }
    assert_eq!(Recording::open(&copy).unwrap().len(), 6);
}

#[test]
fn a_used_folder_and_conflicting_limits_are_refused() {
    let tmp = tempfile::tempdir().unwrap();
    let used = tmp.path().join("used");
    std::fs::create_dir(&used).unwrap();
    std::fs::write(used.join("keep.txt"), b"mine").unwrap();
    let out = umbra()
        .args(["record", "--out", &s(&used)])
        .output()
        .unwrap();
    one_line_error(
        out.status.success(),
        &String::from_utf8_lossy(&out.stderr),
        &[&s(&used), "not empty"],
    );
    assert_eq!(std::fs::read(used.join("keep.txt")).unwrap(), b"mine");
    let out = umbra()
        .args([
            "record",
            "--out",
            &s(&tmp.path().join("new")),
            "--frames",
            "3",
            "--seconds",
            "1",
        ])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2), "a usage error");
    assert!(String::from_utf8_lossy(&out.stderr).contains("cannot be used with"));
    // Without a device nothing is left behind.
    let missing = tmp.path().join("no-device");
    let out = umbra()
        .env("UMBRA_LIBFREENECT", "/nonexistent/libfreenect.so.0.5")
        .args(["record", "--out", &s(&missing)])
        .output()
        .unwrap();
    one_line_error(
        out.status.success(),
        &String::from_utf8_lossy(&out.stderr),
        &["libfreenect0.5"],
    );
    assert!(!missing.exists());
}
