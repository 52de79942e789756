#!/usr/bin/env python3
"""check_links.py: every relative link in the repository's Markdown files points at something that exists.

    python3 tests/check_links.py [ROOT]      (ROOT: the repository, default: this file's parent's parent)

Checks each .md file under ROOT (not hidden directories, not build*/ directories): inline links and
pictures `[text](target)` / `![alt](target)`, reference definitions `[label]: target` and HTML
`<img src="target">` / `<a href="target">`, outside fenced code blocks and `code spans`. A target with a
scheme (https:, mailto:) is not checked. A relative target must name a file or directory that exists,
relative to the Markdown file's own directory; a `#fragment` on a Markdown target (or alone, for the
file itself) must name one of its headings as GitHub spells the anchor (lower case, punctuation but
`-` and `_` dropped, spaces to `-`, `-1`, `-2` for repeats) or an `id=`/`name=` anchor.

It checks itself first on a made-up tree (a good link, a missing file, a missing heading: the last two
must be reported), then the repository; prints one line per broken link (file:line: target: why) and
exits 1 if there is one. ctest runs it as test_markdown_links (tests/CMakeLists.txt). Standard library
only.
"""
import os
import re
import shutil
import sys
import tempfile
import unicodedata

INLINE = re.compile(r"!?\[(?:[^\[\]]|\[[^\]]*\])*\]\(\s*(<[^>]*>|[^)\s]*)(?:\s+(?:\"[^\"]*\"|'[^']*'))?\s*\)")
REFDEF = re.compile(r"^\s{0,3}\[[^\]]+\]:\s*(<[^>]*>|\S+)")
HTML = re.compile(r"<(?:img|a)\b[^>]*?\b(?:src|href)\s*=\s*[\"']([^\"']*)[\"']", re.I)
HEADING = re.compile(r"^\s{0,3}(#{1,6})\s+(.*?)\s*#*\s*$")
ANCHOR = re.compile(r"<a\b[^>]*\b(?:name|id)\s*=\s*[\"']([^\"']+)[\"']", re.I)


def strip_code_spans(line):
    """the line with `code spans` blanked out (their text is not a link)"""
    return re.sub(r"(`+)(.+?)\1", lambda m: " " * len(m.group(0)), line)


def slug(text):
    """GitHub's anchor of a heading's text"""
    text = re.sub(r"!?\[([^\]]*)\]\([^)]*\)", r"\1", text)  # links keep their text
    text = re.sub(r"<[^>]+>", "", text).replace("`", "").lower()
    out = []
    for ch in text:
        cat = unicodedata.category(ch)
        if ch in "-_" or cat[0] in "LN" or cat == "Mn" or cat == "Mc":
            out.append(ch)
        elif ch == " ":
            out.append("-")
    return "".join(out)


def lines_outside_fences(text):
    """(line number, text) of the lines outside fenced code blocks"""
    fence = None
    for i, line in enumerate(text.split("\n"), 1):
        m = re.match(r"^\s{0,3}(```+|~~~+)", line)
        if m:
            if fence is None:
                fence = m.group(1)[0] * 3
            elif m.group(1).startswith(fence):
                fence = None
            continue
        if fence is None:
            yield i, line


_anchor_cache = {}


def anchors(path):
    """the anchors a Markdown file has: its headings' slugs (with GitHub's -1, -2 for repeats) and ids"""
    if path in _anchor_cache:
        return _anchor_cache[path]
    seen, out = {}, set()
    with open(path, encoding="utf-8") as f:
        text = f.read()
    for _, line in lines_outside_fences(text):
        m = HEADING.match(line)
        if m:
            s = slug(m.group(2))
            n = seen.get(s, 0)
            seen[s] = n + 1
            out.add(s if n == 0 else "%s-%d" % (s, n))
        for a in ANCHOR.findall(line):
            out.add(a)
    _anchor_cache[path] = out
    return out


def targets(text):
    """(line number, target) of every link in a Markdown text"""
    for no, line in lines_outside_fences(text):
        line = strip_code_spans(line)
        for m in INLINE.finditer(line):
            yield no, m.group(1).strip("<>")
        m = REFDEF.match(line)
        if m:
            yield no, m.group(1).strip("<>")
        for m in HTML.finditer(line):
            yield no, m.group(1)


