//! [`RsuSigner`]: signs J2735 frames as an RSU, in either of the two ways deployed roadsides
//! do ([`SigningPattern`]), with the signer certificate in every message or once in a while
//! (a `digest` signer in between).

use crate::pki::{signing_psid, time64_of_unix_ms, PkiError};
use j2735::envelope::ieee1609dot2::build::{encode_signed, BuildError, Header, Signer};
use j2735::envelope::ieee1609dot2::crypto::{sha256, RSigForm, SecretKey};
use j2735::envelope::ieee1609dot2::{Certificate, DecodeError, ThreeDLocation, Time64};
use std::fmt;
use std::io;
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex, PoisonError};

/// Why a PKI folder gives no signer ([`RsuSigner::load`]).
#[derive(Debug)]
#[non_exhaustive]
pub enum SignerLoadError {
    /// The certificate file could not be read.
    Io {
        /// The certificate file (`rsu.oer`).
        path: PathBuf,
        /// The file system's error.
        source: io::Error,
    },
    /// The certificate file is not an IEEE 1609.2 certificate.
    Certificate {
        /// The certificate file (`rsu.oer`).
        path: PathBuf,
        /// Why it does not parse.
        source: DecodeError,
    },
    /// The key file (`rsu.key`) could not be read or is not a key.
    Key(PkiError),
}

impl fmt::Display for SignerLoadError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Io { path, source } => write!(f, "{}: {source}", path.display()),
            Self::Certificate { path, source } => write!(f, "{}: {source}", path.display()),
            Self::Key(e) => e.fmt(f),
        }
    }
}

impl std::error::Error for SignerLoadError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            Self::Io { source, .. } => Some(source),
            Self::Certificate { source, .. } => Some(source),
            Self::Key(e) => Some(e),
        }
    }
}

impl From<PkiError> for SignerLoadError {
    fn from(e: PkiError) -> Self {
        Self::Key(e)
    }
}

/// Why a frame could not be signed.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[non_exhaustive]
pub enum SignError {
    /// The frame is shorter than its two-octet `messageId`.
    ShortFrame,
    /// The frame's message has no PSID to sign it under ([`signing_psid`]).
    NoPsid {
        /// The J2735 `messageId`.
        message_id: u16,
    },
    /// The signed data could not be encoded.
    Encode(BuildError),
}

impl fmt::Display for SignError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::ShortFrame => f.write_str("frame shorter than its messageId"),
            Self::NoPsid { message_id } => write!(f, "no PSID for messageId {message_id}"),
            Self::Encode(e) => write!(f, "{e:?}"),
        }
    }
}

impl std::error::Error for SignError {}

/// How an RSU signs what it broadcasts again and again.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum SigningPattern {
    /// Each transmission signed anew, generated when sent (V2X-Hub's way).
    #[default]
    PerTransmission,
    /// Each distinct message signed once and the same bytes sent until its expiry time, then
    /// signed anew: how USDOT's jpo-ode deposits TIMs in an RSU's store-and-repeat table.
    /// The first signature's generation time is `signed_ago_ms` before the message was
    /// first sent (the TIM was deposited that long before the drive).
    Once {
        /// How long before its first transmission the message was signed.
        signed_ago_ms: u64,
    },
}

/// Messages signed once and kept for repeating, at most this many (the oldest leave first).
const MAX_KEPT: usize = 64;

/// What the signer remembers between messages.
#[derive(Debug, Default)]
struct SignState {
    /// When the certificate was last sent whole (Unix ms).
    certificate_sent_ms: Option<u64>,
    /// [`SigningPattern::Once`]: (SHA-256 of the frame, expiry Unix ms, the signed bytes).
    kept: Vec<([u8; 32], u64, Vec<u8>)>,
}

/// Signs J2735 frames as an RSU: its certificate and key.
#[derive(Debug, Clone)]
pub struct RsuSigner {
    cert: Vec<u8>,
    key: SecretKey,
    location: Option<ThreeDLocation>,
    lifetime_ms: u64,
    pattern: SigningPattern,
    certificate_every_ms: Option<u64>,
    state: Arc<Mutex<SignState>>,
}

