//! A minimal Server-Sent Events client over a plain TCP stream (HTTP/1.1 GET, chunked
//! or not): enough to follow the daemon's `/events` as a tablet does.

use std::io::{BufRead, BufReader, Write};
use std::net::TcpStream;
use std::time::Duration;

/// One event.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct SseEvent {
    /// `event:` (empty for the default type).
    pub event: String,
    /// `id:`.
    pub id: String,
    /// `data:` lines joined by newlines.
    pub data: String,
}

/// A connected event stream.
#[derive(Debug)]
pub struct SseClient {
    reader: BufReader<TcpStream>,
    chunked: bool,
    pending: String,
}

impl SseClient {
    /// Connects to `addr` (`host:port`) and requests `/events`; fails unless answered 200.
    pub fn connect(addr: &str, read_timeout: Duration) -> Result<Self, String> {
        let mut s = TcpStream::connect(addr).map_err(|e| format!("connect {addr}: {e}"))?;
        s.set_nodelay(true).map_err(|e| e.to_string())?;
        s.set_read_timeout(Some(read_timeout))
            .map_err(|e| e.to_string())?;
        write!(
            s,
            "GET /events HTTP/1.1\r\nHost: {addr}\r\nAccept: text/event-stream\r\n\r\n"
        )
        .map_err(|e| e.to_string())?;
        let mut reader = BufReader::new(s);
        let mut line = String::new();
        reader.read_line(&mut line).map_err(|e| e.to_string())?;
        if !line.starts_with("HTTP/1.1 200") {
            return Err(format!("/events answered {:?}", line.trim()));
        }
        let mut chunked = false;
        loop {
            line.clear();
            reader.read_line(&mut line).map_err(|e| e.to_string())?;
            if line.trim().is_empty() {
                break;
            }
            let lower = line.to_ascii_lowercase();
            chunked |= lower.starts_with("transfer-encoding:") && lower.contains("chunked");
        }
        Ok(Self {
            reader,
            chunked,
            pending: String::new(),
        })
    }

    /// The next line of the event stream (chunk framing removed).
    fn line(&mut self) -> Result<String, String> {
        loop {
            if let Some(i) = self.pending.find('\n') {
                let line: String = self.pending.drain(..=i).collect();
                return Ok(line.trim_end_matches(['\r', '\n']).to_string());
            }
            if self.chunked {
                let mut size = String::new();
                self.read_line(&mut size)?;
                let n = usize::from_str_radix(size.trim(), 16)
                    .map_err(|_| format!("bad chunk size {size:?}"))?;
                if n == 0 {
                    return Err("stream ended".into());
                }
                let mut chunk = vec![0u8; n + 2];
                std::io::Read::read_exact(&mut self.reader, &mut chunk)
                    .map_err(|e| e.to_string())?;
                self.pending.push_str(&String::from_utf8_lossy(&chunk[..n]));
            } else {
                let mut line = String::new();
                self.read_line(&mut line)?;
                self.pending.push_str(&line);
            }
        }
    }

    fn read_line(&mut self, buf: &mut String) -> Result<(), String> {
        match self.reader.read_line(buf) {
            Ok(0) => Err("stream ended".into()),
            Ok(_) => Ok(()),
            Err(e) => Err(e.to_string()),
        }
    }

    /// The next event (comments such as heartbeats skipped).
    pub fn next_event(&mut self) -> Result<SseEvent, String> {
        let mut ev = SseEvent::default();
        let mut any = false;
        loop {
            let line = self.line()?;
            if line.is_empty() {
                if any {
                    return Ok(ev);
                }
                continue;
            }
            if line.starts_with(':') {
                continue;
            }
            let (field, value) = line.split_once(':').unwrap_or((&line, ""));
            let value = value.strip_prefix(' ').unwrap_or(value);
            match field {
                "event" => ev.event = value.to_string(),
                "id" => ev.id = value.to_string(),
                "data" => {
                    if !ev.data.is_empty() {
                        ev.data.push('\n');
                    }
                    ev.data.push_str(value);
                }
                _ => {}
            }
            any = true;
        }
    }
}
