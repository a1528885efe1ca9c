//! Link octets into `HmiState`s, without I/O: `obu::link` frames (COBS, CRC-32) whose payload
//! is the postcard encoding of one `HmiState`, as the firmware's `send_state` writes them.
//!
//! Everything here comes off a wire and is hostile. No input panics, and every frame ends
//! either as a state or as a [`LinkError`] that names why it was refused; a frame cut by the
//! end of a connection is reported by [`StateDecoder::reset`].

use obu::link::{Deframer, FrameError};
use obu::HmiState;

/// Largest postcard encoding of an `HmiState` the firmware sends (its `app::HMI_MAX`).
pub const HMI_MAX: usize = 512;
/// Largest wire frame of such a state, final zero included; longer frames are refused whole.
pub const WIRE_MAX: usize = obu::link::encoded_len(HMI_MAX);

/// Why link octets did not give a state.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[non_exhaustive]
pub enum LinkError {
    /// The framing refused the frame (COBS, CRC, too long or too short).
    Frame(FrameError),
    /// The payload ends before the state does.
    StateTruncated,
    /// The payload holds a value that no `HmiState` field takes (bad enum, option, bool,
    /// varint, or a list longer than its capacity).
    StateInvalid,
    /// Octets follow the state in the payload.
    TrailingBytes,
    /// The link closed in the middle of a frame.
    CutOff,
}

impl LinkError {
    /// The reason as counted (a closed set of short texts).
    pub const fn as_str(&self) -> &'static str {
        match self {
            LinkError::Frame(FrameError::TooLong) => "frame too long",
            LinkError::Frame(FrameError::Cobs) => "invalid COBS encoding",
            LinkError::Frame(FrameError::TooShort) => "frame shorter than its CRC",
            LinkError::Frame(FrameError::Crc) => "CRC mismatch",
            LinkError::Frame(_) => "frame error",
            LinkError::StateTruncated => "state ends early",
            LinkError::StateInvalid => "state has an invalid value",
            LinkError::TrailingBytes => "octets after the state",
            LinkError::CutOff => "frame cut off by disconnect",
        }
    }
}

impl core::fmt::Display for LinkError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(self.as_str())
    }
}

impl std::error::Error for LinkError {}

/// Turns the octets of one connection into states, in wire order.
#[derive(Debug, Default)]
pub struct StateDecoder {
    deframer: Deframer<{ WIRE_MAX - 1 }>,
    in_frame: bool,
}

impl StateDecoder {
    /// A decoder waiting for the first frame (octets before the first zero are refused as
    /// one frame: a connection may start in the middle of one).
    pub fn new() -> Self {
        Self::default()
    }

    /// Takes received octets; calls `out` once per frame end with its state or error.
    pub fn push(&mut self, octets: &[u8], mut out: impl FnMut(Result<HmiState, LinkError>)) {
        for &b in octets {
            self.in_frame = b != 0;
            if let Some(frame) = self.deframer.push(b) {
                out(frame.map_err(LinkError::Frame).and_then(decode_state));
            }
        }
    }

    /// The connection ended: forgets any partial frame, which is returned as
    /// [`LinkError::CutOff`].
    pub fn reset(&mut self) -> Option<LinkError> {
        self.deframer = Deframer::new();
        std::mem::take(&mut self.in_frame).then_some(LinkError::CutOff)
    }
}

/// The state in one frame's payload; the payload must hold exactly one.
pub fn decode_state(payload: &[u8]) -> Result<HmiState, LinkError> {
    let (state, rest) = postcard::take_from_bytes::<HmiState>(payload).map_err(payload_error)?;
    if rest.is_empty() {
        Ok(state)
    } else {
        Err(LinkError::TrailingBytes)
    }
}

