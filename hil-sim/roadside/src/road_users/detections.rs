//! Parsers of instance-segmentation detector output (Mask R-CNN / YOLO-seg).
//!
//! Per detected object only the class, the score and the convex hull of the
//! mask's outline ([`MaskOutline`]) are kept, in image pixels: x to the right, y down,
//! continuous coordinates (pixel column `c`, row `r` covers `[c, c+1) x [r, r+1)`).
//! RLE masks are read run by run; polygons are filled back into the pixels they cover.

use super::class::RoadUserClass;
use super::outline::MaskOutline;
pub use super::polygon::convex_hull;
use super::rasterise::{fill, MAX_CROSSINGS};
use serde_json::{Map, Value};
use std::collections::HashMap;
use std::fmt;

/// Largest accepted input text, in bytes.
pub const MAX_TEXT_BYTES: usize = 256 << 20;
/// Largest number of images (frames) in one file.
pub const MAX_IMAGES: usize = 10_000;
/// Largest number of annotations (objects) in one file.
pub const MAX_ANNOTATIONS: usize = 100_000;
/// Largest number of polygon points in one annotation.
pub const MAX_POLYGON_POINTS: usize = 100_000;
/// Largest image width or height, in pixels.
pub const MAX_IMAGE_SIDE: u32 = 16_384;
/// Largest number of counts in one RLE mask.
pub const MAX_RLE_COUNTS: usize = 1_000_000;
/// Tolerance on normalised YOLO coordinates outside `[0, 1]`.
const SLACK: f64 = 1e-6;

/// One detected road user: its class, score and the convex hull of its mask.
#[derive(Debug, Clone, PartialEq)]
pub struct Silhouette {
    /// The road-user class.
    pub class: RoadUserClass,
    /// Detector confidence in `0..=1`, when given.
    pub score: Option<f64>,
    /// Convex hull of the mask, at least 3 points, no repeated first point, no
    /// collinear points. Vertices start at the smallest (x, then y) and have a
    /// positive signed shoelace area in (x right, y down) coordinates, i.e. they
    /// run clockwise as seen on screen (counter-clockwise in a y-up plot).
    pub hull: Vec<[f64; 2]>,
    /// Mask area in pixels (for polygons, the pixels whose centres they cover).
    pub area_px: f64,
    /// Number of separate polygons (COCO polygon lists), 1 for RLE and YOLO; >1 hints at occlusion.
    pub parts: usize,
    /// Whether the mask reaches within 1 px of the image border (truncated by
    /// the frame); always `false` when the image size is unknown.
    pub touches_border: bool,
}

/// The detections of one frame.
#[derive(Debug, Clone, PartialEq)]
pub struct FrameMasks {
    /// Frame number (the COCO image id).
    pub frame: u64,
    /// Image file name, when given.
    pub file_name: Option<String>,
    /// Image size as `[width, height]` in pixels, when known.
    pub image_size: Option<[u32; 2]>,
    /// The road users kept.
    pub silhouettes: Vec<Silhouette>,
    /// The detections dropped, counted by reason.
    pub skipped: Skipped,
}

impl FrameMasks {
    fn empty(frame: u64, file_name: Option<String>, image_size: Option<[u32; 2]>) -> Self {
        let (silhouettes, skipped) = (Vec::new(), Skipped::default());
        Self {
            frame,
            file_name,
            image_size,
            silhouettes,
            skipped,
        }
    }
}

/// Detections dropped with a reason, counted (closed set of reasons).
#[derive(Default, Debug, Clone, Copy, PartialEq, Eq)]
pub struct Skipped {
    /// Class name that is not a road-user class.
    pub unknown_class: u32,
    /// Hull of fewer than 3 points or zero mask area.
    pub degenerate: u32,
}

