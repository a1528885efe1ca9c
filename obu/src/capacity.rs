//! Compile-time capacities, all in one place.
//!
//! Every bounded collection in the crate uses one of these constants. Raising one
//! raises the static RAM of [`crate::Obu`]; `obu/ram-probe` prints the total on the
//! firmware target.
//!
//! Feature `firmware-capacities` selects a smaller profile of the stores for a
//! microcontroller (with the codec's matching profile): fewer maps, lanes and zones. The HMI
//! output ([`MAX_ALERTS`], [`MAX_HMI_LANES`]) is the same in both profiles, so that the
//! firmware's `HmiState` stream decodes on the Linux side.

/// Picks the value of the build's profile: default, or `firmware-capacities`.
macro_rules! profile {
    ($(#[$doc:meta])* $name:ident = $default:expr, firmware $firmware:expr) => {
        $(#[$doc])*
        #[cfg(not(feature = "firmware-capacities"))]
        pub const $name: usize = $default;
        $(#[$doc])*
        #[cfg(feature = "firmware-capacities")]
        pub const $name: usize = $firmware;
    };
}

profile! {
    /// Lane models (MAP messages: intersections or road segments) kept at once.
    MAX_MAPS = 4, firmware 2
}
profile! {
    /// Lanes per lane model (J2735 allows 255; deployed MAPs stay well below 64).
    MAX_LANES = 64, firmware 8
}
/// Centreline nodes per lane (J2735 allows 63). Long segments are split, see
/// [`crate::lane::Lane::push_node_cm`].
pub const MAX_NODES: usize = 32;
/// Connections kept per lane (J2735 allows 16).
pub const MAX_CONNECTIONS: usize = 4;
profile! {
    /// Work zones (TIM data frames) kept at once.
    MAX_ZONES = 8, firmware 4
}
profile! {
    /// Regions per work zone (J2735 allows 16).
    MAX_REGIONS = 4, firmware 2
}
/// Path nodes per region, anchor included (J2735 allows 63 offsets).
pub const MAX_PATH_NODES: usize = 16;
profile! {
    /// ITIS codes kept per work zone (J2735 allows 100 items).
    MAX_ITIS = 16, firmware 8
}
/// Lanes a region can be associated with (closed lanes), over all maps.
pub const MAX_ZONE_LANES: usize = 8;
/// Alerts listed in one HMI state besides the primary one.
pub const MAX_ALERTS: usize = 6;
/// Closed lanes listed in one HMI state.
pub const MAX_HMI_LANES: usize = 8;
/// Lanes near the last fix that the matcher keeps for the lane-change advice.
pub const MAX_NEARBY_LANES: usize = 8;
/// Road workers (PSMs, by temporary id) kept at once: 32 bytes each
/// ([`crate::worker::Worker`]). Beyond it a new worker replaces a silent or far one
/// ([`crate::worker::WorkerStore`]).
pub const MAX_WORKERS: usize = 16;
/// Road workers listed in one HMI state (the nearest).
pub const MAX_HMI_WORKERS: usize = 8;

profile! {
    /// Trust anchors (root and issuing CA certificates) a verifier holds.
    MAX_TRUST_ANCHORS = 4, firmware 2
}
profile! {
    /// Verified signer certificates cached by `HashedId8`.
    MAX_CACHED_CERTS = 16, firmware 2
}
profile! {
    /// PSIDs kept per certificate (its app or issue permissions); a certificate with more is
    /// refused.
    MAX_CERT_PSIDS = 8, firmware 4
}
profile! {
    /// Points kept per certificate region: polygon vertices, or two per rectangle.
    MAX_REGION_POINTS = 12, firmware 6
}
/// Certificates in a signer's chain that the verifier walks.
pub const MAX_CHAIN: usize = 4;
profile! {
    /// Accepted signed messages remembered while relevant, for the repeat and replay check.
    MAX_REPEATS = 256, firmware 8
}
profile! {
    /// Message identities whose newest accepted generation time is kept (superseded check).
    MAX_NEWEST = 64, firmware 8
}
profile! {
    /// Payloads remembered as verified lately (`SecurityConfig::reverify_ms`).
    MAX_RECENT = 16, firmware 4
}
profile! {
    /// Octets of an opaque SSP kept per certificate PSID; a certificate with a longer one is
    /// refused.
    MAX_SSP = 16, firmware 8
}
