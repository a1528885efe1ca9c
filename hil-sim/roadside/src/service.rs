//! `roadside run`: a site's messages deposited and kept on its RSUs (and/or broadcast over
//! UDP) until stopped. Work zones come from the site's `[[zones]]` and/or its live WZDx
//! feed; a zone that ends or leaves the feed is destroyed on the RSUs and its signed cancel
//! TIM sent by immediate forward for a while. A reload (SIGHUP) reads the site file again.

mod error;

pub use error::ServiceError;

use crate::broadcast::{Broadcaster, Message, MessageSlot, Wrapping};
use crate::clock::{unix_ms_now, Utc};
use crate::geojson::InputError;
use crate::publisher::{Published, Publisher, SourceZone};
use crate::road::Road;
use crate::rsu_snmp::deposit::{repeat_messages, DepositError, DepositSettings};
use crate::rsu_snmp::fleet::{load_owned, save_owned, Fleet, RsuSpec, RsuStatus};
use crate::rsu_snmp::mib::{RepeatMessage, RsuMib};
use crate::rsu_snmp::reconcile::WantedRow;
use crate::signer::RsuSigner;
use crate::site_file::SiteFile;
use crate::wzdx_feed::{FeedPoll, FeedPoller};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

/// How often zones are published again (a zone's end passes without a feed change) and
/// cancels are forwarded.
const REPUBLISH: Duration = Duration::from_secs(1);

/// The rows of a site as built at one time.
#[derive(Debug, Clone, Default)]
pub struct Deployment {
    /// MAP and TIMs, bare frames (the direct broadcast's messages).
    pub frames: Vec<Message>,
    /// The rows to deposit (payload signed when the roadside signs).
    pub messages: Vec<RepeatMessage>,
    /// Cancel TIMs still being sent: as short store-and-repeat rows on RSU 4.1 units
    /// (which have no immediate-forward table).
    pub cancels: Vec<RepeatMessage>,
}

impl Deployment {
    /// The rows of `rsu`: the site's messages with its channel, interval and priority.
    pub fn wanted_for(&self, rsu: &RsuSpec) -> Vec<WantedRow> {
        let cancels = match rsu.rules.mib {
            RsuMib::Rsu41 => self.cancels.as_slice(),
            RsuMib::Ntcip1218 => &[],
        };
        self.messages
            .iter()
            .chain(cancels)
            .map(|m| {
                let m = RepeatMessage {
                    channel: rsu.deposit.channel,
                    interval_ms: rsu.deposit.interval_ms,
                    priority: rsu.deposit.priority,
                    ..m.clone()
                };
                rsu.rules.mib.repeat_row(&m)
            })
            .collect()
    }
}

/// The feed's state in `status.json`.
#[derive(Debug, Clone, Default, Serialize, Deserialize)]
pub struct FeedStatus {
    /// Its URL.
    pub url: String,
    /// When it last gave a usable feed (Unix ms).
    pub last_good_unix_ms: u64,
    /// What is wrong with it now, if anything (the last good feed stands).
    pub problem: Option<String>,
    /// Live zones from it.
    pub zones: usize,
    /// Polls by outcome.
    pub counts: BTreeMap<String, u64>,
}

/// `status.json` of the state folder.
#[derive(Debug, Clone, Default, Serialize, Deserialize)]
pub struct ServiceStatus {
    /// The site's name.
    pub site: String,
    /// Messages on the air (MAP + TIMs).
    pub messages: usize,
    /// Cancels being sent.
    pub cancels: usize,
    /// Each RSU.
    pub rsus: Vec<RsuStatus>,
    /// The WZDx feed, if the site has one.
    pub feed: Option<FeedStatus>,
}

/// A running roadside.
pub struct Roadside {
    path: PathBuf,
    site: SiteFile,
    road: Road,
    signer: Option<RsuSigner>,
    static_zones: Vec<SourceZone>,
    feed: Option<FeedPoller>,
    feed_zones: Vec<SourceZone>,
    feed_status: Option<FeedStatus>,
    next_feed: Instant,
    publisher: Publisher,
    published: Vec<Published>,
    /// Cancel TIMs by `packetID`, and when their sending stops (Unix ms).
    cancels: Vec<([u8; 9], Message, u64)>,
    deployment: Deployment,
    /// The rows must be built again (the last build failed).
    redeploy: bool,
    /// A site with a feed deposits nothing before the feed's first good answer (its rows
    /// from before a restart stay on the RSUs meanwhile).
    feed_ready: bool,
    delivery_start_ms: u64,
    fleet: Fleet,
    air: Option<(MessageSlot, Arc<AtomicBool>)>,
    next_publish: Instant,
    last_problems: BTreeMap<String, Option<String>>,
}

