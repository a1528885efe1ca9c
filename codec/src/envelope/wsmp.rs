//! IEEE 1609.3 WAVE Short Messages (WSMP version 3): what DSRC radios and RSUs hand up or
//! forward around a 1609.2 SPDU or a bare `MessageFrame`.
//!
//! ```text
//! N-header   subtype (4 bits) | option indicator (1) | version (3) = 3
//!            [WAVE information element extension: count, then count × (id, length, data)]
//!            TPID (1 octet): 0 PSID, 1 PSID and a T-header extension
//! T-header   PSID (IEEE 1609.12 p-encoded, 1-4 octets)
//!            [WAVE information element extension, for TPID 1]
//!            WSM length
//! WSM data   the length's octets
//! ```
//!
//! Counts and lengths take one octet for 0-127 (`0xxxxxxx`) and two for 128-16383
//! (`10xxxxxx xxxxxxxx`). N-header elements the parser reads: channel number (15), data rate
//! (16), transmit power used (4), channel load (23); others are skipped by their length.
//! Every count and length is bounded by the octets that remain.

use core::fmt;

use super::psid::{p_encoded_len, Psid};

/// WSMP version this parser reads.
pub const VERSION: u8 = 3;
/// WAVE element id: transmit power used (dBm, signed).
const ELEMENT_TX_POWER: u8 = 4;
/// WAVE element id: channel number.
const ELEMENT_CHANNEL: u8 = 15;
/// WAVE element id: data rate (500 kb/s units).
const ELEMENT_DATA_RATE: u8 = 16;
/// WAVE element id: channel load.
const ELEMENT_CHANNEL_LOAD: u8 = 23;

/// The N-header fields a receiver uses (each if the sender gave it).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct WsmpInfo {
    /// Channel number.
    pub channel: Option<u8>,
    /// Data rate, 500 kb/s units.
    pub data_rate: Option<u8>,
    /// Transmit power used, dBm.
    pub tx_power_dbm: Option<i8>,
    /// Channel load.
    pub channel_load: Option<u8>,
}

/// A parsed WAVE Short Message.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Wsm<'a> {
    /// The T-header's PSID.
    pub psid: Psid,
    /// The N-header's fields.
    pub info: WsmpInfo,
    /// The WSM data (a 1609.2 SPDU or a bare `MessageFrame`).
    pub data: &'a [u8],
}

/// Why bytes are not a WAVE Short Message this parser reads: a closed set.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum WsmpError {
    /// Fewer octets than a field or length needs.
    Truncated,
    /// A WSMP version other than 3.
    Version,
    /// A subtype other than null networking (0), or a TPID other than 0 and 1 (ITS port
    /// numbers, LPP mode).
    Unsupported,
    /// A length or count field over two octets (`11xxxxxx`), or a PSID that is no
    /// p-encoding (`1111xxxx`).
    Encoding,
    /// Octets after the WSM data the length announced.
    TrailingBytes,
}

impl WsmpError {
    /// Every error, in [`WsmpError::index`] order: for tables with one entry per error (a
    /// receiver's drop counters, for instance).
    pub const ALL: [WsmpError; 5] = [
        Self::Truncated,
        Self::Version,
        Self::Unsupported,
        Self::Encoding,
        Self::TrailingBytes,
    ];
    /// The number of errors.
    pub const COUNT: usize = Self::ALL.len();

    /// Position in [`WsmpError::ALL`] (the declaration order). An exhaustive match: a new
    /// kind does not compile until it has its place here and in `ALL`.
    pub const fn index(self) -> usize {
        match self {
            Self::Truncated => 0,
            Self::Version => 1,
            Self::Unsupported => 2,
            Self::Encoding => 3,
            Self::TrailingBytes => 4,
        }
    }

