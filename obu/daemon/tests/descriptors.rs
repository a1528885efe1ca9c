//! The real `obu` binary out of file descriptors. Configured with a connection cap above
//! its open-file limit (here `ulimit -n 40` and `max_connections = 500`), `accept` fails
//! with EMFILE: the daemon then sheds its oldest idle connection and waits a little instead
//! of retrying at once, so the queued connections (and `/healthz`) are still served; when
//! only event streams hold the descriptors and nothing can be shed, it backs off (to
//! 500 ms) and uses next to no CPU, and serves again as soon as descriptors are freed.

mod common;

use common::{status, temp_dir, Daemon};
use std::io::{Read, Write};
use std::net::TcpStream;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

fn start(dir: &std::path::Path) -> Daemon {
    let config = dir.join("obu.toml");
    let text = format!(
        "[v2x]\nbind = \"127.0.0.1:0\"\n[gnss]\nsource = \"nmea-udp\"\naddress = \"127.0.0.1:0\"\n\
         [http]\nbind = \"127.0.0.1:0\"\nsettings_file = \"{}\"\npin = \"4711\"\nmax_connections = 500\n",
        dir.join("settings.json").display()
    );
    std::fs::write(&config, text).unwrap();
    let mut sh = Command::new("sh");
    sh.args(["-c", "ulimit -n 40 && exec \"$0\" \"$@\""])
        .arg(env!("CARGO_BIN_EXE_obu"))
        .arg("--config")
        .arg(&config)
        .stderr(Stdio::null());
    Daemon::spawn(sh)
}

/// `GET /healthz` on a new connection; the time it took, or `None` within `limit`.
fn health_within(addr: &str, limit: Duration) -> Option<Duration> {
    let t0 = Instant::now();
    let mut s = TcpStream::connect(addr).ok()?;
    s.set_read_timeout(Some(limit)).ok()?;
    write!(
        s,
        "GET /healthz HTTP/1.1\r\nHost: {addr}\r\nConnection: close\r\n\r\n"
    )
    .ok()?;
    let mut out = String::new();
    s.read_to_string(&mut out).ok()?;
    out.ends_with("ok").then(|| t0.elapsed())
}

/// CPU seconds (user + system) of process `pid` so far.
fn cpu_seconds(pid: u32) -> f64 {
    let stat = std::fs::read_to_string(format!("/proc/{pid}/stat")).unwrap();
    let rest = &stat[stat.rfind(')').unwrap() + 2..];
    let f: Vec<&str> = rest.split_whitespace().collect();
    (f[11].parse::<f64>().unwrap() + f[12].parse::<f64>().unwrap()) / 100.0
}

fn rejected(addr: &str, reason: &str) -> u64 {
    status(addr)["counters"]["http_rejected"][reason]
        .as_u64()
        .unwrap_or(0)
}

#[test]
fn out_of_descriptors_the_daemon_sheds_and_backs_off_instead_of_spinning() {
    let dir = temp_dir("descriptors");
    let d = start(&dir);
    // 80 idle connections: more than the 40 descriptors allow.
    let idle: Vec<TcpStream> = (0..80)
        .map(|_| TcpStream::connect(&d.http).unwrap())
        .collect();
    let t = health_within(&d.http, Duration::from_secs(5)).expect("/healthz answers");
    println!("# 80 idle connections under ulimit -n 40: /healthz after {t:?}");
    assert!(t < Duration::from_secs(2), "{t:?}");
    assert!(rejected(&d.http, "accept: out of file descriptors") >= 1);
    assert!(rejected(&d.http, "shed: out of file descriptors") >= 1);
    drop(idle);
    std::thread::sleep(Duration::from_millis(300));

    // Event streams, which are never shed, take every descriptor; more clients wait in
    // the kernel's queue (so the counters can be read only once the streams are gone).
    let before = rejected(&d.http, "accept: out of file descriptors");
    let t0 = Instant::now();
    let streams: Vec<TcpStream> = (0..60)
        .map(|_| {
            let mut s = TcpStream::connect(&d.http).unwrap();
            write!(s, "GET /events HTTP/1.1\r\nHost: {}\r\n\r\n", d.http).unwrap();
            s
        })
        .collect();
    std::thread::sleep(Duration::from_millis(1500));
    let files = std::fs::read_dir(format!("/proc/{}/fd", d.pid()))
        .unwrap()
        .count();
    assert!(
        files >= 38,
        "the streams hold the descriptors: {files} open"
    );
    let cpu0 = cpu_seconds(d.pid());
    std::thread::sleep(Duration::from_secs(3));
    let cpu = cpu_seconds(d.pid()) - cpu0;
    // Descriptors freed: served again within the longest back-off.
    drop(streams);
    let t = health_within(&d.http, Duration::from_secs(5)).expect("/healthz answers again");
    assert!(t < Duration::from_secs(2), "{t:?}");
    let tries = rejected(&d.http, "accept: out of file descriptors") - before;
    let spell = t0.elapsed();
    println!("# out of descriptors with nothing to shed: CPU {cpu:.2} s in 3 s, {tries} accept attempts in {spell:?}");
    assert!(cpu < 0.3, "no busy loop: {cpu:.2} s of CPU in 3 s");
    // A busy loop would make hundreds of thousands.
    assert!(
        (1..=200).contains(&tries),
        "backed off: {tries} attempts in {spell:?}"
    );
    assert!(d.stop().success());
}
