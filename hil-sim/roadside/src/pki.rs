//! A small IEEE 1609.2 PKI for the roadside and the bench (`roadside pki`): a root, an
//! issuing CA and an RSU certificate (explicit, NIST P-256), written as files; the signer
//! the roadside signs MAP and TIM with is `crate::signer::RsuSigner`.
//!
//! Files in the PKI directory: `root.oer`, `ca.oer`, `rsu.oer` (certificates, COER; the
//! first two are the OBU's trust anchors) and `root.key`, `ca.key`, `rsu.key` (the private
//! scalars as hexadecimal text, mode 0600). A deployment keeps the root and CA keys offline
//! and gives the RSU only `rsu.oer` and `rsu.key`; the OBU only `root.oer` and `ca.oer`.
//!
//! Keys come from the operating system's random source (`/dev/urandom`), or, for
//! reproducible test PKIs, from a seed (`SHA-256("hil-sim pki/" + seed + "/" + role)`, the
//! first candidate that is a valid scalar; the label is fixed so that a seed always gives
//! the same keys, and the committed bench PKI stays reproducible).

mod error;

pub use error::{KeyError, PkiError};

use j2735::envelope::ieee1609dot2::build::{encode_certificate, CertificateSpec, IssuedBy};
use j2735::envelope::ieee1609dot2::crypto::{sha256, SecretKey};
use j2735::envelope::ieee1609dot2::{Duration, TwoDLocation};
use j2735::envelope::Psid;
use std::io::{self, Read};
use std::path::Path;

/// Seconds from 1970-01-01 to 2004-01-01 (the IEEE 1609.2 epoch).
const EPOCH_2004_UNIX_S: u64 = 1_072_915_200;
/// Leap seconds inserted into UTC since 2004 (TAI - UTC grew by this much).
const LEAP_SECONDS_SINCE_2004: u64 = 5;

/// `Time64` (TAI microseconds since 2004) of a Unix time in milliseconds.
pub fn time64_of_unix_ms(unix_ms: u64) -> u64 {
    let since_2004_ms = unix_ms.saturating_sub(EPOCH_2004_UNIX_S * 1000);
    (since_2004_ms + LEAP_SECONDS_SINCE_2004 * 1000) * 1000
}

/// `Time32` (TAI seconds since 2004) of a Unix time in seconds.
pub fn time32_of_unix_s(unix_s: u64) -> u32 {
    let t = unix_s.saturating_sub(EPOCH_2004_UNIX_S) + LEAP_SECONDS_SINCE_2004;
    u32::try_from(t).unwrap_or(u32::MAX)
}

/// The PSID a signed message of J2735 `messageId` carries in its 1609.2 header (the
/// integer): TIM 131, MAP 2113687, SPaT 130, BSM 32, PSM 39 (SAE J2945/9).
pub fn signing_psid(message_id: u16) -> Option<Psid> {
    match message_id {
        31 => Some(Psid::TIM),
        32 => Some(Psid::PSM),
        18 => Some(Psid::MAP),
        19 => Some(Psid::SPAT),
        20 => Some(Psid::BSM),
        _ => None,
    }
}

/// What `roadside pki` makes.
#[derive(Debug, Clone, PartialEq)]
pub struct PkiSpec {
    /// Seed for reproducible keys; `None`: keys from the OS random source.
    pub seed: Option<String>,
    /// Validity start of every certificate, Unix seconds.
    pub start_unix_s: u64,
    /// Root validity, years.
    pub root_years: u16,
    /// CA validity, years (inside the root's).
    pub ca_years: u16,
    /// RSU validity, hours (inside the CA's).
    pub rsu_hours: u16,
    /// The RSU certificate's region: centre (1e-7 degrees) and radius (m); `None`: none.
    pub region: Option<(i32, i32, u16)>,
    /// PSIDs the RSU may sign (the integers).
    pub psids: Vec<Psid>,
    /// The RSU certificate's name.
    pub rsu_name: String,
}

/// A certificate (COER) and its private key.
#[derive(Debug, Clone)]
pub struct Issued {
    /// The certificate, COER.
    pub cert: Vec<u8>,
    /// Its private key.
    pub key: SecretKey,
}

/// A root, an issuing CA and an RSU certificate.
#[derive(Debug, Clone)]
pub struct Pki {
    /// The self-signed root.
    pub root: Issued,
    /// The issuing CA (signed by the root).
    pub ca: Issued,
    /// The RSU (signed by the CA).
    pub rsu: Issued,
}

