//! One frame as a picture to read at a glance: the RGB image, the IR-view labels over the depth
//! map and the RGB-view labels over the colour image, side by side, with a title above each panel
//! and a legend (colour, class name, share of the frame's pixels) below.
//!
//! Pure: [`render_panels`] draws into a new image; the caller reads frames and writes the PNG.
//! Text uses the public-domain 8×8 bitmap font of the `font8x8` crate, drawn at 2×.

use image::{Rgb, RgbImage};

use crate::calib::Calibration;
use crate::classify::Classified;
use crate::labels::{self, CLASSES, HEIGHT, NAMES, OTHER, PIXELS, VALID, WIDTH};

/// Font scale: 8×8 glyphs drawn as 16×16 so they read on a full-HD screen.
const SCALE: u32 = 2;
/// Glyph cell size on screen.
const CELL: u32 = 8 * SCALE;
/// Height of the title strip above the panels.
pub const TITLE_HEIGHT: u32 = 32;
/// Height of the legend strip below the panels.
pub const LEGEND_HEIGHT: u32 = 64;
/// Number of panels side by side.
pub const PANELS: u32 = 3;
/// Strip-coloured gap between panels, so that their edges do not run into each other.
pub const GAP: u32 = 8;
/// Titles of the three panels, left to right.
pub const TITLES: [&str; PANELS as usize] = [
    "RGB",
    "IR view: labels over depth",
    "RGB view: labels over colour",
];

/// Background of the title and legend strips.
const STRIP: Rgb<u8> = Rgb([24, 24, 24]);
/// Text colour.
const INK: Rgb<u8> = Rgb([235, 235, 235]);
/// Fill of panel 1 when the recording has no RGB.
const NO_RGB: Rgb<u8> = Rgb([48, 48, 48]);
/// How strongly OTHER's yellow covers the colour image in panel 3 (the image stays readable
/// where the IR camera sees nothing).
const TINT: f32 = 0.7;
/// Depth range mapped to grey (near = bright): the Kinect v1's useful range.
const NEAR_M: f64 = 0.5;
const FAR_M: f64 = 5.0;
/// Grey of the farthest depth: kept above black so far walls stay distinct from "no data".
const FAR_GREY: f64 = 48.0;

/// Top-left corner of panel `k` (0, 1 or 2) in the picture [`render_panels`] draws.
pub fn panel_origin(k: u32) -> (u32, u32) {
    (k * (WIDTH as u32 + GAP), TITLE_HEIGHT)
}

/// Draws the three panels, titles and legend for one frame.
///
/// `rgb` is the paired colour frame (640·480·3 bytes) or `None`; `raw` the 11-bit depth map the
/// labels in `classified` came from. Slices of the wrong length are treated as missing data
/// (black) rather than a panic.
pub fn render_panels(
    rgb: Option<&[u8]>,
    raw: &[u16],
    calib: &Calibration,
    classified: &Classified,
) -> RgbImage {
    let (w, h) = (WIDTH as u32, HEIGHT as u32);
    let mut img = RgbImage::from_pixel(
        PANELS * w + (PANELS - 1) * GAP,
        TITLE_HEIGHT + h + LEGEND_HEIGHT,
        STRIP,
    );
    let (x1, x2) = (panel_origin(1).0, panel_origin(2).0);
    let rgb = rgb.filter(|c| c.len() == PIXELS * 3);
    let colour_at = |i: usize| rgb.map_or([0, 0, 0], |c| [c[3 * i], c[3 * i + 1], c[3 * i + 2]]);

    for i in 0..PIXELS {
        let (x, y) = ((i % WIDTH) as u32, (i / WIDTH) as u32 + TITLE_HEIGHT);
        // Panel 1: the colour image as it is.
        img.put_pixel(
            x,
            y,
            if rgb.is_some() {
                Rgb(colour_at(i))
            } else {
                NO_RGB
            },
        );
        // Panel 2: IR-view labels; valid pixels grey by depth.
        let p2 = ir_label_colour(classified.ir_labels.get(i), calib, raw.get(i).copied());
        img.put_pixel(x1 + x, y, Rgb(p2));
        // Panel 3: RGB-view labels over the colour image (over black without one): shadows in
        // the paper's colours, OTHER tinted so that the image shows through its large areas.
        let base = colour_at(i);
        let p3 = match classified.rgb_labels.get(i) {
            Some(&VALID) => base,
            Some(&OTHER) if rgb.is_some() => blend(base, labels::COLOURS[OTHER as usize], TINT),
            Some(&l) if (l as usize) < CLASSES => labels::COLOURS[l as usize],
            _ => [0, 0, 0],
        };
        img.put_pixel(x2 + x, y, Rgb(p3));
    }
    if rgb.is_none() {
        let text = "no RGB";
        let tw = text.len() as u32 * CELL;
        draw_text(
            &mut img,
            (w - tw) / 2,
            TITLE_HEIGHT + (h - CELL) / 2,
            text,
            INK,
        );
    }
    for (k, title) in TITLES.iter().enumerate() {
        let (x0, _) = panel_origin(k as u32);
        draw_text(&mut img, x0 + 8, (TITLE_HEIGHT - CELL) / 2, title, INK);
    }
    draw_legend(&mut img, classified);
    img
}

