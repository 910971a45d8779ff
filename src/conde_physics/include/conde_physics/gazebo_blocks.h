// The <gazebo> extension blocks of a URDF, read in one place for physics and for the plugins.
//
//   <gazebo reference="link">  mu1, mu2, kp, kd (contact surface, for physics), <sensor> elements
//                              (each with its <plugin>, for the simulator), and the rendering or
//                              solver hints Gazebo accepts (accepted, not used: listed in
//                              `without_effect`);
//   <gazebo>                   model-level <plugin> elements and static/self_collide/... flags.
// Unknown elements and negative surface values are errors that name the source, the line and the
// element; a block referring to a link or joint that does not exist is skipped with a warning.
#pragma once

#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "conde_physics/model.h"

namespace tinyxml2 {
class XMLDocument;
class XMLElement;
}  // namespace tinyxml2

namespace conde_physics {

// One plugin to load, in document order: a model-level plugin (sensor == nullptr, link == ""), or
// a sensor of a link with its plugin (plugin == nullptr: a sensor that nothing publishes).
struct GazeboPluginBlock {
  const tinyxml2::XMLElement* plugin = nullptr;
  const tinyxml2::XMLElement* sensor = nullptr;
  std::string link;
};

struct GazeboBlocks {
  std::shared_ptr<const tinyxml2::XMLDocument> document;  // owns the elements below
  std::map<std::string, SurfaceParams> surfaces;          // by link or joint name
  std::vector<GazeboPluginBlock> plugins;
  // Keys of <gazebo reference> blocks that Gazebo knows and that have no effect here, each with
  // where it was first written ("r.urdf:12: <gazebo reference=\"a\">"); for a log line per key.
  std::map<std::string, std::string> without_effect;
  // Blocks skipped, with file and line: a reference to a link or joint the URDF does not have.
  std::vector<std::string> warnings;
};

// `has_link_or_joint(name)` tells whether the URDF defines that link or joint. A document that
// is not well-formed XML gives empty blocks (the URDF parser reports it). Throws ModelError.
GazeboBlocks readGazeboBlocks(const std::string& urdf_xml, const std::string& source,
                              const std::function<bool(const std::string&)>& has_link_or_joint);

}  // namespace conde_physics
