//! Every real receiver's log in `../shared/gnss/logs` read through the OBU's GNSS reader
//! and compared, epoch by epoch, with gpsd's own decoding of it (`*.log.chk`, an
//! independent implementation): each epoch where gpsd reports a 2D/3D fix gives our fix at
//! the same time within 1 cm of gpsd's latitude and longitude; no epoch gives our fix where
//! gpsd has none; no log is refused. Needs `--features shared-corpus`; fails when
//! `../shared` is missing. Run with `--nocapture` for the table.
//!
//! The exceptions, where gpsd itself is wrong, are listed in [`GPSD_WRONG`] with the reason;
//! each must still occur (the list cannot go stale).
#![cfg(feature = "shared-corpus")]

mod common;

use std::collections::BTreeMap;

use obu::input::gnss::{GnssEvent, GnssReader};
use obu::input::nmea::EpochOutcome;

/// Epochs (log, UTC time of day in ms) where gpsd's report is wrong, and why we keep to
/// what the receiver says.
const GPSD_WRONG: [(&str, u32, &str); 8] = [
    ("GPSmap-76S.log", 46_266_000, SIMULATOR),
    ("ac12_binary.log", 66_931_000, RMC_DIGITS),
    ("ac12_binary.log", 66_932_000, RMC_DIGITS),
    ("ac12_binary.log", 66_933_000, RMC_DIGITS),
    ("ac12_binary.log", 66_934_000, RMC_DIGITS),
    ("mtk-3301.log", 29_674_590, DISOWNED),
    ("myguide-3100.log", 39_027_800, DISOWNED),
    ("myguide-3100.log", 39_028_800, DISOWNED),
];
/// The tr737A+ epoch is the same case as [`DISOWNED`].
const GPSD_WRONG_TR737: (&str, u32, &str) = ("tr737A+.log", 26_254_929, DISOWNED);

const SIMULATOR: &str = "GGA quality 8 and RMC mode S: the unit's simulator (gpsd itself marks it \
    status 8, simulated, yet reports mode 3); never the vehicle's position";
const RMC_DIGITS: &str = "gpsd reports the cycle's last sentence, an RMC with 4 decimals of a \
    minute (up to 9 cm off); the same epoch's GGA gives 5 and we keep it";
const DISOWNED: &str = "the receiver says it has no fix (GGA quality 0 or empty, RMC status V \
    mode N, GSA mode 1); gpsd reports the stale position the GGA still carries";

/// Epochs where the receiver has a fix and gpsd's regression output has no report at all
/// (neither fix nor no fix), and why.
const GPSD_SILENT: [(&str, u32, &str); 4] = [
    (
        "bt451.log",
        55_508_500,
        "the last epoch of a recording segment: the log goes back to \
     another drive and gpsd's cycle ends unreported",
    ),
    (
        "gp-320fw-2019-04-06-overflow.log",
        86_246_020,
        "the receiver's buffer overflowed: gpsd \
     resynchronised on the next cycle",
    ),
    (
        "rst39.log",
        74_492_100,
        "10 Hz GGA between PASHR attitude messages: gpsd reports every \
     other epoch",
    ),
    (
        "tn204.log",
        82_909_000,
        "gpsd's cycle detection dropped the epoch",
    ),
];

/// gpsd's view of one epoch: the positions it reported with a fix (one per sentence of
/// the cycle; empty when it reported none).
type GpsdEpochs = BTreeMap<u32, Vec<(f64, f64)>>;

/// The TPV reports of a `.chk` file per UTC time of day. A report without a time (gpsd
/// withholds it until it has a date) belongs to the time of the last sentence echoed
/// before it.
fn gpsd_epochs(chk: &str) -> GpsdEpochs {
    let mut out = GpsdEpochs::new();
    let mut last_sentence_time: Option<u32> = None;
    for line in chk.lines() {
        if line.starts_with('$') {
            last_sentence_time = sentence_time(line).or(last_sentence_time);
            continue;
        }
        if !line.starts_with('{') {
            continue;
        }
        let Ok(v) = serde_json::from_str::<serde_json::Value>(line) else {
            continue;
        };
        if v["class"] != "TPV" {
            continue;
        }
        let time = v["time"].as_str().and_then(time_of_day);
        let Some(t) = time.or(last_sentence_time) else {
            continue;
        };
        // One cycle's sentences stamped a few ms apart (GLL to the ms, GGA to the cs) are
        // one epoch: the later stamp names it.
        let t = match out.range(t.saturating_sub(9)..t).next_back() {
            Some((&k, _)) => {
                let fixes = out.remove(&k).unwrap_or_default();
                out.entry(t).or_default().extend(fixes);
                t
            }
            None => t,
        };
        let fixes = out.entry(t).or_default();
        if let (Some(m), Some(lat), Some(lon)) =
            (v["mode"].as_u64(), v["lat"].as_f64(), v["lon"].as_f64())
        {
            if m >= 2 {
                fixes.push((lat, lon));
            }
        }
    }
    out
}

