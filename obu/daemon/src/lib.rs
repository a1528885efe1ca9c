//! The in-vehicle process `obu` as a library: [`main`] is the whole program (the binary
//! only calls it), and [`config::Config`] is its typed configuration, which a bench or an
//! integrator's tool builds and writes as TOML instead of composing the text.
//!
//! `obu`, the in-vehicle process, receives MAP and TIM over UDP, GNSS fixes (NMEA or gpsd)
//! and CAN speed, runs the OBU core, and serves the tablet app with a live event stream. In
//! bridge mode (module `bridge`) it runs no core and no input but serves the states that the
//! firmware sends over a serial link instead.
//!
//! Usage: `obu [--config FILE] [--bridge SOURCE]`, `obu gnss-check --source KIND --address
//! ADDR` (module `gnss_check`), `obu --print-default-config`, `obu --print-hmi-contract`,
//! `obu --help` (the command line:
//! [`cli`]).
//!
//! The first line on stdout tells scripts where the daemon is:
//! `obu: http://HTTP_ADDR v2x udp V2X_ADDR` (then `gnss udp ADDR` when NMEA comes over
//! UDP: the port bound, so a caller may configure port 0), or in bridge mode
//! `obu: http://HTTP_ADDR bridge SOURCE` (`SOURCE` as `tcp:HOST:PORT` or `serial:PATH`).
//! When standard output is the systemd journal that line is a structured `ready` entry
//! instead (module `log`). Under systemd the daemon also notifies readiness, stopping and a
//! watchdog (module `systemd`).
#![forbid(unsafe_code)]

mod assets;
mod bridge;
pub mod cli;
pub mod config;
mod conn;
mod counters;
mod gnss;
mod gnss_check;
mod host;
mod http;
mod hub;
mod log;
mod markers;
mod pairing;
mod serve;
pub mod settings;
mod speed;
mod systemd;
mod v2x;

use config::Config;
use settings::{Settings, SettingsFile};
use std::process::ExitCode;
use std::sync::Arc;
use std::time::Duration;

/// The program: reads the command line and runs what it asks for (the daemon, a print, a
/// GNSS check); the exit status to return.
pub fn main() -> ExitCode {
    let config = match cli::parse(std::env::args_os().skip(1)) {
        Ok(cli::Action::Run(c)) => *c,
        Ok(cli::Action::Print(text)) => {
            print!("{text}");
            return ExitCode::SUCCESS;
        }
        Ok(cli::Action::GnssCheck(args)) => return ExitCode::from(gnss_check::run(&args)),
        Err(cli::Usage(e)) => {
            eprint!("obu: {e}");
            if !e.ends_with('\n') {
                eprintln!("\nFor more information, try '--help'.");
            }
            return ExitCode::from(2);
        }
    };
    // Read (and removed from the environment) while this is the only thread.
    let notifier = Arc::new(systemd::Notifier::from_env());
    let runtime = match tokio::runtime::Builder::new_current_thread()
        .enable_all()
        .build()
    {
        Ok(rt) => rt,
        Err(e) => {
            log::error("error", &format!("cannot start the runtime: {e}"));
            return ExitCode::FAILURE;
        }
    };
    let result = runtime.block_on(run(config, notifier));
    // A read of a serial device blocks a pool thread until data comes: do not wait for it.
    runtime.shutdown_timeout(Duration::from_millis(200));
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            log::error("error", &e);
            ExitCode::FAILURE
        }
    }
}

