//! Which UTC the core may believe: GNSS time checked for the week rollover and against a
//! reference clock.
//!
//! GPS counts weeks in a 10-bit field: a receiver whose firmware epoch has passed reports
//! dates exactly 1024 weeks (19.6 years) early. A zone judged on such a date is "expired"
//! and the driver would see a green screen at a closed lane. Every fix's UTC goes through
//! [`ClockCheck::check`]:
//!
//! 1. A date before [`TIME_FLOOR`] (a date this software cannot run before) is moved
//!    forward by 1024 weeks until it is not.
//! 2. With a reference (the host's system clock, NTP or RTC, given with
//!    [`ClockCheck::set_reference`]), a GNSS time within a day of a whole number of
//!    rollovers away from it is moved by those rollovers.
//! 3. The corrected time is [`TimeStatus::Trusted`] when it agrees with the reference
//!    within the configured offset, or when there is no reference and nothing had to be
//!    corrected; otherwise [`TimeStatus::Unverified`] (a date corrected without a reference
//!    to confirm it may have been a receiver's build date, not a rollover). A reference
//!    before the floor is no reference.
//!
//! On an unverified time the core keeps every stored zone (none is judged expired by its
//! validity window) and the display says "time unverified"; the message-time checks of
//! signed data accept either clock ([`crate::security::CheckContext::alt_now_us`]).

#[cfg(feature = "serde")]
use serde::{Deserialize, Serialize};

use crate::time::{Duration, Instant, UtcTime};

/// 1024 weeks in milliseconds: the GPS week-number rollover period.
pub const ROLLOVER_MS: i64 = 1024 * 7 * 86_400_000;

/// No clock this software runs on reads earlier than this: 2024-01-01 00:00 UTC.
pub const TIME_FLOOR: UtcTime = UtcTime {
    year: 2024,
    ms_of_year: 0,
};

/// While the two clocks disagree by at most this, signed messages may be timed by either
/// (15 minutes): a receiver off by minutes keeps working, and a reference clock pushed
/// far off (a spoofed NTP) cannot make old recordings current.
pub const MAX_SECOND_CLOCK_OFFSET_MS: u64 = 15 * 60_000;

/// A GNSS time within this of a whole number of rollovers from the reference is a
/// rollover, not a clock that is merely off.
const ROLLOVER_SLACK_MS: i64 = 86_400_000;

/// How far the time shown and used can be believed.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
#[cfg_attr(feature = "serde", derive(Serialize, Deserialize))]
pub enum TimeStatus {
    /// No fix with a time yet.
    #[default]
    Unknown,
    /// GNSS time (after a rollover correction, if one was needed) that agrees with the
    /// reference clock, or no reference clock to check against.
    Trusted,
    /// GNSS time and the reference clock disagree: zones are kept, none expires by date.
    Unverified,
}

/// A fix's UTC after the checks.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct CheckedTime {
    /// The corrected time.
    pub utc: UtcTime,
    /// Whether it may be believed.
    pub status: TimeStatus,
    /// Whole rollover periods added (negative: removed) to the receiver's time.
    pub rollovers: i8,
}

/// The reference clock and the check of GNSS time against it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct ClockCheck {
    /// The last reference sample: when it was taken on the core's clock, and its UTC.
    reference: Option<(Instant, UtcTime)>,
}

impl ClockCheck {
    /// No reference yet.
    pub const fn new() -> Self {
        ClockCheck { reference: None }
    }

    /// The reference clock read `utc` at `now`; a time before [`TIME_FLOOR`] (an unset
    /// real-time clock) removes the reference.
    pub fn set_reference(&mut self, now: Instant, utc: UtcTime) {
        self.reference = (utc >= TIME_FLOOR).then_some((now, utc));
    }

    /// The reference clock at `now`, extrapolated from its last sample.
    pub fn reference_at(&self, now: Instant) -> Option<UtcTime> {
        let (t, utc) = self.reference?;
        Some(utc.plus_millis(now.saturating_since(t).millis()))
    }

