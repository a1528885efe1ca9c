//! The firmware's logic, independent of the hardware: bytes in (NMEA, V2X frames), the OBU
//! core in the middle, `HmiState` frames out. Fed from the USARTs by `main` and from byte
//! slices by the on-target tests.

use embedded_io::Write;
use j2735::frame::{decode_message_into, peek_message_id, Message};
use j2735::uper::Placeholder;
use j2735::{MapData, TravelerInformation};
use obu::input::nmea::{self, FixAssembler};
use obu::link::{self, Deframer, FrameError};
use obu::{AlertConfig, HmiState, Instant, Obu};

/// Largest V2X frame on the wire (a UPER MessageFrame in a 1609.2 envelope, COBS framed).
pub const V2X_MAX_WIRE: usize = 2048;
/// Longest NMEA sentence kept (82 characters by the standard, with room to spare).
pub const NMEA_MAX: usize = 100;
/// Largest postcard encoding of an `HmiState`.
pub const HMI_MAX: usize = 256;
/// Largest wire frame of an `HmiState`.
pub const HMI_WIRE_MAX: usize = link::encoded_len(HMI_MAX);

/// What happened to the V2X input, by outcome (shown in the logs, checked by the tests).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, defmt::Format)]
pub struct V2xCounters {
    /// Frames whose MAP or TIM the core took.
    pub accepted: u32,
    /// Frames rejected by the framing (bad COBS, CRC, too long or too short).
    pub bad_frames: u32,
    /// Frames whose envelope or UPER content did not decode (or exceeded a capacity).
    pub undecodable: u32,
    /// Decoded MAP/TIM that the core rejected.
    pub rejected: u32,
    /// Other message types (not used by the OBU).
    pub other: u32,
}

/// The decode targets of MAP and TIM, kept between messages (the largest part of the RAM).
///
/// Each is an empty `heapless::Vec` of capacity 1 until the first message: an empty one is
/// all zeros, so a `static` of this type lands in .bss (zeroed at boot) instead of .data
/// (a copy in flash), as an `Option` (whose `None` is a non-zero niche) would.
#[derive(Default)]
pub struct Messages {
    map: heapless::Vec<MapData, 1>,
    tim: heapless::Vec<TravelerInformation, 1>,
}

impl Messages {
    /// Nothing received yet.
    pub const fn new() -> Self {
        Self {
            map: heapless::Vec::new(),
            tim: heapless::Vec::new(),
        }
    }

    fn map(&mut self) -> &mut MapData {
        if self.map.is_empty() {
            let _ = self.map.push(MapData::placeholder());
        }
        &mut self.map[0]
    }

    fn tim(&mut self) -> &mut TravelerInformation {
        if self.tim.is_empty() {
            let _ = self.tim.push(TravelerInformation::placeholder());
        }
        &mut self.tim[0]
    }
}

/// The firmware's state besides [`Messages`], statically allocated.
pub struct Firmware {
    obu: Obu,
    v2x: Deframer<V2X_MAX_WIRE>,
    line: heapless::Vec<u8, NMEA_MAX>,
    fixes: FixAssembler,
    /// V2X input counters.
    pub v2x_counters: V2xCounters,
    /// NMEA sentences that did not parse.
    pub nmea_errors: u32,
    /// HmiState frames that did not fit their buffer (never expected).
    pub hmi_dropped: u32,
}

impl Firmware {
    /// A firmware with nothing received; `const` so that it can be a `static`.
    pub const fn new(config: AlertConfig) -> Self {
        Self {
            obu: Obu::new(config),
            v2x: Deframer::new(),
            line: heapless::Vec::new(),
            fixes: FixAssembler::new(),
            v2x_counters: V2xCounters {
                accepted: 0,
                bad_frames: 0,
                undecodable: 0,
                rejected: 0,
                other: 0,
            },
            nmea_errors: 0,
            hmi_dropped: 0,
        }
    }

    /// The OBU core.
    pub fn obu(&self) -> &Obu {
        &self.obu
    }

