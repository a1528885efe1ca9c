//! V2X input: UDP datagrams holding a UPER MessageFrame, bare, in an IEEE 1609.2 envelope,
//! or as an RSU 4.1 text record. Each goes whole to the core's one receive path
//! ([`obu::Obu::on_datagram`], through [`Hub::on_datagram`]); its outcome is counted.

use crate::hub::Hub;
use obu::v2x::{DatagramReason, DropReason, V2xOutcome};
use std::sync::Arc;
use tokio::net::UdpSocket;
use tokio::sync::watch;

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
                    let receive = DropReason::Datagram(DatagramReason::Receive);
                    hub.counters.v2x(V2xOutcome::Dropped(receive));
                    continue;
                }
            },
            _ = shutdown.changed() => return,
        };
        if n > max_datagram {
            hub.counters.v2x(V2xOutcome::Dropped(DropReason::Datagram(
                DatagramReason::TooLarge,
            )));
            continue;
        }
        let outcome = hub.on_datagram(&buf[..n]);
        hub.counters.v2x(outcome);
    }
}
