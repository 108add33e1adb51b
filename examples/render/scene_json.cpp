#include "scene_json.h"

#include "json_locate.h"
#include "value_checks.h"

#include <algray/gallery.h>
#include <algray/parser.h>

#include <glm/gtc/matrix_transform.hpp>
#include <nlohmann/json.hpp>

#include <cctype>
#include <cerrno>
#include <cstdlib>
#include <fstream>
#include <map>
#include <optional>
#include <set>
#include <sstream>

namespace algray::render {

SceneError::SceneError(const std::string& file, int line, int column, const std::string& message)
    : std::runtime_error(line > 0 ? file + ":" + std::to_string(line) + ":" +
                                        std::to_string(column) + ": " + message
                                  : file + ": " + message),
      file_(file),
      line_(line),
      column_(column),
      message_(message) {}

namespace {

using nlohmann::json;

// Walks the parsed document; every accessor knows the JSON pointer of its value so that
// errors point into the text.
class Loader {
 public:
  // A UTF-8 byte-order mark (editors on Windows write one) is not part of the text: nlohmann
  // skips it, so the position scanner must too, or it saw no values at all and duplicate
  // keys, underflowing literals and every error's line and column went unchecked.
  Loader(std::string_view text, std::string name, std::filesystem::path baseDir)
      : text_(text.starts_with("\xEF\xBB\xBF") ? text.substr(3) : text),
        name_(std::move(name)),
        baseDir_(std::move(baseDir)) {}

  SceneDesc load() {
    // A scene nests 4 levels deep; 64 leaves room for any hand-written "description".
    constexpr int kMaxNesting = 64;
    if (const size_t at = findExcessiveNesting(text_, kMaxNesting); at != std::string_view::npos) {
      const TextLocation loc = locateOffset(text_, at);
      throw SceneError(
          name_, loc.line, loc.column,
          "nesting deeper than " + std::to_string(kMaxNesting) + " levels of arrays and objects");
    }
    // nlohmann's parser stops at a NUL byte as at the end of the input, so whatever
    // followed one was accepted unread ({...}\0garbage rendered with exit code 0).
    if (const size_t at = text_.find('\0'); at != std::string_view::npos) {
      const TextLocation loc = locateOffset(text_, at);
      throw SceneError(name_, loc.line, loc.column, "a NUL byte (the file is not JSON text)");
    }
    try {
      root_ = json::parse(text_.begin(), text_.end());
    } catch (const json::parse_error& e) {
      // e.byte is the 1-based index of the character where parsing failed.
      TextLocation loc = locateOffset(text_, e.byte > 0 ? e.byte - 1 : 0);
      std::string what = e.what();
      auto colon = what.find(": ", what.find("parse error"));
      throw SceneError(name_, loc.line, loc.column,
                       colon == std::string::npos ? what : what.substr(colon + 2));
    } catch (const json::exception& e) {
      // Other parse failures carry no position: out_of_range.406 "number overflow parsing
      // '1e400'" quotes the literal, which is then found in the text.
      std::string what = e.what();
      if (auto close = what.find("] ");
          what.rfind("[json.exception.", 0) == 0 && close != std::string::npos)
        what = what.substr(close + 2);
      size_t at = std::string::npos;
      if (auto open = what.find('\''), end = what.rfind('\'');
          open != std::string::npos && end > open)
        at = locateNumberLiteral(text_, std::string_view(what).substr(open + 1, end - open - 1));
      if (at == std::string::npos) throw SceneError(name_, 0, 0, what);
      TextLocation loc = locateOffset(text_, at);
      throw SceneError(name_, loc.line, loc.column,
                       what.find("overflow") != std::string::npos
                           ? what + " (beyond the range of a double)"
                           : what);
    }
    std::vector<DuplicateKey> duplicates;
    offsets_ = locateJsonValues(text_, &duplicates);
    if (!duplicates.empty()) {
      // nlohmann keeps the last of repeated keys without a word: a typo'd copy-paste would
      // silently override the first value.
      const DuplicateKey& d = duplicates.front();
      TextLocation first = locateOffset(text_, d.first), second = locateOffset(text_, d.second);
      throw SceneError(name_, second.line, second.column,
                       "duplicate key '" + d.key + "' (first at line " +
                           std::to_string(first.line) + ", column " + std::to_string(first.column) +
                           ")");
    }
    SceneDesc scene;
    scene.name = name_;
    if (!root_.is_object()) fail("", "a scene is a JSON object");
    allowKeys(root_, "",
              {"render", "camera", "materials", "environment", "background", "surfaces", "meshes",
               "lights", "description"});
    // Free text for people, unused, but a string as documented (a number was accepted).
    if (root_.contains("description")) string(root_["description"], "/description");
    if (root_.contains("render")) readRender(root_["render"], "/render", scene.settings);
    if (root_.contains("camera")) readCamera(root_["camera"], "/camera", scene.camera);
    if (root_.contains("materials")) {
      const json& ms = root_["materials"];
      if (!ms.is_object()) fail("/materials", "materials is an object of named materials");
      for (auto it = ms.begin(); it != ms.end(); ++it)
        named_[it.key()] =
            scene.addMaterial(readMaterial(it.value(), "/materials/" + jsonPointerToken(it.key())));
    }
    if (root_.contains("environment")) readEnvironment(root_["environment"], "/environment", scene);
    if (root_.contains("background")) {
      scene.hasBackground = true;
      scene.background = color(root_["background"], "/background");
    }
    if (root_.contains("surfaces")) {
      const json& list = array(root_["surfaces"], "/surfaces");
      for (size_t i = 0; i < list.size(); ++i)
        readSurface(list[i], "/surfaces/" + std::to_string(i), scene);
    }
    if (root_.contains("meshes")) {
      const json& list = array(root_["meshes"], "/meshes");
      for (size_t i = 0; i < list.size(); ++i)
        readMesh(list[i], "/meshes/" + std::to_string(i), scene);
    }
    if (root_.contains("lights")) {
      const json& list = array(root_["lights"], "/lights");
      for (size_t i = 0; i < list.size(); ++i)
        readLight(list[i], "/lights/" + std::to_string(i), scene);
    }
    return scene;
  }

