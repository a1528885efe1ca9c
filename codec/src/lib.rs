//! SAE J2735 (2020) in Rust: every message type, generated from the standard's type model,
//! with a UPER codec that needs no heap and reproduces real traffic byte for byte.
//!
//! - [`uper`]: the runtime (bit reader/writer, [`uper::Uper`] trait, [`uper::decode`],
//!   [`uper::encode`]).
//! - [`hex`]: hexadecimal text to bytes and back (no allocation).
//! - The generated types, one module per ASN.1 module ([`message_frame`], [`map_data`],
//!   [`traveler_information`], [`common`], ...), with the most used ones re-exported here.
//!
//! # Storage
//! Without features nothing allocates: SEQUENCE OF and strings are bounded by capacities set
//! per type in `codec/codegen/capacities.toml` (a value over a capacity is a
//! [`uper::DecodeErrorKind::CapacityExceeded`] error that names the capacity). Feature
//! `alloc` switches them to `Vec`/`String`, bounded only by the ASN.1 SIZE constraints.
//! Feature `firmware-capacities` selects a second, much smaller capacity profile
//! (`codec/codegen/capacities-firmware.toml`) for microcontrollers; the capacities that differ
//! between the two profiles are the consts of [`capacities`].
//!
//! # Features
//! - `alloc`: heap storage (see above). `std`: implies `alloc`.
//! - `firmware-capacities`: the small no-heap capacity profile (see above).
//! - `jer`: JSON encoding rules (X.697) for every generated type, in module `jer` (links std).
//! - `serde`: `Serialize`/`Deserialize` of the runtime's storage types.
//! - `defmt`: `defmt::Format` on the error types.
#![no_std]
#![forbid(unsafe_code)]
#![warn(missing_docs)]

#[cfg(feature = "alloc")]
extern crate alloc;
#[cfg(any(feature = "std", feature = "jer", test))]
extern crate std;

pub mod envelope;
pub mod frame;
pub mod hex;
#[cfg(feature = "jer")]
pub mod jer;
pub mod uper;

// The generated types' shared shapes (UPER, JER and random impls of one newtype): above
// both encodings, so neither `uper` nor `jer` imports the other.
mod generated;
mod macros;
pub use generated::*;
