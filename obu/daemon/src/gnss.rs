//! GNSS input: NMEA 0183 from a file (replayed at its own time stamps), a serial device, TCP
//! or UDP, or gpsd's JSON TPV reports over TCP. Lines are read with a length bound; every
//! refused sentence is counted with its reason; TCP sources reconnect with a back-off.

use crate::config::{Gnss, GnssSource};
use crate::counters::group;
use crate::hub::Hub;
use obu::fix::Fix;
use obu::geo::LatLon;
use obu::input::nmea::{self, FixAssembler, Sentence};
use obu::time::UtcTime;
use std::sync::Arc;
use std::time::Duration;
use tokio::io::{AsyncBufReadExt, AsyncRead, AsyncWriteExt, BufReader};
use tokio::sync::watch;

/// Longest line kept; longer ones are dropped whole.
const MAX_LINE: usize = 512;

/// Runs the configured source until `shutdown`; NMEA over UDP reads `udp`, the socket the
/// caller bound to the configured address.
pub async fn run(
    cfg: Gnss,
    udp: Option<tokio::net::UdpSocket>,
    hub: Arc<Hub>,
    shutdown: watch::Receiver<bool>,
) {
    match cfg.source {
        GnssSource::None => {}
        GnssSource::NmeaFile => nmea_file(&cfg, &hub, shutdown).await,
        GnssSource::NmeaSerial => match tokio::fs::File::open(&cfg.address).await {
            Ok(f) => read_lines(f, &hub, Parser::Nmea(FixAssembler::new()), shutdown).await,
            Err(_) => hub
                .counters
                .add(group::GNSS, "serial device cannot be opened"),
        },
        GnssSource::NmeaUdp => match udp {
            Some(sock) => nmea_udp(sock, &hub, shutdown).await,
            None => hub.counters.add(group::GNSS, "udp bind failed"),
        },
        GnssSource::NmeaTcp | GnssSource::Gpsd => tcp(&cfg, &hub, shutdown).await,
    }
}

/// What a line means, by source.
enum Parser {
    Nmea(FixAssembler),
    Gpsd,
}

impl Parser {
    fn line(&mut self, line: &str, hub: &Hub) {
        match self {
            Parser::Nmea(asm) => nmea_line(asm, line, hub),
            Parser::Gpsd => match gpsd_tpv(line) {
                Ok(Some((fix, mode))) => {
                    hub.counters.add(group::GNSS, "fix");
                    hub.on_fix(fix, Some(mode));
                }
                Ok(None) => {}
                Err(reason) => hub.counters.add(group::NMEA_ERRORS, reason),
            },
        }
    }
}

fn nmea_line(asm: &mut FixAssembler, line: &str, hub: &Hub) {
    let line = line.trim();
    if line.is_empty() {
        return;
    }
    match nmea::parse(line) {
        Ok(s) => {
            if let Some(fix) = asm.push(&s) {
                hub.counters.add(group::GNSS, "fix");
                hub.on_fix(fix, Some(asm.quality()));
            }
        }
        Err(nmea::NmeaError::Unsupported) => hub.counters.add(group::GNSS, "other sentence"),
        Err(e) => hub.counters.add(group::NMEA_ERRORS, e.as_str()),
    }
}

/// Reads lines from `r` (bounded) until EOF or shutdown.
async fn read_lines<R: AsyncRead + Unpin>(
    r: R,
    hub: &Hub,
    mut parser: Parser,
    mut shutdown: watch::Receiver<bool>,
) {
    let mut reader = BufReader::new(r);
    let mut buf = Vec::with_capacity(MAX_LINE);
    loop {
        buf.clear();
        let got = tokio::select! {
            got = read_bounded_line(&mut reader, &mut buf) => got,
            _ = shutdown.changed() => return,
        };
        match got {
            Ok(0) => return,
            Ok(_) if buf.len() > MAX_LINE => hub.counters.add(group::NMEA_ERRORS, "line too long"),
            Ok(_) => match std::str::from_utf8(&buf) {
                Ok(line) => parser.line(line, hub),
                Err(_) => hub.counters.add(group::NMEA_ERRORS, "not text"),
            },
            Err(_) => return,
        }
    }
}

