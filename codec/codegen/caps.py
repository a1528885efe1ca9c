"""The generator's configuration: no-heap capacities per type key, and named sentinel values.

See `capacities.toml` for the format. A capacity key is a TypeDef key (`Module.Type` or
`Module.Type.field`), with `:ext` for a SEQUENCE's unknown extension additions and `:unknown`
for the raw content of an unknown CHOICE alternative or open-type value.
"""
import tomllib

import naming


class Capacities:
    def __init__(self, path):
        with open(path, "rb") as f:
            cfg = tomllib.load(f)
        self.defaults = cfg["defaults"]
        self.capacity = cfg.get("capacity", {})
        self.sentinel = cfg.get("sentinel", {})
        self.used = set()

    def get(self, key, default):
        if key in self.capacity:
            self.used.add(key)
            return self.capacity[key]
        return default

    def count(self, td):
        """Items (SEQUENCE OF), octets (OCTET STRING) or characters (IA5String)."""
        kind = {"seq_of": "seq_of", "octets": "octets", "ia5": "ia5"}[td.kind]
        if td.kind == "seq_of" and td.item.typedef and getattr(td.item.typedef, "open_asn", "") == "regExtValue":
            kind = "regional"
        default = self.defaults[kind] if td.ub is None else min(td.ub, self.defaults[kind])
        return max(td.lb, self.get(td.key, default))

    def bits_octets(self, td):
        """Octets of storage for a BIT STRING."""
        root = -(-td.ub // 8)
        if not td.extensible:
            return root
        return max(root, self.get(td.key, self.defaults["bits_extensible_octets"]))

    def ext_octets(self, td):
        return self.get(td.key + ":ext", self.defaults["extension_octets"])

    def unknown_octets(self, td):
        default = self.defaults["unknown_open_octets" if td.kind == "open" else "unknown_choice_octets"]
        return self.get(td.key + ":unknown", default)

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
        return sorted(set(self.capacity) | set(self.sentinel)) and sorted(
            (set(self.capacity) | set(self.sentinel)) - self.used)


__all__ = ["Capacities", "naming"]
