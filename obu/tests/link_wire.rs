//! Literal wire fixtures of the serial link (`obu::link`): frames written out by hand from
//! the layout in the module docs, `COBS(payload ++ crc32_le(payload)) ++ 0x00`, and checked
//! against both directions (encode gives these bytes; the deframer gives the payload back).
//!
//! The CRC-32 values are not computed by the code under test: they come from Python's zlib
//! (`python3 -c "import zlib; print(hex(zlib.crc32(b'...')))"`), the same IEEE 802.3 CRC.
//! COBS: each code byte is 1 + the number of non-zero bytes that follow before the next
//! (replaced) zero; 0xFF means 254 non-zero bytes with no zero after them.

use obu::link::{encode, encoded_len, Deframer, FrameError};

/// (payload, wire frame) pairs, written from the layout.
fn fixtures() -> Vec<(Vec<u8>, Vec<u8>)> {
    vec![
        // Empty payload: zlib.crc32(b"") = 0x00000000, so the data is 00 00 00 00; COBS turns
        // each zero into a code byte 01, plus the final code 01.
        (vec![], vec![0x01, 0x01, 0x01, 0x01, 0x01, 0x00]),
        // 01: zlib.crc32(b"\x01") = 0xa505df1b, little endian 1b df 05 a5; no zero in
        // 01 1b df 05 a5, so one code 06 then the five bytes.
        (vec![0x01], vec![0x06, 0x01, 0x1b, 0xdf, 0x05, 0xa5, 0x00]),
        // 00: zlib.crc32(b"\x00") = 0xd202ef8d -> 8d ef 02 d2; data 00 8d ef 02 d2: code 01
        // for the leading zero, then code 05 and the four CRC bytes.
        (vec![0x00], vec![0x01, 0x05, 0x8d, 0xef, 0x02, 0xd2, 0x00]),
        // 11 22 00 33: zlib.crc32 = 0x4df81c7e -> 7e 1c f8 4d; data 11 22 | 00 | 33 7e 1c f8 4d.
        (
            vec![0x11, 0x22, 0x00, 0x33],
            vec![
                0x03, 0x11, 0x22, // code 03: two bytes, then the zero
                0x06, 0x33, 0x7e, 0x1c, 0xf8, 0x4d, // code 06: five bytes to the end
                0x00, // frame delimiter
            ],
        ),
        // 12 34 56 78 9a: zlib.crc32 = 0x3c4687af -> af 87 46 3c; nine bytes, no zero.
        (
            vec![0x12, 0x34, 0x56, 0x78, 0x9a],
            vec![
                0x0a, 0x12, 0x34, 0x56, 0x78, 0x9a, 0xaf, 0x87, 0x46, 0x3c, 0x00,
            ],
        ),
    ]
}

/// 01 02 .. fe (254 non-zero octets): zlib.crc32 = 0x7963003c -> 3c 00 63 79, whose second
/// octet is a zero. COBS: FF + the 254 octets (a full block, no zero implied), then
/// 02 3c (the zero), then 03 63 79, then the delimiter.
fn long_fixture() -> (Vec<u8>, Vec<u8>) {
    let payload: Vec<u8> = (0x01..=0xfe).collect();
    let mut wire = vec![0xff];
    wire.extend(0x01..=0xfeu8);
    wire.extend([0x02, 0x3c, 0x03, 0x63, 0x79, 0x00]);
    (payload, wire)
}

/// Every payload the deframer gives for `wire`.
fn deframe(wire: &[u8]) -> Vec<Result<Vec<u8>, FrameError>> {
    let mut deframer = Deframer::<512>::new();
    wire.iter()
        .filter_map(|&b| deframer.push(b).map(|r| r.map(<[u8]>::to_vec)))
        .collect()
}

#[test]
fn encode_writes_the_literal_frames() {
    for (payload, wire) in fixtures().into_iter().chain([long_fixture()]) {
        let mut out = [0u8; 512];
        let n = encode(&payload, &mut out).unwrap();
        assert_eq!(&out[..n], &wire[..], "payload {payload:02x?}");
        assert!(n <= encoded_len(payload.len()));
    }
    assert_eq!(long_fixture().1.len(), 261);
}

#[test]
fn the_deframer_reads_the_literal_frames() {
    for (payload, wire) in fixtures().into_iter().chain([long_fixture()]) {
        assert_eq!(deframe(&wire), [Ok(payload.clone())], "wire {wire:02x?}");
    }
    // Back to back, with extra delimiters between them (empty frames are skipped).
    let mut stream = vec![0x00];
    let mut expected = Vec::new();
    for (payload, wire) in fixtures() {
        stream.extend(&wire);
        stream.push(0x00);
        expected.push(Ok(payload));
    }
    assert_eq!(deframe(&stream), expected);
}

#[test]
fn damaged_literal_frames_are_rejected() {
    // 01 with its last CRC octet changed (a5 -> a4).
    let wire = [0x06, 0x01, 0x1b, 0xdf, 0x05, 0xa4, 0x00];
    assert_eq!(deframe(&wire), [Err(FrameError::Crc)]);
    // A code byte pointing past the frame's end.
    let wire = [0x09, 0x01, 0x1b, 0xdf, 0x05, 0xa5, 0x00];
    assert_eq!(deframe(&wire), [Err(FrameError::Cobs)]);
    // Three data octets: no room for a CRC.
    let wire = [0x04, 0x01, 0x02, 0x03, 0x00];
    assert_eq!(deframe(&wire), [Err(FrameError::TooShort)]);
}
