//! `obu`: the in-vehicle process. It receives MAP and TIM over UDP, GNSS fixes (NMEA or gpsd)
//! and CAN speed, runs the OBU core, and serves the tablet app with a live event stream. In
//! bridge mode ([`bridge`]) it runs no core and no input but serves the states that the
//! firmware sends over a serial link instead.
//!
//! Usage: `obu [--config FILE] [--bridge SOURCE]`, `obu --print-default-config`, `obu --help`.
//!
//! The first line on stdout tells scripts where the daemon is:
//! `obu: http://HTTP_ADDR v2x udp V2X_ADDR`, or in bridge mode
//! `obu: http://HTTP_ADDR bridge SOURCE` (`SOURCE` as `tcp:HOST:PORT` or `serial:PATH`).
#![forbid(unsafe_code)]

mod assets;
mod bridge;
mod config;
mod counters;
mod gnss;
mod http;
mod hub;
mod serve;
mod settings;
mod speed;
mod v2x;

use config::Config;
use settings::{Settings, SettingsFile};
use std::process::ExitCode;
use std::sync::atomic::AtomicUsize;
use std::sync::Arc;
use std::time::Duration;

const USAGE: &str = "obu: the work-zone OBU daemon

Usage:
  obu [--config FILE] [--bridge SOURCE]
                               run (without --config: the built-in defaults)
  obu --print-default-config   print the documented default configuration
  obu --help                   this text

The tablet app is served on [http] bind (default http://127.0.0.1:8080).

--bridge SOURCE (or [bridge] source) runs no OBU core and no V2X, GNSS or CAN input:
the firmware's HmiState frames are read from SOURCE and served to the tablet.
  tcp:HOST:PORT   connect to it (e.g. QEMU -serial tcp:127.0.0.1:5003,server,nowait)
  serial:PATH     read a serial device set raw at 115200 8N1 (see [bridge] baud)
Settings changed on the tablet do not reach the firmware (the link is one-way).";

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let config = match parse_args(&args) {
        Ok(Some(c)) => c,
        Ok(None) => return ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("obu: {e}\n\n{USAGE}");
            return ExitCode::from(2);
        }
    };
    let runtime = match tokio::runtime::Builder::new_current_thread()
        .enable_all()
        .build()
    {
        Ok(rt) => rt,
        Err(e) => {
            eprintln!("obu: cannot start the runtime: {e}");
            return ExitCode::FAILURE;
        }
    };
    let result = runtime.block_on(run(config));
    // A read of a serial device blocks a pool thread until data comes: do not wait for it.
    runtime.shutdown_timeout(Duration::from_millis(200));
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("obu: {e}");
            ExitCode::FAILURE
        }
    }
}

/// The configuration to run with, or `None` when the arguments asked for something else.
fn parse_args(args: &[String]) -> Result<Option<Config>, String> {
    match args {
        [flag] if flag == "--help" || flag == "-h" => {
            println!("{USAGE}");
            return Ok(None);
        }
        [flag] if flag == "--print-default-config" => {
            print!("{}", config::DEFAULT_TOML);
            return Ok(None);
        }
        _ => {}
    }
    let (path, bridge) = run_flags(args)?;
    let config = match path {
        None => Config::default_config(),
        Some(path) => {
            let text =
                std::fs::read_to_string(path).map_err(|e| format!("cannot read {path}: {e}"))?;
            Config::parse(&text).map_err(|e| format!("{path}: {e}"))?
        }
    };
    match bridge {
        None => Ok(Some(config)),
        Some(source) => {
            let source = source.parse().map_err(|e| format!("--bridge: {e}"))?;
            let config = config.with_bridge(source);
            config.map(Some).map_err(|e| format!("--bridge: {e}"))
        }
    }
}

/// The values of `--config FILE` and `--bridge SOURCE`, each at most once, in any order.
fn run_flags(args: &[String]) -> Result<(Option<&str>, Option<&str>), String> {
    let (mut config, mut bridge) = (None, None);
    let mut it = args.iter();
    while let Some(flag) = it.next() {
        let slot = match flag.as_str() {
            "--config" => &mut config,
            "--bridge" => &mut bridge,
            _ => return Err(format!("unexpected argument {flag:?}")),
        };
        let value = it.next().ok_or_else(|| format!("{flag} needs a value"))?;
        if slot.replace(value.as_str()).is_some() {
            return Err(format!("{flag} given twice"));
        }
    }
    Ok((config, bridge))
}

