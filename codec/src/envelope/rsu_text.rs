//! RSU 4.1 message text records, as used for immediate forward (UDP port 1516) and
//! store-and-repeat files: one `Key=Value` per line.
//!
//! ```text
//! Version=0.7
//! Type=TIM
//! PSID=0x8003
//! Priority=0
//! TxMode=CONT
//! TxChannel=172
//! TxInterval=0
//! DeliveryStart=
//! DeliveryStop=
//! Signature=False
//! Encryption=False
//! Payload=001F...
//! ```
//!
//! The older `Version=0.5` layout (store-and-repeat "active list" files) has the same keys
//! with blank lines between them. [`RsuMessage::parse`] reads both, and tolerates CRLF line
//! ends, a UTF-8 byte order mark, blank lines, spaces around keys and values, keys in any
//! letter case, and missing optional keys. Keys it does not know (`VehicleID=` and the like)
//! are ignored by the parse; [`fields`] yields every line, unknown keys included.
//!
//! Value conventions: `PSID` is its p-encoded octets in hexadecimal, with or without `0x`
//! (`0x8003` TIM, `0020` BSM);
//! `TxMode` is `CONT` or `ALT`; `TxChannel` is a channel number or `CCH` / `SCH`;
//! `Signature` and `Encryption` are `True` / `False`; an empty value means "not given";
//! `Payload` is the UPER `MessageFrame` in hexadecimal. The writer
//! ([`RsuMessage::write_to`]) always produces the `Version=0.7` layout.
//!
//! # Panics
//!
//! No function in this module panics on any input.

use core::fmt;
use core::str::Split;

use super::psid::Psid;
use crate::hex::{self, HexError};

/// The keys of an RSU message record, in the order the writer emits them.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum RsuKey {
    /// `Version`: format version, `0.7` or `0.5`.
    Version,
    /// `Type`: message type name (`MAP`, `SPAT`, `TIM`, `BSM`, ...).
    Type,
    /// `PSID`: provider service identifier, hexadecimal.
    Psid,
    /// `Priority`: transmit priority.
    Priority,
    /// `TxMode`: `CONT` (continuous) or `ALT` (alternating).
    TxMode,
    /// `TxChannel`: channel number or `CCH` / `SCH`.
    TxChannel,
    /// `TxInterval`: transmit interval.
    TxInterval,
    /// `DeliveryStart`: start of broadcasting (store-and-repeat), free text.
    DeliveryStart,
    /// `DeliveryStop`: end of broadcasting (store-and-repeat), free text.
    DeliveryStop,
    /// `Signature`: whether the RSU should sign the message.
    Signature,
    /// `Encryption`: whether the RSU should encrypt the message.
    Encryption,
    /// `Payload`: the message in hexadecimal.
    Payload,
}

impl RsuKey {
    /// Every key, in the order the writer emits them.
    pub const ALL: [RsuKey; 12] = [
        Self::Version,
        Self::Type,
        Self::Psid,
        Self::Priority,
        Self::TxMode,
        Self::TxChannel,
        Self::TxInterval,
        Self::DeliveryStart,
        Self::DeliveryStop,
        Self::Signature,
        Self::Encryption,
        Self::Payload,
    ];

    /// The key as written in a record.
    #[must_use]
    pub const fn as_str(self) -> &'static str {
        match self {
            Self::Version => "Version",
            Self::Type => "Type",
            Self::Psid => "PSID",
            Self::Priority => "Priority",
            Self::TxMode => "TxMode",
            Self::TxChannel => "TxChannel",
            Self::TxInterval => "TxInterval",
            Self::DeliveryStart => "DeliveryStart",
            Self::DeliveryStop => "DeliveryStop",
            Self::Signature => "Signature",
            Self::Encryption => "Encryption",
            Self::Payload => "Payload",
        }
    }

    /// The key named `name`, compared without regard to ASCII letter case.
    #[must_use]
    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL
            .into_iter()
            .find(|key| key.as_str().eq_ignore_ascii_case(name))
    }

    /// Position of the key in [`Self::ALL`].
    fn index(self) -> usize {
        self as usize
    }
}

