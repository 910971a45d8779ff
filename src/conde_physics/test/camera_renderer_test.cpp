// Camera renderer: geometry against the camera model (ground points, the seed paper's
// field-of-view test with a chessboard, lens distortion checked with OpenCV), depth order, face
// images, the round shapes, clipping, noise, the scene from a world file and bad input.
#include <gtest/gtest.h>

#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <set>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "conde_physics/camera_renderer.h"
#include "conde_physics/world_file.h"
#include "test_models.h"

namespace cp = conde_physics;
using conde_physics_test::lookAt;

namespace {

constexpr double kPi = 3.14159265358979323846;

// Conde's left tracking camera lens as written in the original SDF.
cp::LensDistortion condeDistortion() {
  cp::LensDistortion d;
  d.k1 = -0.245678598507515;
  d.k2 = 0.050106260288961;
  d.k3 = 0.0;
  d.p1 = 0.004883645512607;
  d.p2 = 0.001092737340199;
  return d;
}

// A pose whose local x and y axes point along the given (orthogonal, unit) world directions.
cp::Pose poseFromAxes(const cp::Vec3& centre, const cp::Vec3& x, const cp::Vec3& y) {
  const cp::Vec3 z = x.cross(y);
  const double m[3][3] = {{x.x, y.x, z.x}, {x.y, y.y, z.y}, {x.z, y.z, z.z}};
  return cp::Pose(centre, cp::Quat::fromMatrix(m));
}

cp::RgbImage solid(int w, int h, std::uint8_t r, std::uint8_t g, std::uint8_t b) {
  cp::RgbImage image;
  image.resize(w, h);
  for (int v = 0; v < h; ++v) {
    for (int u = 0; u < w; ++u) {
      image.pixel(u, v)[0] = r;
      image.pixel(u, v)[1] = g;
      image.pixel(u, v)[2] = b;
    }
  }
  return image;
}

void fill(cp::RgbImage& image, int u0, int v0, int u1, int v1, std::uint8_t r, std::uint8_t g, std::uint8_t b) {
  for (int v = v0; v < v1; ++v) {
    for (int u = u0; u < u1; ++u) {
      image.pixel(u, v)[0] = r;
      image.pixel(u, v)[1] = g;
      image.pixel(u, v)[2] = b;
    }
  }
}

cv::Mat grayOf(const cp::RgbImage& image) {
  const cv::Mat rgb(image.height, image.width, CV_8UC3, const_cast<std::uint8_t*>(image.data.data()));
  cv::Mat gray;
  cv::cvtColor(rgb, gray, cv::COLOR_RGB2GRAY);
  return gray;
}

cp::RenderObject box(const cp::Vec3& size, const cp::Pose& pose, const cp::Vec3& color) {
  cp::RenderObject o;
  o.shape = cp::RenderShape::kBox;
  o.size_m = size;
  o.pose = pose;
  o.color_rgb = color;
  return o;
}

// Pixel of a world point seen by a camera at world_T_optical.
cv::Point2d pixelOf(const cp::CameraModel& model, const cp::Pose& world_T_optical, const cp::Vec3& world_point) {
  double u = 0.0, v = 0.0;
  EXPECT_TRUE(model.project(world_T_optical.inverse() * world_point, u, v));
  return {u, v};
}

bool isRed(const std::uint8_t* p) { return p[0] > 90 && p[1] < 40 && p[2] < 40; }
bool isGreen(const std::uint8_t* p) { return p[1] > 90 && p[0] < 40 && p[2] < 40; }

}  // namespace

// --- Camera model --------------------------------------------------------------------------------

TEST(CameraModelTest, IntrinsicsFromHorizontalFovAsGazebo) {
  const cp::CameraModel top = cp::CameraModel::fromHorizontalFov(320, 240, kPi / 2);
  EXPECT_NEAR(top.fx_px, 160.0, 1e-9);
  EXPECT_NEAR(top.fy_px, 160.0, 1e-9);
  EXPECT_DOUBLE_EQ(top.cx_px, 159.5);
  EXPECT_DOUBLE_EQ(top.cy_px, 119.5);
  const cp::CameraModel left = cp::CameraModel::fromHorizontalFov(160, 120, 1.0865);
  EXPECT_NEAR(left.fx_px, 132.48, 0.005);  // the original CameraInfo value
  EXPECT_DOUBLE_EQ(left.fy_px, left.fx_px);
  EXPECT_TRUE(left.distortion.isZero());
}

TEST(CameraModelTest, ProjectMatchesOpenCvPlumbBob) {
  cp::CameraModel model = cp::CameraModel::fromHorizontalFov(160, 120, 1.0865);
  model.distortion = condeDistortion();
  model.distortion.k3 = 0.01;  // exercise every coefficient
  const std::vector<cv::Point3d> points = {{0.0, 0.0, 1.0}, {0.3, -0.2, 1.0}, {-0.5, 0.35, 1.2}, {0.1, 0.4, 0.8}};
  const cv::Matx33d k(model.fx_px, 0, model.cx_px, 0, model.fy_px, model.cy_px, 0, 0, 1);
  const cv::Vec<double, 5> d(model.distortion.k1, model.distortion.k2, model.distortion.p1, model.distortion.p2,
                             model.distortion.k3);
  std::vector<cv::Point2d> expected;
  cv::projectPoints(points, cv::Vec3d(0, 0, 0), cv::Vec3d(0, 0, 0), k, d, expected);
  for (size_t i = 0; i < points.size(); ++i) {
    double u = 0.0, v = 0.0;
    ASSERT_TRUE(model.project(cp::Vec3(points[i].x, points[i].y, points[i].z), u, v));
    EXPECT_NEAR(u, expected[i].x, 1e-9) << "point " << i;
    EXPECT_NEAR(v, expected[i].y, 1e-9) << "point " << i;
  }
  double u = 0.0, v = 0.0;
  EXPECT_FALSE(model.project(cp::Vec3(0.1, 0.1, -1.0), u, v));
  EXPECT_FALSE(model.project(cp::Vec3(0.1, 0.1, 0.0), u, v));
}

// --- Wide-angle lenses ---------------------------------------------------------------------------

// Major Alvega's cameras (reference §3.2.2): 160 px wide, hfov 2.6 rad, Gazebo's default
// stereographic lens scaled to the hfov, so a ray at theta lands 2 f tan(theta / 2) from the centre
// with 2 f = 80 px / tan(0.65) = 105.2 px.
TEST(WideAngleLensTest, StereographicScaledToHfovAsGazebo) {
  const cp::CameraModel model =
      cp::CameraModel::fromWideAngle(160, 120, 2.6, cp::LensMapping::ofType("stereographic"), true);
  EXPECT_NEAR(2.0 * model.fx_px, 105.2, 0.05);
  EXPECT_DOUBLE_EQ(model.cx_px, 79.5);
  for (double theta : {0.1, 0.5, 1.0, 1.3, 1.5}) {
    for (double phi : {0.0, 0.7, 2.0, -2.5}) {
      const cp::Vec3 ray(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta));
      double u = 0.0, v = 0.0;
      ASSERT_TRUE(model.project(ray * 3.0, u, v)) << theta;
      const double r_px = 2.0 * model.fx_px * std::tan(theta / 2.0);
      EXPECT_NEAR(u, model.cx_px + r_px * std::cos(phi), 1e-9);
      EXPECT_NEAR(v, model.cy_px + r_px * std::sin(phi), 1e-9);
    }
  }
  // The image edge is at hfov / 2.
  double u = 0.0, v = 0.0;
  ASSERT_TRUE(model.project(cp::Vec3(std::sin(1.3), 0.0, std::cos(1.3)), u, v));
  EXPECT_NEAR(u - model.cx_px, 80.0, 1e-9);
  // Beyond the default cut-off (1.5707 rad), and behind the camera: not seen.
  EXPECT_FALSE(model.project(cp::Vec3(1.0, 0.0, -0.01), u, v));
}

TEST(WideAngleLensTest, EveryNamedLensMapsAnglesAsItsFormula) {
  struct Case {
    const char* type;
    double (*radius)(double);
  };
  const Case cases[] = {
      {"gnomonical", [](double t) { return std::tan(t); }},
      {"stereographic", [](double t) { return 2.0 * std::tan(t / 2.0); }},
      {"equidistant", [](double t) { return t; }},
      {"equisolid_angle", [](double t) { return 2.0 * std::sin(t / 2.0); }},
      {"orthographic", [](double t) { return std::sin(t); }},
  };
  for (const Case& c : cases) {
    const cp::LensMapping lens = cp::LensMapping::ofType(c.type);
    for (double theta : {0.05, 0.4, 0.9, 1.2}) {
      EXPECT_NEAR(lens.radius(theta), c.radius(theta), 1e-12) << c.type << " " << theta;
      // And back: the ray at that radius has that angle.
      cp::Vec3 ray;
      ASSERT_TRUE(lens.rayAt(lens.radius(theta) * 0.6, lens.radius(theta) * 0.8, ray)) << c.type;
      EXPECT_NEAR(std::acos(ray.z), theta, 1e-9) << c.type;
      EXPECT_NEAR(ray.y / ray.x, 0.8 / 0.6, 1e-9) << c.type;
    }
  }
  // A radius no ray of an orthographic lens reaches (sin > 1).
  cp::Vec3 ray;
  EXPECT_FALSE(cp::LensMapping::ofType("orthographic").rayAt(1.2, 0.0, ray));
}

