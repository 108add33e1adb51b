#!/usr/bin/python3
"""Mutation fuzzer for algray-query and algray-render (best with the ASan+UBSan build).

usage: tests/fuzz/fuzz_tools.py BUILD_DIR OUT_DIR TARGET N [SEED]
  BUILD_DIR  a build tree holding examples/{query,render}/algray-*, e.g. build-asan
             (configure with -DALGRAY_SANITIZE=ON; copy the binaries elsewhere if the tree
             is rebuilt while the fuzzer runs)
  TARGET     q-eq q-csv q-opt q-valid q-diff  (algray-query: mutated equations, ray CSVs,
             options; valid inputs at extreme scales; double against --float)
             r-eq r-valid r-json r-jsurf r-obj r-opt  (algray-render: quick-mode
             equations, JSON scenes, .jsurf files, OBJ meshes, options)
Seeds: the .jsurf files of $ALGRAY_JSURF_DIR (default ../shared/gallery/jsurf beside the
repository), examples/scenes, docs/equations.md's forms. Each case runs with a timeout and
is classified: sanitizer, signal, timeout, error-odd/exit1 (bad input must exit 2 with a
message), ok-* (exit 0 with suspicious output: NaN/inf in OUT.csv or the EXR, no image,
hits outside the clip region or tnear..tfar, double/--float disagreement) or clean-error.
Every case's class and first stderr lines go to OUT_DIR/messages-TARGET.log; the
interesting cases are saved in OUT_DIR/CLASS-TARGET-SEED-N/. ok-hit-suspect (f does not
change sign at a hit) is a weak oracle: rounding noise of ill-conditioned expansions
triggers it.
"""
import json, math, os, random, re, shutil, subprocess, sys, glob, copy, struct, time

BUILD, OUTDIR, TARGET, N = sys.argv[1], sys.argv[2], sys.argv[3], int(sys.argv[4])
SEED = int(sys.argv[5]) if len(sys.argv) > 5 else int(time.time())
R = random.Random(SEED)
QUERY = os.path.join(BUILD, "examples/query/algray-query")
RENDER = os.path.join(BUILD, "examples/render/algray-render")
REPO = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
TIMEOUT = 30
os.makedirs(OUTDIR, exist_ok=True)
WORK = os.path.join(OUTDIR, "work-%s-%d" % (TARGET, os.getpid()))
os.makedirs(WORK, exist_ok=True)
# Sanitizer options: the caller's, else leak detection on and UBSan fatal. (ctest's smoke
# run turns leak detection off: LeakSanitizer's exit-time scan failed now and then under
# load without a reproducible leak, campaign of session 10.)
ENV = dict(os.environ)
ENV.setdefault("ASAN_OPTIONS", "detect_leaks=1:abort_on_error=0")
ENV.setdefault("UBSAN_OPTIONS", "print_stacktrace=1:halt_on_error=1")

# ---------------------------------------------------------------- seeds
JSURF_DIR = os.environ.get("ALGRAY_JSURF_DIR", os.path.join(REPO, "..", "shared", "gallery", "jsurf"))
JSURFS = sorted(glob.glob(os.path.join(JSURF_DIR, "*.jsurf")))
EQUATIONS = []
for f in JSURFS:
    for line in open(f, errors="replace"):
        if line.startswith("surface_equation="):
            EQUATIONS.append(line.split("=", 1)[1].strip().replace("\\", ""))
EQUATIONS += [
    "x^2+y^2+z^2-1", "(x^2 + y^2 + z^2 + R^2 - r^2)^2 = 4*R^2*(x^2 + y^2)",
    ".5*x*y*z - 24/7 + sqrt(2)*pi + y ^2", "x^4 + y^4 + z^4 - a*(x^2+y^2+z^2)",
    "x^6 + y^6 + z^6 - 1", "(x+1e-8)^3 - x^3", "x**2+y**2-z**2-0.1", "2^-1*x^2+y^2+z^2-1",
    "x^2^1+y^2+z^2-exp(0)", "abs(-1)*x^2+ln(e)*y^2+z^2-cos(0)", "z - x*y", "x",
    "-x^2-y^2-z^2+1", "x^2+y^2-1", "(x^2+y^2+z^2)^2-x*y*z-0.1",
    "x\u00b2+y\u00b2+z\u00b2\u22121", "\u03c0\u00b7x\u2074 \u2212 2\u207b\u00b9\u00d7y\u00b2 + z\u00b3",
]
GALLERY = ["torus", "barth-sextic", "chmutov-8", "kummer-quartic", "togliatti-quintic",
           "sarti-dodecic"]
SCENES = [os.path.join(REPO, "examples/scenes", f) for f in
          ("gallery-row.json", "equation-glass.json", "surfer-look.json")]
SCENE_OBJS = [json.load(open(f)) for f in SCENES]

WEIRD_NUMS = ["0", "-0", "1e308", "-1e308", "1e309", "1e-320", "5e-324", "1e-400", "nan", "NaN",
              "inf", "-inf", "Infinity", "0x1p3", "1e17", "1e18", "-1e17", "2147483647",
              "2147483648", "-2147483649", "9223372036854775807", "18446744073709551616",
              "1e1000000", "0.0000000000000000000000001", "3.4e38", "3.5e38", "1.7976931348623157e308",
              "4294967296", "-1", "1e-7", "1e-300", "1e300", "123456789012345678901234567890",
              "00001", "1.", ".5", "+1", "--1", "1e", "e5", "1,5", " 1", "1 ", "\t1"]
