//! The roadside unit's broadcast: MAP and TIM frames sent over UDP at a fixed rate, bare or
//! in IEEE 1609.2 unsecured data, with seeded fault injection for the bench, and the
//! RSU 4.1 text records that make a real roadside unit send the same messages.
//!
//! - [`Broadcaster`]: a UDP socket, its destinations, the [`Wrapping`] and the
//!   [`Message`]s; [`Broadcaster::tick`] sends every message once to every destination,
//!   [`Broadcaster::run_for`] / [`Broadcaster::run_until`] tick at the rate (10 Hz by
//!   default) on a fixed time grid, so the rate does not drift. A lost datagram is not
//!   retried; the next tick sends the message again.
//! - [`FaultInjector`]: what a bench does to the air, seeded and counted: packet loss
//!   ([`LossModel`]: independent, or Gilbert-Elliott bursts), bit flips, and holding the
//!   TIM back until a given time. It is sans-IO: a scenario runner that hands frames to an
//!   OBU core directly uses it without sockets.
//! - [`rsu_record`] / [`write_rsu_files`]: `Version=0.7` store-and-repeat or
//!   immediate-forward records written with the codec's RSU text writer.

use crate::clock::Utc;
use j2735::envelope::ieee1609dot2::{
    encode_unsecured, looks_like_ieee1609dot2, unsecured_encoded_len,
};
use j2735::envelope::rsu_text::{RsuMessage, RsuPayload, RsuWriteError};
pub use j2735::envelope::rsu_text::{TxChannel, TxMode};
use std::net::{Ipv4Addr, Ipv6Addr, SocketAddr, UdpSocket};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex, PoisonError};
use std::time::{Duration, Instant};
use std::{fmt, fs, io};

/// Broadcast rate of MAP and TIM unless set otherwise, Hz.
pub const DEFAULT_RATE_HZ: f64 = 10.0;
/// Highest broadcast rate accepted, Hz.
pub const MAX_RATE_HZ: f64 = 1000.0;
/// How long a run loop sleeps at most before it looks at its stop flag again.
const STOP_POLL: Duration = Duration::from_millis(20);

// ---------------------------------------------------------------------------------------
// Messages

/// The J2735 message a frame carries, from its `messageId`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum MessageKind {
    /// MapData (18).
    Map,
    /// SPaT (19).
    Spat,
    /// TravelerInformation (31).
    Tim,
    /// Any other message id.
    Other(u16),
}

impl MessageKind {
    /// The kind of message id `id`.
    pub const fn from_id(id: u16) -> Self {
        match id {
            18 => Self::Map,
            19 => Self::Spat,
            31 => Self::Tim,
            other => Self::Other(other),
        }
    }

    /// The J2735 `messageId`.
    pub const fn id(self) -> u16 {
        match self {
            Self::Map => 18,
            Self::Spat => 19,
            Self::Tim => 31,
            Self::Other(id) => id,
        }
    }

    /// The kind of a UPER `MessageFrame`: its first 16 bits are the extension bit (0) and
    /// the 15-bit `messageId` (`00 12` MAP, `00 1f` TIM). `None` for fewer than 2 bytes or
    /// a set extension bit.
    pub fn of_frame(frame: &[u8]) -> Option<Self> {
        match frame {
            [hi, lo, ..] if hi & 0x80 == 0 => Some(Self::from_id(u16::from_be_bytes([*hi, *lo]))),
            _ => None,
        }
    }

