//! Road users from files: a camera's folder (its first frame as PNG, the detector's COCO
//! file, the reference points), the tracks written as JSON, the truth read back, and the
//! synthetic folders the renderer makes for tests and demos.
//!
//! A camera folder holds `calibration.json` (reference points: pixel and lat/lon, see
//! [`crate::camera::parse_calibration`]), `detections.json` (COCO: one image per frame, in
//! frame order) and the PNG of its first image (the vanishing points are found on it). All
//! cameras of a site share the local frame around the first camera's first reference point.

use std::fs;
use std::path::{Path, PathBuf};

use geodesy::LatLon;
use serde_json::{json, Value};

use super::calibrate::{calibrate, SceneCalibration};
use super::detections::{parse_coco, FrameMasks};
use super::draw::draw_box;
use super::edgelets::EdgeletSettings;
use super::localize::Localizer;
use super::pipeline::{Run, Truth};
use super::synthetic::{
    coco_json, labels, marking_points, picture, site_cameras, users_at, work_zone_traffic,
    CocoFrame, World,
};
use super::vanishing::RansacSettings;
use super::RoadUserClass;
use crate::camera::synthetic::PinholeCamera;
use crate::camera::{load_calibration, Homography};
use crate::rng::Prng;
use crate::road::Road;

/// Where the synthetic site is on Earth (its local frame's origin).
pub const SYNTHETIC_ORIGIN: (f64, f64) = (42.2808, -83.7430);

/// One camera read from its folder.
#[derive(Debug, Clone)]
pub struct CameraFolder {
    /// The folder.
    pub dir: PathBuf,
    /// Its calibration from the first frame.
    pub calibration: SceneCalibration,
    /// Its localizer.
    pub localizer: Localizer,
    /// Its frames' masks.
    pub frames: Vec<FrameMasks>,
    /// The first frame's file.
    pub first_frame: PathBuf,
    /// Root-mean-square error of the reference points, metres.
    pub rmse_m: f64,
}

fn read(path: &Path) -> Result<String, String> {
    fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))
}

/// The local frame of a site: around the first reference point of `dir`.
pub fn site_frame(dir: &Path) -> Result<Road, String> {
    let points = load_calibration(&dir.join("calibration.json")).map_err(|e| e.to_string())?;
    let first = points.first().ok_or("calibration.json has no points")?;
    Ok(Road::new(first.ground, Vec::new()))
}

/// Reads a camera folder in the local frame of `site`.
pub fn load_camera(dir: &Path, site: &Road) -> Result<CameraFolder, String> {
    let points = load_calibration(&dir.join("calibration.json")).map_err(|e| e.to_string())?;
    let homography = Homography::from_correspondences(site, &points)
        .map_err(|e| format!("{}: {e}", dir.display()))?;
    let detections = dir.join("detections.json");
    let frames =
        parse_coco(&read(&detections)?).map_err(|e| format!("{}: {e}", detections.display()))?;
    let name = frames
        .first()
        .and_then(|f| f.file_name.clone())
        .ok_or_else(|| format!("{}: no image with a file name", detections.display()))?;
    let first_frame = dir.join(name);
    let grey = image::open(&first_frame)
        .map_err(|e| format!("{}: {e}", first_frame.display()))?
        .to_luma8();
    let calibration = calibrate(
        &grey,
        &EdgeletSettings::default(),
        &RansacSettings::default(),
    )
    .map_err(|e| format!("{}: {e}", first_frame.display()))?;
    let localizer = Localizer::new(&calibration, homography.matrix()).map_err(|e| e.to_string())?;
    Ok(CameraFolder {
        dir: dir.to_path_buf(),
        calibration,
        localizer,
        frames,
        first_frame,
        rmse_m: homography.rmse(),
    })
}

