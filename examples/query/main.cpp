// algray-query: trace the rays of a CSV file against one algebraic surface, through an
// Embree scene holding the algray geometry (rtcIntersect1), and write the hits as CSV.
//
//   algray-query --surface "x^2+y^2+z^2-1" --clip-sphere 1.5 --rays in.csv --out out.csv
//   algray-query --surface barth-sextic --rays in.csv --out out.csv   (a gallery name)
//
// Exit codes: 0 success, 2 bad flags, equation or input rows (message on stderr with
// the line or column), 1 anything else (I/O, Embree).
#include "cli_text.h"
#include "equation_place.h"
#include "ray_csv.h"
#include "rounding_noise.h"

#include "algray/cells.h"
#include "algray/embree.h"
#include "algray/gallery.h"
#include "algray/parser.h"

#include <tbb/global_control.h>
#include <tbb/parallel_for.h>
#include <CLI/CLI.hpp>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <limits>
#include <optional>
#include <sstream>
#include <string>
#include <string_view>

#include <unistd.h>

namespace {

using namespace algray;

// Bad input from the user: exit code 2.
struct UsageError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// What goes before the caret under `text` for its 1-based `column` (in code points, as
// ParseError counts): a space per character, but the text's own tabs as tabs, so that the
// terminal moves the caret as far as it moved the equation (a space per tab left the
// caret up to 7 columns short).
std::string caretPad(std::string_view text, int column) {
  std::string pad;
  int character = 1;
  for (size_t i = 0; i < text.size() && character < column; ++i) {
    if ((static_cast<unsigned char>(text[i]) & 0xC0) == 0x80) continue;  // inside a character
    pad += text[i] == '\t' ? '\t' : ' ';
    ++character;
  }
  return pad + std::string(static_cast<size_t>(std::max(0, column - character)), ' ');
}

// `number` read from `text` (trimmed), for the option `what`: finite, or refused.
double checkedNumber(const std::string& text, const cli::Number& number, const std::string& what) {
  // As in IN.csv: a literal below double's range is refused, not silently 0 (--param
  // a=1e-400 turned x^2+y^2+z^2-a into a point). A subnormal result is its value.
  if (number.problem == cli::NumberProblem::kUnderflows)
    throw UsageError(what + ": '" + text + "' underflows to 0 in double");
  if (number.problem != cli::NumberProblem::kNone || !std::isfinite(number.value))
    throw UsageError(what + ": not a finite number: '" + text + "'");
  return number.value;
}

double parseNumber(const std::string& given, const std::string& what) {
  const std::string text = cli::trimmed(given);
  return checkedNumber(text, cli::readNumber(text), what);
}

ClipRegion parseClip(const std::vector<double>& sphere, const std::string& box) {
  if (!sphere.empty()) {
    if (!(sphere[0] > 0.0 && std::isfinite(sphere[0])))
      throw UsageError("--clip-sphere: the radius must be finite and > 0");
    return ClipSphere{glm::dvec3(0.0), sphere[0]};
  }
  // getline drops a trailing empty field: "1,2,3,4,5,6," would pass as six numbers.
  if (!box.empty() && box.back() == ',')
    throw UsageError("--clip-box: a value is missing after the last ','");
  std::vector<double> v;
  std::stringstream s(box);
  std::string item;
  while (std::getline(s, item, ','))
    v.push_back(parseNumber(item, "--clip-box value " + std::to_string(v.size() + 1)));
  if (v.size() != 6)
    throw UsageError("--clip-box: expected X0,Y0,Z0,X1,Y1,Z1 (6 numbers), got " +
                     std::to_string(v.size()));
  ClipBox b{{v[0], v[1], v[2]}, {v[3], v[4], v[5]}};
  if (!(b.lo.x < b.hi.x && b.lo.y < b.hi.y && b.lo.z < b.hi.z))
    throw UsageError("--clip-box: need X0 < X1, Y0 < Y1, Z0 < Z1");
  return b;
}

// One ray through the scene. Double precision through algray's context (default), or
// Embree's float ray and hit (--float).
query::QueryHit trace(RTCScene scene, unsigned geomID, const RayD& ray, bool useFloat) {
  query::QueryHit out;
  glm::dvec3 ng(0.0);
  if (useFloat) {
    RTCRayHit rh = makeRayHit(ray, scene);
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    rtcIntersect1(scene, &context, &rh);
    if (rh.hit.geomID != geomID) return out;
    out.hit = true;
    out.t = fromFloatParameter(ray, rh.ray.tfar, scene);  // the float ray may be re-parametrised
    ng = {rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z};
  } else {
    HitD hit;
    IntersectContext context;
    initIntersectContext(&context, &ray, &hit, scene);
    RTCRayHit rh = makeRayHit(context);
    rtcIntersect1(scene, &context.base, &rh);
    if (!hit.hit || rh.hit.geomID != geomID) return out;
    out.hit = true;
    out.t = hit.t;
    ng = hit.Ng;
  }
  // Scaled first: the gradient of a surface with coefficients like 1e200 has no finite
  // square.
  const double m = std::max({std::abs(ng.x), std::abs(ng.y), std::abs(ng.z)});
  if (m > 0.0 && std::isfinite(m)) out.normal = glm::normalize(ng / m);
  return out;
}

// Without the column org_error, a user's o + t d of a hit carries gamma(3) (|o| + |t d|)
// from the ray that found it, not the rounding of its own coordinates (orgError = 0): a
// ray leaving a cylinder from a hit point of a ray that started 10 clip radii away found
// its own origin at t = 2.5e-15. Every origin is then taken to be such a point, of a ray
// that started within 32 scene radii of the clip centre; it only matters to an origin
// within about 1e-14 scene radii of the surface. The scene's radius: the clip radius, at
// most 2^24 object radii (the window then stays below ~4e-7 of the object's radius), the
// object's from the scene's bounds (the surface's cells, as Embree holds them) and
// surfaceReach (cells.h). (The clip radius alone gave a unit sphere clipped to a ball of
// radius 1e14 an uncertainty of 2.1 at every origin, and every ray from 5 away missed it;
// the object's radius alone, hit points of a camera 10 clip radii from a unit sphere in a
// ball of radius 100 met their own origin; 2^10 object radii, those of a camera 1e6 away
// from one in a ball of radius 1e6: session 51's reviews.)
// Origins beyond 4 clip radii keep 0: the self-root rule ignores them, and the far-ray
// paths read orgError. With the column, each ray's own bound is used as given (hit points
// of rays from farther away).
void setDefaultOrgErrors(std::vector<RayD>& rays, const SurfaceDesc& desc, const glm::dvec3& centre,
                         double radius, RTCScene scene) {
  RTCBounds b;
  rtcGetSceneBounds(scene, &b);
  const glm::dvec3 lo(b.lower_x, b.lower_y, b.lower_z), hi(b.upper_x, b.upper_y, b.upper_z);
  const glm::dvec3 corner = glm::max(glm::max(centre - lo, hi - centre), glm::dvec3(0.0));
  const double m = std::max({corner.x, corner.y, corner.z});
  double farthest = m > 0.0 ? m * glm::length(corner / m) : 0.0;  // (no overflow)
  constexpr double kSceneObjects = 0x1p24;
  if (farthest > 0.0 && kSceneObjects * farthest > radius) {
    std::optional<CellSphere> sphere;
    glm::dvec3 boxLo, boxHi;
    if (const auto* box = std::get_if<ClipBox>(&desc.clip)) {
      boxLo = box->lo, boxHi = box->hi;
    } else {
      sphere = CellSphere{centre, radius};
      boxLo = centre - glm::dvec3(radius), boxHi = centre + glm::dvec3(radius);
    }
    const double reach =
        surfaceReach(desc.polynomial, boxLo, boxHi, sphere, centre, 1.6e7, radius / kSceneObjects);
    if (reach > 0.0) farthest = std::min(farthest, reach);
  }
  const double object = farthest > 0.0 && farthest < radius ? farthest : radius;
  const double size = std::min(radius, kSceneObjects * object);
  for (RayD& ray : rays) {
    const glm::dvec3 oc = glm::abs(ray.org - centre);
    if (std::max({oc.x, oc.y, oc.z}) <= 4.0 * radius)
      ray.orgError = gamma(3) * (glm::length(oc) + 64.0 * size);
  }
}

int run(int argc, char** argv) {
  CLI::App app{"Trace rays from a CSV file against an algebraic surface (algray + Embree)"};
  std::string equation, raysPath, outPath, clipBox;
  std::vector<std::string> params;
  std::vector<double> clipSphere;
  bool useFloat = false;
  int threads = 0;
  app.add_option("--surface", equation,
                 "equation f(x,y,z) = 0, e.g. \"x^2+y^2+z^2-1\", or a gallery name (its clip "
                 "sphere unless --clip-sphere or --clip-box is given)")
      ->required();
  app.add_option("--param", params, "NAME=VALUE for a parameter of the equation (repeatable)");
  auto* sphereOpt =
      app.add_option("--clip-sphere", clipSphere, "clip sphere radius about the origin")
          ->expected(1);
  auto* boxOpt = app.add_option("--clip-box", clipBox, "clip box X0,Y0,Z0,X1,Y1,Z1");
  sphereOpt->excludes(boxOpt);
  app.add_option(
         "--rays", raysPath,
         "input CSV: ox,oy,oz,dx,dy,dz,tnear,tfar[,org_error] (direction non-zero, 0 <= tnear <= "
         "tfar, tfar may be inf; org_error: the origin's uncertainty, >= 0)")
      ->required();
  app.add_option("--out", outPath, "output CSV: hit,t,nx,ny,nz")->required();
  app.add_flag("--float", useFloat,
               "trace Embree's float rays instead of algray's double channel (org_error must be "
               "0: float rays carry none)");
  app.add_option("--threads", threads, "worker threads (default: all cores)")
      ->transform(algray::cli::decimal())
      ->check(CLI::Range(1, 1024));
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::cerr << "algray-query: " << e.what() << "\n"
              << "run with --help for usage\n";
    return 2;
  }
  // ---- Surface ------------------------------------------------------------------------
  ParseOptions parseOptions;
  parseOptions.rejectUnusedParameters = true;
  for (const std::string& p : params) {
    cli::Param param = cli::readParam(p);
    if (param.name.empty()) throw UsageError("--param '" + p + "': expected NAME=VALUE");
    if (param.number.problem == cli::NumberProblem::kNotANumber) {  // a constant, as in f?
      std::string problem;
      const std::optional<double> v = cli::constantExpression(param.valueText, problem);
      if (!v)
        throw UsageError("--param " + param.name + ": '" + param.valueText +
                         "' is neither a number nor a constant (" + problem + ")");
      param.number = {*v, cli::NumberProblem::kNone};
    }
    const double value = checkedNumber(param.valueText, param.number, "--param " + param.name);
    // A second value would silently win: which one the user meant is not ours to guess.
    if (!parseOptions.parameters.emplace(param.name, value).second)
      throw UsageError("--param " + param.name + ": given more than once");
  }
  SurfaceDesc desc;
  if (const GallerySurface* g = findGallerySurface(equation)) {
    // As in algray-render: a gallery surface's parameters are built in.
    if (!parseOptions.parameters.empty())
      throw UsageError("--param " + parseOptions.parameters.begin()->first +
                       ": the gallery surface '" + std::string(g->name) + "' takes no parameters");
    desc.polynomial = g->build();
    if (clipSphere.empty() && clipBox.empty()) clipSphere = {g->clipRadius};
  } else {
    try {
      desc.polynomial = parsePolynomial(equation, parseOptions);
    } catch (const ParameterError& e) {
      throw UsageError("--param " + e.name() + ": " + e.message());
    } catch (const ParseError& e) {
      // A name close to a gallery surface's was most likely meant as one ("barth_sextc").
      std::string hint = similarGallerySurfacesText(equation);
      if (!hint.empty())
        hint = " (or did you mean " + hint + "?)";
      else if (!e.unknownName().empty())
        hint = " (give it a value with --param " + e.unknownName() + "=VALUE)";
      // An equation with line breaks: the line and its column, and that line shown.
      const cli::EquationPlace at = cli::equationPlace(equation, e.column());
      if (!at.multiLine)
        throw UsageError("--surface: column " + std::to_string(e.column()) + ": " + e.message() +
                         hint + "\n  " + equation + "\n  " + caretPad(equation, e.column()) + "^");
      throw UsageError("--surface: line " + std::to_string(at.line) + ", column " +
                       std::to_string(at.column) + ": " + cli::placedMessage(e, equation) + hint +
                       "\n  " + std::string(at.text) + "\n  " + caretPad(at.text, at.column) + "^");
    }
    if (clipSphere.empty() && clipBox.empty())
      throw UsageError("one of --clip-sphere R or --clip-box X0,Y0,Z0,X1,Y1,Z1 is required");
  }
  desc.clip = parseClip(clipSphere, clipBox);

