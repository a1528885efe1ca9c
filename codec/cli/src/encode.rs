//! `j2735 encode`: JER MessageFrames (one per line) to UPER hex, bare or in an envelope.

use std::io::{self, Write};

use j2735::envelope::ieee1609dot2::{encode_unsecured, unsecured_encoded_len};
use j2735::envelope::rsu_text::{RsuMessage, RsuPayload};
use j2735::{jer, uper, MessageFrame};

use crate::args::{EncodeOptions, Wrap};
use crate::messages;
use crate::output::{error_line, to_hex, Outcome};

/// Reads one JER MessageFrame (`strict`: unknown members are errors) and encodes it;
/// returns its `messageId` and UPER bytes.
pub fn encode_line(line: &str, strict: bool) -> Result<(u16, Vec<u8>), String> {
    let frame: MessageFrame =
        jer::from_str_with(line, jer::Options { strict }).map_err(|e| e.to_string())?;
    let bytes = uper::encode_to_vec(&frame).map_err(|e| e.to_string())?;
    Ok((frame.value.id().get(), bytes))
}

/// The output block of one frame, ending in a line break.
fn wrapped(id: u16, frame: &[u8], options: &EncodeOptions) -> Result<String, String> {
    match options.wrap {
        Wrap::None => Ok(to_hex(frame) + "\n"),
        Wrap::Unsecured => {
            let mut out = vec![0; unsecured_encoded_len(frame.len())];
            let n = encode_unsecured(frame, &mut out).map_err(|e| e.to_string())?;
            Ok(to_hex(&out[..n]) + "\n")
        }
        Wrap::Rsu41 => rsu_record(id, frame, options),
    }
}

/// The RSU `Type=` value: `--type` (checked against the frame when it is a known type), or
/// the short name of the frame's message.
fn rsu_type(id: u16, options: &EncodeOptions) -> Result<String, String> {
    let Some(given) = &options.message_type else {
        return messages::by_id(id)
            .map(|m| m.short.to_string())
            .ok_or_else(|| format!("messageId {id} has no RSU message type: give --type"));
    };
    match messages::by_short_name(given) {
        Some(m) if m.id != id => Err(format!(
            "--type {given} is messageId {}, but the frame has messageId {id}",
            m.id
        )),
        _ => Ok(given.clone()),
    }
}

/// One RSU 4.1 text record (`Version=0.7`) around `frame`.
fn rsu_record(id: u16, frame: &[u8], options: &EncodeOptions) -> Result<String, String> {
    let message_type = rsu_type(id, options)?;
    let psid = options
        .psid
        .or_else(|| messages::by_short_name(&message_type).and_then(|m| m.psid))
        .or_else(|| messages::by_id(id).and_then(|m| m.psid))
        .ok_or_else(|| format!("no default PSID for {message_type}: give --psid"))?;
    let mut text = String::new();
    RsuMessage::new(&message_type, psid, RsuPayload::Bytes(frame))
        .write_to(&mut text)
        .map_err(|e| e.to_string())?;
    Ok(text)
}

/// Encodes every non-blank line of `text`; RSU records are separated by a blank line.
pub fn run(text: &str, options: &EncodeOptions, out: &mut dyn Write) -> io::Result<Outcome> {
    let mut outcome = Outcome::AllDone;
    let lines = text.lines().map(str::trim).filter(|l| !l.is_empty());
    for (index, line) in lines.enumerate() {
        if options.wrap == Wrap::Rsu41 && index > 0 {
            writeln!(out)?;
        }
        let block =
            encode_line(line, options.strict).and_then(|(id, frame)| wrapped(id, &frame, options));
        outcome = outcome.and(block.is_ok());
        let block = block.unwrap_or_else(|why| error_line(&why) + "\n");
        out.write_all(block.as_bytes())?;
    }
    Ok(outcome)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::args::Source;

    fn options(wrap: Wrap) -> EncodeOptions {
        EncodeOptions {
            wrap,
            psid: None,
            message_type: None,
            strict: false,
            source: Source::Stdin,
        }
    }

    fn encoded(text: &str, options: &EncodeOptions) -> (String, Outcome) {
        let mut out = Vec::new();
        let outcome = run(text, options, &mut out).unwrap();
        (String::from_utf8(out).unwrap(), outcome)
    }

    #[test]
    fn bad_lines_become_error_lines() {
        let (text, outcome) = encoded("{\"messageId\":31}\n\nnot json\n", &options(Wrap::None));
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(lines.len(), 2, "{text}");
        assert!(
            lines.iter().all(|l| l.starts_with(r#"{"error":"#)),
            "{text}"
        );
        assert_eq!(outcome, Outcome::SomeFailed);
    }

    #[test]
    fn rsu_type_defaults_and_checks() {
        let mut o = options(Wrap::Rsu41);
        assert_eq!(rsu_type(31, &o).unwrap(), "TIM");
        assert!(rsu_type(33, &o).unwrap_err().contains("give --type"));
        o.message_type = Some("MAP".into());
        assert!(rsu_type(31, &o).unwrap_err().contains("messageId 18"));
        o.message_type = Some("CUSTOM".into());
        assert_eq!(rsu_type(31, &o).unwrap(), "CUSTOM");
        let record = rsu_record(31, &[0, 0x1f], &o).unwrap();
        assert!(record.contains("Type=CUSTOM\nPSID=0x8003\n"), "{record}");
        assert!(rsu_record(27, &[0, 0x1b], &options(Wrap::Rsu41))
            .unwrap_err()
            .contains("give --psid"));
    }

    #[test]
    fn strict_rejects_unknown_members_lax_ignores_them() {
        // A BSM MessageFrame whose coreData carries a member BSMcoreData does not have.
        let line = r#"{"messageId":20,"value":{"coreData":{"msgCnt":0,"id":"00000000","secMark":0,"lat":0,"long":0,"elev":0,"accuracy":{"semiMajor":0,"semiMinor":0,"orientation":0},"transmission":"neutral","speed":0,"heading":0,"angle":0,"accelSet":{"long":0,"lat":0,"vert":0,"yaw":0},"brakes":{"wheelBrakes":"00","traction":"unavailable","abs":"unavailable","scs":"unavailable","brakeBoost":"unavailable","auxBrakes":"unavailable"},"size":{"width":0,"length":0},"colour":"red"}}}"#;
        let mut o = options(Wrap::None);
        let (text, outcome) = encoded(line, &o);
        assert_eq!(outcome, Outcome::AllDone, "{text}");
        o.strict = true;
        let (text, outcome) = encoded(line, &o);
        assert_eq!(outcome, Outcome::SomeFailed);
        assert_eq!(
            text,
            "{\"error\":\"unknown member \\\"colour\\\" at value.coreData\"}\n"
        );
    }

    #[test]
    fn unsecured_wrap_prefixes_the_header() {
        let block = wrapped(31, &[0, 0x1f, 1], &options(Wrap::Unsecured)).unwrap();
        assert_eq!(block, "038003001f01\n");
    }
}
