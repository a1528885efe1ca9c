//! Cones: detector output (bounding boxes), their smoothing over video frames, and the lane
//! closures they make.
//!
//! A cone touches the road at the bottom centre of its box ([`BoundingBox::bottom_centre`]);
//! a [`crate::camera::CameraModel`] maps that pixel to local metres; a [`ConeTracker`] keeps
//! the cones seen in enough recent frames; [`closures`] matches them to lanes (the paper's
//! eq. 7-10) and gives the work zone on each closed lane.

use std::fmt;

use serde_json::Value;

use crate::assign::cheapest_first;
use crate::road::{dist, Road, RoadLane};

/// The class id of cones in YOLO files unless told otherwise.
pub const DEFAULT_CONE_CLASS: u32 = 0;
/// Most tracks a [`ConeTracker`] keeps (new cones beyond it are ignored).
pub const MAX_TRACKS: usize = 4096;

/// A detection box in image pixels (x right, y down), `x_min <= x_max`, `y_min <= y_max`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BoundingBox {
    /// Left edge.
    pub x_min: f64,
    /// Top edge.
    pub y_min: f64,
    /// Right edge.
    pub x_max: f64,
    /// Bottom edge.
    pub y_max: f64,
}

impl BoundingBox {
    /// A box; `None` unless all values are finite and the minima do not exceed the maxima.
    pub fn new(x_min: f64, y_min: f64, x_max: f64, y_max: f64) -> Option<Self> {
        let finite = [x_min, y_min, x_max, y_max].iter().all(|v| v.is_finite());
        (finite && x_min <= x_max && y_min <= y_max).then_some(Self {
            x_min,
            y_min,
            x_max,
            y_max,
        })
    }

    /// Where the cone touches the road: the bottom centre `((x_min + x_max) / 2, y_max)`.
    pub fn bottom_centre(&self) -> [f64; 2] {
        [(self.x_min + self.x_max) / 2.0, self.y_max]
    }
}

/// One detection: a box and the detector's confidence when given.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Detection {
    /// The box.
    pub bbox: BoundingBox,
    /// Confidence 0-1, if the file gives one.
    pub score: Option<f64>,
}

/// The detections of one video frame.
#[derive(Debug, Clone, PartialEq)]
pub struct FrameDetections {
    /// Frame number.
    pub frame: u64,
    /// Its detections.
    pub detections: Vec<Detection>,
}

/// Why a detection file was refused.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub enum DetectionError {
    /// Not JSON (serde's message, with line and column).
    Json(String),
    /// A JSON value of the wrong shape, at a path such as `[2].boxes[1]`.
    Entry {
        /// Where in the document.
        path: String,
        /// What is wrong.
        reason: &'static str,
    },
    /// A bad line of a YOLO file.
    Line {
        /// Line number (1-based).
        line: usize,
        /// What is wrong.
        reason: YoloLineError,
    },
    /// The image size is zero.
    ImageSize,
}

impl fmt::Display for DetectionError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Json(e) => write!(f, "detections JSON: {e}"),
            Self::Entry { path, reason } => write!(f, "detections{path}: {reason}"),
            Self::Line { line, reason } => write!(f, "line {line}: {reason}"),
            Self::ImageSize => f.write_str("image size must be positive"),
        }
    }
}

impl std::error::Error for DetectionError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            Self::Line { reason, .. } => Some(reason),
            Self::Json(_) | Self::Entry { .. } | Self::ImageSize => None,
        }
    }
}

/// What is wrong with a line of a YOLO file.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub enum YoloLineError {
    /// Not 5 or 6 fields.
    FieldCount {
        /// Fields found.
        found: usize,
    },
    /// The class is not a non-negative integer.
    Class {
        /// The field as found.
        value: String,
    },
    /// A coordinate or the score is not a number from 0 to 1.
    NotUnit {
        /// The field as found.
        value: String,
    },
    /// The box is empty or inverted.
    InvalidBox,
}

impl fmt::Display for YoloLineError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::FieldCount { found } => write!(
                f,
                "expected `class cx cy w h [score]`, found {found} fields"
            ),
            Self::Class { value } => write!(f, "class {value:?} is not a non-negative integer"),
            Self::NotUnit { value } => write!(f, "{value:?} is not a number in 0-1"),
            Self::InvalidBox => f.write_str("invalid box"),
        }
    }
}

impl std::error::Error for YoloLineError {}

fn entry(path: String, reason: &'static str) -> DetectionError {
    DetectionError::Entry { path, reason }
}