/// The tracks of a run as JSON: per frame, each track's id, class, lat/lon, local metres,
/// speed, heading and their 1-sigma errors.
pub fn tracks_json(run: &Run, site: &Road) -> Value {
    let frames: Vec<Value> = run
        .tracked
        .iter()
        .map(|f| {
            let tracks: Vec<Value> = f
                .tracks
                .iter()
                .map(|t| {
                    let ll = site.to_wgs84(t.position);
                    json!({
                        "id": t.id, "class": t.class.name(),
                        "lat": ll.map(|p| p.lat_deg()), "lon": ll.map(|p| p.lon_deg()),
                        "east_m": t.position[0], "north_m": t.position[1],
                        "speed_mps": t.speed_mps, "heading_deg": t.heading_deg,
                        "position_sigma_m": t.position_sigma_m, "speed_sigma_mps": t.speed_sigma_mps,
                    })
                })
                .collect();
            json!({"frame": f.frame, "time_s": f.time_s, "tracks": tracks})
        })
        .collect();
    json!({ "frames": frames })
}

/// Reads a truth file (as [`synthesize`] writes it) into each frame's truths, local metres
/// of `site`.
pub fn read_truth(path: &Path, site: &Road) -> Result<Vec<Vec<Truth>>, String> {
    let v: Value =
        serde_json::from_str(&read(path)?).map_err(|e| format!("{}: {e}", path.display()))?;
    let frames = v["frames"].as_array().ok_or("truth: no \"frames\" array")?;
    frames
        .iter()
        .map(|f| {
            let users = f["users"]
                .as_array()
                .ok_or("truth: a frame has no \"users\"")?;
            users
                .iter()
                .map(|u| {
                    let class = u["class"].as_str().and_then(RoadUserClass::from_name);
                    let ll = LatLon::from_degrees(
                        u["lat"].as_f64().unwrap_or(f64::NAN),
                        u["lon"].as_f64().unwrap_or(f64::NAN),
                    );
                    match (class, ll) {
                        (Some(c), Some(p)) => Ok((c, site.to_local(p))),
                        _ => Err(String::from("truth: a user needs a class and a lat/lon")),
                    }
                })
                .collect()
        })
        .collect()
}

/// Reads a work-zone area file, `{"area": [{"lat": deg, "lon": deg}, ...]}` (at least three
/// corners, in order), into local metres of `site`.
pub fn read_zone(path: &Path, site: &Road) -> Result<Vec<[f64; 2]>, String> {
    let v: Value =
        serde_json::from_str(&read(path)?).map_err(|e| format!("{}: {e}", path.display()))?;
    let corners = v["area"]
        .as_array()
        .ok_or_else(|| format!("{}: no \"area\" array", path.display()))?;
    let area: Vec<[f64; 2]> = corners
        .iter()
        .map(|c| {
            LatLon::from_degrees(
                c["lat"].as_f64().unwrap_or(f64::NAN),
                c["lon"].as_f64().unwrap_or(f64::NAN),
            )
            .map(|p| site.to_local(p))
            .ok_or_else(|| format!("{}: a corner needs a valid lat and lon", path.display()))
        })
        .collect::<Result<_, _>>()?;
    if area.len() < 3 {
        return Err(format!(
            "{}: the area needs at least three corners",
            path.display()
        ));
    }
    Ok(area)
}

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
/// of road, see [`read_zone`]). Returns the camera folders.
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

/// Draws a camera's first frame with the 3D boxes of its detections (and each position as a
/// cross) to `png`.
pub fn draw_first_frame(camera: &CameraFolder, png: &Path) -> Result<(), String> {
    let mut image = image::open(&camera.first_frame)
        .map_err(|e| format!("{}: {e}", camera.first_frame.display()))?
        .to_rgb8();
    let masks = camera
        .frames
        .first()
        .map_or(&[][..], |f| f.silhouettes.as_slice());
    let (boxes, _) = camera.localizer.frame(masks);
    for b in &boxes {
        let at = camera
            .localizer
            .camera()
            .project([b.position[0], b.position[1], 0.0]);
        draw_box(&mut image, &b.road_user, at);
    }
    image
        .save(png)
        .map_err(|e| format!("{}: {e}", png.display()))
}
