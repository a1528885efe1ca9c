//! The checks behind the fuzz targets of `j2735` (`fuzz_targets/*.rs` only call them), and
//! the big-stack worker thread they run on.
//!
//! Every check panics on a violated invariant; libFuzzer's panic hook (installed by
//! `libfuzzer-sys`) turns any panic, on any thread, into an abort that libFuzzer reports as
//! a crash and saves as an artifact.
//!
//! # Storage and stack
//! The crate is built without feature `alloc` of `j2735`, the storage the firmware uses
//! (features unify across the targets of one crate, so one build fuzzes one storage; this
//! crate's own feature `alloc` makes a separate build for the heap storage, with `std` as the
//! daemon runs it, where `message_frame` also checks new values decoded from recycled
//! storage against the kept ones). Without `alloc`
//! a `MessageFrame` is 7.2 MB (a `MapData` alone is), so:
//! - the decoded values live in `Box`es made once and refilled by `uper::decode_into` on
//!   every input (as the firmware refills its static values). Reusing them also tests that
//!   decoding in place leaves nothing of the previous value behind: the same input decoded
//!   into boxes with different histories (the `MessageFrame` and the direct `MapData` /
//!   `TravelerInformation` ones) must give equal values;
//! - decoding may still build a whole alternative on the stack (switching a CHOICE to
//!   `MapData` builds its placeholder), and JER reading returns values by value, so the checks
//!   that touch `MessageFrame` run on a [`BigStack`] worker thread: libFuzzer calls the target
//!   on the main thread, whose stack (8 MB by default) is too small for that.

use std::sync::mpsc::{sync_channel, Receiver, SyncSender};
use std::sync::{Mutex, PoisonError};
use std::thread;

pub mod envelope;
pub mod gnss;
pub mod jer;
pub mod message_frame;

/// Stack of the worker thread (address space only; pages are used as touched).
pub const WORKER_STACK_BYTES: usize = 256 << 20;

/// A thread with a large stack that owns a state `S` (made on that thread) and runs a check
/// on each input handed to it; [`BigStack::run`] waits until the check is done.
pub struct BigStack {
    channels: Mutex<Channels>,
}

struct Channels {
    jobs: SyncSender<Vec<u8>>,
    done: Receiver<Vec<u8>>,
    /// The input buffer, handed back and forth so that no input allocates.
    spare: Vec<u8>,
}

impl BigStack {
    /// Starts the worker: it makes its state with `init`, then runs `check` on each input.
    pub fn spawn<S, I, C>(name: &str, init: I, mut check: C) -> Self
    where
        I: FnOnce() -> S + Send + 'static,
        C: FnMut(&mut S, &[u8]) + Send + 'static,
    {
        let (jobs, inputs) = sync_channel::<Vec<u8>>(1);
        let (finished, done) = sync_channel::<Vec<u8>>(1);
        thread::Builder::new()
            .name(name.to_string())
            .stack_size(WORKER_STACK_BYTES)
            .spawn(move || {
                let mut state = init();
                while let Ok(input) = inputs.recv() {
                    check(&mut state, &input);
                    if finished.send(input).is_err() {
                        break;
                    }
                }
            })
            .expect("cannot start the fuzzing worker thread");
        Self {
            channels: Mutex::new(Channels {
                jobs,
                done,
                spare: Vec::new(),
            }),
        }
    }

    /// Runs the check on `data` on the worker thread and waits for it.
    pub fn run(&self, data: &[u8]) {
        let mut channels = self.channels.lock().unwrap_or_else(PoisonError::into_inner);
        let mut input = std::mem::take(&mut channels.spare);
        input.clear();
        input.extend_from_slice(data);
        channels
            .jobs
            .send(input)
            .expect("the fuzzing worker thread is gone");
        channels.spare = channels
            .done
            .recv()
            .expect("the fuzzing worker thread is gone");
    }
}

/// Lower-case hex of `bytes` (for panic messages), with `j2735::hex`.
pub fn hex(bytes: &[u8]) -> String {
    j2735::hex::Hex(bytes).to_string()
}
