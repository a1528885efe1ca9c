//! Time as passed in by the caller: a monotonic [`Instant`] and [`Duration`] in
//! milliseconds, and the UTC wall time ([`UtcTime`]) that TIM validity needs.

use core::fmt;
use core::ops::Add;

#[cfg(feature = "serde")]
use serde::{Deserialize, Serialize};

/// A point on the caller's monotonic clock, in milliseconds.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Default)]
#[cfg_attr(feature = "serde", derive(Serialize, Deserialize))]
pub struct Instant(u64);

/// A span of time in milliseconds.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Default)]
#[cfg_attr(feature = "serde", derive(Serialize, Deserialize))]
pub struct Duration(u64);

impl Instant {
    /// The clock's zero.
    pub const ZERO: Instant = Instant(0);

    /// An instant `ms` milliseconds after the clock's zero.
    pub const fn from_millis(ms: u64) -> Self {
        Instant(ms)
    }

    /// Milliseconds since the clock's zero.
    pub const fn millis(self) -> u64 {
        self.0
    }

    /// Time elapsed since `earlier`, zero if `earlier` is later than `self`.
    pub const fn saturating_since(self, earlier: Instant) -> Duration {
        Duration(self.0.saturating_sub(earlier.0))
    }
}

impl Duration {
    /// No time.
    pub const ZERO: Duration = Duration(0);

    /// A duration of `ms` milliseconds.
    pub const fn from_millis(ms: u64) -> Self {
        Duration(ms)
    }

    /// A duration of `s` seconds (saturating).
    pub const fn from_secs(s: u64) -> Self {
        Duration(s.saturating_mul(1000))
    }

    /// The duration in milliseconds.
    pub const fn millis(self) -> u64 {
        self.0
    }

    /// The duration in seconds as f32.
    pub fn as_secs_f32(self) -> f32 {
        self.0 as f32 / 1000.0
    }
}

impl Add<Duration> for Instant {
    type Output = Instant;
    fn add(self, d: Duration) -> Instant {
        Instant(self.0.saturating_add(d.0))
    }
}

impl fmt::Display for Instant {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}.{:03}s", self.0 / 1000, self.0 % 1000)
    }
}

impl fmt::Display for Duration {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}ms", self.0)
    }
}

/// Leap seconds inserted into UTC since 2004-01-01 (ends of 2005-12, 2008-12, 2012-06,
/// 2015-06, 2016-12); none since 2017, and none is announced. A new one would need this
/// constant raised (IERS Bulletin C).
pub const LEAP_SECONDS_SINCE_2004: u64 = 5;

/// Minutes in a common year; J2735 `MinuteOfTheYear` runs to 527 040 (leap year).
pub const MINUTES_PER_DAY: i64 = 1440;

/// UTC wall time as J2735 counts it: a year and the milliseconds into that year.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Default)]
#[cfg_attr(feature = "serde", derive(Serialize, Deserialize))]
pub struct UtcTime {
    /// Calendar year (J2735 `DYear`, 0 = unknown is not accepted here).
    pub year: u16,
    /// Milliseconds since January 1st 00:00 UTC of `year`.
    pub ms_of_year: u64,
}

impl UtcTime {
    /// Builds a time from a year and a J2735 minute of the year.
    pub const fn from_minute_of_year(year: u16, minute: u32) -> Self {
        UtcTime {
            year,
            ms_of_year: minute as u64 * 60_000,
        }
    }

    /// Minutes since 2000-01-01 00:00 UTC (negative before), continuous across years.
    pub const fn abs_minutes(self) -> i64 {
        abs_minutes(self.year, (self.ms_of_year / 60_000) as i64)
    }

    /// IEEE 1609.2 `Time64`: TAI microseconds since 2004-01-01 00:00:00 UTC, i.e. the UTC
    /// time since then plus the leap seconds inserted since ([`LEAP_SECONDS_SINCE_2004`]);
    /// `None` before 2004 or beyond what 64 bits hold.
    pub const fn time64(self) -> Option<u64> {
        let days = days_before_year(self.year) - days_before_year(2004);
        if days < 0 {
            return None;
        }
        // Checked: a hostile receiver's year or offset must give `None`, never overflow.
        let Some(day_ms) = (days as u64).checked_mul(86_400_000) else {
            return None;
        };
        let Some(ms) = day_ms.checked_add(self.ms_of_year) else {
            return None;
        };
        let Some(ms) = ms.checked_add(LEAP_SECONDS_SINCE_2004 * 1000) else {
            return None;
        };
        ms.checked_mul(1000)
    }

    /// Milliseconds since 2000-01-01 00:00 UTC (negative before), continuous across years.
    pub const fn abs_millis(self) -> i64 {
        let into = if self.ms_of_year > i64::MAX as u64 {
            i64::MAX
        } else {
            self.ms_of_year as i64
        };
        ((days_before_year(self.year) - days_before_year(2000)) * 86_400_000).saturating_add(into)
    }

    /// The time `abs_ms` milliseconds after 2000-01-01 00:00 UTC (clamped to year 0 and
    /// `u16::MAX`).
    pub const fn from_abs_millis(abs_ms: i64) -> Self {
        let year = year_of(abs_ms.div_euclid(60_000));
        let start = (days_before_year(year) - days_before_year(2000)) * 86_400_000;
        let into = abs_ms - start;
        UtcTime {
            year,
            ms_of_year: if into < 0 { 0 } else { into as u64 },
        }
    }

