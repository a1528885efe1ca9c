//! Calibration files: ground control points (a pixel and the surveyed position of the same
//! road point).

use std::fmt;

use geodesy::LatLon;
use serde::Deserialize;

/// One ground control point: a pixel and the surveyed position of the same road point.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Correspondence {
    /// Image position `[u, v]`, pixels (u right, v down).
    pub pixel: [f64; 2],
    /// Position on the road plane.
    pub ground: LatLon,
}

/// Why a calibration file was refused.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub enum CalibrationError {
    /// The file could not be read.
    Io(String),
    /// Not JSON of the expected shape (serde's message, with line and column).
    Json(String),
    /// `points[index]` is invalid.
    Point {
        /// Index in `points` (0-based).
        index: usize,
        /// What is wrong with it.
        reason: &'static str,
    },
}

impl fmt::Display for CalibrationError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Io(e) => write!(f, "calibration file: {e}"),
            Self::Json(e) => write!(f, "calibration JSON: {e}"),
            Self::Point { index, reason } => write!(f, "calibration points[{index}]: {reason}"),
        }
    }
}

impl std::error::Error for CalibrationError {}

#[derive(Deserialize)]
struct RawCalibration {
    points: Vec<RawPoint>,
}

#[derive(Deserialize)]
struct RawPoint {
    pixel: [f64; 2],
    lat: f64,
    lon: f64,
}

/// Parses a calibration file: `{"points": [{"pixel": [u, v], "lat": deg, "lon": deg}, ...]}`.
///
/// Other keys are ignored. The number of points is not checked here (see
/// [`ModelError`](super::ModelError)).
pub fn parse_calibration(json: &str) -> Result<Vec<Correspondence>, CalibrationError> {
    let raw: RawCalibration =
        serde_json::from_str(json).map_err(|e| CalibrationError::Json(e.to_string()))?;
    raw.points
        .iter()
        .enumerate()
        .map(|(index, p)| {
            let bad = |reason| CalibrationError::Point { index, reason };
            if !p.pixel.iter().all(|c| c.is_finite()) {
                return Err(bad("pixel is not finite"));
            }
            if !(-90.0..=90.0).contains(&p.lat) || !(-180.0..=180.0).contains(&p.lon) {
                return Err(bad("lat/lon out of range"));
            }
            let ground = LatLon::from_degrees(p.lat, p.lon).ok_or(bad("lat/lon out of range"))?;
            Ok(Correspondence {
                pixel: p.pixel,
                ground,
            })
        })
        .collect()
}

/// Reads and parses a calibration file (see [`parse_calibration`]).
pub fn load_calibration(path: &std::path::Path) -> Result<Vec<Correspondence>, CalibrationError> {
    let text = std::fs::read_to_string(path)
        .map_err(|e| CalibrationError::Io(format!("{}: {e}", path.display())))?;
    parse_calibration(&text)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn calibration_files() {
        let json = r#"{"camera": "cam 1", "points": [
            {"pixel": [10.5, 20], "lat": 39.7392, "lon": -104.9903},
            {"pixel": [30, 40], "lat": -45.0, "lon": 170.25, "name": "kerb"}]}"#;
        let pts = parse_calibration(json).unwrap();
        assert_eq!(pts.len(), 2);
        assert_eq!(pts[0].pixel, [10.5, 20.0]);
        assert_eq!(pts[1].ground, LatLon::from_degrees(-45.0, 170.25).unwrap());
        let bad_lat = r#"{"points": [{"pixel": [1, 2], "lat": 1, "lon": 2}, {"pixel": [1, 2], "lat": 91, "lon": 2}]}"#;
        assert_eq!(
            parse_calibration(bad_lat),
            Err(CalibrationError::Point {
                index: 1,
                reason: "lat/lon out of range"
            })
        );
        for bad in [
            "",
            "[]",
            r#"{"points": [{"pixel": [1], "lat": 1, "lon": 2}]}"#,
            r#"{"points": [{"pixel": [1, 2], "lon": 2}]}"#,
            r#"{"points": [{"pixel": [1, 2], "lat": "x", "lon": 2}]}"#,
            r#"{"points": [{"pixel": [1, 2], "lat": 1e999, "lon": 2}]}"#,
        ] {
            let e = parse_calibration(bad).unwrap_err();
            assert!(matches!(e, CalibrationError::Json(_)), "{bad}: {e}");
        }
        let missing =
            parse_calibration(r#"{"points": [{"pixel": [1, 2], "lon": 2}]}"#).unwrap_err();
        assert!(
            missing.to_string().contains("missing field `lat`"),
            "{missing}"
        );
        let io = load_calibration(std::path::Path::new("/nonexistent/cal.json")).unwrap_err();
        assert!(matches!(io, CalibrationError::Io(_)));
    }
}
