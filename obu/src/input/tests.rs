//! UBX wire fixtures and the mixed NMEA/UBX framer.
//!
//! The fixtures are whole frames written from u-blox's published NAV-PVT (92 bytes),
//! NAV-STATUS (16) and NAV-DOP (18) layouts, field by field with Python's `struct`, and
//! their Fletcher checksums computed there: none of these bytes comes from this crate.
//! All are 2026-12-04 12:34:56.25 UTC at 42.1234567 N, 83.7654321 W, 13.889 m/s east
//! (heading 90 degrees), hAcc 14 mm, 24 satellites, pDOP 0.95.

use super::gnss::{Framed, Framer, GnssEvent, GnssReader, MAX_LINE, MAX_UBX_KEPT};
use super::nmea::{NoFix, Solution};
use super::ubx::{self, Carrier, Message, NavPvt, UbxError};
use crate::fix::AccuracySource;
use std::vec::Vec;

/// NAV-PVT: 3D, gnssFixOK, diffSoln, carrier solution fixed.
const PVT_RTK_FIXED: &str = "b56201075c007a9a4c17ea070c040c2238071400000080b2e60e0383e018cf6812ce87871b19400d0300109203000e00000015000000000000004136000000000000413600004054890032000000f04902005f0000000000000000000000000000004971";
/// The same a second later with the carrier solution float and hAcc 180 mm.
const PVT_RTK_FLOAT: &str = "b56201075c00629e4c17ea070c040c2239071400000080b2e60e0343e018cf6812ce87871b19400d030010920300b400000015000000000000004136000000000000413600004054890032000000f04902005f0000000000000000000000000000009c87";
/// fixType 0, no flags.
const PVT_NO_FIX: &str = "b56201075c004aa24c17ea070c040c223a071400000080b2e60e0000e018cf6812ce87871b19400d030010920300b882010015000000000000004136000000000000413600004054890032000000f04902005f000000000000000000000000000000ca20";
/// fixType 1: the receiver's dead reckoning only.
const PVT_DR_ONLY: &str = "b56201075c0032a64c17ea070c040c223b071400000080b2e60e0100e018cf6812ce87871b19400d0300109203000e00000015000000000000004136000000000000413600004054890032000000f04902005f0000000000000000000000000000008be6";
/// RTK fixed, but `valid` 0: neither date nor time resolved.
const PVT_NO_TIME: &str = "b56201075c007a9a4c17ea070c040c2238001400000080b2e60e0383e018cf6812ce87871b19400d0300109203000e00000015000000000000004136000000000000413600004054890032000000f04902005f000000000000000000000000000000423a";
/// NAV-STATUS: 3D, flags 0x0F, spoofDetState 1 (no spoofing), ttff 31.5 s.
const STATUS: &str = "b562010310007a9a4c17030f02880c7b000040e20100d170";
/// NAV-DOP: g 1.80, p 0.95, t 1.10, v 1.30, h 0.62, n 0.45, e 0.40.
const DOP: &str = "b562010412007a9a4c17b4005f006e0082003e002d00280024d9";

fn hex(s: &str) -> Vec<u8> {
    (0..s.len())
        .step_by(2)
        .map(|i| u8::from_str_radix(&s[i..i + 2], 16).unwrap())
        .collect()
}

/// The payload of a whole fixture frame.
fn payload(frame: &[u8]) -> &[u8] {
    &frame[6..frame.len() - 2]
}

