//! The `obu` binary's command line: texts it prints, and mistakes that exit with status 2
//! before anything starts.

use std::process::{Command, Output};

fn obu(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_obu"))
        .args(args)
        .output()
        .expect("the obu binary runs")
}

#[test]
fn texts_go_to_stdout_with_success() {
    let out = obu(&["--print-default-config"]);
    assert_eq!(out.status.code(), Some(0));
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(text.starts_with("# OBU daemon configuration."), "{text}");
    assert!(text.contains("[bridge]") && text.contains("bind = \"127.0.0.1:8080\""));
    let out = obu(&["--help"]);
    assert_eq!(out.status.code(), Some(0));
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(text.contains("Usage: obu [OPTIONS]"), "{text}");
    assert!(text.contains("--print-default-config"), "{text}");
}

#[test]
fn bad_flags_exit_2_with_a_clear_message() {
    for (args, message) in [
        (
            &["--bogus"][..],
            "obu: error: unexpected argument '--bogus' found",
        ),
        (
            &["--config"][..],
            "a value is required for '--config <FILE>'",
        ),
        (
            &["--bridge", "com1"][..],
            "expected tcp:HOST:PORT or serial:PATH",
        ),
        (
            &["--config", "/nonexistent/obu.toml"][..],
            "obu: error: cannot read /nonexistent/obu.toml",
        ),
        (
            &["--print-default-config", "--bridge", "tcp:h:1"][..],
            "cannot be used with",
        ),
    ] {
        let out = obu(args);
        let stderr = String::from_utf8(out.stderr).unwrap();
        assert_eq!(out.status.code(), Some(2), "{args:?}: {stderr}");
        assert!(out.stdout.is_empty(), "{args:?}");
        assert!(stderr.contains(message), "{args:?}: {stderr}");
        assert!(stderr.contains("try '--help'"), "{args:?}: {stderr}");
    }
}
