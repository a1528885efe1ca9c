//! Criterion benchmarks: our UPER codec against rasn on the same MessageFrame bytes.
//!
//!     cargo bench --manifest-path codec/bench/Cargo.toml                    # no-heap storage
//!     cargo bench --manifest-path codec/bench/Cargo.toml --features alloc   # alloc storage
//!
//! Per frame (criterion group = row of `j2735_bench::frames`), cases:
//! - `ours_decode_into`: `uper::decode_into` into a MessageFrame kept across iterations (the
//!   OBU's steady state: the value already holds this message, lists are refilled in place);
//! - `ours_decode_message_into`: `frame::decode_message_into` into a kept message;
//! - `ours_decode_by_value` (feature `alloc`): `uper::decode`, a new value each time (without
//!   `alloc` a message is too large to return by value: that call does not compile);
//! - `ours_decoder_alternating` / `rasn_decode_alternating`: this frame and its partner (the
//!   next row of another message type) in turn, ours through a `j2735::Decoder`; the time is
//!   per pair;
//! - `ours_encode` / `rasn_encode`: into a reused buffer (rasn: the message, then the
//!   MessageFrame around it); `..._alternating`: this frame's and the partner's values in turn;
//! - `rasn_decode`: `rasn::uper::decode` of the MessageFrame, then of the message in its
//!   open type (rasn-compiler keeps open types as `Any`).
//!
//! A case that makes a value hands criterion nothing back: the value is dropped inside the
//! timed closure (its drop is part of a new value's cost) after `std::hint::black_box(&value)`.
//! Returned to criterion 0.5 instead, it would go through criterion's own `black_box`, a
//! volatile read that copies the value field by field: for our `alloc` MessageFrame of the
//! time (296 octets) that copy was a third of a new BSM's measured time (173 ns, against 114 ns
//! without it), a cost of the harness, not of either codec. rasn's values are treated the
//! same.
//!
//! Every case of a build with `alloc` is named `..._alloc` (rasn's too: each storage's rows are
//! compared with rasn measured in the same run). At the end the table of ours against
//! rasn, with each ratio's goal, is printed (from criterion's estimates, also for earlier
//! runs' cases).

use std::hint::black_box;
use std::time::Duration;

use criterion::{Criterion, Throughput};
use j2735_bench::report::{self, OURS_SUFFIX};
use j2735_bench::{frames, ours, theirs};

fn main() {
    let frames = frames::all();
    let load_before = report::load_average();
    println!("machine: {}", report::machine());
    println!("our storage: {}", ours::STORAGE);
    // Both codecs must do the real work on these bytes before anything is timed.
    for f in &frames {
        assert_eq!(
            ours::round_trips(&f.bytes),
            Ok(true),
            "{}: our decode then encode must give the same bytes",
            f.row
        );
        let m = theirs::decode(&f.bytes)
            .unwrap_or_else(|e| panic!("{}: rasn cannot decode the frame: {e}", f.row));
        assert_eq!(
            theirs::kind(&m),
            f.kind,
            "{}: rasn decoded another message",
            f.row
        );
        let same = theirs::round_trips(&f.bytes) == Ok(true);
        println!(
            "frame {:<17} {:>5} octets  {}  rasn re-encodes identically: {}",
            f.row,
            f.bytes.len(),
            f.source,
            if same { "yes" } else { "NO" }
        );
    }

    let mut c = Criterion::default()
        .warm_up_time(Duration::from_secs(1))
        .measurement_time(Duration::from_secs(3))
        .sample_size(50)
        .configure_from_args();

    for (k, f) in frames.iter().enumerate() {
        let bytes = f.bytes.as_slice();
        let other = frames::partner(&frames, k).bytes.as_slice();
        let mut g = c.benchmark_group(f.row);
        g.throughput(Throughput::Bytes(bytes.len() as u64));
        ours_cases(&mut g, f.kind, bytes, other);
        rasn_cases(&mut g, bytes, other);
        g.finish();
    }
    c.final_summary();

    let sizes: Vec<(String, usize, String)> = frames
        .iter()
        .map(|f| (f.row.to_string(), f.bytes.len(), f.source.clone()))
        .collect();
    println!();
    println!(
        "ours against rasn (criterion medians; load average before {load_before}, after {}):",
        report::load_average()
    );
    let (table, missed) = report::table(&report::criterion_dir(), &sizes);
    println!("{table}");
    println!("{missed} ratio(s) below their goal");
}

