//! A fleet of RSUs reconciled from one process: a session per RSU (SNMPv3 engines
//! discovered once), passes run by a few worker threads, retries with exponential backoff
//! for an RSU that fails, every outcome counted per RSU, and the rows the roadside placed
//! kept in a file so that a restarted roadside still knows which rows are its own.

use super::credentials::Credentials;
use super::deposit::DepositSettings;
use super::reconcile::WantedRow;
use super::session::{Agent, RequestCounts, Session};
use super::table::{reconcile, Owned, RsuProblem, TableRules};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::fmt;
use std::io;
use std::net::SocketAddr;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

/// One RSU of the site.
#[derive(Debug, Clone)]
pub struct RsuSpec {
    /// Its name in the site file.
    pub name: String,
    /// Its SNMP agent.
    pub address: SocketAddr,
    /// How to authenticate.
    pub credentials: Credentials,
    /// Its table's MIB and rules.
    pub rules: TableRules,
    /// How it sends the deposited messages.
    pub deposit: DepositSettings,
}

/// Timing of the fleet.
#[derive(Debug, Clone, Copy)]
pub struct FleetTiming {
    /// How often a converged RSU is read again.
    pub poll: Duration,
    /// Answer timeout of one request.
    pub timeout: Duration,
    /// Retries of a read that timed out.
    pub retries: u32,
    /// First retry delay after a failed pass (doubles up to `poll`).
    pub backoff: Duration,
    /// Worker threads.
    pub workers: usize,
}

/// One RSU's status, as `roadside rsu status` shows it.
#[derive(Debug, Clone, Default, Serialize, Deserialize)]
pub struct RsuStatus {
    /// Its name.
    pub name: String,
    /// Its address.
    pub address: String,
    /// Its MIB.
    pub mib: String,
    /// The last pass found the table as wanted (or made it so).
    pub converged: bool,
    /// The problem of the last pass, if it failed.
    pub problem: Option<String>,
    /// When the last pass ended (Unix ms).
    pub last_pass_unix_ms: u64,
    /// Rows in the table (as last read), ours, foreign.
    pub rows: usize,
    /// Rows the roadside placed.
    pub ours: usize,
    /// Rows left alone.
    pub foreign: usize,
    /// Outcomes: `passes`, `converged`, `created`, `destroyed`, and each
    /// [`RsuProblem::REASONS`].
    pub counts: BTreeMap<String, u64>,
    /// SNMP requests made.
    pub reads: u64,
    /// SET requests made.
    pub writes: u64,
}

struct Member {
    spec: RsuSpec,
    session: Session,
    owned: Owned,
    /// The roadside's immediate-forward row, once made.
    forward_slot: Option<u32>,
    next_pass: Instant,
    failures: u32,
    status: RsuStatus,
}

/// The fleet.
pub struct Fleet {
    members: Vec<Member>,
    timing: FleetTiming,
}

impl std::fmt::Debug for Fleet {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Fleet")
            .field("rsus", &self.members.len())
            .finish_non_exhaustive()
    }
}

impl Fleet {
    /// A fleet of `rsus`, each with the rows it owned before (`owned`, by name).
    pub fn new(
        rsus: Vec<RsuSpec>,
        timing: FleetTiming,
        owned: &BTreeMap<String, Owned>,
        now: Instant,
    ) -> Self {
        let members = rsus
            .into_iter()
            .map(|spec| Member {
                session: Session::new(
                    spec.address,
                    spec.credentials.clone(),
                    timing.timeout,
                    timing.retries,
                ),
                owned: owned.get(&spec.name).cloned().unwrap_or_default(),
                forward_slot: None,
                next_pass: now,
                failures: 0,
                status: RsuStatus {
                    name: spec.name.clone(),
                    address: spec.address.to_string(),
                    mib: spec.rules.mib.name().into(),
                    ..RsuStatus::default()
                },
                spec,
            })
            .collect();
        Self { members, timing }
    }

    /// Runs a pass on every RSU that is due at `now` (all of them with `force`), with the
    /// rows `wanted(rsu)` gives. Returns how many passes ran.
    pub fn poll(
        &mut self,
        wanted: &(dyn Fn(&RsuSpec) -> Vec<WantedRow> + Sync),
        now: Instant,
        unix_ms: u64,
        force: bool,
    ) -> usize {
        let timing = self.timing;
        let mut due: Vec<&mut Member> = self
            .members
            .iter_mut()
            .filter(|m| force || m.next_pass <= now)
            .collect();
        let n = due.len();
        if n == 0 {
            return 0;
        }
        let per = n.div_ceil(timing.workers.max(1));
        std::thread::scope(|scope| {
            for chunk in due.chunks_mut(per) {
                scope.spawn(move || {
                    for m in chunk.iter_mut() {
                        let rows = wanted(&m.spec);
                        m.pass(&rows, timing, unix_ms);
                    }
                });
            }
        });
        n
    }

