//! [`Obu`]: the facade that the daemon, the firmware and the simulator drive.
//!
//! Sans-IO: `on_fix(now, fix)` returns the [`HmiState`] for that fix, `poll(now)`
//! expires data and reports a stale GNSS, `next_deadline()` says when `poll` has work.
//! Decoded J2735 messages enter through [`Obu::on_frame`] (or [`Obu::on_map`],
//! [`Obu::on_tim`] and [`Obu::on_psm`]); models built by other means through [`Obu::update_map`] and
//! [`Obu::update_zone`], whose closures fill the model in place.

mod evaluate;
mod messages;
mod motion;
mod workers;

use crate::alert::{AlertConfig, Counters, HmiState, PositionSource};
use crate::clock::{ClockCheck, TimeStatus};
use crate::fix::Fix;
use crate::geo::LatLon;
use crate::ingest::IngestCounters;
use crate::lane::{LaneModel, MapId, MapStore, MapUpdate};
use crate::matcher::{LaneMatch, Matcher};
use crate::store::Provenance;
use crate::time::{Duration, Instant, UtcTime};
use crate::worker::WorkerStore;
use crate::zone::{self, Validity, WorkZone, ZoneKey, ZoneStore, ZoneUpdate};

/// What [`Obu::store_zone`] did.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Stored {
    /// Filled (new or replaced).
    Filled,
    /// Same version as stored.
    Unchanged,
    /// Older than the stored version.
    Stale,
    /// Cancelled (`true` when a stored zone was removed).
    Cancelled(bool),
    /// Its own window had ended (`true` when the stored version was removed).
    Ended(bool),
    /// Unverified over verified: left alone.
    Refused,
}

/// A dead-reckoned position is published this often.
pub const ESTIMATE_PERIOD: Duration = Duration::from_millis(100);

/// The on-board unit core: no heap, under its 64 KiB RAM budget with the default
/// capacities (asserted below; `obu/ram-probe` prints its size on the firmware target, and the
/// core README's Measured table has it); `new` is `const` so firmware can place it in a
/// `static`.
#[derive(Debug, Clone)]
pub struct Obu {
    config: AlertConfig,
    maps: MapStore,
    zones: ZoneStore,
    /// Road workers from PSMs.
    workers: WorkerStore,
    matcher: Matcher,
    last_fix: Option<(Instant, Fix)>,
    /// The matcher's clock at the last fix (see [`Obu::fix_time`]).
    fix_clock: Instant,
    last_match: Option<LaneMatch>,
    /// The last fix's UTC after the rollover and reference checks.
    utc: Option<(Instant, UtcTime)>,
    /// Whether `utc` may be believed.
    time_status: TimeStatus,
    /// The reference clock GNSS time is checked against.
    clock: ClockCheck,
    /// The receiver's fix period, milliseconds (the matcher clock's last step).
    fix_period_ms: u32,
    /// The last vehicle speed (CAN) and when it came.
    vehicle_speed: Option<(Instant, f32)>,
    /// Distance travelled since the last fix, for dead reckoning.
    travel: motion::Travel,
    stale_reported: bool,
    /// "Position lost" (the dead-reckoning horizon passed) was published.
    lost_reported: bool,
    /// When the next dead-reckoned state is due.
    next_estimate: Option<Instant>,
    /// The last state published from a fix or a poll was urgent (its release needs a
    /// margin: [`crate::alert::URGENT_RELEASE`]).
    was_urgent: bool,
    counters: Counters,
    rejected: IngestCounters,
}

// The static RAM budget holds on every target the crate is built for (the firmware's
// included: `obu/ram-probe` prints the figure for thumbv7em-none-eabihf).
const _: () = assert!(
    core::mem::size_of::<Obu>() < 64 * 1024,
    "Obu is over its 64 KiB RAM budget"
);

impl Default for Obu {
    fn default() -> Self {
        Obu::new(AlertConfig::DEFAULT)
    }
}

