//! The processes and threads behind a daemon in bridge mode when the firmware is the
//! device under test: QEMU, the defmt log decoder and the UDP -> serial relays
//! ([`crate::firmware`] starts them; a [`crate::daemon::Daemon`] owns them).

use std::process::Child;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::Arc;
use std::thread::JoinHandle;

/// QEMU and the relays of a running rig; stopped (QEMU killed, relays ended) on drop.
#[derive(Debug)]
pub struct Rig {
    pub(crate) qemu: Child,
    pub(crate) decoder: Option<Child>,
    pub(crate) stop: Arc<AtomicBool>,
    pub(crate) relays: Vec<JoinHandle<()>>,
    /// The firmware's decoded defmt log (`firmware.log`).
    pub log: std::path::PathBuf,
    /// Bytes written to the firmware's serial ports (NMEA, V2X link frames).
    pub relayed: Arc<[AtomicU64; 2]>,
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
    }
}
