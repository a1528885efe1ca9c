//! Target `jer`: JER (X.697) text of a `MessageFrame` read, UPER-encoded, decoded, written as
//! JER and read again.
//!
//! Invariants, for every input that is UTF-8 and reads as a `MessageFrame` `v`:
//! 1. `uper::encoded_len(v)` / `uper::encode(v)` fail only because a size is outside its
//!    constraint (`SizeOutOfRange`, `OpenTypeTooLarge`: the JER reader does not check every
//!    SIZE constraint, the encoder does); otherwise they agree on the length.
//! 2. That encoding decodes, to a value `d` equal to `v` (nothing of a JER value is lost on
//!    its way through UPER).
//! 3. The JER of `d` reads back to a value equal to `d`, and writing that gives the same text.

use j2735::jer;
use j2735::uper::{self, EncodeErrorKind, Placeholder};
use j2735::MessageFrame;

use crate::hex;

/// The values kept across inputs (made once, on the big-stack thread).
pub struct State {
    decoded: Box<MessageFrame>,
    encoding: Vec<u8>,
}

impl State {
    /// Placeholders of the kept values. Needs a large stack.
    pub fn new() -> Self {
        Self {
            decoded: Box::new(MessageFrame::placeholder()),
            encoding: Vec::new(),
        }
    }
}

impl Default for State {
    fn default() -> Self {
        Self::new()
    }
}

/// Runs every check of this target on `data`. Needs a large stack: JER reading returns the
/// 7.2 MB `MessageFrame` by value.
pub fn check(st: &mut State, data: &[u8]) {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    let Ok(value) = jer::from_str::<MessageFrame>(text) else {
        return;
    };
    let len = match uper::encoded_len(&value) {
        Ok(len) => len,
        Err(e) => {
            assert!(
                matches!(
                    e.kind,
                    EncodeErrorKind::SizeOutOfRange | EncodeErrorKind::OpenTypeTooLarge
                ),
                "a JER value read without error does not encode: {e}; input {text:?}"
            );
            return;
        }
    };
    st.encoding.clear();
    st.encoding.resize(len + 8, 0);
    let n = uper::encode(&value, &mut st.encoding)
        .unwrap_or_else(|e| panic!("encoded_len is {len} but encode fails: {e}; input {text:?}"));
    assert_eq!(
        n, len,
        "encode wrote {n} octets, encoded_len said {len}; input {text:?}"
    );
    st.encoding.truncate(n);
    if let Err(e) = uper::decode_into(&st.encoding, &mut *st.decoded) {
        panic!(
            "UPER of a JER value does not decode: {e}; input {text:?}, UPER {}",
            hex(&st.encoding)
        );
    }
    assert!(
        *st.decoded == value,
        "JER -> UPER -> value differs from the JER value; input {text:?}, UPER {}, \
         JER of the decoded value {}",
        hex(&st.encoding),
        jer::to_string(&*st.decoded)
    );
    let written = jer::to_string(&*st.decoded);
    let reread = match jer::from_str::<MessageFrame>(&written) {
        Ok(v) => v,
        Err(e) => panic!(
            "our JER does not read back: {e}; input {text:?}, UPER {}, our JER {written}",
            hex(&st.encoding)
        ),
    };
    assert!(
        reread == *st.decoded,
        "our JER reads back to another value; input {text:?}, our JER {written}"
    );
    let rewritten = jer::to_string(&reread);
    assert!(
        rewritten == written,
        "our JER is not stable; input {text:?}, first {written}, second {rewritten}"
    );
}