impl Obu {
    /// A core with no data.
    pub const fn new(config: AlertConfig) -> Self {
        Obu {
            config,
            maps: MapStore::new(),
            zones: ZoneStore::new(),
            workers: WorkerStore::new(),
            matcher: Matcher::new(),
            last_fix: None,
            fix_clock: Instant::ZERO,
            last_match: None,
            utc: None,
            time_status: TimeStatus::Unknown,
            clock: ClockCheck::new(),
            fix_period_ms: 100,
            vehicle_speed: None,
            travel: motion::Travel::ZERO,
            stale_reported: false,
            lost_reported: false,
            next_estimate: None,
            was_urgent: false,
            counters: Counters::ZERO,
            rejected: IngestCounters::ZERO,
        }
    }

    /// The configuration.
    pub fn config(&self) -> &AlertConfig {
        &self.config
    }

    /// Replaces the configuration (takes effect on the next fix).
    pub fn set_config(&mut self, config: AlertConfig) {
        self.config = config;
    }

    /// Stored lane models.
    pub fn maps(&self) -> &MapStore {
        &self.maps
    }

    /// Stored work zones.
    pub fn zones(&self) -> &ZoneStore {
        &self.zones
    }

    /// Stored road workers.
    pub fn workers(&self) -> &WorkerStore {
        &self.workers
    }

    /// Counters.
    pub fn counters(&self) -> Counters {
        Counters {
            lane_switches: self.matcher.switches(),
            lane_outliers: self.matcher.outliers(),
            ..self.counters
        }
    }

    /// The matcher's clock step to `fix`, milliseconds: the receiver's own step between the
    /// two fixes' UTC times when both have one and it moved forward, else the arrival
    /// times' step (`None` for the first fix). The lane decision's hold time then follows
    /// from the fixes alone, not from how late each one arrived (serial link, load), so a
    /// replay decides the same on every device; a receiver without usable time falls back
    /// to arrivals. The step is also the fix period the warnings look ahead by.
    fn fix_step_ms(&self, now: Instant, fix: &Fix) -> Option<u64> {
        let (prev_now, prev) = &self.last_fix.as_ref()?;
        Some(match (prev.utc, fix.utc) {
            (Some(a), Some(b)) if a.year == b.year && b.ms_of_year > a.ms_of_year => {
                b.ms_of_year - a.ms_of_year
            }
            _ => now.saturating_since(*prev_now).millis(),
        })
    }

    /// Processes one fix and returns what the display shows. A fresh vehicle speed
    /// ([`Obu::on_speed`]) replaces the fix's speed.
    pub fn on_fix(&mut self, now: Instant, mut fix: Fix) -> HmiState {
        if let Some(v) = self.fresh_vehicle_speed(now) {
            fix.speed_mps = Some(v);
        }
        self.counters.fixes = self.counters.fixes.saturating_add(1);
        match self.fix_step_ms(now, &fix) {
            Some(step) => {
                self.fix_clock = self.fix_clock + Duration::from_millis(step);
                // A step longer than the GNSS timeout is an outage, not the period.
                if step <= self.config.gnss_timeout.millis() {
                    self.fix_period_ms = step.clamp(20, 2000) as u32;
                }
            }
            None => self.fix_clock = now,
        }
        if let Some(utc) = fix.utc {
            self.check_time(now, utc);
        }
        self.last_fix = Some((now, fix));
        self.travel = motion::Travel::start(now, fix.speed());
        self.stale_reported = false;
        self.lost_reported = false;
        self.next_estimate = None;
        let matched = self
            .matcher
            .update(self.fix_clock, &fix, &self.maps, &self.config.matcher);
        if matched.is_none() {
            self.counters.off_map = self.counters.off_map.saturating_add(1);
        }
        self.last_match = matched;
        self.remember_stage(self.evaluate(now))
    }

