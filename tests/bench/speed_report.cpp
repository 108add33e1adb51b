// Speed of the plugin (issue 5): for every gallery surface, Mrays/s of primary and shadow
// rays, beside Embree's native sphere and a marching-cubes tessellation of the same
// surface, all measured in the same run, and the effect of each optimisation switched off.
//
//   primary   a pinhole camera framing the clip sphere (tests/bench/speed_trace.h),
//             width x height rays, tnear = 0, tfar = inf;
//   shadow    from each primary hit towards a point light (t in (tnear, 1)). For algray
//             surfaces the origin is the hit point itself (the double-precision hit,
//             rounded to float) with tnear = 0: the plugin removes the self-root. The
//             native sphere and the meshes have no such rule and get the usual
//             offset, tnear = 1e-4 of the ray's length to the light;
//   1T / allT one thread (a plain loop) / all threads (tbb::parallel_for over rows);
//   pkt8      rtcIntersect8 / rtcOccluded8 on one thread (4x2 pixel tiles);
//   build     SurfaceGeometry (cells) + rtcCommitScene, or marching cubes + BVH build;
//             Embree builds with all threads, the tessellation runs on one.
// Mrays/s = rays / wall seconds of tracing only, best of --reps passes; all methods and
// configurations of a surface are interleaved within each pass so that their ratios are
// measured side by side on this noisy machine. One-thread loops are also timed in CPU
// seconds of the tracing thread (CSV *_cpu_mrays, switch table): on a loaded machine that
// excludes the time the thread waited for a core.
//   rays      a surface whose algray primary pass would exceed --budget CPU seconds traces
//             every stride-th pair of rows only (the same rows for every method);
//   differ %  pixels whose hit/miss differs from the finest marching-cubes mesh: an
//             independent sanity check of every method and configuration (the mesh has
//             its own resolution error at thin features and nodes, typically < 1 %).
//
// Switches (algray::SurfaceOptions, one off at a time, primary and shadow on one thread):
// no-cells (one primitive for the whole clip region), cells-depth4 (cells forced to a
// depth-4 octree, in case the automatic depth chooses few cells), origin-cache (switched on:
// off by default), no-recentre,
// no-closed-forms (RootMethod::Yuksel for degrees <= 4; above, Auto is Yuksel already),
// no-quadric-path (degree 2 through the general restriction, cache and polish),
// no-packet-simd (degree 2: the quadric callbacks loop over a packet's lanes instead of
// quadric_packet.cpp; measured on pkt8, the rows "primary pkt8" and "shadow pkt8"), and
// uv-on (not an optimisation but an option: SurfaceOptions::uv = true, the hits' spherical
// u, v for a textured surface; the default writes u = v = 0, as Embree's own sphere).
//
// Writes DIR/speed.csv and DIR/speed.md and prints the tables.
//
//   speed_report [--tiny] [--out DIR] [--width W --height H] [--reps N] [--surface NAME]...
//                [--no-1m] [--budget S] [--images]
#include "algray/embree.h"
#include "algray/gallery.h"

#include <glm/geometric.hpp>

#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <limits>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "marching_cubes.h"
#include "speed_tables.h"
#include "speed_trace.h"

