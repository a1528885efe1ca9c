//! NMEA 0183 sentences from a GNSS receiver: GGA, RMC, VTG and GST, checksums verified.
//!
//! [`parse`] reads one sentence (`$GPGGA,...*hh`, any talker). [`FixAssembler`] joins the
//! sentences of one epoch into a [`Fix`]: it emits as soon as the epoch has a position (GGA)
//! and a velocity (RMC or VTG), taking the error ellipse of a GST of the same epoch when one
//! came first. Panic contract: nothing here panics on any input; a bad sentence is an
//! [`NmeaError`] that says what is wrong.
//!
//! Written by hand rather than with an NMEA crate: the same parser runs in the `no_std`
//! firmware (no heap, a sentence at a time from the USART) and in the daemon, keeps the
//! receiver's own accuracy (GST) and UTC date with the fix, and refuses every malformed
//! field with a reason from a closed set instead of a default value.

use crate::fix::Fix;
use crate::geo::LatLon;
use crate::time::UtcTime;

/// Longest sentence accepted (the standard says 82 characters; receivers exceed it a little).
pub const MAX_SENTENCE: usize = 120;
const KNOTS_TO_MPS: f32 = 0.514_444;

/// Why a sentence was refused.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum NmeaError {
    /// Longer than [`MAX_SENTENCE`].
    TooLong,
    /// Does not start with `$` (or `!`) and a five-letter address.
    BadStart,
    /// No `*hh` checksum.
    MissingChecksum,
    /// The checksum does not match the sentence.
    BadChecksum,
    /// A field the sentence type needs is missing or malformed (its index).
    BadField(u8),
    /// A sentence type this parser does not read.
    Unsupported,
}

impl NmeaError {
    /// A short lowercase name, for counters and logs.
    pub const fn as_str(self) -> &'static str {
        match self {
            Self::TooLong => "too long",
            Self::BadStart => "bad start",
            Self::MissingChecksum => "missing checksum",
            Self::BadChecksum => "bad checksum",
            Self::BadField(_) => "bad field",
            Self::Unsupported => "unsupported sentence",
        }
    }
}

impl core::fmt::Display for NmeaError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            Self::BadField(i) => write!(f, "bad field {i}"),
            other => f.write_str(other.as_str()),
        }
    }
}

/// UTC time of day, milliseconds since midnight.
pub type DayMillis = u32;

/// GGA: position and fix quality.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Gga {
    /// Time of the fix.
    pub time: DayMillis,
    /// Position, when the receiver has one.
    pub position: Option<LatLon>,
    /// Fix quality: 0 invalid, 1 GPS, 2 DGPS, 4 RTK fixed, 5 RTK float, 6 dead reckoning.
    pub quality: u8,
    /// Satellites used.
    pub satellites: u8,
    /// Horizontal dilution of precision.
    pub hdop: Option<f32>,
    /// Altitude above mean sea level, metres.
    pub altitude_m: Option<f32>,
}

/// RMC: position, speed, course and date.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Rmc {
    /// Time of the fix.
    pub time: DayMillis,
    /// True when the receiver marks the data valid (`A`).
    pub valid: bool,
    /// Position.
    pub position: Option<LatLon>,
    /// Speed over ground, m/s.
    pub speed_mps: Option<f32>,
    /// Course over ground, degrees from true north.
    pub course_deg: Option<f32>,
    /// Date: (year, month, day).
    pub date: Option<(u16, u8, u8)>,
}

/// VTG: course and speed over ground.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Vtg {
    /// Course over ground, degrees from true north.
    pub course_deg: Option<f32>,
    /// Speed over ground, m/s.
    pub speed_mps: Option<f32>,
}

/// GST: pseudorange error statistics (1-sigma, metres).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Gst {
    /// Time of the fix.
    pub time: DayMillis,
    /// Standard deviation of latitude error.
    pub lat_sd_m: Option<f32>,
    /// Standard deviation of longitude error.
    pub lon_sd_m: Option<f32>,
}

impl Gst {
    /// Horizontal 1-sigma accuracy: the root of the summed variances.
    pub fn horizontal_m(&self) -> Option<f32> {
        let (a, b) = (self.lat_sd_m?, self.lon_sd_m?);
        Some(libm::sqrtf(a * a + b * b))
    }
}

