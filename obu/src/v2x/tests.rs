use super::*;
use crate::ingest::IngestError;
use crate::security::{Rejection, SecurityConfig};
use crate::testutil::{big_stack, vector};
use j2735::envelope::ieee1609dot2::DecodeErrorKind as EnvelopeKind;
use j2735::envelope::wsmp::WsmpError;
use j2735::uper::DecodeErrorKind;
use std::boxed::Box;
use std::vec::Vec;

/// A core and its receiver (with room for a 256-octet RSU payload), on the heap, taking
/// unsigned data (these tests are about the unsigned path; `signed` below about security).
fn setup() -> (Box<Obu>, Box<V2xReceiver<256>>) {
    let config = SecurityConfig {
        require_signed: false,
        ..SecurityConfig::DEFAULT
    };
    (
        Box::new(Obu::default()),
        Box::new(V2xReceiver::with_security(config)),
    )
}

fn rsu(payload: &str) -> Vec<u8> {
    std::format!("Version=0.7\nType=MAP\nPSID=0x8002\nPayload={payload}\n").into_bytes()
}

fn hex(bytes: &[u8]) -> std::string::String {
    std::format!("{:X}", j2735::hex::Hex(bytes))
}

#[test]
fn map_then_tim_change_the_state_repeats_do_not_and_a_bsm_is_other() {
    big_stack(|| {
        let (mut obu, mut scratch) = setup();
        let t = Instant::from_millis(10);
        let map = vector("map_work_zone");
        let tim = vector("tim_work_zone_left_lane_closed");
        assert_eq!(
            obu.on_datagram(t, &map, &mut scratch),
            V2xOutcome::Changed(18)
        );
        // The TIM in an unsecured 1609.2 envelope, long-form length (written by hand).
        assert!((128..256).contains(&tim.len()));
        let mut wrapped = std::vec![0x03, 0x80, 0x81, tim.len() as u8];
        wrapped.extend_from_slice(&tim);
        assert_eq!(
            obu.on_datagram(t, &wrapped, &mut scratch),
            V2xOutcome::Changed(31)
        );
        assert_eq!(
            obu.on_datagram(t, &map, &mut scratch),
            V2xOutcome::Unchanged(18)
        );
        assert_eq!(
            obu.on_datagram(t, &tim, &mut scratch),
            V2xOutcome::Unchanged(31)
        );
        assert_eq!(
            obu.on_datagram(t, &vector("bsm_minimal"), &mut scratch),
            V2xOutcome::Other(20)
        );
        assert_eq!(obu.counters().other_messages, 1);
        assert_eq!((obu.maps().len(), obu.zones().len()), (1, 2));
    });
}

#[test]
fn an_rsu_text_record_carries_the_frame() {
    big_stack(|| {
        let (mut obu, mut scratch) = setup();
        let map = vector("map_work_zone");
        assert!(map.len() <= 256);
        let record = rsu(&hex(&map));
        assert_eq!(
            obu.on_datagram(Instant::ZERO, &record, &mut scratch),
            V2xOutcome::Changed(18)
        );
        // One octet over the scratch's 256.
        let big = rsu(&"00".repeat(257));
        assert_eq!(
            obu.on_datagram(Instant::ZERO, &big, &mut scratch),
            V2xOutcome::Dropped(DropReason::from(RsuTextReason::PayloadTooLarge))
        );
    });
}

