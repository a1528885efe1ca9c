//! Work zones: what a J2735 TIM data frame says, in local metres.
//!
//! A [`WorkZone`] is keyed by [`ZoneKey`] (TIM `packetID` plus data-frame index) and
//! carries the TIM `msgCnt`, a [`Validity`] window, up to
//! [`MAX_REGIONS`](crate::capacity::MAX_REGIONS) [`Region`]s and the parsed
//! [`ZoneInfo`] (speed limit, closed lanes). [`ZoneStore`] replaces a zone when a newer
//! `msgCnt` or start time arrives, drops cancelled (`durationTime` 0) and expired ones,
//! and [`associate`] finds the MAP lanes each region lies on with the cone-to-lane rule.

mod assoc;
mod content;
mod region;
mod store;
mod work_zone;

pub use assoc::associate;
pub use content::{
    ClosureSide, ContentKind, ZoneInfo, ITIS_CLOSED, ITIS_CLOSED_AHEAD, ITIS_KMH, ITIS_LEFT_LANE,
    ITIS_MPH, ITIS_NUMBER_BASE, ITIS_NUMBER_MAX, ITIS_RIGHT_LANE, ITIS_ROAD_CONSTRUCTION,
    ITIS_SPEED_LIMIT, ITIS_WORKERS,
};
pub use region::{Region, RegionShape};
pub use store::{ZoneStore, ZoneUpdate};
pub use work_zone::{MapEnds, WorkZone, ZoneLane};

use core::fmt;

#[cfg(feature = "serde")]
use serde::{Deserialize, Serialize};

use crate::math::wrap_360;

/// Identity of a work zone: TIM `packetID` (9 octets, zero-padded when shorter) and
/// the index of the data frame within the TIM. A TIM without `packetID` is keyed by
/// the data frame's `msgId` instead ([`KeySource::MsgId`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Default)]
#[cfg_attr(feature = "serde", derive(Serialize, Deserialize))]
pub struct ZoneKey {
    /// TIM `packetID`, or a digest of the data frame's `msgId` (see `source`).
    pub packet_id: [u8; 9],
    /// Index of the data frame in `dataFrames`.
    pub frame: u8,
    /// What `packet_id` holds.
    pub source: KeySource,
}

/// Where a [`ZoneKey`]'s identity comes from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Default)]
#[cfg_attr(feature = "serde", derive(Serialize, Deserialize))]
pub enum KeySource {
    /// The TIM's `packetID`.
    #[default]
    PacketId,
    /// The data frame's `msgId` (`furtherInfoID` or `roadSignID`), for TIMs without
    /// `packetID`.
    MsgId,
}

impl ZoneKey {
    /// The key of data frame `frame` of a TIM with `packet_id`.
    pub const fn packet(packet_id: [u8; 9], frame: u8) -> Self {
        ZoneKey {
            packet_id,
            frame,
            source: KeySource::PacketId,
        }
    }
}

impl fmt::Display for ZoneKey {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.source == KeySource::MsgId {
            f.write_str("msgId:")?;
        }
        write!(f, "{}/{}", j2735::hex::Hex(&self.packet_id), self.frame)
    }
}

/// TIM validity: `startYear`, `startTime` (minute of the year), `durationTime`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
#[cfg_attr(feature = "serde", derive(Serialize, Deserialize))]
pub struct Validity {
    /// `startYear`; 0 when absent (J2735: the current year), resolved against the
    /// time of each check.
    pub start_year: u16,
    /// `startTime`, minute of the year (0..=527040).
    pub start_minute: u32,
    /// `durationTime` in minutes; [`Validity::INDEFINITE`] never ends, 0 cancels.
    pub duration_min: u16,
}

impl Validity {
    /// `durationTime` meaning "until further notice".
    pub const INDEFINITE: u16 = 32000;

    /// True for `durationTime` 0: the sender cancels the zone.
    pub const fn is_cancelled(&self) -> bool {
        self.duration_min == 0
    }

    /// Start in minutes since 2000 (see [`crate::time::abs_minutes`]); a missing year
    /// counts as year 0 here (only for ordering two versions of one zone).
    pub const fn start_abs(&self) -> i64 {
        crate::time::abs_minutes(self.start_year, self.start_minute as i64)
    }

    /// Start in minutes since 2000 as seen at `now_abs_min` (a missing `startYear` is
    /// the year of `now_abs_min`).
    pub const fn start_abs_at(&self, now_abs_min: i64) -> i64 {
        let year = if self.start_year == 0 {
            crate::time::year_of(now_abs_min)
        } else {
            self.start_year
        };
        crate::time::abs_minutes(year, self.start_minute as i64)
    }