WEIRD_STRS = ["", " ", "\x00", "é", "\u2212", "\u00a0", "𝑥", "\ufeff", "\\", "\"", "'", "%s%n",
              "x" * 5000, "(" * 3000, ")" * 10, "^" * 50, "1" * 400, "\n", "\r", "\x7f", "\xff"]
TOKENS = ["x", "y", "z", "+", "-", "*", "/", "^", "**", "(", ")", "=", "sqrt(", "sin(", "cos(",
          "tan(", "exp(", "log(", "ln(", "abs(", "pi", "e", "a", "b", "R", "r", "2", "0", "40",
          "41", "1e308", "1e-308", "0.5", ".", "e5", "1e400", "9999999999", "-", " ", ",", "_",
          "\u00b2", "\u00b3", "\u2074\u2070", "\u207b\u00b9", "\u207a", "\u2212", "\u00b7",
          "\u00d7", "\u00f7", "\u03c0", "\u2009", "\u00b2" * 12, "\U0001d465", "\U0001d44e",
          "\u210e", "\U0001d70b", "\u200b"]


def weird_num():
    r = R.random()
    if r < 0.5:
        return R.choice(WEIRD_NUMS)
    if r < 0.75:
        return repr(R.choice([1, -1]) * 10.0 ** R.uniform(-330, 308))
    return str(R.randint(-(1 << 70), 1 << 70))


def mutate_text(s, alphabet=TOKENS, n=None):
    s = list(s)
    for _ in range(n or R.choice([1, 1, 1, 2, 3, 5, 10])):
        op = R.randrange(11)
        i = R.randrange(len(s) + 1)
        if op == 0 and s:  # delete a span
            j = min(len(s), i + R.randint(1, 8))
            del s[i:j]
        elif op == 1:  # insert a token
            s[i:i] = list(R.choice(alphabet))
        elif op == 2 and s:  # byte flip
            k = R.randrange(len(s))
            s[k] = chr((ord(s[k]) ^ (1 << R.randrange(7))) or 1)
        elif op == 3 and s:  # duplicate a span
            j = min(len(s), i + R.randint(1, 30))
            s[i:i] = s[i:j] * R.randint(1, 4)
        elif op == 4:  # weird number
            s[i:i] = list(weird_num())
        elif op == 5:
            s[i:i] = list(R.choice(WEIRD_STRS[:12]))
        elif op == 6 and s:  # replace a digit run by a weird number
            txt = "".join(s)
            nums = list(re.finditer(r"[0-9.]+(e[-+]?[0-9]+)?", txt))
            if nums:
                m = R.choice(nums)
                txt = txt[:m.start()] + weird_num() + txt[m.end():]
                s = list(txt)
        elif op == 7 and s:  # swap two chars
            a, b = R.randrange(len(s)), R.randrange(len(s))
            s[a], s[b] = s[b], s[a]
        elif op == 8:  # power up
            s[i:i] = list("^" + str(R.choice([2, 3, 10, 20, 39, 40, 41, 100, 1000000, 2**31, 2**32])))
        elif op == 9 and len(s) < 3000:  # wrap
            s = list("(") + s + list(")^" + str(R.randint(0, 5)))
        elif op == 10 and s:  # truncate
            s = s[:i]
    return "".join(s)


def gen_equation():
    r = R.random()
    base = R.choice(EQUATIONS)
    if r < 0.08:
        return R.choice(WEIRD_STRS)
    if r < 0.15:  # deep nesting
        d = R.choice([10, 100, 1000, 5000, 20000, 100000])
        return "(" * d + "x" + ")" * d + "^2+y^2+z^2-1"
    if r < 0.2:  # many unary signs / long sums
        return R.choice(["-" * R.choice([100, 10000, 200000]) + "x^2+y^2+z^2-1",
                         "+".join(["x^2"] * R.choice([100, 10000, 100000])) + "-1",
                         "*".join(["(x+1)"] * R.choice([39, 40, 41, 1000])),
                         "x^2+y^2+z^2-" + "1" * R.choice([300, 310, 400, 10000]),
                         "x^2+y^2+z^2-0." + "0" * R.choice([300, 400, 10000]) + "1"])
    if r < 0.25:  # random token soup
        return "".join(R.choice(TOKENS) for _ in range(R.randint(1, 40)))
    return mutate_text(base)


def gen_params():
    out = []
    names = ["a", "b", "R", "r", "a", "b", "R", "r"] + (["x", "pi", "e", "_", "a1", "sqrt", "", "é"]
                                                        if R.random() < 0.2 else [])
    for name in set(R.sample(names, R.choice([0, 1, 2, 3]))):
        v = R.choice(["1", "0.5", "2", "1.5", "-1", "0.25", weird_num()])
        out.append("%s=%s" % (name, v))
        if R.random() < 0.05:
            out.append("%s=%s" % (name, v))
    if R.random() < 0.05:
        out.append(R.choice(["a", "=1", "a==1", "a=", "a=1=2"]))
    return out


# ---------------------------------------------------------------- running and classifying
STATS = {}
SAVED = 0


def classify(rc, err, timed_out):
    if timed_out:
        return "timeout"
    if "LeakSanitizer has encountered a fatal error" in err and "ERROR: " not in err:
        return "lsan-tracer-flake"
    if re.search(r"AddressSanitizer|runtime error:|LeakSanitizer|UndefinedBehaviorSanitizer", err):
        return "sanitizer"
    if rc < 0:
        return "signal"
    if rc == 0:
        return "ok"
    if rc == 2 and err.strip():
        return "clean-error"
    if rc == 1 and err.strip():
        return "exit1"
    return "error-odd"


