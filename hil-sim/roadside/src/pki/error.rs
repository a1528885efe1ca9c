//! Why a PKI could not be made, written or read: [`PkiError`], and why a key file's text
//! is not a key: [`KeyError`].

use j2735::envelope::ieee1609dot2::build::BuildError;
use j2735::envelope::ieee1609dot2::crypto::CryptoError;
use j2735::hex::HexError;
use std::fmt;
use std::io;
use std::path::PathBuf;

/// Why a PKI could not be made, written or read.
#[derive(Debug)]
#[non_exhaustive]
pub enum PkiError {
    /// The certificates' validities do not nest (RSU within CA within root), or the RSU's
    /// is zero.
    Validity {
        /// The RSU's validity, hours.
        rsu_hours: u16,
        /// The CA's validity, years.
        ca_years: u16,
        /// The root's validity, years.
        root_years: u16,
    },
    /// The operating system's random source (`/dev/urandom`) could not be read.
    Random(io::Error),
    /// None of 64 candidate scalars was a valid key (practically impossible).
    NoValidKey,
    /// A certificate could not be encoded (a value that does not fit its field).
    Certificate(BuildError),
    /// A file or folder could not be read or written.
    Io {
        /// The file or folder.
        path: PathBuf,
        /// The file system's error.
        source: io::Error,
    },
    /// A key file's text is not a key.
    Key {
        /// The key file.
        path: PathBuf,
        /// What is wrong with its text.
        source: KeyError,
    },
}

impl fmt::Display for PkiError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Validity {
                rsu_hours,
                ca_years,
                root_years,
            } => write!(
                f,
                "validity: the RSU's ({} days) must be within the CA's ({ca_years} years), the \
                 CA's within the root's ({root_years} years)",
                rsu_hours / 24
            ),
            Self::Random(e) => write!(f, "/dev/urandom: {e}"),
            Self::NoValidKey => f.write_str("no valid key in 64 candidates"),
            Self::Certificate(e) => write!(f, "{e:?}"),
            Self::Io { path, source } => write!(f, "{}: {source}", path.display()),
            Self::Key { path, source } => write!(f, "{}: {source}", path.display()),
        }
    }
}

impl std::error::Error for PkiError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            Self::Random(e) | Self::Io { source: e, .. } => Some(e),
            Self::Key { source, .. } => Some(source),
            Self::Validity { .. } | Self::NoValidKey | Self::Certificate(_) => None,
        }
    }
}

/// Why a private key's text is not a key.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[non_exhaustive]
pub enum KeyError {
    /// Not hexadecimal text.
    Hex(HexError),
    /// Hexadecimal text of another length than 32 octets.
    Length {
        /// Octets given.
        octets: usize,
    },
    /// 32 octets that are not a valid NIST P-256 scalar.
    Scalar(CryptoError),
}

impl fmt::Display for KeyError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Hex(e) => e.fmt(f),
            Self::Length { .. } => f.write_str("not a 32-octet key"),
            Self::Scalar(e) => e.fmt(f),
        }
    }
}

impl std::error::Error for KeyError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            Self::Hex(e) => Some(e),
            Self::Scalar(e) => Some(e),
            Self::Length { .. } => None,
        }
    }
}
