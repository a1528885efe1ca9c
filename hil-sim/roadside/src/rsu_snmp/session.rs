//! One SNMP session with one RSU, over the `snmp2` crate: SNMPv3 USM authPriv (engine
//! discovery, re-discovery after the RSU restarts) or SNMPv2c, with every answer mapped to
//! a closed set of outcomes ([`SnmpError`]).
//!
//! `snmp2` is used because it is the maintained Rust SNMP client that has SNMPv3 USM with
//! every protocol RSUs offer (HMAC-SHA-1 to SHA-512, AES-128 to AES-256, with both key
//! extensions for AES-192/256) in pure Rust (no OpenSSL to cross-build for ARM roadside
//! controllers), and a blocking session that a worker thread per RSU batch drives.

use super::credentials::{AuthProtocol, Credentials, PrivProtocol};
use snmp2::{v3, Oid, SyncSession, Value};
use std::fmt;
use std::net::SocketAddr;
use std::time::Duration;

/// An object identifier as arcs.
pub type Arcs = Vec<u64>;

/// A value read from or written to an RSU (the types its tables use).
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum SnmpValue {
    /// INTEGER (and the enumerations, RowStatus).
    Integer(i64),
    /// OCTET STRING.
    Octets(Vec<u8>),
    /// Unsigned32 / Gauge32 / Counter32 / TimeTicks.
    Unsigned(u32),
    /// OBJECT IDENTIFIER.
    Oid(Arcs),
    /// noSuchObject / noSuchInstance / endOfMibView: nothing there.
    Nothing,
    /// Any other type (Counter64, IpAddress, Opaque…), as text: the RSU tables use none.
    Other(String),
}

/// The SNMP error-status values (RFC 3416) an agent answers with.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ErrorStatus {
    /// tooBig (1).
    TooBig,
    /// noSuchName (2).
    NoSuchName,
    /// badValue (3).
    BadValue,
    /// readOnly (4).
    ReadOnly,
    /// genErr (5): RSUs answer it for a row index already in use.
    GenErr,
    /// noAccess (6).
    NoAccess,
    /// wrongType (7).
    WrongType,
    /// wrongLength (8).
    WrongLength,
    /// wrongEncoding (9).
    WrongEncoding,
    /// wrongValue (10): a value this MIB does not take (often: the RSU speaks the other MIB).
    WrongValue,
    /// noCreation (11).
    NoCreation,
    /// inconsistentValue (12).
    InconsistentValue,
    /// resourceUnavailable (13): the table is full.
    ResourceUnavailable,
    /// commitFailed (14).
    CommitFailed,
    /// undoFailed (15).
    UndoFailed,
    /// authorizationError (16): the user may not write this table.
    AuthorizationError,
    /// notWritable (17).
    NotWritable,
    /// inconsistentName (18).
    InconsistentName,
    /// Any other value.
    Other(u32),
}

impl ErrorStatus {
    /// The status of its number.
    pub fn from_code(code: u32) -> Self {
        use ErrorStatus::*;
        const BY_CODE: [ErrorStatus; 18] = [
            TooBig,
            NoSuchName,
            BadValue,
            ReadOnly,
            GenErr,
            NoAccess,
            WrongType,
            WrongLength,
            WrongEncoding,
            WrongValue,
            NoCreation,
            InconsistentValue,
            ResourceUnavailable,
            CommitFailed,
            UndoFailed,
            AuthorizationError,
            NotWritable,
            InconsistentName,
        ];
        code.checked_sub(1)
            .and_then(|i| BY_CODE.get(i as usize).copied())
            .unwrap_or(Other(code))
    }
}

/// Why an SNMP request did not succeed.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum SnmpError {
    /// No answer within the timeout (after the session's retries).
    Timeout,
    /// The RSU refused our credentials: unknown user, wrong password, or a protocol it
    /// does not have for the user (SNMPv3 reports, which carry no more detail).
    AuthRefused,
    /// The agent answered with an error-status for the varbind at `index` (1-based, 0:
    /// the request as a whole).
    Status {
        /// The error-status.
        status: ErrorStatus,
        /// The varbind it is about.
        index: u32,
    },
    /// The RSU's SNMP engine restarted or its clock moved (boots/time out of the window): the
    /// request was not processed and the session took the engine's new state; sent again
    /// once by the session itself.
    Resync,
    /// The answer was not a well-formed SNMP response to our request.
    Malformed(String),
    /// The socket could not be opened or used.
    Io(String),
}

