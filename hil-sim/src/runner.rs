//! `hil-sim run`: a scenario against the real `obu` daemon. The roadside broadcasts the
//! scenario's MAP and TIM over UDP (with its faults), the simulated receiver sends NMEA at
//! 10 Hz (and a candump replay the CAN speed), every `HmiState` of the daemon's event
//! stream is recorded with its arrival time, joined with the simulated truth, checked
//! against the expectations, and written as `report.json`, `states.jsonl` and plots. A
//! scenario's attacker sends beside the roadside for the drive; the device's counters are
//! read at the end ([`crate::attack`]).

use crate::attack::{self, Attack, AttackFacts};
use crate::daemon::Daemon;
use crate::drive::{self, Sample};
use crate::expect::{self, Outcome, Record, RunFacts};
use crate::nmea::{self, Epoch};
use crate::roadside_bench::camera_site::{CameraView, LiveSite};
use crate::roadside_bench::scripted::V2xCounts;
use crate::scenario::Scenario;
use crate::sse::SseClient;
use obu::alert::HmiState;
use roadside::clock::{unix_ms_now, Utc};
use roadside::messages::WorkZone;
use roadside::road::Road;
use roadside::zone_sources::build_zones;
use serde::Serialize;
use std::io::Write;
use std::net::UdpSocket;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

/// How to run.
#[derive(Debug, Clone)]
pub struct RunOptions {
    /// The `obu` executable.
    pub obu: PathBuf,
    /// Where the report goes.
    pub out: PathBuf,
    /// HTTP port of the daemon (0: any free one).
    pub http_port: u16,
    /// Print a progress bar on stderr.
    pub progress: bool,
    /// Run against the firmware in QEMU (through the daemon in bridge mode) instead of
    /// the daemon's own core.
    pub firmware: Option<crate::firmware::FirmwareTarget>,
}

/// The report of one run (`report.json`).
#[derive(Debug, Clone, Serialize)]
pub struct RunReport {
    /// Scenario name.
    pub name: String,
    /// The device under test: `daemon` or `firmware`.
    pub target: &'static str,
    /// All expectations hold.
    pub passed: bool,
    /// The verdicts.
    pub outcomes: Vec<Outcome>,
    /// Where the first warning fired: true metres before the zone start.
    pub first_warning_m: Option<f64>,
    /// NMEA datagram sent -> its state received on `/events`, milliseconds (p50, p99, max).
    pub fix_to_screen_ms: [f64; 3],
    /// Roadside -> tablet: for each new version of the MAP/TIMs (the first, a MAP revision,
    /// a zone shrunk or removed), its first datagram sent -> the first state showing it
    /// (the core's update counters raised), milliseconds.
    pub v2x_to_screen_ms: Vec<f64>,
    /// Fixes sent, states recorded.
    pub fixes_sent: usize,
    /// States recorded.
    pub states: usize,
    /// V2X datagrams sent, lost to the fault model, corrupted.
    pub v2x: V2xCounts,
    /// The attack, when the scenario has an attacker: what it sent and what the device
    /// counted.
    pub attack: Option<AttackFacts>,
    /// The firmware rig's radio: V2X frames it received, delivered over the serial link and
    /// dropped with its receive buffers full (`None` for the daemon).
    pub radio: Option<crate::radio::LinkCounts>,
    /// Workers' PSMs the camera site sent (0 without one).
    pub worker_psms: u64,
    /// The camera site's processing time per frame, milliseconds (mean, max); over 100 ms
    /// the site falls behind its 10 Hz and its PSMs leave late.
    pub camera_frame_ms: Option<[f64; 2]>,
    /// Files written.
    pub files: Vec<PathBuf>,
}