/// Parses detections per frame from JSON:
///
/// ```json
/// [{"frame": 0, "boxes": [[x_min, y_min, x_max, y_max], {"box": [x_min, y_min, x_max, y_max], "score": 0.9}]},
///  {"frame": 1, "boxes": []}]
/// ```
///
/// A box is either a plain array of four pixel values or an object with `box` and an optional
/// `score` (0-1, or null). Frames are returned in file order; other keys are ignored.
pub fn parse_detections_json(text: &str) -> Result<Vec<FrameDetections>, DetectionError> {
    let v: Value = serde_json::from_str(text).map_err(|e| DetectionError::Json(e.to_string()))?;
    let frames = v
        .as_array()
        .ok_or_else(|| entry(String::new(), "expected an array of frames"))?;
    frames
        .iter()
        .enumerate()
        .map(|(i, f)| parse_frame(i, f))
        .collect()
}

fn parse_frame(i: usize, v: &Value) -> Result<FrameDetections, DetectionError> {
    let obj = v.as_object().ok_or_else(|| {
        entry(
            format!("[{i}]"),
            "expected an object {\"frame\", \"boxes\"}",
        )
    })?;
    let frame = obj.get("frame").and_then(Value::as_u64).ok_or_else(|| {
        entry(
            format!("[{i}].frame"),
            "missing or not a non-negative integer",
        )
    })?;
    let boxes = obj
        .get("boxes")
        .and_then(Value::as_array)
        .ok_or_else(|| entry(format!("[{i}].boxes"), "missing or not an array"))?;
    let detections = boxes
        .iter()
        .enumerate()
        .map(|(j, b)| parse_detection(&format!("[{i}].boxes[{j}]"), b))
        .collect::<Result<_, _>>()?;
    Ok(FrameDetections { frame, detections })
}

fn parse_detection(path: &str, v: &Value) -> Result<Detection, DetectionError> {
    let Some(obj) = v.as_object() else {
        let bbox = parse_box(path, v)?;
        return Ok(Detection { bbox, score: None });
    };
    let inner = obj.get("box").ok_or_else(|| {
        entry(
            path.to_owned(),
            "expected [x_min, y_min, x_max, y_max] or {\"box\", \"score\"}",
        )
    })?;
    let bbox = parse_box(&format!("{path}.box"), inner)?;
    let score = match obj.get("score") {
        None | Some(Value::Null) => None,
        Some(s) => Some(
            s.as_f64()
                .filter(|s| (0.0..=1.0).contains(s))
                .ok_or_else(|| entry(format!("{path}.score"), "not a number in 0-1"))?,
        ),
    };
    Ok(Detection { bbox, score })
}

fn parse_box(path: &str, v: &Value) -> Result<BoundingBox, DetectionError> {
    let shape = "expected [x_min, y_min, x_max, y_max]";
    let a = v
        .as_array()
        .filter(|a| a.len() == 4)
        .ok_or_else(|| entry(path.to_owned(), shape))?;
    let n = a
        .iter()
        .map(Value::as_f64)
        .collect::<Option<Vec<f64>>>()
        .ok_or_else(|| entry(path.to_owned(), "box values must be numbers"))?;
    BoundingBox::new(n[0], n[1], n[2], n[3])
        .ok_or_else(|| entry(path.to_owned(), "x_min > x_max or y_min > y_max"))
}

/// Parses a YOLO label/prediction file: one box a line, `class cx cy w h [score]`, centre and
/// size normalised 0-1 to the image of `image_size` = `[width, height]` pixels. Keeps the
/// boxes of `class` (usually [`DEFAULT_CONE_CLASS`]); every line is checked. Blank lines
/// and lines starting with `#` are skipped.
pub fn parse_yolo(
    text: &str,
    image_size: [u32; 2],
    class: u32,
) -> Result<Vec<Detection>, DetectionError> {
    if image_size.contains(&0) {
        return Err(DetectionError::ImageSize);
    }
    let mut out = Vec::new();
    for (k, line) in text.lines().enumerate() {
        let line = line.trim();
        if line.is_empty() || line.starts_with('#') {
            continue;
        }
        let (c, det) =
            parse_yolo_line(line, image_size).map_err(|reason| DetectionError::Line {
                line: k + 1,
                reason,
            })?;
        if c == class {
            out.push(det);
        }
    }
    Ok(out)
}

