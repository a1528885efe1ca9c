//! The table of results: criterion's estimates of ours against rasn, per frame and operation.
//!
//! Benchmark ids are `<row>/<case>` (criterion group = row, function = case); the estimates
//! are read from `<criterion dir>/<row>/<case>/new/estimates.json`. Cases of our codec carry
//! the storage in their name (`ours_decode_into` without `alloc`, `ours_decode_into_alloc`
//! with it), so that runs with and without the feature keep their own results.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use crate::frames::ROW_ORDER;

/// Suffix of our cases in this build (`""` or `"_alloc"`).
pub const OURS_SUFFIX: &str = if cfg!(feature = "alloc") {
    "_alloc"
} else {
    ""
};

/// The operations compared: (label, our case without suffix, rasn case).
pub const PAIRS: [(&str, &str, &str); 4] = [
    (
        "decode (decode_into, kept MessageFrame)",
        "ours_decode_into",
        "rasn_decode",
    ),
    (
        "decode (frame::decode_message_into, kept MapData/TIM)",
        "ours_decode_message_into",
        "rasn_decode",
    ),
    (
        "decode (uper::decode, new value)",
        "ours_decode_by_value",
        "rasn_decode",
    ),
    (
        "encode (uper::encode, reused buffer)",
        "ours_encode",
        "rasn_encode",
    ),
];

/// Where criterion keeps its results: `$CRITERION_HOME`, else `$CARGO_TARGET_DIR/criterion`,
/// else this crate's `target/criterion` (criterion's own order, but for `cargo metadata`).
pub fn criterion_dir() -> PathBuf {
    if let Some(d) = std::env::var_os("CRITERION_HOME") {
        return PathBuf::from(d);
    }
    if let Some(d) = std::env::var_os("CARGO_TARGET_DIR") {
        return PathBuf::from(d).join("criterion");
    }
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("target/criterion")
}

/// One estimate: median and mean time per iteration (ns), and the median's 95% interval.
#[derive(Clone, Copy, Debug)]
pub struct Estimate {
    /// Median time per iteration, ns.
    pub median: f64,
    /// Lower and upper bound of the median's confidence interval, ns.
    pub median_ci: (f64, f64),
    /// Mean time per iteration, ns.
    pub mean: f64,
}

/// The estimate of benchmark `row/case`, if criterion has one.
pub fn estimate(dir: &Path, row: &str, case: &str) -> Option<Estimate> {
    let path = dir.join(row).join(case).join("new/estimates.json");
    let text = std::fs::read_to_string(path).ok()?;
    let v: serde_json::Value = serde_json::from_str(&text).ok()?;
    let point = |k: &str| v[k]["point_estimate"].as_f64();
    let ci = |k: &str, b: &str| v[k]["confidence_interval"][b].as_f64();
    Some(Estimate {
        median: point("median")?,
        median_ci: (ci("median", "lower_bound")?, ci("median", "upper_bound")?),
        mean: point("mean")?,
    })
}

fn ns(v: f64) -> String {
    if v >= 100.0 {
        format!("{v:.0}")
    } else {
        format!("{v:.1}")
    }
}

/// The table (Markdown) of every row and operation that has both estimates in `dir`.
/// `sizes` gives (row, octets, source) for the frame column.
pub fn table(dir: &Path, sizes: &[(String, usize, String)]) -> String {
    let mut out = String::new();
    let _ = writeln!(
        out,
        "| frame | octets | operation | ours ns/msg | rasn ns/msg | ours/rasn | rasn/ours | 5x goal |"
    );
    let _ = writeln!(
        out,
        "| --- | ---: | --- | ---: | ---: | ---: | ---: | --- |"
    );
    for row in ROW_ORDER {
        let octets = sizes
            .iter()
            .find(|s| s.0 == row)
            .map_or(String::from("?"), |s| s.1.to_string());
        for (label, ours_case, rasn_case) in PAIRS {
            for suffix in ["", "_alloc"] {
                let ours_id = format!("{ours_case}{suffix}");
                let (Some(o), Some(r)) =
                    (estimate(dir, row, &ours_id), estimate(dir, row, rasn_case))
                else {
                    continue;
                };
                let storage = if suffix.is_empty() {
                    "no-alloc"
                } else {
                    "alloc"
                };
                let ratio = o.median / r.median;
                let _ = writeln!(
                    out,
                    "| {row} | {octets} | {label}, {storage} | {} | {} | {ratio:.3} | {:.1}x | {} |",
                    ns(o.median),
                    ns(r.median),
                    r.median / o.median,
                    if ratio <= 0.2 { "met" } else { "**not met**" },
                );
            }
        }
    }
    out
}

/// Machine conditions worth printing beside timings: CPU model, cores, load averages.
pub fn machine() -> String {
    let cpu = std::fs::read_to_string("/proc/cpuinfo")
        .ok()
        .and_then(|t| {
            t.lines()
                .find(|l| l.starts_with("model name"))
                .and_then(|l| l.split(':').nth(1))
                .map(|s| s.trim().to_string())
        })
        .unwrap_or_else(|| "unknown CPU".into());
    let cores = std::thread::available_parallelism().map_or(0, |n| n.get());
    format!("{cpu}, {cores} cores, load average {}", load_average())
}

/// `/proc/loadavg`'s 1, 5 and 15 minute averages.
pub fn load_average() -> String {
    std::fs::read_to_string("/proc/loadavg")
        .map(|t| t.split_whitespace().take(3).collect::<Vec<_>>().join(" "))
        .unwrap_or_else(|_| "unknown".into())
}
