//! One GNSS fix as the core consumes it.

use crate::geo::LatLon;
use crate::time::UtcTime;

#[cfg(feature = "serde")]
use serde::{Deserialize, Serialize};

/// Where a fix's horizontal accuracy comes from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
#[cfg_attr(feature = "serde", derive(Serialize, Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "snake_case"))]
pub enum AccuracySource {
    /// Not known: the lane filter assumes its default.
    #[default]
    None,
    /// The receiver's error statistics (NMEA GST).
    Gst,
    /// The receiver's own horizontal accuracy estimate (u-blox UBX NAV-PVT `hAcc`).
    Ubx,
    /// HDOP times the range error of the solution's kind
    /// ([`crate::input::nmea::AccuracyModel`]).
    Hdop,
    /// gpsd's error estimate (TPV `epx`/`epy` or `eph`).
    Gpsd,
}

impl AccuracySource {
    /// A short lowercase name, for `/api/status` and logs.
    pub const fn as_str(self) -> &'static str {
        match self {
            Self::None => "none",
            Self::Gst => "gst",
            Self::Ubx => "ubx",
            Self::Hdop => "hdop",
            Self::Gpsd => "gpsd",
        }
    }
}

/// A position fix with speed and course (NMEA GGA/RMC/GST or gpsd TPV, CAN speed).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[cfg_attr(feature = "serde", derive(Serialize, Deserialize))]
pub struct Fix {
    /// Position.
    pub position: LatLon,
    /// Horizontal 1-sigma accuracy in metres, if known.
    pub accuracy_m: Option<f32>,
    /// Where `accuracy_m` comes from.
    #[cfg_attr(feature = "serde", serde(default))]
    pub accuracy_source: AccuracySource,
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
            accuracy_source: AccuracySource::None,
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