/// Reads up to a newline, keeping at most MAX_LINE + 1 octets (the rest of a long line is
/// consumed and dropped). Returns the octets consumed.
async fn read_bounded_line<R: AsyncBufReadExt + Unpin>(
    r: &mut R,
    out: &mut Vec<u8>,
) -> std::io::Result<usize> {
    let mut total = 0;
    loop {
        let chunk = r.fill_buf().await?;
        if chunk.is_empty() {
            return Ok(total);
        }
        let (take, done) = match chunk.iter().position(|&b| b == b'\n') {
            Some(i) => (i + 1, true),
            None => (chunk.len(), false),
        };
        let room = (MAX_LINE + 1).saturating_sub(out.len());
        out.extend_from_slice(&chunk[..take.min(room)]);
        r.consume(take);
        total += take;
        if done {
            return Ok(total);
        }
    }
}

async fn nmea_file(cfg: &Gnss, hub: &Hub, mut shutdown: watch::Receiver<bool>) {
    let Ok(text) = tokio::fs::read_to_string(&cfg.address).await else {
        hub.counters.add(group::GNSS, "file cannot be read");
        return;
    };
    let mut asm = FixAssembler::new();
    let mut last_time: Option<u32> = None;
    for line in text.lines() {
        if cfg.realtime {
            if let Some(t) = sentence_time(line) {
                if let Some(prev) = last_time.filter(|&p| t > p && t - p < 60_000) {
                    tokio::select! {
                        _ = tokio::time::sleep(Duration::from_millis(u64::from(t - prev))) => {}
                        _ = shutdown.changed() => return,
                    }
                }
                last_time = Some(t);
            }
        }
        nmea_line(&mut asm, line, hub);
    }
    hub.counters.add(group::GNSS, "file replay finished");
}

/// The time stamp of a GGA/RMC/GST line, for pacing a replay.
fn sentence_time(line: &str) -> Option<u32> {
    match nmea::parse(line.trim()).ok()? {
        Sentence::Gga(g) => Some(g.time),
        Sentence::Rmc(r) => Some(r.time),
        Sentence::Gst(g) => Some(g.time),
        Sentence::Vtg(_) => None,
    }
}

async fn nmea_udp(sock: tokio::net::UdpSocket, hub: &Hub, mut shutdown: watch::Receiver<bool>) {
    let mut asm = FixAssembler::new();
    let mut buf = vec![0u8; 2048];
    loop {
        let n = tokio::select! {
            r = sock.recv_from(&mut buf) => match r { Ok((n, _)) => n, Err(_) => continue },
            _ = shutdown.changed() => return,
        };
        match std::str::from_utf8(&buf[..n]) {
            Ok(text) => text.lines().for_each(|l| nmea_line(&mut asm, l, hub)),
            Err(_) => hub.counters.add(group::NMEA_ERRORS, "not text"),
        }
    }
}

async fn tcp(cfg: &Gnss, hub: &Hub, mut shutdown: watch::Receiver<bool>) {
    let mut backoff = Duration::from_millis(250);
    loop {
        if let Ok(mut stream) = tokio::net::TcpStream::connect(&cfg.address).await {
            backoff = Duration::from_millis(250);
            hub.counters.add(group::GNSS, "connected");
            let parser = if cfg.source == GnssSource::Gpsd {
                if stream
                    .write_all(b"?WATCH={\"enable\":true,\"json\":true};\n")
                    .await
                    .is_err()
                {
                    continue;
                }
                Parser::Gpsd
            } else {
                Parser::Nmea(FixAssembler::new())
            };
            read_lines(stream, hub, parser, shutdown.clone()).await;
            hub.counters.add(group::GNSS, "disconnected");
        }
        tokio::select! {
            _ = tokio::time::sleep(backoff) => {}
            _ = shutdown.changed() => return,
        }
        backoff = (backoff * 2).min(Duration::from_secs(5));
    }
}