/// Why a file cannot be read: a closed set, each with the JSON path or line number and a short reason.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum MaskError {
    /// The text is not JSON (serde_json's message).
    Json(String),
    /// A JSON entry is missing or invalid; `path` is like `annotations[3].segmentation`.
    Entry {
        /// Where in the JSON document.
        path: String,
        /// What is wrong.
        reason: &'static str,
    },
    /// A line of a text format is invalid (1-based line number).
    Line {
        /// 1-based line number.
        line: usize,
        /// What is wrong.
        reason: &'static str,
    },
    /// A bound was exceeded.
    TooLarge {
        /// What was counted.
        what: &'static str,
        /// The largest accepted value.
        limit: usize,
    },
}

impl fmt::Display for MaskError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Json(msg) => write!(f, "invalid JSON: {msg}"),
            Self::Entry { path, reason } => write!(f, "{path}: {reason}"),
            Self::Line { line, reason } => write!(f, "line {line}: {reason}"),
            Self::TooLarge { what, limit } => write!(f, "too large: more than {limit} {what}"),
        }
    }
}

impl std::error::Error for MaskError {}

fn entry(path: impl Into<String>, reason: &'static str) -> MaskError {
    MaskError::Entry {
        path: path.into(),
        reason,
    }
}

/// An `Entry` error at `path` followed by `sub`.
fn at(path: &str, sub: &str, reason: &'static str) -> MaskError {
    entry(format!("{path}{sub}"), reason)
}

fn too_large(what: &'static str, limit: usize) -> MaskError {
    MaskError::TooLarge { what, limit }
}

/// COCO compressed RLE counts string -> counts (as pycocotools `rleFrString`:
/// from the 4th count on, i.e. index >= 3, the stored value is a delta to the
/// count two places before). Errors carry the path `counts`.
pub fn rle_from_string(s: &str) -> Result<Vec<u32>, MaskError> {
    decode_rle_string(s, "counts")
}

fn decode_rle_string(s: &str, path: &str) -> Result<Vec<u32>, MaskError> {
    let mut counts: Vec<u32> = Vec::new();
    let (mut x, mut k) = (0i64, 0u32);
    for byte in s.bytes() {
        if !(48..48 + 64).contains(&byte) {
            return Err(entry(path, "invalid character in RLE string"));
        }
        if k >= 12 {
            return Err(entry(path, "RLE count has too many digits"));
        }
        let c = i64::from(byte - 48);
        x |= (c & 0x1f) << (5 * k);
        k += 1;
        if c & 0x20 == 0 {
            if c & 0x10 != 0 {
                x |= -1i64 << (5 * k);
            }
            if counts.len() > 2 {
                x += counts.get(counts.len() - 2).map_or(0, |&v| i64::from(v));
            }
            let v = u32::try_from(x).map_err(|_| {
                entry(
                    path,
                    if x < 0 {
                        "negative RLE count"
                    } else {
                        "RLE count overflows"
                    },
                )
            })?;
            if counts.len() >= MAX_RLE_COUNTS {
                return Err(too_large("RLE counts", MAX_RLE_COUNTS));
            }
            counts.push(v);
            (x, k) = (0, 0);
        }
    }
    if k != 0 {
        return Err(entry(path, "truncated RLE string"));
    }
    Ok(counts)
}

/// Hull, area and border contact of one mask.
struct Shape {
    hull: Vec<[f64; 2]>,
    area: f64,
    touches: bool,
    parts: usize,
}

