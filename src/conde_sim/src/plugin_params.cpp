#include "conde_sim/plugin_params.h"

#include <algorithm>
#include <optional>
#include <sstream>
#include <type_traits>

namespace conde_sim {

std::string formatNumber(double v) {
  std::ostringstream out;
  out << v;
  return out.str();
}

namespace {

// The whole of `t` as a T (double or long): nothing for text that is no number, is out of range
// or goes on after the number ("1.5 m").
template <class T>
std::optional<T> wholeNumber(const std::string& t) {
  try {
    size_t used = 0;
    T v;
    if constexpr (std::is_integral_v<T>) {
      v = std::stol(t, &used);
    } else {
      v = std::stod(t, &used);
    }
    if (used == t.size()) return v;
  } catch (const std::exception&) {
  }
  return std::nullopt;
}

// "true"/"1" and "false"/"0", as gazebo_ros reads booleans; nothing for other text.
std::optional<bool> boolText(const std::string& t) {
  if (t == "true" || t == "1") return true;
  if (t == "false" || t == "0") return false;
  return std::nullopt;
}

// The whole of `t` as a T (double, long or bool), and what an error says was expected.
template <class T>
std::optional<T> parsed(const std::string& t) {
  if constexpr (std::is_same_v<T, bool>) {
    return boolText(t);
  } else {
    return wholeNumber<T>(t);
  }
}
template <class T>
const char* expected() {
  if constexpr (std::is_same_v<T, bool>) return "true, false, 1 or 0";
  if constexpr (std::is_integral_v<T>) return "an integer";
  return "a number";
}

}  // namespace

PluginParams::PluginParams(const tinyxml2::XMLElement* plugin, const tinyxml2::XMLElement* sensor, std::string source,
                           std::string reference_link)
    : plugin_(plugin), sensor_(sensor), source_(std::move(source)), reference_link_(std::move(reference_link)) {
  name_ = plugin->Attribute("name") ? plugin->Attribute("name") : "";
  filename_ = plugin->Attribute("filename") ? plugin->Attribute("filename") : "";
  // Keys every gazebo_ros plugin accepts; the node handles the namespace itself.
  used_.insert("robotNamespace");
  sensor_used_.insert("plugin");
}

std::string PluginParams::where() const {
  std::string w =
      source_ + ":" + std::to_string(plugin_->GetLineNum()) + ": plugin '" + name_ + "' (" + filename_ + ")";
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
  if (const std::optional<double> v = wholeNumber<double>(t)) return *v;
  throw error(key, "expected a number, got '" + t + "'");
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
  if (const std::optional<bool> v = boolText(t)) return *v;
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

// Walks "a/b/c" down from the <sensor> element; nullptr when any step is missing.
const tinyxml2::XMLElement* PluginParams::sensorElement(const std::string& path) const {
  const tinyxml2::XMLElement* e = sensor_;
  size_t start = 0;
  while (e && start <= path.size()) {
    const size_t slash = path.find('/', start);
    const std::string name = path.substr(start, slash == std::string::npos ? std::string::npos : slash - start);
    const bool selected = start == 0 && selected_child_ && name == selected_child_->Name();
    e = selected ? selected_child_ : e->FirstChildElement(name.c_str());
    if (slash == std::string::npos) break;
    start = slash + 1;
  }
  return e;
}

static std::string xmlPath(const std::string& path) {
  std::string out = "<";
  for (char c : path) out += c == '/' ? std::string("><") : std::string(1, c);
  return out + ">";
}

PluginError PluginParams::sensorError(const std::string& key, const std::string& what) const {
  const tinyxml2::XMLElement* e = sensorElement(key);
  const tinyxml2::XMLElement* fallback = selected_child_ ? selected_child_ : sensor_;
  const int line = e ? e->GetLineNum() : (fallback ? fallback->GetLineNum() : plugin_->GetLineNum());
  std::string path = xmlPath(key);
  // Which of several children: <camera name="right"><image>.
  const std::string first = key.substr(0, key.find('/'));
  if (selected_child_ && first == selected_child_->Name() && selected_child_->Attribute("name")) {
    path = "<" + first + " name=\"" + selected_child_->Attribute("name") + "\">" + path.substr(first.size() + 2);
  }
  return PluginError(source_ + ":" + std::to_string(line) + ": sensor '" + sensorName() + "' (" + sensorType() +
                     "): " + path + ": " + what);
}

std::vector<const tinyxml2::XMLElement*> PluginParams::sensorChildren(const std::string& name) const {
  std::vector<const tinyxml2::XMLElement*> children;
  if (!sensor_) return children;
  for (const auto* e = sensor_->FirstChildElement(name.c_str()); e; e = e->NextSiblingElement(name.c_str())) {
    children.push_back(e);
  }
  return children;
}

bool PluginParams::sensorHas(const std::string& key) const { return sensorElement(key) != nullptr; }

conde_physics::Pose PluginParams::sensorPose(const std::string& key) {
  const std::string text = sensorString(key, "0 0 0 0 0 0");
  std::istringstream in(text);
  double v[6];
  std::string rest;
  for (double& x : v) {
    if (!(in >> x)) throw sensorError(key, "expected six numbers 'x y z roll pitch yaw', got '" + text + "'");
  }
  if (in >> rest) throw sensorError(key, "expected six numbers 'x y z roll pitch yaw', got '" + text + "'");
  return conde_physics::Pose::fromXyzRpy(v[0], v[1], v[2], v[3], v[4], v[5]);
}

PluginParams::SensorNoise PluginParams::sensorNoise(const std::string& path) {
  SensorNoise noise;
  if (!sensorHas(path)) return noise;
  const std::string type = sensorString(path + "/type", "gaussian");
  if (type != "gaussian" && type != "none") {
    throw sensorError(path + "/type", "unsupported noise type '" + type + "' (expected gaussian or none)");
  }
  noise.gaussian = type == "gaussian";
  noise.mean = sensorDouble(path + "/mean", 0.0);
  noise.stddev = sensorDouble(path + "/stddev", 0.0);
  if (noise.stddev < 0) throw sensorError(path + "/stddev", "must not be negative");
  return noise;
}

template <class T>
T PluginParams::sensorValue(const std::string& key, T fallback) {
  sensor_used_.insert(key);
  const auto* e = sensorElement(key);
  if (!e) return fallback;
  const std::string t = text(e);
  if (const std::optional<T> v = parsed<T>(t)) return *v;
  throw sensorError(key, std::string("expected ") + expected<T>() + ", got '" + t + "'");
}

double PluginParams::sensorDouble(const std::string& key, double fallback) { return sensorValue(key, fallback); }

long PluginParams::sensorInt(const std::string& key, long fallback) { return sensorValue(key, fallback); }

bool PluginParams::sensorBool(const std::string& key, bool fallback) { return sensorValue(key, fallback); }

std::string PluginParams::sensorString(const std::string& key, const std::string& fallback) {
  sensor_used_.insert(key);
  const auto* e = sensorElement(key);
  return e ? text(e) : fallback;
}

std::string PluginParams::requireReferenceLink() const {
  if (reference_link_.empty()) throw PluginError(where() + ": must sit in <gazebo reference=\"link\">");
  return reference_link_;
}

std::string PluginParams::requireSensor(const std::vector<std::string>& types) const {
  const bool known_type = std::find(types.begin(), types.end(), sensorType()) != types.end();
  if (inSensor() && known_type && !reference_link_.empty()) return reference_link_;
  std::string wanted;
  for (const std::string& t : types)
    wanted += (wanted.empty() ? "" : " or ") + std::string("<sensor type=\"") + t + "\">";
  std::string got;
  if (inSensor() && !known_type) got = " (got type '" + sensorType() + "')";
  throw PluginError(where() + ": must sit in a " + wanted + " inside <gazebo reference=\"link\">" + got);
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
    // Listed once, also when several cameras of one sensor ignore the same keys.
    if (std::find(ignored_.begin(), ignored_.end(), k) == ignored_.end()) ignored_.push_back(k);
  }
}

std::vector<std::string> PluginParams::acceptedWithoutEffect() const {
  std::vector<std::string> present;
  for (const std::string& k : ignored_) {
    if (has(k)) present.push_back("<" + k + ">");
    if (sensor_ && sensorHas(k)) present.push_back("<sensor>" + xmlPath(k));
  }
  return present;
}

void PluginParams::checkAllUsed() const {
  for (const auto* e = plugin_->FirstChildElement(); e; e = e->NextSiblingElement()) {
    if (!used_.count(e->Name())) {
      throw PluginError(source_ + ":" + std::to_string(e->GetLineNum()) + ": plugin '" + name_ + "' (" + filename_ +
                        "): unknown parameter <" + e->Name() + ">");
    }
  }
  if (sensor_) checkSensorChildren(sensor_, "");
}

// A child whose path was read (or ignored) is fine with all it holds; a child on the way to a
// read path is checked in turn; any other child is unknown.
void PluginParams::checkSensorChildren(const tinyxml2::XMLElement* parent, const std::string& path) const {
  for (const auto* e = parent->FirstChildElement(); e; e = e->NextSiblingElement()) {
    const std::string child_path = path.empty() ? e->Name() : path + "/" + e->Name();
    if (sensor_used_.count(child_path)) continue;
    const auto next = sensor_used_.lower_bound(child_path + "/");
    if (next != sensor_used_.end() && next->compare(0, child_path.size() + 1, child_path + "/") == 0) {
      checkSensorChildren(e, child_path);
      continue;
    }
    throw PluginError(source_ + ":" + std::to_string(e->GetLineNum()) + ": sensor '" + sensorName() + "' (" +
                      sensorType() + "): unknown element " + xmlPath(child_path));
  }
}

}  // namespace conde_sim