impl std::fmt::Debug for Roadside {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Roadside")
            .field("site", &self.site.site.name)
            .finish_non_exhaustive()
    }
}

/// The site's signer, if it has a PKI.
fn signer_of(site: &SiteFile) -> Result<Option<RsuSigner>, ServiceError> {
    match site.signing.as_ref().and_then(|s| s.pki.as_ref()) {
        Some(p) => Ok(Some(RsuSigner::load(&site.path(p), None)?)),
        None => Ok(None),
    }
}

/// The site's own `[[zones]]`, delivered for its window from `start_ms`.
fn static_zones(
    site: &SiteFile,
    road: &Road,
    start_ms: u64,
) -> Result<Vec<SourceZone>, ServiceError> {
    let window = u64::from(site.rsus.as_ref().map_or(24, |r| r.window_hours)) * 3_600_000;
    let zones = crate::zone_sources::build_zones(&site.site(), road, Utc::from_unix_ms(start_ms))?;
    Ok(zones
        .into_iter()
        .map(|zone| SourceZone {
            zone,
            stop_unix_ms: start_ms + window,
        })
        .collect())
}

/// The work zones of a WZDx feed on `road`, each until its `end_date`.
///
/// # Errors
///
/// [`InputError`]: the feed is not a WZDx feed the parser takes.
pub fn feed_zones(road: &Road, text: &str) -> Result<Vec<SourceZone>, InputError> {
    let zones = crate::geojson::work_zones_from_wzdx(road, text)?;
    Ok(zones
        .iter()
        .map(|z| SourceZone {
            zone: z.to_work_zone(z.packet_id(), 0),
            stop_unix_ms: z.end_unix_ms,
        })
        .collect())
}

impl Roadside {
    /// Reads the site and starts: its state folder, credentials, PKI and the direct
    /// broadcast; nothing is sent to an RSU before the first [`Roadside::tick`].
    ///
    /// # Errors
    ///
    /// [`ServiceError`]: the site file, its lane map, zones, PKI, credentials or state
    /// folder.
    pub fn start(path: &Path, now: Instant, now_ms: u64) -> Result<Self, ServiceError> {
        Self::start_site(SiteFile::load(path)?, path, now, now_ms)
    }

    /// Starts a site given as a value (`path`: where a reload reads it from).
    ///
    /// # Errors
    ///
    /// As [`Roadside::start`].
    pub fn start_site(
        site: SiteFile,
        path: &Path,
        now: Instant,
        now_ms: u64,
    ) -> Result<Self, ServiceError> {
        let state = site.state_dir();
        if let Err(source) = std::fs::create_dir_all(&state) {
            return Err(ServiceError::Io {
                path: state,
                source,
            });
        }
        let owned = load_owned(&state.join("owned.json"))?;
        let fleet = Fleet::new(site.rsu_specs()?, site.timing(), &owned, now);
        let mut r = Self::with(path, site, fleet, now, now_ms)?;
        r.air = r.start_broadcast()?;
        Ok(r)
    }

    fn with(
        path: &Path,
        site: SiteFile,
        fleet: Fleet,
        now: Instant,
        now_ms: u64,
    ) -> Result<Self, ServiceError> {
        let road = site.site().road()?;
        let start_ms = now_ms - now_ms % 60_000;
        let site_has_no_feed = site.wzdx_feed.is_none();
        let feed = site.wzdx_feed.as_ref().map(FeedPoller::new);
        let feed_status = site.wzdx_feed.as_ref().map(|f| FeedStatus {
            url: f.url.clone(),
            ..FeedStatus::default()
        });
        Ok(Self {
            path: path.to_path_buf(),
            signer: signer_of(&site)?,
            static_zones: static_zones(&site, &road, start_ms)?,
            road,
            site,
            feed,
            feed_zones: Vec::new(),
            feed_status,
            next_feed: now,
            publisher: Publisher::default(),
            published: Vec::new(),
            cancels: Vec::new(),
            deployment: Deployment::default(),
            redeploy: true,
            feed_ready: site_has_no_feed,
            delivery_start_ms: start_ms,
            fleet,
            air: None,
            next_publish: now,
            last_problems: BTreeMap::new(),
        })
    }

