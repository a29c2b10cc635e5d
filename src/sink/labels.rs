//! SPEC §4 label files: 640×480 8-bit grey PNGs whose pixel value is the label code, written
//! atomically so a reader (or a crash) never sees half a file.

use std::io::BufReader;
use std::path::{Path, PathBuf};

use image::{ImageDecoder, ImageEncoder};

use crate::error::{Error, Result};
use crate::labels::{ALIGNMENT, CLASSES, HEIGHT, PIXELS, WIDTH};

/// `DIR/<i:06>.<view>.png`, the SPEC §4 name of frame `i`'s labels in `view` ("depth" or "rgb").
pub fn label_path(dir: &Path, frame: usize, view: &str) -> PathBuf {
    dir.join(format!("{frame:06}.{view}.png"))
}

/// Reads a SPEC §4 label PNG (640×480, 8-bit grey, values 0–4) into `out` (640·480 codes).
pub fn read_label_png(path: &Path, out: &mut [u8]) -> Result<()> {
    read_grey_png(
        path,
        out,
        "missing: no such label PNG (SPEC §4 names them <frame:06>.depth.png and <frame:06>.rgb.png)",
        "with one label code per pixel",
    )?;
    if let Some(i) = out.iter().position(|&v| v as usize >= CLASSES) {
        return Err(Error::input(
            path,
            format!("pixel ({}, {})", i % WIDTH, i / WIDTH),
            format!(
                "value {} is not a label code, expected 0-{} (SPEC §2)",
                out[i],
                CLASSES - 1
            ),
        ));
    }
    Ok(())
}

/// A `--gt` folder that does not exist is an error of its own, rather than every label PNG in it
/// reported missing.
pub fn check_truth_dir(dir: &Path) -> Result<()> {
    if dir.is_dir() {
        Ok(())
    } else {
        Err(Error::input(
            dir,
            "",
            "no such folder: --gt names the folder of ground-truth label PNGs (SPEC §4)",
        ))
    }
}

/// [`read_label_png`] for the IR view's labels, where there is no alignment shadow (SPEC §1–2):
/// a file holding one is most likely an RGB-view file under the wrong name.
pub fn read_ir_label_png(path: &Path, out: &mut [u8]) -> Result<()> {
    read_label_png(path, out)?;
    match out.iter().position(|&v| v == ALIGNMENT) {
        Some(i) => Err(Error::input(
            path,
            format!("pixel ({}, {})", i % WIDTH, i / WIDTH),
            "value 3 (alignment) occurs only in the RGB view (SPEC §2): is this an RGB-view file?",
        )),
        None => Ok(()),
    }
}

/// Reads a 640×480 8-bit (or 16-bit, values under 256) grey PNG into `out` (640·480 bytes).
/// `missing` is the problem reported when the file does not exist; `what` ends the message for a
/// wrong colour type.
pub fn read_grey_png(path: &Path, out: &mut [u8], missing: &str, what: &str) -> Result<()> {
    assert_eq!(out.len(), PIXELS, "a 640x480 frame");
    let file = match std::fs::File::open(path) {
        Ok(f) => f,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
            return Err(Error::input(path, "", missing))
        }
        Err(e) => return Err(Error::io(path, "reading", e)),
    };
    let bad_png = |e: image::ImageError| {
        Error::input(path, "", format!("not a readable 8-bit grey PNG: {e}"))
    };
    let dec = image::codecs::png::PngDecoder::new(BufReader::new(file)).map_err(bad_png)?;
    let (w, h) = dec.dimensions();
    if (w as usize, h as usize) != (WIDTH, HEIGHT) {
        return Err(Error::input(
            path,
            "header",
            format!("size {w}x{h} is wrong, expected {WIDTH}x{HEIGHT}"),
        ));
    }
    match dec.color_type() {
        image::ColorType::L8 => dec.read_image(out).map_err(bad_png),
        // 16-bit grey holds the same values (numpy and OpenCV write uint16 arrays so).
        image::ColorType::L16 => {
            let mut wide = vec![0u8; 2 * PIXELS];
            dec.read_image(&mut wide).map_err(bad_png)?;
            for (i, (o, v)) in out.iter_mut().zip(wide.chunks_exact(2)).enumerate() {
                let v = u16::from_ne_bytes([v[0], v[1]]);
                *o = u8::try_from(v).map_err(|_| {
                    Error::input(
                        path,
                        format!("pixel ({}, {})", i % WIDTH, i / WIDTH),
                        format!("16-bit value {v} does not fit 8 bits {what}"),
                    )
                })?;
            }
            Ok(())
        }
        other => Err(Error::input(
            path,
            "header",
            format!("colour type {other:?} is wrong, expected 8-bit grey (L8; 16-bit grey is read too) {what}"),
        )),
    }
}

