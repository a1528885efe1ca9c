//! The roadside programs a real SNMP agent: net-snmp's snmpd with the bench's NTCIP 1218 /
//! RSU 4.1 agent, over SNMPv3 USM authPriv, and the test RSU broadcasts what was
//! deposited. Needs Debian's snmpd (feature `snmpd-rsu`, enabled by `.ci/run`).

use hil_sim::test_rsu::agent::Mib;
use hil_sim::test_rsu::{TestRsu, TestRsuConfig, TestUser};
use j2735::envelope::Psid;
use roadside::rsu_snmp::credentials::{AuthProtocol, Credentials, PrivProtocol};
use roadside::rsu_snmp::mib::{RepeatMessage, RsuMib};
use roadside::rsu_snmp::session::{Agent, Session};
use roadside::rsu_snmp::table::{reconcile, Owned, RsuProblem, TableRules};
use std::net::UdpSocket;
use std::path::PathBuf;
use std::time::{Duration, Instant};

fn user(name: &str, auth: &'static str, privacy: &'static str) -> TestUser {
    TestUser {
        name: name.into(),
        auth,
        auth_password: format!("{name}-auth-pass"),
        privacy,
        priv_password: format!("{name}-priv-pass"),
    }
}

fn v3(name: &str, auth: AuthProtocol, privacy: PrivProtocol) -> Credentials {
    Credentials::V3 {
        user: name.into(),
        auth,
        auth_password: format!("{name}-auth-pass"),
        privacy,
        priv_password: format!("{name}-priv-pass"),
    }
}

fn start(port: u16, mib: Mib, listener: &UdpSocket) -> TestRsu {
    let dir = std::env::temp_dir().join(format!("test-rsu-{}-{port}", std::process::id()));
    TestRsu::start(TestRsuConfig {
        dir,
        port,
        mib,
        users: vec![
            user("roadside", "SHA", "AES"),
            user("strong", "SHA-512", "AES-256"),
        ],
        community: Some("lab-community".into()),
        broadcast_to: vec![listener.local_addr().unwrap()],
        max_rows: 8,
        pki: None,
        hil_sim: PathBuf::from(env!("CARGO_BIN_EXE_hil-sim")),
    })
    .expect("snmpd test RSU (install Debian's snmpd)")
}

fn message(label: &str, payload: &[u8], interval_ms: u32) -> RepeatMessage {
    let now = roadside::clock::unix_ms_now();
    RepeatMessage {
        label: label.into(),
        psid: Psid::TIM,
        message_id: 31,
        payload: payload.to_vec(),
        channel: 183,
        interval_ms,
        start_unix_ms: now - 60_000,
        stop_unix_ms: now + 3_600_000,
        priority: 6,
        rsu_signs: false,
        alternating: false,
    }
}

fn session(rsu: &TestRsu, c: Credentials) -> Session {
    Session::new(rsu.address(), c, Duration::from_millis(500), 1)
}

/// Empties the socket's queue.
fn drain(listener: &UdpSocket) {
    listener.set_nonblocking(true).unwrap();
    let mut buf = [0u8; 4096];
    while listener.recv(&mut buf).is_ok() {}
    listener.set_nonblocking(false).unwrap();
}

/// Datagrams received within `for_ms`, by payload.
fn received(listener: &UdpSocket, for_ms: u64) -> Vec<Vec<u8>> {
    listener
        .set_read_timeout(Some(Duration::from_millis(20)))
        .unwrap();
    let end = Instant::now() + Duration::from_millis(for_ms);
    let mut out = Vec::new();
    let mut buf = [0u8; 4096];
    while Instant::now() < end {
        if let Ok(n) = listener.recv(&mut buf) {
            out.push(buf[..n].to_vec());
        }
    }
    out
}

