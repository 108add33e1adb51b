// The plugin's accuracy figure (issue 4): through Embree, with the double channel
// (algray::IntersectContext), per gallery surface (plus a degree-20 Chmutov surface and a
// degree-40 product of spheres built here), for ray origins near the surface (2-3 clip
// radii from the centre) and 1000 clip radii away (and 1e6 clip radii), and all from one
// eye 1.5 clip radii from the centre:
//   wc          rays whose reference answer is well-conditioned: a simple first root
//               whose predicted displacement under rounding of f's coefficients is
//               below 1e-10 clip radii (a tenth of the target), no near-tangency before
//               it, not at the clip boundary (tests/support/reference.h, MPFR, independent
//               of the library), or a miss with no near-tangency;
//   agree       of those, how many get the reference's hit/miss answer;
//   max err     max |t - t_ref| |d| / R over well-conditioned hits (target: 1e-9), and
//               how many hits it is taken over ("-" for none);
//   clean err   the same over every clean simple first root whose predicted displacement
//               is below 1e-6 R (the intersector report's limit): how the error grows
//               once the conditioning alone allows more than the target;
//   leaving     rays leaving each hit (origin o + t d with its pbrt-style error bound,
//               tnear = 0; half towards the side the ray came from, half through);
//   self        leaving rays that hit within 1e-6 R of their own origin (target: 0), unless
//               the same ray from the exact surface point meets the surface there too
//               (genuineReentry, MPFR): a ray leaving within ~1e-5 rad of the tangent
//               plane can re-enter a curved surface that close; those are counted apart
//               (the summary's "re-entering"), as they are geometry, not acne;
//   float err   max error of Embree's float tfar on the same rays (what a float host
//               sees; for comparison only).
// Writes DIR/accuracy.csv and DIR/accuracy.md; prints the table.
//
//   accuracy_report [--tiny] [--out DIR] [--rays N]
// (Rows for origins 1e6 R away are included beyond the figure's 1000 R: there the float
// ray Embree traverses with is off by ~0.06 R, which the ownership rule of the cells has
// to survive.) Until session 23 the limit was 1e-12 R, a thousandth of the target, which
// left the degree-20 rows a few dozen hits (101 of 1200 rays) and the figure far from the
// rays it is about; with 1e-10 R they keep most of their hits.
#include "algray/embree.h"
#include "algray/gallery.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include "../support/reference.h"