/// One parsed sentence.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Sentence {
    /// Global positioning fix data.
    Gga(Gga),
    /// Recommended minimum data.
    Rmc(Rmc),
    /// Course and speed.
    Vtg(Vtg),
    /// Error statistics.
    Gst(Gst),
}

/// Parses one sentence (surrounding whitespace and CR/LF ignored).
pub fn parse(line: &str) -> Result<Sentence, NmeaError> {
    let line = line.trim();
    if line.len() > MAX_SENTENCE {
        return Err(NmeaError::TooLong);
    }
    let body = checked_body(line)?;
    let mut fields = body.split(',');
    let address = fields.next().ok_or(NmeaError::BadStart)?;
    if address.len() != 5 || !address.is_ascii() {
        return Err(NmeaError::BadStart);
    }
    let mut f = Fields::new(fields);
    match &address[2..] {
        "GGA" => parse_gga(&mut f).map(Sentence::Gga),
        "RMC" => parse_rmc(&mut f).map(Sentence::Rmc),
        "VTG" => parse_vtg(&mut f).map(Sentence::Vtg),
        "GST" => parse_gst(&mut f).map(Sentence::Gst),
        _ => Err(NmeaError::Unsupported),
    }
}

/// The text between `$` and `*` once the checksum matches.
fn checked_body(line: &str) -> Result<&str, NmeaError> {
    let rest = line
        .strip_prefix('$')
        .or_else(|| line.strip_prefix('!'))
        .ok_or(NmeaError::BadStart)?;
    let (body, sum) = rest.rsplit_once('*').ok_or(NmeaError::MissingChecksum)?;
    let want = u8::from_str_radix(sum, 16).map_err(|_| NmeaError::MissingChecksum)?;
    if sum.len() != 2 {
        return Err(NmeaError::MissingChecksum);
    }
    let got = body.bytes().fold(0u8, |acc, b| acc ^ b);
    if got != want {
        return Err(NmeaError::BadChecksum);
    }
    Ok(body)
}

/// The comma-separated fields after the address, with their index for errors.
struct Fields<'a, I: Iterator<Item = &'a str>> {
    it: I,
    index: u8,
}

