//! Target `message_frame`: UPER `MessageFrame` decode, re-encode, decode again; and the
//! direct message API (`frame::decode_message_into`) agreeing with it.
//!
//! Invariants, for every input:
//! 1. `uper::decode_into::<MessageFrame>` either fails or gives a value `v` such that
//!    `uper::encode(v)` succeeds with exactly `uper::encoded_len(v)` octets (and fails with
//!    `BufferTooSmall` in one octet less), and that encoding decodes to a value equal to `v`
//!    whose encoding is byte-identical to the first.
//! 2. `frame::decode_message_into::<MapData>` (and `<TravelerInformation>`) succeeds exactly
//!    when the `MessageFrame` decodes to that message, with an equal value; on an input whose
//!    `messageId` selects the message, both fail with the same error kind at the same bit;
//!    on another `messageId` the direct decode fails.
//! 3. With the crate's feature `alloc` (the heap storage with `std`, as the daemon runs it):
//!    `uper::decode::<MessageFrame>`, a new value refilling storage that earlier inputs'
//!    values left on the thread's shelves (whole or half decoded), gives the value of 1 or
//!    fails with the same error kind at the same bit.

use j2735::frame::{self, Message};
use j2735::uper::{self, DecodeError, DecodeErrorKind, EncodeErrorKind, Placeholder};
use j2735::{MapData, MessageFrame, MessageFrameValue, TravelerInformation};

use crate::hex;

/// The values kept across inputs (made on the big-stack thread).
///
/// The `MessageFrame`s are kept per `messageId` (a slot per J2735 2020 message, one for every
/// other id): decoding into a `MessageFrame` that holds another message first replaces it by a
/// placeholder of the new one, a 7.2 MB move that takes about 2 ms (against 1-5 us for the
/// decode itself); with a slot per message the fuzzer runs 10-20 times more inputs. Each slot
/// still switches on its first input (from the placeholder), and keeps refilling in place.
pub struct State {
    slots: Vec<Option<Slot>>,
    map: Box<MapData>,
    tim: Box<TravelerInformation>,
    encoding: Vec<u8>,
    again: Vec<u8>,
}

/// The decoded input and the decoded re-encoding, for one `messageId`.
struct Slot {
    first: Box<MessageFrame>,
    second: Box<MessageFrame>,
}

/// Slots: ids 18..=32 (MAP .. PSM), 240..=255 (test messages), and one for any other id or
/// an input too short for one.
const SLOTS: usize = 15 + 16 + 1;

fn slot_index(data: &[u8]) -> usize {
    match frame::peek_message_id(data) {
        Ok(id @ 18..=32) => usize::from(id - 18),
        Ok(id @ 240..=255) => usize::from(id - 240) + 15,
        _ => SLOTS - 1,
    }
}

impl State {
    /// The direct-decode values; the slots are made when first used. Needs a large stack
    /// (the values are megabytes).
    pub fn new() -> Self {
        Self {
            slots: (0..SLOTS).map(|_| None).collect(),
            map: Box::new(MapData::placeholder()),
            tim: Box::new(TravelerInformation::placeholder()),
            encoding: Vec::new(),
            again: Vec::new(),
        }
    }
}

impl Default for State {
    fn default() -> Self {
        Self::new()
    }
}

/// Runs every check of this target on `data`.
pub fn check(st: &mut State, data: &[u8]) {
    let slot = st.slots[slot_index(data)].get_or_insert_with(|| Slot {
        first: Box::new(MessageFrame::placeholder()),
        second: Box::new(MessageFrame::placeholder()),
    });
    let decoded = uper::decode_into(data, &mut *slot.first);
    if decoded.is_ok() {
        round_trip(slot, &mut st.encoding, &mut st.again, data);
    }
    let in_frame_map = match (&decoded, &slot.first.value) {
        (Ok(()), MessageFrameValue::MapData(m)) => Some(&**m),
        _ => None,
    };
    #[cfg(feature = "alloc")]
    new_value_agrees(data, &decoded, &slot.first);
    let direct = frame::decode_message_into(data, &mut *st.map);
    agree("MapData", data, &decoded, in_frame_map, &direct, &*st.map);
    let in_frame_tim = match (&decoded, &slot.first.value) {
        (Ok(()), MessageFrameValue::TravelerInformation(t)) => Some(&**t),
        _ => None,
    };
    let direct = frame::decode_message_into(data, &mut *st.tim);
    agree(
        "TravelerInformation",
        data,
        &decoded,
        in_frame_tim,
        &direct,
        &*st.tim,
    );
}

