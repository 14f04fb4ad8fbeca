# SPDX-License-Identifier: GPL-3.0-or-later
"""Structural checks of sensorscope's SVG figures with a real XML parser.

usage: svgcheck.py [--width PX] [--min-px PX] FILE.svg...

For each file: the document parses (xml.etree, expat) with an <svg> root
and a viewBox; every axes that holds data has an x and a y label with text
and a frame (plot-area); no legend or note box overlaps the plot area of
any axes, and each lies inside the figure; every text, shown with the
figure scaled to at most --width px wide (default 1100, the report's
column at a 1280 px window), is at least --min-px px tall (default 10).
Prints one line per file; exits 1 when a check fails.
"""
import os
import sys
import xml.etree.ElementTree as ET

NS = "{http://www.w3.org/2000/svg}"


def cls(e):
    return e.get("class", "").split()


def groups(root, name):
    return [g for g in root.iter(NS + "g") if name in cls(g)]


def rect_of(e):
    return tuple(float(e.get(k)) for k in ("x", "y", "width", "height"))


def first_rect(g):
    for r in g.iter(NS + "rect"):
        return rect_of(r)
    return None


def overlap(a, b):
    return (a[0] < b[0] + b[2] and b[0] < a[0] + a[2] and
            a[1] < b[1] + b[3] and b[1] < a[1] + a[3])


def text_of(g):
    return "".join("".join(t.itertext()) for t in g.iter(NS + "text")).strip()


def check(path, width, min_px):
    errs = []
    try:
        root = ET.parse(path).getroot()
    except ET.ParseError as e:
        return ["not well-formed XML: %s" % e], {}
    if root.tag != NS + "svg":
        return ["root element is %s, not svg" % root.tag], {}
    vb = root.get("viewBox", "").split()
    if len(vb) != 4:
        return ["no viewBox"], {}
    fw, fh = float(vb[2]), float(vb[3])
    scale = min(1.0, width / fw)
    axes = groups(root, "axes")
    if not axes:
        errs.append("no axes")
    areas = []
    for k, ax in enumerate(axes):
        pa = [g for g in ax if NS + "g" == g.tag and "plot-area" in cls(g)]
        if not pa or first_rect(pa[0]) is None:
            errs.append("axes %d: no plot-area frame" % k)
            continue
        areas.append(first_rect(pa[0]))
        data = [g for g in ax if "data" in cls(g)]
        drawn = data and any(e.tag in (NS + "polyline", NS + "polygon",
                                       NS + "circle", NS + "rect")
                             for e in data[0].iter())
        if drawn:
            for lab in ("xlabel", "ylabel"):
                g = [g for g in ax.iter(NS + "g") if lab in cls(g)]
                if not g or not text_of(g[0]):
                    errs.append("axes %d: no %s" % (k, lab))
    boxes = groups(root, "legend") + groups(root, "note")
    for b in boxes:
        r = first_rect(b)
        if r is None:
            errs.append("%s without a box" % cls(b)[0])
            continue
        for a in areas:
            if overlap(r, a):
                errs.append("%s box %s overlaps the plot area %s" %
                            (cls(b)[0], r, a))
        if r[0] < 0 or r[1] < 0 or r[0] + r[2] > fw + 0.5 or \
                r[1] + r[3] > fh + 0.5:
            errs.append("%s box %s outside the %gx%g figure" %
                        (cls(b)[0], r, fw, fh))
    smallest = None
    for t in root.iter(NS + "text"):
        base = float(t.get("font-size", "16"))
        sizes = [base] if (t.text or "").strip() else []
        for s in t.iter(NS + "tspan"):
            if "".join(s.itertext()).strip():
                sizes.append(float(s.get("font-size", base)))
            if (s.tail or "").strip():
                sizes.append(base)
        for s in sizes:
            px = s * scale
            if smallest is None or px < smallest[0]:
                smallest = (px, "".join(t.itertext()))
    if smallest and smallest[0] < min_px - 1e-9:
        errs.append("text %r is %.1f px at %g px wide (< %g)" %
                    (smallest[1], smallest[0], min(fw, width), min_px))
    info = {"axes": len(axes), "boxes": len(boxes),
            "min_text_px": smallest[0] if smallest else None}
    return errs, info


def main(argv):
    width, min_px, files = 1100.0, 10.0, []
    i = 0
    while i < len(argv):
        if argv[i] == "--width":
            width = float(argv[i + 1])
            i += 2
        elif argv[i] == "--min-px":
            min_px = float(argv[i + 1])
            i += 2
        else:
            files.append(argv[i])
            i += 1
    bad = 0
    for f in files:
        errs, info = check(f, width, min_px)
        if errs:
            bad += 1
            for e in errs:
                print("%s: %s" % (os.path.basename(f), e))
        else:
            print("%s: well-formed, %d axes labelled, %d legend and note "
                  "boxes outside the data, smallest text %.1f px" %
                  (os.path.basename(f), info["axes"], info["boxes"],
                   info["min_text_px"] or 0))
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
