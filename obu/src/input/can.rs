//! Vehicle speed from CAN: a configurable signal (DBC conventions) and `candump -l` log lines.
//!
//! A [`SpeedSignal`] names the frame id, the signal's start bit, length and byte order, and
//! the physical value `raw * scale + offset` in km/h. [`parse_candump_line`] reads one line
//! `(1700000000.123456) can0 1F0#0A1B2C3D4E5F6071`. Panic contract: nothing here panics on any
//! input; a frame too short for the signal is [`CanError::ShortFrame`].

/// Why a frame or log line was refused.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum CanError {
    /// The log line is not `(seconds) interface ID#DATA`.
    BadLine,
    /// The identifier is not 3 (standard) or 8 (extended) hex digits.
    BadId,
    /// The data is not an even number of hex digits, or longer than 64 octets.
    BadData,
    /// The frame is shorter than the signal needs.
    ShortFrame,
    /// A remote-request frame (carries no data).
    Remote,
}

impl CanError {
    /// A short lowercase name, for counters and logs.
    pub const fn as_str(self) -> &'static str {
        match self {
            Self::BadLine => "bad line",
            Self::BadId => "bad id",
            Self::BadData => "bad data",
            Self::ShortFrame => "frame too short for the signal",
            Self::Remote => "remote frame",
        }
    }
}

impl core::fmt::Display for CanError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(self.as_str())
    }
}

/// Bit numbering of a signal.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "snake_case"))]
pub enum ByteOrder {
    /// Intel: the start bit is the least significant bit (`@1` in a DBC file).
    LittleEndian,
    /// Motorola: the start bit is the most significant bit, DBC numbering (`@0`).
    BigEndian,
}

/// Where the vehicle speed is in which frame.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct SpeedSignal {
    /// Frame identifier (11 or 29 bits).
    pub id: u32,
    /// DBC start bit.
    pub start_bit: u16,
    /// Length in bits (1..=64).
    pub length: u8,
    /// Byte order.
    pub byte_order: ByteOrder,
    /// Two's complement signal.
    pub signed: bool,
    /// km/h per raw unit.
    pub scale: f32,
    /// km/h added after scaling.
    pub offset: f32,
}

impl SpeedSignal {
    /// The raw value of the signal in `data`.
    pub fn raw(&self, data: &[u8]) -> Result<i64, CanError> {
        let len = u32::from(self.length.clamp(1, 64));
        let mut value: u64 = 0;
        for k in 0..len {
            // `k` counts from the signal's most significant bit.
            let bit = self.bit_position(k, len).ok_or(CanError::ShortFrame)?;
            let byte = data.get(bit / 8).ok_or(CanError::ShortFrame)?;
            value = (value << 1) | u64::from((byte >> (bit % 8)) & 1);
        }
        if self.signed && len < 64 && value & (1 << (len - 1)) != 0 {
            return Ok(value as i64 - (1i64 << len));
        }
        Ok(value as i64)
    }

    /// The frame bit (byte * 8 + bit in byte, LSB = 0) of the signal's `k`-th bit from its
    /// most significant one.
    fn bit_position(&self, k: u32, len: u32) -> Option<usize> {
        let start = usize::from(self.start_bit);
        match self.byte_order {
            ByteOrder::LittleEndian => start.checked_add((len - 1 - k) as usize),
            ByteOrder::BigEndian => {
                // Walk from the MSB: within a byte towards bit 0, then to bit 7 of the next.
                let mut pos = start;
                for _ in 0..k {
                    pos = if pos % 8 == 0 {
                        pos.checked_add(15)?
                    } else {
                        pos - 1
                    };
                }
                Some(pos)
            }
        }
    }

    /// The speed in m/s carried by frame `data`.
    pub fn speed_mps(&self, data: &[u8]) -> Result<f32, CanError> {
        let kmh = self.raw(data)? as f32 * self.scale + self.offset;
        Ok(kmh / 3.6)
    }
}

/// One frame of a candump log.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct LoggedFrame<'a> {
    /// Time stamp, microseconds since the epoch of the log.
    pub time_us: u64,
    /// Interface name (`can0`).
    pub interface: &'a str,
    /// Frame identifier.
    pub id: u32,
    /// Data octets (up to 64 for CAN FD).
    pub data: heapless::Vec<u8, 64>,
}

/// Parses one `candump -l` line: `(seconds.micros) iface ID#DATA` (`ID##<flags>DATA` for FD).
pub fn parse_candump_line(line: &str) -> Result<LoggedFrame<'_>, CanError> {
    let mut parts = line.split_ascii_whitespace();
    let (stamp, interface, frame) = (
        parts.next().ok_or(CanError::BadLine)?,
        parts.next().ok_or(CanError::BadLine)?,
        parts.next().ok_or(CanError::BadLine)?,
    );
    let stamp = stamp
        .strip_prefix('(')
        .and_then(|s| s.strip_suffix(')'))
        .ok_or(CanError::BadLine)?;
    let time_us = parse_stamp(stamp).ok_or(CanError::BadLine)?;
    let (id, data) = frame.split_once('#').ok_or(CanError::BadLine)?;
    if id.len() != 3 && id.len() != 8 {
        return Err(CanError::BadId);
    }
    let id = u32::from_str_radix(id, 16).map_err(|_| CanError::BadId)?;
    if data.starts_with('R') {
        return Err(CanError::Remote);
    }
    // CAN FD: `##` then one flags digit.
    let data = match data.strip_prefix('#') {
        Some(fd) => fd.get(1..).ok_or(CanError::BadData)?,
        None => data,
    };
    Ok(LoggedFrame {
        time_us,
        interface,
        id,
        data: hex_octets(data)?,
    })
}