    /// The reason in words.
    pub const fn as_str(self) -> &'static str {
        match self {
            Self::Truncated => "WSMP: truncated",
            Self::Version => "WSMP: version not 3",
            Self::Unsupported => "WSMP: subtype or TPID not supported",
            Self::Encoding => "WSMP: bad length or PSID encoding",
            Self::TrailingBytes => "WSMP: bytes after the WSM data",
        }
    }
}

impl fmt::Display for WsmpError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.as_str())
    }
}

#[cfg(feature = "std")]
impl std::error::Error for WsmpError {}

/// Whether `bytes` start like a WSMP version 3 header rather than IEEE 1609.2 data (`03 80`,
/// `03 81`, `03 82`) or a `MessageFrame` (`00 ..`): `0B` (null networking with an N-header
/// extension), or `03` followed by TPID 0 or 1.
#[must_use]
pub fn looks_like_wsmp(bytes: &[u8]) -> bool {
    match bytes {
        [0x0B, ..] => true,
        [0x03, tpid, ..] => *tpid <= 1,
        _ => false,
    }
}

/// A reader over the octets that remain.
struct Reader<'a> {
    rest: &'a [u8],
}

impl<'a> Reader<'a> {
    fn u8(&mut self) -> Result<u8, WsmpError> {
        let (&first, rest) = self.rest.split_first().ok_or(WsmpError::Truncated)?;
        self.rest = rest;
        Ok(first)
    }

    fn take(&mut self, n: usize) -> Result<&'a [u8], WsmpError> {
        if n > self.rest.len() {
            return Err(WsmpError::Truncated);
        }
        let (taken, rest) = self.rest.split_at(n);
        self.rest = rest;
        Ok(taken)
    }

    /// A length or count: one octet `0xxxxxxx`, or two `10xxxxxx xxxxxxxx`.
    fn length(&mut self) -> Result<usize, WsmpError> {
        let first = self.u8()?;
        match first >> 6 {
            0 | 1 => Ok(usize::from(first)),
            2 => Ok(usize::from(u16::from_be_bytes([first & 0x3F, self.u8()?]))),
            _ => Err(WsmpError::Encoding),
        }
    }

    /// A p-encoded PSID.
    fn psid(&mut self) -> Result<Psid, WsmpError> {
        let first = *self.rest.first().ok_or(WsmpError::Truncated)?;
        let len = p_encoded_len(first).ok_or(WsmpError::Encoding)?;
        let octets = self.take(len)?;
        Psid::from_p_encoded(octets).ok_or(WsmpError::Encoding)
    }

    /// A WAVE information element extension; each element goes to `element`.
    fn elements(&mut self, mut element: impl FnMut(u8, &[u8])) -> Result<(), WsmpError> {
        let count = self.length()?;
        for _ in 0..count {
            let id = self.u8()?;
            let len = self.length()?;
            element(id, self.take(len)?);
        }
        Ok(())
    }
}

impl<'a> Wsm<'a> {
    /// Reads one WAVE Short Message that fills `bytes` exactly.
    ///
    /// # Errors
    ///
    /// A [`WsmpError`] naming what is wrong.
    pub fn parse(bytes: &'a [u8]) -> Result<Self, WsmpError> {
        let mut r = Reader { rest: bytes };
        let first = r.u8()?;
        if first & 0x07 != VERSION {
            return Err(WsmpError::Version);
        }
        if first >> 4 != 0 {
            return Err(WsmpError::Unsupported);
        }
        let mut info = WsmpInfo::default();
        if first & 0x08 != 0 {
            r.elements(|id, data| match (id, data) {
                (ELEMENT_CHANNEL, [c]) => info.channel = Some(*c),
                (ELEMENT_DATA_RATE, [d]) => info.data_rate = Some(*d),
                (ELEMENT_TX_POWER, [p]) => info.tx_power_dbm = Some(i8::from_be_bytes([*p])),
                (ELEMENT_CHANNEL_LOAD, [l]) => info.channel_load = Some(*l),
                _ => {}
            })?;
        }
        let tpid = r.u8()?;
        if tpid > 1 {
            return Err(WsmpError::Unsupported);
        }
        let psid = r.psid()?;
        if tpid == 1 {
            r.elements(|_, _| {})?;
        }
        let len = r.length()?;
        let data = r.take(len)?;
        if !r.rest.is_empty() {
            return Err(WsmpError::TrailingBytes);
        }
        Ok(Self { psid, info, data })
    }
}

