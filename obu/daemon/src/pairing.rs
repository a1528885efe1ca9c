//! Pairing: only a tablet that knows the unit's PIN may change settings.
//!
//! The PIN is configured (`[http] pin`) or made at random on the first start (6 digits)
//! and kept in the pairing file beside the settings file, so it stays the same across
//! restarts; the daemon prints it in its log at every start. A tablet sends it once
//! (`POST /api/pair`) and gets a session token (256 random bits) in an `HttpOnly;
//! SameSite=Strict` cookie; every write must carry it. At most [`MAX_SESSIONS`] sessions are
//! kept (the least recently used one makes room), in the pairing file too, so a paired
//! tablet stays paired across restarts. PINs and tokens are compared in constant time.
//!
//! Guessing is bounded: [`FREE_TRIES`] wrong PINs in a row lock pairing for
//! [`FIRST_LOCKOUT`]; each further wrong PIN before a right one locks it for twice as long
//! as the last lockout, up to [`MAX_LOCKOUT`]. While locked every PIN, right or wrong, is
//! refused unchecked.

use serde::{Deserialize, Serialize};
use std::io::{Read, Write};
use std::path::{Path, PathBuf};
use std::sync::{Mutex, MutexGuard};
use std::time::{Duration, Instant};

/// Sessions kept at most.
pub const MAX_SESSIONS: usize = 16;
/// Wrong PINs in a row before the first lockout.
pub const FREE_TRIES: u32 = 5;
/// The first lockout.
pub const FIRST_LOCKOUT: Duration = Duration::from_secs(30);
/// The longest lockout.
pub const MAX_LOCKOUT: Duration = Duration::from_secs(15 * 60);
/// The session cookie's name.
pub const COOKIE: &str = "obu_session";

/// Octets of a session token.
const TOKEN_LEN: usize = 32;

/// What a pairing attempt got.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Attempt {
    /// The right PIN: the new session's token (hexadecimal), for the cookie.
    Paired(String),
    /// A wrong PIN; this many more are allowed before a lockout.
    WrongPin {
        /// Wrong PINs left before pairing locks.
        left: u32,
    },
    /// Pairing is locked for this long; the PIN was not checked.
    Locked(Duration),
    /// The right PIN, but no token could be made (the random source failed).
    Unavailable,
}

/// The pairing file's content.
#[derive(Debug, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct Stored {
    /// The PIN made on the first start; absent when it is configured.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pin: Option<String>,
    /// Session tokens, hexadecimal, least recently paired first.
    #[serde(default)]
    sessions: Vec<String>,
}

#[derive(Debug)]
struct Session {
    token: [u8; TOKEN_LEN],
    last_used: Instant,
}

#[derive(Debug, Default)]
struct State {
    sessions: Vec<Session>,
    wrong_in_a_row: u32,
    last_lockout: Option<Duration>,
    locked_until: Option<Instant>,
}

/// The PIN, the sessions and the guess limit.
#[derive(Debug)]
pub struct Pairing {
    pin: String,
    /// Whether the PIN came from the configuration (else it is kept in the file).
    configured: bool,
    file: PathBuf,
    state: Mutex<State>,
}

impl Pairing {
    /// Loads the pairing file at `file` (its sessions, and its PIN unless `configured_pin`
    /// is given); on the first start makes a PIN and saves it. The error says what failed.
    pub fn load(configured_pin: Option<&str>, file: &Path) -> Result<Self, String> {
        let shown = file.display();
        let stored = match std::fs::read_to_string(file) {
            Ok(text) => serde_json::from_str::<Stored>(&text)
                .map_err(|e| format!("{shown}: {e} (remove it to pair again)"))?,
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => Stored::default(),
            Err(e) => return Err(format!("cannot read {shown}: {e}")),
        };
        random_bytes::<1>().map_err(|e| format!("no random source (/dev/urandom): {e}"))?;
        let now = Instant::now();
        let sessions = stored
            .sessions
            .iter()
            .filter_map(|t| from_hex(t))
            .map(|token| Session {
                token,
                last_used: now,
            })
            .collect();
        let (pin, configured, made) = match (configured_pin, stored.pin) {
            (Some(p), _) => (p.to_owned(), true, false),
            (None, Some(p)) if valid_pin(&p) => (p, false, false),
            (None, _) => (random_pin()?, false, true),
        };
        let pairing = Self {
            pin,
            configured,
            file: file.to_owned(),
            state: Mutex::new(State {
                sessions,
                ..State::default()
            }),
        };
        if made {
            // A made PIN must be kept, or the next start would make another.
            pairing
                .save()
                .map_err(|e| format!("cannot write {shown}: {e}"))?;
        }
        Ok(pairing)
    }

    /// The PIN, for the log.
    pub fn pin(&self) -> &str {
        &self.pin
    }

    /// Whether the PIN is the configured one (else it was made and kept in the file).
    pub fn configured(&self) -> bool {
        self.configured
    }

