//! RFC 3339 date-times (WZDx `start_date` / `end_date`) to Unix milliseconds.

use crate::clock::days_from_civil;

/// Milliseconds since the Unix epoch of an RFC 3339 `date-time`
/// (`2026-11-03T19:37:00Z`, `2026-11-03T12:37:00.250-07:00`; `t`/`z` or a space as the
/// separator are accepted); `None` when malformed or before 1970.
pub fn rfc3339_unix_ms(text: &str) -> Option<u64> {
    let b = text.as_bytes();
    let digits = |from: usize, to: usize| -> Option<i64> {
        let s = text.get(from..to)?;
        s.bytes()
            .all(|c| c.is_ascii_digit())
            .then(|| s.parse().ok())
            .flatten()
    };
    let at = |i: usize, allowed: &[u8]| b.get(i).is_some_and(|c| allowed.contains(c));
    let fixed = at(4, b"-") && at(7, b"-") && at(10, b"Tt ") && at(13, b":") && at(16, b":");
    if !fixed {
        return None;
    }
    let (year, month, day) = (digits(0, 4)?, digits(5, 7)?, digits(8, 10)?);
    let (hour, minute, second) = (digits(11, 13)?, digits(14, 16)?, digits(17, 19)?);
    let valid = (1..=12).contains(&month)
        && day >= 1
        && day <= days_in_month(year, month)
        && hour <= 23
        && minute <= 59
        && second <= 60;
    if !valid {
        return None;
    }
    let (millis, offset_min) = fraction_and_offset(text.get(19..)?)?;
    let days = days_from_civil(year, month as u8, day as u8);
    let ms = ((days * 24 + hour) * 60 + minute - offset_min) * 60_000 + second * 1000 + millis;
    u64::try_from(ms).ok()
}

/// The milliseconds of an optional `.fraction` and the offset in minutes (`Z`, `+hh:mm`).
fn fraction_and_offset(rest: &str) -> Option<(i64, i64)> {
    let (millis, rest) = match rest.strip_prefix('.') {
        Some(frac) => {
            let n = frac.bytes().take_while(u8::is_ascii_digit).count();
            if n == 0 {
                return None;
            }
            let first3: String = frac
                .get(..n)?
                .chars()
                .chain("000".chars())
                .take(3)
                .collect();
            (first3.parse().ok()?, frac.get(n..)?)
        }
        None => (0, rest),
    };
    if rest == "Z" || rest == "z" {
        return Some((millis, 0));
    }
    let sign = match rest.as_bytes().first()? {
        b'+' => 1,
        b'-' => -1,
        _ => return None,
    };
    let (h, m) = rest.get(1..)?.split_once(':')?;
    let ok = |s: &str, max: i64| -> Option<i64> {
        (s.len() == 2 && s.bytes().all(|c| c.is_ascii_digit()))
            .then(|| s.parse().ok())
            .flatten()
            .filter(|v| *v <= max)
    };
    Some((millis, sign * (ok(h, 23)? * 60 + ok(m, 59)?)))
}

/// Days in `month` of `year` (proleptic Gregorian).
fn days_in_month(year: i64, month: i64) -> i64 {
    match month {
        2 if (year % 4 == 0 && year % 100 != 0) || year % 400 == 0 => 29,
        2 => 28,
        4 | 6 | 9 | 11 => 30,
        _ => 31,
    }
}
