//! V2X input: UDP datagrams holding a UPER MessageFrame, bare, in an IEEE 1609.2 envelope,
//! or as an RSU 4.1 text record. MAP and TIM go to the core; other messages are counted.

use crate::counters::group;
use crate::hub::Hub;
use j2735::envelope::rsu_text::RsuMessage;
use j2735::envelope::unwrap_message_frame;
use j2735::uper;
use j2735::MessageFrame;
use std::sync::Arc;
use tokio::net::UdpSocket;
use tokio::sync::watch;

/// The short name of a J2735 message id, for counters.
pub fn message_name(id: u16) -> &'static str {
    match id {
        18 => "MAP",
        19 => "SPaT",
        20 => "BSM",
        21 => "CSR",
        22 => "EVA",
        23 => "ICA",
        24 => "NMEA",
        25 => "PDM",
        26 => "PVD",
        27 => "RSA",
        28 => "RTCM",
        29 => "SRM",
        30 => "SSM",
        31 => "TIM",
        32 => "PSM",
        240..=255 => "TestMessage",
        _ => "unknown",
    }
}

/// Receives datagrams until `shutdown` turns true.
pub async fn run(
    socket: UdpSocket,
    hub: Arc<Hub>,
    max_datagram: usize,
    mut shutdown: watch::Receiver<bool>,
) {
    let mut buf = vec![0u8; max_datagram + 1];
    loop {
        let n = tokio::select! {
            r = socket.recv_from(&mut buf) => match r {
                Ok((n, _)) => n,
                Err(_) => {
                    hub.counters.add(group::V2X_DROPPED, "receive error");
                    continue;
                }
            },
            _ = shutdown.changed() => return,
        };
        if n > max_datagram {
            hub.counters.add(group::V2X_DROPPED, "datagram too large");
            continue;
        }
        handle_datagram(&hub, &buf[..n]);
    }
}

/// Unwraps, decodes and dispatches one datagram; every failure is counted with its reason.
pub fn handle_datagram(hub: &Hub, datagram: &[u8]) {
    let frame = match frame_bytes(datagram) {
        Ok(f) => f,
        Err(reason) => {
            hub.counters.add(group::ENVELOPE_ERRORS, &reason);
            return;
        }
    };
    let mf: MessageFrame = match uper::decode(&frame) {
        Ok(mf) => mf,
        Err(e) => {
            hub.counters.add(group::DECODE_ERRORS, e.kind.as_str());
            return;
        }
    };
    let name = message_name(mf.value.id().get());
    hub.counters.add(group::MESSAGES, name);
    if let Err(reason) = crate::ingest::frame(hub, &mf) {
        hub.counters.add(group::INGEST_ERRORS, &reason);
    }
}

/// The MessageFrame octets inside a datagram.
fn frame_bytes(datagram: &[u8]) -> Result<Vec<u8>, String> {
    if datagram.starts_with(b"Version=") {
        let text = std::str::from_utf8(datagram).map_err(|_| "RSU text: not UTF-8".to_string())?;
        let msg = RsuMessage::parse(text).map_err(|e| format!("RSU text: {e}"))?;
        let len = msg
            .payload
            .decoded_len()
            .map_err(|e| format!("RSU text payload: {e}"))?;
        let mut out = vec![0u8; len];
        let n = msg
            .payload
            .decode_into(&mut out)
            .map_err(|e| format!("RSU text payload: {e}"))?;
        out.truncate(n);
        return Ok(out);
    }
    let unwrapped = unwrap_message_frame(datagram).map_err(|e| format!("1609.2: {e}"))?;
    Ok(unwrapped.frame.to_vec())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_of_the_work_zone_messages() {
        assert_eq!(message_name(18), "MAP");
        assert_eq!(message_name(31), "TIM");
        assert_eq!(message_name(33), "unknown");
    }

    #[test]
    fn rsu_text_and_envelopes_give_the_frame() {
        let frame = [0x00, 0x14, 0x01, 0x00];
        let text = "Version=0.7\nType=BSM\nPSID=0x20\nPayload=00140100\n";
        assert_eq!(frame_bytes(text.as_bytes()).unwrap(), frame);
        let mut wrapped = vec![0u8; 16];
        let n = j2735::envelope::ieee1609dot2::encode_unsecured(&frame, &mut wrapped).unwrap();
        assert_eq!(frame_bytes(&wrapped[..n]).unwrap(), frame);
        assert_eq!(
            frame_bytes(&frame).unwrap(),
            frame,
            "a bare frame passes through"
        );
        assert!(frame_bytes(b"Version=0.7\nType=MAP\n")
            .unwrap_err()
            .starts_with("RSU text"));
    }
}
