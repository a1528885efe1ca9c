use super::*;
use std::ffi::OsString;
use std::sync::atomic::AtomicU64;

fn os(s: &str) -> OsString {
    OsString::from(s)
}

#[test]
fn notify_socket_forms() {
    assert_eq!(parse_notify_socket(None), Ok(None));
    assert_eq!(parse_notify_socket(Some(&os(""))), Ok(None));
    assert_eq!(
        parse_notify_socket(Some(&os("/run/systemd/notify"))),
        Ok(Some(NotifyAddr::Path("/run/systemd/notify".into())))
    );
    assert_eq!(
        parse_notify_socket(Some(&os("@/org/freedesktop/systemd1/notify/123"))),
        Ok(Some(NotifyAddr::Abstract(
            b"/org/freedesktop/systemd1/notify/123".to_vec()
        )))
    );
    for bad in ["@", "relative/sock", "vsock:2:1234"] {
        let e = parse_notify_socket(Some(&os(bad))).unwrap_err();
        assert!(e.contains("NOTIFY_SOCKET"), "{e}");
    }
}

#[test]
fn watchdog_variables() {
    let ms = Duration::from_millis;
    assert_eq!(parse_watchdog(None, None, 7), Ok(None));
    assert_eq!(parse_watchdog(Some(""), None, 7), Ok(None));
    assert_eq!(parse_watchdog(Some("200000"), None, 7), Ok(Some(ms(200))));
    assert_eq!(
        parse_watchdog(Some("30000000"), Some("7"), 7),
        Ok(Some(ms(30_000)))
    );
    assert_eq!(
        parse_watchdog(Some("200000"), Some("8"), 7),
        Ok(None),
        "another process's"
    );
    for (usec, pid) in [
        ("0", None),
        ("-5", None),
        ("12ms", None),
        ("99999999999999999999", None),
        ("1000", Some("x")),
    ] {
        assert!(
            parse_watchdog(Some(usec), pid, 7).is_err(),
            "{usec} {pid:?}"
        );
    }
}

#[test]
fn the_tick_is_a_quarter_of_the_interval() {
    assert_eq!(
        liveness_tick(Duration::from_secs(20)),
        Duration::from_secs(5)
    );
    assert_eq!(
        liveness_tick(Duration::from_micros(2)),
        Duration::from_millis(1)
    );
}

/// A notifier sending to a socket bound in a fresh directory, and that socket.
fn bound(name: &str, watchdog: Option<Duration>) -> (Notifier, UnixDatagram, PathBuf) {
    let dir = std::env::temp_dir().join(format!("obu-notify-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("notify");
    let server = UnixDatagram::bind(&path).unwrap();
    server
        .set_read_timeout(Some(Duration::from_secs(2)))
        .unwrap();
    let notifier = Notifier {
        target: Some((UnixDatagram::unbound().unwrap(), NotifyAddr::Path(path))),
        watchdog,
        failed: AtomicBool::new(false),
    };
    (notifier, server, dir)
}

fn recv(server: &UnixDatagram) -> String {
    let mut buf = [0u8; 512];
    let n = server.recv(&mut buf).expect("a notification");
    String::from_utf8_lossy(&buf[..n]).into_owned()
}

#[test]
fn ready_and_stopping_reach_the_socket() {
    let (n, server, dir) = bound("states", None);
    assert_eq!(n.watchdog(), None);
    n.ready("serving http://127.0.0.1:1\nv2x");
    assert_eq!(
        recv(&server),
        "READY=1\nSTATUS=serving http://127.0.0.1:1 v2x"
    );
    n.stopping();
    assert_eq!(recv(&server), "STOPPING=1\nSTATUS=shutting down");
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn an_abstract_socket_gets_the_notification() {
    use std::os::linux::net::SocketAddrExt;
    let name = format!("obu-notify-test-{}", std::process::id());
    let addr = std::os::unix::net::SocketAddr::from_abstract_name(name.as_bytes()).unwrap();
    let server = UnixDatagram::bind_addr(&addr).unwrap();
    server
        .set_read_timeout(Some(Duration::from_secs(2)))
        .unwrap();
    let parsed = parse_notify_socket(Some(&os(&format!("@{name}"))))
        .unwrap()
        .unwrap();
    let n = Notifier {
        target: Some((UnixDatagram::unbound().unwrap(), parsed)),
        watchdog: None,
        failed: AtomicBool::new(false),
    };
    n.send("WATCHDOG=1");
    assert_eq!(recv(&server), "WATCHDOG=1");
}

#[test]
fn without_a_socket_nothing_is_sent_and_a_gone_socket_is_not_fatal() {
    let n = Notifier::none();
    n.ready("x");
    assert_eq!(n.watchdog(), None);
    let (n, server, dir) = bound("gone", Some(Duration::from_secs(1)));
    assert_eq!(n.watchdog(), Some(Duration::from_secs(1)));
    drop(server);
    std::fs::remove_dir_all(dir).unwrap();
    n.send("WATCHDOG=1");
    n.send("WATCHDOG=1");
    assert!(n.failed.load(Ordering::Relaxed));
}

#[tokio::test(start_paused = true)]
async fn pings_stop_when_the_loop_stops() {
    let (n, server, dir) = bound("watchdog", None);
    server.set_nonblocking(true).unwrap();
    let progress = Arc::new(AtomicU64::new(0));
    let (stop_tx, stop) = watch::channel(false);
    let p = progress.clone();
    let interval = Duration::from_millis(200);
    let task = tokio::spawn(run_watchdog(
        Arc::new(n),
        interval,
        move || p.load(Ordering::Relaxed),
        stop,
    ));
    let count = |server: &UnixDatagram| {
        let mut buf = [0u8; 64];
        let mut n = 0;
        while let Ok(len) = server.recv(&mut buf) {
            assert_eq!(&buf[..len], b"WATCHDOG=1");
            n += 1;
        }
        n
    };
    // The loop turns every 50 ms: a ping every 100 ms.
    for _ in 0..20 {
        tokio::time::sleep(Duration::from_millis(50)).await;
        progress.fetch_add(1, Ordering::Relaxed);
    }
    // The last turn's ping may come at the next check.
    tokio::time::sleep(Duration::from_millis(110)).await;
    let pinged = count(&server);
    assert!((10..=11).contains(&pinged), "{pinged} pings in 1.1 s");
    // The loop is wedged: no more pings.
    tokio::time::sleep(Duration::from_secs(1)).await;
    assert_eq!(count(&server), 0);
    // It turns again: pings again.
    progress.fetch_add(1, Ordering::Relaxed);
    tokio::time::sleep(Duration::from_millis(120)).await;
    assert_eq!(count(&server), 1);
    stop_tx.send(true).unwrap();
    task.await.unwrap();
    std::fs::remove_dir_all(dir).unwrap();
}
