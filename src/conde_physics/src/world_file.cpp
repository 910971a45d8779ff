#include "conde_physics/world_file.h"

#include "conde_physics/sdf_world.h"

#include <yaml-cpp/yaml.h>

#include <sys/stat.h>
#include <unistd.h>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <map>

#include <opencv2/imgcodecs.hpp>

namespace conde_physics {
namespace {

constexpr const char* kFormat = "conde_world/1";

// A YAML value with what a message needs to point at it: 1-based line and dotted path.
struct Value {
  YAML::Node node;
  int line = 1;
  std::string where;
};

std::string joinKeys(const std::vector<std::string>& keys) {
  std::string s;
  for (const auto& k : keys) s += (s.empty() ? "" : ", ") + k;
  return s;
}

std::string child(const std::string& where, const std::string& key) { return where.empty() ? key : where + "." + key; }

std::string item(const std::string& where, size_t i) { return where + "[" + std::to_string(i) + "]"; }

// How a value that has the wrong type looks, for "expected X, got Y".
std::string describe(const YAML::Node& n) {
  switch (n.Type()) {
    case YAML::NodeType::Null:
      return "nothing";
    case YAML::NodeType::Sequence:
      return "a list";
    case YAML::NodeType::Map:
      return "a map";
    case YAML::NodeType::Scalar:
      // Quoted scalars carry the tag "!": show them quoted, "0.5" is not a number here.
      return n.Tag() == "!" ? "\"" + n.Scalar() + "\"" : "'" + n.Scalar() + "'";
    default:
      return "an undefined value";
  }
}

bool isName(const std::string& s) {
  if (s.empty()) return false;
  for (char c : s) {
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_')) return false;
  }
  return true;
}

// ROS graph resource names: optional leading '/' or '~', then [A-Za-z][A-Za-z0-9_]* tokens
// separated by single '/'.
bool isTopicName(const std::string& s) {
  size_t i = (!s.empty() && (s[0] == '/' || s[0] == '~')) ? 1 : 0;
  if (i == s.size()) return false;
  bool token_start = true;
  for (; i < s.size(); ++i) {
    const unsigned char c = static_cast<unsigned char>(s[i]);
    if (c == '/') {
      if (token_start) return false;
      token_start = true;
    } else if (token_start) {
      if (!std::isalpha(c)) return false;
      token_start = false;
    } else if (!(std::isalnum(c) || c == '_')) {
      return false;
    }
  }
  return !token_start;
}

class Loader {
 public:
  Loader(std::string file, std::string dir, const PackageResolver& packages)
      : file_(std::move(file)), dir_(std::move(dir)), packages_(packages) {}

  [[noreturn]] void fail(int line, const std::string& where, const std::string& what) const {
    throw WorldFileError(file_ + ":" + std::to_string(line) + ": " + (where.empty() ? "" : where + ": ") + what);
  }
  [[noreturn]] void fail(const Value& v, const std::string& what) const { fail(v.line, v.where, what); }

  // --- Scalars -------------------------------------------------------------------------------

  double number(const Value& v) const {
    double d = 0.0;
    if (!v.node.IsScalar() || v.node.Tag() == "!" || !YAML::convert<double>::decode(v.node, d))
      fail(v, "expected a number, got " + describe(v.node));
    if (!std::isfinite(d)) fail(v, "expected a finite number, got " + describe(v.node));
    return d;
  }

  int integer(const Value& v) const {
    int i = 0;
    if (!v.node.IsScalar() || v.node.Tag() == "!" || !YAML::convert<int>::decode(v.node, i))
      fail(v, "expected an integer, got " + describe(v.node));
    return i;
  }

  bool boolean(const Value& v) const {
    bool b = false;
    if (!v.node.IsScalar() || v.node.Tag() == "!" || !YAML::convert<bool>::decode(v.node, b))
      fail(v, "expected true or false, got " + describe(v.node));
    return b;
  }

  std::string string(const Value& v) const {
    if (!v.node.IsScalar()) fail(v, "expected a string, got " + describe(v.node));
    return v.node.Scalar();
  }

  std::string name(const Value& v) const {
    const std::string s = string(v);
    if (!isName(s)) fail(v, "invalid name " + describe(v.node) + " (use letters, digits and '_')");
    return s;
  }

