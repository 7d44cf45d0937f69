#!/usr/bin/env python3
"""Check the layering of firmware/ against tools/layers.toml.

Two checks, each naming the file at fault:

  includes  every #include of every .c and .h of each layer, resolved as the
            compiler would (the including file's folder, then the repository's
            include folders), must land in a layer the including layer may
            include; a system header must be a standard C header.
  symbols   (with --lib) the file-level dependency graph of the built objects:
            file A depends on file B when A's object uses a global symbol B's
            object defines (nm of the host build's static libraries, one object
            per source file). Every use must go to a layer the user's layer may
            use (the HAL: only the functions hal/include/hal/hal.h declares);
            every cycle of files must lie inside one group of the allow-list
            (allowed_cycles), and each group must be no larger than its cycles;
            a reach_only file may reach, through any chain, only what it lists.

usage: check_layers.py [--root DIR] [--rules FILE] [--generated DIR]
                       [--lib LAYER=ARCHIVE ...] [--hal-lib ARCHIVE] [--nm NM]
  --root       the repository (default: this script's parent folder)
  --rules      the rules (default: ROOT/tools/layers.toml)
  --generated  the build's generated folder (include/ and src/ of dtc/param_table.*;
               default: ROOT/build/host/generated when it exists)
  --lib        a layer's static library, e.g. control=build/host/firmware/libdtc_control.a
  --hal-lib    the host binding's library (defines the HAL functions)
exit: 0 the layering holds, 1 it does not, 2 usage, a missing file or a tool failed.
"""
import argparse
import collections
import os
import re
import subprocess
import sys

try:
    import tomllib
except ModuleNotFoundError:  # Python < 3.11
    tomllib = None

# The headers of the C11 standard library (ISO/IEC 9899:2011, 7.1.2).
C_STANDARD_HEADERS = {
    "assert.h", "complex.h", "ctype.h", "errno.h", "fenv.h", "float.h", "inttypes.h", "iso646.h",
    "limits.h", "locale.h", "math.h", "setjmp.h", "signal.h", "stdalign.h", "stdarg.h", "stdatomic.h",
    "stdbool.h", "stddef.h", "stdint.h", "stdio.h", "stdlib.h", "stdnoreturn.h", "string.h", "tgmath.h",
    "threads.h", "time.h", "uchar.h", "wchar.h", "wctype.h",
}
HAL_TYPES = "hal/include/hal/hal_types.h"
HAL_HEADER = "hal/include/hal/hal.h"
SKIP_DIRS = {".git", ".venv", "build", "__pycache__"}
INCLUDE = re.compile(r'^[ \t]*#[ \t]*include[ \t]*([<"])([^>"]+)[>"]', re.M)
HAL_FUNCTION = re.compile(r"\b(hal_[A-Za-z0-9_]+)\s*\(")


class Failure(Exception):
    """A usage or tool error (exit 2)."""


def load_rules(path):
    if tomllib is None:
        raise Failure("Python 3.11 or later is needed (tomllib)")
    try:
        with open(path, "rb") as fh:
            rules = tomllib.load(fh)
    except (OSError, tomllib.TOMLDecodeError) as e:
        raise Failure(f"{path}: {e}")
    layers = rules.get("layers", {})
    if not layers:
        raise Failure(f"{path}: no [layers]")
    known = set(layers) | {"hal_types", "hal", "generated"}
    for name, layer in layers.items():
        for key in ("dir", "may_include", "may_use"):
            if key not in layer:
                raise Failure(f"{path}: layers.{name} has no {key}")
        for key in ("may_include", "may_use"):
            unknown = sorted(set(layer[key]) - known)
            if unknown:
                raise Failure(f"{path}: layers.{name}.{key} names {', '.join(unknown)}: "
                              f"not a layer, hal_types, hal or generated")
    for group in rules.get("allowed_cycles", []):
        if not group.get("why") or not group.get("files"):
            raise Failure(f"{path}: an allowed_cycles entry needs why and files")
    for rule in rules.get("reach_only", []):
        if not rule.get("file") or not rule.get("why") or "may_reach" not in rule:
            raise Failure(f"{path}: a reach_only entry needs file, why and may_reach")
    return rules


