//! Decodes a MAP and a TIM and encodes a TIM, as an OBU firmware would; its `.text` size is
//! the codec's flash cost. The frames come from an opaque input so nothing is folded away.
//! (It is linked, not run: with the default capacities a MapData does not fit this RAM.)
#![no_std]
#![no_main]
#![forbid(unsafe_code)]

use core::hint::black_box;
use cortex_m_rt::entry;
use j2735::frame::{decode_message_into, encode_message, peek_message_id, Message};
use j2735::uper::Placeholder;
use j2735::{MapData, TravelerInformation};

#[entry]
fn main() -> ! {
    let mut map = MapData::placeholder();
    let mut tim = TravelerInformation::placeholder();
    let mut out = [0u8; 1500];
    loop {
        let input: &[u8] = black_box(&[]);
        let mut score = 0usize;
        match peek_message_id(input) {
            Ok(MapData::MESSAGE_ID) if decode_message_into(input, &mut map).is_ok() => {
                score += map.intersections.as_ref().map_or(0, |l| l.len());
            }
            Ok(TravelerInformation::MESSAGE_ID) if decode_message_into(input, &mut tim).is_ok() => {
                score += encode_message(&tim, &mut out).unwrap_or(0);
            }
            _ => {}
        }
        black_box(score);
    }
}

#[panic_handler]
fn panic(_: &core::panic::PanicInfo) -> ! {
    loop {
        cortex_m::asm::udf();
    }
}
