//! Sensor inputs shared by the daemon and the firmware: NMEA 0183 GNSS sentences and the
//! vehicle-speed signal of a CAN frame (with `candump` log lines).

pub mod can;
pub mod nmea;
