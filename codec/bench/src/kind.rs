//! The messages the benchmarks carry (shared by the inputs and both codecs' drivers).

/// The message a frame carries.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    /// MapData (messageId 18).
    Map,
    /// SPAT (messageId 19).
    Spat,
    /// BasicSafetyMessage (messageId 20).
    Bsm,
    /// TravelerInformation (messageId 31).
    Tim,
}

impl Kind {
    /// The kind of a corpus file named `<SHORT>_<n>...` (`MAP_061__...hex`).
    pub fn of_corpus_name(name: &str) -> Option<Kind> {
        match name.split('_').next()? {
            "MAP" => Some(Kind::Map),
            "SPAT" => Some(Kind::Spat),
            "BSM" => Some(Kind::Bsm),
            "TIM" => Some(Kind::Tim),
            _ => None,
        }
    }
}