    /// Sends `payloads` (IEEE 1609.2 or bare frames of `template`'s kind) once through each
    /// NTCIP 1218 RSU's immediate-forward table. RSU 4.1 units have none: the caller
    /// deposits such messages as short store-and-repeat rows instead. Counted as
    /// `forwarded` (or the problem's reason).
    pub fn forward(&mut self, template: &super::mib::RepeatMessage, payloads: &[Vec<u8>]) {
        let workers = self.timing.workers.max(1);
        let now = Instant::now();
        let mut due: Vec<&mut Member> = self
            .members
            .iter_mut()
            // An RSU in backoff is left out (its next pass finds out whether it is back).
            .filter(|m| {
                m.spec.rules.mib == super::mib::RsuMib::Ntcip1218
                    && (m.failures == 0 || m.next_pass <= now)
            })
            .collect();
        if due.is_empty() {
            return;
        }
        let per = due.len().div_ceil(workers);
        std::thread::scope(|scope| {
            for chunk in due.chunks_mut(per) {
                scope.spawn(move || {
                    for m in chunk.iter_mut() {
                        let t = super::mib::RepeatMessage {
                            channel: m.spec.deposit.channel,
                            priority: m.spec.deposit.priority,
                            ..template.clone()
                        };
                        let outcome = super::table::forward(
                            &mut m.session,
                            &t,
                            payloads,
                            &mut m.forward_slot,
                        );
                        let key = match &outcome {
                            Ok(_) => "forwarded",
                            Err(p) => p.reason(),
                        };
                        let n = outcome.unwrap_or(1);
                        *m.status.counts.entry(key.to_string()).or_default() += u64::from(n);
                    }
                });
            }
        });
    }

    /// Every RSU's status.
    pub fn status(&self) -> Vec<RsuStatus> {
        self.members.iter().map(|m| m.status.clone()).collect()
    }

    /// The rows the roadside owns, by RSU name.
    pub fn owned(&self) -> BTreeMap<String, Owned> {
        self.members
            .iter()
            .map(|m| (m.spec.name.clone(), m.owned.clone()))
            .collect()
    }

    /// Whether every RSU's last pass converged.
    pub fn all_converged(&self) -> bool {
        self.members.iter().all(|m| m.status.converged)
    }

    /// The earliest time an RSU is due.
    pub fn next_due(&self) -> Option<Instant> {
        self.members.iter().map(|m| m.next_pass).min()
    }
}

impl Member {
    fn pass(&mut self, wanted: &[WantedRow], timing: FleetTiming, unix_ms: u64) {
        let count = |s: &mut RsuStatus, k: &str, n: u64| {
            *s.counts.entry(k.to_string()).or_default() += n;
        };
        count(&mut self.status, "passes", 1);
        let outcome = reconcile(&mut self.session, self.spec.rules, wanted, &mut self.owned);
        let s = &mut self.status;
        s.last_pass_unix_ms = unix_ms;
        let RequestCounts { reads, writes } = self.session.counts();
        (s.reads, s.writes) = (reads, writes);
        let now = Instant::now();
        match outcome {
            Ok(report) => {
                let converged = report.plan.is_converged();
                count(s, if converged { "converged" } else { "changed" }, 1);
                count(s, "created", report.created.into());
                count(s, "destroyed", report.destroyed.into());
                s.converged = true;
                s.problem = None;
                s.rows = report.rows.len() + report.created as usize - report.destroyed as usize;
                s.ours = self.owned.len();
                s.foreign = report.plan.foreign.len();
                self.failures = 0;
                self.next_pass = now + timing.poll;
            }
            Err(problem) => {
                count(s, problem.reason(), 1);
                s.converged = false;
                s.problem = Some(problem.to_string());
                self.failures = self.failures.saturating_add(1);
                let backoff = timing
                    .backoff
                    .saturating_mul(1 << self.failures.min(16).saturating_sub(1))
                    .min(timing.poll);
                self.next_pass = now + backoff;
            }
        }
    }
}

/// Why the owned-rows file could not be read or written.
#[derive(Debug)]
#[non_exhaustive]
pub enum OwnedFileError {
    /// The file could not be read or written.
    Io {
        /// The file.
        path: PathBuf,
        /// The file system's error.
        source: io::Error,
    },
    /// The file is not JSON of the owned-rows shape.
    Json {
        /// The file.
        path: PathBuf,
        /// The parser's error.
        source: serde_json::Error,
    },
    /// A row's digest is not 32 octets of hexadecimal text.
    Digest {
        /// The file.
        path: PathBuf,
        /// The RSU's name.
        rsu: String,
        /// The row's index.
        row: u32,
    },
    /// The rows could not be written as JSON.
    Encode(serde_json::Error),
}

