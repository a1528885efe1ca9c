//! Target `envelope`: IEEE 1609.2 (COER) envelopes, `unwrap_message_frame`, and RSU 4.1 text
//! records. Small values only, so it runs on libFuzzer's thread.
//!
//! Invariants, for every input:
//! 1. `unwrap_message_frame`: a bare input is returned whole (and does not look like
//!    1609.2); a found frame is the slice of the input at its offset and is the application
//!    data of `Ieee1609Dot2Data::parse` of the input; an error only for inputs that look like
//!    1609.2 data, and `NoPlaintextPayload` only for well-formed data without plaintext.
//! 2. `Ieee1609Dot2Data::parse`: on success `encoded()` is the whole input;
//!    `parse_prefix` of the input with bytes appended gives the same data and the input's
//!    length; the application data and every nested layer are slices of the input at their
//!    offsets, and every nested layer parses again (as documented); `to_be_signed` is a slice
//!    of the input. Unsecured data re-encoded by `encode_unsecured` is the input itself
//!    (the parse accepts canonical COER only) and parses to the same payload.
//! 3. `encode_unsecured` of the input as payload parses back to that payload, at offset
//!    `unsecured_encoded_len(len) - len`.
//! 4. `RsuMessage::parse` of the input as text: on success the payload is valid hex of at
//!    least one octet; `write_to` succeeds unless a text value holds a carriage return; the
//!    written record parses to the same record (version `0.7`); the same record with the
//!    payload as bytes writes the same text.
//! 5. `Wsm::parse` (IEEE 1609.3 WSMP): on success the data is the input's tail, and writing
//!    the PSID and the N-header's fields around the data with `wsmp::encode` gives a message
//!    that parses to the same WSM; `encode` of the input as data parses back to it.

use j2735::envelope::ieee1609dot2::{
    encode_unsecured, looks_like_ieee1609dot2, unsecured_encoded_len, Content, Ieee1609Dot2Data,
};
use j2735::envelope::rsu_text::{RsuKey, RsuMessage, RsuPayload, RsuWriteError};
use j2735::envelope::wsmp::{self, Wsm, WsmpInfo};
use j2735::envelope::{unwrap_message_frame, EnvelopeKind, Psid, UnwrapError};

use crate::hex;

/// Runs every check of this target on `data`.
pub fn check(data: &[u8]) {
    check_unwrap(data);
    check_ieee1609dot2(data);
    check_encode_unsecured(data);
    if let Ok(text) = std::str::from_utf8(data) {
        check_rsu_text(text);
    }
    check_wsmp(data);
}

/// Invariant 5.
fn check_wsmp(data: &[u8]) {
    let mut out = vec![0u8; data.len() + 32];
    if let Ok(wsm) = Wsm::parse(data) {
        assert!(
            data.ends_with(wsm.data) && offset_in(data, wsm.data).is_some(),
            "wsmp: data is not the input's tail; input {}",
            hex(data)
        );
        let n = wsmp::encode(wsm.psid, &wsm.info, wsm.data, &mut out)
            .unwrap_or_else(|| panic!("wsmp: a parsed WSM does not write; input {}", hex(data)));
        let again = Wsm::parse(&out[..n]);
        assert_eq!(
            again,
            Ok(wsm),
            "wsmp: written WSM differs; input {}",
            hex(data)
        );
    }
    if let Some(n) = wsmp::encode(Psid::TIM, &WsmpInfo::default(), data, &mut out) {
        let wsm = Wsm::parse(&out[..n]).expect("wsmp: an encoded WSM parses");
        assert!(
            wsm.data == data && wsm.psid == Psid::TIM,
            "wsmp: round trip; input {}",
            hex(data)
        );
    }
}

/// Where `part` lies in `whole`, when it is a slice of it.
fn offset_in(whole: &[u8], part: &[u8]) -> Option<usize> {
    let start = (part.as_ptr() as usize).checked_sub(whole.as_ptr() as usize)?;
    (start + part.len() <= whole.len()).then_some(start)
}

