//! JER (X.697): our JER of every oracle vector equals the oracle's, and JER -> UPER gives the
//! vector's bytes back. With feature `shared-corpus`, the same for every corpus frame whose
//! oracle note is empty (the oracle's JER in `../shared/corpus/jer`).

mod common;

use j2735::jer;
use j2735::uper::{self, Placeholder};
use j2735::MessageFrame;
use serde_json::Value;

/// Equal as JER (the two forms of extensible-size BIT STRINGs alike), with the path of
/// the first difference.
fn same_jer(ours: &Value, theirs: &Value, path: &str) -> Result<(), String> {
    jer::equivalent(ours, theirs).map_err(|e| format!("{path}{e}"))
}

/// Decodes `bytes`, compares our JER with `expected`, and encodes our JER read back.
fn check(
    name: &str,
    bytes: &[u8],
    expected: &Value,
    mf: &mut MessageFrame,
    buf: &mut [u8],
) -> Result<(), String> {
    uper::decode_into(bytes, mf).map_err(|e| format!("{name}: decode: {e}"))?;
    let text = jer::to_string(mf);
    let ours: Value =
        serde_json::from_str(&text).map_err(|e| format!("{name}: our JER is not JSON: {e}"))?;
    same_jer(&ours, expected, "").map_err(|e| format!("{name}: JER differs at {e}"))?;
    // Our own JER has no member the types do not know: the strict reading accepts it.
    let back: MessageFrame =
        jer::from_str_strict(&text).map_err(|e| format!("{name}: JER read: {e}"))?;
    let n = uper::encode(&back, buf).map_err(|e| format!("{name}: encode: {e}"))?;
    if &buf[..n] != bytes {
        return Err(format!("{name}: JER -> UPER differs"));
    }
    Ok(())
}

/// UPER -> JER -> UPER gives the same bytes.
#[cfg(feature = "shared-corpus")]
fn jer_round_trip(
    name: &str,
    bytes: &[u8],
    mf: &mut MessageFrame,
    buf: &mut [u8],
) -> Result<(), String> {
    uper::decode_into(bytes, mf).map_err(|e| format!("{name}: decode: {e}"))?;
    let back: MessageFrame =
        jer::from_str_strict(&jer::to_string(mf)).map_err(|e| format!("{name}: JER read: {e}"))?;
    let n = uper::encode(&back, buf).map_err(|e| format!("{name}: encode: {e}"))?;
    if &buf[..n] != bytes {
        return Err(format!("{name}: JER -> UPER differs"));
    }
    Ok(())
}

#[test]
fn vectors_jer_equals_the_oracle_and_round_trips() {
    common::big_stack(|| {
        let mut mf = Box::new(MessageFrame::placeholder());
        let mut buf = vec![0u8; 1 << 16];
        let mut failures = Vec::new();
        let mut n = 0;
        for line in include_str!("vectors/oracle_vectors.jsonl").lines() {
            let v: Value = serde_json::from_str(line).unwrap();
            let name = v["name"].as_str().unwrap();
            if v["covers"]
                .as_array()
                .unwrap()
                .iter()
                .any(|c| c == "opentype:fragmented")
                && !cfg!(feature = "alloc")
            {
                continue;
            }
            n += 1;
            let bytes = common::from_hex(v["uper"].as_str().unwrap());
            if let Err(e) = check(name, &bytes, &v["jer"], &mut mf, &mut buf) {
                failures.push(e);
            }
        }
        println!(
            "{}/{n} vectors: JER equals the oracle's and JER -> UPER is byte-exact",
            n - failures.len()
        );
        assert!(failures.is_empty(), "{}", failures.join("\n"));
    });
}

