//! Segment files in the output folder: their names (`umbra-<UTC start>-<n>.mcap`), their order,
//! and the total size cap that deletes the oldest.
//!
//! The UTC timestamp is computed from `SystemTime` by hand (days-to-civil-date, ten lines) rather
//! than with chrono or time: it is the only date arithmetic umbra needs.

use std::path::{Path, PathBuf};
use std::time::{SystemTime, UNIX_EPOCH};

use crate::error::{Error, Result};

/// `umbra-<YYYYMMDDTHHMMSSZ>-<n>.mcap` for a segment started at `start`.
pub fn segment_name(start: SystemTime, n: u64) -> String {
    format!("umbra-{}-{n}.mcap", utc_stamp(start))
}

/// `YYYYMMDDTHHMMSSZ` (ISO 8601 basic format, UTC) of `t`; times before 1970 print as 1970.
pub fn utc_stamp(t: SystemTime) -> String {
    let secs = t.duration_since(UNIX_EPOCH).map_or(0, |d| d.as_secs());
    let (days, rem) = (secs / 86_400, secs % 86_400);
    let (y, m, d) = civil_from_days(days as i64);
    format!(
        "{y:04}{m:02}{d:02}T{:02}{:02}{:02}Z",
        rem / 3600,
        rem / 60 % 60,
        rem % 60
    )
}

/// Proleptic Gregorian date of a day count since 1970-01-01 (H. Hinnant's `civil_from_days`).
fn civil_from_days(z: i64) -> (i64, u32, u32) {
    let z = z + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z.rem_euclid(146_097);
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let d = (doy - (153 * mp + 2) / 5 + 1) as u32;
    let m = if mp < 10 { mp + 3 } else { mp - 9 } as u32;
    (yoe + era * 400 + i64::from(m <= 2), m, d)
}

/// Sort key of a segment file name: (UTC stamp, n); `None` for names that are not segments.
pub fn segment_key(name: &str) -> Option<(String, u64)> {
    let rest = name.strip_prefix("umbra-")?.strip_suffix(".mcap")?;
    let (stamp, n) = rest.rsplit_once('-')?;
    let ok = stamp.len() == 16 && stamp.as_bytes()[8] == b'T' && stamp.ends_with('Z');
    ok.then_some(())?;
    Some((stamp.to_string(), n.parse().ok()?))
}

/// The segments in `dir`, oldest first, with their sizes in bytes.
pub fn list_segments(dir: &Path) -> Result<Vec<(PathBuf, u64)>> {
    let entries = std::fs::read_dir(dir).map_err(|e| Error::io(dir, "listing segments", e))?;
    let mut found = Vec::new();
    for e in entries.flatten() {
        let name = e.file_name();
        let Some(key) = name.to_str().and_then(segment_key) else {
            continue;
        };
        // A segment deleted between read_dir and stat (the cap, another process) just drops out.
        if let Ok(meta) = e.metadata() {
            if meta.is_file() {
                found.push((key, e.path(), meta.len()));
            }
        }
    }
    found.sort();
    Ok(found.into_iter().map(|(_, p, len)| (p, len)).collect())
}

/// Deletes the oldest segments of `dir`, never `keep`, until their total size is at most `cap`.
/// Returns the paths deleted.
pub fn enforce_cap(dir: &Path, cap: u64, keep: Option<&Path>) -> Result<Vec<PathBuf>> {
    let segments = list_segments(dir)?;
    let mut total: u64 = segments.iter().map(|(_, len)| len).sum();
    let mut deleted = Vec::new();
    for (path, len) in segments {
        if total <= cap {
            break;
        }
        if Some(path.as_path()) == keep {
            continue;
        }
        match std::fs::remove_file(&path) {
            Ok(()) => {}
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => {}
            Err(e) => return Err(Error::io(&path, "deleting the oldest segment", e)),
        }
        total -= len;
        deleted.push(path);
    }
    Ok(deleted)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::time::Duration;

    #[test]
    fn names_are_utc_and_sortable() {
        let t = UNIX_EPOCH + Duration::from_secs(1_795_349_700); // 2026-11-22 12:15:00 UTC
        assert_eq!(segment_name(t, 3), "umbra-20261122T121500Z-3.mcap");
        assert_eq!(utc_stamp(UNIX_EPOCH), "19700101T000000Z");
        assert_eq!(
            utc_stamp(UNIX_EPOCH + Duration::from_secs(951_782_400)),
            "20000229T000000Z"
        );
        assert_eq!(
            segment_key("umbra-20261122T121500Z-12.mcap"),
            Some(("20261122T121500Z".into(), 12))
        );
        assert_eq!(segment_key("umbra-2026-1.mcap"), None);
        assert_eq!(segment_key("other.mcap"), None);
    }

    #[test]
    fn cap_deletes_oldest_first_but_not_the_open_one() {
        let dir = tempfile::tempdir().unwrap();
        let names = [
            "umbra-20260101T000000Z-2.mcap",
            "umbra-20260101T000000Z-10.mcap",
            "umbra-20250101T000000Z-0.mcap",
        ];
        for n in names {
            std::fs::write(dir.path().join(n), [0u8; 100]).unwrap();
        }
        std::fs::write(dir.path().join("notes.txt"), [0u8; 1000]).unwrap();
        let order: Vec<_> = list_segments(dir.path())
            .unwrap()
            .into_iter()
            .map(|(p, _)| p.file_name().unwrap().to_owned())
            .collect();
        assert_eq!(order, [names[2], names[0], names[1]]);
        let keep = dir.path().join(names[2]);
        let gone = enforce_cap(dir.path(), 150, Some(&keep)).unwrap();
        assert_eq!(gone, [dir.path().join(names[0]), dir.path().join(names[1])]);
        assert!(keep.exists());
    }
}
