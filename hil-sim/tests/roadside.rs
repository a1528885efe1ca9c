//! The roadside unit from a scenario file (`hil-sim roadside`: the bench's scenario loader,
//! then `roadside::rsu`): its messages reach a UDP listener (raw and
//! IEEE 1609.2) at the configured rate and the RSU 4.1 files parse back to the same frames.

use hil_sim::scenario::Scenario;
use j2735::envelope::Psid;
use j2735::msg::message_frame::MessageFrame;
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
            pki_dir: None,
            signing: Default::default(),
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
        pki_dir: None,
        signing: Default::default(),
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

/// `roadside pki` then `hil-sim roadside --pki`: every datagram is signed data that the
/// OBU core's trust policy, trusting only the PKI's root and CA, accepts; the RSU files
/// ask the RSU to sign.
#[test]
fn signs_with_a_pki_that_the_obu_trusts() {
    use obu::security::{CheckContext, Trust};
    use roadside::pki::{time64_of_unix_ms, Pki, PkiSpec};
    let s = scenario("14_geojson_wzdx.toml");
    let dir = std::env::temp_dir().join(format!("hil-sim-pki-{}", std::process::id()));
    let now_s = roadside::clock::unix_ms_now() / 1000;
    let pki = Pki::create(&PkiSpec {
        seed: None,
        start_unix_s: now_s - 86_400,
        root_years: 10,
        ca_years: 5,
        rsu_hours: 48,
        region: None,
        psids: vec![Psid::TIM, Psid::MAP],
        rsu_name: "rsu.test".into(),
    })
    .unwrap();
    pki.write(&dir).unwrap();
    let listener = UdpSocket::bind("127.0.0.1:0").unwrap();
    listener
        .set_read_timeout(Some(Duration::from_millis(500)))
        .unwrap();
    let o = RoadsideOptions {
        destinations: vec![listener.local_addr().unwrap()],
        wrapping: Wrapping::Raw,
        rate_hz: 20.0,
        duration: Some(Duration::from_millis(300)),
        rsu_dir: Some(dir.join("rsu-files")),
        pki_dir: Some(dir.clone()),
        signing: (Default::default(), 60_000, None),
    };
    let summary = run(&s, &o).unwrap();
    assert!(summary.contains("signed"), "{summary}");
    let mut trust = Trust::default();
    trust.add_anchor(&pki.root.cert).unwrap();
    trust.add_anchor(&pki.ca.cert).unwrap();
    let mut buf = [0u8; 4096];
    let mut accepted = 0;
    while let Ok(n) = listener.recv(&mut buf) {
        let data =
            j2735::envelope::ieee1609dot2::Ieee1609Dot2Data::parse(&buf[..n]).expect("signed data");
        let frame = data.application_data().unwrap();
        let ctx = CheckContext {
            message_id: j2735::frame::peek_message_id(frame).unwrap(),
            now_us: Some(time64_of_unix_ms(roadside::clock::unix_ms_now())),
            alt_now_us: None,
            position: None,
        };
        trust
            .check(data.signed_data().expect("signed"), &ctx)
            .unwrap();
        accepted += 1;
    }
    assert!(accepted >= 8, "{accepted} datagrams");
    for f in std::fs::read_dir(dir.join("rsu-files")).unwrap() {
        let text = std::fs::read_to_string(f.unwrap().path()).unwrap();
        assert!(text.contains("Signature=True"), "{text}");
    }
    let _ = std::fs::remove_dir_all(dir);
}
