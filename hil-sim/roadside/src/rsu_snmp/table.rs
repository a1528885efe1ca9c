//! One reconciliation pass over one RSU: read its store-and-repeat table, plan
//! ([`super::reconcile::plan`]), destroy and create rows, and say what happened in terms an
//! operator acts on ([`RsuProblem`]).

use super::mib::{row_status, RsuMib};
use super::reconcile::{plan, Columns, Plan, Rows, WantedRow};
use super::session::{Agent, ErrorStatus, SnmpError, SnmpValue};
use sha2::{Digest, Sha256};
use std::collections::BTreeMap;
use std::fmt;

/// RSU 4.1 tables have no maximum-rows object: the roadside uses at most this many indices
/// there unless the RSU's entry says otherwise (jpo-ode's slot count).
pub const RSU41_DEFAULT_ROWS: u32 = 100;

/// What went wrong with an RSU, in an operator's terms (a closed set: each is counted).
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum RsuProblem {
    /// No answer: the RSU is down, unreachable, or not listening on that port.
    Timeout,
    /// The RSU refused our SNMPv3 credentials (or the v2c community).
    AuthRefused,
    /// The user may read but not write the table (`authorizationError`, `noAccess`,
    /// `notWritable`).
    NotAuthorized(String),
    /// `genErr` on a create: the index is in use (a row was created there by someone else
    /// since the table was read).
    IndexInUse(u32),
    /// `wrongValue` / no such table: the RSU does not speak the MIB its entry names.
    MibMismatch(String),
    /// The table has no free row for a message (or the RSU answered
    /// `resourceUnavailable`).
    TableFull(String),
    /// Any other SNMP error-status.
    Refused(String),
    /// The RSU's answer was not well-formed SNMP, or a row was unreadable.
    Malformed(String),
    /// Our socket failed.
    Io(String),
}

impl RsuProblem {
    /// The counter name of the problem.
    pub const fn reason(&self) -> &'static str {
        match self {
            Self::Timeout => "timeout",
            Self::AuthRefused => "auth_refused",
            Self::NotAuthorized(_) => "not_authorized",
            Self::IndexInUse(_) => "index_in_use",
            Self::MibMismatch(_) => "mib_mismatch",
            Self::TableFull(_) => "table_full",
            Self::Refused(_) => "refused",
            Self::Malformed(_) => "malformed",
            Self::Io(_) => "io",
        }
    }

    /// Every counter name, in the order the status table prints them.
    pub const REASONS: [&'static str; 9] = [
        "timeout",
        "auth_refused",
        "not_authorized",
        "index_in_use",
        "mib_mismatch",
        "table_full",
        "refused",
        "malformed",
        "io",
    ];

    fn of(e: SnmpError, what: &str, mib: RsuMib) -> Self {
        match e {
            SnmpError::Timeout => Self::Timeout,
            SnmpError::AuthRefused => Self::AuthRefused,
            SnmpError::Malformed(m) => Self::Malformed(format!("{what}: {m}")),
            SnmpError::Io(m) => Self::Io(m),
            SnmpError::Resync => Self::Refused(format!(
                "{what}: the RSU's SNMP engine restarted twice during the request"
            )),
            SnmpError::Status { status, index } => {
                let at = format!("{what}: {status:?} at varbind {index}");
                match status {
                    ErrorStatus::AuthorizationError
                    | ErrorStatus::NoAccess
                    | ErrorStatus::NotWritable
                    | ErrorStatus::ReadOnly => Self::NotAuthorized(at),
                    ErrorStatus::WrongValue | ErrorStatus::NoCreation | ErrorStatus::NoSuchName => {
                        Self::MibMismatch(format!("{at} (is this RSU {}?)", mib.name()))
                    }
                    ErrorStatus::ResourceUnavailable => Self::TableFull(at),
                    _ => Self::Refused(at),
                }
            }
        }
    }
}

