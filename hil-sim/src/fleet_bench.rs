//! `hil-sim bench-rsu-fleet`: one roadside fleet reconciling many test RSUs (one snmpd and
//! agent each, on loopback ports) x several messages: the time to converge from empty
//! tables, the SNMP requests per RSU of a poll when nothing changed, and memory.

use crate::test_rsu::agent::Mib;
use crate::test_rsu::{TestRsu, TestRsuConfig, TestUser};
use j2735::envelope::Psid;
use roadside::rsu_snmp::credentials::{AuthProtocol, Credentials, PrivProtocol};
use roadside::rsu_snmp::deposit::{DepositSettings, DepositSigning};
use roadside::rsu_snmp::fleet::{Fleet, FleetTiming, RsuSpec};
use roadside::rsu_snmp::mib::{RepeatMessage, RsuMib};
use roadside::rsu_snmp::table::TableRules;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

/// What the benchmark measured.
#[derive(Debug, Clone)]
pub struct FleetFigures {
    /// RSUs.
    pub rsus: usize,
    /// Messages per RSU.
    pub messages: usize,
    /// Time for every RSU to hold every message, from empty tables.
    pub converge: Duration,
    /// Reads and writes per RSU of a poll with nothing to change.
    pub idle_reads_per_rsu: f64,
    /// Writes per RSU of that poll (goal 0).
    pub idle_writes_per_rsu: f64,
    /// Time of that poll over the whole fleet.
    pub idle_poll: Duration,
    /// The benchmark process's resident memory after the runs, kB.
    pub roadside_rss_kb: u64,
    /// Resident memory of the test RSUs' snmpd and agent processes, kB.
    pub rsus_rss_kb: u64,
}

/// Resident set size of a process, kB (Linux `/proc`).
fn rss_kb(pid: &str) -> u64 {
    std::fs::read_to_string(format!("/proc/{pid}/status"))
        .ok()
        .and_then(|s| {
            s.lines()
                .find(|l| l.starts_with("VmRSS:"))
                .and_then(|l| l.split_whitespace().nth(1)?.parse().ok())
        })
        .unwrap_or(0)
}

/// RSS of every process whose command line contains `needle`, kB.
fn rss_of_matching(needle: &str) -> u64 {
    let Ok(dir) = std::fs::read_dir("/proc") else {
        return 0;
    };
    dir.filter_map(Result::ok)
        .filter_map(|e| e.file_name().into_string().ok())
        .filter(|pid| pid.bytes().all(|b| b.is_ascii_digit()))
        .filter(|pid| {
            std::fs::read(format!("/proc/{pid}/cmdline"))
                .is_ok_and(|c| String::from_utf8_lossy(&c).contains(needle))
        })
        .map(|pid| rss_kb(&pid))
        .sum()
}

/// `n` messages of about the size of a signed TIM.
fn messages(n: usize) -> Vec<RepeatMessage> {
    let now = roadside::clock::unix_ms_now();
    (0..n)
        .map(|i| RepeatMessage {
            label: format!("TIM {i}"),
            psid: Psid::TIM,
            message_id: 31,
            payload: (0..400).map(|b| (b * 7 + i * 13) as u8).collect(),
            channel: 183,
            interval_ms: 1000,
            start_unix_ms: now - now % 60_000,
            stop_unix_ms: now - now % 60_000 + 3_600_000,
            priority: 6,
            rsu_signs: false,
            alternating: false,
        })
        .collect()
}

