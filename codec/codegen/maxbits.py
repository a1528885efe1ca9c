"""Largest UPER encoding of each type, in bits, for the no-heap storage (capacities) and for
heap storage (ASN.1 SIZE bounds only; `None` where the type does not bound it)."""


def nbits(span):
    """Bits of a constrained whole number whose range is 0..=span."""
    return span.bit_length()


def length_bits(lb, ub):
    """Bits of a constrained length determinant."""
    return 0 if lb == ub else nbits(ub - lb)


def open_bits(inner):
    """An open type holding `inner` bits: length determinant plus whole octets."""
    octets = max(1, -(-inner // 8))
    return (8 if octets < 128 else 16) + 8 * octets


UNKNOWN_INDEX = 1 + 8 + 16  # normally small number up to u16
EXT_BITMAP = 7 + 64  # normally small length (<= 64) and the bit-map


def ext_bits(octets):
    """Extension additions kept in `octets` octets of records (4 octets of header each)."""
    return EXT_BITMAP + 8 * octets + 16 * (octets // 4 + 1)


class MaxBits:
    def __init__(self, caps, fw=False):
        self.caps = caps
        self.fw = fw  # the firmware capacity profile
        self.memo = {}

    def of(self, td, heap):
        key = (id(td), heap)
        if key not in self.memo:
            self.memo[key] = getattr(self, "k_" + td.kind)(td, heap)
        return self.memo[key]

    def ref(self, ref, heap):
        if ref.builtin == "bool":
            return 1
        if ref.builtin:
            return 0
        return self.of(ref.typedef, heap)

    def k_alias(self, td, heap):
        return self.ref(td.target, heap)

    def k_int(self, td, heap):
        return nbits(td.ub - td.lb)

    def k_enum(self, td, heap):
        root = nbits(len(td.items) - 1)
        return 1 + max(root, UNKNOWN_INDEX) if td.extensible else root

    def sized(self, td, unit_bits, count):
        """Length determinant plus `count` units; extensible sizes may use the long form."""
        if count is None:
            return None
        root = length_bits(td.lb, td.ub) if td.ub is not None and td.ub < 65536 else 16
        if td.extensible:
            root = 1 + max(root, 16)
        return root + unit_bits * count

    def k_bits(self, td, heap):
        if td.extensible:
            return None if heap else self.sized(td, 1, 8 * self.caps.bits_octets(td, self.fw))
        return self.sized(td, 1, td.ub)

    def k_fixed_octets(self, td, heap):
        return 8 * td.lb

    def k_octets(self, td, heap):
        return self.sized(td, 8, td.ub if heap else self.caps.count(td, self.fw))

    def k_ia5(self, td, heap):
        return self.sized(td, 7, td.ub if heap else self.caps.count(td, self.fw))

    def k_seq_of(self, td, heap):
        item = self.ref(td.item, heap)
        if item is None:
            return None
        return self.sized(td, item, td.ub if heap else self.caps.count(td, self.fw))

    def k_seq(self, td, heap):
        total = len([f for f in td.fields if f.optional])
        for f in td.fields:
            b = self.ref(f.ref, heap)
            if b is None:
                return None
            total += b
        if td.extensible:
            if heap:
                return None
            total += 1 + ext_bits(self.caps.ext_octets(td, self.fw))
        return total

    def k_choice(self, td, heap):
        alts = [self.ref(a.ref, heap) for a in td.alts]
        if any(a is None for a in alts):
            return None
        best = nbits(len(alts) - 1) + max(alts)
        if not td.extensible:
            return best
        if heap:
            return None
        return 1 + max(best, UNKNOWN_INDEX + open_bits(8 * self.caps.unknown_octets(td, self.fw)))

    def k_open(self, td, heap):
        if heap:
            return None
        inner = [self.ref(r, heap) for _, _, r in td.variants]
        if any(i is None for i in inner):
            return None
        known = max([open_bits(i) for i in inner], default=0)
        unknown = open_bits(8 * self.caps.unknown_octets(td, self.fw))
        return self.ref(td.id_ref, heap) + max(known, unknown)
