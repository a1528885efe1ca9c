//! Command-line parsing, by hand: the command, its options (`--name value` or
//! `--name=value`), at most one input (`FILE` or `-`), and errors that say what to do.

use std::fmt;
use std::path::PathBuf;

/// What the command line asks for.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Command {
    /// Print a help text (`help`, `--help`, `help <command>`, `<command> --help`).
    Help(&'static str),
    /// Print the version.
    Version,
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

/// How the input holds frames.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum InputFormat {
    /// One hexadecimal frame per line.
    Hex,
    /// The whole input is one binary frame.
    Bin,
}

/// Whether envelopes around frames are removed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Unwrap {
    /// Remove IEEE 1609.2 envelopes and read RSU text records.
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
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Wrap {
    /// Nothing: hex of the frame.
    None,
    /// IEEE 1609.2 unsecured data, as hex.
    Unsecured,
    /// An RSU 4.1 text record.
    Rsu41,
}

/// The options of `encode`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct EncodeOptions {
    /// `--wrap`.
    pub wrap: Wrap,
    /// `--psid` (rsu41).
    pub psid: Option<u32>,
    /// `--type` (rsu41).
    pub message_type: Option<String>,
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
    fn new(message: impl Into<String>, hint: impl Into<String>) -> Self {
        Self {
            message: message.into(),
            hint: hint.into(),
        }
    }
}

impl fmt::Display for ArgError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}\nhint: {}", self.message, self.hint)
    }
}

/// One command: its name, its help text and its options (each with the values it takes).
struct Spec {
    name: &'static str,
    help: &'static str,
    options: &'static [(&'static str, &'static str)],
    input_required: bool,
}

const INPUT_OPTIONS: &[(&str, &str)] = &[("--input", "hex or bin"), ("--unwrap", "auto or none")];

const SPECS: [Spec; 3] = [
    Spec {
        name: "decode",
        help: crate::help::DECODE,
        options: INPUT_OPTIONS,
        input_required: false,
    },
    Spec {
        name: "encode",
        help: crate::help::ENCODE,
        options: &[
            ("--wrap", "none, 1609.2-unsecured or rsu41"),
            ("--psid", "a hexadecimal PSID such as 0x8003"),
            ("--type", "an RSU message type such as TIM"),
        ],
        input_required: false,
    },
    Spec {
        name: "info",
        help: crate::help::INFO,
        options: INPUT_OPTIONS,
        input_required: true,
    },
];

