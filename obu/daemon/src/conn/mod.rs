//! Open HTTP connections: what each one is doing, when it must be closed, and the table
//! that caps how many are open.
//!
//! A connection is in one of three phases: idle (accepted, or between requests on a
//! kept-alive connection), in a request (from the first octet of the request until its
//! answer has been taken) or streaming events. Each phase has one deadline
//! ([`Conn::deadline`]): idle ones are closed after the idle timeout; a request must be
//! read, answered and its answer taken within the request deadline (so a client sending its
//! head or body one octet at a time is cut); an event stream is cut only when its client
//! has stopped taking data (the socket would block) for the stall timeout. The
//! connection's task ([`crate::serve`]) sleeps until that deadline and is woken when the
//! phase moves it or when the connection is told to close ([`Conn::close`]).
//!
//! The [`Table`] holds every open connection. Over its cap, a new connection closes the
//! one that has been idle or in its request the longest ([`Table::shed_oldest`]); event
//! streams are never shed (their number has its own cap, see [`crate::http::events`]), so
//! `/healthz` and `/events` keep answering whatever a client holds open.

pub mod io;

use std::collections::HashMap;
use std::net::SocketAddr;
use std::sync::atomic::{AtomicU64, AtomicU8, Ordering};
use std::sync::{Arc, Mutex, MutexGuard};
use std::time::{Duration, Instant};
use tokio::sync::Notify;

/// What a connection is doing.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Phase {
    /// No request under way.
    Idle = 0,
    /// A request is being read or answered.
    Request = 1,
    /// An event stream is being sent.
    Streaming = 2,
}

impl Phase {
    fn from_u8(v: u8) -> Phase {
        match v {
            1 => Phase::Request,
            2 => Phase::Streaming,
            _ => Phase::Idle,
        }
    }
}

/// Why a connection's deadline passed (each is counted under its own reason by
/// [`crate::serve`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Expiry {
    /// Idle for the idle timeout: a normal close, not a refusal.
    Idle,
    /// A request not read, answered and taken within the request deadline.
    RequestDeadline,
    /// Between requests, an answer the client did not take within the request deadline.
    AnswerNotTaken,
    /// An event stream whose client took no data for the stall timeout.
    StreamStalled,
}

/// Why a connection was told to close from outside its task.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Closed {
    /// Shed to make room under the connection cap.
    Shed = 1,
    /// Its event-stream slot was given to a new client.
    Evicted = 2,
    /// Shed because the process ran out of file descriptors.
    ShedForDescriptors = 3,
}

/// The timeouts of [`Conn::deadline`].
#[derive(Clone, Copy, Debug)]
pub struct Limits {
    /// Whole request: head, body and the answer taken.
    pub request: Duration,
    /// Between requests.
    pub idle: Duration,
    /// An event stream whose writes block.
    pub stall: Duration,
}

/// One open connection, shared by its task, its I/O ([`io::WatchedIo`]) and the handlers.
#[derive(Debug)]
pub struct Conn {
    id: u64,
    /// Where the client is.
    pub peer: SocketAddr,
    /// The local address the client reached.
    pub local: SocketAddr,
    epoch: Instant,
    phase: AtomicU8,
    /// When the phase began, milliseconds since `epoch`.
    since_ms: AtomicU64,
    /// When writes began to block, milliseconds since `epoch` plus one; 0: they do not.
    blocked_ms: AtomicU64,
    closed: AtomicU8,
    wake: Notify,
}

impl Conn {
    fn new(id: u64, peer: SocketAddr, local: SocketAddr, epoch: Instant) -> Self {
        let conn = Self {
            id,
            peer,
            local,
            epoch,
            phase: AtomicU8::new(Phase::Idle as u8),
            since_ms: AtomicU64::new(0),
            blocked_ms: AtomicU64::new(0),
            closed: AtomicU8::new(0),
            wake: Notify::new(),
        };
        conn.since_ms.store(conn.now_ms(), Ordering::Relaxed);
        conn
    }

    fn now_ms(&self) -> u64 {
        self.epoch.elapsed().as_millis() as u64
    }

    fn at(&self, ms: u64) -> Instant {
        self.epoch + Duration::from_millis(ms)
    }

    /// The current phase.
    pub fn phase(&self) -> Phase {
        Phase::from_u8(self.phase.load(Ordering::Relaxed))
    }

