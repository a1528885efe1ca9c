//! GNSS input: a receiver's bytes (NMEA 0183 and u-blox UBX, mixed or not, other binary
//! skipped and counted) from a file (replayed at its epochs' own time stamps), a serial
//! device, TCP or UDP, read by the core's [`GnssReader`]; or gpsd's JSON TPV reports over
//! TCP (lines read with a length bound). Every refused sentence and every epoch without a
//! fix is counted with its reason; TCP sources reconnect with a back-off.

use crate::config::{Gnss, GnssSource};
use crate::counters::group;
use crate::hub::Hub;
use obu::fix::{AccuracySource, Fix};
use obu::geo::LatLon;
use obu::input::gnss::{GnssEvent, GnssReader};
use obu::input::nmea::{self, NoFix, Solution};
use obu::time::UtcTime;
use std::sync::Arc;
use std::time::Duration;
use tokio::io::{AsyncBufReadExt, AsyncRead, AsyncReadExt, AsyncWriteExt, BufReader};
use tokio::sync::watch;

/// Longest gpsd line kept; longer ones are dropped whole.
const MAX_LINE: usize = 512;

/// Runs the configured source until `shutdown`; NMEA over UDP reads `udp`, the socket the
/// caller bound to the configured address.
pub async fn run(
    cfg: Gnss,
    udp: Option<tokio::net::UdpSocket>,
    hub: Arc<Hub>,
    shutdown: watch::Receiver<bool>,
) {
    let reader = Receiver::new(&cfg);
    match cfg.source {
        GnssSource::None => {}
        GnssSource::NmeaFile => nmea_file(&cfg, reader, &hub, shutdown).await,
        GnssSource::NmeaSerial | GnssSource::UbxSerial => {
            match tokio::fs::File::open(&cfg.address).await {
                Ok(f) => read_bytes(f, reader, &hub, shutdown).await,
                Err(_) => hub
                    .counters
                    .add(group::GNSS, "serial device cannot be opened"),
            }
        }
        GnssSource::NmeaUdp => match udp {
            Some(sock) => nmea_udp(sock, reader, &hub, shutdown).await,
            None => hub.counters.add(group::GNSS, "udp bind failed"),
        },
        GnssSource::NmeaTcp | GnssSource::Gpsd => tcp(&cfg, &hub, shutdown).await,
    }
}

/// A receiver's byte stream, read by the core's [`GnssReader`] (NMEA and UBX, binary
/// skipped), its events counted and its fixes handed to the hub.
struct Receiver {
    reader: GnssReader,
}

impl Receiver {
    fn new(cfg: &Gnss) -> Self {
        Self {
            reader: GnssReader::with_model(cfg.uere.model()),
        }
    }

    /// Reads `bytes`, handing each event to `take` (in order).
    fn read(&mut self, bytes: &[u8], take: impl FnMut(GnssEvent)) {
        // For receivers that send no date (GGA only): the system's.
        if let Some(utc) = crate::hub::system_utc() {
            self.reader.set_date_hint(utc);
        }
        self.reader.push(bytes, take);
    }

    /// Reads `bytes` and delivers what they give.
    fn feed(&mut self, bytes: &[u8], hub: &Hub) {
        self.read(bytes, |e| deliver(e, hub));
    }
}

/// Counts one event of the reader and hands a fix (or the reason for none) to the hub.
fn deliver(e: GnssEvent, hub: &Hub) {
    let c = &hub.counters;
    match e {
        GnssEvent::Epoch(epoch) => match epoch.outcome {
            Ok(fix) => {
                c.add(group::GNSS, "fix");
                hub.on_fix(fix, epoch.solution);
            }
            Err(why) => {
                c.add(group::GNSS_NO_FIX, why.as_str());
                hub.on_no_fix(epoch.solution, why);
            }
        },
        GnssEvent::Sentence(kind) | GnssEvent::Ubx(kind) => c.add(group::GNSS_MESSAGES, kind),
        GnssEvent::OtherSentence => c.add(group::GNSS, "other sentence"),
        GnssEvent::NmeaError(e) => c.add(group::NMEA_ERRORS, e.as_str()),
        GnssEvent::UbxError(e) => c.add(group::NMEA_ERRORS, e.as_str()),
        GnssEvent::CoveredByUbx => c.add(group::GNSS, "nmea epoch covered by ubx"),
        GnssEvent::Skipped(n) => c.add_n(group::GNSS, "bytes skipped", n as u64),
    }
}