async fn run(config: Config, notifier: Arc<systemd::Notifier>) -> Result<(), String> {
    let settings_file = Arc::new(SettingsFile::new(&config.http.settings_file));
    let defaults = Settings::defaults(config.alerts.warning_distance_m, config.alerts.lead_time_s);
    let (settings, warning) = settings_file.load(defaults);
    if let Some(w) = warning {
        log::warn("settings", &format!("{w}; using defaults"));
    }
    let mut base = obu::alert::AlertConfig::DEFAULT;
    config.alerts.apply(&mut base);
    config.lane.apply(&mut base);
    base.max_clock_offset = obu::time::Duration::from_millis(config.time.max_offset_ms);
    base.gnss_timeout = obu::time::Duration::from_millis(config.gnss.stale_after_ms);
    base.speed_timeout = obu::time::Duration::from_millis(config.speed.stale_after_ms);
    let hub = hub::Hub::new(settings, base, config.http.event_buffer);
    hub.check_system_clock(config.time.check_system_clock);

    configure_security(&hub, &config.security, &config.http.settings_file)?;

    let pairing = load_pairing(&config.http)?;
    let listener = serve::bind(config.http.bind)
        .map_err(|e| format!("http bind {}: {e}", config.http.bind))?;
    let http_addr = listener.local_addr().map_err(|e| e.to_string())?;
    let (stop_tx, stop) = tokio::sync::watch::channel(false);
    let watchdog = notifier.watchdog();
    let bridge = config.bridge.source.clone().map(bridge::Status::new);
    let bridge_mode = bridge.is_some();
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
        None => start_inputs(&config, &hub, &stop, watchdog.map(systemd::liveness_tick)).await?,
    };

    let conns = conn::Table::new(config.http.max_connections);
    let app = http::router(http::AppState {
        hub: hub.clone(),
        settings_file,
        pairing,
        slots: http::events::Slots::new(config.http.max_clients),
        conns: conns.clone(),
        heartbeat: Duration::from_millis(config.http.heartbeat_ms),
        bridge,
    });
    let server = serve::Server {
        app,
        hub: hub.clone(),
        conns,
        limits: conn::Limits {
            request: config.http.request_timeout(),
            idle: config.http.idle_timeout(),
            stall: config.http.stalled_stream(),
        },
        hosts: Arc::new(host::AllowedHosts::new(
            config.http.hostname.as_deref(),
            &config.http.allowed_hosts,
        )),
    };
    let server = tokio::spawn(serve::serve(listener, server, stop.clone()));
    announce(&notifier, http_addr, &inputs);
    if let Some(interval) = watchdog {
        let progress = progress(&hub, bridge_mode);
        tokio::spawn(systemd::run_watchdog(
            notifier.clone(),
            interval,
            progress,
            stop.clone(),
        ));
    }

    // The HTTP server runs until it is stopped: one that ends (or panics) by itself leaves
    // the tablet without its app, so the daemon exits non-zero and its supervisor restarts
    // it (Restart=on-failure) instead of pinging the watchdog for a dead server.
    let mut server = server;
    let ended = tokio::select! {
        () = wait_for_signal() => None,
        ended = &mut server => Some(ended),
    };
    notifier.stopping();
    let _ = stop_tx.send(true);
    match ended {
        Some(Ok(())) => Err("the HTTP server stopped".to_owned()),
        Some(Err(e)) => Err(format!("the HTTP server failed: {e}")),
        None => {
            log::notice("shutdown", "shutting down");
            let _ = tokio::time::timeout(Duration::from_secs(2), server).await;
            Ok(())
        }
    }
}

/// Tells where the daemon serves, once the HTTP listener and the inputs are bound: the
/// first line on standard output (for scripts and tests; a structured `ready` entry instead
/// when standard output is the journal), then `READY=1` to the service manager.
fn announce(notifier: &systemd::Notifier, http_addr: std::net::SocketAddr, inputs: &str) {
    let line = format!("http://{http_addr} {inputs}");
    if log::stdout_is_journal() {
        let http = http_addr.to_string();
        log::entry(log::Priority::Info, "ready", &line, &[("OBU_HTTP", &http)]);
    } else {
        println!("obu: {line}");
    }
    notifier.ready(&format!("serving {line}"));
}

/// What the watchdog checks for progress: the turns of the core's deadline loop; in bridge
/// mode (no core, no deadline loop) the watchdog task's own turns, so it proves only that the
/// daemon's single-thread runtime runs.
fn progress(hub: &Arc<hub::Hub>, bridge_mode: bool) -> impl Fn() -> u64 {
    let hub = hub.clone();
    let own = std::sync::atomic::AtomicU64::new(0);
    move || {
        if bridge_mode {
            own.fetch_add(1, std::sync::atomic::Ordering::Relaxed) + 1
        } else {
            hub.turns()
        }
    }
}