type Group<'a> = criterion::BenchmarkGroup<'a, criterion::measurement::WallTime>;

fn ours_cases(g: &mut Group<'_>, kind: frames::Kind, bytes: &[u8], other: &[u8]) {
    let mut kept = ours::Kept::new(bytes).expect("our decode");
    g.bench_function(format!("ours_decode_into{OURS_SUFFIX}"), |b| {
        b.iter(|| kept.decode(black_box(bytes)).expect("our decode"))
    });
    let mut kept_msg = ours::KeptMessage::new(kind, bytes).expect("our decode");
    g.bench_function(format!("ours_decode_message_into{OURS_SUFFIX}"), |b| {
        b.iter(|| kept_msg.decode(black_box(bytes)).expect("our decode"))
    });
    drop(kept_msg);
    #[cfg(feature = "alloc")]
    g.bench_function(format!("ours_decode_by_value{OURS_SUFFIX}"), |b| {
        b.iter(|| {
            let frame = ours::decode_by_value(black_box(bytes)).expect("our decode");
            black_box(&frame);
        })
    });
    let mut pair = ours::Alternating::new(bytes, other).expect("our decode");
    g.bench_function(format!("ours_decoder_alternating{OURS_SUFFIX}"), |b| {
        b.iter(|| {
            pair.decode_pair(black_box(bytes), black_box(other))
                .expect("our decode")
        })
    });
    drop(pair);
    let mut buf = vec![0u8; ours::BUF_LEN];
    g.bench_function(format!("ours_encode{OURS_SUFFIX}"), |b| {
        b.iter(|| ours::encode(black_box(kept.frame()), &mut buf).expect("our encode"))
    });
    let partner = ours::Kept::new(other).expect("our decode");
    g.bench_function(format!("ours_encode_alternating{OURS_SUFFIX}"), |b| {
        b.iter(|| {
            ours::encode(black_box(kept.frame()), &mut buf).expect("our encode");
            ours::encode(black_box(partner.frame()), &mut buf).expect("our encode")
        })
    });
}

fn rasn_cases(g: &mut Group<'_>, bytes: &[u8], other: &[u8]) {
    g.bench_function(format!("rasn_decode{OURS_SUFFIX}"), |b| {
        b.iter(|| {
            let message = theirs::decode(black_box(bytes)).expect("rasn decode");
            black_box(&message);
        })
    });
    g.bench_function(format!("rasn_decode_alternating{OURS_SUFFIX}"), |b| {
        b.iter(|| {
            black_box(&theirs::decode(black_box(bytes)).expect("rasn decode"));
            black_box(&theirs::decode(black_box(other)).expect("rasn decode"));
        })
    });
    let m = theirs::decode(bytes).expect("rasn decode");
    let n = theirs::decode(other).expect("rasn decode");
    let mut out = Vec::new();
    g.bench_function(format!("rasn_encode{OURS_SUFFIX}"), |b| {
        b.iter(|| theirs::encode(black_box(&m), &mut out).expect("rasn encode"))
    });
    g.bench_function(format!("rasn_encode_alternating{OURS_SUFFIX}"), |b| {
        b.iter(|| {
            theirs::encode(black_box(&m), &mut out).expect("rasn encode");
            theirs::encode(black_box(&n), &mut out).expect("rasn encode")
        })
    });
}