// The renderer's per-pixel rays and project() agree: a small ball in a known direction is drawn
// where project() puts it, with the lens alone and with Gazebo-style distortion (in units of the
// image size, centre off the middle) on top, as Major Alvega's tracking camera has it.
TEST(WideAngleLensTest, BallsAreDrawnWhereProjectPutsThem) {
  cp::CameraModel model = cp::CameraModel::fromWideAngle(160, 120, 2.6, cp::LensMapping::ofType("stereographic"), true);
  for (bool distorted : {false, true}) {
    if (distorted) {
      model.distortion.k1 = -0.2673;
      model.distortion.k2 = 0.0629;
      model.distortion.k3 = -0.0061;
      model.distortion.p1 = 0.0012;
      model.distortion.p2 = -9.1477e-4;
      model.setDistortionCenter(0.501996094, 0.4585875);
    }
    const cp::CameraRenderer renderer(model);
    // Render a sphere at known directions and find it where project() says.
    cp::RenderScene scene;
    scene.setGroundColor({0.0, 0.0, 1.0});
    scene.setSkyColor({0.0, 0.0, 1.0});
    for (double theta : {0.0, 0.6, 1.2}) {
      for (double phi : {0.3, 2.4}) {
        const cp::Vec3 dir(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta));
        cp::RenderObject ball;
        ball.shape = cp::RenderShape::kSphere;
        ball.radius_m = 0.03;
        ball.pose.position = dir * 2.0;
        ball.color_rgb = {1.0, 0.0, 0.0};
        cp::RenderScene one = scene;
        one.addObject(ball);
        cp::RgbImage image;
        renderer.render(one, cp::Pose(), -1, nullptr, image);
        double u = 0.0, v = 0.0;
        ASSERT_TRUE(model.project(dir, u, v));
        ASSERT_GE(u, 0.0);
        ASSERT_LT(u, 160.0);
        ASSERT_GE(v, 0.0);
        ASSERT_LT(v, 120.0);
        // Centroid of the red pixels.
        double su = 0.0, sv = 0.0;
        int n = 0;
        for (int pv = 0; pv < 120; ++pv)
          for (int pu = 0; pu < 160; ++pu)
            if (isRed(image.pixel(pu, pv))) {
              su += pu;
              sv += pv;
              ++n;
            }
        ASSERT_GT(n, 0) << "theta " << theta << " phi " << phi << " distorted " << distorted;
        EXPECT_NEAR(su / n, u, 0.6) << "theta " << theta << " phi " << phi << " distorted " << distorted;
        EXPECT_NEAR(sv / n, v, 0.6) << "theta " << theta << " phi " << phi << " distorted " << distorted;
      }
    }
  }
}

// A fisheye sees what a pinhole cannot: a ball 80 degrees off the axis; pixels beyond the
// cut-off angle are black.
TEST(WideAngleLensTest, SeesFarOffAxisAndBlacksOutBeyondTheCutOff) {
  cp::LensMapping lens = cp::LensMapping::ofType("equidistant");
  lens.cutoff_angle_rad = 1.2;
  const cp::CameraModel model = cp::CameraModel::fromWideAngle(160, 120, 3.0, lens, true);
  const cp::CameraRenderer renderer(model);
  cp::RenderScene scene;
  scene.setGroundColor({0.0, 0.0, 1.0});
  scene.setSkyColor({0.0, 1.0, 0.0});
  cp::RgbImage image;
  renderer.render(scene, cp::Pose(), -1, nullptr, image);
  const double f = model.fx_px;
  int black = 0, expected_black = 0;
  for (int v = 0; v < 120; ++v) {
    for (int u = 0; u < 160; ++u) {
      const double theta = std::hypot(u - model.cx_px, v - model.cy_px) / f;  // equidistant
      const std::uint8_t* p = image.pixel(u, v);
      const bool is_black = p[0] == 0 && p[1] == 0 && p[2] == 0;
      if (std::abs(theta - 1.2) < 0.02) continue;  // the rim itself
      EXPECT_EQ(is_black, theta > 1.2) << u << "," << v;
      black += is_black;
      expected_black += theta > 1.2;
    }
  }
  EXPECT_GT(expected_black, 1000);
  EXPECT_EQ(black, expected_black);
}

TEST(WideAngleLensTest, BadLensesAreNamed) {
  try {
    cp::LensMapping::ofType("fisheye");
    FAIL() << "no exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_STREQ(e.what(),
                 "unknown lens type 'fisheye' (expected gnomonical, stereographic, equidistant, equisolid_angle, "
                 "orthographic or custom)");
  }
  EXPECT_THROW(cp::LensMapping::custom(1.0, 1.0, 0.0, "cos"), std::invalid_argument);
  EXPECT_THROW(cp::LensMapping::custom(0.0, 1.0, 0.0, "tan"), std::invalid_argument);
  // A pinhole-like lens cannot spread a 180 degree field over the image.
  try {
    cp::CameraModel::fromWideAngle(160, 120, kPi, cp::LensMapping::ofType("gnomonical"), true);
    FAIL() << "no exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("cannot show half the horizontal_fov"), std::string::npos) << e.what();
  }
  EXPECT_THROW(cp::CameraModel::fromWideAngle(160, 120, 7.0, cp::LensMapping::ofType("equidistant"), true),
               std::invalid_argument);
}

// --- Ground --------------------------------------------------------------------------------------

// A bright 4 x 4 cm patch on a dark 2 x 2 m ground (1 cm texels): the centroid of its image is
// where CameraModel::project puts the patch centre, with and without lens distortion, from
// several viewpoints (the patch well off the image centre, where distortion moves it most).
TEST(CameraRendererTest, GroundPointLandsWhereTheModelProjectsIt) {
  cp::RgbImage texture = solid(200, 200, 0, 0, 0);
  fill(texture, 140, 60, 144, 64, 255, 255, 255);             // columns 140..143, rows 60..63
  const cp::Vec3 patch_centre(-1.0 + 1.42, 1.0 - 0.62, 0.0);  // column 0 at x = -1, row 0 at y = +1
  cp::RenderScene scene;
  scene.setGround(texture, -1.0, 1.0, -1.0, 1.0, {0, 0, 0});
  scene.setSkyColor({0, 0, 0});

  struct View {
    cp::Vec3 eye, target, up;
  };
  const std::vector<View> views = {
      {{-0.3, -0.2, 0.8}, {0.05, 0.05, 0.0}, {0, 0, 1}},
      {{1.1, 1.0, 0.6}, {0.4, 0.0, 0.0}, {0, 0, 1}},
      {{0.9, -0.4, 0.9}, {0.1, 0.7, 0.0}, {1, 1, 1}},  // rolled
  };
  for (const bool distorted : {false, true}) {
    double worst_px = 0.0;
    cp::CameraModel model = cp::CameraModel::fromHorizontalFov(320, 240, 1.2);
    if (distorted) model.distortion = condeDistortion();
    const cp::CameraRenderer camera(model);
    for (size_t i = 0; i < views.size(); ++i) {
      SCOPED_TRACE("view " + std::to_string(i) + (distorted ? ", distorted" : ", pinhole"));
      const cp::Pose pose = lookAt(views[i].eye, views[i].target, views[i].up);
      cp::RgbImage image;
      camera.render(scene, pose, -1, nullptr, image);
      const cv::Point2d expected = pixelOf(model, pose, patch_centre);
      ASSERT_GT(expected.x, 20);
      ASSERT_LT(expected.x, 300);
      ASSERT_GT(expected.y, 20);
      ASSERT_LT(expected.y, 220);
      // The patch must be well off-centre for the distorted case to mean something.
      EXPECT_GT(std::hypot(expected.x - model.cx_px, expected.y - model.cy_px), 40.0);
      double sum = 0.0, su = 0.0, sv = 0.0;
      for (int v = 0; v < image.height; ++v) {
        for (int u = 0; u < image.width; ++u) {
          const double w = image.pixel(u, v)[0];
          sum += w;
          su += w * u;
          sv += w * v;
        }
      }
      ASSERT_GT(sum, 8 * 255.0) << "patch not visible";
      EXPECT_NEAR(su / sum, expected.x, 0.5);
      EXPECT_NEAR(sv / sum, expected.y, 0.5);
      worst_px = std::max(worst_px, std::hypot(su / sum - expected.x, sv / sum - expected.y));
    }
    std::printf("ground patch, %s: largest centroid error %.3f px\n", distorted ? "distorted" : "pinhole", worst_px);
  }
}

