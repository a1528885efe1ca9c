//! Zone geometry of a scenario from its sources: a cone list, a WZDx feed, or cones
//! localised by a calibrated camera from per-frame detections.

use crate::camera::{self, CameraModel};
use crate::cones::{self, ConeTracker, TrackerConfig};
use crate::road::Road;
use crate::scenario::{Scenario, ZoneSource};
use std::path::Path;

/// Closed lanes and the start/end stations (along the first closed lane) of a zone.
pub fn geometry(
    s: &Scenario,
    road: &Road,
    source: &ZoneSource,
) -> Result<(Vec<u8>, f64, f64), String> {
    let read = |p: &Path| {
        let path = s.path(p);
        std::fs::read_to_string(&path).map_err(|e| format!("{}: {e}", path.display()))
    };
    match source {
        ZoneSource::Lanes {
            closed_lanes,
            start_m,
            end_m,
        } => Ok((closed_lanes.clone(), *start_m, *end_m)),
        ZoneSource::Cones { file } => {
            let cones = crate::geojson::load_cones(road, &read(file)?)
                .map_err(|e| format!("{}: {e}", file.display()))?;
            from_cones(road, &cones)
        }
        ZoneSource::Wzdx { file } => {
            let zones = crate::geojson::work_zones_from_wzdx(road, &read(file)?)
                .map_err(|e| format!("{}: {e}", file.display()))?;
            let z = zones
                .first()
                .ok_or(format!("{}: no work-zone event", file.display()))?;
            Ok((z.closed_lanes.clone(), z.start_m, z.end_m))
        }
        ZoneSource::Camera {
            calibration,
            detections,
        } => {
            let points = camera::parse_calibration(&read(calibration)?)
                .map_err(|e| format!("{}: {e}", calibration.display()))?;
            let model = CameraModel::homography(road, &points)
                .map_err(|e| format!("{}: {e}", calibration.display()))?;
            let frames = cones::parse_detections_json(&read(detections)?)
                .map_err(|e| format!("{}: {e}", detections.display()))?;
            let mut tracker =
                ConeTracker::new(TrackerConfig::default()).ok_or("tracker configuration")?;
            let mut confirmed = Vec::new();
            for f in &frames {
                let local: Vec<[f64; 2]> = f
                    .detections
                    .iter()
                    .filter_map(|d| model.to_local(d.bbox.bottom_centre()))
                    .collect();
                confirmed = tracker.push_frame(&local);
            }
            from_cones(road, &confirmed)
        }
    }
}

/// A zone from cone positions: the lanes they close and the closure of the first.
fn from_cones(road: &Road, cones: &[[f64; 2]]) -> Result<(Vec<u8>, f64, f64), String> {
    let closures = cones::closures(road, cones);
    let first = closures
        .first()
        .ok_or("no cone lies on a lane of the map")?;
    Ok((
        closures.iter().map(|c| c.lane).collect(),
        first.start_m,
        first.end_m,
    ))
}