    /// The RSU record `Type` (`MAP`, `SPAT`, `TIM`, `BSM`, `RSA`, `PSM`), if it has one.
    pub const fn rsu_type(self) -> Option<&'static str> {
        match self {
            Self::Map => Some("MAP"),
            Self::Spat => Some("SPAT"),
            Self::Tim => Some("TIM"),
            Self::Other(20) => Some("BSM"),
            Self::Other(27) => Some("RSA"),
            Self::Other(32) => Some("PSM"),
            Self::Other(_) => None,
        }
    }

    /// The PSID deployed RSUs use for it: 0x8002 for MAP and SPaT, 0x8003 for TIM,
    /// 0x20 for BSM, 0x27 for PSM; `None` for the others (give one).
    pub const fn default_psid(self) -> Option<u32> {
        match self {
            Self::Map | Self::Spat => Some(0x8002),
            Self::Tim => Some(0x8003),
            Self::Other(20) => Some(0x20),
            Self::Other(32) => Some(0x27),
            Self::Other(_) => None,
        }
    }
}

impl fmt::Display for MessageKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.rsu_type() {
            Some(name) => f.write_str(name),
            None => write!(f, "message {}", self.id()),
        }
    }
}

/// Why bytes are not a bare `MessageFrame`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FrameError {
    /// Fewer than 2 bytes.
    TooShort {
        /// Bytes given.
        len: usize,
    },
    /// The bytes are an IEEE 1609.2 envelope; give the frame inside it (the
    /// [`Broadcaster`] wraps frames itself).
    Enveloped,
    /// The first bit (the `MessageFrame` extension bit) is set.
    Extended,
}

impl fmt::Display for FrameError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::TooShort { len } => write!(f, "{len} bytes are no MessageFrame (at least 2)"),
            Self::Enveloped => f.write_str(
                "the bytes are an IEEE 1609.2 envelope; give the bare MessageFrame (UPER)",
            ),
            Self::Extended => f.write_str("the MessageFrame extension bit is set"),
        }
    }
}

impl std::error::Error for FrameError {}

/// One message to broadcast: a bare UPER `MessageFrame` and its kind.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Message {
    kind: MessageKind,
    frame: Arc<[u8]>,
}

impl Message {
    /// A message from a bare UPER `MessageFrame` (what `messages::encode` gives).
    ///
    /// # Errors
    ///
    /// [`FrameError`] when the bytes are too short, an IEEE 1609.2 envelope, or extended.
    pub fn new(frame: Vec<u8>) -> Result<Self, FrameError> {
        if looks_like_ieee1609dot2(&frame) {
            return Err(FrameError::Enveloped);
        }
        let kind = MessageKind::of_frame(&frame).ok_or(match frame.len() {
            len @ 0..=1 => FrameError::TooShort { len },
            _ => FrameError::Extended,
        })?;
        Ok(Self {
            kind,
            frame: frame.into(),
        })
    }

    /// What the frame carries.
    pub fn kind(&self) -> MessageKind {
        self.kind
    }

    /// The frame's UPER bytes.
    pub fn frame(&self) -> &[u8] {
        &self.frame
    }
}

/// How frames go on the wire.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Wrapping {
    /// The bare UPER `MessageFrame`.
    #[default]
    Raw,
    /// IEEE 1609.2 unsecured data: `03 80 <COER length> <frame>`.
    Ieee1609Unsecured,
}

impl Wrapping {
    /// Replaces `out` with the datagram carrying `frame`.
    pub fn wrap_into(self, frame: &[u8], out: &mut Vec<u8>) {
        out.clear();
        match self {
            Self::Raw => out.extend_from_slice(frame),
            Self::Ieee1609Unsecured => {
                out.resize(unsecured_encoded_len(frame.len()), 0);
                // The buffer has exactly the length the encoder asks for.
                let written = encode_unsecured(frame, out).unwrap_or(0);
                out.truncate(written);
            }
        }
    }

    /// The datagram carrying `frame`.
    pub fn wrap(self, frame: &[u8]) -> Vec<u8> {
        let mut out = Vec::new();
        self.wrap_into(frame, &mut out);
        out
    }
}

/// The messages a [`Broadcaster`] sends, shared: another thread (a scenario runner) may
/// replace them while the broadcaster runs; the next tick sends the new ones.
#[derive(Clone, Debug, Default)]
pub struct MessageSlot(Arc<Mutex<Arc<Vec<Message>>>>);