impl RsuSigner {
    /// A signer with `cert` (COER) and its `key`; messages expire `lifetime_ms` after they
    /// are generated, carry `location` as generationLocation, are signed per transmission
    /// and carry the whole certificate.
    pub fn new(
        cert: Vec<u8>,
        key: SecretKey,
        location: Option<ThreeDLocation>,
        lifetime_ms: u64,
    ) -> Self {
        Self {
            cert,
            key,
            location,
            lifetime_ms,
            pattern: SigningPattern::PerTransmission,
            certificate_every_ms: None,
            state: Arc::default(),
        }
    }

    /// The same signer signing by `pattern`, messages expiring `lifetime_ms` after their
    /// generation.
    #[must_use]
    pub fn with_pattern(mut self, pattern: SigningPattern, lifetime_ms: u64) -> Self {
        self.pattern = pattern;
        self.lifetime_ms = lifetime_ms;
        self
    }

    /// The same signer sending its certificate whole at most once every `ms` and naming it by
    /// `digest` in between (per-transmission signing; a message signed once carries it).
    #[must_use]
    pub fn with_certificate_every(mut self, ms: u64) -> Self {
        self.certificate_every_ms = Some(ms);
        self
    }

    /// The same signer with all three settings: [`RsuSigner::with_pattern`], and
    /// [`RsuSigner::with_certificate_every`] when `certificate_every_ms` is given.
    #[must_use]
    pub fn signing(
        self,
        pattern: SigningPattern,
        lifetime_ms: u64,
        certificate_every_ms: Option<u64>,
    ) -> Self {
        let signer = self.with_pattern(pattern, lifetime_ms);
        match certificate_every_ms {
            Some(ms) => signer.with_certificate_every(ms),
            None => signer,
        }
    }

    /// The signer of the PKI directory `dir` (`rsu.oer`, `rsu.key`), 60 s lifetime.
    ///
    /// # Errors
    ///
    /// [`SignerLoadError`], naming the missing or malformed file.
    pub fn load(dir: &Path, location: Option<ThreeDLocation>) -> Result<Self, SignerLoadError> {
        let path = dir.join("rsu.oer");
        let cert = match std::fs::read(&path) {
            Ok(cert) => cert,
            Err(source) => return Err(SignerLoadError::Io { path, source }),
        };
        if let Err(source) = Certificate::parse(&cert) {
            return Err(SignerLoadError::Certificate { path, source });
        }
        let key = crate::pki::read_key(&dir.join("rsu.key"))?;
        Ok(Self::new(cert, key, location, 60_000))
    }

    /// The certificate.
    pub fn certificate(&self) -> &[u8] {
        &self.cert
    }

    /// `frame` as IEEE 1609.2 signed data to send at `unix_ms` (PSID by its message): signed
    /// now, or, signing once, the bytes signed before while they have not expired.
    ///
    /// # Errors
    ///
    /// [`SignError`]: a frame of a message without a PSID, or one too large.
    pub fn sign(&self, frame: &[u8], unix_ms: u64) -> Result<Vec<u8>, SignError> {
        let mut state = self.state.lock().unwrap_or_else(PoisonError::into_inner);
        match self.pattern {
            SigningPattern::PerTransmission => {
                let whole = self.certificate_every_ms.is_none_or(|every| {
                    state
                        .certificate_sent_ms
                        .is_none_or(|sent| unix_ms.saturating_sub(sent) >= every)
                });
                if whole {
                    state.certificate_sent_ms = Some(unix_ms);
                }
                self.sign_at(frame, unix_ms, whole)
            }
            SigningPattern::Once { signed_ago_ms } => {
                let digest = sha256(frame);
                state.kept.retain(|(_, expiry, _)| *expiry > unix_ms);
                if let Some((_, _, bytes)) = state.kept.iter().find(|(d, _, _)| *d == digest) {
                    return Ok(bytes.clone());
                }
                let generated = unix_ms.saturating_sub(signed_ago_ms);
                let bytes = self.sign_at(frame, generated, true)?;
                if state.kept.len() >= MAX_KEPT {
                    state.kept.remove(0);
                }
                let expiry = generated.saturating_add(self.lifetime_ms);
                state.kept.push((digest, expiry, bytes.clone()));
                Ok(bytes)
            }
        }
    }

