//! Bridge mode of the real `obu` binary: it reads the firmware's `HmiState` link frames from
//! a TCP server that the test owns (as QEMU's emulated serial port) or from a FIFO (as a
//! serial device), and serves them over SSE and the status endpoint as in the normal mode.
//! The states are the OBU core's own, computed here from the committed MAP and TIM vectors
//! and fixes, then sent as the firmware sends them (postcard, `obu::link` frames).

mod common;

use common::{
    free_udp_port, open_events, read_events, status, status_when, temp_dir, vector, Daemon,
};
use obu::{AlertConfig, Fix, HmiState, Instant as CoreInstant, LatLon, Obu};
use std::io::{BufReader, Write};
use std::net::{TcpListener, TcpStream, UdpSocket};
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

/// The firmware's largest `HmiState` encoding (`obu_firmware::app::HMI_MAX`).
const HMI_MAX: usize = 512;

/// A configuration whose V2X and GNSS inputs would bind `v2x` and `gnss` (UDP) if started.
fn write_config(dir: &Path, v2x: u16, gnss: u16) -> PathBuf {
    let path = dir.join("obu.toml");
    let text = format!(
        "[v2x]\nbind = \"127.0.0.1:{v2x}\"\n[gnss]\nsource = \"nmea-udp\"\naddress = \"127.0.0.1:{gnss}\"\n\
         [http]\nbind = \"127.0.0.1:0\"\nsettings_file = \"{}\"\nheartbeat_ms = 200\nrequest_timeout_ms = 1000\n",
        dir.join("settings.json").display()
    );
    std::fs::write(&path, text).unwrap();
    path
}

/// `count` states of the core: the first after the MAP and TIM, then one per fix driving
/// east from the MAP's reference point area.
fn core_states(count: usize) -> Vec<HmiState> {
    let run = move || {
        let mut core = Box::new(Obu::new(AlertConfig::DEFAULT));
        for name in ["map_work_zone", "tim_work_zone_left_lane_closed"] {
            let mf: j2735::MessageFrame = j2735::uper::decode(&vector(name)).expect("vector");
            core.on_frame(CoreInstant::from_millis(0), &mf)
                .expect("stored");
        }
        let mut states = vec![core.state(CoreInstant::from_millis(10))];
        for i in 1..count {
            let fix = Fix {
                accuracy_m: Some(0.8),
                speed_mps: Some(8.0 + i as f32 * 0.25),
                course_deg: Some(90.0),
                ..Fix::at(LatLon::from_degrees(42.123_456, -83.765_43 + i as f64 * 1e-5).unwrap())
            };
            states.push(core.on_fix(CoreInstant::from_millis(100 * i as u64), fix));
        }
        states
    };
    // Decoding a MessageFrame needs room on the stack.
    std::thread::Builder::new()
        .stack_size(64 << 20)
        .spawn(run)
        .unwrap()
        .join()
        .unwrap()
}

/// The postcard payload of `state`, as the firmware's `send_state` makes it.
fn payload(state: &HmiState) -> Vec<u8> {
    let mut buf = [0u8; HMI_MAX];
    postcard::to_slice(state, &mut buf).expect("fits").to_vec()
}

/// The link frame of `payload`.
fn frame(payload: &[u8]) -> Vec<u8> {
    let mut wire = vec![0u8; obu::link::encoded_len(payload.len())];
    let n = obu::link::encode(payload, &mut wire).unwrap();
    wire.truncate(n);
    wire
}

/// The frame of `state` with one bit flipped in a data octet (not a COBS code octet): only
/// the CRC can tell.
fn bad_crc_frame(state: &HmiState) -> Vec<u8> {
    let mut wire = frame(&payload(state));
    let mut codes = vec![0];
    while let Some(&code) = wire.get(*codes.last().unwrap()).filter(|&&c| c != 0) {
        codes.push(codes.last().unwrap() + usize::from(code));
    }
    let at = (1..wire.len() - 1)
        .find(|i| !codes.contains(i) && wire[*i] >= 2)
        .unwrap();
    wire[at] ^= 1;
    wire
}