#[test]
fn nav_pvt_is_read_field_by_field() {
    let f = hex(PVT_RTK_FIXED);
    let (a, b) = ubx::checksum(&f[2..f.len() - 2]);
    assert_eq!(
        (a, b),
        (f[f.len() - 2], f[f.len() - 1]),
        "the fixture's checksum"
    );
    let pvt = NavPvt::parse(payload(&f)).unwrap();
    assert_eq!(
        (pvt.date, pvt.hms, pvt.nano),
        ((2026, 12, 4), (12, 34, 56), 250_000_000)
    );
    assert_eq!(
        (pvt.fix_type, pvt.num_sv, pvt.carrier()),
        (3, 24, Carrier::Fixed)
    );
    assert!(pvt.gnss_fix_ok());
    assert_eq!((pvt.lat_e7, pvt.lon_e7), (421_234_567, -837_654_321));
    assert_eq!((pvt.h_acc_mm, pvt.v_acc_mm, pvt.hmsl_mm), (14, 21, 234_000));
    assert_eq!(pvt.vel_ned_mm_s, [0, 13_889, 0]);
    assert_eq!(
        (
            pvt.g_speed_mm_s,
            pvt.head_mot_e5,
            pvt.s_acc_mm_s,
            pvt.head_acc_e5
        ),
        (13_889, 9_000_000, 50, 150_000)
    );
    assert_eq!(pvt.pdop_e2, 95);
    assert_eq!(pvt.solution(), Solution::RtkFixed);
    let fix = pvt.fix().unwrap();
    assert_eq!(
        (fix.position.lat_e7(), fix.position.lon_e7()),
        (421_234_567, -837_654_321)
    );
    assert_eq!(
        (fix.accuracy_m, fix.accuracy_source),
        (Some(0.014), AccuracySource::Ubx)
    );
    assert_eq!((fix.speed_mps, fix.course_deg), (Some(13.889), Some(90.0)));
    let utc = fix.utc.unwrap();
    let ms = ((12 * 60 + 34) * 60 + 56) * 1000 + 250;
    assert_eq!(utc, super::nmea::utc_from_date(2026, 12, 4, ms).unwrap());
}

#[test]
fn nav_pvt_solutions_the_receiver_disowns_give_no_fix() {
    let float = NavPvt::parse(payload(&hex(PVT_RTK_FLOAT))).unwrap();
    assert_eq!(
        (float.solution(), float.fix().unwrap().accuracy_m),
        (Solution::RtkFloat, Some(0.18))
    );
    let none = NavPvt::parse(payload(&hex(PVT_NO_FIX))).unwrap();
    assert_eq!(none.fix(), Err(NoFix::NoFix));
    let dr = NavPvt::parse(payload(&hex(PVT_DR_ONLY))).unwrap();
    assert_eq!(dr.fix(), Err(NoFix::DeadReckoning));
    let untimed = NavPvt::parse(payload(&hex(PVT_NO_TIME))).unwrap();
    assert_eq!(untimed.epoch().outcome, Err(NoFix::NoTime));
    // gnssFixOK clear on a 3D fix (outside the receiver's masks): no fix.
    let mut p = hex(PVT_RTK_FIXED)[6..98].to_vec();
    p[21] &= !1;
    assert_eq!(NavPvt::parse(&p).unwrap().fix(), Err(NoFix::NoFix));
    // The u-blox 7 layout (84 bytes) is read; shorter is refused.
    assert!(NavPvt::parse(&p[..84]).is_ok());
    assert_eq!(NavPvt::parse(&p[..83]), Err(UbxError::ShortPayload));
    p[20] = 9;
    assert_eq!(NavPvt::parse(&p), Err(UbxError::BadField));
}

#[test]
fn nav_status_and_nav_dop() {
    let s = hex(STATUS);
    let Message::NavStatus(st) = ubx::parse(s[2], s[3], payload(&s)).unwrap() else {
        panic!("not NAV-STATUS")
    };
    assert_eq!(
        (st.gps_fix, st.flags, st.ttff_ms, st.spoofing()),
        (3, 0x0F, 31_500, false)
    );
    let d = hex(DOP);
    let Message::NavDop(dop) = ubx::parse(d[2], d[3], payload(&d)).unwrap() else {
        panic!("not NAV-DOP")
    };
    assert_eq!(dop.dops_e2, [180, 95, 110, 130, 62, 45, 40]);
    assert!((dop.hdop() - 0.62).abs() < 1e-6);
    assert_eq!(ubx::parse(0x0A, 0x04, &[]), Ok(Message::Other(0x0A, 0x04)));
}

