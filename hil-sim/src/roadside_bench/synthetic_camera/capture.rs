//! A synthetic capture of a work zone (control points and frames of detections) and the
//! files it is written to.

use std::path::{Path, PathBuf};

use serde_json::{json, Value};

use super::{control_points, detect, zone_scene, Placement, SyntheticError, ZoneScene};
use roadside::camera::Correspondence;
use roadside::cones::{Detection, FrameDetections};
use roadside::rng::Prng;
use roadside::road::Road;

/// What a synthetic capture of a zone records.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CaptureSpec {
    /// Frames of detections.
    pub frames: usize,
    /// Pixel noise of the control points and of the cones' boxes, 1-sigma per axis.
    pub noise_px: f64,
    /// Probability that a cone is missed in a frame.
    pub miss_rate: f64,
    /// Seed of the noise and the misses.
    pub seed: u64,
    /// Where the camera goes and how the cones are set.
    pub placement: Placement,
}

impl Default for CaptureSpec {
    /// 10 frames, 1 px noise, a miss rate of 0.1, seed 1, the default [`Placement`].
    fn default() -> Self {
        Self {
            frames: 10,
            noise_px: 1.0,
            miss_rate: 0.1,
            seed: 1,
            placement: Placement::default(),
        }
    }
}

/// A synthetic capture of a zone: the scene (ground truth), the calibration and the frames.
#[derive(Debug, Clone, PartialEq)]
pub struct Capture {
    /// The cones, the camera and the surveyed control points.
    pub scene: ZoneScene,
    /// The control points with noisy pixels.
    pub calibration: Vec<Correspondence>,
    /// The detections of every frame.
    pub frames: Vec<FrameDetections>,
}

/// Captures the zone closing `closed_lanes` from `start_m` to `end_m` (see [`zone_scene`]):
/// control points, then the frames, with the noise of `spec`.
pub fn capture(
    road: &Road,
    closed_lanes: &[u8],
    (start_m, end_m): (f64, f64),
    spec: &CaptureSpec,
) -> Result<Capture, SyntheticError> {
    let noise_ok = spec.noise_px.is_finite() && spec.noise_px >= 0.0;
    if !(noise_ok && (0.0..=1.0).contains(&spec.miss_rate)) {
        return Err(SyntheticError::BadSpec);
    }
    let scene = zone_scene(road, closed_lanes, start_m, end_m, &spec.placement)?;
    let mut rng = Prng::new(spec.seed);
    let calibration = control_points(road, &scene.camera, &scene.control, &mut rng, spec.noise_px)?;
    let (noise, miss) = (spec.noise_px, spec.miss_rate);
    let frames = detect(
        &scene.camera,
        &scene.cones,
        spec.frames,
        noise,
        miss,
        &mut rng,
    );
    Ok(Capture {
        scene,
        calibration,
        frames,
    })
}

impl Capture {
    /// Writes `calibration.json` (with `note` as its `camera`) and `detections.json` into
    /// `dir` (created if missing) and returns their paths.
    pub fn write(&self, dir: &Path, note: &str) -> Result<[PathBuf; 2], String> {
        std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
        let files = [
            (
                "calibration.json",
                calibration_json(&self.calibration, note),
            ),
            ("detections.json", detections_json(&self.frames)),
        ];
        let paths = [0, 1].map(|k| dir.join(files[k].0));
        for (path, (_, text)) in paths.iter().zip(files) {
            std::fs::write(path, text).map_err(|e| format!("{}: {e}", path.display()))?;
        }
        Ok(paths)
    }

    /// Detections over all frames.
    pub fn detections(&self) -> usize {
        self.frames.iter().map(|f| f.detections.len()).sum()
    }
}

/// A calibration file, one point a line: `{"camera": note, "points": [{"pixel": [u, v],
/// "lat": deg, "lon": deg}, ...]}`, pixels to 0.01 px, positions to 1e-7 degrees.
pub fn calibration_json(points: &[Correspondence], note: &str) -> String {
    let lines: Vec<String> = points
        .iter()
        .map(|c| {
            let (lat, lon) = (c.ground.lat_deg(), c.ground.lon_deg());
            let pixel = json!(c.pixel.map(centi));
            format!("    {{\"pixel\": {pixel}, \"lat\": {lat:.7}, \"lon\": {lon:.7}}}")
        })
        .collect();
    let note = Value::from(note);
    let points = lines.join(",\n");
    format!("{{\n  \"camera\": {note},\n  \"points\": [\n{points}\n  ]\n}}\n")
}

