//! The broadcaster (`roadside::broadcast`) against local UDP sockets: frames arrive bare or
//! in IEEE 1609.2, the rate holds, the seeded faults drop/corrupt/hold what they say, and
//! the RSU 4.1 records read back with the codec's parser.

use geodesy::LatLon;
use j2735::envelope::rsu_text::RsuMessage;
use j2735::envelope::{unwrap_message_frame, EnvelopeKind, Psid};
use roadside::broadcast::{
    rsu_record, write_rsu_files, Broadcaster, DropReason, FaultInjector, Faults, LossModel,
    Message, MessageKind, RsuDelivery, RsuFileError, RsuOptions, TxChannel, TxMode, Verdict,
    Wrapping,
};
use roadside::clock::Utc;
use roadside::messages::{self, SignSpeed, WorkZone, DURATION_INDEFINITE};
use roadside::road::Road;
use std::net::{SocketAddr, UdpSocket};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

/// 2026-11-22T10:00:00Z.
const NOW_MS: u64 = 1_795_341_600_000;

/// The MAP and TIM of a two-lane road with the right lane closed, as bare frames.
fn map_and_tim() -> (Message, Message) {
    let reference = LatLon::from_degrees(39.75, -104.995).unwrap();
    let road = Road::straight(reference, 90.0, 600.0, (2, 0), 3.6, 72.0);
    let zone = WorkZone {
        closed_lanes: vec![2],
        start_m: 150.0,
        end_m: 400.0,
        speed_limit: Some(SignSpeed {
            value: 40,
            mph: false,
        }),
        packet_id: [1, 2, 3, 4, 5, 6, 7, 8, 9],
        msg_cnt: 1,
        start: Utc::from_unix_ms(NOW_MS),
        duration_min: DURATION_INDEFINITE,
    };
    let map = messages::encode(&messages::build_map(&road, 1501, 1, Some(&zone)).unwrap()).unwrap();
    let tim = messages::encode(&messages::build_tim(&road, &zone).unwrap()).unwrap();
    (Message::new(map).unwrap(), Message::new(tim).unwrap())
}

/// A receiving socket on loopback with a read timeout.
fn receiver() -> (UdpSocket, SocketAddr) {
    let socket = UdpSocket::bind("127.0.0.1:0").unwrap();
    socket
        .set_read_timeout(Some(Duration::from_millis(500)))
        .unwrap();
    let addr = socket.local_addr().unwrap();
    (socket, addr)
}

/// Every datagram waiting on `socket` (until a read times out).
fn drain(socket: &UdpSocket) -> Vec<Vec<u8>> {
    let mut out = Vec::new();
    let mut buf = [0u8; 65_536];
    while let Ok(n) = socket.recv(&mut buf) {
        out.push(buf[..n].to_vec());
    }
    out
}

#[test]
fn raw_frames_reach_both_destinations() {
    let (map, tim) = map_and_tim();
    let (a, a_addr) = receiver();
    let (b, b_addr) = receiver();
    let mut tx = Broadcaster::new(vec![a_addr, b_addr], Wrapping::Raw).unwrap();
    tx.set_messages(vec![map.clone(), tim.clone()]);
    let n = 5;
    for _ in 0..n {
        tx.tick();
    }
    for socket in [&a, &b] {
        let got = drain(socket);
        assert_eq!(got.len(), 2 * n);
        for pair in got.chunks(2) {
            assert_eq!(pair[0], map.frame());
            assert_eq!(pair[1], tim.frame());
        }
    }
    let stats = tx.stats();
    assert_eq!(
        (stats.ticks, stats.sent, stats.send_errors),
        (n as u64, 4 * n as u64, 0)
    );
    assert_eq!((stats.dropped, stats.corrupted, stats.tim_held), (0, 0, 0));
}

