//! The test RSU: Debian's `snmpd` (net-snmp) with SNMPv3 users, serving the NTCIP 1218 or
//! RSU 4.1 tables through this crate's `pass_persist` agent ([`agent`], [`tables`]), and
//! broadcasting each enabled row's payload over UDP as an RSU does ([`air`]). The bench's
//! scenarios and the roadside's tests program it over SNMP exactly as a field RSU.
//!
//! [`TestRsu::start`] writes the snmpd configuration into a folder of its own and starts
//! snmpd on a loopback port; [`run_agent`] is the agent process snmpd starts
//! (`hil-sim test-rsu-agent`).

pub mod agent;
pub mod air;
pub mod tables;

use agent::{Agent, Mib};
use air::Air;
use std::io::BufReader;
use std::net::SocketAddr;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::sync::{Arc, Mutex, PoisonError};
use std::time::{Duration, Instant};

/// An SNMPv3 user of the test RSU (authPriv).
#[derive(Debug, Clone)]
pub struct TestUser {
    /// User name.
    pub name: String,
    /// net-snmp's auth protocol name (`SHA`, `SHA-256`, `SHA-512`, `MD5`).
    pub auth: &'static str,
    /// Authentication password.
    pub auth_password: String,
    /// net-snmp's privacy protocol name (`AES`, `AES-256`, `DES`).
    pub privacy: &'static str,
    /// Privacy password.
    pub priv_password: String,
}

/// How a test RSU is set up.
#[derive(Debug, Clone)]
pub struct TestRsuConfig {
    /// Its folder (configuration, log).
    pub dir: PathBuf,
    /// Loopback UDP port of its SNMP agent.
    pub port: u16,
    /// The MIB it speaks.
    pub mib: Mib,
    /// SNMPv3 users with write access (authPriv).
    pub users: Vec<TestUser>,
    /// A v2c read-write community (lab units), if any.
    pub community: Option<String>,
    /// Where it broadcasts the rows' payloads.
    pub broadcast_to: Vec<SocketAddr>,
    /// Rows per table.
    pub max_rows: u32,
    /// Its IEEE 1609.2 PKI folder (`rsu.oer`, `rsu.key`) for rows it is asked to sign.
    pub pki: Option<PathBuf>,
    /// The `hil-sim` binary (the agent snmpd starts).
    pub hil_sim: PathBuf,
}

/// A running test RSU: snmpd and its agent.
#[derive(Debug)]
pub struct TestRsu {
    config: TestRsuConfig,
    snmpd: Option<Child>,
}

/// The `hil-sim` executable the test RSU's snmpd starts as its agent: `$HIL_SIM`, this
/// process when it is `hil-sim`, else `hil-sim` beside it or one folder up (a test binary
/// in `target/debug/deps`).
///
/// # Errors
///
/// None of them exists.
pub fn find_hil_sim() -> Result<PathBuf, String> {
    if let Some(p) = std::env::var_os("HIL_SIM") {
        return Ok(PathBuf::from(p));
    }
    let exe = std::env::current_exe().map_err(|e| e.to_string())?;
    if exe.file_stem().is_some_and(|n| n == "hil-sim") {
        return Ok(exe);
    }
    exe.ancestors()
        .skip(1)
        .take(2)
        .map(|d| d.join("hil-sim"))
        .find(|p| p.is_file())
        .ok_or_else(|| {
            "the hil-sim binary (the test RSU's agent) was not found: build it or set HIL_SIM"
                .into()
        })
}

/// Where Debian installs snmpd.
fn snmpd_path() -> Result<PathBuf, String> {
    ["/usr/sbin/snmpd", "/usr/local/sbin/snmpd"]
        .iter()
        .map(PathBuf::from)
        .find(|p| p.exists())
        .ok_or_else(|| "snmpd not found: install Debian's snmpd (apt-get install snmpd)".into())
}

