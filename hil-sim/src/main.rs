//! `hil-sim`: roadside unit software and the hardware-in-the-loop bench of the OBU.
#![forbid(unsafe_code)]

use hil_sim::{hmi_bench, perf};
use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Duration;

const USAGE: &str = "hil-sim: roadside unit software and the OBU's hardware-in-the-loop bench

Usage:
  hil-sim hmi-server     run the real obu daemon and feed it the tablet tests' road, work
                         zone and drive at 10 Hz; prints the daemon's URL first
                         (env: HMI_PORT, HMI_STATE_DIR, OBU_BIN)
  hil-sim hmi-drive S    switch a running hmi-server to scene S (env: HMI_STATE_DIR)
  hil-sim bench-latency [--samples N]
                         GNSS datagram in -> state event out of the real daemon on the
                         loopback: p50/p99/max; fails when p99 >= 2 ms or a state is lost
  hil-sim load-test [--clients N] [--seconds S]
                         N tablets (default 50) follow /events while the daemon is fed at
                         10 Hz for S seconds (default 60): events per client and the
                         daemon's CPU; fails on a dropped client or CPU >= 10 % of a core
  hil-sim --help         this text

The daemon is `obu` beside this executable (build both with the same profile), or $OBU_BIN.

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
        ["bench-latency", rest @ ..] => bench_latency(rest),
        ["load-test", rest @ ..] => load_test(rest),
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

/// `--name value` pairs into a lookup, refusing unknown names.
fn options<'a>(args: &[&'a str], known: &[&str]) -> Result<Vec<(&'a str, &'a str)>, String> {
    let mut out = Vec::new();
    let mut it = args.iter();
    while let Some(name) = it.next() {
        if !known.contains(name) {
            return Err(format!(
                "unknown option {name:?} (options: {})",
                known.join(", ")
            ));
        }
        let value = it.next().ok_or(format!("{name} needs a value"))?;
        out.push((*name, *value));
    }
    Ok(out)
}

fn number<T: std::str::FromStr>(
    opts: &[(&str, &str)],
    name: &str,
    default: T,
) -> Result<T, String> {
    match opts.iter().rev().find(|(n, _)| *n == name) {
        Some((_, v)) => v
            .parse()
            .map_err(|_| format!("{name} {v:?} is not a number")),
        None => Ok(default),
    }
}

fn bench_latency(args: &[&str]) -> Result<(), String> {
    let opts = options(args, &["--samples"])?;
    let samples: usize = number(&opts, "--samples", 2000)?;
    let obu = hil_sim::daemon::find_obu();
    let r = perf::latency(&obu, samples.max(1), Duration::from_millis(10))?;
    let ms = |q: f64| r.quantile(q) / 1000.0;
    println!(
        "GNSS datagram in -> state event out ({} samples, {} lost): p50 {:.3} ms, p99 {:.3} ms, max {:.3} ms",
        r.sorted_us.len(),
        r.lost,
        ms(0.5),
        ms(0.99),
        ms(1.0)
    );
    if r.lost > 0 || ms(0.99) >= 2.0 {
        return Err("goal missed: p99 under 2 ms with nothing lost".into());
    }
    Ok(())
}

fn load_test(args: &[&str]) -> Result<(), String> {
    let opts = options(args, &["--clients", "--seconds"])?;
    let clients: usize = number(&opts, "--clients", 50)?;
    let seconds: f64 = number(&opts, "--seconds", 60.0)?;
    let obu = hil_sim::daemon::find_obu();
    let r = perf::load(&obu, clients.max(1), seconds.max(1.0))?;
    println!(
        "{} clients for {:.1} s: events per client {}..{}, longest gap {:.0} ms, dropped {} (daemon: {}), daemon CPU {:.2} % of one core",
        r.clients,
        r.seconds,
        r.events.0,
        r.events.1,
        r.max_gap_ms,
        r.dropped.len(),
        r.daemon_dropped,
        r.cpu_percent
    );
    for d in &r.dropped {
        println!("  dropped: {d}");
    }
    if !r.dropped.is_empty() || r.daemon_dropped > 0 || r.cpu_percent >= 10.0 {
        return Err("goal missed: no dropped client and daemon CPU under 10 % of a core".into());
    }
    Ok(())
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
        obu: hil_sim::daemon::find_obu(),
        port,
        state_dir: state_dir()?,
    })
}
