//! NMEA 0183 sentences from a GNSS receiver, checksums verified: GGA, RMC, GNS, GLL (the
//! position sentences), GSA (fix mode and dilutions), GST (error statistics), VTG (course
//! and speed) and ZDA (date), from any talker (GP, GL, GA, GB, BD, GN, GQ, ...), with the
//! NMEA 2.3 mode indicators and the 4.1 navigational status.
//!
//! [`parse`] reads one sentence (`$GPGGA,...*hh`). [`FixAssembler`] joins the sentences of
//! one epoch (one time stamp) into a fix or the reason there is none. Panic contract:
//! nothing here panics on any input; a bad sentence is an [`NmeaError`] that says what is
//! wrong.
//!
//! Written by hand rather than with an NMEA crate: the same parser runs in the `no_std`
//! firmware (no heap, a sentence at a time from the USART) and in the daemon, keeps what
//! each receiver says of its own solution (simulator, dead reckoning, RTK float/fixed),
//! its accuracy (GST) and the UTC date with the fix, and refuses every malformed field
//! with a reason from a closed set instead of a default value.

mod epoch;
mod fields;

pub use epoch::{AccuracyModel, Epoch, EpochOutcome, FixAssembler, NoFix};

pub use crate::fix::AccuracySource;
use crate::geo::LatLon;
use crate::time::UtcTime;
use fields::{parse_date, Fields};

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

/// What a receiver says of the solution behind a position: GGA's quality, RMC's and GLL's
/// status, the NMEA 2.3 mode indicator (RMC, GLL, VTG, GNS) and the 4.1 navigational
/// status.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Solution {
    /// Measured, stand-alone (GGA 1, mode `A`).
    Autonomous,
    /// Measured with differential corrections: SBAS, DGPS (GGA 2 and 9, mode `D`).
    Differential,
    /// Precise (P-code, GGA 3, mode `P`).
    Precise,
    /// RTK with fixed integer ambiguities (GGA 4, mode `R`).
    RtkFixed,
    /// RTK with float ambiguities (GGA 5, mode `F`).
    RtkFloat,
    /// No fix (GGA 0, status `V`, mode `N`).
    Invalid,
    /// The receiver's own dead reckoning (GGA 6, mode `E`): not a measured position.
    Estimated,
    /// A position entered by hand (GGA 7, mode `M`).
    Manual,
    /// The receiver's simulator (GGA 8, mode `S`): not the vehicle.
    Simulator,
    /// Navigational status `U`: the receiver's integrity monitor says unsafe.
    Unsafe,
    /// A measured quality with no satellite used (GGA satellites 0): the receiver is
    /// coasting, not measuring.
    NoSatellites,
}

impl Solution {
    /// True for a measured position the OBU may use.
    pub const fn is_measured(self) -> bool {
        matches!(
            self,
            Self::Autonomous | Self::Differential | Self::Precise | Self::RtkFixed | Self::RtkFloat
        )
    }

    /// A short lowercase name, for `/api/status`, counters and logs.
    pub const fn as_str(self) -> &'static str {
        match self {
            Self::Autonomous => "autonomous",
            Self::Differential => "differential",
            Self::Precise => "precise",
            Self::RtkFixed => "rtk fixed",
            Self::RtkFloat => "rtk float",
            Self::Invalid => "no fix",
            Self::Estimated => "receiver dead reckoning",
            Self::Manual => "manual",
            Self::Simulator => "simulator",
            Self::Unsafe => "unsafe",
            Self::NoSatellites => "no satellites",
        }
    }

    /// The GGA quality indicator that names this solution.
    pub const fn gga_quality(self) -> u8 {
        match self {
            Self::Autonomous => 1,
            Self::Differential => 2,
            Self::Precise => 3,
            Self::RtkFixed => 4,
            Self::RtkFloat => 5,
            Self::Estimated => 6,
            Self::Manual => 7,
            Self::Simulator => 8,
            Self::Invalid | Self::Unsafe | Self::NoSatellites => 0,
        }
    }

    /// The solution of a GGA quality indicator; `None` for a value no receiver defines.
    pub const fn from_gga_quality(q: u8) -> Option<Self> {
        Some(match q {
            0 => Self::Invalid,
            1 => Self::Autonomous,
            2 | 9 => Self::Differential,
            3 => Self::Precise,
            4 => Self::RtkFixed,
            5 => Self::RtkFloat,
            6 => Self::Estimated,
            7 => Self::Manual,
            8 => Self::Simulator,
            _ => return None,
        })
    }

    /// The solution of an NMEA 2.3 mode indicator letter; `None` for an unknown letter.
    pub const fn from_mode(letter: u8) -> Option<Self> {
        Some(match letter {
            b'A' => Self::Autonomous,
            b'D' => Self::Differential,
            b'P' => Self::Precise,
            b'R' => Self::RtkFixed,
            b'F' => Self::RtkFloat,
            b'N' => Self::Invalid,
            b'E' => Self::Estimated,
            b'M' => Self::Manual,
            b'S' => Self::Simulator,
            _ => return None,
        })
    }

    /// The more specific of two indications for one position: a non-measured one (the
    /// receiver's warning) wins over a measured one, and a better measured one over a
    /// plainer one.
    const fn rank(self) -> u8 {
        match self {
            Self::Simulator => 10,
            Self::NoSatellites => 9,
            Self::Manual => 8,
            Self::Estimated => 7,
            Self::Unsafe => 6,
            Self::Invalid => 5,
            Self::RtkFixed => 4,
            Self::RtkFloat => 3,
            Self::Differential | Self::Precise => 2,
            Self::Autonomous => 1,
        }
    }

    /// Combines what two indications of one position say: a receiver's warning (simulator,
    /// manual, dead reckoning, unsafe, no fix) wins over a measured indication, a better
    /// measured one over a plainer one.
    pub const fn with(self, other: Self) -> Self {
        if other.rank() > self.rank() {
            other
        } else {
            self
        }
    }
}

