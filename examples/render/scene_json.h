#pragma once
// The JSON scene format (docs/scene-format.md). Every error names the file, the line and
// the column of the offending value: "scene.json:12:17: unknown material 'gold'".
#include "scene_desc.h"

#include <filesystem>
#include <stdexcept>
#include <string>
#include <string_view>

namespace algray::render {

class SceneError : public std::runtime_error {
 public:
  // line 0: no position (e.g. the file cannot be opened).
  SceneError(const std::string& file, int line, int column, const std::string& message);
  const std::string& file() const { return file_; }
  int line() const { return line_; }
  int column() const { return column_; }
  const std::string& message() const { return message_; }

 private:
  std::string file_;
  int line_, column_;
  std::string message_;
};

// name: used in messages; baseDir: where relative paths (OBJ, textures) are looked up.
SceneDesc loadSceneText(std::string_view text, const std::string& name,
                        const std::filesystem::path& baseDir);
SceneDesc loadSceneFile(const std::filesystem::path& path);

}  // namespace algray::render
