// Speed of the CPU camera renderer with Conde's three cameras in a world file, no ROS:
//   conde_render_benchmark WORLD.world.yaml [frames=500] [save_dir]
// Conde starts at the world's "conde" spawn (else the first one) and drives straight ahead
// 1 cm per frame; each camera renders `frames` frames without and with its lens distortion, with
// the ground pass on eight lanes (AVX2) and on four.
// Prints Markdown tables: time per frame per camera (wall clock, and this thread's CPU time,
// which a busy machine disturbs less) with a 64-bit digest (FNV-1a) of the timed frames' pixels
// (a change made for speed must keep it; only this table has one), and what that means for the
// three cameras at 30 Hz on one core, and the cost of the depth image. With save_dir, writes the
// first frame of each camera as PNG (and its depth image as grey PNG, white at 0 m to black at 2 m
// and for no return).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <string>
#include <vector>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "conde_physics/camera_renderer.h"
#include "conde_physics/world_file.h"

namespace cp = conde_physics;

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kCameraRateHz = 30.0;

// Conde's cameras (the original SDF): pose of the Gazebo camera frame (x forward, y left, z up)
// in base_footprint, which is the chassis pose plus the chassis offset (-0.2408312, 0, 0.2169399).
struct CameraSpec {
  std::string name;
  int width_px, height_px;
  double hfov_rad;
  cp::Pose base_T_camera;
  cp::LensDistortion distortion;  // as written in the original file
  double near_m, far_m;
};

std::vector<CameraSpec> condeCameras() {
  const double bx = -0.2408312, bz = 0.2169399;
  cp::LensDistortion left{-0.245678598507515, 0.050106260288961, 0.0, 0.004883645512607, 0.001092737340199};
  cp::LensDistortion right{-0.245678598507515, 0.050106260288961, 0.0, 0.005283645512607, 0.002092737340199};
  cp::LensDistortion top{-0.275678598507515, 0.045106260288961, 0.0, 0.004883645512607, 0.001092737340199};
  return {
      {"tracking_left", 160, 120, 1.0865,
       cp::Pose::fromXyzRpy(bx - 0.1242802892, 0.09985, bz + 0.48372014861, 0.319455, 0.531892, 0.56147), left, 0.001,
       50.0},
      {"tracking_right", 160, 120, 1.0965,
       cp::Pose::fromXyzRpy(bx - 0.12403780772, -0.1015, bz + 0.48372007433, -0.239603, 0.564592, -0.4785536732), right,
       0.001, 50.0},
      {"signalling_panel", 320, 240, 1.5707963,
       cp::Pose::fromXyzRpy(bx - 0.079244135856401, 0.0, bz + 0.562431407758936, 0.0, -0.28, 0.0), top, 0.01, 1000.0},
  };
}

// Major Alvega's wide-angle cameras (reference §3.2.2): hfov 2.6 rad, Gazebo's default
// stereographic lens, Gazebo-style distortion; poses of the camera links in base_link, which rests
// on the ground.
struct WideAngleSpec {
  std::string name;
  int width_px, height_px;
  cp::Pose base_T_camera;
  cp::LensDistortion distortion;
  double center_x, center_y;
};

std::vector<WideAngleSpec> majorCameras() {
  return {
      {"major_tracking", 160, 120, cp::Pose::fromXyzRpy(0.295, 0.0, 0.535, 0.0, 0.76, 0.0),
       cp::LensDistortion{-0.2673, 0.0629, -0.0061, 0.0012, -9.1477e-4}, 0.501996094, 0.4585875},
      {"major_top", 320, 240, cp::Pose::fromXyzRpy(0.288, 0.0, 0.75, 0.0, -0.3, 0.0),
       cp::LensDistortion{-0.254536654032040, 0.052707476272924, 0.004060325839474, 0.001216492819178,
                          0.001034739611621},
       0.486, 0.432},
  };
}

