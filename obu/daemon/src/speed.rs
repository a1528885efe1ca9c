//! Vehicle speed from CAN. Frames come from a [`CanSource`]: a SocketCAN interface (Linux) or
//! a `candump -l` log replayed at its time stamps. The configured signal is read from frames
//! with its id; a frame too short for it, or a bad log line, is counted with its reason.

use crate::config::{Speed, SpeedSource};
use crate::counters::group;
use crate::hub::Hub;
use obu::input::can::{parse_candump_line, CanError, SpeedSignal};
use std::io::BufRead;
use std::sync::Arc;
use std::time::Duration;

/// One frame, or a reason it could not be read.
pub type FrameResult = Result<(u32, Vec<u8>), CanError>;

/// A blocking source of CAN frames.
pub trait CanSource: Send + 'static {
    /// The next frame; `None` at the end of the input (or when the device is gone).
    fn next_frame(&mut self) -> Option<FrameResult>;
}

/// A `candump -l` log, paced by its time stamps when `realtime`.
pub struct CandumpReplay<R: BufRead + Send + 'static> {
    lines: std::io::Lines<R>,
    realtime: bool,
    last_us: Option<u64>,
}

impl<R: BufRead + Send + 'static> CandumpReplay<R> {
    /// A replay of `reader`.
    pub fn new(reader: R, realtime: bool) -> Self {
        Self {
            lines: reader.lines(),
            realtime,
            last_us: None,
        }
    }
}

impl<R: BufRead + Send + 'static> CanSource for CandumpReplay<R> {
    fn next_frame(&mut self) -> Option<FrameResult> {
        let line = loop {
            let line = self.lines.next()?.ok()?;
            if !line.trim().is_empty() {
                break line;
            }
        };
        let frame = match parse_candump_line(&line) {
            Ok(f) => f,
            Err(e) => return Some(Err(e)),
        };
        if self.realtime {
            if let Some(prev) = self.last_us.filter(|&p| frame.time_us > p) {
                std::thread::sleep(Duration::from_micros((frame.time_us - prev).min(5_000_000)));
            }
            self.last_us = Some(frame.time_us);
        }
        Some(Ok((frame.id, frame.data.to_vec())))
    }
}

#[cfg(target_os = "linux")]
mod socket {
    use super::{CanSource, FrameResult};
    use obu::input::can::CanError;
    use socketcan::{CanSocket, EmbeddedFrame, Frame, Socket};

    /// A SocketCAN interface (e.g. `can0`).
    pub struct SocketCan(CanSocket);

    impl SocketCan {
        /// Opens `interface`.
        pub fn open(interface: &str) -> std::io::Result<Self> {
            CanSocket::open(interface)
                .map(Self)
                .map_err(std::io::Error::other)
        }
    }

    impl CanSource for SocketCan {
        fn next_frame(&mut self) -> Option<FrameResult> {
            let frame = self.0.read_frame().ok()?;
            if frame.is_remote_frame() {
                return Some(Err(CanError::Remote));
            }
            Some(Ok((frame.raw_id(), frame.data().to_vec())))
        }
    }
}

/// Starts the configured source on its own thread.
pub fn spawn(cfg: &Speed, hub: Arc<Hub>) {
    let signal = cfg.signal();
    match cfg.source {
        SpeedSource::Gnss => {}
        SpeedSource::CandumpFile => match std::fs::File::open(&cfg.file) {
            Ok(f) => run(
                CandumpReplay::new(std::io::BufReader::new(f), true),
                signal,
                hub,
            ),
            Err(_) => hub
                .counters
                .add(group::CAN_ERRORS, "candump file cannot be opened"),
        },
        #[cfg(target_os = "linux")]
        SpeedSource::Socketcan => match socket::SocketCan::open(&cfg.interface) {
            Ok(s) => run(s, signal, hub),
            Err(_) => hub
                .counters
                .add(group::CAN_ERRORS, "interface cannot be opened"),
        },
        #[cfg(not(target_os = "linux"))]
        SpeedSource::Socketcan => hub.counters.add(group::CAN_ERRORS, "SocketCAN needs Linux"),
    }
}

/// Reads `source` on a thread, feeding the speed signal to the hub.
pub fn run(mut source: impl CanSource, signal: SpeedSignal, hub: Arc<Hub>) {
    std::thread::spawn(move || {
        while let Some(frame) = source.next_frame() {
            feed(&hub, &signal, frame);
        }
    });
}

/// One frame: the speed when it is the signal's frame, else nothing.
pub fn feed(hub: &Hub, signal: &SpeedSignal, frame: FrameResult) {
    match frame {
        Ok((id, data)) if id == signal.id => match signal.speed_mps(&data) {
            Ok(v) if v.is_finite() => hub.on_can_speed(v),
            Ok(_) => hub.counters.add(group::CAN_ERRORS, "speed not finite"),
            Err(e) => hub.counters.add(group::CAN_ERRORS, e.as_str()),
        },
        Ok(_) => {}
        Err(e) => hub.counters.add(group::CAN_ERRORS, e.as_str()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn replay_reads_frames_and_reports_bad_lines() {
        let log = "(1.000000) can0 1F0#E803\n\n(1.100000) can0 1F0#E8\ngarbage\n";
        let mut r = CandumpReplay::new(std::io::Cursor::new(log), false);
        assert_eq!(r.next_frame(), Some(Ok((0x1f0, vec![0xe8, 0x03]))));
        assert_eq!(r.next_frame(), Some(Ok((0x1f0, vec![0xe8]))));
        assert_eq!(r.next_frame(), Some(Err(CanError::BadLine)));
        assert_eq!(r.next_frame(), None);
    }
}