/// What the run produced before the checks.
struct Recorded {
    t0: Instant,
    /// When the zones' own validity windows end (`ends_after_s`), seconds since `t0`.
    window_ends_s: Vec<f64>,
    samples: Vec<Sample>,
    sent: Vec<(usize, Instant)>,
    states: Vec<(Instant, serde_json::Value)>,
    changes: Vec<Instant>,
    v2x: V2xCounts,
    attack: Option<AttackFacts>,
    /// The daemon's counters after the drive (the firmware's drops: from its log).
    device: Option<attack::DeviceCounts>,
    /// The attacker's sending address.
    attacker_from: Option<std::net::SocketAddr>,
    radio: Option<crate::radio::LinkCounts>,
    views: Vec<CameraView>,
    psms: u64,
    camera_ms: (f64, f64, u64),
    /// What the deployed roadside did (`[rsu_deployment]`).
    deployment: Option<crate::deployment::DeploymentFacts>,
}

/// Runs a scenario and writes its report into `opts.out`.
pub fn run(s: &Scenario, opts: &RunOptions) -> Result<RunReport, String> {
    std::fs::create_dir_all(&opts.out).map_err(|e| format!("{}: {e}", opts.out.display()))?;
    let road = s.road()?;
    let start = Utc::from_unix_ms(unix_ms_now().saturating_sub(120_000));
    let mut zones = build_zones(&s.site(), &road, start).map_err(|e| e.to_string())?;
    end_windows(s, &mut zones, unix_ms_now());
    let samples = drive::simulate(&road, &s.drive, 900.0).map_err(|e| e.to_string())?;
    if samples.is_empty() {
        return Err("the drive has no samples (start past its end?)".into());
    }
    let camera = camera_site(s, &road, &zones)?;
    let state_dir = opts.out.join("obu-state");
    let _ = std::fs::remove_dir_all(&state_dir);
    let mut speed_log = None;
    let t0_unix = unix_ms_now() as f64 / 1000.0;
    if s.can_speed || s.drive.candump_file.is_some() {
        let log = state_dir.join("speed.candump");
        std::fs::create_dir_all(&state_dir).map_err(|e| e.to_string())?;
        let text = match &s.drive.candump_file {
            Some(f) => {
                std::fs::read_to_string(s.path(f)).map_err(|e| format!("{}: {e}", f.display()))?
            }
            None => drive::candump(&samples, t0_unix),
        };
        std::fs::write(&log, text).map_err(|e| e.to_string())?;
        speed_log = Some(log);
    }
    let settings = s.settings;
    let configure = |c: &mut obu_daemon::config::Config| {
        c.alerts.warning_distance_m = settings.warning_distance_m as f32;
        c.alerts.lead_time_s = settings.lead_time_s as f32;
        if let Some(log) = speed_log {
            c.speed.source = obu_daemon::config::SpeedSource::CandumpFile;
            c.speed.file = log;
        }
    };
    let daemon = match &opts.firmware {
        None => crate::hmi_bench::start_daemon(&opts.obu, &state_dir, opts.http_port, configure)?,
        Some(target) => {
            if let Some(why) = crate::firmware::unsupported(s) {
                return Err(format!("not runnable on the firmware: {why}"));
            }
            crate::firmware::start(target, &opts.obu, &state_dir, opts.http_port)?
        }
    };
    if opts.http_port != 0 {
        println!("hil-sim: the tablet app is live at {}", daemon.http);
    }
    let work = opts.out.join("deployment");
    let mut recorded = drive_and_record(
        s,
        (&road, &zones),
        samples,
        &daemon,
        opts.progress,
        camera,
        &work,
    )?;
    if let Some(rig) = &daemon.rig {
        // What the roadside sent after the drive may still wait on the serial link: let the
        // firmware work through it before QEMU stops, or a frame sent would be neither
        // taken nor dropped.
        crate::firmware::catch_up(rig, FIRMWARE_CATCH_UP)?;
        let radio = rig.radio_counts();
        if let (Some(a), Some(from)) = (&mut recorded.attack, recorded.attacker_from) {
            a.radio_dropped = radio.dropped_from(from);
        }
        recorded.radio = Some(radio);
    }
    // The firmware's log is complete once QEMU and its decoder have stopped.
    drop(daemon);
    if opts.firmware.is_some() {
        let counts = attack::firmware_counts(&state_dir.join("firmware.log"));
        recorded.device = counts.as_ref().ok().cloned();
        if let Some(a) = &mut recorded.attack {
            match counts {
                Ok(d) => a.device = Some(d),
                Err(e) => a.device_error = Some(e),
            }
        }
    }
    report(s, &road, &zones, recorded, opts)
}

