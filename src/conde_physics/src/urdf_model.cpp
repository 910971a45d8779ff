#include "conde_physics/urdf_model.h"

#include "conde_physics/mesh_bvh.h"
#include "conde_physics/mesh_file.h"

#include <console_bridge/console.h>
#include <tinyxml2.h>
#include <urdf_parser/urdf_parser.h>

#include <cstring>
#include <fstream>
#include <functional>
#include <map>
#include <mutex>
#include <set>
#include <sstream>

namespace conde_physics {
namespace {

// Bodies without mass in a moving model get this, so the engines stay stable.
constexpr double kTinyMassKg = 1e-3;
constexpr double kTinyInertiaKgm2 = 1e-6;

// Collects console_bridge messages (urdfdom reports parse errors through it).
class CapturingOutputHandler : public console_bridge::OutputHandler {
 public:
  void log(const std::string& text, console_bridge::LogLevel level, const char*, int) override {
    if (level >= console_bridge::CONSOLE_BRIDGE_LOG_ERROR) errors.push_back(text);
  }
  std::vector<std::string> errors;
};

Pose toPose(const urdf::Pose& p) {
  return Pose(Vec3(p.position.x, p.position.y, p.position.z),
              Quat(p.rotation.w, p.rotation.x, p.rotation.y, p.rotation.z).normalized());
}

struct MassProps {
  double mass_kg = 0.0;
  Vec3 com;         // in the body's link frame
  Inertia inertia;  // about `com`, body link axes
};

// Adds a point-mass-with-inertia to an accumulated body (parallel-axis theorem).
void addMass(MassProps& acc, double m, const Vec3& com, const Inertia& inertia_at_com) {
  if (m <= 0.0) return;
  const double total = acc.mass_kg + m;
  const Vec3 new_com = (acc.com * acc.mass_kg + com * m) / total;
  auto shifted = [](const Inertia& i, double mass, const Vec3& d) {
    Inertia r = i;
    r.ixx += mass * (d.y * d.y + d.z * d.z);
    r.iyy += mass * (d.x * d.x + d.z * d.z);
    r.izz += mass * (d.x * d.x + d.y * d.y);
    r.ixy -= mass * d.x * d.y;
    r.ixz -= mass * d.x * d.z;
    r.iyz -= mass * d.y * d.z;
    return r;
  };
  const Inertia a = shifted(acc.inertia, acc.mass_kg, acc.com - new_com);
  const Inertia b = shifted(inertia_at_com, m, com - new_com);
  acc.inertia = {a.ixx + b.ixx, a.ixy + b.ixy, a.ixz + b.ixz, a.iyy + b.iyy, a.iyz + b.iyz, a.izz + b.izz};
  acc.mass_kg = total;
  acc.com = new_com;
}

}  // namespace

Shape meshShapeFromFile(const std::string& path, const Vec3& scale) {
  MeshData mesh;
  try {
    mesh = loadMeshFile(path, scale);
  } catch (const MeshFileError& e) {
    throw ModelError(e.what());
  }
  Shape shape;
  shape.type = ShapeType::kMesh;
  shape.mesh_vertices_m = std::move(mesh.vertices_m);
  shape.mesh_triangles = std::move(mesh.triangles);
  shape.mesh_bvh = std::make_shared<const MeshBvh>(shape.mesh_vertices_m, shape.mesh_triangles);
  return shape;
}

ArticulatedModel buildModelFromUrdf(const std::string& urdf_xml, const std::string& source,
                                    const PackageResolver& packages, std::vector<std::string>* warnings,
                                    GazeboBlocks* gazebo) {
  auto warn = [&](const std::string& w) {
    if (warnings) warnings->push_back(source + ": " + w);
  };

  urdf::ModelInterfaceSharedPtr urdf;
  {
    // console_bridge's handler is process-global: serialise parses.
    static std::mutex parse_mutex;
    std::lock_guard<std::mutex> lock(parse_mutex);
    CapturingOutputHandler capture;
    console_bridge::OutputHandler* previous = console_bridge::getOutputHandler();
    console_bridge::useOutputHandler(&capture);
    urdf = urdf::parseURDF(urdf_xml);
    console_bridge::useOutputHandler(previous);
    if (!urdf) {
      std::string why = capture.errors.empty() ? "not a valid URDF document" : capture.errors.front();
      // tinyxml2 knows the line of XML syntax errors; urdfdom does not say it.
      tinyxml2::XMLDocument doc;
      if (doc.Parse(urdf_xml.c_str()) != tinyxml2::XML_SUCCESS) {
        why = "XML error at line " + std::to_string(doc.ErrorLineNum()) + ": " + doc.ErrorName();
      }
      throw ModelError(source + ": malformed URDF: " + why);
    }
  }
  GazeboBlocks blocks = readGazeboBlocks(urdf_xml, source, [&](const std::string& name) {
    return urdf->getLink(name) != nullptr || urdf->getJoint(name) != nullptr;
  });
  if (warnings) warnings->insert(warnings->end(), blocks.warnings.begin(), blocks.warnings.end());
  const auto& surfaces = blocks.surfaces;

  ArticulatedModel model;
  model.name = urdf->getName();
  urdf::LinkConstSharedPtr root = urdf->getRoot();
  if (root->name == "world") {
    if (root->child_links.size() != 1 || root->child_joints[0]->type != urdf::Joint::FIXED) {
      throw ModelError(source + ": link 'world' must have exactly one fixed joint to the robot's root link");
    }
    model.fixed_to_world = true;
    root = root->child_links[0];
  }

  std::vector<MassProps> mass(1);
  std::map<std::string, std::string> mesh_problems;  // resolved path -> "" (loads) or why not
  std::function<void(const urdf::LinkConstSharedPtr&, int, const Pose&, const Pose&)> visit;
  // body: index of the body holding `link`; in_body: link frame in the body's link frame;
  // in_model: link frame in the model frame at zero joint positions.
  visit = [&](const urdf::LinkConstSharedPtr& link, int body, const Pose& in_body, const Pose& in_model) {
    // Taken before any child body is added below (emplace_back would invalidate it).
    BodySpec& b = model.bodies[body];
    if (!b.merged_links.empty()) {
      b.merged_links.push_back(link->name);
      b.merged_link_poses.push_back(in_body);
    } else {
      b.name = link->name;
      b.merged_links = {link->name};
      b.merged_link_poses = {Pose()};
      b.initial_pose_in_model = in_model;
    }
    if (link->inertial) {
      const Pose inertial = in_body * toPose(link->inertial->origin);
      const auto& i = *link->inertial;
      if (i.mass < 0) throw ModelError(source + ": link '" + link->name + "': <mass> must not be negative");
      addMass(mass[body], i.mass, inertial.position,
              rotateInertia({i.ixx, i.ixy, i.ixz, i.iyy, i.iyz, i.izz}, inertial.orientation));
    }
    const auto surface_it = surfaces.find(link->name);
    const SurfaceParams surface = surface_it == surfaces.end() ? SurfaceParams() : surface_it->second;
    for (const auto& c : link->collision_array) {
      if (!c || !c->geometry) continue;
      CollisionSpec spec;
      spec.pose_in_link = in_body * toPose(c->origin);
      spec.surface = surface;
      const std::string where = source + ": link '" + link->name + "' <collision>";
      switch (c->geometry->type) {
        case urdf::Geometry::BOX: {
          const auto& d = std::static_pointer_cast<urdf::Box>(c->geometry)->dim;
          spec.shape.type = ShapeType::kBox;
          spec.shape.box_size_m = Vec3(d.x, d.y, d.z);
          if (d.x <= 0 || d.y <= 0 || d.z <= 0) throw ModelError(where + ": box size must be positive");
          break;
        }
        case urdf::Geometry::CYLINDER: {
          const auto cyl = std::static_pointer_cast<urdf::Cylinder>(c->geometry);
          spec.shape.type = ShapeType::kCylinder;
          spec.shape.radius_m = cyl->radius;
          spec.shape.length_m = cyl->length;
          if (cyl->radius <= 0 || cyl->length <= 0)
            throw ModelError(where + ": cylinder radius and length must be positive");
          break;
        }
        case urdf::Geometry::SPHERE: {
          spec.shape.type = ShapeType::kSphere;
          spec.shape.radius_m = std::static_pointer_cast<urdf::Sphere>(c->geometry)->radius;
          if (spec.shape.radius_m <= 0) throw ModelError(where + ": sphere radius must be positive");
          break;
        }
        case urdf::Geometry::MESH: {
          const auto mesh = std::static_pointer_cast<urdf::Mesh>(c->geometry);
          std::string error;
          const std::string path = resolveResourcePath(mesh->filename, ".", packages, error);
          if (!error.empty()) throw ModelError(where + ": mesh '" + mesh->filename + "': " + error);
          try {
            spec.shape = meshShapeFromFile(path, Vec3(mesh->scale.x, mesh->scale.y, mesh->scale.z));
            mesh_problems[path] = "";
          } catch (const ModelError& e) {
            throw ModelError(where + ": " + e.what());
          }
          break;
        }
      }
      b.collisions.push_back(spec);
    }
    // Gazebo prints an error for a visual mesh it cannot load and goes on without it; so do we
    // (the error is kept in model.visual_errors for the caller's log). Each file is read once.
    for (const auto& v : link->visual_array) {
      if (!v || !v->geometry || v->geometry->type != urdf::Geometry::MESH) continue;
      const auto mesh = std::static_pointer_cast<urdf::Mesh>(v->geometry);
      const std::string where = source + ": link '" + link->name + "' <visual>";
      std::string error;
      const std::string path = resolveResourcePath(mesh->filename, ".", packages, error);
      if (!error.empty()) {
        model.visual_errors.push_back(where + ": mesh '" + mesh->filename + "': " + error);
        continue;
      }
      const auto known = mesh_problems.find(path);
      std::string problem;
      if (known != mesh_problems.end()) {
        problem = known->second;
      } else {
        try {
          loadMeshFile(path, Vec3(1, 1, 1));
        } catch (const MeshFileError& e) {
          problem = e.what();
        }
        mesh_problems[path] = problem;
      }
      if (!problem.empty()) model.visual_errors.push_back(where + ": " + problem);
    }

    for (size_t k = 0; k < link->child_links.size(); ++k) {
      const auto& joint = link->child_joints[k];
      const auto& child = link->child_links[k];
      const Pose joint_in_parent = toPose(joint->parent_to_joint_origin_transform);
      const Pose child_in_model = in_model * joint_in_parent;
      if (joint->type == urdf::Joint::FIXED) {
        visit(child, body, in_body * joint_in_parent, child_in_model);
        continue;
      }
      JointSpec j;
      j.name = joint->name;
      switch (joint->type) {
        case urdf::Joint::REVOLUTE:
          j.type = JointType::kRevolute;
          break;
        case urdf::Joint::CONTINUOUS:
          j.type = JointType::kContinuous;
          break;
        case urdf::Joint::PRISMATIC:
          j.type = JointType::kPrismatic;
          break;
        default:
          throw ModelError(source + ": joint '" + joint->name + "': type " +
                           (joint->type == urdf::Joint::FLOATING ? "floating" : "planar") + " is not supported");
      }
      j.parent_body = body;
      j.pose_in_parent = in_body * joint_in_parent;
      j.axis = Vec3(joint->axis.x, joint->axis.y, joint->axis.z).normalized();
      if (j.axis.norm() == 0) throw ModelError(source + ": joint '" + joint->name + "': <axis> must not be zero");
      if (joint->limits) {
        j.effort_limit = joint->limits->effort;
        j.velocity_limit = joint->limits->velocity;
        if (j.type != JointType::kContinuous) {
          j.has_position_limits = true;
          j.lower = joint->limits->lower;
          j.upper = joint->limits->upper;
          if (j.lower > j.upper) {
            throw ModelError(source + ": joint '" + joint->name + "': <limit> lower " + std::to_string(j.lower) +
                             " is above upper " + std::to_string(j.upper));
          }
        }
      }
      if (joint->dynamics) {
        j.damping = joint->dynamics->damping;
        j.friction = joint->dynamics->friction;
      }
      if (joint->mimic) warn("joint '" + joint->name + "': <mimic> is ignored");
      model.bodies.emplace_back();
      mass.emplace_back();
      j.child_body = static_cast<int>(model.bodies.size()) - 1;
      model.joints.push_back(j);
      visit(child, j.child_body, Pose(), child_in_model);
    }
  };
  model.bodies.emplace_back();
  visit(root, 0, Pose(), Pose());

  for (size_t b = 0; b < model.bodies.size(); ++b) {
    BodySpec& body = model.bodies[b];
    MassProps& m = mass[b];
    const bool must_move = !(b == 0 && model.fixed_to_world);
    if (m.mass_kg <= 0.0) {
      if (must_move) {
        warn("body '" + body.name + "' has no mass; using " + std::to_string(kTinyMassKg) + " kg");
      }
      m.mass_kg = kTinyMassKg;
      m.inertia = {kTinyInertiaKgm2, 0, 0, kTinyInertiaKgm2, 0, kTinyInertiaKgm2};
    }
    body.mass_kg = m.mass_kg;
    Quat axes;
    principalAxes(m.inertia, body.principal_inertia_kgm2, axes);
    const double floor = kTinyInertiaKgm2 * 1e-3;  // keep engines away from zero moments
    body.principal_inertia_kgm2 =
        Vec3(std::max(body.principal_inertia_kgm2.x, floor), std::max(body.principal_inertia_kgm2.y, floor),
             std::max(body.principal_inertia_kgm2.z, floor));
    body.inertial_frame = Pose(m.com, axes);
  }
  if (gazebo) *gazebo = std::move(blocks);
  return model;
}

}  // namespace conde_physics
