//! The counter names of every reason (an external contract: the daemon's `/api/status`,
//! the firmware's log, the simulator's scenarios) and the computed index.

use super::*;
use DropGroup::{Datagram, Decode, Envelope, Ingest, Security};

/// Every reason's layer and counter name, in [`DropReason::index`] order.
const NAMES: [(DropGroup, &str); 89] = [
    // Datagram
    (Datagram, "datagram too large"),
    (Datagram, "receive error"),
    (Datagram, "frame too long"),
    (Datagram, "invalid COBS encoding"),
    (Datagram, "frame shorter than its CRC"),
    (Datagram, "CRC mismatch"),
    // Envelope
    (Envelope, "1609.2: unexpected end"),
    (Envelope, "1609.2: unsupported protocol version"),
    (Envelope, "1609.2: invalid choice tag"),
    (Envelope, "1609.2: unknown choice alternative"),
    (Envelope, "1609.2: non-canonical encoding"),
    (Envelope, "1609.2: invalid length"),
    (Envelope, "1609.2: length too large"),
    (Envelope, "1609.2: value out of range"),
    (Envelope, "1609.2: signed payload without data or hash"),
    (Envelope, "1609.2: nesting too deep"),
    (Envelope, "1609.2: trailing bytes"),
    (Envelope, "1609.2: malformed"),
    (Envelope, "1609.2: no plaintext payload"),
    (Envelope, "RSU text: not UTF-8"),
    (Envelope, "RSU text: line is not Key=Value"),
    (Envelope, "RSU text: missing key"),
    (Envelope, "RSU text: duplicate key"),
    (Envelope, "RSU text: invalid value"),
    (Envelope, "RSU text: malformed"),
    (Envelope, "RSU text: payload not hexadecimal"),
    (Envelope, "RSU text: payload too large"),
    (Envelope, "WSMP: truncated"),
    (Envelope, "WSMP: version not 3"),
    (Envelope, "WSMP: subtype or TPID not supported"),
    (Envelope, "WSMP: bad length or PSID encoding"),
    (Envelope, "WSMP: bytes after the WSM data"),
    (Envelope, "WSMP: PSID does not match the message"),
    // Decode
    (Decode, "unexpected end"),
    (Decode, "value out of range"),
    (Decode, "size out of range"),
    (Decode, "capacity exceeded"),
    (Decode, "invalid choice index"),
    (Decode, "invalid enumerated index"),
    (Decode, "invalid character"),
    (Decode, "open type length mismatch"),
    (Decode, "fragmented open type"),
    (Decode, "trailing bytes"),
    (Decode, "length too large"),
    (Decode, "unexpected message"),
    (Decode, "malformed"),
    // Ingest
    (Ingest, "invalid reference position"),
    (Ingest, "unsupported node offset"),
    (Ingest, "region without usable geometry"),
    (Ingest, "reference lane missing"),
    (Ingest, "reference map not stored"),
    (Ingest, "duplicate lane id"),
    (Ingest, "capacity exceeded"),
    (Ingest, "invalid value"),
    (Ingest, "PSM: not a road worker"),
    (Ingest, "PSM: position unavailable"),
    (Ingest, "PSM: accuracy unavailable"),
    (Ingest, "PSM: stale secMark"),
    (Ingest, "PSM: worker store full"),
    (Ingest, "PSM: update not due for verification"),
    (Ingest, "unverified data over verified data"),
    // Security
    (Security, "1609.2: self-signed (no certificate)"),
    (Security, "1609.2: unsupported hash or signature algorithm"),
    (Security, "1609.2: signer certificate unknown (digest)"),
    (Security, "1609.2: chain does not reach a trust anchor"),
    (Security, "1609.2: certificate chain too long"),
    (Security, "1609.2: certificate invalid"),
    (Security, "1609.2: issuer may not certify the PSID"),
    (Security, "1609.2: certificate beyond the capacities"),
    (Security, "1609.2: signer certificate expired"),
    (Security, "1609.2: signer certificate not yet valid"),
    (
        Security,
        "1609.2: PSID not permitted by the signer certificate",
    ),
    (Security, "1609.2: PSID does not match the message"),
    (Security, "1609.2: outside the certificate region"),
    (Security, "1609.2: no location to check the region"),
    (Security, "1609.2: signature does not verify"),
    (Security, "1609.2: no generation time"),
    (Security, "1609.2: no GNSS time to check against"),
    (Security, "1609.2: generation time in the future"),
    (Security, "1609.2: generation time too old"),
    (Security, "1609.2: message expired"),
    (Security, "1609.2: replay"),
    (Security, "1609.2: superseded by a newer version"),
    (Security, "1609.2: no expiry time"),
    (Security, "1609.2: expiry time before generation time"),
    (Security, "1609.2: lifetime longer than allowed"),
    (Security, "1609.2: certificate malformed"),
    (
        Security,
        "1609.2: SSP not permitted by the signer certificate",
    ),
    (Security, "unsigned (signatures required)"),
];