#[test]
fn ieee1609_frames_unwrap_to_the_same_frames() {
    let (map, tim) = map_and_tim();
    let (a, a_addr) = receiver();
    let (b, b_addr) = receiver();
    let mut tx = Broadcaster::new(vec![a_addr, b_addr], Wrapping::Ieee1609Unsecured).unwrap();
    tx.set_messages(vec![map.clone(), tim.clone()]);
    for _ in 0..3 {
        tx.tick();
    }
    for socket in [&a, &b] {
        let got = drain(socket);
        assert_eq!(got.len(), 6);
        for (k, datagram) in got.iter().enumerate() {
            assert_eq!(&datagram[..2], &[0x03, 0x80]);
            let inner = unwrap_message_frame(datagram).expect("a well-formed envelope");
            assert_eq!(inner.envelope, EnvelopeKind::Unsecured);
            let expected = if k % 2 == 0 { &map } else { &tim };
            assert_eq!(inner.frame, expected.frame());
        }
    }
}

#[test]
fn messages_can_be_replaced_while_running() {
    let (map, tim) = map_and_tim();
    let (a, a_addr) = receiver();
    let mut tx = Broadcaster::new(vec![a_addr], Wrapping::Raw).unwrap();
    tx.set_rate_hz(100.0).unwrap();
    tx.set_messages(vec![map.clone()]);
    let slot = tx.message_slot();
    let stop = Arc::new(AtomicBool::new(false));
    let runner = {
        let stop = Arc::clone(&stop);
        std::thread::spawn(move || {
            let ticks = tx.run_until(&stop);
            (tx, ticks)
        })
    };
    std::thread::sleep(Duration::from_millis(100));
    slot.set(vec![tim.clone()]);
    std::thread::sleep(Duration::from_millis(100));
    stop.store(true, Ordering::Release);
    let (tx, ticks) = runner.join().unwrap();
    assert!(ticks >= 5, "{ticks}");
    let got = drain(&a);
    assert_eq!(got.len() as u64, tx.stats().sent);
    assert_eq!(got.first().map(Vec::as_slice), Some(map.frame()));
    assert_eq!(got.last().map(Vec::as_slice), Some(tim.frame()));
    // Once replaced, only TIMs follow.
    let first_tim = got.iter().position(|d| d == tim.frame()).unwrap();
    assert!(got[first_tim..].iter().all(|d| d == tim.frame()));
}

#[test]
fn run_for_keeps_the_rate() {
    let (map, _) = map_and_tim();
    let (_a, a_addr) = receiver();
    let mut tx = Broadcaster::new(vec![a_addr], Wrapping::Raw).unwrap();
    tx.set_messages(vec![map]);
    assert_eq!(tx.rate_hz(), 10.0);
    tx.set_rate_hz(50.0).unwrap();
    let start = Instant::now();
    let ticks = tx.run_for(Duration::from_millis(300));
    let elapsed = start.elapsed();
    // Ticks at 0, 20, ..., 280 ms: 15, unless a busy machine made the loop skip some.
    assert_eq!(ticks + tx.stats().missed_ticks, 15);
    assert!(ticks >= 10, "{ticks}");
    assert!(elapsed >= Duration::from_millis(300), "{elapsed:?}");
    assert!(tx.set_rate_hz(0.0).is_err() && tx.set_rate_hz(f64::NAN).is_err());
}

#[test]
fn independent_loss_drops_the_configured_fraction() {
    let (map, _) = map_and_tim();
    let (_a, a_addr) = receiver();
    let run = |seed| {
        let mut tx = Broadcaster::new(vec![a_addr], Wrapping::Raw).unwrap();
        tx.set_messages(vec![map.clone()]);
        tx.set_faults(Faults {
            loss: LossModel::independent(0.3).unwrap(),
            seed,
            ..Faults::default()
        })
        .unwrap();
        let now = Instant::now();
        for _ in 0..4000 {
            tx.tick_at(now);
        }
        tx.stats()
    };
    let stats = run(7);
    assert_eq!(stats.dropped + stats.sent + stats.send_errors, 4000);
    let rate = stats.dropped as f64 / 4000.0;
    assert!((rate - 0.3).abs() < 0.03, "{rate}");
    // The same seed drops the same datagrams; another seed others.
    assert_eq!(run(7).dropped, stats.dropped);
    assert_ne!(run(8).dropped, stats.dropped);
}