impl MessageSlot {
    /// A slot holding `messages`.
    pub fn new(messages: Vec<Message>) -> Self {
        Self(Arc::new(Mutex::new(Arc::new(messages))))
    }

    /// Replaces the messages.
    pub fn set(&self, messages: Vec<Message>) {
        *self.0.lock().unwrap_or_else(PoisonError::into_inner) = Arc::new(messages);
    }

    /// The current messages.
    pub fn get(&self) -> Arc<Vec<Message>> {
        Arc::clone(&self.0.lock().unwrap_or_else(PoisonError::into_inner))
    }
}

// ---------------------------------------------------------------------------------------
// Faults

/// A small seeded pseudo-random generator (SplitMix64): the same seed gives the same
/// faults on every run and machine.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Prng(u64);

impl Prng {
    /// A generator from `seed`.
    pub const fn new(seed: u64) -> Self {
        Self(seed)
    }

    /// The next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }

    /// A uniform number in `[0, 1)`.
    pub fn next_f64(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }

    /// True with probability `p` (never for `p <= 0`, always for `p >= 1`).
    pub fn chance(&mut self, p: f64) -> bool {
        self.next_f64() < p
    }

    /// A number in `0..n` (0 when `n` is 0).
    pub fn below(&mut self, n: u64) -> u64 {
        ((u128::from(self.next_u64()) * u128::from(n)) >> 64) as u64
    }

    /// An independent generator seeded from this one.
    pub fn fork(&mut self) -> Self {
        Self::new(self.next_u64())
    }
}

/// Why a fault or rate setting was refused.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ConfigError {
    /// A probability or fraction outside 0-1 (or not a number).
    Probability {
        /// Which setting.
        what: &'static str,
        /// Its value.
        value: f64,
    },
    /// A mean burst length below 1 datagram.
    BurstLength {
        /// The value.
        value: f64,
    },
    /// Bursts this short cannot lose this much: the good state would have to turn bad
    /// more than always.
    BurstsTooShort {
        /// The asked loss rate.
        rate: f64,
        /// The asked mean burst length.
        mean_burst_len: f64,
    },
    /// A rate outside (0, [`MAX_RATE_HZ`]] Hz.
    Rate {
        /// The value, Hz.
        hz: f64,
    },
}

impl fmt::Display for ConfigError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Probability { what, value } => {
                write!(f, "{what} is {value}; it must be a fraction from 0 to 1")
            }
            Self::BurstLength { value } => {
                write!(f, "mean burst length {value}; it must be at least 1 datagram")
            }
            Self::BurstsTooShort {
                rate,
                mean_burst_len,
            } => write!(
                f,
                "a loss rate of {rate} needs bursts of at least {:.2} datagrams on average, not {mean_burst_len}",
                rate / (1.0 - rate)
            ),
            Self::Rate { hz } => write!(
                f,
                "rate {hz} Hz; it must be above 0 and at most {MAX_RATE_HZ} Hz"
            ),
        }
    }
}

impl std::error::Error for ConfigError {}

/// How datagrams get lost.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub enum LossModel {
    /// Nothing is lost.
    #[default]
    None,
    /// Each datagram is lost with probability `rate`, independently.
    Independent {
        /// Loss probability, 0-1.
        rate: f64,
    },
    /// Gilbert-Elliott: a two-state Markov channel. Each datagram is lost with the
    /// probability of the current state, then the state changes with the transition
    /// probability. [`LossModel::bursts`] gives the simple form (the good state loses
    /// nothing, the bad state everything).
    GilbertElliott {
        /// Probability of going from good to bad after a datagram.
        to_bad: f64,
        /// Probability of going from bad to good after a datagram (1 / mean burst length).
        to_good: f64,
        /// Loss probability in the good state.
        loss_good: f64,
        /// Loss probability in the bad state.
        loss_bad: f64,
    },
}

