// A floor under issue #3's speed target: how fast a first-root solver of Auto's kind could
// be on roots_report's problems if it kept nothing but the bare pipeline.
//
//   roots_floor_report [--tiny] [--out DIR] [--problems 2000] [--rounds 61] [--degrees 6,..]
//
// Auto (RootMethod::Auto, roots_subdivide.h) isolates the first root by Bernstein
// subdivision (Descartes' rule of signs; splits between the control polygon's first two
// crossings) and polishes it with Halley's method on the power form, inside a power-of-two
// frame, with rigorous noise bounds on every decision, tangent roots, an exclusion test and
// Yuksel's recursion where the subdivision stalls. The floor here is that pipeline with
// everything the contract needs beyond a plain answer taken out:
//  * no frame (the problems' coefficients and intervals are O(1) already);
//  * no error or noise bounds: a node's signs are its Bernstein coefficients' own, with
//    one fixed margin for the one-variation test;
//  * no tangent roots, no exclusion test, no recursion: a node still undecided at depth 8
//    is given up (the problem then counts as having no root);
//  * a Halley polish that stops after a step below 1e-12 relative (Auto: its predicted
//    error below half an ulp, with noise rules).
// Where its answer agrees with Auto's (column `agree`) it solved the same problem with
// less work than a Bernstein-first solver that keeps the contract can do along the same
// path, so Sturm / floor bounds what tuning Auto's path can reach. (Not at degree 12 and
// above: there Auto's exclusion test and recursion settle near misses with less work than
// the plain subdivision, and the two take about as long.) `floor_free_nm` is the floor
// with every problem it gave up at the depth cap (near misses, mostly) costing nothing: a
// bound more optimistic still.
// All three methods run in one process, one pass each per round (order rotated), on the
// same problems expanded in double (roots_problems.h, roots_report's seed per degree and
// family); ns per solve are the medians over rounds, the ratios the medians of each
// round's ratios. Output: a Markdown table on stdout and DIR/roots-floor.csv.
#include "algray/roots.h"

#include "roots_problems.h"

#include <algorithm>
#include <array>
#include <bit>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

namespace {

constexpr int kMinDegree = 3, kMaxFloorDegree = 20, kMaxDepth = 8;

enum class FloorAnswer { kRoot, kNone, kGaveUp };

// The stripped pipeline for a compile-time degree N (loops unroll, as Auto's up to 20).
template <int N>
struct Floor {
  static constexpr double binomial(int n, int k) {
    double r = 1;
    for (int i = 1; i <= k; ++i) r = r * (n - k + i) / i;
    return r;
  }

  struct Node {
    double b[N + 1];
    double u0, u1;
    int depth;
  };

  static FloorAnswer solve(const double* c, double lo, double hi, double& root) {
    // ---- Bernstein coefficients on [lo, hi]: Taylor shift to lo, scale, Pascal passes
    const double w = hi - lo;
    Node cur;
    for (int j = 0; j <= N; ++j) cur.b[j] = c[j];
#pragma GCC unroll 24
    for (int k = 0; k < N; ++k)
#pragma GCC unroll 24
      for (int i = N - 1; i >= k; --i) cur.b[i] += lo * cur.b[i + 1];
    // C(N, j) from a compile-time table: GCC 12 does not unroll this loop at N = 12 and
    // then computed binomial(N, j) at run time, j divisions each (session 47: the floor's
    // change of basis 89 ns instead of 39, its whole rays 245 ns instead of ~200).
    static constexpr auto kBinomial = [] {
      std::array<double, N + 1> b{};
      for (int j = 0; j <= N; ++j) b[j] = binomial(N, j);
      return b;
    }();
    double p = 1;
    for (int j = 0; j <= N; ++j, p *= w) cur.b[j] = cur.b[j] * p / kBinomial[j];
#pragma GCC unroll 24
    for (int k = 1; k <= N; ++k)
#pragma GCC unroll 24
      for (int i = N; i >= k; --i) cur.b[i] += cur.b[i - 1];
    cur.u0 = 0;
    cur.u1 = 1;
    cur.depth = 0;

    // ---- Left-first subdivision ------------------------------------------------------
    constexpr double kMargin = 1e-14;  // (Auto: the node's rounding and noise bounds)
    Node stack[kMaxDepth + 1];
    int top = 0;
    bool gaveUp = false;
    for (;;) {
      unsigned changes = 0;
      double smallest = std::abs(cur.b[0]);
      for (int i = 0; i < N; ++i) {
        changes |= static_cast<unsigned>(std::signbit(cur.b[i]) != std::signbit(cur.b[i + 1])) << i;
        smallest = std::min(smallest, std::abs(cur.b[i + 1]));
      }
      if (changes != 0 && (changes & (changes - 1)) == 0 && smallest > kMargin) {
        root = polish(c, cur, std::countr_zero(changes), lo, w);
        return FloorAnswer::kRoot;
      }
      if (changes != 0 && cur.depth < kMaxDepth) {
        // Split between the first two crossings (Auto's plain nodes), else at the middle.
        const unsigned rest = changes & (changes - 1);
        double t = 0.5;
        if (rest != 0) {
          const int c1 = std::countr_zero(changes), c2 = std::countr_zero(rest);
          t = std::clamp((8 * (c1 + c2 + 1) + N / 2) / N, 4, 12) / 16.0;
        }
        Node left, right;
        split(cur, t, left, right);
        stack[top++] = right;
        cur = left;
        continue;
      }
      gaveUp |= changes != 0;
      if (top == 0) return gaveUp ? FloorAnswer::kGaveUp : FloorAnswer::kNone;
      cur = stack[--top];
    }
  }