struct Timing {
  double mean_ms = 0.0, p95_ms = 0.0;  // wall clock
  double cpu_mean_ms = 0.0;            // this thread's CPU time (less disturbed on a busy machine)
  std::uint64_t digest = 0;            // of every timed frame's pixels (a different image changes it, all but surely)
};

// FNV-1a over bytes, continuing from `hash` (start with kFnvOffset).
constexpr std::uint64_t kFnvOffset = 14695981039346656037ull;
std::uint64_t fnv1a(const std::uint8_t* data, size_t size, std::uint64_t hash) {
  for (size_t i = 0; i < size; ++i) hash = (hash ^ data[i]) * 1099511628211ull;
  return hash;
}

double threadCpuMs() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return ts.tv_sec * 1e3 + ts.tv_nsec * 1e-6;
}

Timing timeFrames(const cp::CameraRenderer& renderer, const cp::RenderScene& scene, const cp::Pose& start,
                  const cp::Pose& base_T_optical, int frames, cp::RgbImage& image, cp::DepthImage* depth = nullptr) {
  std::vector<double> ms;
  ms.reserve(frames);
  auto poseAt = [&](int frame) {
    const cp::Vec3 forward = start.orientation.rotate(cp::Vec3(0.01 * frame, 0.0, 0.0));
    return cp::Pose(start.position + forward, start.orientation) * base_T_optical;
  };
  for (int i = 0; i < 20; ++i) renderer.render(scene, poseAt(i), -1, nullptr, image, depth);  // warm caches
  double cpu_ms = 0.0;
  Timing t;
  t.digest = kFnvOffset;
  for (int i = 0; i < frames; ++i) {
    const cp::Pose pose = poseAt(i);
    const double cpu0_ms = threadCpuMs();
    const auto t0 = std::chrono::steady_clock::now();
    renderer.render(scene, pose, -1, nullptr, image, depth);
    const auto t1 = std::chrono::steady_clock::now();
    cpu_ms += threadCpuMs() - cpu0_ms;
    ms.push_back(std::chrono::duration<double, std::milli>(t1 - t0).count());
    t.digest = fnv1a(image.data.data(), image.data.size(), t.digest);  // not timed
  }
  t.cpu_mean_ms = cpu_ms / frames;
  for (double m : ms) t.mean_ms += m;
  t.mean_ms /= ms.size();
  std::sort(ms.begin(), ms.end());
  t.p95_ms = ms[std::min(ms.size() - 1, static_cast<size_t>(0.95 * ms.size()))];
  return t;
}

void savePng(const cp::RgbImage& image, const std::string& path) {
  cv::Mat rgb(image.height, image.width, CV_8UC3, const_cast<std::uint8_t*>(image.data.data()));
  cv::Mat bgr;
  cv::cvtColor(rgb, bgr, cv::COLOR_RGB2BGR);
  if (!cv::imwrite(path, bgr)) std::fprintf(stderr, "cannot write '%s'\n", path.c_str());
}