/// The 4.1 navigational status letter as a solution: `U` (unsafe) warns; `S` (safe), `C`
/// (caution) and `V` ("not valid": the receiver gives no navigational status) say nothing
/// against the fix.
fn nav_status(letter: Option<u8>, index: u8) -> Result<Option<Solution>, NmeaError> {
    match letter {
        None | Some(b'S' | b'C' | b'V') => Ok(None),
        Some(b'U') => Ok(Some(Solution::Unsafe)),
        Some(_) => Err(NmeaError::BadField(index)),
    }
}

/// GGA: position, fix quality, satellites, HDOP, altitude.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Gga {
    /// Time of the fix (empty in some receivers' no-fix sentences).
    pub time: Option<DayMillis>,
    /// Position, when the receiver sends one.
    pub position: Option<LatLon>,
    /// The quality indicator; `None` when the field is empty.
    pub quality: Option<u8>,
    /// Satellites used; `None` when the field is empty.
    pub satellites: Option<u8>,
    /// Horizontal dilution of precision.
    pub hdop: Option<f32>,
    /// Altitude above mean sea level, metres.
    pub altitude_m: Option<f32>,
}

/// RMC: position, speed, course and date.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Rmc {
    /// Time of the fix.
    pub time: Option<DayMillis>,
    /// True when the receiver marks the data valid (`A`).
    pub valid: bool,
    /// Position.
    pub position: Option<LatLon>,
    /// Speed over ground, m/s.
    pub speed_mps: Option<f32>,
    /// Course over ground, degrees from true north.
    pub course_deg: Option<f32>,
    /// Date: (year, month, day); `None` when empty or malformed.
    pub date: Option<(u16, u8, u8)>,
    /// The NMEA 2.3 mode indicator with the 4.1 navigational status, when sent.
    pub mode: Option<Solution>,
}

/// GNS: the multi-constellation fix (one mode letter per constellation).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Gns {
    /// Time of the fix.
    pub time: Option<DayMillis>,
    /// Position.
    pub position: Option<LatLon>,
    /// The best mode of the constellations, with the navigational status.
    pub mode: Solution,
    /// Satellites used.
    pub satellites: u8,
    /// Horizontal dilution of precision.
    pub hdop: Option<f32>,
    /// Altitude above mean sea level, metres.
    pub altitude_m: Option<f32>,
}

/// GLL: position with its status.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Gll {
    /// Time of the fix.
    pub time: Option<DayMillis>,
    /// Position.
    pub position: Option<LatLon>,
    /// Status `A` (valid) with the 2.3 mode indicator when sent.
    pub solution: Solution,
}

/// GSA: fix mode and dilutions of precision.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Gsa {
    /// 1 no fix, 2 2D, 3 3D.
    pub fix_mode: Option<u8>,
    /// Position dilution of precision.
    pub pdop: Option<f32>,
    /// Horizontal dilution of precision.
    pub hdop: Option<f32>,
    /// Vertical dilution of precision.
    pub vdop: Option<f32>,
}

/// VTG: course and speed over ground.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Vtg {
    /// Course over ground, degrees from true north.
    pub course_deg: Option<f32>,
    /// Speed over ground, m/s.
    pub speed_mps: Option<f32>,
    /// The 2.3 mode indicator, when sent.
    pub mode: Option<Solution>,
}

/// GST: pseudorange error statistics (1-sigma, metres).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Gst {
    /// Time of the fix.
    pub time: Option<DayMillis>,
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

/// ZDA: time and date.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Zda {
    /// Time of day.
    pub time: Option<DayMillis>,
    /// Date: (year, month, day).
    pub date: Option<(u16, u8, u8)>,
}