    /// Shifts the time by `ms` milliseconds (may cross into the next years).
    pub const fn plus_millis(self, ms: u64) -> Self {
        let mut t = self;
        t.ms_of_year = t.ms_of_year.saturating_add(ms);
        let mut guard = 0;
        while guard < 64 && t.ms_of_year >= year_ms(t.year) {
            t.ms_of_year -= year_ms(t.year);
            t.year = t.year.saturating_add(1);
            guard += 1;
        }
        t
    }
}

/// Days from 0000-01-01 (proleptic Gregorian) to January 1st of `year`.
const fn days_before_year(year: u16) -> i64 {
    let y = year as i64;
    let p = y - 1;
    365 * y + p.div_euclid(4) - p.div_euclid(100) + p.div_euclid(400) + 1
}

/// True if `year` is a Gregorian leap year.
pub const fn is_leap(year: u16) -> bool {
    (year.is_multiple_of(4) && !year.is_multiple_of(100)) || year.is_multiple_of(400)
}

const fn year_ms(year: u16) -> u64 {
    if is_leap(year) {
        366 * 86_400_000
    } else {
        365 * 86_400_000
    }
}

/// Minutes since 2000-01-01 00:00 UTC of `minute` into `year`.
pub const fn abs_minutes(year: u16, minute: i64) -> i64 {
    (days_before_year(year) - days_before_year(2000)) * MINUTES_PER_DAY + minute
}

/// The calendar year (clamped to `0..=u16::MAX`) that contains `abs_min` minutes since
/// 2000-01-01 00:00 UTC.
pub const fn year_of(abs_min: i64) -> u16 {
    let days = abs_min.div_euclid(MINUTES_PER_DAY);
    let guess = 2000 + days.div_euclid(366);
    let mut year = if guess < 0 {
        0
    } else if guess > u16::MAX as i64 {
        u16::MAX
    } else {
        guess as u16
    };
    // The guess is at most a few years early: step forward while the next year has begun.
    let mut guard = 0;
    while guard < 16 && year < u16::MAX && abs_minutes(year + 1, 0) <= abs_min {
        year += 1;
        guard += 1;
    }
    year
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn time64_counts_tai_microseconds_since_2004() {
        // 2025-06-17T12:32:41Z: the independent vectors' generation time
        // (make_signed_vectors.py: 677 248 366 000 000).
        let ms = (31 + 28 + 31 + 30 + 31 + 16) * 86_400_000 + (12 * 3600 + 32 * 60 + 41) * 1000;
        let t = UtcTime {
            year: 2025,
            ms_of_year: ms,
        };
        assert_eq!(t.time64(), Some(677_248_366_000_000));
        assert_eq!(
            UtcTime {
                year: 2004,
                ms_of_year: 0
            }
            .time64(),
            Some(5_000_000)
        );
        assert_eq!(
            UtcTime {
                year: 2003,
                ms_of_year: 0
            }
            .time64(),
            None
        );
    }

    #[test]
    fn year_arithmetic() {
        assert_eq!(abs_minutes(2000, 0), 0);
        assert_eq!(abs_minutes(2001, 0), 366 * 1440);
        assert_eq!(abs_minutes(2002, 0) - abs_minutes(2001, 0), 365 * 1440);
        assert!(is_leap(2024) && !is_leap(2100) && is_leap(2000));
        let t = UtcTime::from_minute_of_year(2023, 525_599).plus_millis(120_000);
        assert_eq!(t.year, 2024);
        assert_eq!(t.ms_of_year, 60_000);
        assert_eq!(t.abs_minutes(), abs_minutes(2023, 525_601));
        assert_eq!(year_of(abs_minutes(2024, 0)), 2024);
        assert_eq!(year_of(abs_minutes(2024, 0) - 1), 2023);
        assert_eq!(year_of(abs_minutes(2025, 527_039 - 1440)), 2025);
        assert_eq!(year_of(abs_minutes(1999, 10)), 1999);
        assert_eq!(year_of(i64::MIN / 2), 0);
        assert_eq!(year_of(i64::MAX / 2), u16::MAX);
    }

    #[test]
    fn absolute_milliseconds_round_trip() {
        let t = UtcTime {
            year: 2026,
            ms_of_year: 328 * 86_400_000 + 12_345,
        };
        assert_eq!(UtcTime::from_abs_millis(t.abs_millis()), t);
        assert_eq!(t.abs_millis() / 60_000, t.abs_minutes());
        let new_year = UtcTime::from_abs_millis(abs_minutes(2025, 0) * 60_000 - 1);
        assert_eq!(
            (new_year.year, new_year.ms_of_year),
            (2024, 366 * 86_400_000 - 1)
        );
    }

    #[test]
    fn instant_ops() {
        let a = Instant::from_millis(1500);
        assert_eq!(
            a.saturating_since(Instant::from_millis(2000)),
            Duration::ZERO
        );
        assert_eq!((a + Duration::from_secs(1)).millis(), 2500);
        assert_eq!(
            Instant::from_millis(u64::MAX) + Duration::from_millis(5),
            Instant::from_millis(u64::MAX)
        );
    }
}
