//! `GET /events`: the driver state as Server-Sent Events, and the slots that bound how many
//! clients follow it.
//!
//! A client that stops reading cannot hold a slot for long: its stream ends once it is
//! more events behind than the ring keeps (broadcast lag), its connection is closed once
//! its socket has taken nothing for the stall timeout ([`crate::conn`]), and when every
//! slot is taken a new client gets one at once: the oldest stream of the address holding
//! the most streams is closed for it ([`Slots::take`]). A flood from one device thus
//! evicts its own streams first, never the tablet's only one.

use super::AppState;
use crate::conn::{Closed, Conn};
use crate::counters::group;
use axum::extract::{Extension, State};
use axum::http::HeaderMap;
use axum::response::sse::{Event as SseEvent, KeepAlive, Sse};
use axum::response::{IntoResponse, Response};
use futures_util::stream::{self, Stream, StreamExt};
use std::convert::Infallible;
use std::net::IpAddr;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, Mutex, MutexGuard};
use std::time::Duration;
use tokio::sync::broadcast::error::RecvError;

/// One held slot.
#[derive(Debug)]
struct Held {
    id: u64,
    ip: IpAddr,
    conn: Arc<Conn>,
}

/// The event-stream slots, oldest first.
#[derive(Debug)]
pub struct Slots {
    max: usize,
    held: Mutex<Vec<Held>>,
    next: AtomicU64,
}

/// A client's slot, given back when its stream is dropped.
#[derive(Debug)]
pub struct Slot {
    slots: Arc<Slots>,
    id: u64,
}

impl Drop for Slot {
    fn drop(&mut self) {
        self.slots.lock().retain(|h| h.id != self.id);
    }
}

impl Slots {
    /// At most `max` streams.
    pub fn new(max: usize) -> Arc<Self> {
        Arc::new(Self {
            max,
            held: Mutex::new(Vec::with_capacity(max.min(256))),
            next: AtomicU64::new(1),
        })
    }

    fn lock(&self) -> MutexGuard<'_, Vec<Held>> {
        self.held.lock().unwrap_or_else(|p| p.into_inner())
    }

    /// Streams held now.
    pub fn len(&self) -> usize {
        self.lock().len()
    }

    /// A slot for the stream of `conn`. When all are held, the oldest stream of the
    /// address holding the most (of those, the one whose oldest stream is oldest) gives
    /// its slot up at once and its connection is told to close; it is returned.
    pub fn take(self: &Arc<Self>, conn: Arc<Conn>) -> (Slot, Option<Arc<Conn>>) {
        let ip = conn.peer.ip().to_canonical();
        let id = self.next.fetch_add(1, Ordering::Relaxed);
        let mut held = self.lock();
        let mut evicted = None;
        if held.len() >= self.max {
            let count = |ip: IpAddr| held.iter().filter(|h| h.ip == ip).count();
            // The first (oldest) stream of the address with the most streams.
            let most = held.iter().map(|h| count(h.ip)).max().unwrap_or(0);
            if let Some(i) = held.iter().position(|h| count(h.ip) == most) {
                let victim = held.remove(i);
                victim.conn.close(Closed::Evicted);
                evicted = Some(victim.conn);
            }
        }
        held.push(Held { id, ip, conn });
        drop(held);
        let slot = Slot {
            slots: self.clone(),
            id,
        };
        (slot, evicted)
    }
}

/// `GET /events`.
pub async fn events(
    State(app): State<AppState>,
    Extension(conn): Extension<Arc<Conn>>,
    headers: HeaderMap,
) -> Response {
    let (slot, _evicted) = app.slots.take(conn.clone());
    conn.on_stream();
    app.hub.counters.add(group::SSE_CLIENTS, "connected");
    let last_id = headers
        .get("last-event-id")
        .and_then(|v| v.to_str().ok())
        .and_then(|v| {
            let seq = app.hub.resume_seq(v);
            if seq.is_none() {
                app.hub
                    .counters
                    .add(group::SSE_CLIENTS, "resume id of another run");
            }
            seq
        });
    let heartbeat = app.heartbeat;
    Sse::new(event_stream(app, last_id, slot))
        .keep_alive(KeepAlive::new().interval(heartbeat).text("hb"))
        .into_response()
}

