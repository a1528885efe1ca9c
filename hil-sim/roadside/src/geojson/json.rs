//! JSON and GeoJSON helpers shared by the readers: members, types, positions.

use super::error::{InputError, Problem};
use geodesy::LatLon;
use serde_json::{Map, Value};
use std::fmt;

/// Parses JSON, with the parser's line and column on error.
pub(super) fn parse_json(text: &str) -> Result<Value, InputError> {
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    serde_json::from_str(text).map_err(|e| InputError::Json {
        line: e.line(),
        column: e.column(),
        message: e.to_string(),
    })
}

/// The `features` of a `FeatureCollection`; none is an error unless `allow_empty` (a lane
/// map needs features; a WZDx feed without an event is a road without a work zone).
pub(super) fn feature_collection(doc: &Value, allow_empty: bool) -> Result<&[Value], InputError> {
    let doc_error = InputError::Document;
    let obj = object(doc, "(top level)").map_err(doc_error)?;
    let kind =
        string(member(obj, "type", "type").map_err(doc_error)?, "type").map_err(doc_error)?;
    if kind != "FeatureCollection" {
        return Err(doc_error(invalid(
            "type",
            format!("{kind:?}"),
            "\"FeatureCollection\"",
        )));
    }
    let features = member(obj, "features", "features").map_err(doc_error)?;
    let features = features
        .as_array()
        .ok_or_else(|| doc_error(wrong_type("features", "an array of features", features)))?;
    if features.is_empty() && !allow_empty {
        return Err(doc_error(Problem::Empty { what: "features" }));
    }
    Ok(features)
}

/// A GeoJSON `Feature` object.
pub(super) fn feature_object(v: &Value) -> Result<&Map<String, Value>, Problem> {
    let feature = object(v, "(feature)")?;
    let kind = string(member(feature, "type", "type")?, "type")?;
    if kind != "Feature" {
        return Err(invalid("type", format!("{kind:?}"), "\"Feature\""));
    }
    Ok(feature)
}

/// The `[lon, lat]` positions of the feature's geometry, whose type must be in `allowed`.
pub(super) fn geometry_positions(
    feature: &Map<String, Value>,
    allowed: &[&str],
) -> Result<Vec<[f64; 2]>, Problem> {
    let geometry = object(member(feature, "geometry", "geometry")?, "geometry")?;
    let kind = string(member(geometry, "type", "geometry.type")?, "geometry.type")?;
    if !allowed.contains(&kind) {
        return Err(invalid(
            "geometry.type",
            format!("{kind:?}"),
            allowed
                .iter()
                .map(|a| format!("\"{a}\""))
                .collect::<Vec<_>>()
                .join(" or "),
        ));
    }
    const WHAT: &str = "geometry.coordinates";
    let coords = member(geometry, "coordinates", WHAT)?;
    let coords = coords
        .as_array()
        .ok_or_else(|| wrong_type(WHAT, "an array of [lon, lat] positions", coords))?;
    let positions = coords
        .iter()
        .enumerate()
        .map(|(k, c)| position(c, &format!("{WHAT}[{k}]")))
        .collect::<Result<Vec<_>, _>>()?;
    if positions.len() < 2 {
        return Err(Problem::TooFewPoints {
            given: positions.len(),
            distinct: positions.len(),
        });
    }
    Ok(positions)
}

/// A GeoJSON position `[lon, lat]` (or `[lon, lat, alt]`), range-checked.
pub(super) fn position(v: &Value, what: &str) -> Result<[f64; 2], Problem> {
    const EXPECTED: &str = "a position [lon, lat] in degrees";
    let items = v.as_array().ok_or_else(|| wrong_type(what, EXPECTED, v))?;
    let (Some(lon), Some(lat), 2..=3) = (items.first(), items.get(1), items.len()) else {
        return Err(invalid(what, v, EXPECTED));
    };
    let lon = number(lon, &format!("{what}[0]"))?;
    let lat = number(lat, &format!("{what}[1]"))?;
    latlon(lon, lat, what)?;
    Ok([lon, lat])
}

/// A WGS84 position from degrees, range-checked (with a hint when the order looks swapped).
pub(super) fn latlon(lon: f64, lat: f64, what: &str) -> Result<LatLon, Problem> {
    let swapped = (-90.0..=90.0).contains(&lon) && (-180.0..=180.0).contains(&lat);
    let hint = match (swapped, what) {
        (false, _) => "",
        (true, "cone") => " (latitude and longitude look swapped)",
        (true, _) => " (latitude and longitude look swapped: GeoJSON positions are [lon, lat])",
    };
    if !(-90.0..=90.0).contains(&lat) {
        return Err(invalid(
            what,
            format!("latitude {lat}"),
            format!("a latitude of -90 to 90 degrees{hint}"),
        ));
    }
    if !(-180.0..=180.0).contains(&lon) {
        return Err(invalid(
            what,
            format!("longitude {lon}"),
            "a longitude of -180 to 180 degrees",
        ));
    }
    LatLon::from_degrees(lat, lon)
        .ok_or_else(|| invalid(what, format!("{lat}, {lon}"), "a position J2735 can carry"))
}

/// Member `name` of `obj`; missing (or `null`) is an error naming `what`.
pub(super) fn member<'a>(
    obj: &'a Map<String, Value>,
    name: &str,
    what: &str,
) -> Result<&'a Value, Problem> {
    obj.get(name)
        .filter(|v| !v.is_null())
        .ok_or_else(|| Problem::Missing { what: what.into() })
}

/// `v` as an object.
pub(super) fn object<'a>(v: &'a Value, what: &str) -> Result<&'a Map<String, Value>, Problem> {
    v.as_object()
        .ok_or_else(|| wrong_type(what, "an object", v))
}

/// `v` as a string.
pub(super) fn string<'a>(v: &'a Value, what: &str) -> Result<&'a str, Problem> {
    v.as_str().ok_or_else(|| wrong_type(what, "a string", v))
}

/// `v` as a finite number.
pub(super) fn number(v: &Value, what: &str) -> Result<f64, Problem> {
    v.as_f64()
        .filter(|x| x.is_finite())
        .ok_or_else(|| wrong_type(what, "a number", v))
}

/// A [`Problem::WrongType`] for `found`.
pub(super) fn wrong_type(what: &str, expected: &'static str, found: &Value) -> Problem {
    Problem::WrongType {
        what: what.into(),
        expected,
        found: match found {
            Value::Null => "null",
            Value::Bool(_) => "a boolean",
            Value::Number(_) => "a number",
            Value::String(_) => "a string",
            Value::Array(_) => "an array",
            Value::Object(_) => "an object",
        },
    }
}

/// A [`Problem::Invalid`].
pub(super) fn invalid(
    what: &str,
    value: impl fmt::Display,
    expected: impl Into<String>,
) -> Problem {
    Problem::Invalid {
        what: what.into(),
        value: value.to_string(),
        expected: expected.into(),
    }
}
