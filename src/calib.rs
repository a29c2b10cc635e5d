//! Camera calibration of SPEC §3 (`calibration.toml`) and the Kinect v1 raw-disparity model.
//!
//! The raw model `z = numerator / (denominator - raw)` makes disparity *linear* in the raw value:
//! `disp_px = f·b / z = (f·b / numerator) · (denominator - raw)`, which is why the classifier can
//! work on raw values with one multiplier ([`Calibration::px_per_raw`]).

use std::path::Path;

use nalgebra::{Matrix3, Vector3};
use serde::{Deserialize, Serialize};

use crate::error::{Error, Result};
use crate::labels::{HEIGHT, NO_DEPTH, WIDTH};

/// Pinhole intrinsics of one camera, pixels.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Intrinsics {
    /// Focal length along x.
    pub fx: f64,
    /// Focal length along y.
    pub fy: f64,
    /// Principal point x.
    pub cx: f64,
    /// Principal point y.
    pub cy: f64,
    /// Image width the intrinsics refer to.
    pub width: u32,
    /// Image height the intrinsics refer to.
    pub height: u32,
}

/// Rigid transform from the depth camera to the RGB camera: `X_rgb = R * X_depth + t`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Extrinsics {
    /// Rotation R.
    pub rotation: Matrix3<f64>,
    /// Translation t, metres.
    pub translation: Vector3<f64>,
}

/// The raw 11-bit disparity model and the projector baseline.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawModel {
    /// Numerator of `depth_m = numerator / (denominator - raw)`.
    pub numerator: f64,
    /// Denominator of the same model.
    pub denominator: f64,
    /// IR projector to IR camera distance `b`, metres.
    pub baseline_m: f64,
}

/// A full calibration: both cameras, the transform between them and the raw model.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Calibration {
    /// The IR camera that produced the raw depth map.
    pub depth: Intrinsics,
    /// The RGB camera.
    pub rgb: Intrinsics,
    /// Depth camera to RGB camera.
    pub depth_to_rgb: Extrinsics,
    /// Raw value to metres.
    pub raw: RawModel,
}

#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct ExtrinsicsToml {
    rotation: [f64; 9],
    translation: [f64; 3],
}

#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct CalibrationToml {
    depth: Intrinsics,
    rgb: Intrinsics,
    depth_to_rgb: ExtrinsicsToml,
    raw: RawModel,
}

impl Default for Calibration {
    fn default() -> Self {
        Self::nyu_default()
    }
}

impl Calibration {
    /// NYU Depth v2 Kinect v1 calibration, the default when a recording carries none (SPEC §3).
    pub fn nyu_default() -> Self {
        Calibration {
            depth: Intrinsics {
                fx: 582.62,
                fy: 582.69,
                cx: 313.04,
                cy: 238.44,
                width: 640,
                height: 480,
            },
            rgb: Intrinsics {
                fx: 518.86,
                fy: 519.47,
                cx: 325.58,
                cy: 253.74,
                width: 640,
                height: 480,
            },
            depth_to_rgb: Extrinsics {
                rotation: Matrix3::identity(),
                translation: Vector3::new(-0.025, 0.0, 0.0),
            },
            raw: RawModel {
                numerator: 351.3,
                denominator: 1092.5,
                baseline_m: 0.075,
            },
        }
    }

    /// Reads and validates a `calibration.toml`.
    pub fn load(path: &Path) -> Result<Self> {
        let text = std::fs::read_to_string(path).map_err(|e| Error::io(path, "reading", e))?;
        Self::from_toml_str(&text, path)
    }

