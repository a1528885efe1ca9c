//! The test RSU's tables as an RSU keeps them: NTCIP 1218 store-and-repeat and
//! immediate-forward rows, RSU 4.1 store-and-repeat rows, with RowStatus semantics.
//!
//! The object identifiers and columns are written here from the standards' facts on their
//! own, not taken from the roadside's `rsu_snmp::mib`: the test RSU is a second reading of
//! the MIBs, so a mistake in one shows as a disagreement.

use std::collections::BTreeMap;

/// A value as the tables hold it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Val {
    /// INTEGER.
    Int(i64),
    /// OCTET STRING (DisplayString too).
    Octets(Vec<u8>),
}

/// A column's type and rules.
#[derive(Debug, Clone, Copy)]
pub struct ColumnSpec {
    /// Column number.
    pub column: u32,
    /// Integer range, or octet-string length range.
    pub kind: Kind,
    /// Needed before createAndGo (else the row's default is used).
    pub mandatory: bool,
}

/// Column types.
#[derive(Debug, Clone, Copy)]
pub enum Kind {
    /// INTEGER in `min..=max`, default.
    Int(i64, i64, i64),
    /// OCTET STRING of `min..=max` octets.
    Octets(usize, usize),
    /// A date: 8 or 11 octets `DateAndTime`, or RSU 4.1's 6 octets.
    Date,
    /// RowStatus.
    Status,
}

/// Which table.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub enum TableId {
    /// NTCIP 1218 `rsuMsgRepeatStatusTable`.
    MsgRepeat,
    /// NTCIP 1218 `rsuIFMStatusTable`.
    Ifm,
    /// RSU 4.1 `rsuSRMStatusTable`.
    Srm,
}

const NTCIP_ROOT: &[u64] = &[1, 3, 6, 1, 4, 1, 1206, 4, 2, 18];
const RSU41_ROOT: &[u64] = &[1, 0, 15628, 4, 1];

impl TableId {
    /// The entry OID, relative to the MIB's root, and the root.
    pub fn entry(self) -> Vec<u64> {
        let (root, tail): (&[u64], &[u64]) = match self {
            Self::MsgRepeat => (NTCIP_ROOT, &[3, 2, 1]),
            Self::Ifm => (NTCIP_ROOT, &[4, 2, 1]),
            Self::Srm => (RSU41_ROOT, &[4, 1]),
        };
        root.iter().chain(tail).copied().collect()
    }

    /// The columns (the index column is not-accessible and not served).
    pub fn columns(self) -> &'static [ColumnSpec] {
        use Kind::*;
        const fn c(column: u32, kind: Kind, mandatory: bool) -> ColumnSpec {
            ColumnSpec {
                column,
                kind,
                mandatory,
            }
        }
        const REPEAT: &[ColumnSpec] = &[
            c(2, Octets(1, 4), true),
            c(3, Int(0, 255, 183), false),
            c(4, Int(1, 2_147_483_647, 1000), true),
            c(5, Date, true),
            c(6, Date, true),
            c(7, Octets(0, 2302), true),
            c(8, Int(0, 1, 0), false),
            c(9, Status, false),
            c(10, Int(0, 63, 6), false),
            c(11, Octets(1, 1), false),
        ];
        const IFM: &[ColumnSpec] = &[
            c(2, Octets(1, 4), true),
            c(3, Int(0, 255, 183), false),
            c(4, Int(0, 1, 0), false),
            c(5, Status, false),
            c(6, Int(0, 63, 6), false),
            c(7, Octets(1, 1), false),
            c(8, Octets(0, 2302), false),
        ];
        const SRM: &[ColumnSpec] = &[
            c(2, Octets(1, 4), true),
            c(3, Int(0, 32767, 31), true),
            c(4, Int(0, 1, 0), false),
            c(5, Int(172, 184, 178), false),
            c(6, Int(1, 2_147_483_647, 1000), true),
            c(7, Date, true),
            c(8, Date, true),
            c(9, Octets(0, 2302), true),
            c(10, Int(0, 1, 0), false),
            c(11, Status, false),
        ];
        match self {
            Self::MsgRepeat => REPEAT,
            Self::Ifm => IFM,
            Self::Srm => SRM,
        }
    }

    /// The RowStatus column.
    pub fn status_column(self) -> u32 {
        self.columns()
            .iter()
            .find(|c| matches!(c.kind, Kind::Status))
            .map(|c| c.column)
            .expect("every table has a RowStatus")
    }
}