impl fmt::Display for OwnedFileError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Io { path, source } => write!(f, "{}: {source}", path.display()),
            Self::Json { path, source } => write!(f, "{}: {source}", path.display()),
            Self::Digest { path, rsu, row } => {
                write!(f, "{}: digest of {rsu} row {row}", path.display())
            }
            Self::Encode(e) => e.fmt(f),
        }
    }
}

impl std::error::Error for OwnedFileError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            Self::Io { source, .. } => Some(source),
            Self::Json { source, .. } | Self::Encode(source) => Some(source),
            Self::Digest { .. } => None,
        }
    }
}

/// Reads the owned-rows file (`{"rsu": {"3": "hex digest"}}`); missing: empty.
///
/// # Errors
///
/// [`OwnedFileError`]: a file that exists but cannot be read or is not of that shape.
pub fn load_owned(path: &Path) -> Result<BTreeMap<String, Owned>, OwnedFileError> {
    let text = match std::fs::read_to_string(path) {
        Ok(t) => t,
        Err(e) if e.kind() == io::ErrorKind::NotFound => return Ok(BTreeMap::new()),
        Err(source) => {
            return Err(OwnedFileError::Io {
                path: path.to_path_buf(),
                source,
            })
        }
    };
    let raw: BTreeMap<String, BTreeMap<u32, String>> =
        serde_json::from_str(&text).map_err(|source| OwnedFileError::Json {
            path: path.to_path_buf(),
            source,
        })?;
    raw.into_iter()
        .map(|(name, rows)| {
            let rows = rows
                .into_iter()
                .map(|(row, hex)| match unhex32(&hex) {
                    Some(digest) => Ok((row, digest)),
                    None => Err(OwnedFileError::Digest {
                        path: path.to_path_buf(),
                        rsu: name.clone(),
                        row,
                    }),
                })
                .collect::<Result<Owned, OwnedFileError>>()?;
            Ok((name, rows))
        })
        .collect()
}

/// Writes the owned-rows file (through a temporary file, so a crash leaves the old one).
///
/// # Errors
///
/// [`OwnedFileError`]: the file cannot be written.
pub fn save_owned(path: &Path, owned: &BTreeMap<String, Owned>) -> Result<(), OwnedFileError> {
    let raw: BTreeMap<&String, BTreeMap<u32, String>> = owned
        .iter()
        .map(|(n, rows)| (n, rows.iter().map(|(i, d)| (*i, hex(d))).collect()))
        .collect();
    let text = serde_json::to_string_pretty(&raw).map_err(OwnedFileError::Encode)?;
    let tmp = path.with_extension("tmp");
    std::fs::write(&tmp, text)
        .and_then(|()| std::fs::rename(&tmp, path))
        .map_err(|source| OwnedFileError::Io {
            path: path.to_path_buf(),
            source,
        })
}

fn hex(d: &[u8]) -> String {
    d.iter().map(|b| format!("{b:02x}")).collect()
}

fn unhex32(s: &str) -> Option<[u8; 32]> {
    let bytes: Vec<u8> = (0..s.len())
        .step_by(2)
        .map(|i| s.get(i..i + 2).and_then(|h| u8::from_str_radix(h, 16).ok()))
        .collect::<Option<_>>()?;
    bytes.try_into().ok()
}

/// The problem reasons, re-exported for status tables.
pub const REASONS: [&str; 9] = RsuProblem::REASONS;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn owned_rows_survive_a_file_round_trip() {
        let dir = std::env::temp_dir().join(format!("owned-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("owned.json");
        assert!(load_owned(&path).unwrap().is_empty());
        let owned = BTreeMap::from([("rsu-1".to_string(), Owned::from([(3, [7u8; 32])]))]);
        save_owned(&path, &owned).unwrap();
        assert_eq!(load_owned(&path).unwrap(), owned);
        std::fs::write(&path, "{\"rsu-1\": {\"3\": \"zz\"}}").unwrap();
        match load_owned(&path) {
            Err(OwnedFileError::Digest { rsu, row, .. }) => {
                assert_eq!((rsu.as_str(), row), ("rsu-1", 3))
            }
            other => panic!("{other:?}"),
        }
        std::fs::write(&path, "[").unwrap();
        assert!(matches!(
            load_owned(&path),
            Err(OwnedFileError::Json { .. })
        ));
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