TEST(CameraRendererTest, GroundTextureKeepsItsColoursAndSkyIsAboveTheHorizon) {
  cp::RgbImage texture = solid(100, 100, 0, 0, 0);  // black track with a white line along x = 0
  fill(texture, 48, 0, 52, 100, 255, 255, 255);
  cp::RenderScene scene;
  scene.setGround(texture, -5.0, 5.0, -5.0, 5.0, {0.2, 0.4, 0.6});
  scene.setSkyColor({0.7, 0.8, 0.9});
  const cp::CameraModel model = cp::CameraModel::fromHorizontalFov(160, 120, 1.0);
  const cp::CameraRenderer camera(model);
  // Level camera at 1 m on the white line, looking along it (+y): the line runs up the middle.
  const cp::Pose pose = lookAt({0, -4, 1}, {0, 0, 1});
  cp::RgbImage image;
  camera.render(scene, pose, -1, nullptr, image);
  const std::uint8_t* sky = image.pixel(80, 10);
  EXPECT_EQ(sky[0], 179);
  EXPECT_EQ(sky[1], 204);
  EXPECT_EQ(sky[2], 230);
  const std::uint8_t* line = image.pixel(80, 110);
  EXPECT_EQ(line[0], 255);
  EXPECT_EQ(line[1], 255);
  EXPECT_EQ(line[2], 255);
  const std::uint8_t* track = image.pixel(30, 110);
  EXPECT_EQ(track[0], 0);
  EXPECT_EQ(track[1], 0);
  EXPECT_EQ(track[2], 0);
  // Looking down past the texture's far edge (y > 5): the plain ground colour.
  const cp::Pose down = lookAt({0, 6, 1}, {0, 7, 0});
  camera.render(scene, down, -1, nullptr, image);
  const std::uint8_t* plain = image.pixel(80, 60);
  EXPECT_EQ(plain[0], 51);
  EXPECT_EQ(plain[1], 102);
  EXPECT_EQ(plain[2], 153);
}

// A 1-texel checkerboard seen from so high that a pixel covers ~14 x 14 texels: the pixels show
// its average grey (read from a coarse mipmap level), not a random mix of black and white.
TEST(CameraRendererTest, FarGroundIsAveragedNotAliased) {
  cp::RgbImage texture = solid(401, 399, 0, 0, 0);  // odd sizes: the mipmap's repeated edges
  for (int v = 0; v < texture.height; ++v)
    for (int u = 0; u < texture.width; ++u)
      if ((u + v) % 2 == 0) fill(texture, u, v, u + 1, v + 1, 255, 255, 255);
  cp::RenderScene scene;
  scene.setGround(texture, -2.005, 2.005, -1.995, 1.995, {0, 0, 1});
  const cp::CameraModel model = cp::CameraModel::fromHorizontalFov(160, 120, 1.0);
  const cp::CameraRenderer camera(model);
  cp::RgbImage image;
  camera.render(scene, lookAt({0, 0, 20}, {0, 0, 0}, {1, 0, 0}), -1, nullptr, image);
  // The texture spans about +-14 px around the image centre.
  for (int v = 50; v < 70; ++v) {
    for (int u = 70; u < 90; ++u) {
      EXPECT_NEAR(image.pixel(u, v)[0], 128, 12) << "pixel (" << u << ", " << v << ")";
      EXPECT_EQ(image.pixel(u, v)[0], image.pixel(u, v)[2]);
    }
  }
  EXPECT_EQ(image.pixel(5, 5)[2], 255);  // plain ground colour outside the texture
}

// --- Depth order ---------------------------------------------------------------------------------

TEST(CameraRendererTest, NearerBoxWinsWhicheverWasAddedFirst) {
  const cp::CameraModel model = cp::CameraModel::fromHorizontalFov(160, 120, 1.0);
  const cp::CameraRenderer camera(model);
  const cp::Pose pose = lookAt({0, 0, 1}, {1, 0, 1});
  const cp::RenderObject near_box = box({0.4, 0.4, 0.4}, cp::Pose::fromXyzRpy(2, 0, 1, 0, 0, 0), {1, 0, 0});
  const cp::RenderObject far_box = box({2, 2, 2}, cp::Pose::fromXyzRpy(5, 0, 1, 0, 0, 0), {0, 1, 0});
  for (const bool near_first : {true, false}) {
    SCOPED_TRACE(near_first ? "near box added first" : "far box added first");
    cp::RenderScene scene;
    scene.setGroundColor({0.5, 0.5, 0.5});
    if (near_first) {
      scene.addObject(near_box);
      scene.addObject(far_box);
    } else {
      scene.addObject(far_box);
      scene.addObject(near_box);
    }
    cp::RgbImage image;
    camera.render(scene, pose, -1, nullptr, image);
    // The near box spans +-0.2 m at 1.8 m (about +-16 px), the far one +-1 m at 4 m (+-36 px).
    EXPECT_TRUE(isRed(image.pixel(80, 60)));
    EXPECT_TRUE(isRed(image.pixel(70, 55)));
    EXPECT_TRUE(isGreen(image.pixel(80 + 26, 60)));
    EXPECT_TRUE(isGreen(image.pixel(80, 60 - 26)));
  }
}

TEST(CameraRendererTest, GroundHidesWhatIsBelowIt) {
  const cp::CameraModel model = cp::CameraModel::fromHorizontalFov(160, 120, 1.0);
  const cp::CameraRenderer camera(model);
  const cp::Pose looking_down = lookAt({0, 0, 2}, {0, 0, 0}, {1, 0, 0});
  for (const double z : {-1.0, 0.6}) {
    cp::RenderScene scene;
    scene.setGroundColor({0.5, 0.5, 0.5});
    scene.addObject(box({1, 1, 1}, cp::Pose::fromXyzRpy(0, 0, z, 0, 0, 0), {1, 0, 0}));
    cp::RgbImage image;
    camera.render(scene, looking_down, -1, nullptr, image);
    int red = 0;
    for (int v = 0; v < image.height; ++v)
      for (int u = 0; u < image.width; ++u) red += isRed(image.pixel(u, v));
    if (z < 0) {
      EXPECT_EQ(red, 0) << "a box under the ground shows";
    } else {
      EXPECT_GT(red, 1000) << "the control box above the ground does not show";
    }
  }
}

TEST(CameraRendererTest, LightRegionDarkensWhatLiesInsideIt) {
  // Looking down on grey ground with a red box; a light region (a triangle plus a square) covers
  // the left half of the view and the box's lower part, not its top.
  const cp::CameraModel model = cp::CameraModel::fromHorizontalFov(160, 120, 1.0);
  const cp::CameraRenderer camera(model);
  const cp::Pose looking_down = lookAt({0, 0, 3}, {0, 0, 0}, {1, 0, 0});
  cp::RenderScene scene;
  scene.setGroundColor({0.8, 0.8, 0.8});
  scene.addObject(box({0.2, 0.2, 0.6}, cp::Pose::fromXyzRpy(0.5, 0.0, 0.3, 0, 0, 0), {1, 1, 1}));
  cp::RgbImage lit;
  camera.render(scene, looking_down, -1, nullptr, lit);
  cp::LightRegion shade;
  shade.name = "tunnel";
  shade.polygon_xy_m = {{-5.0, 0.0}, {5.0, 0.0}, {5.0, 5.0}, {-5.0, 5.0}};  // y >= 0: half the view
  shade.z_min_m = -0.01;
  shade.z_max_m = 0.5;
  shade.light = 0.25;
  scene.addLightRegion(shade);
  cp::LightRegion darker = shade;  // overlapping: the darker region wins
  darker.name = "deeper";
  darker.polygon_xy_m = {{-1.0, 0.5}, {-0.5, 1.0}, {-1.0, 1.0}};
  darker.light = 0.1;
  scene.addLightRegion(darker);
  cp::RgbImage shaded;
  camera.render(scene, looking_down, -1, nullptr, shaded);
  const cp::Vec3 inside(-0.8, 0.3, 0.0), outside(-1.0, -1.0, 0.0), deeper(-0.9, 0.85, 0.0);
  auto at = [&](const cp::RgbImage& image, const cp::Vec3& p) {
    const cv::Point2d px = pixelOf(model, looking_down, p);
    return image.pixel(static_cast<int>(std::lround(px.x)), static_cast<int>(std::lround(px.y)));
  };
  EXPECT_EQ(at(lit, inside)[0], 204);
  EXPECT_EQ(at(shaded, inside)[0], 51);    // 204 * 0.25
  EXPECT_EQ(at(shaded, outside)[0], 204);  // untouched
  EXPECT_EQ(at(shaded, deeper)[0], 20);    // 204 * 0.1
  EXPECT_EQ(scene.lightAt({-0.9, 0.85, 0.0}), 0.1);
  EXPECT_EQ(scene.lightAt({0.0, 1.0, 0.6}), 1.0);  // above the region
  // The box's top (z = 0.6) sticks out of the region: lit as before.
  const cp::Vec3 box_top(0.5, 0.0, 0.6);
  EXPECT_EQ(at(shaded, box_top)[1], at(lit, box_top)[1]);
  int darker_px = 0;
  for (size_t i = 0; i < lit.data.size(); ++i) darker_px += shaded.data[i] < lit.data[i];
  EXPECT_GT(darker_px, 3 * 160 * 50);  // about half the image, three channels
  cp::LightRegion bad = shade;
  bad.light = -0.5;
  EXPECT_THROW(scene.addLightRegion(bad), std::invalid_argument);
}