    fn lock(&self) -> MutexGuard<'_, State> {
        self.state.lock().unwrap_or_else(|p| p.into_inner())
    }

    /// One pairing attempt with `pin`, at `now`.
    pub fn attempt(&self, pin: &str, now: Instant) -> Attempt {
        let mut s = self.lock();
        if let Some(until) = s.locked_until {
            if now < until {
                return Attempt::Locked(until - now);
            }
            s.locked_until = None;
        }
        if !ct_eq(pin.as_bytes(), self.pin.as_bytes()) {
            s.wrong_in_a_row += 1;
            if s.wrong_in_a_row < FREE_TRIES {
                return Attempt::WrongPin {
                    left: FREE_TRIES - s.wrong_in_a_row,
                };
            }
            let lockout = s
                .last_lockout
                .map_or(FIRST_LOCKOUT, |d| (d * 2).min(MAX_LOCKOUT));
            s.last_lockout = Some(lockout);
            s.locked_until = Some(now + lockout);
            return Attempt::Locked(lockout);
        }
        s.wrong_in_a_row = 0;
        s.last_lockout = None;
        let Ok(token) = random_bytes::<TOKEN_LEN>() else {
            return Attempt::Unavailable;
        };
        if s.sessions.len() >= MAX_SESSIONS {
            if let Some(oldest) = (0..s.sessions.len()).min_by_key(|&i| s.sessions[i].last_used) {
                s.sessions.remove(oldest);
            }
        }
        s.sessions.push(Session {
            token,
            last_used: now,
        });
        drop(s);
        if let Err(e) = self.save() {
            let text = format!(
                "cannot save {}: {e} (the pairing holds until a restart)",
                self.file.display()
            );
            crate::log::warn("pairing", &text);
        }
        Attempt::Paired(hex(&token))
    }

    /// Whether the `Cookie` header values carry a session token of this unit.
    pub fn authorised<'a>(&self, cookies: impl Iterator<Item = &'a str>, now: Instant) -> bool {
        let Some(token) = session_cookie(cookies).and_then(from_hex) else {
            return false;
        };
        let mut s = self.lock();
        let mut found = None;
        for (i, session) in s.sessions.iter().enumerate() {
            // Compare with every session: the time taken does not tell which one matched.
            if ct_eq(&session.token, &token) {
                found = Some(i);
            }
        }
        match found {
            Some(i) => {
                s.sessions[i].last_used = now;
                true
            }
            None => false,
        }
    }

    /// Sessions kept now.
    pub fn sessions(&self) -> usize {
        self.lock().sessions.len()
    }

    /// How long pairing stays locked from `now`; zero when it is not.
    pub fn locked_for(&self, now: Instant) -> Duration {
        self.lock()
            .locked_until
            .map_or(Duration::ZERO, |u| u.saturating_duration_since(now))
    }

    /// Writes the pairing file atomically, readable by the owner only.
    fn save(&self) -> std::io::Result<()> {
        let mut sessions: Vec<(Instant, String)> = self
            .lock()
            .sessions
            .iter()
            .map(|s| (s.last_used, hex(&s.token)))
            .collect();
        sessions.sort();
        let stored = Stored {
            pin: (!self.configured).then(|| self.pin.clone()),
            sessions: sessions.into_iter().map(|(_, t)| t).collect(),
        };
        let text = serde_json::to_string_pretty(&stored)?;
        let tmp = crate::settings::temp_beside(&self.file);
        {
            let mut options = std::fs::OpenOptions::new();
            options.write(true).create(true).truncate(true);
            #[cfg(unix)]
            std::os::unix::fs::OpenOptionsExt::mode(&mut options, 0o600);
            let mut f = options.open(&tmp)?;
            f.write_all(text.as_bytes())?;
            f.write_all(b"\n")?;
            f.sync_all()?;
        }
        std::fs::rename(&tmp, &self.file)
    }
}

/// Whether `pin` is a PIN the daemon takes: 4 to 32 letters or digits.
pub fn valid_pin(pin: &str) -> bool {
    (4..=32).contains(&pin.len()) && pin.bytes().all(|b| b.is_ascii_alphanumeric())
}

/// The `Set-Cookie` value that hands `token` to the tablet.
pub fn set_cookie(token: &str) -> String {
    format!("{COOKIE}={token}; HttpOnly; SameSite=Strict; Path=/; Max-Age=31536000")
}

/// The value of the session cookie among `Cookie` header values.
fn session_cookie<'a>(cookies: impl Iterator<Item = &'a str>) -> Option<&'a str> {
    cookies
        .flat_map(|h| h.split(';'))
        .filter_map(|pair| pair.trim().split_once('='))
        .find(|(name, _)| *name == COOKIE)
        .map(|(_, value)| value.trim())
}

/// Equal lengths and octets, in a time that depends on the length only.
fn ct_eq(a: &[u8], b: &[u8]) -> bool {
    if a.len() != b.len() {
        return false;
    }
    let diff = a.iter().zip(b).fold(0u8, |acc, (x, y)| acc | (x ^ y));
    std::hint::black_box(diff) == 0
}

/// `N` octets from the kernel's random source.
fn random_bytes<const N: usize>() -> std::io::Result<[u8; N]> {
    let mut out = [0u8; N];
    std::fs::File::open("/dev/urandom")?.read_exact(&mut out)?;
    Ok(out)
}

/// Six random digits, uniform (a 32-bit draw under the largest multiple of 10^6 kept).
fn random_pin() -> Result<String, String> {
    const LIMIT: u32 = u32::MAX - u32::MAX % 1_000_000;
    loop {
        let n = u32::from_le_bytes(
            random_bytes::<4>().map_err(|e| format!("no random source (/dev/urandom): {e}"))?,
        );
        if n < LIMIT {
            return Ok(format!("{:06}", n % 1_000_000));
        }
    }
}

fn hex(bytes: &[u8]) -> String {
    bytes.iter().map(|b| format!("{b:02x}")).collect()
}

fn from_hex(text: &str) -> Option<[u8; TOKEN_LEN]> {
    let t = text.as_bytes();
    if t.len() != 2 * TOKEN_LEN {
        return None;
    }
    let digit = |c: u8| (c as char).to_digit(16).map(|d| d as u8);
    let mut out = [0u8; TOKEN_LEN];
    for (i, o) in out.iter_mut().enumerate() {
        *o = digit(t[2 * i])? << 4 | digit(t[2 * i + 1])?;
    }
    Some(out)
}

#[cfg(test)]
mod tests;
