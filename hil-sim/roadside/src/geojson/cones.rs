//! The cone list reader: JSON or CSV positions to local points of the road.

use super::error::{InputError, Problem};
use super::geometry::project;
use super::json::{invalid, latlon, member, number, object, parse_json, wrong_type};
use super::MAX_CONE_DISTANCE_M;
use crate::road::Road;
use serde_json::Value;

/// Reads a cone list (JSON or CSV, see the [module docs](super)) into local points of
/// `road` (east/north metres around its reference). An empty list is valid (no cones).
///
/// The format is JSON when the first character that is not white space is `[` or `{`,
/// else CSV.
///
/// # Errors
///
/// [`InputError::Json`] / [`InputError::Document`] for JSON that is not an array;
/// [`InputError::Item`] for an item without numeric `lat` and `lon`; [`InputError::Line`]
/// for a CSV line that is not two numbers (or a header naming `lat` and `lon`); either for
/// a position out of range or farther than [`MAX_CONE_DISTANCE_M`] from every lane.
pub fn load_cones(road: &Road, text: &str) -> Result<Vec<[f64; 2]>, InputError> {
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let json = text.trim_start().starts_with(['[', '{']);
    if json {
        json_cones(road, text)
    } else {
        csv_cones(road, text)
    }
}

/// `[{"lat": .., "lon": ..}, ...]`.
fn json_cones(road: &Road, text: &str) -> Result<Vec<[f64; 2]>, InputError> {
    let doc = parse_json(text)?;
    let items = doc.as_array().ok_or_else(|| {
        InputError::Document(wrong_type(
            "(top level)",
            "an array of {\"lat\": .., \"lon\": ..} objects",
            &doc,
        ))
    })?;
    let mut cones = Vec::with_capacity(items.len());
    for (index, item) in items.iter().enumerate() {
        let cone = json_cone(road, item).map_err(|problem| InputError::Item { index, problem })?;
        cones.push(cone);
    }
    Ok(cones)
}

/// One JSON cone.
fn json_cone(road: &Road, item: &Value) -> Result<[f64; 2], Problem> {
    let obj = object(item, "cone")?;
    let lat = number(member(obj, "lat", "lat")?, "lat")?;
    let lon = number(member(obj, "lon", "lon")?, "lon")?;
    cone_point(road, lat, lon)
}

/// Column order of a CSV cone list.
#[derive(Clone, Copy)]
enum Columns {
    LatLon,
    LonLat,
}

/// `lat,lon` lines, optional header, `#` comments.
fn csv_cones(road: &Road, text: &str) -> Result<Vec<[f64; 2]>, InputError> {
    let mut columns = None;
    let mut cones = Vec::new();
    for (k, raw) in text.lines().enumerate() {
        let line = k + 1;
        let content = raw.split_once('#').map_or(raw, |(c, _)| c).trim();
        if content.is_empty() {
            continue;
        }
        let at_line = |problem| InputError::Line { line, problem };
        let fields: Vec<&str> = content.split(',').map(str::trim).collect();
        let &[a, b] = fields.as_slice() else {
            return Err(at_line(invalid(
                "line",
                format!("{content:?}"),
                "two comma-separated fields `lat,lon`",
            )));
        };
        let numbers = a.parse::<f64>().ok().zip(b.parse::<f64>().ok());
        match (numbers, columns) {
            (Some((x, y)), order) => {
                let (lat, lon) = match order.unwrap_or(Columns::LatLon) {
                    Columns::LatLon => (x, y),
                    Columns::LonLat => (y, x),
                };
                cones.push(cone_point(road, lat, lon).map_err(at_line)?);
                columns = Some(order.unwrap_or(Columns::LatLon));
            }
            (None, None) => columns = Some(csv_header(a, b).map_err(at_line)?),
            (None, Some(_)) => {
                return Err(at_line(invalid(
                    "line",
                    format!("{content:?}"),
                    "two numbers `lat,lon` in decimal degrees",
                )))
            }
        }
    }
    Ok(cones)
}

/// The column order a header line names.
fn csv_header(a: &str, b: &str) -> Result<Columns, Problem> {
    let is_lat = |s: &str| ["lat", "latitude"].contains(&s.to_ascii_lowercase().as_str());
    let is_lon =
        |s: &str| ["lon", "lng", "long", "longitude"].contains(&s.to_ascii_lowercase().as_str());
    if is_lat(a) && is_lon(b) {
        Ok(Columns::LatLon)
    } else if is_lon(a) && is_lat(b) {
        Ok(Columns::LonLat)
    } else {
        Err(invalid(
            "line",
            format!("\"{a},{b}\""),
            "two numbers `lat,lon` in decimal degrees, or a first line naming the columns (`lat,lon`)",
        ))
    }
}

/// A cone position in local metres, checked to lie near a lane.
fn cone_point(road: &Road, lat: f64, lon: f64) -> Result<[f64; 2], Problem> {
    let p = road.to_local(latlon(lon, lat, "cone")?);
    let nearest = road
        .lanes
        .iter()
        .filter_map(|lane| project(lane, p))
        .map(|(_, d)| d)
        .min_by(f64::total_cmp);
    match nearest {
        Some(d) if d.is_nan() || d > MAX_CONE_DISTANCE_M => Err(Problem::TooFar {
            what: "cone".into(),
            from: "the nearest lane",
            distance_m: d,
            limit_m: MAX_CONE_DISTANCE_M,
        }),
        _ => Ok(p),
    }
}
