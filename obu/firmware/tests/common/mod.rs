//! Helpers shared by the on-target tests `drive` and `malformed`: NMEA sentences formatted on
//! target, V2X payloads framed with `obu::link`, byte feeding, a small PRNG.
#![allow(dead_code)] // each test uses its own subset

use core::fmt::Write as _;
use obu::v2x::{DropGroup, V2xCounters};
use obu::{HmiState, Instant};
use obu_firmware::app::{Firmware, Messages};

/// The security settings of the tests of the unsigned paths (the oracle vectors are bare
/// frames): unsigned MAP and TIM are taken. `tests/signed.rs` tests the product setting.
pub const UNSIGNED_TAKEN: obu::security::SecurityConfig = obu::security::SecurityConfig {
    require_signed: false,
    ..obu::security::SecurityConfig::DEFAULT
};

/// Hands out `&'static mut` of a `static mut` initialised at compile time, once: what
/// cortex-m-rt's `#[entry]` does for the firmware's `main`. `cortex_m::singleton!` writes
/// its value at run time, and LLVM then builds part of these large values on the stack (25
/// KiB for [`Messages`]: over the 24 KiB stack).
macro_rules! static_once {
    ($ty:ty = $init:expr) => {{
        static TAKEN: core::sync::atomic::AtomicBool = core::sync::atomic::AtomicBool::new(false);
        static mut VALUE: $ty = $init;
        assert!(
            !TAKEN.swap(true, core::sync::atomic::Ordering::Relaxed),
            "taken once"
        );
        // SAFETY: the flag above lets this run once, so this is the only reference ever made.
        #[allow(unsafe_code)]
        unsafe {
            &mut *core::ptr::addr_of_mut!(VALUE)
        }
    }};
}

/// The firmware state in a `static` (one call only).
pub fn firmware() -> &'static mut Firmware {
    static_once!(Firmware = Firmware::new(obu_firmware::CONFIG))
}

/// The receive path in a `static` (one call only), with `config`.
pub fn messages(config: obu::security::SecurityConfig) -> &'static mut Messages {
    let msgs = static_once!(Messages = Messages::new());
    msgs.trust_mut().set_config(config);
    msgs
}

/// One NMEA sentence with its line end.
pub type Line = heapless::String<128>;

/// `$<body>*hh\r\n` with the checksum (xor of the body's bytes).
pub fn sentence(body: &str) -> Line {
    let sum = body.bytes().fold(0u8, |acc, b| acc ^ b);
    let mut line = Line::new();
    write!(line, "${body}*{sum:02X}\r\n").expect("sentence fits");
    line
}

/// What a GNSS receiver reports for one epoch.
#[derive(Clone, Copy)]
pub struct Epoch {
    /// UTC time of day, milliseconds.
    pub utc_ms: u32,
    /// (day, month, two-digit year).
    pub date: (u8, u8, u8),
    /// Latitude, degrees (north positive).
    pub lat: f64,
    /// Longitude, degrees (east positive).
    pub lon: f64,
    /// Speed over ground, m/s.
    pub speed_mps: f64,
    /// Course over ground, degrees.
    pub course_deg: f64,
    /// 1-sigma error of latitude and of longitude, metres (GST).
    pub sd_m: f64,
}

/// `ddmm.mmmmmmm,N` / `dddmm.mmmmmmm,W` (minutes to 1e-7: 0.2 mm).
fn angle(out: &mut Line, v: f64, deg_digits: usize, pos: char, neg: char) {
    let a = if v < 0.0 { -v } else { v };
    let deg = a as u32;
    let min = (a - deg as f64) * 60.0;
    let hemi = if v < 0.0 { neg } else { pos };
    write!(out, "{deg:0deg_digits$}{min:010.7},{hemi}").expect("fits");
}

/// `hhmmss.ss`.
fn time(out: &mut Line, ms: u32) {
    let (h, m, s, cs) = (
        ms / 3_600_000,
        ms / 60_000 % 60,
        ms / 1000 % 60,
        ms / 10 % 100,
    );
    write!(out, "{h:02}{m:02}{s:02}.{cs:02}").expect("fits");
}

