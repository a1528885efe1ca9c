//! The UDP [`Broadcaster`]: ticks on a fixed time grid, with faults injected and counted.

use super::config::ConfigError;
use super::faults::{DropReason, FaultInjector, Faults, Verdict};
use super::message::{Message, MessageSlot, Wrapping};
use super::{DEFAULT_RATE_HZ, MAX_RATE_HZ};
use std::net::{Ipv4Addr, Ipv6Addr, SocketAddr, UdpSocket};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};
use std::{fmt, io};

/// How long a run loop sleeps at most before it looks at its stop flag again.
const STOP_POLL: Duration = Duration::from_millis(20);

/// What a [`Broadcaster`] has done so far.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct BroadcastStats {
    /// Ticks run.
    pub ticks: u64,
    /// Datagrams the socket accepted (corrupted ones included).
    pub sent: u64,
    /// Datagrams the socket refused.
    pub send_errors: u64,
    /// Datagrams the loss model dropped.
    pub dropped: u64,
    /// Datagrams sent with a flipped bit.
    pub corrupted: u64,
    /// TIM datagrams held back before [`Faults::tim_not_before`].
    pub tim_held: u64,
    /// Ticks skipped because a run loop fell more than a period behind.
    pub missed_ticks: u64,
    /// The kind of the last send error.
    pub last_error: Option<io::ErrorKind>,
}

/// Sends MAP and TIM over UDP at a fixed rate (see the [module docs](super)).
#[derive(Debug)]
pub struct Broadcaster {
    socket: UdpSocket,
    destinations: Vec<SocketAddr>,
    wrapping: Wrapping,
    messages: MessageSlot,
    period: Duration,
    faults: FaultInjector,
    stats: BroadcastStats,
    datagram: Vec<u8>,
    /// Signs every frame (IEEE 1609.2 signed data) instead of `wrapping`, when set.
    signer: Option<Arc<crate::signer::RsuSigner>>,
}

impl Broadcaster {
    /// A broadcaster on a new socket (any local port, on the unspecified address of the
    /// destinations' family; broadcast allowed on IPv4), sending nothing until
    /// [`Broadcaster::set_messages`].
    ///
    /// # Errors
    ///
    /// `InvalidInput` for no destination or a mix of IPv4 and IPv6 destinations; the
    /// socket's error when it cannot be bound.
    pub fn new(destinations: Vec<SocketAddr>, wrapping: Wrapping) -> io::Result<Self> {
        let first = destinations
            .first()
            .ok_or_else(|| invalid_input("no destination"))?;
        let bind: SocketAddr = if first.is_ipv4() {
            (Ipv4Addr::UNSPECIFIED, 0).into()
        } else {
            (Ipv6Addr::UNSPECIFIED, 0).into()
        };
        let socket = UdpSocket::bind(bind)?;
        if first.is_ipv4() {
            socket.set_broadcast(true)?;
        }
        Self::with_socket(socket, destinations, wrapping)
    }

    /// A broadcaster on `socket`.
    ///
    /// # Errors
    ///
    /// `InvalidInput` for no destination or one of another address family than the socket.
    pub fn with_socket(
        socket: UdpSocket,
        destinations: Vec<SocketAddr>,
        wrapping: Wrapping,
    ) -> io::Result<Self> {
        check_destinations(&socket, &destinations)?;
        Ok(Self {
            socket,
            destinations,
            wrapping,
            messages: MessageSlot::default(),
            period: period_of(DEFAULT_RATE_HZ),
            faults: FaultInjector::new(Faults::default()).map_err(invalid_input)?,
            stats: BroadcastStats::default(),
            datagram: Vec::new(),
            signer: None,
        })
    }

    /// The socket's local address.
    ///
    /// # Errors
    ///
    /// The socket's error.
    pub fn local_addr(&self) -> io::Result<SocketAddr> {
        self.socket.local_addr()
    }

    /// The destinations.
    pub fn destinations(&self) -> &[SocketAddr] {
        &self.destinations
    }

