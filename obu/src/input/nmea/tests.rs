//! Sentences written out as receivers send them (checksums computed here, the fields by
//! hand), and the epochs they make.

use super::*;
use std::format;

/// Appends the checksum to a sentence body written without it.
fn with_sum(body: &str) -> heapless::String<128> {
    let sum = body.bytes().fold(0u8, |a, b| a ^ b);
    let mut s = heapless::String::new();
    core::fmt::write(&mut s, format_args!("${body}*{sum:02X}")).unwrap();
    s
}

fn sentence(body: &str) -> Sentence {
    parse(&with_sum(body)).unwrap_or_else(|e| panic!("{body}: {e}"))
}

/// The epochs a sequence of sentence bodies makes (the last one flushed).
fn epochs(bodies: &[&str]) -> heapless::Vec<Epoch, 16> {
    let mut a = FixAssembler::new();
    let mut out = heapless::Vec::new();
    for b in bodies {
        a.push(&sentence(b), |e| out.push(e).unwrap());
    }
    a.finish(|e| out.push(e).unwrap());
    out
}

#[test]
fn gga_position_and_quality() {
    let Sentence::Gga(g) =
        sentence("GPGGA,123519.50,4807.038,N,01131.000,E,4,08,0.9,545.4,M,46.9,M,,")
    else {
        panic!("not GGA")
    };
    assert_eq!(g.time, Some(((12 * 60 + 35) * 60 + 19) * 1000 + 500));
    let p = g.position.unwrap();
    assert_eq!(p.lat_e7(), 481_173_000);
    assert_eq!(p.lon_e7(), 115_166_667);
    assert_eq!((g.quality, g.satellites), (Some(4), Some(8)));
    assert_eq!(g.hdop, Some(0.9));
}

#[test]
fn southern_western_hemispheres_are_negative() {
    let Sentence::Gga(g) = sentence("GNGGA,000000,3351.500,S,15112.000,W,1,05,1.2,10.0,M,,M,,")
    else {
        panic!("not GGA")
    };
    let p = g.position.unwrap();
    assert_eq!(p.lat_e7(), -338_583_333);
    assert_eq!(p.lon_e7(), -1_512_000_000);
}

#[test]
fn checksum_is_verified_and_required() {
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
        parse("$GPGGA,123519,4807.038,N,01131.000,E,1,08,0.9,545.4,M,46.9,M,,"),
        Err(NmeaError::MissingChecksum),
        "a checksum-less sentence is refused"
    );
    assert_eq!(parse("GPGGA,1*00"), Err(NmeaError::BadStart));
}

#[test]
fn every_talker_is_read() {
    for talker in ["GP", "GL", "GA", "GB", "BD", "GN", "GQ"] {
        let body =
            format!("{talker}RMC,123519,A,4807.038,N,01131.000,E,022.4,084.4,230394,003.1,W");
        assert!(
            matches!(parse(&with_sum(&body)), Ok(Sentence::Rmc(_))),
            "{talker}"
        );
    }
    assert_eq!(
        parse(&with_sum("PUBX,00,123519")),
        Err(NmeaError::Unsupported)
    );
    assert_eq!(
        parse(&with_sum("GPGSV,3,1,12")),
        Err(NmeaError::Unsupported)
    );
}

