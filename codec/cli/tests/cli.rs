//! The `j2735` binary on inputs made from the project's oracle vectors
//! (`codec/tests/vectors/oracle_vectors.jsonl`).

mod common;

use common::{error_of, from_hex, j2735, same_jer, scratch_file, vector, vectors, Vector};
use serde_json::Value;

fn hex_lines(vectors: &[Vector]) -> String {
    vectors.iter().map(|v| format!("{}\n", v.uper)).collect()
}

fn work_zone() -> Vec<Vector> {
    [
        "map_work_zone",
        "tim_work_zone_left_lane_closed",
        "bsm_minimal",
    ]
    .into_iter()
    .map(vector)
    .collect()
}

/// Checks that `lines` are the JER of `vectors`, in order.
fn assert_jer_of(lines: &[&str], vectors: &[Vector]) {
    assert_eq!(lines.len(), vectors.len());
    for (line, v) in lines.iter().zip(vectors) {
        let ours: Value = serde_json::from_str(line).unwrap_or_else(|e| panic!("{}: {e}", v.name));
        same_jer(&ours, &v.jer, "").unwrap_or_else(|e| panic!("{}: JER differs at {e}", v.name));
    }
}

#[test]
fn decode_gives_the_oracle_jer_of_every_vector() {
    let all = vectors();
    let run = j2735(&["decode"], hex_lines(&all).as_bytes());
    assert_eq!(run.code, 0, "{}", run.stderr);
    assert_jer_of(&run.lines(), &all);
    println!("{} vectors decoded to the oracle's JER", all.len());
}

#[test]
fn encode_of_the_decoded_vectors_gives_the_hex_back() {
    let all = vectors();
    let input = hex_lines(&all);
    let decoded = j2735(&["decode", "-"], input.as_bytes());
    let encoded = j2735(&["encode", "-"], decoded.stdout.as_bytes());
    assert_eq!(encoded.code, 0, "{}", encoded.stdout);
    assert_eq!(encoded.stdout, input);
}

#[test]
fn failed_frames_get_error_lines_and_the_others_still_come_out() {
    let [map, tim, bsm] = <[Vector; 3]>::try_from(work_zone()).ok().unwrap();
    let truncated = &map.uper[..map.uper.len() / 2];
    let input = format!(
        "{}\ngarbage\n{}\n{truncated}\n{}\n",
        bsm.uper, tim.uper, map.uper
    );
    let run = j2735(&["decode"], input.as_bytes());
    assert_eq!(run.code, 1);
    let lines = run.lines();
    assert_eq!(lines.len(), 5, "{}", run.stdout);
    assert_eq!(
        error_of(lines[1]).unwrap(),
        "invalid hex digit 'g' on line 2"
    );
    let truncated_error = error_of(lines[3]).unwrap();
    let (kind, rest) = truncated_error.split_once(" at bit ").unwrap();
    let (bit, path) = rest.split_once(" in ").unwrap();
    assert_eq!(kind, "unexpected end", "{truncated_error}");
    assert!(bit.parse::<usize>().unwrap() <= 4 * truncated.len());
    assert!(
        path.contains('.') && !path.contains(' '),
        "{truncated_error}"
    );
    assert_jer_of(&[lines[0], lines[2], lines[4]], &[bsm, tim, map]);
}

#[test]
fn hex_with_spaces_and_0x_prefixes_is_read() {
    let tim = vector("tim_work_zone_left_lane_closed");
    let spaced: Vec<String> = (0..tim.uper.len() / 2)
        .map(|i| format!("0x{}", &tim.uper[2 * i..2 * i + 2]))
        .collect();
    let input = format!(
        "\n0x{}\n  {}  \n\n{}\n",
        tim.uper.to_uppercase(),
        spaced.join(" "),
        spaced.join("\t")
    );
    let run = j2735(&["decode"], input.as_bytes());
    assert_eq!(run.code, 0, "{}", run.stdout);
    let expected: Vec<Vector> = (0..3).map(|_| vector(&tim.name)).collect();
    assert_jer_of(&run.lines(), &expected);
}

