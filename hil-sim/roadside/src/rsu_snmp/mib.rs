//! The RSU tables the roadside writes, as facts from NTCIP 1218 and the USDOT RSU 4.1
//! specification (object identifiers, column numbers and value encodings; no MIB text).
//!
//! - NTCIP 1218 `rsuMsgRepeatStatusTable` (store and repeat) and `rsuIFMStatusTable`
//!   (immediate forward), under `1.3.6.1.4.1.1206.4.2.18`;
//! - RSU 4.1 `rsuSRMStatusTable` (store and repeat on older units), under
//!   `1.0.15628.4.1`.

use super::dates::{date_and_time, rsu41_date};
use super::reconcile::{ColumnKind, WantedRow};
use super::session::SnmpValue;
use j2735::envelope::Psid;
use serde::Deserialize;

/// NTCIP 1218's root, `rsu`.
const NTCIP: [u64; 10] = [1, 3, 6, 1, 4, 1, 1206, 4, 2, 18];
/// The RSU 4.1 specification's `rsuMIB`.
const RSU41: [u64; 4] = [1, 0, 15628, 4];

fn under(root: &[u64], tail: &[u64]) -> Vec<u64> {
    root.iter().chain(tail).copied().collect()
}

/// Which MIB an RSU's store-and-repeat table follows.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
pub enum RsuMib {
    /// NTCIP 1218 (RSU 2020 and later firmware).
    #[serde(rename = "ntcip1218")]
    Ntcip1218,
    /// USDOT RSU specification 4.1 (older units).
    #[serde(rename = "rsu4.1")]
    Rsu41,
}

impl RsuMib {
    /// Its name as site files write it.
    pub const fn name(self) -> &'static str {
        match self {
            Self::Ntcip1218 => "ntcip1218",
            Self::Rsu41 => "rsu4.1",
        }
    }

    /// The store-and-repeat table's entry (`…Entry`): objects are `entry.column.index`.
    pub fn repeat_entry(self) -> Vec<u64> {
        match self {
            Self::Ntcip1218 => under(&NTCIP, &[3, 2, 1]),
            Self::Rsu41 => under(&RSU41, &[1, 4, 1]),
        }
    }

    /// The RowStatus column of the store-and-repeat table.
    pub const fn repeat_status_column(self) -> u32 {
        match self {
            Self::Ntcip1218 => 9,
            Self::Rsu41 => 11,
        }
    }

    /// The scalar holding how many store-and-repeat rows the RSU takes (NTCIP 1218's
    /// `maxRsuMsgRepeat`); RSU 4.1 has none.
    pub fn repeat_max_rows(self) -> Option<Vec<u64>> {
        match self {
            Self::Ntcip1218 => Some(under(&NTCIP, &[3, 1, 0])),
            Self::Rsu41 => None,
        }
    }

    /// The MIB's `rsuMibVersion` scalar (a probe: only one of the two answers).
    pub fn mib_version(self) -> Vec<u64> {
        match self {
            Self::Ntcip1218 => under(&NTCIP, &[13, 1, 0]),
            Self::Rsu41 => under(&RSU41, &[1, 17, 1, 0]),
        }
    }

    /// The MIB's `rsuFirmwareVersion` and `rsuID` scalars.
    pub fn identity(self) -> [Vec<u64>; 2] {
        match self {
            Self::Ntcip1218 => [under(&NTCIP, &[13, 2, 0]), under(&NTCIP, &[13, 4, 0])],
            Self::Rsu41 => [under(&RSU41, &[1, 17, 2, 0]), under(&RSU41, &[1, 17, 4, 0])],
        }
    }

    /// The columns of a store-and-repeat row holding `m` (RowStatus excluded), in the order
    /// deployed managers send them.
    pub fn repeat_row(self, m: &RepeatMessage) -> WantedRow {
        use ColumnKind::{Date, Exact};
        let int = |v: i64| SnmpValue::Integer(v);
        let octets = |v: &[u8]| SnmpValue::Octets(v.to_vec());
        let psid = octets(&p_encoded(m.psid));
        let columns = match self {
            Self::Ntcip1218 => vec![
                (2, psid, Exact),
                (3, int(m.channel.into()), Exact),
                (4, int(m.interval_ms.into()), Exact),
                (5, octets(&date_and_time(m.start_unix_ms)), Date),
                (6, octets(&date_and_time(m.stop_unix_ms)), Date),
                (7, octets(&m.payload), Exact),
                (8, int(1), Exact),
                (10, int(m.priority.into()), Exact),
                (11, octets(&[m.options()]), Exact),
            ],
            Self::Rsu41 => vec![
                (2, psid, Exact),
                (3, int(m.message_id.into()), Exact),
                (4, int(i64::from(m.alternating)), Exact),
                (5, int(m.channel.into()), Exact),
                (6, int(m.interval_ms.into()), Exact),
                (7, octets(&rsu41_date(m.start_unix_ms)), Date),
                (8, octets(&rsu41_date(m.stop_unix_ms)), Date),
                (9, octets(&m.payload), Exact),
                (10, int(1), Exact),
            ],
        };
        WantedRow {
            label: m.label.clone(),
            columns,
        }
    }
}