impl LossModel {
    /// Independent loss with probability `rate`.
    ///
    /// # Errors
    ///
    /// [`ConfigError::Probability`] when `rate` is not within 0-1.
    pub fn independent(rate: f64) -> Result<Self, ConfigError> {
        let model = Self::Independent { rate };
        model.validate().map(|()| model)
    }

    /// Bursty loss: on average a fraction `rate` of datagrams lost, in bursts of
    /// `mean_burst_len` datagrams on average (a Gilbert-Elliott channel whose bad state
    /// loses everything and good state nothing: `to_good = 1 / mean_burst_len`,
    /// `to_bad = rate * to_good / (1 - rate)`).
    ///
    /// # Errors
    ///
    /// When `rate` is not within 0-1 (1 excluded), `mean_burst_len` is below 1, or the
    /// bursts are too short for the rate (`mean_burst_len < rate / (1 - rate)`).
    pub fn bursts(rate: f64, mean_burst_len: f64) -> Result<Self, ConfigError> {
        if !(0.0..1.0).contains(&rate) {
            return Err(ConfigError::Probability {
                what: "burst loss rate (below 1)",
                value: rate,
            });
        }
        if mean_burst_len.is_nan() || mean_burst_len < 1.0 {
            return Err(ConfigError::BurstLength {
                value: mean_burst_len,
            });
        }
        let to_good = 1.0 / mean_burst_len;
        let to_bad = rate * to_good / (1.0 - rate);
        if to_bad > 1.0 {
            return Err(ConfigError::BurstsTooShort {
                rate,
                mean_burst_len,
            });
        }
        Ok(Self::GilbertElliott {
            to_bad,
            to_good,
            loss_good: 0.0,
            loss_bad: 1.0,
        })
    }