fn parse_stamp(s: &str) -> Option<u64> {
    let (secs, frac) = s.split_once('.')?;
    if frac.is_empty() || frac.len() > 9 || !frac.bytes().all(|b| b.is_ascii_digit()) {
        return None;
    }
    let secs: u64 = secs.parse().ok()?;
    let digits = frac.get(..frac.len().min(6))?;
    let micros: u64 = digits.parse().ok()?;
    let scale = 10u64.pow(6 - digits.len() as u32);
    secs.checked_mul(1_000_000)?.checked_add(micros * scale)
}

fn hex_octets(s: &str) -> Result<heapless::Vec<u8, 64>, CanError> {
    if !s.len().is_multiple_of(2) || s.len() > 128 {
        return Err(CanError::BadData);
    }
    let mut out = heapless::Vec::new();
    for i in (0..s.len()).step_by(2) {
        let b = s
            .get(i..i + 2)
            .and_then(|h| u8::from_str_radix(h, 16).ok())
            .ok_or(CanError::BadData)?;
        out.push(b).map_err(|_| CanError::BadData)?;
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn signal(start_bit: u16, length: u8, byte_order: ByteOrder) -> SpeedSignal {
        SpeedSignal {
            id: 0x1f0,
            start_bit,
            length,
            byte_order,
            signed: false,
            scale: 0.01,
            offset: 0.0,
        }
    }

    #[test]
    fn little_endian_signal_across_bytes() {
        // 16-bit Intel signal at bit 8: bytes 1 (low) and 2 (high) = 0x1234 -> 46.60 km/h.
        let s = signal(8, 16, ByteOrder::LittleEndian);
        let data = [0xff, 0x34, 0x12, 0, 0, 0, 0, 0];
        assert_eq!(s.raw(&data), Ok(0x1234));
        assert!((s.speed_mps(&data).unwrap() - 46.60 / 3.6).abs() < 1e-4);
    }

    #[test]
    fn big_endian_signal_dbc_numbering() {
        // Motorola 16-bit signal with start (MSB) bit 7: byte 0 high, byte 1 low.
        let s = signal(7, 16, ByteOrder::BigEndian);
        assert_eq!(s.raw(&[0x12, 0x34, 0, 0]), Ok(0x1234));
        // 12-bit Motorola signal with MSB at bit 3 of byte 0: low nibble of byte 0, byte 1.
        let s = signal(3, 12, ByteOrder::BigEndian);
        assert_eq!(s.raw(&[0xa5, 0x67]), Ok(0x567));
    }

    #[test]
    fn signed_and_short_frames() {
        let mut s = signal(0, 8, ByteOrder::LittleEndian);
        s.signed = true;
        assert_eq!(s.raw(&[0xfe]), Ok(-2));
        let s = signal(56, 16, ByteOrder::LittleEndian);
        assert_eq!(
            s.raw(&[0; 8]),
            Err(CanError::ShortFrame),
            "bits 56..72 need 9 octets"
        );
        assert_eq!(s.raw(&[]), Err(CanError::ShortFrame));
    }

    #[test]
    fn candump_lines() {
        let f = parse_candump_line("(1700000000.123456) can0 1F0#0A1B2C3D4E5F6071").unwrap();
        assert_eq!(f.time_us, 1_700_000_000_123_456);
        assert_eq!((f.interface, f.id), ("can0", 0x1f0));
        assert_eq!(
            &f.data[..],
            &[0x0a, 0x1b, 0x2c, 0x3d, 0x4e, 0x5f, 0x60, 0x71]
        );
        let ext = parse_candump_line("(1.5) vcan1 18FEF100#00").unwrap();
        assert_eq!((ext.id, ext.time_us), (0x18fe_f100, 1_500_000));
        let fd = parse_candump_line("(2.000001) can0 123##1AABB").unwrap();
        assert_eq!(&fd.data[..], &[0xaa, 0xbb]);
        assert_eq!(
            parse_candump_line("(2.0) can0 123#R"),
            Err(CanError::Remote)
        );
        assert_eq!(parse_candump_line("(2.0) can0 12#00"), Err(CanError::BadId));
        assert_eq!(
            parse_candump_line("(2.0) can0 123#0"),
            Err(CanError::BadData)
        );
        assert_eq!(
            parse_candump_line("2.0 can0 123#00"),
            Err(CanError::BadLine)
        );
        assert_eq!(parse_candump_line("garbage"), Err(CanError::BadLine));
    }
}