    /// End in minutes since 2000 as seen at `now_abs_min`, `None` when indefinite.
    pub const fn end_abs_at(&self, now_abs_min: i64) -> Option<i64> {
        if self.duration_min >= Self::INDEFINITE {
            None
        } else {
            Some(self.start_abs_at(now_abs_min) + self.duration_min as i64)
        }
    }

    /// Active iff start <= now < start + duration (and not cancelled). `now_abs_min` is
    /// the current minute (the time floored to it), so a zone ends at the instant its
    /// last minute ends: a 60-minute zone from 10:00 is gone at 11:00:00, not at 11:01.
    pub const fn is_active(&self, now_abs_min: i64) -> bool {
        if self.is_cancelled() || now_abs_min < self.start_abs_at(now_abs_min) {
            return false;
        }
        match self.end_abs_at(now_abs_min) {
            Some(end) => now_abs_min < end,
            None => true,
        }
    }

    /// True once the window has ended (the minute `start + duration` has begun).
    pub const fn has_ended(&self, now_abs_min: i64) -> bool {
        if self.is_cancelled() {
            return true;
        }
        match self.end_abs_at(now_abs_min) {
            Some(end) => now_abs_min >= end,
            None => false,
        }
    }
}

/// TIM `directionality` of a region, relative to the path's node order.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
#[cfg_attr(feature = "serde", derive(Serialize, Deserialize))]
pub enum Directionality {
    /// Travel along the node order.
    Forward,
    /// Travel against the node order.
    Reverse,
    /// Both ways (also used for J2735 `unavailable`).
    #[default]
    Both,
}

impl Directionality {
    /// True when a vehicle heading `heading_deg` travels in an allowed direction on a
    /// path segment of bearing `path_bearing_deg`.
    pub fn allows(self, heading_deg: f32, path_bearing_deg: f32) -> bool {
        let diff = crate::math::heading_diff(heading_deg, path_bearing_deg);
        match self {
            Directionality::Forward => diff <= 90.0,
            Directionality::Reverse => diff >= 90.0,
            Directionality::Both => true,
        }
    }
}

/// TIM `HeadingSlice`: bit `n` (least significant first) set means headings in
/// `[22.5 n, 22.5 (n + 1))` degrees from north are concerned.
///
/// The UPER/JER bit string lists bit 0 first (`from000-0to022-5degrees`), so a
/// converter maps string bit `n` to bit `n` here. An all-zero mask is treated as
/// "all headings" since senders use it for "unspecified".
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(Serialize, Deserialize))]
pub struct HeadingSlice(pub u16);

impl Default for HeadingSlice {
    fn default() -> Self {
        HeadingSlice::ALL
    }
}

impl HeadingSlice {
    /// All sixteen slices.
    pub const ALL: HeadingSlice = HeadingSlice(0xffff);

    /// The slice bit of a heading in degrees.
    pub fn bit_of(heading_deg: f32) -> u8 {
        ((wrap_360(heading_deg) / 22.5) as u8).min(15)
    }

    /// True when `heading_deg` falls in a set slice (or the mask is empty).
    pub fn contains(self, heading_deg: f32) -> bool {
        self.0 == 0 || self.0 & (1 << Self::bit_of(heading_deg)) != 0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn validity_window() {
        let v = Validity {
            start_year: 2024,
            start_minute: 1000,
            duration_min: 60,
        };
        let start = v.start_abs();
        assert!(!v.is_active(start - 1));
        assert!(v.is_active(start) && v.is_active(start + 59) && !v.has_ended(start + 59));
        assert!(!v.is_active(start + 60) && v.has_ended(start + 60));
        let forever = Validity {
            duration_min: Validity::INDEFINITE,
            ..v
        };
        assert!(forever.is_active(start + 10_000_000) && !forever.has_ended(i64::MAX));
        let cancel = Validity {
            duration_min: 0,
            ..v
        };
        assert!(cancel.is_cancelled() && !cancel.is_active(start) && cancel.has_ended(start));
        let this_year = Validity { start_year: 0, ..v };
        assert!(this_year.is_active(start + 30) && !this_year.is_active(start - 1));
        let next_year = crate::time::abs_minutes(2025, 1030);
        assert!(
            this_year.is_active(next_year),
            "a missing year is the current one"
        );
    }

    #[test]
    fn heading_slices() {
        let north_east = HeadingSlice(0b0000_0000_0000_0110);
        assert!(north_east.contains(30.0) && north_east.contains(67.4));
        assert!(!north_east.contains(10.0) && !north_east.contains(67.5));
        assert!(HeadingSlice(0).contains(200.0));
        assert_eq!(HeadingSlice::bit_of(359.99), 15);
        assert_eq!(HeadingSlice::bit_of(f32::NAN), 0);
        assert!(Directionality::Forward.allows(10.0, 350.0));
        assert!(!Directionality::Forward.allows(180.0, 0.0));
        assert!(Directionality::Reverse.allows(180.0, 0.0));
    }
}
