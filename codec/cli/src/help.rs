//! The prose of the help texts that clap does not derive from the declaration in
//! [`crate::args`]: the overview, each command's description and its closing notes.

/// What `--version` prints after the program name.
pub const VERSION: &str = concat!(env!("CARGO_PKG_VERSION"), " (SAE J2735 2020, UPER and JER)");

/// The one-line description above the overview.
pub const ABOUT: &str =
    "j2735: SAE J2735 (2020) MessageFrames in UPER, JER (X.697) and human-readable summaries";

/// After the overview's options.
pub const MAIN_AFTER: &str = "\
FILE is read whole; - (or no FILE, where optional) reads standard input.
Exit status: 0 every frame done, 1 some frame failed (its output line says why),
2 usage error or unreadable input.
Run `j2735 help <COMMAND>` (or `j2735 <COMMAND> --help`) for a command's options.";

/// `j2735 decode --help`: the description.
pub const DECODE_ABOUT: &str = "\
Decode UPER MessageFrames to JER (X.697): one compact JSON line per frame.";

/// `j2735 decode --help`: after the options.
pub const DECODE_AFTER: &str = "\
A frame that fails gives {\"error\":\"<what> at bit <n> in <type>\"} on its own line
(envelopes: \"<what> at byte <n> in Ieee1609Dot2Data\"); the other frames still come
out, and the exit status is 1.

Examples:
  j2735 decode frames.hex
  j2735 decode --input bin capture.uper
  j2735 decode tim.rsu41.txt
  echo '0x00 1f 2d ...' | j2735 decode";

/// `j2735 encode --help`: the description.
pub const ENCODE_ABOUT: &str = "\
Encode JER (X.697) MessageFrames, one JSON object per line, to UPER.";

/// `j2735 encode --help`: after the options.
pub const ENCODE_AFTER: &str = "\
Blank lines are skipped. A line that fails gives {\"error\":\"...\"} in its place (the
JER or encoding error); the other frames still come out, and the exit status is 1.

Examples:
  j2735 decode tim.hex | j2735 encode
  j2735 encode --strict tim.jsonl
  j2735 encode --wrap rsu41 --psid 0x8003 tim.jsonl > tim.rsu41.txt
  j2735 encode --wrap 1609.2-unsecured map.jsonl";

/// `j2735 info --help`: the description.
pub const INFO_ABOUT: &str = "\
Summarise each frame for a human: message type, messageId and size in octets; for MAP
the intersections and road segments with lane and node counts; for TIM each data frame's
validity window, regions, content kind and ITIS codes; for other messages type and size.";

/// `j2735 info --help`: after the options.
pub const INFO_AFTER: &str = "\
A frame that fails gives \"frame <n>: error: ...\" and the exit status is 1.

Examples:
  j2735 info workzone.hex
  j2735 info - < map.rsu41.txt";
