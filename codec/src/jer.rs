//! JER, the JSON encoding rules of ITU-T X.697, for every generated type (feature `jer`).
//!
//! SEQUENCE is an object of the present components under their ASN.1 names, CHOICE
//! `{"alternative": value}`, ENUMERATED its identifier, BIT STRING of fixed size hex and of
//! variable size `{"value": hex, "length": bits}`, OCTET STRING hex, an open type the JER of
//! the value it holds (hex of its encoding when the type is unknown here).
//!
//! Reading accepts what X.697 allows and, for BIT STRINGs, also a bare hex string (as some
//! encoders write for extensible sizes). Components this build does not know are ignored
//! by the default (lax) reading and rejected by the strict one ([`Options::strict`],
//! [`from_str_strict`]); extension additions kept from UPER travel in the member
//! [`EXTENSIONS_MEMBER`].

pub(crate) mod parts;
mod strict;

use std::fmt::Write as _;
use std::string::{String, ToString};
use std::vec::Vec;

pub use serde_json::Value;

use parts::boolean;

/// Why a JER value could not be read.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct JerError {
    /// What is wrong.
    pub reason: String,
    /// Where: the ASN.1 type path and components from the outside in.
    pub path: String,
}

impl JerError {
    /// An error with `reason` at an unknown place.
    #[cold]
    pub fn new(reason: impl Into<String>) -> Self {
        Self {
            reason: reason.into(),
            path: String::new(),
        }
    }

    /// Prefixes the path with `part` (the caller's component or type).
    #[cold]
    #[must_use]
    pub fn within(mut self, part: &str) -> Self {
        self.path = if self.path.is_empty() {
            part.to_string()
        } else {
            std::format!("{part}.{}", self.path)
        };
        self
    }
}

impl core::fmt::Display for JerError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        if self.path.is_empty() {
            f.write_str(&self.reason)
        } else {
            write!(f, "{} at {}", self.reason, self.path)
        }
    }
}

impl std::error::Error for JerError {}

/// Result of reading JER.
pub type JerResult<T> = Result<T, JerError>;

/// A type with a JER form.
pub trait Jer: Sized {
    /// Writes the value's JER.
    fn write_jer(&self, out: &mut JerWriter);
    /// Reads a value from its JER.
    fn read_jer(v: &Value) -> JerResult<Self>;
}

impl Jer for bool {
    fn write_jer(&self, out: &mut JerWriter) {
        out.bool(*self);
    }
    fn read_jer(v: &Value) -> JerResult<Self> {
        boolean(v)
    }
}

impl<T: Jer> Jer for crate::uper::Boxed<T> {
    /// The value's JER, as if it were not boxed.
    fn write_jer(&self, out: &mut JerWriter) {
        T::write_jer(self, out)
    }
    fn read_jer(v: &Value) -> JerResult<Self> {
        T::read_jer(v).map(Self::new)
    }
}

impl<T: Jer + 'static> Jer for crate::uper::MessageBox<T> {
    /// The value's JER, as if it were not boxed.
    fn write_jer(&self, out: &mut JerWriter) {
        T::write_jer(self, out)
    }
    fn read_jer(v: &Value) -> JerResult<Self> {
        T::read_jer(v).map(Self::new)
    }
}

impl Jer for crate::uper::Null {
    fn write_jer(&self, out: &mut JerWriter) {
        out.null();
    }
    fn read_jer(v: &Value) -> JerResult<Self> {
        if v.is_null() {
            Ok(crate::uper::Null)
        } else {
            Err(JerError::new("expected null"))
        }
    }
}

/// The compact JER text of `value`.
pub fn to_string<T: Jer>(value: &T) -> String {
    let mut w = JerWriter::default();
    value.write_jer(&mut w);
    w.finish()
}

/// How JER is read.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Options {
    /// Reject members of a SEQUENCE (or of a BIT STRING's or `_extensions`' object) that
    /// the type does not have, naming the member and its path; the default (`false`)
    /// ignores them. [`EXTENSIONS_MEMBER`] is allowed in both modes.
    pub strict: bool,
}

impl Options {
    /// The default reading: unknown members are ignored.
    pub const LAX: Self = Self { strict: false };
    /// Unknown members are errors.
    pub const STRICT: Self = Self { strict: true };
}

/// Reads a value from JER text (lax: unknown members are ignored).
pub fn from_str<T: Jer>(text: &str) -> JerResult<T> {
    from_str_with(text, Options::LAX)
}

/// Reads a value from JER text, rejecting unknown members.
pub fn from_str_strict<T: Jer>(text: &str) -> JerResult<T> {
    from_str_with(text, Options::STRICT)
}

/// Reads a value from JER text as `options` say.
pub fn from_str_with<T: Jer>(text: &str, options: Options) -> JerResult<T> {
    let v: Value =
        serde_json::from_str(text).map_err(|e| JerError::new(std::format!("invalid JSON: {e}")))?;
    read_with(&v, options)
}

/// Reads a value from a parsed JER document as `options` say.
pub fn read_with<T: Jer>(v: &Value, options: Options) -> JerResult<T> {
    if options.strict {
        strict::read_checked(v, T::read_jer)
    } else {
        T::read_jer(v)
    }
}

/// Compares two JER documents as values: `Ok` when equal, treating the object form
/// `{"value": H, "length": n}` of an extensible-size BIT STRING (which we write, as X.697
/// asks) like the bare `H` other tools write for it (pycrate); otherwise the first
/// difference with its path.
pub fn equivalent(ours: &Value, theirs: &Value) -> Result<(), std::string::String> {
    same_at(ours, theirs, "")
}

