//! The PersonalSafetyMessage of a road worker the roadside camera tracks: basic type
//! public-safety worker, activity "working on road", the track's position, accuracy, speed
//! and heading, a temporary id that stays with the track, and the track's recent positions
//! as path history.

use super::{checked, fit, position, velocity, BuildError};
use crate::clock::Utc;
use crate::ellipse::ErrorEllipse;
use geodesy::LatLon;
use j2735::msg::common::{
    DSecond, Heading, MsgCount, OffsetLLB18, PathHistory, PathHistoryPoint, PathHistoryPointList,
    PositionalAccuracy, SemiMajorAxisAccuracy, SemiMajorAxisOrientation, SemiMinorAxisAccuracy,
    TemporaryID, TimeOffset, Velocity, VertOffsetB12,
};
use j2735::msg::personal_safety_message::{
    PersonalDeviceUserType, PersonalSafetyMessage, PublicSafetyAndRoadWorkerActivity,
};
use j2735::uper::Extensions;
use j2735::{MessageFrame, MessageFrameValue};

/// Path history points a PSM carries at most (`PathHistoryPointList` SIZE(1..23)).
pub const MAX_CRUMBS: usize = 23;

/// A tracked worker as the PSM tells it.
#[derive(Debug, Clone, PartialEq)]
pub struct Worker {
    /// Temporary id, stable for the track.
    pub id: [u8; 4],
    /// Where the worker stands.
    pub position: LatLon,
    /// Horizontal error of the position: the 1-sigma ellipse.
    pub accuracy: ErrorEllipse,
    /// Ground speed, m/s.
    pub speed_mps: f64,
    /// Direction of motion, degrees clockwise from true north (`None` when standing).
    pub heading_deg: Option<f64>,
    /// Earlier positions of the track, newest first, with their age in seconds.
    pub history: Vec<(LatLon, f64)>,
}

/// The PSM of `worker` at `now` with message count `msg_cnt` (0-127, bumped per message).
pub fn build_psm(worker: &Worker, now: Utc, msg_cnt: u8) -> Result<Box<MessageFrame>, BuildError> {
    let mut activity =
        PublicSafetyAndRoadWorkerActivity::zeros(6).ok_or(BuildError::Codec("activity".into()))?;
    activity
        .0
        .set(PublicSafetyAndRoadWorkerActivity::WORKING_ON_ROAD, true);
    let psm = PersonalSafetyMessage {
        basic_type: PersonalDeviceUserType::APUBLICSAFETYWORKER,
        sec_mark: fit("secMark", now.dsecond().into(), DSecond::new)?,
        msg_cnt: fit("msgCnt", msg_cnt.into(), MsgCount::new)?,
        id: TemporaryID(worker.id),
        position: position(worker.position)?,
        accuracy: accuracy(&worker.accuracy)?,
        speed: speed(worker.speed_mps)?,
        heading: heading(worker.heading_deg)?,
        accel_set: None,
        path_history: path_history(worker)?,
        path_prediction: None,
        propulsion: None,
        use_state: None,
        cross_request: None,
        cross_state: None,
        cluster_size: None,
        cluster_radius: None,
        event_responder_type: None,
        activity_type: Some(activity),
        activity_sub_type: None,
        assist_type: None,
        sizing: None,
        attachment: None,
        attachment_radius: None,
        animal_type: None,
        regional: None,
        extensions: Extensions::new(),
    };
    checked(MessageFrame {
        value: MessageFrameValue::PersonalSafetyMessage(psm.into()),
        extensions: Extensions::new(),
    })
}

/// m/s as `Velocity` (0.02 m/s units); unavailable (8191) for a speed not known.
fn speed(mps: f64) -> Result<Velocity, BuildError> {
    if mps.is_finite() && mps >= 0.0 {
        fit("speed", velocity(mps), Velocity::new)
    } else {
        Ok(Velocity::UNAVAILABLE)
    }
}

