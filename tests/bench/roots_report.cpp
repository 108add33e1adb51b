// Speed and accuracy of the first-root solvers side by side (roots.h), on random
// first-root problems of ray-tracing shape, against MPFR references.
//
//   roots_report [--tiny] [--out DIR] [--problems N] [--degrees 3,4]
//
// Problems: for each degree, g(t) = lead * prod(t - r_i) * prod((t - a)^2 + b^2) expanded
// in MPFR and rounded (tests/roots_mpfr.h), with a few real roots along the ray
// (t in [0, 1]), the other roots complex pairs whose real parts are spread over
// [-0.5, 1.5] and whose imaginary parts are log-uniform in [1e-3, 1] (near misses), any
// leading scale. Two families of intervals (lo, hi): "ray", a random piece of [0, 1] of
// length >= 0.1 (a whole ray through the surface's bounds), and "cell", a random piece of
// length 1% to 20% (the span of a ray inside one cell of the plugin's grid); some
// intervals hold no root. The reference is the first certified real root of the *rounded*
// polynomial in (lo, hi) (MPFR Newton from the known roots); problems whose first root is
// not well separated (1e6 u cond >= distance to a neighbour or an end) are skipped, so
// every problem has one right answer. The float rows are timed on every problem but
// scored only on those whose float-rounded polynomial passes the same test at float's u
// (their "problems" column counts those). The report stops with exit code 1 where the kept
// problems' share with a root in the interval differs from the drawn ones' by more than
// 0.15 (a filter that changes what is measured; see makeProblems).
//
// Figures per method, precision and degree: ns per solve (median of 5 interleaved
// repetitions, each starting at another method: see the timing loop), the error
// |t - t_ref| in units of u cond(t_ref) (median, p99, max; u of the precision solved),
// missed roots (a reference root and no answer, or an answer beyond the reference root),
// and answers where there is no reference root or before it, split by their exact
// residual |g(t)| / sum|c_i||t|^i (MPFR): "noise hits" are within the solver's rounding
// bound gamma(2n+1) (grazing hits by the tangent rule, or real roots of the rounded
// polynomial that Newton from the known roots did not reach: at degree >= 16 rounding
// turns some complex pairs into close real pairs), "false hits" are beyond it (not a root
// of the data). Writes DIR/roots.csv, prints a Markdown table.
//
// By outcome (DIR/roots-outcomes.csv and a second table): Auto and Sturm timed apart on
// the problems with a reference root, the near misses (no root, but a complex pair within
// 0.01 of the axis whose real part lies inside the interval: where an exclusion test must
// shrink its node to the pair's distance from the axis while Sturm's count settles it at
// once), and the rest (no root anywhere near), so that a ratio over all problems can be
// read as the mix it is.
//
// Per problem (DIR/roots-spread.csv and a third table, degrees 6-12 where the issue sets its
// 5x target): Auto and Sturm timed on each problem alone (the best of a few short runs of
// the same problem, which trains the branch predictors on it and so flatters the branchy
// Auto), the spread of the per-problem ratio (median, 90th percentile, largest, share of
// problems at 5x or more), and what Sturm / Auto would read if every problem took Auto as
// long as the fastest tenth, or the median, of the problems of its outcome: whether the
// gap to a target is the slow problems' (the tail) or every problem's (the base cost).
#include "algray/roots.h"

#include "../roots_mpfr.h"
#include "roots_problems.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <sstream>
#include <string>
#include <vector>

