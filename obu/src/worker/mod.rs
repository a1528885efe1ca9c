//! Road workers: SAE J2735 PSMs (PersonalSafetyMessage, messageId 32) from the roadside
//! camera, kept for a second and placed relative to the lanes.
//!
//! A roadside camera localizes each road worker and its RSU broadcasts one PSM per worker
//! at 10 Hz: `basicType` `aPUBLICSAFETYWORKER`, a stable 4-octet temporary id, `secMark`,
//! `msgCnt`, position, accuracy, speed and heading. [`Worker::from_psm`] keeps those in
//! 32 bytes (`pathHistory` and the other optional parts are not used);
//! [`WorkerStore`] keeps at most [`MAX_WORKERS`] by id, each until [`WORKER_TIMEOUT`]
//! after its last update. [`place`] puts a worker on the vehicle's own lane (distance along
//! it, lateral offset) and [`near_road`] says whether it stands within a few metres of a
//! vehicle lane; the alerts built from them are in [`crate::Obu`]'s evaluation.
//!
//! Only `aPUBLICSAFETYWORKER` is stored; pedestrians, cyclists, animals, "unavailable" and
//! unknown extension values are rejected as [`IngestError::NotRoadWorker`] (this product
//! warns about the work zone's crew, which the camera reports; a phone's pedestrian PSM is
//! not its business). Every other rejection is an [`IngestError`] too, counted with the MAP
//! and TIM ones ([`crate::Obu::rejected`]).
//!
//! [`MAX_WORKERS`]: crate::capacity::MAX_WORKERS

mod place;
mod store;
#[cfg(test)]
mod tests;

pub use place::{near_road, place, Placement};
pub use store::{WorkerStats, WorkerStore, WorkerUpdate};

use j2735::msg::personal_safety_message::{PersonalDeviceUserType, PersonalSafetyMessage};

use crate::geo::LatLon;
use crate::ingest::IngestError;
use crate::store::Provenance;
use crate::time::{Duration, Instant};

/// A worker not updated for this long is gone (1 s: ten PSMs missed).
pub const WORKER_TIMEOUT: Duration = Duration::from_millis(1000);
/// A worker this close to the own lane's edge counts as in its path, metres.
pub const IN_PATH_MARGIN_M: f32 = 1.0;
/// A worker this close to a vehicle lane's edge (or end) is near the road, metres.
pub const NEAR_ROAD_M: f32 = 3.0;
/// A signed PSM of a stored, verified worker is verified and taken at most this often,
/// unless it changes the worker's alert (into or out of the lane's path ahead, near the
/// road or not): a roadside sends 10 a second per worker and each signature check costs
/// tens of milliseconds on a microcontroller, so the updates that change nothing the
/// driver is told wait for the next one due, and the ones that do are checked at once. At
/// 10 Hz every fifth PSM is due (450 ms, so that a PSM a little early still counts).
pub const VERIFY_INTERVAL: Duration = Duration::from_millis(450);
/// When the store is full, a worker silent this long may be replaced by a new one.
pub const REPLACE_AFTER: Duration = Duration::from_millis(500);

/// `secMark` values from this one up are a leap second (60000..=65534) or "unavailable"
/// (65535): not comparable.
const SEC_MARK_MINUTE: u16 = 60_000;
/// `Velocity` "unavailable".
const SPEED_UNAVAILABLE: u16 = 8191;
/// `Heading` "unavailable".
const HEADING_UNAVAILABLE: u16 = 28_800;
/// `SemiMajorAxisAccuracy` "unavailable".
const ACCURACY_UNAVAILABLE: u8 = 255;

/// A PSM's temporary id (`TemporaryID`, 4 octets).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub struct WorkerId(pub [u8; 4]);

impl WorkerId {
    /// The octets as one big-endian number (how the HMI shows it).
    pub const fn as_u32(self) -> u32 {
        u32::from_be_bytes(self.0)
    }
}

