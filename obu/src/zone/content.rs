//! TIM content: ITIS codes and text parsed into what the alerts need.

use heapless::Vec;

use crate::capacity::MAX_ITIS;
use crate::lane::Speed;

#[cfg(feature = "serde")]
use serde::{Deserialize, Serialize};

/// ITIS "speed limit".
pub const ITIS_SPEED_LIMIT: u16 = 268;
/// ITIS numbers: `12544 + N` is the number N.
pub const ITIS_NUMBER_BASE: u16 = 12544;
/// Largest ITIS number code accepted (N up to 511).
pub const ITIS_NUMBER_MAX: u16 = ITIS_NUMBER_BASE + 511;
/// ITIS "mph" (seen in deployed TIMs).
pub const ITIS_MPH: u16 = 8720;
/// ITIS "km/h". Assumed to follow "mph" in the units table; not confirmed against
/// the ITIS list (the domain notes only name 8720), text "km/h" is parsed as well.
pub const ITIS_KMH: u16 = 8721;
/// ITIS "closed".
pub const ITIS_CLOSED: u16 = 769;
/// ITIS "closed ahead".
pub const ITIS_CLOSED_AHEAD: u16 = 771;
/// ITIS "left lane".
pub const ITIS_LEFT_LANE: u16 = 8195;
/// ITIS "right lane".
pub const ITIS_RIGHT_LANE: u16 = 8196;
/// ITIS "road construction".
pub const ITIS_ROAD_CONSTRUCTION: u16 = 1025;
/// ITIS "workers".
pub const ITIS_WORKERS: u16 = 6952;

/// TIM `content` choice.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
#[cfg_attr(feature = "serde", derive(Serialize, Deserialize))]
pub enum ContentKind {
    /// `advisory`.
    Advisory,
    /// `workZone`.
    #[default]
    WorkZone,
    /// `genericSign`.
    GenericSign,
    /// `speedLimit`.
    SpeedLimit,
    /// `exitService`.
    ExitService,
}

/// Which side's lane a closure names.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
#[cfg_attr(feature = "serde", derive(Serialize, Deserialize))]
pub enum ClosureSide {
    /// No side given.
    #[default]
    Unknown,
    /// Left lane (ITIS 8195).
    Left,
    /// Right lane (ITIS 8196).
    Right,
}

/// What a zone's content means for the driver.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct ZoneInfo {
    /// Content kind.
    pub kind: ContentKind,
    /// ITIS codes as received (first [`MAX_ITIS`]).
    pub itis: Vec<u16, MAX_ITIS, u8>,
    /// Reduced speed limit, unavailable when none was given.
    pub speed_limit: Speed,
    /// A lane is closed (ITIS 769 or 771).
    pub lane_closed: bool,
    /// Which lane the closure names.
    pub side: ClosureSide,
    /// Workers present (ITIS 6952).
    pub workers: bool,
}

impl ZoneInfo {
    /// Empty content of `kind`.
    pub const fn new(kind: ContentKind) -> Self {
        ZoneInfo {
            kind,
            itis: Vec::new(),
            speed_limit: Speed::UNAVAILABLE,
            lane_closed: false,
            side: ClosureSide::Unknown,
            workers: false,
        }
    }

    /// Adds one ITIS code of the content list, in order.
    pub fn push_itis(&mut self, code: u16) {
        let prev = self.itis.last().copied();
        let before = self
            .itis
            .len()
            .checked_sub(2)
            .and_then(|i| self.itis.get(i).copied());
        let _ = self.itis.push(code);
        match code {
            ITIS_CLOSED | ITIS_CLOSED_AHEAD => self.lane_closed = true,
            ITIS_LEFT_LANE => self.side = ClosureSide::Left,
            ITIS_RIGHT_LANE => self.side = ClosureSide::Right,
            ITIS_WORKERS => self.workers = true,
            ITIS_MPH | ITIS_KMH => self.unit_after(before, prev, code == ITIS_KMH),
            _ => self.number_after(prev, code),
        }
    }

    /// `268, number` sets the limit in mph (the US default) until a unit follows.
    fn number_after(&mut self, prev: Option<u16>, code: u16) {
        if prev == Some(ITIS_SPEED_LIMIT) {
            if let Some(n) = itis_number(code) {
                self.speed_limit = Speed::from_mph(n as f32);
            }
        }
    }

