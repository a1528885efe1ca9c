//! The firmware's logic, independent of the hardware: bytes in (GNSS NMEA and UBX, V2X frames), the OBU
//! core in the middle, `HmiState` frames out. Fed from the USARTs by `main` and from byte
//! slices by the on-target tests.

use embedded_io::Write;
use obu::ingest::IngestError;
use obu::input::gnss::{GnssEvent, GnssReader};
use obu::link::{self, Deframer};
use obu::v2x::{DropReason, IngestReason, V2xCounters, V2xOutcome, V2xReceiver};
use obu::{AlertConfig, HmiState, Instant, Obu};

/// Largest V2X frame on the wire (a UPER MessageFrame in a 1609.2 envelope, COBS framed).
pub const V2X_MAX_WIRE: usize = 2048;
/// Largest postcard encoding of an `HmiState`.
pub const HMI_MAX: usize = 512;
/// Largest wire frame of an `HmiState`.
pub const HMI_WIRE_MAX: usize = link::encoded_len(HMI_MAX);

/// The largest RSU text payload taken from a V2X frame, octets (a frame of
/// [`V2X_MAX_WIRE`] holds at most half as many in hexadecimal text).
pub const RSU_PAYLOAD_MAX: usize = V2X_MAX_WIRE / 2;

/// The decode targets of MAP and TIM and the RSU payload buffer, kept between messages (the
/// largest part of the RAM): the core's [`V2xReceiver`], all zeros until the first message,
/// so a `static` of it lands in .bss.
pub type Messages = V2xReceiver<RSU_PAYLOAD_MAX>;

/// [`V2xCounters`] for defmt: the outcomes, then every non-zero drop by its reason.
pub struct ShowCounters<'a>(pub &'a V2xCounters);

impl defmt::Format for ShowCounters<'_> {
    fn format(&self, f: defmt::Formatter<'_>) {
        let c = self.0;
        defmt::write!(
            f,
            "changed {=u32} unchanged {=u32} other {=u32}",
            c.changed,
            c.unchanged,
            c.other
        );
        for &r in &DropReason::ALL {
            if c.dropped(r) > 0 {
                defmt::write!(f, ", {=str} {=u32}", r.as_str(), c.dropped(r));
            }
        }
    }
}

/// The firmware's state besides [`Messages`], statically allocated.
pub struct Firmware {
    obu: Obu,
    v2x: Deframer<V2X_MAX_WIRE>,
    gnss: GnssReader,
    /// V2X input counters, by outcome and drop reason.
    pub v2x_counters: V2xCounters,
    /// NMEA sentences and UBX messages that did not parse.
    pub nmea_errors: u32,
    /// GNSS epochs in which the receiver gave no fix (no fix, its simulator, its dead
    /// reckoning, ...).
    pub gnss_no_fix: u32,
    /// GNSS bytes that belonged to no sentence or UBX frame.
    pub gnss_skipped: u32,
    /// HmiState frames that did not fit their buffer (never expected).
    pub hmi_dropped: u32,
}

impl Firmware {
    /// A firmware with nothing received; `const` so that it can be a `static`.
    pub const fn new(config: AlertConfig) -> Self {
        Self {
            obu: Obu::new(config),
            v2x: Deframer::new(),
            gnss: GnssReader::new(),
            v2x_counters: V2xCounters::ZERO,
            nmea_errors: 0,
            gnss_no_fix: 0,
            gnss_skipped: 0,
            hmi_dropped: 0,
        }
    }

    /// The OBU core.
    pub fn obu(&self) -> &Obu {
        &self.obu
    }

    /// One byte of the GNSS port (NMEA sentences and u-blox UBX frames, mixed or not); a
    /// fix yields the new state.
    pub fn on_gnss_byte(&mut self, now: Instant, byte: u8) -> Option<HmiState> {
        let Self {
            obu,
            gnss,
            nmea_errors,
            gnss_no_fix,
            gnss_skipped,
            ..
        } = self;
        let mut state = None;
        gnss.push(&[byte], |e| match e {
            GnssEvent::Epoch(epoch) => match epoch.outcome {
                Ok(fix) => state = Some(obu.on_fix(now, fix)),
                Err(_) => *gnss_no_fix = gnss_no_fix.wrapping_add(1),
            },
            GnssEvent::NmeaError(_) | GnssEvent::UbxError(_) => {
                *nmea_errors = nmea_errors.wrapping_add(1)
            }
            GnssEvent::Skipped(n) => *gnss_skipped = gnss_skipped.wrapping_add(n as u32),
            _ => {}
        });
        state
    }

    /// One byte of the V2X port; a frame that changes what is stored (maps or zones stored,
    /// replaced or cancelled) yields the new state, as the daemon publishes it; a repeat of
    /// what is stored (the roadside's 10 Hz broadcast) yields nothing. Every frame goes
    /// through the core's one receive path ([`Obu::on_datagram`]).
    pub fn on_v2x_byte(&mut self, msgs: &mut Messages, now: Instant, byte: u8) -> Option<HmiState> {
        let outcome = match self.v2x.push(byte)? {
            Ok(payload) => self.obu.on_datagram(now, payload, msgs),
            Err(e) => V2xOutcome::Dropped(DropReason::from(e)),
        };
        self.v2x_counters.record(outcome);
        match outcome {
            V2xOutcome::Changed(_) => Some(self.obu.state(now)),
            // Routine (four of five PSMs of a known worker): counted, not logged, so that
            // the budget that skips their signature checks is not spent on the log.
            V2xOutcome::Dropped(DropReason::Ingest(IngestReason::Refused(IngestError::NotDue))) => {
                None
            }
            V2xOutcome::Dropped(r) => {
                defmt::warn!("v2x: dropped: {=str}", r.as_str());
                None
            }
            V2xOutcome::Unchanged(_) | V2xOutcome::Repeat(_) | V2xOutcome::Other(_) => None,
        }
    }

    /// Expiry and staleness: call often; a state when something changed.
    pub fn poll(&mut self, now: Instant) -> Option<HmiState> {
        self.obu.poll(now)
    }
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
