//! On target: malformed input on the firmware's ports. On the V2X port (`obu::link` frames):
//! bad COBS, bad CRC, frames too short, too long or empty, valid framing around garbage UPER
//! and a truncated MAP, messages other than MAP/TIM (the oracle vectors), bytes from a PRNG.
//! On the NMEA port: bad checksums, overlong lines, binary garbage. Each lands in the counter
//! its kind belongs to (expected counts from the input, not from the firmware), nothing
//! panics, and valid MAP, TIM and fixes sent afterwards still work.
#![no_std]
#![no_main]

mod common;

use common::{feed_nmea, feed_v2x, frame, sentence, tally, vector, Epoch, Rng, Tally};
use defmt_semihosting as _;
use obu::v2x::DropReason;
use obu::Instant;
use obu_firmware::app::{Firmware, Messages, V2X_MAX_WIRE};

include!(concat!(env!("OUT_DIR"), "/vectors.rs"));
include!(concat!(env!("OUT_DIR"), "/other_vectors.rs"));

const MAP: &str = "map_work_zone";
const TIM: &str = "tim_work_zone_left_lane_closed";
/// Wire buffer: room for a frame over the firmware's limit.
const WIRE: usize = 4096;
/// Payload of the oversize frame: its wire frame is over `V2X_MAX_WIRE`.
const OVERSIZE: usize = V2X_MAX_WIRE + 100;

struct State {
    fw: &'static mut Firmware,
    msgs: &'static mut Messages,
    wire: &'static mut [u8; WIRE],
    scratch: &'static mut [u8; WIRE],
    t: u64,
}

impl State {
    fn now(&mut self) -> Instant {
        self.t += 10;
        Instant::from_millis(self.t)
    }

    /// Feeds raw wire bytes; asserts that no state came (nothing was accepted).
    fn raw(&mut self, bytes: &[u8]) {
        let now = self.now();
        let (_, n) = feed_v2x(self.fw, self.msgs, now, bytes);
        assert_eq!(n, 0, "no state from malformed input");
    }

    /// Sends `payload` as one valid link frame; returns the states it yielded.
    fn send(&mut self, payload: &[u8]) -> u32 {
        let now = self.now();
        let wire = frame(payload, &mut self.wire[..]);
        feed_v2x(self.fw, self.msgs, now, wire).1
    }

    /// Counter changes of `f`'s input, checked against `want` (differences).
    fn expect(&mut self, what: &str, want: Tally, f: impl FnOnce(&mut Self)) {
        let before = tally(&self.fw.v2x_counters);
        f(self);
        let after = tally(&self.fw.v2x_counters);
        let got = Tally {
            accepted: after.accepted - before.accepted,
            bad_frames: after.bad_frames - before.bad_frames,
            undecodable: after.undecodable - before.undecodable,
            rejected: after.rejected - before.rejected,
            other: after.other - before.other,
        };
        defmt::info!("{=str}: {}", what, got);
        assert_eq!(got, want, "{}", what);
    }

    /// Like [`State::expect`], and every drop of `f`'s input is of `reason`.
    fn expect_all(
        &mut self,
        what: &str,
        want: Tally,
        reason: DropReason,
        f: impl FnOnce(&mut Self),
    ) {
        let before = self.fw.v2x_counters.dropped(reason);
        let dropped = want.bad_frames + want.undecodable + want.rejected;
        self.expect(what, want, f);
        let got = self.fw.v2x_counters.dropped(reason) - before;
        assert_eq!(got, dropped, "{}: {}", what, reason.as_str());
    }

    /// Valid MAP and TIM, each accepted (stored the first time, then repeats: whether a
    /// state comes out is the firmware's publishing policy, not checked here).
    fn map_and_tim_accepted(&mut self, what: &str) {
        self.expect(what, counts(2, 0, 0, 0), |st| {
            st.send(vector(MAP_TIM_VECTORS, MAP));
            st.send(vector(MAP_TIM_VECTORS, TIM));
        });
        assert_eq!(self.fw.obu().maps().len(), 1);
        assert_eq!(self.fw.obu().zones().len(), 2);
    }
}

/// (accepted, bad frames, undecodable, other); `rejected` always 0 here.
const fn counts(accepted: u32, bad_frames: u32, undecodable: u32, other: u32) -> Tally {
    Tally {
        accepted,
        bad_frames,
        undecodable,
        rejected: 0,
        other,
    }
}