    /// Keeps whether `state` is urgent for the next evaluation's hysteresis.
    fn remember_stage(&mut self, state: HmiState) -> HmiState {
        self.was_urgent = state.stage == crate::alert::AlertStage::Urgent;
        state
    }

    /// Expires old data; returns a new state when something the display shows
    /// changed without a fix: GNSS became stale, data expired, a dead-reckoned position
    /// moved on (every [`ESTIMATE_PERIOD`]) or its horizon passed ("position lost").
    pub fn poll(&mut self, now: Instant) -> Option<HmiState> {
        let maps = self.maps.expire(now, self.config.map_timeout);
        let time64 = self.trusted_time64(now);
        let zones = self
            .zones
            .poll(now, self.utc_minutes(now), time64, self.config.zone_timeout);
        let expired = (maps + zones) as u32;
        self.counters.expired = self.counters.expired.saturating_add(expired);
        let workers_gone = self.workers.expire(now) > 0;
        let stale = !self.gnss_fresh(now);
        let newly_stale = stale && !self.stale_reported;
        if newly_stale {
            self.stale_reported = true;
            // The matcher starts over with the next fix; the last match stays for dead
            // reckoning along its lane.
            self.matcher.reset();
        }
        let position = self.position_source(now);
        let tick =
            position == PositionSource::Estimated && self.next_estimate.is_none_or(|t| now >= t);
        if tick {
            self.next_estimate = Some(now + ESTIMATE_PERIOD);
        }
        let newly_lost =
            position == PositionSource::Lost && self.last_fix.is_some() && !self.lost_reported;
        if newly_lost {
            self.lost_reported = true;
        }
        (expired > 0 || workers_gone || newly_stale || tick || newly_lost)
            .then(|| self.evaluate(now))
            .map(|state| self.remember_stage(state))
    }

    /// The display state at `now` without a new fix: for a caller that publishes as
    /// soon as a message changed what is stored (a new zone, a cancelled one, a new MAP
    /// revision), instead of waiting for the next fix.
    pub fn state(&self, now: Instant) -> HmiState {
        self.evaluate(now)
    }

    /// A vehicle speed (CAN) at `now`, m/s: while fresh ([`AlertConfig::speed_timeout`]) it
    /// is the speed of the next fixes, shown and carried into dead reckoning during a GNSS
    /// outage. Not finite or negative: ignored.
    pub fn on_speed(&mut self, now: Instant, speed_mps: f32) {
        if !(speed_mps.is_finite() && (0.0..1000.0).contains(&speed_mps)) {
            return;
        }
        self.vehicle_speed = Some((now, speed_mps));
        self.travel.set_speed(now, speed_mps);
    }

    /// The reference clock (the host's system clock) read `utc` at `now`: GNSS time is
    /// checked against it ([`crate::clock`]).
    pub fn set_reference_time(&mut self, now: Instant, utc: UtcTime) {
        self.clock.set_reference(now, utc);
    }

    /// Whether the time zones are judged on can be believed.
    pub fn time_status(&self) -> TimeStatus {
        self.time_status
    }

    fn check_time(&mut self, now: Instant, utc: UtcTime) {
        let checked = self.clock.check(now, utc, self.config.max_clock_offset);
        if checked.rollovers != 0 {
            self.counters.rollover_fixes = self.counters.rollover_fixes.saturating_add(1);
        }
        if checked.status == TimeStatus::Unverified {
            self.counters.unverified_time_fixes =
                self.counters.unverified_time_fixes.saturating_add(1);
        }
        self.utc = Some((now, checked.utc));
        self.time_status = checked.status;
    }

