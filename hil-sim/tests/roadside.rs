//! The roadside unit from a scenario file (`hil-sim roadside`: the bench's scenario loader,
//! then `roadside::rsu`): its messages reach a UDP listener (raw and
//! IEEE 1609.2) at the configured rate and the RSU 4.1 files parse back to the same frames.

use hil_sim::scenario::Scenario;
use j2735::message_frame::MessageFrame;
use roadside::broadcast::Wrapping;
use roadside::rsu::{messages_of, run, RoadsideOptions};
use roadside::site::Site;
use std::net::UdpSocket;
use std::path::Path;
use std::time::Duration;

fn scenario(name: &str) -> Site {
    Scenario::load(
        &Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../tests/scenarios")
            .join(name),
    )
    .unwrap()
    .site()
}

#[test]
fn broadcasts_map_and_tims_of_a_wzdx_scenario() {
    let s = scenario("14_geojson_wzdx.toml");
    let msgs = messages_of(&s).unwrap();
    assert_eq!(msgs.len(), 2, "MAP + one TIM");
    let listener = UdpSocket::bind("127.0.0.1:0").unwrap();
    listener
        .set_read_timeout(Some(Duration::from_millis(500)))
        .unwrap();
    for wrapping in [Wrapping::Raw, Wrapping::Ieee1609Unsecured] {
        let o = RoadsideOptions {
            destinations: vec![listener.local_addr().unwrap()],
            wrapping,
            rate_hz: 20.0,
            duration: Some(Duration::from_millis(500)),
            rsu_dir: None,
        };
        let summary = run(&s, &o).unwrap();
        let mut ids = Vec::new();
        let mut buf = [0u8; 4096];
        while let Ok(n) = listener.recv(&mut buf) {
            let frame = j2735::envelope::unwrap_message_frame(&buf[..n]).expect("a frame");
            let _: MessageFrame = j2735::uper::decode(frame.frame).expect("decodes");
            ids.push(j2735::frame::peek_message_id(frame.frame).unwrap());
        }
        // 0.5 s at 20 Hz: about 10 ticks of 2 datagrams.
        assert!(
            (16..=24).contains(&ids.len()),
            "{wrapping:?}: {} datagrams; {summary}",
            ids.len()
        );
        assert!(ids.contains(&18) && ids.contains(&31), "{ids:?}");
    }
}

#[test]
fn writes_rsu_files_that_parse_back() {
    let s = scenario("01_paper_drive.toml");
    let dir = std::env::temp_dir().join(format!("hil-sim-rsu-{}", std::process::id()));
    let o = RoadsideOptions {
        destinations: vec![],
        wrapping: Wrapping::Raw,
        rate_hz: 10.0,
        duration: None,
        rsu_dir: Some(dir.clone()),
    };
    run(&s, &o).unwrap();
    let frames: Vec<Vec<u8>> = messages_of(&s)
        .unwrap()
        .iter()
        .map(|m| m.frame().to_vec())
        .collect();
    let mut files: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    files.sort();
    assert_eq!(files.len(), frames.len());
    for (f, frame) in files.iter().zip(&frames) {
        let text = std::fs::read_to_string(f).unwrap();
        let record = j2735::envelope::rsu_text::RsuMessage::parse(&text).expect("an RSU record");
        let mut back = vec![0u8; record.payload.decoded_len().unwrap()];
        record.payload.decode_into(&mut back).unwrap();
        assert_eq!(back, *frame, "{}", f.display());
    }
    let _ = std::fs::remove_dir_all(dir);
}