    /// Checks the GNSS time `gnss` received at `now`; `max_offset` is how far it may be
    /// from the reference and still be trusted.
    pub fn check(&self, now: Instant, gnss: UtcTime, max_offset: Duration) -> CheckedTime {
        let floor = TIME_FLOOR.abs_millis();
        let mut t = gnss.abs_millis();
        let mut rollovers: i8 = 0;
        while t < floor && rollovers < 3 {
            t = t.saturating_add(ROLLOVER_MS);
            rollovers += 1;
        }
        let Some(reference) = self.reference_at(now).map(UtcTime::abs_millis) else {
            // A corrected date is a guess (it could be a receiver's build date, not a
            // rollover): shown and used for signatures, but no zone expires on it.
            let status = if t >= floor && rollovers == 0 {
                TimeStatus::Trusted
            } else {
                TimeStatus::Unverified
            };
            return CheckedTime {
                utc: UtcTime::from_abs_millis(t),
                status,
                rollovers,
            };
        };
        let off = t.saturating_sub(reference);
        let k = off.saturating_add(ROLLOVER_MS / 2).div_euclid(ROLLOVER_MS);
        if k != 0 && (-3..=3).contains(&k) && (off - k * ROLLOVER_MS).abs() <= ROLLOVER_SLACK_MS {
            t -= k * ROLLOVER_MS;
            rollovers -= k as i8;
        }
        let agrees = t.saturating_sub(reference).unsigned_abs() <= max_offset.millis();
        CheckedTime {
            utc: UtcTime::from_abs_millis(t),
            status: if agrees {
                TimeStatus::Trusted
            } else {
                TimeStatus::Unverified
            },
            rollovers,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// 2026-11-25 08:00:00 UTC.
    fn today() -> UtcTime {
        UtcTime {
            year: 2026,
            ms_of_year: 328 * 86_400_000 + 8 * 3_600_000,
        }
    }

    fn shifted(t: UtcTime, ms: i64) -> UtcTime {
        UtcTime::from_abs_millis(t.abs_millis() + ms)
    }

    const TEN_S: Duration = Duration::from_secs(10);

    #[test]
    fn week_rollover_is_corrected_without_a_reference_but_not_trusted() {
        let clock = ClockCheck::new();
        let faulty = shifted(today(), -ROLLOVER_MS);
        assert_eq!(faulty.year, 2007, "1024 weeks before 2026-11-25");
        let c = clock.check(Instant::ZERO, faulty, TEN_S);
        assert_eq!(c.utc, today());
        assert_eq!((c.status, c.rollovers), (TimeStatus::Unverified, 1));
        // Absurd times saturate instead of overflowing.
        let absurd = UtcTime {
            year: 2026,
            ms_of_year: u64::MAX,
        };
        let _ = clock.check(Instant::ZERO, absurd, TEN_S);
        let c = clock.check(Instant::ZERO, today(), TEN_S);
        assert_eq!(
            (c.utc, c.status, c.rollovers),
            (today(), TimeStatus::Trusted, 0)
        );
    }

    #[test]
    fn a_reference_catches_what_the_floor_cannot_and_disagreement_is_unverified() {
        let mut clock = ClockCheck::new();
        clock.set_reference(Instant::from_millis(1_000), today());
        let now = Instant::from_millis(3_000);
        let at_now = shifted(today(), 2_000);
        // Two rollovers early reads 1987: the floor adds one, the reference the other.
        let c = clock.check(now, shifted(at_now, -2 * ROLLOVER_MS), TEN_S);
        assert_eq!(
            (c.utc, c.status, c.rollovers),
            (at_now, TimeStatus::Trusted, 2)
        );
        // A receiver 1024 weeks ahead (a wrong leap-year rule in some firmware).
        let c = clock.check(now, shifted(at_now, ROLLOVER_MS + 500), TEN_S);
        assert_eq!(c.rollovers, -1);
        assert_eq!(c.status, TimeStatus::Trusted);
        // Two minutes off: kept as received, but not trusted.
        let c = clock.check(now, shifted(at_now, 120_000), TEN_S);
        assert_eq!((c.status, c.rollovers), (TimeStatus::Unverified, 0));
        assert_eq!(c.utc, shifted(at_now, 120_000));
        let c = clock.check(now, shifted(at_now, -9_000), TEN_S);
        assert_eq!(c.status, TimeStatus::Trusted);
    }

    #[test]
    fn an_unset_system_clock_is_no_reference() {
        let mut clock = ClockCheck::new();
        let epoch = UtcTime {
            year: 1970,
            ms_of_year: 0,
        };
        clock.set_reference(Instant::ZERO, epoch);
        assert_eq!(clock.reference_at(Instant::ZERO), None);
        let c = clock.check(Instant::ZERO, today(), TEN_S);
        assert_eq!(c.status, TimeStatus::Trusted);
    }
}