impl<'a, I: Iterator<Item = &'a str>> Fields<'a, I> {
    fn new(it: I) -> Self {
        Self { it, index: 0 }
    }

    /// The next field; empty when the sentence ends early.
    fn next(&mut self) -> (u8, &'a str) {
        self.index = self.index.saturating_add(1);
        (self.index, self.it.next().unwrap_or(""))
    }

    fn optional_f32(&mut self) -> Result<Option<f32>, NmeaError> {
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

    fn time(&mut self) -> Result<DayMillis, NmeaError> {
        let (i, s) = self.next();
        parse_time(s).ok_or(NmeaError::BadField(i))
    }

    /// Latitude/longitude field pairs; `None` when all four are empty.
    fn position(&mut self) -> Result<Option<LatLon>, NmeaError> {
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

    fn skip(&mut self, n: usize) {
        for _ in 0..n {
            self.next();
        }
    }
}

/// `hhmmss.sss` as milliseconds of the day.
fn parse_time(s: &str) -> Option<DayMillis> {
    if s.len() < 6 || !s.is_char_boundary(6) {
        return None;
    }
    let (hms, frac) = s.split_at(6);
    let n: u32 = hms.parse().ok()?;
    let (h, m, sec) = (n / 10_000, n / 100 % 100, n % 100);
    if h > 23 || m > 59 || sec > 60 {
        return None;
    }
    let ms = match frac.strip_prefix('.') {
        None if frac.is_empty() => 0,
        Some(d) if !d.is_empty() && d.len() <= 9 && d.bytes().all(|b| b.is_ascii_digit()) => {
            let first3: u32 = d.get(..d.len().min(3))?.parse().ok()?;
            first3 * [100, 10, 1][d.len().min(3) - 1]
        }
        _ => return None,
    };
    Some(((h * 60 + m) * 60 + sec) * 1000 + ms)
}

/// A plain decimal number as NMEA writes it: an optional sign, digits, an optional point
/// and digits (at most 15 digits in all; no exponent, no `inf` or `nan`).
///
/// Hand-written rather than `str::parse::<f64>`: the standard parser brings about 12 KB of
/// tables and code into the firmware for forms NMEA never uses. Up to 15 digits make an
/// integer below 2^53, exact in f64, divided once by an exact power of ten, so the result
/// is correctly rounded (receivers write 9-12 digits).
fn decimal(s: &str) -> Option<f64> {
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

fn parse_gga<'a>(f: &mut Fields<'a, impl Iterator<Item = &'a str>>) -> Result<Gga, NmeaError> {
    let time = f.time()?;
    let position = f.position()?;
    let (i, q) = f.next();
    let quality = q.parse().map_err(|_| NmeaError::BadField(i))?;
    let (j, n) = f.next();
    let satellites = if n.is_empty() {
        0
    } else {
        n.parse().map_err(|_| NmeaError::BadField(j))?
    };
    let hdop = f.optional_f32()?;
    let altitude_m = f.optional_f32()?;
    let position = if quality == 0 { None } else { position };
    Ok(Gga {
        time,
        position,
        quality,
        satellites,
        hdop,
        altitude_m,
    })
}

fn parse_rmc<'a>(f: &mut Fields<'a, impl Iterator<Item = &'a str>>) -> Result<Rmc, NmeaError> {
    let time = f.time()?;
    let (i, status) = f.next();
    let valid = match status {
        "A" => true,
        "V" => false,
        _ => return Err(NmeaError::BadField(i)),
    };
    let position = f.position()?;
    let speed_mps = f.optional_f32()?.map(|k| k * KNOTS_TO_MPS);
    let course_deg = f.optional_f32()?;
    let (j, d) = f.next();
    let date = if d.is_empty() {
        None
    } else {
        Some(parse_date(d).ok_or(NmeaError::BadField(j))?)
    };
    Ok(Rmc {
        time,
        valid,
        position,
        speed_mps,
        course_deg,
        date,
    })
}

/// `ddmmyy` as (year, month, day), years 80-99 read as 19xx.
fn parse_date(s: &str) -> Option<(u16, u8, u8)> {
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

fn parse_vtg<'a>(f: &mut Fields<'a, impl Iterator<Item = &'a str>>) -> Result<Vtg, NmeaError> {
    let course_deg = f.optional_f32()?;
    f.skip(3); // "T", magnetic course, "M"
    let knots = f.optional_f32()?;
    f.skip(1); // "N"
    let kmh = f.optional_f32()?;
    let speed_mps = kmh.map(|v| v / 3.6).or(knots.map(|k| k * KNOTS_TO_MPS));
    Ok(Vtg {
        course_deg,
        speed_mps,
    })
}

fn parse_gst<'a>(f: &mut Fields<'a, impl Iterator<Item = &'a str>>) -> Result<Gst, NmeaError> {
    let time = f.time()?;
    f.skip(4); // rms, semi-major, semi-minor, orientation
    let lat_sd_m = f.optional_f32()?;
    let lon_sd_m = f.optional_f32()?;
    Ok(Gst {
        time,
        lat_sd_m,
        lon_sd_m,
    })
}

/// The UTC time of a calendar date and a time of day; `None` for an impossible date.
pub fn utc_from_date(year: u16, month: u8, day: u8, ms_of_day: u32) -> Option<UtcTime> {
    if !(1..=12).contains(&month) || !(1..=31).contains(&day) || ms_of_day >= 86_401_000 {
        return None;
    }
    let days = days_before_month(year, month) + u32::from(day) - 1;
    Some(UtcTime {
        year,
        ms_of_year: u64::from(days) * 86_400_000 + u64::from(ms_of_day),
    })
}

/// Days from 1 January to the first of `month` (1-12).
fn days_before_month(year: u16, month: u8) -> u32 {
    const CUM: [u32; 12] = [0, 31, 59, 90, 120, 151, 181, 212, 243, 273, 304, 334];
    let leap = (year.is_multiple_of(4) && !year.is_multiple_of(100)) || year.is_multiple_of(400);
    let base = CUM
        .get(usize::from(month.saturating_sub(1)))
        .copied()
        .unwrap_or(0);
    base + u32::from(leap && month > 2)
}