/// A key for `role`: from the seed, or random.
fn make_key(seed: Option<&str>, role: &str) -> Result<SecretKey, PkiError> {
    for attempt in 0u32..64 {
        let bytes = match seed {
            Some(s) => sha256(format!("hil-sim pki/{s}/{role}/{attempt}").as_bytes()),
            None => {
                let mut b = [0u8; 32];
                std::fs::File::open("/dev/urandom")
                    .and_then(|mut f| f.read_exact(&mut b))
                    .map_err(PkiError::Random)?;
                b
            }
        };
        if let Ok(key) = SecretKey::from_bytes(&bytes) {
            return Ok(key);
        }
    }
    Err(PkiError::NoValidKey)
}

fn certificate(
    spec: &CertificateSpec<'_>,
    key: &SecretKey,
    by: IssuedBy<'_>,
) -> Result<Vec<u8>, PkiError> {
    let mut out = vec![0u8; 1024];
    let n = encode_certificate(spec, key, by, &mut out).map_err(PkiError::Certificate)?;
    out.truncate(n);
    Ok(out)
}

impl Pki {
    /// Makes the three certificates.
    ///
    /// # Errors
    ///
    /// [`PkiError::Validity`] when the validities do not nest, [`PkiError::Random`] when
    /// the random source fails, [`PkiError::Certificate`] when a value does not fit its
    /// field.
    pub fn create(spec: &PkiSpec) -> Result<Self, PkiError> {
        // A certificate's validity must lie within its issuer's (the OBU checks it).
        let (rsu, ca, root) = (
            Duration::Hours(spec.rsu_hours).micros(),
            Duration::Years(spec.ca_years).micros(),
            Duration::Years(spec.root_years).micros(),
        );
        if rsu > ca || ca > root || rsu == 0 {
            return Err(PkiError::Validity {
                rsu_hours: spec.rsu_hours,
                ca_years: spec.ca_years,
                root_years: spec.root_years,
            });
        }
        let seed = spec.seed.as_deref();
        let start = time32_of_unix_s(spec.start_unix_s);
        let root_key = make_key(seed, "root")?;
        let ca_key = make_key(seed, "ca")?;
        let rsu_key = make_key(seed, "rsu")?;
        let root_spec = CertificateSpec {
            name: "root.hil-sim.example",
            start,
            duration: Duration::Years(spec.root_years),
            circle: None,
            app_psids: &[],
            issue_all: Some(2),
            ssp: None,
        };
        let root = certificate(&root_spec, &root_key, IssuedBy::SelfSigned)?;
        let ca_spec = CertificateSpec {
            name: "ca.hil-sim.example",
            duration: Duration::Years(spec.ca_years),
            issue_all: Some(1),
            ssp: None,
            ..root_spec
        };
        let ca = certificate(&ca_spec, &ca_key, IssuedBy::Issuer(&root, &root_key))?;
        let circle = spec.region.map(|(latitude, longitude, radius)| {
            (
                TwoDLocation {
                    latitude,
                    longitude,
                },
                radius,
            )
        });
        let rsu_spec = CertificateSpec {
            name: &spec.rsu_name,
            start,
            duration: Duration::Hours(spec.rsu_hours),
            circle,
            app_psids: &spec.psids,
            issue_all: None,
            ssp: None,
        };
        let rsu = certificate(&rsu_spec, &rsu_key, IssuedBy::Issuer(&ca, &ca_key))?;
        Ok(Self {
            root: Issued {
                cert: root,
                key: root_key,
            },
            ca: Issued {
                cert: ca,
                key: ca_key,
            },
            rsu: Issued {
                cert: rsu,
                key: rsu_key,
            },
        })
    }

    /// Writes the six files into `dir` (created if missing).
    ///
    /// # Errors
    ///
    /// [`PkiError::Io`]: the file system's error, naming the file.
    pub fn write(&self, dir: &Path) -> Result<(), PkiError> {
        std::fs::create_dir_all(dir).map_err(io_error(dir))?;
        for (name, issued) in [("root", &self.root), ("ca", &self.ca), ("rsu", &self.rsu)] {
            let cert = dir.join(format!("{name}.oer"));
            std::fs::write(&cert, &issued.cert).map_err(io_error(&cert))?;
            write_key(&dir.join(format!("{name}.key")), &issued.key)?;
        }
        Ok(())
    }
}

/// A [`PkiError::Io`] naming `path`.
fn io_error(path: &Path) -> impl FnOnce(io::Error) -> PkiError {
    let path = path.to_path_buf();
    move |source| PkiError::Io { path, source }
}

