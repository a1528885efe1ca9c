//! The OBU's GNSS reader (`obu::input::gnss`): any bytes, mixed NMEA and UBX or not.
//!
//! Invariants:
//! 1. Nothing panics and every output is in range: an epoch's time is a time of day, a
//!    fix's position is on the earth, its accuracy, speed and course are finite.
//! 2. The stream may arrive in any pieces: the input read whole and read in two pieces
//!    cut where its first byte says give the same events (a serial port hands over
//!    whatever has arrived).
//! 3. Every byte is accounted for at most once: the bytes skipped never exceed the input.

use obu::input::gnss::{GnssEvent, GnssReader};

fn events(pieces: &[&[u8]]) -> Vec<GnssEvent> {
    let mut r = GnssReader::new();
    let mut out = Vec::new();
    for p in pieces {
        r.push(p, |e| out.push(e));
    }
    r.finish(|e| out.push(e));
    out
}

/// Runs the invariants on one input.
pub fn check(data: &[u8]) {
    let whole = events(&[data]);
    let cut = usize::from(data.first().copied().unwrap_or(0)).min(data.len());
    let (a, b) = data.split_at(cut);
    assert_eq!(whole, events(&[a, b]), "pieces cut at {cut}");
    let mut skipped = 0usize;
    for e in &whole {
        match e {
            GnssEvent::Epoch(epoch) => {
                assert!(epoch.time < 86_401_000, "time of day {}", epoch.time);
                if let Ok(fix) = epoch.outcome {
                    let (lat, lon) = (fix.position.lat_deg(), fix.position.lon_deg());
                    assert!(lat.abs() <= 90.0 && lon.abs() <= 180.0, "{lat} {lon}");
                    for v in [fix.accuracy_m, fix.speed_mps, fix.course_deg]
                        .into_iter()
                        .flatten()
                    {
                        assert!(v.is_finite(), "{fix:?}");
                    }
                }
            }
            GnssEvent::Skipped(n) => skipped += n,
            _ => {}
        }
    }
    assert!(skipped <= data.len(), "{skipped} skipped of {}", data.len());
}
