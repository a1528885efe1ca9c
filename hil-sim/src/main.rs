//! `hil-sim`: roadside unit software and the hardware-in-the-loop bench of the OBU.
#![forbid(unsafe_code)]

use hil_sim::hmi_bench;
use std::path::PathBuf;
use std::process::ExitCode;

const USAGE: &str = "hil-sim: roadside unit software and the OBU's hardware-in-the-loop bench

Usage:
  hil-sim hmi-server     run the real obu daemon and feed it the tablet tests' road, work
                         zone and drive at 10 Hz; prints the daemon's URL first
                         (env: HMI_PORT, HMI_STATE_DIR, OBU_BIN)
  hil-sim hmi-drive S    switch a running hmi-server to scene S (env: HMI_STATE_DIR)
  hil-sim --help         this text

Scenes: cruise, approach, warning, lane_closed, overspeed, in_zone, leaving;
switches: gnss_lost, gnss_back.";

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let result = match args
        .iter()
        .map(String::as_str)
        .collect::<Vec<_>>()
        .as_slice()
    {
        ["hmi-server"] => server_options().and_then(|o| hmi_bench::serve(&o)),
        ["hmi-drive", scene] => state_dir().and_then(|d| hmi_bench::drive(&d, scene)),
        ["--help" | "-h"] => {
            println!("{USAGE}");
            return ExitCode::SUCCESS;
        }
        _ => Err(format!("unexpected arguments {args:?}\n\n{USAGE}")),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("hil-sim: {e}");
            ExitCode::FAILURE
        }
    }
}

fn state_dir() -> Result<PathBuf, String> {
    std::env::var_os("HMI_STATE_DIR")
        .map(PathBuf::from)
        .ok_or_else(|| "set HMI_STATE_DIR (the bench's state directory)".to_string())
}

fn server_options() -> Result<hmi_bench::ServerOptions, String> {
    let port = match std::env::var("HMI_PORT") {
        Ok(p) => p
            .parse()
            .map_err(|_| format!("HMI_PORT {p:?} is not a port"))?,
        Err(_) => 0,
    };
    Ok(hmi_bench::ServerOptions {
        obu: hmi_bench::find_obu(),
        port,
        state_dir: state_dir()?,
    })
}