def strip_comments(text):
    """The text with its comments blanked (line breaks kept, so line numbers hold)."""
    out, i, n = [], 0, len(text)
    while i < n:
        if text.startswith("/*", i):
            j = text.find("*/", i + 2)
            j = n if j < 0 else j + 2
            out.append("".join("\n" if c == "\n" else " " for c in text[i:j]))
            i = j
        elif text.startswith("//", i):
            j = text.find("\n", i)
            j = n if j < 0 else j
            out.append(" " * (j - i))
            i = j
        elif text[i] in "\"'":
            q, j = text[i], i + 1
            while j < n and text[j] != q and text[j] != "\n":
                j += 2 if text[j] == "\\" else 1
            out.append(text[i:j + 1])
            i = j + 1
        else:
            out.append(text[i])
            i += 1
    return "".join(out)


class Tree:
    """The repository's files as the checks see them: which layer owns a path."""

    def __init__(self, root, rules, generated):
        self.root = os.path.abspath(root)
        self.layers = rules["layers"]
        self.generated = os.path.abspath(generated) if generated else None
        self.include_dirs = self._include_dirs()

    def _include_dirs(self):
        dirs = [os.path.join(self.root, layer["dir"], "include") for layer in self.layers.values()]
        dirs.append(os.path.join(self.root, "hal", "include"))
        if self.generated:
            dirs.append(os.path.join(self.generated, "include"))
        # everything else that is an include folder or a board's own folder,
        # so that a reach into a board resolves (and is refused) instead of
        # passing as unknown
        for base in ("hal", "host_sim", "tests"):
            top = os.path.join(self.root, base)
            for dirpath, subdirs, _files in os.walk(top):
                subdirs[:] = sorted(d for d in subdirs if d not in SKIP_DIRS)
                if os.path.basename(dirpath) == "include" or os.path.dirname(dirpath) == top:
                    if dirpath not in dirs:
                        dirs.append(dirpath)
        return [d for d in dirs if os.path.isdir(d)]

    def rel(self, path):
        return os.path.relpath(os.path.abspath(path), self.root).replace(os.sep, "/")

    def owner(self, path):
        """The layer, hal_types, hal, generated or board that a file belongs to."""
        path = os.path.abspath(path)
        if self.generated and path.startswith(self.generated + os.sep):
            return "generated"
        rel = self.rel(path)
        for name, layer in self.layers.items():
            if rel.startswith(layer["dir"].rstrip("/") + "/"):
                return name
        if rel == HAL_TYPES:
            return "hal_types"
        if rel.startswith("hal/include/hal/"):
            return "hal"
        return "board"

    def name(self, path):
        """A file's name in the reports: its path in the repository, or generated/..."""
        path = os.path.abspath(path)
        if self.generated and path.startswith(self.generated + os.sep):
            return "generated/" + os.path.relpath(path, self.generated).replace(os.sep, "/")
        return self.rel(path)

    def layer_files(self, name):
        top = os.path.join(self.root, self.layers[name]["dir"])
        for dirpath, subdirs, files in os.walk(top):
            subdirs[:] = sorted(d for d in subdirs if d not in SKIP_DIRS)
            for f in sorted(files):
                if f.endswith((".c", ".h")):
                    yield os.path.join(dirpath, f)

    def resolve(self, including, kind, target):
        candidates = [os.path.dirname(including)] if kind == '"' else []
        for d in candidates + self.include_dirs:
            p = os.path.join(d, target)
            if os.path.isfile(p):
                return os.path.normpath(p)
        return None