namespace algray::bench {
namespace {

// ---- Command line ----------------------------------------------------------------------
struct Args {
  bool tiny = false;
  std::string out = "speed-report";
  int width = 512, height = 512;
  int reps = 3;
  double budget = 0.2;  // CPU seconds of one algray primary pass on one thread
  bool mesh1m = true;
  bool images = false;  // write each method's depth image (PGM) for a visual check
  std::vector<std::string> surfaces;
};

void releaseEntry(Entry& e) {
  if (e.scene) rtcReleaseScene(e.scene);
  e.scene = nullptr;
  e.geometry.reset();
}

double msSince(std::chrono::steady_clock::time_point start) { return 1e3 * secondsSince(start); }

// ---- Builders ------------------------------------------------------------------------------
Entry algrayEntry(RTCDevice device, const GallerySurface& s, const Polynomial& f,
                  std::string config, const SurfaceOptions& options) {
  Entry e;
  e.surface = std::string(s.name);
  e.degree = f.degree();
  e.method = "algray";
  e.config = std::move(config);
  const auto start = std::chrono::steady_clock::now();
  SurfaceDesc desc;
  desc.polynomial = f;
  desc.clip = ClipSphere{{0, 0, 0}, s.clipRadius};
  desc.options = options;
  e.geometry = std::make_unique<SurfaceGeometry>(device, desc);
  e.scene = rtcNewScene(device);
  rtcAttachGeometry(e.scene, e.geometry->geometry());
  rtcCommitScene(e.scene);
  e.buildMs = msSince(start);
  e.primitives = e.geometry->primitiveCount();
  e.allMetrics = e.config == "default";
  e.packetMetrics = e.config == "no-packet-simd" || e.config == "uv-on";
  return e;
}

// ---- The user-geometry floor ---------------------------------------------------------------
// The unit sphere as the plainest Embree user geometry (Embree's tutorial style: float
// textbook quadratic, no error bound, no clip, u = v = 0): what any user geometry pays for
// Embree's traversal and callback, beside which algray's rigorous double kernel and
// Embree's own sphere primitive are measured.
void floatSphereBounds(const RTCBoundsFunctionArguments* a) {
  *a->bounds_o = RTCBounds{-1.0f, -1.0f, -1.0f, 0.0f, 1.0f, 1.0f, 1.0f, 0.0f};
}
// The first root of |o + t d|^2 = 1 in (tnear, tfar) of one lane, or -1.
float floatSphereRoot(RTCRayN* ray, unsigned n, unsigned i) {
  const glm::vec3 o(RTCRayN_org_x(ray, n, i), RTCRayN_org_y(ray, n, i), RTCRayN_org_z(ray, n, i));
  const glm::vec3 d(RTCRayN_dir_x(ray, n, i), RTCRayN_dir_y(ray, n, i), RTCRayN_dir_z(ray, n, i));
  const float a = glm::dot(d, d), b = 2.0f * glm::dot(o, d), c = glm::dot(o, o) - 1.0f,
              disc = b * b - 4.0f * a * c;
  if (!(disc >= 0.0f)) return -1.0f;
  const float root = std::sqrt(disc), t0 = (-b - root) / (2.0f * a), t1 = (-b + root) / (2.0f * a);
  const float tnear = RTCRayN_tnear(ray, n, i), tfar = RTCRayN_tfar(ray, n, i);
  return t0 > tnear && t0 < tfar ? t0 : t1 > tnear && t1 < tfar ? t1 : -1.0f;
}
void floatSphereIntersect(const RTCIntersectFunctionNArguments* args) {
  RTCRayN* ray = RTCRayHitN_RayN(args->rayhit, args->N);
  RTCHitN* hit = RTCRayHitN_HitN(args->rayhit, args->N);
  for (unsigned i = 0; i < args->N; ++i) {
    if (!args->valid[i]) continue;
    const float t = floatSphereRoot(ray, args->N, i);
    if (t < 0.0f) continue;
    RTCRayN_tfar(ray, args->N, i) = t;
    RTCHitN_Ng_x(hit, args->N, i) =
        RTCRayN_org_x(ray, args->N, i) + t * RTCRayN_dir_x(ray, args->N, i);
    RTCHitN_Ng_y(hit, args->N, i) =
        RTCRayN_org_y(ray, args->N, i) + t * RTCRayN_dir_y(ray, args->N, i);
    RTCHitN_Ng_z(hit, args->N, i) =
        RTCRayN_org_z(ray, args->N, i) + t * RTCRayN_dir_z(ray, args->N, i);
    RTCHitN_u(hit, args->N, i) = RTCHitN_v(hit, args->N, i) = 0.0f;
    RTCHitN_primID(hit, args->N, i) = args->primID;
    RTCHitN_geomID(hit, args->N, i) = args->geomID;
    RTCHitN_instID(hit, args->N, i, 0) = args->context->instID[0];
  }
}
void floatSphereOccluded(const RTCOccludedFunctionNArguments* args) {
  for (unsigned i = 0; i < args->N; ++i)
    if (args->valid[i] && floatSphereRoot(args->ray, args->N, i) >= 0.0f)
      RTCRayN_tfar(args->ray, args->N, i) = -std::numeric_limits<float>::infinity();
}

// A reference sphere (make() returns its uncommitted geometry) in a scene of its own.
template <class MakeGeometry>
Entry sphereEntry(RTCDevice device, std::string method, std::string config, MakeGeometry make) {
  Entry e;
  e.surface = "sphere";
  e.degree = 2;
  e.method = std::move(method);
  e.config = std::move(config);
  const auto start = std::chrono::steady_clock::now();
  RTCGeometry g = make();
  rtcCommitGeometry(g);
  e.scene = rtcNewScene(device);
  rtcAttachGeometry(e.scene, g);
  rtcReleaseGeometry(g);
  rtcCommitScene(e.scene);
  e.buildMs = msSince(start);
  e.primitives = 1;
  e.allMetrics = true;
  e.shadowTnear = 1e-4f;
  return e;
}

Entry floatUserSphereEntry(RTCDevice device) {
  return sphereEntry(device, "user-float-sphere", "floor", [device] {
    RTCGeometry g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_USER);
    rtcSetGeometryUserPrimitiveCount(g, 1);
    rtcSetGeometryBoundsFunction(g, &floatSphereBounds, nullptr);
    rtcSetGeometryIntersectFunction(g, &floatSphereIntersect);
    rtcSetGeometryOccludedFunction(g, &floatSphereOccluded);
    return g;
  });
}

// Embree's own sphere (RTC_GEOMETRY_TYPE_SPHERE_POINT), one point of radius 1.
Entry nativeSphereEntry(RTCDevice device) {
  return sphereEntry(device, "embree-sphere", "native", [device] {
    RTCGeometry g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_SPHERE_POINT);
    auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0,
                                                          RTC_FORMAT_FLOAT4, 4 * sizeof(float), 1));
    v[0] = v[1] = v[2] = 0.0f;
    v[3] = 1.0f;
    return g;
  });
}

