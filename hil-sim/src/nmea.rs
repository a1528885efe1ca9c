//! NMEA 0183 sentences of a simulated GNSS receiver: GGA (position), RMC (speed, course,
//! date) and GST (accuracy), with checksums, in the order that lets a receiver-side
//! assembler complete one fix per epoch (GST, GGA, RMC).

use obu::LatLon;
use roadside::clock::Utc;
use std::fmt::Write;

/// One epoch of a simulated receiver.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Epoch {
    /// Time of the fix.
    pub utc: Utc,
    /// Position.
    pub position: LatLon,
    /// Speed over ground, m/s.
    pub speed_mps: f64,
    /// Course over ground, degrees true.
    pub course_deg: f64,
    /// 1-sigma horizontal error the receiver reports, metres (split evenly over latitude
    /// and longitude in GST).
    pub sigma_m: f64,
}

/// `$..*hh\r\n` around a body: the checksum is the XOR of the body's bytes.
pub fn sentence(body: &str) -> String {
    let sum = body.bytes().fold(0u8, |a, b| a ^ b);
    format!("${body}*{sum:02X}\r\n")
}

/// hhmmss.ss of a time of day.
fn hms(utc: &Utc) -> String {
    let cs = utc.ms_of_day / 10;
    let (h, m, s, c) = (cs / 360_000, cs / 6000 % 60, cs / 100 % 60, cs % 100);
    format!("{h:02}{m:02}{s:02}.{c:02}")
}

/// ddmm.mmmmmm,N / dddmm.mmmmmm,E of a position (7 decimals of minutes: ~2 mm).
fn lat_lon(p: LatLon) -> String {
    let part = |deg: f64, width: usize, pos: char, neg: char| {
        let hemi = if deg < 0.0 { neg } else { pos };
        let a = deg.abs();
        let mut d = a.trunc();
        let mut min = (a - d) * 60.0;
        if (min * 1e7).round() >= 60.0 * 1e7 {
            d += 1.0;
            min = 0.0;
        }
        format!("{:0w$}{:010.7},{hemi}", d as u32, min, w = width)
    };
    format!(
        "{},{}",
        part(p.lat_deg(), 2, 'N', 'S'),
        part(p.lon_deg(), 3, 'E', 'W')
    )
}

/// The GGA sentence of one epoch: `quality`, 12 satellites, `hdop`.
pub fn gga(e: &Epoch, quality: u8, hdop: f64) -> String {
    sentence(&format!(
        "GPGGA,{t},{pos},{quality},12,{hdop:.2},1600.0,M,-17.0,M,,",
        t = hms(&e.utc),
        pos = lat_lon(e.position)
    ))
}

/// The GST, GGA and RMC sentences of one epoch (fix quality 1, 12 satellites, HDOP 0.8).
pub fn epoch(e: &Epoch) -> String {
    let t = hms(&e.utc);
    let sd = e.sigma_m / std::f64::consts::SQRT_2;
    let mut out = String::new();
    out.push_str(&sentence(&format!(
        "GPGST,{t},{rms:.2},{sd:.2},{sd:.2},0.0,{sd:.2},{sd:.2},{alt:.2}",
        rms = e.sigma_m,
        alt = 2.0 * e.sigma_m
    )));
    out.push_str(&gga(e, 1, 0.8));
    let knots = e.speed_mps.max(0.0) / 0.514_444;
    let date = format!("{:02}{:02}{:02}", e.utc.day, e.utc.month, e.utc.year % 100);
    let mut rmc = String::new();
    let _ = write!(
        rmc,
        "GPRMC,{t},A,{pos},{knots:.2},{course:.1},{date},,,A",
        pos = lat_lon(e.position),
        course = e.course_deg.rem_euclid(360.0)
    );
    out.push_str(&sentence(&rmc));
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use obu::input::nmea::{parse, FixAssembler};

    #[test]
    fn checksum_of_a_known_sentence() {
        // The GGA example of the NMEA 0183 literature with its published checksum 47.
        assert_eq!(
            sentence("GPGGA,123519,4807.038,N,01131.000,E,1,08,0.9,545.4,M,46.9,M,,"),
            "$GPGGA,123519,4807.038,N,01131.000,E,1,08,0.9,545.4,M,46.9,M,,*47\r\n"
        );
    }

    #[test]
    fn the_obu_parser_reads_an_epoch_back() {
        let position = LatLon::from_degrees(-33.8688197, 151.2092955).unwrap();
        let utc = Utc::from_unix_ms(1_763_784_961_500);
        let text = epoch(&Epoch {
            utc,
            position,
            speed_mps: 22.0,
            course_deg: 91.5,
            sigma_m: 0.5,
        });
        let mut asm = FixAssembler::new();
        let mut fixes = Vec::new();
        for l in text.lines() {
            asm.push(&parse(l).unwrap(), |e| fixes.push(e.outcome.unwrap()));
        }
        asm.finish(|e| fixes.push(e.outcome.unwrap()));
        assert_eq!(fixes.len(), 1, "one fix per epoch");
        let f = fixes[0];
        assert!((f.position.lat_e7() - position.lat_e7()).abs() <= 2);
        assert!((f.position.lon_e7() - position.lon_e7()).abs() <= 2);
        assert!((f.speed_mps.unwrap() - 22.0).abs() < 0.01);
        assert!((f.course_deg.unwrap() - 91.5).abs() < 0.01);
        assert!((f.accuracy_m.unwrap() - 0.5).abs() < 0.01);
        let u = f.utc.expect("date and time");
        assert_eq!(
            u,
            obu::input::nmea::utc_from_date(2025, 11, 22, utc.ms_of_day).unwrap()
        );
    }
}