  // Range checks print the value as written in the file, not re-formatted.
  double positive(const Value& v) const {
    const double d = number(v);
    if (!(d > 0.0)) fail(v, "must be > 0, got " + v.node.Scalar());
    return d;
  }

  double nonNegative(const Value& v) const {
    const double d = number(v);
    if (d < 0.0) fail(v, "must be >= 0, got " + v.node.Scalar());
    return d;
  }

  int intInRange(const Value& v, int lo, int hi) const {
    const int i = integer(v);
    if (i < lo || i > hi)
      fail(v, "must be in " + std::to_string(lo) + ".." + std::to_string(hi) + ", got " + v.node.Scalar());
    return i;
  }

  // --- Lists ---------------------------------------------------------------------------------

  std::vector<Value> list(const Value& v) const {
    if (!v.node.IsSequence()) fail(v, "expected a list, got " + describe(v.node));
    std::vector<Value> items;
    for (size_t i = 0; i < v.node.size(); ++i) {
      const YAML::Node n = v.node[i];
      // A null item ("-" alone) is marked at the next token; point at the list instead.
      items.push_back({n, n.IsNull() ? v.line : n.Mark().line + 1, item(v.where, i)});
    }
    return items;
  }

  std::vector<double> numbers(const Value& v, size_t count) const {
    const std::string expected = "expected a list of " + std::to_string(count) + " numbers";
    if (!v.node.IsSequence()) fail(v, expected + ", got " + describe(v.node));
    if (v.node.size() != count) fail(v, expected + ", got a list of " + std::to_string(v.node.size()));
    std::vector<double> out;
    for (const Value& e : list(v)) out.push_back(number(e));
    return out;
  }

  Vec3 vec3(const Value& v) const {
    const auto n = numbers(v, 3);
    return {n[0], n[1], n[2]};
  }

  Vec3 positiveVec3(const Value& v) const {
    const Vec3 out = vec3(v);
    for (const Value& e : list(v)) positive(e);
    return out;
  }

  Vec3 color(const Value& v) const {
    const Vec3 out = vec3(v);
    for (const Value& e : list(v)) {
      const double c = number(e);
      if (c < 0.0 || c > 1.0) fail(e, "must be in 0..1, got " + e.node.Scalar());
    }
    return out;
  }

  // [min, max] with min < max.
  void range(const Value& v, double& lo, double& hi) const {
    const auto n = numbers(v, 2);
    if (!(n[0] < n[1]))
      fail(v, "expected [min, max] with min < max, got [" + v.node[0].Scalar() + ", " + v.node[1].Scalar() + "]");
    lo = n[0];
    hi = n[1];
  }

  // --- Maps ----------------------------------------------------------------------------------

  // The entries of a map, in file order. A null value (key with nothing after it) counts as an
  // empty map so a section whose lines are all commented out keeps its defaults.
  class Map {
   public:
    Map(const Loader& loader, const Value& v) : loader_(loader), where_(v.where), line_(v.line) {
      if (v.node.IsNull()) return;
      if (!v.node.IsMap()) loader.fail(v, "expected a map, got " + describe(v.node));
      for (auto it = v.node.begin(); it != v.node.end(); ++it) {
        const YAML::Node& key = it->first;
        const int key_line = key.Mark().line + 1;
        if (!key.IsScalar()) loader.fail(key_line, where_, "expected a plain key, got " + describe(key));
        const std::string k = key.Scalar();
        for (const auto& e : entries_) {
          if (e.name == k)
            loader.fail(key_line, where_,
                        "duplicate key '" + k + "' (first at line " + std::to_string(e.key_line) + ")");
        }
        const YAML::Node value = it->second;
        // A null value is marked at the next token; point at its key instead.
        entries_.push_back({k, key_line, Value{value, value.IsNull() ? key_line : value.Mark().line + 1, ""}});
      }
      rename(where_);
    }

    // Objects get their name into `where` once it is known.
    void rename(const std::string& where) {
      where_ = where;
      for (auto& e : entries_) e.value.where = child(where_, e.name);
    }

    void allowOnly(const std::vector<std::string>& keys) const {
      for (const auto& e : entries_) {
        bool known = false;
        for (const auto& k : keys) known = known || k == e.name;
        if (!known)
          loader_.fail(e.key_line, where_, "unknown key '" + e.name + "' (expected one of: " + joinKeys(keys) + ")");
      }
    }