impl TestRsu {
    /// Writes the configuration and starts snmpd; returns once it answers.
    ///
    /// # Errors
    ///
    /// snmpd missing, the folder unwritable, or snmpd not up within 5 s.
    pub fn start(config: TestRsuConfig) -> Result<Self, String> {
        let mut rsu = Self {
            config,
            snmpd: None,
        };
        rsu.write_config()?;
        rsu.up()?;
        Ok(rsu)
    }

    /// The agent's address.
    pub fn address(&self) -> SocketAddr {
        SocketAddr::from(([127, 0, 0, 1], self.config.port))
    }

    fn write_config(&self) -> Result<(), String> {
        let c = &self.config;
        let io = |e: std::io::Error| format!("{}: {e}", c.dir.display());
        std::fs::create_dir_all(c.dir.join("persist")).map_err(io)?;
        let root: String = c.mib.root().iter().map(|a| format!(".{a}")).collect();
        let mut conf = format!(
            "agentaddress udp:127.0.0.1:{port}\nengineID test-rsu-{port}\n\
             view all included .1\n",
            port = c.port
        );
        for u in &c.users {
            conf.push_str(&format!(
                "createUser {} {} \"{}\" {} \"{}\"\nrwuser {} priv -V all\n",
                u.name, u.auth, u.auth_password, u.privacy, u.priv_password, u.name
            ));
        }
        if let Some(community) = &c.community {
            conf.push_str(&format!("rwcommunity {community} 127.0.0.1\n"));
        }
        let mut agent = format!(
            "{} test-rsu-agent --mib {} --max-rows {}",
            c.hil_sim.display(),
            match c.mib {
                Mib::Ntcip1218 => "ntcip1218",
                Mib::Rsu41 => "rsu4.1",
            },
            c.max_rows
        );
        for d in &c.broadcast_to {
            agent.push_str(&format!(" --to {d}"));
        }
        agent.push_str(&format!(" --log {}", c.dir.join("air.log").display()));
        if let Some(p) = &c.pki {
            agent.push_str(&format!(" --pki {}", p.display()));
        }
        conf.push_str(&format!("pass_persist {root} {agent}\n"));
        std::fs::write(c.dir.join("snmpd.conf"), conf).map_err(io)
    }

    /// Starts snmpd (a fresh agent: empty tables, as after a power cycle).
    ///
    /// # Errors
    ///
    /// snmpd missing or not up within 5 s.
    pub fn up(&mut self) -> Result<(), String> {
        if self.snmpd.is_some() {
            return Ok(());
        }
        let c = &self.config;
        let log = c.dir.join("snmpd.log");
        let _ = std::fs::remove_file(&log);
        let child = Command::new(snmpd_path()?)
            .args(["-f", "-C", "-c"])
            .arg(c.dir.join("snmpd.conf"))
            .args(["-I", "-smux", "-Lf"])
            .arg(&log)
            .env("MIBS", "")
            .env("MIBDIRS", "/nonexistent")
            .env("SNMP_PERSISTENT_DIR", c.dir.join("persist"))
            .stdin(Stdio::null())
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .map_err(|e| format!("snmpd: {e}"))?;
        self.snmpd = Some(child);
        let deadline = Instant::now() + Duration::from_secs(5);
        while Instant::now() < deadline {
            let text = std::fs::read_to_string(&log).unwrap_or_default();
            if text.contains("NET-SNMP version") {
                return Ok(());
            }
            if let Some(Ok(Some(status))) = self.snmpd.as_mut().map(Child::try_wait) {
                self.snmpd = None;
                return Err(format!("snmpd exited ({status}): {}", text.trim()));
            }
            std::thread::sleep(Duration::from_millis(20));
        }
        self.down();
        Err(format!("snmpd not up within 5 s (log {})", log.display()))
    }

    /// Stops snmpd (its agent ends with it: the tables are gone).
    pub fn down(&mut self) {
        if let Some(mut child) = self.snmpd.take() {
            let _ = child.kill();
            let _ = child.wait();
        }
    }

