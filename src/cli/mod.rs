//! Command-line interface: one module per subcommand, each a thin layer over the library.

pub mod bench;
pub mod devices;
pub mod eval;
pub mod record;
pub mod render;
pub mod replay;
pub mod run;
pub mod segment;
pub mod synth;
pub mod tail;

use clap::{Parser, Subcommand};

/// umbra: Kinect v1 shadow classification (Deng et al., ICCVW 2013).
#[derive(Parser, Debug)]
#[command(name = "umbra", version, about, long_about = None)]
pub struct Cli {
    /// More log output (-v info, -vv debug); RUST_LOG overrides.
    #[arg(short, long, action = clap::ArgAction::Count, global = true)]
    pub verbose: u8,
    /// The subcommand.
    #[command(subcommand)]
    pub command: Command,
}

/// Subcommands.
#[derive(Subcommand, Debug)]
pub enum Command {
    /// Classify every frame of a recording as fast as possible; optionally export label PNGs.
    Replay(replay::Args),
    /// Draw one frame as a picture: RGB | IR-view labels | RGB-view labels.
    Render(render::Args),
    /// Simulate Kinect v1 recordings with exact ground-truth labels.
    Synth(synth::Args),
    /// Score the classifier on recordings against ground-truth labels.
    Eval(eval::Args),
    /// Capture from a Kinect (or a recording at recorded speed), classify and write until stopped.
    Run(run::Args),
    /// Print (and export) the frames of MCAP segments; --follow reads them as they are written.
    Tail(tail::Args),
    /// Record a Kinect as a fakenect-format recording with its calibration (your own CI data).
    Record(record::Args),
    /// List the Kinects libfreenect sees and the --source naming each.
    Devices(devices::Args),
    /// Measure the classifier's speed on a recording, and the CPU floors `umbra run` is compared
    /// with (libfreenect receive, zstd alone).
    Bench(bench::Args),
    /// Automatic foreground masks from classified shadows (SPEC §6), with overlay pictures.
    Segment(segment::Args),
}

/// The progress bar every long-running subcommand shows on stderr (hidden when stderr is not a
/// terminal, so logs and CI output stay clean).
pub fn progress_bar(len: u64, unit: &str) -> indicatif::ProgressBar {
    let style = indicatif::ProgressStyle::with_template(&format!(
        "{{prefix}} [{{bar:30}}] {{pos}}/{{len}} {unit} {{rate}} eta {{eta}}"
    ))
    .expect("static template")
    // indicatif's own `per_sec` prints four decimals ("159.8339/s").
    .with_key(
        "rate",
        |s: &indicatif::ProgressState, w: &mut dyn std::fmt::Write| {
            let _ = std::fmt::Write::write_fmt(w, format_args!("{:.1}/s", s.per_sec()));
        },
    )
    .progress_chars("=> ");
    indicatif::ProgressBar::new(len).with_style(style)
}

/// `n` and `noun`, with an `s` unless `n` is 1 ("1 frame", "3 frames").
pub fn count(n: impl Into<u64>, noun: &str) -> String {
    let n = n.into();
    format!("{n} {noun}{}", if n == 1 { "" } else { "s" })
}

/// Longest `--seconds` accepted (a year): `Duration` cannot hold every finite float.
const MAX_SECONDS: f64 = 365.0 * 24.0 * 3600.0;

/// Parses a `--seconds` value: a finite number of seconds from 0 up to a year.
pub fn seconds_arg(s: &str) -> std::result::Result<f64, String> {
    let v: f64 = s
        .trim()
        .parse()
        .map_err(|_| format!("'{s}' is not a number of seconds"))?;
    if (0.0..=MAX_SECONDS).contains(&v) {
        Ok(v)
    } else {
        Err(format!(
            "{s} s: expected a number of seconds from 0 to {MAX_SECONDS} (a year)"
        ))
    }
}

/// Runs the parsed command.
pub fn run(cli: Cli) -> crate::Result<()> {
    match cli.command {
        Command::Replay(a) => replay::run(a),
        Command::Render(a) => render::run(a),
        Command::Synth(a) => synth::run(a),
        Command::Eval(a) => eval::run(a),
        Command::Tail(a) => tail::run(a),
        Command::Run(a) => run::run(a),
        Command::Bench(a) => bench::run(a),
        Command::Devices(a) => devices::run(a),
        Command::Record(a) => record::run(a),
        Command::Segment(a) => segment::run(a),
    }
}