impl fmt::Display for RsuKey {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.as_str())
    }
}

/// What is wrong with an RSU message text.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum RsuTextErrorKind {
    /// A non-blank line that is not `Key=Value` (no `=`, or nothing before it).
    NotKeyValue,
    /// A required key (`Version`, `Type`, `PSID`, `Payload`) is absent.
    MissingKey(RsuKey),
    /// A key appears twice.
    DuplicateKey(RsuKey),
    /// A value that the key does not allow (or an empty value for a required key).
    InvalidValue(RsuKey),
}

/// An RSU message text error and the 1-based line where it was found (0: not tied to a line,
/// as for a missing key).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct RsuTextError {
    /// What is wrong.
    pub kind: RsuTextErrorKind,
    /// 1-based line number, or 0.
    pub line: usize,
}

impl fmt::Display for RsuTextError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.kind {
            RsuTextErrorKind::NotKeyValue => f.write_str("line is not Key=Value")?,
            RsuTextErrorKind::MissingKey(key) => write!(f, "missing key {key}")?,
            RsuTextErrorKind::DuplicateKey(key) => write!(f, "duplicate key {key}")?,
            RsuTextErrorKind::InvalidValue(key) => write!(f, "invalid value for {key}")?,
        }
        if self.line > 0 {
            write!(f, " on line {}", self.line)?;
        }
        Ok(())
    }
}

impl core::error::Error for RsuTextError {}

/// Why an [`RsuMessage`] could not be written.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum RsuWriteError {
    /// A value that cannot be written on one line, or an empty type or payload, or a
    /// payload given as invalid hexadecimal text.
    InvalidValue(RsuKey),
    /// The output refused the text.
    Format,
}

impl fmt::Display for RsuWriteError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::InvalidValue(key) => write!(f, "value for {key} cannot be written"),
            Self::Format => f.write_str("output refused the text"),
        }
    }
}

impl core::error::Error for RsuWriteError {}

impl From<fmt::Error> for RsuWriteError {
    fn from(_: fmt::Error) -> Self {
        Self::Format
    }
}

/// One `Key=Value` line, trimmed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct RsuField<'a> {
    /// The text before the first `=`.
    pub key: &'a str,
    /// The text after the first `=` (may be empty).
    pub value: &'a str,
    /// 1-based line number.
    pub line: usize,
}

/// Iterator over the `Key=Value` lines of a record, skipping blank lines.
#[derive(Clone, Debug)]
pub struct RsuFields<'a> {
    lines: Split<'a, char>,
    line: usize,
}

/// The `Key=Value` lines of `text`, known and unknown keys alike.
#[must_use]
pub fn fields(text: &str) -> RsuFields<'_> {
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    RsuFields {
        lines: text.split('\n'),
        line: 0,
    }
}

impl<'a> Iterator for RsuFields<'a> {
    type Item = Result<RsuField<'a>, RsuTextError>;

    fn next(&mut self) -> Option<Self::Item> {
        loop {
            let raw = self.lines.next()?;
            self.line = self.line.saturating_add(1);
            let trimmed = raw.trim();
            if !trimmed.is_empty() {
                return Some(split_field(trimmed, self.line));
            }
        }
    }
}

/// Splits a non-blank trimmed line at its first `=`.
fn split_field(line_text: &str, line: usize) -> Result<RsuField<'_>, RsuTextError> {
    match line_text.split_once('=') {
        Some((key, value)) if !key.trim().is_empty() => Ok(RsuField {
            key: key.trim(),
            value: value.trim(),
            line,
        }),
        _ => Err(RsuTextError {
            kind: RsuTextErrorKind::NotKeyValue,
            line,
        }),
    }
}

/// `TxMode`: how the radio uses its channels.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum TxMode {
    /// `CONT`: continuous on one channel.
    Continuous,
    /// `ALT`: alternating between control and service channel.
    Alternating,
}

