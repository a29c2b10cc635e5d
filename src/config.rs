//! `umbra.toml`: user settings. Every key is optional; `config/umbra.toml` documents each one with
//! its default. Unknown keys are errors, so a typo never silently falls back to a default.

use std::path::{Path, PathBuf};
use std::time::Duration;

use serde::Deserialize;

use crate::capture::reconnect::Backoff;
use crate::classify::Params;
use crate::error::{Error, Result};
use crate::sink::mcap::McapOptions;

/// The whole configuration file.
#[derive(Clone, Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Config {
    /// `[classifier]`: thresholds of the shadow classifier.
    #[serde(default)]
    pub classifier: ClassifierConfig,
    /// `[run]`: what `umbra run` captures and where it writes.
    #[serde(default)]
    pub run: RunConfig,
    /// `[device]`: how a live Kinect is watched and reopened.
    #[serde(default)]
    pub device: DeviceConfig,
    /// `[mcap]`: the MCAP segments `umbra run` writes.
    #[serde(default)]
    pub mcap: McapConfig,
    /// `[foreground]`: shadow-seeded foreground masks in the daemon.
    #[serde(default)]
    pub foreground: ForegroundConfig,
}

/// `[foreground]` keys.
#[derive(Clone, Debug, Default, Deserialize, PartialEq)]
#[serde(deny_unknown_fields, default)]
pub struct ForegroundConfig {
    /// Foreground masks per second on `/umbra/foreground_mask`; 0 turns them off. Masks are made
    /// on a thread of their own that skips frames while busy, so labels never wait for them.
    pub rate_hz: f64,
}

/// `[run]` keys; the command-line flags of the same names override them.
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields, default)]
pub struct RunConfig {
    /// `kinect`, `kinect:INDEX`, `kinect:SERIAL` or `replay:DIR`.
    pub source: String,
    /// Output folder for MCAP segments (no default: this or `--out`).
    pub out: Option<PathBuf>,
    /// Also write SPEC §4 label PNGs into this folder.
    pub export_labels: Option<PathBuf>,
    /// Calibration file overriding the source's own.
    pub calibration: Option<PathBuf>,
    /// With `replay:` sources, read as fast as possible instead of at recorded speed.
    pub fast: bool,
    /// Seconds between status lines in the log (the systemd STATUS is updated every second).
    pub status_interval_s: f64,
}

impl Default for RunConfig {
    fn default() -> Self {
        RunConfig {
            source: "kinect".into(),
            out: None,
            export_labels: None,
            calibration: None,
            fast: false,
            status_interval_s: 60.0,
        }
    }
}

/// `[device]` keys.
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields, default)]
pub struct DeviceConfig {
    /// A Kinect that delivers no depth frame for this long is treated as lost and reopened.
    pub stall_timeout_s: f64,
    /// First wait before reopening a lost device; it doubles per failed attempt.
    pub reconnect_initial_s: f64,
    /// Longest wait between attempts to reopen a lost device.
    pub reconnect_max_s: f64,
}

impl Default for DeviceConfig {
    fn default() -> Self {
        let b = Backoff::default();
        DeviceConfig {
            stall_timeout_s: 5.0,
            reconnect_initial_s: b.initial.as_secs_f64(),
            reconnect_max_s: b.max.as_secs_f64(),
        }
    }
}

/// `[mcap]` keys; see [`McapOptions`] for their meaning.
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields, default)]
pub struct McapConfig {
    /// Start a new segment at this size, MiB.
    pub segment_mib: u64,
    /// Start a new segment at this age, seconds.
    pub segment_s: f64,
    /// Delete the oldest segments while the folder holds more than this, MiB.
    pub total_cap_mib: u64,
    /// Also write the colour image.
    pub rgb: bool,
    /// zstd level of the chunks.
    pub zstd_level: u32,
    /// fdatasync the open segment this often, seconds (0: leave it to the kernel).
    pub sync_interval_s: f64,
    /// After a write failure, wait this long before trying again, seconds.
    pub retry_interval_s: f64,
}

impl Default for McapConfig {
    fn default() -> Self {
        let o = McapOptions::default();
        McapConfig {
            segment_mib: o.segment_bytes >> 20,
            segment_s: o.segment_age.as_secs_f64(),
            total_cap_mib: o.total_cap_bytes >> 20,
            rgb: o.write_rgb,
            zstd_level: o.zstd_level,
            sync_interval_s: o.sync_interval.map_or(0.0, |d| d.as_secs_f64()),
            retry_interval_s: o.retry_interval.as_secs_f64(),
        }
    }
}