/// Shape of a column-major RLE mask of `h` rows and `w` columns.
fn rle_shape(counts: &[u32], h: u32, w: u32, path: &str) -> Result<Shape, MaskError> {
    let pixels = u64::from(h) * u64::from(w);
    if counts.len() as u64 > pixels + 1 {
        return Err(too_large("RLE counts", (pixels + 1) as usize));
    }
    if counts.iter().map(|&c| u64::from(c)).sum::<u64>() != pixels {
        return Err(entry(path, "RLE counts do not sum to height*width"));
    }
    let h64 = u64::from(h);
    let mut outline = MaskOutline::new(w, h);
    let mut pos = 0u64;
    for (i, &n) in counts.iter().enumerate() {
        let n = u64::from(n);
        if i % 2 == 1 && n > 0 {
            // A run may cross columns: split it per column.
            let (mut at, end) = (pos, pos + n);
            while at < end {
                let (c, r) = (at / h64, at % h64);
                let stop = end.min((c + 1) * h64);
                outline.add_column_run(c as u32, r as u32, (r + stop - at) as u32);
                at = stop;
            }
        }
        pos += n;
    }
    Ok(Shape {
        hull: outline.hull(),
        area: outline.area() as f64,
        touches: outline.touches_border(),
        parts: 1,
    })
}

/// Whether a point is within 1 px of the border of an image of `[width, height]`.
fn near_border(p: [f64; 2], size: Option<[u32; 2]>) -> bool {
    size.is_some_and(|[w, h]| {
        p[0] <= 1.0 || p[1] <= 1.0 || p[0] >= f64::from(w) - 1.0 || p[1] >= f64::from(h) - 1.0
    })
}

/// Shape of polygons given as point lists (each already at least 3 points): the outline of
/// the pixels they cover ([`rasterise`](super::rasterise)), so that a traced polygon's hull
/// has no more bias than its mask's.
fn polygon_shape(parts: &[Vec<[f64; 2]>], size: Option<[u32; 2]>) -> Result<Shape, MaskError> {
    let outline =
        fill(parts, size).map_err(|_| too_large("polygon row crossings", MAX_CROSSINGS))?;
    let touches = parts.iter().flatten().any(|&p| near_border(p, size));
    Ok(Shape {
        hull: outline.hull(),
        area: outline.area() as f64,
        touches,
        parts: parts.len(),
    })
}

/// Classifies and stores one detection, or counts it as skipped.
fn push_detection(frame: &mut FrameMasks, name: &str, score: Option<f64>, shape: Shape) {
    let Some(class) = RoadUserClass::from_name(name) else {
        frame.skipped.unknown_class = frame.skipped.unknown_class.saturating_add(1);
        return;
    };
    if shape.hull.len() < 3 || shape.area <= 0.0 || !shape.area.is_finite() {
        frame.skipped.degenerate = frame.skipped.degenerate.saturating_add(1);
        return;
    }
    frame.silhouettes.push(Silhouette {
        class,
        score,
        hull: shape.hull,
        area_px: shape.area,
        parts: shape.parts,
        touches_border: shape.touches,
    });
}

fn check_text(text: &str) -> Result<(), MaskError> {
    if text.len() > MAX_TEXT_BYTES {
        return Err(too_large("bytes of input text", MAX_TEXT_BYTES));
    }
    Ok(())
}

/// An image side in `1..=MAX_IMAGE_SIDE`.
fn side(v: Option<&Value>, path: impl Fn() -> String) -> Result<u32, MaskError> {
    match v.and_then(Value::as_u64) {
        Some(0) | None => Err(entry(path(), "image side must be an integer >= 1")),
        Some(n) if n > u64::from(MAX_IMAGE_SIDE) => {
            Err(too_large("pixels per image side", MAX_IMAGE_SIDE as usize))
        }
        Some(n) => Ok(n as u32),
    }
}

/// The `[width, height]` of an RLE `size: [h, w]`, if well-formed (no error).
fn rle_size(seg: &Value) -> Option<[u32; 2]> {
    let size = seg.get("size")?.as_array()?;
    let (h, w) = (
        side(size.first(), String::new).ok()?,
        side(size.get(1), String::new).ok()?,
    );
    (size.len() == 2).then_some([w, h])
}