  // de Casteljau at t.
  static void split(const Node& node, double t, Node& left, Node& right) {
    double x[N + 1];
    for (int i = 0; i <= N; ++i) x[i] = node.b[i];
    const double s = 1 - t;
    left.b[0] = x[0];
    right.b[N] = x[N];
#pragma GCC unroll 24
    for (int k = 1; k <= N; ++k) {
#pragma GCC unroll 24
      for (int i = 0; i <= N - k; ++i) x[i] = s * x[i] + t * x[i + 1];
      left.b[k] = x[0];
      right.b[N - k] = x[N - k];
    }
    const double m = node.u0 + (node.u1 - node.u0) * t;
    left.u0 = node.u0;
    left.u1 = m;
    right.u0 = m;
    right.u1 = node.u1;
    left.depth = right.depth = node.depth + 1;
  }

  // Halley's method on the power form from the control polygon's crossing in segment i.
  static double polish(const double* c, const Node& node, int i, double lo, double w) {
    const double u = (i + node.b[i] / (node.b[i] - node.b[i + 1])) / N;
    double x = lo + w * (node.u0 + (node.u1 - node.u0) * u);
    for (int it = 0; it < 8; ++it) {
      double f = c[N], df = 0, dd = 0;
      for (int k = N - 1; k >= 0; --k) {
        dd = dd * x + df;
        df = df * x + f;
        f = f * x + c[k];
      }
      const double step = f * df / (df * df - f * dd);
      x -= step;
      if (!(std::abs(step) > 1e-12 * std::abs(x))) break;
    }
    return x;
  }
};

template <int... Ns>
FloorAnswer floorSolve(int n, const double* c, double lo, double hi, double& root,
                       std::integer_sequence<int, Ns...>) {
  FloorAnswer a = FloorAnswer::kNone;
  static_cast<void>((
      (n == Ns + kMinDegree ? (a = Floor<Ns + kMinDegree>::solve(c, lo, hi, root), true) : false) ||
      ...));
  return a;
}

FloorAnswer floorSolve(int n, const double* c, double lo, double hi, double& root) {
  return floorSolve(n, c, lo, hi, root,
                    std::make_integer_sequence<int, kMaxFloorDegree - kMinDegree + 1>{});
}

struct Problem {
  std::vector<double> c;
  double lo, hi;
};

double median(std::vector<double> v) { return algray::bench::quantile(std::move(v), 0.5); }

struct Row {
  const char* family;
  int degree, problems;
  double autoNs, sturmNs, floorNs, floorFreeNs;
  double sturmOverAuto, sturmOverFloor, sturmOverFloorFree;
  int agree, gaveUp;
};

Row measure(int degree, bool cell, int count, int rounds) {
  std::mt19937_64 rng(static_cast<uint64_t>(42 + 2 * degree + (cell ? 1 : 0)));
  std::vector<Problem> problems;
  for (int i = 0; i < count; ++i) {
    const auto shape = algray::bench::randomProblemShape(degree, cell, rng);
    problems.push_back({algray::bench::expandInDouble(shape), shape.lo, shape.hi});
  }
  // The problems the floor does not give up on, for floor_free_nm; and its agreement.
  std::vector<Problem> settled;
  int agree = 0, gaveUp = 0;
  for (const Problem& p : problems) {
    double ra = 0, rf = 0;
    const bool a = algray::solveFirstRoot(p.c, {}, p.lo, p.hi, ra);
    const FloorAnswer f = floorSolve(degree, p.c.data(), p.lo, p.hi, rf);
    if (f == FloorAnswer::kGaveUp) {
      ++gaveUp;
      continue;
    }
    settled.push_back(p);
    const bool fr = f == FloorAnswer::kRoot;
    agree += a == fr && (!a || std::abs(ra - rf) <= 1e-9 * std::max(1.0, std::abs(ra)));
  }

  const algray::RootOptions autoOptions{};
  algray::RootOptions sturmOptions;
  sturmOptions.method = algray::RootMethod::Sturm;
  using Clock = std::chrono::steady_clock;
  double sink = 0;
  // method 0: Auto, 1: Sturm, 2: the floor
  auto pass = [&](int method, const std::vector<Problem>& set) {
    const algray::RootOptions& options = method == 0 ? autoOptions : sturmOptions;
    const auto t0 = Clock::now();
    for (const Problem& p : set) {
      double r = 0;
      const bool hit = method == 2
                           ? floorSolve(degree, p.c.data(), p.lo, p.hi, r) == FloorAnswer::kRoot
                           : algray::solveFirstRoot(p.c, {}, p.lo, p.hi, r, options);
      if (hit) sink += r;
    }
    return std::chrono::duration<double, std::nano>(Clock::now() - t0).count() /
           static_cast<double>(problems.size());  // per problem of the whole set
  };
  std::vector<double> ns[4], sa, sf, sff;
  for (int round = 0; round < rounds; ++round) {
    double t[4];
    for (int k = 0; k < 4; ++k) {
      const int m = (k + round) % 4;
      t[m] = pass(m == 3 ? 2 : m, m == 3 ? settled : problems);
    }
    for (int m = 0; m < 4; ++m) ns[m].push_back(t[m]);
    sa.push_back(t[1] / t[0]);
    sf.push_back(t[1] / t[2]);
    sff.push_back(t[1] / t[3]);
  }
  if (sink == 0.125) std::puts("");  // keep the answers alive
  return Row{.family = cell ? "cell" : "ray",
             .degree = degree,
             .problems = count,
             .autoNs = median(ns[0]),
             .sturmNs = median(ns[1]),
             .floorNs = median(ns[2]),
             .floorFreeNs = median(ns[3]),
             .sturmOverAuto = median(sa),
             .sturmOverFloor = median(sf),
             .sturmOverFloorFree = median(sff),
             .agree = agree,
             .gaveUp = gaveUp};
}

[[noreturn]] void usage(const char* argv0, const std::string& why) {
  std::fprintf(stderr,
               "%s: %s\nusage: %s [--tiny] [--out DIR] [--problems 2000] [--rounds 61] "
               "[--degrees 6,7]\n",
               argv0, why.c_str(), argv0);
  std::exit(2);
}

int parseInt(const char* argv0, const std::string& text, int lo, int hi) {
  char* end = nullptr;
  const long v = std::strtol(text.c_str(), &end, 10);
  if (text.empty() || *end != '\0' || v < lo || v > hi)
    usage(argv0, "'" + text + "': expected an integer in " + std::to_string(lo) + ".." +
                     std::to_string(hi));
  return static_cast<int>(v);
}

}  // namespace