    /// Reads the site file again; on an error the running site is kept.
    ///
    /// # Errors
    ///
    /// [`ServiceError`]: the new site file's problem.
    pub fn reload(&mut self, now: Instant, now_ms: u64) -> Result<(), ServiceError> {
        let site = SiteFile::load(&self.path)?;
        let fleet = Fleet::new(site.rsu_specs()?, site.timing(), &self.fleet.owned(), now);
        let same_pki = site.signing.as_ref().and_then(|s| s.pki.clone())
            == self.site.signing.as_ref().and_then(|s| s.pki.clone());
        let same_feed =
            site.wzdx_feed.as_ref().map(|f| &f.url) == self.site.wzdx_feed.as_ref().map(|f| &f.url);
        let mut fresh = Self::with(&self.path, site, fleet, now, now_ms)?;
        // What did not change carries over, so that unchanged rows stay as they are: the
        // delivery window, the zones built from it, the signatures already made, the feed.
        fresh.delivery_start_ms = self.delivery_start_ms;
        fresh.static_zones = static_zones(&fresh.site, &fresh.road, self.delivery_start_ms)?;
        if same_pki {
            fresh.signer = self.signer.take();
        }
        if same_feed {
            fresh.feed = self.feed.take();
            fresh.feed_zones = std::mem::take(&mut self.feed_zones);
            fresh.feed_status = self.feed_status.take();
            fresh.feed_ready = self.feed_ready;
        }
        fresh.publisher = std::mem::take(&mut self.publisher);
        fresh.cancels = std::mem::take(&mut self.cancels);
        fresh.air = self.air.take();
        *self = fresh;
        Ok(())
    }

    /// The site's name.
    pub fn name(&self) -> &str {
        &self.site.site.name
    }

    /// One step at `now`: the feed polled when due, zones published again each second
    /// (ends pass, feed changes), RSUs reconciled when due, cancels forwarded, state saved.
    ///
    /// # Errors
    ///
    /// [`ServiceError::Owned`], [`ServiceError::Io`] or [`ServiceError::Status`]: the state
    /// folder cannot be written.
    pub fn tick(
        &mut self,
        now: Instant,
        now_ms: u64,
        force: bool,
        log: &mut dyn Write,
    ) -> Result<(), ServiceError> {
        self.poll_feed(now, now_ms, log);
        let mut forward = false;
        let mut changed = false;
        if now >= self.next_publish || force {
            self.next_publish = now + REPUBLISH;
            changed = self.publish(now_ms, log);
            forward = true;
        }
        let deployment = &self.deployment;
        let wanted = |rsu: &RsuSpec| deployment.wanted_for(rsu);
        // New rows go to every RSU at once, not at its next poll.
        let passes = if self.feed_ready {
            self.fleet.poll(&wanted, now, now_ms, force || changed)
        } else {
            0
        };
        let forwarding = forward && !self.cancels.is_empty();
        if forwarding {
            self.forward_cancels();
        }
        if passes > 0 || forwarding || changed {
            self.save(log)?;
        }
        Ok(())
    }

    fn poll_feed(&mut self, now: Instant, now_ms: u64, log: &mut dyn Write) {
        let (Some(poller), Some(cfg), Some(status)) =
            (&mut self.feed, &self.site.wzdx_feed, &mut self.feed_status)
        else {
            return;
        };
        if now < self.next_feed {
            return;
        }
        self.next_feed = now + Duration::from_secs_f64(cfg.poll_s.max(0.1));
        let problem = match poller.poll() {
            FeedPoll::Changed(text) => match feed_zones(&self.road, &text) {
                Ok(zones) => {
                    let _ = writeln!(log, "wzdx feed: {} work zones on this road", zones.len());
                    self.feed_zones = zones;
                    self.feed_ready = true;
                    self.next_publish = now;
                    status.last_good_unix_ms = now_ms;
                    None
                }
                Err(e) => {
                    poller.refused();
                    Some(format!("not a usable WZDx feed: {e}"))
                }
            },
            FeedPoll::Unchanged => {
                status.last_good_unix_ms = now_ms;
                None
            }
            FeedPoll::Failed(p) => Some(p.to_string()),
        };
        if problem != status.problem {
            let _ = match &problem {
                Some(p) => writeln!(log, "wzdx feed {}: {p}; the last good feed stands", cfg.url),
                None => writeln!(log, "wzdx feed {}: good", cfg.url),
            };
        }
        status.problem = problem;
        status.zones = self.feed_zones.len();
        status.counts = poller
            .counts
            .iter()
            .map(|(k, v)| (k.to_string(), *v))
            .collect();
    }

