//! [`Decoder`]: the fast path behind the simple loop "decode this frame, look at it".

use crate::frame::peek_message_id;
use crate::uper::{self, DecodeError, DecodeErrorKind, SeqOf};
use crate::MessageFrame;

/// Decodes MessageFrames into kept values, one per message type, so that each decode
/// refills storage in place ([`uper::decode_into`]): no value is built or copied per
/// message, and with `alloc` no vector is allocated again once its type has been seen.
///
/// It keeps up to `K` values (default 4: a MAP, a SPaT, a TIM and a BSM), each holding the
/// last frame of one `messageId`; a frame of a type not kept reuses the value decoded least
/// recently (a frame of an unknown `messageId` takes a value too). Without `alloc` each kept value is as large as the largest message of the
/// capacity profile (a `MessageFrame` is 8.5 MB by default, 1.2 MB with
/// `firmware-capacities`; see the crate docs' table of value sizes): the slots are only
/// filled as types arrive, but their room is reserved, so put the decoder in static memory
/// ([`Decoder::new`] is a `const fn`). A value starting out, or switching to another
/// message, is first built as a placeholder, which unoptimised builds place on the stack, a
/// copy per call level: give the decoding thread a stack of many times the largest value (the
/// example below runs on one of 256 MiB), or use `alloc` or the `firmware-capacities` profile.
/// With `alloc` it takes `K` x 136 octets (a `MessageFrame`) plus the heap storage of the
/// kept messages.
///
/// ```
/// use std::sync::Mutex;
/// use j2735::{Decoder, MessageFrameValue};
///
/// // In static memory, not on the stack: without `alloc` the kept values are megabytes.
/// static DECODER: Mutex<Decoder> = Mutex::new(Decoder::new());
/// # std::thread::Builder::new().stack_size(256 << 20).spawn(|| {
///
/// // A BasicSafetyMessage as received (MessageFrame, UPER; an oracle vector).
/// let hex = "00142504468acf136848a7603a059cae1b0f0d4b140c8fa021166978817ad7dc7f7f6903485c8f00";
/// let mut bytes = [0u8; 40];
/// let n = j2735::hex::decode_into(hex, &mut bytes)?;
///
/// let mut decoder = DECODER.lock().unwrap();
/// match &decoder.decode(&bytes[..n])?.value {
///     MessageFrameValue::BasicSafetyMessage(bsm) => {
///         assert_eq!(bsm.core_data.msg_cnt.get(), 17);
///     }
///     other => println!("message {}", other.id().get()),
/// }
/// # Ok::<(), Box<dyn std::error::Error + Send + Sync>>(())
/// # }).unwrap().join().unwrap().unwrap();
/// ```
pub struct Decoder<const K: usize = 4> {
    kept: SeqOf<MessageFrame, K>,
    /// The `messageId` each kept value was last decoded from.
    ids: [u16; K],
    /// When each kept value was last used (a count of decodes).
    used: [u64; K],
    decodes: u64,
}

impl<const K: usize> Decoder<K> {
    /// A decoder that keeps nothing yet (`K` must be at least 1).
    pub const fn new() -> Self {
        assert!(K >= 1, "a Decoder keeps at least one value");
        Self {
            kept: SeqOf::new(),
            ids: [0; K],
            used: [0; K],
            decodes: 0,
        }
    }

    /// Decodes the complete MessageFrame in `bytes` (as [`uper::decode`]) into the value kept
    /// for its `messageId`, and returns it. After an error that value holds an unspecified
    /// valid value and is the first to be reused.
    pub fn decode(&mut self, bytes: &[u8]) -> Result<&MessageFrame, DecodeError> {
        let id = peek_message_id(bytes)?;
        let k = self.slot_for(id).ok_or(DecodeError::at(
            DecodeErrorKind::CapacityExceeded,
            0,
            "Decoder",
        ))?;
        self.decodes += 1;
        self.ids[k] = id;
        let out = &mut self.kept[k];
        match uper::decode_into(bytes, out) {
            Ok(()) => {
                self.used[k] = self.decodes;
                Ok(&self.kept[k])
            }
            Err(e) => {
                self.used[k] = 0;
                Err(e)
            }
        }
    }

    /// How many values are kept now (at most `K`).
    pub fn kept(&self) -> usize {
        self.kept.len()
    }

    /// The index of the value to decode a frame of `id` into: the one kept for `id`, else a
    /// new one while fewer than `K` are kept, else the least recently used.
    fn slot_for(&mut self, id: u16) -> Option<usize> {
        let n = self.kept.len();
        if let Some(k) = (0..n).find(|&k| self.ids[k] == id) {
            return Some(k);
        }
        if n < K && self.kept.push_slot().is_some() {
            return Some(n);
        }
        (0..n).min_by_key(|&k| self.used[k])
    }
}

impl<const K: usize> Default for Decoder<K> {
    fn default() -> Self {
        Self::new()
    }
}

#[cfg(test)]
mod tests;
