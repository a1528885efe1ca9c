//! `roadside road-users DIR...`: the road users of the roadside cameras' folders (masks,
//! reference points, first frame) as tracks, the localization error against a truth file,
//! and the tracked workers of a work zone as PSMs on the air.

use crate::{CommandError, ValueError};
use j2735::MessageFrameValue;
use roadside::broadcast::{Broadcaster, Message, Wrapping};
use roadside::clock::{unix_ms_now, Utc};
use roadside::messages::encode;
use roadside::road::Road;
use roadside::road_users::files::{
    draw_first_frame, load_camera, read_truth, read_zone, site_frame, tracks_json, CameraFolder,
};
use roadside::road_users::pipeline::{error_table, paper_text, stats, ErrorTable, Pipeline, Run};
use roadside::road_users::tracker::TrackerSettings;
use roadside::road_users::workers::WorkerBroadcaster;
use roadside::road_users::RoadUserClass;
use roadside::signer::RsuSigner;

use std::net::SocketAddr;
use std::path::PathBuf;

/// `roadside road-users`.
#[derive(Debug, clap::Args)]
pub struct RoadUsersArgs {
    /// Camera folders (calibration.json, detections.json and the first frame's PNG); two
    /// or more are fused.
    #[arg(value_name = "DIR", required = true)]
    pub cameras: Vec<PathBuf>,
    /// Where the tracks go (JSON, per frame).
    #[arg(long, value_name = "FILE.json")]
    pub out: Option<PathBuf>,
    /// The truth (as `hil-sim road-users --synthesize` writes it): print the error per class.
    #[arg(long, value_name = "FILE.json")]
    pub truth: Option<PathBuf>,
    /// Frames a second of the videos.
    #[arg(long, value_name = "F", default_value_t = 10.0)]
    pub fps: f64,
    /// Draw the first camera's first frame with its 3D boxes to this PNG.
    #[arg(long, value_name = "FILE.png")]
    pub boxes: Option<PathBuf>,
    /// The work-zone area (zone.json, lat/lon corners): its tracked workers go on the air
    /// as PSMs, one per worker per frame.
    #[arg(long, value_name = "FILE.json")]
    pub zone: Option<PathBuf>,
    /// Where the PSMs go (UDP, repeat), in real time at the frame rate; needs --zone.
    #[arg(long = "to", value_name = "HOST:PORT", value_parser = destination, requires = "zone")]
    pub to: Vec<SocketAddr>,
    /// Sign the PSMs with this PKI directory's RSU certificate (IEEE 1609.2, PSID 0x27).
    #[arg(long, value_name = "DIR", requires = "to")]
    pub pki: Option<PathBuf>,
}

/// A `--to` value: an IP address and a port.
fn destination(v: &str) -> Result<SocketAddr, ValueError> {
    v.parse()
        .map_err(|_| format!("{v:?}: give HOST:PORT with an IP address").into())
}

/// Runs the command.
pub fn road_users(a: &RoadUsersArgs) -> Result<bool, CommandError> {
    if !(a.fps.is_finite() && a.fps > 0.0) {
        return Err(format!("--fps {}: give a positive number", a.fps).into());
    }
    let first = a.cameras.first().ok_or("give at least one camera folder")?;
    let site = site_frame(first)?;
    let cameras: Vec<CameraFolder> = a
        .cameras
        .iter()
        .map(|d| load_camera(d, &site))
        .collect::<Result<_, _>>()?;
    for c in &cameras {
        let p = &c.calibration;
        println!(
            "{}: {} frames, {} edgelets, focal {:.0} px, reference points {:.3} m RMS",
            c.dir.display(),
            c.frames.len(),
            p.edgelets,
            p.focal_px,
            c.rmse_m
        );
    }
    let workers = match &a.zone {
        Some(path) => Some(on_air(a, read_zone(path, &site)?)?),
        None => None,
    };
    let run = track(&cameras, a.fps, workers, &site)?;
    for (c, cam) in cameras.iter().enumerate() {
        println!(
            "{}: {} detections, {} localized, refused {:?}",
            cam.dir.display(),
            run.detections[c],
            run.sightings.iter().filter(|s| s.camera == c).count(),
            run.rejected[c]
        );
    }
    if let Some(out) = &a.out {
        let text = tracks_json(&run, &site).to_string();
        std::fs::write(out, text).map_err(|e| format!("{}: {e}", out.display()))?;
        println!("tracks: {}", out.display());
    }
    if let Some(path) = &a.truth {
        let truth = read_truth(path, &site)?;
        let none = Vec::new();
        let at = |k: usize| truth.get(k).unwrap_or(&none).as_slice();
        let seen = run.sightings.iter().map(|s| (s.frame, s.class, s.position));
        print_table(
            "per frame (each camera's boxes)",
            &error_table(seen, at, 1.0),
        );
        let tracked = run
            .tracked
            .iter()
            .flat_map(|f| f.tracks.iter().map(move |t| (f.frame, t.class, t.position)));
        print_table("tracked (cameras fused)", &error_table(tracked, at, 1.0));
    }
    if let Some(png) = &a.boxes {
        draw_first_frame(&cameras[0], png)?;
        println!("boxes: {}", png.display());
    }
    Ok(true)
}