/// Gives each zone with `ends_after_s` a `durationTime` whose window ends at the first
/// minute boundary at least that long after `now_unix_ms`.
fn end_windows(s: &Scenario, zones: &mut [WorkZone], now_unix_ms: u64) {
    for (spec, zone) in s.zones.iter().zip(zones.iter_mut()) {
        if let Some(after_s) = spec.ends_after_s {
            let start_ms = window_start_unix_ms(zone);
            let end_ms = now_unix_ms + (after_s.max(0.0) * 1000.0) as u64;
            let minutes = end_ms.saturating_sub(start_ms).div_ceil(60_000);
            zone.duration_min = minutes.clamp(1, 31_999) as u16;
        }
    }
}

/// The TIM's `startTime` as Unix milliseconds (it counts whole minutes).
fn window_start_unix_ms(zone: &WorkZone) -> u64 {
    zone.start.to_unix_ms() / 60_000 * 60_000
}

/// When the validity windows that `end_windows` set end, Unix milliseconds.
fn window_ends_unix_ms(s: &Scenario, zones: &[WorkZone]) -> Vec<u64> {
    s.zones
        .iter()
        .zip(zones)
        .filter(|(spec, _)| spec.ends_after_s.is_some())
        .map(|(_, z)| window_start_unix_ms(z) + u64::from(z.duration_min) * 60_000)
        .collect()
}

/// The scenario's camera site on its road (its cones along the first zone), calibrated
/// before the drive starts.
fn camera_site(s: &Scenario, road: &Road, zones: &[WorkZone]) -> Result<Option<LiveSite>, String> {
    let Some(spec) = &s.workers else {
        return Ok(None);
    };
    let zone = zones.first().ok_or("[workers] needs a work zone")?;
    let lane = zone.closed_lanes.first().copied().unwrap_or(1);
    // A salt of the temporary ids that changes from run to run, as a roadside's would.
    let salt = (unix_ms_now() as u32).rotate_left(7);
    LiveSite::new(
        spec,
        road,
        (u32::from(lane), [zone.start_m, zone.end_m]),
        salt,
    )
    .map(Some)
}

/// How long the firmware may take, after the bench stopped sending, to work through what it
/// was sent.
const FIRMWARE_CATCH_UP: Duration = Duration::from_secs(60);