#[test]
fn burst_loss_has_the_rate_and_burst_length_per_destination() {
    let model = LossModel::bursts(0.1, 5.0).unwrap();
    let mut faults = FaultInjector::new(Faults {
        loss: model,
        seed: 3,
        ..Faults::default()
    })
    .unwrap();
    let now = Instant::now();
    let mut datagram = [0u8; 4];
    for destination in 0..2 {
        let (mut lost, mut bursts, mut prev) = (0u32, 0u32, false);
        let n = 100_000;
        for _ in 0..n {
            let l = faults.decide(destination, MessageKind::Map, now, &mut datagram)
                == Verdict::Drop(DropReason::Loss);
            lost += u32::from(l);
            bursts += u32::from(l && !prev);
            prev = l;
        }
        let rate = f64::from(lost) / f64::from(n);
        let burst = f64::from(lost) / f64::from(bursts);
        assert!(
            (rate - 0.1).abs() < 0.01,
            "destination {destination}: {rate}"
        );
        assert!(
            (burst - 5.0).abs() < 0.4,
            "destination {destination}: {burst}"
        );
    }
}

#[test]
fn corruption_flips_one_bit_of_the_datagrams() {
    let (map, _) = map_and_tim();
    let (a, a_addr) = receiver();
    let mut tx = Broadcaster::new(vec![a_addr], Wrapping::Raw).unwrap();
    tx.set_messages(vec![map.clone()]);
    tx.set_faults(Faults {
        corrupt_fraction: 1.0,
        seed: 11,
        ..Faults::default()
    })
    .unwrap();
    for _ in 0..20 {
        tx.tick();
    }
    let got = drain(&a);
    assert_eq!(got.len(), 20);
    for datagram in &got {
        let flipped: u32 = datagram
            .iter()
            .zip(map.frame())
            .map(|(x, y)| (x ^ y).count_ones())
            .sum();
        assert_eq!(flipped, 1);
    }
    assert_eq!((tx.stats().corrupted, tx.stats().sent), (20, 20));
    // Half of them, over many datagrams, with the same seed every time.
    let mut faults = FaultInjector::new(Faults {
        corrupt_fraction: 0.5,
        seed: 11,
        ..Faults::default()
    })
    .unwrap();
    let mut buf = map.frame().to_vec();
    let now = Instant::now();
    let corrupted = (0..10_000)
        .filter(|_| {
            matches!(
                faults.decide(0, MessageKind::Map, now, &mut buf),
                Verdict::Corrupted { .. }
            )
        })
        .count();
    assert!((4700..5300).contains(&corrupted), "{corrupted}");
    assert!(FaultInjector::new(Faults {
        corrupt_fraction: 1.5,
        ..Faults::default()
    })
    .is_err());
}

#[test]
fn tim_is_held_until_its_time() {
    let (map, tim) = map_and_tim();
    let (a, a_addr) = receiver();
    let mut tx = Broadcaster::new(vec![a_addr], Wrapping::Raw).unwrap();
    tx.set_messages(vec![map.clone(), tim.clone()]);
    let start = Instant::now();
    tx.set_faults(Faults {
        tim_not_before: Some(start + Duration::from_secs(2)),
        ..Faults::default()
    })
    .unwrap();
    for k in 0..4 {
        tx.tick_at(start + Duration::from_secs(k));
    }
    let got = drain(&a);
    // Ticks at 0 s and 1 s: MAP only; at 2 s and 3 s: MAP and TIM.
    assert_eq!(got.len(), 6);
    assert_eq!(got.iter().filter(|d| *d == tim.frame()).count(), 2);
    assert_eq!(got[0], map.frame());
    assert_eq!(got[3], tim.frame());
    assert_eq!(tx.stats().tim_held, 2);
}

#[test]
fn bad_destinations_and_frames_are_refused() {
    assert!(Broadcaster::new(vec![], Wrapping::Raw).is_err());
    let v4: SocketAddr = "127.0.0.1:5000".parse().unwrap();
    let v6: SocketAddr = "[::1]:5000".parse().unwrap();
    assert!(Broadcaster::new(vec![v4, v6], Wrapping::Raw).is_err());
    let (map, _) = map_and_tim();
    let wrapped = Wrapping::Ieee1609Unsecured.wrap(map.frame());
    assert!(Message::new(wrapped).is_err());
    assert_eq!(map.kind(), MessageKind::Map);
}

