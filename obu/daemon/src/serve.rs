//! The HTTP accept loop and one task per connection: HTTP/1.1 with a 16 KiB head limit, the
//! Host check before any route, and the connection's deadlines ([`crate::conn`]) enforced
//! by its task, which sleeps until the next one.
//!
//! Over the connection cap a new connection first sheds the oldest idle or requesting one
//! ([`Table::shed_oldest`]). When `accept` fails for want of file descriptors the loop
//! sheds one too and waits (5 ms, doubling to 500 ms while it lasts) instead of spinning:
//! the waiting connections stay queued in the kernel.
//!
//! A client closing its connection, while idle or in the middle of an event stream, is
//! normal and not counted as a refusal; malformed requests and deadlines are, each under
//! its own reason.

use crate::conn::io::WatchedIo;
use crate::conn::{Closed, Conn, Expiry, Limits, Table};
use crate::counters::group;
use crate::host::AllowedHosts;
use crate::hub::Hub;
use axum::body::Body;
use axum::http::{header, Request, Response, StatusCode};
use axum::Router;
use hyper::body::{Frame, Incoming, SizeHint};
use hyper::service::Service as _;
use hyper_util::rt::TokioIo;
use hyper_util::service::TowerToHyperService;
use std::pin::Pin;
use std::sync::Arc;
use std::task::{Context, Poll};
use std::time::Duration;
use tokio::net::{TcpListener, TcpStream};
use tokio::sync::watch;

/// Largest request head accepted (request line and headers), octets.
pub const MAX_HEAD: usize = 16 * 1024;

/// The kernel send buffer of every HTTP connection, octets (Linux doubles it for its own
/// bookkeeping). Fixed rather than autotuned (up to 4 MiB), so that what a client that
/// stops reading can leave queued on the unit is bounded: the largest answer (the app's
/// style sheet) fits, and an event stream whose client takes nothing blocks after
/// this plus the client's receive window, and is then dropped after the stall timeout.
pub const SEND_BUFFER: u32 = 32 * 1024;

/// Binds the HTTP listener at `addr` with [`SEND_BUFFER`] (which its connections inherit).
pub fn bind(addr: std::net::SocketAddr) -> std::io::Result<TcpListener> {
    let socket = if addr.is_ipv4() {
        tokio::net::TcpSocket::new_v4()?
    } else {
        tokio::net::TcpSocket::new_v6()?
    };
    socket.set_reuseaddr(true)?;
    socket.set_send_buffer_size(SEND_BUFFER)?;
    socket.bind(addr)?;
    socket.listen(1024)
}

/// What the accept loop and the connections share.
#[derive(Clone)]
pub struct Server {
    /// The routes.
    pub app: Router,
    /// The hub (for its counters).
    pub hub: Arc<Hub>,
    /// The open connections.
    pub conns: Arc<Table>,
    /// The deadlines.
    pub limits: Limits,
    /// The Host names served.
    pub hosts: Arc<AllowedHosts>,
}

/// Whether an `accept` error means the process or the system is out of file descriptors
/// (or socket memory): waiting helps, retrying at once does not.
fn out_of_descriptors(e: &std::io::Error) -> bool {
    // EMFILE, ENFILE, ENOBUFS, ENOMEM on Linux.
    matches!(e.raw_os_error(), Some(24 | 23 | 105 | 12))
}

/// Serves on `listener` until `shutdown` turns true.
pub async fn serve(listener: TcpListener, server: Server, mut shutdown: watch::Receiver<bool>) {
    let counters = &server.hub.counters;
    let mut backoff = Duration::ZERO;
    loop {
        let accepted = tokio::select! {
            accepted = listener.accept() => accepted,
            _ = shutdown.changed() => return,
        };
        let (stream, peer) = match accepted {
            Ok(conn) => {
                backoff = Duration::ZERO;
                conn
            }
            Err(e) => {
                let pause = if out_of_descriptors(&e) {
                    counters.add(group::HTTP_REJECTED, "accept: out of file descriptors");
                    server.conns.shed_oldest(Closed::ShedForDescriptors);
                    backoff =
                        (backoff * 2).clamp(Duration::from_millis(5), Duration::from_millis(500));
                    backoff
                } else {
                    counters.add(group::HTTP_REJECTED, "accept failed");
                    Duration::from_millis(10)
                };
                tokio::select! {
                    _ = tokio::time::sleep(pause) => continue,
                    _ = shutdown.changed() => return,
                }
            }
        };
        let Ok(local) = stream.local_addr() else {
            continue;
        };
        if server.conns.full() && !server.conns.shed_oldest(Closed::Shed) {
            counters.add(group::HTTP_REJECTED, "refused: connection cap");
            continue;
        }
        let _ = stream.set_nodelay(true);
        let entry = server.conns.open(peer, local);
        let server = server.clone();
        let stop = shutdown.clone();
        tokio::spawn(async move {
            connection(stream, &entry.conn, &server, stop).await;
            drop(entry);
        });
    }
}

