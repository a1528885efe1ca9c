//! Seeded fault injection (with the crate's [`Prng`]): the [`Faults`] to inject and the sans-IO
//! [`FaultInjector`] that decides the fate of each datagram.

use super::config::ConfigError;
use super::loss::{probabilities, LossChannel, LossModel};
use super::message::MessageKind;
use crate::rng::Prng;
use std::time::Instant;

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
