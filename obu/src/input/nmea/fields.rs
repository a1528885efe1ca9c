//! The field readers of NMEA 0183 sentences: decimals, angles, times and dates, each
//! refusing a malformed field with its index instead of a default value.

use super::{DayMillis, NmeaError};
use crate::geo::LatLon;

/// The comma-separated fields after the address, with their index for errors.
pub(super) struct Fields<'a, I: Iterator<Item = &'a str>> {
    it: I,
    index: u8,
}

impl<'a, I: Iterator<Item = &'a str>> Fields<'a, I> {
    pub(super) fn new(it: I) -> Self {
        Self { it, index: 0 }
    }

    /// The next field; empty when the sentence ends early.
    pub(super) fn next(&mut self) -> (u8, &'a str) {
        self.index = self.index.saturating_add(1);
        (self.index, self.it.next().unwrap_or(""))
    }

    /// The index the next field will have.
    pub(super) fn index_next(&self) -> u8 {
        self.index.saturating_add(1)
    }

    pub(super) fn optional_f32(&mut self) -> Result<Option<f32>, NmeaError> {
        let (i, s) = self.next();
        if s.is_empty() {
            return Ok(None);
        }
        let v = decimal(s).ok_or(NmeaError::BadField(i))? as f32;
        if v.is_finite() {
            Ok(Some(v))
        } else {
            Err(NmeaError::BadField(i))
        }
    }

    /// A small unsigned integer field (quality, satellites, fix mode); `None` when empty.
    pub(super) fn optional_u8(&mut self) -> Result<Option<u8>, NmeaError> {
        let (i, s) = self.next();
        if s.is_empty() {
            return Ok(None);
        }
        if s.len() > 3 || !s.bytes().all(|b| b.is_ascii_digit()) {
            return Err(NmeaError::BadField(i));
        }
        s.parse().map(Some).map_err(|_| NmeaError::BadField(i))
    }

    /// A single-letter field; `None` when empty.
    pub(super) fn optional_letter(&mut self) -> Result<Option<u8>, NmeaError> {
        let (i, s) = self.next();
        match s.as_bytes() {
            [] => Ok(None),
            [b] if b.is_ascii_uppercase() => Ok(Some(*b)),
            _ => Err(NmeaError::BadField(i)),
        }
    }

    /// `hhmmss[.sss]`; `None` when empty (receivers without a fix often leave it empty).
    pub(super) fn optional_time(&mut self) -> Result<Option<DayMillis>, NmeaError> {
        let (i, s) = self.next();
        if s.is_empty() {
            return Ok(None);
        }
        parse_time(s).map(Some).ok_or(NmeaError::BadField(i))
    }

    /// Latitude/longitude field pairs; `None` when both are empty.
    pub(super) fn position(&mut self) -> Result<Option<LatLon>, NmeaError> {
        let (i, lat) = self.next();
        let (_, ns) = self.next();
        let (j, lon) = self.next();
        let (_, ew) = self.next();
        if lat.is_empty() && lon.is_empty() {
            return Ok(None);
        }
        let lat = angle(lat, 2, ns, 'N', 'S').ok_or(NmeaError::BadField(i))?;
        let lon = angle(lon, 3, ew, 'E', 'W').ok_or(NmeaError::BadField(j))?;
        LatLon::from_degrees(lat, lon)
            .map(Some)
            .ok_or(NmeaError::BadField(i))
    }

    pub(super) fn skip(&mut self, n: usize) {
        for _ in 0..n {
            self.next();
        }
    }
}

/// `hhmmss.sss` as milliseconds of the day.
pub(super) fn parse_time(s: &str) -> Option<DayMillis> {
    if s.len() < 6 || !s.is_char_boundary(6) {
        return None;
    }
    let (hms, frac) = s.split_at(6);
    if !hms.bytes().all(|b| b.is_ascii_digit()) {
        return None;
    }
    let n: u32 = hms.parse().ok()?;
    let (h, m, sec) = (n / 10_000, n / 100 % 100, n % 100);
    if h > 23 || m > 59 || sec > 60 {
        return None;
    }
    let ms = match frac.strip_prefix('.') {
        None if frac.is_empty() => 0,
        Some("") => 0,
        Some(d) if d.len() <= 9 && d.bytes().all(|b| b.is_ascii_digit()) => {
            let first3: u32 = d.get(..d.len().min(3))?.parse().ok()?;
            first3 * [100, 10, 1][d.len().min(3) - 1]
        }
        _ => return None,
    };
    Some(((h * 60 + m) * 60 + sec) * 1000 + ms)
}

