//! [`Obu`]: the facade that the daemon, the firmware and the simulator drive.
//!
//! Sans-IO: `on_fix(now, fix)` returns the [`HmiState`] for that fix, `poll(now)`
//! expires data and reports a stale GNSS, `next_deadline()` says when `poll` has work.
//! Decoded J2735 messages enter through [`Obu::on_frame`] (or [`Obu::on_map`] and
//! [`Obu::on_tim`]); models built by other means through [`Obu::update_map`] and
//! [`Obu::update_zone`], whose closures fill the model in place.

mod evaluate;
mod messages;

use crate::alert::{AlertConfig, Counters, HmiState};
use crate::fix::Fix;
use crate::geo::LatLon;
use crate::ingest::IngestCounters;
use crate::lane::{LaneModel, MapId, MapStore, MapUpdate};
use crate::matcher::{LaneMatch, Matcher};
use crate::store::Provenance;
use crate::time::{Duration, Instant, UtcTime};
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
    /// Unverified over verified: left alone.
    Refused,
}

/// The on-board unit core: 63 648 bytes with the default capacities (x86_64 and
/// thumbv7em alike), no heap; `new` is `const` so firmware can place it in a `static`.
#[derive(Debug, Clone)]
pub struct Obu {
    config: AlertConfig,
    maps: MapStore,
    zones: ZoneStore,
    matcher: Matcher,
    last_fix: Option<(Instant, Fix)>,
    /// The matcher's clock at the last fix (see [`Obu::fix_time`]).
    fix_clock: Instant,
    last_match: Option<LaneMatch>,
    utc: Option<(Instant, UtcTime)>,
    stale_reported: bool,
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
            matcher: Matcher::new(),
            last_fix: None,
            fix_clock: Instant::ZERO,
            last_match: None,
            utc: None,
            stale_reported: false,
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

    /// Counters.
    pub fn counters(&self) -> Counters {
        Counters {
            lane_switches: self.matcher.switches(),
            ..self.counters
        }
    }

    /// The matcher's clock for `fix`: the last one advanced by the receiver's own step
    /// between the two fixes' UTC times when both have one and it moved forward, else by
    /// the arrival times' step. The lane decision's hold time then follows from the fixes
    /// alone, not from how late each one arrived (serial link, load), so a replay decides
    /// the same on every device; a receiver without usable time falls back to arrivals.
    fn fix_time(&self, now: Instant, fix: &Fix) -> Instant {
        let Some((prev_now, prev)) = &self.last_fix else {
            return now;
        };
        let step_ms = match (prev.utc, fix.utc) {
            (Some(a), Some(b)) if a.year == b.year && b.ms_of_year > a.ms_of_year => {
                b.ms_of_year - a.ms_of_year
            }
            _ => now.saturating_since(*prev_now).millis(),
        };
        self.fix_clock + Duration::from_millis(step_ms)
    }

    /// Processes one fix and returns what the display shows.
    pub fn on_fix(&mut self, now: Instant, fix: Fix) -> HmiState {
        self.counters.fixes = self.counters.fixes.saturating_add(1);
        self.fix_clock = self.fix_time(now, &fix);
        if let Some(utc) = fix.utc {
            self.utc = Some((now, utc));
        }
        self.last_fix = Some((now, fix));
        self.stale_reported = false;
        let matched = self
            .matcher
            .update(self.fix_clock, &fix, &self.maps, &self.config.matcher);
        if matched.is_none() {
            self.counters.off_map = self.counters.off_map.saturating_add(1);
        }
        self.last_match = matched;
        self.evaluate(now, true)
    }

    /// Expires old data; returns a new state when something the display shows
    /// changed without a fix (GNSS became stale, data expired).
    pub fn poll(&mut self, now: Instant) -> Option<HmiState> {
        let maps = self.maps.expire(now, self.config.map_timeout);
        let zones = self
            .zones
            .poll(now, self.utc_minutes(now), self.config.zone_timeout);
        let expired = (maps + zones) as u32;
        self.counters.expired = self.counters.expired.saturating_add(expired);
        let stale = !self.gnss_fresh(now);
        let newly_stale = stale && !self.stale_reported;
        if newly_stale {
            self.stale_reported = true;
            self.matcher.reset();
            self.last_match = None;
        }
        (expired > 0 || newly_stale).then(|| self.evaluate(now, !stale))
    }

    /// The display state at `now` without a new fix: for a caller that publishes as
    /// soon as a message changed what is stored (a new zone, a cancelled one, a new MAP
    /// revision), instead of waiting for the next fix.
    pub fn state(&self, now: Instant) -> HmiState {
        self.evaluate(now, self.gnss_fresh(now))
    }

    /// When [`Obu::poll`] next has work, if ever: the GNSS timeout, a map's or zone's
    /// silence timeout, or the end of a zone's validity window.
    pub fn next_deadline(&self) -> Option<Instant> {
        let gnss = match (self.last_fix, self.stale_reported) {
            (Some((t, _)), false) => {
                Some(t + self.config.gnss_timeout + crate::Duration::from_millis(1))
            }
            _ => None,
        };
        let maps = self.maps.next_expiry(self.config.map_timeout);
        let zones = self.zones.next_expiry(self.config.zone_timeout);
        [gnss, maps, zones, self.next_window_end()]
            .into_iter()
            .flatten()
            .min()
    }

    /// When the UTC minute (extrapolated from the last fix with UTC) first passes the end
    /// of a stored zone's validity window, so that [`Obu::poll`] drops it.
    fn next_window_end(&self) -> Option<Instant> {
        let (t, utc) = self.utc?;
        let end = self.zones.next_end(utc.abs_minutes())?;
        let utc_ms = utc.abs_minutes() * 60_000 + (utc.ms_of_year % 60_000) as i64;
        let after = ((end + 1) * 60_000 - utc_ms).max(0);
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
        Ok(matches!(stored, Stored::Filled | Stored::Cancelled(true)))
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
        let zone = match self.zones.update(now, key, msg_cnt, validity, provenance) {
            ZoneUpdate::Fill { zone, .. } => zone,
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

    /// True when the last fix is younger than the GNSS timeout.
    fn gnss_fresh(&self, now: Instant) -> bool {
        self.last_fix
            .is_some_and(|(t, _)| now.saturating_since(t) <= self.config.gnss_timeout)
    }

    /// GNSS time at `now` as IEEE 1609.2 `Time64`, from the last fix that carried UTC.
    pub(crate) fn time64(&self, now: Instant) -> Option<u64> {
        let (t, utc) = self.utc?;
        utc.plus_millis(now.saturating_since(t).millis()).time64()
    }

    /// The last fix's position.
    pub(crate) fn position(&self) -> Option<LatLon> {
        self.last_fix.map(|(_, fix)| fix.position)
    }

    /// UTC minutes since 2000 at `now`, from the last fix that carried UTC.
    fn utc_minutes(&self, now: Instant) -> Option<i64> {
        self.utc.map(|(t, utc)| {
            utc.plus_millis(now.saturating_since(t).millis())
                .abs_minutes()
        })
    }
}

#[cfg(test)]
mod tests;