/// NTCIP 1218 `rsuIFMStatusTable` (immediate forward) entry.
pub fn ifm_entry() -> Vec<u64> {
    under(&NTCIP, &[4, 2, 1])
}

/// NTCIP 1218 `maxRsuIFMs`.
pub fn ifm_max_rows() -> Vec<u64> {
    under(&NTCIP, &[4, 1, 0])
}

/// The RowStatus column of `rsuIFMStatusTable`.
pub const IFM_STATUS_COLUMN: u32 = 5;

/// The columns of an immediate-forward row sending `m` (RowStatus excluded).
pub fn ifm_row(m: &RepeatMessage) -> WantedRow {
    use ColumnKind::Exact;
    WantedRow {
        label: m.label.clone(),
        columns: vec![
            (2, SnmpValue::Octets(p_encoded(m.psid)), Exact),
            (3, SnmpValue::Integer(m.channel.into()), Exact),
            (4, SnmpValue::Integer(1), Exact),
            (6, SnmpValue::Integer(m.priority.into()), Exact),
            (7, SnmpValue::Octets(vec![m.options()]), Exact),
            (8, SnmpValue::Octets(m.payload.clone()), Exact),
        ],
    }
}

/// RowStatus values the roadside writes (SNMPv2-TC).
pub mod row_status {
    /// createAndGo: create the row active in one SET.
    pub const CREATE_AND_GO: i64 = 4;
    /// destroy.
    pub const DESTROY: i64 = 6;
}

/// `rsuMsgRepeatOptions` / `rsuIFMOptions` bit 0 (0x80): the RSU processes IEEE 1609.2
/// (signs the payload); 0x00: the payload is sent as it is (already signed, or unsecured).
pub const OPTION_RSU_SIGNS: u8 = 0x80;

/// A message to deposit on RSUs.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct RepeatMessage {
    /// A name for messages (`MAP`, `TIM <packetID>`).
    pub label: String,
    /// PSID (the integer; written p-encoded).
    pub psid: Psid,
    /// J2735 `messageId` (RSU 4.1's `rsuSRMDsrcMsgId`).
    pub message_id: u16,
    /// The payload: a UPER MessageFrame, or an IEEE 1609.2 SPDU already signed.
    pub payload: Vec<u8>,
    /// Radio channel (172-184 DSRC, 183 C-V2X).
    pub channel: u8,
    /// Repeat interval, milliseconds.
    pub interval_ms: u32,
    /// Delivery window, Unix ms.
    pub start_unix_ms: u64,
    /// End of the delivery window, Unix ms.
    pub stop_unix_ms: u64,
    /// NTCIP 1218 priority, 0-63.
    pub priority: u8,
    /// The RSU signs the payload (options 0x80) rather than sending it as it is.
    pub rsu_signs: bool,
    /// RSU 4.1 tx mode alternating (1) rather than continuous (0).
    pub alternating: bool,
}

impl RepeatMessage {
    /// The options octet.
    pub const fn options(&self) -> u8 {
        if self.rsu_signs {
            OPTION_RSU_SIGNS
        } else {
            0
        }
    }
}

/// The PSID's p-encoded octets (IEEE 1609.12): TIM 131 is `80 03`, MAP 2113687 `e0 00 00 17`.
pub fn p_encoded(psid: Psid) -> Vec<u8> {
    psid.p_encoded()
        .map(|(octets, len)| octets[..len].to_vec())
        .unwrap_or_default()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn psids_are_written_p_encoded_as_deployed_rsus_take_them() {
        assert_eq!(p_encoded(Psid(131)), [0x80, 0x03]);
        assert_eq!(p_encoded(Psid(0x20)), [0x20]);
        assert_eq!(p_encoded(Psid(0x0020_408e)), [0xe0, 0x00, 0x00, 0x0e]);
    }

    #[test]
    fn oids_are_the_standards() {
        let dotted = |a: Vec<u64>| a.iter().map(u64::to_string).collect::<Vec<_>>().join(".");
        assert_eq!(
            dotted(RsuMib::Ntcip1218.repeat_entry()),
            "1.3.6.1.4.1.1206.4.2.18.3.2.1"
        );
        assert_eq!(dotted(RsuMib::Rsu41.repeat_entry()), "1.0.15628.4.1.4.1");
        assert_eq!(dotted(ifm_entry()), "1.3.6.1.4.1.1206.4.2.18.4.2.1");
        assert_eq!(
            dotted(RsuMib::Ntcip1218.mib_version()),
            "1.3.6.1.4.1.1206.4.2.18.13.1.0"
        );
        assert_eq!(dotted(RsuMib::Rsu41.mib_version()), "1.0.15628.4.1.17.1.0");
    }
}
