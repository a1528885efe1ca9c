//! A rendered site written as camera folders (`hil-sim road-users --synthesize DIR`): per
//! camera its first frame's PNG, the detector's COCO file and the reference points, in the
//! layout `roadside road-users` reads ([`roadside::road_users::files`]), with the truth and
//! the work zone's area beside them.

use std::fs;
use std::path::{Path, PathBuf};

use geodesy::LatLon;
use roadside::rng::Prng;
use roadside::road::Road;
use serde_json::{json, Value};

use super::street::{
    coco_json, labels, marking_points, picture, site_cameras, users_at, work_zone_traffic,
    CocoFrame, World,
};
use super::synthetic_camera::PinholeCamera;

/// Where the synthetic site is on Earth (its local frame's origin).
pub const SYNTHETIC_ORIGIN: (f64, f64) = (42.2808, -83.7430);

/// What to synthesize.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SynthSpec {
    /// Frames.
    pub frames: usize,
    /// Frames a second.
    pub fps: f64,
    /// Mask noise, pixels (1-sigma per silhouette corner).
    pub noise_px: f64,
    /// Seed of the traffic and the noise.
    pub seed: u64,
    /// Cameras: 1 (west pole) or 2 (and one on the east side up the street, looking back).
    pub cameras: usize,
    /// Half-resolution cameras (960x540), for quick tests.
    pub small: bool,
}

/// Writes a synthetic site under `out`: `cam1/` (and `cam2/`), each with the first frame's
/// PNG, `detections.json` and `calibration.json` (lane-marking corners in view, 0.5 px of
/// noise); `truth.json` (every road user per frame) and `zone.json` (the work zone's stretch
/// of road, see [`read_zone`](roadside::road_users::files::read_zone)). Returns the camera
/// folders.
pub fn synthesize(spec: &SynthSpec, out: &Path) -> Result<Vec<PathBuf>, String> {
    let world = World::work_zone();
    let movers = work_zone_traffic(&world, spec.seed);
    let origin = LatLon::from_degrees(SYNTHETIC_ORIGIN.0, SYNTHETIC_ORIGIN.1).ok_or("origin")?;
    let site = Road::new(origin, Vec::new());
    let mut rng = Prng::new(spec.seed ^ 0x00c0_ffee);
    let times: Vec<f64> = (0..spec.frames).map(|k| k as f64 / spec.fps).collect();
    let mut dirs = Vec::new();
    for (c, cam) in site_cameras(&world, spec.small)
        .iter()
        .take(spec.cameras.clamp(1, 2))
        .enumerate()
    {
        let dir = out.join(format!("cam{}", c + 1));
        fs::create_dir_all(&dir).map_err(|e| format!("{}: {e}", dir.display()))?;
        let size = cam.image_size().map(|v| v as u32);
        let first = users_at(&movers, 0.0);
        let png = dir.join("frame-0000.png");
        picture(&world, cam, &first)
            .save(&png)
            .map_err(|e| format!("{}: {e}", png.display()))?;
        let names: Vec<String> = (0..spec.frames)
            .map(|k| format!("frame-{k:04}.png"))
            .collect();
        let per_frame: Vec<(Vec<u16>, Vec<_>)> = times
            .iter()
            .map(|t| {
                let users = users_at(&movers, *t);
                (labels(cam, &users, spec.noise_px, &mut rng), users)
            })
            .collect();
        let coco: Vec<CocoFrame<'_>> = per_frame
            .iter()
            .zip(&names)
            .map(|((lab, users), name)| CocoFrame {
                file_name: name,
                size,
                labels: lab,
                users,
                missed: &[],
            })
            .collect();
        write_json(&dir.join("detections.json"), &coco_json(&coco))?;
        write_json(
            &dir.join("calibration.json"),
            &reference_points(cam, &world, &site, &mut rng),
        )?;
        dirs.push(dir);
    }
    let frames: Vec<Value> = times
        .iter()
        .enumerate()
        .map(|(k, t)| {
            let users: Vec<Value> = users_at(&movers, *t)
                .iter()
                .filter_map(|u| {
                    let p = site.to_wgs84(u.centre)?;
                    Some(json!({"id": u.id, "class": u.class.name(), "lat": p.lat_deg(), "lon": p.lon_deg()}))
                })
                .collect();
            json!({"frame": k, "time_s": t, "users": users})
        })
        .collect();
    write_json(
        &out.join("truth.json"),
        &json!({"fps": spec.fps, "frames": frames}),
    )?;
    write_json(&out.join("zone.json"), &zone_area(&world, &site))?;
    Ok(dirs)
}

/// The work zone's stretch of road as an area file: every lane and a metre beyond each edge,
/// from 10 m before the closure to 10 m after it (a worker stepping out of the closed lane
/// stays on the air).
fn zone_area(world: &World, site: &Road) -> Value {
    let (_, [from, to]) = world.closed;
    let (x0, x1) = (-1.0, world.road_width_m() + 1.0);
    let (y0, y1) = (from - 10.0, to + 10.0);
    let area: Vec<Value> = [[x0, y0], [x1, y0], [x1, y1], [x0, y1]]
        .iter()
        .filter_map(|p| site.to_wgs84(*p))
        .map(|p| json!({"lat": p.lat_deg(), "lon": p.lon_deg()}))
        .collect();
    json!({ "area": area })
}

fn write_json(path: &Path, v: &Value) -> Result<(), String> {
    fs::write(path, v.to_string()).map_err(|e| format!("{}: {e}", path.display()))
}

/// Reference points of a camera: lane-marking corners in view, surveyed as lat/lon, their
/// pixels with 0.5 px of noise.
fn reference_points(cam: &PinholeCamera, world: &World, site: &Road, rng: &mut Prng) -> Value {
    let points: Vec<Value> = marking_points(cam, world, rng)
        .into_iter()
        .filter_map(|(pixel, ground)| {
            let ll = site.to_wgs84(ground)?;
            Some(json!({"pixel": pixel, "lat": ll.lat_deg(), "lon": ll.lon_deg()}))
        })
        .collect();
    json!({ "points": points })
}
