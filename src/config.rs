//! `umbra.toml`: user settings. Every key is optional; `config/umbra.toml` documents each one with
//! its default. Unknown keys are errors, so a typo never silently falls back to a default.

use std::path::Path;

use serde::Deserialize;

use crate::classify::Params;
use crate::error::{Error, Result};

/// The whole configuration file.
#[derive(Clone, Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Config {
    /// `[classifier]`: thresholds of the shadow classifier.
    #[serde(default)]
    pub classifier: ClassifierConfig,
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
        let c: Config = toml::from_str(text).map_err(|e| crate::calib::toml_error(path, text, &e))?;
        let k = &c.classifier;
        let check = |ok: bool, key: &str, v: f64, want: &str| {
            if ok && v.is_finite() {
                Ok(())
            } else {
                Err(Error::input(path, format!("key classifier.{key}"), format!("value {v} is not {want}")))
            }
        };
        check((0.25..=10.0).contains(&k.min_step_px), "min_step_px", k.min_step_px, "between 0.25 and 10")?;
        check((0.0..=50.0).contains(&k.attached_over_px), "attached_over_px", k.attached_over_px, "between 0 and 50")?;
        check((0.0..=20.0).contains(&k.detached_tol_px), "detached_tol_px", k.detached_tol_px, "between 0 and 20")?;
        check(k.max_island_px <= 10, "max_island_px", k.max_island_px as f64, "between 0 and 10")?;
        Ok(c)
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
        assert_eq!(c.params(), Params::default(), "config/umbra.toml documents the defaults");
    }

    #[test]
    fn errors_name_key_and_line() {
        let e = Config::from_toml_str("[classifier]\nmin_step_px = -1\n", Path::new("u.toml")).unwrap_err().to_string();
        assert!(e.starts_with("u.toml: key classifier.min_step_px: value -1"), "{e}");
        let e = Config::from_toml_str("[classifier]\nmin_stp_px = 1\n", Path::new("u.toml")).unwrap_err().to_string();
        assert!(e.starts_with("u.toml: line 2, column 1") && e.contains("min_stp_px"), "{e}");
    }
}
