//! Road users from files: a camera's folder (its first frame as PNG, the detector's COCO
//! file, the reference points), the tracks written as JSON, and a truth file and a work
//! zone's area read back. (The bench renders synthetic sites in this layout.)
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
use super::vanishing::RansacSettings;
use super::RoadUserClass;
use crate::camera::{load_calibration, Homography};
use crate::road::Road;

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

/// Reads a truth file, `{"frames": [{"users": [{"class": name, "lat": deg, "lon": deg},
/// ...]}, ...]}` (one entry per frame, as the bench's synthetic sites come with), into each
/// frame's truths, local metres of `site`.
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
