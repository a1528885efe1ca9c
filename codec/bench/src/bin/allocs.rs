//! Counts heap allocations of each codec per message, with a counting global allocator:
//!
//!     cargo run --release --manifest-path codec/bench/Cargo.toml --bin allocs
//!     cargo run --release --manifest-path codec/bench/Cargo.toml --bin allocs --features alloc
//!
//! Without `alloc` our decoding and encoding must not allocate at all: the program fails
//! (exit 1) when one of them does. With `alloc` the counts are reported. rasn's are reported
//! in both builds.

use std::alloc::{GlobalAlloc, Layout, System};
use std::hint::black_box;
use std::process::ExitCode;
use std::sync::atomic::{AtomicU64, Ordering::Relaxed};

use j2735_bench::{frames, ours, theirs, with_large_stack};

/// Allocations (alloc, alloc_zeroed and realloc calls) and bytes requested, since start.
static CALLS: AtomicU64 = AtomicU64::new(0);
static BYTES: AtomicU64 = AtomicU64::new(0);

/// The system allocator, counting every call that obtains memory.
struct Counting;

// SAFETY: every method forwards its arguments unchanged to `System`, which upholds the
// `GlobalAlloc` contract; the only addition is a relaxed atomic increment, which neither
// allocates nor unwinds.
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        CALLS.fetch_add(1, Relaxed);
        BYTES.fetch_add(layout.size() as u64, Relaxed);
        // SAFETY: the caller's contract for `alloc` is passed on as is.
        unsafe { System.alloc(layout) }
    }
    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        CALLS.fetch_add(1, Relaxed);
        BYTES.fetch_add(layout.size() as u64, Relaxed);
        // SAFETY: as above.
        unsafe { System.alloc_zeroed(layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        CALLS.fetch_add(1, Relaxed);
        BYTES.fetch_add(new_size as u64, Relaxed);
        // SAFETY: as above.
        unsafe { System.realloc(ptr, layout, new_size) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        // SAFETY: as above.
        unsafe { System.dealloc(ptr, layout) }
    }
}

#[global_allocator]
static ALLOCATOR: Counting = Counting;

/// Allocations and bytes per call of `f`, averaged over `n` calls.
fn per_call(n: u64, mut f: impl FnMut()) -> (f64, f64) {
    let (c0, b0) = (CALLS.load(Relaxed), BYTES.load(Relaxed));
    for _ in 0..n {
        f();
    }
    let (c1, b1) = (CALLS.load(Relaxed), BYTES.load(Relaxed));
    ((c1 - c0) as f64 / n as f64, (b1 - b0) as f64 / n as f64)
}

fn fmt(v: (f64, f64)) -> String {
    if v.0.fract() == 0.0 {
        format!("{:>6} ({:.0} B)", v.0, v.1)
    } else {
        format!("{:>6.2} ({:.0} B)", v.0, v.1)
    }
}

const N: u64 = 100;

fn main() -> ExitCode {
    let frames = frames::all();
    println!("our storage: {}", ours::STORAGE);
    println!(
        "size of j2735::MessageFrame: {} bytes, of MapData: {} bytes",
        std::mem::size_of::<j2735::MessageFrame>(),
        std::mem::size_of::<j2735::MapData>()
    );
    println!("heap allocations per message (and bytes requested), mean of {N} messages:");
    println!();
    println!("| frame | octets | ours: decode_into, first (fresh value) | ours: decode_into, steady | ours: decode_message_into, steady | ours: uper::decode (new value) | ours: encode | rasn: decode | rasn: encode |");
    println!("| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |");
    let mut failures = Vec::new();
    for f in &frames {
        let bytes = f.bytes.clone();
        // Decoding into a fresh placeholder switches the message variant and fills every
        // optional part: counted on the large-stack thread, after the box exists.
        let first = with_large_stack(move || {
            use j2735::uper::Placeholder;
            let mut frame = Box::new(j2735::MessageFrame::placeholder());
            let r = per_call(1, || {
                j2735::uper::decode_into(&bytes, &mut *frame).expect("our decode")
            });
            black_box(&frame);
            r
        });
        let bytes = f.bytes.as_slice();
        let mut kept = ours::Kept::new(bytes).expect("our decode");
        let steady = per_call(N, || kept.decode(black_box(bytes)).expect("our decode"));
        let mut kept_msg = ours::KeptMessage::new(f.kind, bytes).expect("our decode");
        let steady_msg = per_call(N, || kept_msg.decode(black_box(bytes)).expect("our decode"));
        drop(kept_msg);
        #[cfg(feature = "alloc")]
        let by_value = fmt(per_call(N, || {
            black_box(ours::decode_by_value(black_box(bytes)).expect("our decode"));
        }));
        #[cfg(not(feature = "alloc"))]
        let by_value = String::from("(needs alloc)");
        let mut buf = vec![0u8; ours::BUF_LEN];
        let enc = per_call(N, || {
            black_box(ours::encode(black_box(kept.frame()), &mut buf).expect("our encode"));
        });
        drop(kept);
        let rasn_dec = per_call(N, || {
            black_box(theirs::decode(black_box(bytes)).expect("rasn decode"));
        });
        let m = theirs::decode(bytes).expect("rasn decode");
        let mut out = Vec::new();
        theirs::encode(&m, &mut out).expect("rasn encode");
        let rasn_enc = per_call(N, || {
            theirs::encode(black_box(&m), &mut out).expect("rasn encode")
        });
        println!(
            "| {} | {} | {} | {} | {} | {} | {} | {} | {} |",
            f.row,
            f.bytes.len(),
            fmt(first),
            fmt(steady),
            fmt(steady_msg),
            by_value,
            fmt(enc),
            fmt(rasn_dec),
            fmt(rasn_enc)
        );
        if !cfg!(feature = "alloc") {
            for (what, v) in [
                ("decode_into into a fresh value", first),
                ("decode_into (steady)", steady),
                ("decode_message_into (steady)", steady_msg),
                ("encode", enc),
            ] {
                if v.0 != 0.0 {
                    failures.push(format!("{}: {what} allocated {} times", f.row, v.0));
                }
            }
        }
    }
    println!();
    if failures.is_empty() {
        if !cfg!(feature = "alloc") {
            println!("no-alloc: 0 heap allocations in every decode and encode of ours: ok");
        }
        ExitCode::SUCCESS
    } else {
        for f in &failures {
            println!("FAIL {f}");
        }
        ExitCode::FAILURE
    }
}