// The banded even-odd test gives what testing every edge gives: a tunnel-like curved band (an
// annulus sector of 90 corners), points on a fine grid over its box, on corners' y values and on
// its edges' ends.
TEST(CameraRendererTest, LightRegionInsideTestMatchesEveryEdgeTest) {
  cp::LightRegion band;
  band.name = "curved";
  const int per_arc = 45;
  for (int k = 0; k < per_arc; ++k) {  // outer arc out, inner arc back
    const double a = 1.9 + 1.6 * k / (per_arc - 1);
    band.polygon_xy_m.push_back({-0.2 + 1.3 * std::cos(a), -6.9 + 1.3 * std::sin(a)});
  }
  for (int k = per_arc - 1; k >= 0; --k) {
    const double a = 1.9 + 1.6 * k / (per_arc - 1);
    band.polygon_xy_m.push_back({-0.2 + 0.85 * std::cos(a), -6.9 + 0.85 * std::sin(a)});
  }
  band.z_min_m = -0.01;
  band.z_max_m = 1.0;
  band.light = 0.35;
  cp::RenderScene scene;
  scene.addLightRegion(band);
  auto every_edge = [&](double x, double y) {
    const auto& c = band.polygon_xy_m;
    bool inside = false;
    for (size_t i = 0, j = c.size() - 1; i < c.size(); j = i++)
      if ((c[i][1] > y) != (c[j][1] > y) && x < c[i][0] + (y - c[i][1]) * (c[j][0] - c[i][0]) / (c[j][1] - c[i][1]))
        inside = !inside;
    return inside ? band.light : 1.0;
  };
  std::vector<double> ys, xs;
  for (int k = 0; k <= 400; ++k) ys.push_back(-8.3 + 2.4 * k / 400.0);
  for (int k = 0; k <= 200; ++k) xs.push_back(-1.6 + 1.6 * k / 200.0);
  for (const auto& corner : band.polygon_xy_m) {
    ys.push_back(corner[1]);
    xs.push_back(corner[0]);
  }
  int inside = 0;
  for (double y : ys)
    for (double x : xs) {
      const double light = scene.lightAt({x, y, 0.0});
      ASSERT_EQ(light, every_edge(x, y)) << "at (" << x << ", " << y << ")";
      inside += light < 1.0;
    }
  EXPECT_GT(inside, 1000);  // the grid does reach into the band
  // A NaN point gets no band index from a float-to-int cast, and is lit.
  EXPECT_EQ(scene.lightAt({std::nan(""), std::nan(""), 0.0}), 1.0);
}

TEST(CameraRendererTest, HiddenObjectIsNotDrawn) {
  const cp::CameraModel model = cp::CameraModel::fromHorizontalFov(160, 120, 1.0);
  const cp::CameraRenderer camera(model);
  cp::RenderScene scene;
  scene.setGroundColor({0.5, 0.5, 0.5});
  const int index = scene.addObject(box({0.4, 0.4, 0.4}, cp::Pose::fromXyzRpy(2, 0, 1, 0, 0, 0), {1, 0, 0}));
  const cp::Pose pose = lookAt({0, 0, 1}, {1, 0, 1});
  cp::RgbImage image;
  camera.render(scene, pose, -1, nullptr, image);
  EXPECT_TRUE(isRed(image.pixel(80, 60)));
  scene.setObjectHidden(index, true);  // a robot deleted while the simulation runs
  camera.render(scene, pose, -1, nullptr, image);
  EXPECT_FALSE(isRed(image.pixel(80, 60)));
  scene.setObjectHidden(index, false);
  camera.render(scene, pose, -1, nullptr, image);
  EXPECT_TRUE(isRed(image.pixel(80, 60)));
}

TEST(CameraRendererTest, ExcludedGroupIsNotDrawn) {
  const cp::CameraModel model = cp::CameraModel::fromHorizontalFov(160, 120, 1.0);
  const cp::CameraRenderer camera(model);
  cp::RenderScene scene;
  cp::RenderObject own_body = box({0.4, 0.4, 0.4}, cp::Pose::fromXyzRpy(2, 0, 1, 0, 0, 0), {1, 0, 0});
  own_body.group = 7;
  scene.addObject(own_body);
  const cp::Pose pose = lookAt({0, 0, 1}, {1, 0, 1});
  cp::RgbImage image;
  camera.render(scene, pose, 7, nullptr, image);
  EXPECT_FALSE(isRed(image.pixel(80, 60)));
  camera.render(scene, pose, 3, nullptr, image);
  EXPECT_TRUE(isRed(image.pixel(80, 60)));
  camera.render(scene, pose, -1, nullptr, image);
  EXPECT_TRUE(isRed(image.pixel(80, 60)));
}

TEST(CameraRendererTest, ClipPlanesCutAlongTheRay) {
  cp::CameraModel model = cp::CameraModel::fromHorizontalFov(160, 120, 1.0);
  model.near_clip_m = 0.5;
  model.far_clip_m = 3.0;
  const cp::CameraRenderer camera(model);
  const cp::Pose pose = lookAt({0, 0, 1}, {1, 0, 1});
  cp::RgbImage image;
  {
    // Beyond the far plane: not drawn; the ground beyond it is sky too.
    cp::RenderScene scene;
    scene.setGroundColor({0.5, 0.5, 0.5});
    scene.setSkyColor({0, 0, 1});
    scene.addObject(box({0.4, 0.4, 0.4}, cp::Pose::fromXyzRpy(3.5, 0, 1, 0, 0, 0), {1, 0, 0}));
    camera.render(scene, pose, -1, nullptr, image);
    EXPECT_FALSE(isRed(image.pixel(80, 60)));
    EXPECT_EQ(image.pixel(80, 65)[2], 255);   // ground 1 m below, > 3 m away along the ray
    EXPECT_EQ(image.pixel(80, 119)[0], 128);  // ground within 3 m
  }
  {
    // A box whose front face is nearer than the near plane: the ray sees its inside (back face).
    cp::RenderScene scene;
    scene.addObject(box({1.0, 1.0, 1.0}, cp::Pose::fromXyzRpy(0.7, 0, 1, 0, 0, 0), {1, 0, 0}));
    camera.render(scene, pose, -1, nullptr, image);
    EXPECT_TRUE(isRed(image.pixel(80, 60)));
  }
  {
    // Entirely nearer than the near plane: not drawn.
    cp::RenderScene scene;
    scene.addObject(box({0.2, 0.2, 0.2}, cp::Pose::fromXyzRpy(0.25, 0, 1, 0, 0, 0), {1, 0, 0}));
    camera.render(scene, pose, -1, nullptr, image);
    EXPECT_FALSE(isRed(image.pixel(80, 60)));
  }
}

// --- Face images ---------------------------------------------------------------------------------

// Quadrants: red top-left, green top-right, blue bottom-left, yellow bottom-right.
TEST(CameraRendererTest, FaceImageIsUprightAndNotMirroredFromTheFront) {
  cp::RgbImage quadrants = solid(64, 48, 0, 0, 0);
  fill(quadrants, 0, 0, 32, 24, 255, 0, 0);
  fill(quadrants, 32, 0, 64, 24, 0, 255, 0);
  fill(quadrants, 0, 24, 32, 48, 0, 0, 255);
  fill(quadrants, 32, 24, 64, 48, 255, 255, 0);
  // A panel facing -x (towards the camera), its local +y up.
  const cp::Vec3 size(0.8, 0.6, 0.05);
  const cp::Pose panel_pose = poseFromAxes({2, 0, 1}, {0, -1, 0}, {0, 0, 1});
  cp::RenderObject panel = box(size, panel_pose, {0.5, 0.5, 0.5});
  panel.face_image = quadrants;
  cp::RenderScene scene;
  scene.setGroundColor({0.1, 0.1, 0.1});
  scene.setSkyColor({0.1, 0.1, 0.1});
  const int index = scene.addObject(panel);

  const cp::CameraModel model = cp::CameraModel::fromHorizontalFov(160, 120, 1.0);
  const cp::CameraRenderer camera(model);
  const cp::Pose front = lookAt({0, 0, 1}, {1, 0, 1});
  cp::RgbImage image;
  camera.render(scene, front, -1, nullptr, image);
  struct Quadrant {
    double x, y;  // local face coordinates
    std::uint8_t r, g, b;
    bool left, top;  // where the viewer must see it
  };
  const Quadrant quads[] = {{-0.2, 0.15, 255, 0, 0, true, true},
                            {0.2, 0.15, 0, 255, 0, false, true},
                            {-0.2, -0.15, 0, 0, 255, true, false},
                            {0.2, -0.15, 255, 255, 0, false, false}};
  for (const Quadrant& q : quads) {
    const cv::Point2d p = pixelOf(model, front, panel_pose * cp::Vec3(q.x, q.y, size.z / 2));
    EXPECT_EQ(p.x < model.cx_px, q.left);
    EXPECT_EQ(p.y < model.cy_px, q.top);
    const std::uint8_t* px = image.pixel(static_cast<int>(std::lround(p.x)), static_cast<int>(std::lround(p.y)));
    EXPECT_EQ(px[0], q.r) << "quadrant at local (" << q.x << ", " << q.y << ")";
    EXPECT_EQ(px[1], q.g) << "quadrant at local (" << q.x << ", " << q.y << ")";
    EXPECT_EQ(px[2], q.b) << "quadrant at local (" << q.x << ", " << q.y << ")";
  }

  // From behind the panel only its plain back (grey) shows.
  const cp::Pose behind = lookAt({4, 0, 1}, {3, 0, 1});
  camera.render(scene, behind, -1, nullptr, image);
  int coloured = 0;
  for (int v = 0; v < image.height; ++v) {
    for (int u = 0; u < image.width; ++u) {
      const std::uint8_t* px = image.pixel(u, v);
      coloured += !(px[0] == px[1] && px[1] == px[2]);
    }
  }
  EXPECT_EQ(coloured, 0);
  const std::uint8_t* back = image.pixel(80, 60);
  EXPECT_GT(back[0], 40);  // shaded panel grey, not the background (26)
  EXPECT_EQ(back[0], back[2]);

  // A new image replaces the old one (display panels).
  scene.setObjectImage(index, solid(4, 4, 255, 0, 255));
  camera.render(scene, front, -1, nullptr, image);
  EXPECT_EQ(image.pixel(80, 60)[0], 255);
  EXPECT_EQ(image.pixel(80, 60)[1], 0);
  EXPECT_EQ(image.pixel(80, 60)[2], 255);
}