    /// When [`Obu::poll`] next has work, if ever: the GNSS timeout, a map's, zone's or road
    /// worker's silence timeout, or the end of a zone's validity window.
    pub fn next_deadline(&self) -> Option<Instant> {
        let gnss = match (self.last_fix, self.stale_reported) {
            (Some((t, _)), false) => {
                Some(t + self.config.gnss_timeout + crate::Duration::from_millis(1))
            }
            _ => None,
        };
        let estimate = match (self.last_fix, self.stale_reported && !self.lost_reported) {
            (Some((t, _)), true) => {
                let horizon = t
                    + self.config.gnss_timeout
                    + self.config.dead_reckoning
                    + crate::Duration::from_millis(1);
                Some(self.next_estimate.map_or(horizon, |n| n.min(horizon)))
            }
            _ => None,
        };
        let maps = self.maps.next_expiry(self.config.map_timeout);
        let zones = self.zones.next_expiry(self.config.zone_timeout);
        let workers = self.workers.next_expiry();
        [gnss, estimate, maps, zones, workers, self.next_window_end()]
            .into_iter()
            .flatten()
            .min()
    }

    /// When the UTC time (extrapolated from the last fix with UTC) reaches the end of a
    /// stored zone's validity window, so that [`Obu::poll`] drops it.
    fn next_window_end(&self) -> Option<Instant> {
        let (t, utc) = self
            .utc
            .filter(|_| self.time_status == TimeStatus::Trusted)?;
        let end = self.zones.next_end(utc.abs_minutes())?;
        let utc_ms = utc.abs_minutes() * 60_000 + (utc.ms_of_year % 60_000) as i64;
        let after = (end * 60_000 - utc_ms).max(0);
        Some(t + Duration::from_millis(after as u64))
    }

    /// Stores a decoded MAP intersection or road segment. When `id` is stored with
    /// the same `revision`, only its age is refreshed and `fill` is not called
    /// (returns `Ok(false)`). Otherwise `fill` fills a cleared model in place; on
    /// error the model is dropped. Zones are re-associated with the new lanes.
    pub fn update_map<E>(
        &mut self,
        now: Instant,
        id: MapId,
        revision: u8,
        reference: LatLon,
        elevation_m: f32,
        fill: impl FnOnce(&mut LaneModel) -> Result<(), E>,
    ) -> Result<bool, E> {
        let map = (id, revision, reference, elevation_m);
        let stored = self.store_map(now, map, Provenance::Verified, fill)?;
        Ok(stored == Stored::Filled)
    }

    /// [`Obu::update_map`] for a message of `provenance`: `map` is the id, revision,
    /// reference point and elevation.
    fn store_map<E>(
        &mut self,
        now: Instant,
        map: (MapId, u8, LatLon, f32),
        provenance: Provenance,
        fill: impl FnOnce(&mut LaneModel) -> Result<(), E>,
    ) -> Result<Stored, E> {
        let (id, revision, reference, elevation_m) = map;
        let model = match self
            .maps
            .update(now, id, revision, reference, elevation_m, provenance)
        {
            MapUpdate::Fill { model, .. } => model,
            MapUpdate::Unchanged => return Ok(Stored::Unchanged),
            MapUpdate::Refused => return Ok(Stored::Refused),
        };
        if let Err(e) = fill(model) {
            self.maps.remove(id);
            self.counters.maps_rejected = self.counters.maps_rejected.saturating_add(1);
            self.reassociate_all();
            return Err(e);
        }
        model.drop_degenerate_lanes();
        self.counters.maps_updated = self.counters.maps_updated.saturating_add(1);
        self.reassociate_all();
        Ok(Stored::Filled)
    }

    /// Stores a decoded TIM data frame. Unchanged (`msgCnt` and start) or older
    /// zones only refresh their age (`Ok(false)`); `durationTime` 0 removes the zone;
    /// otherwise `fill` fills a cleared zone (regions, content) in place. On error
    /// the zone is dropped.
    pub fn update_zone<E>(
        &mut self,
        now: Instant,
        key: ZoneKey,
        msg_cnt: u8,
        validity: Validity,
        fill: impl FnOnce(&mut WorkZone) -> Result<(), E>,
    ) -> Result<bool, E> {
        let stored = self.store_zone(
            now,
            key,
            (msg_cnt, validity),
            Provenance::Verified,
            |z, _| fill(z),
        )?;
        Ok(matches!(
            stored,
            Stored::Filled | Stored::Cancelled(true) | Stored::Ended(true)
        ))
    }