/// A detections file, one frame a line: `[{"frame": 0, "boxes": [[x_min, y_min, x_max,
/// y_max], ...]}, ...]`, pixels to 0.01 px (a box with a score as `{"box", "score"}`).
pub fn detections_json(frames: &[FrameDetections]) -> String {
    let lines: Vec<String> = frames
        .iter()
        .map(|f| {
            let boxes = Value::Array(f.detections.iter().map(box_json).collect());
            format!("  {{\"frame\": {}, \"boxes\": {boxes}}}", f.frame)
        })
        .collect();
    format!("[\n{}\n]\n", lines.join(",\n"))
}

fn box_json(d: &Detection) -> Value {
    let b = &d.bbox;
    let corners = [b.x_min, b.y_min, b.x_max, b.y_max].map(centi);
    match d.score {
        Some(score) => json!({ "box": corners, "score": score }),
        None => json!(corners),
    }
}

fn round(v: f64, scale: f64) -> f64 {
    (v * scale).round() / scale
}

fn centi(v: f64) -> f64 {
    round(v, 100.0)
}

#[cfg(test)]
mod tests {
    use super::super::PinholeCamera;
    use super::*;
    use geodesy::LatLon;
    use roadside::camera::{parse_calibration, CameraModel};
    use roadside::cones::parse_detections_json;
    use roadside::road::dist;

    fn road() -> Road {
        let r = LatLon::from_degrees(39.7392, -104.9903).unwrap();
        Road::straight(r, 90.0, 1000.0, (3, 2), 3.6, 80.0)
    }

    #[test]
    fn files_round_trip_and_calibrate() {
        let road = road();
        let cam = PinholeCamera::new([0.0, -11.0, 8.0], 75.0, 18.0);
        let ground = [
            [10.0, -9.0],
            [10.0, 0.0],
            [25.0, -9.0],
            [25.0, 7.2],
            [40.0, 1.8],
        ];
        let mut rng = Prng::new(3);
        let pts = control_points(&road, &cam, &ground, &mut rng, 0.0).unwrap();
        let back = parse_calibration(&calibration_json(&pts, "test")).unwrap();
        assert_eq!(back.len(), 5);
        assert_eq!(back[2].ground, pts[2].ground);
        assert!(dist(back[2].pixel, pts[2].pixel) < 0.01);
        let model = CameraModel::homography(&road, &back).unwrap();
        assert!(model.rmse_m() < 0.03, "{}", model.rmse_m());
        let far = [[0.0, -11.0]];
        assert_eq!(
            control_points(&road, &cam, &far, &mut rng, 0.0),
            Err(SyntheticError::OutOfView { index: 0 })
        );
        let cones = [[20.0, -3.6], [30.0, -7.2], [-5.0, 0.0]];
        let frames = detect(&cam, &cones, 4, 1.0, 0.0, &mut rng);
        let parsed = parse_detections_json(&detections_json(&frames)).unwrap();
        assert_eq!(parsed.len(), 4);
        // The cone behind the camera is never seen; none is missed at a miss rate of 0.
        assert!(parsed.iter().all(|f| f.detections.len() == 2));
        let none = detect(&cam, &cones, 3, 1.0, 1.0, &mut rng);
        assert!(none.iter().all(|f| f.detections.is_empty()));
    }

    #[test]
    fn captures_are_seeded_and_checked() {
        let road = road();
        let spec = CaptureSpec::default();
        let a = capture(&road, &[3], (420.0, 520.0), &spec).unwrap();
        assert_eq!(a, capture(&road, &[3], (420.0, 520.0), &spec).unwrap());
        assert_eq!(a.frames.len(), 10);
        assert!(a.detections() > 0 && a.detections() <= 10 * a.scene.cones.len());
        let other = CaptureSpec { seed: 2, ..spec };
        assert_ne!(
            a.frames,
            capture(&road, &[3], (420.0, 520.0), &other).unwrap().frames
        );
        for bad in [
            CaptureSpec {
                noise_px: -1.0,
                ..spec
            },
            CaptureSpec {
                noise_px: f64::NAN,
                ..spec
            },
            CaptureSpec {
                miss_rate: 1.5,
                ..spec
            },
        ] {
            let got = capture(&road, &[3], (420.0, 520.0), &bad);
            assert_eq!(got, Err(SyntheticError::BadSpec));
        }
    }
}
