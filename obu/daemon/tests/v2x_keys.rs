//! The real `obu` binary under 5,000 crafted V2X datagrams (1609.2 envelopes, RSU text
//! records and UPER frames, each malformed in a different place): the counter keys of
//! `/api/status` come from closed sets, so their number stays what a first small batch
//! covering every kind of fault made it, and every datagram is counted exactly once.

mod common;

use common::craft::{closed_v2x_key, rare_faults, send_all, v2x_counts, Crafter, V2X_GROUPS};
use common::{status, temp_dir, Daemon};
use std::net::UdpSocket;
use std::path::Path;

fn start(dir: &Path) -> Daemon {
    let path = dir.join("obu.toml");
    let text = format!(
        "[v2x]\nbind = \"127.0.0.1:0\"\n[gnss]\nsource = \"nmea-udp\"\naddress = \"127.0.0.1:0\"\n\
         [http]\nbind = \"127.0.0.1:0\"\nsettings_file = \"{}\"\n\
         [security]\nrequire_signed = false\n",
        dir.join("settings.json").display()
    );
    std::fs::write(&path, text).unwrap();
    Daemon::start(["--config".as_ref(), path.as_os_str()])
}

#[test]
fn crafted_datagrams_do_not_grow_the_counter_keys() {
    let dir = temp_dir("v2x-keys");
    let d = start(&dir);
    let udp = UdpSocket::bind("127.0.0.1:0").unwrap();
    let mut c = Crafter::new(0x9E37_79B9_7F4A_7C15);
    let (_, before, _) = v2x_counts(&d.http);
    assert_eq!(before, 0);
    // The first batch: faults written by hand for the rarer reasons, then every fault
    // kind of the generator 30 times, each with its own variation.
    let mut first = rare_faults(&c.map);
    first.extend((0..300).map(|i| c.craft(i % 10)));
    let counted = send_all(&d, &udp, &first, 0);
    let (n_first, _, keys_first) = v2x_counts(&d.http);
    assert!(n_first >= 10, "every kind made a key: {keys_first:?}");
    // 5,000 more, varied differently (the generator has moved on).
    let many: Vec<Vec<u8>> = (0..5000)
        .map(|_| {
            let kind = c.rng.below(10);
            c.craft(kind)
        })
        .collect();
    let counted = send_all(&d, &udp, &many, counted);
    let sent = (first.len() + many.len()) as u64;
    assert_eq!(counted, sent);
    let (n_after, total, keys_after) = v2x_counts(&d.http);
    assert_eq!(total, sent, "every datagram counted once");
    assert_eq!(
        n_after, n_first,
        "no new keys: {keys_first:?} -> {keys_after:?}"
    );
    // Every V2X key is a name of the closed sets.
    for key in &keys_after {
        let (group, reason) = key.split_once('/').unwrap();
        if V2X_GROUPS.contains(&group) {
            assert!(closed_v2x_key(group, reason), "{key}");
        }
    }
    let s = status(&d.http);
    let text = s["counters"].to_string();
    assert!(text.len() < 4096, "a small table: {} B {text}", text.len());
}
