//! Two dropouts of one glossy surface that depth alone took for a depthless occluder and its
//! detached shadow.
//!
//! A glossy cylinder or box returns depth in bands: its unmeasured stripes, row after row, are
//! holes of like width on one surface, which the scanline's pairing (eqs. 4–5 with the occluder's
//! depth unknown) reads as a black rod and its shadow. The RGB camera tells them apart: a rod,
//! seen where the depth its shift implies puts it, shows its own colour; a stripe of the
//! surface shows the surface's.

use super::{hue_dist, ColourSplit, SIDE};
use crate::labels::{DETACHED, NO_DEPTH, OTHER, WIDTH};

/// Colour distance ([`hue_dist`], dimmed with the surface's brightness and the camera's noise)
/// within which the two sides of the hole show one surface: a glossy box's sides are a median 18
/// apart. (With the colour split's 90 here and for [`MATCH`], this project's seed 6174 lost 0.008
/// detached F1 to a glossy rod the colour of its patterned wall; with these, 0.0003.)
const SIDES: u32 = 45;
/// The same within which the occluder, seen where its placement puts it, shows that surface's
/// colour: a glossy box's stripes, a median 16.
const MATCH: u32 = 30;
/// How many times [`SIDES`] apart the two sides of a shaded surface may lie: a glossy cylinder
/// brightening across a stripe (sides 61 apart, the stripe within 13 of one). The fourth
/// simulator's 42 suites: complex IR detached F1 +0.036 summed (j39 +0.027), any-shadow
/// precision +0.022, recall −0.007; simple +0.049 / +0.019. This project's suites lose up to
/// 0.005 detached (x6174: glossy rods the colour of their patterned wall's lighter part); at
/// two times the gain was two thirds, as was the loss; without asking the occluder to match
/// one side, x6174 lost 0.009.
const SHADED: u32 = 3;
/// Disparity (pixels) by which the scanline's placement of a depthless occluder lies before the
/// surface around its hole: less is no placement.
const PLACED: f64 = 1.0;

impl ColourSplit {
    /// When the OTHER hole `[a, b)` of row `v` holds a depthless occluder the scanline placed
    /// (`filled` nearer than the surface on both sides), and the RGB camera sees the colour of
    /// that surface where the placement puts it: puts the hole back at the surface's depth,
    /// relabels OTHER the detached shadow it was paired with, and returns true.
    pub(super) fn dropout_pair(
        &self,
        raw: &[u16],
        rgb: &[u8],
        labels: &mut [u8],
        filled: &mut [u16],
        v: usize,
        (a, b): (usize, usize),
    ) -> bool {
        let row = v * WIDTH;
        if a < SIDE || b + SIDE > WIDTH || b - a < 2 {
            return false;
        }
        let (left, right) = (&raw[row + a - SIDE..row + a], &raw[row + b..row + b + SIDE]);
        if left.contains(&NO_DEPTH) || right.contains(&NO_DEPTH) {
            return false;
        }
        let bg = raw[row + a - 1].max(raw[row + b]);
        let at = filled[row + a];
        let shift = self.disp(at) - self.disp(bg);
        if shift < PLACED || filled[row + a..row + b].iter().any(|&f| f != at) {
            return false;
        }
        // The surface's colour on either side, and the occluder's where its placement puts it.
        let (Some(side_a), Some(side_b), Some(occ)) = (
            self.mean_colour(rgb, v, a - SIDE..a, raw[row + a - 1]),
            self.mean_colour(rgb, v, b..b + SIDE, raw[row + b]),
            self.mean_colour(rgb, v, a..b, at),
        ) else {
            return false;
        };
        let (sides, step) = (self.dimmed(SIDES, side_a), self.dimmed(MATCH, side_a));
        let (apart, to_a, to_b) = (
            hue_dist(side_a, side_b),
            hue_dist(occ, side_a),
            hue_dist(occ, side_b),
        );
        // One surface on both sides, the occluder its colour; or a surface shaded across the
        // hole (a glossy cylinder's sides up to [`SHADED`] times as far apart), the occluder
        // the colour of one side and between the two.
        let plain = apart <= sides && to_a <= step && to_b <= step;
        let shaded =
            apart <= SHADED * sides && to_a.min(to_b) <= step && to_a + to_b <= apart + step;
        if !plain && !shaded {
            return false;
        }
        filled[row + a..row + b].fill(bg);
        // The shadow: the hole's image `shift` pixels left (the sensor's widening aside).
        let reach = shift.ceil() as usize + 4;
        let from = a.saturating_sub(reach);
        let labels = &mut labels[row..row + WIDTH];
        if let Some(k) = labels[from..a].iter().rposition(|&l| l == DETACHED) {
            let end = from + k + 1;
            let start = labels[..end]
                .iter()
                .rposition(|&l| l != DETACHED)
                .map_or(0, |s| s + 1);
            labels[start..end].fill(OTHER);
        }
        true
    }
}