/// Titles of the second row, drawn when ground truth is given ([`render_with_truth`]).
pub const TRUTH_TITLES: [&str; PANELS as usize] = [
    "IR view: ground truth",
    "IR errors: bright=missed, dim=false",
    "RGB errors: bright=missed, dim=false",
];
/// How bright a correctly labelled pixel stays in an error panel, so that errors stand out.
const AGREE_DIM: f32 = 0.35;
/// How bright a falsely labelled pixel's (predicted) class colour is drawn.
const FALSE_DIM: f32 = 0.5;

/// Ground-truth label maps (SPEC §4 codes, 640·480) of the views that have one.
#[derive(Clone, Copy, Debug, Default)]
pub struct Truth<'a> {
    /// IR (depth) view.
    pub ir: Option<&'a [u8]>,
    /// RGB view.
    pub rgb: Option<&'a [u8]>,
}

/// Top-left corner of panel `k` of the second row [`render_with_truth`] draws.
pub fn truth_panel_origin(k: u32) -> (u32, u32) {
    (k * (WIDTH as u32 + GAP), 2 * TITLE_HEIGHT + HEIGHT as u32)
}

/// [`render_panels`] with a second row against ground truth: the IR view's ground truth, then
/// each view's errors. Where the labels agree the error panels show the depth (IR) or colour
/// image (RGB), dimmed; a pixel the ground truth gives a label the frame missed shows that
/// label's colour, bright; a pixel labelled where the ground truth has depth shows the label
/// given, dim. A view without ground truth says so.
pub fn render_with_truth(
    rgb: Option<&[u8]>,
    raw: &[u16],
    calib: &Calibration,
    classified: &Classified,
    truth: Truth,
) -> RgbImage {
    let top = render_panels(rgb, raw, calib, classified);
    let (w, h) = (WIDTH as u32, HEIGHT as u32);
    let panels_end = TITLE_HEIGHT + h;
    let mut img = RgbImage::from_pixel(top.width(), top.height() + TITLE_HEIGHT + h, STRIP);
    for (x, y, p) in top.enumerate_pixels() {
        // The legend moves below the second row.
        let y = if y < panels_end {
            y
        } else {
            y + TITLE_HEIGHT + h
        };
        img.put_pixel(x, y, *p);
    }
    let rgb = rgb.filter(|c| c.len() == PIXELS * 3);
    let colour_at = |i: usize| rgb.map_or([0, 0, 0], |c| [c[3 * i], c[3 * i + 1], c[3 * i + 2]]);
    let grey_at = |i: usize| [depth_grey(calib, raw.get(i).copied()); 3];
    let truth_ir = truth.ir.filter(|t| t.len() == PIXELS);
    let truth_rgb = truth.rgb.filter(|t| t.len() == PIXELS);
    for i in 0..PIXELS {
        let (x, y) = ((i % WIDTH) as u32, (i / WIDTH) as u32);
        let put = |img: &mut RgbImage, k: u32, p: [u8; 3]| {
            let (x0, y0) = truth_panel_origin(k);
            img.put_pixel(x0 + x, y0 + y, Rgb(p));
        };
        if let Some(t) = truth_ir {
            put(
                &mut img,
                0,
                ir_label_colour(t.get(i), calib, raw.get(i).copied()),
            );
            let pred = classified.ir_labels.get(i).copied();
            put(&mut img, 1, error_colour(t[i], pred, grey_at(i)));
        }
        if let Some(t) = truth_rgb {
            let pred = classified.rgb_labels.get(i).copied();
            put(&mut img, 2, error_colour(t[i], pred, colour_at(i)));
        }
    }
    for (k, title) in TRUTH_TITLES.iter().enumerate() {
        let (x0, y0) = truth_panel_origin(k as u32);
        draw_text(
            &mut img,
            x0 + 8,
            y0 - TITLE_HEIGHT + (TITLE_HEIGHT - CELL) / 2,
            title,
            INK,
        );
        let missing = if k == 2 {
            truth_rgb.is_none()
        } else {
            truth_ir.is_none()
        };
        if missing {
            let text = "no ground truth";
            let tw = text.len() as u32 * CELL;
            draw_text(&mut img, x0 + (w - tw) / 2, y0 + (h - CELL) / 2, text, INK);
        }
    }
    img
}