/// Invariant 1, for `data` that decoded into `st.first`; `encoding` and `again` are buffers.
fn round_trip(st: &mut Slot, encoding: &mut Vec<u8>, again: &mut Vec<u8>, data: &[u8]) {
    let len = uper::encoded_len(&*st.first).unwrap_or_else(|e| {
        panic!(
            "decoded MessageFrame does not encode (encoded_len: {e}); input {}",
            hex(data)
        )
    });
    // Room for more than needed: the encoder must stop at `len`.
    encoding.clear();
    encoding.resize(len + 8, 0);
    let n = uper::encode(&*st.first, encoding).unwrap_or_else(|e| {
        panic!(
            "decoded MessageFrame does not encode (encode: {e}); input {}",
            hex(data)
        )
    });
    assert_eq!(
        n,
        len,
        "encode wrote {n} octets, encoded_len said {len}; input {}",
        hex(data)
    );
    encoding.truncate(n);
    if n > 0 {
        again.clear();
        again.resize(n - 1, 0);
        match uper::encode(&*st.first, again) {
            Err(e) if e.kind == EncodeErrorKind::BufferTooSmall => {}
            other => panic!(
                "encode into {} octets (one less than needed) gave {other:?}; input {}",
                n - 1,
                hex(data)
            ),
        }
    }
    if let Err(e) = uper::decode_into(encoding, &mut *st.second) {
        panic!(
            "re-encoding does not decode: {e}; input {}, re-encoding {}",
            hex(data),
            hex(encoding)
        );
    }
    assert!(
        *st.first == *st.second,
        "decode(encode(decode(input))) differs from decode(input); input {}, re-encoding {}",
        hex(data),
        hex(encoding)
    );
    again.clear();
    again.resize(n + 8, 0);
    let m = uper::encode(&*st.second, again).unwrap_or_else(|e| {
        panic!(
            "second decode does not encode: {e}; input {}, re-encoding {}",
            hex(data),
            hex(encoding)
        )
    });
    assert!(
        again[..m] == encoding[..],
        "the two encodings differ; input {}, first {}, second {}",
        hex(data),
        hex(encoding),
        hex(&again[..m])
    );
}

/// Invariant 3: a new value's decode (from recycled storage) agrees with the kept value's
/// decode `kept` into `value`.
#[cfg(feature = "alloc")]
fn new_value_agrees(data: &[u8], kept: &Result<(), DecodeError>, value: &MessageFrame) {
    match (kept, uper::decode::<MessageFrame>(data)) {
        (Ok(()), Ok(new)) => assert!(
            new == *value,
            "a new value's decode differs from the kept value's; input {}",
            hex(data)
        ),
        (Err(k), Err(n)) => assert!(
            (k.kind, k.bit) == (n.kind, n.bit),
            "a new value's decode error ({n}) differs from the kept value's ({k}); input {}",
            hex(data)
        ),
        (Ok(()), Err(n)) => panic!(
            "a new value's decode fails ({n}) where the kept value's succeeds; input {}",
            hex(data)
        ),
        (Err(k), Ok(_)) => panic!(
            "a new value's decode succeeds where the kept value's fails ({k}); input {}",
            hex(data)
        ),
    }
}

/// Invariant 2 for message `M`: `frame` is the `MessageFrame` decode result, `in_frame` the
/// message it holds when it is an `M`, `direct` and `out` the direct decode of `M`.
fn agree<M: Message + PartialEq + core::fmt::Debug>(
    name: &str,
    data: &[u8],
    frame: &Result<(), DecodeError>,
    in_frame: Option<&M>,
    direct: &Result<(), DecodeError>,
    out: &M,
) {
    match (frame, in_frame, direct) {
        (Ok(()), Some(v), Ok(())) => assert!(
            v == out,
            "{name}: direct decode differs from the MessageFrame's; input {}",
            hex(data)
        ),
        (Ok(()), Some(_), Err(e)) => panic!(
            "{name}: MessageFrame decodes but the direct decode fails ({e}); input {}",
            hex(data)
        ),
        (Ok(()), None, Ok(())) => panic!(
            "{name}: direct decode succeeds on a MessageFrame of another message; input {}",
            hex(data)
        ),
        (Ok(()), None, Err(e)) => assert_eq!(
            e.kind,
            DecodeErrorKind::UnexpectedMessage,
            "{name}: direct decode of another message: {e}; input {}",
            hex(data)
        ),
        (Err(f), _, Ok(())) => panic!(
            "{name}: direct decode succeeds but the MessageFrame fails ({f}); input {}",
            hex(data)
        ),
        (Err(f), _, Err(d)) => {
            if frame::peek_message_id(data) == Ok(M::MESSAGE_ID) {
                assert!(
                    (f.kind, f.bit) == (d.kind, d.bit),
                    "{name}: MessageFrame error ({f}) and direct error ({d}) differ; input {}",
                    hex(data)
                );
            }
        }
    }
}