Entry meshEntry(RTCDevice device, const GallerySurface& s, const Polynomial& f, double target,
                std::string label) {
  Entry e;
  e.surface = std::string(s.name);
  e.degree = f.degree();
  e.method = "mc";
  e.config = std::move(label);
  const int cells = marchingCubesResolution(f, glm::dvec3(0.0), s.clipRadius, target);
  auto start = std::chrono::steady_clock::now();
  const TriangleMesh mesh = marchingCubes(f, glm::dvec3(0.0), s.clipRadius, cells);
  e.tessellationMs = msSince(start);
  start = std::chrono::steady_clock::now();
  RTCGeometry g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
  if (!mesh.triangles.empty()) {
    auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(
        g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), mesh.vertices.size()));
    std::memcpy(v, mesh.vertices.data(), mesh.vertices.size() * sizeof(glm::vec3));
    auto* t = static_cast<std::uint32_t*>(
        rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                3 * sizeof(std::uint32_t), mesh.triangles.size()));
    std::memcpy(t, mesh.triangles.data(), mesh.triangles.size() * 3 * sizeof(std::uint32_t));
  }
  rtcCommitGeometry(g);
  e.scene = rtcNewScene(device);
  if (!mesh.triangles.empty()) rtcAttachGeometry(e.scene, g);
  rtcReleaseGeometry(g);
  rtcCommitScene(e.scene);
  e.buildMs = e.tessellationMs + msSince(start);
  e.primitives = mesh.triangles.size();
  e.allMetrics = true;
  e.shadowTnear = 1e-4f;
  return e;
}