/// An IR-view label's colour: its paper colour, grey by the depth `raw` for a valid pixel, black
/// for no label or a code that is none.
fn ir_label_colour(label: Option<&u8>, calib: &Calibration, raw: Option<u16>) -> [u8; 3] {
    match label {
        Some(&VALID) => [depth_grey(calib, raw); 3],
        Some(&l) if (l as usize) < CLASSES => labels::COLOURS[l as usize],
        _ => [0, 0, 0],
    }
}

/// The colour of one error-panel pixel: `base` dimmed where `pred` agrees with `truth`, the
/// ground truth's class bright where it has a label the frame missed, the predicted class dim
/// where the ground truth has depth.
fn error_colour(truth: u8, pred: Option<u8>, base: [u8; 3]) -> [u8; 3] {
    let dim = |c: [u8; 3], f: f32| c.map(|v| (f32::from(v) * f).round() as u8);
    match pred {
        Some(p) if p == truth => dim(base, AGREE_DIM),
        _ if truth != VALID && (truth as usize) < CLASSES => labels::COLOURS[truth as usize],
        Some(p) if (p as usize) < CLASSES => dim(labels::COLOURS[p as usize], FALSE_DIM),
        _ => [0, 0, 0],
    }
}

/// Grey level of a raw value: linear in depth from bright at 0.5 m to dark at 5 m; black when
/// there is no depth (a VALID label without depth would be a classifier bug, drawn as "nothing").
fn depth_grey(calib: &Calibration, raw: Option<u16>) -> u8 {
    match raw.and_then(|r| calib.depth_m(r)) {
        Some(z) => {
            let t = ((z - NEAR_M) / (FAR_M - NEAR_M)).clamp(0.0, 1.0);
            (255.0 - t * (255.0 - FAR_GREY)).round() as u8
        }
        None => 0,
    }
}

fn blend(base: [u8; 3], top: [u8; 3], alpha: f32) -> [u8; 3] {
    let mix = |b: u8, t: u8| (f32::from(b) * (1.0 - alpha) + f32::from(t) * alpha).round() as u8;
    [
        mix(base[0], top[0]),
        mix(base[1], top[1]),
        mix(base[2], top[2]),
    ]
}

