//! The zones a roadside publishes, over time: each zone keyed by its TIM `packetID` (a WZDx
//! event's stays the same across feed updates), its `msgCnt` bumped when its content
//! changes, and a cancel (`durationTime` 0, the next `msgCnt`) made for a zone that ended or
//! left its source. The MAP's `revision` follows the MAP's content likewise.

use crate::broadcast::{FrameError, Message};
use crate::messages::{self, BuildError, WorkZone};
use crate::road::Road;
use std::collections::BTreeMap;
use std::fmt;

/// Why a message could not be built.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub enum PublishError {
    /// The MAP or a TIM could not be built or encoded.
    Build(BuildError),
    /// The encoded frame is not one the broadcaster takes.
    Frame(FrameError),
}

impl fmt::Display for PublishError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Build(e) => e.fmt(f),
            Self::Frame(e) => e.fmt(f),
        }
    }
}

impl std::error::Error for PublishError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            Self::Build(e) => Some(e),
            Self::Frame(e) => Some(e),
        }
    }
}

impl From<BuildError> for PublishError {
    fn from(e: BuildError) -> Self {
        Self::Build(e)
    }
}

impl From<FrameError> for PublishError {
    fn from(e: FrameError) -> Self {
        Self::Frame(e)
    }
}

/// A zone as a source gives it, with its delivery window.
#[derive(Debug, Clone, PartialEq)]
pub struct SourceZone {
    /// The zone (its `msg_cnt` is set by the publisher).
    pub zone: WorkZone,
    /// When deposits of its TIM stop (its end, or the site's window), Unix ms.
    pub stop_unix_ms: u64,
}

/// A published message and when RSUs stop sending it.
#[derive(Debug, Clone)]
pub struct Published {
    /// The bare UPER frame.
    pub message: Message,
    /// Delivery stop, Unix ms.
    pub stop_unix_ms: u64,
}

/// What changed at an update.
#[derive(Debug, Clone, Default)]
pub struct Update {
    /// The messages now to publish: the MAP, then a TIM per live zone.
    pub messages: Vec<Published>,
    /// Cancel TIMs of zones that ended or left the source (to send for a while), by the
    /// zone's `packetID`.
    pub cancels: Vec<([u8; 9], Message)>,
    /// The `packetID`s of the live zones.
    pub live: Vec<[u8; 9]>,
    /// Whether the messages differ from the last update's.
    pub changed: bool,
}

/// The publisher's memory between updates.
#[derive(Debug, Clone, Default)]
pub struct Publisher {
    live: BTreeMap<[u8; 9], WorkZone>,
    /// The `msgCnt` of each zone's cancel, so that a zone coming back counts on from it.
    cancelled: BTreeMap<[u8; 9], u8>,
    map_revision: u8,
    map_frame: Option<Vec<u8>>,
    last: Vec<Vec<u8>>,
}

/// Whether two zones say the same thing (all but `msg_cnt`).
fn same(a: &WorkZone, b: &WorkZone) -> bool {
    WorkZone {
        msg_cnt: 0,
        ..a.clone()
    } == WorkZone {
        msg_cnt: 0,
        ..b.clone()
    }
}

impl Publisher {
    /// The messages of `zones` on `road` at `now_unix_ms`: zones whose stop has passed are
    /// cancelled; the MAP goes until the latest stop or `map_stop_unix_ms`.
    ///
    /// # Errors
    ///
    /// [`PublishError`]: a message that cannot be built.
    pub fn update(
        &mut self,
        road: &Road,
        zones: &[SourceZone],
        now_unix_ms: u64,
        map_stop_unix_ms: u64,
    ) -> Result<Update, PublishError> {
        let mut live = BTreeMap::new();
        let mut out = Update::default();
        let mut tims = Vec::new();
        for z in zones.iter().filter(|z| z.stop_unix_ms > now_unix_ms) {
            let mut zone = z.zone.clone();
            zone.msg_cnt = match (
                self.live.get(&zone.packet_id),
                self.cancelled.remove(&zone.packet_id),
            ) {
                (Some(old), _) if same(old, &zone) => old.msg_cnt,
                (Some(old), _) => (old.msg_cnt + 1) % 128,
                (None, Some(cancel)) => (cancel + 1) % 128,
                (None, None) => 1,
            };
            tims.push(Published {
                message: tim_message(road, &zone)?,
                stop_unix_ms: z.stop_unix_ms,
            });
            live.insert(zone.packet_id, zone);
        }
        for (id, old) in &self.live {
            if !live.contains_key(id) {
                let cancel = WorkZone {
                    duration_min: 0,
                    msg_cnt: (old.msg_cnt + 1) % 128,
                    ..old.clone()
                };
                out.cancels.push((*id, tim_message(road, &cancel)?));
                self.cancelled.insert(*id, cancel.msg_cnt);
            }
        }
        let first = live.values().next();
        // The MAP's content (built at revision 0 to compare): when it changes, the
        // revision moves on.
        let content = map_message(road, 0, first)?.frame().to_vec();
        if self.map_frame.as_ref() != Some(&content) {
            self.map_revision = (self.map_revision % 127) + 1;
            self.map_frame = Some(content);
        }
        let map = map_message(road, self.map_revision, first)?;
        let map_stop = tims
            .iter()
            .map(|t| t.stop_unix_ms)
            .fold(map_stop_unix_ms, u64::max);
        out.messages.push(Published {
            message: map,
            stop_unix_ms: map_stop,
        });
        out.messages.extend(tims);
        let frames: Vec<Vec<u8>> = out
            .messages
            .iter()
            .map(|p| p.message.frame().to_vec())
            .collect();
        out.changed = frames != self.last;
        out.live = live.keys().copied().collect();
        self.last = frames;
        self.live = live;
        Ok(out)
    }
}

