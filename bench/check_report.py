#!/usr/bin/env python3
"""bench/check_report.py: checks that a run of bench/report.py wrote everything the report needs.

    python3 bench/check_report.py DIR [--quick]

DIR/accuracy-vs-time.md, DIR/measurements.json, and every plot of EXPECTED_PLOTS as a real PNG in
DIR/img/, each linked from the text; every image the text links exists; no NaN, inf or None in the text;
and the run is of the kind asked for (docs/ must hold a full run, --quick a quick one). Exit 1 with the
list of problems otherwise. ctest runs it on docs/ (test_report_docs); scripts/report.sh on what it wrote.
Only the standard library: it runs where matplotlib is not installed.
"""
import json
import os
import re
import struct
import sys

EXPECTED_PLOTS = [
    "mipmap_lookups", "mipmap_build", "envlight_variance_city", "envlight_variance_studio",
    "envlight_build", "render_strategies_city", "render_strategies_studio", "render_samplers_city",
    "render_samplers_studio", "render_splitting", "film_filters", "film_dither",
]


def png_size(path):
    with open(path, "rb") as f:
        head = f.read(24)
    if len(head) < 24 or head[:8] != b"\x89PNG\r\n\x1a\n" or head[12:16] != b"IHDR":
        return None
    return struct.unpack(">II", head[16:24])


def check(out, quick):
    problems = []
    md_path = os.path.join(out, "accuracy-vs-time.md")
    if not os.path.isfile(md_path):
        return ["%s: missing" % md_path]
    with open(md_path, encoding="utf-8") as f:
        md = f.read()
    links = re.findall(r"!\[[^\]]*\]\(([^)]+)\)", md)
    for name in EXPECTED_PLOTS:
        rel = "img/%s.png" % name
        path = os.path.join(out, rel)
        size = png_size(path) if os.path.isfile(path) else None
        if not os.path.isfile(path):
            problems.append("%s: missing" % path)
        elif size is None:
            problems.append("%s: not a PNG" % path)
        elif size[0] < 300 or size[1] < 200:
            problems.append("%s: %dx%d, too small for a plot" % (path, size[0], size[1]))
        if rel not in links:
            problems.append("%s: does not link %s" % (md_path, rel))
    for rel in links:
        if not os.path.isfile(os.path.join(out, rel)):
            problems.append("%s: links %s, which does not exist" % (md_path, rel))
    for bad in re.findall(r"\b(nan|NaN|inf|None)\b", md):
        problems.append("%s: the text holds '%s' (a measurement failed)" % (md_path, bad))
        break
    jpath = os.path.join(out, "measurements.json")
    try:
        with open(jpath) as f:
            meas = json.load(f)
        if bool(meas.get("quick")) != quick:
            problems.append("%s: a %s run, expected a %s run" % (jpath, "quick" if meas.get("quick") else "full",
                                                                 "quick" if quick else "full"))
    except (OSError, ValueError) as e:
        problems.append("%s: %s" % (jpath, e))
    return problems


def main():
    args = [a for a in sys.argv[1:] if a != "--quick"]
    if len(args) != 1:
        sys.exit("usage: check_report.py DIR [--quick]")
    problems = check(args[0], "--quick" in sys.argv[1:])
    for p in problems:
        print("check_report: " + p, file=sys.stderr)
    if problems:
        sys.exit(1)
    print("check_report: %s: the text, measurements.json and %d plots are there" % (args[0], len(EXPECTED_PLOTS)))


if __name__ == "__main__":
    main()
