//! Decoded J2735 messages into the core's model: MAP -> [`LaneModel`]s, TIM ->
//! [`WorkZone`]s.
//!
//! [`LaneModel`]: crate::lane::LaneModel
//! [`WorkZone`]: crate::zone::WorkZone
//!
//! The functions take the decoded values by reference (a no-heap `MapData` is megabytes)
//! and fill the stores' slots in place; nothing large is copied or put on the stack.
//! [`crate::Obu::on_map`], [`crate::Obu::on_tim`] and [`crate::Obu::on_frame`] are the
//! entry points; they return an [`Ingest`] report or the [`IngestError`] of the first part
//! that was rejected, and count every rejected part by reason ([`IngestCounters`]).
//!
//! What is kept, per message:
//! * MAP ([`map`]): every intersection and road segment (up to
//!   [`MAX_MAPS`](crate::capacity::MAX_MAPS) per message) becomes a lane model; every
//!   lane a centreline with per-node width (`laneWidth` plus the cumulative `dWidth`),
//!   its direction (`directionalUse`), type, connections and speed limits (the model's
//!   `speedLimits`, and a node's `LaneDataAttribute` `speedLimits` from that node on).
//!   Node offsets of every kind (node-XY1..6 from the previous node, node-LatLon
//!   absolute) and computed lanes (reference lane moved, rotated and scaled) are placed.
//! * TIM ([`tim`]): every data frame becomes a work zone keyed by `packetID` (or the
//!   frame's `msgId`) and frame index, with its validity window, priority, content
//!   ([`itis`]) and regions: paths (node-XY, node-LL, node-LatLon or computed, with the
//!   `scale` zoom), circles (geometry and old-style regions), lane width,
//!   directionality, heading slice and `closedPath`.
//!
//! Polylines longer than the node capacities are thinned (the node whose removal moves
//! the line least goes first) and counted in [`Ingest::thinned`]; regions, models and
//! connections beyond the capacities are left out and counted in [`Ingest::truncated`].

pub mod itis;
pub mod map;
mod nodes;
#[cfg(test)]
mod testdata;
pub mod tim;

use crate::store::Provenance;
use core::fmt;

#[cfg(feature = "serde")]
use serde::{Deserialize, Serialize};

use crate::lane::ModelError;

/// Why part of a MAP or TIM (a lane model, lane, work zone or region), or a PSM (a road
/// worker), was not used.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(Serialize, Deserialize))]
#[non_exhaustive]
pub enum IngestError {
    /// A reference position (MAP `refPoint`, TIM `anchor`, circle centre) is missing,
    /// "unavailable" or out of range.
    InvalidReference,
    /// A node offset the core cannot place (a regional extension, or a node list
    /// alternative added after J2735 2020).
    UnsupportedNode,
    /// A region without a description the core can use (none, or an extension).
    NoGeometry,
    /// A computed lane or path whose reference lane is not in the lane model.
    ReferenceLaneMissing,
    /// A TIM computed path whose MAP (the region's `id`) is not stored; the zone is
    /// dropped and converted again when the TIM is next heard.
    ReferenceMapMissing,
    /// A lane id used twice in one lane model.
    DuplicateLane,
    /// More than the capacities hold even after thinning (e.g. a lane model with more
    /// than [`MAX_LANES`](crate::capacity::MAX_LANES) lanes).
    CapacityExceeded,
    /// A value out of range or not finite after conversion.
    InvalidValue,
    /// A PSM of a personal device other than a road worker (`basicType` not
    /// `aPUBLICSAFETYWORKER`: pedestrian, cyclist, animal, unavailable, extension).
    NotRoadWorker,
    /// A PSM whose position is "unavailable" or out of range.
    InvalidPosition,
    /// A PSM whose position accuracy (`semiMajor`) is "unavailable".
    AccuracyUnavailable,
    /// A PSM whose `secMark` does not follow the stored one of its worker (older, or a
    /// repeat).
    StaleMessage,
    /// A PSM of a new worker while the worker store is full and no stored worker may be
    /// replaced ([`crate::worker::WorkerStore`]).
    StoreFull,
    /// A signed PSM of a stored, verified worker that arrived less than
    /// [`VERIFY_INTERVAL`](crate::worker::VERIFY_INTERVAL) after its last update and would
    /// not change the worker's alert: not worth a signature check ([`crate::Obu::psm_due`]).
    NotDue,
}

