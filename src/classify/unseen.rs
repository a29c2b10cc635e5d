//! Alignment shadows beside occluders that return no depth (black, glossy).
//!
//! The warp places an IR hole at the depth of the background around it, all it knows, so a
//! black rod lands in the RGB view where the wall behind it would. The strip of wall the RGB
//! camera sees past the rod's right edge, hidden from the IR camera by the rod (an alignment
//! shadow, SPEC §1), stays OTHER with the rod. The colour image shows where the rod really
//! ends: the background's colour reaches into the hole's right end, up to the rod's edge.

use super::align::colour_at;
use super::bands::row_mask;
use super::depthless::{hue_dist, EDGE_WIDENING};
use crate::labels::{ALIGNMENT, HEIGHT, OTHER, VALID, WIDTH};

/// Colour distance between neighbours of one surface ([`hue_dist`]; the colour camera's noise
/// alone, at σ = 2.8, makes it about 27 on average and 60 at times), scaled like every colour
/// step by the frame's noise.
const AGREE: u32 = 80;
/// How far a strip's pixel may stray from the background's colour (shading drifts).
const STRAY: u32 = 120;
/// Step from the strip to the occluder, and from the occluder to the background. At 120, summed
/// over 34 simulated suites, RGB alignment F1 rose by 0.418 where it rises by 0.412 at 200, but
/// any-shadow precision fell by 0.055 where it falls by 0.034.
const CONTRAST: u32 = 200;
/// Narrowest strip taken for an alignment shadow (pixels): one pixel is the warp's rounding.
const MIN_STRIP: usize = 2;
/// Measured pixels of the background's colour right of the hole: a narrower stretch is most
/// often a glossy object's own measured part, whose unmeasured part shares its colour.
const BACKGROUND: usize = 6;
/// Pixels over which the background right of a hole must not recede into it.
const RECEDE_SPAN: usize = 6;

/// Where the search may look in the RGB view.
#[derive(Clone, Copy, Debug)]
pub struct Reach {
    /// `fx_rgb · |t_x|`: pixels of alignment shift per unit of inverse depth (per metre).
    pub px_m: f32,
}

impl Reach {
    /// Widest alignment shadow of an occluder before a background `mm` millimetres away (px): the
    /// occluder no nearer than [`NEAREST_M`](super::NEAREST_M).
    fn widest(&self, mm: u16) -> usize {
        let inv_near = (1.0 / super::NEAREST_M) as f32;
        let w = self.px_m * (inv_near - 1000.0 / f32::from(mm.max(1)));
        w.max(0.0) as usize + 1
    }
}

/// What a frame says about its sensor, for [`open_gaps`].
#[derive(Clone, Copy, Debug)]
pub struct Sensor {
    /// The frame's colour-step scale in 64ths (its camera noise).
    pub noise_scale: u32,
    /// Pixels the sensor's widening adds to a hole's end in this frame.
    pub widening: f64,
    /// Depth (mm) from which a surface is at the end of the sensor's range.
    pub range_end_mm: u16,
}

