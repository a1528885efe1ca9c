//! Reconciliation of one RSU's store-and-repeat table with the messages the site wants on
//! it: a pure plan from what was read, so that the same rules serve the daemon's polls, the
//! `roadside rsu` commands and the tests.
//!
//! Rules:
//! - a wanted message already in an active row whose written columns all equal ours is
//!   kept (and that row becomes ours, whoever created it);
//! - a row of ours that no wanted message matches (the message changed, ended or left the
//!   site) is destroyed;
//! - a wanted message with no matching row is created at the lowest index no row uses
//!   (indices freed by this plan's destroys included);
//! - a row that is not ours is left alone unless the RSU's entry says the roadside manages
//!   the whole table;
//! - when no index is free, the message is reported as not placed (table full).

use super::dates::unix_ms_of;
use super::session::SnmpValue;
use std::collections::{BTreeMap, BTreeSet};

/// How a column's values compare.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ColumnKind {
    /// Equal when the values are equal.
    Exact,
    /// A date: equal when both are the same instant (8, 11 or 6 octets).
    Date,
}

/// A row's columns by column number.
pub type Columns = BTreeMap<u32, SnmpValue>;

/// One row of the table as read: its index and columns.
pub type Rows = BTreeMap<u32, Columns>;

/// A message as it should stand in the table: the columns the roadside writes when it
/// creates the row (RowStatus excluded), and how each compares.
#[derive(Debug, Clone, PartialEq)]
pub struct WantedRow {
    /// A name for messages and the status table (e.g. `TIM 0x1c2f…`).
    pub label: String,
    /// Column number, value and how it compares.
    pub columns: Vec<(u32, SnmpValue, ColumnKind)>,
}

impl WantedRow {
    /// Whether the row `have` holds exactly this message.
    pub fn matches(&self, have: &Columns) -> bool {
        self.columns.iter().all(|(col, want, kind)| {
            let Some(got) = have.get(col) else {
                return false;
            };
            match (kind, want, got) {
                (ColumnKind::Date, SnmpValue::Octets(a), SnmpValue::Octets(b)) => {
                    unix_ms_of(a).is_some() && unix_ms_of(a) == unix_ms_of(b)
                }
                _ => want == got,
            }
        })
    }
}

/// What the table's RowStatus column says (SNMPv2-TC).
pub const ROW_ACTIVE: i64 = 1;

/// What to do to one RSU's table.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Plan {
    /// (wanted message, row index) already on the RSU.
    pub keep: Vec<(usize, u32)>,
    /// Row indices to destroy.
    pub destroy: Vec<u32>,
    /// (row index, wanted message) to create.
    pub create: Vec<(u32, usize)>,
    /// Wanted messages for which no index is free.
    pub no_room: Vec<usize>,
    /// Rows left alone: not ours.
    pub foreign: Vec<u32>,
}

impl Plan {
    /// Whether the table already holds what is wanted and nothing of ours is stale.
    pub fn is_converged(&self) -> bool {
        self.destroy.is_empty() && self.create.is_empty() && self.no_room.is_empty()
    }
}