/// Serves one connection until it ends, its deadline passes, it is told to close, or the
/// daemon stops; counts how it ended when that is a refusal.
async fn connection(
    stream: TcpStream,
    conn: &Arc<Conn>,
    server: &Server,
    mut stop: watch::Receiver<bool>,
) {
    let counters = &server.hub.counters;
    let io = TokioIo::new(WatchedIo::new(stream, conn.clone()));
    let service = {
        let (conn, server) = (conn.clone(), server.clone());
        hyper::service::service_fn(move |req| handle(req, conn.clone(), server.clone()))
    };
    let http = hyper::server::conn::http1::Builder::new()
        .header_read_timeout(None)
        .max_buf_size(MAX_HEAD)
        .keep_alive(true)
        .serve_connection(io, service);
    tokio::pin!(http);
    loop {
        let deadline = conn.deadline(&server.limits);
        let sleep = async {
            match deadline {
                Some((at, _)) => tokio::time::sleep_until(at.into()).await,
                None => std::future::pending().await,
            }
        };
        // The connection first: when its deadline and a request both arrived while this task
        // waited for the CPU, the request is read (and moves the deadline) before the
        // deadline is checked. A request already in the socket is never closed as idle.
        tokio::select! {
            biased;
            result = http.as_mut() => {
                if let Err(e) = result {
                    if let Some(reason) = refusal(&e) {
                        counters.add(group::HTTP_REJECTED, reason);
                    }
                }
                return;
            }
            _ = sleep => {
                // The phase may have moved since: only a deadline still past ends it.
                if let Some((at, why)) = conn.deadline(&server.limits) {
                    if at <= std::time::Instant::now() {
                        let (g, reason) = expiry_counter(why);
                        counters.add(g, reason);
                        return;
                    }
                }
            }
            _ = conn.changed() => match conn.closed() {
                Some(Closed::Shed) => {
                    counters.add(group::HTTP_REJECTED, "shed: connection cap");
                    return;
                }
                Some(Closed::ShedForDescriptors) => {
                    counters.add(group::HTTP_REJECTED, "shed: out of file descriptors");
                    return;
                }
                Some(Closed::Evicted) => {
                    counters.add(group::SSE_CLIENTS, "evicted: slots full");
                    return;
                }
                None => {}
            },
            _ = stop.changed() => return,
        }
    }
}

/// The group and reason a passed deadline is counted under.
fn expiry_counter(why: Expiry) -> (&'static str, &'static str) {
    match why {
        Expiry::Idle => (group::HTTP_CONNECTIONS, "closed idle"),
        Expiry::RequestDeadline => (group::HTTP_REJECTED, "request deadline"),
        Expiry::AnswerNotTaken => (group::HTTP_REJECTED, "answer not taken"),
        Expiry::StreamStalled => (group::SSE_CLIENTS, "dropped: not reading"),
    }
}

/// The refusal reason of a connection's error; `None` when the client just went away.
fn refusal(e: &hyper::Error) -> Option<&'static str> {
    use std::io::ErrorKind::*;
    if e.is_parse_too_large() {
        return Some("request head too large");
    }
    if e.is_parse() || e.is_parse_version_h2() {
        return Some("malformed request");
    }
    if e.is_timeout() {
        return Some("request deadline");
    }
    if e.is_incomplete_message() || e.is_canceled() || e.is_body_write_aborted() {
        return None;
    }
    let mut source = std::error::Error::source(e);
    while let Some(s) = source {
        if let Some(io) = s.downcast_ref::<std::io::Error>() {
            let gone = [
                BrokenPipe,
                ConnectionReset,
                ConnectionAborted,
                UnexpectedEof,
            ];
            return (!gone.contains(&io.kind())).then_some("connection error");
        }
        source = s.source();
    }
    Some("connection error")
}

/// One request: the Host check, then the routes; the answer's body tells the connection
/// when it has been handed over whole.
async fn handle(
    mut req: Request<Incoming>,
    conn: Arc<Conn>,
    server: Server,
) -> Result<Response<Answer>, std::convert::Infallible> {
    conn.on_request();
    let authority = req
        .uri()
        .authority()
        .map(|a| a.as_str().to_owned())
        .or_else(|| {
            let host = req.headers().get(header::HOST)?;
            host.to_str().ok().map(str::to_owned)
        });
    let response = match server.hosts.check(authority.as_deref(), conn.local) {
        Err(refused) => {
            server
                .hub
                .counters
                .add(group::HTTP_REJECTED, refused.reason());
            let status = match refused {
                crate::host::HostRefusal::Missing => StatusCode::BAD_REQUEST,
                crate::host::HostRefusal::Wrong => StatusCode::MISDIRECTED_REQUEST,
            };
            let mut r = Response::new(Body::from(refused.reason()));
            *r.status_mut() = status;
            r.headers_mut().insert(
                header::CONNECTION,
                header::HeaderValue::from_static("close"),
            );
            r
        }
        Ok(()) => {
            req.extensions_mut().insert(conn.clone());
            let routes = TowerToHyperService::new(server.app.clone());
            match routes.call(req).await {
                Ok(r) => r,
                Err(never) => match never {},
            }
        }
    };
    Ok(response.map(|body| Answer { body, conn }))
}