namespace {

using namespace algray;

constexpr double kCondLimit = 1e-10;  // predicted displacement / R for "well-conditioned"
constexpr double kCleanLimit = 1e-6;  // ... for the "clean err" column
constexpr double kSelfDistance = 1e-6;

// Chebyshev T_n(v) by T_{k+1} = 2 v T_k - T_{k-1}, written out here so that a degree-20
// surface is in the figure: T20(x) + T20(y) + T20(z) + 1 = 0 (Chmutov's construction).
Polynomial chebyshev(int n, const Polynomial& v) {
  Polynomial a(1.0), b = v;
  if (n == 0) return a;
  for (int k = 1; k < n; ++k) {
    Polynomial c = 2.0 * (v * b) - a;
    a = std::move(b);
    b = std::move(c);
  }
  return b;
}

struct Surface {
  std::string name;
  Polynomial f;
  double radius;
};

struct Row {
  std::string surface;
  int degree = 0;
  std::string origins;
  int rays = 0, wc = 0, agree = 0, wcHits = 0, leaving = 0, self = 0, reentering = 0;
  int cleanHits = 0, cleanDisagree = 0;  // clean rays (kCleanLimit): hits both, disagreements
  double maxErr = 0, floatMaxErr = 0, cleanMaxErr = 0;
};

struct Outcome {
  test::RayRef ref;
  HitD hit;
  double floatT = -1;
  int leaving = 0, self = 0, reentering = 0;
};

glm::dvec3 randomUnit(std::mt19937_64& rng) {
  std::normal_distribution<double> n;
  return glm::normalize(glm::dvec3(n(rng), n(rng), n(rng)));
}

Row measure(RTCDevice device, const Surface& s, double farDistance, int count, std::uint64_t seed) {
  const bool far = farDistance > 0, camera = farDistance < 0;
  SurfaceDesc desc;
  desc.polynomial = s.f;
  desc.clip = ClipSphere{glm::dvec3(0.0), s.radius};
  SurfaceGeometry geometry(device, desc);
  RTCScene scene = rtcNewScene(device);
  const unsigned id = rtcAttachGeometry(scene, geometry.geometry());
  rtcCommitScene(scene);

  // ---- Rays (sequential, reproducible) -------------------------------------------------
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<RayD> rays(count);
  std::vector<std::array<glm::dvec3, 4>> leaveDirs(count);
  for (int i = 0; i < count; ++i) {
    const double dist = (far ? farDistance : 2.0 + unit(rng)) * s.radius;
    glm::dvec3 o = dist * randomUnit(rng);
    // Camera rows: every ray from one eye 1.5 R from the centre (a renderer's primary rays).
    if (farDistance < 0) o = 1.5 * s.radius * glm::normalize(glm::dvec3(1.0, 0.7, 0.5));
    const glm::dvec3 target = 0.8 * s.radius * std::cbrt(unit(rng)) * randomUnit(rng);
    rays[i] = RayD{o, (target - o) * (0.5 + unit(rng)), 0.0,
                   std::numeric_limits<double>::infinity(), 0.0};
    for (auto& d : leaveDirs[i]) d = randomUnit(rng);
  }

  // ---- Reference and plugin, in parallel -------------------------------------------------
  std::vector<Outcome> out(count);
  test::RefOptions refOptions;
  refOptions.condLimit = kCleanLimit;  // the figure's limit is applied in the tally
  tbb::parallel_for(0, count, [&](int i) {
    const RayD& ray = rays[i];
    Outcome& o = out[i];
    o.ref = test::referenceFirstHit(s.f, ray.org, ray.dir, ray.tnear, ray.tfar, glm::dvec3(0.0),
                                    s.radius, refOptions);
    IntersectContext context;
    initIntersectContext(&context, &ray, &o.hit, scene);
    RTCRayHit rh = makeRayHit(context);
    rtcIntersect1(scene, &context.base, &rh);
    if (rh.hit.geomID != id) o.hit.hit = false;
    RTCIntersectContext plain;
    rtcInitIntersectContext(&plain);
    RTCRayHit fh = makeRayHit(ray, scene);
    rtcIntersect1(scene, &plain, &fh);
    if (fh.hit.geomID == id) o.floatT = fromFloatParameter(ray, fh.ray.tfar, scene);
    if (!o.hit.hit) return;
    // ---- Leaving rays from the hit point, with its error bound (pbrt-v4 Sec. 6.8.6) --
    const glm::dvec3 p = ray.org + o.hit.t * ray.dir;
    const double pError = gamma(3) * (glm::length(ray.org) + glm::length(o.hit.t * ray.dir));
    const glm::dvec3 n = glm::normalize(o.hit.Ng);
    const double towardsEye = glm::dot(n, ray.dir) < 0 ? 1.0 : -1.0;
    for (int k = 0; k < 4; ++k) {
      glm::dvec3 d = leaveDirs[i][k];
      // k = 0, 1: the side the ray came from (shadow rays), k = 2, 3: through.
      const double side = (k < 2 ? towardsEye : -towardsEye);
      if (glm::dot(d, n) * side < 0) d -= 2.0 * glm::dot(d, n) * n;
      RayD leave{p, d, 0.0, std::numeric_limits<double>::infinity(), pError};
      HitD lh;
      IntersectContext lc;
      initIntersectContext(&lc, &leave, &lh, scene);
      RTCRayHit lr = makeRayHit(lc);
      rtcIntersect1(scene, &lc.base, &lr);
      ++o.leaving;
      if (lh.hit && lr.hit.geomID == id && lh.t * glm::length(d) < kSelfDistance * s.radius)
        ++(test::genuineReentry(s.f, p, d, lh.t) ? o.reentering : o.self);
    }
  });
  rtcReleaseScene(scene);

  // ---- Tally -------------------------------------------------------------------------------
  Row row;
  row.surface = s.name;
  row.degree = s.f.degree();
  row.origins = camera ? "eye 1.5 R" : far ? (farDistance >= 1e6 ? "1e6 R" : "1000 R") : "2-3 R";
  row.rays = count;
  for (int i = 0; i < count; ++i) {
    const Outcome& o = out[i];
    row.leaving += o.leaving;
    row.self += o.self;
    row.reentering += o.reentering;
    if (!o.ref.wellConditioned) continue;
    const double len = glm::length(rays[i].dir);
    const double err = std::abs(o.hit.t - o.ref.t) * len / s.radius;
    row.cleanDisagree += o.ref.hit != o.hit.hit;
    if (o.ref.hit && o.hit.hit) {
      ++row.cleanHits;
      row.cleanMaxErr = std::max(row.cleanMaxErr, err);
    }
    if (o.ref.hit && !(o.ref.cond < kCondLimit)) continue;
    ++row.wc;
    if (o.ref.hit != o.hit.hit) continue;
    ++row.agree;
    if (!o.ref.hit) continue;
    ++row.wcHits;
    row.maxErr = std::max(row.maxErr, err);
    if (o.floatT >= 0)
      row.floatMaxErr = std::max(row.floatMaxErr, std::abs(o.floatT - o.ref.t) * len / s.radius);
  }
  if (geometry.callbackErrors() > 0)
    std::fprintf(stderr, "warning: %s: %llu callback errors\n", s.name.c_str(),
                 geometry.callbackErrors());
  return row;
}

}  // namespace