#[test]
fn rmc_speed_course_date_mode_and_status() {
    let Sentence::Rmc(r) =
        sentence("GPRMC,123519,A,4807.038,N,01131.000,E,022.4,084.4,230394,003.1,W")
    else {
        panic!("not RMC")
    };
    assert!(r.valid);
    assert!((r.speed_mps.unwrap() - 22.4 * KNOTS_TO_MPS).abs() < 1e-4);
    assert_eq!(r.course_deg, Some(84.4));
    assert_eq!(r.date, Some((1994, 3, 23)));
    assert_eq!(r.mode, None, "NMEA 2.2: no mode");
    let mode = |body: &str| match sentence(body) {
        Sentence::Rmc(r) => r.mode,
        _ => panic!("not RMC"),
    };
    // NMEA 2.3 mode, 4.1 navigational status (V: the receiver gives none).
    assert_eq!(
        mode("GNRMC,091232.000,A,4813.0535,N,00824.8697,E,0.00,0.00,101015,,,A,V"),
        Some(Solution::Autonomous)
    );
    assert_eq!(
        mode("GNRMC,091232.000,A,4813.0535,N,00824.8697,E,0.00,0.00,101015,,,R,S"),
        Some(Solution::RtkFixed)
    );
    assert_eq!(
        mode("GNRMC,091232.000,A,4813.0535,N,00824.8697,E,0.00,0.00,101015,,,F,C"),
        Some(Solution::RtkFloat)
    );
    assert_eq!(
        mode("GNRMC,091232.000,A,4813.0535,N,00824.8697,E,0.00,0.00,101015,,,A,U"),
        Some(Solution::Unsafe)
    );
    assert_eq!(
        mode("GPRMC,091232.000,V,4813.0535,N,00824.8697,E,,,101015,,,S"),
        Some(Solution::Simulator)
    );
    let Sentence::Rmc(r) =
        sentence("GPRMC,000231.099,A,4829.0005,N,00022.0015,E,0.15,212.28,2208-1,,,A")
    else {
        panic!("not RMC")
    };
    assert_eq!(
        (r.date, r.position.is_some()),
        (None, true),
        "a broken date, a good position"
    );
}

