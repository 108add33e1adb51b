#pragma once
// The figures of tests/bench/speed_report.cpp: one measured entry (a scene and its best
// times) and the tables written from them (stdout/Markdown and CSV). Header-only: the
// bench CMake builds one executable per *_report.cpp.
#include "algray/embree.h"

#include <embree3/rtcore.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "speed_trace.h"

namespace algray::bench {
// ---- One measured thing: a scene and its figures ----------------------------------------
enum Metric { kP1, kPAll, kP8, kS1, kSAll, kS8, kMetricCount };
inline constexpr std::array<const char*, kMetricCount> kMetricName = {
    "primary_1t", "primary_allt", "primary_pkt8", "shadow_1t", "shadow_allt", "shadow_pkt8"};

struct Entry {
  std::string surface;
  int degree = 0;
  std::string method;  // algray, embree-sphere, mc
  std::string config;  // algray: default / no-...; mc: target triangle count
  RTCScene scene = nullptr;
  std::unique_ptr<SurfaceGeometry> geometry;
  unsigned long long primitives = 0;
  double tessellationMs = NAN, buildMs = NAN;
  bool allMetrics = false;     // else primary and shadow on one thread only
  bool packetMetrics = false;  // the pkt8 figures too (a packet switch)
  float shadowTnear = 0.0f;
  // Own shadow rays, or shared by all configurations of an algray surface.
  std::shared_ptr<const std::vector<ShadowRay>> shadowSet;
  std::array<Seconds, kMetricCount> best{};  // fastest pass; 0 = not measured
  double hitFraction = NAN, disagreeFraction = NAN, occludedFraction = NAN;
  size_t primaryRays = 0;
  std::vector<float> depth;  // tfar per pixel of the last one-thread primary pass

  // Mrays/s per wall second, or per CPU second of the tracing thread (one-thread metrics).
  double mrays(Metric m, bool cpu = false) const {
    const double s = cpu ? best[m].cpu : best[m].wall;
    if (!(s > 0.0) || (cpu && (m == kPAll || m == kSAll))) return NAN;
    const size_t n = m <= kP8 ? primaryRays : shadowSet->size();
    return static_cast<double>(n) / s * 1e-6;
  }
};

// ---- Output ----------------------------------------------------------------------------------
inline std::string fmt(double v, const char* format = "%.3g") {
  if (!std::isfinite(v)) return "";
  char buf[64];
  std::snprintf(buf, sizeof buf, format, v);
  return buf;
}

inline std::string machineName() {
  std::ifstream in("/proc/cpuinfo");
  std::string line;
  while (std::getline(in, line))
    if (line.rfind("model name", 0) == 0) {
      const auto colon = line.find(':');
      if (colon != std::string::npos) return line.substr(line.find_first_not_of(" \t", colon + 1));
    }
  return "unknown CPU";
}

// Depth image (near = bright, miss = black) of the last primary pass: hit/miss
// disagreements between methods are easiest to judge by eye.
inline void writeDepthImage(const std::string& dir, const Entry& e, const View& v) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  float lo = INFINITY, hi = -INFINITY;
  for (float t : e.depth)
    if (std::isfinite(t)) lo = std::min(lo, t), hi = std::max(hi, t);
  std::ofstream out(
      std::filesystem::path(dir) / (e.surface + "-" + e.method + "-" + e.config + ".pgm"),
      std::ios::binary);
  out << "P5\n" << v.width << " " << v.height << "\n255\n";
  for (float t : e.depth) {
    const double s = std::isfinite(t) ? 255.0 - 200.0 * (t - lo) / std::max(hi - lo, 1e-30f) : 0.0;
    out.put(static_cast<char>(static_cast<unsigned char>(std::clamp(s, 0.0, 255.0))));
  }
}

inline std::string label(const Entry& e) {
  if (e.method == "algray") return e.config == "default" ? "algray" : "algray " + e.config;
  if (e.method == "mc") return "MC " + e.config + " tris";
  if (e.method == "user-float-sphere") return "float user-geometry sphere (floor)";
  return "Embree sphere";
}