impl fmt::Display for RsuProblem {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Timeout => f.write_str("no answer (timeout): RSU down or unreachable"),
            Self::AuthRefused => f.write_str(
                "authentication refused: the user, passwords or auth/privacy protocols do not \
                 match the RSU's SNMPv3 user (nothing was written)",
            ),
            Self::NotAuthorized(m) => write!(f, "not authorized to write the table: {m}"),
            Self::IndexInUse(i) => write!(f, "index {i} already in use (genErr)"),
            Self::MibMismatch(m) => write!(f, "MIB mismatch: {m}"),
            Self::TableFull(m) => write!(f, "table full: {m}"),
            Self::Refused(m) => write!(f, "refused: {m}"),
            Self::Malformed(m) => write!(f, "malformed answer: {m}"),
            Self::Io(m) => write!(f, "socket error: {m}"),
        }
    }
}

/// Rows the roadside placed on one RSU: index and the SHA-256 of the payload it wrote
/// there (a row someone else rewrote at that index is no longer ours).
pub type Owned = BTreeMap<u32, [u8; 32]>;

/// SHA-256 of a payload.
pub fn payload_digest(payload: &[u8]) -> [u8; 32] {
    Sha256::digest(payload).into()
}

/// How one RSU's table is to be managed.
#[derive(Debug, Clone, Copy)]
pub struct TableRules {
    /// The MIB.
    pub mib: RsuMib,
    /// Rows to use at most (`None`: NTCIP 1218's `maxRsuMsgRepeat`, RSU 4.1's default).
    pub max_rows: Option<u32>,
    /// Every row is the roadside's: foreign rows are destroyed.
    pub manage_all: bool,
}

/// What a pass did.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct PassReport {
    /// The plan it followed.
    pub plan: Plan,
    /// Rows destroyed and created.
    pub destroyed: u32,
    /// Rows created.
    pub created: u32,
    /// The table as read (before the changes).
    pub rows: Rows,
}

/// The store-and-repeat table of `agent` as rows.
///
/// # Errors
///
/// [`RsuProblem`].
pub fn read_table(agent: &mut dyn Agent, mib: RsuMib) -> Result<Rows, RsuProblem> {
    let entry = mib.repeat_entry();
    let objects = agent
        .walk(&entry)
        .map_err(|e| RsuProblem::of(e, "reading the table", mib))?;
    let mut rows = Rows::new();
    for (arcs, value) in objects {
        let tail = &arcs[entry.len()..];
        let [column, index] = tail else {
            return Err(RsuProblem::Malformed(format!(
                "object {arcs:?} is not column.index of the table"
            )));
        };
        let (Ok(column), Ok(index)) = (u32::try_from(*column), u32::try_from(*index)) else {
            return Err(RsuProblem::Malformed(format!("object {arcs:?}")));
        };
        rows.entry(index).or_default().insert(column, value);
    }
    Ok(rows)
}

/// Which MIBs the RSU answers `rsuMibVersion` of, with the version text.
///
/// # Errors
///
/// [`RsuProblem`] of the request.
pub fn probe(agent: &mut dyn Agent) -> Result<Vec<(RsuMib, String)>, RsuProblem> {
    let mut out = Vec::new();
    for mib in [RsuMib::Ntcip1218, RsuMib::Rsu41] {
        let got = agent
            .get(&[mib.mib_version()])
            .map_err(|e| RsuProblem::of(e, "reading rsuMibVersion", mib))?;
        if let Some(SnmpValue::Octets(text)) = got.first() {
            out.push((mib, String::from_utf8_lossy(text).into_owned()));
        }
    }
    Ok(out)
}

/// Refuses an RSU that does not answer `mib`'s `rsuMibVersion`.
fn check_mib(agent: &mut dyn Agent, mib: RsuMib) -> Result<(), RsuProblem> {
    let speaks = probe(agent)?;
    if speaks.iter().any(|(m, _)| *m == mib) {
        return Ok(());
    }
    let other = match speaks.first() {
        Some((m, text)) => format!("it answers {} ({text})", m.name()),
        None => "it answers neither NTCIP 1218 nor RSU 4.1".into(),
    };
    Err(RsuProblem::MibMismatch(format!(
        "the site says {} but {other}: set `mib` in its [[rsu]] entry",
        mib.name()
    )))
}

