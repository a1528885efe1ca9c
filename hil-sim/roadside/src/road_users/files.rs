//! Road users from files: a camera's folder (its first frame as PNG, the detector's COCO
//! file, the reference points), the tracks written as JSON, and a truth file and a work
//! zone's area read back. (The bench renders synthetic sites in this layout.)
//!
//! A camera folder holds `calibration.json` (reference points: pixel and lat/lon, see
//! [`crate::camera::parse_calibration`]), `detections.json` (COCO: one image per frame, in
//! frame order) and the PNG of its first image (the vanishing points are found on it). All
//! cameras of a site share the local frame around the first camera's first reference point.

mod error;

pub use error::FileError;

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

fn read(path: &Path) -> Result<String, FileError> {
    fs::read_to_string(path).map_err(|source| FileError::Io {
        path: path.to_path_buf(),
        source,
    })
}

/// The JSON of a file.
fn read_json(path: &Path) -> Result<Value, FileError> {
    serde_json::from_str(&read(path)?).map_err(|source| FileError::Json {
        path: path.to_path_buf(),
        source,
    })
}

/// An image file.
fn open_image(path: &Path) -> Result<image::DynamicImage, FileError> {
    image::open(path).map_err(|source| FileError::Image {
        path: path.to_path_buf(),
        source,
    })
}

/// The local frame of a site: around the first reference point of `dir`.
///
/// # Errors
///
/// [`FileError::Calibration`] or [`FileError::NoCalibrationPoints`].
pub fn site_frame(dir: &Path) -> Result<Road, FileError> {
    let points = load_calibration(&dir.join("calibration.json"))?;
    let first = points.first().ok_or(FileError::NoCalibrationPoints)?;
    Ok(Road::new(first.ground, Vec::new()))
}

/// Reads a camera folder in the local frame of `site`.
///
/// # Errors
///
/// [`FileError`]: a file of the folder that cannot be read or is not what it must be, or
/// a calibration that fails.
pub fn load_camera(dir: &Path, site: &Road) -> Result<CameraFolder, FileError> {
    let points = load_calibration(&dir.join("calibration.json"))?;
    let homography = Homography::from_correspondences(site, &points).map_err(|source| {
        FileError::Homography {
            dir: dir.to_path_buf(),
            source,
        }
    })?;
    let detections = dir.join("detections.json");
    let frames = match parse_coco(&read(&detections)?) {
        Ok(frames) => frames,
        Err(source) => {
            return Err(FileError::Masks {
                path: detections,
                source,
            })
        }
    };
    let Some(name) = frames.first().and_then(|f| f.file_name.clone()) else {
        return Err(FileError::NoImageName { path: detections });
    };
    let first_frame = dir.join(name);
    let grey = open_image(&first_frame)?.to_luma8();
    let calibration = match calibrate(
        &grey,
        &EdgeletSettings::default(),
        &RansacSettings::default(),
    ) {
        Ok(calibration) => calibration,
        Err(source) => {
            return Err(FileError::VanishingPoints {
                path: first_frame,
                source,
            })
        }
    };
    let localizer =
        Localizer::new(&calibration, homography.matrix()).map_err(FileError::Localizer)?;
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
                        "semi_major_m": t.position_ellipse.semi_major_m,
                        "semi_minor_m": t.position_ellipse.semi_minor_m,
                        "orientation_deg": t.position_ellipse.orientation_deg,
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
///
/// # Errors
///
/// [`FileError`]: the file cannot be read, is not JSON or not of that shape.
pub fn read_truth(path: &Path, site: &Road) -> Result<Vec<Vec<Truth>>, FileError> {
    let v = read_json(path)?;
    let frames = v["frames"].as_array().ok_or(FileError::NoTruthFrames)?;
    frames
        .iter()
        .map(|f| {
            let users = f["users"]
                .as_array()
                .ok_or(FileError::TruthFrameWithoutUsers)?;
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
                        _ => Err(FileError::TruthUser),
                    }
                })
                .collect()
        })
        .collect()
}

/// Reads a work-zone area file, `{"area": [{"lat": deg, "lon": deg}, ...]}` (at least three
/// corners, in order), into local metres of `site`.
///
/// # Errors
///
/// [`FileError`]: the file cannot be read, is not JSON or not of that shape.
pub fn read_zone(path: &Path, site: &Road) -> Result<Vec<[f64; 2]>, FileError> {
    let v = read_json(path)?;
    let corners = v["area"].as_array().ok_or_else(|| FileError::NoArea {
        path: path.to_path_buf(),
    })?;
    let area: Vec<[f64; 2]> = corners
        .iter()
        .map(|c| {
            LatLon::from_degrees(
                c["lat"].as_f64().unwrap_or(f64::NAN),
                c["lon"].as_f64().unwrap_or(f64::NAN),
            )
            .map(|p| site.to_local(p))
            .ok_or_else(|| FileError::BadCorner {
                path: path.to_path_buf(),
            })
        })
        .collect::<Result<_, _>>()?;
    if area.len() < 3 {
        return Err(FileError::TooFewCorners {
            path: path.to_path_buf(),
            corners: area.len(),
        });
    }
    Ok(area)
}

/// Draws a camera's first frame with the 3D boxes of its detections (and each position as a
/// cross) to `png`.
///
/// # Errors
///
/// [`FileError::Image`]: the frame cannot be read or the drawing written.
pub fn draw_first_frame(camera: &CameraFolder, png: &Path) -> Result<(), FileError> {
    let mut image = open_image(&camera.first_frame)?.to_rgb8();
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
    image.save(png).map_err(|source| FileError::Image {
        path: png.to_path_buf(),
        source,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_area_file_says_what_is_wrong_with_it() {
        let site = Road::new(
            LatLon::from_degrees(39.7392, -104.9903).unwrap(),
            Vec::new(),
        );
        let dir = std::env::temp_dir().join(format!("area-file-{}", std::process::id()));
        fs::create_dir_all(&dir).unwrap();
        let path = dir.join("zone.json");
        let corner = r#"{"lat": 39.7392, "lon": -104.9903}"#;
        fs::write(&path, format!(r#"{{"area": [{corner}, {corner}]}}"#)).unwrap();
        let err = read_zone(&path, &site).unwrap_err();
        assert!(
            matches!(err, FileError::TooFewCorners { corners: 2, .. }),
            "{err:?}"
        );
        assert!(err
            .to_string()
            .ends_with("zone.json: the area needs at least three corners"));
        fs::write(
            &path,
            format!(r#"{{"area": [{corner}, {{"lat": 91}}, {corner}]}}"#),
        )
        .unwrap();
        assert!(matches!(
            read_zone(&path, &site),
            Err(FileError::BadCorner { .. })
        ));
        fs::write(&path, "{").unwrap();
        assert!(matches!(
            read_zone(&path, &site),
            Err(FileError::Json { .. })
        ));
        assert!(matches!(
            read_zone(&dir.join("missing.json"), &site),
            Err(FileError::Io { source, .. }) if source.kind() == std::io::ErrorKind::NotFound
        ));
        let _ = fs::remove_dir_all(&dir);
    }
}
