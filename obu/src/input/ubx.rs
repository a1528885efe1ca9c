//! u-blox UBX binary messages: the frame checksum and the navigation solution (NAV-PVT),
//! the receiver status (NAV-STATUS) and the dilutions (NAV-DOP).
//!
//! A frame is `B5 62`, class, id, a little-endian payload length, the payload and an
//! 8-bit Fletcher checksum over class to payload ([`checksum`]); the framer
//! ([`super::gnss::Framer`]) cuts frames out of a byte stream. The payload layouts are
//! u-blox's published ones (u-blox 8 / M8 and F9 protocol descriptions): NAV-PVT is 92
//! bytes (84 on u-blox 7, which lacks the last fields; both are read). Hand-written: the
//! same code runs on the `no_std` firmware.

use super::nmea::{DayMillis, Epoch, NoFix, Solution};
use crate::fix::{AccuracySource, Fix};
use crate::geo::LatLon;
use crate::time::UtcTime;

/// The two sync characters that open every frame.
pub const SYNC: [u8; 2] = [0xB5, 0x62];
/// The navigation class.
pub const CLASS_NAV: u8 = 0x01;
/// NAV-STATUS.
pub const ID_NAV_STATUS: u8 = 0x03;
/// NAV-DOP.
pub const ID_NAV_DOP: u8 = 0x04;
/// NAV-PVT.
pub const ID_NAV_PVT: u8 = 0x07;

/// Why a UBX message was not read.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum UbxError {
    /// The checksum does not match the frame.
    BadChecksum,
    /// The payload is shorter than the message's layout.
    ShortPayload,
    /// A field holds a value the layout does not define (a month of 13, ...).
    BadField,
}

impl UbxError {
    /// A short lowercase name, for counters and logs.
    pub const fn as_str(self) -> &'static str {
        match self {
            Self::BadChecksum => "ubx bad checksum",
            Self::ShortPayload => "ubx short payload",
            Self::BadField => "ubx bad field",
        }
    }
}

/// The 8-bit Fletcher checksum (CK_A, CK_B) of `bytes` (class, id, length, payload).
pub fn checksum(bytes: &[u8]) -> (u8, u8) {
    bytes.iter().fold((0u8, 0u8), |(a, b), &x| {
        let a = a.wrapping_add(x);
        (a, b.wrapping_add(a))
    })
}

fn u16_at(p: &[u8], at: usize) -> u16 {
    u16::from_le_bytes([p[at], p[at + 1]])
}

fn u32_at(p: &[u8], at: usize) -> u32 {
    u32::from_le_bytes([p[at], p[at + 1], p[at + 2], p[at + 3]])
}

fn i32_at(p: &[u8], at: usize) -> i32 {
    u32_at(p, at) as i32
}

/// The carrier-phase range solution (NAV-PVT `flags.carrSoln`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Carrier {
    /// No carrier-phase solution.
    None,
    /// RTK with float ambiguities.
    Float,
    /// RTK with fixed ambiguities.
    Fixed,
}

/// NAV-PVT: the navigation solution of one epoch.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NavPvt {
    /// GPS time of week of the epoch, ms.
    pub itow_ms: u32,
    /// UTC date: (year, month, day).
    pub date: (u16, u8, u8),
    /// UTC time of day (hour, minute, second).
    pub hms: (u8, u8, u8),
    /// Fraction of second, nanoseconds (-1e9..1e9).
    pub nano: i32,
    /// Validity flags: bit 0 date valid, bit 1 time valid, bit 2 fully resolved.
    pub valid: u8,
    /// 0 no fix, 1 dead reckoning only, 2 2D, 3 3D, 4 GNSS + dead reckoning, 5 time only.
    pub fix_type: u8,
    /// Flags: bit 0 gnssFixOK, bit 1 diffSoln, bits 6-7 carrSoln.
    pub flags: u8,
    /// Satellites used.
    pub num_sv: u8,
    /// Longitude, 1e-7 degrees.
    pub lon_e7: i32,
    /// Latitude, 1e-7 degrees.
    pub lat_e7: i32,
    /// Height above mean sea level, mm.
    pub hmsl_mm: i32,
    /// Horizontal accuracy estimate, mm.
    pub h_acc_mm: u32,
    /// Vertical accuracy estimate, mm.
    pub v_acc_mm: u32,
    /// North, east, down velocity, mm/s.
    pub vel_ned_mm_s: [i32; 3],
    /// Ground speed, mm/s.
    pub g_speed_mm_s: i32,
    /// Heading of motion, 1e-5 degrees.
    pub head_mot_e5: i32,
    /// Speed accuracy estimate, mm/s.
    pub s_acc_mm_s: u32,
    /// Heading accuracy estimate, 1e-5 degrees.
    pub head_acc_e5: u32,
    /// Position DOP, 0.01.
    pub pdop_e2: u16,
    /// `flags3.invalidLlh` (92-byte layout): the position is not valid.
    pub invalid_llh: bool,
}