    /// Parses and validates calibration TOML; `path` is only used in error messages.
    pub fn from_toml_str(text: &str, path: &Path) -> Result<Self> {
        let table: toml::Table = toml::from_str(text).map_err(|e| toml_error(path, text, &e))?;
        check_required_keys(&table, path)?;
        let parsed: CalibrationToml =
            toml::from_str(text).map_err(|e| toml_error(path, text, &e))?;
        let r = parsed.depth_to_rgb.rotation;
        let t = parsed.depth_to_rgb.translation;
        let calib = Calibration {
            depth: parsed.depth,
            rgb: parsed.rgb,
            depth_to_rgb: Extrinsics {
                rotation: Matrix3::from_row_slice(&r),
                translation: Vector3::new(t[0], t[1], t[2]),
            },
            raw: parsed.raw,
        };
        calib
            .validate()
            .map_err(|(key, problem)| Error::input(path, format!("key {key}"), problem))?;
        Ok(calib)
    }

    /// Serialises in the SPEC §3 layout (what `umbra synth` and `umbra record` write).
    pub fn to_toml_string(&self) -> String {
        let r = self.depth_to_rgb.rotation;
        let t = self.depth_to_rgb.translation;
        let doc = CalibrationToml {
            depth: self.depth,
            rgb: self.rgb,
            depth_to_rgb: ExtrinsicsToml {
                rotation: [
                    r[(0, 0)],
                    r[(0, 1)],
                    r[(0, 2)],
                    r[(1, 0)],
                    r[(1, 1)],
                    r[(1, 2)],
                    r[(2, 0)],
                    r[(2, 1)],
                    r[(2, 2)],
                ],
                translation: [t[0], t[1], t[2]],
            },
            raw: self.raw,
        };
        toml::to_string(&doc).expect("calibration always serialises")
    }

    /// Checks that every number is finite and physically plausible for a Kinect v1.
    /// On failure returns the offending key and what was expected.
    pub fn validate(&self) -> std::result::Result<(), (String, String)> {
        fn check(
            ok: bool,
            key: &str,
            value: f64,
            want: &str,
        ) -> std::result::Result<(), (String, String)> {
            if ok && value.is_finite() {
                Ok(())
            } else {
                Err((key.to_string(), format!("value {value} is not {want}")))
            }
        }
        for (name, k) in [("depth", &self.depth), ("rgb", &self.rgb)] {
            if k.width as usize != WIDTH || k.height as usize != HEIGHT {
                return Err((
                    format!("{name}.width/height"),
                    format!("{}x{} is not supported, expected 640x480 (the only Kinect v1 mode umbra reads)", k.width, k.height),
                ));
            }
            check(
                k.fx > 50.0 && k.fx < 5000.0,
                &format!("{name}.fx"),
                k.fx,
                "a focal length in pixels between 50 and 5000",
            )?;
            check(
                k.fy > 50.0 && k.fy < 5000.0,
                &format!("{name}.fy"),
                k.fy,
                "a focal length in pixels between 50 and 5000",
            )?;
            check(
                k.cx >= 0.0 && k.cx <= k.width as f64,
                &format!("{name}.cx"),
                k.cx,
                "inside the image",
            )?;
            check(
                k.cy >= 0.0 && k.cy <= k.height as f64,
                &format!("{name}.cy"),
                k.cy,
                "inside the image",
            )?;
            if (k.fx / k.fy - 1.0).abs() > 0.2 {
                return Err((
                    format!("{name}.fy"),
                    format!("fx {} and fy {} differ by more than 20%", k.fx, k.fy),
                ));
            }
        }
        let r = self.depth_to_rgb.rotation;
        for (i, v) in r.iter().enumerate() {
            check(
                v.abs() <= 1.0 + 1e-6,
                &format!("depth_to_rgb.rotation[{i}]"),
                *v,
                "a rotation matrix entry in [-1, 1]",
            )?;
        }
        let orth = (r * r.transpose() - Matrix3::identity()).abs().max();
        if orth > 1e-3 || r.determinant() < 0.0 {
            return Err((
                "depth_to_rgb.rotation".into(),
                format!(
                    "is not a proper rotation (|R·Rᵀ − I| = {orth:.2e}, det = {:.4})",
                    r.determinant()
                ),
            ));
        }
        for (i, v) in self.depth_to_rgb.translation.iter().enumerate() {
            check(
                v.abs() < 0.5,
                &format!("depth_to_rgb.translation[{i}]"),
                *v,
                "a translation in metres below 0.5",
            )?;
        }
        let m = &self.raw;
        check(
            m.numerator > 10.0 && m.numerator < 10_000.0,
            "raw.numerator",
            m.numerator,
            "between 10 and 10000",
        )?;
        check(
            m.denominator > 100.0 && m.denominator <= 4096.0,
            "raw.denominator",
            m.denominator,
            "between 100 and 4096",
        )?;
        check(
            m.baseline_m > 0.01 && m.baseline_m < 0.5,
            "raw.baseline_m",
            m.baseline_m,
            "a baseline in metres between 0.01 and 0.5",
        )?;
        Ok(())
    }

