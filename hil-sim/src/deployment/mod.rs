//! A scenario's roadside as deployed (`[rsu_deployment]`): a WZDx feed served over HTTP
//! whose versions change during the drive, the product's roadside service (crate
//! `roadside`, the same code `roadside run` runs) polling it and depositing MAP and TIMs
//! over SNMPv3 into a test RSU (net-snmp's snmpd with the bench's NTCIP 1218 / RSU 4.1
//! agent), and the test RSU broadcasting its rows to the device at their interval. The
//! RSU can be down at the start, restart mid-drive, or be given the wrong credentials.

pub mod feed;

use crate::roadside_bench::scripted::{RoadsideRun, V2xCounts};
use crate::test_rsu::agent::Mib;
use crate::test_rsu::{AirLog, TestRsu, TestRsuConfig, TestUser};
use feed::{FeedServer, FeedVersion};
use roadside::clock::unix_ms_now;
use roadside::road::Road;
use roadside::rsu_snmp::deposit::DepositSigning;
use roadside::rsu_snmp::mib::RsuMib;
use roadside::service::{read_status, Roadside, ServiceStatus};
use roadside::site_file::{RsuEntry, RsusSection, Signing, SiteFile, SiteInfo};
use roadside::wzdx_feed::FeedConfig;
use serde::Deserialize;
use std::io::Write;
use std::path::Path;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

/// `[rsu_deployment]` of a scenario.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DeploymentSpec {
    /// The MIB the test RSU speaks (and the site names): `ntcip1218` or `rsu4.1`.
    #[serde(default = "ntcip1218")]
    pub mib: String,
    /// The roadside's credentials file holds a wrong authentication password.
    #[serde(default)]
    pub wrong_password: bool,
    /// The roadside polls the feed this often, seconds.
    #[serde(default = "one")]
    pub feed_poll_s: f64,
    /// The roadside reads each RSU's table this often, seconds.
    #[serde(default = "five")]
    pub rsu_poll_s: f64,
    /// The RSU is unreachable (snmpd not started) until this many seconds into the drive.
    #[serde(default)]
    pub up_at_s: f64,
    /// The RSU restarts (empty tables) at this many seconds into the drive.
    pub restart_at_s: Option<f64>,
    /// A cancel TIM is sent this long for an event that left the feed, seconds.
    #[serde(default = "twenty")]
    pub cancel_for_s: f64,
    /// The feed's versions.
    pub feed: Vec<FeedVersion>,
}

fn ntcip1218() -> String {
    "ntcip1218".into()
}
fn one() -> f64 {
    1.0
}
fn five() -> f64 {
    5.0
}
fn twenty() -> f64 {
    20.0
}

/// What the deployed roadside did, for the expectations.
#[derive(Debug, Clone, Default)]
pub struct DeploymentFacts {
    /// Datagrams the test RSU sent.
    pub rsu_sent: u64,
    /// Seconds since the drive start of each new payload's first transmission.
    pub first_sent_s: Vec<f64>,
    /// When the RSU came up or restarted, seconds since the drive start.
    pub rsu_up_s: Vec<f64>,
    /// When each feed version after the first took effect on the server, seconds.
    pub feed_changes_s: Vec<f64>,
    /// The first version with the event gone, seconds.
    pub removed_at_s: Option<f64>,
    /// The roadside's status at the end.
    pub status: Option<ServiceStatus>,
}

/// A running deployment.
pub type DeploymentThread = JoinHandle<Result<(RoadsideRun, DeploymentFacts), String>>;

const USER: &str = "roadside";
const AUTH_PASS: &str = "bench-auth-secret";
const PRIV_PASS: &str = "bench-priv-secret";

/// A free loopback UDP port (taken and released: the test RSU binds it next).
fn free_udp_port() -> Result<u16, String> {
    let s = std::net::UdpSocket::bind("127.0.0.1:0").map_err(|e| e.to_string())?;
    Ok(s.local_addr().map_err(|e| e.to_string())?.port())
}

