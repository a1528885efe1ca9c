//! The J2735 2020 messages by `messageId`: their ASN.1 type, the short name RSU records and
//! logs use, and the PSID they are usually sent with.

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
    pub psid: Option<u32>,
}

const fn message(id: u16, short: &'static str, type_name: &'static str) -> Message {
    Message {
        id,
        short,
        type_name,
        psid: None,
    }
}

const fn with_psid(id: u16, short: &'static str, type_name: &'static str, psid: u32) -> Message {
    Message {
        id,
        short,
        type_name,
        psid: Some(psid),
    }
}

/// Every message of J2735 2020 but the test messages.
const MESSAGES: [Message; 15] = [
    with_psid(18, "MAP", "MapData", 0x8002),
    with_psid(19, "SPAT", "SPAT", 0x8002),
    with_psid(20, "BSM", "BasicSafetyMessage", 0x20),
    message(21, "CSR", "CommonSafetyRequest"),
    message(22, "EVA", "EmergencyVehicleAlert"),
    message(23, "ICA", "IntersectionCollision"),
    message(24, "NMEA", "NMEAcorrections"),
    message(25, "PDM", "ProbeDataManagement"),
    message(26, "PVD", "ProbeVehicleData"),
    message(27, "RSA", "RoadSideAlert"),
    message(28, "RTCM", "RTCMcorrections"),
    message(29, "SRM", "SignalRequestMessage"),
    message(30, "SSM", "SignalStatusMessage"),
    with_psid(31, "TIM", "TravelerInformation", 0x8003),
    with_psid(32, "PSM", "PersonalSafetyMessage", 0x27),
];

/// Short names of the test messages 240..=255.
const TEST_SHORT: [&str; 16] = [
    "TEST00", "TEST01", "TEST02", "TEST03", "TEST04", "TEST05", "TEST06", "TEST07", "TEST08",
    "TEST09", "TEST10", "TEST11", "TEST12", "TEST13", "TEST14", "TEST15",
];

/// Types of the test messages 240..=255.
const TEST_TYPES: [&str; 16] = [
    "TestMessage00",
    "TestMessage01",
    "TestMessage02",
    "TestMessage03",
    "TestMessage04",
    "TestMessage05",
    "TestMessage06",
    "TestMessage07",
    "TestMessage08",
    "TestMessage09",
    "TestMessage10",
    "TestMessage11",
    "TestMessage12",
    "TestMessage13",
    "TestMessage14",
    "TestMessage15",
];

/// The message with `messageId` `id`, when J2735 2020 has one.
pub fn by_id(id: u16) -> Option<Message> {
    if let Some(m) = MESSAGES.iter().find(|m| m.id == id) {
        return Some(*m);
    }
    let index = usize::from(id.checked_sub(240)?);
    Some(message(id, TEST_SHORT.get(index)?, TEST_TYPES.get(index)?))
}

/// The message whose short name is `short` (any letter case; `SPaT` too).
pub fn by_short_name(short: &str) -> Option<Message> {
    (18..=32)
        .chain(240..=255)
        .filter_map(by_id)
        .find(|m| m.short.eq_ignore_ascii_case(short))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lookups_agree() {
        assert_eq!(by_id(31).unwrap().short, "TIM");
        assert_eq!(by_id(18).unwrap().psid, Some(0x8002));
        assert_eq!(by_id(245).unwrap().type_name, "TestMessage05");
        assert_eq!(by_id(33), None);
        assert_eq!(by_id(256), None);
        assert_eq!(by_short_name("SPaT").unwrap().id, 19);
        assert_eq!(by_short_name("test15").unwrap().id, 255);
        assert_eq!(by_short_name("RSM"), None);
    }
}