    const Value* find(const std::string& key) const {
      for (const auto& e : entries_) {
        if (e.name == key) return &e.value;
      }
      return nullptr;
    }

    const Value& require(const std::string& key, const std::string& note = "") const {
      const Value* v = find(key);
      if (!v) loader_.fail(line_, where_, "missing required key '" + key + "'" + note);
      return *v;
    }

    // Rejects `key` when present, e.g. a key that the object's shape does not use.
    void forbid(const std::string& key, const std::string& reason) const {
      for (const auto& e : entries_) {
        if (e.name == key) loader_.fail(e.key_line, where_, "key '" + key + "' " + reason);
      }
    }

    struct Entry {
      std::string name;
      int key_line;
      Value value;
    };
    const std::vector<Entry>& entries() const { return entries_; }
    const std::string& where() const { return where_; }
    int line() const { return line_; }

   private:
    const Loader& loader_;
    std::string where_;
    int line_;
    std::vector<Entry> entries_;
  };

  // --- Sections ------------------------------------------------------------------------------

  SurfaceParams friction(const Value& v) const {
    Map m(*this, v);
    m.allowOnly({"mu", "mu2"});
    SurfaceParams s;
    if (const Value* x = m.find("mu")) s.mu = nonNegative(*x);
    if (const Value* x = m.find("mu2")) s.mu2 = nonNegative(*x);
    return s;
  }

  // {xyz: [x, y, z], rpy: [roll, pitch, yaw]}, metres and radians; rpy optional.
  Pose pose(const Value& v) const {
    Map m(*this, v);
    m.allowOnly({"xyz", "rpy"});
    const Vec3 xyz = vec3(m.require("xyz"));
    Vec3 rpy;
    if (const Value* x = m.find("rpy")) rpy = vec3(*x);
    return Pose::fromXyzRpy(xyz.x, xyz.y, xyz.z, rpy.x, rpy.y, rpy.z);
  }

  // Resolves a texture reference and proves that it decodes.
  std::string texture(const Value& v) const {
    const std::string uri = string(v);
    std::string error;
    std::string path = resolveResourcePath(uri, dir_, packages_, error);
    if (!error.empty()) fail(v, error);
    path = std::filesystem::path(path).lexically_normal().string();
    struct stat st {};
    if (::stat(path.c_str(), &st) != 0) fail(v, "cannot load image '" + path + "': " + std::strerror(errno));
    if (!S_ISREG(st.st_mode)) fail(v, "cannot load image '" + path + "': not a regular file");
    if (::access(path.c_str(), R_OK) != 0) fail(v, "cannot load image '" + path + "': " + std::strerror(errno));
    if (!textureLoads(path)) fail(v, "cannot load image '" + path + "': not a decodable image");
    return path;
  }

  PhysicsSettings physics(const Value& v) const {
    Map m(*this, v);
    m.allowOnly({"step_s", "gravity_mps2", "solver_iterations", "max_contacts"});
    PhysicsSettings p;
    if (const Value* x = m.find("step_s")) {
      p.step_s = number(*x);
      if (!(p.step_s > 0.0 && p.step_s <= 0.01)) fail(*x, "must be in (0, 0.01], got " + x->node.Scalar());
    }
    if (const Value* x = m.find("gravity_mps2")) p.gravity_mps2 = vec3(*x);
    if (const Value* x = m.find("solver_iterations")) p.solver_iterations = intInRange(*x, 1, 1000);
    if (const Value* x = m.find("max_contacts")) p.max_contacts = intInRange(*x, 1, 100);
    return p;
  }

  GroundSpec ground(const Value& v) const {
    Map m(*this, v);
    m.allowOnly({"texture", "x_range_m", "y_range_m", "color_rgb", "friction"});
    GroundSpec g;
    const Value* texture_value = m.find("texture");
    // The ranges place the texture; without one they mean nothing but are still checked.
    const std::string note = " (needed with a texture)";
    if (texture_value) {
      m.require("x_range_m", note);
      m.require("y_range_m", note);
    }
    if (const Value* x = m.find("x_range_m")) range(*x, g.x_min_m, g.x_max_m);
    if (const Value* x = m.find("y_range_m")) range(*x, g.y_min_m, g.y_max_m);
    if (const Value* x = m.find("color_rgb")) g.color_rgb = color(*x);
    if (const Value* x = m.find("friction")) g.friction = friction(*x);
    if (texture_value) g.texture_path = texture(*texture_value);
    return g;
  }