def record(kind, case, rc, out, err, extra_files=()):
    global SAVED
    STATS[kind] = STATS.get(kind, 0) + 1
    with open(os.path.join(OUTDIR, "messages-%s.log" % TARGET), "a") as f:
        first = err.strip().splitlines()[:3]
        f.write("%s rc=%s %s\n" % (kind, rc, " | ".join(first)[:400]))
    if kind in ("ok", "clean-error"):
        return
    SAVED += 1
    d = os.path.join(OUTDIR, "%s-%s-%d-%d" % (kind, TARGET, SEED, SAVED))
    os.makedirs(d, exist_ok=True)
    with open(os.path.join(d, "case.json"), "w") as f:
        json.dump(case, f, indent=1)
    with open(os.path.join(d, "stderr.txt"), "w") as f:
        f.write("rc=%s\n%s\n---stdout---\n%s" % (rc, err[-20000:], out[-5000:]))
    for p in extra_files:
        if os.path.exists(p) and os.path.getsize(p) < 5e6:
            shutil.copy(p, d)


def run(argv, case, extra_files=(), timeout=TIMEOUT):
    try:
        p = subprocess.run(argv, capture_output=True, timeout=timeout, env=ENV, cwd=WORK)
        rc, out, err, to = p.returncode, p.stdout.decode(errors="replace"), p.stderr.decode(errors="replace"), False
    except subprocess.TimeoutExpired as e:
        rc, out, err, to = None, (e.stdout or b"").decode(errors="replace"), (e.stderr or b"").decode(errors="replace"), True
    return rc, out, err, to


# ---------------------------------------------------------------- algray-query
def gen_rays():
    rows = []
    n = R.choice([1, 3, 10, 50])
    for _ in range(n):
        kind = R.random()
        if kind < 0.4:  # from outside towards the origin-ish
            o = [R.uniform(-5, 5) for _ in range(3)]
            d = [-c + R.uniform(-0.5, 0.5) for c in o]
        elif kind < 0.7:
            o = [R.uniform(-1, 1) for _ in range(3)]
            d = [R.gauss(0, 1) for _ in range(3)]
        else:
            s = 10.0 ** R.uniform(-300, 300)
            o = [R.gauss(0, 1) * s for _ in range(3)]
            d = [R.gauss(0, 1) * 10.0 ** R.uniform(-300, 300) for _ in range(3)]
        tn = R.choice([0, 0, 0, 1e-3, R.uniform(0, 10)])
        tf = R.choice(["inf", "1e308", repr(tn + R.uniform(0, 100)), repr(tn)])
        rows.append([repr(v) for v in o + d] + [repr(tn), tf])
    return rows


def csv_text(rows, header=None):
    header = header or ["ox", "oy", "oz", "dx", "dy", "dz", "tnear", "tfar"]
    return ",".join(header) + "\n" + "".join(",".join(r) + "\n" for r in rows)


def mutate_csv(rows):
    r = R.random()
    header = ["ox", "oy", "oz", "dx", "dy", "dz", "tnear", "tfar"]
    if r < 0.3:  # field-level
        for _ in range(R.randint(1, 4)):
            row = R.choice(rows)
            row[R.randrange(len(row))] = R.choice([weird_num(), R.choice(WEIRD_STRS[:12]), ""])
        return csv_text(rows)
    if r < 0.45:  # header games
        h = header[:]
        op = R.randrange(5)
        if op == 0:
            R.shuffle(h)
            perm = h
            rows = [[row[header.index(c)] for c in perm] for row in rows]
            h.insert(R.randrange(9), "extra")
            rows = [row[:h.index("extra")] + ["junk"] + row[h.index("extra"):] for row in rows]
        elif op == 1:
            h[R.randrange(8)] = R.choice(["OX", "o x", "", "tfar", "\ufeffox"])
        elif op == 2:
            h = h + h
        elif op == 3:
            return "\ufeff" * R.randint(1, 2) + csv_text(rows, h)
        else:
            return "\r\n".join(csv_text(rows, h).split("\n"))
        return csv_text(rows, h)
    if r < 0.55:
        return R.choice(["", "\n", "\n\n\n", "ox,oy,oz,dx,dy,dz,tnear,tfar", "\x00" * 10,
                         "ox,oy,oz,dx,dy,dz,tnear,tfar\n" + "," * 7 + "\n",
                         "ox,oy,oz,dx,dy,dz,tnear,tfar\n" + "0,0,0,0,0,1,0,inf," * 1000 + "\n",
                         ",".join(["ox"] * 100000) + "\n"])
    if r < 0.6:  # many rows
        rows = rows * R.choice([100, 2000])
        return csv_text(rows)
    return mutate_text(csv_text(rows), alphabet=[",", "\n", "\r", "inf", "nan", "-", "e", "1e400", " ", "\t",
                                                 "0", "\"", "#"])


def query_case(eq=None, params=None, clip=None, rays_text=None, extra=None):
    eq = eq if eq is not None else "x^2+y^2+z^2-1"
    params = params or []
    clip = clip or ["--clip-sphere", "1.5"]
    rays_text = rays_text if rays_text is not None else csv_text(gen_rays())
    rays = os.path.join(WORK, "rays.csv")
    out = os.path.join(WORK, "out.csv")
    if os.path.exists(out):
        os.remove(out)
    with open(rays, "w", encoding="utf-8", errors="surrogateescape") as f:
        f.write(rays_text)
    argv = [QUERY, "--surface", eq] + sum((["--param", p] for p in params), []) + clip + \
           ["--rays", rays, "--out", out, "--threads", "1"] + (extra or [])
    argv = [a.replace("\x00", "")[:120000] for a in argv]
    case = {"argv": argv[1:], "rays": rays_text[:200000]}
    rc, so, se, to = run(argv, case)
    kind = classify(rc, se, to)
    if kind == "ok" and "--help" not in argv:
        kind = check_query_output(rays_text, out, se)
    if kind == "ok" and "--help" not in argv:
        try:
            kind = check_query_hits(eq, params, clip, rays_text, out)
        except Exception as e:
            print("oracle failed:", e)
    record(kind, case, rc, so, se, [rays, out])


