// ROS 2 message definitions (ros2msg text, dependencies appended as `ros2 bag record` writes them
// into MCAP schemas) for the types the fixtures hold.
'use strict';
const SEP = '\n================================================================================\n';
const dep = (name, text) => `MSG: ${name}\n${text}`;

const TIME = dep('builtin_interfaces/Time', 'int32 sec\nuint32 nanosec');
const HEADER = dep('std_msgs/Header', 'builtin_interfaces/Time stamp\nstring frame_id');
const VECTOR3 = dep('geometry_msgs/Vector3', 'float64 x\nfloat64 y\nfloat64 z');
const POINT = dep('geometry_msgs/Point', 'float64 x\nfloat64 y\nfloat64 z');
const QUATERNION = dep('geometry_msgs/Quaternion', 'float64 x\nfloat64 y\nfloat64 z\nfloat64 w');
const POSE = dep('geometry_msgs/Pose', 'geometry_msgs/Point position\ngeometry_msgs/Quaternion orientation');
const join = (main, deps) => [main, ...deps].join(SEP);

const definitions = {
  'realsense2_camera_msgs/msg/Extrinsics': 'float64[9] rotation\nfloat64[3] translation',
  'sensor_msgs/msg/Image': join(
    'std_msgs/Header header\nuint32 height\nuint32 width\nstring encoding\nuint8 is_bigendian\nuint32 step\nuint8[] data',
    [HEADER, TIME]),
  'sensor_msgs/msg/CompressedImage': join('std_msgs/Header header\nstring format\nuint8[] data', [HEADER, TIME]),
  'sensor_msgs/msg/CameraInfo': join(
    'std_msgs/Header header\nuint32 height\nuint32 width\nstring distortion_model\nfloat64[] d\nfloat64[9] k\n' +
      'float64[9] r\nfloat64[12] p\nuint32 binning_x\nuint32 binning_y\nsensor_msgs/RegionOfInterest roi',
    [HEADER, TIME,
     dep('sensor_msgs/RegionOfInterest', 'uint32 x_offset\nuint32 y_offset\nuint32 height\nuint32 width\nbool do_rectify')]),
  'tf2_msgs/msg/TFMessage': join('geometry_msgs/TransformStamped[] transforms', [
    dep('geometry_msgs/TransformStamped', 'std_msgs/Header header\nstring child_frame_id\ngeometry_msgs/Transform transform'),
    HEADER, TIME,
    dep('geometry_msgs/Transform', 'geometry_msgs/Vector3 translation\ngeometry_msgs/Quaternion rotation'),
    VECTOR3, QUATERNION]),
  'geometry_msgs/msg/PoseStamped': join('std_msgs/Header header\ngeometry_msgs/Pose pose', [HEADER, TIME, POSE, POINT, QUATERNION]),
  'nav_msgs/msg/Odometry': join(
    'std_msgs/Header header\nstring child_frame_id\ngeometry_msgs/PoseWithCovariance pose\ngeometry_msgs/TwistWithCovariance twist',
    [HEADER, TIME, dep('geometry_msgs/PoseWithCovariance', 'geometry_msgs/Pose pose\nfloat64[36] covariance'), POSE, POINT,
     QUATERNION, dep('geometry_msgs/TwistWithCovariance', 'geometry_msgs/Twist twist\nfloat64[36] covariance'),
     dep('geometry_msgs/Twist', 'geometry_msgs/Vector3 linear\ngeometry_msgs/Vector3 angular'), VECTOR3]),
};

module.exports = { definitions };
