#include "conde_physics/resource_path.h"

namespace conde_physics {

std::string directoryOf(const std::string& path) {
  const auto slash = path.find_last_of('/');
  return slash == std::string::npos ? "." : path.substr(0, slash == 0 ? 1 : slash);
}

std::string resolveResourcePath(const std::string& uri, const std::string& relative_to_dir,
                                const PackageResolver& packages, std::string& error) {
  error.clear();
  const std::string package_scheme = "package://";
  const std::string file_scheme = "file://";
  if (uri.rfind(package_scheme, 0) == 0) {
    const std::string rest = uri.substr(package_scheme.size());
    const auto slash = rest.find('/');
    const std::string package = rest.substr(0, slash);
    const std::string package_dir = packages ? packages(package) : std::string();
    if (package_dir.empty()) {
      error = "unknown package '" + package + "' in '" + uri + "'";
      return "";
    }
    return slash == std::string::npos ? package_dir : package_dir + rest.substr(slash);
  }
  if (uri.rfind(file_scheme, 0) == 0) return uri.substr(file_scheme.size());
  if (uri.empty()) {
    error = "empty file name";
    return "";
  }
  if (uri[0] == '/') return uri;
  return relative_to_dir + "/" + uri;
}

}  // namespace conde_physics
