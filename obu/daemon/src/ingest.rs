//! Decoded messages into the core: MAP and TIM are stored, others only counted.

use crate::hub::Hub;
use j2735::MessageFrame;

/// Gives a decoded frame to the core; the error is the core's reason for refusing (part of) it.
pub fn frame(hub: &Hub, mf: &MessageFrame) -> Result<(), String> {
    hub.on_frame(mf).map(|_| ()).map_err(|e| e.to_string())
}