  // `name_value` receives the name's location, for the duplicate-name message.
  WorldObject object(const Value& v, Value& name_value) const {
    Map m(*this, v);
    WorldObject o;
    o.name = name(m.require("name"));
    m.rename(v.where + " (" + o.name + ")");
    name_value = m.require("name");
    m.allowOnly({"name", "shape", "size_m", "radius_m", "length_m", "pose", "color_rgb", "texture", "display_topic",
                 "static", "mass_kg", "collision", "friction"});

    const Value& shape = m.require("shape");
    const std::string shape_name = string(shape);
    if (shape_name == "box")
      o.shape = ObjectShape::kBox;
    else if (shape_name == "cylinder")
      o.shape = ObjectShape::kCylinder;
    else if (shape_name == "cone")
      o.shape = ObjectShape::kCone;
    else if (shape_name == "sphere")
      o.shape = ObjectShape::kSphere;
    else
      fail(shape, "unknown shape " + describe(shape.node) + " (expected one of: box, cylinder, cone, sphere)");

    // Which dimension keys each shape takes; the others are errors, not silently ignored.
    const bool box = o.shape == ObjectShape::kBox;
    const bool has_length = o.shape == ObjectShape::kCylinder || o.shape == ObjectShape::kCone;
    const std::string not_for_shape = "does not apply to shape '" + shape_name + "'";
    const std::string for_shape = " for shape '" + shape_name + "'";
    if (box) {
      m.forbid("radius_m", not_for_shape);
      m.forbid("length_m", not_for_shape);
      o.size_m = positiveVec3(m.require("size_m", for_shape));
    } else {
      m.forbid("size_m", not_for_shape);
      m.forbid("texture", not_for_shape + " (only boxes show textures)");
      m.forbid("display_topic", not_for_shape + " (only boxes show images)");
      if (!has_length) m.forbid("length_m", not_for_shape);
      o.radius_m = positive(m.require("radius_m", for_shape));
      if (has_length) o.length_m = positive(m.require("length_m", for_shape));
    }

    o.pose = pose(m.require("pose"));
    if (const Value* x = m.find("color_rgb")) o.color_rgb = color(*x);
    if (const Value* x = m.find("static")) o.is_static = boolean(*x);
    if (const Value* x = m.find("collision")) o.collision = boolean(*x);
    if (o.is_static) {
      m.forbid("mass_kg", "does not apply to static objects (set static: false)");
    } else {
      o.mass_kg = positive(m.require("mass_kg", " for a dynamic object (static: false)"));
      if (!o.collision) fail(*m.find("collision"), "a dynamic object must collide (it would fall through the ground)");
    }
    if (const Value* x = m.find("friction")) o.friction = friction(*x);
    if (const Value* x = m.find("display_topic")) {
      o.display_topic = string(*x);
      if (!isTopicName(o.display_topic)) fail(*x, "invalid topic name " + describe(x->node));
    }
    if (const Value* x = m.find("texture")) o.texture_path = texture(*x);
    return o;
  }

  // spawn: {robot: {xyz: [x, y, z], yaw: rad}}
  std::vector<SpawnPose> spawns(const Value& v) const {
    Map m(*this, v);
    std::vector<SpawnPose> out;
    for (const auto& e : m.entries()) {
      if (!isName(e.name))
        fail(e.key_line, m.where(), "invalid spawn name '" + e.name + "' (use letters, digits and '_')");
      Map s(*this, e.value);
      s.allowOnly({"xyz", "yaw"});
      SpawnPose sp;
      sp.name = e.name;
      sp.pose.position = vec3(s.require("xyz"));
      if (const Value* x = s.find("yaw")) sp.pose.orientation = Quat::fromRpy(0.0, 0.0, number(*x));
      out.push_back(sp);
    }
    return out;
  }

