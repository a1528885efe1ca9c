//! The independent IEEE 1609.2 signed-data vectors: `codec/tests/vectors/ieee1609dot2_signed.jsonl`
//! (made by `codec/codegen/make_signed_vectors.py` with pycrate and Python `cryptography`).

use serde_json::Value;

/// One signed-data vector (the members are documented in the generator).
#[derive(Clone, Debug, PartialEq)]
pub struct SignedVector {
    /// Its name, such as `valid_tim_digest_x_only`.
    pub name: String,
    /// The case, such as `payload bit flipped`.
    pub case: String,
    /// `valid`, or the failure in words.
    pub expect: String,
    /// The whole `Ieee1609Dot2Data`, COER.
    pub coer: Vec<u8>,
    /// `digest`, `certificate`, `certificate-chain` or `self`.
    pub signer: String,
    /// The header's PSID.
    pub psid: u32,
    /// The header's generation time (`Time64`).
    pub generation_time: u64,
    /// The header's expiry time (`Time64`), if it has one.
    pub expiry_time: Option<u64>,
    /// The J2735 `MessageFrame` inside (UPER).
    pub frame: Vec<u8>,
    /// The trusted root certificate (COER).
    pub root: Vec<u8>,
    /// The trusted issuing CA certificate (COER).
    pub ca: Vec<u8>,
    /// Certificates the verifier has seen before (for the digest signer).
    pub known_certs: Vec<Vec<u8>>,
    /// The verifier's clock (`Time64`).
    pub now: u64,
    /// The verifier's profile: how far ahead a generation time may be (and how long past
    /// its expiry time a message is taken), microseconds.
    pub future_tolerance_us: u64,
    /// The verifier's profile: how long after its generation a message without an expiry
    /// time is taken, microseconds.
    pub past_window_us: u64,
    /// The verifier's profile: the longest generation-to-expiry lifetime, microseconds.
    pub max_lifetime_us: u64,
    /// The self signer's key (compressed SEC 1), for `self`.
    pub self_public_key: Option<Vec<u8>>,
    /// The root the chain really leads to, for `untrusted_root`.
    pub untrusted_root: Option<Vec<u8>>,
    /// The ECQV reconstructed key (compressed SEC 1), for implicit certificates.
    pub reconstructed_public_key: Option<Vec<u8>>,
    /// `repeat` for the two vectors of the repeat pair.
    pub pair: Option<String>,
    /// IEEE 1609.3 WAVE Short Messages around this vector or its bare frame: (the datagram,
    /// the verdict in words).
    pub wsmp: Vec<(Vec<u8>, String)>,
}

/// The file's text (compiled in: the vectors are part of the repository).
const TEXT: &str = include_str!("../../tests/vectors/ieee1609dot2_signed.jsonl");

/// Every vector, in file order (sorted by name).
///
/// # Panics
///
/// When a line is not a vector.
pub fn all() -> Vec<SignedVector> {
    TEXT.lines().map(parse).collect()
}

fn parse(line: &str) -> SignedVector {
    let v: Value = serde_json::from_str(line).expect("a JSON line");
    let text = |key: &str| {
        v[key]
            .as_str()
            .unwrap_or_else(|| panic!("{key}"))
            .to_owned()
    };
    let hex = |key: &str| crate::from_hex(&text(key));
    let number = |key: &str| v[key].as_u64().unwrap_or_else(|| panic!("{key}"));
    let optional_hex = |key: &str| v[key].as_str().map(crate::from_hex);
    let anchors = &v["trust_anchors"];
    let anchor = |key: &str| crate::from_hex(anchors[key].as_str().expect("trust anchor"));
    SignedVector {
        name: text("name"),
        case: text("case"),
        expect: text("expect"),
        coer: hex("coer"),
        signer: text("signer"),
        psid: u32::try_from(number("psid")).expect("a 32-bit PSID"),
        generation_time: number("generation_time"),
        expiry_time: v["expiry_time"].as_u64(),
        frame: hex("frame"),
        root: anchor("root"),
        ca: anchor("ca"),
        known_certs: v["known_certs"]
            .as_array()
            .expect("known_certs")
            .iter()
            .map(|c| crate::from_hex(c.as_str().expect("certificate hex")))
            .collect(),
        now: number("now"),
        future_tolerance_us: number("future_tolerance_us"),
        past_window_us: number("past_window_us"),
        max_lifetime_us: number("max_lifetime_us"),
        self_public_key: optional_hex("self_public_key"),
        untrusted_root: optional_hex("untrusted_root"),
        reconstructed_public_key: optional_hex("reconstructed_public_key"),
        pair: v["pair"].as_str().map(str::to_owned),
        wsmp: v["wsmp"]
            .as_array()
            .map(|list| {
                list.iter()
                    .map(|w| {
                        let bytes = crate::from_hex(w["bytes"].as_str().expect("wsmp bytes"));
                        (bytes, w["expect"].as_str().expect("wsmp expect").to_owned())
                    })
                    .collect()
            })
            .unwrap_or_default(),
    }
}