/// A UBX NAV-PVT frame (6 + 92 + 2 bytes).
pub type UbxFrame = [u8; 100];

impl Epoch {
    /// The epoch as a u-blox receiver sends it: a UBX NAV-PVT frame (RTK fixed, 3D,
    /// gnssFixOK, hAcc the GST's horizontal error), written here from u-blox's published
    /// layout with its own Fletcher checksum (not the core's UBX code).
    pub fn nav_pvt(&self) -> UbxFrame {
        let mut f = [0u8; 100];
        f[..6].copy_from_slice(&[0xB5, 0x62, 0x01, 0x07, 92, 0]);
        let p = &mut f[6..98];
        let put = |p: &mut [u8], at: usize, b: &[u8]| p[at..at + b.len()].copy_from_slice(b);
        put(p, 0, &self.utc_ms.to_le_bytes()); // iTOW (any: the time is in the UTC fields)
        put(p, 4, &(2000 + u16::from(self.date.2)).to_le_bytes());
        let s = self.utc_ms / 1000;
        put(
            p,
            6,
            &[
                self.date.1,
                self.date.0,
                (s / 3600) as u8,
                (s / 60 % 60) as u8,
                (s % 60) as u8,
                0x07,
            ],
        );
        put(p, 12, &30u32.to_le_bytes()); // tAcc
        put(
            p,
            16,
            &(((self.utc_ms % 1000) * 1_000_000) as i32).to_le_bytes(),
        );
        put(p, 20, &[3, 0x83, 0xE0, 20]); // 3D; gnssFixOK, diffSoln, carrSoln fixed; 20 SV
        let e7 = |deg: f64| {
            let v = deg * 1e7;
            (if v < 0.0 { v - 0.5 } else { v + 0.5 }) as i32
        };
        put(p, 24, &e7(self.lon).to_le_bytes());
        put(p, 28, &e7(self.lat).to_le_bytes());
        put(p, 32, &250_000i32.to_le_bytes()); // height, mm
        put(p, 36, &270_000i32.to_le_bytes()); // hMSL, mm
        let h_acc = (self.sd_m * core::f64::consts::SQRT_2 * 1000.0 + 0.5) as u32;
        put(p, 40, &h_acc.to_le_bytes());
        put(p, 44, &(2 * h_acc).to_le_bytes());
        let speed = (self.speed_mps * 1000.0 + 0.5) as i32;
        let rad = self.course_deg.to_radians();
        let (vn, ve) = (
            libm::cos(rad) * f64::from(speed),
            libm::sin(rad) * f64::from(speed),
        );
        put(p, 48, &(vn as i32).to_le_bytes());
        put(p, 52, &(ve as i32).to_le_bytes());
        put(p, 60, &speed.to_le_bytes());
        put(p, 64, &((self.course_deg * 1e5 + 0.5) as i32).to_le_bytes());
        put(p, 68, &100u32.to_le_bytes()); // sAcc
        put(p, 72, &40_000u32.to_le_bytes()); // headAcc
        put(p, 76, &110u16.to_le_bytes()); // pDOP
        let (mut a, mut b) = (0u8, 0u8);
        for &x in &f[2..98] {
            a = a.wrapping_add(x);
            b = b.wrapping_add(a);
        }
        f[98] = a;
        f[99] = b;
        f
    }

    /// The epoch's GGA (GPS fix, 12 satellites, HDOP 0.8).
    pub fn gga(&self) -> Line {
        let mut body = Line::new();
        body.push_str("GPGGA,").expect("fits");
        time(&mut body, self.utc_ms);
        body.push(',').expect("fits");
        angle(&mut body, self.lat, 2, 'N', 'S');
        body.push(',').expect("fits");
        angle(&mut body, self.lon, 3, 'E', 'W');
        body.push_str(",1,12,0.8,271.0,M,-34.0,M,,").expect("fits");
        sentence(&body)
    }

