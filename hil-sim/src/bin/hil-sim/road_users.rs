//! `hil-sim road-users --synthesize DIR`: a rendered site with known truth, written as camera
//! folders for `roadside road-users` to run on.

use hil_sim::roadside_bench::synthetic_site::{synthesize, SynthSpec};

use crate::args::RoadUsersArgs;

/// Runs the command.
pub fn road_users(a: &RoadUsersArgs) -> Result<(), String> {
    if !(a.fps.is_finite() && a.fps > 0.0) {
        return Err(format!("--fps {}: give a positive number", a.fps));
    }
    let out = &a.synthesize;
    let spec = SynthSpec {
        frames: a.frames,
        fps: a.fps,
        noise_px: a.noise_px,
        seed: a.seed,
        cameras: usize::from(a.views),
        small: a.small,
    };
    let dirs = synthesize(&spec, out)?;
    println!(
        "{} frames at {} fps from {} cameras:",
        a.frames,
        a.fps,
        dirs.len()
    );
    for d in &dirs {
        println!("  {}", d.display());
    }
    println!("  {}", out.join("truth.json").display());
    println!("  {}", out.join("zone.json").display());
    Ok(())
}
