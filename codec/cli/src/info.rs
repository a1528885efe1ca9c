//! `j2735 info`: a short human summary of each frame. MAP and TIM get their content (see
//! [`map`] and [`tim`]); other messages their type and size.

mod map;
mod tim;

use std::io::{self, Write};

use j2735::msg::common::{Latitude, Longitude, Position3D};
use j2735::{MessageFrame, MessageFrameValue};

use crate::decode::decode_frame;
use crate::input::Item;
use crate::messages;
use crate::output::Outcome;

/// Writes the summary of every item (`frame <n>: ...`), or its error.
pub fn run(items: Vec<Item>, out: &mut dyn Write) -> io::Result<Outcome> {
    let mut outcome = Outcome::AllDone;
    for (index, item) in items.into_iter().enumerate() {
        let n = index + 1;
        let decoded = item.and_then(|bytes| decode_frame(&bytes).map(|f| (bytes.len(), f)));
        outcome = outcome.and(decoded.is_ok());
        let lines = match decoded {
            Ok((size, frame)) => summary(n, size, &frame),
            Err(why) => vec![format!("frame {n}: error: {why}")],
        };
        for line in lines {
            writeln!(out, "{line}")?;
        }
    }
    Ok(outcome)
}

/// The summary lines of one decoded frame of `size` octets.
pub fn summary(n: usize, size: usize, frame: &MessageFrame) -> Vec<String> {
    let id = frame.value.id().get();
    let name = match messages::by_id(id) {
        Some(m) if m.short == m.type_name => m.short.to_string(),
        Some(m) => format!("{} {}", m.short, m.type_name),
        None => "unknown message".to_string(),
    };
    let mut lines = vec![format!("frame {n}: {name} (messageId {id}), {size} octets")];
    match &frame.value {
        MessageFrameValue::MapData(map) => lines.extend(map::lines(map)),
        MessageFrameValue::TravelerInformation(tim) => lines.extend(tim::lines(tim)),
        _ => {}
    }
    lines
}

/// `42.3061820, -83.0651370` (1e-7 degrees), or `unavailable` for the sentinels.
fn position(p: &Position3D) -> String {
    if p.lat == Latitude::UNAVAILABLE || p.long == Longitude::UNAVAILABLE {
        return "unavailable position".to_string();
    }
    let degrees = |v: i32| f64::from(v) * 1e-7;
    format!("{:.7}, {:.7}", degrees(p.lat.get()), degrees(p.long.get()))
}

/// An ENUMERATED identifier, or a note for a value added after J2735 2020.
fn identifier(text: &'static str) -> &'static str {
    if text.is_empty() {
        "(extension value)"
    } else {
        text
    }
}

/// `n thing` or `n things`.
fn count(n: usize, thing: &str) -> String {
    if n == 1 {
        format!("1 {thing}")
    } else {
        format!("{n} {thing}s")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn plural_and_positions() {
        assert_eq!(count(1, "lane"), "1 lane");
        assert_eq!(count(3, "lane"), "3 lanes");
        assert_eq!(identifier(""), "(extension value)");
    }

    #[test]
    fn other_messages_show_type_and_size() {
        // A BSM-free check: an unknown messageId (RSM, 33) decodes as an unknown message.
        let frame = decode_frame(&[0x00, 0x21, 0x01, 0x00]).unwrap();
        assert_eq!(
            summary(2, 4, &frame),
            vec!["frame 2: unknown message (messageId 33), 4 octets".to_string()]
        );
    }
}
