//! `obu gnss-check`: reads a GNSS receiver (a serial device, TCP, UDP or a recorded file)
//! for a while through the same reader the daemon uses, and says what the OBU gets from
//! it: sentences and UBX messages, epochs with and without a fix and why, the fix rate,
//! where the accuracy comes from, whether the time is valid, and a verdict on lane-level
//! use (at least 5 fixes a second, an accuracy with each fix, the receiver's own time and
//! no simulator or dead-reckoned positions). Exit status 0 when good enough, 1 when not, 2
//! when the receiver cannot be read.

use std::collections::BTreeMap;
use std::io::Read;
use std::time::{Duration, Instant};

use obu::fix::AccuracySource;
use obu::input::gnss::{GnssEvent, GnssReader};
use obu::input::nmea::{AccuracyModel, DayMillis, NoFix, Solution};

use crate::config::GnssSource;

/// Fixes per second lane-level use needs.
pub const MIN_RATE_HZ: f64 = 5.0;
/// Share of fixes that must carry an accuracy and a UTC date.
pub const MIN_SHARE: f64 = 0.95;

/// What was read.
#[derive(Debug, Default)]
pub struct Tally {
    /// Sentences and UBX messages read, by type.
    pub messages: BTreeMap<&'static str, u64>,
    /// Well-formed sentences of types not read.
    pub other_sentences: u64,
    /// Refused sentences and UBX frames, by reason.
    pub errors: BTreeMap<&'static str, u64>,
    /// Bytes that belonged to no sentence or frame.
    pub skipped_bytes: u64,
    /// Epochs with a fix, by solution.
    pub fixes: BTreeMap<&'static str, u64>,
    /// Epochs without a fix, by reason.
    pub no_fix: BTreeMap<&'static str, u64>,
    /// Fixes by where their accuracy comes from.
    pub accuracy: BTreeMap<&'static str, u64>,
    /// Fixes with a UTC date and time.
    pub dated: u64,
    /// Time of day of the first and last fix, ms.
    span: Option<(DayMillis, DayMillis)>,
    /// NMEA epochs a NAV-PVT covered.
    pub covered_by_ubx: u64,
}

impl Tally {
    /// Counts one event of the reader.
    pub fn take(&mut self, e: GnssEvent) {
        match e {
            GnssEvent::Epoch(epoch) => match epoch.outcome {
                Ok(fix) => {
                    let solution = epoch.solution.map_or("unstated", Solution::as_str);
                    *self.fixes.entry(solution).or_default() += 1;
                    *self
                        .accuracy
                        .entry(fix.accuracy_source.as_str())
                        .or_default() += 1;
                    self.dated += u64::from(fix.utc.is_some());
                    let t = epoch.time;
                    self.span = Some(self.span.map_or((t, t), |(a, _)| (a, t)));
                }
                Err(why) => *self.no_fix.entry(why.as_str()).or_default() += 1,
            },
            GnssEvent::Sentence(k) | GnssEvent::Ubx(k) => *self.messages.entry(k).or_default() += 1,
            GnssEvent::OtherSentence => self.other_sentences += 1,
            GnssEvent::NmeaError(e) => *self.errors.entry(e.as_str()).or_default() += 1,
            GnssEvent::UbxError(e) => *self.errors.entry(e.as_str()).or_default() += 1,
            GnssEvent::CoveredByUbx => self.covered_by_ubx += 1,
            GnssEvent::Skipped(n) => self.skipped_bytes += n as u64,
        }
    }

    /// Epochs with a fix.
    pub fn fix_count(&self) -> u64 {
        self.fixes.values().sum()
    }

    /// Fixes per second, from the receiver's own time stamps (`None` below two fixes).
    pub fn rate_hz(&self) -> Option<f64> {
        let (a, b) = self.span?;
        let ms = (i64::from(b) - i64::from(a)).rem_euclid(86_400_000);
        (ms > 0 && self.fix_count() > 1).then(|| (self.fix_count() - 1) as f64 * 1000.0 / ms as f64)
    }