/// Parses one annotation into `frame`; `path` names the annotation.
fn parse_annotation(
    ann: &Map<String, Value>,
    name: &str,
    path: &str,
    frame: &mut FrameMasks,
) -> Result<(), MaskError> {
    let score = match ann.get("score") {
        None | Some(Value::Null) => None,
        Some(v) => match v.as_f64() {
            Some(s) if (0.0..=1.0).contains(&s) => Some(s),
            _ => return Err(at(path, ".score", "score not in 0..=1")),
        },
    };
    let shape = match ann.get("segmentation") {
        Some(Value::Array(polys)) => {
            if polys.is_empty() {
                return Err(at(path, ".segmentation", "empty polygon list"));
            }
            let total: usize = polys
                .iter()
                .map(|p| p.as_array().map_or(0, Vec::len) / 2)
                .sum();
            if total > MAX_POLYGON_POINTS {
                return Err(too_large("polygon points", MAX_POLYGON_POINTS));
            }
            let mut parts = Vec::with_capacity(polys.len());
            for (i, poly) in polys.iter().enumerate() {
                let bad = |reason| entry(format!("{path}.segmentation[{i}]"), reason);
                let coords = poly
                    .as_array()
                    .ok_or_else(|| bad("polygon is not an array"))?;
                if coords.len() % 2 != 0 {
                    return Err(bad("odd number of polygon coordinates"));
                }
                if coords.len() < 6 {
                    return Err(bad("polygon has fewer than 3 points"));
                }
                let mut part = Vec::with_capacity(coords.len() / 2);
                for pair in coords.chunks_exact(2) {
                    let num = |v: &Value| v.as_f64().filter(|f| f.is_finite());
                    match pair {
                        [x, y] => match (num(x), num(y)) {
                            (Some(x), Some(y)) => part.push([x, y]),
                            _ => return Err(bad("polygon coordinate is not a finite number")),
                        },
                        _ => return Err(bad("odd number of polygon coordinates")),
                    }
                }
                parts.push(part);
            }
            polygon_shape(&parts, frame.image_size)?
        }
        Some(seg @ Value::Object(_)) => {
            let bad_size = |reason| at(path, ".segmentation.size", reason);
            let [w, h] =
                rle_size(seg).ok_or_else(|| bad_size("size must be [h, w] in 1..=16384"))?;
            match frame.image_size {
                Some(s) if s != [w, h] => {
                    return Err(bad_size("RLE size differs from the image size"));
                }
                Some(_) => {}
                None => frame.image_size = Some([w, h]),
            }
            let counts_path = format!("{path}.segmentation.counts");
            let limit = (u64::from(w) * u64::from(h) + 1).min(MAX_RLE_COUNTS as u64) as usize;
            let counts = match seg.get("counts") {
                Some(Value::String(s)) => decode_rle_string(s, &counts_path)?,
                Some(Value::Array(list)) if list.len() > limit => {
                    return Err(too_large("RLE counts", limit));
                }
                Some(Value::Array(list)) => list
                    .iter()
                    .map(|v| v.as_u64().and_then(|n| u32::try_from(n).ok()))
                    .collect::<Option<Vec<u32>>>()
                    .ok_or_else(|| entry(counts_path.as_str(), "RLE count is not a u32"))?,
                _ => return Err(entry(counts_path, "counts must be a string or a list")),
            };
            rle_shape(&counts, h, w, &counts_path)?
        }
        _ => {
            return Err(at(
                path,
                ".segmentation",
                "not a polygon list nor an RLE object",
            ));
        }
    };
    push_detection(frame, name, score, shape);
    Ok(())
}

/// Appends an empty frame and indexes it by id; returns its position.
fn add_frame(
    frames: &mut Vec<FrameMasks>,
    index: &mut HashMap<u64, usize>,
    id: u64,
    file_name: Option<String>,
    image_size: Option<[u32; 2]>,
) -> Result<usize, MaskError> {
    if frames.len() >= MAX_IMAGES {
        return Err(too_large("images", MAX_IMAGES));
    }
    index.insert(id, frames.len());
    frames.push(FrameMasks::empty(id, file_name, image_size));
    Ok(frames.len() - 1)
}