    /// `frame` signed once at `unix_ms` with the whole certificate and an expiry time of
    /// `expiry_unix_ms` (a message deposited in an RSU's store-and-repeat table until its
    /// end): the bytes signed before for the same frame and expiry while they are kept.
    ///
    /// # Errors
    ///
    /// As [`RsuSigner::sign`].
    pub fn sign_until(
        &self,
        frame: &[u8],
        unix_ms: u64,
        expiry_unix_ms: u64,
    ) -> Result<Vec<u8>, SignError> {
        let mut state = self.state.lock().unwrap_or_else(PoisonError::into_inner);
        let digest = sha256(frame);
        state.kept.retain(|(_, expiry, _)| *expiry > unix_ms);
        let kept = state
            .kept
            .iter()
            .find(|(d, expiry, _)| *d == digest && *expiry == expiry_unix_ms);
        if let Some((_, _, bytes)) = kept {
            return Ok(bytes.clone());
        }
        let lifetime_ms = expiry_unix_ms.saturating_sub(unix_ms).max(1);
        let signer = Self {
            lifetime_ms,
            ..self.clone()
        };
        let bytes = signer.sign_at(frame, unix_ms, true)?;
        if state.kept.len() >= MAX_KEPT {
            state.kept.remove(0);
        }
        state.kept.push((digest, expiry_unix_ms, bytes.clone()));
        Ok(bytes)
    }