/// The site file the bench's roadside runs, written as the type (no TOML text).
fn site(
    spec: &DeploymentSpec,
    (name, road): (&str, &roadside::site::RoadSpec),
    dir: &Path,
    feed_url: String,
    rsu: String,
    mib: RsuMib,
) -> SiteFile {
    SiteFile {
        site: SiteInfo {
            name: format!("bench: {name}"),
            state_dir: dir.join("roadside-state"),
        },
        road: road.clone(),
        zones: Vec::new(),
        wzdx_feed: Some(FeedConfig {
            url: feed_url,
            poll_s: spec.feed_poll_s,
            timeout_s: 2.0,
            max_bytes: 1 << 20,
            cancel_for_s: spec.cancel_for_s,
        }),
        signing: Some(Signing {
            pki: Some(dir.join("pki")),
            deposit: DepositSigning::Roadside,
        }),
        broadcast: None,
        rsus: Some(RsusSection {
            credentials: dir.join("credentials.toml"),
            poll_s: spec.rsu_poll_s,
            timeout_ms: 300,
            retries: 0,
            workers: 1,
            channel: 183,
            interval_ms: 100,
            priority: 6,
            window_hours: 24,
        }),
        rsu: vec![RsuEntry {
            name: "test-rsu".into(),
            address: rsu,
            mib,
            credentials: "bench".into(),
            max_rows: None,
            manage_all_rows: false,
            channel: None,
            interval_ms: None,
        }],
        dir: dir.to_path_buf(),
    }
}

/// Writes the roadside's credentials file (0600).
fn write_credentials(path: &Path, wrong: bool) -> Result<(), String> {
    let auth = if wrong {
        "not-the-auth-secret"
    } else {
        AUTH_PASS
    };
    let text = format!(
        "[bench]\nversion = \"3\"\nuser = \"{USER}\"\nauth = \"sha\"\nauth_password = \"{auth}\"\n\
         privacy = \"aes128\"\npriv_password = \"{PRIV_PASS}\"\n"
    );
    std::fs::write(path, text).map_err(|e| format!("{}: {e}", path.display()))?;
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        std::fs::set_permissions(path, std::fs::Permissions::from_mode(0o600))
            .map_err(|e| format!("{}: {e}", path.display()))?;
    }
    Ok(())
}

