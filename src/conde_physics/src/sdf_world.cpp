#include "conde_physics/sdf_world.h"

#include <tinyxml2.h>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <sdf/sdf.hh>
#include <set>
#include <sstream>

#include "conde_physics/mesh_bvh.h"

namespace conde_physics {

namespace {

namespace fs = std::filesystem;

Pose toPose(const ignition::math::Pose3d& p) {
  return Pose(Vec3(p.Pos().X(), p.Pos().Y(), p.Pos().Z()), Quat(p.Rot().W(), p.Rot().X(), p.Rot().Y(), p.Rot().Z()));
}

// Pose of an element in its default frame (the parent's); the raw pose when the graph cannot
// resolve it (libsdformat has reported that already at load).
Pose resolved(const sdf::SemanticPose& semantic) {
  ignition::math::Pose3d pose;
  if (!semantic.Resolve(pose).empty()) pose = semantic.RawPose();
  return toPose(pose);
}

std::string errorText(const sdf::Error& e, const std::string& path) {
  // SDF given as a string has a placeholder such as "<data-string>" as its file.
  std::string where = e.FilePath() && e.FilePath()->compare(0, 1, "<") != 0 ? *e.FilePath() : path;
  if (e.LineNumber()) where += ":" + std::to_string(*e.LineNumber());
  std::string message = e.Message();
  while (!message.empty() && (message.back() == '\n' || message.back() == ' ')) message.pop_back();
  return where + ": " + message;
}

// Colours of Gazebo's stock script materials (media/materials/scripts/gazebo.material, diffuse).
const std::map<std::string, Vec3>& gazeboMaterials() {
  static const std::map<std::string, Vec3> table = {
      {"Gazebo/White", {1.0, 1.0, 1.0}},
      {"Gazebo/Grey", {0.7, 0.7, 0.7}},
      {"Gazebo/Gray", {0.7, 0.7, 0.7}},
      {"Gazebo/DarkGrey", {0.175, 0.175, 0.175}},
      {"Gazebo/DarkGray", {0.175, 0.175, 0.175}},
      {"Gazebo/Black", {0.0, 0.0, 0.0}},
      {"Gazebo/Red", {1.0, 0.0, 0.0}},
      {"Gazebo/Green", {0.0, 1.0, 0.0}},
      {"Gazebo/Blue", {0.0, 0.0, 1.0}},
      {"Gazebo/Yellow", {1.0, 1.0, 0.0}},
      {"Gazebo/Orange", {1.0, 0.5088, 0.0468}},
      {"Gazebo/Purple", {1.0, 0.0, 1.0}},
      {"Gazebo/Turquoise", {0.0, 1.0, 1.0}},
      {"Gazebo/Indigo", {0.33, 0.0, 0.5}},
      {"Gazebo/Wood", {1.0, 0.8, 0.6}},
      {"Gazebo/WoodFloor", {0.8, 0.6, 0.4}},
      {"Gazebo/Bricks", {0.6, 0.3, 0.2}},
      {"Gazebo/FlatBlack", {0.1, 0.1, 0.1}},
  };
  return table;
}

std::vector<std::string> envPath(const char* variable) {
  std::vector<std::string> dirs;
  const char* value = std::getenv(variable);
  if (value == nullptr) return dirs;
  std::stringstream in(value);
  std::string dir;
  while (std::getline(in, dir, ':')) {
    if (!dir.empty()) dirs.push_back(dir);
  }
  return dirs;
}

class SdfConverter {
 public:
  // `source`: the SDF file, or a name for SDF given as a string; `dir`: the folder that
  // relative mesh paths (and, for a file, model:// URIs) are resolved against.
  SdfConverter(const std::string& source, const std::string& dir, const PackageResolver& packages)
      : path_(source), dir_(dir), packages_(packages) {
    model_dirs_ = envPath("GAZEBO_MODEL_PATH");
  }