impl fmt::Display for SnmpError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Timeout => f.write_str("no answer (timeout)"),
            Self::AuthRefused => f.write_str(
                "authentication refused: check the user, its passwords and the auth/privacy \
                 protocols in the credentials file against the RSU's SNMPv3 user",
            ),
            Self::Status { status, index } => write!(f, "{status:?} (varbind {index})"),
            Self::Resync => f.write_str("the RSU's SNMP engine restarted (not in time window)"),
            Self::Malformed(m) => write!(f, "malformed answer: {m}"),
            Self::Io(m) => write!(f, "socket: {m}"),
        }
    }
}

impl std::error::Error for SnmpError {}

/// How many requests a session made, by kind.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct RequestCounts {
    /// GET / GETNEXT / GETBULK requests (engine discovery included).
    pub reads: u64,
    /// SET requests.
    pub writes: u64,
}

/// What the roadside needs of an SNMP agent: read a subtree, read objects, write objects.
/// [`Session`] is the real one; tests may put a table in memory behind it.
pub trait Agent {
    /// Every object under `root`, in order.
    ///
    /// # Errors
    ///
    /// [`SnmpError`].
    fn walk(&mut self, root: &[u64]) -> Result<Vec<(Arcs, SnmpValue)>, SnmpError>;
    /// The objects `oids` ([`SnmpValue::Nothing`] for one that does not exist).
    ///
    /// # Errors
    ///
    /// [`SnmpError`].
    fn get(&mut self, oids: &[Arcs]) -> Result<Vec<SnmpValue>, SnmpError>;
    /// Writes `values` in one SET request.
    ///
    /// # Errors
    ///
    /// [`SnmpError`].
    fn set(&mut self, values: &[(Arcs, SnmpValue)]) -> Result<(), SnmpError>;
    /// The requests made so far.
    fn counts(&self) -> RequestCounts;
}

/// Objects asked for per GETBULK (halved while the agent answers tooBig).
const BULK_REPETITIONS: u32 = 24;

/// A table read stops with an error past this many objects (an agent that never ends).
const MAX_WALK_OBJECTS: usize = 100_000;

/// A request id to start a session at: different for each session, so that a late answer
/// to an earlier session's request on a reused port is not taken as this one's.
fn first_request_id(address: SocketAddr) -> i32 {
    let nanos = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.subsec_nanos());
    let mixed = nanos ^ u32::from(address.port()).rotate_left(16);
    // Positive, below 2^30: room to count up.
    (mixed & 0x3fff_ffff) as i32
}

/// A real SNMP session with one RSU.
pub struct Session {
    address: SocketAddr,
    credentials: Credentials,
    timeout: Duration,
    retries: u32,
    inner: Option<SyncSession>,
    counts: RequestCounts,
}

impl fmt::Debug for Session {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("Session")
            .field("address", &self.address)
            .field("credentials", &self.credentials)
            .finish_non_exhaustive()
    }
}

impl Session {
    /// A session with the agent at `address`; nothing is sent until the first request.
    /// Each request waits `timeout` for its answer and is sent again `retries` times.
    pub fn new(
        address: SocketAddr,
        credentials: Credentials,
        timeout: Duration,
        retries: u32,
    ) -> Self {
        Self {
            address,
            credentials,
            timeout,
            retries,
            inner: None,
            counts: RequestCounts::default(),
        }
    }

    /// The open session, opened (and, SNMPv3, its engine discovered) if need be.
    fn open(&mut self) -> Result<&mut SyncSession, SnmpError> {
        if self.inner.is_none() {
            let io = |e: std::io::Error| SnmpError::Io(e.to_string());
            let t = Some(self.timeout);
            let id = first_request_id(self.address);
            let session = match &self.credentials {
                Credentials::V2c { community } => {
                    SyncSession::new_v2c(self.address, community.as_bytes(), t, id).map_err(io)?
                }
                Credentials::V3 { .. } => {
                    let security = usm(&self.credentials);
                    let mut s = SyncSession::new_v3(self.address, t, id, security).map_err(io)?;
                    self.counts.reads += 1;
                    s.init().map_err(map_error)?;
                    s
                }
            };
            self.inner = Some(session);
        }
        Ok(self.inner.as_mut().expect("opened above"))
    }