/// Starts the deployment for the drive that starts at `t0`: feed server, test RSU (unless
/// it comes up later), the roadside service; it runs until `stop`.
///
/// # Errors
///
/// The work folder, the feed documents, snmpd, or the roadside's start.
pub fn start(
    scenario: (&str, &roadside::site::RoadSpec),
    spec: &DeploymentSpec,
    road: &Road,
    to: &str,
    t0: Instant,
    stop: Arc<AtomicBool>,
    dir: &Path,
) -> Result<DeploymentThread, String> {
    if spec.feed.is_empty() {
        return Err("[rsu_deployment] needs at least one [[rsu_deployment.feed]] version".into());
    }
    let _ = std::fs::remove_dir_all(dir);
    std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    let mib = match spec.mib.as_str() {
        "ntcip1218" => (Mib::Ntcip1218, RsuMib::Ntcip1218),
        "rsu4.1" => (Mib::Rsu41, RsuMib::Rsu41),
        other => return Err(format!("[rsu_deployment] mib {other}: ntcip1218 or rsu4.1")),
    };
    let now = unix_ms_now();
    let docs = spec
        .feed
        .iter()
        .map(|v| Ok((v.at_s, feed::document(road, v, now)?)))
        .collect::<Result<Vec<_>, String>>()?;
    let server = FeedServer::start(docs, t0)?;
    crate::bench_pki::write_rsu(&dir.join("pki"))?;
    write_credentials(&dir.join("credentials.toml"), spec.wrong_password)?;
    let port = free_udp_port()?;
    let config = TestRsuConfig {
        dir: dir.join("test-rsu"),
        port,
        mib: mib.0,
        users: vec![TestUser {
            name: USER.into(),
            auth: "SHA",
            auth_password: AUTH_PASS.into(),
            privacy: "AES",
            priv_password: PRIV_PASS.into(),
        }],
        community: None,
        broadcast_to: vec![to.parse().map_err(|e| format!("{to}: {e}"))?],
        max_rows: 32,
        pki: None,
        hil_sim: crate::test_rsu::find_hil_sim()?,
    };
    let mut rsu = if spec.up_at_s <= 0.0 {
        Some(TestRsu::start(config.clone())?)
    } else {
        None
    };
    let site = site(
        spec,
        scenario,
        dir,
        server.url(),
        format!("127.0.0.1:{port}"),
        mib.1,
    );
    let mut roadside =
        Roadside::start_site(site, &dir.join("site.toml"), Instant::now(), unix_ms_now())
            .map_err(|e| e.to_string())?;
    let spec = spec.clone();
    let dir = dir.to_path_buf();
    Ok(std::thread::spawn(move || {
        let mut log = std::fs::File::create(dir.join("roadside.log")).map_err(|e| e.to_string())?;
        // When the RSU came up: at the start (None), or the Unix time just before its snmpd
        // started, on the clock the agent stamps its first transmissions with.
        let mut ups: Vec<Option<u64>> = Vec::new();
        if rsu.is_some() {
            ups.push(None);
        }
        let mut restarted = false;
        while !stop.load(Ordering::Relaxed) {
            let t = t0.elapsed().as_secs_f64();
            if rsu.is_none() && t >= spec.up_at_s {
                let _ = writeln!(log, "bench: the RSU comes up at {t:.1} s");
                ups.push(Some(unix_ms_now()));
                rsu = Some(TestRsu::start(config.clone())?);
            }
            if let (Some(at), Some(r), false) = (spec.restart_at_s, rsu.as_mut(), restarted) {
                if t >= at {
                    let _ = writeln!(log, "bench: the RSU restarts at {t:.1} s");
                    ups.push(Some(unix_ms_now()));
                    r.restart()?;
                    restarted = true;
                }
            }
            roadside
                .tick(Instant::now(), unix_ms_now(), false, &mut log)
                .map_err(|e| e.to_string())?;
            std::thread::sleep(Duration::from_millis(20));
        }
        drop(roadside);
        let air_path = dir.join("test-rsu").join("air.log");
        drop(rsu);
        // The agent writes its last count once snmpd has gone.
        std::thread::sleep(Duration::from_millis(100));
        drop(server);
        Ok(finish(&spec, &dir, &air_path, t0, &ups))
    }))
}

fn finish(
    spec: &DeploymentSpec,
    dir: &Path,
    air_path: &Path,
    t0: Instant,
    ups: &[Option<u64>],
) -> (RoadsideRun, DeploymentFacts) {
    let air = AirLog::read(air_path);
    let t0_unix_ms = unix_ms_now().saturating_sub(t0.elapsed().as_millis() as u64);
    let since = |ms: u64| (ms as f64 - t0_unix_ms as f64) / 1000.0;
    let first_sent_s: Vec<f64> = air.first_sent_unix_ms.iter().map(|ms| since(*ms)).collect();
    let changes = first_sent_s
        .iter()
        .filter(|s| **s >= 0.0)
        .map(|s| t0 + Duration::from_secs_f64(*s))
        .collect();
    let run = RoadsideRun {
        changes,
        counts: V2xCounts {
            sent: air.sent,
            ..V2xCounts::default()
        },
        ..RoadsideRun::default()
    };
    let facts = DeploymentFacts {
        rsu_sent: air.sent,
        // Both from the wall clock the agent stamps with: a restart and the first
        // transmission after it compare on one clock.
        rsu_up_s: ups.iter().map(|u| u.map_or(0.0, since)).collect(),
        first_sent_s,
        feed_changes_s: spec.feed.iter().skip(1).map(|v| v.at_s).collect(),
        removed_at_s: spec.feed.iter().find(|v| v.removed).map(|v| v.at_s),
        status: read_status(&dir.join("roadside-state")),
    };
    (run, facts)
}
