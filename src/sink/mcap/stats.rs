//! The `/umbra/frame_stats` message: one JSON object per frame, the same object `umbra tail
//! --json` prints, and the JSON schema that tells Foxglove its fields.

use serde::de::{Deserializer, Error as _};
use serde::ser::{SerializeMap, Serializer};
use serde::{Deserialize, Serialize};

use crate::labels::{histogram, CLASSES, NAMES};
use crate::pipeline::Frame;

/// Schema name of the stats topic.
pub const STATS_TYPE: &str = "umbra/FrameStats";

/// Per-frame metadata and pixel counts per class.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct FrameStats {
    /// Frame sequence number.
    pub seq: u64,
    /// Device timestamp of the depth frame (32-bit, wraps).
    pub device_ts: u32,
    /// Host time the depth frame was received, seconds since the epoch.
    pub unix_time: f64,
    /// Milliseconds from receiving the frame to handing it to the writer.
    pub latency_ms: f64,
    /// Frames dropped between the previous written frame and this one.
    pub dropped_before: u64,
    /// Pixels per class in the IR (depth) view.
    pub ir: ClassCounts,
    /// Pixels per class in the RGB view.
    pub rgb: ClassCounts,
}

impl FrameStats {
    /// Stats of `frame`, counting its labels.
    pub fn of(frame: &Frame, latency_ms: f64, dropped_before: u64) -> Self {
        FrameStats {
            seq: frame.seq,
            device_ts: frame.device_ts,
            unix_time: frame.unix_time,
            latency_ms,
            dropped_before,
            ir: ClassCounts(histogram(&frame.labels.ir_labels)),
            rgb: ClassCounts(histogram(&frame.labels.rgb_labels)),
        }
    }
}

/// Pixel count per label code; serialised as an object keyed by class name
/// (`{"valid": n, "attached": n, ...}`, see [`NAMES`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ClassCounts(pub [u64; CLASSES]);

impl Serialize for ClassCounts {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        let mut m = s.serialize_map(Some(CLASSES))?;
        for (name, n) in NAMES.iter().zip(self.0) {
            m.serialize_entry(name, &n)?;
        }
        m.end()
    }
}

impl<'de> Deserialize<'de> for ClassCounts {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let map = std::collections::BTreeMap::<String, u64>::deserialize(d)?;
        let mut out = [0; CLASSES];
        for (name, n) in map {
            let Some(c) = NAMES.iter().position(|&k| k == name) else {
                return Err(D::Error::custom(format!(
                    "unknown class {name:?}, expected one of {NAMES:?}"
                )));
            };
            out[c] = n;
        }
        Ok(ClassCounts(out))
    }
}

/// The JSON schema (draft 2020-12) of [`FrameStats`], stored as the topic's schema.
pub fn json_schema() -> String {
    let counts = serde_json::json!({
        "type": "object",
        "description": "pixels per class (SPEC §2 label codes by name)",
        "properties": NAMES.iter().map(|n| (n.to_string(), serde_json::json!({"type": "integer", "minimum": 0}))).collect::<serde_json::Map<_, _>>(),
        "required": NAMES,
    });
    serde_json::json!({
        "$schema": "https://json-schema.org/draft/2020-12/schema",
        "title": STATS_TYPE,
        "type": "object",
        "properties": {
            "seq": {"type": "integer", "minimum": 0, "description": "frame sequence number"},
            "device_ts": {"type": "integer", "minimum": 0, "description": "Kinect device timestamp (32-bit, wraps)"},
            "unix_time": {"type": "number", "description": "host receive time, seconds since the epoch"},
            "latency_ms": {"type": "number", "description": "receive to write, milliseconds"},
            "dropped_before": {"type": "integer", "minimum": 0, "description": "frames dropped since the previous one"},
            "ir": counts,
            "rgb": counts,
        },
        "required": ["seq", "device_ts", "unix_time", "latency_ms", "dropped_before", "ir", "rgb"],
    })
    .to_string()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn json_round_trip_uses_class_names() {
        let s = FrameStats {
            seq: 3,
            device_ts: 7,
            unix_time: 1.25,
            latency_ms: 2.5,
            dropped_before: 1,
            ir: ClassCounts([1, 2, 3, 0, 5]),
            rgb: ClassCounts([6, 0, 0, 9, 1]),
        };
        let text = serde_json::to_string(&s).unwrap();
        assert!(
            text.contains(r#""ir":{"valid":1,"attached":2,"detached":3,"alignment":0,"other":5}"#),
            "{text}"
        );
        assert_eq!(serde_json::from_str::<FrameStats>(&text).unwrap(), s);
        assert!(serde_json::from_str::<FrameStats>(&text.replace("valid", "nope")).is_err());
        let schema: serde_json::Value = serde_json::from_str(&json_schema()).unwrap();
        assert_eq!(schema["properties"]["rgb"]["required"][4], "other");
    }
}