  // ---- Rays -----------------------------------------------------------------------------
  // A directory opens as a stream that reads nothing: it was reported as an empty file.
  std::error_code ec;
  if (std::filesystem::is_directory(raysPath, ec))
    throw UsageError("--rays: '" + raysPath + "' is a directory");
  std::ifstream in(raysPath);
  if (!in) throw UsageError("--rays: cannot open '" + raysPath + "'");
  std::vector<RayD> rays;
  bool givenOrgErrors = false;
  try {
    rays = query::readRays(in, raysPath, &givenOrgErrors);
  } catch (const query::CsvError& e) {
    throw UsageError(e.what());
  }
  // Embree's float ray has no field for an origin's uncertainty: with --float a row's
  // org_error was read and silently not used (the float channel assumes its own bound,
  // that of a float origin near the clip region), so a hit point given with the error of
  // a ray from far away could find its own origin. Refused rather than ignored.
  if (useFloat)
    for (size_t i = 0; i < rays.size(); ++i)
      if (rays[i].orgError != 0.0) {
        std::ostringstream value;
        value << rays[i].orgError;
        throw UsageError("--float: ray " + std::to_string(i + 1) + " has org_error " + value.str() +
                         ", which Embree's float rays cannot carry (they assume the rounding "
                         "of a float origin near the clip region): trace it without --float");
      }