    /// Publishes the zones as they stand; rebuilds the rows when anything changed (and
    /// says so).
    fn publish(&mut self, now_ms: u64, log: &mut dyn Write) -> bool {
        let window = self.window_ms();
        if now_ms >= self.delivery_start_ms + window / 2 {
            // Zones without an end are delivered for `window_hours` from the start: half way
            // through, the window moves on (their rows are written again once).
            self.delivery_start_ms = now_ms - now_ms % 60_000;
            match static_zones(&self.site, &self.road, self.delivery_start_ms) {
                Ok(z) => self.static_zones = z,
                Err(e) => {
                    let _ = writeln!(log, "zones not rebuilt, the last ones stand: {e}");
                }
            }
        }
        let zones: Vec<SourceZone> = self
            .static_zones
            .iter()
            .chain(&self.feed_zones)
            .cloned()
            .collect();
        let map_stop = self.delivery_start_ms + window;
        let update = match self.publisher.update(&self.road, &zones, now_ms, map_stop) {
            Ok(u) => u,
            Err(e) => {
                let _ = writeln!(log, "messages not built, the last ones stand: {e}");
                return false;
            }
        };
        let cancel_for = self
            .site
            .wzdx_feed
            .as_ref()
            .map_or(600.0, |f| f.cancel_for_s);
        let until = now_ms.saturating_add((cancel_for * 1000.0) as u64);
        let before = self.cancels.len();
        // A zone that is live again is no longer cancelled; one cancel per zone.
        self.cancels
            .retain(|(id, _, u)| *u > now_ms && !update.live.contains(id));
        let mut changed = update.changed || self.cancels.len() != before || self.redeploy;
        for (id, message) in update.cancels {
            let _ = writeln!(
                log,
                "zone ended or left the feed: cancel TIM sent for {cancel_for:.0} s"
            );
            self.cancels.retain(|(other, _, _)| *other != id);
            self.cancels.push((id, message, until));
            changed = true;
        }
        if !changed {
            return false;
        }
        self.published = update.messages;
        match self.deploy(now_ms) {
            Ok(d) => {
                if let Some((slot, _)) = &self.air {
                    let mut frames = d.frames.clone();
                    frames.extend(self.cancels.iter().map(|(_, m, _)| m.clone()));
                    slot.set(frames);
                }
                self.deployment = d;
                self.redeploy = false;
                true
            }
            Err(e) => {
                let _ = writeln!(log, "rows not built, the last ones stand: {e}");
                self.redeploy = true;
                false
            }
        }
    }

    /// How long zones without an end are delivered, ms.
    fn window_ms(&self) -> u64 {
        u64::from(self.site.rsus.as_ref().map_or(24, |r| r.window_hours)) * 3_600_000
    }

    fn deploy(&self, now_ms: u64) -> Result<Deployment, DepositError> {
        let frames = self.published.iter().map(|p| p.message.clone()).collect();
        if self.site.rsu.is_empty() {
            // Broadcast only: the broadcaster signs each transmission itself.
            return Ok(Deployment {
                frames,
                ..Deployment::default()
            });
        }
        let signing = self
            .site
            .signing
            .as_ref()
            .map(|s| s.deposit)
            .unwrap_or_default();
        // Channel, interval and priority are each RSU's (`Deployment::wanted_for`).
        let settings = DepositSettings {
            channel: 183,
            interval_ms: 100,
            priority: 6,
            signing,
        };
        let with_stop: Vec<(Message, u64)> = self
            .published
            .iter()
            .map(|p| (p.message.clone(), p.stop_unix_ms))
            .collect();
        let cancels: Vec<(Message, u64)> = self
            .cancels
            .iter()
            .map(|(_, m, until)| (m.clone(), *until))
            .collect();
        let signer = self.signer.as_ref();
        let start = self.delivery_start_ms;
        Ok(Deployment {
            frames,
            messages: repeat_messages(&with_stop, start, settings, signer, now_ms)?,
            cancels: repeat_messages(&cancels, start, settings, signer, now_ms)?,
        })
    }

    fn forward_cancels(&mut self) {
        let Some(template) = self.deployment.cancels.first().cloned() else {
            return;
        };
        let payloads: Vec<Vec<u8>> = self
            .deployment
            .cancels
            .iter()
            .map(|c| c.payload.clone())
            .collect();
        self.fleet.forward(&template, &payloads);
    }