/// How many rows the table takes.
fn max_rows(agent: &mut dyn Agent, rules: TableRules) -> Result<u32, RsuProblem> {
    if let Some(n) = rules.max_rows {
        return Ok(n);
    }
    let Some(oid) = rules.mib.repeat_max_rows() else {
        return Ok(RSU41_DEFAULT_ROWS);
    };
    let got = agent
        .get(&[oid])
        .map_err(|e| RsuProblem::of(e, "reading maxRsuMsgRepeat", rules.mib))?;
    match got.first() {
        Some(SnmpValue::Integer(n)) => {
            u32::try_from(*n).map_err(|_| RsuProblem::Malformed(format!("maxRsuMsgRepeat {n}")))
        }
        Some(SnmpValue::Unsigned(n)) => Ok(*n),
        _ => Err(RsuProblem::MibMismatch(
            "no maxRsuMsgRepeat (is this RSU ntcip1218?)".into(),
        )),
    }
}

/// The payload column of the MIB's store-and-repeat table.
const fn payload_column(mib: RsuMib) -> u32 {
    match mib {
        RsuMib::Ntcip1218 => 7,
        RsuMib::Rsu41 => 9,
    }
}

/// Whether the row at `index` is one the roadside placed.
fn is_ours(owned: &Owned, mib: RsuMib, index: u32, cols: &Columns) -> bool {
    let payload = match cols.get(&payload_column(mib)) {
        Some(SnmpValue::Octets(p)) => p,
        _ => return false,
    };
    owned.get(&index) == Some(&payload_digest(payload))
}

/// One pass: read, plan, destroy, create. `owned` is updated with what the pass placed,
/// adopted and destroyed; it is left as the RSU stands when a write fails.
///
/// # Errors
///
/// The first [`RsuProblem`] met (the changes before it stay made).
pub fn reconcile(
    agent: &mut dyn Agent,
    rules: TableRules,
    wanted: &[WantedRow],
    owned: &mut Owned,
) -> Result<PassReport, RsuProblem> {
    let mib = rules.mib;
    let max = max_rows(agent, rules)?;
    let rows = read_table(agent, mib)?;
    if rows.is_empty() {
        // First contact or a restarted RSU: make sure it speaks the MIB before writing.
        check_mib(agent, mib)?;
    }
    let status = mib.repeat_status_column();
    let plan = plan(
        wanted,
        &rows,
        |i, c| is_ours(owned, mib, i, c),
        status,
        max,
        rules.manage_all,
    );
    // Rows that are no longer there are no longer ours.
    owned.retain(|i, _| rows.contains_key(i));
    for (w, index) in &plan.keep {
        owned.insert(*index, digest_of(&wanted[*w], mib));
    }
    let entry = mib.repeat_entry();
    let oid = |column: u32, index: u32| {
        let mut a = entry.clone();
        a.extend([u64::from(column), u64::from(index)]);
        a
    };
    let mut report = PassReport {
        plan: plan.clone(),
        rows,
        ..PassReport::default()
    };
    for index in &plan.destroy {
        let destroy = [(oid(status, *index), SnmpValue::Integer(row_status::DESTROY))];
        agent
            .set(&destroy)
            .map_err(|e| RsuProblem::of(e, &format!("destroying row {index}"), mib))?;
        owned.remove(index);
        report.destroyed += 1;
    }
    for (index, w) in &plan.create {
        let want = &wanted[*w];
        let mut values: Vec<_> = want
            .columns
            .iter()
            .map(|(c, v, _)| (oid(*c, *index), v.clone()))
            .collect();
        // RowStatus after the data columns of the row, as deployed managers send it.
        let at = values.len().min(
            want.columns
                .iter()
                .position(|(c, _, _)| *c > status)
                .unwrap_or(values.len()),
        );
        values.insert(
            at,
            (
                oid(status, *index),
                SnmpValue::Integer(row_status::CREATE_AND_GO),
            ),
        );
        // Ours from before the SET: a SET whose answer was lost, or that the RSU applied in
        // part, may have left our row there (a row someone else wrote at that index has
        // another payload, so it never counts as ours).
        owned.insert(*index, digest_of(want, mib));
        agent.set(&values).map_err(|e| match e {
            SnmpError::Status {
                status: ErrorStatus::GenErr,
                ..
            } => RsuProblem::IndexInUse(*index),
            e => RsuProblem::of(e, &format!("creating row {index} ({})", want.label), mib),
        })?;
        report.created += 1;
    }
    if let Some(w) = plan.no_room.first() {
        return Err(RsuProblem::TableFull(format!(
            "no free index of {max} for {} ({} message(s) not placed)",
            wanted[*w].label,
            plan.no_room.len()
        )));
    }
    Ok(report)
}