#[cfg(test)]
mod tests {
    use crate::calib::Calibration;
    use crate::classify::{Classified, Classifier};
    use crate::labels::{DETACHED, HEIGHT, NO_DEPTH, OTHER, PIXELS, WIDTH};

    /// A blue glossy box at 1.2 m over IR columns [150, 500) before a grey wall at 3 m, its face
    /// unmeasured in two stripes, [250, 256) and [270, 276), in every row; the RGB image is
    /// blue over columns [100, 480) and `paint` may change it. IR row 240's labels over
    /// [250, 256), from depth alone and with the image.
    fn stripes(paint: impl Fn(usize, &mut [u8; 3])) -> (Vec<u8>, Vec<u8>) {
        let calib = Calibration::nyu_default();
        let raw_at = |z: f64| calib.raw_from_depth(z).round() as u16;
        let mut raw = vec![raw_at(3.0); PIXELS];
        let mut rgb = vec![0u8; 3 * PIXELS];
        for v in 0..HEIGHT {
            let row = &mut raw[v * WIDTH..(v + 1) * WIDTH];
            row[150..500].fill(raw_at(1.2));
            row[250..256].fill(NO_DEPTH);
            row[270..276].fill(NO_DEPTH);
            for x in 0..WIDTH {
                let mut c = if (100..480).contains(&x) {
                    [60, 90, 200]
                } else {
                    [150, 150, 150]
                };
                paint(x, &mut c);
                rgb[3 * (v * WIDTH + x)..3 * (v * WIDTH + x) + 3].copy_from_slice(&c);
            }
        }
        let mut out = Classified::default();
        let mut classifier = Classifier::new(&calib);
        classifier.classify(&raw, &mut out);
        let depth_only = out.ir_labels[240 * WIDTH + 250..240 * WIDTH + 256].to_vec();
        classifier.classify_with_rgb(&raw, Some(&rgb), &mut out);
        (
            depth_only,
            out.ir_labels[240 * WIDTH + 250..240 * WIDTH + 256].to_vec(),
        )
    }

    #[test]
    fn stripes_of_one_glossy_surface_are_no_occluder_and_its_shadow() {
        // Depth alone pairs them: same width, 20 px apart, on one surface, in every row; the
        // shift puts a black rod at 1/(1/1.2 + 20/43.67) = 0.77 m.
        let (depth_only, with_rgb) = stripes(|_, _| {});
        assert_eq!(depth_only, [DETACHED; 6], "the scanline pairs them");
        // The RGB camera sees the box's blue where that rod would stand.
        assert_eq!(with_rgb, [OTHER; 6]);
        // A black rod there: the RGB camera sees it, 518.86·0.025·(1/0.77 − 1/1.2) = 5.9 px left
        // of where the box's depth would put the hole, over RGB columns 270 to 276.
        let (_, with_rgb) = stripes(|x, c| {
            if (269..=277).contains(&x) {
                *c = [12, 12, 14];
            }
        });
        assert_eq!(with_rgb, [DETACHED; 6]);
    }

    #[test]
    fn stripes_of_a_shaded_glossy_surface_are_no_occluder_either() {
        // The box brighter by 20 a channel from RGB column 279 on (light falling across a
        // glossy cylinder): the right stripe's two sides, read at the box's depth over RGB
        // columns 272–276 and 282–286, lie 60 apart, past one surface's 24 (45 dimmed for this
        // blue); where the placed rod would stand (270–276) the camera sees the left side's
        // colour, between the two.
        let brighter = |x: usize, c: &mut [u8; 3]| {
            if (279..480).contains(&x) {
                *c = c.map(|k| k + 20);
            }
        };
        let (depth_only, with_rgb) = stripes(brighter);
        assert_eq!(depth_only, [DETACHED; 6], "the scanline pairs them");
        assert_eq!(with_rgb, [OTHER; 6]);
        // A black rod there still shows, the shading notwithstanding.
        let (_, with_rgb) = stripes(|x, c| {
            brighter(x, c);
            if (269..=277).contains(&x) {
                *c = [12, 12, 14];
            }
        });
        assert_eq!(with_rgb, [DETACHED; 6]);
    }
}
