//! `roadside pki DIR`: a small IEEE 1609.2 PKI (root, issuing CA and RSU certificate) as
//! files, for a test site or the bench.

use crate::{CommandError, ValueError};
use j2735::envelope::Psid;
use roadside::pki::{Pki, PkiSpec};
use std::path::PathBuf;

/// `roadside pki`.
#[derive(Debug, clap::Args)]
pub struct PkiArgs {
    /// Where the certificates and keys go (created if missing).
    #[arg(value_name = "DIR")]
    pub dir: PathBuf,
    /// Derive the keys from this seed (reproducible test PKIs); default: random keys.
    #[arg(long, value_name = "TEXT")]
    pub seed: Option<String>,
    /// First day of validity of every certificate, UTC (default: today).
    #[arg(long, value_name = "YYYY-MM-DD", value_parser = date)]
    pub start: Option<u64>,
    /// RSU certificate validity, days (at most 2730; within the CA's).
    #[arg(long, value_name = "N", default_value_t = 30)]
    pub days: u16,
    /// Issuing CA certificate validity, years (within the root's).
    #[arg(long, value_name = "N", default_value_t = 5)]
    pub ca_years: u16,
    /// Root certificate validity, years.
    #[arg(long, value_name = "N", default_value_t = 10)]
    pub root_years: u16,
    /// The RSU certificate's region: a circle (degrees, degrees, metres); default: none.
    #[arg(long, value_name = "LAT,LON,RADIUS_M", value_parser = circle)]
    pub region: Option<(i32, i32, u16)>,
    /// A PSID the RSU may sign: `0x` hexadecimal is its p-encoded octets, decimal the
    /// IEEE 1609.2 integer (repeat; default: TIM 0x8003 = 131, MAP 0xE0000017 = 2113687 and
    /// PSM 0x27 = 39).
    #[arg(long, value_name = "PSID", value_parser = psid)]
    pub psid: Vec<Psid>,
    /// The RSU certificate's name.
    #[arg(long, value_name = "HOST", default_value = "rsu.hil-sim.example")]
    pub name: String,
}

/// `YYYY-MM-DD` as Unix seconds at 00:00 UTC.
fn date(s: &str) -> Result<u64, &'static str> {
    let parts: Vec<&str> = s.split('-').collect();
    let [y, m, d] = parts[..] else {
        return Err("expected YYYY-MM-DD");
    };
    let (Ok(y), Ok(m), Ok(d)) = (y.parse::<i64>(), m.parse::<u8>(), d.parse::<u8>()) else {
        return Err("expected YYYY-MM-DD");
    };
    if !(2004..=2100).contains(&y) || !(1..=12).contains(&m) || !(1..=31).contains(&d) {
        return Err("a date between 2004 and 2100");
    }
    Ok(roadside::clock::days_from_civil(y, m, d) as u64 * 86_400)
}

/// `LAT,LON,RADIUS_M` as 1e-7 degrees and metres.
fn circle(s: &str) -> Result<(i32, i32, u16), &'static str> {
    let bad = || "expected LAT,LON,RADIUS_M (degrees, degrees, metres up to 65535)";
    let parts: Vec<&str> = s.split(',').collect();
    let [lat, lon, r] = parts[..] else {
        return Err(bad());
    };
    let (Ok(lat), Ok(lon), Ok(r)) = (lat.parse::<f64>(), lon.parse::<f64>(), r.parse::<u16>())
    else {
        return Err(bad());
    };
    if !(-90.0..=90.0).contains(&lat) || !(-180.0..=180.0).contains(&lon) || r == 0 {
        return Err(bad());
    }
    Ok(((lat * 1e7).round() as i32, (lon * 1e7).round() as i32, r))
}

/// A PSID: `0x` hexadecimal p-encoded octets, or the decimal integer ([`Psid::parse`]).
fn psid(s: &str) -> Result<Psid, ValueError> {
    Psid::parse(s).ok_or_else(|| {
        format!(
            "{s:?} is not a PSID: give its p-encoded octets in hexadecimal (0x8003 for TIM) \
             or the integer in decimal (131)"
        )
        .into()
    })
}

/// Makes the PKI and writes it to its folder.
pub fn pki(a: &PkiArgs) -> Result<bool, CommandError> {
    let start_unix_s = a
        .start
        .unwrap_or(roadside::clock::unix_ms_now() / 86_400_000 * 86_400);
    let psids = if a.psid.is_empty() {
        vec![Psid::TIM, Psid::MAP, Psid::PSM]
    } else {
        a.psid.clone()
    };
    let spec = PkiSpec {
        seed: a.seed.clone(),
        start_unix_s,
        root_years: a.root_years,
        ca_years: a.ca_years,
        rsu_hours: a.days.checked_mul(24).ok_or("--days: at most 2730")?,
        region: a.region,
        psids,
        rsu_name: a.name.clone(),
    };
    Pki::create(&spec)?.write(&a.dir)?;
    println!(
        "roadside pki: {0}/root.oer, {0}/ca.oer (trust anchors), {0}/rsu.oer and the keys",
        a.dir.display()
    );
    Ok(true)
}
