//! `obu`: the in-vehicle process. It receives MAP and TIM over UDP, GNSS fixes (NMEA or gpsd)
//! and CAN speed, runs the OBU core, and serves the tablet app with a live event stream.
//!
//! Usage: `obu [--config FILE]`, `obu --print-default-config`, `obu --help`.
#![forbid(unsafe_code)]

mod assets;
mod config;
mod counters;
mod gnss;
mod http;
mod hub;
mod ingest;
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
  obu [--config FILE]          run (without --config: the built-in defaults)
  obu --print-default-config   print the documented default configuration
  obu --help                   this text

The tablet app is served on [http] bind (default http://127.0.0.1:8080).";

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
    match runtime.block_on(run(config)) {
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
        [] => Ok(Some(Config::default_config())),
        [flag] if flag == "--help" || flag == "-h" => {
            println!("{USAGE}");
            Ok(None)
        }
        [flag] if flag == "--print-default-config" => {
            print!("{}", config::DEFAULT_TOML);
            Ok(None)
        }
        [flag, path] if flag == "--config" => {
            let text =
                std::fs::read_to_string(path).map_err(|e| format!("cannot read {path}: {e}"))?;
            Config::parse(&text)
                .map(Some)
                .map_err(|e| format!("{path}: {e}"))
        }
        _ => Err(format!("unexpected arguments {args:?}")),
    }
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

    let udp = tokio::net::UdpSocket::bind(config.v2x.bind)
        .await
        .map_err(|e| format!("v2x bind {}: {e}", config.v2x.bind))?;
    let listener = tokio::net::TcpListener::bind(config.http.bind)
        .await
        .map_err(|e| format!("http bind {}: {e}", config.http.bind))?;
    let http_addr = listener.local_addr().map_err(|e| e.to_string())?;
    let v2x_addr = udp.local_addr().map_err(|e| e.to_string())?;
    let (stop_tx, stop) = tokio::sync::watch::channel(false);

    let app = http::router(http::AppState {
        hub: hub.clone(),
        settings_file,
        clients: Arc::new(AtomicUsize::new(0)),
        max_clients: config.http.max_clients,
        heartbeat: Duration::from_millis(config.http.heartbeat_ms),
    });
    let timeout = Duration::from_millis(config.http.request_timeout_ms);
    let server = tokio::spawn(serve::serve(
        listener,
        app,
        hub.clone(),
        timeout,
        stop.clone(),
    ));
    tokio::spawn(v2x::run(
        udp,
        hub.clone(),
        config.v2x.max_datagram,
        stop.clone(),
    ));
    tokio::spawn(gnss::run(config.gnss.clone(), hub.clone(), stop.clone()));
    speed::spawn(&config.speed, hub.clone());
    tokio::spawn(poll_loop(hub.clone(), stop.clone()));
    // The first line is for scripts and tests: where to reach the daemon.
    println!("obu: http://{http_addr} v2x udp {v2x_addr}");

    wait_for_signal().await;
    eprintln!("obu: shutting down");
    let _ = stop_tx.send(true);
    let _ = tokio::time::timeout(Duration::from_secs(2), server).await;
    Ok(())
}

/// Lets the core notice timeouts (GNSS lost, data expired) between fixes.
async fn poll_loop(hub: Arc<hub::Hub>, mut stop: tokio::sync::watch::Receiver<bool>) {
    let mut tick = tokio::time::interval(Duration::from_millis(100));
    loop {
        tokio::select! {
            _ = tick.tick() => hub.poll(),
            _ = stop.changed() => return,
        }
    }
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