/// One parsed sentence.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Sentence {
    /// Global positioning fix data.
    Gga(Gga),
    /// Recommended minimum data.
    Rmc(Rmc),
    /// GNSS fix data.
    Gns(Gns),
    /// Geographic position.
    Gll(Gll),
    /// Dilutions and fix mode.
    Gsa(Gsa),
    /// Course and speed.
    Vtg(Vtg),
    /// Error statistics.
    Gst(Gst),
    /// Time and date.
    Zda(Zda),
}

impl Sentence {
    /// The UTC time of day the sentence is stamped with, if it carries one.
    pub const fn time(&self) -> Option<DayMillis> {
        match self {
            Self::Gga(g) => g.time,
            Self::Rmc(r) => r.time,
            Self::Gns(g) => g.time,
            Self::Gll(g) => g.time,
            Self::Gst(g) => g.time,
            Self::Zda(z) => z.time,
            Self::Gsa(_) | Self::Vtg(_) => None,
        }
    }
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
    if !address.bytes().all(|b| b.is_ascii_alphanumeric()) || address.len() < 3 {
        return Err(NmeaError::BadStart);
    }
    // Proprietary sentences (`$P...`) and addresses other than talker + type are not read.
    if address.len() != 5 || address.starts_with('P') {
        return Err(NmeaError::Unsupported);
    }
    let mut f = Fields::new(fields);
    match &address[2..] {
        "GGA" => parse_gga(&mut f).map(Sentence::Gga),
        "RMC" => parse_rmc(&mut f).map(Sentence::Rmc),
        "GNS" => parse_gns(&mut f).map(Sentence::Gns),
        "GLL" => parse_gll(&mut f).map(Sentence::Gll),
        "GSA" => parse_gsa(&mut f).map(Sentence::Gsa),
        "VTG" => parse_vtg(&mut f).map(Sentence::Vtg),
        "GST" => parse_gst(&mut f).map(Sentence::Gst),
        "ZDA" => parse_zda(&mut f).map(Sentence::Zda),
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
    if sum.len() != 2 {
        return Err(NmeaError::MissingChecksum);
    }
    let want = u8::from_str_radix(sum, 16).map_err(|_| NmeaError::MissingChecksum)?;
    let got = body.bytes().fold(0u8, |acc, b| acc ^ b);
    if got != want {
        return Err(NmeaError::BadChecksum);
    }
    Ok(body)
}

type F<'a> = Fields<'a, core::str::Split<'a, char>>;

fn parse_gga(f: &mut F<'_>) -> Result<Gga, NmeaError> {
    let time = f.optional_time()?;
    let position = f.position()?;
    let (i, q) = f.next();
    let quality = match q {
        "" => None,
        _ => {
            let q: u8 = q.parse().map_err(|_| NmeaError::BadField(i))?;
            Solution::from_gga_quality(q).ok_or(NmeaError::BadField(i))?;
            Some(q)
        }
    };
    let satellites = f.optional_u8()?;
    let hdop = f.optional_f32()?;
    let altitude_m = f.optional_f32()?;
    Ok(Gga {
        time,
        position,
        quality,
        satellites,
        hdop,
        altitude_m,
    })
}

fn parse_rmc(f: &mut F<'_>) -> Result<Rmc, NmeaError> {
    let time = f.optional_time()?;
    let (i, status) = f.next();
    let valid = match status {
        "A" => true,
        "V" => false,
        _ => return Err(NmeaError::BadField(i)),
    };
    let position = f.position()?;
    let speed_mps = f.optional_f32()?.map(|k| k * KNOTS_TO_MPS);
    let course_deg = f.optional_f32()?;
    // A malformed date is left out rather than refusing the position with it: receivers
    // with a week-rollover fault write dates such as `2208-1` in otherwise good RMCs.
    let (_, d) = f.next();
    let date = parse_date(d);
    f.skip(2); // magnetic variation and its direction
    let mode = mode_with_status(f)?;
    Ok(Rmc {
        time,
        valid,
        position,
        speed_mps,
        course_deg,
        date,
        mode,
    })
}

/// The optional mode indicator and navigational status closing RMC and GNS.
fn mode_with_status(f: &mut F<'_>) -> Result<Option<Solution>, NmeaError> {
    let (i, m) = f.next();
    let mode = match m.as_bytes() {
        [] => None,
        [b] => Some(Solution::from_mode(*b).ok_or(NmeaError::BadField(i))?),
        _ => return Err(NmeaError::BadField(i)),
    };
    let j = f.index_next();
    let status = nav_status(f.optional_letter()?, j)?;
    Ok(match (mode, status) {
        (Some(m), Some(s)) => Some(m.with(s)),
        (m, s) => m.or(s),
    })
}

fn parse_gns(f: &mut F<'_>) -> Result<Gns, NmeaError> {
    let time = f.optional_time()?;
    let position = f.position()?;
    let (i, letters) = f.next();
    if letters.is_empty() || letters.len() > 8 {
        return Err(NmeaError::BadField(i));
    }
    // The best measured mode of the constellations, unless one warns (simulator, ...).
    let mut mode: Option<Solution> = None;
    let mut warning: Option<Solution> = None;
    for b in letters.bytes() {
        let s = Solution::from_mode(b).ok_or(NmeaError::BadField(i))?;
        if s.is_measured() {
            mode = Some(mode.map_or(s, |m| m.with(s)));
        } else if s != Solution::Invalid {
            warning = Some(warning.map_or(s, |w| w.with(s)));
        }
    }
    let mode = warning.or(mode).unwrap_or(Solution::Invalid);
    let satellites = f.optional_u8()?.unwrap_or(0);
    let hdop = f.optional_f32()?;
    let altitude_m = f.optional_f32()?;
    f.skip(3); // geoid separation, age of corrections, station
    let j = f.index_next();
    let status = nav_status(f.optional_letter()?, j)?;
    Ok(Gns {
        time,
        position,
        mode: status.map_or(mode, |s| mode.with(s)),
        satellites,
        hdop,
        altitude_m,
    })
}

fn parse_gll(f: &mut F<'_>) -> Result<Gll, NmeaError> {
    let position = f.position()?;
    let time = f.optional_time()?;
    let (i, status) = f.next();
    let valid = match status {
        "A" => true,
        "V" => false,
        _ => return Err(NmeaError::BadField(i)),
    };
    let j = f.index_next();
    let mode = match f.optional_letter()? {
        Some(b) => Some(Solution::from_mode(b).ok_or(NmeaError::BadField(j))?),
        None => None,
    };
    let solution = match (valid, mode) {
        (true, Some(m)) => m,
        (true, None) => Solution::Autonomous,
        (false, Some(m)) if !m.is_measured() => m,
        (false, _) => Solution::Invalid,
    };
    Ok(Gll {
        time,
        position,
        solution,
    })
}

fn parse_gsa(f: &mut F<'_>) -> Result<Gsa, NmeaError> {
    f.skip(1); // M manual / A automatic 2D-3D selection
    let (i, mode) = f.next();
    let fix_mode = match mode {
        "" => None,
        "1" => Some(1),
        "2" => Some(2),
        "3" => Some(3),
        _ => return Err(NmeaError::BadField(i)),
    };
    f.skip(12); // satellites used
    let pdop = f.optional_f32()?;
    let hdop = f.optional_f32()?;
    let vdop = f.optional_f32()?;
    Ok(Gsa {
        fix_mode,
        pdop,
        hdop,
        vdop,
    })
}

fn parse_vtg(f: &mut F<'_>) -> Result<Vtg, NmeaError> {
    let course_deg = f.optional_f32()?;
    f.skip(3); // "T", magnetic course, "M"
    let knots = f.optional_f32()?;
    f.skip(1); // "N"
    let kmh = f.optional_f32()?;
    f.skip(1); // "K"
    let j = f.index_next();
    let mode = match f.optional_letter()? {
        Some(b) => Some(Solution::from_mode(b).ok_or(NmeaError::BadField(j))?),
        None => None,
    };
    let speed_mps = kmh.map(|v| v / 3.6).or(knots.map(|k| k * KNOTS_TO_MPS));
    Ok(Vtg {
        course_deg,
        speed_mps,
        mode,
    })
}

fn parse_gst(f: &mut F<'_>) -> Result<Gst, NmeaError> {
    let time = f.optional_time()?;
    f.skip(4); // rms, semi-major, semi-minor, orientation
    let lat_sd_m = f.optional_f32()?;
    let lon_sd_m = f.optional_f32()?;
    Ok(Gst {
        time,
        lat_sd_m,
        lon_sd_m,
    })
}

fn parse_zda(f: &mut F<'_>) -> Result<Zda, NmeaError> {
    let time = f.optional_time()?;
    let day = f.optional_u8()?;
    let month = f.optional_u8()?;
    let (i, y) = f.next();
    let date = match (day, month, y) {
        (None, None, "") => None,
        (Some(d), Some(m), y) if y.len() == 4 && y.bytes().all(|b| b.is_ascii_digit()) => {
            let year: u16 = y.parse().map_err(|_| NmeaError::BadField(i))?;
            if !(1..=31).contains(&d) || !(1..=12).contains(&m) || year < 1980 {
                return Err(NmeaError::BadField(i));
            }
            Some((year, m, d))
        }
        _ => return Err(NmeaError::BadField(i)),
    };
    Ok(Zda { time, date })
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

#[cfg(test)]
mod tests;
