// A/B timing of two builds of the first-root solver in one process.
//
//   roots_ab A.so B.so [--degree 6] [--family cell|ray] [--problems 2000] [--rounds 41]
//            [--method auto|closedform|yuksel|sturm|bernstein] [--seed 42] [--interleave]
//
// A.so and B.so are builds of roots_ab_module (this directory; the target of the same name):
// this tree's, and the other commit's from a second build tree (a git worktree; for commits
// older than the module, copy roots_ab_module.cpp and its CMake lines there). Given the
// same file twice, B is loaded from a copy: an A/A run, which tells the method's resolution
// (and fails, exit 1, unless both answer bit for bit alike).
//
// Why one process: this machine (a VM on 2 cores) drifts between a fast and a slow phase
// within minutes, and in the slow one Auto slowed by 1.6x and Sturm by 1.3x (session 29,
// degree-6 cells: 56 -> 91 ns, 273 -> 362 ns), far more than the 1-5 % most solver
// changes are worth; runs of two separate binaries compare two phases. Here each round
// times one pass of A and one of B over the same problems back to back (their order
// alternating by round) and keeps the ratio B / A; the median of those paired ratios
// cancels the drift (A/A runs: 1.000 +- 0.01, quartiles within 1 %).
// The problems are roots_report's (roots_problems.h, the same seed per degree and family)
// expanded in double. Sturm's ratio is measured after the A/B rounds, paired per round
// too: warm by default (each timed pass after an untimed one of the same method), or with
// --interleave as roots_report runs them (each method right after the others, on branch
// predictors they trained: Auto's degree-6 cells 56 -> 63 ns, session 29), in which mode
// the other methods' passes also run between the A/B rounds. The answers of A and B are
// compared bit for bit.
#include "algray/roots.h"

#include "roots_problems.h"

#include <dlfcn.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <limits>
#include <string>
#include <vector>

namespace {

using algray::bench::quantile;
using EntryPoint = bool (*)(const double*, std::size_t, double, double, int, double*);

struct Problem {
  std::vector<double> c;
  double lo, hi;
};

struct Options {
  const char* a = nullptr;
  const char* b = nullptr;
  int degree = 6, problems = 2000, rounds = 41, seed = 42;
  bool cell = true, interleave = false;
  algray::RootMethod method = algray::RootMethod::Auto;
};

[[noreturn]] void usage(const char* argv0, const std::string& why) {
  std::fprintf(stderr,
               "%s: %s\nusage: %s A.so B.so [--degree 6] [--family cell|ray] [--problems 2000] "
               "[--rounds 41] [--method auto|closedform|yuksel|sturm|bernstein] [--seed 42] "
               "[--interleave]\n",
               argv0, why.c_str(), argv0);
  std::exit(2);
}

int positiveInt(const char* argv0, const char* flag, const char* text, int max) {
  char* end = nullptr;
  const long v = std::strtol(text, &end, 10);
  if (end == text || *end != '\0' || v < 1 || v > max)
    usage(argv0,
          std::string(flag) + " '" + text + "': expected an integer in 1.." + std::to_string(max));
  return static_cast<int>(v);
}

Options parse(int argc, char** argv) {
  Options o;
  int positional = 0;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    auto value = [&] {
      if (i + 1 >= argc) usage(argv[0], arg + " needs a value");
      return argv[++i];
    };
    if (arg == "--degree") {
      o.degree = positiveInt(argv[0], "--degree", value(), algray::kMaxDegree);
    } else if (arg == "--problems") {
      o.problems = positiveInt(argv[0], "--problems", value(), 1000000);
    } else if (arg == "--rounds") {
      o.rounds = positiveInt(argv[0], "--rounds", value(), 100000);
    } else if (arg == "--seed") {
      o.seed = positiveInt(argv[0], "--seed", value(), 1 << 30);
    } else if (arg == "--family") {
      const std::string f = value();
      if (f != "cell" && f != "ray") usage(argv[0], "--family '" + f + "': cell or ray");
      o.cell = f == "cell";
    } else if (arg == "--method") {
      const std::string m = value();
      const char* names[] = {"auto", "closedform", "yuksel", "sturm", "bernstein"};
      const auto it = std::find(std::begin(names), std::end(names), m);
      if (it == std::end(names)) usage(argv[0], "--method '" + m + "': unknown");
      o.method = static_cast<algray::RootMethod>(it - std::begin(names));
    } else if (arg == "--interleave") {
      o.interleave = true;
    } else if (arg.starts_with("--") || positional == 2) {
      usage(argv[0], "unexpected argument '" + arg + "'");
    } else {
      (positional++ == 0 ? o.a : o.b) = argv[i];
    }
  }
  if (positional != 2) usage(argv[0], "two modules expected");
  return o;
}

EntryPoint load(const char* argv0, const std::string& path) {
  // RTLD_LOCAL: the module's symbols stay out of the global scope, so the second module
  // cannot bind to the first one's (and the modules export only the entry point).
  void* handle = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (!handle) usage(argv0, std::string("cannot load ") + path + ": " + dlerror());
  void* entry = dlsym(handle, "algrayAbFirstRoot");
  if (!entry) usage(argv0, path + " has no algrayAbFirstRoot (not a roots_ab_module build)");
  return reinterpret_cast<EntryPoint>(entry);
}

