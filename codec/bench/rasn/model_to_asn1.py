"""Prints the pycrate-compiled J2735 2020 type model back as ASN.1 modules, for rasn-compiler.

The SAE ASN.1 text is not in this repository (SAE's copyright); `../shared/j2735/j2735_2020.py`
is its pycrate-compiled model (types, constraints, extension markers, object sets). This script
walks that model and writes an equivalent ASN.1 notation, one `<Module>.asn` file per module,
into the directory given on the command line (it must lie outside the repository: the written
files are SAE's type definitions and are never committed):

    PY=$(bash ../shared/oracle/setup.sh)
    $PY codec/bench/rasn/model_to_asn1.py /tmp/j2735-asn1 [../shared/j2735]

What is written is equivalent for PER, not a copy of SAE's text:
- every module is `DEFINITIONS AUTOMATIC TAGS` and components keep their order (the model's
  tags are the automatic ones, checked below), so CHOICE indexes are unchanged;
- ENUMERATED items carry their numbers; INTEGER named numbers and comments are left out;
- classes use the default syntax (`{ &id x, &Type T }`), without `WITH SYNTAX`;
- the two parameterized types (`Common.RegionalExtension`, `BasicSafetyMessage.PartIIcontent`)
  are not kept by pycrate as definitions; they are rebuilt from one of their instances, with
  the formal parameter named `Set`, and each instance names the object set whose content it
  has (for regional extensions `REGION.Reg-<enclosing type>`).
"""
import os
import sys

from collections import OrderedDict

PARAMETERIZED = {("Common", "RegionalExtension"), ("BasicSafetyMessage", "PartIIcontent")}


def fail(msg):
    raise SystemExit(f"model_to_asn1: {msg}")


