//! SNMP credentials of the site's RSUs, from a file only its owner may read.
//!
//! ```toml
//! # one table per credential name; an RSU's site entry names one
//! [field-v3]
//! version = "3"
//! user = "roadside"
//! auth = "sha"          # sha | sha224 | sha256 | sha384 | sha512 | md5
//! auth_password = "..."
//! privacy = "aes128"    # aes128 | aes192 | aes256 | des
//! priv_password = "..."
//!
//! [lab-v2c]
//! version = "2c"
//! community = "..."
//! ```
//!
//! Secrets never reach a log: [`Credentials`]'s `Debug` shows the user and the protocols,
//! not the passwords or the community.

use serde::Deserialize;
use std::collections::BTreeMap;
use std::fmt;
use std::path::{Path, PathBuf};

/// SNMPv3 USM authentication protocols (RFC 3414, RFC 7860).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum AuthProtocol {
    /// HMAC-MD5-96 (legacy units only).
    Md5,
    /// HMAC-SHA-96: what deployed RSUs and jpo-ode use.
    Sha,
    /// HMAC-SHA-224.
    Sha224,
    /// HMAC-SHA-256.
    Sha256,
    /// HMAC-SHA-384.
    Sha384,
    /// HMAC-SHA-512.
    Sha512,
}

/// SNMPv3 USM privacy protocols (RFC 3826 and its 192/256-bit extension).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum PrivProtocol {
    /// CBC-DES (legacy units only).
    Des,
    /// CFB128-AES-128: what deployed RSUs use.
    Aes128,
    /// CFB128-AES-192.
    Aes192,
    /// CFB128-AES-256.
    Aes256,
}

/// How the roadside authenticates to one RSU.
#[derive(Clone, PartialEq, Eq)]
pub enum Credentials {
    /// SNMPv3 USM, authPriv: the only level the roadside uses with SNMPv3.
    V3 {
        /// USM user name.
        user: String,
        /// Authentication protocol.
        auth: AuthProtocol,
        /// Authentication password (at least 8 characters, RFC 3414).
        auth_password: String,
        /// Privacy protocol.
        privacy: PrivProtocol,
        /// Privacy password (at least 8 characters).
        priv_password: String,
    },
    /// SNMPv2c with a community: for lab units only.
    V2c {
        /// The read-write community.
        community: String,
    },
}

impl fmt::Debug for Credentials {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::V3 {
                user,
                auth,
                privacy,
                ..
            } => write!(f, "SNMPv3 user {user:?} authPriv {auth:?}/{privacy:?}"),
            Self::V2c { .. } => f.write_str("SNMPv2c (community not shown)"),
        }
    }
}

/// The file's entry, as written.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct Entry {
    version: String,
    user: Option<String>,
    auth: Option<AuthProtocol>,
    auth_password: Option<String>,
    privacy: Option<PrivProtocol>,
    priv_password: Option<String>,
    community: Option<String>,
}

/// Why the credentials file cannot be used.
#[derive(Debug)]
#[non_exhaustive]
pub enum CredentialsError {
    /// It cannot be read.
    Read(PathBuf, std::io::Error),
    /// Others than its owner may read or write it (its mode is shown).
    Permissions(PathBuf, u32),
    /// It is not TOML of the expected shape (the parser's message, which quotes no value
    /// of a secret key: it names the line).
    Format(PathBuf, String),
    /// An entry is incomplete or inconsistent.
    Entry(PathBuf, String, &'static str),
    /// An RSU names an entry the file does not have.
    Unknown(PathBuf, String),
}

impl fmt::Display for CredentialsError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Read(p, e) => write!(f, "credentials file {}: {e}", p.display()),
            Self::Permissions(p, mode) => write!(
                f,
                "credentials file {} has mode {mode:04o}: it holds passwords, make it 0600 \
                 (chmod 600) and owned by the roadside's user",
                p.display()
            ),
            Self::Format(p, e) => write!(f, "credentials file {}: {e}", p.display()),
            Self::Entry(p, name, why) => {
                write!(f, "credentials file {}: entry [{name}]: {why}", p.display())
            }
            Self::Unknown(p, name) => {
                write!(f, "credentials file {} has no entry [{name}]", p.display())
            }
        }
    }
}

impl std::error::Error for CredentialsError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            Self::Read(_, e) => Some(e),
            _ => None,
        }
    }
}

/// The credentials of a file, by entry name.
#[derive(Debug, Clone)]
pub struct CredentialsFile {
    path: PathBuf,
    entries: BTreeMap<String, Credentials>,
}

impl CredentialsFile {
    /// Reads `path`, which must be readable by its owner only (mode 0600 or 0400).
    ///
    /// # Errors
    ///
    /// [`CredentialsError`]: unreadable, too open, malformed or incomplete.
    pub fn load(path: &Path) -> Result<Self, CredentialsError> {
        check_private(path)?;
        let text = std::fs::read_to_string(path)
            .map_err(|e| CredentialsError::Read(path.to_path_buf(), e))?;
        Self::parse(path, &text)
    }

    /// The credentials of `text` (the file `path` names, for messages).
    ///
    /// # Errors
    ///
    /// [`CredentialsError::Format`] / [`CredentialsError::Entry`].
    pub fn parse(path: &Path, text: &str) -> Result<Self, CredentialsError> {
        let raw: BTreeMap<String, Entry> = toml::from_str(text)
            .map_err(|e| CredentialsError::Format(path.to_path_buf(), strip_values(&e, text)))?;
        let mut entries = BTreeMap::new();
        for (name, e) in raw {
            let bad = |why| CredentialsError::Entry(path.to_path_buf(), name.clone(), why);
            let c = entry(e).map_err(bad)?;
            entries.insert(name, c);
        }
        Ok(Self {
            path: path.to_path_buf(),
            entries,
        })
    }

