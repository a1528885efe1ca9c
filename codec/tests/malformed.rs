//! Malformed input: every corpus frame cut at every octet, and with every single bit flipped,
//! decodes to `Ok` or `Err` and never panics; whatever decodes also encodes. Needs
//! `../shared` (feature `shared-corpus`).
#![cfg(feature = "shared-corpus")]

mod common;

use j2735::uper::{self, Placeholder};
use j2735::MessageFrame;

#[test]
fn truncated_and_bit_flipped_frames_never_panic() {
    common::big_stack(|| {
        let mut mf = Box::new(MessageFrame::placeholder());
        let mut out = vec![0u8; 1 << 16];
        let (mut inputs, mut decoded) = (0usize, 0usize);
        for (name, frame) in common::corpus_frames() {
            let mut check = |input: &[u8], what: &str| {
                inputs += 1;
                let r = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
                    uper::decode_into(input, &mut *mf).map(|()| uper::encode(&*mf, &mut out))
                }));
                match r {
                    Err(_) => panic!("{name}: {what} panicked"),
                    Ok(Ok(Err(e))) => panic!("{name}: {what} decoded but did not encode: {e}"),
                    Ok(Ok(Ok(_))) => decoded += 1,
                    Ok(Err(_)) => {}
                }
            };
            for cut in 0..frame.len() {
                check(&frame[..cut], "cut");
            }
            let mut flipped = frame.clone();
            for bit in 0..frame.len() * 8 {
                flipped[bit / 8] ^= 0x80 >> (bit % 8);
                check(&flipped, "flip");
                flipped[bit / 8] ^= 0x80 >> (bit % 8);
            }
        }
        println!("{inputs} malformed inputs: {decoded} decoded (and encoded), the rest refused; no panic");
        assert!(inputs > 100_000);
    });
}