/// The TIM of `zone`.
fn tim_message(road: &Road, zone: &WorkZone) -> Result<Message, PublishError> {
    let frame = messages::build_tim(road, zone)?;
    Ok(Message::new(messages::encode(&frame)?)?)
}

/// The MAP of `road` at `revision`, with the limit of `zone` on its lanes.
fn map_message(
    road: &Road,
    revision: u8,
    zone: Option<&WorkZone>,
) -> Result<Message, PublishError> {
    let frame = messages::build_map(road, 1, revision, zone)?;
    Ok(Message::new(messages::encode(&frame)?)?)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::clock::Utc;
    use crate::messages::{SignSpeed, DURATION_INDEFINITE};
    use geodesy::LatLon;
    use j2735::msg::message_frame::{MessageFrame, MessageFrameValue};

    fn road() -> Road {
        Road::straight(
            LatLon::from_degrees(39.7392, -104.9903).unwrap(),
            90.0,
            600.0,
            (2, 0),
            3.6,
            40.0,
        )
    }

    fn zone(lane: u8, limit: u16) -> SourceZone {
        SourceZone {
            zone: WorkZone {
                closed_lanes: vec![lane],
                start_m: 300.0,
                end_m: 400.0,
                speed_limit: Some(SignSpeed {
                    value: limit,
                    mph: false,
                }),
                packet_id: *b"EVENT0001",
                msg_cnt: 0,
                start: Utc::from_unix_ms(1_796_390_000_000),
                duration_min: DURATION_INDEFINITE,
            },
            stop_unix_ms: 1_796_400_000_000,
        }
    }

    fn tim_msg_cnt(frame: &[u8]) -> u8 {
        let f: MessageFrame = j2735::uper::decode(frame).unwrap();
        match &f.value {
            MessageFrameValue::TravelerInformation(t) => t.msg_cnt.get(),
            other => panic!("not a TIM: {other:?}"),
        }
    }

    #[test]
    fn msg_cnt_follows_content_and_a_gone_zone_is_cancelled() {
        let now = 1_796_391_000_000;
        let mut p = Publisher::default();
        let a = p
            .update(&road(), &[zone(2, 10)], now, now + 3_600_000)
            .unwrap();
        assert!(a.changed && a.cancels.is_empty());
        assert_eq!(tim_msg_cnt(a.messages[1].message.frame()), 1);
        let same = p
            .update(&road(), &[zone(2, 10)], now + 1000, now + 3_600_000)
            .unwrap();
        assert!(!same.changed);
        let moved = p
            .update(&road(), &[zone(1, 10)], now + 2000, now + 3_600_000)
            .unwrap();
        assert!(moved.changed);
        assert_eq!(tim_msg_cnt(moved.messages[1].message.frame()), 2);
        let gone = p.update(&road(), &[], now + 3000, now + 3_600_000).unwrap();
        assert_eq!(gone.messages.len(), 1);
        assert_eq!(gone.cancels.len(), 1);
        assert_eq!(tim_msg_cnt(gone.cancels[0].1.frame()), 3);
        // It comes back: its count goes on from the cancel's.
        let back = p
            .update(&road(), &[zone(1, 10)], now + 4000, now + 3_600_000)
            .unwrap();
        assert_eq!(back.live, vec![*b"EVENT0001"]);
        assert_eq!(tim_msg_cnt(back.messages[1].message.frame()), 4);
    }

    #[test]
    fn a_zone_past_its_stop_is_cancelled() {
        let now = 1_796_391_000_000;
        let mut p = Publisher::default();
        p.update(&road(), &[zone(2, 10)], now, now).unwrap();
        let ended = p
            .update(&road(), &[zone(2, 10)], 1_796_400_000_001, now)
            .unwrap();
        assert_eq!((ended.messages.len(), ended.cancels.len()), (1, 1));
    }
}
