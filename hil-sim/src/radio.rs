//! The radio chip between the air and the firmware's V2X USART, as the firmware rig models
//! it: frames received over the air wait in a queue of [`QUEUE_FRAMES`] receive buffers and
//! leave one after the other over the serial link; when a frame arrives with every buffer
//! full, the oldest waiting frame is dropped (and counted for its sender), never the one the
//! link is sending.
//!
//! Why a bounded queue: QEMU's emulated USART (each byte a round trip between QEMU's I/O
//! and CPU threads) takes less than the air carries in a scenario with an attacker (the
//! roadside's MAP and TIM at 10 Hz and ten forged frames a second; both rates are in the
//! firmware README's Measured table). A relay that queues without bound (the kernel's
//! socket buffers hold megabytes) delivers every frame later and later: past 30 s behind,
//! the firmware rightly rejects the roadside's own messages as "generation time too old"
//! and lets its zones lapse. A real radio chip has a fixed set of buffers and drops when its host link
//! is slower than the air; the rig does the same, so what the firmware receives is at most
//! about a second old and what was dropped is counted.
//!
//! The link itself is a Unix socket to QEMU's chardev with the smallest send buffer the
//! kernel allows: a Unix stream socket charges the bytes its peer has not read yet to the
//! sender, so the socket holds only a few frames and the queue here is where frames wait.

use std::collections::VecDeque;
use std::io::{ErrorKind, Write};
use std::net::SocketAddr;

/// Receive buffers of the modelled radio chip: frames waiting for the serial link.
pub const QUEUE_FRAMES: usize = 8;

/// Senders whose drops are counted each on their own; the drops of any further sender are
/// counted together ([`LinkCounts::dropped_other`]).
pub const MAX_SENDERS: usize = 16;

/// What became of the frames the radio received.
#[derive(Debug, Clone, Default, PartialEq, Eq, serde::Serialize)]
pub struct LinkCounts {
    /// Frames received over the air.
    pub received: u64,
    /// Frames written whole to the serial link.
    pub delivered: u64,
    /// Frames dropped with every buffer full.
    pub dropped: u64,
    /// Bytes written to the serial link (whole frames and the part of one being sent).
    pub bytes_written: u64,
    /// Dropped frames by sender (the first [`MAX_SENDERS`] senders).
    pub dropped_by_sender: Vec<(SocketAddr, u64)>,
    /// Dropped frames of senders past the first [`MAX_SENDERS`].
    pub dropped_other: u64,
}

impl LinkCounts {
    /// Frames of `sender` dropped (0 for a sender never dropped; a sender past the first
    /// [`MAX_SENDERS`] may be among [`LinkCounts::dropped_other`]).
    pub fn dropped_from(&self, sender: SocketAddr) -> u64 {
        self.dropped_by_sender
            .iter()
            .find(|(a, _)| *a == sender)
            .map_or(0, |(_, n)| *n)
    }

    fn count_drop(&mut self, sender: SocketAddr) {
        self.dropped += 1;
        if let Some((_, n)) = self
            .dropped_by_sender
            .iter_mut()
            .find(|(a, _)| *a == sender)
        {
            *n += 1;
        } else if self.dropped_by_sender.len() < MAX_SENDERS {
            self.dropped_by_sender.push((sender, 1));
        } else {
            self.dropped_other += 1;
        }
    }
}

/// A frame in a receive buffer.
#[derive(Debug)]
struct Waiting {
    seq: u64,
    from: SocketAddr,
    bytes: Vec<u8>,
}

/// The radio's receive buffers and the frame being sent over the link: the pure part of
/// the relay (no sockets, no clock), driven by [`RadioQueue::receive`] and
/// [`RadioQueue::send`].
#[derive(Debug, Default)]
pub struct RadioQueue {
    waiting: VecDeque<Waiting>,
    /// Bytes of the front frame already written (it cannot be dropped any more).
    front_written: usize,
    next_seq: u64,
    counts: LinkCounts,
    /// A catch-up mark: the last frame received when it was set, and once every frame up
    /// to it has left the queue, the link's byte count at that moment.
    mark: Option<(u64, Option<u64>)>,
}