def check_file(md, root):
    """the broken links of one Markdown file: [(line, target, why)]"""
    bad = []
    with open(md, encoding="utf-8") as f:
        text = f.read()
    for no, t in targets(text):
        if not t or re.match(r"^[A-Za-z][A-Za-z0-9+.-]*:", t):  # https:, mailto:, ...
            continue
        path, _, frag = t.partition("#")
        full = os.path.normpath(os.path.join(os.path.dirname(md), path)) if path else md
        if path and not os.path.exists(full):
            bad.append((no, t, "no such file"))
            continue
        if path and not os.path.realpath(full).startswith(os.path.realpath(root) + os.sep):
            bad.append((no, t, "outside the repository"))
            continue
        if frag and full.endswith(".md") and os.path.isfile(full) and frag not in anchors(full):
            bad.append((no, t, "no heading or anchor '%s' in %s" % (frag, os.path.relpath(full, root))))
    return bad


def markdown_files(root):
    for d, dirs, files in os.walk(root):
        dirs[:] = sorted(x for x in dirs if not x.startswith(".") and not x.startswith("build"))
        for f in sorted(files):
            if f.endswith(".md"):
                yield os.path.join(d, f)


def check_tree(root, quiet=False):
    """prints the broken links under root; returns (files checked, broken links)"""
    nfiles = nbad = 0
    for md in markdown_files(root):
        nfiles += 1
        for no, t, why in check_file(md, root):
            nbad += 1
            if not quiet:
                print("%s:%d: %s: %s" % (os.path.relpath(md, root), no, t, why))
    return nfiles, nbad


def self_test():
    """the checker on a made-up tree: the good links pass, each broken one is caught"""
    tmp = tempfile.mkdtemp(prefix="check_links_")
    try:
        os.makedirs(os.path.join(tmp, "docs", "img"))
        open(os.path.join(tmp, "docs", "img", "a.png"), "w").close()
        with open(os.path.join(tmp, "docs", "b.md"), "w", encoding="utf-8") as f:
            f.write("# Part one: `code`, and more!\n## 第 1 章 目录\n## A1.2 Fast\n")
        good = ("[b](docs/b.md) ![p](docs/img/a.png \"t\") [h](docs/b.md#part-one-code-and-more)\n"
                "[z](docs/b.md#第-1-章-目录) [y](docs/b.md#a12-fast) [web](https://example.org/x.md) [me](#top)\n"
                "# Top\n```\n[in a fence](missing.md)\n```\n`[in code](missing.md)`\n[r]: docs/img/a.png\n")
        with open(os.path.join(tmp, "README.md"), "w", encoding="utf-8") as f:
            f.write(good)
        n, bad = check_tree(tmp, quiet=True)
        ok = n == 2 and bad == 0
        if not ok:
            print("self-test: good links reported as broken (%d):" % bad)
            check_tree(tmp)
        cases = [("[gone](docs/gone.md)", "no such file"), ("![gone](docs/img/b.png)", "no such file"),
                 ("[h](docs/b.md#part-two)", "no heading"), ("[r]: ../outside.md", "no such file"),
                 ("<img src=\"img/x.png\">", "no such file"), ("[self](#nowhere)", "no heading")]
        for line, why in cases:
            with open(os.path.join(tmp, "README.md"), "w", encoding="utf-8") as f:
                f.write(good + line + "\n")
            found = check_file(os.path.join(tmp, "README.md"), tmp)
            if len(found) != 1 or why not in found[0][2]:
                print("self-test: %r not caught as '%s' (got %r)" % (line, why, found))
                ok = False
        return ok
    finally:
        shutil.rmtree(tmp)


def main():
    root = os.path.abspath(sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), ".."))
    if not self_test():
        print("FAIL: the checker's self-test")
        return 1
    n, bad = check_tree(root)
    print("%s: %d Markdown files, %d broken links" % ("FAIL" if bad else "PASS", n, bad))
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
