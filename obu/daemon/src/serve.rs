//! The HTTP accept loop: HTTP/1.1 with a header-read timeout and a header size limit, one
//! task per connection, stopped by the shutdown signal.

use crate::counters::group;
use crate::hub::Hub;
use axum::Router;
use hyper_util::rt::{TokioIo, TokioTimer};
use hyper_util::service::TowerToHyperService;
use std::sync::Arc;
use std::time::Duration;
use tokio::net::TcpListener;
use tokio::sync::watch;

/// Largest request head accepted (request line and headers), octets.
pub const MAX_HEAD: usize = 16 * 1024;

/// Serves `app` on `listener` until `shutdown` turns true.
pub async fn serve(
    listener: TcpListener,
    app: Router,
    hub: Arc<Hub>,
    timeout: Duration,
    mut shutdown: watch::Receiver<bool>,
) {
    loop {
        let (stream, _) = tokio::select! {
            accepted = listener.accept() => match accepted {
                Ok(conn) => conn,
                Err(_) => {
                    hub.counters.add(group::HTTP_REJECTED, "accept failed");
                    tokio::time::sleep(Duration::from_millis(50)).await;
                    continue;
                }
            },
            _ = shutdown.changed() => return,
        };
        let _ = stream.set_nodelay(true);
        let service = TowerToHyperService::new(app.clone());
        let hub = hub.clone();
        let mut stop = shutdown.clone();
        tokio::spawn(async move {
            let conn = hyper::server::conn::http1::Builder::new()
                .timer(TokioTimer::new())
                .header_read_timeout(timeout)
                .max_buf_size(MAX_HEAD)
                .keep_alive(true)
                .serve_connection(TokioIo::new(stream), service);
            tokio::pin!(conn);
            tokio::select! {
                result = conn.as_mut() => if result.is_err() {
                    hub.counters.add(group::HTTP_REJECTED, "bad or slow request");
                },
                _ = stop.changed() => conn.as_mut().graceful_shutdown(),
            }
        });
    }
}
