//! The daemon's command line, declared with clap (derive): `obu [--config FILE] [--bridge
//! SOURCE]`, `obu gnss-check --source KIND --address ADDR [--seconds N]`,
//! `obu --print-default-config`, `obu --help`, `obu --version`.

use std::ffi::OsString;
use std::path::PathBuf;

use clap::{Parser, Subcommand};

use crate::config::{self, BridgeSource, Config, GnssSource};
use crate::gnss_check::CheckArgs;

/// What the description of `obu --help` says after the options.
const AFTER_HELP: &str = "\
The tablet app is served on [http] bind (default http://127.0.0.1:8080).

--bridge SOURCE (or [bridge] source) runs no OBU core and no V2X, GNSS or CAN input:
the firmware's HmiState frames are read from SOURCE and served to the tablet.
  tcp:HOST:PORT   connect to it (e.g. QEMU -serial tcp:127.0.0.1:5003,server,nowait)
  serial:PATH     read a serial device set raw at 115200 8N1 (see [bridge] baud)
Settings changed on the tablet do not reach the firmware (the link is one-way).

`obu gnss-check` reads a GNSS receiver and says whether it is good enough for
lane-level use (exit status 0 when it is, 1 when not, 2 when it cannot be read).

Exit status: 0 after a signal (SIGINT, SIGTERM) or a printed text, 1 when it cannot
run (a port in use), 2 for a wrong command line or configuration.";

/// The command line as given.
#[derive(Debug, Parser)]
#[command(
    name = "obu",
    version,
    about = "obu: the work-zone OBU daemon",
    after_help = AFTER_HELP
)]
struct Cli {
    /// The TOML configuration to run with: the keys it has override the built-in defaults
    /// (without --config: the defaults, safe on a laptop; see --print-default-config)
    #[arg(long, value_name = "FILE")]
    config: Option<PathBuf>,
    /// Bridge mode: serve the firmware's HmiState stream from SOURCE, tcp:HOST:PORT or
    /// serial:PATH, instead of running the core (overrides [bridge] source)
    #[arg(long, value_name = "SOURCE", value_parser = clap::value_parser!(BridgeSource))]
    bridge: Option<BridgeSource>,
    /// Print the documented default configuration (every key, with its default) and exit
    #[arg(long, conflicts_with_all = ["config", "bridge"])]
    print_default_config: bool,
    /// Print the tablet's contract (alert kinds in priority order, stages, the settings'
    /// ranges, defaults and units) as JSON and exit: the text of hmi-web/contract.json
    #[arg(long, conflicts_with_all = ["config", "bridge", "print_default_config"])]
    print_hmi_contract: bool,
    #[command(subcommand)]
    command: Option<Command>,
}

/// Commands besides running the daemon.
#[derive(Debug, Subcommand)]
enum Command {
    /// Read a GNSS receiver for a while and print what the OBU gets from it (sentences and
    /// UBX messages, fixes and why not, rate, accuracy source, time) with a verdict on
    /// lane-level use
    GnssCheck {
        /// nmea-serial, ubx-serial, nmea-tcp, nmea-udp or nmea-file (a recording)
        #[arg(long, value_parser = parse_source)]
        source: GnssSource,
        /// Device path, host:port, the UDP address to listen on, or the file
        #[arg(long)]
        address: String,
        /// How long to read a live receiver
        #[arg(long, default_value_t = 10.0)]
        seconds: f64,
    },
}

/// A receiver source (`gpsd` and `none` are no receiver to check).
fn parse_source(s: &str) -> Result<GnssSource, String> {
    GnssSource::from_name(s)
        .filter(|k| !matches!(k, GnssSource::Gpsd | GnssSource::None))
        .ok_or_else(|| "one of nmea-serial, ubx-serial, nmea-tcp, nmea-udp, nmea-file".into())
}

/// What the command line asks for.
#[derive(Debug, PartialEq)]
pub enum Action {
    /// Run with this configuration.
    Run(Box<Config>),
    /// Print this text on standard output and exit with success (help, version, the
    /// default configuration).
    Print(String),
    /// Check a GNSS receiver (`obu gnss-check`).
    GnssCheck(CheckArgs),
}

/// Why the command line cannot be run: the message for standard error (exit status 2).
#[derive(Debug, PartialEq, Eq)]
pub struct Usage(pub String);

