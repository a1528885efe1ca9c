//! The messages the benchmarks carry (shared by the inputs and both codecs' drivers).

/// The message a frame carries.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    /// MapData (messageId 18).
    Map,
    /// TravelerInformation (messageId 31).
    Tim,
}
