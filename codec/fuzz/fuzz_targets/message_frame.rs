//! UPER `MessageFrame`: decode, encode, decode again; direct MAP/TIM decode agrees.
//! The checks: `j2735_fuzz::message_frame`.
#![no_main]

use std::sync::OnceLock;

use j2735_fuzz::{message_frame, BigStack};
use libfuzzer_sys::fuzz_target;

/// The kept values are megabytes: they are made, and every input is checked, on a thread
/// with a large stack.
static WORKER: OnceLock<BigStack> = OnceLock::new();

fuzz_target!(|data: &[u8]| {
    WORKER
        .get_or_init(|| {
            BigStack::spawn(
                "message_frame",
                message_frame::State::new,
                message_frame::check,
            )
        })
        .run(data);
});