def check_includes(tree):
    problems, count = [], 0
    for name, layer in tree.layers.items():
        allowed = set(layer["may_include"])
        for path in tree.layer_files(name):
            with open(path, encoding="utf-8", errors="replace") as fh:
                text = strip_comments(fh.read())
            for m in INCLUDE.finditer(text):
                count += 1
                line = text.count("\n", 0, m.start()) + 1
                kind, target = m.group(1), m.group(2)
                where = f"{tree.rel(path)}:{line}"
                hit = tree.resolve(path, kind, target)
                if hit is None:
                    if kind == "<" and target in C_STANDARD_HEADERS:
                        continue
                    if kind == "<":
                        problems.append(f"{where}: includes <{target}>, not a standard C header "
                                        f"(firmware/ uses no MCU, OS or compiler header)")
                    else:
                        problems.append(f'{where}: includes "{target}", which is in no include folder '
                                        f"of the repository")
                    continue
                owner = tree.owner(hit)
                if owner not in allowed:
                    problems.append(f'{where}: includes "{target}" ({tree.name(hit)}, {owner}); '
                                    f"{name} may include only {', '.join(sorted(allowed))}")
    return problems, count


# ------------------------------------------------------------------ symbols

def run_nm(nm, archive):
    try:
        out = subprocess.run([nm, "-P", "-A", archive], capture_output=True, text=True, check=True).stdout
    except FileNotFoundError:
        raise Failure(f"{nm} not found")
    except subprocess.CalledProcessError as e:
        raise Failure(f"{nm} {archive}: {e.stderr.strip()}")
    member = re.compile(r"^(.*)\[([^\]]+)\]: (\S+) (\S)(?: (\S*))?")
    objects = collections.OrderedDict()
    for line in out.splitlines():
        m = member.match(line)
        if not m:
            continue
        obj, sym, typ, value = m.group(2), m.group(3), m.group(4), m.group(5)
        defs, uses = objects.setdefault(obj, (set(), set()))
        if typ == "U" or (typ in "wv" and not value):
            uses.add(sym)
        elif typ.isupper() and typ != "N":
            defs.add(sym)
    return objects


def object_source(tree, layer, obj):
    """The source file an object of @p layer's library was compiled from."""
    src = re.sub(r"\.(o|obj)$", "", obj)
    candidates = [os.path.join(tree.root, tree.layers[layer]["dir"], "src", src)]
    if tree.generated:
        candidates.append(os.path.join(tree.generated, "src", src))
    for c in candidates:
        if os.path.isfile(c):
            return c
    raise Failure(f"{obj} in {layer}'s library: no {src} in {tree.layers[layer]['dir']}/src"
                  + (" or the generated sources" if tree.generated else "")
                  + " (one object per source file is needed: a unity build hides the files)")


def hal_functions(tree):
    path = os.path.join(tree.root, HAL_HEADER)
    try:
        with open(path, encoding="utf-8") as fh:
            return set(HAL_FUNCTION.findall(strip_comments(fh.read())))
    except OSError as e:
        raise Failure(f"{path}: {e}")


class Graph:
    def __init__(self):
        self.owner = {}                                   # file name -> layer (or generated)
        self.edges = collections.defaultdict(dict)        # file -> {file: first symbol}
        self.outside = collections.defaultdict(dict)      # file -> {symbol: hal or board}


def build_graph(tree, libs, hal_lib, nm):
    g = Graph()
    defined_by = {}
    uses = {}
    for layer, archive in libs:
        if layer not in tree.layers:
            raise Failure(f"--lib {layer}=...: no such layer in the rules")
        if not os.path.isfile(archive):
            raise Failure(f"{archive}: no such library (build the host preset first)")
        for obj, (defs, used) in run_nm(nm, archive).items():
            path = object_source(tree, layer, obj)
            name = tree.name(path)
            g.owner[name] = tree.owner(path)
            uses.setdefault(name, set()).update(used)
            for s in defs:
                defined_by.setdefault(s, name)
    hal_defs = {}
    if hal_lib:
        if not os.path.isfile(hal_lib):
            raise Failure(f"{hal_lib}: no such library")
        declared = hal_functions(tree)
        for _obj, (defs, _used) in run_nm(nm, hal_lib).items():
            for s in defs:
                hal_defs.setdefault(s, "hal" if s in declared else "board")
    for name, used in uses.items():
        for s in sorted(used):
            target = defined_by.get(s)
            if target is not None:
                if target != name:
                    g.edges[name].setdefault(target, s)
            elif s in hal_defs:
                g.outside[name][s] = hal_defs[s]
    return g


