//! The site's messages as rows for the RSUs: PSID and message id by kind, the RSU entry's
//! channel, interval and priority, the delivery window, and who signs: the roadside once
//! (an `expiryTime` at the message's end, options 0x00: the deposited-TIM pattern), the RSU
//! (options 0x80), or nobody.

use super::mib::RepeatMessage;
use crate::broadcast::{Message, MessageKind};
use crate::signer::{RsuSigner, SignError};
use serde::Deserialize;
use std::fmt;

/// Why a message could not be made a row.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[non_exhaustive]
pub enum DepositError {
    /// The message's kind has no PSID to deposit it under.
    NoPsid {
        /// Its kind.
        kind: MessageKind,
    },
    /// The roadside signs deposits ([`DepositSigning::Roadside`]) but has no signer.
    NoSigner,
    /// The roadside's signature could not be made.
    Sign(SignError),
}

impl fmt::Display for DepositError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::NoPsid { kind } => write!(f, "{kind} has no PSID to deposit under"),
            Self::NoSigner => f.write_str("roadside signing needs [signing] pki"),
            Self::Sign(e) => e.fmt(f),
        }
    }
}

impl std::error::Error for DepositError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            Self::Sign(e) => Some(e),
            Self::NoPsid { .. } | Self::NoSigner => None,
        }
    }
}

impl From<SignError> for DepositError {
    fn from(e: SignError) -> Self {
        Self::Sign(e)
    }
}

/// Who signs deposited messages.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum DepositSigning {
    /// The roadside signs each message once, valid until its delivery stop; the RSU sends
    /// the bytes as they are (options 0x00).
    #[default]
    Roadside,
    /// The RSU signs with its own certificate (options 0x80).
    Rsu,
    /// Unsigned (lab use; OBUs with a trust policy drop it).
    None,
}

/// How an RSU sends the deposited messages.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct DepositSettings {
    /// Radio channel.
    pub channel: u8,
    /// Repeat interval, ms.
    pub interval_ms: u32,
    /// NTCIP 1218 priority 0-63.
    pub priority: u8,
    /// Who signs.
    pub signing: DepositSigning,
}

/// The rows of `messages`, each delivered from `start_unix_ms` to its stop (`stops[i]`,
/// or `default_stop` when none), signed by the roadside with `signer` when the settings
/// say so. `now_unix_ms` is the signing time.
///
/// # Errors
///
/// [`DepositError`]: a message kind without a PSID, roadside signing without a signer, or
/// a signing error.
pub fn repeat_messages(
    messages: &[(Message, u64)],
    start_unix_ms: u64,
    settings: DepositSettings,
    signer: Option<&RsuSigner>,
    now_unix_ms: u64,
) -> Result<Vec<RepeatMessage>, DepositError> {
    messages
        .iter()
        .map(|(m, stop)| {
            let kind = m.kind();
            // The message's own PSID, as V2X-Hub configures RSUs (MAP 0xE0000017, not the
            // SPaT PSID RSU 4.1 files share it under): the RSU's WSMP header and, when it
            // signs, its IEEE 1609.2 header carry it.
            let psid = crate::pki::signing_psid(kind.id())
                .or(kind.default_psid())
                .ok_or(DepositError::NoPsid { kind })?;
            let payload = match settings.signing {
                DepositSigning::Roadside => signer.ok_or(DepositError::NoSigner)?.sign_until(
                    m.frame(),
                    now_unix_ms,
                    *stop,
                )?,
                DepositSigning::Rsu | DepositSigning::None => m.frame().to_vec(),
            };
            Ok(RepeatMessage {
                label: label(m),
                psid,
                message_id: kind.id(),
                payload,
                channel: settings.channel,
                interval_ms: settings.interval_ms,
                start_unix_ms,
                stop_unix_ms: *stop,
                priority: settings.priority,
                rsu_signs: settings.signing == DepositSigning::Rsu,
                alternating: false,
            })
        })
        .collect()
}

/// `MAP`, or `TIM` and the first bytes of its frame's digest (a name that follows the
/// message's content).
fn label(m: &Message) -> String {
    let digest = super::table::payload_digest(m.frame());
    let kind = match m.kind() {
        MessageKind::Other(id) => format!("message {id}"),
        k => k.to_string(),
    };
    format!("{kind} {:02x}{:02x}{:02x}", digest[0], digest[1], digest[2])
}