int main(int argc, char** argv) {
  std::string out;
  int count = 2000, rounds = 61;
  std::vector<int> degrees{6, 7, 8, 9, 10, 11, 12};
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    auto value = [&]() -> std::string {
      if (i + 1 >= argc) usage(argv[0], arg + " needs a value");
      return argv[++i];
    };
    if (arg == "--tiny") {
      count = 50;
      rounds = 3;
      degrees = {6};
    } else if (arg == "--out") {
      out = value();
    } else if (arg == "--problems") {
      count = parseInt(argv[0], value(), 1, 1000000);
    } else if (arg == "--rounds") {
      rounds = parseInt(argv[0], value(), 1, 1000);
    } else if (arg == "--degrees") {
      degrees.clear();
      std::stringstream list(value());
      for (std::string d; std::getline(list, d, ',');)
        degrees.push_back(parseInt(argv[0], d, kMinDegree, kMaxFloorDegree));
    } else {
      usage(argv[0], "unknown argument '" + arg + "'");
    }
  }

  std::vector<Row> rows;
  for (const bool cell : {false, true})
    for (const int d : degrees) rows.push_back(measure(d, cell, count, rounds));

  std::printf(
      "| family | degree | Auto ns | Sturm ns | floor ns | floor, near misses free | Sturm / "
      "Auto | Sturm / floor | Sturm / floor, near misses free | floor agrees with Auto | "
      "floor gave up |\n|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
  for (const Row& r : rows)
    std::printf("| %s | %d | %.0f | %.0f | %.0f | %.0f | %.2f | %.2f | %.2f | %d / %d | %d |\n",
                r.family, r.degree, r.autoNs, r.sturmNs, r.floorNs, r.floorFreeNs, r.sturmOverAuto,
                r.sturmOverFloor, r.sturmOverFloorFree, r.agree, r.problems, r.gaveUp);
  if (!out.empty()) {
    std::filesystem::create_directories(out);
    const std::string path = out + "/roots-floor.csv";
    std::ofstream csv(path);
    csv << "family,degree,problems,auto_ns,sturm_ns,floor_ns,floor_free_nm_ns,sturm_over_auto,"
           "sturm_over_floor,sturm_over_floor_free_nm,agree,gave_up\n";
    for (const Row& r : rows)
      csv << r.family << ',' << r.degree << ',' << r.problems << ',' << r.autoNs << ',' << r.sturmNs
          << ',' << r.floorNs << ',' << r.floorFreeNs << ',' << r.sturmOverAuto << ','
          << r.sturmOverFloor << ',' << r.sturmOverFloorFree << ',' << r.agree << ',' << r.gaveUp
          << '\n';
    if (!csv) {
      std::fprintf(stderr, "%s: cannot write %s\n", argv[0], path.c_str());
      return 1;
    }
    std::printf("wrote %s\n", path.c_str());
  }
  return 0;
}
