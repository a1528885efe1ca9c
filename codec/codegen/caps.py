"""The generator's configuration: no-heap capacities per type key, and named sentinel values.

See `capacities.toml` for the format. A capacity key is a TypeDef key (`Module.Type` or
`Module.Type.field`), with `:ext` for a SEQUENCE's unknown extension additions and `:unknown`
for the raw content of an unknown CHOICE alternative or open-type value.

A second file, the firmware profile (`capacities-firmware.toml`), overrides some `[capacity]`
keys for the crate feature `firmware-capacities`. A capacity that differs between the two
profiles becomes a named const of the generated `capacities` module (one value per profile,
chosen by `cfg`); the generated types name the const instead of a literal.
"""
import re
import tomllib

import naming


FEATURE = "firmware-capacities"


def const_name(key):
    """`MapData.LaneList` -> `MAP_DATA_LANE_LIST`, `MapData.MapData:ext` -> `MAP_DATA_MAP_DATA_EXT`."""
    parts = re.split(r"[.:-]", key)
    return "_".join(re.sub(r"(?<=[a-z])(?=[A-Z])", "_", p).upper() for p in parts)


class Capacities:
    def __init__(self, path, firmware_path=None):
        with open(path, "rb") as f:
            cfg = tomllib.load(f)
        self.defaults = cfg["defaults"]
        self.capacity = cfg.get("capacity", {})
        self.sentinel = cfg.get("sentinel", {})
        self.inline_items = cfg.get("inline", {})
        boxed = cfg.get("boxed", {})
        self.boxed = set(boxed.get("members", []))
        self.boxed_alternatives = set(boxed.get("alternatives", []))
        self.boxed_open = set(boxed.get("open", []))
        self.open_in_place = set(boxed.get("open_in_place", []))
        self.firmware = {}
        if firmware_path:
            with open(firmware_path, "rb") as f:
                fw = tomllib.load(f)
            if set(fw) - {"capacity"}:
                raise SystemExit(f"{firmware_path}: only [capacity] may be overridden")
            self.firmware = fw.get("capacity", {})
        self.used = set()
        self.used_firmware = set()
        self.consts = {}  # const name -> (key, default value, firmware value)

    def get(self, key, default, fw=False):
        if fw and key in self.firmware:
            self.used_firmware.add(key)
            return self.firmware[key]
        if key in self.capacity:
            self.used.add(key)
            return self.capacity[key]
        return default

    def expr(self, method, td, suffix=""):
        """Rust expression of a capacity: a literal when both profiles agree, else the name of
        the generated const (registered here) that `cfg` sets per profile."""
        a, b = getattr(self, method)(td), getattr(self, method)(td, fw=True)
        if a == b:
            return str(a)
        name = const_name(td.key + suffix)
        self.consts[name] = (td.key + suffix, a, b)
        return f"{{ {naming.to_msg_root(td.module)}capacities::{name} }}"

    def capacities_module(self, header):
        """Source of the generated `capacities` module."""
        out = [header, "//! No-heap capacities that differ between the default profile and the firmware\n"
               f"//! profile (feature `{FEATURE}`, `codec/codegen/capacities-firmware.toml`).\n"]
        for name, (key, a, b) in sorted(self.consts.items()):
            for value, cfg in ((a, f"not(feature = \"{FEATURE}\")"), (b, f"feature = \"{FEATURE}\"")):
                out.append(f"/// Capacity of `{key}` (default {a}, firmware {b}).\n"
                           f"#[cfg({cfg})]\npub const {name}: usize = {value};")
        return "\n".join(out) + "\n"

    def count(self, td, fw=False):
        """Items (SEQUENCE OF), octets (OCTET STRING) or characters (IA5String)."""
        kind = {"seq_of": "seq_of", "octets": "octets", "ia5": "ia5"}[td.kind]
        if td.kind == "seq_of" and td.item.typedef and getattr(td.item.typedef, "open_asn", "") == "regExtValue":
            kind = "regional"
        default = self.defaults[kind] if td.ub is None else min(td.ub, self.defaults[kind])
        return max(td.lb, self.get(td.key, default, fw))

    def inline(self, td):
        """Items a SEQUENCE OF keeps inside the value before it allocates (feature `alloc`;
        0: all on the heap). At most the list's upper bound and 255 (the inline length is a
        `u8`)."""
        n = self.inline_items.get(td.key, 0)
        if n:
            self.used.add(td.key)
        limit = min(255, td.ub if td.ub is not None else 255)
        if not 0 <= n <= limit:
            raise SystemExit(f"[inline] {td.key} = {n} outside 0..{limit}")
        return n

    def is_boxed(self, td, field):
        """Whether a SEQUENCE member is kept in a `uper::Boxed` (on the heap with `alloc`)."""
        key = f"{td.key}.{field.asn}"
        if key in self.boxed:
            self.used.add(key)
            return True
        return False

    def is_boxed_alternative(self, td, alt):
        """Whether a CHOICE alternative's value is kept in a `uper::Boxed`."""
        key = f"{td.key}.{alt.asn}"
        if key in self.boxed_alternatives:
            self.used.add(key)
            return True
        return False

    def is_boxed_open(self, td, asn):
        """Whether an open type's value of ASN.1 type `asn` (one of its known ids) is kept in
        a `uper::Boxed`: all of them for an open type named in `open`, except the types named
        `Key:Type` in `open_in_place`."""
        if td.key not in self.boxed_open:
            return False
        self.used.add(td.key)
        key = f"{td.key}:{asn}"
        if key in self.open_in_place:
            self.used.add(key)
            return False
        return True

    def bits_octets(self, td, fw=False):
        """Octets of storage for a BIT STRING."""
        root = -(-td.ub // 8)
        if not td.extensible:
            return root
        return max(root, self.get(td.key, self.defaults["bits_extensible_octets"]))

    def ext_octets(self, td, fw=False):
        return self.get(td.key + ":ext", self.defaults["extension_octets"], fw)

    def unknown_octets(self, td, fw=False):
        default = self.defaults["unknown_open_octets" if td.kind == "open" else "unknown_choice_octets"]
        return self.get(td.key + ":unknown", default, fw)

    def sentinels(self, td):
        table = self.sentinel.get(td.key, {})
        if table:
            self.used.add(td.key)
        out = []
        for cname, (value, doc) in table.items():
            if not td.lb <= value <= td.ub:
                raise SystemExit(f"sentinel {td.key}.{cname} = {value} outside {td.lb}..{td.ub}")
            out.append((cname, value, doc))
        return out

    def unused(self):
        named = (set(self.capacity) | set(self.sentinel) | set(self.inline_items) | self.boxed
                 | self.boxed_alternatives | self.boxed_open | self.open_in_place)
        return sorted(named - self.used) + sorted(set(self.firmware) - self.used_firmware)


__all__ = ["Capacities", "naming"]
