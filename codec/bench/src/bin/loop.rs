//! Runs one benchmark case N times, for profilers and instruction counters:
//!
//!     target/release/loop ROW CASE N
//!
//! ROW: bsm_001 | spat_032 | map_052 | tim_222 | tim_036 | map_056 | map_061
//! CASE: ours_decode_into | ours_decode_message_into | ours_decode_by_value (feature alloc)
//!       | ours_decoder_alternating | ours_encode | rasn_decode | rasn_decode_alternating
//!       | rasn_encode
//!
//! `callgrind.sh` runs it under `valgrind --tool=callgrind` at two values of N and divides the
//! difference of the instruction counts by the difference of N: the instructions of one
//! message, without the setup.

use std::hint::black_box;
use std::process::ExitCode;

use j2735_bench::{frames, ours, theirs};

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().collect();
    if args.len() != 4 {
        eprintln!("usage: {} ROW CASE N", args[0]);
        return ExitCode::from(2);
    }
    let (row, case) = (args[1].as_str(), args[2].as_str());
    let n: u64 = match args[3].parse() {
        Ok(n) => n,
        Err(e) => {
            eprintln!("N: {e}");
            return ExitCode::from(2);
        }
    };
    let all = frames::all();
    let Some(k) = all.iter().position(|f| f.row == row) else {
        eprintln!("no row {row}");
        return ExitCode::from(2);
    };
    let frame = &all[k];
    let bytes = frame.bytes.as_slice();
    let other = frames::partner(&all, k).bytes.as_slice();
    match case {
        "ours_decode_into" => {
            let mut kept = ours::Kept::new(bytes).expect("decode");
            for _ in 0..n {
                kept.decode(black_box(bytes)).expect("decode");
                black_box(kept.frame());
            }
        }
        "ours_decode_message_into" => {
            let mut kept = ours::KeptMessage::new(frame.kind, bytes).expect("decode");
            for _ in 0..n {
                kept.decode(black_box(bytes)).expect("decode");
                black_box(&kept);
            }
        }
        #[cfg(feature = "alloc")]
        "ours_decode_by_value" => {
            for _ in 0..n {
                // As the criterion case: a barrier on a reference, not a copy of the value.
                let frame = ours::decode_by_value(black_box(bytes)).expect("decode");
                black_box(&frame);
            }
        }
        "ours_decoder_alternating" => {
            let mut pair = ours::Alternating::new(bytes, other).expect("decode");
            for _ in 0..n {
                pair.decode_pair(black_box(bytes), black_box(other))
                    .expect("decode");
            }
        }
        "rasn_decode_alternating" => {
            for _ in 0..n {
                black_box(&theirs::decode(black_box(bytes)).expect("decode"));
                black_box(&theirs::decode(black_box(other)).expect("decode"));
            }
        }
        "ours_encode" => {
            let kept = ours::Kept::new(bytes).expect("decode");
            let mut buf = vec![0u8; ours::BUF_LEN];
            for _ in 0..n {
                black_box(ours::encode(black_box(kept.frame()), &mut buf).expect("encode"));
            }
        }
        "rasn_decode" => {
            for _ in 0..n {
                let message = theirs::decode(black_box(bytes)).expect("decode");
                black_box(&message);
            }
        }
        "rasn_encode" => {
            let m = theirs::decode(bytes).expect("decode");
            let mut out = Vec::new();
            for _ in 0..n {
                theirs::encode(black_box(&m), &mut out).expect("encode");
                black_box(&out);
            }
        }
        _ => {
            eprintln!("unknown case {case} (with this build's features)");
            return ExitCode::from(2);
        }
    }
    ExitCode::SUCCESS
}