 private:
  // ---- Errors with positions ---------------------------------------------------------
  // stringColumn: the 1-based character of a string value (in code points, as ParseError's
  // column) where the error lies; 0 for the value itself.
  [[noreturn]] void fail(const std::string& pointer, const std::string& message,
                         int stringColumn = 0) const {
    auto it = offsets_.find(pointer);
    if (it == offsets_.end())
      throw SceneError(name_, 0, 0, (pointer.empty() ? "" : pointer + ": ") + message);
    const size_t at =
        stringColumn > 0 ? stringCharacterOffset(text_, it->second, stringColumn) : it->second;
    TextLocation loc = locateOffset(text_, at);
    throw SceneError(name_, loc.line, loc.column, message);
  }
  // "line L, column C" in the file of character `column` of a string value, for a message
  // that names a second place in it.
  std::string placeInString(const std::string& pointer, int column) const {
    auto it = offsets_.find(pointer);
    if (it == offsets_.end()) return "column " + std::to_string(column) + " of the string";
    const TextLocation loc = locateOffset(text_, stringCharacterOffset(text_, it->second, column));
    return "line " + std::to_string(loc.line) + ", column " + std::to_string(loc.column);
  }
  // "file:line:column" of a value, for labels of items whose errors come later (Scene).
  std::string where(const std::string& pointer) const {
    auto it = offsets_.find(pointer);
    if (it == offsets_.end()) return name_;
    TextLocation loc = locateOffset(text_, it->second);
    return name_ + ":" + std::to_string(loc.line) + ":" + std::to_string(loc.column);
  }
  void allowKeys(const json& j, const std::string& p,
                 std::initializer_list<const char*> keys) const {
    std::set<std::string> allowed(keys.begin(), keys.end());
    for (auto it = j.begin(); it != j.end(); ++it)
      if (!allowed.count(it.key()))
        fail(p + "/" + jsonPointerToken(it.key()), "unknown key '" + it.key() + "'");
  }
  // Keys the object type knows but this kind of it ignores: refused like unknown ones
  // ("size" on an OBJ mesh, "roughness" on a diffuse material, "fov" on an orthographic
  // camera were ignored without a word).
  void notFor(const json& j, const std::string& p, std::initializer_list<const char*> keys,
              const std::string& what) const {
    for (const char* k : keys)
      if (j.contains(k))
        fail(p + "/" + jsonPointerToken(k), std::string("'") + k + "' does not apply to " + what);
  }
  const json& object(const json& j, const std::string& p) const {
    if (!j.is_object()) fail(p, "expected an object");
    return j;
  }
  const json& array(const json& j, const std::string& p) const {
    if (!j.is_array()) fail(p, "expected an array");
    return j;
  }
  double number(const json& j, const std::string& p) const {
    if (!j.is_number()) fail(p, "expected a number");
    double v = j.get<double>();
    if (!std::isfinite(v)) fail(p, "expected a finite number");
    // nlohmann rounds a literal below double's range to 0 without a word ("a": 1e-400 made
    // x^2+y^2+z^2-a a point, exit 0); the command lines refuse such a --param. The literal
    // is read again from the text, as strtod reports the underflow.
    if (v == 0.0 && j.is_number_float()) {
      if (auto it = offsets_.find(p); it != offsets_.end()) {
        size_t end = it->second;
        while (end < text_.size() &&
               (std::isdigit(static_cast<unsigned char>(text_[end])) || text_[end] == '.' ||
                text_[end] == 'e' || text_[end] == 'E' || text_[end] == '-' || text_[end] == '+'))
          ++end;
        const std::string literal(text_.substr(it->second, end - it->second));
        errno = 0;
        const double again = std::strtod(literal.c_str(), nullptr);
        if (errno == ERANGE && again == 0.0) fail(p, "'" + literal + "' underflows to 0 in double");
      }
    }
    return v;
  }
  double positive(const json& j, const std::string& p) const {
    double v = number(j, p);
    if (!(v > 0)) fail(p, "expected a positive number");
    return v;
  }
  int integer(const json& j, const std::string& p, int lo, int hi) const {
    if (!j.is_number_integer()) fail(p, "expected an integer");
    auto v = j.get<long long>();
    if (v < lo || v > hi)
      fail(p, "expected an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
    return static_cast<int>(v);
  }
  // (An escaped NUL, "\u0000", is refused as a raw NUL byte is: file names and messages
  // ended at it, so "a.obj\u0000junk" loaded a.obj; the audit of session 51.)
  std::string string(const json& j, const std::string& p) const {
    if (!j.is_string()) fail(p, "expected a string");
    std::string s = j.get<std::string>();
    if (s.find('\0') != std::string::npos) fail(p, "a NUL character (\\u0000) in a string");
    return s;
  }
  glm::dvec3 vec3(const json& j, const std::string& p) const {
    if (!j.is_array() || j.size() != 3) fail(p, "expected an array of 3 numbers");
    return {number(j[0], p + "/0"), number(j[1], p + "/1"), number(j[2], p + "/2")};
  }
  // A colour: [r, g, b] or one number for grey; never negative.
  glm::dvec3 color(const json& j, const std::string& p) const {
    glm::dvec3 c = j.is_number() ? glm::dvec3(number(j, p)) : vec3(j, p);
    if (c.r < 0 || c.g < 0 || c.b < 0) fail(p, "colour components must not be negative");
    // The image is float: a larger component would render as inf.
    if (!isFloatColor(c)) fail(p, "colour components must be at most 3.4e38 (the largest float)");
    return c;
  }
  // A position-like value that rays are built from (value_checks.h): the offending
  // component is named.
  glm::dvec3 coordinate(const json& j, const std::string& p) const {
    glm::dvec3 v = vec3(j, p);
    for (int i = 0; i < 3; ++i)
      if (!withinCoordinateRange(v[i])) fail(p + "/" + std::to_string(i), tooFar);
    return v;
  }
  double length(const json& j, const std::string& p) const {
    double v = positive(j, p);
    if (!withinCoordinateRange(v)) fail(p, tooFar);
    return v;
  }
  static constexpr const char* tooFar =
      "magnitude beyond 1e17, outside the range Embree's float rays can trace (1.8e18): scale the "
      "scene down";
  // A direction: normalised here, where a zero or non-finite one can still be reported.
  glm::dvec3 direction(const json& j, const std::string& p) const {
    std::optional<glm::dvec3> d = safeNormalize(vec3(j, p));
    if (!d) fail(p, "direction must not be zero");
    return *d;
  }
  std::string path(const json& j, const std::string& p) const {
    std::filesystem::path file = string(j, p);
    if (file.is_relative()) file = baseDir_ / file;
    if (!std::filesystem::exists(file)) fail(p, "no such file '" + file.string() + "'");
    return file.string();
  }

  // ---- Sections ----------------------------------------------------------------------
  void readRender(const json& j, const std::string& p, RenderSettings& s) const {
    object(j, p);
    allowKeys(j, p,
              {"width", "height", "spp", "max_depth", "integrator", "seed", "exposure", "tone_map",
               "threads", "clamp"});
    if (j.contains("width")) s.width = integer(j["width"], p + "/width", 1, 1 << 15);
    if (j.contains("height")) s.height = integer(j["height"], p + "/height", 1, 1 << 15);
    if (j.contains("spp")) s.spp = integer(j["spp"], p + "/spp", 1, 1 << 20);
    if (j.contains("max_depth")) s.maxDepth = integer(j["max_depth"], p + "/max_depth", 0, 1000);
    if (j.contains("threads")) s.threads = integer(j["threads"], p + "/threads", 0, 1024);
    if (j.contains("seed"))
      s.seed = static_cast<std::uint64_t>(integer(j["seed"], p + "/seed", 0, 1 << 30));
    if (j.contains("exposure")) s.exposure = number(j["exposure"], p + "/exposure");
    if (j.contains("clamp")) {
      s.clampIndirect = number(j["clamp"], p + "/clamp");
      if (s.clampIndirect < 0) fail(p + "/clamp", "clamp must not be negative (0 = off)");
    }
    if (j.contains("integrator")) {
      std::string v = string(j["integrator"], p + "/integrator");
      if (v == "path")
        s.integrator = IntegratorType::Path;
      else if (v == "direct")
        s.integrator = IntegratorType::Direct;
      else
        fail(p + "/integrator", "integrator must be \"path\" or \"direct\"");
    }
    if (j.contains("tone_map")) {
      std::string v = string(j["tone_map"], p + "/tone_map");
      if (v == "aces")
        s.toneMap = ToneMap::Aces;
      else if (v == "clamp")
        s.toneMap = ToneMap::Clamp;
      else
        fail(p + "/tone_map", "tone_map must be \"aces\" or \"clamp\"");
    }
  }

  void readCamera(const json& j, const std::string& p, CameraDesc& c) const {
    object(j, p);
    allowKeys(j, p,
              {"type", "position", "look_at", "up", "fov", "height", "aperture", "focus_distance"});
    if (j.contains("type")) {
      std::string v = string(j["type"], p + "/type");
      if (v == "perspective")
        c.type = CameraDesc::Type::Perspective;
      else if (v == "orthographic")
        c.type = CameraDesc::Type::Orthographic;
      else
        fail(p + "/type", "camera type must be \"perspective\" or \"orthographic\"");
    }
    if (c.type == CameraDesc::Type::Perspective)
      notFor(j, p, {"height"}, "a perspective camera (it has \"fov\")");
    else
      notFor(j, p, {"fov", "aperture", "focus_distance"}, "an orthographic camera");
    if (j.contains("position")) c.position = coordinate(j["position"], p + "/position");
    if (j.contains("look_at")) c.lookAt = coordinate(j["look_at"], p + "/look_at");
    if (j.contains("up")) c.up = direction(j["up"], p + "/up");
    if (j.contains("fov")) {
      c.fovY = number(j["fov"], p + "/fov");
      if (!(c.fovY > 0 && c.fovY < 180)) fail(p + "/fov", "fov must be in (0, 180) degrees");
    }
    if (j.contains("height")) c.height = length(j["height"], p + "/height");
    if (j.contains("aperture")) {
      c.aperture = number(j["aperture"], p + "/aperture");
      if (c.aperture < 0) fail(p + "/aperture", "aperture must not be negative");
      if (!withinCoordinateRange(c.aperture)) fail(p + "/aperture", tooFar);
    }
    if (j.contains("focus_distance"))
      c.focusDistance = length(j["focus_distance"], p + "/focus_distance");
    if (c.position == c.lookAt) fail(p, "camera position and look_at coincide");
    // The camera's own test (camera.cpp), here so that the message has the file position.
    const std::optional<glm::dvec3> forward = safeNormalize(c.lookAt - c.position);
    if (!forward) fail(p, "camera position and look_at are too close to give a view direction");
    if (!(glm::length(glm::cross(*forward, c.up)) > 1e-9 * glm::length(c.up)))
      fail(p + (j.contains("up") ? "/up" : ""),
           "up must not be parallel to the view direction (position to look_at)");
  }

  Material readMaterial(const json& j, const std::string& p) const {
    object(j, p);
    allowKeys(j, p, {"type", "color", "roughness", "ior", "emission", "texture"});
    Material m;
    std::string type = j.contains("type") ? string(j["type"], p + "/type") : "diffuse";
    if (type == "diffuse")
      m.type = MaterialType::Diffuse;
    else if (type == "conductor")
      m.type = MaterialType::Conductor;
    else if (type == "dielectric")
      m.type = MaterialType::Dielectric, m.color = glm::dvec3(1.0);
    else if (type == "emissive")
      m.type = MaterialType::Emissive;
    else
      fail(p + "/type", "material type must be diffuse, conductor, dielectric or emissive");
    switch (m.type) {
      case MaterialType::Diffuse:
        notFor(j, p, {"roughness", "ior", "emission"}, "a diffuse material");
        break;
      case MaterialType::Conductor:
        notFor(j, p, {"ior", "emission"}, "a conductor");
        break;
      case MaterialType::Dielectric:
        notFor(j, p, {"roughness", "emission"}, "a (smooth) dielectric");
        break;
      case MaterialType::Emissive:
        notFor(j, p, {"color", "roughness", "ior", "texture"},
               "an emissive material (it has \"emission\")");
        break;
    }
    if (j.contains("color")) m.color = color(j["color"], p + "/color");
    if (j.contains("roughness")) {
      m.roughness = number(j["roughness"], p + "/roughness");
      if (m.roughness < 0 || m.roughness > 1) fail(p + "/roughness", "roughness must be in [0, 1]");
    }
    if (j.contains("ior")) m.ior = positive(j["ior"], p + "/ior");
    if (j.contains("emission")) m.emission = color(j["emission"], p + "/emission");
    if (m.type == MaterialType::Emissive && !j.contains("emission"))
      fail(p, "an emissive material needs \"emission\"");
    if (j.contains("texture")) {
      std::string file = path(j["texture"], p + "/texture");
      try {
        m.texture = Texture::load(file);
      } catch (const std::exception& e) {
        fail(p + "/texture", e.what());
      }
      // Each factor within float's range, their product need not be (inf pixels, exit 0).
      if (!isFloatColor(m.color * m.texture->maximum()))
        fail(p + "/texture", "colour times the texture's largest texel is beyond 3.4e38");
    }
    return m;
  }

  // "material": a name from "materials" or an inline material object.
  int materialRef(const json& j, const std::string& p, SceneDesc& scene) const {
    if (j.is_string()) {
      const std::string name = string(j, p);
      auto it = named_.find(name);
      if (it == named_.end()) fail(p, "unknown material '" + name + "'");
      return it->second;
    }
    return scene.addMaterial(readMaterial(j, p));
  }

  void readEnvironment(const json& j, const std::string& p, SceneDesc& scene) const {
    object(j, p);
    allowKeys(j, p, {"color", "image", "rotation"});
    scene.environment.color =
        j.contains("color") ? color(j["color"], p + "/color") : glm::dvec3(1.0);
    if (j.contains("image")) {
      scene.environment.image = path(j["image"], p + "/image");
      std::shared_ptr<const Texture> image;
      try {
        image = Texture::load(scene.environment.image);  // fail here, with a position
      } catch (const std::exception& e) {
        fail(p + "/image", e.what());
      }
      if (!isFloatColor(scene.environment.color * image->maximum()))
        fail(p + "/image", "colour times the image's largest texel is beyond 3.4e38");
    }
    if (j.contains("rotation")) scene.environment.rotation = number(j["rotation"], p + "/rotation");
  }

  // transform: {"translate": [..], "rotate": [x, y, z] degrees (about x, then y, then z),
  // "scale": s or [sx, sy, sz], "matrix": 16 numbers row-major}; M = T R S or the matrix.
  glm::dmat4 readTransform(const json& j, const std::string& p) const {
    object(j, p);
    allowKeys(j, p, {"translate", "rotate", "scale", "matrix"});
    if (j.contains("matrix")) {
      const json& m = j["matrix"];
      if (!m.is_array() || m.size() != 16)
        fail(p + "/matrix", "expected 16 numbers (row-major 4x4)");
      if (j.size() > 1) fail(p + "/matrix", "\"matrix\" excludes translate/rotate/scale");
      glm::dmat4 r(1.0);
      for (int row = 0; row < 4; ++row)
        for (int col = 0; col < 4; ++col)
          r[col][row] = number(m[row * 4 + col], p + "/matrix/" + std::to_string(row * 4 + col));
      if (r[0][3] != 0 || r[1][3] != 0 || r[2][3] != 0 || r[3][3] != 1)
        fail(p + "/matrix", "the matrix must be affine (last row 0 0 0 1)");
      if (glm::determinant(glm::dmat3(r)) == 0) fail(p + "/matrix", "the matrix is singular");
      return r;
    }
    glm::dmat4 m(1.0);
    if (j.contains("translate")) m = glm::translate(m, vec3(j["translate"], p + "/translate"));
    if (j.contains("rotate")) {
      glm::dvec3 r = glm::radians(vec3(j["rotate"], p + "/rotate"));
      m = glm::rotate(m, r.z, glm::dvec3(0, 0, 1));
      m = glm::rotate(m, r.y, glm::dvec3(0, 1, 0));
      m = glm::rotate(m, r.x, glm::dvec3(1, 0, 0));
    }
    if (j.contains("scale")) {
      const json& s = j["scale"];
      glm::dvec3 v = s.is_number() ? glm::dvec3(number(s, p + "/scale")) : vec3(s, p + "/scale");
      if (v.x == 0 || v.y == 0 || v.z == 0) fail(p + "/scale", "scale must not be zero");
      m = glm::scale(m, v);
    }
    return m;
  }

  ClipRegion readClip(const json& j, const std::string& p) const {
    object(j, p);
    allowKeys(j, p, {"sphere", "box"});
    if (j.contains("sphere") && j.contains("box"))
      fail(p + "/box", "clip takes exactly one of sphere, box");
    if (j.contains("sphere")) {
      const json& s = object(j["sphere"], p + "/sphere");
      allowKeys(s, p + "/sphere", {"center", "radius"});
      ClipSphere c;
      if (s.contains("center")) c.center = vec3(s["center"], p + "/sphere/center");
      if (!s.contains("radius")) fail(p + "/sphere", "a clip sphere needs \"radius\"");
      c.radius = positive(s["radius"], p + "/sphere/radius");
      return c;
    }
    if (j.contains("box")) {
      const json& b = object(j["box"], p + "/box");
      allowKeys(b, p + "/box", {"min", "max"});
      if (!b.contains("min") || !b.contains("max"))
        fail(p + "/box", "a clip box needs \"min\" and \"max\"");
      ClipBox c{vec3(b["min"], p + "/box/min"), vec3(b["max"], p + "/box/max")};
      if (!(c.lo.x < c.hi.x && c.lo.y < c.hi.y && c.lo.z < c.hi.z))
        fail(p + "/box", "clip box min must be below max");
      return c;
    }
    fail(p, "clip needs \"sphere\" or \"box\"");
  }

  void readSurface(const json& j, const std::string& p, SceneDesc& scene) const {
    object(j, p);
    allowKeys(j, p,
              {"equation", "gallery", "parameters", "clip", "transform", "material",
               "back_material", "name"});
    SurfaceItem item;
    bool hasClip = false;
    if (j.contains("gallery") == j.contains("equation"))
      fail(p, "a surface needs exactly one of \"equation\" and \"gallery\"");
    if (j.contains("gallery")) {
      std::string name = string(j["gallery"], p + "/gallery");
      const GallerySurface* g = findGallerySurface(name);
      if (!g) {
        const std::vector<std::string_view> similar = similarGallerySurfaces(name);
        std::string hint;
        for (std::string_view s : similar)
          hint += (hint.empty() ? "; did you mean '" : "' or '") + std::string(s);
        if (!hint.empty()) hint += "'?";
        fail(p + "/gallery",
             "no gallery surface '" + name + "'" + hint + " (known: " + galleryNames() + ")");
      }
      if (j.contains("parameters")) fail(p + "/parameters", "gallery surfaces take no parameters");
      item.polynomial = g->build();
      item.clip = ClipSphere{glm::dvec3(0.0), g->clipRadius};
      hasClip = true;
      item.label = where(p) + ": gallery surface '" + std::string(g->name) + "'";
    } else {
      ParseOptions options;
      options.rejectUnusedParameters = true;
      if (j.contains("parameters")) {
        const json& params = object(j["parameters"], p + "/parameters");
        for (auto it = params.begin(); it != params.end(); ++it)
          options.parameters[it.key()] =
              number(it.value(), p + "/parameters/" + jsonPointerToken(it.key()));
      }
      std::string text = string(j["equation"], p + "/equation");
      try {
        item.polynomial = parsePolynomial(text, options);
      } catch (const ParameterError& e) {
        // what(): "parameter 'a': is not used by the equation", as --param names it.
        fail(p + "/parameters/" + jsonPointerToken(e.name()), e.what());
      } catch (const ParseError& e) {
        // The column is the decoded string's: the same character in the file.
        const std::string hint =
            e.unknownName().empty()
                ? ""
                : " (give it a value in the surface's \"parameters\", e.g. {\"" + e.unknownName() +
                      "\": 1})";
        // A second place the message names ("... close '(' at column 7") is the file's too:
        // "column 7" beside the prefix's file column read as the same system.
        std::string message = e.message();
        if (e.relatedColumn() > 0)
          message = e.messageWith(placeInString(p + "/equation", e.relatedColumn()));
        fail(p + "/equation", message + hint, e.column());
      } catch (const std::exception& e) {
        fail(p + "/equation", e.what());
      }
      item.label = where(p) + ": surface " + text;
    }
    // The label leads Scene's errors (the plugin refusing the surface) with this position.
    if (j.contains("name"))
      item.label = where(p) + ": surface '" + string(j["name"], p + "/name") + "'";
    if (j.contains("clip")) {
      item.clip = readClip(j["clip"], p + "/clip");
      hasClip = true;
    }
    if (!hasClip)
      fail(p,
           "an equation surface needs a \"clip\" region (algebraic surfaces are often unbounded)");
    if (j.contains("transform")) item.transform = readTransform(j["transform"], p + "/transform");
    item.material = j.contains("material") ? materialRef(j["material"], p + "/material", scene)
                                           : defaultMaterial(scene);
    if (j.contains("back_material"))
      item.backMaterial = materialRef(j["back_material"], p + "/back_material", scene);
    scene.surfaces.push_back(std::move(item));
  }

  void readMesh(const json& j, const std::string& p, SceneDesc& scene) const {
    object(j, p);
    allowKeys(j, p,
              {"obj", "shape", "size", "subdivisions", "transform", "material", "back_material",
               "name", "uv_scale"});
    MeshItem item;
    if (j.contains("obj") == j.contains("shape"))
      fail(p, "a mesh needs exactly one of \"obj\" and \"shape\"");
    if (j.contains("obj")) {
      notFor(j, p, {"size", "subdivisions", "uv_scale"}, "an OBJ mesh (use \"transform\")");
      std::string file = path(j["obj"], p + "/obj");
      try {
        item.mesh = loadObj(file);
      } catch (const std::exception& e) {
        fail(p + "/obj", e.what());
      }
      item.label = where(p) + ": mesh " + file;
    } else {
      std::string shape = string(j["shape"], p + "/shape");
      double size = j.contains("size") ? positive(j["size"], p + "/size") : 1.0;
      if (shape == "plane") {
        notFor(j, p, {"subdivisions"}, "a plane");
        double uvScale = j.contains("uv_scale") ? positive(j["uv_scale"], p + "/uv_scale") : 1.0;
        item.mesh = makePlane(size, uvScale);
      } else if (shape == "box") {
        notFor(j, p, {"subdivisions", "uv_scale"}, "a box");
        item.mesh = makeBox(glm::dvec3(size));
      } else if (shape == "icosphere") {
        notFor(j, p, {"uv_scale"}, "an icosphere");
        int sub =
            j.contains("subdivisions") ? integer(j["subdivisions"], p + "/subdivisions", 0, 7) : 4;
        item.mesh = makeIcosphere(sub);
        for (glm::dvec3& v : item.mesh.positions) v *= size;
      } else {
        fail(p + "/shape", "shape must be plane, box or icosphere");
      }
      item.label = where(p) + ": mesh " + shape;
    }
    if (j.contains("name"))
      item.label = where(p) + ": mesh '" + string(j["name"], p + "/name") + "'";
    if (j.contains("transform")) item.transform = readTransform(j["transform"], p + "/transform");
    // Embree drops a float triangle beyond +-1.8e18 without a word (a floor of size 1e19
    // vanished from the image, exit code 0): the mesh in scene space keeps to the range of
    // every other position.
    glm::dvec3 lo(std::numeric_limits<double>::infinity()),
        hi(-std::numeric_limits<double>::infinity());
    for (const glm::dvec3& v : item.mesh.positions) {
      const glm::dvec3 w(item.transform * glm::dvec4(v, 1.0));
      if (!withinCoordinateRange(w)) fail(p, std::string("a vertex of the mesh: ") + tooFar);
      lo = glm::min(lo, w);
      hi = glm::max(hi, w);
    }
    if (const double extent = std::max({hi.x - lo.x, hi.y - lo.y, hi.z - lo.z});
        !(extent >= kMinMeshExtent))
      fail(p, "the mesh is " + (std::ostringstream() << extent).str() +
                  " across in scene space, below 1e-15, where Embree's float triangle test "
                  "underflows: scale "
                  "the scene up");
    checkResolvable(p, "the mesh", lo, hi);
    item.material = j.contains("material") ? materialRef(j["material"], p + "/material", scene)
                                           : defaultMaterial(scene);
    if (j.contains("back_material"))
      item.backMaterial = materialRef(j["back_material"], p + "/back_material", scene);
    scene.meshes.push_back(std::move(item));
  }

  // A mesh or area light smaller than 2^-44 of its coordinates: its vertices round onto
  // each other (a sphere light of radius 1e-12 at z = 1e5 became a flat disc, covered
  // twice, and shone 1.4-1.8 times its power; a quad light 1e-14 wide at y = 3 shone 2 %
  // too bright, 1e-15 11 % too dim, 1e-16 not at all), so it is refused, naming the point
  // light that stands for it. `extent`: its smallest size that must stay (a quad's shorter
  // edge), else its bounding box's largest.
  void checkResolvable(const std::string& p, const std::string& what, const glm::dvec3& lo,
                       const glm::dvec3& hi, double extent = -1.0) const {
    if (extent < 0.0) extent = std::max({hi.x - lo.x, hi.y - lo.y, hi.z - lo.z});
    const double reach = std::max({std::abs(lo.x), std::abs(lo.y), std::abs(lo.z), std::abs(hi.x),
                                   std::abs(hi.y), std::abs(hi.z)});
    if (!(extent >= 0x1p-44 * reach))
      fail(p, what + " is " + (std::ostringstream() << extent).str() +
                  " across at coordinates up to " + (std::ostringstream() << reach).str() +
                  ", below 2^-44 of them, where its vertices round onto each other: enlarge it "
                  "or use a point light");
  }

  void readLight(const json& j, const std::string& p, SceneDesc& scene) const {
    object(j, p);
    if (!j.contains("type")) fail(p, "a light needs \"type\" (point, directional, quad, sphere)");
    std::string type = string(j["type"], p + "/type");
    if (type == "point") {
      allowKeys(j, p, {"type", "position", "intensity"});
      if (!j.contains("position")) fail(p, "a point light needs \"position\"");
      scene.pointLights.push_back(
          {coordinate(j["position"], p + "/position"),
           j.contains("intensity") ? color(j["intensity"], p + "/intensity") : glm::dvec3(1.0)});
    } else if (type == "directional") {
      allowKeys(j, p, {"type", "direction", "irradiance"});
      if (!j.contains("direction"))
        fail(p, "a directional light needs \"direction\" (towards the light)");
      glm::dvec3 d = direction(j["direction"], p + "/direction");
      scene.directionalLights.push_back({d, j.contains("irradiance")
                                                ? color(j["irradiance"], p + "/irradiance")
                                                : glm::dvec3(1.0)});
    } else if (type == "quad" || type == "sphere") {
      // Area lights are emissive meshes: found by light sampling and by BSDF rays.
      Material m;
      m.type = MaterialType::Emissive;
      if (!j.contains("radiance")) fail(p, "an area light needs \"radiance\"");
      MeshItem item;
      double quadEdge = -1.0;  // the shorter edge's length
      if (type == "quad") {
        allowKeys(j, p, {"type", "corner", "edge1", "edge2", "radiance"});
        for (const char* k : {"corner", "edge1", "edge2"})
          if (!j.contains(k)) fail(p, std::string("a quad light needs \"") + k + "\"");
        const glm::dvec3 e1 = coordinate(j["edge1"], p + "/edge1"),
                         e2 = coordinate(j["edge2"], p + "/edge2");
        // Parallel or zero edges: a light of no area, which emits nothing (accepted silently).
        if (!(glm::length(glm::cross(e1, e2)) > 1e-12 * glm::length(e1) * glm::length(e2)))
          fail(p + "/edge2",
               "a quad light's edges must span an area (edge1 and edge2 are parallel or zero)");
        item.mesh = makeQuad(coordinate(j["corner"], p + "/corner"), e1, e2);
        quadEdge = std::min(glm::length(e1), glm::length(e2));
      } else {
        allowKeys(j, p, {"type", "center", "radius", "radiance"});
        if (!j.contains("center") || !j.contains("radius"))
          fail(p, "a sphere light needs \"center\" and \"radius\"");
        item.mesh = makeIcosphere(3);
        item.transform =
            glm::scale(glm::translate(glm::dmat4(1.0), coordinate(j["center"], p + "/center")),
                       glm::dvec3(length(j["radius"], p + "/radius")));
      }
      glm::dvec3 lo(std::numeric_limits<double>::infinity()), hi = -lo;
      for (const glm::dvec3& v : item.mesh.positions) {
        const glm::dvec3 w(item.transform * glm::dvec4(v, 1.0));
        lo = glm::min(lo, w);
        hi = glm::max(hi, w);
      }
      checkResolvable(p, "the " + type + " light", lo, hi, type == "quad" ? quadEdge : -1.0);
      m.emission = color(j["radiance"], p + "/radiance");
      item.material = scene.addMaterial(m);
      item.label = where(p) + ": " + type + " light";
      scene.meshes.push_back(std::move(item));
    } else {
      fail(p + "/type", "light type must be point, directional, quad or sphere");
    }
  }

  int defaultMaterial(SceneDesc& scene) const {
    if (defaultMaterial_ < 0) defaultMaterial_ = scene.addMaterial(Material{});
    return defaultMaterial_;
  }

  std::string_view text_;
  std::string name_;
  std::filesystem::path baseDir_;
  json root_;
  std::map<std::string, size_t> offsets_;
  std::map<std::string, int> named_;
  mutable int defaultMaterial_ = -1;
};

}  // namespace

SceneDesc loadSceneText(std::string_view text, const std::string& name,
                        const std::filesystem::path& baseDir) {
  return Loader(text, name, baseDir).load();
}

SceneDesc loadSceneFile(const std::filesystem::path& path) {
  std::error_code ec;
  // An ifstream opens a directory and reads nothing: it would be a JSON syntax error.
  if (std::filesystem::is_directory(path, ec))
    throw SceneError(path.string(), 0, 0, "is a directory, not a scene file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw SceneError(path.string(), 0, 0, "cannot open the scene file");
  std::stringstream buffer;
  buffer << in.rdbuf();
  return loadSceneText(buffer.str(), path.string(), path.parent_path());
}

}  // namespace algray::render
