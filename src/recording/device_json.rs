//! libfreenect's registration record (`device.json`, as newer `fakenect-record` writes it), used
//! for the calibration when a recording has no `calibration.toml`.
//!
//! Only the zero-plane block and `const_shift` matter here: `reference_distance` /
//! `reference_pixel_size` give the IR focal length (the pixel size is for the 1280-wide sensor,
//! hence the factor 2 at 640 px), `dcmos_emitter_distance` / `dcmos_rcmos_distance` (cm) the
//! projector and RGB baselines, and `const_shift` the raw value of zero disparity. Depth from raw
//! then agrees with libfreenect's own `raw_to_mm_shift` table (`src/registration.c`).

use std::path::Path;

use serde::Deserialize;

use crate::calib::Calibration;
use crate::error::{Error, Result};

#[derive(Deserialize)]
struct DeviceJson {
    reg_info: RegInfo,
    /// Absent from hand-made files; the NYU model's zero-disparity value is used then.
    const_shift: Option<f64>,
}

#[derive(Deserialize)]
struct RegInfo {
    zero_plane_info: ZeroPlane,
}

/// The zero-plane block of libfreenect's registration (`freenect_zero_plane_info`): what both
/// `device.json` and a live Kinect's `freenect_copy_registration` provide.
#[derive(Clone, Copy, Debug, Deserialize)]
pub struct ZeroPlane {
    /// IR camera to IR projector, cm.
    pub dcmos_emitter_distance: f64,
    /// IR camera to RGB camera, cm.
    pub dcmos_rcmos_distance: f64,
    /// Zero-plane distance, mm.
    pub reference_distance: f64,
    /// Size of a (1280-wide sensor) pixel on the zero plane, mm.
    pub reference_pixel_size: f64,
}

impl ZeroPlane {
    /// True for the all-zero block libfreenect reports (and `fakenect-record` writes) for a
    /// device without registration data; libfreenect itself takes `reference_distance == 0` as
    /// "no registration info".
    pub fn is_unset(&self) -> bool {
        [
            self.dcmos_emitter_distance,
            self.dcmos_rcmos_distance,
            self.reference_distance,
            self.reference_pixel_size,
        ]
        .iter()
        .all(|&v| v == 0.0)
    }
}

/// Reads `device.json` and derives a calibration from it (NYU defaults for what it lacks);
/// `None` when it records that the device had no registration data ([`ZeroPlane::is_unset`]).
pub fn load(path: &Path) -> Result<Option<Calibration>> {
    let text = std::fs::read_to_string(path).map_err(|e| Error::io(path, "reading", e))?;
    from_str(&text, path)
}

/// Parses device.json text (see [`load`]); `path` is used in error messages only.
pub fn from_str(text: &str, path: &Path) -> Result<Option<Calibration>> {
    let d: DeviceJson = serde_json::from_str(text).map_err(|e| {
        // serde_json's message ends in " at line L column C": the place is already in front.
        let msg = e.to_string();
        let msg = msg
            .rsplit_once(" at line ")
            .map_or(msg.as_str(), |(m, _)| m)
            .to_string();
        Error::input(
            path,
            format!("line {}, column {}", e.line(), e.column()),
            msg,
        )
    })?;
    let z = &d.reg_info.zero_plane_info;
    if z.is_unset() {
        return Ok(None);
    }
    from_zero_plane(z, d.const_shift, path).map(Some)
}

