//! The one V2X receive path: received bytes in, what happened out.
//!
//! [`Obu::on_datagram`] takes what the radio (or UDP, or the firmware's serial link)
//! delivered: a bare UPER `MessageFrame`, one in an IEEE 1609.2 envelope, or an RSU 4.1
//! text record (`Version=...`). It unwraps it, peeks the `messageId`, decodes a MAP or TIM
//! into the caller's kept [`V2xScratch`] (no heap, nothing large on the stack), feeds the
//! core and returns a [`V2xOutcome`]: the state changed (publish it), nothing changed, a
//! message the OBU does not use, or dropped with a [`DropReason`] from a closed set.
//! [`V2xCounters`] counts outcomes in fixed arrays indexed by that set. The daemon and the
//! firmware both call this; the rule "publish on a change" lives here.

mod reason;
#[cfg(test)]
mod tests;

pub use reason::{DropGroup, DropReason};

use j2735::envelope::rsu_text::RsuMessage;
use j2735::envelope::unwrap_message_frame;
use j2735::frame::{decode_message_into, peek_message_id, Message};
use j2735::uper::Placeholder;
use j2735::{MapData, TravelerInformation};

use crate::ingest::Ingest;
use crate::time::Instant;
use crate::Obu;

/// What [`Obu::on_datagram`] did with one input.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum V2xOutcome {
    /// A MAP or TIM (its `messageId`) changed what is stored (maps or zones stored,
    /// replaced or cancelled): the caller publishes [`Obu::state`].
    Changed(u16),
    /// A MAP or TIM (its `messageId`) that only refreshed what is stored (a repeat).
    Unchanged(u16),
    /// A message the OBU does not use, by `messageId` (its content is not decoded).
    Other(u16),
    /// Not used, for this reason.
    Dropped(DropReason),
}

/// The kept decode targets of MAP and TIM, and room for an RSU text record's payload of
/// up to `N` octets.
///
/// Each target is an empty `heapless::Vec` of capacity 1 until the first message: an
/// empty one is all zeros, so a `static` of this type lands in .bss (zeroed at boot)
/// instead of .data (a copy in flash), as an `Option` (whose `None` is a niche) would.
pub struct V2xScratch<const N: usize> {
    map: heapless::Vec<MapData, 1>,
    tim: heapless::Vec<TravelerInformation, 1>,
    payload: [u8; N],
}

impl<const N: usize> V2xScratch<N> {
    /// Nothing received yet; `const` so that firmware can place it in a `static`.
    pub const fn new() -> Self {
        Self {
            map: heapless::Vec::new(),
            tim: heapless::Vec::new(),
            payload: [0; N],
        }
    }
}

impl<const N: usize> Default for V2xScratch<N> {
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
    let text = core::str::from_utf8(bytes).map_err(|_| DropReason::RsuNotUtf8)?;
    let record = RsuMessage::parse(text).map_err(DropReason::from_rsu_text)?;
    let n = record
        .payload
        .decode_into(out)
        .map_err(DropReason::from_hex)?;
    Ok(&out[..n])
}

impl Obu {
    /// Takes one received V2X input (see the [module docs](self)) at `now`; MAP and TIM
    /// are decoded into `scratch` and stored. A MAP or TIM of which the core refused a
    /// part is [`DropReason`]'s ingest group (the parts it could use are stored, as
    /// [`Obu::on_map`] and [`Obu::on_tim`] say).
    pub fn on_datagram<const N: usize>(
        &mut self,
        now: Instant,
        bytes: &[u8],
        scratch: &mut V2xScratch<N>,
    ) -> V2xOutcome {
        match self.datagram(now, bytes, scratch) {
            Ok(outcome) => outcome,
            Err(reason) => V2xOutcome::Dropped(reason),
        }
    }

    fn datagram<const N: usize>(
        &mut self,
        now: Instant,
        bytes: &[u8],
        scratch: &mut V2xScratch<N>,
    ) -> Result<V2xOutcome, DropReason> {
        let V2xScratch { map, tim, payload } = scratch;
        let frame = if is_rsu_text(bytes) {
            rsu_payload(bytes, payload)?
        } else {
            unwrap_message_frame(bytes)
                .map_err(DropReason::from_unwrap)?
                .frame
        };
        let id = peek_message_id(frame).map_err(DropReason::from_decode)?;
        let result = match id {
            MapData::MESSAGE_ID => {
                let map = slot(map);
                decode_message_into(frame, map).map_err(DropReason::from_decode)?;
                self.on_map(now, map)
            }
            TravelerInformation::MESSAGE_ID => {
                let tim = slot(tim);
                decode_message_into(frame, tim).map_err(DropReason::from_decode)?;
                self.on_tim(now, tim)
            }
            other => {
                self.count_other_message();
                return Ok(V2xOutcome::Other(other));
            }
        };
        let report: Ingest = result.map_err(DropReason::from_ingest)?;
        Ok(if report.stored > 0 || report.cancelled > 0 {
            V2xOutcome::Changed(id)
        } else {
            V2xOutcome::Unchanged(id)
        })
    }
}

/// Counts of [`V2xOutcome`]s: drops in a fixed array indexed by [`DropReason::index`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct V2xCounters {
    /// MAP or TIM that changed what is stored.
    pub changed: u32,
    /// MAP or TIM that only refreshed what is stored.
    pub unchanged: u32,
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
        other: 0,
        dropped: [0; DropReason::COUNT],
    };

    /// Counts one outcome.
    pub fn record(&mut self, outcome: V2xOutcome) {
        let n = match outcome {
            V2xOutcome::Changed(_) => &mut self.changed,
            V2xOutcome::Unchanged(_) => &mut self.unchanged,
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
            .saturating_add(self.other);
        self.dropped.iter().fold(taken, |a, &b| a.saturating_add(b))
    }
}

impl Default for V2xCounters {
    fn default() -> Self {
        Self::ZERO
    }
}
