//! `umbra run` as a service (issue 3, item 4), on the bundled recordings: settings from file and
//! flags with `--check-config`, the systemd notify protocol, and `kill -9` mid-write followed by
//! `umbra tail` recovering every complete frame.

mod common;

use std::os::unix::net::UnixDatagram;
use std::path::Path;
use std::process::Stdio;
use std::time::{Duration, Instant};

use common::{bundled, one_line_error, run, s, umbra};

#[test]
fn check_config_accepts_the_shipped_file_and_names_what_is_wrong() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("out");
    let shipped = format!("{}/config/umbra.toml", env!("CARGO_MANIFEST_DIR"));
    let rec = bundled("box-before-wall");
    let (ok, stdout, stderr) = run(&[
        "run",
        "--check-config",
        "--config",
        &shipped,
        "--source",
        &format!("replay:{rec}"),
        "--out",
        &s(&out),
    ]);
    assert!(ok, "{stderr}");
    assert!(
        stdout.starts_with("config OK (") && stdout.contains(&s(&out)),
        "{stdout}"
    );
    assert!(!out.exists(), "checking creates nothing");

    // Flags are optional when the file says it all.
    let cfg = tmp.path().join("u.toml");
    std::fs::write(
        &cfg,
        format!("[run]\nsource = \"replay:{rec}\"\nout = \"{}\"\n", s(&out)),
    )
    .unwrap();
    let (ok, stdout, stderr) = run(&["run", "--check-config", "--config", &s(&cfg)]);
    assert!(
        ok && stdout.contains(&format!("replay:{rec}")),
        "{stdout}{stderr}"
    );

    let bad = |text: &str, needles: &[&str]| {
        std::fs::write(&cfg, text).unwrap();
        let (ok, _, stderr) = run(&[
            "run",
            "--check-config",
            "--config",
            &s(&cfg),
            "--out",
            &s(&out),
        ]);
        let mut all = vec![s(&cfg)];
        all.extend(needles.iter().map(|n| n.to_string()));
        one_line_error(
            ok,
            &stderr,
            &all.iter().map(String::as_str).collect::<Vec<_>>(),
        );
    };
    bad("[mcap]\nzstd_level = 40\n", &["mcap.zstd_level", "40"]);
    bad("[mcap]\nsegment_mb = 5\n", &["line 2", "segment_mb"]);
    bad("[run]\nsource = \"usb:3\"\n", &["run.source", "usb:3"]);
    bad(
        "[device]\nreconnect_initial_s = 5.0\nreconnect_max_s = 1.0\n",
        &["device.reconnect_max_s"],
    );
    bad("[run\n", &["line 1"]);

    // No output folder anywhere; an output "folder" that is a file; a recording that is not there.
    let (ok, _, stderr) = run(&[
        "run",
        "--check-config",
        "--source",
        &format!("replay:{rec}"),
    ]);
    one_line_error(ok, &stderr, &["--out", "run.out"]);
    let file = tmp.path().join("file");
    std::fs::write(&file, b"x").unwrap();
    let (ok, _, stderr) = run(&[
        "run",
        "--check-config",
        "--source",
        &format!("replay:{rec}"),
        "--out",
        &s(&file),
    ]);
    one_line_error(ok, &stderr, &[&s(&file), "not a folder"]);
    let (ok, _, stderr) = run(&[
        "run",
        "--check-config",
        "--source",
        "replay:/nonexistent/rec",
        "--out",
        &s(&out),
    ]);
    one_line_error(ok, &stderr, &["/nonexistent/rec"]);
}

/// Every datagram received on `sock` until `STOPPING=1` or `deadline`.
fn notifications(sock: &UnixDatagram, deadline: Duration) -> Vec<String> {
    sock.set_read_timeout(Some(Duration::from_millis(100)))
        .unwrap();
    let t = Instant::now();
    let mut got = Vec::new();
    let mut buf = [0u8; 4096];
    while t.elapsed() < deadline {
        if let Ok(n) = sock.recv(&mut buf) {
            let msg = String::from_utf8_lossy(&buf[..n]).into_owned();
            let stopping = msg.contains("STOPPING=1");
            got.push(msg);
            if stopping {
                break;
            }
        }
    }
    got
}

