//! Reading the input and taking the MessageFrames out of it: hex lines, one binary frame,
//! IEEE 1609.2 envelopes and RSU 4.1 text records.
//!
//! Every frame of the input becomes one [`Item`], in input order: the frame's bytes, or the
//! reason they could not be found (bad hex, a malformed envelope or record). The decoding
//! commands write one output line per item, so a bad frame never hides the others.

use std::io::{self, IsTerminal, Read};

use j2735::envelope::rsu_text::{RsuMessage, RsuTextError};
use j2735::envelope::{unwrap_message_frame, UnwrapError};
use j2735::hex;

use crate::args::{InputFormat, InputOptions, Source, Unwrap};

/// One frame of the input: its UPER bytes, or why they could not be taken out.
pub type Item = Result<Vec<u8>, String>;

/// Reads the whole input (a file, or standard input).
pub fn read_all(source: &Source) -> io::Result<Vec<u8>> {
    match source {
        Source::File(path) => std::fs::read(path),
        Source::Stdin => {
            let mut stdin = io::stdin().lock();
            if stdin.is_terminal() {
                eprintln!("j2735: reading standard input (end it with Ctrl-D)");
            }
            let mut bytes = Vec::new();
            stdin.read_to_end(&mut bytes)?;
            Ok(bytes)
        }
    }
}

/// The frames of `input`, as [`InputOptions`] say to find them.
pub fn frames(input: &[u8], options: &InputOptions) -> Vec<Item> {
    let auto = options.unwrap == Unwrap::Auto;
    let text = String::from_utf8_lossy(input);
    match options.format {
        InputFormat::Bin if auto && starts_as_rsu_text(&text) => rsu_records(&text),
        InputFormat::Bin => vec![unwrap(input.to_vec(), auto)],
        InputFormat::Hex if auto && is_rsu_text(&text) => rsu_records(&text),
        InputFormat::Hex => hex_lines(&text, auto),
    }
}

/// Removes an IEEE 1609.2 envelope around `bytes` when `auto`.
fn unwrap(bytes: Vec<u8>, auto: bool) -> Item {
    if !auto {
        return Ok(bytes);
    }
    match unwrap_message_frame(&bytes) {
        Ok(found) if found.frame.len() == bytes.len() => Ok(bytes),
        Ok(found) => Ok(found.frame.to_vec()),
        Err(UnwrapError::Envelope(e)) => Err(format!(
            "{} at byte {} in Ieee1609Dot2Data",
            e.kind, e.offset
        )),
        Err(UnwrapError::NoPlaintextPayload) => {
            Err("no plaintext application data in Ieee1609Dot2Data".into())
        }
    }
}

/// One frame per non-blank line that is not a `#` comment.
fn hex_lines(text: &str, auto: bool) -> Vec<Item> {
    text.lines()
        .enumerate()
        .filter(|(_, line)| !is_skipped(line))
        .map(|(index, line)| {
            parse_hex(line)
                .map_err(|why| format!("{why} on line {}", index + 1))
                .and_then(|bytes| unwrap(bytes, auto))
        })
        .collect()
}

fn is_skipped(line: &str) -> bool {
    let line = line.trim();
    line.is_empty() || line.starts_with('#')
}

/// Bytes of one hex line: whitespace anywhere and a `0x` before any group are ignored.
fn parse_hex(line: &str) -> Result<Vec<u8>, String> {
    let digits: String = line
        .split_whitespace()
        .map(|group| {
            group
                .strip_prefix("0x")
                .or_else(|| group.strip_prefix("0X"))
                .unwrap_or(group)
        })
        .collect();
    if let Some(c) = digits.chars().find(|c| !c.is_ascii_hexdigit()) {
        return Err(format!("invalid hex digit {c:?}"));
    }
    let len = hex::decoded_len(&digits).map_err(hex_error)?;
    let mut bytes = vec![0; len];
    hex::decode_into(&digits, &mut bytes).map_err(hex_error)?;
    Ok(bytes)
}

fn hex_error(error: hex::HexError) -> String {
    match error {
        hex::HexError::OddLength => "odd number of hex digits".into(),
        other => other.to_string(),
    }
}

/// Whether a line starts an RSU text record (`Version=`, any letter case).
fn is_version_line(line: &str) -> bool {
    let line = line.trim_start_matches('\u{feff}').trim_start();
    line.get(..8)
        .is_some_and(|key| key.eq_ignore_ascii_case("version="))
}

/// Whether `text` holds RSU text records (some line starts with `Version=`).
fn is_rsu_text(text: &str) -> bool {
    text.lines().any(is_version_line)
}

/// Whether the first non-blank line of `text` starts an RSU record (binary input: a
/// MessageFrame or 1609.2 envelope never starts with `V`).
fn starts_as_rsu_text(text: &str) -> bool {
    text.lines()
        .find(|line| !line.trim_start_matches('\u{feff}').trim().is_empty())
        .is_some_and(is_version_line)
}