/// An error ellipse as `PositionalAccuracy`: its axes in 0.05 m units (254 for 12.7 m or
/// more; unavailable, 255, for an error not known), the major axis's direction in units of
/// 360/65535 degrees from true north (unavailable, 65535, when the axes are not known).
fn accuracy(e: &ErrorEllipse) -> Result<PositionalAccuracy, BuildError> {
    let axis = |sigma_m: f64| {
        if sigma_m.is_finite() && sigma_m >= 0.0 {
            ((sigma_m / 0.05).round() as i64).clamp(0, 254)
        } else {
            255
        }
    };
    let (major, minor) = (axis(e.semi_major_m), axis(e.semi_minor_m));
    let orientation = if major == 255 || minor == 255 || !e.orientation_deg.is_finite() {
        65_535
    } else {
        ((e.orientation_deg.rem_euclid(360.0) * 65_535.0 / 360.0).round() as i64) % 65_535
    };
    Ok(PositionalAccuracy {
        semi_major: fit("semiMajor", major, SemiMajorAxisAccuracy::new)?,
        semi_minor: fit("semiMinor", minor, SemiMinorAxisAccuracy::new)?,
        orientation: fit("orientation", orientation, SemiMajorAxisOrientation::new)?,
    })
}

/// Degrees as `Heading` (0.0125 degree units; unavailable without one).
fn heading(deg: Option<f64>) -> Result<Heading, BuildError> {
    match deg {
        Some(d) if d.is_finite() => {
            let units = ((d.rem_euclid(360.0) / 0.0125).round() as i64) % 28_800;
            fit("heading", units, Heading::new)
        }
        _ => Ok(Heading::UNAVAILABLE),
    }
}