#[test]
fn systemd_hears_ready_status_watchdog_and_stopping() {
    let tmp = tempfile::tempdir().unwrap();
    let path = tmp.path().join("notify.sock");
    let sock = UnixDatagram::bind(&path).unwrap();
    // 2 frames played 30 times at recorded speed: about 2 s, two STATUS updates at least.
    let child = umbra()
        .args([
            "run",
            "--source",
            &format!("replay:{}", bundled("box-before-wall")),
            "--repeat",
            "30",
            "--out",
            &s(&tmp.path().join("out")),
        ])
        .env("NOTIFY_SOCKET", &path)
        .env("WATCHDOG_USEC", "1000000")
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let got = notifications(&sock, Duration::from_secs(20));
    let out = child.wait_with_output().unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert_eq!(
        got.first().map(String::as_str),
        Some("READY=1\n"),
        "{got:?}"
    );
    assert_eq!(
        got.last().map(String::as_str),
        Some("STOPPING=1\n"),
        "{got:?}"
    );
    let status: Vec<&String> = got.iter().filter(|m| m.starts_with("STATUS=")).collect();
    assert!(status.len() >= 2, "{got:?}");
    // While frames flow: ~30 fps, nothing dropped, and the watchdog is fed with each status.
    let busy = status
        .iter()
        .find(|m| m.contains(" fps") && !m.starts_with("STATUS=0.0"))
        .unwrap_or_else(|| panic!("{got:?}"));
    let fps: f64 = busy["STATUS=".len()..]
        .split(' ')
        .next()
        .unwrap()
        .parse()
        .unwrap();
    assert!((20.0..40.0).contains(&fps), "{busy}");
    assert!(
        busy.contains("0 dropped, 0 lost")
            && busy.contains("p99 latency")
            && busy.contains("WATCHDOG=1"),
        "{busy}"
    );
}

fn files(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().into_string().unwrap())
        .collect();
    names.sort();
    names
}