/// One item per RSU record; a record runs from its `Version=` line to the next one.
fn rsu_records(text: &str) -> Vec<Item> {
    let mut items = Vec::new();
    let mut start: Option<(usize, usize)> = None; // (byte offset, 1-based line)
    let mut offset = 0;
    for (index, line) in text.split_inclusive('\n').enumerate() {
        if is_version_line(line) {
            items.extend(start.map(|(from, n)| rsu_record(&text[from..offset], n)));
            start = Some((offset, index + 1));
        } else if start.is_none() && !is_skipped(line) {
            items.push(Err(format!(
                "line {} comes before the first Version= line of the RSU text records",
                index + 1
            )));
        }
        offset += line.len();
    }
    items.extend(start.map(|(from, n)| rsu_record(&text[from..], n)));
    items
}

/// The frame in one RSU record that starts on line `first_line`.
fn rsu_record(record: &str, first_line: usize) -> Item {
    let message = RsuMessage::parse(record).map_err(|e| rsu_error(e, first_line))?;
    let payload_error =
        |e: hex::HexError| format!("{e} in the Payload of the RSU record on line {first_line}");
    let mut bytes = vec![0; message.payload.decoded_len().map_err(payload_error)?];
    message
        .payload
        .decode_into(&mut bytes)
        .map_err(payload_error)?;
    unwrap(bytes, true)
}

/// An RSU record error with line numbers of the whole input.
fn rsu_error(error: RsuTextError, first_line: usize) -> String {
    let line = if error.line > 0 {
        error.line + first_line - 1
    } else {
        0
    };
    let shifted = RsuTextError { line, ..error };
    format!("{shifted} in the RSU record starting on line {first_line}")
}

#[cfg(test)]
mod tests {
    use super::*;

    fn hex_options() -> InputOptions {
        InputOptions {
            format: InputFormat::Hex,
            unwrap: Unwrap::Auto,
            source: Source::Stdin,
        }
    }

    #[test]
    fn hex_lines_tolerate_spaces_prefixes_and_blank_lines() {
        let items = frames(
            b"0x001f01\n\n  00 1F 02 \n# note\n0x00 0x14\n",
            &hex_options(),
        );
        assert_eq!(
            items,
            vec![
                Ok(vec![0, 0x1f, 1]),
                Ok(vec![0, 0x1f, 2]),
                Ok(vec![0, 0x14])
            ]
        );
    }

    #[test]
    fn bad_hex_names_the_line() {
        let items = frames(b"001f\nzz\n001\n", &hex_options());
        assert_eq!(items[0], Ok(vec![0, 0x1f]));
        assert_eq!(items[1], Err("invalid hex digit 'z' on line 2".into()));
        assert_eq!(items[2], Err("odd number of hex digits on line 3".into()));
    }

    #[test]
    fn envelopes_are_removed_unless_told_not_to() {
        let items = frames(b"03 80 03 00 1f 01\n038009001f\n", &hex_options());
        assert_eq!(items[0], Ok(vec![0, 0x1f, 1]));
        assert_eq!(
            items[1],
            Err("unexpected end at byte 3 in Ieee1609Dot2Data".into())
        );
        let none = InputOptions {
            unwrap: Unwrap::None,
            ..hex_options()
        };
        assert_eq!(
            frames(b"03800300 1f01", &none),
            vec![Ok(vec![3, 0x80, 3, 0, 0x1f, 1])]
        );
    }

    #[test]
    fn rsu_records_split_at_version_lines() {
        let text = "Version=0.7\nType=TIM\nPSID=0x8003\nPayload=001F01\n\n\
                    Version=0.5\r\n\r\nType=MAP\r\n\r\nPSID=8002\r\n\r\nPayload=0012\r\n\r\n\
                    Version=0.7\nType=MAP\nPSID=0x8002\n";
        let items = frames(text.as_bytes(), &hex_options());
        assert_eq!(items.len(), 3);
        assert_eq!(items[0], Ok(vec![0, 0x1f, 1]));
        assert_eq!(items[1], Ok(vec![0, 0x12]));
        assert_eq!(
            items[2],
            Err("missing key Payload in the RSU record starting on line 14".into())
        );
    }

    #[test]
    fn rsu_errors_count_lines_of_the_whole_input() {
        let text = "Version=0.7\nType=TIM\nPSID=0x8003\nPayload=001F\n\
                    Version=0.7\nType=TIM\nPSID=xyz\nPayload=001F\n";
        let items = frames(text.as_bytes(), &hex_options());
        assert_eq!(
            items[1],
            Err("invalid value for PSID on line 7 in the RSU record starting on line 5".into())
        );
    }

    #[test]
    fn binary_input_is_one_frame() {
        let bin = InputOptions {
            format: InputFormat::Bin,
            ..hex_options()
        };
        assert_eq!(
            frames(&[3, 0x80, 2, 0, 0x14], &bin),
            vec![Ok(vec![0, 0x14])]
        );
        assert_eq!(
            frames(b"Version=0.7\nType=BSM\nPSID=20\nPayload=0014\n", &bin),
            vec![Ok(vec![0, 0x14])]
        );
    }
}