    /// `frame` signed with generation time `unix_ms`, the certificate whole or by digest.
    fn sign_at(&self, frame: &[u8], unix_ms: u64, whole: bool) -> Result<Vec<u8>, SignError> {
        let id = match frame {
            [hi, lo, ..] => u16::from_be_bytes([*hi, *lo]),
            _ => return Err(SignError::ShortFrame),
        };
        let psid = signing_psid(id).ok_or(SignError::NoPsid { message_id: id })?;
        let generated = time64_of_unix_ms(unix_ms);
        let header = Header {
            psid,
            generation_time: Time64(generated),
            expiry_time: Some(Time64(generated + self.lifetime_ms * 1000)),
            generation_location: self.location,
        };
        let signer = if whole {
            Signer::Certificate(&self.cert)
        } else {
            Signer::Digest(&self.cert)
        };
        let mut out = vec![0u8; frame.len() + self.cert.len() + 160];
        let n = encode_signed(frame, &header, signer, &self.key, RSigForm::XOnly, &mut out)
            .map_err(SignError::Encode)?;
        out.truncate(n);
        Ok(out)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::pki::{Pki, PkiSpec};
    use j2735::envelope::ieee1609dot2::{Ieee1609Dot2Data, SignerIdentifier};
    use j2735::envelope::Psid;

    fn spec() -> PkiSpec {
        PkiSpec {
            seed: Some("signer test".into()),
            start_unix_s: 1_735_689_600,
            root_years: 10,
            ca_years: 5,
            rsu_hours: 24 * 365,
            region: None,
            psids: vec![Psid::TIM, Psid::MAP],
            rsu_name: "rsu.signer.test".into(),
        }
    }

    fn signer() -> RsuSigner {
        let pki = Pki::create(&spec()).unwrap();
        RsuSigner::new(pki.rsu.cert, pki.rsu.key, None, 60_000)
    }

    const TIM: [u8; 4] = [0x00, 0x1F, 0x01, 0x02];
    const T0: u64 = 1_767_225_600_000;

    fn header_times(bytes: &[u8]) -> (u64, u64) {
        let data = Ieee1609Dot2Data::parse(bytes).unwrap();
        let h = data.signed_data().unwrap().header;
        (h.generation_time.unwrap().0, h.expiry_time.unwrap().0)
    }

    #[test]
    fn signed_frames_parse_with_the_psid_of_their_message() {
        let signer = signer();
        let frame = [0x00, 0x1f, 0x01, 0x02];
        let bytes = signer.sign(&frame, 1_767_225_600_000).unwrap();
        let data = Ieee1609Dot2Data::parse(&bytes).unwrap();
        let signed = data.signed_data().unwrap();
        assert_eq!(signed.header.psid, Psid::TIM);
        assert_eq!(data.application_data(), Some(&frame[..]));
        assert_eq!(
            signer.sign(&[0x00, 0x99], 0),
            Err(SignError::NoPsid { message_id: 0x99 })
        );
        assert_eq!(signer.sign(&[0x00], 0), Err(SignError::ShortFrame));
        // 2026-01-01T00:00:00Z is 8036 days (22 years, 6 of them leap) after 2004 in UTC,
        // 694 310 400 s, plus 5 leap seconds.
        assert_eq!(
            signed.header.generation_time.unwrap().0,
            694_310_405_000_000
        );
    }

    #[test]
    fn a_pki_folder_loads_and_a_bad_key_is_named() {
        let dir = std::env::temp_dir().join(format!("signer-test-{}", std::process::id()));
        let pki = Pki::create(&spec()).unwrap();
        pki.write(&dir).unwrap();
        assert_eq!(
            RsuSigner::load(&dir, None).unwrap().certificate(),
            &pki.rsu.cert[..]
        );
        std::fs::write(dir.join("rsu.key"), "zz\n").unwrap();
        let err = RsuSigner::load(&dir, None).unwrap_err();
        assert!(err.to_string().contains("rsu.key"), "{err}");
        assert!(
            matches!(err, SignerLoadError::Key(PkiError::Key { .. })),
            "{err:?}"
        );
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn signed_once_the_same_bytes_repeat_until_they_expire() {
        let hour = 3_600_000;
        let once = signer().with_pattern(
            SigningPattern::Once {
                signed_ago_ms: 2 * hour,
            },
            24 * hour,
        );
        let first = once.sign(&TIM, T0).unwrap();
        let (generated, expiry) = header_times(&first);
        assert_eq!(generated, time64_of_unix_ms(T0 - 2 * hour));
        assert_eq!(expiry - generated, 24 * hour * 1000);
        for k in 1..100 {
            assert_eq!(once.sign(&TIM, T0 + k * 100).unwrap(), first);
        }
        // Another message is signed on its own; past the expiry the TIM is signed anew.
        assert_ne!(once.sign(&[0x00, 0x12, 0x05], T0).unwrap(), first);
        let later = once.sign(&TIM, T0 + 22 * hour + 1).unwrap();
        assert_ne!(later, first);
        assert_eq!(
            header_times(&later).0,
            time64_of_unix_ms(T0 + 20 * hour + 1)
        );
    }

    #[test]
    fn the_certificate_goes_whole_once_a_second_and_by_digest_between() {
        let s = signer().with_certificate_every(1000);
        let kinds: Vec<bool> = (0..25)
            .map(|k| {
                let bytes = s.sign(&TIM, T0 + k * 100).unwrap();
                let data = Ieee1609Dot2Data::parse(&bytes).unwrap();
                matches!(
                    data.signed_data().unwrap().signer,
                    SignerIdentifier::Certificate(_)
                )
            })
            .collect();
        let whole: Vec<usize> = (0..25).filter(|&k| kinds[k]).collect();
        assert_eq!(whole, [0, 10, 20]);
        // Per transmission: every frame its own signature.
        assert_ne!(
            s.sign(&TIM, T0 + 3000).unwrap(),
            s.sign(&TIM, T0 + 3001).unwrap()
        );
    }
}
