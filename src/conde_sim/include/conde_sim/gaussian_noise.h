// Zero-mean Gaussian noise of a fixed standard deviation from a seeded generator: the same
// draws in every run (deterministic simulation), none at all while the deviation is 0.
//
//   GaussianNoise noise(0.01, ctx.noiseSeed("sonar"));   // stddev [unit of the measurement]
//   range_m += noise();
#pragma once

#include <cstdint>
#include <random>

namespace conde_sim {

class GaussianNoise {
 public:
  GaussianNoise() = default;
  GaussianNoise(double stddev, std::uint64_t seed) : stddev_(stddev), rng_(seed) {}

  double stddev() const { return stddev_; }
  double operator()() { return stddev_ > 0 ? stddev_ * gauss_(rng_) : 0.0; }

 private:
  double stddev_ = 0.0;
  std::mt19937_64 rng_;
  std::normal_distribution<double> gauss_{0.0, 1.0};
};

}  // namespace conde_sim