    /// Why the receiver is not good enough for lane-level use (empty: it is).
    pub fn shortcomings(&self) -> Vec<String> {
        let mut out = Vec::new();
        let fixes = self.fix_count();
        if fixes == 0 {
            out.push("no fix at all".to_string());
        }
        match self.rate_hz() {
            _ if fixes == 0 => {}
            Some(r) if r >= MIN_RATE_HZ => {}
            Some(r) => out.push(format!(
                "{r:.1} fixes a second (lane level needs {MIN_RATE_HZ})"
            )),
            None => out.push("a single fix: no rate".to_string()),
        }
        let unknown = self
            .accuracy
            .get(AccuracySource::None.as_str())
            .copied()
            .unwrap_or(0);
        if (fixes - unknown) as f64 / (fixes as f64) < MIN_SHARE {
            out.push(format!(
                "{unknown} of {fixes} fixes without an accuracy (no GST, hAcc or HDOP)"
            ));
        }
        if fixes > 0 && (self.dated as f64) / (fixes as f64) < MIN_SHARE {
            out.push(format!(
                "{} of {fixes} fixes without a UTC date (no RMC, ZDA or NAV-PVT time)",
                fixes - self.dated
            ));
        }
        for why in [NoFix::Simulator, NoFix::DeadReckoning, NoFix::Manual] {
            if let Some(n) = self.no_fix.get(why.as_str()) {
                out.push(format!("{n} epochs the receiver marks {}", why.as_str()));
            }
        }
        out
    }

    /// The report, as printed (`seconds`: how long a live source was read; `None` for a
    /// file, read whole).
    pub fn report(&self, source: &str, seconds: Option<f64>) -> String {
        let read = seconds.map_or("read whole".to_string(), |s| format!("{s:.1} s read"));
        let mut s = format!("gnss-check: {source}, {read}\n");
        let list = |m: &BTreeMap<&'static str, u64>| {
            if m.is_empty() {
                "none".to_string()
            } else {
                m.iter()
                    .map(|(k, v)| format!("{k} {v}"))
                    .collect::<Vec<_>>()
                    .join(", ")
            }
        };
        s += &format!(
            "  messages:        {}; other sentences {}\n",
            list(&self.messages),
            self.other_sentences
        );
        s += &format!(
            "  refused:         {}; bytes skipped {}\n",
            list(&self.errors),
            self.skipped_bytes
        );
        let no_fix: u64 = self.no_fix.values().sum();
        s += &format!(
            "  epochs:          {} with a fix ({}), {no_fix} without ({})\n",
            self.fix_count(),
            list(&self.fixes),
            list(&self.no_fix)
        );
        if self.covered_by_ubx > 0 {
            s += &format!(
                "  nmea epochs taken from NAV-PVT instead: {}\n",
                self.covered_by_ubx
            );
        }
        let rate = self
            .rate_hz()
            .map_or("-".to_string(), |r| format!("{r:.1} Hz"));
        s += &format!("  fix rate:        {rate}\n");
        s += &format!("  accuracy from:   {}\n", list(&self.accuracy));
        s += &format!(
            "  utc date/time:   {} of {} fixes\n",
            self.dated,
            self.fix_count()
        );
        let short = self.shortcomings();
        if short.is_empty() {
            s += "verdict: GOOD for lane-level use\n";
        } else {
            s += "verdict: NOT GOOD for lane-level use:\n";
            for why in short {
                s += &format!("  - {why}\n");
            }
        }
        s
    }
}

/// What to read.
#[derive(Clone, Debug, PartialEq)]
pub struct CheckArgs {
    /// The source kind (as `[gnss] source`; not gpsd).
    pub source: GnssSource,
    /// Path, device, host:port or UDP bind address.
    pub address: String,
    /// How long to read a live source.
    pub seconds: f64,
}

/// Reads the source and prints the report; the exit status.
pub fn run(args: &CheckArgs) -> u8 {
    let mut reader = GnssReader::with_model(AccuracyModel::DEFAULT);
    let mut tally = Tally::default();
    let started = Instant::now();
    let read = read_source(args, |bytes| reader.push(bytes, |e| tally.take(e)));
    reader.finish(|e| tally.take(e));
    if let Err(e) = read {
        eprintln!("obu gnss-check: {}: {e}", args.address);
        return 2;
    }
    let name = format!("{} {}", args.source.name(), args.address);
    let seconds = (args.source != GnssSource::NmeaFile).then(|| started.elapsed().as_secs_f64());
    print!("{}", tally.report(&name, seconds));
    u8::from(!tally.shortcomings().is_empty())
}