impl RadioQueue {
    /// Takes a frame `bytes` (already framed for the link) from `from`; with every buffer
    /// full, first drops the oldest frame not yet on the link.
    pub fn receive(&mut self, from: SocketAddr, bytes: Vec<u8>) {
        self.counts.received += 1;
        if self.waiting.len() >= QUEUE_FRAMES {
            let oldest = usize::from(self.front_written > 0);
            if let Some(w) = self.waiting.remove(oldest) {
                self.counts.count_drop(w.from);
            }
        }
        self.waiting.push_back(Waiting {
            seq: self.next_seq,
            from,
            bytes,
        });
        self.next_seq += 1;
        self.settle_mark();
    }

    /// Writes waiting frames to `link` until it would block or the queue is empty.
    ///
    /// # Errors
    ///
    /// A write error other than "would block" (the link is gone).
    pub fn send(&mut self, link: &mut impl Write) -> std::io::Result<()> {
        while let Some(front) = self.waiting.front() {
            match link.write(&front.bytes[self.front_written..]) {
                Ok(0) => return Err(ErrorKind::WriteZero.into()),
                Ok(n) => {
                    self.front_written += n;
                    self.counts.bytes_written += n as u64;
                    if self.front_written == front.bytes.len() {
                        self.waiting.pop_front();
                        self.front_written = 0;
                        self.counts.delivered += 1;
                        self.settle_mark();
                    }
                }
                Err(e) if e.kind() == ErrorKind::WouldBlock => break,
                Err(e) if e.kind() == ErrorKind::Interrupted => {}
                Err(e) => return Err(e),
            }
        }
        Ok(())
    }

    /// True when no frame waits.
    pub fn is_empty(&self) -> bool {
        self.waiting.is_empty()
    }

    /// What became of the frames so far.
    pub fn counts(&self) -> &LinkCounts {
        &self.counts
    }

    /// Marks the frames received so far: [`RadioQueue::marked_written`] then tells the
    /// link's byte count once each of them has been written or dropped.
    pub fn set_mark(&mut self) {
        self.mark = Some((self.next_seq, None));
        self.settle_mark();
    }

    /// The bytes written to the link once every frame received before
    /// [`RadioQueue::set_mark`] had left the queue; `None` while one still waits (or
    /// without a mark).
    pub fn marked_written(&self) -> Option<u64> {
        self.mark.and_then(|(_, at)| at)
    }