#[test]
fn malformed_inputs_give_their_reason() {
    big_stack(|| {
        let (mut obu, mut scratch) = setup();
        let map = vector("map_work_zone");
        let mut trailing = map.clone();
        trailing.push(0);
        let mut no_plaintext =
            std::vec![0x03, 0x82, 0x01, 0x01, 0x80, 1, 2, 3, 4, 5, 6, 7, 8, 0x80];
        no_plaintext.extend_from_slice(&[0x00; 12]);
        no_plaintext.extend_from_slice(&[0x01, 0xaa]);
        let cases: [(&[u8], DropReason); 12] = [
            // The envelope's length says 9 octets, 4 follow.
            (
                &[0x03, 0x80, 0x09, 0x00, 0x1f, 0x01, 0x02],
                EnvelopeKind::UnexpectedEnd.into(),
            ),
            // Long-form length for 4 octets: not canonical COER.
            (
                &[0x03, 0x80, 0x81, 0x04, 0x00, 0x1f, 0x01, 0x02],
                EnvelopeKind::NonCanonical.into(),
            ),
            (&no_plaintext, Ieee1609Reason::NoPlaintext.into()),
            (b"Version=0.7\nType=MAP\n", RsuTextReason::MissingKey.into()),
            (
                b"Version=0.7\nType=MAP\nType=TIM\nPSID=0x20\nPayload=00\n",
                RsuTextReason::DuplicateKey.into(),
            ),
            (
                b"Version=0.7\nno equals sign\n",
                RsuTextReason::NotKeyValue.into(),
            ),
            (
                b"Version=0.7\nType=MAP\nPSID=0x8002\nPayload=0G\n",
                RsuTextReason::InvalidValue.into(),
            ),
            (b"Version=\xff\n", RsuTextReason::NotUtf8.into()),
            (&[], DecodeErrorKind::UnexpectedEnd.into()),
            (&map[..map.len() / 2], DecodeErrorKind::UnexpectedEnd.into()),
            (&trailing, DecodeErrorKind::TrailingBytes.into()),
            (
                &vector("map_regional_addgrpb"),
                IngestError::UnsupportedNode.into(),
            ),
        ];
        let mut counters = V2xCounters::ZERO;
        for (i, (bytes, want)) in cases.iter().enumerate() {
            let got = obu.on_datagram(Instant::ZERO, bytes, &mut scratch);
            assert_eq!(got, V2xOutcome::Dropped(*want), "case {i}");
            counters.record(got);
        }
        assert_eq!(counters.total(), 12);
        assert_eq!(counters.dropped(DecodeErrorKind::UnexpectedEnd.into()), 2);
        assert_eq!(
            counters.dropped_in(DropGroup::Envelope),
            3 + 5,
            "1609.2 and RSU text"
        );
        assert_eq!(counters.dropped_in(DropGroup::Decode), 3);
        assert_eq!(counters.dropped_in(DropGroup::Ingest), 1);
        // Only the last MAP stored anything: its model without the lanes it could not place.
        assert_eq!(obu.maps().len(), 1);
    });
}

#[test]
fn reasons_are_a_closed_indexed_set_of_static_names() {
    for (i, r) in DropReason::ALL.iter().enumerate() {
        assert_eq!(r.index(), i);
        assert!(!r.as_str().is_empty());
        let same = DropReason::ALL
            .iter()
            .filter(|o| o.group() == r.group() && o.as_str() == r.as_str())
            .count();
        assert_eq!(same, 1, "{} named once in its group", r.as_str());
    }
    assert_eq!(
        DropReason::from(IngestError::InvalidValue).as_str(),
        "invalid value"
    );
    assert_eq!(
        DropReason::from(DecodeErrorKind::TrailingBytes).as_str(),
        "trailing bytes"
    );
    assert_eq!(
        DropReason::from(DatagramReason::TooLarge).as_str(),
        "datagram too large"
    );
}

#[test]
fn message_short_names_have_one_spelling() {
    use j2735::msg::message_frame::message_short_name as name;
    let want = [
        (18, "MAP"),
        (19, "SPAT"),
        (20, "BSM"),
        (21, "CSR"),
        (22, "EVA"),
        (23, "ICA"),
        (24, "NMEA"),
        (25, "PDM"),
        (26, "PVD"),
        (27, "RSA"),
        (28, "RTCM"),
        (29, "SRM"),
        (30, "SSM"),
        (31, "TIM"),
        (32, "PSM"),
        (240, "TEST00"),
        (255, "TEST15"),
    ];
    for (id, short) in want {
        assert_eq!(name(id), Some(short));
    }
    assert_eq!((name(17), name(33), name(256)), (None, None, None));
}

mod signed {
    use super::*;
    use crate::fix::Fix;
    use crate::geo::LatLon;
    use crate::time::UtcTime;
    use j2735::frame::{encode_message, Message};
    use test_support::signed_vectors::{all, SignedVector};

    fn named(name: &str) -> SignedVector {
        all().into_iter().find(|v| v.name == name).unwrap()
    }

