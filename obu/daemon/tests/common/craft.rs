//! Crafted V2X datagrams (1609.2 envelopes, RSU text records, UPER frames, random octets
//! and huge lengths, each malformed in a different place) and the counters they must land
//! in: every datagram in exactly one of the V2X groups, under a key of a closed set.

use super::{status, Daemon};
use obu::v2x::DropReason;
use std::net::UdpSocket;
use std::time::{Duration, Instant};

/// The groups every V2X datagram is counted in, exactly one of them.
pub const V2X_GROUPS: [&str; 7] = [
    "messages",
    "repeats",
    "v2x_dropped",
    "envelope_errors",
    "decode_errors",
    "ingest_errors",
    "security_errors",
];
/// The daemon's default `v2x.max_datagram`.
pub const MAX_DATAGRAM: usize = 4096;
/// The fault kinds of [`Crafter::craft`].
pub const KINDS: usize = 12;

/// Whether `group`/`reason`, a key of a V2X group, is a name of the closed sets (the
/// codec's message short names, `unknown`, the core's drop reasons).
pub fn closed_v2x_key(group: &str, reason: &str) -> bool {
    if group == "messages" || group == "repeats" {
        let named = j2735::msg::message_frame::MESSAGE_NAMES
            .iter()
            .any(|m| m.short == reason);
        named || reason == "unknown"
    } else {
        V2X_GROUPS.contains(&group) && DropReason::ALL.iter().any(|r| r.as_str() == reason)
    }
}

/// xorshift64: the same datagrams on every run.
pub struct Rng(pub u64);

impl Rng {
    pub fn next(&mut self) -> u64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        self.0
    }
    pub fn below(&mut self, n: usize) -> usize {
        (self.next() % n as u64) as usize
    }
    pub fn bytes(&mut self, n: usize) -> Vec<u8> {
        (0..n).map(|_| self.next() as u8).collect()
    }
}

pub fn hex(bytes: &[u8]) -> String {
    format!("{:X}", j2735::hex::Hex(bytes))
}

/// A COER length prefix (short or long form) of `n`.
pub fn coer_len(n: usize) -> Vec<u8> {
    match n {
        0..=127 => vec![n as u8],
        128..=255 => vec![0x81, n as u8],
        _ => vec![0x82, (n >> 8) as u8, n as u8],
    }
}

/// Builds the datagrams: the same generator for the first batch and the large one.
pub struct Crafter {
    /// The generator (its state moves with every datagram made).
    pub rng: Rng,
    /// A valid MAP.
    pub map: Vec<u8>,
    /// A valid TIM.
    pub tim: Vec<u8>,
    /// A MAP the core refuses part of.
    pub addgrpb: Vec<u8>,
}

impl Crafter {
    /// A generator seeded with `seed`, around the codec's committed MAP and TIM vectors.
    pub fn new(seed: u64) -> Self {
        Self {
            rng: Rng(seed),
            map: super::vector("map_work_zone"),
            tim: super::vector("tim_work_zone_left_lane_closed"),
            addgrpb: super::vector("map_regional_addgrpb"),
        }
    }

    fn frame(&mut self) -> Vec<u8> {
        if self.rng.below(2) == 0 {
            self.map.clone()
        } else {
            self.tim.clone()
        }
    }

    /// One malformed datagram of fault kind `kind` (0..[`KINDS`]), varied by the
    /// generator.
    pub fn craft(&mut self, kind: usize) -> Vec<u8> {
        let r = &mut self.rng;
        match kind {
            // A 1609.2 envelope whose length claims more than follows, cut anywhere.
            0 => {
                let frame = self.frame();
                let mut d = vec![0x03, 0x80];
                d.extend(coer_len(frame.len() + 1 + self.rng.below(500)));
                d.extend_from_slice(&frame[..self.rng.below(frame.len())]);
                d
            }
            // A 1609.2 header with random content: tags, lengths, garbage.
            1 => {
                let n = r.below(300);
                let mut d = vec![0x03, 0x80 + r.below(4) as u8];
                d.extend(r.bytes(n));
                d
            }
            // An envelope with octets after the frame.
            2 => {
                let frame = self.frame();
                let mut d = vec![0x03, 0x80];
                d.extend(coer_len(frame.len()));
                d.extend_from_slice(&frame);
                let n = 1 + self.rng.below(40);
                d.extend(self.rng.bytes(n));
                d
            }
            // A bare MAP or TIM truncated at a varying octet.
            3 => {
                let frame = self.frame();
                let cut = 2 + self.rng.below(frame.len() - 2);
                frame[..cut].to_vec()
            }
            // A bare MAP or TIM with trailing octets.
            4 => {
                let mut frame = self.frame();
                let n = 1 + self.rng.below(64);
                frame.extend(self.rng.bytes(n));
                frame
            }
            // The MAP or TIM message id followed by garbage.
            5 => {
                let id = if r.below(2) == 0 { 0x12 } else { 0x1f };
                let n = r.below(200);
                let mut d = vec![0x00, id];
                d.extend(r.bytes(n));
                d
            }
            // An RSU text record with one bad line at a varying place.
            6 => self.bad_rsu_text(),
            // An RSU text record whose payload is a truncated frame.
            7 => {
                let frame = self.frame();
                let cut = 2 + self.rng.below(frame.len() - 2);
                format!(
                    "Version=0.7\nType=MAP\nPSID=0x8002\nPayload={}\n",
                    hex(&frame[..cut])
                )
                .into_bytes()
            }
            // Too large, of a varying size.
            8 => {
                let n = MAX_DATAGRAM + 1 + r.below(3000);
                r.bytes(n)
            }
            // Random octets.
            10 => {
                let n = 1 + r.below(1500);
                r.bytes(n)
            }
            // Huge lengths: a 1609.2 length of up to 2^32 - 1 octets, or a UPER open type
            // claiming 16K fragments, over a few octets.
            11 => {
                let n = r.below(40);
                let mut d = if r.below(2) == 0 {
                    vec![0x03, 0x80, 0x84, 0xff, 0xff, 0xff, 0xff - r.below(16) as u8]
                } else {
                    vec![0x00, 0x1f, 0xc1 + r.below(4) as u8]
                };
                d.extend(r.bytes(n));
                d
            }
            // A MAP the core refuses part of (AddGrpB nodes), in an envelope or not.
            _ => {
                if self.rng.below(2) == 0 {
                    self.addgrpb.clone()
                } else {
                    let mut d = vec![0x03, 0x80];
                    d.extend(coer_len(self.addgrpb.len()));
                    d.extend_from_slice(&self.addgrpb);
                    d
                }
            }
        }
    }