/// The time field of an echoed GGA, RMC, GNS, GST, ZDA or GLL sentence, ms of the day.
fn sentence_time(line: &str) -> Option<u32> {
    let fields: Vec<&str> = line.split(['*', ',']).collect();
    let address = fields.first()?.get(1..)?;
    let at = match address.get(2..)? {
        "GGA" | "RMC" | "GNS" | "GST" | "ZDA" => 1,
        "GLL" => 5,
        _ => return None,
    };
    let f = fields.get(at)?;
    let n = |r: std::ops::Range<usize>| f.get(r)?.parse::<u32>().ok();
    let (h, m, s) = (n(0..2)?, n(2..4)?, n(4..6)?);
    let frac = f.get(6..).unwrap_or("");
    Some(((h * 60 + m) * 60 + s) * 1000 + fraction_ms(frac)?)
}

/// `.25` as 250 ms; empty as 0.
fn fraction_ms(frac: &str) -> Option<u32> {
    match frac.strip_prefix('.') {
        Some(d) if !d.is_empty() => {
            let d3: String = d.chars().chain("000".chars()).take(3).collect();
            d3.parse::<u32>().ok()
        }
        _ => Some(0),
    }
}

/// `2017-01-10T00:09:41.250Z` as milliseconds of the day.
fn time_of_day(iso: &str) -> Option<u32> {
    let hms = iso.get(11..)?;
    let n = |r: std::ops::Range<usize>| hms.get(r)?.parse::<u32>().ok();
    let (h, m, s) = (n(0..2)?, n(3..5)?, n(6..8)?);
    let frac = hms.get(8..).unwrap_or("").trim_end_matches('Z');
    Some(((h * 60 + m) * 60 + s) * 1000 + fraction_ms(frac)?)
}

/// What our reader made of one log.
#[derive(Default)]
struct Ours {
    epochs: BTreeMap<u32, EpochOutcome>,
    /// The time of the last epoch the reader emitted.
    last: Option<u32>,
    sentences: u64,
    /// UBX frames read (good checksum), and refused.
    ubx: u64,
    skipped: u64,
    errors: BTreeMap<String, u64>,
}

/// The receiver's bytes of a log: every line that starts with `#` (the header and the
/// notes between recording segments) left out, as gpsd's own replay does.
fn receiver_bytes(log: &[u8]) -> Vec<u8> {
    let mut out = Vec::with_capacity(log.len());
    for line in log.split_inclusive(|&b| b == b'\n') {
        if !line.starts_with(b"#") {
            out.extend_from_slice(line);
        }
    }
    out
}

fn read_log(bytes: &[u8]) -> Ours {
    let mut ours = Ours::default();
    let mut reader = GnssReader::new();
    let mut take = |e: GnssEvent| match e {
        GnssEvent::Epoch(e) => {
            ours.epochs.insert(e.time, e.outcome);
            ours.last = Some(e.time);
        }
        GnssEvent::Sentence(_) | GnssEvent::OtherSentence => ours.sentences += 1,
        GnssEvent::Skipped(n) => ours.skipped += n as u64,
        GnssEvent::NmeaError(e) => *ours.errors.entry(e.as_str().into()).or_default() += 1,
        GnssEvent::UbxError(e) => {
            ours.ubx += 1;
            *ours.errors.entry(e.as_str().into()).or_default() += 1
        }
        GnssEvent::Ubx(_) => ours.ubx += 1,
        GnssEvent::CoveredByUbx => {}
    };
    // In pieces of 7 bytes: a serial port hands over whatever has arrived.
    for piece in bytes.chunks(7) {
        reader.push(piece, &mut take);
    }
    reader.finish(&mut take);
    ours
}

/// Metres between two positions (small distances, equirectangular).
fn metres(a: (f64, f64), b: (f64, f64)) -> f64 {
    let k = 6_371_000.0_f64.to_radians();
    let dy = (a.0 - b.0) * k;
    let dx = (a.1 - b.1) * k * a.0.to_radians().cos();
    (dx * dx + dy * dy).sqrt()
}

#[derive(Default)]
struct Totals {
    gpsd_fixes: u64,
    matched: u64,
    extra: u64,
    skipped: u64,
    refused: u64,
    ubx: u64,
}

