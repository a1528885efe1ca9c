//! What the test RSU does with its tables: each active, enabled store-and-repeat row's
//! payload goes out over UDP every interval between its delivery start and stop, and each
//! immediate-forward row once per write. A row whose options ask the RSU to process
//! IEEE 1609.2 (0x80) is signed with the RSU's own certificate when it has one.

use super::agent::Agent;
use super::tables::{date_unix_ms, TableId, Val};
use roadside::signer::RsuSigner;
use std::collections::BTreeMap;
use std::net::{SocketAddr, UdpSocket};
use std::time::{Duration, Instant};

/// The test RSU's radio: where it sends, and when each row goes next.
#[derive(Debug)]
pub struct Air {
    socket: UdpSocket,
    destinations: Vec<SocketAddr>,
    signer: Option<RsuSigner>,
    /// (table, index) -> (the payload scheduled, when it goes next).
    next: BTreeMap<(TableId, u32), (Vec<u8>, Instant)>,
    /// Datagrams sent.
    pub sent: u64,
    /// Where first transmissions and the count go (`PID first UNIX_MS LEN`, `PID sent N`).
    log: Option<std::fs::File>,
    logged_sent: u64,
    logged_at: Option<Instant>,
}

/// A row's columns as the air needs them.
struct Repeat<'a> {
    payload: &'a [u8],
    interval_ms: i64,
    start: Option<u64>,
    stop: Option<u64>,
    sign: bool,
}

fn repeat_of(table: TableId, row: &BTreeMap<u32, Val>) -> Option<Repeat<'_>> {
    let int = |c: u32| match row.get(&c) {
        Some(Val::Int(v)) => Some(*v),
        _ => None,
    };
    let octets = |c: u32| match row.get(&c) {
        Some(Val::Octets(o)) => Some(o.as_slice()),
        _ => None,
    };
    // (payload, interval, start, stop, enable, options) columns.
    let (p, i, s, e, en, opt) = match table {
        TableId::MsgRepeat => (7, 4, 5, 6, 8, Some(11)),
        TableId::Srm => (9, 6, 7, 8, 10, None),
        TableId::Ifm => return None,
    };
    if int(en)? != 1 {
        return None;
    }
    Some(Repeat {
        payload: octets(p)?,
        interval_ms: int(i)?,
        start: octets(s).and_then(date_unix_ms),
        stop: octets(e).and_then(date_unix_ms),
        sign: opt
            .and_then(octets)
            .is_some_and(|o| o.first() == Some(&0x80)),
    })
}

impl Air {
    /// A radio sending to `destinations`, signing with `signer` when a row asks.
    ///
    /// # Errors
    ///
    /// The socket cannot be opened.
    pub fn new(
        destinations: Vec<SocketAddr>,
        signer: Option<RsuSigner>,
        log: Option<&std::path::Path>,
    ) -> std::io::Result<Self> {
        let log = match log {
            Some(p) => Some(
                std::fs::OpenOptions::new()
                    .create(true)
                    .append(true)
                    .open(p)?,
            ),
            None => None,
        };
        Ok(Self {
            socket: UdpSocket::bind("127.0.0.1:0")?,
            destinations,
            signer,
            next: BTreeMap::new(),
            sent: 0,
            log,
            logged_sent: 0,
            logged_at: None,
        })
    }

    fn note(&mut self, line: std::fmt::Arguments) {
        use std::io::Write;
        if let Some(f) = &mut self.log {
            let _ = writeln!(f, "{} {line}", std::process::id());
        }
    }

    fn send(&mut self, payload: &[u8], sign: bool, unix_ms: u64) {
        let signed;
        let bytes = match (&self.signer, sign) {
            (Some(s), true) => match s.sign(payload, unix_ms) {
                Ok(b) => {
                    signed = b;
                    &signed
                }
                Err(_) => payload,
            },
            _ => payload,
        };
        for d in &self.destinations {
            if self.socket.send_to(bytes, d).is_ok() {
                self.sent += 1;
            }
        }
    }

    /// Sends what is due at `now` (`unix_ms` on the wall clock).
    pub fn tick(&mut self, agent: &mut Agent, now: Instant, unix_ms: u64) {
        agent.end_quiet_request(now);
        if agent.is_in_request() {
            // A SET request is still being handed over varbind by varbind: the RSU applies
            // a request whole, so nothing of it goes out before it ends.
            return;
        }
        let mut due: Vec<(Vec<u8>, bool)> = Vec::new();
        let mut firsts = Vec::new();
        let mut live = Vec::new();
        for t in &agent.tables {
            for (index, row) in &t.rows {
                if !t.is_active(*index) {
                    continue;
                }
                if t.id == TableId::Ifm {
                    continue;
                }
                let Some(r) = repeat_of(t.id, row) else {
                    continue;
                };
                let in_window =
                    r.start.is_none_or(|s| unix_ms >= s) && r.stop.is_none_or(|e| unix_ms < e);
                if !in_window || r.interval_ms <= 0 {
                    continue;
                }
                let key = (t.id, *index);
                live.push(key);
                let interval = Duration::from_millis(r.interval_ms as u64);
                match self.next.get_mut(&key) {
                    Some((p, at)) if p.as_slice() == r.payload => {
                        if now >= *at {
                            due.push((r.payload.to_vec(), r.sign));
                            // Late ticks do not bunch up: the next one is an interval on.
                            *at = (*at + interval).max(now);
                        }
                    }
                    _ => {
                        due.push((r.payload.to_vec(), r.sign));
                        firsts.push(r.payload.len());
                        self.next.insert(key, (r.payload.to_vec(), now + interval));
                    }
                }
            }
        }
        self.next.retain(|k, _| live.contains(k));
        for index in std::mem::take(&mut agent.forward) {
            let Some(t) = agent.tables.iter().find(|t| t.id == TableId::Ifm) else {
                continue;
            };
            let Some(row) = t.rows.get(&index).filter(|_| t.is_active(index)) else {
                continue;
            };
            let enabled = row.get(&4) == Some(&Val::Int(1));
            if let (true, Some(Val::Octets(p))) = (enabled, row.get(&8)) {
                let sign = row.get(&7) == Some(&Val::Octets(vec![0x80]));
                due.push((p.clone(), sign));
            }
        }
        for len in firsts {
            self.note(format_args!("first {unix_ms} {len}"));
        }
        for (payload, sign) in due {
            if !payload.is_empty() {
                self.send(&payload, sign, unix_ms);
            }
        }
        let second = self
            .logged_at
            .is_none_or(|t| now - t >= Duration::from_secs(1));
        if second && self.sent != self.logged_sent {
            self.logged_sent = self.sent;
            self.logged_at = Some(now);
            let sent = self.sent;
            self.note(format_args!("sent {sent}"));
        }
    }

    /// Writes the count now (the agent is ending).
    pub fn flush_count(&mut self) {
        let sent = self.sent;
        self.note(format_args!("sent {sent}"));
    }
}
