//! JER text of a `MessageFrame`: read, UPER round trip, write and read again.
//! The checks: `j2735_fuzz::jer`.
#![no_main]

use std::sync::OnceLock;

use j2735_fuzz::{jer, BigStack};
use libfuzzer_sys::fuzz_target;

/// JER reading returns the 7.2 MB `MessageFrame` by value: every input is checked on a
/// thread with a large stack.
static WORKER: OnceLock<BigStack> = OnceLock::new();

fuzz_target!(|data: &[u8]| {
    WORKER
        .get_or_init(|| BigStack::spawn("jer", jer::State::new, jer::check))
        .run(data);
});