def check_uses(tree, g):
    problems = []
    for name in sorted(g.owner):
        layer = g.owner[name]
        rule_layer = "drive" if layer == "generated" else layer
        allowed = set(tree.layers[rule_layer]["may_use"])
        for target, sym in sorted(g.edges[name].items()):
            to = g.owner[target]
            if to not in allowed:
                problems.append(f"{name} uses {sym} of {target} ({to}); "
                                f"{rule_layer} may use only {', '.join(sorted(allowed))}")
        for sym, to in sorted(g.outside[name].items()):
            if to not in allowed:
                what = "a HAL function" if to == "hal" else "a function of the host binding that hal.h does not declare"
                problems.append(f"{name} uses {sym}, {what}; {rule_layer} may use only {', '.join(sorted(allowed))}")
    return problems


def strongly_connected(nodes, edges):
    """Tarjan's algorithm, iterative: the components with more than one file."""
    index, low, on, stack, out = {}, {}, set(), [], []
    counter = [0]
    for start in sorted(nodes):
        if start in index:
            continue
        work = [(start, iter(sorted(edges.get(start, {}))))]
        index[start] = low[start] = counter[0]
        counter[0] += 1
        stack.append(start)
        on.add(start)
        while work:
            v, it = work[-1]
            advanced = False
            for w in it:
                if w not in index:
                    index[w] = low[w] = counter[0]
                    counter[0] += 1
                    stack.append(w)
                    on.add(w)
                    work.append((w, iter(sorted(edges.get(w, {})))))
                    advanced = True
                    break
                if w in on:
                    low[v] = min(low[v], index[w])
            if advanced:
                continue
            work.pop()
            if work:
                low[work[-1][0]] = min(low[work[-1][0]], low[v])
            if low[v] == index[v]:
                comp = []
                while True:
                    w = stack.pop()
                    on.discard(w)
                    comp.append(w)
                    if w == v:
                        break
                if len(comp) > 1:
                    out.append(sorted(comp))
    return out


def a_cycle(comp, edges):
    """One shortest cycle through the component's first file, with the symbols on its edges."""
    members, start = set(comp), comp[0]
    prev, queue = {start: None}, collections.deque([start])
    while queue:
        v = queue.popleft()
        for w in sorted(edges.get(v, {})):
            if w not in members:
                continue
            if w == start:
                path = [v]
                while prev[path[-1]] is not None:
                    path.append(prev[path[-1]])
                path.reverse()
                path.append(start)
                return " -> ".join(f"{a} ({edges[a][b]})" for a, b in zip(path, path[1:])) + f" -> {start}"
            if w not in prev:
                prev[w] = v
                queue.append(w)
    return " -> ".join(comp)


def check_cycles(rules, g):
    problems, allowed = [], []
    groups = [(grp["why"], set(grp["files"])) for grp in rules.get("allowed_cycles", [])]
    in_cycle = set()
    for comp in strongly_connected(g.owner.keys(), g.edges):
        in_cycle.update(comp)
        group = next((why for why, files in groups if set(comp) <= files), None)
        if group is None:
            problems.append(f"a cycle of files not in the allow-list ({', '.join(comp)}): {a_cycle(comp, g.edges)}")
        else:
            allowed.append((comp, group))
    for why, files in groups:
        spare = sorted(f for f in files if f in g.owner and f not in in_cycle)
        missing = sorted(f for f in files if f not in g.owner)
        if spare:
            problems.append(f"allowed_cycles names {', '.join(spare)}, in no cycle now: take it out of the group "
                            f"({why.split(':')[0]})")
        if missing:
            problems.append(f"allowed_cycles names {', '.join(missing)}, which is not built: take it out of the group")
    return problems, allowed