/// Why a SET is refused, as pass_persist spells the SNMP error.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SetError {
    /// wrongType.
    WrongType,
    /// wrongLength.
    WrongLength,
    /// wrongValue.
    WrongValue,
    /// inconsistentValue.
    InconsistentValue,
    /// genErr: what deployed RSUs answer to createAndGo on an index in use.
    GenErr,
    /// notWritable.
    NotWritable,
    /// resourceUnavailable: the table is full.
    ResourceUnavailable,
    /// noCreation: index out of range.
    NoCreation,
}

impl SetError {
    /// The pass_persist reply.
    pub fn reply(self) -> &'static str {
        match self {
            Self::WrongType => "wrong-type",
            Self::WrongLength => "wrong-length",
            Self::WrongValue => "wrong-value",
            Self::InconsistentValue => "inconsistent-value",
            Self::GenErr => "gen-error",
            Self::NotWritable => "not-writable",
            Self::ResourceUnavailable => "resource-unavailable",
            Self::NoCreation => "no-creation",
        }
    }
}

/// The longest OCTET STRING value the test RSU takes (pass_persist's line limit).
pub const PASS_PERSIST_MAX_OCTETS: usize = 1365;

/// RowStatus values.
const ACTIVE: i64 = 1;
const NOT_IN_SERVICE: i64 = 2;
const CREATE_AND_GO: i64 = 4;
const CREATE_AND_WAIT: i64 = 5;
const DESTROY: i64 = 6;

/// One row: its columns (RowStatus included once created).
pub type Row = BTreeMap<u32, Val>;

/// One table: rows, and values set for an index within the SET request being applied
/// (pass_persist hands the request's varbinds over one by one).
#[derive(Debug, Clone)]
pub struct Table {
    /// Which table.
    pub id: TableId,
    /// Rows by index.
    pub rows: BTreeMap<u32, Row>,
    /// Values set in the current request, by index (applied on createAndGo, or to the
    /// existing row when the request ends).
    pending: BTreeMap<u32, Row>,
    /// Indices whose RowStatus set failed in the current request: its other values are
    /// dropped.
    failed: Vec<u32>,
    /// The largest index (the `max…` scalar).
    pub max_rows: u32,
}

impl Table {
    /// An empty table of `max_rows` rows.
    pub fn new(id: TableId, max_rows: u32) -> Self {
        Self {
            id,
            rows: BTreeMap::new(),
            pending: BTreeMap::new(),
            failed: Vec::new(),
            max_rows,
        }
    }

    /// A SET of `column` of row `index` to `value`.
    ///
    /// # Errors
    ///
    /// The SNMP error the RSU answers.
    pub fn set(&mut self, column: u32, index: u32, value: Val) -> Result<(), SetError> {
        if index == 0 || index > self.max_rows {
            return Err(SetError::NoCreation);
        }
        let spec = self
            .id
            .columns()
            .iter()
            .find(|c| c.column == column)
            .ok_or(SetError::NotWritable)?;
        check(spec.kind, &value)?;
        if self.failed.contains(&index) {
            return Ok(());
        }
        if matches!(spec.kind, Kind::Status) {
            let Val::Int(status) = value else {
                return Err(SetError::WrongType);
            };
            return self.set_status(index, status).inspect_err(|_| {
                self.pending.remove(&index);
                self.failed.push(index);
            });
        }
        self.pending.entry(index).or_default().insert(column, value);
        Ok(())
    }

