//! The serial link between the firmware and the Linux side: COBS frames with a CRC-32.
//!
//! A frame on the wire is `COBS(payload ++ crc32_le(payload)) ++ 0x00`. The zero byte ends
//! a frame, so a receiver that starts mid-stream or loses bytes resynchronises at the next
//! zero; the CRC rejects corrupted frames. Used for V2X frames into the firmware (payload: a
//! UPER `MessageFrame`, as a radio chip would forward it) and `HmiState` out of it
//! (payload: postcard).
//!
//! Written by hand (COBS and a bitwise CRC-32, a few dozen lines of logic) rather than with
//! crates: it runs in the firmware's receive path with no heap and a fixed buffer, deframes
//! byte by byte as the USART interrupt delivers them, counts each kind of bad frame by its
//! own reason, and the bitwise CRC keeps a 1 KiB table out of flash.
//!
//! ## Panic contract
//! No function here panics on any input: [`encode`] checks the output length first
//! ([`encoded_len`]) and [`Deframer::push`] bounds every write by its buffer.

/// Why a frame was rejected.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum FrameError {
    /// The frame is longer than the receive buffer (the rest up to the next zero is dropped).
    TooLong,
    /// The COBS encoding is invalid (a code byte points past the frame's end).
    Cobs,
    /// Fewer than 4 octets: no room for the CRC.
    TooShort,
    /// The CRC does not match the payload.
    Crc,
    /// The output buffer is too small for the encoded frame.
    NoRoom,
}

impl core::fmt::Display for FrameError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(match self {
            FrameError::TooLong => "frame too long",
            FrameError::Cobs => "invalid COBS encoding",
            FrameError::TooShort => "frame shorter than its CRC",
            FrameError::Crc => "CRC mismatch",
            FrameError::NoRoom => "output buffer too small",
        })
    }
}

/// CRC-32 (IEEE 802.3: reflected, polynomial 0xEDB88320, init and final xor 0xFFFFFFFF).
pub fn crc32(data: &[u8]) -> u32 {
    let mut crc = !0u32;
    for &b in data {
        crc ^= u32::from(b);
        for _ in 0..8 {
            let mask = (crc & 1).wrapping_neg();
            crc = (crc >> 1) ^ (0xEDB8_8320 & mask);
        }
    }
    !crc
}

/// Octets of the wire frame of a `payload_len`-octet payload, final zero included.
pub const fn encoded_len(payload_len: usize) -> usize {
    let n = payload_len + 4;
    n + n / 254 + 2
}

/// Writes the frame of `payload` into `out`; returns its length (final zero included).
pub fn encode(payload: &[u8], out: &mut [u8]) -> Result<usize, FrameError> {
    if out.len() < encoded_len(payload.len()) {
        return Err(FrameError::NoRoom);
    }
    let crc = crc32(payload).to_le_bytes();
    let mut code_at = 0;
    let mut at = 1;
    let mut code = 1u8;
    for &b in payload.iter().chain(crc.iter()) {
        if b == 0 {
            out[code_at] = code;
            code_at = at;
            at += 1;
            code = 1;
        } else {
            out[at] = b;
            at += 1;
            code += 1;
            if code == 0xFF {
                out[code_at] = code;
                code_at = at;
                at += 1;
                code = 1;
            }
        }
    }
    out[code_at] = code;
    out[at] = 0;
    Ok(at + 1)
}

/// Decodes COBS in place (`buf` holds one frame without its final zero); returns the length
/// of the decoded content.
fn cobs_decode_in_place(buf: &mut [u8]) -> Result<usize, FrameError> {
    let (mut read, mut write) = (0, 0);
    while read < buf.len() {
        let code = buf[read] as usize;
        if code == 0 || read + code > buf.len() {
            return Err(FrameError::Cobs);
        }
        read += 1;
        for _ in 1..code {
            buf[write] = buf[read];
            write += 1;
            read += 1;
        }
        if code != 0xFF && read < buf.len() {
            buf[write] = 0;
            write += 1;
        }
    }
    Ok(write)
}

