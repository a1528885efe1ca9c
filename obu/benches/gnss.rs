//! The GNSS reader's throughput on one core: NMEA sentences a second (a 10 Hz receiver's
//! GST + GGA + RMC + GSA + VTG) and UBX NAV-PVT frames a second, through the whole path
//! (framer, parser, epoch assembly, fix). Run with `cargo bench -p obu --bench gnss`; it
//! prints the rates (no peer: gpsd is a daemon, not a library to call in-process).

use criterion::{black_box, criterion_group, criterion_main, Criterion, Throughput};
use obu::input::gnss::{GnssEvent, GnssReader};

/// `$body*hh\r\n`.
fn sentence(body: &str) -> String {
    let sum = body.bytes().fold(0u8, |a, b| a ^ b);
    format!("${body}*{sum:02X}\r\n")
}

/// `epochs` epochs of a 10 Hz NMEA receiver, five sentences each.
fn nmea_stream(epochs: u32) -> Vec<u8> {
    let mut out = String::new();
    for k in 0..epochs {
        let t = format!("{:02}{:02}{:02}.{}0", 12, k / 600 % 60, k / 10 % 60, k % 10);
        let min = 11.0 + 0.000_1 * f64::from(k % 1000);
        out += &sentence(&format!("GNGST,{t},0.5,0.02,0.02,10.0,0.014,0.014,0.03"));
        out += &sentence(&format!(
            "GNGGA,{t},4807.0380000,N,01{min:010.7},E,4,24,0.6,545.4,M,46.9,M,1.0,0000"
        ));
        out += &sentence(&format!(
            "GNRMC,{t},A,4807.0380000,N,01{min:010.7},E,21.6,090.0,041226,,,R,S"
        ));
        out += &sentence("GNGSA,A,3,23,09,16,07,26,03,27,22,,,,,1.71,0.60,1.38,1");
        out += &sentence("GNVTG,090.0,T,,M,21.6,N,40.0,K,R");
    }
    out.into_bytes()
}

/// `epochs` NAV-PVT frames (payload laid out by hand, checksum computed here).
fn ubx_stream(epochs: u32) -> Vec<u8> {
    let mut out = Vec::new();
    for k in 0..epochs {
        let mut p = vec![0u8; 92];
        p[4..6].copy_from_slice(&2026u16.to_le_bytes());
        let s = 12 * 3600 + k / 10;
        p[6..12].copy_from_slice(&[
            12,
            4,
            (s / 3600) as u8,
            (s / 60 % 60) as u8,
            (s % 60) as u8,
            7,
        ]);
        p[16..20].copy_from_slice(&(((k % 10) * 100_000_000) as i32).to_le_bytes());
        p[20..24].copy_from_slice(&[3, 0x83, 0xE0, 24]);
        p[24..28].copy_from_slice(&(115_166_667i32 + k as i32).to_le_bytes());
        p[28..32].copy_from_slice(&481_173_000i32.to_le_bytes());
        p[40..44].copy_from_slice(&14u32.to_le_bytes());
        p[60..64].copy_from_slice(&11_000i32.to_le_bytes());
        p[64..68].copy_from_slice(&9_000_000i32.to_le_bytes());
        let mut f = vec![0xB5, 0x62, 0x01, 0x07, 92, 0];
        f.extend_from_slice(&p);
        let (mut a, mut b) = (0u8, 0u8);
        for &x in &f[2..] {
            a = a.wrapping_add(x);
            b = b.wrapping_add(a);
        }
        f.extend_from_slice(&[a, b]);
        out.extend_from_slice(&f);
    }
    out
}

/// Reads `bytes` whole; the number of fixes.
fn read(bytes: &[u8]) -> usize {
    let mut r = GnssReader::new();
    let mut fixes = 0;
    r.push(bytes, |e| {
        if let GnssEvent::Epoch(e) = e {
            fixes += usize::from(e.outcome.is_ok());
        }
    });
    fixes
}

fn bench(c: &mut Criterion) {
    const EPOCHS: u32 = 1000;
    let nmea = nmea_stream(EPOCHS);
    let ubx = ubx_stream(EPOCHS);
    assert!(read(&nmea) >= EPOCHS as usize - 1, "a fix per NMEA epoch");
    assert_eq!(read(&ubx), EPOCHS as usize, "a fix per NAV-PVT");
    let mut g = c.benchmark_group("gnss");
    g.throughput(Throughput::Elements(u64::from(EPOCHS) * 5));
    g.bench_function("nmea sentences", |b| b.iter(|| read(black_box(&nmea))));
    g.throughput(Throughput::Elements(u64::from(EPOCHS)));
    g.bench_function("ubx nav-pvt", |b| b.iter(|| read(black_box(&ubx))));
    g.finish();
    // The rates, for the README (criterion's own report shows them as "thrpt").
    let time = |bytes: &[u8]| {
        let t = std::time::Instant::now();
        let n = 20;
        for _ in 0..n {
            black_box(read(black_box(bytes)));
        }
        t.elapsed().as_secs_f64() / f64::from(n)
    };
    let (tn, tu) = (time(&nmea), time(&ubx));
    println!(
        "gnss reader: {:.2} M NMEA sentences/s ({:.0} MB/s), {:.2} M UBX NAV-PVT/s on one core",
        f64::from(EPOCHS * 5) / tn / 1e6,
        nmea.len() as f64 / tn / 1e6,
        f64::from(EPOCHS) / tu / 1e6
    );
}

criterion_group!(benches, bench);
criterion_main!(benches);
