#!/usr/bin/python3
"""Run time against error for the whole intersector, one figure per ray class.

Reads the CSV written by tests/bench/intersector_report (the pooled rows, surface "ALL")
and draws, for each ray class, ns per ray (geometric mean over the gallery surfaces)
against the p99 hit-position error relative to the clip radius, where a hit/miss
disagreement on a well-conditioned ray counts as an error of one clip radius (column
werr_p99; for singular rays the distance of the hit from the node, node_werr_p99). The
Pareto front (nothing both faster and more accurate) is marked; because the
machine is noisy, a configuration dominates another only when it is faster by more than
the noise margin (--time-margin, default 10 %) and not less accurate by more than a factor
--error-margin (default 2), or more accurate by more than that factor and not slower.

    /usr/bin/python3 tests/bench/plot_intersector.py docs/intersector.csv --out docs

writes docs/intersector-<class>.png, plus docs/intersector-all.png for all classes together
(geometric mean of ns per ray over the classes, worst error of any class), and prints whether the default configuration is on
the front of each class. Uses matplotlib (the Debian python3-matplotlib: run it with
/usr/bin/python3).
"""
import argparse
import csv
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

ERROR_FLOOR = 1e-17  # an exact answer is drawn here (log axis)


def load(path):
    with open(path, newline="") as f:
        return [r for r in csv.DictReader(f) if r["surface"] == "ALL"]


def number(text):
    try:
        v = float(text)
    except ValueError:
        return math.nan
    return v


def aggregate(rows):
    """Pseudo-class "all": per configuration the geometric mean of ns per ray over the ray
    classes and the worst error of any class (a configuration must be good everywhere)."""
    out = []
    for cfg in dict.fromkeys(r["config"] for r in rows):
        mine = [r for r in rows if r["config"] == cfg]
        errs = [number(r["node_werr_p99"] if r["class"] == "singular" else r["werr_p99"]) for r in mine]
        errs = [e for e in errs if not math.isnan(e)]
        if not errs:
            continue
        ns = math.exp(sum(math.log(number(r["ns_per_ray"])) for r in mine) / len(mine))
        agg = {k: "" for k in mine[0]}
        agg.update(surface="ALL", config=cfg, **{"class": "all"}, ns_per_ray=f"{ns:.1f}", werr_p99=f"{max(errs):.3e}",
                   node_werr_p99="nan", disagree=str(sum(int(r["disagree"]) for r in mine)))
        out.append(agg)
    return out


def dominates(a, b, time_margin, error_margin):
    """a dominates b beyond the measurement noise."""
    faster = a["ns"] < b["ns"] * (1.0 - time_margin)
    not_slower = a["ns"] <= b["ns"] * (1.0 + time_margin)
    more_accurate = a["err"] * error_margin < b["err"]
    not_worse = a["err"] <= b["err"] * error_margin
    return (faster and not_worse) or (more_accurate and not_slower)