impl NavPvt {
    /// Shortest layout (u-blox 7); u-blox 8 and later send 92 bytes.
    pub const MIN_LEN: usize = 84;

    /// Reads a NAV-PVT payload.
    pub fn parse(p: &[u8]) -> Result<Self, UbxError> {
        if p.len() < Self::MIN_LEN {
            return Err(UbxError::ShortPayload);
        }
        let pvt = NavPvt {
            itow_ms: u32_at(p, 0),
            date: (u16_at(p, 4), p[6], p[7]),
            hms: (p[8], p[9], p[10]),
            valid: p[11],
            nano: i32_at(p, 16),
            fix_type: p[20],
            flags: p[21],
            num_sv: p[23],
            lon_e7: i32_at(p, 24),
            lat_e7: i32_at(p, 28),
            hmsl_mm: i32_at(p, 36),
            h_acc_mm: u32_at(p, 40),
            v_acc_mm: u32_at(p, 44),
            vel_ned_mm_s: [i32_at(p, 48), i32_at(p, 52), i32_at(p, 56)],
            g_speed_mm_s: i32_at(p, 60),
            head_mot_e5: i32_at(p, 64),
            s_acc_mm_s: u32_at(p, 68),
            head_acc_e5: u32_at(p, 72),
            pdop_e2: u16_at(p, 76),
            invalid_llh: p.len() >= 92 && p[78] & 1 != 0,
        };
        let (h, m, s) = pvt.hms;
        if pvt.fix_type > 5
            || h > 23
            || m > 59
            || s > 60
            || !(-1_000_000_000..=1_000_000_000).contains(&pvt.nano)
        {
            return Err(UbxError::BadField);
        }
        Ok(pvt)
    }

    /// `flags.gnssFixOK`: the fix is within the receiver's limits (DOP, accuracy masks).
    pub const fn gnss_fix_ok(&self) -> bool {
        self.flags & 1 != 0
    }

    /// The carrier-phase solution.
    pub const fn carrier(&self) -> Carrier {
        match self.flags >> 6 {
            1 => Carrier::Float,
            2 => Carrier::Fixed,
            _ => Carrier::None,
        }
    }

    /// What the receiver says of its solution, as the NMEA side names it.
    pub const fn solution(&self) -> Solution {
        match self.fix_type {
            1 => Solution::Estimated,
            2..=4 if !self.gnss_fix_ok() || self.invalid_llh => Solution::Invalid,
            2..=4 => match self.carrier() {
                Carrier::Fixed => Solution::RtkFixed,
                Carrier::Float => Solution::RtkFloat,
                Carrier::None if self.flags & 2 != 0 => Solution::Differential,
                Carrier::None => Solution::Autonomous,
            },
            _ => Solution::Invalid,
        }
    }

    /// Milliseconds from the UTC date's midnight (the fraction rounded to the
    /// millisecond; a negative fraction may reach back before the whole second).
    fn ms_from_midnight(&self) -> i64 {
        let (h, m, s) = self.hms;
        let whole = ((i64::from(h) * 60 + i64::from(m)) * 60 + i64::from(s)) * 1000;
        whole + (i64::from(self.nano) + 500_000).div_euclid(1_000_000)
    }

    /// UTC time of day, ms; `None` when the receiver does not mark its time valid.
    pub fn time_of_day(&self) -> Option<DayMillis> {
        if self.valid & 2 == 0 {
            return None;
        }
        u32::try_from(self.ms_from_midnight().rem_euclid(86_400_000)).ok()
    }

    /// UTC date and time, when the receiver marks both valid.
    pub fn utc(&self) -> Option<UtcTime> {
        if self.valid & 3 != 3 {
            return None;
        }
        let (y, mo, d) = self.date;
        let midnight = super::nmea::utc_from_date(y, mo, d, 0)?;
        Some(UtcTime::from_abs_millis(
            midnight.abs_millis() + self.ms_from_midnight(),
        ))
    }