/// Invariant 1.
fn check_unwrap(data: &[u8]) {
    let looks = looks_like_ieee1609dot2(data);
    let parsed = Ieee1609Dot2Data::parse(data);
    match unwrap_message_frame(data) {
        Ok(u) => {
            let at = u.offset;
            assert!(
                data.get(at..at + u.frame.len()) == Some(u.frame)
                    && offset_in(data, u.frame) == Some(at),
                "unwrap: frame is not the input slice at its offset {at}; input {}",
                hex(data)
            );
            if u.envelope == EnvelopeKind::Bare {
                assert!(
                    !looks && at == 0 && u.frame.len() == data.len(),
                    "unwrap: bare frame is not the whole input; input {}",
                    hex(data)
                );
            } else {
                let d = parsed.unwrap_or_else(|e| {
                    panic!(
                        "unwrap found a frame, parse fails: {e}; input {}",
                        hex(data)
                    )
                });
                assert!(
                    looks
                        && d.application_data() == Some(u.frame)
                        && d.application_data_offset() == Some(at)
                        && d.is_signed() == (u.envelope == EnvelopeKind::Signed),
                    "unwrap disagrees with parse: {u:?} vs {d:?}; input {}",
                    hex(data)
                );
            }
        }
        Err(UnwrapError::Envelope(e)) => assert!(
            looks && parsed == Err(e),
            "unwrap error {e} but parse gives {parsed:?}; input {}",
            hex(data)
        ),
        Err(UnwrapError::NoPlaintextPayload) => {
            let d = parsed.unwrap_or_else(|e| {
                panic!(
                    "unwrap: no plaintext, but parse fails: {e}; input {}",
                    hex(data)
                )
            });
            assert!(
                looks && d.application_data().is_none(),
                "unwrap: no plaintext, but parse finds some; input {}",
                hex(data)
            );
        }
    }
}

/// Invariant 2.
fn check_ieee1609dot2(data: &[u8]) {
    let Ok(d) = Ieee1609Dot2Data::parse(data) else {
        return;
    };
    assert!(
        d.encoded() == data,
        "parse: encoded() is not the whole input; input {}",
        hex(data)
    );
    let mut longer = Vec::with_capacity(data.len() + 3);
    longer.extend_from_slice(data);
    longer.extend_from_slice(&[0x03, 0x80, 0x00]);
    match Ieee1609Dot2Data::parse_prefix(&longer) {
        Ok((p, used)) => assert!(
            used == data.len() && p.encoded() == data && p.content() == d.content(),
            "parse_prefix with appended bytes: used {used} of {}; input {}",
            data.len(),
            hex(data)
        ),
        Err(e) => panic!(
            "parse_prefix fails ({e}) with bytes appended to a valid input {}",
            hex(data)
        ),
    }
    check_layers(data, &d, 0);
    if let Content::Unsecured(payload) = d.content() {
        let mut out = vec![0u8; unsecured_encoded_len(payload.len())];
        let n = encode_unsecured(payload, &mut out)
            .unwrap_or_else(|e| panic!("encode_unsecured fails: {e}; input {}", hex(data)));
        assert!(
            out[..n] == *data,
            "encode_unsecured of the parsed payload is not the input; input {}, re-encoded {}",
            hex(data),
            hex(&out[..n])
        );
    }
}