// --- Field of view (the seed paper's Table 3) ----------------------------------------------------

namespace {

struct Board {
  int inner_x = 8, inner_y = 6;  // inner corners
  int texels_per_square = 4;     // coarse: bilinear magnification gives sub-pixel edges
  double square_m = 0.05;
  // Squares of the whole face: the board plus a white square of margin on each side.
  int facesX() const { return inner_x + 3; }
  int facesY() const { return inner_y + 3; }

  cp::RgbImage image() const {
    const int n = texels_per_square;
    cp::RgbImage img = solid(facesX() * n, facesY() * n, 255, 255, 255);
    for (int j = 1; j < facesY() - 1; ++j)
      for (int i = 1; i < facesX() - 1; ++i)
        if ((i + j) % 2 == 0) fill(img, i * n, j * n, (i + 1) * n, (j + 1) * n, 0, 0, 0);
    return img;
  }
  // Inner corner (i, j) on the face, local coordinates (x right, y up as seen from the front).
  cp::Vec3 corner(int i, int j, double face_z) const {
    return {(i - (inner_x - 1) / 2.0) * square_m, ((inner_y - 1) / 2.0 - j) * square_m, face_z};
  }
};

// Renders `board` on a thin box whose front face is `distance_m` straight ahead of a camera at
// the origin looking along +x (grey surroundings).
cp::RgbImage renderBoard(const cp::CameraModel& model, const Board& board, double distance_m, cp::Pose& camera_pose,
                         cp::Pose& face_pose) {
  const double thickness = 0.02;
  face_pose = poseFromAxes({distance_m + thickness / 2, 0, 0}, {0, -1, 0}, {0, 0, 1});
  cp::RenderObject panel =
      box({board.facesX() * board.square_m, board.facesY() * board.square_m, thickness}, face_pose, {0.5, 0.5, 0.5});
  panel.face_image = board.image();
  cp::RenderScene scene;
  scene.setGroundColor({0.5, 0.5, 0.5});
  scene.setSkyColor({0.5, 0.5, 0.5});
  scene.addObject(panel);
  camera_pose = lookAt({0, 0, 0}, {1, 0, 0});
  const cp::CameraRenderer camera(model);
  cp::RgbImage image;
  camera.render(scene, camera_pose, -1, nullptr, image);
  return image;
}

std::vector<cv::Point2f> findCorners(const cp::RgbImage& image, const Board& board) {
  const cv::Mat gray = grayOf(image);
  std::vector<cv::Point2f> corners;
  const bool found = cv::findChessboardCorners(gray, cv::Size(board.inner_x, board.inner_y), corners,
                                               cv::CALIB_CB_ADAPTIVE_THRESH | cv::CALIB_CB_NORMALIZE_IMAGE);
  if (!found) return {};
  cv::cornerSubPix(gray, corners, cv::Size(3, 3), cv::Size(-1, -1),
                   cv::TermCriteria(cv::TermCriteria::EPS + cv::TermCriteria::COUNT, 100, 1e-4));
  return corners;
}

// Mean length of the rows (first to last corner of each) and of the columns, in pixels.
void boardSpans(const std::vector<cv::Point2f>& c, const Board& board, double& horizontal_px, double& vertical_px) {
  horizontal_px = 0.0;
  vertical_px = 0.0;
  for (int j = 0; j < board.inner_y; ++j)
    horizontal_px += cv::norm(c[j * board.inner_x + board.inner_x - 1] - c[j * board.inner_x]);
  for (int i = 0; i < board.inner_x; ++i) vertical_px += cv::norm(c[(board.inner_y - 1) * board.inner_x + i] - c[i]);
  horizontal_px /= board.inner_y;
  vertical_px /= board.inner_x;
}

}  // namespace

// Board distances [m] of the field-of-view test: CONDE_FOV_DISTANCES_M (comma-separated, e.g.
// "0.7,1.0"; evaluation_report of conde_eval sets it), 0.7 m when unset.
std::vector<double> fovDistances() {
  std::vector<double> distances;
  const char* text = std::getenv("CONDE_FOV_DISTANCES_M");
  std::stringstream list(text != nullptr ? text : "0.7");
  std::string item;
  while (std::getline(list, item, ',')) {
    if (!item.empty()) distances.push_back(std::stod(item));
  }
  return distances;
}

// The same chessboard at a known distance straight in front of each of Conde's cameras
// (distortion off): its size in pixels, measured with OpenCV's corner finder, is the pinhole
// prediction f * size / distance within half a pixel (the two tracking cameras' predictions
// differ by 0.7 px). Prints the table (Markdown) and one "FOV_RESULT camera distance_m
// predicted_h measured_h predicted_v measured_v" line per board (read by evaluation_report).
TEST(CameraRendererTest, FieldOfViewMatchesThePinholePrediction) {
  struct Camera {
    const char* name;
    int width, height;
    double hfov_rad;
  };
  const Camera cameras[] = {{"tracking_left", 160, 120, 1.0865},
                            {"tracking_right", 160, 120, 1.0965},
                            {"signalling_panel", 320, 240, 1.5707963}};
  // One board (5 cm squares), as a printed board in front of each camera.
  const std::vector<double> distances = fovDistances();
  ASSERT_FALSE(distances.empty()) << "CONDE_FOV_DISTANCES_M names no distance";
  std::printf(
      "\n| camera | image | hfov [rad] | fx [px] | distance [m] | board span H predicted / measured [px] | "
      "V predicted / measured [px] |\n|---|---|---|---|---|---|---|\n");
  std::vector<std::string> results;
  for (const double distance_m : distances) {
    for (const Camera& c : cameras) {
      SCOPED_TRACE(std::string(c.name) + " at " + std::to_string(distance_m) + " m");
      const cp::CameraModel model = cp::CameraModel::fromHorizontalFov(c.width, c.height, c.hfov_rad);
      Board board;
      board.square_m = 0.05;
      cp::Pose camera_pose, face_pose;
      const cp::RgbImage image = renderBoard(model, board, distance_m, camera_pose, face_pose);
      const std::vector<cv::Point2f> corners = findCorners(image, board);
      ASSERT_EQ(corners.size(), static_cast<size_t>(board.inner_x * board.inner_y)) << "chessboard not found";
      double horizontal = 0.0, vertical = 0.0;
      boardSpans(corners, board, horizontal, vertical);
      const double predicted_h = model.fx_px * (board.inner_x - 1) * board.square_m / distance_m;
      const double predicted_v = model.fy_px * (board.inner_y - 1) * board.square_m / distance_m;
      std::printf("| %s | %dx%d | %.7g | %.3f | %.2f | %.3f / %.3f | %.3f / %.3f |\n", c.name, c.width, c.height,
                  c.hfov_rad, model.fx_px, distance_m, predicted_h, horizontal, predicted_v, vertical);
      char line[200];
      std::snprintf(line, sizeof line, "FOV_RESULT %s %.4f %.4f %.4f %.4f %.4f", c.name, distance_m, predicted_h,
                    horizontal, predicted_v, vertical);
      results.emplace_back(line);
      EXPECT_NEAR(horizontal, predicted_h, 0.5);
      EXPECT_NEAR(vertical, predicted_v, 0.5);
    }
  }
  for (const std::string& line : results) std::printf("%s\n", line.c_str());
}

