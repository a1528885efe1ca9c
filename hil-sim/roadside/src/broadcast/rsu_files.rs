//! RSU 4.1 text records (`Version=0.7`) of the messages, and the files a roadside unit
//! reads them from.

use super::message::{Message, MessageKind};
use crate::clock::Utc;
use j2735::envelope::rsu_text::{RsuMessage, RsuPayload, RsuWriteError, TxChannel, TxMode};
use j2735::envelope::Psid;
use std::path::{Path, PathBuf};
use std::{fmt, fs, io};

/// How the roadside unit sends a record's message.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RsuDelivery {
    /// Immediate forward: sent once per record received (UDP port 1516); written with
    /// `TxInterval=0` and no delivery window.
    ImmediateForward,
    /// Store and repeat: sent every `interval_ms` between the two times (Unix ms, written
    /// `MM/DD/YYYY, HH:MM` in UTC).
    StoreAndRepeat {
        /// Start of broadcasting.
        start_unix_ms: u64,
        /// End of broadcasting.
        stop_unix_ms: u64,
    },
}

/// The header fields of RSU records.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct RsuOptions {
    /// `PSID`; `None`: [`MessageKind::default_psid`] of each message.
    pub psid: Option<Psid>,
    /// `TxChannel` (172 in most deployments, 183 for C-V2X).
    pub channel: TxChannel,
    /// `TxInterval` of store-and-repeat records, written as given (milliseconds).
    pub interval_ms: u32,
    /// `TxMode`.
    pub tx_mode: TxMode,
    /// `Priority`, 0-7.
    pub priority: u8,
    /// Immediate forward or store and repeat.
    pub delivery: RsuDelivery,
    /// `Signature`: ask the RSU to sign (the payload stays the bare frame).
    pub sign: bool,
    /// `Encryption`.
    pub encrypt: bool,
}

impl Default for RsuOptions {
    /// Per-kind PSID, channel 172, 100 ms, continuous, priority 5, immediate forward,
    /// neither signed nor encrypted.
    fn default() -> Self {
        Self {
            psid: None,
            channel: TxChannel::Number(172),
            interval_ms: 100,
            tx_mode: TxMode::Continuous,
            priority: 5,
            delivery: RsuDelivery::ImmediateForward,
            sign: false,
            encrypt: false,
        }
    }
}

/// Why RSU records could not be written.
#[derive(Debug)]
#[non_exhaustive]
pub enum RsuFileError {
    /// A message with no PSID of its own and none given.
    NoPsid {
        /// Index of the message.
        index: usize,
        /// Its kind.
        kind: MessageKind,
    },
    /// A message whose kind has no RSU `Type` name.
    NoType {
        /// Index of the message.
        index: usize,
        /// Its kind.
        kind: MessageKind,
    },
    /// A priority above 7.
    Priority {
        /// The value.
        value: u8,
    },
    /// A store-and-repeat window that ends before it starts.
    Window {
        /// Start, Unix ms.
        start_unix_ms: u64,
        /// Stop, Unix ms.
        stop_unix_ms: u64,
    },
    /// The codec's writer refused the record.
    Record {
        /// Index of the message.
        index: usize,
        /// The writer's error.
        error: RsuWriteError,
    },
    /// A file or the directory could not be written.
    Io {
        /// The path.
        path: PathBuf,
        /// The error.
        error: io::Error,
    },
}

impl fmt::Display for RsuFileError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::NoPsid { index, kind } => write!(
                f,
                "message {index} ({kind}) has no usual PSID; give one in RsuOptions::psid"
            ),
            Self::NoType { index, kind } => {
                write!(f, "message {index} ({kind}) has no RSU record Type name")
            }
            Self::Priority { value } => write!(f, "priority {value}; it must be 0 to 7"),
            Self::Window {
                start_unix_ms,
                stop_unix_ms,
            } => write!(
                f,
                "delivery stops (Unix ms {stop_unix_ms}) before it starts ({start_unix_ms})"
            ),
            Self::Record { index, error } => write!(f, "message {index}: {error}"),
            Self::Io { path, error } => write!(f, "{}: {error}", path.display()),
        }
    }
}

impl std::error::Error for RsuFileError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            Self::Io { error, .. } => Some(error),
            Self::Record { error, .. } => Some(error),
            _ => None,
        }
    }
}

