//! The two date forms of the RSU tables: SNMPv2-TC `DateAndTime` (RFC 2579, NTCIP 1218's
//! delivery start and stop) and the RSU 4.1 specification's 6-octet form. Both are UTC on
//! the wire here: the 8-octet form has no zone, as jpo-ode writes it.

use crate::clock::Utc;

/// `DateAndTime` of `unix_ms`, 8 octets: year (2, big-endian), month, day, hour, minutes,
/// seconds, deci-seconds.
pub fn date_and_time(unix_ms: u64) -> [u8; 8] {
    let t = Utc::from_unix_ms(unix_ms);
    let s = t.ms_of_day / 1000;
    let [y0, y1] = t.year.to_be_bytes();
    [
        y0,
        y1,
        t.month,
        t.day,
        (s / 3600) as u8,
        (s / 60 % 60) as u8,
        (s % 60) as u8,
        (t.ms_of_day % 1000 / 100) as u8,
    ]
}

/// The RSU 4.1 form of `unix_ms`, 6 octets: year (2, big-endian), month, day, hour,
/// minute (seconds dropped).
pub fn rsu41_date(unix_ms: u64) -> [u8; 6] {
    let d = date_and_time(unix_ms);
    [d[0], d[1], d[2], d[3], d[4], d[5]]
}

/// Unix ms of a date in either form (8 or 11 octets `DateAndTime`, whose zone, if given,
/// is applied; or 6 octets), `None` when the octets are not a valid date.
pub fn unix_ms_of(octets: &[u8]) -> Option<u64> {
    let (&[y0, y1, month, day, hour, minute], rest) = octets.split_first_chunk::<6>()?;
    let (second, deci, offset_min) = match rest {
        [] => (0, 0, 0i64),
        [s, d] => (*s, *d, 0),
        [s, d, sign, h, m] => {
            let off = i64::from(*h) * 60 + i64::from(*m);
            match sign {
                b'+' => (*s, *d, off),
                b'-' => (*s, *d, -off),
                _ => return None,
            }
        }
        _ => return None,
    };
    let year = u16::from_be_bytes([y0, y1]);
    let valid = (1970..=9999).contains(&year)
        && (1..=12).contains(&month)
        && (1..=31).contains(&day)
        && hour < 24
        && minute < 60
        && second <= 60
        && deci < 10;
    if !valid {
        return None;
    }
    let midnight = Utc {
        year,
        month,
        day,
        ms_of_day: 0,
        day_of_year: 0,
    }
    .to_unix_ms();
    // A day past the month's end comes back as another date: refuse it.
    if Utc::from_unix_ms(midnight).day != day {
        return None;
    }
    let local = midnight as i64
        + (i64::from(hour) * 3600 + i64::from(minute) * 60 + i64::from(second)) * 1000
        + i64::from(deci) * 100;
    u64::try_from(local - offset_min * 60_000).ok()
}

#[cfg(test)]
mod tests {
    use super::*;

    // 2026-12-04T13:45:27.300Z
    const T: u64 = 1_796_391_927_300;

    #[test]
    fn writes_both_forms() {
        assert_eq!(date_and_time(T), [0x07, 0xea, 12, 4, 13, 45, 27, 3]);
        assert_eq!(rsu41_date(T), [0x07, 0xea, 12, 4, 13, 45]);
    }

    #[test]
    fn reads_every_form_back() {
        assert_eq!(unix_ms_of(&date_and_time(T)), Some(T));
        assert_eq!(unix_ms_of(&rsu41_date(T)), Some(T - 27_300));
        let mut zoned = date_and_time(T).to_vec();
        zoned.extend_from_slice(&[b'-', 5, 0]);
        assert_eq!(unix_ms_of(&zoned), Some(T + 5 * 3_600_000));
    }

    #[test]
    fn refuses_what_is_no_date() {
        assert_eq!(unix_ms_of(&[0x07, 0xea, 2, 30, 0, 0]), None);
        assert_eq!(unix_ms_of(&[0x07, 0xea, 13, 1, 0, 0]), None);
        assert_eq!(unix_ms_of(&[0x07, 0xea, 1, 1, 0]), None);
        assert_eq!(unix_ms_of(&[0x07, 0xea, 1, 1, 0, 0, 0]), None);
        assert_eq!(
            unix_ms_of(&[0x07, 0xea, 1, 1, 0, 0, 0, 0, b'x', 0, 0]),
            None
        );
    }
}
