//! What the simulated GNSS receiver sends for one epoch, by the kind of receiver a
//! scenario names (`[drive] receiver`): NMEA GST + GGA + RMC (the default), a GGA-only
//! unit, or a u-blox receiver's UBX NAV-PVT with its carrier-phase (RTK) solution.
//!
//! The NAV-PVT bytes are written here from u-blox's published layout (92 bytes, the
//! Fletcher checksum computed here), not with the OBU core's UBX code: the scenario then
//! checks the core's reader against a second, separate writer.

use crate::nmea::{self, Epoch};
use serde::Deserialize;

/// The kind of receiver a scenario drives the OBU with.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum ReceiverKind {
    /// NMEA GST, GGA (quality 1) and RMC each epoch.
    #[default]
    Nmea,
    /// NMEA GGA alone (DGPS quality, HDOP the reported error in metres): no velocity, no
    /// date, no GST.
    GgaOnly,
    /// u-blox UBX NAV-PVT alone (hAcc the reported error).
    Ubx,
}

/// A carrier-phase solution of a UBX receiver.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Carrier {
    /// No carrier phase: a stand-alone 3D fix.
    None,
    /// RTK float.
    Float,
    /// RTK fixed.
    #[default]
    Fixed,
}

/// The bytes of one epoch for a receiver of `kind` (`carrier`: UBX only).
pub fn epoch_bytes(kind: ReceiverKind, e: &Epoch, carrier: Carrier) -> Vec<u8> {
    match kind {
        ReceiverKind::Nmea => nmea::epoch(e).into_bytes(),
        ReceiverKind::GgaOnly => nmea::gga(e, 2, e.sigma_m).into_bytes(),
        ReceiverKind::Ubx => nav_pvt(e, carrier),
    }
}

/// The carrier solution at `t_s` seconds into the drive: the last `(from_s, carrier)` of
/// `schedule` that has begun (RTK fixed before the first).
pub fn carrier_at(schedule: &[(f64, Carrier)], t_s: f64) -> Carrier {
    schedule
        .iter()
        .rfind(|(from, _)| *from <= t_s)
        .map_or(Carrier::Fixed, |(_, c)| *c)
}