fn parse_yolo_line(line: &str, [w_px, h_px]: [u32; 2]) -> Result<(u32, Detection), YoloLineError> {
    let fields: Vec<&str> = line.split_whitespace().collect();
    if !(5..=6).contains(&fields.len()) {
        return Err(YoloLineError::FieldCount {
            found: fields.len(),
        });
    }
    let class = fields[0].parse::<u32>().map_err(|_| YoloLineError::Class {
        value: fields[0].to_string(),
    })?;
    let mut v = [0.0; 5];
    for (slot, f) in v.iter_mut().zip(&fields[1..]) {
        *slot = f
            .parse::<f64>()
            .ok()
            .filter(|x| (0.0..=1.0).contains(x))
            .ok_or_else(|| YoloLineError::NotUnit {
                value: f.to_string(),
            })?;
    }
    let [cx, cy, w, h, _] = v;
    let (sx, sy) = (f64::from(w_px), f64::from(h_px));
    let bbox = BoundingBox::new(
        (cx - w / 2.0) * sx,
        (cy - h / 2.0) * sy,
        (cx + w / 2.0) * sx,
        (cy + h / 2.0) * sy,
    )
    .ok_or(YoloLineError::InvalidBox)?;
    let score = (fields.len() == 6).then_some(v[4]);
    Ok((class, Detection { bbox, score }))
}

/// Settings of a [`ConeTracker`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TrackerConfig {
    /// Sightings within this distance (metres) of a cone are that cone.
    pub radius_m: f64,
    /// A cone is confirmed when seen in at least `confirm` ...
    pub confirm: u32,
    /// ... of the last `window` frames (1 <= confirm <= window <= 64).
    pub window: u32,
}

impl Default for TrackerConfig {
    /// 1.0 m, 3 of 5 frames.
    fn default() -> Self {
        Self {
            radius_m: 1.0,
            confirm: 3,
            window: 5,
        }
    }
}

#[derive(Debug, Clone)]
struct Track {
    /// (frame, position) of its sightings inside the window, oldest first.
    sightings: Vec<(u64, [f64; 2])>,
}

impl Track {
    fn position(&self) -> [f64; 2] {
        let n = self.sightings.len().max(1) as f64;
        let s = self
            .sightings
            .iter()
            .fold([0.0; 2], |s, (_, p)| [s[0] + p[0], s[1] + p[1]]);
        [s[0] / n, s[1] / n]
    }
}

/// Smooths cone positions over frames: a cone is confirmed while it was seen in at least
/// `confirm` of the last `window` frames (so one missed detection does not drop it) and is
/// forgotten once it was not seen for `window` frames. The default is 3 of 5 frames, 1.0 m.
#[derive(Debug, Clone, Default)]
pub struct ConeTracker {
    config: TrackerConfig,
    frame: u64,
    tracks: Vec<Track>,
}

impl ConeTracker {
    /// A tracker; `None` for an invalid configuration.
    pub fn new(config: TrackerConfig) -> Option<Self> {
        let TrackerConfig {
            radius_m,
            confirm,
            window,
        } = config;
        let ok = radius_m.is_finite()
            && radius_m > 0.0
            && confirm >= 1
            && confirm <= window
            && window <= 64;
        ok.then(|| Self {
            config,
            ..Self::default()
        })
    }

    /// Takes the cones (local metres) seen in the next frame and returns the confirmed cones,
    /// each at the mean of its recent sightings, oldest cone first. Non-finite points are
    /// ignored.
    pub fn push_frame(&mut self, cones_local: &[[f64; 2]]) -> Vec<[f64; 2]> {
        self.frame += 1;
        let seen: Vec<[f64; 2]> = cones_local
            .iter()
            .copied()
            .filter(|p| p[0].is_finite() && p[1].is_finite())
            .collect();
        for (p, track) in seen.iter().zip(self.associate(&seen)) {
            match track {
                Some(t) => self.tracks[t].sightings.push((self.frame, *p)),
                None if self.tracks.len() < MAX_TRACKS => self.tracks.push(Track {
                    sightings: vec![(self.frame, *p)],
                }),
                None => {}
            }
        }
        self.expire();
        self.confirmed()
    }

    /// The confirmed cones now.
    pub fn confirmed(&self) -> Vec<[f64; 2]> {
        self.tracks
            .iter()
            .filter(|t| t.sightings.len() >= self.config.confirm as usize)
            .map(Track::position)
            .collect()
    }

    /// Cones tracked (confirmed or not).
    pub fn tracked(&self) -> usize {
        self.tracks.len()
    }