/// Feeds the daemon for the whole drive while recording its states.
fn drive_and_record(
    s: &Scenario,
    (road, zones): (&Road, &[WorkZone]),
    samples: Vec<Sample>,
    daemon: &Daemon,
    progress: bool,
    camera: Option<LiveSite>,
    work: &Path,
) -> Result<Recorded, String> {
    let stop = Arc::new(AtomicBool::new(false));
    let states = Arc::new(Mutex::new(Vec::new()));
    let mut sse = SseClient::connect(daemon.http_addr(), Duration::from_millis(500))?;
    let recorder = {
        let (stop, states) = (stop.clone(), states.clone());
        std::thread::spawn(move || {
            while !stop.load(Ordering::Relaxed) {
                if let Ok(ev) = sse.next_event() {
                    if ev.event == "state" {
                        if let Ok(v) = serde_json::from_str::<serde_json::Value>(&ev.data) {
                            states
                                .lock()
                                .unwrap_or_else(|p| p.into_inner())
                                .push((Instant::now(), v));
                        }
                    }
                }
            }
        })
    };
    let t0 = Instant::now();
    let t0_unix_ms = unix_ms_now();
    let window_ends_unix_ms = window_ends_unix_ms(s, zones);
    let genuine = crate::bench_pki::signer()?;
    let signer = Arc::new(s.signing.apply(&genuine));
    let attacker = s
        .attacker
        .as_ref()
        .map(|spec| Attack::start(spec, road, zones, &daemon.v2x, t0, &signer))
        .transpose()
        .inspect_err(|_| stop.store(true, Ordering::Relaxed))?;
    let attacker_from = attacker.as_ref().map(Attack::from);
    let v2x = match &s.rsu_deployment {
        None => Roadside::Scripted(crate::roadside_bench::scripted::spawn(
            &s.site(),
            road,
            zones,
            &daemon.v2x,
            t0,
            stop.clone(),
            Some(signer),
            camera,
        )?),
        Some(spec) => Roadside::Deployed(
            crate::deployment::start(
                (&s.name, &s.road),
                spec,
                road,
                &daemon.v2x,
                t0,
                stop.clone(),
                work,
            )
            .inspect_err(|_| stop.store(true, Ordering::Relaxed))?,
        ),
    };
    let sock = UdpSocket::bind("127.0.0.1:0").map_err(|e| e.to_string())?;
    let mut sent = Vec::with_capacity(samples.len());
    let replay = match &s.drive.nmea_file {
        Some(f) => Some(nmea::read_epochs(
            &std::fs::read_to_string(s.path(f)).map_err(|e| format!("{}: {e}", f.display()))?,
        )),
        None => None,
    };
    match &replay {
        Some(epochs) => replay_nmea(
            epochs, &s.drive, &samples, daemon, &sock, t0, progress, &mut sent,
        ),
        None => send_generated(s, road, &samples, daemon, &sock, t0, progress, &mut sent),
    }
    if progress {
        eprintln!();
    }
    // The attack ends with the drive.
    let attacked = attacker.map(Attack::finish).transpose();
    if let Some(rig) = &daemon.rig {
        // The firmware may still be working through the last frames of the drive (its
        // link pauses when it is busy). Its last states are recorded only once it caught up.
        if let Err(e) = crate::firmware::catch_up(rig, FIRMWARE_CATCH_UP) {
            stop.store(true, Ordering::Relaxed);
            return Err(e);
        }
    }
    // Let the last states (and a "no GNSS" after the end) arrive.
    std::thread::sleep(Duration::from_millis(1200));
    stop.store(true, Ordering::Relaxed);
    let _ = recorder.join();
    let (roadside, deployment) = match v2x {
        Roadside::Scripted(h) => (h.join().map_err(|_| "the roadside thread panicked")?, None),
        Roadside::Deployed(h) => {
            let (run, facts) = h.join().map_err(|_| "the deployment thread panicked")??;
            (run, Some(facts))
        }
    };
    let (changes, counts) = (roadside.changes, roadside.counts);
    // The daemon counts every input (read once it has counted all that was sent).
    let attacker_sent = attacked
        .as_ref()
        .ok()
        .and_then(|a| a.as_ref())
        .map_or(0, |a| a.1.sent);
    let device = (daemon.rig.is_none())
        .then(|| attack::daemon_counts_settled(daemon.http_addr(), counts.sent + attacker_sent));
    let attack = attacked?.map(|(kind, sent)| {
        // The daemon counts every input; the firmware's drops are read from its log
        // once it has stopped (`run`).
        AttackFacts {
            kind,
            sent,
            roadside_sent: counts.sent,
            radio_dropped: 0,
            device_error: device.as_ref().and_then(|d| d.as_ref().err().cloned()),
            device: device.clone().and_then(Result::ok),
        }
    });
    let states = std::mem::take(&mut *states.lock().unwrap_or_else(|p| p.into_inner()));
    Ok(Recorded {
        t0,
        window_ends_s: window_ends_unix_ms
            .iter()
            .map(|&end| (end as f64 - t0_unix_ms as f64) / 1000.0)
            .collect(),
        samples,
        sent,
        states,
        changes,
        v2x: counts,
        attack,
        device: device.and_then(Result::ok),
        attacker_from,
        radio: None,
        views: roadside.views,
        psms: roadside.psms,
        camera_ms: roadside.camera_ms,
        deployment,
    })
}

