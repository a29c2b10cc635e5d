//! `umbra render` (stub).
/// Arguments.
#[derive(clap::Args, Debug)]
pub struct Args {}
/// Runs it.
pub fn run(_a: Args) -> crate::Result<()> { Err(crate::Error::Usage("not yet implemented".into())) }
