//! SPEC §6 mask files and overlay pictures: the I/O edge of segmentation.

use std::path::{Path, PathBuf};

use image::ImageEncoder;

use super::{BG, FG};
use crate::error::{Error, Result};
use crate::labels::{HEIGHT, PIXELS, WIDTH};
use crate::sink::labels::write_atomically;

/// `DIR/<i:06>.fg.png`, the SPEC §6 name of frame `i`'s foreground mask.
pub fn mask_path(dir: &Path, frame: usize) -> PathBuf {
    crate::sink::labels::label_path(dir, frame, "fg")
}

/// `DIR/<i:06>.overlay.png`: the picture of frame `i`'s segmentation.
pub fn overlay_path(dir: &Path, frame: usize) -> PathBuf {
    crate::sink::labels::label_path(dir, frame, "overlay")
}

/// Writes a mask (640·480 bytes, 255 foreground, 0 background) as an 8-bit grey PNG, atomically.
pub fn write_mask_png(path: &Path, mask: &[u8], buf: &mut Vec<u8>) -> Result<()> {
    // The same encoding as label PNGs: a mask is a two-valued label map.
    crate::sink::labels::write_label_png_with(path, mask, buf)
}

/// Reads a SPEC §6 mask (640×480, 8-bit grey, every value 0 or 255) into `out`.
pub fn read_mask_png(path: &Path, out: &mut [u8]) -> Result<()> {
    crate::sink::labels::read_grey_png(path, out, "missing: ground truth needs a foreground mask <i>.fg.png for every depth frame (umbra synth writes them)", "with 0 or 255 per pixel")?;
    if let Some(i) = out.iter().position(|&v| v != 0 && v != 255) {
        return Err(Error::input(
            path,
            format!("pixel ({}, {})", i % WIDTH, i / WIDTH),
            format!(
                "value {} is not a mask value, expected 0 (background) or 255 (foreground)",
                out[i]
            ),
        ));
    }
    Ok(())
}

/// The overlay picture (RGB8, 640·480·3): background dimmed to a third, foreground in full
/// colour outlined in yellow, foreground seeds green and background seeds magenta.
pub fn overlay(rgb: &[u8], mask: &[u8], seeds: &[u8], out: &mut Vec<u8>) {
    out.clear();
    out.resize(3 * PIXELS, 0);
    for i in 0..PIXELS {
        let (u, v) = (i % WIDTH, i / WIDTH);
        let fg = mask[i] != 0;
        let edge = fg
            && ((u > 0 && mask[i - 1] == 0)
                || (u + 1 < WIDTH && mask[i + 1] == 0)
                || (v > 0 && mask[i - WIDTH] == 0)
                || (v + 1 < HEIGHT && mask[i + WIDTH] == 0));
        let px: [u8; 3] = match seeds[i] {
            FG => [0, 255, 0],
            BG => [255, 0, 255],
            _ if edge => [255, 255, 0],
            _ if fg => [rgb[3 * i], rgb[3 * i + 1], rgb[3 * i + 2]],
            _ => [rgb[3 * i] / 3, rgb[3 * i + 1] / 3, rgb[3 * i + 2] / 3],
        };
        out[3 * i..3 * i + 3].copy_from_slice(&px);
    }
}

/// Writes an RGB8 640×480 picture as PNG, atomically.
pub fn write_rgb_png(path: &Path, rgb: &[u8], buf: &mut Vec<u8>) -> Result<()> {
    buf.clear();
    image::codecs::png::PngEncoder::new_with_quality(
        &mut *buf,
        image::codecs::png::CompressionType::Fast,
        image::codecs::png::FilterType::Sub,
    )
    .write_image(
        rgb,
        WIDTH as u32,
        HEIGHT as u32,
        image::ExtendedColorType::Rgb8,
    )
    .map_err(|e| Error::input(path, "", format!("encoding PNG failed: {e}")))?;
    write_atomically(path, buf)
}
