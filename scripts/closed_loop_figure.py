#!/usr/bin/env python3
"""The distance to the net of closed-loop runs side by side, as one SVG for docs/.

    scripts/closed_loop_figure.py OUT.svg "title" LABEL=RUN/closed_loop.csv [LABEL=...]

Reads the named columns of closed_loop.csv (contract 1.1): the true distance of each run, and the
reference of the first. Standard library only.
"""
import csv
import math
import sys

COLOURS = ["#1f5fa8", "#d07a18", "#3a9a6a", "#b03a2e"]


def read(path):
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    header = [h.lstrip("#") for h in rows[0]]
    col = {name: i for i, name in enumerate(header)}
    t0 = int(rows[1][col["timestamp [ns]"]])
    t, d, ref = [], [], []
    for r in rows[1:]:
        t.append((int(r[col["timestamp [ns]"]]) - t0) * 1e-9)
        d.append(float(r[col["d_net_true [m]"]]))
        ref.append(float(r[col["d_ref [m]"]]))
    return t, d, ref


def main():
    out, title, runs = sys.argv[1], sys.argv[2], sys.argv[3:]
    series = []
    for k, run in enumerate(runs):
        label, path = run.split("=", 1)
        t, d, ref = read(path)
        series.append((label, COLOURS[k % len(COLOURS)], t, d, False))
        if k == 0:
            series.append(("reference", "#444", t, ref, True))
    w, h, left, right, top, bottom = 760, 260, 56, 12, 44, 34
    values = [v for s in series for v in s[3] if math.isfinite(v)]
    t_max = max(max(s[2]) for s in series)
    lo, hi = min(values), max(values)
    lo, hi = math.floor(lo * 10) / 10, math.ceil(hi * 10) / 10
    px = lambda x: left + x / t_max * (w - left - right)
    py = lambda y: top + (1 - (y - lo) / (hi - lo)) * (h - top - bottom)
    o = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{w}" height="{h}" '
         f'font-family="sans-serif" font-size="12">',
         f'<text x="{left}" y="16" font-weight="bold">{title}</text>',
         f'<rect x="{left}" y="{top}" width="{w - left - right}" height="{h - top - bottom}" '
         'fill="#fafafa" stroke="#999"/>']
    y = lo
    while y <= hi + 1e-9:
        o.append(f'<line x1="{left}" x2="{w - right}" y1="{py(y):.1f}" y2="{py(y):.1f}" '
                 f'stroke="#e4e4e4"/><text x="{left - 5}" y="{py(y) + 4:.1f}" '
                 f'text-anchor="end">{y:.1f}</text>')
        y += 0.1 if hi - lo <= 1.0 else 0.5
    for x in range(0, int(t_max) + 1, 10):
        o.append(f'<text x="{px(x):.1f}" y="{h - bottom + 15}" text-anchor="middle">{x}</text>')
    o.append(f'<text x="{(left + w) / 2}" y="{h - 4}" text-anchor="middle">time [s]</text>')
    o.append(f'<text transform="translate(14,{(top + h - bottom) / 2}) rotate(-90)" '
             'text-anchor="middle">distance to the net [m]</text>')
    x = left
    for label, colour, t, v, dashed in series:
        dash = ' stroke-dasharray="5 3"' if dashed else ""
        o.append(f'<line x1="{x}" y1="30" x2="{x + 22}" y2="30" stroke="{colour}" '
                 f'stroke-width="2"{dash}/><text x="{x + 27}" y="34">{label}</text>')
        x += 45 + 7 * len(label)
        points = " ".join(f"{px(a):.1f},{py(b):.1f}" for a, b in zip(t, v) if math.isfinite(b))
        o.append(f'<polyline points="{points}" fill="none" stroke="{colour}" '
                 f'stroke-width="1.5"{dash}/>')
    o.append("</svg>")
    with open(out, "w") as f:
        f.write("\n".join(o) + "\n")


if __name__ == "__main__":
    main()