    /// Checks that every probability is within 0-1.
    ///
    /// # Errors
    ///
    /// [`ConfigError::Probability`] naming the first that is not.
    pub fn validate(&self) -> Result<(), ConfigError> {
        let checks: &[(&'static str, f64)] = match *self {
            Self::None => &[],
            Self::Independent { rate } => &[("loss rate", rate)],
            Self::GilbertElliott {
                to_bad,
                to_good,
                loss_good,
                loss_bad,
            } => &[
                ("to_bad", to_bad),
                ("to_good", to_good),
                ("loss_good", loss_good),
                ("loss_bad", loss_bad),
            ],
        };
        probabilities(checks)
    }

    /// The long-run fraction of datagrams lost.
    pub fn mean_loss_rate(&self) -> f64 {
        match *self {
            Self::None => 0.0,
            Self::Independent { rate } => rate,
            Self::GilbertElliott {
                loss_good,
                loss_bad,
                ..
            } => {
                let bad = self.stationary_bad();
                bad * loss_bad + (1.0 - bad) * loss_good
            }
        }
    }

    /// Long-run probability of the bad state (0 for the other models).
    fn stationary_bad(&self) -> f64 {
        match *self {
            Self::GilbertElliott {
                to_bad, to_good, ..
            } if to_bad + to_good > 0.0 => to_bad / (to_bad + to_good),
            _ => 0.0,
        }
    }
}

/// Checks `(name, value)` pairs to be probabilities.
fn probabilities(checks: &[(&'static str, f64)]) -> Result<(), ConfigError> {
    match checks.iter().find(|(_, v)| !(0.0..=1.0).contains(v)) {
        Some(&(what, value)) => Err(ConfigError::Probability { what, value }),
        None => Ok(()),
    }
}

/// The loss state of one path (one destination).
#[derive(Clone, Debug, PartialEq)]
pub struct LossChannel {
    model: LossModel,
    bad: bool,
}

impl LossChannel {
    /// A channel of `model`, its state drawn from the long-run distribution.
    pub fn new(model: LossModel, rng: &mut Prng) -> Self {
        let bad = rng.chance(model.stationary_bad());
        Self { model, bad }
    }

    /// Whether the next datagram is lost (and the state moves on).
    pub fn drops(&mut self, rng: &mut Prng) -> bool {
        match self.model {
            LossModel::None => false,
            LossModel::Independent { rate } => rng.chance(rate),
            LossModel::GilbertElliott {
                to_bad,
                to_good,
                loss_good,
                loss_bad,
            } => {
                let lost = rng.chance(if self.bad { loss_bad } else { loss_good });
                let flip = rng.chance(if self.bad { to_good } else { to_bad });
                self.bad ^= flip;
                lost
            }
        }
    }

    /// Whether the channel is in its bad (burst) state.
    pub fn in_burst(&self) -> bool {
        self.bad
    }
}

/// The faults to inject.
#[derive(Clone, Debug, PartialEq, Default)]
pub struct Faults {
    /// Datagram loss.
    pub loss: LossModel,
    /// Fraction (0-1) of the datagrams that get one random bit flipped.
    pub corrupt_fraction: f64,
    /// No TIM is sent before this time (MAPs are).
    pub tim_not_before: Option<Instant>,
    /// Seed of every random choice.
    pub seed: u64,
}

impl Faults {
    /// Checks the settings.
    ///
    /// # Errors
    ///
    /// [`ConfigError`] for a loss probability or corruption fraction outside 0-1.
    pub fn validate(&self) -> Result<(), ConfigError> {
        self.loss.validate()?;
        probabilities(&[("corrupt_fraction", self.corrupt_fraction)])
    }
}

/// Why a datagram was not sent.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum DropReason {
    /// The loss model lost it.
    Loss,
    /// A TIM before [`Faults::tim_not_before`].
    TimHeld,
}

/// What happens to one datagram.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Verdict {
    /// Send it as it is.
    Send,
    /// Send it with bit `bit` (0 = most significant bit of the first byte) flipped.
    Corrupted {
        /// The flipped bit.
        bit: usize,
    },
    /// Do not send it.
    Drop(DropReason),
}

/// Decides the fate of each datagram: sans-IO, seeded, per destination.
#[derive(Clone, Debug)]
pub struct FaultInjector {
    faults: Faults,
    loss_rng: Prng,
    corrupt_rng: Prng,
    channels: Vec<LossChannel>,
}

impl FaultInjector {
    /// An injector of `faults`; loss and corruption use separate streams of the seed, so
    /// turning corruption on does not change which datagrams are lost.
    ///
    /// # Errors
    ///
    /// [`ConfigError`] from [`Faults::validate`].
    pub fn new(faults: Faults) -> Result<Self, ConfigError> {
        faults.validate()?;
        let mut seeds = Prng::new(faults.seed);
        Ok(Self {
            loss_rng: seeds.fork(),
            corrupt_rng: seeds.fork(),
            channels: Vec::new(),
            faults,
        })
    }

    /// The faults injected.
    pub fn faults(&self) -> &Faults {
        &self.faults
    }