/// One epoch of a recorded NMEA log: seconds after the log's first epoch and its lines.
pub type RecordedEpoch = (f64, Vec<String>);

/// Splits a recorded log (one sentence a line; other lines ignored) into epochs by the
/// time field of GGA/RMC/GST, with each epoch's offset from the first (midnight rollover
/// handled).
pub fn read_epochs(text: &str) -> Vec<RecordedEpoch> {
    let mut out: Vec<RecordedEpoch> = Vec::new();
    let (mut first, mut last, mut days) = (None, None, 0.0);
    for line in text.lines().map(str::trim).filter(|l| l.starts_with('$')) {
        let Some(secs) = time_field(line) else {
            continue;
        };
        if last.is_some_and(|l: f64| secs + 43_200.0 < l) {
            days += 86_400.0;
        }
        last = Some(secs);
        let t = secs + days - *first.get_or_insert(secs);
        match out.last_mut() {
            Some((at, lines)) if (*at - t).abs() < 1e-6 => lines.push(line.to_string()),
            _ => out.push((t, vec![line.to_string()])),
        }
    }
    out
}

/// Seconds of the day of a GGA/RMC/GST sentence's time field.
fn time_field(line: &str) -> Option<f64> {
    let body = line.strip_prefix('$')?.split('*').next()?;
    let mut f = body.split(',');
    let kind = f.next()?;
    if !["GGA", "RMC", "GST"].iter().any(|k| kind.ends_with(k)) {
        return None;
    }
    let t = f.next()?;
    let (h, m, s): (f64, f64, f64) = (
        t.get(0..2)?.parse().ok()?,
        t.get(2..4)?.parse().ok()?,
        t.get(4..)?.parse().ok()?,
    );
    Some(h * 3600.0 + m * 60.0 + s)
}

/// The sentence with its time (and for RMC its date) set to `utc` and a new checksum; a
/// replayed log then agrees with the roadside's validity times. `None` for a line that is
/// not a GGA/RMC/GST sentence.
pub fn restamp(line: &str, utc: &Utc) -> Option<String> {
    time_field(line)?;
    let body = line.strip_prefix('$')?.split('*').next()?;
    let mut fields: Vec<String> = body.split(',').map(str::to_string).collect();
    let cs = utc.ms_of_day / 10;
    fields[1] = format!(
        "{:02}{:02}{:02}.{:02}",
        cs / 360_000,
        cs / 6000 % 60,
        cs / 100 % 60,
        cs % 100
    );
    if fields[0].ends_with("RMC") && fields.len() > 9 {
        fields[9] = format!("{:02}{:02}{:02}", utc.day, utc.month, utc.year % 100);
    }
    Some(sentence(&fields.join(",")))
}

#[cfg(test)]
mod replay_tests {
    use super::*;

    #[test]
    fn epochs_of_a_log_and_restamped_sentences() {
        let position = LatLon::from_degrees(39.7392, -104.9903).unwrap();
        let mut log = String::from("garbage line\n");
        for k in 0..3u64 {
            let utc = Utc::from_unix_ms(1_763_769_599_900 + k * 100); // crosses midnight
            log.push_str(&epoch(&Epoch {
                utc,
                position,
                speed_mps: 10.0,
                course_deg: 90.0,
                sigma_m: 0.5,
            }));
        }
        let epochs = read_epochs(&log);
        assert_eq!(epochs.len(), 3);
        assert!(epochs.iter().all(|(_, l)| l.len() == 3));
        assert!(
            (epochs[2].0 - 0.2).abs() < 1e-6,
            "offsets across midnight: {:?}",
            epochs.iter().map(|e| e.0).collect::<Vec<_>>()
        );
        let now = Utc::from_unix_ms(1_795_341_600_000); // 2026-11-22T10:00:00Z
        let rmc = epochs[0].1.iter().find(|l| l.contains("RMC")).unwrap();
        let again = restamp(rmc, &now).unwrap();
        let parsed = obu::input::nmea::parse(&again).expect("checksum and fields valid");
        match parsed {
            obu::input::nmea::Sentence::Rmc(r) => assert_eq!(r.date, Some((2026, 11, 22))),
            other => panic!("{other:?}"),
        }
        assert!(again.starts_with("$GPRMC,100000.00,A,"));
        assert_eq!(restamp("$GPVTG,1,2*00", &now), None);
    }
}