    fn bad_rsu_text(&mut self) -> Vec<u8> {
        let r = &mut self.rng;
        let n = 1 + r.below(60);
        let payload = r.bytes(n);
        let mut lines = vec![
            "Version=0.7".to_string(),
            "Type=TIM".to_string(),
            format!("PSID=0x{:X}", 0x8000 + r.below(4096)),
            format!("Payload={}", hex(&payload)),
        ];
        let at = 1 + r.below(lines.len() - 1);
        match r.below(5) {
            0 => drop(lines.remove(at)),
            1 => lines.insert(at, lines[at].clone()),
            2 => lines.insert(at, format!("garbage line {}", r.next())),
            3 => lines[3].push_str(&"G".repeat(1 + r.below(9))),
            _ => lines[2] = format!("PSID=zz{}", r.next()),
        }
        let mut text = lines.join("\n").into_bytes();
        if r.below(10) == 0 {
            text.push(0xff); // not UTF-8
        }
        text
    }
}

/// Faults that the generator reaches rarely, written by hand (layouts from the standards).
pub fn rare_faults(map: &[u8]) -> Vec<Vec<u8>> {
    // The MAP's MessageFrame: 00 12, a one-octet open-type length, the MapData.
    assert_eq!(
        (map[0], map[1], usize::from(map[2])),
        (0x00, 0x12, map.len() - 3)
    );
    let mut loose = map.to_vec();
    loose[2] += 1;
    loose.push(0x00);
    vec![
        // A long-form COER length for 4 octets: not canonical.
        vec![0x03, 0x80, 0x81, 0x04, 0x00, 0x1f, 0x01, 0x02],
        // Signed data (03 81, SHA-256 00, data present 40) whose inner data's content tag
        // (00) is not of the context-specific class.
        vec![
            0x03, 0x81, 0x00, 0x40, 0x03, 0x00, 0x04, 0x00, 0x1f, 0x01, 0x02,
        ],
        // The MapData's open type one octet longer than the MapData.
        loose,
        // messageId 64: assigned to no message.
        vec![0x00, 0x40, 0x01, 0x00],
        // IEEE 1609.3 WSMs (N-header 03: version 3, no extension; 0B: with one): cut short;
        // a PSID that is no p-encoding; octets after the WSM data; TPID 2 (ITS ports).
        vec![0x03, 0x00, 0x80],
        vec![0x03, 0x00, 0xF0, 0x00],
        vec![0x03, 0x00, 0x20, 0x01, 0x00, 0x00],
        vec![0x0B, 0x00, 0x02, 0x20, 0x00],
        // The MAP in a WSM with BSM's PSID (0x20).
        wsm(0x20, map),
    ]
}

/// `data` in a WSM (N-header 03, TPID 0, the one-octet `psid`, a two-octet length).
fn wsm(psid: u8, data: &[u8]) -> Vec<u8> {
    let len = u16::try_from(data.len()).expect("a short frame");
    assert!(len < 0x4000);
    let [hi, lo] = len.to_be_bytes();
    let mut out = vec![0x03, 0x00, psid, 0x80 | hi, lo];
    out.extend_from_slice(data);
    out
}

/// The V2X counters: the number of keys in every group, and the datagrams counted.
pub fn v2x_counts(http: &str) -> (usize, u64, Vec<String>) {
    let s = status(http);
    let groups = s["counters"].as_object().cloned().unwrap_or_default();
    let mut keys = Vec::new();
    let mut total = 0;
    for (g, reasons) in &groups {
        for (k, n) in reasons.as_object().unwrap() {
            keys.push(format!("{g}/{k}"));
            if V2X_GROUPS.contains(&g.as_str()) {
                total += n.as_u64().unwrap();
            }
        }
    }
    (keys.len(), total, keys)
}

/// Sends `datagrams` in bursts small enough for the loopback buffer, waiting after each
/// until the daemon has counted it (so that none is lost to a full socket buffer).
pub fn send_all(d: &Daemon, udp: &UdpSocket, datagrams: &[Vec<u8>], mut counted: u64) -> u64 {
    for burst in datagrams.chunks(50) {
        for g in burst {
            udp.send_to(g, d.v2x()).unwrap();
        }
        let want = counted + burst.len() as u64;
        let deadline = Instant::now() + Duration::from_secs(20);
        loop {
            let (_, total, _) = v2x_counts(&d.http);
            assert!(total <= want, "more counted than sent: {total} > {want}");
            if total == want {
                break;
            }
            assert!(Instant::now() < deadline, "only {total} of {want} counted");
            std::thread::sleep(Duration::from_millis(5));
        }
        counted = want;
    }
    counted
}
