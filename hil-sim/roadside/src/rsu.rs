//! The roadside unit as a product (`hil-sim roadside`). The lane map and the work zones of
//! a [`Site`] (a scenario file's `[road]` and `[[zones]]`: built in, GeoJSON, WZDx, cone
//! list or a calibrated camera's detections) become a MAP and one TIM per zone, broadcast
//! over UDP to the given destinations (raw or IEEE 1609.2), and/or written as RSU 4.1
//! text files.

use crate::broadcast::{
    write_rsu_files, Broadcaster, ConfigError, Message, RsuFileError, RsuOptions, Wrapping,
};
use crate::clock::{unix_ms_now, Utc};
use crate::messages;
use crate::publisher::PublishError;
use crate::signer::{RsuSigner, SignerLoadError, SigningPattern};
use crate::site::{Site, SiteError};
use crate::zone_sources::ZoneError;
use std::fmt;
use std::io;
use std::net::SocketAddr;
use std::path::PathBuf;
use std::time::Duration;

/// Why a site's messages could not be built, written or broadcast.
#[derive(Debug)]
#[non_exhaustive]
pub enum RoadsideError {
    /// The lane map.
    Road(SiteError),
    /// A work zone's source.
    Zone(ZoneError),
    /// The MAP or a TIM.
    Message(PublishError),
    /// The PKI folder's signer.
    Signer(SignerLoadError),
    /// The RSU 4.1 files.
    RsuFiles(RsuFileError),
    /// The broadcaster's UDP socket.
    Socket(io::Error),
    /// The broadcast rate.
    Rate(ConfigError),
}

impl fmt::Display for RoadsideError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Road(e) => e.fmt(f),
            Self::Zone(e) => e.fmt(f),
            Self::Message(e) => e.fmt(f),
            Self::Signer(e) => e.fmt(f),
            Self::RsuFiles(e) => e.fmt(f),
            Self::Socket(e) => e.fmt(f),
            Self::Rate(e) => e.fmt(f),
        }
    }
}

impl std::error::Error for RoadsideError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            Self::Road(e) => Some(e),
            Self::Zone(e) => Some(e),
            Self::Message(e) => Some(e),
            Self::Signer(e) => Some(e),
            Self::RsuFiles(e) => Some(e),
            Self::Socket(e) => Some(e),
            Self::Rate(e) => Some(e),
        }
    }
}

impl From<SiteError> for RoadsideError {
    fn from(e: SiteError) -> Self {
        Self::Road(e)
    }
}

impl From<ZoneError> for RoadsideError {
    fn from(e: ZoneError) -> Self {
        Self::Zone(e)
    }
}

impl From<PublishError> for RoadsideError {
    fn from(e: PublishError) -> Self {
        Self::Message(e)
    }
}

impl From<SignerLoadError> for RoadsideError {
    fn from(e: SignerLoadError) -> Self {
        Self::Signer(e)
    }
}

impl From<RsuFileError> for RoadsideError {
    fn from(e: RsuFileError) -> Self {
        Self::RsuFiles(e)
    }
}

/// What to do with the messages.
#[derive(Debug, Clone)]
pub struct RoadsideOptions {
    /// UDP destinations (empty: no broadcast).
    pub destinations: Vec<SocketAddr>,
    /// Raw or IEEE 1609.2 unsecured.
    pub wrapping: Wrapping,
    /// Broadcast rate, Hz.
    pub rate_hz: f64,
    /// How long to broadcast (`None`: until stopped).
    pub duration: Option<Duration>,
    /// Write RSU 4.1 text files here.
    pub rsu_dir: Option<PathBuf>,
    /// Sign with this PKI directory's RSU certificate and key (`rsu.oer`, `rsu.key`):
    /// broadcasts are IEEE 1609.2 signed data, RSU files ask the RSU to sign
    /// (`Signature=True`).
    pub pki_dir: Option<PathBuf>,
    /// With `pki_dir`: how to sign (per transmission, or once and repeat), each message's
    /// lifetime (generation to expiry, ms) and how often the certificate goes whole
    /// (`None`: in every message).
    pub signing: (SigningPattern, u64, Option<u64>),
}

/// The MAP and TIMs of a site's road and zones, valid from now until further notice.
///
/// # Errors
///
/// [`RoadsideError::Road`], [`RoadsideError::Zone`] or [`RoadsideError::Message`].
pub fn messages_of(s: &Site) -> Result<Vec<Message>, RoadsideError> {
    let road = s.road()?;
    let zones = crate::zone_sources::build_zones(s, &road, Utc::from_unix_ms(unix_ms_now()))?;
    let e = |x: messages::BuildError| RoadsideError::Message(x.into());
    let mut out = Vec::new();
    let map = messages::build_map(&road, 1, 1, zones.first()).map_err(e)?;
    out.push(messages::encode(&map).map_err(e)?);
    for z in &zones {
        let tim = messages::build_tim(&road, z).map_err(e)?;
        out.push(messages::encode(&tim).map_err(e)?);
    }
    out.into_iter()
        .map(|bytes| Message::new(bytes).map_err(|e| RoadsideError::Message(e.into())))
        .collect()
}

/// Writes the RSU files and/or broadcasts; returns a one-line summary.
///
/// # Errors
///
/// [`RoadsideError`]: the messages ([`messages_of`]), the signer, the RSU files or the
/// broadcaster.
pub fn run(s: &Site, o: &RoadsideOptions) -> Result<String, RoadsideError> {
    let msgs = messages_of(s)?;
    let mut summary = format!("{} messages (MAP + {} TIM)", msgs.len(), msgs.len() - 1);
    let signer = match &o.pki_dir {
        Some(dir) => {
            let (pattern, lifetime_ms, every) = o.signing;
            let signer = RsuSigner::load(dir, None)?.signing(pattern, lifetime_ms, every);
            Some(std::sync::Arc::new(signer))
        }
        None => None,
    };
    if signer.is_some() {
        summary.push_str(", signed (IEEE 1609.2)");
    }
    if let Some(dir) = &o.rsu_dir {
        let options = RsuOptions {
            sign: signer.is_some(),
            ..RsuOptions::default()
        };
        let files = write_rsu_files(dir, &msgs, &options)?;
        summary.push_str(&format!(
            "; {} RSU 4.1 files in {}",
            files.len(),
            dir.display()
        ));
    }
    if o.destinations.is_empty() {
        return Ok(summary);
    }
    let mut b =
        Broadcaster::new(o.destinations.clone(), o.wrapping).map_err(RoadsideError::Socket)?;
    b.set_rate_hz(o.rate_hz).map_err(RoadsideError::Rate)?;
    b.set_signer(signer);
    b.set_messages(msgs);
    match o.duration {
        Some(d) => {
            b.run_for(d);
        }
        None => {
            let stop = std::sync::atomic::AtomicBool::new(false);
            b.run_until(&stop);
        }
    }
    let st = b.stats();
    Ok(format!(
        "{summary}; {} ticks, {} datagrams sent, {} send errors",
        st.ticks, st.sent, st.send_errors
    ))
}
