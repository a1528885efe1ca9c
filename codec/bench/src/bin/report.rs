//! Prints the table of the last benchmark results (criterion's estimates), ours against rasn,
//! each ratio against its goal; `--write-readme` also puts it into `codec/bench/README.md`:
//!
//!     cargo run --release --manifest-path codec/bench/Cargo.toml --bin report [-- --write-readme]
//!
//! Exits 1 when a ratio misses its goal.

use std::process::ExitCode;

use j2735_bench::{frames, report};

fn main() -> ExitCode {
    let sizes: Vec<(String, usize, String)> = frames::all()
        .into_iter()
        .map(|f| (f.row.to_string(), f.bytes.len(), f.source))
        .collect();
    let dir = report::criterion_dir();
    println!("criterion results in {}", dir.display());
    println!("machine now: {}", report::machine());
    for (row, n, source) in &sizes {
        println!("  {row}: {n} octets, {source}");
    }
    println!();
    let (table, missed) = report::table(&dir, &sizes);
    print!("{table}");
    println!("\n{missed} ratio(s) below their goal");
    if std::env::args().any(|a| a == "--write-readme") {
        let path = concat!(env!("CARGO_MANIFEST_DIR"), "/README.md");
        let written = std::fs::read_to_string(path)
            .map_err(|e| e.to_string())
            .and_then(|text| report::with_table(&text, &table))
            .and_then(|text| std::fs::write(path, text).map_err(|e| e.to_string()));
        if let Err(e) = written {
            eprintln!("{path}: {e}");
            return ExitCode::FAILURE;
        }
        println!("table written to {path}");
    }
    if missed == 0 {
        ExitCode::SUCCESS
    } else {
        ExitCode::FAILURE
    }
}