    /// A receiver trusting the vectors' root and CA, with `require_signed` as given.
    fn receiver(v: &SignedVector, require_signed: bool) -> Box<V2xReceiver<256>> {
        let config = SecurityConfig {
            require_signed,
            ..SecurityConfig::DEFAULT
        };
        let mut rx = Box::new(V2xReceiver::with_security(config));
        rx.trust_mut().add_anchor(&v.root).unwrap();
        rx.trust_mut().add_anchor(&v.ca).unwrap();
        rx
    }

    /// A core with a fix at the vectors' clock and a receiver for `v` (see [`receiver`]),
    /// and the time of the fix.
    fn started(
        v: &SignedVector,
        require_signed: bool,
    ) -> (Box<Obu>, Box<V2xReceiver<256>>, Instant) {
        let mut obu = Box::new(Obu::default());
        let rx = receiver(v, require_signed);
        let t = Instant::from_millis(10);
        obu.on_fix(t, fix_at_vector_time(v));
        (obu, rx, t)
    }

    /// A fix at the vectors' clock (2025-06-17T12:32:43Z, their `now`).
    fn fix_at_vector_time(v: &SignedVector) -> Fix {
        let ms = (31 + 28 + 31 + 30 + 31 + 16) * 86_400_000 + (12 * 3600 + 32 * 60 + 43) * 1000;
        let utc = UtcTime {
            year: 2025,
            ms_of_year: ms,
        };
        assert_eq!(utc.time64(), Some(v.now), "the vectors' clock");
        Fix {
            utc: Some(utc),
            ..Fix::at(LatLon::from_degrees(42.1235, -83.7656).unwrap())
        }
    }

    /// The vector's TIM, cancelled (durationTime 0, msgCnt + 1), as a bare frame.
    fn unsigned_cancel_of(v: &SignedVector) -> Vec<u8> {
        let mut tim = crate::testutil::decode::<TravelerInformation>(&v.frame);
        tim.msg_cnt = j2735::msg::common::MsgCount::new((tim.msg_cnt.get() + 1) % 128).unwrap();
        for frame in tim.data_frames.iter_mut() {
            frame.duration_time =
                j2735::msg::traveler_information::MinutesDuration::new(0).unwrap();
        }
        let mut buf = std::vec![0u8; 4096];
        let n = encode_message(&*tim, &mut buf).unwrap();
        buf.truncate(n);
        buf
    }

    #[test]
    fn signed_tim_is_stored_once_gnss_time_is_known() {
        big_stack(|| {
            let v = named("valid_tim_certificate_chain_x_only");
            let mut obu = Box::new(Obu::default());
            let mut rx = receiver(&v, true);
            let t = Instant::from_millis(10);
            let id = TravelerInformation::MESSAGE_ID;
            assert_eq!(
                obu.on_datagram(t, &v.coer, &mut rx),
                V2xOutcome::Dropped(DropReason::from(Rejection::NoTime))
            );
            obu.on_fix(t, fix_at_vector_time(&v));
            assert_eq!(
                obu.on_datagram(t, &v.coer, &mut rx),
                V2xOutcome::Changed(id)
            );
            // The same bytes again: what an RSU repeats, taken as a repeat.
            assert_eq!(obu.on_datagram(t, &v.coer, &mut rx), V2xOutcome::Repeat(id));
            // The bare frame inside, unsigned: signatures are required.
            assert_eq!(
                obu.on_datagram(t, &v.frame, &mut rx),
                V2xOutcome::Dropped(DropReason::from(SecurityReason::Unsigned))
            );
            let state = obu.state(t);
            assert_eq!(
                (state.zones, state.unverified),
                (obu.zones().len() as u8, 0)
            );
            assert!(state.zones > 0);
        });
    }

    #[test]
    fn a_tim_signed_two_hours_ago_with_a_days_expiry_is_shown_and_its_copies_are_repeats() {
        big_stack(|| {
            let v = named("valid_tim_signed_once_expiry_ahead");
            let (mut obu, mut rx, t) = started(&v, true);
            let id = TravelerInformation::MESSAGE_ID;
            let mut counters = V2xCounters::ZERO;
            let first = obu.on_datagram(t, &v.coer, &mut rx);
            assert_eq!(first, V2xOutcome::Changed(id));
            counters.record(first);
            for _ in 0..10 {
                let again = obu.on_datagram(t, &v.coer, &mut rx);
                assert_eq!(again, V2xOutcome::Repeat(id));
                counters.record(again);
            }
            assert_eq!((counters.changed, counters.repeats), (1, 10));
            // Its zones are bounded by the signature's relevance: the expiry plus 5 s.
            let until = (v.expiry_time.unwrap() + 5_000_000).div_ceil(1_000_000);
            assert!(obu
                .zones()
                .iter()
                .all(|z| u64::from(z.signed_until_s) == until));
            assert_eq!(counters.dropped_in(DropGroup::Security), 0);
            assert!(obu.state(t).zones > 0);
        });
    }