  // (The clip region's centre and radius: halves first, the half-diagonal's length scaled:
  // a box beyond the plugin's range, -1e200..1e200, overflowed here to an infinite radius,
  // and the check below blamed the rays' directions instead of letting the plugin name the
  // box's size.)
  auto length = [](const glm::dvec3& v) {
    const double m = std::max({std::abs(v.x), std::abs(v.y), std::abs(v.z)});
    return m > 0 ? m * glm::length(v / m) : 0.0;
  };
  const ClipBox* box = std::get_if<ClipBox>(&desc.clip);
  const glm::dvec3 centre = box ? 0.5 * box->lo + 0.5 * box->hi : glm::dvec3(0.0);
  const double radius = box ? length(0.5 * box->hi - 0.5 * box->lo) : clipSphere[0];

  // A direction so short that the clip region's far side is beyond double's range of t
  // (1e-310 from 3 radii away: t = 2e310) has hits whose t cannot be written; it was
  // reported as a miss. t there is (|o - c| + R) / |d|, with everything scaled by d's
  // largest component (lengths of huge or tiny vectors over- or underflow their squares).
  auto farT = [&](const RayD& ray) {
    const double m = std::max({std::abs(ray.dir.x), std::abs(ray.dir.y), std::abs(ray.dir.z)});
    const double d = glm::length(ray.dir / m);  // its largest component is 1: no over- or underflow
    return length((ray.org - centre) / m) / d + radius / m / d;
  };
  for (size_t i = 0; i < rays.size(); ++i)
    if (!std::isfinite(farT(rays[i])))
      throw UsageError("--rays: ray " + std::to_string(i + 1) +
                       ": the direction is so short that t at the clip region would overflow "
                       "double (scale it up)");