    /// Depth in metres of a raw value; `None` for "no depth" and values the model cannot map.
    pub fn depth_m(&self, raw: u16) -> Option<f64> {
        if raw >= NO_DEPTH || f64::from(raw) >= self.raw.denominator - 0.5 {
            return None;
        }
        Some(self.raw.numerator / (self.raw.denominator - f64::from(raw)))
    }

    /// The raw value a surface at `z` metres produces (rounded, not clamped to the valid range).
    pub fn raw_from_depth(&self, z: f64) -> f64 {
        self.raw.denominator - self.raw.numerator / z
    }

    /// `f·b` in pixel·metres: disparity in pixels of a point at 1 m.
    pub fn fb(&self) -> f64 {
        self.depth.fx * self.raw.baseline_m
    }

    /// Disparity pixels per raw unit: `w = px_per_raw · (raw(Sa) − raw(Sb))` (SPEC §1, eq. 3).
    pub fn px_per_raw(&self) -> f64 {
        self.fb() / self.raw.numerator
    }
}

/// The tables of SPEC §3's `calibration.toml` and the keys each must have, in file order.
const REQUIRED_KEYS: [(&str, &[&str]); 4] = [
    ("depth", &["fx", "fy", "cx", "cy", "width", "height"]),
    ("rgb", &["fx", "fy", "cx", "cy", "width", "height"]),
    ("depth_to_rgb", &["rotation", "translation"]),
    ("raw", &["numerator", "denominator", "baseline_m"]),
];

/// Reports the first missing table or key by name: serde's "missing field" carries no table and
/// points at the top of the file, which says neither where nor what to add.
fn check_required_keys(doc: &toml::Table, path: &Path) -> Result<()> {
    for (name, keys) in REQUIRED_KEYS {
        let place = format!("[{name}]");
        match doc.get(name) {
            None => {
                return Err(Error::input(
                    path,
                    place,
                    format!("missing table; expected one with {}", keys.join(", ")),
                ))
            }
            Some(toml::Value::Table(t)) => {
                if let Some(key) = keys.iter().find(|k| !t.contains_key(**k)) {
                    return Err(Error::input(path, place, format!("missing key {key}")));
                }
            }
            // A table of the wrong type is left to the typed parse, which knows its line.
            Some(_) => {}
        }
    }
    Ok(())
}