    fn set_status(&mut self, index: u32, status: i64) -> Result<(), SetError> {
        let exists = self.rows.contains_key(&index);
        match status {
            CREATE_AND_GO | CREATE_AND_WAIT => {
                if exists {
                    return Err(SetError::GenErr);
                }
                let given = self.pending.remove(&index).unwrap_or_default();
                let mut row = Row::new();
                for spec in self.id.columns() {
                    match (given.get(&spec.column), spec.kind) {
                        (Some(v), _) => {
                            row.insert(spec.column, v.clone());
                        }
                        (None, _) if spec.mandatory => return Err(SetError::InconsistentValue),
                        (None, Kind::Int(_, _, default)) => {
                            row.insert(spec.column, Val::Int(default));
                        }
                        (None, Kind::Octets(1, 1)) => {
                            row.insert(spec.column, Val::Octets(vec![0]));
                        }
                        (None, _) => {}
                    }
                }
                let state = if status == CREATE_AND_GO {
                    ACTIVE
                } else {
                    NOT_IN_SERVICE
                };
                row.insert(self.id.status_column(), Val::Int(state));
                self.rows.insert(index, row);
                Ok(())
            }
            DESTROY => {
                self.rows.remove(&index);
                self.pending.remove(&index);
                Ok(())
            }
            ACTIVE | NOT_IN_SERVICE if exists => {
                let row = self.rows.get_mut(&index).expect("exists");
                row.insert(self.id.status_column(), Val::Int(status));
                Ok(())
            }
            ACTIVE | NOT_IN_SERVICE => Err(SetError::InconsistentValue),
            _ => Err(SetError::WrongValue),
        }
    }

    /// The SET request ended: values set on existing rows are applied (a manager changing
    /// a row in place); those of rows never created are dropped. Returns the indices of
    /// rows changed.
    pub fn end_request(&mut self) -> Vec<u32> {
        self.failed.clear();
        let mut changed = Vec::new();
        for (index, values) in std::mem::take(&mut self.pending) {
            if let Some(row) = self.rows.get_mut(&index) {
                row.extend(values);
                changed.push(index);
            }
        }
        changed
    }

    /// Whether the row at `index` is active.
    pub fn is_active(&self, index: u32) -> bool {
        self.rows
            .get(&index)
            .and_then(|r| r.get(&self.id.status_column()))
            == Some(&Val::Int(ACTIVE))
    }
}

/// Whether `value` fits the column's type.
fn check(kind: Kind, value: &Val) -> Result<(), SetError> {
    match (kind, value) {
        (Kind::Int(min, max, _), Val::Int(v)) => {
            if (min..=max).contains(v) {
                Ok(())
            } else {
                Err(SetError::WrongValue)
            }
        }
        (Kind::Status, Val::Int(v)) => {
            if (1..=6).contains(v) && *v != 3 {
                Ok(())
            } else {
                Err(SetError::WrongValue)
            }
        }
        (Kind::Octets(min, max), Val::Octets(o)) => {
            // net-snmp's pass_persist carries at most about 1,365 octets in one value (its
            // 4 KiB line of hex): a longer one would come back cut, so it is refused.
            if (min..=max.min(PASS_PERSIST_MAX_OCTETS)).contains(&o.len()) {
                Ok(())
            } else {
                Err(SetError::WrongLength)
            }
        }
        (Kind::Date, Val::Octets(o)) => match o.len() {
            6 | 8 | 11 if date_ok(o) => Ok(()),
            6 | 8 | 11 => Err(SetError::WrongValue),
            _ => Err(SetError::WrongLength),
        },
        _ => Err(SetError::WrongType),
    }
}

/// Month, day, hour and minute in range.
fn date_ok(o: &[u8]) -> bool {
    (1..=12).contains(&o[2]) && (1..=31).contains(&o[3]) && o[4] < 24 && o[5] < 60
}

