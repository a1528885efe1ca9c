//! Why a site file cannot be used: [`SiteFileError`], and what is wrong with its content:
//! [`SiteProblem`].

use crate::rsu_snmp::credentials::CredentialsError;
use std::fmt;
use std::io;
use std::path::PathBuf;

/// What is wrong with a site file's content.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub enum SiteProblem {
    /// `[[rsu]]` entries without `[rsus]` (which names the credentials file).
    RsuWithoutCredentials,
    /// Neither `[[rsu]]` entries nor `[broadcast]`.
    NothingToDo,
    /// A number outside its range.
    OutOfRange {
        /// Where the key is (`[rsus]`, `[wzdx_feed]`, `[[rsu]] NAME`).
        section: String,
        /// The key (`poll_s`, `channel`, ...).
        key: &'static str,
        /// The value given.
        value: f64,
        /// The smallest allowed.
        min: f64,
        /// The largest allowed.
        max: f64,
    },
    /// Two `[[rsu]]` entries of the same name.
    DuplicateRsu {
        /// The name.
        name: String,
    },
    /// The roadside signs deposits (`[signing] deposit = "roadside"`, the default) but the
    /// site gives no `[signing] pki`.
    SigningWithoutPki,
}

impl fmt::Display for SiteProblem {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::RsuWithoutCredentials => f.write_str("[[rsu]] entries need [rsus] credentials"),
            Self::NothingToDo => {
                f.write_str("nothing to do: give [[rsu]] entries and/or [broadcast]")
            }
            Self::OutOfRange {
                section,
                key,
                value,
                min,
                max,
            } => write!(f, "{section} {key} = {value}: from {min} to {max}"),
            Self::DuplicateRsu { name } => write!(f, "two [[rsu]] entries are named {name:?}"),
            Self::SigningWithoutPki => f.write_str(
                "[signing] deposit = \"roadside\" (the default) needs [signing] pki \
                 (the roadside's rsu.oer and rsu.key); or deposit = \"rsu\" (the RSU signs)",
            ),
        }
    }
}

impl std::error::Error for SiteProblem {}

/// Why a site file cannot be used.
#[derive(Debug)]
#[non_exhaustive]
pub enum SiteFileError {
    /// It cannot be read.
    Io {
        /// The site file.
        path: PathBuf,
        /// The file system's error.
        source: io::Error,
    },
    /// It is not TOML of the site file's shape (unknown keys are refused).
    Toml {
        /// The site file.
        path: PathBuf,
        /// The parser's error.
        source: toml::de::Error,
    },
    /// Its content is inconsistent or out of range.
    Invalid {
        /// The site file.
        path: PathBuf,
        /// What is wrong.
        problem: SiteProblem,
    },
    /// The credentials file, or an RSU's entry in it.
    Credentials(CredentialsError),
    /// An RSU's address does not resolve.
    Address {
        /// The RSU's name.
        rsu: String,
        /// Its address as given.
        address: String,
        /// The resolver's error; `None`: it resolved to no address.
        source: Option<io::Error>,
    },
}

impl fmt::Display for SiteFileError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Io { path, source } => write!(f, "{}: {source}", path.display()),
            Self::Toml { path, source } => write!(f, "{}: {source}", path.display()),
            Self::Invalid { path, problem } => write!(f, "{}: {problem}", path.display()),
            Self::Credentials(e) => e.fmt(f),
            Self::Address {
                rsu,
                address,
                source: Some(e),
            } => write!(f, "[[rsu]] {rsu}: address {address}: {e}"),
            Self::Address {
                rsu,
                address,
                source: None,
            } => write!(f, "[[rsu]] {rsu}: address {address} does not resolve"),
        }
    }
}

impl std::error::Error for SiteFileError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            Self::Io { source, .. } => Some(source),
            Self::Toml { source, .. } => Some(source),
            Self::Invalid { problem, .. } => Some(problem),
            Self::Credentials(e) => Some(e),
            Self::Address { source, .. } => source.as_ref().map(|e| e as _),
        }
    }
}

impl From<CredentialsError> for SiteFileError {
    fn from(e: CredentialsError) -> Self {
        Self::Credentials(e)
    }
}