/// The states of `n` SSE events, after checking that their ids follow `after`.
fn next_states(events: &mut BufReader<TcpStream>, after: u64, n: usize) -> Vec<HmiState> {
    let got = read_events(events, n);
    let ids: Vec<u64> = got.iter().map(|e| e.0).collect();
    let want: Vec<u64> = (after + 1..=after + n as u64).collect();
    assert_eq!(ids, want, "consecutive event ids");
    got.iter()
        .map(|(id, e)| {
            assert_eq!(e["seq"], *id);
            serde_json::from_value(e["state"].clone()).expect("an HmiState")
        })
        .collect()
}

fn accept_within(listener: &TcpListener, limit: Duration) -> TcpStream {
    listener.set_nonblocking(true).unwrap();
    let deadline = Instant::now() + limit;
    loop {
        match listener.accept() {
            Ok((s, _)) => {
                s.set_nonblocking(false).unwrap();
                return s;
            }
            Err(_) if Instant::now() < deadline => std::thread::sleep(Duration::from_millis(10)),
            Err(e) => panic!("the daemon did not connect: {e}"),
        }
    }
}

#[test]
fn tcp_states_are_served_in_order_bad_frames_counted_and_the_link_reconnects() {
    let states = core_states(5);
    assert_eq!(
        (states[0].maps, states[0].zones),
        (1, 2),
        "MAP and TIM stored"
    );
    assert!(states[4].gnss_ok && states[4].speed_mps == Some(9.0));
    assert!(states.windows(2).all(|w| w[0] != w[1]), "distinct states");

    let dir = temp_dir("bridge-tcp");
    let (v2x_port, gnss_port) = (free_udp_port(), free_udp_port());
    let cfg = write_config(&dir, v2x_port, gnss_port);
    let mut listener = TcpListener::bind("127.0.0.1:0").unwrap();
    let port = listener.local_addr().unwrap().port();
    let source = format!("tcp:127.0.0.1:{port}");
    let d = Daemon::start(["--config", cfg.to_str().unwrap(), "--bridge", &source]);
    assert_eq!(
        d.words,
        [
            "obu:",
            format!("http://{}", d.http).as_str(),
            "bridge",
            source.as_str()
        ],
        "the first line"
    );
    UdpSocket::bind(("127.0.0.1", v2x_port)).expect("no V2X input in bridge mode");
    UdpSocket::bind(("127.0.0.1", gnss_port)).expect("no GNSS input in bridge mode");
    let mut events = open_events(&d.http, None);

    let mut link = accept_within(&listener, Duration::from_secs(5));
    let mut trailing = payload(&states[2]);
    trailing.push(0x55);
    let wire = [
        frame(&payload(&states[0])),
        bad_crc_frame(&states[1]),
        frame(&payload(&states[1])),
        b"not a frame\xff\x00".to_vec(),
        vec![0x42; 2000],
        vec![0],
        frame(&[0xFF; 12]),
        frame(&trailing),
    ]
    .concat();
    link.write_all(&wire).unwrap();
    // The last state in two writes: frames are rebuilt across reads.
    let last = frame(&payload(&states[2]));
    link.write_all(&last[..last.len() / 2]).unwrap();
    link.flush().unwrap();
    std::thread::sleep(Duration::from_millis(50));
    link.write_all(&last[last.len() / 2..]).unwrap();

    assert_eq!(next_states(&mut events, 0, 3), states[..3]);
    let s = status(&d.http);
    assert_eq!(s["mode"], "bridge", "{s}");
    let b = &s["bridge"];
    assert_eq!(b["source"], source.as_str(), "{s}");
    assert_eq!(b["connected"], true, "{s}");
    assert_eq!(
        (&b["connects"], &b["frames"], &b["errors"]),
        (&1.into(), &3.into(), &5.into()),
        "{s}"
    );
    assert_eq!(b["octets"], (wire.len() + last.len()) as u64, "{s}");
    assert!(
        b["last_frame_age_ms"].as_u64().is_some_and(|ms| ms < 5000),
        "{s}"
    );
    let errors = &s["counters"]["bridge_errors"];
    for reason in [
        "CRC mismatch",
        "invalid COBS encoding",
        "frame too long",
        "state has an invalid value",
        "octets after the state",
    ] {
        assert_eq!(errors[reason], 1, "{reason}: {s}");
    }
    assert_eq!(s["counters"]["bridge"]["state"], 3, "{s}");
    assert_eq!(
        (&s["active_maps"], &s["active_zones"]),
        (&1.into(), &2.into()),
        "{s}"
    );
    assert!(s["counters"].get("gnss").is_none(), "{s}");

    // The firmware side goes away in the middle of a frame, and comes back later.
    link.write_all(&last[..5]).unwrap();
    drop(listener);
    drop(link);
    let s = status_when(&d.http, |s| s["bridge"]["connected"] == false);
    assert_eq!(s["bridge"]["connected"], false, "{s}");
    std::thread::sleep(Duration::from_millis(300));
    listener = TcpListener::bind(("127.0.0.1", port)).unwrap();
    let mut link = accept_within(&listener, Duration::from_secs(5));
    link.write_all(&[frame(&payload(&states[3])), frame(&payload(&states[4]))].concat())
        .unwrap();
    assert_eq!(next_states(&mut events, 3, 2), states[3..]);
    let s = status(&d.http);
    let b = &s["bridge"];
    assert_eq!(
        (&b["connected"], &b["connects"]),
        (&true.into(), &2.into()),
        "{s}"
    );
    assert_eq!((&b["frames"], &b["errors"]), (&5.into(), &6.into()), "{s}");
    assert_eq!(
        s["counters"]["bridge_errors"]["frame cut off by disconnect"], 1,
        "{s}"
    );
    let bridge = &s["counters"]["bridge"];
    assert_eq!(
        (&bridge["connected"], &bridge["disconnected"]),
        (&2.into(), &1.into()),
        "{s}"
    );
    assert!(
        bridge["connect failed"].as_u64().is_some_and(|n| n >= 1),
        "refused while away: {s}"
    );
    assert!(d.stop().success(), "SIGTERM is a clean exit");
}

