//! The command line, declared with clap (derive): the commands, their options (`--name value`
//! or `--name=value`) and at most one input (`FILE` or `-`). Usage errors are rendered by
//! [`crate::usage`] as "what is wrong" plus "hint: what to do".

use std::path::PathBuf;

use clap::{Args, Parser, Subcommand, ValueEnum};
use j2735::envelope::Psid;

use crate::help;

/// What the command line asks for.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Command {
    /// Print a help or version text (already rendered) on standard output.
    Help(String),
    /// `decode`.
    Decode(InputOptions),
    /// `encode`.
    Encode(EncodeOptions),
    /// `info`.
    Info(InputOptions),
}

/// Where the input comes from.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Source {
    /// Standard input (`-` or no FILE).
    Stdin,
    /// A file.
    File(PathBuf),
}

impl Source {
    fn of(file: Option<PathBuf>) -> Self {
        match file {
            Some(path) if path.as_os_str() != "-" => Self::File(path),
            _ => Self::Stdin,
        }
    }
}

/// How the input holds frames.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum InputFormat {
    /// One frame per line; spaces and 0x prefixes are ignored, blank lines and lines
    /// starting with # are skipped.
    Hex,
    /// The whole input is one frame (with --unwrap auto, RSU text records when it starts
    /// with Version=).
    Bin,
}

/// Whether envelopes around frames are removed.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum Unwrap {
    /// Remove an IEEE 1609.2 envelope (unsecured or signed; signatures are not verified)
    /// around a frame, and read RSU 4.1 text records: when any line starts with Version=,
    /// the whole input is RSU records, each beginning at its Version= line (Version=0.7 and
    /// the blank-line Version=0.5 layout).
    Auto,
    /// Every input is a bare MessageFrame.
    None,
}

/// The options of `decode` and `info`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct InputOptions {
    /// `--input`.
    pub format: InputFormat,
    /// `--unwrap`.
    pub unwrap: Unwrap,
    /// `FILE` or `-`.
    pub source: Source,
}

/// What `encode` puts around each frame.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum Wrap {
    /// One lower-case hex line per frame.
    None,
    /// One hex line of IEEE 1609.2 unsecured data per frame: 03 80 <COER length> <frame>.
    #[value(name = "1609.2-unsecured")]
    Unsecured,
    /// One RSU 4.1 message text record (Version=0.7) per frame, records separated by a
    /// blank line.
    Rsu41,
}

/// The options of `encode`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct EncodeOptions {
    /// `--wrap`.
    pub wrap: Wrap,
    /// `--psid` (rsu41).
    pub psid: Option<Psid>,
    /// `--type` (rsu41).
    pub message_type: Option<String>,
    /// `--strict`: unknown JER members are errors.
    pub strict: bool,
    /// `FILE` or `-`.
    pub source: Source,
}

/// A command line that cannot be run: what is wrong and what to do about it.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ArgError {
    /// What is wrong.
    pub message: String,
    /// What to do.
    pub hint: String,
}

impl ArgError {
    /// An error saying `message`, with `hint`.
    pub fn new(message: impl Into<String>, hint: impl Into<String>) -> Self {
        Self {
            message: message.into(),
            hint: hint.into(),
        }
    }
}

/// The whole command line.
#[derive(Debug, Parser)]
#[command(
    name = "j2735",
    version = help::VERSION,
    about = help::ABOUT,
    after_help = help::MAIN_AFTER,
    arg_required_else_help = false
)]
pub(crate) struct Cli {
    #[command(subcommand)]
    command: Cmd,
}

