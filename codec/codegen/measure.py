#!/usr/bin/env python3
"""Measures, over the conformance corpus, the largest count each capacity key needs, using the
independent pycrate decoder (not our own). Prints the keys whose need exceeds the configured
default, as lines for capacities.toml.

    $(bash ../shared/oracle/setup.sh) codec/codegen/measure.py [--all]
        [--vectors codec/tests/vectors/oracle_vectors.jsonl] [--firmware]

`--vectors` measures the frames (field `uper`) of a JSON-lines file instead of the corpus;
`--firmware` compares with the firmware profile (capacities-firmware.toml).
"""
import json
import argparse
import glob
import os
import sys

here = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, here)
import caps as caps_mod  # noqa: E402
import model as model_mod  # noqa: E402

REPO = os.path.dirname(os.path.dirname(here))


class Walker:
    def __init__(self, model):
        self.model = model
        self.need = {}

    def note(self, key, n):
        self.need[key] = max(self.need.get(key, 0), n)

    def walk(self, td, obj, val):
        while td.kind == "alias":
            if td.target.builtin:
                return
            td = td.target.typedef
        k = td.kind
        if k in ("seq_of",):
            self.note(td.key, len(val))
            ref = td.item
            if ref.typedef:
                for v in val:
                    self.walk(ref.typedef, obj._cont, v)
        elif k in ("octets", "ia5"):
            self.note(td.key, len(val))
        elif k == "bits" and td.extensible:
            self.note(td.key, -(-val[1] // 8))
        elif k == "seq":
            for f in td.fields:
                if getattr(f, "id_asn", None):
                    if f.asn in val:
                        self.walk_open(f.ref.typedef, obj, val[f.id_asn], val[f.asn])
                elif f.asn in val and f.ref.typedef:
                    self.walk(f.ref.typedef, obj._cont[f.asn], val[f.asn])
        elif k == "choice":
            name, v = val
            alt = next(a for a in td.alts if a.asn == name)
            if alt.ref.typedef:
                self.walk(alt.ref.typedef, obj._cont[name], v)
        elif k == "open":
            self.walk_open(td, obj, val[td.id_asn], val[td.open_asn])

    def walk_open(self, td, obj, ident, val):
        name, v = val
        if isinstance(v, (bytes, bytearray)) and name.startswith("_unk"):
            self.note(td.key + ":unknown", len(v))
            return
        open_obj = obj._cont[td.open_asn]
        for d in open_obj._const_tab._val.root:
            if d["id"] == ident:
                ref = next(r for i, _, r in td.variants if i == ident)
                self.walk(ref.typedef, d["Type"], v)
                return


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--shared", default=os.path.join(REPO, "..", "shared"))
    ap.add_argument("--all", action="store_true", help="print every key, not only those over the default")
    ap.add_argument("--vectors", help="JSON lines with a `uper` hex field, instead of the corpus")
    ap.add_argument("--firmware", action="store_true", help="compare with the firmware profile")
    args = ap.parse_args()
    modules = model_mod.load(args.shared)
    caps = caps_mod.Capacities(os.path.join(here, "capacities.toml"),
                               os.path.join(here, "capacities-firmware.toml"))
    model = model_mod.Model(modules, caps)
    MF = modules["MessageFrame"]["MessageFrame"]
    top = model.named[("MessageFrame", "MessageFrame")]
    w = Walker(model)
    if args.vectors:
        frames = [json.loads(line)["uper"] for line in open(args.vectors) if line.strip()]
    else:
        frames = [open(p).read().strip() for p in sorted(glob.glob(os.path.join(args.shared, "corpus", "frames", "*.hex")))]
    for hex_frame in frames:
        MF.from_uper(bytes.fromhex(hex_frame))
        w.walk(top, MF, MF._val)
    by_key = {td.key: td for tds in model.by_module.values() for td in tds}
    for key, n in sorted(w.need.items()):
        base = key.split(":")[0]
        td = by_key[base]
        if key.endswith(":unknown"):
            default = caps.unknown_octets(td, args.firmware)
        elif key.endswith(":ext"):
            default = caps.ext_octets(td, args.firmware)
        elif td.kind == "bits":
            default = caps.bits_octets(td)
        else:
            default = caps.count(td, args.firmware)
        if args.all or n > default:
            print(f'"{key}" = {n}    # default {default}')


if __name__ == "__main__":
    main()
