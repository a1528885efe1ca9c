//! A GNSS receiver's byte stream as the OBU reads it, whatever it mixes: NMEA 0183
//! sentences and u-blox UBX frames, with any other binary (SiRF, RTCM, a half-sent frame)
//! between them skipped and counted, never a reason to refuse the stream.
//!
//! [`Framer`] cuts the stream into NMEA sentences (from `$` or `!` to the line end) and
//! UBX frames (`B5 62`, length-bounded, checksum verified), one byte at a time, in a
//! fixed buffer. [`GnssReader`] reads what it cuts: sentences into epochs
//! ([`FixAssembler`]), NAV-PVT into epochs of their own, and reports each step as a
//! [`GnssEvent`] for the caller to count. Both the daemon (serial, TCP, UDP, files) and
//! the firmware (its GNSS USART) use it.

use super::nmea::{self, AccuracyModel, DayMillis, Epoch, FixAssembler, NmeaError, Sentence};
use super::ubx::{self, Message, UbxError};
use crate::time::UtcTime;

/// Longest NMEA sentence the framer keeps (longer ones are skipped to their line end).
pub const MAX_LINE: usize = 128;
/// Largest UBX payload the framer keeps; longer frames (satellite lists) are stepped over.
pub const MAX_UBX_KEPT: usize = 120;
/// Largest UBX payload taken as a frame at all: a larger length is not a frame (the
/// `B5 62` was a coincidence in other binary) and the bytes are skipped.
pub const MAX_UBX_LEN: usize = 2048;
const BUF: usize = if MAX_LINE > MAX_UBX_KEPT + 6 {
    MAX_LINE
} else {
    MAX_UBX_KEPT + 6
};

