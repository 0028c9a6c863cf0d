# Find module for what the ROS node (apps/ros/) needs beyond the bag layer: Debian 12's roscpp
# (libroscpp-dev, with rosconsole and xmlrpcpp) and the message headers it publishes
# (libgeometry-msgs-dev, libsensor-msgs-dev, libstd-msgs-dev, libtf2-msgs-dev;
# scripts/packages-ros.txt). As for the bag layer (FindRos1Bag.cmake), Debian ships ROS 1 without
# catkin, so headers and libraries are found by name.
# Sets Ros1Node_FOUND, Ros1Node_INCLUDE_DIRS and Ros1Node_LIBRARIES.
set(_ros1node_vars)
set(_ros1node_dirs)
foreach(header ros/ros.h sensor_msgs/PointCloud2.h geometry_msgs/PoseStamped.h
               geometry_msgs/PoseWithCovarianceStamped.h std_msgs/Float64.h tf2_msgs/TFMessage.h)
  string(MAKE_C_IDENTIFIER "Ros1Node_${header}" var)
  find_path(${var} ${header})
  list(APPEND _ros1node_vars ${var})
  list(APPEND _ros1node_dirs ${${var}})
endforeach()
set(_ros1node_libs)
foreach(lib roscpp rosconsole xmlrpcpp boost_system)
  find_library(Ros1Node_${lib}_LIBRARY ${lib})
  list(APPEND _ros1node_vars Ros1Node_${lib}_LIBRARY)
  list(APPEND _ros1node_libs ${Ros1Node_${lib}_LIBRARY})
endforeach()

include(FindPackageHandleStandardArgs)
find_package_handle_standard_args(Ros1Node REQUIRED_VARS ${_ros1node_vars})
if(Ros1Node_FOUND)
  set(Ros1Node_INCLUDE_DIRS ${_ros1node_dirs})
  list(REMOVE_DUPLICATES Ros1Node_INCLUDE_DIRS)
  set(Ros1Node_LIBRARIES ${_ros1node_libs})
endif()