/// The pairing PIN and sessions ([`pairing`]); logs the PIN and where it comes from.
fn load_pairing(http: &config::Http) -> Result<Arc<pairing::Pairing>, String> {
    let file = http.pairing_file();
    let pairing = pairing::Pairing::load(http.pin.as_deref(), &file)?;
    let from = if pairing.configured() {
        "[http] pin".to_owned()
    } else {
        format!("made on the first start, kept in {}", file.display())
    };
    log::notice(
        "pairing",
        &format!("pairing PIN {} ({from})", pairing.pin()),
    );
    Ok(Arc::new(pairing))
}

/// Starts the inputs of the normal mode (V2X, GNSS, CAN) and the core's deadline loop ([`hub::Hub::run_deadlines`]); returns
/// the first line's description of them: `v2x udp ADDR`, then `gnss udp ADDR` for NMEA over
/// UDP. Both sockets are bound here: a port that cannot be bound stops the start with its
/// error instead of leaving the daemon without input.
async fn start_inputs(
    config: &Config,
    hub: &Arc<hub::Hub>,
    stop: &tokio::sync::watch::Receiver<bool>,
    tick: Option<Duration>,
) -> Result<String, String> {
    let udp = tokio::net::UdpSocket::bind(config.v2x.bind)
        .await
        .map_err(|e| format!("v2x bind {}: {e}", config.v2x.bind))?;
    let v2x_addr = udp.local_addr().map_err(|e| e.to_string())?;
    let max = config.v2x.max_datagram;
    tokio::spawn(v2x::run(udp, hub.clone(), max, stop.clone()));
    let mut line = format!("v2x udp {v2x_addr}");
    let nmea_udp = match config.gnss.source {
        config::GnssSource::NmeaUdp => {
            let sock = tokio::net::UdpSocket::bind(&config.gnss.address)
                .await
                .map_err(|e| format!("gnss bind {}: {e}", config.gnss.address))?;
            let addr = sock.local_addr().map_err(|e| e.to_string())?;
            line.push_str(&format!(" gnss udp {addr}"));
            Some(sock)
        }
        _ => None,
    };
    tokio::spawn(gnss::run(
        config.gnss.clone(),
        nmea_udp,
        hub.clone(),
        stop.clone(),
    ));
    speed::spawn(&config.speed, hub.clone());
    tokio::spawn(hub.clone().run_deadlines(stop.clone(), tick));
    Ok(line)
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

/// Reads the trust anchors and sets the core's trust policy; warns when nothing can verify.
fn configure_security(
    hub: &hub::Hub,
    security: &config::Security,
    settings_file: &std::path::Path,
) -> Result<(), String> {
    let mut anchors = Vec::new();
    for path in &security.trust_anchors {
        let coer = std::fs::read(path).map_err(|e| format!("{}: {e}", path.display()))?;
        anchors.push((path.display().to_string(), coer));
    }
    let config = security.core_config().map_err(|e| e.to_string())?;
    let path = markers::path_for(settings_file);
    let kept = match markers::load(&path) {
        Ok((kept, 0)) => kept,
        Ok((kept, skipped)) => {
            log::warn(
                "security",
                &format!("{}: {skipped} lines skipped", path.display()),
            );
            kept
        }
        Err(e) => {
            log::warn("security", &format!("{}: {e}", path.display()));
            Vec::new()
        }
    };
    hub.configure_security(config, &anchors, Some((path, kept)))?;
    if anchors.is_empty() {
        let effect = if security.require_signed {
            "every MAP and TIM will be dropped"
        } else {
            "signed frames will be dropped, unsigned ones shown as unverified"
        };
        let text = format!("warning: no security.trust_anchors configured: {effect}");
        log::warn("security", &text);
    } else {
        let text = format!(
            "IEEE 1609.2: {} trust anchor(s), signatures {}",
            anchors.len(),
            if security.require_signed {
                "required"
            } else {
                "optional"
            }
        );
        log::notice("security", &text);
    }
    Ok(())
}