/// Writes labels as a SPEC §4 PNG. The file appears whole or not at all: it is written beside
/// the target and renamed, so an interrupted run never leaves a truncated PNG.
pub fn write_label_png(path: &Path, labels: &[u8]) -> Result<()> {
    write_label_png_with(path, labels, &mut Vec::new())
}

/// [`write_label_png`] encoding into `buf`, reused from frame to frame.
pub fn write_label_png_with(path: &Path, labels: &[u8], buf: &mut Vec<u8>) -> Result<()> {
    assert_eq!(labels.len(), PIXELS, "a label frame has 640x480 codes");
    buf.clear();
    // Label maps are large flat areas: fast compression is nearly as small and several times quicker.
    image::codecs::png::PngEncoder::new_with_quality(
        &mut *buf,
        image::codecs::png::CompressionType::Fast,
        image::codecs::png::FilterType::Sub,
    )
    .write_image(
        labels,
        WIDTH as u32,
        HEIGHT as u32,
        image::ExtendedColorType::L8,
    )
    .map_err(|e| Error::input(path, "", format!("encoding PNG failed: {e}")))?;
    write_atomically(path, buf)
}

/// Writes `bytes` to `path` through a temporary file in the same folder and a rename.
pub fn write_atomically(path: &Path, bytes: &[u8]) -> Result<()> {
    let mut tmp = path.as_os_str().to_owned();
    tmp.push(".part");
    let tmp = std::path::PathBuf::from(tmp);
    std::fs::write(&tmp, bytes).map_err(|e| Error::io(path, "writing", e))?;
    std::fs::rename(&tmp, path).map_err(|e| {
        let _ = std::fs::remove_file(&tmp);
        Error::io(path, "writing", e)
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::labels::{ATTACHED, OTHER, VALID};

    #[test]
    fn label_png_round_trip_and_errors() {
        let dir = tempfile::tempdir().unwrap();
        let mut labels = vec![VALID; PIXELS];
        labels[5] = ATTACHED;
        labels[WIDTH + 7] = OTHER;
        let p = dir.path().join("000000.depth.png");
        write_label_png(&p, &labels).unwrap();
        let mut back = vec![9; PIXELS];
        read_label_png(&p, &mut back).unwrap();
        assert_eq!(back, labels);

        let e = read_label_png(&dir.path().join("nope.png"), &mut back)
            .unwrap_err()
            .to_string();
        assert!(e.contains("nope.png") && e.contains("missing"), "{e}");

        labels[WIDTH * 2 + 3] = 5;
        write_label_png(&p, &labels).unwrap();
        let e = read_label_png(&p, &mut back).unwrap_err().to_string();
        assert!(e.contains("pixel (3, 2)") && e.contains("value 5"), "{e}");

        image::RgbImage::new(640, 480).save(&p).unwrap();
        let e = read_label_png(&p, &mut back).unwrap_err().to_string();
        assert!(e.contains("colour type") && e.contains("8-bit grey"), "{e}");
        image::GrayImage::new(320, 240).save(&p).unwrap();
        let e = read_label_png(&p, &mut back).unwrap_err().to_string();
        assert!(e.contains("320x240"), "{e}");
        std::fs::write(&p, b"not a png").unwrap();
        let e = read_label_png(&p, &mut back).unwrap_err().to_string();
        assert!(e.contains("PNG") && !e.contains('\n'), "{e}");
    }
}
