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

// Display value in [0,1] of a linear radiance: exposure (stops), the tone curve, sRGB.
glm::dvec3 toDisplay(const glm::dvec3& linear, double exposure, ToneMap toneMap);

// One channel of toDisplay in 8 bits, exactly lround(255 * toDisplay(...)), by a table
// search instead of std::pow: what PNG files get.
std::uint8_t toDisplayByte(double linear, double exposure, ToneMap toneMap);

// Whether the file format of `path` (its extension) can hold the AOV channels: a float
// format with any number of channels (.exr, .tif, .tiff; not .hdr, which is RGB only).
bool holdsAovs(const std::string& path);

// aovs: also write depth/normal/albedo/id (float formats only). Throws
// std::runtime_error naming the file on failure.
void writeImage(const Image& image, const std::string& path, const RenderSettings& settings,
                bool aovs);

}  // namespace algray::render