    /// The epoch's GST (error ellipse; standard deviations of latitude and longitude).
    pub fn gst(&self) -> Line {
        let mut body = Line::new();
        body.push_str("GPGST,").expect("fits");
        time(&mut body, self.utc_ms);
        let sd = self.sd_m;
        write!(
            body,
            ",{sd:.2},{sd:.2},{sd:.2},0.0,{sd:.2},{sd:.2},{:.2}",
            2.0 * sd
        )
        .expect("fits");
        sentence(&body)
    }

    /// The epoch's RMC (valid, speed in knots, course, date).
    pub fn rmc(&self) -> Line {
        let mut body = Line::new();
        body.push_str("GPRMC,").expect("fits");
        time(&mut body, self.utc_ms);
        body.push_str(",A,").expect("fits");
        angle(&mut body, self.lat, 2, 'N', 'S');
        body.push(',').expect("fits");
        angle(&mut body, self.lon, 3, 'E', 'W');
        let knots = self.speed_mps * 3600.0 / 1852.0;
        let (d, m, y) = self.date;
        write!(
            body,
            ",{knots:.4},{:.2},{d:02}{m:02}{y:02},,,A",
            self.course_deg
        )
        .expect("fits");
        sentence(&body)
    }
}

/// Feeds `bytes` to the NMEA port at `now`; returns the last state and how many came.
pub fn feed_nmea(fw: &mut Firmware, now: Instant, bytes: &[u8]) -> (Option<HmiState>, u32) {
    let mut last = None;
    let mut n = 0;
    for &b in bytes {
        if let Some(s) = fw.on_gnss_byte(now, b) {
            last = Some(s);
            n += 1;
        }
    }
    (last, n)
}

/// Feeds `bytes` to the V2X port at `now`; returns the last state and how many came.
pub fn feed_v2x(
    fw: &mut Firmware,
    msgs: &mut Messages,
    now: Instant,
    bytes: &[u8],
) -> (Option<HmiState>, u32) {
    let mut last = None;
    let mut n = 0;
    for &b in bytes {
        if let Some(s) = fw.on_v2x_byte(msgs, now, b) {
            last = Some(s);
            n += 1;
        }
    }
    (last, n)
}

/// `payload` as an `obu::link` wire frame in `wire` (final zero included).
pub fn frame<'a>(payload: &[u8], wire: &'a mut [u8]) -> &'a [u8] {
    let n = obu::link::encode(payload, wire).expect("wire buffer large enough");
    &wire[..n]
}

/// The named vector of `table`.
pub fn vector(table: &[(&str, &'static [u8])], name: &str) -> &'static [u8] {
    table
        .iter()
        .find(|(n, _)| *n == name)
        .map(|(_, b)| *b)
        .expect("vector present")
}

/// xorshift32: a fixed, reproducible byte stream.
pub struct Rng(pub u32);

impl Rng {
    /// The next byte.
    pub fn byte(&mut self) -> u8 {
        let mut x = self.0;
        x ^= x << 13;
        x ^= x >> 17;
        x ^= x << 5;
        self.0 = x;
        (x >> 24) as u8
    }
}

/// The V2X counters by the tests' five outcomes (each a sum over the core's fixed array).
#[derive(Debug, Clone, Copy, PartialEq, Eq, defmt::Format)]
pub struct Tally {
    /// MAP or TIM taken by the core (changed or only refreshed).
    pub accepted: u32,
    /// Frames the link's framing rejected (COBS, CRC, too long or too short).
    pub bad_frames: u32,
    /// Frames whose envelope or UPER content did not decode (or exceeded a capacity).
    pub undecodable: u32,
    /// Decoded MAP or TIM the core refused.
    pub rejected: u32,
    /// Other message types.
    pub other: u32,
}

/// The counters `c` as a [`Tally`].
pub fn tally(c: &V2xCounters) -> Tally {
    Tally {
        accepted: c.changed + c.unchanged,
        bad_frames: c.dropped_in(DropGroup::Datagram),
        undecodable: c.dropped_in(DropGroup::Envelope) + c.dropped_in(DropGroup::Decode),
        rejected: c.dropped_in(DropGroup::Ingest),
        other: c.other,
    }
}