    /// [`Obu::update_zone`] with the lane models at hand for the conversion.
    fn store_zone<E>(
        &mut self,
        now: Instant,
        key: ZoneKey,
        (msg_cnt, validity): (u8, Validity),
        provenance: Provenance,
        fill: impl FnOnce(&mut WorkZone, &MapStore) -> Result<(), E>,
    ) -> Result<Stored, E> {
        let ended = self.utc_minutes(now).is_some_and(|m| validity.has_ended(m));
        let update = if ended && !validity.is_cancelled() {
            self.zones.end(key, validity, provenance)
        } else {
            self.zones.update(now, key, msg_cnt, validity, provenance)
        };
        let zone = match update {
            ZoneUpdate::Fill { zone, .. } => zone,
            ZoneUpdate::Ended(found) => {
                self.counters.expired = self.counters.expired.saturating_add(found as u32);
                return Ok(Stored::Ended(found));
            }
            ZoneUpdate::Cancelled(found) => {
                self.counters.zones_cancelled =
                    self.counters.zones_cancelled.saturating_add(found as u32);
                return Ok(Stored::Cancelled(found));
            }
            ZoneUpdate::Unchanged => return Ok(Stored::Unchanged),
            ZoneUpdate::Stale => return Ok(Stored::Stale),
            ZoneUpdate::Refused => return Ok(Stored::Refused),
        };
        if let Err(e) = fill(zone, &self.maps) {
            self.zones.remove(&key);
            self.counters.zones_rejected = self.counters.zones_rejected.saturating_add(1);
            return Err(e);
        }
        zone::associate(zone, &self.maps);
        self.counters.zones_updated = self.counters.zones_updated.saturating_add(1);
        Ok(Stored::Filled)
    }

    fn reassociate_all(&mut self) {
        for z in self.zones.iter_mut() {
            zone::associate(z, &self.maps);
        }
    }

    /// GNSS time at `now` as IEEE 1609.2 `Time64`, from the last fix that carried UTC
    /// (corrected for the week rollover).
    pub(crate) fn time64(&self, now: Instant) -> Option<u64> {
        let (t, utc) = self.utc?;
        utc.plus_millis(now.saturating_since(t).millis()).time64()
    }

    /// The reference clock at `now` as `Time64` while GNSS time disagrees with it: message
    /// times may be checked against either clock.
    pub(crate) fn alt_time64(&self, now: Instant) -> Option<u64> {
        if self.time_status != TimeStatus::Unverified {
            return None;
        }
        let reference = self.clock.reference_at(now)?.time64()?;
        let gnss = self.time64(now)?;
        let near = reference.abs_diff(gnss) <= crate::clock::MAX_SECOND_CLOCK_OFFSET_MS * 1000;
        near.then_some(reference)
    }

    /// The last fix's position.
    pub(crate) fn position(&self) -> Option<LatLon> {
        self.last_fix.map(|(_, fix)| fix.position)
    }

    /// GNSS time at `now` as `Time64` when it is trusted (see [`Obu::utc_minutes`]).
    fn trusted_time64(&self, now: Instant) -> Option<u64> {
        (self.time_status == TimeStatus::Trusted)
            .then(|| self.time64(now))
            .flatten()
    }

    /// UTC minutes since 2000 at `now`, from the last fix that carried UTC, when that
    /// time is trusted: zones are judged expired (or not yet valid) on a trusted time only.
    fn utc_minutes(&self, now: Instant) -> Option<i64> {
        let trusted = self.utc.filter(|_| self.time_status == TimeStatus::Trusted);
        trusted.map(|(t, utc)| {
            utc.plus_millis(now.saturating_since(t).millis())
                .abs_minutes()
        })
    }
}

#[cfg(test)]
mod tests;
