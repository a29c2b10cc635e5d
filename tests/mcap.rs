//! MCAP output (issue 3, writer and `umbra tail`): frames written through `McapSink` come back
//! byte for byte; the CDR layout matches one laid out by hand; segments rotate and the cap
//! deletes the oldest; a file cut anywhere (kill -9) yields exactly its complete chunks and a
//! reported torn tail; malformed files are one-line errors; `umbra tail` prints, exports and
//! follows.

mod common;

use std::io::{BufRead, BufReader};
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::sync::atomic::Ordering;
use std::time::{Duration, Instant};

use umbra::classify::Classifier;
use umbra::labels::{histogram, NO_DEPTH, PIXELS, WIDTH};
use umbra::pipeline::Frame;
use umbra::sink::mcap::read::{read_segment, End, Recorded};
use umbra::sink::mcap::ros2::{encode_image, ImageHeader, Pixels};
use umbra::sink::mcap::segment::list_segments;
use umbra::sink::mcap::{McapOptions, McapSink};
use umbra::sink::Sink;
use umbra::Calibration;

use common::one_line_error;

/// `n` classified frames: a box 1 m before a wall at 3 m, moving right, with speckle holes.
fn frames(n: usize) -> Vec<Frame> {
    let calib = Calibration::nyu_default();
    let mut classifier = Classifier::new(&calib);
    let (wall, near) = (
        calib.raw_from_depth(3.0).round() as u16,
        calib.raw_from_depth(1.0).round() as u16,
    );
    (0..n)
        .map(|k| {
            let mut f = Frame {
                seq: k as u64,
                device_ts: (u32::MAX - 1000).wrapping_add(3003 * k as u32),
                unix_time: 1_795_349_700.0 + k as f64 / 30.0,
                ..Frame::default()
            };
            for (i, d) in f.depth.iter_mut().enumerate() {
                let (x, y) = (i % WIDTH, i / WIDTH);
                *d = if (200 + 7 * k..380 + 7 * k).contains(&x) && (140..340).contains(&y) {
                    near
                } else {
                    wall + (x / 64) as u16
                };
                if (i * 7919 + k * 13) % 997 == 0 {
                    *d = NO_DEPTH;
                }
            }
            for (i, c) in f.rgb.iter_mut().enumerate() {
                *c = (i * 31 + k) as u8;
            }
            f.has_rgb = k % 2 == 0;
            classifier.classify(&f.depth, &mut f.labels);
            f
        })
        .collect()
}

fn opts() -> McapOptions {
    McapOptions {
        write_rgb: true,
        retry_interval: Duration::ZERO,
        ..McapOptions::default()
    }
}

fn write_all(dir: &Path, opts: McapOptions, frames: &[Frame]) -> McapSink {
    let mut sink = McapSink::create(dir, opts).unwrap();
    for f in frames {
        sink.write(f).unwrap();
    }
    sink.finish().unwrap();
    sink
}

fn read_folder(dir: &Path) -> Vec<Recorded> {
    list_segments(dir)
        .unwrap()
        .into_iter()
        .flat_map(|(p, _)| read_segment(&p).unwrap().0)
        .collect()
}

fn assert_same(back: &Recorded, f: &Frame, rgb_written: bool) {
    let b = &back.frame;
    assert_eq!((b.seq, b.device_ts), (f.seq, f.device_ts));
    assert!((b.unix_time - f.unix_time).abs() < 1e-6);
    assert!(b.depth == f.depth, "depth of frame {}", f.seq);
    assert!(
        b.labels.ir_labels == f.labels.ir_labels,
        "IR labels of frame {}",
        f.seq
    );
    assert!(
        b.labels.rgb_labels == f.labels.rgb_labels,
        "RGB labels of frame {}",
        f.seq
    );
    assert!(
        b.labels.registered_mm == f.labels.registered_mm,
        "registered depth of frame {}",
        f.seq
    );
    assert_eq!(b.has_rgb, rgb_written && f.has_rgb);
    if b.has_rgb {
        assert!(b.rgb == f.rgb, "RGB of frame {}", f.seq);
    }
    assert_eq!(back.stats.ir.0, histogram(&f.labels.ir_labels));
    assert_eq!(back.stats.rgb.0, histogram(&f.labels.rgb_labels));
}

