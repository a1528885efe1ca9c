//! TIM content (ITIS codes and text of every content kind) -> [`ZoneInfo`].

use j2735::msg::itis::ITIScodesAndTextItemItem;
use j2735::msg::traveler_information::{
    ExitServiceItemItem, GenericSignageItemItem, SpeedLimitItemItem, TravelerDataFrameContent,
    WorkZoneItemItem,
};

use crate::zone::{ContentKind, ZoneInfo};

/// One content item: an ITIS code or a text phrase.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Item<'a> {
    /// An ITIS code.
    Itis(u16),
    /// A text phrase.
    Text(&'a str),
}

/// The content of a data frame: its kind and every item, in order (see
/// [`ZoneInfo::push_itis`] and [`ZoneInfo::push_text`] for what is read from them).
pub fn content(c: &TravelerDataFrameContent) -> ZoneInfo {
    let mut info = ZoneInfo::new(kind(c));
    for_each_item(c, |item| match item {
        Item::Itis(code) => info.push_itis(code),
        Item::Text(t) => info.push_text(t),
    });
    info
}

/// The content kind.
pub fn kind(c: &TravelerDataFrameContent) -> ContentKind {
    match c {
        TravelerDataFrameContent::Advisory(_) => ContentKind::Advisory,
        TravelerDataFrameContent::WorkZone(_) => ContentKind::WorkZone,
        TravelerDataFrameContent::GenericSign(_) => ContentKind::GenericSign,
        TravelerDataFrameContent::SpeedLimit(_) => ContentKind::SpeedLimit,
        TravelerDataFrameContent::ExitService(_) => ContentKind::ExitService,
    }
}

/// Calls `f` with every item of the content, whatever its kind.
pub fn for_each_item<'a>(c: &'a TravelerDataFrameContent, mut f: impl FnMut(Item<'a>)) {
    match c {
        TravelerDataFrameContent::Advisory(l) => l.iter().for_each(|i| f(advisory(&i.item))),
        TravelerDataFrameContent::WorkZone(l) => l.iter().for_each(|i| f(work_zone(&i.item))),
        TravelerDataFrameContent::GenericSign(l) => l.iter().for_each(|i| f(generic(&i.item))),
        TravelerDataFrameContent::SpeedLimit(l) => l.iter().for_each(|i| f(speed(&i.item))),
        TravelerDataFrameContent::ExitService(l) => l.iter().for_each(|i| f(exit(&i.item))),
    }
}

fn advisory(i: &ITIScodesAndTextItemItem) -> Item<'_> {
    match i {
        ITIScodesAndTextItemItem::Itis(c) => Item::Itis(c.get()),
        ITIScodesAndTextItemItem::Text(t) => Item::Text(t.0.as_str()),
    }
}

fn work_zone(i: &WorkZoneItemItem) -> Item<'_> {
    match i {
        WorkZoneItemItem::Itis(c) => Item::Itis(c.get()),
        WorkZoneItemItem::Text(t) => Item::Text(t.0.as_str()),
    }
}

fn generic(i: &GenericSignageItemItem) -> Item<'_> {
    match i {
        GenericSignageItemItem::Itis(c) => Item::Itis(c.get()),
        GenericSignageItemItem::Text(t) => Item::Text(t.0.as_str()),
    }
}

fn speed(i: &SpeedLimitItemItem) -> Item<'_> {
    match i {
        SpeedLimitItemItem::Itis(c) => Item::Itis(c.get()),
        SpeedLimitItemItem::Text(t) => Item::Text(t.0.as_str()),
    }
}

fn exit(i: &ExitServiceItemItem) -> Item<'_> {
    match i {
        ExitServiceItemItem::Itis(c) => Item::Itis(c.get()),
        ExitServiceItemItem::Text(t) => Item::Text(t.0.as_str()),
    }
}