/// One column per class: a swatch, the name, and the share of pixels in each view.
fn draw_legend(img: &mut RgbImage, classified: &Classified) {
    let ir = labels::histogram(&classified.ir_labels);
    let rgb = labels::histogram(&classified.rgb_labels);
    let pct = |h: &[u64; CLASSES], c: usize| {
        let total: u64 = h.iter().sum();
        if total == 0 {
            "-".to_string()
        } else {
            format!("{:.1}%", 100.0 * h[c] as f64 / total as f64)
        }
    };
    let top = TITLE_HEIGHT + HEIGHT as u32 + 8;
    let col_w = img.width() / CLASSES as u32;
    for (c, (name, colour)) in NAMES.iter().zip(labels::COLOURS).enumerate() {
        let x0 = c as u32 * col_w + 16;
        fill_rect(img, x0, top, 2 * CELL, 2 * CELL + 8, Rgb(colour));
        let tx = x0 + 2 * CELL + 12;
        draw_text(img, tx, top, name, INK);
        // Alignment shadows cannot exist in the IR view: say so rather than print 0.0%.
        let ir_pct = if c == labels::ALIGNMENT as usize {
            "-".to_string()
        } else {
            pct(&ir, c)
        };
        draw_text(
            img,
            tx,
            top + CELL + 8,
            &format!("IR {ir_pct}  RGB {}", pct(&rgb, c)),
            INK,
        );
    }
}

fn fill_rect(img: &mut RgbImage, x0: u32, y0: u32, w: u32, h: u32, colour: Rgb<u8>) {
    for y in y0..(y0 + h).min(img.height()) {
        for x in x0..(x0 + w).min(img.width()) {
            img.put_pixel(x, y, colour);
        }
    }
}