  // light_regions: [{name, polygon_xy_m: [[x, y], ...], z_range_m: [min, max], light: 0..1}]
  std::vector<LightRegion> lightRegions(const Value& v) const {
    std::vector<LightRegion> out;
    for (const Value& item : v.node.IsNull() ? std::vector<Value>() : list(v)) {
      Map m(*this, item);
      m.allowOnly({"name", "polygon_xy_m", "z_range_m", "light"});
      LightRegion r;
      r.name = name(m.require("name"));
      m.rename(item.where + " (" + r.name + ")");
      for (const auto& other : out) {
        if (other.name == r.name) fail(*m.find("name"), "duplicate light region name '" + r.name + "'");
      }
      const Value& polygon = m.require("polygon_xy_m");
      const std::vector<Value> corners = list(polygon);
      if (corners.size() < 3)
        fail(polygon, "expected a list of at least 3 [x, y] corners, got " + std::to_string(corners.size()));
      for (const Value& corner : corners) {
        const auto xy = numbers(corner, 2);
        r.polygon_xy_m.push_back({xy[0], xy[1]});
      }
      range(m.require("z_range_m"), r.z_min_m, r.z_max_m);
      const Value& light = m.require("light");
      r.light = number(light);
      if (r.light < 0.0 || r.light > 1.0) fail(light, "must be in 0..1, got " + light.node.Scalar());
      out.push_back(std::move(r));
    }
    return out;
  }

  WorldDescription world(const YAML::Node& root) const {
    const Value top{root, root.IsNull() ? 1 : root.Mark().line + 1, ""};
    if (!root.IsMap()) fail(top, "expected a map with keys format, name, ..., got " + describe(root));
    Map m(*this, top);
    // The format first: a newer file should say so rather than fail on its new keys.
    const Value& format = m.require("format");
    if (!format.node.IsScalar() || format.node.Scalar() != kFormat)
      fail(format, std::string("expected '") + kFormat + "', got " + describe(format.node));
    m.allowOnly({"format", "name", "physics", "ground", "objects", "spawn", "light_regions"});

    WorldDescription w;
    w.name = name(m.require("name"));
    if (const Value* x = m.find("physics")) w.physics = physics(*x);
    w.ground = ground(m.require("ground"));
    if (const Value* x = m.find("objects")) {
      std::map<std::string, Value> names;  // first use of each name, for the duplicate message
      // Null "objects:" = no objects, as for maps.
      const std::vector<Value> items = x->node.IsNull() ? std::vector<Value>() : list(*x);
      for (const Value& item : items) {
        Value name_value;
        WorldObject o = object(item, name_value);
        const auto first = names.find(o.name);
        if (first != names.end()) {
          fail(name_value, "duplicate object name '" + o.name + "' (first used by " + first->second.where +
                               " at line " + std::to_string(first->second.line) + ")");
        }
        names.emplace(o.name, Value{YAML::Node(), name_value.line, item.where});
        w.objects.push_back(std::move(o));
      }
    }
    if (const Value* x = m.find("spawn")) w.spawns = spawns(*x);
    if (const Value* x = m.find("light_regions")) w.light_regions = lightRegions(*x);
    return w;
  }

 private:
  std::string file_;  // as given by the caller, for messages
  std::string dir_;   // absolute directory of the file, for relative textures
  const PackageResolver& packages_;
};

}  // namespace

const SpawnPose* WorldDescription::findSpawn(const std::string& spawn_name) const {
  for (const auto& s : spawns) {
    if (s.name == spawn_name) return &s;
  }
  return nullptr;
}

bool textureLoads(const std::string& path) {
  // Checked first because imread logs a warning to stderr for files it cannot open.
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0 || !S_ISREG(st.st_mode)) return false;
  // IMREAD_UNCHANGED decodes every supported depth and channel count without conversion.
  return !cv::imread(path, cv::IMREAD_UNCHANGED).empty();
}

