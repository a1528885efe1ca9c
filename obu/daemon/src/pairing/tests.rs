use super::*;

fn dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("obu-pairing-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn token_of(a: Attempt) -> String {
    match a {
        Attempt::Paired(t) => t,
        other => panic!("not paired: {other:?}"),
    }
}

#[test]
fn a_made_pin_is_six_digits_and_stays_across_restarts() {
    let d = dir("made");
    let file = d.join("s.pairing.json");
    let first = Pairing::load(None, &file).unwrap();
    assert!(!first.configured());
    let pin = first.pin().to_owned();
    assert_eq!(pin.len(), 6);
    assert!(pin.bytes().all(|b| b.is_ascii_digit()), "{pin}");
    let again = Pairing::load(None, &file).unwrap();
    assert_eq!(again.pin(), pin, "the same PIN after a restart");
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        let mode = std::fs::metadata(&file).unwrap().permissions().mode();
        assert_eq!(mode & 0o077, 0, "owner only: {mode:o}");
    }
    // A configured PIN wins and is not written to the file (which a pairing rewrites).
    let configured = Pairing::load(Some("a1b2c3d4"), &file).unwrap();
    assert!(configured.configured());
    assert_eq!(configured.pin(), "a1b2c3d4");
    token_of(configured.attempt("a1b2c3d4", Instant::now()));
    let text = std::fs::read_to_string(&file).unwrap();
    assert!(
        !text.contains("\"pin\"") && text.contains("sessions"),
        "{text}"
    );
    // With a configured PIN nothing is written at start: a read-only place is fine.
    let elsewhere = d.join("not-there").join("p.json");
    assert!(Pairing::load(Some("a1b2c3d4"), &elsewhere).is_ok());
    let e = Pairing::load(None, &elsewhere).unwrap_err();
    assert!(e.contains("cannot write"), "a made PIN must be kept: {e}");
    // Two made PINs differ (one in a million they do not: then a third must).
    let other = Pairing::load(None, &dir("made-2").join("p.json")).unwrap();
    let third = Pairing::load(None, &dir("made-3").join("p.json")).unwrap();
    assert!(other.pin() != pin || third.pin() != pin);
    std::fs::remove_dir_all(&d).unwrap();
}

#[test]
fn a_corrupt_file_is_a_clear_error() {
    let d = dir("corrupt");
    let file = d.join("p.json");
    std::fs::write(&file, "{\"pin\": 12").unwrap();
    let e = Pairing::load(None, &file).unwrap_err();
    assert!(e.contains("p.json") && e.contains("remove it"), "{e}");
    std::fs::remove_dir_all(&d).unwrap();
}

#[test]
fn the_right_pin_gives_a_session_that_survives_a_restart() {
    let d = dir("session");
    let file = d.join("p.json");
    let p = Pairing::load(Some("4321"), &file).unwrap();
    let now = Instant::now();
    assert!(!p.authorised(std::iter::empty(), now));
    let token = token_of(p.attempt("4321", now));
    assert_eq!(token.len(), 64, "256 bits in hexadecimal");
    let cookie = format!("theme=x; {COOKIE}={token}; other=1");
    assert!(p.authorised([cookie.as_str()].into_iter(), now));
    assert!(p.authorised(["a=b", &format!("{COOKIE}={token}")].into_iter(), now));
    let mut forged = token.clone().into_bytes();
    forged[10] = if forged[10] == b'0' { b'1' } else { b'0' };
    let forged = format!("{COOKIE}={}", String::from_utf8(forged).unwrap());
    assert!(!p.authorised([forged.as_str()].into_iter(), now));
    assert!(!p.authorised([format!("{COOKIE}=zz").as_str()].into_iter(), now));
    assert!(!p.authorised([format!("x{COOKIE}={token}").as_str()].into_iter(), now));
    let restarted = Pairing::load(Some("4321"), &file).unwrap();
    assert!(restarted.authorised([cookie.as_str()].into_iter(), now));
    let set = set_cookie(&token);
    for part in ["HttpOnly", "SameSite=Strict", "Path=/"] {
        assert!(set.contains(part), "{set}");
    }
    std::fs::remove_dir_all(&d).unwrap();
}

#[test]
fn sessions_are_bounded_the_least_recently_used_goes() {
    let d = dir("bounded");
    let p = Pairing::load(Some("9999"), &d.join("p.json")).unwrap();
    let t0 = Instant::now();
    let first = token_of(p.attempt("9999", t0));
    let second = token_of(p.attempt("9999", t0 + Duration::from_millis(1)));
    for i in 2..MAX_SESSIONS as u64 {
        token_of(p.attempt("9999", t0 + Duration::from_millis(i)));
    }
    assert_eq!(p.sessions(), MAX_SESSIONS);
    // The first is used again: the second is now the least recently used.
    let later = t0 + Duration::from_secs(1);
    let cookie = |t: &str| format!("{COOKIE}={t}");
    assert!(p.authorised([cookie(&first).as_str()].into_iter(), later));
    token_of(p.attempt("9999", later));
    assert_eq!(p.sessions(), MAX_SESSIONS);
    assert!(p.authorised([cookie(&first).as_str()].into_iter(), later));
    assert!(!p.authorised([cookie(&second).as_str()].into_iter(), later));
    std::fs::remove_dir_all(&d).unwrap();
}

#[test]
fn wrong_pins_lock_pairing_for_longer_and_longer() {
    let d = dir("lockout");
    let p = Pairing::load(Some("2468"), &d.join("p.json")).unwrap();
    let t0 = Instant::now();
    for left in (1..FREE_TRIES).rev() {
        assert_eq!(p.attempt("0000", t0), Attempt::WrongPin { left });
    }
    assert_eq!(p.attempt("0000", t0), Attempt::Locked(FIRST_LOCKOUT));
    // While locked even the right PIN is refused, unchecked.
    let t1 = t0 + Duration::from_secs(10);
    assert_eq!(
        p.attempt("2468", t1),
        Attempt::Locked(FIRST_LOCKOUT - Duration::from_secs(10))
    );
    assert_eq!(p.locked_for(t1), FIRST_LOCKOUT - Duration::from_secs(10));
    // After it, one more wrong PIN locks again, twice as long, and so on up to the cap.
    let mut t = t0 + FIRST_LOCKOUT;
    let mut want = FIRST_LOCKOUT;
    for _ in 0..10 {
        want = (want * 2).min(MAX_LOCKOUT);
        assert_eq!(p.attempt("1111", t), Attempt::Locked(want));
        t += want;
    }
    assert_eq!(want, MAX_LOCKOUT);
    // The right PIN after a lockout pairs and resets the count.
    token_of(p.attempt("2468", t));
    assert_eq!(
        p.attempt("0000", t),
        Attempt::WrongPin {
            left: FREE_TRIES - 1
        }
    );
    assert!(
        !matches!(p.attempt("24680", t), Attempt::Paired(_)),
        "a longer PIN is wrong"
    );
    std::fs::remove_dir_all(&d).unwrap();
}

#[test]
fn constant_time_comparison_is_exact() {
    assert!(ct_eq(b"123456", b"123456"));
    assert!(!ct_eq(b"123456", b"123457"));
    assert!(!ct_eq(b"12345", b"123456"));
    assert!(ct_eq(b"", b""));
    assert_eq!(from_hex(&hex(&[0xab; 32])), Some([0xab; 32]));
    assert_eq!(from_hex(&"g".repeat(64)), None);
}