def check_query_output(rays_text, out, err):
    try:
        lines = open(out).read().splitlines()
    except OSError:
        return "ok-no-output"
    if not lines or lines[0] != "hit,t,nx,ny,nz":
        return "ok-bad-output"
    for l in lines[1:]:
        f = l.split(",")
        if len(f) != 5:
            return "ok-bad-output"
        v = [float(x) for x in f]
        if any(math.isnan(x) or math.isinf(x) for x in v):
            return "ok-nan-inf"
        if v[0] == 1:
            nn = math.sqrt(v[2] ** 2 + v[3] ** 2 + v[4] ** 2)
            if abs(nn - 1) > 1e-6:
                return "ok-nonunit-normal"
            if v[1] < 0:
                return "ok-negative-t"
    if "failed inside the plugin" in err:
        return "ok-plugin-failures"
    return "ok"


def py_f(eq, params):
    """The equation as a Python function of (x, y, z), or None."""
    if not re.fullmatch(r"[-+*/^().0-9a-zA-Z_ =]*", eq) or len(eq) > 2000:
        return None
    if "=" in eq:
        if eq.count("=") != 1:
            return None
        l, r = eq.split("=")
        eq = "(%s)-(%s)" % (l, r)
    src = eq.replace("^", "**")
    env = {"sqrt": math.sqrt, "sin": math.sin, "cos": math.cos, "tan": math.tan, "exp": math.exp,
           "log": math.log, "ln": math.log, "abs": abs, "pi": math.pi, "e": math.e}
    for p in params:
        k, _, v = p.partition("=")
        try:
            env[k] = float(v)
        except ValueError:
            return None
    try:
        code = compile(src, "eq", "eval")
    except Exception:
        return None
    def f(x, y, z):
        env2 = dict(env, x=x, y=y, z=z)
        return eval(code, env2)
    return f


def check_query_hits(eq, params, clip, rays_text, out):
    f = py_f(eq, params)
    try:
        lines = rays_text.splitlines()
        head = lines[0].split(",")
        idx = [head.index(c) for c in ("ox", "oy", "oz", "dx", "dy", "dz", "tnear", "tfar")]
        rays = [[float(l.split(",")[i]) for i in idx] for l in lines[1:] if l.strip()]
    except Exception:
        return "ok"
    hits = [[float(v) for v in l.split(",")] for l in open(out).read().splitlines()[1:]]
    if len(hits) != len(rays):
        return "ok-row-count"
    for ray, h in zip(rays, hits):
        if h[0] != 1:
            continue
        t = h[1]
        if not (ray[6] * (1 - 1e-12) <= t <= ray[7] * (1 + 1e-12)):
            return "ok-t-outside-interval"
        p = [ray[i] + t * ray[3 + i] for i in range(3)]
        if max(abs(c) for c in p) > 1e100:
            continue
        if clip[0] == "--clip-sphere":
            rad = float(clip[1])
            if math.hypot(*p) > rad * (1 + 1e-5) + 1e-9:
                return "ok-hit-outside-clip"
        if f is None:
            continue
        dn = math.hypot(*ray[3:6])
        step = 1e-7 * max(1.0, math.hypot(*p))
        try:
            vals = [f(*[p[i] + k * step * ray[3 + i] / dn for i in range(3)]) for k in (-1, 0, 1)]
        except Exception:
            continue
        if any(isinstance(v, complex) or math.isnan(v) for v in vals):
            continue
        if vals[1] == 0 or (vals[0] <= 0 <= vals[2]) or (vals[0] >= 0 >= vals[2]):
            continue
        # Tangent hits have no sign change: accept a tiny |f| next to the neighbours.
        if abs(vals[1]) <= 1e-3 * max(abs(vals[0]), abs(vals[2])) or abs(vals[1]) < 1e-9:
            continue
        return "ok-hit-suspect"
    return "ok"


def q_eq():
    eq = gen_equation()
    params = gen_params() if R.random() < 0.5 else (["R=1", "r=0.35"] if "R" in eq else ["a=1.5", "b=0.5"])
    clip = R.choice([["--clip-sphere", "1.5"], ["--clip-sphere", "2"], ["--clip-box", "-1,-1,-1,1,1,1"]])
    query_case(eq, params, clip, extra=(["--float"] if R.random() < 0.3 else []))


def q_csv():
    eq = R.choice(EQUATIONS[:30]) if R.random() < 0.3 else "x^2+y^2+z^2-1"
    p = ["a=1", "b=0.5"] if re.search(r"\ba\b", eq) else []
    query_case(eq, p, None, mutate_csv(gen_rays()), extra=(["--float"] if R.random() < 0.3 else []))