impl IngestError {
    /// Every reason, in [`IngestError::index`] order.
    pub const ALL: [IngestError; 14] = [
        IngestError::InvalidReference,
        IngestError::UnsupportedNode,
        IngestError::NoGeometry,
        IngestError::ReferenceLaneMissing,
        IngestError::ReferenceMapMissing,
        IngestError::DuplicateLane,
        IngestError::CapacityExceeded,
        IngestError::InvalidValue,
        IngestError::NotRoadWorker,
        IngestError::InvalidPosition,
        IngestError::AccuracyUnavailable,
        IngestError::StaleMessage,
        IngestError::StoreFull,
        IngestError::NotDue,
    ];
    /// The number of reasons.
    pub const COUNT: usize = Self::ALL.len();

    /// Position in [`IngestError::ALL`].
    pub const fn index(self) -> usize {
        match self {
            IngestError::InvalidReference => 0,
            IngestError::UnsupportedNode => 1,
            IngestError::NoGeometry => 2,
            IngestError::ReferenceLaneMissing => 3,
            IngestError::ReferenceMapMissing => 4,
            IngestError::DuplicateLane => 5,
            IngestError::CapacityExceeded => 6,
            IngestError::InvalidValue => 7,
            IngestError::NotRoadWorker => 8,
            IngestError::InvalidPosition => 9,
            IngestError::AccuracyUnavailable => 10,
            IngestError::StaleMessage => 11,
            IngestError::StoreFull => 12,
            IngestError::NotDue => 13,
        }
    }
}

impl From<ModelError> for IngestError {
    fn from(e: ModelError) -> Self {
        match e {
            ModelError::CapacityExceeded => IngestError::CapacityExceeded,
            ModelError::DuplicateLane => IngestError::DuplicateLane,
            _ => IngestError::InvalidValue,
        }
    }
}

impl IngestError {
    /// A short lowercase name, for counters and logs.
    pub const fn as_str(self) -> &'static str {
        match self {
            IngestError::InvalidReference => "invalid reference position",
            IngestError::UnsupportedNode => "unsupported node offset",
            IngestError::NoGeometry => "region without usable geometry",
            IngestError::ReferenceLaneMissing => "reference lane missing",
            IngestError::ReferenceMapMissing => "reference map not stored",
            IngestError::DuplicateLane => "duplicate lane id",
            IngestError::CapacityExceeded => "capacity exceeded",
            IngestError::InvalidValue => "invalid value",
            IngestError::NotRoadWorker => "PSM: not a road worker",
            IngestError::InvalidPosition => "PSM: position unavailable",
            IngestError::AccuracyUnavailable => "PSM: accuracy unavailable",
            IngestError::StaleMessage => "PSM: stale secMark",
            IngestError::StoreFull => "PSM: worker store full",
            IngestError::NotDue => "PSM: update not due for verification",
        }
    }
}

impl fmt::Display for IngestError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.as_str())
    }
}

impl core::error::Error for IngestError {}

/// Rejected parts counted by reason.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
#[cfg_attr(feature = "serde", derive(Serialize, Deserialize))]
pub struct IngestCounters {
    counts: [u32; IngestError::ALL.len()],
}

impl IngestCounters {
    /// All zero.
    pub const ZERO: IngestCounters = IngestCounters {
        counts: [0; IngestError::ALL.len()],
    };

    /// Parts rejected for `reason`.
    pub fn get(&self, reason: IngestError) -> u32 {
        self.counts[reason.index()]
    }

    /// Parts rejected for any reason.
    pub fn total(&self) -> u32 {
        self.counts.iter().fold(0u32, |a, &b| a.saturating_add(b))
    }

    /// Counts one rejected part.
    pub fn add(&mut self, reason: IngestError) {
        let c = &mut self.counts[reason.index()];
        *c = c.saturating_add(1);
    }

    /// Adds every count of `other`.
    pub fn merge(&mut self, other: &IngestCounters) {
        for (a, b) in self.counts.iter_mut().zip(other.counts.iter()) {
            *a = a.saturating_add(*b);
        }
    }
}

