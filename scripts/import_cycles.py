#!/usr/bin/env python3
"""Lists import cycles between source files and between top-level modules of src/.

A file imports another when it names it through `crate::a::b` or `super::b` paths (in `use`
lines or inline). Run from the repository root: `python3 scripts/import_cycles.py`; exits 1
when a cycle is found.
"""
import os
import re
import sys

SRC = "src"


def module_of(path):
    rel = os.path.relpath(path, SRC)[:-3].split(os.sep)
    if rel[-1] in ("mod", "lib", "main"):
        rel = rel[:-1]
    return rel


def file_of(parts):
    """The file of module path `parts`, longest prefix that exists."""
    for n in range(len(parts), 0, -1):
        base = os.path.join(SRC, *parts[:n])
        for cand in (base + ".rs", os.path.join(base, "mod.rs")):
            if os.path.exists(cand):
                return cand
    return None


def reexports(mod_file):
    """Item name -> child file, for the `pub use child::{...}` lines of a mod.rs."""
    out = {}
    base = os.path.dirname(mod_file)
    text = open(mod_file).read()
    for m in re.finditer(r"pub use (?:self::)?(\w+)::(\{[^}]*\}|\w+)", text):
        child = os.path.join(base, m.group(1) + ".rs")
        if not os.path.exists(child):
            child = os.path.join(base, m.group(1), "mod.rs")
        if os.path.exists(child):
            for name in re.findall(r"\w+", m.group(2)):
                out[name] = child
    return out


def main():
    files = []
    for root, _, names in os.walk(SRC):
        files += [os.path.join(root, n) for n in names if n.endswith(".rs")]
    edges = {f: set() for f in files}
    exported = {}

    def resolve(parts):
        """The file that defines module path `parts`, through mod.rs re-exports."""
        target = file_of(parts)
        while target and os.path.basename(target) == "mod.rs" and parts:
            if target not in exported:
                exported[target] = reexports(target)
            child = exported[target].get(parts[-1])
            if not child:
                break
            target = child
        return target

    for f in files:
        if os.path.basename(f) in ("mod.rs", "lib.rs", "main.rs"):
            continue  # tables of contents
        if os.path.basename(f) == "tests.rs":
            continue  # a `mod tests` moved into its own file: tests, not imports
        text = open(f).read()
        text = re.split(r"#\[cfg\(test\)\]\s*mod tests", text)[0]
        text = re.sub(r"//.*", "", text)  # doc links are not imports
        me = module_of(f)
        is_mod = os.path.basename(f) in ("mod.rs", "lib.rs", "main.rs")
        for m in re.finditer(r"\b(crate|super)((?:::\w+)+)", text):
            parts = m.group(2).split("::")[1:]
            if m.group(1) == "super":
                parent = me if is_mod else me[:-1]
                parts = parent[:-1] + parts if is_mod else parent + parts
            target = resolve(parts)
            if target and target != f:
                edges[f].add(target)
            # `use crate::m::{a, b}` names the children a and b.
            brace = text[m.end():m.end() + 400]
            if brace.startswith("::{"):
                inner = brace[3:brace.find("}")]
                for name in re.findall(r"(?:^|,)\s*(\w+)", inner):
                    t = resolve(parts + [name])
                    if t and t != f:
                        edges[f].add(t)
    # Module-level edges (top level) and file cycles of length 2 and more (Tarjan).
    top = lambda f: (module_of(f) or ["lib"])[0]
    found = False
    mod_edges = {}
    for a, bs in edges.items():
        for b in bs:
            ta, tb = top(a), top(b)
            if ta != tb:
                mod_edges.setdefault(ta, set()).add(tb)
    for a, bs in sorted(mod_edges.items()):
        for b in sorted(bs):
            if a in mod_edges.get(b, set()) and a < b:
                print(f"module cycle: {a} <-> {b}")
                for x, ys in sorted(edges.items()):
                    for y in sorted(ys):
                        if {top(x), top(y)} == {a, b}:
                            print(f"    {x} -> {y}")
                found = True
    index, low, stack, on, comps = {}, {}, [], set(), []
    sys.setrecursionlimit(10000)

    def strong(v):
        index[v] = low[v] = len(index)
        stack.append(v)
        on.add(v)
        for w in edges[v]:
            if w not in index:
                strong(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1:
                comps.append(comp)

    for v in edges:
        if v not in index:
            strong(v)
    for c in comps:
        # mod.rs re-exports its children: a child naming `super::Item` is not a cycle of
        # concepts, so cycles through a mod.rs alone are left out.
        c2 = [f for f in c if os.path.basename(f) not in ("mod.rs", "lib.rs")]
        if len(c2) > 1:
            print("file cycle: " + " -> ".join(sorted(c2)))
            found = True
    sys.exit(1 if found else 0)


main()
