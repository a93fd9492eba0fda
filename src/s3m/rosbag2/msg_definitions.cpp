#include "s3m/rosbag2/msg_definitions.hpp"

#include <map>

#include "s3m/core/error.hpp"

namespace s3m::rosbag2 {
namespace {

const std::string kSep =
    "\n================================================================================\nMSG: ";
const std::string kTime = kSep + "builtin_interfaces/Time\nint32 sec\nuint32 nanosec";
const std::string kHeader = kSep + "std_msgs/Header\nbuiltin_interfaces/Time stamp\nstring frame_id" + kTime;
const std::string kQuaternion = kSep + "geometry_msgs/Quaternion\nfloat64 x\nfloat64 y\nfloat64 z\nfloat64 w";

}  // namespace

const std::string& message_definition(const std::string& type) {
  static const std::map<std::string, std::string> defs = {
      {"sensor_msgs/msg/Image",
       "std_msgs/Header header\nuint32 height\nuint32 width\nstring encoding\nuint8 is_bigendian\nuint32 "
       "step\n"
       "uint8[] data" +
           kHeader},
      {"sensor_msgs/msg/CameraInfo",
       "std_msgs/Header header\nuint32 height\nuint32 width\nstring distortion_model\nfloat64[] "
       "d\nfloat64[9] k\n"
       "float64[9] r\nfloat64[12] p\nuint32 binning_x\nuint32 binning_y\nsensor_msgs/RegionOfInterest roi" +
           kHeader + kSep +
           "sensor_msgs/RegionOfInterest\nuint32 x_offset\nuint32 y_offset\nuint32 height\nuint32 "
           "width\nbool do_rectify"},
      {"geometry_msgs/msg/PoseStamped",
       "std_msgs/Header header\ngeometry_msgs/Pose pose" + kHeader + kSep +
           "geometry_msgs/Pose\ngeometry_msgs/Point position\ngeometry_msgs/Quaternion orientation" + kSep +
           "geometry_msgs/Point\nfloat64 x\nfloat64 y\nfloat64 z" + kQuaternion},
      {"tf2_msgs/msg/TFMessage",
       "geometry_msgs/TransformStamped[] transforms" + kSep +
           "geometry_msgs/TransformStamped\nstd_msgs/Header header\nstring child_frame_id\n"
           "geometry_msgs/Transform transform" +
           kHeader + kSep +
           "geometry_msgs/Transform\ngeometry_msgs/Vector3 translation\ngeometry_msgs/Quaternion rotation" +
           kSep + "geometry_msgs/Vector3\nfloat64 x\nfloat64 y\nfloat64 z" + kQuaternion},
  };
  const auto it = defs.find(type);
  if (it == defs.end()) throw Error("no message definition for " + type + " (s3m does not write it)");
  return it->second;
}

}  // namespace s3m::rosbag2