    /// The fate of the next datagram of `kind` to destination number `destination` at
    /// `now`; a corrupted datagram has its bit flipped in `datagram` here.
    pub fn decide(
        &mut self,
        destination: usize,
        kind: MessageKind,
        now: Instant,
        datagram: &mut [u8],
    ) -> Verdict {
        let held = self.faults.tim_not_before.is_some_and(|t| now < t);
        if kind == MessageKind::Tim && held {
            return Verdict::Drop(DropReason::TimHeld);
        }
        while self.channels.len() <= destination {
            let channel = LossChannel::new(self.faults.loss, &mut self.loss_rng);
            self.channels.push(channel);
        }
        let lost = self
            .channels
            .get_mut(destination)
            .is_some_and(|c| c.drops(&mut self.loss_rng));
        if lost {
            return Verdict::Drop(DropReason::Loss);
        }
        let bits = datagram.len() as u64 * 8;
        if bits == 0 || !self.corrupt_rng.chance(self.faults.corrupt_fraction) {
            return Verdict::Send;
        }
        let bit = self.corrupt_rng.below(bits) as usize;
        if let Some(byte) = datagram.get_mut(bit / 8) {
            *byte ^= 0x80 >> (bit % 8);
        }
        Verdict::Corrupted { bit }
    }
}

// ---------------------------------------------------------------------------------------
// Broadcaster

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

/// Sends MAP and TIM over UDP at a fixed rate (see the [module docs](self)).
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
                self.wrapping.wrap_into(message.frame(), &mut self.datagram);
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
            let Some(after) = self.next_slot(next) else {
                return ticks;
            };
            next = after;
        }
    }

    /// The tick time after `slot`: one period later, or the first slot of the grid that is
    /// not yet more than a period past when the loop is late.
    fn next_slot(&mut self, slot: Instant) -> Option<Instant> {
        let next = slot.checked_add(self.period)?;
        let Some(late) = Instant::now().checked_duration_since(next) else {
            return Some(next);
        };
        let missed = (late.as_nanos() / self.period.as_nanos().max(1)) as u32;
        if missed == 0 {
            return Some(next);
        }
        self.stats.missed_ticks += u64::from(missed);
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

// ---------------------------------------------------------------------------------------
// RSU 4.1 records

/// How the roadside unit sends a record's message.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RsuDelivery {
    /// Immediate forward: sent once per record received (UDP port 1516); written with
    /// `TxInterval=0` and no delivery window.
    ImmediateForward,
    /// Store and repeat: sent every `interval_ms` between the two times (Unix ms, written
    /// `MM/DD/YYYY, HH:MM` in UTC).
    StoreAndRepeat {
        /// Start of broadcasting.
        start_unix_ms: u64,
        /// End of broadcasting.
        stop_unix_ms: u64,
    },
}

/// The header fields of RSU records.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct RsuOptions {
    /// `PSID`; `None`: [`MessageKind::default_psid`] of each message.
    pub psid: Option<u32>,
    /// `TxChannel` (172 in most deployments, 183 for C-V2X).
    pub channel: TxChannel,
    /// `TxInterval` of store-and-repeat records, written as given (milliseconds).
    pub interval_ms: u32,
    /// `TxMode`.
    pub tx_mode: TxMode,
    /// `Priority`, 0-7.
    pub priority: u8,
    /// Immediate forward or store and repeat.
    pub delivery: RsuDelivery,
    /// `Signature`: ask the RSU to sign (the payload stays the bare frame).
    pub sign: bool,
    /// `Encryption`.
    pub encrypt: bool,
}

impl Default for RsuOptions {
    /// Per-kind PSID, channel 172, 100 ms, continuous, priority 5, immediate forward,
    /// neither signed nor encrypted.
    fn default() -> Self {
        Self {
            psid: None,
            channel: TxChannel::Number(172),
            interval_ms: 100,
            tx_mode: TxMode::Continuous,
            priority: 5,
            delivery: RsuDelivery::ImmediateForward,
            sign: false,
            encrypt: false,
        }
    }
}

/// Why RSU records could not be written.
#[derive(Debug)]
#[non_exhaustive]
pub enum RsuFileError {
    /// A message with no PSID of its own and none given.
    NoPsid {
        /// Index of the message.
        index: usize,
        /// Its kind.
        kind: MessageKind,
    },
    /// A message whose kind has no RSU `Type` name.
    NoType {
        /// Index of the message.
        index: usize,
        /// Its kind.
        kind: MessageKind,
    },
    /// A priority above 7.
    Priority {
        /// The value.
        value: u8,
    },
    /// A store-and-repeat window that ends before it starts.
    Window {
        /// Start, Unix ms.
        start_unix_ms: u64,
        /// Stop, Unix ms.
        stop_unix_ms: u64,
    },
    /// The codec's writer refused the record.
    Record {
        /// Index of the message.
        index: usize,
        /// The writer's error.
        error: RsuWriteError,
    },
    /// A file or the directory could not be written.
    Io {
        /// The path.
        path: PathBuf,
        /// The error.
        error: io::Error,
    },
}