#[test]
fn ntcip1218_deposit_converge_change_restart_over_snmpv3() {
    let listener = UdpSocket::bind("127.0.0.1:0").unwrap();
    let mut rsu = start(17161, Mib::Ntcip1218, &listener);
    let mut s = session(
        &rsu,
        v3("roadside", AuthProtocol::Sha, PrivProtocol::Aes128),
    );
    let rules = TableRules {
        mib: RsuMib::Ntcip1218,
        max_rows: None,
        manage_all: false,
    };
    let map = message("MAP", &[0x00, 0x12, 0x01, 0x02], 100);
    let tim = message("TIM", &[0x00, 0x1f, 0xaa, 0xbb], 100);
    let wanted = [
        RsuMib::Ntcip1218.repeat_row(&map),
        RsuMib::Ntcip1218.repeat_row(&tim),
    ];
    let mut owned = Owned::new();

    let first = reconcile(&mut s, rules, &wanted, &mut owned).unwrap();
    assert_eq!((first.created, first.destroyed), (2, 0));
    assert_eq!(owned.keys().copied().collect::<Vec<_>>(), [1, 2]);

    // Nothing changed: reads only.
    let writes = s.counts().writes;
    let again = reconcile(&mut s, rules, &wanted, &mut owned).unwrap();
    assert!(again.plan.is_converged(), "{again:?}");
    assert_eq!(s.counts().writes, writes);

    // The RSU broadcasts both every 100 ms.
    let got = received(&listener, 1000);
    let tims = got.iter().filter(|p| p.as_slice() == tim.payload).count();
    let maps = got.iter().filter(|p| p.as_slice() == map.payload).count();
    assert!(
        (8..=12).contains(&tims) && (8..=12).contains(&maps),
        "{tims} TIM, {maps} MAP"
    );

    // A foreign row (another manager, v2c) is left alone; a changed TIM replaces ours.
    let mut lab = session(
        &rsu,
        Credentials::V2c {
            community: "lab-community".into(),
        },
    );
    let foreign = message("foreign", &[0x00, 0x1f, 0x99], 1000);
    let mut theirs = Owned::new();
    let other = [RsuMib::Ntcip1218.repeat_row(&foreign)];
    reconcile(&mut lab, rules, &other, &mut theirs).unwrap();
    assert_eq!(theirs.keys().copied().collect::<Vec<_>>(), [3]);
    let tim2 = message("TIM", &[0x00, 0x1f, 0xcc], 100);
    let wanted2 = [
        RsuMib::Ntcip1218.repeat_row(&map),
        RsuMib::Ntcip1218.repeat_row(&tim2),
    ];
    let change = reconcile(&mut s, rules, &wanted2, &mut owned).unwrap();
    assert_eq!((change.destroyed, change.created), (1, 1));
    assert_eq!(change.plan.foreign, [3]);
    // What was sent before the change and still waits in the socket goes first.
    std::thread::sleep(Duration::from_millis(30));
    drain(&listener);
    let got = received(&listener, 500);
    assert!(got.iter().any(|p| p.as_slice() == tim2.payload));
    assert!(got.iter().all(|p| p.as_slice() != tim.payload));

    // The RSU restarts with an empty table (and its engine boots from 1 again): restored.
    rsu.restart().unwrap();
    let restored = reconcile(&mut s, rules, &wanted2, &mut owned).unwrap();
    assert_eq!(restored.created, 2, "{restored:?}");

    // SHA-512 / AES-256 (Blumenthal key extension) reads the same table.
    let mut strong = session(
        &rsu,
        v3("strong", AuthProtocol::Sha512, PrivProtocol::Aes256),
    );
    let rows = roadside::rsu_snmp::table::read_table(&mut strong, RsuMib::Ntcip1218).unwrap();
    assert_eq!(rows.len(), 2);
}

#[test]
fn wrong_credentials_and_the_wrong_mib_are_clear_errors_and_write_nothing() {
    let listener = UdpSocket::bind("127.0.0.1:0").unwrap();
    let rsu = start(17162, Mib::Ntcip1218, &listener);
    let rules = TableRules {
        mib: RsuMib::Ntcip1218,
        max_rows: None,
        manage_all: false,
    };
    let wanted = [RsuMib::Ntcip1218.repeat_row(&message("TIM", &[0x00, 0x1f, 1], 100))];
    let mut bad = session(
        &rsu,
        Credentials::V3 {
            user: "roadside".into(),
            auth: AuthProtocol::Sha,
            auth_password: "not-the-password".into(),
            privacy: PrivProtocol::Aes128,
            priv_password: "roadside-priv-pass".into(),
        },
    );
    let e = reconcile(&mut bad, rules, &wanted, &mut Owned::new()).unwrap_err();
    assert_eq!(e, RsuProblem::AuthRefused, "{e}");
    assert_eq!(bad.counts().writes, 0);
    let mut unknown = session(&rsu, v3("nobody", AuthProtocol::Sha, PrivProtocol::Aes128));
    let e = reconcile(&mut unknown, rules, &wanted, &mut Owned::new()).unwrap_err();
    assert_eq!(e, RsuProblem::AuthRefused, "{e}");

    // Configured as RSU 4.1 against an NTCIP 1218 unit.
    let mut s = session(
        &rsu,
        v3("roadside", AuthProtocol::Sha, PrivProtocol::Aes128),
    );
    let as41 = TableRules {
        mib: RsuMib::Rsu41,
        ..rules
    };
    let w41 = [RsuMib::Rsu41.repeat_row(&message("TIM", &[0x00, 0x1f, 1], 100))];
    let e = reconcile(&mut s, as41, &w41, &mut Owned::new()).unwrap_err();
    let RsuProblem::MibMismatch(why) = &e else {
        panic!("{e}");
    };
    assert!(why.contains("it answers ntcip1218"), "{why}");
    assert_eq!(s.counts().writes, 0);
    let rows = roadside::rsu_snmp::table::read_table(&mut s, RsuMib::Ntcip1218).unwrap();
    assert!(rows.is_empty());
}

