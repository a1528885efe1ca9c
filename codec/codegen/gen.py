#!/usr/bin/env python3
"""Generates the Rust J2735 types of `codec/src/msg/` (module `j2735::msg`) from the
pycrate-compiled J2735 2020 type model.

    PY=$(bash ../shared/oracle/setup.sh)     # pycrate 0.8.1
    $PY codec/codegen/gen.py                 # write codec/src/msg/
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
OUT = os.path.join(REPO, "codec", "src", "msg")


def render(shared):
    modules = model_mod.load(shared)
    caps = caps_mod.Capacities(os.path.join(here, "capacities.toml"),
                               os.path.join(here, "capacities-firmware.toml"))
    model = model_mod.Model(modules, caps)
    em = emit.Emitter(model, caps)
    files = {}
    mods = sorted(modules, key=naming.module)
    for m in mods:
        files["/".join(naming.module_path(m)) + ".rs"] = em.module_source(m)
    files["capacities.rs"] = caps.capacities_module(emit.HEADER)
    declare = lambda m: f"/// ASN.1 module `{m}`.\n#[allow(non_camel_case_types)]\npub mod {naming.module(m)};"  # noqa: E731
    root = [emit.HEADER,
            "//! The J2735 2020 types, one module per ASN.1 module (`map_data::MapData`,\n"
            "//! `traveler_information::TravelerInformation`, `common::Position3D`, ...), generated\n"
            "//! from the standard's type model; the test messages' modules are in [`test`](mod@test).\n"
            "//! The most used messages are re-exported at the crate root.\n",
            "#![allow(clippy::upper_case_acronyms, clippy::large_enum_variant, clippy::identity_op,\n"
            "    clippy::needless_borrow, clippy::match_single_binding)]\n",
            "pub mod capacities;"]
    root += [declare(m) for m in mods if not naming.is_test_module(m)]
    root.append("pub mod test;")
    files["mod.rs"] = "\n".join(root) + "\n"
    test = [emit.HEADER,
            "//! The test messages (`messageId` 240..255, `TEST00`..`TEST15`): one ASN.1 module each.\n"]
    test += [declare(m) for m in mods if naming.is_test_module(m)]
    files["test/mod.rs"] = "\n".join(test) + "\n"
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
            os.makedirs(os.path.dirname(path), exist_ok=True)
            with open(path, "w") as f:
                f.write(text)
            paths.append(path)
        subprocess.run(["rustfmt", "--edition", "2021", *paths], check=True)
        return {name: open(os.path.join(tmp, name)).read() for name in files}


def existing():
    """The files under OUT, as paths relative to it (`test/mod.rs`)."""
    out = []
    for folder, _, names in os.walk(OUT):
        out += [os.path.relpath(os.path.join(folder, n), OUT).replace(os.sep, "/") for n in names]
    return out


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
        extra = set(existing()) - set(files)
        if bad or extra:
            print(f"generated code is stale: {sorted(bad) + sorted(extra)}; run codec/codegen/gen.py", file=sys.stderr)
            return 1
        print(f"generated code is up to date ({len(files)} files)")
        return 0
    for name in existing():
        if name.endswith(".rs") and name not in files:
            os.remove(os.path.join(OUT, name))
    for name, text in files.items():
        os.makedirs(os.path.dirname(os.path.join(OUT, name)), exist_ok=True)
        with open(os.path.join(OUT, name), "w") as f:
            f.write(text)
    print(f"wrote {len(files)} files to {os.path.relpath(OUT, REPO)}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
