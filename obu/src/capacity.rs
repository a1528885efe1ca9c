//! Compile-time capacities, all in one place.
//!
//! Every bounded collection in the crate uses one of these constants. Raising one
//! raises the static RAM of [`crate::Obu`]; `tests/ram.rs` prints the total.

/// Lane models (MAP messages: intersections or road segments) kept at once.
pub const MAX_MAPS: usize = 4;
/// Lanes per lane model (J2735 allows 255; deployed MAPs stay well below 64).
pub const MAX_LANES: usize = 64;
/// Centreline nodes per lane (J2735 allows 63). Long segments are split, see
/// [`crate::lane::Lane::push_node_cm`].
pub const MAX_NODES: usize = 32;
/// Connections kept per lane (J2735 allows 16).
pub const MAX_CONNECTIONS: usize = 4;
/// Work zones (TIM data frames) kept at once.
pub const MAX_ZONES: usize = 8;
/// Regions per work zone (J2735 allows 16).
pub const MAX_REGIONS: usize = 4;
/// Path nodes per region, anchor included (J2735 allows 63 offsets).
pub const MAX_PATH_NODES: usize = 16;
/// ITIS codes kept per work zone (J2735 allows 100 items).
pub const MAX_ITIS: usize = 16;
/// Lanes a region can be associated with (closed lanes), over all maps.
pub const MAX_ZONE_LANES: usize = 8;
/// Alerts listed in one HMI state besides the primary one.
pub const MAX_ALERTS: usize = 6;
/// Closed lanes listed in one HMI state.
pub const MAX_HMI_LANES: usize = 8;
/// Lanes near the last fix that the matcher keeps for the lane-change advice.
pub const MAX_NEARBY_LANES: usize = 8;
