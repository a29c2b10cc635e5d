//! `umbra devices`: the Kinects libfreenect sees, with the `--source` that selects each, so a
//! user can pick one (and name a `umbra@SERIAL` service after it).

use crate::capture::freenect::device::Context;
use crate::capture::freenect::library;
use crate::error::Result;

/// Arguments of `umbra devices` (none).
#[derive(clap::Args, Debug)]
pub struct Args {}

/// Runs `umbra devices`.
pub fn run(_: Args) -> Result<()> {
    let lib = library::load()?;
    if lib.fakenect && std::env::var_os("FAKENECT_PATH").is_none() {
        // fakenect exit()s without a recording to play; say why instead.
        return Err(crate::error::Error::Usage(format!("{} is libfreenect's fakenect replay library and FAKENECT_PATH is not set: set it to a recording folder", lib.name)));
    }
    let ctx = Context::init(lib)?;
    let n = ctx.num_devices()?;
    let serials = ctx.serials();
    let from = if lib.fakenect {
        format!("{} (fakenect replay)", lib.name)
    } else {
        lib.name.clone()
    };
    println!("{n} Kinect(s) found through {from}");
    for i in 0..n as usize {
        match serials.get(i) {
            Some(s) => {
                println!("  --source kinect:{i}   --source kinect:{s}   (camera serial {s})")
            }
            None => println!("  --source kinect:{i}   (serial not available)"),
        }
    }
    Ok(())
}
