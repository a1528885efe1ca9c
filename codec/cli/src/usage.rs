//! Usage errors: clap finds them, this module words them as the tool always has, "what is
//! wrong" plus "hint: what to do" (with "did you mean" for near misses), from the error's
//! kind and context. Help and version requests come back as [`Command::Help`].

use std::ffi::OsString;

use clap::error::{ContextKind, ContextValue, ErrorKind};
use clap::{CommandFactory, Parser};

use crate::args::{ArgError, Cli, Command};

/// The commands, in help order.
const COMMANDS: [&str; 4] = ["decode", "encode", "info", "help"];

/// Parses the arguments after the program name.
pub fn parse(args: &[OsString]) -> Result<Command, ArgError> {
    let argv = std::iter::once(OsString::from("j2735")).chain(args.iter().cloned());
    match Cli::try_parse_from(argv) {
        Ok(cli) => crate::args::command(cli),
        Err(e) => from_clap(&e, args),
    }
}

/// What clap's `error` means for the user of `args` (the arguments after the program name).
pub fn from_clap(error: &clap::Error, args: &[OsString]) -> Result<Command, ArgError> {
    let command = args
        .iter()
        .filter_map(|a| a.to_str())
        .find(|a| COMMANDS[..3].contains(a));
    let text = |kind| context_text(error, kind);
    Err(match error.kind() {
        ErrorKind::DisplayHelp | ErrorKind::DisplayVersion => {
            return Ok(Command::Help(error.render().to_string()));
        }
        ErrorKind::MissingSubcommand | ErrorKind::DisplayHelpOnMissingArgumentOrSubcommand => {
            ArgError::new(
                "no command given",
                "run `j2735 decode FILE`, or `j2735 help` for the commands",
            )
        }
        ErrorKind::InvalidSubcommand => unknown_command(&text(ContextKind::InvalidSubcommand)),
        ErrorKind::UnknownArgument => unknown_argument(command, &text(ContextKind::InvalidArg)),
        ErrorKind::InvalidValue => invalid_value(command, error),
        ErrorKind::ValueValidation => ArgError::new(
            format!(
                "invalid value `{}` for {}",
                text(ContextKind::InvalidValue),
                option_name(&text(ContextKind::InvalidArg))
            ),
            std::error::Error::source(error).map_or_else(String::new, |s| s.to_string()),
        ),
        ErrorKind::ArgumentConflict => {
            let name = option_name(&text(ContextKind::InvalidArg));
            ArgError::new(
                format!("{name} given twice"),
                format!("give {name} once (see {})", help_of(command)),
            )
        }
        ErrorKind::MissingRequiredArgument => {
            let name = command.unwrap_or("the command");
            ArgError::new(
                format!("{name} needs an input"),
                format!("give a FILE, or - for standard input: j2735 {name} frames.hex"),
            )
        }
        _ => other(command, error),
    })
}

/// The text of a context item of `error` (lists joined with ", "), empty when absent.
fn context_text(error: &clap::Error, kind: ContextKind) -> String {
    match error.get(kind) {
        Some(ContextValue::String(s)) => s.clone(),
        Some(ContextValue::Strings(list)) => list.join(", "),
        Some(other) => other.to_string(),
        None => String::new(),
    }
}

/// `--input` of clap's `--input <FORMAT>`.
fn option_name(arg: &str) -> String {
    arg.split([' ', '=']).next().unwrap_or(arg).to_string()
}

/// Where to read more: the command's help, or the overview.
fn help_of(command: Option<&str>) -> String {
    match command {
        Some(name) => format!("`j2735 {name} --help`"),
        None => "`j2735 help`".into(),
    }
}

/// A word where a command belongs.
fn unknown_command(name: &str) -> ArgError {
    let hint = match closest(name, &COMMANDS) {
        Some(near) => format!("did you mean `j2735 {near}`? Commands: decode, encode, info, help"),
        None => "the commands are decode, encode, info and help (`j2735 help`)".into(),
    };
    ArgError::new(format!("unknown command `{name}`"), hint)
}

