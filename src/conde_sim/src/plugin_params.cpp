#include "conde_sim/plugin_params.h"

#include <sstream>

namespace conde_sim {

PluginParams::PluginParams(const tinyxml2::XMLElement* plugin, const tinyxml2::XMLElement* sensor,
                           std::string source, std::string reference_link)
    : plugin_(plugin), sensor_(sensor), source_(std::move(source)), reference_link_(std::move(reference_link)) {
  name_ = plugin->Attribute("name") ? plugin->Attribute("name") : "";
  filename_ = plugin->Attribute("filename") ? plugin->Attribute("filename") : "";
  // Keys every gazebo_ros plugin accepts; the node handles the namespace itself.
  used_.insert("robotNamespace");
  sensor_used_.insert("plugin");
}

std::string PluginParams::where() const {
  std::string w = source_ + ":" + std::to_string(plugin_->GetLineNum()) + ": plugin '" + name_ + "' (" + filename_ + ")";
  return w;
}

PluginError PluginParams::error(const std::string& key, const std::string& what) const {
  return PluginError(where() + ": <" + key + ">: " + what);
}

const tinyxml2::XMLElement* PluginParams::child(const tinyxml2::XMLElement* parent, const std::string& key) const {
  return parent ? parent->FirstChildElement(key.c_str()) : nullptr;
}

std::string PluginParams::text(const tinyxml2::XMLElement* e) const {
  std::string t = e && e->GetText() ? e->GetText() : "";
  const auto first = t.find_first_not_of(" \t\r\n");
  if (first == std::string::npos) return "";
  return t.substr(first, t.find_last_not_of(" \t\r\n") - first + 1);
}

double PluginParams::toDouble(const tinyxml2::XMLElement* e, const std::string& key) const {
  const std::string t = text(e);
  try {
    size_t used = 0;
    const double v = std::stod(t, &used);
    if (used != t.size()) throw std::invalid_argument(t);
    return v;
  } catch (const std::exception&) {
    throw error(key, "expected a number, got '" + t + "'");
  }
}

const tinyxml2::XMLElement* PluginParams::descendant(const tinyxml2::XMLElement* parent,
                                                     const std::string& path) const {
  const tinyxml2::XMLElement* e = parent;
  size_t start = 0;
  while (e && start <= path.size()) {
    const size_t end = path.find('/', start);
    e = child(e, path.substr(start, end == std::string::npos ? std::string::npos : end - start));
    if (end == std::string::npos) break;
    start = end + 1;
  }
  return e;
}

bool PluginParams::has(const std::string& key) const { return child(plugin_, key) != nullptr; }

std::string PluginParams::getString(const std::string& key, const std::string& fallback) {
  used_.insert(key);
  const auto* e = child(plugin_, key);
  return e ? text(e) : fallback;
}

std::string PluginParams::requireString(const std::string& key) {
  used_.insert(key);
  const auto* e = child(plugin_, key);
  if (!e || text(e).empty()) throw error(key, "required parameter is missing");
  return text(e);
}

double PluginParams::getDouble(const std::string& key, double fallback) {
  used_.insert(key);
  const auto* e = child(plugin_, key);
  return e ? toDouble(e, key) : fallback;
}

bool PluginParams::getBool(const std::string& key, bool fallback) {
  used_.insert(key);
  const auto* e = child(plugin_, key);
  if (!e) return fallback;
  const std::string t = text(e);
  if (t == "true" || t == "1") return true;
  if (t == "false" || t == "0") return false;
  throw error(key, "expected true, false, 1 or 0, got '" + t + "'");
}

conde_physics::Vec3 PluginParams::getVec3(const std::string& key, const conde_physics::Vec3& fallback) {
  used_.insert(key);
  const auto* e = child(plugin_, key);
  if (!e) return fallback;
  std::istringstream in(text(e));
  conde_physics::Vec3 v;
  std::string rest;
  if (!(in >> v.x >> v.y >> v.z) || (in >> rest)) throw error(key, "expected three numbers, got '" + text(e) + "'");
  return v;
}

std::vector<std::string> PluginParams::getList(const std::string& key) {
  used_.insert(key);
  std::vector<std::string> out;
  const auto* e = child(plugin_, key);
  if (!e) return out;
  std::string t = text(e);
  for (char& c : t) {
    if (c == ',') c = ' ';
  }
  std::istringstream in(t);
  std::string item;
  while (in >> item) out.push_back(item);
  return out;
}

double PluginParams::sensorDouble(const std::string& key, double fallback) {
  sensor_used_.insert(key);
  const auto* e = descendant(sensor_, key);
  return e ? toDouble(e, key) : fallback;
}

std::string PluginParams::sensorString(const std::string& key, const std::string& fallback) {
  sensor_used_.insert(key);
  const auto* e = descendant(sensor_, key);
  return e ? text(e) : fallback;
}

bool PluginParams::sensorHas(const std::string& key) const { return descendant(sensor_, key) != nullptr; }

bool PluginParams::sensorBool(const std::string& key, bool fallback) {
  sensor_used_.insert(key);
  const auto* e = descendant(sensor_, key);
  if (!e) return fallback;
  const std::string t = text(e);
  if (t == "true" || t == "1") return true;
  if (t == "false" || t == "0") return false;
  throw error(key, "expected true, false, 1 or 0, got '" + t + "'");
}

std::string PluginParams::sensorType() const {
  return sensor_ && sensor_->Attribute("type") ? sensor_->Attribute("type") : "";
}

std::string PluginParams::sensorName() const {
  return sensor_ && sensor_->Attribute("name") ? sensor_->Attribute("name") : "";
}

void PluginParams::ignore(const std::vector<std::string>& keys) {
  for (const auto& k : keys) {
    used_.insert(k);
    sensor_used_.insert(k);
  }
}

void PluginParams::checkAllUsed() const {
  for (const auto* e = plugin_->FirstChildElement(); e; e = e->NextSiblingElement()) {
    if (!used_.count(e->Name())) {
      throw PluginError(source_ + ":" + std::to_string(e->GetLineNum()) + ": plugin '" + name_ + "' (" + filename_ +
                        "): unknown parameter <" + e->Name() + ">");
    }
  }
  if (!sensor_) return;
  for (const auto* e = sensor_->FirstChildElement(); e; e = e->NextSiblingElement()) checkSensorElement(e, e->Name());
}

void PluginParams::checkSensorElement(const tinyxml2::XMLElement* e, const std::string& path) const {
  if (sensor_used_.count(path)) return;
  const std::string prefix = path + "/";
  bool read_below = false;
  for (const auto& used : sensor_used_) read_below = read_below || used.compare(0, prefix.size(), prefix) == 0;
  if (!read_below) {
    throw PluginError(source_ + ":" + std::to_string(e->GetLineNum()) + ": sensor '" + sensorName() + "' (" +
                      sensorType() + "): unknown element <" + path + ">");
  }
  for (const auto* c = e->FirstChildElement(); c; c = c->NextSiblingElement()) checkSensorElement(c, prefix + c->Name());
}

}  // namespace conde_sim
