// Resolving the file names that robot and world files use: package://pkg/path, file:///abs,
// absolute paths and paths relative to the file that names them. The package lookup is a
// callback so this library stays free of ROS (the node passes ros::package::getPath).
#pragma once

#include <functional>
#include <string>

namespace conde_physics {

// Returns the absolute path of a package's folder, or "" when the package is unknown.
using PackageResolver = std::function<std::string(const std::string& package_name)>;

// Returns the absolute path for `uri`, or "" with `error` set (e.g. "unknown package 'foo'").
// Does not check that the file exists.
std::string resolveResourcePath(const std::string& uri, const std::string& relative_to_dir,
                                const PackageResolver& packages, std::string& error);

std::string directoryOf(const std::string& path);

}  // namespace conde_physics