    fn save(&mut self, log: &mut dyn Write) -> Result<(), ServiceError> {
        let state = self.site.state_dir();
        save_owned(&state.join("owned.json"), &self.fleet.owned())?;
        let status = ServiceStatus {
            site: self.site.site.name.clone(),
            messages: self.deployment.frames.len(),
            cancels: self.cancels.len(),
            rsus: self.fleet.status(),
            feed: self.feed_status.clone(),
        };
        for s in &status.rsus {
            let before = self.last_problems.insert(s.name.clone(), s.problem.clone());
            if before.as_ref() != Some(&s.problem) {
                let _ = match &s.problem {
                    Some(p) => writeln!(log, "rsu {} ({}): {p}", s.name, s.address),
                    None => writeln!(
                        log,
                        "rsu {} ({}): in step ({} rows ours, {} foreign)",
                        s.name, s.address, s.ours, s.foreign
                    ),
                };
            }
        }
        write_json(&state.join("status.json"), &status)
    }

    /// Whether every RSU's last pass converged.
    pub fn all_converged(&self) -> bool {
        self.fleet.all_converged()
    }

    /// When something is next due.
    pub fn next_due(&self) -> Instant {
        let rsu = self.fleet.next_due().unwrap_or(self.next_publish);
        let feed = if self.feed.is_some() {
            self.next_feed
        } else {
            rsu
        };
        rsu.min(feed).min(self.next_publish)
    }

    /// The site's direct UDP broadcast in its own thread, if it has one.
    fn start_broadcast(&self) -> Result<Option<(MessageSlot, Arc<AtomicBool>)>, ServiceError> {
        let Some(b) = &self.site.broadcast else {
            return Ok(None);
        };
        let mut air =
            Broadcaster::new(b.to.clone(), Wrapping::Raw).map_err(ServiceError::Socket)?;
        air.set_rate_hz(b.rate_hz).map_err(ServiceError::Rate)?;
        air.set_signer(self.signer.clone().map(Arc::new));
        let slot = air.message_slot();
        let halt = Arc::new(AtomicBool::new(false));
        let flag = Arc::clone(&halt);
        std::thread::spawn(move || air.run_until(&flag));
        Ok(Some((slot, halt)))
    }
}

impl Drop for Roadside {
    fn drop(&mut self) {
        if let Some((_, halt)) = &self.air {
            halt.store(true, Ordering::SeqCst);
        }
    }
}

/// Writes `value` as JSON through a temporary file.
fn write_json<T: Serialize>(path: &Path, value: &T) -> Result<(), ServiceError> {
    let text = serde_json::to_string_pretty(value).map_err(ServiceError::Status)?;
    let tmp = path.with_extension("tmp");
    std::fs::write(&tmp, text)
        .and_then(|()| std::fs::rename(&tmp, path))
        .map_err(|source| ServiceError::Io {
            path: path.to_path_buf(),
            source,
        })
}

/// Reads `status.json` of a state folder, if there is one.
pub fn read_status(state_dir: &Path) -> Option<ServiceStatus> {
    let text = std::fs::read_to_string(state_dir.join("status.json")).ok()?;
    serde_json::from_str(&text).ok()
}

/// Runs the site until `stop` (or, with `once`, one pass over every RSU); `reload` asks
/// for the site file to be read again. Progress lines go to `log`. Returns whether every
/// RSU converged on its last pass.
///
/// # Errors
///
/// [`ServiceError`]: the site file, its state folder, credentials or messages at start (a
/// reload that fails keeps the running site and says so).
pub fn run(
    path: &Path,
    stop: &AtomicBool,
    reload: &AtomicBool,
    once: bool,
    log: &mut dyn Write,
) -> Result<bool, ServiceError> {
    let mut r = Roadside::start(path, Instant::now(), unix_ms_now())?;
    let _ = writeln!(log, "roadside {}: started", r.name());
    loop {
        if reload.swap(false, Ordering::SeqCst) {
            match r.reload(Instant::now(), unix_ms_now()) {
                Ok(()) => {
                    let _ = writeln!(log, "reloaded {}", path.display());
                }
                Err(e) => {
                    let _ = writeln!(log, "reload failed, the running site is kept: {e}");
                }
            }
        }
        r.tick(Instant::now(), unix_ms_now(), once, log)?;
        if once || stop.load(Ordering::SeqCst) {
            break;
        }
        let wait = r
            .next_due()
            .saturating_duration_since(Instant::now())
            .min(Duration::from_millis(200));
        std::thread::sleep(wait);
    }
    Ok(r.all_converged())
}