  // OUT is checked before tracing (a path that cannot be written is bad input) but opened,
  // and so truncated, only once every hit is known: an error on the way (a surface the
  // plugin refuses) left OUT empty, and with --out naming the rays file the input was
  // lost. An existing file is tried for writing without truncation; a new one needs a
  // writable directory. Written in place, so a file keeps its inode, mode and links, a
  // symbolic link (even a dangling one) its target, and /dev/stdout or a pipe works. (A
  // temporary file renamed over OUT, tried first, changed all of those and refused names
  // near NAME_MAX and files in read-only directories.)
  namespace fs = std::filesystem;
  // (An empty name passed as "." and failed after every ray was traced, exit 1.)
  if (outPath.empty()) throw UsageError("--out: the file name is empty");
  const fs::file_status outStatus = fs::status(outPath, ec);
  if (fs::is_directory(outStatus)) throw UsageError("--out: '" + outPath + "' is a directory");
  if (fs::is_regular_file(outStatus)) {
    std::fstream probe(outPath, std::ios::in | std::ios::out);
    if (!probe) throw UsageError("--out: cannot write '" + outPath + "'");
  } else if (!fs::exists(outStatus)) {
    const fs::path parent = fs::path(outPath).parent_path();
    // (A file as the directory was "Permission denied", access()'s word for it.)
    if (!parent.empty() && fs::exists(parent, ec) && !fs::is_directory(parent, ec))
      throw UsageError("--out: cannot write '" + outPath + "' ('" + parent.string() +
                       "' is not a directory)");
    if (access(parent.empty() ? "." : parent.c_str(), W_OK | X_OK) != 0)
      throw UsageError("--out: cannot write '" + outPath + "' (" + std::strerror(errno) + ")");
  }