// With Conde's lens distortion on, the chessboard's corners land where CameraModel::project puts
// them, and undistorting them with OpenCV (K and D from the model) gives the pinhole positions:
// straight rows and columns again.
TEST(CameraRendererTest, DistortedBoardUndistortsToThePinholeImage) {
  cp::CameraModel model = cp::CameraModel::fromHorizontalFov(160, 120, 1.0865);
  model.distortion = condeDistortion();
  const double distance_m = 1.0;
  Board board;
  board.inner_x = 10;
  board.inner_y = 7;
  board.square_m = 1.0 * model.width_px / model.fx_px * distance_m / board.facesX();  // as wide as the image
  cp::Pose camera_pose, face_pose;
  const cp::RgbImage image = renderBoard(model, board, distance_m, camera_pose, face_pose);
  const std::vector<cv::Point2f> corners = findCorners(image, board);
  ASSERT_EQ(corners.size(), static_cast<size_t>(board.inner_x * board.inner_y)) << "chessboard not found";

  const double face_z = 0.01;  // half the thickness
  std::vector<cv::Point2d> distorted_expected, pinhole_expected;
  for (int j = 0; j < board.inner_y; ++j) {
    for (int i = 0; i < board.inner_x; ++i) {
      const cp::Vec3 p = camera_pose.inverse() * (face_pose * board.corner(i, j, face_z));
      double u = 0.0, v = 0.0;
      ASSERT_TRUE(model.project(p, u, v));
      distorted_expected.emplace_back(u, v);
      pinhole_expected.emplace_back(model.fx_px * p.x / p.z + model.cx_px, model.fy_px * p.y / p.z + model.cy_px);
    }
  }
  auto nearest = [](const std::vector<cv::Point2d>& set, const cv::Point2d& p) {
    double best = std::numeric_limits<double>::infinity();
    for (const auto& q : set) best = std::min(best, cv::norm(q - p));
    return best;
  };
  const cv::Matx33d k(model.fx_px, 0, model.cx_px, 0, model.fy_px, model.cy_px, 0, 0, 1);
  const cv::Vec<double, 5> d(model.distortion.k1, model.distortion.k2, model.distortion.p1, model.distortion.p2,
                             model.distortion.k3);
  std::vector<cv::Point2d> found(corners.begin(), corners.end()), undistorted;
  cv::undistortPoints(found, undistorted, k, d, cv::noArray(), k);
  double max_distorted = 0.0, max_pinhole = 0.0, max_shift = 0.0;
  for (size_t i = 0; i < found.size(); ++i) {
    max_distorted = std::max(max_distorted, nearest(distorted_expected, found[i]));
    max_pinhole = std::max(max_pinhole, nearest(pinhole_expected, undistorted[i]));
    max_shift = std::max(max_shift, nearest(pinhole_expected, found[i]));
  }
  std::printf(
      "\ndistorted board: corner error vs project() %.3f px, undistorted vs pinhole %.3f px "
      "(distortion moves corners up to %.1f px)\n",
      max_distorted, max_pinhole, max_shift);
  EXPECT_LT(max_distorted, 0.5);
  EXPECT_LT(max_pinhole, 0.5);
  EXPECT_GT(max_shift, 3.0) << "the distortion is not visible";

  // Rows and columns of undistorted corners are straight lines (residual of a line fit).
  auto maxLineResidual = [&](const std::vector<cv::Point2d>& corner_px, bool rows) {
    double worst = 0.0;
    const int lines = rows ? board.inner_y : board.inner_x, count = rows ? board.inner_x : board.inner_y;
    for (int l = 0; l < lines; ++l) {
      std::vector<cv::Point2f> pts;
      for (int n = 0; n < count; ++n) {
        const cv::Point2d& p = corner_px[rows ? l * board.inner_x + n : n * board.inner_x + l];
        pts.emplace_back(static_cast<float>(p.x), static_cast<float>(p.y));
      }
      cv::Vec4f line;
      cv::fitLine(pts, line, cv::DIST_L2, 0, 1e-3, 1e-3);
      for (const auto& p : pts)
        worst = std::max(worst, std::abs(static_cast<double>((p.x - line[2]) * line[1] - (p.y - line[3]) * line[0])));
    }
    return worst;
  };
  EXPECT_LT(maxLineResidual(undistorted, true), 0.3);
  EXPECT_LT(maxLineResidual(undistorted, false), 0.3);
  // ...while the rendered (distorted) rows and columns bend.
  EXPECT_GT(maxLineResidual(found, true), 0.5);
  EXPECT_GT(maxLineResidual(found, false), 0.5);
}

// --- Shapes --------------------------------------------------------------------------------------

namespace {

// Rows and columns covered by non-black pixels.
struct Silhouette {
  int u_min = 1 << 30, u_max = -1, v_min = 1 << 30, v_max = -1;
  double u_centroid = 0.0, v_centroid = 0.0;
  int pixels = 0;
};

Silhouette silhouetteOf(const cp::RgbImage& image) {
  Silhouette s;
  for (int v = 0; v < image.height; ++v) {
    for (int u = 0; u < image.width; ++u) {
      const std::uint8_t* p = image.pixel(u, v);
      if (p[0] + p[1] + p[2] < 60) continue;
      s.u_min = std::min(s.u_min, u);
      s.u_max = std::max(s.u_max, u);
      s.v_min = std::min(s.v_min, v);
      s.v_max = std::max(s.v_max, v);
      s.u_centroid += u;
      s.v_centroid += v;
      ++s.pixels;
    }
  }
  if (s.pixels > 0) {
    s.u_centroid /= s.pixels;
    s.v_centroid /= s.pixels;
  }
  return s;
}

cp::RgbImage renderAlone(const cp::CameraModel& model, const cp::Pose& camera_pose, const cp::RenderObject& object) {
  cp::RenderScene scene;
  scene.setGroundColor({0, 0, 0});
  scene.setSkyColor({0, 0, 0});
  scene.addObject(object);
  const cp::CameraRenderer camera(model);
  cp::RgbImage image;
  camera.render(scene, camera_pose, -1, nullptr, image);
  return image;
}

}  // namespace

// Each shape seen from the side at 3 m, level with its centre (camera above the ground plane
// so the black ground and sky leave only the object): silhouette extents against projection.
TEST(CameraRendererTest, RoundShapesAreDrawnWhereProjectionPutsThem) {
  const cp::CameraModel model = cp::CameraModel::fromHorizontalFov(320, 240, 1.0);
  const double f = model.fx_px, d = 3.0, r = 0.3, length = 0.8;
  const cp::Pose camera_pose = lookAt({0, 0, 5}, {1, 0, 5});
  const cp::Vec3 centre(d, 0, 5);
  auto shape = [&](cp::RenderShape kind, const cp::Quat& orientation) {
    cp::RenderObject o;
    o.shape = kind;
    o.radius_m = r;
    o.length_m = kind == cp::RenderShape::kSphere ? 0.0 : length;
    o.pose = cp::Pose(centre, orientation);
    return silhouetteOf(renderAlone(model, camera_pose, o));
  };
  // Seen from the camera, a sphere or a vertical cylinder / cone base of radius r at distance d
  // subtends a half-width f r / sqrt(d^2 - r^2) (tangent rays).
  const double half_width_px = f * r / std::sqrt(d * d - r * r);
  {
    SCOPED_TRACE("sphere");
    const Silhouette s = shape(cp::RenderShape::kSphere, cp::Quat());
    // A sphere on the axis images as a circle.
    EXPECT_NEAR(s.u_centroid, model.cx_px, 0.25);
    EXPECT_NEAR(s.v_centroid, model.cy_px, 0.25);
    EXPECT_NEAR(s.pixels, kPi * half_width_px * half_width_px, 0.03 * kPi * half_width_px * half_width_px);
    EXPECT_NEAR((s.u_max - s.u_min) / 2.0, half_width_px, 1.0);
  }
  {
    SCOPED_TRACE("cylinder, axis vertical");
    const Silhouette s = shape(cp::RenderShape::kCylinder, cp::Quat());
    const double half_height_px = f * (length / 2) / (d - r);  // the nearest points of the caps' rims
    EXPECT_NEAR(s.u_centroid, model.cx_px, 0.25);
    EXPECT_NEAR(s.v_centroid, model.cy_px, 0.25);
    EXPECT_NEAR((s.u_max - s.u_min) / 2.0, half_width_px, 1.0);
    EXPECT_NEAR((s.v_max - s.v_min) / 2.0, half_height_px, 1.0);
  }
  {
    SCOPED_TRACE("cone, apex up");
    const Silhouette s = shape(cp::RenderShape::kCone, cp::Quat());
    const double apex_v = model.cy_px - f * (length / 2) / d;        // apex on the axis
    const double base_v = model.cy_px + f * (length / 2) / (d - r);  // nearest point of the base rim
    EXPECT_NEAR(s.v_min, apex_v, 2.0);                               // the tip is thinner than a pixel
    EXPECT_NEAR(s.v_max, base_v, 1.0);
    EXPECT_NEAR(s.u_centroid, model.cx_px, 0.25);
    EXPECT_GT(s.v_centroid, model.cy_px + 5) << "the wide base must be at the bottom";
    EXPECT_NEAR((s.u_max - s.u_min) / 2.0, half_width_px, 1.0);  // base rim
  }
  {
    SCOPED_TRACE("cone lying along +y (apex to the image's left)");
    const Silhouette s = shape(cp::RenderShape::kCone, cp::Quat::fromRpy(-kPi / 2, 0, 0));  // local z = world +y
    const cv::Point2d apex = pixelOf(model, camera_pose, centre + cp::Vec3(0, length / 2, 0));
    EXPECT_NEAR(s.u_min, apex.x, 2.0);
    EXPECT_GT(s.u_centroid, model.cx_px + 5) << "the wide base must be on the right";
  }
}