    /// The track of each point: nearest pairs first, one point per track.
    fn associate(&self, points: &[[f64; 2]]) -> Vec<Option<usize>> {
        let centres: Vec<[f64; 2]> = self.tracks.iter().map(Track::position).collect();
        let mut pairs: Vec<(f64, usize, usize)> = Vec::new();
        for (i, p) in points.iter().enumerate() {
            for (t, c) in centres.iter().enumerate() {
                let d = dist(*p, *c);
                if d <= self.config.radius_m {
                    pairs.push((d, i, t));
                }
            }
        }
        cheapest_first(pairs, points.len(), centres.len())
            .into_iter()
            .map(|m| m.map(|(t, _)| t))
            .collect()
    }

    /// Drops sightings older than the window, then tracks without sightings.
    fn expire(&mut self) {
        let window = u64::from(self.config.window);
        let now = self.frame;
        for t in &mut self.tracks {
            t.sightings.retain(|(f, _)| f + window > now);
        }
        self.tracks.retain(|t| !t.sightings.is_empty());
    }
}

/// The work zone on one lane.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LaneClosure {
    /// Lane id.
    pub lane: u8,
    /// Smallest station of its cones (metres along the lane in its direction of travel).
    pub start_m: f64,
    /// Largest station of its cones.
    pub end_m: f64,
    /// Cones on the lane.
    pub cones: usize,
}

/// Where a cone lies on a lane.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ConeOnLane {
    /// Lane id.
    pub lane: u8,
    /// Metres along the lane's centreline in its direction of travel.
    pub station_m: f64,
    /// Metres left of the centreline (negative: right).
    pub offset_m: f64,
}

/// The lane a cone lies on by the paper's rule (eq. 7-10): for a centreline segment
/// `a -> b`, rotate `a`, `b` and the cone by `-atan2(dy, dx)`; the cone is on it when
/// `a'.x < c'.x < b'.x` and `|c'.y - a'.y| < width / 2`. When several lanes (or segments)
/// match, the nearest centreline wins; `None` when none does.
pub fn locate_cone(road: &Road, cone: [f64; 2]) -> Option<ConeOnLane> {
    road.lanes
        .iter()
        .filter_map(|lane| on_lane(lane, cone))
        .min_by(|a, b| a.offset_m.abs().total_cmp(&b.offset_m.abs()))
}

fn on_lane(lane: &RoadLane, c: [f64; 2]) -> Option<ConeOnLane> {
    let mut best: Option<ConeOnLane> = None;
    let mut start = 0.0;
    for w in lane.centre.windows(2) {
        let (a, b) = (w[0], w[1]);
        let len = dist(a, b);
        if len > 0.0 {
            let (ux, uy) = ((b[0] - a[0]) / len, (b[1] - a[1]) / len);
            let (rx, ry) = (c[0] - a[0], c[1] - a[1]);
            // Rotated by -theta: along = x' - a'.x, offset = y' - a'.y.
            let along = rx * ux + ry * uy;
            let offset = ry * ux - rx * uy;
            let inside = along > 0.0 && along < len && offset.abs() < lane.width_m / 2.0;
            if inside && best.is_none_or(|o| offset.abs() < o.offset_m.abs()) {
                best = Some(ConeOnLane {
                    lane: lane.id,
                    station_m: start + along,
                    offset_m: offset,
                });
            }
        }
        start += len;
    }
    best
}

/// The closed lanes: per lane with at least one cone, the smallest and largest station of its
/// cones, in the road's lane order. Lanes without cones are open; cones on no lane are
/// ignored (see [`off_lane`]).
pub fn closures(road: &Road, cones: &[[f64; 2]]) -> Vec<LaneClosure> {
    let located: Vec<ConeOnLane> = cones.iter().filter_map(|c| locate_cone(road, *c)).collect();
    road.lanes
        .iter()
        .filter_map(|lane| {
            let stations = located
                .iter()
                .filter(|o| o.lane == lane.id)
                .map(|o| o.station_m);
            stations.fold(None, |acc: Option<LaneClosure>, s| {
                Some(match acc {
                    None => LaneClosure {
                        lane: lane.id,
                        start_m: s,
                        end_m: s,
                        cones: 1,
                    },
                    Some(z) => LaneClosure {
                        start_m: z.start_m.min(s),
                        end_m: z.end_m.max(s),
                        cones: z.cones + 1,
                        ..z
                    },
                })
            })
        })
        .collect()
}

