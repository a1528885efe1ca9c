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
/// ITIS "kPH" (km/h): the ITIS `Units` list of SAE J2540/2 (ITIS Phrase Tables, draft
/// RC1 2004-11-09, p. 194, as published at itsware.net) gives `mPH (8720)`, `kPH (8721)`.
/// Text "km/h" and "kph" are parsed as well.
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

/// Where the speed-limit phrase `268, number, unit` stands while items arrive.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
enum SpeedPhrase {
    /// Not in a speed phrase.
    #[default]
    Idle,
    /// After "speed limit" (ITIS 268).
    Limit,
    /// After the number: a unit may follow.
    Number(u16),
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
    phrase: SpeedPhrase,
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
            phrase: SpeedPhrase::Idle,
        }
    }

    /// Adds one ITIS code of the content list, in order. A speed limit is the phrase
    /// `268 (speed limit), 12544 + N, unit`: the number alone sets N mph (the US
    /// default), a following 8720 (mph) or 8721 (km/h) sets the unit.
    pub fn push_itis(&mut self, code: u16) {
        let _ = self.itis.push(code);
        let phrase = self.phrase;
        self.phrase = SpeedPhrase::Idle;
        match code {
            ITIS_CLOSED | ITIS_CLOSED_AHEAD => self.lane_closed = true,
            ITIS_LEFT_LANE => self.side = ClosureSide::Left,
            ITIS_RIGHT_LANE => self.side = ClosureSide::Right,
            ITIS_WORKERS => self.workers = true,
            ITIS_SPEED_LIMIT => self.phrase = SpeedPhrase::Limit,
            ITIS_MPH | ITIS_KMH => self.unit_after(phrase, code == ITIS_KMH),
            _ => {
                if let Some(n) = itis_number(code) {
                    self.number_after(phrase, n);
                }
            }
        }
    }

    /// A number after "speed limit" sets the limit in mph until a unit follows.
    fn number_after(&mut self, phrase: SpeedPhrase, n: u16) {
        if phrase == SpeedPhrase::Limit {
            self.speed_limit = Speed::from_mph(n as f32);
            self.phrase = SpeedPhrase::Number(n);
        }
    }

    /// A unit after "speed limit, number" re-reads the number in that unit.
    fn unit_after(&mut self, phrase: SpeedPhrase, kmh: bool) {
        if let SpeedPhrase::Number(n) = phrase {
            self.speed_limit = speed_in(n as f32, kmh);
        }
    }

    /// Adds a text item: a speed such as "25 mph", "40 km/h" or "speed limit 30"
    /// sets the limit; "lane closed", "left lane", "right lane" set the closure. Text
    /// items take part in the speed phrase too: `268, "25", "MPH"`.
    pub fn push_text(&mut self, text: &str) {
        let lower = Lowercase(text);
        let phrase = self.phrase;
        self.phrase = SpeedPhrase::Idle;
        if lower.contains("closed") {
            self.lane_closed = true;
        }
        if lower.contains("left lane") {
            self.side = ClosureSide::Left;
        } else if lower.contains("right lane") {
            self.side = ClosureSide::Right;
        }
        let unit = lower.unit();
        let speedish = lower.contains("speed");
        match (first_number(text), unit) {
            (Some(n), Some(kmh)) => self.speed_limit = speed_in(n as f32, kmh),
            (Some(n), None) if speedish || phrase == SpeedPhrase::Limit => {
                self.speed_limit = Speed::from_mph(n as f32);
                self.phrase = SpeedPhrase::Number(n);
            }
            (None, Some(kmh)) => self.unit_after(phrase, kmh),
            (None, None) if speedish => self.phrase = SpeedPhrase::Limit,
            _ => {}
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

    /// The speed unit named: `Some(true)` km/h, `Some(false)` mph.
    fn unit(&self) -> Option<bool> {
        if self.contains("km") || self.contains("kph") {
            Some(true)
        } else if self.contains("mph") {
            Some(false)
        } else {
            None
        }
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
        let mut z = ZoneInfo::new(ContentKind::SpeedLimit);
        z.push_itis(ITIS_SPEED_LIMIT);
        z.push_text("40");
        z.push_text("KPH");
        assert_eq!(z.speed_limit, Speed::from_kmh(40.0), "268, \"40\", \"KPH\"");
        let mut z = ZoneInfo::new(ContentKind::SpeedLimit);
        z.push_text("12");
        assert_eq!(
            z.speed_limit,
            Speed::UNAVAILABLE,
            "a bare number is no limit"
        );
    }

    #[test]
    fn phrase_breaks_on_other_codes() {
        assert_eq!(info(&[268, 1025, 12569]).speed_limit, Speed::UNAVAILABLE);
        assert_eq!(
            info(&[268, 12569, 1025, 8721]).speed_limit,
            Speed::from_mph(25.0),
            "the unit must follow the number"
        );
        let many: heapless::Vec<u16, 40> =
            (0..30).map(|_| 1025).chain([268, 12584, 8721]).collect();
        assert_eq!(
            info(&many).speed_limit,
            Speed::from_kmh(40.0),
            "beyond MAX_ITIS"
        );
    }

    #[test]
    fn itis_list_is_bounded() {
        let z = info(&[1025; 40]);
        assert_eq!(z.itis.len(), MAX_ITIS);
    }
}