#[test]
fn gns_gll_gsa_vtg_zda() {
    let Sentence::Gns(g) =
        sentence("GNGNS,122310.2,3722.425671,N,12258.856215,W,DAN,14,0.9,1005.543,6.5,,,S")
    else {
        panic!("not GNS")
    };
    assert_eq!(
        (g.mode, g.satellites, g.hdop),
        (Solution::Differential, 14, Some(0.9))
    );
    let Sentence::Gns(g) =
        sentence("GPGNS,122310.2,3722.425671,N,12258.856215,W,SS,05,1.2,10.0,,,")
    else {
        panic!("not GNS")
    };
    assert_eq!(g.mode, Solution::Simulator);
    let Sentence::Gll(g) = sentence("GPGLL,4916.45,N,12311.12,W,225444,A,D") else {
        panic!("not GLL")
    };
    assert_eq!(
        (g.solution, g.time),
        (Solution::Differential, Some(82_484_000))
    );
    let Sentence::Gll(g) = sentence("GPGLL,4916.45,N,12311.12,W,225444,V,N") else {
        panic!("not GLL")
    };
    assert_eq!(g.solution, Solution::Invalid);
    let Sentence::Gsa(g) = sentence("GNGSA,A,3,23,09,16,07,26,03,27,22,,,,,1.71,1.01,1.38") else {
        panic!("not GSA")
    };
    assert_eq!(
        (g.fix_mode, g.pdop, g.hdop, g.vdop),
        (Some(3), Some(1.71), Some(1.01), Some(1.38))
    );
    let Sentence::Vtg(v) = sentence("GPVTG,054.7,T,034.4,M,005.5,N,010.2,K,E") else {
        panic!("not VTG")
    };
    assert!((v.speed_mps.unwrap() - 10.2 / 3.6).abs() < 1e-5);
    assert_eq!(v.mode, Some(Solution::Estimated));
    let Sentence::Zda(z) = sentence("GPZDA,201530.00,04,07,2002,00,00") else {
        panic!("not ZDA")
    };
    assert_eq!(z.date, Some((2002, 7, 4)));
    let Sentence::Gst(g) = sentence("GPGST,172814.0,0.006,0.023,0.020,273.6,0.3,0.4,0.031") else {
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
    assert_eq!(
        parse(&with_sum(
            "GPGGA,123519,4807.038,N,01131.000,E,12,08,,,,,,,"
        )),
        Err(NmeaError::BadField(6)),
        "no receiver defines quality 12"
    );
    assert_eq!(
        parse(&with_sum("GPGLL,36000.0000,N,72000.0000,E,000452.981,V")),
        Err(NmeaError::BadField(1))
    );
    let long = [b'A'; MAX_SENTENCE + 1];
    assert_eq!(
        parse(core::str::from_utf8(&long).unwrap()),
        Err(NmeaError::TooLong)
    );
}

#[test]
fn gga_rmc_gst_make_one_fix_with_accuracy_and_utc() {
    let e = epochs(&[
        "GPGST,120000.00,0.5,0.6,0.4,10.0,0.6,0.8,1.0",
        "GPGGA,120000.00,4807.038,N,01131.000,E,4,12,0.6,545.4,M,46.9,M,,",
        "GPRMC,120000.00,A,4807.038,N,01131.000,E,010.0,090.0,020124,,,R",
    ]);
    assert_eq!(e.len(), 1);
    let fix = e[0].outcome.unwrap();
    assert_eq!(e[0].solution, Some(Solution::RtkFixed));
    assert!((fix.accuracy_m.unwrap() - 1.0).abs() < 1e-6);
    assert_eq!(fix.accuracy_source, AccuracySource::Gst);
    assert_eq!(fix.course_deg, Some(90.0));
    let utc = fix.utc.unwrap();
    assert_eq!(
        (utc.year, utc.ms_of_year),
        (2024, 86_400_000 + 12 * 3_600_000)
    );
}

#[test]
fn a_fix_comes_as_soon_as_the_learned_cycle_is_complete() {
    let mut a = FixAssembler::new();
    let push = |a: &mut FixAssembler, body: &str| {
        let mut n = 0;
        a.push(&sentence(body), |_| n += 1);
        n
    };
    let gga = |t: &str| format!("GPGGA,{t},4807.038,N,01131.000,E,1,08,0.9,545.4,M,,M,,");
    let rmc = |t: &str| format!("GPRMC,{t},A,4807.038,N,01131.000,E,010.0,090.0,020124,,,A");
    let gst = |t: &str| format!("GPGST,{t},0.5,0.6,0.4,10.0,0.6,0.8,1.0");
    assert_eq!(push(&mut a, &gga("120000.00")), 0);
    assert_eq!(push(&mut a, &gst("120000.00")), 0);
    assert_eq!(
        push(&mut a, &rmc("120000.00")),
        1,
        "cycle unknown: GGA + RMC fix at once"
    );
    assert_eq!(push(&mut a, &gga("120001.00")), 0);
    assert_eq!(push(&mut a, &rmc("120001.00")), 0, "the cycle has a GST");
    assert_eq!(
        push(&mut a, "GPGSA,A,3,23,09,16,07,,,,,,,,,1.71,1.01,1.38"),
        0
    );
    assert_eq!(push(&mut a, &gst("120001.00")), 1, "complete at the GST");
    assert_eq!(
        push(&mut a, "GPVTG,054.7,T,034.4,M,005.5,N,010.2,K,A"),
        0,
        "once per epoch"
    );
    assert_eq!(
        push(&mut a, &gga("120002.00")),
        0,
        "the closed epoch was emitted already"
    );
}

#[test]
fn gga_only_rmc_only_and_alternating_receivers_get_a_fix_every_epoch() {
    let gga = |t: &str| format!("GPGGA,{t},4807.038,N,01131.000,E,1,08,0.9,545.4,M,,M,,");
    let rmc = |t: &str| format!("GPRMC,{t},A,4807.038,N,01131.000,E,010.0,090.0,020124,,,A");
    for bodies in [
        [gga("120000"), gga("120001"), gga("120002"), gga("120003")],
        [rmc("120000"), rmc("120001"), rmc("120002"), rmc("120003")],
        [gga("120000"), rmc("120001"), gga("120002"), rmc("120003")],
    ] {
        let refs: heapless::Vec<&str, 4> = bodies.iter().map(|s| s.as_str()).collect();
        let e = epochs(&refs);
        assert_eq!(e.len(), 4, "{refs:?}");
        assert!(e.iter().all(|e| e.outcome.is_ok()));
        assert_eq!(e[3].time, 43_203_000);
    }
}

#[test]
fn a_gga_without_quality_takes_the_rmcs_validity() {
    let e = epochs(&[
        "GPGGA,120000.00,4807.038,N,01131.000,E,,08,0.9,545.4,M,,M,,",
        "GPRMC,120000.00,A,4807.038,N,01131.000,E,010.0,090.0,020124,,",
    ]);
    assert!(e[0].outcome.is_ok());
    let e = epochs(&["GPGGA,120000.00,4807.038,N,01131.000,E,,08,0.9,545.4,M,,M,,"]);
    assert_eq!(
        e[0].outcome,
        Err(NoFix::NotQualified),
        "nothing says it is valid"
    );
}

#[test]
fn a_position_the_receiver_disowns_is_never_a_fix() {
    let cases = [
        (
            "GPGGA,120000,4807.038,N,01131.000,E,0,08,0.9,545.4,M,,M,,",
            NoFix::NoFix,
        ),
        (
            "GPGGA,120000,4807.038,N,01131.000,E,6,08,0.9,545.4,M,,M,,",
            NoFix::DeadReckoning,
        ),
        (
            "GPGGA,120000,4807.038,N,01131.000,E,7,08,0.9,545.4,M,,M,,",
            NoFix::Manual,
        ),
        (
            "GPGGA,120000,4807.038,N,01131.000,E,8,08,0.9,545.4,M,,M,,",
            NoFix::Simulator,
        ),
        (
            "GPGGA,120000,4807.038,N,01131.000,E,1,00,3.3,545.4,M,,M,,",
            NoFix::NoSatellites,
        ),
        (
            "GPRMC,120000,V,4807.038,N,01131.000,E,010.0,090.0,020124,,",
            NoFix::NoFix,
        ),
        (
            "GPRMC,120000,A,4807.038,N,01131.000,E,010.0,090.0,020124,,,E",
            NoFix::DeadReckoning,
        ),
        (
            "GPRMC,120000,A,4807.038,N,01131.000,E,010.0,090.0,020124,,,S",
            NoFix::Simulator,
        ),
        (
            "GPRMC,120000,A,4807.038,N,01131.000,E,010.0,090.0,020124,,,M",
            NoFix::Manual,
        ),
        (
            "GPRMC,120000,A,4807.038,N,01131.000,E,010.0,090.0,020124,,,N",
            NoFix::NoFix,
        ),
        ("GPGLL,4807.038,N,01131.000,E,120000,V,N", NoFix::NoFix),
        (
            "GNGNS,120000,4807.038,N,01131.000,E,NN,08,0.9,545.4,,,",
            NoFix::NoFix,
        ),
        (
            "GNRMC,120000,A,4807.038,N,01131.000,E,010.0,090.0,020124,,,A,U",
            NoFix::Unsafe,
        ),
    ];
    for (body, why) in cases {
        assert_eq!(epochs(&[body])[0].outcome, Err(why), "{body}");
    }
    // A simulator GGA beside a valid RMC: the warning wins.
    let e = epochs(&[
        "GPGGA,120000,4807.038,N,01131.000,E,8,08,0.9,545.4,M,,M,,",
        "GPRMC,120000,A,4807.038,N,01131.000,E,010.0,090.0,020124,,",
    ]);
    assert_eq!(e[0].outcome, Err(NoFix::Simulator));
}

#[test]
fn without_gst_the_accuracy_is_hdop_times_the_solutions_range_error() {
    let fix = |q: u8| {
        let body = format!("GPGGA,120000,4807.038,N,01131.000,E,{q},08,0.8,545.4,M,,M,,");
        epochs(&[&body])[0].outcome.unwrap()
    };
    let m = AccuracyModel::DEFAULT;
    for (q, uere) in [
        (1, m.autonomous_m),
        (2, m.differential_m),
        (5, m.rtk_float_m),
        (4, m.rtk_fixed_m),
    ] {
        let f = fix(q);
        assert_eq!(f.accuracy_source, AccuracySource::Hdop);
        assert!(
            (f.accuracy_m.unwrap() - 0.8 * uere).abs() < 1e-6,
            "quality {q}"
        );
    }
    let none = epochs(&["GPRMC,120000,A,4807.038,N,01131.000,E,010.0,090.0,020124,,"]);
    let f = none[0].outcome.unwrap();
    assert_eq!(
        (f.accuracy_m, f.accuracy_source),
        (None, AccuracySource::None)
    );
}

#[test]
fn stamps_a_few_ms_apart_are_one_epoch_and_the_date_rolls_at_midnight() {
    let e = epochs(&[
        "GPGLL,5313.2228,N,00634.4228,E,200619.295,A",
        "GPGGA,200619.30,5313.2228,N,00634.4228,E,1,05,2.6,00000,M,,,,",
        "GPRMC,200619.30,A,5313.2228,N,00634.4228,E,00.0,000.0,200506,00,W",
    ]);
    assert_eq!(e.len(), 1);
    assert_eq!(e[0].time, 72_379_300, "named by the GGA");
    let e = epochs(&[
        "GPRMC,235959.50,A,4807.038,N,01131.000,E,010.0,090.0,311224,,",
        "GPGGA,000000.50,4807.038,N,01131.000,E,1,08,0.9,545.4,M,,M,,",
    ]);
    let utc = e[1].outcome.unwrap().utc.unwrap();
    assert_eq!(
        (utc.year, utc.ms_of_year),
        (2025, 500),
        "the day after the RMC's date"
    );
}

#[test]
fn a_gga_only_receiver_takes_its_date_from_a_hint() {
    let mut a = FixAssembler::new();
    a.set_date_hint(utc_from_date(2026, 12, 4, 23 * 3_600_000 + 59 * 60_000).unwrap());
    let mut out: heapless::Vec<Epoch, 2> = heapless::Vec::new();
    a.push(
        &sentence("GPGGA,000001.00,4807.038,N,01131.000,E,1,08,0.9,545.4,M,,M,,"),
        |e| out.push(e).unwrap(),
    );
    a.finish(|e| out.push(e).unwrap());
    let utc = out[0].outcome.unwrap().utc.unwrap();
    assert_eq!(
        utc,
        utc_from_date(2026, 12, 5, 1000).unwrap(),
        "just after midnight: the next day"
    );
}

#[test]
fn leap_year_months() {
    assert_eq!(days_before_month(2024, 3), 60);
    assert_eq!(days_before_month(2023, 3), 59);
    assert_eq!(days_before_month(2000, 12), 335);
}

#[test]
fn a_receiver_without_velocity_gets_one_from_its_positions() {
    // GGA only at 10 Hz, heading east at 10 m/s on the equator (1e-7 deg = 1.113 cm):
    // 1 m = 0.00000898 degrees = 0.00053898 minutes each 100 ms.
    let mut bodies = std::vec::Vec::new();
    for k in 0..20u32 {
        let min = 30.0 + 0.000_538_98 * f64::from(k);
        let t = format!("1200{:02}.{}0", k / 10, k % 10);
        bodies.push(format!(
            "GPGGA,{t},0000.000000,N,000{min:09.6},E,2,12,0.8,10.0,M,,M,,"
        ));
    }
    let refs: std::vec::Vec<&str> = bodies.iter().map(|s| s.as_str()).collect();
    let mut a = FixAssembler::new();
    let mut fixes = std::vec::Vec::new();
    for b in &refs {
        a.push(&sentence(b), |e| fixes.push(e.outcome.unwrap()));
    }
    a.finish(|e| fixes.push(e.outcome.unwrap()));
    assert_eq!(fixes.len(), 20);
    assert_eq!(fixes[0].speed_mps, None, "no position before the first");
    let last = fixes[19];
    assert!(
        (last.speed_mps.unwrap() - 10.0).abs() < 0.05,
        "{:?}",
        last.speed_mps
    );
    assert!(
        (last.course_deg.unwrap() - 90.0).abs() < 0.5,
        "{:?}",
        last.course_deg
    );
}