/// An answer's body that tells its connection when it ends or is dropped.
pub struct Answer {
    body: Body,
    conn: Arc<Conn>,
}

impl Drop for Answer {
    fn drop(&mut self) {
        self.conn.on_answered();
    }
}

impl hyper::body::Body for Answer {
    type Data = axum::body::Bytes;
    type Error = axum::Error;

    fn poll_frame(
        mut self: Pin<&mut Self>,
        cx: &mut Context<'_>,
    ) -> Poll<Option<Result<Frame<Self::Data>, Self::Error>>> {
        let poll = Pin::new(&mut self.body).poll_frame(cx);
        if matches!(poll, Poll::Ready(None)) {
            self.conn.on_answered();
        }
        poll
    }

    fn is_end_stream(&self) -> bool {
        self.body.is_end_stream()
    }

    fn size_hint(&self) -> SizeHint {
        self.body.size_hint()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::settings::Settings;
    use obu::alert::AlertConfig;
    use std::io::{BufRead, BufReader, Read, Write};

    const IDLE: Duration = Duration::from_millis(300);

    /// Sends `GET /healthz` on `stream`.
    fn ask(stream: &mut std::net::TcpStream, host: &str) -> std::io::Result<()> {
        write!(stream, "GET /healthz HTTP/1.1\r\nHost: {host}\r\n\r\n")
    }

    /// Reads one whole answer from `stream`: its status line, or the error that ended it
    /// (`""`: the server closed the connection).
    fn answer(stream: &std::net::TcpStream) -> String {
        let read = || -> std::io::Result<String> {
            let mut r = BufReader::new(stream.try_clone()?);
            let mut status = String::new();
            r.read_line(&mut status)?;
            let mut length = 0;
            loop {
                let mut line = String::new();
                r.read_line(&mut line)?;
                if let Some(v) = line.to_ascii_lowercase().strip_prefix("content-length:") {
                    length = v.trim().parse().unwrap_or(0);
                }
                if line == "\r\n" || line.is_empty() {
                    break;
                }
            }
            r.read_exact(&mut vec![0; length])?;
            Ok(status)
        };
        read().unwrap_or_else(|e| format!("error: {e}"))
    }

    /// The runtime's one thread is held past the idle deadline while a kept-alive client
    /// sends its next request: on waking, the timer and the request are both ready. The
    /// request must be answered, not closed as idle (a random pick between the two closed
    /// one time in two; each round here is one such pick).
    #[tokio::test(flavor = "current_thread")]
    async fn a_request_waiting_in_the_socket_beats_the_idle_deadline_it_arrived_before() {
        let hub = Hub::new(Settings::defaults(100.0, 9.0), AlertConfig::DEFAULT, 16);
        let server = Server {
            app: Router::new().route("/healthz", axum::routing::get(|| async { "ok" })),
            hub: hub.clone(),
            conns: Table::new(8),
            limits: Limits {
                request: Duration::from_secs(5),
                idle: IDLE,
                stall: Duration::from_secs(5),
            },
            hosts: Arc::new(AllowedHosts::new(None, &[])),
        };
        let listener = bind("127.0.0.1:0".parse().unwrap()).unwrap();
        let host = listener.local_addr().unwrap().to_string();
        let (_stop_tx, stop) = watch::channel(false);
        tokio::spawn(serve(listener, server, stop));
        const ROUNDS: usize = 8;
        let (answered_tx, mut answered) = tokio::sync::mpsc::unbounded_channel();
        let (go_tx, go) = std::sync::mpsc::channel::<()>();
        let (asked_tx, asked) = std::sync::mpsc::channel::<()>();
        let client = std::thread::spawn(move || {
            let mut stream = std::net::TcpStream::connect(&host).unwrap();
            stream
                .set_read_timeout(Some(Duration::from_secs(5)))
                .unwrap();
            let mut statuses = Vec::new();
            for _ in 0..=ROUNDS {
                if go.recv().is_err() {
                    break;
                }
                let sent = ask(&mut stream, &host);
                let _ = asked_tx.send(());
                statuses.push(match sent {
                    Ok(()) => answer(&stream),
                    Err(e) => format!("error: {e}"),
                });
                let _ = answered_tx.send(());
            }
            statuses
        });
        for round in 0..=ROUNDS {
            // The connection settles: the last answer handed over, its idle deadline set.
            tokio::time::sleep(IDLE / 10).await;
            // This thread (the runtime's only one) is held from before the request is sent
            // until, after the first, well past that deadline.
            if go_tx.send(()).is_err() || asked.recv().is_err() {
                break;
            }
            if round > 0 {
                std::thread::sleep(IDLE * 2);
            }
            if answered.recv().await.is_none() {
                break;
            }
        }
        let statuses = tokio::task::spawn_blocking(move || client.join().unwrap())
            .await
            .unwrap();
        assert_eq!(statuses.len(), ROUNDS + 1);
        for status in &statuses {
            assert!(status.starts_with("HTTP/1.1 200"), "{statuses:?}");
        }
        assert_eq!(hub.counters.get(group::HTTP_CONNECTIONS, "closed idle"), 0);
    }
}
