//! One GNSS fix as the core consumes it.

use crate::geo::LatLon;
use crate::time::UtcTime;

#[cfg(feature = "serde")]
use serde::{Deserialize, Serialize};

/// A position fix with speed and course (NMEA GGA/RMC/GST or gpsd TPV, CAN speed).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[cfg_attr(feature = "serde", derive(Serialize, Deserialize))]
pub struct Fix {
    /// Position.
    pub position: LatLon,
    /// Horizontal 1-sigma accuracy in metres (GST), if known.
    pub accuracy_m: Option<f32>,
    /// Speed in m/s (CAN or GNSS), if known.
    pub speed_mps: Option<f32>,
    /// Course over ground in degrees from north, if known.
    pub course_deg: Option<f32>,
    /// UTC time of the fix, if known (needed to check TIM validity windows).
    pub utc: Option<UtcTime>,
}

impl Fix {
    /// A fix at `position` with nothing else known.
    pub const fn at(position: LatLon) -> Self {
        Fix {
            position,
            accuracy_m: None,
            speed_mps: None,
            course_deg: None,
            utc: None,
        }
    }

    /// Speed if finite and not negative.
    pub fn speed(&self) -> Option<f32> {
        self.speed_mps
            .filter(|v| v.is_finite() && *v >= 0.0 && *v < 1000.0)
    }

    /// Course if finite, wrapped into `[0, 360)`.
    pub fn course(&self) -> Option<f32> {
        self.course_deg
            .filter(|v| v.is_finite())
            .map(crate::math::wrap_360)
    }

    /// Accuracy if finite and positive.
    pub fn accuracy(&self) -> Option<f32> {
        self.accuracy_m.filter(|v| v.is_finite() && *v > 0.0)
    }
}