/// A FIFO stands in for the serial device: the daemon opens it for reading, reads until
/// the writer closes it, and opens it again.
#[cfg(unix)]
#[test]
fn serial_states_are_read_from_the_device_and_it_is_reopened() {
    let states = core_states(3);
    let dir = temp_dir("bridge-serial");
    let tty = dir.join("ttyOBU");
    let made = std::process::Command::new("mkfifo").arg(&tty).status();
    assert!(made.is_ok_and(|s| s.success()), "mkfifo");
    let cfg = write_config(&dir, free_udp_port(), free_udp_port());
    let source = format!("serial:{}", tty.display());
    let d = Daemon::start(["--config", cfg.to_str().unwrap(), "--bridge", &source]);
    assert_eq!(d.words[2..], ["bridge", source.as_str()]);
    let mut events = open_events(&d.http, None);
    let send = |states: &[HmiState]| {
        let wire: Vec<u8> = states.iter().flat_map(|s| frame(&payload(s))).collect();
        let tty = tty.clone();
        let (done, wait) = std::sync::mpsc::channel();
        // Opening a FIFO for writing blocks until the daemon opens it for reading.
        std::thread::spawn(move || {
            let mut w = std::fs::OpenOptions::new().write(true).open(tty).unwrap();
            done.send(w.write_all(&wire).is_ok()).unwrap();
        });
        assert_eq!(
            wait.recv_timeout(Duration::from_secs(5)),
            Ok(true),
            "written"
        );
    };
    send(&states[..2]);
    assert_eq!(next_states(&mut events, 0, 2), states[..2]);
    // A writer that opened before the daemon closed its end after the first writer would
    // see its bytes discarded with that end (FIFO semantics, not a tty's): wait for the
    // close, then the next open blocks until the daemon opens again.
    status_when(&d.http, |s| s["counters"]["bridge"]["disconnected"] == 1);
    send(&states[2..]);
    assert_eq!(next_states(&mut events, 2, 1), states[2..]);
    // After the second writer the daemon waits in the open for a third one.
    let s = status_when(&d.http, |s| s["counters"]["bridge"]["disconnected"] == 2);
    let b = &s["bridge"];
    assert_eq!(b["source"], source.as_str(), "{s}");
    assert_eq!((&b["frames"], &b["errors"]), (&3.into(), &0.into()), "{s}");
    assert_eq!(
        (&b["connects"], &b["connected"]),
        (&2.into(), &false.into()),
        "{s}"
    );
    assert_eq!(s["counters"]["bridge"]["disconnected"], 2, "{s}");
    assert!(
        d.stop().success(),
        "SIGTERM is a clean exit while waiting for a writer"
    );
}