    /// The fix of this solution, or why there is none; hAcc is its accuracy.
    pub fn fix(&self) -> Result<Fix, NoFix> {
        let solution = self.solution();
        if !solution.is_measured() {
            return Err(match solution {
                Solution::Estimated => NoFix::DeadReckoning,
                _ => NoFix::NoFix,
            });
        }
        let position = LatLon::new(self.lat_e7, self.lon_e7).ok_or(NoFix::NoPosition)?;
        let mm = |v: i32| v as f32 / 1000.0;
        let speed = self.g_speed_mm_s;
        Ok(Fix {
            position,
            accuracy_m: Some(self.h_acc_mm as f32 / 1000.0),
            accuracy_source: AccuracySource::Ubx,
            speed_mps: (speed >= 0).then(|| mm(speed)),
            // The heading of motion is meaningless at a standstill; the receiver freezes it.
            course_deg: (speed > 0).then(|| self.head_mot_e5 as f32 / 1e5),
            utc: self.utc(),
        })
    }

    /// The fix as an epoch of the receiver (time of day, solution, outcome). Without a
    /// valid time the epoch is stamped with the GPS time of day (`iTOW`) and gives no fix.
    pub fn epoch(&self) -> Epoch {
        let (time, outcome) = match self.time_of_day() {
            Some(t) => (t, self.fix()),
            None => (self.itow_ms % 86_400_000, Err(NoFix::NoTime)),
        };
        Epoch {
            time,
            solution: Some(self.solution()),
            outcome,
        }
    }
}

/// NAV-STATUS: the receiver's fix status.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct NavStatus {
    /// GPS time of week, ms.
    pub itow_ms: u32,
    /// 0 no fix, 1 dead reckoning only, 2 2D, 3 3D, 4 GPS + dead reckoning, 5 time only.
    pub gps_fix: u8,
    /// Flags: bit 0 gpsFixOk, bit 1 diffSoln, bit 2 wknSet, bit 3 towSet.
    pub flags: u8,
    /// Flags2: bits 3-4 spoofDetState (0 unknown, 1 none, 2 spoofing, 3 multiple),
    /// bits 6-7 carrSoln.
    pub flags2: u8,
    /// Time to first fix, ms.
    pub ttff_ms: u32,
}

impl NavStatus {
    /// Payload length.
    pub const LEN: usize = 16;

    /// Reads a NAV-STATUS payload.
    pub fn parse(p: &[u8]) -> Result<Self, UbxError> {
        if p.len() < Self::LEN {
            return Err(UbxError::ShortPayload);
        }
        Ok(NavStatus {
            itow_ms: u32_at(p, 0),
            gps_fix: p[4],
            flags: p[5],
            flags2: p[7],
            ttff_ms: u32_at(p, 8),
        })
    }

    /// The receiver's spoofing detector reports spoofing (states 2 and 3).
    pub const fn spoofing(&self) -> bool {
        (self.flags2 >> 3) & 3 >= 2
    }
}

/// NAV-DOP: dilutions of precision (each in 0.01).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct NavDop {
    /// GPS time of week, ms.
    pub itow_ms: u32,
    /// Geometric, position, time, vertical, horizontal, northing, easting DOP.
    pub dops_e2: [u16; 7],
}

impl NavDop {
    /// Payload length.
    pub const LEN: usize = 18;

    /// Reads a NAV-DOP payload.
    pub fn parse(p: &[u8]) -> Result<Self, UbxError> {
        if p.len() < Self::LEN {
            return Err(UbxError::ShortPayload);
        }
        let mut dops_e2 = [0u16; 7];
        for (i, d) in dops_e2.iter_mut().enumerate() {
            *d = u16_at(p, 4 + 2 * i);
        }
        Ok(NavDop {
            itow_ms: u32_at(p, 0),
            dops_e2,
        })
    }

    /// Horizontal DOP.
    pub fn hdop(&self) -> f32 {
        f32::from(self.dops_e2[4]) / 100.0
    }
}

/// One UBX message as read.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Message {
    /// Navigation solution.
    NavPvt(NavPvt),
    /// Receiver status.
    NavStatus(NavStatus),
    /// Dilutions of precision.
    NavDop(NavDop),
    /// A message this reader does not interpret (class, id): counted, not an error.
    Other(u8, u8),
}

/// Reads a frame's payload by its class and id.
pub fn parse(class: u8, id: u8, payload: &[u8]) -> Result<Message, UbxError> {
    Ok(match (class, id) {
        (CLASS_NAV, ID_NAV_PVT) => Message::NavPvt(NavPvt::parse(payload)?),
        (CLASS_NAV, ID_NAV_STATUS) => Message::NavStatus(NavStatus::parse(payload)?),
        (CLASS_NAV, ID_NAV_DOP) => Message::NavDop(NavDop::parse(payload)?),
        _ => Message::Other(class, id),
    })
}
