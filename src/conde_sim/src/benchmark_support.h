// What the physics benchmarks (benchmark_main.cpp, benchmark_cars_main.cpp) share: their
// command-line pieces.
#pragma once

#include <cstdio>
#include <fstream>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

namespace conde_sim {
namespace benchmark {

// "ode,bullet" -> {"ode", "bullet"}.
inline std::vector<std::string> splitList(const std::string& text) {
  std::vector<std::string> out;
  std::stringstream in(text);
  std::string item;
  while (std::getline(in, item, ',')) out.push_back(item);
  return out;
}

// The whole file, or nothing after "cannot open <what> '<path>'" on stderr.
inline std::optional<std::string> readFile(const std::string& path, const std::string& what) {
  std::ifstream file(path);
  if (!file) {
    std::fprintf(stderr, "cannot open %s '%s'\n", what.c_str(), path.c_str());
    return std::nullopt;
  }
  std::stringstream text;
  text << file.rdbuf();
  return text.str();
}

}  // namespace benchmark
}  // namespace conde_sim