// ---- Shadow rays ---------------------------------------------------------------------------
// algray: the exact hit of each primary ray through the double channel (the float ray's
// own values, so it is the hit the timed float pass finds), rounded to float.
std::vector<ShadowRay> algrayShadows(RTCScene scene, const View& v) {
  std::vector<ShadowRay> out;
  for (size_t i = 0; i < v.dirs.size(); ++i) {
    RayD ray;
    ray.org = glm::dvec3(v.eye);
    ray.dir = glm::dvec3(v.dirs[i]);
    ray.tnear = 0.0;
    ray.tfar = INFINITY;
    HitD hit;
    IntersectContext context;
    initIntersectContext(&context, &ray, &hit, scene);
    RTCRayHit rh = makeRayHit(context);
    rtcIntersect1(scene, &context.base, &rh);
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID || !hit.hit) continue;
    const glm::vec3 p(ray.org + hit.t * ray.dir);
    out.push_back({p, v.light - p});
  }
  return out;
}

// Other geometries: the float hit point o + tfar d of the primary pass.
std::vector<ShadowRay> floatShadows(const View& v, const std::vector<float>& t) {
  std::vector<ShadowRay> out;
  for (size_t i = 0; i < v.dirs.size(); ++i) {
    if (!std::isfinite(t[i])) continue;
    const glm::vec3 p = v.eye + t[i] * v.dirs[i];
    out.push_back({p, v.light - p});
  }
  return out;
}

// ---- Measurement -----------------------------------------------------------------------------
void keepBest(Entry& e, Metric m, Seconds s) {
  if (e.best[m].wall == 0.0 || s.wall < e.best[m].wall) e.best[m].wall = s.wall;
  if (e.best[m].cpu == 0.0 || s.cpu < e.best[m].cpu) e.best[m].cpu = s.cpu;
}

// One pass of every metric of the entry; the reference pixels' hits (the finest
// tessellation) give the disagreement fraction.
void measurePass(Entry& e, const View& v, const std::vector<float>* reference) {
  std::vector<float> t;
  std::vector<std::uint8_t> occ;
  e.primaryRays = v.dirs.size();
  keepBest(e, kP1, tracePrimary1(e.scene, v, t));
  size_t hits = 0, differ = 0;
  for (size_t i = 0; i < t.size(); ++i) {
    hits += std::isfinite(t[i]);
    if (reference) differ += std::isfinite(t[i]) != std::isfinite((*reference)[i]);
  }
  e.hitFraction = static_cast<double>(hits) / t.size();
  e.depth = t;
  if (reference) e.disagreeFraction = static_cast<double>(differ) / t.size();
  if (e.allMetrics) keepBest(e, kPAll, tracePrimaryAll(e.scene, v, t));
  if (e.allMetrics || e.packetMetrics) keepBest(e, kP8, tracePrimary8(e.scene, v, t));
  keepBest(e, kS1, traceShadow1(e.scene, *e.shadowSet, e.shadowTnear, occ));
  size_t occluded = 0;
  for (std::uint8_t o : occ) occluded += o;
  e.occludedFraction = occ.empty() ? NAN : static_cast<double>(occluded) / occ.size();
  if (e.allMetrics) keepBest(e, kSAll, traceShadowAll(e.scene, *e.shadowSet, e.shadowTnear, occ));
  if (e.allMetrics || e.packetMetrics)
    keepBest(e, kS8, traceShadow8(e.scene, *e.shadowSet, e.shadowTnear, occ));
}

