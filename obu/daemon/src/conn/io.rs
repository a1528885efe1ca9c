//! A connection's socket as HTTP reads and writes it, telling its [`Conn`] when octets
//! arrive (an idle connection begins a request) and when writes block or go through (a
//! client that stops taking data).

use super::Conn;
use std::io::IoSlice;
use std::pin::Pin;
use std::sync::Arc;
use std::task::{Context, Poll};
use tokio::io::{AsyncRead, AsyncWrite, ReadBuf};

/// `T` (a TCP stream) watched for its [`Conn`].
#[derive(Debug)]
pub struct WatchedIo<T> {
    inner: T,
    conn: Arc<Conn>,
}

impl<T> WatchedIo<T> {
    /// Watches `inner` for `conn`.
    pub fn new(inner: T, conn: Arc<Conn>) -> Self {
        Self { inner, conn }
    }

    fn wrote<R>(&self, poll: Poll<std::io::Result<R>>) -> Poll<std::io::Result<R>> {
        match &poll {
            Poll::Pending => self.conn.on_write_blocked(),
            Poll::Ready(_) => self.conn.on_write_done(),
        }
        poll
    }
}

impl<T: AsyncRead + Unpin> AsyncRead for WatchedIo<T> {
    fn poll_read(
        mut self: Pin<&mut Self>,
        cx: &mut Context<'_>,
        buf: &mut ReadBuf<'_>,
    ) -> Poll<std::io::Result<()>> {
        let before = buf.filled().len();
        let poll = Pin::new(&mut self.inner).poll_read(cx, buf);
        if matches!(poll, Poll::Ready(Ok(()))) && buf.filled().len() > before {
            self.conn.on_read();
        }
        poll
    }
}

impl<T: AsyncWrite + Unpin> AsyncWrite for WatchedIo<T> {
    fn poll_write(
        mut self: Pin<&mut Self>,
        cx: &mut Context<'_>,
        buf: &[u8],
    ) -> Poll<std::io::Result<usize>> {
        let poll = Pin::new(&mut self.inner).poll_write(cx, buf);
        self.wrote(poll)
    }

    fn poll_write_vectored(
        mut self: Pin<&mut Self>,
        cx: &mut Context<'_>,
        bufs: &[IoSlice<'_>],
    ) -> Poll<std::io::Result<usize>> {
        let poll = Pin::new(&mut self.inner).poll_write_vectored(cx, bufs);
        self.wrote(poll)
    }

    fn is_write_vectored(&self) -> bool {
        self.inner.is_write_vectored()
    }

    fn poll_flush(mut self: Pin<&mut Self>, cx: &mut Context<'_>) -> Poll<std::io::Result<()>> {
        let poll = Pin::new(&mut self.inner).poll_flush(cx);
        self.wrote(poll)
    }

    fn poll_shutdown(mut self: Pin<&mut Self>, cx: &mut Context<'_>) -> Poll<std::io::Result<()>> {
        Pin::new(&mut self.inner).poll_shutdown(cx)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::conn::{Phase, Table};
    use tokio::io::{AsyncReadExt, AsyncWriteExt};

    #[tokio::test]
    async fn reads_begin_a_request_and_full_buffers_count_as_blocked() {
        let table = Table::new(2);
        let a = "127.0.0.1:1".parse().unwrap();
        let entry = table.open(a, a);
        let (near, mut far) = tokio::io::duplex(64);
        let mut io = WatchedIo::new(near, entry.conn.clone());
        far.write_all(b"GET").await.unwrap();
        let mut buf = [0u8; 8];
        let n = io.read(&mut buf).await.unwrap();
        assert_eq!(&buf[..n], b"GET");
        assert_eq!(entry.conn.phase(), Phase::Request);
        // The peer takes nothing: the 64-octet pipe fills and the write blocks.
        let blocked = tokio::time::timeout(
            std::time::Duration::from_millis(100),
            io.write_all(&[0u8; 200]),
        )
        .await;
        assert!(blocked.is_err(), "the write could not finish");
        let limits = crate::conn::Limits {
            request: std::time::Duration::from_secs(5),
            idle: std::time::Duration::from_secs(5),
            stall: std::time::Duration::from_secs(1),
        };
        entry.conn.on_stream();
        let (_, why) = entry.conn.deadline(&limits).expect("a stalled stream");
        assert_eq!(why, crate::conn::Expiry::StreamStalled);
        let mut sink = [0u8; 64];
        far.read_exact(&mut sink).await.unwrap();
        io.write_all(b"x").await.unwrap();
        assert_eq!(
            entry.conn.deadline(&limits),
            None,
            "writes go through again"
        );
    }
}