/// The `Version=0.7` RSU record of `message` (the `index`-th of a set, for errors).
///
/// # Errors
///
/// [`RsuFileError`] for a message without PSID or type name, a priority above 7, a
/// delivery window that ends before it starts, or a record the codec refuses.
pub fn rsu_record(
    index: usize,
    message: &Message,
    options: &RsuOptions,
) -> Result<String, RsuFileError> {
    let kind = message.kind();
    let psid = options
        .psid
        .or(kind.default_psid())
        .ok_or(RsuFileError::NoPsid { index, kind })?;
    let message_type = kind
        .rsu_type()
        .ok_or(RsuFileError::NoType { index, kind })?;
    if options.priority > 7 {
        return Err(RsuFileError::Priority {
            value: options.priority,
        });
    }
    let (interval, start, stop) = match options.delivery {
        RsuDelivery::ImmediateForward => (0, None, None),
        RsuDelivery::StoreAndRepeat {
            start_unix_ms,
            stop_unix_ms,
        } => {
            if stop_unix_ms <= start_unix_ms {
                return Err(RsuFileError::Window {
                    start_unix_ms,
                    stop_unix_ms,
                });
            }
            (
                options.interval_ms,
                Some(rsu_time(start_unix_ms)),
                Some(rsu_time(stop_unix_ms)),
            )
        }
    };
    let mut record = RsuMessage::new(message_type, psid, RsuPayload::Bytes(message.frame()));
    record.priority = Some(options.priority);
    record.tx_mode = Some(options.tx_mode);
    record.tx_channel = Some(options.channel);
    record.tx_interval = Some(interval);
    record.delivery_start = start.as_deref();
    record.delivery_stop = stop.as_deref();
    record.signature = Some(options.sign);
    record.encryption = Some(options.encrypt);
    let mut text = String::new();
    record
        .write_to(&mut text)
        .map_err(|error| RsuFileError::Record { index, error })?;
    Ok(text)
}

/// `MM/DD/YYYY, HH:MM` (UTC), as RSU delivery times are written.
pub(super) fn rsu_time(unix_ms: u64) -> String {
    let t = Utc::from_unix_ms(unix_ms);
    let minutes = t.ms_of_day / 60_000;
    format!(
        "{:02}/{:02}/{:04}, {:02}:{:02}",
        t.month,
        t.day,
        t.year,
        minutes / 60,
        minutes % 60
    )
}

/// The file name of the `index`-th message's record: `01-map.txt`, `02-tim.txt`, ...
pub fn rsu_file_name(index: usize, message: &Message) -> String {
    let kind = message.kind();
    let name = kind
        .rsu_type()
        .map_or_else(|| format!("msg{}", kind.id()), str::to_ascii_lowercase);
    format!("{:02}-{name}.txt", index + 1)
}

/// Writes one RSU record file per message into `dir` (created if missing), named by
/// [`rsu_file_name`]; each file is written whole under a temporary name and then renamed,
/// so an RSU watching the directory never reads half a record. Returns the paths.
///
/// # Errors
///
/// [`RsuFileError`] from [`rsu_record`] (before any file is written), or
/// [`RsuFileError::Io`] naming the path that could not be written.
pub fn write_rsu_files(
    dir: &Path,
    messages: &[Message],
    options: &RsuOptions,
) -> Result<Vec<PathBuf>, RsuFileError> {
    let records = messages
        .iter()
        .enumerate()
        .map(|(k, m)| Ok((rsu_file_name(k, m), rsu_record(k, m, options)?)))
        .collect::<Result<Vec<_>, RsuFileError>>()?;
    let io_error = |path: &Path| {
        let path = path.to_path_buf();
        move |error| RsuFileError::Io { path, error }
    };
    fs::create_dir_all(dir).map_err(io_error(dir))?;
    let mut paths = Vec::with_capacity(records.len());
    for (name, text) in records {
        let path = dir.join(&name);
        let partial = dir.join(format!(".{name}.partial"));
        fs::write(&partial, text).map_err(io_error(&partial))?;
        fs::rename(&partial, &path).map_err(io_error(&path))?;
        paths.push(path);
    }
    Ok(paths)
}