/// Turns a TOML parse error into `line L, column C` plus its message.
pub(crate) fn toml_error(path: &Path, text: &str, e: &toml::de::Error) -> Error {
    let place = match e.span() {
        Some(span) => {
            let before = &text[..span.start.min(text.len())];
            let line = before.matches('\n').count() + 1;
            let col = before.rsplit('\n').next().map_or(0, |l| l.chars().count()) + 1;
            format!("line {line}, column {col}")
        }
        None => String::new(),
    };
    Error::input(path, place, e.message().to_string())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn default_round_trips_through_toml() {
        let c = Calibration::nyu_default();
        let back = Calibration::from_toml_str(&c.to_toml_string(), Path::new("x.toml")).unwrap();
        assert_eq!(c, back);
    }

    #[test]
    fn px_per_raw_is_about_one_eighth() {
        // SPEC §1: w ≈ (raw(Sa) − raw(Sb)) / 8.
        let k = Calibration::nyu_default().px_per_raw();
        assert!((k - 0.125).abs() < 0.003, "{k}");
    }

    #[test]
    fn depth_model_matches_spec_formula() {
        let c = Calibration::nyu_default();
        assert_eq!(c.depth_m(2047), None);
        let z = c.depth_m(800).unwrap();
        assert!((z - 351.3 / (1092.5 - 800.0)).abs() < 1e-12);
        assert!((c.raw_from_depth(z) - 800.0).abs() < 1e-9);
    }

    #[test]
    fn bad_values_name_the_key() {
        let c = Calibration::nyu_default()
            .to_toml_string()
            .replace("fx = 582.62", "fx = nan");
        let e = Calibration::from_toml_str(&c, Path::new("cal.toml"))
            .unwrap_err()
            .to_string();
        assert!(e.starts_with("cal.toml: key depth.fx:"), "{e}");
        let c = Calibration::nyu_default()
            .to_toml_string()
            .replace("baseline_m = 0.075", "baseline_m = 7.5");
        let e = Calibration::from_toml_str(&c, Path::new("cal.toml"))
            .unwrap_err()
            .to_string();
        assert!(e.contains("raw.baseline_m"), "{e}");
    }

    #[test]
    fn missing_keys_and_tables_are_named_with_their_table() {
        let full = Calibration::nyu_default().to_toml_string();
        let without = |table: &str, key: &str| {
            let start = full.find(&format!("[{table}]")).unwrap();
            let at = start + full[start..].find(&format!("\n{key} =")).unwrap() + 1;
            let end = at + full[at..].find('\n').unwrap() + 1;
            format!("{}{}", &full[..at], &full[end..])
        };
        let err = |text: &str| {
            Calibration::from_toml_str(text, Path::new("calibration.toml"))
                .unwrap_err()
                .to_string()
        };
        assert_eq!(
            err(&without("depth", "fy")),
            "calibration.toml: [depth]: missing key fy"
        );
        assert_eq!(
            err(&without("rgb", "fy")),
            "calibration.toml: [rgb]: missing key fy"
        );
        assert_eq!(
            err(&without("raw", "baseline_m")),
            "calibration.toml: [raw]: missing key baseline_m"
        );
        let no_raw = &full[..full.find("[raw]").unwrap()];
        assert_eq!(
            err(no_raw),
            "calibration.toml: [raw]: missing table; expected one with numerator, denominator, baseline_m"
        );
    }

    #[test]
    fn required_keys_are_the_serialised_ones() {
        // REQUIRED_KEYS must follow the structs, or a key they lack would pass the check.
        let doc: toml::Table =
            toml::from_str(&Calibration::nyu_default().to_toml_string()).unwrap();
        let want: Vec<(String, Vec<String>)> = REQUIRED_KEYS
            .iter()
            .map(|(t, keys)| (t.to_string(), keys.iter().map(|k| k.to_string()).collect()))
            .collect();
        let got: Vec<(String, Vec<String>)> = doc
            .iter()
            .map(|(t, v)| {
                let keys = v.as_table().unwrap().keys().cloned().collect();
                (t.clone(), keys)
            })
            .collect();
        let sorted = |mut v: Vec<(String, Vec<String>)>| {
            v.iter_mut().for_each(|(_, k)| k.sort());
            v.sort();
            v
        };
        assert_eq!(sorted(got), sorted(want));
    }

    #[test]
    fn syntax_errors_give_line_and_column() {
        let e = Calibration::from_toml_str("[depth]\nfx = = 3\n", Path::new("c.toml"))
            .unwrap_err()
            .to_string();
        assert!(e.starts_with("c.toml: line 2, column"), "{e}");
        assert!(!e.contains('\n'));
    }
}