/// Draws ASCII `text` with its top-left corner at `(x, y)`; other characters show as '?', and
/// anything past the image's edge is clipped.
fn draw_text(img: &mut RgbImage, x: u32, y: u32, text: &str, colour: Rgb<u8>) {
    for (n, ch) in text.chars().enumerate() {
        let code = if ch.is_ascii() {
            ch as usize
        } else {
            '?' as usize
        };
        let glyph = font8x8::legacy::BASIC_LEGACY[code];
        let gx = x + n as u32 * CELL;
        for (row, bits) in glyph.iter().enumerate() {
            for col in 0..8u32 {
                // Bit 0 is the glyph's leftmost pixel.
                if bits >> col & 1 == 1 {
                    fill_rect(
                        img,
                        gx + col * SCALE,
                        y + row as u32 * SCALE,
                        SCALE,
                        SCALE,
                        colour,
                    );
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::labels::{ALIGNMENT, ATTACHED, DETACHED, NO_DEPTH, OTHER};

    fn at(img: &RgbImage, panel: u32, x: usize, y: usize) -> [u8; 3] {
        let (x0, y0) = panel_origin(panel);
        img.get_pixel(x0 + x as u32, y0 + y as u32).0
    }

    fn frame() -> (Vec<u16>, Classified) {
        let calib = Calibration::nyu_default();
        let mut raw = vec![NO_DEPTH; PIXELS];
        let mut c = Classified::default();
        // Row 100: a near pixel at x=10 (1 m), a far one at x=11 (4 m), then one hole per class.
        raw[100 * WIDTH + 10] = calib.raw_from_depth(1.0).round() as u16;
        raw[100 * WIDTH + 11] = calib.raw_from_depth(4.0).round() as u16;
        for (x, l) in [(20, ATTACHED), (21, DETACHED), (22, OTHER)] {
            c.ir_labels[100 * WIDTH + x] = l;
        }
        for (x, l) in [(30, ATTACHED), (31, DETACHED), (32, ALIGNMENT), (33, OTHER)] {
            c.rgb_labels[100 * WIDTH + x] = l;
        }
        (raw, c)
    }

    #[test]
    fn ir_panel_uses_paper_colours_and_grey_by_depth() {
        let (raw, c) = frame();
        let img = render_panels(None, &raw, &Calibration::nyu_default(), &c);
        assert_eq!(
            img.dimensions(),
            (3 * 640 + 2 * GAP, TITLE_HEIGHT + 480 + LEGEND_HEIGHT)
        );
        assert_eq!(at(&img, 1, 20, 100), [255, 0, 0]);
        assert_eq!(at(&img, 1, 21, 100), [0, 0, 255]);
        assert_eq!(at(&img, 1, 22, 100), [255, 255, 0]);
        let near = at(&img, 1, 10, 100);
        let far = at(&img, 1, 11, 100);
        assert!(near[0] == near[1] && near[1] == near[2], "{near:?} is grey");
        assert!(
            near[0] > far[0] && far[0] >= FAR_GREY as u8,
            "near {near:?} brighter than far {far:?}"
        );
    }

    #[test]
    fn rgb_panel_tints_labels_over_colour() {
        let (raw, c) = frame();
        let rgb = vec![100u8; PIXELS * 3];
        let img = render_panels(Some(&rgb), &raw, &Calibration::nyu_default(), &c);
        // Panel 1 is the colour image, panel 3 shows it where the RGB view is valid.
        assert_eq!(at(&img, 0, 30, 100), [100, 100, 100]);
        assert_eq!(at(&img, 2, 5, 5), [100, 100, 100]);
        // Shadows in the paper's colours (SPEC §2); OTHER 0.3·100 + 0.7·255 = 208.5 → 209.
        assert_eq!(at(&img, 2, 30, 100), [255, 0, 0]);
        assert_eq!(at(&img, 2, 31, 100), [0, 0, 255]);
        assert_eq!(at(&img, 2, 32, 100), [0, 255, 0]);
        assert_eq!(at(&img, 2, 33, 100), [209, 209, 30]);
    }

    #[test]
    fn no_rgb_shows_grey_panel_and_labels_over_black() {
        let (raw, c) = frame();
        let img = render_panels(None, &raw, &Calibration::nyu_default(), &c);
        assert_eq!(at(&img, 0, 0, 0), NO_RGB.0);
        assert_eq!(at(&img, 2, 0, 0), [0, 0, 0]);
        assert_eq!(at(&img, 2, 31, 100), [0, 0, 255]);
        // Without an image to show through, OTHER is the paper's yellow too.
        assert_eq!(at(&img, 2, 33, 100), [255, 255, 0]);
        // The "no RGB" caption is drawn in the middle of panel 1.
        let (x0, y0) = panel_origin(0);
        let inked = (y0 + 220..y0 + 260)
            .flat_map(|y| (x0 + 260..x0 + 380).map(move |x| (x, y)))
            .any(|(x, y)| img.get_pixel(x, y).0 == INK.0);
        assert!(inked);
    }

    #[test]
    fn titles_and_legend_are_drawn() {
        let (raw, c) = frame();
        let img = render_panels(None, &raw, &Calibration::nyu_default(), &c);
        let inked = |y0: u32, y1: u32, x0: u32, x1: u32| {
            (y0..y1).any(|y| (x0..x1).any(|x| img.get_pixel(x, y).0 == INK.0))
        };
        for k in 0..PANELS {
            let (x0, _) = panel_origin(k);
            assert!(inked(0, TITLE_HEIGHT, x0, x0 + 200), "title of panel {k}");
        }
        let legend_top = TITLE_HEIGHT + 480;
        assert!(inked(legend_top, img.height(), 0, img.width()));
        // The attached swatch is pure red.
        let col_w = img.width() / CLASSES as u32;
        assert_eq!(img.get_pixel(col_w + 20, legend_top + 12).0, [255, 0, 0]);
    }

    #[test]
    fn short_buffers_do_not_panic() {
        let c = Classified {
            ir_labels: vec![ATTACHED; 3],
            rgb_labels: vec![],
            registered_mm: vec![],
        };
        let img = render_panels(Some(&[1, 2, 3]), &[], &Calibration::nyu_default(), &c);
        assert_eq!(at(&img, 1, 0, 0), [255, 0, 0]);
        assert_eq!(at(&img, 1, 5, 0), [0, 0, 0]);
        assert_eq!(at(&img, 0, 0, 0), NO_RGB.0);
    }
}
