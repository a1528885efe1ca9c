//! `j2735 decode`: UPER MessageFrames to JER, one compact JSON line per frame.

use std::io::{self, Write};

use j2735::{jer, uper, MessageFrame};

use crate::input::Item;
use crate::output::{error_line, Outcome};

/// Decodes one complete MessageFrame (trailing octets are an error).
pub fn decode_frame(bytes: &[u8]) -> Result<MessageFrame, String> {
    uper::decode::<MessageFrame>(bytes).map_err(|e| e.to_string())
}

/// The output line of one input item: its JER, or `{"error": ...}`.
fn line(item: Item) -> (String, bool) {
    match item.and_then(|bytes| decode_frame(&bytes)) {
        Ok(frame) => (jer::to_string(&frame), true),
        Err(why) => (error_line(&why), false),
    }
}

/// Writes one line per item.
pub fn run(items: Vec<Item>, out: &mut dyn Write) -> io::Result<Outcome> {
    let mut outcome = Outcome::AllDone;
    for item in items {
        let (text, ok) = line(item);
        writeln!(out, "{text}")?;
        outcome = outcome.and(ok);
    }
    Ok(outcome)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn decoded(items: Vec<Item>) -> (String, Outcome) {
        let mut out = Vec::new();
        let outcome = run(items, &mut out).unwrap();
        (String::from_utf8(out).unwrap(), outcome)
    }

    #[test]
    fn failures_get_their_own_line() {
        let (text, outcome) = decoded(vec![
            Err("odd number of hex digits on line 1".into()),
            Ok(vec![0, 0x1f]),
        ]);
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(
            lines[0],
            r#"{"error":"odd number of hex digits on line 1"}"#
        );
        assert!(
            lines[1].starts_with(r#"{"error":"unexpected end at bit "#),
            "{}",
            lines[1]
        );
        assert_eq!(outcome, Outcome::SomeFailed);
    }

    #[test]
    fn empty_input_is_no_output() {
        assert_eq!(decoded(Vec::new()), (String::new(), Outcome::AllDone));
    }
}
