// Run time against error for the whole intersector (issue 7).
//
// For every gallery surface, fixed ray sets (tests/bench/intersector_rays.h) are traced
// through Embree with the double-precision side channel (algray::IntersectContext), once
// per configuration of algray::SurfaceOptions, and compared with an MPFR reference
// (tests/support/reference.h) computed here, independently of the library:
//   ns per ray            single thread, best of `reps` passes, configurations interleaved
//                         so that ratios are measured side by side;
//   disagree              hit/miss disagreements on well-conditioned rays;
//   err median/p99/max    |t - t_ref| |d| / R on well-conditioned rays both call a hit;
//   ferr ...              the same for Embree's float tfar (the float proxy ray of
//                         makeRayHit, which starts a far ray near the scene);
//   ... all               hit/miss disagreements and errors on every ray, conditioning
//                         ignored (grazing and singular rays are ill-conditioned by design);
//   speckles              hits within 1e-6 R of the ray origin (shadow rays hitting their
//                         own surface point), unless the reference finds two sheets
//                         crossing there (intersector_rays.h, selfClean);
//   nonfinite             hits with a non-finite t or normal (must stay 0);
//   node ...              singular rays whose node is the first intersection: how many,
//                         how many missed it, and |t - t_node| |d| / R of the hits;
//   werr p99              p99 over well-conditioned rays that either side calls a hit of
//                         the position error, a disagreement counting as 1 clip radius:
//                         the error axis of tests/bench/plot_intersector.py.
// Writes DIR/intersector.csv (one row per surface, ray class and configuration, plus
// pooled rows with surface "ALL": ns per ray is then the geometric mean over surfaces)
// and prints the pooled tables as Markdown.
//
//   intersector_report [--tiny] [--out DIR] [--reps N] [--surface NAME]...
#include "algray/embree.h"
#include "algray/gallery.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <string>
#include <thread>
#include <vector>

#include "float_ray.h"
#include "intersector_rays.h"