#[test]
fn rsu41_store_and_repeat_with_six_octet_dates() {
    let listener = UdpSocket::bind("127.0.0.1:0").unwrap();
    let rsu = start(17163, Mib::Rsu41, &listener);
    let mut s = session(
        &rsu,
        v3("roadside", AuthProtocol::Sha, PrivProtocol::Aes128),
    );
    let rules = TableRules {
        mib: RsuMib::Rsu41,
        max_rows: Some(8),
        manage_all: false,
    };
    let tim = message("TIM", &[0x00, 0x1f, 0x41], 200);
    let wanted = [RsuMib::Rsu41.repeat_row(&tim)];
    let mut owned = Owned::new();
    assert_eq!(
        reconcile(&mut s, rules, &wanted, &mut owned)
            .unwrap()
            .created,
        1
    );
    assert!(reconcile(&mut s, rules, &wanted, &mut owned)
        .unwrap()
        .plan
        .is_converged());
    let got = received(&listener, 1000);
    let n = got.iter().filter(|p| p.as_slice() == tim.payload).count();
    assert!((4..=6).contains(&n), "{n} TIMs at 200 ms");
}

#[test]
fn the_service_deposits_a_site_the_rsu_signs_and_a_reload_replaces_what_changed() {
    use roadside::service::{read_status, Roadside};
    let listener = UdpSocket::bind("127.0.0.1:0").unwrap();
    let dir = std::env::temp_dir().join(format!("test-rsu-site-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    hil_sim::bench_pki::write_rsu(&dir.join("rsu-pki")).unwrap();
    let rsu = TestRsu::start(TestRsuConfig {
        dir: dir.join("rsu"),
        port: 17164,
        mib: Mib::Ntcip1218,
        users: vec![user("roadside", "SHA", "AES")],
        community: None,
        broadcast_to: vec![listener.local_addr().unwrap()],
        max_rows: 8,
        pki: Some(dir.join("rsu-pki")),
        hil_sim: PathBuf::from(env!("CARGO_BIN_EXE_hil-sim")),
    })
    .expect("snmpd test RSU");
    let creds = dir.join("credentials.toml");
    std::fs::write(
        &creds,
        "[field]\nversion = \"3\"\nuser = \"roadside\"\nauth_password = \"roadside-auth-pass\"\n\
         priv_password = \"roadside-priv-pass\"\n",
    )
    .unwrap();
    use std::os::unix::fs::PermissionsExt;
    std::fs::set_permissions(&creds, std::fs::Permissions::from_mode(0o600)).unwrap();
    let site = |limit: u32| {
        format!(
            "[site]\nname = \"test\"\nstate_dir = \"state\"\n\
             [road]\nkind = \"straight\"\nreference = [39.7392, -104.9903]\nbearing_deg = 90.0\n\
             length_m = 600.0\nlanes_forward = 2\nspeed_limit_kmh = 40.0\n\
             [[zones]]\nsource = \"lanes\"\nclosed_lanes = [2]\nstart_m = 300.0\nend_m = 400.0\nlimit_kmh = {limit}\n\
             [signing]\ndeposit = \"rsu\"\n\
             [rsus]\ncredentials = \"credentials.toml\"\npoll_s = 1.0\n\
             [[rsu]]\nname = \"rsu-1\"\naddress = \"{}\"\nmib = \"ntcip1218\"\ncredentials = \"field\"\n",
            rsu.address()
        )
    };
    let path = dir.join("site.toml");
    std::fs::write(&path, site(10)).unwrap();
    let mut log = Vec::new();
    let now = || (Instant::now(), roadside::clock::unix_ms_now());
    let (t, ms) = now();
    let mut r = Roadside::start(&path, t, ms).unwrap();
    let pass = |r: &mut Roadside, log: &mut Vec<u8>| {
        let (t, ms) = now();
        r.tick(t, ms, true, log).unwrap();
    };
    pass(&mut r, &mut log);
    assert!(r.all_converged(), "{}", String::from_utf8_lossy(&log));
    // The RSU signs (options 0x80) with its certificate: IEEE 1609.2 on the air.
    let got = received(&listener, 500);
    assert!(!got.is_empty());
    assert!(got
        .iter()
        .all(|p| j2735::envelope::ieee1609dot2::looks_like_ieee1609dot2(p)));

    // The site changes (another limit): a reload replaces the TIM and the MAP that carries it.
    std::fs::write(&path, site(20)).unwrap();
    let (t, ms) = now();
    r.reload(t, ms).unwrap();
    pass(&mut r, &mut log);
    let status = read_status(&dir.join("state")).unwrap();
    let counts = &status.rsus[0].counts;
    assert_eq!(
        (counts.get("created"), counts.get("destroyed")),
        (Some(&2), Some(&2)),
        "{counts:?}"
    );
    // A broken site file is refused and the running one kept.
    std::fs::write(&path, "[site]\nname = 1\n").unwrap();
    let (t, ms) = now();
    assert!(r.reload(t, ms).is_err());
    pass(&mut r, &mut log);
    assert!(r.all_converged(), "{}", String::from_utf8_lossy(&log));
    drop(r);
    drop(rsu);
    let _ = std::fs::remove_dir_all(&dir);
}