impl TxMode {
    /// The value as written in a record.
    #[must_use]
    pub const fn as_str(self) -> &'static str {
        match self {
            Self::Continuous => "CONT",
            Self::Alternating => "ALT",
        }
    }

    fn from_text(text: &str) -> Option<Self> {
        [Self::Continuous, Self::Alternating]
            .into_iter()
            .find(|mode| mode.as_str().eq_ignore_ascii_case(text))
    }
}

/// `TxChannel`: a channel number, or the control / service channel by name.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum TxChannel {
    /// A channel number (172, 178, 180, 183, ...).
    Number(u8),
    /// `CCH`: the control channel.
    Control,
    /// `SCH`: the service channel.
    Service,
}

impl TxChannel {
    fn from_text(text: &str) -> Option<Self> {
        if text.eq_ignore_ascii_case("CCH") {
            Some(Self::Control)
        } else if text.eq_ignore_ascii_case("SCH") {
            Some(Self::Service)
        } else {
            text.parse().ok().map(Self::Number)
        }
    }
}

impl fmt::Display for TxChannel {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Number(number) => write!(f, "{number}"),
            Self::Control => f.write_str("CCH"),
            Self::Service => f.write_str("SCH"),
        }
    }
}

/// The message bytes of a record: hexadecimal text as read, or bytes to be written.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RsuPayload<'a> {
    /// Hexadecimal text (what [`RsuMessage::parse`] produces; checked to be valid there).
    Hex(&'a str),
    /// Raw bytes (written as upper-case hexadecimal).
    Bytes(&'a [u8]),
}

impl RsuPayload<'_> {
    /// Number of message bytes.
    ///
    /// # Errors
    ///
    /// For [`RsuPayload::Hex`], when the text is not hexadecimal.
    pub fn decoded_len(&self) -> Result<usize, HexError> {
        match self {
            Self::Hex(text) => hex::decoded_len(text),
            Self::Bytes(bytes) => Ok(bytes.len()),
        }
    }

    /// Writes the message bytes to the start of `out`; returns how many were written.
    ///
    /// # Errors
    ///
    /// When the text is not hexadecimal, or `out` is too small (then nothing is written).
    pub fn decode_into(&self, out: &mut [u8]) -> Result<usize, HexError> {
        match self {
            Self::Hex(text) => hex::decode_into(text, out),
            Self::Bytes(bytes) => {
                let needed = bytes.len();
                let target = out
                    .get_mut(..needed)
                    .ok_or(HexError::BufferTooSmall { needed })?;
                target.copy_from_slice(bytes);
                Ok(needed)
            }
        }
    }

    /// Whether the payload holds no byte.
    fn is_empty(&self) -> bool {
        match self {
            Self::Hex(text) => text.is_empty(),
            Self::Bytes(bytes) => bytes.is_empty(),
        }
    }

    /// Writes the payload as hexadecimal text.
    fn write_hex<W: fmt::Write + ?Sized>(&self, out: &mut W) -> fmt::Result {
        match self {
            Self::Hex(text) => out.write_str(text),
            Self::Bytes(bytes) => hex::write_upper(bytes, out),
        }
    }
}

/// One RSU message record (immediate forward or store-and-repeat), borrowing its text.
///
/// `None` means the key was absent or its value empty.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct RsuMessage<'a> {
    /// `Version` as read (`0.7`, `0.5`); the writer always writes `0.7`.
    pub version: &'a str,
    /// `Type`: `MAP`, `SPAT`, `TIM`, `BSM`, ...
    pub message_type: &'a str,
    /// `PSID`. The record writes its p-encoded octets in hexadecimal (`0x8003` for TIM,
    /// `0xE0000017` for MAP, `0x20` for BSM); the field holds the PSID itself ([`Psid`]).
    pub psid: Psid,
    /// `Priority`.
    pub priority: Option<u8>,
    /// `TxMode`.
    pub tx_mode: Option<TxMode>,
    /// `TxChannel`.
    pub tx_channel: Option<TxChannel>,
    /// `TxInterval`.
    pub tx_interval: Option<u32>,
    /// `DeliveryStart`, as written (e.g. `01/31/2024, 06:00`).
    pub delivery_start: Option<&'a str>,
    /// `DeliveryStop`, as written.
    pub delivery_stop: Option<&'a str>,
    /// `Signature`: ask the RSU to sign.
    pub signature: Option<bool>,
    /// `Encryption`: ask the RSU to encrypt.
    pub encryption: Option<bool>,
    /// `Payload`.
    pub payload: RsuPayload<'a>,
}