/// Wire offsets of the COBS code bytes of a frame (the final zero excluded).
fn code_positions(wire: &[u8], out: &mut heapless::Vec<usize, 64>) {
    let mut at = 0;
    while at < wire.len() - 1 {
        out.push(at).expect("few codes");
        at += usize::from(wire[at]);
    }
}

/// `payload` in an unsecured IEEE 1609.2 envelope (`03 80`, COER length), written by hand.
fn envelope<'a>(payload: &[u8], out: &'a mut [u8]) -> &'a [u8] {
    let n = payload.len();
    let head: &[u8] = if n < 128 {
        &[0x03, 0x80, n as u8]
    } else if n < 256 {
        &[0x03, 0x80, 0x81, n as u8]
    } else {
        &[0x03, 0x80, 0x82, (n >> 8) as u8, n as u8]
    };
    out[..head.len()].copy_from_slice(head);
    out[head.len()..head.len() + n].copy_from_slice(payload);
    &out[..head.len() + n]
}

#[defmt_test::tests]
mod tests {
    use super::{
        code_positions, counts, envelope, feed_nmea, sentence, vector, Epoch, Rng, State, MAP,
        MAP_TIM_VECTORS, OTHER_VECTORS, OVERSIZE, TIM, WIRE,
    };
    use j2735::uper::DecodeErrorKind;
    use obu::v2x::{DatagramReason, DropReason};
    use obu::Instant;
    use obu_firmware::app::V2X_MAX_WIRE;

    #[init]
    fn init() -> State {
        State {
            fw: super::common::firmware(),
            msgs: super::common::messages(super::common::UNSIGNED_TAKEN),
            wire: cortex_m::singleton!(: [u8; WIRE] = [0; WIRE]).unwrap(),
            scratch: cortex_m::singleton!(: [u8; WIRE] = [0; WIRE]).unwrap(),
            t: 0,
        }
    }

    #[test]
    fn framing_errors_are_bad_frames(st: &mut State) {
        // Painted here rather than in `init` (whose frame holds the statics' values on their
        // way in): the high-water is the tests'.
        obu_firmware::board::paint_stack();
        st.expect("empty frames (zeros)", counts(0, 0, 0, 0), |st| {
            st.raw(&[0; 16])
        });
        st.expect_all(
            "bad COBS",
            counts(0, 2, 0, 0),
            DropReason::Datagram(DatagramReason::LinkCobs),
            |st| {
                st.raw(&[0x09, 0x01, 0x00]); // the code points past the frame's end
                st.raw(&[0x05, 0x11, 0x22, 0x33, 0x00]);
            },
        );
        st.expect_all(
            "shorter than the CRC",
            counts(0, 3, 0, 0),
            DropReason::Datagram(DatagramReason::LinkTooShort),
            |st| {
                st.raw(&[0x01, 0x00]);
                st.raw(&[0x02, 0x11, 0x00]);
                st.raw(&[0x04, 0x11, 0x22, 0x33, 0x00]);
            },
        );

        let map = vector(MAP_TIM_VECTORS, MAP);
        let n = obu::link::encode(map, &mut st.scratch[..]).expect("fits");
        let mut codes = heapless::Vec::new();
        code_positions(&st.scratch[..n], &mut codes);
        st.expect_all(
            "bad CRC",
            counts(0, 3, 0, 0),
            DropReason::Datagram(DatagramReason::LinkCrc),
            |st| {
                // Each frame one data byte changed (COBS intact), the CRC no longer matches.
                for at in [1, n / 2, n - 2] {
                    let at = (at..n - 1)
                        .find(|i| !codes.contains(i))
                        .expect("a data byte");
                    let mut wire: heapless::Vec<u8, 256> =
                        heapless::Vec::from_slice(&st.scratch[..n]).expect("fits");
                    wire[at] = if wire[at] == 0xFF { 0x01 } else { wire[at] + 1 };
                    st.raw(&wire);
                }
            },
        );
        st.expect("truncated frame", counts(0, 1, 0, 0), |st| {
            let cut = n / 2;
            let mut wire: heapless::Vec<u8, 256> =
                heapless::Vec::from_slice(&st.scratch[..cut]).expect("fits");
            wire.push(0).expect("fits");
            st.raw(&wire);
        });
        st.expect_all(
            "oversize frames",
            counts(0, 2, 0, 0),
            DropReason::Datagram(DatagramReason::LinkTooLong),
            |st| {
                // A valid frame whose wire length is over the firmware's limit ...
                st.wire[..OVERSIZE].fill(0x5A);
                let n = obu::link::encode(&st.wire[..OVERSIZE], &mut st.scratch[..]).expect("fits");
                assert!(n > V2X_MAX_WIRE);
                let now = st.now();
                let (_, k) = super::feed_v2x(st.fw, st.msgs, now, &st.scratch[..n]);
                assert_eq!(k, 0);
                // ... and 5000 non-zero bytes without a delimiter, then one.
                for _ in 0..5 {
                    st.raw(&[0x33; 1000]);
                }
                st.raw(&[0]);
            },
        );
        st.map_and_tim_accepted("MAP and TIM after framing errors");
    }