/// One piece the framer cut out of the stream.
#[derive(Debug, PartialEq)]
pub enum Framed<'a> {
    /// An NMEA sentence (without its line end), not yet checked.
    Sentence(&'a [u8]),
    /// A UBX frame with a good checksum.
    Ubx {
        /// Message class.
        class: u8,
        /// Message id.
        id: u8,
        /// Payload.
        payload: &'a [u8],
    },
    /// A UBX frame too long to keep, stepped over by its length (not checked).
    UbxSkipped {
        /// Message class.
        class: u8,
        /// Message id.
        id: u8,
    },
    /// A UBX frame whose checksum does not match.
    UbxBadChecksum,
    /// A sentence longer than [`MAX_LINE`], dropped.
    SentenceTooLong,
    /// Bytes that belong to no sentence or frame (binary, a sentence cut by binary).
    Skipped(usize),
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum State {
    Idle,
    Line,
    LineTooLong,
    UbxSync,
    UbxHeader,
    UbxBody { total: usize },
    UbxStep { class: u8, id: u8, left: usize },
}

/// Cuts a byte stream into NMEA sentences and UBX frames.
#[derive(Clone, Debug)]
pub struct Framer {
    state: State,
    buf: [u8; BUF],
    len: usize,
}

impl Default for Framer {
    fn default() -> Self {
        Self::new()
    }
}

impl Framer {
    /// A framer between frames.
    pub const fn new() -> Self {
        Self {
            state: State::Idle,
            buf: [0; BUF],
            len: 0,
        }
    }

    /// Takes bytes; calls `out` for each piece they complete.
    pub fn push(&mut self, bytes: &[u8], mut out: impl FnMut(Framed<'_>)) {
        for &b in bytes {
            self.byte(b, &mut out);
        }
    }

    fn byte(&mut self, b: u8, out: &mut impl FnMut(Framed<'_>)) {
        match self.state {
            State::Idle => self.start(b, out),
            State::Line => self.line(b, out),
            State::LineTooLong => {
                if b == b'\n' || b == b'\r' {
                    self.state = State::Idle;
                } else if b == b'$' || b == b'!' || b == SYNC0 {
                    self.state = State::Idle;
                    self.start(b, out);
                }
            }
            State::UbxSync => {
                if b == ubx::SYNC[1] {
                    self.state = State::UbxHeader;
                    self.len = 0;
                } else {
                    out(Framed::Skipped(1));
                    self.state = State::Idle;
                    self.start(b, out);
                }
            }
            State::UbxHeader => self.ubx_header(b, out),
            State::UbxBody { total } => {
                self.buf[self.len] = b;
                self.len += 1;
                if self.len == total {
                    self.state = State::Idle;
                    self.ubx_frame(out);
                }
            }
            State::UbxStep { class, id, left } => {
                if left <= 1 {
                    self.state = State::Idle;
                    out(Framed::UbxSkipped { class, id });
                } else {
                    self.state = State::UbxStep {
                        class,
                        id,
                        left: left - 1,
                    };
                }
            }
        }
    }

    /// Between frames: a `$`/`!` opens a sentence, `B5` perhaps a UBX frame; line ends
    /// are nothing; anything else is skipped.
    fn start(&mut self, b: u8, out: &mut impl FnMut(Framed<'_>)) {
        match b {
            b'$' | b'!' => {
                self.buf[0] = b;
                self.len = 1;
                self.state = State::Line;
            }
            SYNC0 => self.state = State::UbxSync,
            b'\r' | b'\n' => {}
            _ => out(Framed::Skipped(1)),
        }
    }

    fn line(&mut self, b: u8, out: &mut impl FnMut(Framed<'_>)) {
        match b {
            b'\r' | b'\n' => {
                self.state = State::Idle;
                out(Framed::Sentence(&self.buf[..self.len]));
            }
            // A new start before the line end: the sentence so far is handed on as it is
            // (its checksum decides), the new one begins.
            b'$' | b'!' => {
                out(Framed::Sentence(&self.buf[..self.len]));
                self.buf[0] = b;
                self.len = 1;
            }
            0x20..=0x7E => {
                if self.len == MAX_LINE {
                    self.state = State::LineTooLong;
                    out(Framed::SentenceTooLong);
                } else {
                    self.buf[self.len] = b;
                    self.len += 1;
                }
            }
            // Binary inside a sentence: the sentence is lost, the byte may start a frame.
            _ => {
                out(Framed::Skipped(self.len));
                self.state = State::Idle;
                self.start(b, out);
            }
        }
    }

    fn ubx_header(&mut self, b: u8, out: &mut impl FnMut(Framed<'_>)) {
        self.buf[self.len] = b;
        self.len += 1;
        if self.len < 4 {
            return;
        }
        let (class, id) = (self.buf[0], self.buf[1]);
        let payload = usize::from(u16::from_le_bytes([self.buf[2], self.buf[3]]));
        if payload > MAX_UBX_LEN {
            out(Framed::Skipped(6));
            self.state = State::Idle;
        } else if payload > MAX_UBX_KEPT {
            self.state = State::UbxStep {
                class,
                id,
                left: payload + 2,
            };
        } else {
            self.state = State::UbxBody {
                total: 4 + payload + 2,
            };
        }
    }

    /// A whole kept frame in `buf` (class to checksum).
    fn ubx_frame(&mut self, out: &mut impl FnMut(Framed<'_>)) {
        let n = self.len;
        let (a, b) = ubx::checksum(&self.buf[..n - 2]);
        if (a, b) != (self.buf[n - 2], self.buf[n - 1]) {
            out(Framed::UbxBadChecksum);
            return;
        }
        out(Framed::Ubx {
            class: self.buf[0],
            id: self.buf[1],
            payload: &self.buf[4..n - 2],
        });
    }
}

const SYNC0: u8 = ubx::SYNC[0];

/// What reading the stream gave, step by step (for counters and `gnss-check`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum GnssEvent {
    /// An epoch: a fix, or why there is none.
    Epoch(Epoch),
    /// A sentence read (its type: `GGA`, `RMC`, ...).
    Sentence(&'static str),
    /// A well-formed sentence of a type not read (GSV, TXT, proprietary, AIS).
    OtherSentence,
    /// A sentence refused.
    NmeaError(NmeaError),
    /// A UBX message read (`NAV-PVT`, `NAV-STATUS`, `NAV-DOP`, or `other`).
    Ubx(&'static str),
    /// A UBX message refused.
    UbxError(UbxError),
    /// An NMEA epoch ignored because the receiver's NAV-PVT covers it.
    CoveredByUbx,
    /// Bytes skipped (not part of any sentence or frame).
    Skipped(usize),
}

/// NMEA epochs this close (ms) to the last NAV-PVT are the same epoch.
const UBX_COVERS_MS: u32 = 1500;

/// Reads a receiver's byte stream: frames it, parses sentences and UBX messages, joins
/// epochs. A stream with NAV-PVT takes its fixes from NAV-PVT (it carries the receiver's
/// own accuracy) and counts the NMEA epochs it covers.
#[derive(Clone, Debug, Default)]
pub struct GnssReader {
    framer: Framer,
    nmea: FixAssembler,
    last_pvt: Option<DayMillis>,
}

impl GnssReader {
    /// A reader with the default accuracy model.
    pub const fn new() -> Self {
        Self::with_model(AccuracyModel::DEFAULT)
    }

    /// A reader deriving accuracy from HDOP with `model` when the receiver gives none.
    pub const fn with_model(model: AccuracyModel) -> Self {
        Self {
            framer: Framer::new(),
            nmea: FixAssembler::with_model(model),
            last_pvt: None,
        }
    }

    /// A date for receivers that send none ([`FixAssembler::set_date_hint`]).
    pub fn set_date_hint(&mut self, utc: UtcTime) {
        self.nmea.set_date_hint(utc);
    }

    /// Takes bytes from the receiver; calls `out` for what they give.
    pub fn push(&mut self, bytes: &[u8], mut out: impl FnMut(GnssEvent)) {
        let Self {
            framer,
            nmea,
            last_pvt,
        } = self;
        framer.push(bytes, |piece| match piece {
            Framed::Sentence(s) => sentence(nmea, *last_pvt, s, &mut out),
            Framed::Ubx { class, id, payload } => {
                message(ubx::parse(class, id, payload), last_pvt, &mut out)
            }
            Framed::UbxSkipped { .. } => out(GnssEvent::Ubx("other")),
            Framed::UbxBadChecksum => out(GnssEvent::UbxError(UbxError::BadChecksum)),
            Framed::SentenceTooLong => out(GnssEvent::NmeaError(NmeaError::TooLong)),
            Framed::Skipped(n) => out(GnssEvent::Skipped(n)),
        });
    }

    /// Emits the epoch in progress (the end of a recording).
    pub fn finish(&mut self, mut out: impl FnMut(GnssEvent)) {
        let last_pvt = self.last_pvt;
        self.nmea.finish(|e| nmea_epoch(e, last_pvt, &mut out));
    }
}

fn sentence(
    nmea: &mut FixAssembler,
    last_pvt: Option<DayMillis>,
    bytes: &[u8],
    out: &mut impl FnMut(GnssEvent),
) {
    let Ok(text) = core::str::from_utf8(bytes) else {
        return out(GnssEvent::NmeaError(NmeaError::BadStart));
    };
    match nmea::parse(text) {
        Ok(s) => {
            out(GnssEvent::Sentence(kind(&s)));
            nmea.push(&s, |e| nmea_epoch(e, last_pvt, out));
        }
        Err(NmeaError::Unsupported) => out(GnssEvent::OtherSentence),
        Err(e) => out(GnssEvent::NmeaError(e)),
    }
}

fn nmea_epoch(e: Epoch, last_pvt: Option<DayMillis>, out: &mut impl FnMut(GnssEvent)) {
    // Across midnight the two times of day are a day apart less their difference.
    let covered = last_pvt.is_some_and(|t| {
        let d = e.time.abs_diff(t);
        d.min(86_400_000u32.saturating_sub(d)) < UBX_COVERS_MS
    });
    out(if covered {
        GnssEvent::CoveredByUbx
    } else {
        GnssEvent::Epoch(e)
    });
}

fn message(
    m: Result<Message, UbxError>,
    last_pvt: &mut Option<DayMillis>,
    out: &mut impl FnMut(GnssEvent),
) {
    match m {
        Ok(Message::NavPvt(pvt)) => {
            out(GnssEvent::Ubx("NAV-PVT"));
            let e = pvt.epoch();
            *last_pvt = Some(e.time);
            out(GnssEvent::Epoch(e));
        }
        Ok(Message::NavStatus(_)) => out(GnssEvent::Ubx("NAV-STATUS")),
        Ok(Message::NavDop(_)) => out(GnssEvent::Ubx("NAV-DOP")),
        Ok(Message::Other(..)) => out(GnssEvent::Ubx("other")),
        Err(e) => out(GnssEvent::UbxError(e)),
    }
}

/// The sentence type's name.
const fn kind(s: &Sentence) -> &'static str {
    match s {
        Sentence::Gga(_) => "GGA",
        Sentence::Rmc(_) => "RMC",
        Sentence::Gns(_) => "GNS",
        Sentence::Gll(_) => "GLL",
        Sentence::Gsa(_) => "GSA",
        Sentence::Vtg(_) => "VTG",
        Sentence::Gst(_) => "GST",
        Sentence::Zda(_) => "ZDA",
    }
}