    #[test]
    fn an_older_signed_version_of_a_tim_is_superseded() {
        big_stack(|| {
            let newer = named("superseded_1_newer");
            let older = named("superseded_2_older");
            let (mut obu, mut rx, t) = started(&newer, true);
            let id = TravelerInformation::MESSAGE_ID;
            // On its own the older one is valid.
            let mut alone = receiver(&older, true);
            let mut other = Box::new(Obu::default());
            other.on_fix(t, fix_at_vector_time(&older));
            assert_eq!(
                other.on_datagram(t, &older.coer, &mut alone),
                V2xOutcome::Changed(id)
            );
            assert_eq!(
                obu.on_datagram(t, &newer.coer, &mut rx),
                V2xOutcome::Changed(id)
            );
            assert_eq!(
                obu.on_datagram(t, &older.coer, &mut rx),
                V2xOutcome::Dropped(DropReason::from(Rejection::Superseded))
            );
            // The newer one again is a repeat, not superseded.
            assert_eq!(
                obu.on_datagram(t, &newer.coer, &mut rx),
                V2xOutcome::Repeat(id)
            );
        });
    }

    #[test]
    fn a_signed_cancel_cannot_be_undone_by_replaying_the_original() {
        big_stack(|| {
            let v = named("valid_tim_certificate_x_only");
            let (mut obu, mut rx, t) = started(&v, true);
            let id = TravelerInformation::MESSAGE_ID;
            assert_eq!(
                obu.on_datagram(t, &v.coer, &mut rx),
                V2xOutcome::Changed(id)
            );
            let zones = obu.zones().len();
            assert!(zones > 0);
            // The cancel of its first data frame, signed by the same RSU a second later.
            let cancel = named("signed_cancel_of_base");
            assert_eq!(
                obu.on_datagram(t, &cancel.coer, &mut rx),
                V2xOutcome::Changed(id)
            );
            assert_eq!(obu.zones().len(), zones - 1);
            // The original again, byte for byte (still within its expiry): refused.
            for _ in 0..3 {
                assert_eq!(
                    obu.on_datagram(t, &v.coer, &mut rx),
                    V2xOutcome::Dropped(DropReason::from(Rejection::Superseded))
                );
            }
            assert_eq!(obu.zones().len(), zones - 1);
        });
    }

    /// `data` in a WAVE Short Message laid out by hand (IEEE 1609.3): N-header 0x0B (null
    /// networking, an extension, version 3) with channel 172, TPID 0, the p-encoded `psid`
    /// octets, the two-octet WSM length, the data.
    fn in_wsm(psid: &[u8], data: &[u8]) -> Vec<u8> {
        let mut out = std::vec![0x0B, 0x01, 0x0F, 0x01, 172, 0x00];
        out.extend_from_slice(psid);
        assert!(data.len() < 0x4000);
        out.push(0x80 | (data.len() >> 8) as u8);
        out.push(data.len() as u8);
        out.extend_from_slice(data);
        out
    }

    #[test]
    fn the_generators_wave_short_messages_get_its_verdicts() {
        big_stack(|| {
            let vectors = all();
            let id = TravelerInformation::MESSAGE_ID;
            let mut checked = 0;
            for v in &vectors {
                for (bytes, expect) in &v.wsmp {
                    let unsigned = expect == "valid (unsigned)";
                    let (mut obu, mut rx, t) = started(v, !unsigned);
                    let want = match expect.as_str() {
                        "valid" | "valid (unsigned)" => V2xOutcome::Changed(id),
                        "WSMP PSID does not match the message" => {
                            V2xOutcome::Dropped(DropReason::from(WsmpReason::PsidMismatch))
                        }
                        other => panic!("{}: unknown WSMP verdict {other:?}", v.name),
                    };
                    assert_eq!(
                        obu.on_datagram(t, bytes, &mut rx),
                        want,
                        "{}: {expect}",
                        v.name
                    );
                    checked += 1;
                }
            }
            assert_eq!(checked, 4);
        });
    }