    #[test]
    fn garbage_in_valid_frames_is_undecodable(st: &mut State) {
        let map = vector(MAP_TIM_VECTORS, MAP);
        st.expect("garbage UPER", counts(0, 0, 6, 0), |st| {
            assert_eq!(st.send(&[]), 0, "empty payload");
            assert_eq!(st.send(&[0x80]), 0, "one byte: no message id");
            // MAP (18) and TIM (31) ids with garbage after them.
            assert_eq!(st.send(&[0x00, 0x12, 0xFF, 0xFF, 0xFF, 0xFF]), 0);
            assert_eq!(
                st.send(&[0x00, 0x1F, 0x05, 0x01, 0x02, 0x03, 0x04, 0x05]),
                0
            );
            // A 1609.2 header (version 3, unsecured) around nothing valid.
            assert_eq!(st.send(&[0x03, 0x80, 0x40, 0x00, 0x12]), 0);
            assert_eq!(st.send(&[0x03, 0x84, 0xFF]), 0);
        });
        st.expect_all(
            "truncated MAP",
            counts(0, 0, 3, 0),
            DropReason::from(DecodeErrorKind::UnexpectedEnd),
            |st| {
                for cut in [3, map.len() / 2, map.len() - 1] {
                    assert_eq!(st.send(&map[..cut]), 0);
                }
            },
        );
        // The MAP's MessageFrame: id 18 (00 12), a one-octet length, the MapData. Truncated
        // inside the MapData with the length made to match: the MapData decoder runs out.
        assert_eq!(
            (map[0], map[1], usize::from(map[2])),
            (0x00, 0x12, map.len() - 3)
        );
        st.expect("truncated MapData", counts(0, 0, 3, 0), |st| {
            for body in [1, (map.len() - 3) / 2, map.len() - 4] {
                let mut short: heapless::Vec<u8, 256> =
                    heapless::Vec::from_slice(&map[..3 + body]).expect("fits");
                short[2] = body as u8;
                assert_eq!(st.send(&short), 0);
            }
        });
        // Valid J2735 beyond the firmware's capacity profile (one intersection per MAP, see
        // tests/codec.rs): refused by the decoder like garbage.
        st.expect_all(
            "MAP over the firmware capacity",
            counts(0, 0, 1, 0),
            DropReason::from(DecodeErrorKind::CapacityExceeded),
            |st| {
                assert_eq!(st.send(vector(MAP_TIM_VECTORS, "map_two_intersections")), 0);
            },
        );
        st.expect_all(
            "MAP with a trailing byte",
            counts(0, 0, 1, 0),
            DropReason::from(DecodeErrorKind::TrailingBytes),
            |st| {
                let mut long: heapless::Vec<u8, 256> =
                    heapless::Vec::from_slice(map).expect("fits");
                long.push(0x00).expect("fits");
                assert_eq!(st.send(&long), 0);
            },
        );
        // The positive case of the envelope: MAP and TIM in unsecured 1609.2 data.
        st.expect(
            "MAP and TIM in 1609.2 envelopes",
            counts(2, 0, 0, 0),
            |st| {
                for name in [MAP, TIM] {
                    let mut buf = [0u8; 256];
                    let wrapped = envelope(vector(MAP_TIM_VECTORS, name), &mut buf);
                    st.send(wrapped);
                }
            },
        );
        st.map_and_tim_accepted("MAP and TIM after garbage UPER");
    }

