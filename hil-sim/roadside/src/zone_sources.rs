//! Zone geometry of a site from its sources: a cone list, a WZDx feed, or cones
//! localised by a calibrated camera from per-frame detections; and the site's zones as
//! the roadside broadcasts them ([`build_zones`]).

use crate::camera::{self, CameraModel};
use crate::clock::Utc;
use crate::cones::{self, ConeTracker, TrackerConfig};
use crate::messages::{SignSpeed, WorkZone, DURATION_INDEFINITE};
use crate::road::Road;
use crate::site::{Site, ZoneSource};
use std::path::Path;

/// What a source says about a zone.
#[derive(Debug, Clone, PartialEq)]
pub struct SourcedZone {
    /// Closed lanes.
    pub closed_lanes: Vec<u8>,
    /// Start station along the first closed lane, metres.
    pub start_m: f64,
    /// End station, metres.
    pub end_m: f64,
    /// The reduced limit the source gives (WZDx), if any.
    pub speed_limit: Option<SignSpeed>,
}

/// The closed lanes, stations and limit of a zone from its source.
pub fn zone(s: &Site, road: &Road, source: &ZoneSource) -> Result<SourcedZone, String> {
    if let ZoneSource::Wzdx { file } = source {
        let path = s.path(file);
        let text =
            std::fs::read_to_string(&path).map_err(|e| format!("{}: {e}", path.display()))?;
        let zones = crate::geojson::work_zones_from_wzdx(road, &text)
            .map_err(|e| format!("{}: {e}", file.display()))?;
        let z = zones.first().ok_or(format!(
            "{}: no work-zone event on this map",
            file.display()
        ))?;
        return Ok(SourcedZone {
            closed_lanes: z.closed_lanes.clone(),
            start_m: z.start_m,
            end_m: z.end_m,
            speed_limit: z.speed_limit,
        });
    }
    let (closed_lanes, start_m, end_m) = geometry(s, road, source)?;
    Ok(SourcedZone {
        closed_lanes,
        start_m,
        end_m,
        speed_limit: None,
    })
}

/// Closed lanes and the start/end stations (along the first closed lane) of a zone from a
/// source other than WZDx.
fn geometry(s: &Site, road: &Road, source: &ZoneSource) -> Result<(Vec<u8>, f64, f64), String> {
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
        ZoneSource::Wzdx { file } => Err(format!(
            "{}: a WZDx feed goes through zone()",
            file.display()
        )),
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

/// The zones of the site as the roadside builds them (stable packet ids), valid from
/// `start` until further notice.
pub fn build_zones(s: &Site, road: &Road, start: Utc) -> Result<Vec<WorkZone>, String> {
    let mut out = Vec::new();
    for (i, z) in s.zones.iter().enumerate() {
        let mut packet_id = *b"HILZONE00";
        packet_id[7] = b'0' + (i / 10) as u8 % 10;
        packet_id[8] = b'0' + (i % 10) as u8;
        let sourced = zone(s, road, &z.source)?;
        let speed_limit = match (z.limit_kmh, z.limit_mph) {
            (_, Some(value)) => Some(SignSpeed { value, mph: true }),
            (Some(value), None) => Some(SignSpeed { value, mph: false }),
            (None, None) => sourced.speed_limit,
        };
        let (closed_lanes, start_m, end_m) = (sourced.closed_lanes, sourced.start_m, sourced.end_m);
        out.push(WorkZone {
            closed_lanes,
            start_m,
            end_m,
            speed_limit,
            packet_id,
            msg_cnt: 1,
            start,
            duration_min: DURATION_INDEFINITE,
        });
    }
    Ok(out)
}
