//! The one V2X receive path: received bytes in, what happened out.
//!
//! [`Obu::on_datagram`] takes what the radio (or UDP, or the firmware's serial link)
//! delivered: a bare UPER `MessageFrame`, one in an IEEE 1609.2 envelope, either of them in
//! an IEEE 1609.3 WAVE Short Message (whose PSID must be the message's), or an RSU 4.1 text
//! record (`Version=...`). It unwraps it, peeks the `messageId`, decodes a MAP, TIM or
//! PSM (road worker) into the caller's kept [`V2xReceiver`] (no heap, nothing large on the stack), feeds the
//! core and returns a [`V2xOutcome`]: the state changed (publish it), nothing changed, a
//! message the OBU does not use, or dropped with a [`DropReason`] from a closed set.
//! [`V2xCounters`] counts outcomes in fixed arrays indexed by that set. The daemon and the
//! firmware both call this; the rule "publish on a change" lives here.

mod reason;
#[cfg(test)]
mod tests;

pub use reason::{
    DatagramReason, DecodeReason, DropGroup, DropReason, EnvelopeReason, Ieee1609Reason,
    IngestReason, RsuTextReason, SecurityReason, WsmpReason,
};

use j2735::envelope::ieee1609dot2::{looks_like_ieee1609dot2, Ieee1609Dot2Data, SignedData};
use j2735::envelope::rsu_text::RsuMessage;
use j2735::envelope::wsmp::{looks_like_wsmp, Wsm};
use j2735::envelope::Psid;
use j2735::frame::{decode_message_into, peek_message_id, Message};
use j2735::msg::personal_safety_message::PersonalSafetyMessage;
use j2735::uper::Placeholder;
use j2735::{MapData, TravelerInformation};

use crate::ingest::Ingest;
use crate::security::{Accepted, CheckContext, Identity, SecurityConfig, Trust};
use crate::store::Provenance;
use crate::time::Instant;
use crate::Obu;

/// What [`Obu::on_datagram`] did with one input.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum V2xOutcome {
    /// A MAP, TIM or PSM (its `messageId`) changed what is stored (maps or zones stored,
    /// replaced or cancelled, a new road worker) or what a worker means for the car (an
    /// update into or out of the lane's path ahead, near the road or not): the caller
    /// publishes [`Obu::state`].
    Changed(u16),
    /// A MAP or TIM (its `messageId`) that only refreshed what is stored (a repeat), or a
    /// PSM that moved a known worker without changing its alert (shown with the next fix's
    /// state: a PSM per worker at 10 Hz would otherwise flood the display link).
    Unchanged(u16),
    /// A signed MAP, TIM or PSM (its `messageId`) byte-identical to one accepted before and
    /// still relevant, as an RSU repeats what it was given signed once
    /// ([`Accepted::Repeat`](crate::security::Accepted)): checked for the cost of a hash, no
    /// signature verification; it refreshed what it carries (a zone repeated on the air is
    /// never aged out), and changed nothing else.
    Repeat(u16),
    /// A message the OBU does not use, by `messageId` (its content is not decoded).
    Other(u16),
    /// Not used, for this reason.
    Dropped(DropReason),
}

/// The receive path's kept state: the decode targets of MAP, TIM and PSM, room for an RSU text
/// record's payload of up to `N` octets, and the IEEE 1609.2 [`Trust`] (anchors, the cache
/// of verified certificates, the replay window).
///
/// Each decode target is an empty `heapless::Vec` of capacity 1 until the first message:
/// an empty one is all zeros, so a `static` of this type lands in .bss (zeroed at boot)
/// instead of .data (a copy in flash), as an `Option` (whose `None` is a niche) would.
pub struct V2xReceiver<const N: usize> {
    map: heapless::Vec<MapData, 1>,
    tim: heapless::Vec<TravelerInformation, 1>,
    psm: heapless::Vec<PersonalSafetyMessage, 1>,
    payload: [u8; N],
    trust: Trust,
}

impl<const N: usize> V2xReceiver<N> {
    /// Nothing received yet, the product's security settings
    /// ([`SecurityConfig::DEFAULT`]: signatures required) and no trust anchor; `const` and
    /// all zero bytes, so that firmware can place it in a `static` in .bss.
    pub const fn new() -> Self {
        Self {
            map: heapless::Vec::new(),
            tim: heapless::Vec::new(),
            psm: heapless::Vec::new(),
            payload: [0; N],
            trust: Trust::unconfigured(),
        }
    }

    /// Nothing received yet, with these security settings.
    pub const fn with_security(config: SecurityConfig) -> Self {
        Self {
            map: heapless::Vec::new(),
            tim: heapless::Vec::new(),
            psm: heapless::Vec::new(),
            payload: [0; N],
            trust: Trust::new(config),
        }
    }

    /// The trust policy (to add anchors, read or change its settings).
    pub fn trust_mut(&mut self) -> &mut Trust {
        &mut self.trust
    }

    /// The trust policy.
    pub fn trust(&self) -> &Trust {
        &self.trust
    }
}