int run(const Args& args) {
  const std::string machine = machineName();
  const unsigned threads = std::thread::hardware_concurrency();
  std::printf("speed_report: %s, %u hardware threads, %dx%d primary rays, best of %d\n",
              machine.c_str(), threads, args.width, args.height, args.reps);

  RTCDevice device = rtcNewDevice(nullptr);
  if (!device) {
    std::fprintf(stderr, "speed_report: rtcNewDevice failed\n");
    return 1;
  }
  const std::vector<std::string> configs = {"default",         "no-cells",       "cells-depth4",
                                            "origin-cache",    "no-recentre",    "no-closed-forms",
                                            "no-quadric-path", "no-packet-simd", "uv-on"};
  std::vector<Entry> done;
  unsigned long long callbackErrors = 0;
  for (const GallerySurface& s : gallery()) {
    if (!args.surfaces.empty() && std::find(args.surfaces.begin(), args.surfaces.end(),
                                            std::string(s.name)) == args.surfaces.end())
      continue;
    const Polynomial f = s.build();
    const View full = makeView(glm::dvec3(0.0), s.clipRadius, args.width, args.height);
    std::fprintf(stderr, "[%s] building...\n", std::string(s.name).c_str());

    // ---- Scenes: algray configurations, Embree's sphere, tessellations -----------------
    std::vector<Entry> entries;
    for (const auto& c : configs) {
      SurfaceOptions o;
      if (c == "no-cells") o.useCells = false;
      if (c == "cells-depth4")
        o.cellDepth = 4;  // an octree of depth 4, whatever the automatic rule says
      if (c == "origin-cache") o.originCache = true;
      if (c == "no-recentre") o.recentre = false;
      if (c == "no-quadric-path") {
        if (f.degree() != 2) continue;
        o.quadricPath = false;
      }
      if (c == "no-packet-simd") {
        if (f.degree() != 2) continue;
        o.packetSimd = false;
      }
      if (c == "uv-on") o.uv = true;
      if (c == "no-closed-forms") {
        if (f.degree() > 4) continue;
        o.roots.method = RootMethod::Yuksel;
      }
      entries.push_back(algrayEntry(device, s, f, c, o));
    }
    if (s.name == "sphere") {
      entries.push_back(nativeSphereEntry(device));
      entries.push_back(floatUserSphereEntry(device));
    }
    entries.push_back(meshEntry(device, s, f, args.tiny ? 2e4 : 1e5, args.tiny ? "20k" : "100k"));
    if (args.mesh1m) entries.push_back(meshEntry(device, s, f, 1e6, "1M"));

    // ---- Ray budget: slow surfaces trace a subset of rows (the same for every method) ---
    int stride = 1;
    if (args.budget > 0.0) {
      const View probe = subsampleRows(full, std::max(1, full.height / 32));
      std::vector<float> t;
      tracePrimary1(entries[0].scene, probe, t);  // warm-up (caches, first-touch pages)
      const double estimate = tracePrimary1(entries[0].scene, probe, t).cpu *
                              static_cast<double>(full.dirs.size()) /
                              static_cast<double>(probe.dirs.size());
      stride = std::clamp(static_cast<int>(std::ceil(estimate / args.budget)), 1,
                          std::max(1, full.height / 16));
    }
    const View view = subsampleRows(full, stride);

    // ---- Shadow rays: algray's from its exact hits, the others' from their own ------------
    const auto exact =
        std::make_shared<const std::vector<ShadowRay>>(algrayShadows(entries[0].scene, view));
    for (Entry& e : entries) {
      if (e.method == "algray") {
        e.shadowSet = exact;
      } else {
        tracePrimary1(e.scene, view, e.depth);
        e.shadowSet = std::make_shared<const std::vector<ShadowRay>>(floatShadows(view, e.depth));
      }
    }
    // Hit/miss reference: the finest tessellation (independent of the plugin's code).
    const std::vector<float> reference = entries.back().depth;

    // ---- Passes, interleaved -------------------------------------------------------------
    std::fprintf(stderr, "[%s] tracing...\n", std::string(s.name).c_str());
    for (int rep = 0; rep < args.reps; ++rep)
      for (Entry& e : entries) measurePass(e, view, &e == &entries.back() ? nullptr : &reference);
    if (args.images)
      for (const Entry& e : entries) writeDepthImage(args.out, e, view);
    for (Entry& e : entries) {
      if (e.geometry) callbackErrors += e.geometry->callbackErrors();
      releaseEntry(e);
      done.push_back(std::move(e));
    }
    std::fprintf(stderr, "[%s] done\n", std::string(s.name).c_str());
  }
  rtcReleaseDevice(device);

  // ---- Report ---------------------------------------------------------------------------------
  std::ostringstream md;
  md << "Machine: " << machine << ", " << threads
     << " hardware threads. Primary rays: " << args.width << "x" << args.height
     << " pinhole camera framing the clip sphere; shadow rays from every primary hit to a point "
     << "light. Mrays/s, best of " << args.reps
     << " interleaved passes (wall clock). \"differ %\": pixels "
     << "whose hit/miss differs from the finest marching-cubes mesh's. (CPU): the one-thread "
        "figure per CPU second of "
     << "the tracing thread (excludes waiting for a core on a loaded machine).\n\n"
     << summaryTable(done) << "\nAll methods:\n\n"
     << mainTable(done)
     << "\nOptimisations switched off one at a time (algray, one thread, Mrays/s per CPU "
     << "second of the tracing thread, and the ratio to the default; < 1 means the optimisation "
        "helps; "
     << "\"differ %\" as above, for each configuration):\n\n"
     << switchTable(done, configs) << "\nTargets:\n\n"
     << targets(done);
  if (callbackErrors)
    md << "\nWARNING: " << callbackErrors << " exceptions caught in Embree callbacks.\n";
  std::cout << md.str();

  std::error_code ec;
  std::filesystem::create_directories(args.out, ec);
  writeCsv(std::filesystem::path(args.out) / "speed.csv", done);
  std::ofstream(std::filesystem::path(args.out) / "speed.md") << md.str();
  std::printf("wrote %s/speed.csv and %s/speed.md\n", args.out.c_str(), args.out.c_str());
  return callbackErrors ? 1 : 0;
}

}  // namespace
}  // namespace algray::bench