/// How many cones lie on no lane.
pub fn off_lane(road: &Road, cones: &[[f64; 2]]) -> usize {
    cones
        .iter()
        .filter(|c| locate_cone(road, **c).is_none())
        .count()
}

#[cfg(test)]
mod tests {
    use super::*;
    use geodesy::LatLon;

    #[test]
    fn bottom_centre_is_the_road_point() {
        let b = BoundingBox::new(100.0, 200.0, 140.0, 260.0).unwrap();
        assert_eq!(b.bottom_centre(), [120.0, 260.0]);
        assert_eq!(BoundingBox::new(10.0, 0.0, 5.0, 1.0), None);
        assert_eq!(BoundingBox::new(0.0, f64::NAN, 5.0, 1.0), None);
    }

    #[test]
    fn json_detections() {
        let json = r#"[{"frame": 0, "boxes": [[1, 2, 3, 4], {"box": [5, 6, 7.5, 8], "score": 0.9}]},
                       {"frame": 7, "boxes": [{"box": [0, 0, 0, 0]}], "camera": 2}]"#;
        let frames = parse_detections_json(json).unwrap();
        assert_eq!(frames.len(), 2);
        assert_eq!(
            frames[0].detections[0].bbox,
            BoundingBox::new(1.0, 2.0, 3.0, 4.0).unwrap()
        );
        assert_eq!(frames[0].detections[1].score, Some(0.9));
        assert_eq!(frames[0].detections[1].bbox.bottom_centre(), [6.25, 8.0]);
        assert_eq!((frames[1].frame, frames[1].detections[0].score), (7, None));
        let cases = [
            (r#"{"frame": 0}"#, ""),
            (r#"[{"boxes": []}]"#, "[0].frame"),
            (r#"[{"frame": -1, "boxes": []}]"#, "[0].frame"),
            (r#"[{"frame": 0}]"#, "[0].boxes"),
            (
                r#"[{"frame": 0, "boxes": []}, {"frame": 1, "boxes": [[1, 2, 3]]}]"#,
                "[1].boxes[0]",
            ),
            (
                r#"[{"frame": 0, "boxes": [[1, 2, "3", 4]]}]"#,
                "[0].boxes[0]",
            ),
            (r#"[{"frame": 0, "boxes": [[3, 2, 1, 4]]}]"#, "[0].boxes[0]"),
            (r#"[{"frame": 0, "boxes": [{"score": 1}]}]"#, "[0].boxes[0]"),
            (
                r#"[{"frame": 0, "boxes": [{"box": [1, 2, 3, 4], "score": 2}]}]"#,
                "[0].boxes[0].score",
            ),
        ];
        for (text, at) in cases {
            match parse_detections_json(text) {
                Err(DetectionError::Entry { path, .. }) => assert_eq!(path, at, "{text}"),
                other => panic!("{text}: {other:?}"),
            }
        }
        assert!(matches!(
            parse_detections_json("[{"),
            Err(DetectionError::Json(_))
        ));
    }

    #[test]
    fn yolo_files() {
        let text = "# cones\n0 0.5 0.5 0.1 0.2\n\n1 0.1 0.1 0.05 0.05\n0 0.25 0.75 0.05 0.1 0.8\n";
        let dets = parse_yolo(text, [1920, 1080], DEFAULT_CONE_CLASS).unwrap();
        assert_eq!(dets.len(), 2);
        let b = dets[0].bbox;
        assert!((b.x_min - 864.0).abs() < 1e-9 && (b.x_max - 1056.0).abs() < 1e-9);
        assert!((b.y_min - 432.0).abs() < 1e-9 && (b.y_max - 648.0).abs() < 1e-9);
        assert_eq!((dets[0].score, dets[1].score), (None, Some(0.8)));
        assert_eq!(parse_yolo(text, [1920, 1080], 1).unwrap().len(), 1);
        for (bad, line) in [
            ("0 0.5 0.5 0.1\n", 1),
            ("0 0.5 0.5 0.1 0.2\n0 0.5 0.5 0.1 0.2 0.3 0.4\n", 2),
            ("\n\nx 0.5 0.5 0.1 0.2\n", 3),
            ("-1 0.5 0.5 0.1 0.2\n", 1),
            ("0 0.5 1.5 0.1 0.2\n", 1),
            ("0 0.5 0.5 nan 0.2\n", 1),
            ("0 0.5 0.5 0.1 abc\n", 1),
        ] {
            match parse_yolo(bad, [640, 480], 0) {
                Err(DetectionError::Line { line: l, reason }) => {
                    assert_eq!(l, line, "{bad:?}: {reason}")
                }
                other => panic!("{bad:?}: {other:?}"),
            }
        }
        assert_eq!(
            parse_yolo("0 0.5 1.5 0.1 0.2\n", [640, 480], 0),
            Err(DetectionError::Line {
                line: 1,
                reason: YoloLineError::NotUnit {
                    value: "1.5".into()
                }
            })
        );
        assert_eq!(
            parse_yolo(text, [0, 480], 0),
            Err(DetectionError::ImageSize)
        );
    }

    #[test]
    fn tracker_confirms_keeps_and_drops() {
        let mut t = ConeTracker::default();
        let a = [10.0, 5.0];
        let b = [30.0, 5.0];
        // Confirmed only at the third sighting.
        assert!(t.push_frame(&[a]).is_empty());
        assert!(t.push_frame(&[[10.2, 5.1], b]).is_empty());
        let c = t.push_frame(&[[9.8, 4.9], [30.1, 5.0]]);
        assert_eq!(c.len(), 1);
        assert!(dist(c[0], a) < 1e-9, "mean of sightings: {c:?}");
        // b reaches three sightings; one missed frame keeps both.
        assert_eq!(t.push_frame(&[a, b]).len(), 2);
        assert_eq!(t.push_frame(&[b]).len(), 2);
        assert_eq!(t.push_frame(&[a, b, [f64::NAN, 0.0]]).len(), 2);
        // a removed (it also missed frame 5): kept one frame more, then no longer 3 of 5.
        assert_eq!(t.push_frame(&[b]).len(), 2);
        let c = t.push_frame(&[b]);
        assert_eq!(c.len(), 1);
        assert!(dist(c[0], b) < 0.1);
        for _ in 0..3 {
            t.push_frame(&[b]);
        }
        assert_eq!(t.tracked(), 1, "a forgotten after 5 frames unseen");
        // b, seen in every frame, survives two misses and goes at the third.
        assert_eq!(t.push_frame(&[]).len(), 1);
        assert_eq!(t.push_frame(&[]).len(), 1);
        assert!(t.push_frame(&[]).is_empty());
        // Two cones in one frame never merge into one track.
        let mut t = ConeTracker::new(TrackerConfig {
            confirm: 1,
            window: 1,
            radius_m: 1.0,
        })
        .unwrap();
        assert_eq!(t.push_frame(&[[0.0, 0.0], [0.5, 0.0]]).len(), 2);
        assert!(ConeTracker::new(TrackerConfig {
            confirm: 6,
            window: 5,
            radius_m: 1.0
        })
        .is_none());
        assert!(ConeTracker::new(TrackerConfig {
            radius_m: f64::NAN,
            ..TrackerConfig::default()
        })
        .is_none());
    }

    fn road() -> Road {
        Road::straight(
            LatLon::from_degrees(39.7392, -104.9903).unwrap(),
            90.0,
            1000.0,
            (3, 2),
            3.6,
            80.0,
        )
    }

    #[test]
    fn cones_close_lane_three() {
        let road = road();
        let lane = road.lane(3).unwrap();
        let mut cones: Vec<[f64; 2]> = (0..=10)
            .map(|k| {
                lane.beside(400.0 + 10.0 * k as f64, if k % 2 == 0 { 0.8 } else { -0.8 })
                    .unwrap()
                    .point
            })
            .collect();
        cones.push([450.0, -30.0]); // far off the road
        cones.push([-5.0, -7.2]); // before the lane starts
        let zones = closures(&road, &cones);
        assert_eq!(zones.len(), 1, "{zones:?}");
        let z = zones[0];
        assert_eq!((z.lane, z.cones), (3, 11));
        assert!(
            (z.start_m - 400.0).abs() < 1e-9 && (z.end_m - 500.0).abs() < 1e-9,
            "{z:?}"
        );
        assert_eq!(off_lane(&road, &cones), 2);
        // A westbound lane counts stations from its own start (east end).
        let west = road.lane(4).unwrap().at(0.0).unwrap().point;
        let on = locate_cone(&road, [west[0] - 120.0, west[1] + 1.0]).unwrap();
        assert_eq!(on.lane, 4);
        assert!(
            (on.station_m - 120.0).abs() < 1e-9 && (on.offset_m + 1.0).abs() < 1e-9,
            "{on:?}"
        );
        // On the median: on no lane.
        assert_eq!(locate_cone(&road, [450.0, 3.6]), None);
        assert!(closures(&road, &[]).is_empty());
    }
}
