//! Helpers shared by the integration tests that run the `umbra` binary.
#![allow(dead_code)]

use std::path::Path;
use std::process::{Command, Output};

/// The `umbra` binary, with the environment variables that change its behaviour removed.
pub fn umbra() -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_umbra"));
    c.env_remove("UMBRA_LIBFREENECT")
        .env_remove("FAKENECT_PATH")
        .env_remove("RUST_LOG")
        .env_remove("NOTIFY_SOCKET")
        .env_remove("WATCHDOG_USEC");
    c
}

/// Runs `umbra ARGS`: (success, stdout, stderr).
pub fn run(args: &[&str]) -> (bool, String, String) {
    let out: Output = umbra().args(args).output().expect("run umbra");
    (
        out.status.success(),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// SPEC §5: a failure whose stderr is exactly one `umbra: error: ` line containing every needle,
/// with no panic or backtrace.
#[track_caller]
pub fn one_line_error(ok: bool, stderr: &str, needles: &[&str]) {
    assert!(!ok, "expected a failure, got success; stderr: {stderr:?}");
    assert!(
        !stderr.contains("panicked") && !stderr.contains("RUST_BACKTRACE"),
        "panic: {stderr}"
    );
    assert!(
        stderr.ends_with('\n') && stderr.matches('\n').count() == 1,
        "expected exactly one line: {stderr:?}"
    );
    assert!(stderr.starts_with("umbra: error: "), "{stderr:?}");
    for n in needles {
        assert!(stderr.contains(n), "{n:?} missing from: {stderr}");
    }
}

/// A path as a string argument.
pub fn s(p: &Path) -> String {
    p.display().to_string()
}

/// The bundled recording `name` under recordings/.
pub fn bundled(name: &str) -> String {
    format!("{}/recordings/{name}", env!("CARGO_MANIFEST_DIR"))
}

/// Where Debian puts libfreenect's fakenect replay library.
pub const FAKENECT_DIRS: [&str; 3] = [
    "/usr/lib/x86_64-linux-gnu/fakenect",
    "/usr/lib/aarch64-linux-gnu/fakenect",
    "/usr/lib/fakenect",
];

/// The folder holding fakenect's libfreenect.so.0.5, or `None` (and a printed reason to skip).
pub fn fakenect_dir() -> Option<&'static str> {
    let dir = FAKENECT_DIRS
        .into_iter()
        .find(|d| Path::new(d).join("libfreenect.so.0.5").exists());
    if dir.is_none() {
        eprintln!("SKIPPED: libfreenect's fakenect library is not installed (apt-get install libfreenect-bin); looked in {FAKENECT_DIRS:?}");
    }
    dir
}