fn umbra(args: &[&str]) -> (bool, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_umbra"))
        .args(args)
        .output()
        .expect("run umbra");
    (
        out.status.success(),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

fn s(p: &Path) -> String {
    p.display().to_string()
}

#[test]
fn frames_round_trip_byte_for_byte() {
    let dir = tempfile::tempdir().unwrap();
    let input = frames(4);
    let sink = write_all(dir.path(), opts(), &input);
    let segs = list_segments(dir.path()).unwrap();
    assert_eq!(segs.len(), 1);
    let name = segs[0].0.file_name().unwrap().to_str().unwrap().to_string();
    assert!(
        name.starts_with("umbra-") && name.ends_with("Z-0.mcap"),
        "{name}"
    );
    let (back, end) = read_segment(&segs[0].0).unwrap();
    assert_eq!(end, End::Complete);
    assert_eq!(back.len(), input.len());
    for (b, f) in back.iter().zip(&input) {
        assert_same(b, f, true);
    }
    // The frames had some shadow to label, so the comparison means something.
    assert!(input[0].labels.ir_labels.contains(&umbra::labels::ATTACHED));
    assert_eq!(sink.counters().frames_written.load(Ordering::Relaxed), 4);

    // Without the RGB option, no RGB topic; everything else the same.
    let dir2 = tempfile::tempdir().unwrap();
    write_all(
        dir2.path(),
        McapOptions {
            write_rgb: false,
            ..opts()
        },
        &input,
    );
    for (b, f) in read_folder(dir2.path()).iter().zip(&input) {
        assert_same(b, f, false);
    }
}

#[test]
fn cdr_image_matches_a_hand_laid_message() {
    let h = ImageHeader {
        sec: 0x0102_0304,
        nanosec: 5,
        frame_id: "cam",
        height: 1,
        width: 2,
        encoding: "16UC1",
        is_bigendian: 0,
        step: 4,
    };
    let mut got = Vec::new();
    encode_image(&h, Pixels::U16(&[0x0102, 0x07ff]), &mut got);
    #[rustfmt::skip]
    let want: Vec<u8> = vec![
        0x00, 0x01, 0x00, 0x00,             // encapsulation: CDR little-endian
        0x04, 0x03, 0x02, 0x01,             // @0  stamp.sec
        0x05, 0x00, 0x00, 0x00,             // @4  stamp.nanosec
        0x04, 0x00, 0x00, 0x00,             // @8  frame_id length incl. NUL
        b'c', b'a', b'm', 0x00,             // @12
        0x01, 0x00, 0x00, 0x00,             // @16 height
        0x02, 0x00, 0x00, 0x00,             // @20 width
        0x06, 0x00, 0x00, 0x00,             // @24 encoding length incl. NUL
        b'1', b'6', b'U', b'C', b'1', 0x00, // @28
        0x00,                               // @34 is_bigendian
        0x00,                               // @35 padding: step is 4-aligned
        0x04, 0x00, 0x00, 0x00,             // @36 step
        0x04, 0x00, 0x00, 0x00,             // @40 data length
        0x02, 0x01, 0xff, 0x07,             // @44 data, little-endian u16
    ];
    assert_eq!(got, want);
    let (back, data) = umbra::sink::mcap::ros2::decode_image(&want).unwrap();
    assert_eq!((back, data), (h, &want[48..]));
}

#[test]
fn segments_rotate_by_size_and_age_and_the_cap_deletes_the_oldest() {
    let input = frames(6);
    // One frame per segment (size limit 1 byte); measure one segment's size first.
    let probe = tempfile::tempdir().unwrap();
    write_all(
        probe.path(),
        McapOptions {
            segment_bytes: 1,
            ..opts()
        },
        &input[..1],
    );
    let one = list_segments(probe.path()).unwrap()[0].1;

    let dir = tempfile::tempdir().unwrap();
    let cap = 3 * one + one / 2;
    let sink = write_all(
        dir.path(),
        McapOptions {
            segment_bytes: 1,
            total_cap_bytes: cap,
            ..opts()
        },
        &input,
    );
    let segs = list_segments(dir.path()).unwrap();
    let c = sink.counters();
    assert_eq!(c.segments_opened.load(Ordering::Relaxed), 6);
    assert_eq!(
        c.segments_deleted.load(Ordering::Relaxed) as usize,
        6 - segs.len()
    );
    assert!((2..6).contains(&segs.len()), "{segs:?}");
    let back = read_folder(dir.path());
    // What is left is the newest frames, in order, each intact.
    let first = 6 - segs.len();
    assert_eq!(
        back.iter().map(|r| r.frame.seq).collect::<Vec<_>>(),
        (first as u64..6).collect::<Vec<_>>()
    );
    for (b, f) in back.iter().zip(&input[first..]) {
        assert_same(b, f, true);
    }

    // Age: a segment older than the limit is closed before the next frame.
    let aged = tempfile::tempdir().unwrap();
    write_all(
        aged.path(),
        McapOptions {
            segment_age: Duration::from_nanos(1),
            ..opts()
        },
        &input[..3],
    );
    assert_eq!(list_segments(aged.path()).unwrap().len(), 3);
}

/// Offsets where each chunk ends, from the file's own summary: the first holds the schemas and
/// channels, then one per frame.
fn chunk_ends(bytes: &[u8]) -> Vec<u64> {
    let summary = mcap::read::Summary::read(bytes).unwrap().unwrap();
    let mut ends: Vec<u64> = summary
        .chunk_indexes
        .iter()
        .map(|c| c.chunk_start_offset + c.chunk_length)
        .collect();
    ends.sort();
    ends
}

#[test]
fn a_file_cut_anywhere_yields_exactly_its_complete_chunks() {
    let dir = tempfile::tempdir().unwrap();
    let input = frames(3);
    write_all(dir.path(), opts(), &input);
    let path = list_segments(dir.path()).unwrap()[0].0.clone();
    let bytes = std::fs::read(&path).unwrap();
    let ends = chunk_ends(&bytes);
    assert_eq!(
        ends.len(),
        4,
        "a chunk of channels, then one chunk per frame"
    );

    let cut_path = dir.path().join("cut.mcap");
    let mut cuts: Vec<usize> = (0..bytes.len()).step_by(bytes.len() / 97).collect();
    cuts.extend([1, 7, 8, 9, 16]);
    for &e in &ends {
        cuts.extend([e as usize - 1, e as usize, e as usize + 1]);
    }
    for cut in cuts {
        std::fs::write(&cut_path, &bytes[..cut]).unwrap();
        let (back, end) = read_segment(&cut_path).unwrap_or_else(|e| panic!("cut at {cut}: {e}"));
        let complete = ends[1..].iter().filter(|&&e| e <= cut as u64).count();
        assert_eq!(back.len(), complete, "cut at {cut}");
        for (b, f) in back.iter().zip(&input) {
            assert_same(b, f, true);
        }
        match end {
            End::Torn { offset, tail } => assert_eq!(offset + tail, cut as u64, "cut at {cut}"),
            End::Open => {}
            End::Complete => panic!("cut at {cut} read as complete"),
        }
    }

    // A power cut can leave zeros after the last write: a torn tail, not damage.
    let mut zeroed = bytes[..ends[2] as usize].to_vec();
    zeroed.extend([0u8; 5000]);
    std::fs::write(&cut_path, &zeroed).unwrap();
    let (back, end) = read_segment(&cut_path).unwrap();
    assert_eq!(back.len(), 2);
    assert!(
        matches!(end, End::Torn { tail, .. } if tail >= 5000),
        "{end:?}"
    );

    // `umbra tail` prints the complete frames and warns once, naming the file and the offset.
    let mid = (ends[2] + ends[3]) / 2;
    std::fs::write(&cut_path, &bytes[..mid as usize]).unwrap();
    let (ok, out, err) = umbra(&["tail", "--json", &s(&cut_path)]);
    assert!(ok, "{err}");
    assert_eq!(out.lines().count(), 2, "{out}");
    let warn: Vec<&str> = err.lines().collect();
    assert_eq!(warn.len(), 1, "{err}");
    assert!(
        warn[0].contains("cut.mcap") && warn[0].contains("torn tail") && warn[0].contains("byte "),
        "{err}"
    );
}

#[test]
fn malformed_files_are_one_line_errors_naming_file_and_place() {
    let dir = tempfile::tempdir().unwrap();
    let junk = dir.path().join("junk.mcap");
    std::fs::write(&junk, b"this is not an MCAP file at all").unwrap();
    let (ok, _, err) = umbra(&["tail", &s(&junk)]);
    one_line_error(ok, &err, &["junk.mcap", "byte 0", "not an MCAP file"]);

    // A flipped byte inside a complete chunk: its CRC (or zstd) catches it.
    let good = tempfile::tempdir().unwrap();
    write_all(good.path(), opts(), &frames(2));
    let path = list_segments(good.path()).unwrap()[0].0.clone();
    let mut bytes = std::fs::read(&path).unwrap();
    let summary = mcap::read::Summary::read(&bytes).unwrap().unwrap();
    let chunk = &summary.chunk_indexes[2];
    bytes[(chunk.chunk_start_offset + chunk.chunk_length - 100) as usize] ^= 0x5a;
    let bad = dir.path().join("flipped.mcap");
    std::fs::write(&bad, &bytes).unwrap();
    let (ok, _, err) = umbra(&["tail", "--json", &s(&bad)]);
    one_line_error(
        ok,
        &err,
        &[
            "flipped.mcap",
            &format!("byte {}", chunk.chunk_start_offset),
            "chunk",
        ],
    );

    let (ok, _, err) = umbra(&["tail", &s(&dir.path().join("missing"))]);
    one_line_error(ok, &err, &["missing", "no such segment"]);
}

#[test]
fn tail_json_on_a_folder_prints_every_frame_and_exports_labels() {
    let dir = tempfile::tempdir().unwrap();
    let input = frames(3);
    write_all(
        dir.path(),
        McapOptions {
            segment_bytes: 1,
            ..opts()
        },
        &input,
    );
    assert_eq!(list_segments(dir.path()).unwrap().len(), 3);
    let labels = dir.path().join("labels");
    let (ok, out, err) = umbra(&[
        "tail",
        "--json",
        &s(dir.path()),
        "--export-labels",
        &s(&labels),
    ]);
    assert!(ok, "{err}");
    assert!(err.is_empty(), "{err}");
    let lines: Vec<&str> = out.lines().collect();
    assert_eq!(lines.len(), 3, "{out}");
    for (line, f) in lines.iter().zip(&input) {
        let v: serde_json::Value = serde_json::from_str(line).unwrap();
        assert_eq!(v["seq"], f.seq);
        assert_eq!(v["device_ts"], f.device_ts);
        assert!(v["latency_ms"].as_f64().is_some() && v["unix_time"].as_f64().is_some());
        assert_eq!(v["dropped_before"], 0);
        for (view, l) in [("ir", &f.labels.ir_labels), ("rgb", &f.labels.rgb_labels)] {
            let h = histogram(l);
            for (c, name) in umbra::labels::NAMES.iter().enumerate() {
                assert_eq!(v[view][name], h[c], "{view} {name} of frame {}", f.seq);
            }
        }
        let mut back = vec![0u8; PIXELS];
        umbra::sink::labels::read_label_png(
            &umbra::sink::labels::label_path(&labels, f.seq as usize, "depth"),
            &mut back,
        )
        .unwrap();
        assert!(back == f.labels.ir_labels);
        umbra::sink::labels::read_label_png(
            &umbra::sink::labels::label_path(&labels, f.seq as usize, "rgb"),
            &mut back,
        )
        .unwrap();
        assert!(back == f.labels.rgb_labels);
    }
    // Plain output: one line per frame.
    let (ok, out, _) = umbra(&["tail", &s(dir.path())]);
    assert!(
        ok && out.lines().count() == 3 && out.starts_with("seq 0 "),
        "{out}"
    );
}

#[test]
fn tail_follow_reads_frames_as_written_and_across_rotation() {
    let dir = tempfile::tempdir().unwrap();
    let input = frames(4);
    let mut child = Command::new(env!("CARGO_BIN_EXE_umbra"))
        .args([
            "tail",
            "--follow",
            "--json",
            "--poll-ms",
            "20",
            &s(dir.path()),
        ])
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let (tx, rx) = std::sync::mpsc::channel();
    let stdout = child.stdout.take().unwrap();
    std::thread::spawn(move || {
        for line in BufReader::new(stdout).lines() {
            if tx.send(line.unwrap()).is_err() {
                break;
            }
        }
    });
    // One frame per segment; each frame must show up before the next is written.
    let mut sink = McapSink::create(
        dir.path(),
        McapOptions {
            segment_bytes: 1,
            ..opts()
        },
    )
    .unwrap();
    let mut seen = Vec::new();
    for f in &input {
        sink.write(f).unwrap();
        let line = rx
            .recv_timeout(Duration::from_secs(5))
            .unwrap_or_else(|_| panic!("frame {} not seen by tail --follow", f.seq));
        let v: serde_json::Value = serde_json::from_str(&line).unwrap();
        seen.push(v["seq"].as_u64().unwrap());
    }
    sink.finish().unwrap();
    let deadline = Instant::now() + Duration::from_millis(200);
    while Instant::now() < deadline {
        assert!(
            rx.recv_timeout(Duration::from_millis(50)).is_err(),
            "a frame printed twice"
        );
    }
    let _ = child.kill();
    let _ = child.wait();
    assert_eq!(seen, [0, 1, 2, 3]);
    assert_eq!(list_segments(dir.path()).unwrap().len(), 4);
}

#[test]
fn an_unwritable_folder_loses_frames_without_stopping_and_writing_resumes() {
    let root = tempfile::tempdir().unwrap();
    let dir: PathBuf = root.path().join("out");
    let input = frames(4);
    // One frame per segment, so every frame needs a new file in the folder.
    let mut sink = McapSink::create(
        &dir,
        McapOptions {
            segment_bytes: 1,
            ..opts()
        },
    )
    .unwrap();
    sink.write(&input[0]).unwrap();
    std::fs::remove_dir_all(&dir).unwrap();
    sink.write(&input[1]).unwrap();
    sink.write(&input[2]).unwrap();
    std::fs::create_dir(&dir).unwrap();
    sink.write(&input[3]).unwrap();
    sink.finish().unwrap();
    let c = sink.counters();
    assert_eq!(c.frames_written.load(Ordering::Relaxed), 2);
    assert_eq!(c.frames_lost.load(Ordering::Relaxed), 2);
    assert_eq!(c.failure_bursts.load(Ordering::Relaxed), 1);
    let back = read_folder(&dir);
    assert_eq!(back.len(), 1);
    assert_same(&back[0], &input[3], true);
}