/// Derives a calibration from the zero-plane numbers and, when known, the registration's
/// `const_shift` (NYU defaults for the rest); `path` names where they came from in error
/// messages (a file, or a device). An all-zero block ([`ZeroPlane::is_unset`]) is an error that
/// says so.
pub fn from_zero_plane(
    z: &ZeroPlane,
    const_shift: Option<f64>,
    path: &Path,
) -> Result<Calibration> {
    if z.is_unset() {
        return Err(Error::input(
            path,
            "reg_info.zero_plane_info",
            "all zero: the device reported no registration data",
        ));
    }
    let key = |k: &str| format!("key reg_info.zero_plane_info.{k}");
    // Each value in a range a Kinect v1 can have, so a wrong one is reported under its own key
    // rather than as a derived calibration value the file does not contain.
    let within = |v: f64, k: &str, lo: f64, hi: f64, unit: &str| {
        if v.is_finite() && v > lo && v < hi {
            Ok(v)
        } else {
            Err(Error::input(
                path,
                key(k),
                format!("value {v} must be greater than {lo} and less than {hi} {unit}"),
            ))
        }
    };
    let zpd = within(
        z.reference_distance,
        "reference_distance",
        0.0,
        10_000.0,
        "mm",
    )?;
    let zpps = within(
        z.reference_pixel_size,
        "reference_pixel_size",
        0.0,
        10.0,
        "mm",
    )?;
    let emitter_cm = within(
        z.dcmos_emitter_distance,
        "dcmos_emitter_distance",
        1.0,
        50.0,
        "cm",
    )?;
    let rgb_cm = within(
        z.dcmos_rcmos_distance,
        "dcmos_rcmos_distance",
        0.0,
        50.0,
        "cm",
    )?;
    let const_shift = const_shift
        .map(|s| {
            if s.is_finite() && (0.0..1000.0).contains(&s) {
                Ok(s)
            } else {
                Err(Error::input(
                    path,
                    "key const_shift",
                    format!("value {s} must be at least 0 and less than 1000 raw units"),
                ))
            }
        })
        .transpose()?;
    let mut c = Calibration::nyu_default();
    let f = zpd / (2.0 * zpps);
    if !(50.0..5000.0).contains(&f) {
        return Err(Error::input(
            path,
            key("reference_distance"),
            format!("{zpd} mm over twice reference_pixel_size {zpps} mm gives a focal length of {f:.1} px, expected 50 to 5000"),
        ));
    }
    c.depth.fx = f;
    c.depth.fy = f;
    c.depth.cx = 319.5;
    c.depth.cy = 239.5;
    c.raw.baseline_m = emitter_cm / 100.0;
    // Raw values are 1/8-pixel disparity offsets, so the model's numerator is 8·f·b.
    c.raw.numerator = 8.0 * f * c.raw.baseline_m;
    // libfreenect: shift = (raw − 4·const_shift)/4 − 0.375 sensor pixels on the zero plane, and
    // depth = ref·dcl/(dcl − shift·pixel): zero disparity at raw = 4·dcl/pixel + 4·const_shift + 1.5.
    if let Some(s) = const_shift {
        c.raw.denominator = 4.0 * emitter_cm / zpps + 4.0 * s + 1.5;
    }
    c.depth_to_rgb.translation.x = -rgb_cm / 100.0;
    c.validate()
        .map_err(|(k, why)| Error::input(path, format!("derived calibration key {k}"), why))?;
    Ok(c)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn derives_focal_length_and_baseline() {
        let text = r#"{"reg_info":{"ax":1,"zero_plane_info":{"dcmos_emitter_distance":7.5,
            "dcmos_rcmos_distance":2.4,"reference_distance":120,"reference_pixel_size":0.1042}},"const_shift":200}"#;
        let c = from_str(text, Path::new("device.json")).unwrap().unwrap();
        assert!((c.depth.fx - 575.8).abs() < 0.1, "{}", c.depth.fx);
        assert!((c.raw.baseline_m - 0.075).abs() < 1e-9);
        assert!((c.depth_to_rgb.translation.x + 0.024).abs() < 1e-9);
    }

    /// Depth from raw as libfreenect's `raw_to_mm_shift` table gives it (`freenect_raw_to_mm` in
    /// its `src/registration.c`, evaluated by hand and truncated to whole millimetres as it is):
    /// the factory numbers of a Kinect v1 with two values of `const_shift`.
    #[test]
    fn depth_agrees_with_libfreenects_table() {
        let json = |shift: &str| {
            format!(
                r#"{{"reg_info":{{"zero_plane_info":{{"dcmos_emitter_distance":7.5,"dcmos_rcmos_distance":2.4,
                "reference_distance":120,"reference_pixel_size":0.1042}}}}{shift}}}"#
            )
        };
        let cases = [
            (
                ",\"const_shift\":200",
                [(600, 705), (800, 1193), (1000, 3864)],
            ),
            (
                ",\"const_shift\":225",
                [(500, 501), (800, 887), (1050, 2478)],
            ),
        ];
        for (shift, table) in cases {
            let c = from_str(&json(shift), Path::new("device.json"))
                .unwrap()
                .unwrap();
            for (raw, mm) in table {
                let ours = 1000.0 * c.depth_m(raw).unwrap();
                assert!(
                    (0.0..1.0).contains(&(ours - f64::from(mm))),
                    "{shift} raw {raw}: {ours} mm, libfreenect {mm}"
                );
            }
        }
        // Without const_shift (hand-made files) the NYU model's zero-disparity value stays.
        let c = from_str(&json(""), Path::new("device.json"))
            .unwrap()
            .unwrap();
        assert_eq!(
            c.raw.denominator,
            Calibration::nyu_default().raw.denominator
        );
        let e = from_str(&json(",\"const_shift\":-3"), Path::new("d.json"))
            .unwrap_err()
            .to_string();
        assert!(e.starts_with("d.json: key const_shift: "), "{e}");
    }

    #[test]
    fn errors_name_place() {
        let e = from_str("{\"reg_info\": 3", Path::new("d.json"))
            .unwrap_err()
            .to_string();
        assert!(e.starts_with("d.json: line 1, column"), "{e}");
        let e = from_str(r#"{"reg_info":{"zero_plane_info":{"dcmos_emitter_distance":-1,"dcmos_rcmos_distance":2.4,"reference_distance":120,"reference_pixel_size":0.1}}}"#, Path::new("d.json")).unwrap_err().to_string();
        assert!(e.contains("dcmos_emitter_distance"), "{e}");
    }

    #[test]
    fn out_of_range_values_read_as_an_exclusive_range() {
        let e = from_str(r#"{"reg_info":{"zero_plane_info":{"dcmos_emitter_distance":7.5,"dcmos_rcmos_distance":2.4,"reference_distance":0,"reference_pixel_size":0.1}}}"#, Path::new("d.json")).unwrap_err().to_string();
        assert_eq!(
            e,
            "d.json: key reg_info.zero_plane_info.reference_distance: value 0 must be greater than 0 and less than 10000 mm"
        );
    }

    /// What `fakenect-record` writes for a device without registration data.
    const NO_REGISTRATION: &str = r#"{"reg_info":{"ax":0,"zero_plane_info":{"dcmos_emitter_distance":0,
        "dcmos_rcmos_distance":0,"reference_distance":0,"reference_pixel_size":0}},"const_shift":0}"#;

    #[test]
    fn all_zero_zero_plane_means_no_registration_data() {
        assert!(from_str(NO_REGISTRATION, Path::new("device.json"))
            .unwrap()
            .is_none());
        // A live device's all-zero block is reported as what it is, not as a range error.
        let z = ZeroPlane {
            dcmos_emitter_distance: 0.0,
            dcmos_rcmos_distance: 0.0,
            reference_distance: 0.0,
            reference_pixel_size: 0.0,
        };
        let e = from_zero_plane(&z, Some(0.0), Path::new("kinect"))
            .unwrap_err()
            .to_string();
        assert_eq!(
            e,
            "kinect: reg_info.zero_plane_info: all zero: the device reported no registration data"
        );
    }
}