class Printer:
    def __init__(self, modules):
        self.M = modules
        self.imports = None  # module -> OrderedDict(from module -> [names]) for the module printed
        self.module = None
        self.owner = None  # the named type being printed (for regional object-set names)
        self.param_sites = {}  # (mod, name) -> one instance (SEQUENCE) to rebuild the definition

    # -- references --------------------------------------------------------------------------
    def ref(self, mod, name):
        """A reference to `mod.name` from the module being printed (imported when foreign)."""
        if mod != self.module:
            local = set(self.M[self.module]["_obj_"])
            if name in local:
                fail(f"{self.module} references {mod}.{name} and defines {name} itself")
            names = self.imports.setdefault(mod, [])
            if name not in names:
                for other, lst in self.imports.items():
                    if other != mod and name in lst:
                        fail(f"{self.module} imports {name} from {other} and {mod}")
                names.append(name)
        return name

    def target(self, obj):
        tr = obj._typeref
        mod, name = tr.called
        return self.M[mod][name]

    # -- constraints -------------------------------------------------------------------------
    @staticmethod
    def range_text(cset, size=False):
        parts = []
        for r in cset.root:
            if isinstance(r, int):
                parts.append(str(r))
            else:
                lb = "MIN" if r.lb is None else str(r.lb)
                ub = "MAX" if r.ub is None else str(r.ub)
                parts.append(f"{lb}..{ub}")
        if len(parts) != 1:
            fail(f"constraint with {len(parts)} root parts: {cset!r}")
        if cset.ext is not None:
            if cset.ext:
                fail(f"constraint with extension additions: {cset!r}")
            parts.append("...")
        text = ", ".join(parts)
        return f"(SIZE({text}))" if size else f"({text})"

    def constraints(self, obj):
        out = []
        if getattr(obj, "_const_val", None) is not None:
            out.append(self.range_text(obj._const_val))
        if getattr(obj, "_const_sz", None) is not None:
            out.append(self.range_text(obj._const_sz, size=True))
        if getattr(obj, "_const_alpha", None) is not None:
            fail(f"permitted alphabet constraint at {obj._name}")
        return " ".join(out)

    def extra_constraints(self, obj, target):
        """The constraints `obj` adds to the type it references (empty when the same)."""
        same = all(
            repr(getattr(obj, a, None)) == repr(getattr(target, a, None))
            for a in ("_const_val", "_const_sz")
        )
        return "" if same else self.constraints(obj)

    # -- object sets -------------------------------------------------------------------------
    @staticmethod
    def set_signature(cset):
        sig = []
        for o in cset.root:
            t = o["Type"]
            tr = t._typeref.called if t._typeref is not None else (None, t.TYPE)
            sig.append((o["id"], tuple(tr)))
        return tuple(sorted(sig))

    def find_set(self, cls, cset, prefer=None):
        """(module, name) of the object set of class `cls` whose content is `cset`.

        pycrate's copy of a set at a use site drops its extension marker: only the objects
        are compared."""
        sig = self.set_signature(cset)
        found = []
        for m in self.M:
            for s in self.M[m]["_set_"]:
                o = self.M[m][s]
                if tuple(o._typeref.called) == cls and self.set_signature(o._val) == sig:
                    found.append((m, s))
        if prefer is not None:
            if prefer in found:
                return prefer
            fail(f"object set {prefer} does not have the content the model has there")
        if len(found) != 1:
            fail(f"{len(found)} object sets of {cls} match {sig}")
        return found[0]

    # -- types -------------------------------------------------------------------------------
    def type_text(self, obj, indent):
        tr = getattr(obj, "_typeref", None)
        cls = type(tr).__name__ if tr is not None else None
        if cls == "ASN1RefType":
            called = tuple(tr.called)
            if called in PARAMETERIZED:
                return self.param_instance(obj, called)
            target = self.target(obj)
            name = self.ref(*called)
            extra = self.extra_constraints(obj, target)
            return f"{name} {extra}".rstrip()
        if cls == "ASN1RefClassField":
            return self.class_field(obj)
        if tr is not None:
            fail(f"unsupported reference {tr!r}")
        return self.builtin(obj, indent)

    def builtin(self, obj, indent):
        T = obj.TYPE
        pad = "  " * (indent + 1)
        end = "  " * indent
        if T in ("INTEGER", "BOOLEAN", "NULL", "OCTET STRING", "IA5String"):
            return f"{T} {self.constraints(obj)}".rstrip()
        if T == "BIT STRING":
            named = ""
            if obj._cont:
                items = sorted(obj._cont.items(), key=lambda it: it[1])
                named = " { " + ", ".join(f"{n}({v})" for n, v in items) + " }"
            return f"BIT STRING{named} {self.constraints(obj)}".rstrip()
        if T == "ENUMERATED":
            items = sorted(((n, obj._cont[n]) for n in obj._root), key=lambda it: it[1])
            body = [f"{n}({v})" for n, v in items]
            if obj._ext is not None:
                if obj._ext:
                    fail(f"ENUMERATED extension additions at {obj._name}")
                body.append("...")
            return "ENUMERATED {\n" + ",\n".join(pad + b for b in body) + "\n" + end + "}"
        if T == "SEQUENCE OF":
            size = ""
            if obj._const_sz is not None:
                size = self.range_text(obj._const_sz, size=True)[1:-1]
                size = f"({size}) "
            return f"SEQUENCE {size}OF {self.type_text(obj._cont, indent)}"
        if T in ("SEQUENCE", "CHOICE"):
            return self.constructed(obj, indent)
        fail(f"unsupported type {T} at {obj._name}")

    def constructed(self, obj, indent):
        pad = "  " * (indent + 1)
        end = "  " * indent
        opt = set(getattr(obj, "_root_opt", None) or [])
        lines = []
        root = list(obj._root) if obj.TYPE == "CHOICE" else list(obj._cont)
        for i, name in enumerate(root):
            comp = obj._cont[name]
            tag = getattr(comp, "_tag", None)
            if tag is not None and tag[0] != i:
                fail(f"{obj._name}.{name}: tag {tag} is not the automatic one")
            text = f"{name} {self.type_text(comp, indent + 1)}"
            if name in opt:
                text += " OPTIONAL"
            lines.append(pad + text)
        if obj._ext is not None:
            if obj._ext:
                fail(f"extension additions at {obj._name}")
            lines.append(pad + "...")
        return f"{obj.TYPE} {{\n" + ",\n".join(lines) + "\n" + end + "}"

    def class_field(self, obj, formal=None):
        """`CLASS.&field({Set})` or `CLASS.&Type({Set}{@id})` of an open type's components."""
        tr = obj._typeref
        cls = tuple(tr.called)
        field = tr.ced_path[0]
        cname = self.ref(*cls)
        if formal is not None:
            set_text = formal
        else:
            prefer = None
            if cls == ("Common", "REG-EXT-ID-AND-TYPE"):
                prefer = ("REGION", f"Reg-{self.owner}")
            m, s = self.find_set(cls, obj._const_tab._val, prefer)
            set_text = self.ref(m, s)
        at = getattr(obj, "_const_tab_at", None)
        rel = ""
        if at:
            if at[0] != ".." or len(at) != 2:
                fail(f"unsupported relative reference {at}")
            rel = f"{{@{at[1]}}}"
        return f"{cname}.&{field}({{{set_text}}}{rel})"

    def param_instance(self, obj, called):
        """An instance of a parameterized type: `RegionalExtension {{REGION.Reg-X}}`."""
        self.param_sites.setdefault(called, obj)
        id_comp = next(c for c in obj._cont.values() if c._const_tab_at is None)
        cls = tuple(id_comp._typeref.called)
        prefer = None
        if called == ("Common", "RegionalExtension"):
            prefer = ("REGION", f"Reg-{self.owner}")
        m, s = self.find_set(cls, id_comp._const_tab._val, prefer)
        return f"{self.ref(*called)} {{{{{self.ref(m, s)}}}}}"

    def param_definition(self, called):
        """The definition of a parameterized type, rebuilt from one of its instances."""
        site = self.param_sites.get(called)
        if site is None:
            fail(f"no instance of {called} to rebuild it from")
        id_comp = next(c for c in site._cont.values() if c._const_tab_at is None)
        cls = tuple(id_comp._typeref.called)
        cname = self.ref(*cls)
        lines = []
        for name, comp in site._cont.items():
            lines.append(f"  {name} {self.class_field(comp, formal='Set')}")
        return (f"{called[1]} {{{cname} : Set}} ::= SEQUENCE {{\n" + ",\n".join(lines) + "\n}")

    # -- classes, sets, values ---------------------------------------------------------------
    def class_definition(self, obj):
        lines = []
        for name, f in obj._cont.items():
            if f._mode == "TYPE" and f.TYPE == "OPEN_TYPE":
                lines.append(f"  &{name}")
            elif f._mode == "VALUE":
                t = self.type_text(f, 1)
                uniq = " UNIQUE" if getattr(f, "_uniq", False) else ""
                lines.append(f"  &{name} {t}{uniq}")
            else:
                fail(f"unsupported class field {obj._name}.&{name}")
        return f"{obj._name} ::= CLASS {{\n" + ",\n".join(lines) + "\n}"

    def value_name(self, cls_obj, v):
        """The name of a value reference equal to the id `v` of class `cls_obj` (if unique)."""
        id_field = next(f for f in cls_obj._cont.values() if f._mode == "VALUE")
        id_type = tuple(id_field._typeref.called)
        hits = []
        for m in self.M:
            for n in self.M[m]["_val_"]:
                o = self.M[m][n]
                if o.TYPE == "INTEGER" and tuple(o._typeref.called) == id_type and o._val == v:
                    hits.append((m, n))
        return self.ref(*hits[0]) if len(hits) == 1 else str(v)

    def set_definition(self, obj):
        cls = tuple(obj._typeref.called)
        cls_obj = self.M[cls[0]][cls[1]]
        items = []
        for o in sorted(obj._val.root, key=lambda o: o["id"]):
            t = o["Type"]
            if t._typeref is None:
                fail(f"inline type in object set {obj._name}")
            tname = self.ref(*t._typeref.called)
            items.append(f"  {{ &id {self.value_name(cls_obj, o['id'])}, &Type {tname} }}")
        if obj._val.ext is not None:
            items.append("  ...")
        body = " |\n".join(i for i in items if i != "  ...")
        if obj._val.ext is not None:
            body = (body + ",\n  ...") if body else "  ..."
        return f"{obj._name} {self.ref(*cls)} ::= {{\n{body}\n}}"

    def value_definition(self, obj):
        if obj.TYPE != "INTEGER":
            fail(f"unsupported value {obj._name} of type {obj.TYPE}")
        t = self.ref(*obj._typeref.called)
        return f"{obj._name} {t} ::= {obj._val}"

    # -- modules -----------------------------------------------------------------------------
    def module_text(self, mod):
        self.module = mod
        self.imports = OrderedDict()
        d = self.M[mod]
        body = []
        sets, vals, types = set(d["_set_"]), set(d["_val_"]), set(d["_type_"])
        for name in d["_obj_"]:
            obj = d[name]
            self.owner = name
            if (mod, name) in PARAMETERIZED:
                body.append(("param", name))
            elif name in sets:
                body.append(self.set_definition(obj))
            elif name in vals:
                body.append(self.value_definition(obj))
            elif obj.TYPE == "CLASS" and obj._mode == "TYPE":
                body.append(self.class_definition(obj))
            elif name in types:
                body.append(f"{name} ::= {self.type_text_named(obj)}")
            else:
                fail(f"unsupported object {mod}.{name}")
        return body

    def type_text_named(self, obj):
        tr = getattr(obj, "_typeref", None)
        if tr is not None and type(tr).__name__ == "ASN1RefType":
            target = self.target(obj)
            return f"{self.ref(*tr.called)} {self.extra_constraints(obj, target)}".rstrip()
        return self.builtin(obj, 0)

    def finish(self, mod, body):
        """Module text, once every parameterized type has been seen at one of its sites."""
        self.module = mod
        self.owner = None
        out = []
        for item in body:
            if isinstance(item, tuple):
                out.append(self.param_definition((mod, item[1])))
            else:
                out.append(item)
        oid = " ".join(str(n) for n in self.M[mod]["_oid_"])
        lines = [f"{mod} {{ {oid} }}", "DEFINITIONS AUTOMATIC TAGS ::= BEGIN", ""]
        if self.imports:
            lines.append("IMPORTS")
            for m, names in self.imports.items():
                moid = " ".join(str(n) for n in self.M[m]["_oid_"])
                lines.append(f"  {', '.join(names)}")
                lines.append(f"    FROM {m} {{ {moid} }}")
            lines[-1] += ";"
            lines.append("")
        for text in out:
            lines.append(text)
            lines.append("")
        lines.append("END")
        return "\n".join(lines) + "\n"