int main(int argc, char** argv) {
  bool tiny = false;
  std::string outDir = ".";
  int count = 300;
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--tiny")) {
      tiny = true;
    } else if (!std::strcmp(argv[i], "--out") && i + 1 < argc) {
      outDir = argv[++i];
    } else if (!std::strcmp(argv[i], "--rays") && i + 1 < argc) {
      count = std::atoi(argv[++i]);
    } else {
      std::fprintf(stderr, "usage: accuracy_report [--tiny] [--out DIR] [--rays N]\n");
      return 2;
    }
  }
  if (tiny) count = 6;
  // One shared eye at 1.5 R (-1), origins near (0), 1000 R away (the figure's requirement)
  // and, beyond it, 1e6 R.
  const std::vector<double> farDistances = {-1.0, 0.0, 1e3, 1e6};
  std::filesystem::create_directories(outDir);

  std::vector<Surface> surfaces;
  for (const GallerySurface& g : gallery())
    surfaces.push_back({std::string(g.name), g.build(), g.clipRadius});
  {
    const Polynomial t20 = chebyshev(20, Polynomial::variable(0)) +
                           chebyshev(20, Polynomial::variable(1)) +
                           chebyshev(20, Polynomial::variable(2)) + Polynomial(1.0);
    surfaces.push_back({"chmutov-20 (report)", t20, 1.75});
    // Degree 40: the product of 20 spheres of radii 0.3 ... 1 (session 38: its first roots
    // were up to 0.005 R off before settling judged f by its compensated value). None of
    // its rays is well-conditioned by the figure's limit; the clean column shows them.
    const Polynomial x = Polynomial::variable(0), y = Polynomial::variable(1),
                     z = Polynomial::variable(2), radius2 = x * x + y * y + z * z;
    Polynomial spheres(1.0);
    for (int k = 0; k < 20; ++k) {
      const double r = 0.3 + 0.7 * k / 19;
      spheres = spheres * (radius2 - Polynomial(r * r));
    }
    surfaces.push_back({"spheres-40 (report)", spheres, 1.2});
  }
  if (tiny) surfaces.resize(std::min<size_t>(surfaces.size(), 3));

  RTCDevice device = rtcNewDevice(nullptr);
  std::vector<Row> rows;
  std::uint64_t seed = 1;
  for (const Surface& s : surfaces)
    for (double far : farDistances) rows.push_back(measure(device, s, far, count, seed++));
  rtcReleaseDevice(device);

  // ---- Output ----------------------------------------------------------------------------
  std::ofstream csv(std::filesystem::path(outDir) / "accuracy.csv");
  csv << "surface,degree,origins,rays,well_conditioned,agree,wc_hits,max_err_over_R,leaving,"
         "self_hits,float_max_err_over_R,clean_hits,clean_max_err_over_R,clean_disagree\n";
  std::ofstream md(std::filesystem::path(outDir) / "accuracy.md");
  md << "| surface | deg | origins | rays | well-cond. | agree | max err / R (hits) | leaving rays "
        "| self-hits | float err / R | clean err / R (hits) |\n"
        "|---|---|---|---|---|---|---|---|---|---|---|\n";
  int totalWc = 0, totalAgree = 0, totalSelf = 0, totalReentering = 0, totalCleanDisagree = 0;
  // Origins up to 1000 R (the figure), and 1e6 R; the same over the clean rays.
  double worst = 0, worstBeyond = 0, cleanWorst = 0, cleanWorstBeyond = 0;
  // An error over no hits is "-", not 0.
  auto num = [](double e) {
    char t[32];
    std::snprintf(t, sizeof t, "%.2g", e);
    return std::string(t);
  };
  auto errText = [&](double e, int hits) {
    return hits == 0 ? std::string("- (0)") : num(e) + " (" + std::to_string(hits) + ")";
  };
  char buf[512];
  for (const Row& r : rows) {
    std::snprintf(buf, sizeof buf, "%s,%d,%s,%d,%d,%d,%d,%.3g,%d,%d,%.3g,%d,%.3g,%d\n",
                  r.surface.c_str(), r.degree, r.origins.c_str(), r.rays, r.wc, r.agree, r.wcHits,
                  r.maxErr, r.leaving, r.self, r.floatMaxErr, r.cleanHits, r.cleanMaxErr,
                  r.cleanDisagree);
    csv << buf;
    const std::string floatErr = r.wcHits == 0 ? "-" : num(r.floatMaxErr);
    std::snprintf(buf, sizeof buf, "| %s | %d | %s | %d | %d | %d | %s | %d | %d | %s | %s |\n",
                  r.surface.c_str(), r.degree, r.origins.c_str(), r.rays, r.wc, r.agree,
                  errText(r.maxErr, r.wcHits).c_str(), r.leaving, r.self, floatErr.c_str(),
                  errText(r.cleanMaxErr, r.cleanHits).c_str());
    md << buf;
    std::fputs(buf, stdout);
    totalWc += r.wc;
    totalAgree += r.agree;
    totalSelf += r.self;
    totalReentering += r.reentering;
    totalCleanDisagree += r.cleanDisagree;
    const bool beyond = r.origins == "1e6 R";
    double& w = beyond ? worstBeyond : worst;
    w = std::max(w, r.maxErr);
    double& cw = beyond ? cleanWorstBeyond : cleanWorst;
    cw = std::max(cw, r.cleanMaxErr);
  }
  std::printf(
      "\nwell-conditioned rays: %d, hit/miss agreement: %d (%.4f%%), worst position error %.3g R "
      "for origins up to 1000 R (target 1e-9) and %.3g R from 1e6 R (beyond the figure), "
      "self-hits %d (target 0; %d more re-entering, as from the exact surface point)\n"
      "clean rays (predicted displacement below %.0e R): worst position error %.3g R up to "
      "1000 R and %.3g R from 1e6 R, hit/miss disagreements %d\n",
      totalWc, totalAgree, totalWc ? 100.0 * totalAgree / totalWc : 100.0, worst, worstBeyond,
      totalSelf, totalReentering, kCleanLimit, cleanWorst, cleanWorstBeyond, totalCleanDisagree);
  return 0;
}
