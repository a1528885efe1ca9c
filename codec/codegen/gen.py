#!/usr/bin/env python3
"""Generates the Rust J2735 types of `codec/src/generated/` from the pycrate-compiled
J2735 2020 type model.

    PY=$(bash ../shared/oracle/setup.sh)     # pycrate 0.8.1
    $PY codec/codegen/gen.py                 # write codec/src/generated/
    $PY codec/codegen/gen.py --check         # exit 1 if the committed files differ

Options: --shared DIR (default: <repo>/../shared), --model FILE's directory is DIR/j2735.
Someone holding the SAE ASN.1 files makes the model with
`pycrate_asn1compile.py -i <dir of .asn files> -o j2735_2020` and puts it in DIR/j2735/.
"""
import argparse
import os
import subprocess
import sys
import tempfile

here = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, here)

import caps as caps_mod  # noqa: E402
import emit  # noqa: E402
import model as model_mod  # noqa: E402
import naming  # noqa: E402

REPO = os.path.dirname(os.path.dirname(here))
OUT = os.path.join(REPO, "codec", "src", "generated")

# Types re-exported at the crate root (the messages and what the OBU reads most).
REEXPORTS = {
    "MessageFrame": ["MessageFrame", "MessageFrameValue", "DSRCmsgID"],
    "MapData": ["MapData", "IntersectionGeometry", "RoadSegment", "GenericLane", "LaneAttributes",
                "LaneTypeAttributes", "LaneDirection", "Connection",
                "ConnectsToList"],
    "TravelerInformation": ["TravelerInformation", "TravelerDataFrame", "GeographicalPath",
                            "OffsetSystem", "NodeListLL", "TravelerDataFrameList"],
    "Common": ["Position3D", "Latitude", "Longitude", "Elevation", "NodeXY", "NodeSetXY",
               "NodeOffsetPointXY", "NodeAttributeSetXY", "NodeListXY", "ComputedLane", "LaneID", "LaneWidth", "SpeedLimitList",
               "RegulatorySpeedLimit", "SpeedLimitType", "Velocity", "HeadingSlice", "MsgCount",
               "MinuteOfTheYear", "DYear", "DescriptiveName", "IntersectionReferenceID",
               "RoadSegmentReferenceID", "Heading", "Speed"],
    "BasicSafetyMessage": ["BasicSafetyMessage"],
    "SPAT": ["SPAT"],
    "ITIS": ["ITIScodes", "ITIScodesAndText"],
}


def render(shared):
    modules = model_mod.load(shared)
    caps = caps_mod.Capacities(os.path.join(here, "capacities.toml"),
                               os.path.join(here, "capacities-firmware.toml"))
    model = model_mod.Model(modules, caps)
    em = emit.Emitter(model, caps)
    files = {}
    mods = sorted(modules, key=naming.module)
    for m in mods:
        files[naming.module(m) + ".rs"] = em.module_source(m)
    root = [emit.HEADER, "//! The generated J2735 2020 types, one module per ASN.1 module.\n",
            "#![allow(clippy::upper_case_acronyms, clippy::large_enum_variant, clippy::identity_op,\n"
            "    clippy::needless_borrow, clippy::match_single_binding)]\n"]
    files["capacities.rs"] = caps.capacities_module(emit.HEADER)
    root.append("pub mod capacities;")
    for m in mods:
        root.append(f"/// ASN.1 module `{m}`.\n#[allow(non_camel_case_types)]\npub mod {naming.module(m)};")
    root.append("")
    for m, names in REEXPORTS.items():
        have = {td.name for td in model.by_module[m]}
        missing = [n for n in names if n not in have]
        if missing:
            raise SystemExit(f"re-exports missing from {m}: {missing}")
        root.append(f"pub use {naming.module(m)}::{{{', '.join(names)}}};")
    files["mod.rs"] = "\n".join(root) + "\n"
    unused = caps.unused()
    if unused:
        raise SystemExit(f"capacities(-firmware).toml names keys that no type has: {unused}")
    return rustfmt(files)


def rustfmt(files):
    """The files as rustfmt (edition 2021, default style) writes them."""
    with tempfile.TemporaryDirectory() as tmp:
        paths = []
        for name, text in files.items():
            path = os.path.join(tmp, name)
            with open(path, "w") as f:
                f.write(text)
            paths.append(path)
        subprocess.run(["rustfmt", "--edition", "2021", *paths], check=True)
        return {name: open(os.path.join(tmp, name)).read() for name in files}


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--shared", default=os.path.join(REPO, "..", "shared"))
    ap.add_argument("--check", action="store_true", help="fail if the committed files differ")
    args = ap.parse_args()
    files = render(args.shared)
    if args.check:
        bad = []
        for name, text in files.items():
            path = os.path.join(OUT, name)
            if not os.path.exists(path) or open(path).read() != text:
                bad.append(name)
        extra = set(os.listdir(OUT)) - set(files) if os.path.isdir(OUT) else set()
        if bad or extra:
            print(f"generated code is stale: {sorted(bad) + sorted(extra)}; run codec/codegen/gen.py", file=sys.stderr)
            return 1
        print(f"generated code is up to date ({len(files)} files)")
        return 0
    os.makedirs(OUT, exist_ok=True)
    for name in os.listdir(OUT):
        if name.endswith(".rs") and name not in files:
            os.remove(os.path.join(OUT, name))
    for name, text in files.items():
        with open(os.path.join(OUT, name), "w") as f:
            f.write(text)
    print(f"wrote {len(files)} files to {os.path.relpath(OUT, REPO)}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