/// The roadside side of a run: the bench's scripted broadcaster, or the deployed roadside.
enum Roadside {
    Scripted(std::thread::JoinHandle<crate::roadside_bench::scripted::RoadsideRun>),
    Deployed(crate::deployment::DeploymentThread),
}

/// Sends the generated NMEA of every sample at its time.
#[allow(clippy::too_many_arguments)]
fn send_generated(
    s: &Scenario,
    road: &Road,
    samples: &[Sample],
    daemon: &Daemon,
    sock: &UdpSocket,
    t0: Instant,
    progress: bool,
    sent: &mut Vec<(usize, Instant)>,
) {
    // The receiver stamps its epochs on the GNSS clock (whole 100 ms steps from the start),
    // not at the moment the bench sends them.
    let utc0 = unix_ms_now() / 1000 * 1000;
    for (k, sample) in samples.iter().enumerate() {
        let due = t0 + Duration::from_secs_f64(sample.t_s);
        std::thread::sleep(due.saturating_duration_since(Instant::now()));
        if let Some(position) = sample.reported.and_then(|p| road.to_wgs84(p)) {
            let e = Epoch {
                utc: Utc::from_unix_ms(
                    s.drive
                        .receiver_clock(utc0 + (sample.t_s * 1000.0).round() as u64),
                ),
                position,
                speed_mps: sample.speed_mps,
                course_deg: sample.bearing_deg,
                sigma_m: s.drive.reported_sigma(),
            };
            sent.push((k, Instant::now()));
            let carrier = crate::receiver::carrier_at(&s.drive.rtk, sample.t_s);
            let bytes = crate::receiver::epoch_bytes(s.drive.receiver, &e, carrier);
            let _ = sock.send_to(&bytes, &daemon.gnss);
        }
        if progress && k % 10 == 0 {
            progress_bar(k + 1, samples.len(), sample.t_s);
        }
    }
}

/// Sends a recorded log's epochs at their own offsets, restamped to now; the j-th epoch
/// stands for the j-th sample with a fix (the truth of the drive it was recorded from).
#[allow(clippy::too_many_arguments)]
fn replay_nmea(
    epochs: &[nmea::RecordedEpoch],
    drive: &crate::drive::DriveSpec,
    samples: &[Sample],
    daemon: &Daemon,
    sock: &UdpSocket,
    t0: Instant,
    progress: bool,
    sent: &mut Vec<(usize, Instant)>,
) {
    let with_fix: Vec<usize> = (0..samples.len())
        .filter(|&k| samples[k].reported.is_some())
        .collect();
    for (j, (offset, lines)) in epochs.iter().enumerate() {
        std::thread::sleep(
            (t0 + Duration::from_secs_f64(*offset)).saturating_duration_since(Instant::now()),
        );
        let now = Utc::from_unix_ms(drive.receiver_clock(unix_ms_now()));
        let text: String = lines
            .iter()
            .filter_map(|l| nmea::restamp(l, &now))
            .collect();
        let k = with_fix.get(j).copied().unwrap_or(samples.len() - 1);
        sent.push((k, Instant::now()));
        let _ = sock.send_to(text.as_bytes(), &daemon.gnss);
        if progress && j % 10 == 0 {
            progress_bar(j + 1, epochs.len(), *offset);
        }
    }
}

fn progress_bar(done: usize, total: usize, t_s: f64) {
    let width = 40;
    let filled = done * width / total.max(1);
    eprint!(
        "\r[{}{}] {:3}% t = {t_s:5.1} s",
        "#".repeat(filled),
        " ".repeat(width - filled),
        done * 100 / total.max(1)
    );
    let _ = std::io::stderr().flush();
}

