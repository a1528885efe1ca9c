"""Walks the pycrate-compiled J2735 type model into a small intermediate representation.

Every ASN.1 type that needs a Rust type becomes a `TypeDef`: the named types of each module,
and the inline (anonymous) types of their components, named after their parent
(`IntersectionGeometry.regional` -> `IntersectionGeometryRegional`). A SEQUENCE whose only
components are a class-constrained id and the open type it selects (`RegionalExtension`,
`PartIIcontent`) becomes an `open` type: an enum over the object set plus an `Unknown` arm.
Identical object sets share one enum.

Each TypeDef has a `key` (`Module.Type`, or `Module.Type.field...` for an inline type) that
names it in the capacity configuration and in decode errors.
"""
import sys

import naming


class Ref:
    """A reference to a Rust type: a generated TypeDef or a runtime builtin."""

    def __init__(self, typedef=None, builtin=None):
        self.typedef, self.builtin = typedef, builtin

    def rust(self, from_module):
        if self.builtin:
            return self.builtin
        t = self.typedef
        if t.module == from_module:
            return t.name
        return f"{naming.to_msg_root(from_module)}{'::'.join(naming.module_path(t.module))}::{t.name}"


BOOL = Ref(builtin="bool")
NULL = Ref(builtin="crate::uper::Null")


class Field:
    """A SEQUENCE component (or a CHOICE alternative): ASN.1 name, Rust name, type, optional."""

    def __init__(self, asn, ref, optional=False):
        self.asn, self.ref, self.optional = asn, ref, optional
        self.rust = naming.snake(asn)
        self.variant = naming.camel(asn)


class TypeDef:
    """One generated Rust type."""

    def __init__(self, kind, module, name, asn, **attrs):
        self.kind, self.module, self.name, self.asn = kind, module, name, asn
        self.key = f"{module}.{asn}"
        self.__dict__.update(attrs)

    def __repr__(self):
        return f"<{self.kind} {self.key} -> {self.name}>"


def size_of(obj):
    """(lb, ub, extensible) of a SIZE constraint; ub None when unbounded."""
    c = obj._const_sz
    if c is None:
        return (0, None, False)
    (r,) = c.root
    lb, ub = (r, r) if isinstance(r, int) else (r.lb, r.ub)
    return (lb, ub, c.ext is not None)


def int_range(obj):
    (r,) = obj._const_val.root
    if obj._const_val.ext is not None:
        raise SystemExit(f"extensible INTEGER not supported yet: {obj._name}")
    return (r, r) if isinstance(r, int) else (r.lb, r.ub)


