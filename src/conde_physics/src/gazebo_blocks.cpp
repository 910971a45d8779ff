#include "conde_physics/gazebo_blocks.h"

#include <tinyxml2.h>

#include <set>
#include <stdexcept>

#include "conde_physics/urdf_model.h"

namespace conde_physics {
namespace {

// Keys of <gazebo reference="link"> blocks besides <sensor>: those physics reads, and those
// accepted and ignored (Gazebo rendering/solver hints).
const std::set<std::string> kSurfaceKeys = {"mu1", "mu2", "kp", "kd"};
const std::set<std::string> kOtherReferenceKeys = {"material",
                                                   "selfCollide",
                                                   "gravity",
                                                   "turnGravityOff",
                                                   "maxVel",
                                                   "minDepth",
                                                   "fdir1",
                                                   "maxContacts",
                                                   "provideFeedback",
                                                   "implicitSpringDamper",
                                                   "dampingFactor",
                                                   "laserRetro",
                                                   "visual",
                                                   "stopCfm",
                                                   "stopErp",
                                                   "cfmDamping",
                                                   "springStiffness",
                                                   "springReference",
                                                   "preserveFixedJoint",
                                                   "disableFixedJointLumping",
                                                   "kinematic",
                                                   "static"};

// Model-level <gazebo> children that are not plugins, accepted as Gazebo accepts them.
const std::set<std::string> kModelKeys = {"static", "self_collide", "allow_auto_disable", "enable_wind"};

double parseNumber(const std::string& text, const std::string& where) {
  try {
    size_t used = 0;
    const double v = std::stod(text, &used);
    if (text.find_first_not_of(" \t\r\n", used) != std::string::npos) throw std::invalid_argument(text);
    return v;
  } catch (const std::exception&) {
    throw ModelError(where + ": expected a number, got '" + text + "'");
  }
}

std::string at(const std::string& source, const tinyxml2::XMLElement* e) {
  return source + ":" + std::to_string(e->GetLineNum());
}

void readModelBlock(const tinyxml2::XMLElement* g, const std::string& source, GazeboBlocks& blocks) {
  for (const auto* e = g->FirstChildElement(); e; e = e->NextSiblingElement()) {
    const std::string key = e->Name();
    if (key == "plugin") {
      blocks.plugins.push_back({e, nullptr, ""});
    } else if (!kModelKeys.count(key)) {
      throw ModelError(at(source, e) + ": <gazebo>: unknown element <" + key + ">");
    }
  }
}

void readReferenceBlock(const tinyxml2::XMLElement* g, const std::string& ref, const std::string& source,
                        GazeboBlocks& blocks) {
  const std::string where = at(source, g) + ": <gazebo reference=\"" + ref + "\">";
  SurfaceParams& s = blocks.surfaces[ref];
  for (const auto* e = g->FirstChildElement(); e; e = e->NextSiblingElement()) {
    const std::string key = e->Name();
    if (kSurfaceKeys.count(key)) {
      const double v = parseNumber(e->GetText() ? e->GetText() : "", where + " <" + key + ">");
      if (v < 0) throw ModelError(where + " <" + key + ">: must not be negative, got " + std::to_string(v));
      if (key == "mu1") s.mu = v;
      if (key == "mu2") s.mu2 = v;
      if (key == "kp") s.stiffness_npm = v;
      if (key == "kd") s.damping_nspm = v;
    } else if (key == "sensor") {
      blocks.plugins.push_back({e->FirstChildElement("plugin"), e, ref});
    } else if (kOtherReferenceKeys.count(key)) {
      blocks.without_effect.emplace(key, at(source, e) + ": <gazebo reference=\"" + ref + "\">");
    } else {
      throw ModelError(at(source, e) + ": <gazebo reference=\"" + ref + "\">: unknown element <" + key + ">");
    }
  }
}

}  // namespace

GazeboBlocks readGazeboBlocks(const std::string& urdf_xml, const std::string& source,
                              const std::function<bool(const std::string&)>& has_link_or_joint) {
  GazeboBlocks blocks;
  auto doc = std::make_shared<tinyxml2::XMLDocument>();
  if (doc->Parse(urdf_xml.c_str()) != tinyxml2::XML_SUCCESS) return blocks;
  blocks.document = doc;
  const tinyxml2::XMLElement* robot = doc->FirstChildElement("robot");
  for (const auto* g = robot ? robot->FirstChildElement("gazebo") : nullptr; g; g = g->NextSiblingElement("gazebo")) {
    const char* reference = g->Attribute("reference");
    if (!reference) {
      readModelBlock(g, source, blocks);
      continue;
    }
    if (!has_link_or_joint(reference)) {
      // Gazebo skips such a block without a word (public robots have typos there): skip it too, but say so.
      blocks.warnings.push_back(at(source, g) + ": <gazebo reference=\"" + reference + "\">: no link or joint named '" +
                                reference + "': block ignored, as Gazebo ignores it");
      continue;
    }
    readReferenceBlock(g, reference, source, blocks);
  }
  return blocks;
}

}  // namespace conde_physics