    /// Replaces the destinations.
    ///
    /// # Errors
    ///
    /// As [`Broadcaster::with_socket`]; the destinations are unchanged then.
    pub fn set_destinations(&mut self, destinations: Vec<SocketAddr>) -> io::Result<()> {
        check_destinations(&self.socket, &destinations)?;
        self.destinations = destinations;
        Ok(())
    }

    /// How frames go on the wire.
    pub fn wrapping(&self) -> Wrapping {
        self.wrapping
    }

    /// Sets how frames go on the wire.
    pub fn set_wrapping(&mut self, wrapping: Wrapping) {
        self.wrapping = wrapping;
    }

    /// Replaces the messages (also while another thread runs the broadcaster, through
    /// [`Broadcaster::message_slot`]); the next tick sends them.
    pub fn set_messages(&self, messages: Vec<Message>) {
        self.messages.set(messages);
    }

    /// The messages sent on each tick.
    pub fn messages(&self) -> Arc<Vec<Message>> {
        self.messages.get()
    }

    /// The shared slot of the messages, for another thread to replace them.
    pub fn message_slot(&self) -> MessageSlot {
        self.messages.clone()
    }

    /// The rate, Hz.
    pub fn rate_hz(&self) -> f64 {
        1.0 / self.period.as_secs_f64()
    }

    /// Sets the rate.
    ///
    /// # Errors
    ///
    /// [`ConfigError::Rate`] unless 0 < `hz` <= [`MAX_RATE_HZ`].
    pub fn set_rate_hz(&mut self, hz: f64) -> Result<(), ConfigError> {
        if hz.is_nan() || hz <= 0.0 || hz > MAX_RATE_HZ {
            return Err(ConfigError::Rate { hz });
        }
        self.period = period_of(hz);
        Ok(())
    }

    /// Sets the faults (the random streams restart from their seed).
    ///
    /// # Errors
    ///
    /// [`ConfigError`] from [`Faults::validate`]; the faults are unchanged then.
    pub fn set_faults(&mut self, faults: Faults) -> Result<(), ConfigError> {
        self.faults = FaultInjector::new(faults)?;
        Ok(())
    }

    /// The faults injected.
    pub fn faults(&self) -> &Faults {
        self.faults.faults()
    }

    /// What has been done so far.
    pub fn stats(&self) -> BroadcastStats {
        self.stats
    }

    /// Signs every message with `signer` (IEEE 1609.2 signed data, generated at the send
    /// time) instead of wrapping it; `None`: back to the wrapping.
    pub fn set_signer(&mut self, signer: Option<Arc<crate::signer::RsuSigner>>) {
        self.signer = signer;
    }

    /// Sends every message once to every destination, now.
    pub fn tick(&mut self) {
        self.tick_at(Instant::now());
    }

    /// Sends every message once to every destination, with the faults as at `now`.
    pub fn tick_at(&mut self, now: Instant) {
        self.stats.ticks += 1;
        let messages = self.messages.get();
        for message in messages.iter() {
            for (k, destination) in self.destinations.iter().enumerate() {
                match &self.signer {
                    Some(signer) => {
                        match signer.sign(message.frame(), crate::clock::unix_ms_now()) {
                            Ok(bytes) => self.datagram = bytes,
                            Err(_) => {
                                self.stats.send_errors += 1;
                                continue;
                            }
                        }
                    }
                    None => self.wrapping.wrap_into(message.frame(), &mut self.datagram),
                }
                let verdict = self
                    .faults
                    .decide(k, message.kind(), now, &mut self.datagram);
                match verdict {
                    Verdict::Drop(DropReason::Loss) => self.stats.dropped += 1,
                    Verdict::Drop(DropReason::TimHeld) => self.stats.tim_held += 1,
                    Verdict::Send | Verdict::Corrupted { .. } => {
                        if matches!(verdict, Verdict::Corrupted { .. }) {
                            self.stats.corrupted += 1;
                        }
                        match self.socket.send_to(&self.datagram, destination) {
                            Ok(_) => self.stats.sent += 1,
                            Err(e) => {
                                self.stats.send_errors += 1;
                                self.stats.last_error = Some(e.kind());
                            }
                        }
                    }
                }
            }
        }
    }

