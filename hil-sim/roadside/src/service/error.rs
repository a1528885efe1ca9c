//! Why the roadside service cannot start, reload or keep its state: [`ServiceError`].

use crate::broadcast::ConfigError;
use crate::rsu_snmp::fleet::OwnedFileError;
use crate::signer::SignerLoadError;
use crate::site::SiteError;
use crate::site_file::SiteFileError;
use crate::zone_sources::ZoneError;
use std::fmt;
use std::io;
use std::path::PathBuf;

/// Why the roadside service cannot start, reload or keep its state.
#[derive(Debug)]
#[non_exhaustive]
pub enum ServiceError {
    /// The site file (its credentials and RSU addresses included).
    SiteFile(SiteFileError),
    /// The site's lane map.
    Road(SiteError),
    /// A zone of the site's `[[zones]]`.
    Zone(ZoneError),
    /// The site's PKI folder.
    Signer(SignerLoadError),
    /// The owned-rows file of the state folder.
    Owned(OwnedFileError),
    /// The state folder or its `status.json` cannot be written.
    Io {
        /// The folder or file.
        path: PathBuf,
        /// The file system's error.
        source: io::Error,
    },
    /// The status cannot be written as JSON.
    Status(serde_json::Error),
    /// The direct broadcast's UDP socket.
    Socket(io::Error),
    /// The direct broadcast's rate.
    Rate(ConfigError),
}

impl fmt::Display for ServiceError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::SiteFile(e) => e.fmt(f),
            Self::Road(e) => e.fmt(f),
            Self::Zone(e) => e.fmt(f),
            Self::Signer(e) => e.fmt(f),
            Self::Owned(e) => e.fmt(f),
            Self::Io { path, source } => write!(f, "{}: {source}", path.display()),
            Self::Status(e) => e.fmt(f),
            Self::Socket(e) => e.fmt(f),
            Self::Rate(e) => e.fmt(f),
        }
    }
}

/// The wrapping variants are transparent: their message is the inner error's, so their
/// source is the inner error's source (a chain printed whole says each thing once).
impl std::error::Error for ServiceError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            Self::SiteFile(e) => e.source(),
            Self::Road(e) => e.source(),
            Self::Zone(e) => e.source(),
            Self::Signer(e) => e.source(),
            Self::Owned(e) => e.source(),
            Self::Io { source, .. } => Some(source),
            Self::Socket(e) => e.source(),
            Self::Status(e) => e.source(),
            Self::Rate(e) => e.source(),
        }
    }
}

impl From<SiteFileError> for ServiceError {
    fn from(e: SiteFileError) -> Self {
        Self::SiteFile(e)
    }
}

impl From<SiteError> for ServiceError {
    fn from(e: SiteError) -> Self {
        Self::Road(e)
    }
}

impl From<ZoneError> for ServiceError {
    fn from(e: ZoneError) -> Self {
        Self::Zone(e)
    }
}

impl From<SignerLoadError> for ServiceError {
    fn from(e: SignerLoadError) -> Self {
        Self::Signer(e)
    }
}

impl From<OwnedFileError> for ServiceError {
    fn from(e: OwnedFileError) -> Self {
        Self::Owned(e)
    }
}
