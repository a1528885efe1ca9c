//! What the generated `Jer` impls (and the constrained-integer macro) call to read and
//! write the parts of a JER value: members, alternatives, numbers, hex, BIT STRINGs and the
//! `_extensions` member. Public through `crate::__private::jer` only (hidden from the docs).

use std::vec::Vec;

use super::strict;
use super::{JerError, JerResult, JerWriter, Value, EXTENSIONS_MEMBER};

/// A member of a JER object, when present.
pub fn member<'a>(v: &'a Value, name: &str) -> JerResult<Option<&'a Value>> {
    match v {
        Value::Object(map) => {
            strict::note_lookup(map, name);
            Ok(map.get(name))
        }
        _ => Err(JerError::new("expected an object")),
    }
}

/// A mandatory member of a JER object.
pub fn required<'a>(v: &'a Value, name: &str) -> JerResult<&'a Value> {
    member(v, name)?.ok_or_else(|| JerError::new(std::format!("missing component {name}")))
}

/// Reads a member with `read`, naming it in errors.
pub fn read_member<T>(
    v: &Value,
    name: &str,
    read: impl FnOnce(&Value) -> JerResult<T>,
) -> JerResult<T> {
    read(required(v, name)?).map_err(|e| e.within(name))
}

/// Reads an optional member with `read`, naming it in errors.
pub fn read_optional<T>(
    v: &Value,
    name: &str,
    read: impl FnOnce(&Value) -> JerResult<T>,
) -> JerResult<Option<T>> {
    match member(v, name)? {
        Some(m) => read(m).map(Some).map_err(|e| e.within(name)),
        None => Ok(None),
    }
}

/// A whole number in `lb..=ub`.
pub fn int(v: &Value, lb: i64, ub: i64) -> JerResult<i64> {
    let n = v
        .as_i64()
        .ok_or_else(|| JerError::new("expected a whole number"))?;
    if n < lb || n > ub {
        return Err(JerError::new(std::format!("{n} outside {lb}..{ub}")));
    }
    Ok(n)
}

/// A boolean.
pub fn boolean(v: &Value) -> JerResult<bool> {
    v.as_bool()
        .ok_or_else(|| JerError::new("expected true or false"))
}

/// A string.
pub fn string(v: &Value) -> JerResult<&str> {
    v.as_str().ok_or_else(|| JerError::new("expected a string"))
}

/// The single (name, value) member of a CHOICE object.
pub fn alternative(v: &Value) -> JerResult<(&str, &Value)> {
    match v {
        Value::Object(map) if map.len() == 1 => {
            let (k, val) = map
                .iter()
                .next()
                .ok_or_else(|| JerError::new("empty CHOICE"))?;
            Ok((k.as_str(), val))
        }
        _ => Err(JerError::new("expected an object with one alternative")),
    }
}

/// The elements of an array.
pub fn array(v: &Value) -> JerResult<&[Value]> {
    v.as_array()
        .map(Vec::as_slice)
        .ok_or_else(|| JerError::new("expected an array"))
}

/// Octets from a hex string.
pub fn hex(v: &Value) -> JerResult<Vec<u8>> {
    let s = string(v)?;
    let error = |e| match e {
        crate::hex::HexError::OddLength => JerError::new("odd number of hex digits"),
        _ => JerError::new("invalid hex digit"),
    };
    let mut bytes = std::vec![0; crate::hex::decoded_len(s).map_err(error)?];
    crate::hex::decode_into(s, &mut bytes).map_err(error)?;
    Ok(bytes)
}

/// A BIT STRING of `lb..=ub` bits: `{"value", "length"}`, or bare hex (then the length is
/// `ub` or `lb` when the octets fit it exactly, else all the octets' bits).
pub fn bits(v: &Value, lb: usize, ub: usize) -> JerResult<(Vec<u8>, usize)> {
    if v.is_object() {
        let bytes = read_member(v, "value", hex)?;
        let len = read_member(v, "length", |l| int(l, 0, i64::from(u32::MAX)))? as usize;
        if len.div_ceil(8) > bytes.len() {
            return Err(JerError::new("length exceeds the value's bits"));
        }
        return Ok((bytes, len));
    }
    let bytes = hex(v)?;
    let len = if ub.div_ceil(8) == bytes.len() {
        ub
    } else if lb.div_ceil(8) == bytes.len() {
        lb
    } else {
        bytes.len() * 8
    };
    Ok((bytes, len))
}

/// Writes a SEQUENCE's unknown extension additions (when it has any) as the member
/// `"_extensions": {"bitmapLength": n, "additions": [[index, "hex"], ...]}`, so that
/// UPER -> JER -> UPER keeps messages from a newer J2735 byte-exact.
pub fn write_extensions<const N: usize>(out: &mut JerWriter, ext: &crate::uper::Extensions<N>) {
    if !ext.is_present() {
        return;
    }
    out.key(EXTENSIONS_MEMBER);
    out.begin_object();
    out.key("bitmapLength");
    out.int(ext.bitmap_len() as i64);
    out.key("additions");
    out.begin_array();
    for (index, content) in ext.unknown() {
        out.begin_array();
        out.int(index as i64);
        out.hex(content);
        out.end_array();
    }
    out.end_array();
    out.end_object();
}

/// Reads the member written by [`write_extensions`] (absent: no extensions).
pub fn read_extensions<const N: usize>(v: &Value) -> JerResult<crate::uper::Extensions<N>> {
    let Some(e) = member(v, EXTENSIONS_MEMBER)? else {
        return Ok(crate::uper::Extensions::new());
    };
    let bitmap = read_member(e, "bitmapLength", |x| int(x, 0, 64))? as usize;
    let mut parts = Vec::new();
    for item in array(required(e, "additions")?)? {
        let pair = array(item)?;
        let [index, content] = pair else {
            return Err(JerError::new("an addition is [index, hex]"));
        };
        parts.push((int(index, 0, 63)? as usize, hex(content)?));
    }
    crate::uper::Extensions::from_parts(bitmap, parts.iter().map(|(i, c)| (*i, c.as_slice())))
        .ok_or_else(|| {
            JerError::new("extension additions out of order or over the capacity")
                .within(EXTENSIONS_MEMBER)
        })
}

/// The error of a list or string over its no-heap capacity.
#[cold]
pub fn over_capacity() -> JerError {
    JerError::new("more than the no-heap capacity")
}

/// The error of a value outside its type's constraint.
#[cold]
pub fn invalid(what: &str) -> JerError {
    JerError::new(std::format!("{what} outside the type's constraint"))
}