/// The options and input of one command, before their values are checked.
#[derive(Default)]
struct Raw {
    options: Vec<(&'static str, String)>,
    input: Option<String>,
    help: bool,
}

impl Raw {
    fn value(&self, name: &str) -> Option<&str> {
        self.options
            .iter()
            .find(|(n, _)| *n == name)
            .map(|(_, v)| v.as_str())
    }
}

/// Parses the arguments after the program name.
pub fn parse(args: &[String]) -> Result<Command, ArgError> {
    let Some(first) = args.first() else {
        return Err(ArgError::new(
            "no command given",
            "run `j2735 decode FILE`, or `j2735 help` for the commands",
        ));
    };
    match first.as_str() {
        "-h" | "--help" => Ok(Command::Help(crate::help::MAIN)),
        "-V" | "--version" => Ok(Command::Version),
        "help" => parse_help(&args[1..]),
        name => match SPECS.iter().find(|s| s.name == name) {
            Some(spec) => parse_command(spec, &args[1..]),
            None => Err(unknown_command(name)),
        },
    }
}

fn parse_help(rest: &[String]) -> Result<Command, ArgError> {
    match rest {
        [] => Ok(Command::Help(crate::help::MAIN)),
        [topic] if topic == "help" => Ok(Command::Help(crate::help::HELP)),
        [topic] => SPECS
            .iter()
            .find(|s| s.name == topic)
            .map(|s| Command::Help(s.help))
            .ok_or_else(|| unknown_command(topic)),
        _ => Err(ArgError::new(
            "help takes at most one command",
            "run `j2735 help decode` (or encode, info)",
        )),
    }
}

fn unknown_command(name: &str) -> ArgError {
    let names = ["decode", "encode", "info", "help"];
    let hint = match closest(name, &names) {
        Some(near) => format!("did you mean `j2735 {near}`? Commands: decode, encode, info, help"),
        None => "the commands are decode, encode, info and help (`j2735 help`)".into(),
    };
    let what = if name.starts_with('-') {
        format!("unknown option {name} before the command")
    } else {
        format!("unknown command `{name}`")
    };
    ArgError::new(what, hint)
}

fn parse_command(spec: &Spec, args: &[String]) -> Result<Command, ArgError> {
    let raw = collect(spec, args)?;
    if raw.help {
        return Ok(Command::Help(spec.help));
    }
    let source = source(spec, &raw)?;
    match spec.name {
        "encode" => encode_options(spec, &raw, source).map(Command::Encode),
        name => {
            let options = input_options(spec, &raw, source)?;
            Ok(if name == "info" {
                Command::Info(options)
            } else {
                Command::Decode(options)
            })
        }
    }
}

/// Splits `args` into options, the input and `--help`, rejecting unknown options.
fn collect(spec: &Spec, args: &[String]) -> Result<Raw, ArgError> {
    let mut raw = Raw::default();
    let mut rest = args.iter();
    let mut options_done = false;
    while let Some(arg) = rest.next() {
        if options_done || arg == "-" || !arg.starts_with('-') {
            set_input(spec, &mut raw, arg)?;
        } else if arg == "--" {
            options_done = true;
        } else if arg == "-h" || arg == "--help" {
            raw.help = true;
        } else {
            let (name, value) = option(spec, arg, &mut rest)?;
            if raw.value(name).is_some() {
                return Err(ArgError::new(
                    format!("{name} given twice"),
                    format!("give {name} once (see `j2735 {} --help`)", spec.name),
                ));
            }
            raw.options.push((name, value));
        }
    }
    Ok(raw)
}

fn set_input(spec: &Spec, raw: &mut Raw, arg: &str) -> Result<(), ArgError> {
    if let Some(first) = &raw.input {
        return Err(ArgError::new(
            format!("more than one input: {first} and {arg}"),
            format!(
                "`j2735 {}` reads one FILE (or - for standard input); \
                 concatenate hex files first: cat a.hex b.hex | j2735 {} -",
                spec.name, spec.name
            ),
        ));
    }
    raw.input = Some(arg.to_string());
    Ok(())
}

/// One option and its value, from `--name=value` or `--name value`.
fn option(
    spec: &Spec,
    arg: &str,
    rest: &mut std::slice::Iter<'_, String>,
) -> Result<(&'static str, String), ArgError> {
    let (name, inline) = match arg.split_once('=') {
        Some((name, value)) => (name, Some(value.to_string())),
        None => (arg, None),
    };
    let Some(&(known, expects)) = spec.options.iter().find(|(n, _)| *n == name) else {
        return Err(unknown_option(spec, name));
    };
    match inline.or_else(|| rest.next().cloned()) {
        Some(value) => Ok((known, value)),
        None => Err(ArgError::new(
            format!("{known} needs a value"),
            format!("give {known} {expects}"),
        )),
    }
}

fn unknown_option(spec: &Spec, name: &str) -> ArgError {
    let names: Vec<&str> = spec.options.iter().map(|(n, _)| *n).collect();
    let mut hint = match closest(name, &names) {
        Some(near) => format!("did you mean {near}? "),
        None => String::new(),
    };
    hint.push_str(&format!(
        "`j2735 {}` takes {} (see `j2735 {} --help`)",
        spec.name,
        names.join(", "),
        spec.name
    ));
    ArgError::new(format!("unknown option {name} for {}", spec.name), hint)
}

fn source(spec: &Spec, raw: &Raw) -> Result<Source, ArgError> {
    match raw.input.as_deref() {
        None if spec.input_required => Err(ArgError::new(
            format!("{} needs an input", spec.name),
            format!(
                "give a FILE, or - for standard input: j2735 {} frames.hex",
                spec.name
            ),
        )),
        None | Some("-") => Ok(Source::Stdin),
        Some(path) => Ok(Source::File(PathBuf::from(path))),
    }
}

fn input_options(spec: &Spec, raw: &Raw, source: Source) -> Result<InputOptions, ArgError> {
    let format = match raw.value("--input") {
        None | Some("hex") => InputFormat::Hex,
        Some("bin") => InputFormat::Bin,
        Some(other) => return Err(bad_value(spec, "--input", other, "hex or bin")),
    };
    let unwrap = match raw.value("--unwrap") {
        None | Some("auto") => Unwrap::Auto,
        Some("none") => Unwrap::None,
        Some(other) => return Err(bad_value(spec, "--unwrap", other, "auto or none")),
    };
    Ok(InputOptions {
        format,
        unwrap,
        source,
    })
}

fn encode_options(spec: &Spec, raw: &Raw, source: Source) -> Result<EncodeOptions, ArgError> {
    let wrap = match raw.value("--wrap") {
        None | Some("none") => Wrap::None,
        Some("1609.2-unsecured") => Wrap::Unsecured,
        Some("rsu41") => Wrap::Rsu41,
        Some(other) => {
            let expects = "none, 1609.2-unsecured or rsu41";
            return Err(bad_value(spec, "--wrap", other, expects));
        }
    };
    let psid = raw.value("--psid").map(parse_psid).transpose()?;
    let message_type = raw.value("--type").map(parse_type).transpose()?;
    if wrap != Wrap::Rsu41 && (psid.is_some() || message_type.is_some()) {
        return Err(ArgError::new(
            "--psid and --type belong to RSU text records",
            "add --wrap rsu41, or leave out --psid and --type",
        ));
    }
    Ok(EncodeOptions {
        wrap,
        psid,
        message_type,
        source,
    })
}

fn bad_value(spec: &Spec, name: &str, value: &str, expects: &str) -> ArgError {
    ArgError::new(
        format!("invalid value `{value}` for {name}"),
        format!("give {name} {expects} (see `j2735 {} --help`)", spec.name),
    )
}

/// A PSID in hexadecimal, `0x` optional (as RSU records write it).
fn parse_psid(text: &str) -> Result<u32, ArgError> {
    let digits = text
        .strip_prefix("0x")
        .or_else(|| text.strip_prefix("0X"))
        .unwrap_or(text);
    let valid = (1..=8).contains(&digits.len()) && digits.bytes().all(|b| b.is_ascii_hexdigit());
    match valid
        .then(|| u32::from_str_radix(digits, 16).ok())
        .flatten()
    {
        Some(psid) => Ok(psid),
        None => Err(ArgError::new(
            format!("invalid PSID `{text}`"),
            "give --psid in hexadecimal, 1 to 8 digits: --psid 0x8003",
        )),
    }
}

/// An RSU `Type=` value: one word, no spaces.
fn parse_type(text: &str) -> Result<String, ArgError> {
    let valid = !text.is_empty() && text.bytes().all(|b| b.is_ascii_graphic());
    if valid {
        Ok(text.to_string())
    } else {
        Err(ArgError::new(
            format!("invalid message type `{text}`"),
            "give --type one word such as TIM, MAP or SPAT",
        ))
    }
}

/// The candidate nearest to `word` (at most 2 edits away), for "did you mean".
fn closest<'a>(word: &str, candidates: &[&'a str]) -> Option<&'a str> {
    candidates
        .iter()
        .map(|c| (edit_distance(word, c), *c))
        .filter(|(d, _)| *d <= 2)
        .min_by_key(|(d, _)| *d)
        .map(|(_, c)| c)
}