fn payload_error(e: postcard::Error) -> LinkError {
    match e {
        postcard::Error::DeserializeUnexpectedEnd => LinkError::StateTruncated,
        _ => LinkError::StateInvalid,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use obu::alert::{
        Alert, AlertKind, AlertStage, Counters, LaneAdvice, LaneInfo, PositionSource, ZoneState,
    };

    fn sample(time_ms: u64) -> HmiState {
        let mut s = HmiState {
            time_ms,
            speed_mps: Some(13.5),
            speed_limit_mps: Some(11.1),
            reduced_limit: true,
            zone_state: ZoneState::default(),
            distance_m: Some(-4.25),
            gnss_ok: true,
            maps: 1,
            zones: 2,
            ..HmiState::default()
        };
        s.closed_lanes.push(1).unwrap();
        s.road_lanes.extend_from_slice(&[1, 2]).unwrap();
        s
    }

    fn frame(payload: &[u8]) -> Vec<u8> {
        let mut wire = vec![0u8; obu::link::encoded_len(payload.len())];
        let n = obu::link::encode(payload, &mut wire).unwrap();
        wire.truncate(n);
        wire
    }

    fn state_frame(s: &HmiState) -> Vec<u8> {
        let mut buf = [0u8; HMI_MAX];
        frame(postcard::to_slice(s, &mut buf).unwrap())
    }

    fn run(octets: &[u8]) -> Vec<Result<HmiState, LinkError>> {
        let mut d = StateDecoder::new();
        let mut out = Vec::new();
        d.push(octets, |r| out.push(r));
        out
    }

    #[test]
    fn states_survive_the_link_split_anywhere() {
        let (a, b) = (sample(100), sample(200));
        let wire = [state_frame(&a), state_frame(&b)].concat();
        for cut in 0..wire.len() {
            let mut d = StateDecoder::new();
            let mut out = Vec::new();
            d.push(&wire[..cut], |r| out.push(r));
            d.push(&wire[cut..], |r| out.push(r));
            assert_eq!(out, [Ok(a.clone()), Ok(b.clone())], "cut at {cut}");
            assert_eq!(d.reset(), None);
        }
    }

    #[test]
    fn every_bad_frame_is_named_and_the_next_one_is_read() {
        let good = sample(7);
        let mut bad_crc = state_frame(&good);
        let i = bad_crc.iter().rposition(|&b| b > 1).unwrap();
        bad_crc[i] = if bad_crc[i] == 0xFF { 0xFE } else { 0xFF };
        let mut payload = [0u8; HMI_MAX];
        let n = postcard::to_slice(&good, &mut payload).unwrap().len();
        let trailing = frame(&[&payload[..n], &[0x55][..]].concat());
        let cases: [(Vec<u8>, LinkError); 6] = [
            (bad_crc, LinkError::Frame(FrameError::Crc)),
            (
                vec![0x11; WIRE_MAX + 10],
                LinkError::Frame(FrameError::TooLong),
            ),
            (vec![0x05, 0x41, 0x00], LinkError::Frame(FrameError::Cobs)),
            (frame(&payload[..n - 3]), LinkError::StateTruncated),
            (frame(&[0xFF; 12]), LinkError::StateInvalid),
            (trailing, LinkError::TrailingBytes),
        ];
        for (wire, want) in cases {
            let got = run(&[wire, vec![0], state_frame(&good)].concat());
            assert_eq!(got, [Err(want), Ok(good.clone())], "{want}");
        }
    }

    #[test]
    fn a_list_longer_than_its_capacity_is_refused() {
        let mut payload = [0u8; HMI_MAX];
        let n = postcard::to_slice(&sample(1), &mut payload).unwrap().len();
        // The state ends with counters (10 varints) after road_lanes, advice, gnss_ok,
        // roadside_data, maps, zones: find road_lanes' length octet (2, then 1, 2).
        let at = (0..n - 2)
            .rev()
            .find(|&i| payload[i..i + 3] == [2, 1, 2])
            .unwrap();
        payload[at] = 200;
        assert_eq!(run(&frame(&payload[..n])), [Err(LinkError::StateInvalid)]);
    }

    #[test]
    fn a_frame_cut_by_the_disconnect_is_reported_once() {
        let wire = state_frame(&sample(3));
        let mut d = StateDecoder::new();
        d.push(&wire[..wire.len() / 2], |_| panic!("no frame end yet"));
        assert_eq!(d.reset(), Some(LinkError::CutOff));
        assert_eq!(d.reset(), None);
        let mut out = Vec::new();
        d.push(&wire, |r| out.push(r));
        assert_eq!(out, [Ok(sample(3))], "a fresh start after the reset");
    }

    #[test]
    fn the_largest_state_fits_the_buffers() {
        let alert = Alert {
            kind: AlertKind::NoRoadsideData,
            stage: AlertStage::Urgent,
            distance_m: Some(f32::MAX),
            limit_mps: Some(f32::MIN),
        };
        let max = u32::MAX;
        let mut s = HmiState {
            primary: Some(alert),
            lane: Some(LaneInfo {
                map: max,
                lane: u8::MAX,
            }),
            advice: LaneAdvice::MoveRight,
            counters: Counters {
                fixes: max,
                off_map: max,
                lane_switches: max,
                lane_outliers: max,
                maps_updated: max,
                maps_rejected: max,
                zones_updated: max,
                zones_rejected: max,
                zones_cancelled: max,
                expired: max,
                other_messages: max,
                rollover_fixes: max,
                unverified_time_fixes: max,
            },
            speed_limit_mps: Some(f32::MAX),
            limit_ahead_mps: Some(f32::MAX),
            limit_ahead_m: Some(f32::MAX),
            decel_needed_mps2: Some(f32::MAX),
            speed_alarm: true,
            stage: AlertStage::Urgent,
            position: PositionSource::Estimated,
            time_status: obu::clock::TimeStatus::Unverified,
            ..sample(u64::MAX)
        };
        while s.others.push(alert).is_ok() {}
        while s.closed_lanes.push(u8::MAX).is_ok() {}
        while s.road_lanes.push(u8::MAX).is_ok() {}
        let mut payload = [0u8; HMI_MAX];
        let bytes = postcard::to_slice(&s, &mut payload).expect("fits HMI_MAX");
        assert!(obu::link::encoded_len(bytes.len()) <= WIRE_MAX);
        assert_eq!(run(&frame(bytes)), [Ok(s)]);
    }
}
