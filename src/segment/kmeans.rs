//! Small k-means (Lloyd's iterations, k-means++ start with a fixed-seed generator) on 4-D points.
//!
//! Written here rather than taken from a crate: it runs on a few thousand points per frame, must
//! not allocate in the daemon's hot path and must be deterministic. `linfa-clustering` brings
//! ndarray and allocates its own datasets and results on every call; the `kmeans` crate needs
//! nightly SIMD. Forty lines over caller-owned buffers do the job.

/// A 4-D feature: red, green, blue (0–255), depth (cm; 0 = none).
pub type Point = [f32; 4];

/// Squared distance; `w` weighs each dimension.
#[inline]
pub fn dist2(a: &Point, b: &Point, w: &Point) -> f32 {
    let mut d = 0.0;
    for i in 0..4 {
        let t = a[i] - b[i];
        d += w[i] * t * t;
    }
    d
}

/// xorshift32: a tiny deterministic generator for the k-means++ draws.
fn next(state: &mut u32) -> u32 {
    *state ^= *state << 13;
    *state ^= *state >> 17;
    *state ^= *state << 5;
    *state
}

/// Clusters `points` into `centres.len()` clusters (fewer if there are fewer points): fills
/// `assign` (one cluster index per point) and `centres`, and returns the number of clusters used.
/// `weights` scales each dimension's distance; `scratch` holds per-point distances (same length as
/// `points`). Deterministic for given inputs.
pub fn kmeans(
    points: &[Point],
    weights: &Point,
    iterations: usize,
    centres: &mut [Point],
    assign: &mut [u8],
    scratch: &mut [f32],
) -> usize {
    let n = points.len();
    let k = centres.len().min(n).min(255);
    if k == 0 {
        return 0;
    }
    // k-means++: each next centre drawn with probability proportional to squared distance.
    let mut rng = 0x9e37_79b9u32;
    centres[0] = points[(next(&mut rng) as usize) % n];
    for (d, p) in scratch.iter_mut().zip(points) {
        *d = dist2(p, &centres[0], weights);
    }
    let mut used = 1;
    while used < k {
        let total: f64 = scratch[..n].iter().map(|&d| f64::from(d)).sum();
        if total <= 0.0 {
            break; // every point sits on a centre already
        }
        let mut target = f64::from(next(&mut rng)) / f64::from(u32::MAX) * total;
        let mut pick = n - 1;
        for (i, &d) in scratch[..n].iter().enumerate() {
            target -= f64::from(d);
            if target <= 0.0 {
                pick = i;
                break;
            }
        }
        centres[used] = points[pick];
        for (d, p) in scratch.iter_mut().zip(points) {
            *d = d.min(dist2(p, &centres[used], weights));
        }
        used += 1;
    }
    let k = used;
    let mut sums = [[0.0f64; 5]; 255];
    for _ in 0..iterations {
        let mut moved = false;
        for (a, p) in assign.iter_mut().zip(points) {
            let best = nearest(p, &centres[..k], weights);
            moved |= *a != best;
            *a = best;
        }
        for s in &mut sums[..k] {
            *s = [0.0; 5];
        }
        for (&a, p) in assign.iter().zip(points) {
            let s = &mut sums[a as usize];
            for i in 0..4 {
                s[i] += f64::from(p[i]);
            }
            s[4] += 1.0;
        }
        for (c, s) in centres[..k].iter_mut().zip(&sums[..k]) {
            if s[4] > 0.0 {
                for i in 0..4 {
                    c[i] = (s[i] / s[4]) as f32;
                }
            }
        }
        if !moved {
            break;
        }
    }
    for (a, p) in assign.iter_mut().zip(points) {
        *a = nearest(p, &centres[..k], weights);
    }
    k
}

/// Index of the centre nearest to `p`.
#[inline]
pub fn nearest(p: &Point, centres: &[Point], weights: &Point) -> u8 {
    let mut best = (f32::INFINITY, 0u8);
    for (j, c) in centres.iter().enumerate() {
        let d = dist2(p, c, weights);
        if d < best.0 {
            best = (d, j as u8);
        }
    }
    best.1
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn finds_three_separated_blobs() {
        let mut pts = Vec::new();
        for (i, c) in [
            [10.0, 10.0, 10.0, 100.0],
            [200.0, 30.0, 30.0, 150.0],
            [50.0, 200.0, 90.0, 300.0],
        ]
        .iter()
        .enumerate()
        {
            for j in 0..50 {
                let e = (j % 7) as f32 - 3.0 + i as f32;
                pts.push([c[0] + e, c[1] - e, c[2] + e * 0.5, c[3] + e]);
            }
        }
        let mut centres = [[0.0; 4]; 3];
        let mut assign = vec![0u8; pts.len()];
        let mut scratch = vec![0.0; pts.len()];
        let k = kmeans(&pts, &[1.0; 4], 20, &mut centres, &mut assign, &mut scratch);
        assert_eq!(k, 3);
        for b in 0..3 {
            let first = assign[b * 50];
            assert!(
                assign[b * 50..(b + 1) * 50].iter().all(|&a| a == first),
                "blob {b} split"
            );
        }
        assert!(assign[0] != assign[50] && assign[50] != assign[100] && assign[0] != assign[100]);
    }
}