/// Writes a WSMP version 3 message around `data` into `out` (null networking; an N-header
/// extension with the channel, data rate and transmit power given in `info`; TPID 0) and
/// returns its length; `None` when `out` is too small, `data` is over 16383 octets or `psid`
/// has no p-encoding.
#[must_use]
pub fn encode(psid: Psid, info: &WsmpInfo, data: &[u8], out: &mut [u8]) -> Option<usize> {
    let mut header = [0u8; 1 + 1 + 3 * 4 + 1 + 4 + 2];
    let mut n = 0;
    let mut put = |b: u8| {
        let slot = header.get_mut(n)?;
        *slot = b;
        n = n.checked_add(1)?;
        Some(())
    };
    let elements = [
        (ELEMENT_CHANNEL, info.channel),
        (ELEMENT_DATA_RATE, info.data_rate),
        (
            ELEMENT_TX_POWER,
            info.tx_power_dbm.map(|p| p.to_be_bytes()[0]),
        ),
        (ELEMENT_CHANNEL_LOAD, info.channel_load),
    ];
    let count = elements.iter().filter(|(_, v)| v.is_some()).count() as u8;
    put(if count > 0 { 0x08 | VERSION } else { VERSION })?;
    if count > 0 {
        put(count)?;
        for (id, value) in elements {
            if let Some(v) = value {
                put(id)?;
                put(1)?;
                put(v)?;
            }
        }
    }
    put(0)?; // TPID: PSID, no T-header extension
    let (octets, len) = psid.p_encoded()?;
    for &b in octets.get(..len)? {
        put(b)?;
    }
    let [high, low] = u16::try_from(data.len()).ok()?.to_be_bytes();
    match data.len() {
        0..=127 => put(low)?,
        128..=16383 => {
            put(0x80 | high)?;
            put(low)?;
        }
        _ => return None,
    }
    let total = n.checked_add(data.len())?;
    let dest = out.get_mut(..total)?;
    let (head, body) = dest.split_at_mut(n);
    head.copy_from_slice(header.get(..n)?);
    body.copy_from_slice(data);
    Some(total)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A bare WSM laid out by hand from IEEE 1609.3's figures: N-header 0x03 (null
    /// networking, no extension, version 3), TPID 0, PSID 0x80 0x03 (TIM), length 3, data.
    const BARE: [u8; 8] = [0x03, 0x00, 0x80, 0x03, 0x03, 0x00, 0x1F, 0x01];

    /// With an N-header extension: 0x0B, count 3, channel 172, data rate 12 (6 Mb/s),
    /// transmit power 20 dBm; TPID 0; PSID 0xE0 00 00 17 (MAP); length 2.
    const EXTENDED: [u8; 20] = [
        0x0B, 0x03, 0x0F, 0x01, 0xAC, 0x10, 0x01, 0x0C, 0x04, 0x01, 0x14, 0x00, 0xE0, 0x00, 0x00,
        0x17, 0x02, 0x00, 0x12, 0x00,
    ];

    #[test]
    fn every_error_is_listed_once_at_its_index() {
        for (i, e) in WsmpError::ALL.iter().enumerate() {
            assert_eq!(e.index(), i);
            let named = WsmpError::ALL.iter().filter(|o| o.as_str() == e.as_str());
            assert_eq!(named.count(), 1, "{e}");
        }
    }

    #[test]
    fn a_bare_wsm_gives_its_psid_and_data() {
        assert!(looks_like_wsmp(&BARE));
        assert_eq!(Wsm::parse(&BARE[..7]), Err(WsmpError::Truncated));
        let wsm = Wsm::parse(&BARE).unwrap();
        assert_eq!(wsm.psid, Psid::TIM);
        assert_eq!(wsm.data, &[0x00, 0x1F, 0x01]);
        assert_eq!(wsm.info, WsmpInfo::default());
    }

    #[test]
    fn n_header_elements_are_read() {
        assert!(looks_like_wsmp(&EXTENDED));
        let wsm = Wsm::parse(&EXTENDED[..19]).unwrap();
        assert_eq!(wsm.psid, Psid::MAP);
        assert_eq!(wsm.data, &[0x00, 0x12]);
        assert_eq!(wsm.info.channel, Some(172));
        assert_eq!(wsm.info.data_rate, Some(12));
        assert_eq!(wsm.info.tx_power_dbm, Some(20));
        assert_eq!(Wsm::parse(&EXTENDED), Err(WsmpError::TrailingBytes));
    }

    #[test]
    fn the_writer_makes_the_standard_layout() {
        let mut out = [0u8; 64];
        let info = WsmpInfo {
            channel: Some(172),
            data_rate: Some(12),
            tx_power_dbm: Some(20),
            channel_load: None,
        };
        let n = encode(Psid::MAP, &info, &[0x00, 0x12], &mut out).unwrap();
        assert_eq!(&out[..n], &EXTENDED[..19]);
        let n = encode(
            Psid::TIM,
            &WsmpInfo::default(),
            &[0x00, 0x1F, 0x01],
            &mut out,
        )
        .unwrap();
        assert_eq!(&out[..n], &BARE);
        let long = [0u8; 300];
        let n = encode(Psid::TIM, &WsmpInfo::default(), &long, &mut [0u8; 400]).unwrap();
        assert_eq!(n, 1 + 1 + 2 + 2 + 300);
        assert_eq!(
            encode(Psid::TIM, &WsmpInfo::default(), &long, &mut [0u8; 100]),
            None
        );
    }

    #[test]
    fn bad_headers_are_named() {
        assert_eq!(Wsm::parse(&[0x02, 0x00]), Err(WsmpError::Version));
        assert_eq!(Wsm::parse(&[0x13, 0x00]), Err(WsmpError::Unsupported));
        assert_eq!(
            Wsm::parse(&[0x03, 0x02, 0x20, 0x00]),
            Err(WsmpError::Unsupported)
        );
        assert_eq!(
            Wsm::parse(&[0x03, 0x00, 0xF0, 0x00]),
            Err(WsmpError::Encoding)
        );
        assert_eq!(
            Wsm::parse(&[0x03, 0x00, 0x20, 0xC0]),
            Err(WsmpError::Encoding)
        );
        assert_eq!(
            Wsm::parse(&[0x03, 0x00, 0x20, 0x81, 0x00]),
            Err(WsmpError::Truncated)
        );
        // An extension count larger than the octets that remain.
        assert_eq!(
            Wsm::parse(&[0x0B, 0xBF, 0xFF, 0x0F]),
            Err(WsmpError::Truncated)
        );
        assert_eq!(Wsm::parse(&[]), Err(WsmpError::Truncated));
        // IEEE 1609.2 data and MessageFrames are not taken for WSMs.
        assert!(!looks_like_wsmp(&[0x03, 0x81, 0x00]));
        assert!(!looks_like_wsmp(&[0x03, 0x80, 0x05]));
        assert!(!looks_like_wsmp(&[0x00, 0x1F]));
    }

    #[test]
    fn every_prefix_and_bit_flip_is_an_error_or_a_wsm_never_a_panic() {
        for source in [&BARE[..], &EXTENDED[..19]] {
            for len in 0..source.len() {
                assert!(Wsm::parse(&source[..len]).is_err());
            }
            for i in 0..source.len() {
                for bit in 0..8 {
                    let mut b = [0u8; 32];
                    b[..source.len()].copy_from_slice(source);
                    b[i] ^= 1 << bit;
                    let _ = Wsm::parse(&b[..source.len()]);
                }
            }
        }
    }
}