def q_opt():
    clip = []
    r = R.random()
    if r < 0.4:
        clip = ["--clip-sphere", weird_num()]
    elif r < 0.8:
        vals = [weird_num() if R.random() < 0.3 else str(R.choice([-1, 1]) * R.uniform(0.1, 3)) for _ in range(6)]
        if R.random() < 0.5:
            vals = ["-1", "-1", "-1", "1", "1", "1"]
            vals[R.randrange(6)] = weird_num()
        clip = ["--clip-box", ",".join(vals[:R.choice([6, 6, 6, 5, 7])])]
    elif r < 0.9:
        clip = ["--clip-sphere", "1", "--clip-box", "-1,-1,-1,1,1,1"]
    extra = []
    if R.random() < 0.3:
        extra += ["--threads", R.choice(["0", "1", "2", "1025", "-1", "x", "99999999999"])]
    if R.random() < 0.2:
        extra += R.choice([["--float"], ["--bogus"], ["--help"], ["--rays"], ["--out", "/nonexistent/x.csv"],
                           ["--out", "/tmp"], ["--rays", "/nonexistent.csv"], ["--rays", "/tmp"]])
    eq = R.choice(EQUATIONS[:25])
    params = ["a=1", "b=0.5"] if re.search(r"\ba\b", eq) else []
    if R.random() < 0.5:
        params = gen_params()
    query_case(eq, params, clip, extra=extra)


# ---------------------------------------------------------------- algray-render
SMALL = ["--width", "12", "--height", "10", "--spp", "1", "--threads", "1", "--max-depth", "2", "-q"]


def render_case(argv_mid, case_extra=None, files=(), small=True, out_ext=".png"):
    out = os.path.join(WORK, "out" + out_ext)
    for f in (out, out + ".tmp"):
        if os.path.exists(f):
            os.remove(f)
    if small is True:
        small = SMALL
    elif small is False:
        small = []
    argv = [RENDER] + argv_mid + ["-o", out] + small
    argv = [a.replace("\x00", "")[:120000] for a in argv]
    case = {"argv": argv[1:]}
    case.update(case_extra or {})
    rc, so, se, to = run(argv, case)
    kind = classify(rc, se, to)
    if kind == "ok" and "--export-pov" not in argv and "--list-gallery" not in argv and "--help" not in argv:
        if not os.path.exists(out) or os.path.getsize(out) == 0:
            kind = "ok-no-image"
        elif out_ext == ".exr":
            kind = check_exr(out)
    if kind == "ok" and re.search(r"\bnan\b|\binf\b", so + se, re.I):
        kind = "ok-nan-in-text"
    record(kind, case, rc, so, se, list(files) + [out])


def check_exr(path):
    p = subprocess.run(["oiiotool", "--stats", path], capture_output=True, timeout=30)
    t = p.stdout.decode(errors="replace")
    m = re.search(r"NanCount:\s*([0-9 ]+)", t)
    m2 = re.search(r"InfCount:\s*([0-9 ]+)", t)
    if (m and any(int(x) for x in m.group(1).split())) or (m2 and any(int(x) for x in m2.group(1).split())):
        return "ok-nan-image"
    return "ok"


def r_eq():
    eq = gen_equation() if R.random() < 0.8 else R.choice(GALLERY + ["Torus", "torus ", "nope"])
    params = gen_params() if R.random() < 0.5 else (["R=1", "r=0.35"] if "R" in eq else ["a=1.5", "b=0.5"])
    if not re.search(r"\b[abRr]\b", eq) and R.random() < 0.7:
        params = []
    mid = ["--surface", eq] + sum((["--param", p] for p in params), [])
    if R.random() < 0.7:
        mid += ["--clip-sphere", R.choice(["1.5", "2", "1", weird_num()])]
    if R.random() < 0.3:
        mid += ["--integrator", "direct"]
    ext = ".exr" if R.random() < 0.2 else ".png"
    render_case(mid, out_ext=ext)


def json_paths(obj, prefix=()):
    yield prefix
    if isinstance(obj, dict):
        for k, v in obj.items():
            yield from json_paths(v, prefix + (k,))
    elif isinstance(obj, list):
        for i, v in enumerate(obj):
            yield from json_paths(v, prefix + (i,))


def weird_json_value(old):
    r = R.random()
    if r < 0.25:
        return R.choice([None, True, False, 0, -1, 1e300, -1e300, 1e-320, 2**64, -(2**63) - 1, "", "x", [], {},
                         [1], [1, 2], [1, 2, 3, 4], [[1, 2, 3]], {"a": 1}, "gold", 1e17, 1.1e17, 3.5e38,
                         [0, 0, 0], [1e300, 1e300, 1e300], [-1, -1, -1], 0.5, 180, 360, 1e9, 2**31])
    if r < 0.35:
        return float("nan") if R.random() < 0.5 else float("inf") * R.choice([1, -1])
    if isinstance(old, (int, float)) and not isinstance(old, bool):
        return R.choice([old * 10.0 ** R.randint(-40, 40) if abs(old) < 1e260 else old, -old, 0, old + 1e-9, int(old) if math.isfinite(old) else 0,
                         10.0 ** R.uniform(-320, 308)])
    if isinstance(old, str):
        return R.choice([mutate_text(old), old.upper(), old + " ", "", gen_equation()])
    if isinstance(old, list):
        l = copy.deepcopy(old)
        op = R.randrange(4)
        if op == 0 and l:
            l.pop(R.randrange(len(l)))
        elif op == 1:
            l.append(copy.deepcopy(R.choice(l)) if l else 1)
        elif op == 2 and l:
            l[R.randrange(len(l))] = weird_json_value(l[R.randrange(len(l))])
        else:
            l = l * 50
        return l
    if isinstance(old, dict):
        d = copy.deepcopy(old)
        if d and R.random() < 0.5:
            del d[R.choice(list(d))]
        else:
            d[R.choice(["bogus", "type", "radius", "sphere", "box", "matrix", "scale", "color", "texture",
                        "image", "obj", "gallery", "equation", "parameters", "clip", "rotate"])] = \
                R.choice([1, "x", [1, 2, 3], {"radius": 1}, "/nonexistent.png", "../../../etc/passwd",
                          "torus", "x^2+y^2+z^2-1", {"sphere": {"radius": 1}}])
        return d
    return None