impl fmt::Display for RsuFileError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::NoPsid { index, kind } => write!(
                f,
                "message {index} ({kind}) has no usual PSID; give one in RsuOptions::psid"
            ),
            Self::NoType { index, kind } => {
                write!(f, "message {index} ({kind}) has no RSU record Type name")
            }
            Self::Priority { value } => write!(f, "priority {value}; it must be 0 to 7"),
            Self::Window {
                start_unix_ms,
                stop_unix_ms,
            } => write!(
                f,
                "delivery stops (Unix ms {stop_unix_ms}) before it starts ({start_unix_ms})"
            ),
            Self::Record { index, error } => write!(f, "message {index}: {error}"),
            Self::Io { path, error } => write!(f, "{}: {error}", path.display()),
        }
    }
}

impl std::error::Error for RsuFileError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            Self::Io { error, .. } => Some(error),
            Self::Record { error, .. } => Some(error),
            _ => None,
        }
    }
}

/// The `Version=0.7` RSU record of `message` (the `index`-th of a set, for errors).
///
/// # Errors
///
/// [`RsuFileError`] for a message without PSID or type name, a priority above 7, a
/// delivery window that ends before it starts, or a record the codec refuses.
pub fn rsu_record(
    index: usize,
    message: &Message,
    options: &RsuOptions,
) -> Result<String, RsuFileError> {
    let kind = message.kind();
    let psid = options
        .psid
        .or(kind.default_psid())
        .ok_or(RsuFileError::NoPsid { index, kind })?;
    let message_type = kind
        .rsu_type()
        .ok_or(RsuFileError::NoType { index, kind })?;
    if options.priority > 7 {
        return Err(RsuFileError::Priority {
            value: options.priority,
        });
    }
    let (interval, start, stop) = match options.delivery {
        RsuDelivery::ImmediateForward => (0, None, None),
        RsuDelivery::StoreAndRepeat {
            start_unix_ms,
            stop_unix_ms,
        } => {
            if stop_unix_ms <= start_unix_ms {
                return Err(RsuFileError::Window {
                    start_unix_ms,
                    stop_unix_ms,
                });
            }
            (
                options.interval_ms,
                Some(rsu_time(start_unix_ms)),
                Some(rsu_time(stop_unix_ms)),
            )
        }
    };
    let mut record = RsuMessage::new(message_type, psid, RsuPayload::Bytes(message.frame()));
    record.priority = Some(options.priority);
    record.tx_mode = Some(options.tx_mode);
    record.tx_channel = Some(options.channel);
    record.tx_interval = Some(interval);
    record.delivery_start = start.as_deref();
    record.delivery_stop = stop.as_deref();
    record.signature = Some(options.sign);
    record.encryption = Some(options.encrypt);
    let mut text = String::new();
    record
        .write_to(&mut text)
        .map_err(|error| RsuFileError::Record { index, error })?;
    Ok(text)
}

/// `MM/DD/YYYY, HH:MM` (UTC), as RSU delivery times are written.
fn rsu_time(unix_ms: u64) -> String {
    let t = Utc::from_unix_ms(unix_ms);
    let minutes = t.ms_of_day / 60_000;
    format!(
        "{:02}/{:02}/{:04}, {:02}:{:02}",
        t.month,
        t.day,
        t.year,
        minutes / 60,
        minutes % 60
    )
}

/// The file name of the `index`-th message's record: `01-map.txt`, `02-tim.txt`, ...
pub fn rsu_file_name(index: usize, message: &Message) -> String {
    let kind = message.kind();
    let name = kind
        .rsu_type()
        .map_or_else(|| format!("msg{}", kind.id()), str::to_ascii_lowercase);
    format!("{:02}-{name}.txt", index + 1)
}