/// Reads the command line (`args` without the program name) and the configuration it names.
pub fn parse(args: impl IntoIterator<Item = OsString>) -> Result<Action, Usage> {
    let argv = std::iter::once(OsString::from("obu")).chain(args);
    let cli = match Cli::try_parse_from(argv) {
        Ok(cli) => cli,
        Err(e) if e.exit_code() == 0 => return Ok(Action::Print(e.render().to_string())),
        Err(e) => return Err(Usage(e.render().to_string())),
    };
    if cli.print_default_config {
        return Ok(Action::Print(config::DEFAULT_TOML.to_string()));
    }
    if cli.print_hmi_contract {
        return Ok(Action::Print(crate::assets::contract().to_string()));
    }
    if let Some(Command::GnssCheck {
        source,
        address,
        seconds,
    }) = cli.command
    {
        return Ok(Action::GnssCheck(CheckArgs {
            source,
            address,
            seconds,
        }));
    }
    let config = match &cli.config {
        None => Config::default_config(),
        Some(path) => {
            let shown = path.display();
            let text = std::fs::read_to_string(path)
                .map_err(|e| Usage(format!("error: cannot read {shown}: {e}")))?;
            Config::parse(&text).map_err(|e| Usage(format!("error: {shown}: {e}")))?
        }
    };
    let config = match cli.bridge {
        None => config,
        Some(source) => config
            .with_bridge(source)
            .map_err(|e| Usage(format!("error: --bridge: {e}")))?,
    };
    Ok(Action::Run(Box::new(config)))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse_words(words: &[&str]) -> Result<Action, Usage> {
        parse(words.iter().map(OsString::from))
    }

    fn config_of(words: &[&str]) -> Config {
        match parse_words(words) {
            Ok(Action::Run(c)) => *c,
            other => panic!("{words:?}: {other:?}"),
        }
    }

    #[test]
    fn the_declaration_is_consistent() {
        use clap::CommandFactory;
        Cli::command().debug_assert();
    }

    #[test]
    fn config_and_bridge_flags_combine_in_any_order() {
        let dir = std::env::temp_dir().join(format!("obu-cli-test-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let file = dir.join("obu.toml");
        std::fs::write(&file, "[http]\nbind = \"127.0.0.1:9\"\n").unwrap();
        let file = file.to_str().unwrap();
        let c = config_of(&["--bridge", "tcp:127.0.0.1:5003", "--config", file]);
        assert_eq!(c.http.bind.port(), 9);
        let tcp = BridgeSource::Tcp("127.0.0.1:5003".into());
        assert_eq!(c.bridge.source, Some(tcp));
        let c = config_of(&[&format!("--config={file}")]);
        assert_eq!((c.http.bind.port(), c.bridge.source), (9, None));
        assert_eq!(config_of(&[]), Config::default_config());
        let c = config_of(&["--bridge", "serial:/dev/ttyACM0"]);
        let want = BridgeSource::Serial("/dev/ttyACM0".into());
        assert_eq!(c.bridge.source, Some(want));
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn the_packaged_config_differs_from_the_defaults_only_in_the_state_path() {
        let file = concat!(env!("CARGO_MANIFEST_DIR"), "/deploy/obu.toml");
        let mut c = config_of(&["--config", file]);
        assert_eq!(
            c.http.settings_file,
            std::path::PathBuf::from("/var/lib/obu/obu-settings.json")
        );
        assert!(
            c.http.bind.ip().is_loopback(),
            "nothing exposed before set up"
        );
        c.http.settings_file = Config::default_config().http.settings_file;
        assert_eq!(c, Config::default_config());
    }

    #[test]
    fn texts_are_printed() {
        let Ok(Action::Print(text)) = parse_words(&["--print-default-config"]) else {
            panic!()
        };
        assert_eq!(text, config::DEFAULT_TOML);
        let Ok(Action::Print(contract)) = parse_words(&["--print-hmi-contract"]) else {
            panic!("--print-hmi-contract prints")
        };
        let json: serde_json::Value = serde_json::from_str(&contract).expect("JSON");
        assert_eq!(json["alert_kinds"][0], "WorkerInLane");
        assert!(parse_words(&["--print-hmi-contract", "--config", "x.toml"]).is_err());
        let Ok(Action::Print(text)) = parse_words(&["--help"]) else {
            panic!()
        };
        for words in [
            "Usage: obu [OPTIONS]",
            "--config <FILE>",
            "--bridge <SOURCE>",
        ] {
            assert!(text.contains(words), "{words} in {text}");
        }
        assert!(
            text.contains("tcp:HOST:PORT") && text.contains("one-way"),
            "{text}"
        );
        assert!(matches!(parse_words(&["-h"]), Ok(Action::Print(_))));
    }

    #[test]
    fn flag_mistakes_are_named() {
        let error = |words: &[&str]| parse_words(words).unwrap_err().0;
        let e = error(&["--bridge"]);
        assert!(e.contains("--bridge <SOURCE>"), "{e}");
        let e = error(&["--bridge", "tcp:h:1", "--bridge", "tcp:h:2"]);
        assert!(e.contains("cannot be used multiple times"), "{e}");
        let e = error(&["--bridg", "x"]);
        assert!(e.contains("unexpected argument '--bridg'"), "{e}");
        let e = error(&["--bridge", "udp:h:1"]);
        assert!(e.contains("expected tcp:HOST:PORT or serial:PATH"), "{e}");
        let e = error(&["--print-default-config", "--config", "x.toml"]);
        assert!(e.contains("cannot be used with"), "{e}");
        let e = error(&["--config", "/nonexistent/obu.toml"]);
        assert!(
            e.starts_with("error: cannot read /nonexistent/obu.toml"),
            "{e}"
        );
    }
}