def set_path(obj, path, value):
    if not path:
        return value
    cur = obj
    for k in path[:-1]:
        cur = cur[k]
    cur[path[-1]] = value
    return obj


def r_json():
    base = copy.deepcopy(R.choice(SCENE_OBJS))
    r = R.random()
    for _ in range(R.choice([1, 1, 2, 3])):
        paths = list(json_paths(base))
        p = R.choice(paths)
        old = base
        for k in p:
            old = old[k]
        base = set_path(base, p, weird_json_value(old))
    text = json.dumps(base, indent=1)  # NaN/Infinity come out as non-JSON literals
    if r < 0.25:
        text = mutate_text(text, alphabet=["{", "}", "[", "]", ",", ":", "\"", "1e400", "-", "null", "\\u0000",
                                           "\\ud800", "/*", "//", "\n", "é", "true"])
    elif r < 0.3:
        d = R.choice([100, 1000, 100000])
        text = text.rstrip()[:-1] + ", \"render\": " + "[" * d + "]" * d + "}"
    elif r < 0.33:
        text = R.choice(["", "{}", "[]", "null", "{", "\ufeff{}", "{\"render\": {}}", "1", "\"x\"",
                         "{\"surfaces\": [{}]}", "{\"a\":1,\"a\":2}", "{\"render\":{\"width\":1,\"width\":2}}"])
    path = os.path.join(WORK, "scene.json")
    with open(path, "w", encoding="utf-8", errors="surrogateescape") as f:
        f.write(text)
    shutil.copy(os.path.join(REPO, "examples/scenes/tetrahedron.obj"), WORK)
    small = True  # a full-size seed scene takes minutes under ASan
    render_case([path], {"scene": text[:300000]}, [path], small=small,
                out_ext=".exr" if R.random() < 0.2 else ".png")


def r_jsurf():
    src = R.choice(JSURFS)
    lines = open(src, errors="replace").read().splitlines()
    for _ in range(R.choice([1, 1, 2, 3, 5])):
        i = R.randrange(len(lines))
        op = R.randrange(8)
        if op == 0:
            del lines[i]
        elif op == 1:
            lines.insert(i, lines[R.randrange(len(lines))])
        elif op == 2 and "=" in lines[i]:
            k, v = lines[i].split("=", 1)
            vals = v.split(" ")
            vals[R.randrange(len(vals))] = weird_num()
            lines[i] = k + "=" + " ".join(vals)
        elif op == 3 and "=" in lines[i]:
            k, v = lines[i].split("=", 1)
            vs = v.split(" ")
            lines[i] = k + "=" + " ".join(R.choice([vs[:-1], vs + vs[:1], ["x"], [""], vs * 3]))
        elif op == 4:
            lines[i] = mutate_text(lines[i], alphabet=["=", "\\", ":", " ", "#", "!", "\\u00e9", "\\n", "1e400"])
        elif op == 5:
            lines.insert(i, R.choice(["surface_equation=" + gen_equation(), "surface_parameter_a=" + weird_num(),
                                      "surface_parameter_x=1", "scale_factor=" + weird_num(),
                                      "camera_type=" + R.choice(["FOO", "", "ORTHOGRAPHIC_CAMERA"]),
                                      "camera_fov_y=" + weird_num(), "camera_height=" + weird_num(),
                                      "light_status_0=" + R.choice(["ON", "on", "", "MAYBE"]),
                                      "light_intensity_0=" + weird_num(), "surface_equation=",
                                      "unknown_key=1", "\\", "=", "light_position_99=1 1 1",
                                      "light_status_99=ON"]))
        elif op == 6:
            k = [l for l in lines if l.startswith(("rotation_matrix", "camera_transform"))]
            if k:
                key = k[0].split("=")[0]
                m = [R.choice(["0", "1", weird_num(), "1e-300", "1e300"]) for _ in range(R.choice([16, 16, 15, 12, 9]))]
                lines.append(key + "=" + " ".join(m))
        else:
            lines[i:i] = ["surface_equation=" + mutate_text(R.choice(EQUATIONS))]
    text = "\n".join(lines) + R.choice(["\n", "", "\r\n", "\\"])
    if R.random() < 0.05:
        text = R.choice(["", "\n", "#only comment\n", "\x00\x01\x02", "a" * 100000])
    path = os.path.join(WORK, "surf.jsurf")
    with open(path, "w", encoding="utf-8", errors="surrogateescape") as f:
        f.write(text)
    render_case([path], {"jsurf": text}, [path], out_ext=".exr" if R.random() < 0.2 else ".png")