/// The plan for `rows` (as read) given the `wanted` messages. `ours` says whether the row
/// at an index was placed by the roadside; `status_column` is the RowStatus column;
/// indices run from 1 to `max_index`; `manage_all` makes every row the roadside's.
pub fn plan(
    wanted: &[WantedRow],
    rows: &Rows,
    ours: impl Fn(u32, &Columns) -> bool,
    status_column: u32,
    max_index: u32,
    manage_all: bool,
) -> Plan {
    let mut out = Plan::default();
    let mut matched: BTreeSet<u32> = BTreeSet::new();
    let mut unplaced = Vec::new();
    for (i, w) in wanted.iter().enumerate() {
        let hit = rows.iter().find(|(index, cols)| {
            !matched.contains(index)
                && cols.get(&status_column) == Some(&SnmpValue::Integer(ROW_ACTIVE))
                && w.matches(cols)
        });
        match hit {
            Some((index, _)) => {
                matched.insert(*index);
                out.keep.push((i, *index));
            }
            None => unplaced.push(i),
        }
    }
    for (index, cols) in rows {
        if matched.contains(index) {
            continue;
        }
        if manage_all || ours(*index, cols) {
            out.destroy.push(*index);
        } else {
            out.foreign.push(*index);
        }
    }
    let mut used: BTreeSet<u32> = rows.keys().copied().collect();
    for index in &out.destroy {
        used.remove(index);
    }
    let mut free = (1..=max_index).filter(|i| !used.contains(i));
    for i in unplaced {
        match free.next() {
            Some(index) => out.create.push((index, i)),
            None => out.no_room.push(i),
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    const STATUS: u32 = 9;

    fn wanted(label: &str, payload: &[u8]) -> WantedRow {
        WantedRow {
            label: label.into(),
            columns: vec![
                (2, SnmpValue::Octets(vec![0x83]), ColumnKind::Exact),
                (
                    5,
                    SnmpValue::Octets(vec![0x07, 0xea, 12, 4, 13, 0, 0, 0]),
                    ColumnKind::Date,
                ),
                (7, SnmpValue::Octets(payload.to_vec()), ColumnKind::Exact),
            ],
        }
    }

    fn row(payload: &[u8], status: i64) -> Columns {
        BTreeMap::from([
            (2, SnmpValue::Octets(vec![0x83])),
            // The same instant as 6 octets: equal.
            (5, SnmpValue::Octets(vec![0x07, 0xea, 12, 4, 13, 0])),
            (7, SnmpValue::Octets(payload.to_vec())),
            (STATUS, SnmpValue::Integer(status)),
        ])
    }

    #[test]
    fn an_empty_table_gets_every_message_from_index_1() {
        let w = [wanted("MAP", b"m"), wanted("TIM", b"t")];
        let p = plan(&w, &Rows::new(), |_, _| false, STATUS, 8, false);
        assert_eq!(p.create, vec![(1, 0), (2, 1)]);
        assert!(p.keep.is_empty() && p.destroy.is_empty() && !p.is_converged());
    }

    #[test]
    fn a_converged_table_needs_nothing_and_foreign_rows_stay() {
        let w = [wanted("MAP", b"m"), wanted("TIM", b"t")];
        let rows = Rows::from([(3, row(b"t", 1)), (4, row(b"x", 1)), (7, row(b"m", 1))]);
        let p = plan(&w, &rows, |_, _| false, STATUS, 8, false);
        assert_eq!(p.keep, vec![(0, 7), (1, 3)]);
        assert_eq!(p.foreign, vec![4]);
        assert!(p.is_converged());
    }

    #[test]
    fn a_changed_message_replaces_its_row_at_the_freed_index() {
        let w = [wanted("TIM", b"new")];
        let rows = Rows::from([(1, row(b"old", 1)), (2, row(b"x", 1))]);
        let p = plan(&w, &rows, |i, _| i == 1, STATUS, 8, false);
        assert_eq!(p.destroy, vec![1]);
        assert_eq!(p.create, vec![(1, 0)]);
        assert_eq!(p.foreign, vec![2]);
    }

    #[test]
    fn an_inactive_row_does_not_count_and_a_full_table_is_reported() {
        let w = [wanted("TIM", b"t"), wanted("MAP", b"m")];
        let rows = Rows::from([(1, row(b"t", 2)), (2, row(b"x", 1))]);
        let p = plan(&w, &rows, |_, _| false, STATUS, 2, false);
        assert!(p.keep.is_empty());
        assert_eq!(p.no_room, vec![0, 1]);
        let all = plan(&w, &rows, |_, _| false, STATUS, 2, true);
        assert_eq!(all.destroy, vec![1, 2]);
        assert_eq!(all.create, vec![(1, 0), (2, 1)]);
    }
}
