// libgazebo_ros_imu_sensor.so: sensor_msgs/Imu from an IMU sensor on a link; and
// libgazebo_ros_imu.so, the older MODEL plugin form of the same measurement (TurtleBot3 and
// others), which sits in a <gazebo> block without a sensor and names its link:
//
//   <gazebo><plugin name="imu_plugin" filename="libgazebo_ros_imu.so">
//     <bodyName>imu_link</bodyName> <frameName>imu_link</frameName> <topicName>imu</topicName>
//     <serviceName>imu_service</serviceName> <gaussianNoise>0.0</gaussianNoise> <updateRate>0</updateRate>
//   </plugin></gazebo>
//
// Model form as Gazebo's gazebo_ros_imu: bodyName required, frameName defaults to bodyName,
// topicName and serviceName to "default_imu" (the service, std_srvs/Empty, only answers: a
// simulated IMU needs no calibration), updateRate 0 = every step. Gazebo's model plugin reports
// the link's world-frame velocity change without gravity, rotated the wrong way; here both
// forms publish the same measurement (specific force and rates in the link frame). Its <imu>
// noise block and <alwaysOn> are accepted without effect (Gazebo ignores them too).
//
// Sensor form:
//
//   <gazebo reference="imu_link"><sensor name="imu" type="imu">
//     <always_on>true</always_on> <update_rate>100</update_rate>
//     <plugin name="imu_plugin" filename="libgazebo_ros_imu_sensor.so">
//       <topicName>imu</topicName> <frameName>imu_link</frameName> <updateRateHZ>100</updateRateHZ>
//       <gaussianNoise>0.0</gaussianNoise> <xyzOffset>0 0 0</xyzOffset> <rpyOffset>0 0 0</rpyOffset>
//     </plugin></sensor></gazebo>
// Orientation is the link's orientation in the world (rotated by rpyOffset); angular velocity and
// linear acceleration (gravity included, as an accelerometer measures it) are in the link frame.
// gaussianNoise [rad, rad/s, m/s^2] is added to each rate and acceleration component; the
// orientation is turned by a small rotation whose rotation vector has that noise on each axis, so
// it stays a unit quaternion (Gazebo adds noise to the quaternion's components).
// Acceleration is the velocity change over one update period, which smooths contact jitter.
// As in Gazebo, xyzOffset is accepted and unused; <bodyName> (from gazebo_ros_imu) is ignored.
#include <sensor_msgs/Imu.h>
#include <std_srvs/Empty.h>

#include <random>

#include "conde_sim/plugin.h"
#include "conde_sim/ros_conversions.h"
#include "conde_sim/update_timer.h"

namespace conde_sim {
namespace {

class ImuPlugin : public SimPlugin {
 public:
  explicit ImuPlugin(bool model_form) : model_form_(model_form) {}

  void configure(PluginParams& params, ros::NodeHandle& nh) override {
    std::string topic;
    double rate_hz = 0.0;
    if (model_form_) {
      if (params.inSensor()) throw PluginError(params.where() + ": is a model plugin: it must not sit in a <sensor>");
      link_ = params.requireString("bodyName");
      int body = -1;
      cp::Pose unused;
      if (!ctx_.sim->robot(ctx_.robot).model.linkInBody(link_, body, unused)) {
        throw params.error("bodyName",
                           "robot '" + ctx_.sim->robot(ctx_.robot).spec.name + "' has no link '" + link_ + "'");
      }
      topic = params.getString("topicName", "default_imu");
      frame_ = ctx_.frame(params.getString("frameName", link_));
      rate_hz = params.getDouble("updateRate", 0.0);
      if (rate_hz < 0) throw params.error("updateRate", "must not be negative");
      calibrate_ = nh.advertiseService(params.getString("serviceName", "default_imu"), &ImuPlugin::calibrate, this);
      params.ignore({"imu", "alwaysOn"});
    } else {
      link_ = params.requireSensor({"imu"});
      topic = params.getString("topicName", "imu_data");
      frame_ = ctx_.frame(params.requireString("frameName"));
      rate_hz = params.getDouble("updateRateHZ", 1.0);
      const double sensor_rate_hz = params.sensorDouble("update_rate", 0.0);
      if (!params.has("updateRateHZ") && sensor_rate_hz > 0) rate_hz = sensor_rate_hz;
      if (rate_hz < 0) throw params.error("updateRateHZ", "must not be negative");
      params.sensorBool("always_on", true);
      params.ignore({"visualize", "pose", "topic", "imu", "bodyName", "alwaysOn"});
    }
    timer_ = UpdateTimer(rate_hz, ctx_.sim->stepS());
    noise_stddev_ = params.getDouble("gaussianNoise", 0.0);
    if (noise_stddev_ < 0) throw params.error("gaussianNoise", "must not be negative");
    params.getVec3("xyzOffset", cp::Vec3());  // checked, then unused (as in Gazebo)
    params.ignore({"xyzOffset"});
    const cp::Vec3 rpy = params.getVec3("rpyOffset", cp::Vec3());
    rpy_offset_ = cp::Quat::fromRpy(rpy.x, rpy.y, rpy.z);
    pub_ = nh.advertise<sensor_msgs::Imu>(topic, 10);
    last_velocity_ = ctx_.sim->linkTwist(ctx_.robot, link_).linear_mps;
    ROS_INFO("%s: IMU (%s) on link %s publishing %s in frame %s at %.1f Hz, noise %.4f",
             ctx_.sim->robot(ctx_.robot).spec.name.c_str(), model_form_ ? "model plugin" : "sensor", link_.c_str(),
             pub_.getTopic().c_str(), frame_.c_str(), timer_.rateHz(ctx_.sim->stepS()), noise_stddev_);
  }

