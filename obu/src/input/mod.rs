//! Sensor inputs shared by the daemon and the firmware: a GNSS receiver's stream (NMEA
//! 0183 sentences and u-blox UBX frames, [`gnss`]) and the vehicle-speed signal of a CAN
//! frame (with `candump` log lines).

pub mod can;
pub mod gnss;
pub mod nmea;
pub mod ubx;

#[cfg(test)]
mod tests;
