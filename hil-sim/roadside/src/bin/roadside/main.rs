//! `roadside`: the roadside unit software. It builds a site's MAP and TIMs (lane map, work
//! zones from WZDx, cone lists or a camera) and keeps them on the site's RSUs over SNMP
//! (NTCIP 1218 / RSU 4.1, SNMPv3 USM), and/or broadcasts them over UDP (`run`, `rsu`); it
//! makes the site's IEEE 1609.2 certificates (`pki`) and turns roadside cameras' folders
//! into tracked road users and workers' PSMs (`road-users`).
#![forbid(unsafe_code)]

mod pki;
mod road_users;
mod rsu;

use clap::{Parser, Subcommand};
use std::error::Error;
use std::path::PathBuf;
use std::process::ExitCode;
use std::sync::atomic::AtomicBool;
use std::sync::Arc;

/// Why a command failed: the library's error or the command's own, printed with its message.
type CommandError = Box<dyn Error>;

/// Why a command-line value is refused (clap shows the message next to the value).
type ValueError = Box<dyn Error + Send + Sync>;

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
    /// A small IEEE 1609.2 PKI: a root, an issuing CA and an RSU certificate (NIST P-256)
    /// with the RSU's PSIDs, region and validity, as DIR/{root,ca,rsu}.oer (COER) and
    /// DIR/{root,ca,rsu}.key (mode 0600). The OBU trusts root.oer and ca.oer
    /// ([security] trust_anchors); the site file's signing and `hil-sim roadside --pki DIR`
    /// sign with rsu.key.
    Pki(pki::PkiArgs),
    /// Road users from roadside cameras: each camera folder's masks (detections.json, COCO)
    /// to 3D boxes and positions (vanishing points from its first frame's PNG, the road
    /// plane from calibration.json), every camera fused into one set of tracks (JSON);
    /// with --truth the localization error per class; with --zone the tracked workers in
    /// the work zone as PSMs (--to, --pki).
    RoadUsers(road_users::RoadUsersArgs),
}

fn main() -> ExitCode {
    let result = match Cli::parse().command {
        Command::Run { site, once } => run(&site, once),
        Command::Rsu(c) => rsu::rsu(&c),
        Command::Pki(a) => pki::pki(&a),
        Command::RoadUsers(a) => road_users::road_users(&a),
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

fn run(site: &std::path::Path, once: bool) -> Result<bool, CommandError> {
    let stop = Arc::new(AtomicBool::new(false));
    let reload = Arc::new(AtomicBool::new(false));
    for (signal, flag) in [
        (signal_hook::consts::SIGTERM, &stop),
        (signal_hook::consts::SIGINT, &stop),
        (signal_hook::consts::SIGHUP, &reload),
    ] {
        signal_hook::flag::register(signal, Arc::clone(flag))?;
    }
    Ok(roadside::service::run(
        site,
        &stop,
        &reload,
        once,
        &mut std::io::stderr(),
    )?)
}

#[cfg(test)]
mod tests {
    use super::*;
    use clap::CommandFactory;

    fn parse(line: &str) -> Result<Command, clap::Error> {
        Cli::try_parse_from(line.split_whitespace()).map(|c| c.command)
    }

    #[test]
    fn the_command_line_is_consistent() {
        Cli::command().debug_assert();
    }

    #[test]
    fn pki_and_road_users_parse() {
        for line in [
            "roadside pki site-pki --days 30",
            "roadside pki site-pki --region 38.9,-77.1,20000 --days 30",
            "roadside pki d --seed s --start 2025-01-01 --days 2730 --psid 0x8003 --psid 39",
            "roadside road-users site/cam1 site/cam2 --truth site/truth.json --out t.json",
            "roadside road-users site/cam1 --boxes boxes.png",
            "roadside road-users site/cam1 --zone site/zone.json --to 127.0.0.1:1516",
            "roadside road-users site/cam1 --zone z.json --to 127.0.0.1:1516 --pki site-pki",
        ] {
            assert!(parse(line).is_ok(), "{line}: {:?}", parse(line).err());
        }
        let Ok(Command::Pki(a)) = parse("roadside pki d --start 2025-01-01") else {
            panic!("pki did not parse");
        };
        assert_eq!(a.start, Some(1_735_689_600));
        assert_eq!((a.days, a.ca_years, a.root_years), (30, 5, 10));
        assert_eq!(a.name, "rsu.hil-sim.example");
        let Ok(Command::RoadUsers(r)) = parse("roadside road-users a b") else {
            panic!("road-users did not parse");
        };
        assert_eq!((r.cameras.len(), r.fps), (2, 10.0));
    }

    #[test]
    fn bad_values_are_refused() {
        for line in [
            "roadside pki",
            "roadside pki d --start 2025-13-01",
            "roadside pki d --region 91,0,10",
            "roadside pki d --psid tim",
            "roadside road-users",
            "roadside road-users site/cam1 --to 127.0.0.1:1516",
            "roadside road-users site/cam1 --zone z.json --to example.org:1516",
            "roadside road-users --synthesize d",
        ] {
            assert!(parse(line).is_err(), "{line} parsed");
        }
    }
}