/// Hands the source's bytes to `take` for `args.seconds` (a file: all of it).
fn read_source(args: &CheckArgs, mut take: impl FnMut(&[u8])) -> std::io::Result<()> {
    let deadline = Instant::now() + Duration::from_secs_f64(args.seconds.clamp(0.1, 3600.0));
    let mut buf = vec![0u8; 4096];
    let mut stream: Box<dyn Read> = match args.source {
        GnssSource::NmeaFile => {
            take(&std::fs::read(&args.address)?);
            return Ok(());
        }
        GnssSource::NmeaUdp => {
            let sock = std::net::UdpSocket::bind(&args.address)?;
            while Instant::now() < deadline {
                sock.set_read_timeout(Some(left(deadline)))?;
                match sock.recv(&mut buf) {
                    Ok(n) => take(&buf[..n]),
                    Err(e) if timed_out(&e) => break,
                    Err(e) => return Err(e),
                }
            }
            return Ok(());
        }
        GnssSource::NmeaTcp => {
            let s = std::net::TcpStream::connect(&args.address)?;
            s.set_read_timeout(Some(Duration::from_millis(200)))?;
            Box::new(s)
        }
        GnssSource::NmeaSerial | GnssSource::UbxSerial => {
            Box::new(std::fs::File::open(&args.address)?)
        }
        GnssSource::Gpsd | GnssSource::None => {
            return Err(std::io::Error::other(
                "gnss-check reads a receiver, not gpsd",
            ))
        }
    };
    while Instant::now() < deadline {
        match stream.read(&mut buf) {
            Ok(0) => break,
            Ok(n) => take(&buf[..n]),
            Err(e) if timed_out(&e) => {}
            Err(e) => return Err(e),
        }
    }
    Ok(())
}

fn left(deadline: Instant) -> Duration {
    deadline
        .saturating_duration_since(Instant::now())
        .max(Duration::from_millis(1))
}

fn timed_out(e: &std::io::Error) -> bool {
    matches!(
        e.kind(),
        std::io::ErrorKind::WouldBlock | std::io::ErrorKind::TimedOut
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    fn with_sum(body: &str) -> String {
        let sum = body.bytes().fold(0u8, |a, b| a ^ b);
        format!("${body}*{sum:02X}\r\n")
    }

    fn tally_of(text: &str) -> Tally {
        let mut r = GnssReader::new();
        let mut t = Tally::default();
        r.push(text.as_bytes(), |e| t.take(e));
        r.finish(|e| t.take(e));
        t
    }

    #[test]
    fn a_10_hz_receiver_with_gst_is_good() {
        let mut text = String::new();
        for k in 0..20 {
            let t = format!("1200{:02}.{}0", k / 10, k % 10);
            text += &with_sum(&format!(
                "GPGGA,{t},4807.038,N,01131.000,E,4,12,0.6,545.4,M,46.9,M,,"
            ));
            text += &with_sum(&format!(
                "GPRMC,{t},A,4807.038,N,01131.000,E,010.0,090.0,020124,,,R"
            ));
            text += &with_sum(&format!("GPGST,{t},0.5,0.6,0.4,10.0,0.02,0.03,0.05"));
        }
        let t = tally_of(&text);
        assert_eq!(t.fix_count(), 20);
        assert!((t.rate_hz().unwrap() - 10.0).abs() < 1e-9);
        assert_eq!(t.shortcomings(), Vec::<String>::new());
        assert!(t.report("file", None).contains("verdict: GOOD"));
    }

    #[test]
    fn a_1_hz_simulator_gga_only_receiver_is_not() {
        let mut text = String::new();
        for k in 0..5 {
            text += &with_sum(&format!(
                "GPGGA,12000{k},4807.038,N,01131.000,E,1,08,,545.4,M,,M,,"
            ));
            text += &with_sum(&format!(
                "GPRMC,12000{k},V,4807.038,N,01131.000,E,,,020124,,,S"
            ));
        }
        let t = tally_of(&text);
        assert_eq!(t.fix_count(), 0);
        assert_eq!(t.no_fix.get("simulator"), Some(&5));
        assert_eq!(
            t.shortcomings(),
            ["no fix at all", "5 epochs the receiver marks simulator"]
        );
        let mut text = String::new();
        for k in 0..5 {
            text += &with_sum(&format!(
                "GPGGA,12000{k},4807.038,N,01131.000,E,1,08,,545.4,M,,M,,"
            ));
        }
        let short = tally_of(&text).shortcomings();
        assert_eq!(short.len(), 3, "{short:?}");
        assert!(short[0].starts_with("1.0 fixes a second"));
        assert!(short[1].contains("without an accuracy"));
        assert!(short[2].contains("without a UTC date"));
    }
}