    /// Runs `request` on the open session, with the retries: a timeout or a stale answer
    /// opens a fresh session (new socket, engine discovered again) and sends it again.
    fn with_retries<T>(
        &mut self,
        write: bool,
        mut request: impl FnMut(&mut SyncSession) -> Result<T, SnmpError>,
    ) -> Result<T, SnmpError> {
        let mut last = SnmpError::Timeout;
        // A SET whose answer was lost may have been done: it is not sent again blindly (the
        // next poll reads the table and decides).
        let tries = if write { 0 } else { self.retries };
        let mut resynced = false;
        let mut attempt = 0;
        while attempt <= tries {
            attempt += 1;
            let session = match self.open() {
                Ok(s) => s,
                Err(e @ (SnmpError::Timeout | SnmpError::Malformed(_))) => {
                    self.inner = None;
                    last = e;
                    continue;
                }
                Err(e) => {
                    self.inner = None;
                    return Err(e);
                }
            };
            let outcome = request(session);
            if write {
                self.counts.writes += 1;
            } else {
                self.counts.reads += 1;
            }
            match outcome {
                Err(e @ (SnmpError::Timeout | SnmpError::Malformed(_))) => {
                    // A late answer to this request would be read as the next one's.
                    self.inner = None;
                    last = e;
                }
                Err(SnmpError::Resync) if !resynced => {
                    // Not processed: the session took the engine's new boots/time; once more,
                    // reads and writes alike, not counted as a retry.
                    resynced = true;
                    attempt -= 1;
                    last = SnmpError::Resync;
                }
                Err(SnmpError::AuthRefused) => {
                    // The engine may have restarted with a new identity: rediscover.
                    self.inner = None;
                    last = SnmpError::AuthRefused;
                }
                other => return other,
            }
        }
        Err(last)
    }
}

/// snmp2's USM settings of `c` (authPriv).
fn usm(c: &Credentials) -> v3::Security {
    let Credentials::V3 {
        user,
        auth,
        auth_password,
        privacy,
        priv_password,
    } = c
    else {
        unreachable!("called for SNMPv3 credentials only");
    };
    let auth_protocol = match auth {
        AuthProtocol::Md5 => v3::AuthProtocol::Md5,
        AuthProtocol::Sha => v3::AuthProtocol::Sha1,
        AuthProtocol::Sha224 => v3::AuthProtocol::Sha224,
        AuthProtocol::Sha256 => v3::AuthProtocol::Sha256,
        AuthProtocol::Sha384 => v3::AuthProtocol::Sha384,
        AuthProtocol::Sha512 => v3::AuthProtocol::Sha512,
    };
    let cipher = match privacy {
        PrivProtocol::Des => v3::Cipher::Des,
        PrivProtocol::Aes128 => v3::Cipher::Aes128,
        PrivProtocol::Aes192 => v3::Cipher::Aes192,
        PrivProtocol::Aes256 => v3::Cipher::Aes256,
    };
    let security = v3::Security::new(user.as_bytes(), auth_password.as_bytes())
        .with_auth_protocol(auth_protocol)
        .with_auth(v3::Auth::AuthPriv {
            cipher,
            privacy_password: priv_password.as_bytes().to_vec(),
        });
    if cipher.priv_key_needs_extension(&auth_protocol) {
        // net-snmp's "AES-192"/"AES-256" (draft-blumenthal-aes-usm).
        security.with_key_extension_method(v3::KeyExtension::Blumenthal)
    } else {
        security
    }
}

/// Our outcome of an `snmp2` error.
fn map_error(e: snmp2::Error) -> SnmpError {
    use snmp2::Error as E;
    match e {
        E::Receive => SnmpError::Timeout,
        E::Send => SnmpError::Io("send failed".into()),
        E::AuthUpdated => SnmpError::Resync,
        E::AuthFailure(_) => SnmpError::AuthRefused,
        other => SnmpError::Malformed(other.to_string()),
    }
}

/// The arcs of `oid` as snmp2 takes them.
fn to_oid(arcs: &[u64]) -> Result<Oid<'static>, SnmpError> {
    Oid::from(arcs).map_err(|_| SnmpError::Malformed(format!("OID {arcs:?}")))
}

/// Our value of an snmp2 value.
fn from_value(v: &Value) -> Result<SnmpValue, SnmpError> {
    Ok(match v {
        Value::Integer(i) => SnmpValue::Integer(*i),
        Value::OctetString(o) => SnmpValue::Octets(o.to_vec()),
        Value::Counter32(u) | Value::Unsigned32(u) | Value::Timeticks(u) => SnmpValue::Unsigned(*u),
        Value::ObjectIdentifier(o) => SnmpValue::Oid(arcs_of(o)?),
        Value::NoSuchObject | Value::NoSuchInstance | Value::EndOfMibView | Value::Null => {
            SnmpValue::Nothing
        }
        other => SnmpValue::Other(format!("{other:?}")),
    })
}