/// Joins the sentences of one epoch into fixes.
#[derive(Clone, Debug, Default)]
pub struct FixAssembler {
    time: Option<DayMillis>,
    gga: Option<Gga>,
    velocity: Option<(Option<f32>, Option<f32>)>,
    accuracy_m: Option<f32>,
    date: Option<(u16, u8, u8)>,
    emitted: bool,
}

impl FixAssembler {
    /// An assembler with nothing seen.
    pub const fn new() -> Self {
        Self {
            time: None,
            gga: None,
            velocity: None,
            accuracy_m: None,
            date: None,
            emitted: false,
        }
    }

    /// The fix quality of the last GGA (0 before any).
    pub fn quality(&self) -> u8 {
        self.gga.map_or(0, |g| g.quality)
    }

    /// Takes one sentence; returns a fix when its epoch is complete.
    pub fn push(&mut self, s: &Sentence) -> Option<Fix> {
        match *s {
            Sentence::Gga(g) => {
                self.epoch(g.time);
                self.gga = Some(g);
            }
            Sentence::Rmc(r) => {
                self.epoch(r.time);
                self.date = r.date.or(self.date);
                self.velocity = Some((r.speed_mps, r.course_deg));
            }
            Sentence::Vtg(v) => {
                if self.velocity.is_none() {
                    self.velocity = Some((v.speed_mps, v.course_deg));
                }
            }
            Sentence::Gst(g) => {
                self.epoch(g.time);
                self.accuracy_m = g.horizontal_m();
            }
        }
        self.ready()
    }

    /// Starts a new epoch when `time` differs from the current one.
    fn epoch(&mut self, time: DayMillis) {
        if self.time != Some(time) {
            self.time = Some(time);
            self.gga = None;
            self.velocity = None;
            self.accuracy_m = None;
            self.emitted = false;
        }
    }

    fn ready(&mut self) -> Option<Fix> {
        if self.emitted {
            return None;
        }
        let gga = self.gga?;
        let (speed_mps, course_deg) = self.velocity?;
        let position = gga.position?;
        self.emitted = true;
        Some(Fix {
            position,
            accuracy_m: self.accuracy_m.or_else(|| gga.hdop.map(|h| h * 2.0)),
            speed_mps,
            course_deg,
            utc: self.utc(gga.time),
        })
    }

