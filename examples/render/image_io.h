#pragma once
// Image output through OpenImageIO, written atomically (OUT.algray-PID.tmp, then rename).
//  * .exr (and other float formats): linear radiance R,G,B plus the AOV channels
//    Z (depth), N.X N.Y N.Z (normal), albedo.R albedo.G albedo.B, id.
//  * .png, .jpg, ...: exposure, tone mapping and the sRGB transfer curve, 8 bits.
#include "render.h"
#include "scene_desc.h"

#include <glm/vec3.hpp>

#include <cstdint>
#include <string>

namespace algray::render {

// Display value in [0,1] of a linear radiance: exposure (stops), the tone curve, sRGB
// (ToneMap::None: the exposed value clamped, no curve).
glm::dvec3 toDisplay(const glm::dvec3& linear, double exposure, ToneMap toneMap);

// sRGB's decoding (IEC 61966-2-1): the linear value of an encoded one in [0, 1] (8- and
// 16-bit textures, and float files of the surfer integrator's display values).
double srgbDecode(double c);

// One channel of toDisplay in 8 bits, exactly lround(255 * toDisplay(...)), by a table
// search instead of std::pow: what PNG files get.
std::uint8_t toDisplayByte(double linear, double exposure, ToneMap toneMap);

// Whether the file format of `path` (its extension) can hold the AOV channels: a float
// format with any number of channels (.exr, .tif, .tiff; not .hdr, which is RGB only).
bool holdsAovs(const std::string& path);

// The extra channels `--aov` asks for (float formats only): depth `Z`, normal `N.X N.Y
// N.Z`, albedo `albedo.R/G/B`, object `id`.
struct AovSet {
  bool depth = false, normal = false, albedo = false, id = false;
  bool any() const { return depth || normal || albedo || id; }
  static AovSet all() { return {true, true, true, true}; }
};

// Parses a comma-separated `--aov` list ("depth,normal"); throws std::invalid_argument
// naming an unknown or empty entry.
AovSet parseAovList(const std::string& list);

// Writes R, G, B and the channels of `aovs`. Throws std::runtime_error naming the file on
// failure.
// A name part for the tool's own files beside OUT: the PID and 64 random bits in hex (the
// PID alone is shared by processes in different containers writing one directory).
std::string uniqueSuffix();

void writeImage(const Image& image, const std::string& path, const RenderSettings& settings,
                const AovSet& aovs = {});

}  // namespace algray::render