/// Parses a COCO dataset JSON (object with `images`, `annotations`,
/// `categories`; one [`FrameMasks`] per image in the order of `images`,
/// `frame` = image id) or a COCO *results* JSON (array of annotations with
/// `category_name`; frames grouped by `image_id` in first-appearance order).
/// When an image has no size, the first RLE size of its annotations is used.
pub fn parse_coco(text: &str) -> Result<Vec<FrameMasks>, MaskError> {
    check_text(text)?;
    let doc: Value = serde_json::from_str(text).map_err(|e| MaskError::Json(e.to_string()))?;
    let empty = Vec::new();
    let (anns, prefix, categories) = match &doc {
        Value::Object(obj) => {
            let anns = match obj.get("annotations") {
                None | Some(Value::Null) => &empty,
                Some(Value::Array(a)) => a,
                Some(_) => return Err(entry("annotations", "must be an array")),
            };
            let mut cats = HashMap::new();
            for (i, cat) in obj
                .get("categories")
                .and_then(Value::as_array)
                .unwrap_or(&empty)
                .iter()
                .enumerate()
            {
                match (
                    cat.get("id").and_then(Value::as_u64),
                    cat.get("name").and_then(Value::as_str),
                ) {
                    (Some(id), Some(name)) => cats.insert(id, name),
                    _ => {
                        return Err(at(
                            "categories",
                            &format!("[{i}]"),
                            "needs an id and a name",
                        ));
                    }
                };
            }
            (anns, "annotations", Some(cats))
        }
        Value::Array(a) => (a, "", None),
        _ => return Err(entry("$", "not a COCO dataset object nor a results array")),
    };
    if anns.len() > MAX_ANNOTATIONS {
        return Err(too_large("annotations", MAX_ANNOTATIONS));
    }
    let mut frames: Vec<FrameMasks> = Vec::new();
    let mut index: HashMap<u64, usize> = HashMap::new();
    if let Value::Object(obj) = &doc {
        let images = obj.get("images").and_then(Value::as_array);
        for (i, img) in images
            .ok_or_else(|| entry("images", "missing or not an array"))?
            .iter()
            .enumerate()
        {
            let path = || format!("images[{i}]");
            let id = img
                .get("id")
                .and_then(Value::as_u64)
                .ok_or_else(|| entry(path(), "image id must be an integer"))?;
            let size = match (img.get("width"), img.get("height")) {
                (None, None) => None,
                (w, h) => Some([
                    side(w, || format!("{}.width", path()))?,
                    side(h, || format!("{}.height", path()))?,
                ]),
            };
            let name = img
                .get("file_name")
                .and_then(Value::as_str)
                .map(str::to_owned);
            if index.contains_key(&id) {
                return Err(entry(path(), "duplicate image id"));
            }
            add_frame(&mut frames, &mut index, id, name, size)?;
        }
    }
    let mut parsed = Vec::with_capacity(anns.len());
    for (i, ann) in anns.iter().enumerate() {
        let path = format!("{prefix}[{i}]");
        let obj = ann
            .as_object()
            .ok_or_else(|| entry(path.as_str(), "annotation is not an object"))?;
        let image_id = obj.get("image_id").and_then(Value::as_u64);
        let image_id = image_id
            .ok_or_else(|| entry(format!("{path}.image_id"), "image_id must be an integer"))?;
        let name = match &categories {
            Some(cats) => {
                let id = obj.get("category_id").and_then(Value::as_u64);
                let name = id.and_then(|id| cats.get(&id).copied());
                name.ok_or_else(|| at(&path, ".category_id", "category_id not in categories"))?
            }
            None => {
                let name = obj.get("category_name").and_then(Value::as_str);
                name.ok_or_else(|| at(&path, ".category_name", "results need a category_name"))?
            }
        };
        let slot = match index.get(&image_id) {
            Some(&slot) => slot,
            None if categories.is_none() => {
                add_frame(&mut frames, &mut index, image_id, None, None)?
            }
            None => return Err(entry(format!("{path}.image_id"), "image_id not in images")),
        };
        parsed.push((obj, name, path, slot));
    }
    // Sizes first, so polygons parsed before an RLE of the same frame know the border.
    for (obj, _, _, slot) in &parsed {
        if let Some(frame) = frames.get_mut(*slot).filter(|f| f.image_size.is_none()) {
            frame.image_size = obj.get("segmentation").and_then(rle_size);
        }
    }
    for (obj, name, path, slot) in parsed {
        if let Some(frame) = frames.get_mut(slot) {
            parse_annotation(obj, name, &path, frame)?;
        }
    }
    Ok(frames)
}