/// The digest of the payload a wanted row writes.
fn digest_of(w: &WantedRow, mib: RsuMib) -> [u8; 32] {
    let payload = w
        .columns
        .iter()
        .find(|(c, _, _)| *c == payload_column(mib))
        .and_then(|(_, v, _)| match v {
            SnmpValue::Octets(p) => Some(p.as_slice()),
            _ => None,
        })
        .unwrap_or_default();
    payload_digest(payload)
}

/// Sends `payloads` once each through the RSU's NTCIP 1218 immediate-forward table: the
/// roadside's row (`slot`; found again by its PSID, channel and options, or created at a
/// free index with `enable` 0, as V2X-Hub does) gets each payload written with `enable` 1,
/// one SET per transmission.
///
/// # Errors
///
/// The first [`RsuProblem`]; `slot` is forgotten only when the RSU says the row is not
/// there (it restarted), not on a timeout.
pub fn forward(
    agent: &mut dyn Agent,
    template: &super::mib::RepeatMessage,
    payloads: &[Vec<u8>],
    slot: &mut Option<u32>,
) -> Result<u32, RsuProblem> {
    use super::mib::ifm_entry;
    let mib = RsuMib::Ntcip1218;
    let entry = ifm_entry();
    let oid = |column: u32, index: u32| {
        let mut a = entry.clone();
        a.extend([u64::from(column), u64::from(index)]);
        a
    };
    let index = match *slot {
        Some(i) => i,
        None => {
            let i = ifm_slot(agent, template)?;
            *slot = Some(i);
            i
        }
    };
    let mut sent = 0;
    for p in payloads {
        let values = [
            (oid(8, index), SnmpValue::Octets(p.clone())),
            (oid(4, index), SnmpValue::Integer(1)),
        ];
        if let Err(e) = agent.set(&values) {
            let gone = matches!(
                e,
                SnmpError::Status {
                    status: ErrorStatus::NoCreation
                        | ErrorStatus::InconsistentName
                        | ErrorStatus::NoSuchName
                        | ErrorStatus::NotWritable
                        | ErrorStatus::InconsistentValue,
                    ..
                }
            );
            if gone {
                *slot = None;
            }
            return Err(RsuProblem::of(
                e,
                &format!("forwarding through row {index}"),
                mib,
            ));
        }
        sent += 1;
    }
    Ok(sent)
}

