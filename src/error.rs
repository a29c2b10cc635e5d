//! One error type whose `Display` is the one-line message of SPEC §5: the file, the place in it,
//! and what was expected.

use std::fmt;
use std::path::{Path, PathBuf};

/// Everything that can go wrong in umbra, each variant rendered as one line.
#[derive(Debug)]
pub enum Error {
    /// Malformed input: `path: place: problem`.
    Input {
        /// The file (or folder) that is wrong.
        path: PathBuf,
        /// Where in it: a line, a byte offset, a TOML key, a pixel.
        place: String,
        /// What was found and what was expected.
        problem: String,
    },
    /// An operating-system error while reading or writing a file.
    Io {
        /// The file involved.
        path: PathBuf,
        /// What umbra was doing ("reading", "creating", ...).
        action: &'static str,
        /// The underlying error.
        source: std::io::Error,
    },
    /// A request that cannot be satisfied (bad flag combination, frame out of range...).
    Usage(String),
}

/// Result alias used across the crate.
pub type Result<T, E = Error> = std::result::Result<T, E>;

impl Error {
    /// Builds an [`Error::Input`].
    pub fn input(
        path: impl AsRef<Path>,
        place: impl Into<String>,
        problem: impl Into<String>,
    ) -> Self {
        Error::Input {
            path: path.as_ref().to_path_buf(),
            place: place.into(),
            problem: problem.into(),
        }
    }

    /// Builds an [`Error::Io`].
    pub fn io(path: impl AsRef<Path>, action: &'static str, source: std::io::Error) -> Self {
        Error::Io {
            path: path.as_ref().to_path_buf(),
            action,
            source,
        }
    }
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Error::Input {
                path,
                place,
                problem,
            } if place.is_empty() => {
                write!(f, "{}: {}", path.display(), one_line(problem))
            }
            Error::Input {
                path,
                place,
                problem,
            } => {
                write!(f, "{}: {}: {}", path.display(), place, one_line(problem))
            }
            Error::Io {
                path,
                action,
                source,
            } => {
                write!(
                    f,
                    "{}: {} failed: {}",
                    path.display(),
                    action,
                    one_line(&source.to_string())
                )
            }
            Error::Usage(msg) => write!(f, "{}", one_line(msg)),
        }
    }
}

impl std::error::Error for Error {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            Error::Io { source, .. } => Some(source),
            _ => None,
        }
    }
}

/// Folds a multi-line message (TOML parser output, say) into one line.
fn one_line(s: &str) -> String {
    s.split_whitespace().collect::<Vec<_>>().join(" ")
}