    fn settle_mark(&mut self) {
        if let Some((end, at @ None)) = &mut self.mark {
            if self.waiting.front().is_none_or(|w| w.seq >= *end) {
                *at = Some(self.counts.bytes_written);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn addr(port: u16) -> SocketAddr {
        SocketAddr::from(([127, 0, 0, 1], port))
    }

    /// A link that takes up to `room` bytes, then blocks.
    struct Link {
        got: Vec<u8>,
        room: usize,
    }

    impl Write for Link {
        fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
            if self.room == 0 {
                return Err(ErrorKind::WouldBlock.into());
            }
            let n = buf.len().min(self.room);
            self.room -= n;
            self.got.extend_from_slice(&buf[..n]);
            Ok(n)
        }
        fn flush(&mut self) -> std::io::Result<()> {
            Ok(())
        }
    }

    #[test]
    fn a_full_queue_drops_its_oldest_frame_and_counts_it_for_its_sender() {
        let mut q = RadioQueue::default();
        for k in 0..QUEUE_FRAMES as u8 + 3 {
            let from = addr(if k % 2 == 0 { 1000 } else { 2000 });
            q.receive(from, vec![k; 4]);
        }
        let mut link = Link {
            got: Vec::new(),
            room: usize::MAX,
        };
        q.send(&mut link).unwrap();
        // Frames 0, 1 and 2 were dropped: the link got 3..=10 in order.
        let sent: Vec<u8> = link.got.chunks(4).map(|c| c[0]).collect();
        assert_eq!(sent, (3..QUEUE_FRAMES as u8 + 3).collect::<Vec<_>>());
        let c = q.counts();
        assert_eq!((c.received, c.delivered, c.dropped), (11, 8, 3));
        assert_eq!(
            (c.dropped_from(addr(1000)), c.dropped_from(addr(2000))),
            (2, 1)
        );
        assert_eq!(c.bytes_written, 32);
    }

    #[test]
    fn the_frame_on_the_link_is_never_dropped_and_is_finished_whole() {
        let mut q = RadioQueue::default();
        q.receive(addr(1), vec![0xAA; 10]);
        let mut link = Link {
            got: Vec::new(),
            room: 4,
        };
        q.send(&mut link).unwrap();
        for k in 0..QUEUE_FRAMES as u8 {
            q.receive(addr(2), vec![k; 2]);
        }
        // The half-sent frame stays; the oldest frame behind it (0) went instead.
        assert_eq!(q.counts().dropped_from(addr(1)), 0);
        assert_eq!(q.counts().dropped_from(addr(2)), 1);
        link.room = usize::MAX;
        q.send(&mut link).unwrap();
        assert_eq!(&link.got[..10], &[0xAA; 10]);
        assert_eq!(link.got[10], 1);
        assert!(q.is_empty());
    }

    #[test]
    fn the_mark_gives_the_bytes_written_once_its_frames_have_left() {
        let mut q = RadioQueue::default();
        q.receive(addr(1), vec![1; 5]);
        q.receive(addr(1), vec![2; 5]);
        q.set_mark();
        q.receive(addr(1), vec![3; 5]);
        assert_eq!(q.marked_written(), None);
        let mut link = Link {
            got: Vec::new(),
            room: 7,
        };
        q.send(&mut link).unwrap();
        assert_eq!(q.marked_written(), None, "the second frame is half written");
        link.room = 100;
        q.send(&mut link).unwrap();
        // Settled when the second frame left (10 bytes), not after the third.
        assert_eq!(q.marked_written(), Some(10));
        assert_eq!(q.counts().bytes_written, 15);
    }

    #[test]
    fn a_mark_on_an_empty_queue_is_settled_at_once_and_drops_settle_it_too() {
        let mut q = RadioQueue::default();
        q.set_mark();
        assert_eq!(q.marked_written(), Some(0));
        for k in 0..QUEUE_FRAMES as u8 {
            q.receive(addr(1), vec![k; 3]);
        }
        q.set_mark();
        for k in 0..QUEUE_FRAMES as u8 {
            q.receive(addr(1), vec![k; 3]);
        }
        // Every marked frame was dropped for a newer one: nothing of them to wait for.
        assert_eq!(q.marked_written(), Some(0));
    }

    #[test]
    fn drops_of_senders_past_the_tracked_ones_are_counted_together() {
        let mut q = RadioQueue::default();
        for port in 0..(QUEUE_FRAMES + MAX_SENDERS + 5) as u16 {
            q.receive(addr(port), vec![0]);
        }
        let c = q.counts();
        assert_eq!(c.dropped, (MAX_SENDERS + 5) as u64);
        assert_eq!(c.dropped_by_sender.len(), MAX_SENDERS);
        assert_eq!(c.dropped_other, 5);
    }

    #[test]
    fn a_closed_link_is_an_error() {
        struct Closed;
        impl Write for Closed {
            fn write(&mut self, _: &[u8]) -> std::io::Result<usize> {
                Err(ErrorKind::BrokenPipe.into())
            }
            fn flush(&mut self) -> std::io::Result<()> {
                Ok(())
            }
        }
        let mut q = RadioQueue::default();
        q.receive(addr(1), vec![1]);
        assert_eq!(
            q.send(&mut Closed).unwrap_err().kind(),
            ErrorKind::BrokenPipe
        );
    }
}