/// Labels ALIGNMENT the right end of every OTHER run (alignment pixels may sit inside it) that
/// shows the colour of the measured surface right of it, from a clear colour edge inside the
/// run: the RGB camera sees that surface there, past an occluder the IR camera could not
/// measure. `fov_start[v]` is the first column of RGB row `v` that the IR view reaches (left of
/// it everything stays OTHER, SPEC §1); `sensor` what the frame says about its sensor.
///
/// A sensor whose correlation window widens every hole grows the run into the surface right of
/// it too, and the RGB camera sees that surface over the run's last columns, whether an occluder
/// stands before them or not (a box beside a region beyond range). Those columns are no
/// alignment shadow: the strip ends [`EDGE_WIDENING`] of the widening, rounded, before the run
/// does, and must still be [`MIN_STRIP`] wide. Summed over 32 suites of a fifth simulator whose
/// sensor widens every hole: RGB alignment F1 complex +0.218, simple +0.394 (every suite
/// gaining), any-shadow precision +0.184 / +0.252, recall −0.051 / −0.054; this project's
/// suites, whose sensor widens shadows only, alignment −0.003 to 0.000.
pub fn open_gaps(
    labels: &mut [u8],
    mm: &[u16],
    colour: &[u8],
    fov_start: &[u16],
    reach: Reach,
    sensor: Sensor,
) {
    let Sensor {
        noise_scale,
        widening,
        range_end_mm,
    } = sensor;
    let scaled = |step: u32| step * noise_scale / 64;
    let grown = (EDGE_WIDENING * widening).round() as usize;
    let (agree, stray, contrast) = (scaled(AGREE), scaled(STRAY), scaled(CONTRAST));
    let hole = |l: u8| l == OTHER || l == ALIGNMENT;
    for (v, &fov) in fov_start.iter().enumerate().take(HEIGHT) {
        let row = v * WIDTH;
        let labels = &mut labels[row..row + WIDTH];
        let px = |u: usize| colour_at(colour, row + u);
        let fov = usize::from(fov);
        let valid = row_mask(labels, VALID);
        for (k, &word) in valid.iter().enumerate() {
            // A VALID pixel after one that is not: the right end of a run of something else.
            let carry = if k == 0 { 1 } else { valid[k - 1] >> 63 };
            let mut starts = word & !(word << 1 | carry);
            while starts != 0 {
                let b = 64 * k + starts.trailing_zeros() as usize;
                starts &= starts - 1;
                // Room for a strip and the occluder's edge (a shorter run is speckle), and a
                // measured surface past it.
                if b < fov + MIN_STRIP + 2
                    || b + BACKGROUND > WIDTH
                    || !labels[b - MIN_STRIP - 2..b].iter().all(|&l| hole(l))
                    || !labels[b..b + BACKGROUND].iter().all(|&l| l == VALID)
                {
                    continue;
                }
                // A surface that recedes into the hole runs on beyond the range there: the hole
                // is that surface unmeasured, not an occluder.
                let (near, far) = (mm[row + b + RECEDE_SPAN - 1], mm[row + b]);
                if far > near + (near / 50).max(30) {
                    continue;
                }
                let bg = px(b);
                let wide = (b + 1..b + BACKGROUND).all(|u| hue_dist(px(u), bg) <= agree);
                if !wide {
                    continue;
                }
                let lo = fov.max(b.saturating_sub(reach.widest(far)));
                let mut u = b;
                while u > lo
                    && hole(labels[u - 1])
                    && hue_dist(px(u - 1), px(u)) <= agree
                    && hue_dist(px(u - 1), bg) <= stray
                {
                    u -= 1;
                }
                // Stopped by the occluder's edge inside the run: a step within two pixels to a
                // colour far from the background's. (A gradient that strays from the background's
                // colour stops the strip without such a step: the real frame's translucent box.)
                let edge = u >= lo + 2
                    && labels[u - 1] == OTHER
                    && labels[u - 2] == OTHER
                    && hue_dist(px(u - 2), px(u)) >= contrast
                    && hue_dist(px(u - 2), bg) >= contrast;
                // A run from the view's left edge to a surface at the range's end may be that
                // surface running on beyond the range, a dark rod standing in it: the RGB camera
                // then sees the surface's colour left of the rod too, over more of the run than
                // the widest shadow an occluder casts there (three times its alignment strip).
                let beyond = || {
                    far >= range_end_mm
                        && labels[fov..b].iter().all(|&l| hole(l))
                        && (fov..u - 2)
                            .filter(|&x| hue_dist(px(x), bg) <= stray)
                            .count()
                            > 3 * reach.widest(far)
                };
                if edge && b >= u + grown + MIN_STRIP && !beyond() {
                    labels[u..b - grown].fill(ALIGNMENT);
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::labels::PIXELS;

    const WALL: [u8; 3] = [200, 180, 160];
    const BLACK: [u8; 3] = [15, 15, 18];

    /// The NYU defaults' reach: f_rgb·|t_x| = 518.86 · 0.025 px per inverse metre.
    fn reach() -> Reach {
        Reach {
            px_m: 518.86 * 0.025,
        }
    }

    /// A frame of wall at 3 m, every row alike: OTHER over `hole`, VALID elsewhere; `paint`
    /// colours each column.
    fn frame(hole: std::ops::Range<usize>, paint: impl Fn(usize) -> [u8; 3]) -> Scene {
        let mut s = Scene {
            labels: vec![VALID; PIXELS],
            mm: vec![3000; PIXELS],
            colour: vec![0; 3 * PIXELS],
            fov: vec![0; HEIGHT],
        };
        for v in 0..HEIGHT {
            for u in 0..WIDTH {
                let i = v * WIDTH + u;
                if hole.contains(&u) {
                    s.labels[i] = OTHER;
                    s.mm[i] = 0;
                }
                s.colour[3 * i..3 * i + 3].copy_from_slice(&paint(u));
            }
        }
        s
    }

    struct Scene {
        labels: Vec<u8>,
        mm: Vec<u16>,
        colour: Vec<u8>,
        fov: Vec<u16>,
    }

    impl Scene {
        /// Row 240's labels after [`open_gaps`], as text.
        fn run(self) -> String {
            self.run_widened(0.0)
        }

        /// The same in a frame whose sensor widens holes by `widening` px at each end.
        fn run_widened(mut self, widening: f64) -> String {
            open_gaps(
                &mut self.labels,
                &self.mm,
                &self.colour,
                &self.fov,
                reach(),
                Sensor {
                    noise_scale: 64,
                    widening,
                    range_end_mm: u16::MAX,
                },
            );
            let row = &self.labels[240 * WIDTH..241 * WIDTH];
            row.iter().map(|&l| b".ADLO"[l as usize] as char).collect()
        }
    }

    #[test]
    fn strip_between_a_black_rods_edge_and_the_wall_is_alignment() {
        // A black rod at 1.2 m and its shadow, one hole warped at the wall's depth to columns
        // [200, 260). The RGB camera sees the rod's right edge 518.86·0.025·(1/1.2 − 1/3) =
        // 6.5 px left of the hole's end, at 253.5 (the pixel at 253 half rod, half wall), and
        // the wall in the 6 px after it.
        let labels = frame(200..260, |u| match u {
            200..253 => BLACK,
            253 => [110, 100, 90],
            // Shading: the wall darkens by a unit every 4 columns.
            _ => WALL.map(|c| c - (u / 4 % 8) as u8),
        })
        .run();
        let want = [(".", 5), ("O", 54), ("L", 6), (".", 5)].map(|(c, n)| c.repeat(n));
        assert_eq!(labels[195..265], want.concat());
    }

    #[test]
    fn columns_the_widening_grew_the_hole_over_are_no_alignment_shadow() {
        // The black rod's strip, in a frame whose sensor widens holes by 1.5 px: the hole's last
        // column (0.7 of that, rounded) is the wall the IR camera sees but did not measure.
        let rod = |u: usize| match u {
            200..253 => BLACK,
            253 => [110, 100, 90],
            _ => WALL,
        };
        let labels = frame(200..260, rod).run_widened(1.5);
        let want = [(".", 5), ("O", 54), ("L", 5), ("O", 1), (".", 5)].map(|(c, n)| c.repeat(n));
        assert_eq!(labels[195..265], want.concat());
        // A region the sensor cannot measure (dark), then a box (the wall's colour here) whose
        // first two columns the widening took: the RGB camera sees the box there, no strip.
        let region = |u: usize| if u < 258 { BLACK } else { WALL };
        let labels = frame(200..260, region).run_widened(2.0);
        let want: String = (0..WIDTH)
            .map(|u| if (200..260).contains(&u) { 'O' } else { '.' })
            .collect();
        assert_eq!(labels, want);
    }

    #[test]
    fn holes_without_an_occluders_edge_before_the_background_stay_other() {
        let unchanged = |s: Scene, hole: std::ops::Range<usize>| {
            let labels = s.run();
            let want: String = (0..WIDTH)
                .map(|u| if hole.contains(&u) { 'O' } else { '.' })
                .collect();
            assert_eq!(labels, want);
        };
        // A black poster on the wall: black up to the hole's end, where the wall starts.
        unchanged(
            frame(200..260, |u| if u < 260 { BLACK } else { WALL }),
            200..260,
        );
        // A strip of one pixel: the warp's rounding.
        unchanged(
            frame(200..260, |u| if u < 259 { BLACK } else { WALL }),
            200..260,
        );
        // The wall's colour darkening by half over the hole's last 10 px, then black: the strip
        // strays from the background's colour before the edge (the real frame's translucent box).
        let fade = |u: usize| match u {
            ..250 => BLACK,
            250..260 => WALL.map(|c| (c as usize * (10 + u - 250) / 20) as u8),
            _ => WALL,
        };
        unchanged(frame(200..260, fade), 200..260);
        // The wall receding into the hole (4 m at its edge, 3.8 m 5 px on): it goes on there
        // beyond the sensor's range, no occluder before it.
        let mut s = frame(200..260, |u| if u < 253 { BLACK } else { WALL });
        for v in 0..HEIGHT {
            for u in 260..WIDTH {
                s.mm[v * WIDTH + u] = 4000usize.saturating_sub(40 * (u - 260)).max(3000) as u16;
            }
        }
        unchanged(s, 200..260);
        // Only 3 px of the wall's colour past the hole, then another surface: the hole's own
        // surface measured in part (a glossy box), not the background behind an occluder.
        let part = |u: usize| match u {
            ..253 => BLACK,
            253..263 => WALL,
            _ => [40, 120, 200],
        };
        unchanged(frame(200..260, part), 200..260);
        // Left of the IR view's edge in the RGB image (column 40 here) nothing is measured:
        // the edge at 36 lies outside.
        let mut s = frame(0..44, |u| if u < 36 { BLACK } else { WALL });
        s.fov.fill(40);
        unchanged(s, 0..44);
    }
}