async fn run(config: Config) -> Result<(), String> {
    let settings_file = Arc::new(SettingsFile::new(&config.http.settings_file));
    let defaults = Settings::defaults(config.alerts.warning_distance_m, config.alerts.lead_time_s);
    let (settings, warning) = settings_file.load(defaults);
    if let Some(w) = warning {
        eprintln!("obu: {w}; using defaults");
    }
    let mut base = obu::alert::AlertConfig::DEFAULT;
    base.overspeed_tolerance_mps = config.alerts.overspeed_tolerance_kmh / 3.6;
    base.gnss_timeout = obu::time::Duration::from_millis(config.gnss.stale_after_ms);
    let hub = hub::Hub::new(
        settings,
        base,
        config.http.event_buffer,
        config.speed.stale_after_ms,
    );

    let listener = tokio::net::TcpListener::bind(config.http.bind)
        .await
        .map_err(|e| format!("http bind {}: {e}", config.http.bind))?;
    let http_addr = listener.local_addr().map_err(|e| e.to_string())?;
    let (stop_tx, stop) = tokio::sync::watch::channel(false);
    let bridge = config.bridge.source.clone().map(bridge::Status::new);
    let inputs = match &bridge {
        Some(status) => {
            tokio::spawn(bridge::run(
                status.clone(),
                config.bridge.baud,
                hub.clone(),
                stop.clone(),
            ));
            format!("bridge {}", status.source())
        }
        None => start_inputs(&config, &hub, &stop).await?,
    };

    let app = http::router(http::AppState {
        hub: hub.clone(),
        settings_file,
        clients: Arc::new(AtomicUsize::new(0)),
        max_clients: config.http.max_clients,
        heartbeat: Duration::from_millis(config.http.heartbeat_ms),
        bridge,
    });
    let timeout = Duration::from_millis(config.http.request_timeout_ms);
    let server = tokio::spawn(serve::serve(
        listener,
        app,
        hub.clone(),
        timeout,
        stop.clone(),
    ));
    // The first line is for scripts and tests: where to reach the daemon, then its inputs.
    println!("obu: http://{http_addr} {inputs}");

    wait_for_signal().await;
    eprintln!("obu: shutting down");
    let _ = stop_tx.send(true);
    let _ = tokio::time::timeout(Duration::from_secs(2), server).await;
    Ok(())
}

/// Starts the inputs of the normal mode (V2X, GNSS, CAN) and the core's deadline loop ([`hub::Hub::run_deadlines`]); returns
/// the first line's description of them: `v2x udp ADDR`.
async fn start_inputs(
    config: &Config,
    hub: &Arc<hub::Hub>,
    stop: &tokio::sync::watch::Receiver<bool>,
) -> Result<String, String> {
    let udp = tokio::net::UdpSocket::bind(config.v2x.bind)
        .await
        .map_err(|e| format!("v2x bind {}: {e}", config.v2x.bind))?;
    let v2x_addr = udp.local_addr().map_err(|e| e.to_string())?;
    let max = config.v2x.max_datagram;
    tokio::spawn(v2x::run(udp, hub.clone(), max, stop.clone()));
    tokio::spawn(gnss::run(config.gnss.clone(), hub.clone(), stop.clone()));
    speed::spawn(&config.speed, hub.clone());
    tokio::spawn(hub.clone().run_deadlines(stop.clone()));
    Ok(format!("v2x udp {v2x_addr}"))
}

async fn wait_for_signal() {
    let ctrl_c = tokio::signal::ctrl_c();
    #[cfg(unix)]
    {
        match tokio::signal::unix::signal(tokio::signal::unix::SignalKind::terminate()) {
            Ok(mut term) => {
                tokio::select! {
                    _ = ctrl_c => {}
                    _ = term.recv() => {}
                }
            }
            Err(_) => {
                let _ = ctrl_c.await;
            }
        }
    }
    #[cfg(not(unix))]
    let _ = ctrl_c.await;
}

#[cfg(test)]
mod tests {
    use super::*;

    fn args(list: &[&str]) -> Vec<String> {
        list.iter().map(|s| s.to_string()).collect()
    }

    #[test]
    fn config_and_bridge_flags_combine_in_any_order() {
        let a = args(&["--bridge", "tcp:127.0.0.1:5003", "--config", "obu.toml"]);
        assert_eq!(
            run_flags(&a),
            Ok((Some("obu.toml"), Some("tcp:127.0.0.1:5003")))
        );
        assert_eq!(run_flags(&[]), Ok((None, None)));
        let c = parse_args(&args(&["--bridge", "serial:/dev/ttyACM0"]))
            .unwrap()
            .unwrap();
        let want = config::BridgeSource::Serial("/dev/ttyACM0".into());
        assert_eq!(c.bridge.source, Some(want));
    }

    #[test]
    fn flag_mistakes_are_named() {
        let e = run_flags(&args(&["--bridge"])).unwrap_err();
        assert!(e.contains("--bridge needs a value"), "{e}");
        let e = run_flags(&args(&["--bridge", "tcp:h:1", "--bridge", "tcp:h:2"])).unwrap_err();
        assert!(e.contains("twice"), "{e}");
        let e = run_flags(&args(&["--bridg", "x"])).unwrap_err();
        assert!(e.contains("--bridg"), "{e}");
        let e = parse_args(&args(&["--bridge", "udp:h:1"])).unwrap_err();
        assert!(e.starts_with("--bridge: "), "{e}");
    }
}
