#!/usr/bin/env python3
"""Plot the root-solver report (tests/bench/roots_report.cpp).

Usage: /usr/bin/python3 tests/bench/plot_roots.py docs/roots.csv docs/roots.png
       /usr/bin/python3 tests/bench/plot_roots.py --markdown docs/roots.csv  (README tables)
       /usr/bin/python3 tests/bench/plot_roots.py --markdown-full docs/roots.csv  (every column)

One row per interval family (whole ray, one cell). Left: ns per solve against degree.
Right: run time against error (p99 of |t - t_ref| in units of u cond(t_ref)), one marker
curve per method (a point per degree, joined in degree order), so "faster and as accurate"
is down and to the left.
"""
import csv
import sys
from collections import defaultdict

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main(src, dst):
    rows = list(csv.DictReader(open(src)))
    families = sorted({r["family"] for r in rows}, key=lambda f: f != "ray")
    fig, axes = plt.subplots(len(families), 2, figsize=(12, 4.5 * len(families)), squeeze=False)
    for fi, family in enumerate(families):
        curves = defaultdict(list)
        for r in rows:
            if r["family"] != family:
                continue
            label = f'{r["method"]} {r["precision"]}' + (" (any)" if r["query"] == "any" else "")
            curves[label].append(r)
        ax_t, ax_e = axes[fi]
        for ci, (label, rs) in enumerate(sorted(curves.items())):
            color = f"C{ci}"
            rs.sort(key=lambda r: int(r["degree"]))
            deg = [int(r["degree"]) for r in rs]
            ns = [float(r["ns_per_solve"]) for r in rs]
            style = "--" if "float" in label or "(any)" in label else "-"
            ax_t.plot(deg, ns, style, marker="o", ms=3, label=label, color=color)
            if "(any)" in label:
                continue
            err = [max(float(r["err_p99_ucond"]), 1e-2) for r in rs]
            # A curve per method through its degrees in order (the labels name some).
            ax_e.plot(ns, err, style, lw=0.8, ms=4, label=label, color=color,
                      marker="x" if "float" in label else "o")
            for r, x, y in zip(rs, ns, err):
                if int(r["degree"]) in (2, 6, 12, 20, 40):
                    ax_e.annotate(r["degree"], (x, y), fontsize=7, xytext=(2, 2),
                                  textcoords="offset points")
        ax_t.set_yscale("log")
        ax_t.set_xlabel("degree")
        ax_t.set_ylabel("ns per first-root solve")
        ax_t.set_title(f"{family} intervals: time per solve")
        ax_t.grid(True, which="both", alpha=0.3)
        ax_t.legend(fontsize=8)
        ax_e.set_xscale("log")
        ax_e.set_yscale("log")
        ax_e.set_xlabel("ns per solve")
        ax_e.set_ylabel("p99 error / (u cond)  (floored at 0.01)")
        ax_e.set_title(f"{family} intervals: time against error (labels: degree)")
        ax_e.grid(True, which="both", alpha=0.3)
        ax_e.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(dst, dpi=110)


def markdown(src, full=False):
    """The README's summary table per interval family: double precision, first root; with
    full, also ClosedForm, hasRoot, Bernstein's misses and the float solver (docs)."""
    rows = list(csv.DictReader(open(src)))
    get = {(r["family"], r["method"], r["precision"], r["query"], int(r["degree"])): r for r in rows}
    out = []
    extra = (" | ClosedForm ns | Auto any ns | Bernstein missed / noise / false | float Auto ns "
             "| float err p99 | float noise / false" if full else "")
    for family in sorted({r["family"] for r in rows}, key=lambda f: f != "ray"):
        out.append(f"**{family} intervals**\n")
        out.append("| degree | Auto ns | Sturm ns | Sturm / Auto | Bernstein ns | Auto err p99 / max (u cond) "
                   "| Auto missed / noise / false | Sturm missed / noise / false" + extra + " |")
        out.append("|---:|---:|---:|---:|---:|---:|---:|---:|" + ("---:|" * 6 if full else ""))
        for d in sorted({int(r["degree"]) for r in rows if r["family"] == family}):
            a = get.get((family, "Auto", "double", "first", d))
            st = get.get((family, "Sturm", "double", "first", d))
            b = get.get((family, "Bernstein", "double", "first", d))
            if not (a and st):
                continue
            def mnf(r):
                return f'{r["missed"]} / {r["noise_hits"]} / {r["false_hits"]}'
            ta, ts = float(a["ns_per_solve"]), float(st["ns_per_solve"])
            tb = f'{float(b["ns_per_solve"]):.0f}' if b else "-"
            row = (f'| {d} | {ta:.0f} | {ts:.0f} | {ts / ta:.2f} | {tb} '
                   f'| {float(a["err_p99_ucond"]):.2f} / {float(a["err_max_ucond"]):.2f} '
                   f'| {mnf(a)} | {mnf(st)} |')
            if full:
                cf = get.get((family, "ClosedForm", "double", "first", d))
                an = get.get((family, "Auto", "double", "any", d))
                fl = get.get((family, "Auto", "float", "first", d))
                row += (f' {float(cf["ns_per_solve"]):.0f} |' if cf else " - |")
                row += (f' {float(an["ns_per_solve"]):.0f} |' if an else " - |")
                row += (f' {mnf(b)} |' if b else " - |")
                row += (f' {float(fl["ns_per_solve"]):.0f} | {float(fl["err_p99_ucond"]):.2f} '
                        f'| {fl["noise_hits"]} / {fl["false_hits"]} |' if fl else " - | - | - |")
            out.append(row)
        out.append("")
    return "\n".join(out)


if __name__ == "__main__":
    if len(sys.argv) == 3 and sys.argv[1] in ("--markdown", "--markdown-full"):
        print(markdown(sys.argv[2], full=sys.argv[1] == "--markdown-full"))
    elif len(sys.argv) == 3:
        main(sys.argv[1], sys.argv[2])
    else:
        sys.exit("usage: plot_roots.py roots.csv roots.png | plot_roots.py --markdown roots.csv")