impl<const N: usize> Default for V2xReceiver<N> {
    fn default() -> Self {
        Self::new()
    }
}

/// The first (only) element of `v`, made from a placeholder the first time.
fn slot<M: Placeholder>(v: &mut heapless::Vec<M, 1>) -> &mut M {
    if v.is_empty() {
        let _ = v.push(M::placeholder());
    }
    &mut v[0]
}

/// Whether `bytes` are an RSU 4.1 text record rather than binary.
fn is_rsu_text(bytes: &[u8]) -> bool {
    bytes.starts_with(b"Version=")
}

/// The payload octets of the RSU text record `bytes`, written into `out`.
fn rsu_payload<'a>(bytes: &[u8], out: &'a mut [u8]) -> Result<&'a [u8], DropReason> {
    let text = core::str::from_utf8(bytes).map_err(|_| RsuTextReason::NotUtf8)?;
    let record = RsuMessage::parse(text)?;
    let n = record.payload.decode_into(out)?;
    Ok(&out[..n])
}

impl Obu {
    /// Takes one received V2X input (see the [module docs](self)) at `now`; a MAP, TIM or
    /// PSM is checked by `rx`'s [`Trust`] (signed) or its `require_signed` setting (unsigned),
    /// decoded into `rx` and stored. A signed PSM is decoded first and refused as
    /// [`IngestError::NotDue`](crate::ingest::IngestError::NotDue) before its signature
    /// check when it is not due ([`Obu::psm_due`]). A message of which the core refused a
    /// part is [`DropReason`]'s ingest group (the parts it could use are stored, as
    /// [`Obu::on_map`] and [`Obu::on_tim`] say).
    pub fn on_datagram<const N: usize>(
        &mut self,
        now: Instant,
        bytes: &[u8],
        rx: &mut V2xReceiver<N>,
    ) -> V2xOutcome {
        match self.datagram(now, bytes, rx) {
            Ok(outcome) => outcome,
            Err(reason) => V2xOutcome::Dropped(reason),
        }
    }

    fn datagram<const N: usize>(
        &mut self,
        now: Instant,
        bytes: &[u8],
        rx: &mut V2xReceiver<N>,
    ) -> Result<V2xOutcome, DropReason> {
        let V2xReceiver {
            map,
            tim,
            psm,
            payload,
            trust,
        } = rx;
        let bytes = if is_rsu_text(bytes) {
            rsu_payload(bytes, payload)?
        } else {
            bytes
        };
        let (bytes, wsmp_psid) = if looks_like_wsmp(bytes) {
            let wsm = Wsm::parse(bytes)?;
            (wsm.data, Some(wsm.psid))
        } else {
            (bytes, None)
        };
        let (frame, signed) = open_envelope(bytes)?;
        let id = peek_message_id(frame)?;
        let Some(message_psid) = trust.psid_for(id) else {
            self.count_other_message();
            return Ok(V2xOutcome::Other(id));
        };
        if let Some(wsmp) = wsmp_psid {
            let matches = match &signed {
                Some(signed) => signed.header.psid == wsmp,
                // Deployed RSUs forward MAP beside SPaT, with SPaT's PSID.
                None => wsmp == message_psid || (id == MapData::MESSAGE_ID && wsmp == Psid::SPAT),
            };
            if !matches {
                return Err(WsmpReason::PsidMismatch.into());
            }
        }
        // A signed PSM is decoded first: most updates of a known worker are not worth the
        // signature check ([`Obu::psm_due`]).
        let signed_psm = id == PersonalSafetyMessage::MESSAGE_ID && signed.is_some();
        if signed_psm {
            let psm = slot(psm);
            decode_message_into(frame, psm)?;
            self.psm_due(now, psm)?;
        }
        let mut accepted = Accepted::Verified;
        let provenance = match signed {
            Some(signed) => {
                let ctx = CheckContext {
                    message_id: id,
                    now_us: self.time64(now),
                    alt_now_us: self.alt_time64(now),
                    position: self.position(),
                };
                accepted = trust.check(&signed, &ctx)?;
                Provenance::Verified
            }
            None if trust.config().require_signed => return Err(SecurityReason::Unsigned.into()),
            None => Provenance::Unverified,
        };
        // Each decoded message passes the superseded check (signed ones; see
        // `Trust::check_version`) before it is stored.
        let result = if id == MapData::MESSAGE_ID {
            let map = slot(map);
            decode_message_into(frame, map)?;
            if provenance == Provenance::Verified {
                trust.check_version(map_identity(map))?;
            }
            self.ingest_map(now, map, provenance)
        } else if id == PersonalSafetyMessage::MESSAGE_ID {
            let psm = slot(psm);
            if !signed_psm {
                decode_message_into(frame, psm)?;
            }
            if provenance == Provenance::Verified {
                trust.check_version(psm_identity(psm))?;
            }
            self.ingest_psm(now, psm, provenance)
        } else {
            let tim = slot(tim);
            decode_message_into(frame, tim)?;
            let signed_until = match provenance {
                Provenance::Verified => trust.check_version(tim_identity(tim))?,
                _ => None,
            };
            self.ingest_tim(now, tim, provenance, signed_until)
        };
        let report: Ingest = result?;
        if report.stored > 0 || report.cancelled > 0 || report.alert_changed > 0 {
            Ok(V2xOutcome::Changed(id))
        } else if report.refused_unverified > 0 {
            Err(IngestReason::UnverifiedOverVerified.into())
        } else if accepted == Accepted::Repeat {
            Ok(V2xOutcome::Repeat(id))
        } else {
            Ok(V2xOutcome::Unchanged(id))
        }
    }
}

