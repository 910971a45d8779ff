// Parameters of one Gazebo-style plugin block, read as gazebo_ros plugins read them: child
// elements of <plugin> by name, values as text. Every key a plugin reads is recorded, so that
// after loading, a key nobody read is reported as unknown (with file, line, plugin and key).
#pragma once

#include <tinyxml2.h>

#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include "conde_physics/math.h"

namespace conde_sim {

class PluginError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// A value as error messages quote it: shortest form, no trailing zeros ("0.05", "640", "-1e-06").
std::string formatNumber(double v);

class PluginParams {
 public:
  // `plugin` is the <plugin> element; `sensor` the enclosing <sensor> element or nullptr;
  // `source` names the robot description in messages; `reference_link` is the link of the
  // enclosing <gazebo reference="..."> block ("" for model-level plugins).
  PluginParams(const tinyxml2::XMLElement* plugin, const tinyxml2::XMLElement* sensor, std::string source,
               std::string reference_link);

  std::string pluginName() const { return name_; }
  std::string filename() const { return filename_; }
  std::string referenceLink() const { return reference_link_; }
  bool inSensor() const { return sensor_ != nullptr; }
  // The link of the enclosing <gazebo reference="link">; throws PluginError when there is none.
  std::string requireReferenceLink() const;
  // The same for a sensor plugin, whose <sensor> must have one of `types` (e.g. {"ray", "gpu_ray"}):
  // "must sit in a <sensor type="ray"> or <sensor type="gpu_ray"> inside <gazebo reference="link">".
  std::string requireSensor(const std::vector<std::string>& types) const;
  bool has(const std::string& key) const;

  std::string getString(const std::string& key, const std::string& fallback);
  std::string requireString(const std::string& key);
  double getDouble(const std::string& key, double fallback);
  bool getBool(const std::string& key, bool fallback);  // true/false/1/0
  conde_physics::Vec3 getVec3(const std::string& key, const conde_physics::Vec3& fallback);
  // Comma- or space-separated names, e.g. <jointName>left, right</jointName>.
  std::vector<std::string> getList(const std::string& key);

  // Keys of the enclosing <sensor> element (update_rate, always_on, ...). A key may be a path
  // into nested elements, "ray/scan/horizontal/samples" for <ray><scan><horizontal><samples>.
  bool sensorHas(const std::string& key) const;
  double sensorDouble(const std::string& key, double fallback);
  long sensorInt(const std::string& key, long fallback);
  bool sensorBool(const std::string& key, bool fallback);
  std::string sensorString(const std::string& key, const std::string& fallback);
  // What every sensor reads alike. The sensor's <pose> ("x y z roll pitch yaw" in the link; the
  // identity without one), and a <noise> block at `path` ("camera/noise", "ray/noise"): type
  // gaussian or none, mean, stddev >= 0 (no block: no noise).
  // `key` is the element of the pose: "pose" for the sensor's, "camera/pose" for a camera's in it.
  conde_physics::Pose sensorPose(const std::string& key = "pose");
  struct SensorNoise {
    bool gaussian = false;
    double mean = 0.0, stddev = 0.0;
  };
  SensorNoise sensorNoise(const std::string& path);

  // "r.urdf:57: sensor 'laser' (ray): <ray><scan><horizontal><samples>: <what>", with the line
  // of that element (of the <sensor> when it is absent).
  PluginError sensorError(const std::string& key, const std::string& what) const;
  std::string sensorType() const;
  std::string sensorName() const;

  // Sensors with several children of one name (<sensor type="multicamera"> with one <camera> per
  // camera): all of them, in order, and which one the sensor keys read. After
  // selectSensorChild(e), a path that starts with e's name ("camera/image/width") walks down from
  // e instead of the first such child; nullptr goes back to the first. Keys read count for every
  // child of that name when unknown elements are checked.
  std::vector<const tinyxml2::XMLElement*> sensorChildren(const std::string& name) const;
  void selectSensorChild(const tinyxml2::XMLElement* child) { selected_child_ = child; }

  // Keys that Gazebo reads but that have no effect here; accepted (a sensor path accepts
  // everything below it). Those present are listed by acceptedWithoutEffect().
  void ignore(const std::vector<std::string>& keys);
  // The ignored keys this block really has: "<alwaysOn>", "<sensor><visualize>", in the order
  // ignore() got them; the loader logs them once at INFO.
  std::vector<std::string> acceptedWithoutEffect() const;
  // Throws PluginError for the first key of <plugin> (and, at any depth, of <sensor>) that was
  // never read.
  void checkAllUsed() const;

  // "robot.urdf:42: plugin 'diff_drive' (libgazebo_ros_diff_drive.so)"
  std::string where() const;
  PluginError error(const std::string& key, const std::string& what) const;

 private:
  const tinyxml2::XMLElement* child(const tinyxml2::XMLElement* parent, const std::string& key) const;
  std::string text(const tinyxml2::XMLElement* e) const;
  double toDouble(const tinyxml2::XMLElement* e, const std::string& key) const;
  const tinyxml2::XMLElement* sensorElement(const std::string& path) const;
  // A <sensor> value of type T (double, long, bool), or `fallback` when the element is absent.
  template <class T>
  T sensorValue(const std::string& key, T fallback);
  void checkSensorChildren(const tinyxml2::XMLElement* parent, const std::string& path) const;

  const tinyxml2::XMLElement* plugin_;
  const tinyxml2::XMLElement* sensor_;
  const tinyxml2::XMLElement* selected_child_ = nullptr;
  std::string source_, reference_link_, name_, filename_;
  std::set<std::string> used_, sensor_used_;
  std::vector<std::string> ignored_;
};

}  // namespace conde_sim