  WorldDescription loadWorld() {
    model_dirs_.push_back(dir_);
    model_dirs_.push_back(dir_ + "/models");
    // libsdformat reports XML syntax errors only as "Unable to read file" (the line goes to its
    // console): tinyxml2 finds the line first.
    tinyxml2::XMLDocument xml;
    if (xml.LoadFile(path_.c_str()) != tinyxml2::XML_SUCCESS)
      throw WorldFileError(path_ + ":" + std::to_string(xml.ErrorLineNum()) + ": XML error: " + xml.ErrorStr());
    sdf::Root root;
    const sdf::Errors errors = root.Load(path_, parserConfig());
    if (!errors.empty()) throw WorldFileError(errorText(errors.front(), path_));
    if (root.WorldCount() == 0) throw WorldFileError(path_ + ": no <world> in this SDF file");
    const sdf::World& w = *root.WorldByIndex(0);
    world_.name = w.Name();
    world_.source_path = fs::absolute(path_).lexically_normal().string();
    const ignition::math::Vector3d g = w.Gravity();
    world_.physics.gravity_mps2 = Vec3(g.X(), g.Y(), g.Z());
    if (const sdf::Physics* physics = w.PhysicsDefault()) {
      if (physics->MaxStepSize() <= 0.0 || physics->MaxStepSize() > 0.01)
        throw WorldFileError(path_ + ": <physics><max_step_size> " + std::to_string(physics->MaxStepSize()) +
                             " is outside (0, 0.01] s");
      world_.physics.step_s = physics->MaxStepSize();
      if (physics->Element() && physics->Element()->HasElement("real_time_factor"))
        world_.real_time_factor = physics->RealTimeFactor();
    }
    if (w.LightCount() > 0)
      note(std::to_string(w.LightCount()) +
           " <light> accepted and ignored (the cameras light objects with a fixed sun)");
    for (sdf::ElementPtr e = w.Element()->GetFirstElement(); e; e = e->GetNextElement()) {
      static const std::set<std::string> used = {"model", "physics", "gravity", "light", "include", "frame"};
      if (used.count(e->GetName()) == 0 && e->GetExplicitlySetInFile())
        note("<" + e->GetName() + "> accepted and ignored");
    }
    for (uint64_t i = 0; i < w.ModelCount(); ++i) {
      const sdf::Model& model = *w.ModelByIndex(i);
      addModel(model, Pose(), model.Name());
    }
    return world_;
  }

  SdfModelObjects loadModel(const std::string& sdf_xml, const std::string& model_name) {
    tinyxml2::XMLDocument xml;
    if (xml.Parse(sdf_xml.c_str()) != tinyxml2::XML_SUCCESS)
      throw WorldFileError(path_ + ":" + std::to_string(xml.ErrorLineNum()) + ": XML error: " + xml.ErrorStr());
    if (xml.RootElement() == nullptr || std::string(xml.RootElement()->Name()) != "sdf")
      throw WorldFileError(path_ + ": the XML's root element is <" +
                           (xml.RootElement() ? xml.RootElement()->Name() : "") + ">, not <sdf>");
    sdf::Root root;
    const sdf::Errors errors = root.LoadSdfString(sdf_xml, parserConfig());
    if (!errors.empty()) throw WorldFileError(errorText(errors.front(), path_));
    const sdf::Model* model = root.Model();
    if (model == nullptr && root.WorldCount() == 1 && root.WorldByIndex(0)->ModelCount() == 1)
      model = root.WorldByIndex(0)->ModelByIndex(0);  // <world><include>model://NAME</include></world>
    if (model == nullptr)
      throw WorldFileError(path_ + ": no <model> to spawn (expected <sdf><model>, or <sdf><world> with one model)");
    dynamic_object_name_ = model_name;
    addModel(*model, Pose(), model_name);
    SdfModelObjects result;
    result.objects = world_.objects;
    result.is_static = model->Static();
    result.notes = world_.notes;
    return result;
  }

 private:
  void note(const std::string& text) { world_.notes.push_back(path_ + ": " + text); }