/// One road worker as its last PSM told it: 32 bytes, the units of the message.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Worker {
    heard: Instant,
    position: LatLon,
    id: WorkerId,
    sec_mark: u16,
    /// 0.02 m/s, [`SPEED_UNAVAILABLE`] when unknown.
    speed: u16,
    /// 0.0125 degree, [`HEADING_UNAVAILABLE`] when unknown.
    heading: u16,
    /// Semi-major axis of the position's error ellipse, 0.05 m (254: 12.7 m or more).
    accuracy: u8,
    msg_cnt: u8,
    provenance: Provenance,
}

impl Worker {
    /// The worker a PSM received at `now` describes.
    ///
    /// # Errors
    ///
    /// [`IngestError::NotRoadWorker`] for a `basicType` other than `aPUBLICSAFETYWORKER`,
    /// [`IngestError::InvalidPosition`] for a latitude or longitude "unavailable" (or out of
    /// range), [`IngestError::AccuracyUnavailable`] for a `semiMajor` of 255.
    pub fn from_psm(
        now: Instant,
        psm: &PersonalSafetyMessage,
        provenance: Provenance,
    ) -> Result<Worker, IngestError> {
        if psm.basic_type != PersonalDeviceUserType::APUBLICSAFETYWORKER {
            return Err(IngestError::NotRoadWorker);
        }
        let p = &psm.position;
        let position =
            LatLon::new(p.lat.get(), p.long.get()).ok_or(IngestError::InvalidPosition)?;
        let accuracy = psm.accuracy.semi_major.get();
        if accuracy == ACCURACY_UNAVAILABLE {
            return Err(IngestError::AccuracyUnavailable);
        }
        Ok(Worker {
            heard: now,
            position,
            id: WorkerId(psm.id.0),
            sec_mark: psm.sec_mark.get(),
            speed: psm.speed.get(),
            heading: psm.heading.get(),
            accuracy,
            msg_cnt: psm.msg_cnt.get(),
            provenance,
        })
    }

    /// The temporary id.
    pub fn id(&self) -> WorkerId {
        self.id
    }

    /// When its last PSM was received.
    pub fn heard(&self) -> Instant {
        self.heard
    }

    /// Time since the last PSM at `now` (0 when `now` is earlier).
    pub fn age(&self, now: Instant) -> Duration {
        now.saturating_since(self.heard)
    }

    /// Where the worker stands.
    pub fn position(&self) -> LatLon {
        self.position
    }

    /// Speed, m/s, when known.
    pub fn speed_mps(&self) -> Option<f32> {
        (self.speed < SPEED_UNAVAILABLE).then_some(self.speed as f32 * 0.02)
    }

    /// Heading, degrees clockwise from north, when known.
    pub fn heading_deg(&self) -> Option<f32> {
        (self.heading < HEADING_UNAVAILABLE).then_some(self.heading as f32 * 0.0125)
    }

    /// Semi-major axis of the position's error ellipse, metres.
    pub fn accuracy_m(&self) -> f32 {
        self.accuracy as f32 * 0.05
    }

    /// Whether the PSM came with a verified signature.
    pub fn provenance(&self) -> Provenance {
        self.provenance
    }

    /// Whether this PSM may follow `older` of the same worker: its `secMark` is 1 ms to
    /// 30 s later (modulo the minute). When either `secMark` is a leap second or
    /// "unavailable", anything but an exact repeat (same `secMark` and `msgCnt`) may.
    pub fn follows(&self, older: &Worker) -> bool {
        let (new, old) = (self.sec_mark, older.sec_mark);
        if new >= SEC_MARK_MINUTE || old >= SEC_MARK_MINUTE {
            return new != old || self.msg_cnt != older.msg_cnt;
        }
        let minute = u32::from(SEC_MARK_MINUTE);
        let ahead = (u32::from(new) + minute - u32::from(old)) % minute;
        (1..=30_000).contains(&ahead)
    }
}