/// `[classifier]` keys; see [`Params`] for their meaning.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct ClassifierConfig {
    /// Smallest disparity step (px) between a hole's bounds that counts as a depth edge.
    pub min_step_px: f64,
    /// How much wider than eq. (3) predicts an attached shadow may be (px).
    pub attached_over_px: f64,
    /// Tolerance (px) on each detached-shadow equation.
    pub detached_tol_px: f64,
    /// Valid runs this short inside a hole are noise.
    pub max_island_px: usize,
}

impl Default for ClassifierConfig {
    fn default() -> Self {
        let p = Params::default();
        ClassifierConfig {
            min_step_px: p.min_step_px,
            attached_over_px: p.attached_over_px,
            detached_tol_px: p.detached_tol_px,
            max_island_px: p.max_island_px,
        }
    }
}

impl Config {
    /// Reads and validates a configuration file.
    pub fn load(path: &Path) -> Result<Self> {
        let text = std::fs::read_to_string(path).map_err(|e| Error::io(path, "reading", e))?;
        Self::from_toml_str(&text, path)
    }

    /// Loads `path` if given, else the defaults.
    pub fn load_or_default(path: Option<&Path>) -> Result<Self> {
        path.map_or_else(|| Ok(Config::default()), Config::load)
    }

    /// Parses and validates configuration TOML; `path` is only used in error messages.
    pub fn from_toml_str(text: &str, path: &Path) -> Result<Self> {
        let c: Config =
            toml::from_str(text).map_err(|e| crate::calib::toml_error(path, text, &e))?;
        let k = &c.classifier;
        let check = |ok: bool, key: &str, v: f64, want: &str| {
            if ok && v.is_finite() {
                Ok(())
            } else {
                Err(Error::input(
                    path,
                    format!("key classifier.{key}"),
                    format!("value {v} is not {want}"),
                ))
            }
        };
        check(
            (0.25..=10.0).contains(&k.min_step_px),
            "min_step_px",
            k.min_step_px,
            "between 0.25 and 10",
        )?;
        check(
            (0.0..=50.0).contains(&k.attached_over_px),
            "attached_over_px",
            k.attached_over_px,
            "between 0 and 50",
        )?;
        check(
            (0.0..=20.0).contains(&k.detached_tol_px),
            "detached_tol_px",
            k.detached_tol_px,
            "between 0 and 20",
        )?;
        check(
            k.max_island_px <= 10,
            "max_island_px",
            k.max_island_px as f64,
            "between 0 and 10",
        )?;
        let check = |ok: bool, key: &str, v: f64, want: &str| {
            if ok && v.is_finite() {
                Ok(())
            } else {
                Err(Error::input(
                    path,
                    format!("key {key}"),
                    format!("value {v} is not {want}"),
                ))
            }
        };
        let r = &c.run;
        check(
            (0.1..=86_400.0).contains(&r.status_interval_s),
            "run.status_interval_s",
            r.status_interval_s,
            "between 0.1 and 86400 seconds",
        )?;
        if r.source.parse::<crate::cli::run::SourceSpec>().is_err() {
            return Err(Error::input(
                path,
                "key run.source",
                format!(
                    "{:?} is not kinect, kinect:INDEX, kinect:SERIAL or replay:DIR",
                    r.source
                ),
            ));
        }
        for (key, v) in [
            ("run.out", &r.out),
            ("run.export_labels", &r.export_labels),
            ("run.calibration", &r.calibration),
        ] {
            if v.as_ref().is_some_and(|p| p.as_os_str().is_empty()) {
                return Err(Error::input(
                    path,
                    format!("key {key}"),
                    "is empty: give a path or leave the key out",
                ));
            }
        }
        let d = &c.device;
        check(
            (0.1..=3600.0).contains(&d.stall_timeout_s),
            "device.stall_timeout_s",
            d.stall_timeout_s,
            "between 0.1 and 3600 seconds",
        )?;
        check(
            (0.01..=3600.0).contains(&d.reconnect_initial_s),
            "device.reconnect_initial_s",
            d.reconnect_initial_s,
            "between 0.01 and 3600 seconds",
        )?;
        check(
            (d.reconnect_initial_s..=3600.0).contains(&d.reconnect_max_s),
            "device.reconnect_max_s",
            d.reconnect_max_s,
            "between device.reconnect_initial_s and 3600 seconds",
        )?;
        let m = &c.mcap;
        check(
            (1..=1 << 20).contains(&m.segment_mib),
            "mcap.segment_mib",
            m.segment_mib as f64,
            "between 1 and 1048576",
        )?;
        check(
            (1.0..=7.0 * 86_400.0).contains(&m.segment_s),
            "mcap.segment_s",
            m.segment_s,
            "between 1 second and a week",
        )?;
        check(
            m.total_cap_mib >= m.segment_mib,
            "mcap.total_cap_mib",
            m.total_cap_mib as f64,
            "at least mcap.segment_mib",
        )?;
        check(
            (1..=19).contains(&m.zstd_level),
            "mcap.zstd_level",
            m.zstd_level as f64,
            "between 1 and 19",
        )?;
        check(
            (0.0..=3600.0).contains(&m.sync_interval_s),
            "mcap.sync_interval_s",
            m.sync_interval_s,
            "between 0 and 3600 seconds",
        )?;
        check(
            (0.0..=3600.0).contains(&m.retry_interval_s),
            "mcap.retry_interval_s",
            m.retry_interval_s,
            "between 0 and 3600 seconds",
        )?;
        let f = &c.foreground;
        check(
            (0.0..=30.0).contains(&f.rate_hz),
            "foreground.rate_hz",
            f.rate_hz,
            "between 0 (off) and 30 per second",
        )?;
        Ok(c)
    }