def r_opt():
    mid = []
    base = R.choice([[], [SCENES[R.randrange(3)]], [R.choice(JSURFS)], ["--surface", R.choice(GALLERY)]])
    mid += base
    opts = {"--width": ["1", "2", "0", "-1", "32768", "32769", "1e3", "x", ""],
            "--height": ["1", "2", "0", "-1", "32768", "32769", "1e3", "x", ""],
            "--spp": ["1", "0", "-1", "1048577", "1.5"],
            "--threads": ["0", "1", "2", "1024", "1025", "-1"],
            "--max-depth": ["0", "1", "1000", "1001", "-1"],
            "--seed": ["0", "18446744073709551615", "18446744073709551616", "-1", "x"],
            "--exposure": ["0", "nan", "inf", "-inf", "1e308", "-1e308", "1000", "-1000", "x", "1e400"],
            "--aov": ["depth", "depth,normal,albedo,id", "", ",", "depth,", "foo", "depth,,id"],
            "--integrator": ["path", "direct", "PATH", ""],
            "--clip-sphere": ["1", "0", "-1", "nan", "inf", "1e-300", "1e300", "1e17", "1e18"],
            "--param": ["a=1", "a=nan", "a=inf", "x=1", "a", "a=1e400", "a=0x10", "a= 1", "a=1 "],
            "--export-pov": ["pov.pov", "/nonexistent/x.pov", "/tmp", ""],
            "--sturm": None, "--list-gallery": None, "-o": ["x.png", "x.exr", "x.jpg", "x", "x.foo",
                                                            "/nonexistent/x.png", ".png", "x.PNG"]}
    keys = R.sample(list(opts), R.randint(1, 4))
    small = []
    for i in range(0, len(SMALL) - 1, 2):
        if SMALL[i] not in keys:
            small += SMALL[i:i + 2]
    small.append("-q")
    for k in keys:
        if opts[k] is None:
            mid.append(k)
        else:
            mid += [k, R.choice(opts[k])]
    if any(k in keys for k in ("--width", "--height", "--spp")):
        small = ["--threads", "1"] if "--threads" not in keys else []
        mid += [] if "--spp" in keys else ["--spp", "1"]
        mid += ["-q", "--max-depth", "2"] if "--max-depth" not in keys else ["-q"]
        if "--width" not in keys:
            mid += ["--width", "8"]
        if "--height" not in keys:
            mid += ["--height", "8"]
        # Bound the work: a valid 32768 x 1 image at spp 1 is still fast-ish.
        if "--width" in keys and "--height" in keys:
            w = mid[mid.index("--width") + 1]
            h = mid[mid.index("--height") + 1]
            if w.isdigit() and h.isdigit() and int(w) * int(h) > 200000:
                mid[mid.index("--height") + 1] = "1"
    if "-o" in keys:
        i = mid.index("-o")
        del mid[i:i + 2]
        render_case(mid, small=small, out_ext=R.choice([".png", ".exr", ".jpg", "", ".foo", ".PNG"]))
    else:
        render_case(mid, small=small, out_ext=".png")


def num_mutate(eq):
    """Replace numbers of a valid equation by numbers of any magnitude: stays valid syntax."""
    def rep(m):
        if R.random() < 0.4:
            return repr(R.choice([1, -1]) * 10.0 ** R.uniform(-200, 200)) if R.random() < 0.5 else \
                repr(float(m.group(0) or 1) * (1 + R.choice([1e-15, 1e-8, -1e-12, 0])))
        return m.group(0)
    out = re.sub(r"(?<![\^a-zA-Z_])[0-9]+\.?[0-9]*(e[-+]?[0-9]+)?", rep, eq)
    return out.replace("e+", "e").replace("--", "+")


def extreme_clip():
    r = R.random()
    c = [R.choice([0, 0, R.gauss(0, 1) * 10.0 ** R.uniform(-10, 17)]) for _ in range(3)]
    if r < 0.5:
        return ["--clip-sphere", repr(10.0 ** R.uniform(-120, 120) if R.random() < 0.3 else R.uniform(0.3, 3))]
    size = [10.0 ** R.uniform(-120, 120) if R.random() < 0.2 else R.uniform(0.3, 3) for _ in range(3)]
    lo = [c[i] - size[i] for i in range(3)]
    hi = [c[i] + size[i] for i in range(3)]
    if R.random() < 0.3:  # degenerate-ish thin boxes
        k = R.randrange(3)
        hi[k] = lo[k] + abs(lo[k]) * 1e-15 + 5e-324
    return ["--clip-box", ",".join(repr(v) for v in lo + hi)]


def valid_equation():
    """A seed equation, its numbers mutated 7 times in 10, with values for a and b if it names them."""
    eq = R.choice(EQUATIONS)
    if R.random() < 0.7:
        eq = num_mutate(eq)
    params = ["a=%r" % R.choice([1.0, 0.5, 1e-30, 1e30, 3.0]), "b=%r" % R.choice([0.5, 1e-10, 2.0])] \
        if re.search(r"\b[ab]\b", eq) else []
    return eq, params


def q_valid():
    eq, params = valid_equation()
    rows = gen_rays()
    if R.random() < 0.5:  # origins near the clip region, any scale
        for row in rows:
            sc = 10.0 ** R.uniform(-150, 150)
            for i in range(3):
                row[i] = repr(R.gauss(0, 1) * sc)
    query_case(eq, params, extreme_clip(), csv_text(rows), extra=(["--float"] if R.random() < 0.3 else []))


def r_valid():
    eq, params = valid_equation()
    mid = ["--surface", eq] + sum((["--param", p] for p in params), [])
    mid += ["--clip-sphere", repr(10.0 ** R.uniform(-120, 120) if R.random() < 0.3 else R.uniform(0.3, 3))]
    if R.random() < 0.5:
        mid += ["--integrator", "direct"]
    render_case(mid, out_ext=".exr" if R.random() < 0.3 else ".png")


OBJ_SCENE = {
    "render": {"width": 16, "height": 12, "spp": 2, "max_depth": 3},
    "camera": {"position": [0.5, -3, 1.5], "look_at": [0, 0, 0.5], "fov": 50},
    "materials": {"tex": {"type": "diffuse", "texture": os.path.join(REPO, "docs", "jsurf-import.png")},
                  "glow": {"type": "emissive", "emission": 3},
                  "metal": {"type": "conductor", "color": 0.9, "roughness": 0.2},
                  "glass": {"type": "dielectric", "ior": 1.5}},
    "meshes": [{"obj": "m.obj", "material": "tex"}],
    "lights": [{"type": "point", "position": [2, -3, 5], "intensity": 40}],
    "environment": {"color": 0.3}}