#[test]
fn every_shared_receiver_log_gives_gpsds_fixes() {
    let dir = common::shared_dir().join("gnss/logs");
    let mut names: Vec<_> = std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .filter_map(|e| e.ok()?.file_name().into_string().ok())
        .filter(|n| n.ends_with(".log"))
        .collect();
    names.sort();
    assert_eq!(names.len(), 43, "the shared set holds 43 receivers' logs");
    let mut totals = Totals::default();
    let mut failures = Vec::new();
    let mut excused: Vec<(String, u32)> = Vec::new();
    println!(
        "{:<36} {:>6} {:>6} {:>6} {:>7}  errors",
        "log", "gpsd", "ours", "extra", "skipped"
    );
    for name in &names {
        let log = std::fs::read(dir.join(name)).unwrap();
        let chk = String::from_utf8_lossy(&std::fs::read(dir.join(format!("{name}.chk"))).unwrap())
            .into_owned();
        let gpsd = gpsd_epochs(&chk);
        let ours = read_log(&receiver_bytes(&log));
        let (mut fixes, mut matched, mut extra) = (0, 0, 0);
        for (&t, g) in &gpsd {
            let wrong = GPSD_WRONG
                .iter()
                .chain([&GPSD_WRONG_TR737])
                .any(|&(n, at, _)| n == name && at == t);
            let mine = ours.epochs.get(&t).and_then(|o| o.as_ref().ok());
            match (g.is_empty(), mine) {
                (false, _) | (true, Some(_)) if wrong => excused.push((name.clone(), t)),
                (false, Some(f)) => {
                    fixes += 1;
                    let at = (f.position.lat_deg(), f.position.lon_deg());
                    let d = g
                        .iter()
                        .map(|&p| metres(p, at))
                        .fold(f64::INFINITY, f64::min);
                    if d <= 0.01 {
                        matched += 1;
                    } else {
                        failures.push(format!("{name} t={t}: {d:.3} m from gpsd's fix"));
                    }
                }
                (false, None) => {
                    fixes += 1;
                    let why = ours
                        .epochs
                        .get(&t)
                        .map_or("no epoch".into(), |o| format!("{:?}", o.as_ref().err()));
                    failures.push(format!("{name} t={t}: gpsd has a fix, we: {why}"));
                }
                (true, Some(_)) => {
                    extra += 1;
                    failures.push(format!("{name} t={t}: our fix where gpsd has none"));
                }
                (true, None) => {}
            }
        }
        for (&t, o) in &ours.epochs {
            // gpsd's regression output ends with the last sentence, before gpsd reported
            // the log's last epoch.
            let last = Some(t) == ours.last;
            let silent = GPSD_SILENT.iter().any(|&(n, at, _)| n == name && at == t);
            if silent && o.is_ok() && !gpsd.contains_key(&t) {
                excused.push((name.clone(), t));
            } else if o.is_ok() && !gpsd.contains_key(&t) && !last {
                extra += 1;
                failures.push(format!(
                    "{name} t={t}: our fix at a time gpsd reports nothing"
                ));
            }
        }
        if ours.sentences == 0 {
            totals.refused += 1;
            failures.push(format!("{name}: no sentence read"));
        }
        println!(
            "{name:<36} {fixes:>6} {matched:>6} {extra:>6} {:>7}  {:?}",
            ours.skipped, ours.errors
        );
        totals.gpsd_fixes += fixes;
        totals.matched += matched;
        totals.extra += extra;
        totals.skipped += ours.skipped;
        totals.ubx += ours.ubx;
    }
    println!(
        "total: gpsd fix epochs {}, ours at gpsd's position {} ({:.1} %), ours where gpsd has none {}, bytes skipped {}, logs refused {}",
        totals.gpsd_fixes,
        totals.matched,
        100.0 * totals.matched as f64 / totals.gpsd_fixes.max(1) as f64,
        totals.extra,
        totals.skipped,
        totals.refused
    );
    assert!(
        failures.is_empty(),
        "{} differences:\n{}",
        failures.len(),
        failures.join("\n")
    );
    // The shared logs hold no UBX frame at all (no `B5 62` sync pair in any of them: the
    // binary in ublox-8.log is line noise); UBX is checked by the wire fixtures in
    // `obu/src/input/tests.rs`, the bench's and the firmware tests' own NAV-PVT writers.
    assert_eq!(
        totals.ubx, 0,
        "UBX frames appeared in the shared logs: compare them too"
    );
    let listed = GPSD_WRONG
        .iter()
        .chain([&GPSD_WRONG_TR737])
        .chain(GPSD_SILENT.iter());
    let stale: Vec<_> = listed
        .filter(|&&(n, t, _)| !excused.iter().any(|(en, et)| en == n && *et == t))
        .collect();
    assert!(
        stale.is_empty(),
        "listed exceptions that no longer occur: {stale:?}"
    );
}

#[test]
fn the_header_is_cut_at_the_first_receiver_byte() {
    assert_eq!(
        receiver_bytes(b"# a\n# b\n$GPGGA\n# c\n$GPRMC"),
        b"$GPGGA\n$GPRMC"
    );
    assert_eq!(time_of_day("2017-01-10T00:09:41.25Z"), Some(581_250));
    assert_eq!(time_of_day("2017-01-10T00:09:41Z"), Some(581_000));
}