    /// The MCAP writer settings.
    pub fn mcap_options(&self) -> McapOptions {
        let m = &self.mcap;
        McapOptions {
            segment_bytes: m.segment_mib << 20,
            segment_age: Duration::from_secs_f64(m.segment_s),
            total_cap_bytes: m.total_cap_mib << 20,
            write_rgb: m.rgb,
            write_foreground: self.foreground.rate_hz > 0.0,
            zstd_level: m.zstd_level,
            retry_interval: Duration::from_secs_f64(m.retry_interval_s),
            sync_interval: (m.sync_interval_s > 0.0)
                .then(|| Duration::from_secs_f64(m.sync_interval_s)),
        }
    }

    /// How a lost device is reopened.
    pub fn backoff(&self) -> Backoff {
        Backoff {
            initial: Duration::from_secs_f64(self.device.reconnect_initial_s),
            max: Duration::from_secs_f64(self.device.reconnect_max_s),
        }
    }

    /// The classifier thresholds.
    pub fn params(&self) -> Params {
        let k = &self.classifier;
        Params {
            min_step_px: k.min_step_px,
            attached_over_px: k.attached_over_px,
            detached_tol_px: k.detached_tol_px,
            max_island_px: k.max_island_px,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shipped_config_matches_built_in_defaults() {
        let text = include_str!("../config/umbra.toml");
        let c = Config::from_toml_str(text, Path::new("config/umbra.toml")).unwrap();
        assert_eq!(
            c.params(),
            Params::default(),
            "config/umbra.toml documents the defaults"
        );
        let d = Config::default();
        assert_eq!(
            (&c.run, &c.device, &c.mcap, &c.foreground),
            (&d.run, &d.device, &d.mcap, &d.foreground),
            "config/umbra.toml documents the defaults"
        );
        // Every key is written out (commented out only where there is no default), so the file
        // stays a complete reference: a key added to the code must be added there too.
        for key in [
            "source",
            "out",
            "export_labels",
            "calibration",
            "fast",
            "status_interval_s",
            "stall_timeout_s",
            "reconnect_initial_s",
            "reconnect_max_s",
            "segment_mib",
            "segment_s",
            "total_cap_mib",
            "rgb",
            "zstd_level",
            "sync_interval_s",
            "retry_interval_s",
            "rate_hz",
        ] {
            assert!(
                text.lines()
                    .any(|l| l.trim_start_matches("# ").starts_with(&format!("{key} ="))),
                "config/umbra.toml lacks {key}"
            );
        }
    }

    #[test]
    fn errors_name_key_and_line() {
        let e = Config::from_toml_str("[classifier]\nmin_step_px = -1\n", Path::new("u.toml"))
            .unwrap_err()
            .to_string();
        assert!(
            e.starts_with("u.toml: key classifier.min_step_px: value -1"),
            "{e}"
        );
        let e = Config::from_toml_str("[classifier]\nmin_stp_px = 1\n", Path::new("u.toml"))
            .unwrap_err()
            .to_string();
        assert!(
            e.starts_with("u.toml: line 2, column 1") && e.contains("min_stp_px"),
            "{e}"
        );
    }
}