/// Checks the application data and the nested layers of `d` (parsed from `data`).
fn check_layers(data: &[u8], d: &Ieee1609Dot2Data<'_>, depth: usize) {
    assert!(
        depth < 8,
        "more layers than the nesting limit; input {}",
        hex(data)
    );
    if let (Some(app), Some(at)) = (d.application_data(), d.application_data_offset()) {
        assert!(
            data.get(at..at + app.len()) == Some(app),
            "application data is not the input slice at its offset {at}; input {}",
            hex(data)
        );
    } else {
        assert!(
            d.application_data().is_none() && d.application_data_offset().is_none(),
            "application data without offset or offset without data; input {}",
            hex(data)
        );
    }
    assert!(
        offset_in(data, d.encoded()).is_some(),
        "encoded() of a layer is not a slice of the input; input {}",
        hex(data)
    );
    assert_eq!(d.is_signed(), d.signed_data().is_some());
    match d.content() {
        Content::Unsecured(payload) => assert!(
            d.application_data() == Some(*payload),
            "unsecured payload is not the application data; input {}",
            hex(data)
        ),
        Content::Signed(signed) => {
            assert!(
                offset_in(data, signed.to_be_signed).is_some(),
                "to_be_signed is not a slice of the input; input {}",
                hex(data)
            );
            match &signed.payload.data {
                Some(nested) => {
                    let at = nested.offset();
                    assert!(
                        data.get(at..at + nested.encoded().len()) == Some(nested.encoded()),
                        "nested data is not the input slice at its offset {at}; input {}",
                        hex(data)
                    );
                    let inner = nested.parse().unwrap_or_else(|e| {
                        panic!(
                            "nested data of a successful parse does not parse: {e}; input {}",
                            hex(data)
                        )
                    });
                    assert!(
                        inner.encoded() == nested.encoded()
                            && inner.application_data() == d.application_data()
                            && inner.application_data_offset() == d.application_data_offset(),
                        "nested layer disagrees with the outer one; input {}",
                        hex(data)
                    );
                    check_layers(data, &inner, depth + 1);
                }
                None => assert!(
                    d.application_data().is_none(),
                    "signed data without inner data has application data; input {}",
                    hex(data)
                ),
            }
        }
        _ => assert!(
            d.application_data().is_none(),
            "encrypted data or a request has application data; input {}",
            hex(data)
        ),
    }
}

/// Invariant 3.
fn check_encode_unsecured(payload: &[u8]) {
    let len = unsecured_encoded_len(payload.len());
    let mut out = vec![0u8; len + 2];
    if len > 0 {
        assert!(
            encode_unsecured(payload, &mut out[..len - 1]).is_err(),
            "encode_unsecured into a buffer one byte short succeeds"
        );
    }
    let n = encode_unsecured(payload, &mut out).expect("encode_unsecured with room");
    assert_eq!(n, len, "encode_unsecured wrote {n} bytes, expected {len}");
    let d = Ieee1609Dot2Data::parse(&out[..n]).unwrap_or_else(|e| {
        panic!(
            "encode_unsecured output does not parse: {e}; payload {}",
            hex(payload)
        )
    });
    assert!(
        d.content() == &Content::Unsecured(payload)
            && d.application_data_offset() == Some(len - payload.len()),
        "encode_unsecured output parses to {d:?}; payload {}",
        hex(payload)
    );
}

/// Invariant 4.
fn check_rsu_text(text: &str) {
    let Ok(m) = RsuMessage::parse(text) else {
        return;
    };
    let len = m
        .payload
        .decoded_len()
        .unwrap_or_else(|e| panic!("parsed RSU payload is not hex: {e}; input {text:?}"));
    assert!(len > 0, "parsed RSU payload is empty; input {text:?}");
    let mut bytes = vec![0u8; len];
    assert_eq!(m.payload.decode_into(&mut bytes), Ok(len));
    let mut written = String::new();
    match m.write_to(&mut written) {
        Ok(()) => {}
        Err(RsuWriteError::InvalidValue(key)) => {
            let value = match key {
                RsuKey::Type => Some(m.message_type),
                RsuKey::DeliveryStart => m.delivery_start,
                RsuKey::DeliveryStop => m.delivery_stop,
                _ => None,
            };
            assert!(
                value.is_some_and(|v| v.contains('\r')),
                "a parsed RSU record does not write: invalid {key:?}; input {text:?}"
            );
            return;
        }
        Err(e) => panic!("a parsed RSU record does not write: {e:?}; input {text:?}"),
    }
    let back = RsuMessage::parse(&written).unwrap_or_else(|e| {
        panic!("written RSU record does not parse: {e:?}; input {text:?}, written {written:?}")
    });
    let expected = RsuMessage {
        version: "0.7",
        ..m
    };
    assert!(
        back == expected,
        "written RSU record parses to another record: {back:?} vs {expected:?}; \
         input {text:?}, written {written:?}"
    );
    let as_bytes = RsuMessage {
        payload: RsuPayload::Bytes(&bytes),
        ..m
    };
    let mut written_bytes = String::new();
    as_bytes
        .write_to(&mut written_bytes)
        .unwrap_or_else(|e| panic!("RSU record with a bytes payload does not write: {e:?}"));
    assert!(
        written_bytes.eq_ignore_ascii_case(&written),
        "bytes and hex payloads write differently: {written_bytes:?} vs {written:?}"
    );
}