int main(int argc, char** argv) {
  algray::bench::Args args;
  bool sizeGiven = false, repsGiven = false;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto value = [&](int& target) {
      if (i + 1 >= argc) return false;
      target = std::atoi(argv[++i]);
      return target > 0;
    };
    bool ok = true;
    if (a == "--tiny") {
      args.tiny = true;
    } else if (a == "--out" && i + 1 < argc) {
      args.out = argv[++i];
    } else if (a == "--width") {
      ok = value(args.width);
      sizeGiven = true;
    } else if (a == "--height") {
      ok = value(args.height);
      sizeGiven = true;
    } else if (a == "--reps") {
      ok = value(args.reps);
      repsGiven = true;
    } else if (a == "--surface" && i + 1 < argc) {
      args.surfaces.emplace_back(argv[++i]);
    } else if (a == "--budget" && i + 1 < argc) {
      args.budget = std::atof(argv[++i]);
    } else if (a == "--images") {
      args.images = true;
    } else if (a == "--no-1m") {
      args.mesh1m = false;
    } else {
      ok = false;
    }
    if (!ok) {
      std::cerr << "usage: " << argv[0]
                << " [--tiny] [--out DIR] [--width W --height H] [--reps N] [--surface NAME]... "
                   "[--no-1m] [--budget S] [--images]\n"
                << "bad argument: " << a << "\n";
      return 2;
    }
  }
  if (args.tiny) {
    if (!sizeGiven) args.width = args.height = 48;
    if (!repsGiven) args.reps = 1;
    args.mesh1m = false;
    if (args.surfaces.empty()) args.surfaces = {"sphere", "torus", "barth-sextic"};
  }
  for (const auto& name : args.surfaces)
    if (!algray::findGallerySurface(name)) {
      std::cerr << "speed_report: no gallery surface named '" << name << "'\n";
      return 2;
    }
  try {
    return algray::bench::run(args);
  } catch (const std::exception& e) {
    std::cerr << "speed_report: " << e.what() << "\n";
    return 1;
  }
}
