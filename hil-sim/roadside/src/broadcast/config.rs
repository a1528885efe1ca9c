//! Why a fault or rate setting was refused: shared by the loss models, the fault injector
//! and the broadcaster.

use super::MAX_RATE_HZ;
use std::fmt;

/// Why a fault or rate setting was refused.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ConfigError {
    /// A probability or fraction outside 0-1 (or not a number).
    Probability {
        /// Which setting.
        what: &'static str,
        /// Its value.
        value: f64,
    },
    /// A mean burst length below 1 datagram.
    BurstLength {
        /// The value.
        value: f64,
    },
    /// Bursts this short cannot lose this much: the good state would have to turn bad
    /// more than always.
    BurstsTooShort {
        /// The asked loss rate.
        rate: f64,
        /// The asked mean burst length.
        mean_burst_len: f64,
    },
    /// A rate outside (0, [`MAX_RATE_HZ`]] Hz.
    Rate {
        /// The value, Hz.
        hz: f64,
    },
}

impl fmt::Display for ConfigError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Probability { what, value } => {
                write!(f, "{what} is {value}; it must be a fraction from 0 to 1")
            }
            Self::BurstLength { value } => {
                write!(f, "mean burst length {value}; it must be at least 1 datagram")
            }
            Self::BurstsTooShort {
                rate,
                mean_burst_len,
            } => write!(
                f,
                "a loss rate of {rate} needs bursts of at least {:.2} datagrams on average, not {mean_burst_len}",
                rate / (1.0 - rate)
            ),
            Self::Rate { hz } => write!(
                f,
                "rate {hz} Hz; it must be above 0 and at most {MAX_RATE_HZ} Hz"
            ),
        }
    }
}

impl std::error::Error for ConfigError {}
