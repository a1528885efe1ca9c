//! SAE J2735 (2020) in Rust: every message type, generated from the standard's type model,
//! with a UPER codec that needs no heap and reproduces real traffic byte for byte.
//!
//! ```
//! # std::thread::Builder::new().stack_size(64 << 20).spawn(|| {
//! use j2735::{frame, uper::Placeholder, TravelerInformation};
//!
//! let hex = "001f260020807ad693a403ad274801fffffffedfffefd275c61f40280100169e9cfb90410010010040";
//! let mut bytes = [0u8; 41]; // a TIM's MessageFrame as received (an oracle test vector)
//! j2735::hex::decode_into(hex, &mut bytes)?;
//! let mut tim = TravelerInformation::placeholder(); // kept: each decode refills it
//! frame::decode_message_into(&bytes, &mut tim)?;
//! assert_eq!(tim.msg_cnt.get(), 2);
//! # Ok::<(), Box<dyn std::error::Error + Send + Sync>>(())
//! # }).unwrap().join().unwrap().unwrap();
//! ```
//!
//! The generated types are in [`msg`], one module per ASN.1 module (`msg::map_data`,
//! `msg::traveler_information`, `msg::common`, ...; the test messages in `msg::test`); the
//! messages a receiver handles most are re-exported here. Without `alloc` a TIM of the
//! default capacities is 6.6 MB (the table below), more than a thread's default stack (the
//! example runs on a larger one): a firmware uses the `firmware-capacities` profile (40 KB),
//! a host `alloc` (584 octets).
//!
//! # Which decode entry point
//! The first three decode into values that are already there, so no value is built or
//! copied per frame and, with `alloc`, no list is allocated again once its type has been
//! seen; they differ in what the caller keeps.
//! - [`Decoder`]: a receiver decoding frame after frame of any message type. It keeps one
//!   value per type (a MAP, a SPaT, a TIM and a BSM by default) and refills it;
//!   `decoder.decode(bytes)?` returns the `MessageFrame`.
//! - [`uper::decode_into`]: you keep a value of a known type (a [`MessageFrame`] or any type
//!   of [`msg`]) and refill it with each encoding of that type.
//! - [`frame::decode_message_into`]: a firmware that handles a few message types keeps one
//!   value of each and decodes the frames that carry them (the example above); only those
//!   types' decoders are linked, where a `MessageFrame` links every message's.
//! - [`uper::decode`] returns a new value and is meant for small types: it refuses at compile
//!   time a type over [`uper::BY_VALUE_MAX_OCTETS`] (without `alloc`, a `MessageFrame` and
//!   every message but the smallest few), since the copy would cost more than the decoding.
//!
//! With `alloc` a kept `MessageFrame` is 136 octets, so a receiver's [`Decoder`] can live
//! anywhere:
//!
//! ```
//! # #[cfg(feature = "alloc")] {
//! use j2735::{Decoder, MessageFrameValue};
//!
//! let frames = [
//!     "001f260020807ad693a403ad274801fffffffedfffefd275c61f40280100169e9cfb90410010010040",
//!     "00142504468acf136848a7603a059cae1b0f0d4b140c8fa021166978817ad7dc7f7f6903485c8f00",
//! ]; // a TIM and a BasicSafetyMessage (oracle test vectors)
//! let mut decoder = Decoder::<4>::new();
//! for hex in frames {
//!     let mut bytes = [0u8; 64];
//!     let n = j2735::hex::decode_into(hex, &mut bytes)?;
//!     match &decoder.decode(&bytes[..n])?.value {
//!         MessageFrameValue::TravelerInformation(tim) => assert_eq!(tim.msg_cnt.get(), 2),
//!         MessageFrameValue::BasicSafetyMessage(b) => assert_eq!(b.core_data.msg_cnt.get(), 17),
//!         other => println!("message {}", other.id().get()),
//!     }
//! }
//! # }
//! # Ok::<(), Box<dyn std::error::Error + Send + Sync>>(())
//! ```
//!
//! Without `alloc` each kept value is a `MessageFrame` of megabytes: [`Decoder`] shows one in
//! static memory.
//!
//! # Storage
//! Without features nothing allocates: SEQUENCE OF and strings are bounded by capacities set
//! per type in `codec/codegen/capacities.toml` (a value over a capacity is a
//! [`uper::DecodeErrorKind::CapacityExceeded`] error that names the capacity). Feature
//! `alloc` switches them to heap storage, bounded only by the ASN.1 SIZE constraints; what
//! real traffic mostly holds stays inside the value, so that a new value's decode allocates
//! little: the first items of the lists chosen in `capacities.toml`'s `[inline]` (a SPaT
//! movement's event, a lane's connections), up to 15 octets of an OCTET STRING and 15
//! characters of an IA5String. With `alloc` a few large, mostly absent members (a node's
//! attributes), large and seldom chosen alternatives (a TIM path's `geometry`) and the
//! message of a [`MessageFrame`] are boxed ([`uper::Boxed`], [`uper::MessageBox`]), so a
//! `MessageFrame` is a few words to move; without it they are in place.
//!
//! With `alloc` and `std`, a new value's decode reuses what this thread's dropped values
//! held: a dropped message's box (value and all) and a dropped list's storage (items and
//! all) go to a per-thread shelf for their type, and the next new value's decode takes them
//! and refills them in place, as it refills a kept value. A loop that decodes new values and
//! drops them then allocates nothing in the steady state and stays within 1.3x a kept
//! value's time (the goal `codec/bench`'s `new_vs_kept` checks; the figures are in the codec
//! README's Measured table). At most four storages per type are kept per thread, none of
//! over 64 KiB of items; `uper::release_recycled` (with `std`) frees a thread's shelves
//! (they go with the thread otherwise). Only a decode takes them: a list grown or pushed to
//! by other code, and a placeholder, never show another value's former content.
//!
//! Feature `firmware-capacities` selects a second, much smaller capacity profile
//! (`codec/codegen/capacities-firmware.toml`) for microcontrollers; the capacities that differ
//! between the two profiles are the consts of [`msg::capacities`].
//!
//! The size of each message's decoded value, per storage and profile, on a 64-bit host
//! (generated by `codec/tests/value_sizes.rs` from [`msg::message_frame::MESSAGE_NAMES`]):
//!
#![doc = include_str!("../docs/value-sizes.md")]
//!
//! # Features
//! - `alloc`: heap storage (see above). `std`: implies `alloc`.
//! - `firmware-capacities`: the small no-heap capacity profile (see above).
//! - `jer`: JSON encoding rules (X.697) for every generated type, in module `jer` (links std).
//! - `serde`: `Serialize`/`Deserialize` of the runtime's storage types.
//! - `defmt`: `defmt::Format` on the error types.
//! - `crypto`: IEEE 1609.2 signature hashes, ECDSA P-256 verify and sign, ECQV key
//!   reconstruction (`envelope::ieee1609dot2::crypto`).
#![no_std]
#![forbid(unsafe_code)]
#![warn(missing_docs)]