/// Writes a private key as hexadecimal text, readable by the owner only.
fn write_key(path: &Path, key: &SecretKey) -> Result<(), PkiError> {
    use std::io::Write;
    use std::os::unix::fs::OpenOptionsExt;
    let text = format!("{}\n", j2735::hex::Hex(&key.to_bytes()));
    std::fs::OpenOptions::new()
        .write(true)
        .create(true)
        .truncate(true)
        .mode(0o600)
        .open(path)
        .and_then(|mut f| f.write_all(text.as_bytes()))
        .map_err(io_error(path))
}

/// Reads a private key file (hexadecimal text of the 32-octet scalar).
///
/// # Errors
///
/// [`PkiError::Io`] or [`PkiError::Key`], naming the file.
pub fn read_key(path: &Path) -> Result<SecretKey, PkiError> {
    let text = std::fs::read_to_string(path).map_err(io_error(path))?;
    read_key_text(&text).map_err(|source| PkiError::Key {
        path: path.to_path_buf(),
        source,
    })
}

/// A private key from its file's text (hexadecimal, 32 octets; surrounding blanks ignored).
///
/// # Errors
///
/// [`KeyError`]: what is wrong with the text.
pub fn read_key_text(text: &str) -> Result<SecretKey, KeyError> {
    let mut bytes = [0u8; 32];
    let n = j2735::hex::decode_into(text.trim(), &mut bytes).map_err(KeyError::Hex)?;
    if n != 32 {
        return Err(KeyError::Length { octets: n });
    }
    SecretKey::from_bytes(&bytes).map_err(KeyError::Scalar)
}

#[cfg(test)]
mod tests {
    use super::*;
    use j2735::envelope::ieee1609dot2::Certificate;

    fn spec() -> PkiSpec {
        PkiSpec {
            seed: Some("test".into()),
            start_unix_s: 1_767_225_600, // 2026-01-01
            root_years: 10,
            ca_years: 5,
            rsu_hours: 24 * 365,
            region: Some((421_234_567, -837_654_321, 20_000)),
            psids: vec![Psid::TIM, Psid::MAP],
            rsu_name: "rsu.hil-sim.example".into(),
        }
    }

    #[test]
    fn a_seeded_pki_is_reproducible_and_well_formed() {
        let a = Pki::create(&spec()).unwrap();
        let b = Pki::create(&spec()).unwrap();
        assert_eq!(
            (&a.root.cert, &a.ca.cert, &a.rsu.cert),
            (&b.root.cert, &b.ca.cert, &b.rsu.cert)
        );
        let rsu = Certificate::parse(&a.rsu.cert).unwrap();
        assert!(rsu.permission(Psid::TIM).is_some() && rsu.permission(Psid::MAP).is_some());
        assert_eq!(rsu.validity.start.0, time32_of_unix_s(1_767_225_600));
    }

    #[test]
    fn validity_must_nest() {
        let long_rsu = PkiSpec {
            rsu_hours: 2730 * 24,
            ..spec()
        };
        let err = Pki::create(&long_rsu).unwrap_err();
        assert!(
            matches!(err, PkiError::Validity { rsu_hours, .. } if rsu_hours == 2730 * 24),
            "{err:?}"
        );
        assert!(err.to_string().contains("within the CA"));
        let ok = PkiSpec {
            ca_years: 15,
            root_years: 20,
            ..long_rsu
        };
        assert!(Pki::create(&ok).is_ok());
    }

    #[test]
    fn files_round_trip_and_keys_are_private() {
        use std::os::unix::fs::PermissionsExt;
        let dir = std::env::temp_dir().join(format!("pki-test-{}", std::process::id()));
        let pki = Pki::create(&spec()).unwrap();
        pki.write(&dir).unwrap();
        let mode = std::fs::metadata(dir.join("rsu.key"))
            .unwrap()
            .permissions()
            .mode();
        assert_eq!(mode & 0o077, 0, "rsu.key is not readable by others");
        assert_eq!(std::fs::read(dir.join("rsu.oer")).unwrap(), pki.rsu.cert);
        assert_eq!(
            read_key(&dir.join("ca.key")).unwrap().to_bytes(),
            pki.ca.key.to_bytes()
        );
        std::fs::write(dir.join("rsu.key"), "zz\n").unwrap();
        match read_key(&dir.join("rsu.key")) {
            Err(PkiError::Key {
                path,
                source: KeyError::Hex(_),
            }) => assert_eq!(path, dir.join("rsu.key")),
            other => panic!("{other:?}"),
        }
        std::fs::write(dir.join("rsu.key"), "00ff\n").unwrap();
        assert!(matches!(
            read_key(&dir.join("rsu.key")),
            Err(PkiError::Key {
                source: KeyError::Length { octets: 2 },
                ..
            })
        ));
        let _ = std::fs::remove_dir_all(&dir);
    }
}