/// An option the command does not take, or an input too many.
fn unknown_argument(command: Option<&str>, arg: &str) -> ArgError {
    let name = option_name(arg);
    let Some(command) = command else {
        let mut e = unknown_command(&name);
        e.message = format!("unknown option {name} before the command");
        return e;
    };
    if !name.starts_with('-') {
        return ArgError::new(
            format!("more than one input (the second is {arg})"),
            format!(
                "`j2735 {command}` reads one FILE (or - for standard input); \
                 concatenate hex files first: cat a.hex b.hex | j2735 {command} -"
            ),
        );
    }
    let options = options_of(command);
    let names: Vec<&str> = options.iter().map(String::as_str).collect();
    let mut hint = match closest(&name, &names) {
        Some(near) => format!("did you mean {near}? "),
        None => String::new(),
    };
    hint.push_str(&format!(
        "`j2735 {command}` takes {} (see `j2735 {command} --help`)",
        names.join(", ")
    ));
    ArgError::new(format!("unknown option {name} for {command}"), hint)
}

/// The long options of `command` (help left out), from the declaration.
fn options_of(command: &str) -> Vec<String> {
    let cli = Cli::command();
    cli.find_subcommand(command)
        .map(|c| {
            c.get_arguments()
                .filter_map(|a| a.get_long())
                .filter(|l| *l != "help")
                .map(|l| format!("--{l}"))
                .collect()
        })
        .unwrap_or_default()
}

/// A value outside an option's list, or a missing value.
fn invalid_value(command: Option<&str>, error: &clap::Error) -> ArgError {
    let name = option_name(&context_text(error, ContextKind::InvalidArg));
    let value = context_text(error, ContextKind::InvalidValue);
    let expects = match error.get(ContextKind::ValidValue) {
        Some(ContextValue::Strings(list)) => one_of(list),
        _ => "a value".into(),
    };
    if value.is_empty() {
        ArgError::new(
            format!("{name} needs a value"),
            format!("give {name} {expects}"),
        )
    } else {
        ArgError::new(
            format!("invalid value `{value}` for {name}"),
            format!("give {name} {expects} (see {})", help_of(command)),
        )
    }
}

/// "a, b or c".
fn one_of(list: &[String]) -> String {
    match list {
        [] => String::new(),
        [one] => one.clone(),
        [init @ .., last] => format!("{} or {last}", init.join(", ")),
    }
}

/// Any other error: clap's own wording, and where to read more.
fn other(command: Option<&str>, error: &clap::Error) -> ArgError {
    let rendered = error.render().to_string();
    let first = rendered.lines().next().unwrap_or("invalid command line");
    let message = first.strip_prefix("error: ").unwrap_or(first).to_string();
    ArgError::new(message, format!("see {}", help_of(command)))
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

    #[test]
    fn edit_distance_counts_edits() {
        assert_eq!(edit_distance("decode", "decode"), 0);
        assert_eq!(edit_distance("decod", "decode"), 1);
        assert_eq!(edit_distance("--inptu", "--input"), 2);
        assert_eq!(edit_distance("", "abc"), 3);
    }

    #[test]
    fn lists_read_as_prose() {
        let list = |v: &[&str]| one_of(&v.iter().map(|s| s.to_string()).collect::<Vec<_>>());
        assert_eq!(list(&["hex", "bin"]), "hex or bin");
        assert_eq!(
            list(&["none", "1609.2-unsecured", "rsu41"]),
            "none, 1609.2-unsecured or rsu41"
        );
    }

    #[test]
    fn options_come_from_the_declaration() {
        assert_eq!(options_of("decode"), ["--input", "--unwrap"]);
        assert_eq!(
            options_of("encode"),
            ["--wrap", "--psid", "--type", "--strict"]
        );
    }
}