  sdf::ParserConfig parserConfig() {
    sdf::ParserConfig config;
    for (const std::string& dir : model_dirs_) config.AddURIPath("model://", dir);
    config.SetFindCallback([this](const std::string& uri) { return findModelUri(uri); });
    return config;
  }

  // model://<name>/<rest> through GAZEBO_MODEL_PATH and the world's folder, then as
  // <package path>/<rest>; "" when nothing holds it.
  std::string findModelUri(const std::string& uri) const {
    const std::string scheme = "model://";
    if (uri.compare(0, scheme.size(), scheme) != 0) return "";
    const std::string rest = uri.substr(scheme.size());
    for (const std::string& dir : model_dirs_) {
      if (fs::exists(fs::path(dir) / rest)) return (fs::path(dir) / rest).string();
    }
    const size_t slash = rest.find('/');
    const std::string package = rest.substr(0, slash);
    const std::string package_dir = packages_ ? packages_(package) : "";
    if (package_dir.empty()) return "";
    const fs::path candidate =
        slash == std::string::npos ? fs::path(package_dir) : fs::path(package_dir) / rest.substr(slash + 1);
    return fs::exists(candidate) ? candidate.string() : "";
  }

  std::string meshPath(const sdf::Mesh& mesh, const std::string& where) const {
    const std::string uri = mesh.Uri();
    std::string path;
    if (uri.compare(0, 8, "model://") == 0) {
      path = findModelUri(uri);
      if (path.empty())
        throw WorldFileError(where + ": mesh '" + uri + "' not found (GAZEBO_MODEL_PATH, ROS packages)");
      return path;
    }
    std::string error;
    const std::string base = mesh.FilePath().empty() ? dir_ : directoryOf(mesh.FilePath());
    path = resolveResourcePath(uri, base, packages_, error);
    if (!error.empty()) throw WorldFileError(where + ": mesh '" + uri + "': " + error);
    return path;
  }

  static Vec3 colourOf(const sdf::Material* material) {
    if (material == nullptr) return Vec3(0.7, 0.7, 0.7);
    const sdf::ElementPtr e = material->Element();
    auto rgb = [](const ignition::math::Color& c) { return Vec3(c.R(), c.G(), c.B()); };
    if (e && e->HasElement("diffuse")) return rgb(material->Diffuse());
    if (e && e->HasElement("ambient")) return rgb(material->Ambient());
    const auto found = gazeboMaterials().find(material->ScriptName());
    return found != gazeboMaterials().end() ? found->second : Vec3(0.7, 0.7, 0.7);
  }