/// The workers' PSMs going out: the broadcaster of the zone's tracks, and the radio.
struct OnAir {
    workers: WorkerBroadcaster,
    radio: Option<Broadcaster>,
    sent: usize,
    ids: std::collections::BTreeSet<[u8; 4]>,
}

fn on_air(a: &RoadUsersArgs, area: Vec<[f64; 2]>) -> Result<OnAir, CommandError> {
    let salt = (unix_ms_now() & 0xffff_ffff) as u32;
    let radio = if a.to.is_empty() {
        None
    } else {
        let mut b = Broadcaster::new(a.to.clone(), Wrapping::Ieee1609Unsecured)?;
        if let Some(dir) = &a.pki {
            b.set_signer(Some(std::sync::Arc::new(RsuSigner::load(dir, None)?)));
        }
        Some(b)
    };
    Ok(OnAir {
        workers: WorkerBroadcaster::new(area, salt),
        radio,
        sent: 0,
        ids: Default::default(),
    })
}

/// Every frame of every camera through one pipeline (frames of the same index together);
/// with `air`, each frame's workers go out as PSMs, in real time when there is a radio.
fn track(
    cameras: &[CameraFolder],
    fps: f64,
    mut air: Option<OnAir>,
    site: &Road,
) -> Result<Run, CommandError> {
    let localizers = cameras.iter().map(|c| c.localizer.clone()).collect();
    let mut pipeline = Pipeline::new(localizers, TrackerSettings::default())?;
    let frames = cameras.iter().map(|c| c.frames.len()).min().unwrap_or(0);
    let start = std::time::Instant::now();
    for k in 0..frames {
        let masks: Vec<_> = cameras
            .iter()
            .map(|c| c.frames[k].silhouettes.clone())
            .collect();
        let t = k as f64 / fps;
        let tracks = pipeline.frame(k, t, &masks)?;
        let Some(air) = air.as_mut() else { continue };
        if air.radio.is_some() {
            if let Some(wait) = std::time::Duration::from_secs_f64(t).checked_sub(start.elapsed()) {
                std::thread::sleep(wait);
            }
        }
        // secMark: when the PSMs leave.
        let now = Utc::from_unix_ms(unix_ms_now());
        let psms = air.workers.tick(tracks, t, now, site);
        let mut messages = Vec::with_capacity(psms.len());
        for psm in &psms {
            if let MessageFrameValue::PersonalSafetyMessage(p) = &psm.value {
                air.ids.insert(p.id.0);
            }
            let bytes = encode(psm)?;
            messages.push(Message::new(bytes)?);
        }
        air.sent += messages.len();
        if let Some(radio) = air.radio.as_mut() {
            radio.set_messages(messages);
            radio.tick();
        }
    }
    if let Some(air) = &air {
        let radio = air.radio.as_ref().map_or(String::new(), |r| {
            let st = r.stats();
            format!(
                ", {} datagrams sent, {} send errors",
                st.sent, st.send_errors
            )
        });
        println!(
            "workers on the air: {} PSMs of {} temporary ids, {} not built{radio}",
            air.sent,
            air.ids.len(),
            air.workers.failed
        );
    }
    Ok(pipeline.finish())
}

fn print_table(title: &str, t: &ErrorTable) {
    println!(
        "\nlocalization error, {title}; {} not matched within 1 m",
        t.unmatched
    );
    println!("class           n    mean    std     max (cm)   paper mean / max");
    for (k, class) in RoadUserClass::ALL.iter().enumerate() {
        let (mean, std, max) = stats(&t.errors[k]);
        let paper = paper_text(*class);
        let n = t.errors[k].len();
        println!(
            "{:<12} {n:>5} {mean:7.1} {std:6.1} {max:7.1}      {paper}",
            class.name()
        );
    }
}
