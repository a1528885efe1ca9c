//! The conformance corpus of real J2735 frames (`../shared/corpus`, not in this repository):
//! every frame decodes, and encoding the result gives the identical bytes. Runs in whichever
//! storage mode the crate is built with (`--features alloc` or not), so `.ci/run` runs it twice.
//! Only with feature `shared-corpus`; then a missing corpus is a failure, not a skip.
#![cfg(feature = "shared-corpus")]

mod common;

use j2735::uper::{self, Placeholder};
use j2735::MessageFrame;

#[test]
fn every_corpus_frame_round_trips_byte_exact() {
    common::big_stack(|| {
        let all = common::corpus_frames();
        let mut mf = Box::new(MessageFrame::placeholder());
        let mut buf = vec![0u8; 1 << 16];
        let mut failures = Vec::new();
        for (name, bytes) in &all {
            if let Err(e) = uper::decode_into(bytes, &mut *mf) {
                failures.push(format!("{name}: decode: {e}"));
                continue;
            }
            match uper::encode(&*mf, &mut buf) {
                Ok(n) if &buf[..n] == bytes.as_slice() => {}
                Ok(n) => failures.push(format!(
                    "{name}: re-encoded {n} octets differ from the {}",
                    bytes.len()
                )),
                Err(e) => failures.push(format!("{name}: encode: {e}")),
            }
        }
        let mode = if cfg!(feature = "alloc") {
            "alloc"
        } else {
            "no-alloc"
        };
        println!(
            "{mode}: {}/{} corpus frames round-trip byte-exact",
            all.len() - failures.len(),
            all.len()
        );
        assert!(
            failures.is_empty(),
            "{} failures:\n{}",
            failures.len(),
            failures.join("\n")
        );
    });
}

/// With `std`: every corpus frame decoded as a new value, each from the storage that the
/// previous (mostly differently shaped) frame left, re-encodes byte-exact and equals the
/// fresh value (see `common::check_decodes_from_recycled_storage`).
#[cfg(feature = "std")]
#[test]
fn new_values_decoded_from_recycled_storage_equal_fresh_ones() {
    let all = common::corpus_frames();
    let checked = common::check_decodes_from_recycled_storage(&all);
    assert_eq!(checked, 3 * all.len());
    println!("{checked} new-value decodes of corpus frames from recycled storage match");
}
