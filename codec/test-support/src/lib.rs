//! Helpers shared by the project's test trees (a dev-dependency only, never shipped):
//!
//! - [`shared`]: where `../shared` (the conformance corpus and the oracle) is, failing
//!   loudly when it is missing;
//! - [`corpus`]: the corpus frames with their names, and the oracle's JER per frame;
//! - [`vectors`]: the codec's oracle vectors (`codec/tests/vectors/oracle_vectors.jsonl`);
//! - [`signed_vectors`]: the independent IEEE 1609.2 signed-data vectors;
//! - [`oracle`]: the pycrate oracle's Python, made by `shared/oracle/setup.sh`, and a
//!   runner for scripts that use it;
//! - [`from_hex`] / [`to_hex`] (through `j2735::hex`) and [`big_stack`].
//!
//! Every function panics with a message that says what is missing or wrong: a test that
//! needs something absent fails, it never skips.
#![forbid(unsafe_code)]

pub mod corpus;
pub mod oracle;
pub mod shared;
pub mod signed_vectors;
pub mod vectors;

/// Bytes of hexadecimal text; whitespace anywhere is ignored (files end in a line break).
///
/// # Panics
///
/// When the text is not hexadecimal (odd length, a non-digit), naming the problem.
pub fn from_hex(text: &str) -> Vec<u8> {
    let digits: String = text.chars().filter(|c| !c.is_whitespace()).collect();
    let fail = |e: j2735::hex::HexError| -> ! { panic!("not hex ({e}): {text:?}") };
    let mut bytes = vec![0; j2735::hex::decoded_len(&digits).unwrap_or_else(|e| fail(e))];
    j2735::hex::decode_into(&digits, &mut bytes).unwrap_or_else(|e| fail(e));
    bytes
}

/// Lower-case hex of `bytes`.
pub fn to_hex(bytes: &[u8]) -> String {
    j2735::hex::Hex(bytes).to_string()
}

/// Runs `f` on a thread with room for the largest no-heap values (a MapData is megabytes);
/// a panic in `f` goes on in the caller.
pub fn big_stack<T: Send + 'static>(f: impl FnOnce() -> T + Send + 'static) -> T {
    std::thread::Builder::new()
        .stack_size(256 << 20)
        .spawn(f)
        .expect("spawn a test thread")
        .join()
        .unwrap_or_else(|e| std::panic::resume_unwind(e))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hex_both_ways() {
        assert_eq!(from_hex("00 1F\nab\n"), [0x00, 0x1f, 0xab]);
        assert_eq!(to_hex(&[0x00, 0x1f, 0xab]), "001fab");
        assert_eq!(big_stack(|| 2 + 2), 4);
    }

    #[test]
    #[should_panic(expected = "not hex")]
    fn bad_hex_fails_loudly() {
        from_hex("0g");
    }
}
