use std::io::IsTerminal;

use clap::Parser;

fn main() {
    let cli = umbra::cli::Cli::parse();
    if !matches!(cli.command, umbra::cli::Command::Run(_)) {
        restore_sigpipe();
    }
    let default = match cli.verbose {
        0 => "warn",
        1 => "info",
        _ => "debug",
    };
    let filter = tracing_subscriber::EnvFilter::try_from_default_env()
        .unwrap_or_else(|_| tracing_subscriber::EnvFilter::new(default));
    tracing_subscriber::fmt()
        .with_env_filter(filter)
        .with_writer(std::io::stderr)
        // Colour codes only for a person at a terminal, not in journald or a CI log.
        .with_ansi(std::io::stderr().is_terminal())
        .with_target(false)
        .init();
    if let Err(e) = umbra::cli::run(cli) {
        eprintln!("umbra: error: {e}");
        std::process::exit(1);
    }
}

/// Rust ignores SIGPIPE, so printing into a closed pipe (`umbra eval … | head`) panicked; with
/// the default action the command ends quietly there, as other command-line tools do. Not for
/// the daemon: its log stream (journald's socket) going away must not end capture.
fn restore_sigpipe() {
    #[cfg(unix)]
    // SAFETY: called first thing in main, before any thread exists; SIG_DFL is a valid action.
    unsafe {
        libc::signal(libc::SIGPIPE, libc::SIG_DFL);
    }
}