/// Runs the benchmark: `rsus` test RSUs from `base_port`, `per_rsu` messages each.
///
/// # Errors
///
/// A test RSU that does not start, or a fleet that does not converge within 60 s.
pub fn run(
    rsus: usize,
    per_rsu: usize,
    base_port: u16,
    dir: &Path,
    hil_sim: &Path,
) -> Result<FleetFigures, String> {
    let user = TestUser {
        name: "roadside".into(),
        auth: "SHA",
        auth_password: "fleet-auth-pass".into(),
        privacy: "AES",
        priv_password: "fleet-priv-pass".into(),
    };
    let mut handles = Vec::new();
    // Start the RSUs a few at a time (each snmpd reads its configuration and binds).
    let ports: Vec<u16> = (0..rsus)
        .map(|i| u16::try_from(i).ok().and_then(|i| base_port.checked_add(i)))
        .collect::<Option<_>>()
        .ok_or("--base-port + --rsus runs past port 65535")?;
    for chunk in ports.chunks(20) {
        let started: Vec<Result<TestRsu, String>> = std::thread::scope(|s| {
            chunk
                .iter()
                .map(|port| {
                    let config = TestRsuConfig {
                        dir: dir.join(format!("rsu-{port}")),
                        port: *port,
                        mib: Mib::Ntcip1218,
                        users: vec![user.clone()],
                        community: None,
                        broadcast_to: Vec::new(),
                        max_rows: 16,
                        pki: None,
                        hil_sim: hil_sim.to_path_buf(),
                    };
                    s.spawn(move || TestRsu::start(config))
                })
                .collect::<Vec<_>>()
                .into_iter()
                .map(|h| h.join().unwrap_or_else(|_| Err("start panicked".into())))
                .collect()
        });
        for r in started {
            handles.push(r?);
        }
    }
    let specs: Vec<RsuSpec> = handles
        .iter()
        .enumerate()
        .map(|(i, rsu)| RsuSpec {
            name: format!("rsu-{i}"),
            address: rsu.address(),
            credentials: Credentials::V3 {
                user: "roadside".into(),
                auth: AuthProtocol::Sha,
                auth_password: "fleet-auth-pass".into(),
                privacy: PrivProtocol::Aes128,
                priv_password: "fleet-priv-pass".into(),
            },
            rules: TableRules {
                mib: RsuMib::Ntcip1218,
                max_rows: None,
                manage_all: false,
            },
            deposit: DepositSettings {
                channel: 183,
                interval_ms: 1000,
                priority: 6,
                signing: DepositSigning::None,
            },
        })
        .collect();
    let timing = FleetTiming {
        poll: Duration::from_secs(30),
        timeout: Duration::from_millis(1000),
        retries: 1,
        backoff: Duration::from_millis(200),
        workers: 16,
    };
    let msgs = messages(per_rsu);
    let wanted = |s: &RsuSpec| msgs.iter().map(|m| s.rules.mib.repeat_row(m)).collect();
    let mut fleet = Fleet::new(specs, timing, &BTreeMap::new(), Instant::now());
    let t0 = Instant::now();
    while !fleet.all_converged() {
        if t0.elapsed() > Duration::from_secs(60) {
            let bad: Vec<String> = fleet
                .status()
                .into_iter()
                .filter_map(|s| s.problem.map(|p| format!("{}: {p}", s.name)))
                .take(5)
                .collect();
            return Err(format!("not converged within 60 s: {}", bad.join("; ")));
        }
        let now = Instant::now();
        fleet.poll(&wanted, now, roadside::clock::unix_ms_now(), false);
        std::thread::sleep(Duration::from_millis(10));
    }
    let converge = t0.elapsed();
    let before: Vec<(u64, u64)> = fleet.status().iter().map(|s| (s.reads, s.writes)).collect();
    let t1 = Instant::now();
    fleet.poll(
        &wanted,
        Instant::now(),
        roadside::clock::unix_ms_now(),
        true,
    );
    let idle_poll = t1.elapsed();
    let after = fleet.status();
    let n = rsus.max(1) as f64;
    let reads: u64 = after.iter().zip(&before).map(|(a, b)| a.reads - b.0).sum();
    let writes: u64 = after.iter().zip(&before).map(|(a, b)| a.writes - b.1).sum();
    let figures = FleetFigures {
        rsus,
        messages: per_rsu,
        converge,
        idle_reads_per_rsu: reads as f64 / n,
        idle_writes_per_rsu: writes as f64 / n,
        idle_poll,
        roadside_rss_kb: rss_kb("self"),
        rsus_rss_kb: rss_of_matching(&dir.display().to_string()),
    };
    drop(handles);
    Ok(figures)
}

/// Where the benchmark's test RSUs keep their folders.
pub fn default_dir() -> PathBuf {
    std::env::temp_dir().join(format!("rsu-fleet-{}", std::process::id()))
}
