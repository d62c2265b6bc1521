#!/usr/bin/env python3
"""Counts the public API of a crate from its rustdoc JSON.

    cargo +nightly rustdoc -p envmap-render --lib -- -Z unstable-options --output-format json
    python3 scripts/api-count.py target/doc/envmap_render.json [-v] [-f] [--max-functions N]
        [--max-modules N] [--max-reexports N]

Walks the items reachable from the crate root: public functions and
methods (inherent impls and traits; trait impls not counted), public
modules (the root included; a private module whose items a glob
re-exports is not one), re-exports (`pub use` items: named ones, and
globs of public modules, the re-exports inside the module a glob brings
in counted too), public struct fields, and modules reachable by two
paths. A glob of a private module (`pub use io::*;`: a module's file whose
items have no other path) gives no item a second name: it is counted
apart, as a file, not as a re-export. Exits 1 when a count is above its
--max, or any module has two paths.
"""
import json, sys
path = sys.argv[1]
d = json.load(open(path))
idx = d["index"]; root = d["root"]
crate_id = idx[str(root)]["crate_id"] if str(root) in idx else 0
def inner_kind(it):
    return next(iter(it["inner"])) if isinstance(it["inner"], dict) else it["inner"]
# walk reachable public items from the root module
fns = set(); mods = []; reexports = []; files = []; fields = set(); seen_mods = {}
def private_glob(c):
    """Whether `pub use` item `c` is a glob of a private module of this crate."""
    u = c["inner"]["use"]; t = idx.get(str(u.get("id")))
    return bool(u.get("is_glob")) and t is not None and inner_kind(t) == "module" \
        and t.get("crate_id", 0) == 0 and t["visibility"] != "public"
def note_use(path, c):
    (files if private_glob(c) else reexports).append(path + "::" + c["inner"]["use"]["name"])
def visit_module(mid, path):
    it = idx[str(mid)]
    if mid in seen_mods:
        seen_mods[mid].append(path); return
    seen_mods[mid] = [path]
    mods.append(path)
    for child in it["inner"]["module"]["items"]:
        c = idx.get(str(child))
        if c is None: continue
        if c.get("crate_id", 0) != 0: continue
        k = inner_kind(c)
        if c["visibility"] != "public" and k != "use": continue
        if k == "module":
            visit_module(child, path + "::" + c["name"])
        elif k == "use":
            if c["visibility"] != "public": continue
            note_use(path, c)
            tgt = c["inner"]["use"].get("id")
            if tgt is not None and str(tgt) in idx:
                t = idx[str(tgt)]
                if inner_kind(t) == "module" and t.get("crate_id",0)==0:
                    if c["inner"]["use"].get("is_glob"):
                        # `pub use m::*`: m's public items are reachable
                        # here; m itself is not a public path.
                        visit_glob(tgt, path)
                    else:
                        visit_module(tgt, path + "::" + c["inner"]["use"]["name"])
                else:
                    visit_item(tgt)
        else:
            visit_item(child)
def visit_glob(mid, path):
    # The items a glob re-export brings into `path`: each public item of the
    # module (public submodules as modules of `path`, re-exports followed).
    for child in idx[str(mid)]["inner"]["module"]["items"]:
        c = idx.get(str(child))
        if c is None or c.get("crate_id", 0) != 0: continue
        k = inner_kind(c)
        if c["visibility"] != "public": continue
        if k == "module":
            visit_module(child, path + "::" + c["name"])
        elif k == "use":
            note_use(path, c)
            tgt = c["inner"]["use"].get("id")
            if tgt is not None and str(tgt) in idx:
                t = idx[str(tgt)]
                if inner_kind(t) == "module" and t.get("crate_id",0)==0:
                    visit_glob(tgt, path) if c["inner"]["use"].get("is_glob") else visit_module(tgt, path + "::" + c["inner"]["use"]["name"])
                else:
                    visit_item(tgt)
        else:
            visit_item(child)
def visit_item(iid):
    it = idx.get(str(iid))
    if it is None or it.get("crate_id",0)!=0: return
    k = inner_kind(it)
    if k == "function": fns.add(iid)
    elif k in ("struct","enum","union"):
        inner = it["inner"][k]
        if k == "struct":
            kind = inner["kind"]
            if isinstance(kind, dict):
                fl = kind.get("plain",{}).get("fields") or kind.get("tuple") or []
                for f in fl:
                    if f is None: continue
                    fi = idx.get(str(f))
                    if fi and fi["visibility"] == "public": fields.add(f)
        for impl in inner.get("impls", []):
            im = idx[str(impl)]["inner"]["impl"]
            if im.get("trait") is not None: continue
            for m in im["items"]:
                mi = idx.get(str(m))
                if mi and inner_kind(mi) == "function" and mi["visibility"] == "public":
                    fns.add(m)
    elif k == "trait":
        for m in it["inner"]["trait"]["items"]:
            mi = idx.get(str(m))
            if mi and inner_kind(mi) == "function": fns.add(m)
visit_module(root, d["index"][str(root)]["name"])
twice = {m: p for m, p in seen_mods.items() if len(p) > 1}
print(f"public functions and methods: {len(fns)}")
print(f"public modules: {len(mods)}")
print(f"re-exports: {len(reexports)}")
print(f"private files re-exported by glob: {len(files)}")
print(f"public fields: {len(fields)}")
print(f"modules reachable by two paths: {len(twice)}")
for m,p in twice.items(): print("   ", " = ".join(p))
if "-v" in sys.argv:
    for m in mods: print("mod", m)
    for r in reexports: print("use", r)
    for r in files: print("file", r)
if "-f" in sys.argv:
    for f in sorted(fns, key=lambda i: str(idx[str(i)].get("span",{}).get("filename",""))):
        it = idx[str(f)]
        print(it.get("span",{}).get("filename",""), it["name"])

def limit(flag, value):
    if flag in sys.argv:
        m = int(sys.argv[sys.argv.index(flag) + 1])
        if value > m:
            print(f"{flag[6:]}: {value}, above {m}")
            return True
    return False
bad = [limit("--max-functions", len(fns)), limit("--max-modules", len(mods)),
       limit("--max-reexports", len(reexports)), bool(twice)]
sys.exit(1 if any(bad) else 0)