#[cfg(feature = "shared-corpus")]
#[test]
fn corpus_jer_equals_the_oracle_and_round_trips() {
    common::big_stack(|| {
        let dir = common::shared_dir().join("corpus/jer");
        let mut mf = Box::new(MessageFrame::placeholder());
        let mut buf = vec![0u8; 1 << 16];
        let (mut failures, mut compared, mut noted) = (Vec::new(), 0, 0);
        for (name, bytes) in common::corpus_frames() {
            let file = dir.join(format!("{name}.2020.json"));
            let Ok(text) = std::fs::read_to_string(&file) else {
                assert!(
                    name.starts_with("RSM_"),
                    "{name}: no oracle JER (only 2024-only RSM lacks one)"
                );
                noted += 1;
                if let Err(e) = jer_round_trip(&name, &bytes, &mut mf, &mut buf) {
                    failures.push(e);
                }
                continue;
            };
            let doc: Value = serde_json::from_str(&text).unwrap();
            if doc["note"].as_str().is_some_and(|n| !n.is_empty()) {
                // No clean oracle JER (2024 extension additions): our JER must still
                // carry the frame back to the same bytes.
                noted += 1;
                if let Err(e) = jer_round_trip(&name, &bytes, &mut mf, &mut buf) {
                    failures.push(e);
                }
                continue;
            }
            compared += 1;
            if let Err(e) = check(&name, &bytes, &doc["jer"], &mut mf, &mut buf) {
                failures.push(e);
            }
        }
        println!("{}/{compared} corpus frames: JER equals the oracle's, JER -> UPER byte-exact ({noted} without a clean 2020 oracle JER: round trip only)", compared - failures.len());
        assert!(compared >= 250);
        assert!(
            failures.is_empty(),
            "{} failures:\n{}",
            failures.len(),
            failures.join("\n")
        );
    });
}

/// The oracle's JER of the vector `name` and its UPER bytes.
fn oracle_vector(name: &str) -> (Value, Vec<u8>) {
    let line = include_str!("vectors/oracle_vectors.jsonl")
        .lines()
        .find(|l| l.contains(&format!("\"name\":\"{name}\"")))
        .unwrap_or_else(|| panic!("no vector {name}"));
    let v: Value = serde_json::from_str(line).unwrap();
    (
        v["jer"].clone(),
        common::from_hex(v["uper"].as_str().unwrap()),
    )
}

/// The UPER bytes of `frame`.
fn encoded(frame: &MessageFrame) -> Vec<u8> {
    let mut buf = vec![0u8; 1 << 16];
    let n = uper::encode(frame, &mut buf).unwrap();
    buf.truncate(n);
    buf
}

#[test]
fn strict_reading_rejects_an_unknown_member_of_a_nested_sequence() {
    common::big_stack(|| {
        let (mut doc, bytes) = oracle_vector("map_work_zone");
        // refPoint is a Position3D (SEQUENCE) inside IntersectionGeometry inside MapData.
        let ref_point = &mut doc["value"]["intersections"][0]["refPoint"];
        assert!(ref_point.is_object(), "{doc}");
        ref_point["altitudeHint"] = Value::from(12);
        let text = doc.to_string();

        let e = jer::from_str_strict::<MessageFrame>(&text).unwrap_err();
        assert_eq!(e.reason, "unknown member \"altitudeHint\"");
        assert_eq!(e.path, "value.intersections.[0].refPoint");
        assert_eq!(
            e.to_string(),
            "unknown member \"altitudeHint\" at value.intersections.[0].refPoint"
        );
        let e = jer::from_str_with::<MessageFrame>(&text, jer::Options { strict: true });
        assert!(e.is_err());

        // Lax (the default) ignores it and reads the same frame.
        let lax: MessageFrame = jer::from_str(&text).unwrap();
        assert_eq!(encoded(&lax), bytes);
        let lax: MessageFrame = jer::from_str_with(&text, jer::Options::LAX).unwrap();
        assert_eq!(encoded(&lax), bytes);
    });
}

#[test]
fn strict_reading_checks_the_top_level_and_keeps_extensions_allowed() {
    common::big_stack(|| {
        let (mut doc, _) = oracle_vector("bsm_minimal");
        doc["priority"] = Value::from(1);
        let e = jer::from_str_strict::<MessageFrame>(&doc.to_string()).unwrap_err();
        assert_eq!(
            (e.reason.as_str(), e.path.as_str()),
            ("unknown member \"priority\"", "")
        );

        let (mut doc, bytes) = oracle_vector("bsm_minimal");
        // The member of extension additions, here written out with none, is no unknown member.
        doc["_extensions"] = serde_json::json!({"bitmapLength": 0, "additions": []});
        let read = jer::from_str_strict::<MessageFrame>(&doc.to_string()).unwrap();
        assert_eq!(encoded(&read), bytes);
        // Inside `_extensions` the members are checked too.
        doc["_extensions"]["note"] = Value::from("x");
        let e = jer::from_str_strict::<MessageFrame>(&doc.to_string()).unwrap_err();
        assert_eq!(
            (e.reason.as_str(), e.path.as_str()),
            ("unknown member \"note\"", "_extensions")
        );
        let (doc, _) = oracle_vector("bsm_minimal");
        let frame: MessageFrame = jer::from_str_strict(&doc.to_string()).unwrap();
        assert_eq!(encoded(&frame), bytes);
    });
}