def check_reach(rules, g):
    """Walk each reach_only file's uses through what it may reach; every step
    out of that is a problem, named with the chain that leads to it."""
    problems = []
    for rule in rules.get("reach_only", []):
        f, ok = rule["file"], rule["may_reach"]
        if f not in g.owner:
            problems.append(f"reach_only names {f}, which is not built (renamed? update tools/layers.toml)")
            continue

        def permitted(target):
            return any(target == p or (p.endswith("/") and target.startswith(p)) for p in ok)

        def chain(v, parent):
            path = [v]
            while parent[path[-1]] is not None:
                path.append(parent[path[-1]])
            path.reverse()
            return path

        parent, todo = {f: None}, [f]
        while todo:
            v = todo.pop(0)
            for w in sorted(g.edges.get(v, {})):
                if w in parent:
                    continue
                if not permitted(w):
                    path = chain(v, parent) + [w]
                    via = " -> ".join(f"{a} ({g.edges[a][b]})" for a, b in zip(path, path[1:])) + f" -> {w}"
                    problems.append(f"{f} reaches {w}: {via}; {rule['why']}")
                    parent[w] = v  # reported once
                    continue
                parent[w] = v
                todo.append(w)
            if "hal" not in ok:
                for sym, to in sorted(g.outside[v].items()):
                    if to == "hal":
                        problems.append(f"{f} reaches the HAL ({sym}, used by {v}); {rule['why']}")
    return problems


def main(argv=None):
    here = os.path.dirname(os.path.abspath(__file__))
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--root", default=os.path.dirname(here))
    ap.add_argument("--rules")
    ap.add_argument("--generated")
    ap.add_argument("--lib", action="append", default=[], metavar="LAYER=ARCHIVE")
    ap.add_argument("--hal-lib")
    ap.add_argument("--nm", default=os.environ.get("NM", "nm"))
    args = ap.parse_args(argv)
    try:
        rules = load_rules(args.rules or os.path.join(args.root, "tools", "layers.toml"))
        generated = args.generated
        if generated is None and os.path.isdir(os.path.join(args.root, "build", "host", "generated")):
            generated = os.path.join(args.root, "build", "host", "generated")
        tree = Tree(args.root, rules, generated)
        libs = []
        for spec in args.lib:
            layer, sep, archive = spec.partition("=")
            if not sep or not archive:
                raise Failure(f"--lib {spec}: expected LAYER=ARCHIVE")
            libs.append((layer, archive))
        problems, n_includes = check_includes(tree)
        summary = [f"{n_includes} includes"]
        if libs:
            g = build_graph(tree, libs, args.hal_lib, args.nm)
            problems += check_uses(tree, g)
            cycle_problems, allowed = check_cycles(rules, g)
            problems += cycle_problems
            problems += check_reach(rules, g)
            n_edges = sum(len(v) for v in g.edges.values())
            summary.append(f"{len(g.owner)} objects, {n_edges} file dependencies")
            summary.append("cycles only inside the allow-list: " + "; ".join(
                f"{len(comp)} files ({why.split(':')[0]})" for comp, why in allowed) if allowed else "no cycle")
    except Failure as e:
        print(f"check_layers: {e}", file=sys.stderr)
        return 2
    for p in problems:
        print(f"check_layers: {p}")
    if problems:
        print(f"check_layers: {len(problems)} problem(s); the rules are in tools/layers.toml, "
              f"the layers in docs/architecture.md")
        return 1
    print("check_layers: ok: " + ", ".join(summary))
    return 0


if __name__ == "__main__":
    sys.exit(main())
