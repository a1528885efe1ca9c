//! A live WZDx feed: polled over HTTP(S) at an interval (rustls with the system's trust
//! roots, a timeout, a size cap, `ETag` / `Last-Modified` so an unchanged feed costs a 304),
//! its text handed on only when it changed. A feed that cannot be had or read keeps the
//! last good one; every outcome is counted under a reason of a closed set.

use serde::Deserialize;
use std::collections::BTreeMap;
use std::fmt;
use std::time::Duration;

/// `[wzdx_feed]` of a site file.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FeedConfig {
    /// The feed's URL (`https://…`, or `http://` on a private network).
    pub url: String,
    /// Seconds between polls.
    #[serde(default = "default_poll")]
    pub poll_s: f64,
    /// Timeout of one poll (connect, TLS and body), seconds.
    #[serde(default = "default_timeout")]
    pub timeout_s: f64,
    /// Largest body taken, bytes.
    #[serde(default = "default_max_bytes")]
    pub max_bytes: u64,
    /// How long a signed cancel TIM is sent (immediate forward) for an event that ended
    /// or left the feed, seconds.
    #[serde(default = "default_cancel_for")]
    pub cancel_for_s: f64,
}

fn default_poll() -> f64 {
    60.0
}
fn default_timeout() -> f64 {
    10.0
}
fn default_max_bytes() -> u64 {
    8 << 20
}
fn default_cancel_for() -> f64 {
    600.0
}

/// Why a poll gave no new feed.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum FeedProblem {
    /// No connection (DNS, refused, TLS).
    Unreachable(String),
    /// No complete answer within the timeout.
    Timeout,
    /// An HTTP status other than 200 / 304.
    Status(u16),
    /// A body over the size cap.
    TooLarge(u64),
    /// A body that is not UTF-8 text, or a broken transfer.
    Unreadable(String),
    /// A body that is not a WZDx feed for this road (the parser's message).
    Malformed(String),
}

impl FeedProblem {
    /// The counter name.
    pub const fn reason(&self) -> &'static str {
        match self {
            Self::Unreachable(_) => "unreachable",
            Self::Timeout => "timeout",
            Self::Status(_) => "http_status",
            Self::TooLarge(_) => "too_large",
            Self::Unreadable(_) => "unreadable",
            Self::Malformed(_) => "malformed",
        }
    }
}

impl fmt::Display for FeedProblem {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Unreachable(m) => write!(f, "unreachable: {m}"),
            Self::Timeout => f.write_str("no answer within the timeout"),
            Self::Status(s) => write!(f, "HTTP status {s}"),
            Self::TooLarge(n) => write!(f, "body over {n} bytes"),
            Self::Unreadable(m) => write!(f, "unreadable body: {m}"),
            Self::Malformed(m) => write!(f, "not a usable WZDx feed: {m}"),
        }
    }
}

/// What one poll gave.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum FeedPoll {
    /// A new feed text (first poll, or it changed).
    Changed(String),
    /// The same feed as before (304, or the same body).
    Unchanged,
    /// No usable answer: the last good feed stands.
    Failed(FeedProblem),
}

/// A feed being polled.
#[derive(Debug)]
pub struct FeedPoller {
    url: String,
    max_bytes: u64,
    agent: ureq::Agent,
    etag: Option<String>,
    last_modified: Option<String>,
    last_body: Option<String>,
    /// Outcomes by reason: `changed`, `unchanged`, and each [`FeedProblem::reason`].
    pub counts: BTreeMap<&'static str, u64>,
}

impl FeedPoller {
    /// A poller of `config`'s feed.
    pub fn new(config: &FeedConfig) -> Self {
        use ureq::tls::{RootCerts, TlsConfig};
        let agent = ureq::Agent::config_builder()
            .timeout_global(Some(Duration::from_secs_f64(config.timeout_s.max(0.1))))
            .http_status_as_error(false)
            .max_redirects(3)
            .user_agent("roadside (work-zone V2X)")
            .tls_config(
                TlsConfig::builder()
                    .root_certs(RootCerts::PlatformVerifier)
                    .build(),
            )
            .build()
            .new_agent();
        Self {
            url: config.url.clone(),
            max_bytes: config.max_bytes,
            agent,
            etag: None,
            last_modified: None,
            last_body: None,
            counts: BTreeMap::new(),
        }
    }

    /// Polls the feed once.
    pub fn poll(&mut self) -> FeedPoll {
        let outcome = self.fetch();
        let reason = match &outcome {
            FeedPoll::Changed(_) => "changed",
            FeedPoll::Unchanged => "unchanged",
            FeedPoll::Failed(p) => p.reason(),
        };
        *self.counts.entry(reason).or_default() += 1;
        outcome
    }

    /// The feed text the last poll gave could not be used (the WZDx parser refused it): it
    /// counts as `malformed`, not `changed`, and is forgotten (validators and body), so that
    /// the next poll fetches it whole and it is refused again until it is fixed.
    pub fn refused(&mut self) {
        if let Some(n) = self.counts.get_mut("changed") {
            *n = n.saturating_sub(1);
        }
        *self.counts.entry("malformed").or_default() += 1;
        (self.etag, self.last_modified, self.last_body) = (None, None, None);
    }

    fn fetch(&mut self) -> FeedPoll {
        let mut request = self.agent.get(&self.url);
        if let Some(etag) = &self.etag {
            request = request.header("If-None-Match", etag);
        }
        if let Some(date) = &self.last_modified {
            request = request.header("If-Modified-Since", date);
        }
        let mut response = match request.call() {
            Ok(r) => r,
            Err(e) => return FeedPoll::Failed(problem_of(e, self.max_bytes)),
        };
        match response.status().as_u16() {
            304 => return FeedPoll::Unchanged,
            200 => {}
            other => return FeedPoll::Failed(FeedProblem::Status(other)),
        }
        let header = |name: &str| {
            response
                .headers()
                .get(name)
                .and_then(|v| v.to_str().ok())
                .map(str::to_string)
        };
        let (etag, modified) = (header("etag"), header("last-modified"));
        let body = match response
            .body_mut()
            .with_config()
            .limit(self.max_bytes)
            .read_to_string()
        {
            Ok(b) => b,
            Err(e) => return FeedPoll::Failed(problem_of(e, self.max_bytes)),
        };
        (self.etag, self.last_modified) = (etag, modified);
        if self.last_body.as_deref() == Some(body.as_str()) {
            return FeedPoll::Unchanged;
        }
        self.last_body = Some(body.clone());
        FeedPoll::Changed(body)
    }
}

fn problem_of(e: ureq::Error, max_bytes: u64) -> FeedProblem {
    use ureq::Error as E;
    match e {
        E::Timeout(_) => FeedProblem::Timeout,
        E::BodyExceedsLimit(_) => FeedProblem::TooLarge(max_bytes),
        E::HostNotFound | E::ConnectionFailed | E::BadUri(_) => {
            FeedProblem::Unreachable(e.to_string())
        }
        E::Io(io) if io.kind() == std::io::ErrorKind::TimedOut => FeedProblem::Timeout,
        E::Io(io) if io.kind() == std::io::ErrorKind::InvalidData => {
            FeedProblem::Unreadable(io.to_string())
        }
        E::Io(io) => FeedProblem::Unreachable(io.to_string()),
        other => FeedProblem::Unreadable(other.to_string()),
    }
}
