//! What the pipeline measures while it runs: per-stage latency histograms, queue depths, frame
//! counters and per-thread CPU time, shared lock-free with whoever reports them (the systemd
//! STATUS line, the end-of-run summary, tests).
//!
//! Histograms have fixed buckets allocated once, so recording a frame costs a few atomic adds and
//! never allocates.

use std::sync::atomic::{AtomicU64, Ordering};
use std::time::Duration;

/// Bucket width of the latency histograms.
const BUCKET_US: u64 = 20;
/// Buckets: 20 µs resolution up to 100 ms; slower frames land in the last bucket (and `max`).
const BUCKETS: usize = 5000;

/// A latency histogram with 20 µs buckets up to 100 ms, safe to update and read from any thread.
pub struct Histogram {
    buckets: Box<[AtomicU64]>,
    count: AtomicU64,
    sum_us: AtomicU64,
    max_us: AtomicU64,
}

impl Default for Histogram {
    fn default() -> Self {
        Histogram {
            buckets: (0..BUCKETS).map(|_| AtomicU64::new(0)).collect(),
            count: AtomicU64::new(0),
            sum_us: AtomicU64::new(0),
            max_us: AtomicU64::new(0),
        }
    }
}

impl std::fmt::Debug for Histogram {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}", self.summary())
    }
}

impl Histogram {
    /// Records one duration.
    pub fn record(&self, d: Duration) {
        let us = d.as_micros().min(u64::MAX as u128) as u64;
        let b = ((us / BUCKET_US) as usize).min(BUCKETS - 1);
        self.buckets[b].fetch_add(1, Ordering::Relaxed);
        self.count.fetch_add(1, Ordering::Relaxed);
        self.sum_us.fetch_add(us, Ordering::Relaxed);
        self.max_us.fetch_max(us, Ordering::Relaxed);
    }

    /// Number of durations recorded.
    pub fn count(&self) -> u64 {
        self.count.load(Ordering::Relaxed)
    }

    /// The `q` quantile (0..=1) in milliseconds, as the upper edge of its bucket (so it never
    /// understates) but at most the maximum; 0 when empty.
    pub fn quantile_ms(&self, q: f64) -> f64 {
        let n = self.count();
        if n == 0 {
            return 0.0;
        }
        let rank = ((q.clamp(0.0, 1.0) * n as f64).ceil() as u64).max(1);
        let mut seen = 0;
        for (i, b) in self.buckets.iter().enumerate() {
            seen += b.load(Ordering::Relaxed);
            if seen >= rank {
                if i == BUCKETS - 1 {
                    return self.max_ms();
                }
                return (((i as u64 + 1) * BUCKET_US) as f64 / 1e3).min(self.max_ms());
            }
        }
        self.max_ms()
    }

    /// Mean in milliseconds; 0 when empty.
    pub fn mean_ms(&self) -> f64 {
        let n = self.count();
        if n == 0 {
            0.0
        } else {
            self.sum_us.load(Ordering::Relaxed) as f64 / n as f64 / 1e3
        }
    }

    /// Largest duration recorded, in milliseconds.
    pub fn max_ms(&self) -> f64 {
        self.max_us.load(Ordering::Relaxed) as f64 / 1e3
    }

    /// `mean/p50/p99/max` in milliseconds, e.g. `1.02/0.98/1.40/2.31 ms`.
    pub fn summary(&self) -> String {
        format!(
            "{:.2}/{:.2}/{:.2}/{:.2} ms",
            self.mean_ms(),
            self.quantile_ms(0.5),
            self.quantile_ms(0.99),
            self.max_ms()
        )
    }
}

/// A queue's length, sampled once per frame: the latest, the largest and the mean.
#[derive(Default)]
pub struct Gauge {
    last: AtomicU64,
    max: AtomicU64,
    sum: AtomicU64,
    samples: AtomicU64,
}

impl Gauge {
    /// Records one sample.
    pub fn sample(&self, v: usize) {
        let v = v as u64;
        self.last.store(v, Ordering::Relaxed);
        self.max.fetch_max(v, Ordering::Relaxed);
        self.sum.fetch_add(v, Ordering::Relaxed);
        self.samples.fetch_add(1, Ordering::Relaxed);
    }

    /// The latest sample.
    pub fn last(&self) -> u64 {
        self.last.load(Ordering::Relaxed)
    }

    /// The largest sample.
    pub fn max(&self) -> u64 {
        self.max.load(Ordering::Relaxed)
    }

    /// The mean of the samples.
    pub fn mean(&self) -> f64 {
        self.sum.load(Ordering::Relaxed) as f64 / self.samples.load(Ordering::Relaxed).max(1) as f64
    }
}

impl std::fmt::Debug for Gauge {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "mean {:.2}, max {}", self.mean(), self.max())
    }
}