    /// Ticks at the rate for `duration` (the first tick at once, then every period on a
    /// fixed grid) and returns when it is over; returns the ticks run.
    pub fn run_for(&mut self, duration: Duration) -> u64 {
        let start = Instant::now();
        let end = start.checked_add(duration);
        let ticks = self.run_loop(start, end, None);
        if let Some(left) = end.and_then(|e| e.checked_duration_since(Instant::now())) {
            std::thread::sleep(left);
        }
        ticks
    }

    /// Ticks at the rate until `stop` is set (looked at at least every 20 ms); returns the
    /// ticks run.
    pub fn run_until(&mut self, stop: &AtomicBool) -> u64 {
        self.run_loop(Instant::now(), None, Some(stop))
    }

    /// The run loop: tick times are `start + k * period`, so the rate does not drift; a
    /// loop that falls more than a period behind skips the missed ticks (counted) instead
    /// of sending a burst.
    fn run_loop(&mut self, start: Instant, end: Option<Instant>, stop: Option<&AtomicBool>) -> u64 {
        let mut next = start;
        let mut ticks = 0;
        loop {
            if stop.is_some_and(|s| s.load(Ordering::Acquire)) || end.is_some_and(|e| next >= e) {
                return ticks;
            }
            let now = Instant::now();
            if let Some(wait) = next.checked_duration_since(now).filter(|w| !w.is_zero()) {
                std::thread::sleep(wait.min(STOP_POLL));
                continue;
            }
            self.tick_at(now);
            ticks += 1;
            let Some(after) = self.next_slot(next, end) else {
                return ticks;
            };
            next = after;
        }
    }

    /// The tick time after `slot`: one period later, or the first slot of the grid that is
    /// not yet more than a period past when the loop is late. The slots skipped count as
    /// missed, those before the run's `end` only (a loop late at its end missed no tick of
    /// the run beyond it).
    fn next_slot(&mut self, slot: Instant, end: Option<Instant>) -> Option<Instant> {
        let next = slot.checked_add(self.period)?;
        let Some(late) = Instant::now().checked_duration_since(next) else {
            return Some(next);
        };
        let period_ns = self.period.as_nanos().max(1);
        let missed = u32::try_from(late.as_nanos() / period_ns).unwrap_or(u32::MAX);
        if missed == 0 {
            return Some(next);
        }
        // Slots next, next + period, ... before `end`: ceil((end - next) / period).
        let in_run = end.map_or(u128::MAX, |e| {
            e.saturating_duration_since(next)
                .as_nanos()
                .div_ceil(period_ns)
        });
        self.stats.missed_ticks += u64::try_from(in_run.min(u128::from(missed))).unwrap_or(0);
        next.checked_add(self.period.checked_mul(missed)?)
    }
}

/// Refuses no destinations, or destinations of another family than the socket.
fn check_destinations(socket: &UdpSocket, destinations: &[SocketAddr]) -> io::Result<()> {
    if destinations.is_empty() {
        return Err(invalid_input("no destination"));
    }
    let local = socket.local_addr()?;
    match destinations.iter().find(|d| d.is_ipv4() != local.is_ipv4()) {
        Some(d) => Err(invalid_input(format!(
            "destination {d} is not of the socket's address family ({local})"
        ))),
        None => Ok(()),
    }
}

/// The period of a rate (checked by the caller).
fn period_of(hz: f64) -> Duration {
    Duration::from_secs_f64(1.0 / hz)
}

/// An `InvalidInput` I/O error.
fn invalid_input(what: impl fmt::Display) -> io::Error {
    io::Error::new(io::ErrorKind::InvalidInput, what.to_string())
}