#[test]
fn every_reason_keeps_its_layer_and_counter_name() {
    assert_eq!(DropReason::COUNT, NAMES.len());
    assert_eq!(DropReason::ALL.len(), DropReason::COUNT);
    for (i, (r, (group, name))) in DropReason::ALL.iter().zip(NAMES).enumerate() {
        assert_eq!((r.group(), r.as_str()), (group, name), "reason {i}");
        assert_eq!(std::format!("{r}"), name);
    }
    for (group, name) in NAMES {
        let same = NAMES.iter().filter(|&&o| o == (group, name)).count();
        assert_eq!(same, 1, "{name} named once in its group");
        // Only the decoder's and the ingest's "capacity exceeded" share a name.
        let named = NAMES.iter().filter(|o| o.1 == name).count();
        assert_eq!(
            named,
            if name == "capacity exceeded" { 2 } else { 1 },
            "{name}"
        );
    }
}

#[test]
fn the_index_is_the_position_in_all_for_every_layer() {
    fn check<T: Copy + PartialEq + core::fmt::Debug>(all: &[T], index: fn(T) -> usize) {
        for (i, &r) in all.iter().enumerate() {
            assert_eq!(index(r), i, "{r:?}");
        }
    }
    check(&DropReason::ALL, DropReason::index);
    check(&DatagramReason::ALL, DatagramReason::index);
    check(&EnvelopeReason::ALL, EnvelopeReason::index);
    check(&Ieee1609Reason::ALL, Ieee1609Reason::index);
    check(&RsuTextReason::ALL, RsuTextReason::index);
    check(&WsmpReason::ALL, WsmpReason::index);
    check(&DecodeReason::ALL, DecodeReason::index);
    check(&IngestReason::ALL, IngestReason::index);
    check(&SecurityReason::ALL, SecurityReason::index);
    check(&Rejection::ALL, Rejection::index);
    // A layer's reasons follow the previous layer's.
    let first = |g| DropReason::ALL.iter().position(|r| r.group() == g);
    assert_eq!(first(Envelope), Some(DatagramReason::COUNT));
    assert_eq!(
        first(Security),
        Some(DropReason::COUNT - SecurityReason::COUNT)
    );
}

#[test]
fn a_reason_is_two_bytes() {
    assert_eq!(core::mem::size_of::<DropReason>(), 2);
}

#[test]
fn upstream_errors_wrap_into_their_layer() {
    use j2735::envelope::rsu_text::RsuKey;
    let name = |r: DropReason| r.as_str();
    assert_eq!(name(FrameError::NoRoom.into()), "frame too long");
    assert_eq!(name(FrameError::Crc.into()), "CRC mismatch");
    assert_eq!(
        name(UnwrapError::NoPlaintextPayload.into()),
        "1609.2: no plaintext payload"
    );
    let malformed = EnvelopeError::new(EnvelopeKind::NestingTooDeep, 7);
    assert_eq!(
        name(UnwrapError::Envelope(malformed).into()),
        "1609.2: nesting too deep"
    );
    let missing = RsuTextError {
        kind: RsuTextErrorKind::MissingKey(RsuKey::Payload),
        line: 0,
    };
    assert_eq!(name(missing.into()), "RSU text: missing key");
    assert_eq!(
        name(HexError::BufferTooSmall { needed: 9 }.into()),
        "RSU text: payload too large"
    );
    assert_eq!(
        name(HexError::OddLength.into()),
        "RSU text: payload not hexadecimal"
    );
    assert_eq!(name(WsmpError::Version.into()), "WSMP: version not 3");
    let decode = DecodeError::at(DecodeErrorKind::CapacityExceeded, 3, "Lanes");
    assert_eq!(DropReason::from(decode).group(), DropGroup::Decode);
    assert_eq!(
        name(IngestError::NotDue.into()),
        "PSM: update not due for verification"
    );
    assert_eq!(
        DropReason::from(Rejection::Replay).group(),
        DropGroup::Security
    );
}