/// True distance to the zone start along the car's lane and the zone length, when the
/// zone lies beside that lane and runs its way.
pub fn true_distance(road: &Road, zone: &WorkZone, sample: &Sample) -> Option<(f64, f64)> {
    let first = road.lane(*zone.closed_lanes.first()?)?;
    let (zs, ze) = (first.at(zone.start_m)?, first.at(zone.end_m)?);
    let lane = road.lane(sample.lane)?;
    let (s_car, _) = lane.project(sample.point)?;
    let (s_start, d) = lane.project(zs.point)?;
    let (s_end, _) = lane.project(ze.point)?;
    let here = lane.at(s_start)?;
    let diff = (here.bearing_deg - zs.bearing_deg).rem_euclid(360.0);
    (d < 20.0 && diff.min(360.0 - diff) < 90.0).then_some((s_start - s_car, s_end - s_start))
}

/// Joins states with the truth, checks, writes the files.
fn report(
    s: &Scenario,
    road: &Road,
    zones: &[WorkZone],
    rec: Recorded,
    opts: &RunOptions,
) -> Result<RunReport, String> {
    let since = |t: Instant| t.saturating_duration_since(rec.t0).as_secs_f64();
    let mut records = Vec::with_capacity(rec.states.len());
    let mut latencies = Vec::new();
    let mut states_file = String::new();
    for (at, v) in &rec.states {
        let Ok(state) = serde_json::from_value::<HmiState>(v["state"].clone()) else {
            continue;
        };
        let fixes = state.counters.fixes as usize;
        let sent = fixes.checked_sub(1).and_then(|i| rec.sent.get(i));
        if let Some((_, t_sent)) = sent {
            if records
                .last()
                .is_none_or(|r: &Record| r.state.counters.fixes as usize != fixes)
            {
                latencies.push(at.saturating_duration_since(*t_sent).as_secs_f64() * 1000.0);
            }
        }
        let sample = sent.map(|(k, _)| *k);
        let truth = sample.map(|k| &rec.samples[k]);
        let dist = truth.and_then(|t| zones.first().and_then(|z| true_distance(road, z, t)));
        // The truth when the state arrived (during a GNSS outage the last fix is old).
        let now_dist = zones
            .first()
            .and_then(|z| distance_at(road, z, &rec.samples, since(*at)));
        states_file.push_str(
            &serde_json::json!({"t_s": since(*at), "sample": sample, "state": v["state"]})
                .to_string(),
        );
        states_file.push('\n');
        records.push(Record {
            t_s: since(*at),
            state,
            sample,
            true_lane: truth.map(|t| t.lane),
            distance_m: dist.map(|d| d.0),
            zone_len_m: dist.map(|d| d.1),
            true_speed_mps: truth.map(|t| t.speed_mps),
            now_distance_m: now_dist.map(|d| d.0),
        });
    }
    let v2x_to_screen = v2x_latencies(&rec, &records);
    let facts = run_facts(s, &rec);
    let outcomes: Vec<Outcome> = s
        .expectations
        .iter()
        .map(|e| expect::check(e, &records, &facts))
        .collect();
    latencies.sort_by(f64::total_cmp);
    let q = |p: f64| {
        latencies
            .get(((p * latencies.len() as f64).ceil() as usize).max(1) - 1)
            .copied()
            .unwrap_or(f64::NAN)
    };
    let first_warning_m = expect::first_warning(&records).map(|(_, d)| d);
    let mut files = vec![opts.out.join("report.json"), opts.out.join("states.jsonl")];
    std::fs::write(&files[1], states_file).map_err(|e| e.to_string())?;
    files.extend(crate::report_plots::write(
        s,
        road,
        zones,
        &rec.samples,
        &records,
        &opts.out,
    )?);
    let report = RunReport {
        name: s.name.clone(),
        target: if opts.firmware.is_some() {
            "firmware"
        } else {
            "daemon"
        },
        passed: outcomes.iter().all(|o| o.passed),
        outcomes,
        first_warning_m,
        fix_to_screen_ms: [q(0.5), q(0.99), q(1.0)],
        v2x_to_screen_ms: v2x_to_screen,
        fixes_sent: rec.sent.len(),
        states: records.len(),
        v2x: rec.v2x,
        attack: rec.attack.clone(),
        radio: rec.radio.clone(),
        worker_psms: rec.psms,
        camera_frame_ms: (rec.camera_ms.2 > 0)
            .then(|| [rec.camera_ms.0 / rec.camera_ms.2 as f64, rec.camera_ms.1]),
        files: files.clone(),
    };
    let json = serde_json::to_string_pretty(&report).map_err(|e| e.to_string())?;
    std::fs::write(&files[0], json).map_err(|e| e.to_string())?;
    Ok(report)
}