/// What a line means on a gpsd connection.
fn gpsd_line(line: &str, hub: &Hub) {
    match gpsd_tpv(line) {
        Ok(Some((fix, solution))) => {
            hub.counters.add(group::GNSS, "fix");
            hub.on_fix(fix, Some(solution));
        }
        Ok(None) => {}
        Err(TpvError::NoFix(solution, why)) => {
            hub.counters.add(group::GNSS_NO_FIX, why.as_str());
            hub.on_no_fix(Some(solution), why);
        }
        Err(TpvError::Bad(reason)) => hub.counters.add(group::NMEA_ERRORS, reason),
    }
}

/// Reads a byte stream (a serial device, a TCP connection) until EOF or shutdown.
async fn read_bytes<R: AsyncRead + Unpin>(
    mut r: R,
    mut receiver: Receiver,
    hub: &Hub,
    mut shutdown: watch::Receiver<bool>,
) {
    let mut buf = vec![0u8; 4096];
    loop {
        let got = tokio::select! {
            got = r.read(&mut buf) => got,
            _ = shutdown.changed() => return,
        };
        match got {
            Ok(0) | Err(_) => return,
            Ok(n) => receiver.feed(&buf[..n], hub),
        }
    }
}

/// Reads gpsd's JSON lines (bounded) until EOF or shutdown.
async fn read_gpsd<R: AsyncRead + Unpin>(r: R, hub: &Hub, mut shutdown: watch::Receiver<bool>) {
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
                Ok(line) if !line.trim().is_empty() => gpsd_line(line.trim(), hub),
                Ok(_) => {}
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

/// Replays a recorded receiver's file, bytes as they are (NMEA, UBX, binary between), at
/// the pace of its epochs' own time stamps when `realtime`.
async fn nmea_file(
    cfg: &Gnss,
    mut receiver: Receiver,
    hub: &Hub,
    mut shutdown: watch::Receiver<bool>,
) {
    let Ok(bytes) = tokio::fs::read(&cfg.address).await else {
        hub.counters.add(group::GNSS, "file cannot be read");
        return;
    };
    let mut last_time: Option<u32> = None;
    let mut events = Vec::new();
    for piece in bytes.split_inclusive(|&b| b == b'\n') {
        receiver.read(piece, |e| events.push(e));
        for e in events.drain(..) {
            if let (true, GnssEvent::Epoch(epoch)) = (cfg.realtime, &e) {
                let t = epoch.time;
                if let Some(prev) = last_time.filter(|&p| t > p && t - p < 60_000) {
                    tokio::select! {
                        _ = tokio::time::sleep(Duration::from_millis(u64::from(t - prev))) => {}
                        _ = shutdown.changed() => return,
                    }
                }
                last_time = Some(t);
            }
            deliver(e, hub);
        }
    }
    receiver.reader.finish(|e| deliver(e, hub));
    hub.counters.add(group::GNSS, "file replay finished");
}

async fn nmea_udp(
    sock: tokio::net::UdpSocket,
    mut receiver: Receiver,
    hub: &Hub,
    mut shutdown: watch::Receiver<bool>,
) {
    let mut buf = vec![0u8; 2048];
    loop {
        let n = tokio::select! {
            r = sock.recv_from(&mut buf) => match r { Ok((n, _)) => n, Err(_) => continue },
            _ = shutdown.changed() => return,
        };
        receiver.feed(&buf[..n], hub);
    }
}

async fn tcp(cfg: &Gnss, hub: &Hub, mut shutdown: watch::Receiver<bool>) {
    let mut backoff = Duration::from_millis(250);
    loop {
        if let Ok(mut stream) = tokio::net::TcpStream::connect(&cfg.address).await {
            backoff = Duration::from_millis(250);
            hub.counters.add(group::GNSS, "connected");
            if cfg.source == GnssSource::Gpsd {
                if stream
                    .write_all(b"?WATCH={\"enable\":true,\"json\":true};\n")
                    .await
                    .is_err()
                {
                    continue;
                }
                read_gpsd(stream, hub, shutdown.clone()).await;
            } else {
                read_bytes(stream, Receiver::new(cfg), hub, shutdown.clone()).await;
            }
            hub.counters.add(group::GNSS, "disconnected");
        }
        tokio::select! {
            _ = tokio::time::sleep(backoff) => {}
            _ = shutdown.changed() => return,
        }
        backoff = (backoff * 2).min(Duration::from_secs(5));
    }
}

/// Why a TPV report gives no fix.
#[derive(Debug, PartialEq)]
enum TpvError {
    /// gpsd reports a position it marks simulated or dead-reckoned.
    NoFix(Solution, NoFix),
    /// Not a TPV gpsd would send.
    Bad(&'static str),
}

/// A gpsd TPV report as a fix and the solution its `status` names (gpsd: 2 DGPS, 3 RTK
/// fixed, 4 RTK float, 5 dead reckoning, 6 GNSS + dead reckoning, 8 simulated); `None`
/// for other classes and for mode 0/1. A simulated or dead-reckoned report is no fix.
fn gpsd_tpv(line: &str) -> Result<Option<(Fix, Solution)>, TpvError> {
    let v: serde_json::Value =
        serde_json::from_str(line).map_err(|_| TpvError::Bad("gpsd: not JSON"))?;
    if v["class"] != "TPV" {
        return Ok(None);
    }
    let mode = v["mode"].as_u64().unwrap_or(0) as u8;
    if mode < 2 {
        return Ok(None);
    }
    let solution = match v["status"].as_u64() {
        Some(2) => Solution::Differential,
        Some(3) => Solution::RtkFixed,
        Some(4) => Solution::RtkFloat,
        Some(5) => return Err(TpvError::NoFix(Solution::Estimated, NoFix::DeadReckoning)),
        Some(8) => return Err(TpvError::NoFix(Solution::Simulator, NoFix::Simulator)),
        _ => Solution::Autonomous,
    };
    let (lat, lon) = (
        v["lat"].as_f64().ok_or(TpvError::Bad("gpsd: no lat"))?,
        v["lon"].as_f64().ok_or(TpvError::Bad("gpsd: no lon"))?,
    );
    let position =
        LatLon::from_degrees(lat, lon).ok_or(TpvError::Bad("gpsd: position out of range"))?;
    let accuracy = match (v["epx"].as_f64(), v["epy"].as_f64()) {
        (Some(x), Some(y)) => Some((x * x + y * y).sqrt() as f32 / 1.96),
        _ => v["eph"].as_f64().map(|e| e as f32 / 1.96),
    };
    let fix = Fix {
        position,
        accuracy_m: accuracy,
        accuracy_source: if accuracy.is_some() {
            AccuracySource::Gpsd
        } else {
            AccuracySource::None
        },
        speed_mps: v["speed"].as_f64().map(|s| s as f32),
        course_deg: v["track"].as_f64().map(|t| t as f32),
        utc: v["time"].as_str().and_then(iso_utc),
    };
    Ok(Some((fix, solution)))
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
        let (fix, solution) = gpsd_tpv(line).unwrap().unwrap();
        assert_eq!(solution, Solution::Autonomous);
        assert_eq!(fix.position.lat_e7(), 425_000_000);
        assert_eq!(fix.speed_mps, Some(11.1));
        let utc = fix.utc.unwrap();
        assert_eq!((utc.year, utc.ms_of_year), (2024, 60 * 86_400_000 + 1500));
        assert_eq!(gpsd_tpv(r#"{"class":"SKY"}"#), Ok(None));
        assert_eq!(gpsd_tpv(r#"{"class":"TPV","mode":1}"#), Ok(None));
        assert!(gpsd_tpv("{garbage").is_err());
        assert!(gpsd_tpv(r#"{"class":"TPV","mode":3,"lat":95.0,"lon":0.0}"#).is_err());
        let sim = r#"{"class":"TPV","status":8,"mode":3,"lat":38.9,"lon":-77.4}"#;
        assert_eq!(
            gpsd_tpv(sim),
            Err(TpvError::NoFix(Solution::Simulator, NoFix::Simulator))
        );
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