#[test]
fn binary_input_is_one_frame() {
    let map = vector("map_work_zone");
    let bytes = from_hex(&map.uper);
    let run = j2735(&["decode", "--input", "bin"], &bytes);
    assert_eq!(run.code, 0, "{}", run.stdout);
    assert_jer_of(&run.lines(), std::slice::from_ref(&map));
    let file = scratch_file("map_work_zone.uper", &bytes);
    let run = j2735(&["decode", "--input=bin", file.to_str().unwrap()], b"");
    assert_jer_of(&run.lines(), &[map]);
    let mut longer = bytes.clone();
    longer.push(0);
    let run = j2735(&["decode", "--input", "bin"], &longer);
    assert_eq!(run.code, 1);
    assert!(error_of(run.lines()[0])
        .unwrap()
        .starts_with("trailing bytes at bit "));
}

#[test]
fn ieee1609dot2_wrap_then_decode_with_auto_unwrap() {
    let frames = work_zone();
    let jer = j2735(&["decode"], hex_lines(&frames).as_bytes()).stdout;
    let wrapped = j2735(&["encode", "--wrap", "1609.2-unsecured"], jer.as_bytes());
    assert_eq!(wrapped.code, 0);
    for (line, v) in wrapped.lines().iter().zip(&frames) {
        assert!(
            line.starts_with("0380") && line.ends_with(&v.uper),
            "{line}"
        );
    }
    let run = j2735(&["decode"], wrapped.stdout.as_bytes());
    assert_eq!(run.code, 0, "{}", run.stdout);
    assert_jer_of(&run.lines(), &frames);
    let first = from_hex(wrapped.lines()[1]);
    let run = j2735(&["decode", "--input", "bin"], &first);
    assert_jer_of(&run.lines(), &[vector("tim_work_zone_left_lane_closed")]);
    // Without unwrapping, `03 80 <len < 128> <frame>` reads as a MessageFrame of the unknown
    // messageId 0x380 holding the frame; longer envelopes fail.
    let bare = j2735(&["decode", "--unwrap", "none"], wrapped.stdout.as_bytes());
    assert_eq!(bare.code, 1);
    for line in bare.lines() {
        assert!(
            error_of(line).is_some() || line.starts_with(r#"{"messageId":896,"#),
            "{line}"
        );
    }
}

#[test]
fn damaged_envelopes_name_the_byte() {
    let run = j2735(&["decode"], b"03 80 09 00 14 25\n");
    assert_eq!(run.code, 1);
    assert_eq!(
        error_of(run.lines()[0]).unwrap(),
        "unexpected end at byte 3 in Ieee1609Dot2Data"
    );
}

#[test]
fn rsu41_wrap_then_decode() {
    let frames = work_zone();
    let jer = j2735(&["decode"], hex_lines(&frames).as_bytes()).stdout;
    let records = j2735(&["encode", "--wrap", "rsu41"], jer.as_bytes());
    assert_eq!(records.code, 0, "{}", records.stdout);
    let text = &records.stdout;
    assert_eq!(text.matches("Version=0.7\n").count(), 3);
    assert!(text.contains("Type=MAP\nPSID=0x8002\n"), "{text}");
    assert!(text.contains("Type=TIM\nPSID=0x8003\n"), "{text}");
    assert!(text.contains("Type=BSM\nPSID=0x20\n"), "{text}");
    assert_eq!(
        text.matches("\n\nVersion=").count(),
        2,
        "blank line between records"
    );
    let run = j2735(&["decode"], text.as_bytes());
    assert_eq!(run.code, 0, "{}", run.stdout);
    assert_jer_of(&run.lines(), &frames);
    let file = scratch_file("work_zone.rsu41.txt", text.as_bytes());
    let run = j2735(&["decode", file.to_str().unwrap()], b"");
    assert_jer_of(&run.lines(), &frames);
}

#[test]
fn rsu41_psid_and_type_can_be_given() {
    let map = vector("map_work_zone");
    let jer = j2735(&["decode"], map.uper.as_bytes()).stdout;
    let args = [
        "encode",
        "--wrap",
        "rsu41",
        "--psid",
        "0xE0000017",
        "--type",
        "MAP",
    ];
    let run = j2735(&args, jer.as_bytes());
    assert!(
        run.stdout.contains("Type=MAP\nPSID=0xE0000017\n"),
        "{}",
        run.stdout
    );
    let run = j2735(
        &["encode", "--wrap", "rsu41", "--type", "TIM"],
        jer.as_bytes(),
    );
    assert_eq!(run.code, 1);
    assert!(error_of(run.lines()[0])
        .unwrap()
        .contains("--type TIM is messageId 31"));
}

#[test]
fn version_0_5_records_with_blank_lines_are_read() {
    let frames = work_zone();
    let record = |v: &Vector, kind: &str| {
        let payload = v.uper.to_uppercase();
        format!("Version=0.5\r\n\r\nType={kind}\r\n\r\nPSID=0x8002\r\n\r\nPriority=7\r\n\r\nPayload={payload}\r\n\r\n")
    };
    let text = record(&frames[0], "MAP") + &record(&frames[1], "TIM");
    let run = j2735(&["decode"], text.as_bytes());
    assert_eq!(run.code, 0, "{}", run.stdout);
    assert_jer_of(&run.lines(), &frames[..2]);
    let broken = text.replace(
        "PSID=0x8002\r\n\r\nPriority=7\r\n\r\nPayload=001F",
        "Payload=001F",
    );
    let run = j2735(&["decode"], broken.as_bytes());
    assert_eq!(run.code, 1);
    assert_eq!(
        error_of(run.lines()[1]).unwrap(),
        "missing key PSID in the RSU record starting on line 11"
    );
}

#[test]
fn encode_reports_bad_lines_and_goes_on() {
    let bsm = vector("bsm_minimal");
    let jer = j2735(&["decode"], bsm.uper.as_bytes()).stdout;
    let input = format!("{{\"messageId\":20}}\n{jer}not json\n{jer}");
    let run = j2735(&["encode"], input.as_bytes());
    assert_eq!(run.code, 1);
    let lines = run.lines();
    assert_eq!(lines.len(), 4);
    assert!(
        error_of(lines[0]).unwrap().contains("value"),
        "{}",
        lines[0]
    );
    assert!(
        error_of(lines[2]).unwrap().starts_with("invalid JSON"),
        "{}",
        lines[2]
    );
    assert_eq!(lines[1], bsm.uper);
    assert_eq!(lines[3], bsm.uper);
}

#[test]
fn info_mentions_lanes_nodes_and_itis_codes() {
    let run = j2735(&["info", "-"], hex_lines(&work_zone()).as_bytes());
    assert_eq!(run.code, 0, "{}", run.stdout);
    let text = &run.stdout;
    for expected in [
        "frame 1: MAP MapData (messageId 18), 116 octets",
        "intersection 7001 rev 3: 3 lanes, 10 nodes",
        "lane 1: ingress vehicle, 4 nodes",
        "frame 2: TIM TravelerInformation (messageId 31), 157 octets",
        "content workZone: ITIS 1025 (road construction), ITIS 769 (closed), ITIS 8195 (left lane)",
        "valid from 2025-06-17 12:00 UTC for 60 min",
        "region 1: path of 3 node-XY offsets",
        "frame 3: BSM BasicSafetyMessage (messageId 20), 40 octets",
    ] {
        assert!(text.contains(expected), "missing {expected:?} in\n{text}");
    }
    let run = j2735(&["info", "-"], b"zz\n");
    assert_eq!(
        (run.code, run.stdout.as_str()),
        (1, "frame 1: error: invalid hex digit 'z' on line 1\n")
    );
}

#[test]
fn every_command_has_help() {
    for (args, usage) in [
        (&["--help"][..], "Usage: j2735 <COMMAND>"),
        (&["help"][..], "Usage: j2735 <COMMAND>"),
        (&["decode", "--help"][..], "Usage: j2735 decode"),
        (&["help", "decode"][..], "Usage: j2735 decode"),
        (&["encode", "-h"][..], "Usage: j2735 encode"),
        (&["info", "--help"][..], "Usage: j2735 info"),
        (&["help", "help"][..], "Usage: j2735 help"),
    ] {
        let run = j2735(args, b"");
        assert_eq!(run.code, 0, "{args:?}");
        assert!(run.stdout.contains(usage), "{args:?}: {}", run.stdout);
    }
    let run = j2735(&["--version"], b"");
    assert_eq!(run.code, 0);
    assert!(run
        .stdout
        .starts_with(&format!("j2735 {}", env!("CARGO_PKG_VERSION"))));
}

#[test]
fn usage_errors_say_what_to_do() {
    for (args, message, hint) in [
        (
            &["decode", "--wrap", "rsu41"][..],
            "unknown option --wrap for decode",
            "--input, --unwrap",
        ),
        (
            &["decode", "--input", "text"][..],
            "invalid value `text` for --input",
            "hex or bin",
        ),
        (
            &["encode", "--psid", "0x8003"][..],
            "--psid and --type",
            "--wrap rsu41",
        ),
        (&["info"][..], "info needs an input", "FILE"),
        (
            &["decdoe"][..],
            "unknown command `decdoe`",
            "did you mean `j2735 decode`",
        ),
        (&[][..], "no command given", "j2735 help"),
    ] {
        let run = j2735(args, b"");
        assert_eq!(run.code, 2, "{args:?}");
        assert!(run.stdout.is_empty(), "{args:?}");
        assert!(run.stderr.contains(message), "{args:?}: {}", run.stderr);
        assert!(run.stderr.contains("hint: "), "{args:?}: {}", run.stderr);
        assert!(run.stderr.contains(hint), "{args:?}: {}", run.stderr);
    }
    let run = j2735(&["decode", "/nonexistent/frames.hex"], b"");
    assert_eq!(run.code, 2);
    assert!(
        run.stderr.contains("cannot read /nonexistent/frames.hex"),
        "{}",
        run.stderr
    );
}

#[test]
fn bad_flags_exit_2_with_a_message_and_a_hint() {
    for (args, message, hint) in [
        (
            &["--bogus"][..],
            "unknown option --bogus before the command",
            "j2735 help",
        ),
        (
            &["encode", "--stict"][..],
            "unknown option --stict for encode",
            "did you mean --strict?",
        ),
        (
            &["decode", "--input"][..],
            "--input needs a value",
            "hex or bin",
        ),
        (
            &["decode", "--unwrap", "all"][..],
            "invalid value `all` for --unwrap",
            "auto or none",
        ),
        (
            &["encode", "--wrap", "rsu41", "--psid", "0xZZ"][..],
            "invalid value `0xZZ` for --psid",
            "--psid 0x8003",
        ),
        (
            &["decode", "--input", "hex", "--input", "bin"][..],
            "--input given twice",
            "give --input once",
        ),
        (
            &["decode", "a.hex", "b.hex"][..],
            "more than one input",
            "cat a.hex b.hex",
        ),
    ] {
        let run = j2735(args, b"");
        assert_eq!(run.code, 2, "{args:?}");
        assert!(run.stdout.is_empty(), "{args:?}");
        assert!(
            run.stderr.starts_with("j2735: error: "),
            "{args:?}: {}",
            run.stderr
        );
        assert!(run.stderr.contains(message), "{args:?}: {}", run.stderr);
        assert!(run.stderr.contains(hint), "{args:?}: {}", run.stderr);
    }
}

#[test]
fn encode_strict_rejects_unknown_members_that_lax_ignores() {
    let map = vector("map_work_zone");
    let mut jer = map.jer.clone();
    jer["value"]["intersections"][0]["refPoint"]["altitudeHint"] = Value::from(3);
    let input = format!("{jer}\n");
    let lax = j2735(&["encode"], input.as_bytes());
    assert_eq!(
        (lax.code, lax.stdout.clone()),
        (0, format!("{}\n", map.uper))
    );
    let strict = j2735(&["encode", "--strict"], input.as_bytes());
    assert_eq!(strict.code, 1);
    assert_eq!(
        error_of(strict.lines()[0]).unwrap(),
        "unknown member \"altitudeHint\" at value.intersections.[0].refPoint"
    );
    let clean = j2735(&["encode", "--strict"], format!("{}\n", map.jer).as_bytes());
    assert_eq!((clean.code, clean.stdout), (0, format!("{}\n", map.uper)));
}