/// `ddmmyy` as (year, month, day), years 80-99 read as 19xx.
pub(super) fn parse_date(s: &str) -> Option<(u16, u8, u8)> {
    if s.len() != 6 || !s.bytes().all(|b| b.is_ascii_digit()) {
        return None;
    }
    let n: u32 = s.parse().ok()?;
    let (d, m, y) = (n / 10_000, n / 100 % 100, n % 100);
    if !(1..=31).contains(&d) || !(1..=12).contains(&m) {
        return None;
    }
    let year = if y >= 80 { 1900 + y } else { 2000 + y };
    Some((year as u16, m as u8, d as u8))
}

/// A plain decimal number as NMEA writes it: an optional sign, digits, an optional point
/// and digits (at most 15 digits in all; no exponent, no `inf` or `nan`).
///
/// Hand-written rather than `str::parse::<f64>`: the standard parser brings kilobytes of
/// tables and code into the firmware for forms NMEA never uses. Up to 15 digits make an
/// integer below 2^53, exact in f64, divided once by an exact power of ten, so the result
/// is correctly rounded (receivers write 9-12 digits).
pub(super) fn decimal(s: &str) -> Option<f64> {
    let (negative, body) = match s.as_bytes().first()? {
        b'-' => (true, &s[1..]),
        b'+' => (false, &s[1..]),
        _ => (false, s),
    };
    let (int, frac) = match body.split_once('.') {
        Some((i, f)) => (i, f),
        None => (body, ""),
    };
    if (int.is_empty() && frac.is_empty()) || int.len() + frac.len() > 15 {
        return None;
    }
    let mut n: u64 = 0;
    for b in int.bytes().chain(frac.bytes()) {
        if !b.is_ascii_digit() {
            return None;
        }
        n = n * 10 + u64::from(b - b'0');
    }
    let v = n as f64 / POWERS_OF_TEN[frac.len()];
    Some(if negative { -v } else { v })
}

/// 10^0 to 10^18, each exact in f64.
const POWERS_OF_TEN: [f64; 19] = [
    1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9, 1e10, 1e11, 1e12, 1e13, 1e14, 1e15, 1e16,
    1e17, 1e18,
];

/// `dddmm.mmmm` with its hemisphere letter, in signed degrees.
fn angle(s: &str, deg_digits: usize, hemi: &str, pos: char, neg: char) -> Option<f64> {
    if s.len() < deg_digits + 2 || !s.is_char_boundary(deg_digits) {
        return None;
    }
    let (d, m) = s.split_at(deg_digits);
    if !d.bytes().all(|b| b.is_ascii_digit()) {
        return None;
    }
    let d = decimal(d)?;
    let m = decimal(m)?;
    if !(0.0..60.0).contains(&m) || !d.is_finite() {
        return None;
    }
    let v = d + m / 60.0;
    match hemi.chars().next()? {
        c if c == pos => Some(v),
        c if c == neg => Some(-v),
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn decimals_read_as_the_standard_parser_reads_them() {
        for text in [
            "0",
            "7",
            "4807.038",
            "01131.000",
            "-12.5",
            "+0.25",
            ".5",
            "5.",
            "000.0000001",
            "123456789.123456",
            "9825979.19074833",
            "59.99999999",
        ] {
            let want: f64 = text.parse().unwrap_or(f64::NAN);
            assert_eq!(decimal(text), Some(want), "{text}");
        }
        for text in [
            "",
            "-",
            "+",
            ".",
            "1e5",
            "inf",
            "nan",
            "1.2.3",
            "12a",
            " 1",
            "1 ",
            "--1",
            "1234567890123456",
            "0.1234567890123456",
        ] {
            assert_eq!(decimal(text), None, "{text:?}");
        }
    }

    #[test]
    fn times_with_and_without_fractions() {
        assert_eq!(parse_time("123519"), Some(45_319_000));
        assert_eq!(parse_time("123519."), Some(45_319_000));
        assert_eq!(parse_time("123519.5"), Some(45_319_500));
        assert_eq!(parse_time("123519.250"), Some(45_319_250));
        assert_eq!(parse_time("235960.00"), Some(86_400_000), "a leap second");
        for bad in ["12351", "243000", "126000", "12a519", "123519.x", "+23519"] {
            assert_eq!(parse_time(bad), None, "{bad}");
        }
        assert_eq!(parse_date("230394"), Some((1994, 3, 23)));
        assert_eq!(parse_date("010125"), Some((2025, 1, 1)));
        assert_eq!(parse_date("320125"), None);
    }
}