// One pass over all problems; ns per solve. answers[i] is the root, or NaN for none.
double pass(EntryPoint solve, const std::vector<Problem>& ps, algray::RootMethod method,
            std::vector<double>& answers) {
  const int m = static_cast<int>(method);
  const auto t0 = std::chrono::steady_clock::now();
  for (size_t i = 0; i < ps.size(); ++i) {
    double root;
    answers[i] = solve(ps[i].c.data(), ps[i].c.size(), ps[i].lo, ps[i].hi, m, &root)
                     ? root
                     : std::numeric_limits<double>::quiet_NaN();
  }
  const auto t1 = std::chrono::steady_clock::now();
  return std::chrono::duration<double, std::nano>(t1 - t0).count() / ps.size();
}

}  // namespace

int main(int argc, char** argv) {
  const Options o = parse(argc, argv);
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::path pathA = fs::absolute(o.a, ec);
  fs::path pathB = fs::absolute(o.b, ec);
  // dlopen returns the same handle for a path loaded twice: an A/A run loads a copy.
  fs::path copy;
  if (fs::equivalent(pathA, pathB, ec)) {
    copy = fs::temp_directory_path() / ("roots_ab_copy_" + std::to_string(getpid()) + ".so");
    if (!fs::copy_file(pathA, copy, fs::copy_options::overwrite_existing, ec))
      usage(argv[0], "cannot copy " + pathA.string() + " to " + copy.string());
    pathB = copy;
  }
  const EntryPoint solveA = load(argv[0], pathA), solveB = load(argv[0], pathB);
  if (!copy.empty()) fs::remove(copy, ec);  // (mapped: the module stays loaded)

  // roots_report's seed per degree and family (roots_report.cpp: 42 + 2 degree + cell).
  std::mt19937_64 rng(static_cast<uint64_t>(o.seed + 2 * o.degree + (o.cell ? 1 : 0)));
  std::vector<Problem> ps(static_cast<size_t>(o.problems));
  for (Problem& p : ps) {
    const algray::bench::ProblemShape shape =
        algray::bench::randomProblemShape(o.degree, o.cell, rng);
    p.c = algray::bench::expandInDouble(shape);
    p.lo = shape.lo;
    p.hi = shape.hi;
  }

  using algray::RootMethod;
  std::vector<double> answersA(ps.size()), answersB(ps.size()), scratch(ps.size());
  const RootMethod others[] = {RootMethod::ClosedForm, RootMethod::Yuksel, RootMethod::Bernstein,
                               RootMethod::Sturm};
  // ---- A against B: one pass each per round, back to back, the order alternating ----
  // (--interleave: the other methods' passes between rounds, from A and B in turn)
  std::vector<double> timeA, timeB, ratioBA;
  for (int r = 0; r < o.rounds; ++r) {
    const bool aFirst = r % 2 == 0;
    const double first = pass(aFirst ? solveA : solveB, ps, o.method, aFirst ? answersA : answersB);
    const double second =
        pass(aFirst ? solveB : solveA, ps, o.method, aFirst ? answersB : answersA);
    timeA.push_back(aFirst ? first : second);
    timeB.push_back(aFirst ? second : first);
    ratioBA.push_back(timeB.back() / timeA.back());
    if (o.interleave)
      for (RootMethod m : others) pass(aFirst ? solveA : solveB, ps, m, scratch);
  }
  int differ = 0;
  for (size_t i = 0; i < ps.size(); ++i)
    differ += std::memcmp(&answersA[i], &answersB[i], sizeof(double)) != 0;

  // ---- Sturm against A, paired per round ---------------------------------------------
  // Warm (the default): each timed pass follows an untimed pass of the same method, so
  // neither runs on branch predictors the other trained (a Sturm pass just before cost
  // Auto's degree-10 cells 15 %, session 29). Interleaved: each right after the other and
  // the remaining methods, as in roots_report.
  std::vector<double> ratioSturm;
  for (int r = 0; r < o.rounds; ++r) {
    if (!o.interleave) pass(solveA, ps, o.method, scratch);
    const double a = pass(solveA, ps, o.method, scratch);
    if (!o.interleave) pass(solveA, ps, RootMethod::Sturm, scratch);
    const double sturm = pass(solveA, ps, RootMethod::Sturm, scratch);
    ratioSturm.push_back(sturm / a);
    if (o.interleave)
      for (RootMethod m : others)
        if (m != RootMethod::Sturm) pass(solveA, ps, m, scratch);
  }
  const double bOverA = quantile(ratioBA, 0.5), sturmOverA = quantile(ratioSturm, 0.5);
  std::printf(
      "%s degree %d, %d problems, %d rounds%s: A %.1f ns, B %.1f ns; B / A paired median %.4f "
      "(quartiles %.4f %.4f); Sturm / A %.2fx, so Sturm / B %.2fx; answers differ on %d "
      "problems\n",
      o.cell ? "cell" : "ray", o.degree, o.problems, o.rounds, o.interleave ? ", interleaved" : "",
      quantile(timeA, 0.5), quantile(timeB, 0.5), bOverA, quantile(ratioBA, 0.25),
      quantile(ratioBA, 0.75), sturmOverA, sturmOverA / bOverA, differ);
  // An A/A run (the smoke test's) must answer bit for bit alike: the solver is deterministic.
  if (!copy.empty() && differ != 0) {
    std::fprintf(stderr, "A/A run: the two loads of one module answered differently\n");
    return 1;
  }
  return 0;
}
