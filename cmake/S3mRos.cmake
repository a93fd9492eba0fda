# Finds Debian 12's ROS1 (Noetic-era) packages one by one, without catkin: each installs a
# <pkg>Config.cmake setting <pkg>_INCLUDE_DIRS / <pkg>_LIBRARIES. Defines the interface target
# s3m_ros_deps and sets S3M_ROS_FOUND. Missing packages are listed, so the message says what to install.
set(S3M_ROS_PACKAGES roscpp rosbag rosbag_storage std_msgs std_srvs sensor_msgs geometry_msgs nav_msgs
    visualization_msgs message_filters cv_bridge tf2 tf2_ros tf2_geometry_msgs)
# Some message packages pull in catkin (nav_msgs -> genmsg) and rosbag_storage pulls in pluginlib
# (ament_cmake); their CMake scripts need Debian's Python modules (catkin_pkg, ament_package), so use
# /usr/bin/python3, not whatever python3 comes first on PATH (pyenv, a venv).
if(EXISTS /usr/bin/python3)
  if(NOT DEFINED Python3_EXECUTABLE)
    set(Python3_EXECUTABLE /usr/bin/python3 CACHE FILEPATH "Python for ament's CMake scripts")
  endif()
  if(NOT DEFINED PYTHON_EXECUTABLE)
    set(PYTHON_EXECUTABLE /usr/bin/python3 CACHE FILEPATH "Python for catkin's CMake scripts")
  endif()
endif()
set(S3M_ROS_FOUND TRUE)
set(_s3m_ros_missing "")
foreach(pkg ${S3M_ROS_PACKAGES})
  find_package(${pkg} QUIET NO_MODULE)
  if(NOT ${pkg}_FOUND)
    set(S3M_ROS_FOUND FALSE)
    list(APPEND _s3m_ros_missing ${pkg})
  endif()
endforeach()
find_program(S3M_ROSMASTER rosmaster)
if(S3M_ROS_FOUND)
  add_library(s3m_ros_deps INTERFACE)
  foreach(pkg ${S3M_ROS_PACKAGES})
    # ROS headers are third-party: SYSTEM keeps their warnings out of -Wall -Wextra.
    target_include_directories(s3m_ros_deps SYSTEM INTERFACE ${${pkg}_INCLUDE_DIRS})
    target_link_libraries(s3m_ros_deps INTERFACE ${${pkg}_LIBRARIES})
  endforeach()
  message(STATUS "s3m: ROS1 found, building src/ros (s3m_node, rosbag input)")
else()
  message(WARNING "s3m: S3M_WITH_ROS=ON but ROS packages are missing (${_s3m_ros_missing}); "
                  "building without ROS. Install them with scripts/setup.sh --with-ros.")
endif()