    fn utc(&self, time: DayMillis) -> Option<UtcTime> {
        let (year, month, day) = self.date?;
        utc_from_date(year, month, day, time)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Appends the checksum to a sentence body written without it.
    fn with_sum(body: &str) -> heapless::String<128> {
        let sum = body.bytes().fold(0u8, |a, b| a ^ b);
        let mut s = heapless::String::new();
        core::fmt::write(&mut s, format_args!("${body}*{sum:02X}")).unwrap();
        s
    }

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
    fn gga_position_and_quality() {
        let s = with_sum("GPGGA,123519.50,4807.038,N,01131.000,E,4,08,0.9,545.4,M,46.9,M,,");
        let Sentence::Gga(g) = parse(&s).unwrap() else {
            panic!("not GGA")
        };
        assert_eq!(g.time, ((12 * 60 + 35) * 60 + 19) * 1000 + 500);
        let p = g.position.unwrap();
        assert_eq!(p.lat_e7(), 481_173_000);
        assert_eq!(p.lon_e7(), 115_166_667);
        assert_eq!((g.quality, g.satellites), (4, 8));
        assert_eq!(g.hdop, Some(0.9));
    }

    #[test]
    fn southern_western_hemispheres_are_negative() {
        let s = with_sum("GNGGA,000000,3351.500,S,15112.000,W,1,05,1.2,10.0,M,,M,,");
        let Sentence::Gga(g) = parse(&s).unwrap() else {
            panic!("not GGA")
        };
        let p = g.position.unwrap();
        assert_eq!(p.lat_e7(), -338_583_333);
        assert_eq!(p.lon_e7(), -1_512_000_000);
    }

    #[test]
    fn checksum_is_verified() {
        let mut s = with_sum("GPGGA,123519,4807.038,N,01131.000,E,1,08,0.9,545.4,M,46.9,M,,");
        assert!(parse(&s).is_ok());
        let n = s.len();
        let last = if s.as_bytes()[n - 1] == b'0' {
            '1'
        } else {
            '0'
        };
        s.truncate(n - 1);
        s.push(last).unwrap();
        assert_eq!(parse(&s), Err(NmeaError::BadChecksum));
        assert_eq!(
            parse("$GPGGA,123519,4807.038,N"),
            Err(NmeaError::MissingChecksum)
        );
        assert_eq!(parse("GPGGA,1*00"), Err(NmeaError::BadStart));
    }

    #[test]
    fn rmc_speed_course_date() {
        let s = with_sum("GPRMC,123519,A,4807.038,N,01131.000,E,022.4,084.4,230394,003.1,W");
        let Sentence::Rmc(r) = parse(&s).unwrap() else {
            panic!("not RMC")
        };
        assert!(r.valid);
        assert!((r.speed_mps.unwrap() - 22.4 * KNOTS_TO_MPS).abs() < 1e-4);
        assert_eq!(r.course_deg, Some(84.4));
        assert_eq!(r.date, Some((1994, 3, 23)));
    }

    #[test]
    fn vtg_prefers_kmh_and_gst_combines_axes() {
        let s = with_sum("GPVTG,054.7,T,034.4,M,005.5,N,010.2,K");
        let Sentence::Vtg(v) = parse(&s).unwrap() else {
            panic!("not VTG")
        };
        assert!((v.speed_mps.unwrap() - 10.2 / 3.6).abs() < 1e-5);
        let s = with_sum("GPGST,172814.0,0.006,0.023,0.020,273.6,0.3,0.4,0.031");
        let Sentence::Gst(g) = parse(&s).unwrap() else {
            panic!("not GST")
        };
        assert!((g.horizontal_m().unwrap() - 0.5).abs() < 1e-6);
    }

    #[test]
    fn garbage_is_an_error_never_a_panic() {
        for line in [
            "",
            "$",
            "$*",
            "$GPGGA*",
            "$GPGGA,99999,,,,,,*00",
            "$é€€€€,*00",
            "$GPXYZ,1*5A",
        ] {
            let _ = parse(line);
        }
        assert_eq!(parse(&with_sum("GPXYZ,1")), Err(NmeaError::Unsupported));
        assert_eq!(
            parse(&with_sum("GPRMC,123519,X,,,,,,,")),
            Err(NmeaError::BadField(2))
        );
        let long = [b'A'; MAX_SENTENCE + 1];
        assert_eq!(
            parse(core::str::from_utf8(&long).unwrap()),
            Err(NmeaError::TooLong)
        );
    }

    #[test]
    fn assembler_emits_once_per_epoch_with_accuracy_and_utc() {
        let mut a = FixAssembler::new();
        let gst = parse(&with_sum("GPGST,120000.00,0.5,0.6,0.4,10.0,0.6,0.8,1.0")).unwrap();
        let gga = parse(&with_sum(
            "GPGGA,120000.00,4807.038,N,01131.000,E,4,12,0.6,545.4,M,46.9,M,,",
        ))
        .unwrap();
        let rmc = parse(&with_sum(
            "GPRMC,120000.00,A,4807.038,N,01131.000,E,010.0,090.0,020124,,",
        ))
        .unwrap();
        assert_eq!(a.push(&gst), None);
        assert_eq!(a.push(&gga), None);
        let fix = a.push(&rmc).expect("GGA + RMC complete the epoch");
        assert!((fix.accuracy_m.unwrap() - 1.0).abs() < 1e-6);
        assert_eq!(fix.course_deg, Some(90.0));
        let utc = fix.utc.unwrap();
        assert_eq!(utc.year, 2024);
        assert_eq!(utc.ms_of_year, 86_400_000 + 12 * 3_600_000);
        assert_eq!(a.push(&rmc), None, "one fix per epoch");
        assert_eq!(a.quality(), 4);
    }

    #[test]
    fn leap_year_months() {
        assert_eq!(days_before_month(2024, 3), 60);
        assert_eq!(days_before_month(2023, 3), 59);
        assert_eq!(days_before_month(2000, 12), 335);
    }
}
