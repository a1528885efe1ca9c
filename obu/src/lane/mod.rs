//! Lane model: what a J2735 MAP says about lanes, in local metres.
//!
//! A [`LaneModel`] (one MAP intersection or road segment) has a reference point and up
//! to [`MAX_LANES`](crate::capacity::MAX_LANES) [`Lane`]s. A lane's centreline is a
//! polyline stored as centimetre deltas (compact: 6 bytes a node) in J2735 node order:
//! the first node is at the stop line, so ingress traffic moves from the last node to
//! the first and egress traffic follows the node order ([`TravelDirection`]).
//! [`MapStore`] keeps several models keyed by [`MapId`] and replaces one only when its
//! revision changes.

mod geometry;
mod model;
mod store;

pub use geometry::{Lane, LanePosition, Projection};
pub use model::{LaneModel, MapId};
pub use store::{MapStore, MapUpdate};

use core::fmt;

#[cfg(feature = "serde")]
use serde::{Deserialize, Serialize};

/// J2735 `LaneID` (0..=255) within one lane model.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Default)]
#[cfg_attr(feature = "serde", derive(Serialize, Deserialize))]
pub struct LaneId(pub u8);

impl fmt::Display for LaneId {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.0)
    }
}

/// Direction of travel from J2735 `LaneDirection` (`directionalUse` bits).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
#[cfg_attr(feature = "serde", derive(Serialize, Deserialize))]
pub enum TravelDirection {
    /// `ingressPath` only: traffic moves from the last node towards the first.
    Ingress,
    /// `egressPath` only: traffic follows the node order.
    #[default]
    Egress,
    /// Both bits: either way; the vehicle's heading decides.
    Both,
    /// Neither bit (e.g. a median): not matched against vehicles.
    None,
}

impl TravelDirection {
    /// From the two `directionalUse` bits.
    pub const fn from_bits(ingress: bool, egress: bool) -> Self {
        match (ingress, egress) {
            (true, false) => TravelDirection::Ingress,
            (false, true) => TravelDirection::Egress,
            (true, true) => TravelDirection::Both,
            (false, false) => TravelDirection::None,
        }
    }
}

/// J2735 `LaneTypeAttributes` choice (the attribute bits are not kept).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
#[cfg_attr(feature = "serde", derive(Serialize, Deserialize))]
pub enum LaneKind {
    /// Motor vehicle lane.
    #[default]
    Vehicle,
    /// Crosswalk.
    Crosswalk,
    /// Bike lane.
    Bike,
    /// Sidewalk.
    Sidewalk,
    /// Median or barrier.
    Median,
    /// Striping.
    Striping,
    /// Tracked vehicle (rail).
    Tracked,
    /// Parking.
    Parking,
    /// Unknown extension.
    Other,
}

/// A speed in J2735 `Velocity` units of 0.02 m/s; 8191 means unavailable.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
#[cfg_attr(feature = "serde", derive(Serialize, Deserialize))]
pub struct Speed(u16);

impl Default for Speed {
    fn default() -> Self {
        Speed::UNAVAILABLE
    }
}

impl Speed {
    /// "Unavailable" (J2735 value 8191).
    pub const UNAVAILABLE: Speed = Speed(8191);

    /// From J2735 units of 0.02 m/s; `None` above 8191.
    pub const fn from_units(v: u16) -> Option<Self> {
        if v <= 8191 {
            Some(Speed(v))
        } else {
            None
        }
    }

    /// From metres per second, rounded; unavailable when negative, NaN or too large.
    pub fn from_mps(mps: f32) -> Self {
        let u = libm::roundf(mps * 50.0);
        if u.is_finite() && (0.0..8191.0).contains(&u) {
            Speed(u as u16)
        } else {
            Speed::UNAVAILABLE
        }
    }

    /// From kilometres per hour.
    pub fn from_kmh(kmh: f32) -> Self {
        Speed::from_mps(kmh / 3.6)
    }

    /// From miles per hour.
    pub fn from_mph(mph: f32) -> Self {
        Speed::from_mps(mph * 0.447_04)
    }

    /// J2735 units of 0.02 m/s.
    pub const fn units(self) -> u16 {
        self.0
    }

    /// Metres per second, `None` when unavailable.
    pub fn mps(self) -> Option<f32> {
        self.is_available().then_some(self.0 as f32 / 50.0)
    }

    /// False for the "unavailable" value.
    pub const fn is_available(self) -> bool {
        self.0 < 8191
    }

    /// The lower of two speeds, ignoring unavailable ones.
    pub fn min_available(self, other: Speed) -> Speed {
        match (self.is_available(), other.is_available()) {
            (true, true) => Speed(self.0.min(other.0)),
            (true, false) => self,
            _ => other,
        }
    }
}

/// The speed limits of a lane that matter here (from J2735 `SpeedLimitList`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
#[cfg_attr(feature = "serde", derive(Serialize, Deserialize))]
pub struct SpeedLimits {
    /// Regulatory maximum (`vehicleMaxSpeed` / `maxSpeedInSchoolZone...` excluded).
    pub max: Speed,
    /// `maxSpeedInConstructionZone`.
    pub construction_max: Speed,
}

impl SpeedLimits {
    /// Both limits unavailable.
    pub const UNAVAILABLE: SpeedLimits = SpeedLimits {
        max: Speed::UNAVAILABLE,
        construction_max: Speed::UNAVAILABLE,
    };

    /// `self` with each available value of `newer` in its place.
    pub fn replaced_by(self, newer: SpeedLimits) -> SpeedLimits {
        let pick = |old: Speed, new: Speed| if new.is_available() { new } else { old };
        SpeedLimits {
            max: pick(self.max, newer.max),
            construction_max: pick(self.construction_max, newer.construction_max),
        }
    }

    /// The lower available value of each kind.
    pub fn lower(self, other: SpeedLimits) -> SpeedLimits {
        SpeedLimits {
            max: self.max.min_available(other.max),
            construction_max: self.construction_max.min_available(other.construction_max),
        }
    }
}

/// Errors while filling a model from a decoded message.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum ModelError {
    /// A capacity of [`crate::capacity`] would be exceeded.
    CapacityExceeded,
    /// A value was NaN, infinite or out of range.
    InvalidValue,
    /// A lane with this id already exists in the model.
    DuplicateLane,
}

impl fmt::Display for ModelError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            ModelError::CapacityExceeded => "capacity exceeded",
            ModelError::InvalidValue => "invalid value",
            ModelError::DuplicateLane => "duplicate lane id",
        })
    }
}

impl core::error::Error for ModelError {}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn speed_units() {
        assert_eq!(Speed::from_kmh(36.0).units(), 500);
        assert_eq!(Speed::from_mps(f32::NAN), Speed::UNAVAILABLE);
        assert_eq!(Speed::from_mps(-1.0), Speed::UNAVAILABLE);
        assert_eq!(Speed::from_units(9000), None);
        assert_eq!(
            Speed::from_mph(25.0).mps().map(|v| (v * 10.0).round()),
            Some(112.0)
        );
        let a = Speed::from_kmh(40.0);
        assert_eq!(a.min_available(Speed::UNAVAILABLE), a);
        assert_eq!(Speed::UNAVAILABLE.min_available(a), a);
        assert_eq!(
            TravelDirection::from_bits(true, false),
            TravelDirection::Ingress
        );
    }
}