  // Shape of `o` from an SDF geometry; false for a geometry this simulator does not draw or
  // collide (noted). A horizontal plane at z = 0 becomes the ground (false as well).
  bool shapeOf(const sdf::Geometry& geometry, const std::string& where, WorldObject& o, bool visual) {
    switch (geometry.Type()) {
      case sdf::GeometryType::BOX: {
        const auto size = geometry.BoxShape()->Size();
        o.shape = ObjectShape::kBox;
        o.size_m = Vec3(size.X(), size.Y(), size.Z());
        return true;
      }
      case sdf::GeometryType::CYLINDER:
        o.shape = ObjectShape::kCylinder;
        o.radius_m = geometry.CylinderShape()->Radius();
        o.length_m = geometry.CylinderShape()->Length();
        return true;
      case sdf::GeometryType::SPHERE:
        o.shape = ObjectShape::kSphere;
        o.radius_m = geometry.SphereShape()->Radius();
        return true;
      case sdf::GeometryType::PLANE: {
        const auto n = geometry.PlaneShape()->Normal().Normalized();
        const Vec3 normal_world = o.pose.orientation.rotate(Vec3(n.X(), n.Y(), n.Z()));
        if (normal_world.z > 1.0 - 1e-9 && std::abs(o.pose.position.z) < 1e-9) {
          if (visual) world_.ground.color_rgb = o.color_rgb;
          if (!ground_noted_) world_.notes.push_back(where + ": horizontal plane at z = 0 taken as the ground plane");
          ground_noted_ = true;
          return false;
        }
        const auto size = geometry.PlaneShape()->Size();
        o.shape = ObjectShape::kBox;
        o.size_m = Vec3(size.X(), size.Y(), 0.001);
        // Local z along the normal: rotate (0, 0, 1) onto it.
        const Vec3 z(0.0, 0.0, 1.0), normal(n.X(), n.Y(), n.Z());
        const Vec3 axis = z.cross(normal);
        if (axis.norm() > 1e-12)
          o.pose = o.pose * Pose(Vec3(), Quat::fromAxisAngle(axis / axis.norm(),
                                                             std::acos(std::max(-1.0, std::min(1.0, normal.z)))));
        else if (normal.z < 0)
          o.pose = o.pose * Pose(Vec3(), Quat::fromAxisAngle(Vec3(1, 0, 0), M_PI));
        return true;
      }
      case sdf::GeometryType::MESH: {
        const sdf::Mesh& mesh = *geometry.MeshShape();
        const std::string file = meshPath(mesh, where);
        if (!mesh.Submesh().empty()) note(where + ": <submesh> ignored (the whole mesh is used)");
        const auto scale = mesh.Scale();
        // A file used by many models is read (and its BVH built) once.
        std::ostringstream key;
        key << file << ' ' << scale.X() << ' ' << scale.Y() << ' ' << scale.Z();
        LoadedMesh& loaded = meshes_[key.str()];
        if (!loaded.data) {
          try {
            loaded.data = std::make_shared<const MeshData>(loadMeshFile(file, Vec3(scale.X(), scale.Y(), scale.Z())));
          } catch (const MeshFileError& e) {
            throw WorldFileError(where + ": " + e.what());
          }
          loaded.bvh = std::make_shared<const MeshBvh>(loaded.data->vertices_m, loaded.data->triangles);
        }
        o.shape = ObjectShape::kMesh;
        o.mesh = loaded.data;
        o.mesh_bvh = loaded.bvh;
        o.mesh_path = file;
        return true;
      }
      default:
        note(where + ": geometry of this type is not supported and ignored");
        return false;
    }
  }

  // `name`: the model's scoped name ("outer::inner" for nested models).
  void addModel(const sdf::Model& model, const Pose& parent, const std::string& name) {
    const Pose model_pose = parent * resolved(model.SemanticPose());
    const std::string where = path_ + ": model '" + name + "'";
    for (uint64_t i = 0; i < model.ModelCount(); ++i) {
      const sdf::Model& nested = *model.ModelByIndex(i);
      addModel(nested, model_pose, name + "::" + nested.Name());
    }
    for (sdf::ElementPtr e = model.Element()->GetFirstElement(); e; e = e->GetNextElement()) {
      if (e->GetName() == "plugin")
        note("model '" + name + "': <plugin> '" + e->Get<std::string>("filename") + "' accepted and ignored");
    }
    if (model.JointCount() > 0) {
      if (!model.Static())
        throw WorldFileError(where + ": joints in dynamic models are not supported (spawn it as a URDF robot)");
      note("model '" + name + "': joints of a static model ignored");
    }
    if (!model.Static() && model.LinkCount() != 1)
      throw WorldFileError(where + ": a dynamic model must have exactly one <link> (it has " +
                           std::to_string(model.LinkCount()) + ")");
    for (uint64_t l = 0; l < model.LinkCount(); ++l) {
      const sdf::Link& link = *model.LinkByIndex(l);
      const Pose link_pose = model_pose * resolved(link.SemanticPose());
      const std::string link_name = name + "::" + link.Name();
      const std::string link_where = path_ + ": link '" + link_name + "'";
      if (link.SensorCount() > 0)
        note("link '" + link_name + "': sensors ignored (robots carry sensors as URDF plugins)");
      if (model.Static()) {
        addStaticLink(link, link_pose, link_name, link_where);
      } else {
        addDynamicLink(link, link_pose, link_name, link_where);
      }
    }
  }

