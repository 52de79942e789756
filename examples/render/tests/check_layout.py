#!/usr/bin/env python3
"""check_layout.py: the renderer's files call each other one way (ctest: test_render_layout).

    python3 check_layout.py NM libel_render.a

Reads the symbol table of every object file in el_render (`nm` on the static library: each member is
one .c file), draws an edge a -> b where file a uses a function or datum that file b defines, and fails
(exit status 1, naming the files and the symbols) when
  - the graph has a circle: files that call each other, directly or round a loop (the layout of
    README.md's file map: the parser describes, scene.c builds, the lights and the samplers' shared
    helpers are called, never calling back), or
  - one of the rules below is broken: lights.c calls into the scene, the parser or an integrator, or
    the parser's files call into the lights, the scene, the library or the image reader (they describe;
    scene.c builds), or a file of the parser calls one that comes after it in ORDERS (parser.c <
    paramset.c < api_*.c < api.c).
Before looking at the library it checks itself on two made-up symbol tables, one with a circle and one
without, so that a detector that sees nothing fails too.
"""
import fnmatch
import subprocess
import sys

# (from files, to files, why): files matching the first pattern may not use files matching the second
RULES = [
    ("lights", "scene|parser*|paramset*|api*|integrator*|render*",
     "the lights are called by the integrators and built by scene.c; they trace no rays"),
    ("parser*|paramset*|api*", "lights|scene|envlight_impl|imageio",
     "the parser describes the scene; scene.c builds it (reads the images, makes the lights and MIP maps)"),
    ("sampler_*", "sampler", "the samplers' shared helpers are inline or in lowdiscrepancy.c; sampler.c dispatches to them"),
]

# files that call only the files before them in the list (parser.c's opening comment: the parser's files)
ORDERS = [
    ["parser", "paramset", "api_options", "api_lights", "api_shapes", "api_materials", "api"],
]


def matches(name, patterns):
    return any(fnmatch.fnmatchcase(name, p) for p in patterns.split("|"))


def parse_nm(text):
    """nm output of an archive -> {file: (defined symbols, undefined symbols)}"""
    files, cur = {}, None
    for line in text.splitlines():
        line = line.rstrip()
        if not line:
            continue
        if line.endswith(":") and " " not in line:
            cur = line[:-1].split("/")[-1]
            for ext in (".o", ".obj", ".c"):
                if cur.endswith(ext):
                    cur = cur[: -len(ext)]
            files.setdefault(cur, (set(), set()))
            continue
        if cur is None:
            continue
        parts = line.split()
        if len(parts) == 3 and parts[1] in "TDBRVWGS":
            files[cur][0].add(parts[2])
        elif len(parts) == 2 and parts[0] == "U":
            files[cur][1].add(parts[1])
    return files


def graph(files):
    owner = {}
    for f, (defs, _) in files.items():
        for s in defs:
            owner[s] = f
    edges = {}
    for f, (_, und) in files.items():
        edges[f] = {}
        for s in und:
            g = owner.get(s)
            if g is not None and g != f:
                edges[f].setdefault(g, []).append(s)
    return edges


def circles(edges):
    """the strongly connected components of more than one file (Tarjan)"""
    index, low, stack, on, out, counter = {}, {}, [], set(), [], [0]

    def visit(v):
        index[v] = low[v] = counter[0]
        counter[0] += 1
        stack.append(v)
        on.add(v)
        for w in edges[v]:
            if w not in index:
                visit(w)
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
                out.append(sorted(comp))

    sys.setrecursionlimit(10000)
    for v in sorted(edges):
        if v not in index:
            visit(v)
    return out


def problems(edges):
    msgs = []
    for comp in circles(edges):
        msgs.append("circle: " + " <-> ".join(comp))
        for a in comp:
            for b in comp:
                if b in edges[a]:
                    msgs.append("    %s -> %s: %s" % (a, b, " ".join(sorted(edges[a][b]))))
    for frm, tos, why in RULES:
        for a in sorted(edges):
            for b in sorted(edges[a]):
                if matches(a, frm) and matches(b, tos):
                    msgs.append("rule: %s -> %s (%s): %s" % (a, b, why, " ".join(sorted(edges[a][b]))))
    for order in ORDERS:
        for i, a in enumerate(order):
            for b in sorted(edges.get(a, {})):
                if b in order[i:]:
                    msgs.append("order: %s -> %s (%s calls only the files before it in %s): %s"
                                % (a, b, a, " < ".join(order), " ".join(sorted(edges[a][b]))))
    return msgs


def self_test():
    bad = "x/a.c.o:\n0000 T f\n U g\n\nb.c.o:\n0000 T g\n U h\n\nc.c.o:\n0000 T h\n U f\n"
    good = "a.c.o:\n0000 T f\n U g\n\nb.c.o:\n0000 T g\n U h\n\nc.c.o:\n0000 T h\n U printf\n"
    rule = "lights.c.o:\n0000 T elr_light_le\n U elr_occluded\n\nscene.c.o:\n0000 T elr_occluded\n"
    order = "parser.c.o:\n0000 T elr__next\n U elr__pfloat\n\nparamset.c.o:\n0000 T elr__pfloat\n"
    ok = (problems(graph(parse_nm(bad))) and circles(graph(parse_nm(bad))) == [["a", "b", "c"]]
          and not problems(graph(parse_nm(good))) and problems(graph(parse_nm(rule))) and problems(graph(parse_nm(order))))
    if not ok:
        print("check_layout.py: its self-test failed (a circle or a broken rule was not seen, or one was seen where there is none)")
        sys.exit(1)


def main():
    if len(sys.argv) != 3:
        print(__doc__)
        sys.exit(2)
    self_test()
    text = subprocess.run([sys.argv[1], sys.argv[2]], capture_output=True, text=True, check=True).stdout
    files = parse_nm(text)
    if len(files) < 10:
        print("check_layout.py: only %d object files in %s: not the renderer's library?" % (len(files), sys.argv[2]))
        sys.exit(1)
    edges = graph(files)
    msgs = problems(edges)
    if msgs:
        print("the renderer's files call each other round a circle or against the layout (README.md's file map):")
        print("\n".join(msgs))
        sys.exit(1)
    n = sum(len(e) for e in edges.values())
    print("check_layout.py: %d files, %d calling edges, no circle, the layout rules hold" % (len(files), n))


if __name__ == "__main__":
    main()
