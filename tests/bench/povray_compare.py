#!/usr/bin/python3
"""algray-render against POV-Ray on every gallery surface, side by side in one run.

For each surface of `algray-render --list-gallery`:
  1. `algray-render --surface NAME --export-pov` writes the same scene for POV-Ray 3.7:
     a `polynomial` object `clipped_by` its clip sphere, the floor (a `mesh2` square), one parallel
     light with shadows, ambient light, the same camera;
  2. POV-Ray renders it (1 thread, no anti-aliasing: one ray per pixel);
  3. `algray-render --integrator direct --spp 1 --threads 1` renders the same scene;
  4. whole-process wall times (process start to exit, scene parsing and BVH/cell
     building included) and their ratio are printed, with the number of pixels whose
     colours differ by more than a tolerance.

Usage:  /usr/bin/python3 tests/bench/povray_compare.py [--build build] [--out DIR]
        [--size 512] [--tiny] [--only NAME ...] [--sturm] [--picture NAME]
Writes DIR/povray_compare.md (the table) and DIR/<name>-{pov,algray}.png; with
--picture NAME also DIR/povray-vs-algray.png (POV-Ray left, algray right).
Noisy machine: the two renders of one surface run back to back, so their ratio is the
meaningful figure, not the absolute times.
"""
import argparse
import os
import re
import shutil
import statistics
import subprocess
import sys
import time


def run_timed(cmd, **kw):
    start = time.perf_counter()
    proc = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, **kw)
    return time.perf_counter() - start, proc


def read_png(path):
    import matplotlib.image as mpimg  # /usr/bin/python3 has matplotlib (Debian)

    img = mpimg.imread(path)
    return img[..., :3]


def differing_pixels(a_path, b_path, tolerance):
    """Pixels where any channel differs by more than tolerance/255."""
    import numpy as np

    a, b = read_png(a_path), read_png(b_path)
    if a.shape != b.shape:
        return None
    return int(np.count_nonzero(np.max(np.abs(a - b), axis=2) > tolerance / 255.0))