/// The commands.
#[derive(Debug, Subcommand)]
enum Cmd {
    /// UPER frames (hex lines or binary) to JER, one JSON line per frame
    #[command(long_about = help::DECODE_ABOUT, after_help = help::DECODE_AFTER)]
    Decode {
        #[command(flatten)]
        input: InputArgs,
        /// The input, read whole; - or none: standard input
        #[arg(value_name = "FILE|-")]
        file: Option<PathBuf>,
    },
    /// JER MessageFrames, one per line, to UPER hex or an envelope
    #[command(long_about = help::ENCODE_ABOUT, after_help = help::ENCODE_AFTER)]
    Encode(EncodeArgs),
    /// A short summary of each frame (MAP lanes and nodes, TIM regions and ITIS codes)
    #[command(long_about = help::INFO_ABOUT, after_help = help::INFO_AFTER)]
    Info {
        #[command(flatten)]
        input: InputArgs,
        /// The input, read whole; - reads standard input
        #[arg(value_name = "FILE|-", required = true)]
        file: Option<PathBuf>,
    },
}

/// `--input` and `--unwrap`, shared by `decode` and `info`.
#[derive(Debug, Args)]
struct InputArgs {
    /// How the input holds frames
    #[arg(long, value_enum, value_name = "FORMAT", default_value_t = InputFormat::Hex)]
    input: InputFormat,
    /// Whether IEEE 1609.2 envelopes and RSU text records around frames are removed
    #[arg(long, value_enum, value_name = "MODE", default_value_t = Unwrap::Auto)]
    unwrap: Unwrap,
}

/// The options of `encode`, as given.
#[derive(Debug, Args)]
struct EncodeArgs {
    /// What to put around each frame
    #[arg(long, value_enum, value_name = "WRAP", default_value_t = Wrap::None)]
    wrap: Wrap,
    /// rsu41 only: the PSID as RSU records write it, its p-encoded octets in hexadecimal, 0x
    /// optional (default by message type: MAP and SPAT 0x8002, TIM 0x8003, BSM 0x20, PSM
    /// 0x27; other types need --psid)
    #[arg(long, value_name = "HEX", value_parser = parse_psid)]
    psid: Option<Psid>,
    /// rsu41 only: the Type= value (default from the messageId: MAP, SPAT, BSM, TIM, ...);
    /// a known type must match the frame
    #[arg(long = "type", value_name = "TYPE", value_parser = parse_type)]
    message_type: Option<String>,
    /// Reject JER members the message's types do not have (default: ignore them); the
    /// error line names the member and where it is
    #[arg(long)]
    strict: bool,
    /// The input, read whole; - or none: standard input
    #[arg(value_name = "FILE|-")]
    file: Option<PathBuf>,
}

/// The checked command of a parsed command line.
pub fn command(cli: Cli) -> Result<Command, ArgError> {
    Ok(match cli.command {
        Cmd::Decode { input, file } => Command::Decode(input.options(file)),
        Cmd::Info { input, file } => Command::Info(input.options(file)),
        Cmd::Encode(e) => {
            if e.wrap != Wrap::Rsu41 && (e.psid.is_some() || e.message_type.is_some()) {
                return Err(ArgError::new(
                    "--psid and --type belong to RSU text records",
                    "add --wrap rsu41, or leave out --psid and --type",
                ));
            }
            Command::Encode(EncodeOptions {
                wrap: e.wrap,
                psid: e.psid,
                message_type: e.message_type,
                strict: e.strict,
                source: Source::of(e.file),
            })
        }
    })
}

impl InputArgs {
    fn options(self, file: Option<PathBuf>) -> InputOptions {
        InputOptions {
            format: self.input,
            unwrap: self.unwrap,
            source: Source::of(file),
        }
    }
}

/// A PSID as RSU records write it: p-encoded octets in hexadecimal, `0x` optional.
fn parse_psid(text: &str) -> Result<Psid, String> {
    j2735::envelope::rsu_text::parse_psid(text).ok_or_else(|| {
        "give --psid as its p-encoded octets in hexadecimal, 1 to 8 digits: --psid 0x8003 \
         (TIM)"
            .into()
    })
}

