//! Decoded J2735 messages into the stores: [`Obu::on_frame`], [`Obu::on_map`],
//! [`Obu::on_tim`], [`Obu::on_psm`].

use j2735::msg::map_data::MapData;
use j2735::msg::message_frame::{MessageFrame, MessageFrameValue};
use j2735::msg::personal_safety_message::PersonalSafetyMessage;
use j2735::msg::traveler_information::{TravelerDataFrame, TravelerInformation};

use super::{Obu, Stored};
use crate::capacity::MAX_MAPS;
use crate::ingest::{
    self, map::ModelSource, Ingest, IngestCounters, IngestError, MessageKind, Sink,
};
use crate::store::Provenance;
use crate::time::Instant;
use crate::worker::{Worker, WorkerUpdate};

impl Obu {
    /// Takes one decoded MessageFrame: a MAP, TIM or PSM is stored (see [`Obu::on_map`],
    /// [`Obu::on_tim`] and [`Obu::on_psm`]); any other message is counted
    /// ([`crate::alert::Counters::other_messages`]) and reported as
    /// [`MessageKind::Other`].
    pub fn on_frame(&mut self, now: Instant, frame: &MessageFrame) -> Result<Ingest, IngestError> {
        match &frame.value {
            MessageFrameValue::MapData(map) => self.on_map(now, map),
            MessageFrameValue::TravelerInformation(tim) => self.on_tim(now, tim),
            MessageFrameValue::PersonalSafetyMessage(psm) => self.on_psm(now, psm),
            other => {
                self.count_other_message();
                Ok(Ingest::new(MessageKind::Other(other.id().get())))
            }
        }
    }

    /// Counts a message the core does not use ([`crate::alert::Counters::other_messages`]).
    pub(crate) fn count_other_message(&mut self) {
        self.counters.other_messages = self.counters.other_messages.saturating_add(1);
    }

    /// Stores every intersection and road segment of a decoded MAP as a lane model
    /// (a model whose id is stored with the same revision is only refreshed; at most
    /// [`MAX_MAPS`] per message, the rest counted as truncated). Work zones are
    /// associated again with the new lanes.
    ///
    /// Parts that cannot be converted (a model with an invalid reference point, a lane
    /// with an unsupported node) are left out while the rest is stored; each is
    /// counted by reason ([`Obu::rejected`]) and the first reason is returned as the
    /// error. `Ok` reports what was stored.
    pub fn on_map(&mut self, now: Instant, map: &MapData) -> Result<Ingest, IngestError> {
        self.ingest_map(now, map, Provenance::Verified)
    }

    /// [`Obu::on_map`] for a message of `provenance`.
    pub(crate) fn ingest_map(
        &mut self,
        now: Instant,
        map: &MapData,
        provenance: Provenance,
    ) -> Result<Ingest, IngestError> {
        let mut sink = Sink::new(MessageKind::Map, provenance);
        for (i, src) in ingest::map::models(map).enumerate() {
            if i < MAX_MAPS {
                self.map_model(now, &src, &mut sink);
            } else {
                sink.truncated();
            }
        }
        self.finish(sink)
    }

    fn map_model(&mut self, now: Instant, src: &ModelSource<'_>, sink: &mut Sink) {
        let (reference, elevation) = match src.reference() {
            Ok(r) => r,
            Err(e) => {
                self.counters.maps_rejected = self.counters.maps_rejected.saturating_add(1);
                return sink.reject(e);
            }
        };
        let map = (src.id, src.revision, reference, elevation);
        let stored = self.store_map(now, map, sink.provenance, |m| {
            ingest::map::fill_model(m, src, sink);
            Ok::<(), IngestError>(())
        });
        sink.count(stored);
    }

    /// Stores every data frame of a decoded TIM as a work zone keyed by `packetID` (or
    /// the frame's `msgId`) and frame index. A zone stored with the same `msgCnt` and
    /// start time is only refreshed, an older start time is ignored, `durationTime` 0
    /// removes it, anything else replaces it.
    ///
    /// Regions that cannot be converted are left out (the zone keeps the others); a
    /// computed path whose MAP is not stored yet drops the whole zone, so that the next
    /// copy of the TIM converts it again. Each rejected part is counted by reason and
    /// the first reason is returned as the error.
    pub fn on_tim(
        &mut self,
        now: Instant,
        tim: &TravelerInformation,
    ) -> Result<Ingest, IngestError> {
        self.ingest_tim(now, tim, Provenance::Verified, None)
    }

    /// [`Obu::on_tim`] for a message of `provenance`, whose signature (if any) stops being
    /// relevant at `signed_until_us` (`Time64`): its zones are shown until then at most.
    pub(crate) fn ingest_tim(
        &mut self,
        now: Instant,
        tim: &TravelerInformation,
        provenance: Provenance,
        signed_until_us: Option<u64>,
    ) -> Result<Ingest, IngestError> {
        let mut sink = Sink::new(MessageKind::Tim, provenance);
        for (i, frame) in tim.data_frames.iter().enumerate() {
            self.tim_frame(now, (tim, i, frame), signed_until_us, &mut sink);
        }
        self.finish(sink)
    }