def gen_obj():
    n = R.randint(1, 8)
    lines = ["v %r %r %r" % tuple(R.uniform(-1, 1) for _ in range(3)) for _ in range(n)]
    nn = R.randint(0, 4)
    lines += ["vn %r %r %r" % tuple(R.uniform(-1, 1) for _ in range(3)) for _ in range(nn)]
    nt = R.randint(0, 4)
    lines += ["vt %r %r" % tuple(R.uniform(-2, 2) for _ in range(2)) for _ in range(nt)]
    def idx(count):
        r = R.random()
        if r < 0.97 and count:
            return str(R.randint(1, count))
        return R.choice(["0", "-1", str(-count - 1), str(count + 1), "99999999999", "x", ""])
    for _ in range(R.randint(1, 10)):
        k = R.choice([3] * 12 + [4, 5, 2, 8])
        form = R.choice(["v", "v/t", "v//n", "v/t/n"])
        parts = []
        for _ in range(k):
            if form == "v":
                parts.append(idx(n))
            elif form == "v/t":
                parts.append(idx(n) + "/" + idx(nt))
            elif form == "v//n":
                parts.append(idx(n) + "//" + idx(nn))
            else:
                parts.append(idx(n) + "/" + idx(nt) + "/" + idx(nn))
        lines.append("f " + " ".join(parts))
    text = "\n".join(lines) + "\n"
    if R.random() < 0.5:
        text = mutate_text(text, alphabet=["v ", "vn ", "vt ", "f ", "/", "//", " ", "\n", "nan", "inf", "1e39",
                                           "-", "0", "#", "\\\n", "mtllib x.mtl", "usemtl a", "o x", "g y"])
    return text


def r_obj():
    text = gen_obj()
    with open(os.path.join(WORK, "m.obj"), "w", encoding="utf-8", errors="surrogateescape") as f:
        f.write(text)
    sc = copy.deepcopy(OBJ_SCENE)
    sc["meshes"][0]["material"] = R.choice(["tex", "glow", "metal", "glass"])
    if R.random() < 0.3:
        sc["meshes"][0]["transform"] = R.choice([{"scale": [1, 1, 1e-30]}, {"rotate": [30, 40, 50]},
                                                 {"scale": -1}, {"scale": 1e-20}])
    path = os.path.join(WORK, "scene.json")
    with open(path, "w") as f:
        json.dump(sc, f)
    render_case([path], {"obj": text}, [path, os.path.join(WORK, "m.obj")], small=["--threads", "1", "-q"],
                out_ext=".exr")


def q_diff():
    """The same rays in double and --float: hit/miss and t must mostly agree."""
    eq = R.choice(EQUATIONS)
    if R.random() < 0.3:
        eq = num_mutate(eq)
    params = ["a=1", "b=0.5"] if re.search(r"\b[ab]\b", eq) else []
    rows = gen_rays()
    scale = 10.0 ** R.choice([0, 0, R.uniform(-30, 30), R.uniform(-150, 150)])
    if scale != 1.0:  # the whole problem scaled: x -> x / scale
        eq = eq.replace("x", "(x/%r)" % scale).replace("y", "(y/%r)" % scale).replace("z", "(z/%r)" % scale)
        for row in rows:
            for i in range(3):
                row[i] = repr(float(row[i]) * scale)
    clip = ["--clip-sphere", repr(R.choice([1.5, 2.0, 3.0]) * scale)]
    text = csv_text(rows)
    res = []
    for extra in ([], ["--float"]):
        query_case(eq, params, clip, text, extra=extra)
        out = os.path.join(WORK, "out.csv")
        try:
            res.append([[float(v) for v in l.split(",")] for l in open(out).read().splitlines()[1:]])
        except OSError:
            return
    a, b = res
    if len(a) != len(b):
        return
    bad = 0
    for ra, rb in zip(a, b):
        if ra[0] != rb[0]:
            bad += 1
        elif ra[0] == 1 and abs(ra[1] - rb[1]) > 1e-3 * max(abs(ra[1]), abs(rb[1])):
            bad += 1
    if bad > max(1, len(a) // 10):
        record("diff-double-float", {"argv": [eq] + params + clip, "rays": text, "double": a, "float": b},
               0, "", "%d of %d rays disagree" % (bad, len(a)))


FUZZ = {"q-diff": q_diff, "r-obj": r_obj, "q-valid": q_valid, "r-valid": r_valid, "q-eq": q_eq, "q-csv": q_csv, "q-opt": q_opt, "r-eq": r_eq, "r-json": r_json, "r-jsurf": r_jsurf,
        "r-opt": r_opt}
t0 = time.time()
for i in range(N):
    FUZZ[TARGET]()
    if (i + 1) % 50 == 0:
        print("%s seed %d: %d cases %.0fs %s" % (TARGET, SEED, i + 1, time.time() - t0, STATS), flush=True)
print("FINAL %s seed %d: %d cases %.0fs %s" % (TARGET, SEED, N, time.time() - t0, STATS), flush=True)
# Non-zero when a case crashed, hung or tripped a sanitizer (the ctest smoke run's verdict;
# the other classes are for a human to read).
sys.exit(1 if any(STATS.get(k, 0) for k in ("sanitizer", "signal", "timeout")) else 0)