  std::string objectName(const std::string& scoped) {
    // [A-Za-z0-9_]+ as the YAML worlds, unique.
    std::string name;
    for (char c : scoped) name += std::isalnum(static_cast<unsigned char>(c)) || c == '_' ? c : '_';
    std::string unique = name;
    for (int k = 2; used_names_.count(unique) > 0; ++k) unique = name + "_" + std::to_string(k);
    used_names_.insert(unique);
    return unique;
  }

  void addStaticLink(const sdf::Link& link, const Pose& link_pose, const std::string& link_name,
                     const std::string& where) {
    for (uint64_t c = 0; c < link.CollisionCount(); ++c) {
      const sdf::Collision& collision = *link.CollisionByIndex(c);
      WorldObject o;
      o.name = objectName(link_name + "::" + collision.Name());
      o.pose = link_pose * resolved(collision.SemanticPose());
      o.visible = false;
      if (shapeOf(*collision.Geom(), where + " collision '" + collision.Name() + "'", o, false))
        world_.objects.push_back(o);
    }
    for (uint64_t v = 0; v < link.VisualCount(); ++v) {
      const sdf::Visual& visual = *link.VisualByIndex(v);
      WorldObject o;
      o.name = objectName(link_name + "::" + visual.Name());
      o.pose = link_pose * resolved(visual.SemanticPose());
      o.color_rgb = colourOf(visual.Material());
      o.collision = false;
      if (shapeOf(*visual.Geom(), where + " visual '" + visual.Name() + "'", o, true)) world_.objects.push_back(o);
    }
  }

  void addDynamicLink(const sdf::Link& link, const Pose& link_pose, const std::string& link_name,
                      const std::string& where) {
    if (link.CollisionCount() != 1)
      throw WorldFileError(where + ": a dynamic link must have exactly one <collision> (it has " +
                           std::to_string(link.CollisionCount()) + ")");
    const sdf::Collision& collision = *link.CollisionByIndex(0);
    WorldObject o;
    o.name = dynamic_object_name_.empty() ? objectName(link_name) : dynamic_object_name_;
    o.pose = link_pose * resolved(collision.SemanticPose());
    o.is_static = false;
    o.mass_kg = link.Inertial().MassMatrix().Mass();
    if (!(o.mass_kg > 0.0)) throw WorldFileError(where + ": <inertial><mass> must be > 0 for a dynamic link");
    if (link.VisualCount() > 0) o.color_rgb = colourOf(link.VisualByIndex(0)->Material());
    const std::string collision_where = where + " collision '" + collision.Name() + "'";
    if (!shapeOf(*collision.Geom(), collision_where, o, false))
      throw WorldFileError(collision_where + ": this geometry cannot move (box, cylinder, sphere or mesh)");
    if (link.VisualCount() > 0)
      note("link '" + link_name + "': drawn as its collision shape with the first visual's colour");
    world_.objects.push_back(o);
  }

  std::string path_, dir_;
  PackageResolver packages_;
  std::vector<std::string> model_dirs_;
  WorldDescription world_;
  std::set<std::string> used_names_;
  std::string dynamic_object_name_;  // "": dynamic objects are named after their link
  bool ground_noted_ = false;
  struct LoadedMesh {
    std::shared_ptr<const MeshData> data;
    std::shared_ptr<const MeshBvh> bvh;
  };
  std::map<std::string, LoadedMesh> meshes_;  // by file and scale
};

}  // namespace

WorldDescription loadSdfWorld(const std::string& path, const PackageResolver& packages) {
  if (!fs::is_regular_file(path)) throw WorldFileError("cannot open world file '" + path + "': no such file");
  return SdfConverter(path, fs::absolute(path).lexically_normal().parent_path().string(), packages).loadWorld();
}

SdfModelObjects loadSdfModel(const std::string& sdf_xml, const std::string& source, const std::string& model_name,
                             const PackageResolver& packages) {
  return SdfConverter(source, fs::current_path().string(), packages).loadModel(sdf_xml, model_name);
}

}  // namespace conde_physics