fn same_at(ours: &Value, theirs: &Value, path: &str) -> Result<(), std::string::String> {
    use std::format;
    match (ours, theirs) {
        (Value::Object(o), Value::String(t)) if o.len() == 2 && o.contains_key("length") => {
            same_at(&o["value"], &Value::String(t.clone()), path)
        }
        (Value::String(o), Value::Object(t)) if t.len() == 2 && t.contains_key("length") => {
            same_at(&Value::String(o.clone()), &t["value"], path)
        }
        (Value::Object(o), Value::Object(t)) => {
            let mut ok: std::vec::Vec<_> = o.keys().collect();
            let mut tk: std::vec::Vec<_> = t.keys().collect();
            ok.sort();
            tk.sort();
            if ok != tk {
                return Err(format!("{path}: members {ok:?} vs {tk:?}"));
            }
            o.iter()
                .try_for_each(|(k, v)| same_at(v, &t[k], &format!("{path}.{k}")))
        }
        (Value::Array(o), Value::Array(t)) if o.len() == t.len() => o
            .iter()
            .zip(t)
            .enumerate()
            .try_for_each(|(i, (a, b))| same_at(a, b, &format!("{path}[{i}]"))),
        (a, b) if a == b => Ok(()),
        (a, b) => Err(format!("{path}: {a} vs {b}")),
    }
}

/// Writes compact JSON, placing the commas.
#[derive(Default, Debug)]
pub struct JerWriter {
    out: String,
    /// Per open object/array: whether an element was written yet.
    started: Vec<bool>,
}

impl JerWriter {
    /// The text written.
    pub fn finish(self) -> String {
        self.out
    }

    fn element(&mut self) {
        if let Some(started) = self.started.last_mut() {
            if *started {
                self.out.push(',');
            }
            *started = true;
        }
    }

    /// `{`
    pub fn begin_object(&mut self) {
        self.element();
        self.out.push('{');
        self.started.push(false);
    }

    /// `}`
    pub fn end_object(&mut self) {
        self.started.pop();
        self.out.push('}');
    }

    /// `[`
    pub fn begin_array(&mut self) {
        self.element();
        self.out.push('[');
        self.started.push(false);
    }

    /// `]`
    pub fn end_array(&mut self) {
        self.started.pop();
        self.out.push(']');
    }

    /// A member name; the value written next belongs to it.
    pub fn key(&mut self, name: &str) {
        self.element();
        self.quoted(name);
        self.out.push(':');
        if let Some(started) = self.started.last_mut() {
            *started = false;
        }
    }

    /// A whole number.
    pub fn int(&mut self, v: i64) {
        self.element();
        let _ = write!(self.out, "{v}");
    }

    /// `true` / `false`.
    pub fn bool(&mut self, v: bool) {
        self.element();
        self.out.push_str(if v { "true" } else { "false" });
    }

    /// `null`.
    pub fn null(&mut self) {
        self.element();
        self.out.push_str("null");
    }

    /// A string, escaped.
    pub fn string(&mut self, s: &str) {
        self.element();
        self.quoted(s);
    }

    /// Octets as a lower-case hex string.
    pub fn hex(&mut self, bytes: &[u8]) {
        self.element();
        self.out.push('"');
        let _ = crate::hex::encode(bytes, &mut self.out);
        self.out.push('"');
    }

    /// A variable-size BIT STRING: `{"value": hex, "length": n}`.
    pub fn bits(&mut self, bytes: &[u8], len: usize) {
        self.begin_object();
        self.key("value");
        self.hex(bytes);
        self.key("length");
        self.int(len as i64);
        self.end_object();
    }

    fn quoted(&mut self, s: &str) {
        self.out.push('"');
        for c in s.chars() {
            match c {
                '"' => self.out.push_str("\\\""),
                '\\' => self.out.push_str("\\\\"),
                '\n' => self.out.push_str("\\n"),
                '\r' => self.out.push_str("\\r"),
                '\t' => self.out.push_str("\\t"),
                c if (c as u32) < 0x20 || c as u32 == 0x7f => {
                    let _ = write!(self.out, "\\u{:04x}", c as u32);
                }
                c => self.out.push(c),
            }
        }
        self.out.push('"');
    }
}

/// Member name under which unknown extension additions of a SEQUENCE travel. X.697 has no
/// form for them; a name starting with `_` cannot clash with an ASN.1 identifier.
pub const EXTENSIONS_MEMBER: &str = "_extensions";

#[cfg(test)]
mod tests {
    use super::parts::{bits, hex};
    use super::*;

    #[test]
    fn writer_places_commas_and_escapes() {
        let mut w = JerWriter::default();
        w.begin_object();
        w.key("a");
        w.int(-3);
        w.key("b");
        w.begin_array();
        w.string("x\"y");
        w.hex(&[0xab, 1]);
        w.bits(&[0x80], 1);
        w.end_array();
        w.key("c");
        w.bool(true);
        w.end_object();
        assert_eq!(
            w.finish(),
            r#"{"a":-3,"b":["x\"y","ab01",{"value":"80","length":1}],"c":true}"#
        );
    }

    #[test]
    fn bit_strings_in_both_forms() {
        let v: Value = serde_json::from_str(r#"{"value":"a0","length":3}"#).unwrap();
        assert_eq!(bits(&v, 0, 8).unwrap(), (std::vec![0xa0], 3));
        let v = Value::String("8000".into());
        assert_eq!(bits(&v, 13, 13).unwrap(), (std::vec![0x80, 0], 13));
        assert_eq!(
            bits(&Value::String(String::new()), 8, 8).unwrap(),
            (std::vec![], 0)
        );
        assert!(hex(&Value::String("8".into())).is_err());
    }
}
