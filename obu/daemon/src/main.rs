//! `obu`: the in-vehicle daemon (see the `obu_daemon` library).
#![forbid(unsafe_code)]

fn main() -> std::process::ExitCode {
    obu_daemon::main()
}