#[cfg(feature = "alloc")]
extern crate alloc;
#[cfg(any(feature = "std", feature = "jer", test))]
extern crate std;

mod decoder;
pub mod envelope;
pub mod frame;
pub mod hex;
#[cfg(feature = "jer")]
pub mod jer;
// The generated types' shared shapes (UPER, JER and random impls of one newtype): above
// both encodings, so neither `uper` nor `jer` imports the other.
mod macros;
pub mod msg;
pub mod uper;

pub use decoder::Decoder;
pub use msg::basic_safety_message::BasicSafetyMessage;
pub use msg::map_data::MapData;
pub use msg::message_frame::{DSRCmsgID, MessageFrame, MessageFrameValue};
pub use msg::spat::SPAT;
pub use msg::traveler_information::TravelerInformation;

/// What the generated types (`msg`) and the crate's macros call and nothing else does: the
/// UPER helpers that decode and encode their parts and, under `jer`, the JER ones. Not part
/// of the API: hidden from the docs, it changes with the generator. The helpers stay public
/// rather than crate-private because the optimiser treats crate-private functions
/// differently before linking: made crate-private, they grew the size probe's flash
/// (`codec/size-probe`) by 1.7 KB.
#[doc(hidden)]
pub mod __private {
    pub use crate::uper::ext::{decode_open, decode_unknown_open, encode_unknown_open};
    pub use crate::uper::sized::{
        decode_bits, decode_ia5_into, decode_octets_into, decode_seq_of_into, encode_bits,
        encode_ia5, encode_octets, encode_seq_of, Size,
    };
    pub use crate::uper::support::{fill_option, max_bits, max_bits_profiled, replace_with};
    #[cfg(feature = "alloc")]
    pub use crate::uper::support::{item_placeholder, ConstPlaceholder};

    /// The JER helpers of the generated `Jer` impls.
    #[cfg(feature = "jer")]
    pub mod jer {
        pub use crate::jer::parts::*;
    }
}