    #[test]
    fn other_messages_are_counted_as_other(st: &mut State) {
        let (mut fit, mut over) = (0, 0);
        // PSMs (32) are taken: road workers (see the core's tests).
        let others = || OTHER_VECTORS.iter().filter(|v| v.1 != 32);
        for &(_, id, bytes) in others() {
            assert!(id != 18 && id != 31);
            if obu::link::encoded_len(bytes.len()) <= V2X_MAX_WIRE {
                fit += 1;
            } else {
                over += 1;
            }
        }
        defmt::info!(
            "{=usize} other vectors: {=u32} fit a frame, {=u32} over {=usize} B",
            others().count(),
            fit,
            over,
            V2X_MAX_WIRE
        );
        assert!(fit > 0 && over > 0, "both kinds among the vectors");
        st.expect("other messages", counts(0, over, 0, fit), |st| {
            for &(name, _, bytes) in others() {
                let now = st.now();
                let n = obu::link::encode(bytes, &mut st.wire[..]).expect("fits");
                let wire: &[u8] = &st.wire[..n];
                let (_, k) = super::feed_v2x(st.fw, st.msgs, now, wire);
                assert_eq!(k, 0, "{} changes nothing", name);
            }
        });
        st.map_and_tim_accepted("MAP and TIM after other messages");
    }

    #[test]
    fn random_bytes_are_bad_frames_and_the_deframer_resynchronises(st: &mut State) {
        // 4096 uniform bytes (zeros, the frame ends, are rare: long frames), then 4096 with
        // a zero in about one of eight (short frames); the last byte non-zero, so that the
        // stream ends inside a frame.
        let mut rng = Rng(0x1234_5678);
        st.scratch.iter_mut().for_each(|b| *b = rng.byte());
        st.wire.iter_mut().for_each(|b| {
            let r = rng.byte();
            *b = if r < 32 { 0 } else { r };
        });
        st.wire[WIRE - 1] |= 0x01;
        // The expected count: every zero-delimited run of non-zero bytes is one bad frame
        // (a random run passing the CRC: 2^-32), runs of zeros none.
        let (mut frames, mut pending) = (0u32, 0usize);
        for &b in st.scratch.iter().chain(st.wire.iter()) {
            if b == 0 {
                frames += u32::from(pending > 0);
                pending = 0;
            } else {
                pending += 1;
            }
        }
        defmt::info!(
            "random bytes: {=usize}, {=u32} frames, {=usize} bytes left unterminated",
            2 * WIRE,
            frames,
            pending
        );
        assert!(frames > 100 && pending > 0);
        st.expect("random bytes", counts(0, frames, 0, 0), |st| {
            let now = st.now();
            for chunk in [&st.scratch[..], &st.wire[..]] {
                let (_, k) = super::feed_v2x(st.fw, st.msgs, now, chunk);
                assert_eq!(k, 0);
            }
        });
        // The first MAP after the stream is lost with its unterminated tail (one bad frame);
        // the deframer is in step again from its final zero.
        st.expect("MAP glued to the random tail", counts(0, 1, 0, 0), |st| {
            assert_eq!(st.send(vector(MAP_TIM_VECTORS, MAP)), 0);
        });
        st.map_and_tim_accepted("MAP and TIM after random bytes");
        // A sender that starts with a delimiter loses nothing after garbage.
        st.expect("delimiter first", counts(1, 1, 0, 0), |st| {
            st.raw(&[0x17, 0x2A, 0x99]);
            st.raw(&[0x00]);
            st.send(vector(MAP_TIM_VECTORS, TIM));
        });
        let c = obu_firmware::app::ShowCounters(&st.fw.v2x_counters);
        defmt::info!("v2x counters after the V2X tests: {}", c);
    }