/// What the framer cuts from `bytes`, fed `step` bytes at a time.
fn cut(bytes: &[u8], step: usize) -> Vec<std::string::String> {
    let mut f = Framer::new();
    let mut out = Vec::new();
    for piece in bytes.chunks(step) {
        f.push(piece, |p| {
            out.push(match p {
                Framed::Sentence(s) => std::format!("nmea {}", core::str::from_utf8(s).unwrap()),
                Framed::Ubx { class, id, payload } => {
                    std::format!("ubx {class:02x}{id:02x} {}", payload.len())
                }
                Framed::UbxSkipped { class, id } => std::format!("ubx-skipped {class:02x}{id:02x}"),
                Framed::UbxBadChecksum => "ubx-bad".into(),
                Framed::SentenceTooLong => "too-long".into(),
                Framed::Skipped(n) => std::format!("skip {n}"),
            })
        });
    }
    out
}

#[test]
fn the_framer_resynchronises_on_dollar_and_ubx_sync_through_binary() {
    let gga = b"$GPGGA,123456.25,4207.4074,N,08345.9259,W,4,24,0.6,234.0,M,,M,,*6B\r\n";
    let mut stream = Vec::new();
    stream.extend_from_slice(&[0xA0, 0xA2, 0x00, 0x05]); // a SiRF frame's start
    stream.extend_from_slice(gga);
    stream.extend_from_slice(&hex(PVT_RTK_FIXED));
    stream.extend_from_slice(b"$GPRMC,12345"); // cut by binary
    stream.extend_from_slice(&hex(DOP));
    let mut bad = hex(STATUS);
    bad[10] ^= 1;
    stream.extend_from_slice(&bad);
    stream.extend_from_slice(&[0xB5, 0x62, 0x01, 0x35, 0xF8, 0x00]); // NAV-SAT, 248 bytes
    stream.extend_from_slice(&[0u8; 250]);
    stream.extend_from_slice(&[0xB5, 0x62, 0x01, 0x07, 0xFF, 0xFF]); // no frame is 65535 long
    stream.extend_from_slice(gga);
    let want = [
        "skip 1",
        "skip 1",
        "skip 1",
        "skip 1",
        "nmea $GPGGA,123456.25,4207.4074,N,08345.9259,W,4,24,0.6,234.0,M,,M,,*6B",
        "ubx 0107 92",
        "skip 12",
        "ubx 0104 18",
        "ubx-bad",
        "ubx-skipped 0135",
        "skip 6",
        "nmea $GPGGA,123456.25,4207.4074,N,08345.9259,W,4,24,0.6,234.0,M,,M,,*6B",
    ];
    for step in [1, 7, stream.len()] {
        assert_eq!(cut(&stream, step), want, "fed {step} bytes at a time");
    }
}

#[test]
fn overlong_sentences_are_dropped_to_their_line_end() {
    let mut s = Vec::from(&b"$GPGSV,"[..]);
    s.extend(core::iter::repeat_n(b'1', MAX_LINE));
    s.extend_from_slice(b"\r\n$GPZDA,1\r\n");
    assert_eq!(cut(&s, 5), ["too-long", "nmea $GPZDA,1"]);
    const { assert!(MAX_UBX_KEPT >= 92, "NAV-PVT is kept") };
}

#[test]
fn a_mixed_stream_takes_its_fixes_from_nav_pvt() {
    let mut r = GnssReader::new();
    let mut events = Vec::new();
    let nmea = b"$GPGGA,123456.25,4207.4074,N,08345.9259,W,4,24,0.6,234.0,M,,M,,*6B\r\n";
    let mut stream = hex(PVT_RTK_FIXED);
    stream.extend_from_slice(nmea);
    stream.extend_from_slice(&hex(PVT_RTK_FLOAT));
    r.push(&stream, |e| events.push(e));
    r.finish(|e| events.push(e));
    let fixes: Vec<_> = events
        .iter()
        .filter_map(|e| match e {
            GnssEvent::Epoch(e) => Some((e.solution, e.outcome.map(|f| f.accuracy_source))),
            _ => None,
        })
        .collect();
    assert_eq!(
        fixes,
        [
            (Some(Solution::RtkFixed), Ok(AccuracySource::Ubx)),
            (Some(Solution::RtkFloat), Ok(AccuracySource::Ubx))
        ]
    );
    assert!(
        events.contains(&GnssEvent::CoveredByUbx),
        "the GGA of the same epoch is counted"
    );
    assert!(events.contains(&GnssEvent::Sentence("GGA")));
}
