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
const std::string kPose =
    kSep + "geometry_msgs/Pose\ngeometry_msgs/Point position\ngeometry_msgs/Quaternion orientation" + kSep +
    "geometry_msgs/Point\nfloat64 x\nfloat64 y\nfloat64 z" + kQuaternion;
const std::string kVector3 = kSep + "geometry_msgs/Vector3\nfloat64 x\nfloat64 y\nfloat64 z";

}  // namespace

const std::string& message_definition(const std::string& type) {
  static const std::map<std::string, std::string> defs = {
      {"sensor_msgs/msg/Image",
       "std_msgs/Header header\nuint32 height\nuint32 width\nstring encoding\nuint8 is_bigendian\nuint32 "
       "step\n"
       "uint8[] data" +
           kHeader},
      {"sensor_msgs/msg/CompressedImage", "std_msgs/Header header\nstring format\nuint8[] data" + kHeader},
      {"sensor_msgs/msg/CameraInfo",
       "std_msgs/Header header\nuint32 height\nuint32 width\nstring distortion_model\nfloat64[] "
       "d\nfloat64[9] k\n"
       "float64[9] r\nfloat64[12] p\nuint32 binning_x\nuint32 binning_y\nsensor_msgs/RegionOfInterest roi" +
           kHeader + kSep +
           "sensor_msgs/RegionOfInterest\nuint32 x_offset\nuint32 y_offset\nuint32 height\nuint32 "
           "width\nbool do_rectify"},
      {"geometry_msgs/msg/PoseStamped", "std_msgs/Header header\ngeometry_msgs/Pose pose" + kHeader + kPose},
      {"nav_msgs/msg/Path", "std_msgs/Header header\ngeometry_msgs/PoseStamped[] poses" + kHeader + kSep +
                                "geometry_msgs/PoseStamped\nstd_msgs/Header header\ngeometry_msgs/Pose pose" +
                                kPose},
      {"sensor_msgs/msg/PointCloud2",
       "std_msgs/Header header\nuint32 height\nuint32 width\nsensor_msgs/PointField[] fields\nbool "
       "is_bigendian\n"
       "uint32 point_step\nuint32 row_step\nuint8[] data\nbool is_dense" +
           kHeader + kSep +
           "sensor_msgs/PointField\nuint8 INT8=1\nuint8 UINT8=2\nuint8 INT16=3\nuint8 UINT16=4\nuint8 "
           "INT32=5\n"
           "uint8 UINT32=6\nuint8 FLOAT32=7\nuint8 FLOAT64=8\nstring name\nuint32 offset\nuint8 "
           "datatype\nuint32 count"},
      {"visualization_msgs/msg/MarkerArray",
       "visualization_msgs/Marker[] markers" + kSep +
           "visualization_msgs/Marker\nint32 CUBE=1\nint32 CUBE_LIST=6\nint32 TEXT_VIEW_FACING=9\nint32 "
           "ADD=0\n"
           "std_msgs/Header header\nstring ns\nint32 id\nint32 type\nint32 action\ngeometry_msgs/Pose pose\n"
           "geometry_msgs/Vector3 scale\nstd_msgs/ColorRGBA color\nbuiltin_interfaces/Duration lifetime\n"
           "bool frame_locked\ngeometry_msgs/Point[] points\nstd_msgs/ColorRGBA[] colors\nstring "
           "texture_resource\n"
           "sensor_msgs/CompressedImage texture\nsensor_msgs/UVCoordinate[] uv_coordinates\nstring text\n"
           "string mesh_resource\nvisualization_msgs/MeshFile mesh_file\nbool mesh_use_embedded_materials" +
           kHeader + kPose + kVector3 + kSep +
           "std_msgs/ColorRGBA\nfloat32 r\nfloat32 g\nfloat32 b\nfloat32 a" + kSep +
           "builtin_interfaces/Duration\nint32 sec\nuint32 nanosec" + kSep +
           "sensor_msgs/CompressedImage\nstd_msgs/Header header\nstring format\nuint8[] data" + kSep +
           "sensor_msgs/UVCoordinate\nfloat32 u\nfloat32 v" + kSep +
           "visualization_msgs/MeshFile\nstring filename\nuint8[] data"},
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