fn arcs_of(o: &Oid) -> Result<Arcs, SnmpError> {
    o.iter()
        .map(|it| it.collect())
        .ok_or_else(|| SnmpError::Malformed("an OID arc over 64 bits".into()))
}

/// The varbinds of a response, or its error-status.
fn varbinds(pdu: &snmp2::Pdu) -> Result<Vec<(Arcs, SnmpValue)>, SnmpError> {
    if pdu.error_status != 0 {
        return Err(SnmpError::Status {
            status: ErrorStatus::from_code(pdu.error_status),
            index: pdu.error_index,
        });
    }
    pdu.varbinds
        .clone()
        .map(|(oid, v)| Ok((arcs_of(&oid)?, from_value(&v)?)))
        .collect()
}

impl Agent for Session {
    fn walk(&mut self, root: &[u64]) -> Result<Vec<(Arcs, SnmpValue)>, SnmpError> {
        let mut out: Vec<(Arcs, SnmpValue)> = Vec::new();
        let mut from = root.to_vec();
        let mut repetitions = BULK_REPETITIONS;
        loop {
            let oid = to_oid(&from)?;
            let batch = self.with_retries(false, |s| {
                let pdu = s.getbulk(&[&oid], 0, repetitions);
                varbinds(&pdu.map_err(map_error)?)
            });
            let batch = match batch {
                Err(SnmpError::Status {
                    status: ErrorStatus::TooBig,
                    ..
                }) if repetitions > 1 => {
                    repetitions /= 2;
                    continue;
                }
                other => other?,
            };
            if out.len() + batch.len() > MAX_WALK_OBJECTS {
                return Err(SnmpError::Malformed(format!(
                    "more than {MAX_WALK_OBJECTS} objects under {root:?}"
                )));
            }
            if batch.is_empty() {
                return Ok(out);
            }
            for (arcs, value) in batch {
                let past = !arcs.starts_with(root) || value == SnmpValue::Nothing;
                if past {
                    return Ok(out);
                }
                if arcs <= from {
                    return Err(SnmpError::Malformed(format!(
                        "the agent went backwards at {arcs:?}"
                    )));
                }
                from.clone_from(&arcs);
                out.push((arcs, value));
            }
        }
    }

    fn get(&mut self, oids: &[Arcs]) -> Result<Vec<SnmpValue>, SnmpError> {
        let oids = oids
            .iter()
            .map(|a| to_oid(a))
            .collect::<Result<Vec<_>, _>>()?;
        let refs: Vec<&Oid> = oids.iter().collect();
        let got = self.with_retries(false, |s| varbinds(&s.get_many(&refs).map_err(map_error)?))?;
        if got.len() != oids.len() {
            return Err(SnmpError::Malformed(format!(
                "{} values for {} objects",
                got.len(),
                oids.len()
            )));
        }
        Ok(got.into_iter().map(|(_, v)| v).collect())
    }

    fn set(&mut self, values: &[(Arcs, SnmpValue)]) -> Result<(), SnmpError> {
        let oids = values
            .iter()
            .map(|(a, _)| to_oid(a))
            .collect::<Result<Vec<_>, _>>()?;
        let pairs: Vec<(&Oid, Value)> = oids
            .iter()
            .zip(values)
            .map(|(oid, (_, v))| {
                let value = match v {
                    SnmpValue::Integer(i) => Value::Integer(*i),
                    SnmpValue::Octets(o) => Value::OctetString(o),
                    SnmpValue::Unsigned(u) => Value::Unsigned32(*u),
                    SnmpValue::Oid(_) | SnmpValue::Nothing | SnmpValue::Other(_) => {
                        return Err(SnmpError::Malformed(
                            "only INTEGER, Unsigned32 and OCTET STRING are written".into(),
                        ));
                    }
                };
                Ok((oid, value))
            })
            .collect::<Result<_, _>>()?;
        self.with_retries(true, |s| {
            varbinds(&s.set(&pairs).map_err(map_error)?).map(drop)
        })
    }

    fn counts(&self) -> RequestCounts {
        self.counts
    }
}