/// Checks and strips the CRC of a decoded frame.
fn check_crc(content: &[u8]) -> Result<&[u8], FrameError> {
    let Some(split) = content.len().checked_sub(4) else {
        return Err(FrameError::TooShort);
    };
    let (payload, crc) = content.split_at(split);
    let want = u32::from_le_bytes([crc[0], crc[1], crc[2], crc[3]]);
    if crc32(payload) == want {
        Ok(payload)
    } else {
        Err(FrameError::Crc)
    }
}

/// Collects bytes into frames: push every received byte, get a payload at each frame end.
#[derive(Debug, Clone)]
pub struct Deframer<const N: usize> {
    buf: [u8; N],
    len: usize,
    overflow: bool,
}

impl<const N: usize> Default for Deframer<N> {
    fn default() -> Self {
        Self::new()
    }
}

impl<const N: usize> Deframer<N> {
    /// An empty deframer holding frames of up to `N` wire octets.
    pub const fn new() -> Self {
        Self {
            buf: [0; N],
            len: 0,
            overflow: false,
        }
    }

    /// Takes one received byte. Returns `None` inside a frame; at its end the payload (CRC
    /// checked) or why the frame was rejected. Empty frames (repeated zeros) are skipped.
    pub fn push(&mut self, byte: u8) -> Option<Result<&[u8], FrameError>> {
        if byte != 0 {
            if self.len < N {
                self.buf[self.len] = byte;
                self.len += 1;
            } else {
                self.overflow = true;
            }
            return None;
        }
        let (len, overflow) = (self.len, self.overflow);
        self.len = 0;
        self.overflow = false;
        if overflow {
            return Some(Err(FrameError::TooLong));
        }
        if len == 0 {
            return None;
        }
        let buf = &mut self.buf[..len];
        Some(cobs_decode_in_place(buf).and_then(|n| check_crc(&buf[..n])))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn roundtrip(payload: &[u8]) {
        let mut wire = [0u8; 2048];
        let n = encode(payload, &mut wire).unwrap();
        assert!(n <= encoded_len(payload.len()));
        assert!(wire[..n - 1].iter().all(|&b| b != 0));
        let mut d = Deframer::<2048>::new();
        let mut got = None;
        for &b in &wire[..n] {
            if let Some(r) = d.push(b) {
                got = Some(r.map(|p| p.to_vec()));
            }
        }
        assert_eq!(got, Some(Ok(payload.to_vec())));
    }

    #[test]
    fn crc32_check_value() {
        assert_eq!(crc32(b"123456789"), 0xCBF4_3926);
    }

    #[test]
    fn frames_roundtrip() {
        roundtrip(&[]);
        roundtrip(&[0]);
        roundtrip(&[0, 0, 1, 0]);
        roundtrip(&[0x11; 253]);
        roundtrip(&[0x11; 254]);
        roundtrip(&[0x11; 600]);
        let mixed: std::vec::Vec<u8> = (0..1000u32).map(|i| (i % 7) as u8).collect();
        roundtrip(&mixed);
    }

    #[test]
    fn rejects_bad_frames() {
        let mut wire = [0u8; 64];
        let n = encode(b"hello", &mut wire).unwrap();
        wire[3] ^= 0x40;
        let mut d = Deframer::<64>::new();
        let r: std::vec::Vec<_> = wire[..n]
            .iter()
            .filter_map(|&b| d.push(b).map(|r| r.map(|p| p.len())))
            .collect();
        assert_eq!(r, [Err(FrameError::Crc)]);
        let mut d = Deframer::<4>::new();
        let r: std::vec::Vec<_> = [1, 2, 3, 4, 5, 0]
            .iter()
            .filter_map(|&b| d.push(b).map(|r| r.map(|p| p.len())))
            .collect();
        assert_eq!(r, [Err(FrameError::TooLong)]);
        let mut d = Deframer::<8>::new();
        assert_eq!(d.push(9), None);
        assert_eq!(d.push(0), Some(Err(FrameError::Cobs)));
        assert!(d.push(2).is_none());
        assert!(d.push(1).is_none());
        assert_eq!(d.push(0), Some(Err(FrameError::TooShort)));
        let mut small = [0u8; 4];
        assert_eq!(encode(b"x", &mut small), Err(FrameError::NoRoom));
    }
}