/// Levenshtein distance between two short strings.
fn edit_distance(a: &str, b: &str) -> usize {
    let b: Vec<char> = b.chars().collect();
    let mut row: Vec<usize> = (0..=b.len()).collect();
    for (i, ca) in a.chars().enumerate() {
        let mut diagonal = row[0];
        row[0] = i + 1;
        for (j, cb) in b.iter().enumerate() {
            let substitute = diagonal + usize::from(ca != *cb);
            diagonal = row[j + 1];
            row[j + 1] = substitute.min(row[j] + 1).min(diagonal + 1);
        }
    }
    row[b.len()]
}

#[cfg(test)]
mod tests {
    use super::*;

    fn args(line: &str) -> Vec<String> {
        line.split_whitespace().map(String::from).collect()
    }

    #[test]
    fn decode_defaults_to_hex_auto_stdin() {
        let expected = Command::Decode(InputOptions {
            format: InputFormat::Hex,
            unwrap: Unwrap::Auto,
            source: Source::Stdin,
        });
        assert_eq!(parse(&args("decode")), Ok(expected.clone()));
        assert_eq!(parse(&args("decode -")), Ok(expected));
    }

    #[test]
    fn options_take_both_spellings() {
        let cmd = parse(&args("decode --input=bin --unwrap none f.uper")).unwrap();
        let Command::Decode(o) = cmd else { panic!() };
        assert_eq!(o.format, InputFormat::Bin);
        assert_eq!(o.unwrap, Unwrap::None);
        assert_eq!(o.source, Source::File("f.uper".into()));
    }

