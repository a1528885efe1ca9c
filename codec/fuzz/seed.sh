#!/usr/bin/env bash
# Builds the seed corpus of the fuzz targets in codec/fuzz/corpus/<target>/ (git-ignored),
# at run time, from
#   - the shared conformance corpus (../shared/corpus beside the repository, or $1):
#     frames (binary) for message_frame, the oracle's JER of each frame for jer, the wrapped
#     (IEEE 1609.2) frames and RSU text records for envelope;
#   - the shared GNSS receivers' logs (../shared/gnss/logs): their first 2 KB for gnss;
#   - the project's own oracle vectors (codec/tests/vectors/oracle_vectors.jsonl): UPER for
#     message_frame, JER for jer, and for envelope each vector frame wrapped as unsecured and
#     signed 1609.2 data and as an RSU 4.1 text record;
# and a libFuzzer dictionary for jer (corpus/jer.dict: the member names and identifiers of
# those JER texts). Nothing of ../shared is ever written into the repository's tracked files.
# Idempotent; inputs the fuzzer added to corpus/<target>/ are kept.
# Usage: codec/fuzz/seed.sh [SHARED_DIR]
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
shared=${1:-$here/../../../shared}
command -v python3 >/dev/null || { echo "seed.sh: python3 is needed to build the seed corpus" >&2; exit 1; }
python3 - "$here" "$shared" <<'PY'
import hashlib, json, os, sys

here, shared = sys.argv[1], sys.argv[2]
corpus = os.path.join(here, "corpus")
vectors = os.path.join(here, "..", "tests", "vectors", "oracle_vectors.jsonl")
counts = {}


def put(target, name, data):
    d = os.path.join(corpus, target)
    os.makedirs(d, exist_ok=True)
    if isinstance(data, str):
        data = data.encode()
    path = os.path.join(d, "seed-" + name)
    if not (os.path.exists(path) and open(path, "rb").read() == data):
        with open(path, "wb") as f:
            f.write(data)
    counts[target] = counts.get(target, 0) + 1


def from_hex(text):
    return bytes.fromhex("".join(text.split()))