/// Parses one frame of Ultralytics YOLO-seg text: per line
/// `class_index x1 y1 x2 y2 ... [score]` with coordinates normalised to `0..=1`
/// (x by width, y by height); an odd number of values after the class means
/// the last one is the score. Blank lines and `#` comments are skipped.
/// `image_size` is `[width, height]`; `class_names` maps class indices to names.
pub fn parse_yolo_seg(
    text: &str,
    frame: u64,
    image_size: [u32; 2],
    class_names: &[&str],
) -> Result<FrameMasks, MaskError> {
    check_text(text)?;
    let [w, h] = image_size;
    for (n, v) in [("image_size[0]", w), ("image_size[1]", h)] {
        side(Some(&Value::from(v)), || n.to_owned())?;
    }
    let mut out = FrameMasks::empty(frame, None, Some(image_size));
    let mut objects = 0usize;
    for (i, raw) in text.lines().enumerate() {
        let bad = |reason| MaskError::Line {
            line: i + 1,
            reason,
        };
        let line = raw.trim();
        if line.is_empty() || line.starts_with('#') {
            continue;
        }
        objects += 1;
        if objects > MAX_ANNOTATIONS {
            return Err(too_large("objects per frame", MAX_ANNOTATIONS));
        }
        let mut tokens = line.split_whitespace();
        let index: usize = tokens
            .next()
            .and_then(|t| t.parse().ok())
            .ok_or_else(|| bad("class index is not a non-negative integer"))?;
        let name = class_names
            .get(index)
            .ok_or_else(|| bad("class index out of range"))?;
        let mut values = Vec::new();
        for token in tokens {
            if values.len() > 2 * MAX_POLYGON_POINTS {
                return Err(too_large("polygon points", MAX_POLYGON_POINTS));
            }
            let v: f64 = token.parse().map_err(|_| bad("value is not a number"))?;
            if !v.is_finite() {
                return Err(bad("non-finite value"));
            }
            values.push(v);
        }
        let odd = values.len() % 2 == 1;
        let score = odd.then(|| values.pop()).flatten();
        if score.is_some_and(|s| !(0.0..=1.0).contains(&s)) {
            return Err(bad("score outside 0..=1"));
        }
        if values.len() < 6 {
            return Err(bad("polygon has fewer than 3 points"));
        }
        let mut points = Vec::with_capacity(values.len() / 2);
        for pair in values.chunks_exact(2) {
            if let &[x, y] = pair {
                if !(-SLACK..=1.0 + SLACK).contains(&x) || !(-SLACK..=1.0 + SLACK).contains(&y) {
                    return Err(bad("coordinate outside 0..=1"));
                }
                points.push([
                    x.clamp(0.0, 1.0) * f64::from(w),
                    y.clamp(0.0, 1.0) * f64::from(h),
                ]);
            }
        }
        let shape = polygon_shape(&[points], out.image_size)?;
        push_detection(&mut out, name, score, shape);
    }
    Ok(out)
}

#[cfg(test)]
mod tests;