    /// The entry `name`.
    ///
    /// # Errors
    ///
    /// [`CredentialsError::Unknown`].
    pub fn get(&self, name: &str) -> Result<&Credentials, CredentialsError> {
        self.entries
            .get(name)
            .ok_or_else(|| CredentialsError::Unknown(self.path.clone(), name.to_string()))
    }
}

/// Where the file is wrong, without the parser's message (which can quote a value, and so
/// a secret): the line, and what entries look like.
fn strip_values(e: &toml::de::Error, text: &str) -> String {
    let line = e
        .span()
        .map(|s| text[..s.start.min(text.len())].matches('\n').count() + 1)
        .map_or(String::new(), |l| format!("line {l}: "));
    format!(
        "{line}not a credentials entry (tables of `version`, `user`, `auth`, `auth_password`, \
         `privacy`, `priv_password` or `community`, each value a quoted string)"
    )
}

fn entry(e: Entry) -> Result<Credentials, &'static str> {
    match e.version.as_str() {
        "3" => {
            let user = e.user.ok_or("version 3 needs `user`")?;
            let auth_password = e.auth_password.ok_or("version 3 needs `auth_password`")?;
            let priv_password = e.priv_password.ok_or("version 3 needs `priv_password`")?;
            if auth_password.len() < 8 || priv_password.len() < 8 {
                return Err("USM passwords have at least 8 characters (RFC 3414)");
            }
            if e.community.is_some() {
                return Err("`community` belongs to version 2c");
            }
            Ok(Credentials::V3 {
                user,
                auth: e.auth.unwrap_or(AuthProtocol::Sha),
                auth_password,
                privacy: e.privacy.unwrap_or(PrivProtocol::Aes128),
                priv_password,
            })
        }
        "2c" => {
            if e.user.is_some() || e.auth_password.is_some() || e.priv_password.is_some() {
                return Err("version 2c takes only `community`");
            }
            Ok(Credentials::V2c {
                community: e.community.ok_or("version 2c needs `community`")?,
            })
        }
        _ => Err("`version` is \"3\" (USM authPriv) or \"2c\" (lab units)"),
    }
}

/// Refuses a file that its group or others may read or write.
#[cfg(unix)]
fn check_private(path: &Path) -> Result<(), CredentialsError> {
    use std::os::unix::fs::PermissionsExt;
    let meta = std::fs::metadata(path).map_err(|e| CredentialsError::Read(path.into(), e))?;
    let mode = meta.permissions().mode() & 0o7777;
    if mode & 0o077 != 0 {
        return Err(CredentialsError::Permissions(path.into(), mode));
    }
    Ok(())
}

#[cfg(not(unix))]
fn check_private(_: &Path) -> Result<(), CredentialsError> {
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    const FILE: &str = r#"
[field]
version = "3"
user = "roadside"
auth = "sha"
auth_password = "auth-secret-1"
privacy = "aes128"
priv_password = "priv-secret-1"

[lab]
version = "2c"
community = "lab-community"
"#;

    #[test]
    fn parses_both_versions_and_hides_secrets() {
        let f = CredentialsFile::parse(Path::new("c.toml"), FILE).unwrap();
        let field = f.get("field").unwrap();
        assert!(matches!(
            field,
            Credentials::V3 {
                auth: AuthProtocol::Sha,
                ..
            }
        ));
        let shown = format!("{field:?} {:?}", f.get("lab").unwrap());
        assert!(
            !shown.contains("secret") && !shown.contains("lab-community"),
            "{shown}"
        );
        assert!(f.get("other").unwrap_err().to_string().contains("[other]"));
    }

    #[test]
    fn refuses_short_passwords_and_mixed_entries() {
        let short = FILE.replace("auth-secret-1", "short");
        let e = CredentialsFile::parse(Path::new("c.toml"), &short).unwrap_err();
        assert!(e.to_string().contains("at least 8"), "{e}");
        let mixed = format!("{FILE}community = \"x\"\nuser = \"y\"\n");
        assert!(CredentialsFile::parse(Path::new("c.toml"), &mixed).is_err());
        let e = CredentialsFile::parse(Path::new("c.toml"), "[a]\nversion = \"1\"\n");
        assert!(e.unwrap_err().to_string().contains("2c"));
    }

    #[test]
    fn a_format_error_quotes_no_secret() {
        let broken = "[a]\nversion = \"3\"\nauth_password = \"hunter2-secret\" junk\n";
        let e = CredentialsFile::parse(Path::new("c.toml"), broken).unwrap_err();
        assert!(!e.to_string().contains("hunter2"), "{e}");
        assert!(e.to_string().contains("line 3"), "{e}");
        // A secret of the wrong type, which the parser's own message would quote.
        let typed = "[a]\nversion = \"3\"\nauth_password = 31415926535\n";
        let e = CredentialsFile::parse(Path::new("c.toml"), typed).unwrap_err();
        assert!(!e.to_string().contains("31415926535"), "{e}");
    }

    #[cfg(unix)]
    #[test]
    fn refuses_a_file_others_can_read() {
        use std::os::unix::fs::PermissionsExt;
        let dir = std::env::temp_dir().join(format!("cred-test-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("c.toml");
        std::fs::write(&path, FILE).unwrap();
        std::fs::set_permissions(&path, std::fs::Permissions::from_mode(0o644)).unwrap();
        let e = CredentialsFile::load(&path).unwrap_err();
        assert!(e.to_string().contains("0644"), "{e}");
        std::fs::set_permissions(&path, std::fs::Permissions::from_mode(0o600)).unwrap();
        assert!(CredentialsFile::load(&path).is_ok());
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
