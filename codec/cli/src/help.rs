//! The help texts: `j2735 help [COMMAND]`, `--help` after a command, and `--version`.

/// The tool's version line.
pub fn version() -> String {
    format!(
        "j2735 {} (SAE J2735 2020, UPER and JER)",
        env!("CARGO_PKG_VERSION")
    )
}

/// The overview printed by `j2735 help`, `j2735 --help` and `j2735` alone (on stderr).
pub const MAIN: &str = "\
j2735: SAE J2735 (2020) MessageFrames in UPER, JER (X.697) and human-readable summaries

Usage: j2735 <COMMAND> [OPTIONS] [FILE|-]

Commands:
  decode   UPER frames (hex lines or binary) to JER, one JSON line per frame
  encode   JER MessageFrames, one per line, to UPER hex or an envelope
  info     a short summary of each frame (MAP lanes and nodes, TIM regions and ITIS codes)
  help     this text, or a command's: j2735 help <COMMAND>

Options:
  -h, --help     print help (after a command: that command's help)
  -V, --version  print the version

FILE is read whole; - (or no FILE, where optional) reads standard input.
Exit status: 0 every frame done, 1 some frame failed (its output line says why),
2 usage error or unreadable input.
";

/// `j2735 decode --help`.
pub const DECODE: &str = "\
Decode UPER MessageFrames to JER (X.697): one compact JSON line per frame.

Usage: j2735 decode [--input hex|bin] [--unwrap auto|none] [FILE|-]

Options:
  --input hex|bin     hex (default): one frame per line; spaces and 0x prefixes are
                      ignored, blank lines and lines starting with # are skipped.
                      bin: the whole input is one frame (with --unwrap auto, RSU
                      text records when it starts with Version=).
  --unwrap auto|none  auto (default): remove an IEEE 1609.2 envelope (unsecured or
                      signed; signatures are not verified) around a frame, and read
                      RSU 4.1 text records: when any line starts with Version=, the
                      whole input is RSU records, each beginning at its Version= line
                      (Version=0.7 and the blank-line Version=0.5 layout).
                      none: every input is a bare MessageFrame.
  -h, --help          print this help

A frame that fails gives {\"error\":\"<what> at bit <n> in <type>\"} on its own line
(envelopes: \"<what> at byte <n> in Ieee1609Dot2Data\"); the other frames still come
out, and the exit status is 1.

Examples:
  j2735 decode frames.hex
  j2735 decode --input bin capture.uper
  j2735 decode tim.rsu41.txt
  echo '0x00 1f 2d ...' | j2735 decode
";

/// `j2735 encode --help`.
pub const ENCODE: &str = "\
Encode JER (X.697) MessageFrames, one JSON object per line, to UPER.

Usage: j2735 encode [--wrap none|1609.2-unsecured|rsu41] [--psid HEX] [--type TYPE] [FILE|-]

Options:
  --wrap none              one lower-case hex line per frame (default)
  --wrap 1609.2-unsecured  one hex line of IEEE 1609.2 unsecured data per frame:
                           03 80 <COER length> <frame>
  --wrap rsu41             one RSU 4.1 message text record (Version=0.7) per frame,
                           records separated by a blank line
  --psid HEX               rsu41 only: the PSID, hexadecimal, 0x optional. Default by
                           message type: MAP and SPAT 0x8002, TIM 0x8003, BSM 0x20,
                           PSM 0x27 (other types need --psid)
  --type TYPE              rsu41 only: the Type= value (default from the messageId:
                           MAP, SPAT, BSM, TIM, ...); a known type must match the frame
  -h, --help               print this help

Blank lines are skipped. A line that fails gives {\"error\":\"...\"} in its place (the
JER or encoding error); the other frames still come out, and the exit status is 1.

Examples:
  j2735 decode tim.hex | j2735 encode
  j2735 encode --wrap rsu41 --psid 0x8003 tim.jsonl > tim.rsu41.txt
  j2735 encode --wrap 1609.2-unsecured map.jsonl
";

/// `j2735 info --help`.
pub const INFO: &str = "\
Summarise each frame for a human: message type, messageId and size in octets; for MAP
the intersections and road segments with lane and node counts; for TIM each data frame's
validity window, regions, content kind and ITIS codes; for other messages type and size.

Usage: j2735 info [--input hex|bin] [--unwrap auto|none] FILE|-

Options:
  --input hex|bin     as for decode (default hex: one frame per line)
  --unwrap auto|none  as for decode (default auto: 1609.2 envelopes, RSU text records)
  -h, --help          print this help

A frame that fails gives \"frame <n>: error: ...\" and the exit status is 1.

Examples:
  j2735 info workzone.hex
  j2735 info - < map.rsu41.txt
";

/// `j2735 help --help`.
pub const HELP: &str = "\
Print help.

Usage: j2735 help [COMMAND]

COMMAND is decode, encode, info or help; without it the overview is printed.
";
