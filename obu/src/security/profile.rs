//! Security profiles: the relevance rules IEEE 1609.2 leaves to each application (PSID), one
//! row per message the OBU uses.
//!
//! Deployed roadside systems sign in two ways, and the defaults accept both:
//! - **Per transmission** (V2X-Hub's way): each broadcast is signed anew, with a generation
//!   time and no expiry time. It is relevant for [`SecurityProfile::past_window_ms`] after
//!   its generation (30 s).
//! - **Once, then repeated** (how USDOT's jpo-ode deposits TIMs in an RSU's NTCIP 1218
//!   store-and-repeat table): signed once with an expiry time as far ahead as the message
//!   lasts, then broadcast as the same bytes until its delivery stop. It is relevant until its
//!   expiry time, however old its generation time, as long as generation to expiry is at most
//!   [`SecurityProfile::max_lifetime_ms`] (7 days). Each byte-identical copy is a repeat
//!   ([`Duplicates::Repeat`]), not a replay.

use j2735::envelope::Psid;

use super::RequiredSsp;

/// What a byte-identical copy of an accepted signed message is.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "snake_case"))]
pub enum Duplicates {
    /// A repeat: what an RSU broadcasts again; accepted (after the time checks) for the cost
    /// of a hash, no signature verification, and counted as a repeat.
    #[default]
    Repeat,
    /// A replay: dropped (for messages that are signed once per transmission, such as a PSM
    /// from a road worker's device).
    Replay,
}

/// The relevance rules for one message type's signed messages.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct SecurityProfile {
    /// The PSID the 1609.2 header must carry (the integer: TIM 131, MAP 2113687).
    pub psid: Psid,
    /// The SSP the signer certificate must grant with the PSID ([`RequiredSsp::NONE`]: any).
    pub ssp: RequiredSsp,
    /// Refuse messages without a generation time. Off: a message without one must carry an
    /// expiry time, and is relevant until it.
    pub require_generation_time: bool,
    /// Refuse messages without an expiry time.
    pub require_expiry_time: bool,
    /// How far ahead of GNSS time a generation time may be, and how long past its expiry
    /// time a message is still taken (clock differences between sender and OBU), ms.
    pub future_tolerance_ms: u32,
    /// How long after its generation a message without an expiry time is relevant, ms.
    pub past_window_ms: u32,
    /// The longest generation-to-expiry lifetime accepted, ms: a message that claims to be
    /// relevant for longer is refused (a leaked signing key cannot mint week-long zones).
    pub max_lifetime_ms: u64,
    /// What a byte-identical copy of an accepted message is.
    pub duplicates: Duplicates,
}

/// 7 days, in milliseconds.
const WEEK_MS: u64 = 7 * 24 * 3600 * 1000;

impl SecurityProfile {
    /// MAP and TIM: both deployed patterns (per transmission, or once with an expiry time
    /// and repeated): 5 s future tolerance, 30 s past window, 7 days' longest lifetime,
    /// duplicates are repeats.
    pub const fn roadside(psid: Psid) -> Self {
        Self {
            psid,
            ssp: RequiredSsp::NONE,
            require_generation_time: true,
            require_expiry_time: false,
            future_tolerance_ms: 5_000,
            past_window_ms: 30_000,
            max_lifetime_ms: WEEK_MS,
            duplicates: Duplicates::Repeat,
        }
    }

    /// The TIM row's default ([`Psid::TIM`]).
    pub const TIM: Self = Self::roadside(Psid::TIM);
    /// The MAP row's default ([`Psid::MAP`]).
    pub const MAP: Self = Self::roadside(Psid::MAP);
    /// The SPaT row's default ([`Psid::SPAT`]; signed per transmission at 10 Hz).
    pub const SPAT: Self = Self::roadside(Psid::SPAT);
    /// The PSM row's default ([`Psid::PSM`]): a road worker's device signs each PSM; a copy
    /// of one is a replay.
    pub const PSM: Self = Self {
        duplicates: Duplicates::Replay,
        ..Self::roadside(Psid::PSM)
    };

    /// All zero bytes (an unconfigured receiver's placeholder; never used for a check).
    pub(crate) const ZERO: Self = Self {
        psid: Psid(0),
        ssp: RequiredSsp::NONE,
        require_generation_time: false,
        require_expiry_time: false,
        future_tolerance_ms: 0,
        past_window_ms: 0,
        max_lifetime_ms: 0,
        duplicates: Duplicates::Repeat,
    };

    /// Whether the rows' numbers make sense: a past window and a lifetime above zero.
    pub fn is_valid(&self) -> bool {
        self.past_window_ms > 0 && self.max_lifetime_ms > 0
    }
}