    /// One byte of the NMEA port; a complete fix yields the new state.
    pub fn on_nmea_byte(&mut self, now: Instant, byte: u8) -> Option<HmiState> {
        match byte {
            b'\r' => None,
            b'\n' => {
                let state = core::str::from_utf8(&self.line)
                    .ok()
                    .map(|s| nmea::parse(s.trim()));
                self.line.clear();
                match state {
                    Some(Ok(sentence)) => {
                        let fix = self.fixes.push(&sentence)?;
                        Some(self.obu.on_fix(now, fix))
                    }
                    _ => {
                        self.nmea_errors = self.nmea_errors.wrapping_add(1);
                        None
                    }
                }
            }
            _ => {
                if self.line.push(byte).is_err() {
                    self.line.clear();
                    self.nmea_errors = self.nmea_errors.wrapping_add(1);
                }
                None
            }
        }
    }

    /// One byte of the V2X port; a frame that changes what is stored (maps or zones stored,
    /// replaced or cancelled) yields the new state, as the daemon publishes it; a repeat of
    /// what is stored (the roadside's 10 Hz broadcast) yields nothing.
    pub fn on_v2x_byte(&mut self, msgs: &mut Messages, now: Instant, byte: u8) -> Option<HmiState> {
        let outcome = match self.v2x.push(byte)? {
            Ok(payload) => Self::message(&mut self.obu, msgs, now, payload),
            Err(e) => Outcome::BadFrame(e),
        };
        let c = &mut self.v2x_counters;
        match outcome {
            Outcome::Accepted { .. } => c.accepted += 1,
            Outcome::BadFrame(e) => {
                defmt::warn!("v2x: frame dropped: {}", defmt::Display2Format(&e));
                c.bad_frames += 1;
            }
            Outcome::Undecodable => c.undecodable += 1,
            Outcome::Rejected => c.rejected += 1,
            Outcome::Other => c.other += 1,
        }
        (outcome == Outcome::Accepted { changed: true }).then(|| self.obu.state(now))
    }

    fn message(obu: &mut Obu, msgs: &mut Messages, now: Instant, payload: &[u8]) -> Outcome {
        let Ok(frame) = j2735::envelope::unwrap_message_frame(payload) else {
            return Outcome::Undecodable;
        };
        let bytes = frame.frame;
        let result = match peek_message_id(bytes) {
            Ok(MapData::MESSAGE_ID) => {
                let map = msgs.map();
                if let Err(e) = decode_message_into(bytes, map) {
                    defmt::warn!("v2x: MAP: {}", defmt::Display2Format(&e));
                    return Outcome::Undecodable;
                }
                obu.on_map(now, map)
            }
            Ok(TravelerInformation::MESSAGE_ID) => {
                let tim = msgs.tim();
                if let Err(e) = decode_message_into(bytes, tim) {
                    defmt::warn!("v2x: TIM: {}", defmt::Display2Format(&e));
                    return Outcome::Undecodable;
                }
                obu.on_tim(now, tim)
            }
            Ok(_) => return Outcome::Other,
            Err(_) => return Outcome::Undecodable,
        };
        match result {
            Ok(r) => Outcome::Accepted {
                changed: r.stored > 0 || r.cancelled > 0,
            },
            Err(_) => Outcome::Rejected,
        }
    }

    /// Expiry and staleness: call often; a state when something changed.
    pub fn poll(&mut self, now: Instant) -> Option<HmiState> {
        self.obu.poll(now)
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Outcome {
    Accepted { changed: bool },
    BadFrame(FrameError),
    Undecodable,
    Rejected,
    Other,
}

/// Writes `state` as one frame (postcard + COBS + CRC-32) to `out`. Returns false when it
/// did not fit the buffers (counted by the caller).
pub fn send_state<W: Write>(out: &mut W, state: &HmiState) -> bool {
    let mut payload = [0u8; HMI_MAX];
    let mut wire = [0u8; HMI_WIRE_MAX];
    let Ok(bytes) = postcard::to_slice(state, &mut payload) else {
        return false;
    };
    let Ok(n) = link::encode(bytes, &mut wire) else {
        return false;
    };
    out.write_all(&wire[..n]).is_ok()
}