  // ---- Scene -------------------------------------------------------------------------------
  RTCDevice device = rtcNewDevice(nullptr);
  if (!device) throw std::runtime_error("cannot create the Embree device");
  std::vector<query::QueryHit> hits(rays.size());
  double seconds = 0;
  {
    std::unique_ptr<SurfaceGeometry> surface;
    // The library's message names its own class; the user needs the options it came from.
    const std::string clipOption = clipSphere.empty() ? "--clip-box" : "--clip-sphere";
    try {
      surface = std::make_unique<SurfaceGeometry>(device, desc);
    } catch (const ScaleError& e) {
      rtcReleaseDevice(device);
      // The library's remedy is its transform, which this tool does not have: here the
      // scale is the units of the equation, the clip region and the rays (--clip-sphere
      // 1e-300 was told to "scale the polynomial's variables instead of undoing it by the
      // transform").
      throw UsageError("--surface, " + clipOption + ": " + e.problem() +
                       ": write --surface in units of about the surface's size, and " + clipOption +
                       " and the rays in the same units (--rays: every column but tnear and "
                       "tfar; t stays the same)");
    } catch (const Error& e) {
      rtcReleaseDevice(device);
      throw UsageError("--surface, " + clipOption + ": " + e.what());
    }
    if (surface->primitiveCount() == 0)
      std::cerr << "algray-query: warning: no point of the surface lies in the clip region "
                   "(every ray misses)\n";
    else if (const std::string noise = cli::noiseWarning(desc.polynomial, desc.clip);
             !noise.empty())
      std::cerr << "algray-query: warning: " << noise << "\n";
    RTCScene scene = rtcNewScene(device);
    const unsigned geomID = rtcAttachGeometry(scene, surface->geometry());
    rtcCommitScene(scene);
    if (!givenOrgErrors) setDefaultOrgErrors(rays, desc, centre, radius, scene);

    // ---- Trace (timed: tracing only) -----------------------------------------------------
    const int workers = threads > 0 ? threads : tbb::this_task_arena::max_concurrency();
    tbb::global_control control(tbb::global_control::max_allowed_parallelism, workers);
    const auto start = std::chrono::steady_clock::now();
    tbb::parallel_for(tbb::blocked_range<size_t>(0, rays.size(), 64),
                      [&](const tbb::blocked_range<size_t>& r) {
                        for (size_t i = r.begin(); i != r.end(); ++i)
                          hits[i] = trace(scene, geomID, rays[i], useFloat);
                      });
    seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    rtcReleaseScene(scene);
    if (surface->callbackErrors() > 0)
      std::cerr << "algray-query: warning: " << surface->callbackErrors()
                << " rays failed inside the plugin (counted as misses)\n";
  }
  rtcReleaseDevice(device);

  std::ofstream out(outPath);
  if (!out) throw std::runtime_error("--out: cannot write '" + outPath + "'");
  query::writeHits(out, hits);
  out.close();
  if (!out) throw std::runtime_error("--out: error writing '" + outPath + "'");
  const double rate = seconds > 0 ? static_cast<double>(rays.size()) / seconds : 0.0;
  std::fprintf(stderr, "%.0f rays/s\n", rate);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return run(argc, argv);
  } catch (const UsageError& e) {
    std::cerr << "algray-query: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "algray-query: error: " << e.what() << "\n";
    return 1;
  }
}
