//! Prints the table of the last benchmark results (criterion's estimates), ours against rasn:
//!
//!     cargo run --release --manifest-path codec/bench/Cargo.toml --bin report

use j2735_bench::{frames, report};

fn main() {
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
    print!("{}", report::table(&dir, &sizes));
}