namespace {

using namespace algray;
using bench::quantile;

struct Problem {
  std::vector<double> c;
  std::vector<float> cf;
  double lo, hi;
  bool hasRoot;       // reference, double coefficients
  test::RefRoot ref;  // first reference root (double polynomial), its conditioning
  bool hasRootF;      // the same for the float-rounded polynomial
  test::RefRoot refF;
  bool floatScored;  // the float reference is well separated (the float rows' problems)
  bool nearPair;     // a complex pair a +- b i with b < 0.01 and a in (lo, hi)
};

enum Outcome { kRoot, kNearMiss, kNone };
const char* const kOutcomeNames[] = {"root", "near miss", "none"};

Outcome outcomeOf(const Problem& p) { return p.hasRoot ? kRoot : p.nearPair ? kNearMiss : kNone; }

struct Method {
  const char* name;
  const char* precision;
  const char* query;
  RootMethod method;
};

const Method kMethods[] = {
    {"Auto", "double", "first", RootMethod::Auto},
    {"ClosedForm", "double", "first", RootMethod::ClosedForm},
    {"Yuksel", "double", "first", RootMethod::Yuksel},
    {"Sturm", "double", "first", RootMethod::Sturm},
    {"Bernstein", "double", "first", RootMethod::Bernstein},
    {"Auto", "float", "first", RootMethod::Auto},
    {"Auto", "double", "any", RootMethod::Auto},
};

// The double-precision first-root row of a method (the outcome table's).
const Method& doubleFirst(RootMethod m) {
  return *std::find_if(std::begin(kMethods), std::end(kMethods), [&](const Method& k) {
    return k.method == m && !std::strcmp(k.precision, "double") && !std::strcmp(k.query, "first");
  });
}

// ClosedForm is Yuksel's recursion above degree 4 (roots.h): no rows of its own there.
bool applies(const Method& m, int degree) {
  return m.method != RootMethod::ClosedForm || degree <= 4;
}

// First certified root of c in (lo, hi) from the given starts; false when there is none
// or when it is not well separated.
bool reference(const std::vector<double>& c, const std::vector<double>& starts, double lo,
               double hi, double u, bool& has, test::RefRoot& root) {
  const auto ref = test::refineAll(c, starts, lo, hi);
  has = !ref.empty();
  if (!has) return true;
  double sep = std::min(ref[0].value - lo, hi - ref[0].value);
  if (ref.size() > 1) sep = std::min(sep, ref[1].value - ref[0].value);
  root = ref[0];
  return 1e6 * u * root.conditioning < sep;
}

// How many problems the generator drew and how many were kept, each with how many of them
// have one of their real roots in the interval (by construction, before rounding).
struct DrawCounts {
  int drawn = 0, drawnWithRoot = 0, kept = 0, keptWithRoot = 0;
};

std::vector<Problem> makeProblems(int degree, int count, bool cell, std::mt19937_64& rng,
                                  DrawCounts& counts) {
  std::vector<Problem> out;
  int attempts = 0;
  while (static_cast<int>(out.size()) < count && attempts++ < 20 * count) {
    const bench::ProblemShape shape = bench::randomProblemShape(degree, cell, rng);
    const std::vector<double>& roots = shape.roots;
    const auto& pairs = shape.pairs;
    const bool withRoot = std::any_of(roots.begin(), roots.end(),
                                      [&](double r) { return r > shape.lo && r < shape.hi; });
    ++counts.drawn;
    counts.drawnWithRoot += withRoot;
    Problem p;
    p.c = test::expand(roots, pairs, shape.lead);
    p.cf.assign(p.c.begin(), p.c.end());
    p.lo = shape.lo;
    p.hi = shape.hi;
    p.nearPair = std::any_of(pairs.begin(), pairs.end(), [&](const auto& ab) {
      return ab.second < 0.01 && ab.first > p.lo && ab.first < p.hi;
    });
    std::vector<double> starts = roots;
    for (auto [a, b] : pairs)
      if (b < 0.05) starts.push_back(a);  // only near pairs can turn real by rounding
    const std::vector<double> cfd(p.cf.begin(), p.cf.end());
    if (!reference(p.c, starts, p.lo, p.hi, 0x1p-53, p.hasRoot, p.ref)) continue;
    // The float rows are scored only where the float-rounded polynomial's first root is
    // well separated at float's u; that filter must not choose the problems of the double
    // rows: at u = 2^-24 it rejects nearly every problem with a root (1e6 u cond is 0.06
    // cond), and until session 23 it left the double rows 9 % problems with a root at
    // degree 6 instead of the shape's ~60 % (the report then measured mostly misses).
    p.floatScored = reference(cfd, starts, p.lo, p.hi, 0x1p-24, p.hasRootF, p.refF);
    out.push_back(std::move(p));
    ++counts.kept;
    counts.keptWithRoot += withRoot;
  }
  return out;
}

struct OutcomeRow {
  const char* family;
  int degree, outcome, problems;
  double autoNs, sturmNs;
};

// Per-problem timings of Auto and Sturm (see the file's header).
struct SpreadRow {
  const char* family;
  int degree, problems;
  double ratioOfMeans, ratioMedian, ratioP90, ratioMax, shareAt5, ifP10, ifMedian;
};

struct Row {
  const Method* m;
  const char* family;
  int degree = 0, problems = 0, missed = 0, falseHits = 0, noiseHits = 0;
  double ns = 0, errMedian = 0, errP99 = 0, errMax = 0;
};

// One pass of a method over all problems; answers[i] < 0 means no root.
double runPass(const Method& m, const std::vector<Problem>& ps, std::vector<double>& answers) {
  RootOptions o;
  o.method = m.method;
  const bool isFloat = std::strcmp(m.precision, "float") == 0;
  const bool any = std::strcmp(m.query, "any") == 0;
  const auto t0 = std::chrono::steady_clock::now();
  for (size_t i = 0; i < ps.size(); ++i) {
    const Problem& p = ps[i];
    if (any) {
      answers[i] = hasRoot(p.c, {}, p.lo, p.hi, o) ? 1 : -1;
    } else if (isFloat) {
      const auto r = firstRoot(std::span<const float>(p.cf), {}, static_cast<float>(p.lo),
                               static_cast<float>(p.hi), o);
      answers[i] = r ? *r : -1;
    } else {
      const auto r = firstRoot(p.c, {}, p.lo, p.hi, o);
      answers[i] = r ? *r : -1;
    }
  }
  const auto t1 = std::chrono::steady_clock::now();
  return std::chrono::duration<double, std::nano>(t1 - t0).count() / ps.size();
}

void score(Row& row, const std::vector<Problem>& ps, const std::vector<double>& answers) {
  const bool isFloat = std::strcmp(row.m->precision, "float") == 0;
  const bool any = std::strcmp(row.m->query, "any") == 0;
  const double u = isFloat ? 0x1p-24 : 0x1p-53;
  // An answer with no reference root at or before it: noise or false, by its residual.
  // The noise rule compares the computed |g| with gamma(2n+1) sum |c_i| |t|^i, and the
  // computed value is itself off by up to gamma(2n) sum |c_i| |t|^i (Horner; Higham, Eq.
  // (5.3)), so an answer the rule accepts has an exact relative residual up to the sum of
  // the two. (With the first alone, until session 27, a float answer at 1.01 times it, at
  // the interval's end, counted as false.)
  auto unexpected = [&](const Problem& p, double t) {
    const int n = static_cast<int>(p.c.size()) - 1;
    const double bound = test::gammaOfUnit(2 * n + 1, u) + test::gammaOfUnit(2 * n, u);
    const std::vector<double> cf(p.cf.begin(), p.cf.end());
    const double resid = test::relativeResidual(isFloat ? cf : p.c, t);
    (resid <= bound ? row.noiseHits : row.falseHits) += 1;
  };
  std::vector<double> errs;
  row.problems = 0;
  for (size_t i = 0; i < ps.size(); ++i) {
    const Problem& p = ps[i];
    if (isFloat && !p.floatScored) continue;
    ++row.problems;
    const bool has = isFloat ? p.hasRootF : p.hasRoot;
    const test::RefRoot& ref = isFloat ? p.refF : p.ref;
    const double cond = ref.conditioning;
    const bool got = answers[i] >= 0;
    if (any) {
      row.missed += has && !got;
      row.noiseHits += !has && got;  // hasRoot gives no position to check
      continue;
    }
    if (!has) {
      if (got) unexpected(p, answers[i]);
      continue;
    }
    if (!got) {
      ++row.missed;
      continue;
    }
    const double err = test::rootError(answers[i], ref);  // against the root, not its rounding
    // Beyond 1e3 u cond the answer is another root (or none of them): count, not average.
    if (err > 1e3 * u * cond + 1e-12 * (p.hi - p.lo)) {
      if (answers[i] > ref.value)
        ++row.missed;
      else
        unexpected(p, answers[i]);
      continue;
    }
    errs.push_back(err / (u * cond));
  }
  if (!errs.empty()) {
    row.errMedian = quantile(errs, 0.5);
    row.errP99 = quantile(errs, 0.99);
    row.errMax = quantile(errs, 1);
  }
}

// ns per firstRoot of one problem: the best of kSpreadTrials runs of kSpreadSolves solves.
double timeOne(const Problem& p, RootMethod method) {
  constexpr int kSpreadTrials = 7, kSpreadSolves = 4;
  RootOptions o;
  o.method = method;
  double best = std::numeric_limits<double>::infinity(), sink = 0;
  for (int t = 0; t < kSpreadTrials; ++t) {
    const auto t0 = std::chrono::steady_clock::now();
    for (int k = 0; k < kSpreadSolves; ++k) sink += firstRoot(p.c, {}, p.lo, p.hi, o).value_or(0);
    const auto t1 = std::chrono::steady_clock::now();
    best = std::min(best, std::chrono::duration<double, std::nano>(t1 - t0).count());
  }
  volatile double keep = sink;  // the answers are used: the solves cannot be dropped
  (void)keep;
  return best / kSpreadSolves;
}

SpreadRow spreadOf(const char* family, int degree, const std::vector<Problem>& ps) {
  std::vector<double> autoT(ps.size()), sturmT(ps.size()), ratio(ps.size());
  std::vector<double> byOutcome[3];
  for (size_t i = 0; i < ps.size(); ++i) {  // either one first in turn
    if (i % 2 == 1) sturmT[i] = timeOne(ps[i], RootMethod::Sturm);
    autoT[i] = timeOne(ps[i], RootMethod::Auto);
    if (i % 2 == 0) sturmT[i] = timeOne(ps[i], RootMethod::Sturm);
    ratio[i] = sturmT[i] / autoT[i];
    byOutcome[outcomeOf(ps[i])].push_back(autoT[i]);
  }
  double sumAuto = 0, sumSturm = 0, sumP10 = 0, sumMedian = 0;
  for (size_t i = 0; i < ps.size(); ++i) {
    sumAuto += autoT[i];
    sumSturm += sturmT[i];
  }
  for (const auto& times : byOutcome) {
    if (times.empty()) continue;
    const double n = static_cast<double>(times.size());
    sumP10 += n * quantile(times, 0.1);
    sumMedian += n * quantile(times, 0.5);
  }
  const double at5 = static_cast<double>(
      std::count_if(ratio.begin(), ratio.end(), [](double r) { return r >= 5; }));
  return {family,
          degree,
          static_cast<int>(ps.size()),
          sumSturm / sumAuto,
          quantile(ratio, 0.5),
          quantile(ratio, 0.9),
          quantile(ratio, 1.0),
          at5 / static_cast<double>(ps.size()),
          sumSturm / sumP10,
          sumSturm / sumMedian};
}

std::string cpuModel() {
  std::ifstream in("/proc/cpuinfo");
  std::string line;
  while (std::getline(in, line))
    if (line.rfind("model name", 0) == 0) return line.substr(line.find(':') + 2);
  return "unknown";
}

}  // namespace

