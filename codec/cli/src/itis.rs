//! Names of ITIS codes for the `info` summary: the phrases of the codes seen in deployed
//! work-zone TIMs, the numbers 12544 + N, and the ITIS enumerations of the generated code.

use j2735::msg::itis::VehicleGroupAffected;
use j2735::msg::itis::{GenericLocations, IncidentResponseEquipment, ResponderGroupAffected};

/// Codes that deployed work-zone TIMs use (see docs/domain.md).
const WORK_ZONE_CODES: [(u16, &str); 8] = [
    (268, "speed limit"),
    (769, "closed"),
    (771, "closed ahead"),
    (1025, "road construction"),
    (6952, "workers"),
    (8195, "left lane"),
    (8196, "right lane"),
    (8720, "mph"),
];

/// First ITIS code of the small numbers (12544 + N is the number N, N < 256).
const NUMBER_BASE: u16 = 12544;

/// A short name of ITIS code `code`, when known.
pub fn name(code: u16) -> Option<String> {
    if let Some((_, text)) = WORK_ZONE_CODES.iter().find(|(c, _)| *c == code) {
        return Some((*text).to_string());
    }
    if (NUMBER_BASE..NUMBER_BASE + 256).contains(&code) {
        return Some(format!("number {}", code - NUMBER_BASE));
    }
    enumerated(i64::from(code)).map(str::to_string)
}

/// The identifier of `code` in one of the ITIS enumerations of J2735 2020.
fn enumerated(code: i64) -> Option<&'static str> {
    let generic = GenericLocations::ALL
        .iter()
        .find(|v| v.number() == Some(code));
    if let Some(v) = generic {
        return Some(v.identifier());
    }
    let vehicles = VehicleGroupAffected::ALL
        .iter()
        .find(|v| v.number() == Some(code));
    if let Some(v) = vehicles {
        return Some(v.identifier());
    }
    let responders = ResponderGroupAffected::ALL
        .iter()
        .find(|v| v.number() == Some(code));
    if let Some(v) = responders {
        return Some(v.identifier());
    }
    IncidentResponseEquipment::ALL
        .iter()
        .find(|v| v.number() == Some(code))
        .map(|v| v.identifier())
}

/// `1025 (road construction)`, or the bare number when the name is unknown.
pub fn describe(code: u16) -> String {
    match name(code) {
        Some(text) => format!("{code} ({text})"),
        None => code.to_string(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_of_work_zone_codes() {
        assert_eq!(describe(1025), "1025 (road construction)");
        assert_eq!(describe(12569), "12569 (number 25)");
        assert_eq!(describe(7941), "7941 (in-road-construction-area)");
        assert_eq!(describe(3), "3");
    }
}