    fn enter(&self, phase: Phase) {
        self.since_ms.store(self.now_ms(), Ordering::Relaxed);
        self.phase.store(phase as u8, Ordering::Relaxed);
        self.wake.notify_one();
    }

    /// Octets arrived: an idle connection begins a request (its deadline starts now).
    pub fn on_read(&self) {
        if self.phase() == Phase::Idle {
            self.enter(Phase::Request);
        }
    }

    /// The head of a request was read (a pipelined request may not have moved the phase).
    pub fn on_request(&self) {
        if self.phase() != Phase::Request {
            self.enter(Phase::Request);
        }
    }

    /// The answer is an event stream.
    pub fn on_stream(&self) {
        self.enter(Phase::Streaming);
    }

    /// The answer's body was handed over whole (or dropped): idle again.
    pub fn on_answered(&self) {
        if self.phase() != Phase::Idle {
            self.enter(Phase::Idle);
        }
    }

    /// A write would block (the client does not take data).
    pub fn on_write_blocked(&self) {
        if self.blocked_ms.load(Ordering::Relaxed) == 0 {
            self.blocked_ms.store(self.now_ms() + 1, Ordering::Relaxed);
            self.wake.notify_one();
        }
    }

    /// A write went through.
    pub fn on_write_done(&self) {
        self.blocked_ms.store(0, Ordering::Relaxed);
    }

    /// When this connection must be closed, and why; `None`: not before something changes.
    pub fn deadline(&self, limits: &Limits) -> Option<(Instant, Expiry)> {
        let since = self.at(self.since_ms.load(Ordering::Relaxed));
        let blocked = match self.blocked_ms.load(Ordering::Relaxed) {
            0 => None,
            ms => Some(self.at(ms - 1)),
        };
        match (self.phase(), blocked) {
            (Phase::Idle, None) => Some((since + limits.idle, Expiry::Idle)),
            (Phase::Idle, Some(b)) => Some((b + limits.request, Expiry::AnswerNotTaken)),
            (Phase::Request, _) => Some((since + limits.request, Expiry::RequestDeadline)),
            (Phase::Streaming, b) => b.map(|b| (b + limits.stall, Expiry::StreamStalled)),
        }
    }

    /// Tells the connection's task to close it (the first reason given stays).
    pub fn close(&self, why: Closed) {
        let _ = self
            .closed
            .compare_exchange(0, why as u8, Ordering::Relaxed, Ordering::Relaxed);
        self.wake.notify_one();
    }

    /// Why the connection was told to close, if it was.
    pub fn closed(&self) -> Option<Closed> {
        match self.closed.load(Ordering::Relaxed) {
            1 => Some(Closed::Shed),
            2 => Some(Closed::Evicted),
            3 => Some(Closed::ShedForDescriptors),
            _ => None,
        }
    }

    /// Waits until the phase moved, a write blocked, or the connection was told to close.
    pub async fn changed(&self) {
        self.wake.notified().await;
    }
}

/// Every open connection, up to a cap.
#[derive(Debug)]
pub struct Table {
    conns: Mutex<HashMap<u64, Arc<Conn>>>,
    next_id: AtomicU64,
    cap: usize,
    epoch: Instant,
}

/// A connection's place in the [`Table`], given up when dropped.
#[derive(Debug)]
pub struct Entry {
    table: Arc<Table>,
    /// The connection.
    pub conn: Arc<Conn>,
}

impl Drop for Entry {
    fn drop(&mut self) {
        self.table.lock().remove(&self.conn.id);
    }
}

impl Table {
    /// A table of at most `cap` connections.
    pub fn new(cap: usize) -> Arc<Self> {
        Arc::new(Self {
            conns: Mutex::new(HashMap::with_capacity(cap.min(1024) + 1)),
            next_id: AtomicU64::new(1),
            cap,
            epoch: Instant::now(),
        })
    }