int main(int argc, char** argv) {
  bool tiny = false;
  std::string outDir = ".";
  // Per degree and family. Why 2000 (400 until session 24): the Sturm / Auto ratio of one
  // degree depends on the problems drawn, mostly on how many have a root (3-4x) and how
  // many none (5-7x); on 400 problems it moved by up to 10 % from one draw to the next
  // (session 24, cells of degree 6: 4.70x on 400, 4.27x on 2000; scratch timings on 4000
  // others 4.43x). A full run takes ~4.5 minutes (MPFR references).
  int problems = 2000;
  std::vector<int> degrees;
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--tiny"))
      tiny = true;
    else if (!std::strcmp(argv[i], "--out") && i + 1 < argc)
      outDir = argv[++i];
    else if (!std::strcmp(argv[i], "--problems") && i + 1 < argc)
      problems = std::atoi(argv[++i]);
    else if (!std::strcmp(argv[i], "--degrees") && i + 1 < argc) {
      std::istringstream list(argv[++i]);  // comma-separated
      for (std::string d; std::getline(list, d, ',');) degrees.push_back(std::atoi(d.c_str()));
    } else {
      std::fprintf(stderr, "usage: %s [--tiny] [--out DIR] [--problems N] [--degrees 3,4]\n",
                   argv[0]);
      return 2;
    }
  }
  if (tiny) {
    if (degrees.empty()) degrees = {2, 5, 10};
    problems = 30;
  } else if (degrees.empty()) {
    for (int d = 2; d <= 20; ++d) degrees.push_back(d);
    degrees.push_back(30);
    degrees.push_back(40);
  }
  const int reps = tiny ? 1 : 5;
  std::vector<Row> rows;
  std::vector<OutcomeRow> outcomeRows;
  std::vector<SpreadRow> spreadRows;
  for (const char* family : {"ray", "cell"})
    for (int degree : degrees) {
      DrawCounts counts;
      // One seed per family and degree: --degrees 6,7 draws the full run's problems.
      const bool cell = std::strcmp(family, "cell") == 0;
      std::mt19937_64 rng(42 + 2 * degree + (cell ? 1 : 0));
      const auto ps = makeProblems(degree, problems, cell, rng, counts);
      // The kept problems must be the drawn ones, less the few whose first root is not well
      // separated in double: a filter that changes the mix changes what is measured (the
      // float filter of sessions 1-22 kept 9 % problems with a root of the drawn 58 %).
      // 0.15 is about three standard deviations of the fraction at --tiny's 30 problems.
      const double drawnShare = static_cast<double>(counts.drawnWithRoot) / counts.drawn;
      const double keptShare = static_cast<double>(counts.keptWithRoot) / counts.kept;
      if (std::abs(drawnShare - keptShare) > 0.15) {
        std::fprintf(stderr,
                     "%s degree %d: the kept problems are not the drawn ones: %.0f %% of %d "
                     "drawn have a root in the interval, %.0f %% of %d kept\n",
                     family, degree, 100 * drawnShare, counts.drawn, 100 * keptShare, counts.kept);
        return 1;
      }
      std::vector<std::vector<double>> times(std::size(kMethods));
      std::vector<std::vector<double>> answers(std::size(kMethods), std::vector<double>(ps.size()));
      // Interleave the methods in each repetition: machine noise hits all of them alike.
      // Each repetition starts one method further on, so that no method always runs right
      // after the same other one. (Session 24: in the fixed order Yuksel's row, the very
      // code Auto runs at degrees 3-40, timed 2-6 % faster than Auto's at degrees 6-12; with
      // the rotation it still timed 1-7 % faster at degree 6 and ~2 % at 9 and 12, so that
      // gap is not the order alone: the two call paths differ in code layout, not in work.)
      const size_t nMethods = std::size(kMethods);
      for (int r = 0; r < reps; ++r)
        for (size_t i = 0; i < nMethods; ++i) {
          const size_t k = (i + static_cast<size_t>(r)) % nMethods;
          if (applies(kMethods[k], degree))
            times[k].push_back(runPass(kMethods[k], ps, answers[k]));
        }
      for (size_t k = 0; k < std::size(kMethods); ++k) {
        if (!applies(kMethods[k], degree)) continue;
        Row row;
        row.m = &kMethods[k];
        row.family = family;
        row.degree = degree;
        row.ns = quantile(times[k], 0.5);
        score(row, ps, answers[k]);
        rows.push_back(row);
      }
      // Auto and Sturm on each outcome's problems alone, interleaved as above.
      std::vector<Problem> byOutcome[3];
      for (const Problem& p : ps) byOutcome[outcomeOf(p)].push_back(p);
      const Method& autoM = doubleFirst(RootMethod::Auto);
      const Method& sturmM = doubleFirst(RootMethod::Sturm);
      for (int o = 0; o < 3; ++o) {
        const auto& sub = byOutcome[o];
        if (sub.empty()) continue;
        std::vector<double> unused(sub.size()), autoT, sturmT;
        for (int r = 0; r < reps; ++r) {  // either one first in turn
          if (r % 2 == 1) sturmT.push_back(runPass(sturmM, sub, unused));
          autoT.push_back(runPass(autoM, sub, unused));
          if (r % 2 == 0) sturmT.push_back(runPass(sturmM, sub, unused));
        }
        outcomeRows.push_back({family, degree, o, static_cast<int>(sub.size()),
                               quantile(autoT, 0.5), quantile(sturmT, 0.5)});
      }
      if (degree >= 6 && degree <= 12) spreadRows.push_back(spreadOf(family, degree, ps));
      std::fprintf(stderr, "%s degree %d: %zu problems\n", family, degree, ps.size());
    }

  std::filesystem::create_directories(outDir);
  const std::string csvPath = outDir + "/roots.csv";
  std::ofstream csv(csvPath);
  csv << "family,method,precision,query,degree,problems,ns_per_solve,err_median_ucond,"
         "err_p99_ucond,err_max_ucond,missed,noise_hits,false_hits\n";
  for (const Row& r : rows)
    csv << r.family << ',' << r.m->name << ',' << r.m->precision << ',' << r.m->query << ','
        << r.degree << ',' << r.problems << ',' << r.ns << ',' << r.errMedian << ',' << r.errP99
        << ',' << r.errMax << ',' << r.missed << ',' << r.noiseHits << ',' << r.falseHits << '\n';

  std::printf("machine: %s\n\n", cpuModel().c_str());
  std::printf(
      "| family | degree | method | precision | query | ns/solve | err median | "
      "err p99 | err max | missed | noise hits | false hits | Sturm/this |\n"
      "|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
  for (const Row& r : rows) {
    double sturm = 0;
    for (const Row& s : rows)
      if (s.family == r.family && s.degree == r.degree && s.m->method == RootMethod::Sturm)
        sturm = s.ns;
    std::printf("| %s | %d | %s | %s | %s | %.0f | %.2f | %.2f | %.2f | %d | %d | %d | %.2f |\n",
                r.family, r.degree, r.m->name, r.m->precision, r.m->query, r.ns, r.errMedian,
                r.errP99, r.errMax, r.missed, r.noiseHits, r.falseHits, sturm / r.ns);
  }
  std::printf("\nerrors in units of u cond(root) (u of the precision solved); wrote %s\n",
              csvPath.c_str());

  const std::string outcomePath = outDir + "/roots-outcomes.csv";
  std::ofstream ocsv(outcomePath);
  ocsv << "family,degree,outcome,problems,auto_ns,sturm_ns\n";
  std::printf(
      "\nby outcome (double, first root)\n\n"
      "| family | degree | outcome | problems | Auto ns | Sturm ns | Sturm / Auto |\n"
      "|---|---:|---|---:|---:|---:|---:|\n");
  for (const OutcomeRow& r : outcomeRows) {
    ocsv << r.family << ',' << r.degree << ',' << kOutcomeNames[r.outcome] << ',' << r.problems
         << ',' << r.autoNs << ',' << r.sturmNs << '\n';
    std::printf("| %s | %d | %s | %d | %.0f | %.0f | %.2f |\n", r.family, r.degree,
                kOutcomeNames[r.outcome], r.problems, r.autoNs, r.sturmNs, r.sturmNs / r.autoNs);
  }
  std::printf("\nwrote %s\n", outcomePath.c_str());

  const std::string spreadPath = outDir + "/roots-spread.csv";
  std::ofstream scsv(spreadPath);
  scsv << "family,degree,problems,sturm_over_auto,ratio_median,ratio_p90,ratio_max,share_at_5x,"
          "if_outcome_p10,if_outcome_median\n";
  std::printf(
      "\nper problem (double, first root; each problem timed alone)\n\n"
      "| family | degree | problems | Sturm / Auto | per problem: median | p90 | max | "
      "share >= 5x | if each at its outcome's p10 | at its median |\n"
      "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
  for (const SpreadRow& r : spreadRows) {
    scsv << r.family << ',' << r.degree << ',' << r.problems << ',' << r.ratioOfMeans << ','
         << r.ratioMedian << ',' << r.ratioP90 << ',' << r.ratioMax << ',' << r.shareAt5 << ','
         << r.ifP10 << ',' << r.ifMedian << '\n';
    std::printf("| %s | %d | %d | %.2f | %.2f | %.2f | %.2f | %.3f | %.2f | %.2f |\n", r.family,
                r.degree, r.problems, r.ratioOfMeans, r.ratioMedian, r.ratioP90, r.ratioMax,
                r.shareAt5, r.ifP10, r.ifMedian);
  }
  std::printf("\nwrote %s\n", spreadPath.c_str());
  return 0;
}