    #[test]
    fn nmea_errors_are_counted_and_fixes_resume(st: &mut State) {
        let good = Epoch {
            utc_ms: (12 * 60 + 10) * 60_000,
            date: (17, 6, 25),
            lat: 42.1234,
            lon: -83.7654,
            speed_mps: 12.5,
            course_deg: 90.0,
            sd_m: 0.5,
        };
        let now = Instant::from_millis(st.t);
        let errors = |st: &State| st.fw.nmea_errors;

        // Bad checksum: one error per sentence, no fix.
        let e0 = errors(st);
        let gga = good.gga();
        let star = gga.find('*').expect("checksum");
        let bad = if gga.as_bytes()[star + 1] == b'0' {
            "1"
        } else {
            "0"
        };
        let mut wrong: heapless::String<128> = heapless::String::new();
        wrong.push_str(&gga[..star + 1]).expect("fits");
        wrong.push_str(bad).expect("fits");
        wrong.push_str(&gga[star + 2..]).expect("fits");
        let (_, k) = feed_nmea(st.fw, now, wrong.as_bytes());
        assert_eq!(k, 0);
        assert_eq!(errors(st) - e0, 1, "bad checksum");
        // A sentence without checksum and an RMC with an invalid status: one error each.
        // A line not starting with '$' is skipped (counted as bytes), a well-formed type
        // the core does not read (GSV) is no error.
        let (e0, s0) = (errors(st), st.fw.gnss_skipped);
        let unsupported = sentence("GPGSV,1,1,01,05,40,083,46");
        let bad_status = sentence("GPRMC,121000.00,X,4207.4040,N,08345.9240,W,1.0,90.0,170625,,,A");
        for line in [
            "$GPGGA,121000.00,4207.4040,N,08345.9240,W,1,12,0.8,271.0,M,-34.0,M,,\r\n",
            "GPGGA,121000.00*00\r\n",
            unsupported.as_str(),
            bad_status.as_str(),
        ] {
            let (_, k) = feed_nmea(st.fw, now, line.as_bytes());
            assert_eq!(k, 0);
        }
        assert_eq!(errors(st) - e0, 2, "malformed sentences");
        assert_eq!(st.fw.gnss_skipped - s0, 18, "the line without '$'");

        // Overlong sentence ('$' and 150 characters): counted, no fix.
        let e0 = errors(st);
        let (_, k) = feed_nmea(st.fw, now, b"$");
        let (_, k1) = feed_nmea(st.fw, now, &[b'A'; 150]);
        let (_, k2) = feed_nmea(st.fw, now, b"\r\n");
        assert_eq!(k + k1 + k2, 0);
        let overlong = errors(st) - e0;
        assert_eq!(overlong, 1, "overlong sentence");

        // Binary garbage: skipped and counted as bytes, never taken as a sentence; a '$'
        // in it starts a sentence that the next binary byte ends.
        let (e0, s0) = (errors(st), st.fw.gnss_skipped);
        let mut rng = Rng(0xDEAD_BEEF);
        let mut len = 0usize;
        for _ in 0..4 {
            let chunk = &mut st.scratch[..1024];
            chunk.iter_mut().for_each(|b| *b = rng.byte());
            len += chunk.len();
            let (_, k) = feed_nmea(st.fw, now, &st.scratch[..1024]);
            assert_eq!(k, 0);
        }
        let (_, k) = feed_nmea(st.fw, now, b"\r\n");
        assert_eq!(k, 0);
        let (garbage, skipped) = (errors(st) - e0, st.fw.gnss_skipped - s0);
        defmt::info!(
            "GNSS: overlong sentence {=u32} error; {=usize} garbage bytes: {=u32} skipped, {=u32} errors",
            overlong,
            len,
            skipped,
            garbage
        );
        assert!(skipped as usize > len / 2, "the garbage is skipped");
        assert!(
            (garbage as usize) < len / 64,
            "and rarely taken for a sentence"
        );

        // A good fix afterwards: one state, no new error.
        let e0 = errors(st);
        let fixes = st.fw.obu().counters().fixes;
        let (_, k0) = feed_nmea(st.fw, now, good.gst().as_bytes());
        let (_, k1) = feed_nmea(st.fw, now, good.gga().as_bytes());
        let (state, k2) = feed_nmea(st.fw, now, good.rmc().as_bytes());
        assert_eq!((k0, k1, k2), (0, 0, 1), "one fix from GST + GGA + RMC");
        let state = state.expect("state");
        assert_eq!(errors(st), e0, "no error from good sentences");
        assert_eq!(state.counters.fixes, fixes + 1);
        assert!(state.gnss_ok);
        let v = state.speed_mps.expect("speed");
        assert!((v - 12.5).abs() < 0.01, "speed {}", v);
        defmt::info!("NMEA errors in total: {=u32}", errors(st));
    }

    #[test]
    fn stack_high_water(_st: &mut State) {
        let (used, size) = obu_firmware::board::stack_high_water();
        defmt::info!(
            "stack high-water (malformed): {=usize} of {=usize} B",
            used,
            size
        );
    }
}