TEST(CameraRendererTest, ObjectsAreLitFromAbove) {
  const cp::CameraModel model = cp::CameraModel::fromHorizontalFov(160, 120, 1.0);
  cp::RenderObject cube = box({1, 1, 1}, cp::Pose::fromXyzRpy(0, 0, 0.5, 0, 0, 0.3), {1, 1, 1});
  // Seen from above at an angle: the top face is brighter than the sides.
  const cp::Pose pose = lookAt({-2.5, -0.5, 3}, {0, 0, 0.5});
  const cp::RgbImage image = renderAlone(model, pose, cube);
  const cv::Point2d top = pixelOf(model, pose, {0, 0, 1.0});
  const cv::Point2d side = pixelOf(model, pose, {-0.45, 0.1, 0.5});
  const int top_gray = image.pixel(static_cast<int>(top.x), static_cast<int>(top.y))[0];
  const int side_gray = image.pixel(static_cast<int>(side.x), static_cast<int>(side.y))[0];
  EXPECT_GT(top_gray, side_gray + 30);
  EXPECT_GE(side_gray, 100);  // ambient light: no black sides
}

// --- Noise ---------------------------------------------------------------------------------------

// A `width` x `height` camera (1 rad horizontal FOV, noise stddev 0.05) 1 m above a plain
// `ground` under a plain `sky`, looking along +x; noise from `rng` (none when null).
cp::RgbImage renderNoisyPlainView(int width, int height, const cp::Vec3& ground, const cp::Vec3& sky,
                                  std::mt19937* rng) {
  cp::CameraModel model = cp::CameraModel::fromHorizontalFov(width, height, 1.0);
  model.noise_stddev = 0.05;
  cp::RenderScene scene;
  scene.setGroundColor(ground);
  scene.setSkyColor(sky);
  cp::RgbImage image;
  cp::CameraRenderer(model).render(scene, lookAt({0, 0, 1}, {1, 0, 1}), -1, rng, image);
  return image;
}

TEST(CameraRendererTest, GaussianNoiseHasTheModelsStandardDeviation) {
  std::mt19937 rng(42);
  const cp::RgbImage image = renderNoisyPlainView(320, 240, {0.5, 0.5, 0.5}, {0.5, 0.5, 0.5}, &rng);
  for (int c = 0; c < 3; ++c) {
    double sum = 0.0, sum2 = 0.0;
    const int n = image.width * image.height;
    for (int i = 0; i < n; ++i) {
      const double x = image.data[static_cast<size_t>(i) * 3 + c];
      sum += x;
      sum2 += x * x;
    }
    const double mean = sum / n, stddev = std::sqrt(sum2 / n - mean * mean);
    EXPECT_NEAR(mean, 128.0, 0.5) << "channel " << c;
    EXPECT_NEAR(stddev, 0.05 * 255, 0.1 * 0.05 * 255) << "channel " << c;
  }
  // Independent channels: red and green of a pixel are uncorrelated.
  double cov = 0.0;
  const int n = image.width * image.height;
  for (int i = 0; i < n; ++i) cov += (image.data[i * 3] - 128.0) * (image.data[i * 3 + 1] - 128.0);
  EXPECT_LT(std::abs(cov / n) / (12.75 * 12.75), 0.05);
  // No generator: no noise.
  for (std::uint8_t x : renderNoisyPlainView(320, 240, {0.5, 0.5, 0.5}, {0.5, 0.5, 0.5}, nullptr).data) {
    ASSERT_EQ(x, 128);
  }
}

TEST(CameraRendererTest, NoiseIsClampedToTheByteRange) {
  std::mt19937 rng(1);
  const cp::RgbImage image = renderNoisyPlainView(160, 120, {1, 1, 1}, {0, 0, 0}, &rng);
  // White ground can only get darker, black sky only brighter: both ends saturate, nothing wraps
  // (noise of 12.75 levels wrapping past 0 or 255 would land near the other end).
  int sky_zero = 0, ground_full = 0;
  for (int u = 0; u < 160; ++u) {
    sky_zero += image.pixel(u, 5)[0] == 0;
    ground_full += image.pixel(u, 115)[0] == 255;
    EXPECT_LT(image.pixel(u, 5)[1], 100);
    EXPECT_GT(image.pixel(u, 115)[1], 155);
  }
  EXPECT_GT(sky_zero, 50);
  EXPECT_GT(ground_full, 50);
}

// --- Scene from a world file ---------------------------------------------------------------------

TEST(CameraRendererTest, SceneFromWorldFile) {
  const std::string dir = CONDE_WORLD_TEST_DIR;
  const cp::WorldDescription world = cp::loadWorldFile(
      dir + "/valid.world.yaml", [&](const std::string& p) { return p == "fixture_pkg" ? dir : std::string(); });
  const cp::RenderScene scene = cp::renderSceneFromWorld(world);
  ASSERT_EQ(scene.objectCount(), 4);
  EXPECT_EQ(scene.object(0).shape, cp::RenderShape::kBox);
  EXPECT_EQ(scene.object(1).shape, cp::RenderShape::kCylinder);
  EXPECT_EQ(scene.object(2).shape, cp::RenderShape::kCone);
  EXPECT_EQ(scene.object(3).shape, cp::RenderShape::kSphere);
  EXPECT_DOUBLE_EQ(scene.object(0).size_m.x, 0.4758);
  EXPECT_DOUBLE_EQ(scene.object(1).radius_m, 0.1);
  EXPECT_DOUBLE_EQ(scene.object(2).length_m, 0.4);
  EXPECT_DOUBLE_EQ(scene.object(3).pose.position.z, 1.0);
  EXPECT_DOUBLE_EQ(scene.object(0).color_rgb.x, 0.69);
  const cp::RgbImage checker = cp::loadRgbImage(dir + "/textures/checker.png");
  ASSERT_EQ(scene.object(0).face_image.width, checker.width);
  EXPECT_EQ(scene.object(0).face_image.data, checker.data);
  EXPECT_EQ(scene.object(1).face_image.width, 0);

  // The ground texture is in place: straight down onto the middle of texel (0, 0), the
  // north-west corner (x_min, y_max), the camera sees that texel's colour.
  const double texel_x = (3.975 + 3.475) / checker.width, texel_y = (8.35 + 8.35) / checker.height;
  const cp::Vec3 texel_centre(-3.475 + texel_x / 2, 8.35 - texel_y / 2, 0);
  const cp::CameraModel model = cp::CameraModel::fromHorizontalFov(32, 24, 0.2);
  const cp::CameraRenderer camera(model);
  cp::RgbImage image;
  camera.render(scene, lookAt(texel_centre + cp::Vec3(0, 0, 2), texel_centre, {1, 0, 0}), -1, nullptr, image);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(image.pixel(16, 12)[c], checker.pixel(0, 0)[c], 2);
}

// --- Bad input -----------------------------------------------------------------------------------

namespace {

template <typename Exception, typename F>
std::string messageOf(F f) {
  try {
    f();
  } catch (const Exception& e) {
    return e.what();
  }
  return "(no exception)";
}

std::string modelError(int w, int h, double hfov) {
  return messageOf<std::invalid_argument>([&] { cp::CameraModel::fromHorizontalFov(w, h, hfov); });
}

std::string rendererError(const cp::CameraModel& model) {
  return messageOf<std::invalid_argument>([&] { cp::CameraRenderer renderer(model); });
}

}  // namespace

TEST(CameraRendererTest, BadCameraParametersAreRejectedWithClearMessages) {
  EXPECT_EQ(modelError(0, 120, 1.0), "camera image size must be positive (got 0x120)");
  EXPECT_EQ(modelError(160, -1, 1.0), "camera image size must be positive (got 160x-1)");
  EXPECT_EQ(modelError(160, 120, 0.0), "camera horizontal_fov must be in (0, pi) rad (got 0)");
  EXPECT_EQ(modelError(160, 120, 3.2), "camera horizontal_fov must be in (0, pi) rad (got 3.2)");
  EXPECT_EQ(modelError(160, 120, std::nan("")), "camera horizontal_fov must be in (0, pi) rad (got nan)");

  const cp::CameraModel good = cp::CameraModel::fromHorizontalFov(160, 120, 1.0);
  cp::CameraModel m = good;
  m.width_px = 0;
  EXPECT_EQ(rendererError(m), "camera image size must be positive (got 0x120)");
  m = good;
  m.fx_px = 0.0;
  m.fy_px = 100.0;
  EXPECT_EQ(rendererError(m), "camera focal length must be positive (got fx 0 px, fy 100 px)");
  m = good;
  m.near_clip_m = 0.0;
  EXPECT_EQ(rendererError(m), "camera clip distances must satisfy 0 < near < far (got near 0 m, far 100 m)");
  m = good;
  m.near_clip_m = 2.0;
  m.far_clip_m = 1.5;
  EXPECT_EQ(rendererError(m), "camera clip distances must satisfy 0 < near < far (got near 2 m, far 1.5 m)");
  m = good;
  m.noise_stddev = -0.1;
  EXPECT_EQ(rendererError(m), "camera noise_stddev must be >= 0 (got -0.1)");
  // A lens model that folds over inside the image has no ray for the outer pixels.
  m = cp::CameraModel::fromHorizontalFov(320, 240, kPi / 2);
  m.distortion.k1 = -1.0;
  EXPECT_EQ(rendererError(m),
            "camera distortion (k1 -1, k2 0, k3 0, p1 0, p2 0) cannot be inverted at pixel (0, 0): the lens model "
            "folds over inside the image");
}

