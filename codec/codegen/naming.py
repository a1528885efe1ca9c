"""Rust names for ASN.1 names.

Types and variants keep the 2020 ASN.1 spelling with hyphens removed and each part
capitalised (`LaneAttributes-Vehicle` -> `LaneAttributesVehicle`, `node-XY1` -> `NodeXY1`).
Fields and modules are snake case, with J2735's acronym runs kept whole
(`laneID` -> `lane_id`, `BSMcoreData` -> `bsm_core_data`, `NMEAcorrections` -> `nmea_corrections`).
"""
import re

RUST_KEYWORDS = {
    "as", "break", "const", "continue", "crate", "else", "enum", "extern", "false", "fn", "for",
    "if", "impl", "in", "let", "loop", "match", "mod", "move", "mut", "pub", "ref", "return",
    "self", "Self", "static", "struct", "super", "trait", "true", "type", "unsafe", "use", "where",
    "while", "async", "await", "dyn", "abstract", "become", "box", "do", "final", "macro",
    "override", "priv", "typeof", "unsized", "virtual", "yield", "try", "gen",
}


def words(name):
    """Splits an ASN.1 identifier into lowercase words."""
    out = []
    for part in re.split(r"[-_]", name):
        # an upper-case run followed by lower case stays one word when it is 2+ letters
        # (J2735 writes acronyms that way: DSRCmsgID, ITIScodes); a single capital starts a word.
        tokens = re.findall(r"[A-Z]{2,}(?=[a-z])|[A-Z]+(?![a-z])|[A-Z]?[a-z]+|[0-9]+[a-z]*", part)
        merged = []
        for t in tokens:
            if t[0].isdigit() and merged:
                merged[-1] += t
            else:
                merged.append(t)
        out.extend(w.lower() for w in merged)
    return out


def snake(name):
    """`laneID` -> `lane_id`; keywords get a raw-identifier prefix."""
    s = "_".join(words(name))
    return "r#" + s if s in RUST_KEYWORDS else s


def camel(name):
    """`LaneAttributes-Vehicle` -> `LaneAttributesVehicle`, `node-XY1` -> `NodeXY1`."""
    name = re.sub(r"(?<=[0-9])-(?=[0-9])", "_", name)  # prec0-1deg -> Prec0_1deg
    parts = [p for p in re.split(r"-", name) if p]
    s = "".join(p[0].upper() + p[1:] for p in parts)
    if s[0].isdigit():
        s = "V" + s
    return s


def shout(name):
    """`lowBeamHeadlightsOn` -> `LOW_BEAM_HEADLIGHTS_ON`."""
    s = "_".join(words(name)).upper()
    return "V_" + s if s[0].isdigit() else s


def module(name):
    """ASN.1 module name -> Rust module name (`MessageFrame` -> `message_frame`)."""
    return "_".join(words(name))


def is_test_module(name):
    """Whether the ASN.1 module is one of the test messages' (`TestMessage00`..`15`)."""
    return re.fullmatch(r"TestMessage[0-9]{2}", name) is not None


def module_path(name):
    """The Rust module path of an ASN.1 module under `crate::msg`, as a list: the test
    messages' modules are in `msg::test` (`["test", "test_message00"]`), the others at
    the top (`["map_data"]`)."""
    return ["test", module(name)] if is_test_module(name) else [module(name)]


def to_msg_root(name):
    """The relative path from the Rust module of ASN.1 module `name` to `crate::msg`
    (`super::` or `super::super::`)."""
    return "super::" * len(module_path(name))


if __name__ == "__main__":
    for n in ["laneID", "BSMcoreData", "DSRCmsgID", "NMEAcorrections", "node-XY1", "partII-Id",
              "sspTimRights", "scaleXaxis", "TestMessage00", "AddGrpB", "SPAT", "type", "regExtValue",
              "ITIScodesAndText", "rotateXY", "dWidth", "node-LatLon"]:
        print(n, snake(n), camel(n), shout(n))


# The short names SAE J2735 (2020, section 5 and Annex) gives its messages, by ASN.1 type;
# RSU records (`Type=`), logs and counters use these, with this one spelling. The test
# messages 240..255 are `TEST00`..`TEST15`.
MESSAGE_SHORT_NAMES = {
    "MapData": "MAP",
    "SPAT": "SPAT",
    "BasicSafetyMessage": "BSM",
    "CommonSafetyRequest": "CSR",
    "EmergencyVehicleAlert": "EVA",
    "IntersectionCollision": "ICA",
    "NMEAcorrections": "NMEA",
    "ProbeDataManagement": "PDM",
    "ProbeVehicleData": "PVD",
    "RoadSideAlert": "RSA",
    "RTCMcorrections": "RTCM",
    "SignalRequestMessage": "SRM",
    "SignalStatusMessage": "SSM",
    "TravelerInformation": "TIM",
    "PersonalSafetyMessage": "PSM",
}


def message_short_name(type_name):
    """The standard's short name of the message whose ASN.1 type is `type_name`."""
    m = re.fullmatch(r"TestMessage([0-9]{2})", type_name)
    if m:
        return "TEST" + m.group(1)
    if type_name not in MESSAGE_SHORT_NAMES:
        raise SystemExit(f"no short name for message type {type_name}: add it to naming.py")
    return MESSAGE_SHORT_NAMES[type_name]