inline void writeCsv(const std::filesystem::path& path, const std::vector<Entry>& entries) {
  std::ofstream out(path);
  out << "surface,degree,method,config,primitives,tessellation_ms,build_ms,primary_rays,shadow_"
         "rays,"
         "hit_fraction,disagree_fraction,occluded_fraction";
  for (const char* m : kMetricName) out << "," << m << "_mrays";
  for (Metric m : {kP1, kP8, kS1, kS8}) out << "," << kMetricName[m] << "_cpu_mrays";
  out << "\n";
  for (const Entry& e : entries) {
    out << e.surface << "," << e.degree << "," << e.method << "," << e.config << "," << e.primitives
        << "," << fmt(e.tessellationMs, "%.1f") << "," << fmt(e.buildMs, "%.1f") << ","
        << e.primaryRays << "," << e.shadowSet->size() << "," << fmt(e.hitFraction, "%.4f") << ","
        << fmt(e.disagreeFraction, "%.4f") << "," << fmt(e.occludedFraction, "%.4f");
    for (int m = 0; m < kMetricCount; ++m)
      out << "," << fmt(e.mrays(static_cast<Metric>(m)), "%.4g");
    for (Metric m : {kP1, kP8, kS1, kS8}) out << "," << fmt(e.mrays(m, true), "%.4g");
    out << "\n";
  }
}

// Main table: every method of every surface, all columns (switch configs excluded).
inline std::string mainTable(const std::vector<Entry>& entries) {
  std::ostringstream s;
  s << "| surface | deg | method | primitives | build ms | rays | hit % | differ % | primary 1T | "
       "(CPU) | "
       "primary allT | primary pkt8 | shadow 1T | (CPU) | shadow allT | shadow pkt8 |\n"
       "|---|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
  for (const Entry& e : entries) {
    if (!e.allMetrics) continue;
    s << "| " << e.surface << " | " << e.degree << " | " << label(e) << " | " << e.primitives
      << " | " << fmt(e.buildMs, "%.0f") << " | " << e.primaryRays << " | "
      << fmt(100 * e.hitFraction, "%.1f") << " | " << fmt(100 * e.disagreeFraction, "%.2f");
    for (int m = 0; m < kMetricCount; ++m) {
      s << " | " << fmt(e.mrays(static_cast<Metric>(m)));
      if (m == kP1 || m == kS1) s << " | " << fmt(e.mrays(static_cast<Metric>(m), true));
    }
    s << " |\n";
  }
  return s.str();
}

// Summary: one row per surface, algray beside its finest tessellation (and Embree's sphere).
inline std::string summaryTable(const std::vector<Entry>& entries) {
  std::ostringstream s;
  s << "| surface | deg | algray cells | build ms | primary 1T (CPU) | primary allT | shadow 1T "
       "(CPU) | "
       "shadow allT | mesh | mesh build ms | mesh primary 1T (CPU) | mesh shadow 1T (CPU) | algray "
       "/ mesh "
       "primary 1T (CPU) | differ % |\n"
       "|---|---:|---:|---:|---:|---:|---:|---:|---|---:|---:|---:|---:|---:|\n";
  auto both = [](const Entry& e, Metric m) {
    return fmt(e.mrays(m)) + " (" + fmt(e.mrays(m, true)) + ")";
  };
  for (const Entry& a : entries) {
    if (a.method != "algray" || a.config != "default") continue;
    // The other method of this surface to set beside it: Embree's sphere if any, else the last
    // mesh.
    const Entry* other = nullptr;
    for (const Entry& e : entries)
      if (e.surface == a.surface && e.method != "algray" && e.method != "user-float-sphere" &&
          (!other || other->method != "embree-sphere"))
        other = &e;
    if (!other) continue;
    s << "| " << a.surface << " | " << a.degree << " | " << a.primitives << " | "
      << fmt(a.buildMs, "%.0f") << " | " << both(a, kP1) << " | " << fmt(a.mrays(kPAll)) << " | "
      << both(a, kS1) << " | " << fmt(a.mrays(kSAll)) << " | " << label(*other) << " | "
      << fmt(other->buildMs, "%.0f") << " | " << both(*other, kP1) << " | " << both(*other, kS1)
      << " | " << fmt(a.mrays(kP1) / other->mrays(kP1), "%.3f") << " ("
      << fmt(a.mrays(kP1, true) / other->mrays(kP1, true), "%.3f") << ") | "
      << fmt(100 * a.disagreeFraction, "%.2f") << " |\n";
  }
  return s.str();
}