/// Unix ms of a table date (UTC; an 11-octet zone is applied), `None` if invalid.
pub fn date_unix_ms(o: &[u8]) -> Option<u64> {
    if !matches!(o.len(), 6 | 8 | 11) || !date_ok(o) {
        return None;
    }
    let year = i64::from(u16::from_be_bytes([o[0], o[1]]));
    let (month, day) = (i64::from(o[2]), i64::from(o[3]));
    // Days from the civil date (proleptic Gregorian), Howard Hinnant's algorithm.
    let y = if month <= 2 { year - 1 } else { year };
    let era = y.div_euclid(400);
    let yoe = y - era * 400;
    let mp = (month + 9) % 12;
    let doy = (153 * mp + 2) / 5 + day - 1;
    let doe = yoe * 365 + yoe / 4 - yoe / 100 + doy;
    let days = era * 146_097 + doe - 719_468;
    let mut s = days * 86_400 + i64::from(o[4]) * 3600 + i64::from(o[5]) * 60;
    let mut ms = 0;
    if o.len() >= 8 {
        s += i64::from(o[6]);
        ms = i64::from(o[7]) * 100;
    }
    if o.len() == 11 {
        let off = (i64::from(o[9]) * 60 + i64::from(o[10])) * 60;
        s += if o[8] == b'-' { off } else { -off };
    }
    u64::try_from(s * 1000 + ms).ok()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn create(t: &mut Table, index: u32, payload: &[u8]) -> Result<(), SetError> {
        t.set(2, index, Val::Octets(vec![0x80, 0x03]))?;
        t.set(4, index, Val::Int(100))?;
        t.set(5, index, Val::Octets(vec![7, 234, 12, 4, 13, 0, 0, 0]))?;
        t.set(6, index, Val::Octets(vec![7, 234, 12, 4, 14, 0, 0, 0]))?;
        t.set(7, index, Val::Octets(payload.to_vec()))?;
        t.set(8, index, Val::Int(1))?;
        t.set(9, index, Val::Int(CREATE_AND_GO))?;
        t.set(11, index, Val::Octets(vec![0x80]))?;
        t.end_request();
        Ok(())
    }

    #[test]
    fn create_and_go_makes_an_active_row_with_defaults_and_later_columns() {
        let mut t = Table::new(TableId::MsgRepeat, 8);
        create(&mut t, 3, b"tim").unwrap();
        assert!(t.is_active(3));
        let row = &t.rows[&3];
        assert_eq!(row[&10], Val::Int(6));
        assert_eq!(row[&11], Val::Octets(vec![0x80]));
        assert_eq!(row[&3], Val::Int(183));
    }

    #[test]
    fn an_index_in_use_is_gen_err_and_leaves_the_row_alone() {
        let mut t = Table::new(TableId::MsgRepeat, 8);
        create(&mut t, 1, b"first").unwrap();
        assert_eq!(create(&mut t, 1, b"second"), Err(SetError::GenErr));
        t.set(11, 1, Val::Octets(vec![0])).unwrap();
        t.end_request();
        assert_eq!(t.rows[&1][&7], Val::Octets(b"first".to_vec()));
        assert_eq!(t.rows[&1][&11], Val::Octets(vec![0x80]));
    }

    #[test]
    fn refuses_what_the_mib_does_not_take() {
        let mut t = Table::new(TableId::MsgRepeat, 8);
        assert_eq!(
            t.set(9, 1, Val::Int(CREATE_AND_GO)),
            Err(SetError::InconsistentValue)
        );
        assert_eq!(
            t.set(2, 1, Val::Octets(vec![1; 5])),
            Err(SetError::WrongLength)
        );
        assert_eq!(t.set(4, 1, Val::Octets(vec![1])), Err(SetError::WrongType));
        assert_eq!(
            t.set(5, 1, Val::Octets(vec![7, 234, 13, 1, 0, 0])),
            Err(SetError::WrongValue)
        );
        assert_eq!(
            t.set(2, 9, Val::Octets(vec![0x20])),
            Err(SetError::NoCreation)
        );
        assert_eq!(t.set(1, 1, Val::Int(1)), Err(SetError::NotWritable));
        assert_eq!(t.set(9, 1, Val::Int(3)), Err(SetError::WrongValue));
    }

    #[test]
    fn destroy_removes_the_row() {
        let mut t = Table::new(TableId::MsgRepeat, 8);
        create(&mut t, 2, b"x").unwrap();
        t.set(9, 2, Val::Int(DESTROY)).unwrap();
        t.end_request();
        assert!(t.rows.is_empty());
    }

    #[test]
    fn dates_in_every_form() {
        // 2026-12-04T13:45:27.3Z
        let t = 1_796_391_927_300;
        assert_eq!(date_unix_ms(&[7, 234, 12, 4, 13, 45, 27, 3]), Some(t));
        assert_eq!(date_unix_ms(&[7, 234, 12, 4, 13, 45]), Some(t - 27_300));
        assert_eq!(
            date_unix_ms(&[7, 234, 12, 4, 8, 45, 27, 3, b'-', 5, 0]),
            Some(t)
        );
    }
}