def front(points, time_margin, error_margin):
    return [p for p in points if not any(dominates(q, p, time_margin, error_margin) for q in points if q is not p)]


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("csv")
    ap.add_argument("--out", default=".")
    ap.add_argument("--time-margin", type=float, default=0.10)
    ap.add_argument("--error-margin", type=float, default=2.0)
    ap.add_argument("--machine", default="", help="machine note for the figure titles")
    ap.add_argument("--markdown", action="store_true", help="also print the pooled rows as Markdown tables")
    args = ap.parse_args()

    rows = load(args.csv)
    if not rows:
        sys.exit(f"{args.csv}: no pooled rows (surface ALL)")
    os.makedirs(args.out, exist_ok=True)
    rows = rows + aggregate(rows)
    classes = list(dict.fromkeys(r["class"] for r in rows))
    summary = []
    for cls in classes:
        points = []
        for r in rows:
            if r["class"] != cls:
                continue
            # Singular rays are ill-conditioned by design: their error axis is the distance of
            # the hit from the node when the node is the first intersection (a miss = 1).
            err = number(r["node_werr_p99"] if cls == "singular" else r["werr_p99"])
            if math.isnan(err):
                continue  # no well-conditioned ray in this class
            points.append({"name": r["config"], "ns": number(r["ns_per_ray"]), "err": max(err, ERROR_FLOOR),
                           "disagree": int(r["disagree"])})
        if not points:
            continue
        on_front = front(points, args.time_margin, args.error_margin)
        names_on_front = {p["name"] for p in on_front}
        fig, ax = plt.subplots(figsize=(8.4, 4.8))
        cmap = plt.get_cmap("tab20")
        for i, p in enumerate(points):
            is_default = p["name"] == "default"
            marker = "*" if is_default else ("o" if p["disagree"] == 0 else "X")
            label = p["name"] + (f" ({p['disagree']} disagree)" if p["disagree"] else "")
            if p["name"] in names_on_front:
                label += "  [front]"
                ax.scatter(p["err"], p["ns"], marker="o", s=260, facecolors="none", edgecolors="tab:red",
                           linewidths=1.5, zorder=2)
            ax.scatter(p["err"], p["ns"], marker=marker, s=170 if is_default else 50, color=cmap(i % 20),
                       edgecolors="black", linewidths=0.4, zorder=3, label=label)
        fp = sorted(on_front, key=lambda p: p["err"])
        ax.step([p["err"] for p in fp], [p["ns"] for p in fp], where="post", color="tab:red", lw=1, alpha=0.6,
                label="Pareto front (within noise)")
        ax.set_xscale("log")
        if cls == "singular":
            ax.set_xlabel("p99 distance of the hit from the node / clip radius (miss = 1)")
        elif cls == "all":
            ax.set_xlabel("worst p99 error of any ray class / clip radius (disagreement = 1)")
        else:
            ax.set_xlabel("p99 hit-position error / clip radius (disagreement = 1)")
        ax.set_ylabel("ns per ray (geometric mean over surfaces" + (" and classes)" if cls == "all" else ")"))
        title = f"{cls} rays: run time against error"
        if args.machine:
            title += f"\n{args.machine}"
        ax.set_title(title, fontsize=10)
        ax.grid(True, which="both", alpha=0.3)
        ax.set_yscale("log")
        ax.legend(loc="center left", bbox_to_anchor=(1.01, 0.5), fontsize=7, frameon=False)
        fig.tight_layout()
        path = os.path.join(args.out, f"intersector-{cls}.png")
        fig.savefig(path, dpi=110)
        plt.close(fig)
        default_on = "default" in names_on_front
        summary.append((cls, default_on, sorted(names_on_front)))
        print(f"{path}: default {'ON' if default_on else 'NOT on'} the front; front = {', '.join(sorted(names_on_front))}")
    if args.markdown:
        print_markdown(rows, {c: f for c, _, f in summary})
    return 0


def fmt(text):
    v = number(text)
    return "n/a" if math.isnan(v) else f"{v:.1e}"


def print_markdown(rows, fronts):
    """The tables of the README section: the default per class, every configuration against it."""
    classes = list(dict.fromkeys(r["class"] for r in rows))
    configs = list(dict.fromkeys(r["config"] for r in rows))
    by = {(r["class"], r["config"]): r for r in rows}
    print("\n**The default configuration, per ray class** (all gallery surfaces pooled):\n")
    print("| ray class | rays | well-cond. | disagree | err median | err p99 | err max | float tfar p99 "
          "| all rays: disagree | speckles | ns/ray | default on the front |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|")
    for c in classes:
        if c == "all":
            continue
        r = by[(c, "default")]
        on = "yes" if "default" in fronts.get(c, []) else "**no**"
        print(f"| {c} | {r['rays']} | {r['well_conditioned']} | {r['disagree']} | {fmt(r['err_median'])} "
              f"| {fmt(r['err_p99'])} | {fmt(r['err_max'])} | {fmt(r['ferr_p99'])} | {r['disagree_all']} "
              f"| {r['speckles']} | {number(r['ns_per_ray']):.0f} | {on} |")
    r = by.get(("singular", "default"))
    if r:
        print(f"\nSingular rays whose node is the first intersection: {r['node_rays']}; the default misses "
              f"{r['node_miss']}, its hits lie within {fmt(r['node_err_max'])} clip radii of the node "
              f"(median {fmt(r['node_err_median'])}).")
    print("\n**Every configuration against the default**: run time ratio (measured side by side in one run) "
          "and `werr` (p99 error, a disagreement counted as 1 clip radius; singular rays: distance from the "
          "node, a miss = 1); *all* = geometric mean of the time ratios and the worst `werr` over the classes; "
          "[F] = on the Pareto front.\n")
    print("| configuration | " + " | ".join(f"{c}" for c in classes) + " |")
    print("|---|" + "---:|" * len(classes))
    for cfg in configs:
        cells = []
        for c in classes:
            r, d = by.get((c, cfg)), by.get((c, "default"))
            if not r:
                cells.append("–")
                continue
            ratio = number(r["ns_per_ray"]) / number(d["ns_per_ray"])
            w = r["node_werr_p99"] if c == "singular" else r["werr_p99"]
            mark = " [F]" if cfg in fronts.get(c, []) else ""
            cells.append(f"{ratio:.2f}x, {fmt(w)}{mark}")
        print(f"| {cfg} | " + " | ".join(cells) + " |")


if __name__ == "__main__":
    sys.exit(main())
