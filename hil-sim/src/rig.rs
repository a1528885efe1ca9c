//! The processes and threads behind a daemon in bridge mode when the firmware is the
//! device under test: QEMU, the defmt log decoder, the NMEA relay and the radio's relay
//! ([`crate::firmware`] starts them; a [`crate::daemon::Daemon`] owns them).

use crate::radio::{LinkCounts, RadioQueue};
use std::process::Child;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::{Arc, Mutex, MutexGuard};
use std::thread::JoinHandle;

/// QEMU and the relays of a running rig; stopped (QEMU killed, relays ended, the V2X
/// port's socket file removed) on drop.
#[derive(Debug)]
pub struct Rig {
    pub(crate) qemu: Child,
    pub(crate) decoder: Option<Child>,
    pub(crate) stop: Arc<AtomicBool>,
    pub(crate) relays: Vec<JoinHandle<()>>,
    /// The firmware's decoded defmt log (`firmware.log`).
    pub log: std::path::PathBuf,
    /// Bytes written to the firmware's NMEA port.
    pub nmea_relayed: Arc<AtomicU64>,
    /// The radio chip in front of the firmware's V2X port.
    pub(crate) radio: Arc<Mutex<RadioQueue>>,
    /// The V2X port's Unix socket (QEMU's end).
    pub(crate) v2x_socket: std::path::PathBuf,
}

impl Rig {
    /// The radio's buffers (a relay thread that panicked leaves them as they were).
    pub(crate) fn radio(&self) -> MutexGuard<'_, RadioQueue> {
        self.radio.lock().unwrap_or_else(|p| p.into_inner())
    }

    /// What became of the V2X frames the radio received so far.
    pub fn radio_counts(&self) -> LinkCounts {
        self.radio().counts().clone()
    }
}

impl Drop for Rig {
    fn drop(&mut self) {
        self.stop.store(true, Ordering::Relaxed);
        let _ = self.qemu.kill();
        let _ = self.qemu.wait();
        if let Some(d) = &mut self.decoder {
            let _ = d.wait();
        }
        for r in self.relays.drain(..) {
            let _ = r.join();
        }
        let _ = std::fs::remove_file(&self.v2x_socket);
    }
}
