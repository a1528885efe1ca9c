//! The table of results: criterion's estimates of ours against rasn, per frame and operation.
//!
//! Benchmark ids are `<row>/<case>` (criterion group = row, function = case); the estimates
//! are read from `<criterion dir>/<row>/<case>/new/estimates.json`. Every case carries
//! the storage of its build in its name (`ours_decode_into` / `rasn_decode` without `alloc`,
//! `ours_decode_into_alloc` / `rasn_decode_alloc` with it): each storage is compared with rasn
//! measured in the same run.

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
pub const PAIRS: [(&str, &str, &str); 6] = [
    (
        "decode into a kept value (`uper::decode_into`)",
        "ours_decode_into",
        "rasn_decode",
    ),
    (
        "decode into a kept message (`frame::decode_message_into`)",
        "ours_decode_message_into",
        "rasn_decode",
    ),
    (
        "decode into a new value (`uper::decode`)",
        "ours_decode_by_value",
        "rasn_decode",
    ),
    (
        "decode, alternating with another type (`Decoder`)",
        "ours_decoder_alternating",
        "rasn_decode_alternating",
    ),
    (
        "encode (`uper::encode`, reused buffer)",
        "ours_encode",
        "rasn_encode",
    ),
    (
        "encode, alternating with another type",
        "ours_encode_alternating",
        "rasn_encode_alternating",
    ),
];

/// The goal of a ratio rasn/ours: 6x for a frame under 100 octets without `alloc` (the
/// smallest messages have the least work to amortise, and must still lead by most), 5x
/// everywhere else.
pub fn goal(octets: usize, alloc: bool) -> f64 {
    if octets < 100 && !alloc {
        6.0
    } else {
        5.0
    }
}

/// The largest ratio of a new value's decode to a kept value's (`uper::decode` against
/// `uper::decode_into`).
pub const NEW_VALUE_GOAL: f64 = 1.3;

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

/// The table (Markdown) of every row and operation that has both estimates in `dir`, with
/// each ratio against its goal ([`goal`], [`NEW_VALUE_GOAL`]). `sizes` gives (row, octets,
/// source) for the frame column. Returns the table and how many ratios miss their goal.
pub fn table(dir: &Path, sizes: &[(String, usize, String)]) -> (String, usize) {
    let mut out = String::new();
    let mut missed = 0;
    let _ = writeln!(
        out,
        "| frame | octets | operation | storage | ours ns | rasn ns | rasn/ours | goal |"
    );
    let _ = writeln!(out, "| --- | ---: | --- | --- | ---: | ---: | ---: | --- |");
    for row in ROW_ORDER {
        let Some(octets) = sizes.iter().find(|s| s.0 == row).map(|s| s.1) else {
            continue;
        };
        for (label, ours_case, rasn_case) in PAIRS {
            for suffix in ["", "_alloc"] {
                let ours_id = format!("{ours_case}{suffix}");
                let rasn_id = format!("{rasn_case}{suffix}");
                let (Some(o), Some(r)) =
                    (estimate(dir, row, &ours_id), estimate(dir, row, &rasn_id))
                else {
                    continue;
                };
                let alloc = !suffix.is_empty();
                let lead = r.median / o.median;
                let want = goal(octets, alloc);
                let mut verdict = if lead >= want {
                    format!("{want:.0}x met")
                } else {
                    missed += 1;
                    format!("{want:.0}x **not met**")
                };
                if ours_case == "ours_decode_by_value" {
                    if let Some(k) = estimate(dir, row, &format!("ours_decode_into{suffix}")) {
                        let slower = o.median / k.median;
                        let ok = slower <= NEW_VALUE_GOAL;
                        missed += usize::from(!ok);
                        let _ = write!(
                            verdict,
                            "; {slower:.2}x kept, {}",
                            if ok { "met" } else { "**not met**" }
                        );
                    }
                }
                let _ = writeln!(
                    out,
                    "| {row} | {octets} | {label} | {} | {} | {} | {lead:.1}x | {verdict} |",
                    if alloc { "alloc" } else { "no-heap" },
                    ns(o.median),
                    ns(r.median),
                );
            }
        }
    }
    (out, missed)
}

/// Markers of the generated table in `codec/bench/README.md`.
pub const README_MARKERS: (&str, &str) = (
    "<!-- table: generated by `--bin report -- --write-readme`; do not edit -->",
    "<!-- end of table -->",
);

/// Replaces the text between [`README_MARKERS`] in `readme` by `table`.
pub fn with_table(readme: &str, table: &str) -> Result<String, String> {
    let (open, close) = README_MARKERS;
    let start = readme.find(open).ok_or("the README has no table marker")? + open.len();
    let end = readme[start..]
        .find(close)
        .ok_or("the README has no end-of-table marker")?
        + start;
    Ok(format!("{}\n{}{}", &readme[..start], table, &readme[end..]))
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