/// The value of one key and the line it was on.
#[derive(Clone, Copy, Debug)]
struct RawValue<'a> {
    text: &'a str,
    line: usize,
}

/// The values of the known keys of one record, indexed by [`RsuKey::index`].
#[derive(Debug, Default)]
struct RawValues<'a> {
    values: [Option<RawValue<'a>>; 12],
}

impl<'a> RawValues<'a> {
    /// Collects the known keys of `text`.
    fn collect(text: &'a str) -> Result<Self, RsuTextError> {
        let mut collected = Self::default();
        for field in fields(text) {
            let field = field?;
            if let Some(key) = RsuKey::from_name(field.key) {
                collected.insert(key, field)?;
            }
        }
        Ok(collected)
    }

    fn insert(&mut self, key: RsuKey, field: RsuField<'a>) -> Result<(), RsuTextError> {
        let slot = self.values.get_mut(key.index()).ok_or(RsuTextError {
            kind: RsuTextErrorKind::InvalidValue(key),
            line: field.line,
        })?;
        if slot.is_some() {
            return Err(RsuTextError {
                kind: RsuTextErrorKind::DuplicateKey(key),
                line: field.line,
            });
        }
        *slot = Some(RawValue {
            text: field.value,
            line: field.line,
        });
        Ok(())
    }

