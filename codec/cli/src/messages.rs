//! The J2735 2020 messages by `messageId`: their ASN.1 type and the short name RSU records and
//! logs use (both from the codec's generated table, [`j2735::msg::message_frame::MESSAGE_NAMES`]),
//! and the PSID they are usually sent with.

use j2735::envelope::Psid;
use j2735::msg::message_frame::{MessageName, MESSAGE_NAMES};

/// One message of the MessageFrame object set.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Message {
    /// `messageId` (DSRCmsgID).
    pub id: u16,
    /// Short name, as in RSU `Type=` values (`MAP`, `TIM`).
    pub short: &'static str,
    /// The ASN.1 type of the value.
    pub type_name: &'static str,
    /// The PSID it is usually sent with, where the project knows one.
    pub psid: Option<Psid>,
}

/// The PSIDs RSU records forward each message with, by `messageId` (SAE J2735 / IEEE
/// 1609.12 assignments; MAP goes with SPaT's in RSU records).
const PSIDS: [(u16, Psid); 5] = [
    (18, Psid::SPAT),
    (19, Psid::SPAT),
    (20, Psid::BSM),
    (31, Psid::TIM),
    (32, Psid::PSM),
];

fn with_psid(m: &MessageName) -> Message {
    Message {
        id: m.id,
        short: m.short,
        type_name: m.type_name,
        psid: PSIDS.iter().find(|(id, _)| *id == m.id).map(|(_, p)| *p),
    }
}

/// The message with `messageId` `id`, when J2735 2020 has one.
pub fn by_id(id: u16) -> Option<Message> {
    MESSAGE_NAMES.iter().find(|m| m.id == id).map(with_psid)
}

/// The message whose short name is `short` (any letter case; `SPaT` too).
pub fn by_short_name(short: &str) -> Option<Message> {
    MESSAGE_NAMES
        .iter()
        .find(|m| m.short.eq_ignore_ascii_case(short))
        .map(with_psid)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lookups_agree() {
        assert_eq!(by_id(31).unwrap().short, "TIM");
        assert_eq!(by_id(18).unwrap().psid, Some(Psid::SPAT));
        assert_eq!(by_id(245).unwrap().type_name, "TestMessage05");
        assert_eq!(by_id(33), None);
        assert_eq!(by_id(256), None);
        assert_eq!(by_short_name("SPaT").unwrap().id, 19);
        assert_eq!(by_short_name("test15").unwrap().id, 255);
        assert_eq!(by_short_name("RSM"), None);
    }
}