#[test]
fn after_kill_9_tail_recovers_every_complete_frame() {
    let tmp = tempfile::tempdir().unwrap();
    let rec = bundled("complex-room");
    let out = tmp.path().join("out");
    // 3 frames played 40 times at 30 fps: 4 s, killed after about 1.
    let mut child = umbra()
        .args([
            "run",
            "--source",
            &format!("replay:{rec}"),
            "--repeat",
            "40",
            "--out",
            &s(&out.join("mcap")),
            "--export-labels",
            &s(&out.join("labels")),
        ])
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let t = Instant::now();
    while !out.join("labels/000020.rgb.png").exists() {
        assert!(t.elapsed() < Duration::from_secs(20), "no frames written");
        std::thread::sleep(Duration::from_millis(5));
    }
    child.kill().unwrap(); // SIGKILL
    child.wait().unwrap();
    // The PNG of frame 20 is written after its MCAP chunk, so at least 21 frames are complete.
    let back = tmp.path().join("back");
    let (ok, stdout, stderr) = run(&[
        "tail",
        &s(&out.join("mcap")),
        "--json",
        "--export-labels",
        &s(&back),
    ]);
    assert!(ok, "{stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
    let seqs: Vec<u64> = stdout
        .lines()
        .map(|l| {
            serde_json::from_str::<serde_json::Value>(l).unwrap()["seq"]
                .as_u64()
                .unwrap()
        })
        .collect();
    assert!(
        seqs.len() >= 21,
        "{} frames recovered: {stderr}",
        seqs.len()
    );
    assert_eq!(
        seqs,
        (0..seqs.len() as u64).collect::<Vec<_>>(),
        "frames 0..n, none torn, none missing"
    );
    // Each recovered frame carries the labels `umbra replay` gives its recording frame.
    let reference = tmp.path().join("ref");
    let (ok, _, stderr) = run(&["replay", &rec, "--export-labels", &s(&reference)]);
    assert!(ok, "{stderr}");
    assert_eq!(files(&back).len(), 2 * seqs.len());
    for &i in &seqs {
        for view in ["depth", "rgb"] {
            let name = |k: u64| format!("{k:06}.{view}.png");
            let (a, b) = (
                std::fs::read(back.join(name(i))).unwrap(),
                std::fs::read(reference.join(name(i % 3))).unwrap(),
            );
            assert!(
                a == b,
                "frame {i} {view}: recovered labels differ from replay's"
            );
        }
    }
}

#[test]
fn the_service_unit_is_hardened_and_systemd_accepts_it() {
    let unit = std::fs::read_to_string(format!(
        "{}/config/umbra@.service",
        env!("CARGO_MANIFEST_DIR")
    ))
    .unwrap();
    let has = |kv: &str| unit.lines().any(|l| l.trim() == kv);
    for kv in [
        "Type=notify",
        "NoNewPrivileges=yes",
        "ProtectSystem=strict",
        "PrivateNetwork=yes",
        "StateDirectory=umbra/%i",
        "User=umbra",
        "SupplementaryGroups=plugdev",
        "DeviceAllow=char-usb_device rw",
    ] {
        assert!(has(kv), "config/umbra@.service lacks {kv}");
    }
    let exec = unit
        .lines()
        .find_map(|l| l.strip_prefix("ExecStart="))
        .unwrap();
    assert!(
        exec.contains(
            "run --config /etc/umbra/umbra.toml --source kinect:%i --out /var/lib/umbra/%i"
        ),
        "{exec}"
    );
    // The shipped config must be what the unit's --config accepts.
    let shipped = format!("{}/config/umbra.toml", env!("CARGO_MANIFEST_DIR"));
    let (ok, _, stderr) = run(&[
        "run",
        "--check-config",
        "--config",
        &shipped,
        "--source",
        "kinect:A00362A09433114A",
        "--out",
        "/tmp/umbra-unit-check",
    ]);
    assert!(ok, "{stderr}");
    // systemd's own checker, where systemd is installed, with ExecStart pointing at this build.
    let Ok(probe) = std::process::Command::new("systemd-analyze")
        .arg("--version")
        .output()
    else {
        eprintln!("SKIPPED systemd-analyze verify: systemd-analyze is not installed");
        return;
    };
    assert!(probe.status.success());
    let tmp = tempfile::tempdir().unwrap();
    let path = tmp.path().join("umbra@A00362A09433114A.service");
    std::fs::write(
        &path,
        unit.replace("/usr/local/bin/umbra", env!("CARGO_BIN_EXE_umbra")),
    )
    .unwrap();
    let out = std::process::Command::new("systemd-analyze")
        .arg("verify")
        .arg(&path)
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    // Messages about the host's other units are not ours; ones naming this unit are.
    let ours: Vec<&str> = stderr.lines().filter(|l| l.contains("umbra@")).collect();
    assert!(
        out.status.success() && ours.is_empty(),
        "systemd-analyze verify: {stderr}"
    );
}

#[test]
fn foreground_masks_in_the_daemon_match_the_ground_truth() {
    let tmp = tempfile::tempdir().unwrap();
    let cfg = tmp.path().join("u.toml");
    std::fs::write(&cfg, "[foreground]\nrate_hz = 30.0\n").unwrap();
    let out = tmp.path().join("out");
    let rec = bundled("box-before-wall");
    let (ok, _, stderr) = run(&[
        "run",
        "--config",
        &s(&cfg),
        "--source",
        &format!("replay:{rec}"),
        "--out",
        &s(&out),
    ]);
    assert!(ok, "{stderr}");
    let seg = std::fs::read_dir(&out)
        .unwrap()
        .next()
        .unwrap()
        .unwrap()
        .path();
    let bytes = std::fs::read(seg).unwrap();
    let mut masks = 0;
    for m in mcap::MessageStream::new(&bytes).unwrap() {
        let m = m.unwrap();
        if m.channel.topic != "/umbra/foreground_mask" {
            continue;
        }
        masks += 1;
        let (h, pixels) = umbra::sink::mcap::ros2::decode_image(&m.data).unwrap();
        assert_eq!((h.encoding, h.width, h.height), ("mono8", 640, 480));
        // The simulator's exact mask of the same frame (independent of the segmenter).
        let gt = image::open(format!(
            "{rec}/../ground-truth/box-before-wall/{:06}.fg.png",
            m.sequence
        ))
        .unwrap()
        .to_luma8();
        let (mut inter, mut union) = (0u32, 0u32);
        for (&p, &g) in pixels.iter().zip(gt.as_raw()) {
            inter += u32::from(p == 255 && g == 255);
            union += u32::from(p == 255 || g == 255);
        }
        let iou = f64::from(inter) / f64::from(union.max(1));
        assert!(
            iou >= 0.9,
            "frame {}: IoU {iou:.3} with the ground-truth mask",
            m.sequence
        );
    }
    assert!(masks >= 1, "no foreground mask written");
}

/// `umbra run --source replay:REC --fast --out MCAP [--export-labels LABELS]`.
fn fast_replay_run(rec: &str, mcap: &Path, labels: Option<&Path>) -> (bool, String, String) {
    let source = format!("replay:{rec}");
    let out = s(mcap);
    let mut args = vec!["run", "--source", &source, "--fast", "--out", &out];
    let labels = labels.map(s);
    if let Some(l) = &labels {
        args.extend(["--export-labels", l]);
    }
    run(&args)
}

/// The daemon numbers frames from 0 at every start; a restart (a service's, say) with the same
/// `--export-labels` folder keeps the run before's label PNGs and writes after them, never over
/// them. Nothing else in the folder is accepted, as for `replay`.
#[test]
fn a_restarted_daemon_keeps_the_labels_of_the_run_before() {
    let tmp = tempfile::tempdir().unwrap();
    let rec = bundled("box-before-wall");
    let (mcap, labels) = (tmp.path().join("mcap"), tmp.path().join("labels"));
    let daemon = || fast_replay_run(&rec, &mcap, Some(&labels));
    let (ok, _, stderr) = daemon();
    assert!(ok, "{stderr}");
    let first: Vec<(String, Vec<u8>)> = files(&labels)
        .into_iter()
        .map(|n| {
            let bytes = std::fs::read(labels.join(&n)).unwrap();
            (n, bytes)
        })
        .collect();
    let n = first.len() / 2;
    assert!(n >= 2, "{first:?}");
    let (ok, _, stderr) = daemon();
    assert!(ok, "{stderr}");
    assert!(stderr.contains(&format!("written as {n:06}")), "{stderr}");
    assert_eq!(files(&labels).len(), 4 * n);
    for (name, bytes) in &first {
        assert!(
            std::fs::read(labels.join(name)).unwrap() == *bytes,
            "{name} changed"
        );
    }
    // The second session's frame k is the first's frame k, written as n + k.
    for k in 0..n {
        let a = std::fs::read(labels.join(format!("{k:06}.rgb.png"))).unwrap();
        let b = std::fs::read(labels.join(format!("{:06}.rgb.png", n + k))).unwrap();
        assert!(a == b, "frame {k}");
    }
    std::fs::write(labels.join("notes.txt"), "mine").unwrap();
    let (ok, _, stderr) = daemon();
    assert!(!ok && stderr.contains("notes.txt"), "{stderr}");
}

/// `umbra tail --export-labels` read to the end leaves exactly the segments' frames in the
/// folder: an earlier export's frames past the last one are removed, as replay's export does.
#[test]
fn tail_export_replaces_an_earlier_export_whole() {
    let tmp = tempfile::tempdir().unwrap();
    let rec = bundled("box-before-wall");
    let (mcap, labels) = (tmp.path().join("mcap"), tmp.path().join("labels"));
    let (ok, _, stderr) = fast_replay_run(&rec, &mcap, None);
    assert!(ok, "{stderr}");
    std::fs::create_dir(&labels).unwrap();
    std::fs::write(labels.join("000009.depth.png"), b"an earlier export's").unwrap();
    let (ok, _, stderr) = run(&["tail", &s(&mcap), "--export-labels", &s(&labels)]);
    assert!(ok, "{stderr}");
    let names = files(&labels);
    assert!(!names.iter().any(|n| n.starts_with("000009")), "{names:?}");
    assert_eq!(names.len(), 4, "two frames, two views: {names:?}");
}