/// The roadside's immediate-forward row: an active row with the template's PSID, channel
/// and options (one the roadside made before it restarted), else a new one at the lowest
/// free index.
fn ifm_slot(
    agent: &mut dyn Agent,
    template: &super::mib::RepeatMessage,
) -> Result<u32, RsuProblem> {
    use super::mib::{ifm_entry, ifm_max_rows, ifm_row, IFM_STATUS_COLUMN};
    let mib = RsuMib::Ntcip1218;
    let entry = ifm_entry();
    let max = match agent
        .get(&[ifm_max_rows()])
        .map_err(|e| RsuProblem::of(e, "reading maxRsuIFMs", mib))?
        .first()
    {
        Some(SnmpValue::Integer(n)) => u32::try_from(*n).unwrap_or(0),
        Some(SnmpValue::Unsigned(n)) => *n,
        _ => {
            return Err(RsuProblem::MibMismatch(
                "no maxRsuIFMs (is this RSU ntcip1218?)".into(),
            ))
        }
    };
    let mut rows = Rows::new();
    for (arcs, value) in agent
        .walk(&entry)
        .map_err(|e| RsuProblem::of(e, "reading the immediate-forward table", mib))?
    {
        if let [column, index] = arcs[entry.len()..] {
            if let (Ok(c), Ok(i)) = (u32::try_from(column), u32::try_from(index)) {
                rows.entry(i).or_default().insert(c, value);
            }
        }
    }
    let row = ifm_row(template);
    // PSID, channel, priority and options say it is the roadside's kind of row.
    let same = |cols: &Columns| {
        cols.get(&IFM_STATUS_COLUMN) == Some(&SnmpValue::Integer(super::reconcile::ROW_ACTIVE))
            && row
                .columns
                .iter()
                .filter(|(c, _, _)| matches!(c, 2 | 3 | 6 | 7))
                .all(|(c, v, _)| cols.get(c) == Some(v))
    };
    if let Some((index, _)) = rows.iter().find(|(_, cols)| same(cols)) {
        return Ok(*index);
    }
    let free = (1..=max)
        .find(|i| !rows.contains_key(i))
        .ok_or_else(|| RsuProblem::TableFull(format!("no free immediate-forward row of {max}")))?;
    let oid = |column: u32| {
        let mut a = entry.clone();
        a.extend([u64::from(column), u64::from(free)]);
        a
    };
    let mut values: Vec<_> = row
        .columns
        .iter()
        .map(|(c, v, _)| {
            let v = if *c == 4 {
                SnmpValue::Integer(0)
            } else {
                v.clone()
            };
            (oid(*c), v)
        })
        .collect();
    values.push((
        oid(IFM_STATUS_COLUMN),
        SnmpValue::Integer(row_status::CREATE_AND_GO),
    ));
    agent
        .set(&values)
        .map_err(|e| RsuProblem::of(e, &format!("creating immediate-forward row {free}"), mib))?;
    Ok(free)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rsu_snmp::mib::RepeatMessage;
    use crate::rsu_snmp::session::{Arcs, RequestCounts};
    use j2735::envelope::Psid;
    use std::collections::BTreeMap;

    /// An in-memory NTCIP 1218 table, answering SETs with `fail` when given.
    #[derive(Default)]
    struct FakeRsu {
        objects: BTreeMap<Arcs, SnmpValue>,
        fail: Option<ErrorStatus>,
        counts: RequestCounts,
    }

    impl Agent for FakeRsu {
        fn walk(&mut self, root: &[u64]) -> Result<Vec<(Arcs, SnmpValue)>, SnmpError> {
            self.counts.reads += 1;
            Ok(self
                .objects
                .iter()
                .filter(|(o, _)| o.starts_with(root))
                .map(|(o, v)| (o.clone(), v.clone()))
                .collect())
        }
        fn get(&mut self, oids: &[Arcs]) -> Result<Vec<SnmpValue>, SnmpError> {
            self.counts.reads += 1;
            Ok(oids
                .iter()
                .map(|o| {
                    if *o == RsuMib::Ntcip1218.repeat_max_rows().unwrap() {
                        SnmpValue::Integer(2)
                    } else if *o == RsuMib::Ntcip1218.mib_version() {
                        SnmpValue::Octets(b"NTCIP 1218".to_vec())
                    } else {
                        self.objects.get(o).cloned().unwrap_or(SnmpValue::Nothing)
                    }
                })
                .collect())
        }
        fn set(&mut self, values: &[(Arcs, SnmpValue)]) -> Result<(), SnmpError> {
            self.counts.writes += 1;
            if let Some(status) = self.fail {
                return Err(SnmpError::Status { status, index: 1 });
            }
            let status = u64::from(RsuMib::Ntcip1218.repeat_status_column());
            for (o, v) in values {
                let is_status = o[o.len() - 2] == status;
                if is_status && *v == SnmpValue::Integer(row_status::DESTROY) {
                    let row = &o[..o.len() - 2];
                    let index = o[o.len() - 1];
                    self.objects
                        .retain(|k, _| !(k.starts_with(row) && k[k.len() - 1] == index));
                } else {
                    let v = if is_status && *v == SnmpValue::Integer(row_status::CREATE_AND_GO) {
                        SnmpValue::Integer(1)
                    } else {
                        v.clone()
                    };
                    self.objects.insert(o.clone(), v);
                }
            }
            Ok(())
        }
        fn counts(&self) -> RequestCounts {
            self.counts
        }
    }

    fn wanted(payload: u8) -> WantedRow {
        RsuMib::Ntcip1218.repeat_row(&RepeatMessage {
            label: format!("TIM {payload}"),
            psid: Psid::TIM,
            message_id: 31,
            payload: vec![0, 0x1f, payload],
            channel: 183,
            interval_ms: 100,
            start_unix_ms: 1_796_390_000_000,
            stop_unix_ms: 1_796_400_000_000,
            priority: 6,
            rsu_signs: false,
            alternating: false,
        })
    }

    const RULES: TableRules = TableRules {
        mib: RsuMib::Ntcip1218,
        max_rows: None,
        manage_all: false,
    };

    #[test]
    fn each_error_status_is_an_operator_problem() {
        let cases = [
            (ErrorStatus::GenErr, RsuProblem::IndexInUse(1)),
            (
                ErrorStatus::ResourceUnavailable,
                RsuProblem::TableFull(String::new()),
            ),
            (
                ErrorStatus::WrongValue,
                RsuProblem::MibMismatch(String::new()),
            ),
            (
                ErrorStatus::AuthorizationError,
                RsuProblem::NotAuthorized(String::new()),
            ),
            (
                ErrorStatus::CommitFailed,
                RsuProblem::Refused(String::new()),
            ),
        ];
        for (status, want) in cases {
            let mut rsu = FakeRsu {
                fail: Some(status),
                ..FakeRsu::default()
            };
            let e = reconcile(&mut rsu, RULES, &[wanted(1)], &mut Owned::new()).unwrap_err();
            assert_eq!(e.reason(), want.reason(), "{status:?}: {e}");
        }
    }

    #[test]
    fn a_full_table_places_what_fits_and_says_what_did_not() {
        let mut rsu = FakeRsu::default();
        let mut owned = Owned::new();
        let w = [wanted(1), wanted(2), wanted(3)];
        let e = reconcile(&mut rsu, RULES, &w, &mut owned).unwrap_err();
        assert!(
            matches!(&e, RsuProblem::TableFull(m) if m.contains("1 message(s) not placed")),
            "{e}"
        );
        assert_eq!(owned.len(), 2);
        // Nothing to change next time but what cannot fit; the two placed rows are kept.
        let writes = rsu.counts.writes;
        assert!(reconcile(&mut rsu, RULES, &w[..2], &mut owned)
            .unwrap()
            .plan
            .is_converged());
        assert_eq!(rsu.counts.writes, writes);
    }

    #[test]
    fn a_row_rewritten_by_someone_else_is_no_longer_ours() {
        let mut rsu = FakeRsu::default();
        let mut owned = Owned::new();
        reconcile(&mut rsu, RULES, &[wanted(1)], &mut owned).unwrap();
        // Another manager rewrites the payload of our row 1.
        let mut payload = RsuMib::Ntcip1218.repeat_entry();
        payload.extend([7, 1]);
        rsu.objects.insert(payload, SnmpValue::Octets(vec![9, 9]));
        let r = reconcile(&mut rsu, RULES, &[wanted(2)], &mut owned).unwrap();
        assert_eq!(r.plan.foreign, [1]);
        assert_eq!(r.plan.create, [(2, 0)]);
    }
}