/// The `MessageFrame` in `bytes` (bare, or in IEEE 1609.2 data) and the signed data around
/// it, if signed.
fn open_envelope(bytes: &[u8]) -> Result<(&[u8], Option<SignedData<'_>>), DropReason> {
    if !looks_like_ieee1609dot2(bytes) {
        return Ok((bytes, None));
    }
    let data = Ieee1609Dot2Data::parse(bytes)?;
    let frame = data.application_data().ok_or(Ieee1609Reason::NoPlaintext)?;
    Ok((frame, data.signed_data().copied()))
}

/// Counts of [`V2xOutcome`]s: drops in a fixed array indexed by [`DropReason::index`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct V2xCounters {
    /// MAP or TIM that changed what is stored.
    pub changed: u32,
    /// MAP or TIM that only refreshed what is stored.
    pub unchanged: u32,
    /// Signed messages that were repeats of accepted ones ([`V2xOutcome::Repeat`]).
    pub repeats: u32,
    /// Messages the OBU does not use.
    pub other: u32,
    /// Drops, by [`DropReason::index`].
    pub dropped: [u32; DropReason::COUNT],
}

impl V2xCounters {
    /// All zero.
    pub const ZERO: Self = Self {
        changed: 0,
        unchanged: 0,
        repeats: 0,
        other: 0,
        dropped: [0; DropReason::COUNT],
    };

    /// Counts one outcome.
    pub fn record(&mut self, outcome: V2xOutcome) {
        let n = match outcome {
            V2xOutcome::Changed(_) => &mut self.changed,
            V2xOutcome::Unchanged(_) => &mut self.unchanged,
            V2xOutcome::Repeat(_) => &mut self.repeats,
            V2xOutcome::Other(_) => &mut self.other,
            V2xOutcome::Dropped(r) => &mut self.dropped[r.index()],
        };
        *n = n.saturating_add(1);
    }

    /// Drops for `reason`.
    pub fn dropped(&self, reason: DropReason) -> u32 {
        self.dropped[reason.index()]
    }

    /// Drops of every reason in `group`.
    pub fn dropped_in(&self, group: DropGroup) -> u32 {
        DropReason::ALL
            .iter()
            .filter(|r| r.group() == group)
            .fold(0u32, |a, r| a.saturating_add(self.dropped(*r)))
    }

    /// Every input counted.
    pub fn total(&self) -> u32 {
        let taken = self
            .changed
            .saturating_add(self.unchanged)
            .saturating_add(self.repeats)
            .saturating_add(self.other);
        self.dropped.iter().fold(taken, |a, &b| a.saturating_add(b))
    }
}

impl Default for V2xCounters {
    fn default() -> Self {
        Self::ZERO
    }
}

/// The identity of a TIM for the superseded check: its `packetID`, else the digest of its
/// first data frame's `msgId` (the key its zones are stored under).
fn tim_identity(tim: &TravelerInformation) -> Identity {
    match tim.data_frames.first() {
        Some(frame) => {
            let key = crate::ingest::tim::key(tim, frame, 0);
            let mut id = [0u8; 10];
            id[..9].copy_from_slice(&key.packet_id);
            id[9] = key.source as u8;
            Identity::of(b'T', &id)
        }
        None => Identity::of(b'T', &[]),
    }
}

/// The identity of a MAP: its intersections' and road segments' ids (region and id), up to
/// the first 12 of them.
fn map_identity(map: &MapData) -> Identity {
    let intersections = map
        .intersections
        .iter()
        .flat_map(|l| l.iter())
        .map(|g| (b'I', g.id.region.map_or(0, |r| r.get()), g.id.id.get()));
    let segments = map
        .road_segments
        .iter()
        .flat_map(|l| l.iter())
        .map(|s| (b'S', s.id.region.map_or(0, |r| r.get()), s.id.id.get()));
    let mut id = [0u8; Identity::MAX_ID];
    let mut n = 0;
    for (kind, region, number) in intersections.chain(segments).take(Identity::MAX_ID / 5) {
        id[n] = kind;
        id[n + 1..n + 3].copy_from_slice(&region.to_be_bytes());
        id[n + 3..n + 5].copy_from_slice(&number.to_be_bytes());
        n += 5;
    }
    Identity::of(b'M', &id[..n])
}

/// The identity of a PSM: its sender's temporary id.
fn psm_identity(psm: &PersonalSafetyMessage) -> Identity {
    Identity::of(b'P', &psm.id.0)
}