  void reset() override { last_velocity_ = ctx_.sim->linkTwist(ctx_.robot, link_).linear_mps; }

  void afterStep() override {
    if (!timer_.due(ctx_.sim->stepCount())) return;
    const cp::Pose pose = ctx_.sim->linkPose(ctx_.robot, link_);
    const cp::Twist twist = ctx_.sim->linkTwist(ctx_.robot, link_);
    const double dt_s = timer_.stepsPerUpdate() * ctx_.sim->stepS();
    const cp::Vec3 accel_world = (twist.linear_mps - last_velocity_) / dt_s - ctx_.sim->world().physics.gravity_mps2;
    last_velocity_ = twist.linear_mps;
    if (pub_.getNumSubscribers() == 0) return;
    const cp::Quat to_link = pose.orientation.conjugate();
    const cp::Vec3 accel = to_link.rotate(accel_world);
    const cp::Vec3 gyro = to_link.rotate(twist.angular_radps);
    const cp::Quat q = (rpy_offset_ * pose.orientation).normalized();
    sensor_msgs::Imu msg;
    msg.header.stamp = ctx_.now();
    msg.header.frame_id = frame_;
    const cp::Quat noisy = (q * cp::Quat::fromRotationVector({noise(), noise(), noise()})).normalized();
    msg.orientation = toMsg(noisy);
    msg.angular_velocity.x = gyro.x + noise();
    msg.angular_velocity.y = gyro.y + noise();
    msg.angular_velocity.z = gyro.z + noise();
    msg.linear_acceleration.x = accel.x + noise();
    msg.linear_acceleration.y = accel.y + noise();
    msg.linear_acceleration.z = accel.z + noise();
    const double variance = noise_stddev_ * noise_stddev_;
    for (int i : {0, 4, 8}) {
      msg.orientation_covariance[i] = variance;
      msg.angular_velocity_covariance[i] = variance;
      msg.linear_acceleration_covariance[i] = variance;
    }
    pub_.publish(msg);
  }

 private:
  bool calibrate(std_srvs::Empty::Request&, std_srvs::Empty::Response&) { return true; }
  double noise() { return noise_stddev_ > 0 ? gauss_(rng_) * noise_stddev_ : 0.0; }

  bool model_form_;
  std::string link_, frame_;
  cp::Quat rpy_offset_;
  cp::Vec3 last_velocity_;
  double noise_stddev_ = 0.0;
  UpdateTimer timer_;
  std::mt19937 rng_{0};
  std::normal_distribution<double> gauss_{0.0, 1.0};
  ros::Publisher pub_;
  ros::ServiceServer calibrate_;
};

}  // namespace

std::unique_ptr<SimPlugin> makeImuSensorPlugin() { return std::make_unique<ImuPlugin>(false); }
std::unique_ptr<SimPlugin> makeImuModelPlugin() { return std::make_unique<ImuPlugin>(true); }

}  // namespace conde_sim