    fn tim_frame(
        &mut self,
        now: Instant,
        (tim, index, frame): (&TravelerInformation, usize, &TravelerDataFrame),
        signed_until_us: Option<u64>,
        sink: &mut Sink,
    ) {
        let key = ingest::tim::key(tim, frame, index);
        let validity = ingest::tim::validity(frame);
        let msg_cnt = tim.msg_cnt.get();
        let provenance = sink.provenance;
        let stored = self.store_zone(now, key, (msg_cnt, validity), provenance, |zone, maps| {
            ingest::tim::fill_zone(zone, frame, maps, sink)
        });
        // The zone as this message carried it (new or refreshed): bounded by its signature.
        if matches!(stored, Ok(Stored::Filled | Stored::Unchanged)) {
            self.zones.set_signed_until(&key, signed_until_us);
        }
        sink.count(stored);
    }

    /// Stores the road worker a decoded PSM describes ([`crate::worker`]): a worker new to
    /// the store is reported as `stored`, an update of a known one as `alert_changed` when
    /// the alert it raises changed (a state is due now) and as `unchanged` otherwise (it is
    /// shown from the next state on), an unverified PSM over a verified worker as
    /// `refused_unverified`. A PSM that is not a road worker's, has no position or
    /// accuracy, is older than the stored one or finds the store full is counted by reason
    /// ([`Obu::rejected`]) and returned as the error.
    pub fn on_psm(
        &mut self,
        now: Instant,
        psm: &PersonalSafetyMessage,
    ) -> Result<Ingest, IngestError> {
        self.ingest_psm(now, psm, Provenance::Verified)
    }

    /// [`Obu::on_psm`] for a message of `provenance`.
    pub(crate) fn ingest_psm(
        &mut self,
        now: Instant,
        psm: &PersonalSafetyMessage,
        provenance: Provenance,
    ) -> Result<Ingest, IngestError> {
        let mut sink = Sink::new(MessageKind::Psm, provenance);
        let vehicle = self.position();
        let worker = Worker::from_psm(now, psm, provenance);
        let changes_alert = worker
            .as_ref()
            .ok()
            .and_then(|w| self.stored_worker(w))
            .is_some_and(|(_, changes)| changes);
        let stored = worker.and_then(|w| self.workers.update(w, vehicle));
        let r = &mut sink.report;
        let count = match stored {
            Ok(WorkerUpdate::New | WorkerUpdate::Evicted) => &mut r.stored,
            Ok(WorkerUpdate::Updated) if changes_alert => &mut r.alert_changed,
            Ok(WorkerUpdate::Updated) => &mut r.unchanged,
            Ok(WorkerUpdate::Refused) => &mut r.refused_unverified,
            Err(e) => {
                sink.reject(e);
                return self.finish(sink);
            }
        };
        *count = count.saturating_add(1);
        self.finish(sink)
    }

    /// Whether a decoded, signed PSM is worth its signature check at `now`: a new worker, one
    /// stored unverified, one last updated [`VERIFY_INTERVAL`] ago or more, or an update
    /// that changes the worker's alert. Otherwise the PSM is counted and refused as
    /// [`IngestError::NotDue`] before any cryptography (the next one due carries the move).
    ///
    /// # Errors
    ///
    /// [`IngestError::NotDue`].
    ///
    /// [`VERIFY_INTERVAL`]: crate::worker::VERIFY_INTERVAL
    pub fn psm_due(
        &mut self,
        now: Instant,
        psm: &PersonalSafetyMessage,
    ) -> Result<(), IngestError> {
        let Ok(w) = Worker::from_psm(now, psm, Provenance::Verified) else {
            // Refused with its own reason once checked.
            return Ok(());
        };
        let Some((old, changes_alert)) = self.stored_worker(&w) else {
            return Ok(());
        };
        let due = old.provenance() != Provenance::Verified
            || old.age(now) >= crate::worker::VERIFY_INTERVAL
            || changes_alert;
        if due {
            return Ok(());
        }
        self.rejected.add(IngestError::NotDue);
        Err(IngestError::NotDue)
    }

    /// Parts of MAP and TIM messages, and PSMs, rejected so far, by reason.
    pub fn rejected(&self) -> &IngestCounters {
        &self.rejected
    }

    fn finish(&mut self, sink: Sink) -> Result<Ingest, IngestError> {
        self.rejected.merge(&sink.counters);
        sink.finish()
    }
}

impl Sink {
    /// Counts what storing one lane model or work zone did.
    fn count(&mut self, stored: Result<Stored, IngestError>) {
        let r = &mut self.report;
        let count = match stored {
            Ok(Stored::Filled) => &mut r.stored,
            Ok(Stored::Unchanged) => &mut r.unchanged,
            Ok(Stored::Stale) => &mut r.stale,
            Ok(Stored::Cancelled(true)) => &mut r.cancelled,
            // A zone whose window ended is removed as a cancelled one is.
            Ok(Stored::Ended(true)) => &mut r.cancelled,
            // The cancellation or the ended window of a zone not stored (a repeat of one
            // already applied).
            Ok(Stored::Cancelled(false) | Stored::Ended(false)) => &mut r.unchanged,
            Ok(Stored::Refused) => &mut r.refused_unverified,
            Err(e) => return self.reject(e),
        };
        *count = count.saturating_add(1);
    }
}