/// The track's earlier positions as offsets from the present one (1e-7 degree units, 10
/// ms time units); points younger than 5 ms are skipped, points beyond the offsets' reach
/// (about 1.3 km, 655 s) end the list. `None` without history.
fn path_history(worker: &Worker) -> Result<Option<PathHistory>, BuildError> {
    let mut crumbs = PathHistoryPointList::new();
    let (lat0, lon0) = (
        i64::from(worker.position.lat_e7()),
        i64::from(worker.position.lon_e7()),
    );
    for (at, age_s) in worker.history.iter().take(MAX_CRUMBS) {
        let (dlat, dlon) = (i64::from(at.lat_e7()) - lat0, i64::from(at.lon_e7()) - lon0);
        let ticks = (age_s * 100.0).round();
        if ticks.is_nan() || ticks < 1.0 {
            // The present position again (or an age not known): no crumb.
            continue;
        }
        let reach = -131_071..=131_071;
        if !(reach.contains(&dlat) && reach.contains(&dlon) && ticks < 65_535.0) {
            break;
        }
        let point = PathHistoryPoint {
            lat_offset: fit("latOffset", dlat, OffsetLLB18::new)?,
            lon_offset: fit("lonOffset", dlon, OffsetLLB18::new)?,
            // -2048: elevation offset unavailable (the camera measures on the road plane).
            elevation_offset: fit("elevationOffset", -2048, VertOffsetB12::new)?,
            time_offset: fit("timeOffset", ticks as i64, TimeOffset::new)?,
            speed: None,
            pos_accuracy: None,
            heading: None,
            extensions: Extensions::new(),
        };
        if crumbs.0.push(point).is_err() {
            break;
        }
    }
    if crumbs.0.is_empty() {
        return Ok(None);
    }
    Ok(Some(PathHistory {
        initial_position: None,
        curr_gnss_status: None,
        crumb_data: crumbs,
        extensions: Extensions::new(),
    }))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A worker walking east at 1.5 m/s, 0.5 m accuracy, no history.
    fn worker() -> Worker {
        Worker {
            id: [0xde, 0xad, 0x00, 0x01],
            position: LatLon::from_degrees(44.977_8, -93.265_0).unwrap(),
            accuracy: ErrorEllipse::circle(0.5),
            speed_mps: 1.5,
            heading_deg: Some(90.0),
            history: Vec::new(),
        }
    }

    #[test]
    fn the_psm_is_the_oracles_bytes() {
        // pycrate (../shared/oracle) encoding the JER {"messageId": 32, "value":
        // {"basicType": "aPUBLICSAFETYWORKER", "secMark": 12345, "msgCnt": 5, "id":
        // "DEAD0001", "position": {"lat": 449778000, "long": -932650000}, "accuracy":
        // {"semiMajor": 10, "semiMinor": 10, "orientation": 0}, "speed": 75, "heading": 7200,
        // "activityType": {"value": "40", "length": 6}}}.
        const ORACLE: &str = "00201b0010066072177ab400045073fa5033b2b5ef0a0a00000259c20200";
        let at = Utc::from_unix_ms(1_795_341_600_000 + 12_345);
        let frame = build_psm(&worker(), at, 5).unwrap();
        let hex = j2735::hex::Hex(&super::super::encode(&frame).unwrap()).to_string();
        assert_eq!(hex, ORACLE);
    }

    #[test]
    fn the_accuracy_ellipse_is_the_oracles_bytes() {
        // As above with "accuracy": {"semiMajor": 6, "semiMinor": 2, "orientation": 8192}:
        // 0.3 m along the north-east diagonal, 0.1 m across it.
        const ORACLE: &str = "00201b0010066072177ab400045073fa5033b2b5ef060220000259c20200";
        let mut w = worker();
        w.accuracy = ErrorEllipse {
            semi_major_m: 0.3,
            semi_minor_m: 0.1,
            orientation_deg: 45.0,
        };
        let at = Utc::from_unix_ms(1_795_341_600_000 + 12_345);
        let frame = build_psm(&w, at, 5).unwrap();
        let hex = j2735::hex::Hex(&super::super::encode(&frame).unwrap()).to_string();
        assert_eq!(hex, ORACLE);
    }

    #[test]
    fn units_and_unavailable_values() {
        let circle = |s: f64| accuracy(&ErrorEllipse::circle(s)).unwrap();
        assert_eq!(circle(0.5).semi_major.get(), 10);
        assert_eq!(circle(100.0).semi_major.get(), 254);
        assert_eq!(circle(f64::NAN).semi_minor.get(), 255);
        assert_eq!(circle(f64::NAN).orientation.get(), 65_535);
        assert_eq!(heading(Some(359.999)).unwrap().get(), 0);
        assert_eq!(heading(Some(-90.0)).unwrap().get(), 21_600);
        assert_eq!(heading(None).unwrap(), Heading::UNAVAILABLE);
        assert_eq!(heading(Some(f64::INFINITY)).unwrap(), Heading::UNAVAILABLE);
        assert_eq!(circle(-1.0).semi_major.get(), 255);
        assert_eq!(speed(1.5).unwrap().get(), 75);
        assert_eq!(speed(f64::NAN).unwrap(), Velocity::UNAVAILABLE);
        assert_eq!(speed(-0.5).unwrap(), Velocity::UNAVAILABLE);
        assert_eq!(speed(1_000.0).unwrap().get(), 8190);
    }

    #[test]
    fn history_stops_where_the_offsets_end() {
        let mut w = worker();
        let far = LatLon::from_degrees(44.977_8, -93.0).unwrap();
        let near = LatLon::from_degrees(44.977_8, -93.265_1).unwrap();
        w.history = vec![
            (w.position, 0.0),
            (near, 1.0),
            (near, 2.0),
            (far, 3.0),
            (near, 4.0),
        ];
        let ph = path_history(&w).unwrap().unwrap();
        assert_eq!(ph.crumb_data.0.len(), 2);
        assert_eq!(ph.crumb_data.0[0].lon_offset.get(), -1000);
        assert_eq!(ph.crumb_data.0[1].time_offset.get(), 200);
        w.history = (0..40).map(|k| (near, 0.1 * (k + 1) as f64)).collect();
        assert_eq!(
            path_history(&w).unwrap().unwrap().crumb_data.0.len(),
            MAX_CRUMBS
        );
        w.history.clear();
        assert_eq!(path_history(&w).unwrap(), None);
    }
}