/// A whole UBX NAV-PVT frame of the epoch.
pub fn nav_pvt(e: &Epoch, carrier: Carrier) -> Vec<u8> {
    let mut p = Vec::with_capacity(92);
    let u = &e.utc;
    let (ms_of_second, second) = (u.ms_of_day % 1000, u.ms_of_day / 1000);
    // iTOW: GPS time of week (UTC + 18 s of leap seconds), days from Sunday.
    let days_since_sunday = (u.to_unix_ms() / 86_400_000 + 4) % 7;
    let itow =
        (days_since_sunday * 86_400_000 + u64::from(u.ms_of_day) + 18_000) % (7 * 86_400_000);
    p.extend_from_slice(&(itow as u32).to_le_bytes());
    p.extend_from_slice(&u.year.to_le_bytes());
    p.extend_from_slice(&[u.month, u.day]);
    p.extend_from_slice(&[
        (second / 3600) as u8,
        (second / 60 % 60) as u8,
        (second % 60) as u8,
    ]);
    p.push(0x07); // valid: date, time, fully resolved
    p.extend_from_slice(&25u32.to_le_bytes()); // tAcc, ns
    p.extend_from_slice(&((ms_of_second * 1_000_000) as i32).to_le_bytes()); // nano
    p.push(3); // fixType: 3D
    let carr_soln: u8 = match carrier {
        Carrier::None => 0,
        Carrier::Float => 1,
        Carrier::Fixed => 2,
    };
    let diff = u8::from(carrier != Carrier::None) << 1;
    p.push(1 | diff | (carr_soln << 6)); // flags: gnssFixOK, diffSoln, carrSoln
    p.push(0xE0); // flags2: confirmed available, date, time
    p.push(18); // numSV
    let e7 = |deg: f64| ((deg * 1e7).round() as i32).to_le_bytes();
    p.extend_from_slice(&e7(e.position.lon_deg()));
    p.extend_from_slice(&e7(e.position.lat_deg()));
    p.extend_from_slice(&1_583_000i32.to_le_bytes()); // height above the ellipsoid, mm
    p.extend_from_slice(&1_600_000i32.to_le_bytes()); // hMSL, mm
    let h_acc_mm = (e.sigma_m * 1000.0).round().max(1.0) as u32;
    p.extend_from_slice(&h_acc_mm.to_le_bytes());
    p.extend_from_slice(&(h_acc_mm * 2).to_le_bytes()); // vAcc
    let course = e.course_deg.to_radians();
    let speed_mm = e.speed_mps.max(0.0) * 1000.0;
    let (vn, ve) = (speed_mm * course.cos(), speed_mm * course.sin());
    for v in [
        vn.round() as i32,
        ve.round() as i32,
        0,
        speed_mm.round() as i32,
    ] {
        p.extend_from_slice(&v.to_le_bytes()); // velN, velE, velD, gSpeed
    }
    let head = (e.course_deg.rem_euclid(360.0) * 1e5).round() as i32;
    p.extend_from_slice(&head.to_le_bytes()); // headMot
    p.extend_from_slice(&80u32.to_le_bytes()); // sAcc, mm/s
    p.extend_from_slice(&50_000u32.to_le_bytes()); // headAcc, 1e-5 degrees
    p.extend_from_slice(&120u16.to_le_bytes()); // pDOP 1.20
    p.extend_from_slice(&[0; 6]); // flags3, reserved
    p.extend_from_slice(&head.to_le_bytes()); // headVeh
    p.extend_from_slice(&[0; 4]); // magDec, magAcc
    debug_assert_eq!(p.len(), 92);
    let mut frame = vec![0xB5, 0x62, 0x01, 0x07];
    frame.extend_from_slice(&(p.len() as u16).to_le_bytes());
    frame.extend_from_slice(&p);
    let (mut a, mut b) = (0u8, 0u8);
    for &x in &frame[2..] {
        a = a.wrapping_add(x);
        b = b.wrapping_add(a);
    }
    frame.extend_from_slice(&[a, b]);
    frame
}

#[cfg(test)]
mod tests {
    use super::*;
    use obu::input::gnss::{GnssEvent, GnssReader};
    use obu::input::nmea::Solution;
    use obu::LatLon;
    use roadside::clock::Utc;

    fn epoch() -> Epoch {
        Epoch {
            utc: Utc::from_unix_ms(1_795_341_600_250), // 2026-11-22T10:00:00.25Z
            position: LatLon::from_degrees(39.7392, -104.9903).unwrap(),
            speed_mps: 11.0,
            course_deg: 90.0,
            sigma_m: 0.02,
        }
    }

    #[test]
    fn the_obu_reads_this_nav_pvt_back() {
        for (carrier, solution) in [
            (Carrier::Fixed, Solution::RtkFixed),
            (Carrier::Float, Solution::RtkFloat),
            (Carrier::None, Solution::Autonomous),
        ] {
            let mut r = GnssReader::new();
            let mut got = Vec::new();
            r.push(&nav_pvt(&epoch(), carrier), |e| got.push(e));
            let [GnssEvent::Ubx("NAV-PVT"), GnssEvent::Epoch(e)] = got[..] else {
                panic!("{got:?}")
            };
            assert_eq!(e.solution, Some(solution));
            let fix = e.outcome.unwrap();
            assert_eq!(fix.position, epoch().position);
            assert_eq!(fix.accuracy_m, Some(0.02));
            assert!((fix.speed_mps.unwrap() - 11.0).abs() < 1e-3);
            assert_eq!(fix.course_deg, Some(90.0));
            let utc = fix.utc.unwrap();
            assert_eq!((utc.year, utc.ms_of_year % 86_400_000), (2026, 36_000_250));
        }
    }

    #[test]
    fn the_schedule_names_the_carrier_solution() {
        let s = [(10.0, Carrier::Float), (20.0, Carrier::Fixed)];
        assert_eq!(carrier_at(&s, 0.0), Carrier::Fixed);
        assert_eq!(carrier_at(&s, 10.0), Carrier::Float);
        assert_eq!(carrier_at(&s, 25.0), Carrier::Fixed);
    }
}