class Model:
    """The whole J2735 model: modules in order, and every TypeDef of each."""

    def __init__(self, modules, config):
        self.G = modules
        self.config = config
        self.by_module = {m: [] for m in modules}
        self.named = {}  # (module, asn name) -> TypeDef
        self.names = {m: set() for m in modules}
        self.open_sets = {}  # object-set signature -> TypeDef
        self.registry = {}  # id(pycrate object) -> Ref, for tools that walk values
        for m in modules:
            for tn in modules[m]["_type_"]:
                obj = modules[m][tn]
                if obj.TYPE != "CLASS" and not getattr(obj, "_param", None):
                    self.named_def(obj)

    # -- names -------------------------------------------------------------------------------
    def claim(self, module, name):
        base, n = name, 2
        while name in self.names[module]:
            name, n = f"{base}{n}", n + 1
        self.names[module].add(name)
        return name

    def add(self, td):
        self.by_module[td.module].append(td)
        return td

    # -- references --------------------------------------------------------------------------
    def is_named(self, t):
        mod = self.G.get(getattr(t, "_mod", None))
        return (mod is not None and t._name in mod["_type_"] and mod[t._name] is t
                and t.TYPE != "CLASS" and not getattr(t, "_param", None))

    def named_target(self, obj):
        t = getattr(obj, "_tr", None)
        while t is not None:
            if self.is_named(t):
                return t
            t = getattr(t, "_tr", None)
        return None

    @staticmethod
    def same_constraints(a, b):
        if a.TYPE != b.TYPE:
            return False
        for attr in ("_const_val", "_const_sz"):
            if repr(getattr(a, attr, None)) != repr(getattr(b, attr, None)):
                return False
        return True

    def resolve(self, obj, module, asn, rust, owner):
        """The Ref for a component `obj` found at `asn` (path) inside named type `owner`."""
        ref = self._resolve(obj, module, asn, rust, owner)
        self.registry[id(obj)] = ref
        return ref

    def _resolve(self, obj, module, asn, rust, owner):
        target = self.named_target(obj)
        if target is not None and self.same_constraints(obj, target):
            return Ref(self.named_def(target))
        if obj.TYPE == "BOOLEAN":
            return BOOL
        if obj.TYPE == "NULL":
            return NULL
        return Ref(self.define(obj, module, asn, self.claim(module, rust), owner))

    def named_def(self, obj):
        key = (obj._mod, obj._name)
        if key not in self.named:
            name = self.claim(obj._mod, naming.camel(obj._name))
            self.named[key] = None  # guards against recursion while defining
            target = self.named_target(obj)
            if target is not None and self.same_constraints(obj, target):
                td = self.add(TypeDef("alias", obj._mod, name, obj._name, target=Ref(self.named_def(target))))
            elif obj.TYPE == "BOOLEAN":
                td = self.add(TypeDef("alias", obj._mod, name, obj._name, target=BOOL))
            else:
                td = self.define(obj, obj._mod, obj._name, name, name)
            self.named[key] = td
            self.registry[id(obj)] = Ref(td)
        if self.named[key] is None:
            raise SystemExit(f"recursive type {key}: not supported")
        return self.named[key]

    # -- definitions -------------------------------------------------------------------------
    def define(self, obj, module, asn, name, owner):
        T = obj.TYPE
        mk = lambda kind, **kw: self.add(TypeDef(kind, module, name, asn, **kw))  # noqa: E731
        if T == "INTEGER":
            lb, ub = int_range(obj)
            return mk("int", lb=lb, ub=ub)
        if T == "ENUMERATED":
            if obj._ext:
                raise SystemExit(f"ENUMERATED extension additions not supported: {asn}")
            items = sorted(((n, obj._cont[n]) for n in obj._root), key=lambda it: it[1])
            return mk("enum", items=items, extensible=obj._ext is not None)
        if T == "BIT STRING":
            lb, ub, ext = size_of(obj)
            named = sorted(obj._cont.items(), key=lambda it: it[1]) if obj._cont else []
            return mk("bits", lb=lb, ub=ub, extensible=ext, named=named)
        if T == "OCTET STRING":
            lb, ub, ext = size_of(obj)
            kind = "fixed_octets" if lb == ub and not ext else "octets"
            return mk(kind, lb=lb, ub=ub, extensible=ext)
        if T == "IA5String":
            if getattr(obj, "_const_alpha", None) is not None:
                raise SystemExit(f"permitted alphabet not supported yet: {asn}")
            lb, ub, ext = size_of(obj)
            return mk("ia5", lb=lb, ub=ub, extensible=ext)
        if T == "SEQUENCE OF":
            lb, ub, ext = size_of(obj)
            td = mk("seq_of", lb=lb, ub=ub, extensible=ext, item=None)
            td.item = self.resolve(obj._cont, module, asn + "[]", name + "Item", owner)
            return td
        if T == "SEQUENCE":
            return self.define_sequence(obj, module, asn, name, owner)
        if T == "CHOICE":
            if obj._ext:
                raise SystemExit(f"CHOICE extension additions not supported: {asn}")
            td = mk("choice", alts=[], extensible=obj._ext is not None)
            for an in obj._root:
                comp = obj._cont[an]
                td.alts.append(Field(an, self.resolve(comp, module, f"{asn}.{an}", name + naming.camel(an), owner)))
            return td
        raise SystemExit(f"unsupported ASN.1 type {T} at {module}.{asn}")

    @staticmethod
    def open_pair(obj):
        """(id component name, open component name) pairs of a SEQUENCE."""
        pairs = []
        for cn, comp in obj._cont.items():
            if comp.TYPE == "OPEN_TYPE":
                at = comp._const_tab_at
                if not at or at[0] != "..":
                    raise SystemExit(f"open type without a sibling id: {cn}")
                pairs.append((at[1], cn))
        return pairs

    def define_sequence(self, obj, module, asn, name, owner):
        if obj._ext:
            raise SystemExit(f"SEQUENCE extension additions not supported yet: {asn}")
        pairs = self.open_pair(obj)
        comps = list(obj._cont)
        if pairs and len(comps) == 2 and obj._ext is None and not obj._root_opt:
            (id_name, open_name), = pairs
            return self.define_open(obj, module, asn, name, owner, id_name, open_name, collapse=True)
        td = self.add(TypeDef("seq", module, name, asn, fields=[], extensible=obj._ext is not None))
        ids = {i for i, _ in pairs}
        opens = {o: i for i, o in pairs}
        for cn in comps:
            if cn in ids:
                continue  # an id folded into its open type
            comp = obj._cont[cn]
            opt = cn in obj._root_opt
            if cn in opens:
                ref = Ref(self.define_open(obj, module, f"{asn}.{cn}", self.claim(module, name + naming.camel(cn)),
                                           owner, opens[cn], cn, collapse=False))
                fld = Field(cn, ref, opt)
                fld.id_asn = opens[cn]
            else:
                fld = Field(cn, self.resolve(comp, module, f"{asn}.{cn}", name + naming.camel(cn), owner), opt)
            td.fields.append(fld)
        return td

    def define_open(self, obj, module, asn, name, owner, id_name, open_name, collapse):
        id_comp, open_comp = obj._cont[id_name], obj._cont[open_name]
        id_ref = self.resolve(id_comp, module, f"{asn}.{id_name}", name + naming.camel(id_name), owner)
        entries = []
        for d in open_comp._const_tab._val.root:
            t = d["Type"]
            target = self.named_target(t) or t
            entries.append((d["id"], Ref(self.named_def(target))))
            self.registry[id(t)] = entries[-1][1]
        entries.sort(key=lambda e: e[0])
        by_module = open_name == "regExtValue"
        # Each regional-extension site gets its own type (named after its owner), so that its
        # unknown-content capacity can be set on its own; other object sets are shared.
        site = owner if by_module else None
        sig = (site, id_ref.rust(""), tuple((i, r.typedef.key) for i, r in entries))
        if sig in self.open_sets:
            td = self.open_sets[sig]
            self.names[module].discard(name)
            return td
        if collapse and by_module:
            self.names[module].discard(name)
            name = self.claim(module, "Reg" + owner)
            asn = name
        elif collapse and getattr(obj, "_tr", None) is not None:
            self.names[module].discard(name)
            name = self.claim(module, naming.camel(obj._tr._name))
            asn = obj._tr._name
        variants = []
        for i, r in entries:
            v = naming.camel(r.typedef.module) if by_module else r.typedef.name
            variants.append((i, v, r))
        td = self.add(TypeDef("open", module, name, asn, id_ref=id_ref, id_asn=id_name,
                              open_asn=open_name, variants=variants))
        self.open_sets[sig] = td
        return td


def load(shared_dir):
    sys.path.insert(0, f"{shared_dir}/j2735")
    import j2735_2020  # noqa: F401  (registers the modules with pycrate)
    from pycrate_asn1rt.glob import GLOBAL
    return dict(GLOBAL.MOD)