/// The replay after `last_id` (or the newest state for a new client), then live events.
fn event_stream(
    app: AppState,
    last_id: Option<u64>,
    slot: Slot,
) -> impl Stream<Item = Result<SseEvent, Infallible>> {
    let rx = app.hub.subscribe();
    let backlog = match last_id {
        Some(id) => app.hub.since(id),
        None => app.hub.latest().into_iter().collect(),
    };
    let sent = backlog.last().map_or(last_id.unwrap_or(0), |e| e.seq);
    let first: Vec<Result<SseEvent, Infallible>> = backlog
        .iter()
        .map(|e| Ok(to_sse(&app.hub, e).retry(Duration::from_millis(1000))))
        .collect();
    let first = stream::iter(first);
    let hub = app.hub.clone();
    let live = stream::unfold((rx, slot, sent), move |(mut rx, slot, sent)| {
        let hub = hub.clone();
        async move {
            loop {
                match rx.recv().await {
                    Ok(e) if e.seq <= sent => continue,
                    Ok(e) => {
                        let seq = e.seq;
                        return Some((Ok(to_sse(&hub, &e)), (rx, slot, seq)));
                    }
                    Err(RecvError::Lagged(_)) => {
                        hub.counters.add(group::SSE_CLIENTS, "dropped: too slow");
                        return None;
                    }
                    Err(RecvError::Closed) => return None,
                }
            }
        }
    });
    first.chain(live)
}

fn to_sse(hub: &crate::hub::Hub, e: &crate::hub::Event) -> SseEvent {
    SseEvent::default()
        .event("state")
        .id(hub.event_id(e.seq))
        .data(&e.json)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::conn::Table;

    #[test]
    fn a_full_house_evicts_the_oldest_stream_of_the_busiest_address() {
        let table = Table::new(16);
        let at = |s: &str| s.parse().unwrap();
        let local = at("10.0.0.1:80");
        let slots = Slots::new(4);
        let tablet = table.open(at("10.0.0.2:5000"), local);
        let (tablet_slot, none) = slots.take(tablet.conn.clone());
        assert!(none.is_none());
        let flood: Vec<_> = (0..3)
            .map(|i| table.open(at(&format!("10.0.0.66:{}", 6000 + i)), local))
            .collect();
        let mut held: Vec<Slot> = flood
            .iter()
            .map(|e| {
                let (slot, evicted) = slots.take(e.conn.clone());
                assert!(evicted.is_none());
                slot
            })
            .collect();
        assert_eq!(slots.len(), 4);
        // A fifth client: the flooding address's oldest stream goes, not the tablet's.
        let newcomer = table.open(at("10.0.0.66:7000"), local);
        let (slot, evicted) = slots.take(newcomer.conn.clone());
        assert!(Arc::ptr_eq(&evicted.unwrap(), &flood[0].conn));
        assert_eq!(flood[0].conn.closed(), Some(Closed::Evicted));
        assert_eq!(tablet.conn.closed(), None);
        assert_eq!(slots.len(), 4);
        held.push(slot);
        // The evicted stream's slot is already free: dropping its guard later is harmless.
        drop(held.remove(0));
        assert_eq!(slots.len(), 4);
        drop(tablet_slot);
        assert_eq!(slots.len(), 3);
        // With one stream per address, the oldest goes.
        let a = Slots::new(2);
        let one = table.open(at("10.0.0.3:1"), local);
        let two = table.open(at("10.0.0.4:1"), local);
        let three = table.open(at("10.0.0.5:1"), local);
        let _s1 = a.take(one.conn.clone());
        let _s2 = a.take(two.conn.clone());
        let (_s3, evicted) = a.take(three.conn.clone());
        assert!(Arc::ptr_eq(&evicted.unwrap(), &one.conn));
    }
}