    fn lock(&self) -> MutexGuard<'_, HashMap<u64, Arc<Conn>>> {
        self.conns.lock().unwrap_or_else(|p| p.into_inner())
    }

    /// Connections open now.
    pub fn len(&self) -> usize {
        self.lock().len()
    }

    /// Whether a new connection needs room made first.
    pub fn full(&self) -> bool {
        self.len() >= self.cap
    }

    /// Registers a new connection.
    pub fn open(self: &Arc<Self>, peer: SocketAddr, local: SocketAddr) -> Entry {
        let id = self.next_id.fetch_add(1, Ordering::Relaxed);
        let conn = Arc::new(Conn::new(id, peer, local, self.epoch));
        self.lock().insert(id, conn.clone());
        Entry {
            table: self.clone(),
            conn,
        }
    }

    /// Tells the connection idle or in its request the longest (and not already told) to
    /// close, for `why`; `false` when there is none (every one streams events).
    pub fn shed_oldest(&self, why: Closed) -> bool {
        let victim = self
            .lock()
            .values()
            .filter(|c| c.phase() != Phase::Streaming && c.closed().is_none())
            .min_by_key(|c| (c.since_ms.load(Ordering::Relaxed), c.id))
            .cloned();
        match victim {
            Some(c) => {
                c.close(why);
                true
            }
            None => false,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const LIMITS: Limits = Limits {
        request: Duration::from_millis(5000),
        idle: Duration::from_millis(30_000),
        stall: Duration::from_millis(2000),
    };

    fn addr() -> SocketAddr {
        "127.0.0.1:1".parse().unwrap()
    }

    #[test]
    fn each_phase_has_its_deadline() {
        let table = Table::new(4);
        let e = table.open(addr(), addr());
        let c = &e.conn;
        let t0 = Instant::now();
        let (at, why) = c.deadline(&LIMITS).unwrap();
        assert_eq!(why, Expiry::Idle);
        assert!(at >= t0 + LIMITS.idle - Duration::from_millis(50));
        c.on_read();
        assert_eq!(c.phase(), Phase::Request);
        let (at, why) = c.deadline(&LIMITS).unwrap();
        assert_eq!(why, Expiry::RequestDeadline);
        assert!(at <= Instant::now() + LIMITS.request);
        // More octets of the same request do not move its deadline.
        std::thread::sleep(Duration::from_millis(20));
        c.on_read();
        assert_eq!(c.deadline(&LIMITS).unwrap().0, at);
        c.on_stream();
        assert_eq!(
            c.deadline(&LIMITS),
            None,
            "a stream that takes data has none"
        );
        c.on_write_blocked();
        assert_eq!(c.deadline(&LIMITS).unwrap().1, Expiry::StreamStalled);
        c.on_write_done();
        assert_eq!(c.deadline(&LIMITS), None);
        c.on_answered();
        assert_eq!(c.deadline(&LIMITS).unwrap().1, Expiry::Idle);
        c.on_write_blocked();
        assert_eq!(c.deadline(&LIMITS).unwrap().1, Expiry::AnswerNotTaken);
    }

    #[test]
    fn the_oldest_idle_or_requesting_connection_is_shed_never_a_stream() {
        let table = Table::new(3);
        let streaming = table.open(addr(), addr());
        streaming.conn.on_stream();
        std::thread::sleep(Duration::from_millis(5));
        let old = table.open(addr(), addr());
        std::thread::sleep(Duration::from_millis(5));
        let young = table.open(addr(), addr());
        assert!(table.full());
        assert!(table.shed_oldest(Closed::Shed));
        assert_eq!(old.conn.closed(), Some(Closed::Shed));
        assert_eq!(young.conn.closed(), None);
        assert_eq!(streaming.conn.closed(), None);
        assert!(
            table.shed_oldest(Closed::Shed),
            "the next one, not the same again"
        );
        assert_eq!(young.conn.closed(), Some(Closed::Shed));
        assert!(
            !table.shed_oldest(Closed::ShedForDescriptors),
            "only a stream is left"
        );
        drop((old, young));
        assert_eq!(table.len(), 1);
        assert!(!table.full());
    }

    #[tokio::test]
    async fn a_close_wakes_the_task_and_keeps_its_first_reason() {
        let table = Table::new(2);
        let e = table.open(addr(), addr());
        let c = e.conn.clone();
        let waiter = tokio::spawn(async move { c.changed().await });
        e.conn.close(Closed::Evicted);
        e.conn.close(Closed::Shed);
        tokio::time::timeout(Duration::from_secs(1), waiter)
            .await
            .expect("woken")
            .unwrap();
        assert_eq!(e.conn.closed(), Some(Closed::Evicted));
    }
}