def main():
    root = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--build", default=os.path.join(root, "build"))
    ap.add_argument("--out", default=os.path.join(root, "build", "povray_compare"))
    ap.add_argument("--size", type=int, default=512)
    ap.add_argument("--tiny", action="store_true", help="two surfaces at 96x96 (smoke run)")
    ap.add_argument("--only", nargs="*", help="surface names")
    ap.add_argument("--sturm", action="store_true", help="POV-Ray with Sturm root isolation")
    ap.add_argument("--tolerance", type=float, default=16, help="per-channel difference, in 1/255")
    ap.add_argument("--picture", help="surface for the side-by-side picture")
    args = ap.parse_args()

    exe = os.path.join(args.build, "examples", "render", "algray-render")
    povray = shutil.which("povray")
    if not os.access(exe, os.X_OK):
        sys.exit(f"povray_compare: no {exe}; build algray-render first")
    if not povray:
        sys.exit("povray_compare: povray is not installed (Debian package povray)")
    os.makedirs(args.out, exist_ok=True)
    size = 96 if args.tiny else args.size

    listing = subprocess.run([exe, "--list-gallery"], stdout=subprocess.PIPE, text=True, check=True).stdout
    surfaces = []
    for line in listing.splitlines():
        parts = line.split()
        if len(parts) >= 3 and parts[1] == "degree":
            surfaces.append((parts[0], int(parts[2])))
    if args.only:
        surfaces = [s for s in surfaces if s[0] in args.only]
    if args.tiny:
        surfaces = surfaces[:2]

    # Warm-up, untimed: both programs once on a tiny image, so that the first timed
    # surface does not pay for reading the shared libraries (OpenImageIO's 264, Embree)
    # from disk (measured: the first surface of a run took 0.1-0.15 s more).
    if surfaces:
        warm_pov = os.path.join(args.out, "warm-up.pov")
        subprocess.run([exe, "--surface", surfaces[0][0], "--width", "16", "--height", "16",
                        "--export-pov", warm_pov], check=True)
        subprocess.run([povray, f"+I{warm_pov}", f"+O{os.path.join(args.out, 'warm-up-pov.png')}",
                        "+W16", "+H16", "+WT1", "-D", "-GA", "-V"], cwd=args.out, capture_output=True)
        subprocess.run([exe, "--surface", surfaces[0][0], "--width", "16", "--height", "16", "-q",
                        "-o", os.path.join(args.out, "warm-up-algray.png")], capture_output=True)

    rows = []
    print(f"{'surface':<16} {'deg':>3} {'POV-Ray s':>10} {'algray s':>9} {'ratio':>7} {'differing px':>13}")
    for name, degree in surfaces:
        pov_file = os.path.join(args.out, f"{name}.pov")
        pov_png = os.path.join(args.out, f"{name}-pov.png")
        alg_png = os.path.join(args.out, f"{name}-algray.png")
        common = ["--surface", name, "--width", str(size), "--height", str(size)]
        export = [exe] + common + ["--export-pov", pov_file] + (["--sturm"] if args.sturm else [])
        subprocess.run(export, check=True)
        # POV-Ray: 1 thread, no anti-aliasing, no display, PNG with the sRGB curve.
        pov_cmd = [povray, f"+I{pov_file}", f"+O{pov_png}", f"+W{size}", f"+H{size}", "+WT1", "-A",
                   "-D", "+FN", "File_Gamma=sRGB", "-GA", "-V"]
        alg_cmd = [exe] + common + ["--integrator", "direct", "--spp", "1", "--threads", "1", "-q",
                                    "-o", alg_png]
        t_pov, p_pov = run_timed(pov_cmd, cwd=args.out)
        t_alg, p_alg = run_timed(alg_cmd)
        if p_pov.returncode != 0 or not os.path.exists(pov_png):
            print(f"{name:<16} {degree:>3}  POV-Ray failed: {p_pov.stderr.strip().splitlines()[-1:]}")
            rows.append((name, degree, None, t_alg, None, None, None))
            continue
        if p_alg.returncode != 0:
            print(f"{name:<16} {degree:>3}  algray-render failed: {p_alg.stderr.strip()}")
            continue
        diff = differing_pixels(pov_png, alg_png, args.tolerance)
        ratio = t_pov / t_alg
        # algray-render's own figure: the render loop only (no start-up, no scene build).
        m = re.search(r": ([0-9.]+) s, ([0-9]+) rays", p_alg.stdout)
        t_loop = float(m.group(1)) if m else None
        rows.append((name, degree, t_pov, t_alg, ratio, diff, t_loop))
        print(f"{name:<16} {degree:>3} {t_pov:>10.3f} {t_alg:>9.3f} {ratio:>7.1f} {diff:>13}"
              f"   (render loop {t_loop:.3f} s)", flush=True)

    ratios = [r[4] for r in rows if r[4] is not None]
    table = [f"POV-Ray 3.7 (`polynomial`{', `sturm`' if args.sturm else ''}, `clipped_by` sphere, "
             f"1 thread, no anti-aliasing) vs `algray-render --integrator direct --spp 1 --threads 1`, "
             f"{size}x{size}, whole-process wall time, one run on this machine "
             f"(pixels differing by more than {args.tolerance:g}/255 in a channel, of {size * size}).",
             "",
             "| surface | degree | POV-Ray (s) | algray (s) | speed-up | differing pixels | algray render loop (s) |",
             "|---|---:|---:|---:|---:|---:|---:|"]
    for name, degree, t_pov, t_alg, ratio, diff, t_loop in rows:
        pov = f"{t_pov:.3f}" if t_pov is not None else "failed"
        loop = f"{t_loop:.3f}" if t_loop is not None else "n/a"
        table.append(f"| {name} | {degree} | {pov} | {t_alg:.3f} | "
                     f"{f'{ratio:.1f}x' if ratio else 'n/a'} | {diff if diff is not None else 'n/a'} | {loop} |")
    if ratios:
        summary = (f"Median speed-up {statistics.median(ratios):.1f}x, minimum {min(ratios):.1f}x "
                   f"over {len(ratios)} surfaces.")
        table += ["", summary]
        print(summary)
    with open(os.path.join(args.out, "povray_compare.md"), "w") as f:
        f.write("\n".join(table) + "\n")
    if args.picture:
        a = os.path.join(args.out, f"{args.picture}-pov.png")
        b = os.path.join(args.out, f"{args.picture}-algray.png")
        if os.path.exists(a) and os.path.exists(b) and shutil.which("oiiotool"):
            subprocess.run(["oiiotool", a, b, "--mosaic", "2x1", "-o",
                            os.path.join(args.out, "povray-vs-algray.png")], check=True)
    print(f"table: {os.path.join(args.out, 'povray_compare.md')}")


if __name__ == "__main__":
    main()
