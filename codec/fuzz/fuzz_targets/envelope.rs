//! IEEE 1609.2 envelopes, `unwrap_message_frame` and RSU text records.
//! The checks: `j2735_fuzz::envelope`.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    j2735_fuzz::envelope::check(data);
});