/// Everything the pipeline measures, shared between its threads and the reporters.
#[derive(Debug, Default)]
pub struct Telemetry {
    /// Frame received (callback, or read from disk) → picked up by the classify stage.
    pub queue_latency: Histogram,
    /// Time classifying one frame (IR view, alignment, RGB view).
    pub classify_latency: Histogram,
    /// Time writing one frame to every sink.
    pub write_latency: Histogram,
    /// Frame received → written by every sink: the end-to-end latency.
    pub total_latency: Histogram,
    /// Frames waiting for the classify stage.
    pub classify_queue: Gauge,
    /// Frames waiting for the write stage.
    pub write_queue: Gauge,
    /// Frames read from the source.
    pub frames_read: AtomicU64,
    /// Frames written by every sink.
    pub frames_written: AtomicU64,
    /// Depth frames the source dropped (the USB callback found no free buffer).
    pub frames_dropped: AtomicU64,
    /// RGB frames the source dropped.
    pub rgb_dropped: AtomicU64,
    /// Frames rejected before classification (wrong size).
    pub frames_malformed: AtomicU64,
    /// Times the source was reopened after losing its device.
    pub reconnects: AtomicU64,
    /// CPU time of the read, classify and write threads, in microseconds (set as each ends).
    pub cpu_us: [AtomicU64; 3],
}

impl Telemetry {
    /// Frames read but not yet written (in a queue or a stage).
    pub fn in_flight(&self) -> u64 {
        self.frames_read.load(Ordering::Relaxed).saturating_sub(
            self.frames_written.load(Ordering::Relaxed)
                + self.frames_malformed.load(Ordering::Relaxed),
        )
    }
}

/// CPU time the calling thread has used so far.
pub fn thread_cpu_time() -> Duration {
    cpu_clock(libc::CLOCK_THREAD_CPUTIME_ID)
}

/// CPU time the whole process has used so far (every thread, user and system).
pub fn process_cpu_time() -> Duration {
    cpu_clock(libc::CLOCK_PROCESS_CPUTIME_ID)
}

fn cpu_clock(clock: libc::clockid_t) -> Duration {
    let mut ts = libc::timespec {
        tv_sec: 0,
        tv_nsec: 0,
    };
    // SAFETY: `ts` is a valid, writable timespec; the clock ids are the POSIX CPU-time clocks.
    let rc = unsafe { libc::clock_gettime(clock, &mut ts) };
    if rc != 0 {
        return Duration::ZERO;
    }
    Duration::new(ts.tv_sec as u64, ts.tv_nsec as u32)
}

/// Resident memory of this process in bytes (from /proc/self/statm; 0 where unavailable).
pub fn resident_bytes() -> u64 {
    let Ok(s) = std::fs::read_to_string("/proc/self/statm") else {
        return 0;
    };
    let pages: u64 = s
        .split_whitespace()
        .nth(1)
        .and_then(|v| v.parse().ok())
        .unwrap_or(0);
    // SAFETY: sysconf has no preconditions.
    let page = unsafe { libc::sysconf(libc::_SC_PAGESIZE) };
    pages * page.max(0) as u64
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quantiles_come_from_the_recorded_values() {
        let h = Histogram::default();
        assert_eq!(h.quantile_ms(0.99), 0.0);
        // 1..=100 ms in 1 ms steps: p50 is 50 ms, p99 99 ms, each reported as its bucket's top edge.
        for ms in 1..=100u64 {
            h.record(Duration::from_micros(ms * 1000 - 10));
        }
        assert_eq!(h.count(), 100);
        assert!(
            (h.quantile_ms(0.5) - 50.0).abs() < 0.021,
            "{}",
            h.quantile_ms(0.5)
        );
        assert!(
            (h.quantile_ms(0.99) - 99.0).abs() < 0.021,
            "{}",
            h.quantile_ms(0.99)
        );
        // Beyond the last bucket the true maximum is reported.
        assert!(
            (h.quantile_ms(1.0) - 99.99).abs() < 1e-9,
            "{}",
            h.quantile_ms(1.0)
        );
        h.record(Duration::from_millis(250));
        assert_eq!(h.quantile_ms(1.0), 250.0);
        assert!((h.mean_ms() - (5050.0 - 1.0 + 250.0) / 101.0).abs() < 0.01);
    }

    #[test]
    fn gauges_keep_last_max_and_mean() {
        let g = Gauge::default();
        for v in [1, 3, 2] {
            g.sample(v);
        }
        assert_eq!((g.last(), g.max()), (2, 3));
        assert!((g.mean() - 2.0).abs() < 1e-12);
    }

    #[test]
    fn cpu_clocks_advance_with_work() {
        let t0 = thread_cpu_time();
        let mut x = 0u64;
        for i in 0..20_000_000u64 {
            x = x.wrapping_mul(31).wrapping_add(i);
        }
        std::hint::black_box(x);
        assert!(thread_cpu_time() > t0);
        assert!(process_cpu_time() >= thread_cpu_time());
        assert!(resident_bytes() > 0);
    }
}