/// An RSU `Type=` value: one word, no spaces.
fn parse_type(text: &str) -> Result<String, String> {
    if !text.is_empty() && text.bytes().all(|b| b.is_ascii_graphic()) {
        Ok(text.to_string())
    } else {
        Err("give --type one word such as TIM, MAP or SPAT".into())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse_line(line: &str) -> Result<Command, ArgError> {
        let args: Vec<std::ffi::OsString> = line
            .split_whitespace()
            .map(std::ffi::OsString::from)
            .collect();
        crate::usage::parse(&args)
    }

    #[test]
    fn the_declaration_is_consistent() {
        use clap::CommandFactory;
        Cli::command().debug_assert();
    }

    #[test]
    fn decode_defaults_to_hex_auto_stdin() {
        let expected = Command::Decode(InputOptions {
            format: InputFormat::Hex,
            unwrap: Unwrap::Auto,
            source: Source::Stdin,
        });
        assert_eq!(parse_line("decode"), Ok(expected.clone()));
        assert_eq!(parse_line("decode -"), Ok(expected));
    }

    #[test]
    fn options_take_both_spellings() {
        let cmd = parse_line("decode --input=bin --unwrap none f.uper").unwrap();
        let Command::Decode(o) = cmd else { panic!() };
        assert_eq!(o.format, InputFormat::Bin);
        assert_eq!(o.unwrap, Unwrap::None);
        assert_eq!(o.source, Source::File("f.uper".into()));
    }

    #[test]
    fn encode_reads_psid_type_and_strict() {
        let cmd = parse_line("encode --wrap rsu41 --psid 0x8003 --type TIM").unwrap();
        let Command::Encode(o) = cmd else { panic!() };
        assert_eq!(
            (o.wrap, o.psid, o.strict),
            (Wrap::Rsu41, Some(Psid::TIM), false)
        );
        assert_eq!(o.message_type.as_deref(), Some("TIM"));
        let Command::Encode(o) = parse_line("encode --strict x.jsonl").unwrap() else {
            panic!()
        };
        assert_eq!((o.wrap, o.strict), (Wrap::None, true));
        assert_eq!(o.source, Source::File("x.jsonl".into()));
        assert!(parse_line("encode --psid 0x8003").is_err());
        assert!(parse_line("encode --wrap rsu41 --psid 0x1_0").is_err());
        assert!(parse_line("encode --wrap rsu41 --psid 123456789").is_err());
    }

    #[test]
    fn errors_hint_at_the_fix() {
        let e = parse_line("decode --inptu hex").unwrap_err();
        assert!(e.message.contains("unknown option --inptu"), "{e:?}");
        assert!(e.hint.contains("did you mean --input"), "{e:?}");
        let e = parse_line("decod x").unwrap_err();
        assert!(e.hint.contains("j2735 decode"), "{e:?}");
        assert!(parse_line("info").unwrap_err().hint.contains("FILE"));
        let e = parse_line("decode --input").unwrap_err();
        assert_eq!(e.message, "--input needs a value");
        assert!(e.hint.contains("hex or bin"), "{e:?}");
        let e = parse_line("decode --input hex --input bin").unwrap_err();
        assert_eq!(e.message, "--input given twice");
        let e = parse_line("decode a b").unwrap_err();
        assert_eq!(e.message, "more than one input (the second is b)");
        let e = parse_line("encode --wrap rsu41 --psid 0x1_0").unwrap_err();
        assert_eq!(e.message, "invalid value `0x1_0` for --psid");
        assert!(e.hint.contains("--psid 0x8003"), "{e:?}");
        assert!(parse_line("").unwrap_err().message.contains("no command"));
    }

    #[test]
    fn help_and_version() {
        let Ok(Command::Help(text)) = parse_line("--help") else {
            panic!()
        };
        assert!(text.contains("Usage: j2735 <COMMAND>"), "{text}");
        let Ok(Command::Help(text)) = parse_line("help info") else {
            panic!()
        };
        assert!(text.contains("Usage: j2735 info"), "{text}");
        let Ok(Command::Help(text)) = parse_line("encode --help") else {
            panic!()
        };
        for option in ["--wrap", "1609.2-unsecured", "--psid", "--type", "--strict"] {
            assert!(text.contains(option), "{option} in {text}");
        }
        let Ok(Command::Help(text)) = parse_line("-V") else {
            panic!()
        };
        assert!(text.starts_with("j2735 "), "{text}");
    }
}