/// Roadside -> tablet latency of each change of the broadcast messages.
fn v2x_latencies(rec: &Recorded, records: &[Record]) -> Vec<f64> {
    let updates = |r: &Record| {
        let c = &r.state.counters;
        c.maps_updated + c.zones_updated + c.zones_cancelled
    };
    let t0 = rec.t0;
    rec.changes
        .iter()
        .filter_map(|tc| {
            let at = tc.saturating_duration_since(t0).as_secs_f64();
            let before = records
                .iter()
                .take_while(|r| r.t_s <= at)
                .last()
                .map_or(0, updates);
            let shown = records.iter().find(|r| r.t_s > at && updates(r) > before)?;
            Some((shown.t_s - at) * 1000.0)
        })
        .collect()
}

/// Times of the run the checks need.
/// The true distance to `zone` (and its length) `t_s` seconds into the drive, interpolated
/// between the samples around it.
fn distance_at(road: &Road, zone: &WorkZone, samples: &[Sample], t_s: f64) -> Option<(f64, f64)> {
    let x = (t_s / drive::EPOCH_S).max(0.0);
    let k = (x.floor() as usize).min(samples.len().saturating_sub(1));
    let a = true_distance(road, zone, samples.get(k)?)?;
    let Some(b) = samples
        .get(k + 1)
        .and_then(|s| true_distance(road, zone, s))
    else {
        return Some(a);
    };
    let f = (x - k as f64).clamp(0.0, 1.0);
    Some((a.0 + f * (b.0 - a.0), a.1))
}

fn run_facts(s: &Scenario, rec: &Recorded) -> RunFacts {
    let dropout_starts_s = s
        .drive
        .dropouts
        .iter()
        .filter_map(|&(start, _)| {
            rec.sent
                .iter()
                .rev()
                .find(|(k, _)| rec.samples[*k].t_s < start)
                .map(|(_, t)| t.saturating_duration_since(rec.t0).as_secs_f64())
        })
        .collect();
    RunFacts {
        dropout_starts_s,
        dropouts_s: s
            .drive
            .dropouts
            .iter()
            .map(|&(start, len)| (start, start + len))
            .collect(),
        removed_at_s: s
            .zones
            .iter()
            .filter_map(|z| z.removed_at_s)
            .chain(rec.window_ends_s.iter().copied())
            .chain(rec.deployment.as_ref().and_then(|d| d.removed_at_s))
            .reduce(f64::min),
        overspeed_tolerance_mps: 5.0 / 3.6,
        warning_distance_m: s.settings.warning_distance_m,
        attack: rec.attack.clone(),
        device: rec.device.clone(),
        can_speed: s.can_speed || s.drive.candump_file.is_some(),
        camera_views: rec.views.clone(),
        deployment: rec.deployment.clone(),
    }
}

/// The path of a scenario's output folder under `root`.
pub fn out_dir(root: &Path, scenario: &Path) -> PathBuf {
    root.join(scenario.file_stem().unwrap_or_default())
}