namespace algray::bench {
namespace {

// ---- Configurations ----------------------------------------------------------------
struct Config {
  std::string name;
  SurfaceOptions options;
  bool floatRays = false;  // plain float Embree rays (float_ray.h), no double channel
};

std::vector<Config> configurations() {
  std::vector<Config> out;
  out.push_back({"default", {}, false});
  auto with = [&](std::string name, auto edit) {
    Config c{std::move(name), {}, false};
    edit(c);
    out.push_back(std::move(c));
  };
  with("float-rays", [](Config& c) { c.floatRays = true; });
  with("float-solver", [](Config& c) { c.options.singlePrecision = true; });
  with("yuksel", [](Config& c) { c.options.roots.method = RootMethod::Yuksel; });
  with("sturm", [](Config& c) { c.options.roots.method = RootMethod::Sturm; });
  with("bernstein", [](Config& c) { c.options.roots.method = RootMethod::Bernstein; });
  with("closed-form", [](Config& c) { c.options.roots.method = RootMethod::ClosedForm; });
  for (double tol : {1e-3, 1e-6, 1e-9, 1e-12}) {
    char name[32];
    std::snprintf(name, sizeof name, "tol%.0e", tol);
    with(name, [tol](Config& c) { c.options.roots.relTolerance = tol; });
  }
  with("no-cells", [](Config& c) { c.options.useCells = false; });
  with("origin-cache", [](Config& c) { c.options.originCache = true; });  // off by default
  with("no-recentre", [](Config& c) { c.options.recentre = false; });
  return out;
}

// ---- One pass over a ray set -------------------------------------------------------
struct TraceResult {
  bool hit = false;
  double t = 0;
  double tf = 0;  // Embree's float tfar as t along the ray (fromFloatParameter)
  bool finite = true;
};

TraceResult traceOne(RTCScene scene, const RayD& ray, bool floatRays) {
  TraceResult r;
  if (floatRays) {
    // Only what a float host does per ray: the float ray and its trace (until session 23
    // this configuration traced makeRayHit's float proxy, far origins moved near the scene,
    // and its time included the double channel's set-up).
    RTCRayHit rh = plainFloatRay(ray);
    RTCIntersectContext plain;
    rtcInitIntersectContext(&plain);
    rtcIntersect1(scene, &plain, &rh);
    r.hit = rh.hit.geomID != RTC_INVALID_GEOMETRY_ID;
    r.t = r.tf = rh.ray.tfar;  // along the float direction, the double one rounded
    if (r.hit && !std::isfinite(rh.hit.Ng_x + rh.hit.Ng_y + rh.hit.Ng_z)) r.finite = false;
    return r;
  }
  // The double channel; its context also carries the float ray's map (makeRayHit,
  // fromFloatParameter) for the float tfar column.
  HitD hit;
  IntersectContext context;
  initIntersectContext(&context, &ray, &hit, scene);
  RTCRayHit rh = makeRayHit(context);
  rtcIntersect1(scene, &context.base, &rh);
  r.hit = hit.hit;
  r.t = hit.t;
  r.finite = !hit.hit || (std::isfinite(hit.t) && std::isfinite(hit.Ng.x) &&
                          std::isfinite(hit.Ng.y) && std::isfinite(hit.Ng.z));
  r.tf = fromFloatParameter(context, rh.ray.tfar);
  if (r.hit && !std::isfinite(rh.hit.Ng_x + rh.hit.Ng_y + rh.hit.Ng_z)) r.finite = false;
  return r;
}

// ---- Statistics --------------------------------------------------------------------
struct Stats {
  long rays = 0, wc = 0, disagree = 0, speckles = 0, nonfinite = 0, refHits = 0, hits = 0;
  double seconds = 0;
  long disagreeAll = 0, nodeRays = 0, nodeMiss = 0;
  std::vector<double> nodeErr;  // singular rays: |t - 1| |d| / R when the node is first
  std::vector<double> nodeW;    // the same with a miss counted as 1 clip radius
  // Per well-conditioned ray that either side calls a hit: the position error, or one
  // clip radius for a hit/miss disagreement (the error axis of the Pareto plots).
  std::vector<double> err, ferr, errAll, werr;
  void add(const Stats& o) {
    rays += o.rays, wc += o.wc, disagree += o.disagree, speckles += o.speckles,
        nonfinite += o.nonfinite;
    refHits += o.refHits, hits += o.hits, seconds += o.seconds, disagreeAll += o.disagreeAll;
    errAll.insert(errAll.end(), o.errAll.begin(), o.errAll.end());
    werr.insert(werr.end(), o.werr.begin(), o.werr.end());
    nodeRays += o.nodeRays, nodeMiss += o.nodeMiss;
    nodeErr.insert(nodeErr.end(), o.nodeErr.begin(), o.nodeErr.end());
    nodeW.insert(nodeW.end(), o.nodeW.begin(), o.nodeW.end());
    err.insert(err.end(), o.err.begin(), o.err.end());
    ferr.insert(ferr.end(), o.ferr.begin(), o.ferr.end());
  }
};

double quantile(std::vector<double> v, double q) {
  if (v.empty()) return std::nan("");
  std::sort(v.begin(), v.end());
  const size_t i =
      std::min(v.size() - 1, static_cast<size_t>(std::ceil(q * v.size())) - (q > 0 ? 1 : 0));
  return v[i];
}

Stats score(const std::vector<BenchRay>& rays, const std::vector<TraceResult>& res, double radius) {
  Stats s;
  s.rays = static_cast<long>(rays.size());
  for (size_t i = 0; i < rays.size(); ++i) {
    const BenchRay& b = rays[i];
    const TraceResult& r = res[i];
    const double dl = glm::length(b.ray.dir);
    if (!r.finite) ++s.nonfinite;
    if (r.hit) ++s.hits;
    if (b.ref.hit) ++s.refHits;
    if (r.hit && r.t * dl < 1e-6 * radius && b.selfClean) ++s.speckles;
    if (b.nodeFirst) {
      ++s.nodeRays;
      if (r.hit) {
        s.nodeErr.push_back(std::abs(r.t - 1.0) * dl / radius);
        s.nodeW.push_back(s.nodeErr.back());
      } else {
        ++s.nodeMiss;
        s.nodeW.push_back(1.0);
      }
    }
    // Every ray, whatever its conditioning: how far the answer is from the exact one of
    // the given double ray (grazing and singular rays are ill-conditioned by design).
    if (r.hit != b.ref.hit)
      ++s.disagreeAll;
    else if (r.hit)
      s.errAll.push_back(std::abs(r.t - b.ref.t) * dl / radius);
    if (!b.ref.wellConditioned) continue;
    ++s.wc;
    if (r.hit != b.ref.hit) {
      ++s.disagree;
      s.werr.push_back(1.0);
      continue;
    }
    if (!r.hit) continue;
    s.err.push_back(std::abs(r.t - b.ref.t) * dl / radius);
    s.werr.push_back(s.err.back());
    s.ferr.push_back(std::abs(static_cast<double>(r.tf) - b.ref.t) * dl / radius);
  }
  return s;
}

struct Row {
  std::string surface;
  int degree;
  RayClass cls;
  std::string config;
  Stats stats;
  double nsPerRay;
};

void writeCsv(const std::filesystem::path& file, const std::vector<Row>& rows) {
  std::ofstream out(file);
  out << "surface,degree,class,config,rays,well_conditioned,ref_hits,hits,disagree,err_median,err_"
         "p99,err_max,"
         "ferr_median,ferr_p99,ferr_max,disagree_all,errall_median,errall_p99,errall_max,werr_p99,"
         "node_rays,node_miss,node_err_median,node_err_max,node_werr_p99,speckles,nonfinite,ns_per_"
         "ray\n";
  for (const Row& r : rows) {
    const Stats& s = r.stats;
    char line[768];
    std::snprintf(line, sizeof line,
                  "%s,%d,%s,%s,%ld,%ld,%ld,%ld,%ld,%.3e,%.3e,%.3e,%.3e,%.3e,%.3e,%ld,%.3e,%.3e,%."
                  "3e,%.3e,%ld,%ld,%.3e,%.3e,%.3e,%ld,%ld,%.1f\n",
                  r.surface.c_str(), r.degree, className(r.cls), r.config.c_str(), s.rays, s.wc,
                  s.refHits, s.hits, s.disagree, quantile(s.err, 0.5), quantile(s.err, 0.99),
                  quantile(s.err, 1.0), quantile(s.ferr, 0.5), quantile(s.ferr, 0.99),
                  quantile(s.ferr, 1.0), s.disagreeAll, quantile(s.errAll, 0.5),
                  quantile(s.errAll, 0.99), quantile(s.errAll, 1.0), quantile(s.werr, 0.99),
                  s.nodeRays, s.nodeMiss, quantile(s.nodeErr, 0.5), quantile(s.nodeErr, 1.0),
                  quantile(s.nodeW, 0.99), s.speckles, s.nonfinite, r.nsPerRay);
    out << line;
  }
}

void writeMarkdown(std::ostream& out, const std::vector<Row>& pooled, const std::string& note) {
  out << note << "\n\n";
  for (RayClass c : kRayClasses) {
    out << "\n**" << className(c) << " rays**\n\n";
    out << "| configuration | ns/ray | well-cond. rays | disagree | err median | err p99 | err max "
           "| float tfar p99 "
           "| all rays: disagree | all rays: err p99 | speckles "
           "|\n|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
    for (const Row& r : pooled) {
      if (r.cls != c) continue;
      const Stats& s = r.stats;
      char line[512];
      std::snprintf(
          line, sizeof line,
          "| %s | %.0f | %ld | %ld | %.1e | %.1e | %.1e | %.1e | %ld / %ld | %.1e | %ld |\n",
          r.config.c_str(), r.nsPerRay, s.wc, s.disagree, quantile(s.err, 0.5),
          quantile(s.err, 0.99), quantile(s.err, 1.0), quantile(s.ferr, 0.99), s.disagreeAll,
          s.rays, quantile(s.errAll, 0.99), s.speckles);
      out << line;
    }
  }
}

struct Args {
  bool tiny = false;
  std::filesystem::path out = ".";
  int reps = 3;
  std::vector<std::string> surfaces;
};

int run(const Args& args) {
  const auto wall0 = std::chrono::steady_clock::now();
  RaySetSizes sizes;
  if (args.tiny) sizes = {6, 12, 8, 8};
  const int reps = args.tiny ? 1 : args.reps;
  std::vector<std::string> names = args.surfaces;
  if (names.empty()) {
    if (args.tiny)
      names = {"sphere", "cayley-cubic", "barth-sextic"};
    else
      for (const GallerySurface& g : gallery()) names.emplace_back(g.name);
  }
  const std::vector<Config> configs = configurations();
  RTCDevice device = rtcNewDevice("threads=1");
  std::vector<Row> rows;
  std::map<std::pair<int, std::string>, Stats> pooled;
  std::map<std::pair<int, std::string>, std::pair<double, int>> logTime;  // sum log ns, count
  auto parallel = [](size_t n, auto&& body) {
    tbb::parallel_for(size_t(0), n, [&](size_t i) { body(i); });
  };
  unsigned long long callbackErrors = 0;
  for (const std::string& name : names) {
    const GallerySurface* g = findGallerySurface(name);
    if (!g) {
      std::cerr << "unknown gallery surface '" << name << "'\n";
      return 2;
    }
    const Polynomial f = g->build();
    const double radius = g->clipRadius;
    const auto t0 = std::chrono::steady_clock::now();
    const RaySets sets = buildRaySets(f, radius, sizes, 12345u, parallel);
    const double refSeconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::fprintf(stderr, "%-16s degree %2d: references %.1f s (", name.c_str(), f.degree(),
                 refSeconds);
    for (RayClass c : kRayClasses) std::fprintf(stderr, " %s %zu", className(c), sets[c].size());
    std::fprintf(stderr, " rays)\n");

    // ---- One scene per configuration, all alive so passes interleave ----------------
    std::vector<SurfaceGeometry> geoms;
    geoms.reserve(configs.size());
    std::vector<RTCScene> scenes;
    for (const Config& c : configs) {
      SurfaceDesc desc;
      desc.polynomial = f;
      desc.clip = ClipSphere{glm::dvec3(0.0), radius};
      desc.options = c.options;
      geoms.emplace_back(device, desc);
      RTCScene scene = rtcNewScene(device);
      rtcAttachGeometry(scene, geoms.back().geometry());
      rtcCommitScene(scene);
      scenes.push_back(scene);
    }
    for (RayClass cls : kRayClasses) {
      const std::vector<BenchRay>& rays = sets[cls];
      if (rays.empty()) continue;
      std::vector<double> best(configs.size(), 1e300);
      std::vector<std::vector<TraceResult>> results(configs.size(),
                                                    std::vector<TraceResult>(rays.size()));
      // Pass -1 warms caches (and the origin cache) and is not timed.
      for (int rep = -1; rep < reps; ++rep)
        for (size_t k = 0; k < configs.size(); ++k) {
          const auto a = std::chrono::steady_clock::now();
          for (size_t i = 0; i < rays.size(); ++i)
            results[k][i] = traceOne(scenes[k], rays[i].ray, configs[k].floatRays);
          const double s =
              std::chrono::duration<double>(std::chrono::steady_clock::now() - a).count();
          if (rep >= 0) best[k] = std::min(best[k], s);
        }
      for (size_t k = 0; k < configs.size(); ++k) {
        Row row{name, f.degree(), cls, configs[k].name, score(rays, results[k], radius), 0.0};
        row.stats.seconds = best[k];
        row.nsPerRay = 1e9 * best[k] / static_cast<double>(rays.size());
        rows.push_back(row);
        pooled[{static_cast<int>(cls), configs[k].name}].add(row.stats);
        auto& lt = logTime[{static_cast<int>(cls), configs[k].name}];
        lt.first += std::log(row.nsPerRay);
        lt.second += 1;
      }
    }
    for (size_t k = 0; k < configs.size(); ++k) {
      callbackErrors += geoms[k].callbackErrors();
      rtcReleaseScene(scenes[k]);
    }
  }
  rtcReleaseDevice(device);

  std::vector<Row> pooledRows;
  for (RayClass cls : kRayClasses)
    for (const Config& c : configs) {
      const auto key = std::make_pair(static_cast<int>(cls), c.name);
      if (!pooled.count(key)) continue;
      const auto& lt = logTime[key];
      pooledRows.push_back({"ALL", 0, cls, c.name, pooled[key], std::exp(lt.first / lt.second)});
    }
  std::vector<Row> all = rows;
  all.insert(all.end(), pooledRows.begin(), pooledRows.end());
  std::filesystem::create_directories(args.out);
  writeCsv(args.out / "intersector.csv", all);
  const double wall =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
  std::string cpu = "unknown CPU";
  {
    std::ifstream info("/proc/cpuinfo");
    for (std::string line; std::getline(info, line);)
      if (line.rfind("model name", 0) == 0) {
        cpu = line.substr(line.find(':') + 2);
        break;
      }
  }
  char note[512];
  std::snprintf(
      note, sizeof note,
      "Machine: %s, %u hardware threads. Pooled over %zu surfaces; ns/ray = geometric mean over "
      "surfaces of the best of %d passes, single thread; errors relative to the clip radius. "
      "Run time %.0f s.",
      cpu.c_str(), std::thread::hardware_concurrency(), names.size(), reps, wall);
  writeMarkdown(std::cout, pooledRows, note);
  std::cout << "\ncallback errors: " << callbackErrors << "\n";
  long nonfinite = 0;
  for (const Row& r : pooledRows) nonfinite += r.stats.nonfinite;
  if (nonfinite > 0 || callbackErrors > 0) {
    std::cerr << "FAILED: " << nonfinite << " non-finite hits, " << callbackErrors
              << " callback errors\n";
    return 1;
  }
  return 0;
}

}  // namespace
}  // namespace algray::bench

int main(int argc, char** argv) {
  algray::bench::Args args;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--tiny") {
      args.tiny = true;
    } else if (a == "--out" && i + 1 < argc) {
      args.out = argv[++i];
    } else if (a == "--reps" && i + 1 < argc) {
      args.reps = std::max(1, std::atoi(argv[++i]));
    } else if (a == "--surface" && i + 1 < argc) {
      args.surfaces.emplace_back(argv[++i]);
    } else {
      std::cerr << "usage: " << argv[0] << " [--tiny] [--out DIR] [--reps N] [--surface NAME]...\n";
      return 2;
    }
  }
  try {
    return algray::bench::run(args);
  } catch (const std::exception& e) {
    std::cerr << "error: " << e.what() << "\n";
    return 1;
  }
}