/// A gpsd TPV report as a fix and its mode (2 = 2D, 3 = 3D); `None` for other classes.
fn gpsd_tpv(line: &str) -> Result<Option<(Fix, u8)>, &'static str> {
    let v: serde_json::Value = serde_json::from_str(line).map_err(|_| "gpsd: not JSON")?;
    if v["class"] != "TPV" {
        return Ok(None);
    }
    let mode = v["mode"].as_u64().unwrap_or(0) as u8;
    if mode < 2 {
        return Ok(None);
    }
    let (lat, lon) = (
        v["lat"].as_f64().ok_or("gpsd: no lat")?,
        v["lon"].as_f64().ok_or("gpsd: no lon")?,
    );
    let position = LatLon::from_degrees(lat, lon).ok_or("gpsd: position out of range")?;
    let accuracy = match (v["epx"].as_f64(), v["epy"].as_f64()) {
        (Some(x), Some(y)) => Some((x * x + y * y).sqrt() as f32 / 1.96),
        _ => v["eph"].as_f64().map(|e| e as f32 / 1.96),
    };
    let fix = Fix {
        position,
        accuracy_m: accuracy,
        speed_mps: v["speed"].as_f64().map(|s| s as f32),
        course_deg: v["track"].as_f64().map(|t| t as f32),
        utc: v["time"].as_str().and_then(iso_utc),
    };
    Ok(Some((fix, mode)))
}

/// `2024-01-02T12:00:00.250Z` as a UTC time.
fn iso_utc(s: &str) -> Option<UtcTime> {
    let num = |r: std::ops::Range<usize>| s.get(r)?.parse::<u64>().ok();
    let (year, month, day) = (num(0..4)? as u16, num(5..7)?, num(8..10)?);
    let (h, m, sec) = (num(11..13)?, num(14..16)?, num(17..19)?);
    let frac = s
        .get(19..)
        .and_then(|f| f.strip_prefix('.'))
        .map_or(0, |f| {
            let digits: String = f
                .chars()
                .take_while(|c| c.is_ascii_digit())
                .take(3)
                .collect();
            digits.parse::<u64>().unwrap_or(0) * 10u64.pow(3 - digits.len() as u32)
        });
    if h > 23 || m > 59 || sec > 60 {
        return None;
    }
    let ms_of_day = ((h * 60 + m) * 60 + sec) * 1000 + frac;
    let month = u8::try_from(month).ok()?;
    nmea::utc_from_date(
        year,
        month,
        u8::try_from(day).ok()?,
        u32::try_from(ms_of_day).ok()?,
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn gpsd_tpv_reports() {
        let line = r#"{"class":"TPV","mode":3,"time":"2024-03-01T00:00:01.500Z","lat":42.5,"lon":-83.25,"speed":11.1,"track":90.5,"eph":2.0}"#;
        let (fix, mode) = gpsd_tpv(line).unwrap().unwrap();
        assert_eq!(mode, 3);
        assert_eq!(fix.position.lat_e7(), 425_000_000);
        assert_eq!(fix.speed_mps, Some(11.1));
        let utc = fix.utc.unwrap();
        assert_eq!((utc.year, utc.ms_of_year), (2024, 60 * 86_400_000 + 1500));
        assert_eq!(gpsd_tpv(r#"{"class":"SKY"}"#), Ok(None));
        assert_eq!(gpsd_tpv(r#"{"class":"TPV","mode":1}"#), Ok(None));
        assert!(gpsd_tpv("{garbage").is_err());
        assert!(gpsd_tpv(r#"{"class":"TPV","mode":3,"lat":95.0,"lon":0.0}"#).is_err());
    }

    #[tokio::test]
    async fn long_lines_are_bounded_and_dropped() {
        let mut input: Vec<u8> = vec![b'x'; 5000];
        input.extend_from_slice(b"\nshort\n");
        let mut r = BufReader::new(&input[..]);
        let mut buf = Vec::new();
        assert_eq!(read_bounded_line(&mut r, &mut buf).await.unwrap(), 5001);
        assert_eq!(buf.len(), MAX_LINE + 1);
        buf.clear();
        read_bounded_line(&mut r, &mut buf).await.unwrap();
        assert_eq!(buf, b"short\n");
    }
}