/// What a received message was.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
#[cfg_attr(feature = "serde", derive(Serialize, Deserialize))]
pub enum MessageKind {
    /// MapData (messageId 18).
    #[default]
    Map,
    /// TravelerInformation (messageId 31).
    Tim,
    /// PersonalSafetyMessage (messageId 32): a road worker.
    Psm,
    /// Any other message, by messageId (counted, not used).
    Other(u16),
}

/// What one message changed.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
#[cfg_attr(feature = "serde", derive(Serialize, Deserialize))]
pub struct Ingest {
    /// The message.
    pub message: MessageKind,
    /// Lane models or work zones stored or replaced; road workers new to the store.
    pub stored: u8,
    /// Lane models or work zones already stored with the same revision (MAP) or
    /// `msgCnt` and start time (TIM): only their age was refreshed. Road workers updated
    /// whose alert stays the same (moved: shown from the next state on).
    pub unchanged: u8,
    /// Road workers updated whose alert changed: one stepped into the own lane's path
    /// ahead or out of it, or came near the road or left it. A new state is due now, not
    /// at the next fix.
    pub alert_changed: u8,
    /// Work zones cancelled by `durationTime` 0.
    pub cancelled: u8,
    /// Work zones older (start time) than the stored version: ignored.
    pub stale: u8,
    /// Lanes or paths thinned to fit the node capacities.
    pub thinned: u8,
    /// Models, regions or connections left out because a capacity was full.
    pub truncated: u8,
    /// Parts rejected (lane models, lanes, work zones, regions), each counted by reason.
    pub rejected: u8,
    /// Lane models or work zones left alone because this unverified message would have
    /// replaced, refreshed, cancelled or evicted one that came verified.
    pub refused_unverified: u8,
}

impl Ingest {
    /// An empty report for a message of `kind`.
    pub const fn new(kind: MessageKind) -> Self {
        Ingest {
            message: kind,
            stored: 0,
            unchanged: 0,
            alert_changed: 0,
            cancelled: 0,
            stale: 0,
            thinned: 0,
            truncated: 0,
            rejected: 0,
            refused_unverified: 0,
        }
    }
}

/// Collects the report and the rejected parts while one message is converted.
#[derive(Debug, Default)]
pub(crate) struct Sink {
    pub(crate) report: Ingest,
    /// Where the message came from (verified or not).
    pub(crate) provenance: Provenance,
    pub(crate) counters: IngestCounters,
    first: Option<IngestError>,
}

impl Sink {
    /// A sink for a message of `kind`.
    pub(crate) fn new(kind: MessageKind, provenance: Provenance) -> Self {
        Sink {
            report: Ingest::new(kind),
            provenance,
            counters: IngestCounters::ZERO,
            first: None,
        }
    }

    /// Records a rejected part.
    pub(crate) fn reject(&mut self, reason: IngestError) {
        self.report.rejected = self.report.rejected.saturating_add(1);
        self.counters.add(reason);
        self.first.get_or_insert(reason);
    }

    /// Counts one item left out for capacity.
    pub(crate) fn truncated(&mut self) {
        self.report.truncated = self.report.truncated.saturating_add(1);
    }

    /// Counts one thinned polyline.
    pub(crate) fn thinned(&mut self) {
        self.report.thinned = self.report.thinned.saturating_add(1);
    }

    /// The report, or the first rejection.
    pub(crate) fn finish(self) -> Result<Ingest, IngestError> {
        match self.first {
            Some(e) => Err(e),
            None => Ok(self.report),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counters_and_sink() {
        for (i, e) in IngestError::ALL.iter().enumerate() {
            assert_eq!(e.index(), i);
        }
        let mut s = Sink::new(MessageKind::Tim, Provenance::Verified);
        s.thinned();
        assert_eq!(s.finish().map(|r| r.thinned), Ok(1));
        let mut s = Sink::new(MessageKind::Map, Provenance::Verified);
        s.reject(IngestError::UnsupportedNode);
        s.reject(IngestError::DuplicateLane);
        let mut c = IngestCounters::ZERO;
        c.merge(&s.counters);
        assert_eq!((c.total(), c.get(IngestError::DuplicateLane)), (2, 1));
        assert_eq!(s.finish(), Err(IngestError::UnsupportedNode));
        assert_eq!(
            IngestError::from(ModelError::DuplicateLane),
            IngestError::DuplicateLane
        );
    }
}
