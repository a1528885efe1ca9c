//! What the commands write: JSON error lines and the overall outcome.

/// How a command ended, for the exit status.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Outcome {
    /// Every frame was handled.
    AllDone,
    /// Some frame failed (its output line says why); the others were handled.
    SomeFailed,
}

impl Outcome {
    /// The outcome after one more frame (`ok`: whether it succeeded).
    #[must_use]
    pub fn and(self, ok: bool) -> Self {
        if ok {
            self
        } else {
            Self::SomeFailed
        }
    }
}

/// The compact JSON line `{"error":"<message>"}`.
pub fn error_line(message: &str) -> String {
    serde_json::json!({ "error": message }).to_string()
}

/// Lower-case hex of `bytes`.
pub fn to_hex(bytes: &[u8]) -> String {
    j2735::hex::Hex(bytes).to_string()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn error_lines_are_escaped_json() {
        assert_eq!(error_line("bad \"x\""), r#"{"error":"bad \"x\""}"#);
        assert_eq!(to_hex(&[0, 0x1f, 0xab]), "001fab");
        assert_eq!(Outcome::AllDone.and(true), Outcome::AllDone);
        assert_eq!(Outcome::AllDone.and(false).and(true), Outcome::SomeFailed);
    }
}