// Grey depth image: white at 0 m, black at max_m and beyond, no return (+inf) black.
void saveDepthPng(const cp::DepthImage& depth, double max_m, const std::string& path) {
  cv::Mat grey(depth.height, depth.width, CV_8UC1);
  for (int v = 0; v < depth.height; ++v)
    for (int u = 0; u < depth.width; ++u)
      grey.at<std::uint8_t>(v, u) = static_cast<std::uint8_t>(
          std::lround(255.0 * std::clamp(1.0 - depth.at(u, v) / max_m, 0.0, 1.0)));  // inf -> 0
  if (!cv::imwrite(path, grey)) std::fprintf(stderr, "cannot write '%s'\n", path.c_str());
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: %s WORLD.world.yaml [frames=500] [save_dir]\n", argv[0]);
    return 2;
  }
  const int frames = argc > 2 ? std::atoi(argv[2]) : 500;
  if (frames <= 0) {
    std::fprintf(stderr, "frames must be a positive integer (got '%s')\n", argv[2]);
    return 2;
  }
  const std::string save_dir = argc > 3 ? argv[3] : "";
  try {
    // No ROS here: package:// references do not resolve.
    const cp::WorldDescription world = cp::loadWorldFile(argv[1], [](const std::string&) { return std::string(); });
    const cp::RenderScene scene = cp::renderSceneFromWorld(world);
    const cp::SpawnPose* spawn = world.findSpawn("conde");
    if (!spawn && !world.spawns.empty()) spawn = &world.spawns.front();
    const cp::Pose start = spawn ? spawn->pose : cp::Pose();
    // Gazebo camera frame -> REP 103 optical frame.
    const cp::Pose camera_T_optical = cp::Pose::fromXyzRpy(0, 0, 0, -kPi / 2, 0, -kPi / 2);

    std::printf(
        "World %s: %d objects, ground texture %s; Conde from (%.2f, %.2f) yaw %.4f rad, %d frames per "
        "camera, 1 cm apart.\n\n",
        world.name.c_str(), scene.objectCount(), world.ground.texture_path.c_str(), start.position.x, start.position.y,
        start.orientation.yaw(), frames);
    std::printf(
        "| camera | resolution | distortion | ground pass | mean [ms] | p95 [ms] | CPU mean [ms] | "
        "frames/s (wall) | frames/s (CPU) | image digest |\n");
    std::printf("|---|---|---|---|---|---|---|---|---|---|\n");
    // Three cameras, one frame each, without and with distortion, the ground pass on eight lanes
    // (AVX2, when the CPU has it) and on four: wall and CPU time.
    const bool have_wide = cp::CameraRenderer::wideVectorsAvailable();
    const int lane_variants = have_wide ? 2 : 1;
    double set_ms[2][2] = {{0.0, 0.0}, {0.0, 0.0}}, set_cpu_ms[2][2] = {{0.0, 0.0}, {0.0, 0.0}};
    auto lanes = [&](int variant) { return have_wide && variant == 0 ? "8 lanes (AVX2)" : "4 lanes"; };
    for (const CameraSpec& spec : condeCameras()) {
      for (int distorted = 0; distorted < 2; ++distorted) {
        cp::CameraModel model = cp::CameraModel::fromHorizontalFov(spec.width_px, spec.height_px, spec.hfov_rad);
        if (distorted) model.distortion = spec.distortion;
        model.near_clip_m = spec.near_m;
        model.far_clip_m = spec.far_m;
        const cp::CameraRenderer renderer(model);
        cp::RgbImage image;
        for (int variant = 0; variant < lane_variants; ++variant) {
          cp::CameraRenderer::allowWideVectors(variant == 0);
          const Timing t = timeFrames(renderer, scene, start, spec.base_T_camera * camera_T_optical, frames, image);
          set_ms[distorted][variant] += t.mean_ms;
          set_cpu_ms[distorted][variant] += t.cpu_mean_ms;
          std::printf("| %s | %dx%d | %s | %s | %.3f | %.3f | %.3f | %.0f | %.0f | %016llx |\n", spec.name.c_str(),
                      spec.width_px, spec.height_px, distorted ? "on" : "off", lanes(variant), t.mean_ms, t.p95_ms,
                      t.cpu_mean_ms, 1000.0 / t.mean_ms, 1000.0 / t.cpu_mean_ms,
                      static_cast<unsigned long long>(t.digest));
        }
        cp::CameraRenderer::allowWideVectors(true);
        if (!save_dir.empty()) {
          renderer.render(scene, cp::Pose(start.position, start.orientation) * spec.base_T_camera * camera_T_optical,
                          -1, nullptr, image);
          savePng(image, save_dir + "/" + spec.name + (distorted ? "_distorted" : "") + ".png");
        }
      }
    }
    std::printf(
        "\n| three cameras at %.0f Hz, one core | ground pass | render time per simulated second, wall / CPU "
        "[ms] | max real-time factor (rendering only), wall / CPU |\n|---|---|---|---|\n",
        kCameraRateHz);
    for (int distorted = 0; distorted < 2; ++distorted) {
      for (int variant = 0; variant < lane_variants; ++variant) {
        const double wall_ms = kCameraRateHz * set_ms[distorted][variant];
        const double cpu_ms = kCameraRateHz * set_cpu_ms[distorted][variant];
        std::printf("| distortion %s | %s | %.1f / %.1f | %.1f / %.1f |\n", distorted ? "on" : "off", lanes(variant),
                    wall_ms, cpu_ms, 1000.0 / wall_ms, 1000.0 / cpu_ms);
      }
    }

    // Major Alvega from its spawn pose in the original launch files (x 2.17, y -0.58, yaw 1.57).
    const cp::Pose major_start = cp::Pose::fromXyzRpy(2.17, -0.58, 0.0, 0.0, 0.0, 1.57);
    std::printf(
        "\nMajor Alvega's wide-angle cameras (stereographic lens, hfov 2.6 rad, Gazebo-style distortion), "
        "from (2.17, -0.58) yaw 1.57 rad:\n\n| camera | resolution | mean [ms] | p95 [ms] | CPU mean [ms] | "
        "frames/s (CPU) |\n|---|---|---|---|---|---|\n");
    for (const WideAngleSpec& spec : majorCameras()) {
      cp::CameraModel model = cp::CameraModel::fromWideAngle(spec.width_px, spec.height_px, 2.6,
                                                             cp::LensMapping::ofType("stereographic"), true);
      model.distortion = spec.distortion;
      model.setDistortionCenter(spec.center_x, spec.center_y);
      const cp::CameraRenderer renderer(model);
      cp::RgbImage image;
      const Timing t = timeFrames(renderer, scene, major_start, spec.base_T_camera * camera_T_optical, frames, image);
      std::printf("| %s | %dx%d | %.3f | %.3f | %.3f | %.0f |\n", spec.name.c_str(), spec.width_px, spec.height_px,
                  t.mean_ms, t.p95_ms, t.cpu_mean_ms, 1000.0 / t.cpu_mean_ms);
      if (!save_dir.empty()) {
        renderer.render(scene, major_start * spec.base_T_camera * camera_T_optical, -1, nullptr, image);
        savePng(image, save_dir + "/" + spec.name + ".png");
      }
    }

    // The depth image of the same pass (a depth camera's): its cost on top of the colour image.
    std::printf(
        "\nConde's cameras with the depth image (distortion off, default ground pass):\n\n| camera | resolution | "
        "CPU mean colour [ms] | CPU mean colour + depth [ms] |\n|---|---|---|---|\n");
    for (const CameraSpec& spec : condeCameras()) {
      cp::CameraModel model = cp::CameraModel::fromHorizontalFov(spec.width_px, spec.height_px, spec.hfov_rad);
      model.near_clip_m = spec.near_m;
      model.far_clip_m = spec.far_m;
      const cp::CameraRenderer renderer(model);
      cp::RgbImage image;
      cp::DepthImage depth;
      const cp::Pose base_T_optical = spec.base_T_camera * camera_T_optical;
      const Timing colour = timeFrames(renderer, scene, start, base_T_optical, frames, image);
      const Timing both = timeFrames(renderer, scene, start, base_T_optical, frames, image, &depth);
      std::printf("| %s | %dx%d | %.3f | %.3f |\n", spec.name.c_str(), spec.width_px, spec.height_px,
                  colour.cpu_mean_ms, both.cpu_mean_ms);
      if (!save_dir.empty()) {
        renderer.render(scene, cp::Pose(start.position, start.orientation) * base_T_optical, -1, nullptr, image,
                        &depth);
        saveDepthPng(depth, 2.0, save_dir + "/" + spec.name + "_depth.png");
      }
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "conde_render_benchmark: %s\n", e.what());
    return 1;
  }
  return 0;
}