    /// Stops and starts snmpd: an RSU that restarted with an empty table.
    ///
    /// # Errors
    ///
    /// As [`TestRsu::up`].
    pub fn restart(&mut self) -> Result<(), String> {
        self.down();
        self.up()
    }

    /// Its folder.
    pub fn dir(&self) -> &Path {
        &self.config.dir
    }

    /// What its radio did so far, from its agents' log (`air.log`; each start of snmpd
    /// starts a new agent): datagrams sent, and when each new payload first went out.
    pub fn air_log(&self) -> AirLog {
        AirLog::read(&self.config.dir.join("air.log"))
    }
}

/// The test RSU's radio log.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct AirLog {
    /// Datagrams sent (each destination counts).
    pub sent: u64,
    /// Unix ms of each new payload's first transmission, in order.
    pub first_sent_unix_ms: Vec<u64>,
}

impl AirLog {
    /// Reads a log; a missing one is empty.
    pub fn read(path: &Path) -> Self {
        let text = std::fs::read_to_string(path).unwrap_or_default();
        let mut sent_by_agent = std::collections::BTreeMap::new();
        let mut out = Self::default();
        for line in text.lines() {
            match line.split_whitespace().collect::<Vec<_>>()[..] {
                [pid, "sent", n] => {
                    let n: u64 = n.parse().unwrap_or(0);
                    let e = sent_by_agent.entry(pid.to_string()).or_insert(0);
                    *e = n.max(*e);
                }
                [_, "first", ms, _] => out.first_sent_unix_ms.extend(ms.parse::<u64>().ok()),
                _ => {}
            }
        }
        out.sent = sent_by_agent.values().sum();
        out.first_sent_unix_ms.sort_unstable();
        out
    }
}

impl Drop for TestRsu {
    fn drop(&mut self) {
        self.down();
    }
}

/// The agent process (`hil-sim test-rsu-agent`): serves snmpd's pass_persist requests on
/// stdin/stdout and broadcasts the rows until snmpd closes its stdin.
///
/// # Errors
///
/// The broadcast socket or the PKI cannot be opened.
pub fn run_agent(
    mib: Mib,
    max_rows: u32,
    destinations: Vec<SocketAddr>,
    pki: Option<&Path>,
    log: Option<&Path>,
) -> Result<(), String> {
    let signer = match pki {
        Some(dir) => Some(roadside::signer::RsuSigner::load(dir, None).map_err(|e| e.to_string())?),
        None => None,
    };
    let agent = Arc::new(Mutex::new(Agent::new(mib, max_rows)));
    let air = Air::new(destinations, signer, log).map_err(|e| format!("broadcast socket: {e}"))?;
    let air = Arc::new(Mutex::new(air));
    let (radio, tx) = (Arc::clone(&agent), Arc::clone(&air));
    std::thread::spawn(move || loop {
        let now = Instant::now();
        let unix_ms = roadside::clock::unix_ms_now();
        let busy = {
            let mut agent = radio.lock().unwrap_or_else(PoisonError::into_inner);
            tx.lock()
                .unwrap_or_else(PoisonError::into_inner)
                .tick(&mut agent, now, unix_ms);
            agent.tables.iter().any(|t| !t.rows.is_empty()) || agent.is_in_request()
        };
        // 5 ms steps while rows go out (their intervals are 100 ms and more); an idle RSU
        // (200 of them in the fleet benchmark) checks every 20 ms.
        std::thread::sleep(Duration::from_millis(if busy { 5 } else { 20 }));
    });
    let stdin = std::io::stdin();
    let served = agent::serve(
        &agent,
        BufReader::new(stdin.lock()),
        std::io::stdout().lock(),
    );
    // snmpd has gone (its RSU stopped): the last count goes to the log.
    air.lock()
        .unwrap_or_else(PoisonError::into_inner)
        .flush_count();
    served.map_err(|e| format!("pass_persist pipe: {e}"))
}
