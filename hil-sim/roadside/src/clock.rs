//! UTC calendar arithmetic for NMEA and J2735 times (proleptic Gregorian, no leap seconds,
//! as both formats count).

use std::time::{SystemTime, UNIX_EPOCH};

/// A UTC instant split the way NMEA and J2735 need it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Utc {
    /// Year, e.g. 2026.
    pub year: u16,
    /// Month 1-12.
    pub month: u8,
    /// Day of the month 1-31.
    pub day: u8,
    /// Milliseconds since midnight.
    pub ms_of_day: u32,
    /// Day of the year, 0 for 1 January.
    pub day_of_year: u16,
}

impl Utc {
    /// The instant `ms` milliseconds after 1970-01-01T00:00:00Z.
    pub fn from_unix_ms(ms: u64) -> Self {
        let days = ms / 86_400_000;
        let ms_of_day = (ms % 86_400_000) as u32;
        let (year, month, day) = civil_from_days(days as i64);
        let day_of_year = (days as i64 - days_from_civil(year, 1, 1)) as u16;
        Self {
            year: year as u16,
            month,
            day,
            ms_of_day,
            day_of_year,
        }
    }

    /// Milliseconds after 1970-01-01T00:00:00Z (the inverse of [`Utc::from_unix_ms`]).
    pub fn to_unix_ms(&self) -> u64 {
        let days = days_from_civil(i64::from(self.year), self.month, self.day);
        days.max(0) as u64 * 86_400_000 + u64::from(self.ms_of_day)
    }

    /// Now, from the system clock.
    pub fn now() -> Self {
        Self::from_unix_ms(unix_ms_now())
    }

    /// RFC 3339 to the whole second, UTC: `2026-12-04T14:03:20Z` (WZDx dates, logs).
    pub fn rfc3339_seconds(&self) -> String {
        let s = self.ms_of_day / 1000;
        format!(
            "{:04}-{:02}-{:02}T{:02}:{:02}:{:02}Z",
            self.year,
            self.month,
            self.day,
            s / 3600,
            s / 60 % 60,
            s % 60
        )
    }

    /// J2735 `MinuteOfTheYear`: minutes since 1 January 00:00 of the year.
    pub fn minute_of_year(&self) -> u32 {
        self.day_of_year as u32 * 1440 + self.ms_of_day / 60_000
    }

    /// J2735 `DSecond`: milliseconds within the minute.
    pub fn dsecond(&self) -> u16 {
        (self.ms_of_day % 60_000) as u16
    }
}

/// Milliseconds since the Unix epoch from the system clock (0 if it is before 1970).
pub fn unix_ms_now() -> u64 {
    SystemTime::now()
        .duration_since(UNIX_EPOCH)
        .map_or(0, |d| d.as_millis() as u64)
}

/// Days since 1970-01-01 of a civil date (H. Hinnant's algorithm).
pub fn days_from_civil(year: i64, month: u8, day: u8) -> i64 {
    let y = if month <= 2 { year - 1 } else { year };
    let era = y.div_euclid(400);
    let yoe = y - era * 400;
    let m = month as i64;
    let doy = (153 * (if m > 2 { m - 3 } else { m + 9 }) + 2) / 5 + day as i64 - 1;
    let doe = yoe * 365 + yoe / 4 - yoe / 100 + doy;
    era * 146_097 + doe - 719_468
}

/// The civil date of a day count since 1970-01-01.
pub fn civil_from_days(days: i64) -> (i64, u8, u8) {
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z - era * 146_097;
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let day = (doy - (153 * mp + 2) / 5 + 1) as u8;
    let month = if mp < 10 { mp + 3 } else { mp - 9 } as u8;
    let year = yoe + era * 400 + i64::from(month <= 2);
    (year, month, day)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rfc3339_to_the_second() {
        // `date -u -d @1763784961.5 +%FT%TZ`
        assert_eq!(
            Utc::from_unix_ms(1_763_784_961_500).rfc3339_seconds(),
            "2025-11-22T04:16:01Z"
        );
    }

    #[test]
    fn known_dates() {
        // 2025-11-22T04:16:01.500Z, as `date -u -d @1763784961.5` prints it.
        let u = Utc::from_unix_ms(1_763_784_961_500);
        assert_eq!((u.year, u.month, u.day), (2025, 11, 22));
        assert_eq!(u.ms_of_day, (4 * 3600 + 16 * 60 + 1) * 1000 + 500);
        // 22 November is day 325 of a common year (31+28+31+30+31+30+31+31+30+31 + 21).
        assert_eq!(u.day_of_year, 325);
        assert_eq!(u.minute_of_year(), 325 * 1440 + 4 * 60 + 16);
        let leap = Utc::from_unix_ms(days_from_civil(2024, 12, 31) as u64 * 86_400_000);
        assert_eq!(
            (leap.year, leap.month, leap.day, leap.day_of_year),
            (2024, 12, 31, 365)
        );
        assert_eq!(civil_from_days(0), (1970, 1, 1));
        for ms in [0, 1_763_784_961_500, 1_709_164_800_123] {
            assert_eq!(Utc::from_unix_ms(ms).to_unix_ms(), ms);
        }
        assert_eq!(days_from_civil(2000, 3, 1), 11_017);
    }
}
