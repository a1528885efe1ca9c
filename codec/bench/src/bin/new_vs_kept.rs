//! Times decoding into a new `alloc` value against decoding into a kept one, interleaved in one
//! process, and prints their ratio per frame (the goal: at most 1.3x):
//!
//!     cargo run --release --manifest-path codec/bench/Cargo.toml --features alloc \
//!         --bin new_vs_kept [ROUNDS [ROW]]
//!
//! Each round times a batch of kept decodes and then a batch of new ones (the batch sized to
//! about 200 kB of input). The least time per message over the rounds is printed for each,
//! with the median beside it. Both cases meet the same machine state, round after round, so
//! the ratio holds where a virtual machine's speed drifts by tens of percent between runs (on
//! this project's build machine criterion's absolute times did, on unchanged code). Criterion
//! (`benches/codec.rs`) remains the benchmark of record for every other ratio.
//!
//! Exits 1 when a frame's least-time ratio is over the goal.

use std::hint::black_box;
use std::process::ExitCode;
use std::time::Instant;

use j2735_bench::{frames, ours, report};

/// The goal: a new value's decode takes at most this many times a kept value's.
const GOAL: f64 = 1.3;

/// Input octets per batch: a batch of small frames is long enough for the clock.
const BATCH_OCTETS: usize = 200_000;

/// Nanoseconds per message of `batch` calls of `f`.
fn per_message(batch: u32, mut f: impl FnMut()) -> f64 {
    let start = Instant::now();
    for _ in 0..batch {
        f();
    }
    start.elapsed().as_nanos() as f64 / f64::from(batch)
}

/// The least and the median of `times`.
fn least_and_median(mut times: Vec<f64>) -> (f64, f64) {
    times.sort_by(f64::total_cmp);
    (times[0], times[times.len() / 2])
}

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().collect();
    let rounds: usize = match args.get(1).map(|s| s.parse()) {
        None => 100,
        Some(Ok(n)) if n > 0 => n,
        Some(_) => {
            eprintln!("usage: {} [ROUNDS (> 0) [ROW]]", args[0]);
            return ExitCode::from(2);
        }
    };
    let only = args.get(2);
    println!("machine: {}", report::machine());
    println!("frame        kept ns    new ns  new/kept (least; median in brackets), goal {GOAL}x");
    let mut missed = 0;
    for frame in frames::all() {
        if only.is_some_and(|row| *row != frame.row) {
            continue;
        }
        let bytes = frame.bytes.as_slice();
        let mut kept = ours::Kept::new(bytes).expect("the corpus frame decodes");
        let batch = (BATCH_OCTETS / bytes.len().max(1)).clamp(20, 2_000) as u32;
        let (mut kept_ns, mut new_ns) = (Vec::new(), Vec::new());
        for _ in 0..rounds {
            kept_ns.push(per_message(batch, || {
                kept.decode(black_box(bytes)).expect("decode");
                black_box(kept.frame());
            }));
            new_ns.push(per_message(batch, || {
                let value = ours::decode_by_value(black_box(bytes)).expect("decode");
                black_box(&value);
            }));
        }
        let (k, k_median) = least_and_median(kept_ns);
        let (n, n_median) = least_and_median(new_ns);
        let met = n / k <= GOAL;
        missed += usize::from(!met);
        println!(
            "{:10} {:9.1} {:9.1}  {:.2}x ({:.2}x) {}",
            frame.row,
            k,
            n,
            n / k,
            n_median / k_median,
            if met { "met" } else { "not met" }
        );
    }
    println!("{missed} ratio(s) over {GOAL}x");
    if missed == 0 {
        ExitCode::SUCCESS
    } else {
        ExitCode::FAILURE
    }
}