def coer_length(n):
    if n < 0x80:
        return bytes([n])
    digits = n.to_bytes((n.bit_length() + 7) // 8, "big")
    return bytes([0x80 | len(digits)]) + digits


def unsecured(frame):
    return b"\x03\x80" + coer_length(len(frame)) + frame


def rsu_text(frame, version_05=False):
    kind = {18: ("MAP", "0x8002"), 19: ("SPAT", "0x8002"), 31: ("TIM", "0x8003")}
    msg_id = int.from_bytes(frame[:2], "big") & 0x7FFF if len(frame) >= 2 else 0
    name, psid = kind.get(msg_id, ("BSM", "0x20"))
    lines = [("Version", "0.5" if version_05 else "0.7"), ("Type", name), ("PSID", psid),
             ("Priority", "0"), ("TxMode", "CONT"), ("TxChannel", "172"), ("TxInterval", "0"),
             ("DeliveryStart", ""), ("DeliveryStop", ""), ("Signature", "False"),
             ("Encryption", "False"), ("Payload", frame.hex().upper())]
    sep = "\r\n\r\n" if version_05 else "\n"
    return sep.join(f"{k}={v}" for k, v in lines) + sep


dict_tokens = set()


def collect_tokens(v):
    if isinstance(v, dict):
        for k, x in v.items():
            dict_tokens.add(json.dumps(k) + ":")
            collect_tokens(x)
    elif isinstance(v, list):
        for x in v:
            collect_tokens(x)
    elif isinstance(v, str) and v and not all(c in "0123456789abcdefABCDEF" for c in v):
        if len(v) <= 40:
            dict_tokens.add(json.dumps(v))


def short(name):
    return hashlib.sha1(name.encode()).hexdigest()[:8] + "-" + name[:60]


vector_frames = []
if os.path.exists(vectors):
    for line in open(vectors):
        if not line.strip():
            continue
        v = json.loads(line)
        frame = from_hex(v["uper"])
        vector_frames.append((v["name"], frame))
        put("message_frame", "vector-" + short(v["name"]), frame)
        put("jer", "vector-" + short(v["name"]), json.dumps(v["jer"], separators=(",", ":")))
        # The same message with unknown extension additions (the codec's JER member for them).
        if isinstance(v["jer"].get("value"), dict):
            ext = dict(v["jer"])
            ext["value"] = dict(ext["value"], _extensions={
                "bitmapLength": 3, "additions": [[0, "00"], [2, "5a01"]]})
            put("jer", "vector-ext-" + short(v["name"]), json.dumps(ext, separators=(",", ":")))
        collect_tokens(v["jer"])
        put("envelope", "vector-unsecured-" + short(v["name"]), unsecured(frame))
        put("envelope", "vector-rsu-" + short(v["name"]) + ".txt", rsu_text(frame))
else:
    print(f"seed.sh: no {vectors}", file=sys.stderr)

frames_dir = os.path.join(shared, "corpus", "frames")
if os.path.isdir(frames_dir):
    frames = {}
    for f in sorted(os.listdir(frames_dir)):
        if f.endswith(".hex"):
            frames[f[:-4]] = from_hex(open(os.path.join(frames_dir, f)).read())
            put("message_frame", "frame-" + short(f[:-4]), frames[f[:-4]])
    jer_dir = os.path.join(shared, "corpus", "jer")
    for f in sorted(os.listdir(jer_dir)) if os.path.isdir(jer_dir) else []:
        if f.endswith(".json"):
            doc = json.load(open(os.path.join(jer_dir, f)))
            if doc.get("jer") is not None:
                put("jer", "oracle-" + short(f[:-5]), json.dumps(doc["jer"], separators=(",", ":")))
                collect_tokens(doc["jer"])
    wrapped_dir = os.path.join(shared, "corpus", "wrapped")
    signed_tail = None
    for f in sorted(os.listdir(wrapped_dir)) if os.path.isdir(wrapped_dir) else []:
        if f.endswith(".hex"):
            data = from_hex(open(os.path.join(wrapped_dir, f)).read())
            put("envelope", "wrapped-" + short(f[:-4]), data)
            # The signature and header after the frame of a signed envelope, to wrap the
            # vector frames as signed data too.
            inner = frames.get(f.split(".")[0])
            head = b"\x03\x81\x00\x40\x03\x80"
            if inner and data.startswith(head) and signed_tail is None:
                at = data.find(inner)
                if at > 0 and data[len(head):at] == coer_length(len(inner)):
                    signed_tail = data[at + len(inner):]
    if signed_tail is not None:
        for name, frame in vector_frames:
            put("envelope", "vector-signed-" + short(name),
                b"\x03\x81\x00\x40\x03\x80" + coer_length(len(frame)) + frame + signed_tail)
    rsu_dir = os.path.join(shared, "corpus", "rsu-text")
    for f in sorted(os.listdir(rsu_dir)) if os.path.isdir(rsu_dir) else []:
        put("envelope", "rsu-" + short(f), open(os.path.join(rsu_dir, f), "rb").read())
    if vector_frames:
        put("envelope", "vector-rsu05-" + short(vector_frames[0][0]) + ".txt",
            rsu_text(vector_frames[0][1], version_05=True))
else:
    print(f"seed.sh: {frames_dir} is missing: seeds from the project's vectors only",
          file=sys.stderr)

# The GNSS reader: the first 2 KB of each shared receiver log (NMEA, some with UBX and other
# binary between sentences).
gnss_dir = os.path.join(shared, "gnss", "logs")
if os.path.isdir(gnss_dir):
    for name in sorted(os.listdir(gnss_dir)):
        if name.endswith(".log"):
            with open(os.path.join(gnss_dir, name), "rb") as f:
                put("gnss", name, f.read(2048))

os.makedirs(corpus, exist_ok=True)
with open(os.path.join(corpus, "jer.dict"), "w") as out:
    out.write("# JER member names and identifiers (built by seed.sh)\n")
    for t in sorted(dict_tokens) + ['"_extensions":', '"bitmapLength":', '"additions":',
                                     '"value":', '"length":', "{", "}", "[", "]", "null", "true", "false"]:
        esc = "".join(chr(b) if 0x20 <= b < 0x7F and chr(b) not in '"\\' else
                      ("\\" + chr(b) if chr(b) in '"\\' else "\\x%02x" % b)
                      for b in t.encode())
        out.write(f'"{esc}"\n')
print("seed corpus: " + ", ".join(f"{t} {n}" for t, n in sorted(counts.items()))
      + f"; jer.dict {len(dict_tokens)} tokens")
PY
