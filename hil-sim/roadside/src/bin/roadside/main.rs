//! `roadside`: the roadside unit software. It builds a site's MAP and TIMs (lane map, work
//! zones from WZDx, cone lists or a camera) and keeps them on the site's RSUs over SNMP
//! (NTCIP 1218 / RSU 4.1, SNMPv3 USM), and/or broadcasts them over UDP.
#![forbid(unsafe_code)]

mod rsu;

use clap::{Parser, Subcommand};
use std::path::PathBuf;
use std::process::ExitCode;
use std::sync::atomic::AtomicBool;
use std::sync::Arc;

/// Roadside unit software: a site's MAP and TIMs on its RSUs (SNMP) and/or over UDP.
#[derive(Debug, Parser)]
#[command(name = "roadside", version)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Debug, Subcommand)]
enum Command {
    /// Deposit the site's messages on its RSUs and keep them there (a restarted RSU is
    /// restored at the next poll; changed or removed messages replaced or destroyed), and/or
    /// broadcast them ([broadcast]); until SIGTERM/SIGINT. SIGHUP reads the site file again.
    Run {
        /// The site file.
        #[arg(long, value_name = "SITE.toml")]
        site: PathBuf,
        /// One pass over every RSU, then exit (status 0 when every RSU is in step).
        #[arg(long)]
        once: bool,
    },
    /// RSU management: probe, status, deposit, clear.
    #[command(subcommand)]
    Rsu(rsu::RsuCommand),
}

fn main() -> ExitCode {
    let result = match Cli::parse().command {
        Command::Run { site, once } => run(&site, once),
        Command::Rsu(c) => rsu::rsu(&c),
    };
    match result {
        Ok(true) => ExitCode::SUCCESS,
        Ok(false) => ExitCode::from(1),
        Err(e) => {
            eprintln!("roadside: {e}");
            ExitCode::from(2)
        }
    }
}

fn run(site: &std::path::Path, once: bool) -> Result<bool, String> {
    let stop = Arc::new(AtomicBool::new(false));
    let reload = Arc::new(AtomicBool::new(false));
    for (signal, flag) in [
        (signal_hook::consts::SIGTERM, &stop),
        (signal_hook::consts::SIGINT, &stop),
        (signal_hook::consts::SIGHUP, &reload),
    ] {
        signal_hook::flag::register(signal, Arc::clone(flag)).map_err(|e| e.to_string())?;
    }
    roadside::service::run(site, &stop, &reload, once, &mut std::io::stderr())
}