// Switch table: algray 1-thread Mrays/s per configuration, and the ratio to the default.
inline std::string switchTable(const std::vector<Entry>& entries,
                               const std::vector<std::string>& configs) {
  std::ostringstream s;
  s << "| surface | deg | figure |";
  for (const auto& c : configs) s << " " << c << " |";
  s << "\n|---|---:|---|";
  for (size_t i = 0; i < configs.size(); ++i) s << "---:|";
  s << "\n";
  std::vector<std::string> surfaces;
  for (const Entry& e : entries)
    if (std::find(surfaces.begin(), surfaces.end(), e.surface) == surfaces.end())
      surfaces.push_back(e.surface);
  for (const auto& name : surfaces)
    for (Metric m : {kP1, kS1, kP8, kS8, kMetricCount}) {
      const Entry* base = nullptr;
      for (const Entry& e : entries)
        if (e.surface == name && e.method == "algray" && e.config == "default") base = &e;
      if (!base) continue;
      // The pkt8 rows only where a switch measured them (the packet switch).
      bool measured = m != kP8 && m != kS8;
      for (const Entry& e : entries)
        measured = measured || (e.surface == name && e.method == "algray" && e.packetMetrics);
      if (!measured) continue;
      s << "| " << name << " | " << base->degree << " | "
        << (m == kP1   ? "primary"
            : m == kS1 ? "shadow"
            : m == kP8 ? "primary pkt8"
            : m == kS8 ? "shadow pkt8"
                       : "differ %")
        << " |";
      for (const auto& c : configs) {
        const Entry* x = nullptr;
        for (const Entry& e : entries)
          if (e.surface == name && e.method == "algray" && e.config == c) x = &e;
        if (!x || (m != kMetricCount && !std::isfinite(x->mrays(m, true)))) {
          s << " - |";
        } else if (m == kMetricCount) {
          s << " " << fmt(100 * x->disagreeFraction, "%.2f") << " |";
        } else if (x == base) {
          s << " " << fmt(x->mrays(m, true)) << " |";
        } else {
          s << " " << fmt(x->mrays(m, true)) << " ("
            << fmt(x->mrays(m, true) / base->mrays(m, true), "%.2f") << "x) |";
        }
      }
      s << "\n";
    }
  return s.str();
}

inline std::string targets(const std::vector<Entry>& entries) {
  auto find = [&](const std::string& surface, const std::string& method) -> const Entry* {
    for (const Entry& e : entries)
      if (e.surface == surface && e.method == method &&
          (method != "algray" || e.config == "default"))
        return &e;
    return nullptr;
  };
  std::ostringstream s;
  const Entry* sphere = find("sphere", "algray");
  const Entry* native = find("sphere", "embree-sphere");
  if (sphere && native)
    for (Metric m : {kP1, kPAll, kP8, kS1, kSAll, kS8})
      s << "- sphere " << kMetricName[m]
        << ": algray / Embree native = " << fmt(sphere->mrays(m) / native->mrays(m), "%.2f")
        << (m == kPAll || m == kSAll
                ? ""
                : " (per CPU second: " +
                      fmt(sphere->mrays(m, true) / native->mrays(m, true), "%.2f") + ")")
        << " (target >= 1)\n";
  // Embree's sphere writes u = v = 0, as algray by default; with SurfaceOptions::uv on,
  // algray also computes the spherical u, v of each hit.
  const Entry* sphereUV = nullptr;
  for (const Entry& e : entries)
    if (e.surface == "sphere" && e.method == "algray" && e.config == "uv-on") sphereUV = &e;
  if (sphereUV && native)
    for (Metric m : {kP1, kP8})
      s << "- sphere " << kMetricName[m]
        << " with uv on (algray's spherical u, v; Embree's sphere writes 0): "
        << "algray / Embree native = " << fmt(sphereUV->mrays(m) / native->mrays(m), "%.2f")
        << " (per CPU second: " << fmt(sphereUV->mrays(m, true) / native->mrays(m, true), "%.2f")
        << ")\n";
  // The user-geometry floor: a float sphere with no bound (speed_report.cpp).
  if (const Entry* floor = find("sphere", "user-float-sphere"); floor && native && sphere)
    for (Metric m : {kP1, kS1})
      s << "- sphere " << kMetricName[m] << ": plain float user-geometry sphere / Embree native = "
        << fmt(floor->mrays(m) / native->mrays(m), "%.2f")
        << "; algray / that floor = " << fmt(sphere->mrays(m) / floor->mrays(m), "%.2f") << "\n";
  if (const Entry* b = find("barth-sextic", "algray"))
    s << "- barth-sextic primary 1T: " << fmt(b->mrays(kP1)) << " Mrays/s, "
      << fmt(b->mrays(kP1, true)) << " per CPU second (target >= 3)\n";
  if (const Entry* b = find("sarti-dodecic", "algray"))
    s << "- sarti-dodecic primary 1T: " << fmt(b->mrays(kP1)) << " Mrays/s, "
      << fmt(b->mrays(kP1, true)) << " per CPU second (target >= 1)\n";
  return s.str();
}

}  // namespace algray::bench