TEST(CameraRendererTest, BadImagesAndObjectsAreRejectedWithClearMessages) {
  EXPECT_EQ(messageOf<std::runtime_error>([] { cp::loadRgbImage("/nonexistent/panel.png"); }),
            "cannot decode image '/nonexistent/panel.png'");
  const std::string corrupt = std::string(CONDE_WORLD_TEST_DIR) + "/textures/corrupt.png";
  EXPECT_EQ(messageOf<std::runtime_error>([&] { cp::loadRgbImage(corrupt); }), "cannot decode image '" + corrupt + "'");

  cp::RenderScene scene;
  EXPECT_EQ(messageOf<std::invalid_argument>([&] {
              scene.addObject(box({1, 0, 1}, cp::Pose(), {1, 1, 1}));
            }),
            "render object 0: box size must be positive (got 1 x 0 x 1 m)");
  cp::RenderObject sphere;
  sphere.shape = cp::RenderShape::kSphere;
  EXPECT_EQ(messageOf<std::invalid_argument>([&] { scene.addObject(sphere); }),
            "render object 0: radius must be positive (got 0 m)");
  sphere.radius_m = 0.5;
  const int index = scene.addObject(sphere);
  EXPECT_EQ(messageOf<std::invalid_argument>([&] { scene.setObjectImage(index, solid(2, 2, 0, 0, 0)); }),
            "render object 0: only boxes show a face image");
  EXPECT_EQ(messageOf<std::out_of_range>([&] { scene.setObjectPose(3, cp::Pose()); }),
            "render object index 3 out of range (the scene has 1 objects)");
  cp::RgbImage broken;
  broken.width = 4;
  broken.height = 4;
  EXPECT_EQ(messageOf<std::invalid_argument>([&] {
              scene.setGround(broken, 0, 1, 0, 1, {0, 0, 0});
            }),
            "ground texture: image data size 0 does not match 4x4 RGB");
  EXPECT_EQ(messageOf<std::invalid_argument>([&] {
              scene.setGround(solid(2, 2, 0, 0, 0), 1, 1, 0, 1, {0, 0, 0});
            }),
            "ground texture ranges must have min < max (got x [1, 1] m, y [0, 1] m)");
}

// The ground pass on eight lanes (AVX2) and on four draw the same pixels: a random texture seen
// from many poses, with and without distortion, a wide-angle lens too. Without AVX2 there is only
// the four-lane pass, and nothing to compare.
TEST(CameraRendererTest, EightAndFourLaneGroundPassesDrawTheSameImage) {
  if (!cp::CameraRenderer::wideVectorsAvailable()) GTEST_SKIP() << "this CPU has no AVX2: one ground pass only";
  std::mt19937 rng(7);
  cp::RgbImage texture;
  texture.resize(301, 203);
  for (auto& byte : texture.data) byte = static_cast<std::uint8_t>(rng() & 0xFF);
  cp::RenderScene scene;
  scene.setGround(texture, -3.0, 3.0, -2.0, 2.0, {0.2, 0.5, 0.2});
  scene.addObject(box({0.3, 0.3, 0.3}, cp::Pose(cp::Vec3(0.5, 0.4, 0.15), cp::Quat()), {1.0, 0.0, 0.0}));
  cp::CameraModel distorted = cp::CameraModel::fromHorizontalFov(160, 120, 1.0865);
  distorted.distortion = condeDistortion();
  const std::vector<cp::CameraModel> models = {
      cp::CameraModel::fromHorizontalFov(320, 240, 1.5708), distorted,
      cp::CameraModel::fromWideAngle(160, 120, 2.6, cp::LensMapping::ofType("stereographic"), true)};
  std::uniform_real_distribution<double> position(-4.0, 4.0), height(0.05, 3.0), angle(-kPi, kPi);
  int textured_images = 0;  // images that show the random ground texture (so the passes drew something)
  for (const cp::CameraModel& model : models) {
    const cp::CameraRenderer renderer(model);
    for (int pose = 0; pose < 20; ++pose) {
      const cp::Vec3 eye(position(rng), position(rng), height(rng));
      const cp::Vec3 target(position(rng), position(rng), angle(rng) * 0.1);
      const cp::Pose camera = lookAt(eye, target);
      cp::RgbImage wide, narrow;
      cp::CameraRenderer::allowWideVectors(true);
      renderer.render(scene, camera, -1, nullptr, wide);
      cp::CameraRenderer::allowWideVectors(false);
      renderer.render(scene, camera, -1, nullptr, narrow);
      cp::CameraRenderer::allowWideVectors(true);
      ASSERT_EQ(wide.data, narrow.data) << "model " << model.width_px << "x" << model.height_px << ", pose " << pose;
      // Distinct colours: the random texture gives hundreds, sky, box and ground colour a few.
      std::set<std::uint32_t> colours;
      for (size_t i = 0; i + 2 < narrow.data.size(); i += 3)
        colours.insert(narrow.data[i] << 16 | narrow.data[i + 1] << 8 | narrow.data[i + 2]);
      if (colours.size() > 100) ++textured_images;
    }
  }
  // Most of the 60 random poses look at the textured ground: the comparison covered the ground pass.
  EXPECT_GE(textured_images, 30);
}

// --- Depth image ---------------------------------------------------------------------------------

// A level camera 1 m above the ground faces a box whose front face is 2.5 m ahead: the face has the
// z-depth 2.5 m at every pixel (not the longer distance along the off-axis rays), the ground
// row v the z-depth h fy / (v - cy) at every column, the sky +inf; the colour image is unchanged.
TEST(CameraRendererTest, DepthImageIsZDepthOfBoxFaceAndGround) {
  cp::CameraModel model = cp::CameraModel::fromHorizontalFov(160, 120, 1.0);
  const cp::Pose pose = lookAt({0, 0, 1}, {5, 0, 1});
  cp::RenderScene scene;
  scene.setGroundColor({0.5, 0.5, 0.5});
  scene.addObject(box({1, 1, 1}, cp::Pose::fromXyzRpy(3, 0, 1, 0, 0, 0), {1, 0, 0}));
  const cp::CameraRenderer camera(model);
  cp::RgbImage image, image_alone;
  cp::DepthImage depth;
  camera.render(scene, pose, -1, nullptr, image, &depth);
  camera.render(scene, pose, -1, nullptr, image_alone);
  ASSERT_EQ(depth.width, 160);
  ASSERT_EQ(depth.height, 120);
  EXPECT_EQ(image.data, image_alone.data) << "asking for depth changes the colour image";
  // The face spans +-0.5 m at 2.5 m: about +-29 px around the centre.
  for (const auto& [u, v] : std::vector<std::pair<int, int>>{{80, 60}, {79, 59}, {55, 40}, {105, 80}})
    EXPECT_NEAR(depth.at(u, v), 2.5, 1e-4) << "box face at pixel (" << u << ", " << v << ")";
  for (const int v : {100, 110, 119}) {
    const double expected_m = 1.0 * model.fy_px / (v - model.cy_px);
    for (const int u : {0, 10, 150, 159})
      EXPECT_NEAR(depth.at(u, v), expected_m, 1e-3 * expected_m) << "ground at pixel (" << u << ", " << v << ")";
  }
  for (const int u : {0, 80, 159}) EXPECT_EQ(depth.at(u, 0), std::numeric_limits<float>::infinity()) << "sky";

  // The far clip (2.55 m) applies along the ray: the face's centre (2.5 m away) keeps its depth,
  // its corner pixel (2.56 m along the ray) and the ground behind are no return (+inf).
  model.far_clip_m = 2.55;
  const cp::CameraRenderer short_camera(model);
  short_camera.render(scene, pose, -1, nullptr, image, &depth);
  EXPECT_NEAR(depth.at(80, 60), 2.5, 1e-4);
  EXPECT_EQ(depth.at(105, 80), std::numeric_limits<float>::infinity());
  EXPECT_EQ(depth.at(10, 110), std::numeric_limits<float>::infinity());
}

// A camera looking straight down at 2 m sees the flat ground at the z-depth 2 m in every pixel, and
// the top of a 0.6 m box at 1.4 m.
TEST(CameraRendererTest, DepthImageLookingDownIsFlat) {
  const cp::CameraModel model = cp::CameraModel::fromHorizontalFov(64, 48, 1.2);
  const cp::CameraRenderer camera(model);
  cp::RenderScene scene;
  scene.setGroundColor({0.5, 0.5, 0.5});
  scene.addObject(box({0.4, 0.4, 0.6}, cp::Pose::fromXyzRpy(0, 0, 0.3, 0, 0, 0), {1, 0, 0}));
  cp::RgbImage image;
  cp::DepthImage depth;
  camera.render(scene, lookAt({0, 0, 2}, {0, 0, 0}, {1, 0, 0}), -1, nullptr, image, &depth);
  for (const auto& [u, v] : std::vector<std::pair<int, int>>{{0, 0}, {63, 0}, {0, 47}, {63, 47}, {5, 24}})
    EXPECT_NEAR(depth.at(u, v), 2.0, 1e-4) << "ground at pixel (" << u << ", " << v << ")";
  EXPECT_NEAR(depth.at(32, 24), 1.4, 1e-4) << "box top";
  EXPECT_TRUE(isRed(image.pixel(32, 24)));
}