WorldDescription loadWorldFile(const std::string& path, const PackageResolver& packages) {
  const std::string extension = std::filesystem::path(path).extension().string();
  if (extension == ".world" || extension == ".sdf") return loadSdfWorld(path, packages);
  // Read the file ourselves: YAML::LoadFile only says "bad file" without the reason.
  std::string text;
  {
    std::FILE* f = std::fopen(path.c_str(), "rb");
    if (!f) throw WorldFileError("cannot open world file '" + path + "': " + std::strerror(errno));
    char buffer[65536];
    size_t n = 0;
    while ((n = std::fread(buffer, 1, sizeof(buffer), f)) > 0) text.append(buffer, n);
    const bool failed = std::ferror(f);
    const int error = errno;  // e.g. EISDIR: fopen accepts directories, fread does not
    std::fclose(f);
    if (failed) throw WorldFileError("cannot open world file '" + path + "': " + std::strerror(error));
  }

  YAML::Node root;
  try {
    root = YAML::Load(text);
  } catch (const YAML::Exception& e) {
    throw WorldFileError(path + ":" + std::to_string(e.mark.line + 1) + ": YAML syntax error: " + e.msg);
  }

  const std::filesystem::path absolute = std::filesystem::absolute(path).lexically_normal();
  const Loader loader(path, absolute.parent_path().string(), packages);
  WorldDescription world;
  try {
    world = loader.world(root);
  } catch (const YAML::Exception& e) {  // not expected: values are decoded without throwing
    throw WorldFileError(path + ":" + std::to_string(e.mark.line + 1) + ": " + e.msg);
  }
  world.source_path = absolute.string();
  return world;
}

Shape collisionShapeOf(const WorldObject& object) {
  Shape s;
  switch (object.shape) {
    case ObjectShape::kBox:
      s.type = ShapeType::kBox;
      s.box_size_m = object.size_m;
      break;
    case ObjectShape::kCylinder:
    case ObjectShape::kCone:  // collides as its bounding cylinder
      s.type = ShapeType::kCylinder;
      s.radius_m = object.radius_m;
      s.length_m = object.length_m;
      break;
    case ObjectShape::kSphere:
      s.type = ShapeType::kSphere;
      s.radius_m = object.radius_m;
      break;
    case ObjectShape::kMesh:
      s.type = ShapeType::kMesh;
      if (object.mesh) {
        s.mesh_vertices_m = object.mesh->vertices_m;
        s.mesh_triangles = object.mesh->triangles;
      }
      s.mesh_bvh = object.mesh_bvh;
      break;
  }
  return s;
}

ArticulatedModel modelOfDynamicObject(const WorldObject& object) {
  if (object.is_static) throw std::invalid_argument("modelOfDynamicObject: object '" + object.name + "' is static");
  const double m = object.mass_kg;
  const double r = object.radius_m;
  const double h = object.length_m;
  BodySpec body;
  body.name = object.name;
  body.merged_links = {object.name};
  body.merged_link_poses = {Pose()};
  body.mass_kg = m;
  Inertia inertia;
  switch (object.shape) {
    case ObjectShape::kBox:
      inertia = boxInertia(m, object.size_m);
      break;
    case ObjectShape::kCylinder:
      inertia = cylinderInertia(m, r, h);
      break;
    case ObjectShape::kSphere:
      inertia = sphereInertia(m, r);
      break;
    case ObjectShape::kCone:
      // Solid cone, apex at +z: centre of mass h/4 above the base, i.e. h/4 below the centre.
      body.inertial_frame.position = Vec3(0.0, 0.0, -h / 4.0);
      inertia.ixx = inertia.iyy = m * (3.0 * r * r / 20.0 + 3.0 * h * h / 80.0);
      inertia.izz = 3.0 * m * r * r / 10.0;
      break;
    case ObjectShape::kMesh: {
      // The solid bounding box of the vertices (documented simplification).
      Vec3 lo, hi;
      if (object.mesh && !object.mesh->vertices_m.empty()) {
        lo = hi = object.mesh->vertices_m.front();
        for (const Vec3& p : object.mesh->vertices_m) {
          lo = Vec3(std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z));
          hi = Vec3(std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z));
        }
      }
      body.inertial_frame.position = (lo + hi) * 0.5;
      inertia = boxInertia(m, hi - lo);
      break;
    }
  }
  body.principal_inertia_kgm2 = Vec3(inertia.ixx, inertia.iyy, inertia.izz);
  if (object.collision) {
    CollisionSpec c;
    c.shape = collisionShapeOf(object);
    c.surface = object.friction;
    body.collisions.push_back(c);
  }
  ArticulatedModel model;
  model.name = object.name;
  model.bodies.push_back(body);
  return model;
}

}  // namespace conde_physics