    #[test]
    fn wave_short_messages_are_opened_and_their_psid_checked() {
        big_stack(|| {
            let v = named("valid_tim_certificate_x_only");
            let (mut obu, mut rx, t) = started(&v, true);
            let id = TravelerInformation::MESSAGE_ID;
            // TIM's PSID as the MAP's: dropped before the signature check.
            let wrong = in_wsm(&[0xE0, 0x00, 0x00, 0x17], &v.coer);
            assert_eq!(
                obu.on_datagram(t, &wrong, &mut rx),
                V2xOutcome::Dropped(DropReason::from(WsmpReason::PsidMismatch))
            );
            // The misread integer 32771, p-encoded (C0-3F-83): not TIM's PSID.
            let misread = in_wsm(&[0xC0, 0x3F, 0x83], &v.coer);
            assert_eq!(
                obu.on_datagram(t, &misread, &mut rx),
                V2xOutcome::Dropped(DropReason::from(WsmpReason::PsidMismatch))
            );
            let right = in_wsm(&[0x80, 0x03], &v.coer);
            assert_eq!(obu.on_datagram(t, &right, &mut rx), V2xOutcome::Changed(id));
            // A truncated WSM: named, never a panic.
            assert_eq!(
                obu.on_datagram(t, &right[..right.len() - 1], &mut rx),
                V2xOutcome::Dropped(DropReason::from(WsmpError::Truncated))
            );
            // Unsigned frames in WSMs (signatures not required): the message type's PSID.
            let mut open = receiver(&v, false);
            let mut obu = Box::new(Obu::default());
            obu.on_fix(t, fix_at_vector_time(&v));
            let bare = in_wsm(&[0x80, 0x03], &v.frame);
            assert_eq!(
                obu.on_datagram(t, &bare, &mut open),
                V2xOutcome::Changed(id)
            );
            let as_bsm = in_wsm(&[0x20], &v.frame);
            assert_eq!(
                obu.on_datagram(t, &as_bsm, &mut open),
                V2xOutcome::Dropped(DropReason::from(WsmpReason::PsidMismatch))
            );
        });
    }

    #[test]
    fn unsigned_data_is_marked_and_cannot_cancel_a_verified_zone() {
        big_stack(|| {
            let v = named("valid_tim_certificate_x_only");
            let (mut obu, mut rx, t) = started(&v, false);
            let id = TravelerInformation::MESSAGE_ID;
            assert_eq!(
                obu.on_datagram(t, &v.coer, &mut rx),
                V2xOutcome::Changed(id)
            );
            let zones = obu.zones().len();
            let cancel = unsigned_cancel_of(&v);
            assert_eq!(
                obu.on_datagram(t, &cancel, &mut rx),
                V2xOutcome::Dropped(DropReason::from(IngestReason::UnverifiedOverVerified))
            );
            // The same bytes unsigned again cannot refresh it either.
            assert_eq!(
                obu.on_datagram(t, &v.frame, &mut rx),
                V2xOutcome::Dropped(DropReason::from(IngestReason::UnverifiedOverVerified))
            );
            assert_eq!(obu.zones().len(), zones);
            assert_eq!(obu.state(t).unverified, 0);
            // An unsigned zone of its own is shown, marked unverified.
            let other = vector("tim_work_zone_right_lane_closed_ahead");
            assert_eq!(obu.on_datagram(t, &other, &mut rx), V2xOutcome::Changed(id));
            assert!(obu.state(t).unverified >= 1);
        });
    }

    #[test]
    fn a_forged_signature_never_touches_the_stores() {
        big_stack(|| {
            let v = named("signature_bit_flipped");
            let (mut obu, mut rx, t) = started(&v, true);
            assert_eq!(
                obu.on_datagram(t, &v.coer, &mut rx),
                V2xOutcome::Dropped(DropReason::from(Rejection::SignatureInvalid))
            );
            assert!(obu.zones().is_empty() && obu.maps().is_empty());
        });
    }
}
