//! Running under systemd (`Type=notify`): readiness, the watchdog and a one-line STATUS, all
//! driven by a reporter thread that reads the pipeline's [`Telemetry`] once a second. Outside
//! systemd (no `NOTIFY_SOCKET`) the notifications are no-ops and only the log lines remain.
//!
//! The watchdog is fed only while the pipeline makes progress: if a frame has been in flight
//! (read but not written) for longer than the watchdog allows, pings stop and systemd restarts
//! the service. A pipeline with nothing in flight is healthy: the source may be waiting for a
//! reconnecting device.

use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

use sd_notify::NotifyState;
use tracing::{info, warn};

use crate::pipeline::telemetry::{self, Telemetry};

/// Tells systemd the service is up (after the device is open and the outputs are ready).
pub fn notify_ready() {
    notify(&[NotifyState::Ready]);
}

/// Tells systemd the service is shutting down.
pub fn notify_stopping() {
    notify(&[NotifyState::Stopping]);
}

fn notify(state: &[NotifyState]) {
    if let Err(e) = sd_notify::notify(state) {
        warn!("systemd notification failed: {e}");
    }
}

/// Reads a counter kept outside the pipeline.
pub type Counter = Box<dyn Fn() -> u64 + Send>;

/// Counters outside the pipeline that the STATUS line reports.
#[derive(Default)]
pub struct Extra {
    /// Frames the outputs failed to write (disk full...), one counter per output.
    pub lost: Vec<Counter>,
    /// Times the device was reopened.
    pub reconnects: Option<Arc<AtomicU64>>,
}

/// One report: what changed since the previous one.
#[derive(Clone, Debug, PartialEq)]
pub struct Report {
    /// Frames written per second over the interval.
    pub fps: f64,
    /// Frames written so far.
    pub written: u64,
    /// Depth frames dropped by the source so far.
    pub dropped: u64,
    /// Frames the outputs could not write so far.
    pub lost: u64,
    /// Device reopen count so far.
    pub reconnects: u64,
    /// End-to-end latency p99 since the start, milliseconds.
    pub p99_ms: f64,
    /// Resident memory, MiB.
    pub rss_mib: f64,
}

impl Report {
    /// The STATUS line, e.g. `30.0 fps, 0 dropped, 0 lost, p99 latency 4.1 ms, 9000 frames, 0 reconnects, 61 MiB`.
    pub fn line(&self) -> String {
        format!(
            "{:.1} fps, {} dropped, {} lost, p99 latency {:.1} ms, {} frames, {} reconnects, {:.0} MiB",
            self.fps, self.dropped, self.lost, self.p99_ms, self.written, self.reconnects, self.rss_mib
        )
    }
}

/// The reporter thread; stops (and is joined) when dropped.
pub struct Reporter {
    done: Arc<AtomicBool>,
    thread: Option<std::thread::JoinHandle<()>>,
}

impl Reporter {
    /// Starts reporting every second to systemd, and every `log_every` to the log.
    pub fn start(tel: Arc<Telemetry>, extra: Extra, log_every: Duration) -> Reporter {
        let done = Arc::new(AtomicBool::new(false));
        let d = done.clone();
        let thread = std::thread::Builder::new()
            .name("status".into())
            .spawn(move || report_loop(&tel, &extra, log_every, &d))
            .ok();
        Reporter { done, thread }
    }
}

impl Drop for Reporter {
    fn drop(&mut self) {
        self.done.store(true, Ordering::SeqCst);
        if let Some(t) = self.thread.take() {
            let _ = t.join();
        }
    }
}

fn report_loop(tel: &Telemetry, extra: &Extra, log_every: Duration, done: &AtomicBool) {
    let watchdog = sd_notify::watchdog_enabled();
    // systemd recommends pinging at half the watchdog interval.
    let tick = watchdog.map_or(Duration::from_secs(1), |w| {
        (w / 2).min(Duration::from_secs(1))
    });
    let stuck_after = watchdog.unwrap_or(Duration::from_secs(30));
    let mut last = (Instant::now(), tel.frames_written.load(Ordering::Relaxed));
    let mut last_log = Instant::now();
    let mut last_progress = Instant::now();
    let mut last_done = (0, 0);
    while !done.load(Ordering::SeqCst) {
        std::thread::sleep(Duration::from_millis(50));
        if last.0.elapsed() < tick {
            continue;
        }
        let now = Instant::now();
        let written = tel.frames_written.load(Ordering::Relaxed);
        let report = Report {
            fps: (written - last.1) as f64 / (now - last.0).as_secs_f64(),
            written,
            dropped: tel.frames_dropped.load(Ordering::Relaxed),
            lost: extra.lost.iter().map(|c| c()).sum(),
            reconnects: extra
                .reconnects
                .as_ref()
                .map_or(0, |c| c.load(Ordering::Relaxed)),
            p99_ms: tel.total_latency.quantile_ms(0.99),
            rss_mib: telemetry::resident_bytes() as f64 / (1 << 20) as f64,
        };
        last = (now, written);
        let line = report.line();
        // Healthy: frames keep being finished, or none is waiting to be.
        let finished = (written, tel.frames_malformed.load(Ordering::Relaxed));
        if finished != last_done || tel.in_flight() == 0 {
            last_progress = now;
            last_done = finished;
        }
        let healthy = last_progress.elapsed() < stuck_after;
        let status = NotifyState::Status(&line);
        if healthy && watchdog.is_some() {
            notify(&[status, NotifyState::Watchdog]);
        } else {
            notify(&[status]);
        }
        if !healthy {
            warn!(
                in_flight = tel.in_flight(),
                "pipeline stalled: no frame finished for {:?}",
                last_progress.elapsed()
            );
        }
        if last_log.elapsed() >= log_every {
            last_log = now;
            info!(target: "umbra::status", "{line}");
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn status_line_reads_at_a_glance() {
        let r = Report {
            fps: 29.97,
            written: 9000,
            dropped: 2,
            lost: 0,
            reconnects: 1,
            p99_ms: 4.06,
            rss_mib: 60.6,
        };
        assert_eq!(
            r.line(),
            "30.0 fps, 2 dropped, 0 lost, p99 latency 4.1 ms, 9000 frames, 1 reconnects, 61 MiB"
        );
    }
}