#[test]
fn send_errors_are_counted_not_fatal() {
    let (map, _) = map_and_tim();
    let (a, a_addr) = receiver();
    // Port 0 cannot be sent to; the other destination still gets its datagrams.
    let nowhere: SocketAddr = "127.0.0.1:0".parse().unwrap();
    let mut tx = Broadcaster::new(vec![nowhere, a_addr], Wrapping::Raw).unwrap();
    tx.set_messages(vec![map]);
    for _ in 0..3 {
        tx.tick();
    }
    assert_eq!(drain(&a).len(), 3);
    let stats = tx.stats();
    assert_eq!((stats.sent, stats.send_errors), (3, 3));
    assert!(stats.last_error.is_some());
}

#[test]
fn rsu_files_parse_back() {
    let (map, tim) = map_and_tim();
    let dir = std::env::temp_dir().join(format!("hil-sim-rsu-{}", std::process::id()));
    let options = RsuOptions {
        channel: TxChannel::Number(183),
        interval_ms: 100,
        delivery: RsuDelivery::StoreAndRepeat {
            start_unix_ms: NOW_MS,
            stop_unix_ms: NOW_MS + 7 * 86_400_000,
        },
        ..RsuOptions::default()
    };
    let paths = write_rsu_files(&dir, &[map.clone(), tim.clone()], &options).unwrap();
    let names: Vec<String> = paths
        .iter()
        .map(|p| p.file_name().unwrap().to_string_lossy().into_owned())
        .collect();
    assert_eq!(names, ["01-map.txt", "02-tim.txt"]);
    for (path, (message, psid, kind)) in paths
        .iter()
        .zip([(&map, Psid::SPAT, "MAP"), (&tim, Psid::TIM, "TIM")])
    {
        let text = std::fs::read_to_string(path).unwrap();
        assert!(text.starts_with("Version=0.7\n"), "{text}");
        // RSU records write the p-encoded octets (SPaT 0x8002, TIM 0x8003).
        let octets = format!("PSID=0x{:X}\n", psid.p_encoded_value().unwrap());
        assert!(text.contains(&octets), "{text}");
        let record = RsuMessage::parse(&text).expect("the codec reads our record");
        assert_eq!((record.message_type, record.psid), (kind, psid));
        assert_eq!(record.tx_channel, Some(TxChannel::Number(183)));
        assert_eq!(record.tx_mode, Some(TxMode::Continuous));
        assert_eq!(record.tx_interval, Some(100));
        assert_eq!(record.delivery_start, Some("11/22/2026, 10:00"));
        assert_eq!(record.delivery_stop, Some("11/29/2026, 10:00"));
        assert_eq!(
            (record.signature, record.encryption),
            (Some(false), Some(false))
        );
        let mut payload = vec![0u8; record.payload.decoded_len().unwrap()];
        record.payload.decode_into(&mut payload).unwrap();
        assert_eq!(payload, message.frame());
    }
    std::fs::remove_dir_all(&dir).unwrap();

    // Immediate forward: no window, interval 0; a PSID override for every message.
    let text = rsu_record(
        0,
        &tim,
        &RsuOptions {
            psid: Some(Psid::MAP),
            ..RsuOptions::default()
        },
    )
    .unwrap();
    let record = RsuMessage::parse(&text).unwrap();
    assert_eq!((record.psid, record.tx_interval), (Psid::MAP, Some(0)));
    assert!(text.contains("PSID=0xE0000017\n"), "{text}");
    assert_eq!((record.delivery_start, record.delivery_stop), (None, None));

    let bad = RsuOptions {
        priority: 9,
        ..RsuOptions::default()
    };
    assert!(matches!(
        rsu_record(0, &map, &bad),
        Err(RsuFileError::Priority { value: 9 })
    ));
    let backwards = RsuOptions {
        delivery: RsuDelivery::StoreAndRepeat {
            start_unix_ms: NOW_MS,
            stop_unix_ms: NOW_MS,
        },
        ..RsuOptions::default()
    };
    assert!(rsu_record(0, &map, &backwards).is_err());
    let odd = Message::new(vec![0x00, 0x63, 0x00]).unwrap();
    assert!(matches!(
        rsu_record(3, &odd, &RsuOptions::default()),
        Err(RsuFileError::NoPsid { index: 3, .. })
    ));
}