    #[test]
    fn encode_reads_psid_and_type() {
        let cmd = parse(&args("encode --wrap rsu41 --psid 0x8003 --type TIM")).unwrap();
        let Command::Encode(o) = cmd else { panic!() };
        assert_eq!((o.wrap, o.psid), (Wrap::Rsu41, Some(0x8003)));
        assert_eq!(o.message_type.as_deref(), Some("TIM"));
        assert!(parse(&args("encode --psid 0x8003")).is_err());
        assert!(parse(&args("encode --wrap rsu41 --psid 0x1_0")).is_err());
    }

    #[test]
    fn errors_hint_at_the_fix() {
        let e = parse(&args("decode --inptu hex")).unwrap_err();
        assert!(e.message.contains("unknown option --inptu"), "{e}");
        assert!(e.hint.contains("did you mean --input"), "{e}");
        let e = parse(&args("decod x")).unwrap_err();
        assert!(e.hint.contains("j2735 decode"), "{e}");
        assert!(parse(&args("info")).unwrap_err().hint.contains("FILE"));
        assert!(parse(&args("decode --input"))
            .unwrap_err()
            .hint
            .contains("hex or bin"));
        assert!(parse(&args("decode --input hex --input bin")).is_err());
        assert!(parse(&args("decode a b")).is_err());
        assert!(parse(&[]).is_err());
    }

    #[test]
    fn help_and_version() {
        assert_eq!(parse(&args("--help")), Ok(Command::Help(crate::help::MAIN)));
        assert_eq!(
            parse(&args("help info")),
            Ok(Command::Help(crate::help::INFO))
        );
        assert_eq!(
            parse(&args("encode --wrap bogus --help")),
            Ok(Command::Help(crate::help::ENCODE))
        );
        assert_eq!(parse(&args("-V")), Ok(Command::Version));
    }

    #[test]
    fn edit_distance_counts_edits() {
        assert_eq!(edit_distance("decode", "decode"), 0);
        assert_eq!(edit_distance("decod", "decode"), 1);
        assert_eq!(edit_distance("--inptu", "--input"), 2);
        assert_eq!(edit_distance("", "abc"), 3);
    }
}
