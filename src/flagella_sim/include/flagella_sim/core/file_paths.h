// File paths handed over by a launcher: a relative path means relative to the directory the user
// started it in, not to the process's own working directory (ROS nodes run in ROS_HOME).
#pragma once

#include <filesystem>
#include <string>

namespace flagella {

/// `path` joined onto `base` when `path` is relative and `base` is not empty; else `path`.
inline std::string resolveAgainst(const std::string& path, const std::string& base) {
  if (path.empty() || base.empty() || std::filesystem::path(path).is_absolute()) return path;
  return (std::filesystem::path(base) / path).lexically_normal().string();
}

}  // namespace flagella