    /// `268, number, unit`: re-reads the number in the given unit.
    fn unit_after(&mut self, before: Option<u16>, prev: Option<u16>, kmh: bool) {
        if before != Some(ITIS_SPEED_LIMIT) {
            return;
        }
        if let Some(n) = prev.and_then(itis_number) {
            self.speed_limit = speed_in(n as f32, kmh);
        }
    }

    /// Adds a text item: a speed such as "25 mph", "40 km/h" or "speed limit 30"
    /// sets the limit; "lane closed", "left lane", "right lane" set the closure.
    pub fn push_text(&mut self, text: &str) {
        let lower = Lowercase(text);
        if lower.contains("closed") {
            self.lane_closed = true;
        }
        if lower.contains("left lane") {
            self.side = ClosureSide::Left;
        } else if lower.contains("right lane") {
            self.side = ClosureSide::Right;
        }
        let speedish = lower.contains("mph") || lower.contains("km") || lower.contains("speed");
        if let (true, Some(n)) = (speedish, first_number(text)) {
            self.speed_limit = speed_in(n as f32, lower.contains("km") || lower.contains("kph"));
        }
    }
}

/// The number N of an ITIS number code `12544 + N`.
fn itis_number(code: u16) -> Option<u16> {
    (ITIS_NUMBER_BASE..=ITIS_NUMBER_MAX)
        .contains(&code)
        .then(|| code - ITIS_NUMBER_BASE)
}

fn speed_in(n: f32, kmh: bool) -> Speed {
    if kmh {
        Speed::from_kmh(n)
    } else {
        Speed::from_mph(n)
    }
}

/// The first run of ASCII digits as a number (at most 4 digits).
fn first_number(text: &str) -> Option<u16> {
    let bytes = text.as_bytes();
    let start = bytes.iter().position(u8::is_ascii_digit)?;
    let digits = bytes[start..]
        .iter()
        .take_while(|b| b.is_ascii_digit())
        .take(4);
    Some(digits.fold(0u16, |acc, b| acc * 10 + (b - b'0') as u16))
}

/// ASCII case-insensitive substring search without allocating.
struct Lowercase<'a>(&'a str);

impl Lowercase<'_> {
    fn contains(&self, needle: &str) -> bool {
        let (h, n) = (self.0.as_bytes(), needle.as_bytes());
        !n.is_empty() && h.windows(n.len()).any(|w| w.eq_ignore_ascii_case(n))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn info(codes: &[u16]) -> ZoneInfo {
        let mut z = ZoneInfo::new(ContentKind::WorkZone);
        codes.iter().for_each(|&c| z.push_itis(c));
        z
    }

    #[test]
    fn speed_limit_from_itis() {
        let z = info(&[1025, 268, 12569, 8720]);
        assert_eq!(z.speed_limit, Speed::from_mph(25.0));
        let z = info(&[268, 12584, ITIS_KMH]);
        assert_eq!(z.speed_limit, Speed::from_kmh(40.0));
        let z = info(&[268, 12569]);
        assert_eq!(z.speed_limit, Speed::from_mph(25.0));
        assert_eq!(info(&[12569, 8720]).speed_limit, Speed::UNAVAILABLE);
        assert_eq!(info(&[268, 999]).speed_limit, Speed::UNAVAILABLE);
    }

    #[test]
    fn closures_from_itis() {
        let z = info(&[771, 8196, 6952]);
        assert!(z.lane_closed && z.workers);
        assert_eq!(z.side, ClosureSide::Right);
        assert_eq!(info(&[769, 8195]).side, ClosureSide::Left);
        assert!(!info(&[1025]).lane_closed);
    }

    #[test]
    fn text_items() {
        let mut z = ZoneInfo::new(ContentKind::Advisory);
        z.push_text("Speed limit 40 km/h");
        assert_eq!(z.speed_limit, Speed::from_kmh(40.0));
        z.push_text("25 MPH");
        assert_eq!(z.speed_limit, Speed::from_mph(25.0));
        z.push_text("Left lane CLOSED");
        assert!(z.lane_closed && z.side == ClosureSide::Left);
        z.push_text("99999999999 mph");
        assert_eq!(
            z.speed_limit,
            Speed::UNAVAILABLE,
            "9999 mph is out of range"
        );
        z.push_text("");
    }

    #[test]
    fn itis_list_is_bounded() {
        let z = info(&[1025; 40]);
        assert_eq!(z.itis.len(), MAX_ITIS);
    }
}