/// Writes one RSU record file per message into `dir` (created if missing), named by
/// [`rsu_file_name`]; each file is written whole under a temporary name and then renamed,
/// so an RSU watching the directory never reads half a record. Returns the paths.
///
/// # Errors
///
/// [`RsuFileError`] from [`rsu_record`] (before any file is written), or
/// [`RsuFileError::Io`] naming the path that could not be written.
pub fn write_rsu_files(
    dir: &Path,
    messages: &[Message],
    options: &RsuOptions,
) -> Result<Vec<PathBuf>, RsuFileError> {
    let records = messages
        .iter()
        .enumerate()
        .map(|(k, m)| Ok((rsu_file_name(k, m), rsu_record(k, m, options)?)))
        .collect::<Result<Vec<_>, RsuFileError>>()?;
    let io_error = |path: &Path| {
        let path = path.to_path_buf();
        move |error| RsuFileError::Io { path, error }
    };
    fs::create_dir_all(dir).map_err(io_error(dir))?;
    let mut paths = Vec::with_capacity(records.len());
    for (name, text) in records {
        let path = dir.join(&name);
        let partial = dir.join(format!(".{name}.partial"));
        fs::write(&partial, text).map_err(io_error(&partial))?;
        fs::rename(&partial, &path).map_err(io_error(&path))?;
        paths.push(path);
    }
    Ok(paths)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn prng_is_seeded_and_uniform() {
        let mut a = Prng::new(7);
        let mut b = Prng::new(7);
        assert_eq!(a.next_u64(), b.next_u64());
        assert_ne!(Prng::new(8).next_u64(), Prng::new(7).next_u64());
        let mut rng = Prng::new(1);
        let n = 100_000;
        let mean = (0..n).map(|_| rng.next_f64()).sum::<f64>() / n as f64;
        assert!((mean - 0.5).abs() < 0.01, "{mean}");
        assert!((0..1000).all(|_| rng.below(10) < 10));
        assert_eq!(rng.below(0), 0);
    }

    #[test]
    fn message_kinds_from_frames() {
        assert_eq!(
            MessageKind::of_frame(&[0x00, 0x12, 0x34]),
            Some(MessageKind::Map)
        );
        assert_eq!(MessageKind::of_frame(&[0x00, 0x1f]), Some(MessageKind::Tim));
        assert_eq!(MessageKind::of_frame(&[0x00]), None);
        assert_eq!(
            Message::new(vec![0x03, 0x80, 0x01, 0x00]),
            Err(FrameError::Enveloped)
        );
        assert_eq!(Message::new(vec![0x80, 0x12]), Err(FrameError::Extended));
        assert_eq!(Message::new(vec![]), Err(FrameError::TooShort { len: 0 }));
    }

    #[test]
    fn bursts_have_the_asked_rate_and_length() {
        let model = LossModel::bursts(0.2, 4.0).unwrap();
        assert!((model.mean_loss_rate() - 0.2).abs() < 1e-12);
        let mut rng = Prng::new(42);
        let mut ch = LossChannel::new(model, &mut rng);
        let (mut lost, mut bursts, mut prev) = (0u32, 0u32, false);
        let n = 200_000;
        for _ in 0..n {
            let l = ch.drops(&mut rng);
            lost += u32::from(l);
            bursts += u32::from(l && !prev);
            prev = l;
        }
        let rate = f64::from(lost) / f64::from(n);
        let mean_burst = f64::from(lost) / f64::from(bursts);
        assert!((rate - 0.2).abs() < 0.01, "{rate}");
        assert!((mean_burst - 4.0).abs() < 0.2, "{mean_burst}");
        assert!(matches!(
            LossModel::bursts(0.9, 2.0),
            Err(ConfigError::BurstsTooShort { .. })
        ));
        assert!(LossModel::bursts(0.5, 0.5).is_err() && LossModel::independent(1.5).is_err());
    }

    #[test]
    fn rsu_times() {
        // 2026-11-22T10:00:00Z.
        assert_eq!(rsu_time(1_795_341_600_000), "11/22/2026, 10:00");
    }
}
