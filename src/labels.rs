//! Label codes of SPEC §2: the same `u8` values in every output (PNG, MCAP, JSON).

/// Frame width of every Kinect v1 stream umbra handles (libfreenect's medium resolution).
pub const WIDTH: usize = 640;
/// Frame height of every Kinect v1 stream umbra handles.
pub const HEIGHT: usize = 480;
/// Pixels in one frame.
pub const PIXELS: usize = WIDTH * HEIGHT;
/// The raw 11-bit value libfreenect uses for "no depth".
pub const NO_DEPTH: u16 = 2047;

/// `image` (rows of `row` values) with its rows in reverse order: a frame no camera repeats, for
/// timing the classifier without letting the branch predictor learn one frame's holes.
pub fn upside_down<T: Copy>(image: &[T], row: usize) -> Vec<T> {
    image.chunks_exact(row).rev().flatten().copied().collect()
}

/// Pixel has a depth measurement.
pub const VALID: u8 = 0;
/// Projector shadow touching its occluder (Deng et al. eq. 3).
pub const ATTACHED: u8 = 1;
/// Projector shadow separated from its thin occluder by lit background (eqs. 4–5).
pub const DETACHED: u8 = 2;
/// Background the RGB camera sees but the IR camera does not (RGB view only).
pub const ALIGNMENT: u8 = 3;
/// Every other hole: low albedo, specular, out of range, speckle, outside the IR field of view.
pub const OTHER: u8 = 4;

/// Number of label codes; codes are `0..CLASSES`.
pub const CLASSES: usize = 5;

/// Human-readable class names, indexed by code (used in summaries, JSON and legends).
pub const NAMES: [&str; CLASSES] = ["valid", "attached", "detached", "alignment", "other"];

/// Picture colours of the paper's Fig. 1, indexed by code; `VALID` is drawn grey by depth instead.
pub const COLOURS: [[u8; 3]; CLASSES] = [
    [128, 128, 128],
    [255, 0, 0],
    [0, 0, 255],
    [0, 255, 0],
    [255, 255, 0],
];

/// True for the three shadow classes (the paper's "any shadow" of Table 1).
pub fn is_shadow(code: u8) -> bool {
    matches!(code, ATTACHED | DETACHED | ALIGNMENT)
}

/// Counts pixels per class; codes outside the table are ignored.
pub fn histogram(labels: &[u8]) -> [u64; CLASSES] {
    // One pass per code: each compiles to a vectorised compare-and-count, several times faster
    // than one pass that indexes a counter per pixel (this runs twice per frame in the daemon).
    // Counting into a u8 per 255-byte chunk lets the compiler use 16 byte lanes per instruction.
    std::array::from_fn(|c| {
        let c = c as u8;
        labels
            .chunks(255)
            .map(|ch| u64::from(ch.iter().fold(0u8, |n, &l| n + u8::from(l == c))))
            .sum()
    })
}
