#include "output_paths.h"

#include <unistd.h>

#include <filesystem>

#include "rrr/io/input_error.h"

namespace rrr {
namespace fs = std::filesystem;
namespace {

// The file `path` names, resolved through symbolic links and "..", whether
// or not it exists yet.
fs::path Resolved(const std::string& path) {
  std::error_code error;
  const fs::path resolved = fs::weakly_canonical(fs::absolute(path), error);
  return error ? fs::absolute(path).lexically_normal() : resolved;
}

}  // namespace

void CheckOutputPaths(const std::vector<std::string>& inputs,
                      const std::vector<std::string>& outputs) {
  for (size_t k = 0; k < outputs.size(); ++k) {
    const std::string& out = outputs[k];
    if (out.empty()) continue;
    const fs::path target = Resolved(out);
    for (const std::string& in : inputs) {
      if (!in.empty() && Resolved(in) == target) {
        throw InputError(
            out, 0, "is also an input (" + in + "): refusing to overwrite it");
      }
    }
    for (size_t j = 0; j < k; ++j) {
      if (!outputs[j].empty() && Resolved(outputs[j]) == target) {
        throw InputError(
            out, 0, "is given for two outputs (also as " + outputs[j] + ")");
      }
    }
    std::error_code error;
    if (fs::is_directory(target, error)) {
      throw InputError(out, 0, "is a folder, not a file");
    }
    if (fs::exists(target, error)) {
      if (access(target.c_str(), W_OK) != 0) {
        throw InputError(out, 0, "cannot be written (no permission)");
      }
      continue;
    }
    const fs::path folder = target.parent_path();
    if (!fs::is_directory(folder, error)) {
      throw InputError(
          out, 0,
          "cannot be written: folder " + folder.string() + " does not exist");
    }
    if (access(folder.c_str(), W_OK) != 0) {
      throw InputError(
          out, 0, "cannot be written: no permission in " + folder.string());
    }
  }
}

}  // namespace rrr