    /// The non-empty value of `key`, converted by `convert`; absent or empty gives `None`.
    fn optional<T>(
        &self,
        key: RsuKey,
        convert: impl FnOnce(&'a str) -> Option<T>,
    ) -> Result<Option<T>, RsuTextError> {
        match self.values.get(key.index()).copied().flatten() {
            Some(raw) if !raw.text.is_empty() => convert(raw.text).map(Some).ok_or(RsuTextError {
                kind: RsuTextErrorKind::InvalidValue(key),
                line: raw.line,
            }),
            _ => Ok(None),
        }
    }

    /// The value of a required `key`, converted by `convert`.
    fn required<T>(
        &self,
        key: RsuKey,
        convert: impl FnOnce(&'a str) -> Option<T>,
    ) -> Result<T, RsuTextError> {
        let raw = self
            .values
            .get(key.index())
            .copied()
            .flatten()
            .ok_or(RsuTextError {
                kind: RsuTextErrorKind::MissingKey(key),
                line: 0,
            })?;
        let invalid = RsuTextError {
            kind: RsuTextErrorKind::InvalidValue(key),
            line: raw.line,
        };
        self.optional(key, convert)?.ok_or(invalid)
    }
}

impl<'a> RsuMessage<'a> {
    /// A record with the required fields and every optional one absent (`Version` 0.7).
    #[must_use]
    pub fn new(message_type: &'a str, psid: Psid, payload: RsuPayload<'a>) -> Self {
        Self {
            version: "0.7",
            message_type,
            psid,
            priority: None,
            tx_mode: None,
            tx_channel: None,
            tx_interval: None,
            delivery_start: None,
            delivery_stop: None,
            signature: None,
            encryption: None,
            payload,
        }
    }

    /// Reads one record (`Version=0.7` or the blank-line `Version=0.5` layout).
    ///
    /// `Version`, `Type`, `PSID` and `Payload` are required; the payload must be non-empty,
    /// valid hexadecimal text. Unknown keys are ignored.
    ///
    /// # Errors
    ///
    /// An [`RsuTextError`] with the offending key and line: a line that is not `Key=Value`,
    /// a missing required key, a repeated key, or a value the key does not allow.
    pub fn parse(text: &'a str) -> Result<Self, RsuTextError> {
        let raw = RawValues::collect(text)?;
        Ok(Self {
            version: raw.required(RsuKey::Version, Some)?,
            message_type: raw.required(RsuKey::Type, Some)?,
            psid: raw.required(RsuKey::Psid, parse_psid)?,
            priority: raw.optional(RsuKey::Priority, |text| text.parse().ok())?,
            tx_mode: raw.optional(RsuKey::TxMode, TxMode::from_text)?,
            tx_channel: raw.optional(RsuKey::TxChannel, TxChannel::from_text)?,
            tx_interval: raw.optional(RsuKey::TxInterval, |text| text.parse().ok())?,
            delivery_start: raw.optional(RsuKey::DeliveryStart, Some)?,
            delivery_stop: raw.optional(RsuKey::DeliveryStop, Some)?,
            signature: raw.optional(RsuKey::Signature, parse_bool)?,
            encryption: raw.optional(RsuKey::Encryption, parse_bool)?,
            payload: raw.required(RsuKey::Payload, parse_payload)?,
        })
    }

    /// Writes the record in the `Version=0.7` layout, one `Key=Value` per line ending in
    /// `\n`, absent values as empty values, `PSID` as `0x` and upper-case hexadecimal.
    ///
    /// # Errors
    ///
    /// [`RsuWriteError::InvalidValue`] (before anything is written) for a value that would
    /// not read back unchanged: a line break or surrounding spaces in a text value, an empty
    /// `Type`, an empty or non-hexadecimal payload. [`RsuWriteError::Format`] when `out`
    /// refuses the text.
    pub fn write_to<W: fmt::Write + ?Sized>(&self, out: &mut W) -> Result<(), RsuWriteError> {
        self.check_writable()?;
        writeln!(out, "Version=0.7")?;
        writeln!(out, "Type={}", self.message_type)?;
        let octets = self.psid.p_encoded_value();
        writeln!(out, "PSID=0x{:X}", octets.unwrap_or_default())?;
        write_line(out, RsuKey::Priority, self.priority)?;
        write_line(out, RsuKey::TxMode, self.tx_mode.map(TxMode::as_str))?;
        write_line(out, RsuKey::TxChannel, self.tx_channel)?;
        write_line(out, RsuKey::TxInterval, self.tx_interval)?;
        write_line(out, RsuKey::DeliveryStart, self.delivery_start)?;
        write_line(out, RsuKey::DeliveryStop, self.delivery_stop)?;
        write_line(out, RsuKey::Signature, self.signature.map(bool_text))?;
        write_line(out, RsuKey::Encryption, self.encryption.map(bool_text))?;
        out.write_str("Payload=")?;
        self.payload.write_hex(out)?;
        out.write_char('\n')?;
        Ok(())
    }

    /// Checks that every value can be written and read back unchanged.
    fn check_writable(&self) -> Result<(), RsuWriteError> {
        let single_line = |text: &str| !text.contains(['\n', '\r']) && text.trim() == text;
        let texts = [
            (RsuKey::Type, Some(self.message_type)),
            (RsuKey::DeliveryStart, self.delivery_start),
            (RsuKey::DeliveryStop, self.delivery_stop),
        ];
        for (key, text) in texts {
            if text.is_some_and(|text| !single_line(text)) {
                return Err(RsuWriteError::InvalidValue(key));
            }
        }
        if self.message_type.is_empty() {
            return Err(RsuWriteError::InvalidValue(RsuKey::Type));
        }
        if self.psid.p_encoded_value().is_none() {
            return Err(RsuWriteError::InvalidValue(RsuKey::Psid));
        }
        let payload_ok = !self.payload.is_empty() && self.payload.decoded_len().is_ok();
        if payload_ok {
            Ok(())
        } else {
            Err(RsuWriteError::InvalidValue(RsuKey::Payload))
        }
    }
}

/// Writes `Key=value` (or `Key=` when absent) and a line end.
fn write_line<W: fmt::Write + ?Sized, T: fmt::Display>(
    out: &mut W,
    key: RsuKey,
    value: Option<T>,
) -> fmt::Result {
    match value {
        Some(value) => writeln!(out, "{key}={value}"),
        None => writeln!(out, "{key}="),
    }
}

/// `True` / `False`, as RSU records spell them.
fn bool_text(value: bool) -> &'static str {
    if value {
        "True"
    } else {
        "False"
    }
}

/// A PSID written as its p-encoded octets in hexadecimal, with or without `0x`, one to eight
/// digits, as RSU records, NTCIP 1218 tables and command lines write it: `0x8003` is TIM
/// (131), `0020` BSM (32). `None` for text that is not hexadecimal or a number that is no
/// p-encoding (`0x83`).
pub fn parse_psid(text: &str) -> Option<Psid> {
    parse_hex_u32(text).and_then(Psid::from_p_encoded_value)
}

/// One to eight hexadecimal digits, with or without `0x`.
fn parse_hex_u32(text: &str) -> Option<u32> {
    let digits = text
        .strip_prefix("0x")
        .or_else(|| text.strip_prefix("0X"))
        .unwrap_or(text);
    let valid = (1..=8).contains(&digits.len()) && digits.bytes().all(|b| b.is_ascii_hexdigit());
    valid
        .then(|| u32::from_str_radix(digits, 16).ok())
        .flatten()
}

/// `True` / `False` in any letter case.
fn parse_bool(text: &str) -> Option<bool> {
    if text.eq_ignore_ascii_case("true") {
        Some(true)
    } else if text.eq_ignore_ascii_case("false") {
        Some(false)
    } else {
        None
    }
}

/// A payload: valid, non-empty hexadecimal text.
fn parse_payload(text: &str) -> Option<RsuPayload<'_>> {
    match hex::decoded_len(text) {
        Ok(len) if len > 0 => Some(RsuPayload::Hex(text)),
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    extern crate std;

    use super::*;
    use std::string::String;
    use std::vec::Vec;

    /// A made-up record in the 0.7 layout (the payload is not a real J2735 message).
    const RECORD_07: &str = "Version=0.7\nType=TIM\nPSID=0x8003\nPriority=5\nTxMode=CONT\n\
        TxChannel=172\nTxInterval=0\nDeliveryStart=\nDeliveryStop=\nSignature=False\n\
        Encryption=False\nPayload=001F0A0B0C\n";

    fn parse_error(text: &str) -> RsuTextError {
        RsuMessage::parse(text).unwrap_err()
    }

    #[test]
    fn parses_the_07_layout() {
        let message = RsuMessage::parse(RECORD_07).unwrap();
        assert_eq!(message.version, "0.7");
        assert_eq!(message.message_type, "TIM");
        assert_eq!(message.psid, Psid::TIM);
        assert_eq!(message.priority, Some(5));
        assert_eq!(message.tx_mode, Some(TxMode::Continuous));
        assert_eq!(message.tx_channel, Some(TxChannel::Number(172)));
        assert_eq!(message.tx_interval, Some(0));
        assert_eq!(message.delivery_start, None);
        assert_eq!(message.delivery_stop, None);
        assert_eq!(message.signature, Some(false));
        assert_eq!(message.encryption, Some(false));
        assert_eq!(message.payload, RsuPayload::Hex("001F0A0B0C"));
        let mut out = [0u8; 8];
        assert_eq!(message.payload.decode_into(&mut out), Ok(5));
        assert_eq!(&out[..5], &[0x00, 0x1f, 0x0a, 0x0b, 0x0c]);
    }

    #[test]
    fn parses_the_05_layout_with_crlf_and_blank_lines() {
        let text = "\u{feff}Version=0.5\r\n\r\nType=MAP\r\n\r\nPSID=0x8002\r\n\r\n\
            Priority=7\r\n\r\nTxMode=ALT\r\n\r\nTxChannel=CCH\r\n\r\nTxInterval=\r\n\r\n\
            DeliveryStart=01/31/2024, 06:00\r\n\r\nDeliveryStop=\r\n\r\nSignature=True\r\n\r\n\
            Encryption=False\r\n\r\nPayload=0012aabb\r\n";
        let message = RsuMessage::parse(text).unwrap();
        assert_eq!(message.version, "0.5");
        assert_eq!(message.psid, Psid::SPAT);
        assert_eq!(message.tx_mode, Some(TxMode::Alternating));
        assert_eq!(message.tx_channel, Some(TxChannel::Control));
        assert_eq!(message.tx_interval, None);
        assert_eq!(message.delivery_start, Some("01/31/2024, 06:00"));
        assert_eq!(message.signature, Some(true));
        assert_eq!(message.payload.decoded_len(), Ok(4));
    }

    #[test]
    fn tolerates_spaces_case_unknown_and_missing_keys() {
        let text = "  version = 0.7 \n TYPE=BSM\n psid = 0020 \n VehicleID=42\n\
            payload = 00140102\n";
        let message = RsuMessage::parse(text).unwrap();
        assert_eq!(message.message_type, "BSM");
        assert_eq!(message.psid, Psid::BSM);
        assert_eq!(message.priority, None);
        assert_eq!(message.tx_mode, None);
        assert_eq!(message.signature, None);
        let keys: Vec<&str> = fields(text).map(|field| field.unwrap().key).collect();
        assert_eq!(keys, ["version", "TYPE", "psid", "VehicleID", "payload"]);
    }

    #[test]
    fn psid_forms() {
        assert_eq!(parse_psid("0x8003"), Some(Psid::TIM));
        assert_eq!(parse_psid("0XE0000017"), Some(Psid::MAP));
        assert_eq!(parse_psid("20"), Some(Psid::BSM));
        assert_eq!(parse_psid("0x0027"), Some(Psid::PSM));
        // The integer 131 written in hexadecimal is no p-encoding: refused, not misread.
        assert_eq!(parse_psid("0x83"), None);
        assert_eq!(parse_psid("0x"), None);
        assert_eq!(parse_psid("0x123456789"), None);
        assert_eq!(parse_psid("+20"), None);
    }

    #[test]
    fn missing_required_keys_are_reported() {
        let without_psid = RECORD_07.replace("PSID=0x8003\n", "");
        assert_eq!(
            parse_error(&without_psid).kind,
            RsuTextErrorKind::MissingKey(RsuKey::Psid)
        );
        let empty_payload = RECORD_07.replace("Payload=001F0A0B0C", "Payload=");
        let error = parse_error(&empty_payload);
        assert_eq!(error.kind, RsuTextErrorKind::InvalidValue(RsuKey::Payload));
        assert_eq!(error.line, 12);
    }

    #[test]
    fn invalid_values_name_key_and_line() {
        let cases = [
            ("TxMode=CONT", "TxMode=SOMETIMES", RsuKey::TxMode, 5),
            ("Priority=5", "Priority=300", RsuKey::Priority, 4),
            ("Signature=False", "Signature=maybe", RsuKey::Signature, 10),
            ("TxChannel=172", "TxChannel=ABC", RsuKey::TxChannel, 6),
            (
                "Payload=001F0A0B0C",
                "Payload=001F0A0B0",
                RsuKey::Payload,
                12,
            ),
            (
                "Payload=001F0A0B0C",
                "Payload=001F0A0B0X",
                RsuKey::Payload,
                12,
            ),
        ];
        for (from, to, key, line) in cases {
            let error = parse_error(&RECORD_07.replace(from, to));
            assert_eq!(
                error,
                RsuTextError {
                    kind: RsuTextErrorKind::InvalidValue(key),
                    line
                }
            );
        }
    }

    #[test]
    fn duplicate_keys_and_garbage_lines_are_rejected() {
        let duplicate = std::format!("{RECORD_07}psid=0x20\n");
        assert_eq!(
            parse_error(&duplicate),
            RsuTextError {
                kind: RsuTextErrorKind::DuplicateKey(RsuKey::Psid),
                line: 13
            }
        );
        let garbage = RECORD_07.replace("TxInterval=0", "TxInterval");
        assert_eq!(
            parse_error(&garbage),
            RsuTextError {
                kind: RsuTextErrorKind::NotKeyValue,
                line: 7
            }
        );
        assert_eq!(parse_error("=5\n").kind, RsuTextErrorKind::NotKeyValue);
        assert_eq!(
            parse_error("").kind,
            RsuTextErrorKind::MissingKey(RsuKey::Version)
        );
    }

    #[test]
    fn writes_the_07_layout() {
        let payload = [0x00, 0x1f, 0x0a, 0x0b, 0x0c];
        let mut message = RsuMessage::new("TIM", Psid::TIM, RsuPayload::Bytes(&payload));
        message.priority = Some(5);
        message.tx_mode = Some(TxMode::Continuous);
        message.tx_channel = Some(TxChannel::Number(172));
        message.tx_interval = Some(0);
        message.signature = Some(false);
        message.encryption = Some(false);
        let mut text = String::new();
        message.write_to(&mut text).unwrap();
        assert_eq!(text, RECORD_07);
    }

    #[test]
    fn write_then_parse_round_trips() {
        let payload = [0x00, 0x12, 0x81, 0xff];
        let mut message = RsuMessage::new("MAP", Psid::MAP, RsuPayload::Bytes(&payload));
        message.tx_mode = Some(TxMode::Alternating);
        message.tx_channel = Some(TxChannel::Service);
        message.delivery_start = Some("01/31/2024, 06:00");
        message.signature = Some(true);
        let mut text = String::new();
        message.write_to(&mut text).unwrap();
        let parsed = RsuMessage::parse(&text).unwrap();
        let mut decoded = [0u8; 4];
        assert_eq!(parsed.payload.decode_into(&mut decoded), Ok(4));
        assert_eq!(decoded, payload);
        assert_eq!(
            RsuMessage {
                payload: message.payload,
                ..parsed
            },
            message
        );

        let reparsed = RsuMessage::parse(RECORD_07).unwrap();
        let mut again = String::new();
        reparsed.write_to(&mut again).unwrap();
        assert_eq!(RsuMessage::parse(&again).unwrap(), reparsed);
    }

    #[test]
    fn unwritable_values_are_refused() {
        let payload = [0x00];
        let mut message = RsuMessage::new("TIM\nPSID=1", Psid::TIM, RsuPayload::Bytes(&payload));
        let mut text = String::new();
        assert_eq!(
            message.write_to(&mut text),
            Err(RsuWriteError::InvalidValue(RsuKey::Type))
        );
        message.message_type = "TIM";
        message.payload = RsuPayload::Hex("0g");
        assert_eq!(
            message.write_to(&mut text),
            Err(RsuWriteError::InvalidValue(RsuKey::Payload))
        );
        message.payload = RsuPayload::Bytes(&[]);
        assert_eq!(
            message.write_to(&mut text),
            Err(RsuWriteError::InvalidValue(RsuKey::Payload))
        );
    }

    #[test]
    fn payload_decode_reports_small_buffer() {
        let mut out = [0u8; 2];
        assert_eq!(
            RsuPayload::Bytes(&[1, 2, 3]).decode_into(&mut out),
            Err(HexError::BufferTooSmall { needed: 3 })
        );
    }

    #[test]
    fn error_display() {
        let error = RsuTextError {
            kind: RsuTextErrorKind::InvalidValue(RsuKey::Psid),
            line: 3,
        };
        assert_eq!(std::format!("{error}"), "invalid value for PSID on line 3");
        let error = RsuTextError {
            kind: RsuTextErrorKind::MissingKey(RsuKey::Payload),
            line: 0,
        };
        assert_eq!(std::format!("{error}"), "missing key Payload");
    }

    #[test]
    fn arbitrary_text_never_panics() {
        let mut state: u64 = 0x2545_f491_4f6c_dd1d;
        let alphabet = b"=\r\n \t0x8aFPSIDVersionTypePayload\xc3\xa9";
        for _ in 0..5_000 {
            let mut bytes = Vec::new();
            for _ in 0..(state % 64) {
                state ^= state << 13;
                state ^= state >> 7;
                state ^= state << 17;
                bytes.push(alphabet[usize::from(state.to_le_bytes()[0]) % alphabet.len()]);
            }
            state = state.wrapping_add(1);
            let text = String::from_utf8_lossy(&bytes);
            let _ = RsuMessage::parse(&text);
            let _ = fields(&text).count();
        }
    }
}
