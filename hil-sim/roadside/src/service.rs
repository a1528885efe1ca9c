//! `roadside run`: a site's messages deposited on its RSUs and kept there (and/or
//! broadcast over UDP), until stopped; a reload (SIGHUP) reads the site file again.

use crate::broadcast::{Broadcaster, Message, Wrapping};
use crate::clock::unix_ms_now;
use crate::rsu_snmp::deposit::{repeat_messages, DepositSettings, DepositSigning};
use crate::rsu_snmp::fleet::{load_owned, save_owned, Fleet, RsuSpec, RsuStatus};
use crate::rsu_snmp::mib::RepeatMessage;
use crate::rsu_snmp::reconcile::WantedRow;
use crate::signer::RsuSigner;
use crate::site_file::SiteFile;
use std::io::Write;
use std::path::Path;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

/// The messages of a site as built at one time.
#[derive(Debug, Clone)]
pub struct Deployment {
    /// MAP and TIMs, bare frames.
    pub frames: Vec<Message>,
    /// The rows to deposit (payload signed when the roadside signs).
    pub messages: Vec<RepeatMessage>,
}

impl Deployment {
    /// The rows of `rsu`: the site's messages with its channel, interval and priority.
    pub fn wanted_for(&self, rsu: &RsuSpec) -> Vec<WantedRow> {
        self.messages
            .iter()
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

/// The site's signer, if it has a PKI.
fn signer(site: &SiteFile) -> Result<Option<RsuSigner>, String> {
    match site.signing.as_ref().and_then(|s| s.pki.as_ref()) {
        Some(p) => RsuSigner::load(&site.path(p), None).map(Some),
        None => Ok(None),
    }
}

/// Builds the site's messages at `now_unix_ms`: delivered from the current minute for the
/// `[rsus]` window.
///
/// # Errors
///
/// The lane map, a zone source, the PKI, or a message that cannot be built.
pub fn build(site: &SiteFile, now_unix_ms: u64) -> Result<Deployment, String> {
    let frames = crate::rsu::messages_of(&site.site())?;
    let start = now_unix_ms - now_unix_ms % 60_000;
    let window_h = site.rsus.as_ref().map_or(24, |r| r.window_hours);
    let stop = start + u64::from(window_h) * 3_600_000;
    let signing = site.signing.as_ref().map(|s| s.deposit).unwrap_or_default();
    let signing = if signer(site)?.is_none() && signing == DepositSigning::Roadside {
        DepositSigning::None
    } else {
        signing
    };
    let settings = DepositSettings {
        channel: 183,
        interval_ms: 100,
        priority: 6,
        signing,
    };
    let with_stop: Vec<(Message, u64)> = frames.iter().map(|m| (m.clone(), stop)).collect();
    let messages = repeat_messages(
        &with_stop,
        start,
        settings,
        signer(site)?.as_ref(),
        now_unix_ms,
    )?;
    Ok(Deployment { frames, messages })
}

/// Writes the fleet's status as JSON (`status.json` of the state folder).
///
/// # Errors
///
/// The file cannot be written.
pub fn write_status(path: &Path, status: &[RsuStatus]) -> Result<(), String> {
    let text = serde_json::to_string_pretty(status).map_err(|e| e.to_string())?;
    let tmp = path.with_extension("tmp");
    std::fs::write(&tmp, text)
        .and_then(|()| std::fs::rename(&tmp, path))
        .map_err(|e| format!("{}: {e}", path.display()))
}

/// Runs the site until `stop` (or, with `once`, one pass over every RSU); `reload` asks
/// for the site file to be read again. Progress lines go to `log`. Returns whether every
/// RSU converged on its last pass.
///
/// # Errors
///
/// The site file, its state folder, credentials or messages at start (a reload that fails
/// keeps the running site and says so).
pub fn run(
    path: &Path,
    stop: &AtomicBool,
    reload: &AtomicBool,
    once: bool,
    log: &mut dyn Write,
) -> Result<bool, String> {
    let site = SiteFile::load(path)?;
    let state = site.state_dir();
    std::fs::create_dir_all(&state).map_err(|e| format!("{}: {e}", state.display()))?;
    let owned_path = state.join("owned.json");
    let status_path = state.join("status.json");
    let mut deployment = build(&site, unix_ms_now())?;
    let mut fleet = Fleet::new(
        site.rsu_specs()?,
        site.timing(),
        &load_owned(&owned_path)?,
        Instant::now(),
    );
    let _ = writeln!(
        log,
        "roadside {}: {} messages, {} RSUs",
        site.site.name,
        deployment.frames.len(),
        fleet.status().len()
    );
    let air = start_broadcast(&site, &deployment)?;
    let mut last_problems: Vec<Option<String>> = Vec::new();
    loop {
        if reload.swap(false, Ordering::SeqCst) {
            match SiteFile::load(path)
                .and_then(|s| Ok((build(&s, unix_ms_now())?, s.rsu_specs()?, s)))
            {
                Ok((d, specs, s)) => {
                    fleet = Fleet::new(specs, s.timing(), &fleet.owned(), Instant::now());
                    if let Some((slot, _)) = &air {
                        slot.set(d.frames.clone());
                    }
                    deployment = d;
                    drop(s);
                    let _ = writeln!(
                        log,
                        "reloaded {}: {} messages",
                        path.display(),
                        deployment.frames.len()
                    );
                }
                Err(e) => {
                    let _ = writeln!(log, "reload failed, the running site is kept: {e}");
                }
            }
        }
        let wanted = |rsu: &RsuSpec| deployment.wanted_for(rsu);
        let passes = fleet.poll(&wanted, Instant::now(), unix_ms_now(), once);
        if passes > 0 {
            save_owned(&owned_path, &fleet.owned())?;
            let status = fleet.status();
            write_status(&status_path, &status)?;
            report_changes(&status, &mut last_problems, log);
        }
        if once || stop.load(Ordering::SeqCst) {
            break;
        }
        let wait = fleet
            .next_due()
            .map_or(Duration::from_millis(200), |t| {
                t.saturating_duration_since(Instant::now())
            })
            .min(Duration::from_millis(200));
        std::thread::sleep(wait);
    }
    if let Some((_, halt)) = &air {
        halt.store(true, Ordering::SeqCst);
    }
    Ok(fleet.all_converged())
}

/// Logs each RSU's problem when it changes (and when it clears).
fn report_changes(status: &[RsuStatus], last: &mut Vec<Option<String>>, log: &mut dyn Write) {
    last.resize(status.len(), None);
    for (s, before) in status.iter().zip(last.iter_mut()) {
        if s.problem != *before {
            let _ = match &s.problem {
                Some(p) => writeln!(log, "rsu {} ({}): {p}", s.name, s.address),
                None => writeln!(
                    log,
                    "rsu {} ({}): in step ({} rows ours, {} foreign)",
                    s.name, s.address, s.ours, s.foreign
                ),
            };
            before.clone_from(&s.problem);
        }
    }
}

type Air = (crate::broadcast::MessageSlot, Arc<AtomicBool>);

/// The site's direct UDP broadcast in its own thread, if it has one: the slot its messages
/// are taken from, and its stop flag.
fn start_broadcast(site: &SiteFile, d: &Deployment) -> Result<Option<Air>, String> {
    let Some(b) = &site.broadcast else {
        return Ok(None);
    };
    let mut air = Broadcaster::new(b.to.clone(), Wrapping::Raw).map_err(|e| e.to_string())?;
    air.set_rate_hz(b.rate_hz).map_err(|e| e.to_string())?;
    air.set_signer(signer(site)?.map(Arc::new));
    air.set_messages(d.frames.clone());
    let slot = air.message_slot();
    let halt = Arc::new(AtomicBool::new(false));
    let flag = Arc::clone(&halt);
    std::thread::spawn(move || air.run_until(&flag));
    Ok(Some((slot, halt)))
}