def main():
    if len(sys.argv) not in (2, 3) or sys.argv[1] in ("-h", "--help"):
        print(f"usage: {sys.argv[0]} OUT_DIR [MODEL_DIR]", file=sys.stderr)
        print("  OUT_DIR: where the .asn files go, outside the repository (e.g. /tmp/j2735-asn1)",
              file=sys.stderr)
        print("  MODEL_DIR: the folder of j2735_2020.py (default: ../shared/j2735 beside the repo)",
              file=sys.stderr)
        raise SystemExit(2)
    here = os.path.dirname(os.path.abspath(__file__))
    repo = os.path.abspath(os.path.join(here, "../../.."))
    out = os.path.abspath(sys.argv[1])
    model_dir = sys.argv[2] if len(sys.argv) == 3 else os.path.join(repo, "../shared/j2735")
    if out == repo or out.startswith(repo + os.sep):
        fail(f"{out} lies inside the repository; write the ASN.1 outside it (e.g. /tmp)")
    sys.path.insert(0, model_dir)
    import j2735_2020  # noqa: F401  (registers the modules with pycrate)
    from pycrate_asn1rt.glob import GLOBAL

    modules = dict(GLOBAL.MOD)
    p = Printer(modules)
    # Two passes: the first sees every type (and records one instance of each parameterized
    # type); the second prints each module with the imports it collected.
    bodies = {m: p.module_text(m) for m in modules}
    imports = {}
    for m in modules:
        p.module_text(m)
        imports[m] = p.imports
    os.makedirs(out, exist_ok=True)
    for m in modules:
        p.imports = imports[m]
        text = p.finish(m, bodies[m])
        with open(os.path.join(out, f"{m}.asn"), "w") as f:
            f.write(text)
    print(f"wrote {len(modules)} modules to {out}")


if __name__ == "__main__":
    main()
