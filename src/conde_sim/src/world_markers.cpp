#include "conde_sim/world_markers.h"
#include "conde_sim/ros_conversions.h"

#include <sys/stat.h>

#include <fstream>
#include <sstream>
#include <stdexcept>

namespace conde_sim {

namespace cp = conde_physics;

namespace {

void makeDirectories(const std::string& path) {
  std::string partial;
  std::istringstream parts(path);
  std::string part;
  if (!path.empty() && path[0] == '/') partial = "/";
  while (std::getline(parts, part, '/')) {
    if (part.empty()) continue;
    partial += part + "/";
    mkdir(partial.c_str(), 0755);  // existing folders are fine
  }
}

std::string baseName(const std::string& path) {
  const auto slash = path.find_last_of('/');
  return slash == std::string::npos ? path : path.substr(slash + 1);
}

}  // namespace

std::string writeGroundMesh(const cp::WorldDescription& world, const std::string& cache_dir) {
  const cp::GroundSpec& g = world.ground;
  if (g.texture_path.empty()) return "";
  makeDirectories(cache_dir);
  const std::string texture_name = world.name + "_" + baseName(g.texture_path);
  {
    std::ifstream src(g.texture_path, std::ios::binary);
    std::ofstream dst(cache_dir + "/" + texture_name, std::ios::binary);
    dst << src.rdbuf();
    if (!dst) throw std::runtime_error("cannot write '" + cache_dir + "/" + texture_name + "'");
  }
  const std::string mesh_path = cache_dir + "/" + world.name + "_ground.dae";
  std::ofstream out(mesh_path);
  // One textured quad, 1 mm above z = 0 so it never flickers against rviz's grid.
  const double z = 0.001;
  out << "<?xml version=\"1.0\" encoding=\"utf-8\"?>\n"
         "<COLLADA xmlns=\"http://www.collada.org/2005/11/COLLADASchema\" version=\"1.4.1\">\n"
         "<asset><unit name=\"meter\" meter=\"1\"/><up_axis>Z_UP</up_axis></asset>\n"
         "<library_images><image id=\"ground_image\"><init_from>"
      << texture_name
      << "</init_from></image></library_images>\n"
         "<library_effects><effect id=\"ground_effect\"><profile_COMMON>\n"
         "<newparam sid=\"surface\"><surface type=\"2D\"><init_from>ground_image</init_from></surface></newparam>\n"
         "<newparam sid=\"sampler\"><sampler2D><source>surface</source></sampler2D></newparam>\n"
         "<technique sid=\"common\"><lambert><emission><color>0.9 0.9 0.9 1</color></emission>"
         "<diffuse><texture texture=\"sampler\" texcoord=\"uv\"/></diffuse></lambert></technique>\n"
         "</profile_COMMON></effect></library_effects>\n"
         "<library_materials><material id=\"ground_material\"><instance_effect url=\"#ground_effect\"/></material>"
         "</library_materials>\n"
         "<library_geometries><geometry id=\"ground\"><mesh>\n"
         "<source id=\"positions\"><float_array id=\"positions_array\" count=\"12\">"
      << g.x_min_m << " " << g.y_min_m << " " << z << " " << g.x_max_m << " " << g.y_min_m << " " << z << " "
      << g.x_max_m << " " << g.y_max_m << " " << z << " " << g.x_min_m << " " << g.y_max_m << " " << z
      << "</float_array><technique_common><accessor source=\"#positions_array\" count=\"4\" stride=\"3\">"
         "<param name=\"X\" type=\"float\"/><param name=\"Y\" type=\"float\"/><param name=\"Z\" type=\"float\"/>"
         "</accessor></technique_common></source>\n"
         "<source id=\"uvs\"><float_array id=\"uvs_array\" count=\"8\">0 0 1 0 1 1 0 1</float_array>"
         "<technique_common><accessor source=\"#uvs_array\" count=\"4\" stride=\"2\">"
         "<param name=\"S\" type=\"float\"/><param name=\"T\" type=\"float\"/></accessor></technique_common></source>\n"
         "<source id=\"normals\"><float_array id=\"normals_array\" count=\"3\">0 0 1</float_array>"
         "<technique_common><accessor source=\"#normals_array\" count=\"1\" stride=\"3\">"
         "<param name=\"X\" type=\"float\"/><param name=\"Y\" type=\"float\"/><param name=\"Z\" type=\"float\"/>"
         "</accessor></technique_common></source>\n"
         "<vertices id=\"vertices\"><input semantic=\"POSITION\" source=\"#positions\"/></vertices>\n"
         "<triangles material=\"ground_material\" count=\"2\">"
         "<input semantic=\"VERTEX\" source=\"#vertices\" offset=\"0\"/>"
         "<input semantic=\"NORMAL\" source=\"#normals\" offset=\"1\"/>"
         "<input semantic=\"TEXCOORD\" source=\"#uvs\" offset=\"2\" set=\"0\"/>"
         "<p>0 0 0 1 0 1 2 0 2 0 0 0 2 0 2 3 0 3</p></triangles>\n"
         "</mesh></geometry></library_geometries>\n"
         "<library_visual_scenes><visual_scene id=\"scene\"><node id=\"ground_node\">"
         "<instance_geometry url=\"#ground\"><bind_material><technique_common>"
         "<instance_material symbol=\"ground_material\" target=\"#ground_material\">"
         "<bind_vertex_input semantic=\"uv\" input_semantic=\"TEXCOORD\" input_set=\"0\"/></instance_material>"
         "</technique_common></bind_material></instance_geometry></node></visual_scene></library_visual_scenes>\n"
         "<scene><instance_visual_scene url=\"#scene\"/></scene>\n"
         "</COLLADA>\n";
  if (!out) throw std::runtime_error("cannot write '" + mesh_path + "'");
  return mesh_path;
}

visualization_msgs::MarkerArray worldMarkers(const cp::WorldDescription& world, const std::string& ground_mesh_path) {
  visualization_msgs::MarkerArray markers;
  auto base = [&](const std::string& ns, int id) {
    visualization_msgs::Marker m;
    m.header.frame_id = "world";
    m.ns = ns;
    m.id = id;
    m.action = visualization_msgs::Marker::ADD;
    m.pose.orientation.w = 1.0;
    m.scale.x = m.scale.y = m.scale.z = 1.0;
    m.color.a = 1.0;
    m.frame_locked = true;
    return m;
  };
  if (!ground_mesh_path.empty()) {
    visualization_msgs::Marker m = base("ground", 0);
    m.type = visualization_msgs::Marker::MESH_RESOURCE;
    m.mesh_resource = "file://" + ground_mesh_path;
    m.mesh_use_embedded_materials = true;
    m.color.r = m.color.g = m.color.b = 1.0;
    markers.markers.push_back(m);
  }
  int id = 0;
  for (const cp::WorldObject& o : world.objects) {
    visualization_msgs::Marker m = base("objects", id++);
    if (!o.visible) continue;  // an SDF <collision>: its <visual> has a marker of its own
    m.pose = toMsg(o.pose);
    m.color.r = o.color_rgb.x;
    m.color.g = o.color_rgb.y;
    m.color.b = o.color_rgb.z;
    switch (o.shape) {
      case cp::ObjectShape::kBox:
        m.type = visualization_msgs::Marker::CUBE;
        m.scale.x = o.size_m.x;
        m.scale.y = o.size_m.y;
        m.scale.z = o.size_m.z;
        break;
      case cp::ObjectShape::kSphere:
        m.type = visualization_msgs::Marker::SPHERE;
        m.scale.x = m.scale.y = m.scale.z = 2 * o.radius_m;
        break;
      case cp::ObjectShape::kCylinder:
      case cp::ObjectShape::kCone:  // rviz has no cone primitive
        m.type = visualization_msgs::Marker::CYLINDER;
        m.scale.x = m.scale.y = 2 * o.radius_m;
        m.scale.z = o.length_m;
        break;
      case cp::ObjectShape::kMesh:
        m.type = visualization_msgs::Marker::TRIANGLE_LIST;
        m.scale.x = m.scale.y = m.scale.z = 1.0;
        if (o.mesh) {
          for (int index : o.mesh->triangles) {
            geometry_msgs::Point p;
            p.x = o.mesh->vertices_m[index].x;
            p.y = o.mesh->vertices_m[index].y;
            p.z = o.mesh->vertices_m[index].z;
            m.points.push_back(p);
          }
          for (const cp::Vec3& c : o.mesh->triangle_rgb) {
            std_msgs::ColorRGBA rgba;
            rgba.r = c.x;
            rgba.g = c.y;
            rgba.b = c.z;
            rgba.a = 1.0;
            m.colors.insert(m.colors.end(), 3, rgba);  // one per vertex
          }
        }
        break;
    }
    markers.markers.push_back(m);
  }
  return markers;
}

}  // namespace conde_sim
